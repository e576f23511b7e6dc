//! The three lessons, as scene files compiled into the program. `lerpit
//! scene NAME` prints them, so a user's own scene can start from one.

use super::{Scene, parse_scene};
use crate::sim::config::{Choice, variant_array};
use serde::Serialize;
use strum::{EnumCount, VariantArray};

/// The lessons, in the order the visualiser and the study go through them.
/// Named like every choice (see [`Choice`]): `pingpong`, `gravity`,
/// `collisions`.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    strum::VariantArray,
    strum::EnumCount,
    strum::IntoStaticStr,
    strum::Display,
    strum::EnumString,
    strum::EnumMessage,
)]
#[strum(serialize_all = "kebab-case")]
#[serde(into = "&'static str")]
pub enum Lesson {
    /// One sphere between floor and ceiling, no forces, flipping walls.
    Pingpong,
    /// Many small spheres under gravity, walls with restitution 0.95.
    Gravity,
    /// Spheres of several sizes and masses colliding, all pairs tested.
    Collisions,
}

impl Choice for Lesson {
    const KIND: &'static str = "lesson";
}

impl Lesson {
    /// Every lesson, in order.
    pub const ALL: [Lesson; Lesson::COUNT] = variant_array(Self::VARIANTS);

    /// The lesson's name: `lerpit scene NAME`, `--lesson NAME`.
    pub fn name(self) -> &'static str {
        Choice::name(self)
    }

    /// The scene file, as shipped.
    pub fn source(self) -> &'static str {
        match self {
            Lesson::Pingpong => include_str!("lessons/pingpong.toml"),
            Lesson::Gravity => include_str!("lessons/gravity.toml"),
            Lesson::Collisions => include_str!("lessons/collisions.toml"),
        }
    }

    /// How a lesson's scene names its origin in messages: `lesson NAME`.
    pub fn origin(name: &str) -> String {
        format!("lesson {name}")
    }

    pub fn scene(self) -> Scene {
        parse_scene(self.source(), &Self::origin(self.name()), self.name())
            .expect("the built-in lessons are valid scenes (tested)")
    }
}
