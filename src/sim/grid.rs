//! The uniform grid: the "clever data structure" the collisions lesson
//! promises, so that a sphere is tested only against its neighbours.
//!
//! The box is cut into `n^3` cubic cells at least one largest diameter wide
//! ([`CellLayout`]), so two spheres that touch sit in the same cell or in
//! adjacent ones. Cells are numbered x-major (`(x n + y) n + z`): sorting the
//! slots by cell sorts them by x first, so a slab of cells one wide in x is
//! one contiguous run of slots, which the contact solver's slabs use.
//!
//! Every step the grid is rebuilt from scratch with a stable counting sort
//! over the cells, into buffers kept between steps: once warm, a build
//! allocates nothing. The sort runs in two levels so that both run in
//! parallel: by slab first (in fixed chunks of slots), then each slab by
//! cell into its own part of the cell table. The narrow phase then visits
//! each sphere's own cell and the 13 neighbour cells that come after it in
//! cell order (a half stencil: each pair is met once), as five runs of
//! consecutive cells along z, less the cells beyond the sphere's reach to
//! the largest sphere (most of the stencil, for a sphere much smaller than
//! the largest, whose diameter sizes the cells): first it notes every
//! sphere within reach
//! without a branch (in a pile one test in six passes, a branch the
//! processor cannot predict), then builds their contacts. In a crowd (16
//! or more tests a sphere at the last step) that first test runs on a
//! single-precision copy of the spheres, eight pairs at a time, with a
//! slack that lets through every pair the exact test keeps ([`Lanes`]);
//! the exact test then decides, so the contacts are the same either way.
//! It runs in parallel over the x-slabs, each
//! writing its contacts straight into its own region of the output (sized
//! from the slab's count at the previous step plus a margin; the rare slab
//! that outgrows its region makes the pass run again with regions fitted
//! to the counts), and the regions are then closed up in slab order. The
//! list comes out in one fixed order whatever the number of threads: by
//! `(i, j)` when the slots are in cell order, otherwise it is sorted.
//!
//! The grid owns its buffers and reads the bodies; it never moves a sphere
//! (large worlds move their spheres into its cell order:
//! `large/cell_order.rs`). Every parallel task writes its own part of a
//! buffer, cut out with `split_at_mut` or chunking: no unsafe code.

use super::contact::{self, Contact};
use super::threads::{GiveWay, batch_len, each_batch};
use super::{Bodies, Vec3};
use bytemuck::Zeroable;
use rayon::prelude::*;
use std::ops::Range;
use wide::{CmpLt, f32x8};

/// Cells are made this much wider than the largest diameter, so that
/// rounding in `floor(x n)` can never separate two touching spheres by more
/// than one cell.
const CELL_MARGIN: f64 = 1e-9;
/// At most this many cells per sphere (plus [`MIN_CELL_BUDGET`]): tiny
/// spheres get wider cells rather than an unbounded cell array. Spheres
/// filling a tenth of the box, as the benchmark's do, need 5.2 cells a
/// sphere for cells as narrow as their diameter; with 4, their cells were
/// a tenth wider, and a step tested a quarter more pairs (measured with
/// `lerpit bench --start dilute --awake --particles 1000000 --steps 10
/// --threads 2`: 80 instead of 91 ms a step in flight, medians of three by
/// turns, for about 5 more bytes a sphere).
const MAX_CELLS_PER_BODY: usize = 6;
const MIN_CELL_BUDGET: usize = 4096;
/// Slots per parallel task in the per-slot passes.
const SLOT_CHUNK: usize = 4096;
/// Spheres in the smallest batch of slabs ([`CellLayout::slabs_per_batch`]).
const BATCH_BODIES: usize = 1 << 16;
/// A slab's room in the output for the next step: its count plus a quarter
/// plus a few, or, when that is less, its room this step less a sixteenth.
/// In a jittering pile a few slabs' counts swing by more than a quarter
/// from one step to the next; a room that shrinks slowly holds them, where
/// one from the last count alone made every step search twice (measured:
/// 1 to 4 of the 73 slabs of 100,000 settled spheres, as cut then, over
/// their room).
const ROOM_MARGIN_DIVISOR: usize = 4;
const ROOM_MARGIN: usize = 64;
const ROOM_DECAY: usize = 16;

/// How the box `[0, 1]^3` is cut: `n` cells per axis, each `1/n` wide and
/// wider than the largest diameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellLayout {
    /// Cells per axis (at least 1).
    pub n: usize,
}

impl CellLayout {
    /// The finest layout whose cells are wider than `2 max_radius`, within
    /// the cell budget for `bodies` spheres.
    pub fn new(max_radius: f64, bodies: usize) -> Self {
        let budget = MAX_CELLS_PER_BODY * bodies + MIN_CELL_BUDGET;
        let by_budget = (budget as f64).cbrt().floor().max(1.0);
        let diameter = 2.0 * max_radius * (1.0 + CELL_MARGIN);
        let by_size = if diameter > 0.0 {
            (1.0 / diameter).floor()
        } else {
            f64::INFINITY
        };
        Self {
            n: by_size.min(by_budget).max(1.0) as usize,
        }
    }

    /// The layout for `bodies` as they are now.
    pub fn of(bodies: &Bodies) -> Self {
        Self::within(bodies, 0.0)
    }

    /// The layout for `bodies` whose cells also hold every pair closer
    /// than `margin` (m) beyond touching.
    pub(crate) fn within(bodies: &Bodies, margin: f64) -> Self {
        Self::new(bodies.max_radius() + margin / 2.0, bodies.len())
    }

    /// Slabs per parallel task for `bodies` spheres: enough that a task
    /// has a few thousand spheres to work on, so small worlds run on one
    /// thread instead of paying to wake the others.
    pub(crate) fn slabs_per_task(&self, bodies: usize) -> usize {
        (SLOT_CHUNK * self.n).div_ceil(bodies.max(1)).max(1)
    }

    /// Slabs per batch of a stage that may give way between batches
    /// (`threads::batch_len`): enough for [`BATCH_BODIES`] spheres, so that
    /// a world whose stage takes a few milliseconds runs it whole, on every
    /// thread, and only larger ones are cut.
    pub(crate) fn slabs_per_batch(&self, bodies: usize) -> usize {
        (BATCH_BODIES * self.n).div_ceil(bodies.max(1)).max(1)
    }

    pub(crate) fn cells(&self) -> usize {
        self.n * self.n * self.n
    }

    /// The cell coordinate of `x` along one axis. Centres outside the box
    /// (after integration, before the walls) fall in the edge cells; this
    /// only brings cells closer, so touching spheres stay in adjacent cells.
    #[inline]
    pub(crate) fn axis(&self, x: f64) -> usize {
        // `as` truncates toward zero and saturates (negative and NaN give
        // 0), which for the clamped result is the floor.
        ((x * self.n as f64) as usize).min(self.n - 1)
    }

    #[inline]
    pub(crate) fn coords(&self, p: Vec3) -> [usize; 3] {
        [self.axis(p.x), self.axis(p.y), self.axis(p.z)]
    }

    #[inline]
    pub(crate) fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        (x * self.n + y) * self.n + z
    }
}

