"""Measured tensions and winches on a rigid 6-DoF platform (cdpr.analyses.calibration on CoGiRo):
the tension rows' exact Jacobian against central differences of the full residual (re-solving
every equilibrium) with and without drums, encoder-only data with tensions recovering the offsets,
moduli and mass, the gauge without tensions, bad tension columns, the drums in simulate, check and fit,
and the command line round trip."""

import json

import numpy as np
import pandas as pd
import pytest

import cdpr.models.cables as cables
from cdpr.analyses import calibration as cal
from cdpr.cli.main import main
from cdpr.errors import CdprError, ConfigError
from cdpr.models.drive import has_winches
from cdpr.parameters import calibration_names
from cdpr.pipeline.calibration_files import write_data
from cdpr.robot import load_robot
from tests.analyses.test_calibration import evaluated_problem
from tests.analyses.test_calibration_platform import COGIRO, _poses, _truth
from tests.conftest import ROBOTS

#: Drums on every cable of CoGiRo: Table 1 of the winch seed with 4 m more cable on the drum, so
#: that the drums pay out CoGiRo's 9-14 m (Table 1's l_u0 = 5.93 m reaches about 12 m).
WINCH = "winch: {l_u0_m: 9.9261}\n"


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(COGIRO)


@pytest.fixture(scope="module")
def cogiro_winch(tmp_path_factory):
    path = tmp_path_factory.mktemp("cogw") / "cogiro_winch.yaml"
    path.write_text((ROBOTS / "cogiro_massless.yaml").read_text(encoding="utf-8") + WINCH, encoding="utf-8")
    robot = load_robot(path)
    assert has_winches(robot)
    return robot


def _encoder_only(data):
    """The same samples with the tracker removed: encoder readings and tensions only."""
    data.pose[:] = np.nan
    data.rotvec[:] = np.nan
    return data


@pytest.mark.parametrize("winch", [False, True], ids=["no winch", "winch"])
def test_tension_rows_jacobian_equals_central_differences(cogiro, cogiro_winch, monkeypatch, winch):
    """Problem.jacobian (tension rows: dt/dθ = ∂t/∂x dx*/dθ + ∂t/∂θ + ∂t/∂L0 dL0/dθ, with the
    drums' chain rule on the offsets and dead lengths) against central differences of
    Problem.residual, which re-solves every equilibrium; two of the four samples have no pose
    (solved from the start pose). Every cable taut by > 50 N: no taut-set change within the steps.

    The tension derivative is a small difference of two large terms (the pose term and the
    fixed-pose term cancel to ~1/500: the balance holds the tensions), so the equilibria are
    re-solved to round-off (FTOL_REL 1e-15) and the steps are 2e-3 prior sd (FD error ~1e-6).
    Length priors of 5 mm: a cable's stiffness E S / L0 ~ 1.3e5 N/m turns 0.1 prior sd of 5 mm
    into ~65 N."""
    monkeypatch.setattr(cables, "FTOL_REL", 1e-15)
    robot = cogiro_winch if winch else cogiro
    groups = ["moduli", "pulleys", "dead_lengths", "anchors", "attachments", "offsets", "mass"]
    rng = np.random.default_rng(4)
    data = cal.simulate(robot, robot, _poses(rng, 4), offsets=np.zeros(8), tensions=True, sigma_t=5.0)
    assert len(data.sample) == 4
    data.pose[:2] = np.nan
    data.rotvec[:2] = np.nan
    prob, idx, z, ev, J = evaluated_problem(
        robot, data, groups, "dead_lengths=5mm,offsets=5mm", 1e-15, 0.1, rng
    )
    assert ev["t"].min() > 50.0
    n_pose, n_t = 6 * 2, 8 * 4
    assert J.shape == (n_pose + n_t + len(idx), len(idx))
    names = [calibration_names(robot)[k] for k in idx]
    cols = ["E_2", "h_3", "r_p_4", "d_3", "A_1_x", "A_6_z", "b_2_y", "b_5_z", "offset_4", "offset_7", "M"]
    assert_columns_match_central_differences(prob, z, J, names, cols, n_pose, n_t)


def assert_columns_match_central_differences(prob, z, J, names, cols, n_pose, n_t, step=2e-3):
    """Each column ``cols`` of the Jacobian J at z against central differences of prob.residual
    (steps ``step`` prior sd), the pose rows and the tension rows apart (relative 1e-5 of each
    part's largest change, which must be > 1e-3), and the prior rows exactly the identity."""
    k = len(names)
    for name in cols:
        j = names.index(name)
        e = np.zeros(k)
        e[j] = step
        fd = (prob.residual(z + e) - prob.residual(z - e)) / (2 * step)
        for part, rows in (("pose", slice(0, n_pose)), ("tension", slice(n_pose, n_pose + n_t))):
            scale = np.abs(fd[rows]).max()
            assert scale > 1e-3, (name, part)  # the column moves these rows
            err = np.abs(J[rows, j] - fd[rows]).max() / scale
            assert err < 1e-5, (name, part, err)
        np.testing.assert_array_equal(J[n_pose + n_t :, j], np.eye(k)[j])


