//! What a valid value is. Scene files and command-line flags share these
//! checks, so a value is accepted or refused the same way everywhere. Each
//! returns the reason a value is refused, phrased to follow the field name.

/// Largest time step accepted, s: a step longer than a second is no
/// simulation of a 1 m box.
pub(crate) const MAX_DT: f64 = 1.0;
/// Largest number of spheres a scene may hold.
pub(crate) const MAX_BODIES: usize = 10_000_000;
/// Most sub-steps per step.
pub(crate) const MAX_SUBSTEPS: u32 = 10_000;
/// Largest radius: a sphere must fit in the unit box.
pub(crate) const MAX_RADIUS: f64 = 0.5;
/// Masses, kg: wide enough for any scene, narrow enough that inverse
/// masses, momenta and energies stay finite.
pub(crate) const MIN_MASS: f64 = 1e-9;
pub(crate) const MAX_MASS: f64 = 1e9;
/// Largest speed, m/s, and largest gravity, m/s^2: beyond these a step's
/// energies and positions would leave the range of finite numbers.
pub const MAX_SPEED: f64 = 1e6;
pub const MAX_GRAVITY: f64 = 1e6;
/// Most steps one run may take (`--steps`, or `--time` over `dt`): a
/// trillion steps of even one sphere is days of computing.
pub(crate) const MAX_STEPS: u64 = 1_000_000_000_000;

/// `v` as a person writes it: plain for everyday magnitudes, in
/// exponent form for the very large and very small (`1e300`, not three
/// hundred digits).
pub(crate) fn show(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `text` without its minus sign when its number reads as zero: `-0.000`
/// (from -0, or a tiny negative rounded) is shown as `0.000`.
pub(crate) fn unsigned_zero(text: String) -> String {
    let Some(rest) = text.strip_prefix('-') else {
        return text;
    };
    let number: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    if number.contains('0') && number.chars().all(|c| c == '0' || c == '.') {
        rest.to_string()
    } else {
        text
    }
}

/// Whether the digits of `text` before any exponent are all zeros: a
/// number typed as 0, whatever 64-bit floating point makes of it.
pub(crate) fn typed_as_zero(text: &str) -> bool {
    let mantissa = text.split(['e', 'E']).next().unwrap_or("");
    !mantissa.bytes().any(|b| (b'1'..=b'9').contains(&b))
}

/// Why `text`, typed as other than 0, reads as 0: nothing nearer 0 than
/// about 5e-324 fits in a 64-bit number.
pub(crate) fn read_as_zero(text: &str) -> String {
    format!("{text} is closer to 0 than a 64-bit number can hold, so it reads as 0")
}

pub(crate) fn finite(v: f64) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("must be a finite number, got {}", show(v)))
    }
}

pub(crate) fn positive(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("must be greater than 0, got {}", show(v)))
    }
}

pub(crate) fn non_negative(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("must be 0 or more, got {}", show(v)))
    }
}

pub(crate) fn dt(v: f64) -> Result<f64, String> {
    positive(v)?;
    if v <= MAX_DT {
        Ok(v)
    } else {
        Err(format!("must be at most {MAX_DT} s, got {}", show(v)))
    }
}

pub(crate) fn restitution(v: f64) -> Result<f64, String> {
    finite(v)?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be between 0 and 1, got {}", show(v)))
    }
}

pub(crate) fn radius(v: f64) -> Result<f64, String> {
    positive(v)?;
    if v <= MAX_RADIUS {
        Ok(v)
    } else {
        Err(format!(
            "must be at most {MAX_RADIUS} m to fit in the 1 m box, got {}",
            show(v)
        ))
    }
}

pub(crate) fn vector(v: [f64; 3]) -> Result<[f64; 3], String> {
    for c in v {
        if !c.is_finite() {
            return Err(format!(
                "must hold finite numbers, got [{}, {}, {}]",
                v[0], v[1], v[2]
            ));
        }
    }
    Ok(v)
}

