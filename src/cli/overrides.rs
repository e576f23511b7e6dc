//! Command-line overrides of a scene's parameters, shared by `lerpit run`
//! and the visualiser. Values are checked by the same rules as scene files.

use super::values::{choice, number, whole, whole_number};
use crate::scene::{Scene, rules};
use crate::sim::config::SupportIdle;
use crate::sim::{BroadPhase, Integrator, WallMode, gravity_along};
use clap::Args;

#[derive(Args, Debug, Clone, Default)]
pub struct Overrides {
    /// Time step, s (0 < dt <= 1), as a number or a fraction: 0.004, 1/240.
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::dt))]
    pub dt: Option<f64>,
    /// Integration method.
    #[arg(long, value_parser = choice::<Integrator>())]
    pub integrator: Option<Integrator>,
    /// Which pairs are tested for contact.
    #[arg(long, value_name = "METHOD", value_parser = choice::<BroadPhase>())]
    pub broadphase: Option<BroadPhase>,
    /// Wall restitution c_r in [0, 1]; switches `flip` walls to `restitution`.
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::restitution))]
    pub restitution: Option<f64>,
    /// Sphere-sphere restitution e in [0, 1].
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::restitution))]
    pub pair_restitution: Option<f64>,
    /// Gravity magnitude, m/s^2, along the scene's gravity (down, -y, when
    /// the scene has none).
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::gravity_magnitude))]
    pub gravity: Option<f64>,
    /// Number of spheres in all: the scene's bodies
    /// first, then its spawns in their proportions, every radius scaled so
    /// that the spheres fill the same fraction of the box, as + and - do in
    /// the visualiser.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_particles)]
    pub particles: Option<usize>,
    /// Sub-steps per step (1 to 10000), for any integrator.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_substeps)]
    pub substeps: Option<u32>,
    /// Approach speed, m/s, below which an impact is perfectly inelastic
    /// (0 = off).
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::non_negative))]
    pub rest_threshold: Option<f64>,
    /// Resting contact: impacts slower than gravity adds along their normal
    /// in this many sub-steps keep no normal speed (0 = off, at most 10);
    /// the continuous method holds touching pairs slower than this many
    /// steps plus one of all of gravity.
    #[arg(long, allow_negative_numbers = true, value_parser = number(rules::rest_steps))]
    pub rest_steps: Option<f64>,
    /// Passes over a step's contacts (1 to 64): more cut a deep pile's
    /// overlap but keep it moving, most without sub-steps (--substeps or
    /// --support hold a pile).
    #[arg(long, allow_negative_numbers = true, value_parser = parse_projection_passes)]
    pub projection_passes: Option<u32>,
    /// Solve every resting contact together so piles carry their weight:
    /// the support pass (needs gravity,
    /// pair collisions, resting contact and a discrete method; refused
    /// without them).
    #[arg(long)]
    pub support: bool,
    /// Let spheres sleep: an island at rest (under 0.05 m/s) for half a
    /// second is neither moved nor solved until something touches it, and
    /// a world all asleep costs nothing (discrete methods; refused with the
    /// continuous one).
    #[arg(long)]
    pub sleep: bool,
    /// Seed of the scene's random choices (0 to 2^64 - 1).
    #[arg(long, allow_negative_numbers = true, value_parser = whole::<u64>(0, u64::MAX))]
    pub seed: Option<u64>,
}

fn parse_projection_passes(s: &str) -> Result<u32, String> {
    whole_number(s, 1, rules::MAX_PROJECTION_PASSES.into())
}

fn parse_substeps(s: &str) -> Result<u32, String> {
    whole_number(s, 1, rules::MAX_SUBSTEPS.into())
}

/// A positive number of spheres within the scene limit; shared with
/// `lerpit bench`.
pub(crate) fn parse_particles(s: &str) -> Result<usize, String> {
    whole_number(s, 1, rules::MAX_BODIES as u64)
}

