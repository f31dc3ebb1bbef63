"""Every name of the package that the prose mentions exists: no documentation points to a module,
function or file that was renamed or removed.

The scan covers the READMEs (``README.md``, ``benchmarks/README.md``, ``config/README.md``), the
documentation (``docs/**/*.md``), ``pyproject.toml``, ``mkdocs.yml``, the workflow (``Snakefile``,
``workflow/**/*.smk`` and the report captions ``workflow/**/*.rst``), the configuration
(``config/**/*.yaml``) and the package itself (``cdpr/**/*.py``: docstrings, comments and code;
``cdpr/**/*.yaml``). In each line it finds

* dotted names ``cdpr.x.y...``: the longest importable prefix is imported and the rest must be
  attributes of it (a class's dataclass fields and annotated attributes count);
* paths ``cdpr/x/y.py`` (and ``.yaml``, ``.yml``, ``.md``, ``.json``): the file must exist;
* ``from cdpr.x import a, b``: every imported name must be an attribute or a submodule of cdpr.x;
* short names of the flat modules the layers replaced (``redundancy.solve_points``,
  ``fast_sensitivity.linear_dp``, ...): no module of that name is left to resolve them against.

Each failure lists ``file:line: name (why)`` for every unresolved name. The test reads only: it
imports the package (bytecode and numba caches go where ``tests/conftest.py`` sends them) and writes
nothing to the working tree.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import re

from tests.conftest import ROOT

#: Historical names deliberately kept in dated benchmark text, each with where and why. Empty: the
#: dated measurements of benchmarks/README.md name today's modules (``cdpr/compiled/subsets.py``,
#: ``cdpr.compiled.sensitivity.linear_dp``, ...); the code they measured is in git history, at the
#: commit of each measurement. Add an entry only for a name that must stay as it was written, as
#: ``{"cdpr/fast.py": "benchmarks/README.md, dated table: the file measured, today
#: cdpr/compiled/subsets.py"}``; an entry no file mentions any more fails the test.
ALLOWED: dict[str, str] = {}

#: Files scanned, as glob patterns relative to the repository root.
PATTERNS = [
    "README.md",
    "benchmarks/README.md",
    "config/README.md",
    "docs/**/*.md",
    "pyproject.toml",
    "mkdocs.yml",
    "Snakefile",
    "workflow/**/*.smk",
    "workflow/**/*.rst",
    "config/**/*.yaml",
    "cdpr/**/*.py",
    "cdpr/**/*.yaml",
]

#: Endings of file names written with dots (``cdpr.yaml``): not a dotted module name.
FILE_SUFFIXES = ("py", "yaml", "yml", "md", "json", "toml", "csv", "parquet", "png", "log", "txt")

#: A dotted name of the package: not part of a longer word, path or dotted name.
DOTTED = re.compile(r"(?<![\w/.-])cdpr(?:\.[A-Za-z_][A-Za-z0-9_]*)+")
#: A path into the package that names a file.
PATH = re.compile(r"(?<![\w/.-])cdpr(?:/[A-Za-z0-9_.-]+)+\.(?:py|yaml|yml|md|json)\b")
#: ``from cdpr.x import a, b`` (one line; parentheses and ``as`` aliases allowed).
FROM_IMPORT = re.compile(r"\bfrom\s+(cdpr(?:\.[A-Za-z_]\w*)*)\s+import\s+([\w\s,()]+?)(?:\s*#|$)")
#: ``module.name`` with a module of the flat package that the layers renamed (house refactor):
#: fast -> compiled.subsets, fast_physical -> compiled.equilibrium, fast_sensitivity ->
#: compiled.sensitivity, redundancy -> models.subsets, distribution -> models.tension_distribution.
RETIRED = {
    "fast": "cdpr.compiled.subsets",
    "fast_physical": "cdpr.compiled.equilibrium",
    "fast_sensitivity": "cdpr.compiled.sensitivity",
    "redundancy": "cdpr.models.subsets",
    "distribution": "cdpr.models.tension_distribution",
}
RETIRED_NAME = re.compile(r"(?<![\w/.-])(" + "|".join(RETIRED) + r")\.[A-Za-z_]\w*")


def scanned_files():
    files = sorted(
        {p for pat in PATTERNS for p in ROOT.glob(pat) if p.is_file() and "__pycache__" not in p.parts}
    )
    assert files, "no file to scan"
    return files


@functools.lru_cache(maxsize=None)
def unresolved(dotted):
    """Why ``dotted`` (``cdpr.x.y``) does not name an existing module or attribute, or None."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        mod = ".".join(parts[:i])
        try:
            obj = importlib.import_module(mod)
        except ModuleNotFoundError as exc:
            if exc.name and not (mod == exc.name or mod.startswith(exc.name + ".")):
                return f"importing {mod} fails: {exc}"  # a dependency is missing, not the name
            continue
        for j, attr in enumerate(parts[i:], start=i):
            if not has_name(obj, attr):
                return f"{'.'.join(parts[:j])} has no attribute {attr!r}"
            obj = getattr(obj, attr, None)
        return None
    return "no such module"


