//! The stability suite: where each method fails, and what holds instead.
//!
//! Every check builds a small scene of its own, runs it and returns the
//! measured figures; [`suite`] turns them into the table `lerpit study
//! --stability` prints (scene x method -> holds / fails), and the tests
//! assert the same figures. The checks:
//!
//! 1. **energy**: a ball bouncing at `c_r = 1`: in flight explicit Euler
//!    gains `u^2 / 2 + g y` at every step and semi-implicit Euler loses it,
//!    each keeping an energy of its own that the wall stage keeps too
//!    (`walls.rs`), so both stay bounded; velocity Verlet and RK4 reflect
//!    at the crossing of their exact parabola and keep it to rounding;
//!    a settled pile must show no upward trend in its total energy beyond
//!    the noise (its least-squares slope below twice its standard error):
//!    the collisions lesson with each method, and the benchmark's pile held
//!    by the support pass;
//! 2. **rest**: a ball dropped at `c_r = 0.95` must rest near
//!    `sqrt(2h/g)(1 + c_r)/(1 - c_r)` without penetrating the floor, with
//!    the default rules (resting contact) and without them; the gravity
//!    lesson must lie on its floor after 40 s and the collisions lesson
//!    keep under 0.1% of its peak kinetic energy after 60 s;
//! 3. **tunnelling**: two spheres meeting head on at relative speed `v`:
//!    discrete detection only sees them if a step ends while they overlap
//!    with their centres not yet past each other, guaranteed while
//!    `v dt < r1 + r2` (at equality a step may end with them touching and
//!    the next with their centres on each other); past it some starting gap
//!    lets them through, and the scan over `v` tries that gap too, so the
//!    first miss it finds is its first speed past `r1 + r2`; continuous
//!    detection and sub-steps prevent it;
//! 4. **piles**: many spheres settling under gravity (residual overlap,
//!    kinetic energy decay, jitter; for the continuous method, the steps
//!    at its impact cap and its step's cost against semi-implicit Euler's
//!    in the same pile), and a box packed beyond random close
//!    packing that must not blow up; a deep pile, where one projection pass
//!    per step leaves the lower layers pressed into each other, against its
//!    remedies (sub-steps, further projection passes, both, the support
//!    pass) and their cost, and at the full scale the goal's pile of
//!    100,000 spheres with the lesson's pass and the support pass;
//! 5. **critical dt**: the largest `dt` at which each method holds each
//!    lesson;
//! 6. **extremes**: restitution 0 and 1, a mass ratio of 1:1000, and elastic
//!    spheres at the fastest speed and strongest gravity a scene may ask
//!    for: so many impacts per step that the continuous method reaches its
//!    cap every step, and must keep the energy all the same.

use crate::scene::bench::bench_world;
use crate::scene::{Lesson, rules};
use crate::sim::{
    Bodies, Body, BroadPhase, Integrator, MassLaw, Spawn, Vec3, WallMode, World, WorldConfig,
};

/// Earth's gravity in the lessons, m/s^2.
const G: f64 = crate::sim::STANDARD_GRAVITY;

/// A ball of radius 0.05 m and mass 1 kg resting at height `y` under
/// gravity, walls with restitution `c`.
pub(crate) fn ball_world(method: Integrator, dt: f64, y: f64, c: f64) -> World {
    let config = WorldConfig {
        dt,
        integrator: method,
        wall_mode: WallMode::Restitution,
        wall_restitution: c,
        pair_collisions: false,
        ..WorldConfig::default()
    };
    let bodies: Bodies = [Body {
        position: Vec3::new(0.5, y, 0.5),
        velocity: Vec3::ZERO,
        radius: 0.05,
        mass: 1.0,
    }]
    .into_iter()
    .collect();
    World::new(config, bodies)
}

/// Mechanical energy of body 0 above resting on the floor, J.
fn energy_above_rest(w: &World) -> f64 {
    let b = &w.bodies;
    0.5 * b.mass[0] * b.velocity[0].length_squared()
        + b.mass[0] * G * (b.position[0].y - b.radius[0])
}

// ---------------------------------------------------------------- 1. energy

/// Relative energy change of a ball bouncing at `c_r = 1` from 0.5 m:
/// `(E(t) - E(0)) / E(0)` at `seconds`, and the largest absolute value on
/// the way.
pub fn energy_drift(method: Integrator, dt: f64, seconds: f64) -> (f64, f64) {
    let mut w = ball_world(method, dt, 0.5, 1.0);
    let e0 = energy_above_rest(&w);
    let mut worst: f64 = 0.0;
    let steps = (seconds / dt).round() as u64;
    for _ in 0..steps {
        w.step();
        worst = worst.max(((energy_above_rest(&w) - e0) / e0).abs());
    }
    ((energy_above_rest(&w) - e0) / e0, worst)
}

/// Largest relative energy change a bounded method shows on the bouncing
/// ball at `dt = 1/120` s (the Euler methods' oscillation is 2.8%).
pub const ENERGY_BOUND: f64 = 0.1;

// ------------------------------------------------------------------ 2. rest

/// The exact time a ball dropped from rest at height `h` (of its lowest
/// point above the floor) comes to rest: `sqrt(2h/g)(1 + c)/(1 - c)`.
pub fn time_to_rest(h: f64, c: f64) -> f64 {
    (2.0 * h / G).sqrt() * (1.0 + c) / (1.0 - c)
}

/// What a dropped ball did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestOutcome {
    /// The exact time to rest, s.
    pub exact: f64,
    /// The first step end from which the ball stayed on the floor with no
    /// vertical speed to the end of the run, s; `None` if it never did.
    pub rested_at: Option<f64>,
    /// Mechanical energy above rest at the end of the run, J.
    pub leftover: f64,
    /// Largest depth of the centre below `r` seen at a step end, m.
    pub penetration: f64,
}

/// Drop a ball from `y = 0.5` (`h = 0.45`) at `c_r = 0.95` and run for twice
/// the exact time to rest, with the rest threshold and resting contact
/// (`rest_steps`, 0: off) given.
pub fn rest(method: Integrator, dt: f64, rest_threshold: f64, rest_steps: f64) -> RestOutcome {
    drop_ball(method, dt, 0.95, rest_threshold, rest_steps)
}

