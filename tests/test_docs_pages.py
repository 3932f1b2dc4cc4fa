"""Every code example of the documentation pages and of the README runs and prints what it says.

Each ```python block of ``docs/**/*.md`` is in doctest form (``>>>``) and runs here with the
same runner the docs build uses (and each ``gyrobias …`` line of a ```bash run block runs through
the CLI and must exit with 0) (docs/_ext/mdexamples.py: one namespace per page, a fresh
temporary working directory). The README's Python example and its ``gyrobias`` command lines
run on a small simulated ROS bag written beside them. The gallery scripts are executed by the
docs build (sphinx-gallery), not here.
"""

from __future__ import annotations

import re
import shlex
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import mdexamples  # noqa: E402

GENERATED = {"cli.md"}
PAGES = sorted(
    p
    for p in DOCS.rglob("*.md")
    if "_build" not in p.parts
    and "auto_examples" not in p.parts
    and p.relative_to(DOCS).as_posix() not in GENERATED
)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(DOCS).as_posix())
def test_page_examples_run(page: Path) -> None:
    result = mdexamples.run_file(page)
    assert result.failures == [], "\n\n".join(f"line {ln}:\n{r}" for ln, r in result.failures)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(DOCS).as_posix())
def test_every_python_block_is_an_executed_example(page: Path) -> None:
    """A ```python block without ``>>>`` would be shown but never run: not allowed."""
    text = page.read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert all(b.lstrip().startswith(">>>") for b in blocks)


def test_the_runner_reports_a_wrong_output() -> None:
    """The runner can fail: a wrong expected output and an exception are both reported."""
    text = "```python\n>>> 1 + 1\n3\n>>> 1 / 0\n```\n"
    result = mdexamples.run_text(text, "bad.md")
    assert [ln for ln, _ in result.failures] == [2, 4]
    assert result.attempted == 2


def test_the_runner_runs_bash_run_blocks_and_reports_a_failing_command() -> None:
    text = (
        "```bash\ngyrobias allan shown-only.csv\n```\n"  # shown, not run
        "```bash run\ngyrobias --version\ngyrobias allan missing.csv  # no such file\n```\n"
    )
    assert mdexamples.commands(text) == [
        (5, "gyrobias --version"),
        (6, "gyrobias allan missing.csv"),
    ]
    result = mdexamples.run_text(text, "cli.md")
    assert result.attempted == 2
    assert [ln for ln, _ in result.failures] == [6]
    assert "exit code 2" in result.failures[0][1]


def _write_bag(directory: Path) -> None:
    """A 2-minute, 200 Hz ROS1 bag of a white-noise IMU (gyro in rad/s, accel in m/s²)."""
    from tests.test_bags import regular, write_bag

    n, fs = 24_000, 200.0
    rng = np.random.default_rng(5)
    data = np.empty((n, 6))
    data[:, :3] = rng.normal(0.0, 2e-3 * np.sqrt(fs), (n, 3))
    data[:, 3:] = rng.normal(0.0, 3e-2 * np.sqrt(fs), (n, 3))
    data[:, 5] += 9.81
    write_bag(directory / "imu", "ros1", regular(n, fs), data)


def test_readme_python_examples_run() -> None:
    pytest.importorskip("rosbags")
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert mdexamples.extract(text), "the README has no Python example"
    result = mdexamples.run_text(text, "README.md", setup=_write_bag)
    assert result.failures == [], "\n\n".join(f"line {ln}:\n{r}" for ln, r in result.failures)


def test_readme_command_lines_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every ``gyrobias …`` line of the README's shell blocks runs (exit 0) on the bag."""
    pytest.importorskip("rosbags")
    from gyrobias.cli import main

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```(?:bash|console|sh)\n(.*?)^```", text, flags=re.S | re.M)
    lines = [
        ln.strip() for b in blocks for ln in b.splitlines() if ln.strip().startswith("gyrobias ")
    ]
    assert lines, "the README has no gyrobias command line"
    _write_bag(tmp_path)
    monkeypatch.chdir(tmp_path)
    for line in lines:
        argv = shlex.split(line.split(" #")[0])[1:]
        if argv[:1] == ["demo"]:
            argv += ["--hours", "0.05", "--outdir", str(tmp_path / "demo")]
        assert main([*argv, "--no-progress"] if argv[0] == "allan" else argv) == 0, line


def _ci_readme_command() -> str:
    """The command ``.ci/run`` runs as "the README's test command, verbatim": the first line after
    that comment that is neither a comment nor a progress message (``echo``/``step``)."""
    lines = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    marks = [
        i
        for i, ln in enumerate(lines)
        if ln.lstrip().startswith("#") and "README's test command, verbatim" in ln
    ]
    assert marks, ".ci/run does not say which command is the README's test command"
    for ln in lines[marks[0] + 1 :]:
        s = ln.strip()
        if s and not s.startswith(("#", "echo ", "step ")):
            return s
    raise AssertionError(".ci/run has no command after its README test-command comment")


def test_readme_test_command_is_the_one_ci_runs() -> None:
    """The README's test command is, verbatim, the one ``.ci/run`` runs (no drift between them)."""
    command = _ci_readme_command()
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```bash\n(.*?)^```", readme, flags=re.S | re.M)
    assert command in {ln.strip() for b in blocks for ln in b.splitlines()}


def _first_bash_line(text: str) -> str:
    block = re.search(r"^```bash\n(.*?)^```", text, flags=re.S | re.M)
    assert block, "no bash block"
    return next(ln for ln in block.group(1).splitlines() if ln.strip())


def test_readme_first_command_is_what_ci_runs_first() -> None:
    """The README's first command (issue 33) installs from the source tree, needs no build
    artefact, and is what ``.ci/run`` runs — verbatim, extracted from README.md by
    ``scripts/readme-first-command`` — in a fresh clone and venv before anything is built."""
    import subprocess

    script = ROOT / "scripts" / "readme-first-command"
    if not script.is_file():  # pragma: no cover - make test-wheel copies scripts/
        pytest.skip("scripts/ is not beside tests/")
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    first = _first_bash_line(readme)
    extracted = subprocess.run(
        ["bash", str(script)], capture_output=True, text=True, check=True
    ).stdout
    assert extracted == first + "\n"
    # It builds from the clone it is run in: no dist/, no other build product named.
    assert "'.[plot]'" in first and "gyrobias demo" in first
    assert not re.search(r"\bdist\b|find-links|target/", first), first
    # docs/index.md and docs/install.md show the same first command.
    for page in ("index.md", "install.md"):
        assert _first_bash_line((DOCS / page).read_text(encoding="utf-8")) == first, page
    # .ci/run runs it first: before the Rust checks and before any wheel is built.
    ci = [ln.strip() for ln in (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()]
    runs = [i for i, ln in enumerate(ci) if ln == "bash scripts/first-command"]
    assert len(runs) == 1, "the README's first command is not run by .ci/run"
    later = [i for i, ln in enumerate(ci) if ln.startswith(('step "cargo', "make wheel", "cargo "))]
    assert later and runs[0] < min(later)
    # scripts/first-command: a fresh clone and venv, the extracted command, nothing exported.
    runner = (ROOT / "scripts" / "first-command").read_text(encoding="utf-8")
    assert "git clone" in runner and "-m venv" in runner
    assert "command=$(bash scripts/readme-first-command)" in runner
    assert 'bash -c "$command"' in runner
    assert not re.search(r"^\s*export\b", runner, flags=re.M)
    assert re.search(r"^unset CARGO_TARGET_DIR\b", runner, flags=re.M)
