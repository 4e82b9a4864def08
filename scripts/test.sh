#!/usr/bin/env bash
# Sets up a virtual environment and runs every test: cargo (engine) and pytest (Python face),
# plus the lint and stub checks that keep the tree clean. Usage: bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PHYSSTEP_VENV:-.venv}
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q -e ".[test,distributed,demo,docs]"
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace --exclude physstep-py
RUSTDOCFLAGS="-D warnings" cargo doc -q -p physstep --no-deps
cargo run -q -p physstep --example custom_force
"$VENV/bin/ruff" check python tests scripts bench examples
"$VENV/bin/ruff" format --check python tests scripts bench examples
"$VENV/bin/python" -m mypy.stubtest physstep._core
for example in examples/*.py; do MPLBACKEND=Agg "$VENV/bin/python" "$example" >/dev/null; done
MPLBACKEND=Agg "$VENV/bin/python" -m pytest -q
# The documentation site: a broken link or anchor, a README section gone or a missing docstring
# fails it (not --quiet: mkdocs then drops the warnings that --strict counts).
SITE=$(mktemp -d)
trap 'rm -rf "$SITE"' EXIT
NO_MKDOCS_2_WARNING=1 "$VENV/bin/mkdocs" build --strict --site-dir "$SITE"
