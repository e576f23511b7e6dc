//! Deep piles: further projection passes keep the same bits for any number
//! of threads and either broad phase, and a step whose passes run out says
//! so.

use crate::support::run_on_threads;
use lerpit::sim::{BroadPhase, World};
use lerpit::study::stability::pile_world;

/// A pile of `n` spheres, 4 sub-steps of 4 passes, after `steps` steps on
/// `threads` threads.
fn run(n: usize, steps: u64, broad_phase: BroadPhase, threads: usize) -> World {
    let mut w = pile_world(
        lerpit::sim::Integrator::SemiImplicitEuler,
        n,
        0.3,
        1.0 / 240.0,
    )
    .expect("the pile spawns");
    w.config.broad_phase = broad_phase;
    w.config.substeps = 4;
    w.config.projection_passes = 4;
    run_on_threads(&mut w, steps, threads);
    w
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
