"""The house's import structure: no import cycle between the modules of cdpr (grimp's graph counts
imports inside functions and under TYPE_CHECKING too), and no import inside a function outside
cdpr/cli/ (the layers themselves are import-linter's contracts in pyproject.toml, `make test`)."""

import ast

import grimp

from tests.conftest import ROOT


def find_cycle(graph):
    """One import cycle of ``graph`` as a list of modules [a, b, ..., a], or None (iterative DFS)."""
    modules = sorted(graph.modules)
    state = dict.fromkeys(modules, 0)  # 0 new, 1 on the current path, 2 done
    for root in modules:
        if state[root]:
            continue
        path = [root]
        stack = [iter(sorted(graph.find_modules_directly_imported_by(root)))]
        state[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state[nxt] == 1:
                return path[path.index(nxt) :] + [nxt]
            elif state[nxt] == 0:
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(graph.find_modules_directly_imported_by(nxt))))
    return None


class _Graph:
    """A hand-made graph with grimp's two methods, to show that ``find_cycle`` finds one."""

    def __init__(self, edges):
        self.edges = edges
        self.modules = set(edges) | {b for bs in edges.values() for b in bs}

    def find_modules_directly_imported_by(self, module):
        return set(self.edges.get(module, ()))


def test_find_cycle_finds_and_names_a_cycle():
    assert find_cycle(_Graph({"a": {"b"}, "b": {"c"}, "c": set()})) is None
    assert find_cycle(_Graph({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}})) == ["a", "b", "c", "a"]
    assert find_cycle(_Graph({"x": {"x"}})) == ["x", "x"]


def test_no_import_cycle_between_modules():
    # cache_dir=None: no .grimp_cache/ in the current folder (grimp's default cache)
    graph = grimp.build_graph("cdpr", include_external_packages=False, cache_dir=None)
    assert {"cdpr.solve", "cdpr.models.results", "cdpr.pipeline.uq"} <= graph.modules
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


#: The command line's start-up path: the only places where an import may sit inside a function, each
#: marked ``# lazy: <reason>`` (``cdpr --help`` must not load numpy; ``cdpr.__version__`` is read
#: from the installed metadata only when asked for; scipy's ``Rotation`` is imported where it is used,
#: issue 17, and so is the anchors' ``ConvexHull`` of the physical mode, of the envelope volume and
#: of the platform's body (interference), so
#: that scipy.spatial, 0.2 s, stays off the start-up of every command that does not need it; SALib and
#: scipy.stats, 0.4 s, are imported by the Sobol analysis and the truncated normal that use them, not
#: by every job that reads a study).
STARTUP = {
    "cdpr/__init__.py",
    "cdpr/__main__.py",
    "cdpr/models/platform.py",
    "cdpr/models/results.py",
    "cdpr/models/interference.py",
    "cdpr/analyses/workspace.py",
    "cdpr/analyses/uncertainty.py",
}


def _imports_cdpr(node):
    """True when the import statement ``node`` imports one of the package's own modules."""
    names = [node.module or ""] if isinstance(node, ast.ImportFrom) else [a.name for a in node.names]
    return any(n == "cdpr" or n.startswith("cdpr.") for n in names)


def test_no_import_inside_a_function_outside_the_cli():
    """Outside cdpr/cli/ the only imports inside functions are the lazy third-party ones of STARTUP
    (scipy.spatial, scipy.stats, SALib: docs/code.md), never one of the package's own modules."""
    found = []
    for path in sorted((ROOT / "cdpr").rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if "cli" in path.relative_to(ROOT / "cdpr").parts:
            continue
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found += [
                    f"{rel}:{sub.lineno} {ast.unparse(sub)}"
                    for sub in ast.walk(node)
                    if isinstance(sub, (ast.Import, ast.ImportFrom))
                    and not (
                        rel in STARTUP
                        and "# lazy:" in lines[sub.lineno - 1]
                        and (rel in ("cdpr/__init__.py", "cdpr/__main__.py") or not _imports_cdpr(sub))
                    )
                ]
    assert not found, "imports inside functions (move them to the module top):\n" + "\n".join(found)


def private_crossings(path, rel):
    """Where the file at ``path`` uses another cdpr module's private name: ``from cdpr.x import _y``
    (a private *module*, such as ``cdpr.compiled._kernels``, may be imported: its names are public
    inside it) or ``alias._y`` on a cdpr module imported as ``alias``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    modules, found = {}, []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("cdpr") and a.asname:
                    modules[a.asname] = a.name
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("cdpr"):
            for a in node.names:
                full = f"{node.module}.{a.name}"
                is_module = (ROOT / (full.replace(".", "/") + ".py")).exists() or (
                    ROOT / full.replace(".", "/")
                ).is_dir()
                if is_module:
                    modules[a.asname or a.name] = full
                elif a.name.startswith("_"):
                    found.append(f"{rel}:{node.lineno} from {node.module} import {a.name}")
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in modules
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            found.append(f"{rel}:{node.lineno} {modules[node.value.id]}.{node.attr}")
    return found


def test_private_crossings_are_found(tmp_path):
    f = tmp_path / "m.py"
    f.write_text(
        "from cdpr.robot import _hidden, load_robot\n"
        "from cdpr.pipeline import comparison as cm\n"
        "from cdpr.compiled import _kernels\n"
        "x = cm._read, cm.verdict, _kernels.CHUNK, cm.__name__\n"
    )
    assert private_crossings(f, "m.py") == [
        "m.py:1 from cdpr.robot import _hidden",
        "m.py:4 cdpr.pipeline.comparison._read",
    ]


def test_no_private_name_crosses_a_module_boundary():
    """Issue 16: a module uses only the public names of another (public names inside private
    modules such as ``compiled/_kernels.py``)."""
    found = []
    for path in sorted((ROOT / "cdpr").rglob("*.py")):
        found += private_crossings(path, path.relative_to(ROOT).as_posix())
    assert not found, "private names used across modules (make them public):\n" + "\n".join(found)
