//! Marks that tell reasons apart, legends clear of data, and each law's axis units.

use super::*;
use crate::line::{Corner, densify, place_legend};

/// One hollow triangle cannot tell "every start squeals" from "no start squeals". Two gap
/// groups of one colour each are drawn as two shapes: a triangle up has its widest row at
/// the bottom, a triangle down at the top.
#[test]
fn sweep_chart_gap_groups_have_their_own_glyph() {
    assert_ne!(Glyph::TriangleUp.outline(), Glyph::TriangleDown.outline());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("gaps.png");
    let xs = [1.0, 2.0, 3.0, 4.0];
    let size = Curve {
        label: "size".into(),
        xs: xs.to_vec(),
        ys: vec![f64::NAN, 0.5, 0.6, f64::NAN],
        color: CYCLE,
        points_only: false,
    };
    let (up, down) = (Rgb(0, 200, 0), Rgb(0, 0, 230));
    let gaps = [
        Gap {
            label: "every start squeals".into(),
            xs: vec![1.0],
            glyph: Glyph::TriangleUp,
            color: up,
        },
        Gap {
            label: "no start squeals".into(),
            xs: vec![4.0],
            glyph: Glyph::TriangleDown,
            color: down,
        },
    ];
    sweep_chart(&path, "t", "x", "size", &[size], false, &gaps).unwrap();
    let pic = decode(&path, (900, 700));
    // Widest fill rows of the lowest mark of that colour (the legend's sample lies far
    // above it), in the upper and the lower half of the 16 rows above its lowest pixel.
    let widths = |c: Rgb| -> (u32, u32) {
        let (x0, _, x1, y1) = pic.bbox(c).unwrap();
        let row = |y: u32| (x0..=x1).filter(|&x| pic.pixel(x, y) == c).count() as u32;
        let rows: Vec<u32> = (y1 - 15..=y1).map(row).collect();
        let filled = rows.iter().filter(|&&w| w > 0).count();
        assert!(filled >= 6, "a mark, not a dot: {filled} rows");
        let widest = |r: &[u32]| r.iter().copied().max().unwrap_or(0);
        (widest(&rows[..8]), widest(&rows[8..]))
    };
    let (top, bottom) = widths(up);
    assert!(
        bottom > top,
        "triangle up: wide at the bottom ({top} vs {bottom})"
    );
    let (top, bottom) = widths(down);
    assert!(
        top > bottom,
        "triangle down: wide at the top ({top} vs {bottom})"
    );
}

/// The legend of `stribeck-vd.png` once covered a vertical line whose ends lie outside
/// the legend's corner. Every corner holds data here: the vertical line at x = 0.1 crosses the
/// upper left, a curve runs through the upper right and points sit in the lower corners. The
/// legend must then go where no data is, which takes room above the data.
#[test]
fn the_legend_covers_no_data() {
    let mut points = Vec::new();
    // A vertical line from the bottom to the top at x = 0.1: only its ends are vertices.
    densify(&[(0.1, 0.0), (0.1, 0.95)], &mut points);
    densify(&[(0.5, 0.5), (0.95, 0.95)], &mut points);
    points.extend([(0.05, 0.05), (0.95, 0.05)]);
    let size = (0.45, 0.3);
    let (corner, stretch) = place_legend(&points, size);
    assert!(
        stretch > 1.0,
        "no corner is free: room is made above the data"
    );
    // After stretching the y range, no point lies in the legend's box.
    let (wx, wy) = corner.window(size);
    let covered = points
        .iter()
        .filter(|(x, y)| wx.contains(x) && wy.contains(&(y / stretch)))
        .count();
    assert_eq!(covered, 0, "{corner:?} x {stretch}");
    // A free corner is taken as it is.
    let free = [(0.1, 0.1), (0.9, 0.1), (0.1, 0.9)];
    assert_eq!(place_legend(&free, size), (Corner::UpperRight, 1.0));
}

/// Stribeck pictures must not say "(unit: μk m g / k)": the Stribeck law is divided by the
/// normal load (MODEL.md section 8: the friction coefficient is the force), so its axes
/// carry no μk; McMillan's keep it.
#[test]
fn each_law_has_its_own_axis_units() {
    let stribeck = StateScale::of_law("stribeck");
    assert_eq!(stribeck, StateScale::NormalLoad);
    // Every law with true stick is written in the normal load (MODEL.md section 8), and
    // titled by its own words; an unknown name keeps McMillan's scale and its own name.
    assert_eq!(StateScale::of_law("cubic"), StateScale::NormalLoad);
    assert_eq!(crate::law_title("cubic"), "cubic law with true stick");
    assert_eq!(StateScale::of_law("zz"), StateScale::KineticFriction);
    assert_eq!(crate::law_title("zz"), "zz");
    for label in stribeck
        .phase_labels()
        .iter()
        .chain(&stribeck.initial_labels())
    {
        assert!(!label.contains("μk"), "{label}");
        assert!(label.contains("(unit: m g / k)") || label.contains("(unit: g √(m/k))"));
    }
    for law in ["mcmillan", "mcmillan-nonhysteretic", "coulomb"] {
        let s = StateScale::of_law(law);
        assert_eq!(s.initial_labels(), [X0_LABEL, V0_LABEL], "{law}");
        assert_eq!(s.phase_labels(), [X_LABEL, V_LABEL], "{law}");
    }
}

