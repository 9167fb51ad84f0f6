//! HDF5 types of the stored enums and of the dimension-scale attributes.

use hdf5::H5Type;
use hdf5::ObjectReference1;

/// The `labels` enum: [`squeal_core::Regime`] values plus `not_computed`.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Label {
    #[hdf5(rename = "undecided")]
    Undecided = 0,
    #[hdf5(rename = "steady_slip")]
    SteadySlip = 1,
    #[hdf5(rename = "stick_slip")]
    StickSlip = 2,
    #[hdf5(rename = "slip_oscillation")]
    SlipOscillation = 3,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl Label {
    pub(crate) fn from_u8(v: u8) -> Option<Label> {
        Some(match v {
            0 => Label::Undecided,
            1 => Label::SteadySlip,
            2 => Label::StickSlip,
            3 => Label::SlipOscillation,
            255 => Label::NotComputed,
            _ => return None,
        })
    }
}

/// The `reason` enum: [`squeal_core::Reason`] values plus `not_computed`.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum ReasonH5 {
    #[hdf5(rename = "time_limit")]
    TimeLimit = 0,
    #[hdf5(rename = "near_fixed_point")]
    NearFixedPoint = 1,
    #[hdf5(rename = "inside_cycle")]
    InsideCycle = 2,
    #[hdf5(rename = "outside_cycle")]
    OutsideCycle = 3,
    #[hdf5(rename = "settled_stick_slip")]
    SettledStickSlip = 4,
    #[hdf5(rename = "diverged")]
    Diverged = 5,
    #[hdf5(rename = "solver_failure")]
    SolverFailure = 6,
    #[hdf5(rename = "sticking_band")]
    StickingBand = 7,
    #[hdf5(rename = "start_inside_cycle")]
    StartInsideCycle = 8,
    #[hdf5(rename = "start_outside_cycle")]
    StartOutsideCycle = 9,
    #[hdf5(rename = "stick_cycle")]
    StickCycle = 10,
    #[hdf5(rename = "entered_region")]
    EnteredRegion = 11,
    #[hdf5(rename = "start_in_region")]
    StartInRegion = 12,
    #[hdf5(rename = "stuck_onto_cycle")]
    StuckOntoCycle = 13,
    #[hdf5(rename = "stuck_then_settles")]
    StuckThenSettles = 14,
    #[hdf5(rename = "below_settling_start")]
    BelowSettlingStart = 15,
    #[hdf5(rename = "between_sticking_starts")]
    BetweenStickingStarts = 16,
    #[hdf5(rename = "below_decaying_section")]
    BelowDecayingSection = 17,
    #[hdf5(rename = "start_inside_decaying_turn")]
    StartInsideDecayingTurn = 18,
    // Appended: files written before it hold values up to 18 and still read.
    #[hdf5(rename = "entered_decaying_turn")]
    EnteredDecayingTurn = 19,
    // Appended: files written before it hold values up to 19 and still read.
    #[hdf5(rename = "lasting_oscillation")]
    LastingOscillation = 20,
    #[hdf5(rename = "slip_oscillation")]
    SlipOscillation = 21,
    #[hdf5(rename = "in_trapped_band")]
    InTrappedBand = 22,
    #[hdf5(rename = "on_certified_orbit")]
    OnCertifiedOrbit = 23,
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl ReasonH5 {
    pub(crate) fn from_u8(v: u8) -> Option<ReasonH5> {
        Some(match v {
            0 => ReasonH5::TimeLimit,
            1 => ReasonH5::NearFixedPoint,
            2 => ReasonH5::InsideCycle,
            3 => ReasonH5::OutsideCycle,
            4 => ReasonH5::SettledStickSlip,
            5 => ReasonH5::Diverged,
            6 => ReasonH5::SolverFailure,
            7 => ReasonH5::StickingBand,
            8 => ReasonH5::StartInsideCycle,
            9 => ReasonH5::StartOutsideCycle,
            10 => ReasonH5::StickCycle,
            11 => ReasonH5::EnteredRegion,
            12 => ReasonH5::StartInRegion,
            13 => ReasonH5::StuckOntoCycle,
            14 => ReasonH5::StuckThenSettles,
            15 => ReasonH5::BelowSettlingStart,
            16 => ReasonH5::BetweenStickingStarts,
            17 => ReasonH5::BelowDecayingSection,
            18 => ReasonH5::StartInsideDecayingTurn,
            19 => ReasonH5::EnteredDecayingTurn,
            20 => ReasonH5::LastingOscillation,
            21 => ReasonH5::SlipOscillation,
            22 => ReasonH5::InTrappedBand,
            23 => ReasonH5::OnCertifiedOrbit,
            255 => ReasonH5::NotComputed,
            _ => return None,
        })
    }
}

/// The `audit` enum: [`squeal_scan::cell::Audit`] values.
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum AuditH5 {
    #[hdf5(rename = "not_audited")]
    NotAudited = 0,
    #[hdf5(rename = "agrees")]
    Agrees = 1,
    #[hdf5(rename = "disagrees")]
    Disagrees = 2,
    #[hdf5(rename = "undecided")]
    Undecided = 3,
}

impl AuditH5 {
    pub(crate) fn from_u8(v: u8) -> Option<AuditH5> {
        Some(match v {
            0 => AuditH5::NotAudited,
            1 => AuditH5::Agrees,
            2 => AuditH5::Disagrees,
            3 => AuditH5::Undecided,
            _ => return None,
        })
    }
}

