//! Errors of the numerical core.

/// What the core refuses.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum CoreError {
    /// A model or integration parameter is out of range.
    #[error("invalid {name} = {}: expected {expected}", Number(*value))]
    InvalidParameter {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// The physical units are McMillan's scaling; this law has none.
    #[error(
        "law {0} has no physical units (they are McMillan's scaling): give its nondimensional \
         parameters"
    )]
    NoPhysicalUnits(&'static str),
    /// A physical key whose value, valid alone, makes a nondimensional figure the model
    /// cannot use: the key named is the one of the figure's factors that is furthest from
    /// a plausible system ([`crate::units`], "the key at fault"), with the value as given.
    #[error("invalid {key} = {}: {why}", Number(*value))]
    Source {
        /// The physical key at fault (`m`, `normal_force`, ...).
        key: &'static str,
        /// Its value, as given.
        value: f64,
        /// The figure it makes, its value and what that figure must be.
        why: String,
    },
    /// A belt speed below what the step resolves (`lambda < dt` in the model's units;
    /// [`crate::Params::check_step`] gives the argument).
    #[error(
        "invalid {name} = {}: expected a belt speed of at least the step dt = {} in the \
         model's units: below it one step under the unit friction force changes the velocity \
         by more than the belt speed, so the run crosses zero slip within a step and chatters \
         about it, and its labels are the step's, not the model's",
        Number(*value),
        Number(*dt)
    )]
    Unresolved {
        /// `lambda` or `v_d`.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The step.
        dt: f64,
    },
    /// A physical key the law needs and was not given (`mu_s` or `tau` for McMillan's laws,
    /// `mu_k` for them and Coulomb, the curve for the table law).
    #[error(
        "missing: law {law} needs it ({})",
        crate::units::friction_key_meaning(key)
    )]
    MissingPhysicalKey {
        /// The key (one of [`crate::units::FRICTION_KEYS`]).
        key: &'static str,
        /// The law's name.
        law: &'static str,
    },
    /// A physical key given to a law that does not use it (`mu_s` or `tau` with Coulomb,
    /// whose force has no static peak and no surface time; `mu_k` with a measured curve).
    #[error(
        "given, but law {law} does not use it ({}): leave it out",
        crate::units::friction_key_meaning(key)
    )]
    UnusedPhysicalKey {
        /// The key (one of [`crate::units::FRICTION_KEYS`]).
        key: &'static str,
        /// The law's name.
        law: &'static str,
    },
    /// Both `g` and `normal_force` given: the normal force `N` replaces the weight `m g` in
    /// the law (friction is `mu N`), so `g` would mean nothing beside it.
    #[error(
        "given with g, but the normal force N replaces the block's weight m g in the law \
         (friction is mu N): give normal_force for a pressed block, or g for one under its own \
         weight, not both"
    )]
    BothLoads,
    /// A friction-law name that is not one of ours, with the names that are
    /// ([`crate::FrictionLaw::names`], so the next law needs no edit here).
    #[error("unknown friction law '{name}' (expected one of {expected})")]
    UnknownLaw {
        /// The name given.
        name: String,
        /// Every law's name.
        expected: String,
    },
    /// A friction table ([`crate::table::FrictionTable`]) with a bad row, or too few or too
    /// many rows: the row (counted from 1; 0 for an empty table) and what is wrong with it.
    #[error("friction table {unit} {row}: {reason}")]
    InvalidTable {
        /// `row` (of a list of rows) or `line` (of a CSV text).
        unit: &'static str,
        /// The row or line, counted from 1.
        row: usize,
        /// What is wrong, with the values.
        reason: String,
    },
    /// A scheme name that is not one of ours.
    #[error("unknown scheme '{0}' (expected foh or zoh)")]
    UnknownScheme(String),
    /// A solver name that is not one of ours.
    #[error("unknown solver '{0}' (expected robust or paper)")]
    UnknownSolver(String),
}

