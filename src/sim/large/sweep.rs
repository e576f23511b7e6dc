//! The narrow phase and the lesson's pass in one sweep, for a large world
//! in which nothing reads the contacts before they are all resolved.
//!
//! The two-stage path writes every contact of the step to a list (40
//! bytes each, twenty-odd a sphere in a dense pile: most of the world's
//! memory), then reads it back slab by slab to resolve it (`slabs.rs`).
//! The sweep instead finds one slab's contacts with the grid's half
//! stencil into a buffer of its task's own and resolves them at once, in
//! the same slabs and the same waves: every even slab in parallel, then
//! every odd one. Both the test and the contact are taken from a copy of
//! the centres made before anything moves, so each contact is the one the
//! narrow phase would have listed (same normal, same penetration, same
//! bits), and the buffer holds them in `(i, j)` order, the order the
//! stencil meets pairs in when the slots are in cell order: the slab
//! solver's list of the slab, resolved in its order
//! (`slabs::resolve_slab`). The bodies therefore come out with the same
//! bits as from the two stages, for any number of threads, and each
//! thread holds one slab's contacts at a time.
//!
//! A world that keeps no list (`World::keep_contacts`) never writes it. One
//! that keeps it has each slab copy its contacts to its own region of the
//! list, sized as the narrow phase sizes it (`Grid::sweep_regions`); what
//! outgrows a region waits in a spill of the slab's own, and the regions
//! are then put together in slab order: the list of the two stages.
//!
//! A contact of slab `s` joins a sphere of slab `s` with one of slab `s`
//! or `s + 1` (the stencil looks only forward, into the next slab), so
//! each task writes only its own run of slots, as in `slabs.rs`.

use super::CellOrder;
use super::slabs::{Shared, resolve_slab, runs_of};
use crate::sim::contact::BodiesMut;
use crate::sim::grid::{Grid, Stencil};
use crate::sim::restitution::Restitution;
use crate::sim::threads::{GiveWay, batch_len, each_batch};
use crate::sim::{Bodies, Contact, Vec3};
use rayon::prelude::*;

/// What a sweep found and resolved.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Swept {
    /// Overlapping pairs found (and resolved).
    pub contacts: usize,
    /// Pairs tested.
    pub tests: u64,
    /// The deepest overlap found, before it was corrected (0 for none), m.
    pub deepest: f64,
    /// Slabs the contacts were cut into (1: a single slab, one sequence).
    pub slabs: usize,
}

impl Swept {
    fn add(self, other: Self) -> Self {
        Self {
            contacts: self.contacts + other.contacts,
            tests: self.tests + other.tests,
            deepest: self.deepest.max(other.deepest),
            slabs: self.slabs,
        }
    }
}

