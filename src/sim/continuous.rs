//! The continuous method: times of impact inside the step.
//!
//! The discrete methods move every body a whole step and then look for
//! overlaps; a fast sphere can jump over a wall or another sphere, and the
//! impact happens at the end of the step instead of when it really did.
//! This method moves bodies only as far as the earliest impact:
//!
//! 1. free flight: under uniform gravity the motion between impacts is
//!    exactly `x(s) = x + v s + g s^2 / 2`, `v(s) = v + g s`;
//! 2. time of impact: a centre meets a wall when one coordinate of that
//!    parabola reaches `r` or `1 - r` (a quadratic per axis); two spheres
//!    feel the same gravity, so their relative motion `d(s) = d + w s` is a
//!    straight line and they meet when `|d(s)|^2 = (r1 + r2)^2` (a quadratic);
//! 3. the earliest impact is resolved with the same rules as the discrete
//!    stages (`v_n <- -c_r v_n` at a wall, the lesson's V1/V2 for a pair,
//!    the rest threshold) at the exact instant of contact, and the step goes
//!    on from there.
//!
//! Impacts are kept in a priority queue (earliest first). Each body keeps
//! its own clock and a version number; resolving an impact moves only the
//! bodies involved to its instant, bumps their versions (which makes every
//! queued impact of theirs stale) and schedules their next impacts. Without
//! pair collisions every coordinate of every body is independent (a wall
//! changes only its own coordinate): one pass moves every coordinate whose
//! free flight stays inside the box, and only the few that meet a wall
//! solve their impacts, with no queue.
//!
//! Rest. With `c_r < 1` a ball on a floor makes infinitely many bounces in
//! finite time. After an impact on a wall that gravity pushes into, the
//! remaining bounces last `2 u / (g (1 - c_r))` in all (`u` the outgoing
//! speed); when that fits in what is left of the step, the normal speed is
//! set to 0 and the body rests on the wall: it is then "supported", and
//! gravity's component into that wall no longer moves it (the wall's normal
//! force cancels it) until an impact lifts it. Only in this case can the
//! relative motion of a pair be curved (one body supported, the other in
//! flight); its time of impact is then the first root of a quartic, found
//! by splitting at the roots of the derivatives and bisecting.
//!
//! Resting contact. Spheres pressed together under gravity ask for
//! infinitely many impacts in finite time too (inelastic collapse): a
//! sphere lying on another that lies on the floor falls into it, is
//! stopped, passes the blow down, the floor sends it back up, and so on,
//! ever faster; perfectly elastic spheres (`e = 1`) lying on each other
//! ask for endless impacts of no speed at all. With resting contact on
//! (`rest_steps > 0`), a pair that touches (to rounding) and moves along
//! its normal slower than `(rest_steps + 1) |g| h` when an impact of one
//! of its spheres is predicted rests: no impact is predicted for it, and
//! it is listed. That speed is the resting threshold `rest_steps |g| h`
//! of the discrete methods, plus what gravity adds to a resting pair
//! within the step. Perfectly elastic pairs (`e = 1`) rest only below the
//! part of it along their normal, `(rest_steps + 1) |g . n| h`, as the
//! discrete methods count gravity: side by side they keep every impact. A
//! resting pair may sink into itself by about `|g| h^2` by the end of the
//! step, where `settle_resting` takes out what it gathered: from the lowest
//! pair up, the resting pairs that overlap are pushed apart and lose their
//! normal approach (the lesson's projection and V1/V2 with `e = 0`, except
//! that the lower sphere of a pair within 60 degrees of the vertical, or
//! one pressed into a wall, holds the other: shock propagation), the walls
//! put back what this pushed past them (with resting contact on the walls
//! gravity pushes into), and [`SETTLE_PASSES`] passes over the velocities
//! take out the approach each pass gave back to the pairs before it. A pair that
//! approaches faster, or that does not touch, meets as an impact with the
//! lesson's rule at any speed: where no pair touches when its impact is
//! predicted (a dilute scene) the motion is the same as without the rule.
//! A pair that meets exactly as a step begins, even in the air, touches
//! then, and rests if it is that slow. The rule reads only
//! the state, and keeps nothing from one step to the next.
//!
//! Neighbour lists. Which pairs can meet is found from a grid, once for
//! several steps: the pairs closer than `r_i + r_j + 2 s`, the skin `s`
//! twice the farthest a body flies in the step, between [`SKIN`] of the
//! largest radius and the largest radius. The lists hold while every body
//! keeps within `s` of where they were made; a body that may leave that
//! bound is tested against every body (too many of them, and the lists are
//! made again). When many bodies fly farther than the largest radius in a
//! step (a dilute fast scene), the skin is the farthest flight instead, and
//! the lists are made again every step. The lists
//! only choose which pairs are tested: every pair that can meet within the
//! step is, whatever lists a world has, so the motion does not depend on
//! them.
//!
//! Fast spheres under strong gravity can ask for millions of impacts in
//! one step, and resting contact off, a pile for unboundedly many. A step
//! resolves
//! at most [`EVENT_ALLOWANCE`] + [`EVENTS_PER_BODY`] x bodies impacts, and
//! says so in `StepStats::event_cap_reached` when it reaches that cap. The
//! rest of such a step keeps the energy where the impacts would (`e = c_r =
//! 1`), with one exception named in [`return_to_walls`]:
//!
//! - each body finishes it against the walls alone: in closed form
//!   ([`elastic_axis`]: between walls that return every impact at full
//!   speed, a coordinate's motion is periodic), after a share of the cap
//!   impact by impact where the walls take energy; no centre leaves the
//!   box and no wall makes energy;
//! - the pairs that met meanwhile overlap; the world's contact stage
//!   projects them apart, which keeps each pair's centre of mass, and so
//!   the potential energy, and gives them the lesson's V1/V2;
//! - [`return_to_walls`] puts back a centre the projection pushed past a
//!   wall, its speed paying for the height, where the discrete wall stage
//!   would mirror it up for nothing.
//!
//! Free flight to the end of the step and the discrete wall stage, the
//! earlier way to finish, carried centres up to `v dt` past the walls and
//! put them back inside with the speed they had gained falling: under
//! strong gravity, energy without bound. With walls only, the closed form
//! is the exact motion when the walls are elastic (no cap is reported);
//! with `c_r < 1` it keeps the energy the impacts past the cap would have
//! taken.
//!
//! This module owns the times of impact and their order; the impact rules
//! themselves are the contact solver's and the rest threshold's.

use super::contact::{apply_pair_impulse, solve_contacts, test_pair, test_pair_within};
use super::restitution::Restitution;
use super::walls::clamp_to_box;
use super::world::StepStats;
use super::{Bodies, Contact, Vec3, WorldConfig};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Impacts a step may resolve per body, beyond [`EVENT_ALLOWANCE`].
pub(crate) const EVENTS_PER_BODY: usize = 8;
/// Impacts a step may always resolve.
pub(crate) const EVENT_ALLOWANCE: usize = 1_000;

/// Whether a body rests on the wall that the acceleration `a` pushes it into
/// (one axis).
#[inline]
fn supported(p: f64, u: f64, a: f64, lo: f64, hi: f64) -> bool {
    u == 0.0 && ((a < 0.0 && p <= lo) || (a > 0.0 && p >= hi))
}

/// The acceleration a body of radius `r` at `p` moving at `u` feels under
/// gravity `g`: `g`, except on the axes where it rests on a wall.
#[inline]
pub(crate) fn effective_acceleration(p: Vec3, u: Vec3, g: Vec3, r: f64) -> Vec3 {
    let (lo, hi) = (r, 1.0 - r);
    let mut a = g;
    for k in 0..3 {
        if supported(p[k], u[k], g[k], lo, hi) {
            a[k] = 0.0;
        }
    }
    a
}

