//! The progress of `squeal scan`: a bar for the whole scan and one per map of a sweep on a
//! terminal, plain lines off one, the time left weighed by the pilot's cost per cell.

use std::sync::Arc;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};
use squeal_scan::estimate::Estimate;
use squeal_scan::{Observer, Pending, Plan};

use super::progress;

/// The bars and lines of one scan (an [`Observer`] of the driver).
pub struct Bars {
    overall: ProgressBar,
    maps: Vec<ProgressBar>,
    /// The cells done, each weighed by its map's cost per cell (the time left).
    meter: Arc<progress::WorkMeter>,
    plain: Option<progress::PlainLines>,
}

impl Bars {
    /// The terminal bars (the whole scan, and each map of a sweep) and the plain lines off a
    /// terminal for the `pending` cells, the time left weighed by the pilot's cost per cell.
    pub fn new(plan: &Plan, pending: &Pending, pilot: Option<&Estimate>, quiet: bool) -> Bars {
        let multi = MultiProgress::with_draw_target(if progress::show_progress(quiet) {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        });
        let style = progress::bar_style(
            "{prefix:>8} [{bar:40}] {pos}/{len} cells  {avg_rate}  ETA {avg_eta}",
            "cell",
        );
        let counts: Vec<u64> = (0..plan.maps.len())
            .map(|m| pending.cells_of(plan, m) as u64)
            .collect();
        let meter = Arc::new(match pilot {
            // The time left weighs each map's cells by the pilot's cost per cell there.
            Some(e) => progress::WorkMeter::weighted(
                (0..plan.maps.len()).map(|m| e.cell_cost(m)).collect(),
                &counts,
            ),
            None => progress::WorkMeter::uniform(pending.cells as u64),
        });
        let overall = multi.add(
            ProgressBar::new(pending.cells as u64)
                .with_style(progress::metered_bar_style(
                    "{prefix:>8} [{bar:40}] {pos}/{len} cells  {avg_rate}  ETA {avg_eta}",
                    "cell",
                    meter.clone(),
                ))
                .with_prefix("all"),
        );
        let maps = if plan.maps.len() > 1 {
            (0..plan.maps.len())
                .map(|m| {
                    let label = plan.sweep.as_ref().map_or(String::new(), |s| {
                        let v = s.values_at(m);
                        let each = s.names().into_iter().zip(v);
                        let each: Vec<_> = each.map(|(n, x)| format!("{n}={x:.3e}")).collect();
                        each.join(",")
                    });
                    let n = pending.cells_of(plan, m) as u64;
                    if n == 0 {
                        ProgressBar::hidden()
                    } else {
                        multi.add(
                            ProgressBar::new(n)
                                .with_style(style.clone())
                                .with_prefix(label),
                        )
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let plain = progress::PlainLines::with_meter("cells", "cell", meter.clone(), quiet);
        Bars {
            overall,
            maps,
            meter,
            plain,
        }
    }
}

impl Bars {
    /// Clears the bars off the terminal.
    pub fn finish(&self) {
        for b in &self.maps {
            b.finish_and_clear();
        }
        self.overall.finish_and_clear();
    }
}

impl Observer for Bars {
    fn cells_done(&self, map: usize, n: u64) {
        self.meter.add_n(map, n);
        self.overall.inc(n);
        if let Some(p) = &self.plain {
            p.report();
        }
        if let Some(m) = self.maps.get(map) {
            m.inc(n);
        }
    }
}
