"""cdpr: pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry."""


def __getattr__(name):
    """``cdpr.__version__``, read from the installed metadata on first use: importlib.metadata costs
    ~25 ms, a tenth of ``cdpr --help``, which never asks for it (PEP 562 module attribute)."""
    if name != "__version__":
        raise AttributeError(f"module 'cdpr' has no attribute {name!r}")
    # lazy: importlib.metadata only when the version is asked for
    from importlib.metadata import PackageNotFoundError, version

    try:
        v = version("cdpr")
    except PackageNotFoundError:  # a source tree that is not installed
        v = "0+unknown"
    globals()["__version__"] = v
    return v
