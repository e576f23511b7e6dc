//! `World::step`: one fixed step, as a pipeline of the named stages of
//! [`Stage`], each a method below, run only if the scene uses it:
//!
//! 1. [`Stage::Integrate`] (`Integrator::integrate`): gravity changes the
//!    velocity (`v += F/m dt`), velocity changes the position
//!    (`x += v dt`), in the order the method prescribes;
//! 2. [`Stage::BroadPhase`], [`Stage::NarrowPhase`], [`Stage::SolveContacts`],
//!    only when the scene has pair collisions: find the overlapping pairs
//!    (all-pairs, as the lesson does, or the grid of `grid.rs`), then
//!    resolve each by the lesson's position projection and `V1`/`V2`
//!    (`contact.rs`), then, when `projection_passes > 1`, project the pairs
//!    still overlapping again, for deep piles. A large world on the grid
//!    in which nothing reads the contacts before they are all resolved
//!    runs the narrow phase and the solve as one stage,
//!    [`Stage::NarrowAndSolve`]: each contact resolved as it is found,
//!    with the same bits, and listed as well when the step keeps its list
//!    ([`World::keep_contacts`]);
//! 3. [`Stage::Walls`] (`walls::resolve_walls_after`): every centre back
//!    inside the box whatever the contacts did; velocity Verlet and RK4
//!    reflect at the crossing of their parabola, the Euler methods mirror
//!    the overshoot;
//! 4. [`Stage::Support`] (`support.rs`), only when the world asks for it
//!    (`WorldConfig::support`): every resting contact, between spheres and
//!    against the walls, solved together at the velocity level, so that a
//!    pile carries its weight. The narrow phase then also lists the pairs
//!    within the pass's margin of touching.
//!
//! Around the stages, when the world lets spheres sleep
//! (`WorldConfig::sleep`), the step first wakes the sleepers something
//! touched or leaves them still (`World::wake_or_rest`), and after its
//! last sub-step puts to sleep the islands at rest long enough
//! (`sleep::settle`): see `sleep.rs`.
//!
//! Worlds of at least `large::SPATIAL_ORDER_MIN_BODIES` spheres also keep their
//! slots in cell order and solve contacts in parallel slabs: that machinery
//! lives in `large/`, and the step meets it through `CellOrder::sort` in
//! the broad phase, then the slab solver (`CellOrder::solve`) or the
//! single stage (`CellOrder::find_and_solve`). The support pass sweeps the
//! same slabs in parallel, from the grid's slab starts
//! (`Grid::slab_slots`).
//!
//! Resting contact (`restitution.rs`, `WorldConfig::rest_steps`): in the
//! discrete methods an impact slower than the speed gravity adds along its
//! normal in `rest_steps` sub-steps is perfectly inelastic, in the contact
//! and wall stages, so that bodies come to rest instead of micro-bouncing.
//!
//! The continuous method replaces these stages with one,
//! [`Stage::Events`] (`continuous::advance`): free flight to the earliest
//! time of impact, resolve it, repeat until the step is done. With
//! `substeps = k` the step runs its stages `k` times with `dt / k`.
//!
//! The step is deterministic: the same bodies (their times at rest among
//! them), config, carried impulses (the support pass's, `support.rs`) and
//! parameters the sleepers fell asleep under (`sleep.rs`) give the same
//! bits, for any number
//! of threads (the stages run on the current rayon pool; see
//! `threads.rs`), and for either broad phase, since both report the same
//! contacts in the same order.

use super::broad_phase::all_pairs_until;
use super::contact::{BodiesMut, Held, in_contact_list};
use super::continuous::{self, EventQueue};
use super::grid::{CellLayout, Grid};
use super::large::{CellOrder, is_large};
use super::sleep::{self, SleepWork, Touch};
use super::sleeping_pairs::SleepingPairs;
use super::stage::{Stage, StageSeconds};
use super::support::{CarriedImpulses, Support, SupportWork};
use super::threads::GiveWay;
use super::walls::{Flight, clamp_to_box, resolve_walls_after};
use super::{Bodies, BroadPhase, Contact, Diagnostics, Integrator, Vec3, WorldConfig};
use std::time::Instant;

