#!/usr/bin/env bash
# Checks the patches of docs/extending.md against this tree: each still applies
# (`git apply --check`) and touches at most 3 source files outside tests and docs (a path
# with a `tests/` folder or a `tests.rs` file, and `*.md`, are not counted, as in
# docs/extending.md). Prints one line a patch and exits 1 if any fails. It does not build:
# docs/extending.md says how each patch was built and run.
#
#   scripts/ci/check-extending.sh
#
# The `*-c5db8c1.patch` files are the same changes as made on main at c5db8c1, kept for
# the record: they apply to that tree only and are not checked. Run it on a clean tree: an
# uncommitted edit to a file a patch touches can make it fail to apply.
set -euo pipefail
cd "$(dirname "$0")/../.."
MAX_SOURCE_FILES=3
status=0
for patch in docs/extending/*.patch; do
    case $patch in *-c5db8c1.patch) continue ;; esac
    if ! why=$(git apply --check "$patch" 2>&1); then
        echo "$patch: does not apply to this tree; make it again (docs/extending.md):"
        echo "$why" | sed 's/^/    /'
        status=1
        continue
    fi
    sources=$(git apply --numstat "$patch" | cut -f3 |
        grep -vE '(^|/)tests(/|\.rs$)|\.md$' || true)
    count=$(printf '%s' "$sources" | grep -c . || true)
    if [ "$count" -gt "$MAX_SOURCE_FILES" ]; then
        echo "$patch: applies, but touches $count source files (at most $MAX_SOURCE_FILES):"
        echo "$sources" | sed 's/^/    /'
        status=1
    else
        echo "$patch: applies; $count source file(s):" $sources
    fi
done
exit $status
