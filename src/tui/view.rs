//! Drawing the app: `impl Widget for &App`, with small `render_*` helpers
//! for the box view, its legend, the footer and the too-small message. The
//! side panel and the help overlay have their own modules.
//!
//! Owns layout and drawing; it reads the app and never changes it.

use super::app::App;
use super::box_view::{BoxPicture, MAX_CONTACT_MARKS, Marks};
use super::frame::Trail;
use super::keymap;
use super::palette::{self, Colouring, fg};
use super::{help, panel, work_chart};
use crate::sim::Vec3;
use ratatui::buffer::Buffer;
use ratatui::layout::{Alignment, Constraint, Layout, Rect, Size};
use ratatui::style::{Modifier, Style, Stylize};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::Canvas;
use ratatui::widgets::{Block, Paragraph, Widget, Wrap};
use std::borrow::Cow;
use std::cell::Cell;

/// The smallest terminal the layout fits.
pub(crate) const MIN_WIDTH: u16 = 80;
pub(crate) const MIN_HEIGHT: u16 = 24;
/// Columns of the side panel, at most: it gives way so that the box keeps
/// at least half the width.
pub(crate) const PANEL_WIDTH: u16 = 42;

/// Where the parts of the screen go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Areas {
    /// Everything above the footer.
    pub main: Rect,
    pub footer: Rect,
    /// The box view, its border included.
    pub view: Rect,
    /// The side panel, when shown.
    pub side: Option<Rect>,
}

impl Areas {
    /// The areas with a footer of one row.
    pub fn of(area: Rect, panel: bool) -> Self {
        Self::with_footer(area, panel, 1)
    }

    /// The areas with a footer of `footer_rows` rows.
    pub fn with_footer(area: Rect, panel: bool, footer_rows: u16) -> Self {
        let [main, footer] =
            Layout::vertical([Constraint::Fill(1), Constraint::Length(footer_rows)]).areas(area);
        let width = if panel {
            PANEL_WIDTH.min(main.width / 2)
        } else {
            0
        };
        let [view, side] =
            Layout::horizontal([Constraint::Fill(1), Constraint::Length(width)]).areas(main);
        Self {
            main,
            footer,
            view,
            side: panel.then_some(side),
        }
    }

    /// The braille canvas inside the box view (within its border, above
    /// its legend), if there is room for one.
    pub fn canvas(&self) -> Option<Rect> {
        let inner = Block::bordered().inner(self.view);
        if inner.height < 2 || inner.width < 2 {
            return None;
        }
        let [canvas, _legend] =
            Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(inner);
        Some(canvas)
    }
}

impl Widget for &App {
    fn render(self, area: Rect, buf: &mut Buffer) {
        if too_small(area.width, area.height) {
            render_too_small(area, self.timing.keys_held, buf);
            return;
        }
        let areas = self.areas(area);
        if self.chart_open {
            work_chart::render_work_chart(self, areas.main, buf);
        } else {
            render_view(self, areas.view, buf);
            if let Some(side) = areas.side {
                panel::render_panel(self, side, buf);
            }
        }
        let footer = areas.footer;
        render_footer(self, footer, buf);
        if self.help_open {
            let above_footer = Rect {
                height: area.height - footer.height,
                ..area
            };
            help::render_help(self, above_footer, buf);
        }
    }
}

/// Whether a terminal of `width` x `height` is below the size the
/// visualiser draws in: it then shows only its size and the way out.
pub(crate) fn too_small(width: u16, height: u16) -> bool {
    width < MIN_WIDTH || height < MIN_HEIGHT
}

fn render_too_small(area: Rect, keys_held: bool, buf: &mut Buffer) {
    // A tiny window gets the short form, so that the size needed and the
    // way out still show.
    let mut text = if area.width >= 48 && area.height >= 5 {
        vec![
            Line::from("The terminal is too small.".bold()),
            Line::from(format!(
                "It is {}x{}; lerpit needs at least {MIN_WIDTH}x{MIN_HEIGHT}.",
                area.width, area.height
            )),
            Line::from("Enlarge the window, or press q to quit."),
        ]
    } else {
        vec![
            Line::from(format!("too small: {}x{}", area.width, area.height).bold()),
            Line::from(format!("needs {MIN_WIDTH}x{MIN_HEIGHT}")),
            Line::from("q quits"),
        ]
    };
    // The way out holds only once the keys reach it.
    if keys_held {
        text.push(Line::from(KEYS_HELD_SHORT));
    }
    let top = area.height.saturating_sub(text.len() as u16) / 2;
    let [_, middle] = Layout::vertical([Constraint::Length(top), Constraint::Fill(1)]).areas(area);
    Paragraph::new(text)
        .alignment(Alignment::Center)
        .wrap(Wrap { trim: true })
        .render(middle, buf);
}