/// Drop a ball from `y = 0.5` (`h = 0.45`) at restitution `c` and run for
/// twice the exact time to rest (at most 30 s).
pub fn drop_ball(
    method: Integrator,
    dt: f64,
    c: f64,
    rest_threshold: f64,
    rest_steps: f64,
) -> RestOutcome {
    let mut w = ball_world(method, dt, 0.5, c);
    w.config.rest_threshold = rest_threshold;
    w.config.rest_steps = rest_steps;
    let exact = if c < 1.0 {
        time_to_rest(0.45, c)
    } else {
        f64::INFINITY
    };
    let steps = ((2.0 * exact).min(30.0) / dt).round() as u64;
    let mut rested_at = None;
    let mut penetration: f64 = 0.0;
    for _ in 0..steps {
        w.step();
        let (y, vy, r) = (
            w.bodies.position[0].y,
            w.bodies.velocity[0].y,
            w.bodies.radius[0],
        );
        penetration = penetration.max(r - y);
        match (y == r && vy == 0.0, rested_at) {
            (true, None) => rested_at = Some(w.steps as f64 * dt),
            (false, Some(_)) => rested_at = None,
            _ => {}
        }
    }
    RestOutcome {
        exact,
        rested_at,
        leftover: energy_above_rest(&w),
        penetration,
    }
}

/// The rest threshold the suite gives the discrete methods: `2 g dt`, the
/// smallest multiple of `g dt` that stops semi-implicit Euler's
/// micro-bounce at `dt = 1/120` s (one `g dt` does not).
pub fn rest_threshold_for(dt: f64) -> f64 {
    2.0 * G * dt
}

/// How near the exact rest time a remedy must bring the ball: 10%.
pub(crate) const REST_TOLERANCE: f64 = 0.1;

impl RestOutcome {
    /// Rested within [`REST_TOLERANCE`] of the exact time, never below the
    /// floor by more than rounding.
    pub fn rests_near(&self) -> bool {
        self.rested_at
            .is_some_and(|t| (t - self.exact).abs() <= REST_TOLERANCE * self.exact)
            && self.penetration <= 1e-12
    }
}

/// Where a lesson's spheres are after a run with the default rules.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettleOutcome {
    /// Largest height of a centre above its resting height `y = r`, m.
    pub max_height: f64,
    /// Largest vertical speed, m/s.
    pub max_vertical_speed: f64,
    /// Kinetic energy at the end over the largest seen.
    pub kinetic_fraction: f64,
}

/// Run `lesson` with `method` for `seconds` (its own `dt` and rules, or
/// resting contact set to `rest_steps`) and say how settled it is.
pub fn settle(
    lesson: Lesson,
    method: Integrator,
    seconds: f64,
    rest_steps: Option<f64>,
) -> Result<SettleOutcome, String> {
    let mut w = lesson.scene().build().map_err(|e| e.to_string())?;
    w.config.integrator = method;
    if let Some(k) = rest_steps {
        w.config.rest_steps = k;
    }
    let mut peak = w.diagnostics().kinetic_energy;
    for _ in 0..(seconds / w.config.dt).round() as u64 {
        w.step();
        peak = peak.max(w.diagnostics().kinetic_energy);
    }
    let b = &w.bodies;
    let (mut max_height, mut max_vertical_speed): (f64, f64) = (0.0, 0.0);
    for i in 0..b.len() {
        max_height = max_height.max(b.position[i].y - b.radius[i]);
        max_vertical_speed = max_vertical_speed.max(b.velocity[i].y.abs());
    }
    Ok(SettleOutcome {
        max_height,
        max_vertical_speed,
        kinetic_fraction: w.diagnostics().kinetic_energy / peak.max(f64::MIN_POSITIVE),
    })
}

/// How settled the gravity lesson must be after [`GRAVITY_SETTLE_SECONDS`]:
/// every centre within 1e-4 m of `y = r`, moving under 1 mm/s vertically.
pub const SETTLED_HEIGHT: f64 = 1e-4;
pub const SETTLED_SPEED: f64 = 1e-3;
pub const GRAVITY_SETTLE_SECONDS: f64 = 40.0;
/// The collisions lesson after [`COLLISIONS_SETTLE_SECONDS`] keeps less than
/// this fraction of its peak kinetic energy.
pub const SETTLED_KINETIC_FRACTION: f64 = 1e-3;
pub const COLLISIONS_SETTLE_SECONDS: f64 = 60.0;

/// The total energy of a settled lesson, step by step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettledEnergy {
    /// Mean total energy over the run, J.
    pub mean: f64,
    /// Least-squares slope of the total energy against time, J/s.
    pub slope: f64,
    /// The slope's standard error, J/s: from the scatter of the energy
    /// about the fitted line, with the steps counted as fewer independent
    /// samples as far as each is correlated with the next.
    pub slope_error: f64,
    /// Steps that raised the total energy, of `steps`.
    pub rises: u64,
    pub steps: u64,
    /// The largest rise in one step, J.
    pub largest_rise: f64,
    /// Mean kinetic energy over the run, J: how still the pile is.
    pub mean_kinetic: f64,
}

impl SettledEnergy {
    /// No upward trend beyond the noise: the slope is at most 0, or below
    /// twice its standard error. A pile that never stops quite still (a
    /// sphere at a few mm/s) moves its total energy by a little every step,
    /// so the sign of a slope within its error says nothing; a real source
    /// of energy shows as a slope well beyond it. An energy that drifts
    /// along a curve leaves residuals that follow each other, too few
    /// independent samples for an error, and only the sign counts.
    pub fn no_upward_trend(&self) -> bool {
        self.slope <= 0.0 || (self.slope_error.is_finite() && self.slope <= 2.0 * self.slope_error)
    }

    /// The row's figure: slope and error, the mean, the rises.
    pub fn figure(&self) -> String {
        format!(
            "slope {:+.1e} J/s ({}) of {:.1} J, {} of {} steps rose, largest rise {:.1e} J, kinetic {:.1e} J",
            self.slope,
            if self.slope_error.is_finite() {
                format!("error {:.1e}", self.slope_error)
            } else {
                "error n/a: too few independent samples".to_string()
            },
            self.mean,
            self.rises,
            self.steps,
            self.largest_rise,
            self.mean_kinetic
        )
    }
}

/// Let the collisions lesson settle for `settle_seconds` with `method`,
/// then follow its total energy for `seconds`.
///
/// Where a rise comes from: the position projection keeps each pair's
/// centre of mass, so it leaves the potential energy as it was (to
/// rounding), and the impulses only take kinetic energy. But a sphere
/// resting on the floor under another is pushed into the floor by the
/// projection, and the wall stage puts it back while its partner stays
/// lifted: the wall stage is the one place a step can gain, by at most
/// `m g` times the depth the projection pushed a centre past the wall,
/// which the next steps' fall pays back.
pub fn settled_energy(
    method: Integrator,
    settle_seconds: f64,
    seconds: f64,
) -> Result<SettledEnergy, String> {
    let mut w = Lesson::Collisions
        .scene()
        .build()
        .map_err(|e| e.to_string())?;
    w.config.integrator = method;
    Ok(energy_trend(w, settle_seconds, seconds))
}

