//! The chart screen: the work-precision chart of the lesson shown (log10
//! RMS position error against log10 wall time per simulated second, one
//! series per method), from `crate::study::work_precision`.
//!
//! The sweep takes seconds, so it runs once per lesson, on demand, in a
//! background thread; the result comes back over a channel and is kept for
//! the rest of the session. The app polls for it between frames, so the
//! view keeps running meanwhile.
//!
//! Owns the per-lesson results and the chart's drawing; it never changes
//! the world.

use super::app::App;
use super::palette::fg;
use super::panel::wrap;
use crate::scene::Lesson;
use crate::study::charts::{Series, work_precision_series};
use crate::study::sweep::{Plan, Row};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Stylize};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Chart, Clear, Dataset, GraphType, Paragraph, Widget, Wrap};
use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// What computes a lesson's rows (the study's sweep; tests give their own).
pub type Source = fn(Lesson) -> Result<Vec<Row>, String>;

#[derive(Debug)]
pub enum ChartData {
    Computing(Receiver<Result<Vec<Row>, String>>),
    Ready(Vec<Row>),
    Failed(String),
}

/// The results per lesson, computed at most once each.
#[derive(Debug)]
pub struct WorkCharts {
    source: Source,
    data: Vec<(Lesson, ChartData)>,
    /// Computations started so far.
    pub started: usize,
}

impl WorkCharts {
    pub fn new(source: Source) -> Self {
        Self {
            source,
            data: Vec::new(),
            started: 0,
        }
    }

    pub fn get(&self, lesson: Lesson) -> Option<&ChartData> {
        self.data.iter().find(|(l, _)| *l == lesson).map(|(_, d)| d)
    }

    /// Start computing `lesson`'s rows in a background thread unless they
    /// are known or on their way.
    pub fn request(&mut self, lesson: Lesson) {
        if self.get(lesson).is_some() {
            return;
        }
        let (tx, rx) = channel();
        let source = self.source;
        let spawned = std::thread::Builder::new()
            .name(format!("work-precision {}", lesson.name()))
            .spawn(move || {
                let _ = tx.send(compute(source, lesson));
            });
        let data = match spawned {
            Ok(_) => ChartData::Computing(rx),
            Err(e) => ChartData::Failed(format!("cannot start the computation: {e}")),
        };
        self.started += 1;
        self.data.push((lesson, data));
    }

    /// Rows computed elsewhere (kept as if computed here).
    pub fn insert(&mut self, lesson: Lesson, rows: Vec<Row>) {
        self.data.retain(|(l, _)| *l != lesson);
        self.data.push((lesson, ChartData::Ready(rows)));
    }

    /// Take in finished computations; true if any finished.
    pub fn poll(&mut self) -> bool {
        let mut changed = false;
        for (_, data) in &mut self.data {
            if let ChartData::Computing(rx) = data {
                let done = match rx.try_recv() {
                    Ok(Ok(rows)) => ChartData::Ready(rows),
                    Ok(Err(e)) => ChartData::Failed(e),
                    Err(TryRecvError::Empty) => continue,
                    Err(TryRecvError::Disconnected) => {
                        ChartData::Failed("the computation stopped without a result".into())
                    }
                };
                *data = done;
                changed = true;
            }
        }
        changed
    }

    /// Whether a computation is under way.
    pub fn busy(&self) -> bool {
        self.data
            .iter()
            .any(|(_, d)| matches!(d, ChartData::Computing(_)))
    }
}

/// `source(lesson)`, with a panic turned into an error result (the event
/// loop's panic hook leaves the screen alone for threads other than its
/// own).
fn compute(source: Source, lesson: Lesson) -> Result<Vec<Row>, String> {
    std::panic::catch_unwind(|| source(lesson)).unwrap_or_else(|payload| {
        let why = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        Err(format!("the computation panicked: {why}"))
    })
}

/// Colours of the methods, in `Integrator::ALL` order, and the markers
/// that tell them apart under NO_COLOR.
const COLOURS: [Color; 5] = [
    Color::LightRed,
    Color::Yellow,
    Color::LightGreen,
    Color::LightCyan,
    Color::LightMagenta,
];
const MARKERS: [(Marker, &str); 5] = [
    (Marker::Dot, "•"),
    (Marker::Block, "█"),
    (Marker::HalfBlock, "▀"),
    (Marker::Bar, "▄"),
    (Marker::Braille, "⣿"),
];

/// Most tick labels on an axis of `rows` rows or columns.
fn ticks(lo: f64, hi: f64, room: usize) -> (f64, f64, Vec<Span<'static>>) {
    let (mut lo, mut hi) = (lo.floor(), hi.ceil());
    if hi - lo < 1.0 {
        hi = lo + 1.0;
    }
    let most = room.max(2);
    let span = (hi - lo) as usize;
    let step = span.div_ceil(most - 1).max(1);
    let count = span.div_ceil(step);
    hi = lo + (count * step) as f64;
    if !hi.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    let labels = (0..=count)
        .map(|k| Span::raw(format!("1e{}", lo as i64 + (k * step) as i64)))
        .collect();
    (lo, hi, labels)
}

