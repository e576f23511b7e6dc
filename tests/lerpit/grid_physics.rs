//! The lesson's physics holds on the large-world path (grid broad phase,
//! spatial slot order, slab-parallel contact solver): momentum and the
//! centre of mass are kept by the contact solve, separating pairs get no
//! impulse, a pair separates at e times its approach speed, and no sphere
//! ends a step outside the box.

use crate::support::sphere;
use lerpit::scene::bench::bench_world;
use lerpit::sim::large::solve_contacts_in_slabs;
use lerpit::sim::{Bodies, BroadPhase, CellLayout, Grid, Vec3};

/// A crowd with mixed masses, in cell order, and its contacts.
fn crowd_with_contacts() -> (Bodies, Vec<lerpit::sim::Contact>, CellLayout) {
    let world = bench_world(20_000, BroadPhase::Grid);
    let mut bodies = world.bodies;
    for (k, m) in bodies.mass.iter_mut().enumerate() {
        *m *= 1.0 + (k % 7) as f64;
    }
    for k in 0..bodies.len() {
        bodies.inverse_mass[k] = 1.0 / bodies.mass[k];
    }
    let layout = CellLayout::of(&bodies);
    let mut grid = Grid::new();
    grid.build(&bodies, layout);
    grid.reorder_bodies(&mut bodies, &mut Vec::new());
    let mut contacts = Vec::new();
    grid.find_contacts(&bodies, &mut contacts);
    (bodies, contacts, layout)
}

fn sums(b: &Bodies) -> (Vec3, Vec3, f64) {
    let (mut p, mut mx, mut scale) = (Vec3::ZERO, Vec3::ZERO, 0.0);
    for k in 0..b.len() {
        p += b.mass[k] * b.velocity[k];
        mx += b.mass[k] * b.position[k];
        scale += b.mass[k] * b.velocity[k].length();
    }
    (p, mx, scale)
}

#[test]
fn the_slab_solver_conserves_momentum_and_the_centre_of_mass() {
    let (mut bodies, contacts, layout) = crowd_with_contacts();
    assert!(contacts.len() > 1000, "the crowd overlaps");
    let (p0, mx0, scale) = sums(&bodies);
    let slabs = solve_contacts_in_slabs(&mut bodies, &contacts, 0.95, layout);
    assert!(slabs > 2, "the slab path ran ({slabs} slabs)");
    let (p1, mx1, _) = sums(&bodies);
    let mass: f64 = bodies.mass.iter().sum();
    assert!(
        (p1 - p0).length() <= 1e-12 * scale,
        "momentum changed by {:e}",
        (p1 - p0).length()
    );
    assert!(
        (mx1 - mx0).length() <= 1e-12 * mass,
        "centre of mass moved by {:e} m",
        ((mx1 - mx0) / mass).length()
    );
}

fn pair(v1: Vec3, v2: Vec3, m1: f64, m2: f64) -> Bodies {
    [
        sphere([0.45, 0.5, 0.5], v1, 0.06, m1),
        sphere([0.55, 0.5, 0.5], v2, 0.06, m2),
    ]
    .into_iter()
    .collect()
}

fn solve_pair(bodies: &mut Bodies, e: f64) -> usize {
    let mut contacts = Vec::new();
    BroadPhase::Grid.find_contacts(bodies, &mut contacts);
    assert_eq!(contacts.len(), 1, "the pair overlaps");
    solve_contacts_in_slabs(bodies, &contacts, e, CellLayout::of(bodies))
}

#[test]
fn a_separating_pair_gets_no_impulse_but_is_pushed_apart() {
    let (v1, v2) = (Vec3::new(-1.0, 0.2, 0.0), Vec3::new(0.5, 0.0, 0.3));
    let mut bodies = pair(v1, v2, 1.0, 3.0);
    assert!(solve_pair(&mut bodies, 0.95) > 1, "the slab path ran");
    assert_eq!((bodies.velocity[0], bodies.velocity[1]), (v1, v2));
    let d = bodies.position[0].distance(bodies.position[1]);
    assert!((d - 0.12).abs() < 1e-15, "distance after projection {d}");
    // Split by inverse mass: the lighter sphere (mass 1) moves 3 times as far.
    let moved = (0.45 - bodies.position[0].x, bodies.position[1].x - 0.55);
    assert!((moved.0 - 3.0 * moved.1).abs() < 1e-15, "{moved:?}");
}

#[test]
fn an_approaching_pair_separates_at_e_times_its_approach_speed() {
    let (m1, m2, e) = (2.0, 5.0, 0.8);
    let (v1, v2) = (Vec3::new(1.5, 0.3, 0.0), Vec3::new(-0.5, 0.0, -0.2));
    let mut bodies = pair(v1, v2, m1, m2);
    solve_pair(&mut bodies, e);
    let (w1, w2) = (bodies.velocity[0], bodies.velocity[1]);
    let approach = v1.x - v2.x;
    assert!(((w2.x - w1.x) - e * approach).abs() < 1e-14);
    assert!(((m1 * w1 + m2 * w2) - (m1 * v1 + m2 * v2)).length() < 1e-14);
    assert_eq!((w1.y, w1.z, w2.y, w2.z), (v1.y, v1.z, v2.y, v2.z));
}

#[test]
fn no_sphere_leaves_the_box_on_the_large_world_path() {
    let mut world = bench_world(20_000, BroadPhase::Grid);
    for step in 0..30 {
        world.step();
        let b = &world.bodies;
        for k in 0..b.len() {
            let (p, r) = (b.position[k], b.radius[k]);
            assert!(
                p.cmpge(Vec3::splat(r)).all() && p.cmple(Vec3::splat(1.0 - r)).all(),
                "step {step}: sphere {} at {p} outside [r, 1 - r]",
                b.id[k]
            );
        }
    }
    assert!(world.last.contact_slabs > 2, "the slab path ran");
}
