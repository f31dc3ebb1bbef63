"""docs/cli.md shows the command line as it is: every ``usage: cdpr ...`` block of the page and its
``cdpr --help`` block are the parser's own text (argparse at 100 columns), so a new option or
command cannot be left out of the page. ``python tests/cli/test_docs_usage.py`` rewrites the blocks
from the parser."""

import argparse
import re
import sys
from pathlib import Path

from cdpr.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "cli.md"
WIDTH = "100"
#: A fenced block whose first line is ``usage: cdpr <command>`` (the text of ``cdpr <command> --help``
#: up to its first blank line), or the ``$ .venv/bin/cdpr --help`` console block (the whole help).
USAGE = re.compile(r"```text\n(usage: cdpr (\S+) .*?)\n```", re.S)
TOP = re.compile(r"```console\n\$ \.venv/bin/cdpr --help\n(.*?)\n```", re.S)


def _parsers():
    """{command: its parser} and the top parser, formatted at ``WIDTH`` columns."""
    top = build_parser(jobs=True)
    sub = next(a for a in top._actions if isinstance(a, argparse._SubParsersAction))
    return top, dict(sub.choices)


def expected_blocks(monkeypatch_env):
    monkeypatch_env("COLUMNS", WIDTH)
    top, subs = _parsers()
    return top.format_help().rstrip("\n"), {k: p.format_usage().rstrip("\n") for k, p in subs.items()}


def rewrite(text, top_help, usages):
    """The page with its usage blocks and ``--help`` block replaced by the parser's."""
    text = USAGE.sub(lambda m: f"```text\n{usages[m.group(2)]}\n```", text)
    return TOP.sub(lambda m: f"```console\n$ .venv/bin/cdpr --help\n{top_help}\n```", text)


def test_every_usage_block_of_the_page_is_the_parsers(monkeypatch):
    top_help, usages = expected_blocks(monkeypatch.setenv)
    text = PAGE.read_text()
    shown = [m.group(2) for m in USAGE.finditer(text)]
    assert len(TOP.findall(text)) == 1
    assert sorted(shown) == sorted(usages), "docs/cli.md shows one usage block per command"
    for m in USAGE.finditer(text):
        assert m.group(1) == usages[m.group(2)], f"docs/cli.md: usage of cdpr {m.group(2)} differs"
    assert TOP.search(text).group(1) == top_help


def test_rewrite_replaces_a_stale_block(monkeypatch):
    """The check can fail: a usage block missing an option is found and rewritten."""
    top_help, usages = expected_blocks(monkeypatch.setenv)
    stale = "```text\nusage: cdpr inverse [-h] --robot FILE\n```"
    assert rewrite(stale, top_help, usages) == f"```text\n{usages['inverse']}\n```"
    assert "--rotvec" in usages["inverse"] and "--rotvec" not in stale


if __name__ == "__main__":  # rewrite docs/cli.md from the parser
    import os

    top_help, usages = expected_blocks(lambda k, v: os.environ.__setitem__(k, v))
    PAGE.write_text(rewrite(PAGE.read_text(), top_help, usages))
    sys.exit(0)
