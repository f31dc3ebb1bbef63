"""The calibration study's pipeline (cdpr.pipeline.calibration): its study file is checked key by key
in one line each, and the helpers of its report (error statistics in mm, markdown tables) give the
numbers they are given. The study itself (a few minutes) runs in the pipeline, not here."""

import numpy as np
import pandas as pd
import pytest

from cdpr.errors import CdprError, ConfigError
from cdpr.pipeline.calibration import error_stats, md_table


def test_calibration_study_file_is_checked(tmp_path):
    import yaml

    from cdpr.pipeline.calibration import load_calibration_study
    from tests.conftest import ROOT

    path = ROOT / "config" / "studies" / "calibration.yaml"
    st = load_calibration_study(path)
    assert st["deviation_groups"] == ["anchors", "dead_lengths", "pulleys", "moduli"]
    assert st["truth_deviations"]["anchors"] == pytest.approx(5e-3)
    good = yaml.safe_load(path.read_text())
    for key, value, words in [
        ("n_train", 0, "expected a positive integer"),
        ("validation_box_m", [0, 1], "expected 6 numbers"),
        ("truth_deviations", {"anchors": "0mm"}, "must be > 0"),
        ("truth_deviations", {"wheels": "1mm"}, "unknown group 'wheels'"),
        ("colour", "red", "unknown key"),
    ]:
        bad = dict(good, **{key: value})
        f = tmp_path / "s.yaml"
        f.write_text(yaml.safe_dump(bad))
        with pytest.raises(CdprError, match=words):
            load_calibration_study(f)
    bad = dict(good)
    del bad["seed"]
    f.write_text(yaml.safe_dump(bad))
    with pytest.raises(ConfigError, match="key 'seed': missing"):
        load_calibration_study(f)


def test_study_winch_key_is_checked(tmp_path):
    import yaml

    from cdpr.errors import ConfigError
    from cdpr.pipeline.calibration import load_calibration_study
    from cdpr.robot import TABLE1
    from tests.conftest import ROOT

    path = ROOT / "config" / "studies" / "calibration.yaml"
    assert load_calibration_study(path)["winch"] == TABLE1
    base = yaml.safe_load(path.read_text())
    for value, words in ((3, "expected a mapping of winch parameters"), ({"k_w": 0.07}, "unknown key")):
        bad = tmp_path / "s.yaml"
        bad.write_text(yaml.safe_dump(dict(base, winch=value)))
        with pytest.raises(ConfigError, match=words) as exc:
            load_calibration_study(bad)
        assert "\n" not in str(exc.value) and "winch" in str(exc.value)
    del base["winch"]
    bad.write_text(yaml.safe_dump(base))
    assert "winch" not in load_calibration_study(bad)


def test_error_stats_are_in_mm_over_the_finite_errors_only():
    err = np.r_[np.arange(1, 101) * 1e-4, np.nan, np.inf]  # 0.1 .. 10 mm, and two failed samples
    st = error_stats(err)
    assert st["median_mm"] == pytest.approx(5.05) and st["max_mm"] == pytest.approx(10.0)
    assert st["p95_mm"] == pytest.approx(np.percentile(np.arange(1, 101) * 0.1, 95))
    assert all(np.isnan(v) for v in error_stats([np.nan, np.inf]).values())
    assert set(error_stats([]).keys()) == {"median_mm", "p95_mm", "max_mm"}


def test_md_table_writes_floats_with_the_format_and_the_rest_as_text():
    df = pd.DataFrame({"model": ["exact", "standard"], "parameters": [12, 4], "rms_mm": [0.123456, 12.5]})
    text = md_table(df, ["model", "rms_mm", "parameters"])
    assert text.splitlines() == [
        "| model | rms_mm | parameters |",
        "|---|---|---|",
        "| exact | 0.123 | 12 |",
        "| standard | 12.5 | 4 |",
    ]
    assert md_table(df, ["rms_mm"], fmt="{:.1f}").splitlines()[2:] == ["| 0.1 |", "| 12.5 |"]


def test_study_wrench_key_is_checked_and_reaches_the_study_robot(tmp_path):
    """``wrench`` (optional, both kinds): the load on the platform during every measurement, on the
    study's nominal robot (so on the true robot drawn from it, and on every model); bad values are one
    line naming the key, a moment on a point mass too."""
    import yaml

    from cdpr.pipeline.calibration import load_calibration_study, study_robot
    from tests.conftest import ROOT

    path = ROOT / "config" / "studies" / "calibration.yaml"
    base = yaml.safe_load(path.read_text())
    assert (
        "wrench" not in load_calibration_study(path)
        and not study_robot(load_calibration_study(path)).platform.has_wrench
    )
    f = tmp_path / "s.yaml"
    f.write_text(yaml.safe_dump(dict(base, wrench=[10, 0, -50, 0, 0, 0])))
    st = load_calibration_study(f)
    assert st["wrench"] == (10.0, 0.0, -50.0, 0.0, 0.0, 0.0)
    assert study_robot(st).platform.wrench == st["wrench"]
    for value, words in (
        ([0, 0, -50], "expected 6 numbers"),
        ([0, 0, ".nan", 0, 0, 0], "must be finite"),
        ([0, 0, -50, 1, 0, 0], "cannot carry a moment"),
    ):
        f.write_text(yaml.safe_dump(dict(base, wrench=value)).replace("'.nan'", ".nan"))
        with pytest.raises(ConfigError, match=words) as exc:
            load_calibration_study(f)
        assert "\n" not in str(exc.value) and "'wrench'" in str(exc.value)
    cog = yaml.safe_load((ROOT / "config" / "studies" / "calibration_cogiro.yaml").read_text())
    cog["robot"] = str(ROOT / cog["robot"])
    f.write_text(yaml.safe_dump(dict(cog, wrench=[0, 0, -196.2, -19.62, 39.24, 0])))
    assert study_robot(load_calibration_study(f)).platform.wrench[3:] == (-19.62, 39.24, 0.0)