/// What the last step did: counters filled by the stages as they run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Overlapping pairs found this step (the continuous method: pair
    /// impacts resolved).
    pub contacts: usize,
    /// Pairs tested for overlap this step.
    pub pair_tests: u64,
    /// Largest penetration found this step (before it was corrected), m.
    pub max_overlap: f64,
    /// Wall impacts that reversed a velocity component this step.
    pub wall_impacts: usize,
    /// Sum of the impulses the walls gave this step, kg m/s.
    pub wall_impulse: Vec3,
    /// The continuous method reached its cap of impacts in a step and
    /// finished it against the walls alone, then the contact stage
    /// (`continuous.rs` says what that keeps).
    pub event_cap_reached: bool,
    /// The broad phase that ran (`auto` resolved); `None` without pair
    /// collisions.
    pub broad_phase: Option<BroadPhase>,
    /// Slabs the contact solver cut the contacts into (1: the sequential
    /// `(i, j)` pass; 0: no contact solve).
    pub contact_slabs: usize,
    /// Slabs the support pass's sweeps ran in (1: one sequence; 0: no
    /// pass), the most over the step's sub-steps.
    pub support_slabs: usize,
    /// Projection passes run after the lesson's pass this step (at most
    /// `projection_passes - 1` per sub-step, summed over sub-steps).
    pub projection_passes: u32,
    /// The largest penetration the last projection pass met, m (0 with no
    /// further pass).
    pub residual_overlap: f64,
    /// The further passes ran out before every pair was within
    /// [`PROJECTION_TOLERANCE`] of touching: the pile stays compressed.
    pub projection_unconverged: bool,
    /// Spheres whose velocity the support pass changed (`support.rs`).
    pub supported: usize,
    /// Spheres of a row the support pass's sweeps left short of its
    /// target by more than 1% of a radius (`support.rs`,
    /// `HoldCount::unsettled`).
    pub support_unsettled: usize,
    /// Spheres asleep after the step (`sleep.rs`).
    pub asleep: usize,
}

/// Further projection passes stop once no pair overlaps by more than this
/// fraction of the largest radius.
pub(crate) const PROJECTION_TOLERANCE: f64 = 0.01;

#[derive(Clone, Debug)]
pub struct World {
    pub config: WorldConfig,
    pub bodies: Bodies,
    /// Simulated time, s.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Counters of the last step.
    pub last: StepStats,
    /// Contacts found by the last step (reused buffer).
    contacts: Vec<Contact>,
    /// The continuous method's pending impacts (reused buffers).
    events: EventQueue,
    /// The grid's buffers (reused).
    grid: Grid,
    /// Seconds per stage, summed since timing was switched on.
    timing: Option<StageSeconds>,
    /// Pairs within the support pass's margin of touching, not
    /// overlapping (reused buffer).
    near: Vec<Contact>,
    /// The support pass's working memory.
    support_work: SupportWork,
    /// The parameters of the last step while the world sleeps spheres
    /// (those its sleepers fell asleep under); `None` while it does not.
    slept_under: Option<WorldConfig>,
    /// The sleeping rules' working memory.
    sleep_work: SleepWork,
    /// The pairs of two sleepers, which the narrow phase skips.
    sleeping_pairs: SleepingPairs,
    /// Spheres asleep in the step under way (counted as it starts, less
    /// those a touch woke).
    asleep: usize,
    /// While some sphere sleeps, the inverse masses the sub-step's
    /// solvers use: a sleeper's is 0, so that it is held still
    /// (`contact::Held`). Filled after each narrow phase with sleepers.
    held: Vec<f64>,
    /// Whether the list of the last step's contacts must be kept
    /// ([`World::keep_contacts`]).
    keep_contacts: bool,
    /// Whether the step under way needs its list of contacts: it is to
    /// be kept, or sleeping may read it (set as the step starts).
    needs_list: bool,
    /// Working memory of a large world that sweeps: the reorder's and the
    /// sweep's (`large/sweep.rs`).
    spare: Vec<Contact>,
    /// The method of the last step that finished (`None`: none yet).
    method_before: Option<Integrator>,
    /// The step under way is the world's first with the continuous method
    /// (its first, or the first after a discrete one): its first sub-step
    /// resolves the overlaps the method did not make
    /// (`continuous::separate_overlaps`).
    entering_continuous: bool,
}

