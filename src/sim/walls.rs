//! The box `[0, 1]^3`. A sphere of radius `r` must keep its centre in
//! `[r, 1 - r]` on every axis.
//!
//! When a step carries a centre past a wall (or onto it) while moving into
//! it, the velocity component normal to that wall is reversed and scaled by
//! the restitution `c` (`c = 1` for `flip`). Where the impact happened
//! inside the step depends on how the method moved the body:
//!
//! - mirror (explicit and semi-implicit Euler): the overshoot is mirrored
//!   back into the box and scaled the same way: the distance travelled after
//!   the impact is `c` times what the step had carried it beyond the wall.
//!   For `flip` this makes the ping-pong path an exact triangle wave at any
//!   `dt`;
//! - at the crossing (velocity Verlet and RK4, whose free flight under
//!   uniform gravity is the exact parabola): the parabola is followed back
//!   to the instant it crossed the wall, the velocity *there* is reflected,
//!   and the body flies the rest of the step from the wall. Reflecting the
//!   end-of-step velocity instead (what the mirror does) returns the speed
//!   gravity added after the crossing as if the body had it at the wall, and
//!   gains energy at every bounce. A rebound that would land again within
//!   the step rests on the wall. A centre pushed past the wall by another
//!   stage, which never crossed it in flight, is mirrored.
//!
//! A rebound that carries the centre across the box past the other wall
//! meets that wall in the same step, by the same rule, from where the
//! first left it, and so on: one impact for each wall met (at most
//! [`MAX_REFLECTIONS`] a coordinate in a step, past which it is stopped on
//! the wall). For `flip` the ping-pong path stays the exact triangle wave
//! however far a step carries it, up to that many walls.
//!
//! A centre outside while already moving away (another stage pushed it
//! there, or, with gravity along the axis, the step's own flight crossed
//! the wall and turned back before the step ended) is only put back on
//! the wall. Whatever happened, every centre
//! ends the stage inside `[r, 1 - r]`.
//!
//! An impact slower than the rest threshold, or than gravity's resting
//! speed into that wall, uses `c = 0` ([`Restitution`]). The stage also sums
//! the impulses the walls gave (`m` times the velocity change), so momentum
//! can be balanced.
//!
//! Each sphere meets the walls on its own, so the stage runs in parallel
//! (rayon) over fixed chunks of spheres; the chunks' impulses are added in
//! chunk order, so every bit is the same for any number of threads.

use super::continuous::first_entry;
use super::restitution::Restitution;
use super::{Bodies, Integrator, Vec3, WallMode, WorldConfig};
use rayon::prelude::*;

/// Spheres per parallel task, and per partial sum of the impulse.
const CHUNK: usize = 4096;

/// What the wall stage did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct WallReport {
    /// Impacts that reversed a velocity component.
    pub impacts: usize,
    /// Sum of the impulses the walls gave, kg m/s.
    pub impulse: Vec3,
}

/// How the step moved the bodies: under the uniform acceleration
/// `gravity`, m/s^2, over `h` s, along the exact parabola (`parabola`) or
/// not. With a parabola the wall stage reflects at the crossing. Otherwise
/// it mirrors, keeping the energy the method keeps in flight: `shadow`
/// says which velocity that is, `u + shadow a h` (see [`mirror`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Flight {
    pub gravity: Vec3,
    pub h: f64,
    pub parabola: bool,
    pub shadow: f64,
}

impl Flight {
    /// The flight of a step of `h` s by `method` under `gravity`.
    pub fn of(method: Integrator, gravity: Vec3, h: f64) -> Flight {
        let (parabola, shadow) = match method {
            Integrator::VelocityVerlet | Integrator::Rk4 | Integrator::Continuous => (true, 0.0),
            Integrator::SemiImplicitEuler => (false, 0.5),
            Integrator::ExplicitEuler => (false, -0.5),
        };
        Flight {
            gravity,
            h,
            parabola,
            shadow,
        }
    }
}

