//! An atlas in words (`squeal atlas`, `squeal info`): its axes, the points per regime, the
//! maps, and the boundaries found.

use std::path::Path;

use squeal_core::error::Number;
use squeal_scan::atlas::{AtlasPlan, AtlasRegime, AtlasResults, BoundaryStatus};

/// The atlas in words: its axes, the points per regime, the maps and the boundaries found,
/// then the file. `computed` is what this run computed (none: the line says nothing of it).
pub fn print_summary(
    plan: &AtlasPlan,
    res: &AtlasResults,
    out: &Path,
    computed: Option<(f64, usize)>,
) {
    let axes = plan.space.axes();
    let over = if axes.is_empty() {
        "1 parameter point (nothing swept: no chart; the figures are below and in the file)"
            .to_string()
    } else {
        format!(
            "{} points over {}",
            plan.space.n_points(),
            axes.iter()
                .map(|a| format!("{} ({} values)", a.key, a.values.len()))
                .collect::<Vec<_>>()
                .join(" x ")
        )
    };
    println!(
        "atlas {}: {} law, {over}{}",
        plan.name,
        plan.space.law,
        computed.map_or(String::new(), |(seconds, units)| format!(
            ", {units} units computed in {seconds:.1} s"
        ))
    );
    for r in AtlasRegime::ALL {
        let n = res
            .points
            .iter()
            .filter(|p| p.as_ref().is_some_and(|p| p.regime == r))
            .count();
        if n > 0 {
            println!("  {:>6} points: {}", n, r.description());
        }
    }
    // One point: its note (what the runs found, a conflict) and its boundaries' notes.
    if axes.is_empty() {
        let point = res.points.iter().flatten().filter_map(|p| p.note.as_ref());
        let bounds = res
            .boundaries
            .iter()
            .flatten()
            .filter_map(|b| b.note.as_ref());
        for n in point.chain(bounds) {
            println!("  note: {n}");
        }
    }
    if let Some(m) = &plan.maps {
        println!(
            "  basin maps: {} x {} cells per point; basin fraction of steady slip from the maps",
            m.grid.x0.count, m.grid.v0.count
        );
        for w in sensitivity_lines(plan, out) {
            println!("  {w}");
        }
    }
    print_boundaries(plan, res);
    print_fold_warnings(plan, res);
    println!("{}", out.display());
}

/// Loud lines where the fold is less than one clean change: boundaries whose coarse scan
/// found the regime changing more than once along the bisected parameter, and points whose
/// label says some start squeals although they lie above their fold's uncertainty (their
/// stick-slip run stayed for the attractor's window on a band the crisis finds leaking: a
/// long transient).
fn print_fold_warnings(plan: &AtlasPlan, res: &AtlasResults) {
    let flips = res
        .boundaries
        .iter()
        .flatten()
        .filter(|b| b.fold.changes > 1)
        .count();
    if flips > 0 {
        println!(
            "  WARNING: at {flips} of {} boundaries the regime changes more than once along the {} before bisecting (fold_changes; squares on the chart): the fold is the last change",
            res.boundaries.len(),
            plan.boundary_words()
        );
    }
    // The critical value of the operating point should not exceed the fold (above the fold
    // nothing squeals for good). Where it does the two predicates disagree above the fold:
    // the critical one counts a marginal band as squealing and reads the cycle from the
    // points' own search, and a bisection finds one change of its predicate, not the last.
    let crit_above = res
        .boundaries
        .iter()
        .flatten()
        .filter(|b| {
            let (f, c) = (b.fold, b.critical);
            f.status == BoundaryStatus::Found
                && c.status == BoundaryStatus::Found
                && c.bracket[0] > f.nu + f.uncertainty.max(0.5 * (f.bracket[1] - f.bracket[0]))
        })
        .count();
    if crit_above > 0 {
        println!(
            "  WARNING: at {crit_above} of {} boundaries the critical value lies above the fold's uncertainty: its predicate (a marginal band counts as squealing) still changes above the fold there, and the bisection found that change",
            res.boundaries.len()
        );
    }
    // Points above their fold labelled bistable by their run were made undecided
    // (`AtlasResults::reconcile_folds`); any still saying squeal (a repelling fixed point)
    // contradict the fold.
    let above = res.above_fold(plan);
    let conflict = |regime| {
        (above.iter())
            .filter(|&&i| res.points[i].as_ref().is_some_and(|p| p.regime == regime))
            .count()
    };
    let (undecided, repelling) = (
        conflict(AtlasRegime::Undecided),
        conflict(AtlasRegime::FixedPointUnstable),
    );
    if undecided + repelling > 0 {
        println!(
            "  WARNING: of {} points above their fold's uncertainty, {undecided} are undecided (a stick-slip run stayed for the attractor's window on a band the crisis finds leaking: a long transient, or the regime flips there; see their notes) and {repelling} have a repelling fixed point",
            above.len()
        );
    }
}

