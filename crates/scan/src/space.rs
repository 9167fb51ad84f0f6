//! The parameter space of a spec: every key of `[model]` (nondimensional) or `[physical]`
//! (SI units), each a number, a list or a range, and its points, the Cartesian product of the
//! keys given several values in C order (the last fastest).
//!
//! One reader ([`Space::read`]) serves both kinds of spec: a scan draws one basin map per
//! point, an atlas computes its figures (and, with a `[grid]`, a map) per point. A key new to
//! a law or to `[physical]` is read, swept, checked and converted here for both.

use serde::Serialize;
use squeal_core::{FrictionLaw, Load, Params, Physical, SurfaceSi};

use crate::bounds::{Invalid, Rules};
use crate::error::ScanError;
use crate::spec::ModelTable;
use crate::spec::physical::{PhysicalFile, physical_error};
use crate::values::{Value, expand};

/// Whether the spec describes the nondimensional model or the physical system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// `nu, lambda, tau, phi` (paper Section 4), or a law's own keys.
    Nondimensional,
    /// `m, k, c, v_belt, mu_k, mu_s, tau, g` in SI units (no `mu_s, tau` under Coulomb).
    Physical,
}

impl Units {
    /// The name in files.
    pub fn name(self) -> &'static str {
        match self {
            Units::Nondimensional => "nondimensional",
            Units::Physical => "physical",
        }
    }

    /// The spec table its keys are given in (and errors name).
    pub fn table(self) -> &'static str {
        match self {
            Units::Nondimensional => "model",
            Units::Physical => "physical",
        }
    }
}

/// One parameter of the spec: its key, words, units and values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParamAxis {
    /// The key (`nu`, `v_belt`, ...), also the dataset name of the coordinate.
    pub key: &'static str,
    /// Words for axes and `long_name`.
    pub long_name: &'static str,
    /// Units (`"1"` for nondimensional).
    pub units: &'static str,
    /// The values (one: fixed; more: swept).
    pub values: Vec<f64>,
    /// Given as a list or a range (even of one value): a scan then keeps a map dimension for
    /// it; a point of an atlas counts only the keys of several values.
    pub listed: bool,
}

/// `(key, long name, units)` of the nondimensional parameters, in axis order.
pub const NONDIMENSIONAL: [(&str, &str, &str); 4] = [
    ("nu", "damping ratio nu", "1"),
    ("lambda", "belt speed lambda (nondimensional)", "1"),
    ("tau", "surface time tau' (nondimensional)", "1"),
    ("phi", "Phi = arcsin(mu_k / mu_s)", "rad"),
];

/// `(key, long name, units)` of the physical parameters, in axis order.
pub const PHYSICAL: [(&str, &str, &str); 9] = [
    ("m", "mass m", "kg"),
    ("k", "stiffness k", "N/m"),
    ("c", "damping coefficient c", "N s/m"),
    ("v_belt", "belt speed v_belt", "m/s"),
    ("mu_k", "kinetic friction coefficient mu_k", "1"),
    ("mu_s", "static friction coefficient mu_s", "1"),
    ("tau", "surface time tau", "s"),
    ("g", "gravitational acceleration g", "m/s^2"),
    (
        "normal_force",
        "normal force N pressing the block on the belt (friction is mu N)",
        "N",
    ),
];

/// `(key, long name, units)` of a law's parameters in axis order ([`FrictionLaw::keys`];
/// the words of [`Params::named`]), for the laws with true stick. All are nondimensional
/// (`"1"`, as [`NONDIMENSIONAL`]'s): velocities in units of the natural-frequency velocity
/// scale.
pub fn law_params(law: FrictionLaw) -> Vec<(&'static str, &'static str, &'static str)> {
    Params::defaults(law)
        .named()
        .into_iter()
        .map(|n| (n.name, n.long_name, "1"))
        .collect()
}

/// The keys of `[physical]` that set the units of the state (the length mu_k N / k and the
/// velocity mu_k N / sqrt(m k)): with a grid in m and m/s, each must have one value.
pub const SCALE_KEYS: [&str; 5] = ["m", "k", "mu_k", "g", "normal_force"];

/// How many points a space may hold, and what a point is to the spec (for the refusal).
#[derive(Clone, Copy, Debug)]
pub struct Limit {
    /// Most values of one key.
    pub per_key: i64,
    /// Most points (the product of the value counts).
    pub points: usize,
    /// What a point is: "maps", "points".
    pub noun: &'static str,
}

