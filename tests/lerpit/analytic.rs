//! Closed-form truths of the lesson's physics: the ping-pong triangle wave,
//! the apex ratio c_r^2 of a bouncing ball, and two-body collisions against
//! the momentum and restitution equations that define V1 and V2.

use crate::support::{sphere, world};
use lerpit::sim::{Integrator, Vec3, WallMode, WorldConfig};

/// Height of a point moving at unit speed between `lo` and `hi`, starting at
/// `y0` moving up: the exact triangle wave.
fn triangle_wave(y0: f64, speed: f64, lo: f64, hi: f64, t: f64) -> f64 {
    let span = hi - lo;
    let unfolded = (y0 - lo) + speed * t;
    let m = unfolded.rem_euclid(2.0 * span);
    lo + if m <= span { m } else { 2.0 * span - m }
}

#[test]
fn pingpong_follows_the_exact_triangle_wave_at_every_step() {
    let r = 0.05;
    for dt in [1.0 / 60.0, 0.0137, 1.0 / 1000.0, 0.25] {
        for integrator in Integrator::ALL {
            let config = WorldConfig {
                gravity: Vec3::ZERO,
                dt,
                integrator,
                wall_mode: WallMode::Flip,
                pair_collisions: false,
                ..WorldConfig::default()
            };
            let mut w = world(config, &[sphere([0.5, 0.5, 0.5], [0.0, 1.0, 0.0], r, 1.0)]);
            for n in 1..=5000u32 {
                w.step();
                let t = f64::from(n) * dt;
                let exact = triangle_wave(0.5, 1.0, r, 1.0 - r, t);
                let y = w.bodies.position[0].y;
                assert!(
                    (y - exact).abs() < 1e-9,
                    "{integrator:?}, dt {dt}: step {n}, t {t}: y = {y}, triangle wave = {exact}"
                );
                assert_eq!(w.bodies.velocity[0].y.abs(), 1.0, "flip keeps the speed");
                assert_eq!(w.bodies.position[0].x, 0.5);
                assert_eq!(w.bodies.position[0].z, 0.5);
            }
        }
    }
}

/// Apex heights above the floor of a ball dropped from `h0` above it.
fn apex_heights(integrator: Integrator, dt: f64, h0: f64, c_r: f64, bounces: usize) -> Vec<f64> {
    let r = 0.05;
    let config = WorldConfig {
        dt,
        integrator,
        wall_mode: WallMode::Restitution,
        wall_restitution: c_r,
        pair_collisions: false,
        ..WorldConfig::default()
    };
    let mut w = world(config, &[sphere([0.5, r + h0, 0.5], [0.0; 3], r, 1.0)]);
    let mut heights = vec![h0];
    let mut previous_vy = 0.0;
    while heights.len() <= bounces {
        w.step();
        let vy = w.bodies.velocity[0].y;
        if previous_vy > 0.0 && vy <= 0.0 {
            heights.push(w.bodies.position[0].y - r);
        }
        previous_vy = vy;
        assert!(w.time < 60.0, "{integrator:?}, dt {dt}: no apex found");
    }
    heights
}

#[test]
fn successive_apex_heights_shrink_by_restitution_squared_within_a_tolerance_shrinking_with_dt() {
    let c_r = 0.95;
    for integrator in Integrator::ALL {
        let mut worst_by_dt = Vec::new();
        for dt in [1.0 / 120.0, 1.0 / 1000.0, 1e-4] {
            let h = apex_heights(integrator, dt, 0.75, c_r, 6);
            let worst = h
                .windows(2)
                .map(|p| (p[1] / p[0] - c_r * c_r).abs())
                .fold(0.0, f64::max);
            // First order in dt: the bounce and the sampled apex are each off
            // by at most about a step.
            assert!(
                worst < 25.0 * dt,
                "{integrator:?}, dt {dt}: apex ratio off c_r^2 by {worst:.3e}, bound {:.3e}",
                25.0 * dt
            );
            worst_by_dt.push(worst);
        }
        assert!(
            worst_by_dt[2] < worst_by_dt[0] / 10.0,
            "{integrator:?}: apex-ratio error does not shrink with dt: {worst_by_dt:?}"
        );
    }
}

