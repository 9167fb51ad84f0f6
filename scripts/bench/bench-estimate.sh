#!/usr/bin/env bash
# Checks the time estimate of `squeal scan` and `squeal atlas` (the pilots of
# crates/scan/src/estimate.rs) against the measured time of shipped specs: each must lie within a factor 2 of the other.
# Prints one row per spec and exits 1 if any is outside.
#
#   scripts/bench/bench-estimate.sh                       # the quick specs
#   scripts/bench/bench-estimate.sh scans/bstab-friction.toml scans/atlas-nu.toml   # any specs
#
# What is compared: the estimate printed before computing ("roughly ... (S s)") with the
# time from that line to the end of the run (the pilot is over by then), both floored at
# 1 s (the estimate is printed to the second: "roughly 1 s" for a 0.3 s scan is right).
# Two measures of that time: the wall clock, and the CPU seconds the run used after the
# estimate divided by the threads (2). On an idle machine they agree; on a shared one the
# wall clock depends on the other users' load, which no estimate can know, so the check is
# on the CPU measure and the wall ratio is printed beside it. Atlas specs are run and
# reported but not checked: their lines run points in sequence, so CPU / threads is not
# their time (the check is of `squeal scan`'s estimate).
#
# Needs target/release/squeal (cargo build --release). Results: docs/history/benchmarks.md, "Scan time
# estimates".
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=target/release/squeal
[ -x "$bin" ] || { echo "build first: cargo build --release" >&2; exit 2; }
specs=("$@")
[ ${#specs[@]} -gt 0 ] || specs=(scans/fig9.toml scans/fig10.toml scans/fig11.toml scans/fig9-zoom.toml scans/nu-sweep.toml)
echo "# $(date -u +%Y-%m-%dT%H:%MZ) $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
exec python3 - "$bin" "${specs[@]}" <<'PY'
import os, re, subprocess, sys, tempfile, time

def cpu_seconds(pid):
    # utime + stime of the process and its waited-for children, in clock ticks.
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return sum(int(x) for x in fields[11:15]) / os.sysconf("SC_CLK_TCK")

binary, specs = sys.argv[1], sys.argv[2:]
threads = 2
print(f"{'spec':<20} {'estimate_s':>10} {'wall_s':>8} {'cpu/2_s':>8} {'wall/est':>8} {'cpu/est':>8}")
fail = False
with tempfile.TemporaryDirectory() as tmp:
    for spec in specs:
        name = os.path.basename(spec)[:-5]
        out = os.path.join(tmp, name + ".h5")
        # An atlas spec: named atlas-* or with neither [grid] nor [sample] (the tests' rule).
        text = open(spec).read()
        atlas = name.startswith("atlas-") or not re.search(r"^\[(grid|sample)\]", text, re.M)
        p = subprocess.Popen([binary, "atlas" if atlas else "scan", spec, "-o", out, "--force", "--threads", str(threads),
                              "--allow-long"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        est = t_line = cpu_line = None
        for line in p.stderr:
            m = re.search(r"roughly [^(]*\(([0-9.]+) s\)", line)
            if m and est is None:
                est, t_line = float(m.group(1)), time.monotonic()
                cpu_line = cpu_seconds(p.pid)
        # The whole run's CPU time, from the kernel's account at exit (all threads).
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        cpu_last = ru.ru_utime + ru.ru_stime
        t_end = time.monotonic()
        if p.returncode != 0 or est is None:
            print(f"{name}: the scan failed or printed no estimate", file=sys.stderr)
            fail = True
            continue
        wall = t_end - t_line
        cpu = (cpu_last - cpu_line) / threads
        floor = lambda x: max(x, 1.0)
        r_wall, r_cpu = floor(wall) / floor(est), floor(cpu) / floor(est)
        ok = 0.5 <= r_cpu <= 2.0
        note = "" if ok else "  OUTSIDE 2x"
        if atlas:
            # An atlas's lines run their points in sequence, so its threads are not all busy
            # and CPU / threads undercounts its time: reported, not checked.
            note = "  (atlas: not checked)"
        else:
            fail |= not ok
        print(f"{name:<20} {est:>10.1f} {wall:>8.1f} {cpu:>8.1f} {r_wall:>8.2f} {r_cpu:>8.2f}{note}")
sys.exit(1 if fail else 0)
PY
