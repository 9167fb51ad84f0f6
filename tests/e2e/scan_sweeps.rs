//! End-to-end tests of a scan's sweep over several keys (one map per point of their
//! product): each map is the scan of its own point, and the file says which point it is.

use std::path::Path;

use crate::scan::{ok, spec, squeal};

/// A 9 x 7 grid around the fixed point (the e2e `TINY` grid), the model given by `model`.
fn grid_spec(model: &str, out: &str) -> String {
    format!(
        r#"version = 1
{model}
[grid]
x0 = {{ min = -3.0, max = 5.0, count = 9 }}
v0 = {{ min = -4.0, max = 4.0, count = 7 }}
block_rows = 2
[classifier]
t_max = 3000.0
[output]
path = "{out}"
"#
    )
}

fn labels(dir: &Path, file: &str) -> (Vec<usize>, Vec<u8>) {
    let f = hdf5::File::open(dir.join(file)).unwrap();
    let ds = f.dataset("labels").unwrap();
    (ds.shape(), ds.read_raw().unwrap())
}

fn f64s(f: &hdf5::File, name: &str) -> Vec<f64> {
    f.dataset(name).unwrap().read_raw().unwrap()
}

fn text_attr(f: &hdf5::File, name: &str) -> String {
    let a: hdf5::types::VarLenUnicode = f.attr(name).unwrap().read_scalar().unwrap();
    a.as_str().to_string()
}

/// A sweep of `nu` and `lambda` together makes one map per pair, the last key fastest, and
/// each map's labels are those of a scan of that pair alone (an independent run of the same
/// binary: same grid, same classifier). Before sweeps of every key, the spec was refused
/// ("only one of model.nu and model.lambda may be swept").
#[test]
fn a_sweep_of_two_keys_maps_each_pair_as_its_own_scan() {
    let d = tempfile::tempdir().unwrap();
    let (nus, lambdas) = ([1e-3, 2e-2], [2.0, 3.0]);
    let model = "[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 2e-2]\nlambda = [2.0, 3.0]";
    spec(d.path(), "both.toml", &grid_spec(model, "both.h5"));
    ok(&squeal(d.path(), &["scan", "both.toml", "--quiet"]));
    let (shape, all) = labels(d.path(), "both.h5");
    assert_eq!(shape, vec![4, 7, 9]);
    let f = hdf5::File::open(d.path().join("both.h5")).unwrap();
    assert_eq!(text_attr(&f, "swept"), "nu lambda");
    assert_eq!(f64s(&f, "nu"), [1e-3, 1e-3, 2e-2, 2e-2]);
    assert_eq!(f64s(&f, "lambda"), [2.0, 3.0, 2.0, 3.0]);
    let map: Vec<u64> = f.dataset("map").unwrap().read_raw().unwrap();
    assert_eq!(map, [0, 1, 2, 3]);
    // A swept key is a coordinate, not a root attribute; the others stay attributes.
    assert!(f.attr("nu").is_err() && f.attr("lambda").is_err());
    assert!(f.attr("tau").is_ok() && f.attr("phi").is_ok());
    for (m, (nu, lambda)) in nus
        .iter()
        .flat_map(|nu| lambdas.iter().map(move |l| (nu, l)))
        .enumerate()
    {
        let one = format!("one{m}.h5");
        let model = format!("[model]\nlaw = \"mcmillan\"\nnu = {nu:?}\nlambda = {lambda:?}");
        spec(d.path(), &format!("one{m}.toml"), &grid_spec(&model, &one));
        ok(&squeal(
            d.path(),
            &["scan", &format!("one{m}.toml"), "--quiet"],
        ));
        let (_, alone) = labels(d.path(), &one);
        assert_eq!(
            all[m * 63..(m + 1) * 63],
            alone[..],
            "map {m}: nu {nu}, lambda {lambda}"
        );
    }
    // info names both keys at every map; render draws the sheet (no cycle chart over two
    // keys: the sizes are in the file).
    let info = ok(&squeal(d.path(), &["info", "both.h5", "--json"]));
    let v: serde_json::Value = serde_json::from_str(&info).unwrap();
    let keys = &v["sweep"]["keys"];
    assert_eq!(keys[0]["name"], "nu");
    assert_eq!(keys[1]["values"], serde_json::json!([2.0, 3.0, 2.0, 3.0]));
    let text = ok(&squeal(d.path(), &["info", "both.h5"]));
    assert!(text.contains("nu = 2.0000e-2, lambda = 3.0000e0"), "{text}");
    ok(&squeal(d.path(), &["render", "both.h5", "-o", "again.png"]));
    assert!(d.path().join("again.png").exists());
    assert!(!d.path().join("again-cycle.png").exists());
}

