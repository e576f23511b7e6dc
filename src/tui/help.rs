//! The help overlay: every entry of the key table, grouped, plus the mouse.
//! Owns the overlay's layout; the words come from the key table.

use super::app::App;
use super::keymap::{BINDINGS, Group, MOUSE_HELP};
use super::palette::{self, fg};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Stylize;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph, Widget};

/// Columns of the key column.
const KEYS_WIDTH: usize = 13;
/// Widest a column of the help gets.
const COLUMN_WIDTH: u16 = 54;

/// The help's lines for one group.
fn group_lines(group: Group, colour: bool) -> Vec<Line<'static>> {
    let mut lines = vec![Line::from(group.title().bold().underlined())];
    for b in BINDINGS.iter().filter(|b| b.group == group) {
        let keys: Vec<String> = b.keys.iter().map(|k| k.label()).collect();
        lines.push(Line::from(vec![
            Span::styled(
                format!(" {:<KEYS_WIDTH$}", keys.join(" ")),
                fg(colour, palette::KEY).bold(),
            ),
            Span::raw(format!("{}{}", b.description, b.when.note())),
        ]));
    }
    if group == Group::View {
        for (what, does) in MOUSE_HELP {
            lines.push(Line::from(vec![
                Span::styled(
                    format!(" {:<KEYS_WIDTH$}", format!("mouse {what}")),
                    fg(colour, palette::KEY).bold(),
                ),
                Span::raw(*does),
            ]));
        }
    }
    lines.push(Line::raw(""));
    lines
}

pub fn render_help(app: &App, area: Rect, buf: &mut Buffer) {
    let left: Vec<Line> = [Group::Time, Group::Lesson, Group::Program]
        .into_iter()
        .flat_map(|g| group_lines(g, app.colour))
        .collect();
    let right: Vec<Line> = [Group::Parameters, Group::View]
        .into_iter()
        .flat_map(|g| group_lines(g, app.colour))
        .collect();
    let two_columns = area.width >= 2 * COLUMN_WIDTH + 4;
    let (columns, width) = if two_columns {
        (vec![left, right], 2 * COLUMN_WIDTH + 2)
    } else {
        let mut all = left;
        all.extend(right);
        (
            vec![all],
            COLUMN_WIDTH.min(area.width.saturating_sub(2)) + 2,
        )
    };
    let content_rows = columns.iter().map(Vec::len).max().unwrap_or(0) as u16;
    let height = (content_rows + 2).min(area.height);
    let popup = centred(area, width.min(area.width), height);
    let visible = height.saturating_sub(2);
    let max_scroll = content_rows.saturating_sub(visible);
    let scroll = app.help_scroll.min(max_scroll);
    let mut block = Block::bordered().title(" keys: ? or Esc closes ".bold());
    if max_scroll > 0 {
        block = block.title_bottom(Line::from(" j/k or arrows scroll ").right_aligned());
    }
    Clear.render(popup, buf);
    let inner = block.inner(popup);
    block.render(popup, buf);
    let parts = Layout::horizontal(vec![Constraint::Fill(1); columns.len()]).split(inner);
    for (lines, &part) in columns.into_iter().zip(parts.iter()) {
        Paragraph::new(lines).scroll((scroll, 0)).render(part, buf);
    }
}

fn centred(area: Rect, width: u16, height: u16) -> Rect {
    Rect {
        x: area.x + area.width.saturating_sub(width) / 2,
        y: area.y + area.height.saturating_sub(height) / 2,
        width,
        height,
    }
}
