//! The benchmark scene: `N` equal spheres of radius
//! `r = (0.075 / (pi N))^(1/3)`, so that they fill 10% of the box, standard
//! gravity down, wall and pair restitution 0.95, `dt = 1/60` s, pair
//! collisions on. `lerpit bench` times it at any size, from either of two
//! starts ([`BenchStart`]); tests use it as a large world.
//!
//! The dilute start: centres uniform in `[r, 1 - r]^3` (overlaps allowed:
//! the solver separates them), velocities uniform in `[-1, 1]^3` m/s, all
//! drawn from one PCG-64 generator seeded with [`BENCH_SEED`]. Its first 20
//! steps find about 0.6 contact pairs per sphere.
//!
//! The settled start: what the dilute start becomes under gravity. Within
//! about 4 s (240 steps) the spheres collect in a layer on the floor that
//! keeps its contact count (within 1%) and its height from then on. It is
//! no static pile: each step gravity moves a sphere by `g dt^2 = 2.7 mm`,
//! which is 0.2 `r` at N = 10^4, 0.44 `r` at 10^5 and 0.95 `r` at 10^6, more
//! than the one projection pass a step removes from a pile several spheres
//! deep. So the layer stays compressed, its spheres overlapping by up to
//! 2 `r` (as the overlaps of random centres are distributed) and moving
//! 0.3 `r` (N = 10^3) to 2.5 `r` (10^6) a step; about 30% of them lie on
//! the floor. Its contact pairs per sphere grow nearly as `1/r`, as those
//! of random centres in a layer a fixed number of radii thick do. Measured
//! over steps 581 to 600 (the end of 10 s; `lerpit bench --warmup 579`):
//!
//! | N         | contact pairs per sphere |
//! |-----------|--------------------------|
//! | 1,000     | 2.68                     |
//! | 3,000     | 3.79                     |
//! | 10,000    | 5.30                     |
//! | 100,000   | 11.08                    |
//! | 1,000,000 | 20.07                    |
//!
//! The settled start builds that layer directly, at rest: x and z uniform
//! in `[r, 1 - r]`, and y such that a fraction [`SETTLED_FLOOR_FRACTION`]
//! of the spheres lies on the floor (`y = r`) and the rest is uniform in a
//! layer [`SETTLED_LAYER_RADII`] radii thick above it (the layer never
//! passes `1 - r`: below about ten spheres it fills the box), from the same
//! seeded generator. Its 20 steps after the first find 0.92, 0.97, 1.04,
//! 1.05 and 1.05 times the contact pairs above at those sizes; stepping
//! on, it keeps its height and its contact count (the tests below).

use super::file::DEFAULT_DENSITY;
use crate::sim::config::choice;
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
/// Thickness of the settled start's layer of centres, in radii (above the
/// lowest height a centre can take, `r`).
pub(crate) const SETTLED_LAYER_RADII: f64 = 4.5;
/// Fraction of the settled start's spheres lying on the floor (`y = r`).
pub(crate) const SETTLED_FLOOR_FRACTION: f64 = 0.3;

choice! {
    /// The state the benchmark scene starts from.
    pub enum BenchStart: "start state" {
        /// Spheres spread through the box in flight, as spawned (under one
        /// contact pair per sphere).
        Dilute,
        /// Spheres at rest in a layer on the floor, as dense as the scene
        /// settles to under gravity without the support pass.
        Settled,
    }
}

/// The radius that makes `n` equal spheres fill [`SOLID_FRACTION`] of the
/// box: `n (4/3) pi r^3 = 0.1`.
pub fn bench_radius(n: usize) -> f64 {
    (SOLID_FRACTION * 3.0 / (4.0 * PI * n as f64)).cbrt()
}

/// The benchmark scene's time step, s.
pub const BENCH_DT: f64 = 1.0 / 60.0;

/// The benchmark scene with `n` spheres, from the dilute start.
pub fn bench_world(n: usize, broad_phase: BroadPhase) -> World {
    bench_world_from(BenchStart::Dilute, n, broad_phase)
}

/// The overlapping pairs per sphere the settled start of `n` spheres has
/// on average, from its geometry. Centres lie within a square of side
/// `w = 1 - 2 r`: a fraction `f` on the floor at area density
/// `sigma = f n / w^2`, the rest in the layer `h` thick above at volume
/// density `rho = (1 - f) n / (w^2 h)`; spheres overlap within `d = 2 r`.
/// Within the layer there are `(1 - f) n rho V / 2` pairs, where
/// `V = 4/3 pi d^3 - pi d^4 / (2 h)` is the mean volume within `d` of a
/// centre that lies inside the layer; between the floor and the layer,
/// `f n rho (2/3 pi d^3)`; on the floor, `f n sigma pi d^2 / 2`. The side
/// walls take `3 d / (4 w)` of a volume and `8 d / (3 pi w)` of an area
/// (the same mean over the positions across the square). Meant from 10
/// spheres, where the layer stops filling the box.
pub(crate) fn settled_pairs_per_sphere(n: usize) -> f64 {
    settled_pairs_within(n, 2.0 * bench_radius(n))
}

