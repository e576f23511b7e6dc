//! Sphere-sphere contact: detection and the lesson's resolution.
//!
//! Detection: two spheres collide when the distance between their centres
//! is less than the sum of their radii, `d < r1 + r2`. (The lesson's code
//! sample adds the two positions; the distance is what it means.)
//!
//! Resolution, for contacts in a fixed order (ascending `(i, j)`), each seeing
//! the corrections made before it:
//!
//! 1. Position: the penetration `delta = (r1 + r2) - d` is removed along the
//!    contact normal `n` (from `i` to `j`), split by inverse mass:
//!    `p_i = w_i / (w1 + w2) * delta * n`, `w_i = 1 / m_i`. A projection,
//!    not a force.
//! 2. Velocity: only the normal components `v1 = v_i . n`, `v2 = v_j . n`
//!    change, to the lesson's
//!    `V1 = (m1 v1 + m2 v2 - m2 (v1 - v2) e) / (m1 + m2)` and
//!    `V2 = (m1 v1 + m2 v2 - m1 (v2 - v1) e) / (m1 + m2)`,
//!    which conserve momentum and give separation speed `e` times approach
//!    speed. Tangential components are untouched; a pair already separating
//!    (`v1 <= v2`) gets no impulse. An approach slower than the rest
//!    threshold uses `e = 0` ([`Restitution`]).

use super::restitution::Restitution;
use super::{Bodies, Vec3};

/// A detected overlap between bodies `i < j`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub i: u32,
    pub j: u32,
    /// Unit vector from the centre of `i` to the centre of `j`.
    pub contact_normal: Vec3,
    /// `(r_i + r_j) - d > 0`, m.
    pub penetration: f64,
}

/// The narrow-phase test for one pair: `Some(contact)` when the spheres
/// overlap. Coincident centres get the normal `+y`, so the result never
/// depends on anything but the two bodies.
#[inline]
pub fn test_pair(bodies: &Bodies, i: usize, j: usize) -> Option<Contact> {
    let d = bodies.position[j] - bodies.position[i];
    let reach = bodies.radius[i] + bodies.radius[j];
    let d2 = d.length_squared();
    if d2 >= reach * reach {
        return None;
    }
    let dist = d2.sqrt();
    let contact_normal = if dist > 0.0 { d / dist } else { Vec3::Y };
    Some(Contact {
        i: i as u32,
        j: j as u32,
        contact_normal,
        penetration: reach - dist,
    })
}

/// The lesson's post-impact normal speeds `(V1, V2)`.
#[inline]
pub fn normal_speeds_after(m1: f64, m2: f64, v1: f64, v2: f64, e: f64) -> (f64, f64) {
    let p = m1 * v1 + m2 * v2;
    let m = m1 + m2;
    ((p - m2 * (v1 - v2) * e) / m, (p - m1 * (v2 - v1) * e) / m)
}

/// Resolve `contacts` in order: position projection, then the velocity
/// update along the normal with restitution `e` (a coefficient, or a
/// coefficient with its rest threshold).
pub fn solve_contacts(bodies: &mut Bodies, contacts: &[Contact], e: impl Into<Restitution>) {
    let rule = e.into();
    for c in contacts {
        let (i, j, n) = (c.i as usize, c.j as usize, c.contact_normal);
        let (w1, w2) = (bodies.inverse_mass[i], bodies.inverse_mass[j]);
        let share = c.penetration / (w1 + w2);
        bodies.position[i] -= n * (w1 * share);
        bodies.position[j] += n * (w2 * share);

        let (v1, v2) = (bodies.velocity[i].dot(n), bodies.velocity[j].dot(n));
        if v1 <= v2 {
            continue; // already separating (or resting): no impulse
        }
        let (m1, m2) = (bodies.mass[i], bodies.mass[j]);
        let e = rule.at(v1 - v2);
        let (big_v1, big_v2) = normal_speeds_after(m1, m2, v1, v2, e);
        bodies.velocity[i] += n * (big_v1 - v1);
        bodies.velocity[j] += n * (big_v2 - v2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_masses_swap_normal_speeds_when_perfectly_elastic() {
        assert_eq!(normal_speeds_after(2.0, 2.0, 3.0, -1.0, 1.0), (-1.0, 3.0));
    }

    #[test]
    fn v1_v2_satisfy_momentum_and_the_restitution_definition() {
        let (m1, m2, v1, v2, e) = (0.3, 7.0, 2.5, -0.5, 0.7);
        let (a, b) = normal_speeds_after(m1, m2, v1, v2, e);
        assert!((m1 * a + m2 * b - (m1 * v1 + m2 * v2)).abs() < 1e-14);
        assert!(((b - a) - e * (v1 - v2)).abs() < 1e-14);
    }

    #[test]
    fn detection_uses_the_distance_between_centres_not_their_sum() {
        let bodies: Bodies = [
            crate::sim::Body {
                position: Vec3::new(0.2, 0.2, 0.2),
                velocity: Vec3::ZERO,
                radius: 0.1,
                mass: 1.0,
            },
            crate::sim::Body {
                position: Vec3::new(0.8, 0.8, 0.8),
                velocity: Vec3::ZERO,
                radius: 0.1,
                mass: 1.0,
            },
        ]
        .into_iter()
        .collect();
        assert_eq!(test_pair(&bodies, 0, 1), None, "far apart: no contact");
        let mut near = bodies.clone();
        near.position[1] = Vec3::new(0.2, 0.35, 0.2);
        let c = test_pair(&near, 0, 1).expect("0.15 apart, radii sum 0.2");
        assert_eq!(c.contact_normal, Vec3::Y);
        assert!((c.penetration - 0.05).abs() < 1e-15);
    }
}
