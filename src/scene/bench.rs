//! The benchmark scene: `N` equal spheres of radius
//! `r = (0.075 / (pi N))^(1/3)`, so that they fill 10% of the box, centres
//! uniform in `[r, 1 - r]^3` (overlaps allowed: the solver separates them),
//! velocities uniform in `[-1, 1]^3` m/s, all drawn from one PCG-64
//! generator seeded with [`BENCH_SEED`]; standard gravity down, wall and
//! pair restitution 0.95, `dt = 1/60` s, pair collisions on. `lerpit
//! bench` times it at any size; tests use it as a large world.

use super::file::DEFAULT_DENSITY;
use crate::sim::{
    Bodies, Body, BroadPhase, MassLaw, STANDARD_GRAVITY, Vec3, WallMode, World, WorldConfig,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::f64::consts::PI;

/// Seed of the benchmark scene.
pub const BENCH_SEED: u64 = 7;
/// Fraction of the box's volume the spheres fill.
pub const SOLID_FRACTION: f64 = 0.1;

/// The radius that makes `n` equal spheres fill [`SOLID_FRACTION`] of the
/// box: `n (4/3) pi r^3 = 0.1`.
pub fn bench_radius(n: usize) -> f64 {
    (SOLID_FRACTION * 3.0 / (4.0 * PI * n as f64)).cbrt()
}

/// The benchmark scene with `n` spheres.
pub fn bench_world(n: usize, broad_phase: BroadPhase) -> World {
    let r = bench_radius(n);
    let mass = MassLaw::Volume {
        density: DEFAULT_DENSITY,
    }
    .mass(r);
    let mut rng = Pcg64Mcg::seed_from_u64(BENCH_SEED);
    let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    let mut bodies = Bodies::with_capacity(n);
    for _ in 0..n {
        let position = Vec3::new(
            uniform(r, 1.0 - r),
            uniform(r, 1.0 - r),
            uniform(r, 1.0 - r),
        );
        let velocity = Vec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
        bodies.push(Body {
            position,
            velocity,
            radius: r,
            mass,
        });
    }
    let config = WorldConfig {
        gravity: Vec3::new(0.0, -STANDARD_GRAVITY, 0.0),
        dt: 1.0 / 60.0,
        wall_mode: WallMode::Restitution,
        wall_restitution: 0.95,
        pair_collisions: true,
        pair_restitution: 0.95,
        broad_phase,
        ..WorldConfig::default()
    };
    World::new(config, bodies)
}
