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

#[cfg(test)]
mod tests {
    use crate::sim::{Body, Vec3, World, WorldConfig};

    /// One field of a world changed in place.
    type Change = Box<dyn Fn(&mut World)>;

    #[test]
    fn one_bit_of_any_field_the_hash_covers_changes_it() {
        // Two spheres, one at rest on the floor long enough to have a time
        // at rest (so the times at rest are hashed), one in flight. Each
        // field the hash covers, one bit flipped at a time, gives another
        // hash; flipped back, the same. (The support pass's carried
        // impulses: `support.rs`.)
        let r = 0.05;
        let body = |position: Vec3, velocity: Vec3| Body {
            position,
            velocity,
            radius: r,
            mass: 1.0,
        };
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            sleep: true,
            ..WorldConfig::default()
        };
        let bodies = [
            body(Vec3::new(0.3, r, 0.6), Vec3::ZERO),
            body(Vec3::new(0.7, 0.5, 0.4), Vec3::new(0.3, 1.0, -0.2)),
        ];
        let mut w = World::new(config, bodies.into_iter().collect());
        w.run(10);
        assert!(w.bodies.rest[0] > 0.0 && w.bodies.rest[1] == 0.0);
        let hash = w.state_hash();
        let flip = |x: f64| f64::from_bits(x.to_bits() ^ 1);
        let mut changes: Vec<(String, Change)> = vec![
            ("steps".into(), Box::new(|w| w.steps ^= 1)),
            ("time".into(), Box::new(move |w| w.time = flip(w.time))),
        ];
        for k in 0..2 {
            for axis in 0..3 {
                changes.push((
                    format!("position {k}[{axis}]"),
                    Box::new(move |w| {
                        w.bodies.position[k][axis] = flip(w.bodies.position[k][axis])
                    }),
                ));
                changes.push((
                    format!("velocity {k}[{axis}]"),
                    Box::new(move |w| {
                        w.bodies.velocity[k][axis] = flip(w.bodies.velocity[k][axis])
                    }),
                ));
            }
            changes.push((
                format!("time at rest {k}"),
                Box::new(move |w| {
                    w.bodies.rest[k] = f32::from_bits(w.bodies.rest[k].to_bits() ^ 1)
                }),
            ));
        }
        for (field, change) in &changes {
            change(&mut w);
            assert_ne!(w.state_hash(), hash, "{field}");
            change(&mut w);
            assert_eq!(w.state_hash(), hash, "{field} back");
        }
        // Asleep: the time at rest of a sleeper.
        let rest = w.bodies.rest[0];
        w.bodies.rest[0] = crate::sim::sleep::ASLEEP;
        assert_ne!(w.state_hash(), hash, "asleep");
        w.bodies.rest[0] = rest;
        assert_eq!(w.state_hash(), hash);
    }
}
