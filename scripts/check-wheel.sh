#!/usr/bin/env bash
# Installs the wheel in dist/ into a new virtual environment with no Rust toolchain on PATH
# and runs the README's quick-start table and a smoke test from it: what a user of the wheel
# gets. Usage: bash scripts/check-wheel.sh  (after scripts/build-wheel.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
shopt -s nullglob
WHEELS=(dist/physstep-*.whl)
if [ ${#WHEELS[@]} -ne 1 ]; then
    echo "check-wheel: expected one wheel in dist/, found ${#WHEELS[@]}: run bash scripts/build-wheel.sh first" >&2
    exit 2
fi
WHEEL=${WHEELS[0]}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
python3 -m venv "$TMP/venv"
# PATH without cargo or rustc: the wheel must not need them.
CLEAN_PATH=$(printf '%s' "$PATH" | tr ':' '\n' | while read -r d; do
    [ -x "$d/cargo" ] || [ -x "$d/rustc" ] || printf '%s:' "$d"
done)
export PATH="$TMP/venv/bin:${CLEAN_PATH%:}"
if command -v cargo >/dev/null || command -v rustc >/dev/null; then
    echo "check-wheel: a Rust toolchain is still on PATH" >&2
    exit 1
fi
# --no-compile: this venv runs two programs and is deleted (4-5 s less; scripts/setup.sh says
# why a venv that is used byte-compiles at install).
"$TMP/venv/bin/python" -m pip install -q --no-compile "$WHEEL"
cd "$TMP"   # not the checkout: the installed package, not python/physstep, is imported
physstep table spring --method symplectic-euler --dt 1 --until 17 >table.txt
head -4 table.txt
grep -q -- "-5.0  -15.0    2.5" table.txt || { echo "check-wheel: not the notes' table" >&2; exit 1; }
python - <<'PY'
import numpy as np
import physstep

w = physstep.World(3, method="velocity-verlet", dt=0.01)
w.add_particles(np.zeros((2, 3)), np.array([[1.0, 0, 0], [0, 1.0, 0]]), np.ones(2))
w.add_gravity([0.0, 0.0, -9.81])
w.step(100)
assert abs(w.positions[0, 2] + 0.5 * 9.81) < 1e-9, w.positions
print("wheel smoke test: ok,", physstep.__file__)
PY
