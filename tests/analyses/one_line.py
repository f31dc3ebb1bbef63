"""A bad calibration table is refused in one line naming the file, the column and what is allowed."""

from __future__ import annotations

import pytest

from cdpr.errors import ConfigError


def assert_refused_in_one_line(read, path, robot, column, words):
    """``read(path, robot)`` raises one ConfigError line naming ``path``, the key ``column`` (when
    not None) and ``words``."""
    with pytest.raises(ConfigError) as info:
        read(path, robot)
    msg = str(info.value)
    assert "\n" not in msg and str(path) in msg and words in msg
    if column:
        assert f"key '{column}'" in msg
