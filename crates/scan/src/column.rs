//! One stored column of a table of records: a scan's cells ([`crate::cell::COLUMNS`]), an
//! atlas's points ([`crate::atlas::columns::COLUMNS`], with
//! [`crate::atlas::true_stick::LANDSCAPE_COLUMNS`]) and its boundary searches
//! ([`crate::atlas::columns::BOUNDARY_COLUMNS`]).
//!
//! A [`Column`] says everything a file needs of one quantity: its dataset name, CF long
//! name and units, how it is stored ([`Kind`], with the members of an enum), its fill value
//! where nothing was computed, how to read it from and write it into a record ([`Num`]), and
//! its SI twin in a physical file ([`Twin`]). The journals, the HDF5 writer and reader, the
//! CSV of `squeal classify` and `squeal atlas --json` all loop over these tables.

use squeal_core::Scales;

use crate::si::Si;

/// How a column is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An 8-bit enum with named values ([`Column::flags`]).
    Enum,
    /// Unsigned 8-bit.
    U8,
    /// Unsigned 32-bit.
    U32,
    /// Unsigned 64-bit.
    U64,
    /// 64-bit float.
    F64,
}

impl Kind {
    /// Bytes in the journal.
    pub fn bytes(self) -> usize {
        match self {
            Kind::Enum | Kind::U8 => 1,
            Kind::U32 => 4,
            Kind::U64 | Kind::F64 => 8,
        }
    }
}

/// One column's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Num {
    /// An unsigned integer (enums, flags, counters).
    U(u64),
    /// A float.
    F(f64),
}

impl Num {
    /// As an unsigned integer (floats truncate).
    pub fn as_u64(self) -> u64 {
        match self {
            Num::U(u) => u,
            Num::F(f) => f as u64,
        }
    }

    /// As a float.
    pub fn as_f64(self) -> f64 {
        match self {
            Num::U(u) => u as f64,
            Num::F(f) => f,
        }
    }
}

/// The SI twin a physical file stores beside a nondimensional column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Twin {
    /// None: a ratio, a count or a flag.
    None,
    /// `<name>_si`, converted by the scales of its record, with its own long name.
    Named(Si, &'static str),
    /// `<name>_si`, converted by the scales of its record; its long name is the column's
    /// as [`Si::long_name`] makes it.
    Si(Si),
    /// A value of the parameter a boundary search bisects: `<name>` with `nu` replaced by
    /// `c` (N s/m), or `lambda` by `v_belt` (m/s).
    Bisected,
    /// A nondimensional time of a boundary search: `<name>_s`, in seconds.
    Seconds,
}

/// One stored quantity of a record `R` (a cell, a point, a boundary search).
pub struct Column<R> {
    /// Dataset (and CSV, journal, JSON) name.
    pub name: &'static str,
    /// CF `long_name`.
    pub long_name: &'static str,
    /// CF `units` (`"1"` for dimensionless numbers; `""`: no attribute, as on enums and
    /// counters).
    pub units: &'static str,
    /// Storage type.
    pub kind: Kind,
    /// For [`Kind::Enum`]: `(value, name)` of each member, including the fill.
    pub flags: &'static [(u8, &'static str)],
    /// The value where nothing was computed.
    pub fill: Num,
    /// Reads the column from a record.
    pub get: fn(&R) -> Num,
    /// Writes the column into a record.
    pub set: fn(&mut R, Num),
    /// Its SI twin in a physical file.
    pub si: Twin,
}

// Not derived: a derive would ask `R: Clone` of the record, which the fn pointers do not need.
impl<R> Clone for Column<R> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<R> Copy for Column<R> {}

impl<R> std::fmt::Debug for Column<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Column")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .finish_non_exhaustive()
    }
}

