//! PNG pictures for squeal: phase planes, friction curves, parameter sweeps and basin maps.
//!
//! Everything is rendered with [`plotters`]' bitmap backend and written straight to a file.
//! Text is drawn with the DejaVu Sans font embedded in the binary (crate `dejavu`), registered
//! once with plotters' `ab_glyph` support, so no system font library (fontconfig, freetype) is
//! needed at run time.
//!
//! Entry points:
//!
//! * [`line_plot`]: curves (polylines or scatter) plus labelled [`Marker`]s, with axes, tick
//!   values, axis labels, a title and a legend; optionally a logarithmic x axis.
//! * [`phase_plot`]: a phase plane `(x, x')` with equal scales on both axes (a circle is drawn
//!   as a circle) and the axis labels of the law's [`StateScale`].
//! * [`sweep_chart`]: a quantity against a swept parameter, with the values where it does not
//!   exist (e.g. no unstable cycle) marked on the axis and listed in the legend.
//! * [`basin_map`]: one categorical image of a grid of initial conditions `(x0, x'0)`, each cell
//!   coloured by its class, with a legend giving each class's cell count, plus overlays (e.g. the
//!   unstable limit cycle) and markers (e.g. the fixed point) drawn on top. Equal scales on
//!   both axes.
//! * [`basin_sheet`]: several basin maps in a grid of panels with one shared legend.
//! * [`stability_chart`]: parameter-plane cells coloured by regime, with contours and
//!   boundary curves; [`atlas_chart`] and [`atlas_sheet`] draw an atlas's chart and its sheet
//!   of maps from its plan and results (`squeal_scan::atlas`), the only pictures that know
//!   squeal's types; the others take plain numbers.
//!
//! Titles are built by functions that return strings, so callers and tests see the text:
//! [`map_title`], [`sheet_title`], [`panel_title`] and [`phase_title`] from a
//! [`ModelParams`]; numbers are written by [`fmt_number`] (four significant digits). A title
//! may hold several lines separated by `\n`.
//!
//! Units: squeal's variables are nondimensional, each law in its own scale ([`StateScale`]):
//! under McMillan's laws (crates/core/MODEL.md, "Units") a displacement is measured in units of
//! `mu_k m g / k` (the spring's stretch under the kinetic friction force) and a velocity in
//! units of `mu_k g sqrt(m/k)`; under the Stribeck law in `m g / k` and `g sqrt(m/k)`. The
//! axis labels say so; a basin map of a physical scan is drawn in um and mm/s.
//!
//! The output format follows the file extension of `path` (use `.png`); the parent directory must
//! exist. All input is validated before anything is drawn: bad shapes or empty data give a
//! [`PlotError`], never a panic.
//!
//! The palette constants [`STEADY`], [`STICK`], [`UNDECIDED`], [`NOT_COMPUTED`], [`OTHER`],
//! [`CYCLE`] and [`FIXED_POINT`] are suggestions for the classes and overlays of a basin map.

mod atlas;
mod atlas_chart;
mod atlas_sensitivity;
mod atlas_sheet;
mod basin;
mod legend;
mod lifetime_chart;
mod line;
mod transient;

pub use atlas::{Marks, StabilityChart, contour_segments, fmt_value, stability_chart};
pub use atlas_chart::atlas_chart;
pub use atlas_sensitivity::{atlas_sensitivity, has_sensitivity, sensitivity_path};
pub use atlas_sheet::{atlas_sheet, regime_classes};
pub use basin::{basin_map, basin_sheet, cycle_overlay, state_markers};
pub use lifetime_chart::{fold_lifetime_charts, fold_lifetime_paths, has_fold_lifetimes};
pub use line::{
    Gap, cycle_gaps, cycle_plot, line_plot, missing_values, phase_plot, phase_plot_si, sweep_chart,
    trajectory_plot,
};
pub use transient::{has_transients, transient_map, transient_sheet};

use std::error::Error as StdError;

use squeal_core::error::Number;
use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

/// RGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    fn color(self) -> RGBColor {
        RGBColor(self.0, self.1, self.2)
    }
}

mod viridis;
pub(crate) use viridis::{draw_viridis_strip, viridis};

