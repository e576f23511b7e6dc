//! Support: how a pile carries its weight. Every resting contact of the
//! step, between spheres and against the walls, solved together at the
//! velocity level.
//!
//! The lesson's pass resolves each contact once, splitting the correction
//! by inverse mass, and changes velocities only along each normal in turn.
//! In a pile that cannot carry weight. Every step gravity moves each sphere
//! `g dt^2` down (a quarter of a radius at dt = 1/60 s for the benchmark's
//! 20,000 spheres); the floor lifts the bottom layer back, but the layers
//! above are lifted one step late, each sphere keeps a falling velocity its
//! supports should have taken, and the pile jitters, compressed.
//!
//! After the lesson's pass and the walls, the support pass takes every pair
//! the narrow phase found overlapping or within [`Support::margin`] of
//! touching (taken where the spheres are now), and every sphere now within
//! the margin of a wall, as one row each (but a pair still apart, or a
//! sphere short of its wall, that closes faster than the margin in a step:
//! an impact to come, which the lesson's rules resolve with `e` or `c_r`
//! when it meets), and solves them all at once, as contact solvers do
//! (Catto's sequential impulses, in the order of Box2D's soft step):
//!
//! 0. *bounce*: a pair the narrow phase found apart, so that the lesson's
//!    pass did not resolve it, but which that pass then struck together
//!    (a sphere hit into its neighbour) as fast as an impact, has its
//!    normal speeds set first by the lesson's velocity rule, with `e`:
//!    held as a resting contact it would lose its approach. Its overlap
//!    is then pushed out as an older one is. (A pair the lesson's pass
//!    resolved that a later contact or a wall sends back together is held
//!    as before: bouncing those too, by the lesson's rule, keeps a deep
//!    pile boiling, as the lesson's one pass does);
//! 1. *solve*: projected Gauss-Seidel sweeps over the rows, lowest first
//!    (the lower half's and the upper half's in turn), each row an impulse
//!    along its normal, accumulated and never pulling (`>= 0`), split by
//!    inverse mass between its two spheres (a wall takes its share whole). A
//!    row's target is the normal speed that leaves the pair, at the end of the
//!    step, overlapping by [`RESTING_OVERLAP`] of its reach: for a pair apart,
//!    a speed that closes at most the gap (speculative contact); for a pair
//!    the step's motion pushed together, the speed that undoes it; an overlap
//!    older than the step is pushed out by at most [`PUSH_OUT`] `g dt^2` a
//!    step, so a pile jammed into itself comes apart over a few steps instead
//!    of bursting;
//! 2. *integrate positions*: each sphere moves by the change of its
//!    velocity times `dt`, so that it ends where its new velocity would
//!    have taken it;
//! 3. *relax*: sweeps again ([`RELAX_SWEEPS`], half the solve's), with
//!    the target of a touching row now 0 (no approach, no separation), so
//!    that the speed used to push an old overlap out is not kept;
//! 4. *a last look from the floor up*: what the sweeps left of a sphere's
//!    velocity into the spheres below it that it touches, or into a wall,
//!    beyond what their own motion away makes room for, is taken away, and
//!    the sphere moves by that change times `dt`. A sphere follows a
//!    support that falls away, but a support that rises does not lift it.
//!
//! Rows whose normal is within 60 degrees of the vertical start from the
//! impulse they ended the last step with (warm starting, [`CARRY_TILT`]):
//! a stack's rows carry its weight from the first sweep, so a column of
//! ten stands still, where sweeps from nothing leave it pressed together.
//!
//! The rows push their two spheres by equal and opposite impulses, and the
//! last look, one way, only takes speed away: the pass moves a sphere as
//! its velocity says (and a sphere it would move past a wall stops at it). A sphere at rest on others comes to rest again after
//! gravity's step: the solve takes back the `g dt` gravity gave it and the
//! `g dt^2` it sank, and the relax leaves no speed. The one lift the relax
//! does not pay for is the push out of an overlap older than the step, at
//! most [`PUSH_OUT`] `g dt^2` a step, and such an overlap is what an
//! earlier step's fall left: so a held pile neither heats nor sinks, and
//! what the sweeps have not converged is left as overlap, which the next
//! steps push out.
//!
//! Resting pairs (slower than the resting window along their normal) are
//! left to this pass by the lesson's pass; every faster impact keeps the
//! lesson's rules. The sweeps stop early once no row changes a normal
//! speed by more than [`Support::speed_tolerance`]; a row they leave short
//! of its target by more than [`UNSETTLED`] of a radius in the step leaves
//! its spheres counted unsettled.
//!
//! The rows are sorted in one order: by height, then slot; in a large world
//! (`large/`), whose slots are in the grid's cell order, by x-slab of cells
//! first, each sweep solving the even slabs in parallel, then the odd ones
//! ([`SlabRows`]). A sweep takes the rows of the list (of a slab) from its
//! lower and its upper half in turn ([`sweep`]). Either way the result is
//! the same for any number of threads, and for either broad phase, which
//! find the same pairs in the same order. The last look from the floor up
//! runs on one thread.
//!
//! The pass runs when the world asks for it (`WorldConfig::support`, the
//! flag `--support`, the scene key `support = true`, the key `Y` in the
//! visualiser) with resting contact on (`rest_steps > 0`), under gravity, in
//! scenes with pair collisions, for the discrete methods.

use super::contact::{BodiesMut, Contact, in_turns};
use super::grid::split_runs;
use super::restitution::Restitution;
use super::sleep::is_asleep;
use super::threads::GiveWay;
use super::{Vec3, WorldConfig};
use rayon::prelude::*;

/// The overlap the support pass leaves between resting spheres, as a
/// fraction of the pair's reach `r_i + r_j`: far below any overlap a
/// learner can see, far above rounding, so the pair stays in contact.
pub const RESTING_OVERLAP: f64 = 1e-4;

/// A row the solve's sweeps leave closing faster than its target, so that
/// its pair ends more than this fraction of a radius deeper than the
/// resting overlap, leaves its spheres unsettled: the sweeps ran out.
pub const UNSETTLED: f64 = 0.01;

/// Sweeps of the solve, and of the relax. The relax must take back the
/// speed the solve gave to push old overlaps out, or what it leaves of
/// that speed is kept: with 4 sweeps a pile of 10,000 or 20,000 of the
/// benchmark's spheres (at dt = 1/60 s) kept boiling, with over 5 J of
/// kinetic energy 4 s after spawning, and over 0.05 J until 5 to 9 s,
/// where with 8 it is still (under 0.05 J) 2 s after spawning.
pub const SOLVE_SWEEPS: usize = 16;
pub const RELAX_SWEEPS: usize = 8;

/// An overlap older than the step is pushed out by at most this many times
/// `g dt^2` a step: faster than gravity presses a pile together, slow
/// enough that one sphere jammed into another does not throw its
/// neighbours into a third.
pub const PUSH_OUT: f64 = 4.0;

/// Rows whose normal is within 60 degrees of the vertical (`|n . up|` at
/// least this) start each step from the impulse they ended the last one
/// with (warm starting), so that a stack carries its weight from the first
/// sweep. Rows nearer the horizontal start from nothing: in a pile without
/// friction they carry the sideways pressure from wall to wall, which
/// shifts as the pile settles, and carried over it throws spheres about.
pub const CARRY_TILT: f64 = 0.5;

/// Sweeps over one sphere's supports in the last look from the floor up.
const SHOCK_SWEEPS: usize = 4;