impl World {
    pub fn new(config: WorldConfig, bodies: Bodies) -> Self {
        Self {
            config,
            bodies,
            time: 0.0,
            steps: 0,
            last: StepStats::default(),
            contacts: Vec::new(),
            events: EventQueue::default(),
            grid: Grid::new(),
            timing: None,
            near: Vec::new(),
            support_work: SupportWork::default(),
            slept_under: None,
            sleep_work: SleepWork::default(),
            sleeping_pairs: SleepingPairs::default(),
            asleep: 0,
            held: Vec::new(),
            keep_contacts: true,
            needs_list: true,
            spare: Vec::new(),
            method_before: None,
            entering_continuous: false,
        }
    }

    /// Advance the world by one step of `config.dt`.
    pub fn step(&mut self) {
        let finished = self.try_step(&|| false);
        debug_assert!(finished, "a step that nothing interrupts finishes");
    }

    /// Advance the world by one step of `config.dt`, unless `interrupted`
    /// says to stop: it is asked before every sub-step but the first,
    /// between the stages of a discrete sub-step, every few rows of the
    /// all-pairs narrow phase, between batches of slabs in a large world's
    /// contact stages (about every eighth of each: the sweep, the grid's
    /// narrow phase, the slab solver), before each sweep of the support
    /// pass, and by the continuous method every few hundred impacts and
    /// before each pass that pushes apart the overlaps it was given.
    /// Returns true when the step finished. A step abandoned part-way
    /// leaves the bodies moved (and sleepers woken) by the sub-steps and
    /// stages it ran, with `time`, `steps` and `last` as they were: the
    /// caller puts the bodies back from its own copy, times at rest and the
    /// parameters the sleepers slept under included (the visualiser's
    /// step-back history).
    #[must_use]
    pub fn try_step(&mut self, interrupted: &dyn Fn() -> bool) -> bool {
        let mut stats = StepStats::default();
        let h = self.config.substep_dt();
        if Support::of(&self.config, h, || f64::INFINITY).is_none() {
            // Impulses carried from a pass that no longer runs would be
            // stale by the time it runs again.
            self.support_work.carried.clear();
        }
        if self.config.integrator == Integrator::Continuous {
            // Its sub-steps' impacts add up to the step's contacts.
            self.contacts.clear();
        }
        if self.wake_or_rest() {
            self.time += self.config.dt;
            self.steps += 1;
            let c = &self.config;
            self.last = StepStats {
                asleep: self.bodies.len(),
                // The broad phase that would have run: it had nothing to
                // test.
                broad_phase: c
                    .pair_collisions
                    .then(|| c.broad_phase.resolve(self.bodies.len())),
                ..StepStats::default()
            };
            return true;
        }
        self.entering_continuous = self.config.integrator == Integrator::Continuous
            && self.method_before != Some(Integrator::Continuous);
        self.needs_list = self.keep_contacts
            || (self.config.sleeps()
                && (self.some_asleep()
                    || sleep::may_fall_asleep(&self.bodies.rest, self.config.dt)));
        for k in 0..self.config.substeps.max(1) {
            if k > 0 && interrupted() {
                return false;
            }
            let finished = match self.config.integrator {
                Integrator::Continuous => self.continuous_substep(h, &mut stats, interrupted),
                _ => self.discrete_substep(h, &mut stats, interrupted),
            };
            if !finished {
                return false;
            }
        }
        if self.config.sleeps() {
            let links = [&self.contacts[..], &self.near[..]];
            sleep::settle(
                &mut self.bodies,
                links,
                (self.config.dt, self.config.gravity),
                &mut self.sleep_work,
            );
            if self.config.pair_collisions {
                self.sleeping_pairs.fell_asleep(&self.sleep_work.fell);
            }
            stats.asleep = sleep::asleep_count(&self.bodies.rest);
        }
        self.time += self.config.dt;
        self.steps += 1;
        self.last = stats;
        self.method_before = Some(self.config.integrator);
        true
    }