/// The grid's buffers, reused from step to step.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    layout: Option<CellLayout>,
    /// Cell of each slot.
    key: Vec<u32>,
    /// `start[c]..start[c + 1]` are the positions in `order` of cell `c`.
    start: Vec<u32>,
    /// Slots sorted by cell (by slot within a cell).
    order: Vec<u32>,
    /// Per chunk of slots, per slab: how many.
    chunk_slabs: Vec<u32>,
    /// Per chunk of slots, per slab: where its slots end in the chunk's
    /// part of `by_slab`.
    chunk_slab_end: Vec<u32>,
    /// Where each slab begins in `order` (one more entry: the end).
    slab_start: Vec<u32>,
    /// Whether `order` is the identity: the slots are already in cell order.
    in_cell_order: bool,
    /// Contacts found in each x-slab.
    slab_counts: Vec<usize>,
    /// Room in the output for each slab's contacts, and where it starts.
    slab_room: Vec<usize>,
    slab_offset: Vec<usize>,
    /// Pair tests made in each x-slab.
    slab_tests: Vec<u64>,
    /// The deepest overlap each x-slab found (0 for none), m.
    slab_deepest: Vec<f64>,
    /// The deepest overlap the last narrow phase found (0 for none), m.
    deepest: f64,
    /// Contacts found and pairs tested in each x-slab, as the tasks report.
    slab_found: Vec<(usize, u64)>,
    /// Each chunk's slots sorted by slab (the first level of the sort), in
    /// the chunk's own part.
    by_slab: Vec<u32>,
    /// The spheres in single precision, in sorted order, for the narrow
    /// phase's first test in a crowd.
    lanes: Lanes,
    /// Pair tests the last narrow phase made, and for how many spheres.
    last_tests: (u64, usize),
    /// With quiet spheres (`sleeping_pairs.rs`): how many spheres are not
    /// quiet before each position of `order` (one more entry: all).
    active_before: Vec<u32>,
}

impl Grid {
    pub fn new() -> Self {
        Self::default()
    }

    /// Sort the slots of `bodies` into cells (counting sort).
    pub fn build(&mut self, bodies: &Bodies, layout: CellLayout) {
        let count = bodies.len();
        let (n, slab_cells, cells) = (layout.n, layout.n * layout.n, layout.cells());
        // A key holds the slab in its high bits and the cell within the slab
        // (`y n + z`) in the low `shift` bits: both come out with a shift
        // and a mask, and keys sort as the cells do.
        let shift = usize::BITS - (slab_cells - 1).leading_zeros();
        let mask = (1usize << shift) - 1;
        assert!(
            count < u32::MAX as usize && ((n - 1) << shift | mask) < u32::MAX as usize,
            "grid indices are 32-bit"
        );
        self.layout = Some(layout);

        // A stable counting sort of the slots by cell, in two levels so that
        // both run in parallel: first by slab (x), in fixed chunks of slots;
        // then each slab by cell, into its own part of `start` and `order`.
        // A stable sort has one result, so the chunks and the threads
        // change nothing. The keys and the chunks' slab counts come out of
        // one pass over the positions.
        let chunks = count.div_ceil(SLOT_CHUNK);
        if self.key.len() != count {
            self.key.clear();
            self.key.resize(count, 0);
        }
        self.chunk_slabs.clear();
        self.chunk_slabs.resize(chunks * n, 0);
        self.chunk_slabs
            .par_chunks_mut(n)
            .zip(self.key.par_chunks_mut(SLOT_CHUNK))
            .zip(bodies.position.par_chunks(SLOT_CHUNK))
            .for_each(|((counts, keys), positions)| {
                for (key, p) in keys.iter_mut().zip(positions) {
                    let [x, y, z] = layout.coords(*p);
                    *key = (x << shift | (y * n + z)) as u32;
                    counts[x] += 1;
                }
            });
        // Where each slab begins in `order`.
        self.slab_start.clear();
        let mut at = 0;
        for s in 0..n {
            self.slab_start.push(at);
            at += (0..chunks)
                .map(|c| self.chunk_slabs[c * n + s])
                .sum::<u32>();
        }
        self.slab_start.push(at);

        // Level one: each chunk sorts its own slots by slab, in its own part
        // of `by_slab`.
        self.by_slab.clear();
        self.by_slab.resize(count, 0);
        self.chunk_slab_end.clear();
        self.chunk_slab_end.resize(chunks * n, 0);
        self.by_slab
            .par_chunks_mut(SLOT_CHUNK)
            .zip(self.key.par_chunks(SLOT_CHUNK))
            .zip(self.chunk_slabs.par_chunks(n))
            .zip(self.chunk_slab_end.par_chunks_mut(n))
            .enumerate()
            .for_each(|(c, (((out, keys), counts), next))| {
                let mut at = 0;
                for (next, &count) in next.iter_mut().zip(counts) {
                    *next = at;
                    at += count;
                }
                for (k, &key) in keys.iter().enumerate() {
                    let next = &mut next[key as usize >> shift];
                    out[*next as usize] = (c * SLOT_CHUNK + k) as u32;
                    *next += 1;
                }
            });

        // Level two: each slab gathers its slots from the chunks in order
        // and sorts them by cell into its own part of `start` and `order`.
        if self.start.len() != cells + 1 {
            self.start.clear();
            self.start.resize(cells + 1, 0);
        }
        self.start[cells] = count as u32;
        if self.order.len() != count {
            self.order.clear();
            self.order.resize(count, 0);
        }
        let slab_orders = split_runs(&mut self.order, self.slab_start.iter().map(|&s| s as usize));
        let (key, by_slab) = (&self.key, &self.by_slab);
        let (counts, ends) = (&self.chunk_slabs, &self.chunk_slab_end);
        let slab_start = &self.slab_start;
        self.in_cell_order = self.start[..cells]
            .par_chunks_mut(slab_cells)
            .zip(slab_orders)
            .with_min_len(layout.slabs_per_task(count))
            .enumerate()
            .map(|(s, (cell_start, order))| {
                let lo = slab_start[s];
                let slots = || {
                    (0..chunks).flat_map(move |c| {
                        let (end, count) = (ends[c * n + s], counts[c * n + s]);
                        let base = c * SLOT_CHUNK;
                        &by_slab[base + (end - count) as usize..base + end as usize]
                    })
                };
                cell_start.fill(0);
                for &slot in slots() {
                    cell_start[key[slot as usize] as usize & mask] += 1;
                }
                // Each entry becomes the end of its cell; the scatter walks
                // back, so it ends at the cell's start.
                let mut end = lo;
                for c in cell_start.iter_mut() {
                    end += *c;
                    *c = end;
                }
                let mut in_order = true;
                for &slot in slots().rev() {
                    let c = &mut cell_start[key[slot as usize] as usize & mask];
                    *c -= 1;
                    order[(*c - lo) as usize] = slot;
                    in_order &= *c == slot;
                }
                in_order
            })
            .reduce(|| true, |a, b| a && b);
    }