/// What the support pass needs to know about the step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Support {
    /// Unit vector against gravity: rows are swept from the lowest up.
    pub up: Vec3,
    /// Pairs this far (m) beyond touching are listed for the pass, and
    /// spheres this far from a wall: the distance the speed of the resting
    /// window carries a sphere in a sub-step, `(rest_steps + 1) |g| h^2`,
    /// but no more than the smallest radius. Beyond that (a strong gravity
    /// or a long step) every sphere would be near every other, and the
    /// rows would grow as the square of the spheres.
    pub margin: f64,
    /// The speed of approach from which a row is an impact, not a resting
    /// contact: the speed of the resting window, `(rest_steps + 1) |g| h`,
    /// m/s.
    impact: f64,
    /// The sweeps stop once no row changes a normal speed by more than
    /// this, m/s: a thousandth of the speed gravity adds in a sub-step.
    pub speed_tolerance: f64,
    /// The farthest an old overlap is pushed out in a sub-step,
    /// [`PUSH_OUT`] `|g| h^2`, m.
    pub push_out: f64,
    /// The sub-step, s.
    pub h: f64,
    /// The restitution of pair impacts, with the rest threshold (for the
    /// impacts the pass resolves, [`BodiesMut::bounce`]).
    pub pair: Restitution,
}

impl Support {
    /// The support pass for a discrete sub-step of `h` s of `config`, in a
    /// world whose smallest radius is `smallest()` (m, asked for only when
    /// the pass runs); `None` when it is off or idle
    /// (`WorldConfig::support_idle`).
    pub(crate) fn of(config: &WorldConfig, h: f64, smallest: impl FnOnce() -> f64) -> Option<Self> {
        let g = config.gravity_strength();
        let on = config.support_runs();
        let impact = (config.rest_steps + 1.0) * g * h;
        on.then(|| Support {
            up: -config.gravity / g,
            margin: (impact * h).min(smallest()),
            impact,
            speed_tolerance: 1e-3 * g * h,
            push_out: PUSH_OUT * g * h * h,
            h,
            pair: config.pair_rule(),
        })
    }

    /// The speed of approach from which a row is an impact, not a resting
    /// contact, m/s.
    pub(crate) fn impact(&self) -> f64 {
        self.impact
    }
}

/// What a support pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct HoldCount {
    /// Spheres whose velocity it changed.
    pub held: usize,
    /// Spheres of a row the solve's sweeps left short of its target by
    /// more than [`UNSETTLED`] of a radius in the step: they ran out.
    pub unsettled: usize,
    /// Slabs its sweeps ran in (1: one sequence; [`SlabRows`]).
    pub slabs: usize,
}

/// A sphere held in the last look from the floor up: its height, its
/// slot, what holds it (a slot, or [`WALL`] and a wall) and the normal
/// pointing from that to it.
type Hold = (f64, u32, u32, Vec3);

/// The name of the row of spheres `i` and `j` (scene indices).
fn pair_key(i: u32, j: u32) -> u64 {
    (u64::from(i.min(j)) << 32) | u64::from(i.max(j))
}

/// The entries of `carried` whose rows are the sleepers' own (`sleep.rs`:
/// a pair of sleepers, or a sleeper and a wall), which the pass does not
/// build; none without sleepers. A row of a sleeper and a sphere awake is
/// built, and carries its impulse itself. `ids` and `rest`: each slot's
/// scene index and time at rest.
fn sleepers_impulses(ids: &[u32], rest: &[f32], carried: &[(u64, f64)]) -> Vec<(u64, f64)> {
    if carried.is_empty() || !rest.iter().any(|&r| is_asleep(r)) {
        return Vec::new();
    }
    let mut asleep = vec![false; ids.len()];
    for (&id, &r) in ids.iter().zip(rest) {
        asleep[id as usize] = is_asleep(r);
    }
    let sleeps = |k: u64| asleep.get(k as usize).copied().unwrap_or(false);
    carried
        .iter()
        .filter(|&&(key, _)| {
            let other = key & u64::from(u32::MAX);
            sleeps(key >> 32) && (other & u64::from(WALL) != 0 || sleeps(other))
        })
        .copied()
        .collect()
}

/// The entries of `a` and `b`, each sorted by key, in one list sorted by
/// key.
fn merge_by_key(a: &[(u64, f64)], b: &[(u64, f64)]) -> Vec<(u64, f64)> {
    let mut merged = Vec::with_capacity(a.len() + b.len());
    let (mut a, mut b) = (a.iter().peekable(), b.iter().peekable());
    while let (Some(x), Some(y)) = (a.peek(), b.peek()) {
        merged.push(if x.0 <= y.0 {
            *a.next().expect("peeked")
        } else {
            *b.next().expect("peeked")
        });
    }
    merged.extend(a.chain(b));
    merged
}

/// A row's other side: a sphere's slot, or a wall.
const WALL: u32 = 1 << 31;

/// One resting contact: sphere `a` against sphere `b` (a slot) or, with
/// [`WALL`] set, against wall `b & 7` (`2 axis + 1` for the wall at 1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Row {
    /// Height along `up` of the lower centre (of the sphere's lowest
    /// point, for the floor), for the order of the sweeps.
    height: f64,
    a: u32,
    b: u32,
    /// Unit normal from `b` to `a`.
    n: Vec3,
    /// `w_a + w_b`, the inverse masses (`w_a` against a wall).
    w: f64,
    /// The gap along `n` where the pass found the row (negative: an
    /// overlap), beyond the resting overlap for a pair, m.
    gap: f64,
    /// The normal speed `(v_a - v_b) . n` where the pass found the row.
    u: f64,
    /// The row's name from one step to the next: the two scene indices,
    /// lower first, or the scene index and the wall.
    key: u64,
    /// The x-slab of cells of its lower slot in a large world, as the
    /// grid was built this sub-step (see [`SlabRows`]); 0 otherwise.
    slab: u32,
    /// A pair the narrow phase found apart, so that the lesson's pass did
    /// not resolve it (false for a wall).
    found_apart: bool,
}

/// What the sweeps read and write of a [`Row`], in a list of its own in
/// the rows' order: a sweep over the rows of a large world, which outgrow
/// the processor's caches, then streams 64 bytes a row, not the whole row.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Constraint {
    /// The row's normal.
    n: Vec3,
    /// The row's `a` and `b`.
    a: u32,
    b: u32,
    /// `1 / w`: the impulse that changes the row's normal speed by 1 m/s
    /// (Box2D's normal mass), kg. The sweeps multiply by it, so that no
    /// division waits on the velocities.
    mass: f64,
    /// The row's `w`.
    w: f64,
    /// The normal speed the sweeps aim at.
    target: f64,
    /// The impulse accumulated along `n`, kg m/s, at least 0.
    impulse: f64,
}

const _: () = assert!(size_of::<Constraint>() == 64, "a constraint is 64 bytes");

impl Constraint {
    /// `row`'s, aiming at the normal speed `target`, with no impulse yet.
    fn of(row: &Row, target: f64) -> Self {
        Self {
            n: row.n,
            a: row.a,
            b: row.b,
            mass: 1.0 / row.w,
            w: row.w,
            target,
            impulse: 0.0,
        }
    }
}

/// The rows of a large world cut along x into the slabs of its grid, so
/// that the sweeps run in parallel with the same bits for any number of
/// threads (as the contact solver does, `large/slabs.rs`). The slots are
/// in cell order, and the rows sorted by slab (then height): a row of slab
/// `s` joins spheres of slots `slot[s]..slot[s + 2]`, so each sweep
/// solves every even slab, in parallel, then every odd one, and no two
/// slabs solved together share a sphere.
struct SlabRows<'a> {
    /// Slab `s` holds the slots `slot[s]..slot[s + 1]` (of the world, as
    /// the rows' slots are counted from the run's first).
    slot: &'a [u32],
    /// Slab `s`'s rows are `rows[at[s]..at[s + 1]]`.
    at: Vec<usize>,
}

