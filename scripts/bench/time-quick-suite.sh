#!/usr/bin/env bash
# Times the README's test command as a newcomer meets it: a fresh clone of this checkout's
# HEAD, no target folder (so the first build compiles HDF5 and every dependency), then
# `cargo test --workspace`. Prints the wall time in all, the build's (cargo's "Finished"
# line), the tests' (the sum of every binary's "finished in"), the tests passed, and the
# load average before and after. Run it on an idle machine; nothing else should build.
#
#   scripts/bench/time-quick-suite.sh            # clone under a temporary folder, removed after
#   KEEP=1 scripts/bench/time-quick-suite.sh     # keep the clone (its path is printed)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
[ -n "${KEEP:-}" ] || trap 'rm -rf "$tmp"' EXIT
git clone --quiet "$repo" "$tmp/squeal"
cd "$tmp/squeal"
echo "revision $(git rev-parse --short HEAD), $(nproc) cores, load before: $(cut -d' ' -f1-3 /proc/loadavg)"
start=$(date +%s.%N)
cargo test --workspace >"$tmp/log" 2>&1 || { tail -40 "$tmp/log"; echo "FAILED (log: $tmp/log)"; exit 1; }
end=$(date +%s.%N)
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
grep -m1 'Finished `test` profile' "$tmp/log" || true
awk -v w="$(echo "$end - $start" | bc)" '
  /^test result:/ {
    for (i = 1; i <= NF; i++) {
      if ($i == "passed;") p += $(i - 1)
      if ($i == "ignored;") g += $(i - 1)
      if ($i == "in") { t = $(i + 1); sub(/s$/, "", t); s += t }
    }
  }
  END { printf "wall %.0f s in all; tests %.0f s (sum of the binaries'"'"' finished in); %d passed, %d ignored\n", w, s, p, g }
' "$tmp/log"
[ -z "${KEEP:-}" ] || echo "clone kept: $tmp/squeal"