/// Exact free flight over `s` seconds.
#[inline]
pub(crate) fn free_flight(p: Vec3, u: Vec3, g: Vec3, r: f64, s: f64) -> (Vec3, Vec3) {
    if s == 0.0 {
        return (p, u);
    }
    let a = effective_acceleration(p, u, g, r);
    (p + u * s + a * (0.5 * s * s), u + a * s)
}

/// The smallest `s` in `[0, horizon]` at which `f(s) = c0 + c1 s + c2 s^2`
/// enters `f <= 0` while decreasing: the instant a gap `f` closes. A gap
/// already closed (`c0 <= 0`) counts when it is closing now or turns back to
/// close later.
pub fn first_entry(c0: f64, c1: f64, c2: f64, horizon: f64) -> Option<f64> {
    let s = if c0 <= 0.0 {
        if c1 < 0.0 {
            return Some(0.0);
        }
        if c2 >= 0.0 || 0.5 * c1 > -c2 * horizon {
            // Opening for good, or not back before c1 / (2 |c2|) > horizon.
            return None;
        }
        // Opening now, closing again after the turn at -c1 / (2 c2).
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc <= 0.0 {
            -c1 / (2.0 * c2)
        } else {
            -0.5 * (c1 + disc.sqrt()) / c2
        }
    } else if c2 == 0.0 {
        if c1 >= 0.0 {
            return None;
        }
        -c0 / c1
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc < 0.0 {
            return None;
        }
        let sign = if c1 < 0.0 { -1.0 } else { 1.0 };
        let q = -0.5 * (c1 + sign * disc.sqrt());
        let (r1, r2) = (q / c2, c0 / q);
        let s = match (r1 >= 0.0, r2 >= 0.0) {
            (true, true) => r1.min(r2),
            (true, false) => r1,
            (false, true) => r2,
            (false, false) => return None,
        };
        if c1 + 2.0 * c2 * s >= 0.0 {
            return None; // grazing: the gap touches zero and opens again
        }
        s
    };
    (s <= horizon).then_some(s)
}

fn eval(c: &[f64], s: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * s + k)
}

/// The coefficients of the derivative of `c` into `d` (`c.len() - 1` of
/// them).
fn derivative_into(c: &[f64], d: &mut [f64]) {
    for (k, (slot, &v)) in d.iter_mut().zip(c.iter().skip(1)).enumerate() {
        *slot = (k + 1) as f64 * v;
    }
}

/// A root of `c` in `[a, b]`, where `c` changes sign, to the last bit.
fn bisect(c: &[f64], mut a: f64, mut b: f64) -> f64 {
    let fa_positive = eval(c, a) > 0.0;
    loop {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            return b;
        }
        if (eval(c, m) > 0.0) == fa_positive {
            a = m;
        } else {
            b = m;
        }
    }
}

/// The roots of the polynomial `c` (coefficients from the constant up) in
/// the open interval `(lo, hi)`, ascending, into `out` (room for its
/// degree); returns how many. The roots of its derivative split the
/// interval into pieces where it is monotone, each piece holds at most
/// one root. `scratch` has room for `degree^2` numbers.
fn roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64], scratch: &mut [f64]) -> usize {
    let degree = c.iter().rposition(|&k| k != 0.0).unwrap_or(0);
    match degree {
        0 => 0,
        1 => {
            let s = -c[0] / c[1];
            if s > lo && s < hi {
                out[0] = s;
                1
            } else {
                0
            }
        }
        _ => {
            let (d, rest) = scratch.split_at_mut(degree);
            derivative_into(&c[..=degree], d);
            let (turns, rest) = rest.split_at_mut(degree - 1);
            let k = roots_in(d, lo, hi, turns, rest);
            let mut count = 0;
            let mut a = lo;
            for b in turns[..k].iter().copied().chain([hi]) {
                let (fa, fb) = (eval(c, a), eval(c, b));
                if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
                    out[count] = bisect(c, a, b);
                    count += 1;
                } else if fb == 0.0 && b < hi {
                    out[count] = b;
                    count += 1;
                }
                a = b;
            }
            count
        }
    }
}

/// Polynomials up to this many coefficients are solved without the heap.
const ON_STACK: usize = 9;

/// [`first_entry`] for a polynomial of any degree.
pub fn first_entry_poly(c: &[f64], horizon: f64) -> Option<f64> {
    let n = c.len().saturating_sub(1);
    let m = n.saturating_sub(1);
    let (mut d_stack, mut turns_stack, mut scratch_stack) =
        ([0.0; ON_STACK], [0.0; ON_STACK], [0.0; ON_STACK * ON_STACK]);
    let mut heap = Vec::new();
    let (d, turns, scratch) = if c.len() <= ON_STACK {
        (
            &mut d_stack[..n],
            &mut turns_stack[..m],
            &mut scratch_stack[..m * m],
        )
    } else {
        heap.resize(n + m + m * m, 0.0);
        let (d, rest) = heap.split_at_mut(n);
        let (turns, scratch) = rest.split_at_mut(m);
        (d, turns, scratch)
    };
    derivative_into(c, d);
    let (f0, df0) = (eval(c, 0.0), eval(d, 0.0));
    if f0 <= 0.0 && df0 < 0.0 {
        return Some(0.0);
    }
    let k = roots_in(d, 0.0, horizon, turns, scratch);
    let mut a = 0.0;
    for b in turns[..k].iter().copied().chain([horizon]) {
        let (fa, fb) = (eval(c, a), eval(c, b));
        if fa > 0.0 && fb <= 0.0 {
            return Some(bisect(c, a, b));
        }
        if fa <= 0.0 && fb < fa {
            return Some(a);
        }
        a = b;
    }
    None
}

/// The earliest wall impact of one coordinate (`p`, `u`, acceleration `a`,
/// walls at `lo` and `hi`) within `horizon`: `(s, upper)`.
#[inline]
pub(crate) fn axis_impact(
    p: f64,
    u: f64,
    a: f64,
    lo: f64,
    hi: f64,
    horizon: f64,
) -> Option<(f64, bool)> {
    // Farthest the coordinate can move within the horizon.
    let travel = u.abs() * horizon + 0.5 * a.abs() * horizon * horizon;
    let lower = (p - lo <= travel)
        .then(|| first_entry(p - lo, u, 0.5 * a, horizon))
        .flatten();
    let upper = (hi - p <= travel)
        .then(|| first_entry(hi - p, -u, -0.5 * a, horizon))
        .flatten();
    match (lower, upper) {
        (Some(l), Some(h)) if h < l => Some((h, true)),
        (Some(l), _) => Some((l, false)),
        (None, Some(h)) => Some((h, true)),
        (None, None) => None,
    }
}

/// The earliest wall a body meets within `horizon`: `(s, axis, upper)`.
pub(crate) fn wall_impact(
    p: Vec3,
    u: Vec3,
    a: Vec3,
    r: f64,
    horizon: f64,
) -> Option<(f64, usize, bool)> {
    let (lo, hi) = (r, 1.0 - r);
    let mut best: Option<(f64, usize, bool)> = None;
    for k in 0..3 {
        if let Some((s, upper)) = axis_impact(p[k], u[k], a[k], lo, hi, horizon)
            && best.is_none_or(|b| s < b.0)
        {
            best = Some((s, k, upper));
        }
    }
    best
}

