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
//!    speed. The step computes them as the equal
//!    `V1 = v1 - m2 (1 + e) u / (m1 + m2)`, `V2 = v2 + m1 (1 + e) u / (m1 + m2)`
//!    from the approach speed `u = (v_i - v_j) . n` (the same to rounding),
//!    whose chain from one contact's velocities to the next contact's is
//!    half as long: in a pile a sphere's contacts are resolved one after
//!    the other, each waiting for the velocity the last one left.
//!    Tangential components are untouched; a pair already separating
//!    (`u <= 0`) gets no impulse. An approach slower than the rest
//!    threshold, or than gravity's resting speed along `n` (resting
//!    contact), uses `e = 0` ([`Restitution`]).
//!
//! Every contact moves both of its spheres by equal and opposite momentum,
//! so whatever the order, the total momentum is conserved to rounding.
//!
//! [`solve_contacts`] is the lesson's sequential pass: one contact after
//! the other in `(i, j)` order. Large worlds run the same per-contact
//! update over a partition of the contacts, in parallel
//! (`large/slabs.rs`), through the same [`BodiesMut`] view.

use super::restitution::Restitution;
use super::{Bodies, Vec3};

/// A detected overlap between bodies `i < j`. Plain data (`Pod`): a large
/// world lends the contact buffer as spare memory (`large/cell_order.rs`).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Contact {
    pub i: u32,
    pub j: u32,
    /// Unit vector from the centre of `i` to the centre of `j`.
    pub contact_normal: Vec3,
    /// `(r_i + r_j) - d`, m: positive for an overlap (every contact the
    /// solver resolves); negative for a pair found within a margin
    /// (`support.rs`).
    pub penetration: f64,
}

/// The narrow-phase test for one pair: `Some(contact)` when the spheres
/// overlap. Coincident centres get the normal `+y`, so the result never
/// depends on anything but the two bodies.
#[inline]
pub(crate) fn test_pair(bodies: &Bodies, i: usize, j: usize) -> Option<Contact> {
    test_pair_within(bodies, i, j, 0.0)
}

/// As [`test_pair`], for spheres closer than `margin` (m) beyond touching:
/// the contact's `penetration` is then negative down to `-margin` (a gap).
/// A margin of 0 is exactly [`test_pair`].
#[inline]
pub(crate) fn test_pair_within(
    bodies: &Bodies,
    i: usize,
    j: usize,
    margin: f64,
) -> Option<Contact> {
    let d = bodies.position[j] - bodies.position[i];
    let reach = bodies.radius[i] + bodies.radius[j];
    let within = reach + margin;
    let d2 = d.length_squared();
    if d2 >= within * within {
        return None;
    }
    Some(contact_of(i, j, d, d2, reach))
}

/// Whether a pair found within `margin` (m) of touching goes to the step's
/// contacts (it overlaps), not to its pairs near touching: with a margin,
/// a pair that does not overlap (a penetration of 0 included) goes to the
/// second list; without one, every pair found goes to the first. The one
/// rule the narrow phase and the sleepers' pairs split by.
pub(crate) fn in_contact_list(c: &Contact, margin: f64) -> bool {
    !(margin > 0.0 && c.penetration <= 0.0)
}

/// The contact of bodies `i < j` found within reach: `d` is the centre of
/// `j` less the centre of `i`, `d2` its squared length and `reach` the
/// sum of their radii. The one place a contact's normal and penetration
/// are computed one at a time (for the narrow phases and the projection
/// passes), and [`finish_pairs`] computes them four at a time with the
/// same operations, so every narrow phase gives the same bits.
#[inline]
pub(crate) fn contact_of(i: usize, j: usize, d: Vec3, d2: f64, reach: f64) -> Contact {
    let dist = d2.sqrt();
    let contact_normal = if dist > 0.0 { d / dist } else { Vec3::Y };
    Contact {
        i: i as u32,
        j: j as u32,
        contact_normal,
        penetration: reach - dist,
    }
}

