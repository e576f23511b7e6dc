//! Elastic collisions without gravity: what each method conserves.
//!
//! The collisions lesson with gravity off and every restitution 1 (walls
//! flip): no energy enters or leaves, so the kinetic energy must stay at
//! its start; the walls change the momentum, by impulses every method
//! reports, so `P(t) - P(0) - sum of wall impulses` must stay at 0. Both
//! are measured relative to their scales (`E(0)`, and `sum m |v|` at the
//! start). The continuous method runs until it has resolved a given number
//! of pair collisions; the discrete methods cover the same simulated time
//! at each `dt`. A [`Plan`] says how many collisions and which `dt`s;
//! [`run`] makes every run of it.

use super::sweep::{LARGEST_DT, log_spaced};
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
pub(crate) fn elastic_world(method: Integrator, dt: f64) -> Result<World, String> {
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
pub(crate) const MAX_SECONDS: f64 = 1000.0;

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

/// Pair collisions the continuous method resolves in the full study.
pub(crate) const COLLISIONS: u64 = 10_000;
/// The continuous method's time step, s.
pub(crate) const CONTINUOUS_DT: f64 = 1.0 / 240.0;

/// What the conservation study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Pair collisions the continuous method resolves; its simulated time
    /// is then every discrete run's.
    pub collisions: u64,
    /// The discrete methods' time steps, s, largest first.
    pub dts: Vec<f64>,
}

impl Plan {
    /// [`COLLISIONS`] collisions; two decades of `dt` in eight steps.
    pub(crate) fn full() -> Self {
        Self {
            collisions: COLLISIONS,
            dts: log_spaced(LARGEST_DT, 2.0, 8),
        }
    }

    /// A twentieth of the collisions; one decade in three steps.
    pub(crate) fn quick() -> Self {
        Self {
            collisions: COLLISIONS / 20,
            dts: log_spaced(LARGEST_DT, 1.0, 3),
        }
    }

    /// How many runs the plan makes.
    pub(crate) fn runs(&self) -> usize {
        1 + Integrator::DISCRETE.len() * self.dts.len()
    }
}

/// Run the plan: the continuous method first, then every discrete method
/// at every `dt` for as long. `progress` hears about every run before it
/// starts (`done`, `total`, a description), and once more at the end.
pub fn run(
    plan: &Plan,
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<Vec<Drift>, String> {
    let total = plan.runs();
    progress(
        0,
        total,
        &format!(
            "conservation, continuous method to {} collisions",
            plan.collisions
        ),
    );
    let cont = drift(
        Integrator::Continuous,
        CONTINUOUS_DT,
        Some(plan.collisions),
        0.0,
    )?;
    let seconds = cont.time;
    let mut out = vec![cont];
    for m in Integrator::DISCRETE {
        for &dt in &plan.dts {
            progress(
                out.len(),
                total,
                &format!("conservation, {} dt={dt:.2e}", m.name()),
            );
            out.push(drift(m, dt, None, seconds)?);
        }
    }
    progress(total, total, "done");
    Ok(out)
}
