//! Crowding: spheres that start piled on one another. A step keeps every
//! overlapping pair in its contact list (40 bytes each), so 20,000 bodies at
//! one point ask for 200 million contacts, 8 GB, in the first step. A scene
//! whose spheres start with more than [`MAX_CONTACTS_PER_SPHERE`]
//! overlapping pairs per sphere is refused when it is built, before any
//! step. No physical packing comes near: a sphere among equal ones touches
//! at most 12.
//!
//! The count stops as soon as it passes the limit, and keeps no contact
//! list: its memory is a few bytes a sphere whatever the crowding. Spheres
//! heaped by the million would take it billions of tests to get there, so
//! past a few tests a sphere it first asks a lower bound that one sort
//! finds (16 bytes a sphere): centres sharing a cube too small for two
//! spheres to sit apart in ([`pairs_in_shared_cells`]). Spheres
//! of any mix of sizes are found through a grid per size class (cells
//! `2^-k` m wide, at least one diameter of the spheres filed there): a
//! sphere looks for overlaps in the 27 cells around it in its own class and
//! in every coarser one, so each overlapping pair is met exactly once, from
//! the smaller sphere (or, between equals, from the earlier one). Like the
//! simulation's grid, the finest cells are limited to about four per
//! sphere. Each class keeps its centres and radii in cell order, so the
//! spheres of neighbouring cells are read from neighbouring memory. The
//! overlap test is the narrow phase's
//! ([`test_pair`](crate::sim::contact::test_pair)): centres closer than the
//! sum of the radii.

use crate::sim::{Bodies, Vec3};

/// Most overlapping pairs per sphere, on average, a scene may start with
/// (when it has pair collisions).
pub(crate) const MAX_CONTACTS_PER_SPHERE: u64 = 64;

/// Finest cells: at most this many per sphere (plus [`MIN_CELLS`]).
const MAX_CELLS_PER_SPHERE: usize = 4;
const MIN_CELLS: usize = 4096;
/// A size class with at most this many spheres is searched whole rather
/// than cell by cell.
const FEW: usize = 27;

/// What the count found.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Overlaps {
    /// Overlapping pairs counted: all of them, or once past the limit,
    /// those counted so far (just past it) or the shared cubes' bound
    /// (beyond it).
    pub pairs: u64,
    /// Whether the count passed the limit.
    pub exceeded: bool,
    /// The sphere with the most overlaps counted, and how many: all of
    /// them, or once past the limit at least that many.
    pub most: Option<(usize, u32)>,
}

/// One size class: the spheres whose diameter fits a cell `2^-k` wide (and
/// not one half as wide), sorted by cell, with their centres and radii
/// copied in that order so that a cell's spheres sit together in memory.
struct Class {
    k: u32,
    /// Scene index of each sphere of the class, by cell.
    id: Vec<u32>,
    position: Vec<Vec3>,
    radius: Vec<f64>,
    /// `start[c]..start[c + 1]` are the class's spheres in cell `c`; empty
    /// when the class is searched whole.
    start: Vec<u32>,
}

impl Class {
    fn new(k: u32, members: Vec<u32>, bodies: &Bodies) -> Self {
        let mut c = Class {
            k,
            id: members,
            position: Vec::new(),
            radius: Vec::new(),
            start: Vec::new(),
        };
        if c.id.len() > FEW {
            let cells = 1usize << (3 * k);
            let cell_of: Vec<usize> =
                c.id.iter()
                    .map(|&i| c.index(c.coords(bodies.position[i as usize])))
                    .collect();
            let mut start = vec![0u32; cells + 1];
            for &cell in &cell_of {
                start[cell + 1] += 1;
            }
            for k in 0..cells {
                start[k + 1] += start[k];
            }
            let mut at = start.clone();
            let mut id = vec![0u32; c.id.len()];
            for (&i, &cell) in c.id.iter().zip(&cell_of) {
                id[at[cell] as usize] = i;
                at[cell] += 1;
            }
            c.id = id;
            c.start = start;
        }
        c.position = c.id.iter().map(|&i| bodies.position[i as usize]).collect();
        c.radius = c.id.iter().map(|&i| bodies.radius[i as usize]).collect();
        c
    }

    fn per_axis(&self) -> usize {
        1 << self.k
    }

    fn coords(&self, p: Vec3) -> [usize; 3] {
        let n = self.per_axis();
        // `as` saturates: negative and NaN give 0.
        let axis = |x: f64| ((x * n as f64) as usize).min(n - 1);
        [axis(p.x), axis(p.y), axis(p.z)]
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        let n = self.per_axis();
        (x * n + y) * n + z
    }

