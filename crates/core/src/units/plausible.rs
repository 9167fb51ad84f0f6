//! Values squeal accepts that a slip of units would give: a friction coefficient in
//! percent, speeds in mm/s read as m/s, a belt speed beyond the measured curve. Each is a
//! [`Doubt`], said as one sentence before anything runs, by every door (the command line on
//! stderr, Python as a warning); none is refused, since each can be meant.

use crate::error::Number;
use crate::table::FrictionTable;

use super::{FrictionSi, Physical};

/// A friction coefficient above this is more likely given in percent than measured. Dry
/// friction coefficients lie below it: brake pads on iron 0.3-0.6, metals on metals up to
/// about 1, rubber on dry glass or asphalt about 1-1.5 (the highest common pairs). mu = 50,
/// 0.5 written in percent, is 25 times it.
pub const MU_PLAUSIBLE: f64 = 2.0;

/// A speed (m/s) above this is more likely given in mm/s than measured: 100 m/s is 360
/// km/h, faster than a car's brake pad slides on its disc at top speed (about 60 m/s at
/// 250 km/h) or a tribometer's disc turns. 300 mm/s read as m/s is 300.
pub const SPEED_PLAUSIBLE: f64 = 100.0;

/// A value that is valid but looks like a slip of units, with what the sentence needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Doubt {
    /// `mu_k` or `mu_s` above [`MU_PLAUSIBLE`].
    Coefficient {
        /// `mu_k` or `mu_s`.
        key: &'static str,
        /// Its value.
        value: f64,
    },
    /// A measured curve whose `mu` rises above [`MU_PLAUSIBLE`]: its largest `mu` and the
    /// slip speed of that row (in m/s where `si`, else in the model's units).
    CurveCoefficient {
        /// The largest `mu`.
        mu: f64,
        /// Its row's slip speed.
        speed: f64,
        /// Whether the curve's speeds are in m/s (the physical system's).
        si: bool,
    },
    /// A measured curve in m/s whose slip speeds run above [`SPEED_PLAUSIBLE`].
    CurveSpeeds {
        /// Its last slip speed (m/s).
        top: f64,
    },
    /// The belt speed beyond the measured curve's last slip speed, where `mu` is held.
    BeltBeyondCurve {
        /// The belt speed (m/s).
        v_belt: f64,
        /// The curve's last slip speed (m/s).
        top: f64,
        /// Its `mu`, held beyond it.
        mu: f64,
    },
    /// A belt speed above [`SPEED_PLAUSIBLE`] (laws without a curve).
    BeltSpeed {
        /// The belt speed (m/s).
        v_belt: f64,
    },
}

impl Doubt {
    /// The key the doubt is about: `mu_k`, `mu_s`, `friction_table` or `v_belt`.
    pub fn key(&self) -> &'static str {
        match self {
            Doubt::Coefficient { key, .. } => key,
            Doubt::CurveCoefficient { .. } | Doubt::CurveSpeeds { .. } => "friction_table",
            Doubt::BeltBeyondCurve { .. } | Doubt::BeltSpeed { .. } => "v_belt",
        }
    }

    /// The doubt as one sentence, the key written as `name` gives it (`--v-belt`,
    /// `` `physical.v_belt` ``), the values as given and in the units given.
    pub fn sentence(&self, name: &dyn Fn(&'static str) -> String) -> String {
        let key = name(self.key());
        match *self {
            Doubt::Coefficient { value, .. } => format!(
                "{key} = {} is above {MU_PLAUSIBLE}, higher than any dry friction coefficient: \
                 if it is in percent, give {}",
                Number(value),
                Number(value / 100.0)
            ),
            Doubt::CurveCoefficient { mu, speed, si } => format!(
                "{key}: mu reaches {} (at slip speed {}{}), above {MU_PLAUSIBLE} and higher than \
                 any dry friction coefficient: if the curve's mu is in percent, divide it by 100",
                Number(mu),
                Number(speed),
                if si { " m/s" } else { "" }
            ),
            Doubt::CurveSpeeds { top } => format!(
                "{key}: its slip speeds run to {} m/s, faster than brakes and belts slide \
                 (above {SPEED_PLAUSIBLE} m/s): if they are in mm/s, divide them by 1000",
                Number(top)
            ),
            Doubt::BeltBeyondCurve { v_belt, top, mu } => format!(
                "{key} = {} m/s is beyond the friction curve's last slip speed, {} m/s, where \
                 its mu is held at {}, so the run never sees the curve's slope{}",
                Number(v_belt),
                Number(top),
                Number(mu),
                mm_hint(v_belt, top)
            ),
            Doubt::BeltSpeed { v_belt } => format!(
                "{key} = {} m/s is faster than brakes and belts slide (above {SPEED_PLAUSIBLE} \
                 m/s): if it is in mm/s, give {} m/s",
                Number(v_belt),
                Number(v_belt / 1000.0)
            ),
        }
    }
}

