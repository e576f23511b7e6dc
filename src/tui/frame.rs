//! A frame: the copy of the simulation session's state that the view
//! draws. The worker thread publishes one after the steps it takes and the
//! actions it carries out; the drawing thread draws the newest it has, so
//! drawing never waits for a step and a step never waits for drawing.
//!
//! Owns copies only: the world's state without its working buffers, the
//! energy log, the ghost, the trails asked for, and the pace of the
//! simulation against real time. Large parts are shared (`Arc`) or reuse
//! the buffers of an earlier frame, so publishing costs about one copy of
//! the positions and velocities.

use super::energy_log::EnergyLog;
use super::ghost::Unavailable;
use super::selection::{Inspection, Selection};
use super::session::Session;
use crate::scene::Scene;
use crate::sim::{Bodies, Vec3, World};
use std::sync::Arc;

/// Trails follow at most this many spheres (evenly chosen)...
pub(crate) const MAX_TRAILS: usize = 24;
/// ...over at most this many recent steps.
pub(crate) const TRAIL_STEPS: usize = 90;
/// A selected sphere's trail: its recent steps, short enough to read
/// around a collision.
pub(crate) const SELECTED_TRAIL_STEPS: usize = 30;

/// One trail: positions of a sphere, oldest first.
pub(crate) type Trail = Vec<Vec3>;

/// Slots of at most `most` spheres, evenly chosen by scene index (every
/// `len / most`-th), so the same spheres are chosen whatever slots the
/// world's spatial order has moved them to.
pub(crate) fn sample_slots(b: &Bodies, most: usize) -> impl Iterator<Item = usize> + '_ {
    let stride = b.len().div_ceil(most.max(1)).max(1);
    (0..b.len()).filter(move |&k| (b.id[k] as usize).is_multiple_of(stride))
}

/// How the simulation keeps up with real time, measured by the worker.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pace {
    /// Wall time of the last step, ms.
    pub step_ms: Option<f64>,
    /// Simulated seconds per real second over the last second of running.
    pub achieved: Option<f64>,
    /// The world could not keep up with the time scale asked: steps owed
    /// were dropped.
    pub behind: bool,
    /// Steps abandoned part-way so that an action could act at once.
    pub abandoned: u64,
}

#[derive(Clone, Debug)]
pub struct Frame {
    /// The number of the last action carried out (see `App::apply`).
    pub applied: u64,
    pub scene: Arc<Scene>,
    /// The gravity the lesson's text was written for, m/s^2: the panel
    /// says when the world's is another.
    pub lesson_gravity: Vec3,
    /// The world's state (its working buffers left out).
    pub world: World,
    pub energy: EnergyLog,
    pub show_ghost: bool,
    pub ghost: Option<GhostView>,
    /// The grid's pair tests over the present spheres, if counted.
    pub grid_tests: Option<u64>,
    /// Whether the panel shows `grid_tests` rather than the step's count.
    pub needs_grid_tests: bool,
    /// Recent paths of the sampled spheres, when asked for.
    pub trails: Vec<Trail>,
    /// Recent paths of the selected spheres, always.
    pub selected_trails: Vec<Trail>,
    /// The speed drawn in the hottest colour, m/s.
    pub speed_scale: f64,
    pub pace: Pace,
    /// The spheres picked, and their numbers at this step.
    pub selection: Option<Selection>,
    pub inspection: Option<Inspection>,
    /// The newest message of the session: its number, the action it
    /// followed, and the text.
    pub message: Option<Message>,
}

/// What the view draws of the ghost (see `ghost.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct GhostView {
    /// Exact positions at the time shown; empty when unavailable.
    pub positions: Vec<crate::sim::Vec3>,
    /// Radii in the same order, m.
    pub radius: Vec<f64>,
    /// RMS distance between the simulated spheres and the ghost, m.
    pub rms: Option<f64>,
    /// The RMS distance is more than a mean radius (`Ghost::diverged`).
    pub diverged: bool,
    /// The step the ghost started from: where it was switched on, or
    /// where the lesson or its physics last changed (`ghost.rs`).
    pub anchor_step: u64,
    pub unavailable: Option<Unavailable>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    pub id: u64,
    /// The number of the action it answers; `None` when the simulation
    /// itself has something to say (the ghost reached its horizon).
    pub after: Option<u64>,
    pub text: String,
}

