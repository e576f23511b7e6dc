//! The surface a braille picture is composed on before it is painted.
//!
//! Braille gives 2x4 dots per cell and one colour per cell, and the
//! canvas's painter can only turn dots on. A [`DotBuffer`] can also turn
//! dots off, so a nearer shape can hide a farther one: per dot, off or lit
//! with an [`Ink`] (a colour, a tag saying what drew it, and whether it
//! fills a surface); per cell, the ink that last claimed it, which is the
//! colour the whole cell is painted in. [`DotBuffer::paint`] hands the lit
//! dots to the painter at the end.
//!
//! Owns dots and how they are marked (filled discs with a cleared rim,
//! half-tone ellipses, dashed lines, circle outlines); it knows nothing of
//! the box, the world or the order things are drawn in (`box_view` does).

use ratatui::style::Color;
use ratatui::widgets::canvas::Painter;

/// A colour, the tag of what uses it and whether it fills a surface, as
/// stored in a [`DotBuffer`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Ink(u8);

#[derive(Clone, Copy, Debug, PartialEq)]
struct InkDef<T> {
    colour: Color,
    tag: T,
    surface: bool,
}

/// How a dot is marked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mark {
    /// Lit; the cell takes the ink's colour.
    Solid,
    /// On top, see-through: a dot of a surface (a disc) is cut, so the
    /// mark shows on a filled area without colour too; any other dot is
    /// lit. The cell takes the ink's colour.
    Overlay,
    /// Like `Overlay`, but a cell that holds something keeps its colour:
    /// thin lines in front of surfaces cut them without recolouring them.
    Faint,
}

/// How a line's dots alternate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dash {
    Solid,
    /// Two dots on, two off.
    Dashed,
    /// Every other dot.
    Dotted,
}

impl Dash {
    #[inline]
    fn on(self, k: usize) -> bool {
        match self {
            Dash::Solid => true,
            Dash::Dashed => k % 4 < 2,
            Dash::Dotted => k.is_multiple_of(2),
        }
    }
}

/// A picture being composed: dots that can be lit and cleared, one ink
/// per dot and the colour of each braille cell. `T` tags each ink with
/// what drew it. Dots off the grid are dropped.
#[derive(Clone, Debug)]
pub(crate) struct DotBuffer<T> {
    width: usize,
    height: usize,
    /// Cells per row.
    columns: usize,
    /// Per dot, row by row: 0 off, else 1 + the index of its ink.
    dots: Vec<u8>,
    /// Per cell: the ink that last claimed it (0: nothing was lit there).
    cell_ink: Vec<u8>,
    inks: Vec<InkDef<T>>,
}

impl<T: Copy + PartialEq> DotBuffer<T> {
    pub fn new(width: usize, height: usize) -> Self {
        let columns = width.div_ceil(2);
        Self {
            width,
            height,
            columns,
            dots: vec![0; width * height],
            cell_ink: vec![0; columns * height.div_ceil(4)],
            inks: Vec::new(),
        }
    }

    /// The ink of `colour` for lines and dots tagged `tag`.
    pub(crate) fn ink(&mut self, colour: Color, tag: T) -> Ink {
        self.intern(InkDef {
            colour,
            tag,
            surface: false,
        })
    }

    /// The ink of `colour` for filled surfaces tagged `tag`: marks in
    /// front cut through them.
    pub(crate) fn surface_ink(&mut self, colour: Color, tag: T) -> Ink {
        self.intern(InkDef {
            colour,
            tag,
            surface: true,
        })
    }

    /// At most 255 distinct inks; beyond that the last is shared.
    fn intern(&mut self, def: InkDef<T>) -> Ink {
        if let Some(k) = self.inks.iter().position(|&i| i == def) {
            return Ink(k as u8 + 1);
        }
        if self.inks.len() < usize::from(u8::MAX) {
            self.inks.push(def);
        }
        Ink(self.inks.len() as u8)
    }

    /// The colour and tag of the ink that lit the dot, if it is lit.
    #[cfg(test)]
    pub fn at(&self, x: i64, y: i64) -> Option<(Color, T)> {
        let d = self.dots[self.index(x, y)?];
        (d != 0).then(|| {
            let i = self.inks[usize::from(d) - 1];
            (i.colour, i.tag)
        })
    }

    #[cfg(test)]
    pub(crate) fn width(&self) -> usize {
        self.width
    }

    #[cfg(test)]
    pub(crate) fn height(&self) -> usize {
        self.height
    }

