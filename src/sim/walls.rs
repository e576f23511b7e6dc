//! The box `[0, 1]^3`. A sphere of radius `r` must keep its centre in
//! `[r, 1 - r]` on every axis.
//!
//! When a step carries a centre past a wall while moving into it, the
//! velocity component normal to that wall is reversed and scaled by the
//! restitution `c` (`c = 1` for `flip`), and the overshoot is mirrored back
//! into the box and scaled the same way: the distance travelled after the
//! impact is `c` times what the step had carried it beyond the wall. For
//! `flip` this makes the ping-pong path an exact triangle wave at any `dt`.
//! A centre outside while already moving away (another stage pushed it
//! there) is only put back on the wall. Whatever happened, every centre
//! ends the stage inside `[r, 1 - r]`.
//!
//! An impact slower than the rest threshold uses `c = 0`
//! ([`Restitution`]). The stage also sums the impulses the walls gave
//! (`m` times the velocity change), so momentum can be balanced.
//!
//! Each sphere meets the walls on its own, so the stage runs in parallel
//! (rayon) over fixed chunks of spheres; the chunks' impulses are added in
//! chunk order, so every bit is the same for any number of threads.

use super::restitution::Restitution;
use super::{Bodies, Vec3, WallMode};
use rayon::prelude::*;

/// Spheres per parallel task, and per partial sum of the impulse.
const CHUNK: usize = 4096;

/// What the wall stage did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallReport {
    /// Impacts that reversed a velocity component.
    pub impacts: usize,
    /// Sum of the impulses the walls gave, kg m/s.
    pub impulse: Vec3,
}

/// Resolve wall contacts for every body. `flip` walls keep the speed;
/// `restitution` walls use `restitution` (a coefficient, or a coefficient
/// with its rest threshold).
pub fn resolve_walls(
    bodies: &mut Bodies,
    mode: WallMode,
    restitution: impl Into<Restitution>,
) -> WallReport {
    let rule = mode.rule(restitution.into());
    let Bodies {
        position,
        velocity,
        radius,
        mass,
        ..
    } = bodies;
    let chunks: Vec<WallReport> = position
        .par_chunks_mut(CHUNK)
        .zip(velocity.par_chunks_mut(CHUNK))
        .zip(radius.par_chunks(CHUNK))
        .zip(mass.par_chunks(CHUNK))
        .map(|(((x, v), r), m)| {
            let mut report = WallReport::default();
            for (((x, v), &r), &m) in x.iter_mut().zip(v).zip(r).zip(m) {
                resolve_sphere(x, v, r, m, rule, &mut report);
            }
            report
        })
        .collect();
    chunks
        .into_iter()
        .fold(WallReport::default(), |total, c| WallReport {
            impacts: total.impacts + c.impacts,
            impulse: total.impulse + c.impulse,
        })
}

/// Keep one sphere of radius `r` and mass `m` in the box, adding to `report`.
#[inline]
fn resolve_sphere(
    x: &mut Vec3,
    v: &mut Vec3,
    r: f64,
    m: f64,
    rule: Restitution,
    report: &mut WallReport,
) {
    let (lo, hi) = (r, 1.0 - r);
    for axis in 0..3 {
        let (p, u) = (&mut x[axis], &mut v[axis]);
        let before = *u;
        if *p < lo {
            if *u < 0.0 {
                let c = rule.at(-*u);
                *p = lo + c * (lo - *p);
                *u *= -c;
                report.impacts += 1;
            }
            *p = p.clamp(lo, hi);
        } else if *p > hi {
            if *u > 0.0 {
                let c = rule.at(*u);
                *p = hi - c * (*p - hi);
                *u *= -c;
                report.impacts += 1;
            }
            *p = p.clamp(lo, hi);
        }
        report.impulse[axis] += m * (*u - before);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Body, Vec3};

    fn one(position: Vec3, velocity: Vec3) -> Bodies {
        [Body {
            position,
            velocity,
            radius: 0.1,
            mass: 1.0,
        }]
        .into_iter()
        .collect()
    }

    #[test]
    fn an_overshoot_is_mirrored_and_scaled_by_restitution() {
        let mut b = one(Vec3::new(0.5, 0.04, 0.95), Vec3::new(0.0, -2.0, 1.0));
        let impacts = resolve_walls(&mut b, WallMode::Restitution, 0.5).impacts;
        assert_eq!(impacts, 2);
        // Floor: 0.06 past y = 0.1, half of it mirrored back; speed halved.
        assert!((b.position[0].y - 0.13).abs() < 1e-15);
        assert_eq!(b.velocity[0].y, 1.0);
        // Far z wall at 0.9: 0.05 past it.
        assert!((b.position[0].z - 0.875).abs() < 1e-15);
        assert_eq!(b.velocity[0].z, -0.5);
    }

    #[test]
    fn flip_keeps_the_speed_whatever_the_restitution_setting() {
        let mut b = one(Vec3::new(0.5, 0.95, 0.5), Vec3::new(0.0, 1.0, 0.0));
        resolve_walls(&mut b, WallMode::Flip, 0.2);
        assert_eq!(b.velocity[0].y, -1.0);
        assert!((b.position[0].y - 0.85).abs() < 1e-15);
    }

    #[test]
    fn a_centre_outside_but_moving_away_is_only_put_back_on_the_wall() {
        let mut b = one(Vec3::new(0.05, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(resolve_walls(&mut b, WallMode::Restitution, 0.9).impacts, 0);
        assert_eq!(b.position[0].x, 0.1);
        assert_eq!(b.velocity[0].x, 1.0);
    }

    #[test]
    fn a_huge_overshoot_still_ends_inside_the_box() {
        let mut b = one(Vec3::new(0.5, -3.0, 0.5), Vec3::new(0.0, -100.0, 0.0));
        resolve_walls(&mut b, WallMode::Flip, 1.0);
        assert_eq!(b.position[0].y, 0.9);
    }
}
