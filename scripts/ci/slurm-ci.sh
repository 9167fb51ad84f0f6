#!/usr/bin/env bash
# A real single-node SLURM cluster for CI: runs a sharded scan through scripts/tools/slurm-array.sh,
# (and then a small 2-shard atlas whose merged file must hold a single run's content),
# stops one array task mid-run and puts it back in the queue (`scontrol requeue`: SIGTERM,
# then SIGKILL after KillWait, as at a preemption), checks that it resumed (the blocks in
# its journal were kept and not computed again) and that the merged file holds the same
# data as a single run. Run as root on Debian bookworm (no systemd needed):
#
#   scripts/ci/slurm-ci.sh            # SQUEAL=/path/to/squeal to skip `cargo build --release`
#
# Installs slurm-wlm (22.05) and munge with apt-get if they are missing. Everything else
# (munge key and socket, slurm.conf, state, spool, logs, the scan) lives in a fresh folder
# under /tmp, removed on success and kept (its path printed) on failure. The daemons it
# starts (munged, slurmctld, slurmd) are stopped by their PIDs on exit, whatever happens.
# Ports: SLURM_CI_PORT (default 16817) for slurmctld and the next one for slurmd.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
say() { printf '[slurm-ci %(%H:%M:%S)T] %s\n' -1 "$*"; }
die() {
  say "FAIL: $*" >&2
  exit 1
}
[ "$(id -u)" = 0 ] || die "run as root (the daemons run as SlurmUser=root)"
started=$(date +%s)

# --- packages ---------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null ||
  ! command -v sbatch >/dev/null || ! command -v munged >/dev/null ||
  ! command -v python3 >/dev/null; then
  say "installing slurm-wlm, munge and python3 (reads the journal)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends slurm-wlm munge python3
fi
say "$(slurmctld -V), munge $(munged -V 2>&1 | awk '{print $2; exit}')"

# --- the squeal binary ------------------------------------------------------------------
bin=${SQUEAL:-$repo/target/release/squeal}
if [ -z "${SQUEAL:-}" ]; then
  say "cargo build --release --bin squeal"
  (cd "$repo" && cargo build --release --bin squeal --quiet)
fi
[ -x "$bin" ] || die "no squeal binary at $bin"
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")

