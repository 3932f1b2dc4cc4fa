"""Generate the API reference from every public module's ``__all__`` at build time.

The reference is one page (``api/index.rst``) grouped by task, as scipy.signal's index is.
Which names exist is read from the package at build time, never written down here: the task
groups below only *place* names. A group lists explicit names (``"gyrobias.allan.adev"``)
and/or whole modules (``"gyrobias.kalman"``: every name of that module not placed elsewhere),
so a name added to a module's ``__all__`` tomorrow appears in its module's group without an
edit here. A name placed by no group lands in a final "Other public names" section (and the
build says so), so coverage never depends on this table being complete.

Each object is documented exactly once, under its *canonical* public path: a name that several
public modules export (``gyrobias.adev`` is ``gyrobias.allan.adev``; ``gyrobias.noise.from_datasheet``
is ``gyrobias.datasheet.from_datasheet``) is documented where it is defined, and the other
paths are listed in the "Also importable as" table at the end. Submodules listed in a
package's ``__all__`` are sections of the page, not entries.

Public modules: ``gyrobias`` and every module below it without a leading underscore in any
path component, except the command implementations ``gyrobias.cli.<command>`` (each command
is documented by its ``--help``, rendered on the command-line page; ``gyrobias.cli`` itself,
with ``main``, is in the reference).

``tests/test_docs_api.py`` checks the result: every name in every public module's ``__all__``
appears exactly once (as an entry or as an alias row of its entry).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import types
from collections.abc import Iterable
from dataclasses import dataclass, field

PACKAGE = "gyrobias"

# (title, one-line description, placements). Order is the page's order.
GROUPS: list[tuple[str, str, list[str]]] = [
    (
        "Reading logs",
        "Text, NumPy, ROS1/ROS2 bags and MCAP files, with a sampling report.",
        ["gyrobias.io"],
    ),
    (
        "Cleaning a log",
        "Stable32's Outliers and Drift steps (robust MAD z-score, least-squares drift) and the "
        "min/max envelope that draws a long log.",
        ["gyrobias.cleaning"],
    ),
    (
        "Allan family of deviations",
        "Overlapping and non-overlapping Allan, modified, Hadamard, total, Théo statistics, with "
        "chi-square confidence intervals (NIST SP 1065, IEEE Std 952).",
        [
            "gyrobias.allan.adev",
            "gyrobias.allan.avar",
            "gyrobias.allan.mdev",
            "gyrobias.allan.tdev",
            "gyrobias.allan.hdev",
            "gyrobias.allan.totdev",
            "gyrobias.allan.mtotdev",
            "gyrobias.allan.htotdev",
            "gyrobias.allan.theo1",
            "gyrobias.allan.theobr",
            "gyrobias.allan.theoh",
            "gyrobias.allan.adev_batch",
            "gyrobias.allan.AllanResult",
            "gyrobias.allan.NOISE_NAMES",
            "gyrobias.allan",
        ],
    ),
    (
        "Dynamic Allan deviation",
        "Allan deviation in sliding windows: a time × τ map (Galleani & Tavella 2009).",
        ["gyrobias.allan.dynamic_adev", "gyrobias.allan.DynamicAllanResult"],
    ),
    (
        "Noise identification",
        "IEEE-952 coefficients (Q, N, B, K, R) and Gauss–Markov terms with uncertainties: joint "
        "fit, IEEE read-off, GMWM, diagnostics.",
        [
            "gyrobias.noise.fit",
            "gyrobias.noise.gmwm",
            "gyrobias.noise.NoiseCoefficients",
            "gyrobias.noise.Term",
            "gyrobias.noise.GaussMarkovTerm",
            "gyrobias.noise.FitDiagnostics",
            "gyrobias.noise.gauss_markov_avar",
            "gyrobias.noise.TERM_NAMES",
            "gyrobias.noise.FLICKER_FACTOR",
            "gyrobias.noise",
        ],
    ),
    (
        "Simulation",
        "Simulated gyro logs with known noise terms.",
        ["gyrobias.noise.simulate", "gyrobias.fractional.arfima"],
    ),
    (
        "Estimator parameters",
        "Datasheets in, conservative (overbounding) sets, estimator files (Kalibr, OpenVINS, VINS, "
        "ORB-SLAM3, LIO-SAM, MATLAB, JSON), discrete-time values.",
        [
            "gyrobias.datasheet",
            "gyrobias.conservative",
            "gyrobias.exports.write_kalibr",
            "gyrobias.exports",
        ],
    ),
    (
        "HTML report",
        "One self-contained page per log.",
        ["gyrobias.report"],
    ),
    (
        "Exploring a log",
        "The interactive app (gyrobias explore): its state object, from which the results, the "
        "reproducing Python code and the command are derived, and its Panel views and server.",
        [
            "gyrobias.explore",
            "gyrobias.explore.state",
            "gyrobias.explore.app",
            "gyrobias.explore.server",
        ],
    ),
    (
        "Fleets of units",
        "Every unit's noise terms on Dask, out-of-family units, the fleet's spread.",
        ["gyrobias.fleet"],
    ),
    (
        "Long-memory (1/f) noise",
        "Type-II fractional differencing and integration, local Whittle estimation of d.",
        ["gyrobias.fractional"],
    ),
    (
        "Bias prediction",
        "Predicting a bias from a calibration window ([BP]).",
        ["gyrobias.predict"],
    ),
    (
        "Fixed-gain Kalman filter",
        "The [rate, bias] filter of [NR]: design, frequency response, streaming.",
        ["gyrobias.kalman"],
    ),
    (
        "FIR filtering",
        "Kaiser-window low-pass design and zero-phase or causal filtering ([TS]).",
        ["gyrobias.fir"],
    ),
    (
        "C code generation",
        "C99 for the fixed-gain filter, the FIR and the compiled predictor (float64, float32, Q31).",
        ["gyrobias.codegen"],
    ),
    (
        "Spectral analysis",
        "Least-squares spectra of unequally spaced data, Welch PSD, noise density.",
        ["gyrobias.spectral"],
    ),
    (
        "Temperature-dependent models",
        "AR(1) drift fits and noise parameters interpolated in temperature ([TS]).",
        ["gyrobias.thermal"],
    ),
    (
        "Plotting",
        "Every figure the library draws (needs matplotlib: ``pip install 'gyrobias[plot]'``).",
        ["gyrobias.plotting"],
    ),
    (
        "Units",
        "The one unit parser: deg, rad, g, m, s, h, Hz, √, powers.",
        ["gyrobias.units"],
    ),
    (
        "Errors, version and command line",
        "The package-level names and the ``gyrobias`` command's entry point.",
        ["gyrobias", "gyrobias.cli"],
    ),
]


def public_modules() -> list[types.ModuleType]:
    """``gyrobias`` and every public module below it (see the module docstring)."""
    root = importlib.import_module(PACKAGE)
    names = [PACKAGE]
    for info in pkgutil.walk_packages(root.__path__, PACKAGE + ".", onerror=lambda _: None):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts):
            continue
        if parts[:2] == [PACKAGE, "cli"] and len(parts) > 2:
            continue
        names.append(info.name)
    mods = []
    for name in sorted(set(names)):
        mod = importlib.import_module(name)
        if hasattr(mod, "__all__"):
            mods.append(mod)
    return mods


@dataclass
class Entry:
    """One documented object: its canonical path and every other public path of it."""

    module: str
    name: str
    obj: object
    aliases: list[str] = field(default_factory=list)

    @property
    def path(self) -> str:
        return f"{self.module}.{self.name}"


def _is_identity_object(obj: object) -> bool:
    """Objects whose identity means "the same thing" (not small ints/strings that may coincide)."""
    return inspect.isclass(obj) or inspect.isroutine(obj) or isinstance(obj, types.ModuleType)


def _rank(module: str, obj: object) -> tuple[int, int, int, str]:
    """Sort key choosing the canonical module of an object exported by several modules."""
    defined = getattr(obj, "__module__", None) or ""
    depth = module.count(".")
    return (
        0 if module != PACKAGE else 1,  # a subpackage over the top-level re-export
        0 if defined == module or defined.startswith(module + ".") else 1,
        depth,
        module,
    )


def collect() -> tuple[list[Entry], list[tuple[str, str]]]:
    """All documented entries, and the (module, name) pairs that are submodules (sections)."""
    seen: dict[int, list[tuple[str, str, object]]] = {}  # key -> every (module, name, obj)
    order: list[int] = []
    submodules: list[tuple[str, str]] = []
    for mod in public_modules():
        for name in mod.__all__:
            obj = getattr(mod, name)
            if isinstance(obj, types.ModuleType):
                submodules.append((mod.__name__, name))
                continue
            # a class/function/module is itself wherever it is exported; a constant is "the
            # same" when a module re-exports it under its name (same name, same object)
            key = id(obj) if _is_identity_object(obj) else hash((name, id(obj)))
            if key not in seen:
                seen[key] = []
                order.append(key)
            seen[key].append((mod.__name__, name, obj))
    entries = []
    for key in order:
        places = sorted(seen[key], key=lambda p: _rank(p[0], p[2]))
        module, name, obj = places[0]
        entries.append(Entry(module, name, obj, [f"{m}.{n}" for m, n, _ in places[1:]]))
    return entries, submodules


def place(entries: Iterable[Entry]) -> tuple[list[tuple[str, str, list[Entry]]], list[Entry]]:
    """Assign entries to the task groups: explicit names first, then whole modules."""
    entries = list(entries)
    by_path = {e.path: e for e in entries}
    placed: dict[str, int] = {}
    for gi, (_, _, items) in enumerate(GROUPS):
        for item in items:
            if item in by_path and item not in placed:
                placed[item] = gi
    for gi, (_, _, items) in enumerate(GROUPS):
        for item in items:
            for e in entries:
                if e.module == item and e.path not in placed:
                    placed[e.path] = gi
    groups: list[tuple[str, str, list[Entry]]] = [(t, d, []) for t, d, _ in GROUPS]
    for gi, (_, _, items) in enumerate(GROUPS):
        explicit = [by_path[i] for i in items if i in by_path and placed.get(i) == gi]
        rest = [e for e in entries if placed.get(e.path) == gi and e not in explicit]
        groups[gi][2].extend(explicit + sorted(rest, key=lambda e: (e.module, e.name.lower())))
    unplaced = [e for e in entries if e.path not in placed]
    return [g for g in groups if g[2]], unplaced


def _underline(text: str, char: str) -> str:
    return f"{text}\n{char * len(text)}\n"


def render() -> tuple[str, list[str]]:
    """The reStructuredText of ``api/index.rst`` and the unplaced names (for a build warning)."""
    entries, submodules = collect()
    groups, unplaced = place(entries)
    if unplaced:
        groups.append(("Other public names", "Names not yet placed in a task group.", unplaced))
    out = [
        ".. This file is generated by docs/_ext/apiref.py at every build; do not edit.\n",
        _underline("API reference", "="),
        "Every public name of every public module's ``__all__`` appears once, grouped by task, "
        "under the module that defines it; names that are also importable from elsewhere "
        "(``gyrobias.adev`` is :func:`gyrobias.allan.adev`) are listed in "
        ":ref:`api-aliases`. The package's modules: "
        + ", ".join(f"``{PACKAGE}.{n}``" for m, n in submodules if m == PACKAGE)
        + ".\n",
    ]
    for title, desc, group in groups:
        out.append(_underline(title, "-"))
        out.append(desc + "\n")
        out.append(".. autosummary::\n   :toctree: generated/\n   :nosignatures:\n")
        out.extend(f"   {e.path}" for e in group)
        out.append("")
    out.append(".. _api-aliases:\n")
    out.append(_underline("Also importable as", "-"))
    out.append("The same objects under other public paths (re-exports; documented once, above).\n")
    rows = [(a, e.path) for e in entries for a in e.aliases]
    out.append(".. list-table::\n   :header-rows: 1\n\n   * - path\n     - documented as")
    for alias, path in sorted(rows):
        role = _role(next(e for e in entries if e.path == path).obj)
        out.append(f"   * - ``{alias}``\n     - :{role}:`{path}`")
    out.append("")
    return "\n".join(out) + "\n", [e.path for e in unplaced]


def _role(obj: object) -> str:
    if inspect.isclass(obj):
        return "py:class"
    if inspect.isroutine(obj):
        return "py:func"
    return "py:data"


def documented_names(rst: str) -> list[str]:
    """The autosummary entries and alias rows of a rendered page (for the coverage test)."""
    names = []
    for line in rst.splitlines():
        s = line.strip()
        if line.startswith("   gyrobias"):
            names.append(s)
        elif s.startswith("* - ``") and s.endswith("``"):
            names.append(s[len("* - ``") : -2])
    return names
