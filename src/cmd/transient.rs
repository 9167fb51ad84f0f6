//! The transient-squeal picture of a scan file: beside the basin map, where some start that
//! ends in steady slip squealed first, a map of its `t_squeal` (`squeal_plot::transient_map`).

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
    let seconds = attr(info, "time_unit")
        .and_then(|v| v.parse::<f64>().ok())
        .map(|u| format!("1 unit = {} s", squeal_plot::fmt_value(u)));
    let mut bar = vec!["t_squeal", "nondimensional time", "(natural period 2π)"];
    if let Some(s) = &seconds {
        bar.push(s);
    }
    let with_title = squeal_plot::BasinPanel {
        title,
        ..panel.clone()
    };
    squeal_plot::transient_map(&out, &with_title, t, &bar).map_err(|e| discard(&out, e))?;
    Ok(Some(out))
}
