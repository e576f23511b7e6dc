//! Seeded random placement of spheres: the "bunch of smaller spheres at
//! random positions and velocities" of the gravity and collisions lessons.
//!
//! Every random choice comes from one PCG-64 generator seeded by the scene,
//! drawn in a fixed order (for each sphere: radius, position, direction,
//! speed), so a scene and a seed always give the same bodies. Unless a spawn
//! allows overlaps, a sphere is placed only where it touches no sphere placed
//! before it (rejection sampling over a hash grid of cells one diameter
//! wide); a spawn that cannot find room is an error, not a silent shortfall.

use super::config::{Choice, UnknownChoice};
use super::{Bodies, Body, Vec3, thousands};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Deserialize;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt;

/// How a spawned sphere's mass follows its size. Its kinds, without their
/// numbers, are [`MassLawKind`]: `volume` and `constant` in scene files.
#[derive(Clone, Copy, Debug, PartialEq, strum::EnumDiscriminants)]
#[strum_discriminants(
    name(MassLawKind),
    derive(
        Hash,
        Deserialize,
        strum::VariantArray,
        strum::IntoStaticStr,
        strum::Display,
        strum::EnumString,
        strum::EnumMessage
    ),
    strum(serialize_all = "kebab-case"),
    serde(try_from = "String")
)]
pub enum MassLaw {
    /// `m = density * (4/3) pi r^3`, density in kg/m^3.
    Volume { density: f64 },
    /// Every sphere has this mass, kg.
    Constant { mass: f64 },
}

impl Choice for MassLawKind {
    const KIND: &'static str = "mass law";
}

impl TryFrom<String> for MassLawKind {
    type Error = UnknownChoice;
    fn try_from(name: String) -> Result<Self, UnknownChoice> {
        Self::parse(&name)
    }
}

impl MassLaw {
    pub(crate) fn mass(self, radius: f64) -> f64 {
        match self {
            MassLaw::Volume { density } => density * 4.0 / 3.0 * PI * radius.powi(3),
            MassLaw::Constant { mass } => mass,
        }
    }
}

/// `count` spheres with radius uniform in `radius`, speed uniform in `speed`
/// and direction uniform on the sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct Spawn {
    pub count: usize,
    /// `[min, max]`, m.
    pub radius: [f64; 2],
    /// `[min, max]`, m/s.
    pub speed: [f64; 2],
    pub mass_law: MassLaw,
    /// Allow spheres to start overlapping (the solver separates them).
    pub overlap: bool,
}

/// Attempts to place one sphere before the spawn is declared too full.
pub(crate) const PLACEMENT_ATTEMPTS: usize = 2000;
/// How much of the box [`PLACEMENT_ATTEMPTS`] tries a sphere fill with
/// equal spheres before one finds no room (measured: 100,000 spheres fit
/// at 27.5% and not at 28%, 1,000 not at 27%).
pub(crate) const PLACED_EQUAL_SPHERES: f64 = 0.27;
/// No arrangement of random spheres fills more of the box than random close
/// packing does.
pub(crate) const RANDOM_CLOSE_PACKING: f64 = 0.64;
/// Equal spheres placed one after another at random places where they
/// overlap nothing jam at this fraction of the space (random sequential
/// addition, 0.3841 in three dimensions; less in a box, whose walls keep
/// centres a radius away): a box cannot take more of them this way.
pub(crate) const RANDOM_SEQUENTIAL_JAMMING: f64 = 0.385;

#[derive(Clone, Debug, PartialEq)]
pub enum SpawnError {
    /// Index of the spawn, how many it asked for, how many were placed.
    CannotFit {
        spawn: usize,
        count: usize,
        placed: usize,
    },
    /// The spheres' volume alone exceeds what the placement can hold:
    /// `limit` is [`RANDOM_CLOSE_PACKING`], or for equal spheres in an
    /// empty box [`RANDOM_SEQUENTIAL_JAMMING`].
    TooDense {
        spawn: usize,
        count: usize,
        fraction: f64,
        limit: f64,
    },
}

