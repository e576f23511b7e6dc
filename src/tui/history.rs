//! The step-back ring buffer: exact copies of the last states of a world.
//!
//! Owns the snapshots only; it never steps the world. A snapshot holds what
//! a step changes (positions, velocities, times at rest, time, step count,
//! the step's counters and the impulses the support pass carries); radii and masses
//! never change within a world, and the parameters are the user's live
//! choice, so stepping back keeps them. A
//! snapshot also notes the parameters of the step that reached it, so
//! that a step is described as it ran even after they changed.
//! Restoring copies the bits back, so a state reached by stepping back is
//! bit-for-bit the state the world had (same `state_hash`).
//!
//! Large worlds move spheres between slots every step (`sim::body`, slots
//! and scene order), so a snapshot also keeps which sphere each slot held:
//! stepping back puts the slots back in that order, and a trail follows one
//! sphere, not one slot.
//!
//! Capacity: [`STEPS`] snapshots, the current state included, unless that
//! many would exceed [`MEMORY_BUDGET`]; big worlds keep as many as fit the
//! budget (at least two, so one step back is always possible). At 60 bytes
//! a sphere, 600 steps fit for up to about 7,400 spheres; 100,000 spheres
//! keep 44 steps. The support pass's carried impulses (16 bytes a row)
//! count too: when they would take the snapshots past the budget, the
//! oldest go and the history keeps that many from then on.

use crate::sim::sleep::is_asleep;
use crate::sim::support::CarriedImpulses;
use crate::sim::{StepStats, Vec3, World, WorldConfig};
use std::collections::VecDeque;

/// Steps kept when the budget allows.
pub(crate) const STEPS: usize = 601;
/// Bytes the snapshots of one world may take.
pub(crate) const MEMORY_BUDGET: usize = 256 * 1024 * 1024;

#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    position: Vec<Vec3>,
    velocity: Vec<Vec3>,
    /// Scene index of the sphere in each slot.
    id: Vec<u32>,
    /// Each sphere's time at rest (`Bodies::rest`: infinite asleep).
    rest: Vec<f32>,
    /// Slot of each scene index; empty while every sphere is in its own
    /// slot.
    slot_of: Vec<u32>,
    time: f64,
    steps: u64,
    last: StepStats,
    /// The parameters in force when this state was recorded: those of the
    /// step that reached it.
    config: WorldConfig,
    /// The impulses the support pass carried into the next step
    /// (`World::carried_impulses`): none without it.
    carried: CarriedImpulses,
}

impl Snapshot {
    fn fill_from(&mut self, world: &World) {
        self.position.clear();
        self.position.extend_from_slice(&world.bodies.position);
        self.velocity.clear();
        self.velocity.extend_from_slice(&world.bodies.velocity);
        self.id.clear();
        self.id.extend_from_slice(&world.bodies.id);
        self.rest.clear();
        self.rest.extend_from_slice(&world.bodies.rest);
        self.slot_of.clear();
        if self.id.iter().enumerate().any(|(k, &s)| k != s as usize) {
            self.slot_of.resize(self.id.len(), 0);
            for (k, &s) in self.id.iter().enumerate() {
                self.slot_of[s as usize] = k as u32;
            }
        }
        self.time = world.time;
        self.steps = world.steps;
        self.last = world.last;
        self.config.clone_from(&world.config);
        self.carried.clone_from(world.carried_impulses());
    }
}

/// The kept state one step before the present (see [`History::previous`]),
/// in its own slot order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Previous<'a> {
    pub position: &'a [Vec3],
    pub velocity: &'a [Vec3],
    /// Each slot's time at rest (`Bodies::rest`).
    pub rest: &'a [f32],
    slot_of: &'a [u32],
}