/// Resolve wall contacts for every body after the step's `flight`: at the
/// crossing when it was the exact parabola, else by the mirror rule.
pub(crate) fn resolve_walls_after(
    bodies: &mut Bodies,
    mode: WallMode,
    restitution: impl Into<Restitution>,
    flight: Flight,
) -> WallReport {
    let rule = mode.rule(restitution.into());
    let Bodies {
        position,
        velocity,
        radius,
        mass,
        ..
    } = bodies;
    let chunks: Vec<WallReport> = position
        .par_chunks_mut(CHUNK)
        .zip(velocity.par_chunks_mut(CHUNK))
        .zip(radius.par_chunks(CHUNK))
        .zip(mass.par_chunks(CHUNK))
        .map(|(((x, v), r), m)| {
            let mut report = WallReport::default();
            for (((x, v), &r), &m) in x.iter_mut().zip(v).zip(r).zip(m) {
                resolve_sphere(x, v, r, m, rule, flight, &mut report);
            }
            report
        })
        .collect();
    chunks
        .into_iter()
        .fold(WallReport::default(), |total, c| WallReport {
            impacts: total.impacts + c.impacts,
            impulse: total.impulse + c.impulse,
        })
}

/// Put every centre back inside `[r, 1 - r]` without touching a velocity:
/// the walls as a position constraint, between the projection passes of a
/// deep pile (`World::step`), so that the next pass sees the overlaps the
/// walls leave; not when the support pass runs, which holds the walls
/// itself. The wall stage proper runs after the passes, as always.
pub(crate) fn clamp_to_box(bodies: &mut Bodies) {
    let Bodies {
        position, radius, ..
    } = bodies;
    position
        .par_chunks_mut(CHUNK)
        .zip(radius.par_chunks(CHUNK))
        .for_each(|(x, r)| {
            for (x, &r) in x.iter_mut().zip(r) {
                *x = x.clamp(Vec3::splat(r), Vec3::splat(1.0 - r));
            }
        });
}

/// Keep one sphere of radius `r` and mass `m` in the box, adding to `report`.
#[inline]
fn resolve_sphere(
    x: &mut Vec3,
    v: &mut Vec3,
    r: f64,
    m: f64,
    rule: Restitution,
    flight: Flight,
    report: &mut WallReport,
) {
    let (lo, hi) = (r, 1.0 - r);
    if x.cmpgt(Vec3::splat(lo)).all() && x.cmplt(Vec3::splat(hi)).all() {
        // Clear of every wall: no impact, nothing to clamp, no impulse
        // (what the loop below would find, without its work).
        return;
    }
    for axis in 0..3 {
        if x[axis] > lo && x[axis] < hi {
            // Clear of this axis's walls: no impact (what `follow_axis`
            // would find), nothing to clamp, no impulse.
            continue;
        }
        let before = v[axis];
        (x[axis], v[axis]) = follow_axis(x[axis], v[axis], r, axis, rule, flight, |_| {
            report.impacts += 1;
        });
        x[axis] = x[axis].clamp(lo, hi);
        report.impulse[axis] += m * (v[axis] - before);
    }
}

/// Reflections one coordinate may take in one step. A rebound that carries
/// a centre across the box past the other wall meets that wall in the same
/// step, and so on; a coordinate still past a wall after this many walls
/// (a sphere crossing the box a hundred times a step, or one as wide as
/// the box, which bounces without end) is stopped on the wall it is past:
/// its velocity component set to 0, which can only take energy away.
pub const MAX_REFLECTIONS: usize = 100;