/// The benchmark scene's `n` spheres (dt = 1/60 s, restitution 0.95),
/// their pile held by the support pass: let it settle for
/// `settle_seconds`, then follow its total energy for `seconds`.
///
/// The pass moves a sphere only as the impulses it takes say, shared with
/// the spheres it touches, then takes away what is left of its speed into
/// the ones below (`support.rs`); the one lift it does not pay for is the
/// push out of an overlap an earlier step's fall left.
pub fn held_pile_energy(n: usize, settle_seconds: f64, seconds: f64) -> SettledEnergy {
    let mut w = bench_world(n, BroadPhase::Auto);
    w.config.support = true;
    energy_trend(w, settle_seconds, seconds)
}

/// Run `w` for `settle_seconds`, then follow its total energy step by step
/// for `seconds`.
fn energy_trend(mut w: World, settle_seconds: f64, seconds: f64) -> SettledEnergy {
    w.run((settle_seconds / w.config.dt).round() as u64);
    let steps = (seconds / w.config.dt).round() as u64;
    let mut samples = Vec::with_capacity(steps as usize);
    let mut previous = w.diagnostics().total_energy;
    let (mut rises, mut largest_rise, mut kinetic) = (0, 0.0_f64, 0.0);
    for _ in 0..steps {
        w.step();
        let d = w.diagnostics();
        kinetic += d.kinetic_energy / steps as f64;
        let e = d.total_energy;
        if e > previous {
            rises += 1;
            largest_rise = largest_rise.max(e - previous);
        }
        previous = e;
        samples.push((w.time, e));
    }
    let n = samples.len().max(1) as f64;
    let (mt, me) = samples
        .iter()
        .fold((0.0, 0.0), |(t, e), s| (t + s.0 / n, e + s.1 / n));
    let (num, den) = samples.iter().fold((0.0, 0.0), |(num, den), s| {
        (num + (s.0 - mt) * (s.1 - me), den + (s.0 - mt).powi(2))
    });
    let slope = if den > 0.0 { num / den } else { 0.0 };
    SettledEnergy {
        mean: me,
        slope,
        slope_error: slope_error(&samples, me - slope * mt, slope, den),
        rises,
        steps,
        largest_rise,
        mean_kinetic: kinetic,
    }
}

/// Fewer independent samples than this give no standard error.
const EFFECTIVE_SAMPLES: f64 = 30.0;

/// The standard error of the least-squares `slope` (and `intercept`) of
/// `samples`, whose times spread as `spread` (the sum of squares about
/// their mean): the residuals' variance over the spread, with the sample
/// count cut to `n (1 - rho) / (1 + rho)` for the correlation `rho` of
/// each residual with the next. Infinite for fewer than
/// [`EFFECTIVE_SAMPLES`] effective samples.
fn slope_error(samples: &[(f64, f64)], intercept: f64, slope: f64, spread: f64) -> f64 {
    let residual: Vec<f64> = samples
        .iter()
        .map(|&(t, e)| e - intercept - slope * t)
        .collect();
    let squares: f64 = residual.iter().map(|r| r * r).sum();
    let n = residual.len() as f64;
    if n < 3.0 || spread <= 0.0 {
        return f64::INFINITY;
    }
    if squares == 0.0 {
        return 0.0;
    }
    let rho = (residual.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / squares).clamp(0.0, 1.0);
    let effective = n * (1.0 - rho) / (1.0 + rho);
    if effective < EFFECTIVE_SAMPLES {
        return f64::INFINITY;
    }
    (squares / (effective - 2.0) / spread).sqrt()
}

/// Seconds the collisions lesson settles before its energy is followed,
/// and for how long.
pub const SETTLED_ENERGY_START: f64 = 20.0;
pub(crate) const SETTLED_ENERGY_SECONDS: f64 = 100.0;
/// Seconds the benchmark pile settles before its energy is followed with
/// the support pass: the pile has formed by then (`scene::bench`).
pub const HELD_PILE_SETTLE: f64 = 10.0;

// ------------------------------------------------------------ 3. tunnelling

/// Radius of both spheres of the tunnelling check, m.
pub(crate) const TUNNEL_RADIUS: f64 = 0.05;

/// Starting gaps between the centres tried for each speed, as fractions of
/// `r1 + r2` added to 3 (r1 + r2): where the steps fall relative to the
/// contact decides whether a step ends inside it.
pub(crate) const TUNNEL_PHASES: usize = 10;

/// Whether two spheres (radius [`TUNNEL_RADIUS`], 1 kg, `e = 1`, no gravity)
/// approaching at relative speed `v` from a gap of `gap` between centres
/// pass through each other: just after the centres would have met, the
/// one that came from the left is on the right.
pub(crate) fn passes_through(method: Integrator, dt: f64, substeps: u32, v: f64, gap: f64) -> bool {
    let config = WorldConfig {
        gravity: Vec3::ZERO,
        dt,
        integrator: method,
        pair_collisions: true,
        pair_restitution: 1.0,
        wall_mode: WallMode::Flip,
        substeps,
        ..WorldConfig::default()
    };
    let body = |x: f64, u: f64| Body {
        position: Vec3::new(x, 0.5, 0.5),
        velocity: Vec3::new(u, 0.0, 0.0),
        radius: TUNNEL_RADIUS,
        mass: 1.0,
    };
    let bodies: Bodies = [
        body(0.5 - gap / 2.0, v / 2.0),
        body(0.5 + gap / 2.0, -v / 2.0),
    ]
    .into_iter()
    .collect();
    let mut w = World::new(config, bodies);
    w.run((gap / v / dt).ceil() as u64 + 1);
    w.bodies.position[0].x > w.bodies.position[1].x
}

/// The worst starting gap (at least 3 (r1 + r2)) for discrete detection,
/// when the centres close by `closing` a (sub-)step, more than `reach` =
/// r1 + r2: a step then ends with the spheres apart by half of what the
/// closing has beyond `reach`, and the next with their centres past each
/// other. `None` when the closing is within `reach`: every gap is found.
fn worst_gap(reach: f64, closing: f64) -> Option<f64> {
    (closing > reach).then(|| {
        let apart = reach + (closing - reach) / 2.0;
        apart + ((3.0 * reach - apart) / closing).ceil() * closing
    })
}

