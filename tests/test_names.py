"""One model, one door (issue 37): the point mass is the rigid platform with b = 0, so no concept
exists twice as a point-mass name and a "6" name. No module file and no public name (a top-level
function, class or assignment, or an entry of ``__all__``) of ``cdpr/models``, ``cdpr/compiled``,
``cdpr/analyses``, ``cdpr/pipeline`` and ``cdpr/tables.py`` ends in ``6``."""

import ast
from pathlib import Path

import pytest

CDPR = Path(__file__).resolve().parents[1] / "cdpr"
FILES = sorted(
    [f for part in ("models", "compiled", "analyses", "pipeline") for f in (CDPR / part).rglob("*.py")]
    + [CDPR / "tables.py"]
)


def public_names(path):
    """The public top-level names of a module: functions, classes, assigned names and ``__all__``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        for t in targets if isinstance(node, (ast.Assign, ast.AnnAssign)) else []:
            for n in ast.walk(t):
                if isinstance(n, ast.Name):
                    names.add(n.id)
            if (
                isinstance(t, ast.Name)
                and t.id == "__all__"
                and isinstance(node.value, (ast.List, ast.Tuple))
            ):
                names.update(e.value for e in node.value.elts if isinstance(e, ast.Constant))
    return sorted(n for n in names if not n.startswith("_"))


def test_the_layers_have_files():
    assert len(FILES) > 50 and CDPR / "tables.py" in FILES


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.relative_to(CDPR).as_posix())
def test_no_name_ends_in_6(path):
    assert not path.stem.endswith("6"), f"{path.relative_to(CDPR)}: a module file ending in 6"
    six = [n for n in public_names(path) if n.endswith("6")]
    assert not six, f"{path.relative_to(CDPR)}: public names ending in 6: {', '.join(six)}"


def test_the_check_sees_a_twin(tmp_path):
    """The check is not vacuous: a module with a "6" function, class, constant or ``__all__``
    entry is caught, private names are not."""
    f = tmp_path / "twin.py"
    f.write_text(
        '__all__ = ["solve6"]\nRULE6 = 1\ndef solve6(): pass\nclass Problem6: pass\ndef _private6(): pass\n'
    )
    assert public_names(f) == ["Problem6", "RULE6", "solve6"]
