#!/usr/bin/env bash
# Sets up a virtual environment and runs every test: cargo (engine) and pytest (Python face),
# plus the lint and stub checks that keep the tree clean. Usage: bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PHYSSTEP_VENV:-.venv}
START=$SECONDS
stage() { printf '[test %4ds] %s\n' "$((SECONDS - START))" "$*"; }
PHYSSTEP_EXTRAS=test,distributed,demo,docs bash scripts/setup.sh
stage "rustfmt, clippy"
cargo fmt --all --check
# --all-targets: every target is checked here, also those `cargo test` below does not build
# (the examples' programs, the criterion benchmarks in crates/physstep-bench).
cargo clippy --workspace --all-targets -- -D warnings
stage "cargo test (the test profile: the engine's one test harness)"
# Only what is run: the engine (-p, not the workspace: not the benchmarks' crate, nor criterion)
# in its library's test harness, which holds every test of the engine: the unit tests, those of
# tests/it, the examples' runs (src/lib.rs: the engine compiled once). The doc examples are
# example programs (clippy checked them, tests/it/examples.rs runs the quick start).
cargo test -p physstep --lib
stage "cargo doc"
RUSTDOCFLAGS="-D warnings" cargo doc -q -p physstep --no-deps
# The wheel a user without Rust installs: built from the same release build, installed into a
# new venv with no toolchain on PATH, the quick-start table and a smoke test run from it.
stage "the wheel, installed in a new venv without Rust"
bash scripts/build-wheel.sh >/dev/null
bash scripts/check-wheel.sh
stage "ruff, stubtest, mypy, the examples"
"$VENV/bin/ruff" check python tests scripts bench examples build_backend
"$VENV/bin/ruff" format --check python tests scripts bench examples build_backend
"$VENV/bin/python" -m mypy.stubtest physstep._core
"$VENV/bin/python" -m mypy python/physstep
# An example that calls a deprecated physstep API fails (the warning is raised in the example).
for example in examples/*.py; do MPLBACKEND=Agg "$VENV/bin/python" -W error::DeprecationWarning:__main__ "$example" >/dev/null; done
stage "pytest"
# Across the cores (pytest-xdist), a module's tests on one worker so its fixtures are made once.
MPLBACKEND=Agg "$VENV/bin/python" -m pytest -q -n auto --dist loadscope
# The documentation site: a broken link or anchor, a README section gone or a missing docstring
# fails it (not --quiet: mkdocs then drops the warnings that --strict counts).
stage "the documentation site (mkdocs --strict)"
SITE=$(mktemp -d)
trap 'rm -rf "$SITE"' EXIT
NO_MKDOCS_2_WARNING=1 "$VENV/bin/mkdocs" build --strict --site-dir "$SITE"
stage "all passed"
