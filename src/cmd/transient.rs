//! The transient-squeal picture of a scan file: beside the basin map, where some start that
//! ends in steady slip squealed first, a map of its `t_squeal` (`squeal_plot::transient_map`;
//! a sweep's maps as one sheet, `squeal_plot::transient_sheet`).

use std::path::{Path, PathBuf};

use super::common::{attr, check_new, discard, sibling};

/// Draws `<png>-t_squeal.png` for one map of `h5` (already read as `m`, its panel `panel`
/// drawn as the basin map) if some cell squealed before it settled; returns the file drawn.
pub fn draw(
    png: &Path,
    force: bool,
    info: &squeal_store::FileInfo,
    m: &squeal_store::MapData,
    panel: &squeal_plot::BasinPanel<'_>,
) -> anyhow::Result<Option<PathBuf>> {
    let Some(t) = &m.t_squeal else {
        return Ok(None);
    };
    if !squeal_plot::has_transients(&m.labels, t) {
        return Ok(None);
    }
    let out = sibling(png, "-t_squeal", "png");
    check_new(&out, force, "picture")?;
    let title = panel.title.replacen(
        "Basins of attraction",
        "time on stick-slip before steady slip",
        1,
    );
    let bar = bar_words(info);
    let bar: Vec<&str> = bar.iter().map(String::as_str).collect();
    let with_title = squeal_plot::BasinPanel {
        title,
        ..panel.clone()
    };
    squeal_plot::transient_map(&out, &with_title, t, &bar).map_err(|e| discard(&out, e))?;
    Ok(Some(out))
}

/// The colour bar's words: the quantity, its unit, and for a physical scan the seconds of
/// one unit (root attribute `time_unit`).
fn bar_words(info: &squeal_store::FileInfo) -> Vec<String> {
    let mut bar: Vec<String> = ["t_squeal", "nondimensional time", "(natural period 2π)"]
        .map(String::from)
        .into();
    if let Some(u) = attr(info, "time_unit").and_then(|v| v.parse::<f64>().ok()) {
        bar.push(format!("1 unit = {} s", squeal_plot::fmt_value(u)));
    }
    bar
}

/// The sweep's sheet of transient maps, `<png>-t_squeal.png` (the panels of its basin
/// sheet, titled `title` with `ncols` columns), if some cell of some map squealed first.
pub fn draw_sheet(
    (png, force): (&Path, bool),
    info: &squeal_store::FileInfo,
    maps: &[squeal_store::MapData],
    panels: &[squeal_plot::BasinPanel<'_>],
    (title, ncols): (&str, usize),
) -> anyhow::Result<Option<PathBuf>> {
    let Some(ts) = maps
        .iter()
        .map(|m| m.t_squeal.as_deref())
        .collect::<Option<Vec<&[f64]>>>()
    else {
        return Ok(None);
    };
    if !maps
        .iter()
        .zip(&ts)
        .any(|(m, t)| squeal_plot::has_transients(&m.labels, t))
    {
        return Ok(None);
    }
    let out = sibling(png, "-t_squeal", "png");
    check_new(&out, force, "picture")?;
    let title = title.replacen(
        "basins of attraction",
        "time on stick-slip before steady slip",
        1,
    );
    let bar = bar_words(info);
    let bar: Vec<&str> = bar.iter().map(String::as_str).collect();
    squeal_plot::transient_sheet(&out, &title, panels, &ts, (&bar, ncols))
        .map_err(|e| discard(&out, e))?;
    Ok(Some(out))
}