    /// The order the spheres of `bodies` must be moved in to be in cell
    /// order (slot `k` gets the sphere in slot `order[k]`), or `None` when
    /// they already are. Needs a [`Grid::build`] of these bodies first.
    pub(crate) fn order_to_apply(&self, bodies: &Bodies) -> Option<&[u32]> {
        assert!(self.layout.is_some(), "reorder before any build");
        assert_eq!(
            self.order.len(),
            bodies.len(),
            "grid built for other bodies"
        );
        (!self.in_cell_order).then_some(&self.order[..])
    }

    /// The bodies were moved into the order [`Grid::order_to_apply`] gave:
    /// the grid stays valid for them, with slots now in cell order.
    pub(crate) fn set_in_cell_order(&mut self) {
        self.order
            .par_iter_mut()
            .with_min_len(SLOT_CHUNK)
            .enumerate()
            .for_each(|(k, o)| *o = k as u32);
        self.in_cell_order = true;
    }

    /// Into `out` (cleared): the slots of the spheres the last build
    /// sorted into the cells that the box from `lo` to `hi` reaches, cell
    /// by cell; every sphere whose centre, where the build found it, lies
    /// in the box is among them. False (and `out` empty) when the grid
    /// holds no build.
    pub(crate) fn slots_within(&self, lo: Vec3, hi: Vec3, out: &mut Vec<u32>) -> bool {
        out.clear();
        let Some(l) = self.layout else {
            return false;
        };
        let (lo, hi) = (l.coords(lo), l.coords(hi));
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                let run = self.start[l.index([x, y, lo[2]])] as usize
                    ..self.start[l.index([x, y, hi[2]]) + 1] as usize;
                if self.in_cell_order {
                    out.extend(run.map(|a| a as u32));
                } else {
                    out.extend_from_slice(&self.order[run]);
                }
            }
        }
        true
    }

    /// Where the slots of each x-slab of cells begin, and (last) where the
    /// last one ends, while the slots are in cell order: slab `s` holds the
    /// slots `slab_slots[s]..slab_slots[s + 1]`. `None` otherwise.
    pub(crate) fn slab_slots(&self) -> Option<&[u32]> {
        self.in_cell_order.then_some(&self.slab_start[..])
    }

    /// The deepest overlap the last [`Grid::find_contacts_within`] (or
    /// sweep, [`Grid::note_sweep`]) found
    /// (0 for none), m.
    pub(crate) fn deepest(&self) -> f64 {
        self.deepest
    }

    /// Whether the last narrow phase, over as many spheres, made
    /// [`CROWDED_TESTS`] tests a sphere or more: a crowd, where the first
    /// test runs in single precision.
    pub(crate) fn crowded(&self, bodies: usize) -> bool {
        self.last_tests.1 == bodies && self.last_tests.0 >= CROWDED_TESTS * bodies as u64
    }

    /// For slots in cell order ([`Grid::slab_slots`]): the half stencil
    /// over `position` and `radius` (a copy of the centres of the bodies
    /// the grid was built for, taken before any of them moves, and their
    /// radii), for a narrow phase that resolves each slab's contacts as
    /// soon as it has found them (`large/sweep.rs`). In a crowd the
    /// single-precision copy is filled from `bodies` first. Call [`Grid::note_sweep`] after.
    pub(crate) fn frozen_stencil<'a>(
        &'a mut self,
        bodies: &Bodies,
        position: &'a [Vec3],
        radius: &'a [f64],
    ) -> Stencil<'a> {
        let layout = self.layout.expect("a sweep before any build");
        assert!(
            self.in_cell_order
                && self.order.len() == bodies.len()
                && position.len() == bodies.len(),
            "a sweep needs the slots in the cell order of this build"
        );
        let slack = if self.crowded(bodies.len()) {
            self.lanes.fill(bodies, None, 0.0)
        } else {
            None
        };
        Stencil {
            layout,
            in_cell_order: true,
            start: &self.start,
            slab_start: &self.slab_start,
            order: &self.order,
            position,
            radius,
            margin: 0.0,
            max_radius: bodies.max_radius(),
            lanes: slack.map(|slack| (&self.lanes, slack)),
            quiet: None,
        }
    }

    /// A sweep over [`Grid::frozen_stencil`] made `tests` pair tests over
    /// `bodies` spheres and found `deepest` as its deepest overlap.
    pub(crate) fn note_sweep(&mut self, tests: u64, bodies: usize, deepest: f64) {
        self.last_tests = (tests, bodies);
        self.deepest = deepest;
    }

    /// Whether a narrow phase or a sweep has run over as many slabs as the
    /// last build cut, so that a sweep can list its contacts
    /// ([`Grid::sweep_regions`]).
    pub(crate) fn sized_for_sweep(&self) -> bool {
        self.layout.is_some_and(|l| self.slab_room.len() == l.n)
    }

    /// For a sweep that lists the contacts it finds (`large/sweep.rs`):
    /// `contacts` cut into each slab's region, with the room the narrow
    /// phases and sweeps before found it needs. `None` when none has run
    /// over as many slabs yet. [`Grid::close_sweep`] after.
    pub(crate) fn sweep_regions<'c>(
        &mut self,
        contacts: &'c mut Vec<Contact>,
    ) -> Option<Vec<&'c mut [Contact]>> {
        let n = self.layout.expect("a sweep before any build").n;
        (self.slab_room.len() == n)
            .then(|| cut_regions(&self.slab_room, &mut self.slab_offset, contacts))
    }

    /// A sweep found `count[s]` contacts in each slab: fit the slabs' rooms
    /// to them. With `listed`, the sweep wrote the first of them to the
    /// regions of [`Grid::sweep_regions`] and the rest, where a slab found
    /// more than its room, to `spilled[s]`: put them together in `contacts`
    /// as one list in slab order. `None` when `give_way` stopped that.
    pub(crate) fn close_sweep(
        &mut self,
        count: &[usize],
        listed: Option<(&mut Vec<Contact>, &[Vec<Contact>])>,
        give_way: &mut GiveWay,
    ) -> Option<()> {
        if self.slab_room.len() != count.len() {
            self.slab_room.clear();
            self.slab_room.resize(count.len(), 0);
        }
        fit_rooms(&mut self.slab_room, count);
        let Some((contacts, spilled)) = listed else {
            return Some(());
        };
        let total = if spilled.iter().all(Vec::is_empty) {
            close_up(contacts, &self.slab_offset, count, give_way)?
        } else {
            assemble(contacts, &self.slab_offset, count, spilled, give_way)?
        };
        contacts.truncate(total);
        Some(())
    }

    /// Fill `contacts` (cleared first) with every overlapping pair of the
    /// bodies the grid was last built for, sorted by `(i, j)`; returns the
    /// number of pair tests made.
    pub fn find_contacts(&mut self, bodies: &Bodies, contacts: &mut Vec<Contact>) -> u64 {
        let mut never = GiveWay::never();
        self.find_contacts_within(bodies, contacts, 0.0, None, &mut never)
            .expect("nothing interrupts the narrow phase")
    }

    /// As [`Grid::find_contacts`], with every pair closer than `margin` (m)
    /// beyond touching as well (`contact::test_pair_within`); the grid must
    /// have been built with [`CellLayout::within`] that margin. With
    /// `quiet` (per slot), no pair of two quiet spheres is tested or
    /// listed (`sleeping_pairs.rs`), and a quiet sphere is tested only
    /// against the runs of cells that hold a sphere that is not. The slabs
    /// are searched in batches (`threads::batch_len`); `give_way` may stop
    /// the search before any batch but the first, and then `None`, with
    /// `contacts` meaningless.
    pub(crate) fn find_contacts_within(
        &mut self,
        bodies: &Bodies,
        contacts: &mut Vec<Contact>,
        margin: f64,
        quiet: Option<&[bool]>,
        give_way: &mut GiveWay,
    ) -> Option<u64> {
        let layout = self.layout.expect("find_contacts before any build");
        assert_eq!(
            self.order.len(),
            bodies.len(),
            "grid built for other bodies"
        );
        if let Some(quiet) = quiet {
            assert_eq!(quiet.len(), bodies.len(), "one flag a sphere");
            let order = &self.order;
            let slot = |a: usize| {
                if self.in_cell_order {
                    a
                } else {
                    order[a] as usize
                }
            };
            self.active_before.clear();
            self.active_before.push(0);
            let mut active = 0;
            for a in 0..bodies.len() {
                active += u32::from(!quiet[slot(a)]);
                self.active_before.push(active);
            }
        }
        let n = layout.n;
        // In a crowd (a pile) the first test goes eight pairs at a time
        // ([`Lanes`]); spread out, a sphere has too few neighbours to fill
        // the lanes, and copying the spheres would cost more than it saves.
        // Either way the contacts are the same.
        let slack = if self.crowded(bodies.len()) {
            let order = (!self.in_cell_order).then_some(&self.order[..]);
            self.lanes.fill(bodies, order, margin)
        } else {
            None
        };
        let stencil = Stencil {
            layout,
            in_cell_order: self.in_cell_order,
            start: &self.start,
            slab_start: &self.slab_start,
            order: &self.order,
            position: &bodies.position,
            radius: &bodies.radius,
            margin,
            max_radius: bodies.max_radius(),
            lanes: slack.map(|slack| (&self.lanes, slack)),
            quiet: quiet.map(|q| (q, &self.active_before[..])),
        };

        // Each slab writes its contacts straight into its own region of the
        // output, sized from the slab's counts at the last steps plus a
        // margin; a slab that finds more only counts them, and the pass is
        // repeated with regions fitted to the counts (the first step, or a
        // sudden crowding). The regions are then closed up in slab order.
        if self.slab_room.len() != n {
            self.slab_room.clear();
            self.slab_room.resize(n, 0);
        }
        loop {
            let regions = cut_regions(&self.slab_room, &mut self.slab_offset, contacts);
            let per_task = layout.slabs_per_task(bodies.len());
            self.slab_found.clear();
            self.slab_deepest.clear();
            let (found_all, deepest_all) = (&mut self.slab_found, &mut self.slab_deepest);
            let batch = batch_len(n, layout.slabs_per_batch(bodies.len()));
            each_batch(
                regions.into_iter().enumerate(),
                batch,
                give_way,
                |regions| {
                    let (found, deepest): (Vec<_>, Vec<_>) = regions
                        .into_par_iter()
                        .with_min_len(per_task)
                        .map_init(Vec::new, |near, (s, region)| {
                            let (mut count, mut tests) = (0usize, 0u64);
                            stencil.visit_pairs(s, near, &mut tests, |c| {
                                if let Some(slot) = region.get_mut(count) {
                                    *slot = c;
                                }
                                count += 1;
                            });
                            // A slab that outgrew its room is found again
                            // in a larger one before its contacts are used.
                            let room = region.len();
                            let kept = &mut region[..count.min(room)];
                            let deepest = contact::finish_pairs(kept);
                            ((count, tests), deepest)
                        })
                        .unzip();
                    found_all.extend(found);
                    deepest_all.extend(deepest);
                },
            )?;
            self.slab_counts.clear();
            self.slab_tests.clear();
            for &(count, tests) in &self.slab_found {
                self.slab_counts.push(count);
                self.slab_tests.push(tests);
            }
            if fit_rooms(&mut self.slab_room, &self.slab_counts) {
                break;
            }
        }
        let total = close_up(contacts, &self.slab_offset, &self.slab_counts, give_way)?;
        contacts.truncate(total);
        let tests = self.slab_tests.iter().sum();
        self.last_tests = (tests, bodies.len());
        self.deepest = self.slab_deepest.iter().copied().fold(0.0, f64::max);

        if !self.in_cell_order {
            if contacts.len() < SLOT_CHUNK {
                contacts.sort_unstable_by_key(|c| (c.i, c.j));
            } else {
                contacts.par_sort_unstable_by_key(|c| (c.i, c.j));
            }
        }
        Some(tests)
    }
}

