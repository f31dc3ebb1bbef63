"""The README is a front page, the documentation holds the rest, and nothing was lost in the move.

* ``README.md`` has at most 150 lines and still says what a newcomer needs first: the set-up
  command, the two commands (``.ci/run`` runs the README's test command), that the quick start runs
  from the repository root, that rigid platforms are physical-mode robots, and links to every page;
* every page under ``docs/`` is linked from ``docs/index.md`` and listed in the ``nav`` of
  ``mkdocs.yml`` (a page outside the nav is built but unreachable from the menu);
* every section of the README before its cut to a front page (448 lines, December 2026) has a home:
  ``MOVED`` maps each of its headings to the files that now hold it and, for each, text that the
  section carried (a heading or a key sentence); the test finds that text in that file, so the
  move is checked, not asserted;
* the README's headline table is a part of the full table on the Results page, row for row, and
  the measured times the README corrected are not contradicted by another page.
"""

from __future__ import annotations

import re

import pytest
import yaml

from tests.conftest import ROOT

DOCS = ROOT / "docs"
README = ROOT / "README.md"
MAX_README_LINES = 150

#: Each heading of the old README -> (file, text) pairs: the file now holding that section's
#: content and a heading or key sentence of it (whitespace-insensitive; line breaks may differ).
MOVED: dict[str, list[tuple[str, str]]] = {
    "What this is": [
        ("README.md", "the direct elasto-geometric model DEGM_E with two solvers"),
        ("README.md", "the dead length d that the paper never gives (default 4 m)"),
    ],
    "Library quick-start": [
        ("README.md", "df = solve_table(dr, P)  # DEGM_E, one row per point"),
        ("docs/index.md", "picks the compiled kernel for Newton and the numpy reference for the fixed point"),
        ("docs/index.md", "are `cdpr.__all__`, loaded on first use (`import cdpr` alone imports no numpy)"),
        ("docs/index.md", "Points that are not `ok` are kept and flagged, never dropped."),
    ],
    "Command line": [
        ("docs/cli.md", "## At a glance"),
        ("docs/cli.md", "# many points at once: a table with columns x, y, z in, a result table out"),
        (
            "docs/cli.md",
            "Bad input gives one line, `cdpr: error: ...`, naming the file, the key and what is allowed",
        ),
        ("docs/cli.md", "A grid whose table cannot fit in the machine's memory is refused"),
    ],
    "Robot files": [
        ("docs/config.md", "then for the physics, whenever it is read"),
        ("docs/config.md", "`h_m = r_p_m` is the common swivel pulley"),
    ],
    "Spatial robots: a rigid 6-DoF platform, pulleys at any angle": [
        ("README.md", "## Spatial robots are physical-mode robots"),
        ("docs/spatial.md", "the robot is then solved as a rigid 6-DoF platform"),
        ("docs/spatial.md", "| `hang4_6dof.yaml` | under-constrained: 4 cables, rigid platform |"),
        ("docs/spatial.md", "On CoGiRo the best is test 6"),
        ("docs/spatial.md", "It is 1.70 on CoGiRo against 2.96 on CDPR4"),
    ],
    "The pipeline": [
        ("docs/pipeline.md", "## Results folders"),
        (
            "docs/pipeline.md",
            "| `dead_length/` | calibration of the dead length d, which the paper does not give |",
        ),
        ("docs/pipeline.md", "Any study resumes the same way, your own included"),
        ("docs/pipeline.md", "Snakemake reads `--config` as a list"),
        ("docs/pipeline.md", "`make reproduce` rewrites the tracked results under `results/` while it runs"),
        ("docs/pipeline.md", "Files are written with the mode your umask allows"),
        ("docs/pipeline.md", "5 min 45 s measured on the 2-core machine"),
        ("docs/pipeline.md", "`make report` builds Snakemake's HTML reports"),
        ("docs/pipeline.md", "runs on its own pytest-xdist worker"),
    ],
    "Running on a cluster (SLURM)": [
        ("docs/pipeline.md", "### Running on a cluster (SLURM)"),
        ("docs/pipeline.md", "**Site settings.**"),
        ("docs/pipeline.md", "**Job accounting.**"),
        ("docs/pipeline.md", "**Interrupted run.**"),
        ("docs/pipeline.md", "**Testing on a real SLURM.**"),
        ("docs/pipeline.md", "On the 2-CPU VM at load 5 (2026-12-02) it took 545 s"),
    ],
    "Studying your own design": [
        ("docs/own-robot.md", "Copy a robot file, e.g. `config/robots/example_8x6x4.yaml`"),
        ("docs/own-robot.md", "A test runs this example end to end at low resolution"),
    ],
    "Speed": [
        ("benchmarks/README.md", "## Speed in short"),
        ("benchmarks/README.md", "CDPR4 with DR pulleys solves at 877,000 points/s in the kernel"),
        ("benchmarks/README.md", "69 s measured on the 2-core machine"),
        ("README.md", "9.8 minutes"),
    ],
    "Where we stand against the papers": [
        ("docs/results.md", "## Where we stand against the papers"),
        ("docs/results.md", "| RW_C volume | 80.31 | 82.83 (our computed box) |"),
        ("docs/results.md", "The dead length d is not given by the paper"),
    ],
    "Does the paper survive physics?": [
        ("docs/results.md", "## Does the paper survive physics?"),
        ("docs/results.md", "| SR* is more robust to E than DR* (smaller band of the index over E) |"),
        ("docs/results.md", "Pulley geometry dominates every design"),
    ],
    "Calibration: what each model buys": [
        ("docs/results.md", "## Calibration: what each model buys"),
        ("docs/results.md", "| (iv) pulleys + elasticity + winch | 28 |"),
        ("docs/results.md", "A rigid 6-DoF platform calibrates with the same commands"),
    ],
}


