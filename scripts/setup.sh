#!/usr/bin/env bash
# Sets up a virtual environment with physstep installed (builds the Rust engine), showing
# what it builds and the time taken.
# Usage: bash scripts/setup.sh && .venv/bin/physstep ...
# PHYSSTEP_EXTRAS=test,docs installs those extras too (scripts/test.sh does).
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PHYSSTEP_VENV:-.venv}
START=$SECONDS
say() { printf '[setup %3ds] %s\n' "$((SECONDS - START))" "$*"; }
say "virtual environment $VENV"
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q --upgrade pip
TARGET=.
[ -z "${PHYSSTEP_EXTRAS:-}" ] || TARGET=".[${PHYSSTEP_EXTRAS}]"
say "installing physstep (${TARGET}): Python dependencies, then the Rust engine (release build; minutes on a cold cache, seconds after)"
LOG=$(mktemp)
trap 'rm -f "$LOG"' EXIT
# pip -v streams cargo's lines; show the crates being compiled, keep the rest for a failure.
# Byte-compiled at install (not --no-compile, 5 s faster here): where PYTHONDONTWRITEBYTECODE is
# set, as in many containers, Python would otherwise compile every module again in every process
# (the test suite took 100 s instead of 73).
"$VENV/bin/python" -m pip install -v -e "$TARGET" >"$LOG" 2>&1 </dev/null &
PIP=$!
tail -n +1 -f "$LOG" --pid="$PIP" 2>/dev/null | while IFS= read -r line; do
    case "$line" in
        *" Compiling "* | *" Finished "*) say "${line#"${line%%[![:space:]]*}"}" ;;
    esac
done
if ! wait "$PIP"; then
    tail -n 40 "$LOG" >&2
    say "failed (the last lines of the log above)" >&2
    exit 1
fi
say "done: $VENV/bin/physstep"
