//! An atlas in words (`squeal atlas`, `squeal info`): its axes, the points per regime, the
//! maps, and the boundaries found.

use std::path::Path;

use squeal_scan::atlas::{AtlasPlan, AtlasRegime, AtlasResults, BoundaryStatus};

/// The atlas in words: its axes, the points per regime, the maps and the boundaries found,
/// then the file. `computed` is what this run computed (none: the line says nothing of it).
pub fn print_summary(
    plan: &AtlasPlan,
    res: &AtlasResults,
    out: &Path,
    computed: Option<(f64, usize)>,
) {
    let axes = plan.axes();
    let over = if axes.is_empty() {
        "1 parameter point (nothing swept: no chart; the figures are below and in the file)"
            .to_string()
    } else {
        format!(
            "{} points over {}",
            plan.n_points(),
            axes.iter()
                .map(|a| format!("{} ({} values)", a.key, a.values.len()))
                .collect::<Vec<_>>()
                .join(" x ")
        )
    };
    println!(
        "atlas {}: {} law, {over}{}",
        plan.name,
        plan.law,
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
    if let Some(m) = &plan.maps {
        println!(
            "  basin maps: {} x {} cells per point; basin fraction of steady slip from the maps",
            m.grid.x0.count, m.grid.v0.count
        );
    }
    print_boundaries(plan, res);
    println!("{}", out.display());
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
            .params
            .iter()
            .zip(plan.values_at(i))
            .filter(|(a, _)| a.values.len() > 1 && a.key != dkey)
            .map(|(a, v)| {
                format!(
                    "{} = {v:.4} {}",
                    a.key,
                    if a.units == "1" { "" } else { a.units }
                )
            })
            .collect();
        let show = |bd: &squeal_scan::atlas::Boundary| {
            let half = match bd.half_dt_holds {
                Some(true) => "",
                Some(false) => " [moves at dt/2]",
                None => " [dt/2 not checked]",
            };
            match bd.status {
                BoundaryStatus::Found => match plan.boundary_si(i, bd.nu) {
                    Some((v, u)) => {
                        format!("{bkey} = {:.5} ({dkey} = {v:.4} {u}){half}", bd.nu)
                    }
                    None => format!("{bkey} = {:.5}{half}", bd.nu),
                },
                s => s.name().to_string(),
            }
        };
        println!(
            "    {}: fold {}, critical {}",
            if at.is_empty() {
                "here".into()
            } else {
                at.join(", ")
            },
            show(&b.fold),
            show(&b.critical)
        );
    }
}
