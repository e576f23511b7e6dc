//! Deep piles: further projection passes keep the same bits for any number
//! of threads and either broad phase, and a step whose passes run out says
//! so.

use crate::support::run_on_threads;
use lerpit::sim::{BroadPhase, World};
use lerpit::study::stability::pile_world;

/// A pile of `n` spheres (30% solid) after `steps` steps of `dt` on
/// `threads` threads, with `remedy` applied to its configuration.
fn pile(
    n: usize,
    dt: f64,
    steps: u64,
    broad_phase: BroadPhase,
    threads: usize,
    remedy: impl Fn(&mut lerpit::sim::WorldConfig),
) -> World {
    let mut w = pile_world(lerpit::sim::Integrator::SemiImplicitEuler, n, 0.3, dt)
        .expect("the pile spawns");
    w.config.broad_phase = broad_phase;
    remedy(&mut w.config);
    run_on_threads(&mut w, steps, threads);
    w
}

/// The pile with 4 sub-steps of 4 passes.
fn run(n: usize, steps: u64, broad_phase: BroadPhase, threads: usize) -> World {
    pile(n, 1.0 / 240.0, steps, broad_phase, threads, |c| {
        c.substeps = 4;
        c.projection_passes = 4;
    })
}

#[test]
fn projection_passes_give_the_same_bits_for_any_thread_count_and_broad_phase() {
    let one = run(6_000, 40, BroadPhase::Grid, 1);
    assert!(
        one.last.projection_passes > 0 && one.last.contact_slabs > 2,
        "the test must exercise the passes in slabs: {:?}",
        one.last
    );
    let two = run(6_000, 40, BroadPhase::Grid, 2);
    assert_eq!(one.state_hash(), two.state_hash(), "2 threads against 1");
    let all_pairs = run(6_000, 40, BroadPhase::AllPairs, 2);
    assert_eq!(
        one.state_hash(),
        all_pairs.state_hash(),
        "all-pairs against grid"
    );
}

#[test]
fn a_step_whose_passes_run_out_says_so() {
    let mut w = pile_world(
        lerpit::sim::Integrator::SemiImplicitEuler,
        2_000,
        0.6,
        1.0 / 60.0,
    )
    .expect("the pile spawns");
    w.config.projection_passes = 2;
    w.step();
    assert!(w.last.projection_unconverged, "{:?}", w.last);
    assert_eq!(w.last.projection_passes, 1);
    assert!(w.last.residual_overlap > 0.0);
}

/// The pile at dt = 1/60 s with the support pass.
fn run_supported(n: usize, steps: u64, broad_phase: BroadPhase, threads: usize) -> World {
    pile(n, 1.0 / 60.0, steps, broad_phase, threads, |c| {
        c.support = true
    })
}

#[test]
fn the_support_pass_gives_the_same_bits_for_any_thread_count_and_broad_phase() {
    let one = run_supported(6_000, 40, BroadPhase::Grid, 1);
    assert!(one.last.supported > 1_000, "{:?}", one.last);
    assert!(
        one.last.support_slabs > 2,
        "the test must exercise the parallel slab sweeps: {} slabs",
        one.last.support_slabs
    );
    let two = run_supported(6_000, 40, BroadPhase::Grid, 2);
    assert_eq!(one.state_hash(), two.state_hash(), "2 threads against 1");
    let all_pairs = run_supported(6_000, 40, BroadPhase::AllPairs, 2);
    assert_eq!(
        one.state_hash(),
        all_pairs.state_hash(),
        "all-pairs against grid"
    );
}

/// Rows of spheres stacked as oranges are, in a slice of the box one
/// sphere deep: rows of `per_row` spheres touching each other and the side
/// walls, and rows of one fewer in the grooves between them.
fn stacked_rows(per_row: usize, rows: usize, support: bool) -> World {
    let r = 0.5 / per_row as f64;
    let mut bodies = Vec::new();
    for row in 0..rows {
        let (count, shift) = if row % 2 == 0 {
            (per_row, 0.0)
        } else {
            (per_row - 1, r)
        };
        for k in 0..count {
            let x = r + 2.0 * r * k as f64 + shift;
            let y = r + row as f64 * 3f64.sqrt() * r;
            bodies.push(crate::support::sphere([x, y, 0.5], [0.0; 3], r, 0.01));
        }
    }
    let config = lerpit::sim::WorldConfig {
        dt: 1.0 / 60.0,
        support,
        ..Default::default()
    };
    crate::support::world(config, &bodies)
}