    /// The ranges of the class's spheres that may touch a sphere of this
    /// class or a finer one centred at `p`: the 27 cells around it (runs
    /// of three along z), or the whole class.
    fn near(&self, p: Vec3, mut visit: impl FnMut(std::ops::Range<usize>) -> bool) -> bool {
        if self.start.is_empty() {
            return visit(0..self.id.len());
        }
        let [x, y, z] = self.coords(p);
        let last = self.per_axis() - 1;
        let (z0, z1) = (z.saturating_sub(1), (z + 1).min(last));
        for cx in x.saturating_sub(1)..=(x + 1).min(last) {
            for cy in y.saturating_sub(1)..=(y + 1).min(last) {
                let from = self.start[self.index([cx, cy, z0])] as usize;
                let to = self.start[self.index([cx, cy, z1]) + 1] as usize;
                if visit(from..to) {
                    return true;
                }
            }
        }
        false
    }
}

/// The finest class spheres of `radius` may be filed in: cells `2^-k` wide
/// with `2^-k >= 2 radius`, `k <= finest`.
fn class_of(radius: f64, finest: u32) -> u32 {
    let diameter = 2.0 * radius * (1.0 + 1e-9);
    let mut k = 0;
    while k < finest && 0.5f64.powi(k as i32 + 1) >= diameter {
        k += 1;
    }
    k
}

/// Count the overlapping pairs of `bodies`, stopping once past `limit`.
pub(crate) fn count_overlaps(bodies: &Bodies, limit: u64) -> Overlaps {
    let n = bodies.len();
    let budget = MAX_CELLS_PER_SPHERE * n + MIN_CELLS;
    let mut finest = 0u32;
    while 8usize.pow(finest + 1) <= budget && finest < 20 {
        finest += 1;
    }
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); finest as usize + 1];
    for (i, &r) in bodies.radius.iter().enumerate() {
        members[class_of(r, finest) as usize].push(i as u32);
    }
    // Coarsest first.
    let classes: Vec<Class> = members
        .into_iter()
        .enumerate()
        .filter(|(_, m)| !m.is_empty())
        .map(|(k, m)| Class::new(k as u32, m, bodies))
        .collect();

    let mut found = Overlaps {
        pairs: 0,
        exceeded: false,
        most: None,
    };
    let mut neighbours = vec![0u32; n];
    // Tests after which a count still under the limit asks the bound of
    // shared cells whether it can stop (`pairs_in_shared_cells`).
    let (mut tests, mut bound_asked) = (0u64, false);
    let ask_after = SHARED_CELLS_AFTER_TESTS_A_SPHERE * n as u64 + (1 << 20);
    for (own, class) in classes.iter().enumerate() {
        for a in 0..class.id.len() {
            if !bound_asked && tests > ask_after {
                bound_asked = true;
                if let Some(mut shared) =
                    pairs_in_shared_cells(bodies, limit).filter(|s| s.exceeded)
                {
                    // Each is a lower bound: the larger says more.
                    shared.most = match (shared.most, found.most) {
                        (Some(cube), Some(counted)) if counted.1 > cube.1 => Some(counted),
                        (cube, counted) => cube.or(counted),
                    };
                    return shared;
                }
            }
            let (p, r) = (class.position[a], class.radius[a]);
            for (c, other) in classes[..=own].iter().enumerate() {
                let exceeded = other.near(p, |range| {
                    // A pair within a class is met from its earlier sphere.
                    let range = if c == own {
                        range.start.max(a + 1)..range.end
                    } else {
                        range
                    };
                    tests += range.len() as u64;
                    for b in range {
                        // The narrow phase's test (`contact::test_pair`).
                        let reach = r + other.radius[b];
                        if other.position[b].distance_squared(p) >= reach * reach {
                            continue;
                        }
                        found.pairs += 1;
                        for s in [class.id[a], other.id[b]].map(|s| s as usize) {
                            neighbours[s] += 1;
                            if found.most.is_none_or(|(_, m)| neighbours[s] > m) {
                                found.most = Some((s, neighbours[s]));
                            }
                        }
                        if found.pairs > limit {
                            return true;
                        }
                    }
                    false
                });
                if exceeded {
                    found.exceeded = true;
                    return found;
                }
            }
        }
    }
    found
}

/// Tests a sphere, on average, after which the count asks
/// [`pairs_in_shared_cells`] whether the spheres are past the limit: about
/// what the bound's sort costs (10,000,000 spheres heaped in the box:
/// 0.7 s of sorting against 6 s for 32 tests a sphere, where each overlap
/// found adds to a count kept for every sphere), so that the bound adds
/// little to a count that goes on to the end, and refuses spheres heaped
/// by the million in one sort instead of billions of tests.
const SHARED_CELLS_AFTER_TESTS_A_SPHERE: u64 = 4;

