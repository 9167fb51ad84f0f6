//! Basin maps: categorical images of grids of initial conditions, one map or a sheet.

use super::*;
use crate::legend::{LEGEND_WIDTH, LegendItem, draw_legend, overlay_items};

/// A validated grid axis: cell centres `first + i * step`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Axis {
    first: f64,
    step: f64,
    n: usize,
}

impl Axis {
    fn spacing(name: &str, c: &[f64]) -> Result<Option<f64>, PlotError> {
        if c.is_empty() {
            return Err(PlotError::EmptyData("basin grid axis has no points"));
        }
        if let Some(bad) = c.iter().position(|v| !v.is_finite()) {
            return Err(PlotError::InvalidGrid(format!(
                "{name}[{bad}] = {} is not finite",
                c[bad]
            )));
        }
        if c.len() == 1 {
            return Ok(None);
        }
        let n = c.len();
        let step = (c[n - 1] - c[0]) / (n - 1) as f64;
        if step == 0.0 || !step.is_finite() {
            return Err(PlotError::InvalidGrid(format!(
                "{name} is not strictly monotone"
            )));
        }
        for (i, &v) in c.iter().enumerate() {
            let expect = c[0] + i as f64 * step;
            if (v - expect).abs() > 1e-3 * step.abs() {
                return Err(PlotError::InvalidGrid(format!(
                    "{name} is not equally spaced: {name}[{i}] = {v}, expected {expect}"
                )));
            }
        }
        Ok(Some(step))
    }

    /// Extent of the cells, `lo..hi`.
    fn range(&self) -> Range<f64> {
        let last = self.first + (self.n - 1) as f64 * self.step;
        let half = self.step.abs() / 2.0;
        (self.first.min(last) - half)..(self.first.max(last) + half)
    }

    /// Index of the cell containing `v` (clamped to the grid).
    fn index(&self, v: f64) -> usize {
        let i = ((v - self.first) / self.step).round();
        if i <= 0.0 {
            0
        } else {
            (i as usize).min(self.n - 1)
        }
    }
}

/// Validates a panel's shapes and grid.
pub(crate) fn check_panel(panel: &BasinPanel<'_>) -> Result<(Axis, Axis), PlotError> {
    let sx = Axis::spacing("x0", panel.x0)?;
    let sv = Axis::spacing("v0", panel.v0)?;
    let expected = panel.x0.len() * panel.v0.len();
    if panel.labels.len() != expected {
        return Err(PlotError::ShapeMismatch {
            what: format!(
                "basin labels of {:?} (v0.len() = {} rows x x0.len() = {} columns)",
                panel.title,
                panel.v0.len(),
                panel.x0.len()
            ),
            expected,
            found: panel.labels.len(),
        });
    }
    for c in &panel.overlays {
        check_curve(c)?;
    }
    let ax = Axis {
        first: panel.x0[0],
        step: sx.or(sv).unwrap_or(1.0),
        n: panel.x0.len(),
    };
    let av = Axis {
        first: panel.v0[0],
        step: sv.or(sx).unwrap_or(1.0),
        n: panel.v0.len(),
    };
    Ok((ax, av))
}

/// Value-to-class lookup: the first entry of `classes` with a given value wins.
pub(crate) struct Classes<'c> {
    classes: &'c [(u8, &'c str, Rgb)],
    index: [Option<usize>; 256],
}

