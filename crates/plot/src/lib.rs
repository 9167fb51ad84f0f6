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
//!   as a circle) and the axis labels [`X_LABEL`] and [`V_LABEL`].
//! * [`sweep_chart`]: a quantity against a swept parameter, with the values where it does not
//!   exist (e.g. no unstable cycle) marked on the axis and listed in the legend.
//! * [`basin_map`]: one categorical image of a grid of initial conditions `(x0, x'0)`, each cell
//!   coloured by its class, with a legend giving each class's cell count, plus overlays (e.g. the
//!   unstable limit cycle) and markers (e.g. the fixed point) drawn on top. Equal scales on
//!   both axes.
//! * [`basin_sheet`]: several basin maps in a grid of panels with one shared legend.
//!
//! Titles are built by functions that return strings, so callers and tests see the text:
//! [`map_title`], [`sheet_title`], [`panel_title`] and [`phase_title`] from a
//! [`ModelParams`]; numbers are written by [`fmt_number`] (four significant digits). A title
//! may hold several lines separated by `\n`.
//!
//! Units: squeal's variables are nondimensional (crates/core/MODEL.md, "Units"): a
//! displacement is measured in units of `mu_k m g / k` (the spring's stretch under the
//! kinetic friction force) and a velocity in units of `mu_k g sqrt(m/k)`; the axis labels say
//! so.
//!
//! The output format follows the file extension of `path` (use `.png`); the parent directory must
//! exist. All input is validated before anything is drawn: bad shapes or empty data give a
//! [`PlotError`], never a panic.
//!
//! The palette constants [`STEADY`], [`STICK`], [`UNDECIDED`], [`NOT_COMPUTED`], [`OTHER`],
//! [`CYCLE`] and [`FIXED_POINT`] are suggestions for the classes and overlays of a basin map.

mod atlas;

pub use atlas::{StabilityChart, contour_segments, fmt_value, stability_chart};

use std::error::Error as StdError;
use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
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

/// Steady slip (the orbit settles on the fixed point): blue.
pub const STEADY: Rgb = Rgb(49, 110, 198);
/// Stick-slip (the orbit settles on the stable stick-slip cycle): orange.
pub const STICK: Rgb = Rgb(238, 118, 22);
/// Undecided (time limit reached): bright magenta, visible against blue and orange.
pub const UNDECIDED: Rgb = Rgb(230, 0, 200);
/// Not computed (yet): light grey.
pub const NOT_COMPUTED: Rgb = Rgb(222, 222, 222);
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

/// The nondimensional model parameters and step shown in titles (the names of the spec keys
/// and of the HDF5 attributes). The plot crate does not depend on squeal-core: callers fill
/// this in from `Params` and the step.
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
pub fn law_title(law: &str) -> String {
    match law {
        "mcmillan" => "McMillan law (hysteretic)".into(),
        "mcmillan-nonhysteretic" => "McMillan law (non-hysteretic)".into(),
        "coulomb" => "Coulomb friction".into(),
        "stribeck" => "Stribeck law with true stick".into(),
        other => other.to_string(),
    }
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
    format!(
        "{name}: basins of attraction, {}, one map per {swept}\n{}",
        law_title(&p.law),
        params_line(p, Some(swept))
    )
}

/// Title of one panel of a sheet: `nu = 0.001`.
pub fn panel_title(swept: &str, value: f64) -> String {
    format!("{swept} = {}", fmt_number(value))
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

// ---------------------------------------------------------------------------------------------
// Line plots
// ---------------------------------------------------------------------------------------------

/// Line plot with axes (tick values), axis labels, title and legend.
///
/// Used for friction curves (F/mg vs velocity); phase planes use [`phase_plot`] and sweeps
/// [`sweep_chart`]. `log_x` gives a logarithmic x axis; points with `x <= 0` are then
/// skipped. Axis ranges are the extent of all drawable points and markers plus a 5%
/// margin. Non-finite points are skipped (polylines are broken there); a curve with no drawable
/// point is an error, as is a call with neither curves nor drawable markers. The title may
/// have several lines (`\n`). Size 900x700.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    markers: &[Marker],
    log_x: bool,
) -> Result<(), PlotError> {
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers,
            log_x,
            equal_aspect: false,
            missing: None,
        },
    )
}

/// A phase plane `(x, x')`: as [`line_plot`] with the axis labels [`X_LABEL`] and
/// [`V_LABEL`] and equal scales on both axes (the shorter range is widened about its centre,
/// so a circle is drawn as a circle). Size 900x800.
pub fn phase_plot(
    path: &Path,
    title: &str,
    curves: &[Curve],
    markers: &[Marker],
) -> Result<(), PlotError> {
    line_chart(
        path,
        LineOpts {
            title,
            x_label: X_LABEL,
            y_label: V_LABEL,
            curves,
            markers,
            log_x: false,
            equal_aspect: true,
            missing: None,
        },
    )
}

/// A quantity against a swept parameter (e.g. the unstable cycle's size against `nu`).
///
/// Each curve is drawn as a line with a dot at every value (so a value between two gaps still
/// shows). The x values where no curve has a finite y (e.g. no cycle was located) are drawn as
/// hollow triangles on the bottom of the chart and listed in the legend as
/// `missing_label` with their count; if every value is missing, the chart holds only those
/// marks. Curves must share one set of x values only in the sense that "missing" is decided per
/// x value over all curves. Size 900x700.
pub fn sweep_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    curves: &[Curve],
    log_x: bool,
    missing_label: &str,
) -> Result<(), PlotError> {
    for c in curves {
        check_curve(c)?;
    }
    let mut xs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.xs.iter().copied())
        .filter(|x| x.is_finite() && (!log_x || *x > 0.0))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let missing: Vec<f64> = missing_values(curves, &xs);
    line_chart(
        path,
        LineOpts {
            title,
            x_label,
            y_label,
            curves,
            markers: &[],
            log_x,
            equal_aspect: false,
            missing: Some((&missing, missing_label)),
        },
    )
}

