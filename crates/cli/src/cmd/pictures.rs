//! Pictures of the files squeal writes (`squeal render`, and each command after writing):
//! basin maps and sheets, cycle sizes, with the model in the titles.

use std::path::{Path, PathBuf};

use squeal_plot::{BasinPanel, Curve, Rgb};

use super::common::{attr, check_new, discard, sibling};

/// The model parameters of map `map` of a file, for picture titles (root attributes, with the
/// swept parameter's value of that map).
pub fn model_params(info: &squeal_store::FileInfo, map: usize) -> squeal_plot::ModelParams {
    let num = |key: &str| -> f64 {
        match info.sweep.as_ref().filter(|s| s.names().contains(&key)) {
            Some(s) => s.value(key, map).unwrap_or(f64::NAN),
            None => attr(info, key)
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN),
        }
    };
    let law = attr(info, "law").unwrap_or("?");
    // The law's own keys (files of an unknown law: McMillan's, as files before the
    // Stribeck law).
    let keys = law
        .parse::<squeal_core::FrictionLaw>()
        .map_or(squeal_core::FrictionLaw::McMillan.keys(), |l| l.keys());
    squeal_plot::ModelParams {
        law: law.to_string(),
        params: keys.iter().map(|k| (k.to_string(), num(k))).collect(),
        dt: num("dt"),
    }
}

/// The parameters of a run for picture titles, by the law's own names.
pub fn plot_params(p: &squeal_core::Params, dt: f64) -> squeal_plot::ModelParams {
    squeal_plot::ModelParams {
        law: p.law.name().into(),
        params: p
            .named()
            .iter()
            .map(|n| (n.name.to_string(), n.value))
            .collect(),
        dt,
    }
}

/// The SI size of a physical system's state units, for pictures drawn in m and m/s.
pub fn si_state(s: &squeal_core::Scales) -> squeal_plot::SiState {
    squeal_plot::SiState {
        length: s.length,
        velocity: s.velocity,
        time: s.time,
    }
}

/// A basin panel for one map of a file, its axes in the law's units (`scale`).
pub fn panel(m: &squeal_store::MapData, scale: squeal_plot::StateScale) -> BasinPanel<'_> {
    let overlays = m
        .cycle
        .iter()
        .map(|(x, v)| squeal_plot::cycle_overlay(x, v))
        .collect();
    BasinPanel {
        axis_labels: Some(scale.initial_labels().map(String::from)),
        title: m.title.clone(),
        x0: &m.x0,
        v0: &m.v0,
        labels: &m.labels,
        overlays,
        markers: squeal_plot::state_markers(m.fixed_point, &m.x0, &m.v0),
    }
}

/// Draws the pictures of a finished scan file: the basin map (one map), or a sheet of the
/// maps and the cycle size against the swept parameter (sweeps). Returns the files written.
pub fn render_file(h5: &Path, png: &Path, force: bool) -> anyhow::Result<Vec<PathBuf>> {
    let n = squeal_store::map_count(h5)?;
    let info = squeal_store::read_info(h5)?;
    let scale = squeal_plot::StateScale::of_law(attr(&info, "law").unwrap_or("?"));
    let name = attr(&info, "name").unwrap_or("squeal");
    if n == 1 {
        check_new(png, force, "picture")?;
        let m = squeal_store::read_map(h5, 0)?;
        let units = physical_units(&info);
        let scaled = units.map(|u| scaled_axes(&m, u));
        let mut one = panel(&m, scale);
        if let (Some(u), Some((xs, vs))) = (units, &scaled) {
            to_si(&mut one, xs, vs, u);
        }
        let system = physical_line(&info);
        one.title = format!(
            "{name}: {}{system}",
            squeal_plot::map_title(&model_params(&info, 0))
        );
        // The transient picture first: a whole basin map then means every picture of the
        // map is whole (the rule a rerun after a signal relies on, `common::up_to_date`).
        let transient = super::transient::draw(png, force, &info, &m, &one)?;
        squeal_plot::basin_map(png, &one, &squeal_plot::label_classes())
            .map_err(|e| discard(png, e))?;
        return Ok(std::iter::once(png.to_path_buf())
            .chain(transient)
            .collect());
    }
    // The cycle's size is charted against one swept key; a sweep of several keys has its
    // sizes per map in the file (`cycle_r_section`, ... over `map`).
    let one_key = info.sweep.as_ref().is_none_or(|s| s.single().is_some());
    let size = one_key.then(|| sibling(png, "-cycle", "png"));
    check_new(png, force, "picture")?;
    if let Some(size) = &size {
        check_new(size, force, "picture")?;
    }
    // Each map read once: the sheet draws them, the cycle chart counts their labels.
    let maps: Vec<_> = (0..info.maps)
        .map(|i| squeal_store::read_map(h5, i))
        .collect::<Result<_, _>>()?;
    let transient = render_sheet((png, force), &info, &maps, scale)?;
    if let Some(size) = &size {
        let counts: Vec<[u64; 5]> = (maps.iter())
            .map(|m| squeal_scan::MapSummary::of(&m.labels, m.x0.len(), false).counts)
            .collect();
        render_cycle_sizes(h5, size, &info, &counts)?;
    }
    Ok(std::iter::once(png.to_path_buf())
        .chain(size)
        .chain(transient)
        .collect())
}

