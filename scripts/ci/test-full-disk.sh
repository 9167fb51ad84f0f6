#!/usr/bin/env bash
# A full disk, for real: a scan and an atlas write into a small tmpfs
# that fills up at some point of the run (the journal, the HDF5 file or the picture,
# depending on the size). Each failed run must
#   - exit non-zero with the operating system's reason ("No space left on device"),
#   - leave no lock, no partial `<out>.tmp` and no empty or cut picture behind,
# and once the tmpfs is grown (remount keeps its contents) the same command with --resume
# (or a plain rerun, make-like, when no journal is left) must finish, with every
# picture whole, and give the labels of a clean run on a roomy disk.
#
#   scripts/ci/test-full-disk.sh        # needs root (mount); prints "skipped" otherwise
#
# Exit status 0 when every size passes. .ci/run calls it (CI runs as root).
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ "$(id -u)" != 0 ] || ! command -v mount >/dev/null; then
  echo "test-full-disk: skipped (needs root to mount a tmpfs)"
  exit 0
fi
cargo build --release --quiet
bin=$(pwd)/target/release/squeal
work=$(mktemp -d)
mnt=$work/disk
mkdir -p "$mnt"
cleanup() {
  umount "$mnt" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

cat >"$work/scan.toml" <<'EOF'
version = 1
name = "full-disk"
[model]
law = "mcmillan"
nu = [1e-3, 1e-2]
[grid]
x0 = { min = -3.0, max = 5.0, count = 24 }
v0 = { min = -4.0, max = 4.0, count = 24 }
block_rows = 4
[output]
path = "out.h5"
EOF
cat >"$work/atlas.toml" <<'EOF'
version = 1
name = "full-disk-atlas"
[model]
law = "mcmillan"
nu = { from = 1e-3, to = 3e-2, count = 4, spacing = "log" }
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
rtol = 1e-2
[output]
path = "out.h5"
EOF

# PNG whole: the 8-byte signature and an IEND chunk at the end.
png_whole() {
  python3 - "$1" <<'PY'
import sys
b = open(sys.argv[1], "rb").read()
sys.exit(0 if len(b) > 12 and b[:8] == b"\x89PNG\r\n\x1a\n" and b[-8:-4] == b"IEND" else 1)
PY
}

fail=0
checked=0
bad() {
  echo "  FAIL: $*"
  fail=1
}

# Reference labels on a roomy disk.
(cd "$work" && "$bin" scan scan.toml -o ref.h5 --quiet --threads 2 >/dev/null)

for kind in scan atlas; do
  for size in 24k 96k 400k; do
    mount -t tmpfs -o size=$size tmpfs "$mnt"
    set +e
    (cd "$mnt" && "$bin" "$kind" "$work/$kind.toml" -o out.h5 --quiet --threads 2) \
      >"$work/out.txt" 2>"$work/err.txt"
    rc=$?
    set -e
    what="$kind at $size"
    if [ "$rc" = 0 ]; then
      echo "  $what: fitted (nothing to check)"
      umount "$mnt"
      continue
    fi
    checked=$((checked + 1))
    grep -q "No space left on device" "$work/err.txt" ||
      bad "$what: exit $rc without the OS reason: $(tail -n 2 "$work/err.txt")"
    [ ! -e "$mnt/out.h5.lock" ] || bad "$what: lock left behind"
    [ ! -e "$mnt/out.h5.tmp" ] || bad "$what: partial out.h5.tmp left behind"
    for p in "$mnt"/*.png; do
      [ -e "$p" ] || continue
      png_whole "$p" || bad "$what: cut picture $(basename "$p") left behind"
    done
    # Room again: the same run finishes (resume what the journal kept, else start anew).
    mount -o remount,size=50m "$mnt"
    # The journal kept: resume it; none (the file itself was finished before the disk
    # filled, or nothing was started): a plain rerun, which is make-like.
    if [ -s "$mnt/out.h5.journal" ]; then
      again=(--resume)
    else
      again=()
    fi
    (cd "$mnt" && "$bin" "$kind" "$work/$kind.toml" -o out.h5 --quiet --threads 2 "${again[@]}") \
      >/dev/null 2>"$work/err2.txt" || bad "$what: ${again[*]} failed: $(tail -n 2 "$work/err2.txt")"
    for p in "$mnt"/*.png; do
      [ -e "$p" ] || bad "$what: no picture after the rerun"
      png_whole "$p" || bad "$what: picture $(basename "$p") not whole after the rerun"
    done
    if [ "$kind" = scan ] && [ -e "$mnt/out.h5" ]; then
      "$bin" compare "$mnt/out.h5" "$work/ref.h5" --min-agreement 1 >/dev/null ||
        bad "$what: labels differ from the clean run"
    fi
    echo "  $what: failed with the OS reason, nothing partial left, finished after a rerun ${again[*]}"
    umount "$mnt"
  done
done
[ "$checked" -gt 0 ] || bad "no size made a run fail: the test checked nothing"
if [ "$fail" = 0 ]; then
  echo "test-full-disk: $checked full-disk runs, all clean"
else
  echo "test-full-disk: FAILED"
fi
exit "$fail"
