//! The picture of the box: a custom canvas [`Shape`] that composes one
//! frame in a [`DotBuffer`] (where a nearer sphere can hide a farther one)
//! and then paints the buffer's lit dots. Each dot's ink is tagged with
//! the [`Step`] that drew it.
//!
//! Draw order, back to front ([`Step::ORDER`]):
//! 1. `HiddenEdges`: the box edges behind everything (both faces meeting
//!    there turned away), dashed.
//! 2. `FloorBehind`: seen from above, the floor grid (`#`, dotted) and the
//!    spheres' shadows: a half-tone spot straight under each centre, so a
//!    sphere's height reads as the gap to its shadow.
//! 3. `Spheres`: filled discs, far to near. Each first clears a rim one dot
//!    wide around itself, so a nearer sphere cuts a dark gap through what
//!    is behind it and touching spheres stay apart.
//! 4. `VisibleEdges`: the other edges, solid: nothing in the box is
//!    nearer. Where one crosses a sphere it is a thin gap through it
//!    ([`Mark::Faint`]).
//! 5. `FloorInFront`: seen from below, the floor grid is nearer than the
//!    spheres and is drawn over them the same way. No shadows: they lie on
//!    the floor's upper side.
//! 6. Overlays, on top of everything: `Trails`, `GhostOutlines`, `Vectors`,
//!    `GhostCentres` (the exact reference's ghost: dashed outlines and a
//!    small cross at each exact centre), `Contacts` (a ring round each
//!    sphere in contact and the contact normal through the contact point)
//!    and `Selection` (a double ring round each selected sphere, its trail
//!    and velocity vector always, and for a pair in contact its outlines
//!    before the correction, dotted). An overlay marks its dots with
//!    [`Mark::Overlay`]: a dot of a sphere is cut, any other dot lit, so the
//!    overlay shows on a filled sphere without colour too; the cell takes
//!    the overlay's colour.
//!
//! To add an overlay: a [`Step`] at the end of `ORDER` (and among the
//! overlays in `Step::is_overlay`, which the tests read), an arm in
//! `BoxPicture::draw_step`, and a `draw_*` function that marks dots with
//! [`Mark::Overlay`].
//!
//! Owns the drawing of one frame from a [`Projection`] and read-only
//! bodies; it never steps or changes the world. The canvas it draws on has
//! bounds equal to its dot grid, so a canvas coordinate is a dot and the
//! picture works in dots throughout: each sphere costs one projection and
//! a few spans of dots (the canvas's own `Circle` only outlines, and
//! converts 360 points per circle from canvas coordinates).

use super::camera::Projection;
use super::dot_buffer::{Dash, DiscStamp, DotBuffer, Ink, Mark, nearest_dot};
use super::frame::{Trail, sample_slots};
use super::palette::{self, Colouring};
use crate::sim::{Bodies, Contact, Vec3};
use ratatui::style::Color;
use ratatui::widgets::canvas::{Painter, Shape};
use std::cell::Cell;

/// Projected radius below which a sphere is drawn as one dot (and no rim),
/// dots.
pub(crate) const DISC_MIN_DOTS: f64 = 1.0;
/// Disc shapes kept for reuse within a frame: radii below this many
/// quarter dots (larger spheres are few).
const STAMPS_KEPT: usize = 1024;
/// Width of the dark rim a sphere clears around its disc, dots.
pub(crate) const RIM_DOTS: f64 = 1.0;
/// Seconds of motion a velocity vector spans.
pub(crate) const VECTOR_SECONDS: f64 = 0.1;
/// At most this many spheres get a velocity vector (evenly chosen).
pub(crate) const MAX_VECTORS: usize = 2000;
/// At most this many spheres cast a shadow (evenly chosen): every sphere
/// of the lessons, and a readable sample of the floor in larger worlds.
pub(crate) const MAX_SHADOWS: usize = 200;
/// Divisions of the floor grid per metre each way (0.2 m squares: finer
/// ones crowd the spheres when the grid is drawn in front of them).
pub(crate) const FLOOR_GRID_LINES: u32 = 5;

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

/// One step of drawing the picture. [`Step::ORDER`] is the drawing order;
/// the module's top comment says what each step draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    HiddenEdges,
    FloorBehind,
    Spheres,
    VisibleEdges,
    FloorInFront,
    Trails,
    GhostOutlines,
    Vectors,
    GhostCentres,
    Contacts,
    Selection,
}

impl Step {
    /// Back to front: the scene first, the overlays last.
    pub(crate) const ORDER: [Step; 11] = [
        Step::HiddenEdges,
        Step::FloorBehind,
        Step::Spheres,
        Step::VisibleEdges,
        Step::FloorInFront,
        Step::Trails,
        Step::GhostOutlines,
        Step::Vectors,
        Step::GhostCentres,
        Step::Contacts,
        Step::Selection,
    ];

    /// Drawn on top of the scene (see [`Mark::Overlay`]).
    #[cfg(test)]
    pub(crate) fn is_overlay(self) -> bool {
        match self {
            Step::HiddenEdges
            | Step::FloorBehind
            | Step::Spheres
            | Step::VisibleEdges
            | Step::FloorInFront => false,
            Step::Trails
            | Step::GhostOutlines
            | Step::Vectors
            | Step::GhostCentres
            | Step::Contacts
            | Step::Selection => true,
        }
    }
}