impl Previous<'_> {
    /// Position and velocity of the sphere of scene index `id`.
    pub fn of(&self, id: u32) -> Option<(Vec3, Vec3)> {
        let slot = self.slot(id)?;
        Some((*self.position.get(slot)?, *self.velocity.get(slot)?))
    }

    /// Whether the sphere of scene index `id` was asleep (`sim::sleep`).
    pub fn was_asleep(&self, id: u32) -> bool {
        self.slot(id)
            .and_then(|slot| self.rest.get(slot))
            .is_some_and(|&r| is_asleep(r))
    }

    /// Whether any sphere was asleep.
    pub fn any_asleep(&self) -> bool {
        self.rest.iter().any(|&r| is_asleep(r))
    }

    /// The slot that held the sphere of scene index `id`.
    fn slot(&self, id: u32) -> Option<usize> {
        if self.slot_of.is_empty() {
            Some(id as usize)
        } else {
            self.slot_of.get(id as usize).map(|&s| s as usize)
        }
    }
}

#[derive(Clone, Debug)]
pub struct History {
    snapshots: VecDeque<Snapshot>,
    capacity: usize,
    /// While a search that may be undone runs ([`History::mark`]).
    marked: Option<Marked>,
}

/// The snapshots a [`History::mark`] found, kept whatever is recorded
/// after it: those still held are the oldest of `snapshots`, those pushed
/// out wait in `out`.
#[derive(Clone, Debug)]
struct Marked {
    /// Of the snapshots marked, how many `snapshots` still holds.
    held: usize,
    /// Those pushed out since, oldest first.
    out: Vec<Snapshot>,
    capacity: usize,
}

/// How many snapshots a world of `bodies` spheres keeps.
pub(crate) fn capacity_for(bodies: usize) -> usize {
    (MEMORY_BUDGET / snapshot_bytes(bodies)).clamp(2, STEPS)
}

/// The bytes the snapshots of a world of `bodies` spheres take after
/// `steps` steps (its first state and each step's, as many as it keeps),
/// without carried impulses.
pub(crate) fn bytes_after(bodies: usize, steps: usize) -> usize {
    steps.saturating_add(1).min(capacity_for(bodies)) * snapshot_bytes(bodies)
}

/// The bytes of one snapshot of `bodies` spheres, without carried impulses.
fn snapshot_bytes(bodies: usize) -> usize {
    bodies.max(1)
        * (2 * std::mem::size_of::<Vec3>()
            + 2 * std::mem::size_of::<u32>()
            + std::mem::size_of::<f32>())
}

impl History {
    /// A history holding `world`'s current state.
    pub fn new(world: &World) -> Self {
        let capacity = capacity_for(world.bodies.len());
        let mut h = Self {
            snapshots: VecDeque::with_capacity(capacity),
            capacity,
            marked: None,
        };
        h.record(world);
        h
    }

    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Snapshots held, the current state included.
    pub fn len(&self) -> usize {
        self.snapshots.len()
    }

    pub fn is_empty(&self) -> bool {
        self.snapshots.is_empty()
    }

    /// How many steps back are possible.
    pub fn steps_back(&self) -> usize {
        self.snapshots.len().saturating_sub(1)
    }

    /// Remember `world`'s state (after a step). The oldest goes when full;
    /// its buffers are reused.
    pub(crate) fn record(&mut self, world: &World) {
        let reused = if self.snapshots.len() >= self.capacity {
            self.push_out_oldest()
        } else {
            None
        };
        let mut snap = if let Some(snap) = reused {
            snap
        } else {
            Snapshot {
                position: Vec::with_capacity(world.bodies.len()),
                velocity: Vec::with_capacity(world.bodies.len()),
                id: Vec::with_capacity(world.bodies.len()),
                rest: Vec::with_capacity(world.bodies.len()),
                slot_of: Vec::new(),
                time: 0.0,
                steps: 0,
                last: StepStats::default(),
                config: world.config.clone(),
                carried: CarriedImpulses::default(),
            }
        };
        snap.fill_from(world);
        self.snapshots.push_back(snap);
        // The support pass's carried impulses count in the budget too:
        // the oldest go while they would exceed it.
        let fixed = snapshot_bytes(world.bodies.len());
        let carried = |s: &Snapshot| s.carried.len() * std::mem::size_of::<(u64, f64)>();
        let mut bytes: usize = self.snapshots.iter().map(|s| fixed + carried(s)).sum();
        if bytes > MEMORY_BUDGET && self.snapshots.len() > 2 {
            while bytes > MEMORY_BUDGET && self.snapshots.len() > 2 {
                bytes -= fixed + carried(self.snapshots.front().expect("more than two"));
                self.push_out_oldest();
            }
            // Kept from now on: what fits with the impulses.
            self.capacity = self.snapshots.len();
        }
    }

