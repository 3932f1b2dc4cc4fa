"""One version, set in one place (issue 25 item 6).

The workspace version of ``Cargo.toml`` (``[workspace.package]``) is the only place a version
is written: maturin gives it to the wheel and the sdist (``dynamic = ["version"]``), the
extension exports it (``gyrobias._core.__version__``, ``env!("CARGO_PKG_VERSION")``), and
``gyrobias.__version__``, ``gyrobias --version`` and the CHANGELOG's latest release must agree.
The tests that read repository files (``Cargo.toml``, ``CHANGELOG.md``, ``pyproject.toml``) run
wherever those files sit beside ``tests/``: in the source tree, and in the copy ``make
test-wheel`` tests the installed wheel from.
"""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pytest

import gyrobias
from gyrobias import _core
from gyrobias.cli import main

ROOT = Path(__file__).resolve().parents[1]


def _repo_file(name: str) -> Path:
    path = ROOT / name
    if not path.is_file():  # pragma: no cover - make test-wheel copies these files
        pytest.skip(f"{name} is not beside tests/")
    return path


def _cargo_version() -> str:
    with _repo_file("Cargo.toml").open("rb") as f:
        return str(tomllib.load(f)["workspace"]["package"]["version"])


def test_package_version_is_the_extension_version() -> None:
    assert gyrobias.__version__ == _core.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", gyrobias.__version__), gyrobias.__version__


def test_installed_metadata_has_the_same_version() -> None:
    try:
        installed = version("gyrobias")
    except PackageNotFoundError:  # pragma: no cover - PYTHONPATH=python developer runs
        pytest.skip("gyrobias is not installed (a PYTHONPATH run of scripts/dev-build)")
    assert installed == gyrobias.__version__


def test_command_line_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"gyrobias {gyrobias.__version__}"
    # and through the interpreter, as `python -m gyrobias --version`
    out = subprocess.run(
        [sys.executable, "-m", "gyrobias", "--version"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert out.strip() == f"gyrobias {gyrobias.__version__}"


def test_cargo_workspace_version_is_the_version() -> None:
    assert _cargo_version() == gyrobias.__version__
    # Every crate inherits it: no second version anywhere.
    with _repo_file("pyproject.toml").open("rb") as f:
        project = tomllib.load(f)["project"]
    assert "version" not in project and project["dynamic"] == ["version"]


def test_changelog_latest_release_is_the_version() -> None:
    text = _repo_file("CHANGELOG.md").read_text(encoding="utf-8")
    headings = re.findall(r"^## \[([^\]]+)\](.*)$", text, flags=re.MULTILINE)
    assert headings and headings[0][0] == "Unreleased", "keep '## [Unreleased]' on top"
    released = [(name, rest) for name, rest in headings if name != "Unreleased"]
    assert released, "no released section"
    name, rest = released[0]
    assert name == gyrobias.__version__
    assert re.fullmatch(r" - \d{4}-\d{2}-\d{2}", rest), f"'## [{name}]{rest}' needs ' - YYYY-MM-DD'"
