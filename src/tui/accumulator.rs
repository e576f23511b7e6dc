//! Fixed-step timing ("Fix Your Timestep"): physics advances in whole steps
//! of `dt` however fast frames are drawn. Real time, scaled by the time
//! scale, is added to an accumulator and drained one `dt` at a time.
//!
//! Against the spiral of death (steps too slow to keep up, each frame owing
//! more steps than the last): a frame adds at most [`MAX_FRAME_SECONDS`] of
//! real time, owes at most [`MAX_STEPS_PER_FRAME`] steps, and the event
//! loop drops the backlog when stepping runs over its time budget. The
//! simulation then runs slower than real time instead of freezing.
//!
//! Owns the accumulator only; it never steps the world and never reads a
//! clock (the event loop passes elapsed time in).

/// Real time one frame may add, s.
pub(crate) const MAX_FRAME_SECONDS: f64 = 0.25;
/// Steps one frame may owe.
pub(crate) const MAX_STEPS_PER_FRAME: u32 = 1000;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Accumulator {
    /// Simulated time owed, s.
    pending: f64,
}

impl Accumulator {
    /// Add `elapsed` real seconds at `time_scale`; return the number of
    /// steps of `dt` now due, and keep the remainder.
    pub(crate) fn advance(&mut self, elapsed: f64, time_scale: f64, dt: f64) -> u32 {
        if !(elapsed.is_finite() && time_scale.is_finite() && dt > 0.0) {
            return 0;
        }
        self.pending += elapsed.clamp(0.0, MAX_FRAME_SECONDS) * time_scale.max(0.0);
        let due = (self.pending / dt).floor();
        if due >= f64::from(MAX_STEPS_PER_FRAME) {
            self.pending = 0.0;
            return MAX_STEPS_PER_FRAME;
        }
        self.pending -= due * dt;
        due as u32
    }

    /// Forget the time owed (after a pause, or when steps ran over budget).
    pub(crate) fn drop_backlog(&mut self) {
        self.pending = 0.0;
    }

    pub(crate) fn pending(&self) -> f64 {
        self.pending
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_steps_are_taken_and_the_remainder_carried() {
        let mut a = Accumulator::default();
        let dt = 0.01;
        assert_eq!(a.advance(0.025, 1.0, dt), 2);
        assert!((a.pending() - 0.005).abs() < 1e-12);
        assert_eq!(
            a.advance(0.005, 1.0, dt),
            1,
            "the carried half step completes"
        );
        assert_eq!(a.advance(0.01, 0.5, dt), 0, "slow motion: half a step");
        assert_eq!(a.advance(0.01, 4.0, dt), 4, "0.005 + 0.04 s owed: 4 steps");
    }

    #[test]
    fn a_long_stall_cannot_spiral() {
        let mut a = Accumulator::default();
        assert_eq!(
            a.advance(10.0, 1.0, 0.01),
            25,
            "at most a quarter second a frame"
        );
        assert_eq!(a.advance(0.25, 4.0, 1e-4), MAX_STEPS_PER_FRAME);
        assert_eq!(a.pending(), 0.0, "the backlog beyond the cap is dropped");
        assert_eq!(a.advance(f64::NAN, 1.0, 0.01), 0);
        assert_eq!(a.advance(-1.0, 1.0, 0.01), 0);
    }
}