impl<'a> SlabRows<'a> {
    /// The slabs of `rows` (sorted by slab) of a run of `len` slots from
    /// slot `first`, when the slabs cover the run and every row keeps to
    /// its slab and the next; `None` otherwise (the sweeps then run in one
    /// sequence).
    fn of(slot: &'a [u32], first: usize, len: usize, rows: &[Row]) -> Option<Self> {
        let slabs = slot.len().checked_sub(1).filter(|&s| s >= 2)?;
        if slot[0] as usize != first || slot[slabs] as usize != first + len {
            return None;
        }
        let at: Vec<usize> = (0..=slabs)
            .map(|s| rows.partition_point(|r| (r.slab as usize) < s))
            .collect();
        let keeps = (0..slabs).all(|s| {
            let slots = slot[s] as usize..slot[(s + 2).min(slabs)] as usize;
            rows[at[s]..at[s + 1]].iter().all(|r| {
                slots.contains(&(r.a as usize + first))
                    && (r.b & WALL != 0 || slots.contains(&(r.b as usize + first)))
            })
        });
        (keeps && at[slabs] == rows.len()).then_some(Self { slot, at })
    }
}

/// The impulses the support pass carries from one step to the next: those
/// its rows near the vertical (see [`CARRY_TILT`]) ended the last step
/// with, by [`Row::key`], sorted, and the pass that made them. Part of the
/// world's state (the only part that is not the bodies): a copy of a world,
/// a step back and the state hash carry them. A pass with other settings
/// (another dt, gravity or resting window) starts from nothing, and so
/// does a step that did not run the pass.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CarriedImpulses {
    made_by: Option<Support>,
    impulses: Vec<(u64, f64)>,
}

impl CarriedImpulses {
    /// How many rows carry an impulse.
    pub fn len(&self) -> usize {
        self.impulses.len()
    }

    pub fn is_empty(&self) -> bool {
        self.impulses.is_empty()
    }

    /// Forget them: the next pass starts from nothing.
    pub(crate) fn clear(&mut self) {
        self.made_by = None;
        self.impulses.clear();
    }

    /// The bits, for the state hash.
    pub(crate) fn hash_into(&self, h: &mut xxhash_rust::xxh3::Xxh3) {
        for (key, impulse) in &self.impulses {
            h.update(&key.to_le_bytes());
            h.update(&impulse.to_bits().to_le_bytes());
        }
    }
}

/// The support pass's memory: the impulses it carries from one step to the
/// next, and buffers kept for their allocations.
#[derive(Clone, Debug, Default)]
pub(crate) struct SupportWork {
    pub(crate) carried: CarriedImpulses,
    rows: Vec<Row>,
    /// What the sweeps solve of each of `rows`.
    constraints: Vec<Constraint>,
    /// Each slot's velocity as the pass found it.
    velocity: Vec<Vec3>,
    /// Slots of a row the solve left short of its target.
    unsettled: Vec<bool>,
    /// The two sides of each row the solve left short of its target.
    shorts: Vec<(u32, u32)>,
    /// Slots whose velocity [`BodiesMut::bounce`] changed.
    struck: Vec<bool>,
    holds: Vec<Hold>,
    push: Vec<f64>,
    /// Where each scene index's carried impulses begin (`carry_in`).
    carried_at: Vec<u32>,
}

