"""Uncertainty propagation (cdpr.analyses.uncertainty): seeded samples independent of the shards, the
linearised propagation against full solves, Sobol indices (SALib) of a model with a known answer,
first-order contributions against Monte Carlo, and the study section's checks."""

import copy

import numpy as np
import pytest

from cdpr.analyses import uncertainty as uq
from cdpr.analyses.workspace import grid_points
from cdpr.errors import CdprError, ConfigError
from cdpr.parameters import parameter_names, parameter_values
from cdpr.pipeline.study import Study, check_study, load_study
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROOT

QUICK = ROOT / "config" / "studies" / "quick.yaml"
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]
PARAMS = {
    "young_modulus_Pa": {"dist": "uniform", "low": 67.2e9, "high": 137.2e9, "per_cable": True},
    "h_offset_m": {"dist": "normal", "mean": 0.0, "sd": 2e-4, "low": -6e-4, "high": 6e-4},
    "anchor_offset_m": {"dist": "normal", "mean": 0.0, "sd": 0.002},
    "dead_length_offset_m": {"dist": "uniform", "low": -0.005, "high": 0.005, "per_cable": False},
    "mass_kg": {"dist": "uniform", "low": 285.0, "high": 315.0},
}


@pytest.fixture(scope="module")
def quick():
    import os

    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        yield load_study(QUICK)
    finally:
        os.chdir(cwd)


def _study(st, **mc):
    s = Study(copy.deepcopy(dict(st)))
    s.path = st.path
    s["uncertainty"]["monte_carlo"].update(mc)
    return s


def test_drivers_names_columns_and_order(cdpr4):
    dr = uq.drivers(dict(reversed(list(PARAMS.items()))), cdpr4)  # the study's key order does not matter
    names = [d.name for d in dr]
    assert names[:4] == ["E_1", "E_2", "E_3", "E_4"] and names[-1] == "M"
    assert names[4:8] == ["h_1", "h_2", "h_3", "h_4"] and "d_all" in names and "A_2_y" in names
    cols = parameter_names(cdpr4)
    for d in dr:
        if d.name in cols:
            assert d.columns == (cols.index(d.name),)
    assert next(d for d in dr if d.name == "d_all").columns == tuple(
        cols.index(f"d_{i}") for i in range(1, 5)
    )


def test_samples_do_not_depend_on_the_shards():
    full = uq.mc_uniforms(11, 0, 10, 7)
    parts = np.vstack([uq.mc_uniforms(11, a, b, 7) for a, b in ((0, 3), (3, 4), (4, 10))])
    assert np.array_equal(full, parts)
    assert not np.array_equal(full, uq.mc_uniforms(12, 0, 10, 7))


def test_parameter_samples_and_physical_checks(cdpr4):
    robot = with_pulleys(cdpr4, kind="DR", h=0.1, r_p=0.08)
    dr = uq.drivers(PARAMS, robot)
    U = uq.mc_uniforms(3, 0, 200, len(dr))
    th = uq.parameter_samples(robot, dr, U)
    th0 = parameter_values(robot)
    E = th[:, :4]
    assert (E >= 67.2e9).all() and (E <= 137.2e9).all() and E.std(axis=0).min() > 1e10
    h = th[:, 4:8] - th0[4:8]
    assert np.abs(h).max() <= 6e-4 and h.std() == pytest.approx(2e-4 * 0.986, rel=0.15)  # truncated at 3 sd
    d = th[:, 12:16] - th0[12:16]
    assert np.allclose(d, d[:, :1])  # shared: one draw for every cable
    only_E = uq.parameter_samples(robot, dr, U, active=[x.key == "young_modulus_Pa" for x in dr])
    assert np.array_equal(only_E[:, 4:], np.tile(th0[4:], (200, 1)))
    uq.check_samples(robot, th)
    bad = th.copy()
    bad[7, 4] = 0.05  # DR lever arm below the sheave radius
    with pytest.raises(ConfigError, match="sample 7 gives a DR pulley with h <= r_p"):
        uq.check_samples(robot, bad, "s.yaml")


