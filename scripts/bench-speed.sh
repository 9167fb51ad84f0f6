#!/usr/bin/env bash
# Scan speed against the code before issue 7 (BASE, default c44a1a5), ratios measured in one
# run: cells per second of `squeal scan` on 512 x 512 versions of scans/fig9.toml and
# scans/fig9-zoom.toml, 2 threads, alternating old and new runs (ROUNDS of each).
#
# Columns: old = BASE at its defaults (dt = 0.01, zero-order hold); new = this tree at its
# defaults (dt = 0.005, first-order hold: the step chosen for 0.1% accuracy); new@0.01 zoh =
# this tree on the old step and scheme (the per-step speed-up alone).
#
# The old binary is built from a git worktree of BASE in /tmp (kept between runs).
set -euo pipefail
cd "$(dirname "$0")/.."
base=${BASE:-c44a1a5}
rounds=${ROUNDS:-2}
oldtree=/tmp/squeal-bench-$base
old=${OLD_BIN:-$oldtree/target/release/squeal}  # OLD_BIN: an already built binary of BASE
if [ ! -x "$old" ]; then
  [ -d "$oldtree" ] || git worktree add --detach "$oldtree" "$base" >/dev/null
  (cd "$oldtree" && cargo build --release --quiet)
fi
cargo build --release --quiet
new=target/release/squeal
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rate() { "$@" --threads 2 --force --quiet | grep -o '[0-9]* cells/s' | cut -d' ' -f1; }
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(lscpu | grep 'Model name' | sed 's/  */ /g')  cpus: $(nproc)"
echo "| grid (512 x 512, 2 threads) | round | old cells/s | new cells/s | new/old | new@0.01 zoh cells/s | ratio |"
echo "|---|---|---:|---:|---:|---:|---:|"
for s in fig9 fig9-zoom; do
  grid() { sed -e 's/count = 256/count = 512/g' "scans/$s.toml"; }
  grid | sed -e '/^scheme = /d' -e 's/^dt = .*/dt = 0.01/' >"$tmp/old.toml"
  grid >"$tmp/new.toml"
  grid | sed -e 's/^scheme = .*/scheme = "zoh"/' -e 's/^dt = .*/dt = 0.01/' >"$tmp/zoh.toml"
  for i in $(seq "$rounds"); do
    a=$(rate "$old" scan "$tmp/old.toml" -o "$tmp/old.h5")
    b=$(rate "$new" scan "$tmp/new.toml" -o "$tmp/new.h5")
    c=$(rate "$new" scan "$tmp/zoh.toml" -o "$tmp/zoh.h5")
    echo "| $s | $i | $a | $b | $(echo "scale=2; $b / $a" | bc) | $c | $(echo "scale=2; $c / $a" | bc) |"
  done
done
