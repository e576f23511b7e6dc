//! Large worlds: what lets a million spheres step in parallel. Nothing here
//! runs below [`SPATIAL_ORDER_MIN_BODIES`] spheres ([`is_large`]), so no
//! lesson meets it; the world reaches it through [`CellOrder::sort`], and
//! then the solves of the [`CellOrder`] that sort returns. The
//! support pass (`support.rs`) cuts its rows along the same slabs, from
//! the grid this sort builds.
//!
//! | file            | concept                                                         |
//! |-----------------|-----------------------------------------------------------------|
//! | `cell_order.rs` | moving spheres between slots so that neighbours in space are neighbours in memory |
//! | `slabs.rs`      | the contact solver over x-slabs of cells, in parallel, same bits for any thread count |
//! | `sweep.rs`      | the narrow phase and that solver in one sweep, listing the contacts only when the step keeps its list |
//!
//! A large world keeps its slots sorted by grid cell (x-major): each
//! sub-step sorts them again after integration, before the narrow phase.
//! The grid's narrow phase then walks memory in order, and the contacts of
//! an x-slab of cells touch only that slab and the next, which is what lets
//! the solver cut its work into independent parts. Reports and the state
//! hash go through the spheres' scene ids (`body.rs`), so the order of the
//! slots never shows.

mod cell_order;
mod slabs;
mod sweep;

use super::contact::{EqualMasses, Held};
use super::grid::{CellLayout, Grid};
use super::restitution::Restitution;
use super::threads::GiveWay;
use super::{Bodies, Contact};
use slabs::{Pass, run_in_slabs};
pub(crate) use sweep::Swept;

/// From this many spheres up (with pair collisions), the world keeps its
/// slots in cell order and solves contacts in parallel slabs. Smaller worlds,
/// every lesson among them, keep the scene order and the lesson's sequential
/// `(i, j)` pass exactly. Below a few thousand spheres the whole state fits
/// in the caches and there is too little work to share between threads.
pub const SPATIAL_ORDER_MIN_BODIES: usize = 4096;

/// Whether a world of `bodies` spheres is large: from
/// [`SPATIAL_ORDER_MIN_BODIES`] up, its slots are in cell order (not the
/// scene's) and its contacts are solved slab by slab.
pub fn is_large(bodies: usize) -> bool {
    bodies >= SPATIAL_ORDER_MIN_BODIES
}

/// A large world's slots, sorted into the cells of `layout` this sub-step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellOrder {
    layout: CellLayout,
    /// The sort moved the spheres, and the memory it was lent holds a copy
    /// of their centres in the new slots (`Grid::reorder_bodies`).
    centres_lent: bool,
    /// Every sphere has the same mass, and none is held: what the
    /// lesson's update of a pair computes from the masses, once.
    equal: Option<EqualMasses>,
}

impl CellOrder {
    /// For a world of at least [`SPATIAL_ORDER_MIN_BODIES`] spheres: build
    /// `grid` for `bodies` (cells wide enough for pairs `margin` apart) and move the spheres into its cell order. The
    /// memory of `contacts` (cleared) is lent to the move. `None` (and
    /// nothing done) for smaller worlds.
    pub(crate) fn sort(
        grid: &mut Grid,
        bodies: &mut Bodies,
        contacts: &mut Vec<Contact>,
        margin: f64,
    ) -> Option<Self> {
        if !is_large(bodies.len()) {
            return None;
        }
        let layout = CellLayout::within(bodies, margin);
        grid.build(bodies, layout);
        let masses_equal = cell_order::masses_equal(bodies);
        let centres_lent = grid.reorder_bodies_knowing(bodies, contacts, masses_equal);
        let equal = masses_equal
            .then(|| EqualMasses::of(bodies.mass[0], bodies.inverse_mass[0]))
            .flatten();
        Some(Self {
            layout,
            centres_lent,
            equal,
        })
    }

    /// The lesson's contact pass, slab by slab in parallel (`slabs.rs`),
    /// with the sleepers held still ([`Held`]) when some sphere sleeps.
    /// Returns the slabs used (1 when the contacts do not follow the slabs
    /// and the sequential pass ran instead), or `None` when `give_way`
    /// stopped it part-way, with some spheres moved.
    pub(crate) fn solve(
        self,
        bodies: &mut Bodies,
        held: Option<Held>,
        contacts: &[Contact],
        rule: Restitution,
        give_way: &mut GiveWay,
    ) -> Option<usize> {
        self.run(bodies, held, contacts, Pass::Solve(rule), give_way)
            .map(|(slabs, _)| slabs)
    }

    /// The narrow phase and the lesson's pass in one sweep, each contact
    /// resolved as it is found, with the bits of [`Grid::find_contacts`]
    /// then [`CellOrder::solve`] (`sweep.rs`); `grid` is the one
    /// [`CellOrder::sort`] built, `spare` the memory that sort was lent
    /// (it may hold the copy of the centres the sweep needs) and may use.
    /// With `list`, the contacts are also written to it as they are found,
    /// as [`Grid::find_contacts`] lists them; that needs a narrow phase or
    /// a sweep over as many slabs before ([`Grid::sized_for_sweep`]).
    /// `None` when `give_way` stopped it part-way (as [`CellOrder::solve`]).
    pub(crate) fn find_and_solve(
        self,
        grid: &mut Grid,
        bodies: &mut Bodies,
        spare: &mut Vec<Contact>,
        list: Option<&mut Vec<Contact>>,
        rule: Restitution,
        give_way: &mut GiveWay,
    ) -> Option<Swept> {
        sweep::find_and_solve(self, grid, bodies, spare, list, rule, give_way)
    }

    /// A further projection pass (`BodiesMut::project`), slab by
    /// slab in parallel; returns the largest penetration met (`None`: as
    /// [`CellOrder::solve`]).
    pub(crate) fn project(
        self,
        bodies: &mut Bodies,
        held: Option<Held>,
        contacts: &[Contact],
        rule: Restitution,
        give_way: &mut GiveWay,
    ) -> Option<f64> {
        self.run(bodies, held, contacts, Pass::Project(rule), give_way)
            .map(|(_, worst)| worst)
    }

    /// `pass` over `contacts` in the slabs of this order ([`run_in_slabs`]).
    fn run(
        self,
        bodies: &mut Bodies,
        held: Option<Held>,
        contacts: &[Contact],
        pass: Pass,
        give_way: &mut GiveWay,
    ) -> Option<(usize, f64)> {
        let (layout, equal) = (self.layout, self.equal);
        run_in_slabs(bodies, held, equal, contacts, pass, layout, give_way)
    }
}

/// The lesson's contact pass slab by slab over `layout`, as a large world
/// runs it, for any bodies (the sequential pass when the contacts do not
/// follow the slabs). Returns the slabs used.
pub fn solve_contacts_in_slabs(
    bodies: &mut Bodies,
    contacts: &[Contact],
    e: impl Into<Restitution>,
    layout: CellLayout,
) -> usize {
    let pass = Pass::Solve(e.into());
    let mut never = GiveWay::never();
    let (slabs, _) = run_in_slabs(bodies, None, None, contacts, pass, layout, &mut never)
        .expect("nothing interrupts the pass");
    slabs
}