/// When two spheres (states at the same instant, effective accelerations
/// `ai`, `aj`) first touch within `horizon`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn pair_impact(
    pi: Vec3,
    ui: Vec3,
    ai: Vec3,
    pj: Vec3,
    uj: Vec3,
    aj: Vec3,
    reach: f64,
    horizon: f64,
) -> Option<f64> {
    let (d, w, b) = (pj - pi, uj - ui, 0.5 * (aj - ai));
    // They can meet only if |d| <= reach + |w| h + |b| h^2, whose square is
    // at most 3 (reach^2 + |w|^2 h^2 + |b|^2 h^4): a test with no square root.
    let h2 = horizon * horizon;
    let bound = 3.0 * (reach * reach + w.length_squared() * h2 + b.length_squared() * h2 * h2);
    if d.length_squared() > bound {
        return None;
    }
    // The same with the square roots, with room for rounding: most pairs
    // that pass the test above (neighbours) stop here.
    let closest = d.length() - w.length() * horizon - b.length() * h2;
    if closest > reach * (1.0 + 1e-9) {
        return None;
    }
    let c0 = d.length_squared() - reach * reach;
    if b == Vec3::ZERO {
        first_entry(c0, 2.0 * d.dot(w), w.length_squared(), horizon)
    } else {
        let c = [
            c0,
            2.0 * d.dot(w),
            w.length_squared() + 2.0 * d.dot(b),
            2.0 * w.dot(b),
            b.length_squared(),
        ];
        first_entry_poly(&c, horizon)
    }
}

/// Resolve a wall impact of one body at the instant of contact: the normal
/// speed takes `-c u` (0 below the rest threshold) and the centre sits
/// exactly on the wall. `remaining` is what is left of the step: when
/// gravity pushes into this wall and all further bounces fit in it, the body
/// rests. Returns the impulse along the axis, per unit mass.
fn resolve_wall(
    p: &mut Vec3,
    u: &mut Vec3,
    r: f64,
    (axis, upper): (usize, bool),
    config: &WorldConfig,
    remaining: f64,
    resting: Vec3,
) -> f64 {
    let (lo, hi) = (r, 1.0 - r);
    let before = u[axis];
    p[axis] = if upper { hi } else { lo };
    let approach = if upper { before } else { -before };
    if approach <= 0.0 {
        return 0.0;
    }
    let c = config
        .wall_rule()
        .with_resting(resting)
        .at_wall(approach, axis, upper);
    let mut out = -c * before;
    let g = config.gravity[axis];
    if (if upper { g > 0.0 } else { g < 0.0 }) && c < 1.0 {
        // All further bounces last 2 speed / (g (1 - c)) and rise
        // speed^2 / (2 g): rest when they fit in the step and under the
        // opposite wall.
        let (speed, g) = (out.abs(), g.abs());
        if 2.0 * speed <= remaining * g * (1.0 - c) && speed * speed < 2.0 * g * (hi - lo) {
            out = 0.0;
        }
    }
    u[axis] = out;
    out - before
}

/// The wall stage of a capped step, after the contact stage's projection
/// (`World::step` runs it in place of the discrete wall stage). A centre
/// that the projection pushed past a wall goes back onto it, and its speed
/// pays for the height this gains along gravity (or receives the height it
/// loses), its direction kept, so that its energy is what it was; moving
/// into the wall, it then meets it like any impact ([`resolve_wall`]).
/// The discrete wall stage mirrors such a centre back instead: a sphere
/// pushed into the floor rises for nothing, and under strong gravity every
/// capped step adds energy. (The projection itself keeps each pair's centre
/// of mass, and so the potential energy.) Only a sphere too slow to pay for
/// the climb, left at rest on the wall, keeps more energy than it had.
pub fn return_to_walls(bodies: &mut Bodies, config: &WorldConfig, stats: &mut StepStats) {
    return_to_walls_with(bodies, config, Vec3::ZERO, stats);
}

/// [`return_to_walls`] with resting contact over `resting` (see
/// `Restitution::at_wall`).
fn return_to_walls_with(
    bodies: &mut Bodies,
    config: &WorldConfig,
    resting: Vec3,
    stats: &mut StepStats,
) {
    let g = config.gravity;
    for i in 0..bodies.len() {
        let (r, m) = (bodies.radius[i], bodies.mass[i]);
        let (lo, hi) = (r, 1.0 - r);
        let (mut p, mut u) = (bodies.position[i], bodies.velocity[i]);
        for k in 0..3 {
            let upper = p[k] > hi;
            if !upper && p[k] >= lo {
                continue;
            }
            let (wall, inward) = if upper { (hi, -1.0) } else { (lo, 1.0) };
            // |u|^2 / 2 - g . x kept: the climb costs -g[k] (wall - p[k]).
            let speed2 = u.length_squared();
            let after2 = (speed2 + 2.0 * g[k] * (wall - p[k])).max(0.0);
            if speed2 > 0.0 {
                u *= (after2 / speed2).sqrt();
            } else {
                u[k] = inward * after2.sqrt();
            }
            let into_wall = u[k] * inward < 0.0;
            resolve_wall(&mut p, &mut u, r, (k, upper), config, 0.0, resting);
            stats.wall_impacts += usize::from(into_wall);
        }
        stats.wall_impulse += m * (u - bodies.velocity[i]);
        bodies.position[i] = p;
        bodies.velocity[i] = u;
    }
}

/// Resolve a pair impact at the instant of contact with the lesson's V1/V2.
/// Returns false when the pair was not approaching (nothing to do).
fn resolve_pair(bodies: &mut Bodies, i: usize, j: usize, config: &WorldConfig) -> bool {
    let n = (bodies.position[j] - bodies.position[i]).normalize_or(Vec3::Y);
    let (m1, m2) = (bodies.mass[i], bodies.mass[j]);
    let (mut vi, mut vj) = (bodies.velocity[i], bodies.velocity[j]);
    let moved = apply_pair_impulse(&mut vi, &mut vj, m1, m2, n, config.pair_rule());
    (bodies.velocity[i], bodies.velocity[j]) = (vi, vj);
    moved
}

/// What an impact is with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum With {
    Wall { axis: u8, upper: bool },
    Body(u32),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Event {
    /// Time from the start of the step, s.
    time: f64,
    i: u32,
    with: With,
    /// Versions of the bodies when the impact was predicted.
    version_i: u32,
    version_j: u32,
}

impl Event {
    /// Earliest first; simultaneous impacts in a fixed order, so a step is
    /// deterministic.
    fn key(&self) -> (f64, u32, u32) {
        let code = match self.with {
            With::Wall { axis, upper } => 2 * u32::from(axis) + u32::from(upper),
            With::Body(j) => 6 + j,
        };
        (self.time, self.i, code)
    }
}

impl Eq for Event {}

impl Ord for Event {
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (self.key(), other.key());
        // BinaryHeap pops the greatest: reverse for earliest first.
        b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)).then(b.2.cmp(&a.2))
    }
}

