#!/usr/bin/env bash
# Where an atlas run spends its time: samples the run with perf (call stacks) and attributes
# each sample to a phase by the functions on its stack (boundary unit or point; stick-slip
# runs, confirmation runs, cycle searches, dt/2 checks, ...). Shares of samples, both threads.
#
#   cargo build --release && scripts/bench/profile-atlas.sh [SPEC]   (needs perf: apt-get install linux-perf)
set -euo pipefail
bin=${SQUEAL:-target/release/squeal}
spec=${1:-scans/atlas-lambda-nu.toml}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
command -v perf >/dev/null || { echo "perf not found (apt-get install linux-perf)" >&2; exit 2; }
perf record -g --call-graph dwarf,8192 -F "${FREQ:-40}" -o "$tmp/perf.data" \
  "$bin" atlas "$spec" -o "$tmp/out.h5" --threads 2 --force --no-render --quiet >/dev/null 2>"$tmp/err"
perf script -i "$tmp/perf.data" 2>/dev/null > "$tmp/stacks.txt"
python3 - "$tmp/stacks.txt" <<'PY'
import collections, sys
samples, cur = [], []
for line in open(sys.argv[1]):
    if line and not line[0].isspace():
        if cur:
            samples.append(" ".join(cur))
        cur = []
    elif line.strip():
        cur.append(line.strip())
if cur:
    samples.append(" ".join(cur))
# The first key on a sample's stack names its phase (outermost phases last: a confirmation
# run's band search is inside the confirmation, the fold's steps inside the crisis).
phases = [("classifier_for", "confirmation: band search"),
          ("Classifier::classify", "confirmation run (classifier)"), ("stick_slip", "stick-slip runs"),
          ("half_dt_shift", "dt/2 check"), ("describe_bracket", "cycle description"),
          ("clear_above", "fold: samples above its interval"),
          ("widen", "fold: ends at dt/2 and longer horizon"),
          ("bisect_both", "fold: bisections"), ("coarse_changes", "fold: coarse scan"),
          ("raise_top", "fold: raised over the critical damping"),
          ("check_half_dt", "critical damping: dt/2 check"),
          ("bisect_nu", "critical damping: bisection"),
          ("refine", "bracket narrowing"), ("search", "cycle search")]
count = collections.Counter()
for s in samples:
    unit = "boundary" if ("both_in" in s or "both_with" in s or "Evaluator" in s or "Crossings" in s) else ("point" if "compute_point" in s else "other")
    phase = next((name for key, name in phases if key in s), "rest")
    count[(unit, phase)] += 1
n = max(len(samples), 1)
print(f"{len(samples)} samples")
for (unit, phase), k in count.most_common():
    print(f"{unit:>8}  {phase:<40} {100 * k / n:5.1f}%")
PY