/// The pairs per sphere of the settled start of `n` spheres whose centres
/// are closer than `d` (m, from a diameter up), by the geometry of
/// [`settled_pairs_per_sphere`] with `d` for the diameter.
pub(crate) fn settled_pairs_within(n: usize, d: f64) -> f64 {
    let (r, f, n) = (bench_radius(n), SETTLED_FLOOR_FRACTION, n as f64);
    let (h, w) = (SETTLED_LAYER_RADII * r, 1.0 - 2.0 * r);
    let (sides_3d, sides_2d) = (1.0 - 3.0 * d / (4.0 * w), 1.0 - 8.0 * d / (3.0 * PI * w));
    let rho = (1.0 - f) * n / (w * w * h);
    let sigma = f * n / (w * w);
    let within = 4.0 / 3.0 * PI * d.powi(3) - PI * d.powi(4) / (2.0 * h);
    let layer = 0.5 * (1.0 - f) * n * rho * within * sides_3d;
    let floor_to_layer = f * n * rho * 2.0 / 3.0 * PI * d.powi(3) * sides_3d;
    let floor = 0.5 * f * n * sigma * PI * d * d * sides_2d;
    (layer + floor_to_layer + floor) / n
}

/// The benchmark scene with `n` spheres from `start`.
pub fn bench_world_from(start: BenchStart, n: usize, broad_phase: BroadPhase) -> World {
    let r = bench_radius(n);
    let mass = MassLaw::Volume {
        density: DEFAULT_DENSITY,
    }
    .mass(r);
    let mut rng = Pcg64Mcg::seed_from_u64(BENCH_SEED);
    let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    let mut bodies = Bodies::with_capacity(n);
    // The settled layer: at most the box's height (fewer than about ten
    // spheres fill it).
    let thickness = (SETTLED_LAYER_RADII * r).min(1.0 - 2.0 * r);
    let floor = SETTLED_FLOOR_FRACTION;
    for _ in 0..n {
        let (position, velocity) = match start {
            BenchStart::Dilute => (
                Vec3::new(
                    uniform(r, 1.0 - r),
                    uniform(r, 1.0 - r),
                    uniform(r, 1.0 - r),
                ),
                Vec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0)),
            ),
            BenchStart::Settled => (
                Vec3::new(
                    uniform(r, 1.0 - r),
                    r + thickness * ((uniform(0.0, 1.0) - floor) / (1.0 - floor)).max(0.0),
                    uniform(r, 1.0 - r),
                ),
                Vec3::ZERO,
            ),
        };
        bodies.push(Body {
            position,
            velocity,
            radius: r,
            mass,
        });
    }
    World::new(bench_config(broad_phase), bodies)
}

/// The benchmark scene's parameters.
pub(crate) fn bench_config(broad_phase: BroadPhase) -> WorldConfig {
    WorldConfig {
        gravity: Vec3::new(0.0, -STANDARD_GRAVITY, 0.0),
        dt: BENCH_DT,
        wall_mode: WallMode::Restitution,
        wall_restitution: 0.95,
        pair_collisions: true,
        pair_restitution: 0.95,
        broad_phase,
        ..WorldConfig::default()
    }
}

