"""``cdpr point``'s reached equilibrium (issue 39): the ``reached`` and ``global`` objects,
``reached_is_global``, ``--equilibrium global`` and the start options, spelled as the issue spells
them, on the issue's wall robot example."""

import json
from pathlib import Path

import pytest

from cdpr.cli.main import main
from tests.conftest import ROBOTS

ROOT = Path(__file__).resolve().parents[2]
WALL = str(ROOT / "tests" / "data" / "wall_crossed.yaml")
L0 = "6.52907908125 6.14882031715 5.85918529262 6.26397544351 6.06888687927 5.63634727396 5.23674973794 5.70862689323".split()
EXAMPLE = [
    "point",
    "--robot",
    WALL,
    "--at",
    "0.3",
    "0.3",
    "0.7",
    "--rotvec",
    "0.12",
    "0.12",
    "0",
    "--lengths",
    *L0,
]
OBJECT = {"solved", "solved_rotvec", "energy_J", "taut", "tensions", "interference_free", "status"}


def run_json(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_reached_and_global_objects(capsys):
    out = run_json(capsys, *EXAMPLE)
    assert set(out["reached"]) == OBJECT | {"folds", "start", "steps"}
    assert set(out["global"]) == OBJECT
    assert out["reached_is_global"] is False and out["equilibrium"] == "reached"
    assert out["reached"]["start"] == "compensated" and out["reached"]["folds"] == []
    # the top-level answer is the reached one: free of interference, turned 0.13 rad
    assert (
        out["solved"] == out["reached"]["solved"] and out["solved_rotvec"] == out["reached"]["solved_rotvec"]
    )
    assert out["interference_free"] is True and out["global"]["interference_free"] is False
    assert out["dphi"] == pytest.approx(0.13, abs=0.01)
    assert out["reached"]["energy_J"] - out["global"]["energy_J"] == pytest.approx(21.0, abs=0.5)
    glob = run_json(capsys, *EXAMPLE, "--equilibrium", "global")
    assert glob["solved"] == glob["global"]["solved"] and glob["dphi"] == pytest.approx(2.56, abs=0.01)
    assert glob["interference_free"] is False and glob["reached"]["solved"] == pytest.approx(
        out["solved"], abs=1e-12
    )


def test_alternatives_are_the_equilibria_other_than_the_answer(capsys):
    """With the reached answer, ``alternatives`` lists the global (flipped) equilibrium and not the
    answer itself; with --equilibrium global it lists the reached one. Each entry is another
    equilibrium under the same lengths: the other answer's pose, rotation and energy."""
    out = run_json(capsys, *EXAMPLE)
    glob = run_json(capsys, *EXAMPLE, "--equilibrium", "global")
    for ans, other in ((out, "global"), (glob, "reached")):
        assert ans["unique"] is False and len(ans["alternatives"]) == 1
        (alt,) = ans["alternatives"]
        assert alt["P_s"] == pytest.approx(ans[other]["solved"], abs=1e-9)
        assert alt["rotvec_s"] == pytest.approx(ans[other]["solved_rotvec"], abs=1e-9)
        assert alt["energy"] == pytest.approx(ans[other]["energy_J"], abs=1e-9)
        assert alt["taut"] == ans[other]["taut"]
        assert alt["P_s"] != pytest.approx(ans["solved"], abs=1e-3)
    assert main(EXAMPLE) == 0
    text = capsys.readouterr().out
    assert "not unique (1 alternative; --json lists them)" in text


def test_unique_equilibrium_reached_is_global(capsys):
    out = run_json(capsys, "point", "--robot", str(ROBOTS / "cogiro.yaml"), "--at", "0.5", "0.3", "1.5")
    assert out["reached_is_global"] is True and out["unique"] is True
    assert out["reached"]["solved"] == pytest.approx(out["global"]["solved"], abs=1e-9)
    assert out["alternatives"] == []


def test_given_start_and_text(capsys):
    out = run_json(
        capsys,
        *EXAMPLE,
        "--from",
        "0.3",
        "0.3",
        "0.7",
        "--from-rotvec",
        "0.12",
        "0.12",
        "0",
        "--from-lengths",
        *L0,
    )
    assert out["reached"]["start"] == "given"
    assert main(EXAMPLE) == 0
    text = capsys.readouterr().out
    assert "start          : compensated" in text and "global         :" in text


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--from", "0", "0", "1"], "--from-lengths"),
        (["--from-lengths", *L0], "--from X Y Z"),
        (["--from", "0", "0", "1", "--from-lengths", "5", "5"], "one rest length per cable"),
        (["--t-min", "500", "--t-max", "400"], "--t-min must be below --t-max"),
    ],
)
def test_bad_starts_are_one_line(capsys, extra, words):
    assert main(EXAMPLE + extra) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]