    /// Put `world` back to the state one step before the newest snapshot and
    /// forget the newest. Returns false (and changes nothing) at the start
    /// of the history.
    pub(crate) fn step_back(&mut self, world: &mut World) -> bool {
        if self.snapshots.len() < 2 {
            return false;
        }
        self.snapshots.pop_back();
        self.restore_newest(world);
        true
    }

    /// Take out the oldest snapshot; its buffers to reuse, unless a mark
    /// keeps it.
    fn push_out_oldest(&mut self) -> Option<Snapshot> {
        let old = self.snapshots.pop_front()?;
        match &mut self.marked {
            Some(m) if m.held > 0 => {
                m.held -= 1;
                m.out.push(old);
                None
            }
            _ => Some(old),
        }
    }

    /// Keep the snapshots held now, whatever is recorded after, until
    /// [`History::rewind`] or [`History::unmark`].
    pub(crate) fn mark(&mut self) {
        self.marked = Some(Marked {
            held: self.snapshots.len(),
            out: Vec::new(),
            capacity: self.capacity,
        });
    }

    /// Record as before the mark: what it kept and nothing else goes.
    pub(crate) fn unmark(&mut self) {
        self.marked = None;
    }

    /// Back to the snapshots of the mark, exactly: those recorded since
    /// are forgotten. Without a mark, nothing changes.
    pub(crate) fn rewind(&mut self) {
        let Some(m) = self.marked.take() else {
            return;
        };
        self.snapshots.truncate(m.held);
        for snap in m.out.into_iter().rev() {
            self.snapshots.push_front(snap);
        }
        self.capacity = m.capacity;
    }

    /// Put `world` back to the newest snapshot: the state before a step
    /// that was abandoned part-way.
    pub(crate) fn restore_newest(&self, world: &mut World) {
        let s = self.snapshots.back().expect("a history holds a state");
        if world.bodies.id != s.id {
            world.bodies.reorder_to_ids(&s.id);
        }
        world.bodies.position.copy_from_slice(&s.position);
        world.bodies.velocity.copy_from_slice(&s.velocity);
        world.bodies.rest.copy_from_slice(&s.rest);
        world.restore_slept_under(&s.config);
        world.restore_method_before((s.steps > 0).then_some(s.config.integrator));
        world.restore_carried_impulses(&s.carried);
        world.time = s.time;
        world.steps = s.steps;
        world.last = s.last;
    }

