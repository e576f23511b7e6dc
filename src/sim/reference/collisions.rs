//! The collisions reference: the exact motion of colliding spheres, event
//! by event, for short horizons.
//!
//! Between impacts every sphere flies a parabola under the same gravity;
//! the earliest wall or pair impact is found exactly (a quadratic), resolved
//! at its instant, and the search starts again. This is the continuous
//! method's own event loop run over the whole horizon at once, with no
//! step: the only approximation left is rounding.
//!
//! Many colliding spheres are chaotic: a difference of `delta` in one
//! position grows roughly like `delta exp(t / tau)`. Rounding (`1e-16`
//! relative) is such a difference, so beyond a predictability horizon even
//! two exact computations disagree, and positions are no longer a fair
//! measure of error: statistics and invariants (energy against time,
//! collision counts) are. [`predictability_horizon`] measures it: the time
//! at which two event-driven runs whose starts differ by `delta` drift
//! apart by `tolerance` (RMS over the bodies).

use crate::sim::{Bodies, Integrator, Vec3, World};

/// Positions and velocities of the bodies of `world` advanced by `t`
/// seconds event by event, or `None` if the event cap of the continuous
/// method was reached (the exact motion asked for too many impacts).
pub(crate) fn state_at(world: &World, t: f64) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
    let mut w = exact_world(exact_config(world), world.bodies.clone());
    if t > 0.0 {
        w.config.dt = t;
        w.step();
        if w.last.event_cap_reached {
            return None;
        }
    }
    Some((w.bodies.position, w.bodies.velocity))
}

/// A world that runs the event-driven motion of `bodies` from where they
/// are: not one entering the continuous method, which would first push
/// apart the overlaps it was given (`continuous::separate_overlaps`).
fn exact_world(config: crate::sim::WorldConfig, bodies: Bodies) -> World {
    let mut w = World::new(config, bodies);
    w.restore_method_before(Some(Integrator::Continuous));
    w
}

fn exact_config(world: &World) -> crate::sim::WorldConfig {
    let mut config = world.config.clone();
    config.integrator = Integrator::Continuous;
    config.substeps = 1;
    config.rest_threshold = 0.0;
    config.rest_steps = 0.0;
    config
}

/// Root mean square distance between two sets of positions, m.
pub fn rms_distance(a: &[Vec3], b: &[Vec3]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    let sum: f64 = a.iter().zip(b).map(|(p, q)| p.distance_squared(*q)).sum();
    (sum / a.len() as f64).sqrt()
}

/// The first sample time (every `interval` s, up to `t_max`) at which the
/// event-driven motion of `world` and of a copy with body 0 moved by
/// `delta` m along x are more than `tolerance` m apart (RMS); `None` if
/// they stay closer up to `t_max` or the event cap was reached.
pub fn predictability_horizon(
    world: &World,
    delta: f64,
    tolerance: f64,
    interval: f64,
    t_max: f64,
) -> Option<f64> {
    let mut config = exact_config(world);
    config.dt = interval;
    let mut a = exact_world(config.clone(), world.bodies.clone());
    let mut moved: Bodies = world.bodies.clone();
    if let Some(p) = moved.position.first_mut() {
        p.x += delta;
    }
    let mut b = exact_world(config, moved);
    while a.time < t_max {
        a.step();
        b.step();
        if a.last.event_cap_reached || b.last.event_cap_reached {
            return None;
        }
        if rms_distance(&a.bodies.position, &b.bodies.position) > tolerance {
            return Some(a.time);
        }
    }
    None
}