/// The parameter space: the law, its table, and every key with its values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Space {
    /// Friction law.
    pub law: FrictionLaw,
    /// The table law's table (`friction_table` or `friction_csv`); `None` for other laws.
    /// In a physical space its slip speeds are in m/s (as `[physical]` gives them; each
    /// point's model has them over its own velocity unit, [`Space::params_at`]).
    pub table: Option<&'static squeal_core::FrictionTable>,
    /// Nondimensional or physical.
    pub units: Units,
    /// Every parameter in axis order (fixed ones have one value).
    pub params: Vec<ParamAxis>,
    /// The key the table was given by (`friction_table` or `friction_csv`), for messages;
    /// `None` without a table. Not a setting: results do not depend on it.
    #[serde(skip)]
    pub table_key: Option<&'static str>,
}

impl Space {
    /// The space of a spec's `[model]` table `m` and its `[physical]` table `ph`, if any:
    /// the law's keys checked, its table read (relative to `folder`; `stored`, the table a
    /// file holds, stands for it), every key expanded and the number of points checked
    /// against `limit`. The points' models are checked by [`Space::check_points`].
    pub(crate) fn read(
        m: &ModelTable,
        ph: Option<&PhysicalFile>,
        (folder, stored): (
            &std::path::Path,
            Option<&'static squeal_core::FrictionTable>,
        ),
        limit: Limit,
        inv: Invalid,
    ) -> Result<Space, ScanError> {
        m.check_law(inv)?;
        let (units, table, params, csv) = match ph {
            Some(ph) => {
                m.check_physical(inv)?;
                ph.check_friction_keys(m.law, inv)?;
                let table = ph.table(folder, stored, inv)?;
                let axes = physical_axes(ph, limit, inv)?;
                (Units::Physical, table, axes, ph.friction_csv.is_some())
            }
            None => {
                let table = m.table(folder, stored, inv)?;
                let axes = model_axes(m, limit, inv)?;
                (Units::Nondimensional, table, axes, m.friction_csv.is_some())
            }
        };
        let table_key = table.map(|_| match csv {
            true => "friction_csv",
            false => "friction_table",
        });
        let space = Space {
            law: m.law,
            table,
            units,
            params,
            table_key,
        };
        space.check_count(limit, inv)?;
        Ok(space)
    }

    /// Refuses more points than `limit` allows.
    fn check_count(&self, limit: Limit, inv: Invalid) -> Result<(), ScanError> {
        let n = (self.params.iter().map(|a| a.values.len()))
            .try_fold(1usize, |acc, n| acc.checked_mul(n));
        if n.is_some_and(|n| n <= limit.points) {
            return Ok(());
        }
        let counts: Vec<String> = (self.params.iter())
            .filter(|a| a.listed)
            .map(|a| format!("{}: {} values", a.key, a.values.len()))
            .collect();
        let n = n.map_or("more than 2^64".to_string(), |n| n.to_string());
        Err(inv(
            self.units.table(),
            format!("{n} {} ({})", limit.noun, counts.join(", ")),
            &format!(
                "at most {} {} (the product of the value counts)",
                limit.points, limit.noun
            ),
        ))
    }

    /// Today's bounds (under [`Rules::Today`]; under [`Rules::Stored`], for a physical
    /// space, only that each point converts) on every point's model, naming the spec key
    /// (a derived value names the physical keys it comes from).
    pub(crate) fn check_points(&self, rules: Rules, inv: Invalid) -> Result<(), ScanError> {
        (0..self.n_points()).try_for_each(|i| self.check_point(i, rules, inv).map(|_| ()))
    }

    /// [`Space::check_points`] at point `i`: its model, where checked (`None` for a
    /// nondimensional space under [`Rules::Stored`]).
    pub(crate) fn check_point(
        &self,
        i: usize,
        rules: Rules,
        inv: Invalid,
    ) -> Result<Option<Params>, ScanError> {
        match (self.physical_at(i), rules) {
            (Some(ph), Rules::Today) => ph.params(self.law),
            (Some(ph), Rules::Stored) => ph.nondimensional(self.law),
            (None, Rules::Stored) => return Ok(None),
            (None, Rules::Today) => {
                let p = self.params_at(i);
                return (p.validate().map(|()| Some(p)))
                    .map_err(|e| crate::bounds::core_error("model", e, inv));
            }
        }
        .map(Some)
        .map_err(|e| physical_error(e, inv))
    }