/// Find every overlapping pair of `bodies` (slots in the cell order of
/// `grid`'s last build, `order`) and resolve each by the lesson's update
/// with `rule` as it is found, slab by slab in two parallel waves.
/// `spare` is memory to hold the copy of the centres (it is resized to at
/// least 24 bytes a sphere; what it holds afterwards is of no use); when
/// the reorder into cell order moved the spheres, its first bytes already
/// hold that copy. With `list`, the contacts are listed in it as well,
/// which needs [`Grid::sized_for_sweep`]. `None` when `give_way` stopped
/// the sweep part-way (between batches of slabs, `threads::batch_len`):
/// some spheres have moved, others not.
pub(crate) fn find_and_solve(
    order: CellOrder,
    grid: &mut Grid,
    bodies: &mut Bodies,
    spare: &mut Vec<Contact>,
    mut list: Option<&mut Vec<Contact>>,
    rule: Restitution,
    give_way: &mut GiveWay,
) -> Option<Swept> {
    let CellOrder {
        layout,
        centres_lent: copied,
        equal,
    } = order;
    let count = bodies.len();
    let needed = (count * size_of::<Vec3>()).div_ceil(size_of::<Contact>());
    if spare.len() < needed {
        spare.resize(needed, bytemuck::Zeroable::zeroed());
    }
    let bytes: &mut [u8] = bytemuck::cast_slice_mut(spare.as_mut_slice());
    let frozen: &mut [Vec3] = bytemuck::cast_slice_mut(&mut bytes[..count * size_of::<Vec3>()]);
    if copied {
        debug_assert!(
            frozen == &bodies.position[..],
            "the copy is of these centres"
        );
    } else {
        frozen
            .par_chunks_mut(COPY_CHUNK)
            .zip(bodies.position.par_chunks(COPY_CHUNK))
            .for_each(|(to, from)| to.copy_from_slice(from));
    }
    let first: Vec<usize> = grid
        .slab_slots()
        .expect("a sweep needs the slots in cell order")
        .iter()
        .map(|&s| s as usize)
        .collect();
    let per_task = layout.slabs_per_task(count);
    let slabs = first.len() - 1;
    // Listing, each slab writes its contacts to its region of the list as
    // it resolves them, and those beyond its room to a spill of its own.
    let mut regions: Vec<Option<&mut [Contact]>> = match list.as_deref_mut() {
        Some(list) => grid
            .sweep_regions(list)
            .expect("a listing sweep after the rooms were sized")
            .into_iter()
            .map(Some)
            .collect(),
        None => (0..slabs).map(|_| None).collect(),
    };
    let mut found = vec![0; slabs];
    let mut spilled: Vec<Vec<Contact>> = (0..slabs).map(|_| Vec::new()).collect();

    let frozen: &[Vec3] = frozen;
    // The single-precision copy, when the grid fills one, is taken from
    // the bodies before they move too.
    let stencil = grid.frozen_stencil(bodies, frozen, &bodies.radius);
    let shared = Shared {
        radius: &bodies.radius,
        mass: &bodies.mass,
        inverse_mass: &bodies.inverse_mass,
        fall: Vec3::ZERO,
        equal,
    };
    let mut swept = Swept {
        slabs: slabs.max(1),
        ..Swept::default()
    };
    // Each wave runs in batches of slabs, between which the sweep may stop.
    // The slabs of a wave share nothing, so batches change no bit.
    let batch = batch_len(slabs, layout.slabs_per_batch(count));
    for parity in [0, 1] {
        let runs = runs_of(
            &mut bodies.position,
            &mut bodies.velocity,
            shared,
            &first,
            parity,
        );
        let slab_regions = (parity..slabs).step_by(2).map(|s| (s, regions[s].take()));
        let tasks = runs.into_iter().zip(slab_regions);
        each_batch(tasks, batch, give_way, |tasks| {
            let slabs_found: Vec<(usize, Swept, Vec<Contact>)> = tasks
                .into_par_iter()
                .with_min_len(per_task.div_ceil(2))
                .map_init(Default::default, |(near, all), (mut run, (s, region))| {
                    run.read_ahead();
                    let (found, spill) = sweep_slab(&stencil, s, near, all, &mut run, region, rule);
                    (s, found, spill)
                })
                .collect();
            for (s, found_in_slab, spill) in slabs_found {
                found[s] = found_in_slab.contacts;
                spilled[s] = spill;
                swept = swept.add(found_in_slab);
            }
        })?;
    }
    grid.note_sweep(swept.tests, count, swept.deepest);
    grid.close_sweep(&found, list.map(|list| (list, &spilled[..])), give_way)?;
    Some(swept)
}

/// Find the contacts of slab `s` into `all` and resolve them
/// (`find_and_solve`), copying them to `region` if given and what
/// outgrows it to the spill returned.
///
/// Compiled twice, for any x86-64 processor and for one with AVX2, and
/// chosen at run time: the same operations in the same order (Rust never
/// fuses a multiply and an add on its own), so the same bits, which the
/// test against the two stages (compiled once) checks on a processor with
/// AVX2. Measured with `lerpit bench --start settled --awake --particles
/// 1000000 --threads 2`: 165 ms a step against 196 without the AVX2
/// version (three runs each, by turns). Compiling the two-stage narrow
/// phase and the support pass's sweeps the same way changed their times
/// by under 5%.
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn sweep_slab(
    stencil: &Stencil,
    s: usize,
    near: &mut Vec<u32>,
    all: &mut Vec<Contact>,
    run: &mut BodiesMut,
    region: Option<&mut [Contact]>,
    rule: Restitution,
) -> (Swept, Vec<Contact>) {
    let mut found = Swept::default();
    all.clear();
    stencil.visit_pairs(s, near, &mut found.tests, |c| all.push(c));
    found.deepest = crate::sim::contact::finish_pairs(all);
    resolve_slab(run, all, rule);
    found.contacts = all.len();
    let mut spill = Vec::new();
    if let Some(region) = region {
        let fit = all.len().min(region.len());
        region[..fit].copy_from_slice(&all[..fit]);
        spill.extend_from_slice(&all[fit..]);
    }
    (found, spill)
}

/// Centres per parallel task when copying.
const COPY_CHUNK: usize = 4096;

#[cfg(test)]
mod tests {
    use super::super::CellOrder;
    use crate::sim::grid::Grid;
    use crate::sim::restitution::Restitution;
    use crate::sim::threads::GiveWay;
    use crate::sim::{Bodies, Body, Vec3};
    use rand::{RngExt, SeedableRng};

