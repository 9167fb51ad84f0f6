//! Pictures of an atlas: the sheet of its basin maps, and the helpers shared with its chart
//! ([`crate::atlas_chart`]): regime colours, axis words, titles.

use std::path::Path;

use squeal_scan::atlas::{AtlasPlan, AtlasRegime, AtlasResults};

use crate::{PlotError, Rgb};

/// Regime colours, in the order of the enum, and `not computed`.
pub fn regime_classes() -> Vec<(u8, &'static str, Rgb)> {
    vec![
        (
            AtlasRegime::FixedPointUnstable as u8,
            AtlasRegime::FixedPointUnstable.description(),
            Rgb(200, 40, 40),
        ),
        (
            AtlasRegime::BistableSqueals as u8,
            AtlasRegime::BistableSqueals.description(),
            crate::STICK,
        ),
        (
            AtlasRegime::BistableQuiet as u8,
            AtlasRegime::BistableQuiet.description(),
            Rgb(140, 190, 235),
        ),
        (
            AtlasRegime::SteadySlipOnly as u8,
            AtlasRegime::SteadySlipOnly.description(),
            crate::STEADY,
        ),
        (
            AtlasRegime::Undecided as u8,
            AtlasRegime::Undecided.description(),
            crate::UNDECIDED,
        ),
        (255, "not computed", crate::NOT_COMPUTED),
    ]
}

pub(crate) fn is_log(v: &[f64]) -> bool {
    v.len() > 2 && v.iter().all(|&x| x > 0.0) && {
        let r0 = v[1] / v[0];
        let d0 = v[1] - v[0];
        let geo = v
            .windows(2)
            .all(|w| ((w[1] / w[0]) / r0 - 1.0).abs() < 1e-6);
        let lin = v
            .windows(2)
            .all(|w| ((w[1] - w[0]) / d0 - 1.0).abs() < 1e-6);
        geo && !lin
    }
}

pub(crate) fn axis_label(a: &squeal_scan::atlas::ParamAxis) -> String {
    if a.units == "1" {
        a.long_name.to_string()
    } else {
        format!("{} ({})", a.long_name, a.units)
    }
}

pub(crate) fn title(plan: &AtlasPlan, what: Option<&str>) -> String {
    let fixed: Vec<String> = plan
        .space
        .fixed()
        .iter()
        .map(|(a, v)| {
            let u = if a.units == "1" {
                String::new()
            } else {
                format!(" {}", a.units)
            };
            format!("{} = {}{u}", a.key, crate::fmt_value(*v))
        })
        .collect();
    // The spec's name first (docs/atlas-spec.md: "used in titles").
    match what {
        Some(w) => format!(
            "{}: {} law, {w}; {}",
            plan.name,
            plan.space.law,
            fixed.join(", ")
        ),
        None => format!(
            "{}: {} law; {}",
            plan.name,
            plan.space.law,
            fixed.join(", ")
        ),
    }
}

/// Panels per axis of a sheet of maps at most (1-D: `MAX_PANELS_1D` in all).
const MAX_PANELS_AXIS: usize = 6;
const MAX_PANELS_1D: usize = 24;

/// `m` indices of `0..n`, evenly spread, first and last included.
fn pick(n: usize, m: usize) -> Vec<usize> {
    if n <= m {
        return (0..n).collect();
    }
    let mut v: Vec<usize> = (0..m)
        .map(|k| ((k * (n - 1)) as f64 / (m - 1) as f64).round() as usize)
        .collect();
    v.dedup();
    v
}

fn value_text(a: &squeal_scan::atlas::ParamAxis, v: f64) -> String {
    let u = if a.units == "1" {
        String::new()
    } else {
        format!(" {}", a.units)
    };
    format!("{} = {}{u}", a.key, crate::fmt_number(v))
}

/// The sheet of basin maps laid out over the parameter grid: one row of panels per value
/// of the first swept parameter and one column per value of the second (1-D: the values in
/// reading order), at most 6 per axis (24 in 1-D), evenly spread with both ends; further
/// axes at their first value. The title says which were drawn.
pub fn atlas_sheet(plan: &AtlasPlan, res: &AtlasResults, png: &Path) -> Result<(), PlotError> {
    let Some(m) = &plan.maps else {
        return Ok(());
    };
    let g = m.grid;
    // A physical atlas's maps in um and mm/s (one system's units serve every map).
    let si = plan
        .space
        .physical_at(0)
        .map(|ph| ph.scales())
        .map(|s| (s.length * 1e6, s.velocity * 1e3));
    let (lx, lv) = si.unwrap_or((1.0, 1.0));
    let sheet = Sheet {
        plan,
        res,
        picks: drawn_indices(plan),
        x0: g.x0.values().iter().map(|x| x * lx).collect(),
        v0: g.v0.values().iter().map(|v| v * lv).collect(),
        scale: crate::StateScale::of_law(plan.space.law.name()),
        si,
    };
    let data: Vec<(usize, Vec<u8>)> = sheet
        .points()
        .into_iter()
        .map(|i| {
            let labels = res.map_cells(plan, i).map_or_else(
                || vec![squeal_scan::cell::NOT_COMPUTED; g.cells()],
                |c| c.iter().map(|c| c.regime).collect(),
            );
            (i, labels)
        })
        .collect();
    let panels: Vec<crate::BasinPanel> = data
        .iter()
        .map(|(i, labels)| sheet.panel(*i, labels))
        .collect();
    let ncols = match plan.space.axes().len() {
        0 => 1,
        1 => (panels.len() as f64).sqrt().ceil() as usize,
        _ => sheet.picks[1].len(),
    };
    crate::basin_sheet(png, &sheet.title(), &panels, &crate::label_classes(), ncols)
}

