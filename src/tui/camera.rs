//! The orbit camera and the orthographic projection of the box.
//!
//! Owns the view only: yaw, pitch and zoom, the preset views, and the map
//! from a point of the box `[0, 1]^3` (y up) to braille dots on the screen.
//! It never reads or changes the world.
//!
//! Projection: the point is moved so the box centre is the origin, turned
//! by `yaw` about the vertical axis and then by `pitch` about the screen's
//! horizontal axis, and its depth dropped (orthographic). A braille cell is
//! 2 dots wide and 4 tall and a terminal cell is about twice as tall as it
//! is wide, so a dot is about square: one scale serves both axes and the
//! box keeps its true proportions at any terminal size.

use crate::sim::Vec3;

/// Half the screen extent the view frames at zoom 1, in metres: the box's
/// diagonal is `sqrt 3 ~ 1.73`, so the whole box fits at any orientation.
const HALF_EXTENT: f64 = 0.9;
/// Radians turned by one orbit key press.
pub(crate) const ORBIT_STEP: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// Factor of one zoom key press or wheel notch.
pub(crate) const ZOOM_STEP: f64 = 1.25;
pub const ZOOM_MIN: f64 = 0.5;
pub const ZOOM_MAX: f64 = 8.0;
/// Pitch stays inside the poles so "up" on screen is always defined.
pub const PITCH_LIMIT: f64 = std::f64::consts::FRAC_PI_2;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    Front,
    Side,
    Top,
    ThreeQuarter,
}

impl Preset {
    /// `(yaw, pitch)` in radians.
    pub(crate) fn angles(self) -> (f64, f64) {
        let deg = std::f64::consts::PI / 180.0;
        match self {
            Preset::Front => (0.0, 0.0),
            Preset::Side => (90.0 * deg, 0.0),
            Preset::Top => (0.0, 90.0 * deg),
            Preset::ThreeQuarter => (-35.0 * deg, 25.0 * deg),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Turn about the vertical axis, rad.
    pub yaw: f64,
    /// Tilt towards looking down on the box, rad, in `[-PITCH_LIMIT, PITCH_LIMIT]`.
    pub pitch: f64,
    /// Magnification, in `[ZOOM_MIN, ZOOM_MAX]`.
    pub zoom: f64,
}

impl Default for Camera {
    fn default() -> Self {
        let (yaw, pitch) = Preset::ThreeQuarter.angles();
        Self {
            yaw,
            pitch,
            zoom: 1.0,
        }
    }
}

impl Camera {
    pub(crate) fn orbit(&mut self, d_yaw: f64, d_pitch: f64) {
        if d_yaw.is_finite() {
            self.yaw = (self.yaw + d_yaw).rem_euclid(std::f64::consts::TAU);
        }
        if d_pitch.is_finite() {
            self.pitch = (self.pitch + d_pitch).clamp(-PITCH_LIMIT, PITCH_LIMIT);
        }
    }

    pub(crate) fn zoom_by(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            self.zoom = (self.zoom * factor).clamp(ZOOM_MIN, ZOOM_MAX);
        }
    }

    /// Turn to a preset, keeping the zoom.
    pub(crate) fn look(&mut self, preset: Preset) {
        (self.yaw, self.pitch) = preset.angles();
    }

    /// The projection onto a `width x height` dot grid, the box centre in
    /// the middle.
    pub fn projection(&self, width_dots: usize, height_dots: usize) -> Projection {
        self.projection_at(width_dots, height_dots, Vec3::splat(0.5))
    }

    /// The projection onto a `width x height` dot grid with `target` in
    /// the middle.
    pub fn projection_at(&self, width_dots: usize, height_dots: usize, target: Vec3) -> Projection {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let (w, h) = (width_dots as f64, height_dots as f64);
        let scale = w.min(h) / (2.0 * HALF_EXTENT) * self.zoom;
        Projection {
            right: Vec3::new(cy, 0.0, -sy),
            up: Vec3::new(-sp * sy, cp, -sp * cy),
            toward: Vec3::new(cp * sy, sp, cp * cy),
            scale,
            centre: (w / 2.0, h / 2.0),
            target,
        }
    }
}

/// A fixed view: screen axes in world coordinates and the dot scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// World direction drawn to the right.
    pub right: Vec3,
    /// World direction drawn upwards.
    pub up: Vec3,
    /// World direction toward the viewer (larger is nearer).
    pub toward: Vec3,
    /// Dots per metre.
    pub scale: f64,
    /// Screen position of `target`, dots from the top left.
    pub centre: (f64, f64),
    /// The point drawn in the middle: the box centre, or what a zoomed view
    /// follows.
    pub target: Vec3,
}

impl Projection {
    /// Dots from the top left, `(x, y)` with y down. May lie off the grid.
    #[inline]
    pub fn to_screen(&self, p: Vec3) -> (f64, f64) {
        let q = p - self.target;
        (
            self.centre.0 + q.dot(self.right) * self.scale,
            self.centre.1 - q.dot(self.up) * self.scale,
        )
    }

    /// Distance toward the viewer from the box centre, m, in `[-0.87, 0.87]`
    /// for points of the box.
    #[inline]
    pub(crate) fn depth(&self, p: Vec3) -> f64 {
        (p - Vec3::splat(0.5)).dot(self.toward)
    }

    /// A screen displacement for a world displacement (no offset), dots.
    #[inline]
    pub(crate) fn to_screen_vector(self, v: Vec3) -> (f64, f64) {
        (v.dot(self.right) * self.scale, -v.dot(self.up) * self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_view_maps_x_right_and_y_up_with_equal_scales() {
        let mut cam = Camera::default();
        cam.look(Preset::Front);
        let p = cam.projection(200, 100);
        let (cx, cy) = p.to_screen(Vec3::splat(0.5));
        assert_eq!((cx, cy), (100.0, 50.0));
        let (x1, _) = p.to_screen(Vec3::new(1.0, 0.5, 0.5));
        let (_, y1) = p.to_screen(Vec3::new(0.5, 1.0, 0.5));
        assert!((x1 - cx - p.scale * 0.5).abs() < 1e-9, "x to the right");
        assert!(
            (cy - y1 - p.scale * 0.5).abs() < 1e-9,
            "y upwards, same scale"
        );
        assert!(
            p.depth(Vec3::new(0.5, 0.5, 1.0)) > 0.0,
            "+z toward the viewer"
        );
    }

    #[test]
    fn the_box_fits_the_grid_at_every_orientation() {
        let mut cam = Camera::default();
        for k in 0..36 {
            cam.orbit(0.17, 0.11 * if k % 2 == 0 { 1.0 } else { -3.0 });
            let p = cam.projection(120, 80);
            for c in 0..8 {
                let corner = Vec3::new((c & 1) as f64, ((c >> 1) & 1) as f64, (c >> 2) as f64);
                let (x, y) = p.to_screen(corner);
                assert!((0.0..=120.0).contains(&x) && (0.0..=80.0).contains(&y));
            }
        }
    }

    #[test]
    fn pitch_and_zoom_are_clamped() {
        let mut cam = Camera::default();
        cam.orbit(0.0, 100.0);
        assert_eq!(cam.pitch, PITCH_LIMIT);
        cam.zoom_by(1e9);
        assert_eq!(cam.zoom, ZOOM_MAX);
        cam.zoom_by(0.0);
        assert_eq!(cam.zoom, ZOOM_MAX, "a zero factor is ignored");
        cam.zoom_by(1e-9);
        assert_eq!(cam.zoom, ZOOM_MIN);
    }
}
