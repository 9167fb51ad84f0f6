//! Notes on atlas points and boundary searches: a [`NoteKind`] that code and readers of the
//! file branch on (stored as the flags `note_kind` and `boundary_note_kind`), and the words
//! that say what was found.

use serde::{Deserialize, Serialize};

/// What a note says about its point or boundary search, from the mildest to the gravest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum NoteKind {
    /// Something found along the way that the label does not rest on (the landscape's
    /// words, no attractor outside an unstable cycle, a regime that flips along the line).
    Finding = 1,
    /// The label stands, but a check of it did not finish (a run that did not settle).
    Unconfirmed = 2,
    /// A computation failed; what it would have given is missing.
    Failure = 3,
    /// Two findings contradict each other: the point is undecided (never one of them
    /// guessed).
    Conflict = 4,
}

impl NoteKind {
    /// All kinds, in value order.
    pub const ALL: [NoteKind; 4] = [
        NoteKind::Finding,
        NoteKind::Unconfirmed,
        NoteKind::Failure,
        NoteKind::Conflict,
    ];

    /// The name in files and JSON.
    pub fn name(self) -> &'static str {
        match self {
            NoteKind::Finding => "finding",
            NoteKind::Unconfirmed => "unconfirmed",
            NoteKind::Failure => "failure",
            NoteKind::Conflict => "conflict",
        }
    }

    /// The kind of a stored value (0 is "no note").
    pub fn from_u8(v: u8) -> Option<NoteKind> {
        NoteKind::ALL.into_iter().find(|k| *k as u8 == v)
    }

    /// The flags of the stored datasets: value and name, "none" (0) first.
    pub fn flags() -> Vec<(u8, &'static str)> {
        std::iter::once((0, "none"))
            .chain(NoteKind::ALL.iter().map(|k| (*k as u8, k.name())))
            .collect()
    }
}

/// A note: its kind and its words.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Note {
    /// What it says about the result.
    pub kind: NoteKind,
    /// The words (amplitudes and times in the plan's units).
    pub text: String,
}

impl Note {
    /// A note of `kind`.
    pub fn new(kind: NoteKind, text: impl Into<String>) -> Note {
        Note {
            kind,
            text: text.into(),
        }
    }

    /// A conflict ([`NoteKind::Conflict`]).
    pub fn conflict(text: impl Into<String>) -> Note {
        Note::new(NoteKind::Conflict, text)
    }

    /// This note and `then`: the graver kind, the words joined by "; ".
    pub fn and(self, then: Note) -> Note {
        Note {
            kind: self.kind.max(then.kind),
            text: format!("{}; {}", self.text, then.text),
        }
    }

    /// `note` followed by `then`, where there is a note already.
    pub fn add(note: Option<Note>, then: Note) -> Note {
        match note {
            Some(n) => n.and(then),
            None => then,
        }
    }
}

impl std::fmt::Display for Note {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_graver_kind_wins_and_the_words_are_kept() {
        let a = Note::new(NoteKind::Finding, "the landscape says bistable");
        let c = Note::conflict("the run ends steady_slip");
        let both = Note::add(Some(a.clone()), c.clone());
        assert_eq!(both.kind, NoteKind::Conflict);
        assert_eq!(
            both.text,
            "the landscape says bistable; the run ends steady_slip"
        );
        assert_eq!(c.and(a).kind, NoteKind::Conflict);
        // The stored values round-trip, and 0 is no note.
        for k in NoteKind::ALL {
            assert_eq!(NoteKind::from_u8(k as u8), Some(k));
        }
        assert_eq!(NoteKind::from_u8(0), None);
        assert_eq!(NoteKind::flags()[0], (0, "none"));
    }
}