/// The smallest relative speed at which the spheres pass through each other
/// for some starting gap, as `v dt / (r1 + r2)`, scanning from 0.5 in steps
/// of 0.01 up to `max_ratio` (at most 4, so no wall is reached); `None` if
/// they never do. The gaps tried are [`TUNNEL_PHASES`] spread over one
/// contact's width and the worst one ([`worst_gap`]).
pub fn first_miss_ratio(method: Integrator, dt: f64, substeps: u32, max_ratio: f64) -> Option<f64> {
    let reach = 2.0 * TUNNEL_RADIUS;
    let last = (max_ratio.min(4.0) * 100.0).round() as u32;
    (50..=last).map(|k| f64::from(k) / 100.0).find(|&ratio| {
        let closing = ratio * reach / f64::from(substeps.max(1));
        (0..TUNNEL_PHASES)
            .map(|p| reach * (3.0 + p as f64 / TUNNEL_PHASES as f64))
            .chain(worst_gap(reach, closing))
            .any(|gap| passes_through(method, dt, substeps, ratio * reach / dt, gap))
    })
}

// ----------------------------------------------------------------- 4. piles

/// What a pile run measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PileOutcome {
    pub bodies: usize,
    /// Largest penetration at the end, as a fraction of the smallest radius.
    pub residual_overlap: f64,
    /// Kinetic energy at the end over the largest kinetic energy seen.
    pub kinetic_decay: f64,
    /// RMS speed at the end, m/s.
    pub jitter: f64,
    /// Largest speed seen, m/s.
    pub max_speed: f64,
    /// Largest rise of the total energy above its start, as a fraction of
    /// the starting potential energy.
    pub energy_growth: f64,
    /// Steps where the continuous method reached its impact cap.
    pub capped_steps: u64,
    /// Median wall time of a step, s (measured, for the table only).
    pub seconds_per_step: f64,
}

/// Solid fraction above which the pile is spawned overlapping: random
/// placement without overlaps jams well below random close packing.
pub(crate) const OVERLAPPING_SPAWN: f64 = 0.2;

/// `n` spheres under gravity with restitution 0.5 at walls and pairs,
/// filling `fraction` of the box (spawned overlapping above
/// [`OVERLAPPING_SPAWN`]), run for `seconds`.
pub fn pile(
    method: Integrator,
    n: usize,
    fraction: f64,
    dt: f64,
    seconds: f64,
) -> Result<PileOutcome, crate::sim::SpawnError> {
    let r = pile_radius(n, fraction);
    let mut w = pile_world(method, n, fraction, dt)?;
    let d0 = w.diagnostics();
    let mut max_kinetic = d0.kinetic_energy;
    let mut max_speed: f64 = 0.0;
    let mut energy_growth: f64 = 0.0;
    let mut capped_steps = 0;
    let steps = (seconds / dt).round() as u64;
    let mut times = Vec::with_capacity(steps as usize);
    for _ in 0..steps {
        let start = std::time::Instant::now();
        w.step();
        times.push(start.elapsed().as_secs_f64());
        capped_steps += u64::from(w.last.event_cap_reached);
        let d = w.diagnostics();
        max_kinetic = max_kinetic.max(d.kinetic_energy);
        energy_growth = energy_growth.max((d.total_energy - d0.total_energy) / d0.potential_energy);
        let fastest = w
            .bodies
            .velocity
            .iter()
            .map(|v| v.length_squared())
            .fold(0.0, f64::max);
        max_speed = max_speed.max(fastest.sqrt());
    }
    let mut contacts = Vec::new();
    crate::sim::BroadPhase::AllPairs.find_contacts(&w.bodies, &mut contacts);
    let overlap = contacts.iter().map(|c| c.penetration).fold(0.0, f64::max);
    let d = w.diagnostics();
    let total_mass: f64 = w.bodies.mass.iter().sum();
    Ok(PileOutcome {
        bodies: n,
        residual_overlap: overlap / r,
        kinetic_decay: d.kinetic_energy / max_kinetic.max(f64::MIN_POSITIVE),
        jitter: (2.0 * d.kinetic_energy / total_mass).sqrt(),
        max_speed,
        energy_growth,
        capped_steps,
        seconds_per_step: crate::study::metrics::median(&mut times),
    })
}

/// The radius of `n` equal spheres filling `fraction` of the box.
pub(crate) fn pile_radius(n: usize, fraction: f64) -> f64 {
    (fraction * 3.0 / (4.0 * std::f64::consts::PI * n as f64)).cbrt()
}

/// The pile's world before it falls: `n` spheres of 0.01 kg filling
/// `fraction` of the box, restitution 0.5 at walls and pairs, the broad
/// phase chosen by size.
pub fn pile_world(
    method: Integrator,
    n: usize,
    fraction: f64,
    dt: f64,
) -> Result<World, crate::sim::SpawnError> {
    let r = pile_radius(n, fraction);
    let config = WorldConfig {
        dt,
        integrator: method,
        wall_restitution: 0.5,
        pair_restitution: 0.5,
        broad_phase: crate::sim::BroadPhase::Auto,
        ..WorldConfig::default()
    };
    let spawn = Spawn {
        count: n,
        radius: [r, r],
        speed: [0.0, 0.5],
        mass_law: MassLaw::Constant { mass: 0.01 },
        overlap: fraction > OVERLAPPING_SPAWN,
    };
    let mut bodies = Bodies::with_capacity(n);
    crate::sim::spawn::spawn_bodies(&mut bodies, &[spawn], 7)?;
    Ok(World::new(config, bodies))
}

/// What a deep pile looked like once settled, and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeepPileOutcome {
    pub bodies: usize,
    /// Mean penetration over the overlapping pairs at the end, in radii.
    pub mean_overlap: f64,
    /// Largest penetration at the end, in radii.
    pub max_overlap: f64,
    /// Overlapping pairs at the end per sphere (random close packing: about
    /// 3, six neighbours each).
    pub pairs_per_sphere: f64,
    /// Steps whose further projection passes ran out before converging.
    pub unconverged_steps: u64,
    /// The spheres' root-mean-square speed at the end, m/s: a pile at rest
    /// keeps less than the speed gravity adds in a step (0.041 m/s at
    /// 1/240 s).
    pub rms_speed: f64,
    /// Wall time per step, s (measured, for the table only).
    pub seconds_per_step: f64,
}

/// A remedy for deep piles: sub-steps, projection passes, and the support
/// pass on or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PileRemedy {
    pub substeps: u32,
    pub projection_passes: u32,
    pub support: bool,
}

impl PileRemedy {
    /// The lesson's single pass.
    pub const LESSON: PileRemedy = PileRemedy::passes(1, 1);
    /// The support pass after the lesson's single pass.
    pub const SUPPORT: PileRemedy = PileRemedy {
        support: true,
        ..PileRemedy::LESSON
    };

