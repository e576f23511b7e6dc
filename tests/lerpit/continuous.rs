//! The continuous method, sub-steps and the rest threshold.

use crate::support::{BODY, sphere, world};
use lerpit::scene::{Lesson, parse_scene};
use lerpit::sim::continuous::{first_entry, first_entry_poly};
use lerpit::sim::{Integrator, World};
use lerpit::study::conservation;

#[test]
fn first_entry_finds_the_closing_root() {
    // (s - 1)(s - 3) = s^2 - 4 s + 3: closes at 1.
    assert_eq!(first_entry(3.0, -4.0, 1.0, 10.0), Some(1.0));
    assert_eq!(first_entry(3.0, -4.0, 1.0, 0.5), None, "beyond the horizon");
    assert_eq!(
        first_entry(-1.0, -1.0, 0.0, 1.0),
        Some(0.0),
        "closed and closing"
    );
    assert_eq!(first_entry(-1.0, 1.0, 0.0, 1.0), None, "closed and opening");
    assert_eq!(first_entry(1.0, 0.0, 1.0, 1.0), None, "never reaches zero");
    // A ball leaving the floor at 2 m/s under g = 9.81 comes back at 4/9.81.
    let back = first_entry(0.0, 2.0, -9.81 / 2.0, 1.0).unwrap();
    assert!((back - 4.0 / 9.81).abs() < 1e-15, "{back}");
}

#[test]
fn first_entry_poly_agrees_with_a_factored_quartic() {
    // (s - 0.5)(s - 1)(s - 2)(s - 4) > 0 at 0, first closes at 0.5.
    let c = [4.0, -15.0, 17.5, -7.5, 1.0];
    let s = first_entry_poly(&c, 5.0).unwrap();
    assert!((s - 0.5).abs() < 1e-15, "{s}");
    // The same quadratic as above, through the general path.
    let s = first_entry_poly(&[3.0, -4.0, 1.0], 10.0).unwrap();
    assert!((s - 1.0).abs() < 1e-15, "{s}");
}

#[test]
fn elastic_collisions_keep_momentum_and_energy_to_rounding() {
    let d = conservation::drift(Integrator::Continuous, 1.0 / 240.0, Some(1000), 0.0).unwrap();
    assert!(d.collisions >= 1000, "{} collisions", d.collisions);
    assert!(
        d.momentum_error <= 1e-12,
        "momentum error {:e}",
        d.momentum_error
    );
    assert!(d.energy_drift <= 1e-12, "energy drift {:e}", d.energy_drift);
}

#[test]
fn the_continuous_step_is_deterministic() {
    let run = || {
        let mut w = Lesson::Collisions.scene().build().unwrap();
        w.config.integrator = Integrator::Continuous;
        w.run(50);
        w.state_hash()
    };
    assert_eq!(run(), run());
}

#[test]
fn k_substeps_equal_k_steps_of_dt_over_k() {
    for method in Integrator::ALL {
        let mut scene = Lesson::Collisions.scene();
        scene.world.integrator = method;
        let mut a: World = scene.build().unwrap();
        let mut b = a.clone();
        a.config.substeps = 3;
        b.config.dt = a.config.dt / 3.0;
        a.run(20);
        b.run(60);
        assert_eq!(
            a.bodies,
            b.bodies,
            "{}: 20 steps of 3 sub-steps",
            method.name()
        );
    }
}

#[test]
fn scene_files_take_substeps_and_rest_threshold() {
    let s = parse_scene(
        &format!(
            "[world]\nsubsteps = 4\nrest_threshold = 0.2\nintegrator = \"continuous\"\n{BODY}"
        ),
        "test",
        "test",
    )
    .unwrap();
    assert_eq!(s.world.substeps, 4);
    assert_eq!(s.world.rest_threshold, 0.2);
    assert_eq!(s.world.integrator, Integrator::Continuous);
}

#[test]
fn scene_files_refuse_bad_substeps_and_thresholds_with_the_line() {
    let e = parse_scene(&format!("[world]\nsubsteps = 0\n{BODY}"), "f", "f").unwrap_err();
    assert_eq!(e.field.as_deref(), Some("world.substeps"));
    assert_eq!(e.at.map(|a| a.0), Some(2), "{e}");
    let e = parse_scene(
        &format!("[world]\n\nrest_threshold = -1.0\n{BODY}"),
        "f",
        "f",
    )
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("world.rest_threshold"));
    assert_eq!(e.at.map(|a| a.0), Some(3), "{e}");
}

