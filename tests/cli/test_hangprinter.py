"""The Hangprinter on the command line: ``cdpr import rrf``, ``cdpr export rrf | klipper`` (round
trip, bad lines named with the file and the word, assumed values said), and ``cdpr point`` /
``cdpr inverse`` on the shipped robot with motor angles through the spool model."""

import json

import numpy as np
import pytest
import yaml

from cdpr.cli.main import main
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

HP4 = ROBOTS / "hangprinter_hp4.yaml"
HP4_G = ROBOTS / "hangprinter_hp4.g"

CONFIG = """; a Hangprinter's config.g (test)
M550 P"hp"                ; other G-code is ignored
M584 X40.0 Y41.0 Z42.0 E0
M669 K6 A16.83:-1584.86:-113.17 B1290.18:1229.19:-157.45 C-1409.88:742.61:-151.80 D21.85:-0.16:2343.67 P2000
m666 Q0.06875 R76.017:76.017:76.017:75.657 U2:2:2:4 O1 L20 H255 W2.5 S30000 X80:80:80:120 Y3000:3100:2900:0
G28
"""


def run(argv, capsys):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def _point_at_motor_deg(at, deg, capsys):
    """``point --json`` on HP4 at ``at`` in physical mode with the motor angles ``deg`` [deg]: its
    parsed answer (the command must succeed)."""
    code, out, err = run(
        [
            "point",
            "--robot",
            HP4,
            "--at",
            *at,
            "--redundancy",
            "physical",
            "--motor-deg",
            *map(str, deg),
            "--json",
        ],
        capsys,
    )
    assert code == 0, err
    return json.loads(out)


def test_import_reads_every_word_and_assumes_only_the_diameter(tmp_path, capsys):
    cfg = tmp_path / "config.g"
    cfg.write_text(CONFIG)
    out = tmp_path / "hp.yaml"
    code, stdout, err = run(["import", "rrf", "--config", cfg, "--out", out], capsys)
    assert code == 0, err
    r = load_robot(out)
    assert r.name == "config" and r.platform.mass == 2.5 and not r.suspended_point_mass
    assert r.A[0] == pytest.approx([0.01683, -1.58486, -0.11317]) and r.A[3] == pytest.approx(
        [0.02185, -0.00016, 2.34367]
    )
    assert [p.r0 for p in r.spools] == pytest.approx([0.076017] * 3 + [0.075657])
    assert [p.U for p in r.spools] == [2, 2, 2, 4] and [p.Q for p in r.spools] == pytest.approx(
        [6.875e-5] * 4
    )
    assert {(p.lines_per_spool, p.motor_teeth, p.spool_teeth) for p in r.spools} == {(1, 20, 255)}
    assert r.ES == pytest.approx([60000, 60000, 60000, 120000])  # U strands of a 30 kN line
    assert list(r.T_a) == [80, 80, 80, 120]
    assert r.d == pytest.approx([1.5, 1.55, 1.45, 0.0])  # guy wires Y / U
    text = out.read_text()
    # the header and one stderr line name what was assumed: here only the line's diameter
    assert "Assumed (not in the configuration): line diameter 0.5 mm" in text
    assert (
        err.count("\n") == 1
        and "assumed" in err
        and "line diameter" in err
        and "RepRapFirmware's default" not in err
    )


def test_import_says_each_firmware_default_it_assumed(tmp_path, capsys):
    cfg = tmp_path / "bare.g"
    cfg.write_text("M669 K6 A0:-1600:-120 B1400:800:-120 C-1400:800:-120 D0:0:2300\n")
    code, _, err = run(
        ["import", "rrf", "--config", cfg, "--out", tmp_path / "b.yaml", "--name", "bare"], capsys
    )
    assert code == 0, err
    for word in (
        "M666 Q0.007",
        "M666 R75:75:75:75",
        "M666 U2:2:2:2",
        "M666 S20000",
        "mover mass 1 kg",
        "guy-wire",
    ):
        assert word in err, word
    r = load_robot(tmp_path / "b.yaml")
    assert r.name == "bare" and r.ES == pytest.approx([40000] * 4)


