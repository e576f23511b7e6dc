//! The exact references against closed forms.

use crate::support::{sphere, world};
use lerpit::scene::Lesson;
use lerpit::sim::reference::collisions::{predictability_horizon, rms_distance};
use lerpit::sim::reference::gravity::AxisMotion;
use lerpit::sim::reference::pingpong::triangle_wave;
use lerpit::sim::reference::{Reference, exact_positions};
use lerpit::sim::{Integrator, STANDARD_GRAVITY as G, World};
use proptest::prelude::*;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

#[test]
fn triangle_wave_reaches_each_wall_and_returns_after_one_period() {
    let (lo, hi, p0, u0) = (0.05, 0.95, 0.5, 1.0);
    let eps = 1e-9;
    let (p, u) = triangle_wave(p0, u0, lo, hi, 0.45 - eps);
    assert!(
        close(p, hi - eps, 1e-15) && u == 1.0,
        "rising to the ceiling: {p} {u}"
    );
    let (p, u) = triangle_wave(p0, u0, lo, hi, 0.45 + eps);
    assert!(
        close(p, hi - eps, 1e-15) && u == -1.0,
        "falling from the ceiling: {p} {u}"
    );
    let (p, u) = triangle_wave(p0, u0, lo, hi, 0.45 + 0.9 + eps);
    assert!(
        close(p, lo + eps, 1e-15) && u == 1.0,
        "rising from the floor 0.9 s later: {p} {u}"
    );
    let (p, u) = triangle_wave(p0, u0, lo, hi, 1.8);
    assert!(
        close(p, p0, 1e-15) && u == u0,
        "back at the start after 2L/u: {p} {u}"
    );
}

proptest! {
    #[test]
    fn triangle_wave_stays_in_the_box_at_the_start_speed(
        p0 in 0.05f64..0.95, u0 in -5.0f64..5.0, t in 0.0f64..100.0
    ) {
        let (p, u) = triangle_wave(p0, u0, 0.05, 0.95, t);
        prop_assert!((0.05..=0.95).contains(&p), "position {} left the box", p);
        prop_assert_eq!(u.abs(), u0.abs());
    }
}

#[test]
fn a_dropped_ball_rests_at_the_closed_form_time() {
    let (h, c) = (0.45, 0.95);
    let a = AxisMotion {
        p0: 0.05 + h,
        u0: 0.0,
        a: -G,
        lo: 0.05,
        hi: 0.95,
        c,
    };
    let exact = (2.0 * h / G).sqrt() * (1.0 + c) / (1.0 - c);
    let rest = a.rest_time().expect("c < 1 rests");
    assert!(
        close(rest, exact, 1e-13),
        "rest at {rest}, closed form {exact}"
    );
    assert_eq!(
        a.at(rest + 1e-9),
        (0.05, 0.0),
        "resting after the rest time"
    );
    assert_eq!(a.at(1e6), (0.05, 0.0), "still resting much later");
    let before = a.at(rest - 1e-3);
    assert!(
        before.0 > 0.05 || before.1 != 0.0,
        "still bouncing just before"
    );
}

#[test]
fn the_bounces_of_a_dropped_ball_follow_the_geometric_series() {
    let (h, c) = (0.45, 0.8);
    let a = AxisMotion {
        p0: 0.05 + h,
        u0: 0.0,
        a: -G,
        lo: 0.05,
        hi: 0.95,
        c,
    };
    let impacts = a.impacts(100.0, 12);
    assert_eq!(impacts.len(), 12);
    let t1 = (2.0 * h / G).sqrt();
    let v1 = (2.0 * G * h).sqrt();
    for (k, i) in impacts.iter().enumerate() {
        // t_k = t_1 + 2 v_1 c (1 - c^(k)) / (g (1 - c)) for k = 0, 1, ...
        let expected = t1 + 2.0 * v1 * c * (1.0 - c.powi(k as i32)) / (G * (1.0 - c));
        assert!(
            close(i.time, expected, 1e-13),
            "impact {k}: {} vs {expected}",
            i.time
        );
        assert!(!i.upper, "impact {k} on the floor");
        assert!(
            close(i.speed_out, v1 * c.powi(k as i32 + 1), 1e-13),
            "speed after impact {k}"
        );
    }
    // Apexes shrink by c^2.
    for w in impacts.windows(2) {
        let ratio = (w[1].speed_out / w[0].speed_out).powi(2);
        assert!(close(ratio, c * c, 1e-13), "apex ratio {ratio}");
    }
}

