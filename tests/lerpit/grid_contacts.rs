//! The grid finds exactly the contacts all-pairs finds, in the same order,
//! with the same bits: on random scenes of mixed radii, with spheres on and
//! past the walls, and on a large world in cell order.

use crate::support;
use lerpit::sim::broad_phase::all_pairs;
use lerpit::sim::{Bodies, Body, BroadPhase, CellLayout, Grid, Vec3};
use proptest::prelude::*;

fn body(position: Vec3, radius: f64) -> Body {
    support::sphere(position, Vec3::ZERO, radius, 1.0)
}

/// A coordinate for a sphere of radius `r`: anywhere inside, on either
/// wall, or a little past one (as after integration, before the walls).
fn coordinate(r: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => r..=1.0 - r,
        1 => Just(r),
        1 => Just(1.0 - r),
        1 => -0.05..0.0f64,
        1 => 1.0..1.05f64,
    ]
}

fn sphere() -> impl Strategy<Value = Body> {
    prop_oneof![0.005..0.02f64, 0.02..0.06f64, 0.06..0.15f64].prop_flat_map(|r| {
        (coordinate(r), coordinate(r), coordinate(r))
            .prop_map(move |(x, y, z)| body(Vec3::new(x, y, z), r))
    })
}

fn contacts(method: BroadPhase, bodies: &Bodies) -> (Vec<lerpit::sim::Contact>, u64) {
    let mut c = Vec::new();
    let tests = method.find_contacts(bodies, &mut c);
    (c, tests)
}