/// Cut `contacts` into each slab's region, `room[s]` entries from
/// `offset[s]` (set here), after extending it to hold them all.
///
/// The regions' entries must be set before the slabs write into them: the
/// list kept from the last step is its length, so the slack beyond it (a
/// fifth of the list) is set again, on every thread (one thread took 25 to
/// 45 ms of a step for 1,000,000 settled spheres).
fn cut_regions<'c>(
    room: &[usize],
    offset: &mut Vec<usize>,
    contacts: &'c mut Vec<Contact>,
) -> Vec<&'c mut [Contact]> {
    offset.clear();
    let mut capacity = 0;
    for &r in room {
        offset.push(capacity);
        capacity += r;
    }
    if contacts.len() < capacity {
        let more = capacity - contacts.len();
        contacts.par_extend(rayon::iter::repeat_n(Contact::zeroed(), more));
    }
    split_runs(&mut contacts[..capacity], offset.iter().copied())
}

/// Fit each slab's room to the contacts it found (`count`), with a margin,
/// shrinking slowly; whether every slab's contacts fitted the room it had.
fn fit_rooms(room: &mut [usize], count: &[usize]) -> bool {
    let fits = count.iter().zip(room.iter()).all(|(c, r)| c <= r);
    for (room, &count) in room.iter_mut().zip(count) {
        *room = (count + count / ROOM_MARGIN_DIVISOR + ROOM_MARGIN).max(*room - *room / ROOM_DECAY);
    }
    fits
}

/// Entries per parallel task when closing up runs.
const CLOSE_UP_CHUNK: usize = 1 << 14;