/// The sheet of a sweep's maps, one panel per swept value, and beside it their transient
/// squeal where some start squealed first (returned).
fn render_sheet(
    (png, force): (&Path, bool),
    info: &squeal_store::FileInfo,
    maps: &[squeal_store::MapData],
    scale: squeal_plot::StateScale,
) -> anyhow::Result<Option<PathBuf>> {
    let n = maps.len();
    let units = physical_units(info);
    let scaled: Vec<_> = maps
        .iter()
        .map(|m| units.map(|u| scaled_axes(m, u)))
        .collect();
    let axes = SweepAxis::all(info);
    let panels: Vec<_> = maps
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut p = panel(m, scale);
            if let (Some(u), Some((xs, vs))) = (units, &scaled[i]) {
                to_si(&mut p, xs, vs, u);
            }
            let value = |a: &SweepAxis| info.sweep.as_ref().and_then(|s| s.value(&a.swept, i));
            let titles: Vec<_> = (axes.iter())
                .map(|a| a.panel_title(value(a).unwrap_or(f64::NAN)))
                .collect();
            p.title = titles.join(", ");
            p
        })
        .collect();
    // The shared line names every key but the swept ones.
    let mut params = model_params(info, 0);
    params
        .params
        .retain(|(k, _)| !axes.iter().skip(1).any(|a| a.swept == *k));
    let per: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
    let title = squeal_plot::sheet_title_per(
        attr(info, "name").unwrap_or("squeal"),
        &params,
        &axes[0].swept,
        &per.join(" and "),
    ) + &physical_line(info);
    let ncols = (n as f64).sqrt().ceil() as usize;
    // The transient sheet first, as for one map (`render_file`).
    let transient =
        super::transient::draw_sheet((png, force), info, maps, &panels, (&title, ncols))?;
    squeal_plot::basin_sheet(png, &title, &panels, &squeal_plot::label_classes(), ncols)
        .map_err(|e| discard(png, e))?;
    Ok(transient)
}

/// The unstable cycle's size against the swept parameter; values without a cycle marked by
/// what the map found instead (every start squeals, none does, or neither). A physical
/// sweep's in SI units: against `c` (N s/m) or `v_belt` (m/s), the sizes in um and mm/s.
fn render_cycle_sizes(
    h5: &Path,
    size: &Path,
    info: &squeal_store::FileInfo,
    counts: &[[u64; 5]],
) -> anyhow::Result<()> {
    let summary = squeal_store::read_cycle_summary(h5)?;
    let axis = SweepAxis::of(info);
    let words = CycleWords::of(physical_units(info));
    let xs: Vec<f64> = summary.iter().map(|s| axis.value(s.0)).collect();
    let ys = [
        summary.iter().map(|s| s.2 * words.scale[0]).collect(),
        summary.iter().map(|s| s.1 * words.scale[1]).collect(),
    ];
    let colors = [Rgb(200, 60, 20), Rgb(30, 90, 200)];
    let curves: Vec<Curve> = (words.curves.iter().zip(ys).zip(colors))
        .map(|((label, ys), color)| Curve {
            label: label.clone(),
            xs: xs.clone(),
            ys,
            color,
            points_only: false,
        })
        .collect();
    let log_x = ["nu", "xi"].contains(&axis.swept.as_str());
    let missing = squeal_plot::missing_values(&curves, log_x);
    let gaps = squeal_plot::cycle_gaps(&missing, &xs, counts);
    let mut shared = squeal_plot::params_line(&model_params(info, 0), Some(&axis.swept));
    shared.insert_str(
        0,
        &format!(
            "{}, ",
            squeal_plot::law_title(attr(info, "law").unwrap_or("?"))
        ),
    );
    let name = attr(info, "name").unwrap_or("squeal");
    let key = &axis.key;
    squeal_plot::sweep_chart(
        size,
        &format!(
            "{name}: unstable limit cycle size against {key}\n{shared}{}",
            physical_line(info)
        ),
        &axis.label(),
        &words.y_label,
        &curves,
        log_x,
        &gaps,
    )
    .map_err(|e| discard(size, e))
}