    /// `substeps` sub-steps of `projection_passes` passes each.
    pub const fn passes(substeps: u32, projection_passes: u32) -> Self {
        Self {
            substeps,
            projection_passes,
            support: false,
        }
    }

    /// The remedy's name in the suite's table.
    pub fn name(self) -> String {
        match (self.substeps, self.projection_passes, self.support) {
            (1, 1, false) => "one pass (the lesson)".to_string(),
            (1, 1, true) => "support pass".to_string(),
            (k, 1, _) => format!("{k} sub-steps"),
            (1, p, _) => format!("{p} passes"),
            (k, p, _) => format!("{k} sub-steps x {p} passes"),
        }
    }
}

/// `n` spheres (15% solid) fall into a pile under semi-implicit Euler at
/// `dt = 1/240` s for `seconds`, with `remedy`.
pub fn deep_pile(
    n: usize,
    remedy: PileRemedy,
    seconds: f64,
) -> Result<DeepPileOutcome, crate::sim::SpawnError> {
    let dt = 1.0 / 240.0;
    let r = pile_radius(n, 0.15);
    let mut w = pile_world(Integrator::SemiImplicitEuler, n, 0.15, dt)?;
    w.config.substeps = remedy.substeps;
    w.config.projection_passes = remedy.projection_passes;
    w.config.support = remedy.support;
    let steps = (seconds / dt).round() as u64;
    let mut unconverged_steps = 0;
    let start = std::time::Instant::now();
    for _ in 0..steps {
        w.step();
        unconverged_steps += u64::from(w.last.projection_unconverged);
    }
    let seconds_per_step = start.elapsed().as_secs_f64() / steps.max(1) as f64;
    let mut contacts = Vec::new();
    crate::sim::BroadPhase::Grid.find_contacts(&w.bodies, &mut contacts);
    let pairs = contacts.len().max(1) as f64;
    Ok(DeepPileOutcome {
        bodies: n,
        mean_overlap: contacts.iter().map(|c| c.penetration).sum::<f64>() / pairs / r,
        max_overlap: contacts.iter().map(|c| c.penetration).fold(0.0, f64::max) / r,
        pairs_per_sphere: contacts.len() as f64 / n as f64,
        unconverged_steps,
        rms_speed: (w
            .bodies
            .velocity
            .iter()
            .map(|v| v.length_squared())
            .sum::<f64>()
            / n.max(1) as f64)
            .sqrt(),
        seconds_per_step,
    })
}

/// What a settled deep pile must reach: mean overlap under 0.05 r, fewer
/// than 3.5 overlapping pairs per sphere.
pub const DEEP_PILE_MEAN_OVERLAP: f64 = 0.05;
pub const DEEP_PILE_PAIRS_PER_SPHERE: f64 = 3.5;

/// The remedies the suite compares on the deep pile.
pub(crate) const DEEP_PILE_REMEDIES: [PileRemedy; 9] = [
    PileRemedy::LESSON,
    PileRemedy::passes(2, 1),
    PileRemedy::passes(4, 1),
    PileRemedy::passes(8, 1),
    PileRemedy::passes(16, 1),
    PileRemedy::passes(1, 4),
    PileRemedy::passes(4, 4),
    PileRemedy::passes(8, 4),
    PileRemedy::SUPPORT,
];

/// Spheres in the continuous method's pile.
pub const CONTINUOUS_PILE: usize = 200;

/// Largest speed a pile may reach, m/s: a free fall through the whole box
/// reaches `sqrt(2 g)`, about 4.4 m/s, plus the spawn's 0.5 m/s.
pub const PILE_SPEED_LIMIT: f64 = 5.0;

// ----------------------------------------------------------- 5. critical dt

/// Time steps tried by the critical-dt search, s: halving from 1/4 s to
/// about 1/2000 s.
pub fn critical_dt_grid() -> Vec<f64> {
    (2..=11).map(|k| 1.0 / f64::from(1u32 << k)).collect()
}

/// Whether `method` holds `lesson` at `dt` for `seconds`: the state stays
/// finite and the total energy never rises more than 1% (of its start, or
/// of the kinetic energy if larger) above its start: the lessons have no
/// energy source, so a rise is the method's own.
pub(crate) fn holds(lesson: Lesson, method: Integrator, dt: f64, seconds: f64) -> bool {
    let Ok(mut w) = lesson.scene().build() else {
        return false;
    };
    w.config.integrator = method;
    w.config.dt = dt;
    let e0 = w.diagnostics().total_energy;
    let scale = e0.abs().max(w.diagnostics().kinetic_energy).max(1e-12);
    let steps = (seconds / dt).round() as u64;
    for _ in 0..steps {
        w.step();
        let e = w.diagnostics().total_energy;
        if !e.is_finite() || e - e0 > 0.01 * scale {
            return false;
        }
    }
    true
}

/// The largest `dt` of [`critical_dt_grid`] such that `method` holds
/// `lesson` at it and at every smaller `dt` of the grid; `None` if it fails
/// even at the smallest.
pub fn critical_dt(lesson: Lesson, method: Integrator, seconds: f64) -> Option<f64> {
    let grid = critical_dt_grid();
    let mut best = None;
    for &dt in grid.iter().rev() {
        if holds(lesson, method, dt, seconds) {
            best = Some(dt);
        } else {
            break;
        }
    }
    best
}

// -------------------------------------------------------------- 6. extremes

/// Two spheres meeting head on along x without gravity: body 0 (mass
/// `m0`) at speed `v`, body 1 (mass `m1`) at rest, restitution `e`. Returns
/// the velocities after the run and the relative momentum error.
pub fn head_on(method: Integrator, dt: f64, m0: f64, m1: f64, v: f64, e: f64) -> (f64, f64, f64) {
    let config = WorldConfig {
        gravity: Vec3::ZERO,
        dt,
        integrator: method,
        pair_collisions: true,
        pair_restitution: e,
        wall_mode: WallMode::Flip,
        ..WorldConfig::default()
    };
    let body = |x: f64, u: f64, m: f64| Body {
        position: Vec3::new(x, 0.5, 0.5),
        velocity: Vec3::new(u, 0.0, 0.0),
        radius: 0.05,
        mass: m,
    };
    let bodies: Bodies = [body(0.3, v, m0), body(0.6, 0.0, m1)].into_iter().collect();
    let mut w = World::new(config, bodies);
    let p0 = m0 * v;
    // Long enough to meet (gap 0.2 m), short enough that no wall is reached.
    w.run((0.25 / v / dt).ceil() as u64);
    let b = &w.bodies;
    let p = b.mass[0] * b.velocity[0].x + b.mass[1] * b.velocity[1].x;
    (b.velocity[0].x, b.velocity[1].x, (p - p0).abs() / p0.abs())
}

