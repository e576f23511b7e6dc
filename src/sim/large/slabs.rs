//! The contact solver of large worlds: the lesson's Gauss-Seidel pass over
//! a fixed partition of the contacts into slabs, in parallel, with the same
//! bits for any number of threads.
//!
//! Cut the box along x into the slabs of the grid's [`CellLayout`] (each
//! wider than the largest diameter), give each sphere the slab of its
//! centre as the step found it, and each contact the slab of its sphere
//! `i`. When the slots are in cell order, a contact's sphere `j` lies in
//! the same slab or the next one, so the contacts of slab `s` touch only
//! the spheres of slabs `s` and `s + 1`: the consecutive slots
//! `first[s]..first[s + 2]`. The slabs of one parity therefore own
//! disjoint runs of slots, and each task gets its run as its own slices
//! (`split_at_mut`): resolving one slab cannot change what another reads.
//! The solver resolves
//!
//! 1. every even slab, in parallel, each slab's contacts (in `(i, j)`
//!    order) its four quarters in turn ([`resolve_slab`]);
//! 2. then every odd slab, in parallel, the same way.
//!
//! The result is one fixed sequence of the lesson's updates (even slabs
//! before odd ones, the quarters in turn within a slab), whichever thread
//! runs which slab. The physics of each update is the lesson's
//! ([`BodiesMut`]); only the order of the contacts differs from the
//! sequential pass, as any order is a choice. The partition depends only
//! on the state, and is checked before anything moves: if any contact
//! breaks the slab rule (slots not in cell order), the sequential pass
//! runs instead.

use crate::sim::contact::{BodiesMut, Contact, EqualMasses, Held};
use crate::sim::grid::CellLayout;
use crate::sim::restitution::Restitution;
use crate::sim::threads::{GiveWay, batch_len, each_batch};
use crate::sim::{Bodies, Vec3};
use rayon::prelude::*;
use std::ops::Range;

/// Resolve the contacts of one slab (in `(i, j)` order) as the large
/// worlds' pass does: its four quarters in turn, one contact from each
/// (the first quarter's first, the second's first, the third's, the
/// fourth's, then each one's second, ...; the last quarter has the zero
/// to three left over, resolved at the end). Each update of a pile's contact
/// waits on the one before it that moved the same sphere; the quarters of
/// a slab share few spheres, so taking them in turn lets the processor
/// work on four updates at once. Measured with `lerpit bench --start
/// settled --awake --particles 1000000 --threads 2`: 237 ms a step
/// against 253 with the two halves in turn (medians of three, by turns);
/// 100,000 spheres, 15.0 against 16.1 ms (medians of five).
#[inline(always)]
pub(super) fn resolve_slab(run: &mut BodiesMut, contacts: &[Contact], rule: Restitution) {
    // Written out rather than through a helper taking a closure: that
    // gave the same bits 8% and 13% slower (100,000 settled spheres, one
    // thread, medians of five and seven, by turns).
    let q = contacts.len() / 4;
    let (first, rest) = contacts.split_at(q);
    let (second, rest) = rest.split_at(q);
    let (third, fourth) = rest.split_at(q);
    let mut fourth = fourth.iter();
    for k in 0..q {
        run.resolve_one(&first[k], rule);
        run.resolve_one(&second[k], rule);
        run.resolve_one(&third[k], rule);
        if let Some(c) = fourth.next() {
            run.resolve_one(c, rule);
        }
    }
    for c in fourth {
        run.resolve_one(c, rule);
    }
}

/// One pass over a contact list: the lesson's resolution, or a projection
/// of the pairs still overlapping.
#[derive(Clone, Copy, Debug)]
pub(super) enum Pass {
    Solve(Restitution),
    Project(Restitution),
}

impl Pass {
    /// Run over `contacts` in order; the largest penetration a projection
    /// met (0 for the lesson's pass).
    fn run(self, bodies: &mut BodiesMut, contacts: &[Contact]) -> f64 {
        match self {
            Pass::Solve(rule) => {
                bodies.resolve(contacts, rule);
                0.0
            }
            Pass::Project(rule) => bodies.project(contacts, rule),
        }
    }

    /// Run over the contacts of one slab: the lesson's resolution in the
    /// order of [`resolve_slab`], as the sweep has it (`sweep.rs`); a
    /// projection in order.
    fn run_slab(self, bodies: &mut BodiesMut, contacts: &[Contact]) -> f64 {
        match self {
            Pass::Solve(rule) => {
                resolve_slab(bodies, contacts, rule);
                0.0
            }
            Pass::Project(_) => self.run(bodies, contacts),
        }
    }
}

/// Run `pass` over `contacts` slab by slab when they follow the slabs of
/// `layout`, else in one sequential pass. Returns the slabs used (1: the
/// sequential pass) and the largest penetration a projection pass met.
///
/// Each wave runs in batches of slabs (`threads::batch_len`); `give_way`
/// may stop the pass before any batch but its first, and then `None`:
/// some spheres have moved, others not. The slabs of a wave share nothing,
/// so batches change no bit.
pub(super) fn run_in_slabs(
    bodies: &mut Bodies,
    held: Option<Held>,
    equal: Option<EqualMasses>,
    contacts: &[Contact],
    pass: Pass,
    layout: CellLayout,
    give_way: &mut GiveWay,
) -> Option<(usize, f64)> {
    let slabs = layout.n;
    // Held spheres count as of infinite mass: the masses are not equal.
    let equal = if held.is_some() { None } else { equal };
    let Some(at) = partition(bodies, contacts, layout, give_way)? else {
        let mut whole = BodiesMut::held(bodies, held);
        whole.equal = equal;
        // A single slab is resolved as the sweep resolves it.
        let worst = if slabs < 2 {
            pass.run_slab(&mut whole, contacts)
        } else {
            pass.run(&mut whole, contacts)
        };
        return Some((1, worst));
    };
    let per_task = layout.slabs_per_task(bodies.len());
    let batch = batch_len(slabs, layout.slabs_per_batch(bodies.len()));
    let mut worst: f64 = 0.0;
    for parity in [0, 1] {
        let tasks = runs(bodies, held, equal, &at.first, parity)
            .into_iter()
            .zip((parity..slabs).step_by(2))
            .map(|(run, s)| (run, &contacts[at.contacts[s]..at.contacts[s + 1]]));
        each_batch(tasks, batch, give_way, |tasks| {
            let w = tasks
                .into_par_iter()
                .with_min_len(per_task.div_ceil(2))
                .map(|(mut run, contacts)| {
                    run.read_ahead();
                    pass.run_slab(&mut run, contacts)
                })
                .reduce(|| 0.0, f64::max);
            worst = worst.max(w);
        })?;
    }
    Some((slabs, worst))
}