impl fmt::Display for SpawnError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SpawnError::CannotFit { count, placed, .. } => {
                let spheres = if *count == 1 { "sphere" } else { "spheres" };
                write!(
                    f,
                    "cannot fit {} non-overlapping {spheres} in the box: found room for {} \
                     (use fewer or smaller spheres, or set overlap = true)",
                    thousands(*count as u64),
                    thousands(*placed as u64)
                )?;
                if *count > 1 {
                    write!(
                        f,
                        "; random places without overlap run out long before the box is \
                         full: {PLACEMENT_ATTEMPTS} tries a sphere fit equal spheres up to \
                         about {:.0}% of it",
                        PLACED_EQUAL_SPHERES * 100.0
                    )?;
                }
                Ok(())
            }
            SpawnError::TooDense {
                count,
                fraction,
                limit,
                ..
            } => write!(
                f,
                "{} spheres of at least the minimum radius would fill {:.0}% of the box, \
                 beyond {}",
                thousands(*count as u64),
                fraction * 100.0,
                packing_limit(*limit)
            ),
        }
    }
}

impl std::error::Error for SpawnError {}

/// What a spawn's `limit` is, with its figure.
pub(crate) fn packing_limit(limit: f64) -> String {
    if limit < RANDOM_CLOSE_PACKING {
        format!(
            "where equal spheres placed at random without overlapping jam ({:.1}%; \
             set overlap = true to start them overlapping)",
            limit * 100.0
        )
    } else {
        format!("random close packing ({:.0}%)", limit * 100.0)
    }
}

impl SpawnError {
    /// Index of the `[[spawn]]` entry at fault.
    pub(crate) fn spawn(&self) -> usize {
        match *self {
            SpawnError::CannotFit { spawn, .. } | SpawnError::TooDense { spawn, .. } => spawn,
        }
    }
}

/// Refuse, before anything is placed, a spawn whose spheres of at least
/// its minimum radius would fill more of the box than placement reaches:
/// random close packing, or for equal spheres alone in the box the point
/// where random placement jams. `bodies`: the scene has bodies of its own,
/// placed first.
pub(crate) fn check_packing(spawns: &[Spawn], bodies: bool) -> Result<(), SpawnError> {
    let mut placed_before = bodies;
    for (index, s) in spawns.iter().enumerate() {
        // A lone sphere meets none of its own spawn: whether it fits is
        // for the placement to find.
        if !s.overlap && s.count > 1 {
            let fraction = s.count as f64 * 4.0 / 3.0 * PI * s.radius[0].powi(3);
            let limit = if s.radius[0] == s.radius[1] && !placed_before {
                RANDOM_SEQUENTIAL_JAMMING
            } else {
                RANDOM_CLOSE_PACKING
            };
            if fraction > limit {
                return Err(SpawnError::TooDense {
                    spawn: index,
                    count: s.count,
                    fraction,
                    limit,
                });
            }
        }
        placed_before |= s.count > 0;
    }
    Ok(())
}

/// Append the spheres of `spawns` to `bodies`, in order, drawing from a
/// generator seeded with `seed`.
pub(crate) fn spawn_bodies(
    bodies: &mut Bodies,
    spawns: &[Spawn],
    seed: u64,
) -> Result<(), SpawnError> {
    spawn_bodies_telling(bodies, spawns, seed, &|_| {})
}

/// Spheres placed between two calls of [`spawn_bodies_telling`]'s
/// `placed_so_far`.
pub const PLACED_TOLD_EVERY: usize = 4096;

