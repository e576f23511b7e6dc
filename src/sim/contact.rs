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
//!    threshold, or than gravity's resting speed along `n` (resting
//!    contact), uses `e = 0` ([`Restitution`]).
//!
//! Every contact moves both of its spheres by equal and opposite momentum,
//! so whatever the order, the total momentum is conserved to rounding.
//!
//! ## In parallel, with the same bits for any number of threads
//!
//! [`solve_contacts`] is the lesson's sequential pass: one contact after
//! the other in `(i, j)` order. Small worlds (every lesson) use it.
//!
//! [`solve_contacts_in_slabs`] is the same Gauss-Seidel pass over a fixed
//! partition of the contacts into slabs, and serves large worlds whose
//! slots are in cell order (`grid.rs`). Cut the box along x into the slabs
//! of the grid's [`CellLayout`] (each wider than the largest diameter), give
//! each sphere the slab of its centre as the step found it, and each contact
//! the slab of its sphere `i`. When the slots are in cell order, a contact's
//! sphere `j` lies in the same slab or the next one, so the contacts of
//! slab `s` touch only spheres of slabs `s` and `s + 1`. Two even slabs (or
//! two odd ones) therefore share no sphere, and resolving one cannot change
//! what the other reads. The solver resolves
//!
//! 1. every even slab, in parallel, each slab's contacts in `(i, j)` order;
//! 2. then every odd slab, in parallel, the same way.
//!
//! The result is one fixed sequence of the lesson's updates (even slabs
//! before odd ones, `(i, j)` order within a slab), whichever thread runs
//! which slab: the bits do not depend on the thread count or the
//! scheduling. The physics of each update is the lesson's; only the order
//! of the contacts differs from the sequential pass, as any order is a
//! choice. The partition depends only on the state, and is checked before
//! anything moves: if any contact breaks the slab rule (slots not in cell
//! order), the sequential pass runs instead.

use super::grid::CellLayout;
use super::restitution::Restitution;
use super::{Bodies, Vec3};
use rayon::prelude::*;

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

/// The velocity half of a contact: when the pair approaches along `n`
/// (from `i` to `j`), set its normal speeds to the lesson's `V1`, `V2` with
/// the restitution `rule` gives at that approach speed; tangential
/// components are untouched. Returns false (and changes nothing) for a pair
/// already separating or resting.
#[inline]
pub fn apply_pair_impulse(
    vi: &mut Vec3,
    vj: &mut Vec3,
    m1: f64,
    m2: f64,
    n: Vec3,
    rule: Restitution,
) -> bool {
    let (v1, v2) = (vi.dot(n), vj.dot(n));
    if v1 <= v2 {
        return false;
    }
    let e = rule.at_pair(v1 - v2, n);
    let (big_v1, big_v2) = normal_speeds_after(m1, m2, v1, v2, e);
    *vi += n * (big_v1 - v1);
    *vj += n * (big_v2 - v2);
    true
}

/// Resolve `contacts` in order: position projection, then the velocity
/// update along the normal with restitution `e` (a coefficient, or a
/// coefficient with its rest threshold).
pub fn solve_contacts(bodies: &mut Bodies, contacts: &[Contact], e: impl Into<Restitution>) {
    let shared = SharedBodies::new(bodies);
    // SAFETY: one task, and `shared` is the only access to the bodies here.
    unsafe { shared.resolve(contacts, e.into()) };
}

/// Resolve `contacts` slab by slab (see the module notes): even slabs in
/// parallel, then odd slabs in parallel, each in `(i, j)` order. Falls back
/// to [`solve_contacts`] when the contacts do not follow the slabs of
/// `layout`. Returns the number of slabs used (1 for the sequential pass).
pub fn solve_contacts_in_slabs(
    bodies: &mut Bodies,
    contacts: &[Contact],
    e: impl Into<Restitution>,
    layout: CellLayout,
) -> usize {
    run_in_slabs(bodies, contacts, Pass::Solve(e.into()), layout).0
}

/// One pass over a contact list: the lesson's resolution, or a projection
/// only (see [`project_contacts`]).
#[derive(Clone, Copy, Debug)]
enum Pass {
    Solve(Restitution),
    Again(Restitution),
}

