#!/usr/bin/env bash
# Fuzzes the command line, the World API and the scene-file parser for a while: the
# property-based tests of tests/test_properties.py and tests/test_scene_fuzz.py in the "long"
# hypothesis profile, and the Rust proptest harness crates/physstep/tests/it/scene_fuzz.rs, round
# after round, each round with a new seed, until the time is up or a property fails.
#
# Usage: bash scripts/fuzz.sh [MINUTES]        (default 10 minutes)
#
#   PHYSSTEP_VENV         the virtual environment (default .venv, with the package and
#                         ".[test]" installed: see scripts/test.sh)
#   PHYSSTEP_FUZZ_SEED    the first round's seed (default: the clock); round k uses SEED + k
#   PHYSSTEP_FUZZ_SCALE   examples per round, as a multiple of the ci profile's (default 20:
#                         a round takes a few minutes)
#   PHYSSTEP_FUZZ_CASES   proptest cases per property per round (default 200000)
#
# Each round's output is in target/fuzz/seed-SEED.log. On a failure the script prints the end
# of the log (the falsifying example, shrunk) and exits 1; rerun that round alone with
#   PHYSSTEP_FUZZ_PROFILE=long PHYSSTEP_FUZZ_SEED=SEED .venv/bin/python -m pytest -q tests/test_properties.py
# then write the example as an xfail case at the end of that file (or fix the bug). A proptest
# failure prints its shrunk input: add it to regressions_stay_fixed in scene_fuzz.rs.
# Exit status 0: the time ran out and every round passed (a round cut short by the time
# limit counts as passed so far).
set -uo pipefail
cd "$(dirname "$0")/.."

MINUTES=${1:-10}
if ! [[ "$MINUTES" =~ ^[0-9]+$ ]] || [ "$MINUTES" -lt 1 ]; then
    echo "usage: bash scripts/fuzz.sh [MINUTES]  (a whole number >= 1, not '$MINUTES')" >&2
    exit 2
fi
VENV=${PHYSSTEP_VENV:-.venv}
PY="$VENV/bin/python"
if [ ! -x "$PY" ]; then
    echo "fuzz: no $PY (set PHYSSTEP_VENV, or run scripts/test.sh once)" >&2
    exit 2
fi
if ! "$PY" -c "import hypothesis" 2>/dev/null; then
    echo "fuzz: hypothesis is not installed in $VENV: $PY -m pip install 'hypothesis>=6'" >&2
    exit 2
fi

seed=${PHYSSTEP_FUZZ_SEED:-$(date +%s)}
if ! [[ "$seed" =~ ^[0-9]+$ ]]; then
    echo "fuzz: PHYSSTEP_FUZZ_SEED must be a whole number, not '$seed'" >&2
    exit 2
fi
end=$(($(date +%s) + MINUTES * 60))
mkdir -p target/fuzz
rounds=0
# The Rust harness, built once (the test profile) before the clock matters.
cargo test -q -p physstep --lib --no-run >/dev/null 2>&1 || {
    echo "fuzz: cargo could not build crates/physstep/tests/it/scene_fuzz.rs" >&2
    exit 2
}

while :; do
    left=$((end - $(date +%s)))
    [ "$left" -gt 0 ] || break
    log="target/fuzz/seed-$seed.log"
    echo "fuzz: round $((rounds + 1)), seed $seed, ${left} s left (log: $log)"
    PROPTEST_RNG_SEED=$seed PHYSSTEP_FUZZ_CASES=${PHYSSTEP_FUZZ_CASES:-200000} \
        timeout --kill-after=10 "$left" \
        cargo test -q -p physstep --lib it::scene_fuzz:: >"$log" 2>&1
    status=$?
    if [ "$status" -eq 0 ]; then
        left=$((end - $(date +%s)))
        [ "$left" -gt 0 ] || break
        PHYSSTEP_FUZZ_PROFILE=long PHYSSTEP_FUZZ_SEED=$seed MPLBACKEND=Agg \
            timeout --kill-after=10 "$left" \
            "$PY" -m pytest -q -p no:cacheprovider tests/test_properties.py tests/test_scene_fuzz.py \
            >>"$log" 2>&1
        status=$?
    fi
    # 124: stopped by the time limit (TERM: the CLI under test takes SIGINT as Ctrl-C), 137: killed
    if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
        echo "fuzz: time is up (round $((rounds + 1)) cut short, no failure so far)"
        break
    fi
    if [ "$status" -ne 0 ]; then
        tail -n 60 "$log"
        echo "fuzz: FAILED in round $((rounds + 1)), seed $seed: see $log" >&2
        exit 1
    fi
    rounds=$((rounds + 1))
    seed=$((seed + 1))
done
echo "fuzz: $rounds whole rounds passed in $MINUTES min"