/// What a run of elastic spheres measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticOutcome {
    pub bodies: usize,
    pub steps: u64,
    /// Largest `|E(t) - E(0)| / |E(0)|` seen at a step end.
    pub energy_drift: f64,
    /// Steps where the continuous method reached its impact cap.
    pub capped_steps: u64,
}

/// How far the total energy of elastic spheres may drift, relative.
pub const ELASTIC_ENERGY_BOUND: f64 = 1e-9;

/// The collisions lesson with `n` spheres, all starting at `speed` m/s,
/// gravity `g` m/s^2 down, every restitution 1 (walls and pairs), run for
/// `steps` steps of `dt`: nothing takes energy out or puts it in, so the
/// total must stay at its start.
pub fn elastic_spheres(
    method: Integrator,
    n: usize,
    speed: f64,
    g: f64,
    dt: f64,
    steps: u64,
) -> Result<ElasticOutcome, String> {
    let mut scene = Lesson::Collisions.scene();
    scene.set_particles(n)?;
    for spawn in &mut scene.spawns {
        spawn.speed = [speed, speed];
    }
    let c = &mut scene.world;
    c.gravity = Vec3::new(0.0, -g, 0.0);
    c.dt = dt;
    c.integrator = method;
    c.wall_mode = WallMode::Restitution;
    c.wall_restitution = 1.0;
    c.pair_restitution = 1.0;
    let mut w = scene.build().map_err(|e| e.to_string())?;
    let e0 = w.diagnostics().total_energy;
    let mut energy_drift: f64 = 0.0;
    let mut capped_steps = 0;
    for _ in 0..steps {
        w.step();
        capped_steps += u64::from(w.last.event_cap_reached);
        let drift = (w.diagnostics().total_energy - e0).abs() / e0.abs();
        // NaN (a state that left the finite range) counts as the worst.
        energy_drift = if drift.is_nan() {
            f64::INFINITY
        } else {
            energy_drift.max(drift)
        };
    }
    Ok(ElasticOutcome {
        bodies: n,
        steps,
        energy_drift,
        capped_steps,
    })
}

/// Spheres of the extreme elastic check: the scene.
pub(crate) const EXTREME_SPHERES: usize = 30;

// ----------------------------------------------------------------- table

fn miss_text(miss: Option<f64>) -> String {
    miss.map_or("no miss up to v dt = 4 (r1 + r2)".into(), |k| {
        format!("first miss at v dt = {k:.2} (r1 + r2)")
    })
}

/// One line of the table.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Finding {
    pub check: &'static str,
    pub scene: String,
    pub method: String,
    pub holds: bool,
    pub figure: String,
}

fn finding(check: &'static str, scene: &str, method: &str, holds: bool, figure: String) -> Finding {
    Finding {
        check,
        scene: scene.to_string(),
        method: method.to_string(),
        holds,
        figure,
    }
}

/// The deep-pile row of `remedy` with `n` spheres; `single` keeps the
/// step time of the first row of the same size, which the cost is given
/// against (the lesson's single pass comes first).
fn deep_pile_row(n: usize, remedy: PileRemedy, single: &mut Option<f64>) -> Finding {
    let (holds, figure) = match deep_pile(n, remedy, 2.0) {
        Ok(o) => {
            let base = *single.get_or_insert(o.seconds_per_step);
            (
                o.mean_overlap < DEEP_PILE_MEAN_OVERLAP
                    && o.pairs_per_sphere < DEEP_PILE_PAIRS_PER_SPHERE,
                format!(
                    "mean overlap {:.3} r (largest {:.3} r), {:.2} pairs per sphere, \
                     rms speed {:.3} m/s, cost x{:.1} of one pass{}",
                    o.mean_overlap,
                    o.max_overlap,
                    o.pairs_per_sphere,
                    o.rms_speed,
                    o.seconds_per_step / base,
                    if o.unconverged_steps > 0 {
                        format!(", passes ran out in {} steps", o.unconverged_steps)
                    } else {
                        String::new()
                    }
                ),
            )
        }
        Err(e) => (false, format!("cannot build: {e}")),
    };
    finding(
        "deep pile",
        &format!("{n} spheres, 15% solid, settled 2 s, dt 1/240"),
        &remedy.name(),
        holds,
        figure,
    )
}

/// How big the suite runs: `quick` for the tests' scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scale {
    pub pile_bodies: usize,
    pub pile_seconds: f64,
    pub critical_seconds: f64,
    /// Steps of the extreme elastic check.
    pub extreme_steps: u64,
    /// Spheres of the deep pile the remedies are compared on.
    pub deep_pile_bodies: usize,
    /// Spheres of the deep pile of the goal (100,000), run with the
    /// lesson's pass and the support pass only; `None`: not run.
    pub deep_pile_goal_bodies: Option<usize>,
    /// Spheres of the benchmark pile whose energy is followed with the
    /// support pass, and for how long (s, after [`HELD_PILE_SETTLE`]).
    pub held_pile_bodies: usize,
    pub held_pile_seconds: f64,
}

impl Scale {
    pub(crate) fn full() -> Scale {
        Scale {
            pile_bodies: 1000,
            pile_seconds: 2.0,
            critical_seconds: 2.0,
            extreme_steps: 20_000,
            deep_pile_bodies: 10_000,
            deep_pile_goal_bodies: Some(100_000),
            held_pile_bodies: 20_000,
            held_pile_seconds: SETTLED_ENERGY_SECONDS,
        }
    }

    pub(crate) fn quick() -> Scale {
        Scale {
            pile_bodies: 200,
            pile_seconds: 0.5,
            critical_seconds: 0.5,
            extreme_steps: 200,
            deep_pile_bodies: 1_000,
            deep_pile_goal_bodies: None,
            held_pile_bodies: 1_000,
            held_pile_seconds: 10.0,
        }
    }
}

