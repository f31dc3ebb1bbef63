"""Physical quantities in configuration values (cdpr.units.quantity): a plain number is SI, a string
carries a unit of the key's dimension and is converted exactly; anything else is one ConfigError
naming the file, the key and the allowed units."""

import math

import pytest

from cdpr.errors import ConfigError
from cdpr.units import DIMENSIONLESS, UNITS, quantity


@pytest.mark.parametrize(
    "value,dimension,si",
    [
        (0.1, "m", 0.1),
        (3, "m", 3.0),
        ("100 mm", "m", 0.1),
        ("2.5cm", "m", 0.025),
        ("102.2 GPa", "Pa", 102.2e9),
        ("102.2e9", "Pa", 102.2e9),  # PyYAML reads 102.2e9 as a string
        ("210 N/mm^2", "Pa", 210e6),
        ("5.14 kN", "N", 5140.0),
        ("300 kg", "kg", 300.0),
        ("1.5 t", "kg", 1500.0),
        ("500 g", "kg", 0.5),
        ("9.81 m/s2", "m/s^2", 9.81),
        ("180 deg", "rad", math.pi),
        ("-90deg", "rad", -math.pi / 2),
        (" .5 m ", "m", 0.5),
    ],
)
def test_values_are_converted_to_si(value, dimension, si):
    assert quantity(value, dimension, "r.yaml", "k") == pytest.approx(si, rel=1e-15)


def test_every_unit_converts_by_its_factor():
    for dimension, units in UNITS.items():
        for unit, factor in units.items():
            assert quantity(f"2 {unit}", dimension, "r.yaml", "k") == pytest.approx(2 * factor, rel=1e-15)


@pytest.mark.parametrize(
    "value,dimension,words",
    [
        ("100 kg", "m", "unit 'kg' is not a unit of m; allowed units: m, cm, mm"),
        ("5 kN", "Pa", "unit 'kN' is not a unit of Pa; allowed units: Pa, kPa, MPa, GPa, N/mm^2"),
        (
            "ten m",
            "m",
            "cannot read 'ten m' as a quantity; write a number in m or a number with one of the units m, cm, mm",
        ),
        ("1,5 m", "m", "cannot read '1,5 m' as a quantity"),
        (True, "m", "expected a number in m (or a string with one of the units m, cm, mm), got True"),
        ([1, 2], "N", "expected a number in N (or a string with one of the units N, kN), got list [1, 2]"),
        (None, "kg", "got NoneType None"),
        (float("inf"), "m", "must be finite, got inf"),
        ("1e400 Pa", "Pa", "must be finite, got '1e400 Pa'"),
    ],
)
def test_bad_values_are_one_line_naming_file_key_and_units(value, dimension, words):
    with pytest.raises(ConfigError) as exc:
        quantity(value, dimension, "config/robots/r.yaml", "cables[1].pulley.h_m")
    msg = str(exc.value)
    assert msg.startswith("config/robots/r.yaml: key 'cables[1].pulley.h_m': ") and words in msg, msg
    assert "\n" not in msg


def test_a_dimensionless_value_takes_no_unit():
    assert quantity(0.5, DIMENSIONLESS, "r.yaml", "axis") == 0.5
    assert quantity("-1e-3", DIMENSIONLESS, "r.yaml", "axis") == -1e-3
    for value, words in [
        ("1 m", "expected a plain number (dimensionless, no unit), got '1 m' with the unit 'm'"),
        ("x", "cannot read 'x' as a number"),
        (False, "expected a plain number (dimensionless, no unit), got bool False"),
        ("nan", "cannot read 'nan' as a number"),
        (float("nan"), "must be finite, got nan"),
    ]:
        with pytest.raises(ConfigError, match=words.replace("(", r"\(").replace(")", r"\)")):
            quantity(value, DIMENSIONLESS, "r.yaml", "axis")