impl BodiesMut<'_> {
    /// The support pass over the pairs of `lists` (overlapping or within
    /// the margin) and the walls: solve, integrate positions, relax, then
    /// the last look from the floor up. `ids`: the scene index of each slot
    /// of this run, which names a row from one step to the next. `rest`:
    /// each slot's time at rest (`sleep.rs`), or empty; a sleeper gets no
    /// wall row, `lists` holds no pair of two, and while some sleep the
    /// run's inverse masses are the held ones (`contact::Held`: a
    /// sleeper's 0), so that a row moves only its sphere awake, and the
    /// last look leaves a sleeper alone. `slabs`: in a large
    /// world, where each x-slab's slots begin ([`SlabRows`]).
    /// Returns how many spheres' velocities it changed, how many its sweeps
    /// left unsettled, and the slabs they ran in; `None` when `give_way`
    /// stopped it before one of its solve or relax sweeps, with velocities
    /// (and, in the relax, positions) changed but the impulses it carries
    /// from step to step as they were.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn support(
        &mut self,
        ids: &[u32],
        rest: &[f32],
        lists: [&[Contact]; 2],
        support: Support,
        slabs: Option<&[u32]>,
        work: &mut SupportWork,
        give_way: &mut GiveWay,
    ) -> Option<HoldCount> {
        let SupportWork {
            carried,
            rows,
            constraints,
            velocity,
            unsettled,
            shorts,
            struck,
            holds,
            push,
            carried_at,
        } = work;
        // The impulses carried are the pass's own: a new `e` keeps them.
        if carried.made_by.map(|m| Support {
            pair: support.pair,
            ..m
        }) != Some(support)
        {
            carried.clear();
        }
        self.support_rows(ids, rest, lists, support, slabs, rows, true);
        // A pair still apart, or a sphere short of a wall, closing faster
        // than the margin in a step is an impact to come, not a resting
        // contact: the lesson's rules resolve it when it meets, with its
        // `e` or `c_r`. As a speculative row it would lose its approach.
        let impact = support.impact();
        self.bounce(rows, support, struck);
        let keep = |r: &Row| r.gap <= 0.0 || r.u >= -impact;
        // Rarely is there one to drop: look for it in parallel first.
        if rows
            .par_iter()
            .with_min_len(ROWS_PER_TASK)
            .any(|r| !keep(r))
        {
            rows.retain(keep);
        }
        let slabs =
            slabs.and_then(|slot| SlabRows::of(slot, self.first, self.velocity.len(), rows));
        // The rows of two sleepers, or of a sleeper and a wall, are not
        // built, but their impulses are kept for when they wake.
        let kept = sleepers_impulses(ids, rest, &carried.impulses);
        if rows.is_empty() {
            carried.impulses = kept;
            if carried.impulses.is_empty() {
                carried.clear();
            }
            return Some(HoldCount::default());
        }
        velocity.clear();
        velocity.extend_from_slice(self.velocity);
        let h = support.h;
        let large = slabs.is_some();
        let solve = |row: &Row| {
            // The overlap the step's motion made is undone whole; an
            // older one only by `push_out`.
            let need = -row.gap;
            let made = (-row.u * h).max(0.0);
            let push = if need > made {
                made + (need - made).min(support.push_out)
            } else {
                need
            };
            Constraint::of(row, row.u + push / h)
        };
        constraints.clear();
        if large {
            constraints.par_extend(rows.par_iter().with_min_len(ROWS_PER_TASK).map(solve));
        } else {
            constraints.extend(rows.iter().map(solve));
        }
        let constraints = &mut constraints[..];
        self.carry_in(rows, constraints, &carried.impulses, support.up, carried_at);
        let tolerance = support.speed_tolerance;
        let last = self.sweeps(
            constraints,
            SOLVE_SWEEPS,
            tolerance,
            slabs.as_ref(),
            give_way,
        )?;
        unsettled.clear();
        unsettled.resize(velocity.len(), false);
        if last > support.speed_tolerance {
            let now = &*self;
            let short = |c: &&Constraint| {
                (c.target - now.normal_speed(c.a, c.b, c.n)) * h
                    > UNSETTLED * now.radius[c.a as usize + now.first]
            };
            shorts.clear();
            if large {
                shorts.par_extend(
                    constraints
                        .par_iter()
                        .with_min_len(ROWS_PER_TASK)
                        .filter(short)
                        .map(|c| (c.a, c.b)),
                );
            } else {
                shorts.extend(constraints.iter().filter(short).map(|c| (c.a, c.b)));
            }
            for &(a, b) in shorts.iter() {
                unsettled[a as usize] = true;
                if b & WALL == 0 {
                    unsettled[b as usize] = true;
                }
            }
        }
        let radius = &self.radius[self.first..][..velocity.len()];
        let moved = |((x, now), (then, &r)): ((&mut Vec3, &Vec3), (&Vec3, &f64))| {
            if now != then {
                *x += (*now - *then) * h;
                *x = x.clamp(Vec3::splat(r), Vec3::splat(1.0 - r));
            }
        };
        if large {
            self.position
                .par_iter_mut()
                .zip(self.velocity.par_iter())
                .zip(velocity.par_iter().zip(radius))
                .with_min_len(ROWS_PER_TASK)
                .for_each(moved);
        } else {
            self.position
                .iter_mut()
                .zip(self.velocity.iter())
                .zip(velocity.iter().zip(radius))
                .for_each(moved);
        }
        let now = &*self;
        let relax = |(c, row): (&mut Constraint, &Row)| {
            let gap = row.gap + (now.normal_speed(c.a, c.b, c.n) - row.u) * h;
            c.target = if gap > 0.0 { -gap / h } else { 0.0 };
        };
        if large {
            constraints
                .par_iter_mut()
                .zip(rows.par_iter())
                .with_min_len(ROWS_PER_TASK)
                .for_each(relax);
        } else {
            constraints.iter_mut().zip(rows.iter()).for_each(relax);
        }
        self.sweeps(
            constraints,
            RELAX_SWEEPS,
            tolerance,
            slabs.as_ref(),
            give_way,
        )?;
        carried.made_by = Some(support);
        carried.impulses.clear();
        let carry = |(r, c): (&Row, &Constraint)| {
            (c.impulse > 0.0 && c.n.dot(support.up).abs() >= CARRY_TILT)
                .then_some((r.key, c.impulse))
        };
        if large {
            carried.impulses.par_extend(
                rows.par_iter()
                    .zip(constraints.par_iter())
                    .with_min_len(ROWS_PER_TASK)
                    .filter_map(carry),
            );
        } else {
            carried
                .impulses
                .extend(rows.iter().zip(constraints.iter()).filter_map(carry));
        }
        if large {
            carried.impulses.par_sort_unstable_by_key(|c| c.0);
        } else {
            carried.impulses.sort_unstable_by_key(|c| c.0);
        }
        // The sleepers' own, already in order (and no row's key among
        // them), merged in: with a pile asleep, most of the entries.
        if !kept.is_empty() {
            carried.impulses = merge_by_key(&carried.impulses, &kept);
        }
        self.shock(rows, rest, support, holds, push, large);
        Some(HoldCount {
            held: velocity
                .iter()
                .zip(self.velocity.iter())
                .filter(|(a, b)| a != b)
                .count(),
            unsettled: unsettled.iter().filter(|&&u| u).count(),
            slabs: slabs.map_or(1, |s| s.at.len() - 1),
        })
    }

    /// The rows of the pass, sorted ([`sort_rows`]): every pair of `lists`
    /// and every sphere within the margin of a wall, with `slabs` (a large
    /// world's slab starts) each row's slab. With `by_slab`, a large world
    /// whose lists follow its slots (as both broad phases list them there)
    /// builds and sorts each slab's rows in their own part of `rows`, in
    /// parallel, which gives the order that sorting them all together
    /// gives (tested).
    #[allow(clippy::too_many_arguments)]
    fn support_rows(
        &self,
        ids: &[u32],
        rest: &[f32],
        lists: [&[Contact]; 2],
        support: Support,
        slabs: Option<&[u32]>,
        rows: &mut Vec<Row>,
        by_slab: bool,
    ) {
        // The slab of a slot, in a large world.
        let slab_of = |k: usize| {
            slabs.map_or(0, |slot| {
                (slot.partition_point(|&s| s as usize <= k + self.first) - 1) as u32
            })
        };
        let (first, up) = (self.first, support.up);
        let pair_row = |c: &Contact, slab: u32| {
            let (a, b) = (c.i as usize - first, c.j as usize - first);
            let d = self.position[a] - self.position[b];
            let dist = d.length();
            let n = if dist > 0.0 { d / dist } else { up };
            let reach = self.radius[c.i as usize] + self.radius[c.j as usize];
            let w = self.inverse_mass[c.i as usize] + self.inverse_mass[c.j as usize];
            Row {
                height: self.position[a].dot(up).min(self.position[b].dot(up)),
                a: a as u32,
                b: b as u32,
                n,
                w,
                gap: dist - reach * (1.0 - RESTING_OVERLAP),
                u: (self.velocity[a] - self.velocity[b]).dot(n),
                key: pair_key(ids[a], ids[b]),
                slab,
                found_apart: c.penetration <= 0.0,
            }
        };
        // The walls within the margin of slot `k`, each as `(axis, high,
        // gap)`.
        let walls = |k: usize| {
            let asleep = rest.get(k).is_some_and(|&r| is_asleep(r));
            let (x, r) = (self.position[k], self.radius[k + first]);
            (0..3)
                .flat_map(|axis| [(axis, false), (axis, true)])
                .filter_map(move |(axis, high)| {
                    let gap = if high { 1.0 - r - x[axis] } else { x[axis] - r };
                    (!asleep && gap <= support.margin).then_some((axis, high, gap))
                })
        };
        let wall_row = |k: usize, (axis, high, gap): (usize, bool, f64), slab: u32| {
            let (x, r) = (self.position[k], self.radius[k + first]);
            let mut n = Vec3::ZERO;
            n[axis] = if high { -1.0 } else { 1.0 };
            let wall = WALL | (2 * axis + usize::from(high)) as u32;
            Row {
                height: (x - n * r).dot(up),
                a: k as u32,
                b: wall,
                n,
                w: self.inverse_mass[k + first],
                gap,
                u: self.velocity[k].dot(n),
                key: (u64::from(ids[k]) << 32) | u64::from(wall),
                slab,
                found_apart: false,
            }
        };
        let len = self.position.len();
        if let Some(slot) = slabs.filter(|slot| {
            by_slab
                && slot.len() >= 2
                && slot[0] as usize == first
                && slot[slot.len() - 1] as usize == first + len
                && lists.iter().all(|l| follows_slots(l))
        }) {
            let count = slot.len() - 1;
            // Where each slab's pairs begin in each list, and how many
            // walls each slab's spheres are near.
            let cut = |list: &[Contact], s: usize| list.partition_point(|c| c.i.min(c.j) < slot[s]);
            let cuts: Vec<[usize; 2]> = (0..=count)
                .map(|s| [cut(lists[0], s), cut(lists[1], s)])
                .collect();
            let slots = |s: usize| slot[s] as usize - first..slot[s + 1] as usize - first;
            let near_walls: Vec<usize> = (0..count)
                .into_par_iter()
                .with_min_len(SLABS_PER_TASK)
                .map(|s| slots(s).map(|k| walls(k).count()).sum())
                .collect();
            let mut at = Vec::with_capacity(count);
            let mut total = 0;
            for s in 0..count {
                at.push(total);
                total += cuts[s + 1][0] - cuts[s][0] + cuts[s + 1][1] - cuts[s][1] + near_walls[s];
            }
            // Every row is written below: the last step's rows need no
            // clearing first.
            rows.truncate(total);
            rows.resize(total, Row::default());
            split_runs(rows, at)
                .into_par_iter()
                .enumerate()
                .with_min_len(SLABS_PER_TASK)
                .for_each(|(s, out)| {
                    let pairs = (0..2).flat_map(|l| &lists[l][cuts[s][l]..cuts[s + 1][l]]);
                    let own = pairs.map(|c| pair_row(c, s as u32)).chain(
                        slots(s).flat_map(|k| walls(k).map(move |w| wall_row(k, w, s as u32))),
                    );
                    let mut filled = 0;
                    for (to, row) in out.iter_mut().zip(own) {
                        *to = row;
                        filled += 1;
                    }
                    debug_assert_eq!(filled, out.len(), "slab {s}'s rows fill its part");
                    sort_rows(out, false);
                });
            return;
        }
        // Otherwise in the order of `lists`, then sorted together.
        rows.clear();
        let row_of = |c: &Contact| pair_row(c, slab_of(c.i.min(c.j) as usize - first));
        for list in lists {
            if slabs.is_some() {
                rows.par_extend(list.par_iter().with_min_len(ROWS_PER_TASK).map(row_of));
            } else {
                rows.extend(list.iter().map(row_of));
            }
        }
        for k in 0..len {
            rows.extend(walls(k).map(|w| wall_row(k, w, slab_of(k))));
        }
        sort_rows(rows, slabs.is_some());
    }

    /// From the lowest sphere up, each sphere's velocity into the spheres
    /// below it that it touches, and into the walls, taken away beyond
    /// what the lower sphere's own motion away makes room for: a sphere
    /// follows a support that falls away, but a support that rises does
    /// not lift it (the next step's rows do, sharing momentum). It moves
    /// by the change times `dt`. With `parallel` (a large world) the holds
    /// are found and sorted in parallel; the look itself runs on one
    /// thread, as each sphere waits for the spheres under it.
    fn shock(
        &mut self,
        rows: &[Row],
        rest: &[f32],
        support: Support,
        holds: &mut Vec<Hold>,
        push: &mut Vec<f64>,
        parallel: bool,
    ) {
        let (first, up, h) = (self.first, support.up, support.h);
        let now = &*self;
        // The hold of the row's upper sphere on its lower one, or of a
        // sphere on the wall it reaches.
        let hold = |row: &Row| -> Option<Hold> {
            let a = row.a as usize;
            if row.b & WALL != 0 {
                let axis = (row.b & 7) as usize / 2;
                let r = now.radius[a + first];
                let x = now.position[a][axis];
                let gap = if row.b & 1 == 1 { 1.0 - r - x } else { x - r };
                return (gap <= 0.0).then(|| (now.position[a].dot(up), row.a, row.b, row.n));
            }
            let b = row.b as usize;
            let d = now.position[a] - now.position[b];
            let reach = now.radius[a + first] + now.radius[b + first];
            if d.length_squared() >= reach * reach {
                return None;
            }
            let n = d.normalize_or(up);
            let rise = n.dot(up);
            if rise > 0.0 {
                Some((now.position[a].dot(up), row.a, row.b, n))
            } else if rise < 0.0 {
                Some((now.position[b].dot(up), row.b, row.a, -n))
            } else {
                None
            }
        };
        // By height, then slot, then what holds it: no two holds have the
        // same two, so whoever sorts them, in whatever order they were
        // found, they come out in one order.
        let key = |p: &Hold| {
            (u128::from(ordered_bits(p.0)) << 64) | (u128::from(p.1) << 32) | u128::from(p.2)
        };
        // A sleeper on a sphere awake is held still: it is not looked at.
        let hold = |row: &Row| {
            hold(row).filter(|h| !rest.get(h.1 as usize).is_some_and(|&r| is_asleep(r)))
        };
        holds.clear();
        if parallel {
            holds.par_extend(rows.par_iter().with_min_len(ROWS_PER_TASK).filter_map(hold));
            holds.par_sort_unstable_by_key(key);
        } else {
            holds.extend(rows.iter().filter_map(hold));
            holds.sort_unstable_by_key(key);
        }
        for group in holds.chunk_by(|p, q| p.1 == q.1) {
            let k = group[0].1 as usize;
            push.clear();
            push.resize(group.len(), 0.0);
            let mut v = self.velocity[k];
            for _ in 0..SHOCK_SWEEPS {
                let mut largest: f64 = 0.0;
                for (held, p) in group.iter().zip(push.iter_mut()) {
                    let n = held.3;
                    let away = if held.2 & WALL != 0 {
                        0.0
                    } else {
                        self.velocity[held.2 as usize].dot(n).min(0.0)
                    };
                    let next = (*p + away - v.dot(n)).max(0.0);
                    v += n * (next - *p);
                    largest = largest.max((next - *p).abs());
                    *p = next;
                }
                if largest <= support.speed_tolerance {
                    break;
                }
            }
            if v != self.velocity[k] {
                let r = self.radius[k + first];
                self.position[k] += (v - self.velocity[k]) * h;
                self.position[k] = self.position[k].clamp(Vec3::splat(r), Vec3::splat(1.0 - r));
                self.velocity[k] = v;
            }
        }
    }

    /// Start each row near the vertical (see [`CARRY_TILT`]) from the
    /// impulse it ended the last step with, if it was a row then. `at`
    /// keeps where each scene index's entries of `carried` begin.
    fn carry_in(
        &mut self,
        rows: &[Row],
        constraints: &mut [Constraint],
        carried: &[(u64, f64)],
        up: Vec3,
        at: &mut Vec<u32>,
    ) {
        let Some(&(last, _)) = carried.last() else {
            return;
        };
        // `carried` is sorted by key, and so by the key's first scene
        // index: the entries of index `i` are `at[i]..at[i + 1]`.
        let first_index = |key: u64| (key >> 32) as usize;
        at.clear();
        at.resize(first_index(last) + 2, 0);
        for &(key, _) in carried {
            at[first_index(key) + 1] += 1;
        }
        for i in 1..at.len() {
            at[i] += at[i - 1];
        }
        let at = &at[..];
        // Look the impulses up in parallel, then push in the rows' order.
        constraints
            .par_iter_mut()
            .zip(rows.par_iter())
            .with_min_len(ROWS_PER_TASK)
            .for_each(|(c, row)| {
                if row.n.dot(up).abs() < CARRY_TILT {
                    return;
                }
                let i = first_index(row.key);
                let Some(&[from, to]) = at.get(i..i + 2) else {
                    return;
                };
                if let Some(&(_, impulse)) = carried[from as usize..to as usize]
                    .iter()
                    .find(|c| c.0 == row.key)
                {
                    c.impulse = impulse;
                }
            });
        for c in constraints.iter() {
            if c.impulse != 0.0 {
                self.apply(c);
            }
        }
    }

    /// Push `c`'s spheres by its impulse along its normal, split by
    /// inverse mass (a wall takes its share whole).
    #[inline]
    fn apply(&mut self, c: &Constraint) {
        let (a, first) = (c.a as usize, self.first);
        self.velocity[a] += c.n * (c.impulse * self.inverse_mass[a + first]);
        if c.b & WALL == 0 {
            let b = c.b as usize;
            self.velocity[b] -= c.n * (c.impulse * self.inverse_mass[b + first]);
        }
    }

    /// The impacts among `rows` that the lesson's pass did not see,
    /// resolved one by one in the rows' order by the lesson's rule: each
    /// pair the narrow phase found apart that now touches and closes as
    /// fast as an impact ([`Support::impact`]) has its two spheres'
    /// velocities along its normal changed by an impulse split by inverse
    /// mass, so that they separate at `e` times their approach. The `u`
    /// of each row of a sphere so `struck` is then taken again.
    fn bounce(&mut self, rows: &mut [Row], support: Support, struck: &mut Vec<bool>) {
        let impact = support.impact();
        // One such row starts any chain of them.
        if rows
            .iter()
            .all(|r| !r.found_apart || r.gap > 0.0 || r.u >= -impact)
        {
            return;
        }
        struck.clear();
        struck.resize(self.velocity.len(), false);
        let first = self.first;
        for row in rows.iter().filter(|r| r.found_apart && r.gap <= 0.0) {
            let u = self.normal_speed(row.a, row.b, row.n);
            if u >= -impact {
                continue;
            }
            let impulse = -(1.0 + support.pair.at(-u)) * u / row.w;
            let (a, b) = (row.a as usize, row.b as usize);
            self.velocity[a] += row.n * (impulse * self.inverse_mass[a + first]);
            self.velocity[b] -= row.n * (impulse * self.inverse_mass[b + first]);
            (struck[a], struck[b]) = (true, true);
        }
        for row in rows.iter_mut() {
            if struck[row.a as usize] || (row.b & WALL == 0 && struck[row.b as usize]) {
                row.u = self.normal_speed(row.a, row.b, row.n);
            }
        }
    }

    /// `(v_a - v_b) . n` now, of a row of `a` and `b`.
    #[inline]
    fn normal_speed(&self, a: u32, b: u32, n: Vec3) -> f64 {
        let u = self.velocity[a as usize].dot(n);
        if b & WALL == 0 {
            u - self.velocity[b as usize].dot(n)
        } else {
            u
        }
    }

    /// Up to `sweeps` projected Gauss-Seidel sweeps of `rows` towards their
    /// targets, stopping once no row changes by more than `tolerance` m/s;
    /// returns the largest change of the last sweep. With `slabs`, each
    /// sweep solves the even slabs in parallel, then the odd ones. `give_way`
    /// is asked before each sweep (but the pass's first), and `None` when it
    /// stopped them.
    fn sweeps(
        &mut self,
        rows: &mut [Constraint],
        sweeps: usize,
        tolerance: f64,
        slabs: Option<&SlabRows>,
        give_way: &mut GiveWay,
    ) -> Option<f64> {
        let mut largest = 0.0_f64;
        for _ in 0..sweeps {
            if give_way.stop() {
                return None;
            }
            largest = match slabs {
                None => sweep(self.velocity, 0, &self.inverse_mass[self.first..], rows),
                Some(slabs) => self.sweep_in_slabs(rows, slabs),
            };
            if largest <= tolerance {
                break;
            }
        }
        Some(largest)
    }

    /// One sweep of [`BodiesMut::sweeps`] over the slabs of a large world.
    fn sweep_in_slabs(&mut self, rows: &mut [Constraint], slabs: &SlabRows) -> f64 {
        let count = slabs.at.len() - 1;
        let mut by_slab: Vec<Option<&mut [Constraint]>> =
            split_runs(rows, slabs.at[..count].iter().copied())
                .into_iter()
                .map(Some)
                .collect();
        let per_task = SLABS_PER_TASK;
        let mut largest = 0.0_f64;
        for parity in [0, 1] {
            // Slab `s` (of this parity) writes the slots of slabs `s` and
            // `s + 1`: one run each, cut one after the other.
            let starts = (parity..count)
                .step_by(2)
                .map(|s| slabs.slot[s] as usize - self.first);
            let runs = split_runs(self.velocity, starts);
            let inverse_mass = &self.inverse_mass[self.first..];
            let tasks: Vec<(&mut [Vec3], usize, &mut [Constraint])> = runs
                .into_iter()
                .zip((parity..count).step_by(2))
                .map(|(run, s)| {
                    let rows = by_slab[s].take().expect("each slab sweeps once");
                    (run, slabs.slot[s] as usize - self.first, rows)
                })
                .collect();
            let l = tasks
                .into_par_iter()
                .with_min_len(per_task)
                .map(|(run, first, rows)| sweep(run, first, inverse_mass, rows))
                .reduce(|| 0.0, f64::max);
            largest = largest.max(l);
        }
        largest
    }
}

