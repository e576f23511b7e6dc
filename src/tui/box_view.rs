//! The picture of the box: a custom canvas [`Shape`] that paints braille
//! dots directly (box edges, spheres, trails, velocity vectors, and the
//! ghost of the exact reference: dashed outlines under the spheres and a
//! small cross at each exact centre over them, so it shows without colour
//! too and where it coincides with a sphere).
//!
//! Owns the drawing of one frame from a [`Projection`] and read-only
//! bodies; it never steps or changes the world. The canvas it draws on has
//! bounds equal to its dot grid, so a canvas coordinate is a dot and the
//! shape works in dots throughout: no per-point coordinate conversion, and
//! each sphere costs one projection and a few dot writes. A sphere whose
//! projected radius spans [`CIRCLE_MIN_DOTS`] or more is drawn as a circle
//! outline, smaller ones as one dot.
//!
//! Why not the canvas's own `Circle`: it converts 360 points per circle
//! from canvas coordinates, which took about 100 ms a frame for 10,000
//! spheres where this shape takes under 1 ms (`lerpit bench --render`).

use super::camera::Projection;
use super::palette::{self, Colouring, ramp_colour};
use crate::sim::{Bodies, Vec3};
use ratatui::style::Color;
use ratatui::widgets::canvas::{Painter, Shape};

/// Projected radius from which a sphere is drawn as a circle, dots.
pub const CIRCLE_MIN_DOTS: f64 = 1.5;
/// Seconds of motion a velocity vector spans.
pub const VECTOR_SECONDS: f64 = 0.1;
/// At most this many spheres get a velocity vector (evenly chosen).
pub const MAX_VECTORS: usize = 2000;

/// The 12 edges of the unit box: the axis an edge runs along and the two
/// other coordinates (each 0 or 1).
const EDGES: [(usize, [u8; 2]); 12] = {
    let mut e = [(0, [0, 0]); 12];
    let mut k = 0;
    while k < 12 {
        e[k] = (k / 4, [(k % 4 / 2) as u8, (k % 2) as u8]);
        k += 1;
    }
    e
};

/// One trail: positions of a sphere, oldest first.
pub type Trail = Vec<Vec3>;

pub struct BoxPicture<'a> {
    pub projection: Projection,
    pub width: usize,
    pub height: usize,
    pub bodies: &'a Bodies,
    pub colouring: Colouring,
    /// Speed drawn in the hottest colour, m/s.
    pub speed_scale: f64,
    /// False under NO_COLOR.
    pub colour: bool,
    pub trails: &'a [Trail],
    pub vectors: bool,
    /// The exact reference's spheres: positions and radii.
    pub ghost: Option<(&'a [Vec3], &'a [f64])>,
}

/// Writes dots, dropping those off the grid.
struct Dots<'p, 'a, 'b> {
    painter: &'p mut Painter<'a, 'b>,
    width: usize,
    height: usize,
}

impl Dots<'_, '_, '_> {
    #[inline]
    fn dot(&mut self, x: i64, y: i64, c: Color) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.painter.paint(x as usize, y as usize, c);
        }
    }

    /// Bresenham between two dot positions.
    fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: Color) {
        let lim = 4.0 * (self.width + self.height) as f64;
        if ![x0, y0, x1, y1]
            .iter()
            .all(|v| v.is_finite() && v.abs() < lim)
        {
            return;
        }
        let (mut x, mut y) = (x0.round() as i64, y0.round() as i64);
        let (x1, y1) = (x1.round() as i64, y1.round() as i64);
        let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
        let (sx, sy) = (if x < x1 { 1 } else { -1 }, if y < y1 { 1 } else { -1 });
        let mut err = dx + dy;
        loop {
            self.dot(x, y, c);
            if x == x1 && y == y1 {
                break;
            }
            let e2 = 2 * err;
            if e2 >= dy {
                err += dy;
                x += sx;
            }
            if e2 <= dx {
                err += dx;
                y += sy;
            }
        }
    }

    /// Midpoint circle outline of radius `r` dots; `dashed` leaves out
    /// every other step of it.
    fn circle(&mut self, cx: i64, cy: i64, r: i64, c: Color) {
        self.outline(cx, cy, r, c, false);
    }

    fn outline(&mut self, cx: i64, cy: i64, r: i64, c: Color, dashed: bool) {
        let (mut x, mut y, mut err) = (r, 0i64, 1 - r);
        while x >= y {
            let skip = dashed && y % 2 == 1;
            for (px, py) in [
                (x, y),
                (y, x),
                (-y, x),
                (-x, y),
                (-x, -y),
                (-y, -x),
                (y, -x),
                (x, -y),
            ] {
                if !skip {
                    self.dot(cx + px, cy + py, c);
                }
            }
            y += 1;
            if err < 0 {
                err += 2 * y + 1;
            } else {
                x -= 1;
                err += 2 * (y - x) + 1;
            }
        }
    }
}

