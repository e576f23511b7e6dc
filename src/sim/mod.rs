//! The simulation core: spheres in the unit box `[0, 1]^3`, y up.
//!
//! This module tree owns the physics and nothing else. It never draws and
//! never reads a terminal: the headless runner, the tests and the visualiser
//! all drive it through [`World`].
//!
//! One file per concept. A step (`world.rs`) first wakes the sleepers or
//! leaves them to rest (`sleep.rs`), then runs its stages in this order:
//! integration, the broad phase, the contacts (or the continuous method in
//! their place; the narrow phase wakes the sleepers its pairs disturb),
//! the walls, then the support pass; last, the spheres at rest long enough
//! fall asleep (`sleep.rs`).
//!
//! | file              | concept                                                        |
//! |-------------------|----------------------------------------------------------------|
//! | `body.rs`         | the spheres: position, velocity, radius, mass (hot data, SoA)  |
//! | `config.rs`       | what a world runs: gravity, dt, integrator, walls, pairs       |
//! | `integrator.rs`   | explicit Euler, semi-implicit Euler, velocity Verlet, RK4      |
//! | `restitution.rs`  | rest threshold, resting contact: slow impacts are inelastic    |
//! | `walls.rs`        | the box: `flip` and `restitution` wall response                |
//! | `broad_phase.rs`  | which pairs are tested: all-pairs (the lesson), grid, auto     |
//! | `grid.rs`         | the uniform grid: cells, counting sort, half-stencil search    |
//! | `contact.rs`      | sphere-sphere detection and the lesson's projection + V1/V2    |
//! | `continuous.rs`   | the continuous method: times of impact inside the step         |
//! | `support.rs`      | the support pass: resting contacts solved together, piles held |
//! | `sleep.rs`        | spheres at rest sleep until disturbed; a world asleep costs nothing |
//! | `sleeping_pairs.rs` | the pairs of two sleepers, kept so the narrow phase skips them |
//! | `stage.rs`        | the stages of a step, named once, and their timings            |
//! | `world.rs`        | `World::step`: the stages in order                             |
//! | `large/`          | worlds of thousands of spheres and up: cell order, parallel slabs |
//! | `reference/`      | exact motions to measure the methods against                   |
//! | `diagnostics.rs`  | energy, momentum, contacts: the readouts of a step             |
//! | `spawn.rs`        | seeded random placement of spheres                             |
//! | `state_hash.rs`   | a bit-exact fingerprint of the state, for determinism          |
//! | `threads.rs`      | the thread pool a world steps on                               |

//!
//! The core has no unsafe code: parallel tasks write disjoint parts of a
//! buffer cut out with `split_at_mut` or chunking.
#![forbid(unsafe_code)]

pub(crate) mod body;
pub mod broad_phase;
pub mod config;
pub mod contact;
pub mod continuous;
pub mod diagnostics;
pub(crate) mod grid;
pub(crate) mod integrator;
pub mod large;
pub mod reference;
pub(crate) mod restitution;
pub mod sleep;
pub(crate) mod sleeping_pairs;
pub(crate) mod spawn;
pub(crate) mod stage;
pub mod state_hash;
pub mod support;
pub mod threads;
pub mod walls;
pub mod world;

pub use body::{Bodies, Body};
pub use broad_phase::BroadPhase;
pub use config::{STANDARD_GRAVITY, WallMode, WorldConfig, gravity_along, gravity_down};
pub use contact::Contact;
pub use diagnostics::Diagnostics;
pub use grid::{CellLayout, Grid};
pub use integrator::Integrator;
pub use spawn::{MassLaw, MassLawKind, Spawn, SpawnError};
pub use stage::{Stage, StageSeconds};
pub use world::{StepStats, World};

/// Vectors are `f64`: the lesson scenes are small, and the accuracy study
/// compares against closed forms at rounding level.
pub use glam::DVec3 as Vec3;

/// A count as every message gives it: `1234567` as `1,234,567`.
pub(crate) fn thousands(v: u64) -> String {
    let digits = v.to_string();
    let mut out = String::new();
    for (k, ch) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(ch);
    }
    out
}
