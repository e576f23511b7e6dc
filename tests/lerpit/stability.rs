//! The stability suite: every failure it names is asserted here, and every
//! remedy is asserted to hold. Small scenes and few steps.

use lerpit::scene::Lesson;
use lerpit::sim::contact::normal_speeds_after;
use lerpit::sim::{Integrator, STANDARD_GRAVITY as G};
use lerpit::study::stability::*;

const DT: f64 = 1.0 / 120.0;

// 1. energy ---------------------------------------------------------------

#[test]
fn every_method_keeps_the_energy_bounded_at_restitution_one() {
    for m in Integrator::ALL {
        let (_, worst) = energy_drift(m, DT, 20.0);
        assert!(
            worst < ENERGY_BOUND,
            "{}: largest change {worst:.3}",
            m.name()
        );
    }
}

#[test]
fn semi_implicit_euler_energy_stays_bounded() {
    let (_, worst_20) = energy_drift(Integrator::SemiImplicitEuler, DT, 20.0);
    let (_, worst_200) = energy_drift(Integrator::SemiImplicitEuler, DT, 200.0);
    assert!(worst_200 < ENERGY_BOUND, "largest change {worst_200:.3}");
    assert!(
        worst_200 <= worst_20 * 1.01,
        "no growth: {worst_20:.4} at 20 s, {worst_200:.4} at 200 s"
    );
}

#[test]
fn explicit_euler_energy_stays_bounded_with_a_wall_that_keeps_its_energy() {
    // In flight explicit Euler gains g^2 dt^2 / 2 of u^2 / 2 + g y per unit
    // mass at every step; the wall keeps the energy the method keeps, so the
    // gain does not accumulate from bounce to bounce.
    let (_, worst_20) = energy_drift(Integrator::ExplicitEuler, DT, 20.0);
    let (_, worst_200) = energy_drift(Integrator::ExplicitEuler, DT, 200.0);
    assert!(worst_200 < ENERGY_BOUND, "largest change {worst_200:.3}");
    assert!(
        worst_200 <= worst_20 * 1.01,
        "no growth: {worst_20:.4} at 20 s, {worst_200:.4} at 200 s"
    );
}

#[test]
fn verlet_and_rk4_keep_the_energy_reflecting_at_the_crossing() {
    for m in [Integrator::VelocityVerlet, Integrator::Rk4] {
        let (_, worst) = energy_drift(m, DT, 20.0);
        assert!(
            worst < 1e-12,
            "{}: largest relative change {worst:e}",
            m.name()
        );
    }
}

#[test]
fn the_continuous_method_keeps_the_energy_at_restitution_one() {
    let (_, worst) = energy_drift(Integrator::Continuous, DT, 20.0);
    assert!(worst < 1e-12, "largest relative change {worst:e}");
}

#[test]
fn a_settled_pile_shows_no_upward_energy_trend_and_small_rises() {
    let o = settled_energy(Integrator::SemiImplicitEuler, SETTLED_ENERGY_START, 100.0).unwrap();
    assert!(o.slope <= 0.0, "{o:?}");
    // The wall stage's put-back of centres the projection pushed into the
    // floor: bounded far below a joule in a 124 J lesson.
    assert!(o.largest_rise <= 1e-4 * o.mean, "{o:?}");
}

#[test]
fn the_benchmark_pile_held_by_the_support_pass_gains_no_energy() {
    // 1,000 spheres at dt = 1/60 s, 10 s after spawning, followed 30 s:
    // the pile's energy wanders up and down over some 20 s as its spheres
    // shift (10 s of it can rise by more than twice the slope's error), so a source
    // of energy shows only over a longer run.
    let o = held_pile_energy(1_000, HELD_PILE_SETTLE, 30.0);
    eprintln!("{}", o.figure());
    assert!(o.no_upward_trend(), "{}", o.figure());
    // The noise the error measures is small: the pile is nearly still,
    // its energy moving by under a thousandth of a percent a step.
    assert!(o.slope_error < 1e-5 * o.mean, "{}", o.figure());
    assert!(o.largest_rise < 1e-4 * o.mean, "{}", o.figure());
}