/// The values of `xs` at which no curve has a finite y.
fn missing_values(curves: &[Curve], xs: &[f64]) -> Vec<f64> {
    xs.iter()
        .copied()
        .filter(|&x| {
            !curves.iter().any(|c| {
                c.xs.iter()
                    .zip(&c.ys)
                    .any(|(&cx, &cy)| cx == x && cy.is_finite())
            })
        })
        .collect()
}

struct LineOpts<'p> {
    title: &'p str,
    x_label: &'p str,
    y_label: &'p str,
    curves: &'p [Curve],
    markers: &'p [Marker],
    log_x: bool,
    equal_aspect: bool,
    /// Sweep charts: the x values without data, and their legend label. Curves without any
    /// drawable point are then allowed.
    missing: Option<(&'p [f64], &'p str)>,
}

/// Layout of line charts: margin, label areas (pixels).
const LINE_MARGIN: u32 = 18;
const LINE_X_AREA: u32 = 70;
const LINE_Y_AREA: u32 = 95;

fn line_chart(path: &Path, o: LineOpts<'_>) -> Result<(), PlotError> {
    let log_x = o.log_x;
    let mut segs = Vec::with_capacity(o.curves.len());
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut extend_x = |x: f64| {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
    };
    let mut ys_seen = Vec::new();
    for curve in o.curves {
        check_curve(curve)?;
        let s = segments(curve, log_x);
        if s.is_empty() && o.missing.is_none() {
            return Err(PlotError::NoDrawablePoint {
                label: curve.label.clone(),
            });
        }
        s.iter().flatten().for_each(|&(x, y)| {
            extend_x(x);
            ys_seen.push(y);
        });
        segs.push(s);
    }
    for m in o.markers.iter().filter(|m| marker_drawable(m, log_x)) {
        extend_x(m.x);
        ys_seen.push(m.y);
    }
    if let Some((missing, _)) = o.missing {
        missing.iter().for_each(|&x| extend_x(x));
    }
    for y in ys_seen {
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y);
    }
    if !x_lo.is_finite() {
        return Err(PlotError::EmptyData(
            "line plot without curves or drawable markers",
        ));
    }
    if !y_lo.is_finite() {
        // Only missing values: an empty y axis.
        (y_lo, y_hi) = (0.0, 1.0);
    }
    let all_points: Vec<(f64, f64)> = segs
        .iter()
        .flatten()
        .flatten()
        .copied()
        .chain(o.markers.iter().map(|m| (m.x, m.y)))
        .collect();
    let size = if o.equal_aspect {
        (900, 800)
    } else {
        (900, 700)
    };
    render(path, size, |root| {
        let body = draw_title(root, o.title, 24)?;
        let (w, h) = body.dim_in_pixel();
        let pixels = (
            w.saturating_sub(2 * LINE_MARGIN + LINE_Y_AREA),
            h.saturating_sub(2 * LINE_MARGIN + LINE_X_AREA),
        );
        let mut y_range = padded(y_lo, y_hi, 0.05);
        if let Some((missing, _)) = o.missing
            && !missing.is_empty()
        {
            // Room below the data for the "missing" marks.
            let span = y_range.end - y_range.start;
            y_range.start -= 0.06 * span;
        }
        let plot = LinePlot {
            opts: &o,
            segs: &segs,
        };
        if log_x {
            let (a, b) = (x_lo.log10(), x_hi.log10());
            let r = padded(a, b, 0.05);
            let x_range = 10f64.powf(r.start)..10f64.powf(r.end);
            let pos = legend_corner(&all_points, &x_range, &y_range, true);
            plot.draw(&body, x_range.clone().log_scale(), x_range, y_range, pos)
        } else {
            let mut x_range = padded(x_lo, x_hi, 0.05);
            if o.equal_aspect {
                (x_range, y_range) = equal_aspect_ranges(x_range, y_range, pixels);
            }
            let pos = legend_corner(&all_points, &x_range, &y_range, false);
            plot.draw(&body, x_range.clone(), x_range, y_range, pos)
        }
    })
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

/// Picks the chart corner with the fewest data points for the legend.
fn legend_corner(
    points: &[(f64, f64)],
    xr: &Range<f64>,
    yr: &Range<f64>,
    log_x: bool,
) -> SeriesLabelPosition {
    let fx = |x: f64| {
        if log_x {
            (x.log10() - xr.start.log10()) / (xr.end.log10() - xr.start.log10())
        } else {
            (x - xr.start) / (xr.end - xr.start)
        }
    };
    let fy = |y: f64| (y - yr.start) / (yr.end - yr.start);
    // (position, x window, y window) in unit coordinates; the legend box is roughly this big.
    let corners = [
        (SeriesLabelPosition::UpperRight, 0.6..1.0, 0.7..1.0),
        (SeriesLabelPosition::UpperLeft, 0.0..0.4, 0.7..1.0),
        (SeriesLabelPosition::LowerRight, 0.6..1.0, 0.0..0.3),
        (SeriesLabelPosition::LowerLeft, 0.0..0.4, 0.0..0.3),
    ];
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (pos, wx, wy) in corners {
        let n = points
            .iter()
            .filter(|&&(x, y)| wx.contains(&fx(x)) && wy.contains(&fy(y)))
            .count();
        if n < best.1 {
            best = (pos, n);
        }
    }
    best.0
}

