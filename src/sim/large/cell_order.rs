//! Moving spheres between slots: slot `k` receives the sphere that was in
//! slot `order[k]`. A large world does it every sub-step with the grid's
//! cell order ([`Grid::reorder_bodies`]); the visualiser's history does it
//! to put back the slots of a saved state ([`Bodies::reorder_to_ids`]).
//!
//! Each array is gathered into spare memory and copied back, in parallel.
//! The spare memory is the world's contact buffer, which sits idle at that
//! point of the step, so the order costs no second copy of the bodies: it
//! is seen as raw words through `bytemuck`, as [`Contact`] is plain data.

use crate::sim::grid::Grid;
use crate::sim::{Bodies, Contact, Vec3};
use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

/// Slots per parallel task when gathering.
const GATHER_CHUNK: usize = 4096;

/// `v[k] = old v[order[k]]`, gathered into `spare` (at least as many bytes
/// as `v`, 8-byte aligned) and copied back.
fn permute<T: Pod + Send + Sync>(v: &mut [T], order: &[u32], spare: &mut [u8]) {
    let buffer: &mut [T] = bytemuck::cast_slice_mut(&mut spare[..size_of_val(v)]);
    buffer
        .par_iter_mut()
        .zip(order.par_iter())
        .with_min_len(GATHER_CHUNK)
        .for_each(|(b, &k)| *b = v[k as usize]);
    v.par_chunks_mut(GATHER_CHUNK)
        .zip(buffer.par_chunks(GATHER_CHUNK))
        .for_each(|(x, b)| x.copy_from_slice(b));
}

/// Whether every entry has the bits of the first.
fn all_equal<T: Pod + Send + Sync>(v: &[T]) -> bool {
    let Some(first) = v.first().map(|x| bytemuck::bytes_of(x)) else {
        return true;
    };
    v.par_iter()
        .with_min_len(GATHER_CHUNK)
        .all(|x| bytemuck::bytes_of(x) == first)
}

impl Bodies {
    /// Move the spheres between slots: slot `k` receives the sphere that
    /// was in slot `order[k]` (`order` a permutation of `0..len`), through
    /// `spare` (at least 24 bytes a sphere, 8-byte aligned). An array whose
    /// entries are all equal (the radii and masses of equal spheres) is
    /// left alone: moving it would change nothing.
    fn reorder(&mut self, order: &[u32], spare: &mut [u8]) {
        assert_eq!(order.len(), self.len(), "a reorder moves every sphere");
        permute(&mut self.position, order, spare);
        permute(&mut self.velocity, order, spare);
        for v in [&mut self.radius, &mut self.mass, &mut self.inverse_mass] {
            if !all_equal(v) {
                permute(v, order, spare);
            }
        }
        permute(&mut self.id, order, spare);
        if !all_equal(&self.rest) {
            permute(&mut self.rest, order, spare);
        }
    }

    /// Move the spheres so that slot `k` holds the sphere of scene index
    /// `ids[k]` (`ids` a permutation of the current ids): puts back the slot
    /// order of a saved state. Allocates its own spare memory.
    pub fn reorder_to_ids(&mut self, ids: &[u32]) {
        assert_eq!(ids.len(), self.len(), "a reorder moves every sphere");
        let slot = self.slots_in_scene_order();
        let order: Vec<u32> = ids.iter().map(|&s| slot[s as usize] as u32).collect();
        let mut memory = vec![Vec3::ZERO; self.len()];
        self.reorder(&order, bytemuck::cast_slice_mut(&mut memory));
    }
}

impl Grid {
    /// Move the spheres of `bodies` into cell order (slot `k` gets the
    /// `k`-th sphere of the sorted order). Needs a [`Grid::build`] of these
    /// bodies first; the grid stays valid for them afterwards. The memory
    /// of `contacts` is lent to the move, so it must not hold anything
    /// still needed: its entries are left meaningless.
    pub fn reorder_bodies(&mut self, bodies: &mut Bodies, contacts: &mut Vec<Contact>) {
        let Some(order) = self.order_to_apply(bodies) else {
            return;
        };
        let needed = (bodies.len() * size_of::<Vec3>()).div_ceil(size_of::<Contact>());
        if contacts.len() < needed {
            contacts.resize(needed, Contact::zeroed());
        }
        bodies.reorder(order, bytemuck::cast_slice_mut(contacts.as_mut_slice()));
        self.set_in_cell_order();
    }
}

#[cfg(test)]
mod tests {
    use crate::sim::{Bodies, Body, Vec3};

    #[test]
    fn every_array_of_a_sphere_moves_with_it() {
        let mut bodies: Bodies = (0..5)
            .map(|k| Body {
                position: Vec3::splat(0.1 * k as f64),
                velocity: Vec3::X * k as f64,
                radius: 0.01 * (k + 1) as f64,
                mass: 1.0 + k as f64,
            })
            .collect();
        bodies.rest = vec![0.0, 0.5, f32::INFINITY, 0.25, 0.0];
        let before = bodies.clone();
        let ids = [3, 0, 4, 2, 1];
        bodies.reorder_to_ids(&ids);
        assert_eq!(bodies.id, ids);
        for (k, &s) in ids.iter().enumerate() {
            let s = s as usize;
            assert_eq!(bodies.get(k), before.get(s));
            assert_eq!(bodies.inverse_mass[k], before.inverse_mass[s]);
            assert_eq!(bodies.rest[k].to_bits(), before.rest[s].to_bits());
        }
    }
}