#[test]
fn a_stack_of_oranges_stands_with_the_support_pass_and_collapses_without() {
    // 57 spheres of r = 0.05 m in six rows; at dt = 1/60 s gravity moves
    // each 0.055 r a step.
    let potential = |w: &World| w.diagnostics().potential_energy;
    let mut held = stacked_rows(10, 6, true);
    let mut lesson = stacked_rows(10, 6, false);
    let start = potential(&held);
    held.run(600);
    lesson.run(600);
    let r = held.bodies.radius[0];
    let mut contacts = Vec::new();
    BroadPhase::AllPairs.find_contacts(&held.bodies, &mut contacts);
    let deepest = contacts.iter().map(|c| c.penetration).fold(0.0, f64::max);
    let (held_drop, lesson_drop) = (start - potential(&held), start - potential(&lesson));
    eprintln!(
        "10 s: held PE change {:.3e} J, deepest overlap {:.4} r, KE {:.3e} J; lesson PE change {:.3e} J",
        -held_drop,
        deepest / r,
        held.diagnostics().kinetic_energy,
        -lesson_drop
    );
    assert!(deepest < 0.05 * r, "deepest overlap {} r", deepest / r);
    assert!(
        held_drop.abs() < 0.01 * lesson_drop,
        "held: {held_drop:e} J lost, lesson: {lesson_drop:e} J"
    );
    assert!(lesson_drop > 0.1 * start, "the lesson's stack collapses");
}

#[test]
fn the_support_pass_settles_the_collisions_lesson_with_further_projection_passes_too() {
    // Further passes clamp the spheres into the box between them; with
    // the support pass they must leave the walls to it, or every clamp
    // lifts a sphere out of the floor under the spheres on it, the pass
    // pushes those up, and the pile never settles (it kept 0.15 to 0.5 J
    // of kinetic energy at 40 s, its total energy rising and falling by
    // 0.1 J). When a settling pile falls under 0.02 J is chance: over 40
    // other seeds of the lesson, with one pass or two, from 22 to 42 s
    // (the struck pairs the support pass bounces keep some moving), and
    // the lesson's own seed with one pass at 47 s. So the test looks at
    // 60 s, and at the energy after 30 s.
    for passes in [1, 2, 4] {
        let mut w = lerpit::scene::Lesson::Collisions.scene().build().unwrap();
        w.config.support = true;
        w.config.projection_passes = passes;
        let steps = (60.0 / w.config.dt).round() as u64;
        w.run(steps / 2);
        let half = w.diagnostics().total_energy;
        let mut highest = half;
        for _ in steps / 2..steps {
            w.step();
            highest = highest.max(w.diagnostics().total_energy);
        }
        let end = w.diagnostics();
        eprintln!(
            "{passes} passes: KE {:.2e} J at 60 s; total {half:.5} J at 30 s, at most {highest:.5} J after",
            end.kinetic_energy
        );
        assert!(
            end.kinetic_energy < 0.02,
            "{passes} passes: KE {} J at 60 s",
            end.kinetic_energy
        );
        assert!(
            highest - half < 0.01,
            "{passes} passes: energy rose from {half} J to {highest} J"
        );
    }
}

#[test]
fn the_support_pass_with_further_passes_keeps_a_pile_on_the_floor_at_a_huge_step() {
    // At dt = 1 s every sphere falls through the floor in one step; the
    // clamp between the passes used to put them on it with their speed
    // intact, and the pile ended pressed against the ceiling with seven
    // times its energy.
    for passes in [1, 2] {
        let mut w = lerpit::scene::Lesson::Collisions.scene().build().unwrap();
        (w.config.support, w.config.projection_passes, w.config.dt) = (true, passes, 1.0);
        w.run(100);
        let highest = w.bodies.position.iter().map(|x| x.y).fold(0.0, f64::max);
        assert!(
            highest < 0.5,
            "{passes} passes: a sphere at y = {highest} m"
        );
    }
}

