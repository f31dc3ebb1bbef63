"""Sensitivities dP*/dθ (cdpr.models.sensitivity, cdpr.compiled.sensitivity): against central finite differences
of full solves, compiled against numpy, and the points where the answer switches are flagged."""

import numpy as np
import pytest

from cdpr.analyses.workspace import grid_points
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.subsets import solve_points_fast
from cdpr.models.inverse import L_TS, igm_e
from cdpr.models.sensitivity import GAP_TOL, cable_partials
from cdpr.models.subsets import solve_points
from cdpr.parameters import parameter_names, parameter_values, robot_with_parameters
from cdpr.robot import with_pulleys
from cdpr.solve import sensitivities
from tests.point_mass import solve_physical

DESIGNS = {"SR": ("SR", 0.1077, 0.035), "DR": ("DR", 0.100, 0.080), "fixed": ("fixed", 0.0, 0.0)}
#: a few points in the paper's RW_C, away from the CDPR4 diagonals
POINTS = np.array([[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1], [-0.4, -2.0, 2.6], [2.1, 0.3, 1.2]])
RTOL = 1e-5
SOLVE_TOL = 1e-13


def _robot(robot, design):
    kind, h, r_p = DESIGNS[design]
    return with_pulleys(robot, kind=kind, h=h, r_p=r_p)


def _full_solve(robot, p, L, mode):
    """P* of the full solve (paper: every subset and the paper's choice) at fixed commanded lengths."""
    if mode == "paper":
        return solve_points_fast(robot, p, L=L, tol=SOLVE_TOL)["P_s"]
    return solve_physical_fast(robot, p, L0=L, tol=SOLVE_TOL)["P_s"]


def _finite_differences(robot, p, mode):
    """Central differences of full solves for every parameter: relative step 1e-4 for E and M,
    1e-6 m for lengths; and each column's noise floor (solve round-off over the step)."""
    L = L_TS(robot, p)
    th = parameter_values(robot)
    fd = np.empty((len(p), 3, len(th)))
    floor = np.empty(len(th))
    for k, name in enumerate(parameter_names(robot)):
        step = 1e-4 * th[k] if name[0] in "EM" else 1e-6
        up, down = th.copy(), th.copy()
        up[k] += step
        down[k] -= step
        fd[:, :, k] = (
            _full_solve(robot_with_parameters(robot, up), p, L, mode)
            - _full_solve(robot_with_parameters(robot, down), p, L, mode)
        ) / (2 * step)
        floor[k] = 1e-13 / step
    return fd, floor


@pytest.mark.parametrize("mode", ["paper", "physical"])
@pytest.mark.parametrize("design", ["SR", "DR", "fixed"])
@pytest.mark.parametrize("name", ["cdpr3", "cdpr4"])
def test_sensitivities_equal_central_differences_of_full_solves(request, name, design, mode):
    robot = _robot(request.getfixturevalue(name), design)
    p = POINTS if name == "cdpr4" else POINTS * [0.6, 0.6, 1.0]
    res = sensitivities(robot, p, redundancy=mode)
    assert res["smooth"].all(), res["smooth"]
    fd, floor = _finite_differences(robot, p, mode)
    err = np.linalg.norm(res["S"] - fd, axis=1)  # (points, parameters)
    bound = RTOL * np.linalg.norm(fd, axis=1) + floor
    worst = np.unravel_index(np.argmax(err / bound), err.shape)
    assert (err <= bound).all(), (
        f"{parameter_names(robot)[worst[1]]} at {p[worst[0]]}: IFT {res['S'][worst[0], :, worst[1]]}, "
        f"FD {fd[worst[0], :, worst[1]]}"
    )
    # the parameters do move the pose: the test is not comparing zeros
    for group in ("E_", "h_", "r_p_", "d_", "A_", "M"):
        cols = [k for k, nm in enumerate(res["names"]) if nm.startswith(group)]
        assert np.abs(fd[:, :, cols]).max() > 1e-9 * (1e-11 if group == "E_" else 1.0), group


@pytest.mark.parametrize("mode", ["paper", "physical"])
@pytest.mark.parametrize("design", ["SR", "DR", "fixed"])
def test_compiled_equals_numpy_reference(cdpr4, design, mode):
    robot = _robot(cdpr4, design)
    P = grid_points([-2.7, 2.7, -2.7, 2.7, -0.2, 5.3], 9)  # also slack, inaccessible, lone-cable points
    a = sensitivities(robot, P, redundancy=mode, engine="numpy")
    b = sensitivities(robot, P, redundancy=mode)
    assert (a["status"] == b["status"]).all() and (a["smooth"] == b["smooth"]).all()
    assert np.array_equal(np.isnan(a["S"]), np.isnan(b["S"]))
    sm = a["smooth"]
    assert sm.sum() > 100
    scale = np.nanmax(np.abs(a["S"][sm]), axis=0)
    assert (np.abs(a["S"][sm] - b["S"][sm]) <= 1e-9 * scale).all()


def test_tied_subsets_are_flagged_and_not_differentiable(cdpr4):
    """On a diagonal of CDPR4 two subsets give the same |dp|: the point is flagged, and the one-sided
    differences of the full solve (which switches subset) indeed differ there."""
    robot = _robot(cdpr4, "SR")
    p = np.array([[1.0, 1.0, 2.0], [1.0, 1.3, 2.0]])
    res = sensitivities(robot, p)
    assert not res["smooth"][0] and res["dp_gap"][0] < GAP_TOL
    assert res["smooth"][1]
    k = res["names"].index("E_2")  # subsets 1-2-3 and 1-3-4 tie on the diagonal: E_2 moves only one
    E = parameter_values(robot)
    L = L_TS(robot, p[:1])
    step = 1e-3 * E[k]
    one_sided = []
    for sign in (1, -1):
        th = E.copy()
        th[k] += sign * step
        one_sided.append(
            sign * (_full_solve(robot_with_parameters(robot, th), p[:1], L, "paper") - res["P_s"][:1]) / step
        )
    assert np.linalg.norm(one_sided[0] - one_sided[1]) > 0.1 * np.linalg.norm(one_sided[0])


