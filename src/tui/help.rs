//! The help overlay: every entry of the key table, grouped, plus the mouse,
//! then what the picture's marks and the panel's rows mean.
//! Owns the overlay's layout; the words come from the key table.

use super::action::Action;
use super::app::App;
use super::keymap::{BINDINGS, Group, MOUSE_HELP, key_of};
use super::palette::{self, fg};
use super::panel::wrap;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect, Size};
use ratatui::style::Stylize;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget};

/// Columns of the key column.
const KEYS_WIDTH: usize = 13;
/// Widest a column of the help gets.
const COLUMN_WIDTH: u16 = 54;

/// The help's lines for one group, in a column `width` wide: each
/// description wrapped beside its keys, a column clear of the next.
fn group_lines(group: Group, colour: bool, width: u16) -> Vec<Line<'static>> {
    let mut lines = vec![Line::from(group.title().bold().underlined())];
    let text_width = usize::from(width).saturating_sub(KEYS_WIDTH + 2).max(12);
    let mut entry = |keys: String, what: String| {
        for (k, part) in wrap(&what, text_width).into_iter().enumerate() {
            let keys = if k == 0 { keys.as_str() } else { "" };
            lines.push(Line::from(vec![
                Span::styled(
                    format!(" {keys:<KEYS_WIDTH$}"),
                    fg(colour, palette::KEY).bold(),
                ),
                Span::raw(part),
            ]));
        }
    };
    for b in BINDINGS.iter().filter(|b| b.group == group) {
        let keys: Vec<String> = b.keys.iter().map(|k| k.label()).collect();
        entry(
            keys.join(" "),
            format!("{}{}", b.description, b.when.note()),
        );
    }
    if group == Group::View {
        for (what, does) in MOUSE_HELP {
            entry(format!("mouse {what}"), (*does).to_string());
        }
    }
    lines.push(Line::raw(""));
    lines
}

/// A row of the help's last section: what the picture or the panel shows,
/// and what it means. `{key}` in the meaning names the key of `key`'s
/// action, from the key table.
struct Seen {
    what: &'static str,
    means: &'static str,
    key: Option<Action>,
}

const fn row(what: &'static str, means: &'static str) -> Seen {
    Seen {
        what,
        means,
        key: None,
    }
}

const fn keyed(what: &'static str, means: &'static str, key: Action) -> Seen {
    Seen {
        what,
        means,
        key: Some(key),
    }
}

impl Seen {
    /// The meaning, with its key named.
    fn means(&self) -> String {
        match self.key {
            Some(action) => self.means.replace("{key}", &key_of(action)),
            None => self.means.to_string(),
        }
    }
}

