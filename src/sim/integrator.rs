//! The integration step: how velocity and position move over `dt`.
//!
//! The lesson's two equations are `x(t+dt) = x(t) + v(t) dt` and
//! `v(t+dt) = v(t) + F/m dt`. The order in which they are applied is the
//! method:
//!
//! - explicit Euler: position first, with the old velocity;
//! - semi-implicit (symplectic) Euler: velocity first, position with the new one;
//! - velocity Verlet: `x += v dt + a dt^2 / 2`, then `v += (a + a') dt / 2`;
//! - classical Runge-Kutta (RK4): four evaluations of `(dx/dt, dv/dt) =
//!   (v, a)` per step, weighted 1, 2, 2, 1;
//! - continuous: the exact free flight `x += v dt + a dt^2 / 2`, `v += a dt`,
//!   split at every time of impact inside the step. `World::step` hands this
//!   method to [`continuous`](super::continuous), which owns the impacts;
//!   [`Integrator::integrate`] gives only its free flight.
//!
//! The only force in the lessons is uniform gravity, so the acceleration is
//! the same vector `g` for every body and no per-body force buffer is kept.
//! With a constant `a`, Verlet and RK4 reproduce the parabola exactly
//! between impacts (RK4 at four times the work): in these scenes the error
//! of every method comes from the impacts, not from the free flight.
//!
//! Every body advances on its own, so the loops run in parallel (rayon)
//! with the same bits for any number of threads.

use super::config::choice;
use super::sleep::is_asleep;
use super::{Bodies, Vec3};
use rayon::prelude::*;
use strum::EnumCount;

/// Bodies per parallel task.
const CHUNK: usize = 4096;

choice! {
    /// The methods, in the order the lessons, tables and charts list them.
    /// The names (`explicit-euler`, ...) are the variants' in kebab case.
    pub enum Integrator: "integrator" {
        /// Position first, with the old velocity, then velocity.
        ExplicitEuler,
        /// Velocity first, then position with the new velocity (symplectic).
        SemiImplicitEuler,
        /// Position with half the acceleration's term, then velocity.
        VelocityVerlet,
        /// Classical Runge-Kutta: four evaluations a step.
        Rk4,
        /// Time of impact inside the step, for walls and pairs.
        Continuous,
    }
}

impl Integrator {
    /// The methods that detect contacts only at the end of a step: every
    /// one but [`Integrator::Continuous`].
    pub const DISCRETE: [Integrator; Integrator::COUNT - 1] = {
        let mut out = [Integrator::ExplicitEuler; Integrator::COUNT - 1];
        let (mut i, mut k) = (0, 0);
        while i < Self::COUNT {
            if Self::ALL[i].is_discrete() {
                out[k] = Self::ALL[i];
                k += 1;
            }
            i += 1;
        }
        assert!(k == out.len(), "one method is continuous");
        out
    };

    /// Whether contacts are found only at the end of a step.
    pub(crate) const fn is_discrete(self) -> bool {
        !matches!(self, Integrator::Continuous)
    }

    /// The position update of [`Integrator::integrate`] from the velocity
    /// `v0` a body began the step with, in the lesson's terms
    /// `x += v dt (+ a dt^2 / 2)`: the velocity `v` it moves with (the one
    /// it began with, or for semi-implicit Euler the one it ends with) and
    /// the parabola's term, `Some` for the methods that follow the exact
    /// parabola of a uniform `a`.
    pub fn position_update(self, v0: Vec3, a: Vec3, dt: f64) -> (Vec3, Option<Vec3>) {
        match self {
            Integrator::ExplicitEuler => (v0, None),
            Integrator::SemiImplicitEuler => (v0 + a * dt, None),
            Integrator::Rk4 | Integrator::VelocityVerlet | Integrator::Continuous => {
                (v0, Some(0.5 * a * dt * dt))
            }
        }
    }

    /// Advance every body by `dt` under the uniform acceleration `a`.
    /// `a == 0` skips the velocity update entirely: no forces, no work.
    pub(crate) fn integrate(self, bodies: &mut Bodies, a: Vec3, dt: f64) {
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
            Integrator::Rk4 => {
                x.par_iter_mut()
                    .zip(v.par_iter_mut())
                    .with_min_len(CHUNK)
                    .for_each(|(x, v)| (*x, *v) = rk4_step(*x, *v, |_, _| a, dt));
            }
            Integrator::VelocityVerlet | Integrator::Continuous => {
                let half_a_dt2 = 0.5 * a * dt * dt;
                x.par_iter_mut()
                    .zip(v.par_iter_mut())
                    .with_min_len(CHUNK)
                    .for_each(|(x, v)| {
                        *x += *v * dt + half_a_dt2;
                        // a(t + dt) == a(t): the force is uniform and constant.
                        *v += a * dt;
                    });
            }
        }
    }
}

