//! The work-precision sweep: every method at every time step on each lesson,
//! measured against the lesson's exact reference (see [`metrics`]).
//!
//! A [`Plan`] says which lessons, methods and time steps, how long to
//! simulate and how often to repeat the timed runs. Each point is one
//! [`Row`]: cost and error of one method at one `dt` on one lesson. The
//! sweep only reads the library's scenes and worlds; it never changes how a
//! method works.

use super::metrics::{self, BOUNCES, BounceLog};
use crate::scene::{Lesson, rules};
use crate::sim::reference::Reference;
use crate::sim::{Integrator, World};
use serde::Serialize;
use std::time::Instant;

/// What to sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub lessons: Vec<Lesson>,
    pub methods: Vec<Integrator>,
    /// Time steps, s, largest first.
    pub dts: Vec<f64>,
    /// Simulated time of every run, per lesson (same order as `lessons`), s.
    pub horizons: Vec<f64>,
    /// Timed repeats of every run (the fastest is kept).
    pub repeats: usize,
}

/// `count` time steps spaced evenly in `log dt` from `largest` down to
/// `largest / 10^decades`.
pub fn log_spaced(largest: f64, decades: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|k| largest * 10f64.powf(-decades * k as f64 / (count - 1).max(1) as f64))
        .collect()
}

/// The largest time step of the sweeps, s (the gravity goal's 1/30 s).
pub(crate) const LARGEST_DT: f64 = 1.0 / 30.0;

impl Plan {
    /// The full study: three decades of `dt` in ten steps, every method,
    /// every lesson (under a minute on two cores in a release build). The
    /// collisions lesson is compared at 0.1 s, well inside its
    /// predictability horizon (about 1 s): later, chaos amplifies every
    /// error, rounding included, until positions say nothing.
    pub(crate) fn full() -> Plan {
        Plan {
            lessons: Lesson::ALL.to_vec(),
            methods: Integrator::ALL.to_vec(),
            dts: log_spaced(LARGEST_DT, 3.0, 10),
            horizons: vec![2.0, 2.0, 0.1],
            repeats: 5,
        }
    }

    /// Under a second: two decades in eight steps, short horizons, the
    /// fastest of five timed runs as in the full study (a single run's
    /// timing swings by several times on a shared machine).
    pub(crate) fn quick() -> Plan {
        Plan {
            lessons: Lesson::ALL.to_vec(),
            methods: Integrator::ALL.to_vec(),
            dts: log_spaced(LARGEST_DT, 2.0, 8),
            horizons: vec![0.5, 0.5, 0.1],
            repeats: 5,
        }
    }

    /// The simulated time of a lesson's runs, s.
    pub(crate) fn horizon(&self, lesson: Lesson) -> f64 {
        let k = self.lessons.iter().position(|&l| l == lesson).unwrap_or(0);
        self.horizons.get(k).copied().unwrap_or(1.0)
    }

    /// How many runs the plan makes.
    pub(crate) fn runs(&self) -> usize {
        self.lessons.len() * self.methods.len() * self.dts.len()
    }
}

/// One method at one `dt` on one lesson; a line of `sweep.csv`, with the
/// field names as its header.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    pub lesson: Lesson,
    pub method: Integrator,
    /// s.
    pub dt: f64,
    pub steps: u64,
    pub bodies: usize,
    /// Simulated time, s.
    pub horizon: f64,
    /// Wall time of the run, fastest of the repeats, s.
    pub wall_time: f64,
    /// Wall time per simulated second.
    pub cost_per_second: f64,
    /// Wall time per body-step, ns.
    pub ns_per_body_step: f64,
    /// RMS position error at the horizon, m.
    pub rms_error: f64,
    /// Bounce-time error, s (scenes with floor bounces).
    pub bounce_time_error: Option<f64>,
    /// Apex-ratio error (scenes with floor bounces).
    pub apex_ratio_error: Option<f64>,
    /// Relative energy error at the horizon.
    pub energy_error: f64,
    /// The continuous method fell back to the discrete stages in some step.
    pub event_cap_reached: bool,
}

/// How `method`'s error falls with dt in `rows` (see
/// [`metrics::convergence`]); `None` when `rows` has none of its runs.
pub(crate) fn convergence_of<R: std::borrow::Borrow<Row>>(
    rows: &[R],
    method: Integrator,
) -> Option<metrics::Convergence> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| r.borrow())
        .filter(|r| r.method == method)
        .map(|r| (r.dt, r.error()))
        .collect();
    (!pts.is_empty()).then(|| metrics::convergence(&pts))
}

impl Row {
    /// The error the charts show: RMS position error.
    pub(crate) fn error(&self) -> f64 {
        self.rms_error
    }
}