#[test]
fn the_elastic_closed_form_agrees_with_the_reference_chain_of_parabolas() {
    use lerpit::sim::continuous::elastic_axis;
    use lerpit::sim::reference::gravity::AxisMotion;
    let (lo, hi) = (0.05, 0.95);
    // (p, u, a, s): no gravity; bouncing on the floor only; reaching the
    // ceiling; gravity towards the ceiling; and the accepted extremes,
    // thousands of impacts in each.
    let cases = [
        (0.3, 7.3, 0.0, 1000.3),
        (0.2, 1.0, -9.81, 100.0),
        (0.5, -5.0, -9.81, 100.0),
        (0.7, -12.0, 50.0, 10.0),
        (0.9, 1e6, -1e6, 0.01),
    ];
    for (p, u, a, s) in cases {
        let exact = AxisMotion {
            p0: p,
            u0: u,
            a,
            lo,
            hi,
            c: 1.0,
        };
        let (x, v) = exact.at(s);
        let e = elastic_axis(p, u, a, lo, hi, s);
        let scale = u.abs().max((2.0 * a.abs()).sqrt());
        assert!(
            (e.p - x).abs() <= 1e-9 && (e.u - v).abs() <= 1e-9 * scale,
            "p {p}, u {u}, a {a}, after {s} s: ({}, {}) against the reference ({x}, {v})",
            e.p,
            e.u
        );
        let impacts = exact.impacts(s, usize::MAX).len();
        assert!(
            e.impacts.abs_diff(impacts) <= 1,
            "p {p}, u {u}, a {a}: {} impacts against the reference's {impacts}",
            e.impacts
        );
        // The axis energy u^2 / 2 - a p, kept through every impact.
        let energy = |p: f64, u: f64| 0.5 * u * u - a * p;
        let before = energy(p, u);
        assert!(
            (energy(e.p, e.u) - before).abs() <= 1e-13 * before.abs().max(1.0),
            "p {p}, u {u}, a {a}: axis energy {before} became {}",
            energy(e.p, e.u)
        );
    }
}

fn one_sphere(position: [f64; 3], velocity: [f64; 3]) -> World {
    use lerpit::sim::WorldConfig;
    let config = WorldConfig {
        integrator: Integrator::Continuous,
        wall_restitution: 1.0,
        ..WorldConfig::default()
    };
    world(config, &[sphere(position, velocity, 0.05, 2.0)])
}

#[test]
fn spheres_that_start_overlapping_are_pushed_apart_by_the_lessons_rule_then_fly() {
    use lerpit::sim::{Vec3, WallMode, WorldConfig};
    // Overlapping by 0.1 m and approaching, masses 1 and 3, e = 0.5, no
    // gravity: the lesson's split moves them 0.075 and 0.025 m apart, V1 =
    // (1 - 3 - 3 (2) 0.5) / 4 = -1.25 and V2 = (1 - 3 + (2) 0.5) / 4 =
    // -0.25 m/s, then they fly 0.01 s. No time of impact meets a pair
    // already overlapping: without the push they would pass through.
    let config = WorldConfig {
        integrator: Integrator::Continuous,
        gravity: Vec3::ZERO,
        wall_mode: WallMode::Flip,
        pair_restitution: 0.5,
        dt: 0.01,
        ..WorldConfig::default()
    };
    let mut w = world(
        config,
        &[
            sphere([0.45, 0.5, 0.5], [1.0, 0.0, 0.0], 0.1, 1.0),
            sphere([0.55, 0.5, 0.5], [-1.0, 0.0, 0.0], 0.1, 3.0),
        ],
    );
    w.step();
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-15;
    let (p, v) = (&w.bodies.position, &w.bodies.velocity);
    assert!(near(v[0].x, -1.25) && near(v[1].x, -0.25), "{v:?}");
    assert!(near(p[0].x, 0.375 - 0.0125), "{p:?}");
    assert!(near(p[1].x, 0.575 - 0.0025), "{p:?}");
    assert!((w.last.max_overlap - 0.1).abs() <= 1e-15, "{:?}", w.last);
    assert_eq!(w.last.contacts, 1);
    // Apart now, and separating: the next step only flies.
    w.step();
    assert_eq!((w.last.contacts, w.last.max_overlap), (0, 0.0));
    assert!(near(w.bodies.position[0].x, 0.375 - 0.025));
}