/// Steady slip (the orbit settles on the fixed point): blue.
pub const STEADY: Rgb = Rgb(49, 110, 198);
/// Stick-slip (the orbit settles on the stable stick-slip cycle): orange.
pub const STICK: Rgb = Rgb(238, 118, 22);
/// Undecided (time limit reached): bright magenta, visible against blue and orange.
pub const UNDECIDED: Rgb = Rgb(230, 0, 200);
/// Not computed (yet): light grey.
pub const NOT_COMPUTED: Rgb = Rgb(222, 222, 222);
/// Cells of the small slip oscillation about an unstable steady slip: purple.
pub const SLIP_OSCILLATION: Rgb = Rgb(148, 103, 189);
/// Cells whose value is not among the classes passed to [`basin_map`]: neutral grey.
pub const OTHER: Rgb = Rgb(128, 128, 128);
/// Overlay curves such as the unstable limit cycle: black.
pub const CYCLE: Rgb = Rgb(0, 0, 0);
/// Marker for the fixed point: black (markers get a white halo, so they stay visible).
pub const FIXED_POINT: Rgb = Rgb(0, 0, 0);
/// Marker for the state at rest `(0, 0)` on basin maps: dark red.
pub const REST: Rgb = Rgb(190, 0, 30);
/// Marks of swept values without data in a [`sweep_chart`]: dark red.
pub const MISSING: Rgb = Rgb(180, 20, 40);

/// The classes of a basin map's labels (value, name, colour), in the order of the HDF5 enum
/// of the files: steady slip, stick-slip, slip oscillation, undecided, not computed.
pub fn label_classes() -> Vec<(u8, &'static str, Rgb)> {
    vec![
        (1, "steady slip", STEADY),
        (2, "stick-slip", STICK),
        (3, "slip oscillation", SLIP_OSCILLATION),
        (0, "undecided", UNDECIDED),
        (255, "not computed", NOT_COMPUTED),
    ]
}

/// Errors from the plotting functions.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// Drawing or writing the file failed; the message starts with the file path.
    #[error("cannot draw {0}")]
    Draw(String),
    /// There is nothing to draw (no curves, an empty grid, no panels).
    #[error("nothing to plot: {0}")]
    EmptyData(&'static str),
    /// Two pieces of data that must have matching lengths do not.
    #[error("shape mismatch in {what}: expected {expected} values, found {found}")]
    ShapeMismatch {
        /// Which data (e.g. `"curve \"orbit\": ys vs xs"`, `"basin labels"`).
        what: String,
        /// The length implied by the other data.
        expected: usize,
        /// The actual length.
        found: usize,
    },
    /// A curve has no point that can be drawn (finite, and with `x > 0` on a log axis).
    #[error(
        "curve {label:?} has no drawable point (all non-finite, empty, or x <= 0 on a log axis)"
    )]
    NoDrawablePoint {
        /// The curve's label.
        label: String,
    },
    /// A basin grid axis is not finite, not strictly monotone or not equally spaced.
    #[error("invalid grid: {0}")]
    InvalidGrid(String),
    /// An axis's data span a range the plot cannot draw: beyond [`MAX_AXIS`] in size, or
    /// narrower than [`MIN_AXIS_SPAN`] (the plotting library's tick search looped for ever
    /// on `squeal friction --mu-k 5e307`).
    #[error(
        "the {axis} axis would span [{}, {}]: a plot draws values within +-1e300 over a width of at least 1e-300",
        Number(*lo),
        Number(*hi)
    )]
    AxisRange {
        /// Which axis ("x" or "y").
        axis: &'static str,
        /// Its smallest value.
        lo: f64,
        /// Its largest value.
        hi: f64,
    },
}

/// Largest magnitude a plot's axis reaches ([`PlotError::AxisRange`]).
pub const MAX_AXIS: f64 = 1e300;
/// Smallest width of a plot's axis, its padding included ([`PlotError::AxisRange`]).
pub const MIN_AXIS_SPAN: f64 = 1e-300;

/// Refuses an axis over the data `[lo, hi]` that the plot cannot draw: padded as [`padded`]
/// pads it, its ends must lie within [`MAX_AXIS`] and its width be at least
/// [`MIN_AXIS_SPAN`].
pub fn check_axis(axis: &'static str, lo: f64, hi: f64) -> Result<(), PlotError> {
    let r = padded(lo, hi, 0.05);
    let fine = |x: f64| x.is_finite() && x.abs() <= MAX_AXIS;
    if fine(r.start) && fine(r.end) && r.end - r.start >= MIN_AXIS_SPAN {
        Ok(())
    } else {
        Err(PlotError::AxisRange { axis, lo, hi })
    }
}

