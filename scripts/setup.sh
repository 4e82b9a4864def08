#!/usr/bin/env bash
# Sets up a virtual environment with physstep installed (builds the Rust engine).
# Usage: bash scripts/setup.sh && .venv/bin/physstep ...
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PHYSSTEP_VENV:-.venv}
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q -e .
