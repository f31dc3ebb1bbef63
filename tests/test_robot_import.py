"""CASPR import (issue 17): hand-written XML files in CASPR's format become robot files (the command
line that writes them: tests/cli/test_caspr.py)."""

import numpy as np
import pytest

from cdpr.errors import ConfigError
from cdpr.robot import robot_from_dict
from cdpr.robot_import import import_caspr, model_name, robot_dict_from_caspr

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


def test_what_the_xml_does_not_hold_is_named_and_force_min_is_kept(tmp_path):
    """Issue 41: every value not from the XML is listed, assumed or given; force_min becomes the
    cable's min_tension_N; the name is the model's (not CASPR's link name) and the description
    names the files without their folders."""
    b, c = files(tmp_path)
    got = import_caspr(b, c, E=80e9)
    text = "; ".join(got.assumed)
    assert "cable.young_modulus_Pa = 8e+10 Pa (given on the command line, --E" in text
    assert "cable.diameter_m = 0.004 m (assumed" in text and "dead_length_m = 0 m (assumed" in text
    assert "max_tension_N" not in text  # every cable has its force_max
    r = robot_from_dict(got.data, "x")
    assert [cab.material.T_min for cab in r.cables] == [10.0] * 6
    assert r.name == "X" and got.data["name"] == model_name(b) != "Plate"
    assert str(tmp_path) not in got.data["description"] and "X_bodies.xml" in got.data["description"]
    assert import_caspr(b, c, name="mine").data["name"] == "mine"
    c.write_text(c.read_text().replace("<force_max>3002</force_max>", ""))
    assert "cable.max_tension_N = 5000 N for cables 3 (assumed: no force_max)" in import_caspr(b, c).assumed


def test_model_name_is_the_file_stem_or_the_folder(tmp_path):
    assert model_name(tmp_path / "CoGiRo_bodies.xml") == "CoGiRo"
    (tmp_path / "IPAnema").mkdir()
    assert model_name(tmp_path / "IPAnema" / "bodies.xml") == "IPAnema"


def test_force_min_above_force_max_is_refused_in_one_line(tmp_path):
    b, c = files(tmp_path)
    c.write_text(
        c.read_text().replace(
            "<force_min>10.0</force_min><force_max>3001<", "<force_min>4000</force_min><force_max>3001<"
        )
    )
    with pytest.raises(ConfigError) as exc:
        robot_dict_from_caspr(b, c)
    msg = str(exc.value)
    assert msg.startswith(f"{c}:") and "force_min 4000 N exceeds force_max 3001 N" in msg and "\n" not in msg


def test_translational_model_is_a_point_mass(tmp_path):
    """CASPR's T_XYZ joint (the platform does not turn) with every cable at the reference point is a
    point-mass robot; with a cable attached elsewhere it is refused in one line."""
    b, c = files(tmp_path)
    b.write_text(
        BODIES.replace("SPATIAL_EULER_XYZ", "T_XYZ").replace(
            'q_initial="0 0 2.0 0 0 0"', 'q_initial="0 0 2.0"'
        )
    )
    text = c.read_text()
    with pytest.raises(ConfigError, match="a translational \\(T_XYZ\\) model is read as a point mass"):
        robot_dict_from_caspr(b, c)
    for a in ATTACH:
        text = text.replace(f"<location>{a}</location>", "<location>0 0 0</location>")
    c.write_text(text.replace("3 -2 0.2", "3 -2 2.9").replace("-3 -2 0.2", "-3 -2.5 2.9"))
    got = import_caspr(b, c)
    r = robot_from_dict(got.data, "x")
    assert r.point_mass and r.platform.com == (0.0, 0.0, 0.0)
    assert any("com_location [0.01, -0.02, 0.1] left out" in n for n in got.notes)


def test_an_anchor_that_breaks_a_symmetry_by_a_typo_is_reported_not_changed(tmp_path):
    b, c = files(tmp_path)
    assert import_caspr(b, c).notes == []  # the anchors are mirror images about x = 0
    c.write_text(c.read_text().replace("<location>3 2 3</location>", "<location>3.02 2 3</location>"))
    got = import_caspr(b, c)
    assert (
        len(got.notes) == 1
        and "anchors 3 and 4" in got.notes[0]
        and "about x = 0 m but for 20 mm" in got.notes[0]
    )
    assert got.data["cables"][2]["A_m"] == [3.02, 2.0, 3.0]
