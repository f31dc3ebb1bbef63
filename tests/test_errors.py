"""The project's exceptions (cdpr.errors): a ConfigError is one sentence naming the file and the key,
catchable as CdprError and as ValueError; raise_problems raises nothing, the one problem itself, or
one ConfigError listing each key once."""

import pytest

from cdpr.errors import CdprError, ConfigError, raise_problems


def test_a_config_error_names_the_file_and_the_key():
    e = ConfigError("config/robots/r.yaml", "cables[2].pulley.h_m", "must be >= 0, got -1")
    assert str(e) == "config/robots/r.yaml: key 'cables[2].pulley.h_m': must be >= 0, got -1"
    assert (e.source, e.key, e.detail) == (
        "config/robots/r.yaml",
        "cables[2].pulley.h_m",
        "must be >= 0, got -1",
    )
    assert isinstance(e, CdprError) and isinstance(e, ValueError)


def test_a_config_error_without_a_key_names_the_file_only(tmp_path):
    e = ConfigError(tmp_path / "s.yaml", None, "is a folder, not a YAML file")
    assert str(e) == f"{tmp_path / 's.yaml'}: is a folder, not a YAML file" and e.source == str(
        tmp_path / "s.yaml"
    )


def test_no_problem_raises_nothing():
    assert raise_problems("s.yaml", []) is None


def test_one_problem_is_raised_as_it_is():
    p = ConfigError("s.yaml", "n", "must be > 0")
    with pytest.raises(ConfigError) as exc:
        raise_problems("s.yaml", [p])
    assert exc.value is p


def test_several_problems_are_one_line_listing_each_key_once():
    found = [
        ConfigError("s.yaml", "a", "must be > 0"),
        ConfigError("s.yaml", "b.c", "unknown key"),
        ConfigError("s.yaml", "a", "a second complaint about a"),
        ConfigError("s.yaml", None, "is not UTF-8"),
    ]
    with pytest.raises(ConfigError) as exc:
        raise_problems("study.yaml", found)
    msg = str(exc.value)
    assert msg == ("study.yaml: 3 problems: key 'a': must be > 0; key 'b.c': unknown key; is not UTF-8")
    assert exc.value.key is None and "\n" not in msg