/// What the picture's marks and the selection panel's rows mean, for the
/// help's last section.
const SEEN: &[Seen] = &[
    row(
        "white rings",
        "the selected spheres, in their own colours; every other sphere dim grey",
    ),
    row(
        "pink",
        "each contact of the step: a ring round both spheres, and the normal n through the point of contact",
    ),
    row(
        "dotted rings",
        "where a selected pair was before the step's correction",
    ),
    keyed("sand", "a sphere asleep ({key})", Action::ToggleSleep),
    keyed(
        "dashed slate",
        "the exact reference, the ghost ({key})",
        Action::ToggleGhost,
    ),
    row(
        "n",
        "the unit normal, from the pair's first sphere (1) to its second (2)",
    ),
    row(
        "delta",
        "the overlap (r1 + r2) - d that the correction removes along n",
    ),
    row(
        "found",
        "n and delta are as the step found them, and earlier contacts of the step moved the pair since: the lesson resolves each with what was found (delta then: as it stood)",
    ),
    row(
        "w/(w1+w2)",
        "each sphere's share of delta, w = 1/m: the lighter moves more",
    ),
    row(
        "v1, v2",
        "the velocities along n as the pair met; V1, V2 after the lesson's update",
    ),
    row(
        "across n",
        "each sphere's speed across n, |v - (v\u{b7}n) n|: the impulse acts along n only, so these are the same before and after",
    ),
    row(
        "e",
        "the restitution the impact used: 0 for resting contact or below the rest threshold",
    ),
    row(
        "J",
        "the impulse that fired on sphere 1 along n, m1 (V1 - v1) = -(1 + e) \u{3bc} (v1 - v2), with the reduced mass \u{3bc} (the next row) and v1 - v2 from the V1 row; sphere 2 takes its opposite, -J",
    ),
    row(
        "\u{3bc}",
        "the pair's reduced mass, m1 m2 / (m1 + m2): J changes v1 - v2 by J / \u{3bc}, to V1 - V2 = -e (v1 - v2)",
    ),
    row(
        "moved",
        "how far the correction moved each sphere: its share of delta",
    ),
    row(
        "m1v1+m2v2",
        "the pair's momentum along n before the impact, which the impulse keeps: m1V1 + m2V2 is the same sum; V1 = and V2 = work the lesson's formulas with the pair's numbers",
    ),
    keyed(
        "step end",
        "with the support pass ({key}): the pair's speeds along n at the step's end, after that pass",
        Action::ToggleSupport,
    ),
    row(
        "p, KE",
        "the pair's momentum (kept) and kinetic energy (lost unless e = 1), before and after",
    ),
    row(
        "v += g dt",
        "a sphere's step: gravity changes the velocity, then x += v dt moves it by the new v (semi-implicit Euler) or the old",
    ),
    row(
        "+ g dt²/2",
        "velocity Verlet, RK4 and the continuous method follow gravity's exact parabola: this term too",
    ),
    row(
        "motion",
        "with sub-steps or the continuous method's impacts, how the step moved the sphere instead",
    ),
    row(
        "ran with",
        "the parameters the step shown ran with, where they changed since",
    ),
    row(
        "then",
        "what the contacts, a wall or the support pass moved the sphere after its flight, so that the rows add up to its x",
    ),
    row(
        "then v",
        "what they added to its velocity: v += g dt, then + this, give its v",
    ),
    row(
        "asleep",
        "the sphere slept through the step: nothing moved it",
    ),
    row(
        "wall",
        "the wall the sphere was found past at the step's end: its velocity into it, and where the move left its centre against the centre's limit (the coordinate r at a near wall, 1 \u{2212} r at a far one), to a micrometre",
    ),
    row(
        "at wall, c",
        "w, the speed as it met the wall (under gravity, with the Euler methods, the one the energy the method keeps in flight gives: explicit Euler's can pass the speed the step began with), and the restitution c that wall used",
    ),
    row(
        "out",
        "c w, the speed it leaves with, and its velocity at the step's end",
    ),
    row(
        "back",
        "where the wall put its centre: the overshoot d mirrored and scaled by c, as its speed is (the Euler methods), so the sphere ends c d clear of the wall",
    ),
    row(
        "why",
        "at a wall: gravity acts on either side of it within the step, so the speed out need not be c_r times the speed in; for a pair whose e is 0: how fast it approached, against the resting speed or the rest threshold",
    ),
    keyed(
        "resting",
        "resting contact ({key}): an impact slower than gravity adds along its normal n in a step, |g\u{b7}n| dt, keeps no normal speed; the floor's is the largest. A threshold on speed alone: a pair this slow meeting in the air keeps none either, though gravity does not press it together",
        Action::ToggleResting,
    ),
    row(
        "took",
        "the computer's time for the last step and frame (not the simulation's dt)",
    ),
    row(
        "ghost",
        "how far the spheres are from the exact motion (RMS)",
    ),
    keyed(
        "impact",
        "the sphere's last impact, and when, since it was picked ('{key}' back to earlier steps looks at them too)",
        Action::StepBack,
    ),
];

/// The help's section on what the picture and the panel show, in a
/// column `width` wide.
fn seen_lines(colour: bool, width: u16) -> Vec<Line<'static>> {
    let mut lines = vec![Line::from("What you see".bold().underlined())];
    let text_width = usize::from(width).saturating_sub(KEYS_WIDTH + 2).max(12);
    for seen in SEEN {
        for (k, part) in wrap(&seen.means(), text_width).into_iter().enumerate() {
            let what = if k == 0 { seen.what } else { "" };
            lines.push(Line::from(vec![
                Span::styled(format!(" {what:<KEYS_WIDTH$}"), fg(colour, palette::KEY)),
                Span::raw(part),
            ]));
        }
    }
    lines
}

/// The key table as Markdown, in the help's order: what the README shows
/// (a test keeps the two equal).
pub fn markdown_table() -> String {
    let mut out = String::from("| keys | what they do |\n|---|---|\n");
    for group in Group::ALL {
        out.push_str(&format!("| **{}** | |\n", group.title()));
        for b in BINDINGS.iter().filter(|b| b.group == group) {
            let keys: Vec<String> = b
                .keys
                .iter()
                .map(|k| format!("`{}`", k.label().replace('|', "\\|")))
                .collect();
            out.push_str(&format!(
                "| {} | {}{} |\n",
                keys.join(" "),
                b.description,
                b.when.note()
            ));
        }
        if group == Group::View {
            for (what, does) in MOUSE_HELP {
                out.push_str(&format!("| mouse {what} | {does} |\n"));
            }
        }
    }
    out
}

/// The lesson's whole text, which the panel may cut: its title, idea
/// (with what no longer holds) and equation, in a column `width` wide.
fn lesson_lines(app: &App, width: u16) -> Vec<Line<'static>> {
    let (title, idea, equation) = super::panel::lesson_text(app);
    let text_width = usize::from(width).saturating_sub(1).max(12);
    let mut lines = vec![Line::from(title.bold().underlined())];
    lines.extend(
        wrap(&idea, text_width)
            .into_iter()
            .map(|l| Line::from(format!(" {l}"))),
    );
    lines.extend(
        wrap(&equation, text_width)
            .into_iter()
            .map(|l| Line::from(format!(" {l}").italic())),
    );
    lines.push(Line::raw(""));
    lines
}