/// Close up the runs `v[at[k]..at[k] + count[k]]` (in order, apart) into
/// one run from `v[0]`; returns its length, or `None` when `give_way`
/// stopped it before a batch (what `v` holds is then meaningless).
///
/// Every entry moves towards the front, and the runs' shifts grow from
/// one run to the next, so the closing up goes front to back in batches:
/// what lands in `[a, a + shift)`, where `shift` is the smallest shift of
/// the entries landing from `a` on, is all read from beyond the batch's
/// end. The buffer is cut there (`split_at_mut`), and the batch's pieces
/// copy in parallel; a batch smaller than [`CLOSE_UP_CHUNK`] is copied on
/// one thread. The batches grow with the shifts, so a list of millions
/// closes up in a few dozen of them, on every thread.
fn close_up<T: Copy + Send + Sync>(
    v: &mut [T],
    at: &[usize],
    count: &[usize],
    give_way: &mut GiveWay,
) -> Option<usize> {
    let mut dest = Vec::with_capacity(count.len());
    let mut total = 0;
    for &c in count {
        dest.push(total);
        total += c;
    }
    let (mut a, mut k) = (0, 0);
    while a < total {
        while a >= dest[k] + count[k] {
            k += 1;
        }
        let shift = at[k] - dest[k];
        if shift == 0 {
            // This run is in place already.
            a = dest[k] + count[k];
            continue;
        }
        let b = (a + shift).min(total);
        if give_way.stop() {
            return None;
        }
        if b - a < CLOSE_UP_CHUNK {
            // A small batch (a small shift): one thread, no hand-off.
            let (mut pos, mut r) = (a, k);
            while pos < b {
                let end = (dest[r] + count[r]).min(b);
                let from = at[r] + (pos - dest[r]);
                v.copy_within(from..from + (end - pos), pos);
                pos = end;
                r += 1;
            }
            a = b;
            continue;
        }
        let (front, back) = v.split_at_mut(b);
        let mut pieces: Vec<(&mut [T], &[T])> = Vec::new();
        let mut out = &mut front[a..b];
        let (mut pos, mut r) = (a, k);
        while pos < b {
            let end = (dest[r] + count[r]).min(b);
            // At least `pos + shift`, so at least `b`: in `back`.
            let from = at[r] + (pos - dest[r]) - b;
            let (piece, rest) = std::mem::take(&mut out).split_at_mut(end - pos);
            out = rest;
            let source = &back[from..from + piece.len()];
            pieces.extend(
                piece
                    .chunks_mut(CLOSE_UP_CHUNK)
                    .zip(source.chunks(CLOSE_UP_CHUNK)),
            );
            pos = end;
            r += 1;
        }
        pieces
            .into_par_iter()
            .for_each(|(piece, source)| piece.copy_from_slice(source));
        a = b;
    }
    Some(total)
}

/// Entries moved between asks whether to stop in [`assemble`] (10 MB of
/// contacts).
const ASSEMBLE_BATCH: usize = 1 << 18;

/// Put runs together in order as one run from `v[0]`, as [`close_up`]
/// does, where run `k` may have outgrown its room: its first
/// `count[k] - spilled[k].len()` entries are at `v[at[k]..]`, the rest in
/// `spilled[k]`. Returns the length of the whole (`v` grows to hold it),
/// or `None` when `give_way` stopped it, asked before a run once
/// [`ASSEMBLE_BATCH`] entries have moved since it was last asked (what `v`
/// holds is then meaningless).
///
/// In place: the runs moving towards the front go first, front to back,
/// then those moving towards the back, back to front, and the spilled
/// entries last, into the gaps left for them. No run then lands on
/// entries not yet moved: a run's destination begins after every earlier
/// run's destination ends, and its source after every earlier source.
fn assemble<T: Copy + bytemuck::Zeroable>(
    v: &mut Vec<T>,
    at: &[usize],
    count: &[usize],
    spilled: &[Vec<T>],
    give_way: &mut GiveWay,
) -> Option<usize> {
    let kept: Vec<usize> = count
        .iter()
        .zip(spilled)
        .map(|(c, s)| c - s.len())
        .collect();
    let mut dest = Vec::with_capacity(count.len());
    let mut total = 0;
    for &c in count {
        dest.push(total);
        total += c;
    }
    if v.len() < total {
        v.resize(total, T::zeroed());
    }
    let forward = (0..count.len()).filter(|&k| dest[k] <= at[k]);
    let backward = (0..count.len()).rev().filter(|&k| dest[k] > at[k]);
    let mut moved = 0;
    for k in forward.chain(backward) {
        if moved >= ASSEMBLE_BATCH {
            if give_way.stop() {
                return None;
            }
            moved = 0;
        }
        v.copy_within(at[k]..at[k] + kept[k], dest[k]);
        moved += kept[k];
    }
    for (k, spill) in spilled.iter().enumerate() {
        v[dest[k] + kept[k]..dest[k] + count[k]].copy_from_slice(spill);
    }
    Some(total)
}

/// `v` cut at `starts` (ascending) into the runs `starts[k]..starts[k + 1]`,
/// the last to the end of `v`; what lies before the first start is left
/// out.
pub(crate) fn split_runs<T>(v: &mut [T], starts: impl IntoIterator<Item = usize>) -> Vec<&mut [T]> {
    let starts: Vec<usize> = starts.into_iter().collect();
    let mut runs = Vec::with_capacity(starts.len());
    let Some(&first) = starts.first() else {
        return runs;
    };
    let mut rest = &mut v[first..];
    for (k, &at) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(at + rest.len());
        let (run, tail) = std::mem::take(&mut rest).split_at_mut(end - at);
        runs.push(run);
        rest = tail;
    }
    runs
}

/// The half stencil of the narrow phase.
pub(crate) struct Stencil<'a> {
    layout: CellLayout,
    in_cell_order: bool,
    start: &'a [u32],
    slab_start: &'a [u32],
    order: &'a [u32],
    /// The centres and radii tested, by slot.
    position: &'a [Vec3],
    radius: &'a [f64],
    /// Pairs this far beyond touching count too, m.
    margin: f64,
    /// The largest of `radius`, m.
    max_radius: f64,
    /// The spheres in single precision for the first test, with what it
    /// adds to a pair's reach (`Lanes::fill`); `None`: the exact test only.
    lanes: Option<(&'a Lanes, f32)>,
    /// Which slots are quiet, and how many spheres are not before each
    /// sorted position (`Grid::active_before`): no pair of two quiet
    /// spheres is tested.
    quiet: Option<(&'a [bool], &'a [u32])>,
}

