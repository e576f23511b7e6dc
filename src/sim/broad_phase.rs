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
use super::config::choice;
use super::contact::{Contact, test_pair_within};
use super::grid::{CellLayout, Grid};

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
pub(crate) const MAX_SPHERES_ALL_PAIRS: usize = 5_000;

/// The grid is refused (without `--allow-slow`) when its cells would hold
/// so many spheres that it tests at least this many pairs a sphere, and more
/// pairs in all than all-pairs at [`MAX_SPHERES_ALL_PAIRS`] spheres: one
/// large sphere sizes every cell, so a box of small ones beside it is
/// all-pairs in disguise.
pub(crate) const MAX_GRID_TESTS_PER_SPHERE: u64 = 100;

/// Pair tests the grid makes a step for `n` spheres spread evenly through
/// the box, the largest of radius `max_radius`: with `c` cells a side
/// (`CellLayout::new`), each of the `(3c - 2)^3 / 2` pairs of neighbouring
/// cells (a cell with itself counted half) meets `(n / c^3)^2` pairs of
/// spheres. At most [`all_pairs_tests`]; a pile, denser than even,
/// takes more, and spheres much smaller than the largest fewer (each
/// leaves out the neighbour cells beyond its reach).
pub fn grid_tests(n: usize, max_radius: f64) -> u64 {
    let c = CellLayout::new(max_radius, n).n as f64;
    let per_cell = n as f64 / (c * c * c);
    let estimate = (3.0 * c - 2.0).powi(3) / 2.0 * per_cell * per_cell;
    (estimate.round() as u64).min(all_pairs_tests(n))
}

/// Whether the grid, for `n` spheres the largest of radius `max_radius`,
/// tests too many pairs to run without being asked
/// ([`MAX_GRID_TESTS_PER_SPHERE`]).
pub(crate) fn grid_too_slow(n: usize, max_radius: f64) -> bool {
    let tests = grid_tests(n, max_radius);
    tests > all_pairs_tests(MAX_SPHERES_ALL_PAIRS)
        && tests > MAX_GRID_TESTS_PER_SPHERE.saturating_mul(n as u64)
}

/// Pair tests all-pairs makes a step for `n` spheres: `n (n - 1) / 2`.
pub(crate) fn all_pairs_tests(n: usize) -> u64 {
    let n = n as u64;
    n * n.saturating_sub(1) / 2
}

choice! {
    /// How the pairs to test are found.
    pub enum BroadPhase: "broad phase" {
        /// Test every pair, as the lesson does.
        AllPairs,
        /// A uniform grid of cells one largest diameter wide.
        Grid,
        /// All-pairs or the grid, by the number of spheres.
        ///
        /// All-pairs below [`AUTO_GRID_MIN_BODIES`] spheres, the grid from there.
        Auto,
    }
}

impl BroadPhase {
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
    all_pairs_within(bodies, contacts, 0.0)
}

/// As [`all_pairs`], with every pair closer than `margin` (m) beyond
/// touching as well (`contact::test_pair_within`).
pub(crate) fn all_pairs_within(bodies: &Bodies, contacts: &mut Vec<Contact>, margin: f64) -> u64 {
    all_pairs_until(bodies, contacts, margin, None, &|| false).expect("nothing interrupts it")
}

/// Pairs tested between two looks at `interrupted` in [`all_pairs_until`]:
/// a few milliseconds' work.
const TESTS_PER_LOOK: usize = 1 << 20;

/// As [`all_pairs_within`], asking `interrupted` every
/// [`TESTS_PER_LOOK`] pair tests or so; `None` when it said stop (the
/// contacts then are a part of them). With `quiet` (per slot), no pair of
/// two quiet spheres is listed (`sleeping_pairs.rs`).
pub(crate) fn all_pairs_until(
    bodies: &Bodies,
    contacts: &mut Vec<Contact>,
    margin: f64,
    quiet: Option<&[bool]>,
    interrupted: &dyn Fn() -> bool,
) -> Option<u64> {
    contacts.clear();
    let n = bodies.len();
    let mut since_look = 0;
    for i in 0..n {
        if since_look >= TESTS_PER_LOOK {
            if interrupted() {
                return None;
            }
            since_look = 0;
        }
        since_look += n - i - 1;
        let quiet_i = quiet.filter(|q| q[i]);
        for j in i + 1..n {
            if quiet_i.is_some_and(|q| q[j]) {
                continue;
            }
            if let Some(c) = test_pair_within(bodies, i, j, margin) {
                contacts.push(c);
            }
        }
    }
    Some(all_pairs_tests(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_estimate_is_all_pairs_in_one_cell_and_13_5_cells_of_neighbours_in_many() {
        // A sphere of radius 0.3 leaves one cell: every pair.
        assert_eq!(grid_tests(50_000, 0.3), all_pairs_tests(50_000));
        assert!(grid_too_slow(50_000, 0.3));
        // 100 cells a side (radius 0.00499): (298^3 / 2) (n / 10^6)^2.
        let n = 1_000_000;
        assert_eq!(CellLayout::new(0.00499, n).n, 100);
        assert_eq!(grid_tests(n, 0.00499), 298u64.pow(3) / 2);
        assert!(!grid_too_slow(n, 0.00499));
        // At or below all-pairs' own limit, never refused.
        assert!(!grid_too_slow(MAX_SPHERES_ALL_PAIRS, 0.5));
        assert!(grid_too_slow(MAX_SPHERES_ALL_PAIRS + 1, 0.5));
    }
}
