//! The legend beside basin maps and stability charts: swatches, line samples, markers.

use super::*;

/// One row of a basin legend.
pub(crate) enum LegendItem {
    /// A colour swatch with a name and an optional count line.
    Swatch {
        name: String,
        color: Rgb,
        detail: Option<String>,
    },
    /// A line sample (overlay curve).
    Line {
        name: String,
        color: Rgb,
        dots: bool,
    },
    /// A dashed line sample (a curve drawn dashed on top of others).
    Dashed { name: String, color: Rgb },
    /// A marker sample.
    Marker { name: String, color: Rgb },
    /// A glyph sample: the shape filled with `fill`, outlined in black.
    Glyph {
        name: String,
        glyph: Glyph,
        fill: Rgb,
    },
}

/// Draws a vertical legend into `area`, starting at the top.
pub(crate) fn draw_legend(area: &Area<'_>, heading: &str, items: &[LegendItem]) -> DrawResult<()> {
    let x = 12;
    let mut y = 60;
    area.draw_text(heading, &bold(18), (x, y))?;
    y += 34;
    for item in items {
        match item {
            LegendItem::Swatch {
                name,
                color,
                detail,
            } => {
                area.draw(&Rectangle::new(
                    [(x, y), (x + 22, y + 22)],
                    color.color().filled(),
                ))?;
                area.draw(&Rectangle::new([(x, y), (x + 22, y + 22)], BLACK))?;
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                if let Some(d) = detail {
                    area.draw_text(d, &font(14).color(&RGBColor(70, 70, 70)), (x + 32, y + 24))?;
                    y += 50;
                } else {
                    y += 34;
                }
            }
            LegendItem::Line { name, color, dots } => {
                let c = color.color();
                if *dots {
                    for k in 0..4 {
                        area.draw(&Circle::new((x + 2 + 6 * k, y + 11), 2, c.filled()))?;
                    }
                } else {
                    area.draw(&PathElement::new(
                        vec![(x, y + 11), (x + 22, y + 11)],
                        c.stroke_width(2),
                    ))?;
                }
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                y += 34;
            }
            LegendItem::Dashed { name, color } => {
                for k in 0..2 {
                    let x0 = x + 14 * k;
                    area.draw(&PathElement::new(
                        vec![(x0, y + 11), (x0 + 8, y + 11)],
                        color.color().stroke_width(3),
                    ))?;
                }
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                y += 34;
            }
            LegendItem::Marker { name, color } => {
                draw_marker_at(area, (x + 11, y + 11), *color, 7)?;
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                y += 34;
            }
            LegendItem::Glyph { name, glyph, fill } => {
                area.draw(&glyph_element(*glyph, *fill, (x + 11, y + 11)))?;
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                y += 34;
            }
        }
    }
    Ok(())
}

/// Legend rows for the overlays and markers of the given panels (deduplicated by label).
pub(crate) fn overlay_items<'p>(
    panels: impl IntoIterator<Item = &'p BasinPanel<'p>>,
) -> Vec<LegendItem> {
    let mut seen = std::collections::HashSet::new();
    let mut items = Vec::new();
    let panels: Vec<_> = panels.into_iter().collect();
    for p in &panels {
        for c in &p.overlays {
            if !c.label.is_empty() && seen.insert(c.label.clone()) {
                items.push(LegendItem::Line {
                    name: c.label.clone(),
                    color: c.color,
                    dots: c.points_only,
                });
            }
        }
    }
    for p in &panels {
        for m in &p.markers {
            if !m.label.is_empty() && seen.insert(m.label.clone()) {
                items.push(LegendItem::Marker {
                    name: m.label.clone(),
                    color: m.color,
                });
            }
        }
    }
    items
}

pub(crate) const LEGEND_WIDTH: u32 = 245;
