"""The public face of the package (cdpr/__init__.py): every name of ``__all__`` resolves to the
object of the module that defines it, lazily, and ``import cdpr`` alone stays cheap."""

import importlib
import subprocess
import sys

import pytest

import cdpr
from tests.conftest import ROBOTS, ROOT


@pytest.mark.parametrize("name", cdpr.__all__)
def test_every_public_name_resolves(name):
    value = getattr(cdpr, name)
    if name == "__version__":
        assert isinstance(value, str) and value
        return
    module = importlib.import_module(cdpr._EXPORTS[name])
    assert value is getattr(module, name)
    assert name in dir(cdpr)


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="module 'cdpr' has no attribute 'nope'"):
        cdpr.nope  # noqa: B018
    assert not hasattr(cdpr, "solve_tabel")


def test_import_is_lazy():
    """``import cdpr`` loads none of the heavy dependencies; the first public name loads its layer."""
    code = (
        "import sys, cdpr; heavy = ('numpy', 'pandas', 'numba', 'scipy', 'cdpr.solve');"
        "print(*[m for m in heavy if m in sys.modules]); cdpr.igm_e;"
        "print('numpy' in sys.modules, 'cdpr.solve' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    lines = out.stdout.splitlines()
    assert lines[0].strip() == "", f"import cdpr loaded {lines[0]}"
    assert lines[1] == "True False"


def test_the_quick_start_runs_from_the_public_names():
    robot = cdpr.with_pulleys(cdpr.load_robot(ROBOTS / "cdpr4.yaml"), kind="DR")
    P = [[0.0, 0.0, 2.5], [1.0, -0.5, 1.0]]
    extra = cdpr.igm_e(robot, P).L_TE - cdpr.L_TS(robot, P)
    # on the axis of the square robot the four cables are alike, and the pulleys change their length
    assert abs(extra[0, 0]) > 1e-3 and abs(extra[0] - extra[0, 0]).max() < 1e-12
    assert abs(extra[1] - extra[1, 0]).max() > 1e-3  # off the axis they differ
    df = cdpr.solve_table(robot, P)
    assert list(df["status"].astype(str)) == ["ok", "ok"] and set(df["status"].cat.categories) == set(
        cdpr.STATUSES
    )
