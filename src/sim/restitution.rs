//! The rest rules: below a small approach speed an impact is perfectly
//! inelastic.
//!
//! With `c_r < 1` a ball bouncing on a floor makes infinitely many ever
//! smaller bounces before it rests, in finite time. A fixed-step method
//! cannot follow them: gravity adds `g dt` of approach speed every step, the
//! wall returns `c_r` of it, and the ball locks into a micro-bounce of one
//! step that never dies out. Two rules end the series:
//!
//! - the rest threshold `v_rest` (m/s, `WorldConfig::rest_threshold`, off by
//!   default): an impact slower than `v_rest` keeps no normal speed;
//! - resting contact (`WorldConfig::rest_steps`, on by default for the
//!   discrete methods): an impact slower than the speed gravity adds along
//!   its normal in `rest_steps` (sub-)steps, `rest_steps |g . n| h`, keeps no
//!   normal speed. Such an impact is not a bounce the step can show: its
//!   rebound would land again within a step or two. It is a body resting on
//!   a wall or on another body, which the normal force holds up. At a wall
//!   only gravity's push into that wall counts; between two spheres (which
//!   both feel the same gravity, so one of them is held up by something
//!   else) the component along the normal, either way. Sideways impacts
//!   keep the lesson's rules at every speed, and nothing here is friction:
//!   a resting sphere still slides.
//!
//! Every impact faster than both keeps the lesson's restitution. This owns
//! only the rule; the wall stage, the contact solver and the continuous
//! method each call it where they apply restitution. The continuous method
//! follows the bounces exactly, and its impacts carry no rest rule; its
//! resting contact holds a touching pair at contact for the rest of the
//! step instead (`continuous.rs`).

use super::Vec3;

/// The coefficient an impact uses: `coefficient` when the approach speed is
/// at least `rest_threshold` (m/s), else 0. A threshold of 0 never fires.
#[inline]
pub(crate) fn restitution_at(coefficient: f64, approach_speed: f64, rest_threshold: f64) -> f64 {
    if approach_speed < rest_threshold {
        0.0
    } else {
        coefficient
    }
}

/// A coefficient of restitution with its rest rules: what an impact needs
/// to know to choose its restitution. A bare `f64` converts to a
/// coefficient with no rest rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// In `[0, 1]`.
    pub coefficient: f64,
    /// Approach speed below which the impact is perfectly inelastic, m/s.
    pub rest_threshold: f64,
    /// The velocity gravity adds over the resting window
    /// (`g rest_steps h`), m/s: an impact slower than its component along
    /// the impact's normal is resting contact (zero: no such rule).
    pub resting: Vec3,
    /// Resting pairs are left to the support pass (`support.rs`) instead
    /// of being resolved as impacts with `e = 0`.
    pub(crate) supported: bool,
}

impl Restitution {
    pub fn new(coefficient: f64, rest_threshold: f64) -> Self {
        Self {
            coefficient,
            rest_threshold,
            resting: Vec3::ZERO,
            supported: false,
        }
    }

    /// This rule with resting contact over the velocity `resting`
    /// (`g rest_steps h`).
    pub(crate) fn with_resting(self, resting: Vec3) -> Self {
        Self { resting, ..self }
    }

    /// This rule, leaving resting pairs to the support pass.
    pub(crate) fn with_support(self, supported: bool) -> Self {
        Self { supported, ..self }
    }

    /// A pair approaching at `approach_speed` (negative: separating) along
    /// `n` rests, and the support pass holds it: the lesson's pass leaves
    /// it alone.
    #[inline]
    pub(crate) fn left_to_support(self, approach_speed: f64, n: Vec3) -> bool {
        self.supported && approach_speed < self.resting.dot(n).abs()
    }

    /// The coefficient for an impact approaching at `approach_speed`, by
    /// the rest threshold alone.
    #[inline]
    pub fn at(self, approach_speed: f64) -> f64 {
        restitution_at(self.coefficient, approach_speed, self.rest_threshold)
    }

    /// The coefficient for a pair impact approaching at `approach_speed`
    /// along the unit normal `n`: 0 below the rest threshold or below the
    /// resting speed along `n`.
    #[inline]
    pub(crate) fn at_pair(self, approach_speed: f64, n: Vec3) -> f64 {
        let resting = self.resting.dot(n).abs();
        restitution_at(
            self.coefficient,
            approach_speed,
            self.rest_threshold.max(resting),
        )
    }

    /// The coefficient for a wall impact approaching at `approach_speed`
    /// along `axis` (`upper`: the wall at `1 - r`): 0 below the rest
    /// threshold or below the resting speed gravity gives into this wall.
    #[inline]
    pub(crate) fn at_wall(self, approach_speed: f64, axis: usize, upper: bool) -> f64 {
        let into = if upper {
            self.resting[axis]
        } else {
            -self.resting[axis]
        };
        restitution_at(
            self.coefficient,
            approach_speed,
            self.rest_threshold.max(into),
        )
    }
}

impl From<f64> for Restitution {
    fn from(coefficient: f64) -> Self {
        Self::new(coefficient, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resting_contact_counts_gravity_into_the_wall_only() {
        let rule = Restitution::new(0.9, 0.0).with_resting(Vec3::new(0.0, -0.2, 0.0));
        assert_eq!(rule.at_wall(0.1, 1, false), 0.0, "slow onto the floor");
        assert_eq!(rule.at_wall(0.3, 1, false), 0.9, "fast onto the floor");
        assert_eq!(rule.at_wall(0.1, 1, true), 0.9, "the ceiling");
        assert_eq!(rule.at_wall(0.1, 0, false), 0.9, "a side wall");
    }

    #[test]
    fn resting_contact_between_spheres_counts_gravity_along_the_normal() {
        let rule = Restitution::new(0.9, 0.0).with_resting(Vec3::new(0.0, -0.2, 0.0));
        assert_eq!(rule.at_pair(0.1, Vec3::Y), 0.0);
        assert_eq!(rule.at_pair(0.1, -Vec3::Y), 0.0);
        assert_eq!(rule.at_pair(0.1, Vec3::X), 0.9, "side by side");
        assert_eq!(rule.at_pair(0.3, Vec3::Y), 0.9);
    }
}
