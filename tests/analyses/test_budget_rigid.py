"""The error budget's rigid-cable entries (cables E x ``budget.RIGID``): where Newton from the desired
pose stops without converging, ``budget.variant`` solves the point again by the continuation in
stiffness of ``solve.solve_stiff`` (the cables' own E, then x 10, x 100, ... x RIGID, each stage from
the previous pose). On the quick spatial study's SRopt design (CoGiRo, 100 mm swivel pulleys) the
pulley entry's two points that Newton leaves ``not_converged`` converge, to a pose whose force
residual is that of the points the plain solver converges at, which an independent method reaches
too: the rigid-cable equilibrium as a constrained minimum (SLSQP: the potential energy under
L_TE,i <= L0_i, no E at all), polished by Newton at E x RIGID from there, equals it to 1e-9 m and
rad; the points the plain solver converged at are kept bit for bit."""

import numpy as np
import pytest
from scipy.optimize import minimize

from cdpr import solve as solver
from cdpr.analyses import budget
from cdpr.analyses.workspace import grid_points
from cdpr.errors import CdprError
from cdpr.models import equilibrium
from cdpr.models.cables import Cables
from cdpr.models.inverse import pose_state
from cdpr.models.platform import rotation_matrix, rotvec_of
from cdpr.pipeline import study
from tests.conftest import ROOT

#: The budget box of tests/pipeline/test_study_wrench.py inside CoGiRo's RW_C (2^3 points).
BOX = np.array([-0.4, 0.4, -0.4, 0.4, 2.4, 3.0])
P = grid_points(BOX, 2)
RV = np.zeros((len(P), 3))
PULLEY = ("pulley",)


@pytest.fixture(scope="module")
def design():
    st = study.load_study(ROOT / "config" / "studies" / "quick_spatial.yaml")
    robot = study.design_robot(st, st["doe"]["robot"], st["optimal"]["SRopt"])
    return budget.with_drums(robot, budget.TABLE1)


@pytest.fixture(scope="module")
def case(design):
    """The pulley entry's robot (E x RIGID), its commanded lengths, and the plain solve of it."""
    L0 = budget.model_lengths(design, P, (), rotvec=RV)
    rigid = budget.effect_robot(design, PULLEY)
    plain = solver.solve(rigid, P, RV, redundancy="physical", L0=L0, engine="numpy")
    return rigid, L0, plain


@pytest.fixture(scope="module")
def stiff(design, case):
    _, L0, plain = case
    bad = np.flatnonzero(plain["status"] == "not_converged")
    elastic = budget.effect_robot(design, (*PULLEY, "elasticity"))
    res = solver.solve_stiff(elastic, P[bad], budget.RIGID, RV[bad], L0=L0[bad], engine="numpy")
    return bad, res


def test_newton_from_the_desired_pose_leaves_points_of_the_pulley_entry_unsolved(case):
    # what the continuation is for: the stiff problem's Newton stops at its iteration cap
    _, _, plain = case
    bad = plain["status"] == "not_converged"
    assert 0 < bad.sum() < len(P)
    assert (plain["iterations"][bad] == equilibrium.PHYSICAL_DEFAULTS["maxiter"]).all()
    assert plain["residual"][bad].min() > 1.0  # N, far from balance


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_the_pulley_entry_converges_at_every_point(design, case, engine):
    _, _, plain = case
    v = budget.variant(design, P, PULLEY, (), rotvec=RV, engine=engine)
    assert (v["status"] == "ok").all(), v["status"]
    if engine == "numpy":  # the points solved before are kept bit for bit
        ok = plain["status"] == "ok"
        assert np.array_equal(v["dp"][ok], plain["P_s"][ok] - P[ok])
        assert np.array_equal(v["dphi"][ok], rotvec_of(plain["R_s"][ok]))


def test_the_continued_points_are_balanced_as_the_solved_ones(case, stiff):
    _, _, plain = case
    _, res = stiff
    assert (res["status"] == "ok").all() and res["converged"].all()
    ok = plain["status"] == "ok"
    # a stiff solve converges on its 1e-10 m step rule, not on the force (1e-6 of the elastic
    # compliance turns a 1e-10 m step into ~1e-4 N): the continued points are as balanced as the others
    assert res["residual"].max() <= 2 * plain["residual"][ok].max()
    assert res["n_taut"].min() >= 6  # held by six cables at least: a determinate equilibrium


def test_an_independent_rigid_cable_minimum_reaches_the_same_pose(case, stiff):
    rigid, L0, _ = case
    bad, res = stiff
    cab = Cables(rigid)
    for j, i in enumerate(bad):

        def lengths(x, i=i):
            return pose_state(rigid, x[None, :3], rotation_matrix(x[None, 3:]))[1].L_TE[0]

        def energy(x, i=i):  # gravity's potential (no wrench on this robot); inextensible cables
            return -(x[:3] - P[i] + rotation_matrix(x[None, 3:])[0] @ cab.com) @ cab.f

        for start in ([0.0, 0.0, 0.0], [0.0, 0.0, 0.05], [0.03, -0.03, 0.1]):
            x0 = np.r_[P[i] + start, 0.0, 0.0, 0.0]
            cons = [{"type": "ineq", "fun": lambda x, i=i: L0[i] - lengths(x)}]
            o = minimize(
                energy, x0, method="SLSQP", constraints=cons, options={"ftol": 1e-14, "maxiter": 500}
            )
            assert np.linalg.norm(o.x[:3] - res["P_s"][j]) < 1e-4  # the same equilibrium, to SLSQP's accuracy
            Pn, Rn, _, _, conv = equilibrium.local_newton(
                cab,
                o.x[None, :3],
                rotation_matrix(o.x[None, 3:]),
                L0[i : i + 1],
                P[i : i + 1],
                1e-10,
                60,
                0.5,
            )
            assert conv[0]
            assert np.linalg.norm(Pn[0] - res["P_s"][j]) < 1e-9
            assert np.linalg.norm(rotvec_of(Rn)[0] - res["rotvec_s"][j]) < 1e-9


def test_without_stiffening_it_is_the_plain_solve(design):
    elastic = budget.effect_robot(design, (*PULLEY, "elasticity"))
    L0 = budget.model_lengths(design, P[:2], (), rotvec=RV[:2])
    a = solver.solve_stiff(elastic, P[:2], 1.0, RV[:2], L0=L0, engine="numpy")
    b = solver.solve(elastic, P[:2], RV[:2], redundancy="physical", L0=L0, engine="numpy")
    assert np.array_equal(a["P_s"], b["P_s"]) and np.array_equal(a["status"], b["status"])
    assert solver.stiffened(elastic, 1e3).cables[0].material.E == elastic.cables[0].material.E * 1e3
    with pytest.raises(CdprError, match="factor"):
        solver.solve_stiff(elastic, P[:1], 0.5)
