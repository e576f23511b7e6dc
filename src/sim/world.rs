//! `World::step`: one fixed step, as a pipeline of named stages.
//!
//! 1. forces and integration (`Integrator::integrate`): gravity changes the
//!    velocity (`v += F/m dt`), velocity changes the position
//!    (`x += v dt`), in the order the method prescribes; with no gravity
//!    the velocity update is skipped;
//! 2. collide (`BroadPhase::find_contacts`): detect overlapping pairs, only
//!    when the scene has pair collisions;
//! 3. solve contacts (`contact::solve_contacts`): position projection by
//!    inverse mass, then the lesson's V1/V2 along the normal;
//! 4. walls (`walls::resolve_walls`): last, so that every centre ends the
//!    step inside the box whatever the contacts did.
//!
//! The continuous method replaces the four stages with one
//! (`continuous::advance`): free flight to the earliest time of impact,
//! resolve it, repeat until the step is done. With `substeps = k` the step
//! runs its stages `k` times with `dt / k`.
//!
//! A stage a scene does not use costs nothing. The step is deterministic:
//! the same bodies and config give the same bits.

use super::contact::solve_contacts;
use super::continuous::{self, EventQueue};
use super::walls::resolve_walls;
use super::{Bodies, Contact, Diagnostics, Integrator, Vec3, WorldConfig};

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
    /// finished it with the discrete stages.
    pub event_cap_reached: bool,
}

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
        }
    }

    /// Advance the world by one step of `config.dt`.
    pub fn step(&mut self) {
        let mut stats = StepStats::default();
        let h = self.config.substep_dt();
        for _ in 0..self.config.substeps.max(1) {
            match self.config.integrator {
                Integrator::Continuous => continuous::advance(
                    &mut self.bodies,
                    &self.config,
                    h,
                    &mut self.events,
                    &mut self.contacts,
                    &mut stats,
                ),
                _ => self.discrete_substep(h, &mut stats),
            }
        }
        self.time += self.config.dt;
        self.steps += 1;
        self.last = stats;
    }

    /// The four stages of the discrete methods over `h`.
    fn discrete_substep(&mut self, h: f64, stats: &mut StepStats) {
        let config = &self.config;
        config
            .integrator
            .integrate(&mut self.bodies, config.gravity, h);

        if config.pair_collisions {
            stats.pair_tests += config
                .broad_phase
                .find_contacts(&self.bodies, &mut self.contacts);
            stats.contacts += self.contacts.len();
            stats.max_overlap = self
                .contacts
                .iter()
                .map(|c| c.penetration)
                .fold(stats.max_overlap, f64::max);
            solve_contacts(&mut self.bodies, &self.contacts, config.pair_rule());
        } else {
            self.contacts.clear();
        }

        let walls = resolve_walls(&mut self.bodies, config.wall_mode, config.wall_rule());
        stats.wall_impacts += walls.impacts;
        stats.wall_impulse += walls.impulse;
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