/// [`spawn_bodies`], telling `placed_so_far` how many spheres of the
/// spawns it has placed so far, after every [`PLACED_TOLD_EVERY`] of them
/// and once all are placed: a large scene near the packing limit takes
/// minutes.
pub(crate) fn spawn_bodies_telling(
    bodies: &mut Bodies,
    spawns: &[Spawn],
    seed: u64,
    placed_so_far: &dyn Fn(usize),
) -> Result<(), SpawnError> {
    let mut done = 0;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let spawned_r = spawns.iter().map(|s| s.radius[1]).fold(0.0, f64::max);
    let mut grid = Placed::new(spawned_r, bodies.max_radius().max(spawned_r));
    for i in 0..bodies.len() {
        grid.insert(bodies, i);
    }

    check_packing(spawns, !bodies.is_empty())?;
    for (index, s) in spawns.iter().enumerate() {
        for placed in 0..s.count {
            let radius = uniform(&mut rng, s.radius[0], s.radius[1]);
            let position = if s.overlap {
                random_position(&mut rng, radius)
            } else {
                (0..PLACEMENT_ATTEMPTS)
                    .map(|_| random_position(&mut rng, radius))
                    .find(|&p| !grid.overlaps(bodies, p, radius))
                    .ok_or(SpawnError::CannotFit {
                        spawn: index,
                        count: s.count,
                        placed,
                    })?
            };
            let direction = random_direction(&mut rng);
            let speed = uniform(&mut rng, s.speed[0], s.speed[1]);
            bodies.push(Body {
                position,
                velocity: at_speed(direction, speed),
                radius,
                mass: s.mass_law.mass(radius),
            });
            done += 1;
            if done % PLACED_TOLD_EVERY == 0 {
                placed_so_far(done);
            }
            grid.insert(bodies, bodies.len() - 1);
        }
    }
    if done % PLACED_TOLD_EVERY != 0 {
        placed_so_far(done);
    }
    Ok(())
}