struct LinePlot<'p> {
    opts: &'p LineOpts<'p>,
    segs: &'p [Vec<Vec<(f64, f64)>>],
}

impl LinePlot<'_> {
    fn draw<X>(
        &self,
        root: &Area<'_>,
        x_spec: X,
        x_range: Range<f64>,
        y_range: Range<f64>,
        legend_pos: SeriesLabelPosition,
    ) -> DrawResult<()>
    where
        X: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
    {
        let o = self.opts;
        let mut chart = ChartBuilder::on(root)
            .margin(LINE_MARGIN)
            .x_label_area_size(LINE_X_AREA)
            .y_label_area_size(LINE_Y_AREA)
            .build_cartesian_2d(x_spec, y_range.clone())?;
        let x_span = x_range.end - x_range.start;
        let y_span = y_range.end - y_range.start;
        let log_x = o.log_x;
        // On a log axis plotters' own labels stay empty (see the ticks drawn below).
        let x_fmt = move |v: &f64| {
            if log_x {
                String::new()
            } else {
                fmt_linear(*v, x_span)
            }
        };
        let y_fmt = move |v: &f64| fmt_linear(*v, y_span);
        chart
            .configure_mesh()
            .x_desc(o.x_label)
            .y_desc(o.y_label)
            .axis_desc_style(font(20))
            .label_style(font(16))
            .x_labels(10)
            .y_labels(10)
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;

        if log_x {
            // plotters' log key points can repeat a value (0.01 twice from rounding): draw
            // the ticks, grid lines and labels of `log_ticks` instead.
            let ticks = log_ticks(x_range.start, x_range.end);
            chart.draw_series(ticks.iter().map(|&(v, _)| {
                PathElement::new(
                    vec![(v, y_range.start), (v, y_range.end)],
                    RGBColor(215, 215, 215),
                )
            }))?;
            let (bx, by) = root.get_base_pixel();
            let style = font(16).pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Top,
            ));
            for (v, text) in &ticks {
                let (px, py) = chart.backend_coord(&(*v, y_range.start));
                let (px, py) = (px - bx, py - by);
                root.draw(&PathElement::new(vec![(px, py), (px, py + 6)], BLACK))?;
                root.draw_text(text, &style, (px, py + 9))?;
            }
        }
        let mut any_label = false;
        let dots_on_lines = o.missing.is_some();
        for (curve, segs) in o.curves.iter().zip(self.segs) {
            let color = curve.color.color();
            let series = if curve.points_only {
                chart.draw_series(
                    segs.iter()
                        .flatten()
                        .map(|&p| Circle::new(p, 2, color.filled())),
                )?
            } else {
                if dots_on_lines {
                    chart.draw_series(
                        segs.iter()
                            .flatten()
                            .map(|&p| Circle::new(p, 4, color.filled())),
                    )?;
                }
                chart.draw_series(
                    segs.iter()
                        .map(|s| PathElement::new(s.clone(), color.stroke_width(2))),
                )?
            };
            if !curve.label.is_empty() {
                any_label = true;
                let points_only = curve.points_only;
                series.label(curve.label.as_str()).legend(
                    move |(x, y)| -> DynElement<'static, _, (i32, i32)> {
                        if points_only {
                            Circle::new((x + 10, y), 3, color.filled()).into_dyn()
                        } else {
                            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                                .into_dyn()
                        }
                    },
                );
            }
        }
        if let Some((missing, label)) = o.missing
            && !missing.is_empty()
        {
            let y = y_range.start + 0.03 * y_span;
            let ink = MISSING.color();
            let series = chart.draw_series(missing.iter().map(|&x| {
                EmptyElement::at((x, y))
                    + Polygon::new(vec![(0, -7), (-7, 6), (7, 6)], WHITE.filled())
                    + PathElement::new(vec![(0, -7), (-7, 6), (7, 6), (0, -7)], ink.stroke_width(2))
            }))?;
            any_label = true;
            series
                .label(format!("{label} ({} values)", missing.len()))
                .legend(move |(x, y)| {
                    EmptyElement::at((x + 10, y))
                        + PathElement::new(
                            vec![(0, -7), (-7, 6), (7, 6), (0, -7)],
                            ink.stroke_width(2),
                        )
                });
        }
        for m in o.markers.iter().filter(|m| marker_drawable(m, log_x)) {
            let (color, r) = (m.color, 7);
            let series = chart.draw_series(
                marker_glyph(color, r)
                    .into_iter()
                    .map(|g| EmptyElement::at((m.x, m.y)) + g),
            )?;
            if !m.label.is_empty() {
                any_label = true;
                series.label(m.label.as_str()).legend(move |(x, y)| {
                    EmptyElement::at((x + 10, y))
                        + Circle::new((0, 0), 6, color.color())
                        + Cross::new((0, 0), 4, color.color())
                });
            }
        }
        if any_label {
            chart
                .configure_series_labels()
                .position(legend_pos)
                .margin(12)
                .label_font(font(17))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// Basin maps
// ---------------------------------------------------------------------------------------------

/// A validated grid axis: cell centres `first + i * step`.
#[derive(Clone, Copy, Debug)]
struct Axis {
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
fn check_panel(panel: &BasinPanel<'_>) -> Result<(Axis, Axis), PlotError> {
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
struct Classes<'c> {
    classes: &'c [(u8, &'c str, Rgb)],
    index: [Option<usize>; 256],
}