    /// Before a step: wake every sleeper if the world stopped sleeping
    /// spheres or a parameter changed since they fell asleep
    /// (`sleep.rs`). True when every sphere sleeps, so that the step only
    /// advances the clock.
    fn wake_or_rest(&mut self) -> bool {
        self.asleep = 0;
        if !self.config.sleeps() {
            if self.slept_under.take().is_some() {
                sleep::wake_all(&mut self.bodies.rest);
            }
            return false;
        }
        if self.slept_under.as_ref() != Some(&self.config) {
            sleep::wake_all(&mut self.bodies.rest);
            self.slept_under = Some(self.config.clone());
            return false;
        }
        self.asleep = sleep::asleep_count(&self.bodies.rest);
        let everyone = !self.bodies.is_empty() && self.asleep == self.bodies.len();
        if everyone {
            self.contacts.clear();
            self.near.clear();
        }
        everyone
    }

    /// Whether some sphere sleeps in this step (`sleep.rs`).
    fn some_asleep(&self) -> bool {
        self.asleep > 0
    }

    /// The stages of the discrete methods over `h`, in order; false when
    /// `interrupted` stopped them.
    fn discrete_substep(
        &mut self,
        h: f64,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        let resting = self.config.resting(h);
        let support = Support::of(&self.config, h, || self.bodies.min_radius());
        self.stage(Stage::Integrate, |w| w.integrate(h));
        if self.config.pair_collisions {
            if !self.collide(resting, support, stats, interrupted) {
                return false;
            }
        } else {
            self.contacts.clear();
            self.near.clear();
        }
        if interrupted() {
            return false;
        }
        self.stage(Stage::Walls, |w| w.walls(h, resting, stats));
        if let Some(support) = support {
            return self.stage(Stage::Support, |w| w.support(support, stats, interrupted));
        }
        true
    }

    /// The continuous method over `h`; false when `interrupted` stopped it.
    /// A sub-step that reaches the impact cap finishes with the contact
    /// stages and the walls (`continuous.rs` says what that keeps).
    fn continuous_substep(
        &mut self,
        h: f64,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        let events = self.stage(Stage::Events, |w| {
            continuous::advance(
                &mut w.bodies,
                &w.config,
                h,
                &mut w.events,
                (stats, std::mem::take(&mut w.entering_continuous)),
                interrupted,
            )
        });
        let Ok(capped) = events else {
            return false;
        };
        self.contacts.extend_from_slice(&self.events.impacts);
        if capped {
            if self.config.pair_collisions && !self.collide(Vec3::ZERO, None, stats, interrupted) {
                return false;
            }
            continuous::return_to_walls(&mut self.bodies, &self.config, stats);
        }
        true
    }

    /// The three contact stages, with resting contact below `resting`
    /// (`g rest_steps h`; zero: none). With a `support` pass to follow,
    /// they also find the pairs within its margin of touching, and leave
    /// the resting pairs to it. False when `interrupted` stopped them.
    fn collide(
        &mut self,
        resting: Vec3,
        support: Option<Support>,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        if self.sweeps(support) {
            return self.sweep(resting, stats, interrupted);
        }
        let margin = support.map_or(0.0, |s| s.margin);
        let order = self.stage(Stage::BroadPhase, |w| w.broad_phase(margin, stats));
        if interrupted()
            || !self.stage(Stage::NarrowPhase, |w| {
                w.narrow_phase(margin, stats, interrupted)
            })
            || interrupted()
        {
            return false;
        }
        let supported = support.is_some();
        self.stage(Stage::SolveContacts, |w| {
            w.solve(order, resting, supported, stats, interrupted)
        })
    }

