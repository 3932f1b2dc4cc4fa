"""What the sdist and the wheel built by ``make wheel`` must contain (issue 25 items 1-2).

These tests read ``dist/`` beside ``tests/``: ``make test-wheel`` copies the wheel and the sdist
there with the tests, so they run against the very files CI built (in a source tree without a
``make wheel`` they are skipped). The sdist must build on its own (``make wheel`` builds the
wheel from it): the workspace manifest and the lock file, every crate with every Rust module
its ``lib.rs`` declares, the Python sources (the same files the wheel installs), the licences
and the README. The wheel is one abi3 extension for every CPython >= 3.11 and bundles no
shared library.
"""

from __future__ import annotations

import platform
import re
import tarfile
import tomllib
import zipfile
from email.parser import Parser
from pathlib import Path, PurePosixPath

import pytest

import gyrobias

ROOT = Path(__file__).resolve().parents[1]
DIST = ROOT / "dist"
VERSION = gyrobias.__version__
PREFIX = PurePosixPath(f"gyrobias-{VERSION}")
#: Files of the installed package (the wheel's Python part), relative to the package.
PACKAGE = Path(gyrobias.__file__).resolve().parent
PYTHON_FILES = sorted(
    p.relative_to(PACKAGE).as_posix()
    for p in PACKAGE.rglob("*")
    if p.is_file() and p.suffix in {".py", ".pyi", ".typed"} and "__pycache__" not in p.parts
)


def _sdist() -> tarfile.TarFile:
    path = DIST / f"gyrobias-{VERSION}.tar.gz"
    if not path.is_file():
        pytest.skip(f"no {path.name} in dist/ (run make wheel)")
    return tarfile.open(path)


def _wheel() -> Path:
    found = sorted(DIST.glob(f"gyrobias-{VERSION}-*.whl"))
    if not found:
        pytest.skip("no wheel in dist/ (run make wheel)")
    assert len(found) == 1, found
    return found[0]


def _sdist_files() -> dict[str, bytes]:
    with _sdist() as tar:
        out: dict[str, bytes] = {}
        for member in tar.getmembers():
            if member.isfile():
                f = tar.extractfile(member)
                assert f is not None
                rel = PurePosixPath(member.name).relative_to(PREFIX).as_posix()
                out[rel] = f.read()
        return out


def _rust_modules(files: dict[str, bytes], crate: str) -> set[str]:
    """The source files of ``crate`` its ``mod x;`` declarations require, from ``src/lib.rs``."""
    needed: set[str] = set()
    todo = [f"crates/{crate}/src/lib.rs"]
    while todo:
        path = todo.pop()
        needed.add(path)
        assert path in files, f"sdist lacks {path}"
        text = files[path].decode("utf-8")
        here = PurePosixPath(path)
        # lib.rs and mod.rs own the directory they are in; x.rs owns x/.
        base = here.parent if here.name in ("lib.rs", "mod.rs") else here.with_suffix("")
        # `#[path = "f.rs"] mod x;` (among its other attributes) names its file,
        # relative to the declaring file's directory (the Rust reference, "Module source
        # filenames": path attributes outside inline modules)
        declared = [
            (re.search(r'#\[path\s*=\s*"([^"]+)"\]', attrs), name)
            for attrs, name in re.findall(
                r"((?:^[ \t]*#\[[^\]]*\][ \t]*\n)*)"
                r"^[ \t]*(?:pub(?:\([a-z]+\))?\s+)?mod\s+(\w+)\s*;",
                text,
                re.M,
            )
        ]
        for explicit, name in declared:
            options = (
                [str(here.parent / explicit.group(1))]
                if explicit
                else [str(base / f"{name}.rs"), str(base / name / "mod.rs")]
            )
            present = [o for o in options if o in files]
            assert present, f"sdist lacks module {name} of {path} ({' or '.join(options)})"
            todo.append(present[0])
    return needed


