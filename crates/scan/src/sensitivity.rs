//! Final-state sensitivity: how predictable a start's fate is, per map (MODEL.md section
//! 14). Three measures, each with what it can and cannot tell:
//!
//! * **Basin entropy** ([`Entropy`], Daza, Wagemakers, Georgeot, Guery-Odelin and Sanjuan,
//!   Sci. Rep. 6, 31416, 2016), from the map's labels alone: the grid is cut into boxes of
//!   `box_cells x box_cells` cells; box `i` has the Gibbs entropy `S_i = -sum_j p_ij ln p_ij`
//!   of its labels' shares. `S_b` is the mean over every box, `S_bb` the mean over the boxes
//!   that hold more than one label (the boundary's boxes). The **log 2 test** (Puy,
//!   Daza, Wagemakers and Sanjuan 2021): `S_bb > ln 2` is sufficient for a fractal boundary.
//!   A box cut by a smooth boundary between two labels has `S_i <= ln 2`, so with two
//!   labels the test can never say "fractal": it is then inconclusive, not negative proof.
//! * **Uncertainty exponent** `alpha` (Grebogi, McDonald, Ott and Yorke, Phys. Lett. A 99,
//!   415, 1983), from extra runs: `N` starts drawn uniformly in the map's box, each also
//!   run from a point `eps` away (in a random direction, `eps` a share of the box's sides)
//!   at [`EPS_LEVELS`] values of `eps`; `f(eps)` is the share of starts whose fate changes.
//!   The starts are drawn where the map's labels show the boundary ([`Domain`]: its
//!   boundary boxes and their neighbours), not over the whole box: the exponent is a
//!   property of the boundary, and a small basin (Fig. 9's covers 0.7% of its box) would
//!   otherwise leave too few starts near it. So `alpha` is that of the boundary the map
//!   resolves; a piece of boundary finer than its boxes is not sampled.
//!   Where `f ~ eps^alpha`, `alpha = D - d` (phase-plane dimension `D = 2` less the
//!   boundary's box-counting dimension): 1 for a smooth boundary, below 1 for a fractal one,
//!   near 0 for a riddled one. The fit is a weighted least-squares line through the levels
//!   with at least [`MIN_UNCERTAIN`] changed starts and `f <= 1/2`, the [`FIT_LEVELS`]
//!   smallest such (the power law holds as `eps -> 0`), weights from the binomial counts; its standard error is scaled up by the
//!   fit's own scatter where that exceeds the counts' (a curved log-log plot).
//! * **Step sensitivity** ([`StepShare`]): the share of the same `N` starts whose fate at
//!   `dt / 2` differs from the one at `dt`, with its binomial standard error. Where it is
//!   above [`STEP_SHARE_SMALL`], a finer grid alone will not settle the map: the step does.
//!
//! The fates are the map's own classification (its rules, certificates and runs, as the
//! scan decides a cell); at `dt / 2` the map is prepared again at half the step, with the
//! rule groups withdrawn that the map at `dt` withdrew.

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::State;

use crate::census::Rules;
use crate::error::ScanError;
use crate::scanner::MapContext;
use crate::spec::Plan;

/// The box side of the basin entropy, in cells (Daza et al. 2016 use boxes of 5 x 5
/// pixels in their examples).
pub const ENTROPY_BOX: usize = 5;

/// The number of perturbation sizes: `eps = 2^-3, 2^-4, ..., 2^-10` of the box's sides (at
/// `2^-2` the Weierstrass boundary of the tests is not yet in its power law: the local
/// slope there is 0.63 against 0.37).
pub const EPS_LEVELS: usize = 8;

/// The least number of changed starts at a level for it to enter the fit (its `ln f` then
/// has a relative error of about `1 / sqrt(8) = 0.35` or less).
pub const MIN_UNCERTAIN: u64 = 8;

