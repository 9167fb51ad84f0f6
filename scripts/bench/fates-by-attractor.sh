#!/usr/bin/env bash
# The speed targets of "fates by attractor" against a base binary, measured in one run on
# this machine (base, new, base, new, ... for ROUNDS rounds; the machine is shared, so only
# ratios measured back to back count):
#   1. the main job, `squeal scan scans/fig9.toml` (256 x 256, its pilot included), and its
#      audit's line (how many audited cells the runs decided);
#   2. bSTAB's 20 belt speeds at 128 x 64 (scans/bstab-friction.toml with those counts);
#   3. the lambda-nu chart (scans/atlas-lambda-nu.toml at N x N points, N = CHART, default
#      16; the shipped 64 x 64 with CHART=64), the gate included, with the atlas's own
#      estimate beside its wall time (the estimate's factor).
#
#   cargo build --release
#   BASE=/path/to/48d225a/squeal ROUNDS=2 scripts/bench/fates-by-attractor.sh
#
# BASE defaults to none (the new binary alone). Outputs go to a temporary folder.
set -euo pipefail
cd "$(dirname "$0")/../.."
new=${SQUEAL:-target/release/squeal}
rounds=${ROUNDS:-1}
chart=${CHART:-16}
[ -x "$new" ] || { echo "build first: cargo build --release (or set SQUEAL=...)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed 's/count = 256 }/count = 128 }/; s/v0 = { min = 0.0, max = 2.0, count = 128 }/v0 = { min = 0.0, max = 2.0, count = 64 }/' \
  scans/bstab-friction.toml > "$tmp/bstab.toml"
sed "s/count = 64,/count = $chart,/g" scans/atlas-lambda-nu.toml > "$tmp/chart.toml"
date -u '+%Y-%m-%d %H:%M UTC'
lscpu | grep 'Model name' || true
echo "cores: $(nproc); rounds: $rounds; chart: $chart x $chart"

# label binary what -> one line: label what wall user [extra]
one() {
  local label=$1 bin=$2 what=$3 log="$tmp/$1-$3.log" extra=""
  local timed=(/usr/bin/time -o "$tmp/time" -f "%e %U")
  case $what in
    fig9) "${timed[@]}" "$bin" scan scans/fig9.toml -o "$tmp/f.h5" --force >"$log" 2>&1
      extra=$(grep -o 'audit (run to settlement) of [0-9]* cells: [0-9]* agree, [0-9]* disagree, [0-9]* undecided' "$log" || true) ;;
    bstab) "${timed[@]}" "$bin" scan "$tmp/bstab.toml" -o "$tmp/b.h5" --force --quiet >"$log" 2>&1 ;;
    chart) "${timed[@]}" "$bin" atlas "$tmp/chart.toml" -o "$tmp/c.h5" --force --no-render >"$log" 2>&1
      extra="estimate: $(grep -o 'roughly [^(]*' "$log" | head -1)" ;;
  esac
  echo "$label $what $(cat "$tmp/time") $extra"
}
for what in fig9 bstab chart; do
  for _ in $(seq "$rounds"); do
    [ -n "${BASE:-}" ] && one base "$BASE" "$what"
    one new "$new" "$what"
  done
done | tee "$tmp/all.txt"
awk '{ w[$1" "$2] += $3; n[$1" "$2]++ }
  END { for (k in w) printf "mean %-12s wall %8.2f s\n", k, w[k] / n[k]
        split("fig9 bstab chart", ws, " ")
        for (i = 1; i <= 3; i++) if (w["base " ws[i]] > 0)
          printf "ratio new/base %-6s %.3f\n", ws[i], w["new " ws[i]] / w["base " ws[i]] }' "$tmp/all.txt"
