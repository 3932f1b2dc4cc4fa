"""The release workflow runs only what CI runs (issue 25 item 5).

Every build and test step of ``.github/workflows/release.yml`` is a ``make`` target that
``.ci/run`` also runs, so a release builds and tests exactly what CI builds and tests on every
change (the workflow itself cannot run here; ``make actionlint`` checks its syntax and
expressions). Setting up a runner (toolchains, GNU make on Windows) and moving artifacts are
actions, not ``run`` steps.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: A `run` step that only prepares the runner (no build, no test).
SETUP_STEPS = {"GNU make (Windows)"}


def _make_targets(command: str) -> set[str]:
    """The targets of every ``make`` invocation in a shell command (options and VAR=x skipped)."""
    targets: set[str] = set()
    for m in re.finditer(r"(?:^|[\s;&|(]|\$\()make((?:[ \t]+[^\s;&|)]+)*)", command, re.M):
        targets.update(w for w in m.group(1).split() if not w.startswith("-") and "=" not in w)
    return targets


def _with_prerequisites(targets: set[str]) -> set[str]:
    """``targets`` and every target they depend on in the Makefile (``wheel: sdist``)."""
    rules: dict[str, list[str]] = {}
    for line in (ROOT / "Makefile").read_text(encoding="utf-8").splitlines():
        if m := re.match(r"^([a-z][a-z-]*):(?!=)([^#]*)", line):
            rules[m.group(1)] = m.group(2).split()
    done: set[str] = set()
    todo = list(targets)
    while todo:
        t = todo.pop()
        if t not in done:
            done.add(t)
            todo.extend(rules.get(t, []))
    return done


def _workflow() -> dict[str, Any]:
    yaml = pytest.importorskip("yaml")
    path = ROOT / ".github" / "workflows" / "release.yml"
    if not path.is_file():  # pragma: no cover - make test-wheel copies it
        pytest.skip("the release workflow is not beside tests/")
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


def test_target_parser() -> None:
    assert _make_targets("make wheel test-wheel") == {"wheel", "test-wheel"}
    assert _make_targets('test "$x" = "$(make -s version)"') == {"version"}
    assert _make_targets("make lint-python PYTHON=venv/bin/python") == {"lint-python"}
    assert _make_targets("cmake --build .; echo make") == set()


def test_every_release_step_is_a_make_target_ci_runs() -> None:
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    ci_targets = _with_prerequisites(_make_targets(ci))
    assert {"sdist", "wheel", "test-wheel", "actionlint", "version"} <= ci_targets
    used: set[str] = set()
    for name, job in _workflow()["jobs"].items():
        for step in job["steps"]:
            if "run" not in step or step.get("name") in SETUP_STEPS:
                continue
            targets = _make_targets(step["run"])
            assert targets, f"job {name}: step {step.get('name')!r} is not a make target"
            assert targets <= ci_targets, f"job {name}: {targets - ci_targets} not run by .ci/run"
            used |= targets
    assert {"sdist", "wheel", "test-wheel"} <= used


def test_publishing_uses_trusted_publishing_on_tags_only() -> None:
    publish = _workflow()["jobs"]["publish"]
    assert publish["if"] == "startsWith(github.ref, 'refs/tags/v')"
    assert publish["permissions"] == {"id-token": "write"}
    assert any("pypa/gh-action-pypi-publish" in s.get("uses", "") for s in publish["steps"])
    assert not any("password" in s.get("with", {}) for s in publish["steps"])