/// The most levels in the fit: the smallest `eps` that qualify (the power law holds as
/// `eps -> 0`; at Fig. 9 the two largest, an eighth and a sixteenth of the box, exceed the
/// unstable cycle's size and `f` is not even monotone there).
pub const FIT_LEVELS: usize = 5;

/// Above this share of starts whose fate moves when the step halves, a map's summaries say
/// that its fates depend on the step.
pub const STEP_SHARE_SMALL: f64 = 0.01;

/// The seed of the sampled starts (fixed: the same starts for every run of the same map).
pub const SEED: u64 = 0x5EA1_5E75;

/// The relative sizes of the perturbations, largest first.
pub fn eps_levels() -> [f64; EPS_LEVELS] {
    std::array::from_fn(|k| 0.5f64.powi(k as i32 + 3))
}

/// The default number of sampled starts for a map of `cells` cells
/// (`classifier.sensitivity_samples`): one per 32 cells, between 64 and 4096. Each costs
/// `EPS_LEVELS + 2` classifications, near the boundary where runs are slowest: at the
/// brake's c = 155 N s/m (`scans/brake-sensitivity.toml`), 512 starts on a map of 1024
/// cells cost 5 times the map's own runs, so the default stays at a thirty-second.
pub fn samples_for(cells: usize) -> usize {
    (cells / 32).clamp(64, 4096)
}

/// What the log 2 test says of a map's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum Log2Test {
    /// `S_bb <= ln 2`: no conclusion (a smooth boundary, or a fractal one the test misses;
    /// with two labels the test can never conclude).
    Inconclusive = 0,
    /// `S_bb > ln 2`: the boundary is fractal.
    Fractal = 1,
    /// No box holds two labels: no boundary at this box size.
    NoBoundary = 2,
}

impl Log2Test {
    /// Every value, in value order.
    pub const ALL: [Log2Test; 3] = [
        Log2Test::Inconclusive,
        Log2Test::Fractal,
        Log2Test::NoBoundary,
    ];

    /// The name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Log2Test::Inconclusive => "inconclusive",
            Log2Test::Fractal => "fractal",
            Log2Test::NoBoundary => "no_boundary",
        }
    }
}

/// The basin entropy of a map's labels ([`Entropy::of`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Entropy {
    /// The box side, in cells.
    pub box_cells: usize,
    /// Full boxes with every cell computed.
    pub boxes: u64,
    /// Of those, boxes that hold more than one label.
    pub boundary_boxes: u64,
    /// `S_b`: the mean entropy over the boxes (natural logarithm; NaN without a box).
    pub s_b: f64,
    /// `S_bb`: the mean entropy over the boundary boxes (NaN without one).
    pub s_bb: f64,
}

impl Entropy {
    /// No grid (random samples): every figure NaN.
    pub const NONE: Entropy = Entropy {
        box_cells: 0,
        boxes: 0,
        boundary_boxes: 0,
        s_b: f64::NAN,
        s_bb: f64::NAN,
    };

    /// Of `labels` (stored label values, row-major with `nx` columns), in boxes of
    /// `box_cells` cells a side. Boxes that would cross the grid's last row or column are
    /// left out, and so are boxes with a cell not computed (a value of 4 or more).
    pub fn of(labels: &[u8], nx: usize, box_cells: usize) -> Entropy {
        if nx == 0 || box_cells == 0 {
            return Entropy::NONE;
        }
        let all: Vec<f64> = boxes(labels, nx, box_cells).into_iter().flatten().collect();
        let boundary: Vec<f64> = all.iter().copied().filter(|&s| s > 0.0).collect();
        let mean = |v: &[f64]| match v.len() {
            0 => f64::NAN,
            n => v.iter().sum::<f64>() / n as f64,
        };
        Entropy {
            box_cells,
            boxes: all.len() as u64,
            boundary_boxes: boundary.len() as u64,
            s_b: mean(&all),
            s_bb: mean(&boundary),
        }
    }

