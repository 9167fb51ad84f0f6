#!/usr/bin/env bash
# Times the 64 x 64 atlas without maps (scans/atlas-lambda-nu.toml) on 2 worker threads,
# the issue-8 target (at most 2 minutes on 2 cores). Prints the machine, its load, and
# wall/user time; user time / 2 is what two free cores would need.
#
#   cargo build --release && scripts/bench-atlas.sh [OUT.h5]
set -euo pipefail
bin=${SQUEAL:-target/release/squeal}
out=${1:-${TMPDIR:-/tmp}/squeal-bench-atlas.h5}
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=...)" >&2; exit 2; }
date -u '+%Y-%m-%d %H:%M UTC'
lscpu | grep 'Model name' || true
echo "cores: $(nproc); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, cpu %P" \
  "$bin" atlas scans/atlas-lambda-nu.toml -o "$out" --threads 2 --force --no-render --quiet
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