/// A lower bound on the overlapping pairs, in one sort: cut space into
/// cubes whose diagonal is under the smallest sum of two radii, and any
/// two centres in one cube overlap, so each cube of `k` centres holds at
/// least `k (k - 1) / 2` pairs; `exceeded` when they pass `limit`. Its
/// `most` is a sphere of the fullest cube, which overlaps at least the
/// others there. `None` when the cubes would be too many to number
/// (spheres under a micrometre in a box a metre wide).
fn pairs_in_shared_cells(bodies: &Bodies, limit: u64) -> Option<Overlaps> {
    let r_min = bodies.radius.iter().copied().fold(f64::INFINITY, f64::min);
    let lo = bodies
        .position
        .iter()
        .copied()
        .fold(Vec3::INFINITY, Vec3::min);
    let hi = bodies
        .position
        .iter()
        .copied()
        .fold(Vec3::NEG_INFINITY, Vec3::max);
    // A hair under 2 r_min / sqrt(3): `floor` is exact, but `p - lo` and
    // the division round, by at most 2^-31 of a cube while `across` is
    // under 2^21 cubes (the keys' 21 bits a coordinate), far under the
    // 1e-9 taken off.
    let side = 2.0 * r_min / 3f64.sqrt() * (1.0 - 1e-9);
    let across = ((hi - lo) / side).max_element();
    if !(side > 0.0 && across < f64::from(1u32 << 21)) {
        return None;
    }
    let mut keys: Vec<(u64, u32)> = bodies
        .position
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let c = ((p - lo) / side).floor().to_array().map(|x| x as u64);
            ((c[0] << 42) | (c[1] << 21) | c[2], i as u32)
        })
        .collect();
    keys.sort_unstable();
    let mut found = Overlaps {
        pairs: 0,
        exceeded: false,
        most: None,
    };
    for cube in keys.chunk_by(|a, b| a.0 == b.0) {
        let k = cube.len() as u64;
        found.pairs += k * (k - 1) / 2;
        if k > 1 && found.most.is_none_or(|(_, m)| u64::from(m) < k - 1) {
            found.most = Some((cube[0].1 as usize, (k - 1) as u32));
        }
    }
    found.exceeded = found.pairs > limit;
    Some(found)
}