fn render_view(app: &App, area: Rect, buf: &mut Buffer) {
    let title = match &app.frame.scene.info {
        Some(info) if !info.title.is_empty() => info.title.clone(),
        _ => app.frame.scene.name.clone(),
    };
    let state = header_state(app);
    // The title gives way to the state, ending in an ellipsis where it is
    // cut, as the side panel's do.
    // One pass over the title, however long a scene file made it.
    let room = usize::from(area.width).saturating_sub(2 + Span::raw(&state).width() + 1);
    let full = Line::from(format!(" lerpit: {title} "));
    let head = if full.width() <= room {
        full
    } else if room >= 2 {
        let mut cut = super::panel::cut_to(full, room - 1);
        cut.push_span(" ");
        cut
    } else {
        Line::from("\u{2026} ")
    };
    let block = Block::bordered()
        .title(head.bold())
        .title(Line::from(state).right_aligned());
    let inner = block.inner(area);
    block.render(area, buf);
    if inner.height < 2 || inner.width < 2 {
        return;
    }
    let [canvas_area, legend] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(inner);
    let as_points = render_box(app, canvas_area, buf);
    render_legend(app, as_points, legend, buf);
}

/// The braille canvas with the box and its spheres. Returns how many of
/// the spheres were drawn as a dot each rather than as discs (the
/// farthest, when the discs would take too long to draw: `disc_budget`).
pub fn render_box(app: &App, area: Rect, buf: &mut Buffer) -> usize {
    let (width, height) = (usize::from(area.width) * 2, usize::from(area.height) * 4);
    let trails: &[Trail] = if app.show_trails {
        &app.frame.trails
    } else {
        &[]
    };
    let frame = &app.frame;
    let selected = frame.selected_slots();
    let before: Vec<(Vec3, f64)> = frame
        .inspection
        .as_ref()
        .and_then(|i| i.pair.as_ref())
        .map_or_else(Vec::new, |p| {
            let r: Vec<f64> = selected
                .iter()
                .map(|&k| frame.world.bodies.radius[k])
                .collect();
            p.before.iter().zip(r).map(|(&x, r)| (x, r)).collect()
        });
    let marks = Marks {
        contacts: if app.show_contacts {
            frame.world.contacts()
        } else {
            &[]
        },
        selected: &selected,
        selected_trails: &frame.selected_trails,
        before: &before,
    };
    let picture = BoxPicture {
        marks,
        projection: app.projection_of(width, height, &selected),
        width,
        height,
        bodies: &app.frame.world.bodies,
        colouring: app.colouring,
        speed_scale: app.frame.speed_scale,
        colour: app.colour,
        trails,
        vectors: app.show_vectors,
        floor_grid: app.show_floor_grid,
        ghost: app
            .frame
            .ghost
            .as_ref()
            .filter(|g| g.unavailable.is_none())
            .map(|g| (g.positions.as_slice(), g.radius.as_slice())),
        as_points: Cell::new(0),
    };
    Canvas::default()
        .marker(Marker::Braille)
        .x_bounds([0.0, (width.max(2) - 1) as f64])
        .y_bounds([0.0, (height.max(2) - 1) as f64])
        .paint(|ctx| ctx.draw(&picture))
        .render(area, buf);
    picture.as_points.get()
}

