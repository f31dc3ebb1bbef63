"""Calibration of a rigid 6-DoF platform (cdpr.analyses.calibration on CoGiRo): recovery of a
perturbed robot from noise-free poses, the exact Jacobian (position and orientation rows) against
central differences of the full residual, a parameter the data cannot reach, the d_i / offset_i
gauge and the E/M ratio, the D-optimal plan against random plans, bad data, and the command line
(fit, the written robot, check)."""

import json

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.cli.main import main
from cdpr.errors import CdprError, ConfigError
from cdpr.models.inverse import L_TS
from cdpr.models.platform import rotation_matrix
from cdpr.parameters import calibration_names, parameter_names, select_groups
from cdpr.pipeline.calibration_files import write_data
from cdpr.robot import load_robot
from tests.analyses.test_calibration import _truth, assert_d_optimal_beats_random_plans, evaluated_problem
from tests.conftest import ROBOTS

COGIRO = str(ROBOTS / "cogiro_massless.yaml")


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(COGIRO)


def _poses(rng, n, tilt=0.1, margin=100.0):
    """n poses inside CoGiRo's workspace with small tilts where, commanded with L_TS, the nominal
    robot holds every cable taut by more than ``margin`` [N] (a perturbed robot stays away from a
    taut-set change): ``calibration.random_poses``."""
    return cal.random_poses(load_robot(COGIRO), rng, n, [-3, 3, -2, 2, 1.0, 2.5], tilt, margin)


def test_one_naming_of_the_spatial_vector(cogiro):
    """The sensitivities' names are the parameter vector's (cdpr.parameters), attachments b_i_xyz."""
    from cdpr.models import sensitivity

    assert sensitivity.parameter_names is parameter_names
    names = calibration_names(cogiro)
    idx = select_groups(cogiro, ["attachments"])
    assert [names[k] for k in idx] == [f"b_{i}_{a}" for i in range(1, 9) for a in "xyz"]
    assert cal.prior_sd(cogiro, idx, cal.parse_priors(None)) == pytest.approx(np.full(24, 3e-3))


