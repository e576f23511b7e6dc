//! The energy log: kinetic, potential and total energy and the momentum
//! after each step, the newest samples kept.
//!
//! Owns the samples; the session records one per step and drops those
//! after a restored step when stepping back. The chart that draws them is
//! `energy_chart.rs`.

use crate::sim::{Vec3, World};
use std::collections::VecDeque;

/// Samples kept: the chart shows at most this many steps.
pub(crate) const SAMPLES: usize = 1200;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub steps: u64,
    pub time: f64,
    pub kinetic: f64,
    pub potential: f64,
    pub total: f64,
    /// Sum of `m v`, kg m/s.
    pub momentum: Vec3,
}

impl Sample {
    /// `world`'s step, time, energies and momentum now.
    pub fn of(world: &World) -> Self {
        let d = world.diagnostics();
        Self {
            steps: d.steps,
            time: d.time,
            kinetic: d.kinetic_energy,
            potential: d.potential_energy,
            total: d.total_energy,
            momentum: d.momentum,
        }
    }
}

#[derive(Clone, Debug)]
pub struct EnergyLog {
    samples: VecDeque<Sample>,
}

impl EnergyLog {
    /// A log holding `world`'s current energies.
    pub fn new(world: &World) -> Self {
        let mut log = Self {
            samples: VecDeque::with_capacity(SAMPLES),
        };
        log.record(world);
        log
    }

    pub(crate) fn record(&mut self, world: &World) {
        if self.samples.len() == SAMPLES {
            self.samples.pop_front();
        }
        self.samples.push_back(Sample::of(world));
    }

    /// Take the newest sample again: the energies of the same state
    /// changed (a new gravity changes the potential energy).
    pub(crate) fn record_again(&mut self, world: &World) {
        self.samples.pop_back();
        self.record(world);
    }

    /// The newest sample, if it is of `world`'s present step.
    pub(crate) fn now(&self, world: &World) -> Option<&Sample> {
        self.samples.back().filter(|s| s.steps == world.steps)
    }

    /// Forget samples taken after step `steps`.
    pub(crate) fn truncate_after(&mut self, steps: u64) {
        while self.samples.back().is_some_and(|s| s.steps > steps) {
            self.samples.pop_back();
        }
    }

    pub fn len(&self) -> usize {
        self.samples.len()
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The oldest sample kept and the newest.
    pub(crate) fn ends(&self) -> Option<(&Sample, &Sample)> {
        self.samples.front().zip(self.samples.back())
    }

    pub fn samples(&self) -> impl Iterator<Item = &Sample> {
        self.samples.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;

    #[test]
    fn the_log_keeps_its_newest_samples_and_truncates_on_step_back() {
        let mut world = Lesson::Pingpong.scene().build().unwrap();
        let mut log = EnergyLog::new(&world);
        for _ in 0..SAMPLES + 5 {
            world.step();
            log.record(&world);
        }
        assert_eq!(log.len(), SAMPLES);
        log.truncate_after(world.steps - 3);
        assert_eq!(log.samples().last().unwrap().steps, world.steps - 3);
        let ke = log.samples().next().unwrap().kinetic;
        assert_eq!(ke, 0.5, "m v^2 / 2 with m = 1 kg, v = 1 m/s");
    }
}