/// A pair of bodies `i < j` found within reach, its contact not yet
/// worked out: `d` (the centre of `j` less the centre of `i`) where the
/// normal goes and `reach` (the sum of their radii) where the penetration
/// goes, for [`finish_pairs`].
#[inline]
pub(crate) fn pair_within(i: usize, j: usize, d: Vec3, reach: f64) -> Contact {
    Contact {
        i: i as u32,
        j: j as u32,
        contact_normal: d,
        penetration: reach,
    }
}

/// Work out the contacts of `pairs` listed by [`pair_within`]: each the
/// one [`contact_of`] gives, to the bit. Four at a time, as lanes of
/// arrays, which the compiler turns into vector instructions: in the
/// sweep's AVX2 version four square roots in one instruction and twelve
/// divisions in three, elsewhere two to an instruction, where one contact
/// at a time takes a square root and three divisions of its own. The
/// operations are the same, each correctly rounded, so the bits are too.
/// Returns the deepest penetration (0 for none).
#[inline(always)]
pub(crate) fn finish_pairs(pairs: &mut [Contact]) -> f64 {
    let mut fours = pairs.chunks_exact_mut(4);
    for four in &mut fours {
        let d: [Vec3; 4] = std::array::from_fn(|k| four[k].contact_normal);
        let dist = d.map(|d| d.length_squared().sqrt());
        let [x, y, z] =
            [0, 1, 2].map(|axis| std::array::from_fn::<f64, 4, _>(|k| d[k][axis] / dist[k]));
        for (k, c) in four.iter_mut().enumerate() {
            c.contact_normal = if dist[k] > 0.0 {
                Vec3::new(x[k], y[k], z[k])
            } else {
                Vec3::Y
            };
            c.penetration -= dist[k];
        }
    }
    for c in fours.into_remainder() {
        let d = c.contact_normal;
        *c = contact_of(
            c.i as usize,
            c.j as usize,
            d,
            d.length_squared(),
            c.penetration,
        );
    }
    pairs
        .iter()
        .fold(0.0, |deepest, c| deepest.max(c.penetration))
}

/// The lesson's post-impact normal speeds `(V1, V2)`.
#[inline]
pub fn normal_speeds_after(m1: f64, m2: f64, v1: f64, v2: f64, e: f64) -> (f64, f64) {
    let p = m1 * v1 + m2 * v2;
    let m = m1 + m2;
    ((p - m2 * (v1 - v2) * e) / m, (p - m1 * (v2 - v1) * e) / m)
}

/// The approach speed of velocities `vi`, `vj` along `n` (from `i` to
/// `j`): `v1 - v2` of the lesson, positive while the pair closes.
#[inline]
pub(crate) fn approach_speed(vi: Vec3, vj: Vec3, n: Vec3) -> f64 {
    (vi - vj).dot(n)
}

/// The velocity half of a contact: when the pair approaches along `n`
/// (from `i` to `j`), set its normal speeds to the lesson's `V1`, `V2` with
/// the restitution `rule` gives at that approach speed, computed from the
/// approach speed as the module's header gives; tangential components are
/// untouched. Returns false for a pair already separating or resting,
/// whose velocities then change by zero (which may turn a component of
/// -0 into 0). The impulse is computed either way and zeroed for such a
/// pair, with no branch: in a pile whether a pair still approaches is a
/// coin toss no branch predictor foresees.
#[inline]
pub(crate) fn apply_pair_impulse(
    vi: &mut Vec3,
    vj: &mut Vec3,
    m1: f64,
    m2: f64,
    n: Vec3,
    rule: Restitution,
) -> bool {
    // The masses' shares do not wait on the velocities.
    let m = m1 + m2;
    apply_impulse_in_shares(vi, vj, m2 / m, m1 / m, n, rule)
}

