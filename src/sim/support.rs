//! Support: how a pile carries its weight, from the floor up (shock
//! propagation).
//!
//! The lesson's pass resolves each contact once, splitting the correction
//! by inverse mass, and changes velocities only along each normal in turn.
//! In a pile that cannot carry weight. Every step gravity moves each sphere
//! `g dt^2` down (a quarter of a radius at dt = 1/60 s for the benchmark's
//! 20,000 spheres); the floor lifts the bottom layer back, but the layers
//! above are lifted one step late, each sphere keeps a falling velocity its
//! supports should have taken, and the pile jitters, compressed.
//!
//! After the lesson's pass and the walls, the support pass visits the
//! spheres from the floor up, by height against gravity. Each sphere's
//! supports are the spheres it touches that are lower than it; they have
//! been put in place already, so they count as infinitely heavy:
//!
//! - position: the sphere is moved out of its supports, to overlap each by
//!   [`RESTING_OVERLAP`] of the pair's reach (and to stay in the box);
//! - velocity: what remains of its velocity into any support is removed.
//!
//! Both are projected Gauss-Seidel sweeps over the sphere's supports with
//! accumulated, non-negative corrections, as contact solvers iterate
//! (Catto's sequential impulses): a push along one normal is taken back
//! when another support carries the load, so a sphere resting in the pocket
//! of three others comes to rest, neither rising nor sliding. The floor
//! holds the bottom layer, the bottom layer the next, and one pass carries the
//! weight of the whole pile to the floor, as the normal forces of a resting
//! pile do.
//!
//! A sphere lifted above the height it had when the step began pays for
//! the rise with its own kinetic energy (`m g` per metre), and rises no
//! further than that pays for: the pass undoes the step's fall for free.
//! Without this rule, sideways corrections passed up a pile slowly lifted
//! it.
//!
//! The rule is not yet tight, and this is where a held pile gains energy.
//! The kinetic energy that pays includes the speed `g h` the step's own
//! gravity gave the sphere, which the velocity sweeps then take: a sphere
//! at rest that its supports push up rises `g h^2 / 2` above where its
//! step began without paying for it (1.4 mm at dt = 1/60 s). Paying with
//! the speed the sphere had when the step began instead takes the heat out
//! of the benchmark's 1,000-sphere pile (from 20 s on, its kinetic energy
//! about 0.01 J instead of 0.5 J, its total energy falling at 0.06 J/s),
//! but a sphere pushed up by its supports then cannot pay, stays sunk in
//! them, and the pile compresses to a mean overlap of 0.29 radii: the
//! supports, counted infinitely heavy, never make way. With 4 sub-steps
//! that variant sinks less (0.02 radii) but gains energy again
//! (+0.03 J/s). A pile that neither heats nor sinks needs its contacts
//! solved both ways, at the velocity level.
//!
//! The velocity removed is the sphere's own, towards each support: the
//! support's velocity does not count, so a sphere never takes speed from a
//! support rising into it (that is an impact, which the lesson's pass
//! resolves next step with momentum shared). The velocity sweeps project
//! the velocity onto the directions that leave every support, which never
//! lengthens it: the pass only removes kinetic energy, and it moves a
//! sphere only out of overlaps the step made. Momentum is not shared with
//! the support: the floor takes it, through the pile.
//!
//! The narrow phase also lists the pairs within [`Support::margin`] of
//! touching: a pair that touched at the step's start is apart after
//! integration by rounding, and overlaps only once the pass has lifted its
//! lower sphere. Such a pair is left by the pass with the small overlap
//! [`RESTING_OVERLAP`], so the next step's narrow phase finds it, whatever
//! the rounding.
//!
//! A sphere's hold reads only its supports and writes only itself, so any
//! order that holds every support before the spheres on it gives the same
//! bits. The pass holds the spheres level by level (a sphere's level is one
//! more than its highest support's), each level's spheres in parallel: the
//! result is the same for any number of threads, and the same as holding
//! them one after another by height (a unit test compares the two).
//!
//! The pass runs when the world asks for it (`WorldConfig::support`, the
//! flag `--support`, the scene key `support = true`, the key `Y` in the
//! visualiser) with resting contact on (`rest_steps > 0`), under gravity, in
//! scenes with pair collisions, for the discrete methods. Pairs that rest
//! (slower than the resting window along their normal) are left to it by
//! the lesson's pass; every faster impact keeps the lesson's rules.