/// Run every check; `progress` hears the name of each before it starts.
pub(crate) fn suite(scale: Scale, progress: &mut dyn FnMut(&str)) -> Vec<Finding> {
    let mut out = Vec::new();
    let dt = 1.0 / 120.0;

    progress("energy at c_r = 1");
    for m in Integrator::ALL {
        let (end, worst) = energy_drift(m, dt, 20.0);
        let holds = worst < ENERGY_BOUND;
        out.push(finding(
            "energy",
            "ball, c_r = 1, dt 1/120, 20 s",
            m.name(),
            holds,
            format!("energy change {:+.2e} (largest {:.2e})", end, worst),
        ));
    }

    progress("rest at c_r = 0.95");
    let resting = WorldConfig::default().rest_steps;
    let cases = Integrator::ALL
        .iter()
        .map(|&m| (m, 0.0, resting))
        .chain(Integrator::DISCRETE.iter().map(|&m| (m, 0.0, 0.0)))
        .chain([(Integrator::SemiImplicitEuler, rest_threshold_for(dt), 0.0)]);
    for (m, threshold, rest_steps) in cases {
        let r = rest(m, dt, threshold, rest_steps);
        let holds = r.rests_near();
        let name = match (
            threshold > 0.0,
            rest_steps > 0.0 || m == Integrator::Continuous,
        ) {
            (true, _) => format!("{}, threshold {:.3} m/s only", m.name(), threshold),
            (false, true) => m.name().to_string(),
            (false, false) => format!("{}, resting contact off", m.name()),
        };
        let when = r.rested_at.map_or("never rests".to_string(), |t| {
            format!(
                "rests at {t:.3} s (exact {:.3} s, {:+.1}%)",
                r.exact,
                100.0 * (t - r.exact) / r.exact
            )
        });
        out.push(finding(
            "rest",
            "ball dropped 0.45 m, c_r = 0.95, dt 1/120",
            &name,
            holds,
            format!("{when}, leftover {:.1e} J", r.leftover),
        ));
    }
    for m in Integrator::ALL {
        for (lesson, seconds) in [
            (Lesson::Gravity, GRAVITY_SETTLE_SECONDS),
            (Lesson::Collisions, COLLISIONS_SETTLE_SECONDS),
        ] {
            let scene = format!("{} lesson after {seconds} s", lesson.name());
            let (holds, figure) = match settle(lesson, m, seconds, None) {
                Ok(o) => (
                    match lesson {
                        Lesson::Gravity => {
                            o.max_height <= SETTLED_HEIGHT && o.max_vertical_speed <= SETTLED_SPEED
                        }
                        _ => o.kinetic_fraction <= SETTLED_KINETIC_FRACTION,
                    },
                    format!(
                        "highest centre {:.1e} m above y = r, vertical speed up to {:.1e} m/s, \
                         KE end/peak {:.1e}",
                        o.max_height, o.max_vertical_speed, o.kinetic_fraction
                    ),
                ),
                Err(e) => (false, format!("cannot build: {e}")),
            };
            out.push(finding("rest", &scene, m.name(), holds, figure));
        }
    }

    progress("energy of a settled pile");
    for m in Integrator::ALL {
        let scene =
            format!("collisions lesson, {SETTLED_ENERGY_SECONDS} s from {SETTLED_ENERGY_START} s");
        let (holds, figure) = match settled_energy(m, SETTLED_ENERGY_START, SETTLED_ENERGY_SECONDS)
        {
            Ok(o) => (o.no_upward_trend(), o.figure()),
            Err(e) => (false, format!("cannot build: {e}")),
        };
        out.push(finding("energy", &scene, m.name(), holds, figure));
    }
    let (n, seconds) = (scale.held_pile_bodies, scale.held_pile_seconds);
    let o = held_pile_energy(n, HELD_PILE_SETTLE, seconds);
    out.push(finding(
        "energy",
        &format!("benchmark pile of {n} spheres, {seconds} s from {HELD_PILE_SETTLE} s"),
        &PileRemedy::SUPPORT.name(),
        o.no_upward_trend(),
        o.figure(),
    ));

    progress("tunnelling");
    for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
        for dt in [1.0 / 30.0, 1.0 / 60.0, 1.0 / 120.0, 1.0 / 240.0] {
            let miss = first_miss_ratio(m, dt, 1, 4.0);
            out.push(finding(
                "tunnelling",
                &format!("head-on pair, r1 + r2 = 0.1 m, dt 1/{:.0}", 1.0 / dt),
                m.name(),
                miss.is_none(),
                miss_text(miss),
            ));
        }
    }
    for k in [2, 4] {
        let miss = first_miss_ratio(Integrator::SemiImplicitEuler, 1.0 / 60.0, k, 4.0);
        out.push(finding(
            "tunnelling",
            "head-on pair, r1 + r2 = 0.1 m, dt 1/60",
            &format!("semi-implicit-euler, {k} sub-steps"),
            miss.is_none_or(|r| r > f64::from(k)),
            miss_text(miss),
        ));
    }

    progress("piles");
    for (label, fraction) in [("pile", 0.15), ("over-packed box", 0.7)] {
        let methods: &[Integrator] = if fraction > OVERLAPPING_SPAWN {
            &[Integrator::SemiImplicitEuler, Integrator::VelocityVerlet]
        } else {
            &[
                Integrator::SemiImplicitEuler,
                Integrator::VelocityVerlet,
                Integrator::Continuous,
            ]
        };
        // Median step of semi-implicit Euler per pile size, for the
        // continuous method's cost.
        let mut euler_step: Vec<(usize, f64)> = Vec::new();
        for &m in methods {
            // The continuous method runs a pile of [`CONTINUOUS_PILE`]
            // spheres at most, whatever the scale.
            let n = if m == Integrator::Continuous {
                scale.pile_bodies.min(CONTINUOUS_PILE)
            } else {
                scale.pile_bodies
            };
            let scene = format!(
                "{label}: {n} spheres, {:.0}% solid, {} s",
                fraction * 100.0,
                scale.pile_seconds
            );
            let run = |m| pile(m, n, fraction, 1.0 / 240.0, scale.pile_seconds);
            let (holds, figure) = match run(m) {
                Ok(p) => {
                    if m == Integrator::SemiImplicitEuler {
                        euler_step.push((n, p.seconds_per_step));
                    }
                    let cost = if m == Integrator::Continuous {
                        let euler = match euler_step.iter().find(|e| e.0 == n) {
                            Some(e) => Some(e.1),
                            None => run(Integrator::SemiImplicitEuler)
                                .ok()
                                .map(|e| e.seconds_per_step),
                        };
                        euler.map_or(String::new(), |e| {
                            format!(
                                ", step x{:.1} of semi-implicit Euler's (medians)",
                                p.seconds_per_step / e
                            )
                        })
                    } else {
                        String::new()
                    };
                    (
                        p.max_speed < PILE_SPEED_LIMIT
                            && p.energy_growth <= 0.01
                            && p.capped_steps == 0,
                        format!(
                            "overlap {:.2} r, KE end/max {:.1e}, jitter {:.1e} m/s, \
                             max speed {:.2} m/s, energy rise {:+.1e}{}{cost}",
                            p.residual_overlap,
                            p.kinetic_decay,
                            p.jitter,
                            p.max_speed,
                            p.energy_growth,
                            if m != Integrator::Continuous {
                                String::new()
                            } else if p.capped_steps > 0 {
                                format!(", impact cap in {} steps", p.capped_steps)
                            } else {
                                ", no step at the impact cap".to_string()
                            }
                        ),
                    )
                }
                Err(e) => (false, format!("cannot build: {e}")),
            };
            out.push(finding("piles", &scene, m.name(), holds, figure));
        }
    }

    progress("deep pile");
    let mut single = None;
    for remedy in DEEP_PILE_REMEDIES {
        out.push(deep_pile_row(scale.deep_pile_bodies, remedy, &mut single));
    }
    // The goal's size, for the lesson's pass and the support pass.
    if let Some(n) = scale.deep_pile_goal_bodies {
        let mut single = None;
        for remedy in [PileRemedy::LESSON, PileRemedy::SUPPORT] {
            out.push(deep_pile_row(n, remedy, &mut single));
        }
    }

    progress("critical dt");
    for lesson in Lesson::ALL {
        for m in Integrator::ALL {
            let c = critical_dt(lesson, m, scale.critical_seconds);
            let largest = critical_dt_grid()[0];
            out.push(finding(
                "critical dt",
                &format!("{} lesson, {} s", lesson.name(), scale.critical_seconds),
                m.name(),
                c == Some(largest),
                c.map_or("fails at every dt tried".into(), |dt| {
                    format!("holds up to dt = 1/{:.0} s", 1.0 / dt)
                }),
            ));
        }
    }

    // Restitution 1 is the energy check's scene above: not run twice.
    progress("extremes");
    for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
        let r = drop_ball(m, dt, 0.0, 0.0, 0.0);
        let exact = time_to_rest(0.45, 0.0);
        out.push(finding(
            "extremes",
            "ball dropped 0.45 m, c_r = 0",
            m.name(),
            r.rested_at.is_some_and(|t| (t - exact).abs() <= dt + 1e-12),
            r.rested_at.map_or("never rests".into(), |t| {
                format!("rests at {t:.4} s (exact {exact:.4} s)")
            }),
        ));
        let (v0, v1, dp) = head_on(m, dt, 1000.0, 1.0, 1.0, 1.0);
        let (e0, e1) = crate::sim::contact::normal_speeds_after(1000.0, 1.0, 1.0, 0.0, 1.0);
        let err = (v0 - e0).abs().max((v1 - e1).abs());
        out.push(finding(
            "extremes",
            "mass ratio 1000:1, e = 1",
            m.name(),
            dp <= 1e-12 && err <= 1e-12,
            format!("momentum error {dp:.1e}, velocity error {err:.1e}"),
        ));
        let (v0, v1, dp) = head_on(m, dt, 1.0, 1.0, 1.0, 0.0);
        out.push(finding(
            "extremes",
            "equal masses, e = 0",
            m.name(),
            dp <= 1e-12 && (v0 - v1).abs() <= 1e-12,
            format!("velocities {v0:.6} and {v1:.6} m/s, momentum error {dp:.1e}"),
        ));
    }
    let (speed, g) = (rules::MAX_SPEED, rules::MAX_GRAVITY);
    let steps = scale.extreme_steps;
    for m in [Integrator::SemiImplicitEuler, Integrator::Continuous] {
        let scene = format!(
            "{EXTREME_SPHERES} spheres at {speed:.0e} m/s, g {g:.0e}, e = c_r = 1, dt 1 s, \
             {steps} steps"
        );
        let (holds, figure) = match elastic_spheres(m, EXTREME_SPHERES, speed, g, 1.0, steps) {
            Ok(r) => (
                r.energy_drift <= ELASTIC_ENERGY_BOUND,
                format!(
                    "energy drift {:.1e}{}",
                    r.energy_drift,
                    if r.capped_steps > 0 {
                        format!(", impact cap in {} steps", r.capped_steps)
                    } else {
                        String::new()
                    }
                ),
            ),
            Err(e) => (false, format!("cannot build: {e}")),
        };
        out.push(finding("extremes", &scene, m.name(), holds, figure));
    }
    out
}

