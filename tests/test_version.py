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


def _fake_dist(site: Path, version_text: str, files: list[str]) -> None:
    """A ``gyrobias-<version>.dist-info`` in ``site`` whose RECORD lists ``files``."""
    info = site / f"gyrobias-{version_text}.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: gyrobias\nVersion: {version_text}\n"
    )
    (info / "RECORD").write_text("".join(f"{f},,\n" for f in files))


def _version_from(pythonpath: list[Path], tmp_path: Path) -> tuple[str, set[str]]:
    """``python -m gyrobias --version`` with ``pythonpath`` first: (its output, modules loaded)."""
    import os

    modules = tmp_path / f"modules-{len(list(tmp_path.iterdir()))}.txt"
    wrapper = (
        "import atexit, runpy, sys\n"
        f"atexit.register(lambda: open({str(modules)!r}, 'w').write(' '.join(sys.modules)))\n"
        "sys.argv = ['gyrobias', '--version']\n"
        "runpy.run_module('gyrobias', run_name='__main__', alter_sys=True)\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(str(p) for p in pythonpath)}
    out = subprocess.run(
        [sys.executable, "-c", wrapper], capture_output=True, text=True, env=env, check=True
    ).stdout
    return out.strip(), set(modules.read_text().split())


def test_version_is_the_imported_packages_in_every_layout(tmp_path: Path) -> None:
    """``--version`` names the copy that runs (issue 33): another gyrobias installed on the path
    (here a dist-info claiming 9.9.9 for a package that is not the one imported) is never
    reported, and the metadata of the copy that is imported is. Never NumPy or the core."""
    package = Path(gyrobias.__file__).resolve().parent
    expected = f"gyrobias {gyrobias.__version__}"
    # 1. The package as it is imported here (source tree or installed wheel), with another
    #    installed copy's metadata after it on the path.
    other = tmp_path / "other-site"
    _fake_dist(other, "9.9.9", ["gyrobias/__init__.py"])
    out, loaded = _version_from([package.parent, other], tmp_path)
    assert out == expected
    # 2. An installed copy whose metadata lists its files: that metadata is the version (a
    #    made-up 7.7.7 shows it is read; the copy imports first on the path, before 9.9.9).
    import shutil

    site = tmp_path / "site"
    shutil.copytree(package, site / "gyrobias", ignore=shutil.ignore_patterns("__pycache__"))
    _fake_dist(site, "7.7.7", ["gyrobias/__init__.py", "gyrobias/cli/__init__.py"])
    out, loaded = _version_from([site, other], tmp_path)
    assert out == "gyrobias 7.7.7"
    assert not {"numpy", "gyrobias._core"} & loaded
    # 3. A copy with no metadata of its own and no Cargo.toml beside it (another copy's
    #    metadata on the path): the extension's version.
    bare = tmp_path / "bare"
    shutil.copytree(package, bare / "gyrobias", ignore=shutil.ignore_patterns("__pycache__"))
    out, _ = _version_from([bare, other], tmp_path)
    assert out == expected
