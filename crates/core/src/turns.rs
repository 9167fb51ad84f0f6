//! Turning points of `x` and the lasting oscillation they show, wherever it lies in the
//! plane (crates/core/MODEL.md section 10, "A lasting oscillation off the section").
//!
//! The classifier's band rules read the Poincare section `x = x*, x' > 0`: an oscillation
//! that never reaches the fixed point's `x*` (at a real brake's parameters, a swing around
//! `x ~ 0.6` with the slip reversing) never crosses it, and they never see it.
//! This watch reads the run itself: every maximum and minimum of `x` (where `x'` changes
//! sign, located on the step's cubic Hermite interpolant as the section's crossings are),
//! and per *turn*, from one maximum of `x` to the next, its period, the extent of `x` and
//! `x'`, whether the block stuck, whether the slip reversed (`x' > lambda`), and whether it
//! crossed the section. Over the last `turns` turns the half-ranges of `x` are read by the
//! classifier's band tests ([`crate::classify::narrow_band`],
//! [`crate::classify::converging_band`], and [`crate::classify::wide_band`] where a turn
//! stuck or reversed its slip): a band without trend, or whose trend dies out inside it, is
//! a [`Lasting`] oscillation. The classifier, the return map's runs
//! ([`crate::section::half_return`]) and `squeal trajectory` all watch turns through
//! [`TurnWatch`].

use std::collections::VecDeque;

use serde::Serialize;

use crate::classify::{Classifier, converging_band, narrow_band, wide_band};
use crate::friction::Branch;
use crate::params::Params;
use crate::run::{Run, Step};
use crate::section::{crossing, hermite, hermite_root};
use crate::stepper::Sample;
use crate::verdict::Regime;

/// The band test's settings: the classifier's window, width and floor.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TurnSettings {
    /// Turns in the window (at least 4).
    pub turns: u32,
    /// Relative width of the narrow band.
    pub rtol: f64,
    /// A window whose smallest half-range of `x` is at or below this is closing on a point.
    pub floor: f64,
}

impl TurnSettings {
    /// The settings of classifier `cl`: `settle_cycles` turns, `settle_rtol`, and its
    /// [`Classifier::band_floor`].
    pub fn of(cl: &Classifier) -> TurnSettings {
        TurnSettings {
            turns: cl.settle_cycles,
            rtol: cl.settle_rtol,
            floor: cl.band_floor(),
        }
    }
}

impl Default for TurnSettings {
    /// [`TurnSettings::of`] the default classifier.
    fn default() -> Self {
        TurnSettings::of(&Classifier::default())
    }
}

/// One turn of a run: from a maximum of `x` to the next.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Turn {
    /// Time of the maximum that opens it.
    pub t_start: f64,
    /// Time of the maximum that closes it.
    pub t_end: f64,
    /// `[x at its minimum, the larger of its two maxima]`.
    pub x_range: [f64; 2],
    /// Smallest and largest `x'` of its samples (0 at the turning points included).
    pub v_range: [f64; 2],
    /// Whether the block stuck on any of its steps (the quasi-static branch of McMillan's
    /// laws, a Coulomb stick, a stick phase of a law with true stick).
    pub stuck: bool,
    /// Whether the slip reversed: `x' > lambda` at some sample.
    pub reversed: bool,
    /// Whether it crossed the section `x = x*, x' > 0`.
    pub crossed: bool,
}

impl Turn {
    /// Its duration.
    pub fn period(&self) -> f64 {
        self.t_end - self.t_start
    }

    /// Half its range of `x`.
    pub fn amplitude(&self) -> f64 {
        0.5 * (self.x_range[1] - self.x_range[0])
    }
}

/// Which band test the window passed (the wider of its half-ranges' and its periods'),
/// narrowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BandKind {
    /// [`narrow_band`]: within the relative width, reversing, no trend (or constant).
    Narrow,
    /// [`converging_band`]: within the relative width, its trend dying out inside it.
    Converging,
    /// [`wide_band`]: some turn stuck or reversed its slip; spread up to the mean,
    /// reversing, no trend.
    Wide,
}

/// A lasting oscillation: the last `turns` turns of a run in a band without trend.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Lasting {
    /// End of the window's last turn.
    pub t: f64,
    /// Turns in the window.
    pub turns: u32,
    /// Angular frequency `2 pi turns / (duration of the window)`.
    pub omega: f64,
    /// Shortest and longest turn.
    pub period: [f64; 2],
    /// Extent of `x` over the window.
    pub x_range: [f64; 2],
    /// Extent of `x'` over the window (sampled).
    pub v_range: [f64; 2],
    /// Smallest and largest half-range of `x` of a turn.
    pub amplitude: [f64; 2],
    /// Whether any turn stuck.
    pub stuck: bool,
    /// Whether any turn reversed its slip (`x' > lambda`).
    pub reversed: bool,
    /// Turns of the window that crossed the section `x = x*, x' > 0`.
    pub crossings: u32,
    /// The band test it passed (the wider of the half-ranges' and the periods').
    pub band: BandKind,
}