def _flat(text: str) -> str:
    """Whitespace runs as one space: a sentence matches whatever the line breaks."""
    return re.sub(r"\s+", " ", text)


def _read(rel: str) -> str:
    return (ROOT / rel).read_text(encoding="utf-8")


def _doc_pages() -> list[str]:
    """Every Markdown page under docs/, relative to docs/ (the Results page is one: the hook only
    appends to it)."""
    pages = sorted(p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md"))
    assert pages, "no page under docs/"
    return pages


def _nav_pages(node) -> set[str]:
    if isinstance(node, str):
        return {node}
    if isinstance(node, list):
        return set().union(*(_nav_pages(n) for n in node)) if node else set()
    if isinstance(node, dict):
        return set().union(*(_nav_pages(v) for v in node.values())) if node else set()
    return set()


def _links(text: str) -> set[str]:
    """Targets of the inline Markdown links of ``text``, without their #anchor."""
    return {m.group(1).split("#")[0] for m in re.finditer(r"\]\(([^)\s]+)\)", text)}


def test_readme_is_a_front_page():
    text = _read("README.md")
    n = len(text.splitlines())
    assert n <= MAX_README_LINES, f"README.md has {n} lines, at most {MAX_README_LINES}"
    for needed in ("make venv", "make reproduce", "make test", "repository root", "physical-mode"):
        assert needed in text, f"README.md does not say {needed!r}"
    # the two commands are commands the README shows in a shell block, not just words
    blocks = "\n".join(re.findall(r"```bash\n(.*?)```", text, flags=re.S))
    for command in ("make venv", "make reproduce", "make test"):
        assert re.search(rf"^{command}\b", blocks, flags=re.M), f"no `{command}` line in a README shell block"


def test_ci_runs_the_readme_test_command():
    """.ci/run runs exactly what the README tells a user to run for the tests."""
    ci = _read(".ci/run")
    assert re.search(r"^make test$", ci, flags=re.M)
    assert "make test" in _read("README.md")


def test_readme_links_every_top_level_page():
    links = _links(_read("README.md"))
    for page in _doc_pages():
        if "/" in page and page != "api/index.md":
            continue  # the API pages are reached from api/index.md
        assert f"docs/{page}" in links, f"README.md does not link docs/{page}"
    for target in links:
        if not target.startswith(("http://", "https://")):
            assert (ROOT / target).is_file(), f"README.md links {target}, which does not exist"


def test_every_docs_page_is_linked_from_the_index():
    links = _links(_read("docs/index.md"))
    missing = [p for p in _doc_pages() if p != "index.md" and p not in links]
    assert not missing, f"docs/index.md does not link: {missing}"


def test_every_docs_page_is_in_the_mkdocs_nav():
    nav = _nav_pages(yaml.safe_load(_read("mkdocs.yml"))["nav"])
    pages = set(_doc_pages())
    assert pages - nav == set(), f"pages missing from mkdocs.yml nav: {sorted(pages - nav)}"
    assert nav - pages == set(), f"mkdocs.yml nav names pages that do not exist: {sorted(nav - pages)}"


@pytest.mark.parametrize("heading", sorted(MOVED))
def test_every_old_readme_section_has_a_home(heading):
    for rel, key in MOVED[heading]:
        assert (ROOT / rel).is_file(), f"{heading!r}: {rel} does not exist"
        assert _flat(key) in _flat(_read(rel)), f"section {heading!r}: {rel} lacks {key!r}"


def test_the_mapping_checks_something():
    """A made-up sentence is not found: the check above can fail."""
    assert _flat("a sentence no page has, 1234567") not in _flat(_read("docs/pipeline.md"))
    assert _flat("## Results folders") not in _flat(_read("docs/cli.md"))


def _table_rows(text: str, header: str) -> list[str]:
    """The body rows of the first Markdown table whose header line is ``header``."""
    lines = text.splitlines()
    start = lines.index(header)
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append(line.strip())
    return rows


def test_readme_headline_rows_are_rows_of_the_results_page():
    header = "| quantity | paper | ours | unit | verdict |"
    headline = _table_rows(_read("README.md"), header)
    full = _table_rows(_read("docs/results.md"), header)
    assert len(headline) >= 3
    missing = [row for row in headline if row not in full]
    assert not missing, f"README headline rows not on the Results page (docs/results.md): {missing}"


def test_corrected_times_are_not_contradicted():
    """make reproduce-quick took 5 min 45 s and the first compile 69 s on the 2-core machine:
    no page says "about a minute" for the one or 15 s for the other."""
    texts = {"README.md": _read("README.md")} | {f"docs/{p}": _read(f"docs/{p}") for p in _doc_pages()}
    for name, text in texts.items():
        flat = _flat(text)
        assert not re.search(r"reproduce-quick[^.]*about a minute", flat), name
        assert not re.search(r"compil[^.]{0,80}\b15 s\b", flat), name
    assert "5 min 45 s" in _flat(_read("README.md"))
    assert "69 s" in _flat(_read("README.md"))