/// How far beyond touching (m) the support pass lists the pairs of the
/// benchmark scene of `n` spheres (`support.rs`).
pub(crate) fn bench_support_margin(n: usize) -> f64 {
    let config = WorldConfig {
        support: true,
        ..bench_config(BroadPhase::Auto)
    };
    crate::sim::support::Support::of(&config, BENCH_DT, || bench_radius(n))
        .map_or(0.0, |s| s.margin)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Above [`crate::sim::large::SPATIAL_ORDER_MIN_BODIES`], so that the
    /// steps take the path of large benchmarks (cell order, slabs).
    const N: usize = 5_000;

    fn settled(n: usize) -> World {
        bench_world_from(BenchStart::Settled, n, BroadPhase::Auto)
    }

    /// Contact pairs per sphere over the next `steps` steps.
    fn contacts_per_sphere(w: &mut World, steps: u64) -> f64 {
        let mut contacts = 0;
        for _ in 0..steps {
            w.step();
            contacts += w.last.contacts;
        }
        contacts as f64 / steps as f64 / w.bodies.len() as f64
    }

    fn mean_height(w: &World) -> f64 {
        w.bodies.position.iter().map(|p| p.y).sum::<f64>() / w.bodies.len() as f64
    }

    #[test]
    fn settled_start_has_the_contacts_of_ten_seconds_of_settling() {
        // The dilute start after 10 s (600 steps of 1/60 s): its last 20.
        let mut dilute = bench_world(N, BroadPhase::Auto);
        let spread = contacts_per_sphere(&mut dilute, 20);
        dilute.run(560);
        let after_10_s = contacts_per_sphere(&mut dilute, 20);
        // The settled start as `lerpit bench --start settled` times it: 20
        // steps after the first.
        let mut w = settled(N);
        w.step();
        let start = contacts_per_sphere(&mut w, 20);
        let ratio = start / after_10_s;
        eprintln!("settled start {start:.3}, after 10 s {after_10_s:.3}, first steps {spread:.3}");
        assert!(
            (0.8..=1.2).contains(&ratio),
            "settled start {start:.3} contact pairs per sphere, the dilute start after 10 s \
             {after_10_s:.3}: ratio {ratio:.3}"
        );
        assert!(
            spread < 0.5 * after_10_s,
            "the dilute start's first steps ({spread:.3}) are far from settled"
        );
    }

    #[test]
    fn the_settled_starts_pairs_are_as_its_geometry_says() {
        for n in [1_000, N, 20_000] {
            let w = settled(n);
            let mut contacts = Vec::new();
            BroadPhase::Grid.find_contacts(&w.bodies, &mut contacts);
            let found = contacts.len() as f64 / n as f64;
            let expected = settled_pairs_per_sphere(n);
            eprintln!("n = {n}: {found:.3} pairs per sphere, {expected:.3} expected");
            assert!(
                (expected / found - 1.0).abs() < 0.03,
                "n = {n}: {found:.3} pairs per sphere, {expected:.3} expected"
            );
        }
    }

    #[test]
    fn settled_start_is_at_rest_inside_the_box_and_the_same_every_time() {
        for n in [1, 2, 7, 100, N] {
            let w = settled(n);
            let r = bench_radius(n);
            assert_eq!(w.bodies.len(), n);
            let top = r + SETTLED_LAYER_RADII * r;
            let mass = bench_world(n, BroadPhase::Auto).bodies.mass[0];
            for b in w.bodies.iter() {
                assert_eq!(b.velocity, Vec3::ZERO, "n = {n}");
                assert_eq!((b.radius, b.mass), (r, mass), "n = {n}");
                let p = b.position.to_array();
                assert!(
                    p.iter().all(|&c| (r..=1.0 - r).contains(&c)),
                    "n = {n}: {p:?}"
                );
                assert!(
                    p[1] <= top * (1.0 + 1e-12),
                    "n = {n}: {p:?} above the layer"
                );
            }
            assert_eq!(w.state_hash(), settled(n).state_hash(), "n = {n}");
        }
        let w = settled(N);
        let r = bench_radius(N);
        let on_floor = w.bodies.position.iter().filter(|p| p.y == r).count();
        let expected = SETTLED_FLOOR_FRACTION * N as f64;
        assert!(
            (on_floor as f64 - expected).abs() < 0.05 * expected,
            "{on_floor} of {N} on the floor"
        );
    }

    /// The mean height's change over 60 steps (1 s), in radii, and the
    /// contact pairs per sphere of the first step and the last 20.
    fn hold(mut w: World) -> (f64, f64, f64) {
        let r = w.bodies.radius[0];
        let y0 = mean_height(&w);
        let first = contacts_per_sphere(&mut w, 1);
        w.run(39);
        let last = contacts_per_sphere(&mut w, 20);
        ((mean_height(&w) - y0) / r, first, last)
    }

    #[test]
    fn the_settled_layer_holds_its_height_and_contacts() {
        let (rise, first, last) = hold(settled(N));
        eprintln!("settled: rise {rise:.3} r, contacts {first:.3} then {last:.3}");
        assert!(rise.abs() < 1.0, "the layer moved {rise:.3} r in 1 s");
        assert!(
            (last / first - 1.0).abs() < 0.2,
            "contact pairs per sphere went from {first:.3} to {last:.3}"
        );
        // A layer placed 3 r above the floor falls, and one half as thick
        // expands: the bounds above tell them apart.
        let r = bench_radius(N);
        let mut lifted = settled(N);
        lifted
            .bodies
            .position
            .iter_mut()
            .for_each(|p| p.y += 3.0 * r);
        let (rise, ..) = hold(lifted);
        eprintln!("lifted: rise {rise:.3} r");
        assert!(rise < -2.0, "a lifted layer fell {rise:.3} r");
        let mut squeezed = settled(N);
        squeezed
            .bodies
            .position
            .iter_mut()
            .for_each(|p| p.y = r + 0.5 * (p.y - r));
        let (rise, first, last) = hold(squeezed);
        eprintln!("squeezed: rise {rise:.3} r, contacts {first:.3} then {last:.3}");
        assert!(
            last < 0.8 * first,
            "a squeezed layer expanded {rise:.3} r, contacts {first:.3} then {last:.3}"
        );
    }
}