use super::contact::{BodiesMut, Contact};
use super::{Vec3, WorldConfig};
use rayon::prelude::*;

/// The overlap the support pass leaves between resting spheres, as a
/// fraction of the pair's reach `r_i + r_j`: far below any overlap a
/// learner can see, far above rounding, so the pair stays in contact.
pub const RESTING_OVERLAP: f64 = 1e-4;

/// Sweeps over a sphere's supports, for its position and for its velocity:
/// they leave a sphere dropped into a pocket of three overlapping them by
/// under 1% of a radius and not approaching them (the unit test).
pub const SUPPORT_SWEEPS: usize = 4;

/// A sphere the last position sweep still moved by more than this
/// fraction of its radius is left unsettled: the sweeps ran out before the
/// sphere came to rest on its supports, and the step says so.
pub const UNSETTLED: f64 = 0.01;

/// Levels with fewer spheres than this are held on one thread: below it
/// the hand-off costs more than the holds.
const PARALLEL_LEVEL: usize = 128;

/// What the support pass needs to know about the step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Support {
    /// Unit vector against gravity.
    pub up: Vec3,
    /// Pairs this far (m) beyond touching are listed for the pass: the
    /// distance the speed of the resting window carries a sphere in a
    /// sub-step, `(rest_steps + 1) |g| h^2`.
    pub margin: f64,
    /// The velocity sweeps stop once no correction exceeds this, m/s: a
    /// thousandth of the speed gravity adds in a sub-step.
    pub speed_tolerance: f64,
    /// `|g|`, m/s^2.
    pub gravity: f64,
}

impl Support {
    /// The support pass for a discrete sub-step of `h` s of `config`;
    /// `None` when it is off or idle (`WorldConfig::support_idle`).
    pub(crate) fn of(config: &WorldConfig, h: f64) -> Option<Self> {
        let g = config.gravity.length();
        let on = config.support && config.support_idle().is_none();
        on.then(|| Support {
            up: -config.gravity / g,
            margin: (config.rest_steps + 1.0) * g * h * h,
            speed_tolerance: 1e-3 * g * h,
            gravity: g,
        })
    }
}

/// Where one sphere ends up, held on its supports.
#[derive(Clone, Copy, Debug)]
struct Held {
    x: Vec3,
    v: Vec3,
    /// It moved or slowed.
    changed: bool,
    /// The position sweeps ran out while the last one still moved it by
    /// more than [`UNSETTLED`] of its radius.
    unsettled: bool,
}

/// What a support pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct HoldCount {
    /// Spheres it moved or slowed.
    pub held: usize,
    /// Spheres its [`SUPPORT_SWEEPS`] sweeps left unsettled: still moving
    /// by more than [`UNSETTLED`] of their radius in the last sweep.
    pub unsettled: usize,
}

impl HoldCount {
    fn add(&mut self, h: Held) {
        self.held += usize::from(h.changed);
        self.unsettled += usize::from(h.unsettled);
    }
}

/// The support pass's working memory, kept between steps for its
/// allocations only.
#[derive(Clone, Debug, Default)]
pub(crate) struct SupportWork {
    /// The supports of slot `k` are `below[start[k]..start[k + 1]]`.
    start: Vec<usize>,
    below: Vec<u32>,
    fill: Vec<usize>,
    /// Slots with supports, by height.
    order: Vec<(f64, u32)>,
    /// One sphere's sweeps: the accumulated correction per support (with
    /// its normal, for the velocity sweeps).
    push: Vec<f64>,
    /// Each slot's height at the start of the step.
    start_height: Vec<f64>,
    /// Each slot's level: one more than its highest support's (0 for a
    /// sphere with no supports).
    level: Vec<u32>,
    /// The spheres with supports, level by level: level `k` is
    /// `by_level[level_start[k - 1]..level_start[k]]`.
    by_level: Vec<u32>,
    level_start: Vec<usize>,
    /// Where one level's spheres end up, when held in parallel.
    held: Vec<Held>,
}

impl SupportWork {
    /// Note each sphere's height at the start of the step, from where the
    /// integration left it and the `displacement` its velocity says it made.
    pub(crate) fn note_start_heights(
        &mut self,
        bodies: &crate::sim::Bodies,
        support: Support,
        displacement: impl Fn(Vec3) -> Vec3 + Sync,
    ) {
        self.start_height.clear();
        bodies
            .position
            .par_iter()
            .zip(&bodies.velocity)
            .map(|(x, v)| (*x - displacement(*v)).dot(support.up))
            .collect_into_vec(&mut self.start_height);
    }
}