    #[inline]
    fn index(&self, x: i64, y: i64) -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height)
            .then(|| y as usize * self.width + x as usize)
    }

    #[inline]
    fn cell(&self, i: usize) -> usize {
        let (x, y) = (i % self.width, i / self.width);
        (y / 4) * self.columns + x / 2
    }

    #[inline]
    pub(crate) fn mark(&mut self, x: i64, y: i64, ink: Ink, how: Mark) {
        let Some(i) = self.index(x, y) else {
            return;
        };
        let cell = self.cell(i);
        let d = self.dots[i];
        let on_surface = d != 0 && self.inks[usize::from(d) - 1].surface;
        match how {
            Mark::Solid => {
                self.dots[i] = ink.0;
                self.cell_ink[cell] = ink.0;
            }
            Mark::Overlay | Mark::Faint if on_surface => self.dots[i] = 0,
            Mark::Overlay => {
                self.dots[i] = ink.0;
                self.cell_ink[cell] = ink.0;
            }
            Mark::Faint => {
                self.dots[i] = ink.0;
                if self.cell_ink[cell] == 0 {
                    self.cell_ink[cell] = ink.0;
                }
            }
        }
    }

    /// A disc stamped about the dot `(cx, cy)`: its rim cleared, its
    /// inside lit.
    pub(crate) fn disc(&mut self, (cx, cy): (i64, i64), stamp: &DiscStamp, ink: Ink) {
        let reach = stamp.rows.len() as i64 - 1;
        let (w, h) = (self.width as i64, self.height as i64);
        if cx.saturating_add(reach) < 0 || cx.saturating_sub(reach) >= w {
            return;
        }
        let y0 = cy.saturating_sub(reach).max(0);
        let y1 = cy.saturating_add(reach).min(h - 1);
        for y in y0..=y1 {
            let (outer, inner) = stamp.rows[(y - cy).unsigned_abs() as usize];
            let (o0, o1) = ((cx - outer).max(0), (cx + outer).min(w - 1));
            if o0 > o1 {
                continue;
            }
            let (f0, f1) = (cx - inner, cx + inner);
            let (y, o0, o1) = (y as usize, o0 as usize, o1 as usize);
            let row = &mut self.dots[y * self.width..][..=o1];
            let cells = &mut self.cell_ink[(y / 4) * self.columns..][..=o1 / 2];
            // One pass (spans of a few dots: calls to memset cost more).
            for x in o0..=o1 {
                if (f0..=f1).contains(&(x as i64)) {
                    row[x] = ink.0;
                    cells[x / 2] = ink.0;
                } else {
                    row[x] = 0;
                }
            }
        }
    }

    /// A half-tone ellipse (every other dot, in a checkerboard fixed to the
    /// screen): the points `centre + a u + b v` with `a^2 + b^2 <= 1`. At
    /// least the dot nearest the centre, so a very flat one still shows.
    pub(crate) fn half_tone_ellipse(
        &mut self,
        (cx, cy): (f64, f64),
        u: (f64, f64),
        v: (f64, f64),
        ink: Ink,
    ) {
        let det = u.0 * v.1 - u.1 * v.0;
        if !(det.abs() > 1e-12 && cx.is_finite() && cy.is_finite()) {
            return;
        }
        let (hx, hy) = (u.0.hypot(v.0), u.1.hypot(v.1));
        let clip = |v: f64, n: usize| v.clamp(-1.0, n as f64) as i64;
        let (x0, x1) = (
            clip((cx - hx).ceil(), self.width),
            clip((cx + hx).floor(), self.width),
        );
        let (y0, y1) = (
            clip((cy - hy).ceil(), self.height),
            clip((cy + hy).floor(), self.height),
        );
        let mut lit = false;
        for y in y0..=y1 {
            let dy = y as f64 - cy;
            for x in x0..=x1 {
                if (x + y).rem_euclid(2) != 0 {
                    continue;
                }
                let dx = x as f64 - cx;
                let (a, b) = ((dx * v.1 - dy * v.0) / det, (u.0 * dy - u.1 * dx) / det);
                if a * a + b * b <= 1.0 {
                    self.mark(x, y, ink, Mark::Solid);
                    lit = true;
                }
            }
        }
        if !lit {
            self.mark(cx.round() as i64, cy.round() as i64, ink, Mark::Solid);
        }
    }

    /// A straight line between two dot positions.
    pub(crate) fn line(&mut self, a: (f64, f64), b: (f64, f64), ink: Ink, how: Mark, dash: Dash) {
        let far = 4.0 * (self.width + self.height) as f64;
        for (k, (x, y)) in LinePoints::new(a, b, far).enumerate() {
            if dash.on(k) {
                self.mark(x, y, ink, how);
            }
        }
    }

    /// Midpoint circle outline of radius `r` dots; `dashed` leaves out
    /// every other step of it.
    pub(crate) fn outline(
        &mut self,
        (cx, cy): (i64, i64),
        r: i64,
        ink: Ink,
        how: Mark,
        dashed: bool,
    ) {
        let (mut x, mut y, mut err) = (r, 0i64, 1 - r);
        while x >= y {
            if !(dashed && y % 2 == 1) {
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
                    self.mark(cx + px, cy + py, ink, how);
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

    /// Paint the lit dots, each cell in one colour: that of the ink which
    /// last claimed it, or, when its dots were cleared since, of a dot
    /// still lit there.
    pub(crate) fn paint(&self, painter: &mut Painter) {
        for row in 0..self.height.div_ceil(4) {
            let ys = row * 4..(row * 4 + 4).min(self.height);
            for col in 0..self.columns {
                let claimed = self.cell_ink[row * self.columns + col];
                if claimed == 0 {
                    continue;
                }
                let xs = col * 2..(col * 2 + 2).min(self.width);
                let (mut chosen, mut any) = (0, 0);
                for y in ys.clone() {
                    for x in xs.clone() {
                        let d = self.dots[y * self.width + x];
                        if d != 0 {
                            any = d;
                            if d == claimed {
                                chosen = d;
                            }
                        }
                    }
                }
                if any == 0 {
                    continue;
                }
                let ink = if chosen != 0 { chosen } else { any };
                let colour = self.inks[usize::from(ink) - 1].colour;
                for y in ys.clone() {
                    for x in xs.clone() {
                        if self.dots[y * self.width + x] != 0 {
                            painter.paint(x, y, colour);
                        }
                    }
                }
            }
        }
    }
}

/// A disc's shape on the dot grid, about a centre dot: per row away from
/// the centre, the half-widths of the ring cleared and of the disc lit
/// (negative: none). Computed once per radius in quarter dots.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DiscStamp {
    rows: Vec<(i64, i64)>,
}

impl DiscStamp {
    /// Radius `r` dots, rim `rim` dots wide.
    pub fn new(r: f64, rim: f64) -> Self {
        let outer = r + rim;
        let half = |radius: f64, dy: f64| {
            let h2 = radius * radius - dy * dy;
            if h2 < 0.0 {
                -1
            } else {
                h2.sqrt().floor() as i64
            }
        };
        let rows = (0..=outer.floor() as i64)
            .map(|dy| (half(outer, dy as f64), half(r, dy as f64)))
            .collect();
        Self { rows }
    }
}

/// The dot nearest a coordinate (saturating), without a call into the
/// maths library (which `f64::round` makes on a baseline x86-64 target).
#[inline]
pub(crate) fn nearest_dot(v: f64) -> i64 {
    let u = v + 0.5;
    let t = u as i64;
    t.saturating_sub(i64::from((t as f64) > u))
}

/// The dots of a straight line between two dot positions (Bresenham), both
/// ends included; none when an end is not finite or lies `far` or more
/// off the grid.
struct LinePoints {
    at: (i64, i64),
    end: (i64, i64),
    d: (i64, i64),
    s: (i64, i64),
    err: i64,
    done: bool,
}

impl LinePoints {
    fn new((x0, y0): (f64, f64), (x1, y1): (f64, f64), far: f64) -> Self {
        let done = ![x0, y0, x1, y1]
            .iter()
            .all(|v| v.is_finite() && v.abs() < far);
        let (at, end) = if done {
            ((0, 0), (0, 0))
        } else {
            (
                (x0.round() as i64, y0.round() as i64),
                (x1.round() as i64, y1.round() as i64),
            )
        };
        let d = ((end.0 - at.0).abs(), -(end.1 - at.1).abs());
        let s = (
            if at.0 < end.0 { 1 } else { -1 },
            if at.1 < end.1 { 1 } else { -1 },
        );
        Self {
            at,
            end,
            d,
            s,
            err: d.0 + d.1,
            done,
        }
    }
}

impl Iterator for LinePoints {
    type Item = (i64, i64);

    fn next(&mut self) -> Option<(i64, i64)> {
        if self.done {
            return None;
        }
        let p = self.at;
        if p == self.end {
            self.done = true;
            return Some(p);
        }
        let e2 = 2 * self.err;
        if e2 >= self.d.1 {
            self.err += self.d.1;
            self.at.0 += self.s.0;
        }
        if e2 <= self.d.0 {
            self.err += self.d.0;
            self.at.1 += self.s.1;
        }
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn buffer() -> DotBuffer<&'static str> {
        DotBuffer::new(40, 40)
    }

    fn lit(dots: &DotBuffer<&'static str>) -> usize {
        let mut n = 0;
        for y in 0..dots.height() as i64 {
            for x in 0..dots.width() as i64 {
                n += usize::from(dots.at(x, y).is_some());
            }
        }
        n
    }

    #[test]
    fn a_disc_is_lit_inside_and_cleared_on_its_rim() {
        let mut dots = buffer();
        let under = dots.ink(Color::Blue, "under");
        for y in 0..40 {
            dots.line(
                (0.0, y as f64),
                (39.0, y as f64),
                under,
                Mark::Solid,
                Dash::Solid,
            );
        }
        let disc = dots.surface_ink(Color::Red, "disc");
        dots.disc((20, 20), &DiscStamp::new(5.0, 1.0), disc);
        for (x, y, what) in [
            (20, 20, Some("disc")),
            (25, 20, Some("disc")),
            (20, 15, Some("disc")),
            (26, 20, None),
            (14, 20, None),
            (20, 26, None),
            (27, 20, Some("under")),
        ] {
            assert_eq!(dots.at(x, y).map(|(_, t)| t), what, "({x}, {y})");
        }
    }

    #[test]
    fn marks_in_front_cut_surfaces_and_light_everything_else() {
        let mut dots = buffer();
        let disc = dots.surface_ink(Color::Red, "disc");
        let wire = dots.ink(Color::Gray, "wire");
        dots.disc((10, 10), &DiscStamp::new(4.0, 1.0), disc);
        dots.mark(3, 3, wire, Mark::Solid);
        let over = dots.ink(Color::Green, "over");
        for x in [10, 3, 30] {
            dots.mark(x, if x == 3 { 3 } else { 10 }, over, Mark::Overlay);
        }
        assert_eq!(dots.at(10, 10), None, "a disc's dot is cut");
        assert_eq!(
            dots.at(3, 3),
            Some((Color::Green, "over")),
            "a line's is lit over"
        );
        assert_eq!(
            dots.at(30, 10),
            Some((Color::Green, "over")),
            "an empty one lit"
        );
        let faint = dots.ink(Color::DarkGray, "faint");
        dots.mark(11, 10, faint, Mark::Faint);
        assert_eq!(dots.at(11, 10), None);
    }

    #[test]
    fn lines_include_both_ends_and_dash() {
        let lit_by = |dash: Dash, to: (f64, f64)| {
            let mut dots = buffer();
            let ink = dots.ink(Color::Gray, "line");
            dots.line((2.0, 5.0), to, ink, Mark::Solid, dash);
            lit(&dots)
        };
        assert_eq!(lit_by(Dash::Solid, (9.0, 5.0)), 8);
        assert_eq!(lit_by(Dash::Dashed, (9.0, 5.0)), 4);
        assert_eq!(lit_by(Dash::Dotted, (9.0, 5.0)), 4);
        assert_eq!(
            lit_by(Dash::Solid, (f64::NAN, 5.0)),
            0,
            "to a point not finite"
        );
        assert_eq!(lit_by(Dash::Solid, (1e12, 5.0)), 0, "to a point far off");
    }

    #[test]
    fn a_half_tone_ellipse_lights_every_other_dot_and_at_least_one() {
        let ellipse = |centre: (f64, f64), v: (f64, f64)| {
            let mut dots = buffer();
            let ink = dots.ink(Color::DarkGray, "shadow");
            dots.half_tone_ellipse(centre, (6.0, 0.0), v, ink);
            dots
        };
        let dots = ellipse((20.0, 20.0), (0.0, 3.0));
        let n = lit(&dots);
        assert!((20..=40).contains(&n), "{n} dots, about pi 6 3 / 2");
        assert!(dots.at(20, 20).is_some() && dots.at(21, 20).is_none());
        assert_eq!(
            lit(&ellipse((20.3, 20.6), (0.0, 0.1))),
            1,
            "a flat one still shows"
        );
    }

    #[test]
    fn nearest_dot_rounds_half_up_and_saturates() {
        assert_eq!(nearest_dot(2.5), 3);
        assert_eq!(nearest_dot(2.49), 2);
        assert_eq!(nearest_dot(-2.5), -2);
        assert_eq!(nearest_dot(-2.51), -3);
        assert_eq!(nearest_dot(1e300), i64::MAX);
        assert_eq!(nearest_dot(-1e300), i64::MIN);
    }
}