impl Stencil<'_> {
    /// Positions in `order` of cells `z0..=z1` of row `(x, y)`.
    #[inline]
    fn run(&self, x: usize, y: usize, z0: usize, z1: usize) -> Range<usize> {
        let l = &self.layout;
        self.start[l.index([x, y, z0])] as usize..self.start[l.index([x, y, z1]) + 1] as usize
    }

    /// The cells of the half stencil of `cell` along each axis (lowest and
    /// highest; along x the lowest is not used).
    #[inline]
    fn stencil_cells(&self, cell: [usize; 3]) -> [[usize; 2]; 3] {
        let last = self.layout.n - 1;
        cell.map(|c| [c.saturating_sub(1), (c + 1).min(last)])
    }

    /// The runs of the half stencil of `cell` within `bounds` (as
    /// [`Stencil::stencil_cells`] gives): the own row from the cell to its
    /// highest z (its start left for the sphere tested to set), the next
    /// row in y, and the rows of the next slab in x.
    #[inline]
    fn runs(&self, [x, y, z]: [usize; 3], bounds: [[usize; 2]; 3]) -> [Range<usize>; 5] {
        let [[_, x1], [y0, y1], [z0, z1]] = bounds;
        let mut runs: [Range<usize>; 5] = Default::default();
        runs[0] = 0..self.run(x, y, z, z1).end;
        if y1 > y {
            runs[1] = self.run(x, y1, z0, z1);
        }
        if x1 > x {
            for (r, y2) in (y0..=y1).enumerate() {
                runs[2 + r] = self.run(x1, y2, z0, z1);
            }
        }
        runs
    }

    /// The lowest and highest cell along each axis, within one of `cell`,
    /// that a sphere of radius `r` centred at `p` in `cell` may touch: a
    /// neighbour is left out only when the sphere's centre is at least its
    /// reach to the largest sphere (with the margin, and a slack far
    /// beyond rounding) from the face they share. A centre outside its
    /// cell (or not a number) never leaves out a neighbour it moved toward.
    #[inline]
    fn reach_cells(&self, cell: [usize; 3], p: Vec3, r: f64) -> [[usize; 2]; 3] {
        let n = self.layout.n;
        let width = 1.0 / n as f64;
        let reach = (r + self.max_radius + self.margin) * (1.0 + REACH_SLACK)
            + REACH_SLACK * (1.0 + p.abs().max_element());
        let mut bounds = [[0; 2]; 3];
        for ((b, c), x) in bounds.iter_mut().zip(cell).zip(p.to_array()) {
            // Out of reach only by a comparison that holds: a NaN keeps
            // the neighbour.
            let below_out = x - c as f64 * width >= reach;
            let above_out = (c + 1) as f64 * width - x >= reach;
            b[0] = if c > 0 && !below_out { c - 1 } else { c };
            b[1] = if c + 1 < n && !above_out { c + 1 } else { c };
        }
        bounds
    }

    /// Test every sphere of slab `x` against the spheres after it in its own
    /// and the next cells; `emit` each contact unfinished
    /// ([`contact::pair_within`], for [`contact::finish_pairs`] to finish
    /// many at a time), counting tests. `near` is working memory (the
    /// sorted positions of the spheres that may be within reach of the one
    /// tested), kept by each task. Contacts come out in sorted-position
    /// order of the first sphere, then of the second.
    #[inline]
    pub(crate) fn visit_pairs(
        &self,
        x: usize,
        near: &mut Vec<u32>,
        tests: &mut u64,
        mut emit: impl FnMut(Contact),
    ) {
        let emit = |i, j, d, reach| emit(contact::pair_within(i, j, d, reach));
        // Slots already in cell order need no look-up through `order`.
        if self.in_cell_order {
            self.visit_with::<true>(x, near, tests, emit)
        } else {
            self.visit_with::<false>(x, near, tests, emit)
        }
    }

    fn visit_with<const IN_CELL_ORDER: bool>(
        &self,
        x: usize,
        near: &mut Vec<u32>,
        tests: &mut u64,
        mut emit: impl FnMut(usize, usize, Vec3, f64),
    ) {
        let l = self.layout;
        let (position, radius) = (self.position, self.radius);
        // Spheres whose reach to the largest is under [`PRUNE_REACH`] of a
        // cell leave out the neighbour cells beyond it.
        let prune_below = PRUNE_REACH / l.n as f64 - self.max_radius - self.margin;
        let slot = |a: usize| {
            if IN_CELL_ORDER {
                a
            } else {
                self.order[a] as usize
            }
        };
        // Walk the slab's sorted positions cell by cell: the cell of the
        // sphere at `a` is the one the build sorted it into, so `a` starts
        // that cell's range and the empty cells between are never visited.
        let (mut next, end) = (self.slab_start[x] as usize, self.slab_start[x + 1] as usize);
        while next < end {
            let [_, y, z] = l.coords(position[slot(next)]);
            let c = l.index([x, y, z]);
            // `max`: a sphere moved since the build (a broken promise) must
            // not stall the walk.
            let own = next..(self.start[c + 1] as usize).max(next + 1);
            next = own.end;
            let cell = [x, y, z];
            let whole = self.runs(cell, self.stencil_cells(cell));
            // A cell whose spheres and neighbours are all quiet has no
            // pair to test.
            if let Some((_, active_before)) = self.quiet {
                let active = |r: &Range<usize>| active_before[r.end] - active_before[r.start];
                let mine = own.start..whole[0].end;
                if active(&mine) == 0 && whole[1..].iter().all(|r| r.is_empty() || active(r) == 0) {
                    continue;
                }
            }
            for a in own {
                let i = slot(a);
                let (pi, ri) = (position[i], radius[i]);
                // A sphere much smaller than the largest tests only the
                // neighbour cells within its reach: the cells left out hold
                // no sphere the exact test would keep, and the rest are
                // met in the same order, so the contacts are the same.
                let mut runs = if ri < prune_below {
                    self.runs(cell, self.reach_cells(cell, pi, ri))
                } else {
                    whole.clone()
                };
                // The spheres after `a` in its own run.
                runs[0].start = a + 1;
                // A quiet sphere leaves out the runs of quiet spheres only.
                let quiet_i = match self.quiet {
                    Some((quiet, active_before)) if quiet[i] => {
                        for run in runs.iter_mut() {
                            if run.start >= run.end
                                || active_before[run.end] == active_before[run.start]
                            {
                                *run = 0..0;
                            }
                        }
                        Some(quiet)
                    }
                    _ => None,
                };
                let reachable: usize = runs.iter().map(Range::len).sum();
                *tests += reachable as u64;
                if near.len() < reachable + LANES {
                    near.resize(reachable + LANES, 0);
                }
                // First every sphere that may be within reach, noted
                // without a branch: each is written, and the count moves
                // on only past those that pass (in a pile one in six,
                // which no branch predictor could foresee).
                let mut found = 0;
                if let Some((lanes, slack)) = self.lanes {
                    let lane = lanes.reach_of(a, self.margin, slack);
                    for run in &runs {
                        for from in run.clone().step_by(LANES) {
                            let mut hits = lanes.within(from, lane);
                            if run.end - from < LANES {
                                hits &= (1 << (run.end - from)) - 1;
                            }
                            // The lanes that pass, packed: eight stores
                            // that do not wait on one another.
                            let packed = &PASSING_LANES[hits as usize];
                            let at = &mut near[found..found + LANES];
                            for (to, &k) in at.iter_mut().zip(packed) {
                                *to = from as u32 + u32::from(k);
                            }
                            found += hits.count_ones() as usize;
                        }
                    }
                } else {
                    for run in &runs {
                        for b in run.clone() {
                            let j = slot(b);
                            let within = ri + radius[j] + self.margin;
                            let hit = (position[j] - pi).length_squared() < within * within;
                            near[found] = b as u32;
                            found += usize::from(hit);
                        }
                    }
                }
                // Then each by `test_pair_within`'s own comparison (its
                // operands swapped at most, which changes no bit), in the
                // order they were met, and the contact from the difference
                // of its centres taken as `test_pair_within` takes it
                // (negating the other one would turn its zeros into -0).
                for &b in &near[..found] {
                    let j = slot(b as usize);
                    let reach = ri + radius[j];
                    let within = reach + self.margin;
                    let d = if i < j {
                        position[j] - pi
                    } else {
                        pi - position[j]
                    };
                    let d2 = d.length_squared();
                    if d2 < within * within && !quiet_i.is_some_and(|q| q[j]) {
                        emit(i.min(j), i.max(j), d, reach);
                    }
                }
            }
        }
    }
}

