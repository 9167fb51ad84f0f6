//! A friction curve given as a table: `mu` against slip speed `s`, rows `(s_i, mu_i)` with
//! `s_0 = 0 < s_1 < ... < s_n`, interpolated by the monotone cubic Hermite of Fritsch and
//! Carlson (PCHIP; SIAM J. Numer. Anal. 17(2), 1980), so the curve has no extremum the rows
//! do not have: between two rows it stays between their values.
//!
//! ```text
//! mu(s) = Hermite cubic on [s_i, s_i+1] through mu_i, mu_i+1 with slopes d_i, d_i+1
//! d_i   = 0                                            where mu turns (delta_i-1 delta_i <= 0)
//!       = (w1 + w2) / (w1 / delta_i-1 + w2 / delta_i)  else (w1 = 2 h_i + h_i-1, w2 = h_i + 2 h_i-1)
//! mu(s) = mu_n  for s >= s_n  (constant beyond the last row, mu' = 0)
//! ```
//!
//! with `h_i = s_i+1 - s_i`, `delta_i = (mu_i+1 - mu_i) / h_i`, and the ends' slopes by the
//! three-point formula limited as scipy's `PchipInterpolator` limits them. The row at
//! `s = 0` is the static coefficient `mu_s = mu_0`, the limit of stick (the curve is
//! continuous from it, as the Stribeck law's `mu(0) = mu_s`).
//!
//! [`Params`](crate::Params) and [`Friction`](crate::Friction) are `Copy`; a table is held
//! by a `&'static` reference, interned ([`FrictionTable::new`]): an equal table gives the
//! same reference, so a process leaks one copy per distinct table.

use std::sync::Mutex;

use crate::error::CoreError;

/// Most rows of a table.
pub const MAX_ROWS: usize = 10_000;

/// A tabulated friction curve with its interpolation slopes. Equal by content.
#[derive(Clone, PartialEq)]
pub struct FrictionTable {
    slip: Vec<f64>,
    mu: Vec<f64>,
    /// The PCHIP slopes `d_i` at the rows.
    slope: Vec<f64>,
}

impl std::fmt::Debug for FrictionTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "FrictionTable({} rows to s = {}, mu_s = {})",
            self.slip.len(),
            self.slip[self.slip.len() - 1],
            self.mu[0]
        )
    }
}

/// The tables made so far, each leaked once.
static INTERNED: Mutex<Vec<&'static FrictionTable>> = Mutex::new(Vec::new());

impl FrictionTable {
    /// The table law's keys in specs, flags and files: damping and belt speed only (the table
    /// itself is no scalar key: `friction_table`, `friction_csv`).
    pub const KEYS: [&'static str; 2] = ["xi", "v_d"];
    /// The table law's default damping ratio `xi`: bSTAB's ([`crate::Stribeck::XI`]).
    pub const XI: f64 = crate::Stribeck::XI;
    /// The table law's default belt speed `v_d`: bSTAB's ([`crate::Stribeck::V_D`]).
    pub const V_D: f64 = crate::Stribeck::V_D;

    /// The table law's default table: bSTAB's Stribeck law (`mu_d = 0.5`, `mu_sd = 2`,
    /// `v_0 = 0.5`, `mu_v = 0`) sampled at 201 rows, slip speeds `0, 0.05, ..., 10` (where
    /// its `mu` is within `0.5 exp(-20) = 1e-9` of `mu_d`). A run names its table by
    /// `friction_table` or `friction_csv`; this one is what help lines and defaults show.
    pub fn default_table() -> &'static FrictionTable {
        static T: std::sync::OnceLock<&'static FrictionTable> = std::sync::OnceLock::new();
        T.get_or_init(|| {
            let s = crate::Stribeck::default();
            FrictionTable::sampled(|v| s.mu(v).0, 10.0, 201).expect("a valid table")
        })
    }

