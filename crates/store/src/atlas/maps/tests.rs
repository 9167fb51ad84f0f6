//! Reading an atlas file's final-state sensitivity back.

use super::*;

/// An atlas plan with maps over the values `nu` of nu (a TOML list).
fn plan(nu: &str) -> AtlasPlan {
    let spec = format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = {nu}\n\
         [grid]\nx0 = {{ min = -2.0, max = 4.0, count = 10 }}\n\
         v0 = {{ min = -3.0, max = 3.0, count = 8 }}\n[output]\npath = \"x.h5\"\n"
    );
    AtlasPlan::from_toml(&spec, "x.toml").expect("a valid spec")
}

const NU: &str = "[1e-3, 1e-2, 3e-2]";

/// An atlas file at `path` holding the `map_` datasets `f64s` and `map_log2_test`.
fn file(path: &Path, f64s: &[(&str, [f64; 3])], log2: Option<[u8; 3]>) {
    let f = File::create(path).unwrap();
    str_attr(&f, "schema", crate::ATLAS_SCHEMA).unwrap();
    for (name, v) in f64s {
        let ds = f.new_dataset_builder().with_data(&v[..]);
        ds.create(map_name(name).as_str()).unwrap();
    }
    if let Some(v) = log2 {
        let ds = f.new_dataset_builder().with_data(&v[..]);
        ds.create(map_name("log2_test").as_str()).unwrap();
    }
}

#[test]
fn the_sensitivity_is_read_per_point_and_absent_figures_are_nan() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.h5");
    let nan = f64::NAN;
    // Point 0: no complete map; 1: a fractal boundary; 2: no boundary box. No step
    // sensitivity stored (a figure the file predates).
    file(
        &path,
        &[
            ("boundary_basin_entropy", [nan, 0.8, nan]),
            ("basin_entropy_boxes", [nan, 4.0, 4.0]),
        ],
        Some([2, 1, 2]),
    );
    let s = read_map_sensitivity(&path, &plan(NU))
        .unwrap()
        .expect("stored");
    assert_eq!(s.values.len(), 3);
    assert_eq!(s.values[1].len(), SENSITIVITY_FIELDS.len());
    let sbb = s.field("boundary_basin_entropy");
    assert!(
        sbb[0].is_nan() && sbb[1] == 0.8 && sbb[2].is_nan(),
        "{sbb:?}"
    );
    assert!(s.field("step_sensitivity").iter().all(|v| v.is_nan()));
    assert!(s.field("no such figure").iter().all(|v| v.is_nan()));
    let tests = [None, Some(Log2Test::Fractal), Some(Log2Test::NoBoundary)];
    assert_eq!(s.log2_test, tests);
    // A file written before the sensitivity was stored: none, no error.
    let old = dir.path().join("old.h5");
    file(&old, &[("basin_entropy", [0.1; 3])], None);
    assert_eq!(read_map_sensitivity(&old, &plan(NU)).unwrap(), None);
    // Another number of points than the stored spec's is refused.
    let other = dir.path().join("other.h5");
    file(&other, &[("boundary_basin_entropy", [0.5; 3])], None);
    assert!(read_map_sensitivity(&other, &plan("[1e-3, 1e-2]")).is_err());
}
