//! Tests of the plot crate: pictures are drawn to temporary files and decoded.

use super::*;
use crate::basin::{clip_polyline, clip_segment};
use crate::legend::LEGEND_WIDTH;

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
    // A sweep value of 1e-3 as a log-spaced grid computes it.
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
    phase_plot(
        &path,
        "round",
        StateScale::KineticFriction,
        &[c.clone(), far.clone()],
        &[],
    )
    .unwrap();
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

/// A physical system's phase plane (`squeal ulc --plot`) is drawn in
/// metres and m/s, and still at equal scales in the model's units: the clamped pad's length
/// unit is 2.85 mm and its velocity unit 1.425 m/s (crates/core/src/units.rs's
/// `a_normal_force_stands_for_the_weight`), so at equal scales in m and m/s a circle would be
/// a strip 500 times taller than wide. Before, the picture was in the model's units only.
#[test]
fn a_physical_phase_plane_is_in_si_units_and_round() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("si.png");
    let mut c = circle(1.0, 1.0, 720);
    c.color = STICK;
    c.label = String::new();
    let si = SiState {
        length: 2.85e-3,
        velocity: 1.425,
        time: 2e-3,
    };
    assert_eq!(
        SiState::PHASE_LABELS,
        ["displacement x (m)", "velocity x' (m/s)"]
    );
    phase_plot_si(&path, "si", si, &[c], &[]).unwrap();
    let pic = decode(&path, (900, 800));
    let (x0, y0, x1, y1) = pic.bbox(STICK).expect("the circle is drawn");
    let (w, h) = ((x1 - x0) as i64, (y1 - y0) as i64);
    assert!(
        w > 100 && (w - h).abs() <= 3,
        "cycle drawn {w} x {h} pixels"
    );
}

/// One gap group holding every missing value of `curves`.
fn one_gap(curves: &[Curve]) -> Vec<Gap> {
    vec![Gap {
        label: "no cycle".into(),
        xs: missing_values(curves, true),
        glyph: Glyph::TriangleUp,
        color: MISSING,
    }]
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
        missing_values(std::slice::from_ref(&size), true),
        [2e-2, 5e-2]
    );
    let gaps = one_gap(std::slice::from_ref(&size));
    sweep_chart(
        &path,
        "t",
        "nu",
        "size",
        std::slice::from_ref(&size),
        true,
        &gaps,
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
    let gaps = one_gap(std::slice::from_ref(&full));
    sweep_chart(&path, "t", "nu", "size", &[full], true, &gaps).unwrap();
    assert_eq!(decode(&path, (900, 700)).count(MISSING), 0);
    // No value at all: only the marks, no error.
    let none = Curve {
        ys: vec![f64::NAN; 6],
        ..size
    };
    let gaps = one_gap(std::slice::from_ref(&none));
    sweep_chart(&path, "t", "nu", "size", &[none], true, &gaps).unwrap();
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

/// Data over more decades than a log axis can span are drawn on a linear axis: a sweep over
/// `nu = [1e-300, 1e-3]` never finished drawing (plotters' log mesh loops without end once
/// the ratio of the axis's ends overflows to inf; this test did not finish on that code).
#[test]
fn line_plot_over_hundreds_of_decades_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.png");
    let curve = Curve {
        label: "cycle size".into(),
        xs: vec![1e-300, 1e-3],
        ys: vec![1.0, 2.0],
        color: STICK,
        points_only: false,
    };
    line_plot(&path, "wide", "nu", "size", &[curve], &[], true).unwrap();
    // The segment between the two points crosses the plotting area (about 800 px wide, 2 px
    // thick): far more than 500 pixels of its colour.
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

/// A basin panel of McMillan's law at Table 1 over `x0` and `v0` with `labels`, the fixed
/// point marked and `overlays` drawn.
fn table1_panel<'a>(
    x0: &'a [f64],
    v0: &'a [f64],
    labels: &'a [u8],
    overlays: Vec<Curve>,
) -> BasinPanel<'a> {
    BasinPanel {
        axis_labels: None,
        title: map_title(&table1("mcmillan")),
        x0,
        v0,
        labels,
        overlays,
        markers: vec![fixed_point()],
    }
}

#[test]
fn basin_map_writes_png() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("basin.png");
    let x0 = linspace(-1.0, 3.0, 200);
    let v0 = linspace(-2.0, 2.0, 160);
    let labels = grid_labels(&x0, &v0, 0.9);
    let overlays = vec![circle(0.9, 1.0, 300), circle(2.5, 1.0, 300)];
    let panel = table1_panel(&x0, &v0, &labels, overlays);
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
fn basin_map_is_the_same_file_at_any_thread_count() {
    // The image's rows and the cell counts are made on the rayon pool: the PNG must be the
    // same bytes in a pool of 1 thread and of 4 (a grid of 300 x 257 cells, not a multiple
    // of the pixels, so that rows map to cells unevenly).
    let dir = tempfile::tempdir().unwrap();
    let x0 = linspace(-1.0, 3.0, 300);
    let v0 = linspace(-2.0, 2.0, 257);
    let labels = grid_labels(&x0, &v0, 0.9);
    let panel = table1_panel(&x0, &v0, &labels, vec![circle(0.9, 1.0, 300)]);
    let bytes: Vec<Vec<u8>> = [1, 4]
        .into_iter()
        .map(|n| {
            let path = dir.path().join(format!("basin-{n}.png"));
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            pool.install(|| basin_map(&path, &panel, &classes()).unwrap());
            std::fs::read(&path).unwrap()
        })
        .collect();
    assert!(bytes[0] == bytes[1], "the pictures differ");
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

mod marks;
