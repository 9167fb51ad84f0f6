//! SI twins of nondimensional figures: how a figure in the model's units converts to SI
//! ([`Si`], by the system's [`Scales`]). One table for every file that stores `<name>_si`
//! beside a nondimensional figure: the atlas's points ([`crate::atlas::columns::COLUMNS`])
//! and a scan's cells ([`crate::cell::COLUMNS`]).

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
        }
    }
}

/// A swept parameter of a physical scan in SI units (a `[physical]` table sweeps `c` or
/// `v_belt`; the maps' values are `nu` or `lambda`, [`crate::atlas::BoundaryParam`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptSi {
    /// The physical key: `c` or `v_belt`.
    pub key: &'static str,
    /// The SI value of one unit of the nondimensional parameter.
    pub unit: f64,
    /// The SI units: `N s/m` or `m/s`.
    pub units: &'static str,
    /// The long name ([`crate::atlas::spec::PHYSICAL`]'s).
    pub long_name: &'static str,
}

impl SweptSi {
    /// The SI twin of the nondimensional swept parameter `name` of a system with scales
    /// `s`: `c` for `nu`, `v_belt` for `lambda`; `None` for any other (the laws with true
    /// stick have no physical units).
    pub fn of(name: &str, s: &Scales) -> Option<SweptSi> {
        use crate::atlas::BoundaryParam;
        let param = [BoundaryParam::Nu, BoundaryParam::Lambda]
            .into_iter()
            .find(|b| b.key() == name)?;
        let key = param.physical_key();
        let (unit, units) = param.si(s);
        let (_, long_name, _) = crate::atlas::spec::PHYSICAL
            .iter()
            .find(|(k, ..)| *k == key)
            .copied()?;
        Some(SweptSi {
            key,
            unit,
            units,
            long_name,
        })
    }
}
