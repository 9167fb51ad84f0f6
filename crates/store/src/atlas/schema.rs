//! The atlas file's datasets that are not rows of the scan crate's tables
//! ([`squeal_scan::atlas::columns::COLUMNS`], [`BOUNDARY_COLUMNS`](squeal_scan::atlas::columns::BOUNDARY_COLUMNS),
//! [`LANDSCAPE_COLUMNS`](squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS)): their names,
//! long names and stored enums, in one place for the writer, the reader and the journal.

use hdf5::H5Type;
use squeal_scan::atlas::columns::Column;
use squeal_scan::atlas::{AtlasPlan, AtlasRegime, Boundary, BoundaryParam, BoundaryResult};
use squeal_scan::atlas::{BoundaryStatus, Note, NoteKind, PointResult};

/// A dataset's name and long name.
pub(super) type Named = (&'static str, &'static str);

pub(super) const REGIME: Named = ("regime", "regime of the parameter point");
pub(super) const NOTE: Named = (
    "note",
    "why a point is undecided, or the caveat its label rests on (empty: none)",
);
pub(super) const NOTE_KIND: Named = (
    "note_kind",
    "what the point's note says: none, finding (the label does not rest on it), unconfirmed (a check of the label did not finish), failure (a computation failed), conflict (two findings contradict each other: undecided)",
);
pub(super) const BOUNDARY_NOTE_KIND: Named = (
    "boundary_note_kind",
    "what the boundary's note says: none, finding, unconfirmed, failure (a search was not computed), conflict",
);

/// The notes of `notes` as stored: their words (empty: none) and their kinds (0: none).
pub(super) fn note_columns<'n>(
    notes: impl Iterator<Item = Option<&'n Note>>,
) -> (Vec<Option<&'n str>>, Vec<u8>) {
    notes
        .map(|n| (n.map(|n| n.text.as_str()), n.map_or(0, |n| n.kind as u8)))
        .unzip()
}

/// A note read back from its words and stored kind. Files and journals written before the
/// kinds were stored (`kind` absent) say a conflict or an unconfirmed label in their first
/// word, as their notes always did; any other note was a finding or a failure, and is read
/// as a finding.
pub(super) fn note_of(text: Option<String>, kind: Option<u8>) -> Option<Note> {
    let text = text.filter(|t| !t.is_empty())?;
    let kind = match kind.map(NoteKind::from_u8) {
        Some(Some(k)) => k,
        _ if text.starts_with("conflict:") => NoteKind::Conflict,
        _ if text.starts_with("unconfirmed:") => NoteKind::Unconfirmed,
        _ => NoteKind::Finding,
    };
    Some(Note::new(kind, text))
}

pub(super) const POINTS_DONE: Named = ("points_done", "1 where the point is computed");
pub(super) const BOUNDARY_NOTE: Named = (
    "boundary_note",
    "why a boundary search was not computed (empty: none)",
);
pub(super) const BOUNDARIES_DONE: Named =
    ("boundaries_done", "1 where the boundary search is computed");
pub(super) const FOLD_CHANGES: Named = (
    "fold_changes",
    "fold: changes of regime (squeal lasting or not) the coarse scan found along the bisected parameter before bisecting; more than 1: the regime flips back and forth and the fold is the last change (0: no coarse scan)",
);

/// One of the two searches of a boundary result, stored as `<key>_status` (how the
/// bisection ended) and `<key>_half_dt` (the bracket checked again at dt/2), and journalled
/// with its evaluations.
pub(super) struct Search {
    /// `fold` or `critical`.
    pub key: &'static str,
    /// Long name of `<key>_status`.
    pub status_long: fn(&AtlasPlan) -> &'static str,
    /// Long name of `<key>_half_dt`.
    pub half_dt_long: &'static str,
    pub get: fn(&BoundaryResult) -> &Boundary,
    pub get_mut: fn(&mut BoundaryResult) -> &mut Boundary,
}

/// The fold of cycles and the critical value, in file order.
pub(super) const SEARCHES: [Search; 2] = [
    Search {
        key: "fold",
        status_long: |_| "fold of cycles: how the bisection ended",
        half_dt_long: "fold of cycles: 1 if at dt/2 the predicate still holds at both ends of the bracket (the fold at dt/2 lies in it), 0 if it moved out, 255 not checked",
        get: |b| &b.fold,
        get_mut: |b| &mut b.fold,
    },
    Search {
        key: "critical",
        status_long: |plan| match plan.boundary_in {
            BoundaryParam::Lambda => "critical belt speed: how the bisection ended",
            BoundaryParam::Nu => "critical damping: how the bisection ended",
        },
        half_dt_long: "critical value: 1 if at dt/2 the operating point still squeals at the lower end and is quiet at the upper, 0 if the boundary moved out, 255 not checked",
        get: |b| &b.critical,
        get_mut: |b| &mut b.critical,
    },
];

impl Search {
    pub(super) fn status_name(&self) -> String {
        format!("{}_status", self.key)
    }

    pub(super) fn half_dt_name(&self) -> String {
        format!("{}_half_dt", self.key)
    }
}

/// CF flags of `<key>_half_dt`.
pub(super) const HALF_DT_FLAGS: (&str, &[u8]) = ("moves holds not_checked", &[0, 1, 255]);

