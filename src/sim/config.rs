//! What a world runs. `WorldConfig::default()` is the one place defaults
//! live; every field says its unit. A scene file's `[world]` table and the
//! command line's overrides both end here.
//!
//! The choices among them (the integrator, the broad phase, the wall mode;
//! elsewhere the mass law and the lesson) are enums that name themselves:
//! each lists its variants once, and strum derives from that list the rest
//! (`VariantArray` the list, `IntoStaticStr` and `Display` the kebab-case
//! names, `EnumString` the parsing, `EnumMessage` the doc line of each).
//! [`Choice`] adds what they share: what one is called in messages, the
//! refusal of an unknown name, and the next one in order. Scene files,
//! flags and JSON all go through these names. [`choice!`](choice) declares
//! such an enum with all of that in one place.

use super::restitution::Restitution;
use super::{BroadPhase, Integrator, Vec3};
use std::fmt;
use std::str::FromStr;
use strum::{EnumMessage, VariantArray};

/// Standard gravity in the lessons, m/s^2, pointing down (`-y`). The one
/// place the number lives: the default world, the benchmark scene and the
/// references use it; the lesson files write it out (tested to agree).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Gravity of magnitude `g` (m/s^2) pointing down (`-y`). `0 - g`, not
/// `-g`: no gravity is `[0, 0, 0]`, where `-0` would be reported as `-0.0`.
pub fn gravity_down(g: f64) -> Vec3 {
    Vec3::new(0.0, 0.0 - g, 0.0)
}

/// Gravity of magnitude `g` (m/s^2) along `direction`, as the flag
/// `--gravity` and the keys `g`/`G` set it: a scene whose gravity points
/// sideways keeps its direction. Down (`-y`, [`gravity_down`]) when
/// `direction` has none (zero, or not finite) or is down.
pub fn gravity_along(g: f64, direction: Vec3) -> Vec3 {
    let largest = direction.abs().max_element();
    if !(largest > 0.0 && largest.is_finite()) {
        return gravity_down(g);
    }
    // Scaled first, so that a faint gravity's square does not underflow.
    let unit = (direction / largest).normalize();
    if unit == Vec3::NEG_Y {
        gravity_down(g)
    } else {
        // `0 + ...`: a zero component stays `+0` (see above).
        Vec3::ZERO + unit * g
    }
}

/// A choice made by name in scene files, flags and output (see the top of
/// this file). Declare one with [`choice!`](choice); by hand, derive
/// strum's `VariantArray`, `IntoStaticStr`, `EnumString` and `EnumMessage`
/// with `#[strum(serialize_all = "kebab-case")]`.
pub trait Choice:
    Copy + PartialEq + VariantArray + FromStr + Into<&'static str> + EnumMessage
{
    /// What one is called in messages: `integrator`, `broad phase`.
    const KIND: &'static str;

    /// The name in scene files, on the command line and in output.
    fn name(self) -> &'static str {
        self.into()
    }

    /// The choice called `name`; the refusal lists every name.
    fn parse(name: &str) -> Result<Self, UnknownChoice> {
        name.parse().map_err(|_| UnknownChoice {
            kind: Self::KIND,
            given: name.to_string(),
            choices: Self::VARIANTS.iter().map(|&c| c.name()).collect(),
        })
    }

    /// The next choice in declaration order, wrapping around.
    fn next(self) -> Self {
        let i = Self::VARIANTS.iter().position(|&c| c == self).unwrap_or(0);
        Self::VARIANTS[(i + 1) % Self::VARIANTS.len()]
    }

    /// The first paragraph of the variant's doc comment as plain text, for
    /// `--help`: one line, no link markup, no full stop.
    fn about(self) -> Option<String> {
        let doc = self.get_documentation()?;
        let paragraph: Vec<&str> = doc
            .lines()
            .map(str::trim)
            .take_while(|l| !l.is_empty())
            .collect();
        let text = paragraph.join(" ").replace(['[', ']', '`'], "");
        Some(text.trim_end_matches('.').to_string())
    }
}

/// A name that is none of a [`Choice`]'s.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownChoice {
    /// What was asked for: [`Choice::KIND`].
    pub kind: &'static str,
    pub given: String,
    /// Every name, in order.
    pub choices: Vec<&'static str>,
}

impl fmt::Display for UnknownChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown {} '{}'; choose one of {}",
            self.kind,
            self.given,
            self.choices.join(", ")
        )
    }
}

impl std::error::Error for UnknownChoice {}

