#!/usr/bin/env bash
# Every HDF5 dataset and attribute written by the shipped specs, compared between a revision
# REV and this working tree: does a change alter anything users see?
#
#   scripts/tools/same-results.sh 6685246                    # builds REV in a worktree under target/
#   OLD_BIN=path/to/squeal scripts/tools/same-results.sh REV  # an already built binary of REV
#   COUNT=12 SWEEP=4 scripts/tools/same-results.sh REV        # reduction (defaults 16 and 5)
#   LABELS=1 COUNT=64 SWEEP=100 scripts/tools/same-results.sh REV   # labels only, cell by cell
#   SPECS="scans/fig9.toml scans/fig10.toml" scripts/tools/same-results.sh REV   # these specs only
#   WORK=target/same-results/run2 scripts/tools/same-results.sh REV   # another folder, so runs go side by side
#
# With LABELS=1 only the scan specs run (not the atlases), and each pair of files is
# compared cell by cell with `squeal compare` instead of bit for bit: the check that an
# early decision changed no label, where reasons and counters are expected to
# move. A spec the old binary refuses (a table newer than it) is skipped and said so.
# Each spec in scans/ is run by both binaries with its counts reduced (a grid or sample
# count above COUNT becomes COUNT, a swept axis above SWEEP points becomes SWEEP, `n = ` of a
# random sample likewise COUNT^2), with `--threads 2`, into two folders; then
# scripts/tools/h5_same.py compares the files: the same datasets and attributes with the same
# types, shapes and values (bit for bit; NaN equals NaN). Provenance (software version, git
# revision, creation time) is expected to differ and is listed apart. Exits 1 on any other
# difference. Needs h5py and numpy: installed once into target/py-tools if missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
rev=${1:?usage: scripts/tools/same-results.sh REV}
count=${COUNT:-16}
sweep=${SWEEP:-5}
root=$(pwd)
oldtree=$root/target/same-results/tree-$rev
old=${OLD_BIN:-$oldtree/target/release/squeal}
if [ ! -x "$old" ]; then
  [ -d "$oldtree" ] || git worktree add --detach "$oldtree" "$rev" >/dev/null
  (cd "$oldtree" && cargo build --release --quiet)
fi
cargo build --release --quiet
new=$root/target/release/squeal
py=python3
if ! python3 -c 'import h5py, numpy' 2>/dev/null; then
  venv=$root/target/py-tools
  [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
  "$venv/bin/python" -c 'import h5py, numpy' 2>/dev/null ||
    "$venv/bin/python" -m pip install --quiet h5py numpy
  py=$venv/bin/python
fi
work=$root/${WORK:-target/same-results/run}
rm -rf "$work"
mkdir -p "$work/old" "$work/new" "$work/specs"
# Specs name their data (a friction CSV) relative to their folder, scans/.
ln -s "$root/scans/data" "$work/specs/data"
status=0
echo "same-results: $rev ($old) against the working tree ($new); counts <= $count, sweeps <= $sweep"
for spec in ${SPECS:-scans/*.toml}; do
  name=$(basename "$spec" .toml)
  small=$work/specs/$name.toml
  # Grid/sample counts (inline tables with min/max) and swept axes (from/to) are reduced
  # separately, so a 20-speed sweep keeps 5 speeds while its grid keeps 16 x 16 cells.
  sed -E -e "/from *=/ s/count *= *([0-9]+)/count = __S\1__/" \
    -e "s/count *= *([0-9]+)/count = __C\1__/" \
    -e "s/^n *= *([0-9]+)/n = __N\1__/" "$spec" |
    COUNT=$count SWEEP=$sweep perl -pe '
      s/__S(\d+)__/$1 > $ENV{SWEEP} ? $ENV{SWEEP} : $1/ge;
      s/__C(\d+)__/$1 > $ENV{COUNT} ? $ENV{COUNT} : $1/ge;
      s/__N(\d+)__/$1 > $ENV{COUNT}**2 ? $ENV{COUNT}**2 : $1/ge;' >"$small"
  cmd=scan
  grep -q '^\[grid\]\|^\[sample\]' "$small" || cmd=atlas
  case "$name" in atlas-*) cmd=atlas ;; esac
  [ "${LABELS:-0}" = 1 ] && [ "$cmd" = atlas ] && continue
  for side in old new; do
    bin=$old
    [ "$side" = new ] && bin=$new
    if ! (cd "$work/$side" && "$bin" "$cmd" "$small" -o "$name.h5" --threads 2 --quiet \
      >"$name.log" 2>&1); then
      if [ "${LABELS:-0}" = 1 ] && [ "$side" = old ]; then
        echo "  $name: the old binary refuses it ($(head -1 "$work/old/$name.log")), skipped"
        rm -f "$work/old/$name.h5"
        continue 2
      fi
      echo "  $name: $side run failed (see $work/$side/$name.log)"
      status=1
    fi
  done
  if [ ! -f "$work/old/$name.h5" ] || [ ! -f "$work/new/$name.h5" ]; then
    continue
  elif [ "${LABELS:-0}" = 1 ]; then
    echo "  $name:"
    "$new" compare "$work/new/$name.h5" "$work/old/$name.h5" | grep -v ' against ' | sed 's/^ */    /' |
      tee "$work/$name.compare"
    ! grep -qE '[1-9][0-9]* disagree' "$work/$name.compare" || status=1
  else
    "$py" scripts/tools/h5_same.py "$work/old/$name.h5" "$work/new/$name.h5" --label "$name" || status=1
  fi
done
if [ "${LABELS:-0}" = 1 ]; then
  [ "$status" = 0 ] && echo "same-results: every label equal" || echo "same-results: LABELS DIFFER (above)"
else
  [ "$status" = 0 ] && echo "same-results: every dataset and attribute equal" || echo "same-results: DIFFERENCES (above)"
fi
exit "$status"
