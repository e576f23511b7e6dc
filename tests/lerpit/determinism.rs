//! Bit-identical results for any number of threads, from run to run, and
//! for either broad phase, on worlds large enough to take the parallel,
//! spatially ordered path.

use crate::support::run_on_threads;
use lerpit::scene::Lesson;
use lerpit::scene::bench::bench_world;
use lerpit::sim::large::SPATIAL_ORDER_MIN_BODIES;
use lerpit::sim::{BroadPhase, World};

/// Step the benchmark scene on `threads` threads; the final state hash and
/// the last step's contact slabs.
fn run(n: usize, steps: u64, broad_phase: BroadPhase, threads: usize) -> (u64, World) {
    let mut world = bench_world(n, broad_phase);
    run_on_threads(&mut world, steps, threads);
    (world.state_hash(), world)
}

#[test]
fn one_two_and_four_threads_give_the_same_bits() {
    let (n, steps) = (30_000, 12);
    let (one, world) = run(n, steps, BroadPhase::Grid, 1);
    assert!(
        world.last.contacts > 1000 && world.last.contact_slabs > 2,
        "the test must exercise the parallel slab solver: {} contacts in {} slabs",
        world.last.contacts,
        world.last.contact_slabs
    );
    for threads in [2, 4] {
        let (hash, _) = run(n, steps, BroadPhase::Grid, threads);
        assert_eq!(hash, one, "{threads} threads against 1 thread");
    }
}

#[test]
fn a_world_that_keeps_no_contact_list_sweeps_to_the_same_bits() {
    // Without a list the large world finds and resolves each contact in one
    // sweep; the bodies and the step's counts must be those of the two
    // stages, on one thread or two, in a dense pile (the narrow phase's
    // single-precision first test from the second step) and spread out.
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    for start in [BenchStart::Settled, BenchStart::Dilute] {
        let listed = |threads| {
            let mut w = bench_world_from(start, 20_000, BroadPhase::Auto);
            run_on_threads(&mut w, 6, threads);
            w
        };
        let swept = |threads| {
            let mut w = bench_world_from(start, 20_000, BroadPhase::Auto);
            w.keep_contacts(false);
            run_on_threads(&mut w, 6, threads);
            w
        };
        let want = listed(2);
        assert!(
            want.last.contacts > 1000 && want.last.contact_slabs > 2,
            "{start:?}: {} contacts in {} slabs",
            want.last.contacts,
            want.last.contact_slabs
        );
        assert_eq!(want.contacts().len(), want.last.contacts);
        for threads in [1, 2] {
            let got = swept(threads);
            assert_eq!(
                got.state_hash(),
                want.state_hash(),
                "{start:?}, {threads} threads"
            );
            assert_eq!(got.last, want.last, "{start:?}, {threads} threads");
            assert!(got.contacts().is_empty(), "no list was kept");
        }
    }
}

#[test]
fn the_same_run_twice_gives_the_same_bits() {
    let (a, _) = run(20_000, 8, BroadPhase::Auto, 2);
    let (b, _) = run(20_000, 8, BroadPhase::Auto, 2);
    assert_eq!(a, b);
}

#[test]
fn grid_and_all_pairs_give_the_same_motion() {
    let n = SPATIAL_ORDER_MIN_BODIES + 500;
    let (grid, world) = run(n, 3, BroadPhase::Grid, 2);
    let (all, _) = run(n, 3, BroadPhase::AllPairs, 2);
    assert!(world.last.contacts > 0, "the scene has contacts to resolve");
    assert_eq!(grid, all);
}