#[test]
fn a_ball_thrown_up_rests_after_its_first_impact_plus_the_series() {
    let (h, u0, c) = (0.3, 1.5, 0.9);
    let a = AxisMotion {
        p0: 0.05 + h,
        u0,
        a: -G,
        lo: 0.05,
        hi: 0.95,
        c,
    };
    let v1 = (u0 * u0 + 2.0 * G * h).sqrt();
    let t1 = (u0 + v1) / G;
    let exact = t1 + 2.0 * c * v1 / (G * (1.0 - c));
    let rest = a.rest_time().expect("rests");
    assert!(
        close(rest, exact, 1e-13),
        "rest at {rest}, closed form {exact}"
    );
}

#[test]
fn energy_is_kept_between_impacts_and_lost_by_c_squared_at_each() {
    // Start near the ceiling going up fast: the ceiling is hit first, then
    // the floor, the ceiling again, then the floor only. In flight the
    // axis energy u^2 / 2 + g p is constant; an impact at a wall keeps p
    // and turns u into -c u, so the kinetic part at the wall, the flight's
    // energy less g p_wall, comes out c^2 times what went in, at the
    // ceiling as at the floor.
    let (c, lo, hi) = (0.9, 0.05, 0.95);
    let a = AxisMotion {
        p0: 0.9,
        u0: 3.0,
        a: -G,
        lo,
        hi,
        c,
    };
    let impacts = a.impacts(10.0, 7);
    let uppers: Vec<bool> = impacts.iter().map(|i| i.upper).collect();
    assert_eq!(uppers, [true, false, true, false, false, false, false]);
    let energy = |(p, u): (f64, f64)| 0.5 * u * u + G * p;
    // The energy of each flight, read at its middle: before the first
    // impact, then between each two.
    let bounds: Vec<f64> = std::iter::once(0.0)
        .chain(impacts.iter().map(|i| i.time))
        .collect();
    let flights: Vec<f64> = bounds
        .windows(2)
        .map(|w| energy(a.at(0.5 * (w[0] + w[1]))))
        .collect();
    for (k, w) in impacts.windows(2).enumerate() {
        let after = w[0].time + 1e-9;
        assert!(
            close(flights[k + 1], energy(a.at(after)), 1e-7),
            "energy constant in flight between {} and {}",
            w[0].time,
            w[1].time
        );
    }
    for (k, impact) in impacts[..6].iter().enumerate() {
        let wall = if impact.upper { hi } else { lo };
        let (into, out) = (flights[k] - G * wall, flights[k + 1] - G * wall);
        assert!(
            close(out, c * c * into, 1e-12),
            "impact {k} (upper {}): kinetic energy {into} J/kg in, {out} J/kg out",
            impact.upper
        );
    }
}

#[test]
fn the_continuous_method_follows_the_gravity_reference_to_rounding() {
    let mut world = Lesson::Gravity.scene().build().unwrap();
    world.config.integrator = Integrator::Continuous;
    world.config.dt = 1.0 / 30.0;
    let reference = Reference::of(&world);
    world.run(60);
    let exact = reference.positions_at(60.0 / 30.0).unwrap();
    let error = rms_distance(&exact, &world.bodies.position);
    assert!(
        error < 1e-12,
        "RMS error {error:e} m after 2 s at dt = 1/30"
    );
}

#[test]
fn the_event_driven_reference_agrees_with_itself_split_into_steps() {
    let world = Lesson::Collisions.scene().build().unwrap();
    let once = exact_positions(&world, 0.2).unwrap();
    let mut stepped: World = world.clone();
    stepped.config.integrator = Integrator::Continuous;
    stepped.config.dt = 0.01;
    stepped.run(20);
    let error = rms_distance(&once, &stepped.bodies.position);
    assert!(
        error < 1e-12,
        "one event loop and twenty differ by {error:e} m at 0.2 s"
    );
}

