//! The three lessons, as scene files compiled into the program. `lerpit
//! scene NAME` prints them, so a user's own scene can start from one.

use super::{Scene, parse_scene};
use crate::sim::config::choice;

choice! {
    /// The lessons, in the order the visualiser and the study go through
    /// them.
    pub enum Lesson: "lesson" {
        /// One sphere between floor and ceiling, no forces, flipping walls.
        Pingpong,
        /// Many small spheres under gravity, walls with restitution 0.95.
        Gravity,
        /// Spheres of several sizes and masses colliding, all pairs tested.
        Collisions,
    }
}

impl Lesson {
    /// The scene file, as shipped.
    pub(crate) fn source(self) -> &'static str {
        match self {
            Lesson::Pingpong => include_str!("lessons/pingpong.toml"),
            Lesson::Gravity => include_str!("lessons/gravity.toml"),
            Lesson::Collisions => include_str!("lessons/collisions.toml"),
        }
    }

    /// How a lesson's scene names its origin in messages: `lesson NAME`.
    pub(crate) fn origin(name: &str) -> String {
        format!("lesson {name}")
    }

    pub fn scene(self) -> Scene {
        parse_scene(self.source(), &Self::origin(self.name()), self.name())
            .expect("the built-in lessons are valid scenes (tested)")
    }
}