/// The stored value of a dt/2 check.
pub(super) fn half_dt_u8(h: Option<bool>) -> u8 {
    match h {
        Some(true) => 1,
        Some(false) => 0,
        None => 255,
    }
}

/// A dt/2 check read back (255 and values of files without the check: not checked).
pub(super) fn half_dt_of(v: Option<&u8>) -> Option<bool> {
    match v {
        Some(1) => Some(true),
        Some(0) => Some(false),
        _ => None,
    }
}

/// The `regime` enum in files: [`AtlasRegime`] plus `not_computed`.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum RegimeH5 {
    #[hdf5(rename = "undecided")]
    Undecided = 0,
    #[hdf5(rename = "steady_slip_only")]
    SteadySlipOnly = 1,
    #[hdf5(rename = "bistable_quiet")]
    BistableQuiet = 2,
    #[hdf5(rename = "bistable_squeals")]
    BistableSqueals = 3,
    #[hdf5(rename = "fixed_point_unstable")]
    FixedPointUnstable = 4,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl RegimeH5 {
    pub(super) fn from(r: Option<AtlasRegime>) -> RegimeH5 {
        match r {
            None => RegimeH5::NotComputed,
            Some(AtlasRegime::Undecided) => RegimeH5::Undecided,
            Some(AtlasRegime::SteadySlipOnly) => RegimeH5::SteadySlipOnly,
            Some(AtlasRegime::BistableQuiet) => RegimeH5::BistableQuiet,
            Some(AtlasRegime::BistableSqueals) => RegimeH5::BistableSqueals,
            Some(AtlasRegime::FixedPointUnstable) => RegimeH5::FixedPointUnstable,
        }
    }

    /// CF flags: [`AtlasRegime`]'s names in value order, then `not_computed`.
    pub(super) fn flags() -> (String, [u8; 6]) {
        let meanings: Vec<&str> = AtlasRegime::ALL.iter().map(|r| r.name()).collect();
        (
            format!("{} not_computed", meanings.join(" ")),
            [0, 1, 2, 3, 4, 255],
        )
    }
}

/// The boundary `*_status` enum in files.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum StatusH5 {
    #[hdf5(rename = "found")]
    Found = 0,
    #[hdf5(rename = "below_range")]
    BelowRange = 1,
    #[hdf5(rename = "above_range")]
    AboveRange = 2,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl StatusH5 {
    pub(super) fn from(s: BoundaryStatus) -> StatusH5 {
        match s {
            BoundaryStatus::Found => StatusH5::Found,
            BoundaryStatus::BelowRange => StatusH5::BelowRange,
            BoundaryStatus::AboveRange => StatusH5::AboveRange,
            BoundaryStatus::NotComputed => StatusH5::NotComputed,
        }
    }
}

/// The stored `landscape` of a point not computed.
pub(super) const LANDSCAPE_NOT_COMPUTED: u8 = 255;

/// The CF flag meanings and values of the per-point `landscape` enum.
pub(super) fn landscape_flags() -> (String, Vec<u8>) {
    let mut values: Vec<u8> = squeal_core::Landscape::ALL
        .iter()
        .map(|l| *l as u8)
        .collect();
    let mut names: Vec<&str> = squeal_core::Landscape::ALL
        .iter()
        .map(|l| l.name())
        .collect();
    values.push(LANDSCAPE_NOT_COMPUTED);
    names.push("not_computed");
    (names.join(" "), values)
}

/// Sets the stored landscape verdict of a point (laws with true stick).
pub(super) fn set_landscape(p: &mut PointResult, v: u8) {
    if let Some(l) = p.landscape.as_mut() {
        l.landscape = v;
    } else {
        p.landscape = Some(squeal_scan::atlas::true_stick::LandscapeRecord {
            landscape: v,
            damping: f64::NAN,
            cycle_period: f64::NAN,
            cycle_stuck: f64::NAN,
        });
    }
}

/// The dataset name and long name of a point column: with maps, `basin_fraction` and
/// `basin_fraction_err` are the map's, and the point's own (from the cycle) are stored as
/// `basin_fraction_cycle` and `basin_fraction_cycle_err`; laws with true stick store
/// `stick_quasi_static_share` as `stick_stuck_share`.
pub(super) fn stored_name(plan: &AtlasPlan, c: &Column) -> (String, String) {
    if plan.space.law.family().locates_stick() && c.name == "stick_quasi_static_share" {
        let (name, long) = squeal_scan::atlas::true_stick::STUCK_SHARE;
        return (name.into(), long.into());
    }
    match (plan.maps.is_some(), c.name) {
        (true, "basin_fraction" | "basin_fraction_err") => (
            c.name.replacen("basin_fraction", "basin_fraction_cycle", 1),
            format!("{} (from the unstable cycle)", c.long_name),
        ),
        _ => (c.name.to_string(), c.long_name.to_string()),
    }
}

/// The dataset of a per-cell column (or a per-map check) in an atlas file: `map_` and its
/// name in [`squeal_scan::cell::COLUMNS`] (a point's own columns such as `evaluations`
/// keep their names).
pub fn map_name(column: &str) -> String {
    format!("map_{column}")
}