/// A polyline (or scatter if `points_only`).
///
/// Non-finite points are skipped; a polyline is broken at them rather than joined across.
/// An empty `label` gives no legend entry.
#[derive(Clone, Debug)]
pub struct Curve {
    /// Legend label (empty: no legend entry).
    pub label: String,
    /// x coordinates.
    pub xs: Vec<f64>,
    /// y coordinates, same length as `xs`.
    pub ys: Vec<f64>,
    /// Line or point colour.
    pub color: Rgb,
    /// Draw small dots instead of a line.
    pub points_only: bool,
}

/// The shape of a mark that is not a curve (the gaps of a [`sweep_chart`], flagged points of a
/// [`stability_chart`]): marks for different reasons get different shapes, so they are told
/// apart without relying on colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Glyph {
    /// A triangle pointing up.
    TriangleUp,
    /// A triangle pointing down.
    TriangleDown,
    /// A diamond.
    Diamond,
    /// A square.
    Square,
}

impl Glyph {
    /// The outline in pixels about the mark's centre (y grows downwards).
    pub(crate) fn outline(self) -> Vec<(i32, i32)> {
        match self {
            Glyph::TriangleUp => vec![(0, -7), (-7, 6), (7, 6)],
            Glyph::TriangleDown => vec![(0, 7), (-7, -6), (7, -6)],
            Glyph::Diamond => vec![(0, -8), (-7, 0), (0, 8), (7, 0)],
            Glyph::Square => vec![(-6, -6), (6, -6), (6, 6), (-6, 6)],
        }
    }

    /// The outline closed (its first vertex repeated), for drawing it as a path.
    pub(crate) fn closed(self) -> Vec<(i32, i32)> {
        let mut v = self.outline();
        v.push(v[0]);
        v
    }
}

/// A glyph at a point: its fill, then its outline, in pixels about the point.
pub(crate) type GlyphElement<C, DB> =
    plotters::element::ComposedElement<C, DB, Polygon<(i32, i32)>, PathElement<(i32, i32)>>;

/// A glyph filled with `fill` and outlined in black, centred at `at` (of any coordinate
/// system: the shape itself is in pixels).
pub(crate) fn glyph_element<DB: DrawingBackend, C>(
    glyph: Glyph,
    fill: Rgb,
    at: C,
) -> GlyphElement<C, DB> {
    EmptyElement::at(at)
        + Polygon::new(glyph.outline(), fill.color().filled())
        + PathElement::new(glyph.closed(), BLACK.stroke_width(2))
}

/// A marked point (e.g. the fixed point (1,0)), drawn as a cross in a circle with a legend label.
///
/// Markers with a non-finite coordinate are not drawn. An empty `label` gives no legend entry.
#[derive(Clone, Debug)]
pub struct Marker {
    /// Legend label (empty: no legend entry).
    pub label: String,
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// Colour of the cross and circle.
    pub color: Rgb,
}

/// One basin map: a categorical image over a grid of initial conditions.
///
/// `labels` is row-major with shape `(v0.len(), x0.len())`: `labels[j * x0.len() + i]` is the
/// cell at `(x0[i], v0[j])`. Grid coordinates are cell centres, equally spaced (ascending or
/// descending); `x0`/`v0` may have length 1, in which case the cell is given the spacing of the
/// other axis (or width 1 if both have length 1).
#[derive(Clone, Debug)]
pub struct BasinPanel<'a> {
    /// Title of the map (the panel title in a [`basin_sheet`]).
    pub title: String,
    /// Cell centres along the horizontal axis (`x0`).
    pub x0: &'a [f64],
    /// Cell centres along the vertical axis (`x'0`).
    pub v0: &'a [f64],
    /// Cell values, row-major, `v0.len() * x0.len()` of them.
    pub labels: &'a [u8],
    /// Curves drawn on top of the image, clipped to it (e.g. the unstable limit cycle).
    pub overlays: Vec<Curve>,
    /// Points marked on top of everything (e.g. the fixed point). Markers outside the grid
    /// extent are listed in the legend but not drawn.
    pub markers: Vec<Marker>,
    /// Axis labels (horizontal, vertical) when the coordinates are not the nondimensional
    /// ones of [`X0_LABEL`] and [`V0_LABEL`] (e.g. a physical scan drawn in um and mm/s).
    pub axis_labels: Option<[String; 2]>,
}