/// Whether the pairs of `list` come in the order of their lower slots, as
/// a large world lists them: then each slab's pairs are a run of it.
fn follows_slots(list: &[Contact]) -> bool {
    list.par_windows(2)
        .with_min_len(ROWS_PER_TASK)
        .all(|w| w[0].i.min(w[0].j) <= w[1].i.min(w[1].j))
}

/// Sort `rows` by slab, then height, then slots (`a`, then `b`): one
/// order whoever sorts, as no two rows join the same slots. By integer
/// keys, each with its row's place, which are sorted and then read the
/// rows in their order: a row is 80 bytes and its key 32, so the sort
/// moves less than it would sorting the rows. In parallel when
/// `parallel`.
fn sort_rows(rows: &mut [Row], parallel: bool) {
    let key = |(k, r): (usize, &Row)| {
        let first = (u128::from(r.slab) << 96)
            | (u128::from(ordered_bits(r.height)) << 32)
            | u128::from(r.a);
        (first, r.b, k as u32)
    };
    let sorted: Vec<Row> = if parallel {
        let mut keys: Vec<_> = rows.par_iter().enumerate().map(key).collect();
        keys.par_sort_unstable();
        keys.par_iter().map(|k| rows[k.2 as usize]).collect()
    } else {
        let mut keys: Vec<_> = rows.iter().enumerate().map(key).collect();
        keys.sort_unstable();
        keys.iter().map(|k| rows[k.2 as usize]).collect()
    };
    rows.copy_from_slice(&sorted);
}

