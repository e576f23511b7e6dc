//! How often the view draws. The world steps on every core, and drawing a
//! frame takes the main thread's share of one (a few milliseconds at
//! 100,000 spheres, and the terminal then has to show it). While the
//! steps need most of real time to keep the pace asked, the view draws at
//! most [`BUSY_FPS`] frames a second instead of [`FPS`], and leaves those
//! cores to the steps; it goes back to [`FPS`] once the steps need well
//! under it (two thresholds, so that it does not flicker between the two).
//! Paused, it draws at [`FPS`]: no step is waiting for the cores.
//!
//! Owns the choice only; it reads no clock (the worker's measured pace
//! comes in) and draws nothing.

use super::frame::Pace;
use std::time::Duration;

/// Most frames drawn per second.
const FPS: f64 = 60.0;
/// Most frames drawn per second while the steps are busy.
pub(crate) const BUSY_FPS: f64 = 30.0;
/// Share of real time the steps take, at the pace asked, from which the
/// view draws at [`BUSY_FPS`].
const BUSY_FROM: f64 = 0.5;
/// Share of real time under which it draws at [`FPS`] again.
const CALM_BELOW: f64 = 0.3;

/// The view's drawing rate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct DrawRate {
    held: bool,
}

impl DrawRate {
    /// The share of real time that steps of `step_ms` take, one every
    /// `dt / time_scale` seconds: 1 when they take all of it.
    pub(crate) fn load(step_ms: f64, dt: f64, time_scale: f64) -> f64 {
        let load = step_ms * 1e-3 * time_scale / dt;
        if load.is_nan() { 0.0 } else { load }
    }

    /// Look at the newest pace: `running` (not paused), the last step's
    /// time and whether the world fell behind, at `dt` and `time_scale`.
    pub(crate) fn update(&mut self, running: bool, pace: &Pace, dt: f64, time_scale: f64) {
        let load = pace
            .step_ms
            .map_or(0.0, |ms| Self::load(ms, dt, time_scale));
        self.held = running
            && if self.held {
                load >= CALM_BELOW || pace.behind
            } else {
                load >= BUSY_FROM || pace.behind
            };
    }

    /// Whether the view draws at [`BUSY_FPS`].
    pub(crate) fn held(&self) -> bool {
        self.held
    }

    /// The most frames a second now.
    pub(crate) fn fps(&self) -> f64 {
        if self.held { BUSY_FPS } else { FPS }
    }

    /// The least time between two frames now.
    pub(crate) fn interval(&self) -> Duration {
        Duration::from_secs_f64(1.0 / self.fps())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1.0 / 60.0;

    fn pace(step_ms: f64, behind: bool) -> Pace {
        Pace {
            step_ms: Some(step_ms),
            behind,
            ..Pace::default()
        }
    }

    #[test]
    fn the_load_is_the_share_of_real_time_the_steps_take() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(DrawRate::load(8.0, 1.0 / 125.0, 1.0), 1.0));
        assert!(close(DrawRate::load(4.0, 1.0 / 125.0, 0.5), 0.25));
        assert!(close(DrawRate::load(2.0, 1.0 / 125.0, 4.0), 1.0));
        assert_eq!(DrawRate::load(f64::NAN, DT, 1.0), 0.0);
    }

    #[test]
    fn busy_steps_hold_the_view_to_fewer_frames_until_they_calm_down() {
        let mut rate = DrawRate::default();
        assert_eq!(rate.fps(), FPS);
        // A step of 6 ms every 16.7 ms: 36%, not yet busy.
        rate.update(true, &pace(6.0, false), DT, 1.0);
        assert!(!rate.held());
        // 10 ms: 60%.
        rate.update(true, &pace(10.0, false), DT, 1.0);
        assert!(rate.held());
        assert_eq!(rate.fps(), BUSY_FPS);
        assert_eq!(rate.interval(), Duration::from_secs_f64(1.0 / BUSY_FPS));
        // Back to 36%: between the thresholds, it stays held.
        rate.update(true, &pace(6.0, false), DT, 1.0);
        assert!(rate.held());
        // 3 ms: 18%, calm again.
        rate.update(true, &pace(3.0, false), DT, 1.0);
        assert!(!rate.held());
        assert_eq!(rate.interval(), Duration::from_secs_f64(1.0 / FPS));
    }

    #[test]
    fn a_world_behind_holds_it_and_a_paused_one_never_does() {
        let mut rate = DrawRate::default();
        rate.update(true, &pace(1.0, true), DT, 1.0);
        assert!(rate.held(), "behind, whatever the last step took");
        rate.update(false, &pace(100.0, true), DT, 1.0);
        assert!(!rate.held(), "paused: no step waits for the cores");
        // A faster time scale owes more steps in the same real time.
        rate.update(true, &pace(3.0, false), DT, 4.0);
        assert!(rate.held(), "3 ms at x4 is 72%");
        rate.update(true, &Pace::default(), DT, 1.0);
        assert!(!rate.held(), "no step measured yet");
    }
}
