"""Exact partials of the heavy-cable balance (issue 38; ``cdpr.models.catenary_partials``,
``cdpr.models.heavy_partials``, ``heavy_sensitivity.balance_partials``) tested by physics: the span
partials and the end-force partials of one catenary against central differences of the span
equations and of full span solves (ordinary, U-shaped, w = 1e-8, w = 0, EA = inf); the exit point's
derivatives against differences of ``pulleys.pulley_state`` (SR, DR, turned axes); every column of
∂F6/∂x, ∂F6/∂L0 and ∂F6/∂θ against central differences of the balance (the differenced partials
that heavy_sensitivity used before, tests/models/heavy_fd_reference.py), relative ≤ 1e-6 of the
column, on CDPR4 with SR, DR and fixed pulleys at 0.5 kg/m, on CoGiRo at 0.063 kg/m and on a
platform whose axes and gravity are turned (DR); and w -> 0 gives the massless partials and
sensitivities (``sensitivity``) to 1e-9."""

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.errors import CdprError
from cdpr.models import catenary as cat
from cdpr.models import heavy_sensitivity as hs
from cdpr.models import sensitivity as ms
from cdpr.models.catenary_partials import end_force_partials, span_partials
from cdpr.models.equilibrium import solve
from cdpr.models.heavy_partials import _pulley_jets
from cdpr.models.inverse import pulley_args
from cdpr.models.pulleys import pulley_state
from cdpr.parameters import parameter_names
from cdpr.robot import load_robot, with_pulleys, with_values
from tests.models import heavy_fd_reference as fdr
from tests.models.test_equilibrium_heavy import heavy
from tests.models.test_equilibrium_pose import pretensioned, robot8_turned

ROBOTS = Path(__file__).resolve().parents[2] / "config" / "robots"


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro_massless.yaml")


#: (H, V_B, L0, w, EA): ordinary, U-shaped, hanging, nearly weightless, weightless, inextensible,
#: steep, CoGiRo-like.
SPANS = [
    (100.0, 20.0, 3.0, 5.0, 1e6),
    (100.0, -5.0, 3.0, 5.0, 1e6),
    (50.0, -40.0, 10.0, 5.0, 1e5),
    (200.0, 10.0, 10.0, 1e-8, 1e5),
    (200.0, 10.0, 10.0, 0.0, 1e5),
    (1000.0, 30.0, 12.0, 0.62, np.inf),
    (5.0, 100.0, 5.0, 50.0, 1e6),
    (1500.0, 400.0, 14.0, 0.62, 1.28e6),
]


def _richardson(f, x, h, forward=False):
    """f'(x) by Richardson-extrapolated central (or, ``forward``, one-sided) differences."""

    def d(s):
        if forward:
            return (4.0 * f(x + s / 2) - 3.0 * f(x) - f(x + s)) / s
        return (f(x + s) - f(x - s)) / (2.0 * s)

    return (4.0 * d(h / 2) - d(h)) / 3.0


@pytest.mark.parametrize("span", SPANS)
def test_span_partials_match_central_differences(span):
    x = np.array(span, dtype=float)
    P = span_partials(*x)
    assert P.shape == (2, 5)
    np.testing.assert_allclose(P[:, :2], cat.flexibility(*x))
    for k in range(5):
        if k == 4 and np.isinf(x[4]):
            assert not P[:, 4].any()  # inextensible: no EA dependence
            continue

        def f(v, k=k):
            y = x.copy()
            y[k] = v
            return np.array(cat.span_equations(*y))

        if k == 3:  # w >= 0: one-sided where the step would make it negative
            h = max(1e-3 * x[3], 1e-3)
            fwd = x[3] < h
        else:
            h, fwd = 1e-3 * abs(x[k]), False
        fd = _richardson(f, x[k], h, forward=fwd)
        np.testing.assert_allclose(P[:, k], fd, rtol=0, atol=1e-7 * np.abs(fd).max(), err_msg=str(k))


def test_w_derivative_is_continuous_across_the_quadrature_switch():
    """dl_h/dw by quadrature (w L0 <= 0.1 H) and in closed form meet where they switch."""
    H, V, EA = 100.0, -3.0, 1e6
    L0 = 0.1 * H / 5.0
    below = span_partials(H, V, L0, 5.0 * (1 - 1e-12), EA)[0, 3]
    above = span_partials(H, V, L0, 5.0 * (1 + 1e-12), EA)[0, 3]
    assert abs(below - above) <= 1e-10 * abs(below)


