//! The part of a [`ContactSet`] that crosses steps, for checkpoints
//! (`simulation/checkpoint.rs`): everything else in the set is rebuilt by the next step's
//! detection on the restored geometry.

use super::{Committed, ContactKey, ContactSet};
use crate::contact::law::{LawId, LawState};

/// The committed state of a contact set after a converged step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SavedContacts {
    /// Converged steps committed so far.
    pub commits: usize,
    /// Each closed contact as committed (law, state, outward normal, the branch it ended
    /// on and its record of the first iterate's predictions), sorted by key.
    pub committed: Vec<(ContactKey, Committed)>,
    /// Whether a contact with no record of its own takes its last branch at the first
    /// iterate where the predictions differ.
    pub prefer_last: bool,
    /// The states kept while their contacts are open or out of sight (broken bonds), sorted
    /// by key.
    pub lasting: Vec<(ContactKey, LawId, LawState)>,
    /// Every contact of the last committed step, open ones included, sorted.
    pub seen: Vec<ContactKey>,
}

impl ContactSet {
    /// What the next step needs of this set (sorted, so that the same state saves the
    /// same bytes).
    pub fn saved(&self) -> SavedContacts {
        let mut committed: Vec<(ContactKey, Committed)> =
            self.committed.iter().map(|(k, c)| (*k, *c)).collect();
        committed.sort_by_key(|c| c.0);
        let mut lasting: Vec<(ContactKey, LawId, LawState)> = self
            .lasting
            .iter()
            .map(|(k, (l, h))| (*k, *l, *h))
            .collect();
        lasting.sort_by_key(|c| c.0);
        let mut seen: Vec<ContactKey> = self.seen.iter().copied().collect();
        seen.sort_unstable();
        SavedContacts {
            commits: self.commits,
            committed,
            prefer_last: self.prefer_last,
            lasting,
            seen,
        }
    }

    /// Restore a saved state into a fresh set (the contacts themselves are found again by
    /// the next detection).
    pub fn restore(&mut self, s: &SavedContacts) {
        self.commits = s.commits;
        self.committed = s.committed.iter().copied().collect();
        self.prefer_last = s.prefer_last;
        self.lasting = s.lasting.iter().map(|(k, l, h)| (*k, (*l, *h))).collect();
        self.seen = s.seen.iter().copied().collect();
        self.contacts.clear();
        self.unsymmetric = 0;
        self.chosen_own = false;
        self.generation += 1;
        self.evaluated.clear();
    }
}