    /// The log 2 test of Puy et al. (2021) on `S_bb`.
    pub fn log2_test(&self) -> Log2Test {
        if self.boundary_boxes == 0 {
            Log2Test::NoBoundary
        } else if self.s_bb > std::f64::consts::LN_2 {
            Log2Test::Fractal
        } else {
            Log2Test::Inconclusive
        }
    }
}

/// The entropy of every full box of `box_cells` cells a side, row by row of boxes (`None`:
/// a cell not computed, a value of 4 or more).
fn boxes(labels: &[u8], nx: usize, box_cells: usize) -> Vec<Option<f64>> {
    if nx == 0 || box_cells == 0 {
        return Vec::new();
    }
    let nv = labels.len() / nx;
    let (bx, bv) = (nx / box_cells, nv / box_cells);
    (0..bx * bv)
        .into_par_iter()
        .map(|b| {
            let (i0, j0) = ((b % bx) * box_cells, (b / bx) * box_cells);
            let mut counts = [0u32; 4];
            for j in j0..j0 + box_cells {
                for &l in &labels[j * nx + i0..j * nx + i0 + box_cells] {
                    *counts.get_mut(usize::from(l))? += 1;
                }
            }
            Some(gibbs(&counts))
        })
        .collect()
}

/// `-sum p ln p` of the shares of `counts`.
fn gibbs(counts: &[u32]) -> f64 {
    let n: u32 = counts.iter().sum();
    if n == 0 {
        return 0.0;
    }
    counts
        .iter()
        .filter(|&&c| c > 0)
        .map(|&c| {
            let p = f64::from(c) / f64::from(n);
            -p * p.ln()
        })
        // From +0: a box of one label has entropy 0, not -0.
        .fold(0.0, |a, s| a + s)
}

/// The uncertainty exponent's counts and fit ([`probe`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Uncertainty {
    /// Starts sampled.
    pub samples: u64,
    /// Per level of [`eps_levels`]: starts whose fate changed at that perturbation.
    pub changed: [u64; EPS_LEVELS],
    /// The fitted exponent (NaN: fewer than three levels qualify).
    pub alpha: f64,
    /// Its standard error.
    pub alpha_se: f64,
    /// The smallest and largest `eps` in the fit (NaN without a fit).
    pub fit: [f64; 2],
    /// Levels in the fit.
    pub fitted: u32,
}

impl Uncertainty {
    /// `f(eps)` per level.
    pub fn shares(&self) -> [f64; EPS_LEVELS] {
        std::array::from_fn(|k| self.changed[k] as f64 / self.samples.max(1) as f64)
    }

    /// The fit of `ln f` against `ln eps` over the levels that qualify, `eps <= max_eps`.
    fn fitted(samples: u64, changed: [u64; EPS_LEVELS], max_eps: f64) -> Uncertainty {
        let eps = eps_levels();
        let n = samples as f64;
        // (ln eps, ln f, weight): the weight is 1 / var(ln f) = count / (1 - f).
        let pts: Vec<(f64, f64, f64)> = (0..EPS_LEVELS)
            .rev()
            .filter(|&k| {
                changed[k] >= MIN_UNCERTAIN && 2 * changed[k] <= samples && eps[k] <= max_eps
            })
            .take(FIT_LEVELS)
            .map(|k| {
                let f = changed[k] as f64 / n;
                (eps[k].ln(), f.ln(), changed[k] as f64 / (1.0 - f))
            })
            .collect();
        let mut out = Uncertainty {
            samples,
            changed,
            alpha: f64::NAN,
            alpha_se: f64::NAN,
            fit: [f64::NAN; 2],
            fitted: pts.len() as u32,
        };
        if pts.len() < 3 {
            return out;
        }
        let w: f64 = pts.iter().map(|p| p.2).sum();
        let mx = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / w;
        let my = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / w;
        let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
        let sxy: f64 = pts.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum();
        let slope = sxy / sxx;
        let chi2: f64 = pts
            .iter()
            .map(|p| p.2 * (p.1 - my - slope * (p.0 - mx)).powi(2))
            .sum();
        let scatter = (chi2 / (pts.len() - 2) as f64).max(1.0);
        out.alpha = slope;
        out.alpha_se = (scatter / sxx).sqrt();
        let used: Vec<f64> = pts.iter().map(|p| p.0.exp()).collect();
        out.fit = [
            used.iter().copied().fold(f64::INFINITY, f64::min),
            used.iter().copied().fold(0.0, f64::max),
        ];
        out
    }
}