impl<R> Column<R> {
    /// The name of an enum value (`None` if not a member).
    pub fn flag_name(&self, v: u64) -> Option<&'static str> {
        self.flags
            .iter()
            .find(|(k, _)| *k as u64 == v)
            .map(|(_, n)| *n)
    }

    /// The value as text (enum members by name; floats shortest round-trip).
    pub fn text(&self, r: &R) -> String {
        let v = (self.get)(r);
        match (self.kind, v) {
            (Kind::Enum, v) => self
                .flag_name(v.as_u64())
                .map_or_else(|| v.as_u64().to_string(), str::to_string),
            (_, Num::U(u)) => u.to_string(),
            (_, Num::F(f)) => f.to_string(),
        }
    }

    /// The value as a float, NaN where it is not known: a float's NaN, an enum at its fill
    /// (as the atlas's journal and `--json` carry a point's figures).
    pub fn value(&self, r: &R) -> f64 {
        let v = (self.get)(r);
        match self.kind {
            Kind::Enum if v == self.fill => f64::NAN,
            _ => v.as_f64(),
        }
    }

    /// Writes a float as [`Column::value`] gives it: NaN writes the fill.
    pub fn set_value(&self, r: &mut R, x: f64) {
        let v = match self.kind {
            Kind::F64 => Num::F(x),
            _ if x.is_nan() => self.fill,
            _ => Num::U(x as u64),
        };
        (self.set)(r, v)
    }

    /// The SI units and long name of its `<name>_si` twin ([`Twin::Named`], [`Twin::Si`]).
    pub fn si_twin(&self) -> Option<(Si, String)> {
        match self.si {
            Twin::Named(si, long) => Some((si, long.to_string())),
            Twin::Si(si) => Some((si, si.long_name(self.long_name))),
            _ => None,
        }
    }

    /// The column's value in a record in SI units by the scales `s` (NaN for a column
    /// without a `<name>_si` twin). A time keeps [`squeal_core::T_SQUEAL_UNKNOWN`]
    /// (`t_squeal`'s "not known", no time); infinity stays infinite, NaN NaN.
    pub fn si_value(&self, r: &R, s: &Scales) -> f64 {
        self.si_of((self.get)(r).as_f64(), s)
    }

    /// [`Column::si_value`] of a value `v` of the column.
    pub fn si_of(&self, v: f64, s: &Scales) -> f64 {
        match self.si_twin() {
            None => f64::NAN,
            Some((Si::Time, _)) if v == squeal_core::T_SQUEAL_UNKNOWN => v,
            Some((si, _)) => si.convert(v, s),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `table`'s names are unique and every column's setter writes what its getter
    /// reads and no other column: first every column is set to a base value, then each in
    /// turn to a value of its own, and every column is read back. Returns the first fault,
    /// naming the column.
    fn check_table<R>(table: &[Column<R>], mut r: R) -> Result<(), String> {
        for (i, c) in table.iter().enumerate() {
            if table[..i].iter().any(|d| d.name == c.name) {
                return Err(format!("{}: name used twice", c.name));
            }
        }
        for (i, c) in table.iter().enumerate() {
            let base = match c.kind {
                Kind::F64 => Num::F(i as f64 + 0.25),
                Kind::Enum => c.fill,
                _ => Num::U(1),
            };
            (c.set)(&mut r, base);
        }
        for (i, c) in table.iter().enumerate() {
            let now = (c.get)(&r);
            let v = match c.kind {
                Kind::F64 => Num::F(1000.0 + i as f64 + 0.5),
                Kind::Enum => (c.flags.iter())
                    .map(|(f, _)| Num::U(*f as u64))
                    .find(|f| *f != c.fill && *f != now)
                    .ok_or(format!("{}: no second member", c.name))?,
                _ => Num::U(100 + i as u64),
            };
            let before: Vec<Num> = table.iter().map(|d| (d.get)(&r)).collect();
            (c.set)(&mut r, v);
            let got = (c.get)(&r);
            if got != v {
                return Err(format!("{}: set {v:?}, read {got:?}", c.name));
            }
            for (d, b) in table.iter().zip(&before) {
                let same =
                    (d.get)(&r) == *b || (d.get)(&r).as_f64().is_nan() && b.as_f64().is_nan();
                if d.name != c.name && !same {
                    return Err(format!("{}: setting it changed {}", c.name, d.name));
                }
            }
        }
        Ok(())
    }

    #[test]
    fn every_table_has_unique_names_and_its_setters_write_their_own_field() {
        use crate::atlas::columns::{BOUNDARY_COLUMNS, COLUMNS, empty_boundary, empty_point};
        use crate::atlas::true_stick::LANDSCAPE_COLUMNS;
        check_table(crate::cell::COLUMNS, crate::cell::Cell::fill()).unwrap();
        let points: Vec<_> = COLUMNS.iter().chain(LANDSCAPE_COLUMNS).copied().collect();
        check_table(&points, empty_point()).unwrap();
        check_table(BOUNDARY_COLUMNS, empty_boundary(0)).unwrap();
    }

    #[test]
    fn the_check_finds_a_setter_that_writes_another_field() {
        use crate::atlas::columns::{BOUNDARY_COLUMNS, empty_boundary};
        let mut bad = BOUNDARY_COLUMNS.to_vec();
        let k = bad.iter().position(|c| c.name == "fold_nu_lo").unwrap();
        bad[k].set = |b, v| b.fold.bracket[1] = v.as_f64();
        let err = check_table(&bad, empty_boundary(0)).unwrap_err();
        assert!(err.starts_with("fold_nu_lo:"), "{err}");
        // A getter and a setter both of another column's field: that column changes.
        bad[k].get = |b| Num::F(b.fold.bracket[1]);
        let err = check_table(&bad, empty_boundary(0)).unwrap_err();
        assert!(err.contains("changed fold_nu_hi"), "{err}");
    }

    #[test]
    fn a_value_as_a_float_is_nan_where_an_enum_is_at_its_fill() {
        use crate::atlas::columns::{COLUMNS, empty_point};
        let c = COLUMNS.iter().find(|c| c.name == "warm_started").unwrap();
        let mut p = empty_point();
        assert_eq!(c.value(&p), 0.0);
        c.set_value(&mut p, f64::NAN);
        assert!(!p.warm_started);
        c.set_value(&mut p, 1.0);
        assert!(p.warm_started);
        let e = COLUMNS
            .iter()
            .find(|c| c.name == "cycle_encloses_operating_point")
            .unwrap();
        assert!(e.value(&p).is_nan(), "no cycle: not known");
    }
}
