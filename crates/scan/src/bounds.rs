//! Bounds shared by the scan spec, the atlas spec and the command line, each written once
//! with the reason for it (the users' words are in `docs/spec.md` and `docs/atlas-spec.md`).
//!
//! A check takes the name to print (`sample.region.x0`, `disturbance.v`, `--r-max`) and an
//! [`Invalid`] that builds the error, so a spec key and a flag are refused by the same rule
//! and each message names what the user wrote.

use crate::error::ScanError;
use crate::section::CycleSettings;
use squeal_core::error::Number;

/// A spec error: the key, the value found, what was expected.
pub type Invalid<'a> = &'a dyn Fn(&str, String, &str) -> ScanError;

/// Largest `|x|` or `|x'|` of a start, a grid or sample bound, an operating point or a
/// disturbance box. It is the classifier's escape radius (`Classifier::max_radius`, 1e6): a
/// start beyond it is labelled diverged before its first step, so nothing there can be
/// mapped. It also keeps every derived number finite: a grid spacing or box width is at
/// most 2e6 and a box area at most 4e12 (with `min = -1e308, max = 1e308` the width
/// overflowed to inf and the grid's coordinates became NaN).
pub const MAX_STATE: f64 = 1e6;

/// Largest ratio of neighbouring amplitudes in the cycle search's log-spaced sampling
/// (`(r_max / r_min)^(1 / (samples - 1))`). The search sees the unstable cycle only as a
/// sign change of `D = P(r) - r` between two samples; a band of growing returns narrower
/// than one sample spacing falls between samples and the point is reported as having no
/// cycle. The defaults (r_min = 0.01, r_max = 6, 96 samples) give 1.07. Measured on Table 1
/// (nu = 1e-3, lambda = 3; `squeal ulc --r-max R --no-half-dt` before this bound), whose
/// band of growing returns is wide (from the cycle at 0.367 to the stick-slip orbit near
/// 3): found up to R = 1e200 (ratio 133, a sample at 1.33 lands in the band), lost at
/// R = 1e250 (ratio 449: "the return map decays at every sampled section amplitude").
/// Near the fold the band shrinks to nothing, so no ratio is safe everywhere; 1.25 stays
/// within about three times the default spacing (ln 1.25 / ln 1.07 = 3.3).
pub const MAX_SAMPLE_RATIO: f64 = 1.25;

/// Most steps of one run (`t_max / dt` of the classifier, `t_end / dt` of a trajectory):
/// at up to about 250 ns per step with the robust solver (docs/history/benchmarks.md, "Time per
/// step") one run then takes at most about 40 minutes; `--dt 1e-12` with `--t-end 5000` asked
/// for 5e15 steps (about 40 years).
pub const MAX_STEPS: f64 = 1e10;

/// Most rays of `squeal ulc --verify-rays`: 10 000 rays put one every 0.036 degrees, finer
/// than the located curve's samples at the default step (about 1260 per revolution at
/// dt = 0.005), so more rays check no new part of the curve.
pub const MAX_RAYS: usize = 10_000;

/// Most starts on the stick-slip band per damping of the transient lifetimes
/// (`[boundaries] lifetime_starts`, `squeal critical --starts`). Each start is a run of up
/// to the lifetime's `t_max` (40 000 by default: 8e6 steps at dt = 0.005, about 2 s), at
/// each damping of the table; 4096 starts put the standard error of a mean lifetime at
/// 1/sqrt(4096) = 1.6% of it (lifetimes spread exponentially: their spread is their mean).
/// `squeal critical --starts 100000000` had no bound.
pub const MAX_LIFETIME_STARTS: usize = 4096;

/// Largest cycle-search sample count: each sample is one revolution.
pub const MAX_CYCLE_SAMPLES: usize = 100_000;

