#!/usr/bin/env bash
# Python's `squeal.trajectory` of README's pad (t_end = 50) in a fresh interpreter against
# the command line's same run: median wall and CPU (user + system) of 5, interleaved.
#   scripts/bench/python-trajectory.sh BEFORE_PYTHON AFTER_PYTHON SQUEAL
# (two venvs' python with the wheels to compare, and a `squeal` command). docs/history/benchmarks.md,
# "Python's trajectory against the command line's".
set -euo pipefail
before=$1 after=$2 squeal=$3
code="import squeal; squeal.trajectory(law='mcmillan', m=0.8, k=2e5, v_belt=0.3, mu_k=0.38,
mu_s=0.48, tau_s=5e-4, c=100.0, normal_force=1500.0, t_end=50.0)"
for _ in 1 2 3 4 5; do
    /usr/bin/time -f "before %e %U %S" "$before" -c "$code"
    /usr/bin/time -f "after %e %U %S" "$after" -c "$code"
    /usr/bin/time -f "cli %e %U %S" "$squeal" trajectory --law mcmillan --m 0.8 --k 2e5 \
        --v-belt 0.3 --mu-k 0.38 --mu-s 0.48 --tau-s 5e-4 --c 100 --normal-force 1500 \
        --t-end 50 >/dev/null
done 2>&1 | grep -E "^(before|after|cli) " | python3 -c "
import sys, statistics as st
d = {}
for line in sys.stdin:
    k, w, u, s = line.split()
    d.setdefault(k, []).append((float(w), float(u) + float(s)))
for k, v in d.items():
    print(f'{k}: wall {st.median(x[0] for x in v):.2f} s, cpu {st.median(x[1] for x in v):.2f} s')
"