impl<'c> Classes<'c> {
    pub(crate) fn new(classes: &'c [(u8, &'c str, Rgb)]) -> Self {
        let mut index = [None; 256];
        for (k, &(value, _, _)) in classes.iter().enumerate() {
            index[value as usize].get_or_insert(k);
        }
        Self { classes, index }
    }

    fn color(&self, value: u8) -> Rgb {
        self.index[value as usize].map_or(OTHER, |k| self.classes[k].2)
    }

    /// Cell counts per class, plus the count of cells with other values (last entry); the
    /// cells counted in parallel, by chunks (a 4096 x 4096 map has 16.8M).
    pub(crate) fn counts(&self, labels: &[u8]) -> Vec<usize> {
        use rayon::prelude::*;
        let per_value = labels
            .par_chunks(1 << 16)
            .map(|chunk| {
                let mut n = [0usize; 256];
                for &l in chunk {
                    n[l as usize] += 1;
                }
                n
            })
            .reduce(
                || [0usize; 256],
                |mut a, b| {
                    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                    a
                },
            );
        let mut counts = vec![0; self.classes.len() + 1];
        for (value, &n) in per_value.iter().enumerate() {
            match self.index[value] {
                Some(k) => counts[k] += n,
                None => *counts.last_mut().expect("non-empty") += n,
            }
        }
        counts
    }
}

/// Font sizes and label areas of a basin chart.
#[derive(Clone, Copy)]
pub(crate) struct BasinLayout {
    title: u32,
    axis_desc: u32,
    tick: u32,
    x_area: u32,
    y_area: u32,
    margin: u32,
    marker: i32,
    ticks: usize,
}

pub(crate) const MAP_LAYOUT: BasinLayout = BasinLayout {
    title: 24,
    axis_desc: 21,
    tick: 15,
    x_area: 55,
    y_area: 80,
    margin: 14,
    marker: 7,
    ticks: 10,
};

/// Pixels of one panel of a sheet.
pub(crate) const SHEET_PANEL: (u32, u32) = (440, 420);

/// [`draw_title`]'s height for a sheet's title at size 26 (first line 26, others 21, x 1.3,
/// + 10).
pub(crate) fn sheet_title_height(title: &str) -> u32 {
    let nlines = title.lines().filter(|l| !l.trim().is_empty()).count() as u32;
    if nlines == 0 {
        0
    } else {
        26 * 13 / 10 + (nlines - 1) * (21 * 13 / 10) + 10
    }
}

pub(crate) const SHEET_LAYOUT: BasinLayout = BasinLayout {
    title: 18,
    axis_desc: 14,
    tick: 13,
    x_area: 45,
    y_area: 65,
    margin: 10,
    marker: 6,
    ticks: 6,
};

/// Draws the image, axes, overlays and markers of one panel into `area`.
pub(crate) fn draw_basin_chart(
    area: &Area<'_>,
    panel: &BasinPanel<'_>,
    (ax, av): (Axis, Axis),
    classes: &Classes<'_>,
    layout: BasinLayout,
) -> DrawResult<()> {
    let (xr, vr) = (ax.range(), av.range());
    let body = draw_title(area, &panel.title, layout.title)?;
    let area = &body;
    // Equal scales: shrink the plotting area to the grid's aspect ratio, centred.
    let (m, l) = basin_margins(area.dim_in_pixel(), layout, (xr.clone(), vr.clone()));
    let mut chart = ChartBuilder::on(area)
        .margin_left(m.0)
        .margin_right(m.1)
        .margin_top(m.2)
        .margin_bottom(m.3)
        .x_label_area_size(l.0)
        .y_label_area_size(l.1)
        .build_cartesian_2d(xr.clone(), vr.clone())?;

    draw_image(&chart, panel, (ax, av), classes)?;

    let (xs, vs) = (xr.end - xr.start, vr.end - vr.start);
    let x_fmt = move |v: &f64| fmt_linear(*v, xs);
    let y_fmt = move |v: &f64| fmt_linear(*v, vs);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(
            panel
                .axis_labels
                .as_ref()
                .map_or(X0_LABEL, |l| l[0].as_str()),
        )
        .y_desc(
            panel
                .axis_labels
                .as_ref()
                .map_or(V0_LABEL, |l| l[1].as_str()),
        )
        .axis_desc_style(font(layout.axis_desc))
        .label_style(font(layout.tick))
        .x_labels(layout.ticks)
        .y_labels(layout.ticks)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .draw()?;

    draw_overlays(&mut chart, panel, (xr.clone(), vr.clone()))?;
    for m in &panel.markers {
        if marker_drawable(m, false) && xr.contains(&m.x) && vr.contains(&m.y) {
            // `backend_coord` is absolute; `area` is drawn in coordinates relative to its corner.
            let pos = chart.backend_coord(&(m.x, m.y));
            let (bx, by) = area.get_base_pixel();
            draw_marker_at(area, (pos.0 - bx, pos.1 - by), m.color, layout.marker)?;
        }
    }
    Ok(())
}