/// Where each slab begins among the slots and among the contacts.
struct Partition {
    /// The slots of slab `s` are `first[s]..first[s + 1]`.
    first: Vec<usize>,
    /// The contacts of slab `s` are `contacts[s]..contacts[s + 1]`.
    contacts: Vec<usize>,
}

/// The slabs' slots and contacts, when every contact of slab `s` joins
/// spheres of slots `first[s]..first[s + 2]`; `Some(None)` otherwise (or
/// with fewer than two slabs). Both searches are plain binary searches;
/// the check is what makes the partition sound whatever they return. It
/// runs in batches of slabs, and `None` when `give_way` stopped it.
fn partition(
    bodies: &Bodies,
    contacts: &[Contact],
    layout: CellLayout,
    give_way: &mut GiveWay,
) -> Option<Option<Partition>> {
    let slabs = layout.n;
    if slabs < 2 {
        return Some(None);
    }
    let position = &bodies.position;
    let first: Vec<usize> = (0..=slabs)
        .map(|s| position.partition_point(|p| layout.axis(p.x) < s))
        .collect();
    let at: Vec<usize> = first
        .iter()
        .map(|&f| contacts.partition_point(|c| (c.i as usize) < f))
        .collect();
    let per_task = layout.slabs_per_task(bodies.len());
    let mut follows = at[0] == 0
        && at[slabs] == contacts.len()
        && first.windows(2).all(|w| w[0] <= w[1])
        && at.windows(2).all(|w| w[0] <= w[1]);
    if follows {
        each_batch(
            0..slabs,
            batch_len(slabs, layout.slabs_per_batch(bodies.len())),
            give_way,
            |batch| {
                follows = follows
                    && batch.into_par_iter().with_min_len(per_task).all(|s| {
                        let slots = first[s]..first[(s + 2).min(slabs)];
                        contacts[at[s]..at[s + 1]].iter().all(|c| {
                            slots.contains(&(c.i as usize)) && slots.contains(&(c.j as usize))
                        })
                    });
            },
        )?;
    }
    Some(follows.then_some(Partition {
        first,
        contacts: at,
    }))
}

/// The runs of slots the slabs `parity, parity + 2, ...` write: slab `s`
/// owns `first[s]..first[s + 2]` (to the end for the last slabs), cut out
/// of the arrays one after the other, so no two overlap.
/// `held`: the inverse masses to solve with, when some sphere sleeps
/// ([`BodiesMut::held`]); `equal`, the masses' sums and shares when every
/// sphere has the same mass and none is held.
fn runs<'a>(
    bodies: &'a mut Bodies,
    held: Option<Held<'a>>,
    equal: Option<EqualMasses>,
    first: &[usize],
    parity: usize,
) -> Vec<BodiesMut<'a>> {
    let Bodies {
        position,
        velocity,
        radius,
        mass,
        inverse_mass,
        ..
    } = bodies;
    let shared = Shared {
        radius,
        mass,
        inverse_mass: held.map_or(inverse_mass, |h| h.inverse_mass),
        fall: held.map_or(Vec3::ZERO, |h| h.fall),
        equal,
    };
    runs_of(position, velocity, shared, first, parity)
}

/// What every slab reads and none writes.
#[derive(Clone, Copy)]
pub(super) struct Shared<'a> {
    pub radius: &'a [f64],
    pub mass: &'a [f64],
    pub inverse_mass: &'a [f64],
    pub fall: Vec3,
    pub equal: Option<EqualMasses>,
}

/// [`runs`], from the arrays the runs write and those they share.
pub(super) fn runs_of<'a>(
    position: &'a mut [Vec3],
    velocity: &'a mut [Vec3],
    shared: Shared<'a>,
    first: &[usize],
    parity: usize,
) -> Vec<BodiesMut<'a>> {
    let slabs = first.len() - 1;
    let ranges: Vec<Range<usize>> = (parity..slabs)
        .step_by(2)
        .map(|s| first[s]..first[(s + 2).min(slabs)])
        .collect();
    let Shared {
        radius,
        mass,
        inverse_mass,
        fall,
        equal,
    } = shared;
    let mut position: &mut [Vec3] = &mut position[first[parity]..];
    let mut velocity: &mut [Vec3] = &mut velocity[first[parity]..];
    ranges
        .into_iter()
        .map(|r| {
            let (p, rest_p) = std::mem::take(&mut position).split_at_mut(r.len());
            let (v, rest_v) = std::mem::take(&mut velocity).split_at_mut(r.len());
            (position, velocity) = (rest_p, rest_v);
            BodiesMut {
                first: r.start,
                position: p,
                velocity: v,
                radius,
                mass,
                inverse_mass,
                fall,
                equal,
            }
        })
        .collect()
}
