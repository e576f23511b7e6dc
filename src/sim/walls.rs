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

use super::{Bodies, WallMode};

/// Resolve wall contacts for every body; returns how many wall impacts
/// reversed a velocity component.
pub fn resolve_walls(bodies: &mut Bodies, mode: WallMode, wall_restitution: f64) -> usize {
    let c = match mode {
        WallMode::Flip => 1.0,
        WallMode::Restitution => wall_restitution,
    };
    let mut impacts = 0;
    let Bodies {
        position,
        velocity,
        radius,
        ..
    } = bodies;
    for ((x, v), &r) in position
        .iter_mut()
        .zip(velocity.iter_mut())
        .zip(radius.iter())
    {
        let (lo, hi) = (r, 1.0 - r);
        for axis in 0..3 {
            let (p, u) = (&mut x[axis], &mut v[axis]);
            if *p < lo {
                if *u < 0.0 {
                    *p = lo + c * (lo - *p);
                    *u *= -c;
                    impacts += 1;
                }
                *p = p.clamp(lo, hi);
            } else if *p > hi {
                if *u > 0.0 {
                    *p = hi - c * (*p - hi);
                    *u *= -c;
                    impacts += 1;
                }
                *p = p.clamp(lo, hi);
            }
        }
    }
    impacts
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
        let impacts = resolve_walls(&mut b, WallMode::Restitution, 0.5);
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
        assert_eq!(resolve_walls(&mut b, WallMode::Restitution, 0.9), 0);
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