def test_sdist_contains_what_a_build_needs() -> None:
    files = _sdist_files()
    for name in (
        "PKG-INFO",
        "pyproject.toml",
        "Cargo.toml",
        "Cargo.lock",
        "README.md",
        "LICENSE-MIT",
        "LICENSE-APACHE",
        "crates/gyrocore/Cargo.toml",
        "crates/gyrobias-py/Cargo.toml",
    ):
        assert name in files, f"sdist lacks {name}"
    # The workspace it ships names only crates it ships.
    workspace = tomllib.loads(files["Cargo.toml"].decode())
    for member in workspace["workspace"]["members"]:
        assert f"{member}/Cargo.toml" in files, member
    assert workspace["workspace"]["package"]["version"] == VERSION
    # Every Rust module of both crates.
    for crate in ("gyrocore", "gyrobias-py"):
        _rust_modules(files, crate)
    # The Python sources: the very files the wheel installed.
    for rel in PYTHON_FILES:
        assert f"python/gyrobias/{rel}" in files, f"sdist lacks python/gyrobias/{rel}"
    # Metadata: name, version, the light base install.
    meta = Parser().parsestr(files["PKG-INFO"].decode())
    assert meta["Name"] == "gyrobias" and meta["Version"] == VERSION
    base = [r for r in meta.get_all("Requires-Dist", []) if "extra ==" not in r]
    assert sorted(re.split(r"[<>=;\[ ]", r)[0] for r in base) == ["numpy", "ruamel-yaml", "tqdm"]


def test_sdist_lock_file_matches_its_workspace() -> None:
    # `--locked` builds of the sdist need a lock with exactly the shipped crates' packages:
    # `make sdist` prunes the benches' entries (maturin drops the benches crate).
    files = _sdist_files()
    lock = tomllib.loads(files["Cargo.lock"].decode())
    names = {p["name"] for p in lock["package"]}
    assert {"gyrocore", "gyrobias-py", "pyo3", "pulp", "numpy"} <= names
    assert "gyrobias-benches" not in names and "divan" not in names


def test_sdist_builds_for_the_baseline_cpu() -> None:
    # The wheel must run on any CPU of its architecture: nothing in what is built may ask for
    # the build machine's CPU (target-cpu=native) or a fixed feature level; the vector kernels
    # are chosen at run time (tests/test_cpu_dispatch.py).
    for rel, data in _sdist_files().items():
        if rel.endswith((".toml", ".cfg", ".rs", ".py", ".pyi")) or "/.cargo/" in f"/{rel}":
            text = data.decode("utf-8", errors="replace")
            assert "target-cpu" not in text and "target-feature" not in text, rel


def test_sdist_has_no_build_products() -> None:
    for rel in _sdist_files():
        parts = PurePosixPath(rel).parts
        assert not {"target", "build", "dist", ".venv", "__pycache__", ".git"} & set(parts), rel
        assert not rel.endswith((".so", ".pyd", ".dylib", ".dll", ".pyc", ".whl")), rel


def test_wheel_is_one_abi3_extension_and_the_python_sources() -> None:
    wheel = _wheel()
    name = wheel.name
    assert name.startswith(f"gyrobias-{VERSION}-cp311-abi3-"), name
    if platform.system() == "Linux" and platform.machine() == "x86_64":
        assert "manylinux_2_17_x86_64" in name, name
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        wheel_meta = z.read(f"gyrobias-{VERSION}.dist-info/WHEEL").decode()
    assert "Root-Is-Purelib: false" in wheel_meta
    binaries = [n for n in names if n.endswith((".so", ".pyd", ".dylib", ".dll"))]
    assert len(binaries) == 1 and re.fullmatch(r"gyrobias/_core\.(abi3\.so|pyd)", binaries[0])
    # No vendored shared libraries (auditwheel would have added a gyrobias.libs/ directory).
    assert not [n for n in names if ".libs/" in n], names
    package = sorted(n.removeprefix("gyrobias/") for n in names if n.startswith("gyrobias/"))
    assert package == sorted([*PYTHON_FILES, binaries[0].removeprefix("gyrobias/")])
    # Stripped and small: 2.1 MB when this was written; 6 MB would mean debug info crept in.
    assert wheel.stat().st_size < 6_000_000, wheel.stat().st_size


def test_installed_extension_is_the_abi3_build() -> None:
    ext = Path(gyrobias._core.__file__)
    assert ext.parent == PACKAGE
    assert ext.name in ("_core.abi3.so", "_core.pyd"), ext.name
