//! How often the view draws. The world steps on every core, and drawing a
//! frame takes the main thread's share of one (a few milliseconds at
//! 100,000 spheres, and the terminal then has to show it). While the
//! steps need most of real time to keep the pace asked, the view draws at
//! most [`BUSY_FPS`] frames a second instead of [`FPS`], and leaves those
//! cores to the steps; it goes back to [`FPS`] once the steps need well
//! under it (two thresholds, so that it does not flicker between the two).
//! Paused, it draws at [`FPS`]: no step is waiting for the cores.
//!
//! Owns the choice, and the measure of the rate drawn ([`FrameRate`], for
//! the panel's `fps` row); it reads no clock (the worker's measured pace
//! and the gaps between frames come in) and draws nothing.

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

/// The frames drawn a second, as measured: a running average of the time
/// between frames (an average of rates would favour the short gaps). It
/// starts afresh whenever the most frames a second changes, and the frame
/// drawn as it changes, timed by the old rate, is not counted: so it never
/// shows a rate the view no longer draws at.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct FrameRate {
    /// The average time between frames, s, since the rate last changed.
    gap: Option<f64>,
    /// The most frames a second the average was measured under.
    most: Option<f64>,
}

impl FrameRate {
    /// A frame drawn `seconds` after the one before, under `most` frames a
    /// second: the frames a second now, or `None` on the frame where
    /// `most` changed.
    pub(crate) fn record(&mut self, seconds: f64, most: f64) -> Option<f64> {
        if self.most != Some(most) {
            *self = Self {
                gap: None,
                most: Some(most),
            };
            return None;
        }
        let seconds = seconds.max(1e-6);
        let gap = self.gap.map_or(seconds, |g| 0.9 * g + 0.1 * seconds);
        self.gap = Some(gap);
        Some(1.0 / gap)
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
    fn the_measured_rate_starts_afresh_when_the_most_frames_change() {
        let mut measured = FrameRate::default();
        assert_eq!(measured.record(1.0 / FPS, FPS), None, "the first frame");
        for _ in 0..50 {
            let fps = measured.record(1.0 / FPS, FPS).unwrap();
            assert!((fps - FPS).abs() < 1e-9, "{fps}");
        }
        // The steps get busy: the frame drawn as the rate changes came
        // 1/60 s after the last, and says nothing of the new rate.
        assert_eq!(measured.record(1.0 / FPS, BUSY_FPS), None);
        let fps = measured.record(1.0 / BUSY_FPS, BUSY_FPS).unwrap();
        assert!((fps - BUSY_FPS).abs() < 1e-9, "{fps}, not the old rate's");
        // An average of the gaps: one gap of 1/10 s among 1/30 s ones.
        let fps = measured.record(0.1, BUSY_FPS).unwrap();
        assert!((fps - 1.0 / (0.9 / BUSY_FPS + 0.1 * 0.1)).abs() < 1e-9);
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