/// The image: one nearest-cell lookup per pixel of the plotting area (the rows in
/// parallel, each into its own part of the buffer: the same bytes as one row after the
/// other), blitted at once, and its frame.
fn draw_image(
    chart: &Plane,
    panel: &BasinPanel<'_>,
    (ax, av): (Axis, Axis),
    classes: &Classes<'_>,
) -> DrawResult<()> {
    let (xr, vr) = (ax.range(), av.range());
    let plot = chart.plotting_area().strip_coord_spec();
    let (w, h) = plot.dim_in_pixel();
    if w > 0 && h > 0 {
        let nx = ax.n;
        let cols: Vec<usize> = (0..w)
            .map(|px| ax.index(xr.start + (px as f64 + 0.5) / w as f64 * (xr.end - xr.start)))
            .collect();
        let mut buf = vec![0u8; w as usize * h as usize * 3];
        {
            use rayon::prelude::*;
            buf.par_chunks_mut(w as usize * 3)
                .enumerate()
                .for_each(|(py, out)| {
                    let v = vr.end - (py as f64 + 0.5) / h as f64 * (vr.end - vr.start);
                    let row = &panel.labels[av.index(v) * nx..][..nx];
                    for (px, &i) in out.chunks_exact_mut(3).zip(&cols) {
                        let Rgb(r, g, b) = classes.color(row[i]);
                        px.copy_from_slice(&[r, g, b]);
                    }
                });
        }
        let image = BitMapElement::with_owned_buffer((0, 0), (w, h), buf)
            .ok_or("image buffer has the wrong size")?;
        plot.draw(&image)?;
        plot.draw(&Rectangle::new(
            [(0, 0), (w as i32 - 1, h as i32 - 1)],
            BLACK.stroke_width(1),
        ))?;
    }

    Ok(())
}

/// The overlays (cycles), clipped to the plotting ranges `(xr, vr)`: lines, or dots where a
/// curve is points only.
fn draw_overlays(
    chart: &mut Plane,
    panel: &BasinPanel<'_>,
    (xr, vr): (Range<f64>, Range<f64>),
) -> DrawResult<()> {
    let bounds = (xr, vr);
    for c in &panel.overlays {
        let color = c.color.color();
        if c.points_only {
            chart.draw_series(
                segments(c, false)
                    .into_iter()
                    .flatten()
                    .filter(|(x, y)| bounds.0.contains(x) && bounds.1.contains(y))
                    .map(|p| Circle::new(p, 2, color.filled())),
            )?;
        } else {
            let pieces = segments(c, false)
                .iter()
                .flat_map(|s| clip_polyline(s, &bounds))
                .collect::<Vec<_>>();
            chart.draw_series(
                pieces
                    .into_iter()
                    .map(|s| PathElement::new(s, color.stroke_width(2))),
            )?;
        }
    }
    Ok(())
}

/// Margins (left, right, top, bottom) and label areas (x, y) of a basin chart in an area of
/// `dims` pixels, such that the plotting area has the grid's aspect ratio (equal scales) and
/// sits centred, its labels next to it; grids more than four times longer than wide fill the
/// area instead.
fn basin_margins(
    dims: (u32, u32),
    layout: BasinLayout,
    (xr, vr): (Range<f64>, Range<f64>),
) -> ((u32, u32, u32, u32), (u32, u32)) {
    let avail = (
        dims.0.saturating_sub(2 * layout.margin + layout.y_area),
        dims.1.saturating_sub(2 * layout.margin + layout.x_area),
    );
    let (mut w, mut h) = equal_aspect_fit(avail, xr.end - xr.start, vr.end - vr.start);
    if w < avail.0 / 4 || h < avail.1 / 4 {
        // A grid more than four times longer than wide (e.g. a single row) would become a
        // sliver: use the whole area, unequal scales.
        (w, h) = avail;
    }
    let (ex, ey) = (avail.0 - w, avail.1 - h);
    (
        (
            layout.margin + ex / 2,
            layout.margin + ex - ex / 2,
            layout.margin + ey / 2,
            layout.margin + ey - ey / 2,
        ),
        (layout.x_area, layout.y_area),
    )
}