/// How a sweep's pictures show its swept parameter: a physical scan's model key as the
/// `[physical]` key given (`nu` as the damping `c` in N s/m, `lambda` as the belt speed
/// `v_belt` in m/s, `phi` as `mu_s`, `tau` in s), from the SI twins the file holds
/// ([`squeal_store::SweptSi`]); any other as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepAxis {
    /// The stored swept parameter (`nu`, `lambda`, `phi`, `xi`, ...).
    pub swept: String,
    /// The name shown: the physical key in a physical scan, else `swept`.
    pub key: String,
    /// The shown value's units (`None`: nondimensional).
    pub units: Option<String>,
    /// Each map's stored value with its SI twin (empty: shown as stored).
    pub si: Vec<(f64, f64)>,
}

impl SweepAxis {
    /// The axis of a sweep file (the first swept key of several; `nu` for a file of one
    /// map).
    pub fn of(info: &squeal_store::FileInfo) -> SweepAxis {
        (SweepAxis::all(info).into_iter().next()).unwrap_or_else(|| SweepAxis::new("nu", &[], None))
    }

    /// The axis of every swept key of a sweep file (`nu` for a file of one map).
    pub fn all(info: &squeal_store::FileInfo) -> Vec<SweepAxis> {
        match &info.sweep {
            Some(s) => (s.keys.iter().zip(&s.si))
                .map(|((k, v), si)| SweepAxis::new(k, v, si.as_ref()))
                .collect(),
            None => vec![SweepAxis::new("nu", &[], None)],
        }
    }

    /// The axis of the swept parameter `swept` with its values at each map, shown as its
    /// twin `si` (the same maps' values in SI units) where the file holds one.
    pub fn new(swept: &str, values: &[f64], si: Option<&squeal_store::SweptSi>) -> SweepAxis {
        match si {
            Some(si) => SweepAxis {
                swept: swept.into(),
                key: si.key.clone(),
                units: si.shown_units().map(str::to_string),
                si: values
                    .iter()
                    .copied()
                    .zip(si.values.iter().copied())
                    .collect(),
            },
            None => SweepAxis {
                swept: swept.into(),
                key: swept.into(),
                units: None,
                si: Vec::new(),
            },
        }
    }

    /// A stored value as shown: its twin at the map that holds it (NaN if none does).
    pub fn value(&self, v: f64) -> f64 {
        if self.si.is_empty() {
            return v;
        }
        (self.si.iter().find(|(m, _)| *m == v)).map_or(f64::NAN, |(_, si)| *si)
    }

    /// The title of the panel of the stored value `v`: `c = 4 N s/m`, `nu = 0.001`.
    pub fn panel_title(&self, v: f64) -> String {
        squeal_plot::panel_title_in(&self.key, self.value(v), self.units.as_deref())
    }

    /// The words of a chart's axis over it.
    pub fn label(&self) -> String {
        match &self.units {
            Some(u) => format!("{} ({u}; swept parameter)", self.key),
            None => format!("{} (swept parameter)", self.key),
        }
    }
}

/// The words and scales of the cycle-size chart ([`render_cycle_sizes`]): the distance from
/// the fixed point along +x and the crossing velocity, in um and mm/s for a physical scan
/// (`units`: um and mm/s per model unit, [`physical_units`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CycleWords {
    /// The two curves' labels.
    pub curves: [String; 2],
    /// What each curve's values are multiplied by.
    pub scale: [f64; 2],
    /// The vertical axis's words.
    pub y_label: String,
}

