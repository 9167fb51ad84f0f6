#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = ["numpy"]
# ///
"""bSTAB's friction benchmark by bSTAB's approach, in plain numpy: an independent check of
squeal's basin stability and the wall time of the approach squeal is compared with.

Model (bSTAB's friction case, Stender et al., Nonlinear Dynamics 2021):
    x'' + 2 xi x' + x = -sgn(v_rel) mu(|v_rel|),   v_rel = x' - v_d,
    mu(s) = mu_d + mu_d (mu_sd - 1) exp(-s / v_0) + mu_v s / v_0,
    stick (x' = v_d) while |x + 2 xi v_d| <= mu_s = mu_d mu_sd.

bSTAB's approach: N uniform random initial conditions in x0 in [-2, 2], v0 in [0, 2]
(seeded here), each integrated to t = 500; the label is bSTAB's feature rule
(bSTAB-M/case_friction/features_friction.m): stick-slip (LC) if max |x'| over t > 400 exceeds
0.2, else steady slip (FP). Basin stability is the share of each label with standard error
sqrt(p (1 - p) / N).

The integrator is this script's own (not bSTAB's ode45 with a smoothed stick band): classic
RK4 at a fixed step, all samples at once as numpy arrays, with true stick. Within a step
each sample follows one slip branch (the sign of v_rel held, so the right-hand side is
smooth); a step in which v_rel changes sign is cut at the crossing (secant iteration on the
RK4 step length); there the block sticks if |x + 2 xi v_d| <= mu_s, else it slips on the
branch the force points to. A stick phase is exact (x = x_c + v_d t) and ends at breakaway
x + 2 xi v_d = mu_s, located exactly; the rest of the step is slip. At most one crossing
and one breakaway per step are resolved (the step is far shorter than a stick or slip
phase).

Writes a JSON file (default tests/data/bstab_friction_reference.json) with the shares, the
standard errors, the counts, the step, the seed and the wall time per v_d, and the command.

    python3 scripts/tools/bstab_reference.py -o tests/data/bstab_friction_reference.json
    python3 scripts/tools/bstab_reference.py --vd 1.5 --n 1000 -o /tmp/quick.json

numpy is installed with pip (--user) if it is missing."""
import argparse
import json
import os
import platform
import subprocess
import sys
import time

try:
    import numpy as np
except ImportError:
    print("bstab_reference.py: numpy missing, installing it with pip --user", file=sys.stderr)
    subprocess.check_call(
        [sys.executable, "-m", "pip", "install", "--user", "--quiet", "numpy"]
    )
    import site

    sys.path.insert(0, site.getusersitepackages())
    import numpy as np

# bSTAB's case (setup_friction.m / ode_friction.m) and its belt-speed study.
XI, MU_D, MU_SD, V_0, MU_V = 0.05, 0.5, 2.0, 0.5, 0.0
VD_STUDY = [0.8 + 0.075 * i for i in range(20)]  # numpy.linspace(0.8, 2.225, 20)
REGION = ((-2.0, 2.0), (0.0, 2.0))
T_END, TAIL, THRESHOLD = 500.0, 100.0, 0.2  # bSTAB: tSpanEnd = 500, tStar = tSpanEnd - 100


def mu_branch(s, u):
    """mu(s u) for a held branch s = sgn(v_rel) and u = v_rel (smooth in u: no abs)."""
    w = s * u
    return MU_D + MU_D * (MU_SD - 1.0) * np.exp(-w / V_0) + MU_V * w / V_0


def accel(x, v, s, vd):
    return -x - 2.0 * XI * v - s * mu_branch(s, v - vd)


def rk4(x, v, s, vd, h):
    """One RK4 step of length h (array or scalar) on branch s."""
    k1x, k1v = v, accel(x, v, s, vd)
    k2x, k2v = v + 0.5 * h * k1v, accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v, s, vd)
    k3x, k3v = v + 0.5 * h * k2v, accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v, s, vd)
    k4x, k4v = v + h * k3v, accel(x + h * k3x, v + h * k3v, s, vd)
    return (
        x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x),
        v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v),
    )


def slip_branch_at_rest(x, vd):
    """Branch taken when leaving v_rel = 0: the friction opposes the net spring-damper force."""
    return np.where(x + 2.0 * XI * vd > 0.0, -1.0, 1.0)


