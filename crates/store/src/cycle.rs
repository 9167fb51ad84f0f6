//! A map's cycle search as stored: the whole [`CycleReport`] (or the [`NoCycle`] reason)
//! written generically from its serde form, never field by field.
//!
//! * Journal: the record as TOML text (exact: floats print shortest round-trip, NaN and
//!   infinities are TOML values).
//! * HDF5 group: the same TOML without the curve in the attribute `record` (what `merge`
//!   reads back), every scalar flattened into its own attribute for h5py and xarray users
//!   (nested tables joined with `_`: `half_dt_shift`, `params_nu`, `solver_evaluations`),
//!   and the curve as the datasets `x` and `v`.

use serde::{Deserialize, Serialize};
use squeal_scan::ClosedCurve;
use squeal_scan::error::NoCycle;
use squeal_scan::ulc::{CycleOutcome, CycleReport};

/// A map's recorded cycle search: `None` when the plan does not locate cycles.
pub(crate) type CycleRecord = Option<CycleOutcome>;

#[derive(Serialize, Deserialize, Default)]
struct Wire {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    no_cycle: Option<NoCycle>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cycle: Option<CycleReport>,
    /// True when the plan does not locate cycles (no search result to record).
    #[serde(default)]
    not_located: bool,
}

fn table(rec: &CycleRecord) -> toml::Table {
    let w = match rec {
        None => Wire {
            not_located: true,
            ..Wire::default()
        },
        Some(Ok(c)) => Wire {
            cycle: Some(c.clone()),
            ..Wire::default()
        },
        Some(Err(e)) => Wire {
            no_cycle: Some(e.clone()),
            ..Wire::default()
        },
    };
    toml::Table::try_from(&w).unwrap_or_default()
}

/// The record as TOML; without the curve points unless `with_curve`.
pub(crate) fn to_text(rec: &CycleRecord, with_curve: bool) -> String {
    let mut t = table(rec);
    if !with_curve {
        if let Some(toml::Value::Table(c)) = t.get_mut("cycle") {
            c.remove("curve");
        }
    }
    toml::to_string(&t).unwrap_or_default()
}

/// Parses [`to_text`]'s output; `curve` supplies the points when the text has none.
pub(crate) fn from_text(text: &str, curve: Option<ClosedCurve>) -> Result<CycleRecord, String> {
    let mut t: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    if let (Some(toml::Value::Table(c)), Some(curve)) = (t.get_mut("cycle"), curve) {
        if !c.contains_key("curve") {
            let v = toml::Value::try_from(&curve).map_err(|e| e.to_string())?;
            c.insert("curve".into(), v);
        }
    }
    let w: Wire = t.try_into().map_err(|e: toml::de::Error| e.to_string())?;
    Ok(match (w.not_located, w.cycle, w.no_cycle) {
        (true, _, _) => None,
        (_, Some(c), _) => Some(Ok(c)),
        (_, None, Some(e)) => Some(Err(e)),
        (false, None, None) => return Err("neither a cycle nor a reason".into()),
    })
}

/// A flattened scalar attribute.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Flat {
    F64(f64),
    I64(i64),
    Bool(bool),
    Text(String),
    F64s(Vec<f64>),
}

/// Every scalar of the record (curve excluded), nested names joined with `_`.
pub(crate) fn flatten(rec: &CycleRecord) -> Vec<(String, Flat)> {
    let mut t = table(rec);
    let mut out = Vec::new();
    if let Some(toml::Value::Table(c)) = t.get_mut("cycle") {
        c.remove("curve");
        walk("", c, &mut out);
    }
    if let Some(toml::Value::Table(e)) = t.get("no_cycle") {
        walk("no_cycle_", e, &mut out);
    }
    out
}

