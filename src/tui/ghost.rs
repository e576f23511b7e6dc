//! The ghost: the exact reference of the scene drawn over the simulated
//! spheres, and the RMS distance between the two, so a person sees the
//! error of the method grow.
//!
//! A ghost is anchored at one state of the world: where it was switched
//! on, where the lesson was (re)started, where a parameter of the physics
//! (restitution, gravity) changed, or where a step back went to before the
//! anchor. From the anchor, `crate::sim::reference` gives the exact
//! positions `t` seconds later (the same reference as
//! `reference::exact_positions(&anchor, t)`), with `t` the world's time
//! since the anchor. Stepping back and forward therefore shows the ghost
//! where the exact motion is at the time shown; changing the method or
//! `dt` keeps the anchor, since the exact motion does not depend on them.
//!
//! Where no reference can say: colliding spheres are followed event by
//! event only up to [`PAIR_HORIZON`] after the anchor (the collisions are
//! chaotic: beyond about a second, rounding alone moves the exact motion by
//! millimetres, see `reference::collisions`), and only for up to
//! [`MAX_PAIR_GHOST_SPHERES`] spheres (every frame replays the events from
//! the anchor); spheres that meet only walls, up to [`MAX_GHOST_SPHERES`].
//!
//! Owns the anchor and the latest exact positions; it never changes the
//! world.

use crate::sim::reference::Reference;
use crate::sim::reference::collisions::rms_distance;
use crate::sim::{Vec3, World};

/// How long after its anchor the ghost of colliding spheres is shown, s:
/// the collisions lesson's predictability horizon (`lerpit study` measures
/// 0.96 s for a nudge of 1e-12 m to grow to 1 mm).
pub(crate) const PAIR_HORIZON: f64 = 1.0;
/// Most spheres the ghost follows when they meet only walls.
pub(crate) const MAX_GHOST_SPHERES: usize = 10_000;
/// Most spheres the ghost follows when they collide with each other: the
/// replay costs a few milliseconds a frame for the lesson's 100 spheres
/// a second after the anchor, and grows as the square of the count (at 400
/// it also runs out of impacts within half a second).
pub(crate) const MAX_PAIR_GHOST_SPHERES: usize = 200;

#[derive(Clone, Debug)]
pub struct Ghost {
    reference: Reference,
    /// Simulated time and step of the anchor.
    anchor_time: f64,
    anchor_steps: u64,
    /// Scene index of the sphere in each slot at the anchor: the order of
    /// the reference's positions.
    ids: Vec<u32>,
    /// Radii in the same order, m.
    pub radius: Vec<f64>,
    /// Their mean, m: past it the RMS distance says the run has diverged.
    mean_radius: f64,
    pairs: bool,
    /// The world's `(steps, time)` the positions below are for.
    shown_at: Option<(u64, u64)>,
    /// Exact positions at the time shown, in anchor slot order; empty when
    /// unavailable.
    pub positions: Vec<Vec3>,
    /// RMS distance between the simulated spheres and the ghost, m.
    pub rms: Option<f64>,
    /// Why the ghost is not shown at the current time.
    pub unavailable: Option<Unavailable>,
}

/// Why a ghost has no positions at some time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unavailable {
    /// Colliding spheres, more than [`PAIR_HORIZON`] after the anchor.
    PastHorizon,
    /// The event-driven reference reached its cap of impacts.
    TooManyImpacts,
}

impl Unavailable {
    /// A status line saying why.
    pub(crate) fn message(self) -> String {
        match self {
            Unavailable::PastHorizon => format!(
                "no ghost {PAIR_HORIZON} s past its start: colliding spheres are chaotic, \
                 compare energy instead (x twice restarts the ghost here)"
            ),
            Unavailable::TooManyImpacts => "no ghost: the exact motion needs too many impacts \
                 here (x twice restarts the ghost)"
                .into(),
        }
    }