fn collision_config(e: f64) -> WorldConfig {
    WorldConfig {
        gravity: Vec3::ZERO,
        dt: 1e-3,
        integrator: Integrator::SemiImplicitEuler,
        wall_mode: WallMode::Flip,
        pair_collisions: true,
        pair_restitution: e,
        ..WorldConfig::default()
    }
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn head_on_collision_of_unequal_masses_matches_v1_v2() {
    // m1 = 1 at +1 m/s meets m2 = 3 at -1 m/s, e = 0.8. Momentum -2 and
    // separation speed 0.8 * 2 give V1 = -1.7, V2 = -0.1.
    let (m1, m2, e) = (1.0, 3.0, 0.8);
    let a = sphere([0.3, 0.5, 0.5], [1.0, 0.0, 0.0], 0.1, m1);
    let b = sphere([0.499, 0.5, 0.5], [-1.0, 0.0, 0.0], 0.1, m2);
    let mut w = world(collision_config(e), &[a, b]);
    w.step();
    assert_eq!(w.last.contacts, 1, "the spheres overlap after one step");
    let (v1, v2) = (w.bodies.velocity[0], w.bodies.velocity[1]);
    assert!((v1.x - -1.7).abs() < 1e-12, "V1 = {}", v1.x);
    assert!((v2.x - -0.1).abs() < 1e-12, "V2 = {}", v2.x);
    assert_eq!((v1.y, v1.z, v2.y, v2.z), (0.0, 0.0, 0.0, 0.0));

    // The overlap is removed, split by inverse mass: m1 moves 3/4 of it.
    let before = [0.3 + 1e-3, 0.499 - 1e-3];
    let penetration = 0.2 - (before[1] - before[0]);
    let (p1, p2) = (w.bodies.position[0].x, w.bodies.position[1].x);
    assert!((before[0] - p1 - 0.75 * penetration).abs() < 1e-15);
    assert!((p2 - before[1] - 0.25 * penetration).abs() < 1e-15);
    assert!(
        (p2 - p1 - 0.2).abs() < 1e-15,
        "touching after the correction"
    );
}

#[test]
fn oblique_collision_keeps_tangential_velocity_and_conserves_momentum() {
    let (m1, m2, e) = (2.0, 0.5, 0.6);
    let u1 = Vec3::new(1.3, 0.4, -0.2);
    let u2 = Vec3::new(-0.7, -0.9, 0.35);
    // Centres 0.15 apart along a skewed direction; radii 0.1 each.
    let n = Vec3::new(1.0, 0.6, -0.3).normalize();
    let c1 = Vec3::new(0.4, 0.4, 0.5);
    let a = sphere(c1.to_array(), u1.to_array(), 0.1, m1);
    let b = sphere((c1 + 0.15 * n).to_array(), u2.to_array(), 0.1, m2);
    let mut w = world(collision_config(e), &[a, b]);
    let p_before = m1 * u1 + m2 * u2;
    w.step();
    assert_eq!(w.last.contacts, 1);
    let normal = (w.bodies.position[1] - w.bodies.position[0]).normalize();
    // The normal at impact is along the centres before correction; the
    // correction moves them along it, so the direction is unchanged.
    let (v1, v2) = (w.bodies.velocity[0], w.bodies.velocity[1]);
    let tangential = |v: Vec3| v - v.dot(normal) * normal;
    assert!((tangential(v1) - tangential(u1)).length() < 1e-12);
    assert!((tangential(v2) - tangential(u2)).length() < 1e-12);
    // Restitution: separation speed = e * approach speed along the normal.
    let approach = (u1 - u2).dot(normal);
    let separation = (v2 - v1).dot(normal);
    assert!(approach > 0.0);
    assert!(relative(separation, e * approach) < 1e-12);
    // Momentum, to 1e-12 relative.
    let p_after = m1 * v1 + m2 * v2;
    assert!(
        (p_after - p_before).length() / p_before.length() < 1e-12,
        "momentum {p_before} -> {p_after}"
    );
}

#[test]
fn a_separating_pair_gets_no_impulse_only_the_projection() {
    let a = sphere([0.4, 0.5, 0.5], [-1.0, 0.2, 0.0], 0.1, 1.0);
    let b = sphere([0.55, 0.5, 0.5], [1.0, 0.0, 0.3], 0.1, 2.0);
    let mut w = world(collision_config(1.0), &[a, b]);
    w.step();
    assert_eq!(w.last.contacts, 1);
    assert_eq!(w.bodies.velocity[0], a.velocity);
    assert_eq!(w.bodies.velocity[1], b.velocity);
    let d = w.bodies.position[0].distance(w.bodies.position[1]);
    assert!((d - 0.2).abs() < 1e-14, "separated to touching: {d}");
}

#[test]
fn restitution_zero_leaves_the_pair_moving_together_along_the_normal() {
    let a = sphere([0.3, 0.5, 0.5], [2.0, 0.0, 0.0], 0.1, 1.0);
    let b = sphere([0.499, 0.5, 0.5], [0.0, 0.0, 0.0], 0.1, 4.0);
    let mut w = world(collision_config(0.0), &[a, b]);
    w.step();
    // Perfectly inelastic: both at the centre-of-mass velocity 2/5.
    assert!((w.bodies.velocity[0].x - 0.4).abs() < 1e-15);
    assert!((w.bodies.velocity[1].x - 0.4).abs() < 1e-15);
}