/// The share of starts whose fate differs between `dt` and `dt / 2`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StepShare {
    /// Starts compared.
    pub compared: u64,
    /// Of those, starts whose fate differs.
    pub changed: u64,
    /// `changed / compared` (NaN without a start).
    pub share: f64,
    /// `sqrt(share (1 - share) / compared)`.
    pub se: f64,
}

impl StepShare {
    /// Of `changed` in `compared`.
    pub fn of(changed: u64, compared: u64) -> StepShare {
        let s = crate::basin::Share::of(changed, compared);
        StepShare {
            compared,
            changed,
            share: s.p,
            se: s.se,
        }
    }

    /// Whether the share is above [`STEP_SHARE_SMALL`].
    pub fn not_small(&self) -> bool {
        self.share > STEP_SHARE_SMALL
    }

    /// The sentence a summary prints where the share is not small: of a map's sampled
    /// starts, or of the runs at an answer's bracket (`critical`, `--fold`).
    pub fn warning(&self, of: StepOf) -> Option<String> {
        let (whose, means) = match of {
            StepOf::Map => (
                "sampled starts",
                "the map's labels there depend on dt, and a finer grid will not settle them",
            ),
            StepOf::Answer => (
                "starts at the answer's bracket",
                "the verdicts near the answer depend on dt, and the interval is as wide as both steps' answers",
            ),
        };
        self.not_small().then(|| {
            format!(
                "WARNING: the fate of {} of {} {whose} ({:.1}% +- {:.1}%) changes when the step halves: {means}",
                self.changed,
                self.compared,
                100.0 * self.share,
                100.0 * self.se
            )
        })
    }
}

/// Whose fates a [`StepShare`] counts (its warning's words).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepOf {
    /// A map's starts sampled near its boundary.
    Map,
    /// The runs at the bracket's ends of a `critical` or `--fold` answer.
    Answer,
}

/// The run-based measures of one map ([`probe`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Probed {
    /// The uncertainty exponent.
    pub uncertainty: Uncertainty,
    /// The step sensitivity (`None`: no map at `dt / 2`).
    pub step: Option<StepShare>,
    /// Classifications made (starts, their perturbations, and the starts at `dt / 2`).
    pub runs: u64,
    /// The share of the map's box the starts were drawn from ([`Domain::share`]).
    pub domain_share: f64,
}

/// A start's fate as a stored label value.
pub type Fate<'a> = &'a (dyn Fn(State) -> u8 + Sync);

/// Where the starts of [`probe`] are drawn: rectangles of one size in the phase plane
/// (uniformly over their union), and the box whose sides scale the perturbations.
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    /// The box `[x_lo, x_hi] x [v_lo, v_hi]` of the map.
    pub sides: ([f64; 2], [f64; 2]),
    /// The rectangles, each `(x range, v range)`, all of one size.
    pub rects: Vec<([f64; 2], [f64; 2])>,
    /// The largest `eps` (a share of the box's sides) the fit takes: a rectangle's side,
    /// the scale the domain resolves (1 for the whole box).
    pub max_eps: f64,
}

impl Domain {
    /// The whole box.
    pub fn whole(x: [f64; 2], v: [f64; 2]) -> Domain {
        Domain {
            sides: (x, v),
            rects: vec![(x, v)],
            max_eps: 1.0,
        }
    }

