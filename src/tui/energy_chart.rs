//! Energy over time: the log of kinetic, potential and total energy after
//! each step, and its chart in the side panel.
//!
//! Owns the samples; the app records one per step and drops those after a
//! restored step when stepping back. Drawing never steps the world.

use super::palette::fg;
use crate::sim::{Vec3, World};
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Chart, Dataset, GraphType, Widget};
use std::collections::VecDeque;

const TOTAL: Color = Color::White;
const KINETIC: Color = Color::LightRed;
const POTENTIAL: Color = Color::LightBlue;

/// Samples kept: the chart shows at most this many steps.
pub(crate) const SAMPLES: usize = 1200;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub steps: u64,
    pub time: f64,
    pub kinetic: f64,
    pub potential: f64,
    pub total: f64,
    /// Sum of `m v`, kg m/s.
    pub momentum: Vec3,
}

impl Sample {
    /// `world`'s step, time, energies and momentum now.
    pub fn of(world: &World) -> Self {
        let d = world.diagnostics();
        Self {
            steps: d.steps,
            time: d.time,
            kinetic: d.kinetic_energy,
            potential: d.potential_energy,
            total: d.total_energy,
            momentum: d.momentum,
        }
    }
}

#[derive(Clone, Debug)]
pub struct EnergyLog {
    samples: VecDeque<Sample>,
}

impl EnergyLog {
    /// A log holding `world`'s current energies.
    pub fn new(world: &World) -> Self {
        let mut log = Self {
            samples: VecDeque::with_capacity(SAMPLES),
        };
        log.record(world);
        log
    }

    pub(crate) fn record(&mut self, world: &World) {
        if self.samples.len() == SAMPLES {
            self.samples.pop_front();
        }
        self.samples.push_back(Sample::of(world));
    }

    /// Take the newest sample again: the energies of the same state
    /// changed (a new gravity changes the potential energy).
    pub(crate) fn record_again(&mut self, world: &World) {
        self.samples.pop_back();
        self.record(world);
    }

    /// The newest sample, if it is of `world`'s present step.
    pub(crate) fn now(&self, world: &World) -> Option<&Sample> {
        self.samples.back().filter(|s| s.steps == world.steps)
    }

    /// Forget samples taken after step `steps`.
    pub(crate) fn truncate_after(&mut self, steps: u64) {
        while self.samples.back().is_some_and(|s| s.steps > steps) {
            self.samples.pop_back();
        }
    }

    pub fn len(&self) -> usize {
        self.samples.len()
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    pub fn samples(&self) -> impl Iterator<Item = &Sample> {
        self.samples.iter()
    }
}

/// The chart of `log` inside `block`.
pub(crate) fn render_energy_chart(log: &EnergyLog, colour: bool, area: Rect, buf: &mut Buffer) {
    let series = |f: fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        log.samples().map(|s| (s.time, f(s))).collect()
    };
    let (kinetic, potential, total) = (
        series(|s| s.kinetic),
        series(|s| s.potential),
        series(|s| s.total),
    );
    let (t0, t1) = match (log.samples.front(), log.samples.back()) {
        (Some(a), Some(b)) if b.time > a.time => (a.time, b.time),
        (Some(a), _) => (a.time, a.time + 1.0),
        _ => (0.0, 1.0),
    };
    let (mut lo, mut hi) = log
        .samples()
        .flat_map(|s| [s.kinetic, s.potential, s.total])
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        (lo, hi) = (0.0, 1.0);
    }
    lo = lo.min(0.0);
    let pad = ((hi - lo) * 0.05).max(hi.abs() * 0.05).max(1e-9);
    hi += pad;
    let series_style = [
        ("total", TOTAL, Marker::Braille),
        ("kinetic", KINETIC, Marker::Dot),
        ("potential", POTENTIAL, Marker::Block),
    ];
    // Without colour the series differ by marker, and the title says which.
    // Without gravity the potential energy is 0 throughout and the total
    // line lies on the kinetic one: the title says so, as the chart cannot.
    let no_potential = log.samples().all(|s| s.potential == 0.0);
    let mut title = vec![Span::raw(" energy: ")];
    for (name, c, marker) in series_style {
        let mark = match marker {
            Marker::Dot if !colour => "•",
            Marker::Block if !colour => "█",
            _ => "",
        };
        // The kinetic line is drawn over the total one: when they lie
        // together, the title names them with the kinetic line's mark.
        let shown = match name {
            "total" if no_potential => continue,
            "kinetic" if no_potential => "total = kinetic",
            "potential" if no_potential => "potential 0",
            _ => name,
        };
        title.push(Span::styled(format!("{mark}{shown} "), fg(colour, c)));
    }
    let block = Block::bordered().title(Line::from(title));
    let dataset = |name: &'static str, data, c: Color, marker| {
        Dataset::default()
            .name(name)
            .marker(if colour { Marker::Braille } else { marker })
            .graph_type(GraphType::Line)
            .style(fg(colour, c))
            .data(data)
    };
    let label = |v: f64| Span::raw(format_energy(v));
    let chart = Chart::new(vec![
        dataset("total", &total, TOTAL, Marker::Braille),
        dataset("kinetic", &kinetic, KINETIC, Marker::Dot),
        dataset("potential", &potential, POTENTIAL, Marker::Block),
    ])
    .block(block)
    .x_axis(
        Axis::default()
            .bounds([t0, t1])
            .labels([
                Span::raw(format!("{t0:.1} s")),
                Span::raw(format!("{t1:.1} s")),
            ])
            .style(Style::default()),
    )
    .y_axis(
        Axis::default()
            .bounds([lo, hi])
            .labels([label(lo), label(hi)]),
    )
    .legend_position(None);
    chart.render(area, buf);
}