impl PartialOrd for Event {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The pending impacts and each body's clock (buffers reused between steps).
#[derive(Clone, Debug, Default)]
pub(crate) struct EventQueue {
    heap: BinaryHeap<Event>,
    /// Time (from the start of the step) each body's stored state is at.
    clock: Vec<f64>,
    version: Vec<u32>,
    /// Coordinates `(body, axis)` whose free flight meets a wall this step
    /// (walls only).
    meets_wall: Vec<(u32, u8)>,
    /// The pairs that can meet (kept over several steps).
    near: Neighbours,
    /// Pairs `(i < j)` found resting this step by escaped bodies (may
    /// repeat); the others are marked in the lists.
    resting: Vec<(u32, u32)>,
    /// Every resting pair of the step, once.
    pairs: Vec<(u32, u32)>,
    /// The resting pairs that overlap at the end of the step.
    contacts: Vec<Contact>,
    /// Which spheres stand on something, as the resting pairs are settled.
    supported: Vec<bool>,
    /// The pair impacts of the step that took an impulse, in the order
    /// they happened: the pair, its normal at the impact, no penetration.
    pub(crate) impacts: Vec<Contact>,
}

/// Advance every body by `h` with the continuous method, adding what
/// happened to `stats`. Returns true when the step reached its cap of
/// impacts: the bodies have then finished the step against the walls alone
/// (see the module notes), and the caller resolves the overlaps with the
/// contact stage (collide, solve contacts), then [`return_to_walls`].
pub(crate) fn advance(
    bodies: &mut Bodies,
    config: &WorldConfig,
    h: f64,
    queue: &mut EventQueue,
    (stats, separate): (&mut StepStats, bool),
    interrupted: &dyn Fn() -> bool,
) -> Result<bool, Abandoned> {
    let cap = EVENT_ALLOWANCE + EVENTS_PER_BODY * bodies.len();
    queue.impacts.clear();
    let capped = if config.pair_collisions {
        advance_pairs(
            bodies,
            config,
            h,
            queue,
            cap,
            (stats, separate),
            interrupted,
        )?
    } else {
        free_flights(bodies, config.gravity, h, &mut queue.meets_wall);
        let mut capped = false;
        for &(i, k) in &queue.meets_wall {
            capped |= !advance_axis(bodies, i as usize, k as usize, config, 0.0, h, cap, stats);
        }
        capped
    };
    stats.event_cap_reached |= capped;
    Ok(capped)
}

/// A step given up part-way because the caller asked (see
/// `World::try_step`): the bodies are left mid-step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Abandoned;

/// The caller is asked whether to give up once per this many impacts (and
/// bodies scheduled): often enough to answer within milliseconds, rarely
/// enough to cost nothing.
const ASK_EVERY: usize = 256;

/// Most steps of most bodies meet no wall. With walls only, the three
/// coordinates of a body move independently (a wall changes only its own
/// coordinate), so each is checked on its own: a coordinate whose free flight
/// over `h` stays inside the box is moved; the others are listed in
/// `meets_wall`, untouched.
fn free_flights(bodies: &mut Bodies, g: Vec3, h: f64, meets_wall: &mut Vec<(u32, u8)>) {
    meets_wall.clear();
    let half_h2 = 0.5 * h * h;
    let Bodies {
        position,
        velocity,
        radius,
        ..
    } = bodies;
    for (i, ((p, u), &r)) in position
        .iter_mut()
        .zip(velocity.iter_mut())
        .zip(radius.iter())
        .enumerate()
    {
        let a = effective_acceleration(*p, *u, g, r);
        let end = *p + *u * h + a * half_h2;
        let end_u = *u + a * h;
        for k in 0..3 {
            if stays_inside(p[k], u[k], a[k], end[k], r, h) {
                p[k] = end[k];
                u[k] = end_u[k];
            } else {
                meets_wall.push((i as u32, k as u8));
            }
        }
    }
}

/// Whether the free flight of one coordinate from `p` (velocity `u`,
/// acceleration `a`) to `end` over `h` stays in `[r, 1 - r]`: both ends
/// inside, and the turning point, where the velocity changes sign inside the
/// step, inside too. Touching a wall counts as inside (the impact, if any, is
/// found at the start of the next step).
#[inline]
fn stays_inside(p: f64, u: f64, a: f64, end: f64, r: f64, h: f64) -> bool {
    let inside = |x: f64| x >= r && x <= 1.0 - r;
    let turns = u * (u + a * h) < 0.0;
    inside(end) && (!turns || inside(p - u * u / (2.0 * a)))
}

/// Coordinate `k` of body `i`, which has only walls to meet, from time
/// `from` of the step to its end `h`: impact by impact, at most `budget` of
/// them; past that, the rest of the way in [`elastic_axis`]'s closed form.
/// Returns false when that closed form was not the exact motion (the walls
/// take energy at these speeds): the coordinate then kept the energy the
/// remaining impacts would have taken, never more than it had.
#[allow(clippy::too_many_arguments)]
fn advance_axis(
    bodies: &mut Bodies,
    i: usize,
    k: usize,
    config: &WorldConfig,
    from: f64,
    h: f64,
    budget: usize,
    stats: &mut StepStats,
) -> bool {
    let (g, r, m) = (config.gravity[k], bodies.radius[i], bodies.mass[i]);
    let (lo, hi) = (r, 1.0 - r);
    let (mut p, mut u) = (bodies.position[i], bodies.velocity[i]);
    let mut t = from;
    let mut impacts = 0;
    let exact = loop {
        let a = if supported(p[k], u[k], g, lo, hi) {
            0.0
        } else {
            g
        };
        match axis_impact(p[k], u[k], a, lo, hi, h - t) {
            Some((s, upper)) if impacts < budget => {
                p[k] += u[k] * s + a * (0.5 * s * s);
                u[k] += a * s;
                t += s;
                let dv = resolve_wall(&mut p, &mut u, r, (k, upper), config, h - t, Vec3::ZERO);
                stats.wall_impulse[k] += m * dv;
                stats.wall_impacts += 1;
                impacts += 1;
            }
            Some(_) => {
                let s = h - t;
                let e = elastic_axis(p[k], u[k], a, lo, hi, s);
                stats.wall_impulse[k] += m * (e.u - u[k] - a * s);
                stats.wall_impacts += e.impacts;
                (p[k], u[k]) = (e.p, e.u);
                break config.wall_rule().at(e.slowest_impact) == 1.0;
            }
            None => {
                let s = h - t;
                p[k] += u[k] * s + a * (0.5 * s * s);
                u[k] += a * s;
                break true;
            }
        }
    };
    bodies.position[i][k] = p[k];
    bodies.velocity[i][k] = u[k];
    exact
}

/// Where [`elastic_axis`] leaves a coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticFlight {
    /// Position, m, in `[lo, hi]`.
    pub p: f64,
    /// Velocity, m/s.
    pub u: f64,
    /// Wall impacts on the way.
    pub impacts: usize,
    /// The slowest approach speed of any impact of this motion, m/s
    /// (infinite when it meets no wall).
    pub slowest_impact: f64,
}

/// One coordinate (`p` in `[lo, hi]`, velocity `u`, constant acceleration
/// `a`) between walls that return every impact at full speed, `s` seconds
/// on, in closed form: the motion is periodic, so the cost does not grow
/// with the number of impacts.
///
/// Mirrored so that `a` pulls towards `lo` (`G = |a|`), the axis energy
/// gives the speed at the floor, `w^2 = u^2 + 2 G (p - lo)`. A coordinate
/// that cannot reach the ceiling (`w^2 <= 2 G L`, `L = hi - lo`) bounces on
/// the floor with period `2 w / G`; one that can reaches it at
/// `w_h = sqrt(w^2 - 2 G L)` after `2 L / (w + w_h)` and comes back in as
/// long (with `G = 0`: the triangle wave of period `2 L / |u|`). The phase
/// since the last floor impact, plus `s`, reduced modulo the period, gives
/// the state, with the axis energy `w^2` kept to rounding however many
/// periods pass.
pub fn elastic_axis(p: f64, u: f64, a: f64, lo: f64, hi: f64, s: f64) -> ElasticFlight {
    let mirrored = a > 0.0;
    let (g, span) = (a.abs(), hi - lo);
    let (height, speed) = if mirrored { (hi - p, -u) } else { (p - lo, u) };
    let height = height.clamp(0.0, span);
    let (height, speed, impacts, slowest) = if span <= 0.0 {
        // A sphere as wide as the box: no room to move along this axis.
        (0.0, speed, 0.0, speed.abs())
    } else if g == 0.0 {
        if speed == 0.0 {
            (height, speed, 0.0, f64::INFINITY)
        } else {
            // Unfold the walls, seen moving up: a straight line folded
            // every `span`.
            let down = speed < 0.0;
            let (q0, v) = if down {
                (span - height, -speed)
            } else {
                (height, speed)
            };
            let q = q0 + v * s;
            let folds = (q / span).floor() - (q0 / span).floor();
            let q = q.rem_euclid(2.0 * span);
            let (x, v) = if q <= span {
                (q, v)
            } else {
                (2.0 * span - q, -v)
            };
            let (x, v) = if down { (span - x, -v) } else { (x, v) };
            (x, v, folds, speed.abs())
        }
    } else {
        let w = (speed * speed + 2.0 * g * height).sqrt();
        if w == 0.0 {
            (0.0, 0.0, 0.0, f64::INFINITY)
        } else if w * w <= 2.0 * g * span {
            // Floor only: rising at w - G phi from phase 0.
            let period = 2.0 * w / g;
            let phase = if speed > 0.0 {
                2.0 * height / (w + speed)
            } else {
                (w - speed) / g
            };
            let end = phase + s;
            let floors = (end / period).floor() - (phase / period).floor();
            let phi = end.rem_euclid(period);
            (phi * (w - 0.5 * g * phi), w - g * phi, floors, w)
        } else {
            // Floor and ceiling: up in `rise`, down in `rise`.
            let w_top = (w * w - 2.0 * g * span).sqrt();
            let rise = 2.0 * span / (w + w_top);
            let period = 2.0 * rise;
            let phase = if speed >= 0.0 {
                2.0 * height / (w + speed)
            } else {
                rise + 2.0 * (span - height) / (w_top - speed)
            };
            let end = phase + s;
            let count = |from: f64| (end / period - from).floor() - (phase / period - from).floor();
            let walls = count(0.0) + count(0.5);
            let phi = end.rem_euclid(period);
            let (x, v) = if phi < rise {
                (phi * (w - 0.5 * g * phi), w - g * phi)
            } else {
                let psi = phi - rise;
                (span - psi * (w_top + 0.5 * g * psi), -(w_top + g * psi))
            };
            (x, v, walls, w_top)
        }
    };
    let height = height.clamp(0.0, span);
    let (p, u) = if mirrored {
        (hi - height, -speed)
    } else {
        (lo + height, speed)
    };
    ElasticFlight {
        p,
        u,
        impacts: impacts as usize,
        slowest_impact: slowest,
    }
}