/// [`apply_pair_impulse`] of a pair whose masses' shares `m2 / (m1 + m2)`
/// and `m1 / (m1 + m2)` are `k1` and `k2`.
#[inline]
fn apply_impulse_in_shares(
    vi: &mut Vec3,
    vj: &mut Vec3,
    k1: f64,
    k2: f64,
    n: Vec3,
    rule: Restitution,
) -> bool {
    let u = approach_speed(*vi, *vj, n);
    let approaching = u > 0.0;
    let s = zero_unless(approaching, (1.0 + rule.at_pair(u, n)) * u);
    *vi -= n * (k1 * s);
    *vj += n * (k2 * s);
    approaching
}

/// `x` when `yes`, else 0, through the bits: an and the compiler keeps as
/// one, where an `if` on floats may become a jump.
#[inline(always)]
fn zero_unless(yes: bool, x: f64) -> f64 {
    f64::from_bits(x.to_bits() & 0_u64.wrapping_sub(u64::from(yes)))
}

/// Take the items of `low` and `high` in turn, one of each (`low`'s
/// first), until `high` runs out; `low` may be one shorter. A solver that
/// updates a pile's contacts one after the other waits, at each update, on
/// the one before it that moved the same sphere. Given the two halves of
/// its list, which share few spheres, it has two updates to work on at
/// once: the support pass takes its rows so (`support.rs`). The large
/// worlds' pass takes each slab's contacts from four quarters in turn
/// (`large/slabs.rs`).
#[inline(always)]
pub(crate) fn in_turns<I: IntoIterator>(low: I, high: I, mut f: impl FnMut(I::Item)) {
    let mut low = low.into_iter();
    for h in high {
        if let Some(l) = low.next() {
            f(l);
        }
        f(h);
    }
}

/// Resolve `contacts` in order: position projection, then the velocity
/// update along the normal with restitution `e` (a coefficient, or a
/// coefficient with its rest threshold).
pub(crate) fn solve_contacts(bodies: &mut Bodies, contacts: &[Contact], e: impl Into<Restitution>) {
    BodiesMut::whole(bodies).resolve(contacts, e.into());
}

/// How the solvers hold the sleepers still while other spheres are awake
/// (`sleep.rs`). A sleeper's inverse mass counts as 0: the rows and
/// impulses of the support pass then move only the awake sphere of a pair,
/// as against a wall. The lesson's pass moves the awake sphere alone, by
/// the whole correction, and sets its normal speed as the lesson's `V1`
/// does against a body of infinite mass at rest, `-e` times its approach.
/// Whether such a pair rests (so that `e` is 0, or the support pass holds
/// it) is judged as if the sleeper had fallen with the sub-step's gravity,
/// as the sphere on it did: otherwise every sphere lying on a sleeper
/// would come down on it at `g h`, a bounce at the edge of the resting
/// window each sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Held<'a> {
    /// Each sphere's inverse mass, 0 for a sleeper.
    pub inverse_mass: &'a [f64],
    /// What gravity gives a velocity in the sub-step, `g h`, m/s.
    pub fall: Vec3,
}

/// What the contact solver writes: the positions and velocities of a run
/// of consecutive slots `first..first + position.len()`, with read access
/// to every sphere's radius and mass. The whole world is one such run; the
/// parallel solver gives each task its own (`large/slabs.rs`), so tasks
/// never share a sphere they write. A contact outside the run is a broken
/// promise and panics (index out of bounds).
pub(crate) struct BodiesMut<'a> {
    pub first: usize,
    pub position: &'a mut [Vec3],
    pub velocity: &'a mut [Vec3],
    pub radius: &'a [f64],
    pub mass: &'a [f64],
    pub inverse_mass: &'a [f64],
    /// While some sphere sleeps, [`Held::fall`]; zero otherwise.
    pub fall: Vec3,
    /// Every sphere of the same mass, none held: the pair's sums and
    /// shares, worked out once.
    pub equal: Option<EqualMasses>,
}

/// What the lesson's update of a pair computes from the two masses, when
/// every sphere has the same mass `m` and inverse mass `w` (not 0): `w + w`
/// and `m / (m + m)`, the same operations on the same numbers as each pair
/// would do, so the same bits, without a pair's two divisions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EqualMasses {
    inverse_mass: f64,
    inverse_sum: f64,
    share: f64,
}

