//! What a world runs. `WorldConfig::default()` is the one place defaults
//! live; every field says its unit. A scene file's `[world]` table and the
//! command line's overrides both end here.

use super::restitution::Restitution;
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

    /// The rule a wall impact follows: `flip` always keeps the speed;
    /// `restitution` uses `restitution`.
    pub fn rule(self, restitution: Restitution) -> Restitution {
        match self {
            WallMode::Flip => Restitution::new(1.0, 0.0),
            WallMode::Restitution => restitution,
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
    /// Sub-steps per step (>= 1): every stage runs `substeps` times with
    /// `dt / substeps`, whatever the method.
    pub substeps: u32,
    /// Approach speed below which an impact (wall or pair) is perfectly
    /// inelastic, m/s; 0 switches the threshold off.
    pub rest_threshold: f64,
    /// Resting contact for the discrete methods, in (sub-)steps, in
    /// [0, 10]: an impact slower than the speed gravity adds along its
    /// normal in this many sub-steps is perfectly inelastic
    /// (`restitution.rs`); 0 switches it off.
    pub rest_steps: f64,
    /// Position passes over a step's contacts (>= 1, at most 64): the
    /// lesson's pass, then up to `projection_passes - 1` projections of the
    /// pairs still overlapping (`contact::project_contacts`), stopping
    /// early once none overlaps by more than 1% of the largest radius.
    pub projection_passes: u32,
}

impl WorldConfig {
    /// The rule of wall impacts: the wall mode, restitution and threshold.
    pub fn wall_rule(&self) -> Restitution {
        self.wall_mode
            .rule(Restitution::new(self.wall_restitution, self.rest_threshold))
    }

    /// Wall restitution as the wall stage applies it: 1 for `flip` walls.
    pub fn wall_coefficient(&self) -> f64 {
        self.wall_rule().coefficient
    }

    /// The rule of sphere-sphere impacts.
    pub fn pair_rule(&self) -> Restitution {
        Restitution::new(self.pair_restitution, self.rest_threshold)
    }

    /// The velocity gravity adds over the resting window of a sub-step of
    /// `h` s (`g rest_steps h`), m/s.
    pub fn resting(&self, h: f64) -> Vec3 {
        self.gravity * (self.rest_steps * h)
    }

    /// The length of one sub-step, s.
    pub fn substep_dt(&self) -> f64 {
        self.dt / f64::from(self.substeps.max(1))
    }
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
            substeps: 1,
            rest_threshold: 0.0,
            rest_steps: 1.0,
            projection_passes: 1,
        }
    }
}