def test_the_floor_check_is_for_suspended_robots_only(cdpr4):
    """An anchor drawn at or below the floor is refused on a suspended point mass (CDPR4) and
    allowed on a robot whose anchors lie anywhere (IPAnema's lower anchors are at z = 0, so every
    sample with a downward anchor offset would have been refused)."""
    dr = uq.drivers({"anchor_offset_m": {"dist": "normal", "mean": 0.0, "sd": 0.002}}, cdpr4)
    U = uq.mc_uniforms(5, 0, 20, len(dr))
    bad = uq.parameter_samples(cdpr4, dr, U)
    bad[3, 4 * 4 + 2] = 0.0  # A_1_z
    with pytest.raises(ConfigError, match="sample 3 gives an anchor at or below the floor"):
        uq.check_samples(cdpr4, bad, "s.yaml")
    ipa = load_robot(ROOT / "config" / "robots" / "ipanema_like.yaml")
    assert not ipa.suspended_point_mass
    dr8 = uq.drivers({"anchor_offset_m": {"dist": "normal", "mean": 0.0, "sd": 0.002}}, ipa)
    th = uq.parameter_samples(ipa, dr8, uq.mc_uniforms(5, 0, 20, len(dr8)))
    assert (th[:, 4 * ipa.m + 2 : 7 * ipa.m : 3] < 0).any()  # lower anchors drawn below z = 0
    uq.check_samples(ipa, th, "s.yaml")


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_linearised_propagation_against_full_solves_per_cable_E(cdpr4, kind):
    """Paper mode with per-cable moduli over the paper's range: the linearisation (in 1/E, every
    subset and its tensions propagated) gives the global index within 0.1 %; with the nominal
    subset only it does not (the best subset switches)."""
    robot = with_pulleys(
        cdpr4, kind=kind, h=0.1 if kind == "DR" else 0.1077, r_p=0.08 if kind == "DR" else 0.035
    )
    dr = uq.drivers({"young_modulus_Pa": PARAMS["young_modulus_Pa"]}, cdpr4)
    th = uq.parameter_samples(robot, dr, uq.mc_uniforms(5, 0, 6, len(dr)))
    m = uq.PoseErrorModel(robot, grid_points(RW_C, 8), "uncompensated")
    y, ok = m.solve(th)
    dp = y["dp"]
    lin = m.linearise(uq.driver_columns(dr))
    dl = lin.dp(th)
    full, linear = uq.sample_stats(dp, ok), uq.sample_stats(dl, np.isfinite(dl))
    rel = np.abs(linear.index_m - full.index_m) / full.index_m
    assert rel.max() < 1e-3, rel.max()
    # the same propagation restricted to the nominal subset misses the switches
    best = lin.best
    n = len(best)
    v = lin.dp0[np.arange(n), best][None] + np.einsum(
        "nak,sk->sna", lin.S[np.arange(n), best], lin.tau(th) - lin.tau(lin.theta0)
    )
    naive = np.where(lin.ok, np.linalg.norm(v, axis=2), np.nan)
    assert (np.abs(np.nanmean(naive, axis=1) - full.index_m) / full.index_m).max() > 3 * rel.max()


def test_linearisation_error_is_second_order_when_compensated(cdpr4):
    """Compensated robot (physical equilibrium, four taut cables): the linearisation's error falls
    with the square of the parameter spread."""
    robot = with_pulleys(cdpr4, kind="SR", h=0.1077, r_p=0.035)
    m = uq.PoseErrorModel(robot, grid_points([-1.5, 1.5, -1.5, 1.5, 0.5, 3.0], 4), "compensated")
    lin = m.linearise()
    th0 = parameter_values(robot)
    rng = np.random.default_rng(0)
    direction = rng.uniform(-1, 1, (3, len(th0))) * np.abs(th0 + 0.01)
    direction[:, 4 * 4 : 7 * 4] = rng.uniform(-1, 1, (3, 12))  # anchors: metres, not their coordinates
    errs = []
    for eps in (1e-3, 1e-4):
        th = th0 + eps * direction
        y, ok = m.solve(th)
        dp = y["dp"]
        assert ok.all()
        errs.append(np.abs(lin.dp(th) - dp).max() / np.abs(dp).max())
    assert errs[1] < errs[0] / 30, errs