fn walk(prefix: &str, t: &toml::Table, out: &mut Vec<(String, Flat)>) {
    for (k, v) in t {
        let name = format!("{prefix}{k}");
        match v {
            toml::Value::Float(f) => out.push((name, Flat::F64(*f))),
            toml::Value::Integer(i) => out.push((name, Flat::I64(*i))),
            toml::Value::Boolean(b) => out.push((name, Flat::Bool(*b))),
            toml::Value::String(s) => out.push((name, Flat::Text(s.clone()))),
            toml::Value::Array(a) => {
                let fs: Option<Vec<f64>> = a.iter().map(|x| x.as_float()).collect();
                if let Some(fs) = fs {
                    out.push((name, Flat::F64s(fs)));
                }
            }
            toml::Value::Table(inner) => walk(&format!("{name}_"), inner, out),
            toml::Value::Datetime(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_core::{FrictionLaw, Params, SolverStats};
    use squeal_scan::error::Damping;

    fn report() -> CycleReport {
        CycleReport {
            params: Params::paper(FrictionLaw::McMillan, 1e-3),
            dt: 0.01,
            r_section: 0.1 + 0.2,
            bracket: [0.3, 0.30000000000000004],
            period: 6.5,
            omega: 1.0,
            x_range: [-1e-300, 5e300],
            v_range: [-0.0, 1.0 / 3.0],
            distance_plus_x: f64::NAN,
            area: f64::INFINITY,
            multiplier: 1.0064,
            encloses_origin: true,
            half_dt: None,
            returns: 7,
            solver: SolverStats::default(),
            stable_above: Some(2.5),
            escape: None,
            curve: ClosedCurve::new(vec![1.0, 2.0, 1.5], vec![0.0, 0.5, 1.0 / 7.0]),
        }
    }

    fn same(a: &CycleReport, b: &CycleReport) -> bool {
        // Bit equality (NaN included) through the TOML text of both.
        toml::to_string(a).unwrap() == toml::to_string(b).unwrap()
            && a.curve == b.curve
            && a.distance_plus_x.to_bits() == b.distance_plus_x.to_bits()
    }

    #[test]
    fn records_round_trip_exactly() {
        let r = report();
        let back = from_text(&to_text(&Some(Ok(r.clone())), true), None).unwrap();
        assert!(same(&r, back.as_ref().unwrap().as_ref().unwrap()));
        let back = from_text(&to_text(&Some(Ok(r.clone())), false), Some(r.curve.clone())).unwrap();
        assert!(same(&r, back.as_ref().unwrap().as_ref().unwrap()));
        let e = NoCycle::Decays {
            r_max: 4.0,
            damping: Damping::Nu(0.5),
        };
        let back = from_text(&to_text(&Some(Err(e.clone())), true), None).unwrap();
        assert_eq!(back, Some(Err(e.clone())));
        // McMillan's record is as before the damping got its law's name (the text of
        // this record a build of main wrote before this change; files and journals read back the
        // same), and the Stribeck law's says xi.
        let old = "not_located = false\n\n[no_cycle]\nkind = \"decays\"\nnu = 0.5\nr_max = 4.0\n";
        assert_eq!(to_text(&Some(Err(e.clone())), true), old);
        assert_eq!(from_text(old, None).unwrap(), Some(Err(e)));
        let x = NoCycle::FixedPointRepels {
            r_min: 1e-3,
            damping: Damping::Xi(0.05),
        };
        let rec = Some(Err(x.clone()));
        assert_eq!(from_text(&to_text(&rec, true), None).unwrap(), rec);
        assert!(x.to_string().contains("(xi = 0.05)"), "{x}");
        let flat = flatten(&rec);
        assert!(
            flat.contains(&("no_cycle_xi".into(), Flat::F64(0.05))),
            "{flat:?}"
        );
        assert!(!flat.iter().any(|(k, _)| k == "no_cycle_nu"));
        assert_eq!(from_text(&to_text(&None, true), None).unwrap(), None);
        let flat = flatten(&Some(Ok(r)));
        let get = |n: &str| flat.iter().find(|(k, _)| k == n).map(|(_, v)| v.clone());
        assert_eq!(get("params_nu"), Some(Flat::F64(1e-3)));
        // McMillan's params as before the Stribeck law had its own names (the derived
        // form: law, nu, lambda, tau, phi).
        assert_eq!(
            toml::to_string(&Params::paper(FrictionLaw::McMillan, 1e-3)).unwrap(),
            "law = \"mcmillan\"\nnu = 0.001\nlambda = 3.0\ntau = 0.31622776601683794\nphi = 1.0\n"
        );
        assert_eq!(get("stable_above"), Some(Flat::F64(2.5)));
        assert_eq!(get("encloses_origin"), Some(Flat::Bool(true)));
        assert_eq!(get("curve_x"), None);
    }

    #[test]
    fn stribeck_params_are_stored_by_their_own_names() {
        let mut r = report();
        r.params = Params::bstab();
        let rec = Some(Ok(r.clone()));
        let back = from_text(&to_text(&rec, true), None).unwrap();
        assert!(same(&r, back.as_ref().unwrap().as_ref().unwrap()));
        assert_eq!(back.unwrap().unwrap().params, Params::bstab());
        let flat = flatten(&rec);
        let names: Vec<&str> = flat.iter().map(|(k, _)| k.as_str()).collect();
        for k in ["xi", "v_d", "mu_d", "mu_sd", "v_0", "mu_v"] {
            assert!(
                names.contains(&format!("params_{k}").as_str()),
                "{k}: {names:?}"
            );
        }
        for k in ["nu", "lambda", "tau", "phi", "stribeck_mu_d"] {
            assert!(
                !names.contains(&format!("params_{k}").as_str()),
                "{k}: {names:?}"
            );
        }
        // The form of earlier builds (nu, lambda, tau, phi and a stribeck table) still reads.
        let legacy = "law = \"stribeck\"\nnu = 0.05\nlambda = 1.5\ntau = 0.31622776601683794\n\
                      phi = 1.0\n[stribeck]\nmu_d = 0.5\nmu_sd = 2.0\nv_0 = 0.5\nmu_v = 0.0\n";
        assert_eq!(toml::from_str::<Params>(legacy).unwrap(), Params::bstab());
        // A missing key is named.
        let e = toml::from_str::<Params>("law = \"stribeck\"\nxi = 0.05\n").unwrap_err();
        assert!(e.to_string().contains("v_d"), "{e}");
    }
}
