//! Exact motions to measure the methods against.
//!
//! - [`pingpong`]: the triangle wave of a centre between flipping walls;
//! - [`gravity`]: each coordinate of a sphere that meets only walls, as a
//!   chain of parabolas with exactly solved impact times and the
//!   finite-time rest;
//! - [`collisions`]: colliding spheres, event by event, for short horizons.
//!
//! A reference is the ideal motion of a scene's physics: the rest threshold
//! (a numerical remedy) and the sub-steps are not part of it. This module
//! reads a world's bodies and configuration and never changes a world.

pub mod collisions;
pub mod gravity;
pub mod pingpong;

use super::{Vec3, World};
use gravity::AxisMotion;

/// The exact motion of a world's bodies from its current state.
#[derive(Clone, Debug)]
pub enum Reference {
    /// No pair collisions: every coordinate of every body on its own.
    Independent(Vec<[AxisMotion; 3]>),
    /// Pair collisions: event by event from the start state.
    EventDriven(Box<World>),
}

impl Reference {
    /// The reference for `world`, taking its present state as time 0.
    pub fn of(world: &World) -> Reference {
        let config = &world.config;
        if !config.pair_collisions {
            let c = config.wall_coefficient();
            let axes = world
                .bodies
                .iter()
                .map(|b| {
                    std::array::from_fn(|k| AxisMotion {
                        p0: b.position[k],
                        u0: b.velocity[k],
                        a: config.gravity[k],
                        lo: b.radius,
                        hi: 1.0 - b.radius,
                        c,
                    })
                })
                .collect();
            Reference::Independent(axes)
        } else {
            let mut start = world.clone();
            start.time = 0.0;
            start.steps = 0;
            Reference::EventDriven(Box::new(start))
        }
    }

    /// The exact positions and velocities `t` seconds after the start, or
    /// `None` where the reference cannot say (the event-driven motion hit
    /// its event cap).
    pub(crate) fn state_at(&self, t: f64) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
        match self {
            Reference::Independent(axes) => Some(
                axes.iter()
                    .map(|a| {
                        let [x, y, z] = [a[0].at(t), a[1].at(t), a[2].at(t)];
                        (Vec3::new(x.0, y.0, z.0), Vec3::new(x.1, y.1, z.1))
                    })
                    .unzip(),
            ),
            Reference::EventDriven(world) => collisions::state_at(world, t),
        }
    }

    /// The exact positions `t` seconds after the start (see
    /// [`Reference::state_at`]).
    pub fn positions_at(&self, t: f64) -> Option<Vec<Vec3>> {
        self.state_at(t).map(|(x, _)| x)
    }
}

/// The exact positions of a scene's bodies `t` seconds after `world`'s
/// present state, where an exact reference exists (for the visualiser's
/// ghost). For colliding spheres this replays the events from the start,
/// so call it with the world as it was built and keep `t` short.
pub fn exact_positions(world: &World, t: f64) -> Option<Vec<Vec3>> {
    Reference::of(world).positions_at(t)
}