/// `variants` as an array of `N`, for a choice's `ALL` constant: strum's
/// `VariantArray` gives a slice; a constant array can be indexed and
/// iterated by value. Refused at compile time if the lengths differ.
pub(crate) const fn variant_array<T: Copy, const N: usize>(variants: &[T]) -> [T; N] {
    assert!(variants.len() == N, "the count of variants is wrong");
    let mut out = [variants[0]; N];
    let mut i = 0;
    while i < N {
        out[i] = variants[i];
        i += 1;
    }
    out
}

/// Declares a [`Choice`]: the enum as written, and from its variants the
/// list, the kebab-case names, the parsing, the `--help` lines (each
/// variant's first doc paragraph), the serde form (the same names, the
/// same refusal), `ALL` as an array, and `name()` and `next()` callable
/// without the trait in scope.
///
/// ```text
/// choice! {
///     /// What the enum is.
///     pub enum WallMode: "wall mode" {
///         /// What this one does.
///         Flip,
///         Restitution,
///     }
/// }
/// ```
macro_rules! choice {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident: $kind:literal {
            $($(#[$variant_meta:meta])* $variant:ident,)+
        }
    ) => {
        $(#[$meta])*
        #[derive(
            Clone,
            Copy,
            Debug,
            PartialEq,
            Eq,
            Hash,
            ::serde::Serialize,
            ::serde::Deserialize,
            ::strum::VariantArray,
            ::strum::EnumCount,
            ::strum::IntoStaticStr,
            ::strum::Display,
            ::strum::EnumString,
            ::strum::EnumMessage,
        )]
        #[strum(serialize_all = "kebab-case")]
        #[serde(try_from = "String", into = "&'static str")]
        $vis enum $name {
            $($(#[$variant_meta])* $variant,)+
        }

        impl $crate::sim::config::Choice for $name {
            const KIND: &'static str = $kind;
        }

        impl TryFrom<String> for $name {
            type Error = $crate::sim::config::UnknownChoice;
            fn try_from(name: String) -> Result<Self, Self::Error> {
                <Self as $crate::sim::config::Choice>::parse(&name)
            }
        }

        impl $name {
            /// Every one, in declaration order.
            pub const ALL: [$name; <$name as ::strum::EnumCount>::COUNT] =
                $crate::sim::config::variant_array(<$name as ::strum::VariantArray>::VARIANTS);

            /// The name in scene files, on the command line and in output.
            pub fn name(self) -> &'static str {
                <Self as $crate::sim::config::Choice>::name(self)
            }

            /// The next one in `ALL`, wrapping around.
            pub fn next(self) -> Self {
                <Self as $crate::sim::config::Choice>::next(self)
            }
        }
    };
}
pub(crate) use choice;

choice! {
    /// How a sphere that reaches a wall of the box responds.
    pub enum WallMode: "wall mode" {
        /// The ping-pong lesson: the velocity component normal to the wall
        /// reverses and the speed is kept.
        Flip,
        /// The gravity lesson: `v_n <- -c_r v_n` with `c_r = wall_restitution`.
        Restitution,
    }
}

impl WallMode {
    /// The rule a wall impact follows: `flip` always keeps the speed;
    /// `restitution` uses `restitution`.
    pub(crate) fn rule(self, restitution: Restitution) -> Restitution {
        match self {
            WallMode::Flip => Restitution::new(1.0, 0.0),
            WallMode::Restitution => restitution,
        }
    }
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct WorldConfig {
    /// Uniform gravitational acceleration, m/s^2 (the lessons:
    /// [`STANDARD_GRAVITY`] down).
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
    /// pairs still overlapping (`BodiesMut::project`), stopping
    /// early once none overlaps by more than 1% of the largest radius.
    pub projection_passes: u32,
    /// The support pass (`support.rs`): after the lesson's pass and the
    /// walls, every resting contact, between spheres and against the walls,
    /// is solved together at the velocity level, so that a pile carries its
    /// weight. Needs pair
    /// collisions, gravity and resting contact (`rest_steps > 0`); the
    /// discrete methods only (`WorldConfig::support_idle` says which is
    /// missing).
    pub support: bool,
    /// Sleeping (`sleep.rs`): spheres at rest for half a second stop
    /// costing anything until something disturbs them or a parameter
    /// changes. The discrete methods only.
    pub sleep: bool,
}

impl WorldConfig {
    /// The strength of gravity, `|g|` (m/s^2), taken without squaring a
    /// component that is too small to square (1e-300 m/s^2 is 1e-300, not
    /// 0).
    pub fn gravity_strength(&self) -> f64 {
        let largest = self.gravity.abs().max_element();
        if largest > 0.0 && largest.is_finite() {
            largest * (self.gravity / largest).length()
        } else {
            self.gravity.length()
        }
    }

    /// Whether the support pass runs in this world: asked for and not idle
    /// ([`WorldConfig::support_idle`]).
    pub fn support_runs(&self) -> bool {
        self.support && self.support_idle().is_none()
    }

    /// Why the support pass, though asked for (`support`), does not run in
    /// this world (one of [`SupportIdle`]'s); `None` when it runs or is off.
    pub fn support_idle(&self) -> Option<&'static str> {
        let g = self.gravity_strength();
        if !self.support {
            None
        } else if !self.pair_collisions {
            Some(SupportIdle::NO_PAIRS)
        } else if !(g > 0.0 && g.is_finite()) {
            Some(SupportIdle::NO_GRAVITY)
        } else if self.rest_steps <= 0.0 {
            Some(SupportIdle::NO_RESTING)
        } else if !self.integrator.is_discrete() {
            Some(SupportIdle::CONTINUOUS)
        } else {
            None
        }
    }

    /// Whether spheres sleep in this world: asked for, with a discrete
    /// method (the continuous one moves every sphere to its impacts).
    pub fn sleeps(&self) -> bool {
        self.sleep && self.sleep_idle().is_none()
    }

    /// Why spheres, though asked to sleep (`sleep`), do not in this world;
    /// `None` when they may, or sleeping is off.
    pub fn sleep_idle(&self) -> Option<&'static str> {
        (self.sleep && !self.integrator.is_discrete())
            .then_some("the continuous method moves every sphere to its impacts")
    }

    /// The rule of wall impacts: the wall mode, restitution and threshold.
    pub(crate) fn wall_rule(&self) -> Restitution {
        self.wall_mode
            .rule(Restitution::new(self.wall_restitution, self.rest_threshold))
    }

    /// Wall restitution as the wall stage applies it: 1 for `flip` walls.
    pub(crate) fn wall_coefficient(&self) -> f64 {
        self.wall_rule().coefficient
    }

    /// The rule of sphere-sphere impacts.
    pub(crate) fn pair_rule(&self) -> Restitution {
        Restitution::new(self.pair_restitution, self.rest_threshold)
    }

    /// The rule the contact stages resolve pairs with: resting contact
    /// below `resting` (`resting(h)`), resting pairs left to the support
    /// pass when `supported`. The one place both contact paths take it
    /// from, so that they resolve alike.
    pub(crate) fn contact_rule(&self, resting: Vec3, supported: bool) -> Restitution {
        self.pair_rule()
            .with_resting(resting)
            .with_support(supported)
    }

    /// The velocity gravity adds over the resting window of a sub-step of
    /// `h` s (`g rest_steps h`), m/s.
    pub(crate) fn resting(&self, h: f64) -> Vec3 {
        self.gravity * (self.rest_steps * h)
    }

    /// The length of one sub-step, s.
    pub(crate) fn substep_dt(&self) -> f64 {
        self.dt / f64::from(self.substeps.max(1))
    }
}