/// Run `pass` over `contacts` slab by slab when they follow the slabs of
/// `layout`, else in one sequential pass. Returns the slabs used and the
/// largest penetration a projection pass met.
fn run_in_slabs(
    bodies: &mut Bodies,
    contacts: &[Contact],
    pass: Pass,
    layout: CellLayout,
) -> (usize, f64) {
    let slabs = layout.n;
    if slabs < 2 {
        return (1, run_sequential(bodies, contacts, pass));
    }
    let position = &bodies.position;
    let per_task = layout.slabs_per_task(bodies.len());
    // The slots of slab `s` are `first[s]..first[s + 1]` when the slots are
    // in slab order; the contacts of slab `s` are those whose sphere `i`
    // lies in it (when sorted by `i`). Both searches are plain binary
    // searches; the check below is what makes the partition safe whatever
    // they return.
    let first: Vec<usize> = (0..=slabs)
        .map(|s| position.partition_point(|p| layout.axis(p.x) < s))
        .collect();
    let at: Vec<usize> = first
        .iter()
        .map(|&f| contacts.partition_point(|c| (c.i as usize) < f))
        .collect();
    // Slab `s` may touch only the slots `first[s]..first[s + 2]`: then two
    // slabs of the same parity share no sphere. Checked for every contact,
    // in one pass, before anything moves.
    let follows_slabs = at[0] == 0
        && at[slabs] == contacts.len()
        && first.windows(2).all(|w| w[0] <= w[1])
        && at.windows(2).all(|w| w[0] <= w[1])
        && (0..slabs).into_par_iter().with_min_len(per_task).all(|s| {
            let slots = first[s]..first[(s + 2).min(slabs)];
            contacts[at[s]..at[s + 1]]
                .iter()
                .all(|c| slots.contains(&(c.i as usize)) && slots.contains(&(c.j as usize)))
        });
    if !follows_slabs {
        return (1, run_sequential(bodies, contacts, pass));
    }
    let ranges: Vec<_> = (0..slabs).map(|s| at[s]..at[s + 1]).collect();
    let shared = SharedBodies::new(bodies);
    let mut worst: f64 = 0.0;
    for parity in [0, 1] {
        let w = (parity..slabs)
            .into_par_iter()
            .step_by(2)
            .with_min_len(per_task.div_ceil(2))
            .map(|s| {
                // SAFETY: the slabs of one parity touch disjoint spheres
                // (checked above), so no two tasks touch the same sphere.
                unsafe { shared.run(&contacts[ranges[s].clone()], pass) }
            })
            .reduce(|| 0.0, f64::max);
        worst = worst.max(w);
    }
    (slabs, worst)
}

/// `pass` over `contacts` in order, on one thread.
fn run_sequential(bodies: &mut Bodies, contacts: &[Contact], pass: Pass) -> f64 {
    let shared = SharedBodies::new(bodies);
    // SAFETY: one task, and `shared` is the only access to the bodies here.
    unsafe { shared.run(contacts, pass) }
}

/// A further projection pass over the contacts a step found: each pair
/// still overlapping is pushed apart along its current line of centres by
/// the lesson's inverse-mass split, with no velocity change. Pairs that no
/// longer overlap are left alone. One pass of the lesson removes each
/// penetration as it was found, but in a pile every correction pushes into
/// the next sphere; repeated passes (Gauss-Seidel, as position-based
/// dynamics iterates its constraints) spread the correction through the
/// pile. Slab by slab in parallel when `layout` is given (the same order
/// rule as [`solve_contacts_in_slabs`]). Returns the largest penetration the
/// pass met, m.
pub fn project_contacts(
    bodies: &mut Bodies,
    contacts: &[Contact],
    e: impl Into<Restitution>,
    layout: Option<CellLayout>,
) -> f64 {
    let pass = Pass::Again(e.into());
    match layout {
        Some(layout) => run_in_slabs(bodies, contacts, pass, layout).1,
        None => run_sequential(bodies, contacts, pass),
    }
}

/// Raw access to the arrays the solver writes, so that tasks resolving
/// disjoint sets of spheres can share one `Bodies`.
struct SharedBodies {
    position: *mut Vec3,
    velocity: *mut Vec3,
    radius: *const f64,
    mass: *const f64,
    inverse_mass: *const f64,
    len: usize,
}