pub(crate) struct BoxPicture<'a> {
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
    /// Draw the floor grid.
    pub floor_grid: bool,
    /// Contacts and the selection, on top.
    pub marks: Marks<'a>,
    /// Spheres the last drawing showed as a dot at their centre, not as
    /// discs: the farthest, where all the discs are more dots than
    /// [`disc_budget`] allows.
    pub as_points: Cell<usize>,
}

/// Dots a frame may write in discs, for a canvas of `dots` dots and
/// `spheres` spheres: [`DISC_DOTS_PER_CANVAS_DOT`] a dot of the canvas and
/// [`DISC_DOTS_PER_SPHERE`] a sphere. Spheres as wide as the box, a
/// million of them on top of one another, would otherwise take seconds to
/// draw, and keys would wait for them.
pub(crate) fn disc_budget(dots: usize, spheres: usize) -> usize {
    DISC_DOTS_PER_CANVAS_DOT
        .saturating_mul(dots)
        .saturating_add(DISC_DOTS_PER_SPHERE.saturating_mul(spheres))
}

/// See [`disc_budget`]: enough to cover the canvas this many times over.
const DISC_DOTS_PER_CANVAS_DOT: usize = 16;
/// See [`disc_budget`]: a disc of about a dot's radius.
const DISC_DOTS_PER_SPHERE: usize = 4;

/// What the learner asked to see on top of the picture.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Marks<'a> {
    /// The contacts of the step, drawn (at most [`MAX_CONTACT_MARKS`]).
    pub contacts: &'a [Contact],
    /// Slots of the selected spheres.
    pub selected: &'a [usize],
    /// Their recent paths.
    pub selected_trails: &'a [Trail],
    /// A selected pair's centres and radii before its correction.
    pub before: &'a [(Vec3, f64)],
}

/// Contacts drawn at most: beyond this the legend says how many are not.
pub(crate) const MAX_CONTACT_MARKS: usize = 300;
/// Length of a drawn contact normal on each side of the contact point, as
/// a share of the smaller radius.
const NORMAL_SHARE: f64 = 0.8;

/// A sphere as drawn: centre and radius in dots, its ink and depth class.
#[derive(Clone, Copy, Debug)]
struct Disc {
    x: f32,
    y: f32,
    r: f32,
    ink: Ink,
    class: u16,
}

/// Which side of the floor (the `y = 0` face) the viewer sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FloorSide {
    /// From above: the floor is behind the spheres.
    Above,
    /// From below: the floor is in front of them.
    Below,
    /// Its depth spans less than a dot on the screen.
    EdgeOn,
}