#[test]
fn a_large_world_on_the_grid_lists_what_all_pairs_lists_step_by_step() {
    // Keeping its list, a large world on the grid sweeps from its second
    // step, writing each contact to the list as it resolves it; all-pairs
    // lists them first and then resolves them. Every step gives the same
    // list and the same bits, also the step after the layer is squeezed
    // sideways, whose slabs find more contacts than the room the steps
    // before left them.
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    let n = SPATIAL_ORDER_MIN_BODIES + 500;
    let make = |method| {
        let mut w = bench_world_from(BenchStart::Settled, n, method);
        w.time_stages(true);
        w
    };
    let (mut grid, mut all) = (make(BroadPhase::Grid), make(BroadPhase::AllPairs));
    for step in 1..=6 {
        if step == 4 {
            for w in [&mut grid, &mut all] {
                for p in &mut w.bodies.position {
                    (p.x, p.z) = (0.5 + (p.x - 0.5) * 0.7, 0.5 + (p.z - 0.5) * 0.7);
                }
            }
        }
        let before = grid.last.contacts;
        run_on_threads(&mut grid, 1, 2);
        run_on_threads(&mut all, 1, 2);
        assert!(
            grid.last.contacts > n,
            "step {step}: {}",
            grid.last.contacts
        );
        if step == 4 {
            assert!(
                grid.last.contacts > 2 * before,
                "squeezed: {before} then {}",
                grid.last.contacts
            );
        }
        assert_eq!(grid.contacts(), all.contacts(), "step {step}");
        // The counts but those of the broad phase's own.
        let counts = |w: &World| lerpit::sim::StepStats {
            pair_tests: 0,
            broad_phase: None,
            ..w.last
        };
        assert_eq!(counts(&grid), counts(&all), "step {step}");
        assert_eq!(grid.state_hash(), all.state_hash(), "step {step}");
        // Stage times add up over the steps: none in the sweep before it
        // first runs, and (on a clock that sees the milliseconds it takes)
        // some once it has.
        let swept = grid.stage_seconds().unwrap().narrow_and_solve > 0.0;
        if crate::support::stage_clock_is_fine() {
            assert_eq!(swept, step > 1, "step {step}: the grid world swept");
        } else {
            assert!(!swept || step > 1, "step {step}: the grid world swept");
        }
    }
}

#[test]
fn the_lessons_run_the_same_with_either_broad_phase() {
    use lerpit::scene::Lesson;
    for lesson in Lesson::ALL {
        let mut hashes = Vec::new();
        for method in [BroadPhase::AllPairs, BroadPhase::Grid] {
            let mut scene = lesson.scene();
            scene.world.broad_phase = method;
            let mut world = scene.build().expect("the lessons build");
            world.run(240);
            hashes.push(world.state_hash());
        }
        assert_eq!(hashes[0], hashes[1], "lesson {}", lesson.name());
    }
}

#[test]
fn an_interrupted_step_stops_between_sub_steps_and_counts_no_step() {
    let mut world = Lesson::Collisions.scene().build().unwrap();
    world.config.substeps = 4;
    let before = world.clone();
    let asked = std::cell::Cell::new(0);
    let finished = world.try_step(&|| {
        asked.set(asked.get() + 1);
        asked.get() == 2
    });
    assert!(!finished, "the step was abandoned");
    assert_eq!(
        asked.get(),
        2,
        "asked before sub-steps 2 and 3, stopped at 3"
    );
    assert_eq!((world.steps, world.time), (0, 0.0));
    assert_eq!(world.last, before.last);
    assert_ne!(
        world.bodies, before.bodies,
        "two sub-steps moved the bodies"
    );

    // Put back, the world steps to the same bits as one never interrupted.
    world.bodies = before.bodies.clone();
    assert!(world.try_step(&|| false));
    let mut reference = before;
    reference.step();
    assert_eq!(world.state_hash(), reference.state_hash());
}

#[test]
fn the_continuous_method_gives_way_between_impacts() {
    let mut world = Lesson::Collisions.scene().build().unwrap();
    world.config.integrator = lerpit::sim::Integrator::Continuous;
    world.config.dt = 0.5;
    let before = world.clone();
    let asked = std::cell::Cell::new(0);
    let finished = world.try_step(&|| {
        asked.set(asked.get() + 1);
        true
    });
    assert!(!finished, "a step of many impacts was abandoned");
    assert_eq!(asked.get(), 1, "at the first time it asked");
    assert_eq!((world.steps, world.time), (0, 0.0));
    world.bodies = before.bodies.clone();
    assert!(world.try_step(&|| false));
    let mut reference = before;
    reference.step();
    assert_eq!(world.state_hash(), reference.state_hash());
}

