//! The gravity reference: one coordinate of one sphere between two walls,
//! in closed form.
//!
//! With walls only (no pair collisions) a sphere's three coordinates move
//! independently: each is a free flight `p + u s + a s^2 / 2` until it
//! reaches `lo = r` or `hi = 1 - r`, where `u <- -c u`. The motion is a
//! chain of parabolas (straight lines where `a = 0`), each wall-impact time
//! solved exactly from a quadratic.
//!
//! Finite-time rest. Once the coordinate leaves the wall that gravity pulls
//! it into with a speed `w` too small to reach the opposite wall, every
//! later flight stays on that wall's side: flight `n` lasts `2 w c^n / g`,
//! so with `c < 1` the infinitely many bounces end at
//! `t_rest = t_0 + 2 w / (g (1 - c))` (for a ball dropped from rest at
//! height `h`: `sqrt(2 h / g) (1 + c) / (1 - c)`). After `n` bounces the time
//! is `t_0 + 2 w (1 - c^n) / (g (1 - c))`, so the state at any time follows
//! from a logarithm, not from walking the bounces, and after `t_rest` the
//! coordinate rests on the wall.

use super::pingpong::triangle_wave;

/// One coordinate's motion: start `p0`, `u0`, constant acceleration `a`,
/// walls at `lo` and `hi` with restitution `c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisMotion {
    pub p0: f64,
    pub u0: f64,
    pub a: f64,
    pub lo: f64,
    pub hi: f64,
    pub c: f64,
}

/// A wall impact of the exact motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// s.
    pub time: f64,
    /// At `hi` (else at `lo`).
    pub upper: bool,
    /// Speed leaving the wall, m/s.
    pub speed_out: f64,
}

/// Impacts followed one by one before the motion is declared never to
/// settle into the closed form (only reached by scenes far outside the
/// lessons: a coordinate bouncing between walls for millions of impacts).
const MAX_WALK: usize = 1_000_000;

/// A free flight starting at time `t` from `(p, u)`, in coordinates where
/// the acceleration points to `lo` (or is zero).
#[derive(Clone, Copy, Debug)]
struct Flight {
    t: f64,
    p: f64,
    u: f64,
}

/// What comes after a flight.
enum Ahead {
    /// Flies on forever without a wall.
    Free,
    /// Bounces on `lo` only, forever (closed form from here).
    OnFloor,
    /// The next impact: after `s`, at `hi` if `upper`.
    Impact { s: f64, upper: bool },
}

impl AxisMotion {
    /// Mirror so that the acceleration points to `lo` (or is 0).
    fn mirrored(&self) -> bool {
        self.a > 0.0
    }

    fn start(&self) -> Flight {
        let m = self.mirrored();
        Flight {
            t: 0.0,
            p: if m {
                self.lo + self.hi - self.p0
            } else {
                self.p0
            },
            u: if m { -self.u0 } else { self.u0 },
        }
    }

    fn g(&self) -> f64 {
        self.a.abs()
    }

    fn unmirror(&self, (p, u): (f64, f64)) -> (f64, f64) {
        if self.mirrored() {
            (self.lo + self.hi - p, -u)
        } else {
            (p, u)
        }
    }

    /// Where `f` ends: `p + u s - g s^2 / 2` reaching `lo` (moving down) or
    /// `hi` (moving up) first.
    fn ahead(&self, f: Flight) -> Ahead {
        let (g, lo, hi) = (self.g(), self.lo, self.hi);
        if g > 0.0 && f.p <= lo && f.u >= 0.0 && f.u * f.u / (2.0 * g) < hi - lo {
            return Ahead::OnFloor;
        }
        // Earliest s > 0 (or s = 0 when on a wall moving into it) at a wall.
        let floor = time_to(f.p - lo, f.u, -0.5 * g);
        let ceiling = time_to(hi - f.p, -f.u, 0.5 * g);
        match (floor, ceiling) {
            (None, None) => Ahead::Free,
            (Some(s), None) => Ahead::Impact { s, upper: false },
            (None, Some(s)) => Ahead::Impact { s, upper: true },
            (Some(a), Some(b)) => {
                if a <= b {
                    Ahead::Impact { s: a, upper: false }
                } else {
                    Ahead::Impact { s: b, upper: true }
                }
            }
        }
    }

    fn fly(&self, f: Flight, s: f64) -> (f64, f64) {
        let g = self.g();
        (f.p + f.u * s - 0.5 * g * s * s, f.u - g * s)
    }

    fn bounce(&self, f: Flight, s: f64, upper: bool) -> (Flight, Impact) {
        let (_, u) = self.fly(f, s);
        let out = -self.c * u;
        let next = Flight {
            t: f.t + s,
            p: if upper { self.hi } else { self.lo },
            u: out,
        };
        let impact = Impact {
            time: next.t,
            upper: upper != self.mirrored(),
            speed_out: out.abs(),
        };
        (next, impact)
    }