impl EqualMasses {
    /// For spheres that all have the mass `mass` and the inverse mass
    /// `inverse_mass`; `None` for an inverse mass of 0 (held spheres).
    pub(crate) fn of(mass: f64, inverse_mass: f64) -> Option<Self> {
        (inverse_mass != 0.0).then(|| Self {
            inverse_mass,
            inverse_sum: inverse_mass + inverse_mass,
            share: mass / (mass + mass),
        })
    }
}

impl<'a> BodiesMut<'a> {
    /// Every sphere of `bodies`.
    pub(crate) fn whole(bodies: &'a mut Bodies) -> Self {
        Self::whole_with_ids(bodies).0
    }

    /// Every sphere of `bodies`, solved as [`Held`] says while some sphere
    /// sleeps.
    pub(crate) fn held(bodies: &'a mut Bodies, held: Option<Held<'a>>) -> Self {
        let mut whole = Self::whole(bodies);
        if let Some(held) = held {
            whole.inverse_mass = held.inverse_mass;
            whole.fall = held.fall;
        }
        whole
    }

    /// Every sphere of `bodies`, the scene index of each slot, and each
    /// sphere's time at rest (`Bodies::rest`).
    pub(crate) fn whole_with_ids(bodies: &'a mut Bodies) -> (Self, &'a [u32], &'a [f32]) {
        let Bodies {
            position,
            velocity,
            radius,
            mass,
            inverse_mass,
            id,
            rest,
        } = bodies;
        let whole = Self {
            first: 0,
            position,
            velocity,
            radius,
            mass,
            inverse_mass,
            fall: Vec3::ZERO,
            equal: None,
        };
        (whole, id, rest)
    }

    /// Read the run's centres and velocities in slot order, every other
    /// entry (48 bytes apart, so every 64-byte line of memory), before its
    /// contacts are resolved. A slab of a large world in flight has about
    /// one contact for every two spheres, and they write spheres scattered
    /// through the run: each would wait on main memory, where the run read
    /// in order arrives at the speed of a sequential read. Measured with
    /// `lerpit bench --particles 1000000 --threads 2` (dilute): a step of
    /// 54 ms instead of 60 ms, the sweep 34.5 instead of 40 ms (medians of
    /// three, by turns); no change at 10,000 and 100,000 spheres, which
    /// the caches hold, nor in a settled pile, whose contacts are dense.
    pub(crate) fn read_ahead(&self) {
        let lines = |v: &[Vec3]| v.iter().step_by(2).fold(0, |a, p| a ^ p.x.to_bits());
        std::hint::black_box(lines(self.position) ^ lines(self.velocity));
    }

    /// Resolve `contacts` in order: position projection, then the velocity
    /// update along the normal with restitution `rule`.
    pub fn resolve(&mut self, contacts: &[Contact], rule: Restitution) {
        for c in contacts {
            self.resolve_one(c, rule);
        }
    }

    /// Resolve one contact (as [`BodiesMut::resolve`] does each).
    #[inline(always)]
    pub(crate) fn resolve_one(&mut self, c: &Contact, rule: Restitution) {
        self.correct(
            c.i as usize,
            c.j as usize,
            c.contact_normal,
            c.penetration,
            rule,
        );
    }

    /// A further projection pass over the contacts a step found: each pair
    /// still overlapping is pushed apart along its current line of centres
    /// by the lesson's inverse-mass split, and its velocities get the
    /// lesson's update if it still approaches. Pairs that no longer overlap
    /// are left alone. One pass of the lesson removes each penetration as
    /// it was found, but in a pile every correction pushes into the next
    /// sphere; repeated passes (Gauss-Seidel, as position-based dynamics
    /// iterates its constraints) spread the correction through the pile.
    /// Returns the largest penetration met, m.
    pub(crate) fn project(&mut self, contacts: &[Contact], rule: Restitution) -> f64 {
        let mut worst: f64 = 0.0;
        for c in contacts {
            let (i, j) = (c.i as usize, c.j as usize);
            let (a, b) = (i - self.first, j - self.first);
            let d = self.position[b] - self.position[a];
            let reach = self.radius[i] + self.radius[j];
            let d2 = d.length_squared();
            if d2 >= reach * reach {
                continue;
            }
            let c = contact_of(i, j, d, d2, reach);
            worst = worst.max(c.penetration);
            self.correct(i, j, c.contact_normal, c.penetration, rule);
        }
        worst
    }