/// The most bodies that share one exact centre, and that centre.
pub(crate) fn largest_shared_point(bodies: &Bodies) -> Option<(Vec3, usize)> {
    let mut keys: Vec<[u64; 3]> = bodies
        .position
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect();
    keys.sort_unstable();
    keys.chunk_by(|a, b| a == b)
        .max_by_key(|run| run.len())
        .map(|run| (Vec3::from_array(run[0].map(f64::from_bits)), run.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Body;
    use crate::sim::broad_phase::all_pairs;
    use proptest::prelude::*;

    fn bodies(spheres: &[([f64; 3], f64)]) -> Bodies {
        let mut b = Bodies::default();
        for &(p, radius) in spheres {
            b.push(Body {
                position: Vec3::from_array(p),
                velocity: Vec3::ZERO,
                radius,
                mass: 1.0,
            });
        }
        b
    }

    #[test]
    fn coincident_spheres_pass_the_limit_and_are_found_at_their_point() {
        let b = bodies(&vec![([0.5, 0.5, 0.5], 0.01); 300]);
        let o = count_overlaps(&b, 64 * 300);
        assert!(o.exceeded && o.pairs == 64 * 300 + 1, "{o:?}");
        assert_eq!(largest_shared_point(&b), Some((Vec3::splat(0.5), 300)));
        let o = count_overlaps(&b, u64::MAX);
        assert_eq!(o.pairs, crate::sim::broad_phase::all_pairs_tests(300));
        assert_eq!(o.most.map(|m| m.1), Some(299));
    }

    #[test]
    fn thousands_of_spheres_of_three_sizes_count_as_all_pairs() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let spheres: Vec<([f64; 3], f64)> = (0..3000)
            .map(|k| {
                let r = [0.004, 0.02, 0.15][k % 3];
                let p = [0; 3].map(|_| r + (1.0 - 2.0 * r) * rng.random::<f64>());
                (p, r)
            })
            .collect();
        let b = bodies(&spheres);
        let mut contacts = Vec::new();
        all_pairs(&b, &mut contacts);
        assert!(contacts.len() > 1000, "a test with overlaps");
        let o = count_overlaps(&b, u64::MAX);
        assert_eq!(o.pairs, contacts.len() as u64);
        let mut per_sphere = vec![0usize; b.len()];
        for c in &contacts {
            per_sphere[c.i as usize] += 1;
            per_sphere[c.j as usize] += 1;
        }
        let most = per_sphere.iter().copied().max();
        assert_eq!(o.most.map(|m| m.1 as usize), most);
    }

    #[test]
    fn spheres_heaped_by_the_hundred_thousand_are_refused_by_the_bound_of_shared_cells() {
        // 100,000 spheres 0.1 m in radius in the box: each overlaps about
        // 6,500 of the 41,000 its 27 cells hold, so the count would test
        // about 800 a sphere before passing the limit; past 4 it takes
        // the shared cubes' bound, which passes the limit at once. The
        // exact count stops one pair past the limit; the bound's total is
        // beyond it, and its fullest cube's sphere overlaps at least the
        // cube's others.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let r = 0.1;
        let spheres: Vec<([f64; 3], f64)> = (0..100_000)
            .map(|_| ([0; 3].map(|_| r + (1.0 - 2.0 * r) * rng.random::<f64>()), r))
            .collect();
        let b = bodies(&spheres);
        let limit = 64 * 100_000;
        let o = count_overlaps(&b, limit);
        assert!(o.exceeded && o.pairs > 2 * limit, "{o:?}");
        let (s, m) = o.most.expect("a fullest cube");
        let p = b.position[s];
        let overlapping = (0..b.len())
            .filter(|&j| j != s && b.position[j].distance(p) < 2.0 * r)
            .count();
        assert!(
            overlapping >= m as usize && m > 200,
            "{overlapping} against {m}"
        );
    }

    #[test]
    fn spheres_just_apart_across_a_cube_s_diagonal_share_no_cube() {
        // Two spheres of radius r whose centres are 2 r apart, or a hair
        // more, along the diagonal of a cube of side 2 r / sqrt(3) (the
        // bound's cube, less its hair), from anywhere in a cube measured
        // from the lowest centre: the cubes count a pair only where the
        // narrow phase's test finds one. A cube even 1e-4 of its side too
        // wide would put about one in ten thousand of them in one cube.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let lo = [0.01, 0.02, 0.03];
        let mut wrong = 0;
        for _ in 0..100_000 {
            let r = 0.001 + 0.05 * rng.random::<f64>();
            let side = 2.0 * r / 3f64.sqrt();
            let k = (0.3 / side).ceil();
            let u = rng.random::<f64>();
            let a = lo.map(|l| l + (k + u) * side);
            let step = side * (1.0 + 1e-12 * rng.random::<f64>());
            let b = a.map(|x| x + step);
            let spheres = [(a, r), (b, r), (lo, 2.0 * r)];
            let bodies = bodies(&spheres);
            let mut contacts = Vec::new();
            all_pairs(&bodies, &mut contacts);
            let shared = pairs_in_shared_cells(&bodies, u64::MAX).expect("cubes to number");
            wrong += usize::from(shared.pairs > contacts.len() as u64);
        }
        assert_eq!(wrong, 0);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The shared cubes' count is a lower bound on the overlapping
        /// pairs, and its fullest cube's on the most a sphere overlaps,
        /// for spheres heaped in a corner or spread over the box.
        #[test]
        fn the_shared_cells_never_count_more_than_all_pairs(
            spheres in prop::collection::vec(
                ((0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64), prop_oneof![
                    0.001..0.01f64, 0.01..0.1f64, 0.1..0.5f64
                ]),
                1..160,
            ),
            heap in prop_oneof![Just(1.0), 0.001..0.1f64],
        ) {
            let b = bodies(
                &spheres
                    .iter()
                    .map(|&((x, y, z), r)| ([x, y, z].map(|c| c * heap), r))
                    .collect::<Vec<_>>(),
            );
            let mut contacts = Vec::new();
            all_pairs(&b, &mut contacts);
            let shared = pairs_in_shared_cells(&b, u64::MAX).expect("cubes to number");
            prop_assert!(shared.pairs <= contacts.len() as u64);
            prop_assert!(!shared.exceeded);
            if let Some((s, m)) = shared.most {
                let own = contacts
                    .iter()
                    .filter(|c| c.i as usize == s || c.j as usize == s)
                    .count();
                prop_assert!(own >= m as usize, "{} against {}", own, m);
            }
            let limit = contacts.len() as u64;
            prop_assert!(!pairs_in_shared_cells(&b, limit).unwrap().exceeded);
        }

        /// Every overlapping pair is counted once, for any mix of sizes:
        /// the count equals all-pairs' contacts.
        #[test]
        fn the_count_equals_all_pairs(
            spheres in prop::collection::vec(
                ((0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64), prop_oneof![
                    0.001..0.01f64, 0.01..0.1f64, 0.1..0.5f64
                ]),
                0..120,
            )
        ) {
            let b = bodies(
                &spheres.iter().map(|&((x, y, z), r)| ([x, y, z], r)).collect::<Vec<_>>(),
            );
            let mut contacts = Vec::new();
            all_pairs(&b, &mut contacts);
            let o = count_overlaps(&b, u64::MAX);
            prop_assert_eq!(o.pairs, contacts.len() as u64);
            prop_assert!(!o.exceeded);
        }
    }
}