/// For a belt speed `v` beyond a curve ending at `top` (m/s): the hint that `v` is in mm/s,
/// where it is at least 100 times `top` (a slip beyond a curve's last row is plausible; two
/// decades beyond it are not) and would lie on the curve in m/s.
fn mm_hint(v: f64, top: f64) -> String {
    if v >= 100.0 * top && v / 1000.0 <= top {
        format!(": if it is in mm/s, give {} m/s", Number(v / 1000.0))
    } else {
        String::new()
    }
}

/// The doubts about a measured curve alone: its `mu` above [`MU_PLAUSIBLE`] (percent), and
/// where its speeds are in m/s (`si`), speeds above [`SPEED_PLAUSIBLE`] (mm/s).
pub fn curve_doubts(t: &FrictionTable, si: bool) -> Vec<Doubt> {
    let rows = t.rows();
    let mut doubts = Vec::new();
    let top_mu = rows.iter().copied().max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((speed, mu)) = top_mu.filter(|r| r.1 > MU_PLAUSIBLE) {
        doubts.push(Doubt::CurveCoefficient { mu, speed, si });
    }
    let top = rows.last().map_or(0.0, |r| r.0);
    if si && top > SPEED_PLAUSIBLE {
        doubts.push(Doubt::CurveSpeeds { top });
    }
    doubts
}

