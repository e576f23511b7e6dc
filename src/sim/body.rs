//! The spheres. `Bodies` keeps what every step touches (positions,
//! velocities, radii, masses and inverse masses) in parallel arrays, so the
//! stages walk memory in order; `Body` is the one-sphere view used to build
//! and report a world.
//!
//! Slots and scene order: index `k` of every array is one *slot*, and
//! `id[k]` is the scene index of the sphere in it (its place in the scene's
//! bodies and spawns). A world starts with `id[k] == k`. Large worlds
//! (see `large::SPATIAL_ORDER_MIN_BODIES`) move spheres between slots every
//! step so that spheres close in space sit close in memory
//! (`large/cell_order.rs`); reports and the state hash go through `id`, so
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
    /// How long each sphere has been at rest, s, while the world sleeps
    /// spheres (`sleep.rs`; 0 otherwise); infinite for a sleeping one.
    pub rest: Vec<f32>,
}

/// Spheres per parallel task in the reductions.
const REDUCE_CHUNK: usize = 4096;

impl Bodies {
    pub(crate) fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inverse_mass: Vec::with_capacity(n),
            id: Vec::with_capacity(n),
            rest: Vec::with_capacity(n),
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
        self.rest.push(0.0);
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
    pub(crate) fn slots_in_scene_order(&self) -> Vec<usize> {
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

    /// The smallest radius, or infinity for no bodies.
    pub(crate) fn min_radius(&self) -> f64 {
        self.radius
            .par_iter()
            .with_min_len(REDUCE_CHUNK)
            .copied()
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// The largest radius, or 0 for no bodies.
    pub(crate) fn max_radius(&self) -> f64 {
        self.radius
            .par_iter()
            .with_min_len(REDUCE_CHUNK)
            .copied()
            .reduce(|| 0.0, f64::max)
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
