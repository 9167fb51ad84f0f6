//! The transient-squeal picture of a scan file: beside the basin map, where some start that
//! ends in steady slip squealed first, a map of its `t_squeal` (`squeal_plot::transient_map`;
//! a sweep's maps as one sheet, `squeal_plot::transient_sheet`).

use std::path::{Path, PathBuf};

use super::common::{check_new, discard, sibling};

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
    let seconds = in_seconds(info);
    let (bar, t) = (
        bar_words(seconds.as_ref()),
        shown_times(seconds.as_ref(), t),
    );
    let bar: Vec<&str> = bar.iter().map(String::as_str).collect();
    let with_title = squeal_plot::BasinPanel {
        title,
        ..panel.clone()
    };
    squeal_plot::transient_map(&out, &with_title, &t, &bar).map_err(|e| discard(&out, e))?;
    Ok(Some(out))
}

/// Whether a file's transient times are drawn in seconds: a physical scan's (with a time
/// unit), by these scales.
fn in_seconds(info: &squeal_store::FileInfo) -> Option<squeal_core::Scales> {
    super::pictures::file_scales(info).filter(|s| s.time.is_finite())
}

/// The colour bar's words: the quantity and its unit (seconds for a physical scan,
/// [`in_seconds`]).
pub fn bar_words(seconds: Option<&squeal_core::Scales>) -> Vec<String> {
    match seconds {
        Some(_) => vec!["t_squeal".into(), "seconds".into()],
        None => ["t_squeal", "nondimensional time", "(natural period 2π)"]
            .map(String::from)
            .into(),
    }
}

/// The times the colour bar colours: `t_squeal` in seconds for a physical scan (its SI twin,
/// [`squeal_scan::cell::Column::si_of`]), else as stored.
pub fn shown_times(seconds: Option<&squeal_core::Scales>, t: &[f64]) -> Vec<f64> {
    let col = squeal_scan::cell::column("t_squeal").expect("a stored column");
    match seconds {
        Some(s) => t.iter().map(|&v| col.si_of(v, s)).collect(),
        None => t.to_vec(),
    }
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
    let seconds = in_seconds(info);
    let times: Vec<Vec<f64>> = ts
        .iter()
        .map(|t| shown_times(seconds.as_ref(), t))
        .collect();
    let ts: Vec<&[f64]> = times.iter().map(Vec::as_slice).collect();
    let bar = bar_words(seconds.as_ref());
    let bar: Vec<&str> = bar.iter().map(String::as_str).collect();
    squeal_plot::transient_sheet(&out, &title, panels, &ts, (&bar, ncols))
        .map_err(|e| discard(&out, e))?;
    Ok(Some(out))
}
