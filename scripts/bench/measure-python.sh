#!/usr/bin/env bash
# The numbers docs/python.md states for the Python package: the wheel's size, and the time of
# `import squeal` in a fresh venv (median of 7 runs, each a new interpreter; xarray is
# imported on first use, timed separately). Builds the wheel (scripts/tools/build-wheel.sh)
# unless one is given.
#   scripts/bench/measure-python.sh [WHEEL]
set -euo pipefail
cd "$(dirname "$0")/../.."
wheel=${1:-$(scripts/tools/build-wheel.sh)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install --quiet "$wheel"
py=$work/venv/bin/python
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_of() {
    for _ in 1 2 3 4 5 6 7; do
        "$py" -c "import time; t = time.perf_counter(); import $1; print(time.perf_counter() - t)"
    done | median
}
printf 'wheel: %s, %.1f MB\n' "$(basename "$wheel")" "$(stat -c %s "$wheel" | awk '{print $1 / 1e6}')"
printf 'import squeal: %.3f s (median of 7)\n' "$(time_of squeal)"
printf 'import xarray (on first use of a Dataset): %.3f s (median of 7)\n' "$(time_of xarray)"
