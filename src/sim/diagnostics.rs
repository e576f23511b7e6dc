//! The readouts of a world: energy, momentum and what the last step did.
//! Energies and momentum are computed on demand in one pass over the bodies;
//! the counters come free from the stages. Potential energy is `m g h`
//! measured from the origin (the floor is `y = 0`): `-m (g . x)`.
//!
//! `lerpit run` prints [`Diagnostics`] as they are, flattened into its JSON
//! report: the field names are the report's keys, and scripts read them.

use super::{Vec3, World};
use serde::Serialize;

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Diagnostics {
    /// Simulated time, s.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Sum of `m v^2 / 2`, J.
    pub kinetic_energy: f64,
    /// Sum of `-m (g . x)`, J.
    pub potential_energy: f64,
    /// Kinetic plus potential, J.
    pub total_energy: f64,
    /// Sum of `m v`, kg m/s.
    pub momentum: Vec3,
    /// Overlapping pairs found by the last step.
    pub contacts: usize,
    /// Pair tests made by the last step.
    pub pair_tests: u64,
    /// Largest penetration found by the last step, m.
    pub max_overlap: f64,
    /// Wall impacts in the last step.
    pub wall_impacts: usize,
    /// Spheres asleep after the last step (`sleep.rs`).
    pub asleep: usize,
}

impl Diagnostics {
    pub fn of(world: &World) -> Self {
        let b = &world.bodies;
        let g = world.config.gravity;
        let mut kinetic = 0.0;
        let mut potential = 0.0;
        let mut momentum = Vec3::ZERO;
        for i in 0..b.len() {
            let (m, v) = (b.mass[i], b.velocity[i]);
            kinetic += 0.5 * m * v.length_squared();
            potential -= m * g.dot(b.position[i]);
            momentum += m * v;
        }
        Self {
            time: world.time,
            steps: world.steps,
            kinetic_energy: kinetic,
            potential_energy: potential,
            total_energy: kinetic + potential,
            momentum,
            contacts: world.last.contacts,
            pair_tests: world.last.pair_tests,
            max_overlap: world.last.max_overlap,
            wall_impacts: world.last.wall_impacts,
            asleep: world.last.asleep,
        }
    }
}