    /// Where a grid's labels show the boundary: every box of `box_cells` cells that holds
    /// more than one label, with its eight neighbours (the boundary may run beside a box's
    /// edge), each box covering its cells' centres plus half a spacing. `None` where no box
    /// holds two labels.
    pub fn near_boundary(
        labels: &[u8],
        (x0, v0): (crate::grid::Axis, crate::grid::Axis),
        box_cells: usize,
    ) -> Option<Domain> {
        let nx = x0.count;
        let (bx, bv) = (nx / box_cells, (labels.len() / nx.max(1)) / box_cells);
        let mixed = boxes(labels, nx, box_cells);
        let near = |b: usize| {
            let (i, j) = ((b % bx) as i64, (b / bx) as i64);
            (-1..=1).any(|dj| {
                (-1..=1).any(|di| {
                    let (a, c) = (i + di, j + dj);
                    a >= 0
                        && c >= 0
                        && (a as usize) < bx
                        && (c as usize) < bv
                        && mixed[c as usize * bx + a as usize].is_some_and(|s| s > 0.0)
                })
            })
        };
        let (hx, hv) = (x0.spacing(), v0.spacing());
        let rects: Vec<_> = (0..bx * bv)
            .filter(|&b| near(b))
            .map(|b| {
                let (i0, j0) = ((b % bx) * box_cells, (b / bx) * box_cells);
                let span = |a: &crate::grid::Axis, k0: usize, h: f64| {
                    [a.value(k0) - 0.5 * h, a.value(k0 + box_cells - 1) + 0.5 * h]
                };
                (span(&x0, i0, hx), span(&v0, j0, hv))
            })
            .collect();
        // A box's side as a share of the box's sides: the smaller of the two axes' shares.
        let max_eps = box_cells as f64 / (nx.max(bv * box_cells).max(2) - 1) as f64;
        let domain = Domain {
            sides: ([x0.min, x0.max], [v0.min, v0.max]),
            rects,
            max_eps,
        };
        (!domain.rects.is_empty()).then_some(domain)
    }

    /// The share of the box the rectangles cover.
    pub fn share(&self) -> f64 {
        let area = |(x, v): &([f64; 2], [f64; 2])| (x[1] - x[0]) * (v[1] - v[0]);
        self.rects.iter().map(area).sum::<f64>() / area(&self.sides)
    }
}

/// The measures from `samples` starts drawn uniformly over `domain` (seeded by `seed`):
/// each start's `fate`, its fate `eps` away at every level (`eps` a share of the domain's
/// box sides), and its fate at half the step (`half`).
pub fn probe(
    (fate, half): (Fate, Option<Fate>),
    domain: &Domain,
    samples: usize,
    seed: u64,
) -> Probed {
    let unit = crate::grid::Axis {
        min: 0.0,
        max: 1.0,
        count: 2,
    };
    let stream = |s: u64| crate::grid::RandomSample {
        n: samples,
        seed: s,
    };
    // The point in its rectangle, and (from a stream of its own) the rectangle and the
    // perturbation's direction.
    let (at, pick) = (stream(seed), stream(seed ^ 0xA5A5_A5A5_A5A5_A5A5));
    let (x, v) = domain.sides;
    let eps = eps_levels();
    let n_rects = domain.rects.len();
    let per: Vec<([bool; EPS_LEVELS], Option<bool>)> = (0..samples)
        .into_par_iter()
        .map(|i| {
            let (a, b) = at.point(i, &unit, &unit);
            let (r, turn) = pick.point(i, &unit, &unit);
            let (rx, rv) = domain.rects[((r * n_rects as f64) as usize).min(n_rects - 1)];
            let (x0, v0) = (rx[0] + a * (rx[1] - rx[0]), rv[0] + b * (rv[1] - rv[0]));
            let angle = std::f64::consts::TAU * turn;
            let base = fate(State { x: x0, v: v0 });
            let moved = std::array::from_fn(|k| {
                let (dx, dv) = (
                    eps[k] * (x[1] - x[0]) * angle.cos(),
                    eps[k] * (v[1] - v[0]) * angle.sin(),
                );
                fate(State {
                    x: x0 + dx,
                    v: v0 + dv,
                }) != base
            });
            let step = half.map(|h| h(State { x: x0, v: v0 }) != base);
            (moved, step)
        })
        .collect();
    let changed = std::array::from_fn(|k| per.iter().filter(|p| p.0[k]).count() as u64);
    let step = half.map(|_| {
        let c = per.iter().filter(|p| p.1 == Some(true)).count() as u64;
        StepShare::of(c, samples as u64)
    });
    let n = samples as u64;
    Probed {
        uncertainty: Uncertainty::fitted(n, changed, domain.max_eps),
        step,
        runs: n * (1 + EPS_LEVELS as u64) + if half.is_some() { n } else { 0 },
        domain_share: domain.share(),
    }
}

