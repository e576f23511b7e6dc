//! What colour means: the speed or depth ramps, the legend's wording, and
//! NO_COLOR (<https://no-color.org>). Owns colours only.

use ratatui::style::{Color, Style};

/// What a sphere's colour shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colouring {
    /// Slow is cold (blue), fast is hot (red).
    Speed,
    /// Far is dim, near is bright.
    Depth,
}

impl Colouring {
    pub(crate) fn other(self) -> Self {
        match self {
            Colouring::Speed => Colouring::Depth,
            Colouring::Depth => Colouring::Speed,
        }
    }

    pub(crate) fn ramp(self) -> &'static [Color] {
        match self {
            Colouring::Speed => &SPEED_RAMP,
            Colouring::Depth => &DEPTH_RAMP,
        }
    }
}

const SPEED_RAMP: [Color; 6] = [
    Color::Blue,
    Color::Cyan,
    Color::Green,
    Color::Yellow,
    Color::LightRed,
    Color::Red,
];

const DEPTH_RAMP: [Color; 4] = [Color::DarkGray, Color::Blue, Color::Cyan, Color::White];

/// Box edges: hidden (behind the box) and visible.
pub(crate) const EDGE_HIDDEN: Color = Color::DarkGray;
pub(crate) const EDGE_VISIBLE: Color = Color::Gray;
/// The spheres' shadows on the floor (drawn as a half-tone of dots, so
/// they differ from the solid spheres without colour too).
pub(crate) const SHADOW: Color = Color::DarkGray;
/// The floor grid (`#`), dotted.
pub(crate) const FLOOR_GRID: Color = Color::DarkGray;
pub(crate) const TRAIL: Color = Color::Magenta;
pub(crate) const VECTOR: Color = Color::LightGreen;
/// The exact reference's ghost: a dim slate blue (256-colour palette),
/// apart from every ramp's colours and the edges' greys.
pub(crate) const GHOST: Color = Color::Indexed(103);
/// A sleeping sphere (`sim::sleep`), whatever the colouring: sand, a
/// hue outside both ramps and apart from the ghost (256-colour palette).
pub(crate) const ASLEEP: Color = Color::Indexed(137);
/// Contacts: a ring round each sphere in contact and its normal (a hue
/// outside both ramps).
pub(crate) const CONTACT: Color = Color::LightMagenta;
/// The selected spheres, their trails, vectors and outlines before a
/// correction.
pub(crate) const SELECTION: Color = Color::White;
/// Every other sphere while some are selected, so that the selected ones
/// stand out in their own colours: a grey darker than the edges' and the
/// far end of the depth ramp (256-colour palette).
pub(crate) const UNSELECTED: Color = Color::Indexed(237);
/// Keys in the footer and the help.
pub(crate) const KEY: Color = Color::Cyan;
/// What every colour becomes under NO_COLOR.
pub(crate) const PLAIN: Color = Color::Reset;

/// Whether the environment asks for no colour: NO_COLOR set and non-empty.
pub(crate) fn colour_allowed() -> bool {
    std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
}

/// The ramp colour for `t` in [0, 1] (clamped; NaN is the coldest).
#[inline]
#[cfg(test)]
pub(crate) fn ramp_colour(ramp: &[Color], t: f64) -> Color {
    ramp[ramp_index(ramp.len(), t)]
}

/// The index into a ramp of `n` colours for `t` in [0, 1] (clamped; NaN is
/// the coldest).
#[inline]
pub(crate) fn ramp_index(n: usize, t: f64) -> usize {
    let k = (t.clamp(0.0, 1.0) * n as f64) as usize;
    k.min(n.saturating_sub(1))
}

/// `style` with a foreground colour, or plain under NO_COLOR.
pub(crate) fn fg(colour: bool, c: Color) -> Style {
    if colour {
        Style::default().fg(c)
    } else {
        Style::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_covers_its_ends_and_clamps() {
        let r = Colouring::Speed.ramp();
        assert_eq!(ramp_colour(r, 0.0), Color::Blue);
        assert_eq!(ramp_colour(r, 1.0), Color::Red);
        assert_eq!(ramp_colour(r, 7.0), Color::Red);
        assert_eq!(ramp_colour(r, -1.0), Color::Blue);
        assert_eq!(ramp_colour(r, f64::NAN), Color::Blue);
    }
}
