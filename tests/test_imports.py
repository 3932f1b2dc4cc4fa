"""The package's import structure: every module imports on its own, without cycles.

Plotting lives in ``gyrobias.plotting`` only; the science modules import it (and matplotlib)
lazily inside their ``.plot()`` methods, so ``import gyrobias.allan`` or ``import
gyrobias.noise`` never loads it. The module-level import graph (what runs when a module is
first imported: top-level statements, ``try``/``if`` bodies, but not function bodies nor
``if TYPE_CHECKING:`` blocks) is read from the source with :mod:`ast` and must be acyclic.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import gyrobias

# The package under test, wherever it is imported from (the source tree or an installed wheel).
PACKAGE = Path(gyrobias.__file__).resolve().parent


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {
    _module_name(p): p for p in sorted(PACKAGE.rglob("*.py")) if "__pycache__" not in p.parts
}
#: The compiled extension: a leaf (it imports no Python module of gyrobias).
EXTENSION = "gyrobias._core"


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _top_level_imports(tree: ast.Module) -> list[ast.Import | ast.ImportFrom]:
    """Import statements executed when the module is imported (no functions, no TYPE_CHECKING)."""
    found: list[ast.Import | ast.ImportFrom] = []

    def visit(body: list[ast.stmt]) -> None:
        for node in body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found.append(node)
            elif isinstance(node, ast.If):
                if not _is_type_checking(node.test):
                    visit(node.body)
                visit(node.orelse)
            elif isinstance(node, ast.Try):
                visit(node.body)
                for handler in node.handlers:
                    visit(handler.body)
                visit(node.orelse)
                visit(node.finalbody)
            elif isinstance(node, (ast.With, ast.For, ast.While)):
                visit(node.body)
            # Function and class bodies: functions run later; classes hold no imports here.

    visit(tree.body)
    return found


def _edges(name: str, path: Path) -> set[str]:
    """The gyrobias modules ``name`` imports at module level."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in _top_level_imports(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            # ``from pkg import sub`` imports the submodule ``pkg.sub`` when there is one.
            targets = [
                f"{base}.{a.name}" if f"{base}.{a.name}" in (*MODULES, EXTENSION) else base
                for a in node.names
            ]
        out.update(t for t in targets if t in MODULES and t != name)
    return out


def _graph() -> dict[str, set[str]]:
    return {name: _edges(name, path) for name, path in MODULES.items()}


def _find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}  # 1: on the stack, 2: done
    stack: list[str] = []

    def dfs(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return [*stack[stack.index(nxt) :], nxt]
            if nxt not in state and (cycle := dfs(nxt)) is not None:
                return cycle
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (cycle := dfs(node)) is not None:
            return cycle
    return None


def test_module_level_import_graph_is_acyclic() -> None:
    graph = _graph()
    assert "gyrobias.allan" in graph and "gyrobias.plotting" in graph
    assert _find_cycle(graph) is None, " -> ".join(_find_cycle(graph) or [])


def test_the_cycle_finder_finds_cycles() -> None:
    # The checker itself can fail: a two- and a three-module cycle are reported.
    assert _find_cycle({"a": {"b"}, "b": {"a"}}) == ["a", "b", "a"]
    assert _find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert _find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_edges_follow_module_level_imports_only() -> None:
    tree = ast.parse(
        "from typing import TYPE_CHECKING\n"
        "from gyrobias import _core, units\n"
        "if TYPE_CHECKING:\n    from gyrobias.allan import AllanResult\n"
        "def f():\n    from gyrobias.plotting import plot_allan\n"
        "try:\n    import gyrobias.noise\nexcept ImportError:\n    pass\n"
    )
    seen = {
        (n.module if isinstance(n, ast.ImportFrom) else n.names[0].name)
        for n in _top_level_imports(tree)
    }
    assert seen == {"typing", "gyrobias", "gyrobias.noise"}


def test_science_modules_do_not_import_plotting_at_module_level() -> None:
    graph = _graph()
    for name in ("gyrobias.allan", "gyrobias.noise", "gyrobias.thermal", "gyrobias.predict"):
        assert "gyrobias.plotting" not in graph[name], name


def _import_fresh(module: str) -> tuple[str, int, list[str], str]:
    """Import ``module`` in a fresh interpreter: (module, exit code, gyrobias modules, stderr)."""
    code = (
        f"import sys, {module}\n"
        "print(' '.join(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('gyrobias', 'matplotlib'))))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False
    )
    return module, done.returncode, done.stdout.split(), done.stderr


def test_each_module_imports_in_a_fresh_interpreter() -> None:
    # ``python -c "import gyrobias.noise"`` for every module: an import cycle that bites only
    # when a particular module is imported first fails here. Importing ``gyrobias.x`` runs
    # ``gyrobias/__init__`` first, so every module that ``import gyrobias`` loads starts from
    # the same state; those are imported fresh as ``gyrobias`` (plus the allan/noise/plotting
    # trio by name), and every other module (cli, fleet, report, plotting, ...) on its own.
    # ``__main__`` is the command line itself (it runs on import) and is left out.
    _, code, package, err = _import_fresh("gyrobias")
    assert code == 0, err
    loaded_by_package = set(package)
    modules = sorted(
        {"gyrobias.allan", "gyrobias.noise", "gyrobias.plotting"}
        | {m for m in MODULES if m not in loaded_by_package and m != "gyrobias.__main__"}
    )
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = [("gyrobias", code, package, err), *pool.map(_import_fresh, modules)]
    failed = [f"{m}: {err.strip().splitlines()[-1:]}" for m, rc, _, err in results if rc != 0]
    assert failed == []
    # No import loads matplotlib, and only plotting itself loads gyrobias.plotting.
    for module, _, loaded, _ in results:
        assert not any(m.split(".")[0] == "matplotlib" for m in loaded), module
        assert module == "gyrobias.plotting" or "gyrobias.plotting" not in loaded, module


def test_only_plotting_imports_matplotlib() -> None:
    # All drawing code lives in gyrobias.plotting: no other module (science or command line)
    # imports matplotlib, even lazily inside a function.
    offenders = []
    for name, path in MODULES.items():
        if name == "gyrobias.plotting":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            offenders += [f"{name}: {n}" for n in names if n.split(".")[0] == "matplotlib"]
    assert offenders == []
