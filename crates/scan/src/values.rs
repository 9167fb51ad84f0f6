//! A parameter's values in a spec: a number, a list, or a lin/log range, expanded by index
//! (never by adding a step). Shared by the scan spec ([`crate::spec`]) and the atlas spec
//! ([`crate::atlas::spec`]), so both read and check values the same way.

use serde::Deserialize;

use crate::error::ScanError;
use crate::grid::Axis;
use squeal_core::error::Number;

/// One parameter's values as written in a spec.
#[derive(Deserialize, Debug, Clone)]
#[serde(
    untagged,
    expecting = "a number, a list of numbers such as [1e-3, 2e-3], or a range such as { from = 1e-3, to = 1e-2, count = 8, spacing = \"log\" }"
)]
pub(crate) enum Value {
    One(f64),
    List(Vec<f64>),
    Range(RangeSpec),
}

/// `{ from, to, count, spacing }`.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct RangeSpec {
    pub from: f64,
    pub to: f64,
    pub count: i64,
    #[serde(default)]
    pub spacing: Spacing,
}

/// How a range's values are spaced.
#[derive(Deserialize, Debug, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum Spacing {
    #[default]
    Linear,
    Log,
}

impl Value {
    /// Whether the spec asks for several values (a list or a range, even of one value).
    pub fn is_sweep(&self) -> bool {
        matches!(self, Value::List(_) | Value::Range(_))
    }
}

/// The values of the range `r` of key `key`, checked: a count in `1..=max`, finite bounds,
/// positive ones for log spacing, and a single value only where `from = to`.
fn range_values(
    r: &RangeSpec,
    key: &str,
    max: i64,
    invalid: &dyn Fn(&str, String, &str) -> ScanError,
) -> Result<Vec<f64>, ScanError> {
    if r.count < 1 || r.count > max {
        return Err(invalid(
            &format!("{key}.count"),
            r.count.to_string(),
            &format!("a count in 1..={max}"),
        ));
    }
    if !r.from.is_finite() || !r.to.is_finite() {
        return Err(invalid(
            key,
            format!("from {} to {}", Number(r.from), Number(r.to)),
            "finite bounds",
        ));
    }
    if r.spacing == Spacing::Log && (r.from <= 0.0 || r.to <= 0.0) {
        return Err(invalid(
            key,
            format!("from {} to {}", Number(r.from), Number(r.to)),
            "positive bounds for log spacing",
        ));
    }
    // As a grid axis's: one value cannot stand for a range, and `to` would be dropped.
    if r.count == 1 && r.from != r.to {
        return Err(invalid(
            &format!("{key}.count"),
            format!("1 from {} to {}", Number(r.from), Number(r.to)),
            "count >= 2 for a range, or from = to for a single value",
        ));
    }
    let a = Axis {
        min: 0.0,
        max: 1.0,
        count: r.count as usize,
    };
    Ok((0..a.count)
        .map(|i| {
            let t = a.value(i);
            match r.spacing {
                Spacing::Linear => r.from + t * (r.to - r.from),
                Spacing::Log => (r.from.ln() + t * (r.to.ln() - r.from.ln())).exp(),
            }
        })
        .collect())
}

/// The values of `v`, checked: at most `max` of them, finite, strictly monotone. `invalid`
/// builds the error from the key, the value given and what is accepted.
pub(crate) fn expand(
    v: &Value,
    key: &str,
    max: i64,
    invalid: &dyn Fn(&str, String, &str) -> ScanError,
) -> Result<Vec<f64>, ScanError> {
    let values = match v {
        Value::One(x) => vec![*x],
        Value::List(xs) => {
            if xs.is_empty() {
                return Err(invalid(key, "[]".into(), "a non-empty list"));
            }
            xs.clone()
        }
        Value::Range(r) => range_values(r, key, max, invalid)?,
    };
    if values.len() as i64 > max {
        return Err(invalid(
            key,
            format!("{} values", values.len()),
            &format!("at most {max} values"),
        ));
    }
    if let Some(bad) = values.iter().find(|x| !x.is_finite()) {
        return Err(invalid(key, Number(*bad).to_string(), "finite values"));
    }
    let increasing = values.windows(2).all(|w| w[1] > w[0]);
    let decreasing = values.windows(2).all(|w| w[1] < w[0]);
    if values.len() > 1 && !increasing && !decreasing {
        return Err(invalid(
            key,
            format!("{values:?}"),
            "strictly monotone values (no repeats, one direction)",
        ));
    }
    Ok(values)
}
