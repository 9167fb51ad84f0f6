#!/usr/bin/env bash
# Early stopping's margin (classifier.trap_margin) against time and labels: the 512 x 512
# version of scans/fig9-zoom.toml (the unstable cycle at nu = 1e-3 through its middle) at
# trap_margin = 1e-3, 1e-4, 1e-5 (the default), 1e-6, audit off, 2 threads. Prints each
# run's rate and label counts, and `squeal compare` of each against the default's labels.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
bin=target/release/squeal
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(lscpu | grep 'Model name' | sed 's/  */ /g')  cpus: $(nproc)  load: $(cut -d' ' -f1-3 /proc/loadavg)"
for m in 1e-5 1e-3 1e-4 1e-6; do
  sed -e 's/count = 256/count = 512/g' \
    -e "s/^early_stop = \"cycle\"/early_stop = \"cycle\"\ntrap_margin = $m\naudit_every = 0/" \
    scans/fig9-zoom.toml >"$tmp/$m.toml"
  echo "trap_margin = $m:"
  "$bin" scan "$tmp/$m.toml" -o "$tmp/$m.h5" --threads 2 --force --quiet | grep -E 'steady_slip|wrong side|cells/s'
  [ "$m" = 1e-5 ] || "$bin" compare "$tmp/$m.h5" "$tmp/1e-5.h5" | sed -n 2p
done