// 2. rest -----------------------------------------------------------------

const RESTING: f64 = 1.0;

#[test]
fn every_method_rests_near_the_exact_time_with_the_default_rules() {
    assert_eq!(lerpit::sim::WorldConfig::default().rest_steps, RESTING);
    for m in Integrator::ALL {
        let r = rest(m, DT, 0.0, RESTING);
        assert!(r.rests_near(), "{}: {r:?}", m.name());
    }
}

#[test]
fn without_resting_contact_explicit_euler_never_settles() {
    let r = rest(Integrator::ExplicitEuler, DT, 0.0, 0.0);
    assert_eq!(r.rested_at, None, "came to rest");
    assert!(r.leftover > 1e-6, "{:e} J still moving", r.leftover);
}

#[test]
fn the_gravity_lesson_lies_on_its_floor_after_40_s_with_every_method() {
    for m in Integrator::ALL {
        let o = settle(Lesson::Gravity, m, GRAVITY_SETTLE_SECONDS, None).unwrap();
        assert!(
            o.max_height <= SETTLED_HEIGHT && o.max_vertical_speed <= SETTLED_SPEED,
            "{}: {o:?}",
            m.name()
        );
    }
}

#[test]
fn the_collisions_lesson_keeps_under_a_thousandth_of_its_peak_kinetic_energy() {
    for m in [Integrator::SemiImplicitEuler, Integrator::ExplicitEuler] {
        let o = settle(Lesson::Collisions, m, COLLISIONS_SETTLE_SECONDS, None).unwrap();
        assert!(
            o.kinetic_fraction <= SETTLED_KINETIC_FRACTION,
            "{}: {o:?}",
            m.name()
        );
    }
}

#[test]
fn the_continuous_method_rests_at_the_exact_time_without_penetrating() {
    for dt in [1.0 / 30.0, DT] {
        let r = rest(Integrator::Continuous, dt, 0.0, 0.0);
        let t = r.rested_at.expect("rests");
        assert!(
            (t - r.exact).abs() <= dt,
            "dt {dt}: rests at {t}, exact {}",
            r.exact
        );
        assert!(r.penetration <= 0.0, "penetration {:e}", r.penetration);
        assert_eq!(r.leftover, 0.0);
    }
}

#[test]
fn the_rest_threshold_brings_semi_implicit_euler_to_rest_near_the_exact_time() {
    let r = rest(
        Integrator::SemiImplicitEuler,
        DT,
        rest_threshold_for(DT),
        0.0,
    );
    assert!(r.rests_near(), "{r:?}");
}

// 3. tunnelling -----------------------------------------------------------

#[test]
fn discrete_detection_first_misses_just_past_v_dt_equal_r1_plus_r2() {
    // Within r1 + r2 a step, some step ends with the pair overlapping;
    // past it, some starting gap lets the pair through: the scan's first
    // speed past it, 1.01.
    for dt in [1.0 / 30.0, 1.0 / 240.0] {
        let k = first_miss_ratio(Integrator::SemiImplicitEuler, dt, 1, 4.0);
        assert_eq!(k, Some(1.01), "dt {dt}: first miss at v dt / (r1 + r2)");
    }
}

#[test]
fn continuous_detection_never_misses() {
    assert_eq!(
        first_miss_ratio(Integrator::Continuous, 1.0 / 30.0, 1, 4.0),
        None
    );
}

#[test]
fn substeps_move_the_first_miss_to_k_times_the_speed() {
    assert_eq!(
        first_miss_ratio(Integrator::SemiImplicitEuler, 1.0 / 60.0, 2, 4.0),
        Some(2.01),
        "2 sub-steps: first miss at v dt / (r1 + r2)"
    );
}

// 4. piles ----------------------------------------------------------------

