//! A fingerprint of a world's state: the exact bits of every position and
//! velocity, in scene order (whatever slots the spheres occupy), the step
//! count and the time, the impulses the support pass carries into the
//! next step (none without it), and each sphere's time at rest while
//! spheres sleep (`sleep.rs`), hashed with XXH3. Equal hashes mean (with
//! overwhelming probability) bit-identical states.

use super::World;
use xxhash_rust::xxh3::Xxh3;

pub fn state_hash(world: &World) -> u64 {
    let mut h = Xxh3::new();
    h.update(&world.steps.to_le_bytes());
    h.update(&world.time.to_bits().to_le_bytes());
    let b = &world.bodies;
    for i in b.slots_in_scene_order() {
        for v in [b.position[i], b.velocity[i]] {
            for c in v.to_array() {
                h.update(&c.to_bits().to_le_bytes());
            }
        }
    }
    world.carried_impulses().hash_into(&mut h);
    // The times at rest, once the world sleeps spheres (before, all 0).
    if b.rest.iter().any(|&r| r != 0.0) {
        for i in b.slots_in_scene_order() {
            h.update(&b.rest[i].to_bits().to_le_bytes());
        }
    }
    h.digest()
}

impl World {
    /// See [`state_hash`].
    pub fn state_hash(&self) -> u64 {
        state_hash(self)
    }
}