#[test]
fn a_chain_of_overlapping_spheres_is_pushed_apart_pass_after_pass() {
    use lerpit::sim::{Vec3, WallMode, WorldConfig};
    // Three at rest, each pair 0.1 m into the other: one pass pushes the
    // middle pair apart into the outer ones; the passes go on until no pair
    // overlaps by 1% of its reach, and then nothing meets them again.
    let config = WorldConfig {
        integrator: Integrator::Continuous,
        gravity: Vec3::ZERO,
        wall_mode: WallMode::Flip,
        dt: 0.01,
        ..WorldConfig::default()
    };
    let at = |x: f64| sphere([x, 0.5, 0.5], [0.0, 0.0, 0.0], 0.1, 1.0);
    let mut w = world(config, &[at(0.4), at(0.5), at(0.6)]);
    w.step();
    let p = &w.bodies.position;
    for (a, b) in [(0, 1), (1, 2)] {
        let gap = p[b].x - p[a].x;
        assert!(gap >= 0.2 * 0.99, "{a} and {b} {gap} apart");
    }
    assert!(!w.last.projection_unconverged);
    assert!((w.bodies.position[0].x + w.bodies.position[2].x - 1.0).abs() < 1e-12);
}

#[test]
fn a_centre_pushed_past_a_wall_returns_with_the_speed_that_pays_for_the_height() {
    use lerpit::sim::StepStats;
    use lerpit::sim::continuous::return_to_walls;
    // Pushed 1 cm into the floor moving down, and 1 cm past the ceiling
    // moving up: back on the wall, moving away, with the total energy kept.
    for (y, vy) in [(0.04, -2.0), (0.96, 2.0)] {
        let mut w = one_sphere([0.5, y, 0.5], [3.0, vy, -1.0]);
        let before = w.diagnostics().total_energy;
        let mut stats = StepStats::default();
        return_to_walls(&mut w.bodies, &w.config, &mut stats);
        let (p, v) = (w.bodies.position[0], w.bodies.velocity[0]);
        let wall = if y < 0.5 { 0.05 } else { 0.95 };
        assert_eq!(p.y, wall, "on the wall");
        assert!(v.y * vy < 0.0, "moving away from the wall: {v}");
        assert_eq!(stats.wall_impacts, 1);
        let after = w.diagnostics().total_energy;
        assert!(
            (after - before).abs() <= 1e-14 * before,
            "y {y}: energy {before} became {after}"
        );
    }
}

#[test]
fn a_centre_too_slow_to_climb_back_rests_on_the_wall() {
    use lerpit::sim::StepStats;
    use lerpit::sim::continuous::return_to_walls;
    // 4 cm down at 0.1 m/s: the climb costs g 0.04 = 0.39 J/kg, the speed
    // pays 0.005 J/kg.
    let mut w = one_sphere([0.5, 0.01, 0.5], [0.0, -0.1, 0.0]);
    let before = w.diagnostics().total_energy;
    return_to_walls(&mut w.bodies, &w.config, &mut StepStats::default());
    assert_eq!(w.bodies.position[0].y, 0.05);
    assert_eq!(w.bodies.velocity[0].length(), 0.0);
    let gained = w.diagnostics().total_energy - before;
    let most = 2.0 * 9.81 * 0.04;
    assert!(
        gained > 0.0 && gained <= most,
        "gained {gained} J, at most m g depth = {most} J"
    );
}

#[test]
fn the_200_sphere_pile_never_reaches_the_impact_cap_and_never_gains_energy() {
    use lerpit::study::stability::{CONTINUOUS_PILE, PILE_SPEED_LIMIT, pile};
    let p = pile(
        Integrator::Continuous,
        CONTINUOUS_PILE,
        0.15,
        1.0 / 240.0,
        2.0,
    )
    .unwrap();
    assert_eq!(p.capped_steps, 0, "{p:?}");
    // The total energy at every step end, against its start (restitution
    // 0.5: the impacts and the resting pairs only take energy).
    assert!(p.energy_growth <= 0.0, "{p:?}");
    assert!(p.max_speed < PILE_SPEED_LIMIT, "{p:?}");
}

