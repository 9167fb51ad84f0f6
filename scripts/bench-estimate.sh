#!/usr/bin/env bash
# Checks `squeal scan`'s time estimate (the pilot of crates/scan/src/estimate.rs) against
# the measured wall time of shipped specs: each must lie within a factor 2 of the other.
# Prints one row per spec (estimate, measured, ratio) and exits 1 if any is outside.
#
#   scripts/bench-estimate.sh                       # the quick specs
#   scripts/bench-estimate.sh scans/bstab-friction.toml scans/nu-sweep.toml   # any specs
#
# Needs target/release/squeal (cargo build --release). Run on an otherwise idle machine:
# the pilot and the scan then see the same speed. Results: BENCHMARKS.md, "Scan time
# estimates".
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/squeal
[ -x "$bin" ] || { echo "build first: cargo build --release" >&2; exit 2; }
specs=("$@")
[ ${#specs[@]} -gt 0 ] || specs=(scans/fig9.toml scans/fig10.toml scans/fig11.toml scans/fig9-zoom.toml scans/nu-sweep.toml)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# $(date -u +%Y-%m-%dT%H:%MZ) $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
printf '%-28s %12s %12s %8s\n' spec estimate_s measured_s ratio
fail=0
for spec in "${specs[@]}"; do
  name=$(basename "$spec" .toml)
  start=$(date +%s.%N)
  "$bin" scan "$spec" -o "$tmp/$name.h5" --force --threads 2 --allow-long 2>"$tmp/$name.err" >/dev/null
  end=$(date +%s.%N)
  est=$(sed -n 's/.*roughly [^(]*(\([0-9.]*\) s).*/\1/p' "$tmp/$name.err" | head -1)
  wall=$(echo "$end - $start" | bc -l)
  ratio=$(echo "$wall / $est" | bc -l)
  ok=$(echo "$ratio >= 0.5 && $ratio <= 2" | bc -l)
  [ "$ok" = 1 ] || fail=1
  printf '%-28s %12.1f %12.1f %8.2f%s\n' "$name" "$est" "$wall" "$ratio" "$([ "$ok" = 1 ] || echo '  OUTSIDE 2x')"
done
exit $fail