def test_noise_free_data_recover_the_truth(cogiro):
    """CoGiRo perturbed in anchors, attachments, dead lengths and moduli (64 parameters), 30
    noise-free poses (σ = 1 nm, 1 nrad): full rank, every parameter back to 1e-6 relative."""
    groups = ["anchors", "attachments", "dead_lengths", "moduli"]
    rng, idx, sd, truth, th = _truth(cogiro, groups, 1)
    data = cal.simulate(truth, cogiro, _poses(rng, 30), sigma=1e-9, sigma_rad=1e-9)
    assert len(data.sample) == 30  # every pose reached with 8 taut cables
    c = cal.fit(cogiro, data, groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == len(idx) == 64
    scale = np.maximum(np.abs(th[idx]), sd)  # b_i_z is ~0: relative to the prior sd there
    rel = np.abs(c.estimate - th[idx]) / scale
    worst = int(np.argmax(rel))
    assert rel.max() < 1e-6, (c.names[worst], rel[worst])
    assert (np.abs(th[idx] - c.nominal) / scale).max() > 0.5  # the truth is far from the nominal
    assert set(c.ident["labels"]) == {"identified"}
    s = c.summary()
    assert s["samples_used"] == 30 and s["residual_rms_m"] < 1e-9 and s["residual_rms_rad"] < 1e-9
    before = c.table["residual_before_rad"].to_numpy()
    assert np.sqrt(np.mean(before**2)) > 1e-4  # the nominal robot's orientation error was real


def test_analytic_jacobian_equals_central_differences_of_the_full_residual(cogiro):
    """Problem.jacobian (implicit-function sensitivities, the offsets' dx/dL0 column and the SO(3)
    log Jacobian of the orientation rows) against central differences of Problem.residual, which
    re-solves every equilibrium; orientation errors of ~0.1 rad so J_r^-1 matters."""
    groups = ["moduli", "dead_lengths", "anchors", "attachments", "offsets", "mass"]
    rng = np.random.default_rng(4)
    data = cal.simulate(cogiro, cogiro, _poses(rng, 4), offsets=np.zeros(8), sigma_rad=0.1, rng=rng)
    prob, idx, z, ev, J = evaluated_problem(cogiro, data, groups, None, 1e-14, 0.3, rng)
    names = [calibration_names(cogiro)[k] for k in idx]
    cols = [names.index(n) for n in ("E_2", "d_3", "A_1_x", "A_6_z", "b_2_y", "b_5_z", "offset_4", "M")]
    step = 1e-5
    for j in cols:
        e = np.zeros(len(idx))
        e[j] = step
        fd = (prob.residual(z + e) - prob.residual(z - e)) / (2 * step)
        rows = fd[: 6 * len(data.sample)].reshape(-1, 6)
        an = J[: 6 * len(data.sample), j].reshape(-1, 6)
        for part, sl in (("position", slice(0, 3)), ("orientation", slice(3, 6))):
            scale = np.abs(rows[:, sl]).max()
            assert scale > 1e-3, (names[j], part)  # the column moves these rows
            err = np.abs(an[:, sl] - rows[:, sl]).max() / scale
            assert err < 1e-5, (names[j], part, err)
        np.testing.assert_array_equal(J[6 * len(data.sample) :, j], np.eye(len(idx))[j])
    # the orientation residual is large: J_r^-1 differs from the identity by ~|e|/2
    e = cal.orientation_residual(prob._R, ev["R"])
    assert np.linalg.norm(e, axis=1).min() > 0.02


def _measure(truth, L, P6):
    """Noise-free poses of ``truth`` under commanded lengths L started at P6 (test helper)."""
    res = cal.equilibria(truth, P6[:, :3], L, rotvec=P6[:, 3:])
    assert ((res["status"] == "ok") & res["smooth"]).all()
    n = len(L)
    return cal.Data(
        sample=np.array([f"s{i}" for i in range(n)]),
        L=L,
        pose=res["P_s"],
        sigma=np.full(n, 2e-4),
        encoder=False,
        source="<test>",
        rotvec=res["rotvec_s"],
        sigma_rad=np.full(n, 1e-3),
    ), res


def test_a_parameter_the_data_cannot_reach_stays_at_its_prior(cogiro):
    """Cable 8 commanded 0.5 m too long: where it hangs slack its dead length moves no pose; on
    those samples d_8 stays at the nominal, prior-dominated (ratio 1), "not seen by the data"; the
    other seven dead lengths are identified."""
    priors = cal.parse_priors("dead_lengths=1mm")
    rng, idx, sd, truth, th = _truth(cogiro, ["dead_lengths"], 11, priors)
    P6 = _poses(rng, 16, tilt=0.05)
    L = L_TS(cogiro, P6[:, :3], R=rotation_matrix(P6[:, 3:]))
    L[:, 7] += 0.5
    data, res = _measure(truth, L, P6)
    slack8 = ~res["taut"][:, 7]
    assert slack8.sum() >= 10
    c = cal.fit(cogiro, data.subset(np.flatnonzero(slack8)), ["dead_lengths"], priors=priors)
    assert (c.table["status"] == "used").all()
    assert c.estimate[7] == c.nominal[7]
    assert list(c.ident["labels"]) == ["identified"] * 7 + ["prior-dominated"]
    assert c.ident["ratio"][7] == pytest.approx(1.0, abs=1e-12)
    assert c.ident["unidentified"] == ["d_8 alone (not seen by the data)"]
    assert c.ident["rank"] == 7


def test_moduli_and_mass_enter_only_as_their_ratio(cogiro):
    """Scaling every E_i and M by one factor moves no pose of the rigid platform either: rank
    k - 1, the null direction named, E_i / M recovered."""
    groups = ["moduli", "mass"]
    rng, idx, sd, truth, th = _truth(cogiro, groups, 5)
    data = cal.simulate(truth, cogiro, _poses(rng, 12), sigma=1e-9, sigma_rad=1e-9)
    c = cal.fit(cogiro, data, groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == len(idx) - 1 == 8
    assert (
        c.ident["unidentified"][0].startswith("M with E_")
        and "not seen by the data" in c.ident["unidentified"][0]
    )
    np.testing.assert_allclose(c.estimate[:8] / c.estimate[8], th[idx][:8] / th[idx][8], rtol=1e-6)


def test_encoder_data_dead_length_against_offset(cogiro):
    """Encoder readings with poses: d_i and offset_i differ only through the stiffness E S / L0;
    the weak directions name them against each other, the sum d_i + offset_i is sharp."""
    groups = ["dead_lengths", "offsets"]
    rng, idx, sd, truth, th = _truth(cogiro, groups[:1], 7)
    off = np.linspace(-0.02, 0.03, 8)
    data = cal.simulate(truth, cogiro, _poses(rng, 20), sigma=2e-4, rng=rng, offsets=off)
    c = cal.fit(cogiro, data, groups)
    words = c.ident["unidentified"]
    assert len(words) >= 1 and all(" against offset_" in w or " against d_" in w for w in words)
    assert "prior-dominated" in set(c.ident["labels"]) or "partly" in set(c.ident["labels"])
    cov = c.covariance
    for i in range(8):
        var_sum = cov[i, i] + cov[8 + i, 8 + i] + 2 * cov[i, 8 + i]
        assert np.sqrt(var_sum) < 0.05 * c.sd[i]
        assert abs((c.estimate[i] + c.estimate[8 + i]) - (th[idx][i] + off[i])) < 5 * np.sqrt(var_sum)


def test_d_optimal_plan_beats_random_plans(cogiro):
    groups = ["anchors", "attachments"]
    idx = select_groups(cogiro, groups)
    sd = cal.prior_sd(cogiro, idx, cal.parse_priors(None))
    P, L0 = cal.candidates(cogiro, cal.default_box(cogiro), n_axis=5)
    assert P.shape[1] == 6 and len(P) >= 40
    rows = cal.info_rows(cogiro, P, L0, idx, sd)
    assert rows.shape == (len(P), 6, 48)
    assert_d_optimal_beats_random_plans(rows, len(P), 12)


@pytest.mark.parametrize(
    "drop, column",
    [("rz_rad", "rz_rad"), ("sigma_none", None)],
)
def test_bad_spatial_data(cogiro, tmp_path, drop, column):
    rng = np.random.default_rng(5)
    data = cal.simulate(cogiro, cogiro, _poses(rng, 3))
    path = tmp_path / "d.csv"
    write_data(path, data, cogiro)
    back = cal.read_data(path, cogiro)
    np.testing.assert_array_equal(back.rotvec, data.rotvec)
    import pandas as pd

    df = pd.read_csv(path)
    if column:  # an orientation column missing on a spatial robot: one line naming file and column
        df.drop(columns=[column]).to_csv(path, index=False)
        with pytest.raises(ConfigError, match=rf"{path.name}.*{column}.*6-DoF platform"):
            cal.read_data(path, cogiro)
    else:  # half a pose
        df.loc[1, "ry_rad"] = np.nan
        df.to_csv(path, index=False)
        with pytest.raises(ConfigError, match=r"ry_rad.*row 2: a 6-DoF pose needs all six"):
            cal.read_data(path, cogiro)


def test_attachments_and_orientation_refused_on_a_point_mass(cdpr4, tmp_path):
    with pytest.raises(
        CdprError, match="'attachments' .* are for a 6-DoF platform; robot CDPR4 is a point mass"
    ):
        select_groups(cdpr4, ["anchors", "attachments"])
    path = tmp_path / "pm.csv"
    path.write_text("sample,L1,L2,L3,L4,x_m,y_m,z_m,rx_rad\ns1,5,5,5,5,0,0,1,0\n")
    with pytest.raises(ConfigError, match="rx_rad.*point mass"):
        cal.read_data(path, cdpr4)


def test_cli_fit_on_cogiro(cogiro, tmp_path, capsys):
    """`cdpr calibrate fit --robot config/robots/cogiro.yaml --estimate anchors,attachments --json`:
    the issue's keys, residual_rms_rad filled, the residual drops to the noise; --out has B_m."""
    rng, idx, sd, truth, th = _truth(cogiro, ["anchors", "attachments"], 9)
    data = cal.simulate(truth, cogiro, _poses(rng, 20), sigma=2e-4, sigma_rad=1e-3, rng=rng)
    csv = tmp_path / "m.csv"
    write_data(csv, data, cogiro)
    out = tmp_path / "cal.yaml"
    args = ["calibrate", "fit", "--robot", COGIRO, "--data", str(csv)]
    args += ["--estimate", "anchors,attachments", "--out", str(out), "--json"]
    assert main(args) == 0
    s = json.loads(capsys.readouterr().out)
    assert set(s) >= {"parameters", "rank", "residual_rms_m", "residual_rms_rad", "samples_used"}
    assert s["n_parameters"] == 48 and s["samples_used"] == 20
    assert s["parameters"][24]["name"] == "b_1_x" and s["parameters"][24]["group"] == "attachments"
    assert s["residual_rms_m"] < 2e-4 * np.sqrt(3) * 1.3 and s["residual_rms_rad"] < 1e-3 * np.sqrt(3) * 1.3
    back = load_robot(out)  # the written robot: B_m per cable, com_m, reloads to the estimate
    assert not back.point_mass and "B_m" in out.read_text()
    est = np.array([p["estimate"] for p in s["parameters"]])
    np.testing.assert_array_equal(np.concatenate([back.A.ravel(), back.arrays.b.ravel()]), est)
    np.testing.assert_array_equal(back.arrays.com, cogiro.arrays.com)
    assert main(["calibrate", "check", "--robot", COGIRO, "--data", str(csv), "--json"]) == 0
    nominal = json.loads(capsys.readouterr().out)
    assert nominal["rms_m"] > 5 * s["residual_rms_m"]
    assert main(["calibrate", "check", "--robot", str(out), "--data", str(csv), "--json"]) == 0
    after = json.loads(capsys.readouterr().out)
    assert nominal["rms_rad"] > 3 * after["rms_rad"] and nominal["max_rad"] >= nominal["rms_rad"]
    assert set(after["samples"][0]) == {"sample", "status", "error_m", "error_rad"}
    assert after["rms_m"] == pytest.approx(s["residual_rms_m"], rel=1e-3)
    assert after["rms_rad"] == pytest.approx(s["residual_rms_rad"], rel=1e-3)


def test_cli_plan_on_cogiro_and_a_fully_constrained_robot(tmp_path, capsys):
    """`cdpr calibrate plan` on CoGiRo writes the expected orientation too; IPAnema-like needs the
    compensated commands (L_TS over-tensions a fully constrained robot); a point mass refuses them."""
    out = tmp_path / "plan.csv"
    args = ["calibrate", "plan", "--robot", COGIRO, "--estimate", "anchors", "--n", "6", "--grid", "3"]
    assert main([*args, "--out", str(out), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["n_candidates"] == 27 * 7 and len(res["poses"][0]) == 6  # 3^3 points at 7 orientations
    assert (
        out.read_text()
        .splitlines()[0]
        .endswith("x_expected_m,y_expected_m,z_expected_m,rx_expected_rad,ry_expected_rad,rz_expected_rad")
    )
    assert res["logdet_d_optimal"] > res["logdet_random_median"]
    ipa = ["calibrate", "plan", "--robot", str(ROBOTS / "ipanema_like.yaml"), "--estimate", "anchors"]
    ipa += ["--n", "6", "--grid", "3", "--json"]
    assert main(ipa) == 2 and "no admissible candidate" in capsys.readouterr().err
    assert main([*ipa, "--command", "compensated"]) == 0
    assert json.loads(capsys.readouterr().out)["n_candidates"] > 6
    pm = ["calibrate", "plan", "--robot", str(ROBOTS / "cdpr4.yaml"), "--estimate", "anchors", "--n", "4"]
    assert main([*pm, "--grid", "3", "--command", "compensated"]) == 2
    assert "allowed for robot CDPR4: standard" in capsys.readouterr().err


def test_a_named_engine_reaches_the_6dof_problem(cogiro):
    """fit, info_rows and the plan build their MAP problem through _problem: a named engine is used
    on a 6-DoF platform too (it was dropped there), None keeps the solvers' default (compiled, on
    every robot), an unknown engine is refused in one line naming the allowed ones."""
    index, sd = np.arange(3), np.ones(3)

    def data(m, spatial):
        return cal.Data(
            sample=np.array(["s1"]),
            L=np.full((1, m), 3.0),
            pose=np.array([[0.0, 0.0, 2.0]]),
            sigma=np.array([1e-3]),
            encoder=False,
            source="<test>",
            rotvec=np.zeros((1, 3)) if spatial else None,
        )

    d6 = data(cogiro.m, True)
    assert cal.Problem(cogiro, d6, index, sd).engine is None  # check_engine: compiled
    assert cal.Problem(cogiro, d6, index, sd, engine="numpy").engine == "numpy"
    assert cal.Problem(cogiro, d6, index, sd, engine="compiled").engine == "compiled"
    point_mass = load_robot(ROBOTS / "cdpr4.yaml")
    assert cal.Problem(point_mass, data(4, False), index, sd).engine is None  # check_engine: compiled
    with pytest.raises(CdprError, match="unknown engine 'nope'; allowed: compiled, numpy"):
        cal.Problem(cogiro, d6, index, sd, engine="nope")
    # the plan, the simulator and the check on a 6-DoF platform check and use a named engine too
    assert (
        cal.equilibrium_engine(cogiro, None) is None
        and cal.equilibrium_engine(cogiro, "numpy") == "numpy"
        and cal.equilibrium_engine(cogiro, "compiled") == "compiled"
    )
    with pytest.raises(CdprError, match="unknown engine 'nope'"):
        cal.candidates(cogiro, [-1, 1, -1, 1, 1.5, 2.5], n_axis=2, engine="nope")
    P, L0 = cal.candidates(cogiro, [-1, 1, -1, 1, 1.5, 2.5], n_axis=2)
    Pc, L0c = cal.candidates(cogiro, [-1, 1, -1, 1, 1.5, 2.5], n_axis=2, engine="compiled")
    assert np.allclose(Pc, P, rtol=0, atol=1e-9) and np.array_equal(L0c, L0)