    /// Refuses a point whose belt speed the step `dt` cannot resolve
    /// ([`Params::check_step`] gives the argument), naming the key at fault: a physical
    /// key (`physical.normal_force` = 1e308 made lambda 4.5e-307), or the model's belt
    /// speed.
    /// A point refused for another reason is left to the check that names it
    /// ([`Space::check_points`]).
    pub(crate) fn check_step(&self, dt: f64, inv: Invalid) -> Result<(), ScanError> {
        for i in 0..self.n_points() {
            match self.physical_at(i) {
                Some(ph) => match ph.params(self.law) {
                    Ok(p) => ph.check_step(&p, dt).map_err(|e| physical_error(e, inv))?,
                    Err(_) => continue,
                },
                None => {
                    let p = self.params_at(i);
                    if p.validate().is_ok() {
                        (p.check_step(dt))
                            .map_err(|e| crate::bounds::core_error(self.units.table(), e, inv))?;
                    }
                }
            }
        }
        Ok(())
    }

    /// What in this space looks like a slip of units ([`squeal_core::units::Doubt`]: a
    /// friction coefficient in percent, speeds in mm/s), each kind's first over the points,
    /// said as one sentence naming the spec key given (`` `physical.v_belt` ``).
    pub fn warnings(&self) -> Vec<String> {
        use squeal_core::units::{Doubt, curve_doubts};
        let found: Vec<Doubt> = match self.units {
            Units::Physical => (0..self.n_points())
                .filter_map(|i| self.physical_at(i))
                .flat_map(|ph| ph.doubts())
                .collect(),
            Units::Nondimensional => (self.table.iter())
                .flat_map(|t| curve_doubts(t, false))
                .collect(),
        };
        let mut doubts: Vec<Doubt> = Vec::new();
        for d in found {
            let same = |seen: &&Doubt| {
                seen.key() == d.key() && std::mem::discriminant(*seen) == std::mem::discriminant(&d)
            };
            if !doubts.iter().any(|seen| same(&seen)) {
                doubts.push(d);
            }
        }
        let table = self.units.table();
        let table_key = self.table_key.unwrap_or("friction_table");
        let name = |key: &'static str| match key {
            "friction_table" => format!("`{table}.{table_key}`"),
            key => format!("`{table}.{key}`"),
        };
        doubts.iter().map(|d| d.sentence(&name)).collect()
    }

    /// Refuses a swept key that sets the units of a grid in m and m/s
    /// ([`SCALE_KEYS`]): basin maps share one grid, so one length and one velocity unit.
    pub(crate) fn check_map_units(&self, inv: Invalid) -> Result<(), ScanError> {
        if self.units != Units::Physical {
            return Ok(());
        }
        match (self.params.iter()).find(|a| a.values.len() > 1 && SCALE_KEYS.contains(&a.key)) {
            None => Ok(()),
            Some(a) => Err(inv(
                &format!("physical.{}", a.key),
                format!("{} values with basin maps", a.values.len()),
                &format!(
                    "a single value: the grid is in m and m/s, and this key sets the units \
                     that scale it (sweep {} here, or this key with squeal atlas and no \
                     [grid])",
                    scan_keys_in_words()
                ),
            )),
        }
    }

    /// The swept parameters (more than one value), in axis order.
    pub fn axes(&self) -> Vec<&ParamAxis> {
        self.params.iter().filter(|a| a.values.len() > 1).collect()
    }

    /// The fixed parameters with their value.
    pub fn fixed(&self) -> Vec<(&ParamAxis, f64)> {
        (self.params.iter())
            .filter(|a| a.values.len() == 1)
            .map(|a| (a, a.values[0]))
            .collect()
    }

    /// Shape of the point array (the swept axes' lengths).
    pub fn shape(&self) -> Vec<usize> {
        self.axes().iter().map(|a| a.values.len()).collect()
    }

    /// Number of parameter points.
    pub fn n_points(&self) -> usize {
        self.shape().iter().product()
    }

    /// The index of each swept axis at point `i` (C order).
    pub fn unravel(&self, mut i: usize) -> Vec<usize> {
        let shape = self.shape();
        let mut idx = vec![0; shape.len()];
        for d in (0..shape.len()).rev() {
            idx[d] = i % shape[d];
            i /= shape[d];
        }
        idx
    }

    /// Every parameter's value at point `i`, in `params` order.
    pub fn values_at(&self, i: usize) -> Vec<f64> {
        let idx = self.unravel(i);
        let mut k = 0;
        (self.params.iter())
            .map(|a| {
                if a.values.len() > 1 {
                    k += 1;
                    a.values[idx[k - 1]]
                } else {
                    a.values[0]
                }
            })
            .collect()
    }

    /// The physical system at point `i` (physical spaces only).
    pub fn physical_at(&self, i: usize) -> Option<Physical> {
        if self.units != Units::Physical {
            return None;
        }
        let v = self.values_at(i);
        // Axes by key: a Coulomb system has no mu_s and tau axes.
        let at = |key: &str| self.params.iter().position(|a| a.key == key).map(|j| v[j]);
        let need = |key: &str| {
            at(key).expect("every physical key but mu_s, tau and a table's mu_k has an axis")
        };
        Some(Physical {
            m: need("m"),
            k: need("k"),
            c: need("c"),
            v_belt: need("v_belt"),
            friction: match self.table {
                Some(friction_table) => squeal_core::FrictionSi::Table { friction_table },
                None => squeal_core::FrictionSi::Kinetic {
                    mu_k: need("mu_k"),
                    surface: match (at("mu_s"), at("tau")) {
                        (Some(mu_s), Some(tau)) => Some(SurfaceSi { mu_s, tau }),
                        _ => None,
                    },
                },
            },
            load: match at("normal_force") {
                Some(n) => Load::NormalForce(n),
                None => Load::Weight(need("g")),
            },
        })
    }

    /// The model parameters at point `i`.
    pub fn params_at(&self, i: usize) -> Params {
        if let Some(ph) = self.physical_at(i) {
            return ph
                .nondimensional(self.law)
                .expect("a physical space has a law with physical units (checked when read)");
        }
        // Axis order is the law's keys (FrictionLaw::keys).
        let v = self.values_at(i);
        let keys = self.law.keys();
        Params::from_named_table(self.law, self.table, |k| {
            keys.iter().position(|x| *x == k).map(|j| v[j])
        })
        .expect("every key of the law has an axis")
    }

    /// The keys a scan indexes its maps by: those given as a list or a range, in the model's
    /// units. A physical space's keys become the model's ([`model_key`]: `c` the law's
    /// damping, `v_belt` its belt speed, `mu_s` the angle `phi`, `tau` the surface time),
    /// each with its values as given beside them ([`crate::si::SweptSi`]); the keys that
    /// set the grid's units are refused when read ([`Space::check_map_units`]). `None`
    /// if no key is listed.
    pub fn sweep(&self) -> Option<crate::Sweep> {
        let shape = self.shape();
        let stride = |d: usize| shape[d + 1..].iter().product::<usize>();
        let swept: Vec<&ParamAxis> = self.axes();
        let axes: Vec<crate::spec::SweepAxis> = (self.params.iter())
            .filter(|a| a.listed)
            .map(|a| {
                if self.units != Units::Physical {
                    return crate::spec::SweepAxis {
                        name: a.key,
                        values: a.values.clone(),
                        si: None,
                    };
                }
                let model = model_key(self.law, a.key).unwrap_or_else(|| {
                    unreachable!("a scan sweeps no {} (checked when read)", a.key)
                });
                // The model's value, read off the points along this key.
                let d = swept.iter().position(|s| s.key == a.key);
                let at = |j: usize| d.map_or(0, |d| j * stride(d));
                let pick = |j: usize| {
                    (self.params_at(at(j)).named().iter())
                        .find(|n| n.name == model)
                        .map(|n| n.value)
                        .expect("the model has every key of its law")
                };
                crate::spec::SweepAxis {
                    name: model,
                    values: (0..a.values.len()).map(pick).collect(),
                    si: Some(crate::si::SweptSi::of(a)),
                }
            })
            .collect();
        (!axes.is_empty()).then_some(crate::Sweep { axes })
    }
}