    /// The state one step before the present one, if kept.
    pub(crate) fn previous(&self) -> Option<Previous<'_>> {
        let n = self.snapshots.len();
        let s = self.snapshots.get(n.checked_sub(2)?)?;
        Some(Previous {
            position: &s.position,
            velocity: &s.velocity,
            rest: &s.rest,
            slot_of: &s.slot_of,
        })
    }

    /// The parameters the step to the present state ran with, when the
    /// state before it is kept (see [`History::previous`]): they may differ
    /// from the world's own, changed since.
    pub(crate) fn stepped_with(&self) -> Option<&WorldConfig> {
        self.previous()?;
        self.snapshots.back().map(|s| &s.config)
    }

    /// Positions of the sphere of scene index `id`, oldest first, over the
    /// newest `n` snapshots.
    pub(crate) fn track(&self, id: usize, n: usize) -> impl Iterator<Item = Vec3> + '_ {
        let skip = self.snapshots.len().saturating_sub(n);
        self.snapshots.iter().skip(skip).filter_map(move |s| {
            let slot = if s.slot_of.is_empty() {
                id
            } else {
                *s.slot_of.get(id)? as usize
            };
            s.position.get(slot).copied()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;

    #[test]
    fn capacity_is_600_steps_back_for_lesson_worlds_and_budgeted_for_big_ones() {
        assert_eq!(capacity_for(1), STEPS);
        assert_eq!(capacity_for(150), STEPS);
        assert_eq!(capacity_for(100_000), MEMORY_BUDGET / (100_000 * 60));
        assert_eq!(capacity_for(usize::MAX / 64), 2);
        // What a few steps hold, against the budget many steps fill: one
        // sphere for 5 steps, 6 snapshots of 60 bytes (`bench --render`
        // had counted the whole 268 MB budget for it).
        assert_eq!(bytes_after(1, 5), 6 * 60);
        assert_eq!(bytes_after(150, 10_000), STEPS * 150 * 60);
        let big = bytes_after(100_000, 10_000);
        assert!(big <= MEMORY_BUDGET && big > MEMORY_BUDGET - 100_000 * 60);
    }

    #[test]
    fn a_rewind_gives_back_exactly_the_snapshots_of_the_mark() {
        // Marked at step 5, then recorded past the capacity, which pushes
        // out every snapshot of the mark: the rewind gives them back, in
        // order, and nothing recorded since; without a mark, they go.
        let mut world = Lesson::Pingpong.scene().build().unwrap();
        let mut history = History::new(&world);
        for _ in 0..5 {
            world.step();
            history.record(&world);
        }
        let steps = |h: &History| h.snapshots.iter().map(|s| s.steps).collect::<Vec<_>>();
        let marked = steps(&history);
        history.mark();
        for _ in 0..STEPS + 50 {
            world.step();
            history.record(&world);
        }
        assert_eq!(history.len(), STEPS);
        history.rewind();
        assert_eq!(steps(&history), marked);
        assert_eq!(history.capacity(), STEPS);
        history.restore_newest(&mut world);
        assert_eq!(world.steps, 5);
        history.mark();
        history.unmark();
        for _ in 0..STEPS {
            world.step();
            history.record(&world);
        }
        history.rewind();
        assert_eq!(history.snapshots.front().map(|s| s.steps), Some(6));
    }

    #[test]
    fn stepping_back_restores_the_exact_bits_at_any_restitution() {
        let mut world = Lesson::Collisions.scene().build().unwrap();
        world.config.wall_restitution = 0.3;
        world.config.pair_restitution = 0.5;
        let mut history = History::new(&world);
        let mut hashes = vec![world.state_hash()];
        for _ in 0..40 {
            world.step();
            history.record(&world);
            hashes.push(world.state_hash());
        }
        let later = world.bodies.clone();
        while history.step_back(&mut world) {
            hashes.pop();
            assert_eq!(world.state_hash(), *hashes.last().unwrap());
        }
        assert_eq!(world.steps, 0);
        world.run(40);
        assert_eq!(world.bodies, later, "replaying gives the same bits");
    }

    #[test]
    fn stepping_back_over_falling_asleep_replays_the_same_bits() {
        // A sphere at rest on the floor falls asleep at step 30, while
        // another still bounces; stepping back to step 20 and on again
        // must count its time at rest again from where it was.
        let r = 0.05;
        let body = |x: f64, y: f64| crate::sim::Body {
            position: Vec3::new(x, y, 0.5),
            velocity: Vec3::ZERO,
            radius: r,
            mass: 1.0,
        };
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            sleep: true,
            ..WorldConfig::default()
        };
        let mut world = World::new(config, [body(0.2, r), body(0.8, 0.7)].into_iter().collect());
        let mut history = History::new(&world);
        let mut hashes = vec![world.state_hash()];
        for _ in 0..40 {
            world.step();
            history.record(&world);
            hashes.push(world.state_hash());
        }
        assert_eq!(world.last.asleep, 1);
        for _ in 0..20 {
            assert!(history.step_back(&mut world));
            hashes.pop();
        }
        assert_eq!(world.state_hash(), *hashes.last().unwrap());
        assert_eq!(world.steps, 20);
        assert!(
            world.bodies.rest[0] > 0.0 && world.bodies.rest[0].is_finite(),
            "awake again"
        );
        assert_eq!(world.last.asleep, 0);
        world.run(20);
        assert_eq!(world.last.asleep, 1);
        assert_eq!(world.bodies.velocity[0], Vec3::ZERO);
        let mut again = World::new(
            world.config.clone(),
            [body(0.2, r), body(0.8, 0.7)].into_iter().collect(),
        );
        again.run(40);
        assert_eq!(
            world.state_hash(),
            again.state_hash(),
            "replaying gives the same bits"
        );
    }

    #[test]
    fn stepping_back_with_the_support_pass_restores_the_impulses_it_carries() {
        // A column of ten spheres held by the support pass: its rows carry
        // impulses from step to step, which a step back must put back for
        // the replay to give the same bits.
        let r = 0.04;
        let bodies: crate::sim::Bodies = (0..10)
            .map(|k| crate::sim::Body {
                position: Vec3::new(0.5, r + 2.0 * r * k as f64, 0.5),
                velocity: Vec3::ZERO,
                radius: r,
                mass: 1.0,
            })
            .collect();
        let config = WorldConfig {
            support: true,
            ..WorldConfig::default()
        };
        let mut world = World::new(config, bodies);
        world.run(60);
        assert!(world.carried_impulses().len() > 5);
        let mut history = History::new(&world);
        for _ in 0..20 {
            world.step();
            history.record(&world);
        }
        let later = world.bodies.clone();
        for _ in 0..20 {
            assert!(history.step_back(&mut world));
        }
        world.run(20);
        assert_eq!(world.bodies, later, "replaying gives the same bits");
    }

    #[test]
    fn stepping_back_over_the_change_to_the_continuous_method_replays_its_entry() {
        // Two spheres overlapping at rest: the first continuous step pushes
        // them apart (its entry). Back over it, the replay enters again;
        // back to the state before any step, too.
        let body = |x: f64| crate::sim::Body {
            position: Vec3::new(x, 0.5, 0.5),
            velocity: Vec3::ZERO,
            radius: 0.1,
            mass: 1.0,
        };
        let config = WorldConfig {
            gravity: Vec3::ZERO,
            pair_restitution: 1.0,
            ..WorldConfig::default()
        };
        let mut world = World::new(config, [body(0.5), body(0.55)].into_iter().collect());
        world.config.integrator = crate::sim::Integrator::Continuous;
        let mut history = History::new(&world);
        world.step();
        history.record(&world);
        let entered = world.bodies.clone();
        assert!(entered.position[1].x - entered.position[0].x > 0.2 - 1e-12);
        world.step();
        history.record(&world);
        assert!(history.step_back(&mut world) && history.step_back(&mut world));
        assert_eq!(world.steps, 0);
        world.step();
        assert_eq!(world.bodies, entered, "the replay enters the method again");
    }

    #[test]
    fn a_world_that_moves_spheres_between_slots_steps_back_and_trails_one_sphere() {
        use crate::sim::large::SPATIAL_ORDER_MIN_BODIES;
        let n = SPATIAL_ORDER_MIN_BODIES + 1000;
        let mut world = crate::scene::bench::bench_world(n, crate::sim::BroadPhase::Grid);
        let mut history = History::new(&world);
        let start = world.state_hash();
        for _ in 0..6 {
            world.step();
            history.record(&world);
        }
        assert!(
            world
                .bodies
                .id
                .iter()
                .enumerate()
                .any(|(k, &s)| k != s as usize),
            "a world this large keeps its slots in cell order"
        );
        let later = world.state_hash();
        // Each trail point is one step (1/60 s, speeds of a few m/s) from
        // the last: the trail stays on one sphere.
        for i in [0, n / 2, n - 1] {
            let trail: Vec<Vec3> = history.track(i, 7).collect();
            assert_eq!(trail.len(), 7);
            for w in trail.windows(2) {
                assert!(w[0].distance(w[1]) < 0.2, "sphere {i} jumps: {w:?}");
            }
        }
        while history.step_back(&mut world) {}
        assert_eq!(world.state_hash(), start);
        world.run(6);
        assert_eq!(world.state_hash(), later, "replaying gives the same bits");
    }

    #[test]
    fn a_full_history_drops_the_oldest_state() {
        let mut world = Lesson::Pingpong.scene().build().unwrap();
        let mut history = History::new(&world);
        for _ in 0..STEPS + 10 {
            world.step();
            history.record(&world);
        }
        assert_eq!(history.len(), STEPS);
        let mut back = 0;
        while history.step_back(&mut world) {
            back += 1;
        }
        assert_eq!(back, STEPS - 1);
        assert_eq!(world.steps, 11);
    }
}
