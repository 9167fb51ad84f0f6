//! The picture of final-state sensitivity drawn from synthetic figures, decoded.

use super::*;

/// An atlas plan with maps over `model` (the `[model]` table's keys).
fn plan(model: &str) -> AtlasPlan {
    let spec = format!(
        "version = 1\nname = \"sens\"\n[model]\nlaw = \"mcmillan\"\n{model}\n\
         [grid]\nx0 = {{ min = -2.0, max = 4.0, count = 10 }}\n\
         v0 = {{ min = -3.0, max = 3.0, count = 8 }}\n[output]\npath = \"x.h5\"\n"
    );
    AtlasPlan::from_toml(&spec, "x.toml").expect("a valid spec")
}

/// One point's figures in the order of [`SENSITIVITY_FIELDS`], `set` by name (NaN else).
fn point(set: &[(&str, f64)]) -> Vec<f64> {
    (SENSITIVITY_FIELDS.iter())
        .map(|f| set.iter().find(|s| s.0 == f.0).map_or(f64::NAN, |s| s.1))
        .collect()
}

/// A measured map: S_bb `sbb` (its verdict from it), step share `step` with its error,
/// uncertainty exponent `alpha`.
fn measured(sbb: f64, step: f64, alpha: f64) -> (Vec<f64>, Option<Log2Test>) {
    let v = point(&[
        ("boundary_basin_entropy", sbb),
        ("basin_entropy_boxes", 10.0),
        ("step_sensitivity", step),
        ("step_sensitivity_se", 0.3 * step),
        ("uncertainty_exponent", alpha),
        ("uncertainty_exponent_se", 0.1),
        ("uncertainty_samples", 256.0),
    ]);
    let t = if sbb > LN_2 {
        Log2Test::Fractal
    } else {
        Log2Test::Inconclusive
    };
    (v, Some(t))
}

/// The decoded pixels of a PNG as plotters writes it (8-bit RGB), with its size.
fn pixels(path: &Path) -> ((u32, u32), Vec<Rgb>) {
    let file = std::fs::File::open(path).expect("the picture is written");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    let px = buf.chunks_exact(3).map(|p| Rgb(p[0], p[1], p[2])).collect();
    ((info.width, info.height), px)
}

fn count_of(px: &[Rgb], c: Rgb) -> usize {
    px.iter().filter(|&&p| p == c).count()
}

#[test]
fn a_column_shows_the_entropy_the_step_and_the_exponent_per_point() {
    let plan = plan("nu = { from = 1e-3, to = 3e-2, count = 6, spacing = \"log\" }");
    let no_map = (point(&[]), None);
    let no_boundary = (
        point(&[("basin_entropy_boxes", 10.0)]),
        Some(Log2Test::NoBoundary),
    );
    let points = [
        no_boundary,
        measured(0.45, 0.002, 1.0),
        measured(0.62, 0.004, 0.9),
        measured(0.81, 0.03, 0.55),
        measured(0.95, 0.05, 0.4),
        no_map,
    ];
    let (values, tests): (Vec<_>, Vec<_>) = points.into_iter().unzip();
    let dir = tempfile::tempdir().unwrap();
    let png = sensitivity_path(&dir.path().join("sens.png"));
    assert!(png.ends_with("sens-sensitivity.png"));
    assert!(atlas_sensitivity(&plan, &values, &tests, &png).unwrap());
    let (size, px) = pixels(&png);
    // Three panels: S_bb, the step's share, the uncertainty exponent.
    assert_eq!(size, (COLUMN.0, 170 + 3 * PANEL));
    let white = count_of(&px, Rgb(255, 255, 255));
    assert!(white < px.len() * 97 / 100, "a blank picture");
    // Fractal points and shares above 1% are red diamonds, the others blue squares, the
    // map without a boundary a grey triangle, the exponent's points green (each glyph
    // about 60 pixels inside, in the plots and the legends).
    for (fill, least) in [
        (VERDICTS[0].2, 5 * 50),
        (VERDICTS[1].2, 5 * 50),
        (VERDICTS[2].2, 2 * 30),
        (Rgb(20, 130, 80), 5 * 50),
    ] {
        let n = count_of(&px, fill);
        assert!(n > least, "{fill:?}: {n} pixels");
    }
    // Without a fitted exponent: two panels.
    let no_alpha: Vec<Vec<f64>> = (values.iter())
        .map(|v| {
            let mut v = v.clone();
            let k = SENSITIVITY_FIELDS
                .iter()
                .position(|f| f.0 == "uncertainty_exponent");
            v[k.unwrap()] = f64::NAN;
            v
        })
        .collect();
    assert!(atlas_sensitivity(&plan, &no_alpha, &tests, &png).unwrap());
    assert_eq!(pixels(&png).0, (COLUMN.0, 170 + 2 * PANEL));
    // Without runs (`sensitivity_samples = 0`): the entropies alone.
    let entropies: Vec<Vec<f64>> = (no_alpha.iter())
        .map(|v| {
            let keep = ["boundary_basin_entropy", "basin_entropy_boxes"];
            let kept = SENSITIVITY_FIELDS
                .iter()
                .zip(v)
                .filter(|(f, _)| keep.contains(&f.0));
            point(&kept.map(|(f, &x)| (f.0, x)).collect::<Vec<_>>())
        })
        .collect();
    assert!(atlas_sensitivity(&plan, &entropies, &tests, &png).unwrap());
    assert_eq!(pixels(&png).0, (COLUMN.0, 170 + PANEL));
}

