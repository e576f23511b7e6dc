//! Invariants over random scenes (proptest) and a long soak of the
//! collisions lesson: finite state, every centre inside [r, 1 - r], kinetic
//! energy that never grows without gravity, and bit-identical reruns.

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