    /// The table of `rows` `(s, mu)`, checked and interned: at least 2 rows, at most
    /// [`MAX_ROWS`]; slip speeds finite and strictly increasing, the first exactly 0; every
    /// `mu` finite and `> 0`. The error names the row (counted from 1).
    pub fn new(rows: &[(f64, f64)]) -> Result<&'static FrictionTable, CoreError> {
        let t = FrictionTable::checked(rows)?;
        let mut all = INTERNED.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(same) = all.iter().find(|u| ***u == t) {
            return Ok(same);
        }
        let leaked: &'static FrictionTable = Box::leak(Box::new(t));
        all.push(leaked);
        Ok(leaked)
    }

    /// The table of `n >= 2` rows sampling `mu` at `s = i s_max / (n - 1)` (computed by
    /// index), for tests and defaults.
    pub fn sampled(
        mu: impl Fn(f64) -> f64,
        s_max: f64,
        n: usize,
    ) -> Result<&'static FrictionTable, CoreError> {
        let rows: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let s = i as f64 * s_max / (n - 1).max(1) as f64;
                (s, mu(s))
            })
            .collect();
        FrictionTable::new(&rows)
    }

    /// The table of a CSV text: two columns, slip speed and `mu`, separated by a comma (or
    /// a semicolon, tab or spaces); an optional header line (its first field not a number);
    /// blank lines and `#` comments skipped. The error names the line (counted from 1).
    pub fn from_csv(text: &str) -> Result<&'static FrictionTable, CoreError> {
        let (mut rows, mut lines) = (Vec::new(), Vec::new());
        let bad = |row: usize, reason: String| CoreError::InvalidTable {
            unit: "line",
            row,
            reason,
        };
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split([',', ';', '\t', ' '])
                .map(str::trim)
                .filter(|f| !f.is_empty())
                .collect();
            let nums: Vec<Option<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
            if rows.is_empty() && lines.is_empty() && nums.first().is_some_and(Option::is_none) {
                // A header line ("slip_speed,mu"), once, before the rows.
                lines.push(0);
                continue;
            }
            match nums[..] {
                [Some(s), Some(mu)] => {
                    rows.push((s, mu));
                    lines.push(i + 1);
                }
                _ => {
                    return Err(bad(
                        i + 1,
                        format!(
                            "`{line}` is not two numbers (slip speed, mu) separated by a comma"
                        ),
                    ));
                }
            }
        }
        let header = usize::from(lines.first() == Some(&0));
        FrictionTable::new(&rows).map_err(|e| match e {
            CoreError::InvalidTable { row, reason, .. } if row > 0 => {
                bad(lines[row - 1 + header], reason)
            }
            other => other,
        })
    }

    fn checked(rows: &[(f64, f64)]) -> Result<FrictionTable, CoreError> {
        let bad = |row: usize, reason: String| {
            Err(CoreError::InvalidTable {
                unit: "row",
                row,
                reason,
            })
        };
        if rows.len() < 2 || rows.len() > MAX_ROWS {
            return bad(
                rows.len().min(1),
                format!(
                    "{} rows given, expected 2 to {MAX_ROWS} rows of slip speed and mu",
                    rows.len()
                ),
            );
        }
        for (i, &(s, mu)) in rows.iter().enumerate() {
            let row = i + 1;
            let n = crate::error::Number;
            if i == 0 && s != 0.0 {
                return bad(
                    row,
                    format!(
                        "slip speed {} where the first row must be at slip speed 0 (its mu is \
                         the static coefficient)",
                        n(s)
                    ),
                );
            }
            if !s.is_finite() {
                return bad(
                    row,
                    format!("slip speed {}, expected a finite number", n(s)),
                );
            }
            if i > 0 && s <= rows[i - 1].0 {
                return bad(
                    row,
                    format!(
                        "slip speed {} not above the row before's {} (slip speeds must \
                         increase strictly)",
                        n(s),
                        n(rows[i - 1].0)
                    ),
                );
            }
            if !(mu.is_finite() && mu > 0.0 && mu <= 1e6) {
                return bad(
                    row,
                    format!(
                        "mu = {}, expected a friction coefficient in (0, 1e6]",
                        n(mu)
                    ),
                );
            }
        }
        let slip: Vec<f64> = rows.iter().map(|r| r.0).collect();
        let mu: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let slope = pchip_slopes(&slip, &mu);
        Ok(FrictionTable { slip, mu, slope })
    }

    /// The static coefficient `mu_s`: the row at slip speed 0.
    pub fn mu_s(&self) -> f64 {
        self.mu[0]
    }

    /// The largest `mu` (the interpolation has no value above its rows').
    pub fn max_mu(&self) -> f64 {
        self.mu.iter().copied().fold(0.0, f64::max)
    }

    /// The rows' slip speeds.
    pub fn slip_speeds(&self) -> &[f64] {
        &self.slip
    }

    /// The rows' coefficients.
    pub fn coefficients(&self) -> &[f64] {
        &self.mu
    }

    /// The rows `(s, mu)`.
    pub fn rows(&self) -> Vec<(f64, f64)> {
        self.slip
            .iter()
            .copied()
            .zip(self.mu.iter().copied())
            .collect()
    }

    /// The same curve with every slip speed multiplied by `factor > 0` (a change of velocity
    /// unit), interned.
    pub fn scaled(&self, factor: f64) -> Result<&'static FrictionTable, CoreError> {
        let rows: Vec<(f64, f64)> = self
            .slip
            .iter()
            .zip(&self.mu)
            .map(|(&s, &m)| (s * factor, m))
            .collect();
        FrictionTable::new(&rows)
    }

    /// `mu(s)` and `mu'(s)` for a slip speed `s >= 0`.
    #[inline]
    pub fn mu(&self, s: f64) -> (f64, f64) {
        let n = self.slip.len();
        if s >= self.slip[n - 1] {
            return (self.mu[n - 1], 0.0);
        }
        // The interval [s_i, s_i+1] holding s (s >= 0 = s_0).
        let i = self.slip.partition_point(|&x| x <= s).max(1) - 1;
        let h = self.slip[i + 1] - self.slip[i];
        let t = (s - self.slip[i]) / h;
        let (y0, y1, d0, d1) = (self.mu[i], self.mu[i + 1], self.slope[i], self.slope[i + 1]);
        let (t2, t3) = (t * t, t * t * t);
        let value = (2.0 * t3 - 3.0 * t2 + 1.0) * y0
            + (t3 - 2.0 * t2 + t) * h * d0
            + (3.0 * t2 - 2.0 * t3) * y1
            + (t3 - t2) * h * d1;
        let slope = (6.0 * t2 - 6.0 * t) * (y0 - y1) / h
            + (3.0 * t2 - 4.0 * t + 1.0) * d0
            + (3.0 * t2 - 2.0 * t) * d1;
        (value, slope)
    }
}

