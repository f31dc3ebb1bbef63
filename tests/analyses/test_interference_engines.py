"""Heavy cables' interference by either engine (``analyses.interference.tested``): the catenaries
the compiled ``heavy_cables`` solved give the numpy reference's polylines, flags and distances."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from cdpr.analyses.interference import add_interference, cable_interference, interfering_at
from cdpr.models.cables import HeavyCables, heavy_cables
from cdpr.models.interference import cable_polylines
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays
from cdpr.robot import robot_from_dict
from cdpr.solve import heavy_cables_at

ROOT = Path(__file__).resolve().parents[2]


def _cogiro(density):
    data = yaml.safe_load((ROOT / "config" / "robots" / "cogiro.yaml").read_text())
    data["cable"]["linear_density_kg_m"] = density
    return robot_from_dict(data, "cogiro")


def _poses(robot, n, seed):
    rng = np.random.default_rng(seed)
    p = np.column_stack([rng.uniform(-5, 5, n), rng.uniform(-3.5, 3.5, n), rng.uniform(0.5, 4.0, n)])
    rv = rng.normal(0.0, 0.2, (n, 3))
    L0 = L_TS(robot, np.column_stack([p, rv])) * (1.0 + rng.uniform(-2e-3, 2e-3, (n, robot.m)))
    return p, rv, L0


def test_compiled_cable_state_draws_the_reference_polylines():
    """CoGiRo at 0.5 kg/m (sags of decimetres), random tilted poses and perturbed rest lengths: the
    compiled cables' V_B and L0_free equal the reference's, and the polylines drawn from them equal
    the reference's own within 1e-12 m (both ends exactly B and D)."""
    robot = _cogiro(0.5)
    p, rv, L0 = _poses(robot, 40, 3)
    P, R = pose_arrays(p, rv)
    ref = heavy_cables(HeavyCables(robot), P, R, L0)
    got = heavy_cables_at(robot, P, R, L0)
    for key in ("H", "V_B", "L0_free", "D"):
        np.testing.assert_allclose(got[key], ref[key], rtol=1e-11, atol=1e-9, err_msg=key)
    assert (ref["V_B"] != 0).all() and (ref["L0_free"] < L0).all()
    X = cable_polylines(robot, P, R, L0)
    Y = cable_polylines(robot, P, R, L0, cables=got)
    np.testing.assert_allclose(Y, X, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(Y[:, :, -1], got["D"])


def test_both_engines_flag_the_same_poses():
    """The same poses tested with the numpy coupling and with the compiled cables: the same
    interference flags, pairs through the body and closest pairs; distances within 1e-12 m. Some
    poses interfere (else the test says nothing)."""
    robot = _cogiro(0.5)
    p, rv, L0 = _poses(robot, 120, 5)
    P, R = pose_arrays(p, rv)
    a, b = cable_interference(robot, P, R, L0, engine="numpy"), cable_interference(robot, P, R, L0)
    for name in ("free", "cc", "cp", "dmin_pair"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    for name in ("distance", "dmin", "length", "depth"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=0, atol=1e-12, err_msg=name)
    assert 0 < (~a.free).sum() < len(p)
    np.testing.assert_array_equal(interfering_at(robot, p, rv, L0=L0), ~b.free)
    np.testing.assert_array_equal(interfering_at(robot, p, rv, L0=L0, engine="numpy"), ~a.free)
    df = pd.DataFrame(
        np.column_stack([p, rv, p, rv]),
        columns=[*"xyz", "rx", "ry", "rz", "x_s", "y_s", "z_s", "rx_s", "ry_s", "rz_s"],
    )
    t1 = add_interference(robot, df.copy(), L0=L0)
    t2 = add_interference(robot, df.copy(), L0=L0, engine="numpy")
    np.testing.assert_array_equal(t1["interference_free"].to_numpy(), t2["interference_free"].to_numpy())
    np.testing.assert_allclose(t1["dmin_m"], t2["dmin_m"], rtol=0, atol=1e-12)


def test_a_pose_where_no_pair_can_interfere():
    """CoGiRo with its 4 mm cable at the centre of its workspace: no pair's bound allows contact,
    so the flags-only test measures no pair at all (and says free), as the full test does."""
    robot = _cogiro(0.0631)
    p, rv = np.array([[0.0, 0.0, 2.0]]), np.zeros((1, 3))
    L0 = L_TS(robot, np.column_stack([p, rv]))
    assert not interfering_at(robot, p, rv, L0=L0)[0]
    assert cable_interference(robot, *pose_arrays(p, rv), L0).free[0]