/// The fold and its "bracket moves at dt/2" points once were a black line and small
/// yellow dots on it (a run of them a yellow line). Marks are now glyphs: a yellow diamond
/// (`Glyph::Diamond`'s outline spans y = -8..8, its fill at least 11 px of it inside the
/// black border) on the black line, never joined.
#[test]
fn stability_chart_marks_are_glyphs_apart_from_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("marks.png");
    let (xs, ys) = ([1.0, 2.0, 3.0, 4.0], [1.0, 2.0]);
    let yellow = Rgb(250, 220, 0);
    let fold = Curve {
        label: "fold".into(),
        xs: xs.to_vec(),
        ys: vec![1.5; 4],
        color: CYCLE,
        points_only: false,
    };
    // Two neighbouring moved points: a curve would join them into a yellow line.
    let chart = StabilityChart {
        title: "t".into(),
        subtitle: "s".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        xs: &xs,
        ys: &ys,
        log_x: false,
        log_y: false,
        classes: &[1; 8],
        palette: vec![(1, "a", STEADY)],
        field: None,
        levels: vec![],
        field_name: String::new(),
        curves: vec![fold],
        dashed: vec![],
        marks: vec![Marks {
            label: "fold: bracket moves at dt/2".into(),
            xs: vec![f64::NAN, 2.0, 3.0, f64::NAN],
            ys: vec![f64::NAN, 1.5, 1.5, f64::NAN],
            glyph: Glyph::Diamond,
            fill: yellow,
        }],
    };
    stability_chart(&p, &chart).unwrap();
    let pic = decode(&p, (1300, 900));
    // The plot is the left 900 px; the legend's sample lies right of it.
    let plot: Vec<(u32, u32)> = (0..pic.height)
        .flat_map(|y| (0..900).map(move |x| (x, y)))
        .filter(|&(x, y)| pic.pixel(x, y) == yellow)
        .collect();
    let (y0, y1) = plot
        .iter()
        .fold((u32::MAX, 0), |(a, b), p| (a.min(p.1), b.max(p.1)));
    assert!(
        y1 - y0 >= 10,
        "a diamond, taller than a dot: {} px",
        y1 - y0 + 1
    );
    // Between the two marks the line stays black: along the row through them, the yellow
    // pixels form two groups far apart.
    let row = (y0 + y1) / 2;
    let yellow_xs: Vec<u32> = (0..900).filter(|&x| pic.pixel(x, row) == yellow).collect();
    let (first, last) = (yellow_xs[0], *yellow_xs.last().unwrap());
    let gap = (first..=last)
        .filter(|&x| pic.pixel(x, row) != yellow)
        .count();
    assert!(gap > 50, "the marks are not joined ({gap} px apart)");
}

/// A fold whose coarse scan found more than one change of regime along the
/// damping is marked on the atlas's chart with its own glyph (a red square, in the chart and
/// its legend); the same chart with one change per fold has no red at all.
#[test]
fn a_fold_that_flips_is_marked_on_the_atlas_chart() {
    use squeal_scan::atlas::driver::{BoundaryResult, UnitResult};
    use squeal_scan::atlas::{AtlasPlan, AtlasResults, Boundary, BoundaryStatus};
    let plan = AtlasPlan::from_toml(
        "version = 1\nname = \"flip\"\n[model]\nlaw = \"mcmillan\"\n\
         nu = { from = 1e-3, to = 0.05, count = 4, spacing = \"log\" }\n\
         lambda = { from = 1.0, to = 4.0, count = 3 }\n[output]\npath = \"flip.h5\"\n",
        "flip.toml",
    )
    .unwrap();
    assert_eq!(plan.n_boundaries(), 3);
    let red = Rgb(230, 60, 60);
    let draw = |flips: u32| {
        let mut res = AtlasResults::new(&plan);
        for j in 0..plan.n_boundaries() {
            let fold = Boundary {
                status: BoundaryStatus::Found,
                nu: 0.02,
                bracket: [0.019, 0.021],
                evaluations: 10,
                half_dt_holds: Some(true),
                uncertainty: 0.001,
                changes: if j == 1 { flips } else { 1 },
            };
            let b = BoundaryResult {
                index: j,
                fold,
                critical: Boundary::none(),
                lifetime: Default::default(),
                note: None,
            };
            res.add(&plan, UnitResult::Boundary(b));
        }
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("flip.png");
        atlas_chart(&plan, &res, &p).unwrap();
        let file = std::fs::File::open(&p).unwrap();
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        buf.chunks_exact(3)
            .filter(|px| px == &[red.0, red.1, red.2])
            .count()
    };
    let (flipping, plain) = (draw(3), draw(1));
    assert!(flipping > 20, "a square glyph: {flipping} red pixels");
    assert_eq!(plain, 0);
}

