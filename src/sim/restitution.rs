//! The restitution threshold: below a small approach speed an impact is
//! perfectly inelastic.
//!
//! With `c_r < 1` a ball bouncing on a floor makes infinitely many ever
//! smaller bounces before it rests, in finite time. A fixed-step method
//! cannot follow them: gravity adds `g dt` of approach speed every step, the
//! wall returns `c_r` of it, and the ball locks into a micro-bounce of one
//! step that never dies out. A threshold `v_rest` ends the series: an impact
//! slower than `v_rest` keeps no normal speed, and the ball rests. This owns
//! only the rule; the wall stage, the contact solver and the continuous
//! method each call it where they apply restitution.

/// The coefficient an impact uses: `coefficient` when the approach speed is
/// at least `rest_threshold` (m/s), else 0. A threshold of 0 never fires.
#[inline]
pub fn restitution_at(coefficient: f64, approach_speed: f64, rest_threshold: f64) -> f64 {
    if approach_speed < rest_threshold {
        0.0
    } else {
        coefficient
    }
}

/// A coefficient of restitution with its rest threshold: what an impact
/// needs to know to choose its restitution. A bare `f64` converts to a
/// coefficient with no threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restitution {
    /// In `[0, 1]`.
    pub coefficient: f64,
    /// Approach speed below which the impact is perfectly inelastic, m/s.
    pub rest_threshold: f64,
}

impl Restitution {
    pub fn new(coefficient: f64, rest_threshold: f64) -> Self {
        Self {
            coefficient,
            rest_threshold,
        }
    }

    /// The coefficient for an impact approaching at `approach_speed`.
    #[inline]
    pub fn at(self, approach_speed: f64) -> f64 {
        restitution_at(self.coefficient, approach_speed, self.rest_threshold)
    }
}

impl From<f64> for Restitution {
    fn from(coefficient: f64) -> Self {
        Self::new(coefficient, 0.0)
    }
}