/// The run-based measures of map `map` of `plan` ([`probe`] with the plan's
/// `sensitivity_samples` starts, none where it is 0): its fates as the scan decides them (the map prepared with the rule groups
/// `withdrawn` that its census withdrew; `None`: not known, the census is taken again),
/// and at `dt / 2` the same. The starts are drawn
/// where `labels` show the boundary ([`Domain::near_boundary`]; a random sample's whole
/// box); a map with no boundary box is not probed.
pub fn of_map(
    plan: &Plan,
    map: usize,
    withdrawn: Option<&[Rules]>,
    labels: &[u8],
) -> Result<Option<Probed>, ScanError> {
    let g = &plan.map.grid;
    let domain = match g.starts {
        crate::grid::Starts::Sample(_) => {
            Some(Domain::whole([g.x0.min, g.x0.max], [g.v0.min, g.v0.max]))
        }
        crate::grid::Starts::Grid => Domain::near_boundary(labels, (g.x0, g.v0), ENTROPY_BOX),
    };
    let samples = plan.map.sensitivity_samples as usize;
    let Some(domain) = domain.filter(|_| samples > 0) else {
        return Ok(None);
    };
    let prepare = |p: &Plan, withdrawn: &[Rules]| -> Result<MapContext, ScanError> {
        let mut ctx = MapContext::prepare_checked(p, map, crate::scanner::Checks::LabelsOnly)?;
        for &r in withdrawn {
            ctx.withdraw(r);
        }
        Ok(ctx)
    };
    let mut quiet = plan.clone();
    quiet.cycle.locate = false;
    let mut halved = quiet.clone();
    halved.dt = 0.5 * plan.dt;
    let (at_dt, at_half) = match withdrawn {
        Some(w) => {
            let (a, b) = rayon::join(|| prepare(&quiet, w), || prepare(&halved, w));
            (a?, b?)
        }
        // Not stored (an atlas's maps): the census at dt says which groups to withdraw.
        None => {
            let at_dt = MapContext::prepare(&quiet, map)?;
            let w: Vec<Rules> = at_dt.withdrawn.iter().map(|w| w.rules).collect();
            (at_dt, prepare(&halved, &w)?)
        }
    };
    let fate = |s: State| at_dt.classify(s).regime as u8;
    let half = |s: State| at_half.classify(s).regime as u8;
    Ok(Some(probe((&fate, Some(&half)), &domain, samples, SEED)))
}

/// A map's final-state sensitivity as a file stores it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// The basin entropy of its labels.
    pub entropy: Entropy,
    /// The run-based measures (`None`: not measured, as for a map whose preparation failed).
    pub probed: Option<Probed>,
}

impl Sensitivity {
    /// Of map `map` of `plan` with `labels` (its stored label values): the entropy of a
    /// grid's labels and the probe of [`of_map`] (`None` where it could not be made: the
    /// map's preparation failed, which the scan itself reported).
    pub fn of_map(
        plan: &Plan,
        map: usize,
        withdrawn: Option<&[Rules]>,
        labels: &[u8],
    ) -> Sensitivity {
        let g = &plan.map.grid;
        let entropy = match g.starts {
            crate::grid::Starts::Sample(_) => Entropy::NONE,
            crate::grid::Starts::Grid => Entropy::of(labels, g.x0.count, ENTROPY_BOX),
        };
        Sensitivity {
            entropy,
            probed: of_map(plan, map, withdrawn, labels).ok().flatten(),
        }
    }