/// The bits of `x` as an unsigned integer in the order of
/// [`f64::total_cmp`].
pub(crate) fn ordered_bits(x: f64) -> u64 {
    let bits = x.to_bits();
    // Negative numbers count down; the sign bit then puts them first.
    (bits ^ ((((bits as i64) >> 63) as u64) >> 1)) ^ (1 << 63)
}

/// Rows a parallel task builds or looks up at least.
const ROWS_PER_TASK: usize = 4096;

/// Slabs a parallel task of the sweeps takes at least.
const SLABS_PER_TASK: usize = 2;

/// One projected Gauss-Seidel sweep of `rows`, over the spheres whose
/// velocities `velocity` holds from slot `first` on (`inverse_mass` and
/// the rows' slots counted from the same origin as `first`); the largest
/// change of a normal speed. The rows are taken from their lower half and
/// their upper half in turn (`contact::in_turns`): each half from its
/// lowest row up, one fixed order.
///
/// A row waits on the rows before it that share a sphere, so the loop has
/// no branch and no division: a wall row reads and writes its sphere as
/// both sides, the other side's share zeroed, and a row whose impulse does
/// not change adds zero. The processor can then start the next rows while
/// one waits; with a branch or a division on that path it cannot, and
/// taking the halves in turn gives it a second chain of rows to work on.
/// Measured with `lerpit bench --support --start dilute --warmup 600
/// --particles 20000 --threads T`: 53.3 ms a step against 58.6 for the
/// rows in order on one thread, 31.6 against 37.7 on two (medians of
/// five, by turns). Four parts in turn were no faster.
fn sweep(
    velocity: &mut [Vec3],
    first: usize,
    inverse_mass: &[f64],
    rows: &mut [Constraint],
) -> f64 {
    let mut largest = 0.0_f64;
    let (low, high) = rows.split_at_mut(rows.len() / 2);
    in_turns(low, high, |row| {
        largest = largest.max(sweep_row(velocity, first, inverse_mass, row));
    });
    largest
}

