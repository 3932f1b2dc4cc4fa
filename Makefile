# Common commands of gyrobias (`make help` lists them). Run inside a virtual environment.
# The Rust build cache goes to $CARGO_TARGET_DIR (default: target/).

PYTHON ?= python

.DEFAULT_GOAL := help
.PHONY: help dev build test lint format doc bench ci clean docs perf-page

help: ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F ':.*## ' '{printf "  %-8s %s\n", $$1, $$2}'

dev: ## install gyrobias editable with the test and plot extras, and maturin
	$(PYTHON) -m pip install -U pip maturin
	$(PYTHON) -m pip install -e '.[test,plot]'

build: ## rebuild the extension into python/gyrobias/ after a Rust change (release)
	maturin develop --release -q

test: build ## Rust tests, stub check and every Python test (the README test command)
	cargo test --workspace --locked
	$(PYTHON) -m mypy.stubtest gyrobias._core --allowlist .ci/stubtest-allowlist
	$(PYTHON) -m pytest

lint: ## cargo fmt/clippy/doc, ruff (lint + format check), mypy --strict
	cargo fmt --all --check
	cargo clippy --workspace --all-targets --locked -- -D warnings
	RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked
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
	rm -rf .pytest_cache .mypy_cache .ruff_cache .hypothesis