#[test]
fn the_collisions_lesson_settles_for_60_s_without_reaching_the_impact_cap() {
    use lerpit::study::stability::{COLLISIONS_SETTLE_SECONDS, SETTLED_KINETIC_FRACTION};
    let mut w = Lesson::Collisions.scene().build().unwrap();
    w.config.integrator = Integrator::Continuous;
    let mut peak = w.diagnostics().kinetic_energy;
    for n in 0..(COLLISIONS_SETTLE_SECONDS / w.config.dt).round() as u64 {
        w.step();
        assert!(!w.last.event_cap_reached, "step {n} reached the cap");
        peak = peak.max(w.diagnostics().kinetic_energy);
    }
    let fraction = w.diagnostics().kinetic_energy / peak;
    assert!(
        fraction <= SETTLED_KINETIC_FRACTION,
        "kinetic energy end/peak {fraction:e}"
    );
}

#[test]
fn a_resting_pile_steps_to_the_same_bits_from_a_copy_of_its_state() {
    use lerpit::study::stability::pile_world;
    // The copy has none of the world's working buffers (its neighbour
    // lists among them): what it does next depends on the state alone.
    let mut w = pile_world(Integrator::Continuous, 200, 0.15, 1.0 / 240.0).unwrap();
    w.run(240);
    let mut copy = w.copy_state(None);
    w.run(30);
    copy.run(30);
    assert_eq!(w.state_hash(), copy.state_hash());
}

#[test]
fn a_dilute_fast_scene_tests_a_few_pairs_a_sphere_not_every_pair() {
    // 5,000 spheres at up to 1 m/s fly up to 2.6 of their radii a step:
    // most fly farther than lists one radius wide cover. The lists then
    // widen to the farthest flight instead of testing those spheres
    // against every other (12.5 million pair tests a step).
    let n = 5000;
    let source = format!(
        "[world]\nintegrator = \"continuous\"\ndt = 0.016666666666666666\n\
         [[spawn]]\ncount = {n}\nradius = [0.0064, 0.0064]\nspeed = [0, 1]\n"
    );
    let mut w = parse_scene(&source, "fast.toml", "fast")
        .unwrap()
        .build()
        .unwrap();
    for _ in 0..5 {
        w.step();
        let per_sphere = w.last.pair_tests as f64 / n as f64;
        assert!(per_sphere < 100.0, "{per_sphere} pair tests a sphere");
    }
    assert!(w.last.contacts > 0, "the spheres meet");
}

#[test]
fn a_slow_contact_in_mid_air_keeps_the_pairs_momentum() {
    use lerpit::sim::{Vec3, WorldConfig};
    // A 10 kg sphere settles slowly onto a 1 g one, both falling, neither
    // on anything: resting contact stops their approach, and gravity is
    // all that changes their momentum. The lower sphere held the upper
    // one up as if it stood on the floor: the 1 g sphere stopped the 10 kg
    // one, and the pair lost 0.6 kg m/s.
    for e in [0.0, 0.5, 1.0] {
        let config = WorldConfig {
            integrator: Integrator::Continuous,
            dt: 1.0 / 120.0,
            pair_restitution: e,
            ..WorldConfig::default()
        };
        let pair = [
            sphere([0.5, 0.4, 0.5], [0.0; 3], 0.1, 0.001),
            sphere([0.5, 0.55, 0.5], [0.0, -0.06, 0.0], 0.05, 10.0),
        ];
        let mut w = world(config, &pair);
        let before = w.diagnostics().momentum;
        w.step();
        let gained = w.diagnostics().momentum - before;
        let expected = Vec3::new(0.0, -9.81 * 10.001 / 120.0, 0.0);
        assert!(
            (gained - expected).length() < 1e-12,
            "e = {e}: momentum changed by {gained}, gravity gives {expected}"
        );
    }
}