impl Default for WorldConfig {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -STANDARD_GRAVITY, 0.0),
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
            support: false,
            sleep: false,
        }
    }
}

/// The reasons [`WorldConfig::support_idle`] gives.
pub struct SupportIdle;

impl SupportIdle {
    pub const NO_PAIRS: &'static str = "there are no pair collisions";
    pub const NO_GRAVITY: &'static str = "there is no gravity";
    pub const NO_RESTING: &'static str =
        "it needs resting contact (rest_steps > 0; y in the visualiser)";
    pub const CONTINUOUS: &'static str = "the continuous method holds resting pairs itself";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gravity_along_keeps_a_direction_and_falls_back_to_down() {
        assert_eq!(
            gravity_along(2.0, Vec3::new(0.0, -9.81, 0.0)),
            gravity_down(2.0)
        );
        assert_eq!(gravity_along(2.0, Vec3::ZERO), gravity_down(2.0));
        assert_eq!(gravity_along(2.0, Vec3::splat(f64::NAN)), gravity_down(2.0));
        // A faint gravity along x keeps x, though its square underflows.
        assert_eq!(
            gravity_along(3.0, Vec3::new(1e-300, 0.0, 0.0)),
            Vec3::new(3.0, 0.0, 0.0)
        );
        let g = gravity_along(10.0, Vec3::new(-3.0, 0.0, 4.0));
        assert!((g - Vec3::new(-6.0, 0.0, 8.0)).length() < 1e-14, "{g}");
        // No gravity is all +0, whatever the direction's signs.
        let none = gravity_along(0.0, Vec3::new(-3.0, -0.0, -4.0));
        assert_eq!(none.to_array().map(f64::to_bits), [0; 3]);
    }
}