/// Contacts as bits: `==` on floats takes -0 for +0, which the solver's
/// sums do not.
fn bits(contacts: &[lerpit::sim::Contact]) -> Vec<(u32, u32, [u64; 3], u64)> {
    contacts
        .iter()
        .map(|c| {
            let n = c.contact_normal;
            let normal = [n.x.to_bits(), n.y.to_bits(), n.z.to_bits()];
            (c.i, c.j, normal, c.penetration.to_bits())
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn grid_finds_the_contacts_all_pairs_finds(spheres in prop::collection::vec(sphere(), 0..250)) {
        let bodies: Bodies = spheres.into_iter().collect();
        let (expected, _) = contacts(BroadPhase::AllPairs, &bodies);
        let (found, _) = contacts(BroadPhase::Grid, &bodies);
        prop_assert_eq!(bits(&found), bits(&expected));
    }

    #[test]
    fn a_reused_grid_gives_the_same_contacts(
        first in prop::collection::vec(sphere(), 1..120),
        second in prop::collection::vec(sphere(), 1..120),
    ) {
        // A warm grid (buffers sized for another world) must not leak state.
        let mut grid = Grid::new();
        let mut found = Vec::new();
        for spheres in [first, second] {
            let bodies: Bodies = spheres.into_iter().collect();
            BroadPhase::Grid.find_contacts_with(&mut grid, &bodies, &mut found);
            let (expected, _) = contacts(BroadPhase::AllPairs, &bodies);
            prop_assert_eq!(bits(&found), bits(&expected));
        }
    }
}

/// The grid's contacts for `bodies` from a grid that has just found them
/// once: with at least 16 pair tests a sphere that first pass makes the
/// second a crowd's (a first test in single precision, eight pairs at a
/// time). Returns both passes' contacts.
fn twice(bodies: &Bodies) -> [Vec<lerpit::sim::Contact>; 2] {
    let mut grid = Grid::new();
    let mut found = [Vec::new(), Vec::new()];
    for f in &mut found {
        grid.build(bodies, CellLayout::of(bodies));
        grid.find_contacts(bodies, f);
    }
    found
}

/// A crowd in a corner: spheres of mixed radii within 0.25 m of the
/// origin, some past the walls, so most pairs are close.
fn cornered() -> impl Strategy<Value = Body> {
    prop_oneof![0.002..0.01f64, 0.01..0.03f64].prop_flat_map(|r| {
        let c = || prop_oneof![4 => 0.0..0.25f64, 1 => -0.03..0.0f64, 1 => Just(r)];
        (c(), c(), c()).prop_map(move |(x, y, z)| body(Vec3::new(x, y, z), r))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn a_crowded_grid_finds_the_contacts_all_pairs_finds(
        spheres in prop::collection::vec(cornered(), 150..400),
    ) {
        let bodies: Bodies = spheres.into_iter().collect();
        let (expected, _) = contacts(BroadPhase::AllPairs, &bodies);
        let (_, tests) = contacts(BroadPhase::Grid, &bodies);
        prop_assume!(tests >= 16 * bodies.len() as u64, "{} tests a sphere", tests / bodies.len() as u64);
        for found in twice(&bodies) {
            prop_assert_eq!(bits(&found), bits(&expected));
        }
    }
}

#[test]
fn a_crowded_grid_keeps_pairs_closer_than_single_precision_sees() {
    // Spheres of radius 1/16 m: one pair exactly touching (not a contact),
    // one closer by 2^-40 m, which single precision rounds to touching
    // too; 120 spheres heaped in a corner make the world a crowd.
    let r = 0.0625;
    let mut bodies: Bodies = [
        body(Vec3::new(0.25, 0.75, 0.75), r),
        body(Vec3::new(0.375, 0.75, 0.75), r),
        body(Vec3::new(0.5, 0.5, 0.75), r),
        body(Vec3::new(0.625 - 2f64.powi(-40), 0.5, 0.75), r),
    ]
    .into_iter()
    .collect();
    for k in 0..120 {
        let t = k as f64 / 120.0;
        bodies.push(body(Vec3::new(0.1 + 0.01 * t, 0.1, 0.1 + 0.02 * t), 0.01));
    }
    let (expected, tests) = contacts(BroadPhase::Grid, &bodies);
    assert!(
        tests >= 16 * bodies.len() as u64,
        "{tests} tests: not a crowd"
    );
    assert!(
        expected.iter().any(|c| (c.i, c.j) == (2, 3)),
        "the pair 2^-40 m closer than touching is a contact"
    );
    assert!(
        !expected.iter().any(|c| (c.i, c.j) == (0, 1)),
        "touching is not a contact"
    );
    let [first, crowded] = twice(&bodies);
    assert_eq!(bits(&first), bits(&expected));
    assert_eq!(bits(&crowded), bits(&expected));
}

#[test]
fn a_normal_s_zero_components_have_all_pairs_signs() {
    // Centres that share two coordinates, the first sphere of each pair in
    // the later cell (so the grid meets the pair from its second sphere):
    // the normal's other components are zeros whose sign must be
    // all-pairs' too. Cells are 1/9 wide.
    let bodies: Bodies = [
        body(Vec3::new(0.58, 0.5, 0.5), 0.05),
        body(Vec3::new(0.50, 0.5, 0.5), 0.05),
        body(Vec3::new(0.2, 0.38, 0.7), 0.05),
        body(Vec3::new(0.2, 0.30, 0.7), 0.05),
    ]
    .into_iter()
    .collect();
    let (expected, _) = contacts(BroadPhase::AllPairs, &bodies);
    let (found, _) = contacts(BroadPhase::Grid, &bodies);
    assert_eq!(expected.len(), 2, "two overlapping pairs");
    assert_eq!(bits(&found), bits(&expected));
}

#[test]
fn spheres_exactly_one_cell_apart_are_found() {
    // Diameter 0.1: ten cells would be exactly one diameter wide; touching
    // spheres straddling a cell boundary must still be found.
    let r = 0.05;
    let bodies: Bodies = [
        body(Vec3::new(0.3 - 1e-12, 0.5, 0.5), r),
        body(Vec3::new(0.4 - 2e-12, 0.5, 0.5), r),
        body(Vec3::new(0.5 - 3e-12, 0.5, 0.5), r),
    ]
    .into_iter()
    .collect();
    let (expected, _) = contacts(BroadPhase::AllPairs, &bodies);
    assert_eq!(expected.len(), 2, "the scene holds two overlapping pairs");
    assert_eq!(contacts(BroadPhase::Grid, &bodies).0, expected);
}

/// Many equal spheres filling 10% of the box, as the benchmark scene.
fn crowd(n: usize, seed: u64) -> Bodies {
    let r = (0.075 / (std::f64::consts::PI * n as f64)).cbrt();
    let mut state = seed;
    let mut next = move || {
        // SplitMix64: a fixed, dependency-free sequence for the test.
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let p = Vec3::new(next(), next(), next()) * (1.0 - 2.0 * r) + Vec3::splat(r);
            body(p, r)
        })
        .collect()
}

#[test]
fn grid_in_cell_order_matches_all_pairs_on_a_large_world() {
    let mut bodies = crowd(6000, 3);
    let mut grid = Grid::new();
    grid.build(&bodies, CellLayout::of(&bodies));
    grid.reorder_bodies(&mut bodies, &mut Vec::new());
    let mut found = Vec::new();
    let tests = grid.find_contacts(&bodies, &mut found);
    let (expected, all_tests) = contacts(BroadPhase::AllPairs, &bodies);
    assert!(!expected.is_empty(), "the crowd overlaps somewhere");
    assert_eq!(bits(&found), bits(&expected));
    assert!(
        tests * 100 < all_tests,
        "the grid makes {tests} pair tests, all-pairs {all_tests}"
    );
}

#[test]
fn reordering_keeps_every_sphere_and_its_scene_index() {
    let mut original = crowd(5000, 4);
    // Mixed radii and masses, so every array has to move.
    for k in 0..original.len() {
        original.radius[k] *= 1.0 - 0.1 * (k % 3) as f64;
        original.mass[k] = 1.0 + (k % 5) as f64;
        original.inverse_mass[k] = 1.0 / original.mass[k];
    }
    let mut bodies = original.clone();
    let mut grid = Grid::new();
    grid.build(&bodies, CellLayout::of(&bodies));
    grid.reorder_bodies(&mut bodies, &mut Vec::new());
    assert_ne!(
        bodies.id, original.id,
        "a random crowd is not in cell order"
    );
    for (k, &s) in bodies.id.iter().enumerate() {
        assert_eq!(bodies.get(k), original.get(s as usize), "slot {k}");
    }
    let in_scene_order: Vec<Body> = bodies.iter_scene_order().collect();
    assert_eq!(in_scene_order, original.iter().collect::<Vec<_>>());
}

#[test]
fn auto_resolves_by_sphere_count() {
    use lerpit::sim::broad_phase::AUTO_GRID_MIN_BODIES as n;
    assert_eq!(BroadPhase::Auto.resolve(n - 1), BroadPhase::AllPairs);
    assert_eq!(BroadPhase::Auto.resolve(n), BroadPhase::Grid);
    assert_eq!(BroadPhase::Grid.resolve(1), BroadPhase::Grid);
    assert_eq!(BroadPhase::AllPairs.resolve(1 << 20), BroadPhase::AllPairs);
    for m in BroadPhase::ALL {
        assert_eq!(m.name().parse(), Ok(m));
    }
    assert_eq!(BroadPhase::AllPairs.next(), BroadPhase::Grid);
    assert_eq!(BroadPhase::Auto.next(), BroadPhase::AllPairs);
}

#[test]
fn all_pairs_and_grid_agree_through_the_lessons_contacts() {
    let mut bodies: Bodies = Bodies::default();
    assert_eq!(all_pairs(&bodies, &mut Vec::new()), 0);
    bodies.push(body(Vec3::splat(0.5), 0.1));
    bodies.push(body(Vec3::new(0.5, 0.5, 0.6), 0.1));
    let (c, tests) = contacts(BroadPhase::Grid, &bodies);
    assert_eq!((c.len(), tests), (1, 1));
    assert_eq!(c[0].contact_normal, Vec3::Z);
    assert!((c[0].penetration - 0.1).abs() < 1e-15);
}