def test_encoder_only_with_tensions_recovers_offsets_moduli_and_mass(cogiro):
    """Encoder readings and measured tensions, no pose, noise-free (σ_t = 1 µN): the tensions
    fix the pose through the balance, Hooke's law then the rest lengths, so the offsets, the moduli
    and the mass (which poses alone see only as E_i / M) are identified (rank 17) and recovered to
    1e-6 relative."""
    groups = ["moduli", "mass", "offsets"]
    rng, idx, sd, truth, th = _truth(cogiro, ["moduli", "mass"], 21)
    off = np.linspace(-0.035, 0.035, 8)  # none 0: 1e-6 relative on each
    data = cal.simulate(truth, cogiro, _poses(rng, 12), offsets=off, tensions=True, sigma_t=1e-6)
    c = cal.fit(cogiro, _encoder_only(data), groups, solver={"tol": 1e-13})
    assert c.names == [*[f"E_{i}" for i in range(1, 9)], "M", *[f"offset_{i}" for i in range(1, 9)]]
    assert c.ident["rank"] == 17 and set(c.ident["labels"]) == {"identified"}
    np.testing.assert_allclose(c.estimate[9:], off, rtol=1e-6)
    np.testing.assert_allclose(c.estimate[:9], th[idx], rtol=1e-6)
    assert (np.abs(c.estimate[:9] - c.nominal[:9]) / c.nominal[:9]).max() > 0.05  # far from the nominal
    s = c.summary()
    assert s["samples_used"] == 12 and s["residual_rms_m"] is None and s["residual_rms_rad"] is None


def test_encoder_only_with_tensions_through_the_drums(cogiro_winch):
    """The same on CoGiRo with drums: the readings are commands realised through the drums, the
    offsets and the mass come back to 1e-6 relative."""
    robot = cogiro_winch
    groups = ["offsets", "mass"]
    rng, idx, sd, truth, th = _truth(robot, ["mass"], 22)
    off = np.linspace(0.02, -0.03, 8)
    data = cal.simulate(truth, robot, _poses(rng, 8), offsets=off, tensions=True, sigma_t=1e-6)
    c = cal.fit(robot, _encoder_only(data), groups, solver={"tol": 1e-13})
    assert c.ident["rank"] == 9 and c.names == ["M", *[f"offset_{i}" for i in range(1, 9)]]
    np.testing.assert_allclose(c.estimate[1:], off, rtol=1e-6)
    assert c.estimate[0] == pytest.approx(truth.platform.mass, rel=1e-6)
    blind = cal.fit(cal.without_winches(robot), _encoder_only(data), groups, solver={"tol": 1e-13})
    assert np.abs(blind.estimate[1:] - off).max() > 1e-4  # without the drums the offsets absorb δl


def test_without_tensions_pose_less_samples_give_no_equation(cogiro):
    """Encoder readings without tensions: a sample without a pose is no equation (every set of
    lengths has an equilibrium for every θ); alone they are refused in one line, beside measured
    poses they are counted and left out, and the fit reports the d_i / offset_i gauge."""
    rng, idx, sd, truth, th = _truth(cogiro, ["dead_lengths"], 7)
    off = np.linspace(-0.02, 0.03, 8)
    data = cal.simulate(truth, cogiro, _poses(rng, 24), sigma=2e-4, rng=rng, offsets=off)
    groups = ["dead_lengths", "offsets"]
    none = _encoder_only(data.subset(np.arange(24)))
    with pytest.raises(CdprError, match="no sample has a measured pose or tensions") as info:
        cal.fit(cogiro, none, groups)
    assert "\n" not in str(info.value)
    with pytest.raises(
        CdprError, match="rigid self-calibration .* is for point-mass robots; robot cogiro_massless"
    ):
        cal.fit(cogiro, none, ["dead_lengths"], model="standard")
    data.pose[::6] = np.nan
    data.rotvec[::6] = np.nan
    c = cal.fit(cogiro, data, groups)
    status = c.table["status"].to_numpy()
    assert (status[::6] == "no pose or tension").all()
    assert (np.delete(status, np.s_[::6]) != "no pose or tension").all() and (status == "used").sum() >= 18
    words = c.ident["unidentified"]
    assert len(words) >= 1 and all(" against offset_" in w or " against d_" in w for w in words)