def run(vd, x0, v0, dt, counters, t_end=T_END):
    mu_s = MU_D * MU_SD
    x, v = x0.copy(), v0.copy()
    n = x.size
    s = np.sign(v - vd)
    stuck = np.zeros(n, dtype=bool)
    # A start exactly on the belt speed: stick or slip by the static limit.
    at = s == 0.0
    stuck[at] = np.abs(x[at] + 2 * XI * vd) <= mu_s
    s[at] = slip_branch_at_rest(x[at], vd)
    vmax = np.zeros(n)
    steps = int(round(t_end / dt))
    t_star = t_end - TAIL
    x_break = mu_s - 2.0 * XI * vd
    for k in range(steps):
        t1 = (k + 1) * dt
        xn, vn = rk4(x, v, s, vd, dt)
        sl = ~stuck
        # Stick phases: exact motion with the belt, breakaway inside the step.
        if stuck.any():
            idx = np.nonzero(stuck)[0]
            xs = x[idx] + vd * dt
            brk = xs > x_break
            xn[idx], vn[idx] = xs, vd
            if brk.any():
                b = idx[brk]
                tau = (x_break - x[b]) / vd  # time in the step at breakaway
                sb = slip_branch_at_rest(np.full(b.size, x_break), vd)
                xb, vb = rk4(np.full(b.size, x_break), np.full(b.size, vd), sb, vd, dt - tau)
                xn[b], vn[b], s[b] = xb, vb, sb
                stuck[b] = False
                counters["breakaways"] += b.size
        # Slip steps that cross v_rel = 0: cut at the crossing.
        cross = sl & (np.sign(vn - vd) != s)
        if cross.any():
            c = np.nonzero(cross)[0]
            xc0, vc0, sc = x[c], v[c], s[c]
            ua, ub = vc0 - vd, vn[c] - vd
            ha, hb = np.zeros(c.size), np.full(c.size, dt)
            h = hb * ua / (ua - ub)
            for _ in range(4):  # secant on the step length (RK4 polynomial in h)
                xh, vh = rk4(xc0, vc0, sc, vd, h)
                uh = vh - vd
                ha, ua, hb, ub = hb, ub, h, uh
                den = np.where(ua - ub == 0.0, 1.0, ua - ub)
                h = np.clip(hb - ub * (hb - ha) / den, 0.0, dt)
            xh, _ = rk4(xc0, vc0, sc, vd, h)
            counters["crossings"] += c.size
            rest = dt - h
            sticks = np.abs(xh + 2.0 * XI * vd) <= mu_s
            # Sticking: move with the belt for the rest of the step (breakaway next step
            # at the earliest; the rest of a step is far shorter than a stick phase).
            st = c[sticks]
            xn[st] = np.minimum(xh[sticks] + vd * rest[sticks], x_break)
            vn[st] = vd
            stuck[st] = True
            counters["stick_onsets"] += st.size
            # Passing through: slip on the branch the force points to.
            ps = ~sticks
            if ps.any():
                p = c[ps]
                sp = slip_branch_at_rest(xh[ps], vd)
                xp, vp = rk4(xh[ps], np.full(p.size, vd), sp, vd, rest[ps])
                xn[p], vn[p], s[p] = xp, vp, sp
        x, v = xn, vn
        if t1 > t_star:
            np.maximum(vmax, np.abs(v), out=vmax)
    return vmax > THRESHOLD


def share(count, n):
    p = count / n
    return p, (p * (1.0 - p) / n) ** 0.5


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vd", type=float, nargs="*", help="belt speeds (default: the study's 20)")
    ap.add_argument("--n", type=int, default=5000, help="random samples per v_d (default 5000)")
    ap.add_argument("--seed", type=int, default=1, help="numpy default_rng seed (default 1)")
    ap.add_argument("--dt", type=float, default=0.01, help="RK4 step (default 0.01 = bSTAB's 1/fs)")
    ap.add_argument(
        "--t-end",
        type=float,
        default=T_END,
        help="integration time (default 500, bSTAB's); the rule looks at the last 100",
    )
    ap.add_argument("-o", "--out", default="tests/data/bstab_friction_reference.json")
    a = ap.parse_args()
    if not a.t_end > TAIL:
        sys.exit(f"--t-end {a.t_end}: expected more than {TAIL}")
    if a.n < 1:
        sys.exit(f"--n {a.n}: expected at least one sample")
    vds = a.vd if a.vd else VD_STUDY
    rng = np.random.default_rng(a.seed)
    (xa, xb), (va, vb) = REGION
    x0 = rng.uniform(xa, xb, a.n)
    v0 = rng.uniform(va, vb, a.n)
    rows = []
    total = time.perf_counter()
    for vd in vds:
        counters = {"crossings": 0, "stick_onsets": 0, "breakaways": 0}
        t0 = time.perf_counter()
        lc = run(vd, x0, v0, a.dt, counters, a.t_end)
        secs = time.perf_counter() - t0
        n_lc = int(lc.sum())
        p_lc, se = share(n_lc, a.n)
        rows.append(
            {
                "v_d": round(vd, 12),
                "n": a.n,
                "n_LC": n_lc,
                "n_FP": a.n - n_lc,
                "bs_LC": p_lc,
                "bs_FP": 1.0 - p_lc,
                "se": se,
                "seconds": secs,
                **counters,
            }
        )
        print(
            f"v_d = {vd:.3f}: FP {1 - p_lc:.4f}  LC {p_lc:.4f}  (se {se:.4f})  {secs:.1f} s",
            flush=True,
        )
    doc = {
        "what": "bSTAB's friction benchmark by bSTAB's approach (uniform random samples, "
        "t = 500, LC if max |x'| over t > 400 exceeds 0.2), computed by scripts/tools/bstab_reference.py "
        "with true stick and RK4 at a fixed step",
        "command": " ".join(["python3", "scripts/tools/bstab_reference.py"] + sys.argv[1:]),
        "parameters": {"xi": XI, "mu_d": MU_D, "mu_sd": MU_SD, "v_0": V_0, "mu_v": MU_V},
        "region": {"x0": list(REGION[0]), "v0": list(REGION[1])},
        "seed": a.seed,
        "dt": a.dt,
        "t_end": a.t_end,
        "t_star": a.t_end - TAIL,
        "threshold": THRESHOLD,
        "machine": f"{platform.node()} {platform.machine()} {os.cpu_count()} cpu(s), "
        f"python {platform.python_version()}, numpy {np.__version__}",
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "wall_seconds": time.perf_counter() - total,
        "results": rows,
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(doc, f, indent=1)
    print(f"wrote {a.out} ({doc['wall_seconds']:.1f} s)")


if __name__ == "__main__":
    main()