def test_import_export_round_trip(tmp_path, capsys):
    """config -> robot -> M669/M666 -> robot: the same robot (anchors to 1 µm, spools, masses)."""
    cfg = tmp_path / "config.g"
    cfg.write_text(CONFIG)
    run(["import", "rrf", "--config", cfg, "--out", tmp_path / "a.yaml"], capsys)
    code, _, err = run(
        ["export", "rrf", "--robot", tmp_path / "a.yaml", "--out", tmp_path / "again.g"], capsys
    )
    assert code == 0 and err == "", err
    lines = (tmp_path / "again.g").read_text().splitlines()
    assert lines[1].startswith("M669 K6 A16.830:-1584.860:-113.170 B") and lines[2].startswith(
        "M666 Q0.068750 R76.017"
    )
    run(["import", "rrf", "--config", tmp_path / "again.g", "--out", tmp_path / "b.yaml"], capsys)
    a, b = load_robot(tmp_path / "a.yaml"), load_robot(tmp_path / "b.yaml")
    assert b.A == pytest.approx(a.A, abs=1e-9) and b.d == pytest.approx(a.d, abs=1e-9)
    assert b.spools == a.spools and b.ES == pytest.approx(a.ES) and list(b.T_a) == list(a.T_a)
    assert b.platform.mass == a.platform.mass
    # deterministic: the same file gives the same bytes
    run(["import", "rrf", "--config", tmp_path / "again.g", "--out", tmp_path / "c.yaml"], capsys)
    assert (tmp_path / "c.yaml").read_bytes() == (tmp_path / "b.yaml").read_bytes()


def test_shipped_robot_is_the_import_of_its_config(tmp_path, capsys):
    code, _, err = run(
        ["import", "rrf", "--config", HP4_G, "--out", tmp_path / "hp.yaml", "--name", "HP4"], capsys
    )
    assert code == 0, err
    assert (tmp_path / "hp.yaml").read_text() == HP4.read_text()


def test_export_rrf_of_a_per_cable_buildup_is_its_mean_with_a_warning(tmp_path, capsys):
    d = yaml.safe_load(HP4.read_text())
    for c, q in zip(d["cables"], (5e-5, 6e-5, 7e-5, 8e-5)):
        c["winch"]["buildup_factor_m"] = q
    (tmp_path / "r.yaml").write_text(yaml.safe_dump(d))
    code, out, err = run(["export", "rrf", "--robot", tmp_path / "r.yaml"], capsys)
    assert code == 0
    assert " Q0.065000 " in out
    assert err.count("\n") == 1 and "one buildup factor per machine" in err and "mean" in err


def test_export_klipper_writes_the_winch_section_and_says_no_buildup(tmp_path, capsys):
    code, out, err = run(["export", "klipper", "--robot", HP4, "--out", tmp_path / "printer.cfg"], capsys)
    assert code == 0, err
    text = (tmp_path / "printer.cfg").read_text()
    assert "[printer]\nkinematics: winch\n" in text
    for s, (x, y, z) in zip(
        "abcd", [(0, -1620, -150), (1272.79, 1272.79, -150), (-1402.96, 810, -150), (0, 0, 2350)]
    ):
        block = text.split(f"[stepper_{s}]\n")[1].split("\n\n")[0]
        assert f"anchor_x: {x:.3f}\nanchor_y: {y:.3f}\nanchor_z: {z:.3f}" in block
    # rotation_distance: anchor-mover distance per motor turn at the origin, 2 pi r0 L / (H U) [mm]
    assert "rotation_distance: 18.479957" in text.split("[stepper_a]")[1]
    assert "no spool buildup model" in err and "no spool buildup model" in text


@pytest.mark.parametrize(
    "config, words",
    [
        ("M669 K6 A0:-1600 B1:1:1 C2:2:2 D0:0:2000\n", ["line 1", "'M669 A0:-1600'", "3 values"]),
        ("M669 K6 A0:-1600:x B1:1:1 C2:2:2 D0:0:2000\n", ["line 1", "'M669 A0:-1600:x'", "numbers"]),
        ("M669 K6 A0:-1600:-100 B1:1:1 C2:2:2\n", ["no anchor D"]),
        ("M669 K5 A0:-1600:-100 B1:1:1:1\n", ["line 1", "'M669 K5'", "not the Hangprinter"]),
        ("G28\nM666 R75\n", ["no 'M669 K6' line"]),
        (
            "M669 K6 A0:-1:-1 B1:1:-1 C-1:1:-1 D0:0:2\n; ok\nM666 U2:2:2.5:4\n",
            ["line 3", "'M666 U2:2:2.5:4'", "positive integers"],
        ),
        (
            "M669 K6 A0:-1:-1 B1:1:-1 C-1:1:-1 D0:0:2\nM666 R75:75:75\n",
            ["line 2", "'M666 R75:75:75'", "4 values"],
        ),
        ("M669 K6 A0:-1:-1 B1:1:-1 C-1:1:-1 D0:0:2\nM666 S-5\n", ["line 2", "'M666 S-5'", "> 0"]),
        (
            "M669 K6 A0:-1:-1 B1:1:-1 C-1:1:-1 D0:0:2\nM666 R0:75:75:75\n",
            ["line 2", "'M666 R0:75:75:75'", "> 0"],
        ),
    ],
)
def test_bad_lines_are_one_line_errors_naming_the_file_and_the_word(tmp_path, capsys, config, words):
    cfg = tmp_path / "bad.g"
    cfg.write_text(config)
    code, out, err = run(["import", "rrf", "--config", cfg, "--out", tmp_path / "x.yaml"], capsys)
    assert code == 2 and err.startswith("cdpr: error: ") and err.count("\n") == 1, err
    assert str(cfg) in err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "x.yaml").exists()