impl Physical {
    /// What in this system looks like a slip of units ([`Doubt`]), in key order.
    pub fn doubts(&self) -> Vec<Doubt> {
        let mut doubts = Vec::new();
        if let FrictionSi::Kinetic { mu_k, surface } = self.friction {
            let mu_s = surface.map(|s| ("mu_s", s.mu_s));
            for (key, value) in std::iter::once(("mu_k", mu_k)).chain(mu_s) {
                if value > MU_PLAUSIBLE {
                    doubts.push(Doubt::Coefficient { key, value });
                }
            }
        }
        match self.friction.table() {
            Some(t) => {
                doubts.extend(curve_doubts(t, true));
                let (top, mu) = t.rows().last().copied().unwrap_or_default();
                if self.v_belt > top {
                    doubts.push(Doubt::BeltBeyondCurve {
                        v_belt: self.v_belt,
                        top,
                        mu,
                    });
                }
            }
            None if self.v_belt > SPEED_PLAUSIBLE => {
                doubts.push(Doubt::BeltSpeed {
                    v_belt: self.v_belt,
                });
            }
            None => {}
        }
        doubts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::Load;

    /// The pad of README section 4 on scans/data/pad-mu.csv (0.8 kg, 200 kN/m, c = 60 N s/m,
    /// 0.3 m/s, N = 1500 N), its curve's rows scaled by `speed` and `mu` (1000: mm/s; 100:
    /// percent).
    fn pad(speed: f64, mu: f64) -> Physical {
        let rows = [
            (0.0, 0.48),
            (0.05, 0.45),
            (0.1, 0.43),
            (0.2, 0.41),
            (0.3, 0.40),
            (0.5, 0.385),
            (1.0, 0.37),
            (2.0, 0.36),
        ];
        let rows: Vec<(f64, f64)> = rows.iter().map(|(s, m)| (s * speed, m * mu)).collect();
        Physical {
            m: 0.8,
            k: 2e5,
            c: 60.0,
            v_belt: 0.3,
            friction: FrictionSi::Table {
                friction_table: FrictionTable::new(&rows).unwrap(),
            },
            load: Load::NormalForce(1500.0),
        }
    }

    fn flag(key: &'static str) -> String {
        format!("--{}", key.replace('_', "-"))
    }

    /// The curve as measured raises no doubt; in percent, in mm/s, or under a belt speed in
    /// mm/s, each is named in one sentence with the value as given and what to do.
    #[test]
    fn a_curve_in_percent_or_mm_per_s_is_doubted() {
        assert_eq!(pad(1.0, 1.0).doubts(), []);
        let percent = pad(1.0, 100.0).doubts();
        assert_eq!(
            percent,
            [Doubt::CurveCoefficient {
                mu: 48.0,
                speed: 0.0,
                si: true
            }]
        );
        let said = percent[0].sentence(&flag);
        assert!(
            said.starts_with("--friction-table: mu reaches 48 (at slip speed 0 m/s), above 2")
                && said.ends_with("divide it by 100")
                && !said.contains(". "),
            "{said}"
        );
        let mm = pad(1000.0, 1.0).doubts();
        assert_eq!(mm, [Doubt::CurveSpeeds { top: 2000.0 }]);
        assert!(mm[0].sentence(&flag).contains("run to 2000 m/s"));
        let fast = Physical {
            v_belt: 300.0,
            ..pad(1.0, 1.0)
        };
        let d = fast.doubts();
        assert_eq!(
            d,
            [Doubt::BeltBeyondCurve {
                v_belt: 300.0,
                top: 2.0,
                mu: 0.36
            }]
        );
        let said = d[0].sentence(&flag);
        assert!(
            said.starts_with(
                "--v-belt = 300 m/s is beyond the friction curve's last slip speed, 2 m/s"
            ) && said.ends_with("give 0.3 m/s"),
            "{said}"
        );
        // Just beyond the curve (1.5 times its last row): a slip there is plausible, no hint.
        let beyond = Physical {
            v_belt: 3.0,
            ..pad(1.0, 1.0)
        };
        assert!(!beyond.doubts()[0].sentence(&flag).contains("mm/s"));
    }

    /// McMillan's coefficients in percent and a belt speed in mm/s are doubted; the brake of
    /// README section 4 (mu_k 0.38, mu_s 0.48, 0.3 m/s) is not.
    #[test]
    fn coefficients_in_percent_and_a_fast_belt_are_doubted() {
        let brake = |mu_k: f64, mu_s: f64, v_belt: f64| Physical {
            m: 0.8,
            k: 2e5,
            c: 20.0,
            v_belt,
            friction: FrictionSi::Kinetic {
                mu_k,
                surface: Some(super::super::SurfaceSi { mu_s, tau: 5e-4 }),
            },
            load: Load::NormalForce(1500.0),
        };
        assert_eq!(brake(0.38, 0.48, 0.3).doubts(), []);
        assert_eq!(
            brake(0.38, 2.0, 100.0).doubts(),
            [],
            "the bounds themselves"
        );
        let d = brake(38.0, 48.0, 300.0).doubts();
        assert_eq!(
            d,
            [
                Doubt::Coefficient {
                    key: "mu_k",
                    value: 38.0
                },
                Doubt::Coefficient {
                    key: "mu_s",
                    value: 48.0
                },
                Doubt::BeltSpeed { v_belt: 300.0 },
            ]
        );
        assert_eq!(
            d[0].sentence(&flag),
            "--mu-k = 38 is above 2, higher than any dry friction coefficient: if it is in \
             percent, give 0.38"
        );
        assert!(d[2].sentence(&flag).ends_with("give 0.3 m/s"));
    }

    /// A curve in the model's units is doubted for its mu alone (its speeds have no unit).
    #[test]
    fn a_curve_in_the_models_units_is_doubted_for_its_mu() {
        let t = FrictionTable::new(&[(0.0, 60.0), (5000.0, 40.0)]).unwrap();
        let d = curve_doubts(t, false);
        assert_eq!(
            d,
            [Doubt::CurveCoefficient {
                mu: 60.0,
                speed: 0.0,
                si: false
            }]
        );
        assert!(d[0].sentence(&flag).contains("(at slip speed 0)"));
    }
}