fn render_legend(app: &App, as_points: usize, area: Rect, buf: &mut Buffer) {
    // Items in order, each shown whole or not at all, with a rank: a
    // narrow view leaves out the lowest ranked first (an overlay that is
    // off before the colour scale, the scale before what is drawn on top)
    // rather than cutting a word, and keeps the rest in order.
    let mut items: Vec<(Rank, Vec<Span>)> = Vec::new();
    if as_points > 0 {
        // It says what the picture leaves out.
        items.push((
            Rank::Vital,
            vec![Span::raw(format!(
                "{} far spheres as dots",
                crate::scene::thousands(as_points as u64)
            ))],
        ));
    }
    if app.colour {
        let ramp = app.colouring.ramp();
        let (name, lo, hi) = match app.colouring {
            Colouring::Speed => (
                "speed",
                "0".to_string(),
                format!("{} m/s", app.frame.speed_scale),
            ),
            Colouring::Depth => ("depth", "far".to_string(), "near".to_string()),
        };
        let mut scale = vec![Span::raw(format!("{name} {lo} "))];
        for &c in ramp {
            scale.push(Span::styled("█", fg(true, c)));
        }
        scale.push(Span::raw(format!(" {hi}")));
        items.push((Rank::Scale, scale));
    } else {
        items.push((Rank::Scale, vec![Span::raw("colour off (NO_COLOR)")]));
    }
    // Each overlay named in its own colour when it is on.
    let mut overlay = |name: String, on: bool, colour| {
        items.push(if on {
            (
                Rank::Drawn,
                vec![Span::styled(name, fg(app.colour, colour))],
            )
        } else {
            (Rank::Off, vec![Span::raw(format!("{name} off"))])
        });
    };
    overlay("trails".into(), app.show_trails, palette::TRAIL);
    overlay("vectors".into(), app.show_vectors, palette::VECTOR);
    let world = &app.frame.world;
    let contacts = world.contacts().len();
    let contacts_name = if contacts > MAX_CONTACT_MARKS && app.show_contacts {
        format!("contacts ({} not drawn)", contacts - MAX_CONTACT_MARKS)
    } else if app.show_contacts && contacts == 0 && world.last.contacts > 0 {
        // A large world lists them only while something reads them
        // (`Session::show_contacts`), and a step back finds them again
        // only in small worlds.
        "contacts (none listed for this step)".into()
    } else {
        "contacts".into()
    };
    overlay(contacts_name, app.show_contacts, palette::CONTACT);
    if app.frame.selection.is_some() {
        overlay("selected".into(), true, palette::SELECTION);
    }
    if app.frame.world.last.asleep > 0 {
        overlay("asleep".into(), true, palette::ASLEEP);
    }
    if app.frame.show_ghost {
        // Asked for, but with no positions at this time (past its
        // horizon), it is not drawn: the panel's ghost row says why, and
        // x twice starts it again.
        let drawn = app
            .frame
            .ghost
            .as_ref()
            .is_some_and(|g| g.unavailable.is_none());
        items.push(if drawn {
            (
                Rank::Drawn,
                vec![Span::styled(
                    "+ exact ghost",
                    fg(app.colour, palette::GHOST),
                )],
            )
        } else {
            (Rank::Off, vec![Span::raw("no ghost now")])
        });
    }
    let width = |item: &[Span]| item.iter().map(Span::width).sum::<usize>();
    let mut by_rank: Vec<usize> = (0..items.len()).collect();
    by_rank.sort_by_key(|&k| items[k].0);
    let (mut shown, mut used) = (vec![false; items.len()], 0);
    for k in by_rank {
        let gap = if used == 0 { 0 } else { 2 };
        let w = width(&items[k].1);
        if used + gap + w <= usize::from(area.width) {
            used += gap + w;
            shown[k] = true;
        }
    }
    let mut spans = Vec::new();
    for (item, _) in items.into_iter().zip(shown).filter(|(_, shown)| *shown) {
        if !spans.is_empty() {
            spans.push(Span::raw("  "));
        }
        spans.extend(item.1);
    }
    Paragraph::new(Line::from(spans)).render(area, buf);
}

/// How much a legend item matters, the first kept longest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Rank {
    /// What the picture leaves out.
    Vital,
    /// Marks drawn on the spheres: selection, contacts, trails, vectors,
    /// sleepers, the ghost.
    Drawn,
    /// The colour scale.
    Scale,
    /// An overlay that is off.
    Off,
}

/// The most rows the footer grows to for a long message.
pub(crate) const FOOTER_MAX_ROWS: u16 = 3;

/// A status message laid out in a footer `width` columns wide: one line
/// when it fits, else wrapped over up to [`FOOTER_MAX_ROWS`] lines, the
/// last cut with an ellipsis if the message goes on.
fn footer_lines(status: &str, width: u16) -> Vec<String> {
    let room = usize::from(width).saturating_sub(2);
    if status.chars().count() <= room {
        return vec![status.to_string()];
    }
    let mut lines = super::panel::wrap(status, room);
    if lines.is_empty() {
        // Nothing but spaces.
        return vec![String::new()];
    }
    let rows = usize::from(FOOTER_MAX_ROWS);
    let goes_on = lines.len() > rows;
    lines.truncate(rows);
    for (k, line) in lines.iter_mut().enumerate() {
        // A word longer than the line, or the last line of a message that
        // goes on, ends with an ellipsis.
        let longer = line.chars().count() > room;
        if longer || (goes_on && k + 1 == rows) {
            *line = line.chars().take(room.saturating_sub(1)).collect();
            line.push('\u{2026}');
        }
    }
    lines
}

