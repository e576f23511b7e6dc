//! Which pairs of spheres are tested for contact.
//!
//! The lesson checks every sphere against every other: `n (n - 1) / 2` tests
//! a step. That stays here as [`BroadPhase::AllPairs`]. [`BroadPhase::Grid`]
//! tests a sphere only against the spheres in its own and the adjacent cells
//! of a uniform grid (`grid.rs`), about a handful of tests per sphere at any
//! size. [`BroadPhase::Auto`] picks between them by the number of spheres.
//!
//! Every broad phase must report exactly the contacts all-pairs finds,
//! sorted by `(i, j)`, so the contact solver sees the same list whichever
//! one ran: switching broad phase never changes the motion.

use super::Bodies;
use super::config::{Choice, UnknownChoice, variant_array};
use super::contact::{Contact, test_pair};
use super::grid::{CellLayout, Grid};
use serde::{Deserialize, Serialize};
use strum::{EnumCount, VariantArray};

/// From this many spheres up, `auto` uses the grid; below, all-pairs.
///
/// Measured on the benchmark scene with
/// `lerpit bench --particles N --steps 2000 --threads T --broadphase all-pairs|grid`
/// for N = 10 ... 300 and T = 1, 2 (release build): all-pairs is faster up to
/// about 100 spheres (10.0 against 13.1 us a step at N = 100, one thread),
/// the two are even at about 150 (21.7 against 21.0 us), and the grid is
/// ahead from 200 up (85.8 against 51.2 us at N = 300). See the README,
/// "Performance".
pub const AUTO_GRID_MIN_BODIES: usize = 150;

/// Most spheres all-pairs is run for with pair collisions, unless asked for
/// explicitly (`--allow-slow` on the command line): 12.5 million pair tests
/// a step here, half a trillion at a million spheres.
pub const MAX_SPHERES_ALL_PAIRS: usize = 5_000;

/// Pair tests all-pairs makes a step for `n` spheres: `n (n - 1) / 2`.
pub fn all_pairs_tests(n: usize) -> u64 {
    let n = n as u64;
    n * n.saturating_sub(1) / 2
}

#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    strum::VariantArray,
    strum::EnumCount,
    strum::IntoStaticStr,
    strum::Display,
    strum::EnumString,
    strum::EnumMessage,
)]
#[strum(serialize_all = "kebab-case")]
#[serde(try_from = "String", into = "&'static str")]
pub enum BroadPhase {
    /// Test every pair, as the lesson does.
    AllPairs,
    /// A uniform grid of cells one largest diameter wide.
    Grid,
    /// All-pairs or the grid, by the number of spheres.
    ///
    /// All-pairs below [`AUTO_GRID_MIN_BODIES`] spheres, the grid from there.
    Auto,
}

impl Choice for BroadPhase {
    const KIND: &'static str = "broad phase";
}

impl TryFrom<String> for BroadPhase {
    type Error = UnknownChoice;
    fn try_from(name: String) -> Result<Self, UnknownChoice> {
        Self::parse(&name)
    }
}

impl BroadPhase {
    /// Every method, in declaration order.
    pub const ALL: [BroadPhase; BroadPhase::COUNT] = variant_array(Self::VARIANTS);

    /// The name used on the command line and in scene files.
    pub fn name(self) -> &'static str {
        Choice::name(self)
    }

    /// The next method in [`BroadPhase::ALL`], wrapping around.
    pub fn next(self) -> Self {
        Choice::next(self)
    }

    /// The method that actually runs for `bodies` spheres: `auto` resolved.
    pub fn resolve(self, bodies: usize) -> Self {
        match self {
            BroadPhase::Auto if bodies >= AUTO_GRID_MIN_BODIES => BroadPhase::Grid,
            BroadPhase::Auto => BroadPhase::AllPairs,
            other => other,
        }
    }

    /// Fill `contacts` (cleared first) with every overlapping pair, sorted by
    /// `(i, j)`; returns the number of pair tests made. Uses a fresh grid:
    /// a world keeps one and calls [`BroadPhase::find_contacts_with`].
    pub fn find_contacts(self, bodies: &Bodies, contacts: &mut Vec<Contact>) -> u64 {
        self.find_contacts_with(&mut Grid::new(), bodies, contacts)
    }

    /// As [`BroadPhase::find_contacts`], building into `grid`'s buffers.
    pub fn find_contacts_with(
        self,
        grid: &mut Grid,
        bodies: &Bodies,
        contacts: &mut Vec<Contact>,
    ) -> u64 {
        match self.resolve(bodies.len()) {
            BroadPhase::Grid => {
                grid.build(bodies, CellLayout::of(bodies));
                grid.find_contacts(bodies, contacts)
            }
            _ => all_pairs(bodies, contacts),
        }
    }
}

/// The lesson's method: every pair `i < j`, in order.
pub fn all_pairs(bodies: &Bodies, contacts: &mut Vec<Contact>) -> u64 {
    contacts.clear();
    let n = bodies.len();
    for i in 0..n {
        for j in i + 1..n {
            if let Some(c) = test_pair(bodies, i, j) {
                contacts.push(c);
            }
        }
    }
    all_pairs_tests(n)
}