/// Each `[physical]` key a scan's maps may be indexed by, with the model's keys it becomes
/// (a law's damping and belt speed are `nu` and `lambda`, a measured curve's `xi` and
/// `v_d`). The other physical keys set the units of the state ([`SCALE_KEYS`]).
const TWINS: [(&str, &str); 6] = [
    ("c", "nu"),
    ("c", "xi"),
    ("v_belt", "lambda"),
    ("v_belt", "v_d"),
    ("mu_s", "phi"),
    ("tau", "tau"),
];

/// The `[physical]` keys a scan's maps may be indexed by, in words: "c, v_belt, mu_s and tau".
pub fn scan_keys_in_words() -> String {
    let mut keys: Vec<&str> = TWINS.iter().map(|(p, _)| *p).collect();
    keys.dedup();
    let last = keys.pop().unwrap_or_default();
    format!("{} and {last}", keys.join(", "))
}

/// The model's key that the `[physical]` key `key` becomes under `law`; `None` for a key
/// that sets the units ([`SCALE_KEYS`]).
pub fn model_key(law: FrictionLaw, key: &str) -> Option<&'static str> {
    (TWINS.iter())
        .find(|(p, m)| *p == key && law.keys().contains(m))
        .map(|(_, m)| *m)
}

/// The `[physical]` key a model's key `model` comes from, and the name of the dataset a
/// physical scan stores its values in beside the model's: the key itself, or `<key>_si`
/// where both share a name (`tau_si` beside the model's `tau`); `None` for a key no
/// physical key becomes.
pub fn si_twin(model: &str) -> Option<(&'static str, String)> {
    let (p, _) = TWINS.iter().find(|(_, m)| *m == model)?;
    let name = if *p == model {
        format!("{p}_si")
    } else {
        p.to_string()
    };
    Some((p, name))
}

