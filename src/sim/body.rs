//! The spheres. `Bodies` keeps what every step touches (positions,
//! velocities, radii, masses and inverse masses) in parallel arrays, so the
//! stages walk memory in order; `Body` is the one-sphere view used to build
//! and report a world.

use super::Vec3;
use serde::{Deserialize, Serialize};

/// One sphere, as a scene file or a report sees it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// Centre, m.
    pub position: Vec3,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Radius, m.
    pub radius: f64,
    /// Mass, kg (> 0).
    pub mass: f64,
}

/// All spheres of a world, structure-of-arrays. Index `i` is the same body in
/// every array; the order is the scene order and never changes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bodies {
    pub position: Vec<Vec3>,
    pub velocity: Vec<Vec3>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub inverse_mass: Vec<f64>,
}

impl Bodies {
    pub fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inverse_mass: Vec::with_capacity(n),
        }
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn push(&mut self, body: Body) {
        self.position.push(body.position);
        self.velocity.push(body.velocity);
        self.radius.push(body.radius);
        self.mass.push(body.mass);
        self.inverse_mass.push(1.0 / body.mass);
    }

    pub fn get(&self, i: usize) -> Body {
        Body {
            position: self.position[i],
            velocity: self.velocity[i],
            radius: self.radius[i],
            mass: self.mass[i],
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = Body> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// The largest radius, or 0 for no bodies.
    pub fn max_radius(&self) -> f64 {
        self.radius.iter().copied().fold(0.0, f64::max)
    }
}

impl FromIterator<Body> for Bodies {
    fn from_iter<I: IntoIterator<Item = Body>>(iter: I) -> Self {
        let mut bodies = Bodies::default();
        for b in iter {
            bodies.push(b);
        }
        bodies
    }
}
