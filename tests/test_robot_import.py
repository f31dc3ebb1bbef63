"""CASPR import (issue 17): hand-written XML files in CASPR's format become robot files (the command
line that writes them: tests/cli/test_caspr.py)."""

import numpy as np
import pytest

from cdpr.errors import ConfigError
from cdpr.robot import robot_from_dict
from cdpr.robot_import import robot_dict_from_caspr

BODIES = """<?xml version="1.0" encoding="utf-8"?>
<bodies_system>
  <links display_range="-8 8 -6 6 0 6" view_angle="-37 32">
    <link_rigid num="1" name="Plate">
      <joint type="SPATIAL_EULER_XYZ" q_initial="0 0 2.0 0 0 0"/>
      <physical>
        <mass>40.5</mass>
        <com_location>0.01 -0.02 0.1</com_location>
        <end_location>0.0 0.0 0.0</end_location>
      </physical>
      <parent><num>0</num><location>0.0 0.0 0.0</location></parent>
    </link_rigid>
  </links>
</bodies_system>
"""

CABLE = """    <cable_ideal name="cable {i}" attachment_reference="{ref}">
      <properties><force_min>10.0</force_min><force_max>{fmax}</force_max></properties>
      <attachments>
        {base}
        <attachment><link>1</link><location>{b}</location></attachment>
      </attachments>
    </cable_ideal>
"""
FIXED = "<attachment><link>0</link><location>{a}</location></attachment>"
PULLEY = (
    "<base_rotating_pulley><fixed_location>{a}</fixed_location><pulley_radius>0.05</pulley_radius>"
    "<cable_entry_vector>0 0 1</cable_entry_vector></base_rotating_pulley>"
)
ANCHORS = ["-3 -2 3", "3 -2 3", "3 2 3", "-3 2 3", "-3 -2 0.2", "3 -2 0.2"]
ATTACH = ["-0.2 -0.1 0.1", "0.2 -0.1 0.1", "0.2 0.1 0.1", "-0.2 0.1 0.1", "-0.2 -0.1 -0.1", "0.2 -0.1 -0.1"]


def cables_xml(ref="joint", pulley_cables=(0, 1), extra=""):
    body = "".join(
        CABLE.format(
            i=i + 1,
            ref=ref,
            fmax=3000 + i,
            base=(PULLEY if i in pulley_cables else FIXED).format(a=a),
            b=b,
        )
        for i, (a, b) in enumerate(zip(ANCHORS, ATTACH))
    )
    return (
        '<?xml version="1.0" encoding="utf-8"?>\n<cables default_cable_set="main">\n'
        f'  <cable_set id="main">\n{body}{extra}  </cable_set>\n  <cable_set id="other">\n{body}  </cable_set>\n</cables>\n'
    )


def files(tmp_path, **kw):
    b, c = tmp_path / "X_bodies.xml", tmp_path / "X_cables.xml"
    b.write_text(BODIES)
    c.write_text(cables_xml(**kw))
    return b, c


def test_caspr_files_become_the_same_robot(tmp_path):
    b, c = files(tmp_path)
    r = robot_from_dict(robot_dict_from_caspr(b, c, E=100e9, dead_length=1.5), "x")
    assert r.m == 6 and r.platform.mass == 40.5 and r.arrays.com == pytest.approx([0.01, -0.02, 0.1])
    assert r.A[0] == pytest.approx([-3, -2, 3]) and r.arrays.b[5] == pytest.approx([0.2, -0.1, -0.1])
    assert list(r.kind) == [1, 1, 0, 0, 0, 0] and r.h[0] == r.r_p[0] == 0.05
    assert r.arrays.axis[0] == pytest.approx([0, 0, 1]) and list(r.T_a) == [
        3000,
        3001,
        3002,
        3003,
        3004,
        3005,
    ]
    assert (r.arrays.E == 100e9).all() and (r.d == 1.5).all()


def test_attachment_reference_com_moves_to_the_platform_frame(tmp_path):
    b, c = files(tmp_path, ref="com")
    r = robot_from_dict(robot_dict_from_caspr(b, c), "x")
    assert r.arrays.b[0] == pytest.approx(np.array([-0.2, -0.1, 0.1]) + [0.01, -0.02, 0.1])


@pytest.mark.parametrize(
    "extra,message",
    [
        ('<cable_vsd name="c7"/>\n', "element <cable_vsd> is not read; only <cable_ideal>"),
        (
            CABLE.format(i=7, ref="joint", fmax=1, base="<spring_attachment/>", b="0 0 0"),
            "element <spring_attachment> is not read",
        ),
    ],
)
def test_unsupported_elements_are_refused_in_one_line(tmp_path, extra, message):
    b, c = files(tmp_path, extra=extra)
    with pytest.raises(ConfigError) as exc:
        robot_dict_from_caspr(b, c)
    assert message in str(exc.value) and str(c) in str(exc.value) and "\n" not in str(exc.value)


def test_multi_link_models_and_unknown_sets_are_refused(tmp_path):
    b, c = files(tmp_path)
    with pytest.raises(ConfigError, match="no cable set 'nope'; the file has: main, other"):
        robot_dict_from_caspr(b, c, "nope")
    b.write_text(BODIES.replace("</link_rigid>", "</link_rigid><link_rigid num='2'/>"))
    with pytest.raises(ConfigError, match="only single-link models"):
        robot_dict_from_caspr(b, c)


@pytest.mark.parametrize(
    "which,old,new,message",
    [
        (
            "b",
            "<mass>40.5</mass>",
            "<mass>nan</mass>",
            "key 'link_rigid.physical.mass': expected a finite number",
        ),
        ("b", "<mass>40.5</mass>", "<mass>0</mass>", "key 'link_rigid.physical.mass': must be > 0"),
        ("b", "0.01 -0.02 0.1</com", "0.01 inf 0.1</com", "com_location': expected 3 finite numbers"),
        (
            "b",
            "bodies_system>",
            "robot>",
            "the root element is <robot>; a CASPR file of this kind has <bodies_system>",
        ),
        ("c", "<pulley_radius>0.05<", "<pulley_radius>-0.05<", "pulley_radius': must be >= 0"),
        ("c", "<force_max>3000<", "<force_max>nan<", "properties.force_max': expected a finite number"),
        ("c", '<cable_set id="other">', '<cable_set id="main">', "the id 'main' names 2 cable sets"),
        (
            "c",
            ' default_cable_set="main"',
            "",
            "names no default cable set; give --cable-set ID (the file has: main, other)",
        ),
        ("c", "cables", "wires", "the root element is <wires>; a CASPR file of this kind has <cables>"),
    ],
)
def test_bad_values_are_named_in_the_file_that_holds_them(tmp_path, which, old, new, message):
    """A bad number, a duplicate or missing cable-set id, or the wrong root element: one line naming
    the XML file that holds it (not the robot file made from it) and the element."""
    b, c = files(tmp_path)
    f = b if which == "b" else c
    text = f.read_text()
    assert old in text
    f.write_text(text.replace(old, new))
    with pytest.raises(ConfigError) as exc:
        robot_dict_from_caspr(b, c)
    assert str(exc.value).startswith(f"{f}:") and message in str(exc.value) and "\n" not in str(exc.value)