// ---------------------------------------------------------------------------------------------
// Titles and axis labels
// ---------------------------------------------------------------------------------------------

/// Horizontal axis of a phase plane.
pub const X_LABEL: &str = "displacement x (unit: μk m g / k)";
/// Vertical axis of a phase plane.
pub const V_LABEL: &str = "velocity x' (unit: μk g √(m/k))";
/// Horizontal axis of a basin map.
pub const X0_LABEL: &str = "initial displacement x0 (unit: μk m g / k)";
/// Vertical axis of a basin map.
pub const V0_LABEL: &str = "initial velocity x'0 (unit: μk g √(m/k))";

/// A physical system's state in SI units: metres per model unit of `x`, m/s per model unit
/// of `x'` (its `length_unit` and `velocity_unit`), for pictures drawn in SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SiState {
    /// Metres per model unit of `x`.
    pub length: f64,
    /// m/s per model unit of `x'`.
    pub velocity: f64,
    /// Seconds per model unit of time.
    pub time: f64,
}

impl SiState {
    /// Horizontal and vertical axis words of a phase plane `(x, x')` in SI units.
    pub const PHASE_LABELS: [&'static str; 2] = ["displacement x (m)", "velocity x' (m/s)"];
}

/// The unit of a picture's state axes: each friction law is written in its own
/// nondimensional variables, so the axis words follow the law.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StateScale {
    /// McMillan's laws (crates/core/MODEL.md, section 2): the equation is divided by the
    /// kinetic friction force `μk m g`, so `x` is in `μk m g / k` and `x'` in `μk g √(m/k)`.
    KineticFriction,
    /// The Stribeck law (bSTAB's friction case, MODEL.md section 8): the friction
    /// coefficient itself is the force, i.e. the equation is divided by the normal load `m g`,
    /// so `x` is in `m g / k` and `x'` in `g √(m/k)` (no `μk`: there is no kinetic scale).
    NormalLoad,
}

impl StateScale {
    /// The scale of the law named `law` (the spec's `law` key): the laws with true stick
    /// are written in the normal load, McMillan's (and an unknown name) in the kinetic
    /// friction.
    pub fn of_law(law: &str) -> StateScale {
        match law.parse::<squeal_core::FrictionLaw>() {
            Ok(l) if l.family().in_normal_load() => StateScale::NormalLoad,
            _ => StateScale::KineticFriction,
        }
    }

    /// Horizontal and vertical axis words of a phase plane `(x, x')`.
    pub fn phase_labels(self) -> [&'static str; 2] {
        match self {
            StateScale::KineticFriction => [X_LABEL, V_LABEL],
            StateScale::NormalLoad => [
                "displacement x (unit: m g / k)",
                "velocity x' (unit: g √(m/k))",
            ],
        }
    }

    /// Horizontal and vertical axis words of a basin map `(x0, x'0)`.
    pub fn initial_labels(self) -> [&'static str; 2] {
        match self {
            StateScale::KineticFriction => [X0_LABEL, V0_LABEL],
            StateScale::NormalLoad => [
                "initial displacement x0 (unit: m g / k)",
                "initial velocity x'0 (unit: g √(m/k))",
            ],
        }
    }
}

/// The nondimensional model parameters and step shown in titles (the names of the spec keys
/// and of the HDF5 attributes). Callers fill this in from `Params` and the step, so the
/// drawing functions stay free of the model's types.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelParams {
    /// The friction law's name (`mcmillan`, `mcmillan-nonhysteretic`, `coulomb`, `stribeck`).
    pub law: String,
    /// The law's own parameters in order, by their names: `nu, lambda, tau, phi` for
    /// McMillan's laws, `xi, v_d, mu_d, mu_sd, v_0, mu_v` for the Stribeck law.
    pub params: Vec<(String, f64)>,
    /// Time step.
    pub dt: f64,
}