#[test]
fn the_continuous_method_gives_way_between_the_passes_that_push_a_pile_apart() {
    // A settled layer handed to the continuous method is jammed too deep
    // for the passes that push its overlaps apart: all 64 run, then a last
    // look still finds deep pairs. The step asks before each pass, so a key
    // waits for one pass, not for all of them (at 100,000 spheres a fifth
    // of a second each). Stopped at any ask and put back, the world steps
    // to the bits of the step never interrupted.
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    use lerpit::sim::Integrator;
    let deep = |w: &World| {
        let b = &w.bodies;
        let mut count = 0;
        for i in 0..b.len() {
            for j in i + 1..b.len() {
                let reach = b.radius[i] + b.radius[j];
                if b.position[i].distance(b.position[j]) < 0.99 * reach {
                    count += 1;
                }
            }
        }
        count
    };
    let mut world = bench_world_from(BenchStart::Settled, 1000, BroadPhase::Auto);
    world.step();
    world.config.integrator = Integrator::Continuous;
    let before = world.clone();
    let (reference, asked) = asks_in_a_step(&before);
    assert!(
        reference.last.projection_unconverged,
        "the layer stays jammed"
    );
    assert!(asked > 65, "{asked} asks");
    // Stopped at the third ask, two passes have run: far more pairs are
    // still deep than after all of them.
    let mut w = before.clone();
    let asks = std::cell::Cell::new(0);
    assert!(!w.try_step(&|| {
        asks.set(asks.get() + 1);
        asks.get() == 3
    }));
    let (after_two, after_all) = (deep(&w), deep(&reference));
    assert!(
        2 * after_two > 3 * after_all,
        "{after_two} pairs deeper than 1% after two passes, {after_all} after the step"
    );
    for stop in [1, 2, 3, 40, 65, 66, asked] {
        stopped_and_put_back_steps_as(&before, &reference, stop);
    }
}

#[test]
fn a_large_step_gives_way_between_batches_of_slabs() {
    // A step asks between batches of slabs as well as between stages;
    // stopped at any of those, put back, the world steps to the bits of
    // the step never interrupted. Without a list, and with one: the first
    // step runs the narrow phase, then the slab solver; later ones sweep
    // and list, and either put the slabs' parts of the list together in
    // place (a slab found more than its room: the third step here) or
    // close them up (the ninth).
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    // This world has 101 slabs in batches of 34: the sweep's two waves take
    // 2 batches each, the slab solver's too; the narrow phase takes 3 (6 in
    // the first step, which counts before it lists), as does the check
    // that the contacts follow the slabs. Putting the list together takes
    // PUTTING asks of its own, closing it up CLOSING (FIRST_CLOSING in the
    // first step: the list and its slack differ). A stage asks before each batch but
    // its first; the check and the solver are one stage. Besides, the step
    // asks after the broad phase, after the narrow phase (with a list) and
    // after the contacts.
    const FIRST_CLOSING: usize = 29;
    const PUTTING: usize = 11;
    const CLOSING: usize = 19;
    let swept = 2 + (4 - 1);
    let first = 3 + (6 - 1) + FIRST_CLOSING + (3 - 1) + 4;
    for (keep, steps_before, asks) in [
        (false, 1, swept),
        (true, 0, first),
        (true, 2, swept + PUTTING),
        (true, 8, swept + CLOSING),
    ] {
        let mut world = bench_world_from(BenchStart::Settled, 200_000, BroadPhase::Auto);
        world.keep_contacts(keep);
        world.run(steps_before);
        let before = world.clone();
        let (reference, asked) = asks_in_a_step(&before);
        assert!(
            reference.contacts().is_empty() != keep && reference.last.contact_slabs == 101,
            "kept {keep}: {} slabs",
            reference.last.contact_slabs
        );
        assert_eq!(asked, asks, "kept {keep}, after {steps_before} steps");
        let mut stops = vec![1, 2, asks / 2, asks - 1, asks];
        stops.dedup();
        for stop in stops {
            stopped_and_put_back_steps_as(&before, &reference, stop);
        }
    }
}

/// A step of `before` that nothing stops, and how many times it asked
/// whether to stop.
fn asks_in_a_step(before: &World) -> (World, usize) {
    let asked = std::cell::Cell::new(0);
    let mut reference = before.clone();
    assert!(reference.try_step(&|| {
        asked.set(asked.get() + 1);
        false
    }));
    (reference, asked.get())
}

/// A step of `before` stopped at its `stop`-th ask counts no step; with
/// the bodies put back, the next step ends in the bits of `reference`.
fn stopped_and_put_back_steps_as(before: &World, reference: &World, stop: usize) {
    let mut w = before.clone();
    let asked = std::cell::Cell::new(0);
    let finished = w.try_step(&|| {
        asked.set(asked.get() + 1);
        asked.get() == stop
    });
    assert!(!finished, "stopped at ask {stop}");
    assert_eq!((w.steps, w.time), (before.steps, before.time));
    w.bodies = before.bodies.clone();
    assert!(w.try_step(&|| false));
    assert_eq!(w.state_hash(), reference.state_hash(), "stopped at {stop}");
}