impl BodiesMut<'_> {
    /// The support pass over the pairs of `lists` (overlapping or within
    /// the margin): from the floor up (by height, ties in slot order), level
    /// by level, each sphere held on its supports. Returns how many it
    /// moved or slowed, and how many its sweeps left unsettled.
    pub(crate) fn support(
        &mut self,
        lists: [&[Contact]; 2],
        support: Support,
        work: &mut SupportWork,
    ) -> HoldCount {
        self.support_levels(lists, support, work, PARALLEL_LEVEL)
    }

    /// [`BodiesMut::support`], holding levels of at least `parallel_level`
    /// spheres in parallel.
    fn support_levels(
        &mut self,
        lists: [&[Contact]; 2],
        support: Support,
        work: &mut SupportWork,
        parallel_level: usize,
    ) -> HoldCount {
        let n = self.position.len();
        let first = self.first;
        let up = support.up;
        let position = &*self.position;
        let lower_upper = |c: &Contact| {
            let (a, b) = (c.i as usize - first, c.j as usize - first);
            // Ties go to slot order: the lower slot is the lower sphere.
            if position[b].dot(up) < position[a].dot(up) {
                (b, a)
            } else {
                (a, b)
            }
        };
        let SupportWork {
            start,
            below,
            fill,
            order,
            push,
            start_height,
            level,
            by_level,
            level_start,
            held,
        } = work;
        start.clear();
        start.resize(n + 1, 0);
        for c in lists.iter().flat_map(|l| l.iter()) {
            start[lower_upper(c).1 + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        below.clear();
        below.resize(start[n], 0);
        fill.clear();
        fill.extend_from_slice(&start[..n]);
        for c in lists.iter().flat_map(|l| l.iter()) {
            let (lower, upper) = lower_upper(c);
            below[fill[upper]] = lower as u32;
            fill[upper] += 1;
        }
        order.clear();
        order.extend(
            (0..n)
                .filter(|&k| start[k + 1] > start[k])
                .map(|k| (position[k].dot(up), k as u32)),
        );
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Levels, from the floor up. A sphere's hold reads its supports and
        // writes only itself, and the supports of a sphere are of lower
        // levels: the spheres of one level are held independently, in
        // parallel, with the same bits as one after another by height.
        level.clear();
        level.resize(n, 0);
        let mut levels = 0;
        for &(_, u) in order.iter() {
            let u = u as usize;
            let lv = below[start[u]..start[u + 1]]
                .iter()
                .map(|&l| level[l as usize])
                .max()
                .unwrap_or(0)
                + 1;
            level[u] = lv;
            levels = levels.max(lv as usize);
        }
        level_start.clear();
        level_start.resize(levels + 1, 0);
        for &(_, u) in order.iter() {
            level_start[level[u as usize] as usize] += 1;
        }
        for k in 1..=levels {
            level_start[k] += level_start[k - 1];
        }
        by_level.clear();
        by_level.resize(order.len(), 0);
        fill.clear();
        fill.extend_from_slice(level_start);
        for &(_, u) in order.iter() {
            let lv = level[u as usize] as usize - 1;
            by_level[fill[lv]] = u;
            fill[lv] += 1;
        }
        let mut count = HoldCount::default();
        for k in 1..=levels {
            let members = &by_level[level_start[k - 1]..level_start[k]];
            let hold = |this: &Self, u: u32, push: &mut Vec<f64>| {
                let u = u as usize;
                let supports = &below[start[u]..start[u + 1]];
                let ceiling = start_height.get(u + first).copied();
                this.held(u, supports, support, ceiling, push)
            };
            if members.len() < parallel_level {
                for &u in members {
                    let h = hold(self, u, push);
                    (self.position[u as usize], self.velocity[u as usize]) = (h.x, h.v);
                    count.add(h);
                }
            } else {
                let this = &*self;
                members
                    .par_iter()
                    .with_min_len((parallel_level / 2).max(1))
                    .map_init(Vec::new, |push, &u| hold(this, u, push))
                    .collect_into_vec(held);
                for (&u, &h) in members.iter().zip(held.iter()) {
                    (self.position[u as usize], self.velocity[u as usize]) = (h.x, h.v);
                    count.add(h);
                }
            }
        }
        count
    }

    /// Hold the sphere in slot `u` (of this run) on its `supports`, which
    /// stay where they are. True when it moved or slowed.
    #[cfg(test)]
    fn hold(
        &mut self,
        u: usize,
        supports: &[u32],
        support: Support,
        ceiling: Option<f64>,
        push: &mut Vec<f64>,
    ) -> bool {
        let h = self.held(u, supports, support, ceiling, push);
        (self.position[u], self.velocity[u]) = (h.x, h.v);
        h.changed
    }

    /// Where the sphere in slot `u` (of this run), held on its `supports`,
    /// ends up: its position, then what its lift costs, then its velocity;
    /// and whether it moved or slowed.
    fn held(
        &self,
        u: usize,
        supports: &[u32],
        support: Support,
        ceiling: Option<f64>,
        push: &mut Vec<f64>,
    ) -> Held {
        let ru = self.radius[u + self.first];
        let before = self.position[u];
        let (mut x, mut v) = (before, self.velocity[u]);
        let (moved, settled) = self.hold_position(&mut x, ru, supports, support.up, push);
        if let Some(ceiling) = ceiling {
            pay_for_lift(&mut x, &mut v, before, ceiling, ru, support);
        }
        x = x.clamp(Vec3::splat(ru), Vec3::splat(1.0 - ru));
        let slowed = self.hold_velocity(x, &mut v, ru, supports, support, push);
        Held {
            x,
            v,
            changed: moved || slowed,
            unsettled: !settled,
        }
    }

    /// The offset from support `l` (a slot of this run) to a sphere of
    /// radius `ru` at `x`, its squared length, and the pair's reach.
    #[inline]
    fn apart(&self, x: Vec3, ru: f64, l: usize) -> (Vec3, f64, f64) {
        let d = x - self.position[l];
        let reach = ru + self.radius[l + self.first];
        (d, d.length_squared(), reach)
    }

    /// Projected Gauss-Seidel sweeps moving a sphere of radius `ru` at `x`
    /// out of its `supports` to the resting overlap, with accumulated
    /// non-negative pushes. Whether it moved, and whether it settled: the
    /// last sweep moved it by no more than [`UNSETTLED`] of `ru`.
    fn hold_position(
        &self,
        x: &mut Vec3,
        ru: f64,
        supports: &[u32],
        up: Vec3,
        push: &mut Vec<f64>,
    ) -> (bool, bool) {
        push.clear();
        push.resize(supports.len(), 0.0);
        let (mut moved, mut largest) = (false, 0.0_f64);
        for _ in 0..SUPPORT_SWEEPS {
            largest = 0.0;
            for (k, &l) in supports.iter().enumerate() {
                let (d, d2, reach) = self.apart(*x, ru, l as usize);
                let rest = reach * (1.0 - RESTING_OVERLAP);
                if d2 >= rest * rest && push[k] == 0.0 {
                    continue;
                }
                let dist = d2.sqrt();
                let next = (push[k] + (rest - dist)).max(0.0);
                *x += normal(d, dist, up) * (next - push[k]);
                largest = largest.max((next - push[k]).abs());
                push[k] = next;
            }
            moved |= largest > 0.0;
            if largest <= RESTING_OVERLAP * ru {
                break;
            }
        }
        (moved, largest <= UNSETTLED * ru)
    }

    /// Projected Gauss-Seidel sweeps removing the velocity `v` of a sphere
    /// of radius `ru` at `x` into the `supports` it touches, with
    /// accumulated non-negative impulses. True when it slowed.
    fn hold_velocity(
        &self,
        x: Vec3,
        v: &mut Vec3,
        ru: f64,
        supports: &[u32],
        support: Support,
        push: &mut Vec<f64>,
    ) -> bool {
        // The sphere stays at `x`: each touching support's normal, and
        // the impulse accumulated along it, as four numbers, found once.
        push.clear();
        for &l in supports {
            let (d, d2, reach) = self.apart(x, ru, l as usize);
            if d2 < reach * reach {
                let n = normal(d, d2.sqrt(), support.up);
                push.extend([n.x, n.y, n.z, 0.0]);
            }
        }
        let mut slowed = false;
        for _ in 0..SUPPORT_SWEEPS {
            let mut largest: f64 = 0.0;
            for held in push.chunks_exact_mut(4) {
                let n = Vec3::new(held[0], held[1], held[2]);
                let next = (held[3] - v.dot(n)).max(0.0);
                *v += n * (next - held[3]);
                largest = largest.max(next - held[3]);
                held[3] = next;
            }
            slowed |= largest > 0.0;
            if largest <= support.speed_tolerance {
                break;
            }
        }
        slowed
    }
}

/// Above `ceiling`, where the step began (or above where the sphere was,
/// `before`, if higher), the lift of a sphere of radius `ru` now at `x` is
/// paid for with its own kinetic energy, and goes no further than that
/// pays for.
fn pay_for_lift(x: &mut Vec3, v: &mut Vec3, before: Vec3, ceiling: f64, ru: f64, support: Support) {
    let up = support.up;
    let (from, to) = (before.dot(up), x.dot(up));
    let top = ceiling.max(from) + RESTING_OVERLAP * ru;
    if to <= top {
        return;
    }
    let budget = 0.5 * v.length_squared();
    let cost = support.gravity * (to - top);
    if cost <= budget {
        *v *= ((budget - cost) / budget).sqrt();
    } else {
        let reach = top + budget / support.gravity;
        let t = (reach - from) / (to - from);
        *x = before + (*x - before) * t;
        *v = Vec3::ZERO;
    }
}

/// The unit vector along `d` of length `dist`; `up` for coincident centres.
#[inline]
fn normal(d: Vec3, dist: f64, up: Vec3) -> Vec3 {
    if dist > 0.0 { d / dist } else { up }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Bodies, Body};
    use rand::{RngExt, SeedableRng};

    /// A sphere of radius `r` sunk `depth` into one support below it,
    /// moving at `v`.
    fn sunk(r: f64, depth: f64, v: Vec3) -> Bodies {
        let below = Vec3::new(0.5, r, 0.5);
        let above = below + Vec3::Y * (2.0 * r - depth);
        [below, above]
            .into_iter()
            .zip([Vec3::ZERO, v])
            .map(|(position, velocity)| Body {
                position,
                velocity,
                radius: r,
                mass: 1.0,
            })
            .collect()
    }

    #[test]
    fn holding_level_by_level_in_parallel_gives_the_bits_of_holding_by_height() {
        // A dense, overlapping layer of 1,500 spheres falling onto the floor.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let r = 0.02;
        let bodies: Bodies = (0..1_500)
            .map(|_| Body {
                position: Vec3::new(
                    r + (1.0 - 2.0 * r) * rng.random::<f64>(),
                    r + 0.1 * rng.random::<f64>(),
                    r + (1.0 - 2.0 * r) * rng.random::<f64>(),
                ),
                velocity: Vec3::new(rng.random(), -rng.random::<f64>(), rng.random()) - 0.5,
                radius: r,
                mass: 1.0,
            })
            .collect();
        let h = 1.0 / 60.0;
        let support = Support {
            up: Vec3::Y,
            margin: 3.0 * 9.81 * h * h,
            speed_tolerance: 1e-3 * 9.81 * h,
            gravity: 9.81,
        };
        let mut pairs = Vec::new();
        crate::sim::broad_phase::all_pairs_within(&bodies, &mut pairs, support.margin);
        let mut work = SupportWork::default();
        work.note_start_heights(&bodies, support, |v| v * h);
        // The reference: one sphere after another by height, each on the
        // touching spheres that were lower when the pass began.
        let mut by_height = bodies.clone();
        let reference = {
            let mut b = BodiesMut::whole(&mut by_height);
            let mut order: Vec<usize> = (0..b.position.len()).collect();
            order.sort_by(|&a, &c| b.position[a].y.total_cmp(&b.position[c].y).then(a.cmp(&c)));
            let mut held = 0;
            let mut push = Vec::new();
            for u in order {
                let supports: Vec<u32> = pairs
                    .iter()
                    .filter_map(|c| {
                        let (i, j) = (c.i as usize, c.j as usize);
                        let (lower, upper) = if bodies.position[j].y < bodies.position[i].y {
                            (j, i)
                        } else {
                            (i, j)
                        };
                        (upper == u).then_some(lower as u32)
                    })
                    .collect();
                if !supports.is_empty() {
                    let ceiling = Some(work.start_height[u]);
                    held += usize::from(b.hold(u, &supports, support, ceiling, &mut push));
                }
            }
            held
        };
        assert!(reference > 1_000, "held {reference}");
        let pool = crate::sim::threads::thread_pool(Some(2)).unwrap();
        for parallel_level in [1, 16, usize::MAX] {
            let mut b = bodies.clone();
            let held = pool.install(|| {
                BodiesMut::whole(&mut b).support_levels(
                    [&pairs, &[]],
                    support,
                    &mut work,
                    parallel_level,
                )
            });
            assert_eq!(held.held, reference, "levels of {parallel_level}");
            assert_eq!(b.position, by_height.position, "levels of {parallel_level}");
            assert_eq!(b.velocity, by_height.velocity, "levels of {parallel_level}");
        }
    }

    #[test]
    fn a_lift_above_the_steps_start_is_paid_with_kinetic_energy() {
        let (r, g) = (0.05, 9.81);
        let support = Support {
            up: Vec3::Y,
            margin: 0.0,
            speed_tolerance: 0.0,
            gravity: g,
        };
        let mut push = Vec::new();
        // At rest and sunk 0.2 r, with the step begun where it is: it
        // cannot pay, so it stays.
        let mut still = sunk(r, 0.2 * r, Vec3::ZERO);
        let start = still.position[1].y;
        BodiesMut::whole(&mut still).hold(1, &[0], support, Some(start), &mut push);
        assert!(still.position[1].y <= start + RESTING_OVERLAP * r);
        // Sliding sideways at 1 m/s: the rise of 0.2 r costs g 0.01 m of
        // its 0.5 J/kg.
        let mut sliding = sunk(r, 0.2 * r, Vec3::X);
        let start = sliding.position[1].y;
        BodiesMut::whole(&mut sliding).hold(1, &[0], support, Some(start), &mut push);
        let rise = sliding.position[1].y - start;
        let kinetic = 0.5 * sliding.velocity[1].length_squared();
        assert!(rise > 0.19 * r, "rose {} r", rise / r);
        let paid = g * (rise - RESTING_OVERLAP * r);
        assert!(
            (0.5 - kinetic - paid).abs() < 1e-12,
            "paid {paid}, left {kinetic}"
        );
    }

    #[test]
    fn holding_a_sphere_on_its_supports_never_speeds_it_up_and_leaves_no_approach() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let r = 0.05;
        let (mut worst, mut approach): (f64, f64) = (0.0, 0.0);
        for _ in 0..2_000 {
            // Three supports around (0.5, r, 0.5) and a sphere dropped
            // into them, moving anywhere.
            let mut spheres = Vec::new();
            for k in 0..3 {
                let a = k as f64 * 2.0 + rng.random::<f64>();
                let p = Vec3::new(0.5 + 1.2 * r * a.cos(), r, 0.5 + 1.2 * r * a.sin());
                spheres.push(Body {
                    position: p,
                    velocity: Vec3::ZERO,
                    radius: r,
                    mass: 1.0,
                });
            }
            let v = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
            let top = Vec3::new(0.5 + 0.02 * rng.random::<f64>(), 2.4 * r, 0.5);
            spheres.push(Body {
                position: top,
                velocity: v,
                radius: r,
                mass: 1.0,
            });
            let mut bodies: Bodies = spheres.into_iter().collect();
            let support = Support {
                up: Vec3::Y,
                margin: 0.0,
                speed_tolerance: 0.0,
                gravity: 9.81,
            };
            let mut push = Vec::new();
            BodiesMut::whole(&mut bodies).hold(3, &[0, 1, 2], support, None, &mut push);
            let after = bodies.velocity[3];
            assert!(
                after.length() <= v.length() * (1.0 + 1e-12),
                "{v:?} became {after:?}"
            );
            for k in 0..3 {
                let d = bodies.position[3] - bodies.position[k];
                worst = worst.max(2.0 * r - d.length());
                if d.length() < 2.0 * r {
                    approach = approach.max(-after.dot(d.normalize()) / v.length());
                }
            }
        }
        // The sweeps leave under 1% of a radius and of the speed.
        eprintln!(
            "largest overlap left {:.2e} r, largest approach left {approach:.2e} of the speed",
            worst / r
        );
        assert!(approach < 0.01, "approach left {approach} of the speed");
        assert!(worst < 0.01 * r, "largest overlap left {} r", worst / r);
    }
}