    /// The lesson's update of one pair: remove `penetration` along `n`
    /// split by inverse mass, then `V1`, `V2` along `n`.
    #[inline(always)]
    fn correct(&mut self, i: usize, j: usize, n: Vec3, penetration: f64, rule: Restitution) {
        assert!(i != j, "a contact joins two different spheres");
        let (a, b) = (i - self.first, j - self.first);
        let (w1, w2, w, k1, k2) = match self.equal {
            Some(e) => {
                debug_assert!(
                    [i, j]
                        .iter()
                        .all(|&k| self.inverse_mass[k].to_bits() == e.inverse_mass.to_bits()),
                    "equal masses, as the pass was told"
                );
                (
                    e.inverse_mass,
                    e.inverse_mass,
                    e.inverse_sum,
                    e.share,
                    e.share,
                )
            }
            None => {
                let (w1, w2) = (self.inverse_mass[i], self.inverse_mass[j]);
                if w1 == 0.0 || w2 == 0.0 {
                    return self.correct_held(a, b, w2 == 0.0, n, penetration, rule);
                }
                let (m1, m2) = (self.mass[i], self.mass[j]);
                let m = m1 + m2;
                (w1, w2, w1 + w2, m2 / m, m1 / m)
            }
        };
        if rule.left_to_support(approach_speed(self.velocity[a], self.velocity[b], n), n) {
            return;
        }
        let share = penetration / w;
        self.position[a] -= n * (w1 * share);
        self.position[b] += n * (w2 * share);
        let (mut vi, mut vj) = (self.velocity[a], self.velocity[b]);
        apply_impulse_in_shares(&mut vi, &mut vj, k1, k2, n, rule);
        self.velocity[a] = vi;
        self.velocity[b] = vj;
    }