    /// Time after `f.t` at which flight `n` of the on-floor series from `f`
    /// starts: `2 w (1 - c^n) / (g (1 - c))`.
    fn series_time(&self, w: f64, n: u64) -> f64 {
        let (g, c) = (self.g(), self.c);
        if c == 1.0 {
            2.0 * w * n as f64 / g
        } else {
            2.0 * w * (1.0 - c.powf(n as f64)) / (g * (1.0 - c))
        }
    }

    /// When the on-floor series from `f` ends (infinite for `c = 1`).
    fn series_end(&self, f: Flight) -> f64 {
        if f.u == 0.0 {
            return f.t;
        }
        if self.c >= 1.0 {
            return f64::INFINITY;
        }
        f.t + 2.0 * f.u / (self.g() * (1.0 - self.c))
    }

    /// Flights of the on-floor series from `f` completed by time `t`.
    fn series_count(&self, f: Flight, t: f64) -> u64 {
        let (w, g, c) = (f.u, self.g(), self.c);
        let tau = t - f.t;
        let guess = if c == 1.0 {
            (tau * g / (2.0 * w)).floor()
        } else if c == 0.0 {
            0.0
        } else {
            let x = 1.0 - tau * g * (1.0 - c) / (2.0 * w);
            (x.ln() / c.ln()).floor()
        };
        let mut n = if guess.is_finite() && guess > 0.0 {
            guess as u64
        } else {
            0
        };
        while self.series_time(w, n + 1) <= tau {
            n += 1;
        }
        while n > 0 && self.series_time(w, n) > tau {
            n -= 1;
        }
        n
    }

    fn on_floor_at(&self, f: Flight, t: f64) -> (f64, f64) {
        if t >= self.series_end(f) {
            return (self.lo, 0.0);
        }
        let n = self.series_count(f, t);
        let v = f.u * self.c.powf(n as f64);
        let s = t - f.t - self.series_time(f.u, n);
        let (p, u) = self.fly(
            Flight {
                t: 0.0,
                p: self.lo,
                u: v,
            },
            s,
        );
        (p.max(self.lo), u)
    }

    /// Position and velocity at time `t >= 0`.
    pub fn at(&self, t: f64) -> (f64, f64) {
        if self.a == 0.0 && self.c == 1.0 {
            return triangle_wave(self.p0, self.u0, self.lo, self.hi, t);
        }
        let mut f = self.start();
        for _ in 0..MAX_WALK {
            match self.ahead(f) {
                Ahead::Free => return self.unmirror(self.fly(f, t - f.t)),
                Ahead::OnFloor => return self.unmirror(self.on_floor_at(f, t)),
                Ahead::Impact { s, upper } => {
                    if f.t + s > t {
                        return self.unmirror(self.fly(f, t - f.t));
                    }
                    f = self.bounce(f, s, upper).0;
                }
            }
        }
        self.unmirror(self.fly(f, t - f.t))
    }

    /// The wall impacts up to `horizon`, at most `max` of them, in order.
    pub fn impacts(&self, horizon: f64, max: usize) -> Vec<Impact> {
        let mut out = Vec::new();
        let mut f = self.start();
        while out.len() < max {
            match self.ahead(f) {
                Ahead::Free => break,
                Ahead::OnFloor => {
                    let end = self.series_end(f);
                    let mut n = 1;
                    while out.len() < max {
                        let time = f.t + self.series_time(f.u, n);
                        if time > horizon || time >= end {
                            break;
                        }
                        out.push(Impact {
                            time,
                            upper: self.mirrored(),
                            speed_out: f.u * self.c.powf(n as f64),
                        });
                        n += 1;
                    }
                    break;
                }
                Ahead::Impact { s, upper } => {
                    if f.t + s > horizon {
                        break;
                    }
                    let (next, impact) = self.bounce(f, s, upper);
                    out.push(impact);
                    f = next;
                }
            }
        }
        out
    }

    /// When the coordinate comes to rest for good, if it does.
    pub fn rest_time(&self) -> Option<f64> {
        let mut f = self.start();
        for _ in 0..MAX_WALK {
            match self.ahead(f) {
                Ahead::Free => return None,
                Ahead::OnFloor => {
                    let end = self.series_end(f);
                    return end.is_finite().then_some(end);
                }
                Ahead::Impact { s, upper } => f = self.bounce(f, s, upper).0,
            }
        }
        None
    }
}

/// Earliest `s >= 0` at which the gap `c0 + c1 s + c2 s^2` (`c0 >= 0`)
/// closes while closing; `s = 0` when it is already closed and closing.
fn time_to(c0: f64, c1: f64, c2: f64) -> Option<f64> {
    if c0 <= 0.0 && c1 < 0.0 {
        return Some(0.0);
    }
    let mut best: Option<f64> = None;
    let mut consider = |s: f64| {
        if s > 0.0 && c1 + 2.0 * c2 * s < 0.0 && best.is_none_or(|b| s < b) {
            best = Some(s);
        }
    };
    if c2 == 0.0 {
        if c1 != 0.0 {
            consider(-c0 / c1);
        }
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc >= 0.0 {
            let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
            if q != 0.0 {
                consider(q / c2);
                consider(c0 / q);
            } else {
                consider(-c1 / (2.0 * c2));
            }
        }
    }
    best
}
