//! Sleeping: spheres at rest are neither integrated nor solved until
//! something touches them, and a world at rest costs nothing
//! (`WorldConfig::sleep`; the discrete methods).
//!
//! The rule is Box2D's, by islands:
//!
//! - A sphere slower than [`SLEEP_SPEED`] counts the time it has stayed
//!   so (`Bodies::rest`); any faster step sets the count back to zero.
//! - An island is a set of spheres linked by the step's pairs: those
//!   overlapping, and with the support pass those within its margin of
//!   touching. Walls link nothing.
//! - An island whose every sphere has been slow for [`TIME_TO_SLEEP`]
//!   and, under gravity, one of whose spheres lies on a wall that gravity
//!   presses it against (an island in flight is slow at the top of its arc
//!   under weak gravity, not at rest) falls asleep whole: its velocities are set to zero, and from then on
//!   its spheres are not integrated, solved or held by the support pass.
//!   While some sphere is awake, the narrow phase still finds the pairs of
//!   two sleepers, and they are dropped unsolved.
//! - A sleeper wakes when a pair of the narrow phase links it to a sphere
//!   that is awake (something touched it or, with the support pass, came
//!   within its margin), and when any parameter of the
//!   world changes (gravity, restitution, the method...). Either wakes
//!   every sleeper in the world, not just the touched island: a rule this
//!   simple never leaves a sphere asleep in mid-air above one that moved,
//!   and in the scenes here the piles are one island anyway.
//! - While every sphere sleeps, a step only advances the clock: then, and
//!   only then, the spheres cost nothing. While some are awake, the
//!   sleepers still take their part of the broad and narrow phases, which
//!   find their pairs before they are dropped.
//!
//! Islands are the connected parts of a graph, which do not depend on the
//! order the pairs come in: the same contacts give the same sleepers for
//! any number of threads and either broad phase.

use super::{Bodies, Contact, Vec3};
use rayon::prelude::*;

/// Speed below which a sphere counts as at rest, m/s (Box2D's default
/// sleep threshold, for bodies of about a metre: here the box).
pub const SLEEP_SPEED: f64 = 0.05;
/// Time an island must stay at rest before it sleeps, s (Box2D's).
pub const TIME_TO_SLEEP: f32 = 0.5;
/// `Bodies::rest` of a sleeping sphere.
pub(crate) const ASLEEP: f32 = f32::INFINITY;

/// Spheres per parallel task.
const CHUNK: usize = 4096;

/// Whether a sphere with this `rest` sleeps.
#[inline]
pub(crate) fn is_asleep(rest: f32) -> bool {
    rest == ASLEEP
}

/// How many spheres sleep.
pub(crate) fn asleep_count(rest: &[f32]) -> usize {
    // Chunk by chunk, so that each chunk's count is a plain loop the
    // compiler turns into vector instructions: a world all asleep pays
    // for this count and nothing else each step.
    rest.par_chunks(CHUNK)
        .map(|chunk| chunk.iter().filter(|&&r| is_asleep(r)).count())
        .sum()
}

/// Whether a step of `dt` s can end with some sphere ready to sleep (its
/// time at rest reaching [`TIME_TO_SLEEP`], counted as [`settle`] counts
/// it): only then does [`settle`] read the step's links. A sleeper counts
/// as ready.
pub(crate) fn may_fall_asleep(rest: &[f32], dt: f64) -> bool {
    let dt = dt as f32;
    rest.par_iter()
        .with_min_len(CHUNK)
        .any(|&r| r + dt >= TIME_TO_SLEEP)
}

/// Wake every sphere, and start every count of time at rest afresh.
pub(crate) fn wake_all(rest: &mut [f32]) {
    rest.par_iter_mut()
        .with_min_len(CHUNK)
        .for_each(|r| *r = 0.0);
}

