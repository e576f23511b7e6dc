//! Energy over time: the chart of the energy log (`energy_log.rs`) in the
//! side panel. Drawing never steps the world.

use super::energy_log::{EnergyLog, Sample};
use super::numbers::format_energy;
use super::palette::fg;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Chart, Dataset, GraphType, Widget};

const TOTAL: Color = Color::White;
const KINETIC: Color = Color::LightRed;
const POTENTIAL: Color = Color::LightBlue;

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
    let (t0, t1) = match log.ends() {
        Some((a, b)) if b.time > a.time => (a.time, b.time),
        Some((a, _)) => (a.time, a.time + 1.0),
        None => (0.0, 1.0),
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
            "kinetic" if no_potential => "total = kinetic,",
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;

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
            pingpong.contains("energy: total = kinetic, potential 0"),
            "{pingpong}"
        );
        // Without colour, with the mark of the line that is seen (the
        // kinetic one, drawn over the total).
        let pingpong = title(Lesson::Pingpong, false);
        assert!(
            pingpong.contains("energy: •total = kinetic, █potential 0"),
            "{pingpong}"
        );
        let gravity = title(Lesson::Gravity, true);
        assert!(gravity.contains("total kinetic potential"), "{gravity}");
    }
}
