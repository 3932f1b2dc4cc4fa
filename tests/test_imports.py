"""The package's import structure: every module imports on its own, and the whole import graph
of ``python/gyrobias`` is acyclic — function-level imports included.

The graph is read from the source with :mod:`ast`: every ``import``/``from … import`` statement
anywhere in a module (top level, ``try``/``if`` bodies, function and method bodies, nested
functions and classes) is an edge, except those under ``if TYPE_CHECKING:`` (annotations only,
never executed). Relative imports are resolved against the importing module's package, and
``from pkg import name`` points at the submodule ``pkg.name`` when there is one (else at
``pkg``). A function-level import is an edge too: a cycle held together by imports deferred
into functions is still a cycle (issue 24), so the value types (``gyrobias.allan._types``,
``gyrobias.noise._types``) reach plotting, exports and conservative only through the generic
functions of ``gyrobias._generics``, which those modules register (see docs/architecture.md).
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


def _module_name(path: Path, root: Path = PACKAGE) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _modules(root: Path = PACKAGE) -> dict[str, Path]:
    return {
        _module_name(p, root): p for p in sorted(root.rglob("*.py")) if "__pycache__" not in p.parts
    }


MODULES = _modules()
#: The compiled extension: a leaf (it imports no Python module of gyrobias).
EXTENSION = "gyrobias._core"


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _all_imports(tree: ast.Module) -> list[ast.Import | ast.ImportFrom]:
    """Every import statement in the module, at any depth, except under ``if TYPE_CHECKING:``."""
    found: list[ast.Import | ast.ImportFrom] = []

    def visit(node: ast.AST) -> None:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            found.append(node)
            return
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            for child in node.orelse:  # ``else:`` of ``if TYPE_CHECKING`` runs
                visit(child)
            return
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return found


def _edges(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The gyrobias modules that ``name`` imports anywhere in its source."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    known = {*modules, EXTENSION}
    out: set[str] = set()
    for node in _all_imports(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                anchor = parts[: len(parts) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            # ``from pkg import sub`` imports the submodule ``pkg.sub`` when there is one.
            targets = [
                f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names
            ]
        out.update(t for t in targets if t in modules and t != name)
    return out


def _graph(modules: dict[str, Path] = MODULES) -> dict[str, set[str]]:
    return {name: _edges(name, path, modules) for name, path in modules.items()}


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


def test_whole_import_graph_is_acyclic() -> None:
    graph = _graph()
    assert "gyrobias.allan" in graph and "gyrobias.plotting" in graph
    cycle = _find_cycle(graph)
    assert cycle is None, "import cycle (function-level imports count): " + " -> ".join(cycle or [])


def test_the_cycle_finder_finds_cycles() -> None:
    # The checker itself can fail: a two- and a three-module cycle are reported.
    assert _find_cycle({"a": {"b"}, "b": {"a"}}) == ["a", "b", "a"]
    assert _find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert _find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_edges_include_function_level_imports_but_not_type_checking(tmp_path: Path) -> None:
    # A miniature package: ``a`` imports ``b`` only inside a method, ``b`` imports ``a`` at
    # module level (the shape of issue 24's cycle), ``c`` imports ``a`` only for annotations,
    # and ``d`` uses a relative ``from . import``.
    pkg = tmp_path / "gyrobias"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("class A:\n    def plot(self):\n        from gyrobias.b import f\n")
    (pkg / "b.py").write_text("from gyrobias.a import A\n")
    (pkg / "c.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from gyrobias.a import A\n"
        "else:\n    import gyrobias.b\n"
    )
    (pkg / "sub" / "__init__.py").write_text("from . import d\n")
    (pkg / "sub" / "d.py").write_text("def g():\n    from .. import c\n    from ..a import A\n")
    graph = _graph(_modules(pkg))
    assert graph["gyrobias.a"] == {"gyrobias.b"}
    assert graph["gyrobias.b"] == {"gyrobias.a"}
    assert graph["gyrobias.c"] == {"gyrobias.b"}
    assert graph["gyrobias.sub"] == {"gyrobias.sub.d"}
    assert graph["gyrobias.sub.d"] == {"gyrobias.c", "gyrobias.a"}
    assert _find_cycle(graph) == ["gyrobias.a", "gyrobias.b", "gyrobias.a"]


def test_value_types_import_no_algorithm_module() -> None:
    # The result and coefficient types sit below every algorithm: they import only leaves
    # (the core, validation, units, file helpers, the generic functions) and each other.
    graph = _graph()
    types = {
        "gyrobias.allan._types",
        "gyrobias.noise._types",
        "gyrobias.io._types",
        "gyrobias.exports._types",
        "gyrobias._spectral_lines",
        "gyrobias.cleaning._types",
    }
    leaves = {"gyrobias._generics", "gyrobias._files", "gyrobias._validation", "gyrobias.units"}
    for name in sorted(types):
        assert graph[name] <= types | leaves, (name, graph[name] - types - leaves)
    for leaf in ("gyrobias._generics", "gyrobias._files"):
        assert graph[leaf] == set(), (leaf, graph[leaf])
    # The fleet table's layout, which plotting reads, needs nothing of the analysis.
    assert graph["gyrobias.fleet.table"] <= leaves, graph["gyrobias.fleet.table"]


#: The layers of docs/architecture.md, lowest first: (layer, module or package prefixes). A
#: module belongs to the layer of its longest matching prefix and imports only from its own
#: layer or lower ones (within a layer the acyclicity test above orders them).
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    (
        "leaves",
        (
            "gyrobias._validation",
            "gyrobias._cnames",
            "gyrobias.units",
            "gyrobias._files",
            "gyrobias._generics",
            "gyrobias._version",
            "gyrobias.io._store",
            "gyrobias.io._bag",
            "gyrobias.io._bagcore",
        ),
    ),
    (
        "value types",
        (
            "gyrobias.allan._types",
            "gyrobias.noise._types",
            "gyrobias.io._types",
            "gyrobias.exports._types",
            "gyrobias._spectral_lines",
            "gyrobias.fleet.table",
            "gyrobias.cleaning._types",
        ),
    ),
    (
        "science",
        (
            "gyrobias._line_detection",
            "gyrobias.allan",
            "gyrobias.noise",
            "gyrobias.io",
            "gyrobias.fir",
            "gyrobias.fractional",
            "gyrobias.spectral",
            "gyrobias.kalman",
            "gyrobias.predict",
            "gyrobias.datasheet",
            "gyrobias.conservative",
            "gyrobias.exports",
            "gyrobias.fleet.spread",
            "gyrobias.cleaning",
        ),
    ),
    (
        "composition",
        (
            "gyrobias.thermal",
            "gyrobias.fleet",
            "gyrobias.plotting",
            "gyrobias.report",
            "gyrobias.codegen",
        ),
    ),
    ("applications", ("gyrobias", "gyrobias.cli", "gyrobias.__main__", "gyrobias.explore")),
]


def _layer(module: str) -> int:
    best, rank = "", -1
    for i, (_, prefixes) in enumerate(LAYERS):
        for p in prefixes:
            if (module == p or module.startswith(p + ".")) and len(p) > len(best):
                best, rank = p, i
    assert rank >= 0, f"{module} is in no layer: place it in LAYERS and docs/architecture.md"
    return rank


def test_every_import_points_to_the_same_or_a_lower_layer() -> None:
    graph = _graph()
    upward = [
        f"{a} ({LAYERS[_layer(a)][0]}) imports {b} ({LAYERS[_layer(b)][0]})"
        for a in sorted(graph)
        for b in sorted(graph[a])
        if _layer(b) > _layer(a)
    ]
    assert upward == []


def test_the_layer_check_can_fail() -> None:
    assert _layer("gyrobias.noise._types") < _layer("gyrobias.noise.fitting")
    assert (
        _layer("gyrobias.fleet.table") < _layer("gyrobias.fleet.spread") < _layer("gyrobias.fleet")
    )
    assert _layer("gyrobias") == len(LAYERS) - 1


def test_science_modules_do_not_import_plotting() -> None:
    graph = _graph()
    for name in MODULES:
        if name.startswith(("gyrobias.allan", "gyrobias.noise", "gyrobias.io")) or name in (
            "gyrobias.thermal",
            "gyrobias.predict",
            "gyrobias.fleet",
            "gyrobias.exports",
        ):
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
    # ``python -c "import gyrobias.noise"`` for every module: an import-order problem that
    # bites only when a particular module is imported first fails here. Importing
    # ``gyrobias.x`` runs ``gyrobias/__init__`` first, so every module that ``import gyrobias``
    # loads starts from the same state (the façade is lazy: that is only ``_generics``); those
    # are imported fresh as ``gyrobias`` (plus the allan/noise/plotting trio by name), and every
    # other module on its own. ``__main__`` is the command line itself (it runs on import) and
    # is left out.
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
    # No import loads matplotlib: gyrobias.plotting (loaded for its ``.plot()`` registrations)
    # imports it only when a plot is drawn.
    for module, _, loaded, _ in results:
        assert not any(m.split(".")[0] == "matplotlib" for m in loaded), module


def test_only_plotting_imports_matplotlib() -> None:
    # All drawing code lives in the gyrobias.plotting package: no other module (science or
    # command line) imports matplotlib, even lazily inside a function.
    offenders = []
    for name, path in MODULES.items():
        if name == "gyrobias.plotting" or name.startswith("gyrobias.plotting."):
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