/// The help's columns on a screen `screen_width` wide for `app` (its
/// lesson's text first), and the width of the popup that holds them.
fn columns(app: &App, screen_width: u16, colour: bool) -> (Vec<Vec<Line<'static>>>, u16) {
    let two = screen_width >= 2 * COLUMN_WIDTH + 4;
    // One column takes the screen's width (less the box), so that fewer
    // of its lines wrap.
    let width = if two {
        COLUMN_WIDTH
    } else {
        screen_width.saturating_sub(2)
    };
    let lines = |groups: &[Group]| -> Vec<Line<'static>> {
        groups
            .iter()
            .flat_map(|&g| group_lines(g, colour, width))
            .collect()
    };
    let mut left = lesson_lines(app, width);
    let seen = seen_lines(colour, width);
    if two {
        // The program's keys balance the lesson's text in the left column.
        left.extend(lines(&[Group::Time, Group::Lesson, Group::Program]));
        let mut right = lines(&[Group::Parameters, Group::View]);
        // What you see goes under the shorter column.
        let shorter = if left.len() <= right.len() {
            &mut left
        } else {
            &mut right
        };
        shorter.extend(seen);
        (vec![left, right], 2 * COLUMN_WIDTH + 2)
    } else {
        // One column keeps the groups in the order of the README's table.
        let mut all = left;
        all.extend(lines(&[
            Group::Time,
            Group::Lesson,
            Group::Parameters,
            Group::View,
            Group::Program,
        ]));
        all.extend(seen);
        (vec![all], width + 2)
    }
}

/// Rows of the longest column and the popup's height on `screen`.
fn rows(columns: &[Vec<Line>], screen: Size) -> (u16, u16) {
    let content_rows = columns.iter().map(Vec::len).max().unwrap_or(0) as u16;
    (content_rows, (content_rows + 2).min(screen.height))
}

/// The furthest the help scrolls on a screen of `screen`: 0 when it fits.
pub(crate) fn max_scroll(app: &App, screen: Size) -> u16 {
    let (content_rows, _) = content(app, screen);
    content_rows.saturating_sub(page(app, screen))
}

/// How many rows of the help show at once on a `screen`: what PgUp and
/// PgDn move it by.
pub(crate) fn page(app: &App, screen: Size) -> u16 {
    let (_, height) = content(app, screen);
    height.saturating_sub(2)
}

/// The help's rows, and the height of its box, on a `screen`.
fn content(app: &App, screen: Size) -> (u16, u16) {
    let (columns, _) = columns(app, screen.width, false);
    rows(&columns, screen)
}

pub(crate) fn render_help(app: &App, area: Rect, buf: &mut Buffer) {
    let screen = Size::new(area.width, area.height);
    let (columns, width) = columns(app, area.width, app.colour);
    let (_, height) = rows(&columns, screen);
    let popup = area.centered(
        Constraint::Length(width.min(area.width)),
        Constraint::Length(height),
    );
    let max_scroll = max_scroll(app, screen);
    let scroll = app.help_scroll.min(max_scroll);
    let closes = format!(
        " keys: {} or {} closes ",
        key_of(Action::ToggleHelp),
        key_of(Action::CloseHelp)
    );
    let mut block = Block::bordered().title(closes.bold());
    if max_scroll > 0 {
        block = block
            .title_bottom(Line::from(" j/k, arrows, PgUp/PgDn, Home/End scroll ").right_aligned());
    }
    Clear.render(popup, buf);
    let inner = block.inner(popup);
    block.render(popup, buf);
    let parts = Layout::horizontal(vec![Constraint::Fill(1); columns.len()]).split(inner);
    for (lines, &part) in columns.into_iter().zip(parts.iter()) {
        Paragraph::new(lines).scroll((scroll, 0)).render(part, buf);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_you_see_names_its_keys_from_the_key_table() {
        // Each row that names a key has it from the table, in brackets or
        // quotes, and no row is left with a `{key}` unfilled.
        for seen in SEEN {
            let means = seen.means();
            assert!(!means.contains('{'), "{}: {means}", seen.what);
            if let Some(action) = seen.key {
                let key = key_of(action);
                assert!(!key.is_empty(), "{}", seen.what);
                assert!(
                    means.contains(&format!("({key})")) || means.contains(&format!("'{key}'")),
                    "{}: {means}",
                    seen.what
                );
            }
        }
        let keyed = |what: &str| SEEN.iter().find(|s| s.what == what).unwrap().means();
        assert_eq!(keyed("sand"), "a sphere asleep (S)");
        assert_eq!(keyed("dashed slate"), "the exact reference, the ghost (x)");
    }
}