def test_points_table_answers_with_the_reached_equilibrium(tmp_path, capsys):
    """``point --points``: continuation where the restarts find several equilibria (the studies'
    rule), with the columns n_folds and reached_is_global; --equilibrium global keeps the lowest."""
    import pandas as pd

    pts = tmp_path / "p.csv"
    pts.write_text("x,y,z,rx,ry,rz\n0.3,0.3,0.7,0.12,0.12,0\n")
    out = tmp_path / "o.csv"
    base = ["point", "--robot", WALL, "--points", str(pts), "--out", str(out), "--lengths", *L0, "--quiet"]
    assert main(base) == 0
    df = pd.read_csv(out)
    assert df["n_folds"].tolist() == [0] and df["reached_is_global"].tolist() == [False]
    assert df["dphi"][0] == pytest.approx(0.13, abs=0.01) and not df["unique"][0]
    assert main(base + ["--equilibrium", "global"]) == 0
    df = pd.read_csv(out)
    assert "n_folds" not in df and df["dphi"][0] == pytest.approx(2.56, abs=0.01)
    capsys.readouterr()


def test_sensitivities_are_those_of_the_reached_equilibrium(capsys):
    """--sensitivities answers at the reached equilibrium (0.13 rad), not at the flipped global
    one: dP*/dθ and dφ*/dθ of the mass M and of cable 1's modulus E_1 equal central differences of
    the reached equilibrium itself (``solve.reach`` of the changed robot under the same lengths)."""
    import numpy as np

    from cdpr.models.platform import rotation_matrix, rotvec_of
    from cdpr.robot import load_robot, with_values
    from cdpr.solve import reach

    out = run_json(capsys, *EXAMPLE, "--sensitivities")
    glob = run_json(capsys, *EXAMPLE, "--sensitivities", "--equilibrium", "global")
    assert out["dphi"] == pytest.approx(0.13, abs=0.01) and glob["dphi"] == pytest.approx(2.56, abs=0.01)
    robot = load_robot(WALL)
    P, RV, L = np.array([[0.3, 0.3, 0.7]]), np.array([0.12, 0.12, 0.0]), np.array([float(x) for x in L0])
    E = np.array([c.material.E for c in robot.cables])
    R0 = rotation_matrix(np.asarray(out["solved_rotvec"]))

    def pose(r):
        a = reach(r, P, RV, L0=L)
        assert a["status"][0] == "ok" and a["n_folds"][0] == 0
        # position, and the rotation from the answer's orientation as a base-frame rotation vector
        return np.concatenate([a["P_s"][0], rotvec_of(a["R_s"][:1] @ R0.T)[0]])

    for name, changed, step in (
        ("M", lambda d: with_values(robot, mass=robot.platform.mass + d), 1e-2),
        ("E_1", lambda d: with_values(robot, E_cables=E + d * (np.arange(robot.m) == 0)), 1e8),
    ):
        fd = (pose(changed(step)) - pose(changed(-step))) / (2 * step)
        got = np.array(out["sensitivities"][name] + out["sensitivities_phi"][name])
        scale = np.abs(fd).max()
        assert np.abs(got - fd).max() < 1e-5 * scale, (name, got, fd)
        other = np.array(glob["sensitivities"][name] + glob["sensitivities_phi"][name])
        assert np.abs(other - fd).max() > 1e-2 * scale  # the flipped equilibrium's are not these


def test_points_table_sensitivities_are_those_of_the_reached_equilibrium(tmp_path, capsys):
    """``point --points --sensitivities``: a row whose restarts find several equilibria answers at
    the reached one with its sensitivities, those ``point --at --sensitivities`` gives (checked
    against central differences above); --equilibrium global keeps the flipped one's."""
    import numpy as np
    import pandas as pd

    pts = tmp_path / "p.csv"
    pts.write_text("x,y,z,rx,ry,rz\n0.3,0.3,0.7,0.12,0.12,0\n")
    out = tmp_path / "o.csv"
    base = ["point", "--robot", WALL, "--points", str(pts), "--out", str(out), "--lengths", *L0]
    base += ["--sensitivities", "--quiet"]
    one = run_json(capsys, *EXAMPLE, "--sensitivities")
    assert main(base) == 0
    df = pd.read_csv(out)
    assert df["reached_is_global"].tolist() == [False] and df["dphi"][0] == pytest.approx(0.13, abs=0.01)
    for name in ("M", "E_1", "A_5_z"):
        got = [df[f"d{c}_d{name}"][0] for c in ("x", "y", "z", "phix", "phiy", "phiz")]
        want = one["sensitivities"][name] + one["sensitivities_phi"][name]
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12 * np.abs(want).max())
    assert bool(df["smooth"][0]) is one["sensitivities_smooth"]
    assert main(base + ["--equilibrium", "global"]) == 0
    glob = pd.read_csv(out)
    assert glob["dphi"][0] == pytest.approx(2.56, abs=0.01)
    assert abs(glob["dz_dM"][0] - df["dz_dM"][0]) > 1e-2 * abs(df["dz_dM"][0])
    capsys.readouterr()
