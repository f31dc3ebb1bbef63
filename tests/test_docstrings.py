"""Docstrings of the model modules: numpy-style Parameters and Returns sections that name every
parameter, and a citation of the paper each module reproduces (Paty 2021 or Métillon 2022)."""

import importlib
import inspect
import re

import pytest

MODEL_MODULES = [
    "models.pulleys",
    "models.inverse",
    "models.statics",
    "models.direct",
    "models.subsets",
    "models.results",
    "models.winch",
    "analyses.workspace",
    "analyses.doe",
    "models.equilibrium",
    "models.tension_distribution",
    "analyses.compensation",
    "models.drive",
    "analyses.scans",
    "models.sensitivity",
    "analyses.uncertainty",
    "analyses.budget",
    "analyses.symmetry",
    "models.platform",
    "compiled._pose_sensitivity",
    "models.catenary",
    "models.cables",
    "models.interference",
    "analyses.interference",
    "models.continuation",
]

#: A numpy section header: a title line underlined by dashes of the same length.
_UNDERLINE = re.compile(r"-{3,}")
#: A parameter entry of a numpy Parameters section: "name : type", "a, b : type" or a bare "name".
_ENTRY = re.compile(r"(\*{0,2}[A-Za-z_]\w*(?:\s*,\s*\*{0,2}[A-Za-z_]\w*)*)\s*(?::.*)?")


def sections(doc):
    """Numpy sections of a docstring: {title: [lines]}, lines dedented as ``inspect.cleandoc``."""
    lines = inspect.cleandoc(doc or "").splitlines()
    out, title = {}, None
    for i, line in enumerate(lines):
        nxt = lines[i + 1].strip() if i + 1 < len(lines) else ""
        if line.strip() and _UNDERLINE.fullmatch(nxt) and len(nxt) == len(line.strip()):
            title = line.strip()
            out[title] = []
        elif title is not None and not (_UNDERLINE.fullmatch(line.strip()) and not out[title]):
            out[title].append(line)
    return out


def documented_names(lines):
    """Names of the entries (unindented lines) of a Parameters section."""
    names = set()
    for line in lines:
        if not line.strip() or line[0].isspace():
            continue
        match = _ENTRY.fullmatch(line.strip())
        if match:
            names.update(n.strip().lstrip("*") for n in match.group(1).split(","))
    return names


def public_functions():
    for m in MODEL_MODULES:
        mod = importlib.import_module(f"cdpr.{m}")
        for name, f in inspect.getmembers(mod, inspect.isfunction):
            if not name.startswith("_") and f.__module__ == mod.__name__:
                yield pytest.param(f, id=f"{m}.{name}")


def test_parser_reads_numpy_sections():
    def f(a, b, *args, c=1, **options):
        """Summary.

        Parameters
        ----------
        a : array (N, 3) [m]
            Text mentioning d : not an entry.
        b, c : float [N]
        options : passed on.

        Returns
        -------
        x : float [m]
        """

    sec = sections(f.__doc__)
    assert set(sec) == {"Parameters", "Returns"}
    assert documented_names(sec["Parameters"]) == {"a", "b", "c", "options"}
    assert any(line.startswith("x :") for line in sec["Returns"])


@pytest.mark.parametrize("func", list(public_functions()))
def test_parameters_and_returns_sections(func):
    sec = sections(func.__doc__)
    assert "Parameters" in sec, f"{func.__qualname__}: no numpy 'Parameters' section"
    assert "Returns" in sec, f"{func.__qualname__}: no numpy 'Returns' section"
    assert any(line.strip() for line in sec["Returns"]), f"{func.__qualname__}: empty Returns section"
    summary = inspect.cleandoc(func.__doc__).splitlines()[0]
    assert summary.strip() and not _UNDERLINE.fullmatch(summary.strip())


@pytest.mark.parametrize("func", list(public_functions()))
def test_every_parameter_documented(func):
    params = inspect.signature(func).parameters.values()
    documented = documented_names(sections(func.__doc__).get("Parameters", []))
    named = {p.name for p in params if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}
    missing = sorted(named - documented)
    assert not missing, f"{func.__qualname__}: parameters {missing} not in its Parameters section"
    stale = sorted(documented - {p.name for p in params})
    assert not stale, f"{func.__qualname__}: Parameters section names {stale}, not in the signature"


@pytest.mark.parametrize("name", MODEL_MODULES)
def test_module_cites_its_paper(name):
    mod = importlib.import_module(f"cdpr.{name}")
    texts = [mod.__doc__ or ""] + [
        f.__doc__ or ""
        for _, f in inspect.getmembers(mod, inspect.isfunction)
        if f.__module__ == mod.__name__
    ]
    assert any("Paty" in t or "Métillon" in t for t in texts), f"cdpr.{name} cites neither paper"


@pytest.mark.parametrize("name", MODEL_MODULES)
def test_module_reference_section_is_complete(name):
    """A module's References section gives the full reference of the paper it cites."""
    refs = "\n".join(sections(importlib.import_module(f"cdpr.{name}").__doc__).get("References", []))
    assert refs, f"cdpr.{name}: no References section in the module docstring"
    full = {
        "Paty": "Mechanism and Machine Theory 159, 104263",
        "Métillon": "hal-03758222",
    }
    cited = [key for key in full if key in refs]
    assert cited, f"cdpr.{name}: References cite neither paper"
    for key in cited:
        assert full[key] in " ".join(refs.split()), f"cdpr.{name}: incomplete reference of {key}"
