#!/usr/bin/env bash
# Labels of every shipped scan spec (scans/*.toml except the atlases), an old binary against
# this tree, compared cell by cell with `squeal compare`: the early decisions of issue 18
# must not change a label. OLD_BIN: the old binary (required); COUNT: grid points per axis
# (default: each spec's own grid). Prints one line per map with differences, or "agree".
#
#   OLD_BIN=path/to/squeal-6685246 COUNT=64 scripts/same-labels.sh
set -euo pipefail
cd "$(dirname "$0")/.."
old=${OLD_BIN:?set OLD_BIN to the old squeal binary}
cargo build --release --quiet
new=target/release/squeal
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  load: $(cut -d' ' -f1-3 /proc/loadavg)  count: ${COUNT:-spec}"
for spec in scans/*.toml; do
  name=$(basename "$spec" .toml)
  case $name in atlas-*) continue ;; esac
  # An atlas spec without the prefix (scans/brake.toml): neither [grid] nor [sample].
  grep -qE "^\[(grid|sample)\]" "$spec" || continue
  if [ -n "${COUNT:-}" ]; then
    sed -E "/^(x0|v0) = /s/count = [0-9]+/count = $COUNT/" "$spec" >"$tmp/$name.toml"
  else
    cp "$spec" "$tmp/$name.toml"
  fi
  if ! "$old" scan "$tmp/$name.toml" -o "$tmp/$name-old.h5" --threads 2 --force --quiet \
    >/dev/null 2>"$tmp/err"; then
    # A spec newer than the old binary (e.g. a table it does not know): nothing to compare.
    echo "== $name: the old binary refuses it ($(head -1 "$tmp/err")), skipped"
    continue
  fi
  "$new" scan "$tmp/$name.toml" -o "$tmp/$name-new.h5" --threads 2 --force --quiet >/dev/null
  echo "== $name"
  "$new" compare "$tmp/$name-new.h5" "$tmp/$name-old.h5" | grep -v ' against '
done
