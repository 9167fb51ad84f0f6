#!/usr/bin/env bash
# Labels of `squeal scan` (early stopping on the located cycle, the default step) against a
# reference run to settlement at a quarter of the step, on the boundary-straddling
# grid of scans/fig9-zoom.toml (the unstable cycle at nu = 1e-3 runs through its middle).
#
#   scripts/bench/agreement.sh            # N = 64: a 64 x 64 grid
#   N=32 scripts/bench/agreement.sh       # quicker
#
# The reference has early_stop = "none", dt / 4 and t_max = 20000 (starts inside the cycle
# spiral in slowly at nu = 1e-3: about 7500 time units to reach fp_radius). Its cost is
# about 1 s of one core per start inside the cycle. Exits 1 when fewer than MIN (default
# 0.999) of the cells agree; `squeal compare` prints the disagreeing starts.
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${N:-64}
min=${MIN:-0.999}
cargo build --release --quiet
bin=target/release/squeal
out=${OUT:-out/agreement}
mkdir -p "$out"
spec=scans/fig9-zoom.toml
dt=$(sed -n 's/^dt = //p' "$spec")
quarter=$(python3 -c "print($dt / 4)")
sed -e "s/count = 256/count = $n/g" -e "s|^path = .*|path = \"$out/scan.h5\"|" "$spec" >"$out/scan.toml"
sed -e "s/^dt = .*/dt = $quarter/" -e 's/^early_stop = .*/early_stop = "none"/' \
  -e 's/^t_max = .*/t_max = 20000.0/' -e "s|^path = .*|path = \"$out/reference.h5\"|" \
  "$out/scan.toml" >"$out/reference.toml"
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(lscpu | grep 'Model name' | sed 's/  */ /g')  cpus: $(nproc)"
"$bin" scan "$out/scan.toml" --force --quiet
"$bin" scan "$out/reference.toml" --force --quiet
"$bin" compare "$out/scan.h5" "$out/reference.h5" --min-agreement "$min"