/// The `sticks` and `reverses` enums: [`squeal_scan::cell::YES_NO_FLAGS`].
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum YesNoH5 {
    #[hdf5(rename = "no")]
    No = 0,
    #[hdf5(rename = "yes")]
    Yes = 1,
    #[hdf5(rename = "not_identified")]
    NotIdentified = 255,
}

impl YesNoH5 {
    pub(crate) fn from_u8(v: u8) -> Option<YesNoH5> {
        Some(match v {
            0 => YesNoH5::No,
            1 => YesNoH5::Yes,
            255 => YesNoH5::NotIdentified,
            _ => return None,
        })
    }
}

/// The per-map `landscape` enum: [`squeal_core::Landscape`] values plus `not_applicable`
/// (laws without true stick).
#[derive(H5Type, Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum LandscapeH5 {
    #[hdf5(rename = "unknown")]
    Unknown = 0,
    #[hdf5(rename = "stick_slip_only")]
    StickSlipOnly = 1,
    #[hdf5(rename = "bistable")]
    Bistable = 2,
    #[hdf5(rename = "steady_slip_only")]
    SteadySlipOnly = 3,
    #[hdf5(rename = "not_applicable")]
    NotApplicable = 255,
}

impl LandscapeH5 {
    pub(crate) fn of(l: Option<squeal_core::Landscape>) -> LandscapeH5 {
        use squeal_core::Landscape as L;
        match l {
            Some(L::Unknown) => LandscapeH5::Unknown,
            Some(L::StickSlipOnly) => LandscapeH5::StickSlipOnly,
            Some(L::Bistable) => LandscapeH5::Bistable,
            Some(L::SteadySlipOnly) => LandscapeH5::SteadySlipOnly,
            None => LandscapeH5::NotApplicable,
        }
    }
}

/// The HDF5 enum type of an enum column of [`squeal_scan::cell::COLUMNS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EnumColumn {
    Label,
    Reason,
    Audit,
    YesNo,
}

impl EnumColumn {
    /// The stored enum of a column with these flags (`None`: not an enum column).
    pub(crate) fn of(col: &squeal_scan::Column) -> Option<EnumColumn> {
        use squeal_scan::cell::{AUDIT_FLAGS, REASON_FLAGS, REGIME_FLAGS, YES_NO_FLAGS};
        if col.kind != squeal_scan::column::Kind::Enum {
            None
        } else if col.flags == REGIME_FLAGS {
            Some(EnumColumn::Label)
        } else if col.flags == REASON_FLAGS {
            Some(EnumColumn::Reason)
        } else if col.flags == AUDIT_FLAGS {
            Some(EnumColumn::Audit)
        } else if col.flags == YES_NO_FLAGS {
            Some(EnumColumn::YesNo)
        } else {
            None
        }
    }

    #[cfg(test)]
    pub(crate) fn descriptor(self) -> hdf5::types::TypeDescriptor {
        match self {
            EnumColumn::Label => Label::type_descriptor(),
            EnumColumn::Reason => ReasonH5::type_descriptor(),
            EnumColumn::Audit => AuditH5::type_descriptor(),
            EnumColumn::YesNo => YesNoH5::type_descriptor(),
        }
    }
}

/// One entry of a dimension scale's `REFERENCE_LIST` (HDF5 dimension-scale spec).
#[derive(H5Type, Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct RefEntry {
    pub dataset: ObjectReference1,
    pub dimension: i32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use hdf5::types::TypeDescriptor;

    #[test]
    fn every_enum_column_has_a_stored_type_with_its_flags() {
        for col in squeal_scan::COLUMNS {
            if col.kind != squeal_scan::column::Kind::Enum {
                continue;
            }
            let e = EnumColumn::of(col).unwrap_or_else(|| panic!("{}", col.name));
            let TypeDescriptor::Enum(t) = e.descriptor() else {
                panic!("not an enum")
            };
            assert_eq!(t.members.len(), col.flags.len(), "{}", col.name);
            for (v, name) in col.flags {
                assert!(
                    t.members
                        .iter()
                        .any(|m| m.name == *name && m.value == *v as u64),
                    "{}: {name}",
                    col.name
                );
            }
        }
    }

    #[test]
    fn enum_members_match_core_names() {
        let TypeDescriptor::Enum(e) = ReasonH5::type_descriptor() else {
            panic!("not an enum")
        };
        for r in squeal_core::Reason::ALL {
            assert!(
                e.members
                    .iter()
                    .any(|m| m.name == r.name() && m.value == r as u64)
            );
        }
        let TypeDescriptor::Enum(e) = LandscapeH5::type_descriptor() else {
            panic!("not an enum")
        };
        let flags = squeal_scan::landscape::flags();
        assert_eq!(e.members.len(), flags.len());
        for (v, name) in flags {
            assert!(
                e.members
                    .iter()
                    .any(|m| m.name == name && m.value == v as u64),
                "{name}"
            );
        }
        for l in squeal_core::Landscape::ALL {
            assert_eq!(LandscapeH5::of(Some(l)) as u8, l as u8);
        }
        let TypeDescriptor::Enum(e) = Label::type_descriptor() else {
            panic!("not an enum")
        };
        for r in squeal_core::Regime::ALL {
            assert!(
                e.members
                    .iter()
                    .any(|m| m.name == r.name() && m.value == r as u64)
            );
        }
    }
}