#[test]
fn the_collisions_lesson_is_predictable_for_a_fraction_of_a_second_only() {
    let world = Lesson::Collisions.scene().build().unwrap();
    let horizon = predictability_horizon(&world, 1e-12, 1e-3, 0.02, 3.0)
        .expect("a 1e-12 m nudge grows to 1 mm within 3 s");
    assert!(
        (0.2..3.0).contains(&horizon),
        "1e-12 m grows to 1 mm at {horizon} s"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// One sphere and the walls: the continuous method and the closed-form
    /// chain of parabolas agree at every step end, whatever the start, the
    /// restitution and the step.
    #[test]
    fn the_continuous_method_matches_the_closed_form_for_one_sphere(
        p in prop::array::uniform3(0.06f64..0.94),
        u in prop::array::uniform3(-3.0f64..3.0),
        c in 0.0f64..=1.0,
        dt in 0.001f64..0.1,
    ) {
        use lerpit::sim::{WallMode, WorldConfig};
        let config = WorldConfig {
            dt,
            integrator: Integrator::Continuous,
            wall_mode: WallMode::Restitution,
            wall_restitution: c,
            pair_collisions: false,
            ..WorldConfig::default()
        };
        let mut w = world(config, &[sphere(p, u, 0.05, 1.0)]);
        let reference = Reference::of(&w);
        for n in 1..=60u32 {
            w.step();
            let exact = reference.positions_at(f64::from(n) * dt).unwrap();
            let error = exact[0].distance(w.bodies.position[0]);
            prop_assert!(error < 1e-9, "step {}: {:e} m off", n, error);
        }
    }
}

#[test]
fn rk4_and_verlet_are_exact_between_impacts() {
    use lerpit::sim::{Vec3, WorldConfig};
    for m in [Integrator::Rk4, Integrator::VelocityVerlet] {
        let config = WorldConfig {
            dt: 0.01,
            integrator: m,
            pair_collisions: false,
            ..WorldConfig::default()
        };
        let (p0, u0) = (Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.3, 1.0, -0.2));
        let mut w = world(config, &[sphere(p0, u0, 0.05, 1.0)]);
        w.run(20);
        let (t, g) = (0.2, Vec3::new(0.0, -G, 0.0));
        let exact = p0 + u0 * t + g * (0.5 * t * t);
        let error = exact.distance(w.bodies.position[0]);
        assert!(error < 1e-15, "{}: {error:e} m from the parabola", m.name());
    }
}

#[test]
fn one_sphere_past_its_impact_cap_still_follows_the_closed_form() {
    use lerpit::sim::{Vec3, WallMode, WorldConfig};
    // Thousands of impacts per axis per step, beyond the cap: with elastic
    // walls the rest of the step is the exact periodic motion, and the step
    // does not report a fallback.
    let config = WorldConfig {
        dt: 0.5,
        gravity: Vec3::new(0.0, -1e4, 0.0),
        integrator: Integrator::Continuous,
        wall_mode: WallMode::Restitution,
        wall_restitution: 1.0,
        pair_collisions: false,
        ..WorldConfig::default()
    };
    let mut w = world(
        config,
        &[sphere([0.3, 0.6, 0.8], [5e3, 2e3, -3e3], 0.05, 1.0)],
    );
    let reference = Reference::of(&w);
    for n in 1..=20u32 {
        w.step();
        assert!(!w.last.event_cap_reached, "step {n} reported a fallback");
        assert!(w.last.wall_impacts > 1008, "step {n} must pass the cap");
        let exact = reference.positions_at(f64::from(n) * 0.5).unwrap();
        let error = exact[0].distance(w.bodies.position[0]);
        // Both round: the reference adds up the times of thousands of
        // impacts. 1e-12 of the distance travelled (6 km per second).
        let travelled = 6.2e3 * f64::from(n) * 0.5;
        assert!(
            error < 1e-12 * travelled,
            "step {n}: {error:e} m off after {travelled} m"
        );
    }
}