#[test]
fn an_oblique_impact_with_e_below_one_acts_along_the_line_of_centres_at_contact() {
    use lerpit::sim::{Vec3, WorldConfig};
    // Spheres of 1 kg and 3 kg, no gravity, whose paths meet off centre
    // three tenths of the way into the step, far from the walls. The
    // impulse lies along the line of centres at that instant, not along
    // the relative velocity: each sphere keeps the part of its velocity
    // across it, the normal approach comes out e times as fast, momentum is
    // kept, and the kinetic energy lost is (1 - e^2) mu v_n^2 / 2, mu the
    // reduced mass. Then each flies straight from where it met the other.
    let (m1, m2, r1, r2, e, dt) = (1.0, 3.0, 0.05, 0.08, 0.6, 1.0 / 120.0);
    let (u1, u2) = (Vec3::new(1.2, 0.3, -0.1), Vec3::new(-0.8, 0.1, 0.4));
    let n = Vec3::new(1.0, 0.6, -0.3).normalize();
    let t = 0.3 * dt;
    let at1 = Vec3::new(0.45, 0.45, 0.5);
    let at2 = at1 + (r1 + r2) * n;
    let config = WorldConfig {
        integrator: Integrator::Continuous,
        gravity: Vec3::ZERO,
        dt,
        pair_restitution: e,
        ..WorldConfig::default()
    };
    let pair = [
        sphere(at1 - u1 * t, u1, r1, m1),
        sphere(at2 - u2 * t, u2, r2, m2),
    ];
    let mut w = world(config, &pair);
    let energy_before = w.diagnostics().kinetic_energy;
    w.step();
    assert_eq!((w.last.contacts, w.last.wall_impacts), (1, 0), "one impact");
    let (v1, v2) = (w.bodies.velocity[0], w.bodies.velocity[1]);
    let across = |v: Vec3| v - v.dot(n) * n;
    assert!((across(v1) - across(u1)).length() < 1e-14, "{v1}");
    assert!((across(v2) - across(u2)).length() < 1e-14, "{v2}");
    let approach = (u1 - u2).dot(n);
    assert!(approach > 1.0, "off centre but closing: {approach}");
    let separation = (v2 - v1).dot(n);
    assert!((separation - e * approach).abs() < 1e-14, "{separation}");
    let momentum = (m1 * v1 + m2 * v2) - (m1 * u1 + m2 * u2);
    assert!(momentum.length() < 1e-14, "momentum changed by {momentum}");
    let mu = m1 * m2 / (m1 + m2);
    let lost = energy_before - w.diagnostics().kinetic_energy;
    let expected = 0.5 * (1.0 - e * e) * mu * approach * approach;
    assert!(
        (lost - expected).abs() < 1e-13 * expected,
        "lost {lost} J, the closed form {expected} J"
    );
    for (k, (at, v)) in [(at1, v1), (at2, v2)].into_iter().enumerate() {
        let end = at + v * (dt - t);
        assert!((w.bodies.position[k] - end).length() < 1e-14, "sphere {k}");
    }
}

#[test]
fn elastic_spheres_side_by_side_keep_a_slow_impact() {
    use lerpit::sim::{Vec3, WorldConfig};
    // Touching spheres, e = c_r = 1, under gravity, the first moving at
    // 0.1 m/s along x, far slower than a step of gravity: resting contact
    // counts gravity along the normal only, so the blow passes down the
    // row and the last sphere leaves with all of it (a Newton's cradle),
    // on the floor and in mid-air alike. Held as resting contact, the
    // row had shared the speed, 0.033 m/s each, losing two thirds of the
    // energy.
    let r = 0.05;
    for y in [r, 0.5] {
        let config = WorldConfig {
            integrator: Integrator::Continuous,
            dt: 1.0 / 120.0,
            pair_restitution: 1.0,
            wall_restitution: 1.0,
            ..WorldConfig::default()
        };
        let row: Vec<_> = (0..3)
            .map(|k| {
                let x = 0.3 + 2.0 * r * k as f64;
                sphere(
                    [x, y, 0.5],
                    [if k == 0 { 0.1 } else { 0.0 }, 0.0, 0.0],
                    r,
                    1.0,
                )
            })
            .collect();
        let mut w = world(config, &row);
        w.step();
        let vx: Vec<f64> = w.bodies.velocity.iter().map(|v: &Vec3| v.x).collect();
        assert_eq!(vx, [0.0, 0.0, 0.1], "at height {y}");
    }
}