/// Follow one coordinate at `p` moving at `u` (as the step's `flight`
/// left it) from wall to wall while each rebound carries it past the
/// other wall, passing each impact to `each` in turn; returns the coordinate
/// and velocity component after the last (not yet put back in the box).
/// Each impact starts where the one before left the centre: after an
/// impact at the crossing, the next crossing is looked for only in the
/// part of the step that followed it. The last impact of a chain stopped
/// at [`MAX_REFLECTIONS`] comes with `stopped` set, on the wall and at
/// rest.
#[inline]
fn follow_axis(
    mut p: f64,
    mut u: f64,
    r: f64,
    axis: usize,
    rule: Restitution,
    mut flight: Flight,
    mut each: impl FnMut(AxisImpact),
) -> (f64, f64) {
    // Each impact is passed on once the next is known, so that the last
    // of a stopped chain can say so.
    let mut last: Option<AxisImpact> = None;
    let mut stopped = true;
    for _ in 0..MAX_REFLECTIONS {
        // None: past the other wall yet moving away from it (an Euler
        // method's velocity in flight), to be put back on it.
        let Some(impact) = axis_impact(p, u, r, axis, rule, flight) else {
            stopped = false;
            break;
        };
        (p, u) = (impact.position, impact.velocity);
        if impact.at_crossing {
            flight.h = impact.flew;
        }
        each_of(last.replace(impact), &mut each);
        // Only a rebound past the other wall meets another in this step:
        // one left on the wall it met, even moving into it (an Euler
        // method's velocity in flight), meets it again in the next step.
        if !past_the_other(&impact, r) {
            stopped = false;
            break;
        }
    }
    if let Some(mut impact) = last {
        if stopped {
            // Still past a wall after the most walls a step follows.
            let wall = if impact.far { r } else { 1.0 - r };
            (p, u) = (wall, 0.0);
            (impact.position, impact.velocity, impact.stopped) = (p, u, true);
        }
        each(impact);
    }
    (p, u)
}

/// `impact` to `each`, if any.
#[inline]
fn each_of(impact: Option<AxisImpact>, each: &mut impl FnMut(AxisImpact)) {
    if let Some(impact) = impact {
        each(impact);
    }
}

/// Whether `impact` of a sphere of radius `r` left its centre past the
/// other wall of its axis.
#[inline]
fn past_the_other(impact: &AxisImpact, r: f64) -> bool {
    if impact.far {
        impact.position < r
    } else {
        impact.position > 1.0 - r
    }
}

/// One coordinate's impact with a wall, as the wall stage resolves it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisImpact {
    /// The wall: the axis (0 x, 1 y, 2 z), and whether it is the far one.
    pub axis: usize,
    pub far: bool,
    /// Reflected at the crossing of the exact parabola (velocity Verlet,
    /// RK4); else the overshoot was mirrored (the Euler methods).
    pub at_crossing: bool,
    /// The velocity component the stage found, moving into the wall, m/s.
    pub before: f64,
    /// How far past the wall the step carried the centre, m.
    pub overshoot: f64,
    /// The speed at the wall, m/s: the mirror's (the overshoot fallen
    /// back), or the parabola's at the crossing.
    pub at_wall: f64,
    /// The coefficient the impact used: `c_r` (1 for flip walls), or 0 below
    /// the rest rules.
    pub coefficient: f64,
    /// The rebound could not leave the wall within the step: the sphere
    /// rests on it.
    pub rests: bool,
    /// At the crossing: the time from the impact to the end of the step,
    /// s (0 for the mirror, which has no instant of impact).
    pub flew: f64,
    /// The rebound carried the centre past the other wall after the most
    /// walls a step follows ([`MAX_REFLECTIONS`]): the stage stopped it on
    /// the wall it is past, at rest (`position`, `velocity`).
    pub stopped: bool,
    /// The coordinate and the velocity component after.
    pub position: f64,
    pub velocity: f64,
}