/// Reach (to the largest sphere, as a fraction of a cell's width) under
/// which a sphere looks for the neighbour cells it can leave out: with a
/// reach near a whole cell, as among equal spheres, it could leave out
/// too few to pay for looking.
const PRUNE_REACH: f64 = 0.75;

/// What a sphere's reach to a neighbour cell's face is widened by, as a
/// fraction of the reach and of the largest coordinate (besides 1): far
/// beyond the rounding of a centre's cell or of a distance.
const REACH_SLACK: f64 = 1e-9;

/// Spheres the single-precision test takes at once.
const LANES: usize = 8;

/// For each mask of `LANES` bits, the lanes whose bit is set, in order
/// (the rest of the entry is padding, never read as a lane).
const PASSING_LANES: [[u8; LANES]; 1 << LANES] = {
    let mut table = [[0; LANES]; 1 << LANES];
    let mut mask = 0;
    while mask < 1 << LANES {
        let (mut k, mut found) = (0, 0);
        while k < LANES {
            if mask >> k & 1 == 1 {
                table[mask][found] = k as u8;
                found += 1;
            }
            k += 1;
        }
        mask += 1;
    }
    table
};

/// Largest coordinate or reach (m) the single-precision test is used for:
/// its squares stay far inside single precision's range.
const LANE_RANGE: f64 = 1e15;
/// Pair tests a sphere (at the last step) from which the narrow phase
/// tests in single precision first: with fewer the lanes run mostly empty
/// (measured: 0.4 contacts a sphere at 6 tests a sphere slower by a
/// quarter, 12 contacts at 74 tests faster by a seventh).
const CROWDED_TESTS: u64 = 16;

/// The spheres' centres and radii in single precision, one array each, in
/// the grid's sorted order and padded with `LANES` that touch nothing: the
/// narrow phase tests eight neighbours at once with them (vector
/// instructions), and only those that pass get the exact test.
#[derive(Clone, Debug, Default)]
struct Lanes {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    r: Vec<f32>,
    /// Every radius is the same: a reach is then the same for every pair
    /// of a sphere, and the test reads no radius.
    equal_radii: bool,
}

impl Lanes {
    /// Copy `bodies` in sorted order (`order`, or the slots' own order);
    /// returns the slack to add to a reach so that the rounded test passes
    /// every pair the exact one does, or `None` when some coordinate is
    /// beyond [`LANE_RANGE`] (far outside the box: single precision
    /// cannot hold it).
    ///
    /// Rounding a coordinate to single precision moves it by at most
    /// `2^-24` of the largest coordinate `P`, and the test's own arithmetic
    /// (a difference, three squares, two sums, a sum of radii) adds a few
    /// roundings of `2^-24` relative: the rounded distance and reach are
    /// within about `1e-6 (P + reach)` of the exact ones. A slack of `1e-5`
    /// times the larger of `P`, the largest reach and 1 covers that ten
    /// times over; a pair it lets through only costs the exact test.
    fn fill(&mut self, bodies: &Bodies, order: Option<&[u32]>, margin: f64) -> Option<f32> {
        let count = bodies.len();
        // Only the spheres are written: the padding stays as it was set.
        for v in [&mut self.x, &mut self.y, &mut self.z, &mut self.r] {
            if v.len() != count + LANES {
                v.clear();
                v.resize(count + LANES, f32::NAN);
            }
        }
        let (largest, equal_radii) = self
            .x
            .par_chunks_mut(SLOT_CHUNK)
            .zip(self.y.par_chunks_mut(SLOT_CHUNK))
            .zip(self.z.par_chunks_mut(SLOT_CHUNK))
            .zip(self.r.par_chunks_mut(SLOT_CHUNK))
            .enumerate()
            .map(|(c, (((x, y), z), r))| {
                let (mut largest, mut equal) = (0.0_f64, true);
                let first = c * SLOT_CHUNK;
                let radius = bodies.radius.first().map_or(0.0, |&r| r as f32);
                for a in first..count.min(first + SLOT_CHUNK) {
                    let s = order.map_or(a, |o| o[a] as usize);
                    let (p, k) = (bodies.position[s], a - first);
                    (x[k], y[k], z[k]) = (p.x as f32, p.y as f32, p.z as f32);
                    r[k] = bodies.radius[s] as f32;
                    equal &= r[k] == radius;
                    largest = largest.max(p.abs().max_element());
                }
                (largest, equal)
            })
            .reduce(|| (0.0, true), |a, b| (a.0.max(b.0), a.1 && b.1));
        self.equal_radii = equal_radii;
        let reach = 2.0 * bodies.max_radius() + margin;
        let scale = largest.max(reach).max(1.0);
        (scale < LANE_RANGE).then_some((1e-5 * scale) as f32)
    }

    /// The centre of the sphere at `a` and what its reach to another adds
    /// to that sphere's radius (its own radius, the margin and the slack),
    /// or with equal radii the square of the whole reach, each in every
    /// lane.
    #[inline]
    fn reach_of(&self, a: usize, margin: f64, slack: f32) -> [f32x8; 4] {
        let w = self.r[a] + margin as f32 + slack;
        let last = if self.equal_radii {
            let reach = self.r[a] + w;
            reach * reach
        } else {
            w
        };
        [self.x[a], self.y[a], self.z[a], last].map(f32x8::splat)
    }