    /// The values of [`SENSITIVITY_FIELDS`], in order.
    pub fn values(&self) -> Vec<f64> {
        SENSITIVITY_FIELDS.iter().map(|f| (f.3)(self)).collect()
    }

    /// The log 2 test's verdict.
    pub fn log2_test(&self) -> Log2Test {
        self.entropy.log2_test()
    }

    /// The uncertainty exponent's counts per level (zeros where not measured).
    pub fn changed(&self) -> [u64; EPS_LEVELS] {
        self.probed
            .map_or([0; EPS_LEVELS], |p| p.uncertainty.changed)
    }
}

/// A stored per-map figure: name, long name, units, value.
pub type Field = (
    &'static str,
    &'static str,
    &'static str,
    fn(&Sensitivity) -> f64,
);

fn probed(s: &Sensitivity, f: impl Fn(&Probed) -> f64) -> f64 {
    s.probed.as_ref().map_or(f64::NAN, f)
}

fn step(s: &Sensitivity, f: impl Fn(&StepShare) -> f64) -> f64 {
    s.probed.and_then(|p| p.step).as_ref().map_or(f64::NAN, f)
}

/// What a file stores per map (beside `log2_test`, an enum, and `uncertainty_changed`
/// over the levels `uncertainty_eps`): the one table of the sensitivity's fields.
pub const SENSITIVITY_FIELDS: &[Field] = &[
    (
        "basin_entropy",
        "basin entropy S_b: mean Gibbs entropy (natural log) of the labels over boxes of basin_entropy_box x basin_entropy_box cells (Daza et al. 2016)",
        "1",
        |s| s.entropy.s_b,
    ),
    (
        "boundary_basin_entropy",
        "boundary basin entropy S_bb: mean entropy over the boxes that hold more than one label; above ln 2 the boundary is fractal (Puy et al. 2021)",
        "1",
        |s| s.entropy.s_bb,
    ),
    (
        "basin_entropy_box",
        "side of the basin entropy's boxes, in cells",
        "1",
        |s| s.entropy.box_cells as f64,
    ),
    (
        "basin_entropy_boxes",
        "boxes of the basin entropy (full boxes with every cell computed)",
        "1",
        |s| s.entropy.boxes as f64,
    ),
    (
        "boundary_boxes",
        "of those, the boxes that hold more than one label",
        "1",
        |s| s.entropy.boundary_boxes as f64,
    ),
    (
        "uncertainty_exponent",
        "uncertainty exponent alpha: f(eps) ~ eps^alpha, f the share of sampled starts whose fate changes under a perturbation eps (Grebogi et al. 1983); 1 for a smooth boundary, below 1 for a fractal one; NaN: fewer than 3 levels with 8 changed starts",
        "1",
        |s| probed(s, |p| p.uncertainty.alpha),
    ),
    (
        "uncertainty_exponent_se",
        "standard error of the uncertainty exponent (weighted least squares on the binomial counts, scaled up by the fit's scatter)",
        "1",
        |s| probed(s, |p| p.uncertainty.alpha_se),
    ),
    (
        "uncertainty_eps_lo",
        "smallest eps in the uncertainty exponent's fit, as a share of the box's sides",
        "1",
        |s| probed(s, |p| p.uncertainty.fit[0]),
    ),
    (
        "uncertainty_eps_hi",
        "largest eps in the uncertainty exponent's fit, as a share of the box's sides",
        "1",
        |s| probed(s, |p| p.uncertainty.fit[1]),
    ),
    (
        "uncertainty_samples",
        "starts drawn uniformly in the map's box for the uncertainty exponent and the step sensitivity",
        "1",
        |s| probed(s, |p| p.uncertainty.samples as f64),
    ),
    (
        "step_sensitivity",
        "share of the sampled starts whose fate at dt/2 differs from the one at dt",
        "1",
        |s| step(s, |t| t.share),
    ),
    (
        "step_sensitivity_se",
        "sqrt(p (1 - p) / N) of the step sensitivity",
        "1",
        |s| step(s, |t| t.se),
    ),
    (
        "step_sensitivity_changed",
        "sampled starts whose fate at dt/2 differs from the one at dt",
        "1",
        |s| step(s, |t| t.changed as f64),
    ),
    (
        "sensitivity_domain_share",
        "share of the map's box the sampled starts were drawn from: the boxes where its labels show the boundary, with their neighbours",
        "1",
        |s| probed(s, |p| p.domain_share),
    ),
    (
        "sensitivity_runs",
        "classifications made for the uncertainty exponent and the step sensitivity (starts, their perturbations, and the starts at dt/2)",
        "1",
        |s| probed(s, |p| p.runs as f64),
    ),
];

