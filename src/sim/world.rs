//! `World::step`: one fixed step, as a pipeline of named stages.
//!
//! 1. forces and integration (`Integrator::integrate`): gravity changes the
//!    velocity (`v += F/m dt`), velocity changes the position
//!    (`x += v dt`), in the order the method prescribes; with no gravity
//!    the velocity update is skipped;
//! 2. spatial order (`Grid::reorder_bodies`), only for worlds of at least
//!    [`SPATIAL_ORDER_MIN_BODIES`] spheres with pair collisions: the slots
//!    are sorted into grid cells, so that neighbours in space are
//!    neighbours in memory and the contact solver can cut the work into
//!    independent slabs;
//! 3. collide (`BroadPhase::find_contacts_with`): detect overlapping pairs,
//!    only when the scene has pair collisions;
//! 4. solve contacts: position projection by inverse mass, then the
//!    lesson's V1/V2 along the normal; in `(i, j)` order
//!    (`contact::solve_contacts`), or for spatially ordered worlds slab by
//!    slab in parallel (`contact::solve_contacts_in_slabs`); then, when
//!    `projection_passes > 1`, further projections of the pairs still
//!    overlapping (`contact::project_contacts`), for deep piles;
//! 5. walls (`walls::resolve_walls_after`): last, so that every centre ends
//!    the step inside the box whatever the contacts did; velocity Verlet and
//!    RK4 reflect at the crossing of their parabola, the Euler methods
//!    mirror the overshoot.
//!
//! Resting contact (`restitution.rs`, `WorldConfig::rest_steps`): in the
//! discrete methods an impact slower than the speed gravity adds along its
//! normal in `rest_steps` sub-steps is perfectly inelastic, in stages 4
//! and 5, so that bodies come to rest instead of micro-bouncing.
//!
//! The continuous method replaces the four stages with one
//! (`continuous::advance`): free flight to the earliest time of impact,
//! resolve it, repeat until the step is done. With `substeps = k` the step
//! runs its stages `k` times with `dt / k`.
//!
//! A stage a scene does not use costs nothing. The step is deterministic:
//! the same bodies and config give the same bits, for any number of threads
//! (the stages run on the current rayon pool; see `threads.rs`), and for
//! either broad phase, since both report the same contacts in the same
//! order.

use super::contact::{project_contacts, solve_contacts, solve_contacts_in_slabs};
use super::continuous::{self, EventQueue};
use super::grid::{CellLayout, Grid};
use super::walls::{Flight, clamp_to_box, resolve_walls_after};
use super::{Bodies, BroadPhase, Contact, Diagnostics, Integrator, Vec3, WorldConfig};
use rayon::prelude::*;

/// From this many spheres up (with pair collisions), the world keeps its
/// slots in cell order and solves contacts in parallel slabs. Smaller worlds,
/// every lesson among them, keep the scene order and the lesson's sequential
/// `(i, j)` pass exactly. Below a few thousand spheres the whole state fits
/// in the caches and there is too little work to share between threads.
pub const SPATIAL_ORDER_MIN_BODIES: usize = 4096;

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
    /// Projection passes run after the lesson's pass this step (at most
    /// `projection_passes - 1` per sub-step, summed over sub-steps).
    pub projection_passes: u32,
    /// The largest penetration the last projection pass met, m (0 with no
    /// further pass).
    pub residual_overlap: f64,
    /// The further passes ran out before every pair was within
    /// [`PROJECTION_TOLERANCE`] of touching: the pile stays compressed.
    pub projection_unconverged: bool,
}