#[test]
fn a_thousand_spheres_fall_into_a_pile_without_blowing_up() {
    let p = pile(Integrator::SemiImplicitEuler, 1000, 0.15, 1.0 / 240.0, 1.5).unwrap();
    assert!(p.max_speed < PILE_SPEED_LIMIT, "max speed {}", p.max_speed);
    assert!(
        p.energy_growth <= 0.0,
        "energy rose by {:e}",
        p.energy_growth
    );
    assert!(
        p.kinetic_decay < 0.1,
        "kinetic energy at the end / largest {}",
        p.kinetic_decay
    );
    // One projection pass per step leaves the bottom layers pressed into
    // each other (about 0.7 r at this dt), but no centre sinks past a radius.
    assert!(
        p.residual_overlap < 1.0,
        "residual overlap {} r",
        p.residual_overlap
    );
}

#[test]
fn an_over_packed_box_does_not_blow_up() {
    let p = pile(Integrator::SemiImplicitEuler, 1000, 0.7, 1.0 / 120.0, 0.5).unwrap();
    assert!(p.max_speed < PILE_SPEED_LIMIT, "max speed {}", p.max_speed);
    assert!(
        p.energy_growth <= 0.01,
        "energy rose by {:e}",
        p.energy_growth
    );
}

#[test]
fn sub_steps_with_projection_passes_hold_a_deep_pile_that_one_pass_cannot() {
    let one = deep_pile(2_000, PileRemedy::LESSON, 2.0).unwrap();
    assert!(
        one.mean_overlap > DEEP_PILE_MEAN_OVERLAP,
        "one pass: mean overlap {} r",
        one.mean_overlap
    );
    let remedy = deep_pile(2_000, PileRemedy::passes(4, 4), 2.0).unwrap();
    assert!(
        remedy.mean_overlap < DEEP_PILE_MEAN_OVERLAP
            && remedy.pairs_per_sphere < DEEP_PILE_PAIRS_PER_SPHERE,
        "{remedy:?}"
    );
    // The sub-steps also calm it.
    assert!(
        remedy.rms_speed < one.rms_speed,
        "rms speed {} m/s against {} with one pass",
        remedy.rms_speed,
        one.rms_speed
    );
}

#[test]
fn the_support_pass_holds_a_deep_pile_in_one_pass() {
    let support = deep_pile(2_000, PileRemedy::SUPPORT, 2.0).unwrap();
    eprintln!("{support:?}");
    assert!(
        support.mean_overlap < DEEP_PILE_MEAN_OVERLAP
            && support.pairs_per_sphere < DEEP_PILE_PAIRS_PER_SPHERE,
        "{support:?}"
    );
    // At rest: its spheres keep less than the speed gravity adds in one
    // of its steps of 1/240 s.
    assert!(
        support.rms_speed < G / 240.0,
        "rms speed {} m/s",
        support.rms_speed
    );
}

// 5. critical dt ----------------------------------------------------------

#[test]
fn explicit_euler_needs_the_smallest_step_and_continuous_the_largest() {
    let ee = critical_dt(Lesson::Gravity, Integrator::ExplicitEuler, 0.5).expect("holds somewhere");
    let sie = critical_dt(Lesson::Gravity, Integrator::SemiImplicitEuler, 0.5).expect("holds");
    let cont = critical_dt(Lesson::Gravity, Integrator::Continuous, 0.5).expect("holds");
    assert!(
        ee < sie,
        "explicit Euler up to {ee}, semi-implicit Euler up to {sie}"
    );
    assert_eq!(
        cont,
        critical_dt_grid()[0],
        "continuous holds at every dt tried"
    );
}

// 6. extremes -------------------------------------------------------------

#[test]
fn restitution_zero_stops_the_ball_at_its_first_impact() {
    let first_impact = time_to_rest(0.45, 0.0);
    for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
        let r = drop_ball(m, DT, 0.0, 0.0, 0.0);
        let t = r.rested_at.expect("rests");
        assert!((t - first_impact).abs() <= DT, "{}: rests at {t}", m.name());
    }
}

#[test]
fn restitution_zero_between_spheres_leaves_them_moving_together() {
    for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
        let (v0, v1, dp) = head_on(m, DT, 1.0, 1.0, 1.0, 0.0);
        assert!(
            (v0 - 0.5).abs() <= 1e-12 && (v1 - 0.5).abs() <= 1e-12,
            "{}: {v0} {v1}",
            m.name()
        );
        assert!(dp <= 1e-12);
    }
}