impl ModelParams {
    /// McMillan's four parameters.
    pub fn mcmillan(law: &str, nu: f64, lambda: f64, tau: f64, phi: f64, dt: f64) -> Self {
        ModelParams {
            law: law.into(),
            params: [("nu", nu), ("lambda", lambda), ("tau", tau), ("phi", phi)]
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
            dt,
        }
    }

    /// The value of parameter `name`, if the law has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.params.iter().find(|(k, _)| k == name).map(|(_, v)| *v)
    }
}

/// A number with at most four significant digits, trailing zeros dropped, scientific notation
/// outside `[1e-3, 1e5)`: `0.0010000000000000002` is `0.001`, `0.31622776` is `0.3162`,
/// `1.5e-5` is `1.5e-5`.
pub fn fmt_number(v: f64) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    fmt_sig(v)
}

/// How a law is named in titles.
/// How a law is named in titles ([`squeal_core::FrictionLaw::title`]; an unknown name as
/// it is).
pub fn law_title(law: &str) -> String {
    law.parse::<squeal_core::FrictionLaw>()
        .map_or_else(|_| law.to_string(), |l| l.title().to_string())
}

/// `nu = 0.001, lambda = 3, tau = 0.3162, phi = 1, dt = 0.01` (the law's own parameters,
/// then the step), leaving out `skip` (the swept parameter of a sheet).
pub fn params_line(p: &ModelParams, skip: Option<&str>) -> String {
    p.params
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .chain([("dt", p.dt)])
        .filter(|(name, _)| Some(*name) != skip)
        .map(|(name, v)| format!("{name} = {}", fmt_number(v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Title of one basin map: the law, then every parameter and the step.
pub fn map_title(p: &ModelParams) -> String {
    format!(
        "Basins of attraction, {}\n{}",
        law_title(&p.law),
        params_line(p, None)
    )
}

/// Overall title of a sheet of maps sweeping `swept`: `name`, the law, then the parameters
/// shared by all maps (`p` holds them; its value of `swept` is not shown).
pub fn sheet_title(name: &str, p: &ModelParams, swept: &str) -> String {
    sheet_title_per(name, p, swept, swept)
}

/// [`sheet_title`] of a sheet whose panels are named by `per` (a physical sweep's `c` for
/// its swept `nu`).
pub fn sheet_title_per(name: &str, p: &ModelParams, swept: &str, per: &str) -> String {
    format!(
        "{name}: basins of attraction, {}, one map per {per}\n{}",
        law_title(&p.law),
        params_line(p, Some(swept))
    )
}

/// Title of one panel of a sheet: `nu = 0.001`.
pub fn panel_title(swept: &str, value: f64) -> String {
    format!("{swept} = {}", fmt_number(value))
}

/// [`panel_title`] with units: `c = 4 N s/m` (none: as [`panel_title`]).
pub fn panel_title_in(swept: &str, value: f64, units: Option<&str>) -> String {
    match units {
        Some(u) => format!("{} {u}", panel_title(swept, value)),
        None => panel_title(swept, value),
    }
}

/// Title of a phase-plane picture: `what`, the law, then every parameter and the step.
pub fn phase_title(what: &str, p: &ModelParams) -> String {
    format!("{what}, {}\n{}", law_title(&p.law), params_line(p, None))
}

/// The largest `(w, h)` inside `avail` with `w / h = x_span / y_span`: one data unit has the
/// same length in pixels on both axes. Spans must be positive; a zero pixel size stays zero.
pub fn equal_aspect_fit(avail: (u32, u32), x_span: f64, y_span: f64) -> (u32, u32) {
    let (aw, ah) = (avail.0 as f64, avail.1 as f64);
    if !(x_span > 0.0 && y_span > 0.0 && x_span.is_finite() && y_span.is_finite()) {
        return avail;
    }
    let scale = (aw / x_span).min(ah / y_span);
    let w = (x_span * scale).round().min(aw) as u32;
    let h = (y_span * scale).round().min(ah) as u32;
    (w, h)
}

/// Widens `x` or `y` about its centre so that, drawn into `pixels`, one data unit has the same
/// length in pixels on both axes (the data stay in view; nothing is cut).
pub fn equal_aspect_ranges(
    x: Range<f64>,
    y: Range<f64>,
    pixels: (u32, u32),
) -> (Range<f64>, Range<f64>) {
    let (w, h) = (pixels.0.max(1) as f64, pixels.1.max(1) as f64);
    let (sx, sy) = (x.end - x.start, y.end - y.start);
    if !(sx > 0.0 && sy > 0.0) {
        return (x, y);
    }
    // Units per pixel: the larger wins, the other range is widened to match.
    let upp = (sx / w).max(sy / h);
    let widen = |r: Range<f64>, span: f64| {
        let c = 0.5 * (r.start + r.end);
        (c - 0.5 * span)..(c + 0.5 * span)
    };
    (widen(x, upp * w), widen(y, upp * h))
}

/// The labelled ticks of a logarithmic axis over `lo..hi` (both > 0): powers of ten when the
/// axis spans more than 2.5 decades, 1-2-5 values above one decade, 1..9 times a power of ten
/// otherwise. Each value appears once, ascending, so labels never pile up.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let decades = (hi / lo).log10();
    let mantissas: &[f64] = if decades > 2.5 {
        &[1.0]
    } else if decades > 1.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    };
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let mut out = Vec::new();
    for k in k0..=k1 {
        for &m in mantissas {
            // m * 10^k written as text first and parsed back, so 0.001 is exactly 0.001.
            let v: f64 = format!("{m}e{k}").parse().unwrap_or(f64::NAN);
            if v >= lo && v <= hi {
                out.push((v, fmt_sig(v)));
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Fonts, styles, formatting
// ---------------------------------------------------------------------------------------------

const FONT: &str = "sans-serif";

/// Registers the embedded DejaVu Sans (regular and bold) as plotters' `"sans-serif"` family.
fn ensure_fonts() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            let fail = |style: &str| format!("embedded DejaVu Sans {style} font is invalid");
            plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
                .map_err(|_| fail("regular"))?;
            plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold())
                .map_err(|_| fail("bold"))?;
            Ok(())
        })
        .clone()
        .map_err(PlotError::Draw)
}

fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

fn bold(size: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, size, FontStyle::Bold).into_font()).color(&BLACK)
}

