//! Scenes as data: which bodies, which stages, which parameters.
//!
//! A [`Scene`] is the recipe a [`World`] is built from: explicit bodies,
//! seeded random spawns and a [`WorldConfig`]. The three lessons are scene
//! files compiled into the program (`lessons/*.toml`); users write their own
//! in the same format (see [`file`]).

pub mod error;
pub mod file;
pub mod lessons;
pub mod rules;

pub use error::SceneError;
pub use file::parse_scene;
pub use lessons::Lesson;

use crate::sim::spawn::spawn_bodies;
use crate::sim::{Bodies, Body, Spawn, World, WorldConfig};

/// What the visualiser's side panel says about a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LessonInfo {
    pub title: String,
    pub idea: String,
    pub equation: String,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name: the lesson's, or the file's stem.
    pub name: String,
    /// Where it came from, for messages: a path or `lesson NAME`.
    pub origin: String,
    pub info: Option<LessonInfo>,
    pub world: WorldConfig,
    /// Seed of every random choice the scene makes.
    pub seed: u64,
    pub bodies: Vec<Body>,
    pub spawns: Vec<Spawn>,
    /// Source line of each `[[spawn]]`, for messages.
    pub spawn_lines: Vec<usize>,
}

impl Scene {
    /// Read a scene file.
    pub fn from_file(path: &std::path::Path) -> Result<Scene, SceneError> {
        let origin = path.display().to_string();
        let source = std::fs::read_to_string(path)
            .map_err(|e| SceneError::new(&origin, format!("cannot read the scene file: {e}")))?;
        let name = path
            .file_stem()
            .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned());
        parse_scene(&source, &origin, &name)
    }

    /// How many spheres the spawns place.
    pub fn spawned(&self) -> usize {
        self.spawns.iter().map(|s| s.count).sum()
    }

    /// How many spheres the built world holds.
    pub fn body_count(&self) -> usize {
        self.bodies.len() + self.spawned()
    }

    /// Resize the spawns to place `n` spheres in all, keeping their
    /// proportions (largest remainder, ties to the earlier spawn). Refused
    /// when the scene has no spawns.
    pub fn set_particles(&mut self, n: usize) -> Result<(), String> {
        let total = self.spawned();
        if self.spawns.is_empty() {
            return Err(format!(
                "the scene '{}' places no random spheres (it has no [[spawn]] entries)",
                self.name
            ));
        }
        let weights: Vec<f64> = if total == 0 {
            vec![1.0; self.spawns.len()]
        } else {
            self.spawns.iter().map(|s| s.count as f64).collect()
        };
        let sum: f64 = weights.iter().sum();
        let exact: Vec<f64> = weights.iter().map(|w| w / sum * n as f64).collect();
        let mut counts: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
        let mut order: Vec<usize> = (0..counts.len()).collect();
        order.sort_by(|&a, &b| {
            let (fa, fb) = (exact[a] - exact[a].floor(), exact[b] - exact[b].floor());
            fb.total_cmp(&fa).then(a.cmp(&b))
        });
        let short = n - counts.iter().sum::<usize>();
        for &k in order.iter().take(short) {
            counts[k] += 1;
        }
        for (s, c) in self.spawns.iter_mut().zip(counts) {
            s.count = c;
        }
        self.check_size().map_err(|e| e.message)
    }

    /// A scene must hold at least one and at most [`rules::MAX_BODIES`] spheres.
    pub fn check_size(&self) -> Result<(), SceneError> {
        let n = self.body_count();
        if n == 0 {
            return Err(SceneError::new(
                &self.origin,
                "the scene has no bodies: add a [[body]] or a [[spawn]] entry",
            ));
        }
        if n > rules::MAX_BODIES {
            return Err(SceneError::new(
                &self.origin,
                format!(
                    "the scene holds {n} spheres; at most {} are allowed",
                    rules::MAX_BODIES
                ),
            ));
        }
        Ok(())
    }

    /// Build the world: explicit bodies first, then each spawn in order.
    pub fn build(&self) -> Result<World, SceneError> {
        let mut bodies = Bodies::with_capacity(self.body_count());
        for &b in &self.bodies {
            bodies.push(b);
        }
        spawn_bodies(&mut bodies, &self.spawns, self.seed).map_err(|e| {
            let mut error =
                SceneError::new(&self.origin, e.to_string()).field(format!("spawn[{}]", e.spawn()));
            if let Some(&line) = self.spawn_lines.get(e.spawn()) {
                error.at = Some((line, 1));
            }
            error
        })?;
        Ok(World::new(self.world.clone(), bodies))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_lesson_parses_and_builds() {
        for lesson in Lesson::ALL {
            let scene = lesson.scene();
            let world = scene.build().unwrap();
            assert_eq!(world.bodies.len(), scene.body_count());
            assert!(
                scene.info.is_some(),
                "{} has its lesson text",
                lesson.name()
            );
        }
    }

    #[test]
    fn set_particles_keeps_the_spawn_proportions_and_the_total() {
        let mut scene = Lesson::Collisions.scene();
        scene.set_particles(1000).unwrap();
        let counts: Vec<usize> = scene.spawns.iter().map(|s| s.count).collect();
        assert_eq!(counts, [800, 150, 50]);
        scene.set_particles(7).unwrap();
        let counts: Vec<usize> = scene.spawns.iter().map(|s| s.count).collect();
        assert_eq!(counts.iter().sum::<usize>(), 7);
        assert_eq!(counts, [6, 1, 0]);
        assert!(Lesson::Pingpong.scene().set_particles(3).is_err());
    }

    #[test]
    fn a_spawn_that_cannot_fit_is_reported_at_its_line() {
        let text = "[world]\ndt = 0.01\n\n[[spawn]]\ncount = 400\nradius = [0.07, 0.07]\n";
        let scene = parse_scene(text, "t.toml", "t").unwrap();
        let err = scene.build().unwrap_err();
        assert_eq!(err.at, Some((4, 1)));
        assert_eq!(err.field.as_deref(), Some("spawn[0]"));
    }
}