/// The axes of a `[physical]` table, in SI units.
fn physical_axes(
    ph: &PhysicalFile,
    limit: Limit,
    inv: Invalid,
) -> Result<Vec<ParamAxis>, ScanError> {
    let load = ph.load(inv)?;
    // The keys given, in key order: a Coulomb system has no mu_s and tau, McMillan's
    // laws both, a measured curve no mu_k either (checked by the caller, so `zip` drops
    // none alone; the curve is no axis).
    let vals = Physical {
        m: Some(&ph.m),
        k: Some(&ph.k),
        c: Some(&ph.c),
        v_belt: Some(&ph.v_belt),
        friction: squeal_core::FrictionSi::Kinetic {
            mu_k: ph.mu_k.as_ref(),
            surface: (ph.mu_s.as_ref().zip(ph.tau.as_ref())).map(|(mu_s, tau)| SurfaceSi {
                mu_s: Some(mu_s),
                tau: Some(tau),
            }),
        },
        load: match &load {
            Load::Weight(g) => Load::Weight(Some(g)),
            Load::NormalForce(n) => Load::NormalForce(Some(n)),
        },
    }
    .values();
    let (names, vals): (Vec<_>, Vec<_>) = PHYSICAL
        .into_iter()
        .zip(vals)
        .filter_map(|(name, v)| Some((name, v.flatten()?)))
        .unzip();
    axes("physical", &names, vals, limit, inv)
}

/// The axes of a `[model]` table, in the model's units: the law's own keys in their order,
/// each as given or at the law's default (the laws named by McMillan's keys need `nu`).
fn model_axes(m: &ModelTable, limit: Limit, inv: Invalid) -> Result<Vec<ParamAxis>, ScanError> {
    let own_names = m.law.family().has_own_names();
    if !own_names && m.given("nu").is_none() {
        return Err(inv(
            "model.nu",
            "missing".into(),
            "a damping ratio: a number, a list or a range (or a [physical] table instead)",
        ));
    }
    // The law's own keys in their order, each as given or at the law's default.
    let vals: Vec<Value> = Params::defaults(m.law)
        .named()
        .iter()
        .map(|n| m.given(n.name).unwrap_or(Value::One(n.value)))
        .collect();
    let names = if own_names {
        law_params(m.law)
    } else {
        let own = m.law.keys();
        NONDIMENSIONAL
            .into_iter()
            .filter(|(k, ..)| own.contains(k))
            .collect()
    };
    axes("model", &names, &vals, limit, inv)
}

/// The axes named `names` (key, long name, units) with the values `vals` of table `table`,
/// each expanded (a number, a list or a range; errors name `table.key`).
fn axes<'a>(
    table: &str,
    names: &[(&'static str, &'static str, &'static str)],
    vals: impl IntoIterator<Item = &'a Value>,
    limit: Limit,
    inv: Invalid,
) -> Result<Vec<ParamAxis>, ScanError> {
    names
        .iter()
        .zip(vals)
        .map(|(&(key, long_name, units), v)| {
            Ok(ParamAxis {
                key,
                long_name,
                units,
                values: expand(v, &format!("{table}.{key}"), limit.per_key, inv)?,
                listed: v.is_sweep(),
            })
        })
        .collect()
}