/// A sweep's values without a cycle are grouped by what the map found, not one triangle.
/// Counts are `[undecided, steady, stick, not computed]` per map (as `FileInfo::counts`).
#[test]
fn values_without_a_cycle_are_grouped_by_what_the_map_found() {
    let xs = [0.8, 1.0, 1.5, 2.0, 2.2];
    let counts = [
        [0, 0, 100, 0, 0], // stick-slip only: the fixed point repels
        [3, 0, 97, 0, 0],  // stick-slip and undecided cells: still no steady start
        [0, 40, 60, 0, 0], // both basins (has a cycle: not among `missing`)
        [0, 100, 0, 0, 0], // steady slip only: above the fold
        [10, 45, 45, 0, 0],
    ];
    let missing = [0.8, 1.0, 2.0, 2.2];
    let gaps = cycle_gaps(&missing, &xs, &counts);
    let of = |g: Glyph| gaps.iter().find(|x| x.glyph == g).map(|x| x.xs.clone());
    assert_eq!(of(Glyph::TriangleUp), Some(vec![0.8, 1.0]));
    assert_eq!(of(Glyph::TriangleDown), Some(vec![2.0]));
    assert_eq!(of(Glyph::Diamond), Some(vec![2.2]));
    assert!(gaps[0].label.contains("every start squeals"));
    assert!(gaps[1].label.contains("no start squeals"));
}

/// Under true stick the fold and the critical line coincide, and the fold (black) was drawn
/// under the critical line (purple) at the same width: not one black pixel of it showed.
/// Now the fold is drawn dashed on top: in the plot (the left 900 px) a chart whose fold
/// lies on its critical line has black pixels that the same chart without the fold lacks,
/// and the critical line's purple still shows between the dashes.
#[test]
fn a_fold_on_the_critical_line_is_seen_on_the_atlas_chart() {
    use squeal_scan::atlas::driver::{BoundaryResult, UnitResult};
    use squeal_scan::atlas::{AtlasPlan, AtlasResults, Boundary, BoundaryStatus};
    let plan = AtlasPlan::from_toml(
        "version = 1\nname = \"same\"\n[model]\nlaw = \"mcmillan\"\n\
         nu = { from = 1e-3, to = 0.05, count = 4, spacing = \"log\" }\n\
         lambda = { from = 1.0, to = 4.0, count = 3 }\n[output]\npath = \"same.h5\"\n",
        "same.toml",
    )
    .unwrap();
    let (black, purple) = (Rgb(0, 0, 0), Rgb(120, 0, 160));
    let found = |nu: f64| Boundary {
        status: BoundaryStatus::Found,
        nu,
        bracket: [nu - 1e-4, nu + 1e-4],
        evaluations: 10,
        half_dt_holds: Some(true),
        uncertainty: f64::NAN,
        changes: 1,
    };
    let draw = |with_fold: bool| {
        let mut res = AtlasResults::new(&plan);
        for j in 0..plan.n_boundaries() {
            // The same value for both, as under true stick: the fold is the critical value.
            let nu = 0.01 + 0.005 * j as f64;
            let b = BoundaryResult {
                index: j,
                fold: if with_fold {
                    found(nu)
                } else {
                    Boundary::none()
                },
                critical: found(nu),
                lifetime: Default::default(),
                note: None,
            };
            res.add(&plan, UnitResult::Boundary(b));
        }
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("same.png");
        atlas_chart(&plan, &res, &p).unwrap();
        let pic = decode(&p, (1300, 900));
        let in_plot = |c: Rgb| {
            (0..pic.height)
                .flat_map(|y| (0..900).map(move |x| (x, y)))
                .filter(|&(x, y)| pic.pixel(x, y) == c)
                .count()
        };
        (in_plot(black), in_plot(purple))
    };
    let ((black_both, purple_both), (black_alone, purple_alone)) = (draw(true), draw(false));
    assert!(purple_alone > 300, "the critical line: {purple_alone} px");
    assert!(
        black_both > black_alone + 100,
        "the fold's black on the critical line: {black_both} px against {black_alone} without it"
    );
    assert!(
        purple_both > purple_alone / 4,
        "the critical line between the fold's dashes: {purple_both} of {purple_alone} px"
    );
}
