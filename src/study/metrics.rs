//! What the study measures, and how.
//!
//! Error, against the exact reference of the scene:
//! - **RMS position error** at a fixed horizon `T`:
//!   `sqrt(mean_i |x_i(T) - x_ref_i(T)|^2)`, m;
//! - **bounce-time error**: the largest `|t_k - t_ref_k|` over the first
//!   [`BOUNCES`] floor impacts of every sphere, s. A method's impact time
//!   is read from the first state after the impact (the end of the step in
//!   which the vertical velocity turned upward): the exact free flight is
//!   traced back from it to the floor. For the continuous method that gives
//!   the instant it resolved; for a discrete method, the instant its
//!   trajectory implies;
//! - **apex-ratio error**: the largest `|h_{k+1} / h_k - c_r^2|` over the
//!   same bounces, with `h_k` the apex height above the floor implied by
//!   that first state after impact `k` (`y - r + v_y^2 / (2 g)`); only
//!   spheres whose exact first bounces never reach the ceiling count;
//! - **energy error**: `|E(T) - E_ref(T)| / E_ref(0)`, kinetic plus
//!   potential;
//! - **time-to-rest error** and **leftover kinetic energy** (the rest check
//!   of the stability suite): when the sphere last came to rest against the
//!   exact `sqrt(2h/g)(1 + c_r)/(1 - c_r)`, and the kinetic energy left at
//!   a time well after it.
//!
//! Cost: wall time of the run, without any measuring, as the fastest of
//! several repeats (on a shared machine, other work only ever adds time),
//! per simulated second and per body-step (a step of one body). Compare
//! costs from one release build on one machine only.
//!
//! Convergence: the order `p` of a method is the least-squares slope of
//! `log10 error` against `log10 dt` over the points above the rounding
//! floor ([`ROUNDING_FLOOR`]).

use crate::sim::{Vec3, World};

/// Floor impacts compared per sphere.
pub(crate) const BOUNCES: usize = 5;
/// Errors below this are rounding: they say nothing about the order.
pub(crate) const ROUNDING_FLOOR: f64 = 1e-12;

/// Root mean square distance between two sets of positions, m.
pub(crate) fn rms_error(a: &[Vec3], b: &[Vec3]) -> f64 {
    crate::sim::reference::collisions::rms_distance(a, b)
}

/// Kinetic plus potential energy of bodies with masses `m` at `x`, `v`
/// under gravity `g` (potential `-m g . x`).
pub(crate) fn energy(m: &[f64], x: &[Vec3], v: &[Vec3], g: Vec3) -> f64 {
    m.iter()
        .zip(x)
        .zip(v)
        .map(|((&m, x), v)| 0.5 * m * v.length_squared() - m * g.dot(*x))
        .sum()
}

/// A floor impact read from the first state after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SeenBounce {
    /// s.
    pub time: f64,
    /// Apex height above the floor of the flight that follows, m.
    pub apex: f64,
}

/// Trace the free flight back from a state just after a floor impact:
/// `(time of impact, apex height above the floor)`. `height` is `y - r`,
/// `vy` the upward speed, `g` the magnitude of gravity.
pub(crate) fn trace_back(t: f64, height: f64, vy: f64, g: f64) -> SeenBounce {
    let height = height.max(0.0);
    let apex = height + vy * vy / (2.0 * g);
    let since = if g > 0.0 {
        (vy * vy + 2.0 * g * height).sqrt() / g - vy / g
    } else {
        0.0
    };
    SeenBounce {
        time: t - since,
        apex,
    }
}

/// Watches a world step by step and records each sphere's floor impacts
/// (gravity along `-y`).
#[derive(Clone, Debug)]
pub(crate) struct BounceLog {
    g: f64,
    last_vy: Vec<f64>,
    pub bounces: Vec<Vec<SeenBounce>>,
}

impl BounceLog {
    pub fn new(world: &World) -> Self {
        Self {
            g: -world.config.gravity.y,
            last_vy: world.bodies.velocity.iter().map(|v| v.y).collect(),
            bounces: vec![Vec::new(); world.bodies.len()],
        }
    }

    /// Call after every step. Time is `steps dt`, exact to rounding.
    pub(crate) fn observe(&mut self, world: &World) {
        let b = &world.bodies;
        let t = world.steps as f64 * world.config.dt;
        for i in 0..b.len() {
            let vy = b.velocity[i].y;
            let was = self.last_vy[i];
            self.last_vy[i] = vy;
            if was < 0.0 && vy > 0.0 && self.bounces[i].len() < BOUNCES + 1 {
                let height = b.position[i].y - b.radius[i];
                self.bounces[i].push(trace_back(t, height, vy, self.g));
            }
        }
    }
}

/// Bounce-time and apex-ratio errors of `seen` against the exact floor
/// impacts `exact` (times; `None` for a sphere whose exact bounces touch
/// the ceiling and so has no apex ratio to compare), restitution `c`.
pub(crate) fn bounce_errors(
    seen: &[Vec<SeenBounce>],
    exact: &[(Vec<f64>, bool)],
    c: f64,
) -> (f64, f64) {
    let mut time_error: f64 = 0.0;
    let mut apex_error: f64 = 0.0;
    for (s, (t_ref, clean)) in seen.iter().zip(exact) {
        for (a, b) in s.iter().zip(t_ref).take(BOUNCES) {
            time_error = time_error.max((a.time - b).abs());
        }
        if *clean {
            for w in s.windows(2).take(BOUNCES - 1) {
                if w[0].apex > 0.0 {
                    apex_error = apex_error.max((w[1].apex / w[0].apex - c * c).abs());
                }
            }
        }
    }
    (time_error, apex_error)
}

/// Least-squares slope of `log10 error` against `log10 dt`, over the points
/// whose error is above [`ROUNDING_FLOOR`]; `None` with fewer than two.
pub(crate) fn fitted_order(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(dt, e)| *dt > 0.0 && e.is_finite() && *e > ROUNDING_FLOOR)
        .map(|(dt, e)| (dt.log10(), e.log10()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// What the fitted order of a method's error against `dt` says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Convergence {
    /// The error falls as `dt^p`.
    Order(f64),
    /// The error grows as `dt` shrinks (a negative slope): rounding
    /// accumulated over more steps.
    Diverging(f64),
    /// Every error at rounding level: no order to fit.
    Rounding,
}

/// The convergence of `(dt, error)` points (see [`fitted_order`]).
pub(crate) fn convergence(points: &[(f64, f64)]) -> Convergence {
    match fitted_order(points) {
        Some(p) if p < 0.0 => Convergence::Diverging(p),
        Some(p) => Convergence::Order(p),
        None => Convergence::Rounding,
    }
}

/// The median of `v` (sorted in place); 0 for none.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}