def has_name(obj, attr):
    """``attr`` is an attribute of ``obj``, a field of a dataclass or an annotated attribute."""
    if hasattr(obj, attr):
        return True
    if isinstance(obj, type):
        if dataclasses.is_dataclass(obj) and attr in {f.name for f in dataclasses.fields(obj)}:
            return True
        return any(attr in getattr(k, "__annotations__", {}) for k in obj.__mro__)
    return False


def scan(label, text):
    """Unresolved references of ``text`` as ``(where, name, why)``, where = ``label:line``."""
    bad = []
    for no, line in enumerate(text.splitlines(), start=1):
        where = f"{label}:{no}"
        for m in DOTTED.finditer(line):
            name = m.group(0)
            if name.rsplit(".", 1)[-1] in FILE_SUFFIXES:
                continue  # a file name such as cdpr.yaml
            why = unresolved(name)
            if why:
                bad.append((where, name, why))
        for m in PATH.finditer(line):
            name = m.group(0)
            if not (ROOT / name).is_file():
                bad.append((where, name, "no such file"))
        for m in FROM_IMPORT.finditer(line):
            module, names = m.group(1), m.group(2).replace("(", " ").replace(")", " ")
            for item in filter(None, (n.strip() for n in names.split(","))):
                name = f"{module}.{item.split()[0]}"
                why = unresolved(name)
                if why:
                    bad.append((where, f"from {module} import {item.split()[0]}", why))
        for m in RETIRED_NAME.finditer(line):
            bad.append((where, m.group(0), f"module {m.group(1)} is now {RETIRED[m.group(1)]}"))
    return bad


def report(bad):
    return f"{len(bad)} unresolved reference(s):\n" + "\n".join(f"{w}: {n} ({why})" for w, n, why in bad)


def test_every_package_name_the_docs_mention_exists():
    bad, seen = [], set()
    for path in scanned_files():
        label = path.relative_to(ROOT).as_posix()
        for where, name, why in scan(label, path.read_text(encoding="utf-8", errors="replace")):
            seen.add(name)
            if name not in ALLOWED:
                bad.append((where, name, why))
    assert not bad, report(bad)
    stale = sorted(set(ALLOWED) - seen)
    assert not stale, f"allow-listed names no longer mentioned (remove them from ALLOWED): {stale}"


def test_the_scanner_reports_made_up_names_with_file_and_line():
    text = "\n".join(
        [
            "Real: `cdpr.tables.solve_table`, cdpr/compiled/subsets.py, cdpr/schemas/study.schema.yaml.",
            "From `cdpr.models.no_such_module` and `cdpr.tables.no_such_function`,",
            "see cdpr/no_such_file.py; a file name cdpr.yaml is not a module.",
            "from cdpr.solve import solve_table  # lives in cdpr.tables",
            "from cdpr.tables import solve_table, to_frame",
            "as ``redundancy.solve_points``; fast. Not a name: redundancy.",
        ]
    )
    bad = scan("made_up.md", text)
    assert [(w, n) for w, n, _ in bad] == [
        ("made_up.md:2", "cdpr.models.no_such_module"),
        ("made_up.md:2", "cdpr.tables.no_such_function"),
        ("made_up.md:3", "cdpr/no_such_file.py"),
        ("made_up.md:4", "from cdpr.solve import solve_table"),
        ("made_up.md:6", "redundancy.solve_points"),
    ], report(bad)
    assert "made_up.md:2: cdpr.models.no_such_module (cdpr.models has no attribute" in report(bad)
    assert "cdpr.tables has no attribute 'no_such_function'" in report(bad)
