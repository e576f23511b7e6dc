//! The spheres. `Bodies` keeps what every step touches (positions,
//! velocities, radii, masses and inverse masses) in parallel arrays, so the
//! stages walk memory in order; `Body` is the one-sphere view used to build
//! and report a world.
//!
//! Slots and scene order: index `k` of every array is one *slot*, and
//! `id[k]` is the scene index of the sphere in it (its place in the scene's
//! bodies and spawns). A world starts with `id[k] == k`. Large worlds
//! (see `world::SPATIAL_ORDER_MIN_BODIES`) move spheres between slots every
//! step so that spheres close in space sit close in memory
//! ([`Bodies::reorder`]); reports and the state hash go through `id`, so
//! what a reader sees is always in scene order.

use super::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One sphere, as a scene file or a report sees it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// Centre, m.
    pub position: Vec3,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Radius, m.
    pub radius: f64,
    /// Mass, kg (> 0).
    pub mass: f64,
}

/// All spheres of a world, structure-of-arrays. Index `k` is the same slot
/// in every array; `id[k]` is the scene index of the sphere in slot `k`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bodies {
    pub position: Vec<Vec3>,
    pub velocity: Vec<Vec3>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub inverse_mass: Vec<f64>,
    /// Scene index of the sphere in each slot.
    pub id: Vec<u32>,
}

/// Memory [`Bodies::reorder`] may gather into: any idle buffer of at least
/// 24 bytes per sphere, 8-byte aligned (a world lends its contact buffer,
/// which sits empty at that point of the step), so the spatial order costs
/// no second copy of the bodies.
pub struct Spare<'a> {
    memory: &'a mut [std::mem::MaybeUninit<u64>],
}

impl<'a> Spare<'a> {
    pub fn new(memory: &'a mut [std::mem::MaybeUninit<u64>]) -> Self {
        Self { memory }
    }

    /// The memory seen as `n` values of `T` (at most 8-byte aligned).
    fn slice<T>(&mut self, n: usize) -> &mut [std::mem::MaybeUninit<T>] {
        assert!(
            std::mem::align_of::<T>() <= 8 && n * std::mem::size_of::<T>() <= self.memory.len() * 8,
            "the spare memory is too small for the reorder"
        );
        // SAFETY: aligned and in bounds (asserted); `MaybeUninit` has no
        // invalid bit patterns, and the borrow of `self` keeps it exclusive.
        unsafe { std::slice::from_raw_parts_mut(self.memory.as_mut_ptr().cast(), n) }
    }
}

/// Slots per parallel task when gathering.
const GATHER_CHUNK: usize = 4096;

/// `v[k] = old v[order[k]]`, through `spare`, in parallel.
fn permute<T: Copy + Send + Sync>(v: &mut [T], order: &[u32], spare: &mut Spare) {
    let buffer = spare.slice::<T>(v.len());
    buffer
        .par_iter_mut()
        .zip(order.par_iter())
        .with_min_len(GATHER_CHUNK)
        .for_each(|(b, &k)| {
            b.write(v[k as usize]);
        });
    v.par_iter_mut()
        .zip(buffer.par_iter())
        .with_min_len(GATHER_CHUNK)
        .for_each(|(x, b)| {
            // SAFETY: the gather above wrote every entry.
            *x = unsafe { b.assume_init() };
        });
}

/// Whether every entry has the bits of the first.
fn all_equal(v: &[f64]) -> bool {
    let Some(first) = v.first().map(|x| x.to_bits()) else {
        return true;
    };
    v.par_iter()
        .with_min_len(GATHER_CHUNK)
        .all(|x| x.to_bits() == first)
}

impl Bodies {
    pub fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inverse_mass: Vec::with_capacity(n),
            id: Vec::with_capacity(n),
        }
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn push(&mut self, body: Body) {
        self.position.push(body.position);
        self.velocity.push(body.velocity);
        self.radius.push(body.radius);
        self.mass.push(body.mass);
        self.inverse_mass.push(1.0 / body.mass);
        self.id.push(self.id.len() as u32);
    }

    pub fn get(&self, i: usize) -> Body {
        Body {
            position: self.position[i],
            velocity: self.velocity[i],
            radius: self.radius[i],
            mass: self.mass[i],
        }
    }

    /// The spheres in slot order.
    pub fn iter(&self) -> impl Iterator<Item = Body> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// `slot[s]`: the slot holding the sphere of scene index `s`.
    pub fn slots_in_scene_order(&self) -> Vec<usize> {
        let mut slot = vec![0; self.len()];
        for (k, &s) in self.id.iter().enumerate() {
            slot[s as usize] = k;
        }
        slot
    }

    /// The spheres in scene order, whatever slots they occupy.
    pub fn iter_scene_order(&self) -> impl Iterator<Item = Body> + '_ {
        self.slots_in_scene_order().into_iter().map(|k| self.get(k))
    }

    /// Move the spheres so that slot `k` holds the sphere of scene index
    /// `ids[k]` (`ids` a permutation of the current ids): puts back the slot
    /// order of a saved state. Allocates its own spare memory.
    pub fn reorder_to_ids(&mut self, ids: &[u32]) {
        assert_eq!(ids.len(), self.len(), "a reorder moves every sphere");
        let slot = self.slots_in_scene_order();
        let order: Vec<u32> = ids.iter().map(|&s| slot[s as usize] as u32).collect();
        let mut memory = vec![std::mem::MaybeUninit::<u64>::uninit(); 3 * self.len()];
        self.reorder(&order, &mut Spare::new(&mut memory));
    }

    /// The largest radius, or 0 for no bodies.
    pub fn max_radius(&self) -> f64 {
        self.radius
            .par_iter()
            .with_min_len(GATHER_CHUNK)
            .copied()
            .reduce(|| 0.0, f64::max)
    }

    /// Move the spheres between slots: slot `k` receives the sphere that was
    /// in slot `order[k]`. `order` must be a permutation of `0..len`; each
    /// array is gathered into `spare` and copied back. An array whose
    /// entries are all equal (the radii and masses of equal spheres) is left
    /// alone: moving it would change nothing.
    pub fn reorder(&mut self, order: &[u32], spare: &mut Spare) {
        assert_eq!(order.len(), self.len(), "a reorder moves every sphere");
        permute(&mut self.position, order, spare);
        permute(&mut self.velocity, order, spare);
        for v in [&mut self.radius, &mut self.mass, &mut self.inverse_mass] {
            if !all_equal(v) {
                permute(v, order, spare);
            }
        }
        permute(&mut self.id, order, spare);
    }
}

impl FromIterator<Body> for Bodies {
    fn from_iter<I: IntoIterator<Item = Body>>(iter: I) -> Self {
        let mut bodies = Bodies::default();
        for b in iter {
            bodies.push(b);
        }
        bodies
    }
}