/// The table, one line per finding.
pub(crate) fn table(findings: &[Finding]) -> String {
    use std::fmt::Write;
    let wc = findings
        .iter()
        .map(|f| f.check.len())
        .max()
        .unwrap_or(5)
        .max(5);
    let ws = findings
        .iter()
        .map(|f| f.scene.len())
        .max()
        .unwrap_or(5)
        .max(5);
    let wm = findings
        .iter()
        .map(|f| f.method.len())
        .max()
        .unwrap_or(6)
        .max(6);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:wc$}  {:ws$}  {:wm$}  result  measured",
        "check", "scene", "method"
    );
    let _ = writeln!(out, "{}", "-".repeat(wc + ws + wm + 20));
    for f in findings {
        let _ = writeln!(
            out,
            "{:wc$}  {:ws$}  {:wm$}  {:6}  {}",
            f.check,
            f.scene,
            f.method,
            if f.holds { "holds" } else { "FAILS" },
            f.figure
        );
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_slope_error_is_zero_on_a_line_and_grows_with_correlated_noise() {
        let line: Vec<(f64, f64)> = (0..100).map(|k| (k as f64, 3.0 + 2.0 * k as f64)).collect();
        let spread: f64 = (0..100).map(|k| (k as f64 - 49.5).powi(2)).sum();
        assert_eq!(super::slope_error(&line, 3.0, 2.0, spread), 0.0);
        // Noise of 1 that flips every step, then in runs of ten: the same
        // scatter, but the runs make about a tenth as many independent
        // samples.
        let noisy = |run: usize| -> Vec<(f64, f64)> {
            (0..1000)
                .map(|k| {
                    (
                        k as f64,
                        if (k / run).is_multiple_of(2) {
                            1.0
                        } else {
                            -1.0
                        },
                    )
                })
                .collect()
        };
        let spread: f64 = (0..1000).map(|k| (k as f64 - 499.5).powi(2)).sum();
        let (flips, runs) = (
            super::slope_error(&noisy(1), 0.0, 0.0, spread),
            super::slope_error(&noisy(10), 0.0, 0.0, spread),
        );
        let white = (1000.0 / 998.0 / spread).sqrt();
        assert!(
            (flips - white).abs() < 1e-12 * white,
            "{flips} against {white}"
        );
        assert!(runs > 2.5 * flips, "{runs} against {flips}");
    }
}
