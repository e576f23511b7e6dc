//! The ping-pong reference: a centre moving at constant speed between two
//! walls that flip its velocity follows an exact triangle wave.
//!
//! Unfold the walls: the centre moves freely along a line, `q = p0 - lo +
//! u0 t`, and the box is that line folded every `L = hi - lo`. With `q`
//! reduced modulo `2L`, the centre is at `lo + q` going the way it started
//! for `q <= L`, and at `lo + 2L - q` going back for `q > L`.

/// Position and velocity at time `t` of a centre that starts at `p0` with
/// velocity `u0` between walls at `lo` and `hi` that flip it.
pub fn triangle_wave(p0: f64, u0: f64, lo: f64, hi: f64, t: f64) -> (f64, f64) {
    let span = hi - lo;
    if span <= 0.0 {
        return (lo, 0.0);
    }
    let q = (p0 - lo + u0 * t).rem_euclid(2.0 * span);
    if q <= span {
        (lo + q, u0)
    } else {
        (lo + 2.0 * span - q, -u0)
    }
}
