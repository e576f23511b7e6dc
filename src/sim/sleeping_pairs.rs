//! The pairs of two sleepers, kept while both sleep, so that the narrow
//! phase does not look for them again.
//!
//! Sleepers do not move (`sleep.rs`), so the pairs two of them make are
//! the same from one sub-step to the next. The narrow phase is told which
//! spheres are *quiet* (asleep, their pairs with other sleepers kept here)
//! and tests no pair of two quiet spheres; the sleeping rules read the kept
//! pairs instead ([`SleepingPairs::slots`]). A sphere that has just fallen
//! asleep is not quiet until the next touch has kept its pairs, from a
//! narrow phase that found them. A sleeper that wakes gives its kept pairs
//! back to the step's lists, in their places, each with the contact the
//! narrow phase finds for it (`contact::test_pair_within`, the narrow
//! phases' own test). So the lists the solvers read, and every bit of the
//! state, are the same as with the narrow phase finding every pair.
//!
//! The pairs are kept by the spheres' scene ids, so the order of the slots
//! (which a large world sorts every sub-step, and a caller may put back)
//! does not matter. What they were found for is kept as a fingerprint: the
//! sleepers' ids, centres and radii, and the margin of the narrow phase.
//! When a caller has changed any of it (putting back an earlier state,
//! say), the fingerprint differs and the kept pairs are dropped; that
//! sub-step's narrow phase then finds every pair, and the touch keeps them
//! again.

use super::contact::test_pair_within;
use super::sleep::{LINK_CHUNK, Touch, is_asleep, mark_higher, remove_at};
use super::{Bodies, Contact, Vec3};
use rayon::prelude::*;

/// Spheres per parallel task.
const CHUNK: usize = 4096;

/// The pairs of two sleepers, and what they were found for.
#[derive(Clone, Debug, Default)]
pub(crate) struct SleepingPairs {
    /// The pairs, by scene id.
    pairs: Vec<(u32, u32)>,
    /// Per scene id: higher than a sphere a kept pair links it to (it
    /// rests on something, `sleep::mark_higher`).
    higher: Vec<bool>,
    /// Scene ids of the spheres fallen asleep since the last touch: their
    /// pairs are not kept yet.
    fresh: Vec<u32>,
    /// The fingerprint of the sleepers the pairs were kept for, and the
    /// bits of the narrow phase's margin and of `up` (`higher`'s).
    print: (u64, u64, [u64; 3]),
    /// This sub-step: the margin, each scene id's slot, which slots are
    /// quiet, which rest on something by a kept pair, and the pairs by
    /// slot (as `pairs`, once asked for).
    margin: f64,
    slot_of: Vec<u32>,
    /// Whether `slot_of` holds this sub-step's slots.
    mapped: bool,
    quiet: Vec<bool>,
    rests: Vec<bool>,
    slots: Vec<(u32, u32)>,
    slots_ready: bool,
}

impl SleepingPairs {
    /// The spheres with these scene ids have just fallen asleep.
    pub(crate) fn fell_asleep(&mut self, ids: &[u32]) {
        self.fresh.extend_from_slice(ids);
    }

    /// Before a narrow phase of `bodies` that finds the pairs within
    /// `margin` (m) of touching, under gravity along `-up` (zero without
    /// gravity): which slots are quiet, or `None` when none is (the narrow
    /// phase then finds every pair, and the kept ones are dropped if they
    /// were found for other sleepers or another `up`).
    pub(crate) fn quiet(&mut self, bodies: &Bodies, margin: f64, up: Vec3) -> Option<&[bool]> {
        self.margin = margin;
        self.slots.clear();
        self.slots_ready = false;
        self.rests.clear();
        self.mapped = self.map_slots(bodies);
        if !self.mapped {
            self.forget();
            return None;
        }
        self.quiet.clear();
        self.quiet.par_extend(
            bodies
                .rest
                .par_iter()
                .with_min_len(CHUNK)
                .map(|&r| is_asleep(r)),
        );
        for &id in &self.fresh {
            if let Some(&s) = self.slot_of.get(id as usize) {
                self.quiet[s as usize] = false;
            }
        }
        let quiet = &self.quiet;
        let print = (
            fingerprint(bodies, |k| quiet[k]),
            margin.to_bits(),
            up.to_array().map(f64::to_bits),
        );
        if print != self.print {
            self.forget();
            return None;
        }
        if !self.quiet.contains(&true) {
            return None;
        }
        let higher = &self.higher;
        self.rests.par_extend(
            bodies
                .id
                .par_iter()
                .with_min_len(CHUNK)
                .map(|&id| higher.get(id as usize).copied().unwrap_or(false)),
        );
        Some(&self.quiet)
    }

