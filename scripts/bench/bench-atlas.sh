#!/usr/bin/env bash
# Times the 64 x 64 atlas without maps (scans/atlas-lambda-nu.toml) on 2 worker threads
# (the aim: at most 2 minutes on 2 cores). Prints the machine, its load, and
# wall/user time; user time / 2 is what two free cores would need.
#
#   cargo build --release && scripts/bench/bench-atlas.sh [OUT.h5]
#
# With BASE=path/to/other/squeal it times that binary too, in the same run (base, new,
# base, new when ROUNDS=2), and prints the ratio of their CPU and wall times: the machine
# is shared, so the ratio measured back to back is the figure to trust. SPEC=... times
# another atlas spec.
set -euo pipefail
bin=${SQUEAL:-target/release/squeal}
spec=${SPEC:-scans/atlas-lambda-nu.toml}
out=${1:-${TMPDIR:-/tmp}/squeal-bench-atlas.h5}
rounds=${ROUNDS:-1}
[ -x "$bin" ] || { echo "build first: cargo build --release (or set SQUEAL=...)" >&2; exit 2; }
date -u '+%Y-%m-%d %H:%M UTC'
lscpu | grep 'Model name' || true
echo "cores: $(nproc); spec: $spec"
one() { # label binary -> prints "label wall user"
  local t
  t=$( { /usr/bin/time -f "%e %U" "$2" atlas "$spec" -o "$out" --threads 2 --force \
    --no-render --quiet >/dev/null; } 2>&1 | tail -1)
  echo "$1 $t load=$(cut -d' ' -f1 /proc/loadavg)"
}
res=()
for _ in $(seq "$rounds"); do
  [ -n "${BASE:-}" ] && res+=("$(one base "$BASE")")
  res+=("$(one new "$bin")")
done
printf '%s\n' "${res[@]}" | awk '
  { printf "%-4s wall %7.1f s  user %7.1f s  (load average after: %s)\n", $1, $2, $3, $4
    w[$1] += $2; u[$1] += $3 }
  END { if (w["base"] > 0) printf "ratio new/base: wall %.3f, CPU %.3f\n", w["new"] / w["base"], u["new"] / u["base"] }'