@pytest.mark.parametrize("span", [s for s in SPANS if s[3] > 0])
def test_end_force_partials_match_span_solves(span):
    H, V, L0, w, EA = span
    l_h, l_v = cat.span_equations(*span)
    s = cat.span_state(l_h, l_v, L0, w, EA)
    D = end_force_partials(s.H, s.V_B, L0, w, EA)
    x = np.array([l_h, l_v, L0, w, EA], dtype=float)
    for k in range(5):
        if k == 4 and np.isinf(EA):
            continue

        def f(v, k=k):
            y = x.copy()
            y[k] = v
            st = cat.span_state(*y, rtol=1e-16)
            return np.array([st.H, st.V_B])

        # lengths: a step that changes the forces by 1e-2 of T (the spans' stiffness K can be EA/L0)
        T = np.hypot(H, V)
        h = 1e-2 * T / np.abs(D[:, :3]).max() if k < 3 else 1e-3 * x[k]
        if k == 3:  # w >= 0: at least 1e-3 N/m (above the re-solves' noise), one-sided near 0
            h = max(h, 1e-3)
        fd = _richardson(f, x[k], h, forward=k == 3 and x[3] < h)
        np.testing.assert_allclose(D[:, k], fd, rtol=0, atol=1e-6 * np.abs(fd).max(), err_msg=str(k))


def test_end_force_partials_of_a_slack_weightless_span_are_zero():
    np.testing.assert_array_equal(end_force_partials(0.0, 0.0, 2.0, 0.0, 1e5), np.zeros((2, 5)))


@pytest.mark.parametrize("kind", ["SR", "DR"])
@pytest.mark.parametrize("turned", [False, True])
def test_exit_point_derivatives_match_pulley_state(kind, turned):
    """D and l_dead = |l_d| + r_p gamma of the jets equal pulley_state's and their derivatives by
    P*, h, r_p, d, A equal central differences of it (vertical and turned axes)."""
    Q = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix() if turned else np.eye(3)
    r = robot8_turned(kind, Q)
    A, k, h, r_p, d, inward, frame = pulley_args(r)
    rng = np.random.default_rng(1)
    Pv = (Q @ np.array([0.3, -0.2, 1.2]) + 0.5 * rng.standard_normal((3, 1, 3))).repeat(r.m, axis=1)
    D, dD, ell, dell = _pulley_jets(Pv, A, k, h, r_p, d, frame)

    def f(Pv, A, h, r_p, d):
        s = pulley_state(Pv, A, k, h, r_p, d, inward, frame, per_cable=True)
        return np.concatenate([s.D, (s.l_d + r_p * s.gamma)[..., None]], axis=-1)

    np.testing.assert_allclose(
        np.concatenate([D, ell[..., None]], axis=-1), f(Pv, A, h, r_p, d), rtol=0, atol=1e-14
    )
    an = np.concatenate([dD, dell[..., None, :]], axis=-2)
    for j in range(9):
        args = [Pv, A, h, r_p, d]

        def g(s, j=j):
            a = [x.copy() for x in args]
            if j < 3:
                a[0][..., j] += s
            elif j < 6:
                a[j - 1] = a[j - 1] + s
            else:
                a[1][:, j - 6] += s
            return f(*a)

        fd = _richardson(g, 0.0, 1e-5)
        np.testing.assert_allclose(
            an[..., j], fd, rtol=0, atol=1e-7 * max(np.abs(fd).max(), 1e-3), err_msg=str(j)
        )


def _cdpr4(cdpr4, kind):
    return with_values(with_pulleys(cdpr4, kind=kind), linear_density=0.5)


def _poses(robot):
    A = robot.A
    c = A.mean(axis=0)
    z = A[:, 2].min()
    p = np.array([[c[0] + 0.1, c[1] - 0.05, 0.5 * z], [c[0] + 1.0, c[1] + 0.7, 0.3 * z]])
    rv = np.zeros((2, 3)) if robot.point_mass else np.array([[0.02, -0.01, 0.03], [0.26, 0.0, 0.0]])
    return p, rv


def _check_against_differences(robot, P, R, L0):
    names = parameter_names(robot, rigid=True)
    bp = hs.balance_partials(robot, P, R, L0, names)
    assert np.isfinite(bp["J"]).all() and np.isfinite(bp["dtheta"]).all()
    pairs = [
        ("x", bp["J"], fdr.pose_jacobian(robot, P, R, L0), [f"x{k}" for k in range(6)]),
        ("L0", bp["dL0"], fdr.rest_length_partials(robot, P, R, L0), [f"L0_{i + 1}" for i in range(robot.m)]),
        ("theta", bp["dtheta"], fdr.parameter_partials(robot, P, R, L0, names, rel_step=1e-5), names),
    ]
    worst = 0.0
    for what, an, fd, cols in pairs:
        for k, nm in enumerate(cols):
            scale = np.abs(fd[:, :, k]).max()
            if scale == 0.0:  # a point mass's rotation columns
                assert not an[:, :, k].any(), (what, nm)
                continue
            err = np.abs(an[:, :, k] - fd[:, :, k]).max() / scale
            worst = max(worst, err)
            assert err <= 1e-6, (what, nm, err)
    return worst