/// The length of `v`, scaled so that squaring cannot overflow: the length
/// of `[0, 1e308, 0]` is 1e308, not infinity.
fn magnitude(v: [f64; 3]) -> f64 {
    let scale = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if scale == 0.0 {
        return 0.0;
    }
    scale * v.iter().map(|c| (c / scale).powi(2)).sum::<f64>().sqrt()
}

fn magnitude_at_most(v: [f64; 3], limit: f64, unit: &str) -> Result<[f64; 3], String> {
    vector(v)?;
    let m = magnitude(v);
    if m <= limit {
        Ok(v)
    } else {
        Err(format!(
            "must be at most {limit:e} {unit} in magnitude, got {m:e}"
        ))
    }
}

/// A velocity, m/s.
pub(crate) fn velocity(v: [f64; 3]) -> Result<[f64; 3], String> {
    magnitude_at_most(v, MAX_SPEED, "m/s")
}

/// A gravity vector, m/s^2.
pub(crate) fn gravity(v: [f64; 3]) -> Result<[f64; 3], String> {
    magnitude_at_most(v, MAX_GRAVITY, "m/s^2")
}

/// A gravity magnitude, m/s^2.
pub(crate) fn gravity_magnitude(g: f64) -> Result<f64, String> {
    non_negative(g)?;
    gravity([0.0, g, 0.0]).map(|_| g)
}

/// A speed, m/s.
pub(crate) fn speed(v: f64) -> Result<f64, String> {
    non_negative(v)?;
    if v <= MAX_SPEED {
        Ok(v)
    } else {
        Err(format!("must be at most {MAX_SPEED:e} m/s, got {v:e}"))
    }
}

/// A mass, kg.
pub(crate) fn mass(m: f64) -> Result<f64, String> {
    finite(m)?;
    if (MIN_MASS..=MAX_MASS).contains(&m) {
        Ok(m)
    } else {
        Err(format!(
            "must be between {MIN_MASS:e} and {MAX_MASS:e} kg, got {}",
            show(m)
        ))
    }
}

/// `[min, max]` with `min <= max`, each passing `each`.
pub(crate) fn range(v: [f64; 2], each: fn(f64) -> Result<f64, String>) -> Result<[f64; 2], String> {
    for c in v {
        each(c).map_err(|e| format!("[{}, {}]: each end {e}", show(v[0]), show(v[1])))?;
    }
    if v[0] <= v[1] {
        Ok(v)
    } else {
        Err(format!(
            "[{}, {}]: min must not exceed max",
            show(v[0]),
            show(v[1])
        ))
    }
}

/// A centre inside `[r, 1 - r]` on every axis: `c >= r` and `c + r <= 1`
/// as the numbers add, so that a sphere written touching the far wall
/// (0.93 with radius 0.07, where `1 - 0.07` is 0.9299999999999999) is
/// taken, as one touching the near wall is.
pub(crate) fn inside_box(position: [f64; 3], r: f64) -> Result<[f64; 3], String> {
    vector(position)?;
    if position.iter().all(|&c| c >= r && c + r <= 1.0) {
        Ok(position)
    } else {
        Err(format!(
            "[{}, {}, {}] puts the sphere (radius {r}) outside the box: \
             each coordinate must be in [{r}, 1 - {r}]",
            show(position[0]),
            show(position[1]),
            show(position[2]),
        ))
    }
}

/// Characters a scene's `[lesson] title` may have: the header and the
/// side panel show one line of it.
pub(crate) const MAX_TITLE_CHARS: usize = 1_000;
/// Characters a scene's `[lesson] idea` or `equation` may have: the side
/// panel wraps them every frame and shows what fits (a screenful is a few
/// thousand).
pub(crate) const MAX_LESSON_TEXT_CHARS: usize = 10_000;
/// Resting contact's window, in sub-steps of gravity (0 = off).
pub(crate) const MAX_REST_STEPS: f64 = 10.0;
/// Projection passes over a step's contacts.
pub(crate) const MAX_PROJECTION_PASSES: u32 = 64;

