//! The study's verdicts: each goal with its threshold, and whether the
//! measurements meet it. The command line prints them; nothing here writes
//! text.
//!
//! - gravity lesson, continuous method: the bounce-time and apex-ratio
//!   errors at most [`BOUNCE_TIME_GOAL`] and [`APEX_RATIO_GOAL`] at every
//!   `dt`, and a cost per step at most [`COST_RATIO_GOAL`] times
//!   semi-implicit Euler's;
//! - elastic collisions without gravity (see [`conservation`]), continuous
//!   method: a momentum error at most [`MOMENTUM_GOAL`] and an energy
//!   drift below [`ENERGY_DRIFT_GOAL`];
//! - the collisions lesson's predictability horizon: how long moving one
//!   sphere by [`NUDGE`] takes to move the exact reference by
//!   [`DIVERGED`]; the sweep must compare positions before then.
//!
//! [`conservation`]: super::conservation

use super::conservation::Drift;
use super::sweep::Row;
use crate::scene::{Lesson, SceneError};
use crate::sim::Integrator;
use crate::sim::reference::collisions::predictability_horizon;

/// Largest bounce-time error of the continuous method, s.
pub(crate) const BOUNCE_TIME_GOAL: f64 = 1e-12;
/// Largest apex-ratio error of the continuous method.
pub(crate) const APEX_RATIO_GOAL: f64 = 1e-12;
/// Largest cost per step of the continuous method over semi-implicit
/// Euler's, at the same `dt`.
pub(crate) const COST_RATIO_GOAL: f64 = 2.0;
/// Largest momentum error of the continuous method in the conservation run.
pub(crate) const MOMENTUM_GOAL: f64 = 1e-12;
/// The continuous method's energy drift in the conservation run stays
/// below this.
pub(crate) const ENERGY_DRIFT_GOAL: f64 = 1e-9;

/// Nudge applied to one sphere to find the predictability horizon, m.
pub(crate) const NUDGE: f64 = 1e-12;
/// Distance (RMS) at which two runs no longer tell the same story, m.
pub(crate) const DIVERGED: f64 = 1e-3;
/// The horizon is looked for every this many seconds, up to
/// [`HORIZON_LIMIT`].
pub(crate) const HORIZON_INTERVAL: f64 = 0.01;
pub(crate) const HORIZON_LIMIT: f64 = 5.0;

/// A measured figure against its goal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Goal {
    pub value: f64,
    pub limit: f64,
    /// `value <= limit` meets the goal; otherwise only `value < limit`.
    pub inclusive: bool,
}

impl Goal {
    pub(crate) fn at_most(value: f64, limit: f64) -> Self {
        Self {
            value,
            limit,
            inclusive: true,
        }
    }

    pub(crate) fn below(value: f64, limit: f64) -> Self {
        Self {
            value,
            limit,
            inclusive: false,
        }
    }

    /// Whether the figure meets the goal (a NaN never does).
    pub(crate) fn met(&self) -> bool {
        if self.inclusive {
            self.value <= self.limit
        } else {
            self.value < self.limit
        }
    }
}

/// The gravity goal: the continuous method on the gravity lesson.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GravityGoal {
    /// The worst bounce-time error over every `dt`, s.
    pub bounce_time: Goal,
    /// The worst apex-ratio error over every `dt`.
    pub apex_ratio: Goal,
    /// The largest `dt` swept, s.
    pub largest_dt: f64,
    /// Per `dt` (s): cost per step over semi-implicit Euler's.
    pub cost_ratios: Vec<(f64, Goal)>,
}