    /// [`BodiesMut::correct`] of a pair one of whose spheres is held still
    /// (a sleeper, [`Held`]): `b` when `b_held`, else `a`.
    #[cold]
    #[inline(never)]
    fn correct_held(
        &mut self,
        a: usize,
        b: usize,
        b_held: bool,
        n: Vec3,
        penetration: f64,
        rule: Restitution,
    ) {
        let (i, j) = (a + self.first, b + self.first);
        if self.inverse_mass[i] == 0.0 && self.inverse_mass[j] == 0.0 {
            return;
        }
        let (mut vi, mut vj) = (self.velocity[a], self.velocity[b]);
        let counted = if b_held {
            approach_speed(vi, self.fall, n)
        } else {
            approach_speed(self.fall, vj, n)
        };
        if rule.left_to_support(counted, n) {
            return;
        }
        let u = approach_speed(vi, vj, n);
        let s = if u > 0.0 {
            (1.0 + rule.at_pair(counted, n)) * u
        } else {
            0.0
        };
        if b_held {
            self.position[a] -= n * penetration;
            vi -= n * s;
        } else {
            self.position[b] += n * penetration;
            vj += n * s;
        }
        self.velocity[a] = vi;
        self.velocity[b] = vj;
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

    proptest::proptest! {
        /// The step's form of V1, V2 (from the approach speed) is the
        /// lesson's to rounding, keeps the tangential components and the
        /// momentum, and leaves a separating pair alone.
        #[test]
        fn the_impulse_gives_the_lessons_normal_speeds(
            m1 in 1e-3f64..1e3, m2 in 1e-3f64..1e3, e in 0.0f64..=1.0,
            vi in proptest::array::uniform3(-10.0f64..10.0),
            vj in proptest::array::uniform3(-10.0f64..10.0),
            n in proptest::array::uniform3(-1.0f64..1.0),
        ) {
            let n = Vec3::from(n).normalize_or(Vec3::Y);
            let (vi, vj) = (Vec3::from(vi), Vec3::from(vj));
            let (mut a, mut b) = (vi, vj);
            let moved = apply_pair_impulse(&mut a, &mut b, m1, m2, n, e.into());
            let (v1, v2) = (vi.dot(n), vj.dot(n));
            let scale = 1e-12 * (1.0 + vi.length() + vj.length());
            if !moved {
                proptest::prop_assert!(v1 - v2 <= scale, "approaching, yet no impulse");
                proptest::prop_assert_eq!((a, b), (vi, vj));
                return Ok(());
            }
            let (big_v1, big_v2) = normal_speeds_after(m1, m2, v1, v2, e);
            proptest::prop_assert!((a.dot(n) - big_v1).abs() <= scale, "{} {}", a.dot(n), big_v1);
            proptest::prop_assert!((b.dot(n) - big_v2).abs() <= scale, "{} {}", b.dot(n), big_v2);
            let tangent = |v: Vec3| v - n * v.dot(n);
            proptest::prop_assert!((tangent(a) - tangent(vi)).length() <= scale);
            proptest::prop_assert!((tangent(b) - tangent(vj)).length() <= scale);
            let p = vi * m1 + vj * m2;
            proptest::prop_assert!((a * m1 + b * m2 - p).length() <= scale * (m1 + m2));
        }
    }

    #[test]
    fn a_sphere_against_a_held_sleeper_moves_alone_as_against_a_wall() {
        // Sphere 0 awake, sphere 1 asleep (held, inverse mass 0), 0.01 m
        // into each other along a slanted normal; 0 moving along it and
        // sideways. The sleeper's position and velocity keep every bit.
        let (h, g) = (1.0 / 60.0, Vec3::new(0.0, -9.81, 0.0));
        let n = Vec3::new(0.6, -0.8, 0.0);
        let side = Vec3::Z;
        let body = |x: Vec3, v: Vec3| crate::sim::Body {
            position: x,
            velocity: v,
            radius: 0.1,
            mass: 2.0,
        };
        let x0 = Vec3::splat(0.5);
        let x1 = x0 + n * 0.19;
        let contact = test_pair(
            &[body(x0, Vec3::ZERO), body(x1, Vec3::ZERO)]
                .into_iter()
                .collect(),
            0,
            1,
        )
        .expect("they overlap");
        let held = [0.5, 0.0];
        let resolve = |v0: Vec3, supported: bool| {
            let mut bodies: Bodies = [body(x0, v0), body(x1, Vec3::ZERO)].into_iter().collect();
            let rule = Restitution::new(0.8, 0.0)
                .with_resting(g * h)
                .with_support(supported);
            let fall = g * h;
            BodiesMut::held(
                &mut bodies,
                Some(Held {
                    inverse_mass: &held,
                    fall,
                }),
            )
            .resolve(&[contact], rule);
            assert_eq!((bodies.position[1], bodies.velocity[1]), (x1, Vec3::ZERO));
            (bodies.position[0], bodies.velocity[0])
        };
        // A blow at 1 m/s: pushed out by the whole overlap, sent back at
        // 0.8 m/s, its sideways speed kept.
        let (x, v) = resolve(n + 0.3 * side, false);
        assert!((x - (x0 - n * contact.penetration)).length() < 1e-15, "{x}");
        assert!(
            (v.dot(n) + 0.8).abs() < 1e-15 && (v.dot(side) - 0.3).abs() < 1e-15,
            "{v}"
        );
        // At rest on it before gravity's sub-step (moving `g h` after it):
        // left to the support pass, or stopped dead by the lesson's pass
        // (e = 0 in the resting window), not bounced at 0.8 g h.
        let resting = g * h + 0.3 * side;
        assert_eq!(resolve(resting, true), (x0, resting));
        let (_, v) = resolve(resting, false);
        assert!(v.dot(n).abs() < 1e-15, "{v}");
    }

    #[test]
    fn pairs_finished_four_at_a_time_are_the_contacts_of_each_alone() {
        // Pairs at random offsets, a few coincident (the +y normal, from
        // 0, -0, or an offset whose square is 0) among the fours and in the
        // three left over, each finished in lanes and alone: the same bits.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let mut pairs = Vec::new();
        let mut alone = Vec::new();
        for k in 0..1003_usize {
            let d = if k % 97 == 5 || k == 1001 {
                Vec3::ZERO
            } else if k % 97 == 6 || k == 1002 {
                Vec3::splat(-0.0)
            } else if k % 97 == 7 {
                // Not zero, but its square is.
                Vec3::new(-1e-200, 0.0, 1e-170)
            } else {
                let scale = 10f64.powi(rng.random_range(-8..=1));
                Vec3::new(rng.random(), rng.random(), rng.random()) * scale
                    - Vec3::splat(scale / 2.0)
            };
            let reach = rng.random::<f64>() * 0.1;
            pairs.push(pair_within(k, k + 1, d, reach));
            alone.push(contact_of(k, k + 1, d, d.length_squared(), reach));
        }
        let deepest = finish_pairs(&mut pairs);
        assert_eq!(
            deepest,
            alone.iter().map(|c| c.penetration).fold(0.0, f64::max)
        );
        let bits = |c: &Contact| {
            let n = c.contact_normal;
            (c.i, c.j, [n.x, n.y, n.z, c.penetration].map(f64::to_bits))
        };
        for (k, (lanes, one)) in pairs.iter().zip(&alone).enumerate() {
            assert_eq!(bits(lanes), bits(one), "pair {k}");
        }
        for k in [5, 6, 7, 1001, 1002] {
            assert_eq!(alone[k].contact_normal, Vec3::Y, "pair {k}");
        }
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

    #[test]
    fn equal_masses_worked_out_once_give_the_bits_of_each_pairs_own() {
        // A crowded heap of equal spheres of an awkward mass, every pair
        // overlapping resolved in (i, j) order, with each rule a step
        // uses: the pass with the sums and shares computed once against
        // the pass computing them from each pair's masses.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let mass = 0.013_7;
        let bodies: Bodies = (0..300)
            .map(|_| {
                let mut at = || 0.4 + 0.2 * rng.random::<f64>();
                crate::sim::Body {
                    position: Vec3::new(at(), at(), at()),
                    velocity: Vec3::new(at() - 0.5, at() - 0.5, at() - 0.5) * 9.0,
                    radius: 0.021,
                    mass,
                }
            })
            .collect();
        let contacts: Vec<Contact> = (0..bodies.len())
            .flat_map(|i| (i + 1..bodies.len()).map(move |j| (i, j)))
            .filter_map(|(i, j)| test_pair(&bodies, i, j))
            .collect();
        assert!(contacts.len() > 3 * bodies.len(), "{}", contacts.len());
        let equal = EqualMasses::of(mass, bodies.inverse_mass[0]);
        assert!(equal.is_some());
        assert_eq!(EqualMasses::of(mass, 0.0), None, "held spheres");
        let fall = Vec3::new(0.0, -9.81 / 120.0, 0.0);
        for rule in [
            Restitution::new(0.95, 0.0),
            Restitution::new(0.6, 0.3).with_resting(fall),
            Restitution::new(0.95, 0.0)
                .with_resting(fall)
                .with_support(true),
        ] {
            let (mut each, mut once) = (bodies.clone(), bodies.clone());
            BodiesMut::whole(&mut each).resolve(&contacts, rule);
            let mut with_equal = BodiesMut::whole(&mut once);
            with_equal.equal = equal;
            with_equal.resolve(&contacts, rule);
            let bits = |b: &Bodies| {
                b.position
                    .iter()
                    .chain(&b.velocity)
                    .flat_map(|v| v.to_array().map(f64::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&each), bits(&once), "{rule:?}");
            assert_ne!(each.velocity, bodies.velocity, "{rule:?}: something moved");
        }
    }
}