fn bounds(series: &[Series], pick: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    series
        .iter()
        .flat_map(|s| s.points.iter())
        .map(pick)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

/// The chart screen over `area`.
pub fn render_work_chart(app: &App, area: Rect, buf: &mut Buffer) {
    Clear.render(area, buf);
    let title = match app.lesson {
        Some(l) => format!(" work against precision: {} lesson ", l.name()),
        None => " work against precision ".to_string(),
    };
    let block = Block::bordered()
        .title(Line::from(title.bold()))
        .title_bottom(Line::from(" c or Esc closes ").right_aligned());
    let inner = block.inner(area);
    block.render(area, buf);
    let Some(lesson) = app.lesson else {
        say_in(
            vec![
                Line::from("The chart covers the lessons only.".bold()),
                Line::from(format!(
                    "This is the scene {} from {}: its work-precision data would need an \
                     exact reference and a sweep made for it. Press 1, 2 or 3 to open a \
                     lesson, then c.",
                    app.frame.scene.name, app.frame.scene.origin
                )),
            ],
            inner,
            buf,
        );
        return;
    };
    let rows = match app.charts.get(lesson) {
        Some(ChartData::Ready(rows)) => rows,
        Some(ChartData::Failed(e)) => {
            say_in(
                vec![Line::from(format!("The sweep failed: {e}"))],
                inner,
                buf,
            );
            return;
        }
        _ => {
            say_in(
                vec![
                    Line::from("computing...".bold()),
                    Line::from(format!(
                        "Every method at {} time steps on the {} lesson, in the background; \
                         the view keeps running. This is done once per lesson.",
                        Plan::quick().dts.len(),
                        lesson.name()
                    )),
                ],
                inner,
                buf,
            );
            return;
        }
    };
    let refs: Vec<&Row> = rows.iter().collect();
    let series = work_precision_series(&refs);
    let horizon = rows.first().map_or(0.0, |r| r.horizon);
    let (dt_hi, dt_lo) = rows.iter().fold((0.0f64, f64::INFINITY), |(a, b), r| {
        (a.max(r.dt), b.min(r.dt))
    });
    let mut legend = vec![Span::raw("legend: ")];
    for (k, s) in series.iter().enumerate() {
        let (c, (_, glyph)) = (COLOURS[k % 5], MARKERS[k % 5]);
        let mark = if app.colour { "━━" } else { glyph };
        legend.push(Span::styled(
            format!("{mark} {}  ", s.name),
            fg(app.colour, c),
        ));
    }
    let intro = format!(
        "RMS position error (m) at t = {horizon} s, up the side, against the wall time one \
         simulated second takes (s), along the bottom, for dt from 1/{:.0} s to 1/{:.0} s; \
         both scales logarithmic, down and left is better. Costs are this machine's, measured \
         once.",
        1.0 / dt_hi.max(f64::MIN_POSITIVE),
        1.0 / dt_lo
    );
    let width = usize::from(inner.width.max(1));
    let mut header: Vec<Line> = wrap(&intro, width).into_iter().map(Line::from).collect();
    let legend = Line::from(legend);
    let legend_rows = legend.width().div_ceil(width);
    header.push(legend);
    let header_rows = (header.len() - 1 + legend_rows) as u16;
    let [top, plot] =
        Layout::vertical([Constraint::Length(header_rows), Constraint::Fill(1)]).areas(inner);
    say_in(header, top, buf);

    let (x0, x1) = bounds(&series, |p| p.0);
    let (y0, y1) = bounds(&series, |p| p.1);
    if !(x0.is_finite() && y0.is_finite()) {
        say_in(vec![Line::from("The sweep gave no points.")], plot, buf);
        return;
    }
    let (x0, x1, x_labels) = ticks(x0, x1, usize::from(plot.width / 8));
    let (y0, y1, y_labels) = ticks(y0, y1, usize::from(plot.height.saturating_sub(3) / 2));
    let datasets = series
        .iter()
        .enumerate()
        .map(|(k, s)| {
            Dataset::default()
                .name(s.name.clone())
                .marker(if app.colour {
                    Marker::Braille
                } else {
                    MARKERS[k % 5].0
                })
                .graph_type(GraphType::Line)
                .style(fg(app.colour, COLOURS[k % 5]))
                .data(&s.points)
        })
        .collect();
    Chart::new(datasets)
        .x_axis(Axis::default().bounds([x0, x1]).labels(x_labels))
        .y_axis(Axis::default().bounds([y0, y1]).labels(y_labels))
        .legend_position(None)
        .render(plot, buf);
}

fn say_in(text: Vec<Line<'static>>, area: Rect, buf: &mut Buffer) {
    Paragraph::new(text)
        .wrap(Wrap { trim: true })
        .render(area, buf);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panicking(_: Lesson) -> Result<Vec<Row>, String> {
        panic!("synthetic panic")
    }

    #[test]
    fn a_panicking_computation_becomes_a_failed_result() {
        let mut charts = WorkCharts::new(panicking);
        charts.request(Lesson::Gravity);
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
        while charts.busy() {
            assert!(std::time::Instant::now() < deadline, "no result came back");
            charts.poll();
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        match charts.get(Lesson::Gravity) {
            Some(ChartData::Failed(e)) => {
                assert_eq!(e, "the computation panicked: synthetic panic")
            }
            other => panic!("expected a failed result, got {other:?}"),
        }
    }

    #[test]
    fn ticks_fall_on_whole_decades_and_cover_the_data() {
        let (lo, hi, labels) = ticks(-12.3, -1.2, 20);
        assert_eq!((lo, hi), (-13.0, -1.0));
        assert_eq!(labels.len(), 13);
        assert_eq!(labels[0].content, "1e-13");
        let (lo, hi, labels) = ticks(-12.3, -1.2, 4);
        assert!(lo <= -12.3 && hi >= -1.2);
        assert!(labels.len() <= 5, "{} labels", labels.len());
        let (lo, hi, _) = ticks(-3.0, -3.0, 4);
        assert_eq!((lo, hi), (-3.0, -2.0), "a flat series still gets a decade");
    }
}