impl Lasting {
    /// Whether a turn of the window stuck or reversed the slip: a sticking oscillation.
    pub fn sticks(&self) -> bool {
        self.stuck || self.reversed
    }

    /// The regime of a lasting oscillation whose last window is `lasting` (`None`: no window
    /// closed), where steady slip `attracts` or not: the squeal where a turn of it stuck (or
    /// steady slip attracts: it is then no slip oscillation about it), else the slip
    /// oscillation about the unstable steady slip. `None` counts as sticking (not quiet).
    pub fn regime(lasting: Option<&Lasting>, attracts: bool) -> Regime {
        match attracts || lasting.is_none_or(|l| l.sticks()) {
            true => Regime::StickSlip,
            false => Regime::SlipOscillation,
        }
    }

    /// Whether no turn of the window crossed the section: the section's rules cannot see
    /// this oscillation.
    pub fn misses_section(&self) -> bool {
        self.crossings == 0
    }
}

/// The turn in progress: from its opening maximum.
#[derive(Clone, Copy, Debug)]
struct Open {
    t: f64,
    x_max: f64,
    x_min: f64,
    v_lo: f64,
    v_hi: f64,
    stuck: bool,
    crossed: bool,
}

impl Open {
    fn at(t: f64, x: f64) -> Open {
        Open {
            t,
            x_max: x,
            x_min: f64::NAN,
            v_lo: 0.0,
            v_hi: 0.0,
            stuck: false,
            crossed: false,
        }
    }
}

/// Watches a run's turns; feed it every step ([`TurnWatch::observe_step`] or
/// [`TurnWatch::observe`]) and ask [`TurnWatch::lasting`] when a turn closes.
#[derive(Clone, Debug)]
pub struct TurnWatch {
    settings: TurnSettings,
    lambda: f64,
    x_star: f64,
    /// The run's Coulomb stick count at the last step ([`TurnWatch::observe_step`]).
    sticks: u64,
    open: Option<Open>,
    ring: VecDeque<Turn>,
    amplitudes: VecDeque<f64>,
    periods: VecDeque<f64>,
    turns: u64,
}

impl TurnWatch {
    /// A watch for a run of a model with parameters `p`.
    pub fn new(p: &Params, settings: TurnSettings) -> TurnWatch {
        let n = settings.turns.max(1) as usize;
        TurnWatch {
            settings,
            lambda: p.lambda,
            x_star: p.fixed_point().x,
            sticks: 0,
            open: None,
            ring: VecDeque::with_capacity(n),
            amplitudes: VecDeque::with_capacity(n),
            periods: VecDeque::with_capacity(n),
            turns: 0,
        }
    }

    /// Observes a step of `run` (the step just taken); the turn it closed, if any. The block
    /// stuck on it where its force is on the quasi-static branch or holds it stuck, the run's
    /// Coulomb stick count grew, or a stick phase was located inside it.
    #[inline]
    pub fn observe_step(&mut self, run: &Run, step: &Step) -> Option<Turn> {
        let sticks = run.stats().sticks;
        let stuck = matches!(step.solution.branch, Branch::QuasiStatic | Branch::Stick)
            || sticks > self.sticks
            || step.events.stuck
            || step.events.onsets > 0;
        self.sticks = sticks;
        self.observe(&step.prev, &step.next, stuck)
    }

    /// Observes the step from `prev` to `next` (`stuck`: the block stuck on it); the turn
    /// it closed, if any.
    #[inline]
    pub fn observe(&mut self, prev: &Sample, next: &Sample, stuck: bool) -> Option<Turn> {
        if let Some(o) = self.open.as_mut() {
            o.v_lo = o.v_lo.min(next.v);
            o.v_hi = o.v_hi.max(next.v);
            o.stuck |= stuck;
            o.crossed |= crossing(self.x_star, prev, next).is_some();
        }
        if prev.v > 0.0 && next.v <= 0.0 {
            let (t, x) = turning_point(prev, next, -1.0);
            let closed = self.open.take().filter(|o| o.x_min.is_finite());
            let mut open = Open::at(t, x);
            open.v_lo = next.v.min(0.0);
            self.open = Some(open);
            let o = closed?;
            let turn = Turn {
                t_start: o.t,
                t_end: t,
                x_range: [o.x_min, o.x_max.max(x)],
                v_range: [o.v_lo, o.v_hi],
                stuck: o.stuck,
                reversed: o.v_hi > self.lambda,
                crossed: o.crossed,
            };
            self.push(turn);
            return Some(turn);
        }
        if prev.v < 0.0
            && next.v >= 0.0
            && let Some(o) = self.open.as_mut()
        {
            let (_, x) = turning_point(prev, next, 1.0);
            // NaN (no minimum yet) gives way to `x`.
            o.x_min = o.x_min.min(x);
        }
        None
    }