/// A finite coordinate of the phase plane within [`MAX_STATE`].
pub fn state(key: &str, v: f64, invalid: Invalid) -> Result<f64, ScanError> {
    if v.is_finite() && v.abs() <= MAX_STATE {
        Ok(v)
    } else {
        Err(invalid(
            key,
            format!("{v:?}"),
            "a finite coordinate with |value| <= 1e6 (the classifier's escape radius)",
        ))
    }
}

/// How a start refused by the bounds here (in the model's units) is reported from `path`
/// (the command line, a file's line, a Python helper): where the start was
/// given in SI units (`si`: the start as given, in m and m/s, and the system's scales),
/// the message shows the value the user wrote, in m or m/s, and the model's value after
/// it: `--x0 1e3` (metres) was reported as "`--x0` = 7281199.94". Other keys (`--t-end`)
/// say their bound is in the model's units. One rule for the command line's `trajectory`,
/// `critical` and `classify` and Python's helpers.
pub fn start_invalid(
    path: String,
    si: Option<(squeal_core::State, squeal_core::Scales)>,
) -> impl Fn(&str, String, &str) -> crate::error::ScanError {
    use squeal_core::error::Number;
    move |key: &str, value: String, expected: &str| {
        let axis = match si {
            Some((given, s)) if key.ends_with("x0") => Some((given.x, "m", s.length)),
            Some((given, s)) if key.ends_with("v0") => Some((given.v, "m/s", s.velocity)),
            _ => None,
        };
        let (value, expected) = match (axis, si) {
            (Some((given, unit, scale)), _) => (
                format!("{} {unit}", Number(given)),
                format!(
                    "{expected}, in the model's units: at most {} {unit} for this system \
                     (one unit is {} {unit}), where {} {unit} is {value}",
                    Number(MAX_STATE * scale),
                    Number(scale),
                    Number(given)
                ),
            ),
            (None, Some(_)) => (value, format!("{expected}, in the model's units")),
            (None, None) => (value, expected.to_string()),
        };
        crate::error::ScanError::Invalid {
            path: path.clone(),
            key: key.into(),
            value,
            expected,
        }
    }
}

/// Narrowest side of a box with an area (the disturbance box), in the model's units (the
/// fixed point sits at x = 1). Narrower is a point for a basin fraction, and below about
/// 1e-154 a side's square underflows: with `[physical] m = 1e308` the disturbance box
/// scaled to the model's units had sides of 1e-308 and an area of 0.
pub const MIN_WIDTH: f64 = 1e-9;

/// Whether a range may be a single value (`min = max`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    /// `min <= max`.
    MayBeEmpty,
    /// `min < max` (a box with an area).
    Positive,
}

/// The two numbers `[min, max]` of a list (TOML arrays are read as lists so that a third
/// element is refused here instead of being dropped): what a range is under any [`Rules`].
pub(crate) fn pair(key: &str, list: &[f64], invalid: Invalid) -> Result<[f64; 2], ScanError> {
    match *list {
        [lo, hi] => Ok([lo, hi]),
        _ => Err(invalid(
            key,
            shown_list(list),
            &format!("exactly two numbers [min, max] (got {})", list.len()),
        )),
    }
}