impl CycleWords {
    /// The words of the chart of a file with `units` (um and mm/s per model unit), if any.
    pub fn of(units: Option<(f64, f64)>) -> CycleWords {
        let what = [
            "distance from the fixed point along +x",
            "velocity x' where the cycle crosses x = x*",
        ];
        match units {
            Some((l, v)) => CycleWords {
                curves: [format!("{} (um)", what[0]), format!("{} (mm/s)", what[1])],
                scale: [l, v],
                y_label: "size of the unstable cycle (um; mm/s)".into(),
            },
            None => CycleWords {
                curves: what.map(String::from),
                scale: [1.0, 1.0],
                y_label: "size of the unstable cycle (nondimensional)".into(),
            },
        }
    }
}

/// The SI size of one model unit of a physical scan file (its `length_unit`,
/// `velocity_unit`, `time_unit` and `damping_unit` attributes; a time or damping unit a
/// file lacks is NaN); `None` for nondimensional files.
pub fn file_scales(info: &squeal_store::FileInfo) -> Option<squeal_core::Scales> {
    let num = |k: &str| attr(info, k).and_then(|v| v.parse::<f64>().ok());
    let time = num("time_unit").unwrap_or(f64::NAN);
    Some(squeal_core::Scales {
        omega0: 1.0 / time,
        time,
        length: num("length_unit")?,
        velocity: num("velocity_unit")?,
        damping: num("damping_unit").unwrap_or(f64::NAN),
    })
}

/// Micrometres and mm/s per nondimensional length and velocity unit of a physical scan file
/// (its `length_unit`, `velocity_unit` attributes); `None` for nondimensional files.
fn physical_units(info: &squeal_store::FileInfo) -> Option<(f64, f64)> {
    file_scales(info).map(|s| (s.length * 1e6, s.velocity * 1e3))
}

/// The physical system of a physical scan file as a title line ("\nm = 2 kg, k = ..."; empty
/// for nondimensional files), from its `physical_<key>` attributes.
fn physical_line(info: &squeal_store::FileInfo) -> String {
    system_line(
        squeal_scan::atlas::spec::PHYSICAL
            .iter()
            .filter_map(|(key, ..)| {
                Some((*key, attr(info, &format!("physical_{key}"))?.parse().ok()?))
            }),
    )
}

/// A physical system as a title line, "\nm = 2 kg, k = 5e4 N/m, ..." (empty for no
/// values): each key with its value and units ([`squeal_scan::atlas::spec::PHYSICAL`]).
pub fn system_line(values: impl IntoIterator<Item = (&'static str, f64)>) -> String {
    let parts: Vec<String> = values
        .into_iter()
        .map(|(key, v)| {
            let units = (squeal_scan::atlas::spec::PHYSICAL.iter())
                .find(|(k, ..)| *k == key)
                .map_or("1", |(.., u)| *u);
            let u = if units == "1" {
                String::new()
            } else {
                format!(" {units}")
            };
            format!("{key} = {}{u}", squeal_plot::fmt_value(v))
        })
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("\n{}", parts.join(", "))
    }
}

/// The physical system `ph` as a title line ([`system_line`]): every key given, and the
/// normal force (the weight m g where none was given).
pub fn physical_system_line(ph: &squeal_core::Physical) -> String {
    let mut values = ph.values();
    values[8] = Some(ph.normal_force());
    let keys = squeal_scan::atlas::spec::PHYSICAL.iter().map(|(k, ..)| *k);
    system_line(keys.zip(values).filter_map(|(k, v)| Some((k, v?))))
}

/// A map's grid in um and mm/s.
fn scaled_axes(m: &squeal_store::MapData, (l, v): (f64, f64)) -> (Vec<f64>, Vec<f64>) {
    (
        m.x0.iter().map(|x| x * l).collect(),
        m.v0.iter().map(|y| y * v).collect(),
    )
}

