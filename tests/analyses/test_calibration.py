"""Calibration (cdpr.analyses.calibration): recovery of a perturbed robot, coverage of the posterior
intervals, unreachable parameters, the encoder gauge, the exact Jacobian against central differences
of the full residual, D-optimal plans against random ones, and every bad-data case."""

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.errors import CdprError, ConfigError
from cdpr.models.inverse import L_TS
from cdpr.parameters import calibration_names, select_groups
from cdpr.pipeline.calibration_files import write_data, write_robot
from cdpr.robot import BoxBody
from tests.analyses.one_line import assert_refused_in_one_line

BOX = [-1.8, 1.8, -1.8, 1.8, 0.8, 3.5]


def _poses(rng, n, box=BOX):
    lo, hi = np.array(box[::2]), np.array(box[1::2])
    return rng.uniform(lo, hi, (n, 3))


def _truth(robot, groups, seed, priors=None):
    rng = np.random.default_rng(seed)
    idx = select_groups(robot, groups)
    sd = cal.prior_sd(robot, idx, priors or cal.parse_priors(None))
    truth, th = cal.perturbed(robot, idx, sd, rng)
    return rng, idx, sd, truth, th


def recovered_noise_free(robot, groups, seed=3):
    """Fit ``robot`` to noise-free poses (40, σ = 1 nm so the prior no longer pulls) of a truth
    perturbed in ``groups``: full rank, every parameter back to 1e-6 relative from a truth more
    than 1e-3 away, the residual below 1 nm. Returns the Calibration and the true robot."""
    rng, idx, sd, truth, th = _truth(robot, groups, seed)
    data = cal.simulate(truth, robot, _poses(rng, 40), sigma=1e-9)
    c = cal.fit(robot, data, groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == len(idx)
    rel = np.abs(c.estimate - th[idx]) / np.abs(th[idx])
    worst = int(np.argmax(rel))
    assert rel.max() < 1e-6, (c.names[worst], rel[worst])
    # the truth differs from the nominal by far more than that: the test is not comparing nominals
    assert (np.abs(th[idx] - c.nominal) / np.abs(th[idx])).max() > 1e-3
    s = c.summary()
    assert s["samples_used"] == 40 and s["samples_left_out"] == 0 and s["residual_rms_m"] < 1e-9
    return c, truth


def test_noise_free_data_recover_the_truth(cdpr4):
    """A robot perturbed in anchors, dead lengths, pulleys and moduli (28 parameters), noise-free
    poses: every parameter back to 1e-6 relative, every one identified."""
    c, _ = recovered_noise_free(cdpr4, ["anchors", "dead_lengths", "pulleys", "moduli"])
    assert len(c.index) == 28
    assert set(c.ident["labels"]) == {"identified"}


def test_moduli_and_mass_enter_only_as_their_ratio(cdpr4):
    """Scaling every E_i and M by one factor leaves every equilibrium in place: the gauge is found
    and named, not an arbitrary answer."""
    groups = ["moduli", "mass"]
    rng, idx, sd, truth, th = _truth(cdpr4, groups, 5)
    data = cal.simulate(truth, cdpr4, _poses(rng, 20), sigma=1e-9)
    c = cal.fit(cdpr4, data, groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == len(idx) - 1
    words = c.ident["unidentified"][0]
    assert words.startswith("M with E_") and "not seen by the data" in words
    # the estimate satisfies the data: E_i / M recovered exactly
    np.testing.assert_allclose(c.estimate[:4] / c.estimate[4], th[idx][:4] / th[idx][4], rtol=1e-6)


def test_coverage_of_the_95_percent_intervals(cdpr3):
    """Truth drawn from the prior, tracker noise 0.2 mm, 12 poses, full nonlinear fit each time:
    over 120 seeded repeats the truth lies inside the 95 % interval in 90-99 % of the cases."""
    groups = ["dead_lengths", "mass"]
    priors = cal.parse_priors("dead_lengths=20mm,mass=5%")
    inside = []
    box = [-1.2, 1.2, -1.0, 1.4, 0.8, 3.5]
    for seed in range(120):
        rng, idx, sd, truth, th = _truth(cdpr3, groups, 1000 + seed, priors)
        data = cal.simulate(truth, cdpr3, _poses(rng, 12, box), sigma=2e-4, rng=rng)
        c = cal.fit(cdpr3, data, groups, priors=priors)
        pt = c.parameter_table()
        inside.extend(((pt.lo95 <= th[idx]) & (th[idx] <= pt.hi95)).tolist())
    frac = np.mean(inside)
    assert 0.90 <= frac <= 0.99, frac
    assert len(inside) >= 100 * len(groups)


def test_a_parameter_the_data_cannot_reach_stays_at_its_prior(cdpr4):
    """Poses where cable 4 is slack: its dead length moves no pose, stays at the nominal and is
    marked prior-dominated; the other three are identified."""
    from cdpr.analyses.workspace import grid_points
    from cdpr.models.pulleys import total_length_and_direction
    from cdpr.models.sensitivity import sensitivities

    p = grid_points([-2, 2, -2, 2, 0.5, 4], 8)
    L0 = L_TS(cdpr4, p)
    res = sensitivities(cdpr4, p, redundancy="physical", L=L0)
    a = cdpr4.arrays
    stretch = total_length_and_direction(res["P_s"], a.A, a.kind, a.h, a.r_p, a.d, a.inward).L_TE - L0
    # cable 4 slack by more than 3 mm: three prior sds of every dead length cannot make it pull
    slack4 = (res["status"] == "ok") & res["smooth"] & (stretch[:, 3] < -3e-3)
    priors = cal.parse_priors("dead_lengths=1mm")
    rng, idx, sd, truth, th = _truth(cdpr4, ["dead_lengths"], 11, priors)
    data = cal.simulate(truth, cdpr4, p[slack4], sigma=2e-4, rng=rng)
    assert len(data.sample) >= 6
    c = cal.fit(cdpr4, data, ["dead_lengths"], priors=priors)
    assert c.estimate[3] == c.nominal[3]
    assert list(c.ident["labels"]) == ["identified"] * 3 + ["prior-dominated"]
    assert c.ident["ratio"][3] == pytest.approx(1.0, abs=1e-12)
    assert c.ident["unidentified"] == ["d_4 alone (not seen by the data)"]
    assert c.ident["rank"] == 3


def test_encoder_data_without_poses_report_the_gauge(cdpr4, tmp_path):
    """Encoder readings and no pose: no equation in the exact model; the fit says why (d_i and
    offset_i only as their sum) instead of returning an answer."""
    rng = np.random.default_rng(2)
    data = cal.simulate(cdpr4, cdpr4, _poses(rng, 10), offsets=[0.01, -0.02, 0.0, 0.03])
    data.pose[:] = np.nan
    path = tmp_path / "enc.csv"
    write_data(path, data, cdpr4)
    back = cal.read_data(path, cdpr4)
    assert back.encoder and not back.has_pose.any()
    with pytest.raises(
        CdprError, match="no sample has a measured pose.*d_i and offset_i enter only as their sum"
    ):
        cal.fit(cdpr4, back, ["dead_lengths", "offsets"])


def test_encoder_data_with_poses_dead_length_against_offset(cdpr4):
    """With poses, offsets are estimable, but d_i and offset_i differ only through the cable's
    stiffness E S / L0: the weakest directions name them against each other and the sum is sharp."""
    groups = ["dead_lengths", "offsets"]
    rng, idx, sd, truth, th = _truth(cdpr4, groups[:1], 7)
    off = np.array([0.02, -0.01, 0.03, 0.005])
    data = cal.simulate(truth, cdpr4, _poses(rng, 30), sigma=2e-4, rng=rng, offsets=off)
    c = cal.fit(cdpr4, data, groups)
    words = c.ident["unidentified"]
    assert len(words) >= 1 and all(" against offset_" in w or " against d_" in w for w in words)
    cov = c.covariance
    for i in range(4):  # sd of d_i + offset_i (the sum seen by the data) far below either alone
        var_sum = cov[i, i] + cov[4 + i, 4 + i] + 2 * cov[i, 4 + i]
        assert np.sqrt(var_sum) < 0.05 * c.sd[i]
        assert abs((c.estimate[i] + c.estimate[4 + i]) - (th[idx][i] + off[i])) < 5 * np.sqrt(var_sum)


def evaluated_problem(robot, data, groups, priors, tol, scale, rng, base=None):
    """The MAP problem (``calibration.Problem``) of ``data`` on ``base`` (default ``robot``), the
    groups' parameters with the ``priors`` (``parse_priors``), evaluated at z = scale N(0, I) with
    every sample ok and smooth. Returns the problem, the parameters' indices, z, the evaluation and
    the Jacobian at z."""
    base = robot if base is None else base
    idx = select_groups(robot, groups)
    sd = cal.prior_sd(base, idx, cal.parse_priors(priors))
    prob = cal.Problem(base, data, idx, sd, solver={"tol": tol})
    z = scale * rng.standard_normal(len(idx))
    ev = prob.evaluate(z)
    assert ((ev["status"] == "ok") & ev["smooth"]).all()
    return prob, idx, z, ev, prob.jacobian(z)


@pytest.mark.parametrize("model", ["exact", "standard"])
def test_analytic_jacobian_equals_central_differences_of_the_full_residual(cdpr4, model):
    """Problem.jacobian (implicit-function sensitivities and the offset column) against central
    differences of Problem.residual, which re-solves every equilibrium, away from taut-set changes."""
    groups = ["anchors", "dead_lengths", "offsets", "mass"] + (
        ["pulleys", "moduli"] if model == "exact" else []
    )
    rng = np.random.default_rng(4)
    data = cal.simulate(cdpr4, cdpr4, _poses(rng, 8), offsets=np.zeros(4))
    base = cal.model_robot(cdpr4, model)
    prob, idx, z, ev, J = evaluated_problem(cdpr4, data, groups, None, 1e-14, 0.3, rng, base=base)
    step = 1e-5
    fd = np.empty_like(J)
    for j in range(len(idx)):
        e = np.zeros(len(idx))
        e[j] = step
        fd[:, j] = (prob.residual(z + e) - prob.residual(z - e)) / (2 * step)
    scale = np.abs(fd).max(axis=0)
    assert (scale[: len(idx)] > 1e-3).all()  # every column moves the residual
    err = np.abs(J - fd).max(axis=0) / scale
    names = [calibration_names(prob.robot)[k] for k in idx]
    assert err.max() < 1e-5, (names[int(np.argmax(err))], err.max())


def assert_d_optimal_beats_random_plans(rows, n, k):
    """The D-optimal plan of k of the n candidate poses' information ``rows`` has a larger log det
    than 40 random plans of k (seed 0), a smaller median expected sd than theirs, and ``plan_sd``
    gives it the log det ``d_optimal`` says."""
    chosen, logdet = cal.d_optimal(rows, k)
    rng = np.random.default_rng(0)
    rand = [cal.plan_sd(rows, rng.choice(n, k, replace=False)) for _ in range(40)]
    assert logdet > max(r[1] for r in rand)
    assert np.median(cal.plan_sd(rows, chosen)[0]) < np.median([np.median(r[0]) for r in rand])
    assert cal.plan_sd(rows, chosen)[1] == pytest.approx(logdet)


def test_d_optimal_plan_beats_random_plans(cdpr4):
    groups = ["anchors", "dead_lengths", "pulleys"]
    idx = select_groups(cdpr4, groups)
    sd = cal.prior_sd(cdpr4, idx, cal.parse_priors(None))
    P, L0 = cal.candidates(cdpr4, cal.default_box(cdpr4), n_axis=6)
    rows = cal.info_rows(cdpr4, P, L0, idx, sd)
    assert_d_optimal_beats_random_plans(rows, len(P), 15)


def test_calibrated_robot_reaches_the_noise_floor_on_held_out_poses(cdpr4):
    """60 tracker samples at σ = 0.2 mm; on 200 held-out poses the calibrated exact model is within
    10 % of the truth robot's own RMS (the noise floor), the nominal robot far off."""
    groups = ["anchors", "dead_lengths", "pulleys", "moduli"]
    rng, idx, sd, truth, th = _truth(cdpr4, groups, 21)
    train = cal.simulate(truth, cdpr4, _poses(rng, 60), sigma=2e-4, rng=rng)
    test = cal.simulate(truth, cdpr4, _poses(rng, 200), sigma=2e-4, rng=rng)
    c = cal.fit(cdpr4, train, groups)
    floor = cal.check(truth, test)["rms_m"]
    after = cal.check(c.calibrated_robot(), test)["rms_m"]
    before = cal.check(cdpr4, test)["rms_m"]
    assert floor == pytest.approx(2e-4 * np.sqrt(3), rel=0.15)
    assert after <= 1.10 * floor, (after, floor)
    assert before > 10 * floor


def test_write_robot_round_trip(cdpr4, tmp_path):
    from cdpr.parameters import calibration_values
    from cdpr.robot import load_robot

    groups = ["anchors", "dead_lengths", "pulleys", "moduli"]
    rng, idx, sd, truth, th = _truth(cdpr4, groups, 8)
    c = cal.fit(cdpr4, cal.simulate(truth, cdpr4, _poses(rng, 30), sigma=2e-4, rng=rng), groups)
    out = tmp_path / "cal.yaml"
    write_robot(out, c, "m.csv")
    text = out.read_text()
    assert text.startswith("# CDPR4 calibrated by cdpr calibrate fit (exact model) from m.csv")
    back = load_robot(out)
    np.testing.assert_array_equal(calibration_values(back)[idx], c.estimate)


@pytest.mark.parametrize("body", [BoxBody(centre=(0.01, -0.02, 0.03), half=(0.1, 0.2, 0.05)), "none"])
def test_write_robot_keeps_the_platform_body(cdpr4, tmp_path, body):
    """A robot whose platform has a body other than the default hull (a box, none) comes back from
    the calibrated robot file with that body, not with the hull."""
    import dataclasses

    from cdpr.robot import load_robot

    robot = dataclasses.replace(cdpr4, platform=dataclasses.replace(cdpr4.platform, body=body))
    rng, idx, sd, truth, th = _truth(robot, ["anchors"], 3)
    c = cal.fit(robot, cal.simulate(truth, robot, _poses(rng, 12), sigma=2e-4, rng=rng), ["anchors"])
    assert c.calibrated_robot().platform.body == body
    out = tmp_path / "cal.yaml"
    write_robot(out, c, "m.csv")
    back = load_robot(out)
    assert back.platform.body == body
    np.testing.assert_array_equal(back.A, c.calibrated_robot().A)


def test_sr_pulley_may_come_out_slightly_below_its_radius():
    """The loader accepts SR with h >= r_p - 1 mm (calibrated swivel pulleys) and still refuses lower."""
    from cdpr.robot import check_pulley

    check_pulley("SR", 0.0660, 0.0665, "r.yaml", "pulley")
    with pytest.raises(ConfigError, match="h_m >= sheave radius r_p_m - 1 mm"):
        check_pulley("SR", 0.0650, 0.0665, "r.yaml", "pulley")


# --- bad data -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text,column,words",
    [
        ("sample,L1,L2,x_m,y_m,z_m\n1,4,4,0,0,2\n", "L1,L2", "2 length columns but robot CDPR3 has 3 cables"),
        ("sample,L1,L2,L3,L4,x_m,y_m,z_m\n1,4,4,4,4,0,0,2\n", "L1,L2,L3,L4", "allowed: L1..L3"),
        ("sample,L1,L2,L3,x_m,y_m\n1,4,4,4,0,0\n", "z_m", "missing column"),
        ("sample,L1,L2,L3,x_m,y_m,z_m,foo\n1,4,4,4,0,0,2,1\n", "foo", "unknown column"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,,4,0,0,2\n", "L2", "lengths must be finite and > 0"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,inf,4,0,0,2\n", "L2", "lengths must be finite and > 0"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,-4,4,0,0,2\n", "L2", "lengths must be finite and > 0"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,abc,4,0,0,2\n", "L2", "is not a number"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,4,4,0,,2\n", "x_m,y_m,z_m", "all three finite coordinates"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n1,4,4,4,,,\n", "x_m,y_m,z_m", "only encoder data"),
        (
            "sample,L1,L2,L3,x_m,y_m,z_m,sigma_m\n1,4,4,4,0,0,2,0\n",
            "sigma_m",
            "sigma_m must be finite and > 0",
        ),
        ("sample,L1,L2,L3,x_m,y_m,z_m,rx_rad\n1,4,4,4,0,0,2,0\n", "rx_rad", "is a point mass"),
        ("sample,L1,L2,L3,L_enc1,x_m,y_m,z_m\n1,4,4,4,4,0,0,2\n", "L1", "not both"),
        ("sample,L1,L2,L3,x_m,y_m,z_m,t1_N\n1,4,4,4,0,0,2,100\n", "t2_N", "tensions need all of t1_N..t3_N"),
        (
            "sample,L1,L2,L3,x_m,y_m,z_m,t1_N,t2_N,t3_N\n1,4,4,4,0,0,2,1,-2,3\n",
            "t1_N,t2_N,t3_N",
            "tensions must be all finite and >= 0",
        ),
        ("sample,L1,L2,L3,x_m,y_m,z_m,sigma_N\n1,4,4,4,0,0,2,1\n", "sigma_N", "needs the tension columns"),
        ("sample,L1,L2,L3,x_m,y_m,z_m\n", None, "no samples"),
    ],
)
def test_bad_data_is_one_line_naming_file_and_column(cdpr3, tmp_path, text, column, words):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    assert_refused_in_one_line(cal.read_data, path, cdpr3, column, words)


def test_bad_fit_requests(cdpr3, tmp_path):
    data = cal.simulate(cdpr3, cdpr3, np.array([[0.1, 0.2, 2.0], [0.0, -0.3, 2.5]]))
    with pytest.raises(CdprError, match="unknown group 'wheels'"):
        cal.fit(cdpr3, data, ["wheels"])
    with pytest.raises(CdprError, match="'attachments' .* is a point mass"):
        cal.fit(cdpr3, data, ["attachments"])
    with pytest.raises(CdprError, match="offsets needs encoder readings"):
        cal.fit(cdpr3, data, ["offsets"])
    with pytest.raises(CdprError, match="standard model has no pulleys"):
        cal.fit(cdpr3, data, ["pulleys"], model="standard")
    for bad in ("anchors=0mm", "moduli=-5%", "moduli=0", "wheels=1mm", "anchors", "anchors=5 kg"):
        with pytest.raises(CdprError):
            cal.parse_priors(bad)
    assert cal.parse_priors("anchors=2mm,moduli=10%")["anchors"] == pytest.approx(2e-3)
    # a bare relative number is a fraction: 20 would be 2000 %, refused with the percentage asked for
    with pytest.raises(
        CdprError, match=r"must be below 100 %, got '20' \(2000%\); give a percentage, e.g. moduli=20%"
    ):
        cal.parse_priors("moduli=20")
    assert cal.parse_priors("moduli=0.2")["moduli"] == cal.parse_priors("moduli=20%")["moduli"] == 0.2
    # a prior for a group that is not estimated would do nothing: refused, naming it
    with pytest.raises(CdprError, match="a prior for mass, which is not estimated"):
        cal.parse_priors("anchors=3mm,mass=5%", estimate=["anchors"])
    assert cal.parse_priors("anchors=3mm", estimate=["anchors"])["anchors"] == pytest.approx(3e-3)


def test_samples_without_equilibrium_are_flagged_not_dropped(cdpr4):
    """A sample whose commanded lengths (10 % short) would pull the cables beyond their admissible
    tension gives no usable equilibrium: left out with its status in the per-sample table, counted."""
    rng, idx, sd, truth, th = _truth(cdpr4, ["dead_lengths"], 9)
    data = cal.simulate(truth, cdpr4, _poses(rng, 12), sigma=2e-4, rng=rng)
    data.L[0] *= 0.9
    c = cal.fit(cdpr4, data, ["dead_lengths"])
    s = c.summary()
    assert s["samples_used"] == 11 and s["samples_left_out"] == 1
    assert c.table["status"][0] in ("left out at nominal: over_tension", "left out at nominal: inaccessible")
    assert np.isnan(c.table["residual_after_m"][0])


def test_check_reports_rms_max_median(cdpr4):
    rng = np.random.default_rng(1)
    data = cal.simulate(cdpr4, cdpr4, _poses(rng, 25), sigma=2e-4, rng=rng)
    out = cal.check(cdpr4, data)
    err = np.array([s["error_m"] for s in out["samples"]])
    assert out["n"] == 25 and out["rms_m"] == pytest.approx(np.sqrt(np.mean(err**2)))
    assert out["max_m"] == err.max() and out["median_m"] == np.median(err)
    assert 1e-4 < out["rms_m"] < 6e-4


def test_encoder_data_with_tensions_calibrate_without_poses(cdpr4):
    """Encoder readings and measured tensions, no pose: the exact model is identifiable from the
    tensions (offsets, dead lengths, mass); noise-free data recover the truth."""
    groups = ["offsets", "mass"]
    rng, idx, sd, truth, th = _truth(cdpr4, ["mass"], 13)
    off = np.array([0.012, -0.02, 0.007, 0.03])
    data = cal.simulate(truth, cdpr4, _poses(rng, 30), offsets=off, tensions=True, sigma_t=1e-6)
    data.pose[:] = np.nan
    c = cal.fit(cdpr4, data, groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == 5
    assert c.names == ["M", "offset_1", "offset_2", "offset_3", "offset_4"]
    np.testing.assert_allclose(c.estimate[1:], off, rtol=1e-6)
    assert c.estimate[0] == pytest.approx(truth.platform.mass, rel=1e-6)
    s = c.summary()
    assert s["samples_used"] == 30 and s["residual_rms_m"] is None


def test_jacobian_with_tension_rows(cdpr4):
    groups = ["anchors", "dead_lengths", "offsets", "pulleys", "moduli", "mass"]
    rng = np.random.default_rng(6)
    data = cal.simulate(cdpr4, cdpr4, _poses(rng, 6), offsets=np.zeros(4), tensions=True)
    data.pose[::2] = np.nan  # half with tensions only
    idx = select_groups(cdpr4, groups)
    sd = cal.prior_sd(cdpr4, idx, cal.parse_priors(None))
    prob = cal.Problem(cdpr4, data, idx, sd, solver={"tol": 1e-14})
    z = 0.3 * rng.standard_normal(len(idx))
    J = prob.jacobian(z)
    assert J.shape == (3 * 3 + 4 * 6 + len(idx), len(idx))
    fd = np.empty_like(J)
    for j in range(len(idx)):
        e = np.zeros(len(idx))
        e[j] = 1e-5
        fd[:, j] = (prob.residual(z + e) - prob.residual(z - e)) / 2e-5
    scale = np.abs(fd).max(axis=0)
    err = np.abs(J - fd).max(axis=0) / scale
    assert err.max() < 1e-5, (calibration_names(prob.robot)[idx[int(np.argmax(err))]], err.max())


def test_rigid_self_calibration_reports_its_gauge(cdpr4):
    """Encoder-only data of a straight-line robot, poses unknown: the rigid self-calibration fits
    the readings to the noise and reports d_i against offset_i (only their sum is seen) instead of an
    arbitrary split; the sums d_i + o_i are recovered."""
    rng = np.random.default_rng(3)
    n = 30
    P = _poses(rng, n)
    base = cal.model_robot(cdpr4, "standard")
    off = np.array([0.02, -0.03, 0.01, 0.04])
    d_true = cdpr4.arrays.d + np.array([0.01, -0.02, 0.015, 0.0])
    L = cal.standard_lengths(base.A, d_true, off, P) + rng.normal(0, 1e-5, (n, 4))
    data = cal.Data(
        sample=np.arange(n).astype(str),
        L=L,
        pose=np.full((n, 3), np.nan),
        sigma=np.full(n, 2e-4),
        encoder=True,
        source="enc",
    )
    c = cal.self_calibrate_standard(cdpr4, data, ["dead_lengths", "offsets"], sigma_L=1e-5)
    assert c.ident["rank"] == 4
    assert sorted(c.ident["unidentified"]) == [
        f"d_{i} against offset_{i} (not seen by the data)" for i in range(1, 5)
    ]
    cov = c.covariance
    sd_sum = np.sqrt([cov[i, i] + cov[4 + i, 4 + i] + 2 * cov[i, 4 + i] for i in range(4)])
    assert (sd_sum < 1e-4).all() and (c.sd > 0.5 * 0.05).all()  # the sum is sharp, d and o alone are not
    assert (np.abs(c.estimate[:4] + c.estimate[4:] - (d_true + off)) < 4 * sd_sum).all()
    assert c.table["residual_after_m"].max() < 3e-5
    # the split between d and o is the prior's: equal shares of the sum's deviation (same prior sd)
    np.testing.assert_allclose(c.estimate[:4] - cdpr4.arrays.d, c.estimate[4:], atol=1e-5)


def test_robust_loss_lists_the_outlier_and_resists_it(cdpr4):
    """One sample measured 20 mm off: the linear fit is dragged, the soft-L1 fit stays within a few
    sd of the truth and lists the sample as an outlier."""
    groups = ["dead_lengths"]
    rng, idx, sd, truth, th = _truth(cdpr4, groups, 31)
    data = cal.simulate(truth, cdpr4, _poses(rng, 20), sigma=2e-4, rng=rng)
    data.pose[3, 2] += 0.02
    lin = cal.fit(cdpr4, data, groups)
    rob = cal.fit(cdpr4, data, groups, loss="soft_l1")
    assert list(rob.table["sample"][rob.table["outlier"]]) == ["s4"]
    assert not lin.table["outlier"].any()
    err_lin = np.abs(lin.estimate - th[idx]) / lin.sd
    err_rob = np.abs(rob.estimate - th[idx]) / rob.sd
    assert err_rob.max() < 4 and err_lin.max() > 2 * err_rob.max()


def test_plan_refuses_a_bad_box(cdpr4):
    with pytest.raises(CdprError, match="XMIN < XMAX"):
        cal.plan(cdpr4, ["dead_lengths"], 5, box=[1, -1, -1, 1, 0.5, 3])


def test_d_optimal_plan_does_not_depend_on_the_last_bits():
    """Tied candidates (a symmetric robot on a symmetric grid: here each candidate twice, once with
    its rows negated, the same information exactly) go to the first in candidate order, so noise in
    the last bits (another CPU's round-off) does not change the plan."""
    rng = np.random.default_rng(7)
    base = rng.normal(size=(6, 3, 4))
    rows = np.concatenate([base, -base])  # candidate c and c + 6 carry the same information
    chosen, logdet = cal.d_optimal(rows, 5)
    assert (chosen < 6).all()  # every tie went to the first of the pair
    for seed in range(5):
        noise = 1 + 1e-13 * np.random.default_rng(seed).normal(size=rows.shape)
        again, logdet2 = cal.d_optimal(rows * noise, 5)
        assert (again == chosen).all() and logdet2 == pytest.approx(logdet, rel=1e-9)
    # a real difference above the tie tolerance still decides
    better = rows.copy()
    better[6 + chosen[0]] *= 1.01
    assert cal.d_optimal(better, 1)[0][0] == 6 + chosen[0]


def test_prior_only_map_with_fewer_equations_than_parameters(cdpr3):
    """2 samples give 6 equations for 12 parameters: not refused (every group has a prior, so the MAP
    is proper); the data pull the fit towards them, and at least 12 - 6 directions stay at their prior
    (posterior variance 1 in prior-scaled variables)."""
    index = select_groups(cdpr3, ["anchors", "dead_lengths"])
    sd = cal.prior_sd(cdpr3, index, cal.parse_priors(None))
    truth, _ = cal.perturbed(cdpr3, index, sd, np.random.default_rng(7))
    data = cal.simulate(truth, cdpr3, np.array([[0.1, 0.2, 2.0], [0.0, -0.3, 2.5]]))
    res = cal.fit(cdpr3, data, ["anchors", "dead_lengths"])
    t = res.table
    assert (t["status"] == "used").all()
    assert t["residual_after_m"].max() < 0.5 * t["residual_before_m"].max()
    assert res.ident["rank"] <= 6
    eig = np.linalg.eigvalsh(res.ident["cov_scaled"])
    assert (eig > 1 - 1e-9).sum() >= 6 and eig.max() <= 1 + 1e-9