#[test]
fn a_column_at_rest_on_the_floor_stays_at_rest() {
    use lerpit::sim::{Vec3, WorldConfig};
    // Three spheres stacked on the floor, touching, under gravity, with
    // resting contact: nothing should move. Split by mass, half of each
    // resting pair's overlap went down the column into the floor, which
    // gave it back: the column stayed sunk 2.5 and 4.2 mm into itself,
    // with speeds it never moved by. Perfectly elastic spheres held
    // nothing: every step asked for endless impacts, reached the cap, and
    // the column gained 8.5% of its energy in 5 s.
    let cases = [[1.0, 1.0, 1.0], [5.0, 1.0, 0.2]]
        .into_iter()
        .flat_map(|masses| [(masses, 0.5), (masses, 1.0)]);
    for (masses, e) in cases {
        let r = 0.0625;
        let config = WorldConfig {
            integrator: Integrator::Continuous,
            dt: 1.0 / 120.0,
            pair_restitution: e,
            wall_restitution: e,
            ..WorldConfig::default()
        };
        let column: Vec<_> = (0..3)
            .map(|k| sphere([0.5, r * (1 + 2 * k) as f64, 0.5], [0.0; 3], r, masses[k]))
            .collect();
        let mut w = world(config, &column);
        let start = w.bodies.position.clone();
        for _ in 0..600 {
            w.step();
            assert!(!w.last.event_cap_reached, "{masses:?}, e = {e}: capped");
        }
        for (k, (p, p0)) in w.bodies.position.iter().zip(&start).enumerate() {
            assert!(
                (*p - *p0).length() <= 1e-12,
                "{masses:?}, e = {e}: sphere {k} at {p}, from {p0}"
            );
        }
        assert!(
            w.bodies.velocity.iter().all(|&v| v == Vec3::ZERO),
            "{masses:?}, e = {e}: {:?}",
            w.bodies.velocity
        );
    }
}

#[test]
fn a_capped_step_below_c_r_one_keeps_the_energy_of_its_last_walked_impact_never_more() {
    use lerpit::sim::reference::gravity::AxisMotion;
    use lerpit::sim::{Vec3, WallMode, WorldConfig};
    // Two spheres far apart, each bouncing on the floor only, straight up
    // and down, under the strongest gravity a scene may ask for, with walls
    // at c_r = 0.9999. A flight lasts 2 w / g (2 microseconds at w = 1
    // m/s), and the bounces outlast the step (2 w / (g (1 - c_r)) = 20 ms
    // in all at 1 m/s, the step 8.3 ms): the step asks for thousands of
    // impacts, past its cap of 1000 + 8 n = 1016. Past the cap it walks a
    // share of impacts one by one, each taking (1 - c_r^2) of the kinetic
    // energy, then finishes in the elastic closed form, which keeps the
    // energy: a sphere ends with the energy the exact motion has just after
    // its last walked impact, n of them, m (w c_r^n)^2 / 2 + m g r. That is
    // less than it had, and more than the exact motion keeps to the end
    // of the step: the impacts past the cap take nothing. With walls only
    // each coordinate walks the cap itself; with pair collisions the queue
    // walks the step's first 1016 impacts, both spheres' in time order,
    // then each sphere a share of the cap, 1016 / 2.
    let (g, c, r, dt) = (1e6, 0.9999, 0.05, 1.0 / 120.0);
    let (lo, hi) = (r, 1.0 - r);
    let (speeds, masses) = ([1.0, 1.37], [1.0, 2.0]);
    let cap = 1000 + 8 * 2;
    let exact = |w: f64| AxisMotion {
        p0: lo,
        u0: w,
        a: -g,
        lo,
        hi,
        c,
    };
    let times: Vec<Vec<f64>> = speeds
        .iter()
        .map(|&w| {
            exact(w)
                .impacts(dt, 2 * cap)
                .iter()
                .map(|i| i.time)
                .collect()
        })
        .collect();
    assert!(times.iter().all(|t| t.len() == 2 * cap), "past the cap");
    let mut merged: Vec<f64> = times.concat();
    merged.sort_by(f64::total_cmp);
    let queue_walked = |k: usize| times[k].iter().filter(|&&t| t <= merged[cap - 1]).count();
    for pair_collisions in [false, true] {
        let config = WorldConfig {
            integrator: Integrator::Continuous,
            gravity: Vec3::new(0.0, -g, 0.0),
            dt,
            wall_mode: WallMode::Restitution,
            wall_restitution: c,
            pair_collisions,
            ..WorldConfig::default()
        };
        let pair = [
            sphere([0.25, lo, 0.5], [0.0, speeds[0], 0.0], r, masses[0]),
            sphere([0.75, lo, 0.5], [0.0, speeds[1], 0.0], r, masses[1]),
        ];
        let mut w = world(config, &pair);
        w.step();
        assert!(w.last.event_cap_reached, "pairs {pair_collisions}: capped");
        for k in 0..2 {
            let (m, speed) = (masses[k], speeds[k]);
            let energy = |y: f64, v: f64| m * (0.5 * v * v + g * y);
            let walked = if pair_collisions {
                queue_walked(k) + cap.div_ceil(2)
            } else {
                cap
            };
            let kept = energy(lo, speed * c.powi(walked as i32));
            let (p, v) = (w.bodies.position[k], w.bodies.velocity[k]);
            assert_eq!((p.x, p.z, v.x, v.z), (pair[k].position.x, 0.5, 0.0, 0.0));
            let after = energy(p.y, v.y);
            let before = energy(lo, speed);
            let (y, u) = exact(speed).at(dt);
            let to_the_end = energy(y, u);
            assert!(
                (after - kept).abs() <= 1e-9 * kept,
                "pairs {pair_collisions}, sphere {k}: {after} J, {walked} impacts leave {kept} J"
            );
            assert!(
                to_the_end < after && after < before,
                "pairs {pair_collisions}, sphere {k}: {after} J, from {before} J; \
                 the exact motion keeps {to_the_end} J"
            );
        }
    }
}