/// One row of [`sweep`]; the change of its normal speed.
#[inline(always)]
fn sweep_row(
    velocity: &mut [Vec3],
    first: usize,
    inverse_mass: &[f64],
    row: &mut Constraint,
) -> f64 {
    let a = row.a as usize;
    let wall = row.b & WALL != 0;
    let b = if wall { a } else { row.b as usize };
    let pair = if wall { 0.0 } else { 1.0 };
    let n = row.n;
    let u = velocity[a - first].dot(n) - pair * velocity[b - first].dot(n);
    let next = (row.impulse + (row.target - u) * row.mass).max(0.0);
    let change = next - row.impulse;
    row.impulse = next;
    velocity[a - first] += n * (change * inverse_mass[a]);
    velocity[b - first] -= n * (change * (pair * inverse_mass[b]));
    (change * row.w).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Bodies, Body, World};
    use rand::{RngExt, SeedableRng};

    fn sphere(position: Vec3, velocity: Vec3, radius: f64, mass: f64) -> Body {
        Body {
            position,
            velocity,
            radius,
            mass,
        }
    }

    fn held_world(bodies: Bodies, dt: f64) -> World {
        let config = WorldConfig {
            dt,
            support: true,
            ..WorldConfig::default()
        };
        World::new(config, bodies)
    }

    #[test]
    fn a_column_at_rest_stays_at_rest_and_keeps_its_energy() {
        // Ten spheres of r = 0.04 m standing on the floor, each touching
        // the next, with masses from 1 to 10 kg: the bottom one carries 54
        // kg above it.
        let r = 0.04;
        let bodies: Bodies = (0..10)
            .map(|k| {
                let y = r + k as f64 * 2.0 * r * (1.0 - RESTING_OVERLAP);
                sphere(Vec3::new(0.5, y, 0.5), Vec3::ZERO, r, (k + 1) as f64)
            })
            .collect();
        let mut w = held_world(bodies, 1.0 / 60.0);
        let start = w.bodies.position.clone();
        let e0 = w.diagnostics().total_energy;
        for _ in 0..600 {
            w.step();
        }
        let sank = start
            .iter()
            .zip(&w.bodies.position)
            .map(|(a, b)| (a.y - b.y).abs())
            .fold(0.0, f64::max);
        let fastest = w
            .bodies
            .velocity
            .iter()
            .map(|v| v.length())
            .fold(0.0, f64::max);
        let e = w.diagnostics().total_energy;
        assert!(sank < 1e-5 * r, "a sphere moved {:.2e} r", sank / r);
        assert!(fastest < 1e-9, "a sphere still moves at {fastest:.2e} m/s");
        assert!((e - e0).abs() < 1e-6 * e0.abs(), "energy {e0} became {e}");
    }

    #[test]
    fn one_bit_of_a_carried_impulse_or_of_its_rows_name_changes_the_state_hash() {
        // A column carrying its weight: the impulses its rows carry into
        // the next step are part of the state, and the hash covers each
        // one's name and bits.
        let r = 0.04;
        let bodies: Bodies = (0..3)
            .map(|k| {
                sphere(
                    Vec3::new(0.5, r + 2.0 * r * k as f64, 0.5),
                    Vec3::ZERO,
                    r,
                    1.0,
                )
            })
            .collect();
        let mut w = held_world(bodies, 1.0 / 60.0);
        w.run(10);
        let carried = w.carried_impulses().clone();
        assert!(carried.impulses.len() >= 3, "{carried:?}");
        let hash = w.state_hash();
        for k in 0..carried.impulses.len() {
            let mut impulse = carried.clone();
            let bits = impulse.impulses[k].1.to_bits() ^ 1;
            impulse.impulses[k].1 = f64::from_bits(bits);
            let mut name = carried.clone();
            name.impulses[k].0 ^= 1;
            for (what, changed) in [("impulse", impulse), ("name", name)] {
                w.restore_carried_impulses(&changed);
                assert_ne!(w.state_hash(), hash, "row {k}'s {what}");
            }
        }
        w.restore_carried_impulses(&carried);
        assert_eq!(w.state_hash(), hash);
    }

    #[test]
    fn the_margin_is_what_gravity_closes_in_the_window_but_never_wider_than_a_sphere() {
        let config = WorldConfig {
            support: true,
            ..WorldConfig::default()
        };
        let g = config.gravity.length();
        let window = config.rest_steps + 1.0;
        let short = Support::of(&config, 1.0 / 240.0, || 0.01).expect("on");
        assert_eq!(short.margin, window * g / 240.0 / 240.0);
        assert_eq!(short.impact(), window * g / 240.0);
        let long = Support::of(&config, 1.0, || 0.01).expect("on");
        assert_eq!(long.margin, 0.01, "held to the smallest radius");
        assert_eq!(
            long.impact(),
            window * g,
            "impacts still by the window's speed"
        );
        // A gravity whose square is below the smallest number still pulls.
        let faint = WorldConfig {
            gravity: Vec3::new(1e-300, 0.0, 0.0),
            ..config
        };
        assert_eq!(faint.gravity_strength(), 1e-300);
        assert_eq!(faint.support_idle(), None);
        let pass = Support::of(&faint, 1.0 / 240.0, || 0.01).expect("on");
        assert_eq!(pass.up, -Vec3::X);
    }

    /// The pass of a world asking for it, at step `h`, and every pair of
    /// `bodies` within its margin.
    fn pass_and_pairs(bodies: &Bodies, h: f64) -> (Support, Vec<Contact>) {
        let support = Support::of(
            &WorldConfig {
                support: true,
                ..WorldConfig::default()
            },
            h,
            || bodies.min_radius(),
        )
        .expect("the pass runs");
        let mut pairs = Vec::new();
        crate::sim::broad_phase::all_pairs_within(bodies, &mut pairs, support.margin);
        (support, pairs)
    }

    fn pass(bodies: &mut Bodies, h: f64) -> HoldCount {
        let (support, pairs) = pass_and_pairs(bodies, h);
        let ids = bodies.id.clone();
        BodiesMut::whole(bodies)
            .support(
                &ids,
                &[],
                [&pairs, &[]],
                support,
                None,
                &mut SupportWork::default(),
                &mut GiveWay::never(),
            )
            .expect("nothing interrupts the pass")
    }

    #[test]
    fn the_pass_gives_way_between_its_sweeps_and_carries_nothing_new_then() {
        // A column of ten spheres on the floor, each touching the next,
        // after a step of gravity: the solve needs many sweeps to carry the
        // weight down.
        let (r, h) = (0.04, 1.0 / 60.0);
        let fall = Vec3::new(0.0, -crate::sim::STANDARD_GRAVITY * h, 0.0);
        let bodies: Bodies = (0..10)
            .map(|k| {
                let y = r + k as f64 * 2.0 * r * (1.0 - RESTING_OVERLAP);
                sphere(Vec3::new(0.5, y, 0.5), fall, r, 1.0)
            })
            .collect();
        let (support, pairs) = pass_and_pairs(&bodies, h);
        let ids = bodies.id.clone();
        let run = |bodies: &mut Bodies, work: &mut SupportWork, stop_at: usize| {
            let asked = std::cell::Cell::new(0);
            let interrupted = || {
                asked.set(asked.get() + 1);
                asked.get() == stop_at
            };
            let held = BodiesMut::whole(bodies).support(
                &ids,
                &[],
                [&pairs, &[]],
                support,
                None,
                work,
                &mut GiveWay::new(&interrupted),
            );
            (held, asked.get())
        };
        let (mut whole, mut work) = (bodies.clone(), SupportWork::default());
        let (held, asks) = run(&mut whole, &mut work, 0);
        assert!(held.expect("never stopped").held > 0);
        assert!(
            asks >= 4,
            "asked {asks} times: before every sweep but the first"
        );
        assert!(!work.carried.is_empty(), "the pass carries impulses on");
        for stop in [1, asks] {
            let (mut stopped, mut work) = (bodies.clone(), SupportWork::default());
            let (held, _) = run(&mut stopped, &mut work, stop);
            assert_eq!(held, None, "stopped at {stop} of {asks}");
            assert!(
                work.carried.is_empty(),
                "stopped at {stop}: nothing carried"
            );
            assert_ne!(stopped.velocity, bodies.velocity, "its sweeps ran");
        }
    }

    #[test]
    fn ordered_bits_sort_as_total_cmp_does() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let mut xs = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            f64::MAX,
            f64::MIN,
            1.0,
            -1.0,
        ];
        xs.extend((0..200).map(|_| rng.random_range(-2.0..2.0)));
        for p in &xs {
            for q in &xs {
                assert_eq!(
                    ordered_bits(*p).cmp(&ordered_bits(*q)),
                    p.total_cmp(q),
                    "{p} against {q}"
                );
            }
        }
    }

    /// A row of slab `slab` at `height` joining `a` and `b`, at rest.
    fn bare_row(slab: u32, height: f64, a: u32, b: u32) -> Row {
        Row {
            height,
            a,
            b,
            n: Vec3::Y,
            w: 1.0,
            gap: 0.0,
            u: 0.0,
            key: 0,
            slab,
            found_apart: false,
        }
    }

    #[test]
    fn a_large_world_builds_its_rows_slab_by_slab_in_the_order_sorting_them_all_gives() {
        // A heap of mixed spheres on the floor, against the side walls, in
        // the cell order of a large world, some asleep.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let n = 6000;
        let mut bodies: Bodies = (0..n)
            .map(|_| {
                let r = 0.008 + 0.004 * rng.random::<f64>();
                let mut across = || r + (1.0 - 2.0 * r) * rng.random::<f64>();
                let (x, z) = (across(), across());
                let y = r + 0.06 * rng.random::<f64>();
                sphere(
                    Vec3::new(x, y, z),
                    Vec3::new(0.0, -0.1, 0.0),
                    r,
                    1.0 + rng.random::<f64>(),
                )
            })
            .collect();
        let h = 1.0 / 60.0;
        let margin = pass_and_pairs(&[].into_iter().collect(), h).0.margin;
        let (mut grid, mut spare) = (crate::sim::grid::Grid::new(), Vec::new());
        crate::sim::large::CellOrder::sort(&mut grid, &mut bodies, &mut spare, margin)
            .expect("a large world");
        let (support, pairs) = pass_and_pairs(&bodies, h);
        // As the world lists them: those touching, then those near.
        let (touching, near): (Vec<Contact>, Vec<Contact>) =
            pairs.iter().partition(|c| c.penetration >= 0.0);
        let rest: Vec<f32> = (0..n)
            .map(|k| {
                if k % 7 == 0 {
                    crate::sim::sleep::ASLEEP
                } else {
                    0.0
                }
            })
            .collect();
        let ids = bodies.id.clone();
        let slabs = grid.slab_slots().expect("in cell order");
        let whole = BodiesMut::whole(&mut bodies);
        let build = |by_slab: bool| {
            let mut rows = Vec::new();
            let lists = [&touching[..], &near[..]];
            whole.support_rows(&ids, &rest, lists, support, Some(slabs), &mut rows, by_slab);
            rows
        };
        let (by_slab, together) = (build(true), build(false));
        assert!(slabs.len() > 10, "{} slabs", slabs.len() - 1);
        let walls = by_slab.iter().filter(|r| r.b & WALL != 0).count();
        assert!(
            walls > 100 && by_slab.len() > walls + 2 * n,
            "{} rows, {walls} walls",
            by_slab.len()
        );
        assert!(by_slab.len() == together.len() && by_slab == together);
        // Lists that do not follow the slots are sorted together.
        let mut shuffled = touching.clone();
        shuffled.reverse();
        let mut rows = Vec::new();
        whole.support_rows(
            &ids,
            &rest,
            [&shuffled, &near],
            support,
            Some(slabs),
            &mut rows,
            true,
        );
        assert!(rows == together);
    }

    #[test]
    fn rows_sort_by_slab_then_height_then_slots_whoever_sorts() {
        let row = bare_row;
        let built = vec![
            row(1, 0.1, 4, 5),
            row(0, 0.5, 2, WALL | 2),
            row(0, 0.5, 2, 1),
            row(0, -0.0, 3, WALL | 2),
            row(0, 0.0, 0, WALL | 2),
            row(1, 0.05, 6, 4),
            row(0, 0.5, 1, 2),
        ];
        let expect = [(0, 3), (0, 0), (0, 1), (0, 2), (0, 2), (1, 6), (1, 4)];
        for parallel in [false, true] {
            let mut rows = built.clone();
            sort_rows(&mut rows, parallel);
            let got: Vec<(u32, u32)> = rows.iter().map(|r| (r.slab, r.a)).collect();
            assert_eq!(got, expect);
            // Ties of slab, height and `a` go by `b`.
            assert_eq!((rows[3].b, rows[4].b), (1, WALL | 2));
        }
    }

    #[test]
    fn rows_are_cut_into_slabs_only_where_each_keeps_to_its_slab_and_the_next() {
        let row = |slab: u32, a: u32, b: u32| bare_row(slab, 0.0, a, b);
        // Three slabs of two slots each.
        let slot = [0, 2, 4, 6];
        let rows = [row(0, 0, 3), row(1, 2, 5), row(2, 4, WALL | 2)];
        let slabs = SlabRows::of(&slot, 0, 6, &rows).expect("each keeps to its slab and the next");
        assert_eq!(slabs.at, [0, 1, 2, 3]);
        // A row of slab 0 reaching into slab 2.
        assert!(SlabRows::of(&slot, 0, 6, &[row(0, 0, 4)]).is_none());
        // Slabs that do not cover the run, or the run counted from
        // elsewhere.
        assert!(SlabRows::of(&slot, 0, 7, &rows).is_none());
        assert!(SlabRows::of(&slot, 1, 5, &rows).is_none());
        // One slab is no partition.
        assert!(SlabRows::of(&[0, 6], 0, 6, &rows).is_none());
        // An empty slab holds no rows and no slots.
        let slabs = SlabRows::of(&[0, 2, 2, 6], 0, 6, &[row(0, 0, 1), row(2, 2, 5)])
            .expect("an empty slab between");
        assert_eq!(slabs.at, [0, 1, 1, 2]);
    }

    #[test]
    fn a_pair_pressed_together_in_mid_air_shares_momentum_and_stops_closing() {
        // 1 kg above 3 kg, overlapping by 0.1 mm and closing at 0.1 m/s,
        // far from every wall: one row, between the two spheres.
        let r = 0.05;
        let mut b: Bodies = [
            sphere(Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.2, 0.05, 0.0), r, 3.0),
            sphere(
                Vec3::new(0.5, 0.5 + 2.0 * r - 1e-4, 0.5),
                Vec3::new(0.0, -0.05, 0.1),
                r,
                1.0,
            ),
        ]
        .into_iter()
        .collect();
        let momentum = |b: &Bodies| b.velocity[0] * b.mass[0] + b.velocity[1] * b.mass[1];
        let before = momentum(&b);
        pass(&mut b, 1.0 / 60.0);
        let after = momentum(&b);
        assert!((after - before).length() < 1e-15, "{before} became {after}");
        let n = (b.position[1] - b.position[0]).normalize();
        let closing = (b.velocity[0] - b.velocity[1]).dot(n);
        assert!(closing.abs() < 1e-12, "still closing at {closing} m/s");
        // Sideways motion is untouched: no friction.
        assert_eq!((b.velocity[0].x, b.velocity[1].z), (0.2, 0.1));
    }

    #[test]
    fn spheres_falling_together_are_not_held_up_by_each_other() {
        // Two touching spheres in free fall at the same speed: nothing
        // holds either, so the pass leaves both as they are.
        let r = 0.05;
        let v = Vec3::new(0.0, -1.0, 0.0);
        let mut b: Bodies = [
            sphere(Vec3::new(0.5, 0.5, 0.5), v, r, 1.0),
            sphere(
                Vec3::new(0.5, 0.5 + 2.0 * r * (1.0 - RESTING_OVERLAP), 0.5),
                v,
                r,
                1.0,
            ),
        ]
        .into_iter()
        .collect();
        let start = b.clone();
        pass(&mut b, 1.0 / 60.0);
        assert_eq!(b.velocity, start.velocity);
        assert_eq!(b.position, start.position);
    }

    #[test]
    fn a_sphere_dropped_between_two_comes_to_rest_on_them() {
        // Two spheres of r = 0.25 m on the floor, each against a side wall
        // and touching the other; a third dropped onto them, off centre and
        // moving sideways. Without friction it rests only where it sits on
        // both: centred, sqrt(3) r above them.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let r = 0.25;
        for trial in 0..20 {
            let x = 0.5 + 0.2 * r * (rng.random::<f64>() - 0.5);
            let v = Vec3::new(0.2 * (rng.random::<f64>() - 0.5), 0.0, 0.0);
            let bodies: Bodies = [
                sphere(Vec3::new(r, r, 0.5), Vec3::ZERO, r, 1.0),
                sphere(Vec3::new(1.0 - r, r, 0.5), Vec3::ZERO, r, 1.0),
                sphere(Vec3::new(x, 0.74, 0.5), v, r, 1.0),
            ]
            .into_iter()
            .collect();
            let mut w = held_world(bodies, 1.0 / 120.0);
            w.config.pair_restitution = 0.5;
            let e0 = w.diagnostics().total_energy;
            w.run(1200);
            let b = &w.bodies;
            let fastest = b.velocity.iter().map(|v| v.length()).fold(0.0, f64::max);
            let rest = Vec3::new(0.5, r + 3.0_f64.sqrt() * r, 0.5);
            let off = (b.position[2] - rest).length();
            let e = w.diagnostics().total_energy;
            assert!(
                fastest < 1e-4,
                "trial {trial}: still moving at {fastest:.2e} m/s"
            );
            assert!(
                off < 0.01 * r,
                "trial {trial}: {:.2e} r from where it rests",
                off / r
            );
            assert!(e < e0, "trial {trial}: energy {e0} rose to {e}");
        }
    }
}