pub(crate) fn rest_steps(v: f64) -> Result<f64, String> {
    finite(v)?;
    if (0.0..=MAX_REST_STEPS).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "must be from 0 (off) to {MAX_REST_STEPS}, got {}",
            show(v)
        ))
    }
}

/// Steps of `dt` that cover `time`: the smallest `n` with `n dt >= time`,
/// forgiving rounding in the division, a few units in the last place of
/// the quotient (0.5 s at 0.01 s is 50 steps, not 51). Refused beyond [`MAX_STEPS`]; the reason is phrased to follow a
/// description of the two values.
pub(crate) fn steps_for(time: f64, dt: f64) -> Result<u64, String> {
    non_negative(time)?;
    positive(dt)?;
    let steps = ((time / dt) * (1.0 - 8.0 * f64::EPSILON)).ceil().max(0.0);
    if steps <= MAX_STEPS as f64 {
        return Ok(steps as u64);
    }
    // Whole digits while they are exact, so a count just past the limit
    // does not read as equal to it.
    let count = if steps < 1e15 {
        format!("{steps:.0}")
    } else if steps.is_finite() {
        format!("{steps:.3e}")
    } else {
        format!("more than {:.1e}", f64::MAX)
    };
    Err(format!(
        "make {count} steps; at most {MAX_STEPS:.0e} are allowed"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sphere_written_touching_either_wall_is_inside_the_box() {
        // 1 - r rounds below the far wall's touching centre for these
        // radii; c + r reaches 1 exactly.
        for (c, r) in [(0.93, 0.07), (0.68, 0.32), (0.67, 0.33), (0.66, 0.34)] {
            assert!(1.0 - r < c, "{c}, {r}");
            assert_eq!(inside_box([r, 0.5, c], r), Ok([r, 0.5, c]));
        }
        let err = inside_box([0.5, 0.9300001, 0.5], 0.07).unwrap_err();
        assert_eq!(
            err,
            "[0.5, 0.9300001, 0.5] puts the sphere (radius 0.07) outside the box: \
             each coordinate must be in [0.07, 1 - 0.07]"
        );
        assert!(inside_box([0.0699, 0.5, 0.5], 0.07).is_err());
    }

    #[test]
    fn steps_for_rounds_up_forgiving_the_division_and_stops_at_the_maximum() {
        assert_eq!(steps_for(0.5, 0.01), Ok(50));
        assert_eq!(steps_for(0.505, 0.01), Ok(51));
        assert_eq!(steps_for(1.0, 1.0 / 3.0), Ok(3));
        assert_eq!(steps_for(0.0, 0.01), Ok(0));
        assert_eq!(steps_for(0.1, 1.0 / 240.0), Ok(24));
        assert_eq!(steps_for(1e12, 1.0), Ok(MAX_STEPS));
        assert_eq!(steps_for(1e12 - 1.0, 1.0), Ok(MAX_STEPS - 1));
        for (time, dt) in [(1e30, 1.0), (1e308, 1.0), (1e300, 1e-300), (1.0, 1e-300)] {
            let e = steps_for(time, dt).unwrap_err();
            assert!(e.contains("at most 1e12"), "{time} / {dt}: {e}");
        }
        // Just past the limit, the count says by how much.
        assert_eq!(
            steps_for(1e12 + 2.0, 1.0).unwrap_err(),
            "make 1000000000002 steps; at most 1e12 are allowed"
        );
    }

    #[test]
    fn magnitudes_near_the_largest_float_do_not_overflow() {
        let e = gravity_magnitude(1e308).unwrap_err();
        assert!(e.contains("got 1e308"), "{e}");
        assert_eq!(magnitude([3.0, 4.0, 0.0]), 5.0);
        assert_eq!(magnitude([0.0; 3]), 0.0);
    }
}