    /// Per slot, this sub-step: whether the sphere rests on something by a
    /// kept pair (higher than the other sphere); empty when none is kept.
    pub(crate) fn rests(&self) -> &[bool] {
        &self.rests
    }

    /// The kept pairs by slot, this sub-step (none when
    /// [`SleepingPairs::quiet`] said `None`).
    pub(crate) fn slots(&mut self) -> &[(u32, u32)] {
        if !self.slots_ready {
            let slot_of = &self.slot_of;
            self.slots.clear();
            self.slots.extend(
                self.pairs
                    .iter()
                    .map(|&(a, b)| (slot_of[a as usize], slot_of[b as usize])),
            );
            self.slots_ready = true;
        }
        &self.slots
    }

    /// After the touch of this sub-step (`sleep::touch`), which `touched`
    /// the sleepers, under gravity along `-up` (as [`SleepingPairs::quiet`]
    /// was told): the kept pairs with a sphere now awake go to `back`,
    /// each with the contact the narrow phase finds for it, for the caller
    /// to put back in `lists` (the overlapping contacts, then, with a
    /// margin, those within it) in their places by `(i, j)`; the pairs of
    /// two sleepers in `lists` are kept, and taken out of them. Every
    /// sleeper is then quiet until it wakes.
    pub(crate) fn keep(
        &mut self,
        bodies: &Bodies,
        lists: [&mut Vec<Contact>; 2],
        touched: Touch,
        up: Vec3,
        back: &mut Vec<Contact>,
    ) {
        let rest = &bodies.rest;
        let asleep = |k: u32| is_asleep(rest[k as usize]);
        if !self.mapped && !self.map_slots(bodies) {
            // Scene ids that are not the slots' numbers: nothing is kept,
            // and the pairs of two sleepers are dropped.
            self.forget();
            self.fresh.clear();
            for list in lists {
                list.retain(|c| !(asleep(c.i) && asleep(c.j)));
            }
            return;
        }
        let mut changed = false;
        if touched != Touch::Some(0) && !self.pairs.is_empty() {
            self.slots();
            let (slots, margin) = (&self.slots, self.margin);
            let mut k = 0;
            self.pairs.retain(|_| {
                let (a, b) = slots[k];
                k += 1;
                let stays = touched != Touch::All && asleep(a) && asleep(b);
                if !stays {
                    let (i, j) = (a.min(b) as usize, a.max(b) as usize);
                    back.extend(test_pair_within(bodies, i, j, margin));
                }
                stays
            });
            changed = k != self.pairs.len();
        }
        for list in lists {
            // Found in parallel, in the list's order, then taken out.
            let both: Vec<usize> = list
                .par_iter()
                .with_min_len(LINK_CHUNK)
                .enumerate()
                .filter(|(_, c)| asleep(c.i) && asleep(c.j))
                .map(|(at, _)| at)
                .collect();
            if both.is_empty() {
                continue;
            }
            changed = true;
            self.pairs.extend(both.iter().map(|&at| {
                let c = &list[at];
                (bodies.id[c.i as usize], bodies.id[c.j as usize])
            }));
            remove_at(list, both.into_iter());
        }
        if changed {
            // By the rule the touch marks the listed pairs with, per slot,
            // then by scene id.
            let slot_of = &self.slot_of;
            let slots = self
                .pairs
                .par_iter()
                .with_min_len(CHUNK)
                .map(|&(a, b)| (slot_of[a as usize], slot_of[b as usize]));
            let by_slot = mark_higher(&mut self.rests, &bodies.position, slots, up, |_| true);
            self.higher.clear();
            self.higher.resize(bodies.len(), false);
            for (&id, &h) in bodies.id.iter().zip(by_slot) {
                self.higher[id as usize] = h;
            }
        }
        if changed || touched != Touch::Some(0) || !self.fresh.is_empty() {
            self.print = (
                fingerprint(bodies, |k| is_asleep(rest[k])),
                self.margin.to_bits(),
                up.to_array().map(f64::to_bits),
            );
        }
        self.slots.clear();
        self.slots_ready = false;
        self.rests.clear();
        self.mapped = false;
        self.fresh.clear();
    }

    /// Each scene id's slot, into `slot_of`; false when the ids are not
    /// the slots' numbers in some order.
    fn map_slots(&mut self, bodies: &Bodies) -> bool {
        self.slot_of.clear();
        self.slot_of.resize(bodies.len(), u32::MAX);
        for (k, &id) in bodies.id.iter().enumerate() {
            match self.slot_of.get_mut(id as usize) {
                Some(s) if *s == u32::MAX => *s = k as u32,
                _ => return false,
            }
        }
        true
    }

    /// Keep nothing.
    pub(crate) fn forget(&mut self) {
        self.pairs.clear();
        self.higher.clear();
        self.print = (0, 0, [0; 3]);
        self.slots.clear();
        self.rests.clear();
    }