/// A panel of a physical scan drawn in um and mm/s: the grid `xs`, `vs` (from
/// [`scaled_axes`]), the overlays and markers scaled alike, the axes saying so.
fn to_si<'a>(p: &mut BasinPanel<'a>, xs: &'a [f64], vs: &'a [f64], (l, v): (f64, f64)) {
    p.x0 = xs;
    p.v0 = vs;
    for c in &mut p.overlays {
        c.xs.iter_mut().for_each(|x| *x *= l);
        c.ys.iter_mut().for_each(|y| *y *= v);
    }
    for m in &mut p.markers {
        m.x *= l;
        m.y *= v;
    }
    p.axis_labels = Some([
        "initial displacement x0 (um)".into(),
        "initial velocity x'0 (mm/s)".into(),
    ]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// README's brake (scans/brake.toml): m = 2 kg, k = 50 kN/m, mu_k = 0.35 under g = 9.81:
    /// damping unit 2 sqrt(m k) = 632.456 N s/m, length unit mu_k m g / k = 137.3 um,
    /// velocity unit mu_k g sqrt(m / k) = 21.7 mm/s, time unit sqrt(m / k) = 6.32 ms.
    fn brake() -> squeal_core::Scales {
        let time = (2.0f64 / 5e4).sqrt();
        squeal_core::Scales {
            omega0: 1.0 / time,
            time,
            length: 0.35 * 2.0 * 9.81 / 5e4,
            velocity: 0.35 * 9.81 * time,
            damping: 2.0 * (2.0f64 * 5e4).sqrt(),
        }
    }

    /// The twin a physical scan's file holds beside its swept model key.
    fn twin(key: &str, units: &str, values: &[f64]) -> squeal_store::SweptSi {
        squeal_store::SweptSi {
            key: key.into(),
            units: units.into(),
            values: values.to_vec(),
        }
    }

    /// A physical sweep's pictures name its parameter in SI units: the
    /// panels `c = 4 N s/m` (the map at nu = 4 / 632.456), the cycle chart against
    /// `c (N s/m)` with the sizes in um and mm/s, the transient map's colour bar in
    /// seconds. Before, they said `nu = 0.006325` and "nondimensional". A nondimensional
    /// sweep's words are as they were. The shown value is the file's twin at the map
    /// whose stored value it is (`mu_s` beside `phi`, a ratio: no units).
    #[test]
    fn a_physical_sweeps_pictures_are_in_si_units() {
        let s = brake();
        let nus = [2.0 / s.damping, 4.0 / s.damping];
        let c = SweepAxis::new("nu", &nus, Some(&twin("c", "N s/m", &[2.0, 4.0])));
        assert_eq!(c.panel_title(4.0 / s.damping), "c = 4 N s/m");
        assert_eq!(c.label(), "c (N s/m; swept parameter)");
        assert_eq!(c.value(4.0 / s.damping), 4.0);
        assert!(c.value(3.0 / s.damping).is_nan(), "no map holds it");
        let v = SweepAxis::new(
            "lambda",
            &[0.05 / s.velocity],
            Some(&twin("v_belt", "m/s", &[0.05])),
        );
        assert_eq!(v.panel_title(0.05 / s.velocity), "v_belt = 0.05 m/s");
        let phi = (0.35f64 / 0.45).asin();
        let mu_s = SweepAxis::new("phi", &[phi], Some(&twin("mu_s", "1", &[0.45])));
        assert_eq!(mu_s.panel_title(phi), "mu_s = 0.45");
        assert_eq!(mu_s.label(), "mu_s (swept parameter)");
        let w = CycleWords::of(Some((s.length * 1e6, s.velocity * 1e3)));
        assert_eq!(w.y_label, "size of the unstable cycle (um; mm/s)");
        assert!(w.curves[0].ends_with("(um)") && w.curves[1].ends_with("(mm/s)"));
        let bar = super::super::transient::bar_words(Some(&s));
        assert_eq!(bar, ["t_squeal", "seconds"]);
        let t = [f64::INFINITY, -1.0, 0.0, 100.0];
        let shown = super::super::transient::shown_times(Some(&s), &t);
        // inf (squeals for good) and -1 (not known) are no times: kept as they are.
        assert_eq!(shown, [f64::INFINITY, -1.0, 0.0, 100.0 * s.time]);

        let nu = SweepAxis::new("nu", &[0.001], None);
        assert_eq!(nu.panel_title(0.001), "nu = 0.001");
        assert_eq!(nu.label(), "nu (swept parameter)");
        let w = CycleWords::of(None);
        assert_eq!(w.y_label, "size of the unstable cycle (nondimensional)");
        assert_eq!(w.curves[0], "distance from the fixed point along +x");
        assert_eq!(
            super::super::transient::bar_words(None),
            ["t_squeal", "nondimensional time", "(natural period 2π)"]
        );
        // A nondimensional file (the laws with true stick's) has no twin: xi stays xi.
        assert_eq!(SweepAxis::new("xi", &[0.1], None).key, "xi");
    }
}
