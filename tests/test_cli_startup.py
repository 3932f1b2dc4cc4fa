"""The command line starts light: ``gyrobias --help``, ``--version`` and every subcommand's
``--help`` import neither NumPy nor the compiled core (``gyrobias._core``).

Not timed (timings belong in ``benches/python/bench_install.py``): each command runs as
``python -m gyrobias ...`` in a fresh interpreter, which writes the modules it loaded to a file
when it exits, and the test reads that list. The subcommands are found from the parser itself,
so a new command is checked without being listed here.

The lazy package façade this needs keeps its promises, checked here too: a public name's first
use loads it, and the results' methods are in place whatever the caller imported first.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

import gyrobias
from gyrobias import _generics
from gyrobias.cli import build_parser

#: Modules a light start must not load (NumPy, and the extension, which needs it for any work).
HEAVY = ("numpy", "gyrobias._core")

_WRAPPER = """
import atexit, runpy, sys
out, argv = sys.argv[1], sys.argv[2:]
atexit.register(lambda: open(out, "w").write("\\n".join(sorted(sys.modules))))
sys.argv = ["gyrobias", *argv]
runpy.run_module("gyrobias", run_name="__main__", alter_sys=True)
"""


def _subcommands(
    parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()
) -> Iterator[tuple[str, ...]]:
    """Every command path of ``parser`` (``("allan",)``, ``("kalman", "design")``, ...)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield (*prefix, name)
                yield from _subcommands(sub, (*prefix, name))


COMMANDS = [["--help"], ["--version"]] + [
    [*path, "--help"] for path in _subcommands(build_parser())
]


def _run(argv: list[str], tmp_path: Path) -> tuple[list[str], int, str, set[str]]:
    out = tmp_path / ("modules-" + "-".join(a.strip("-") for a in argv) + ".txt")
    done = subprocess.run(
        [sys.executable, "-c", _WRAPPER, str(out), *argv],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    return argv, done.returncode, done.stdout, set(out.read_text().split())


def test_the_commands_are_found() -> None:
    # The walk of the parser finds the nested commands too (the test cannot pass vacuously).
    paths = {tuple(c[:-1]) for c in COMMANDS}
    assert {("allan",), ("fleet",), ("kalman", "design"), ("experiment", "table1")} <= paths


def test_help_and_version_import_neither_numpy_nor_the_core(tmp_path: Path) -> None:
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(lambda argv: _run(argv, tmp_path), COMMANDS))
    problems = []
    for argv, code, stdout, modules in results:
        if code != 0:
            problems.append(f"gyrobias {' '.join(argv)}: exit {code}")
        elif argv == ["--version"]:
            if stdout.strip() != f"gyrobias {gyrobias.__version__}":
                problems.append(f"--version printed {stdout.strip()!r}")
        elif not stdout.startswith("usage: gyrobias"):
            problems.append(f"gyrobias {' '.join(argv)}: no usage text")
        loaded = sorted(m for m in modules if m in HEAVY or m.startswith("numpy."))
        if loaded:
            problems.append(f"gyrobias {' '.join(argv)} imported {loaded[:3]}")
    assert problems == []


def test_the_check_sees_numpy_when_it_is_imported(tmp_path: Path) -> None:
    # The same wrapper on a command that computes does load NumPy and the core.
    argv, code, _, modules = _run(
        ["fir", "design", "--fs", "100", "--fpass", "10", "--fstop", "30"], tmp_path
    )
    assert code == 0 and set(HEAVY) <= modules


def test_fleet_threshold_help_states_the_default() -> None:
    # --threshold's default is read when the command runs; its help text repeats the value.
    from gyrobias import fleet

    fleet_parser = next(
        a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)
    ).choices["fleet"]
    (threshold,) = [a for a in fleet_parser._actions if "--threshold" in a.option_strings]
    assert threshold.default is None
    assert f"default {fleet.OUT_OF_FAMILY_THRESHOLD:g}," in (threshold.help or "")


def test_import_gyrobias_alone_is_light_and_names_load_on_first_use() -> None:
    code = (
        "import sys, gyrobias\n"
        "assert 'numpy' not in sys.modules and 'gyrobias._core' not in sys.modules\n"
        "assert 'adev' in dir(gyrobias)\n"
        "assert gyrobias.noise.__name__ == 'gyrobias.noise'\n"
        "from gyrobias import AllanResult, __version__\n"
        "assert gyrobias.adev is gyrobias.allan.adev and __version__ == gyrobias._core.__version__\n"
        "try:\n"
        "    gyrobias.no_such_name\n"
        "except AttributeError as e:\n"
        "    print(e)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "module 'gyrobias' has no attribute 'no_such_name'"


@pytest.mark.parametrize(
    "code",
    [
        # .to_c() of a class imported from its own module: gyrobias.codegen was not imported
        "from gyrobias.kalman import FixedGainKalman\n"
        "assert 'gyrobias.codegen' not in sys.modules\n"
        "g = FixedGainKalman(100.0, arw=0.01, rrw=0.0, bandwidth=10.0).to_c(sys.argv[1])\n"
        "assert g.header.exists()\n",
        # .export() of a fit: gyrobias.exports was not imported
        "import numpy as np\n"
        "from gyrobias.allan import adev\n"
        "from gyrobias.noise import fit\n"
        "assert 'gyrobias.exports' not in sys.modules\n"
        "x = np.random.default_rng(1).normal(size=20000)\n"
        "c = fit(adev(x, 100.0, units='deg/s'))\n"
        "c.export('json', sys.argv[1] + '/n.json')\n",
    ],
)
def test_methods_are_in_place_whatever_was_imported_first(code: str, tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-c", "import sys\n" + code, str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr


def test_a_generic_without_a_method_still_says_so() -> None:
    # After the façade's loader has run, an unsupported type is a TypeError naming the verb.
    with pytest.raises(TypeError, match="^plot: no method for object objects$"):
        _generics.plot(object())
    with pytest.raises(TypeError, match="^to_c: no method for int objects$"):
        _generics.to_c(3, "x")
