//! Invariants over random scenes (proptest) and a long soak of the
//! collisions lesson: finite state, every centre inside [r, 1 - r], kinetic
//! energy that never grows without gravity, and bit-identical reruns; and
//! momentum that only gravity and the walls' reported impulses change.

use lerpit::scene::Lesson;
use lerpit::sim::{Bodies, Body, Integrator, Vec3, WallMode, World, WorldConfig};
use proptest::prelude::*;

fn assert_inside_and_finite(w: &World) {
    let b = &w.bodies;
    for i in 0..b.len() {
        let (x, v, r) = (b.position[i], b.velocity[i], b.radius[i]);
        assert!(
            x.is_finite() && v.is_finite(),
            "step {}: body {i} not finite: {x} {v}",
            w.steps
        );
        for axis in 0..3 {
            assert!(
                x[axis] >= r && x[axis] <= 1.0 - r,
                "step {}: body {i} (r {r}) outside the box on axis {axis}: {x}",
                w.steps
            );
        }
    }
}

fn arb_body() -> impl Strategy<Value = Body> {
    (
        0.01..0.12f64,
        prop::array::uniform3(0.0..1.0f64),
        prop::array::uniform3(-5.0..5.0f64),
        0.05..20.0f64,
    )
        .prop_map(|(radius, u, v, mass)| Body {
            // Map [0, 1) onto the allowed range [r, 1 - r].
            position: Vec3::from_array(u.map(|c| radius + c * (1.0 - 2.0 * radius))),
            velocity: Vec3::from_array(v),
            radius,
            mass,
        })
}

fn arb_config(with_gravity: bool) -> impl Strategy<Value = WorldConfig> {
    (
        1e-4..0.05f64,
        0..Integrator::ALL.len(),
        any::<bool>(),
        0.0..=1.0f64,
        0.0..=1.0f64,
        0.0..20.0f64,
        any::<bool>(),
    )
        .prop_map(move |(dt, m, flip, c_r, e, g, pairs)| WorldConfig {
            gravity: if with_gravity {
                Vec3::new(0.0, -g, 0.0)
            } else {
                Vec3::ZERO
            },
            dt,
            integrator: Integrator::ALL[m],
            wall_mode: if flip {
                WallMode::Flip
            } else {
                WallMode::Restitution
            },
            wall_restitution: c_r,
            pair_collisions: pairs,
            pair_restitution: e,
            ..WorldConfig::default()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn every_sphere_stays_finite_and_inside_the_box(
        bodies in prop::collection::vec(arb_body(), 1..30),
        config in arb_config(true),
    ) {
        let mut w = World::new(config, bodies.into_iter().collect::<Bodies>());
        for _ in 0..60 {
            w.step();
            assert_inside_and_finite(&w);
        }
    }

    /// Walls with c_r <= 1 and impulses with e <= 1 only remove kinetic
    /// energy, and nothing adds any without gravity. The tolerance, 1e-12
    /// relative per step, covers the rounding of the velocity updates.
    #[test]
    fn kinetic_energy_never_grows_without_gravity(
        bodies in prop::collection::vec(arb_body(), 1..30),
        config in arb_config(false),
    ) {
        let mut w = World::new(config, bodies.into_iter().collect::<Bodies>());
        let mut previous = w.diagnostics().kinetic_energy;
        for _ in 0..60 {
            w.step();
            let now = w.diagnostics().kinetic_energy;
            prop_assert!(
                now <= previous * (1.0 + 1e-12),
                "step {}: kinetic energy grew from {previous} to {now}", w.steps
            );
            previous = now;
        }
    }

    #[test]
    fn the_same_scene_and_seed_give_bit_identical_states(
        lesson in prop::sample::select(Lesson::ALL.to_vec()),
        seed in any::<u64>(),
        steps in 1u64..200,
    ) {
        let run = || {
            let mut scene = lesson.scene();
            scene.seed = seed;
            let mut w = scene.build().unwrap();
            w.run(steps);
            w
        };
        let (a, b) = (run(), run());
        prop_assert_eq!(a.state_hash(), b.state_hash());
        prop_assert_eq!(&a.bodies, &b.bodies);
    }
}

#[test]
fn the_collisions_lesson_keeps_every_invariant_for_100_000_steps() {
    let mut w = Lesson::Collisions.scene().build().unwrap();
    let initial = w.diagnostics().total_energy;
    for _ in 0..100_000 {
        w.step();
        assert_inside_and_finite(&w);
        let d = w.diagnostics();
        // Restitution below 1 only dissipates; the position projection can
        // lift a sphere, but never by more than the energy lost.
        assert!(
            d.total_energy <= initial,
            "step {}: total energy {} above the initial {initial}",
            w.steps,
            d.total_energy
        );
    }
    assert_eq!(w.steps, 100_000);
}

#[test]
fn every_step_changes_the_momentum_by_gravitys_impulse_plus_the_walls_reported_one() {
    // Spheres of unlike masses thrown at every wall, no pair collisions:
    // over each step of a discrete method the momentum changes by gravity's
    // impulse, sum m g dt, plus the impulse the wall stage reports
    // (`StepStats::wall_impulse`), to rounding. The spheres bounce for two
    // seconds, then some rest on the floor, which then gives back each
    // step's m g dt.
    let bodies = [
        ([0.5, 0.5, 0.5], [3.0, -4.0, 1.0], 0.05, 0.3),
        ([0.2, 0.8, 0.3], [-2.0, 1.5, -3.0], 0.08, 2.5),
        ([0.7, 0.2, 0.8], [1.0, 5.0, 2.5], 0.1, 7.0),
    ]
    .map(|(x, v, radius, mass)| Body {
        position: Vec3::from_array(x),
        velocity: Vec3::from_array(v),
        radius,
        mass,
    });
    let scale: f64 = bodies.iter().map(|b| b.mass * b.velocity.length()).sum();
    for integrator in Integrator::DISCRETE {
        let config = WorldConfig {
            integrator,
            wall_restitution: 0.8,
            pair_collisions: false,
            ..WorldConfig::default()
        };
        let (g, dt) = (config.gravity, config.dt);
        let mut w = World::new(config, bodies.into_iter().collect::<Bodies>());
        let mass: f64 = w.bodies.mass.iter().sum();
        // Steps in which the walls pushed along each axis.
        let mut pushed = [0; 3];
        for _ in 0..240 {
            let before = w.diagnostics().momentum;
            w.step();
            let gained = w.diagnostics().momentum - before;
            let walls = w.last.wall_impulse;
            assert!(
                (gained - mass * g * dt - walls).length() < 1e-13 * scale,
                "{integrator}, step {}: momentum changed by {gained}, gravity and walls \
                 gave {} and {walls}",
                w.steps,
                mass * g * dt
            );
            for (axis, count) in pushed.iter_mut().enumerate() {
                *count += usize::from(walls[axis] != 0.0);
            }
        }
        assert!(pushed.iter().all(|&n| n > 2), "{integrator}: {pushed:?}");
    }
}