@pytest.mark.parametrize(
    "case,redundancy",
    [("uncompensated", "physical"), ("compensated", "physical"), ("uncompensated", "paper")],
)
def test_full_solves_from_the_linearised_start_equal_those_from_p(cdpr4, case, redundancy):
    """The full solves start Newton at each sample's linearised solution (``start="linear"``, the
    default: the equilibrium in physical mode, every subset in paper mode) or at p: the same ‖δp‖
    within the solver's tolerance and the same ok points, over every declared parameter (all
    drivers vary); the starts are p + Linearisation.shift, which the compiled and numpy engines
    compute alike."""
    robot = with_pulleys(cdpr4, kind="SR", h=0.1077, r_p=0.035)
    dr = uq.drivers(PARAMS, robot)
    th = uq.parameter_samples(robot, dr, uq.mc_uniforms(7, 0, 12, len(dr)))
    pts = grid_points(RW_C, 7)
    models = {
        s: uq.PoseErrorModel(robot, pts, case, redundancy=redundancy, start=s) for s in ("linear", "desired")
    }
    (yl, okl), (yd, okd) = (models[s].solve(th) for s in ("linear", "desired"))
    dl, dd = yl["dp"], yd["dp"]
    np.testing.assert_array_equal(okl, okd)
    assert okl.mean() > 0.5
    assert np.abs(dl - dd)[okl].max() < 1e-9
    # the starts: p + dp0 + S delta of the nominal slot, by either engine, and their definition
    lin = models["linear"].linearise()
    shift = lin.shift(th)
    np.testing.assert_allclose(lin.shift(th, engine="numpy"), shift, rtol=0, atol=1e-15)
    i = np.flatnonzero(lin.ok)[3]
    want = lin.dp0[i, lin.best[i]] + lin.S[i, lin.best[i]] @ (lin.tau(th[2]) - lin.tau(lin.theta0))[0]
    np.testing.assert_allclose(shift[2, i], want, rtol=0, atol=1e-15)
    assert (shift[:, ~lin.ok] == 0).all()
    if redundancy == "paper":  # every subset's start: its slot's shift where valid, p elsewhere
        every = lin.shift(th, every_slot=True)
        start = models["linear"]._starts(th, np.flatnonzero((th != parameter_values(robot)).any(axis=0)))
        np.testing.assert_allclose(start - pts[None, :, None], every, rtol=0, atol=1e-12)
        assert (every[:, ~lin.valid] == 0).all() and lin.valid.sum() > len(pts)
        return
    # the linearised start is far closer to the equilibrium than p (a lower bound of its distance)
    start = models["linear"]._starts(th, np.flatnonzero((th != parameter_values(robot)).any(axis=0)))
    P = pts[models["linear"].feasible][None] + 0  # desired points
    with np.errstate(invalid="ignore"):
        miss = np.abs(np.linalg.norm(start - P, axis=2) - dl[:, models["linear"].feasible])
    miss = np.where(okl[:, models["linear"].feasible], miss, np.nan)
    assert np.nanmedian(miss) < 0.05 * np.nanmedian(dl)
    with pytest.raises(CdprError, match="unknown start 'nominal'; allowed: linear, desired"):
        uq.PoseErrorModel(robot, pts, case, start="nominal")


def test_sobol_indices_of_a_model_with_a_known_answer(cdpr4):
    """Y = sum_k a_k x_k of independent uniform drivers: S1 = ST = a_k^2 / sum a^2 (SALib)."""
    dr = uq.drivers(
        {"mass_kg": {"dist": "uniform", "low": 0.0 + 1, "high": 2.0}, **{"h_offset_m": PARAMS["h_offset_m"]}},
        cdpr4,
    )
    dr = [d for d in dr if d.name in ("M", "h_1", "h_2")]
    a = {"M": 1.0, "h_1": 2.0 / 2e-4, "h_2": 0.5 / 2e-4}  # comparable spreads
    cols = {d.name: d.columns[0] for d in dr}
    m = 4
    robot = cdpr4

    def evaluate(theta):
        th0 = parameter_values(robot)
        return sum(a[nm] * (theta[:, c] - th0[c]) for nm, c in cols.items())[:, None]

    tab, Y, theta = uq.sobol_analysis(evaluate, dr, robot, 1024, 1, ["y"])
    var = {nm: a[nm] ** 2 * d.dist.moments()[1] for nm, d in zip(cols, dr)}
    total = sum(var.values())
    for r in tab.itertuples():
        assert r.ST == pytest.approx(var[r.name] / total, abs=max(0.03, 2 * r.ST_conf)), r
    assert tab.set_index("name").ST.idxmax() == max(var, key=var.get)
    # the rows A and B of Saltelli's design are where uncertainty.sobol takes them
    from SALib.analyze.sobol import separate_output_values

    A, B, _, _ = separate_output_values(Y[:, 0], len(dr), 1024, False)
    D = len(dr)
    assert np.array_equal(A, Y[0 :: D + 2, 0]) and np.array_equal(B, Y[D + 1 :: D + 2, 0])
    assert m == robot.m