impl Frame {
    /// The slots of the selected spheres in the world shown (a large
    /// world keeps its spheres in cell order, not by id).
    pub(crate) fn selected_slots(&self) -> Vec<usize> {
        self.selection.map_or_else(Vec::new, |s| {
            let id = &self.world.bodies.id;
            s.ids()
                .iter()
                .filter_map(|&want| id.iter().position(|&k| k == want))
                .collect()
        })
    }

    /// The frame of `session`'s present state; `trails` asks for the
    /// recent paths of the sampled spheres. `into` lends its buffers.
    pub fn of(session: &Session, trails: bool, into: Option<Frame>) -> Frame {
        let world = session.world.copy_state(into.map(|f| f.world));
        let trails = if trails {
            let b = &session.world.bodies;
            sample_slots(b, MAX_TRAILS)
                .map(|k| {
                    session
                        .history
                        .track(b.id[k] as usize, TRAIL_STEPS)
                        .collect()
                })
                .collect()
        } else {
            Vec::new()
        };
        let selected_trails = session.selection.map_or_else(Vec::new, |s| {
            s.ids()
                .iter()
                .map(|&id| {
                    session
                        .history
                        .track(id as usize, SELECTED_TRAIL_STEPS)
                        .collect()
                })
                .collect()
        });
        Frame {
            selected_trails,
            applied: 0,
            scene: Arc::clone(&session.scene),
            lesson_gravity: session.lesson_gravity,
            world,
            energy: session.energy.clone(),
            show_ghost: session.show_ghost,
            ghost: session.ghost.as_ref().map(|g| GhostView {
                positions: g.positions.clone(),
                radius: g.radius.clone(),
                rms: g.rms,
                diverged: g.diverged(),
                anchor_step: g.anchor_step(),
                unavailable: g.unavailable,
            }),
            grid_tests: session.grid_tests(),
            needs_grid_tests: session.needs_grid_tests(),
            trails,
            speed_scale: session.speed_scale,
            pace: Pace::default(),
            selection: session.selection,
            inspection: session.inspection(),
            message: None,
        }
    }

    /// Gravity's magnitude, m/s^2.
    pub fn gravity(&self) -> f64 {
        self.world.config.gravity.length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;
    use crate::sim::{BroadPhase, Vec3};

    #[test]
    fn trails_follow_the_same_spheres_while_slots_move() {
        let n = crate::sim::large::SPATIAL_ORDER_MIN_BODIES + 1000;
        let mut scene = Lesson::Collisions.scene();
        for s in &mut scene.spawns {
            s.overlap = true;
        }
        scene.set_particles(n).unwrap();
        scene.world.broad_phase = BroadPhase::Grid;
        let mut session = Session::new(scene, Some(Lesson::Collisions)).unwrap();
        for _ in 0..3 {
            session.step();
        }
        let b = &session.world.bodies;
        assert!(
            b.id.iter().enumerate().any(|(k, &s)| k != s as usize),
            "a world this large keeps its slots in cell order"
        );
        let slot = b.slots_in_scene_order();
        let frame = session.frame(true, None);
        assert!(
            session.frame(false, None).trails.is_empty(),
            "only when asked"
        );
        let ends: Vec<Vec3> = frame.trails.iter().map(|t| *t.last().unwrap()).collect();
        let stride = n.div_ceil(MAX_TRAILS);
        let expected: Vec<Vec3> = (0..n)
            .step_by(stride)
            .map(|s| b.position[slot[s]])
            .collect();
        let mut ends_sorted = ends.clone();
        let mut expected_sorted = expected.clone();
        for v in [&mut ends_sorted, &mut expected_sorted] {
            v.sort_by(|a, b| a.x.total_cmp(&b.x));
        }
        assert_eq!(
            ends_sorted,
            expected_sorted,
            "the trails end at the spheres of scene index 0, {stride}, {}...",
            2 * stride
        );
    }

    #[test]
    fn a_frame_reusing_an_earlier_one_is_the_present_state() {
        let mut session = Session::lesson(Lesson::Collisions);
        let old = session.frame(false, None);
        session.world.run(5);
        let frame = session.frame(false, Some(old));
        assert_eq!(frame.world.state_hash(), session.world.state_hash());
        assert_eq!(frame.world.contacts(), session.world.contacts());
        assert_eq!(frame.world.diagnostics(), session.world.diagnostics());
    }
}
