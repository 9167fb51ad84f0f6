//! The per-cell and per-map datasets of a scan file, printed from the tables that write
//! them: the cell columns ([`squeal_scan::cell::COLUMNS`]), the checks
//! ([`squeal_scan::checks::CHECK_FIELDS`]), steady slip's stability, the landscape
//! ([`squeal_scan::landscape::LANDSCAPE_FIELDS`]), basin stability
//! ([`squeal_scan::BASIN_FIELDS`]) and the final-state sensitivity
//! ([`squeal_scan::sensitivity::SENSITIVITY_FIELDS`]). The crate's overview states the rest
//! of the schema (root attributes, coordinates, the cycle); this is the one statement of
//! the datasets, so it cannot fall behind what the writer writes
//! (`cargo run -p squeal-store --example schema` prints it).

use std::fmt::Write;

use squeal_scan::column::{Column, Kind, Num};

/// The per-cell and per-map datasets, one a line: name, type, fill, units and long name,
/// and an enum's members.
pub fn text() -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "per cell, shape (v0, x0), or (map|<swept key>, v0, x0) for a sweep:"
    );
    column_lines(&mut out, squeal_scan::cell::COLUMNS);
    let _ = writeln!(out, "per map, i64 (-1: not applicable):");
    for (name, long) in squeal_scan::checks::CHECK_FIELDS {
        let _ = writeln!(out, "  {name}: {long}");
    }
    let stability: Vec<(u8, &str)> = squeal_core::Stability::ALL
        .iter()
        .map(|s| (*s as u8, s.name()))
        .collect();
    let (name, long) = squeal_scan::finish::STEADY_SLIP;
    let _ = writeln!(out, "  {name} u8 enum: {long}{}", flag_words(&stability));
    let (name, long) = squeal_scan::finish::STEADY_SLIP_GROWTH;
    let _ = writeln!(out, "  {name} f64, units \"1\": {long} (_si in 1/s)");
    let _ = writeln!(out, "per map, laws with true stick only:");
    let (name, long) = squeal_scan::landscape::LANDSCAPE;
    let _ = writeln!(
        out,
        "  {name} u8 enum: {long}{}",
        flag_words(&squeal_scan::landscape::flags())
    );
    for (name, long, units, _) in squeal_scan::landscape::LANDSCAPE_FIELDS {
        let _ = writeln!(out, "  {name} f64, units \"{units}\": {long}");
    }
    let _ = writeln!(out, "per map, f64, units \"1\" (basin stability):");
    for (name, long) in squeal_scan::BASIN_FIELDS {
        let _ = writeln!(out, "  {name}: {long}");
    }
    let _ = writeln!(out, "per map, f64 (final-state sensitivity):");
    for (name, long, units, _) in squeal_scan::sensitivity::SENSITIVITY_FIELDS {
        let _ = writeln!(out, "  {name}, units \"{units}\": {long}");
    }
    let log2: Vec<(u8, &str)> = squeal_scan::sensitivity::Log2Test::ALL
        .iter()
        .map(|t| (*t as u8, t.name()))
        .collect();
    let _ = writeln!(out, "  log2_test u8 enum{}", flag_words(&log2));
    let _ = writeln!(
        out,
        "  uncertainty_changed u64 (map, uncertainty_eps): starts whose fate moved at each eps"
    );
    out
}

/// One line per column of `cols`: name, type, fill, units, long name and an enum's members.
fn column_lines<R>(out: &mut String, cols: &[Column<R>]) {
    for c in cols {
        let kind = match c.kind {
            Kind::Enum => "u8 enum",
            Kind::U8 => "u8",
            Kind::U32 => "u32",
            Kind::U64 => "u64",
            Kind::F64 => "f64",
        };
        let fill = match c.fill {
            Num::U(u) => u.to_string(),
            Num::F(f) => f.to_string(),
        };
        let units = match c.units {
            "" => String::new(),
            u => format!(", units \"{u}\""),
        };
        let members = match c.kind {
            Kind::Enum => flag_words(c.flags),
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "  {} {kind}, fill {fill}{units}: {}{members}",
            c.name, c.long_name
        );
    }
}

/// An enum's members, ` {name=value, ...}`.
fn flag_words(f: &[(u8, &str)]) -> String {
    let members: Vec<String> = f.iter().map(|(v, n)| format!("{n}={v}")).collect();
    format!(" {{{}}}", members.join(", "))
}

/// The per-point and per-boundary datasets of an atlas file (`squeal-atlas/1`), printed
/// from the tables that write them ([`squeal_scan::atlas::columns::COLUMNS`],
/// [`squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS`],
/// [`squeal_scan::atlas::columns::BOUNDARY_COLUMNS`]); the maps' datasets are the scan's
/// ([`text`]) with the prefix `map_`.
pub fn atlas_text() -> String {
    let mut out = String::new();
    let _ = writeln!(out, "over the swept dims:");
    column_lines(&mut out, squeal_scan::atlas::columns::COLUMNS);
    let _ = writeln!(out, "over the swept dims, laws with true stick only:");
    column_lines(&mut out, squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS);
    let _ = writeln!(
        out,
        "over the swept dims except the one bisected (the damping):"
    );
    column_lines(&mut out, squeal_scan::atlas::columns::BOUNDARY_COLUMNS);
    out
}

#[cfg(test)]
mod tests {
    /// Every dataset the schema prints is in docs/hdf5.md, the page h5py and xarray users
    /// read: a column or figure added to a table without its line there fails here. (The
    /// store's overview once listed the cell columns by hand and lacked four of them.)
    #[test]
    fn docs_hdf5_names_every_dataset_the_tables_write() {
        let doc = include_str!("../../../docs/hdf5.md");
        let text = super::text();
        let names: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("  "))
            .filter_map(|l| l.split([' ', ',', ':']).find(|w| !w.is_empty()))
            .collect();
        assert!(names.len() > 40, "{text}");
        // A name is documented as itself, or (basin stability) with its regime written R
        // and the regime among those R stands for.
        let regimes = ["steady_slip", "stick_slip", "undecided", "slip_oscillation"];
        let as_itself =
            |n: &str| doc.contains(&format!("`{n}`")) || doc.contains(&format!("`{n}("));
        let documented = |n: &&str| {
            as_itself(n)
                || regimes.iter().any(|r| {
                    n.contains(&format!("_{r}"))
                        && as_itself(&n.replacen(&format!("_{r}"), "_R", 1))
                        && doc.contains(&format!("`{r}`"))
                })
        };
        let missing: Vec<&&str> = names.iter().filter(|n| !documented(n)).collect();
        assert!(missing.is_empty(), "docs/hdf5.md lacks {missing:?}");
        for c in squeal_scan::cell::COLUMNS {
            assert!(text.contains(c.name), "{}", c.name);
            for (_, member) in c.flags {
                assert!(text.contains(member), "{member}");
            }
        }
    }
}