/// A key that is neither the damping nor the belt speed may be swept alone: `tau` is the
/// maps' dimension, found by the `swept` list (readers looked for nu, lambda, xi, v_d only).
#[test]
fn a_surface_time_sweep_is_stored_and_read_back() {
    let d = tempfile::tempdir().unwrap();
    let model = "[model]\nlaw = \"mcmillan\"\nnu = 1e-3\ntau = [0.2, 0.4]";
    spec(d.path(), "tau.toml", &grid_spec(model, "tau.h5"));
    ok(&squeal(d.path(), &["scan", "tau.toml", "--quiet"]));
    let f = hdf5::File::open(d.path().join("tau.h5")).unwrap();
    assert_eq!(text_attr(&f, "swept"), "tau");
    assert_eq!(f64s(&f, "tau"), [0.2, 0.4]);
    assert!(f.attr("tau").is_err() && f.attr("nu").is_ok());
    let info = ok(&squeal(d.path(), &["info", "tau.h5", "--json"]));
    let v: serde_json::Value = serde_json::from_str(&info).unwrap();
    assert_eq!(v["sweep"]["name"], "tau");
    assert!(d.path().join("tau-cycle.png").exists());
}

/// A physical scan over the dashpot and the disc speed together: the maps' `nu` and `lambda`
/// are `c` and `v_belt` over the file's damping and velocity units, and `c` and `v_belt`
/// are stored in SI over the maps (no attribute of a single value).
#[test]
fn a_physical_scan_sweeps_the_dashpot_and_the_disc_speed() {
    let d = tempfile::tempdir().unwrap();
    // The brake of scans/brake.toml, its grid in metres and m/s.
    let text = r#"version = 1
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 5.0e4
c = [5.0, 10.0]
v_belt = [0.05, 0.1, 0.2]
mu_k = 0.35
mu_s = 0.45
tau = 1e-3
[grid]
x0 = { min = -1e-4, max = 2e-4, count = 5 }
v0 = { min = -0.01, max = 0.01, count = 4 }
[classifier]
t_max = 3000.0
[output]
path = "brake.h5"
"#;
    spec(d.path(), "brake.toml", text);
    ok(&squeal(d.path(), &["scan", "brake.toml", "--quiet"]));
    let f = hdf5::File::open(d.path().join("brake.h5")).unwrap();
    assert_eq!(text_attr(&f, "swept"), "nu lambda");
    let num = |n: &str| f.attr(n).unwrap().read_scalar::<f64>().unwrap();
    let (damping, velocity) = (num("damping_unit"), num("velocity_unit"));
    let (c, v_belt) = (f64s(&f, "c"), f64s(&f, "v_belt"));
    for (m, want) in [5.0, 5.0, 5.0, 10.0, 10.0, 10.0].iter().enumerate() {
        assert!((c[m] - want).abs() <= 1e-12 * want, "map {m}: c {}", c[m]);
    }
    let (nu, lambda) = (f64s(&f, "nu"), f64s(&f, "lambda"));
    for m in 0..6 {
        // Each map's model is its SI point over the units, to rounding.
        assert!((nu[m] * damping - c[m]).abs() <= 1e-12 * c[m], "map {m}");
        assert!(
            (lambda[m] * velocity - v_belt[m]).abs() <= 1e-12 * v_belt[m],
            "map {m}"
        );
    }
    assert!((v_belt[1] - 0.1).abs() < 1e-15 && (v_belt[5] - 0.2).abs() < 1e-15);
    assert!(f.attr("physical_c").is_err() && f.attr("physical_v_belt").is_err());
    assert!(f.attr("physical_m").is_ok());
    assert_eq!(labels(d.path(), "brake.h5").0, vec![6, 4, 5]);
}

