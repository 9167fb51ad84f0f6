#!/usr/bin/env bash
# The fuzz run (tests/e2e/fuzz.rs): shipped specs made small and mutated, hostile
# flag values and input files, each case run by the binary under a time limit; it fails on a
# panic, a silent hang or a lost file. Seeded and bounded in time (about 100 s on 2 cores):
#
#   scripts/ci/fuzz.sh                                   # seed 32, 100 s
#   SQUEAL_FUZZ_SEED=7 SQUEAL_FUZZ_SECONDS=300 scripts/ci/fuzz.sh
#
# Run with `--workspace`, as the quick suite does, so cargo reuses its build.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo test --workspace --test e2e -- --ignored --exact fuzz::fuzz_specs_flags_and_files --nocapture
# The Python door's family: every public function given arguments of the wrong type or
# shape (bool for a number, text, floats for counts, tuples of the wrong length, None, NaN),
# each refused naming the argument (python/tests/test_fuzz.py), in a fresh venv from the wheel.
scripts/ci/test-python.sh -k "wrong_type_or_shape or shape_cases"
