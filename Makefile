# Common commands of gyrobias (`make help` lists them). Run inside a virtual environment.
# The Rust build cache goes to $CARGO_TARGET_DIR (default: target/).

PYTHON ?= python
# The one version: [workspace.package] of Cargo.toml (maturin gives it to the wheel and the sdist).
VERSION := $(shell sed -n '/^\[workspace.package\]/,/^\[/s/^version = "\(.*\)"/\1/p' Cargo.toml)
DIST ?= dist
MATURIN ?= maturin
# Linux wheels: zig links against glibc 2.17 (manylinux2014), no Docker needed; elsewhere native.
ifeq ($(shell uname -s),Linux)
WHEEL_FLAGS ?= --zig --compatibility manylinux2014
else
WHEEL_FLAGS ?=
endif

.DEFAULT_GOAL := help
.PHONY: help dev build test lint lint-python format doc bench ci clean build-tools sdist wheel \
	test-wheel actionlint version docs perf-page

help: ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F ':.*## ' '{printf "  %-11s %s\n", $$1, $$2}'

dev: ## install gyrobias editable with the test and plot extras, and maturin
	$(PYTHON) -m pip install -U pip maturin
	$(PYTHON) -m pip install -e '.[test,plot]'

build: ## rebuild the extension into python/gyrobias/ after a Rust change (release)
	maturin develop --release -q

test: build ## source tree: Rust tests, stub check, every Python test (CI tests the wheel)
	cargo test --workspace --locked
	$(PYTHON) -m mypy.stubtest gyrobias._core --allowlist .ci/stubtest-allowlist
	$(PYTHON) -m pytest

lint: ## cargo fmt/clippy/doc, ruff (lint + format check), mypy --strict
	cargo fmt --all --check
	cargo clippy --workspace --all-targets --locked -- -D warnings
	RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked
	$(MAKE) lint-python

lint-python: ## ruff (lint + format check) and mypy --strict only (needs the test extras)
	$(PYTHON) -m ruff check python tests benches
	$(PYTHON) -m ruff format --check python tests benches
	$(PYTHON) -m mypy --strict python/gyrobias

format: ## apply cargo fmt, ruff --fix and ruff format
	cargo fmt --all
	$(PYTHON) -m ruff check --fix python tests benches
	$(PYTHON) -m ruff format python tests benches

doc: ## Rust API docs (target/doc/gyrocore/index.html)
	RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked

bench: build ## Rust (divan) and Python benchmarks; ratios against same-run baselines (needs .[bench])
	cargo bench -p gyrobias-benches --locked
	for f in benches/python/bench_*.py; do echo "== $$f"; $(PYTHON) $$f || exit 1; done

version: ## print the version (Cargo.toml's [workspace.package], the one place it is set)
	@echo $(VERSION)

build-tools: ## install the pinned wheel build tools (maturin, ziglang) into $(PYTHON)
	$(PYTHON) -m pip install -q -r .ci/requirements-build.txt

sdist: build-tools ## the source distribution dist/gyrobias-<version>.tar.gz
	rm -f $(DIST)/gyrobias-*.tar.gz
	$(MATURIN) sdist --out $(DIST)
	@# maturin drops the benches crate from the sdist's workspace but ships the whole Cargo.lock,
	@# which `--locked` (pyproject's locked = true) then refuses as out of date: prune it to the
	@# shipped crates (cargo only removes the benches' entries, offline) and repack.
	rm -rf build/sdist-lock && mkdir -p build/sdist-lock
	tar -xzf $(DIST)/gyrobias-$(VERSION).tar.gz -C build/sdist-lock
	cd build/sdist-lock/gyrobias-$(VERSION) && cargo metadata --offline --format-version 1 >/dev/null
	tar -czf $(DIST)/gyrobias-$(VERSION).tar.gz -C build/sdist-lock gyrobias-$(VERSION)
	rm -rf build/sdist-lock

wheel: sdist ## the abi3 wheel (manylinux2014 on Linux), built from the sdist, into dist/
	rm -rf build/sdist $(DIST)/gyrobias-*.whl
	mkdir -p build/sdist
	@# -m: fresh mtimes, or cargo would take the unpacked sources for older than its last build
	tar -xzmf $(DIST)/gyrobias-$(VERSION).tar.gz -C build/sdist
	@# The checkout's target dir (unless CARGO_TARGET_DIR says otherwise): rebuilds are incremental.
	cd build/sdist/gyrobias-$(VERSION) && CARGO_TARGET_DIR="$${CARGO_TARGET_DIR:-$(CURDIR)/target}" \
		$(MATURIN) build --release --locked $(WHEEL_FLAGS) --out $(CURDIR)/$(DIST)
	@ls -l $(DIST)/gyrobias-$(VERSION)-*.whl

test-wheel: ## install dist/'s wheel in a fresh venv without Rust; every test + gyrobias demo
	bash scripts/test-wheel

actionlint: ## check the GitHub workflows with actionlint (pinned, installed from PyPI)
	$(PYTHON) -m pip install -q --require-hashes -r .ci/requirements-actionlint.txt
	"$$($(PYTHON) -c 'import sysconfig; print(sysconfig.get_path("scripts"))')/actionlint" \
		.github/workflows/*.yml

# --- documentation site (docs/; owned by the docs engineer)
docs: ## build the docs site (docs/_build/html): warnings are errors, every example executed
	$(PYTHON) -m sphinx -W --keep-going -b html -j 1 docs docs/_build/html

perf-page: ## regenerate docs/performance.md from quick runs of the benchmarks (commit the result)
	$(PYTHON) docs/_tools/perf_page.py

ci: ## what CI runs, from this checkout
	bash .ci/run

clean: ## remove build products (the Rust target dir, the built extension, caches)
	cargo clean
	rm -f python/gyrobias/_core.*.so
	rm -rf .pytest_cache .mypy_cache .ruff_cache .hypothesis build $(DIST)