impl<'c> Classes<'c> {
    fn new(classes: &'c [(u8, &'c str, Rgb)]) -> Self {
        let mut index = [None; 256];
        for (k, &(value, _, _)) in classes.iter().enumerate() {
            index[value as usize].get_or_insert(k);
        }
        Self { classes, index }
    }

    fn color(&self, value: u8) -> Rgb {
        self.index[value as usize].map_or(OTHER, |k| self.classes[k].2)
    }

    /// Cell counts per class, plus the count of cells with other values (last entry).
    fn counts(&self, labels: &[u8]) -> Vec<usize> {
        let mut per_value = [0usize; 256];
        for &l in labels {
            per_value[l as usize] += 1;
        }
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
struct BasinLayout {
    title: u32,
    axis_desc: u32,
    tick: u32,
    x_area: u32,
    y_area: u32,
    margin: u32,
    marker: i32,
    ticks: usize,
}

const MAP_LAYOUT: BasinLayout = BasinLayout {
    title: 24,
    axis_desc: 21,
    tick: 15,
    x_area: 55,
    y_area: 80,
    margin: 14,
    marker: 7,
    ticks: 10,
};

const SHEET_LAYOUT: BasinLayout = BasinLayout {
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
fn draw_basin_chart(
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

    // The image: one nearest-cell lookup per pixel of the plotting area, blitted at once.
    let plot = chart.plotting_area().strip_coord_spec();
    let (w, h) = plot.dim_in_pixel();
    if w > 0 && h > 0 {
        let nx = ax.n;
        let cols: Vec<usize> = (0..w)
            .map(|px| ax.index(xr.start + (px as f64 + 0.5) / w as f64 * (xr.end - xr.start)))
            .collect();
        let mut buf = Vec::with_capacity(w as usize * h as usize * 3);
        for py in 0..h {
            let v = vr.end - (py as f64 + 0.5) / h as f64 * (vr.end - vr.start);
            let row = &panel.labels[av.index(v) * nx..][..nx];
            for &i in &cols {
                let Rgb(r, g, b) = classes.color(row[i]);
                buf.extend_from_slice(&[r, g, b]);
            }
        }
        let image = BitMapElement::with_owned_buffer((0, 0), (w, h), buf)
            .ok_or("image buffer has the wrong size")?;
        plot.draw(&image)?;
        plot.draw(&Rectangle::new(
            [(0, 0), (w as i32 - 1, h as i32 - 1)],
            BLACK.stroke_width(1),
        ))?;
    }

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

    let bounds = (xr.clone(), vr.clone());
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
fn clip_polyline(points: &[(f64, f64)], bounds: &(Range<f64>, Range<f64>)) -> Vec<Vec<(f64, f64)>> {
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
fn clip_segment(
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

/// One row of a basin legend.
enum LegendItem {
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
    /// A marker sample.
    Marker { name: String, color: Rgb },
}

/// Draws a vertical legend into `area`, starting at the top.
fn draw_legend(area: &Area<'_>, heading: &str, items: &[LegendItem]) -> DrawResult<()> {
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
            LegendItem::Marker { name, color } => {
                draw_marker_at(area, (x + 11, y + 11), *color, 7)?;
                area.draw_text(name, &font(17), (x + 32, y + 2))?;
                y += 34;
            }
        }
    }
    Ok(())
}

/// Legend rows for the overlays and markers of the given panels (deduplicated by label).
fn overlay_items<'p>(panels: impl IntoIterator<Item = &'p BasinPanel<'p>>) -> Vec<LegendItem> {
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

const LEGEND_WIDTH: u32 = 245;

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
    let (panel_w, panel_h) = (440u32, 420u32);
    // draw_title's height for this title at size 26 (first line 26, others 21, x 1.3, + 10).
    let nlines = title.lines().filter(|l| !l.trim().is_empty()).count() as u32;
    let title_h = if nlines == 0 {
        0
    } else {
        26 * 13 / 10 + (nlines - 1) * (21 * 13 / 10) + 10
    };
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A decoded RGB picture.
    struct Picture {
        width: u32,
        height: u32,
        rgb: Vec<u8>,
    }

    impl Picture {
        fn pixel(&self, x: u32, y: u32) -> Rgb {
            let i = 3 * (y as usize * self.width as usize + x as usize);
            Rgb(self.rgb[i], self.rgb[i + 1], self.rgb[i + 2])
        }

        /// Pixels of exactly this colour.
        fn count(&self, c: Rgb) -> usize {
            self.rgb
                .chunks_exact(3)
                .filter(|p| p == &[c.0, c.1, c.2])
                .count()
        }

        /// Bounding box (x0, y0, x1, y1), inclusive, of the pixels of colour `c`.
        fn bbox(&self, c: Rgb) -> Option<(u32, u32, u32, u32)> {
            let mut b: Option<(u32, u32, u32, u32)> = None;
            for y in 0..self.height {
                for x in 0..self.width {
                    if self.pixel(x, y) == c {
                        b = Some(match b {
                            None => (x, y, x, y),
                            Some((a0, b0, a1, b1)) => (a0.min(x), b0.min(y), a1.max(x), b1.max(y)),
                        });
                    }
                }
            }
            b
        }
    }

    /// Decodes the PNG at `path` (8-bit RGB, as plotters writes it) and checks its size.
    fn decode(path: &Path, size: (u32, u32)) -> Picture {
        let file = std::fs::File::open(path).expect("file written");
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .expect("a PNG header");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("PNG data");
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgb, png::BitDepth::Eight)
        );
        assert_eq!((info.width, info.height), size, "{}", path.display());
        buf.truncate(info.buffer_size());
        Picture {
            width: info.width,
            height: info.height,
            rgb: buf,
        }
    }

    fn classes() -> Vec<(u8, &'static str, Rgb)> {
        vec![
            (0, "undecided", UNDECIDED),
            (1, "steady slip", STEADY),
            (2, "stick-slip", STICK),
            (255, "not computed", NOT_COMPUTED),
        ]
    }

    fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
            .collect()
    }

    fn circle(r: f64, cx: f64, n: usize) -> Curve {
        let t = linspace(0.0, std::f64::consts::TAU, n);
        Curve {
            label: "unstable cycle".into(),
            xs: t.iter().map(|t| cx + r * t.cos()).collect(),
            ys: t.iter().map(|t| r * t.sin()).collect(),
            color: CYCLE,
            points_only: false,
        }
    }

    fn fixed_point() -> Marker {
        Marker {
            label: "fixed point (1, 0)".into(),
            x: 1.0,
            y: 0.0,
            color: FIXED_POINT,
        }
    }

    /// Labels: steady inside a circle around (1,0), stick-slip outside, a few undecided and
    /// not-computed cells, and one value (7) that is not a class.
    fn grid_labels(x0: &[f64], v0: &[f64], r: f64) -> Vec<u8> {
        let mut labels = Vec::with_capacity(x0.len() * v0.len());
        for (j, &v) in v0.iter().enumerate() {
            for (i, &x) in x0.iter().enumerate() {
                let d = ((x - 1.0).powi(2) + v * v).sqrt();
                labels.push(if (d - r).abs() < 0.02 {
                    0
                } else if j < 3 && i < 10 {
                    255
                } else if j == v0.len() - 1 && i < 5 {
                    7
                } else if d < r {
                    1
                } else {
                    2
                });
            }
        }
        labels
    }

    #[test]
    fn tick_formatting() {
        assert_eq!(fmt_linear(0.30000000000000004, 2.0), "0.3");
        assert_eq!(fmt_linear(-0.0, 2.0), "0");
        assert_eq!(fmt_linear(1e-17, 2.0), "0");
        assert_eq!(fmt_linear(250.0, 1000.0), "250");
        assert_eq!(fmt_linear(1.0005, 0.001), "1.0005");
        assert_eq!(fmt_linear(2e6, 1e7), "2e6");
        assert_eq!(fmt_sig(0.01), "0.01");
        assert_eq!(fmt_sig(20.0), "20");
        assert_eq!(fmt_sig(1.5e-5), "1.5e-5");
        // The sweep value the issue quotes (1e-3 computed as a log-spaced grid point).
        assert_eq!(fmt_number(0.0010000000000000002), "0.001");
        assert_eq!(fmt_number(0.316_227_766_016_837_94), "0.3162");
        assert_eq!(fmt_number(3.0), "3");
        assert_eq!(fmt_number(-0.5), "-0.5");
        assert_eq!(fmt_number(0.013894954943731374), "0.01389");
        assert_eq!(fmt_number(f64::NAN), "NaN");
    }

    #[test]
    fn log_ticks_do_not_crowd() {
        let values = |lo: f64, hi: f64| -> Vec<String> {
            log_ticks(lo, hi).into_iter().map(|(_, t)| t).collect()
        };
        // The nu sweep's axis (1e-3 to 5e-2, padded): 1.7 decades, 1-2-5 labels, each once.
        assert_eq!(
            values(8.2e-4, 6.1e-2),
            ["0.001", "0.002", "0.005", "0.01", "0.02", "0.05"]
        );
        // Over 3 decades only powers of ten.
        assert_eq!(values(1e-4, 0.5), ["1e-4", "0.001", "0.01", "0.1"]);
        // Under one decade every integer multiple.
        assert_eq!(values(2.5, 6.0), ["3", "4", "5", "6"]);
        let ticks = log_ticks(9.9e-4, 1.01e-2);
        assert_eq!(ticks.first().map(|t| t.0), Some(0.001));
        assert_eq!(ticks.last().map(|t| t.0), Some(0.01));
        assert!(ticks.windows(2).all(|w| w[0].0 < w[1].0));
        assert!(log_ticks(0.0, 1.0).is_empty() && log_ticks(2.0, 1.0).is_empty());
    }

    fn table1(law: &str) -> ModelParams {
        ModelParams::mcmillan(law, 1e-3, 3.0, 0.316_227_766_016_837_94, 1.0, 0.01)
    }

    #[test]
    fn titles_name_every_parameter() {
        assert_eq!(
            map_title(&table1("mcmillan")),
            "Basins of attraction, McMillan law (hysteretic)\n\
             nu = 0.001, lambda = 3, tau = 0.3162, phi = 1, dt = 0.01"
        );
        // A lambda = 0.5 map must not look like Fig. 9.
        let slow = ModelParams::mcmillan(
            "mcmillan-nonhysteretic",
            1e-3,
            0.5,
            0.316_227_766_016_837_94,
            1.0,
            0.01,
        );
        let t = map_title(&slow);
        assert!(
            t.contains("lambda = 0.5") && t.contains("non-hysteretic"),
            "{t}"
        );
        assert_ne!(t, map_title(&table1("mcmillan-nonhysteretic")));
        // A sheet leaves the swept parameter to the panels.
        let sheet = sheet_title("nu-sweep", &table1("mcmillan"), "nu");
        assert!(!sheet.contains("nu = "), "{sheet}");
        assert!(sheet.contains("one map per nu") && sheet.contains("lambda = 3, tau"));
        assert_eq!(panel_title("nu", 0.0010000000000000002), "nu = 0.001");
        assert_eq!(panel_title("lambda", 1.25), "lambda = 1.25");
        assert!(
            phase_title("Unstable limit cycle", &table1("coulomb"))
                .starts_with("Unstable limit cycle, Coulomb friction\nnu = 0.001")
        );
        // The Stribeck law's titles name its own parameters, none of McMillan's.
        let s = ModelParams {
            law: "stribeck".into(),
            params: [
                ("xi", 0.05),
                ("v_d", 1.5),
                ("mu_d", 0.5),
                ("mu_sd", 2.0),
                ("v_0", 0.5),
                ("mu_v", 0.0),
            ]
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
            dt: 0.005,
        };
        assert_eq!(
            map_title(&s),
            "Basins of attraction, Stribeck law with true stick\n\
             xi = 0.05, v_d = 1.5, mu_d = 0.5, mu_sd = 2, v_0 = 0.5, mu_v = 0, dt = 0.005"
        );
        let sheet = sheet_title("bstab", &s, "v_d");
        assert!(
            !sheet.contains("v_d = ") && !sheet.contains("nu"),
            "{sheet}"
        );
    }

    #[test]
    fn equal_aspect_geometry() {
        assert_eq!(equal_aspect_fit((600, 500), 8.0, 8.0), (500, 500));
        assert_eq!(equal_aspect_fit((600, 500), 8.0, 4.0), (600, 300));
        assert_eq!(equal_aspect_fit((600, 500), 1.0, 10.0), (50, 500));
        assert_eq!(equal_aspect_fit((600, 500), 0.0, 1.0), (600, 500));
        let (x, y) = equal_aspect_ranges(0.0..2.0, -1.0..1.0, (400, 200));
        // 2 units over 400 px would be 0.005 units/px; 2 units over 200 px is 0.01: x widens.
        assert_eq!((x, y), (-1.0..3.0, -1.0..1.0));
        let (x, y) = equal_aspect_ranges(0.0..4.0, 0.0..1.0, (100, 100));
        assert_eq!((x, y), (0.0..4.0, -1.5..2.5));
    }

    #[test]
    fn clipping() {
        let b = (0.0..1.0, 0.0..1.0);
        assert_eq!(
            clip_segment((-1.0, 0.5), (2.0, 0.5), &b),
            Some(((0.0, 0.5), (1.0, 0.5)))
        );
        assert_eq!(clip_segment((-1.0, 2.0), (-0.5, 3.0), &b), None);
        let pieces = clip_polyline(&[(0.5, 0.5), (1.5, 0.5), (1.5, 0.6), (0.5, 0.6)], &b);
        assert_eq!(pieces.len(), 2);
    }

    #[test]
    fn line_plot_writes_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("phase.png");
        let mut orbit = circle(0.8, 1.0, 400);
        orbit.label = "orbit".into();
        orbit.color = STEADY;
        orbit.xs[100] = f64::NAN; // a gap, not a failure
        let dots = Curve {
            label: "Poincaré points".into(),
            xs: vec![0.5, 1.2, 1.7, f64::INFINITY],
            ys: vec![0.1, -0.4, 0.3, 0.0],
            color: STICK,
            points_only: true,
        };
        line_plot(
            &path,
            "Phase plane",
            "x",
            "x'",
            &[orbit, dots],
            &[fixed_point()],
            false,
        )
        .unwrap();
        let pic = decode(&path, (900, 700));
        assert!(pic.count(STEADY) > 500, "the orbit is drawn");
        assert!(pic.count(STICK) > 20, "the dots are drawn");
        assert!(
            pic.count(Rgb(255, 255, 255)) > 300_000,
            "a white background"
        );
    }

    #[test]
    fn phase_plot_draws_circles_round() {
        // A circle of radius 1 around (1, 0) and, far off to the right, a point that makes the
        // x range three times the y range: with equal scales the circle's pixel width and
        // height agree (line_plot would stretch it into a tall ellipse).
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("round.png");
        let mut c = circle(1.0, 1.0, 720);
        c.color = STICK;
        c.label = String::new();
        let far = Curve {
            label: String::new(),
            xs: vec![6.0, 6.0],
            ys: vec![0.0, 0.0],
            color: STEADY,
            points_only: true,
        };
        phase_plot(&path, "round", &[c.clone(), far.clone()], &[]).unwrap();
        let pic = decode(&path, (900, 800));
        let (x0, y0, x1, y1) = pic.bbox(STICK).expect("the circle is drawn");
        let (w, h) = ((x1 - x0) as i64, (y1 - y0) as i64);
        assert!((w - h).abs() <= 3, "circle drawn {w} x {h} pixels");
        // The same data through line_plot: not round (so the check above can fail).
        line_plot(&path, "t", "x", "y", &[c, far], &[], false).unwrap();
        let pic = decode(&path, (900, 700));
        let (x0, y0, x1, y1) = pic.bbox(STICK).unwrap();
        assert!((y1 - y0) as f64 > 1.5 * (x1 - x0) as f64);
    }

    #[test]
    fn sweep_chart_marks_values_without_data() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sweep.png");
        let nu = [1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2];
        let size = Curve {
            label: "size".into(),
            xs: nu.to_vec(),
            ys: vec![0.1, 0.2, 0.5, 1.0, f64::NAN, f64::NAN],
            color: STEADY,
            points_only: false,
        };
        assert_eq!(
            missing_values(std::slice::from_ref(&size), &nu),
            [2e-2, 5e-2]
        );
        sweep_chart(
            &path,
            "t",
            "nu",
            "size",
            std::slice::from_ref(&size),
            true,
            "no cycle",
        )
        .unwrap();
        let pic = decode(&path, (900, 700));
        assert!(pic.count(MISSING) > 40, "missing values are marked");
        assert!(pic.count(STEADY) > 100);
        // Every value present: no marks.
        let full = Curve {
            ys: vec![0.1, 0.2, 0.5, 1.0, 1.5, 2.0],
            ..size.clone()
        };
        sweep_chart(&path, "t", "nu", "size", &[full], true, "no cycle").unwrap();
        assert_eq!(decode(&path, (900, 700)).count(MISSING), 0);
        // No value at all: only the marks, no error.
        let none = Curve {
            ys: vec![f64::NAN; 6],
            ..size
        };
        sweep_chart(&path, "t", "nu", "size", &[none], true, "no cycle").unwrap();
        assert!(decode(&path, (900, 700)).count(MISSING) > 60);
    }

    #[test]
    fn line_plot_log_x() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sweep.png");
        let nu: Vec<f64> = (0..40)
            .map(|k| 10f64.powf(-3.0 + k as f64 / 10.0))
            .collect();
        let size: Vec<f64> = nu.iter().map(|n| 1.0 + n.ln().abs().sqrt()).collect();
        let mut xs = nu.clone();
        xs.push(0.0); // skipped on a log axis
        let mut ys = size.clone();
        ys.push(3.0);
        let curve = Curve {
            label: "cycle size".into(),
            xs,
            ys,
            color: STICK,
            points_only: false,
        };
        line_plot(&path, "Cycle size vs nu", "nu", "size", &[curve], &[], true).unwrap();
        assert!(decode(&path, (900, 700)).count(STICK) > 500);
    }

    #[test]
    fn line_plot_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.png");
        let empty = Curve {
            label: "empty".into(),
            xs: vec![],
            ys: vec![],
            color: STEADY,
            points_only: false,
        };
        assert!(matches!(
            line_plot(&path, "t", "x", "y", &[empty], &[], false),
            Err(PlotError::NoDrawablePoint { .. })
        ));
        let nan = Curve {
            label: "nan".into(),
            xs: vec![f64::NAN, 1.0],
            ys: vec![0.0, f64::NAN],
            color: STEADY,
            points_only: false,
        };
        assert!(matches!(
            line_plot(&path, "t", "x", "y", &[nan], &[], false),
            Err(PlotError::NoDrawablePoint { .. })
        ));
        let negative = Curve {
            label: "negative".into(),
            xs: vec![-1.0, 0.0],
            ys: vec![1.0, 2.0],
            color: STEADY,
            points_only: false,
        };
        assert!(matches!(
            line_plot(&path, "t", "x", "y", &[negative], &[], true),
            Err(PlotError::NoDrawablePoint { .. })
        ));
        let mismatch = Curve {
            label: "m".into(),
            xs: vec![1.0, 2.0],
            ys: vec![1.0],
            color: STEADY,
            points_only: false,
        };
        assert!(matches!(
            line_plot(&path, "t", "x", "y", &[mismatch], &[], false),
            Err(PlotError::ShapeMismatch {
                expected: 2,
                found: 1,
                ..
            })
        ));
        assert!(matches!(
            line_plot(&path, "t", "x", "y", &[], &[], false),
            Err(PlotError::EmptyData(_))
        ));
        assert!(!path.exists());
        // A single point or only a marker still works (degenerate ranges are widened).
        let single = Curve {
            label: "one".into(),
            xs: vec![2.0],
            ys: vec![3.0],
            color: STEADY,
            points_only: false,
        };
        line_plot(&path, "t", "x", "y", &[single], &[fixed_point()], false).unwrap();
        decode(&path, (900, 700));
    }

    #[test]
    fn draw_error_names_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing-dir").join("x.png");
        let c = circle(1.0, 0.0, 10);
        let err = line_plot(&path, "t", "x", "y", &[c], &[], false).unwrap_err();
        assert!(matches!(err, PlotError::Draw(ref m) if m.contains("missing-dir")));
    }

    #[test]
    fn basin_map_writes_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("basin.png");
        let x0 = linspace(-1.0, 3.0, 200);
        let v0 = linspace(-2.0, 2.0, 160);
        let labels = grid_labels(&x0, &v0, 0.9);
        let panel = BasinPanel {
            axis_labels: None,
            title: map_title(&table1("mcmillan")),
            x0: &x0,
            v0: &v0,
            labels: &labels,
            overlays: vec![circle(0.9, 1.0, 300), circle(2.5, 1.0, 300)],
            markers: vec![fixed_point()],
        };
        basin_map(&path, &panel, &classes()).unwrap();
        let pic = decode(&path, (900, 800));
        for c in [STEADY, STICK, UNDECIDED, NOT_COMPUTED, OTHER] {
            assert!(pic.count(c) > 100, "colour {c:?} missing");
        }
        // The grid is 4 x 4 units: with equal scales the image is square. The image's
        // outline is the extent of the stick-slip colour left of the legend.
        let map_w = 900 - LEGEND_WIDTH;
        let left = Picture {
            width: map_w,
            height: 800,
            rgb: (0..800)
                .flat_map(|y| {
                    let i = 3 * (y * 900) as usize;
                    pic.rgb[i..i + 3 * map_w as usize].to_vec()
                })
                .collect(),
        };
        let (a, b, c, d) = left.bbox(STICK).unwrap();
        let (w, h) = ((c - a) as i64, (d - b) as i64);
        assert!((w - h).abs() <= 2, "image {w} x {h} pixels");
    }

    #[test]
    fn basin_map_degenerate_axes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("row.png");
        let x0 = linspace(0.0, 2.0, 50);
        let v0 = [0.5];
        let labels: Vec<u8> = (0..50).map(|i| (i % 3) as u8).collect();
        let panel = BasinPanel {
            axis_labels: None,
            title: "one row".into(),
            x0: &x0,
            v0: &v0,
            labels: &labels,
            overlays: vec![],
            markers: vec![],
        };
        basin_map(&path, &panel, &classes()).unwrap();
        let pic = decode(&path, (900, 800));
        assert!(pic.count(STEADY) > 100 && pic.count(STICK) > 100);
        // Descending axes and a single cell also work.
        let x1 = [1.0];
        let panel = BasinPanel {
            axis_labels: None,
            x0: &x1,
            labels: &labels[..1],
            ..panel
        };
        basin_map(&path, &panel, &classes()).unwrap();
        let v2 = linspace(1.0, -1.0, 50);
        let panel = BasinPanel {
            axis_labels: None,
            x0: &x1,
            v0: &v2,
            labels: &labels,
            ..panel
        };
        basin_map(&path, &panel, &[]).unwrap();
        // No classes: every cell is "other".
        assert!(decode(&path, (900, 800)).count(OTHER) > 1000);
    }

    #[test]
    fn basin_map_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.png");
        let x0 = linspace(0.0, 1.0, 4);
        let v0 = linspace(0.0, 1.0, 3);
        let labels = vec![1u8; 11];
        let panel = BasinPanel {
            axis_labels: None,
            title: "bad".into(),
            x0: &x0,
            v0: &v0,
            labels: &labels,
            overlays: vec![],
            markers: vec![],
        };
        assert!(matches!(
            basin_map(&path, &panel, &classes()),
            Err(PlotError::ShapeMismatch {
                expected: 12,
                found: 11,
                ..
            })
        ));
        assert!(matches!(
            basin_sheet(&path, "t", std::slice::from_ref(&panel), &classes(), 2),
            Err(PlotError::ShapeMismatch { .. })
        ));
        let empty = BasinPanel {
            axis_labels: None,
            x0: &[],
            labels: &[],
            ..panel.clone()
        };
        assert!(matches!(
            basin_map(&path, &empty, &classes()),
            Err(PlotError::EmptyData(_))
        ));
        let uneven = [0.0, 0.1, 0.5, 1.0];
        let labels12 = vec![1u8; 12];
        let bad_grid = BasinPanel {
            axis_labels: None,
            x0: &uneven,
            labels: &labels12,
            ..panel.clone()
        };
        assert!(matches!(
            basin_map(&path, &bad_grid, &classes()),
            Err(PlotError::InvalidGrid(_))
        ));
        let bad_overlay = BasinPanel {
            axis_labels: None,
            labels: &labels12,
            overlays: vec![Curve {
                label: "c".into(),
                xs: vec![0.0],
                ys: vec![],
                color: CYCLE,
                points_only: false,
            }],
            ..panel.clone()
        };
        assert!(matches!(
            basin_map(&path, &bad_overlay, &classes()),
            Err(PlotError::ShapeMismatch { .. })
        ));
        assert!(matches!(
            basin_sheet(&path, "t", &[], &classes(), 2),
            Err(PlotError::EmptyData(_))
        ));
        assert!(!path.exists());
    }

    #[test]
    fn basin_sheet_writes_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sheet.png");
        let x0 = linspace(-1.0, 3.0, 120);
        let v0 = linspace(-2.0, 2.0, 100);
        let radii = [0.5, 0.9, 1.3, 1.6, 1.9];
        let labels: Vec<Vec<u8>> = radii.iter().map(|&r| grid_labels(&x0, &v0, r)).collect();
        let panels: Vec<BasinPanel<'_>> = radii
            .iter()
            .zip(&labels)
            .map(|(&r, l)| BasinPanel {
                axis_labels: None,
                title: panel_title("r", r),
                x0: &x0,
                v0: &v0,
                labels: l,
                overlays: vec![circle(r, 1.0, 200)],
                markers: vec![fixed_point()],
            })
            .collect();
        let title = sheet_title("test", &table1("mcmillan"), "nu");
        basin_sheet(&path, &title, &panels, &classes(), 3).unwrap();
        // 3 columns of 440 px plus the legend; 2 rows of 420 px plus a two-line title.
        let pic = decode(&path, (3 * 440 + LEGEND_WIDTH, 2 * 420 + 33 + 27 + 10));
        for c in [STEADY, STICK, UNDECIDED, NOT_COMPUTED] {
            assert!(pic.count(c) > 100, "colour {c:?} missing");
        }
        // ncols = 0 is clamped rather than rejected.
        let path = dir.path().join("sheet-one-column.png");
        basin_sheet(&path, "one column", &panels[..2], &classes(), 0).unwrap();
        decode(&path, (440 + LEGEND_WIDTH, 2 * 420 + 33 + 10));
    }

    #[test]
    fn large_basin_map_shows_the_right_shares() {
        // A 1024 x 1024 grid is resampled to the plotting area: the share of steady-slip
        // pixels in the image matches the share of steady-slip cells (within 1%).
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("large.png");
        let n = 1024;
        let x0 = linspace(-1.0, 3.0, n);
        let v0 = linspace(-2.0, 2.0, n);
        let labels: Vec<u8> = v0
            .iter()
            .flat_map(|&v| x0.iter().map(move |&x| 1 + u8::from(x + v > 1.0 + 0.8)))
            .collect();
        let panel = BasinPanel {
            axis_labels: None,
            title: "1024 x 1024".into(),
            x0: &x0,
            v0: &v0,
            labels: &labels,
            overlays: vec![],
            markers: vec![],
        };
        basin_map(&path, &panel, &classes()).unwrap();
        let pic = decode(&path, (900, 800));
        let cells = labels.iter().filter(|&&l| l == 1).count() as f64 / labels.len() as f64;
        // The legend holds one swatch of each colour (22 x 22 px, 21 x 21 inside its border).
        let steady = pic.count(STEADY) as f64 - 21.0 * 21.0;
        let stick = pic.count(STICK) as f64 - 21.0 * 21.0;
        let share = steady / (steady + stick);
        assert!(
            (share - cells).abs() < 0.01,
            "pixels {share}, cells {cells}"
        );
    }
}