#[test]
fn the_support_pass_leaves_fast_impacts_to_the_lessons_rules() {
    // The pass holds what rests. A pair still apart, or a sphere short of
    // a wall, that closes faster than the pass's margin in a step is an
    // impact to come: held as a speculative contact it lost its approach
    // (a head-on impact at 0.5 m/s came out with e = 0.23 instead of 0.95,
    // a bounce off a side wall at c_r = 1 kept 0.06 of its 2 m/s).
    use crate::support::{sphere, world};
    use lerpit::sim::WorldConfig;
    let config = WorldConfig {
        dt: 1.0 / 120.0,
        wall_restitution: 0.9,
        pair_restitution: 0.95,
        ..WorldConfig::default()
    };
    // Two spheres on the floor, 1 mm apart after the first step, closing
    // at 0.5 m/s: the lesson's V1 = 0.0125, V2 = 0.4875 m/s, with the pass
    // as without it.
    let pair = [
        sphere([0.6, 0.05, 0.5], [0.0; 3], 0.05, 1.0),
        sphere(
            [0.494_833_333_333_333_35, 0.05, 0.5],
            [0.5, 0.0, 0.0],
            0.05,
            1.0,
        ),
    ];
    for support in [false, true] {
        let mut w = world(
            WorldConfig {
                support,
                ..config.clone()
            },
            &pair,
        );
        w.run(2);
        let vx: Vec<f64> = w.bodies.velocity.iter().map(|v| v.x).collect();
        assert!(
            (vx[0] - 0.4875).abs() < 1e-12 && (vx[1] - 0.0125).abs() < 1e-12,
            "support {support}: {vx:?}"
        );
    }
    // A sphere in mid-air 2 m/s short of the side wall at x = 1, c_r = 1:
    // it comes back at 2 m/s.
    let flying = [
        sphere(
            [0.932_833_333_333_333_3, 0.5, 0.5],
            [2.0, 3.0, 0.0],
            0.05,
            1.0,
        ),
        sphere([0.2, 0.05, 0.5], [0.0; 3], 0.05, 1.0),
    ];
    let elastic = WorldConfig {
        wall_restitution: 1.0,
        pair_restitution: 1.0,
        support: true,
        ..config
    };
    let mut w = world(elastic, &flying);
    w.run(2);
    assert_eq!(w.bodies.velocity[0].x, -2.0);
}

#[test]
fn a_sphere_struck_into_its_neighbour_passes_the_blow_on_with_the_support_pass() {
    // Three spheres in a row on the floor, the second 0.5 mm from the
    // third: the first strikes the second, which the lesson's pass sends
    // into the third. The narrow phase found that pair apart, so the
    // lesson's pass did not resolve it; held as a resting contact it lost
    // its approach (the second and third went on together at half the
    // speed). Resolved by the lesson's rule, the blow passes on, with
    // e = 1 whole, as it does without the pass one step later.
    use crate::support::{sphere, world};
    use lerpit::sim::WorldConfig;
    let dt = 1.0 / 120.0;
    let row = [
        sphere(
            [0.5 - 0.1 + 0.002 - dt, 0.05, 0.5],
            [1.0, 0.0, 0.0],
            0.05,
            1.0,
        ),
        sphere([0.5, 0.05, 0.5], [0.0; 3], 0.05, 1.0),
        sphere([0.6005, 0.05, 0.5], [0.0; 3], 0.05, 1.0),
    ];
    let expected = [0.0, 0.0, 1.0];
    for support in [false, true] {
        let config = WorldConfig {
            dt,
            pair_restitution: 1.0,
            support,
            ..WorldConfig::default()
        };
        let mut w = world(config, &row);
        w.run(2);
        let b = &w.bodies;
        for (k, want) in expected.into_iter().enumerate() {
            let v = b.velocity[k];
            assert!(
                (v.x - want).abs() < 1e-12 && v.y.abs() < 1e-12 && v.z == 0.0,
                "support {support}: sphere {k} moves at {v:?}, not {want} along x"
            );
        }
        let kinetic: f64 = b.velocity.iter().map(|v| 0.5 * v.length_squared()).sum();
        assert!(
            (kinetic - 0.5).abs() < 1e-12,
            "support {support}: the energy is kept ({kinetic} J)"
        );
    }
}

#[test]
fn an_elastic_gas_sliding_on_the_floor_keeps_most_of_its_energy_with_the_support_pass() {
    // 25 elastic spheres on a 5 x 5 lattice on the floor, each sliding at
    // 0.2 to 1 m/s in a random direction, for 10 s at dt = 1/120 s: the
    // lesson's rules keep every joule. The support pass holds an approach
    // slower than its margin in a step, (rest_steps + 1) g dt, as resting
    // contact, and so takes some: over eight starts it kept 78% on average
    // while it also held the faster blows of a sphere struck into its
    // neighbour, and keeps 89% now that those bounce.
    use crate::support::{sphere, world};
    use lerpit::sim::WorldConfig;
    use rand::{RngExt, SeedableRng};
    let kept = |seed: u64, support: bool| {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
        let gas: Vec<_> = (0..25)
            .map(|k| {
                let angle = rng.random::<f64>() * std::f64::consts::TAU;
                let speed = 0.2 + 0.8 * rng.random::<f64>();
                let at = |i: usize| 0.1 + 0.2 * i as f64;
                sphere(
                    [at(k / 5), 0.04, at(k % 5)],
                    [speed * angle.cos(), 0.0, speed * angle.sin()],
                    0.04,
                    1.0,
                )
            })
            .collect();
        let config = WorldConfig {
            dt: 1.0 / 120.0,
            wall_restitution: 1.0,
            pair_restitution: 1.0,
            support,
            ..WorldConfig::default()
        };
        let mut w = world(config, &gas);
        let start = w.diagnostics().kinetic_energy;
        w.run(1200);
        w.diagnostics().kinetic_energy / start
    };
    let mut with_pass = Vec::new();
    for seed in 1..=8 {
        let without = kept(seed, false);
        assert!((without - 1.0).abs() < 1e-9, "seed {seed}: {without}");
        with_pass.push(kept(seed, true));
    }
    let mean = with_pass.iter().sum::<f64>() / 8.0;
    eprintln!("kept with the support pass: {with_pass:.3?}, mean {mean:.3}");
    assert!(mean > 0.85, "{with_pass:?}");
}