def test_local_contributions_add_up_to_the_linearised_mean_square(cdpr4):
    """Compensated: the first-order contributions of independent drivers add up to E|dp|^2 of the
    linearised model (Monte Carlo over 4000 samples, 5 %)."""
    robot = with_pulleys(cdpr4, kind="DR", h=0.1, r_p=0.08)
    m = uq.PoseErrorModel(robot, np.array([[0.4, -0.6, 1.8], [-1.2, 0.9, 2.9]]), "compensated")
    params = {k: v for k, v in PARAMS.items() if k != "young_modulus_Pa"}  # linear in these
    dr = uq.drivers(params, robot)
    lin = m.linearise(uq.driver_columns(dr))
    c = uq.local_contributions(lin, dr, projected=False)
    th = uq.parameter_samples(robot, dr, uq.mc_uniforms(9, 0, 4000, len(dr)))
    msq = (lin.dp(th) ** 2).mean(axis=0)
    np.testing.assert_allclose(c.sum(axis=1), msq, rtol=0.05)


UQ_CASES = [  # (edit of the quick study's text, key named in the message)
    ("designs: [SRopt, DRopt]", "designs: [SRopt, XRopt]", "uncertainty.designs[1]"),
    ("vary: [young_modulus_Pa]", "vary: [young_modulus_Pa, h_offset_m]", "uncertainty.parameters.h_offset_m"),
    ("full_samples: 4", "full_samples: 40", "uncertainty.monte_carlo.full_samples"),
    ("shards: 1\n    index_n: 6", "shards: 5\n    index_n: 6", "uncertainty.monte_carlo.shards"),
    ("base_samples: 4", "base_samples: 6", "uncertainty.sobol.base_samples"),
    ("low: 67.2e+9, high: 137.2e+9", "low: 67.2e+9", "uncertainty.parameters.young_modulus_Pa.high"),
    (
        "low: 67.2e+9, high: 137.2e+9",
        "low: -1.0e+9, high: 137.2e+9",
        "uncertainty.parameters.young_modulus_Pa",
    ),
    ("dist: uniform, low: 285.0", "dist: gamma, low: 285.0", "uncertainty.parameters.mass_kg.dist"),
    (
        "h_offset_m: {dist: normal, mean: 0.0, sd: 0.0002, low: -0.0006",
        "h_offset_m: {dist: normal, mean: 0.0, sd: 0.0002, low: -0.03",
        "uncertainty.parameters.h_offset_m",
    ),
    ("points_m: [[0.0, 0.0, 1.0]]", "points_m: [[0.0, 0.0, 6.0]]", "uncertainty.sobol.points_m[0]"),
    ("map_n: 7", "map_n: 7\n  extra: 1", "uncertainty.extra"),
]


@pytest.mark.parametrize("old,new,key", UQ_CASES, ids=[c[2] for c in UQ_CASES])
def test_bad_uncertainty_values_name_file_and_key(tmp_path, monkeypatch, old, new, key):
    monkeypatch.chdir(ROOT)
    text = QUICK.read_text()
    assert old in text, old
    if "vary" in new:
        text = text.replace("    h_offset_m:", "    #", 1)  # h_offset_m not declared
        key = "uncertainty.monte_carlo.vary[1]"
    bad = tmp_path / "study.yaml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(ConfigError) as exc:
        load_study(bad)
    msg = str(exc.value)
    assert msg.startswith(f"{bad}: key '{key}") and len(msg.splitlines()) == 1, msg


def test_a_study_without_uncertainty_section_is_valid(quick):
    st = Study({k: v for k, v in quick.items() if k != "uncertainty"})
    st.path = quick.path
    check_study(st)


@pytest.mark.parametrize("shape,axis", [((300, 40), 1), ((300, 40), 0), ((7, 9, 11), 1), ((60, 3), 0)])
def test_nanquantile_is_numpys_to_the_bit(shape, axis):
    """Grouping the slices by where their NaN are gives numpy's nanquantile bit for bit, also for
    slices of NaN only, several NaN patterns shared by many slices, and a 3-D array."""
    rng = np.random.default_rng(7)
    a = rng.random(shape) ** 3
    a[rng.random(shape) < 0.15] = np.nan
    a[..., :2][rng.random(a[..., :2].shape) < 0.9] = np.nan  # many slices share their first NaN
    a.reshape(-1)[:5] = np.nan
    np.moveaxis(a, axis, -1)[0] = np.nan  # a slice of NaN only
    q = [0.025, 0.5, 0.95]
    with np.errstate(all="ignore"), pytest.warns(RuntimeWarning):
        ref = np.nanquantile(a, q, axis=axis)
    got = uq.nanquantile(a, q, axis)
    assert got.shape == ref.shape and np.isnan(got).any()
    assert np.array_equal(got, ref, equal_nan=True)
    assert uq.nanquantile(np.zeros((0, 4)), q, 1).shape == (3, 0)  # sample_stats' empty table