/// An atlas of a physical system draws basin maps on a grid in m and m/s, as a scan of the
/// same system does: over the dashpot, each of its maps is the scan's map at that `c`, cell
/// for cell (the same scanner, classifier and grid in the model's units), and the grid is
/// stored in SI beside the model's. Before, `[grid]` with `[physical]` was refused.
#[test]
fn a_physical_atlas_draws_the_scans_maps_in_si_units() {
    let d = tempfile::tempdir().unwrap();
    let system = "[model]\nlaw = \"mcmillan\"\n[physical]\nm = 2.0\nk = 5.0e4\nc = [5.0, 10.0]\n\
                  v_belt = 0.05\nmu_k = 0.35\nmu_s = 0.45\ntau = 1e-3\n";
    let grid = "[grid]\nx0 = { min = -1e-4, max = 2e-4, count = 5 }\n\
                v0 = { min = -0.01, max = 0.01, count = 4 }\n[classifier]\nt_max = 3000.0\n";
    let atlas = format!(
        "version = 1\nname = \"pad\"\n{system}[boundaries]\nfold = false\ncritical = false\n\
         {grid}[output]\npath = \"atlas.h5\"\n"
    );
    let scan = format!("version = 1\n{system}{grid}[output]\npath = \"scan.h5\"\n");
    spec(d.path(), "atlas.toml", &atlas);
    spec(d.path(), "scan.toml", &scan);
    ok(&squeal(d.path(), &["atlas", "atlas.toml", "--quiet"]));
    ok(&squeal(d.path(), &["scan", "scan.toml", "--quiet"]));
    let a = hdf5::File::open(d.path().join("atlas.h5")).unwrap();
    let maps = a.dataset("map_labels").unwrap();
    assert_eq!(maps.shape(), vec![2, 4, 5]);
    let (shape, cells) = labels(d.path(), "scan.h5");
    assert_eq!(shape, vec![2, 4, 5]);
    assert_eq!(maps.read_raw::<u8>().unwrap(), cells);
    let s = hdf5::File::open(d.path().join("scan.h5")).unwrap();
    for name in ["x0", "v0", "x0_si", "v0_si"] {
        assert_eq!(f64s(&a, name), f64s(&s, name), "{name}");
    }
    assert!((f64s(&a, "x0_si")[4] - 2e-4).abs() < 1e-15);
    assert!(d.path().join("atlas-maps.png").exists());
    // The units must be one for every map: a swept mass is refused by name.
    let swept_m = atlas.replace("m = 2.0", "m = [2.0, 3.0]");
    spec(
        d.path(),
        "mass.toml",
        &swept_m.replace("atlas.h5", "mass.h5"),
    );
    let o = squeal(d.path(), &["atlas", "mass.toml", "--quiet"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("physical.m"), "{err}");
}

/// The brake of `a_physical_scan_sweeps_the_dashpot_and_the_disc_speed` with `surfaces`
/// for its `mu_s` and `tau` lines, on that test's grid in metres and m/s.
fn brake_surfaces(surfaces: &str, out: &str) -> String {
    format!(
        "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = 2.0\nk = 5.0e4\nc = 5.0\n\
         v_belt = 0.05\nmu_k = 0.35\n{surfaces}\n[grid]\n\
         x0 = {{ min = -1e-4, max = 2e-4, count = 5 }}\n\
         v0 = {{ min = -0.01, max = 0.01, count = 4 }}\n[classifier]\nt_max = 3000.0\n\
         [output]\npath = \"{out}\"\n"
    )
}

/// A physical scan sweeps the static friction coefficient and the surface time, the keys
/// of `[physical]` that leave the grid's units alone besides `c` and `v_belt`: the maps
/// are indexed by the model's `phi` and `tau`, with `mu_s` and `tau_si` (s) as given
/// beside them, and each map is the one-map scan of its own point (the model's values
/// and the labels equal, cell for cell). Before, a scan refused any physical key but `c`
/// and `v_belt` given as a list.
#[test]
fn a_physical_scan_sweeps_the_static_friction_and_the_surface_time() {
    let d = tempfile::tempdir().unwrap();
    let swept = brake_surfaces("mu_s = [0.45, 0.5]\ntau = [1e-3, 2e-3]", "s.h5");
    spec(d.path(), "s.toml", &swept);
    ok(&squeal(d.path(), &["scan", "s.toml", "--quiet"]));
    let f = hdf5::File::open(d.path().join("s.h5")).unwrap();
    assert_eq!(text_attr(&f, "swept"), "phi tau");
    // C order, the last key fastest: mu_s at maps 0 1 2 3 is 0.45 0.45 0.5 0.5.
    assert_eq!(f64s(&f, "mu_s"), [0.45, 0.45, 0.5, 0.5]);
    assert_eq!(f64s(&f, "tau_si"), [1e-3, 2e-3, 1e-3, 2e-3]);
    let units = |n: &str| -> String {
        let a: hdf5::types::VarLenUnicode = f
            .dataset(n)
            .unwrap()
            .attr("units")
            .unwrap()
            .read_scalar()
            .unwrap();
        a.as_str().to_string()
    };
    assert_eq!((units("mu_s"), units("tau_si")), ("1".into(), "s".into()));
    // A swept key is a coordinate over the maps, no attribute of the first map's value.
    assert!(f.attr("physical_mu_s").is_err() && f.attr("physical_tau").is_err());
    assert!(f.attr("physical_mu_k").is_ok());
    let (shape, cells) = labels(d.path(), "s.h5");
    assert_eq!(shape, vec![4, 4, 5]);
    let (phi, tau) = (f64s(&f, "phi"), f64s(&f, "tau"));
    for (m, (mu_s, tau_si)) in [(0.45, 1e-3), (0.45, 2e-3), (0.5, 1e-3), (0.5, 2e-3)]
        .into_iter()
        .enumerate()
    {
        let one = format!("one{m}.h5");
        let text = brake_surfaces(&format!("mu_s = {mu_s}\ntau = {tau_si}"), &one);
        spec(d.path(), "one.toml", &text);
        ok(&squeal(d.path(), &["scan", "one.toml", "--quiet"]));
        let g = hdf5::File::open(d.path().join(&one)).unwrap();
        let attr = |n: &str| g.attr(n).unwrap().read_scalar::<f64>().unwrap();
        assert_eq!((phi[m], tau[m]), (attr("phi"), attr("tau")), "map {m}");
        assert_eq!(
            labels(d.path(), &one).1,
            cells[m * 20..(m + 1) * 20],
            "map {m}"
        );
    }
    // A key that sets the grid's units is refused as a list, even of one value.
    let mass = swept.replace("m = 2.0", "m = [2.0]");
    spec(d.path(), "m.toml", &mass);
    let o = squeal(d.path(), &["scan", "m.toml", "--quiet"]);
    let text = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && text.contains("`physical.m`"),
        "{text}"
    );
}