/// A long step under gravity would carry a sphere across the box: the
/// support pass's margin is then held to the smallest radius, so a step
/// still tests pairs near each sphere, not every pair of the box.
#[test]
fn a_long_step_keeps_the_support_pass_to_each_spheres_neighbours() {
    let n = 3_000;
    let w = pile(n, 1.0, 3, BroadPhase::Grid, 2, |c| c.support = true);
    let all_pairs = (n * (n - 1) / 2) as u64;
    assert!(
        w.last.pair_tests < all_pairs / 10,
        "{} pair tests of {all_pairs} pairs",
        w.last.pair_tests
    );
    assert!(w.last.supported > 0, "the pass ran");
    assert!(w.bodies.position.iter().all(|p| p.is_finite()));
}

#[test]
fn a_sphere_struck_into_its_neighbour_bounces_off_it_with_e_below_one_with_the_support_pass() {
    // The row above at e = 0.5, with a light striker so that no pair
    // closes again: a 0.1 kg sphere at 2 m/s strikes the first of two
    // 1 kg spheres on the floor, 0.2 mm apart. The lesson's pass gives
    // V1 = 2 (0.1 - 0.5) / 1.1 = -0.727 m/s (it bounces back) and
    // V2 = 2 (0.1) (1.5) / 1.1 = 0.273 m/s, and pushes the struck sphere
    // 0.3 mm into its neighbour, a pair the narrow phase found apart. The
    // support pass's bounce resolves that impact by the lesson's rule with
    // e: equal masses leave at V2 (1 - e) / 2 and V2 (1 + e) / 2, as the
    // lesson's pass resolves it one step later without the support pass.
    // Taken as elastic, the blow would pass on whole, as at e = 1.
    use crate::support::{sphere, world};
    use lerpit::sim::WorldConfig;
    use lerpit::sim::contact::normal_speeds_after;
    let (dt, e, u) = (1.0 / 120.0, 0.5, 2.0);
    let (m, r) = ([0.1, 1.0, 1.0], 0.05);
    // Overlapping the second by 3.3 mm after the first step: the lesson's
    // pass moves the second 3.3 mm x 1 / 11 = 0.3 mm.
    let row = [
        sphere(
            [0.5 - 2.0 * r + 0.0033 - u * dt, r, 0.5],
            [u, 0.0, 0.0],
            r,
            m[0],
        ),
        sphere([0.5, r, 0.5], [0.0; 3], r, m[1]),
        sphere([0.5 + 2.0 * r + 0.0002, r, 0.5], [0.0; 3], r, m[2]),
    ];
    let (v1, v2) = normal_speeds_after(m[0], m[1], u, 0.0, e);
    let (v2, v3) = normal_speeds_after(m[1], m[2], v2, 0.0, e);
    assert!(v1 < v2 && v2 < v3, "no pair closes again: {v1} {v2} {v3}");
    for support in [false, true] {
        let config = WorldConfig {
            dt,
            pair_restitution: e,
            support,
            ..WorldConfig::default()
        };
        let mut w = world(config, &row);
        w.run(2);
        for (k, want) in [v1, v2, v3].into_iter().enumerate() {
            let v = w.bodies.velocity[k];
            assert!(
                (v.x - want).abs() < 1e-12 && v.y.abs() < 1e-12 && v.z == 0.0,
                "support {support}: sphere {k} moves at {v:?}, not {want} along x"
            );
        }
    }
}

#[test]
fn a_benchmark_pile_held_by_the_support_pass_comes_to_rest_soon_after_its_fall() {
    // 10,000 spheres at dt = 1/60 s land within 1.5 s, after a fall that
    // gives them up to 290 J. The relax must take back the speed the
    // solve gave to push old overlaps out: with half its sweeps it left
    // enough of it to keep this pile boiling, with 12 to 15 J from 2 to 4 s,
    // and over 0.05 J until 9 s.
    let mut w = lerpit::scene::bench::bench_world(10_000, BroadPhase::Grid);
    w.config.support = true;
    w.run(150);
    for _ in 150..240 {
        w.step();
        let kinetic = w.diagnostics().kinetic_energy;
        assert!(
            kinetic < 0.05,
            "step {}: {kinetic:.3} J still moving",
            w.steps
        );
    }
}