/// Formats a tick value on a linear axis whose visible span is `span`.
fn fmt_linear(v: f64, span: f64) -> String {
    let a = v.abs();
    if a < span * 1e-9 {
        return "0".to_string();
    }
    if !(1e-3..1e5).contains(&a) {
        return fmt_sci(v);
    }
    let step = (span / 10.0).abs().max(f64::MIN_POSITIVE);
    let decimals = (-step.log10().floor()).clamp(0.0, 9.0) as usize;
    trim_zeros(format!("{v:.decimals$}"))
}

/// Formats a tick value with about four significant digits (used on log axes).
fn fmt_sig(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".to_string();
    }
    if !(1e-3..1e5).contains(&a) {
        return fmt_sci(v);
    }
    let decimals = (3.0 - a.log10().floor()).clamp(0.0, 9.0) as usize;
    trim_zeros(format!("{v:.decimals$}"))
}

fn fmt_sci(v: f64) -> String {
    let s = format!("{v:.2e}");
    match s.split_once('e') {
        Some((mantissa, exp)) => format!("{}e{exp}", trim_zeros(mantissa.to_string())),
        None => s,
    }
}

fn trim_zeros(s: String) -> String {
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".to_string() } else { s }
}

/// Data extent `lo..hi` widened by `frac` of its span on both sides (or a sensible width if the
/// span is zero).
fn padded(lo: f64, hi: f64, frac: f64) -> Range<f64> {
    let span = hi - lo;
    let pad = if span > 0.0 {
        span * frac
    } else if lo != 0.0 {
        lo.abs() * frac
    } else {
        1.0
    };
    (lo - pad)..(hi + pad)
}

type DrawResult<T> = Result<T, Box<dyn StdError>>;
type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// A chart's plotting plane with linear f64 axes (log10 values where an axis is logarithmic).
type Plane<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_error(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(format!("{}: {e}", path.display()))
}

/// Creates the bitmap, runs `body` on a white root area and writes the file.
fn render(
    path: &Path,
    size: (u32, u32),
    body: impl FnOnce(&Area<'_>) -> DrawResult<()>,
) -> Result<(), PlotError> {
    ensure_fonts()?;
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_error(path, e))?;
    body(&root).map_err(|e| draw_error(path, e))?;
    root.present().map_err(|e| draw_error(path, e))
}

