//! Which pairs of spheres are tested for contact.
//!
//! The lesson checks every sphere against every other: `n (n - 1) / 2` tests
//! a step. That stays here as [`BroadPhase::AllPairs`]. Every broad phase
//! must report exactly the contacts all-pairs finds, sorted by `(i, j)`, so
//! the contact solver sees the same list whichever one ran.

use super::Bodies;
use super::contact::{Contact, test_pair};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BroadPhase {
    /// Test every pair, as the lesson does.
    AllPairs,
}

impl BroadPhase {
    pub const ALL: [BroadPhase; 1] = [BroadPhase::AllPairs];

    pub fn name(self) -> &'static str {
        match self {
            BroadPhase::AllPairs => "all-pairs",
        }
    }

    /// Fill `contacts` (cleared first) with every overlapping pair, sorted by
    /// `(i, j)`; returns the number of pair tests made.
    pub fn find_contacts(self, bodies: &Bodies, contacts: &mut Vec<Contact>) -> u64 {
        contacts.clear();
        match self {
            BroadPhase::AllPairs => all_pairs(bodies, contacts),
        }
    }
}

fn all_pairs(bodies: &Bodies, contacts: &mut Vec<Contact>) -> u64 {
    let n = bodies.len();
    for i in 0..n {
        for j in i + 1..n {
            if let Some(c) = test_pair(bodies, i, j) {
                contacts.push(c);
            }
        }
    }
    (n as u64) * (n as u64).saturating_sub(1) / 2
}
