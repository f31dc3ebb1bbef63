"""Robot and study files that are not what they claim (issue: trust, second round): a key given
twice, text that is not UTF-8, binary files, devices and folders. Each row is a command and what must
come out: exit code 2 and a one-line message naming the file (and the key), before any work. And the
package's own files are read as UTF-8 whatever the locale."""

import os
import subprocess
import sys

import pytest
import yaml

from cdpr.cli.main import main
from cdpr.errors import ConfigError
from cdpr.pipeline.study import load_study
from tests.conftest import ROBOTS, ROOT

R4 = ROBOTS / "cdpr4.yaml"
QUICK = ROOT / "config" / "studies" / "quick.yaml"


def run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def robot_variants(tmp_path):
    text = R4.read_text(encoding="utf-8")
    mass_line = next(i for i, line in enumerate(text.splitlines()) if "mass_kg" in line)
    lines = text.splitlines()
    dup_top = "\n".join(
        lines[: mass_line + 1] + [lines[mass_line].replace("mass_kg", "mass_kg")] + lines[mass_line + 1 :]
    )
    robot = yaml.safe_load(text)
    files = {
        "dup_mass": dup_top.encode(),
        "latin1": text.replace("Paty", "Paty \u00e9").encode("latin-1", errors="replace")
        if "Paty" in text
        else ("# caf\u00e9\n" + text).encode("latin-1"),
        "utf16": text.encode("utf-16"),
        "binary": b"\x00\x01\x02\x03" * 100,
        "utf8_bom_ok": b"\xef\xbb\xbf" + yaml.safe_dump(robot).encode(),
    }
    out = {}
    for name, data in files.items():
        p = tmp_path / f"{name}.yaml"
        p.write_bytes(data)
        out[name] = str(p)
    return out, mass_line + 1


@pytest.mark.parametrize(
    "name, fragment",
    [
        ("dup_mass", "key 'mass_kg': given twice (lines {line} and {line2})"),
        ("latin1", "is not UTF-8 text"),
        ("utf16", "is UTF-16 text; save it as UTF-8"),
        ("binary", "is a binary file"),
    ],
)
@pytest.mark.parametrize("command", ["point", "inverse", "grid"])
def test_bad_robot_files(tmp_path, capsys, name, fragment, command):
    files, line = robot_variants(tmp_path)
    argv = [command, "--robot", files[name]]
    argv += (
        ["--frame", "--n", "3", "--out", str(tmp_path / "g.parquet")]
        if command == "grid"
        else ["--at", "0", "0", "2.5"]
    )
    code, out, err = run(argv, capsys)
    assert code == 2, err
    assert err.startswith("cdpr: error: ") and err.count("\n") == 1, err
    assert files[name] in err
    assert fragment.format(line=line, line2=line + 1) in err
    assert not (tmp_path / "g.parquet").exists()


def test_utf8_with_bom_is_accepted(tmp_path, capsys):
    files, _ = robot_variants(tmp_path)
    code, out, err = run(
        ["point", "--robot", files["utf8_bom_ok"], "--at", "0", "0", "2.5", "--json"], capsys
    )
    assert code == 0, err


@pytest.mark.parametrize("target", ["/dev/zero", "folder"])
def test_devices_and_folders_are_refused_before_reading(tmp_path, capsys, target):
    path = str(tmp_path) if target == "folder" else target
    code, out, err = run(["point", "--robot", path, "--at", "0", "0", "2.5"], capsys)
    assert code == 2
    assert path in err and ("not a regular file" in err or "is a folder" in err), err


def test_oversized_robot_file(tmp_path, capsys):
    p = tmp_path / "big.yaml"
    p.write_bytes(b"# " + b"x" * (5 * 2**20) + b"\n")
    code, out, err = run(["point", "--robot", str(p), "--at", "0", "0", "2.5"], capsys)
    assert code == 2 and "MiB" in err and str(p) in err, err


def test_study_key_given_twice(tmp_path):
    text = QUICK.read_text(encoding="utf-8")
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("dead_length_m"))
    p = tmp_path / "quick.yaml"
    p.write_text("\n".join(lines[: i + 1] + [lines[i]] + lines[i + 1 :]) + "\n", encoding="utf-8")
    with pytest.raises(ConfigError, match=rf"key 'dead_length_m': given twice \(lines {i + 1} and {i + 2}\)"):
        load_study(p)


def test_nested_key_given_twice(tmp_path):
    text = QUICK.read_text(encoding="utf-8")
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("  ") and ":" in line)
    p = tmp_path / "quick.yaml"
    p.write_text("\n".join(lines[: i + 1] + [lines[i]] + lines[i + 1 :]) + "\n", encoding="utf-8")
    key = lines[i].split(":")[0].strip().lstrip("- ")
    with pytest.raises(ConfigError, match=rf"key '{key}': given twice"):
        load_study(p)


def test_study_not_utf8(tmp_path):
    p = tmp_path / "quick.yaml"
    p.write_bytes(("# \u00e9tude\n" + QUICK.read_text(encoding="utf-8")).encode("latin-1", errors="replace"))
    with pytest.raises(ConfigError, match="is not UTF-8 text"):
        load_study(p)


ASCII = {**os.environ, "LANG": "C", "LC_ALL": "C", "PYTHONUTF8": "0", "PYTHONIOENCODING": ""}


@pytest.mark.parametrize(
    "argv",
    [
        ["point", "--robot", str(R4), "--at", "0.5", "0.2", "2.5"],
        ["inverse", "--robot", str(R4), "--at", "0.5", "0.2", "2.5"],
        ["point", "--robot", str(ROBOTS / "cdpr4_winch.yaml"), "--at", "0.5", "0.2", "2.5", "--json"],
        ["winch"],
        ["--help"],
    ],
)
def test_ascii_locale(argv):
    """Under LANG=C every command still runs on the shipped robots (the package opens its own files,
    whose texts contain non-ASCII letters, as UTF-8, and prints what the terminal can show)."""
    p = subprocess.run([sys.executable, "-m", "cdpr", *argv], capture_output=True, env=ASCII, cwd=ROOT)
    assert p.returncode == 0, p.stderr.decode(errors="replace")[-2000:]
    assert b"Traceback" not in p.stderr


def test_several_schema_mistakes_in_one_report(tmp_path, capsys):
    """Three mistakes in three places of one robot file: one run names all three."""
    robot = yaml.safe_load(R4.read_text(encoding="utf-8"))
    robot["cables"][1]["pulley"] = {"kind": "XX"}
    robot["cables"][2]["A_m"] = [1, 2]
    robot["cable"]["colour"] = "red"
    p = tmp_path / "r.yaml"
    p.write_text(yaml.safe_dump(robot), encoding="utf-8")
    code, out, err = run(["point", "--robot", str(p), "--at", "0", "0", "2.5"], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert "3 problems" in err
    for key in ("cables[1].pulley.kind", "cables[2].A_m", "cable.colour"):
        assert f"key '{key}'" in err, err