/// The first 12 boundary searches: where each searched, and the fold and the critical value
/// found there (with their SI values for a physical plan and whether they hold at dt/2).
fn print_boundaries(plan: &AtlasPlan, res: &AtlasResults) {
    let (dkey, _) = plan.boundary_axis();
    let bkey = plan.boundary_key();
    let shown = res.boundaries.len().min(12);
    if shown > 0 {
        println!(
            "  boundaries in the {} (first {shown} of {}):",
            plan.boundary_words(),
            res.boundaries.len()
        );
    }
    for (j, b) in res.boundaries.iter().enumerate().take(shown) {
        let Some(b) = b else { continue };
        let (i, _) = plan.boundary_setup(j);
        let at: Vec<String> = plan
            .space
            .params
            .iter()
            .zip(plan.space.values_at(i))
            .filter(|(a, _)| a.values.len() > 1 && a.key != dkey)
            // A huge value in exponent form ([`Number`]), not written out in full.
            .map(|(a, v)| match a.units {
                "1" => format!("{} = {:.4}", a.key, Number(v)),
                u => format!("{} = {:.4} {u}", a.key, Number(v)),
            })
            .collect();
        println!(
            "    {}: fold {}, critical {}",
            if at.is_empty() {
                "here".into()
            } else {
                at.join(", ")
            },
            boundary_text(plan, i, &b.fold),
            boundary_text(plan, i, &b.critical)
        );
        let l = &b.lifetime;
        if l.mean.is_finite() {
            let period = std::f64::consts::TAU;
            println!(
                "      transient squeal at {bkey} = {:.5}: mean lifetime {:.1} +- {:.1} periods ({:.0}% censored), gamma = {:.2} +- {:.2}",
                l.nu,
                l.mean / period,
                l.se / period,
                100.0 * l.censored,
                l.exponent,
                l.exponent_se
            );
        }
    }
}

/// One boundary of a search as the summary words it: the value with its uncertainty, and
/// for a physical plan the same in SI units beside it, then whether it holds at dt/2.
fn boundary_text(plan: &AtlasPlan, i: usize, bd: &squeal_scan::atlas::Boundary) -> String {
    let (dkey, _) = plan.boundary_axis();
    let bkey = plan.boundary_key();
    let half = match bd.half_dt_holds {
        Some(true) => "",
        Some(false) => " [moves at dt/2]",
        None => " [dt/2 not checked]",
    };
    // The uncertainty stands next to the value it belongs to, in both unit systems: printed
    // after the SI value, a nondimensional "+- 0.00128" read as if it were in N s/m.
    let known = bd.uncertainty.is_finite();
    let err = |e: f64, digits: usize| match known {
        true => format!(" +- {:.digits$}", Number(e)),
        false => String::new(),
    };
    let flips = match bd.changes > 1 {
        true => format!(" [REGIME CHANGES {} TIMES]", bd.changes),
        false => String::new(),
    };
    let value = format!("{bkey} = {:.5}{}", Number(bd.nu), err(bd.uncertainty, 5));
    match bd.status {
        BoundaryStatus::Found => match plan.boundary_si(i, bd.nu) {
            Some((v, u)) => {
                // The SI scale is linear (c = nu 2 sqrt(m k), v_belt = lambda mu_k g /
                // omega_0), so the uncertainty scales as the value does.
                let e = plan
                    .boundary_si(i, bd.uncertainty)
                    .map_or(f64::NAN, |p| p.0);
                format!(
                    "{value} ({dkey} = {:.4}{} {u}){half}{flips}",
                    Number(v),
                    err(e, 4)
                )
            }
            None => format!("{value}{half}{flips}"),
        },
        s => s.name().to_string(),
    }
}

/// The maps' final-state sensitivity over the atlas (crates/core/MODEL.md section 14), read
/// from its file: how many mapped points the log 2 test finds fractal, the range of the
/// uncertainty exponent, and every point whose fates move by more than 1% when the step
/// halves (loudly). Nothing for a file without them.
fn sensitivity_lines(plan: &AtlasPlan, out: &Path) -> Vec<String> {
    let Ok(Some(s)) = squeal_store::atlas::read_map_sensitivity(out, plan) else {
        return Vec::new();
    };
    let mapped = s.log2_test.iter().flatten().count();
    let fractal = (s.log2_test.iter().flatten())
        .filter(|t| **t == squeal_scan::sensitivity::Log2Test::Fractal)
        .count();
    let alpha: Vec<f64> = (s.field("uncertainty_exponent").into_iter())
        .filter(|a| a.is_finite())
        .collect();
    let range = match alpha.is_empty() {
        true => "not fitted at any point".to_string(),
        false => format!(
            "{:.2} to {:.2} over {} points (1: a smooth boundary, below 1: fractal)",
            alpha.iter().copied().fold(f64::INFINITY, f64::min),
            alpha.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            alpha.len()
        ),
    };
    let (share, se) = (s.field("step_sensitivity"), s.field("step_sensitivity_se"));
    let most = (0..share.len())
        .filter(|&i| share[i].is_finite())
        .max_by(|&a, &b| share[a].total_cmp(&share[b]));
    let step = most.map_or("not measured".to_string(), |i| {
        format!("at most {:.1}% +- {:.1}%", 100.0 * share[i], 100.0 * se[i])
    });
    let mut out = vec![format!(
        "final-state sensitivity of the maps: log 2 test fractal at {fractal} of {mapped} mapped points; uncertainty exponent {range}; fates moved by halving the step: {step}"
    )];
    let moved: Vec<String> = (0..share.len())
        .filter(|&i| share[i] > squeal_scan::sensitivity::STEP_SHARE_SMALL)
        .map(|i| {
            let at: Vec<String> = (plan.space.axes().iter().zip(plan.space.unravel(i)))
                .map(|(a, k)| format!("{} = {}", a.key, Number(a.values[k])))
                .collect();
            format!(
                "{} ({:.1}% +- {:.1}%)",
                at.join(", "),
                100.0 * share[i],
                100.0 * se[i]
            )
        })
        .collect();
    if !moved.is_empty() {
        out.push(format!(
            "WARNING: at {} of {mapped} mapped points the fates of more than 1% of the starts near the boundary change when the step halves (the map's labels there depend on dt): {}",
            moved.len(),
            moved.join("; ")
        ));
    }
    out
}