# --- cleanup: stop what we started, by PID ----------------------------------------------
work=$(mktemp -d /tmp/squeal-slurm-ci.XXXXXX)
pids=()
jobs_started=()
ok=0
cleanup() {
  local rc=$?
  set +e
  if [ ${#jobs_started[@]} -gt 0 ] && [ -n "${SLURM_CONF:-}" ]; then
    scancel "${jobs_started[@]}" 2>/dev/null
    sleep 1
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill -TERM "${pids[i]}" 2>/dev/null
  done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do
      kill -0 "$p" 2>/dev/null || break
      sleep 0.1
    done
    kill -KILL "$p" 2>/dev/null
    wait "$p" 2>/dev/null
  done
  if [ "$ok" = 1 ]; then
    rm -rf "$work"
  else
    say "kept $work for inspection (logs/, *.log)" >&2
    for f in "$work"/slurmctld.log "$work"/slurmd.log "$work"/run/logs/*; do
      [ -f "$f" ] && { echo "==== $f"; tail -n 30 "$f"; } >&2
    done
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# --- munge --------------------------------------------------------------------------------
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/run"
chmod 755 "$work/munge" # munged wants its socket folder searchable by all
mungekey --create --keyfile="$work/munge/munge.key" --force
sock=$work/munge/munge.socket
munged --foreground --force --key-file="$work/munge/munge.key" --socket="$sock" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" \
  --log-file="$work/munge/munged.log" >>"$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do
  [ -S "$sock" ] && break
  sleep 0.1
done
munge --socket="$sock" -n | unmunge --socket="$sock" >/dev/null || die "munge does not work"
say "munged running (pid ${pids[0]})"

# --- slurm.conf ---------------------------------------------------------------------------
host=$(hostname -s)
node=$(slurmd -C | head -n 1) # NodeName=... CPUs=... RealMemory=... from this machine
case $node in NodeName=*) ;; *) die "slurmd -C printed: $node" ;; esac
port=${SLURM_CI_PORT:-16817}
export SLURM_CONF=$work/slurm.conf
: >"$work/plugstack.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=squealci
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock,cred_expire=10
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
PlugStackConfig=$work/plugstack.conf
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ReturnToService=2
JobRequeue=1
KillWait=5
MinJobAge=600
SchedulerType=sched/backfill
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
sed -i 's/ UpTime=[^ ]*//' "$SLURM_CONF"
# cred_expire: a requeued job may start again only after its credential expires (120 s by
# default), which would be most of this script's run time.

slurmctld -D -i -f "$SLURM_CONF" >>"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$host" -f "$SLURM_CONF" >>"$work/slurmd.out" 2>&1 &
pids+=($!)
say "slurmctld (pid ${pids[1]}) and slurmd (pid ${pids[2]}) started; waiting for the node"
state=
for _ in $(seq 120); do
  state=$(sinfo -h -n "$host" -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || die "node state '$state' after 60 s"
say "cluster up: $(sinfo -h -o '%P %D %c CPUs %m MB %T')"

# --- the scan: 2 shards through slurm-array.sh --------------------------------------------
# 64 x 64 cells of paper Fig. 9's model, run to settlement (early_stop = none) so each of the
# 16 blocks takes seconds: time to kill a task between blocks.
cd "$work/run"
cat >ci.toml <<'EOF'
version = 1
name = "slurm-ci"
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 64 }
v0 = { min = -4.0, max = 4.0, count = 64 }
block_rows = 4
[classifier]
early_stop = "none"
[output]
path = "out/ci.h5"
EOF
n=2
victim=2
submitted=$(KIND=scan SQUEAL=$bin CPUS=1 "$repo/scripts/tools/slurm-array.sh" ci.toml "$n" out/ci.h5)
echo "$submitted"
array=$(sed -n 's/.*array \([0-9]*\).*/\1/p' <<<"$submitted")
merge=$(sed -n 's/.*merge job \([0-9]*\).*/\1/p' <<<"$submitted")
[ -n "$array" ] && [ -n "$merge" ] || die "could not read the job ids from: $submitted"
jobs_started=("$array" "$merge")

# The reference: the same spec in one run, outside SLURM, while the shards run.
"$bin" scan ci.toml -o single.h5 --threads 1 --quiet >single.log 2>&1 &
single_pid=$!
pids+=("$single_pid")

# Journal records: "SQJR" kind:u8 len:u32 payload fnv1a64(kind, payload):u64; a block
# payload starts map:u64 block:u64 n:u64. Counts the complete block records and their
# cells, stopping at a torn or corrupt record as `--resume` does.
journal_blocks() {
  python3 - "$1" <<'PY'
import struct, sys
try:
    data = open(sys.argv[1], "rb").read()
except FileNotFoundError:
    print(0, 0); sys.exit()
M = 0xFFFFFFFFFFFFFFFF
def step(h, w):
    h = ((h ^ w) * 0x100000001b3) & M
    return h ^ (h >> 29)
def record_sum(kind, payload):
    # The journal's checksum (crates/store/src/journal.rs, record_sum): FNV-1a's basis and
    # prime over the payload's little-endian 8-byte words, the last zero-padded, each
    # product folded; the kind and the length start the sum.
    h = step(0xcbf29ce484222325, kind | (len(payload) << 8))
    for i in range(0, len(payload), 8):
        h = step(h, int.from_bytes(payload[i:i + 8].ljust(8, b"\0"), "little"))
    return h
pos, blocks, cells = 0, 0, 0
while pos + 9 <= len(data) and data[pos:pos + 4] == b"SQJR":
    kind, n = data[pos + 4], struct.unpack_from("<I", data, pos + 5)[0]
    end = pos + 9 + n + 8
    if end > len(data):
        break
    payload = data[pos + 9:pos + 9 + n]
    if record_sum(kind, payload) != struct.unpack_from("<Q", data, end - 8)[0]:
        break
    if kind == ord("B"):
        blocks += 1
        cells += struct.unpack_from("<Q", payload, 16)[0]
    pos = end
print(blocks, cells)
PY
}

task_state() { scontrol show job "${array}_$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1; }
job_state() { scontrol show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1; }

# --- stop and requeue task $victim once its journal holds a block ---------------------------------------
shard=out/ci.shard$victim.h5
journal=$shard.journal
blocks=0
for _ in $(seq 600); do
  read -r blocks cells < <(journal_blocks "$journal")
  [ "$blocks" -ge 1 ] && break
  sleep 0.2
done
[ "$blocks" -ge 1 ] || die "task $victim stored no block in 120 s (state $(task_state "$victim"))"
[ "$(task_state "$victim")" = RUNNING ] || die "task $victim is $(task_state "$victim"), not running"
# As at a preemption or a node failure: SLURM signals the running task (SIGTERM, then
# SIGKILL after KillWait) and puts it back in the queue; the merge keeps waiting for it.
scontrol requeue "${array}_$victim"
say "requeued running task ${array}_$victim with $blocks block(s) in its journal"
for _ in $(seq 300); do
  pgrep -f -- "-o $shard " >/dev/null || break
  sleep 0.1
done
pgrep -f -- "-o $shard " >/dev/null && die "task $victim still runs 30 s after the requeue"
read -r kept_blocks kept_cells < <(journal_blocks "$journal")
[ -e "$shard" ] && die "$shard exists: the task had finished before it was stopped"
say "task ${array}_$victim stopped ($(task_state "$victim")) with $kept_blocks block(s), $kept_cells cells in its journal"

# --- wait for the merge ---------------------------------------------------------------------
s=
for _ in $(seq 1800); do
  s=$(job_state "$merge")
  case $s in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  sleep 0.5
done
[ "$s" = COMPLETED ] || die "merge job $merge ended $s ($(squeue -h -j "$merge" -o %r 2>/dev/null))"
for k in $(seq 1 "$n"); do
  [ "$(task_state "$k")" = COMPLETED ] || die "task ${array}_$k is $(task_state "$k")"
done
say "all shards and the merge completed"

# --- it resumed: the requeued run computed only the cells not in the kept journal ----------
log=logs/squeal-${array}_$victim.out
[ -f "$log" ] || die "no log $log"
computed=$(sed -n 's/^  \([0-9]*\) cells in .*/\1/p' "$log" | tail -n 1)
owned=$("$bin" info "$shard" --json | python3 -c \
  'import json,sys; c=json.load(sys.stdin)["counts"]; print(sum(sum(m.values()) - m["not_computed"] for m in c))')
[ -n "$computed" ] || die "no summary line in $log: $(cat "$log")"
say "shard $victim owns $owned cells: $kept_cells kept from the journal, $computed computed after the requeue"
[ "$((kept_cells + computed))" = "$owned" ] ||
  die "resume did not add up: kept $kept_cells + computed $computed != owned $owned (a restart computes all $owned)"
[ "$computed" -lt "$owned" ] || die "the requeued task recomputed everything"
[ -e "$journal" ] && die "$journal is left behind"

# --- the merged file holds the same data as the single run ----------------------------------
wait "$single_pid" || die "single run failed: $(cat single.log)"
say "single run: $(grep 'cells in' single.log)"
(cd "$repo" && SQUEAL_SAME_A="$work/run/out/ci.h5" SQUEAL_SAME_B="$work/run/single.h5" \
  cargo test --workspace --quiet --test e2e -- --ignored --nocapture same_content::files_hold_the_same_content) |
  grep -E 'same content|test result' || die "the merged file differs from the single run"
[ -s out/ci.png ] || die "the merge drew no picture"

# --- an atlas: 2 shards by points through slurm-array.sh, merged = a single run ---------
# 3 x 2 points (Figs 9 and 10 and above the fold, at two belt speeds) with their boundary
# searches: a few seconds of work. slurm-array.sh picks `squeal atlas` (no [grid] table).
cat >ci-atlas.toml <<'EOF'
version = 1
name = "slurm-ci-atlas"
[model]
law = "mcmillan"
nu = [1e-3, 1e-2, 5e-2]
lambda = [2.0, 3.0]
[integration]
dt = 0.01
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
rtol = 1e-2
[output]
path = "out/ci-atlas.h5"
EOF
submitted=$(SQUEAL=$bin CPUS=1 "$repo/scripts/tools/slurm-array.sh" ci-atlas.toml 2 out/ci-atlas.h5)
echo "$submitted"
grep -q "atlas shards" <<<"$submitted" || die "slurm-array.sh did not see an atlas spec: $submitted"
aarray=$(sed -n 's/.*array \([0-9]*\).*/\1/p' <<<"$submitted")
amerge=$(sed -n 's/.*merge job \([0-9]*\).*/\1/p' <<<"$submitted")
[ -n "$aarray" ] && [ -n "$amerge" ] || die "could not read the atlas job ids from: $submitted"
jobs_started+=("$aarray" "$amerge")
"$bin" atlas ci-atlas.toml -o single-atlas.h5 --threads 1 --quiet --no-render >single-atlas.log 2>&1 ||
  die "single atlas run failed: $(cat single-atlas.log)"
s=
for _ in $(seq 600); do
  s=$(job_state "$amerge")
  case $s in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  sleep 0.5
done
[ "$s" = COMPLETED ] || die "atlas merge job $amerge ended $s"
(cd "$repo" && SQUEAL_SAME_A="$work/run/out/ci-atlas.h5" SQUEAL_SAME_B="$work/run/single-atlas.h5" \
  cargo test --workspace --quiet --test e2e -- --ignored --nocapture same_content::files_hold_the_same_content) |
  grep -E 'same content|test result' || die "the merged atlas differs from the single run"
say "atlas: 2 shards merged into the single run's content"
ok=1
say "PASS in $(($(date +%s) - started)) s (work folder $work removed)"