impl BoxPicture<'_> {
    fn colour_or_plain(&self, c: Color) -> Color {
        if self.colour { c } else { palette::PLAIN }
    }

    fn draw_edges(&self, dots: &mut Dots) {
        let toward = self.projection.toward;
        for (axis, [a, b]) in EDGES {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut p0 = Vec3::ZERO;
            p0[u] = f64::from(a);
            p0[w] = f64::from(b);
            let mut p1 = p0;
            p1[axis] = 1.0;
            // An edge is hidden when both faces meeting there face away.
            let faces_away = |k: usize, side: u8| {
                let s = if side == 1 { 1.0 } else { -1.0 };
                s * toward[k] < -1e-9
            };
            let hidden = faces_away(u, a) && faces_away(w, b);
            let c = if hidden {
                palette::EDGE_HIDDEN
            } else {
                palette::EDGE_VISIBLE
            };
            let pr = &self.projection;
            dots.line(pr.to_screen(p0), pr.to_screen(p1), self.colour_or_plain(c));
        }
    }

    fn draw_trails(&self, dots: &mut Dots) {
        let c = self.colour_or_plain(palette::TRAIL);
        for trail in self.trails {
            for pair in trail.windows(2) {
                let (a, b) = (
                    self.projection.to_screen(pair[0]),
                    self.projection.to_screen(pair[1]),
                );
                dots.line(a, b, c);
            }
        }
    }

    fn sphere_colour(&self, i: usize) -> Color {
        let b = self.bodies;
        let t = match self.colouring {
            Colouring::Speed => b.velocity[i].length() / self.speed_scale,
            Colouring::Depth => {
                (self.projection.depth(b.position[i]) + DEPTH_HALF_RANGE) / (2.0 * DEPTH_HALF_RANGE)
            }
        };
        self.colour_or_plain(ramp_colour(self.colouring.ramp(), t))
    }

    fn draw_sphere(&self, dots: &mut Dots, i: usize) {
        let b = self.bodies;
        let (x, y) = self.projection.to_screen(b.position[i]);
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        let c = self.sphere_colour(i);
        let r = b.radius[i] * self.projection.scale;
        let (cx, cy) = (x.round() as i64, y.round() as i64);
        if r >= CIRCLE_MIN_DOTS {
            dots.circle(cx, cy, r.round() as i64, c);
        } else {
            dots.dot(cx, cy, c);
        }
    }

    /// The ghost's outlines, dashed, under the spheres.
    fn draw_ghost_outlines(&self, dots: &mut Dots, (x, r): (&[Vec3], &[f64])) {
        let c = self.colour_or_plain(palette::GHOST);
        for (&p, &r) in x.iter().zip(r) {
            let (sx, sy) = self.projection.to_screen(p);
            let r = r * self.projection.scale;
            if sx.is_finite() && sy.is_finite() && r >= CIRCLE_MIN_DOTS {
                dots.outline(
                    sx.round() as i64,
                    sy.round() as i64,
                    r.round() as i64,
                    c,
                    true,
                );
            }
        }
    }

    /// The ghost's centres, a small cross over the spheres: visible even
    /// where the ghost and the sphere coincide.
    fn draw_ghost_centres(&self, dots: &mut Dots, x: &[Vec3]) {
        let c = self.colour_or_plain(palette::GHOST);
        for &p in x {
            let (sx, sy) = self.projection.to_screen(p);
            if !(sx.is_finite() && sy.is_finite()) {
                continue;
            }
            let (cx, cy) = (sx.round() as i64, sy.round() as i64);
            for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                dots.dot(cx + dx, cy + dy, c);
            }
        }
    }

    fn draw_vectors(&self, dots: &mut Dots) {
        let b = self.bodies;
        let c = self.colour_or_plain(palette::VECTOR);
        for i in sample_slots(b, MAX_VECTORS) {
            let from = self.projection.to_screen(b.position[i]);
            let (dx, dy) = self
                .projection
                .to_screen_vector(b.velocity[i] * VECTOR_SECONDS);
            dots.line(from, (from.0 + dx, from.1 + dy), c);
        }
    }
}

/// Slots of at most `most` spheres, evenly chosen by scene index (every
/// `len / most`-th), so the same spheres are chosen whatever slots the
/// world's spatial order has moved them to.
pub fn sample_slots(b: &Bodies, most: usize) -> impl Iterator<Item = usize> + '_ {
    let stride = b.len().div_ceil(most.max(1)).max(1);
    (0..b.len()).filter(move |&k| (b.id[k] as usize).is_multiple_of(stride))
}

/// Points of the box lie within this distance of its centre along any
/// direction: half its diagonal, m.
const DEPTH_HALF_RANGE: f64 = 0.866_025_403_784_438_6;

impl Shape for BoxPicture<'_> {
    fn draw(&self, painter: &mut Painter) {
        let mut dots = Dots {
            painter,
            width: self.width,
            height: self.height,
        };
        self.draw_edges(&mut dots);
        if !self.trails.is_empty() {
            self.draw_trails(&mut dots);
        }
        if let Some(ghost) = self.ghost {
            self.draw_ghost_outlines(&mut dots, ghost);
        }
        let n = self.bodies.len();
        match self.colouring {
            // Far first, so the nearest sphere's colour wins a shared cell.
            Colouring::Depth => {
                let mut order: Vec<(f32, u32)> = (0..n)
                    .map(|i| {
                        (
                            self.projection.depth(self.bodies.position[i]) as f32,
                            i as u32,
                        )
                    })
                    .collect();
                order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                for (_, i) in order {
                    self.draw_sphere(&mut dots, i as usize);
                }
            }
            Colouring::Speed => {
                for i in 0..n {
                    self.draw_sphere(&mut dots, i);
                }
            }
        }
        if self.vectors {
            self.draw_vectors(&mut dots);
        }
        if let Some((x, _)) = self.ghost {
            self.draw_ghost_centres(&mut dots, x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_twelve_edges_are_distinct_and_run_along_each_axis_four_times() {
        for axis in 0..3 {
            let along: Vec<_> = EDGES.iter().filter(|e| e.0 == axis).collect();
            assert_eq!(along.len(), 4);
            for (k, a) in along.iter().enumerate() {
                for b in &along[k + 1..] {
                    assert_ne!(a.1, b.1);
                }
            }
        }
    }
}