/// After the narrow phase of a world with `asleep` sleepers: wake them
/// all if a pair of `lists` links a sleeper to a sphere that is awake
/// (true), otherwise drop the pairs of two sleepers, which stay as they
/// are (false).
pub(crate) fn touch(rest: &mut [f32], lists: [&mut Vec<Contact>; 2]) -> bool {
    let asleep = |k: u32| is_asleep(rest[k as usize]);
    let touched = lists
        .iter()
        .flat_map(|l| l.iter())
        .any(|c| asleep(c.i) != asleep(c.j));
    if touched {
        wake_all(rest);
        return true;
    }
    for list in lists {
        list.retain(|c| !asleep(c.i));
    }
    false
}

/// The island rule's working memory (reused from step to step).
#[derive(Clone, Debug, Default)]
pub(crate) struct SleepWork {
    /// Union-find forest over the slots.
    parent: Vec<u32>,
    /// Per slot: the slot, or (at a root) its island, touches a sphere that
    /// is not ready to sleep.
    blocked: Vec<bool>,
    /// Per slot: at rest for [`TIME_TO_SLEEP`], not yet asleep.
    ready: Vec<bool>,
    /// Per root: the island lies on the ground (per slot before).
    held: Vec<bool>,
}

/// A sphere closer than this fraction of its radius to a wall touches it.
const GROUND_TOLERANCE: f64 = 0.05;

/// Whether a sphere at `x` of radius `r` touches a wall that `gravity`
/// presses it against (the floor, for gravity down).
fn on_the_ground(x: Vec3, r: f64, gravity: Vec3) -> bool {
    (0..3).any(|axis| {
        let g = gravity[axis];
        (g < 0.0 && x[axis] - r <= GROUND_TOLERANCE * r)
            || (g > 0.0 && 1.0 - r - x[axis] <= GROUND_TOLERANCE * r)
    })
}

/// End of a step of `dt` s under `gravity`: count each awake sphere's time
/// at rest, then put to sleep every island of `links` (the step's pairs,
/// every sphere of them awake) whose spheres have all been at rest for
/// [`TIME_TO_SLEEP`] and, under gravity, one of which lies on a wall that
/// holds it up ([`on_the_ground`]). Returns how many spheres fell asleep.
pub(crate) fn settle(
    bodies: &mut Bodies,
    links: [&[Contact]; 2],
    (dt, gravity): (f64, Vec3),
    work: &mut SleepWork,
) -> usize {
    let slow2 = SLEEP_SPEED * SLEEP_SPEED;
    let dt = dt as f32;
    let waiting = bodies
        .rest
        .par_iter_mut()
        .zip(bodies.velocity.par_iter())
        .with_min_len(CHUNK)
        .filter_map(|(r, v)| {
            if is_asleep(*r) {
                return None;
            }
            *r = if v.length_squared() < slow2 {
                *r + dt
            } else {
                0.0
            };
            (*r >= TIME_TO_SLEEP).then_some(())
        })
        .count();
    if waiting == 0 {
        return 0;
    }
    let n = bodies.len();
    let SleepWork {
        parent,
        blocked,
        ready,
        held,
    } = work;
    ready.clear();
    ready.extend(
        bodies
            .rest
            .iter()
            .map(|&r| r >= TIME_TO_SLEEP && !is_asleep(r)),
    );
    parent.clear();
    parent.extend(0..n as u32);
    blocked.clear();
    blocked.resize(n, false);
    // Islands among the spheres ready to sleep; one that touches a sphere
    // not ready is blocked (the whole island then is: following the links
    // out of a part of an island, the first sphere met that is not in it
    // is one not ready).
    for c in links.iter().flat_map(|l| l.iter()) {
        let (i, j) = (c.i as usize, c.j as usize);
        match (ready[i], ready[j]) {
            (true, true) => union(parent, i, j),
            (true, false) => blocked[i] = true,
            (false, true) => blocked[j] = true,
            (false, false) => {}
        }
    }
    // An island in flight is not at rest, however slowly it moves at the
    // top of its arc: under gravity one of its spheres must lie on the
    // ground.
    held.clear();
    held.resize(n, gravity == Vec3::ZERO);
    for k in 0..n {
        if ready[k] && blocked[k] {
            let root = find(parent, k);
            blocked[root] = true;
        }
        if ready[k] && !held[k] && on_the_ground(bodies.position[k], bodies.radius[k], gravity) {
            let root = find(parent, k);
            held[root] = true;
        }
    }
    let mut fell = 0;
    for k in 0..n {
        if ready[k] && !blocked[find(parent, k)] && held[find(parent, k)] {
            bodies.velocity[k] = Vec3::ZERO;
            bodies.rest[k] = ASLEEP;
            fell += 1;
        }
    }
    fell
}