/// The footer's word while input may wait for the end of an escape
/// sequence (`input.rs`): it shows until the next key acts.
pub(crate) const KEYS_HELD: &str = "an escape sequence (ESC[...) may be unfinished, and keys go into it \
     until it ends: a letter ends most, m a mouse report (ESC[<), c a query (ESC[?), \
     ESC[201~ a paste";

/// The too-small screen's short word on it.
const KEYS_HELD_SHORT: &str = "keys held by an unfinished ESC[ sequence: type m or c";

impl App {
    /// What the footer says before the key hints: that input is held,
    /// else, while the world works on an action for a while, which, else
    /// the status message.
    pub(crate) fn footer_status(&self) -> Option<Cow<'_, str>> {
        if self.timing.keys_held {
            Some(Cow::Borrowed(KEYS_HELD))
        } else if self.timing.waiting
            && let Some(working) = self.working_note()
        {
            Some(Cow::Owned(working))
        } else {
            self.status
                .as_deref()
                .or(self.status_kept.as_deref())
                .map(Cow::Borrowed)
        }
    }

    /// Rows of the footer on a screen `width` wide: one, or more while a
    /// status message needs them.
    pub(crate) fn footer_rows(&self, width: u16) -> u16 {
        self.footer_status()
            .map_or(1, |s| footer_lines(&s, width).len() as u16)
    }

    /// The room the help has: the screen above the footer, which stays in
    /// view so that what a key did behind the help can be read.
    pub(crate) fn help_space(&self) -> Size {
        let footer = self.footer_rows(self.screen.width);
        Size::new(self.screen.width, self.screen.height.saturating_sub(footer))
    }

    /// Where the parts of a screen of `area` go, now.
    pub(crate) fn areas(&self, area: Rect) -> Areas {
        Areas::with_footer(area, self.show_panel, self.footer_rows(area.width))
    }
}

fn render_footer(app: &App, area: Rect, buf: &mut Buffer) {
    let width = usize::from(area.width);
    let mut lines = Vec::new();
    let mut spans = Vec::new();
    let mut used = 0;
    if let Some(status) = app.footer_status() {
        let shown = footer_lines(&status, area.width);
        let last = shown.len() - 1;
        for (k, line) in shown.into_iter().enumerate() {
            let text = Span::styled(
                format!(" {line} "),
                Style::default().add_modifier(Modifier::REVERSED),
            );
            if k < last {
                lines.push(Line::from(text));
            } else {
                used += line.chars().count() + 3;
                spans.push(text);
                spans.push(Span::raw(" "));
            }
        }
    }
    // The key hints that fit whole.
    for (keys, hint) in keymap::footer(app.mode()) {
        let text = format!(" {hint}  ");
        let needed = keys.chars().count() + text.chars().count();
        if used + needed > width + 2 {
            break;
        }
        used += needed;
        spans.push(Span::styled(keys, fg(app.colour, palette::KEY).bold()));
        spans.push(Span::raw(text));
    }
    lines.push(Line::from(spans));
    Paragraph::new(lines).render(area, buf);
}

/// The header's word on time: paused, running at the scale asked, or, when
/// the world cannot keep up, both the scale asked and the one achieved;
/// and whether the world is still working on the last action.
pub(crate) fn header_state(app: &App) -> String {
    let pace = &app.frame.pace;
    let mut state = if app.paused {
        " paused ".to_string()
    } else if let Some(s) = app.timing.busy_for {
        // Short, so that the lesson's title beside it keeps its room.
        format!(" behind: one step has taken {s:.1} s ")
    } else {
        match pace.achieved.filter(|_| pace.behind) {
            Some(achieved) => format!(
                " behind: x{} asked, x{} achieved ",
                format_scale(app.time_scale()),
                format_achieved(achieved)
            ),
            None => format!(" running x{} ", format_scale(app.time_scale())),
        }
    };
    if app.timing.waiting {
        let what = match (app.paused, app.timing.busy_for) {
            (true, Some(s)) => format!(" working: {s:.1} s... |"),
            _ => " working... |".to_string(),
        };
        state.insert_str(0, &what);
    }
    state
}

/// An achieved time scale with two significant digits.
pub(crate) fn format_achieved(s: f64) -> String {
    if s >= 10.0 {
        format!("{s:.0}")
    } else if s >= 1.0 {
        format!("{s:.1}")
    } else if s >= 0.1 {
        format!("{s:.2}")
    } else {
        // Far behind: two figures, not x0.00 or x0.01.
        super::numbers::format_significant_to(s, 2)
    }
}

/// A time scale as a short fraction or whole number.
pub(crate) fn format_scale(s: f64) -> String {
    if s >= 1.0 {
        format!("{s}")
    } else {
        format!("1/{}", (1.0 / s).round())
    }
}