impl Integrator {
    /// As [`Integrator::integrate`], leaving the sleeping spheres
    /// (`sleep.rs`) where they are, at rest: the same bits for every sphere
    /// awake.
    pub(crate) fn integrate_awake(self, bodies: &mut Bodies, a: Vec3, dt: f64) {
        bodies
            .position
            .par_iter_mut()
            .zip(bodies.velocity.par_iter_mut())
            .zip(bodies.rest.par_iter())
            .with_min_len(CHUNK)
            .for_each(|((x, v), &rest)| {
                if !is_asleep(rest) {
                    self.integrate_one(x, v, a, dt);
                }
            });
    }

    /// As [`Integrator::integrate`], for the spheres of slots `slots`
    /// only: the same bits as for every sphere.
    pub(crate) fn integrate_slots(self, bodies: &mut Bodies, slots: &[u32], a: Vec3, dt: f64) {
        for &k in slots {
            let k = k as usize;
            self.integrate_one(&mut bodies.position[k], &mut bodies.velocity[k], a, dt);
        }
    }

    /// One body's step of [`Integrator::integrate`], with the same
    /// operations, so the same bits.
    #[inline(always)]
    fn integrate_one(self, x: &mut Vec3, v: &mut Vec3, a: Vec3, dt: f64) {
        match self {
            _ if a == Vec3::ZERO => *x += *v * dt,
            Integrator::ExplicitEuler => {
                *x += *v * dt;
                *v += a * dt;
            }
            Integrator::SemiImplicitEuler => {
                *v += a * dt;
                *x += *v * dt;
            }
            Integrator::Rk4 => (*x, *v) = rk4_step(*x, *v, |_, _| a, dt),
            Integrator::VelocityVerlet | Integrator::Continuous => {
                *x += *v * dt + 0.5 * a * dt * dt;
                *v += a * dt;
            }
        }
    }
}

/// One classical Runge-Kutta step of `dx/dt = v`, `dv/dt = accel(x, v)`.
#[inline]
pub(crate) fn rk4_step(
    x: Vec3,
    v: Vec3,
    accel: impl Fn(Vec3, Vec3) -> Vec3,
    dt: f64,
) -> (Vec3, Vec3) {
    let h = 0.5 * dt;
    let (k1x, k1v) = (v, accel(x, v));
    let (k2x, k2v) = (v + k1v * h, accel(x + k1x * h, v + k1v * h));
    let (k3x, k3v) = (v + k2v * h, accel(x + k2x * h, v + k2v * h));
    let (k4x, k4v) = (v + k3v * dt, accel(x + k3x * dt, v + k3v * dt));
    let sixth = dt / 6.0;
    (
        x + (k1x + 2.0 * k2x + 2.0 * k3x + k4x) * sixth,
        v + (k1v + 2.0 * k2v + 2.0 * k3v + k4v) * sixth,
    )
}

/// `v += a dt` for every body.
pub(crate) fn integrate_velocities(v: &mut [Vec3], a: Vec3, dt: f64) {
    let dv = a * dt;
    v.par_iter_mut().with_min_len(CHUNK).for_each(|v| *v += dv);
}

/// `x += v dt` for every body.
pub(crate) fn integrate_positions(x: &mut [Vec3], v: &[Vec3], dt: f64) {
    x.par_iter_mut()
        .zip(v.par_iter())
        .with_min_len(CHUNK)
        .for_each(|(x, v)| *x += *v * dt);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Body;

    #[test]
    fn the_position_update_in_the_lessons_terms_is_the_step_each_method_takes() {
        let (x0, v0, a, dt) = (
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(1.0, 1.0, -0.5),
            Vec3::new(0.0, -9.81, 0.0),
            1.0 / 30.0,
        );
        for method in Integrator::ALL.into_iter().filter(|m| m.is_discrete()) {
            let mut bodies: Bodies = [Body {
                position: x0,
                velocity: v0,
                radius: 0.05,
                mass: 1.0,
            }]
            .into_iter()
            .collect();
            method.integrate(&mut bodies, a, dt);
            let (v, parabola) = method.position_update(v0, a, dt);
            let x = x0 + v * dt + parabola.unwrap_or(Vec3::ZERO);
            assert!(
                (bodies.position[0] - x).length() < 1e-15,
                "{method:?}: {} against {x}",
                bodies.position[0]
            );
            assert_eq!(
                parabola.is_some(),
                matches!(method, Integrator::VelocityVerlet | Integrator::Rk4),
                "{method:?}"
            );
        }
    }
}
