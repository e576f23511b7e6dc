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
use std::ops::{BitOr, BitXor};

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

/// Whether every entry has the bits of the first (`bits`: `f64::to_bits`
/// or `f32::to_bits`). Each chunk ors together how far each entry's bits
/// are from the first's, with no branch, so the loop runs in vector
/// instructions.
fn all_equal<T: Copy + Send + Sync, B>(v: &[T], bits: impl Fn(T) -> B + Sync) -> bool
where
    B: Copy + Default + Eq + Sync + BitOr<Output = B> + BitXor<Output = B>,
{
    let Some(&first) = v.first() else {
        return true;
    };
    let first = bits(first);
    v.par_chunks(GATHER_CHUNK).all(|chunk| {
        let apart = chunk
            .iter()
            .fold(B::default(), |apart, &x| apart | (bits(x) ^ first));
        apart == B::default()
    })
}

/// Whether every sphere of `bodies` has the mass and the inverse mass of
/// the first, to the bit.
pub(crate) fn masses_equal(bodies: &Bodies) -> bool {
    all_equal(&bodies.mass, f64::to_bits) && all_equal(&bodies.inverse_mass, f64::to_bits)
}

impl Bodies {
    /// Move the spheres between slots: slot `k` receives the sphere that
    /// was in slot `order[k]` (`order` a permutation of `0..len`), through
    /// `spare` (at least 24 bytes a sphere, 8-byte aligned). An array whose
    /// entries are all equal (the radii and masses of equal spheres) is
    /// left alone: moving it would change nothing. The centres move last,
    /// so `spare` ends holding a copy of them in their new slots.
    /// With `masses_equal` (every mass, and every inverse mass, has the
    /// bits of the first), the masses are left alone unchecked.
    fn reorder(&mut self, order: &[u32], spare: &mut [u8], masses_equal: bool) {
        assert_eq!(order.len(), self.len(), "a reorder moves every sphere");
        permute(&mut self.velocity, order, spare);
        let arrays = [
            (&mut self.radius, false),
            (&mut self.mass, masses_equal),
            (&mut self.inverse_mass, masses_equal),
        ];
        for (v, equal) in arrays {
            if !equal && !all_equal(v, f64::to_bits) {
                permute(v, order, spare);
            }
        }
        permute(&mut self.id, order, spare);
        if !all_equal(&self.rest, f32::to_bits) {
            permute(&mut self.rest, order, spare);
        }
        permute(&mut self.position, order, spare);
    }

    /// Move the spheres so that slot `k` holds the sphere of scene index
    /// `ids[k]` (`ids` a permutation of the current ids): puts back the slot
    /// order of a saved state. Allocates its own spare memory.
    pub fn reorder_to_ids(&mut self, ids: &[u32]) {
        assert_eq!(ids.len(), self.len(), "a reorder moves every sphere");
        let slot = self.slots_in_scene_order();
        let order: Vec<u32> = ids.iter().map(|&s| slot[s as usize] as u32).collect();
        let mut memory = vec![Vec3::ZERO; self.len()];
        self.reorder(&order, bytemuck::cast_slice_mut(&mut memory), false);
    }
}

impl Grid {
    /// Move the spheres of `bodies` into cell order (slot `k` gets the
    /// `k`-th sphere of the sorted order). Needs a [`Grid::build`] of these
    /// bodies first; the grid stays valid for them afterwards. The memory
    /// of `contacts` is lent to the move, so it must not hold anything
    /// still needed: its entries are left meaningless as contacts. Returns
    /// whether the spheres moved; if so, the first bytes of `contacts`
    /// hold a copy of the centres (`bodies.position`), seen as raw words.
    pub fn reorder_bodies(&mut self, bodies: &mut Bodies, contacts: &mut Vec<Contact>) -> bool {
        self.reorder_bodies_knowing(bodies, contacts, false)
    }

    /// [`Grid::reorder_bodies`], told whether every mass, and every
    /// inverse mass, has the bits of the first ([`masses_equal`]): then
    /// they are left where they are, unchecked.
    pub(crate) fn reorder_bodies_knowing(
        &mut self,
        bodies: &mut Bodies,
        contacts: &mut Vec<Contact>,
        masses_equal: bool,
    ) -> bool {
        let Some(order) = self.order_to_apply(bodies) else {
            return false;
        };
        let needed = (bodies.len() * size_of::<Vec3>()).div_ceil(size_of::<Contact>());
        if contacts.len() < needed {
            contacts.resize(needed, Contact::zeroed());
        }
        bodies.reorder(
            order,
            bytemuck::cast_slice_mut(contacts.as_mut_slice()),
            masses_equal,
        );
        self.set_in_cell_order();
        true
    }
}

#[cfg(test)]
mod tests {
    use super::{GATHER_CHUNK, all_equal};
    use crate::sim::{Bodies, Body, Vec3};

    #[test]
    fn arrays_are_equal_only_when_every_entry_has_the_same_bits() {
        let n = 3 * GATHER_CHUNK + 5;
        let mut radii = vec![0.25_f64; n];
        assert!(all_equal(&radii, f64::to_bits));
        assert!(all_equal(&radii[..0], f64::to_bits), "empty");
        radii[n - 1] = 0.25 + f64::EPSILON;
        assert!(
            !all_equal(&radii, f64::to_bits),
            "the last entry of the last chunk"
        );
        let mut zeros = vec![0.0_f32; n];
        assert!(all_equal(&zeros, f32::to_bits));
        zeros[GATHER_CHUNK] = -0.0;
        assert!(!all_equal(&zeros, f32::to_bits), "-0 has other bits than 0");
        let nans = vec![f32::NAN; n];
        assert!(
            all_equal(&nans, f32::to_bits),
            "the same NaN has the same bits"
        );
    }

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
