"""MkDocs hook: the Results page (results.md) completed from the tracked results/ folder at build time.

The page is ``docs/results.md`` (the headline tables and dated findings, written by hand) followed by
what this hook reads from results/ when the site is built: per study (results/paper,
results/physical) its summary.md and every figure (PNG) it wrote, then results/comparison.md with
the comparison's figures. The PNGs are added to the site as files (copied from results/, never
duplicated under docs/); nothing needs the network. A missing results folder gives a section that
says so (``make reproduce`` writes them)."""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "results"
STUDIES = {
    "paper": "Paper study (paper rule: best 3-cable subset)",
    "physical": "Physical study (equilibrium on all cables)",
}
PAGE = "results.md"
#: The generated part of the page, built in on_files (where the figures are added to the site) and
#: appended to docs/results.md in on_page_markdown.
_GENERATED: dict[str, str] = {}


def _demote(md: str, by: int = 1) -> str:
    """Headings one level deeper (the page has its own title), links to repository files as code."""
    md = re.sub(r"^(#+) ", lambda m: "#" * (len(m[1]) + by) + " ", md, flags=re.M)
    return md


def _figures(rel_dir: Path, files, config) -> list[str]:
    out = []
    for png in sorted((RESULTS / rel_dir).rglob("*.png")):
        uri = f"results/{png.relative_to(RESULTS).as_posix()}"
        files.append(File(uri, str(ROOT), config["site_dir"], config["use_directory_urls"]))
        name = png.relative_to(RESULTS / rel_dir).as_posix()
        out.append(f"**{name}**\n\n![{name}]({uri})\n")
    return out


def page_markdown(files, config) -> str:
    """The generated sections of the Results page (figures are added to ``files``)."""
    parts = [
        "## The results folder, as built",
        "",
        "The tables and figures of `make reproduce`, read from `results/` when the site was built: each "
        "study's summary (the papers' numbers beside ours) and figures, then the paper-rule-versus-physics "
        "comparison. [Models and reproduction](models.md) says which function draws each figure.",
        "",
    ]
    if not RESULTS.is_dir():
        return "\n".join(parts + ["No results/ folder: run `make reproduce` first."])
    for study, title in STUDIES.items():
        parts += [f"### {title}", ""]
        summary = RESULTS / study / "summary.md"
        if summary.is_file():
            parts += [_demote(summary.read_text(encoding="utf-8"), 3), ""]
        parts += [f"#### Figures of results/{study}", ""] + _figures(Path(study), files, config)
    cmp = RESULTS / "comparison.md"
    if cmp.is_file():
        text = cmp.read_text(encoding="utf-8")
        text = re.sub(r"\]\((comparison/[^)]+\.png)\)", r"](results/\1)", text)
        parts += ["### Paper rule versus physics", "", _demote(text, 3), ""]
        _figures(Path("comparison"), files, config)  # the page links them; add them to the site
    return "\n".join(parts)


def on_files(files, config):
    _GENERATED[PAGE] = page_markdown(files, config)
    return files


def on_page_markdown(markdown, page, config, files):
    if page.file.src_uri == PAGE:
        return markdown.rstrip("\n") + "\n\n" + _GENERATED.get(PAGE, "") + "\n"
    return markdown