/// The impact of a coordinate at `p` moving at `u` along `axis` of a
/// sphere of radius `r` with a wall it is past (or on) and moving into,
/// after the step's `flight`, with the walls' `rule` (`WallMode::rule`
/// applied); `None` when it meets no wall.
#[inline]
pub(crate) fn axis_impact(
    p: f64,
    u: f64,
    r: f64,
    axis: usize,
    rule: Restitution,
    flight: Flight,
) -> Option<AxisImpact> {
    let (lo, hi) = (r, 1.0 - r);
    let upper = if p <= lo && u < 0.0 {
        false
    } else if p >= hi && u > 0.0 {
        true
    } else {
        return None;
    };
    let wall = if upper { hi } else { lo };
    let g = flight.gravity[axis];
    let crossed = if flight.parabola {
        crossing(p, u, g, wall, upper, flight.h)
    } else {
        None
    };
    let impact =
        |at_crossing, flew, at_wall, coefficient, rests, (position, velocity)| AxisImpact {
            axis,
            far: upper,
            at_crossing,
            before: u,
            overshoot: (p - wall).abs(),
            at_wall,
            coefficient,
            rests,
            flew,
            stopped: false,
            position,
            velocity,
        };
    Some(match crossed {
        Some((tau, a)) => {
            // Back along the parabola to the wall, reflect there, and fly
            // the remaining `tau` from it.
            let at_wall = u - a * tau;
            let c = rule.at_wall(at_wall.abs(), axis, upper);
            let out = -c * at_wall;
            let end = wall + out * tau + 0.5 * a * tau * tau;
            let lands_again = if upper { end > hi } else { end < lo };
            let after = if lands_again {
                (wall, 0.0)
            } else {
                (end, out + a * tau)
            };
            impact(true, tau, at_wall.abs(), c, lands_again, after)
        }
        None => {
            let side = if upper { 1.0 } else { -1.0 };
            let shift = flight.shadow * g * flight.h;
            let m = mirror(p, u, wall, side, side * g, shift, |w| {
                rule.at_wall(w, axis, upper)
            });
            impact(false, 0.0, m.at_wall, m.coefficient, m.rests, m.after)
        }
    })
}

/// What the mirror rule did: the speed at the wall, the coefficient it
/// used, whether the rebound rests on the wall, and the coordinate and
/// velocity component after.
struct Mirrored {
    at_wall: f64,
    coefficient: f64,
    rests: bool,
    after: (f64, f64),
}

/// The mirror rule for a centre at `p` moving at `u` past the wall at
/// `wall` on the side `side` (+1: the wall at `1 - r`, -1: at `r`), with
/// `into` the acceleration towards the wall, and restitution `c(speed)`.
/// The overshoot `d` is mirrored back and scaled by `c`. Without gravity
/// along the axis the velocity is `-c u`.
///
/// With gravity, an Euler step keeps an energy of its own in flight: with
/// `a` the acceleration, semi-implicit Euler keeps `(u + a h / 2)^2 / 2 -
/// a x` exactly, explicit Euler `(u - a h / 2)^2 / 2 - a x` (which is why
/// `u^2 / 2 - a x` drifts in flight, down for the one, up for the other).
/// The mirror works on that velocity, `v = u + shift` (`shift = shadow a
/// h`): the speed at the wall is what `v` was before the overshoot was
/// fallen (`w^2 = v^2 - 2 into d`), the impact returns `c w`, the way back
/// out pays for the height (`v'^2 = (c w)^2 - 2 into c d`), and `u' = v' -
/// shift`. At `c = 1` the impact keeps the method's energy exactly; `-c u`
/// instead keeps the speed gained below the wall and lifts the centre back
/// up for nothing, which pumps a micro-bounce. A rebound too slow to climb
/// out rests on the wall.
#[inline]
fn mirror(
    p: f64,
    u: f64,
    wall: f64,
    side: f64,
    into: f64,
    shift: f64,
    c: impl Fn(f64) -> f64,
) -> Mirrored {
    let d = side * (p - wall);
    if into == 0.0 {
        let w = u.abs();
        let c = c(w);
        return Mirrored {
            at_wall: w,
            coefficient: c,
            rests: false,
            after: (wall - side * c * d, -c * u),
        };
    }
    let v = u + shift;
    let w = (v * v - 2.0 * into * d).max(0.0).sqrt();
    let c = c(w);
    let out2 = c * c * w * w - 2.0 * into * c * d;
    let rests = out2 <= 0.0;
    Mirrored {
        at_wall: w,
        coefficient: c,
        rests,
        after: if rests {
            (wall, 0.0)
        } else {
            (wall - side * c * d, -side * out2.sqrt() - shift)
        },
    }
}