/// Splits a curve into runs of drawable points (finite, and `x > 0` if `log_x`).
fn segments(curve: &Curve, log_x: bool) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut run = Vec::new();
    for (&x, &y) in curve.xs.iter().zip(&curve.ys) {
        if x.is_finite() && y.is_finite() && (!log_x || x > 0.0) {
            run.push((x, y));
        } else if !run.is_empty() {
            out.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        out.push(run);
    }
    out
}

fn check_curve(curve: &Curve) -> Result<(), PlotError> {
    if curve.xs.len() != curve.ys.len() {
        return Err(PlotError::ShapeMismatch {
            what: format!("curve {:?}: ys vs xs", curve.label),
            expected: curve.xs.len(),
            found: curve.ys.len(),
        });
    }
    Ok(())
}

fn marker_drawable(m: &Marker, log_x: bool) -> bool {
    m.x.is_finite() && m.y.is_finite() && (!log_x || m.x > 0.0)
}

/// A marker glyph (cross in a circle with a white halo) at backend offset (0, 0).
fn marker_glyph<DB: DrawingBackend>(
    color: Rgb,
    r: i32,
) -> impl IntoIterator<Item = DynElement<'static, DB, (i32, i32)>> {
    let halo = WHITE.stroke_width(5);
    let ink = color.color().stroke_width(2);
    vec![
        Circle::new((0, 0), r, halo).into_dyn(),
        Cross::new((0, 0), r - 2, halo).into_dyn(),
        Circle::new((0, 0), r, ink).into_dyn(),
        Cross::new((0, 0), r - 2, ink).into_dyn(),
    ]
}

fn draw_marker_at(area: &Area<'_>, pos: (i32, i32), color: Rgb, r: i32) -> DrawResult<()> {
    for element in marker_glyph(color, r) {
        let element = EmptyElement::at(pos) + element;
        area.draw(&element)?;
    }
    Ok(())
}

/// Draws a title (lines separated by `\n`; the first bold, the others regular and smaller)
/// centred at the top of `area`, and returns the area below it.
fn draw_title<'a>(area: &Area<'a>, title: &str, size: u32) -> DrawResult<Area<'a>> {
    let sub = (size * 4).div_ceil(5).max(8);
    let (width, _) = area.dim_in_pixel();
    let mut lines: Vec<String> = Vec::new();
    for (i, line) in title.lines().filter(|l| !l.trim().is_empty()).enumerate() {
        let style = if i == 0 { bold(size) } else { font(sub) };
        lines.extend(wrap_line(area, line, &style, width.saturating_sub(24)));
    }
    if lines.is_empty() {
        return Ok(area.clone());
    }
    let heights: Vec<u32> = (0..lines.len())
        .map(|i| if i == 0 { size } else { sub } * 13 / 10)
        .collect();
    let total: u32 = heights.iter().sum::<u32>() + 10;
    let (top, rest) = area.split_vertically(total);
    let (w, _) = top.dim_in_pixel();
    let mut y = 6i32;
    for (i, (line, h)) in lines.iter().zip(&heights).enumerate() {
        let style = if i == 0 { bold(size) } else { font(sub) };
        let style = style.pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
        top.draw_text(line, &style, (w as i32 / 2, y + *h as i32 / 2))?;
        y += *h as i32;
    }
    Ok(rest)
}

/// `line` split after its commas into lines no wider than `width` pixels in `style` (a
/// title with every parameter of a physical system is wider than the picture).
fn wrap_line(area: &Area<'_>, line: &str, style: &TextStyle<'_>, width: u32) -> Vec<String> {
    let fits = |t: &str| {
        area.estimate_text_size(t, style)
            .is_ok_and(|(w, _)| w <= width)
    };
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    for part in line.split_inclusive(", ") {
        let joined = format!("{cur}{part}");
        if cur.is_empty() || fits(joined.trim_end()) {
            cur = joined;
        } else {
            out.push(cur.trim_end().trim_end_matches(',').to_string());
            cur = part.to_string();
        }
    }
    if !cur.is_empty() {
        out.push(cur.trim_end().to_string());
    }
    out
}

#[cfg(test)]
mod tests;