@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_balance_partials_match_differences_on_cdpr4(cdpr4, kind):
    robot = _cdpr4(cdpr4, kind)
    p, rv = _poses(robot)
    res = solve(robot, p, rv)
    assert (res["status"] == "ok").all()
    _check_against_differences(robot, res["P_s"], res["R_s"], res["L0"])


def test_balance_partials_match_differences_on_cogiro(cogiro):
    robot = with_values(cogiro, linear_density=0.063)
    p, rv = _poses(robot)
    res = solve(robot, p, rv)
    assert (res["status"] == "ok").all()
    _check_against_differences(robot, res["P_s"], res["R_s"], res["L0"])


def test_balance_partials_match_differences_with_turned_axes_and_gravity():
    """DR pulleys whose swivel axes and gravity are turned: the general pulley coupling."""
    Q = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix()
    r = heavy(robot8_turned("DR", Q), rho=0.5)
    p = (Q @ np.array([[0.3, -0.2, 1.4], [-0.5, 0.4, 1.7]]).T).T
    rv = Rotation.from_matrix(
        Q @ Rotation.from_rotvec([[0.05, -0.1, 0.2], [0.2, 0.1, -0.1]]).as_matrix() @ Q.T
    )
    rv = rv.as_rotvec()
    res = solve(r, p, rv, L0=pretensioned(r, p, rv))
    assert (res["status"] == "ok").all()
    _check_against_differences(r, res["P_s"], res["R_s"], res["L0"])


@pytest.mark.parametrize("rho", [0.0, 1e-10])
@pytest.mark.parametrize(
    "name, kind", [("cdpr4", "SR"), ("cdpr4", "DR"), ("cdpr4", "fixed"), ("cogiro", None)]
)
def test_zero_weight_gives_the_massless_partials_and_sensitivities(request, name, kind, rho):
    """w = 0 through the catenary (and w -> 0): the massless ∂F6/∂x (``Cables``), ∂F6/∂θ
    (``sensitivity._wrench_partials``; a point mass's moment rows are 0 there) and dx*/dθ
    (``sensitivity.sensitivities_at``) to 1e-9 of each column."""
    robot = request.getfixturevalue(name)
    robot = robot if kind is None else with_pulleys(robot, kind=kind)
    p, rv = _poses(robot)
    res = solve(robot, p, rv)
    P, R, L0 = res["P_s"], res["R_s"], res["L0"]
    names = parameter_names(robot, rigid=True)
    light = with_values(robot, linear_density=rho)
    bp = hs.balance_partials(light, P, R, L0, names)
    cab = ms._cables(robot)
    dF, t = ms._wrench_partials(cab, P, R, L0)
    J = cab.evaluate(P, R, L0, P)["J"]
    rows = slice(None) if cab.rigid else slice(0, 3)
    np.testing.assert_allclose(bp["t"], t, rtol=1e-9)
    np.testing.assert_allclose(bp["J"][:, rows], J[:, rows], rtol=0, atol=1e-9 * np.abs(J).max())
    scale = np.abs(dF[:, rows]).max(axis=(0, 1))
    err = np.abs(bp["dtheta"][:, rows] - dF[:, rows]).max(axis=(0, 1))
    assert (err <= 1e-9 * scale).all(), [names[k] for k in np.flatnonzero(err > 1e-9 * scale)]
    S_light = ms.sensitivities_at(robot, res)["S"]
    S_heavy = hs.sensitivities_at(light, res, names)["S"]
    scale = np.abs(S_light).max(axis=(0, 1))
    err = np.abs(S_heavy - S_light).max(axis=(0, 1))
    assert (err <= 1e-9 * scale).all(), [names[k] for k in np.flatnonzero(err > 1e-9 * scale)]


def test_an_unknown_parameter_is_one_error_line(cdpr4):
    with pytest.raises(CdprError, match="unknown 6-DoF parameter"):
        hs.balance_partials(
            _cdpr4(cdpr4, "SR"),
            np.zeros((1, 3)) + [0, 0, 1.5],
            np.eye(3)[None],
            np.full((1, 4), 4.0),
            ["rho_9"],
        )