    /// Whether this sub-step's contact stages run as one sweep
    /// (`large/sweep.rs`): a large world on the grid in which nothing
    /// reads the contacts before they are all resolved (no `support` pass,
    /// no further projection pass, a discrete method, and no sleeper to
    /// wake). The sweep lists them as it goes when the step needs its list
    /// afterwards (kept for the caller, or read by sleeping).
    fn sweeps(&self, support: Option<Support>) -> bool {
        let c = &self.config;
        let n = self.bodies.len();
        !self.some_asleep()
            && support.is_none()
            && c.projection_passes < 2
            && c.integrator != Integrator::Continuous
            && is_large(n)
            && c.broad_phase.resolve(n) == BroadPhase::Grid
    }

    /// The contact stages of [`World::collide`] as one sweep (see
    /// [`World::sweeps`]): the broad phase sorts into cell order, then
    /// [`Stage::NarrowAndSolve`] finds and resolves the contacts slab by
    /// slab, with the bits of the narrow phase and the solve, listing them
    /// when the step needs the list. The first step to list them over
    /// these slabs runs the two stages instead, which size each slab's
    /// part of the list.
    fn sweep(
        &mut self,
        resting: Vec3,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        if !self.needs_list {
            self.contacts.clear();
        }
        // No support pass: no pairs near touching, which sleeping would
        // otherwise read from an earlier step (and an earlier cell order).
        self.near.clear();
        stats.broad_phase = Some(BroadPhase::Grid);
        let order = self.stage(Stage::BroadPhase, |w| {
            CellOrder::sort(&mut w.grid, &mut w.bodies, &mut w.spare, 0.0)
        });
        let order = order.expect("a large world sorts into cell order");
        if interrupted() {
            return false;
        }
        if self.needs_list && !self.grid.sized_for_sweep() {
            return self.stage(Stage::NarrowPhase, |w| {
                w.narrow_phase(0.0, stats, interrupted)
            }) && !interrupted()
                && self.stage(Stage::SolveContacts, |w| {
                    w.solve(Some(order), resting, false, stats, interrupted)
                });
        }
        let rule = self.config.contact_rule(resting, false);
        let swept = self.stage(Stage::NarrowAndSolve, |w| {
            let mut give_way = GiveWay::new(interrupted);
            let list = w.needs_list.then_some(&mut w.contacts);
            order.find_and_solve(
                &mut w.grid,
                &mut w.bodies,
                &mut w.spare,
                list,
                rule,
                &mut give_way,
            )
        });
        let Some(swept) = swept else {
            return false;
        };
        stats.pair_tests += swept.tests;
        stats.contacts += swept.contacts;
        stats.max_overlap = swept.deepest.max(stats.max_overlap);
        stats.contact_slabs = swept.slabs;
        true
    }

    /// Whether the world keeps the list of the last step's contacts
    /// ([`World::contacts`]; the default). A caller that never reads it
    /// may say no: then, in each step that reads no list either, a world
    /// of at least `large::SPATIAL_ORDER_MIN_BODIES` spheres on the grid
    /// (`auto` or `grid`) with a discrete method, no support pass, one
    /// projection pass and no sleeper finds and resolves its contacts in
    /// one sweep and never writes the list (`large/sweep.rs`), with the
    /// same bits; the list is then empty. (Keeping the list, such a world
    /// sweeps too, and writes each contact to the list as it goes.)
    /// Sleeping reads the list only in steps that may put spheres to sleep
    /// or wake them. Other worlds and steps keep the list whatever this
    /// says.
    pub fn keep_contacts(&mut self, keep: bool) {
        if self.keep_contacts && !keep {
            self.contacts = Vec::new();
        }
        self.keep_contacts = keep;
    }

    /// Run `stage`, timing it when timing is on.
    fn stage<R>(&mut self, stage: Stage, run: impl FnOnce(&mut Self) -> R) -> R {
        if self.timing.is_none() {
            return run(self);
        }
        let start = Instant::now();
        let result = run(self);
        if let Some(timing) = &mut self.timing {
            *timing.of(stage) += start.elapsed().as_secs_f64();
        }
        result
    }

