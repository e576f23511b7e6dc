//! What a world runs. `WorldConfig::default()` is the one place defaults
//! live; every field says its unit. A scene file's `[world]` table and the
//! command line's overrides both end here.

use super::{BroadPhase, Integrator, Vec3};
use serde::{Deserialize, Serialize};

/// How a sphere that reaches a wall of the box responds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallMode {
    /// The ping-pong lesson: the velocity component normal to the wall
    /// reverses and the speed is kept.
    Flip,
    /// The gravity lesson: `v_n <- -c_r v_n` with `c_r = wall_restitution`.
    Restitution,
}

impl WallMode {
    pub const ALL: [WallMode; 2] = [WallMode::Flip, WallMode::Restitution];

    pub fn name(self) -> &'static str {
        match self {
            WallMode::Flip => "flip",
            WallMode::Restitution => "restitution",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct WorldConfig {
    /// Uniform gravitational acceleration, m/s^2 (the lesson: 9.81 down).
    /// The only force in the lessons, so `F/m = gravity` for every body;
    /// a zero vector switches the force stage off.
    pub gravity: Vec3,
    /// Fixed time step, s.
    pub dt: f64,
    /// How velocity and position advance over one step.
    pub integrator: Integrator,
    /// Wall response.
    pub wall_mode: WallMode,
    /// Coefficient of restitution at the walls, in [0, 1] (`restitution`
    /// mode only; `flip` keeps the speed).
    pub wall_restitution: f64,
    /// Whether spheres collide with each other (the collisions lesson).
    pub pair_collisions: bool,
    /// Coefficient of restitution between spheres, in [0, 1].
    pub pair_restitution: f64,
    /// Which pairs are tested for contact.
    pub broad_phase: BroadPhase,
}

impl Default for WorldConfig {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 120.0,
            integrator: Integrator::SemiImplicitEuler,
            wall_mode: WallMode::Restitution,
            wall_restitution: 0.95,
            pair_collisions: true,
            pair_restitution: 0.95,
            broad_phase: BroadPhase::AllPairs,
        }
    }
}
