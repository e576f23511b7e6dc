//! Elastic collisions without gravity: what each method conserves.
//!
//! The collisions lesson with gravity off and every restitution 1 (walls
//! flip): no energy enters or leaves, so the kinetic energy must stay at
//! its start; the walls change the momentum, by impulses every method
//! reports, so `P(t) - P(0) - sum of wall impulses` must stay at 0. Both
//! are measured relative to their scales (`E(0)`, and `sum m |v|` at the
//! start). The continuous method runs until it has resolved a given number
//! of pair collisions; the discrete methods cover the same simulated time
//! at each `dt`.

use crate::scene::Lesson;
use crate::sim::{Integrator, Vec3, WallMode, World};
use serde::Serialize;

/// One run; a line of `conservation.csv`, with the field names as its
/// header.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Drift {
    pub method: Integrator,
    /// s.
    pub dt: f64,
    /// Simulated time, s.
    pub time: f64,
    /// Pair collisions resolved (continuous) or contacts found (discrete).
    pub collisions: u64,
    /// Largest `|E(t) - E(0)| / E(0)` over the run.
    pub energy_drift: f64,
    /// Largest `|P(t) - P(0) - J_walls(t)| / sum m |v(0)|` over the run.
    pub momentum_error: f64,
}

/// The elastic, gravity-free collisions lesson.
pub fn elastic_world(method: Integrator, dt: f64) -> Result<World, String> {
    let mut scene = Lesson::Collisions.scene();
    let w = &mut scene.world;
    w.gravity = Vec3::ZERO;
    w.pair_restitution = 1.0;
    w.wall_mode = WallMode::Flip;
    w.wall_restitution = 1.0;
    w.integrator = method;
    w.dt = dt;
    scene.build().map_err(|e| e.to_string())
}

/// Simulated time after which a run that counts collisions gives up.
pub const MAX_SECONDS: f64 = 1000.0;

/// Run until `collisions` pair collisions (when `Some`; an error if they do
/// not come within [`MAX_SECONDS`]) or for `seconds`.
pub fn drift(
    method: Integrator,
    dt: f64,
    collisions: Option<u64>,
    seconds: f64,
) -> Result<Drift, String> {
    let mut w = elastic_world(method, dt)?;
    let d0 = w.diagnostics();
    let scale: f64 = (0..w.bodies.len())
        .map(|i| w.bodies.mass[i] * w.bodies.velocity[i].length())
        .sum();
    let mut impulse = Vec3::ZERO;
    let mut count = 0u64;
    let (mut energy_drift, mut momentum_error): (f64, f64) = (0.0, 0.0);
    loop {
        let done = match collisions {
            Some(n) if w.time >= MAX_SECONDS => {
                return Err(format!(
                    "{}: only {count} of {n} collisions in {MAX_SECONDS} s",
                    method.name()
                ));
            }
            Some(n) => count >= n,
            None => w.time >= seconds - 0.5 * dt,
        };
        if done {
            break;
        }
        w.step();
        count += w.last.contacts as u64;
        impulse += w.last.wall_impulse;
        let d = w.diagnostics();
        energy_drift =
            energy_drift.max((d.kinetic_energy - d0.kinetic_energy).abs() / d0.kinetic_energy);
        momentum_error = momentum_error.max((d.momentum - d0.momentum - impulse).length() / scale);
    }
    Ok(Drift {
        method,
        dt,
        time: w.steps as f64 * dt,
        collisions: count,
        energy_drift,
        momentum_error,
    })
}