/// Clips a polyline to the box `bounds`, returning the visible pieces.
pub(crate) fn clip_polyline(
    points: &[(f64, f64)],
    bounds: &(Range<f64>, Range<f64>),
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    if points.len() == 1 {
        return out;
    }
    for pair in points.windows(2) {
        match clip_segment(pair[0], pair[1], bounds) {
            Some((a, b)) => {
                if cur.last() != Some(&a) {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                    cur.push(a);
                }
                cur.push(b);
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// Liang-Barsky clipping of the segment `p`-`q` to `bounds`.
pub(crate) fn clip_segment(
    p: (f64, f64),
    q: (f64, f64),
    (xr, yr): &(Range<f64>, Range<f64>),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, num) in [
        (-dx, p.0 - xr.start),
        (dx, xr.end - p.0),
        (-dy, p.1 - yr.start),
        (dy, yr.end - p.1),
    ] {
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
        } else {
            let t = num / den;
            if den < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            p
        } else if t == 1.0 {
            q
        } else {
            (p.0 + t * dx, p.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

/// The located unstable cycle `(x, v)` as a closed overlay curve of a basin map (the first
/// point repeated at the end), in [`CYCLE`] colour.
pub fn cycle_overlay(x: &[f64], v: &[f64]) -> Curve {
    let mut xs = x.to_vec();
    let mut ys = v.to_vec();
    if let (Some(&a), Some(&b)) = (x.first(), v.first()) {
        xs.push(a);
        ys.push(b);
    }
    Curve {
        label: "unstable limit cycle".into(),
        xs,
        ys,
        color: CYCLE,
        points_only: false,
    }
}

/// The marks of a basin map over the grid `(x0, v0)`: the steady-slip fixed point, and the
/// state at rest `(0, 0)`, the start most engineers ask about, where the grid covers it.
pub fn state_markers(fixed_point: (f64, f64), x0: &[f64], v0: &[f64]) -> Vec<Marker> {
    let mut markers = vec![Marker {
        label: "steady-slip fixed point".into(),
        x: fixed_point.0,
        y: fixed_point.1,
        color: FIXED_POINT,
    }];
    let covers = |axis: &[f64]| {
        axis.first()
            .zip(axis.last())
            .is_some_and(|(a, b)| a.min(*b) <= 0.0 && a.max(*b) >= 0.0)
    };
    if covers(x0) && covers(v0) {
        markers.push(Marker {
            label: "state at rest (0, 0)".into(),
            x: 0.0,
            y: 0.0,
            color: REST,
        });
    }
    markers
}

/// One basin map: a categorical image of `panel.labels` over the grid `(x0, v0)`.
///
/// Each cell value is looked up in `classes` (value, name, colour); a value not in `classes` is
/// drawn in the neutral grey [`OTHER`] and listed in the legend as "other". The legend (right of
/// the map) shows each class name with its colour, cell count and percentage, then the labelled
/// overlays and markers. Axes: `x0` horizontal ([`X0_LABEL`]), `v0` vertical ([`V0_LABEL`]), at
/// equal scales (the plotting area takes the grid's aspect ratio). The overlays (e.g.
/// the unstable limit cycle, clipped to the grid extent) and markers (fixed point) are drawn on
/// top. Build the title with [`map_title`]. Size 900x800; the image is resampled nearest-cell to
/// the plotting area, so any grid size renders quickly.
pub fn basin_map(
    path: &Path,
    panel: &BasinPanel<'_>,
    classes: &[(u8, &str, Rgb)],
) -> Result<(), PlotError> {
    let axes = check_panel(panel)?;
    let lookup = Classes::new(classes);
    let counts = lookup.counts(panel.labels);
    let total = panel.labels.len();
    let mut items: Vec<LegendItem> = classes
        .iter()
        .zip(&counts)
        .enumerate()
        .filter(|&(k, ((v, _, _), _))| lookup.index[*v as usize] == Some(k))
        .map(|(_, (&(_, name, color), &n))| LegendItem::Swatch {
            name: name.to_string(),
            color,
            detail: Some(count_text(n, total)),
        })
        .collect();
    let others = counts[classes.len()];
    if others > 0 {
        items.push(LegendItem::Swatch {
            name: "other".into(),
            color: OTHER,
            detail: Some(count_text(others, total)),
        });
    }
    items.extend(overlay_items([panel]));
    render(path, (900, 800), |root| {
        let (left, right) = root.split_horizontally(900 - LEGEND_WIDTH);
        draw_basin_chart(&left, panel, axes, &lookup, MAP_LAYOUT)?;
        draw_legend(&right, &format!("{total} cells"), &items)
    })
}

fn count_text(n: usize, total: usize) -> String {
    let pct = if total > 0 {
        100.0 * n as f64 / total as f64
    } else {
        0.0
    };
    format!("{n} ({pct:.1}%)")
}

/// A sheet of several basin maps (e.g. one per damping value) in a grid with `ncols` columns.
///
/// Each panel gets its own small title (`panel.title`) and axes; one shared legend on the right
/// lists the classes (and "other" if any panel has a value not in `classes`), then the labelled
/// overlays and markers of all panels (deduplicated by label); `title` is the overall title.
/// `ncols` is clamped to `1..=panels.len()`. Each panel is 440x420 pixels, its map drawn at
/// equal scales. Build the titles with [`sheet_title`] and [`panel_title`].
pub fn basin_sheet(
    path: &Path,
    title: &str,
    panels: &[BasinPanel<'_>],
    classes: &[(u8, &str, Rgb)],
    ncols: usize,
) -> Result<(), PlotError> {
    if panels.is_empty() {
        return Err(PlotError::EmptyData("basin sheet without panels"));
    }
    let axes = panels
        .iter()
        .map(check_panel)
        .collect::<Result<Vec<_>, _>>()?;
    let lookup = Classes::new(classes);
    let ncols = ncols.clamp(1, panels.len());
    let nrows = panels.len().div_ceil(ncols);
    let (panel_w, panel_h) = SHEET_PANEL;
    let title_h = sheet_title_height(title);
    let width = ncols as u32 * panel_w + LEGEND_WIDTH;
    let height = title_h + nrows as u32 * panel_h;

    let mut items: Vec<LegendItem> = classes
        .iter()
        .enumerate()
        .filter(|&(k, (v, _, _))| lookup.index[*v as usize] == Some(k))
        .map(|(_, &(_, name, color))| LegendItem::Swatch {
            name: name.to_string(),
            color,
            detail: None,
        })
        .collect();
    if panels
        .iter()
        .any(|p| p.labels.iter().any(|&l| lookup.index[l as usize].is_none()))
    {
        items.push(LegendItem::Swatch {
            name: "other".into(),
            color: OTHER,
            detail: None,
        });
    }
    items.extend(overlay_items(panels));

    render(path, (width, height), |root| {
        let body = draw_title(root, title, 26)?;
        let (grid, legend) = body.split_horizontally(ncols as u32 * panel_w);
        let cells = grid.split_evenly((nrows, ncols));
        for ((panel, ax), cell) in panels.iter().zip(axes).zip(&cells) {
            draw_basin_chart(cell, panel, ax, &lookup, SHEET_LAYOUT)?;
        }
        draw_legend(&legend, "Legend", &items)
    })
}