#[test]
fn a_chart_colours_each_point_and_rings_the_fractal_and_the_step_bound() {
    let plan = plan("nu = [1e-3, 1e-2, 3e-2]\nlambda = [2.5, 3.0]");
    // Points (nu, lambda) in C order: the rows are nu, the columns lambda.
    let points = [
        measured(0.3, 0.001, 1.0),
        measured(0.5, 0.005, 0.9),
        measured(0.75, 0.02, 0.6),
        measured(0.9, 0.04, 0.5),
        (point(&[]), None),
        (
            point(&[("basin_entropy_boxes", 10.0)]),
            Some(Log2Test::NoBoundary),
        ),
    ];
    let (values, tests): (Vec<_>, Vec<_>) = points.into_iter().unzip();
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("chart-sensitivity.png");
    assert!(atlas_sensitivity(&plan, &values, &tests, &png).unwrap());
    let (size, px) = pixels(&png);
    assert_eq!(size, (CHART.0, CHART.1));
    assert!(count_of(&px, Rgb(255, 255, 255)) < px.len() * 97 / 100);
    // The ends of the colour scale (the bars' ends; the largest value of each panel at
    // the top), the rings and the no-boundary triangle.
    for (c, least) in [
        (ramp(0.0), 2 * 20),
        (ramp(1.0), 2 * 500),
        (Rgb(0, 0, 0), 2000),
        (Rgb(150, 150, 150), 2 * 30),
    ] {
        let n = count_of(&px, c);
        assert!(n > least, "{c:?}: {n} pixels");
    }
    // The markers: many colours of the scale (4 measured points per panel).
    let mut seen: Vec<Rgb> = px.clone();
    seen.sort_by_key(|c| (c.0, c.1, c.2));
    seen.dedup();
    assert!(seen.len() > 100, "{} colours", seen.len());
}

#[test]
fn nothing_measured_draws_nothing() {
    let plan = plan("nu = [1e-3, 1e-2]");
    let values = vec![point(&[]), point(&[("basin_entropy_boxes", 10.0)])];
    let tests = [None, Some(Log2Test::NoBoundary)];
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("none.png");
    assert!(!atlas_sensitivity(&plan, &values, &tests, &png).unwrap());
    assert!(!png.exists());
    // Figures for another number of points are refused.
    let err = atlas_sensitivity(&plan, &values[..1], &tests, &png).unwrap_err();
    assert!(
        matches!(
            err,
            PlotError::ShapeMismatch {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{err}"
    );
}
