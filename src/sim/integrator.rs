//! The integration step: how velocity and position move over `dt`.
//!
//! The lesson's two equations are `x(t+dt) = x(t) + v(t) dt` and
//! `v(t+dt) = v(t) + F/m dt`. The order in which they are applied is the
//! method:
//!
//! - explicit Euler: position first, with the old velocity;
//! - semi-implicit (symplectic) Euler: velocity first, position with the new one;
//! - velocity Verlet: `x += v dt + a dt^2 / 2`, then `v += (a + a') dt / 2`.
//!
//! The only force in the lessons is uniform gravity, so the acceleration is
//! the same vector `g` for every body and no per-body force buffer is kept.
//! With a constant `a`, Verlet reproduces the parabola exactly between
//! impacts.

use super::{Bodies, Vec3};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    ExplicitEuler,
    SemiImplicitEuler,
    VelocityVerlet,
}

impl Integrator {
    pub const ALL: [Integrator; 3] = [
        Integrator::ExplicitEuler,
        Integrator::SemiImplicitEuler,
        Integrator::VelocityVerlet,
    ];

    /// The name used on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::ExplicitEuler => "explicit-euler",
            Integrator::SemiImplicitEuler => "semi-implicit-euler",
            Integrator::VelocityVerlet => "velocity-verlet",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The next method in [`Integrator::ALL`], wrapping around.
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|&m| m == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// Advance every body by `dt` under the uniform acceleration `a`.
    /// `a == 0` skips the velocity update entirely: no forces, no work.
    pub fn integrate(self, bodies: &mut Bodies, a: Vec3, dt: f64) {
        let forces = a != Vec3::ZERO;
        let (x, v) = (&mut bodies.position, &mut bodies.velocity);
        match self {
            _ if !forces => integrate_positions(x, v, dt),
            Integrator::ExplicitEuler => {
                integrate_positions(x, v, dt);
                integrate_velocities(v, a, dt);
            }
            Integrator::SemiImplicitEuler => {
                integrate_velocities(v, a, dt);
                integrate_positions(x, v, dt);
            }
            Integrator::VelocityVerlet => {
                let half_a_dt2 = 0.5 * a * dt * dt;
                for (x, v) in x.iter_mut().zip(v.iter_mut()) {
                    *x += *v * dt + half_a_dt2;
                    // a(t + dt) == a(t): the force is uniform and constant.
                    *v += a * dt;
                }
            }
        }
    }
}

/// `v += a dt` for every body.
pub fn integrate_velocities(v: &mut [Vec3], a: Vec3, dt: f64) {
    let dv = a * dt;
    for v in v {
        *v += dv;
    }
}

/// `x += v dt` for every body.
pub fn integrate_positions(x: &mut [Vec3], v: &[Vec3], dt: f64) {
    for (x, v) in x.iter_mut().zip(v) {
        *x += *v * dt;
    }
}
