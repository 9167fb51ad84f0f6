//! SI twins of nondimensional figures: how a figure in the model's units converts to SI
//! ([`Si`], by the system's [`Scales`]). One table for every file that stores `<name>_si`
//! beside a nondimensional figure: the atlas's points ([`crate::atlas::columns::COLUMNS`])
//! and a scan's cells ([`crate::cell::COLUMNS`]).

use serde::Serialize;
use squeal_core::Scales;

/// How a nondimensional figure converts to SI units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Si {
    /// Not converted (a ratio, a count, a flag).
    None,
    /// A displacement: m.
    Length,
    /// A velocity: m/s.
    Velocity,
    /// A time: s.
    Time,
    /// An angular frequency, converted to a frequency in Hz (its SI column says
    /// "frequency", [`Si::long_name`]).
    Frequency,
    /// A phase-plane area: m^2/s.
    Area,
    /// A damping ratio, converted to a damping coefficient in N s/m.
    Damping,
    /// A rate per time unit: 1/s.
    Rate,
}

impl Si {
    /// The SI unit's symbol.
    pub fn units(self) -> &'static str {
        match self {
            Si::None => "1",
            Si::Length => "m",
            Si::Velocity => "m/s",
            Si::Time => "s",
            Si::Frequency => "Hz",
            Si::Area => "m^2/s",
            Si::Damping => "N s/m",
            Si::Rate => "1/s",
        }
    }

    /// The long name of the SI column of a column named `long`: an angular frequency's is a
    /// frequency (Hz), a damping ratio's a damping coefficient (N s/m).
    pub fn long_name(self, long: &str) -> String {
        match self {
            Si::Frequency => long.replace("angular frequency", "frequency"),
            Si::Damping => long.replace("damping ratio", "damping coefficient c"),
            _ => long.to_string(),
        }
    }

    /// A nondimensional value in SI units.
    pub fn convert(self, v: f64, s: &Scales) -> f64 {
        match self {
            Si::None => v,
            Si::Length => v * s.length,
            Si::Velocity => v * s.velocity,
            Si::Time => v * s.time,
            Si::Frequency => s.hz(v),
            Si::Area => v * s.area(),
            Si::Damping => v * s.damping,
            Si::Rate => v / s.time,
        }
    }
}

/// The SI twin of a key a physical scan sweeps: the `[physical]` key with its values as the
/// spec gave them, stored beside the model's key the maps are indexed by
/// ([`crate::space::si_twin`] names the dataset; [`crate::space::model_key`] the model's key).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweptSi {
    /// The physical key: `c`, `v_belt`, `mu_s` or `tau`.
    pub key: &'static str,
    /// Its long name ([`crate::space::PHYSICAL`]'s).
    pub long_name: &'static str,
    /// Its SI units: `N s/m`, `m/s`, `1` or `s`.
    pub units: &'static str,
    /// Its values, one per value of the swept model key, in the same order.
    pub values: Vec<f64>,
}

impl SweptSi {
    /// The twin of a physical space's axis `a`.
    pub fn of(a: &crate::space::ParamAxis) -> SweptSi {
        SweptSi {
            key: a.key,
            long_name: a.long_name,
            units: a.units,
            values: a.values.clone(),
        }
    }
}