def test_export_refuses_a_robot_without_spools(capsys):
    code, _, err = run(["export", "rrf", "--robot", ROBOTS / "cdpr4.yaml"], capsys)
    assert code == 2 and err.count("\n") == 1 and "needs a Hangprinter robot" in err and "spool" in err


def test_inverse_and_point_on_the_hangprinter(capsys):
    """inverse gives the motor angles of L_TS through the spools; point with those angles solves the
    physical equilibrium close to the desired point (stiff lines), not 'inaccessible'."""
    at = ["0.1", "-0.2", "0.5"]
    code, out, err = run(["inverse", "--robot", HP4, "--at", *at, "--json"], capsys)
    assert code == 0, err
    cables = json.loads(out)
    deg = [c["motor_deg"] for c in cables]
    r = load_robot(HP4)
    # by hand: the line released is U (|A_i - P| - |A_i|), the spool angle from the buildup law
    P = np.array([0.1, -0.2, 0.5])
    for i, p in enumerate(r.spools):
        s = p.U * (np.linalg.norm(r.A[i] - P) - np.linalg.norm(r.A[i]))
        phi = 2 * (p.r0 - np.sqrt(p.r0**2 - p.Q * s)) / p.Q
        assert deg[i] == pytest.approx(np.degrees(phi) * 255 / 20, rel=1e-9)
    res = _point_at_motor_deg(at, deg, capsys)
    assert res["status"] == "ok" and res["dp_norm"] < 5e-3
    code, out, _ = run(["point", "--robot", HP4, "--at", *at, "--redundancy", "physical", "--json"], capsys)
    assert json.loads(out)["solved"] == pytest.approx(res["solved"], abs=1e-9)  # L_TS either way
    code, out, err = run(["inverse", "--robot", HP4, "--at", *at], capsys)
    assert code == 0 and "motor [deg] for L_TS (spool)" in out


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--motor-deg", "1", "2", "3"], "one motor angle per cable (4)"),
        (
            ["--motor-deg", "1", "2", "3", "4", "--lengths", "1", "2", "3", "4"],
            "not --lengths and --motor-deg",
        ),
        (["--motor-deg", "1e9", "0", "0", "0"], "cannot pay out that much line"),
    ],
)
def test_point_motor_deg_bad_input(capsys, extra, words):
    code, _, err = run(
        ["point", "--robot", HP4, "--at", "0", "0", "0.5", "--redundancy", "physical", *extra], capsys
    )
    assert code == 2 and err.count("\n") == 1 and words in err, err


def test_motor_deg_needs_spools(capsys):
    code, _, err = run(
        [
            "point",
            "--robot",
            ROBOTS / "cdpr4.yaml",
            "--at",
            "0",
            "0",
            "2",
            "--redundancy",
            "physical",
            "--motor-deg",
            "0",
            "0",
            "0",
            "0",
        ],
        capsys,
    )
    assert code == 2 and "need spool winches" in err


def test_compensate_motor_angles_put_the_mover_at_the_point(capsys):
    """compensate plans tensions (>= 1 N, below the 70 N of the HP4 file) and gives the motor angles
    of their rest lengths through the spools; commanding those angles, the physical equilibrium is
    the desired point with the planned tensions (the chain closes through the spool map both ways)."""
    at = ["0.1", "-0.2", "0.5"]
    code, out, err = run(["compensate", "--robot", HP4, "--at", *at, "--t-min", "1", "--json"], capsys)
    assert code == 0, err
    plan = json.loads(out)
    assert plan["status"] == "ok" and len(plan["motor_deg"]) == 4
    got = _point_at_motor_deg(at, plan["motor_deg"], capsys)
    assert got["status"] == "ok" and got["dp_norm"] < 1e-9
    assert got["tensions"] == pytest.approx(plan["tensions"], abs=1e-6)
