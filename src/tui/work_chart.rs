//! The chart screen: the work-precision chart of the lesson shown (log10
//! RMS position error against log10 wall time per simulated second, one
//! series per method), from `crate::study::work_precision`.
//!
//! The sweep takes seconds, so it runs once per lesson, on demand, in a
//! background thread; the result comes back over a channel and is kept for
//! the rest of the session. The app polls for it between frames, so the
//! view keeps running meanwhile.
//!
//! The plot is drawn here rather than by ratatui's `Chart`, whose axis
//! labels are spread evenly whatever their values: each axis is whole
//! decades, and every labelled decade sits on the cell its value maps to,
//! the same map the points use. Each point carries its method's marker and
//! colour and, where there is room, its dt.
//!
//! Owns the per-lesson results and the chart's drawing; it never changes
//! the world.

use super::app::App;
use super::palette::fg;
use super::panel::wrap;
use crate::scene::Lesson;
use crate::sim::Integrator;
use crate::study::charts::{SHARED, log10, marker};
use crate::study::metrics::{self, Convergence};
use crate::study::sweep::{self, Plan, Row};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Style, Stylize};
use ratatui::symbols::{Marker, line};
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine};
use ratatui::widgets::{Block, Clear, Paragraph, Widget, Wrap};
use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// What computes a lesson's rows (the study's sweep; tests give their own).
pub(crate) type Source = fn(Lesson) -> Result<Vec<Row>, String>;

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
    pub(crate) fn request(&mut self, lesson: Lesson) {
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
    pub(crate) fn poll(&mut self) -> bool {
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
    pub(crate) fn busy(&self) -> bool {
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

/// The colour of a method; under NO_COLOR its marker ([`marker`]) carries
/// the distinction alone. A new method chooses its own here.
fn method_colour(m: Integrator) -> Color {
    match m {
        Integrator::ExplicitEuler => Color::LightRed,
        Integrator::SemiImplicitEuler => Color::Yellow,
        Integrator::VelocityVerlet => Color::LightGreen,
        Integrator::Rk4 => Color::LightCyan,
        Integrator::Continuous => Color::LightMagenta,
    }
}

/// A log10 axis whose labelled decades fall on whole cells, evenly spaced:
/// `ticks + 1` labels, `step` decades and `gap` cells apart, from decade
/// `lo` at cell 0.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DecadeAxis {
    lo: i32,
    step: i32,
    ticks: u16,
    gap: u16,
}

impl DecadeAxis {
    /// The axis over log10 values `lo..=hi` in at most `cells` cells, with
    /// labels at least `min_gap` cells apart and on multiples of their
    /// step. Of those, three labels or more where they fit; then the most
    /// labels among those within a quarter of the finest cells per decade.
    /// `None` if nothing fits.
    fn fit(lo: f64, hi: f64, cells: u16, min_gap: u16) -> Option<Self> {
        if !(lo.is_finite() && hi.is_finite()) || lo > hi || cells < 2 {
            return None;
        }
        let first = lo.floor() as i32;
        let last = (hi.ceil() as i32).max(first + 1);
        let span = last - first;
        let fitting: Vec<Self> = (1..=2 * span)
            .filter_map(|step| {
                let lo = first.div_euclid(step) * step;
                let hi = -((-last).div_euclid(step) * step);
                let ticks = u16::try_from((hi - lo) / step).ok()?;
                let gap = (cells - 1) / ticks;
                (gap >= min_gap.max(1)).then_some(Self {
                    lo,
                    step,
                    ticks,
                    gap,
                })
            })
            .collect();
        let three = fitting.iter().any(|a| a.ticks >= 2);
        let fitting = fitting.into_iter().filter(|a| a.ticks >= 2 || !three);
        let finest = fitting.clone().map(|a| a.per_cell()).reduce(f64::min)?;
        fitting
            .filter(|a| a.per_cell() <= 1.25 * finest)
            .max_by_key(|a| (a.ticks, std::cmp::Reverse(a.step)))
    }

    /// Cells the axis covers, both ends included.
    fn len(&self) -> u16 {
        self.ticks * self.gap + 1
    }

    fn hi(&self) -> i32 {
        self.lo + self.step * i32::from(self.ticks)
    }

    /// Decades one cell spans.
    fn per_cell(&self) -> f64 {
        f64::from(self.step) / f64::from(self.gap)
    }

    /// The cell of log10 value `v`, counted from the axis' start.
    fn cell(&self, v: f64) -> u16 {
        let at = ((v - f64::from(self.lo)) / self.per_cell()).round();
        at.clamp(0.0, f64::from(self.len() - 1)) as u16
    }

    /// The labelled decades and their cells.
    fn labels(&self) -> impl Iterator<Item = (i32, u16)> + '_ {
        (0..=self.ticks).map(|k| (self.lo + self.step * i32::from(k), k * self.gap))
    }
}

fn decade_label(d: i32) -> String {
    format!("1e{d}")
}

/// Rows around the graph: the y axis' title above; the x axis, its labels
/// and its title below.
const ROWS_AROUND: u16 = 4;
/// Columns of the widest x label (`1e-17`, the log floor's decade).
const X_LABEL_ROOM: u16 = 5;

/// Where the plot goes in its area: the graph's cells and its two axes.
#[derive(Debug)]
struct PlotLayout {
    graph: Rect,
    x: DecadeAxis,
    y: DecadeAxis,
}

impl PlotLayout {
    /// The layout over log10 ranges `xs` and `ys`, if `area` has room.
    fn fit(area: Rect, xs: (f64, f64), ys: (f64, f64)) -> Option<Self> {
        let y = DecadeAxis::fit(ys.0, ys.1, area.height.checked_sub(ROWS_AROUND)?, 2)?;
        let label_width = y.labels().map(|(d, _)| decade_label(d).len()).max()? as u16;
        let left = area.x + label_width + 2;
        let room = area.right().checked_sub(left + X_LABEL_ROOM / 2 + 1)?;
        let x = DecadeAxis::fit(xs.0, xs.1, room, X_LABEL_ROOM + 2)?;
        let graph = Rect::new(left, area.y + 1, x.len(), y.len());
        Some(Self { graph, x, y })
    }

    fn column(&self, cell: u16) -> u16 {
        self.graph.x + cell
    }

    fn row(&self, cell: u16) -> u16 {
        self.graph.bottom() - 1 - cell
    }

    /// The screen cell of log10 values `(x, y)`.
    fn at(&self, x: f64, y: f64) -> (u16, u16) {
        (self.column(self.x.cell(x)), self.row(self.y.cell(y)))
    }

    /// Rows used, from the area's top.
    fn height(&self) -> u16 {
        self.graph.height + ROWS_AROUND
    }
}

/// One measured run: log10 cost per simulated second, log10 RMS error.
#[derive(Clone, Copy, Debug)]
struct Point {
    method: Integrator,
    dt: f64,
    x: f64,
    y: f64,
}

/// The rows as points, method by method in [`Integrator::ALL`] order, each
/// method's in row order (largest dt first).
fn points(rows: &[Row]) -> Vec<Point> {
    Integrator::ALL
        .iter()
        .flat_map(|&m| rows.iter().filter(move |r| r.method == m))
        .map(|r| Point {
            method: r.method,
            dt: r.dt,
            x: log10(r.cost_per_second),
            y: log10(r.error()),
        })
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect()
}

/// `1/120` for dt = 1/120 s (n rounded).
fn dt_label(dt: f64) -> String {
    if dt > 0.0 && dt < 1.0 {
        format!("1/{:.0}", 1.0 / dt)
    } else {
        format!("{dt}")
    }
}

/// The sentence under the chart: what it shows on `lesson`, with the
/// discrete methods' convergence and the continuous method's cost relative
/// to theirs read from `rows`.
fn caption(lesson: Lesson, rows: &[Row]) -> String {
    let times = |r: f64| {
        if r >= 10.0 {
            format!("{r:.0}")
        } else {
            format!("{r:.1}")
        }
    };
    let ratios = continuous_cost_ratios(rows);
    let cost = match (ratios.first(), ratios.last()) {
        (Some(&(dt_large, large)), Some(&(dt_small, small)))
            if large.max(small) > COST_SPREAD * large.min(small) =>
        {
            format!(
                ", for {} times their cost at dt = {} s and {} times at {} s",
                times(large),
                dt_label(dt_large),
                times(small),
                dt_label(dt_small)
            )
        }
        (Some(_), Some(_)) => {
            let mut all: Vec<f64> = ratios.iter().map(|&(_, r)| r).collect();
            format!(
                ", for about {} times their cost",
                times(metrics::median(&mut all))
            )
        }
        _ => String::new(),
    };
    match lesson {
        Lesson::Pingpong => "Ping-pong: nothing accelerates the sphere between the walls, so \
             every method is exact and only rounding is left, growing with the number of steps: \
             a smaller dt costs more and buys nothing."
            .to_string(),
        Lesson::Gravity => {
            let euler = [Integrator::ExplicitEuler, Integrator::SemiImplicitEuler];
            let parabola = [Integrator::VelocityVerlet, Integrator::Rk4];
            format!(
                "Gravity: {} find a bounce at the end of a step and mirror the overshoot: {}; {} reflect where \
                 their parabola crosses the wall: {}; the continuous method times each \
                 bounce: {}{cost}.",
                names(&euler),
                group_convergence(rows, &euler),
                names(&parabola),
                group_convergence(rows, &parabola),
                group_convergence(rows, &[Integrator::Continuous]),
            )
        }
        Lesson::Collisions => format!(
            "Collisions: the discrete methods meet a contact only at the end of a step: {}; \
             the continuous method resolves each collision at its moment: {}{cost}.",
            group_convergence(rows, &Integrator::DISCRETE),
            group_convergence(rows, &[Integrator::Continuous]),
        ),
    }
}

/// `a and b`, or `a, b and c`: the methods' names.
fn names(methods: &[Integrator]) -> String {
    let names: Vec<&str> = methods.iter().map(|m| m.name()).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

/// How the error of `methods` falls with `dt` in `rows`: "fitted order
/// 1.00", "fitted orders 0.99 to 1.01", "at rounding", or each method's own
/// when they differ in kind (as `lerpit study` says it).
fn group_convergence(rows: &[Row], methods: &[Integrator]) -> String {
    let each: Vec<(Integrator, Convergence)> = methods
        .iter()
        .filter_map(|&m| Some((m, sweep::convergence_of(rows, m)?)))
        .collect();
    let orders: Vec<f64> = each
        .iter()
        .filter_map(|(_, c)| match c {
            Convergence::Order(p) => Some(*p),
            _ => None,
        })
        .collect();
    let word = |c: &Convergence| match c {
        Convergence::Order(p) => format!("fitted order {p:.2}"),
        Convergence::Rounding => "at rounding".to_string(),
        Convergence::Diverging(_) => "at rounding, growing as dt shrinks".to_string(),
    };
    if each.is_empty() {
        return "not run".to_string();
    }
    if orders.len() == each.len() {
        let lo = orders.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = orders.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        return if format!("{lo:.2}") == format!("{hi:.2}") {
            format!("fitted order {lo:.2}")
        } else {
            format!("fitted orders {lo:.2} to {hi:.2}")
        };
    }
    if orders.is_empty() && each.iter().all(|(_, c)| word(c) == word(&each[0].1)) {
        return word(&each[0].1);
    }
    each.iter()
        .map(|(m, c)| format!("{} {}", m.name(), word(c)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The continuous method's cost over the discrete methods' median cost at
/// the same dt, for each of its dts from the largest down.
fn continuous_cost_ratios(rows: &[Row]) -> Vec<(f64, f64)> {
    let mut ratios: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.method == Integrator::Continuous)
        .filter_map(|c| {
            let mut costs: Vec<f64> = rows
                .iter()
                .filter(|r| r.dt == c.dt && Integrator::DISCRETE.contains(&r.method))
                .map(|r| r.cost_per_second)
                .collect();
            let median = metrics::median(&mut costs);
            (median > 0.0).then(|| (c.dt, c.cost_per_second / median))
        })
        .filter(|(_, r)| r.is_finite())
        .collect();
    ratios.sort_by(|a, b| b.0.total_cmp(&a.0));
    ratios
}

/// From this spread between the continuous method's relative cost at its
/// largest and its smallest dt, the sentence gives both, not one figure.
const COST_SPREAD: f64 = 1.5;

/// The chart screen over `area`.
pub fn render_work_chart(app: &App, area: Rect, buf: &mut Buffer) {
    Clear.render(area, buf);
    let title = match app.lesson {
        Some(l) => format!(
            " work against precision: {} lesson, with its own parameters ",
            l.name()
        ),
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
    match app.charts.get(lesson) {
        Some(ChartData::Ready(rows)) => draw_chart(lesson, rows, app.colour, inner, buf),
        Some(ChartData::Failed(e)) => say_in(
            vec![Line::from(format!("The sweep failed: {e}"))],
            inner,
            buf,
        ),
        _ => say_in(
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
        ),
    }
}

/// The chart of `rows` over `area`: what it shows and the legend above,
/// the plot, the lesson's sentence below.
fn draw_chart(lesson: Lesson, rows: &[Row], colour: bool, area: Rect, buf: &mut Buffer) {
    let pts = points(rows);
    if pts.is_empty() {
        say_in(vec![Line::from("The sweep gave no points.")], area, buf);
        return;
    }
    let (dt_hi, dt_lo) = rows.iter().fold((0.0f64, f64::INFINITY), |(a, b), r| {
        (a.max(r.dt), b.min(r.dt))
    });
    let width = usize::from(area.width.max(1));
    let intro = format!(
        "One point per run, labelled 1/n for dt = 1/n s (n rounded, from {:.0} to {:.0}); log \
         scales: down and left is better. Costs are this machine's, measured once.",
        1.0 / dt_hi,
        1.0 / dt_lo
    );
    let mut header: Vec<Line> = wrap(&intro, width).into_iter().map(Line::from).collect();
    header.extend(legend(&pts, colour, width));
    let below: Vec<Line> = wrap(&caption(lesson, rows), width)
        .into_iter()
        .map(Line::from)
        .collect();
    let [top, rest] =
        Layout::vertical([Constraint::Length(header.len() as u16), Constraint::Fill(1)])
            .areas(area);
    say_in(header, top, buf);
    let plot_area = Rect {
        height: rest.height.saturating_sub(below.len() as u16),
        ..rest
    };
    let bounds = |pick: fn(&Point) -> f64| {
        pts.iter()
            .map(pick)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let Some(plot) = PlotLayout::fit(plot_area, bounds(|p| p.x), bounds(|p| p.y)) else {
        say_in(
            vec![Line::from("The window is too small for the chart.")],
            rest,
            buf,
        );
        return;
    };
    let horizon = rows.first().map_or(0.0, |r| r.horizon);
    draw_axes(
        &plot,
        plot_area,
        &format!("RMS position error at t = {horizon} s (m)"),
        "wall time per simulated second (s)",
        buf,
    );
    draw_lines(&plot, &pts, colour, buf);
    draw_points(&plot, &pts, colour, buf);
    let caption_area = Rect {
        y: plot_area.y + plot.height(),
        height: rest.bottom().saturating_sub(plot_area.y + plot.height()),
        ..rest
    };
    say_in(below, caption_area, buf);
}

/// The legend: each method's marker (and, in colour, its line) and name,
/// then the marker of a shared cell; flowed into lines of `width`.
fn legend(pts: &[Point], colour: bool, width: usize) -> Vec<Line<'static>> {
    let mut items: Vec<Vec<Span<'static>>> = Integrator::ALL
        .iter()
        .filter(|&&m| pts.iter().any(|p| p.method == m))
        .map(|&m| {
            let style = fg(colour, method_colour(m));
            let mark = if colour {
                format!("━{}━", marker(m))
            } else {
                marker(m).to_string()
            };
            vec![
                Span::styled(mark, style.bold()),
                Span::styled(format!(" {}", m.name()), style),
            ]
        })
        .collect();
    items.push(vec![
        Span::raw(SHARED.to_string()).bold(),
        Span::raw(" more than one method"),
    ]);
    let mut lines = Vec::new();
    let mut line: Vec<Span<'static>> = Vec::new();
    let mut used = 0;
    for item in items {
        let w: usize = item.iter().map(Span::width).sum();
        if used > 0 && used + 3 + w > width {
            lines.push(Line::from(std::mem::take(&mut line)));
            used = 0;
        }
        if used > 0 {
            line.push(Span::raw("   "));
            used += 3;
        }
        line.extend(item);
        used += w;
    }
    lines.push(Line::from(line));
    lines
}

/// Both axes: lines with a tick at each labelled decade, the labels
/// centred on their ticks (x) or level with them (y), and the titles.
fn draw_axes(plot: &PlotLayout, area: Rect, y_title: &str, x_title: &str, buf: &mut Buffer) {
    let g = plot.graph;
    let axis_x = g.x - 1;
    let axis_y = g.bottom();
    for y in g.top()..g.bottom() {
        buf[(axis_x, y)].set_symbol(line::VERTICAL);
    }
    for x in g.left()..g.right() {
        buf[(x, axis_y)].set_symbol(line::HORIZONTAL);
    }
    buf[(axis_x, axis_y)].set_symbol(line::BOTTOM_LEFT);
    for (d, cell) in plot.y.labels() {
        let row = plot.row(cell);
        let text = decade_label(d);
        buf[(axis_x, row)].set_symbol(line::VERTICAL_LEFT);
        let x = axis_x - 1 - text.len() as u16;
        buf.set_string(x, row, text, Style::default());
    }
    for (d, cell) in plot.x.labels() {
        let col = plot.column(cell);
        let text = decade_label(d);
        buf[(col, axis_y)].set_symbol(line::HORIZONTAL_DOWN);
        let start = col - (text.len() as u16 - 1) / 2;
        buf.set_string(start, axis_y + 1, text, Style::default());
    }
    buf.set_stringn(
        area.x,
        area.y,
        y_title,
        usize::from(area.width),
        Style::default(),
    );
    let end = (g.right() + X_LABEL_ROOM / 2).min(area.right());
    let start = end.saturating_sub(x_title.len() as u16).max(area.x);
    buf.set_stringn(
        start,
        axis_y + 2,
        x_title,
        usize::from(end - start),
        Style::default(),
    );
}

/// Each method's points joined in dt order, in Braille dots, in its colour.
/// The canvas reaches half a cell past each end so that a value falls in
/// the cell [`PlotLayout::at`] gives it.
fn draw_lines(plot: &PlotLayout, pts: &[Point], colour: bool, buf: &mut Buffer) {
    let half = |a: &DecadeAxis| 0.5 * a.per_cell();
    let (x0, x1) = (f64::from(plot.x.lo), f64::from(plot.x.hi()));
    let (y0, y1) = (f64::from(plot.y.lo), f64::from(plot.y.hi()));
    Canvas::default()
        .marker(Marker::Braille)
        .x_bounds([x0 - half(&plot.x), x1 + half(&plot.x)])
        .y_bounds([y0 - half(&plot.y), y1 + half(&plot.y)])
        .paint(|ctx| {
            for pair in pts.windows(2) {
                let [a, b] = [pair[0], pair[1]];
                if a.method == b.method {
                    ctx.draw(&CanvasLine {
                        x1: a.x,
                        y1: a.y,
                        x2: b.x,
                        y2: b.y,
                        color: if colour {
                            method_colour(a.method)
                        } else {
                            Color::Reset
                        },
                    });
                }
            }
        })
        .render(plot.graph, buf);
}

/// Each point's marker at its cell ([`SHARED`] where methods share one),
/// then its dt beside, above or below it where that overlaps no other label
/// or line and has no other marker next to it (else no label).
fn draw_points(plot: &PlotLayout, pts: &[Point], colour: bool, buf: &mut Buffer) {
    let g = plot.graph;
    let mut cells: Vec<((u16, u16), Vec<Point>)> = Vec::new();
    for p in pts {
        let at = plot.at(p.x, p.y);
        match cells.iter_mut().find(|(c, _)| *c == at) {
            Some((_, here)) => here.push(*p),
            None => cells.push((at, vec![*p])),
        }
    }
    let index =
        |(x, y): (u16, u16)| usize::from(y - g.y) * usize::from(g.width) + usize::from(x - g.x);
    let line_at: Vec<bool> = g
        .positions()
        .map(|p| !matches!(buf[p].symbol(), " " | "⠀"))
        .collect();
    let mut taken = vec![false; line_at.len()];
    let mut marked = vec![false; line_at.len()];
    for ((x, y), here) in &cells {
        let first = here[0].method;
        let (mark, style) = if here.iter().all(|p| p.method == first) {
            (marker(first), fg(colour, method_colour(first)).bold())
        } else {
            (SHARED, Style::default().bold())
        };
        buf[(*x, *y)].set_char(mark).set_style(style);
        taken[index((*x, *y))] = true;
        marked[index((*x, *y))] = true;
    }
    for ((x, y), here) in &cells {
        let dt = here[0].dt;
        if here.iter().any(|p| p.dt != dt) {
            continue;
        }
        let text = dt_label(dt);
        let len = text.len() as u16;
        let (x, y) = (i32::from(*x), i32::from(*y));
        let candidates = [
            (x + 2, y),
            (x - 1 - i32::from(len), y),
            (x, y - 1),
            (x, y + 1),
        ];
        let fits = |&(sx, sy): &(i32, i32)| {
            let inside = sx >= i32::from(g.left())
                && sx + i32::from(len) <= i32::from(g.right())
                && sy >= i32::from(g.top())
                && sy < i32::from(g.bottom());
            inside
                && (sx - 1..=sx + i32::from(len)).all(|cx| {
                    cx < i32::from(g.left())
                        || cx >= i32::from(g.right())
                        || !taken[index((cx as u16, sy as u16))]
                })
        };
        // No other marker next to the label, so that it reads as this one's.
        let own = |&(sx, sy): &(i32, i32)| {
            (sy - 1..=sy + 1).all(|cy| {
                (sx - 1..=sx + i32::from(len)).all(|cx| {
                    let inside = (i32::from(g.left())..i32::from(g.right())).contains(&cx)
                        && (i32::from(g.top())..i32::from(g.bottom())).contains(&cy);
                    (cx, cy) == (x, y) || !inside || !marked[index((cx as u16, cy as u16))]
                })
            })
        };
        let covered = |&(sx, sy): &(i32, i32)| {
            (sx..sx + i32::from(len))
                .filter(|&cx| line_at[index((cx as u16, sy as u16))])
                .count()
        };
        // A label over a curve hides the curve and reads as part of it:
        // rather none (the points run in order of dt along each curve).
        let Some((sx, sy)) = candidates
            .iter()
            .find(|c| fits(c) && own(c) && covered(c) == 0)
        else {
            continue;
        };
        let style = if here.iter().all(|p| p.method == here[0].method) {
            fg(colour, method_colour(here[0].method))
        } else {
            Style::default()
        };
        buf.set_string(*sx as u16, *sy as u16, &text, style);
        for cx in *sx..sx + i32::from(len) {
            taken[index((cx as u16, *sy as u16))] = true;
        }
    }
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
    fn every_method_has_its_own_marker_and_colour() {
        for (k, &a) in Integrator::ALL.iter().enumerate() {
            assert_ne!(marker(a), SHARED, "{} uses the shared marker", a.name());
            for &b in &Integrator::ALL[k + 1..] {
                assert_ne!(marker(a), marker(b), "{} and {}", a.name(), b.name());
                assert_ne!(
                    method_colour(a),
                    method_colour(b),
                    "{} and {}",
                    a.name(),
                    b.name()
                );
            }
        }
    }

    #[test]
    fn decade_axes_take_whole_decades_evenly_spaced() {
        let a = DecadeAxis::fit(-12.3, -1.2, 40, 2).unwrap();
        assert_eq!((a.lo, a.hi(), a.step), (-13, -1, 1), "one label a decade");
        assert_eq!(a.gap, 39 / 12);
        let labels: Vec<(i32, u16)> = a.labels().collect();
        assert_eq!(labels.first(), Some(&(-13, 0)));
        assert_eq!(labels.last(), Some(&(-1, 12 * a.gap)));
        assert_eq!(
            a.cell(-7.0),
            6 * a.gap,
            "a decade's value is its label's cell"
        );

        let a = DecadeAxis::fit(-12.3, -1.2, 12, 2).unwrap();
        assert!(a.step > 1 && a.gap >= 2 && a.len() <= 12, "{a:?}");
        assert!(a.ticks >= 2, "three labels where they fit: {a:?}");
        assert_eq!(a.lo % a.step, 0, "labels on multiples of the step");
        assert!(a.lo as f64 <= -12.3 && a.hi() as f64 >= -1.2, "{a:?}");

        let a = DecadeAxis::fit(-3.0, -3.0, 10, 2).unwrap();
        assert_eq!(
            (a.lo, a.hi()),
            (-3, -2),
            "a flat series still gets a decade"
        );
        assert_eq!(DecadeAxis::fit(-3.0, -1.0, 2, 2), None, "no room");
    }

    /// Work-precision rows with fixed figures: cost grows as 1/dt, error as
    /// dt (flat at 1e-15 for the continuous method, at five times the
    /// cost of the discrete methods' median).
    fn synthetic(lesson: Lesson) -> Vec<Row> {
        let dts = crate::study::sweep::log_spaced(1.0 / 30.0, 2.0, 8);
        let mut rows = Vec::new();
        for (k, &method) in Integrator::ALL.iter().enumerate() {
            for &dt in &dts {
                let (cost, error) = if method == Integrator::Continuous {
                    (5.0 * 2.5e-5 / dt, 1e-15)
                } else {
                    ((1.0 + k as f64) * 1e-5 / dt, (0.5 + k as f64) * dt)
                };
                rows.push(Row {
                    lesson,
                    method,
                    dt,
                    steps: (0.5 / dt).round() as u64,
                    bodies: 150,
                    horizon: 0.5,
                    wall_time: cost * 0.5,
                    cost_per_second: cost,
                    ns_per_body_step: cost * dt * 1e9 / 150.0,
                    rms_error: error,
                    bounce_time_error: None,
                    apex_ratio_error: None,
                    energy_error: error,
                    event_cap_reached: false,
                });
            }
        }
        rows
    }

    fn drawn(rows: &[Row], colour: bool, width: u16, height: u16) -> Buffer {
        let area = Rect::new(0, 0, width, height);
        let mut buf = Buffer::empty(area);
        draw_chart(Lesson::Gravity, rows, colour, area, &mut buf);
        buf
    }

    /// The whole word around column `x` of row `y`: its first column and text.
    fn word_at(buf: &Buffer, x: u16, y: u16) -> (u16, String) {
        let blank = |x: u16| buf[(x, y)].symbol() == " ";
        let mut start = x;
        while start > 0 && !blank(start - 1) {
            start -= 1;
        }
        let mut end = x;
        while end + 1 < buf.area.right() && !blank(end + 1) {
            end += 1;
        }
        let text = (start..=end).map(|x| buf[(x, y)].symbol()).collect();
        (start, text)
    }

    fn screen(buf: &Buffer) -> String {
        let w = usize::from(buf.area.width);
        let cells: Vec<&str> = buf.content().iter().map(|c| c.symbol()).collect();
        cells.chunks(w).map(|r| r.concat() + "\n").collect()
    }

    fn decade(text: &str) -> i32 {
        text.strip_prefix("1e")
            .and_then(|d| d.parse().ok())
            .unwrap_or_else(|| panic!("{text:?} is not a decade label"))
    }

    /// Labelled decades and their cells along one axis, read from the
    /// screen, checked to be evenly spaced; returns the cell of log10 `v`
    /// (whole cells counted from the first label).
    fn evenly_spaced(axis: &str, ticks: &[(i32, u16)]) -> impl Fn(f64) -> f64 {
        assert!(
            ticks.len() >= 2,
            "{axis}: at least two labels, got {ticks:?}"
        );
        let (d0, c0) = ticks[0];
        let (d1, c1) = ticks[1];
        for w in ticks.windows(2) {
            assert_eq!(
                w[1].0 - w[0].0,
                d1 - d0,
                "{axis}: decades evenly stepped {ticks:?}"
            );
            assert_eq!(
                i32::from(w[1].1) - i32::from(w[0].1),
                i32::from(c1) - i32::from(c0),
                "{axis}: labels evenly spaced {ticks:?}"
            );
        }
        let gap = f64::from(c1) - f64::from(c0);
        let per_decade = gap.abs() / f64::from(d1 - d0);
        move |v| f64::from(c0) + gap.signum() * ((v - f64::from(d0)) * per_decade).round()
    }

    #[test]
    fn each_decade_label_sits_where_its_value_maps() {
        let rows = synthetic(Lesson::Gravity);
        for (width, height) in [(78, 21), (118, 37), (198, 57)] {
            let buf = drawn(&rows, true, width, height);
            let corner = buf
                .area
                .positions()
                .find(|&p| buf[p].symbol() == line::BOTTOM_LEFT)
                .unwrap_or_else(|| panic!("{width}x{height}: no axes"));
            let (axis_x, axis_y) = (corner.x, corner.y);
            let x_ticks: Vec<(i32, u16)> = (axis_x..buf.area.right())
                .filter(|&x| buf[(x, axis_y)].symbol() == line::HORIZONTAL_DOWN)
                .map(|x| {
                    let (start, text) = word_at(&buf, x, axis_y + 1);
                    let centre = start + (text.len() as u16 - 1) / 2;
                    assert_eq!(centre, x, "{width}x{height}: {text} centred on its tick");
                    (decade(&text), x)
                })
                .collect();
            let y_ticks: Vec<(i32, u16)> = (0..axis_y)
                .rev()
                .filter(|&y| buf[(axis_x, y)].symbol() == line::VERTICAL_LEFT)
                .map(|y| {
                    let (start, text) = word_at(&buf, axis_x - 2, y);
                    assert_eq!(
                        start + text.len() as u16,
                        axis_x - 1,
                        "{width}x{height}: {text} ends beside its tick"
                    );
                    (decade(&text), y)
                })
                .collect();
            let column = evenly_spaced("x", &x_ticks);
            let row = evenly_spaced("y", &y_ticks);
            for p in points(&rows) {
                let (x, y) = (column(p.x) as u16, row(p.y) as u16);
                let got = buf[(x, y)].symbol();
                assert!(
                    got == marker(p.method).to_string() || got == SHARED.to_string(),
                    "{width}x{height}: {} at dt {} belongs at ({x}, {y}), which shows \
                     {got:?}:\n{}",
                    p.method.name(),
                    dt_label(p.dt),
                    screen(&buf)
                );
            }
        }
    }

    #[test]
    fn without_colour_nothing_is_coloured_and_the_legend_names_each_marker() {
        let buf = drawn(&synthetic(Lesson::Gravity), false, 118, 37);
        assert!(
            buf.content().iter().all(|c| c.fg == Color::Reset),
            "a cell has a colour"
        );
        let text: String = buf.content().iter().map(|c| c.symbol()).collect();
        for m in Integrator::ALL {
            let entry = format!("{} {}", marker(m), m.name());
            assert!(text.contains(&entry), "the legend lacks {entry:?}");
        }
    }

    #[test]
    fn the_sentence_reads_orders_and_cost_from_the_rows() {
        let rows = synthetic(Lesson::Collisions);
        let said = caption(Lesson::Collisions, &rows);
        assert!(
            said.contains("end of a step: fitted order 1.00; the continuous method"),
            "{said}"
        );
        assert!(said.contains("about 5.0 times their cost"), "{said}");
        // A relative cost that falls as dt shrinks: both ends are given.
        let mut falling = rows.clone();
        for r in &mut falling {
            if r.method == Integrator::Continuous {
                r.cost_per_second *= (r.dt * 30.0).sqrt();
            }
        }
        let said = caption(Lesson::Collisions, &falling);
        assert!(
            said.contains("for 5.0 times their cost at dt = 1/30 s and 0.5 times at 1/3000 s"),
            "{said}"
        );
        let said = caption(Lesson::Pingpong, &rows);
        assert!(said.contains("every method is exact"), "{said}");
    }

    #[test]
    fn the_gravity_sentence_names_the_methods_at_rounding_apart_from_the_first_order_ones() {
        let mut rows = synthetic(Lesson::Gravity);
        for r in &mut rows {
            if matches!(r.method, Integrator::VelocityVerlet | Integrator::Rk4) {
                (r.rms_error, r.energy_error) = (1e-15, 1e-15);
            }
        }
        let said = caption(Lesson::Gravity, &rows);
        assert!(
            said.contains(
                "explicit-euler and semi-implicit-euler find a bounce at the end of a step and \
                 mirror the overshoot: fitted order 1.00;"
            ),
            "{said}"
        );
        assert!(
            said.contains(
                "velocity-verlet and rk4 reflect where their parabola crosses the wall: at \
                 rounding;"
            ),
            "{said}"
        );
        // A method with an order beside one at rounding: each is named.
        let rk4_rows = rows.iter_mut().filter(|r| r.method == Integrator::Rk4);
        for r in rk4_rows {
            (r.rms_error, r.energy_error) = (r.dt.powi(4), r.dt.powi(4));
        }
        let said = caption(Lesson::Gravity, &rows);
        assert!(
            said.contains("velocity-verlet at rounding, rk4 fitted order 4.00"),
            "{said}"
        );
        // Rounding that grows with the steps is said as `lerpit study` says it.
        for r in rows.iter_mut().filter(|r| r.method == Integrator::Rk4) {
            (r.rms_error, r.energy_error) = (1e-9 / r.dt, 1e-9 / r.dt);
        }
        let said = caption(Lesson::Gravity, &rows);
        assert!(
            said.contains("velocity-verlet at rounding, rk4 at rounding, growing as dt shrinks"),
            "{said}"
        );
    }
}