def test_lone_cable_points_are_flagged(cdpr4):
    """Hanging on one SR cable, the platform can swing round the joint axis: J is singular."""
    robot = _robot(cdpr4, "SR")
    res = sensitivities(robot, [[-2.45, -2.45, 4.0]], redundancy="physical")
    assert res["status"][0] == "ok" and res["n_taut"][0] == 1
    assert not res["smooth"][0] and res["cond"][0] > 1e8


def test_slack_cables_have_no_sensitivity_in_paper_mode(cdpr4):
    robot = _robot(cdpr4, "DR")
    res = sensitivities(robot, POINTS)
    names = res["names"]
    for i, sub in enumerate(res["subset"]):
        slack = (set(range(4)) - set(sub.tolist())).pop() + 1
        cols = [names.index(f"{g}_{slack}") for g in ("E", "h", "r_p", "d")]
        cols += [names.index(f"A_{slack}_{a}") for a in "xyz"]
        assert (res["S"][i][:, cols] == 0).all() and (res["S"][i] != 0).sum() > 20


def test_sheave_normal_at_the_exit_point(cdpr4):
    """cable_partials writes n_D = (u . z) e_s - (u . e_s) z; it is (D - H) / r_p."""
    robot = _robot(cdpr4, "DR")
    a = robot.arrays
    st = igm_e(robot, POINTS)
    cp = cable_partials(POINTS, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    n_D = cp.du[..., 1] * cp.l_E[..., None]  # du/dr_p = n_D / |l_E|
    np.testing.assert_allclose(n_D, (st.D - st.H) / a.r_p[:, None], atol=1e-12)


@pytest.mark.parametrize("design", ["SR", "DR"])
def test_commanded_lengths_paper_mode(cdpr4, design):
    """Paper mode with commanded lengths: L_TS gives the default answer; the compiled and numpy
    engines agree for other lengths."""
    robot = _robot(cdpr4, design)
    P = grid_points([-2.3, 2.3, -2.3, 2.3, 0.2, 3.7], 6)
    L = L_TS(robot, P)
    a, b = solve_points_fast(robot, P), solve_points_fast(robot, P, L=L)
    for key in ("P_s", "subset", "status", "iterations"):
        assert np.array_equal(a[key], b[key]), key
    L2 = L + 0.003 * np.array([1.0, -0.5, 0.2, 0.7])
    c, d = solve_points_fast(robot, P, L=L2), solve_points(robot, P, L=L2)
    assert (c["status"] == d["status"]).all() and (c["subset"] == d["subset"]).all()
    np.testing.assert_allclose(c["P_s"], d["P_s"], atol=1e-9)
    assert np.abs(c["P_s"] - a["P_s"]).max() > 1e-3


def test_physical_numpy_reference_solver_agrees(cdpr4):
    """The FD test uses the compiled physical solver; the numpy one gives the same P*."""
    robot = _robot(cdpr4, "DR")
    L = L_TS(robot, POINTS)
    np.testing.assert_allclose(
        solve_physical(robot, POINTS, L0=L, tol=SOLVE_TOL)["P_s"],
        _full_solve(robot, POINTS, L, "physical"),
        atol=1e-10,
    )


def test_command_line_point_and_grid(tmp_path, capsys):
    """`cdpr point --sensitivities --json` adds the key `sensitivities` (name -> 3-vector [SI]);
    `cdpr grid --sensitivities` writes the same as columns; both equal the library."""
    import json

    import pandas as pd

    from cdpr.cli.main import main
    from tests.conftest import ROBOTS

    robot = str(ROBOTS / "cdpr4.yaml")
    args = ["--robot", robot, "--pulley", "DR", "--h", "0.1", "--rp", "0.08"]
    assert main(["point", *args, "--at", "0.7", "-1.3", "0.4", "--sensitivities", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = parameter_names(robot_from_file(robot))
    assert list(out["sensitivities"]) == names and out["sensitivities_smooth"] is True
    assert names[0] == "E_1" and names[-1] == "M" and "A_4_z" in names and "r_p_2" in names
    ref = sensitivities(_robot(robot_from_file(robot), "DR"), POINTS[:1])
    np.testing.assert_allclose(
        np.array([out["sensitivities"][nm] for nm in names]).T, ref["S"][0], rtol=1e-12, atol=0
    )
    table = tmp_path / "g.csv"
    assert (
        main(
            [
                "grid",
                *args,
                "--box",
                "-2",
                "2",
                "-2",
                "2",
                "0.5",
                "3",
                "--n",
                "3",
                "--out",
                str(table),
                "--sensitivities",
            ]
        )
        == 0
    )
    df = pd.read_csv(table)
    assert len(df) == 27 and {"dx_dE_1", "dz_dM", "dy_dA_3_z", "smooth"} <= set(df.columns)
    assert main(["point", *args, "--at", "0", "0", "1", "--sensitivities", "--method", "fixed_point"]) == 2
    assert "--sensitivities needs --method newton" in capsys.readouterr().err


def robot_from_file(path):
    from cdpr.robot import load_robot

    return load_robot(path)
