#!/usr/bin/env bash
# Does the fold's stored uncertainty cover the truth on the shipped chart?
#
# For every belt speed of the chart (scans/atlas-lambda-nu.toml by default), the fold is
# computed again as a whole search, once at dt/2 (`squeal critical --crisis --dt <dt/2>`)
# and once with the longer horizon (`--longer-horizon`: twice the band's samples and
# t_return), over the chart's damping range and rtol. Each gives its own bracket [last value
# where squeal lasts, first value where it is quiet]; the script counts the belt speeds where
# that bracket lies inside the stored `fold_nu -+ fold_nu_err` (and, looser, where its middle
# does).
#
#   scripts/bench/fold-coverage.sh [atlas.h5 [spec.toml]]
#
# Without a file it runs the atlas first (--no-render). Two crisis searches run at a time.
# Prints one line per belt speed and the counts; exits 1 when a bracket is not covered.
set -euo pipefail
cd "$(dirname "$0")/../.."
spec=${2:-scans/atlas-lambda-nu.toml}
squeal=${SQUEAL:-target/release/squeal}
[ -x "$squeal" ] || cargo build --release --quiet
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
file=${1:-}
if [ -z "$file" ]; then
  file=$work/chart.h5
  "$squeal" atlas "$spec" -o "$file" --threads 2 --quiet --no-render >/dev/null
fi
"$squeal" info "$file" --json >"$work/info.json"
# One line per found fold: lambda, tau, phi, dt, nu_lo, nu_hi, rtol, fold, uncertainty.
python3 - "$work/info.json" "$spec" >"$work/folds.txt" <<'EOF'
import json, re, sys
info = json.load(open(sys.argv[1]))
spec = open(sys.argv[2]).read()
m = re.search(r"^\s*rtol\s*=\s*([0-9.eE+-]+)", spec, re.M)
rtol = float(m.group(1)) if m else 1e-3  # the atlas's default [boundaries] rtol
fixed = {k: v["value"] for k, v in info["fixed"].items()}
dt = float(info["attributes"]["dt"])
for b in info["boundaries"]:
    f = b.get("fold", {})
    if f.get("status") != "found" or f.get("uncertainty") is None:
        continue
    lam = b["coords"].get("lambda", fixed.get("lambda"))
    lo, hi = b["nu_range"]
    print(lam, fixed["tau"], fixed["phi"], dt, lo, hi, rtol, f["nu"], f["uncertainty"])
EOF
check() {
  read -r lam tau phi dt lo hi rtol nu err <<<"$1"
  local half out label flags
  half=$(python3 -c "print($dt / 2)")
  for label in dt/2 longer; do
    flags="--dt $half"
    [ "$label" = longer ] && flags="--dt $dt --longer-horizon"
    # shellcheck disable=SC2086
    out=$("$squeal" critical --crisis --lambda "$lam" --tau "$tau" --phi "$phi" $flags \
      --nu-lo "$lo" --nu-hi "$hi" --rtol "$rtol" --json 2>/dev/null || echo '{}')
    python3 -c '
import json, sys
lam, nu, err, how = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
c = json.loads(sys.argv[5])
if "interval" not in c:
    print(f"lambda {lam:.4f} {how}: no crisis found")
    sys.exit()
a, b = c["interval"]
# The file stores the interval as its middle and half-width; rebuilding its ends from them
# rounds by an ulp or so, so ends that agree to 1e-12 (relative) are the same end.
tol = 1e-12 * (nu + err)
if nu - err - tol <= a and b <= nu + err + tol:
    verdict = "covered"
elif nu - err <= 0.5 * (a + b) <= nu + err:
    verdict = "middle covered"
else:
    verdict = "NOT covered"
print(f"lambda {lam:.4f} {how}: [{a:.6f}, {b:.6f}] against {nu:.6f} +- {err:.6f}: {verdict}")
' "$lam" "$nu" "$err" "$label" "$out"
  done
}
export -f check
export squeal
xargs -P 2 -I{} bash -c 'check "$@"' _ {} <"$work/folds.txt" | sort >"$work/lines.txt"
cat "$work/lines.txt"
n=$(wc -l <"$work/folds.txt")
for how in dt/2 longer; do
  all=$(grep -c " $how:" "$work/lines.txt" || true)
  ok=$(grep " $how:" "$work/lines.txt" | grep -c ": covered$" || true)
  mid=$(grep " $how:" "$work/lines.txt" | grep -c "[:e] covered$" || true)
  echo "$how: bracket inside the stored uncertainty at $ok of $all belt speeds ($n folds found); middle inside at $mid"
done
! grep -q "NOT covered\|middle covered\|no crisis" "$work/lines.txt"
