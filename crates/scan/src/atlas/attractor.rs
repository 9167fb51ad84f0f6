//! The stick-slip attractor outside the unstable cycle: runs from starts outside it, followed
//! until they settle on a band of section amplitudes (the attractor's figures) or fall inside
//! the cycle (no attractor there).

use squeal_core::classify::crossing;
use squeal_core::{SolverStats, State, Stepper, friction};

use super::figures::PointSettings;
pub use super::figures::StickSlipFigures;

/// Why a stick-slip run did not give the attractor.
#[derive(Clone, Debug, PartialEq)]
pub enum StickFail {
    /// A section crossing fell inside the unstable cycle (below `r_inside`), or the run
    /// reached the fixed point: this start returns to steady slip.
    FellInside {
        /// Time of that crossing.
        t: f64,
    },
    /// The run failed (solver failure, blow-up, no crossing for `t_return`).
    Failed(String),
}

/// Runs the stick-slip attractor from `(x*, r_start)`: `ps.transient` revolutions
/// discarded, then `ps.window` measured. A crossing below `r_inside` (the unstable cycle's crossing; 0 if
/// there is none) means the run fell inside the cycle: in the plane it then cannot leave.
pub fn stick_slip(
    st: &Stepper,
    r_start: f64,
    r_inside: f64,
    ps: &PointSettings,
    t_return: f64,
    stats: &mut SolverStats,
) -> Result<StickSlipFigures, StickFail> {
    let (transient, window) = (ps.transient, ps.window);
    let p = *st.params();
    let fp = p.fixed_point();
    let (mut s, _) = st.initial(
        State {
            x: fp.x,
            v: r_start,
        },
        stats,
    );
    let mut crossings = 0u32;
    let mut last_cross = f64::NAN;
    let mut t_last = 0.0;
    let (mut rs, mut omegas) = (Vec::new(), Vec::new());
    let mut x_range = [f64::INFINITY, f64::NEG_INFINITY];
    let mut v_range = [f64::INFINITY, f64::NEG_INFINITY];
    let (mut steps, mut qs) = (0u64, 0u64);
    let total = transient + window;
    while crossings <= total {
        let (n, _) = st.step(&s, stats);
        if stats.failures > 0 || !n.x.is_finite() || n.x.abs() > 1e6 {
            return Err(StickFail::Failed(format!(
                "the stick-slip run failed at t = {:.1}",
                n.t
            )));
        }
        if (n.x - fp.x).hypot(n.v - fp.v) < 1e-3 {
            return Err(StickFail::FellInside { t: n.t });
        }
        if n.t - t_last > t_return {
            return Err(StickFail::Failed(format!(
                "no crossing of the section x = x*, x' > 0 for {t_return} time units without reaching the fixed point: an oscillation that does not surround the fixed point, which the section method cannot measure"
            )));
        }
        if crossings > transient {
            steps += 1;
            qs += u64::from(friction::on_quasi_static_branch(&p, n.v - p.lambda, n.a));
            x_range = [x_range[0].min(n.x), x_range[1].max(n.x)];
            v_range = [v_range[0].min(n.v), v_range[1].max(n.v)];
        }
        if let Some(c) = crossing(fp.x, &s, &n) {
            if c.r < r_inside {
                return Err(StickFail::FellInside { t: c.t });
            }
            crossings += 1;
            t_last = n.t;
            if crossings > transient {
                rs.push(c.r);
                if crossings > transient + 1 {
                    omegas.push(std::f64::consts::TAU / (c.t - last_cross));
                }
            }
            last_cross = c.t;
        }
        s = n;
    }
    // The window is the revolutions between crossing transient+1 and the last one.
    rs.pop();
    let share = qs as f64 / steps.max(1) as f64;
    Ok(figures(&rs, &omegas, [x_range, v_range], p.lambda, share))
}

/// The figures of the window's section amplitudes `rs`, angular frequencies `omegas` and
/// extents `[x_range, v_range]` at belt speed `lambda`, `share` of its steps quasi-static.
fn figures(
    rs: &[f64],
    omegas: &[f64],
    [x_range, v_range]: [[f64; 2]; 2],
    lambda: f64,
    share: f64,
) -> StickSlipFigures {
    let m = rs.len().max(1) as f64;
    let mean = rs.iter().sum::<f64>() / m;
    let half = rs.len() / 2;
    let m1 = rs[..half].iter().sum::<f64>() / half.max(1) as f64;
    let m2 = rs[rs.len() - half..].iter().sum::<f64>() / half.max(1) as f64;
    let no = omegas.len().max(1) as f64;
    let om = omegas.iter().sum::<f64>() / no;
    let var = omegas.iter().map(|o| (o - om).powi(2)).sum::<f64>() / no;
    StickSlipFigures {
        r_band: [
            rs.iter().copied().fold(f64::INFINITY, f64::min),
            mean,
            rs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        ],
        drift: (m2 - m1) / mean,
        x_range,
        v_range,
        overshoot: v_range[1] - lambda,
        omega_mean: om,
        omega_std: var.sqrt(),
        quasi_static_share: share,
    }
}

/// The starts tried for stick-slip outside a cycle crossing `r_u` (upper end `hi` of the
/// window where `D > 0` first showed): far out (`max(1.5 r_u, lambda)`), then just outside
/// the cycle. The return map jumps where the orbit starts to stick (D falls from positive to
/// strongly negative), so a start just outside the cycle can overshoot and fall back inside:
/// squeal exists only if some start settles.
fn stick_starts(r_u: f64, lambda: f64) -> [f64; 2] {
    [(1.5 * r_u).max(lambda), r_u * 1.02]
}

/// The stick-slip attractor outside a cycle at `r_u` (0: none), tried from each start.
pub fn find_stick_slip(
    st: &Stepper,
    r_u: f64,
    ps: &PointSettings,
    t_return: f64,
    stats: &mut SolverStats,
) -> Result<StickSlipFigures, StickFail> {
    let lambda = st.params().lambda;
    let starts: Vec<f64> = if r_u > 0.0 {
        stick_starts(r_u, lambda).to_vec()
    } else {
        vec![lambda.max(10.0 * ps.cycle.r_min)]
    };
    let mut last = StickFail::Failed("no start".into());
    for r0 in starts {
        match stick_slip(st, r0, r_u, ps, t_return, stats) {
            Ok(s) => return Ok(s),
            Err(e @ StickFail::Failed(_)) => return Err(e),
            Err(e) => last = e,
        }
    }
    Err(last)
}