#[test]
fn the_support_pass_gives_way_between_its_sweeps() {
    // Stopped in the support pass's sweeps, put back, a world holding a
    // pile steps to the bits of the step never interrupted: what the pass
    // carries from step to step is changed only by a pass that finished.
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    let mut world = bench_world_from(BenchStart::Settled, 20_000, BroadPhase::Auto);
    world.config.support = true;
    world.step();
    world.step();
    let before = world.clone();
    let (reference, asks) = asks_in_a_step(&before);
    assert!(reference.last.supported > 1000, "the pass holds the pile");
    assert!(
        asks > lerpit::sim::support::SOLVE_SWEEPS,
        "asked {asks} times: between stages and before every sweep but the first"
    );
    for stop in [asks - 10, asks - 1, asks] {
        stopped_and_put_back_steps_as(&before, &reference, stop);
    }
}

/// 64 spheres of radius `r` thrown at `velocity` from halfway up the box,
/// each over a site of a `side` x `side` floor lattice (site 73 k), a
/// little off its centre.
fn thrown_over(side: usize, r: f64, velocity: lerpit::sim::Vec3) -> Vec<lerpit::sim::Body> {
    use lerpit::sim::{Body, Vec3};
    let at = |k: usize| (0.5 + k as f64) / side as f64;
    (0..64)
        .map(|k| Body {
            position: Vec3::new(at(73 * k % side) + 0.002, 0.5, at(73 * k / side)),
            velocity,
            radius: r,
            mass: 1.0,
        })
        .collect()
}

/// 4,624 spheres at rest on the floor, apart, and 64 thrown up from above
/// some of them, which land after the floor has fallen asleep (0.5 s) and
/// wake the spheres they strike: sleeping, waking and sleeping again in a
/// world large enough to move its spheres between slots.
fn sleeping_floor(broad_phase: BroadPhase) -> World {
    use lerpit::sim::{Body, Vec3, WorldConfig};
    let (side, r) = (68, 0.005);
    let at = |k: usize| (0.5 + k as f64) / side as f64;
    let mut bodies: Vec<Body> = (0..side * side)
        .map(|k| Body {
            position: Vec3::new(at(k % side), r, at(k / side)),
            velocity: Vec3::ZERO,
            radius: r,
            mass: 1.0,
        })
        .collect();
    bodies.extend(thrown_over(side, r, Vec3::new(0.0, 3.0, 0.0)));
    let config = WorldConfig {
        dt: 1.0 / 60.0,
        broad_phase,
        sleep: true,
        ..WorldConfig::default()
    };
    World::new(config, bodies.into_iter().collect())
}

#[test]
fn sleeping_and_waking_give_the_same_bits_for_any_thread_count_and_broad_phase() {
    let mut w = sleeping_floor(BroadPhase::Grid);
    assert!(w.bodies.len() >= SPATIAL_ORDER_MIN_BODIES);
    run_on_threads(&mut w, 40, 2);
    assert_eq!(
        w.last.asleep,
        68 * 68,
        "the floor sleeps, the thrown do not"
    );
    let mut fewest = w.last.asleep;
    for _ in 40..120 {
        run_on_threads(&mut w, 1, 2);
        fewest = fewest.min(w.last.asleep);
    }
    // Each landing wakes the sphere it strikes, not the whole floor.
    assert!(
        (68 * 68 / 2..=68 * 68 - 64).contains(&fewest),
        "{fewest} asleep at the fewest"
    );
    let hash = w.state_hash();
    for (threads, method) in [(1, BroadPhase::Grid), (2, BroadPhase::AllPairs)] {
        let mut other = sleeping_floor(method);
        run_on_threads(&mut other, 120, threads);
        assert_eq!(other.state_hash(), hash, "{threads} threads, {method}");
    }
}

