#!/usr/bin/env bash
# Reference long runs for the tests of crates/scan/tests/scanning/edge.rs: ten far starts near the
# fold at Table 1's lambda, tau, phi (hysteretic law, dt 0.005, robust solver, foh) and
# five dampings near the fold, each run to t = 40000 with `squeal trajectory`. The final
# state says how the run ends: at the fixed point (1, 0), or still swinging (its last
# section amplitude). Writes crates/scan/tests/data/edge_long_runs.csv.
#
#   scripts/tools/edge-long-runs.sh [path/to/squeal]     # default: target/release/squeal
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/squeal}
out=crates/scan/tests/data/edge_long_runs.csv
starts="-2.6,0 -4,0 1,3 4,3 -1,-2 3,-3 6,0 -6,2 2,-4 8,1"
{
  echo "nu,x0,v0,t_end,x,v,last_amplitude"
  for nu in 0.0236 0.0240 0.0242 0.0245 0.025; do
    for s in $starts; do
      x0=${s%,*}
      v0=${s#*,}
      # "final state: t = 40000 x = X x' = V ..." and "... section amplitude x' = A at t = ..."
      txt=$("$bin" trajectory --nu "$nu" --x0="$x0" --v0="$v0" --t-end 40000 2>&1)
      x=$(sed -n "s/^final state: .* x = \([^ ]*\) x' = \([^ ]*\) .*/\1/p" <<<"$txt")
      v=$(sed -n "s/^final state: .* x = \([^ ]*\) x' = \([^ ]*\) .*/\2/p" <<<"$txt")
      a=$(sed -n "s/.*section amplitude x' = \([^ ]*\) at .*/\1/p" <<<"$txt")
      echo "$nu,$x0,$v0,40000,$x,$v,${a:-nan}"
    done
  done
} >"$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"
