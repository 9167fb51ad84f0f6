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
    #[hdf5(rename = "not_computed")]
    NotComputed = 255,
}

impl Label {
    pub(crate) fn from_u8(v: u8) -> Option<Label> {
        Some(match v {
            0 => Label::Undecided,
            1 => Label::SteadySlip,
            2 => Label::StickSlip,
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
            255 => ReasonH5::NotComputed,
            _ => return None,
        })
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
