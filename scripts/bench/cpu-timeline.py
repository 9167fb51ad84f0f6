#!/usr/bin/env python3
"""How many cores a run keeps busy over time: where its serial stretches lie.

    scripts/bench/cpu-timeline.py THREADS squeal scan spec.toml -o out.h5 --threads THREADS --quiet

Runs the command with SQUEAL_TIMINGS=1, samples its CPU time (user + system, from
/proc/PID/stat) every 0.1 s, and prints each sample's cores in use as a bar, then the idle
thread-seconds (THREADS minus the cores in use, summed over the samples) in total and in the
run's first 2 s, middle and last 0.5 s. A serial stretch shows as a run of samples near one
core. Linux only (/proc). The run's own timing lines (SQUEAL_TIMINGS) are printed first.
"""
import os
import subprocess
import sys
import time

if len(sys.argv) < 3:
    sys.exit(__doc__)
threads = float(sys.argv[1])
tick = os.sysconf("SC_CLK_TCK")
env = dict(os.environ, SQUEAL_TIMINGS="1")
p = subprocess.Popen(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
t0 = time.time()
last_t, last_cpu, rows = t0, 0.0, []
while p.poll() is None:
    time.sleep(0.1)
    try:
        with open(f"/proc/{p.pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except OSError:
        break
    cpu = (int(fields[11]) + int(fields[12])) / tick  # utime, stime
    now = time.time()
    rows.append((now - t0, (cpu - last_cpu) / (now - last_t), now - last_t))
    last_t, last_cpu = now, cpu
err = p.stderr.read().decode()
print("".join(l + "\n" for l in err.splitlines() if l.startswith("squeal timing")), end="")
for t, cores, _ in rows:
    print(f"{t:7.2f} {cores:5.2f} " + "#" * int(round(cores * 20)))
end = rows[-1][0] if rows else 0.0
idle = {"first 2 s": 0.0, "middle": 0.0, "last 0.5 s": 0.0}
for t, cores, dt in rows:
    part = "first 2 s" if t <= 2.0 else "last 0.5 s" if t > end - 0.5 else "middle"
    idle[part] += max(threads - cores, 0.0) * dt
total = sum(idle.values())
print(f"idle thread-seconds {total:.2f}: " + ", ".join(f"{k} {v:.2f}" for k, v in idle.items()))
sys.exit(p.returncode)
