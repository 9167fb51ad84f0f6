#!/usr/bin/env bash
# The report pages (`squeal report`) in a real headless browser: writes a scan (Fig. 9), a
# physical scan swept over three dashpots, an atlas with maps and a physical trajectory,
# their reports, and what the files hold at the cells the test looks at (h5py, in a venv);
# then scripts/ci/test-report.mjs opens each page in Debian's chromium through
# playwright-core and checks it. Installs chromium (apt-get, root) and playwright-core
# (npm, into target/report-test) if missing. Screenshots go to target/report-test/artifacts.
# About 2-4 minutes after `cargo build --release`.
#
#   scripts/ci/test-report.sh                 # the four reports
#   BIG=out/atlas-lambda-nu.h5 scripts/ci/test-report.sh   # also time that chart's report
set -euo pipefail
cd "$(dirname "$0")/../.."
here=target/report-test
mkdir -p "$here"
if ! command -v chromium >/dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
if [[ ! -d $here/node_modules/playwright-core ]]; then
    (cd "$here" && npm init -y >/dev/null && npm install --silent --no-audit --no-fund playwright-core@1.65.2)
fi
if [[ ! -x $here/venv/bin/python ]] || ! "$here/venv/bin/python" -c "import h5py" 2>/dev/null; then
    python3 -m venv "$here/venv"
    "$here/venv/bin/pip" install --quiet h5py numpy
fi
cargo build --release --quiet
squeal=$PWD/target/release/squeal
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Fig. 9 as the README makes it; the others small.
sed -e 's#^path = .*#path = "scan.h5"#' scans/fig9.toml > "$work/scan.toml"
sed -e 's#^path = .*#path = "sweep.h5"#' tests/report/physical-sweep.toml > "$work/sweep.toml"
sed -e 's/count = 64/count = 24/g' -e 's/count = 6,/count = 3,/' -e 's#^path = .*#path = "atlas.h5"#' \
    scans/atlas-maps.toml > "$work/atlas.toml"
(
    cd "$work"
    "$squeal" scan scan.toml --quiet >/dev/null
    "$squeal" scan sweep.toml --quiet >/dev/null
    "$squeal" atlas atlas.toml --quiet --no-render >/dev/null
    "$squeal" trajectory --m 0.8 --k 2e5 --c 20 --v-belt 0.3 --mu-k 0.38 --mu-s 0.48 --tau-s 5e-4 \
        --normal-force 1500 --t-end 300 --out trajectory.h5 >/dev/null
    for f in scan sweep atlas trajectory; do "$squeal" report "$f.h5" >/dev/null; done
)
if [[ -n ${BIG:-} ]]; then
    "$squeal" report "$BIG" -o "$work/big.html" --force >/dev/null
fi
"$here/venv/bin/python" scripts/ci/report_expect.py "$work" > "$work/expect.json"
REPORT_TEST_MODULES=$here node scripts/ci/test-report.mjs "$work/expect.json" "$here/artifacts"
