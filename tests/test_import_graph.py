"""The package's import graph: no loop among module-level imports, and no new loop hidden behind an
import inside a function (the ones left are listed, to be removed, never added to).

Python tolerates some import loops, but a loop makes the layers unreadable (which module is built
on which) and forces imports into function bodies; `farm-studio look` draws the same graph.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "setsmooth"

#: The loops still closed by an import inside a function (strongly connected components).
KNOWN_LOOPS = 1

#: Third-party packages that may be imported inside a function, to stay optional (Dask's
#: ``distributed``) or out of the import time of the package, the command line and the numpy-only
#: layers (plotting, python-control, progress bars, thread control).
LAZY_PACKAGES = ("matplotlib", "mpl_toolkits", "control", "tqdm", "distributed", "threadpoolctl")

#: A ceiling on every other import inside a function: it may only go down. They are the imports that
#: close the sets/ loop (`ConvexSet`'s operators and relations call the algorithms built on it:
#: base, relations, extension, box), the command line's (`runs.cli`, `arena.command`: no NumPy or
#: solver at start-up), `analysis`'s of sets and models (it stays a NumPy-only layer, without
#: CVXPY), and in `solvers/` those of highspy (its import time) and CVXPY's Clarabel interface, and
#: `certify`'s and `parametric`'s of `sets` (the sets/ loop).
MAX_OTHER_IMPORTS_INSIDE_FUNCTIONS = 46


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _graph(module_level_only: bool) -> dict[str, set[str]]:
    modules = {_module(p): p for p in ROOT.rglob("*.py")}
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for name, path in modules.items():
        tree = ast.parse(path.read_text())
        nodes = tree.body if module_level_only else list(ast.walk(tree))
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for node in nodes:
            if not isinstance(node, ast.ImportFrom):
                continue  # (module-level ``if TYPE_CHECKING:`` blocks are If nodes: skipped)
            if node.level:
                base = package[:len(package) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            elif node.module and node.module.split(".")[0] == "setsmooth":
                target = node.module
            else:
                continue
            for candidate in [f"{target}.{alias.name}" for alias in node.names] + [target]:
                if candidate in modules and candidate != name:
                    graph[name].add(candidate)
                    break
    return graph


def _loops(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    loops: list[list[str]] = []
    counter = 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    loops.append(sorted(component))
    return loops


def test_the_loop_finder_finds_a_loop():
    assert _loops({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_loop_among_module_level_imports():
    assert _loops(_graph(module_level_only=True)) == []


def test_no_new_loop_behind_imports_inside_functions():
    loops = _loops(_graph(module_level_only=False))
    assert len(loops) <= KNOWN_LOOPS, loops


def _imports_inside_functions() -> list[tuple[str, int, str]]:
    """(module, line, imported module) of every import statement inside a function of setsmooth."""
    found = set()
    for path in ROOT.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for function in ast.walk(tree):
            if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in ast.walk(function):
                    if isinstance(node, ast.Import):
                        found.add((_module(path), node.lineno, node.names[0].name))
                    elif isinstance(node, ast.ImportFrom):
                        found.add((_module(path), node.lineno, "." * node.level + (node.module or "")))
    return sorted(found)


def test_imports_inside_functions_are_lazy_dependencies_or_fewer_than_before():
    other = [found for found in _imports_inside_functions()
             if found[2].split(".")[0] not in LAZY_PACKAGES]
    assert len(other) <= MAX_OTHER_IMPORTS_INSIDE_FUNCTIONS, other
