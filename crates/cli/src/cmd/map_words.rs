//! The words about a scan file's maps that `scan` and `info` print: the landscape, the
//! return map's escape and the checks.

/// The landscape of a map in words: the verdict, its note and its evidence.
pub fn landscape_words(l: &squeal_store::LandscapeInfo) -> Vec<String> {
    let ev: Vec<String> = l
        .evidence
        .iter()
        .map(|(n, v)| format!("{n} = {v:.6}"))
        .collect();
    vec![
        format!("landscape: {} ({})", l.landscape.name(), l.landscape.note()),
        format!("  evidence: {}", ev.join(", ")),
    ]
}

/// The landscape of a map as JSON (`null` where none is stored).
pub fn landscape_json(l: Option<&squeal_store::LandscapeInfo>) -> serde_json::Value {
    l.map_or(serde_json::Value::Null, |l| {
        let mut o = serde_json::Map::new();
        o.insert("landscape".into(), l.landscape.name().into());
        o.insert("note".into(), l.landscape.note().into());
        for (n, v) in &l.evidence {
            // NaN (no stick-slip cycle) is null in JSON.
            o.insert((*n).into(), serde_json::json!(v.is_finite().then_some(*v)));
        }
        o.into()
    })
}

/// The line for a map whose return map jumps past the cycle from `r` (the scanner's
/// [`squeal_scan::scanner::Outside::Escapes`]).
pub fn escape_words(r: f64) -> String {
    format!(
        "the return map jumps past the cycle (the start r = {r:.4} on the section returns inside): starts outside may end in steady slip, so none is labelled stick-slip for lying outside, and none by its band unless the band above the cycle is trapped (its returns never fall inside)"
    )
}

/// One line per check that found something, in words (`sample`: random initial conditions,
/// where a cell, and so "beyond a pixel", does not exist).
pub fn check_words(values: &[i64], sample: bool) -> Vec<String> {
    let v = |name: &str| {
        squeal_scan::checks::CHECK_FIELDS
            .iter()
            .position(|(n, _)| *n == name)
            .and_then(|i| values.get(i).copied())
            .unwrap_or(-1)
    };
    let mut out = Vec::new();
    if v("wrong_side_cells") >= 0 && sample {
        out.push(format!(
            "wrong side of cycle: {} samples",
            v("wrong_side_cells")
        ));
    } else if v("wrong_side_cells") >= 0 {
        out.push(format!(
            "wrong side of cycle: {} ({} beyond a pixel)",
            v("wrong_side_cells"),
            v("wrong_side_beyond_pixel")
        ));
    }
    if v("audit_cells") > 0 {
        out.push(format!(
            "audit (run to settlement) of {} cells: {} agree, {} disagree, {} undecided",
            v("audit_cells"),
            v("audit_agrees"),
            v("audit_disagrees"),
            v("audit_undecided")
        ));
    }
    let (steady, stick) = (v("settled_steady_slip"), v("settled_stick_slip"));
    if steady > 0 || stick > 0 {
        // Why: no certified shortcut reached these runs (crates/core/MODEL.md section 9).
        out.push(format!(
            "runs to settlement: {steady} steady slip within fp_radius (no certified region, \
             or the run never entered it), {stick} stick-slip by a settled band or a second \
             stick (no located cycle or known orbit from breakaway decided them)"
        ));
    }
    if v("origin_disagrees") == 1 {
        out.push(
            "DISAGREEMENT: the label at (0, 0) contradicts whether the cycle encloses (0, 0)"
                .into(),
        );
    }
    if v("landscape_contradictions") >= 0 {
        out.push(format!(
            "against the landscape: {} decided cells labelled otherwise",
            v("landscape_contradictions")
        ));
    }
    if v("landscape_contradictions") > 0 {
        out.push(format!(
            "DISAGREEMENT: {} decided cells are labelled against the landscape",
            v("landscape_contradictions")
        ));
    }
    if v("audit_disagrees") > 0 {
        out.push(
            "DISAGREEMENT: the early-stopping rule and runs to settlement label some cells differently"
                .into(),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::check_words;

    /// "wrong side of cycle: N (M beyond a pixel)" is a grid's words: random samples have no
    /// pixel. The values follow `checks::CHECK_FIELDS`: 3 wrong-side cells, 1 of them beyond a
    /// pixel, every other check -1 (not applicable).
    #[test]
    fn random_samples_have_no_pixel() {
        let fields = squeal_scan::checks::CHECK_FIELDS;
        let values: Vec<i64> = fields
            .iter()
            .map(|(name, _)| match *name {
                "wrong_side_cells" => 3,
                "wrong_side_beyond_pixel" => 1,
                _ => -1,
            })
            .collect();
        let grid = check_words(&values, false).join("\n");
        assert!(
            grid.contains("wrong side of cycle: 3 (1 beyond a pixel)"),
            "{grid}"
        );
        let sample = check_words(&values, true).join("\n");
        assert!(
            sample.contains("wrong side of cycle: 3 samples"),
            "{sample}"
        );
        assert!(!sample.contains("pixel"), "{sample}");
    }
}