/// An energy in joules, about four significant digits.
pub(crate) fn format_energy(v: f64) -> String {
    energy_at_scale(v, v.abs(), 0)
}

/// Two energies to compare (before and after), in one format: the one
/// [`format_energy`] gives the larger, so that `0.0101 J -> 0.0099 J`
/// does not read `0.0101 J -> 9.921e-3 J`.
///
/// Two energies that differ get the figures that show it (up to six
/// more), so that a collision's loss never reads as none.
pub(crate) fn format_energies(a: f64, b: f64) -> (String, String) {
    let larger = a.abs().max(b.abs());
    let at = |more| {
        (
            energy_at_scale(a, larger, more),
            energy_at_scale(b, larger, more),
        )
    };
    // Two that differ by rounding alone (an elastic collision's) read as
    // equal, to the usual figures.
    (0..=MORE_FIGURES)
        .map(at)
        .find(|(x, y)| x != y)
        .unwrap_or_else(|| at(0))
}

/// Figures [`format_energies`] may add to tell two energies apart.
const MORE_FIGURES: usize = 6;

/// `v` in joules, in the format [`format_energy`] gives an energy of size
/// `scale` (with `more` figures): decimals for everyday sizes, else
/// exponent form.
fn energy_at_scale(v: f64, scale: f64, more: usize) -> String {
    if v == 0.0 {
        "0 J".into()
    } else if (0.01..1e4).contains(&scale) {
        let digits = (3 - scale.log10().floor() as i32).clamp(0, 4) as usize + more;
        format!("{v:.digits$} J")
    } else {
        let digits = 3 + more;
        format!("{v:.digits$e} J")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;

    #[test]
    fn energies_compared_share_one_format() {
        assert_eq!(
            format_energies(0.0101, 0.009921),
            ("0.0101 J".to_string(), "0.0099 J".to_string())
        );
        assert_eq!(
            format_energies(3.137, 3.088),
            ("3.137 J".to_string(), "3.088 J".to_string())
        );
        assert_eq!(
            format_energies(1.482, 0.0),
            ("1.482 J".to_string(), "0 J".to_string())
        );
        assert_eq!(
            format_energies(2e-3, 1e-3),
            ("2.000e-3 J".to_string(), "1.000e-3 J".to_string())
        );
        // A loss below the usual figures still shows.
        assert_eq!(
            format_energies(0.036012, 0.035982),
            ("0.03601 J".to_string(), "0.03598 J".to_string())
        );
        assert_eq!(
            format_energies(0.0360121, 0.0360118),
            ("0.0360121 J".to_string(), "0.0360118 J".to_string())
        );
        assert_eq!(
            format_energies(2.0e-3, 2.0000004e-3),
            ("2.0000000e-3 J".to_string(), "2.0000004e-3 J".to_string())
        );
        assert_eq!(
            format_energies(1.0, 1.0),
            ("1.000 J".to_string(), "1.000 J".to_string())
        );
        // An elastic collision's: equal but for rounding.
        assert_eq!(
            format_energies(3.137, 3.137 + 4.5e-16),
            ("3.137 J".to_string(), "3.137 J".to_string())
        );
    }

    #[test]
    fn the_log_keeps_its_newest_samples_and_truncates_on_step_back() {
        let mut world = Lesson::Pingpong.scene().build().unwrap();
        let mut log = EnergyLog::new(&world);
        for _ in 0..SAMPLES + 5 {
            world.step();
            log.record(&world);
        }
        assert_eq!(log.len(), SAMPLES);
        log.truncate_after(world.steps - 3);
        assert_eq!(log.samples().last().unwrap().steps, world.steps - 3);
        let ke = log.samples().next().unwrap().kinetic;
        assert_eq!(ke, 0.5, "m v^2 / 2 with m = 1 kg, v = 1 m/s");
    }

    #[test]
    fn the_title_says_when_the_total_lies_on_the_kinetic_line() {
        let title = |lesson: Lesson, colour: bool| {
            let mut world = lesson.scene().build().unwrap();
            let mut log = EnergyLog::new(&world);
            for _ in 0..20 {
                world.step();
                log.record(&world);
            }
            let area = Rect::new(0, 0, 60, 10);
            let mut buf = Buffer::empty(area);
            render_energy_chart(&log, colour, area, &mut buf);
            (0..area.width)
                .map(|x| buf[(x, 0)].symbol().to_string())
                .collect::<String>()
        };
        let pingpong = title(Lesson::Pingpong, true);
        assert!(
            pingpong.contains("energy: total = kinetic potential 0"),
            "{pingpong}"
        );
        // Without colour, with the mark of the line that is seen (the
        // kinetic one, drawn over the total).
        let pingpong = title(Lesson::Pingpong, false);
        assert!(
            pingpong.contains("energy: •total = kinetic █potential 0"),
            "{pingpong}"
        );
        let gravity = title(Lesson::Gravity, true);
        assert!(gravity.contains("total kinetic potential"), "{gravity}");
    }

    #[test]
    fn energies_read_with_four_significant_digits() {
        assert_eq!(format_energy(0.5), "0.5000 J");
        assert_eq!(format_energy(12.634), "12.63 J");
        assert_eq!(format_energy(1234.4), "1234 J");
        assert_eq!(format_energy(-0.0012345), "-1.234e-3 J");
        assert_eq!(format_energy(0.0), "0 J");
    }
}
