"""Property test: random poses and pulley sizes keep the model's invariants."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cdpr.models.direct import degm_e
from cdpr.models.inverse import L_TS, igm_e
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.statics import equilibrium_residual
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROBOTS

ROBOT = load_robot(ROBOTS / "cdpr4.yaml")
SUB = [0, 1, 2]


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    kind=st.sampled_from(["SR", "DR"]),
    r_p=st.floats(0.0, 0.12),
    extra=st.floats(0.001, 0.1),
    a=st.floats(0.1, 0.9),
    b=st.floats(0.1, 0.9),
    z=st.floats(0.0, 4.0),
    E=st.floats(50e9, 200e9),
)
def test_solution_invariants(kind, r_p, extra, a, b, z, E):
    r = with_pulleys(ROBOT, kind=kind, h=r_p + extra, r_p=r_p, E=E)
    # a point inside the triangle A1 A2 A3 (x > y)
    P = np.array([[-2.0 + 4.0 * a, -2.0 + 4.0 * a * b, z]])
    st_ = igm_e(r, P)
    # triangle inequality: each straight strand moves by at most |H - A| + r_p = h + r_p, the arc adds <= 2 pi r_p
    assert (np.abs(st_.L_TE - L_TS(r, P)) <= 2 * (r.h + r.r_p) + 2 * np.pi * r.r_p + 1e-12).all()
    res = degm_e(r, P, SUB)
    assert res.converged.all()
    sel = (r.A[SUB], r.kind[SUB], r.h[SUB], r.r_p[SUB], r.d[SUB], r.inward[SUB])
    L_TE, u = total_length_and_direction(res.P, *sel)[:2]
    assert equilibrium_residual(u, res.t, r.platform.w_ext).max() < 1e-6
    assert np.abs(L_TE - L_TS(r, P)[:, SUB] * (1 + res.t / r.ES[list(SUB)])).max() < 1e-9
    # |dp| is bounded by the pulley size plus the elastic stretch scale
    assert np.linalg.norm(res.P - P) < 20 * (r.h[0] + r.r_p[0]) + 0.5