/// The root of `k`'s tree, halving the path on the way.
fn find(parent: &mut [u32], mut k: usize) -> usize {
    while parent[k] as usize != k {
        let up = parent[parent[k] as usize];
        parent[k] = up;
        k = up as usize;
    }
    k
}

/// Join the trees of `a` and `b` (the smaller root under the larger: any
/// rule gives the same islands).
fn union(parent: &mut [u32], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi] = lo as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Body, BroadPhase, World, WorldConfig};

    fn sphere(position: Vec3, velocity: Vec3, radius: f64) -> Body {
        Body {
            position,
            velocity,
            radius,
            mass: 1.0,
        }
    }

    fn sleeping_world(bodies: Vec<Body>) -> World {
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            sleep: true,
            ..WorldConfig::default()
        };
        World::new(config, bodies.into_iter().collect())
    }

    /// Steps until every sphere sleeps; `None` if not within `limit`.
    fn steps_to_sleep(w: &mut World, limit: u64) -> Option<u64> {
        (1..=limit).find(|_| {
            w.step();
            w.last.asleep == w.bodies.len()
        })
    }

    #[test]
    fn sleepers_are_counted_in_every_chunk() {
        // Sleepers at the first and last slot of the chunks, and a time
        // at rest that is not asleep (finite, however long).
        let n = 3 * CHUNK + 5;
        let mut rest = vec![0.25_f32; n];
        assert_eq!(asleep_count(&rest), 0);
        assert_eq!(asleep_count(&[]), 0);
        for k in [0, CHUNK - 1, CHUNK, 3 * CHUNK, n - 1] {
            rest[k] = ASLEEP;
        }
        rest[1] = f32::MAX;
        assert_eq!(asleep_count(&rest), 5);
        assert_eq!(asleep_count(&vec![ASLEEP; n]), n);
    }

    #[test]
    fn a_sphere_at_rest_sleeps_after_half_a_second_and_then_stays_put() {
        let r = 0.05;
        for method in crate::sim::Integrator::ALL
            .into_iter()
            .filter(|m| m.is_discrete())
        {
            let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
            w.config.integrator = method;
            // At rest on the floor from the first step: 0.5 s is 30 steps.
            let steps = steps_to_sleep(&mut w, 100).expect("it falls asleep");
            assert_eq!(steps, 30, "{method}");
            let (x, e) = (w.bodies.position[0], w.diagnostics().total_energy);
            w.run(600);
            assert_eq!(
                w.bodies.position[0], x,
                "a sleeper does not move ({method})"
            );
            assert_eq!(w.bodies.velocity[0], Vec3::ZERO);
            assert_eq!(w.diagnostics().total_energy, e);
            assert_eq!(w.steps, 630, "the clock goes on");
        }
    }

    #[test]
    fn a_sphere_at_rest_on_the_ceiling_under_gravity_up_sleeps_after_half_a_second() {
        // The floor's test turned upside down: gravity presses the sphere
        // against the ceiling, which holds it up, so it lies on the ground
        // there. In mid-air it would not sleep (the test of the slow arc).
        let r = 0.05;
        for method in crate::sim::Integrator::ALL
            .into_iter()
            .filter(|m| m.is_discrete())
        {
            let at = Vec3::new(0.3, 1.0 - r, 0.6);
            let mut w = sleeping_world(vec![sphere(at, Vec3::ZERO, r)]);
            w.config.integrator = method;
            w.config.gravity = -w.config.gravity;
            let steps = steps_to_sleep(&mut w, 100).expect("it falls asleep");
            assert_eq!(steps, 30, "{method}");
            let x = w.bodies.position[0];
            assert!(1.0 - r - x.y <= GROUND_TOLERANCE * r, "{method}: at {x}");
            w.run(600);
            assert_eq!(
                w.bodies.position[0], x,
                "a sleeper does not move ({method})"
            );
            assert_eq!(w.bodies.velocity[0], Vec3::ZERO);
        }
    }

    #[test]
    fn a_sphere_sliding_faster_than_the_threshold_never_sleeps() {
        // No friction: it slides along the floor from wall to wall.
        let r = 0.05;
        let v = Vec3::new(2.0 * SLEEP_SPEED, 0.0, 0.0);
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), v, r)]);
        assert_eq!(steps_to_sleep(&mut w, 600), None);
        // Slowed by the walls' c_r = 0.95 only.
        assert!(w.bodies.velocity[0].length() > 0.9 * v.length());
    }

    #[test]
    fn an_island_with_one_moving_sphere_stays_awake_whole() {
        // Three spheres overlapping in a row, without gravity: the outer
        // ones at rest, the middle one moving. Linked, none may sleep,
        // though two are slow.
        let mut bodies: Bodies = (0..3)
            .map(|k| {
                let v = if k == 1 { Vec3::X } else { Vec3::ZERO };
                sphere(Vec3::new(0.3 + 0.09 * k as f64, 0.5, 0.5), v, 0.05)
            })
            .collect();
        bodies.rest = vec![TIME_TO_SLEEP; 3];
        let mut links = Vec::new();
        crate::sim::broad_phase::all_pairs_within(&bodies, &mut links, 0.0);
        assert_eq!(links.len(), 2, "a chain of three");
        let mut work = SleepWork::default();
        assert_eq!(
            settle(
                &mut bodies,
                [&links, &[]],
                (1.0 / 60.0, Vec3::ZERO),
                &mut work
            ),
            0
        );
        assert_eq!(
            bodies.rest,
            [TIME_TO_SLEEP + 1.0 / 60.0, 0.0, TIME_TO_SLEEP + 1.0 / 60.0]
        );
        // Unlinked, the slow ones sleep and the moving one does not.
        assert_eq!(
            settle(&mut bodies, [&[], &[]], (1.0 / 60.0, Vec3::ZERO), &mut work),
            2
        );
        assert!(is_asleep(bodies.rest[0]) && is_asleep(bodies.rest[2]));
        assert!(!is_asleep(bodies.rest[1]));
        // The middle one now at rest too, and linked again to the two
        // asleep: a sleeper is not ready to sleep (it sleeps already), so
        // the links block the middle one, which stays awake with its time
        // at rest counted. (In a world such links never reach `settle`:
        // the narrow phase's `touch` wakes every sleeper first.) Unlinked,
        // it falls asleep alone.
        links.clear();
        let mut mid = bodies.clone();
        mid.rest[1] = TIME_TO_SLEEP;
        mid.velocity[1] = Vec3::ZERO;
        crate::sim::broad_phase::all_pairs_within(&mid, &mut links, 0.0);
        assert_eq!(links.len(), 2, "the same chain");
        let mut linked = mid.clone();
        assert_eq!(
            settle(
                &mut linked,
                [&links, &[]],
                (1.0 / 60.0, Vec3::ZERO),
                &mut work
            ),
            0
        );
        assert_eq!(linked.rest, [ASLEEP, TIME_TO_SLEEP + 1.0 / 60.0, ASLEEP]);
        assert_eq!(
            settle(&mut mid, [&[], &[]], (1.0 / 60.0, Vec3::ZERO), &mut work),
            1
        );
        assert_eq!(mid.rest, [ASLEEP; 3]);
    }

    #[test]
    fn a_sphere_in_flight_beside_a_sleeper_flies_the_bits_it_flies_alone() {
        // While some spheres sleep and others do not, the step integrates
        // only those awake, by a copy of each method's formula
        // (`Integrator::integrate_awake`). A sphere thrown up at x = 0.7
        // beside one at rest on the floor at x = 0.2, which falls asleep
        // in step 30, flies with the same bits as alone: up to 0.77 m
        // and back, free until it lands (step 44 to 46, by the method), then
        // off the floor.
        let r = 0.05;
        let thrown = sphere(Vec3::new(0.7, 0.15, 0.5), Vec3::new(0.0, 3.5, 0.0), r);
        let resting = sphere(Vec3::new(0.2, r, 0.5), Vec3::ZERO, r);
        for method in crate::sim::Integrator::DISCRETE {
            let mut alone = sleeping_world(vec![thrown]);
            let mut beside = sleeping_world(vec![thrown, resting]);
            alone.config.integrator = method;
            beside.config.integrator = method;
            for step in 1..=60 {
                alone.step();
                beside.step();
                assert_eq!(
                    beside.last.asleep,
                    usize::from(step >= 30),
                    "{method}, step {step}"
                );
                assert_eq!(
                    (beside.bodies.position[0], beside.bodies.velocity[0]),
                    (alone.bodies.position[0], alone.bodies.velocity[0]),
                    "{method}, step {step}"
                );
            }
            assert_eq!(beside.bodies.position[1], resting.position, "{method}");
        }
    }

    #[test]
    fn a_sphere_rolling_into_a_sleeper_wakes_it_and_pushes_it() {
        // A sphere at rest on the floor, and one sliding towards it along
        // the floor at 0.5 m/s with a gap of 0.3 m: the first falls asleep
        // (0.5 s) before the second arrives (0.6 s, step 36).
        let r = 0.05;
        let mut w = sleeping_world(vec![
            sphere(Vec3::new(0.6, r, 0.5), Vec3::ZERO, r),
            sphere(Vec3::new(0.2, r, 0.5), Vec3::new(0.5, 0.0, 0.0), r),
        ]);
        w.run(30);
        assert!(is_asleep(w.bodies.rest[0]) && !is_asleep(w.bodies.rest[1]));
        let mut touched = None;
        for k in 30..120 {
            w.step();
            if !is_asleep(w.bodies.rest[0]) {
                touched = Some(k);
                break;
            }
            assert_eq!(w.bodies.position[0], Vec3::new(0.6, r, 0.5));
        }
        let k = touched.expect("the touch woke the sleeper");
        assert_eq!(k, 36, "woken at the step of the touch");
        w.run(2);
        assert!(
            w.bodies.velocity[0].x > 0.4,
            "the impact passed the momentum on (e = 0.95): v = {}",
            w.bodies.velocity[0]
        );
    }

    #[test]
    fn a_sphere_at_the_top_of_a_slow_arc_does_not_sleep_in_mid_air() {
        // Under 0.1 m/s^2 a sphere thrown up at 0.04 m/s stays slower than
        // 0.05 m/s for 0.9 s about the top of its arc: slow, not at rest.
        let r = 0.05;
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.5, 0.5, 0.5), 0.04 * Vec3::Y, r)]);
        w.config.gravity = Vec3::new(0.0, -0.1, 0.0);
        let mut longest: f32 = 0.0;
        for _ in 0..150 {
            w.step();
            assert_eq!(w.last.asleep, 0, "asleep at y = {}", w.bodies.position[0].y);
            longest = longest.max(w.bodies.rest[0]);
        }
        assert!(
            longest >= TIME_TO_SLEEP,
            "it was slow long enough: {longest} s"
        );
        // Without gravity, the same slow sphere sleeps where it is.
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.5, 0.5, 0.5), 0.04 * Vec3::Y, r)]);
        w.config.gravity = Vec3::ZERO;
        assert_eq!(steps_to_sleep(&mut w, 100), Some(30));
    }

    /// A column of ten spheres held by the support pass on the floor at
    /// x = 0.3, and a sphere sliding to and fro along the floor at z = 0.9,
    /// which never sleeps.
    fn column_and_slider(broad_phase: BroadPhase) -> World {
        let r = 0.04;
        let mut bodies: Vec<Body> = (0..10)
            .map(|k| {
                let y = r + k as f64 * 2.0 * r * (1.0 - crate::sim::support::RESTING_OVERLAP);
                sphere(Vec3::new(0.3, y, 0.5), Vec3::ZERO, r)
            })
            .collect();
        bodies.push(sphere(Vec3::new(0.5, r, 0.9), Vec3::new(1.0, 0.0, 0.0), r));
        let mut w = sleeping_world(bodies);
        w.config.support = true;
        w.config.broad_phase = broad_phase;
        w
    }

    #[test]
    fn with_some_spheres_asleep_the_readouts_are_the_same_for_either_broad_phase() {
        let mut worlds = [BroadPhase::AllPairs, BroadPhase::Grid].map(column_and_slider);
        for step in 0..120 {
            for w in &mut worlds {
                w.step();
            }
            let [a, b] = [0, 1].map(|k| {
                let d = worlds[k].diagnostics();
                (
                    d.contacts,
                    d.max_overlap,
                    d.asleep,
                    d.wall_impacts,
                    d.total_energy,
                )
            });
            assert_eq!(a, b, "step {step}");
            assert_eq!(
                worlds[0].state_hash(),
                worlds[1].state_hash(),
                "step {step}"
            );
        }
        assert_eq!(
            worlds[0].last.asleep, 10,
            "the column sleeps, the slider does not"
        );
    }

    #[test]
    fn a_held_column_woken_from_sleep_goes_on_as_if_it_had_never_slept() {
        // Asleep while the slider moves, its support impulses are kept, so
        // that woken it carries its weight at once: it goes on settling as
        // the same column kept awake did from the step it fell asleep
        // (step 30), where without its impulses it would sink by a hundredth
        // of a radius within five steps.
        let r = 0.04;
        let mut slept = column_and_slider(BroadPhase::Grid);
        slept.run(120);
        assert_eq!(slept.last.asleep, 10);
        slept.config.sleep = false;
        let mut awake = column_and_slider(BroadPhase::Grid);
        awake.config.sleep = false;
        awake.run(30);
        let (top_slept, top_awake) = (slept.bodies.position[9], awake.bodies.position[9]);
        assert_eq!(top_slept, top_awake, "asleep where it stopped at step 30");
        for k in 0..40 {
            slept.step();
            awake.step();
            let moved = |w: &World, top: Vec3| (w.bodies.position[9] - top).length();
            let (a, b) = (moved(&slept, top_slept), moved(&awake, top_awake));
            assert!(
                (a - b).abs() < 1e-6 * r,
                "step {k} after waking: {a:.3e} m against {b:.3e} m"
            );
        }
    }

    #[test]
    fn changing_gravity_wakes_the_sleepers() {
        let r = 0.05;
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
        steps_to_sleep(&mut w, 100).expect("it falls asleep");
        w.config.gravity = -w.config.gravity;
        w.step();
        assert!(!is_asleep(w.bodies.rest[0]));
        assert!(w.bodies.velocity[0].y > 0.0, "it falls up");
        // And switching sleeping off wakes them too.
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
        steps_to_sleep(&mut w, 100).expect("it falls asleep");
        w.config.sleep = false;
        w.step();
        assert_eq!(w.bodies.rest[0], 0.0);
        assert_eq!(w.last.asleep, 0);
    }

    #[test]
    fn a_pile_sleeps_the_same_for_either_broad_phase() {
        // The collisions lesson's kind of pile, small: 60 spheres dropped.
        let mut worlds: Vec<World> = [BroadPhase::AllPairs, BroadPhase::Grid]
            .into_iter()
            .map(|bp| {
                let bodies: Vec<Body> = (0..60)
                    .map(|k| {
                        let (x, z) = ((k % 8) as f64, ((k / 8) % 8) as f64);
                        let p = Vec3::new(0.1 + 0.1 * x, 0.1 + 0.011 * k as f64, 0.1 + 0.1 * z);
                        sphere(p, Vec3::new(0.3, 0.0, -0.2), 0.06)
                    })
                    .collect();
                let mut w = sleeping_world(bodies);
                w.config.broad_phase = bp;
                w.config.support = true;
                w
            })
            .collect();
        let slept: Vec<Option<u64>> = worlds.iter_mut().map(|w| steps_to_sleep(w, 3000)).collect();
        assert!(slept[0].is_some(), "the pile comes to rest and sleeps");
        assert_eq!(slept[0], slept[1]);
        assert_eq!(worlds[0].state_hash(), worlds[1].state_hash());
    }
}
