//! The viridis colour scale: the transient-squeal map's ramp and the sensitivity chart's
//! colours, and the colour bar strip both draw.

use plotters::prelude::*;

use crate::{Area, DrawResult, Rgb};

/// Anchors of the viridis colour scale, dark to light.
const VIRIDIS: [Rgb; 5] = [
    Rgb(68, 1, 84),
    Rgb(59, 82, 139),
    Rgb(33, 145, 140),
    Rgb(94, 201, 98),
    Rgb(253, 231, 37),
];

/// The viridis colour scale at `s` in `[0, 1]` (dark to light), linear between five anchors:
/// the transient-squeal map's ramp and the sensitivity chart's scale.
pub(crate) fn viridis(s: f64) -> Rgb {
    let x = s.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    let mix = |p: u8, q: u8| (p as f64 + f * (q as f64 - p as f64)).round() as u8;
    Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A vertical strip of the viridis scale, its top at 1 and its bottom at 0, framed in black:
/// the colour bars of the transient-squeal map and of the sensitivity chart.
pub(crate) fn draw_viridis_strip(
    area: &Area<'_>,
    (x, top, w, h): (i32, i32, i32, i32),
) -> DrawResult<()> {
    for k in 0..h {
        let c = viridis(1.0 - k as f64 / (h - 1) as f64).color();
        area.draw(&Rectangle::new(
            [(x, top + k), (x + w, top + k + 1)],
            c.filled(),
        ))?;
    }
    area.draw(&Rectangle::new([(x, top), (x + w, top + h)], BLACK))?;
    Ok(())
}