/// A value as a reader reads it: as Rust writes it (`0.45`, `-1`, `NaN`), in exponent form
/// where that would run to more than 16 digits (`1e300`, not 301 digits; `2.5e-7`). With a
/// precision (`{:.6}`) it is written to that many decimals, in exponent form from 1e16 up
/// (`x = {:.9}` of 1e300 ran to 310 characters); small values keep their fixed form.
#[derive(Clone, Copy, Debug)]
pub struct Number(pub f64);

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (x, a) = (self.0, self.0.abs());
        let huge = a.is_finite() && a >= 1e16;
        match f.precision() {
            Some(p) if huge => write!(f, "{x:.p$e}"),
            Some(p) => write!(f, "{x:.p$}"),
            None if huge || (a.is_finite() && a != 0.0 && a < 1e-5) => write!(f, "{x:e}"),
            None => write!(f, "{x}"),
        }
    }
}

/// `text` with each number written out to more than 17 digits put as [`Number`] writes it:
/// for messages of other libraries (serde's "invalid type: floating point `1000...0`" wrote
/// `count = 1e308` as 309 digits).
pub fn readable_numbers(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphanumeric());
        if !starts {
            let c = text[i..].chars().next().expect("in bounds");
            out.push(c);
            i += c.len_utf8();
            continue;
        }
        let mut j = i;
        while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
            j += 1;
        }
        let run = &text[i..j];
        let digits = run.bytes().filter(u8::is_ascii_digit).count();
        match run.parse::<f64>() {
            Ok(v) if digits > 17 => out.push_str(&Number(v).to_string()),
            _ => out.push_str(run),
        }
        i = j;
    }
    out
}

impl CoreError {
    /// The key an error is about, if it names one (a parameter out of range, a physical key
    /// missing or not used): callers turn it into their flag or spec key.
    pub fn key(&self) -> Option<&'static str> {
        match self {
            CoreError::InvalidParameter { name, .. } | CoreError::Unresolved { name, .. } => {
                Some(name)
            }
            CoreError::Source { key, .. } => Some(key),
            CoreError::MissingPhysicalKey { key, .. }
            | CoreError::UnusedPhysicalKey { key, .. } => Some(key),
            CoreError::BothLoads => Some("normal_force"),
            _ => None,
        }
    }

    /// `Err(InvalidParameter)`: a value out of its range, naming the key and what it must be.
    pub fn invalid<T>(
        name: &'static str,
        value: f64,
        expected: &'static str,
    ) -> Result<T, CoreError> {
        Err(CoreError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// serde writes a float given for an integer key in full (`count = 1e308`: 309 digits);
    /// rewritten, it reads as given. Short numbers and names are left alone.
    #[test]
    fn long_numbers_in_other_messages_are_shortened() {
        let long = format!("floating point `{}`, expected usize", 1e308);
        assert_eq!(long.len(), 309 + 33, "{long}");
        assert_eq!(
            readable_numbers(&long),
            "floating point `1e308`, expected usize"
        );
        let tiny = format!("at {}", 1e-300);
        assert_eq!(readable_numbers(&tiny), "at 1e-300");
        let short = "line 3, column 9: count = 12.5 at map_0012 of 0.000001";
        assert_eq!(readable_numbers(short), short);
    }

    /// A huge or tiny value is named in exponent form: `1e300` was written out as 301 digits
    /// (`squeal critical --law cubic --a1 1e300`), which no reader can check at a glance.
    #[test]
    fn a_refused_value_is_named_as_a_reader_reads_it() {
        let msg = |v: f64| {
            CoreError::invalid::<()>("a1", v, "a coefficient")
                .unwrap_err()
                .to_string()
        };
        assert_eq!(msg(1e300), "invalid a1 = 1e300: expected a coefficient");
        assert_eq!(msg(-2.5e-7), "invalid a1 = -2.5e-7: expected a coefficient");
        assert_eq!(
            msg(f64::MAX),
            "invalid a1 = 1.7976931348623157e308: expected a coefficient"
        );
        // In range, as Rust writes them (what existing messages and tests read).
        for (v, w) in [(0.45, "0.45"), (-1.0, "-1"), (0.0, "0"), (1e6, "1000000")] {
            assert_eq!(msg(v), format!("invalid a1 = {w}: expected a coefficient"));
        }
        assert_eq!(msg(f64::NAN), "invalid a1 = NaN: expected a coefficient");
        assert_eq!(
            msg(f64::NEG_INFINITY),
            "invalid a1 = -inf: expected a coefficient"
        );
    }
}
