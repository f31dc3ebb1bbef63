"""The repository is self-contained: no tracked text file points outside it.

Two checks over every tracked text file (``git ls-files``: Python, Markdown, YAML, Snakemake,
TOML, reStructuredText and shell sources, the Makefile, the Snakefile and the CI script):

* no mention of the project's out-of-repository notes folder (its name followed by a slash);
* no relative path that climbs out of the repository with parent-directory steps, and no Markdown
  link (``[text](target)``, ``<target>``, ``[ref]: target``) whose target starts with a
  parent-directory step: the documentation site and a forge render those links from inside the
  repository, where such a target is broken or leaves the project.

Each failure lists ``file:line: text`` for every offending line. The patterns are built from
pieces so that this file does not match itself.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

SUFFIXES = {".py", ".md", ".yaml", ".yml", ".smk", ".toml", ".rst", ".sh", ".cfg", ".ini", ".txt"}
NAMES = {"Makefile", "Snakefile", ".ci/run"}

UP = "." + "." + "/"  # one parent-directory step
NOTES = "sha" + "red" + "/"  # the notes folder that lives beside the repository, not in it

#: A relative path made of one or more parent-directory steps and what follows up to a delimiter.
UP_PATH = re.compile(r"(?<![\w.])(?:" + re.escape(UP) + r")+[^\s\"'`<>()\[\]{},;]*")
#: Markdown link targets: inline links/images, autolinks and reference definitions.
MD_TARGET = re.compile(r"\]\(\s*<?([^)\s>]+)|<([^<>\s]+)>|^\s*\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)")


def tracked_text_files():
    if shutil.which("git") is None:
        pytest.skip("git is not installed")
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0:
        pytest.skip("not a git work tree: " + out.stderr.strip())
    files = []
    for name in out.stdout.split("\0"):
        path = ROOT / name
        if name and (Path(name).suffix in SUFFIXES or name in NAMES) and path.is_file():
            files.append(name)
    assert files, "git ls-files listed no text file"
    return files


def lines_of(name):
    text = (ROOT / name).read_text(encoding="utf-8", errors="replace")
    return enumerate(text.splitlines(), start=1)


def escapes_repository(name, rel):
    """True when ``rel``, read relative to the folder of file ``name``, resolves outside ROOT."""
    target = (ROOT / name).parent / rel
    try:
        target.resolve().relative_to(ROOT)
    except ValueError:
        return True
    return False


def report(hits):
    return f"{len(hits)} offending line(s):\n" + "\n".join(hits)


def test_no_reference_to_the_notes_folder():
    hits = [
        f"{name}:{no}: {line.strip()}"
        for name in tracked_text_files()
        for no, line in lines_of(name)
        if NOTES in line
    ]
    if hits:
        pytest.fail(report(hits), pytrace=False)


def test_no_parent_directory_escape():
    hits = []
    for name in tracked_text_files():
        markdown = name.endswith(".md")
        for no, line in lines_of(name):
            bad = [m.group(0) for m in UP_PATH.finditer(line) if escapes_repository(name, m.group(0))]
            if markdown:
                for m in MD_TARGET.finditer(line):
                    target = next(g for g in m.groups() if g is not None)
                    if target.startswith(UP) and target not in bad:
                        bad.append(target)
            if bad:
                hits.append(f"{name}:{no}: {', '.join(bad)}: {line.strip()}")
    if hits:
        pytest.fail(report(hits), pytrace=False)
