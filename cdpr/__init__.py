"""cdpr: pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("cdpr")
except PackageNotFoundError:  # a source tree that is not installed
    __version__ = "0+unknown"