/// A physical scan on a measured friction curve sweeping the dashpot stores `c` (N s/m)
/// beside the model's `xi`, as a McMillan scan stores it beside `nu`. Before, the twin
/// was found for `nu` and `lambda` only: the file had no `c` and said `physical_c` = the
/// first map's 20 N s/m for all of them.
#[test]
fn a_physical_scan_on_a_measured_curve_stores_its_swept_c() {
    let d = tempfile::tempdir().unwrap();
    // The README's clamped disc brake on a four-point curve (crates/scan's spec tests' PAD).
    let text = "version = 1\n[model]\nlaw = \"table\"\n[physical]\nm = 0.8\nk = 2e5\n\
                c = [20.0, 40.0]\nv_belt = 0.3\nnormal_force = 1500.0\n\
                friction_table = [[0.0, 0.48], [0.1, 0.43], [0.3, 0.4], [1.0, 0.37]]\n\
                [grid]\nx0 = { min = -1e-3, max = 1e-3, count = 3 }\n\
                v0 = { min = -0.1, max = 0.1, count = 3 }\n[classifier]\nt_max = 300.0\n\
                [output]\npath = \"pad.h5\"\n";
    spec(d.path(), "pad.toml", text);
    ok(&squeal(d.path(), &["scan", "pad.toml", "--quiet"]));
    let f = hdf5::File::open(d.path().join("pad.h5")).unwrap();
    assert_eq!(f64s(&f, "c"), [20.0, 40.0]);
    // xi = c / (2 sqrt(m k)) = c / 800 (MODEL.md section 8).
    let xi = f64s(&f, "xi");
    assert!((xi[1] - 0.05).abs() < 1e-15, "{xi:?}");
    assert!(f.attr("physical_c").is_err());
}