/// A list as an error shows it, `[a, b, c]`.
fn shown_list(list: &[f64]) -> String {
    format!(
        "[{}]",
        list.iter()
            .map(|v| format!("{v:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// A `[min, max]` pair of phase-plane coordinates: exactly two finite numbers within
/// [`MAX_STATE`], in order. TOML arrays are read as lists so that a third element is
/// refused here instead of being dropped.
pub fn state_range(
    key: &str,
    list: &[f64],
    width: Width,
    invalid: Invalid,
) -> Result<[f64; 2], ScanError> {
    let shown = shown_list(list);
    let [lo, hi] = pair(key, list, invalid)?;
    if !(lo.is_finite() && hi.is_finite() && lo.abs() <= MAX_STATE && hi.abs() <= MAX_STATE) {
        return Err(invalid(
            key,
            shown,
            "finite bounds [min, max] with |value| <= 1e6 (the classifier's escape radius)",
        ));
    }
    let ordered = match width {
        Width::MayBeEmpty => lo <= hi,
        Width::Positive => hi - lo >= MIN_WIDTH,
    };
    if !ordered {
        let expected = match width {
            Width::MayBeEmpty => "min <= max (the range is inverted)",
            Width::Positive => "[min, max] with max - min >= 1e-9 (a box with an area)",
        };
        return Err(invalid(key, shown, expected));
    }
    Ok([lo, hi])
}

/// The relative width at which a bisection stops (`squeal critical --rtol`, Python's
/// `critical(rtol=)`): a finite fraction in (0, 1). NaN stopped the bisection after its two
/// ends and answered their geometric middle; a negative one ran 200 halvings.
pub fn bisection_rtol(key: &str, rtol: f64, invalid: Invalid) -> Result<f64, ScanError> {
    if rtol.is_finite() && rtol > 0.0 && rtol < 1.0 {
        Ok(rtol)
    } else {
        Err(invalid(
            key,
            format!("{rtol:?}"),
            "a finite fraction in (0, 1)",
        ))
    }
}

/// The horizon of the runs behind a boundary ([`crate::fates`]): a finite time > 0 of at
/// most [`MAX_STEPS`] steps of `dt` (`squeal critical --horizon`, Python's `horizon=`).
pub fn horizon(key: &str, h: f64, dt: f64, invalid: Invalid) -> Result<f64, ScanError> {
    if h.is_finite() && h > 0.0 && h / dt <= MAX_STEPS {
        Ok(h)
    } else {
        Err(invalid(
            key,
            format!("{h:?}"),
            "a finite time > 0 of at most 1e10 steps of dt",
        ))
    }
}

/// The cycle search's settings (`[cycle]` of an atlas spec, `squeal ulc`'s flags). `name`
/// turns a field name (`r_max`) into what the user wrote (`cycle.r_max`, `--r-max`).
pub fn cycle_search(
    cs: &CycleSettings,
    name: &dyn Fn(&str) -> String,
    invalid: Invalid,
) -> Result<(), ScanError> {
    if !(cs.r_min.is_finite() && cs.r_min > 0.0 && cs.r_min < 1.0) {
        return Err(invalid(
            &name("r_min"),
            format!("{:?}", cs.r_min),
            "a finite amplitude in (0, 1) (the search starts next to the fixed point)",
        ));
    }
    if !(cs.r_max.is_finite() && cs.r_max > 2.0 * cs.r_min && cs.r_max <= MAX_STATE) {
        return Err(invalid(
            &name("r_max"),
            format!("{:?}", cs.r_max),
            "a finite amplitude > 2 r_min and <= 1e6 (the classifier's escape radius)",
        ));
    }
    if !(3..=MAX_CYCLE_SAMPLES).contains(&cs.samples) {
        return Err(invalid(
            &name("samples"),
            cs.samples.to_string(),
            "a count in 3..=100000",
        ));
    }
    // In logarithms: r_max / r_min overflows for r_min = 1e-320 (and blamed r_max).
    let ratio_of = |lo: f64, hi: f64| ((hi.ln() - lo.ln()) / (cs.samples - 1) as f64).exp();
    let ratio = ratio_of(cs.r_min, cs.r_max);
    if ratio > MAX_SAMPLE_RATIO {
        // The end that makes the range too wide: r_min where the default r_min would do.
        let r_min_default = CycleSettings::default().r_min;
        let (key, value) = match cs.r_min < r_min_default
            && ratio_of(r_min_default, cs.r_max) <= MAX_SAMPLE_RATIO
        {
            true => ("r_min", cs.r_min),
            false => ("r_max", cs.r_max),
        };
        let ratio = match ratio < 1e6 {
            true => format!("{ratio:.3}"),
            false => Number(ratio).to_string(),
        };
        return Err(invalid(
            &name(key),
            format!("{value:?}"),
            &format!(
                "a range the {} samples cover finely: neighbouring samples {ratio} apart \
                 in ratio, at most 1.25 (a cycle between two samples is missed); raise r_min, \
                 lower r_max or raise the samples",
                cs.samples
            ),
        ));
    }
    if !(cs.rtol.is_finite() && cs.rtol > 0.0 && cs.rtol < 0.1) {
        return Err(invalid(
            &name("rtol"),
            format!("{:?}", cs.rtol),
            "a relative width in (0, 0.1)",
        ));
    }
    if !(cs.t_return.is_finite() && cs.t_return > 10.0 && cs.t_return <= 1e6) {
        return Err(invalid(
            &name("t_return"),
            format!("{:?}", cs.t_return),
            "a finite time in (10, 1e6] (one revolution takes about 2 pi)",
        ));
    }
    Ok(())
}

/// Largest `classifier.fp_radius`: the smallest amplitude the cycle search samples
/// ([`CycleSettings::default`]'s `r_min`, 0.01). The classifier ends a run as steady slip
/// once it is inside this ball around the fixed point, so the ball must lie inside the
/// unstable cycle; the cycle is only known after the search (then [`fp_radius_inside`]
/// checks it), and a ball wider than the search's first sample would cover amplitudes the
/// search itself looks at. With `fp_radius = 10` every cell of Fig. 9 was labelled steady
/// slip.
pub const MAX_FP_RADIUS: f64 = 1e-2;

/// Smallest `classifier.fp_radius`. A settled run does not sit on the fixed point: it
/// jitters about it at the level of the step's rounding (the force is solved to a residual
/// of `4 eps (1 + |F|)`, about `9e-16` at `F = x* = 1`). A ball narrower than that jitter is
/// entered by chance or never: measured on a 4 x 4 grid around `(1, 0)` at `nu = 0.1`
/// (McMillan, `early_stop = "none"`, `t_max = 5000`), every cell is steady slip with
/// `fp_radius` down to `1e-13`, undecided at `1e-14`, and labelled *stick-slip* at `1e-15`
/// and `1e-300` (the jitter passed the settled-band rule). `1e-10` leaves three orders above
/// the last radius that worked.
pub const MIN_FP_RADIUS: f64 = 1e-10;

/// Smallest `classifier.trap_margin`. The trap's band only has to cover the error of the
/// cycle's location as the classifier sees it (the bisection bracket is covered by taking
/// the band outside the bracket's ends): the crossings' cubic Hermite interpolation errs by
/// up to about `1e-11` relative at the default step (`squeal_core::defaults::TRAP_MARGIN`,
/// docs/history/benchmarks.md "Early stopping"; it grows as `dt^4`). A narrower band is narrower
/// than what the cycle is known to, and below about `1.1e-16` it is nothing at all in `f64`
/// (`r (1 - margin)` rounds to `r`): `trap_margin = 1e-300` was accepted. `1e-10` is one order
/// above the interpolation's error at the default step; the default `1e-5` is five orders
/// above the bound, six above that error. The argument holds at the default step only: the
/// bound does not follow `integration.dt` (accepted up to 1), and the error grows as `dt^4`,
/// so by that scaling it is about `1.6e-10` at `dt = 0.01` (above the bound) and reaches the
/// default margin near `dt = 0.16`. A coarse step needs a wider margin than the bound allows
/// for; the bound only refuses margins that are too narrow at any step.
pub const MIN_TRAP_MARGIN: f64 = 1e-10;

/// Which rules a spec is read under. A spec given to run is held to every bound of today
/// ([`Rules::Today`]); the spec a file (or journal) stores is read as a description of
/// what was run ([`Rules::Stored`]), so a bound added or tightened since (a `t_max`, `dt`,
/// `fp_radius` or sample count a newer squeal refuses) does not make the file unreadable.
/// Under both, what the plan cannot be built without is refused: text that is not TOML, a
/// missing table or key, a law or key this squeal does not know, a count that is no count,
/// a list that is no pair, and the sizes of a plan (axis and cell counts, sweeps, points),
/// which bound what a reader of the file holds in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Rules {
    /// Every bound: the spec is about to be run.
    Today,
    /// Only what the plan needs to exist: the spec is a file's record of what was run.
    Stored,
}

impl Rules {
    /// Runs `check`, a bound on a value, under [`Rules::Today`]; under [`Rules::Stored`]
    /// the value stands as stored.
    pub(crate) fn bound(
        self,
        check: impl FnOnce() -> Result<(), ScanError>,
    ) -> Result<(), ScanError> {
        match self {
            Rules::Today => check(),
            Rules::Stored => Ok(()),
        }
    }

    /// Under [`Rules::Today`], the error `error` unless `ok` (a bound on a value); under
    /// [`Rules::Stored`] the value stands as stored.
    pub(crate) fn require(
        self,
        ok: bool,
        error: impl FnOnce() -> ScanError,
    ) -> Result<(), ScanError> {
        self.bound(|| if ok { Ok(()) } else { Err(error()) })
    }
}

/// A core check's refusal as a spec error naming `table.<key>` (the parameter the core
/// names); any other core error as the table's.
pub(crate) fn core_error(table: &str, e: squeal_core::CoreError, invalid: Invalid) -> ScanError {
    match e {
        squeal_core::CoreError::InvalidParameter {
            name,
            value,
            expected,
        } => invalid(
            &format!("{table}.{name}"),
            Number(value).to_string(),
            expected,
        ),
        // A belt speed below the step: the message after "invalid lambda = ...: ".
        e @ squeal_core::CoreError::Unresolved { name, value, .. } => {
            let text = e.to_string();
            let expected = text
                .split_once(": ")
                .map_or(text.as_str(), |(_, rest)| rest);
            invalid(
                &format!("{table}.{name}"),
                Number(value).to_string(),
                expected,
            )
        }
        other => invalid(table, String::new(), &other.to_string()),
    }
}

/// The error of a spec stored in a file (or journal), read under [`Rules::Stored`]: what
/// it names is the stored spec's, not one the user gave (the error names the key).
pub(crate) fn in_stored_spec(e: ScanError) -> ScanError {
    match e {
        ScanError::Invalid {
            path,
            key,
            value,
            expected,
        } => ScanError::Invalid {
            path: format!("{path}: this file's stored spec"),
            key,
            value,
            expected,
        },
        ScanError::Parse { path, message } => ScanError::Parse {
            path: format!("{path}: this file's stored spec"),
            message,
        },
        e => e,
    }
}

/// A count read from a spec as the integer type the plan holds it in (`u32`, `u64`,
/// `usize`): a negative one or one too large for the type is refused under any
/// [`Rules`] (the plan could not hold it); `what` says what it counts.
pub(crate) fn count<T: TryFrom<i64>>(
    key: &str,
    n: i64,
    what: &str,
    invalid: Invalid,
) -> Result<T, ScanError> {
    T::try_from(n).map_err(|_| {
        invalid(
            key,
            n.to_string(),
            &format!(
                "{what}: a whole number >= 0 that fits a {}",
                std::any::type_name::<T>()
            ),
        )
    })
}

/// The fixed point's ball against the located unstable cycle of map `map`: its radius must
/// be at most half the cycle's crossing `r_cycle` of the section (the cycle's smallest
/// crossing bracket), else runs that start between the ball and the cycle, and would
/// squeal, are stopped as steady slip.
pub fn fp_radius_inside(fp_radius: f64, r_cycle: f64, map: usize) -> Result<(), ScanError> {
    if fp_radius <= 0.5 * r_cycle {
        return Ok(());
    }
    Err(ScanError::Invalid {
        path: format!("map {map}"),
        key: "classifier.fp_radius".into(),
        value: Number(fp_radius).to_string(),
        expected: format!(
            "a ball well inside the unstable cycle: at most half its section crossing \
             r = {r_cycle:.4} (found by the cycle search before any cell ran)"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inv(key: &str, value: String, expected: &str) -> ScanError {
        ScanError::Invalid {
            path: "t".into(),
            key: key.into(),
            value,
            expected: expected.into(),
        }
    }

    /// The search's range too wide for its samples names the end that made it so: `r_min =
    /// 1e-320` was blamed on `r_max` (r_max / r_min overflowed); with 100000 samples the
    /// same range is fine ((6 / 1e-320)^(1/99999) = 1.0076, taken in logarithms).
    #[test]
    fn a_too_wide_search_names_the_end_that_widened_it() {
        let key_of = |cs: CycleSettings| {
            cycle_search(&cs, &|k| k.to_string(), &inv)
                .err()
                .map(|e| match e {
                    ScanError::Invalid { key, .. } => key,
                    e => panic!("{e}"),
                })
        };
        let d = CycleSettings::default();
        let tiny = CycleSettings { r_min: 1e-320, ..d };
        assert_eq!(key_of(tiny).as_deref(), Some("r_min"));
        assert_eq!(
            key_of(CycleSettings {
                samples: 100_000,
                ..tiny
            }),
            None
        );
        // r_max = 1e6 over 10 samples from the default r_min: r_max's doing.
        let wide = CycleSettings {
            r_max: 1e6,
            samples: 10,
            ..d
        };
        assert_eq!(key_of(wide).as_deref(), Some("r_max"));
    }

    #[test]
    fn ranges_take_exactly_two_finite_ordered_numbers() {
        let ok = state_range("k", &[-2.0, 2.0], Width::Positive, &inv).unwrap();
        assert_eq!(ok, [-2.0, 2.0]);
        for (list, width, want) in [
            (vec![-2.0, 2.0, 3.0], Width::MayBeEmpty, "exactly two"),
            (vec![1.0], Width::MayBeEmpty, "exactly two"),
            (vec![-1e308, 1e308], Width::MayBeEmpty, "1e6"),
            (vec![f64::NAN, 1.0], Width::MayBeEmpty, "finite"),
            (vec![1.0, 1.0], Width::Positive, "an area"),
            (vec![2.0, 1.0], Width::MayBeEmpty, "inverted"),
        ] {
            let e = state_range("k", &list, width, &inv)
                .unwrap_err()
                .to_string();
            assert!(e.contains(want) && e.contains("`k`"), "{list:?}: {e}");
        }
        assert!(state_range("k", &[1.0, 1.0], Width::MayBeEmpty, &inv).is_ok());
    }

    #[test]
    fn the_cycle_search_refuses_ranges_it_cannot_sample() {
        let name = |k: &str| format!("cycle.{k}");
        assert!(cycle_search(&CycleSettings::default(), &name, &inv).is_ok());
        for (r_max, want) in [
            (1e100, "1e6"),
            (f64::INFINITY, "finite"),
            (0.015, "> 2 r_min"),
            // 1e6 with 96 samples: ratio (1e8)^(1/95) = 1.214, accepted; with 40
            // samples (1e8)^(1/39) = 1.604, refused.
        ] {
            let cs = CycleSettings {
                r_max,
                ..Default::default()
            };
            let e = cycle_search(&cs, &name, &inv).unwrap_err().to_string();
            assert!(
                e.contains("cycle.r_max") && e.contains(want),
                "{r_max}: {e}"
            );
        }
        let wide = CycleSettings {
            r_max: 1e6,
            ..Default::default()
        };
        assert!(cycle_search(&wide, &name, &inv).is_ok());
        let coarse = CycleSettings {
            samples: 40,
            ..wide
        };
        let e = cycle_search(&coarse, &name, &inv).unwrap_err().to_string();
        assert!(e.contains("1.6") && e.contains("samples"), "{e}");
    }
}