#[test]
fn a_mass_ratio_of_a_thousand_keeps_momentum_and_the_lesson_speeds() {
    for (heavy, light) in [(1000.0, 1.0), (1.0, 1000.0)] {
        let (e0, e1) = normal_speeds_after(heavy, light, 1.0, 0.0, 1.0);
        for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
            let (v0, v1, dp) = head_on(m, DT, heavy, light, 1.0, 1.0);
            assert!(dp <= 1e-12, "{}: momentum error {dp:e}", m.name());
            assert!(
                (v0 - e0).abs() <= 1e-12 && (v1 - e1).abs() <= 1e-12,
                "{}: {v0} {v1}",
                m.name()
            );
        }
    }
}

#[test]
fn explicit_euler_fails_the_lessons_with_gravity_at_some_dt() {
    for lesson in [Lesson::Gravity, Lesson::Collisions] {
        let c = critical_dt(lesson, Integrator::ExplicitEuler, 0.5);
        assert!(
            c.is_some_and(|dt| dt < critical_dt_grid()[0]),
            "explicit Euler on {}: holds up to {c:?}",
            lesson.name()
        );
    }
}

#[test]
fn elastic_spheres_at_the_fastest_speed_and_strongest_gravity_keep_their_energy() {
    use lerpit::scene::rules::{MAX_GRAVITY, MAX_SPEED};
    // The issue's case with four spheres: millions of impacts asked for in
    // every step, so every step reaches the cap and finishes without them.
    let steps = 20_000;
    let r = elastic_spheres(
        Integrator::Continuous,
        4,
        MAX_SPEED,
        MAX_GRAVITY,
        1.0,
        steps,
    )
    .unwrap();
    assert_eq!(r.capped_steps, steps, "the case must exercise the cap");
    assert!(
        r.energy_drift <= ELASTIC_ENERGY_BOUND,
        "energy drift {:e} over {steps} capped steps",
        r.energy_drift
    );
}

#[test]
fn elastic_spheres_keep_their_energy_whether_or_not_their_steps_reach_the_cap() {
    use lerpit::scene::rules::{MAX_GRAVITY, MAX_SPEED};
    // Every corner of the accepted range, and between. A capped step costs
    // about a thousand impacts, so these runs are short; the 20,000 steps
    // are the extreme corner's, above. Past the cap the energy is kept
    // (`continuous.rs`): the walls in the elastic closed form, the pairs by
    // the contact stage's projection, which keeps each pair's centre of
    // mass, and V1/V2 at e = 1, and a centre pushed past a wall returns
    // with the speed that pays for the height. The one exception, a sphere
    // too slow to climb back onto a wall (`continuous::return_to_walls`),
    // meets none of these runs. Half of them reach the cap (12 of the 24
    // here, in every step): both kinds must be among them.
    let mut capped = 0;
    let mut runs = 0;
    for g in [0.0, G, 1e3, MAX_GRAVITY] {
        for speed in [1.0, 1e3, MAX_SPEED] {
            for dt in [DT, 1.0] {
                let r = elastic_spheres(Integrator::Continuous, 4, speed, g, dt, 300).unwrap();
                assert!(
                    r.energy_drift <= ELASTIC_ENERGY_BOUND,
                    "g {g:e} m/s^2, speed {speed:e} m/s, dt {dt} s: energy drift {:e} \
                     ({} steps at the impact cap)",
                    r.energy_drift,
                    r.capped_steps
                );
                capped += usize::from(r.capped_steps > 0);
                runs += 1;
            }
        }
    }
    assert!(
        capped > 0 && capped < runs,
        "{capped} of {runs} runs capped"
    );
}

#[test]
fn the_discrete_methods_cannot_keep_the_energy_at_the_extremes() {
    use lerpit::scene::rules::{MAX_GRAVITY, MAX_SPEED};
    let r = elastic_spheres(
        Integrator::SemiImplicitEuler,
        4,
        MAX_SPEED,
        MAX_GRAVITY,
        1.0,
        200,
    )
    .unwrap();
    assert!(r.energy_drift > 1e-3, "energy drift {:e}", r.energy_drift);
}