/// The drawn indices per swept axis: at most 6 of each of the first two (24 in 1-D), evenly
/// spread with both ends; further axes at their first value.
fn drawn_indices(plan: &AtlasPlan) -> Vec<Vec<usize>> {
    let axes = plan.space.axes().len();
    plan.space
        .shape()
        .iter()
        .enumerate()
        .map(|(k, &n)| match (axes, k) {
            (1, _) => pick(n, MAX_PANELS_1D),
            (_, 0 | 1) => pick(n, MAX_PANELS_AXIS),
            _ => vec![0],
        })
        .collect()
}

/// A sheet of an atlas's maps being laid out.
struct Sheet<'a> {
    plan: &'a AtlasPlan,
    res: &'a AtlasResults,
    /// The drawn indices per swept axis ([`drawn_indices`]).
    picks: Vec<Vec<usize>>,
    x0: Vec<f64>,
    v0: Vec<f64>,
    scale: crate::StateScale,
    /// Micrometres and mm/s per model unit of length and velocity (physical plans).
    si: Option<(f64, f64)>,
}

impl Sheet<'_> {
    /// The drawn points (flat indices, C order), in reading order.
    fn points(&self) -> Vec<usize> {
        let shape = self.plan.space.shape();
        let mut points: Vec<Vec<usize>> = vec![vec![]];
        for p in &self.picks {
            points = points
                .into_iter()
                .flat_map(|pre| {
                    p.iter().map(move |&i| {
                        let mut v = pre.clone();
                        v.push(i);
                        v
                    })
                })
                .collect();
        }
        let flat = |idx: &[usize]| idx.iter().zip(&shape).fold(0, |acc, (i, n)| acc * n + i);
        points.iter().map(|idx| flat(idx)).collect()
    }

    /// Point `i`'s panel: titled by the parameters that differ between panels, its cycle,
    /// fixed point and the state at rest drawn on its map.
    fn panel<'p>(&'p self, i: usize, labels: &'p [u8]) -> crate::BasinPanel<'p> {
        let (plan, values) = (self.plan, self.plan.space.values_at(i));
        let swept: Vec<(&squeal_scan::atlas::ParamAxis, f64)> = plan
            .space
            .params
            .iter()
            .zip(&values)
            .filter(|(a, _)| a.values.len() > 1)
            .map(|(a, &v)| (a, v))
            .collect();
        // Only the parameters that differ between panels (axes 0 and 1).
        let title = swept
            .iter()
            .enumerate()
            .filter(|(k, _)| self.picks[*k].len() > 1)
            .map(|(_, (a, v))| value_text(a, *v))
            .collect::<Vec<_>>()
            .join(", ");
        let (lx, lv) = self.si.unwrap_or((1.0, 1.0));
        let si = |xs: &[f64], l: f64| xs.iter().map(|x| x * l).collect::<Vec<_>>();
        let overlays = self
            .res
            .map_cycle(i)
            .map(|r| crate::cycle_overlay(&si(&r.curve.x, lx), &si(&r.curve.v, lv)))
            .into_iter()
            .collect();
        let fp = plan.space.params_at(i).fixed_point();
        let axis_labels = match self.si {
            Some(_) => [
                "initial displacement x0 (um)".to_string(),
                "initial velocity x'0 (mm/s)".to_string(),
            ],
            None => self.scale.initial_labels().map(String::from),
        };
        crate::BasinPanel {
            axis_labels: Some(axis_labels),
            title: if title.is_empty() {
                plan.name.clone()
            } else {
                title
            },
            x0: &self.x0,
            v0: &self.v0,
            labels,
            overlays,
            markers: crate::state_markers((fp.x * lx, fp.v * lv), &self.x0, &self.v0),
        }
    }

    /// The sheet's title: the name, the law, every fixed parameter, and which panels of
    /// each swept axis are drawn.
    fn title(&self) -> String {
        let (plan, axes) = (self.plan, self.plan.space.axes());
        let drawn: Vec<String> = axes
            .iter()
            .zip(&self.picks)
            .map(|(a, p)| {
                let n = a.values.len();
                if p.len() == n {
                    format!("{}: all {n} values", a.key)
                } else if p.len() == 1 {
                    let first = crate::fmt_number(a.values[0]);
                    format!("{} at its first value {first}", a.key)
                } else {
                    format!("{}: {} of {n} values, evenly spread", a.key, p.len())
                }
            })
            .collect();
        let layout = match axes.len() {
            0 | 1 => String::new(),
            _ => format!("; rows: {}, columns: {}", axes[0].key, axes[1].key),
        };
        format!(
            "{}: basins of attraction, {}, one map per parameter point\n{}, dt = {}, scheme {}\npanels: {}{layout}",
            plan.name,
            crate::law_title(plan.space.law.name()),
            title(plan, None)
                .split_once(": ")
                .map_or(String::new(), |(_, f)| f.to_string()),
            crate::fmt_number(plan.dt),
            plan.solver.scheme.name(),
            drawn.join("; "),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::pick;

    #[test]
    fn sheet_panels_are_spread_evenly_with_both_ends() {
        assert_eq!(pick(4, 6), vec![0, 1, 2, 3]);
        // round(k * 47 / 5): 0, 9.4, 18.8, 28.2, 37.6, 47.
        assert_eq!(pick(48, 6), vec![0, 9, 19, 28, 38, 47]);
        assert_eq!(pick(7, 2), vec![0, 6]);
    }
}
