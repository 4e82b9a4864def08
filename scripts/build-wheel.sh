#!/usr/bin/env bash
# Builds physstep's wheel into dist/: one abi3 wheel (CPython 3.11 and later) for this
# platform, which installs without a Rust toolchain: pip install dist/physstep-*.whl
# Usage: bash scripts/build-wheel.sh   (needs Rust; reuses the release build of setup.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PHYSSTEP_VENV:-.venv}
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q "maturin>=1.5,<2"
rm -f dist/physstep-*.whl
"$VENV/bin/maturin" build --release --out dist --interpreter "$VENV/bin/python"
ls dist/physstep-*.whl