/// The wall impacts the wall stage gives a sphere of radius `r` that the
/// step of `h` s by `config` left at `x` moving at `v` (before the stage),
/// axis by axis, and on one axis wall by wall in the order met: what the
/// visualiser's panel shows for one sphere.
pub fn wall_impacts(x: Vec3, v: Vec3, r: f64, config: &WorldConfig, h: f64) -> Vec<AxisImpact> {
    let rule = config
        .wall_mode
        .rule(config.wall_rule().with_resting(config.resting(h)));
    let flight = Flight::of(config.integrator, config.gravity, h);
    let mut impacts = Vec::new();
    for axis in 0..3 {
        follow_axis(x[axis], v[axis], r, axis, rule, flight, |i| impacts.push(i));
    }
    impacts
}

/// How long ago, within the last `h` s, a coordinate now at `p` moving at
/// `u` under the acceleration `a` crossed the wall at `wall` (`upper`: the
/// wall at `1 - r`) along its parabola: `(tau, a)`; `None` when it did not
/// cross it in flight.
#[inline]
fn crossing(p: f64, u: f64, a: f64, wall: f64, upper: bool, h: f64) -> Option<(f64, f64)> {
    // Backwards the coordinate is at p - u tau + a tau^2 / 2; the gap to the
    // wall seen from outside closes when it crosses back into the box.
    let tau = if upper {
        first_entry(p - wall, -u, 0.5 * a, h)
    } else {
        first_entry(wall - p, u, -0.5 * a, h)
    }?;
    (tau > 0.0).then_some((tau, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mirror rule with no force: what every method does at a wall
    /// when nothing accelerates the sphere.
    fn resolve_walls(
        bodies: &mut Bodies,
        mode: WallMode,
        restitution: impl Into<Restitution>,
    ) -> WallReport {
        let still = Flight::of(Integrator::SemiImplicitEuler, Vec3::ZERO, 0.0);
        resolve_walls_after(bodies, mode, restitution, still)
    }
    use crate::sim::{Body, Vec3};

    fn one(position: Vec3, velocity: Vec3) -> Bodies {
        [Body {
            position,
            velocity,
            radius: 0.1,
            mass: 1.0,
        }]
        .into_iter()
        .collect()
    }

    #[test]
    fn an_overshoot_is_mirrored_and_scaled_by_restitution() {
        let mut b = one(Vec3::new(0.5, 0.04, 0.95), Vec3::new(0.0, -2.0, 1.0));
        let impacts = resolve_walls(&mut b, WallMode::Restitution, 0.5).impacts;
        assert_eq!(impacts, 2);
        // Floor: 0.06 past y = 0.1, half of it mirrored back; speed halved.
        assert!((b.position[0].y - 0.13).abs() < 1e-15);
        assert_eq!(b.velocity[0].y, 1.0);
        // Far z wall at 0.9: 0.05 past it.
        assert!((b.position[0].z - 0.875).abs() < 1e-15);
        assert_eq!(b.velocity[0].z, -0.5);
    }

    #[test]
    fn flip_keeps_the_speed_whatever_the_restitution_setting() {
        let mut b = one(Vec3::new(0.5, 0.95, 0.5), Vec3::new(0.0, 1.0, 0.0));
        resolve_walls(&mut b, WallMode::Flip, 0.2);
        assert_eq!(b.velocity[0].y, -1.0);
        assert!((b.position[0].y - 0.85).abs() < 1e-15);
    }

    #[test]
    fn a_centre_outside_but_moving_away_is_only_put_back_on_the_wall() {
        let mut b = one(Vec3::new(0.05, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(resolve_walls(&mut b, WallMode::Restitution, 0.9).impacts, 0);
        assert_eq!(b.position[0].x, 0.1);
        assert_eq!(b.velocity[0].x, 1.0);
    }

    /// `u^2 / 2 + g y` per unit mass of body 0, with `g` = 9.81 down.
    fn energy(b: &Bodies) -> f64 {
        0.5 * b.velocity[0].y * b.velocity[0].y + 9.81 * b.position[0].y
    }

    #[test]
    fn reflecting_at_the_crossing_keeps_the_energy_of_the_parabola() {
        // A ball that crossed the floor 2 ms before the end of a 10 ms step
        // of free flight: end state from the exact parabola.
        let (g, h, tau, w) = (-9.81, 0.01, 0.002, -1.0);
        let (y, v) = (0.1 + w * tau + 0.5 * g * tau * tau, w + g * tau);
        let mut b = one(Vec3::new(0.5, y, 0.5), Vec3::new(0.0, v, 0.0));
        let before = 0.5 * w * w + 9.81 * 0.1;
        let flight = Flight::of(Integrator::VelocityVerlet, Vec3::new(0.0, g, 0.0), h);
        resolve_walls_after(&mut b, WallMode::Restitution, 1.0, flight);
        assert!(
            (energy(&b) - before).abs() < 1e-12,
            "{} {before}",
            energy(&b)
        );
        // Out at 1 m/s from the wall 2 ms ago.
        assert!((b.velocity[0].y - (1.0 + g * tau)).abs() < 1e-12);
    }

    #[test]
    fn the_euler_mirror_keeps_the_energy_the_method_keeps_in_flight() {
        // Semi-implicit Euler keeps (u + a h / 2)^2 / 2 - a y exactly in
        // flight; an elastic wall keeps it too.
        let (g, h) = (-9.81, 0.01);
        let shadow = |b: &Bodies| {
            let u = b.velocity[0].y + 0.5 * g * h;
            0.5 * u * u - g * b.position[0].y
        };
        let mut b = one(Vec3::new(0.5, 0.097, 0.5), Vec3::new(0.0, -1.3, 0.0));
        let before = shadow(&b);
        let flight = Flight::of(Integrator::SemiImplicitEuler, Vec3::new(0.0, g, 0.0), h);
        resolve_walls_after(&mut b, WallMode::Restitution, 1.0, flight);
        assert!((shadow(&b) - before).abs() < 1e-12);
        assert!(b.velocity[0].y > 0.0 && b.position[0].y > 0.1);
    }

    #[test]
    fn the_euler_mirror_with_restitution_keeps_c_squared_of_the_methods_energy_above_the_wall() {
        // Each Euler method keeps (u + shadow a h)^2 / 2 - a y in flight;
        // measured from the wall (y = 0.1), c_r = 0.8 returns 0.64 of it,
        // and the overshoot of 3 mm comes back as 0.8 of it.
        let (g, h, c) = (-9.81, 0.01, 0.8);
        for method in [Integrator::SemiImplicitEuler, Integrator::ExplicitEuler] {
            let flight = Flight::of(method, Vec3::new(0.0, g, 0.0), h);
            let above_the_wall = |b: &Bodies| {
                let u = b.velocity[0].y + flight.shadow * g * h;
                0.5 * u * u - g * (b.position[0].y - 0.1)
            };
            let mut b = one(Vec3::new(0.5, 0.097, 0.5), Vec3::new(0.0, -1.3, 0.0));
            let before = above_the_wall(&b);
            let report = resolve_walls_after(&mut b, WallMode::Restitution, c, flight);
            assert_eq!(report.impacts, 1, "{method}");
            assert!(
                (above_the_wall(&b) - c * c * before).abs() < 1e-12,
                "{method}: {} against {}",
                above_the_wall(&b),
                c * c * before
            );
            assert!(
                (b.position[0].y - (0.1 + c * 0.003)).abs() < 1e-15,
                "{method}"
            );
            assert!(b.velocity[0].y > 0.0, "{method}");
        }
    }

    #[test]
    fn at_the_crossing_the_wall_returns_c_times_the_speed_there_and_the_parabola_goes_on() {
        // A step of 10 ms by velocity Verlet or RK4 from a state whose
        // parabola meets the floor at 1 m/s 8 ms in: c_r = 0.8 sends it
        // back at 0.8 m/s from the wall for the last 2 ms.
        let (g, h, c, tau, w) = (-9.81, 0.01, 0.8, 0.002, -1.0);
        let t = h - tau;
        let v0 = w - g * t;
        let y0 = 0.1 - v0 * t - 0.5 * g * t * t;
        let a = Vec3::new(0.0, g, 0.0);
        for method in [Integrator::VelocityVerlet, Integrator::Rk4] {
            let mut b = one(Vec3::new(0.5, y0, 0.5), Vec3::new(0.0, v0, 0.0));
            method.integrate(&mut b, a, h);
            let report =
                resolve_walls_after(&mut b, WallMode::Restitution, c, Flight::of(method, a, h));
            assert_eq!(report.impacts, 1, "{method}");
            let (y, v) = (0.1 - c * w * tau + 0.5 * g * tau * tau, -c * w + g * tau);
            assert!(
                (b.position[0].y - y).abs() < 1e-12,
                "{method}: y = {} against {y}",
                b.position[0].y
            );
            assert!(
                (b.velocity[0].y - v).abs() < 1e-12,
                "{method}: v = {} against {v}",
                b.velocity[0].y
            );
        }
    }

    /// Where a coordinate that moved freely to `q` (any distance past the
    /// walls) ends between elastic walls at `r` and `1 - r`, and the sign
    /// of its velocity then, for a velocity of sign `sign` before: the
    /// triangle wave, by unfolding the box (`q` mod `2 (1 - 2 r)`).
    fn triangle(q: f64, sign: f64, r: f64) -> (f64, f64) {
        let span = 1.0 - 2.0 * r;
        let m = (q - r).rem_euclid(2.0 * span);
        if m <= span {
            (r + m, sign)
        } else {
            (r + 2.0 * span - m, -sign)
        }
    }

    #[test]
    fn a_rebound_across_the_box_meets_the_other_wall_in_the_same_step() {
        // Without gravity every method moves a sphere in a straight line;
        // elastic walls then fold its path into the box however far the
        // step carried it: a triangle wave, one impact a wall met.
        for method in [
            Integrator::ExplicitEuler,
            Integrator::SemiImplicitEuler,
            Integrator::VelocityVerlet,
            Integrator::Rk4,
        ] {
            for (y0, v, h) in [
                (0.23, -70.0, 1.0 / 60.0),
                (0.5, 1.0, 1.0),
                (0.9, 1.0, 1.0),
                (0.5, -3.7, 1.0),
                (0.15, 123.4, 0.5),
            ] {
                let mut b = one(Vec3::new(0.5, y0, 0.5), Vec3::new(0.0, v, 0.0));
                method.integrate(&mut b, Vec3::ZERO, h);
                let q = b.position[0].y;
                let flight = Flight::of(method, Vec3::ZERO, h);
                let report = resolve_walls_after(&mut b, WallMode::Flip, 0.3, flight);
                let (y, sign) = triangle(q, v.signum(), 0.1);
                let case = format!("{method}: from {y0} at {v} m/s for {h} s");
                assert!(
                    (b.position[0].y - y).abs() < 1e-12,
                    "{case}: y = {}, not {y}",
                    b.position[0].y
                );
                assert_eq!(b.velocity[0].y, sign * v.abs(), "{case}");
                // The walls met: one for each multiple of the span past
                // the first wall.
                let past = if v > 0.0 { q - 0.9 } else { 0.1 - q };
                let met = if past > 0.0 {
                    (past / 0.8).floor() as usize + 1
                } else {
                    0
                };
                assert_eq!(report.impacts, met, "{case}");
            }
        }
    }

    #[test]
    fn each_wall_met_in_one_step_scales_what_is_left_by_c() {
        // 2 m past the floor at y = 0.1 moving down at 4 m/s, c = 1/2: 1 m
        // comes back, of which 0.8 m reaches the ceiling (y = 0.9) at 2 m/s;
        // the 0.2 m left comes back halved, to 0.8, at 1 m/s down.
        let mut b = one(Vec3::new(0.5, -1.9, 0.5), Vec3::new(0.0, -4.0, 0.0));
        let report = resolve_walls(&mut b, WallMode::Restitution, 0.5);
        assert_eq!(report.impacts, 2);
        assert!((b.position[0].y - 0.8).abs() < 1e-15, "{}", b.position[0].y);
        assert_eq!(b.velocity[0].y, -1.0);
        // Momentum: the walls took the difference.
        assert_eq!(report.impulse.y, 3.0);
    }

    #[test]
    fn bounces_between_floor_and_ceiling_in_one_step_keep_each_methods_energy() {
        // A step of 0.1 s from 0.5 m down at 20 m/s under g = 9.81: the
        // path meets the floor, climbs past the ceiling and comes back. Elastic walls keep what each method keeps in flight:
        // velocity Verlet and RK4 the parabola's u^2/2 - g y, semi-implicit
        // Euler (u + g h/2)^2/2 - g y, explicit Euler (u - g h/2)^2/2 - g y.
        let (g, h) = (-9.81, 0.1);
        let a = Vec3::new(0.0, g, 0.0);
        for method in [
            Integrator::VelocityVerlet,
            Integrator::Rk4,
            Integrator::SemiImplicitEuler,
            Integrator::ExplicitEuler,
        ] {
            let flight = Flight::of(method, a, h);
            let energy = |b: &Bodies| {
                let u = b.velocity[0].y + flight.shadow * g * h;
                0.5 * u * u - g * b.position[0].y
            };
            let mut b = one(Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.0, -20.0, 0.0));
            method.integrate(&mut b, a, h);
            let before = energy(&b);
            let report = resolve_walls_after(&mut b, WallMode::Restitution, 1.0, flight);
            assert!(report.impacts >= 2, "{method}: {} impacts", report.impacts);
            let y = b.position[0].y;
            assert!(y > 0.1 && y < 0.9, "{method}: y = {y}");
            assert!(
                (energy(&b) - before).abs() < 1e-12 * before.abs(),
                "{method}: {} against {before}",
                energy(&b)
            );
        }
    }

    #[test]
    fn a_sphere_as_wide_as_the_box_is_stopped_and_never_gains_energy() {
        // Its walls coincide: it would bounce without end, so the stage
        // stops it on the wall after its most reflections. Under gravity,
        // step after step, for every method and both kinds of walls, it
        // stays at the centre and never speeds up.
        let g = Vec3::new(0.0, -9.81, 0.0);
        let h = 1.0 / 120.0;
        for method in [
            Integrator::ExplicitEuler,
            Integrator::SemiImplicitEuler,
            Integrator::VelocityVerlet,
            Integrator::Rk4,
        ] {
            for (mode, c) in [(WallMode::Flip, 0.5), (WallMode::Restitution, 1.0)] {
                let mut b: Bodies = [Body {
                    position: Vec3::splat(0.5),
                    velocity: Vec3::new(0.0, -1.0, 0.0),
                    radius: 0.5,
                    mass: 1.0,
                }]
                .into_iter()
                .collect();
                let mut stopped = 0;
                for step in 0..1200 {
                    method.integrate(&mut b, g, h);
                    let flight = Flight::of(method, g, h);
                    let report = resolve_walls_after(&mut b, mode, c, flight);
                    stopped += usize::from(report.impacts == MAX_REFLECTIONS);
                    assert_eq!(b.position[0], Vec3::splat(0.5), "{method}");
                    let v = b.velocity[0].length();
                    assert!(v <= 1.0, "{method}, {mode:?}, step {step}: {v} m/s");
                }
                assert!(stopped > 0, "{method}, {mode:?}: never stopped");
            }
        }
        // The panel's record of it: the last impact says it was stopped.
        let config = WorldConfig {
            gravity: Vec3::ZERO,
            ..WorldConfig::default()
        };
        let impacts = wall_impacts(Vec3::new(0.5, 0.6, 0.5), Vec3::Y, 0.5, &config, h);
        assert_eq!(impacts.len(), MAX_REFLECTIONS);
        assert!(impacts[..MAX_REFLECTIONS - 1].iter().all(|i| !i.stopped));
        let last = impacts[MAX_REFLECTIONS - 1];
        assert!(last.stopped);
        assert_eq!((last.position, last.velocity), (0.5, 0.0));
    }
}