/// Move body `i` to time `t` of the step.
fn catch_up(bodies: &mut Bodies, clock: &mut [f64], g: Vec3, i: usize, t: f64) {
    let s = t - clock[i];
    if s > 0.0 {
        let (p, u) = free_flight(
            bodies.position[i],
            bodies.velocity[i],
            g,
            bodies.radius[i],
            s,
        );
        bodies.position[i] = p;
        bodies.velocity[i] = u;
    }
    clock[i] = t;
}

/// Each body's list of the bodies it can meet, from a grid, kept over
/// several steps (see the module notes). A body keeps within `half` of
/// where it was when the lists were made, or it has escaped and is tested
/// against every body: two bodies that were not within
/// `r_i + r_j + 2 half` of each other then, and both keep within `half` of
/// where they were, never touch.
#[derive(Clone, Debug, Default)]
struct Neighbours {
    /// Where each body's list starts in `list` (`n + 1` offsets).
    start: Vec<u32>,
    list: Vec<u32>,
    /// Positions when the lists were made.
    origin: Vec<Vec3>,
    half: f64,
    escaped: Vec<bool>,
    escaped_list: Vec<u32>,
    /// Grid buffers: each body's cell, the bodies sorted by cell, and
    /// where each cell starts among them.
    cell: Vec<u32>,
    sorted: Vec<u32>,
    cell_start: Vec<u32>,
    fill: Vec<u32>,
    pairs: Vec<(u32, u32)>,
    /// For each entry of `list`, where the same pair sits in the other
    /// body's list.
    mirror: Vec<u32>,
    /// The entries of `list` found resting this step.
    held: Vec<bool>,
    /// Radii the lists were made for.
    radius: Vec<f64>,
    /// How far each body can go in this step as it flies at its start.
    travel: Vec<f64>,
}

/// The lists hold while every body keeps within this fraction of the
/// largest radius of where it was when they were made (more when the
/// fastest body flies farther in a step, at most the largest radius).
pub(crate) const SKIN: f64 = 0.2;

/// The most bodies of `n` that may escape their lists' bound and be
/// tested against every body; more, and the lists are made again.
fn most_escaped(n: usize) -> usize {
    2 + n / 64
}

impl Neighbours {
    /// Lists for the bodies at the start of a step of `h`: the last ones
    /// when every body can still keep within `half` of its origin through
    /// this step (the same number of bodies, the same radii), else new ones.
    fn prepare(&mut self, bodies: &Bodies, g: Vec3, h: f64) {
        let n = bodies.len();
        self.escaped.clear();
        self.escaped.resize(n, false);
        self.escaped_list.clear();
        self.travel.clear();
        self.travel.extend((0..n).map(|i| {
            let (p, u, r) = (bodies.position[i], bodies.velocity[i], bodies.radius[i]);
            let a = effective_acceleration(p, u, g, r);
            u.length() * h + 0.5 * a.length() * h * h
        }));
        let fits =
            |i: usize| bodies.position[i].distance(self.origin[i]) + self.travel[i] <= self.half;
        let mut kept = self.origin.len() == n && self.radius == bodies.radius;
        if kept {
            // A few bodies past their bound are tested against every body;
            // more, and the lists are made again.
            let most = most_escaped(n);
            for i in 0..n {
                if !fits(i) {
                    self.escaped[i] = true;
                    self.escaped_list.push(i as u32);
                    if self.escaped_list.len() > most {
                        kept = false;
                        break;
                    }
                }
            }
        }
        if !kept {
            self.escaped.fill(false);
            self.escaped_list.clear();
            self.build(bodies);
        }
        self.held.clear();
        self.held.resize(self.list.len(), false);
    }