    fn push(&mut self, turn: Turn) {
        let n = self.settings.turns as usize;
        if self.ring.len() == n {
            self.ring.pop_front();
            self.amplitudes.pop_front();
            self.periods.pop_front();
        }
        self.ring.push_back(turn);
        self.amplitudes.push_back(turn.amplitude());
        self.periods.push_back(turn.period());
        self.turns += 1;
    }

    /// Turns closed so far.
    pub fn turns(&self) -> u64 {
        self.turns
    }

    /// The last closed turn.
    pub fn last(&self) -> Option<&Turn> {
        self.ring.back()
    }

    /// The lasting oscillation of the last `turns` turns, if their half-ranges of `x` and
    /// their periods each pass the narrow or the converging band test, or (where a turn
    /// stuck or reversed its slip) the wide one. The periods are read too: a run still
    /// settling can hold its half-range while its period drifts (at the README's disc brake
    /// the first turns from rest last 1.05, 1.16, 1.30, ... 1.79 at a nearly constant
    /// half-range, and the wide test alone took them for a band at omega 3.81).
    pub fn lasting(&mut self) -> Option<Lasting> {
        let n = self.settings.turns as usize;
        if n == 0 || self.ring.len() < n {
            return None;
        }
        let s = self.settings;
        let sticky = self.ring.iter().any(|t| t.stuck || t.reversed);
        let band_of = |v: &[f64]| {
            if narrow_band(v, s.rtol, s.floor) {
                Some(BandKind::Narrow)
            } else if converging_band(v, s.rtol, s.floor) {
                Some(BandKind::Converging)
            } else if sticky && wide_band(v, s.floor) {
                Some(BandKind::Wide)
            } else {
                None
            }
        };
        let band = band_of(self.amplitudes.make_contiguous())?
            .max(band_of(self.periods.make_contiguous())?);
        let (first, last) = (self.ring.front()?, self.ring.back()?);
        let fold = |f: fn(&Turn) -> f64| {
            self.ring
                .iter()
                .map(f)
                .fold([f64::INFINITY, f64::NEG_INFINITY], |[l, h], v| {
                    [l.min(v), h.max(v)]
                })
        };
        let lo = |f: fn(&Turn) -> f64| fold(f)[0];
        let hi = |f: fn(&Turn) -> f64| fold(f)[1];
        Some(Lasting {
            t: last.t_end,
            turns: n as u32,
            omega: std::f64::consts::TAU * n as f64 / (last.t_end - first.t_start),
            period: fold(Turn::period),
            x_range: [lo(|t| t.x_range[0]), hi(|t| t.x_range[1])],
            v_range: [lo(|t| t.v_range[0]), hi(|t| t.v_range[1])],
            amplitude: fold(Turn::amplitude),
            stuck: self.ring.iter().any(|t| t.stuck),
            reversed: self.ring.iter().any(|t| t.reversed),
            crossings: self.ring.iter().filter(|t| t.crossed).count() as u32,
            band,
        })
    }
}