/// 2,116 columns of two spheres, one resting on the other on the floor,
/// apart from each other, at dt = 1/240 s: each step gravity presses the
/// pairs together (a contact each), slowly enough that they are at rest,
/// and they fall asleep after half a second.
fn resting_columns() -> World {
    use lerpit::sim::{Body, Vec3, WorldConfig};
    let (side, r) = (46, 0.005);
    let at = |k: usize| (0.5 + k as f64) / side as f64;
    let bodies: Vec<Body> = (0..side * side)
        .flat_map(|k| {
            [r, 3.0 * r].map(|y| Body {
                position: Vec3::new(at(k % side), y, at(k / side)),
                velocity: Vec3::ZERO,
                radius: r,
                mass: 1.0,
            })
        })
        .collect();
    let config = WorldConfig {
        dt: 1.0 / 240.0,
        broad_phase: BroadPhase::Grid,
        sleep: true,
        ..WorldConfig::default()
    };
    World::new(config, bodies.into_iter().collect())
}

#[test]
fn keeping_no_list_a_sleeping_world_sweeps_until_sleep_reads_the_links() {
    // Keeping no list of contacts, the world sweeps in the steps where
    // sleeping reads no links and lists them in the others (those that
    // may end with spheres ready to sleep), step for step with the bits
    // of a world on all-pairs, which lists every step's contacts first.
    let mut listed = resting_columns();
    listed.config.broad_phase = BroadPhase::AllPairs;
    assert!(listed.bodies.len() >= SPATIAL_ORDER_MIN_BODIES);
    let mut swept = resting_columns();
    swept.keep_contacts(false);
    let (mut sweeps, mut lists) = (0, 0);
    for step in 1..=150 {
        run_on_threads(&mut listed, 1, 2);
        run_on_threads(&mut swept, 1, 2);
        // The counts but those of the broad phase's own.
        let counts = |w: &World| lerpit::sim::StepStats {
            pair_tests: 0,
            broad_phase: None,
            ..w.last
        };
        assert_eq!(counts(&swept), counts(&listed), "step {step}");
        if swept.last.contacts > 0 {
            if swept.contacts().is_empty() {
                sweeps += 1;
            } else {
                assert_eq!(swept.contacts(), listed.contacts(), "step {step}");
                lists += 1;
            }
        }
    }
    assert_eq!(swept.state_hash(), listed.state_hash());
    assert_eq!(
        listed.last.asleep,
        listed.bodies.len(),
        "every column sleeps"
    );
    assert!(
        sweeps > 100 && lists > 0,
        "{sweeps} steps swept, {lists} listed"
    );
}

#[test]
fn a_world_whose_step_reads_its_contacts_lists_them_however_it_was_told() {
    // The support pass, further projection passes, the continuous method
    // and all-pairs each need the list (or find no grid to sweep): told to
    // keep none, the world still lists them, with the same bits.
    use lerpit::scene::bench::{BenchStart, bench_world_from};
    use lerpit::sim::{Integrator, WorldConfig};
    type Change = fn(&mut WorldConfig);
    let changes: [(&str, BenchStart, Change); 3] = [
        ("support", BenchStart::Settled, |c| c.support = true),
        ("projection passes", BenchStart::Settled, |c| {
            c.projection_passes = 3
        }),
        ("all-pairs", BenchStart::Settled, |c| {
            c.broad_phase = BroadPhase::AllPairs
        }),
    ];
    for (what, start, change) in changes {
        let make = || {
            let mut w = bench_world_from(start, SPATIAL_ORDER_MIN_BODIES + 500, BroadPhase::Auto);
            change(&mut w.config);
            w.time_stages(true);
            w
        };
        let (mut kept, mut told) = (make(), make());
        told.keep_contacts(false);
        run_on_threads(&mut kept, 2, 2);
        run_on_threads(&mut told, 2, 2);
        assert_eq!(told.state_hash(), kept.state_hash(), "{what}");
        assert_eq!(told.last, kept.last, "{what}");
        assert!(!told.contacts().is_empty(), "{what}: the list is kept");
        assert_eq!(told.contacts(), kept.contacts(), "{what}");
        let stages = told.stage_seconds().unwrap();
        assert_eq!(stages.narrow_and_solve, 0.0, "{what}: no sweep");
    }

    // The continuous method runs the contact stages after its impact cap:
    // a lattice of 4,913 elastic spheres a thousandth of a radius apart,
    // moving every way, meets it in its first step.
    use lerpit::sim::{Body, Vec3};
    let lattice = || {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let (side, r) = (17, 0.005);
        let at = |k: usize| 0.3 + 2.001 * r * k as f64;
        let bodies: Vec<Body> = (0..side * side * side)
            .map(|k| Body {
                position: Vec3::new(at(k % side), at(k / side % side), at(k / side / side)),
                velocity: Vec3::new(
                    rng.random::<f64>() - 0.5,
                    rng.random::<f64>() - 0.5,
                    rng.random::<f64>() - 0.5,
                ) * 0.2,
                radius: r,
                mass: 1.0,
            })
            .collect();
        let config = WorldConfig {
            integrator: Integrator::Continuous,
            gravity: Vec3::ZERO,
            pair_collisions: true,
            pair_restitution: 1.0,
            broad_phase: BroadPhase::Grid,
            ..WorldConfig::default()
        };
        World::new(config, bodies.into_iter().collect())
    };
    let (mut kept, mut told) = (lattice(), lattice());
    told.keep_contacts(false);
    run_on_threads(&mut kept, 1, 2);
    run_on_threads(&mut told, 1, 2);
    assert!(kept.last.event_cap_reached, "the cap is reached");
    assert_eq!(told.state_hash(), kept.state_hash());
    assert_eq!(told.contacts(), kept.contacts());
}