    /// [`Stage::Integrate`].
    fn integrate(&mut self, h: f64) {
        let (method, g) = (self.config.integrator, self.config.gravity);
        if self.some_asleep() {
            method.integrate_awake(&mut self.bodies, g, h);
        } else {
            method.integrate(&mut self.bodies, g, h);
        }
    }

    /// [`Stage::BroadPhase`]: resolve `auto`; sort a large world into cell
    /// order (building the grid), or build the grid for a smaller one that
    /// uses it. Returns the cell order when the world is large.
    fn broad_phase(&mut self, margin: f64, stats: &mut StepStats) -> Option<CellOrder> {
        let method = self.config.broad_phase.resolve(self.bodies.len());
        stats.broad_phase = Some(method);
        let order = CellOrder::sort(&mut self.grid, &mut self.bodies, &mut self.contacts, margin);
        if method == BroadPhase::Grid && order.is_none() {
            self.grid
                .build(&self.bodies, CellLayout::within(&self.bodies, margin));
        }
        order
    }

    /// [`Stage::NarrowPhase`]: every overlapping pair, sorted by `(i, j)`,
    /// from the grid the broad phase built or from every pair; with a
    /// `margin`, the pairs not overlapping but within it go to the support
    /// pass's list (`near`), in the same order. False when `interrupted`
    /// stopped all-pairs part-way.
    fn narrow_phase(
        &mut self,
        margin: f64,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        // The pairs of two sleepers kept from earlier sub-steps are not
        // looked for again.
        let quiet = if self.some_asleep() {
            let up = sleep::up_of(self.config.gravity);
            self.sleeping_pairs.quiet(&self.bodies, margin, up)
        } else {
            None
        };
        stats.pair_tests += match stats.broad_phase {
            Some(BroadPhase::Grid) => {
                let mut give_way = GiveWay::new(interrupted);
                let grid = &mut self.grid;
                match grid.find_contacts_within(
                    &self.bodies,
                    &mut self.contacts,
                    margin,
                    quiet,
                    &mut give_way,
                ) {
                    Some(tests) => tests,
                    None => return false,
                }
            }
            _ => {
                match all_pairs_until(&self.bodies, &mut self.contacts, margin, quiet, interrupted)
                {
                    Some(tests) => tests,
                    None => return false,
                }
            }
        };
        self.near.clear();
        if margin > 0.0 {
            self.near
                .extend(self.contacts.iter().filter(|c| !in_contact_list(c, margin)));
            self.contacts.retain(|c| in_contact_list(c, margin));
        }
        // With sleepers, those a pair disturbs wake (every one, without
        // gravity), the pairs of two still asleep are kept aside and those
        // kept of a sleeper woken come back: the grid's deepest may be one
        // of either. A blow is faster than the resting window and a
        // sub-step's gravity.
        let mut dropped = false;
        if self.some_asleep() {
            dropped = true;
            let lists = [&mut self.contacts, &mut self.near];
            let (g, h) = (self.config.gravity, self.config.substep_dt());
            let blow = self.config.resting(h).length() + g.length() * h;
            let kept = &mut self.sleeping_pairs;
            // The grid holds this sub-step's build when the narrow phase
            // used it or the world is large (its sort built it).
            let searched =
                stats.broad_phase == Some(BroadPhase::Grid) || is_large(self.bodies.len());
            match sleep::touch(
                &mut self.bodies,
                lists,
                kept,
                (g, h, blow),
                sleep::CatchUp {
                    method: self.config.integrator,
                    margin,
                    grid: searched.then_some(&self.grid),
                },
                &mut self.sleep_work,
            ) {
                Touch::All => self.asleep = 0,
                Touch::Some(woken) => self.asleep -= woken,
            }
            if self.some_asleep() {
                sleep::held_inverse_masses(&self.bodies, &mut self.held);
            }
        }
        stats.contacts += self.contacts.len();
        let deepest = match stats.broad_phase {
            // Found by the narrow phase's own tasks as they went.
            Some(BroadPhase::Grid) if !dropped => self.grid.deepest(),
            _ => self
                .contacts
                .iter()
                .map(|c| c.penetration)
                .fold(0.0, f64::max),
        };
        stats.max_overlap = deepest.max(stats.max_overlap);
        true
    }

