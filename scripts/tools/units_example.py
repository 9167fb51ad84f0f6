#!/usr/bin/env python3
# /// script
# requires-python = ">=3.9"
# dependencies = []
# ///
"""Convert between squeal's nondimensional variables and a real system (docs/model.md, "Units").

squeal integrates x'' + 2 nu x' + x = F with the scaling of McMillan (1997), Section 4:
time in units of sqrt(m/k), displacement in units of mu_k m g / k, velocity in units of
mu_k g sqrt(m/k), force in units of mu_k m g. Give a system (mass, stiffness, damping,
friction coefficients, belt speed, surface time) and this prints squeal's parameters
nu, lambda, tau, phi; give squeal's parameters instead (--nu, --lam, --tau-nd with the
mass, stiffness and mu_k) and it prints the dimensional ones. It also converts the grid
of Fig. 9 to metres and metres per second. The unstable cycle's size depends on the system:
`squeal ulc` with the same physical flags (--m --k --c --v-belt --mu-k --mu-s --tau-s)
prints it in metres and m/s; this script quotes the paper's Table 1 cycle only when the
system is Table 1's (nu = 1e-3, lambda = 3, tau = 0.1 sqrt(10), phi = 1).

    python3 scripts/tools/units_example.py                     # the worked example of docs/model.md
    python3 scripts/tools/units_example.py --m 2 --k 5e4 --mu-k 0.4 --mu-s 0.5 --v-belt 0.05
"""
import argparse
import math

G = 9.81  # m/s^2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--m", type=float, default=1.0, help="mass m, kg (default 1)")
    ap.add_argument("--k", type=float, default=1e5, help="spring stiffness k, N/m (default 1e5)")
    ap.add_argument("--mu-k", type=float, default=0.3, help="kinetic friction coefficient (default 0.3)")
    ap.add_argument("--mu-s", type=float, default=None,
                    help="static friction coefficient (default: mu_k / sin(1), i.e. phi = 1 as in Table 1)")
    ap.add_argument("--nu", type=float, default=1e-3,
                    help="damping ratio nu = c / (2 sqrt(m k)) (default 1e-3, Fig. 9); or give --c")
    ap.add_argument("--c", type=float, default=None, help="dashpot coefficient c, N s/m (overrides --nu)")
    ap.add_argument("--lam", type=float, default=3.0,
                    help="nondimensional belt speed lambda (default 3, Table 1); or give --v-belt")
    ap.add_argument("--v-belt", type=float, default=None, help="belt speed v_belt, m/s (overrides --lam)")
    ap.add_argument("--tau-nd", type=float, default=0.1 * math.sqrt(10),
                    help="nondimensional tau (default 0.1 sqrt(10), Table 1); or give --tau")
    ap.add_argument("--tau", type=float, default=None, help="surface time tau, s (overrides --tau-nd)")
    a = ap.parse_args()

    w = math.sqrt(a.k / a.m)  # rad/s: the time unit is 1/w
    x_unit = a.mu_k * a.m * G / a.k  # m
    v_unit = a.mu_k * G / w  # m/s
    f_unit = a.mu_k * a.m * G  # N
    mu_s = a.mu_s if a.mu_s is not None else a.mu_k / math.sin(1.0)
    if not 0 < a.mu_k <= mu_s:
        raise SystemExit(f"need 0 < mu_k <= mu_s (got mu_k = {a.mu_k}, mu_s = {mu_s})")
    phi = math.asin(a.mu_k / mu_s)
    c = a.c if a.c is not None else a.nu * 2 * math.sqrt(a.m * a.k)
    nu = c / (2 * math.sqrt(a.m * a.k))
    v_belt = a.v_belt if a.v_belt is not None else a.lam * v_unit
    lam = v_belt / v_unit
    tau = a.tau if a.tau is not None else a.tau_nd * a.mu_k / w
    tau_nd = tau / a.mu_k * w

    print("system")
    print(f"  m = {a.m:g} kg, k = {a.k:g} N/m, c = {c:.4g} N s/m")
    print(f"  mu_k = {a.mu_k:g}, mu_s = {mu_s:.4g}, v_belt = {v_belt:.4g} m/s, tau = {tau:.4g} s")
    print("units of squeal's variables")
    print(f"  time         sqrt(m/k)        = {1 / w:.4g} s  (undamped frequency {w:.4g} rad/s = {w / 2 / math.pi:.4g} Hz)")
    print(f"  displacement mu_k m g / k     = {x_unit:.4g} m")
    print(f"  velocity     mu_k g sqrt(m/k) = {v_unit:.4g} m/s")
    print(f"  force        mu_k m g         = {f_unit:.4g} N")
    print("squeal's parameters (spec keys)")
    print(f"  nu     = c / (2 sqrt(m k))              = {nu:.4g}")
    print(f"  lambda = v_B sqrt(k/m) / (mu_k g)       = {lam:.4g}")
    print(f"  tau    = (tau / mu_k) sqrt(k/m)         = {tau_nd:.4g}")
    print(f"  phi    = arcsin(mu_k / mu_s)            = {phi:.4g}")
    print("examples")
    print(f"  fixed point x* = 1: the spring holds the kinetic friction force, stretched {x_unit * 1e6:.4g} um")
    print(f"  Fig. 9 grid x0 in [-3, 5], x'0 in [-4, 4]: x0 in [{-3 * x_unit * 1e6:.4g}, {5 * x_unit * 1e6:.4g}] um,"
          f" x'0 in [{-4 * v_unit * 1e3:.4g}, {4 * v_unit * 1e3:.4g}] mm/s")
    table1 = (abs(nu - 1e-3) < 1e-9 and abs(lam - 3.0) < 1e-6
              and abs(tau_nd - 0.1 * math.sqrt(10)) < 1e-6 and abs(phi - 1.0) < 1e-6)
    if table1:
        # `squeal ulc --nu 1e-3` (default dt 0.005, foh; 2026-11-25): "distance from the fixed
        # point along +x 0.374326" and section "x' = 0.3667494277" (dt 0.01: 0.374378, 0.366805).
        r = 0.374  # the nu = 1e-3 unstable cycle's distance along +x
        r_v = 0.367  # its x' on the section x = x*
        print(f"  the nu = 1e-3 unstable cycle reaches {r} beyond the fixed point ({r * x_unit * 1e6:.3g} um)"
              f" and x' = {r_v} on the section ({r_v * v_unit * 1e3:.3g} mm/s):"
              f" a start inside it slides steadily, one outside squeals")
        print(f"  stick-slip angular frequency 0.96 (paper, Fig. 9): {0.96 * w / 2 / math.pi:.4g} Hz")
    else:
        print("  the unstable cycle of this system (not Table 1's): squeal ulc --m ... --tau-s ...,"
              " which prints it in metres and m/s")


if __name__ == "__main__":
    main()