/// A lesson's start and what its exact reference says about bounces.
struct Exact {
    world: World,
    reference: Reference,
    /// The horizon asked for, s (each run ends at the first whole step at
    /// or after it, `rules::steps_for`).
    t: f64,
    energy_start: f64,
    /// Per sphere: exact floor-impact times and whether the first bounces
    /// stay clear of the ceiling. Empty without gravity or with pairs.
    floor: Vec<(Vec<f64>, bool)>,
}

fn exact(lesson: Lesson, horizon: f64) -> Result<Exact, String> {
    let world = lesson
        .scene()
        .build()
        .map_err(|e| format!("cannot build the {} lesson: {e}", lesson.name()))?;
    let reference = Reference::of(&world);
    let (b, g) = (&world.bodies, world.config.gravity);
    let energy_start = metrics::energy(&b.mass, &b.position, &b.velocity, g);
    let floor = match &reference {
        Reference::Independent(axes) if g.y < 0.0 => axes
            .iter()
            .map(|a| {
                let impacts = a[1].impacts(horizon, 2 * BOUNCES + 2);
                let first = impacts.iter().position(|i| !i.upper);
                let clean =
                    first.is_some_and(|f| impacts[f..].iter().take(BOUNCES + 1).all(|i| !i.upper));
                let times = impacts.iter().filter(|i| !i.upper).map(|i| i.time);
                (times.collect(), clean)
            })
            .collect(),
        _ => Vec::new(),
    };
    Ok(Exact {
        world,
        reference,
        t: horizon,
        energy_start,
        floor,
    })
}

fn measure(
    exact: &Exact,
    lesson: Lesson,
    method: Integrator,
    dt: f64,
    repeats: usize,
) -> Result<Row, String> {
    let mut start = exact.world.clone();
    start.config.integrator = method;
    start.config.dt = dt;
    let steps = rules::steps_for(exact.t, dt)
        .map_err(|m| format!("{} s at dt {dt} s would {m}", exact.t))?
        .max(1);
    let bodies = start.bodies.len();

    let times: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let mut w = start.clone();
            let t0 = Instant::now();
            w.run(steps);
            t0.elapsed().as_secs_f64()
        })
        .collect();
    let wall_time = times.iter().copied().fold(f64::INFINITY, f64::min);

    let mut w = start.clone();
    let mut log = BounceLog::new(&w);
    let mut capped = false;
    for _ in 0..steps {
        w.step();
        log.observe(&w);
        capped |= w.last.event_cap_reached;
    }
    // Compare at the exact time `steps dt`, not the summed clock.
    let t = steps as f64 * dt;
    let (x, v) = exact.reference.state_at(t).ok_or_else(|| {
        format!(
            "the exact reference of the {} lesson needs too many impacts",
            lesson.name()
        )
    })?;
    let g = w.config.gravity;
    let energy_exact = metrics::energy(&w.bodies.mass, &x, &v, g);
    let b = &w.bodies;
    let energy = metrics::energy(&b.mass, &b.position, &b.velocity, g);
    let (bounce_time_error, apex_ratio_error) = if exact.floor.is_empty() {
        (None, None)
    } else {
        let c = w.config.wall_coefficient();
        let (te, ae) = metrics::bounce_errors(&log.bounces, &exact.floor, c);
        (Some(te), Some(ae))
    };
    let horizon = t;
    Ok(Row {
        lesson,
        method,
        dt,
        steps,
        bodies,
        horizon,
        wall_time,
        cost_per_second: wall_time / horizon,
        ns_per_body_step: wall_time * 1e9 / (steps as f64 * bodies as f64),
        rms_error: metrics::rms_error(&b.position, &x),
        bounce_time_error,
        apex_ratio_error,
        energy_error: (energy - energy_exact).abs()
            / exact.energy_start.abs().max(f64::MIN_POSITIVE),
        event_cap_reached: capped,
    })
}

/// Run the plan; `progress` hears about every run before it starts
/// (`done`, `total`, a description).
pub fn run(plan: &Plan, progress: &mut dyn FnMut(usize, usize, &str)) -> Result<Vec<Row>, String> {
    let total = plan.runs();
    let mut rows = Vec::with_capacity(total);
    for &lesson in &plan.lessons {
        let exact = exact(lesson, plan.horizon(lesson))?;
        for &method in &plan.methods {
            for &dt in &plan.dts {
                progress(
                    rows.len(),
                    total,
                    &format!("{} {} dt={dt:.3e}", lesson.name(), method.name()),
                );
                rows.push(measure(&exact, lesson, method, dt, plan.repeats)?);
            }
        }
    }
    progress(total, total, "done");
    Ok(rows)
}

/// The work-precision data of one lesson (the visualiser's chart screen):
/// the quick plan restricted to `lesson`.
pub fn work_precision(lesson: Lesson) -> Result<Vec<Row>, String> {
    let mut plan = Plan::quick();
    plan.horizons = vec![plan.horizon(lesson)];
    plan.lessons = vec![lesson];
    run(&plan, &mut |_, _, _| {})
}