impl serde::Serialize for FrictionTable {
    /// The rows, `[[s, mu], ...]`.
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        let mut seq = ser.serialize_seq(Some(self.slip.len()))?;
        for (s, mu) in self.slip.iter().zip(&self.mu) {
            seq.serialize_element(&[*s, *mu])?;
        }
        seq.end()
    }
}

/// Fritsch and Carlson's slopes at the rows: zero where the data turn, the weighted harmonic
/// mean of the neighbouring secants elsewhere, the ends by the three-point formula limited
/// so as not to overshoot (as scipy's `PchipInterpolator`); two rows give the secant.
fn pchip_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let delta: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    if n == 2 {
        return vec![delta[0]; 2];
    }
    let mut d = vec![0.0; n];
    for k in 1..n - 1 {
        let (a, b) = (delta[k - 1], delta[k]);
        if a * b > 0.0 {
            let (w1, w2) = (2.0 * h[k] + h[k - 1], h[k] + 2.0 * h[k - 1]);
            d[k] = (w1 + w2) / (w1 / a + w2 / b);
        }
    }
    let end = |h0: f64, h1: f64, m0: f64, m1: f64| {
        let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
        if d.signum() != m0.signum() || m0 == 0.0 {
            0.0
        } else if m0.signum() != m1.signum() && d.abs() > 3.0 * m0.abs() {
            3.0 * m0
        } else {
            d
        }
    };
    d[0] = end(h[0], h[1], delta[0], delta[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], delta[n - 2], delta[n - 3]);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interpolation passes through the rows, stays within each interval's values (no
    /// new extrema: the rows fall, rise and fall), is exact on a straight line (PCHIP
    /// reproduces linear data: every slope is the common secant), and is constant beyond
    /// the last row.
    #[test]
    fn monotone_through_the_rows_and_flat_beyond() {
        let rows = [(0.0, 0.6), (0.1, 0.4), (0.3, 0.35), (0.7, 0.45), (1.5, 0.2)];
        let t = FrictionTable::new(&rows).unwrap();
        for &(s, mu) in &rows {
            assert!((t.mu(s).0 - mu).abs() < 1e-15, "{s}");
        }
        for w in rows.windows(2) {
            let (lo, hi) = (w[0].1.min(w[1].1), w[0].1.max(w[1].1));
            for j in 0..=200 {
                let s = w[0].0 + (w[1].0 - w[0].0) * j as f64 / 200.0;
                let (mu, dmu) = t.mu(s);
                assert!(mu >= lo - 1e-15 && mu <= hi + 1e-15, "{s}: {mu}");
                // The slope has the interval's sign (or is zero).
                assert!(dmu * (w[1].1 - w[0].1) >= -1e-12, "{s}: {dmu}");
            }
        }
        assert_eq!(t.mu(1.5), (0.2, 0.0));
        assert_eq!(t.mu(100.0), (0.2, 0.0));
        let line = FrictionTable::new(&[(0.0, 1.0), (0.5, 0.9), (2.0, 0.6), (2.5, 0.5)]).unwrap();
        for s in [0.0, 0.2, 0.77, 1.9, 2.4] {
            let (mu, dmu) = line.mu(s);
            assert!(
                (mu - (1.0 - 0.2 * s)).abs() < 1e-14 && (dmu + 0.2).abs() < 1e-13,
                "{s}"
            );
        }
    }

    /// `mu'` is the derivative of `mu` (central differences, step 1e-6, inside intervals).
    #[test]
    fn the_slope_is_the_derivative() {
        let t = FrictionTable::new(&[(0.0, 0.6), (0.2, 0.3), (0.5, 0.28), (2.0, 0.5)]).unwrap();
        for s in [0.05, 0.13, 0.31, 0.44, 0.9, 1.7] {
            let e = 1e-6;
            let fd = (t.mu(s + e).0 - t.mu(s - e).0) / (2.0 * e);
            assert!((fd - t.mu(s).1).abs() < 1e-7, "{s}: {fd} vs {}", t.mu(s).1);
        }
    }

    /// An equal table is the same reference; a different one is not.
    #[test]
    fn equal_tables_are_interned_once() {
        let a = FrictionTable::new(&[(0.0, 0.5), (1.0, 0.4)]).unwrap();
        let b = FrictionTable::new(&[(0.0, 0.5), (1.0, 0.4)]).unwrap();
        let c = FrictionTable::new(&[(0.0, 0.5), (1.0, 0.41)]).unwrap();
        assert!(std::ptr::eq(a, b) && !std::ptr::eq(a, c) && a != c);
    }

    /// Each hostile table is refused naming its row and what is wrong.
    #[test]
    fn hostile_tables_are_refused_by_row() {
        type Rows = &'static [(f64, f64)];
        let cases: [(Rows, usize, &str); 8] = [
            (&[(0.0, 0.5)], 1, "1 rows given"),
            (&[], 0, "0 rows given"),
            (
                &[(0.1, 0.5), (1.0, 0.4)],
                1,
                "first row must be at slip speed 0",
            ),
            (
                &[(0.0, 0.5), (1.0, 0.4), (0.5, 0.3)],
                3,
                "increase strictly",
            ),
            (
                &[(0.0, 0.5), (1.0, 0.4), (1.0, 0.3)],
                3,
                "increase strictly",
            ),
            (&[(0.0, 0.5), (1.0, -0.4)], 2, "mu = -0.4"),
            (&[(0.0, 0.5), (f64::NAN, 0.4)], 2, "finite"),
            (&[(0.0, f64::NAN), (1.0, 0.4)], 1, "mu = NaN"),
        ];
        for (rows, row, words) in cases {
            match FrictionTable::new(rows) {
                Err(
                    e @ CoreError::InvalidTable {
                        row: r,
                        unit: "row",
                        ..
                    },
                ) => {
                    assert_eq!(r, row, "{e}");
                    assert!(e.to_string().contains(words), "{e}");
                }
                other => panic!("{rows:?}: {other:?}"),
            }
        }
        let many: Vec<(f64, f64)> = (0..=MAX_ROWS).map(|i| (i as f64, 0.5)).collect();
        assert!(FrictionTable::new(&many).is_err());
        assert!(FrictionTable::new(&many[..MAX_ROWS]).is_ok());
    }

    /// A CSV with a header, comments and blank lines reads as its rows; a bad line is
    /// named by its number in the file.
    #[test]
    fn a_csv_reads_and_names_its_lines() {
        let t = FrictionTable::from_csv("# pad\nslip_speed,mu\n0, 0.5\n\n0.5,0.4 # fast\n1;0.38\n")
            .unwrap();
        assert_eq!(t.rows(), [(0.0, 0.5), (0.5, 0.4), (1.0, 0.38)]);
        for (text, line, words) in [
            ("s,mu\n0,0.5\n0.5,x\n", 3, "not two numbers"),
            ("0,0.5\n# c\n0.5,0.4\n0.4,0.3\n", 4, "increase strictly"),
            ("s,mu\n0,0.5\n1,-2\n", 3, "mu = -2"),
            ("0,0.5,1\n", 1, "not two numbers"),
        ] {
            let e = FrictionTable::from_csv(text).unwrap_err();
            match &e {
                CoreError::InvalidTable {
                    unit: "line", row, ..
                } => assert_eq!(*row, line, "{e}"),
                other => panic!("{other:?}"),
            }
            assert!(e.to_string().contains(words), "{e}");
        }
        let e = FrictionTable::from_csv("s,mu\n0,0.5\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("1 rows given"), "{e}");
    }
}