fn uniform(rng: &mut Pcg64Mcg, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

fn random_position(rng: &mut Pcg64Mcg, r: f64) -> Vec3 {
    Vec3::new(
        uniform(rng, r, 1.0 - r),
        uniform(rng, r, 1.0 - r),
        uniform(rng, r, 1.0 - r),
    )
}

/// `direction` times `speed`, where a sphere at rest has +0 components: a
/// negative direction times 0 is -0, which would print as `-0.0`.
fn at_speed(direction: Vec3, speed: f64) -> Vec3 {
    if speed == 0.0 {
        Vec3::ZERO
    } else {
        direction * speed
    }
}

/// Uniform on the unit sphere, by rejection from the cube.
fn random_direction(rng: &mut Pcg64Mcg) -> Vec3 {
    loop {
        let u = Vec3::new(
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
        );
        let l2 = u.length_squared();
        if l2 > 1e-12 && l2 <= 1.0 {
            return u / l2.sqrt();
        }
    }
}

/// The spheres placed so far, for the overlap test of the next: those no
/// larger than any a spawn places in cells one such diameter wide, the
/// larger ones (a scene's big bodies) in cells of their own size, so that one
/// large body does not make every cell large and the placement quadratic.
struct Placed {
    /// Spheres up to this radius go in `small`.
    small_r: f64,
    small: HashGrid,
    large: HashGrid,
}

impl Placed {
    fn new(spawned_r: f64, max_r: f64) -> Self {
        Self {
            small_r: spawned_r,
            small: HashGrid::new(2.0 * spawned_r.max(1e-6)),
            large: HashGrid::new(2.0 * max_r.max(1e-6)),
        }
    }

    fn insert(&mut self, bodies: &Bodies, i: usize) {
        let grid = if bodies.radius[i] <= self.small_r {
            &mut self.small
        } else {
            &mut self.large
        };
        grid.insert(bodies.position[i], i);
    }

    /// Whether a sphere at `p` of radius `r` (at most a spawn's largest)
    /// overlaps one placed: in each grid, a sphere it touches lies in its
    /// cell or the next, both radii being at most half a cell.
    fn overlaps(&self, bodies: &Bodies, p: Vec3, r: f64) -> bool {
        self.small.overlaps(bodies, p, r) || self.large.overlaps(bodies, p, r)
    }
}

/// Cells one largest diameter wide: any overlapping sphere lies in one of
/// the 27 cells around a centre.
struct HashGrid {
    cell: f64,
    cells: HashMap<[i32; 3], Vec<u32>>,
}

impl HashGrid {
    fn new(cell: f64) -> Self {
        Self {
            cell,
            cells: HashMap::new(),
        }
    }

    fn key(&self, p: Vec3) -> [i32; 3] {
        (p / self.cell).floor().as_ivec3().to_array()
    }

    fn insert(&mut self, p: Vec3, i: usize) {
        self.cells.entry(self.key(p)).or_default().push(i as u32);
    }

    fn overlaps(&self, bodies: &Bodies, p: Vec3, r: f64) -> bool {
        let [x, y, z] = self.key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = self.cells.get(&[x + dx, y + dy, z + dz]) else {
                        continue;
                    };
                    for &k in list {
                        let k = k as usize;
                        let reach = r + bodies.radius[k];
                        if bodies.position[k].distance_squared(p) < reach * reach {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spawn(count: usize, r: f64, overlap: bool) -> Spawn {
        Spawn {
            count,
            radius: [r, r],
            speed: [0.5, 1.0],
            mass_law: MassLaw::Volume { density: 1000.0 },
            overlap,
        }
    }

    #[test]
    fn large_bodies_among_small_spheres_give_the_bodies_every_pair_would() {
        // The rule spelled out: each sphere tested against every one placed
        // before it, with the same draws in the same order.
        fn every_pair(bodies: &mut Bodies, spawns: &[Spawn], seed: u64) {
            let mut rng = Pcg64Mcg::seed_from_u64(seed);
            for s in spawns {
                for _ in 0..s.count {
                    let radius = uniform(&mut rng, s.radius[0], s.radius[1]);
                    let position = (0..PLACEMENT_ATTEMPTS)
                        .map(|_| random_position(&mut rng, radius))
                        .find(|&p| {
                            (0..bodies.len()).all(|k| {
                                let reach = radius + bodies.radius[k];
                                bodies.position[k].distance_squared(p) >= reach * reach
                            })
                        })
                        .unwrap();
                    let velocity =
                        random_direction(&mut rng) * uniform(&mut rng, s.speed[0], s.speed[1]);
                    bodies.push(Body {
                        position,
                        velocity,
                        radius,
                        mass: s.mass_law.mass(radius),
                    });
                }
            }
        }
        let body = |position: Vec3, radius: f64| Body {
            position,
            velocity: Vec3::ZERO,
            radius,
            mass: 1.0,
        };
        // A large body, one exactly as large as the largest spawned sphere
        // can be, and one between the two spawns' largest; the second
        // spawn's range reaches beyond the first's.
        let bodies = [
            body(Vec3::splat(0.5), 0.3),
            body(Vec3::splat(0.1), 0.02),
            body(Vec3::new(0.9, 0.1, 0.1), 0.015),
        ];
        let spawns = [
            Spawn {
                count: 1500,
                radius: [0.002, 0.01],
                ..spawn(0, 0.0, false)
            },
            Spawn {
                count: 500,
                radius: [0.005, 0.02],
                ..spawn(0, 0.0, false)
            },
        ];
        let mut placed: Bodies = bodies.into_iter().collect();
        spawn_bodies(&mut placed, &spawns, 4).unwrap();
        let mut expected: Bodies = bodies.into_iter().collect();
        every_pair(&mut expected, &spawns, 4);
        assert_eq!(placed.len(), 2003);
        assert_eq!(placed.position, expected.position);
        assert_eq!(placed.radius, expected.radius);
        assert_eq!(placed.velocity, expected.velocity);
    }

    #[test]
    fn spawned_spheres_lie_inside_the_box_without_overlap_at_their_speeds() {
        let mut b = Bodies::default();
        spawn_bodies(&mut b, &[spawn(300, 0.03, false)], 9).unwrap();
        assert_eq!(b.len(), 300);
        for i in 0..b.len() {
            let (x, r) = (b.position[i], b.radius[i]);
            assert!(x.min_element() >= r && x.max_element() <= 1.0 - r);
            let speed = b.velocity[i].length();
            assert!((0.5..=1.0 + 1e-12).contains(&speed), "speed {speed}");
            assert!((b.mass[i] - 1000.0 * 4.0 / 3.0 * PI * r.powi(3)).abs() < 1e-15);
            for j in 0..i {
                assert!(
                    b.position[j].distance(x) >= r + b.radius[j],
                    "{i} overlaps {j}"
                );
            }
        }
    }

    #[test]
    fn spheres_spawned_at_rest_have_no_negative_zero_in_their_velocity() {
        let mut b = Bodies::default();
        let at_rest = Spawn {
            speed: [0.0, 0.0],
            ..spawn(100, 0.02, false)
        };
        spawn_bodies(&mut b, &[at_rest], 5).unwrap();
        for v in &b.velocity {
            assert_eq!(v.to_array().map(f64::to_bits), [0; 3], "{v}");
        }
    }

    #[test]
    fn the_same_seed_places_the_same_spheres_and_another_seed_does_not() {
        let place = |seed| {
            let mut b = Bodies::default();
            spawn_bodies(&mut b, &[spawn(50, 0.02, false)], seed).unwrap();
            b
        };
        assert_eq!(place(3), place(3));
        assert_ne!(place(3).position, place(4).position);
    }

    #[test]
    fn a_spawn_without_room_says_how_many_fitted() {
        // 250 spheres of 0.07 m: 36% of the box, under the jamming limit,
        // more than random placement finds room for.
        let mut b = Bodies::default();
        let err = spawn_bodies(&mut b, &[spawn(250, 0.07, false)], 1).unwrap_err();
        let SpawnError::CannotFit { placed, count, .. } = err else {
            panic!("expected CannotFit, got {err:?}");
        };
        assert_eq!(count, 250);
        assert!(placed > 0 && placed < 250);
        // 400 (57%) are refused before any is placed: equal spheres placed
        // at random without overlap jam at 38%.
        let err = spawn_bodies(&mut Bodies::default(), &[spawn(400, 0.07, false)], 1).unwrap_err();
        assert!(
            matches!(err, SpawnError::TooDense { limit, .. } if limit == RANDOM_SEQUENTIAL_JAMMING),
            "{err:?}"
        );
        assert!(err.to_string().contains("jam (38.5%"), "{err}");
        // With overlaps allowed the same request is placed in full.
        let mut b = Bodies::default();
        spawn_bodies(&mut b, &[spawn(400, 0.07, true)], 1).unwrap();
        assert_eq!(b.len(), 400);
    }

    #[test]
    fn a_lone_sphere_fills_what_fits_it_and_no_more() {
        // 0.49 m: 49% of the box, beyond where many would jam, but alone it
        // fits, centred within 0.02 m of the middle.
        let mut b = Bodies::default();
        spawn_bodies(&mut b, &[spawn(1, 0.49, false)], 1).unwrap();
        assert_eq!(b.len(), 1);
        assert!((b.position[0] - Vec3::splat(0.5)).abs().max_element() <= 0.01 + 1e-12);
        // Beside a body it does not fit: placement says so.
        let mut b = Bodies::default();
        spawn_bodies(&mut b, &[spawn(1, 0.2, false)], 1).unwrap();
        let err = spawn_bodies(&mut b, &[spawn(1, 0.45, false)], 2).unwrap_err();
        assert_eq!(
            err.to_string(),
            "cannot fit 1 non-overlapping sphere in the box: found room for 0 (use fewer or \
             smaller spheres, or set overlap = true)"
        );
    }

    #[test]
    fn placing_tells_how_many_are_placed_every_few_thousand() {
        let told = std::cell::RefCell::new(Vec::new());
        let spawns = [spawn(6000, 0.002, false), spawn(3000, 0.002, true)];
        let mut b = Bodies::default();
        spawn_bodies_telling(&mut b, &spawns, 3, &|k| told.borrow_mut().push(k)).unwrap();
        assert_eq!(b.len(), 9000);
        assert_eq!(
            *told.borrow(),
            [PLACED_TOLD_EVERY, 2 * PLACED_TOLD_EVERY, 9000],
            "every few thousand, and all at the end"
        );
        // The same spheres as without telling.
        let mut quiet = Bodies::default();
        spawn_bodies(&mut quiet, &spawns, 3).unwrap();
        assert_eq!(quiet.position, b.position);
    }
}