impl Overrides {
    /// For `lerpit run`, where no key can change the scene afterwards:
    /// refuse the seed where nothing is placed at random, and the resting
    /// flags that `scene` (with the flags applied) gives nothing to act on. The visualiser takes them, as its keys may
    /// add gravity or make walls restitution walls.
    pub(crate) fn check_for_run(&self, scene: &Scene) -> Result<(), String> {
        let w = &scene.world;
        if let Some(seed) = self.seed
            && scene.spawns.iter().all(|s| s.count == 0)
        {
            return Err(format!(
                "--seed {seed}: {} places no sphere at random (no [[spawn]] places any), so \
                 the seed would change no sphere",
                scene.origin
            ));
        }
        let g = w.gravity_strength();
        if let Some(k) = self.rest_steps.filter(|&k| k > 0.0 && g == 0.0) {
            // The scene's gravity, or the flag that took it away.
            let without = match self.gravity {
                Some(g) => format!("with --gravity {} there is", rules::show(g)),
                None => format!("{} has", scene.origin),
            };
            return Err(format!(
                "--rest-steps {}: {without} no gravity, so no impact is resting contact and it \
                 would change nothing",
                rules::show(k),
            ));
        }
        let flip_alone = !w.pair_collisions && w.wall_mode == WallMode::Flip;
        if let Some(k) = self.rest_steps.filter(|&k| k > 0.0 && flip_alone) {
            return Err(format!(
                "--rest-steps {}: {} has flip walls, which keep the speed, and no pair \
                 collisions, so no impact is resting contact and it would change nothing \
                 (--restitution makes the walls restitution walls)",
                rules::show(k),
                scene.origin
            ));
        }
        if let Some(v) = self.rest_threshold.filter(|&v| v > 0.0)
            && flip_alone
        {
            return Err(format!(
                "--rest-threshold {}: {} has flip walls, which keep the speed, and no pair \
                 collisions, so no impact uses it (--restitution makes the walls restitution \
                 walls)",
                rules::show(v),
                scene.origin
            ));
        }
        Ok(())
    }

    /// Apply to `scene`; the message names the flag at fault.
    pub(crate) fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        let w = &mut scene.world;
        if let Some(dt) = self.dt {
            w.dt = dt;
        }
        if let Some(m) = self.integrator {
            w.integrator = m;
        }
        if let Some(b) = self.broadphase {
            w.broad_phase = b;
        }
        if let Some(c) = self.restitution {
            w.wall_mode = WallMode::Restitution;
            w.wall_restitution = c;
        }
        if let Some(e) = self.pair_restitution {
            w.pair_restitution = e;
        }
        if let Some(g) = self.gravity {
            w.gravity = gravity_along(g, w.gravity);
        }
        if let Some(k) = self.substeps {
            w.substeps = k;
        }
        if let Some(v) = self.rest_threshold {
            w.rest_threshold = v;
        }
        if let Some(v) = self.rest_steps {
            w.rest_steps = v;
        }
        if let Some(k) = self.projection_passes {
            w.projection_passes = k;
        }
        if self.support {
            w.support = true;
        }
        if self.sleep {
            w.sleep = true;
        }
        // Flags for pair collisions (their restitution, passes and broad
        // phase) in a scene without them would change nothing, in any
        // command or key: refused, as an idle support pass is.
        let for_pairs = [
            self.pair_restitution
                .map(|e| format!("--pair-restitution {}", rules::show(e))),
            self.projection_passes
                .map(|k| format!("--projection-passes {k}")),
            self.broadphase.map(|b| format!("--broadphase {b}")),
        ];
        if !w.pair_collisions
            && let Some(flag) = for_pairs.into_iter().flatten().next()
        {
            return Err(format!(
                "{flag}: {} has no pair collisions, so it would change nothing \
                 (the collisions lesson has them, as has a scene file with \
                 pair_collisions = true)",
                scene.origin
            ));
        }
        if w.support
            && let Some(why) = w.support_idle()
        {
            // The flag given that leaves the pass idle for the reason
            // said, if any.
            let given: Vec<String> = [
                (
                    why == SupportIdle::NO_GRAVITY,
                    self.gravity
                        .map(|g| format!("--gravity {}", rules::show(g))),
                ),
                (
                    why == SupportIdle::NO_RESTING,
                    self.rest_steps
                        .map(|k| format!("--rest-steps {}", rules::show(k))),
                ),
                (
                    why == SupportIdle::CONTINUOUS,
                    self.integrator.map(|i| format!("--integrator {i}")),
                ),
            ]
            .into_iter()
            .filter_map(|(idles, flag)| flag.filter(|_| idles))
            .collect();
            return Err(if self.support && given.is_empty() {
                format!("--support: the support pass would not run: {why}")
            } else if self.support {
                format!(
                    "--support with {}: the support pass would not run: {why}",
                    given.join(" and ")
                )
            } else if given.is_empty() {
                format!("with these flags the scene's support pass would not run: {why}")
            } else {
                format!(
                    "with {} the scene's support pass would not run: {why}",
                    given.join(" and ")
                )
            });
        }
        if let Some(why) = w.sleep_idle() {
            return Err(match (self.sleep, self.integrator) {
                (true, _) => format!("--sleep: no sphere would sleep: {why}"),
                (false, Some(i)) => {
                    format!("with --integrator {i} the scene's spheres would not sleep: {why}")
                }
                (false, None) => format!("the scene's spheres would not sleep: {why}"),
            });
        }
        if let Some(seed) = self.seed {
            scene.seed = seed;
        }
        if let Some(n) = self.particles {
            *scene = scene
                .with_count(scene, n)
                .map_err(|m| format!("--particles {n}: {m}"))?;
        }
        Ok(())
    }
}