impl BoxPicture<'_> {
    /// The composed picture: every step of [`Step::ORDER`] in turn.
    pub(crate) fn compose(&self) -> DotBuffer<Step> {
        let mut dots = DotBuffer::new(self.width, self.height);
        for step in Step::ORDER {
            self.draw_step(step, &mut dots);
        }
        dots
    }

    fn draw_step(&self, step: Step, dots: &mut DotBuffer<Step>) {
        let floor = self.floor_side();
        match step {
            Step::HiddenEdges => self.draw_edges(dots, true),
            Step::FloorBehind if floor == FloorSide::Above => {
                if self.floor_grid {
                    self.draw_floor_grid(dots, step, Mark::Solid);
                }
                self.draw_shadows(dots);
            }
            Step::FloorBehind => {}
            Step::Spheres => self.draw_spheres(dots),
            Step::VisibleEdges => self.draw_edges(dots, false),
            Step::FloorInFront => {
                if self.floor_grid && floor == FloorSide::Below {
                    self.draw_floor_grid(dots, step, Mark::Faint);
                }
            }
            Step::Trails => self.draw_trails(dots),
            Step::GhostOutlines => {
                if let Some(ghost) = self.ghost {
                    self.draw_ghost_outlines(dots, ghost);
                }
            }
            Step::Vectors => {
                if self.vectors {
                    self.draw_vectors(dots);
                }
            }
            Step::GhostCentres => {
                if let Some((x, _)) = self.ghost {
                    self.draw_ghost_centres(dots, x);
                }
            }
            Step::Contacts => self.draw_contacts(dots),
            Step::Selection => self.draw_selection(dots),
        }
    }

    /// A ring round both spheres of each contact and its normal through
    /// the contact point (midway across the overlap).
    fn draw_contacts(&self, dots: &mut DotBuffer<Step>) {
        if self.marks.contacts.is_empty() {
            return;
        }
        let ink = self.ink(dots, palette::CONTACT, Step::Contacts);
        let b = self.bodies;
        let pr = &self.projection;
        for c in self.marks.contacts.iter().take(MAX_CONTACT_MARKS) {
            let (i, j) = (c.i as usize, c.j as usize);
            if i >= b.len() || j >= b.len() {
                continue;
            }
            for k in [i, j] {
                self.ring(dots, k, 1.0, ink, false);
            }
            let n = c.contact_normal;
            let at = b.position[i] + n * (b.radius[i] - 0.5 * c.penetration);
            let half = NORMAL_SHARE * b.radius[i].min(b.radius[j]);
            dots.line(
                pr.to_screen(at - n * half),
                pr.to_screen(at + n * half),
                ink,
                Mark::Overlay,
                Dash::Solid,
            );
        }
    }

    /// The selected spheres: a double ring, their trails and velocity
    /// vectors, and a pair's dotted outlines before its correction.
    fn draw_selection(&self, dots: &mut DotBuffer<Step>) {
        let m = &self.marks;
        if m.selected.is_empty() {
            return;
        }
        let ink = self.ink(dots, palette::SELECTION, Step::Selection);
        let b = self.bodies;
        let pr = &self.projection;
        for trail in m.selected_trails {
            for pair in trail.windows(2) {
                let (a, z) = (pr.to_screen(pair[0]), pr.to_screen(pair[1]));
                dots.line(a, z, ink, Mark::Overlay, Dash::Solid);
            }
        }
        for &(p, r) in m.before {
            let (sx, sy) = pr.to_screen(p);
            let r = r * pr.scale;
            if sx.is_finite() && sy.is_finite() && r >= DISC_MIN_DOTS {
                let centre = (nearest_dot(sx), nearest_dot(sy));
                dots.outline(centre, nearest_dot(r), ink, Mark::Overlay, true);
            }
        }
        for &k in m.selected.iter().filter(|&&k| k < b.len()) {
            self.ring(dots, k, 1.0, ink, false);
            self.ring(dots, k, 3.0, ink, false);
            self.vector(dots, k, ink);
        }
    }

    /// The velocity vector of the sphere in slot `k`: [`VECTOR_SECONDS`]
    /// of its motion.
    fn vector(&self, dots: &mut DotBuffer<Step>, k: usize, ink: Ink) {
        let b = self.bodies;
        let from = self.projection.to_screen(b.position[k]);
        let (dx, dy) = self
            .projection
            .to_screen_vector(b.velocity[k] * VECTOR_SECONDS);
        let to = (from.0 + dx, from.1 + dy);
        dots.line(from, to, ink, Mark::Overlay, Dash::Solid);
    }

    /// A ring `gap` dots outside the drawn disc of the sphere in slot `k`.
    fn ring(&self, dots: &mut DotBuffer<Step>, k: usize, gap: f64, ink: Ink, dashed: bool) {
        let (sx, sy) = self.projection.to_screen(self.bodies.position[k]);
        if !(sx.is_finite() && sy.is_finite()) {
            return;
        }
        let r = self.bodies.radius[k] * self.projection.scale + gap;
        dots.outline(
            (nearest_dot(sx), nearest_dot(sy)),
            nearest_dot(r),
            ink,
            Mark::Overlay,
            dashed,
        );
    }

    fn colour_or_plain(&self, c: Color) -> Color {
        if self.colour { c } else { palette::PLAIN }
    }

    fn ink(&self, dots: &mut DotBuffer<Step>, c: Color, step: Step) -> Ink {
        dots.ink(self.colour_or_plain(c), step)
    }

    fn floor_side(&self) -> FloorSide {
        // The floor's one metre of depth spans up to this many dots of height.
        let span = self.projection.toward.y * self.projection.scale;
        if span >= 1.0 {
            FloorSide::Above
        } else if span <= -1.0 {
            FloorSide::Below
        } else {
            FloorSide::EdgeOn
        }
    }

    /// The hidden edges (both faces meeting there turned away), dashed, or
    /// the others, solid.
    fn draw_edges(&self, dots: &mut DotBuffer<Step>, hidden: bool) {
        let (colour, step, dash) = if hidden {
            (palette::EDGE_HIDDEN, Step::HiddenEdges, Dash::Dashed)
        } else {
            (palette::EDGE_VISIBLE, Step::VisibleEdges, Dash::Solid)
        };
        let ink = self.ink(dots, colour, step);
        let toward = self.projection.toward;
        for (axis, [a, b]) in EDGES {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let faces_away = |k: usize, side: u8| {
                let s = if side == 1 { 1.0 } else { -1.0 };
                s * toward[k] < -1e-9
            };
            if (faces_away(u, a) && faces_away(w, b)) != hidden {
                continue;
            }
            let mut p0 = Vec3::ZERO;
            p0[u] = f64::from(a);
            p0[w] = f64::from(b);
            let mut p1 = p0;
            p1[axis] = 1.0;
            let pr = &self.projection;
            let how = if hidden { Mark::Solid } else { Mark::Faint };
            dots.line(pr.to_screen(p0), pr.to_screen(p1), ink, how, dash);
        }
    }

    /// Dotted lines across the floor, [`FLOOR_GRID_LINES`] a metre.
    fn draw_floor_grid(&self, dots: &mut DotBuffer<Step>, step: Step, how: Mark) {
        let ink = self.ink(dots, palette::FLOOR_GRID, step);
        let pr = &self.projection;
        for k in 1..FLOOR_GRID_LINES {
            let t = f64::from(k) / f64::from(FLOOR_GRID_LINES);
            for (a, b) in [
                (Vec3::new(t, 0.0, 0.0), Vec3::new(t, 0.0, 1.0)),
                (Vec3::new(0.0, 0.0, t), Vec3::new(1.0, 0.0, t)),
            ] {
                dots.line(pr.to_screen(a), pr.to_screen(b), ink, how, Dash::Dotted);
            }
        }
    }

    /// Each sphere's shadow: its disc projected straight down onto the floor.
    fn draw_shadows(&self, dots: &mut DotBuffer<Step>) {
        let ink = self.ink(dots, palette::SHADOW, Step::FloorBehind);
        let pr = &self.projection;
        let (along_x, along_z) = (pr.to_screen_vector(Vec3::X), pr.to_screen_vector(Vec3::Z));
        let b = self.bodies;
        for i in sample_slots(b, MAX_SHADOWS) {
            let (p, r) = (b.position[i], b.radius[i]);
            let centre = pr.to_screen(Vec3::new(p.x, 0.0, p.z));
            let u = (along_x.0 * r, along_x.1 * r);
            let v = (along_z.0 * r, along_z.1 * r);
            dots.half_tone_ellipse(centre, u, v, ink);
        }
    }

    /// Every sphere, far to near, so the nearer hides the farther.
    fn draw_spheres(&self, dots: &mut DotBuffer<Step>) {
        let (b, pr) = (self.bodies, &self.projection);
        let ramp = self.colouring.ramp();
        let inks: Vec<Ink> = ramp
            .iter()
            .map(|&c| dots.surface_ink(self.colour_or_plain(c), Step::Spheres))
            .collect();
        let asleep = dots.surface_ink(self.colour_or_plain(palette::ASLEEP), Step::Spheres);
        // With a selection, the others in one dim grey.
        let selected = self.marks.selected;
        let unselected = (!selected.is_empty())
            .then(|| dots.surface_ink(self.colour_or_plain(palette::UNSELECTED), Step::Spheres));
        // Each sphere's disc, in slot order (the world's arrays read in
        // sequence), counted by depth class.
        let mut discs = Vec::with_capacity(b.len());
        let mut starts = vec![0usize; DEPTH_CLASSES + 1];
        for i in 0..b.len() {
            let p = b.position[i];
            let near = depth_fraction(pr.depth(p));
            let t = match self.colouring {
                Colouring::Speed => b.velocity[i].length() / self.speed_scale,
                Colouring::Depth => near,
            };
            let (x, y) = pr.to_screen(p);
            let class = depth_class(near);
            starts[class + 1] += 1;
            discs.push(Disc {
                x: x as f32,
                y: y as f32,
                r: (b.radius[i] * pr.scale) as f32,
                ink: match unselected {
                    Some(dim) if !selected.contains(&i) => dim,
                    _ if b
                        .rest
                        .get(i)
                        .is_some_and(|&r| crate::sim::sleep::is_asleep(r)) =>
                    {
                        asleep
                    }
                    _ => inks[palette::ramp_index(ramp.len(), t)],
                },
                class: class as u16,
            });
        }
        // Far to near by counting sort: stable, and read in sequence below.
        for k in 1..starts.len() {
            starts[k] += starts[k - 1];
        }
        let mut sorted = discs.clone();
        for d in discs {
            let at = &mut starts[usize::from(d.class)];
            sorted[*at] = d;
            *at += 1;
        }
        // The nearest discs whole, as many as the budget holds; the rest,
        // farther and drawn first, as a dot each.
        let budget = disc_budget(self.width * self.height, sorted.len());
        let mut spent = 0usize;
        let whole_from = sorted
            .iter()
            .rposition(|d| {
                spent = spent.saturating_add(self.disc_dots(d));
                spent > budget
            })
            .map_or(0, |k| k + 1);
        self.as_points.set(whole_from);
        let mut stamps: Vec<Option<DiscStamp>> = Vec::new();
        for (k, d) in sorted.into_iter().enumerate() {
            let (x, y, r) = (f64::from(d.x), f64::from(d.y), f64::from(d.r));
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            let centre = (nearest_dot(x), nearest_dot(y));
            if r < DISC_MIN_DOTS || k < whole_from {
                dots.mark(centre.0, centre.1, d.ink, Mark::Solid);
                continue;
            }
            // No disc needs to reach further than across the whole grid.
            let r = r.min((self.width + self.height) as f64);
            let quarters = nearest_dot(r * 4.0) as usize;
            let stamp = |q: usize| DiscStamp::new(q as f64 / 4.0, RIM_DOTS);
            if quarters < STAMPS_KEPT {
                if stamps.len() <= quarters {
                    stamps.resize(quarters + 1, None);
                }
                let s = stamps[quarters].get_or_insert_with(|| stamp(quarters));
                dots.disc(centre, s, d.ink);
            } else {
                dots.disc(centre, &stamp(quarters), d.ink);
            }
        }
    }

    /// The dots drawing `d` writes at most: its stamp's square, clipped to
    /// the canvas as the drawing is (1 for a dot, or for a disc wholly off
    /// the canvas).
    fn disc_dots(&self, d: &Disc) -> usize {
        let (x, y, r) = (f64::from(d.x), f64::from(d.y), f64::from(d.r));
        // A NaN radius or centre is drawn as a dot, or not at all.
        if r.is_nan() || r < DISC_MIN_DOTS || !(x.is_finite() && y.is_finite()) {
            return 1;
        }
        let reach = r.min((self.width + self.height) as f64) + 2.0;
        let span = |c: f64, n: usize| {
            let (lo, hi) = ((c - reach).max(0.0), (c + reach).min(n as f64 - 1.0));
            if lo > hi { 0 } else { (hi - lo) as usize + 1 }
        };
        (span(x, self.width) * span(y, self.height)).max(1)
    }

    fn draw_trails(&self, dots: &mut DotBuffer<Step>) {
        if self.trails.is_empty() {
            return;
        }
        let ink = self.ink(dots, palette::TRAIL, Step::Trails);
        for trail in self.trails {
            for pair in trail.windows(2) {
                let (a, b) = (
                    self.projection.to_screen(pair[0]),
                    self.projection.to_screen(pair[1]),
                );
                dots.line(a, b, ink, Mark::Overlay, Dash::Solid);
            }
        }
    }

    /// The ghost's outlines, dashed.
    fn draw_ghost_outlines(&self, dots: &mut DotBuffer<Step>, (x, r): (&[Vec3], &[f64])) {
        let ink = self.ink(dots, palette::GHOST, Step::GhostOutlines);
        for (&p, &r) in x.iter().zip(r) {
            let (sx, sy) = self.projection.to_screen(p);
            let r = r * self.projection.scale;
            if sx.is_finite() && sy.is_finite() && r >= DISC_MIN_DOTS {
                let centre = (nearest_dot(sx), nearest_dot(sy));
                dots.outline(centre, nearest_dot(r), ink, Mark::Overlay, true);
            }
        }
    }

    /// The ghost's centres, a small cross: visible even where the ghost
    /// and the sphere coincide.
    fn draw_ghost_centres(&self, dots: &mut DotBuffer<Step>, x: &[Vec3]) {
        let ink = self.ink(dots, palette::GHOST, Step::GhostCentres);
        for &p in x {
            let (sx, sy) = self.projection.to_screen(p);
            if !(sx.is_finite() && sy.is_finite()) {
                continue;
            }
            let (cx, cy) = (nearest_dot(sx), nearest_dot(sy));
            for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                dots.mark(cx + dx, cy + dy, ink, Mark::Overlay);
            }
        }
    }

    fn draw_vectors(&self, dots: &mut DotBuffer<Step>) {
        let b = self.bodies;
        let ink = self.ink(dots, palette::VECTOR, Step::Vectors);
        for i in sample_slots(b, MAX_VECTORS) {
            self.vector(dots, i, ink);
        }
    }
}