    /// [`Stage::SolveContacts`]: the lesson's pass over the contacts (slab
    /// by slab for a large world), then the further projection passes.
    /// False when `interrupted` stopped a large world's pass part-way.
    fn solve(
        &mut self,
        order: Option<CellOrder>,
        resting: Vec3,
        supported: bool,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        let config = &self.config;
        let (bodies, contacts) = (&mut self.bodies, &self.contacts[..]);
        let held = (self.asleep > 0).then(|| Held {
            inverse_mass: &self.held,
            fall: config.gravity * config.substep_dt(),
        });
        let rule = config.contact_rule(resting, supported);
        // A large world's slab passes may stop between batches of slabs.
        let mut give_way = GiveWay::new(interrupted);
        stats.contact_slabs = match order {
            Some(order) => match order.solve(bodies, held, contacts, rule, &mut give_way) {
                Some(slabs) => slabs,
                None => return false,
            },
            None => {
                BodiesMut::held(bodies, held).resolve(contacts, rule);
                1
            }
        };
        if config.projection_passes < 2 || contacts.is_empty() {
            return true;
        }
        let tolerance = PROJECTION_TOLERANCE * bodies.max_radius();
        let mut converged = false;
        for _ in 1..config.projection_passes {
            // Not with the support pass: its rows hold the walls, and it
            // takes each overlap the step's motion did not make for an old
            // one to push out. A clamp lifts a sphere out of the floor
            // without moving the spheres on it, and the pass would push
            // them up: the pile would gain energy.
            if !supported {
                clamp_to_box(bodies);
            }
            let worst = match order {
                Some(order) => match order.project(bodies, held, contacts, rule, &mut give_way) {
                    Some(worst) => worst,
                    None => return false,
                },
                None => BodiesMut::held(bodies, held).project(contacts, rule),
            };
            stats.projection_passes += 1;
            stats.residual_overlap = worst;
            if worst <= tolerance {
                converged = true;
                break;
            }
        }
        stats.projection_unconverged |= !converged;
        true
    }

    /// [`Stage::Support`]: every resting contact of the step solved
    /// together (`support.rs`). False when `interrupted` stopped its sweeps.
    fn support(
        &mut self,
        support: Support,
        stats: &mut StepStats,
        interrupted: &dyn Fn() -> bool,
    ) -> bool {
        let pairs = [&self.contacts[..], &self.near[..]];
        // A large world's slots are in the cell order of this sub-step's
        // grid: the pass sweeps its slabs in parallel.
        let large = is_large(self.bodies.len());
        let slabs = self.grid.slab_slots().filter(|_| large);
        let (mut bodies, id, rest) = BodiesMut::whole_with_ids(&mut self.bodies);
        if self.asleep > 0 {
            bodies.inverse_mass = &self.held;
        }
        let mut give_way = GiveWay::new(interrupted);
        let work = &mut self.support_work;
        let Some(count) = bodies.support(id, rest, pairs, support, slabs, work, &mut give_way)
        else {
            return false;
        };
        stats.supported += count.held;
        stats.support_unsettled += count.unsettled;
        stats.support_slabs = stats.support_slabs.max(count.slabs);
        true
    }

    /// [`Stage::Walls`].
    fn walls(&mut self, h: f64, resting: Vec3, stats: &mut StepStats) {
        let config = &self.config;
        let flight = Flight::of(config.integrator, config.gravity, h);
        let rule = config.wall_rule().with_resting(resting);
        let walls = resolve_walls_after(&mut self.bodies, config.wall_mode, rule, flight);
        stats.wall_impacts += walls.impacts;
        stats.wall_impulse += walls.impulse;
    }

    /// Time each stage of the steps from now on (`true`), or stop.
    /// Timing starts again from zero.
    pub fn time_stages(&mut self, on: bool) {
        self.timing = on.then(StageSeconds::default);
    }