    /// Which of the `LANES` spheres from `b` may be within reach of `lane`
    /// (`reach_of`): bit `k` for the sphere at `b + k`.
    #[inline]
    fn within(&self, b: usize, [x, y, z, last]: [f32x8; 4]) -> u32 {
        let at = |v: &[f32]| -> f32x8 {
            let lanes: [f32; LANES] = v[b..b + LANES].try_into().expect("padded");
            f32x8::from(lanes)
        };
        let (dx, dy, dz) = (at(&self.x) - x, at(&self.y) - y, at(&self.z) - z);
        let reach_squared = if self.equal_radii {
            last
        } else {
            let reach = at(&self.r) + last;
            reach * reach
        };
        // One bit a lane: the mask is at most `LANES` bits wide. Padding
        // (NaN) never passes.
        (dx * dx + dy * dy + dz * dz)
            .cmp_lt(reach_squared)
            .move_mask() as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn a_crowd_within_a_margin_gets_all_pairs_contacts() {
        // A heap of spheres in scene order (so the grid meets pairs from
        // either end), then in cell order, with and without the support
        // pass's margin: the second narrow phase of a grid is a crowd's
        // (single precision first), and both give exactly all-pairs'
        // list, gaps within the margin included. Mixed radii, then equal
        // ones (the first test then reads no radius), every other sphere
        // of those just inside touching the one before.
        for equal in [false, true] {
            let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
            let mut heap: Vec<crate::sim::Body> = Vec::new();
            for k in 0..600 {
                let r = if equal {
                    0.01
                } else {
                    rng.random_range(0.004..0.02)
                };
                let mut position = Vec3::new(
                    rng.random_range(-0.01..0.2),
                    rng.random_range(-0.01..0.15),
                    rng.random_range(-0.01..0.2),
                );
                if equal && k % 2 == 1 {
                    let d = (position - heap[k - 1].position).normalize();
                    position = heap[k - 1].position + d * (2.0 * r * (1.0 - 1e-12));
                }
                heap.push(crate::sim::Body {
                    position,
                    velocity: Vec3::ZERO,
                    radius: r,
                    mass: 1.0,
                });
            }
            let bodies: Bodies = heap.into_iter().collect();
            crowd_gets_all_pairs_contacts(&bodies, equal);
            // And with the slots in cell order, as a large world keeps
            // them (the narrow phase then reads no slot order).
            let mut sorted = bodies.clone();
            let mut grid = Grid::new();
            grid.build(&sorted, CellLayout::of(&sorted));
            grid.reorder_bodies(&mut sorted, &mut Vec::new());
            grid.build(&sorted, CellLayout::of(&sorted));
            assert!(grid.in_cell_order);
            crowd_gets_all_pairs_contacts(&sorted, equal);
        }
    }

    #[test]
    fn small_spheres_touching_a_large_one_across_a_face_are_found() {
        // Large spheres (the largest radius, so a small one's reach to them
        // is exactly the pair's) with small ones grazing them along an
        // axis or a diagonal, most across a cell face: the grid leaves out
        // only the neighbour cells a small sphere cannot reach, and still
        // finds every pair all-pairs does, just inside touching included.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let (large, small) = (0.02, 0.002);
        let directions = [
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::ONE.normalize(),
            Vec3::new(1.0, -1.0, 1.0).normalize(),
        ];
        let mut heap = Vec::new();
        for _ in 0..150 {
            let centre = Vec3::new(
                rng.random_range(0.05..0.95),
                rng.random_range(0.05..0.95),
                rng.random_range(0.05..0.95),
            );
            heap.push((centre, large));
            for (k, d) in directions.iter().enumerate() {
                let inside = if k % 2 == 0 { 1e-12 } else { 1e-15 };
                heap.push((centre + *d * ((large + small) * (1.0 - inside)), small));
            }
        }
        let bodies: Bodies = heap
            .into_iter()
            .map(|(position, radius)| crate::sim::Body {
                position,
                velocity: Vec3::ZERO,
                radius,
                mass: 1.0,
            })
            .collect();
        let mut expected = Vec::new();
        crate::sim::broad_phase::all_pairs(&bodies, &mut expected);
        assert!(expected.len() >= 150 * 4, "{} contacts", expected.len());
        let mut grid = Grid::new();
        grid.build(&bodies, CellLayout::of(&bodies));
        let mut found = Vec::new();
        grid.find_contacts(&bodies, &mut found);
        assert_eq!(found, expected);
    }

    fn crowd_gets_all_pairs_contacts(bodies: &Bodies, equal: bool) {
        let contact_bits = |c: &[Contact]| -> Vec<_> {
            c.iter()
                .map(|c| {
                    let n = c.contact_normal;
                    let n = [n.x, n.y, n.z].map(f64::to_bits);
                    (c.i, c.j, n, c.penetration.to_bits())
                })
                .collect()
        };
        for margin in [0.0, 1e-9, 0.003, 0.02] {
            let mut expected = Vec::new();
            crate::sim::broad_phase::all_pairs_within(bodies, &mut expected, margin);
            if margin > 1e-3 {
                assert!(expected.iter().any(|c| c.penetration < 0.0), "no gap");
            }
            if equal && margin == 0.0 {
                let grazing = expected.iter().filter(|c| c.penetration < 1e-9).count();
                assert!(grazing > 200, "{grazing} pairs just inside touching");
            }
            let mut grid = Grid::new();
            for pass in 0..2 {
                grid.build(bodies, CellLayout::within(bodies, margin));
                let mut found = Vec::new();
                let mut never = GiveWay::never();
                let tests = grid
                    .find_contacts_within(bodies, &mut found, margin, None, &mut never)
                    .expect("nothing interrupts");
                assert!(tests >= CROWDED_TESTS * 600, "{tests} tests: not a crowd");
                assert_eq!(grid.lanes.equal_radii, equal && pass == 1);
                assert_eq!(
                    contact_bits(&found),
                    contact_bits(&expected),
                    "margin {margin}, pass {pass}, equal radii {equal}"
                );
            }
        }
    }

    #[test]
    fn runs_that_outgrew_their_room_are_put_together_in_order() {
        // Runs in rooms with gaps, some keeping all their entries, some
        // spilling past their room (moving the later runs back), some
        // empty: the same list as concatenating them.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        for case in 0..2000 {
            let runs = rng.random_range(1..12);
            let (mut at, mut count, mut spilled) = (Vec::new(), Vec::new(), Vec::new());
            let mut expected: Vec<u64> = Vec::new();
            let mut v: Vec<u64> = Vec::new();
            let mut next = 1_u64;
            for _ in 0..runs {
                let room = rng.random_range(0..10);
                let c = if case % 3 == 0 {
                    rng.random_range(0..=room)
                } else {
                    rng.random_range(0..20)
                };
                let entries: Vec<u64> = (next..next + c as u64).collect();
                next += c as u64;
                expected.extend(&entries);
                at.push(v.len());
                let kept = c.min(room);
                v.extend(&entries[..kept]);
                v.extend(std::iter::repeat_n(0, room - kept));
                count.push(c);
                spilled.push(entries[kept..].to_vec());
            }
            let total = assemble(&mut v, &at, &count, &spilled, &mut GiveWay::never());
            assert_eq!(total, Some(expected.len()), "case {case}");
            let total = expected.len();
            assert_eq!(v[..total], expected[..], "case {case}");
        }
    }

    #[test]
    fn closing_up_runs_in_batches_gives_the_one_by_one_result() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let pool = crate::sim::threads::thread_pool(Some(2)).unwrap();
        for case in 0..200 {
            // Runs of up to 3 chunks each, some empty, some filling their
            // room, with gaps of up to a run's length.
            let runs = rng.random_range(1..40);
            let mut at = Vec::new();
            let mut count = Vec::new();
            let mut end = 0;
            for _ in 0..runs {
                let c = match rng.random_range(0..4) {
                    0 => 0,
                    1 => rng.random_range(0..8),
                    _ => rng.random_range(0..3 * CLOSE_UP_CHUNK),
                };
                let gap = if case % 5 == 0 {
                    0
                } else {
                    rng.random_range(0..=c + 64)
                };
                at.push(end);
                count.push(c);
                end += c + gap;
            }
            let v: Vec<u64> = (0..end as u64).collect();
            let mut expected = v.clone();
            let mut total = 0;
            for (&a, &c) in at.iter().zip(&count) {
                expected.copy_within(a..a + c, total);
                total += c;
            }
            let mut got = v.clone();
            let closed = pool.install(|| {
                let mut never = GiveWay::never();
                close_up(&mut got, &at, &count, &mut never)
            });
            assert_eq!(closed, Some(total), "case {case}");
            assert_eq!(got[..total], expected[..total], "case {case}");
        }
    }
}