// SAFETY: the pointers come from a `&mut Bodies` that outlives every use;
// callers of `resolve` guarantee that concurrent calls touch disjoint spheres.
unsafe impl Sync for SharedBodies {}
unsafe impl Send for SharedBodies {}

impl SharedBodies {
    fn new(bodies: &mut Bodies) -> Self {
        let len = bodies.len();
        assert!(
            bodies.velocity.len() == len
                && bodies.radius.len() == len
                && bodies.mass.len() == len
                && bodies.inverse_mass.len() == len,
            "every body array has one entry per sphere"
        );
        Self {
            position: bodies.position.as_mut_ptr(),
            velocity: bodies.velocity.as_mut_ptr(),
            radius: bodies.radius.as_ptr(),
            mass: bodies.mass.as_ptr(),
            inverse_mass: bodies.inverse_mass.as_ptr(),
            len,
        }
    }

    /// Run `pass` over `contacts` in order; returns the largest penetration
    /// a projection pass met (0 for the lesson's pass).
    ///
    /// # Safety
    /// As [`SharedBodies::resolve`].
    unsafe fn run(&self, contacts: &[Contact], pass: Pass) -> f64 {
        match pass {
            Pass::Solve(rule) => {
                // SAFETY: as the caller promises.
                unsafe { self.resolve(contacts, rule) };
                0.0
            }
            // SAFETY: as the caller promises.
            Pass::Again(rule) => unsafe { self.project(contacts, rule) },
        }
    }

    /// Push every pair of `contacts` still overlapping apart along its
    /// current line of centres, split by inverse mass; returns the largest
    /// penetration met.
    ///
    /// # Safety
    /// As [`SharedBodies::resolve`].
    unsafe fn project(&self, contacts: &[Contact], rule: Restitution) -> f64 {
        let mut worst: f64 = 0.0;
        for c in contacts {
            let (i, j) = (c.i as usize, c.j as usize);
            assert!(
                i != j && i < self.len && j < self.len,
                "a contact joins two different existing spheres"
            );
            // SAFETY: in bounds and distinct (asserted); exclusive by the
            // caller's promise.
            unsafe {
                let (xi, xj) = (&mut *self.position.add(i), &mut *self.position.add(j));
                let d = *xj - *xi;
                let reach = *self.radius.add(i) + *self.radius.add(j);
                let d2 = d.length_squared();
                if d2 >= reach * reach {
                    continue;
                }
                let dist = d2.sqrt();
                let n = if dist > 0.0 { d / dist } else { Vec3::Y };
                let penetration = reach - dist;
                worst = worst.max(penetration);
                let (w1, w2) = (*self.inverse_mass.add(i), *self.inverse_mass.add(j));
                let share = penetration / (w1 + w2);
                *xi -= n * (w1 * share);
                *xj += n * (w2 * share);
                let (vi, vj) = (&mut *self.velocity.add(i), &mut *self.velocity.add(j));
                let (m1, m2) = (*self.mass.add(i), *self.mass.add(j));
                apply_pair_impulse(vi, vj, m1, m2, n, rule);
            }
        }
        worst
    }

    /// Resolve `contacts` in order: position projection, then the velocity
    /// update along the normal with restitution `rule`.
    ///
    /// # Safety
    /// No other call may run concurrently on a contact sharing a sphere with
    /// these, and the `Bodies` must not be used otherwise meanwhile.
    unsafe fn resolve(&self, contacts: &[Contact], rule: Restitution) {
        for c in contacts {
            let (i, j, n) = (c.i as usize, c.j as usize, c.contact_normal);
            assert!(
                i != j && i < self.len && j < self.len,
                "a contact joins two different existing spheres"
            );
            // SAFETY: in bounds and distinct (asserted); exclusive by the
            // caller's promise.
            unsafe {
                let (xi, xj) = (&mut *self.position.add(i), &mut *self.position.add(j));
                let (vi, vj) = (&mut *self.velocity.add(i), &mut *self.velocity.add(j));
                let (w1, w2) = (*self.inverse_mass.add(i), *self.inverse_mass.add(j));
                let share = c.penetration / (w1 + w2);
                *xi -= n * (w1 * share);
                *xj += n * (w2 * share);

                let (m1, m2) = (*self.mass.add(i), *self.mass.add(j));
                apply_pair_impulse(vi, vj, m1, m2, n, rule);
            }
        }
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