    /// New lists around the bodies where they are.
    fn build(&mut self, bodies: &Bodies) {
        let n = bodies.len();
        let largest = bodies.radius.iter().copied().fold(0.0, f64::max);
        self.origin.clear();
        self.origin.extend_from_slice(&bodies.position);
        self.radius.clear();
        self.radius.extend_from_slice(&bodies.radius);
        let fastest = self.travel.iter().copied().fold(0.0, f64::max);
        let capped = (2.0 * fastest).max(SKIN * largest).min(largest);
        // Many bodies flying farther than that in a step would each be
        // tested against every body (n^2 tests at a million dilute fast
        // spheres); lists as wide as the farthest flight, made again each
        // step, cost a few tests a body instead.
        let escaping = self.travel.iter().filter(|&&t| t > capped).count();
        self.half = if escaping > most_escaped(n) {
            fastest
        } else {
            capped
        };
        for i in 0..n {
            let fits = self.travel[i] <= self.half;
            if !fits {
                self.escaped[i] = true;
                self.escaped_list.push(i as u32);
            }
        }
        self.cell.clear();
        // Cells at least one largest reach wide, at most about 8 n of them.
        let width = 2.0 * (largest + self.half);
        let most = ((2.0 * (n as f64).cbrt()).ceil() as usize).max(1);
        let m = ((1.0 / width).floor() as usize).clamp(1, most);
        let cell_of = |p: Vec3| {
            let c = |x: f64| ((x * m as f64).floor().max(0.0) as usize).min(m - 1);
            [c(p.x), c(p.y), c(p.z)]
        };
        let index = |c: [usize; 3]| (c[0] * m + c[1]) * m + c[2];
        self.cell_start.clear();
        self.cell_start.resize(m * m * m + 1, 0);
        for &p in &bodies.position {
            let k = index(cell_of(p));
            self.cell.push(k as u32);
            self.cell_start[k + 1] += 1;
        }
        for k in 0..m * m * m {
            self.cell_start[k + 1] += self.cell_start[k];
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.cell_start);
        for (i, &k) in self.cell.iter().enumerate() {
            self.sorted[self.fill[k as usize] as usize] = i as u32;
            self.fill[k as usize] += 1;
        }
        // Each pair once (i < j), then each body's list.
        self.pairs.clear();
        self.start.clear();
        self.start.resize(n + 1, 0);
        for i in 0..n {
            let (pi, ri) = (bodies.position[i], bodies.radius[i]);
            let c = cell_of(pi);
            let span = |k: usize| k.saturating_sub(1)..=(k + 1).min(m - 1);
            for x in span(c[0]) {
                for y in span(c[1]) {
                    for z in span(c[2]) {
                        let k = index([x, y, z]);
                        let cell = self.cell_start[k] as usize..self.cell_start[k + 1] as usize;
                        for &j in &self.sorted[cell] {
                            if (j as usize) <= i {
                                continue;
                            }
                            let pj = bodies.position[j as usize];
                            let reach = ri + bodies.radius[j as usize] + 2.0 * self.half;
                            if pi.distance_squared(pj) <= reach * reach {
                                self.pairs.push((i as u32, j));
                                self.start[i + 1] += 1;
                                self.start[j as usize + 1] += 1;
                            }
                        }
                    }
                }
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        self.list.clear();
        self.list.resize(self.start[n] as usize, 0);
        self.mirror.clear();
        self.mirror.resize(self.start[n] as usize, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.start[..n]);
        for &(i, j) in &self.pairs {
            let (i, j) = (i as usize, j as usize);
            let (ki, kj) = (self.fill[i], self.fill[j]);
            self.list[ki as usize] = j as u32;
            self.list[kj as usize] = i as u32;
            self.mirror[ki as usize] = kj;
            self.mirror[kj as usize] = ki;
            self.fill[i] += 1;
            self.fill[j] += 1;
        }
    }

    /// Every pair of `bodies` that overlaps now, each once, in `(i, j)`
    /// order, into `out`: from the lists, and an escaped body against
    /// every other. Needs [`Neighbours::prepare`] for these bodies first.
    fn overlapping(&self, bodies: &Bodies, out: &mut Vec<Contact>) -> u64 {
        out.clear();
        let mut tests = 0;
        for i in 0..self.start.len().saturating_sub(1) {
            for k in self.start[i] as usize..self.start[i + 1] as usize {
                let j = self.list[k] as usize;
                if j > i {
                    tests += 1;
                    out.extend(test_pair(bodies, i, j));
                }
            }
        }
        for &e in &self.escaped_list {
            let e = e as usize;
            for j in (0..bodies.len()).filter(|&j| j != e) {
                tests += 1;
                out.extend(test_pair(bodies, e.min(j), e.max(j)));
            }
        }
        // A body's list holds its neighbours in the order the lists were
        // made in: sorted, the pairs come in an order of their own.
        out.sort_unstable_by_key(|c| (c.i, c.j));
        out.dedup_by_key(|c| (c.i, c.j));
        tests
    }

    /// The pairs found resting this step, each once, in `(i, j)` order:
    /// those marked in the lists and `others` (found by escaped bodies,
    /// used up). The order depends only on the pairs, not on the lists.
    fn resting_pairs(&mut self, others: &mut Vec<(u32, u32)>, out: &mut Vec<(u32, u32)>) {
        others.sort_unstable();
        others.dedup();
        others.retain(|&(i, j)| {
            let list = self.start[i as usize] as usize..self.start[i as usize + 1] as usize;
            match list.clone().find(|&k| self.list[k] == j) {
                Some(k) => {
                    self.held[k] = true;
                    false
                }
                None => true,
            }
        });
        out.clear();
        for i in 0..self.start.len().saturating_sub(1) {
            for k in self.start[i] as usize..self.start[i + 1] as usize {
                let j = self.list[k];
                if j as usize > i && (self.held[k] || self.held[self.mirror[k] as usize]) {
                    out.push((i as u32, j));
                }
            }
        }
        out.append(others);
        out.sort_unstable();
    }

    /// Whether body `i` (at `p`, moving at `u` with acceleration `a`) may
    /// leave its bound in the `left` seconds of the step still to go; it
    /// then escapes for the rest of the step.
    fn escapes(&mut self, i: usize, p: Vec3, u: Vec3, a: Vec3, left: f64) -> bool {
        if self.escaped[i] {
            return true;
        }
        let reach = p.distance(self.origin[i]) + u.length() * left + 0.5 * a.length() * left * left;
        let fits = reach <= self.half;
        if !fits {
            self.escaped[i] = true;
            self.escaped_list.push(i as u32);
        }
        self.escaped[i]
    }
}

/// What a step of the continuous method holds as resting contact: a pair
/// that touches and moves along its normal slower than `speed`, m/s; with
/// perfectly elastic pairs, slower than its part along the normal,
/// `speed |g . n| / |g|`, as the discrete methods count gravity: side by
/// side, elastic spheres keep every impact, however slow.
#[derive(Clone, Copy, Debug)]
struct Hold {
    speed: f64,
    /// Gravity's direction, when only the part of `speed` along a pair's
    /// normal counts.
    along: Option<Vec3>,
}

impl Hold {
    fn of(config: &WorldConfig, h: f64) -> Self {
        let speed = if config.rest_steps > 0.0 {
            (config.rest_steps + 1.0) * config.gravity.length() * h
        } else {
            0.0
        };
        let along =
            (config.pair_rule().coefficient == 1.0).then(|| config.gravity.normalize_or_zero());
        Self { speed, along }
    }

    /// The speed below which a touching pair `d` apart (`dist = |d|`,
    /// clamped above 0) rests.
    #[inline]
    fn below(self, d: Vec3, dist: f64) -> f64 {
        match self.along {
            Some(g) => self.speed * (g.dot(d) / dist).abs(),
            None => self.speed,
        }
    }
}

/// Two spheres touch when `|d|^2 <= (r1 + r2)^2 TOUCH`: in contact to
/// rounding.
const TOUCH: f64 = 1.0 + 1e-9;

/// Passes over the velocities of the resting pairs at the end of a step,
/// after the first (a bounded budget: what they leave is met as impacts
/// in the next step).
pub(crate) const SETTLE_PASSES: usize = 2;

/// Predict body `i`'s next wall impact and its next pair impacts, from
/// time `t` (where `i` is) to the end `h`: against the bodies it can meet
/// numbered from `first` on, except `except`. A pair that touches and
/// moves along its normal slower than `hold` is resting contact: no impact
/// is predicted for it, and it is listed for the end of the step.
#[allow(clippy::too_many_arguments)]
fn schedule(
    bodies: &Bodies,
    queue: &mut EventQueue,
    g: Vec3,
    i: usize,
    first: usize,
    except: Option<usize>,
    t: f64,
    h: f64,
    hold: Hold,
) -> u64 {
    let (pi, ui, ri) = (bodies.position[i], bodies.velocity[i], bodies.radius[i]);
    let ai = effective_acceleration(pi, ui, g, ri);
    let version_i = queue.version[i];
    if let Some((s, axis, upper)) = wall_impact(pi, ui, ai, ri, h - t) {
        queue.heap.push(Event {
            time: t + s,
            i: i as u32,
            with: With::Wall {
                axis: axis as u8,
                upper,
            },
            version_i,
            version_j: 0,
        });
    }
    let mut tests = 0;
    let mut test = |queue: &mut EventQueue, j: usize, slot: Option<usize>| {
        if j < first || j == i || Some(j) == except {
            return;
        }
        tests += 1;
        let rj = bodies.radius[j];
        let (pj, uj) = free_flight(
            bodies.position[j],
            bodies.velocity[j],
            g,
            rj,
            t - queue.clock[j],
        );
        let reach = ri + rj;
        let d = pj - pi;
        let d2 = d.length_squared();
        let (a, b) = (i.min(j), i.max(j));
        if d2 <= reach * reach * TOUCH && hold.speed > 0.0 {
            let dist = d2.sqrt().max(f64::MIN_POSITIVE);
            let normal = (uj - ui).dot(d) / dist;
            if normal.abs() < hold.below(d, dist) {
                match slot {
                    Some(k) => queue.near.held[k] = true,
                    None => queue.resting.push((a as u32, b as u32)),
                }
                return;
            }
        }
        let aj = effective_acceleration(pj, uj, g, rj);
        if let Some(s) = pair_impact(pi, ui, ai, pj, uj, aj, reach, h - t) {
            queue.heap.push(Event {
                time: t + s,
                i: a as u32,
                with: With::Body(b as u32),
                version_i: queue.version[a],
                version_j: queue.version[b],
            });
        }
    };
    if queue.near.escapes(i, pi, ui, ai, h - t) {
        for j in 0..bodies.len() {
            test(queue, j, None);
        }
    } else {
        let list = queue.near.start[i] as usize..queue.near.start[i + 1] as usize;
        for k in list {
            let j = queue.near.list[k] as usize;
            if !queue.near.escaped[j] {
                test(queue, j, Some(k));
            }
        }
        for k in 0..queue.near.escaped_list.len() {
            test(queue, queue.near.escaped_list[k] as usize, None);
        }
    }
    tests
}

/// All bodies, walls and pairs, through the queue. Returns true if the cap
/// was reached.
fn advance_pairs(
    bodies: &mut Bodies,
    config: &WorldConfig,
    h: f64,
    queue: &mut EventQueue,
    cap: usize,
    (stats, separate): (&mut StepStats, bool),
    interrupted: &dyn Fn() -> bool,
) -> Result<bool, Abandoned> {
    let n = bodies.len();
    let g = config.gravity;
    let hold = Hold::of(config, h);
    queue.heap.clear();
    queue.resting.clear();
    queue.clock.clear();
    queue.clock.resize(n, 0.0);
    queue.version.clear();
    queue.version.resize(n, 0);
    queue.near.prepare(bodies, g, h);
    if separate {
        separate_overlaps(bodies, config, h, queue, stats, interrupted)?;
    }
    for i in 0..n {
        if i % ASK_EVERY == ASK_EVERY - 1 && interrupted() {
            return Err(Abandoned);
        }
        stats.pair_tests += schedule(bodies, queue, g, i, i + 1, None, 0.0, h, hold);
    }

    let mut impacts = 0;
    let mut capped = false;
    while let Some(event) = queue.heap.pop() {
        if impacts % ASK_EVERY == ASK_EVERY - 1 && interrupted() {
            return Err(Abandoned);
        }
        let i = event.i as usize;
        let fresh_i = queue.version[i] == event.version_i;
        let fresh = match event.with {
            With::Wall { .. } => fresh_i,
            With::Body(j) => fresh_i && queue.version[j as usize] == event.version_j,
        };
        if !fresh {
            continue;
        }
        if impacts >= cap {
            capped = true;
            break;
        }
        let t = event.time;
        catch_up(bodies, &mut queue.clock, g, i, t);
        match event.with {
            With::Wall { axis, upper } => {
                let axis = axis as usize;
                let (mut p, mut u) = (bodies.position[i], bodies.velocity[i]);
                let dv = resolve_wall(
                    &mut p,
                    &mut u,
                    bodies.radius[i],
                    (axis, upper),
                    config,
                    h - t,
                    Vec3::ZERO,
                );
                bodies.position[i] = p;
                bodies.velocity[i] = u;
                stats.wall_impulse[axis] += bodies.mass[i] * dv;
                stats.wall_impacts += 1;
                queue.version[i] += 1;
                stats.pair_tests += schedule(bodies, queue, g, i, 0, None, t, h, hold);
            }
            With::Body(j) => {
                let j = j as usize;
                catch_up(bodies, &mut queue.clock, g, j, t);
                if resolve_pair(bodies, i, j, config) {
                    stats.contacts += 1;
                    let (a, b) = (i.min(j), i.max(j));
                    queue.impacts.push(Contact {
                        i: a as u32,
                        j: b as u32,
                        contact_normal: (bodies.position[b] - bodies.position[a])
                            .normalize_or(Vec3::Y),
                        penetration: 0.0,
                    });
                }
                queue.version[i] += 1;
                queue.version[j] += 1;
                stats.pair_tests += schedule(bodies, queue, g, i, 0, None, t, h, hold);
                stats.pair_tests += schedule(bodies, queue, g, j, 0, Some(i), t, h, hold);
            }
        }
        impacts += 1;
    }
    if capped {
        // The rest of the step: every body meets the walls only, exactly,
        // from its own clock; the caller then resolves the overlaps the
        // pairs were left with. Elastic walls go straight to the closed
        // form; others walk a share of the cap first.
        let rule = config.wall_rule();
        let budget = if rule.coefficient == 1.0 && rule.rest_threshold == 0.0 {
            0
        } else {
            cap.div_ceil(n.max(1))
        };
        for i in 0..n {
            if i % ASK_EVERY == ASK_EVERY - 1 && interrupted() {
                return Err(Abandoned);
            }
            for k in 0..3 {
                advance_axis(bodies, i, k, config, queue.clock[i], h, budget, stats);
            }
            queue.clock[i] = h;
        }
    } else {
        for i in 0..n {
            catch_up(bodies, &mut queue.clock, g, i, h);
        }
        queue
            .near
            .resting_pairs(&mut queue.resting, &mut queue.pairs);
        let buffers = (&mut queue.contacts, &mut queue.supported);
        settle_resting(bodies, config, h, &queue.pairs, buffers, stats);
    }
    Ok(capped)
}

/// An overlap deeper than this fraction of the pair's reach is resolved
/// when a world enters the continuous method ([`separate_overlaps`]): far
/// above rounding, and below what a learner sees.
const FOREIGN_OVERLAP: f64 = 0.01;

/// Before the impacts of a world's first step with this method (its first
/// step, or the first after a discrete one): the pairs that overlap deeper
/// than [`FOREIGN_OVERLAP`] of their reach are resolved as the discrete
/// contact stage resolves them: pushed apart by the lesson's inverse-mass
/// split, with its V1/V2 if approaching, then a centre pushed past a wall
/// is put back at it. Such overlaps come from outside the method (a
/// scene's or a spawn's bodies, a discrete method's pile before the method
/// changed): no time of impact meets them, so without this their spheres
/// would stay inside each other, or pass through. Each pass pushes apart
/// the pairs it finds, and passes go on (at most [`SEPARATE_PASSES`])
/// while pushes leave or make such overlaps. Later steps leave the
/// overlaps of the method's own piles (up to a tenth of a reach in the
/// 200-sphere pile of the stability study) to its resting contact, as
/// before. Needs the lists prepared for these bodies; leaves them
/// prepared. `interrupted` is asked before each pass and before the last
/// look (in a pile of 100,000 spheres a pass takes a fifth of a second).
fn separate_overlaps(
    bodies: &mut Bodies,
    config: &WorldConfig,
    h: f64,
    queue: &mut EventQueue,
    stats: &mut StepStats,
    interrupted: &dyn Fn() -> bool,
) -> Result<(), Abandoned> {
    let rule = config.contact_rule(config.resting(h), false);
    for pass in 0..=SEPARATE_PASSES {
        if interrupted() {
            return Err(Abandoned);
        }
        let found = &mut queue.contacts;
        stats.pair_tests += queue.near.overlapping(bodies, found);
        found.retain(|c| {
            let reach = bodies.radius[c.i as usize] + bodies.radius[c.j as usize];
            c.penetration > FOREIGN_OVERLAP * reach
        });
        if found.is_empty() {
            return Ok(());
        }
        if pass == SEPARATE_PASSES {
            // Still some left after the last pass (a pile jammed into
            // itself): counted as a projection that did not converge.
            stats.projection_unconverged = true;
            return Ok(());
        }
        if pass == 0 {
            stats.contacts += found.len();
            stats.max_overlap = found
                .iter()
                .map(|c| c.penetration)
                .fold(stats.max_overlap, f64::max);
            queue.impacts.extend_from_slice(found);
        }
        solve_contacts(bodies, found, rule);
        clamp_to_box(bodies);
        // They moved: the lists may no longer hold them.
        queue.near.prepare(bodies, config.gravity, h);
    }
    Ok(())
}

/// Most passes [`separate_overlaps`] makes: as many as the projection
/// passes a step may take (`--projection-passes`).
const SEPARATE_PASSES: usize = 64;

/// The end of a step with resting contacts: from the lowest pair up, the
/// resting pairs that overlap are pushed apart and lose their normal
/// approach (the lesson's projection and V1/V2 with `e = 0`, or all of it
/// taken by the upper sphere where the lower holds it: [`pinned_shares`]);
/// the walls put back what this pushed past them, with resting contact;
/// further passes over those pairs and walls, velocities only, take out the
/// approach each pass gave back to the pairs before it.
fn settle_resting(
    bodies: &mut Bodies,
    config: &WorldConfig,
    h: f64,
    resting: &[(u32, u32)],
    (contacts, supported): (&mut Vec<Contact>, &mut Vec<bool>),
    stats: &mut StepStats,
) {
    // Every resting pair, touching or not by now: a pair below may push
    // one into overlap.
    contacts.clear();
    contacts.extend(
        resting
            .iter()
            .filter_map(|&(i, j)| test_pair_within(bodies, i as usize, j as usize, f64::INFINITY)),
    );
    let walls = config.resting(h);
    let stop = Restitution::new(0.0, 0.0);
    let down = config.gravity.normalize_or_zero();
    let g = (config.gravity, down);
    // From the lowest pair up, each taken as it is when its turn comes, so
    // that a column is set right in one pass: each pair moves only its
    // upper sphere, which no pair below it moves again.
    let up = -down;
    let height = |c: &Contact| {
        let (a, b) = (bodies.position[c.i as usize], bodies.position[c.j as usize]);
        a.dot(up).min(b.dot(up))
    };
    // Pairs are named once, so the order is whole without a stable sort.
    contacts.sort_unstable_by(|a, b| {
        height(a)
            .total_cmp(&height(b))
            .then((a.i, a.j).cmp(&(b.i, b.j)))
    });
    // Which spheres stand on something: gravity presses them into a wall,
    // or a sphere below that stands holds them (found from the lowest pair
    // up). A lower sphere in free fall holds nothing up: the pair shares
    // its correction by mass, and keeps its momentum.
    supported.clear();
    supported.extend((0..bodies.len()).map(|b| on_a_wall(bodies, b, config.gravity)));
    let mut overlapped = false;
    for c in contacts.iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        let Some(now) = test_pair(bodies, i, j) else {
            continue;
        };
        overlapped = true;
        let n = now.contact_normal;
        match pinned_shares(bodies, i, j, n, g, supported) {
            None => solve_contacts(bodies, std::slice::from_ref(&now), stop),
            Some([si, sj]) => {
                bodies.position[i] -= n * (si * now.penetration);
                bodies.position[j] += n * (sj * now.penetration);
                stop_pinned(bodies, i, j, n, [si, sj]);
                // The sphere held stands too.
                if si == 0.0 && sj > 0.0 {
                    supported[j] = true;
                } else if sj == 0.0 && si > 0.0 {
                    supported[i] = true;
                }
            }
        }
    }
    if !overlapped {
        return;
    }
    return_to_walls_with(bodies, config, walls, stats);
    for _ in 0..SETTLE_PASSES {
        let mut moved = false;
        for c in contacts.iter() {
            let (i, j) = (c.i as usize, c.j as usize);
            let d = bodies.position[j] - bodies.position[i];
            let reach = bodies.radius[i] + bodies.radius[j];
            if d.length_squared() > reach * reach * TOUCH {
                continue;
            }
            let n = d.normalize_or(Vec3::Y);
            if let Some(shares) = pinned_shares(bodies, i, j, n, g, supported) {
                moved |= stop_pinned(bodies, i, j, n, shares);
                continue;
            }
            let (mut vi, mut vj) = (bodies.velocity[i], bodies.velocity[j]);
            if apply_pair_impulse(&mut vi, &mut vj, bodies.mass[i], bodies.mass[j], n, stop) {
                moved = true;
                (bodies.velocity[i], bodies.velocity[j]) = (vi, vj);
                for b in [i, j] {
                    stop_at_walls(bodies, b, config, walls, stats);
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// Whether gravity `g` presses sphere `b` into a wall it is on.
fn on_a_wall(bodies: &Bodies, b: usize, g: Vec3) -> bool {
    let (p, r) = (bodies.position[b], bodies.radius[b]);
    (0..3).any(|k| (g[k] < 0.0 && p[k] <= r) || (g[k] > 0.0 && p[k] >= 1.0 - r))
}

/// For a resting pair `i`, `j` (`n` from `i` to `j`) under gravity `g`
/// (`down`: its direction):
/// each sphere's share of a correction along `n` when one holds the other
/// up, `None` for the lesson's split by inverse mass. The lower sphere of
/// a pair within 60 degrees of the vertical holds the upper one when it
/// stands on something itself (`supported`; shock propagation: its share
/// is 0), and so does a sphere that gravity presses into a wall, where the
/// correction would push it into that wall. Split by mass there, half of
/// each overlap would go down the column and into the floor, which gives
/// it back: a resting column would stay sunk into itself, by millimetres a
/// sphere. A lower sphere in free fall holds nothing: held, a 1 g sphere
/// stopped a 10 kg one in mid-air.
fn pinned_shares(
    bodies: &Bodies,
    i: usize,
    j: usize,
    n: Vec3,
    (g, down): (Vec3, Vec3),
    supported: &[bool],
) -> Option<[f64; 2]> {
    let pressed = |b: usize, along: Vec3| {
        let (p, r) = (bodies.position[b], bodies.radius[b]);
        (0..3).any(|k| {
            (g[k] < 0.0 && along[k] < 0.0 && p[k] <= r)
                || (g[k] > 0.0 && along[k] > 0.0 && p[k] >= 1.0 - r)
        })
    };
    // Along gravity: positive when `j` lies below `i`.
    let below = n.dot(down);
    let (hold_i, hold_j) = (
        (below < -HOLD_TILT && supported[i]) || pressed(i, -n),
        (below > HOLD_TILT && supported[j]) || pressed(j, n),
    );
    match (hold_i, hold_j) {
        (false, false) => None,
        (true, true) => Some([0.0, 0.0]),
        (true, false) => Some([0.0, 1.0]),
        (false, true) => Some([1.0, 0.0]),
    }
}

/// A resting pair whose normal is within 60 degrees of the vertical has
/// its lower sphere hold the upper one up (`pinned_shares`): `cos 60`.
const HOLD_TILT: f64 = 0.5;

/// The velocity half of [`pinned_shares`]'s correction: the pair's
/// approach along `n` is taken from its spheres by their `shares`. Returns
/// whether it approached.
fn stop_pinned(bodies: &mut Bodies, i: usize, j: usize, n: Vec3, [si, sj]: [f64; 2]) -> bool {
    let u = (bodies.velocity[i] - bodies.velocity[j]).dot(n);
    if u <= 0.0 || u.is_nan() {
        return false;
    }
    bodies.velocity[i] -= n * (si * u);
    bodies.velocity[j] += n * (sj * u);
    true
}

/// Body `b`, on a wall and moving into it, meets it (velocity only).
fn stop_at_walls(
    bodies: &mut Bodies,
    b: usize,
    config: &WorldConfig,
    resting: Vec3,
    stats: &mut StepStats,
) {
    let r = bodies.radius[b];
    let (mut p, mut u) = (bodies.position[b], bodies.velocity[b]);
    for k in 0..3 {
        let upper = if p[k] <= r && u[k] < 0.0 {
            false
        } else if p[k] >= 1.0 - r && u[k] > 0.0 {
            true
        } else {
            continue;
        };
        let dv = resolve_wall(&mut p, &mut u, r, (k, upper), config, 0.0, resting);
        stats.wall_impulse[k] += bodies.mass[b] * dv;
    }
    bodies.position[b] = p;
    bodies.velocity[b] = u;
}