/// Further projection passes stop once no pair overlaps by more than this
/// fraction of the largest radius.
pub const PROJECTION_TOLERANCE: f64 = 0.01;

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
        }
    }

    /// Advance the world by one step of `config.dt`.
    pub fn step(&mut self) {
        let finished = self.try_step(&|| false);
        debug_assert!(finished, "a step that nothing interrupts finishes");
    }

    /// Advance the world by one step of `config.dt`, unless `interrupted`
    /// says to stop: it is asked before every sub-step but the first, and
    /// by the continuous method every few hundred impacts.
    /// Returns true when the step finished. A step abandoned part-way
    /// leaves the bodies moved by the sub-steps it took, with `time`,
    /// `steps` and `last` as they were: the caller puts the bodies back
    /// from its own copy (the visualiser's step-back history).
    #[must_use]
    pub fn try_step(&mut self, interrupted: &dyn Fn() -> bool) -> bool {
        let mut stats = StepStats::default();
        let h = self.config.substep_dt();
        for k in 0..self.config.substeps.max(1) {
            if k > 0 && interrupted() {
                return false;
            }
            match self.config.integrator {
                Integrator::Continuous => {
                    self.contacts.clear();
                    let Ok(capped) = continuous::advance(
                        &mut self.bodies,
                        &self.config,
                        h,
                        &mut self.events,
                        &mut stats,
                        interrupted,
                    ) else {
                        return false;
                    };
                    if capped {
                        if self.config.pair_collisions {
                            self.collide(Vec3::ZERO, &mut stats);
                        }
                        continuous::return_to_walls(&mut self.bodies, &self.config, &mut stats);
                    }
                }
                _ => self.discrete_substep(h, &mut stats),
            }
        }
        self.time += self.config.dt;
        self.steps += 1;
        self.last = stats;
        true
    }

    /// A copy of this world's state (config, bodies, time, step count, the
    /// last step's counters and contacts) without its working buffers:
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
        w
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

    /// The four stages of the discrete methods over `h`.
    fn discrete_substep(&mut self, h: f64, stats: &mut StepStats) {
        let config = &self.config;
        config
            .integrator
            .integrate(&mut self.bodies, config.gravity, h);
        let resting = config.resting(h);
        if config.pair_collisions {
            self.collide(resting, stats);
        } else {
            self.contacts.clear();
        }

        let config = &self.config;
        let flight = Flight::of(config.integrator, config.gravity, h);
        let rule = config.wall_rule().with_resting(resting);
        let walls = resolve_walls_after(&mut self.bodies, config.wall_mode, rule, flight);
        stats.wall_impacts += walls.impacts;
        stats.wall_impulse += walls.impulse;
    }

    /// Stages 2 to 4: spatial order, broad and narrow phase, contact solve,
    /// with resting contact below `resting` (`g rest_steps h`; zero: none).
    fn collide(&mut self, resting: Vec3, stats: &mut StepStats) {
        let config = &self.config;
        let bodies = &mut self.bodies;
        let n = bodies.len();
        let broad_phase = config.broad_phase.resolve(n);
        // Only worlds kept in cell order need the layout before the broad
        // phase; the others never pay for it.
        let layout = (n >= SPATIAL_ORDER_MIN_BODIES).then(|| CellLayout::of(bodies));
        if let Some(layout) = layout {
            self.grid.build(bodies, layout);
            self.grid.reorder_bodies(bodies, &mut self.contacts);
        }
        stats.broad_phase = Some(broad_phase);
        stats.pair_tests += match broad_phase {
            BroadPhase::Grid if layout.is_some() => {
                self.grid.find_contacts(bodies, &mut self.contacts)
            }
            other => other.find_contacts_with(&mut self.grid, bodies, &mut self.contacts),
        };
        stats.contacts += self.contacts.len();
        stats.max_overlap = self
            .contacts
            .par_iter()
            .with_min_len(8192)
            .map(|c| c.penetration)
            .reduce(|| 0.0, f64::max)
            .max(stats.max_overlap);
        let rule = config.pair_rule().with_resting(resting);
        stats.contact_slabs = match layout {
            Some(layout) => solve_contacts_in_slabs(bodies, &self.contacts, rule, layout),
            None => {
                solve_contacts(bodies, &self.contacts, rule);
                1
            }
        };
        if config.projection_passes > 1 && !self.contacts.is_empty() {
            let tolerance = PROJECTION_TOLERANCE * bodies.max_radius();
            let mut converged = false;
            for _ in 1..config.projection_passes {
                clamp_to_box(bodies);
                let worst = project_contacts(bodies, &self.contacts, rule, layout);
                stats.projection_passes += 1;
                stats.residual_overlap = worst;
                if worst <= tolerance {
                    converged = true;
                    break;
                }
            }
            stats.projection_unconverged |= !converged;
        }
    }

    /// Take `n` steps.
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    /// The contacts the last step found and resolved.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// Energy, momentum and the last step's counters.
    pub fn diagnostics(&self) -> Diagnostics {
        Diagnostics::of(self)
    }
}