    /// Seconds spent in each stage since timing was switched on.
    pub fn stage_seconds(&self) -> Option<StageSeconds> {
        self.timing
    }

    /// A copy of this world's state (config, bodies, time, step count, the
    /// last step's counters and contacts, the impulses the support pass
    /// carries) without its working buffers:
    /// what a reader of the state needs, at the cost of the state alone.
    /// `into` is reused when given, so its allocations are kept.
    pub fn copy_state(&self, into: Option<World>) -> World {
        let mut w = into.unwrap_or_else(|| World::new(self.config.clone(), Bodies::default()));
        w.config.clone_from(&self.config);
        w.bodies.clone_from(&self.bodies);
        w.time = self.time;
        w.steps = self.steps;
        w.last = self.last;
        w.contacts.clone_from(&self.contacts);
        w.support_work
            .carried
            .clone_from(&self.support_work.carried);
        w.slept_under.clone_from(&self.slept_under);
        w.method_before = self.method_before;
        w
    }

    /// After the bodies (their times at rest among them) were put back to
    /// the state an earlier step reached with `config`: the sleepers of
    /// that state fell asleep under it.
    pub fn restore_slept_under(&mut self, config: &WorldConfig) {
        self.slept_under = config.sleeps().then(|| config.clone());
    }

    /// After putting back a saved state: the method of the step that
    /// reached it (`None`: no step did), which decides whether the next
    /// step enters the continuous method (`continuous::separate_overlaps`).
    pub fn restore_method_before(&mut self, method: Option<Integrator>) {
        self.method_before = method;
    }

    /// The impulses the support pass carries into the next step
    /// (`support.rs`): part of the state, with the bodies.
    pub fn carried_impulses(&self) -> &CarriedImpulses {
        &self.support_work.carried
    }

    /// Put back the impulses the support pass carried at an earlier state
    /// (see [`World::carried_impulses`]).
    pub fn restore_carried_impulses(&mut self, carried: &CarriedImpulses) {
        self.support_work.carried.clone_from(carried);
    }

    /// Forget the pairs of two sleepers kept (`sleeping_pairs.rs`), so
    /// that the next narrow phase finds every pair.
    #[cfg(test)]
    pub(crate) fn forget_sleeping_pairs(&mut self) {
        self.sleeping_pairs.forget();
    }

    /// How many pairs of two sleepers are kept (`sleeping_pairs.rs`).
    #[cfg(test)]
    pub(crate) fn sleeping_pairs_kept(&self) -> usize {
        self.sleeping_pairs.len()
    }

    /// Forget the contacts of the last step (after the bodies were put
    /// back to an earlier state, they no longer describe it).
    pub fn forget_contacts(&mut self) {
        self.contacts.clear();
    }

    /// After the bodies were put back to the state of an earlier step,
    /// give the world the contacts that step found (a caller that kept the
    /// state before it can find them again, see `tui::session`).
    pub fn restore_contacts(&mut self, contacts: &[Contact]) {
        self.contacts.clear();
        self.contacts.extend_from_slice(contacts);
    }

    /// Take `n` steps.
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    /// The contacts the last step found and resolved (its last sub-step's;
    /// none when it resolved them in one sweep without listing them,
    /// [`World::keep_contacts`]);
    /// for the continuous method, the pair impacts that took an impulse,
    /// in the order they happened over its sub-steps (touching: no
    /// penetration); a sub-step that reaches its impact cap starts the
    /// list again with its contact stage's contacts, and the impacts of
    /// later sub-steps follow them.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// The pairs the last step's support pass took within its margin of
    /// touching but not overlapping (speculative contacts: a pair closing
    /// slowly is brought to rest on the other in the step it meets), by
    /// slot; empty without the pass.
    pub fn near_pairs(&self) -> &[Contact] {
        &self.near
    }

    /// Energy, momentum and the last step's counters.
    pub fn diagnostics(&self) -> Diagnostics {
        Diagnostics::of(self)
    }
}