#[test]
fn a_sphere_in_flight_meets_one_held_on_the_floor_when_and_where_the_closed_form_says() {
    use lerpit::sim::contact::normal_speeds_after;
    use lerpit::sim::{Vec3, WorldConfig};
    // Sphere 0 (r 0.1 m, 2 kg) lies on the floor: the floor holds it, so
    // gravity does not move it. Sphere 1 (r 0.05 m, 1 kg) flies under
    // gravity and touches its side, level with its centre, three tenths of
    // the way into the step, moving at V then. Their relative motion is a
    // parabola, d(s) = d0 + w s - g s^2 / 2, and |d(s)| = r0 + r1 a quartic;
    // built backwards from the contact, its first root is 0.3 dt. Were the
    // held sphere taken to fall too, the motion would be a straight line and
    // they would meet elsewhere, later. In mid-air (sphere 0 falling at U),
    // both feel gravity: d(s) = d0 + w s, |d0 + w s| = r0 + r1, the same
    // 0.3 dt. At the contact the impulse lies along the line of centres, n
    // = x here: the lesson's V1/V2 along x, the rest of each velocity kept;
    // then each flies from where they met, the held sphere sliding on the
    // floor.
    let (m0, m1, r0, r1, e, dt) = (2.0, 1.0, 0.1, 0.05, 0.6, 1.0 / 120.0);
    let g = Vec3::new(0.0, -9.81, 0.0);
    let t = 0.3 * dt;
    let n = Vec3::X;
    let v = Vec3::new(1.2, -1.0, 0.3);
    let config = WorldConfig {
        integrator: Integrator::Continuous,
        dt,
        pair_restitution: e,
        ..WorldConfig::default()
    };
    // Where a body under acceleration `a` starts to be at `at` moving at
    // `vel` after t.
    let start = |at: Vec3, vel: Vec3, a: Vec3| (at - vel * t + a * (0.5 * t * t), vel - a * t);
    for (q, u, a0) in [
        (Vec3::new(0.5, r0, 0.5), Vec3::ZERO, Vec3::ZERO),
        (Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.0, -0.4, 0.0), g),
    ] {
        let p = q - n * (r0 + r1);
        let (q0, u0) = start(q, u, a0);
        let (p0, v0) = start(p, v, g);
        let pair = [sphere(q0, u0, r0, m0), sphere(p0, v0, r1, m1)];
        let mut w = world(config.clone(), &pair);
        w.step();
        assert_eq!(w.last.contacts, 1, "at {q}");
        let normal = w.contacts()[0].contact_normal;
        assert!((normal + n).length() < 1e-12, "at {q}: met along {normal}");
        let (u_n, v_n) = normal_speeds_after(m0, m1, u.x, v.x, e);
        let (u_after, v_after) = (Vec3::new(u_n, u.y, u.z), Vec3::new(v_n, v.y, v.z));
        let left = dt - t;
        let ends = [
            (
                q + u_after * left + a0 * (0.5 * left * left),
                u_after + a0 * left,
            ),
            (
                p + v_after * left + g * (0.5 * left * left),
                v_after + g * left,
            ),
        ];
        for (k, (at, vel)) in ends.into_iter().enumerate() {
            let (pk, vk) = (w.bodies.position[k], w.bodies.velocity[k]);
            assert!(
                (pk - at).length() < 1e-13 && (vk - vel).length() < 1e-12,
                "at {q}: sphere {k} at {pk} moving at {vk}, the closed form {at}, {vel}"
            );
        }
    }
}