    /// How many pairs are kept.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.pairs.len()
    }
}

/// A fingerprint of the spheres `pick` picks: the sum of a hash of each
/// one's scene id, centre and radius, so that the order of the slots does
/// not change it.
fn fingerprint(bodies: &Bodies, pick: impl Fn(usize) -> bool + Sync) -> u64 {
    let mix = |h: u64, x: u64| (h ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29);
    (0..bodies.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&k| pick(k))
        .map(|k| {
            let p = bodies.position[k];
            [p.x, p.y, p.z, bodies.radius[k]].iter().fold(
                mix(0x243F_6A88_85A3_08D3, u64::from(bodies.id[k])),
                |h, x| mix(h, x.to_bits()),
            )
        })
        .reduce(|| 0, u64::wrapping_add)
}

#[cfg(test)]
mod tests {
    use crate::sim::{Bodies, Body, BroadPhase, Vec3, World, WorldConfig};

    /// Columns of three spheres on the floor, `nx` by `nz`, in blocks of
    /// two by two, each beside the next within the support pass's margin
    /// (pairs of sleepers that touch and that do not) and the blocks a
    /// diameter apart, and a sphere thrown up over every seventh column,
    /// which lands after the columns have fallen asleep and wakes the
    /// block it strikes.
    fn columns(nx: usize, nz: usize, broad_phase: BroadPhase) -> World {
        let r = 0.006;
        let at = |k: usize| 0.05 + 2.0005 * r * k as f64 + 2.0 * r * (k / 2) as f64;
        let mut bodies: Vec<Body> = Vec::new();
        for k in 0..nx * nz {
            let (x, z) = (at(k % nx), at(k / nx));
            for level in 0..3 {
                bodies.push(Body {
                    position: Vec3::new(x, r + 1.999 * r * level as f64, z),
                    velocity: Vec3::ZERO,
                    radius: r,
                    mass: 1.0,
                });
            }
            if k % 7 == 3 {
                bodies.push(Body {
                    position: Vec3::new(x + 0.3 * r, 0.3, z),
                    velocity: Vec3::new(0.0, 3.5 + 0.01 * (k % 5) as f64, 0.0),
                    radius: r,
                    mass: 1.0,
                });
            }
        }
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            broad_phase,
            support: true,
            sleep: true,
            ..WorldConfig::default()
        };
        World::new(config, bodies.into_iter().collect::<Bodies>())
    }

    fn same(a: &World, b: &World, at: &str) {
        assert_eq!(a.bodies.id, b.bodies.id, "{at}: slots");
        assert_eq!(a.bodies.position, b.bodies.position, "{at}: positions");
        assert_eq!(a.bodies.velocity, b.bodies.velocity, "{at}: velocities");
        let bits = |w: &World| {
            w.bodies
                .rest
                .iter()
                .map(|r| r.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(a), bits(b), "{at}: times at rest");
        assert!(a.contacts() == b.contacts(), "{at}: contacts");
        assert!(
            a.carried_impulses() == b.carried_impulses(),
            "{at}: carried impulses"
        );
        assert_eq!(
            a.last.max_overlap.to_bits(),
            b.last.max_overlap.to_bits(),
            "{at}: deepest overlap"
        );
    }

    /// `steps` steps of `kept` and of `found`, which forgets its kept pairs
    /// before each, with the same bits after each.
    fn step_together(kept: &mut World, found: &mut World, steps: std::ops::Range<u32>, case: &str) {
        for step in steps {
            found.forget_sleeping_pairs();
            kept.step();
            found.step();
            same(kept, found, &format!("{case}, step {step}"));
        }
    }

    fn sphere(x: f64, y: f64, vx: f64, r: f64) -> Body {
        Body {
            position: Vec3::new(x, y, 0.5),
            velocity: Vec3::new(vx, 0.0, 0.0),
            radius: r,
            mass: 1.0,
        }
    }

    #[test]
    fn kept_pairs_keep_the_bits_at_the_edges() {
        let r = 0.05;
        // Without gravity or a margin: a sleeper struck wakes all, and
        // gives back a pair of two spheres exactly touching (a
        // penetration of 0), which the narrow phase lists with the
        // overlapping ones.
        let touching: Bodies = [
            sphere(0.15, 0.5, 0.25, r),
            sphere(0.5, 0.5, 0.0, r),
            sphere(0.6, 0.500000002083, 0.0, r),
        ]
        .into_iter()
        .collect();
        let (a, b) = (touching.position[1], touching.position[2]);
        let d2 = (b - a).length_squared();
        assert!(
            d2 < 4.0 * r * r && 2.0 * r - d2.sqrt() == 0.0,
            "exactly touching"
        );
        for method in [BroadPhase::AllPairs, BroadPhase::Grid] {
            let config = WorldConfig {
                dt: 1.0 / 60.0,
                gravity: Vec3::ZERO,
                broad_phase: method,
                sleep: true,
                ..WorldConfig::default()
            };
            let mut kept = World::new(config.clone(), touching.clone());
            let mut found = World::new(config, touching.clone());
            step_together(
                &mut kept,
                &mut found,
                1..200,
                &format!("touching, {method}"),
            );
        }
        // A stack asleep without gravity, then gravity: the same sleepers,
        // which rest on nothing they rested on before (as a state put back
        // from a step under gravity).
        let stack: Bodies = [
            sphere(0.5, r, 0.0, r),
            sphere(0.5, 3.0 * r - 1e-4, 0.0, r),
            sphere(0.2, 0.8, 0.3, r),
        ]
        .into_iter()
        .collect();
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            gravity: Vec3::ZERO,
            sleep: true,
            ..WorldConfig::default()
        };
        let (mut kept, mut found) = (
            World::new(config.clone(), stack.clone()),
            World::new(config, stack),
        );
        step_together(&mut kept, &mut found, 1..60, "stack");
        assert_eq!(
            (kept.last.asleep, kept.sleeping_pairs_kept()),
            (2, 1),
            "the stack sleeps"
        );
        for w in [&mut kept, &mut found] {
            w.config.gravity = Vec3::new(0.0, -9.81, 0.0);
            let under = w.config.clone();
            w.restore_slept_under(&under);
        }
        step_together(&mut kept, &mut found, 60..70, "stack under gravity");
        // Columns without gravity: touched, every sleeper wakes and gives
        // back its pairs, the deepest overlap among them.
        let mut kept = columns(40, 35, BroadPhase::Grid);
        for (k, v) in kept.bodies.velocity.iter_mut().enumerate() {
            *v = Vec3::X * if k % 37 == 0 { 0.06 } else { 0.0 };
        }
        kept.config.gravity = Vec3::ZERO;
        let mut found = kept.clone();
        step_together(&mut kept, &mut found, 1..200, "columns without gravity");
        // Scene ids that are not the slots' numbers: nothing is kept.
        let mut kept = columns(4, 4, BroadPhase::Grid);
        let mut found = columns(4, 4, BroadPhase::Grid);
        step_together(&mut kept, &mut found, 1..40, "columns");
        assert!(kept.sleeping_pairs_kept() > 0);
        for w in [&mut kept, &mut found] {
            w.bodies.id[1] = w.bodies.id[0];
        }
        step_together(&mut kept, &mut found, 40..50, "columns, ids repeated");
        assert_eq!(kept.sleeping_pairs_kept(), 0);
    }

    #[test]
    fn kept_pairs_of_sleepers_give_the_bits_of_finding_every_pair_even_after_a_state_is_put_back() {
        // Against a world that forgets its kept pairs before every step
        // (its narrow phase finds every pair), step by step: columns that
        // fall asleep, spheres that land on them and wake them (their
        // kept pairs go back to the lists), and then the bodies put back
        // to an earlier state with other sleepers, in another slot order.
        for (nx, nz, method) in [
            (40, 35, BroadPhase::Grid),
            (12, 10, BroadPhase::Grid),
            (12, 10, BroadPhase::AllPairs),
        ] {
            let (mut kept, mut found) = (columns(nx, nz, method), columns(nx, nz, method));
            let case = format!("{} spheres, {method}", kept.bodies.len());
            let (mut most, mut given_back, mut fewer_tests) = (0, false, false);
            let mut earlier = None;
            let mut asleep_at_40 = 0;
            for step in 1..=110 {
                if step == 80 {
                    let back: Bodies = earlier.clone().expect("kept at step 40");
                    kept.bodies = back.clone();
                    found.bodies = back;
                }
                let before = kept.sleeping_pairs_kept();
                found.forget_sleeping_pairs();
                kept.step();
                found.step();
                same(&kept, &found, &format!("{case}, step {step}"));
                let now = kept.sleeping_pairs_kept();
                most = most.max(now);
                given_back |= now < before && kept.last.asleep > 0;
                fewer_tests |= kept.last.pair_tests < found.last.pair_tests;
                if step == 40 {
                    earlier = Some(kept.bodies.clone());
                    asleep_at_40 = kept.last.asleep;
                }
                if step == 79 {
                    assert!(
                        kept.last.asleep < asleep_at_40,
                        "{case}: the landings woke spheres ({} asleep, {asleep_at_40} at step 40)",
                        kept.last.asleep
                    );
                }
            }
            let columns = nx * nz;
            assert!(most >= 2 * columns, "{case}: at most {most} pairs kept");
            assert!(given_back, "{case}: no kept pair went back to the lists");
            if method == BroadPhase::Grid {
                assert!(fewer_tests, "{case}: the kept pairs were tested anyway");
            }
        }
    }
}
