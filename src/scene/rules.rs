//! What a valid value is. Scene files and command-line flags share these
//! checks, so a value is accepted or refused the same way everywhere. Each
//! returns the reason a value is refused, phrased to follow the field name.

/// Largest time step accepted, s: a step longer than a second is no
/// simulation of a 1 m box.
pub const MAX_DT: f64 = 1.0;
/// Largest number of spheres a scene may hold.
pub const MAX_BODIES: usize = 10_000_000;
/// Most sub-steps per step.
pub const MAX_SUBSTEPS: u32 = 10_000;
/// Largest radius: a sphere must fit in the unit box.
pub const MAX_RADIUS: f64 = 0.5;
/// Masses, kg: wide enough for any scene, narrow enough that inverse
/// masses, momenta and energies stay finite.
pub const MIN_MASS: f64 = 1e-9;
pub const MAX_MASS: f64 = 1e9;
/// Largest speed, m/s, and largest gravity, m/s^2: beyond these a step's
/// energies and positions would leave the range of finite numbers.
pub const MAX_SPEED: f64 = 1e6;
pub const MAX_GRAVITY: f64 = 1e6;

pub fn finite(v: f64) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("must be a finite number, got {v}"))
    }
}

pub fn positive(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("must be greater than 0, got {v}"))
    }
}

pub fn non_negative(v: f64) -> Result<f64, String> {
    finite(v)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("must be 0 or more, got {v}"))
    }
}

pub fn dt(v: f64) -> Result<f64, String> {
    positive(v)?;
    if v <= MAX_DT {
        Ok(v)
    } else {
        Err(format!("must be at most {MAX_DT} s, got {v}"))
    }
}

pub fn restitution(v: f64) -> Result<f64, String> {
    finite(v)?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be between 0 and 1, got {v}"))
    }
}

pub fn radius(v: f64) -> Result<f64, String> {
    positive(v)?;
    if v <= MAX_RADIUS {
        Ok(v)
    } else {
        Err(format!(
            "must be at most {MAX_RADIUS} m to fit in the 1 m box, got {v}"
        ))
    }
}

pub fn vector(v: [f64; 3]) -> Result<[f64; 3], String> {
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

fn magnitude_at_most(v: [f64; 3], limit: f64, unit: &str) -> Result<[f64; 3], String> {
    vector(v)?;
    let m = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if m <= limit {
        Ok(v)
    } else {
        Err(format!(
            "must be at most {limit:e} {unit} in magnitude, got {m:e}"
        ))
    }
}

/// A velocity, m/s.
pub fn velocity(v: [f64; 3]) -> Result<[f64; 3], String> {
    magnitude_at_most(v, MAX_SPEED, "m/s")
}

/// A gravity vector, m/s^2.
pub fn gravity(v: [f64; 3]) -> Result<[f64; 3], String> {
    magnitude_at_most(v, MAX_GRAVITY, "m/s^2")
}

/// A gravity magnitude, m/s^2.
pub fn gravity_magnitude(g: f64) -> Result<f64, String> {
    non_negative(g)?;
    gravity([0.0, g, 0.0]).map(|_| g)
}

/// A speed, m/s.
pub fn speed(v: f64) -> Result<f64, String> {
    non_negative(v)?;
    if v <= MAX_SPEED {
        Ok(v)
    } else {
        Err(format!("must be at most {MAX_SPEED:e} m/s, got {v:e}"))
    }
}

/// A mass, kg.
pub fn mass(m: f64) -> Result<f64, String> {
    positive(m)?;
    if (MIN_MASS..=MAX_MASS).contains(&m) {
        Ok(m)
    } else {
        Err(format!(
            "must be between {MIN_MASS:e} and {MAX_MASS:e} kg, got {m:e}"
        ))
    }
}

/// `[min, max]` with `min <= max`, each passing `each`.
pub fn range(v: [f64; 2], each: fn(f64) -> Result<f64, String>) -> Result<[f64; 2], String> {
    for c in v {
        each(c).map_err(|e| format!("[{}, {}]: each end {e}", v[0], v[1]))?;
    }
    if v[0] <= v[1] {
        Ok(v)
    } else {
        Err(format!("[{}, {}]: min must not exceed max", v[0], v[1]))
    }
}

/// A centre inside `[r, 1 - r]` on every axis.
pub fn inside_box(position: [f64; 3], r: f64) -> Result<[f64; 3], String> {
    vector(position)?;
    if position.iter().all(|&c| c >= r && c <= 1.0 - r) {
        Ok(position)
    } else {
        Err(format!(
            "[{}, {}, {}] puts the sphere (radius {r}) outside the box: \
             each coordinate must be in [{r}, {}]",
            position[0],
            position[1],
            position[2],
            1.0 - r
        ))
    }
}

/// A whole number of spheres within [`MAX_BODIES`].
pub fn count(n: usize) -> Result<usize, String> {
    if n <= MAX_BODIES {
        Ok(n)
    } else {
        Err(format!("must be at most {MAX_BODIES}, got {n}"))
    }
}

/// Sub-steps per step: a whole number in `1..=MAX_SUBSTEPS`.
pub fn substeps(n: i64) -> Result<u32, String> {
    if (1..=i64::from(MAX_SUBSTEPS)).contains(&n) {
        Ok(n as u32)
    } else {
        Err(format!(
            "must be a whole number from 1 to {MAX_SUBSTEPS}, got {n}"
        ))
    }
}