/// The turning point of `x` inside the step from `prev` to `next` where `x'` changes sign
/// (`sign` -1: from + to -, a maximum; +1: from - to +, a minimum): its time and `x`, on
/// the cubic Hermite interpolants of `x'` (through `x'`, `x''`) and `x` (through `x`,
/// `x'`), as the section's crossings are located.
#[inline]
fn turning_point(prev: &Sample, next: &Sample, sign: f64) -> (f64, f64) {
    let h = next.t - prev.t;
    let c = [
        sign * prev.v,
        sign * h * prev.a,
        sign * next.v,
        sign * h * next.a,
    ];
    let th = hermite_root(c, prev.v / (prev.v - next.v));
    let x = hermite([prev.x, h * prev.v, next.x, h * next.v], th);
    (prev.t + th * h, x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FrictionLaw;

    /// Samples of the closed form `x = c + A e^{-z t} cos(w t)` at steps `h` (with its exact
    /// `x'` and `x''`), fed to a watch; returns the watch and every turn it closed.
    fn watch_closed_form(
        (c, amp, z, w): (f64, f64, f64, f64),
        h: f64,
        t_end: f64,
        settings: TurnSettings,
    ) -> (TurnWatch, Vec<Turn>) {
        let p = Params::paper(FrictionLaw::McMillan, 1e-3);
        let sample = |t: f64| {
            let (e, cs, sn) = (amp * (-z * t).exp(), (w * t).cos(), (w * t).sin());
            Sample {
                t,
                x: c + e * cs,
                v: e * (-z * cs - w * sn),
                a: e * ((z * z - w * w) * cs + 2.0 * z * w * sn),
                force: 0.0,
            }
        };
        let mut tw = TurnWatch::new(&p, settings);
        let mut turns = Vec::new();
        let steps = (t_end / h) as u64;
        for k in 0..steps {
            let (a, b) = (sample(k as f64 * h), sample((k + 1) as f64 * h));
            turns.extend(tw.observe(&a, &b, false));
        }
        (tw, turns)
    }

    /// A pure sinusoid `x = 0.6 + 0.3 cos(3.5 t)` (the shape of a real brake's swing)
    /// sampled at dt = 0.005: every turn lasts `2 pi / 3.5` and spans `[0.3, 0.9]` to the
    /// Hermite interpolation's accuracy (`O(dt^4)`: below 1e-9 here), never reaches the
    /// section `x = 1` nor `x' > lambda = 3` (its `x'` peaks at 1.05), and the window is a
    /// lasting oscillation with exactly that frequency and amplitude.
    #[test]
    fn a_sinusoid_is_lasting_with_its_period_and_amplitude() {
        let w = 3.5;
        let (mut tw, turns) =
            watch_closed_form((0.6, 0.3, 0.0, w), 0.005, 60.0, TurnSettings::default());
        // Maxima at t = 2 pi k / w, k >= 1 (t = 0 is no step's inside): 60 w / (2 pi) = 33.4,
        // so 32 closed turns.
        assert_eq!(turns.len(), 32);
        let period = std::f64::consts::TAU / w;
        for t in &turns {
            assert!((t.period() - period).abs() < 1e-9, "{t:?}");
            assert!((t.amplitude() - 0.3).abs() < 1e-9, "{t:?}");
            assert!((t.x_range[0] - 0.3).abs() < 1e-9 && (t.x_range[1] - 0.9).abs() < 1e-9);
            assert!((t.v_range[1] - 1.05).abs() < 1e-4 && !t.crossed && !t.reversed);
        }
        let l = tw.lasting().expect("lasting");
        assert!((l.omega - w).abs() < 1e-9, "{l:?}");
        assert!((l.amplitude[0] - 0.3).abs() < 1e-9 && (l.amplitude[1] - 0.3).abs() < 1e-9);
        assert!(l.misses_section() && l.band == BandKind::Narrow && l.turns == 20);
    }

    /// A decaying linear oscillator `x = 1 + 2 e^{-nu t} cos(w t)`, `w = sqrt(1 - nu^2)`, for
    /// damping ratios nu from 1e-4 (amplitude down 0.06% per turn: within the narrow band's 5% for 80
    /// turns) to 0.1: its half-ranges shrink monotonically, so no window is ever lasting,
    /// the slow ones included (the reversal test refuses them), and with stuck turns the
    /// wide band refuses them too. It crosses the section every turn.
    #[test]
    fn a_decaying_oscillator_is_never_lasting() {
        // (nu, t_end): at nu = 0.1 the amplitude is down to 2 e^-14 by t = 140 (22 turns);
        // further on `x` rounds to `x*` and the crossings are lost in rounding.
        for (nu, t_end) in [(1e-4, 400.0), (1e-3, 400.0), (1e-2, 400.0), (0.1, 140.0)] {
            let (mut tw, turns) = watch_closed_form(
                (1.0, 2.0, nu, (1.0 - nu * nu).sqrt()),
                0.005,
                t_end,
                TurnSettings::default(),
            );
            assert!(turns.len() >= 21, "{nu}: {}", turns.len());
            assert!(turns.iter().all(|t| t.crossed));
            assert!(tw.lasting().is_none(), "{nu}");
            // After every turn, not only at the end.
            let (_, turns) = watch_closed_form(
                (1.0, 2.0, nu, (1.0 - nu * nu).sqrt()),
                0.005,
                t_end,
                TurnSettings::default(),
            );
            let mut tw = TurnWatch::new(
                &Params::paper(FrictionLaw::McMillan, 1e-3),
                TurnSettings::default(),
            );
            for t in turns {
                tw.push(Turn { stuck: true, ..t });
                assert!(tw.lasting().is_none(), "{nu}: {t:?}");
            }
        }
    }
}