impl GravityGoal {
    /// From the sweep's rows; `None` unless both methods ran on the
    /// gravity lesson.
    pub fn of(rows: &[Row]) -> Option<Self> {
        let of = |m: Integrator| -> Vec<&Row> {
            rows.iter()
                .filter(|r| r.lesson == Lesson::Gravity && r.method == m)
                .collect()
        };
        let (cont, sie) = (
            of(Integrator::Continuous),
            of(Integrator::SemiImplicitEuler),
        );
        if cont.is_empty() || sie.is_empty() {
            return None;
        }
        let worst =
            |f: fn(&Row) -> Option<f64>| cont.iter().filter_map(|r| f(r)).fold(0.0, f64::max);
        Some(Self {
            bounce_time: Goal::at_most(worst(|r| r.bounce_time_error), BOUNCE_TIME_GOAL),
            apex_ratio: Goal::at_most(worst(|r| r.apex_ratio_error), APEX_RATIO_GOAL),
            largest_dt: cont.iter().map(|r| r.dt).fold(0.0, f64::max),
            cost_ratios: cont
                .iter()
                .zip(&sie)
                .map(|(c, s)| {
                    let ratio = c.ns_per_body_step / s.ns_per_body_step;
                    (c.dt, Goal::at_most(ratio, COST_RATIO_GOAL))
                })
                .collect(),
        })
    }

    /// Each `dt` at which the cost goal is missed, in the order measured;
    /// empty when it is met at every `dt`.
    pub(crate) fn cost_missed_at(&self) -> Vec<f64> {
        self.cost_ratios
            .iter()
            .filter(|(_, g)| !g.met())
            .map(|&(dt, _)| dt)
            .collect()
    }
}

/// The conservation goal: the continuous method's run of elastic
/// collisions without gravity.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ConservationGoal {
    pub run: Drift,
    pub momentum: Goal,
    pub energy: Goal,
}

impl ConservationGoal {
    /// From the conservation runs; `None` without the continuous one.
    pub fn of(drifts: &[Drift]) -> Option<Self> {
        let run = drifts
            .iter()
            .find(|d| d.method == Integrator::Continuous)?
            .clone();
        Some(Self {
            momentum: Goal::at_most(run.momentum_error, MOMENTUM_GOAL),
            energy: Goal::below(run.energy_drift, ENERGY_DRIFT_GOAL),
            run,
        })
    }
}

/// Where the collisions lesson stops being predictable, and whether the
/// sweep compares its positions before then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Horizon {
    /// When the nudged reference is [`DIVERGED`] from the plain one, s;
    /// `None` if not within [`HORIZON_LIMIT`].
    pub diverged_at: Option<f64>,
    /// When the sweep compares positions, s.
    pub compared_at: f64,
}

impl Horizon {
    /// The collisions lesson's horizon, for a sweep comparing at
    /// `compared_at` s.
    pub(crate) fn of_collisions(compared_at: f64) -> Result<Self, SceneError> {
        let world = Lesson::Collisions.scene().build()?;
        Ok(Self {
            diverged_at: predictability_horizon(
                &world,
                NUDGE,
                DIVERGED,
                HORIZON_INTERVAL,
                HORIZON_LIMIT,
            ),
            compared_at,
        })
    }

    /// Whether the sweep compares positions while they still say something.
    pub(crate) fn compared_inside(&self) -> bool {
        self.diverged_at.is_none_or(|t| self.compared_at < t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_goal_at_most_takes_its_limit_and_one_below_does_not() {
        assert!(Goal::at_most(1e-12, 1e-12).met());
        assert!(!Goal::below(1e-9, 1e-9).met());
        assert!(Goal::below(0.5e-9, 1e-9).met());
        assert!(!Goal::at_most(f64::NAN, 1.0).met());
    }

    #[test]
    fn the_cost_goal_is_missed_at_each_dt_over_the_ratio() {
        let goal = GravityGoal {
            bounce_time: Goal::at_most(0.0, BOUNCE_TIME_GOAL),
            apex_ratio: Goal::at_most(0.0, APEX_RATIO_GOAL),
            largest_dt: 0.1,
            cost_ratios: [(0.1, 1.5), (0.01, 2.5), (0.001, 1.9), (0.0001, 3.0)]
                .map(|(dt, r)| (dt, Goal::at_most(r, COST_RATIO_GOAL)))
                .to_vec(),
        };
        assert_eq!(goal.cost_missed_at(), [0.01, 0.0001]);
        let met = GravityGoal {
            cost_ratios: vec![(0.1, Goal::at_most(2.0, COST_RATIO_GOAL))],
            ..goal
        };
        assert!(met.cost_missed_at().is_empty());
    }
}
