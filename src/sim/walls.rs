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
                    *u = -c * *u;
                    impacts += 1;
                }
                *p = p.clamp(lo, hi);
            } else if *p > hi {
                if *u > 0.0 {
                    *p = hi - c * (*p - hi);
                    *u = -c * *u;
                    impacts += 1;
                }
                *p = p.clamp(lo, hi);
            }
        }
    }
    impacts
}