/// Where a depth lies between the farthest and the nearest point of the
/// box: 0 to 1.
#[inline]
fn depth_fraction(depth: f64) -> f64 {
    (depth + DEPTH_HALF_RANGE) / (2.0 * DEPTH_HALF_RANGE)
}

/// Spheres are drawn far to near by depth class: the box's depth range in
/// this many slices (about 0.2 mm each, finer than a dot at any zoom), in
/// slot order within one.
const DEPTH_CLASSES: usize = 8192;

/// The depth class of a depth fraction (clamped; NaN is the farthest).
#[inline]
fn depth_class(fraction: f64) -> usize {
    ((fraction * DEPTH_CLASSES as f64) as usize).min(DEPTH_CLASSES - 1)
}

/// Points of the box lie within this distance of its centre along any
/// direction: half its diagonal, m.
const DEPTH_HALF_RANGE: f64 = 0.866_025_403_784_438_6;

impl Shape for BoxPicture<'_> {
    fn draw(&self, painter: &mut Painter) {
        self.compose().paint(painter);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Body;
    use crate::tui::camera::{Camera, Preset};
    use ratatui::buffer::Buffer;
    use ratatui::layout::Rect;
    use ratatui::symbols::Marker;
    use ratatui::widgets::Widget;
    use ratatui::widgets::canvas::Canvas;

    /// Dots each way of the test pictures: 60x30 cells.
    const SIZE: usize = 120;

    fn bodies(list: &[(Vec3, Vec3, f64)]) -> Bodies {
        let mut b = Bodies::with_capacity(list.len());
        for &(position, velocity, radius) in list {
            b.push(Body {
                position,
                velocity,
                radius,
                mass: 1.0,
            });
        }
        b
    }

    fn still(list: &[(Vec3, f64)]) -> Bodies {
        let moving: Vec<_> = list.iter().map(|&(p, r)| (p, Vec3::ZERO, r)).collect();
        bodies(&moving)
    }

    fn camera(yaw_deg: f64, pitch_deg: f64) -> Camera {
        let deg = std::f64::consts::PI / 180.0;
        Camera {
            yaw: yaw_deg * deg,
            pitch: pitch_deg * deg,
            zoom: 1.0,
        }
    }

    fn picture(bodies: &Bodies, camera: Camera) -> BoxPicture<'_> {
        BoxPicture {
            projection: camera.projection(SIZE, SIZE),
            width: SIZE,
            height: SIZE,
            bodies,
            colouring: Colouring::Depth,
            speed_scale: 1.0,
            colour: true,
            trails: &[],
            vectors: false,
            ghost: None,
            floor_grid: false,
            marks: Marks::default(),
            as_points: Cell::new(0),
        }
    }

    fn dot(p: &BoxPicture, x: Vec3) -> (i64, i64) {
        let (sx, sy) = p.projection.to_screen(x);
        (nearest_dot(sx), nearest_dot(sy))
    }

    fn step_at(dots: &DotBuffer<Step>, (x, y): (i64, i64)) -> Option<Step> {
        dots.at(x, y).map(|(_, s)| s)
    }

    /// Every lit dot of `step`.
    fn dots_of(dots: &DotBuffer<Step>, step: Step) -> Vec<(i64, i64)> {
        let mut found = Vec::new();
        for y in 0..dots.height() as i64 {
            for x in 0..dots.width() as i64 {
                if step_at(dots, (x, y)) == Some(step) {
                    found.push((x, y));
                }
            }
        }
        found
    }

    /// A back sphere and a front sphere to its right, seen from the front:
    /// they overlap on the screen, 10 dots apart.
    fn back_and_front() -> Bodies {
        still(&[
            (Vec3::new(0.4, 0.5, 0.3), 0.1),
            (Vec3::new(0.55, 0.5, 0.7), 0.1),
        ])
    }

    #[test]
    fn discs_beyond_the_budget_are_drawn_as_dots_behind_the_nearest() {
        // Spheres as wide as most of the box, all on one centre: the
        // nearest are drawn whole, as many as the budget holds, the rest
        // as a dot at that centre, under them. The picture is the one
        // sphere's.
        let n = 2000;
        let stack = still(&vec![(Vec3::splat(0.5), 0.45); n]);
        let one = still(&[(Vec3::splat(0.5), 0.45)]);
        let (stacked, alone) = (
            picture(&stack, camera(30.0, 20.0)),
            picture(&one, camera(30.0, 20.0)),
        );
        let mut dots = stacked.compose();
        let drawn = n - stacked.as_points.get();
        let (cx, cy) = stacked.projection.to_screen(Vec3::splat(0.5));
        let disc = stacked.disc_dots(&Disc {
            x: cx as f32,
            y: cy as f32,
            r: (0.45 * stacked.projection.scale) as f32,
            ink: dots.surface_ink(Color::White, Step::Spheres),
            class: 0,
        });
        assert_eq!(
            drawn,
            disc_budget(SIZE * SIZE, n) / disc,
            "discs drawn whole"
        );
        assert!(drawn > 1 && drawn < n / 10, "{drawn} drawn whole");
        assert_eq!(
            dots_of(&dots, Step::Spheres),
            dots_of(&alone.compose(), Step::Spheres)
        );
        assert_eq!(alone.as_points.get(), 0);
        // Zoomed in on the centre, a thousand spheres in a corner lie off
        // the canvas and cost nothing: none is drawn as a dot for them.
        let corner = still(&vec![(Vec3::splat(0.03), 0.02); 1000]);
        let zoomed = Camera {
            zoom: 8.0,
            ..camera(30.0, 20.0)
        };
        let p = picture(&corner, zoomed);
        p.compose();
        assert!(
            p.disc_dots(&Disc {
                x: -500.0,
                y: -500.0,
                r: 40.0,
                ink: dots.surface_ink(Color::White, Step::Spheres),
                class: 0,
            }) == 1
        );
        assert_eq!(p.as_points.get(), 0);
        // A lesson's hundred spheres are all drawn whole.
        let hundred: Vec<(Vec3, f64)> = (0..100)
            .map(|k| (Vec3::new(0.1 + 0.008 * k as f64, 0.5, 0.5), 0.05))
            .collect();
        let hundred = still(&hundred);
        let p = picture(&hundred, camera(30.0, 20.0));
        p.compose();
        assert_eq!(p.as_points.get(), 0);
    }

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

    #[test]
    fn every_step_is_drawn_once_and_the_overlays_after_the_scene() {
        for (k, a) in Step::ORDER.iter().enumerate() {
            assert!(!Step::ORDER[k + 1..].contains(a), "{a:?} twice");
            if a.is_overlay() {
                assert!(
                    Step::ORDER[k..].iter().all(|s| s.is_overlay()),
                    "a scene step after the overlay {a:?}"
                );
            }
        }
        assert!(!Step::Spheres.is_overlay());
    }

    #[test]
    fn with_a_selection_the_other_spheres_are_drawn_dim() {
        let b = back_and_front();
        let colour_at = |p: &BoxPicture, x: Vec3| {
            let dots = p.compose();
            let (sx, sy) = dot(p, x);
            dots.at(sx, sy).map(|(c, _)| c)
        };
        // Half way out from each centre, away from the other (the selected
        // one's velocity vector starts at its centre; its rings are
        // outside its disc).
        let inside =
            |k: usize| b.position[k] + Vec3::new(if k == 0 { -0.05 } else { 0.05 }, 0.0, 0.0);
        let p = picture(&b, camera(0.0, 0.0));
        let own = colour_at(&p, inside(1));
        assert!(own.is_some_and(|c| c != palette::UNSELECTED));
        let mut p = picture(&b, camera(0.0, 0.0));
        let selected = [1];
        p.marks.selected = &selected;
        assert_eq!(
            colour_at(&p, inside(1)),
            own,
            "the selected keeps its colour"
        );
        assert_eq!(colour_at(&p, inside(0)), Some(palette::UNSELECTED));
    }

    #[test]
    fn a_sleeping_sphere_is_drawn_in_its_own_colour_in_either_colouring() {
        let mut b = back_and_front();
        b.rest[1] = f32::INFINITY;
        for colouring in [Colouring::Depth, Colouring::Speed] {
            let mut p = picture(&b, camera(0.0, 0.0));
            p.colouring = colouring;
            let dots = p.compose();
            let colour = |x: Vec3| {
                let (sx, sy) = dot(&p, x);
                dots.at(sx, sy).map(|(c, _)| c)
            };
            assert_eq!(
                colour(b.position[1]),
                Some(palette::ASLEEP),
                "{colouring:?}"
            );
            assert!(
                colour(b.position[0]).is_some_and(|c| c != palette::ASLEEP),
                "the awake one keeps the ramp's ({colouring:?})"
            );
        }
    }

    #[test]
    fn a_nearer_sphere_hides_a_farther_one_behind_a_dark_rim() {
        let b = back_and_front();
        let p = picture(&b, camera(0.0, 0.0));
        let dots = p.compose();
        let (back, front) = (dot(&p, b.position[0]), dot(&p, b.position[1]));
        let r = b.radius[0] * p.projection.scale;
        assert!(r > 6.0 && (front.0 - back.0) as f64 > r + RIM_DOTS + 1.0);
        let colour = |c: (i64, i64)| dots.at(c.0, c.1).map(|(c, _)| c);
        let (back_colour, front_colour) = (colour(back), colour(front));
        assert!(back_colour.is_some() && back_colour != front_colour);
        // Along the row through both centres, from the back one's centre
        // rightwards: the back sphere, then the gap of the front one's rim,
        // then the front sphere over the rest of the back one.
        let gap_from = front.0 - r as i64 - 1;
        for x in back.0..gap_from {
            assert_eq!(
                colour((x, back.1)),
                back_colour,
                "the back sphere at x = {x}"
            );
        }
        assert_eq!(
            colour((gap_from, back.1)),
            None,
            "the rim at x = {gap_from}"
        );
        for x in gap_from + 1..=front.0 {
            assert_eq!(
                colour((x, back.1)),
                front_colour,
                "the front sphere at x = {x}"
            );
        }
    }

    #[test]
    fn the_order_of_drawing_follows_depth_not_the_slots() {
        let b = back_and_front();
        let swapped = still(&[(b.position[1], b.radius[1]), (b.position[0], b.radius[0])]);
        let (p, q) = (
            picture(&b, camera(0.0, 0.0)),
            picture(&swapped, camera(0.0, 0.0)),
        );
        let (one, other) = (p.compose(), q.compose());
        for y in 0..SIZE as i64 {
            for x in 0..SIZE as i64 {
                assert_eq!(one.at(x, y), other.at(x, y), "dot ({x}, {y})");
            }
        }
    }

    #[test]
    fn shadows_lie_on_the_floor_seen_from_above_and_are_not_drawn_from_below() {
        let b = still(&[(Vec3::new(0.5, 0.7, 0.5), 0.06)]);
        let above = picture(&b, camera(-35.0, 30.0));
        let dots = above.compose();
        let shadow = dots_of(&dots, Step::FloorBehind);
        assert!(!shadow.is_empty(), "a shadow from above");
        let under = dot(&above, Vec3::new(0.5, 0.0, 0.5));
        let r = 0.06 * above.projection.scale;
        assert!(
            shadow
                .iter()
                .all(|&(x, y)| { ((x - under.0) as f64).hypot((y - under.1) as f64) <= r + 1.0 }),
            "the shadow is around the point of the floor under the centre"
        );
        let below = picture(&b, camera(-35.0, -30.0)).compose();
        assert!(
            dots_of(&below, Step::FloorBehind).is_empty(),
            "no shadow from below"
        );
        let side = picture(&b, camera(-35.0, 0.0)).compose();
        assert!(dots_of(&side, Step::FloorBehind).is_empty(), "none edge-on");
    }

    #[test]
    fn the_floor_grid_is_behind_the_spheres_from_above_and_in_front_from_below() {
        // Near the floor, where no visible edge crosses it on the screen.
        let b = still(&[(Vec3::new(0.65, 0.15, 0.35), 0.1)]);
        let inside_disc = |p: &BoxPicture| {
            let c = dot(p, b.position[0]);
            let r = (b.radius[0] * p.projection.scale) as i64 - 1;
            let mut d = Vec::new();
            for y in c.1 - r..=c.1 + r {
                for x in c.0 - r..=c.0 + r {
                    if (x - c.0).pow(2) + (y - c.1).pow(2) <= r * r {
                        d.push((x, y));
                    }
                }
            }
            d
        };
        for (pitch, step) in [(30.0, Step::FloorBehind), (-30.0, Step::FloorInFront)] {
            let mut p = picture(&b, camera(-35.0, pitch));
            p.floor_grid = true;
            let dots = p.compose();
            assert!(
                !dots_of(&dots, step).is_empty(),
                "the grid at pitch {pitch}"
            );
            let gaps = inside_disc(&p)
                .into_iter()
                .filter(|&(x, y)| dots.at(x, y).is_none())
                .count();
            if pitch > 0.0 {
                assert_eq!(gaps, 0, "from above the sphere hides the grid");
            } else {
                assert!(gaps > 0, "from below the grid cuts across the sphere");
            }
        }
    }

    #[test]
    fn without_colour_the_shadow_is_a_half_tone_and_the_sphere_solid() {
        let b = still(&[(Vec3::new(0.5, 0.6, 0.5), 0.1)]);
        let mut p = picture(&b, camera(-35.0, 30.0));
        p.colour = false;
        let dots = p.compose();
        let shadow = dots_of(&dots, Step::FloorBehind);
        assert!(shadow.len() > 4);
        for &(x, y) in &shadow {
            for n in [(x + 1, y), (x, y + 1)] {
                assert_ne!(
                    step_at(&dots, n),
                    Some(Step::FloorBehind),
                    "{n:?} next to {x}, {y}"
                );
            }
        }
        let c = dot(&p, b.position[0]);
        for (x, y) in [c, (c.0 + 1, c.1), (c.0, c.1 + 1), (c.0 - 3, c.1 - 3)] {
            assert_eq!(step_at(&dots, (x, y)), Some(Step::Spheres), "({x}, {y})");
        }
        for x in 0..SIZE as i64 {
            for y in 0..SIZE as i64 {
                if let Some((colour, _)) = dots.at(x, y) {
                    assert_eq!(colour, palette::PLAIN);
                }
            }
        }
    }

    #[test]
    fn overlays_are_drawn_over_the_spheres_and_cut_through_them() {
        let b = bodies(&[(Vec3::new(0.5, 0.5, 0.5), Vec3::new(3.0, 0.0, 0.0), 0.1)]);
        let ghost = ([Vec3::new(0.5, 0.5, 0.5)], [0.1]);
        for colour in [true, false] {
            let mut p = picture(&b, camera(0.0, 0.0));
            (p.vectors, p.colour) = (true, colour);
            p.ghost = Some((&ghost.0, &ghost.1));
            let dots = p.compose();
            let c = dot(&p, b.position[0]);
            let r = (b.radius[0] * p.projection.scale) as i64;
            // Inside the disc the vector is a gap; outside, lit.
            assert_eq!(dots.at(c.0 + 3, c.1), None, "colour {colour}");
            assert_eq!(step_at(&dots, (c.0 + r + 3, c.1)), Some(Step::Vectors));
            // The ghost's cross above the centre, a gap in the sphere.
            assert_eq!(dots.at(c.0, c.1 - 1), None);
            assert_eq!(step_at(&dots, (c.0, c.1 - 2)), Some(Step::Spheres));
            assert!(!dots_of(&dots, Step::GhostOutlines).is_empty());
        }
    }

    #[test]
    fn a_painted_cell_takes_the_colour_of_what_was_drawn_last_in_it() {
        let b = back_and_front();
        let p = picture(&b, camera(0.0, 0.0));
        let dots = p.compose();
        let area = Rect::new(0, 0, (SIZE / 2) as u16, (SIZE / 4) as u16);
        let mut buf = Buffer::empty(area);
        Canvas::default()
            .marker(Marker::Braille)
            .x_bounds([0.0, (SIZE - 1) as f64])
            .y_bounds([0.0, (SIZE - 1) as f64])
            .paint(|ctx| ctx.draw(&p))
            .render(area, &mut buf);
        for c in [dot(&p, b.position[0]), dot(&p, b.position[1])] {
            let cell = &buf[((c.0 / 2) as u16, (c.1 / 4) as u16)];
            assert_eq!(cell.symbol(), "⣿");
            assert_eq!(Some(cell.fg), dots.at(c.0, c.1).map(|(c, _)| c));
        }
    }

    #[test]
    fn a_tiny_sphere_is_one_dot_and_a_huge_one_stays_on_the_grid() {
        let tiny = still(&[(Vec3::new(0.2, 0.5, 0.5), 0.001)]);
        let p = picture(&tiny, camera(0.0, 0.0));
        let dots = p.compose();
        let c = dot(&p, tiny.position[0]);
        assert_eq!(step_at(&dots, c), Some(Step::Spheres));
        assert_eq!(dots.at(c.0 + 1, c.1), None);
        let huge = still(&[(Vec3::new(0.51, 0.5, 0.5), 0.49)]);
        let mut cam = camera(0.0, 0.0);
        cam.zoom = 8.0;
        let dots = picture(&huge, cam).compose();
        let middle = SIZE as i64 / 2;
        assert_eq!(step_at(&dots, (middle, middle)), Some(Step::Spheres));
    }

    #[test]
    fn depth_classes_run_far_to_near_and_clamp() {
        let classes: Vec<usize> = [-1.0, -0.8, -0.1, 0.0, 0.3, 0.86, 1.0]
            .iter()
            .map(|&d| depth_class(depth_fraction(d)))
            .collect();
        assert!(classes.is_sorted(), "{classes:?}");
        assert_eq!(classes[0], 0);
        assert_eq!(classes[6], DEPTH_CLASSES - 1);
        assert_eq!(depth_class(f64::NAN), 0);
        let slice = 2.0 * DEPTH_HALF_RANGE / DEPTH_CLASSES as f64;
        assert!(slice < 0.25e-3, "a class is {slice} m deep");
    }

    #[test]
    fn a_preset_view_from_the_top_sees_the_floor_from_above() {
        let mut cam = Camera::default();
        cam.look(Preset::Top);
        let b = still(&[(Vec3::new(0.5, 0.5, 0.5), 0.05)]);
        assert_eq!(picture(&b, cam).floor_side(), FloorSide::Above);
        cam.look(Preset::Front);
        assert_eq!(picture(&b, cam).floor_side(), FloorSide::EdgeOn);
    }
}