#[test]
fn a_sleeping_world_that_turned_the_support_pass_off_sleeps_as_all_pairs_does() {
    // Pairs a hair apart on the floor (the support pass lists them as near
    // touching), and spheres thrown up among them. After 10 steps with the
    // pass the world turns it off: sweeping, keeping no list, it must put
    // the same spheres to sleep as all-pairs, which lists every step's
    // contacts afresh, and end in the same bits.
    use lerpit::sim::{Body, Vec3, WorldConfig};
    let (side, r) = (46, 0.004);
    let at = |k: usize| (0.5 + k as f64) / side as f64;
    let mut bodies: Vec<Body> = (0..side * side)
        .flat_map(|k| {
            [-r - 5e-5, r + 5e-5].map(|dx| Body {
                position: Vec3::new(at(k % side) + dx, r, at(k / side)),
                velocity: Vec3::ZERO,
                radius: r,
                mass: 1.0,
            })
        })
        .collect();
    bodies.extend(thrown_over(side, r, Vec3::new(1.3, 3.0, 0.7)));
    assert!(bodies.len() >= SPATIAL_ORDER_MIN_BODIES);
    let config = WorldConfig {
        dt: 1.0 / 240.0,
        broad_phase: BroadPhase::Grid,
        sleep: true,
        support: true,
        ..WorldConfig::default()
    };
    let mut world = World::new(config, bodies.into_iter().collect());
    world.run(10);
    let mut swept = world.clone();
    swept.config.support = false;
    swept.keep_contacts(false);
    let mut listed = swept.clone();
    listed.keep_contacts(true);
    listed.config.broad_phase = BroadPhase::AllPairs;
    let mut most_asleep = 0;
    for step in 1..=200 {
        swept.step();
        listed.step();
        assert_eq!(swept.last.asleep, listed.last.asleep, "step {step}");
        assert_eq!(swept.state_hash(), listed.state_hash(), "step {step}");
        most_asleep = most_asleep.max(listed.last.asleep);
    }
    assert!(most_asleep > 4000, "at most {most_asleep} asleep");
}

#[test]
fn a_step_without_the_support_pass_forgets_its_carried_impulses() {
    // A column of ten spheres held by the support pass carries its rows'
    // impulses from step to step. One step with the pass off, and they are
    // forgotten (stale by the time it runs again): turned back on, the
    // world steps to the same bits as a new world started from the same
    // bodies with the pass on, which carries nothing.
    use crate::support::{sphere, world};
    use lerpit::sim::WorldConfig;
    let r = 0.04;
    let column: Vec<_> = (0..10)
        .map(|k| sphere([0.5, r + 2.0 * r * k as f64, 0.5], [0.0; 3], r, 1.0))
        .collect();
    let config = WorldConfig {
        support: true,
        ..WorldConfig::default()
    };
    let mut held = world(config.clone(), &column);
    held.run(60);
    assert!(
        held.carried_impulses().len() > 5,
        "the column carries weight"
    );
    held.config.support = false;
    held.step();
    assert!(held.carried_impulses().is_empty());
    held.config.support = true;
    let mut fresh = World::new(config, held.bodies.clone());
    (fresh.time, fresh.steps) = (held.time, held.steps);
    for step in 1..=20 {
        held.step();
        fresh.step();
        assert_eq!(held.state_hash(), fresh.state_hash(), "step {step}");
    }
}