/// A stored figure of [`SENSITIVITY_FIELDS`] by name, from `values` in the table's order
/// (NaN where absent).
fn stored(values: &[f64], name: &str) -> f64 {
    SENSITIVITY_FIELDS
        .iter()
        .position(|f| f.0 == name)
        .and_then(|i| values.get(i).copied())
        .unwrap_or(f64::NAN)
}

/// A map's final-state sensitivity in words, from its stored figures `values` (the order
/// of [`SENSITIVITY_FIELDS`]): the entropy and the log 2 test, the uncertainty exponent,
/// the step's share, and a warning where that share is not small. Empty for a file
/// written before them.
pub fn words(values: &[f64]) -> Vec<String> {
    let get = |name| stored(values, name);
    let mut out = Vec::new();
    let (boxes, side) = (get("basin_entropy_boxes"), get("basin_entropy_box"));
    if boxes.is_finite() && boxes > 0.0 {
        let stored = Entropy {
            box_cells: side as usize,
            boxes: boxes as u64,
            boundary_boxes: get("boundary_boxes") as u64,
            s_b: get("basin_entropy"),
            s_bb: get("boundary_basin_entropy"),
        };
        out.push(format!(
            "basin entropy S_b {:.4}, boundary S_bb {:.4} over {} of {} boxes of {side} x {side} cells: log 2 test {}",
            stored.s_b,
            stored.s_bb,
            stored.boundary_boxes,
            stored.boxes,
            stored.log2_test().name()
        ));
    }
    let samples = get("uncertainty_samples");
    if samples.is_finite() {
        let alpha = get("uncertainty_exponent");
        let fit = if alpha.is_finite() {
            format!(
                "uncertainty exponent alpha {alpha:.3} +- {:.3} (eps {:.2e} to {:.2e} of the box; 1: a smooth boundary, below 1: fractal)",
                get("uncertainty_exponent_se"),
                get("uncertainty_eps_lo"),
                get("uncertainty_eps_hi")
            )
        } else {
            format!(
                "uncertainty exponent: not fitted (fewer than 3 perturbation sizes moved {MIN_UNCERTAIN} starts)"
            )
        };
        // Random samples draw over the whole box (no grid to show where the boundary is).
        let share = get("sensitivity_domain_share");
        let drawn = match share >= 1.0 {
            true => "over the whole box".to_string(),
            false => format!("near the boundary ({:.1}% of the box)", 100.0 * share),
        };
        out.push(format!(
            "{fit}; {samples} starts {drawn}, {} runs",
            get("sensitivity_runs")
        ));
        let step = StepShare::of(get("step_sensitivity_changed") as u64, samples as u64);
        out.push(format!(
            "step sensitivity: {} of {} of those starts change fate at dt/2 ({:.2}% +- {:.2}%)",
            step.changed,
            step.compared,
            100.0 * step.share,
            100.0 * step.se
        ));
        out.extend(step.warning(StepOf::Map));
    }
    out
}

#[cfg(test)]
mod tests;