    /// A few words for the side panel.
    pub(crate) fn short(self) -> String {
        match self {
            Unavailable::PastHorizon => format!("off: past {PAIR_HORIZON} s, chaotic"),
            Unavailable::TooManyImpacts => "off: too many impacts".into(),
        }
    }
}

impl Ghost {
    /// A ghost anchored at `world`'s present state, or why there can be
    /// none.
    pub(crate) fn anchor(world: &World) -> Result<Ghost, String> {
        let n = world.bodies.len();
        let pairs = world.config.pair_collisions;
        let most = if pairs {
            MAX_PAIR_GHOST_SPHERES
        } else {
            MAX_GHOST_SPHERES
        };
        if n > most {
            return Err(format!(
                "no ghost for {}: the exact reference follows at most {}{}",
                crate::scene::spheres(n),
                crate::scene::thousands(most as u64),
                if pairs { " colliding spheres" } else { "" }
            ));
        }
        Ok(Ghost {
            reference: Reference::of(world),
            anchor_time: world.time,
            anchor_steps: world.steps,
            ids: world.bodies.id.clone(),
            radius: world.bodies.radius.clone(),
            mean_radius: world.bodies.radius.iter().sum::<f64>() / n.max(1) as f64,
            pairs,
            shown_at: None,
            positions: Vec::new(),
            rms: None,
            unavailable: None,
        })
    }

    /// The step the ghost started from.
    pub(crate) fn anchor_step(&self) -> u64 {
        self.anchor_steps
    }

    /// Whether the simulated spheres are, in RMS, further from the exact
    /// ones than a mean radius: the run has diverged from the exact motion.
    pub(crate) fn diverged(&self) -> bool {
        self.rms.is_some_and(|rms| rms > self.mean_radius)
    }

    /// What [`Ghost::diverged`] means here, once, as it happens.
    pub(crate) fn divergence(&self) -> String {
        let why = if self.pairs {
            "a collision went another way than in the exact motion (a step sees \
             an overlap only at its end), and from there the two part"
        } else {
            "the method's error has grown past it"
        };
        format!("the run is now further from the ghost than a sphere's radius (RMS): {why}")
    }

    /// Seconds of `world`'s time since the anchor.
    pub(crate) fn since_anchor(&self, world: &World) -> f64 {
        world.time - self.anchor_time
    }

    /// Whether `world` is at a step before the anchor (after a step back).
    pub(crate) fn is_before_anchor(&self, world: &World) -> bool {
        world.steps < self.anchor_steps
    }

    /// Bring the positions and the RMS distance to `world`'s present time
    /// (nothing to do if they are already there).
    pub(crate) fn update(&mut self, world: &World) {
        let key = (world.steps, world.time.to_bits());
        if self.shown_at == Some(key) {
            return;
        }
        self.shown_at = Some(key);
        let t = self.since_anchor(world).max(0.0);
        let exact = if self.pairs && t > PAIR_HORIZON {
            Err(Unavailable::PastHorizon)
        } else {
            self.reference
                .positions_at(t)
                .ok_or(Unavailable::TooManyImpacts)
        };
        match exact {
            Ok(positions) => {
                self.rms = Some(self.distance(world, &positions));
                self.positions = positions;
                self.unavailable = None;
            }
            Err(why) => {
                self.positions.clear();
                self.rms = None;
                self.unavailable = Some(why);
            }
        }
    }

    /// RMS distance between the world's spheres and `exact` (anchor slot
    /// order), sphere by sphere whatever slots they moved to.
    fn distance(&self, world: &World, exact: &[Vec3]) -> f64 {
        let b = &world.bodies;
        if b.id == self.ids {
            return rms_distance(&b.position, exact);
        }
        let slot = b.slots_in_scene_order();
        let simulated: Vec<Vec3> = self
            .ids
            .iter()
            .map(|&s| b.position[slot[s as usize]])
            .collect();
        rms_distance(&simulated, exact)
    }
}