    #[test]
    fn a_sweep_resolves_what_the_two_stages_do_and_counts_its_crowd() {
        // A dense heap of mixed spheres, scattered over the slots: the
        // sweep against the narrow phase then the slab solver, from the
        // same cell order, and the test counts it keeps for the next
        // step's choice of the single-precision first test. From the
        // second round the sweep lists its contacts too: the list of the
        // narrow phase. Before the third the heap is squeezed, so that its
        // slabs find more contacts than the rooms the earlier rounds left
        // (spilled, then put in place).
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let n = 6000;
        let mut bodies: Bodies = (0..n)
            .map(|_| {
                let mut at = || 0.3 + 0.1 * rng.random::<f64>();
                Body {
                    position: Vec3::new(at(), at(), at()),
                    velocity: Vec3::new(at() - 0.35, at() - 0.35, at() - 0.35),
                    radius: 0.003 + 0.002 * rng.random::<f64>(),
                    mass: 1.0 + rng.random::<f64>(),
                }
            })
            .collect();
        let rule = Restitution::new(0.8, 0.0);
        let (mut grid, mut spare, mut list) = (Grid::new(), Vec::new(), Vec::new());
        let mut never = GiveWay::never();
        let (mut listed, mut listed_grid, mut contacts) = (bodies.clone(), Grid::new(), Vec::new());
        let mut last_count = 0;
        for round in 1..=4 {
            if round == 3 {
                for p in bodies.position.iter_mut().chain(&mut listed.position) {
                    *p = Vec3::splat(0.35) + (*p - Vec3::splat(0.35)) * 0.7;
                }
            }
            let order = CellOrder::sort(&mut grid, &mut bodies, &mut spare, 0.0).expect("large");
            CellOrder::sort(&mut listed_grid, &mut listed, &mut contacts, 0.0);
            // The second round on is a crowd's: both test in single
            // precision first.
            assert_eq!(grid.crowded(n), round > 1);
            assert_eq!(grid.sized_for_sweep(), round > 1);
            let tests = listed_grid.find_contacts(&listed, &mut contacts);
            let slabs = order
                .solve(&mut listed, None, &contacts, rule, &mut never)
                .expect("nothing interrupts");
            let listing = (round > 1).then_some(&mut list);
            let swept = order
                .find_and_solve(
                    &mut grid,
                    &mut bodies,
                    &mut spare,
                    listing,
                    rule,
                    &mut never,
                )
                .expect("nothing interrupts");
            assert_eq!(
                (swept.contacts, swept.tests, swept.slabs),
                (contacts.len(), tests, slabs),
                "round {round}"
            );
            assert!(
                slabs > 2 && contacts.len() > 3 * n,
                "{slabs} slabs, {} contacts",
                contacts.len()
            );
            if round > 1 {
                assert!(list == contacts, "round {round}: the listed contacts");
            }
            if round == 3 {
                assert!(
                    contacts.len() > 2 * last_count,
                    "squeezed: {} contacts after {last_count}",
                    contacts.len()
                );
            }
            last_count = contacts.len();
            assert_eq!(swept.deepest, listed_grid.deepest(), "round {round}");
            assert_eq!(bodies.position, listed.position, "round {round}");
            assert_eq!(bodies.velocity, listed.velocity, "round {round}");
            assert!(grid.crowded(n), "{} tests a sphere", tests / n as u64);
        }
    }

    #[test]
    fn a_world_of_one_slab_sweeps_as_its_two_stages_solve() {
        // One sphere wider than half the box makes the cells, and so the
        // slabs, as wide as the box: the sweep resolves its one slab in
        // the slab's order, and the two stages must too.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let mut bodies: Bodies = (0..5000)
            .map(|_| {
                let mut at = || 0.1 + 0.8 * rng.random::<f64>();
                Body {
                    position: Vec3::new(at(), at(), at()),
                    velocity: Vec3::new(at() - 0.5, at() - 0.5, at() - 0.5),
                    radius: 0.02,
                    mass: 1.0,
                }
            })
            .collect();
        bodies.push(Body {
            position: Vec3::splat(0.5),
            velocity: Vec3::ZERO,
            radius: 0.3,
            mass: 1.0,
        });
        let rule = Restitution::new(0.8, 0.0);
        let mut listed = bodies.clone();
        let (mut grid, mut spare) = (Grid::new(), Vec::new());
        let (mut listed_grid, mut contacts) = (Grid::new(), Vec::new());
        let mut never = GiveWay::never();
        let order = CellOrder::sort(&mut grid, &mut bodies, &mut spare, 0.0).expect("large");
        CellOrder::sort(&mut listed_grid, &mut listed, &mut contacts, 0.0);
        listed_grid.find_contacts(&listed, &mut contacts);
        let slabs = order
            .solve(&mut listed, None, &contacts, rule, &mut never)
            .expect("nothing interrupts");
        let swept = order
            .find_and_solve(&mut grid, &mut bodies, &mut spare, None, rule, &mut never)
            .expect("nothing interrupts");
        assert_eq!((slabs, swept.slabs), (1, 1), "one slab");
        assert!(contacts.len() > 100, "{} contacts", contacts.len());
        assert_eq!(swept.contacts, contacts.len());
        assert_eq!(bodies.position, listed.position);
        assert_eq!(bodies.velocity, listed.velocity);
    }
}