@pytest.mark.parametrize(
    "edit, column, words",
    [
        (lambda df: df.drop(columns=["t8_N"]), "t8_N", "tensions need all of t1_N..t8_N"),
        (lambda df: df.assign(t3_N=-df["t3_N"]), "t1_N,", "row 1: tensions must be all finite and >= 0"),
        (lambda df: df.assign(t5_N=[np.nan, 1.0, 1.0]), "t1_N,", "row 1: tensions must be all finite"),
        (lambda df: df.assign(sigma_N=[5.0, 0.0, 5.0]), "sigma_N", "row 2: sigma_N must be finite and > 0"),
        (
            lambda df: df.drop(columns=[f"t{i}_N" for i in range(1, 9)]),
            "sigma_N",
            "needs the tension columns t1_N..t8_N",
        ),
        (lambda df: df.assign(t9_N=1.0), "t9_N", "unknown column; allowed: sample, L1"),
    ],
)
def test_bad_tension_data_is_one_line(cogiro, tmp_path, edit, column, words):
    """The point-mass reader's tension checks, on a 6-DoF table (one line naming file and column)."""
    rng = np.random.default_rng(5)
    data = cal.simulate(cogiro, cogiro, _poses(rng, 3), tensions=True)
    path = tmp_path / "d.csv"
    write_data(path, data, cogiro)
    back = cal.read_data(path, cogiro)
    np.testing.assert_array_equal(back.tension, data.tension)
    np.testing.assert_array_equal(back.sigma_t, data.sigma_t)
    edit(pd.read_csv(path)).to_csv(path, index=False)
    with pytest.raises(ConfigError) as info:
        cal.read_data(path, cogiro)
    msg = str(info.value)
    assert "\n" not in msg and str(path) in msg and words in msg and f"key '{column}" in msg


def test_pose_less_rows_need_encoder_or_tension_data(cogiro, tmp_path):
    """Commanded lengths with an empty pose: refused without tensions, an equation with them."""
    rng = np.random.default_rng(6)
    data = cal.simulate(cogiro, cogiro, _poses(rng, 3), tensions=True)
    data.pose[1] = np.nan
    data.rotvec[1] = np.nan
    path = tmp_path / "d.csv"
    write_data(path, data, cogiro)
    back = cal.read_data(path, cogiro)
    assert list(back.has_pose) == [True, False, True] and back.has_tension.all()
    df = pd.read_csv(path)
    df.drop(columns=[c for c in df.columns if c.endswith("_N")]).to_csv(path, index=False)
    with pytest.raises(ConfigError, match=r"row 2: no pose; only encoder data .* or tension data"):
        cal.read_data(path, cogiro)


def test_drums_in_simulate_check_and_fit(cogiro, cogiro_winch):
    """CoGiRo with drums, dead lengths perturbed, poses measured (σ = 10 µm, 10 µrad): simulate
    realises the commands through the drums, check of the true robot with drums is at the noise
    while the same robot without them is not, and the exact fit on the drum robot reaches the
    noise floor where the fit that ignores the drums cannot."""
    robot = cogiro_winch
    rng, idx, sd, truth, th = _truth(robot, ["dead_lengths"], 23)
    data = cal.simulate(truth, robot, _poses(rng, 16), sigma=1e-5, sigma_rad=1e-5, rng=rng)
    assert len(data.sample) == 16
    drums = cal.check(truth, data)
    blind = cal.check(cal.without_winches(truth), data)
    assert drums["rms_m"] < 3e-5 and blind["rms_m"] > 5 * drums["rms_m"]
    c = cal.fit(robot, data, ["dead_lengths"])
    s = c.summary()
    assert s["residual_rms_m"] < 3e-5 and s["residual_rms_rad"] < 3e-5
    assert (np.abs(c.estimate - th[idx]) < 4 * c.sd).all()
    b = cal.fit(cal.without_winches(robot), data, ["dead_lengths"]).summary()
    assert b["residual_rms_m"] > 5 * s["residual_rms_m"]


def test_cli_round_trip_encoder_and_tensions(cogiro, tmp_path, capsys):
    """simulate (encoder readings and tensions, σ_t = 0.5 N) -> CSV with empty pose cells ->
    `cdpr calibrate fit --estimate offsets --json` on CoGiRo: every sample used, the offsets back
    within 4 sd, their sd below 1 mm (the prior's is 50 mm); the table printout too."""
    rng = np.random.default_rng(24)
    off = np.linspace(-0.03, 0.03, 8)
    data = cal.simulate(cogiro, cogiro, _poses(rng, 10), offsets=off, tensions=True, sigma_t=0.5, rng=rng)
    csv = tmp_path / "m.csv"
    write_data(csv, _encoder_only(data), cogiro)
    row = pd.read_csv(csv).iloc[0]
    assert np.isnan(row["x_m"]) and np.isnan(row["rz_rad"]) and row["t1_N"] > 0
    args = ["calibrate", "fit", "--robot", COGIRO, "--data", str(csv), "--estimate", "offsets"]
    assert main([*args, "--out", str(tmp_path / "c.yaml"), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["samples_used"] == 10 and s["rank"] == 8 and s["residual_rms_m"] is None
    est = np.array([p["estimate"] for p in s["parameters"]])
    sdv = np.array([p["sd"] for p in s["parameters"]])
    assert (np.abs(est - off) < 4 * sdv).all() and sdv.max() < 1e-3
    assert "# encoder offsets [m]" in (tmp_path / "c.yaml").read_text()
    assert main([*args, "--out", str(tmp_path / "d.yaml")]) == 0
    out = capsys.readouterr().out
    assert "offset_8" in out and "samples used 10" in out
