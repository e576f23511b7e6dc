//! The side panel: the lesson (title, idea, equation), the live
//! parameters, the live readouts and the energy chart.
//!
//! Owns the panel's wording and layout; it reads the app and never changes
//! it. When the terminal is short, the lesson's idea and the section
//! headers give up their lines, and the chart shrinks to its minimum.

use super::action::Action;
use super::app::{App, SelectionBox};
use super::draw_rate::BUSY_FPS;
use super::energy_chart::render_energy_chart;
use super::energy_log::Sample;
use super::keymap::key_of;
use super::numbers::{
    broad_phase_name, format_dt, format_energies, format_energy, format_significant,
    format_significant_to, whole_per_second,
};
use super::selection::{ImpactKind, Inspection, PairReadout, PairRule, SphereReadout};
use super::session::gravity_name;
use super::view::format_scale;
use crate::scene::rules::unsigned_zero;
use crate::scene::{spheres, thousands};
use crate::sim::broad_phase::all_pairs_tests;
use crate::sim::walls::AxisImpact;
use crate::sim::{BroadPhase, Integrator, StepStats, Vec3, WallMode, WorldConfig};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Stylize;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget};

/// Rows the chart keeps however short the terminal (it needs 5 to draw).
const CHART_MIN_ROWS: u16 = 6;

pub(crate) fn render_panel(app: &App, area: Rect, buf: &mut Buffer) {
    let text_width = usize::from(area.width.saturating_sub(2)).max(1);
    let params = parameter_lines(app, text_width);
    let readouts = readout_lines(app);
    let (title, idea, equation) = lesson_text(app);

    let equation_lines = wrap(&equation, text_width);
    let idea_lines = wrap(&idea, text_width);
    // Rows that always show: top border, title, equation, parameters, readouts.
    let essential = 2 + equation_lines.len() + params.len() + readouts.len();
    // A selection's numbers come before the lesson's idea and the headers.
    // The selection's box takes all but the panel's top border, title,
    // first equation row and time (and its own two borders); where its
    // rows would still give way, the equation's row gives way to them (a
    // pair's worked sums write the equation out with its numbers).
    // The same selection at the same size keeps the most rows its box has
    // had, and the equation's row once given, so that the rows above the
    // box stay put while the numbers change (`SelectionBox`).
    let selection_rows = usize::from(area.height).saturating_sub(6);
    let held = app.selection_box.get().filter(|held| {
        app.frame
            .inspection
            .as_ref()
            .is_some_and(|i| i.selection == held.selection && held.area == area)
    });
    let selection = app.frame.inspection.as_ref().map(|i| {
        let now = &app.frame.world.config;
        let within = |rows| selection_lines_within(i, now, text_width, rows);
        let given_up = held.is_some_and(|h| h.equation_given_up)
            || (within(usize::MAX).len() > selection_rows && selection_rows > 0);
        let rows = if given_up {
            within(selection_rows + 1)
        } else {
            within(selection_rows)
        };
        let box_rows = rows.len().max(held.map_or(0, |h| h.rows));
        app.selection_box.set(Some(SelectionBox {
            selection: i.selection,
            area,
            rows: box_rows,
            equation_given_up: given_up,
        }));
        (rows, box_rows, given_up)
    });
    if selection.is_none() {
        app.selection_box.set(None);
    }
    let equation_given_up = selection.as_ref().is_some_and(|(_, _, given_up)| *given_up);
    let box_rows = selection.as_ref().map_or(0, |(_, box_rows, _)| *box_rows);
    let selection = selection.map(|(rows, _, _)| rows);
    // Below the text: a selection's box, or the energy chart where the
    // essential rows leave it room, or else only the text's bottom border
    // (the rows the chart cannot use go to the lesson's idea).
    let below = match &selection {
        Some(_) => box_rows + 2,
        None if usize::from(area.height) >= essential + usize::from(CHART_MIN_ROWS) => {
            usize::from(CHART_MIN_ROWS)
        }
        None => 1,
    };
    let spare = usize::from(area.height).saturating_sub(essential + below);
    // The section headers only where the whole idea fits with them: the
    // idea is worth more than they are.
    let headers = spare >= idea_lines.len() + 2;
    let idea_shown = idea_lines
        .len()
        .min(spare.saturating_sub(if headers { 2 } else { 0 }));

    let mut lines = vec![Line::from(title.bold())];
    let idea_cut = idea_shown < idea_lines.len();
    let mut idea_lines: Vec<String> = idea_lines.into_iter().take(idea_shown).collect();
    if idea_cut && let Some(last) = idea_lines.last_mut() {
        end_with_ellipsis(last, text_width);
    }
    lines.extend(idea_lines.into_iter().map(Line::from));
    let equation = lines.len()..lines.len() + equation_lines.len();
    lines.extend(equation_lines.into_iter().map(|l| Line::from(l.italic())));
    if headers {
        lines.push(Line::from("Parameters".bold().underlined()));
    }
    lines.extend(params);
    if headers {
        lines.push(Line::from("Readouts".bold().underlined()));
    }
    lines.extend(readouts);

    let block = Block::default().borders(Borders::LEFT | Borders::TOP | Borders::RIGHT);
    // With a selection, its numbers come before the panel's own: the
    // readouts give way from the bottom, then the parameters, down to the
    // title and the equation's first line (or the title alone, where the
    // equation's row went to the selection); the step's time stays.
    if selection.is_some() {
        let kept = if equation_given_up { 1 } else { 2 };
        let room = usize::from(area.height)
            .saturating_sub(box_rows + 2)
            .max(kept + 1)
            - 1;
        let time = lines
            .iter()
            .rposition(|l| line_text(l).starts_with(" time "));
        let mut k = lines.len();
        while lines.len() > room && k > kept {
            k -= 1;
            if Some(k) != time {
                lines.remove(k);
            }
        }
        // An equation cut short says so with an ellipsis, as the idea does.
        if equation.start < k && k < equation.end {
            let last = k - 1;
            let mut text = line_text(&lines[last]);
            end_with_ellipsis(&mut text, text_width);
            lines[last] = Line::from(text.italic());
        }
    }
    let mut text_rows = (lines.len() as u16 + 1).min(area.height);
    // With neither a selection nor room for the chart below, the text's
    // own frame closes the panel at the bottom.
    let chart_fits = area.height.saturating_sub(text_rows) >= CHART_MIN_ROWS;
    let block = if selection.is_none() && !chart_fits {
        text_rows = area.height;
        block.borders(Borders::ALL)
    } else {
        block
    };
    let [text_area, chart_area] =
        Layout::vertical([Constraint::Length(text_rows), Constraint::Fill(1)]).areas(area);
    let inner = block.inner(text_area);
    block.render(text_area, buf);
    // A row longer than the panel ends in an ellipsis, not mid-number.
    let width = usize::from(inner.width);
    let lines: Vec<Line> = lines.into_iter().map(|l| cut_to(l, width)).collect();
    Paragraph::new(lines).render(inner, buf);
    // A selection's numbers take the place of the energy chart.
    match selection {
        Some(rows) => {
            let title = format!(" selection ({} forgets) ", key_of(Action::ClearSelection));
            let block = Block::bordered().title(Line::from(title.bold()));
            let inner = block.inner(chart_area);
            block.render(chart_area, buf);
            Paragraph::new(rows).render(inner, buf);
        }
        None if chart_fits => {
            render_energy_chart(&app.frame.energy, app.colour, chart_area, buf);
        }
        None => {}
    }
}

/// The selected spheres' numbers, and for a pair in contact the lesson's
/// equations with the pair's own values, for the step as it ran (with the
/// parameters it ran with, whatever they are now).
#[cfg(test)]
pub(crate) fn selection_lines(inspection: &Inspection, width: usize) -> Vec<Line<'static>> {
    selection_lines_within(inspection, &inspection.config, width, usize::MAX)
}

/// What the step shown ran with that has changed since (`now`): the
/// method, dt, gravity, the walls, the pairs' rules and passes; empty when
/// nothing has.
fn changed_since(then: &WorldConfig, now: &WorldConfig) -> Vec<String> {
    let mut changed = Vec::new();
    if then.integrator != now.integrator {
        changed.push(then.integrator.name().to_string());
    }
    if then.dt != now.dt {
        changed.push(format!("dt {}", format_dt(then.dt)));
    }
    if then.gravity != now.gravity {
        changed.push(format!("g {:.2} m/s^2", then.gravity.length()));
    }
    match then.wall_mode {
        WallMode::Flip if now.wall_mode != WallMode::Flip => changed.push("flip walls".into()),
        WallMode::Restitution
            if now.wall_mode != WallMode::Restitution
                || then.wall_restitution != now.wall_restitution =>
        {
            changed.push(format!("c_r {:.2}", then.wall_restitution));
        }
        _ => {}
    }
    if then.pair_restitution != now.pair_restitution && then.pair_collisions {
        changed.push(format!("e {:.2}", then.pair_restitution));
    }
    let on = |b: bool| if b { "on" } else { "off" };
    if then.pair_collisions != now.pair_collisions {
        changed.push(format!("pair collisions {}", on(then.pair_collisions)));
    }
    if (then.rest_steps > 0.0) != (now.rest_steps > 0.0) {
        changed.push(format!("resting contact {}", on(then.rest_steps > 0.0)));
    } else if then.rest_steps != now.rest_steps {
        changed.push(format!("rest_steps {}", then.rest_steps));
    }
    if then.rest_threshold != now.rest_threshold {
        changed.push(format!("rest threshold {} m/s", then.rest_threshold));
    }
    if then.support != now.support {
        changed.push(format!("support pass {}", on(then.support)));
    }
    if then.substeps != now.substeps {
        changed.push(format!("{} sub-steps", then.substeps));
    }
    if then.projection_passes != now.projection_passes {
        changed.push(format!("{} projection passes", then.projection_passes));
    }
    changed
}

/// The selection's lines (`selection_lines`, for the tests: all of them)
/// in at most `rows` rows where it can: the rows of a sphere's flight
/// over the step (`v += g dt`, `x += v dt`, ...) give way
/// first, last sphere first, so that what it met and the velocity out
/// stay in view, then a wall impact's `why`, then the position, velocity,
/// speed, radius and mass of a sphere at a wall (its wall rows give the
/// component and the coordinate that met the wall); for a pair, its
/// momentum and energy first, then how far each sphere moved, their
/// radii and why its e is 0, then the lesson's sums. Rows that still do not fit are cut, the last one shown
/// ending in an ellipsis.
fn selection_lines_within(
    inspection: &Inspection,
    now: &WorldConfig,
    width: usize,
    rows: usize,
) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    // The numbers are the step's as it ran: say with what, where the
    // parameters shown above have changed since.
    let changed = changed_since(&inspection.config, now);
    if !changed.is_empty() {
        lines.extend(wrapped_row(
            width,
            "ran with",
            format!("{} (changed since)", changed.join(", ")),
        ));
    }
    // The rows that give way, as ranges of `lines`, each with its rank:
    // the lowest rank gives way first, then the last rows first.
    let mut give_way: Vec<(u8, std::ops::Range<usize>)> = Vec::new();
    let c = &inspection.config;
    let dt = c.dt;
    match (&inspection.pair, inspection.spheres.as_slice()) {
        (Some(pair), [a, b]) => {
            lines.push(Line::from(
                format!("Pair {} & {}: found in contact", a.id, b.id).bold(),
            ));
            // The masses to the figures the momentum row needs to check by
            // hand, in every row that shows them.
            let [m1, m2] = pair.mass;
            let digits = digits_that_add_up(
                [(m1, pair.v_normal[0]), (m2, pair.v_normal[1])],
                m1 * pair.v_normal[0] + m2 * pair.v_normal[1],
            );
            let mass = |m: f64| format_significant_to(m, digits);
            lines.extend(wrapped_row(
                width,
                "m1, m2",
                format!("{}, {} kg", mass(m1), mass(m2)),
            ));
            let radii = lines.len();
            lines.extend(wrapped_row(
                width,
                "r1, r2",
                format!("{} m", two_significant([a.radius, b.radius])),
            ));
            give_way.push((1, radii..lines.len()));
            lines.extend(wrapped_row(width, "n", format_vector(pair.normal)));
            lines.extend(wrapped_row(
                width,
                "delta",
                format!("{} = (r1 + r2) - d", format_length(pair.penetration)),
            ));
            // The lesson resolves each contact with the normal and overlap
            // the narrow phase found; an earlier contact of the step may
            // have moved either sphere since. Said where it shows.
            let reach = a.radius + b.radius;
            let apart = pair.before[1] - pair.before[0];
            let then = reach - apart.length();
            let turned = format_vector(apart.normalize_or_zero()) != format_vector(pair.normal);
            if turned || format_length(then) != format_length(pair.penetration) {
                let found = lines.len();
                lines.extend(wrapped_row(
                    width,
                    "found",
                    format!(
                        "n, delta as found; earlier contacts of the step moved the pair \
                         before its turn: (r1 + r2) - d = {} then",
                        format_length(then)
                    ),
                ));
                give_way.push((1, found..lines.len()));
            }
            // `w = 1/m` where it fits on the row (the help says it too).
            let shares = format!(
                "{} of delta",
                shares_that_check(pair.share, pair.penetration)
            );
            let with_w = format!("{shares}; w = 1/m");
            let fits = with_w.chars().count() + LABEL_WIDTH <= width;
            lines.extend(wrapped_row(
                width,
                "w/(w1+w2)",
                if fits { with_w } else { shares },
            ));
            // What each sphere moved; gives way when the panel is short.
            let moved = lines.len();
            lines.extend(wrapped_row(
                width,
                "moved",
                format!(
                    "1 by {} against n, 2 by {} along n",
                    format_length(pair.share[0] * pair.penetration),
                    format_length(pair.share[1] * pair.penetration)
                ),
            ));
            give_way.push((1, moved..lines.len()));
            lines.extend(wrapped_row(
                width,
                "v1, v2",
                format!("{} m/s along n", two(pair.v_normal)),
            ));
            match pair.v_after {
                Some([v1, v2]) => {
                    // Why e is 0, where it is not the scene's, gives way
                    // before the sums that check it.
                    let (e, why) = pair_coefficient(pair, c);
                    lines.extend(wrapped_row(width, "e", e));
                    if let Some(why) = why {
                        let at = lines.len();
                        lines.extend(wrapped_row(width, "why", why));
                        give_way.push((1, at..lines.len()));
                    }
                    // The speeds after, which the worked sums below end
                    // with: this row gives way last before them, so that
                    // they stay, and comes back where they go.
                    let after = lines.len();
                    lines.extend(wrapped_row(
                        width,
                        "V1, V2",
                        format!("{} m/s along n", two([v1, v2])),
                    ));
                    give_way.push((2, after..lines.len()));
                    // What the impulse, along n, leaves: each sphere's
                    // speed across n. Gives way after J.
                    let across = lines.len();
                    lines.extend(wrapped_row(
                        width,
                        "across n",
                        format!("{} m/s, kept", two(pair.v_across)),
                    ));
                    give_way.push((0, across..lines.len()));
                    // The impulse that fired on 1 along n, m1 (V1 - v1),
                    // 2 taking its opposite: written with v1 - v2, which
                    // the V1 row gives to four figures, where V1 - v1 from
                    // the rows' three decimals can be all rounding (a
                    // heavy sphere 1, a slow approach). Three figures.
                    // It gives way after the pair's momentum and energy,
                    // and after the row of its mu.
                    let [u1, u2] = pair.v_normal;
                    let j = -(1.0 + pair.e) * m1 * m2 / (m1 + m2) * (u1 - u2);
                    let impulse = lines.len();
                    lines.extend(wrapped_row(
                        width,
                        "J",
                        format!("-(1+e)\u{3bc}(v1-v2) = {} N s", format_significant_to(j, 3)),
                    ));
                    give_way.push((0, impulse..lines.len()));
                    // The reduced mass the impulse is written with, to
                    // four figures, so that J checks by hand from it and
                    // the V1 row's v1 - v2; gives way just before J.
                    let reduced = lines.len();
                    lines.extend(wrapped_row(
                        width,
                        "\u{3bc}",
                        format!(
                            "m1m2/(m1+m2) = {} kg",
                            format_significant(m1 * m2 / (m1 + m2))
                        ),
                    ));
                    give_way.push((0, reduced..lines.len()));
                    // The lesson's V1 and V2 with this pair's numbers; these
                    // rows give way first when the panel is short.
                    let worked = lines.len();
                    let ([u1, u2], e) = (pair.v_normal, pair.e);
                    let p = m1 * u1 + m2 * u2;
                    let total = m1 + m2;
                    let sig = format_significant;
                    // The masses and velocities to four figures, or more
                    // where the products of those shown would not add up
                    // to the sum shown: the row checks by hand.
                    let fig = |v: f64| format_significant_to(v, digits);
                    lines.extend(wrapped_row(
                        width,
                        "m1v1+m2v2",
                        format!(
                            "{} \u{d7} {} + {} \u{d7} {} = {} kg m/s",
                            fig(m1),
                            signed(fig(u1)),
                            fig(m2),
                            signed(fig(u2)),
                            sig(p)
                        ),
                    ));
                    // As the lesson writes them: V1 with m2 (v1 - v2), V2
                    // with m1 (v2 - v1); each number to four figures, or
                    // more where those shown would not give the V shown.
                    let e_text = exactly(e);
                    let e_shown = e_text.parse().unwrap_or(e);
                    for (name, m, apart, v) in
                        [("V1 =", m2, u1 - u2, v1), ("V2 =", m1, u2 - u1, v2)]
                    {
                        let figures = digits_that_give(v, |d| {
                            let shown = |x: f64| shown_to(x, d);
                            (shown(p) - shown_to(m, d.max(digits)) * shown(apart) * e_shown)
                                / shown(total)
                        });
                        let sig = |x: f64| format_significant_to(x, figures);
                        lines.extend(wrapped_row(
                            width,
                            name,
                            format!(
                                "({} - {} \u{d7} {} \u{d7} {e_text}) / {} = {}",
                                sig(p),
                                format_significant_to(m, figures.max(digits)),
                                signed(sig(apart)),
                                sig(total),
                                format_number(v)
                            ),
                        ));
                    }
                    give_way.push((3, worked..lines.len()));
                }
                None => lines.extend(wrapped_row(
                    width,
                    "V1, V2",
                    "separating: no impulse".to_string(),
                )),
            }
            // Where the support pass left the pair; gives way with what
            // each sphere moved.
            if let Some(end) = pair.step_end {
                let at = lines.len();
                lines.extend(wrapped_row(
                    width,
                    "step end",
                    format!(
                        "{} m/s along n, after the support pass, which solves the \
                         pair with what it rests on and pushes out overlaps",
                        two(end)
                    ),
                ));
                give_way.push((1, at..lines.len()));
            }
            // The pair's momentum and energy, before and after: they give
            // way before the lesson's sums, which show the same momentum.
            let totals = lines.len();
            lines.extend(wrapped_row(
                width,
                "p before",
                format!("{} kg m/s", format_vector(pair.momentum[0])),
            ));
            lines.extend(wrapped_row(
                width,
                "p after",
                format!("{} kg m/s", format_vector(pair.momentum[1])),
            ));
            let (before, after) = format_energies(pair.kinetic[0], pair.kinetic[1]);
            lines.extend(wrapped_row(width, "KE", format!("{before} -> {after}")));
            give_way.push((0, totals..lines.len()));
        }
        (None, spheres) => {
            if let (Some(note), [a, b]) = (&inspection.pair_note, spheres) {
                lines.push(Line::from(format!("Pair {} & {}", a.id, b.id).bold()));
                lines.extend(wrapped_row(width, "", note.clone()));
            }
            // Moved impact by impact (the continuous method), not by one
            // flight over dt.
            let event_driven = |s: &SphereReadout| {
                // One parabola over dt gives its x and v, to rounding, or
                // something (an impact, a resting contact) changed them.
                let one_flight = s.previous.is_some_and(|(x0, v0)| {
                    let g = c.gravity;
                    let x = x0 + v0 * dt + 0.5 * g * dt * dt;
                    x.abs_diff_eq(s.position, 1e-9) && (v0 + g * dt).abs_diff_eq(s.velocity, 1e-9)
                });
                c.integrator == Integrator::Continuous
                    && (s.in_contact || s.wall_now.is_some() || !one_flight)
            };
            // The rows of one dt's flight, x += v dt: shown or not.
            let flight_shown = |s: &SphereReadout| !s.asleep && !event_driven(s) && c.substeps <= 1;
            // The spheres' centres to the decimals with which their rows
            // add up by hand (three, or more), the same for the two of a
            // pair where some number of them serves both.
            let flown: Vec<&SphereReadout> = spheres.iter().filter(|s| flight_shown(s)).collect();
            let shared = flight_decimals(&flown, c);
            for s in spheres {
                lines.push(Line::from(format!("Sphere {}", s.id).bold()));
                let event_driven = event_driven(s);
                let flight_shown = flight_shown(s);
                let decimals = match shared {
                    Some(d) if flight_shown => d,
                    _ if flight_shown => flight_decimals(&[s], c).unwrap_or(3),
                    _ => 3,
                };
                let at = |v: Vec3| format_vector_to(v, decimals);
                let readout = lines.len();
                lines.extend(wrapped_row(width, "x", format!("{} m", at(s.position))));
                lines.extend(wrapped_row(
                    width,
                    "v",
                    format!("{} m/s", format_vector(s.velocity)),
                ));
                lines.extend(wrapped_row(
                    width,
                    "speed",
                    format!("{} m/s", format_number(s.velocity.length())),
                ));
                lines.extend(wrapped_row(
                    width,
                    "r, m",
                    format!(
                        "{} m, {} kg",
                        format_significant(s.radius),
                        format_significant(s.mass)
                    ),
                ));
                let readout = readout..lines.len();
                let flight_start = lines.len();
                if s.asleep {
                    lines.extend(wrapped_row(
                        width,
                        "asleep",
                        "the step left it where it was, at rest until something touches it"
                            .to_string(),
                    ));
                } else if event_driven {
                    // Not one flight over dt: the step's own formulas would
                    // not give its x and v.
                    lines.extend(wrapped_row(
                        width,
                        "motion",
                        "impact by impact: free flight (x += v t + g t²/2) to each \
                         impact of the step, that impact's rule, then on to the step's end"
                            .to_string(),
                    ));
                } else if c.substeps > 1 && s.previous.is_some() {
                    lines.extend(wrapped_row(
                        width,
                        "motion",
                        format!(
                            "{} sub-steps of dt/{}, each the whole step (flight, contacts, \
                             walls) over its part of dt",
                            c.substeps, c.substeps
                        ),
                    ));
                } else if let Some((x0, v0)) = s.previous {
                    let g = c.gravity;
                    if g != Vec3::ZERO && g.x == 0.0 && g.z == 0.0 {
                        lines.extend(wrapped_row(
                            width,
                            "v += g dt",
                            format!(
                                "v_y {} + ({}) {} = {}",
                                format_number(v0.y),
                                format_number(g.y),
                                format_dt_short(dt),
                                format_number(v0.y + g.y * dt)
                            ),
                        ));
                    } else if g != Vec3::ZERO {
                        // Gravity off the y axis: every component.
                        lines.extend(wrapped_row(
                            width,
                            "v += g dt",
                            format!(
                                "{} + {} {} = {}",
                                format_vector(v0),
                                format_vector(g),
                                format_dt_short(dt),
                                format_vector(v0 + g * dt)
                            ),
                        ));
                    }
                    lines.extend(wrapped_row(width, "x += v dt", format!("{} +", at(x0))));
                    let (v_used, parabola) = c.integrator.position_update(v0, g, dt);
                    // Which v: under gravity the methods differ (the
                    // lesson's equation moves with v(t)).
                    let which = match (g != Vec3::ZERO, c.integrator) {
                        (false, _) => "",
                        (true, Integrator::SemiImplicitEuler) => ", the new v",
                        (true, _) => ", the old v",
                    };
                    lines.extend(wrapped_row(
                        width,
                        "",
                        format!("{} {}{which}", at(v_used), format_dt_short(dt)),
                    ));
                    let term = parabola.filter(|_| g != Vec3::ZERO);
                    if let Some(term) = term {
                        lines.extend(wrapped_row(
                            width,
                            "+ g dt²/2",
                            format_shift(term, decimals),
                        ));
                    }
                    // What the later stages moved it, so that the rows add
                    // up to its x: a contact's correction, a wall's.
                    let flight = x0 + v_used * dt + term.unwrap_or(Vec3::ZERO);
                    let rest = s.position - flight;
                    // Shown only where it reads as more than 0 (half a
                    // thousandth of a millimetre).
                    if rest.abs().max_element() >= 5e-7 {
                        let by = later_stages(c, s);
                        lines.extend(wrapped_row(
                            width,
                            "then",
                            format!(
                                "{} by {by}: x = {}",
                                format_shift(rest, decimals),
                                at(s.position)
                            ),
                        ));
                    }
                    // And what they did to its velocity, where it shows.
                    let v_rest = s.velocity - (v0 + g * dt);
                    if v_rest.abs().max_element() >= 5e-4 {
                        lines.extend(wrapped_row(
                            width,
                            "then v",
                            format!(
                                "+ {} m/s by {}: v = {}",
                                format_vector(v_rest),
                                later_stages(c, s),
                                format_vector(s.velocity)
                            ),
                        ));
                    }
                }
                give_way.push((0, flight_start..lines.len()));
                match (s.wall_now, s.wall_impacts.as_slice()) {
                    (Some(_), impacts @ [_, ..]) => {
                        // The wall rows give the component and the
                        // coordinate that met the wall: the readout above
                        // gives way after their `why`.
                        give_way.push((1, readout));
                        let shown = walls_shown(impacts);
                        for (k, shown_now) in shown.iter().enumerate() {
                            // Another wall on this axis follows in the step.
                            let more = match (shown_now, shown.get(k + 1)) {
                                (WallShown::Impact(i), Some(WallShown::Impact(next))) => {
                                    next.axis == i.axis
                                }
                                (_, Some(WallShown::Between { .. })) => true,
                                _ => false,
                            };
                            let i = match *shown_now {
                                WallShown::Impact(i) => i,
                                WallShown::Between { axis, walls } => {
                                    lines.extend(wrapped_row(
                                        width,
                                        "then",
                                        format!(
                                            "{walls} more walls along {}, each rebound \
                                             carrying it across the box, 1 \u{2212} 2r = {} \
                                             wide, to the other wall; the last:",
                                            ["x", "y", "z"][axis],
                                            format_length(1.0 - 2.0 * s.radius)
                                        ),
                                    ));
                                    continue;
                                }
                            };
                            let wall = ImpactKind::Wall {
                                axis: i.axis,
                                far: i.far,
                            };
                            let (rows, why) = wall_rows(width, wall, i, more, s.radius, c);
                            lines.extend(rows);
                            if why > 0 {
                                give_way.push((1, lines.len() - why..lines.len()));
                            }
                        }
                    }
                    (Some(wall), []) => lines.extend(wrapped_row(
                        width,
                        "wall",
                        if c.integrator == Integrator::Continuous {
                            format!(
                                "{}: v <- -c_r v at the instant of impact, c_r = {:.2}",
                                wall.describe(),
                                c.wall_coefficient()
                            )
                        } else {
                            format!(
                                "{}, c_r = {:.2}; other stages moved it too in this \
                                 step (a contact, projection passes, the support pass \
                                 or sub-steps), so its wall numbers are not shown",
                                wall.describe(),
                                c.wall_coefficient()
                            )
                        },
                    )),
                    (None, _) => {}
                }
                lines.extend(wrapped_row(
                    width,
                    "impact",
                    match s.last_impact {
                        // The wall rows above show a contact the log of
                        // impacts leaves out: one held as resting contact.
                        last if s.wall_now.is_some()
                            && last.is_none_or(|i| i.steps < inspection.steps)
                            && s.wall_impacts
                                .iter()
                                .any(|i| i.rests || i.coefficient == 0.0) =>
                        {
                            format!(
                                "{} in this step, resting contact (no bounce)",
                                s.wall_now.map(|w| w.describe()).unwrap_or_default()
                            )
                        }
                        Some(i) => format!(
                            "{} at step {} ({:.3} s)",
                            i.kind.describe(),
                            i.steps,
                            i.time
                        ),
                        None if inspection.impacts_known_from < inspection.steps => {
                            format!("none since step {}", inspection.impacts_known_from)
                        }
                        None if inspection.impacts_known_from == inspection.steps => {
                            format!(
                                "none in this step (noted from here on; '{}' steps back to \
                                 look earlier)",
                                key_of(Action::StepBack)
                            )
                        }
                        // A state whose step cannot be told (the one
                        // before it is no longer kept) precedes the log.
                        None => format!(
                            "unknown at this step (the log starts at step {})",
                            inspection.impacts_known_from
                        ),
                    },
                ));
            }
        }
        (Some(_), _) => {}
    }
    give_way.sort_by_key(|(rank, range)| (*rank, std::cmp::Reverse(range.start)));
    // The rows that give way to fit `room` rows.
    let fit = |room: usize| {
        let (mut left, mut dropped) = (lines.len(), Vec::new());
        for (_, range) in &give_way {
            if left <= room {
                break;
            }
            left -= range.len();
            dropped.push(range.clone());
        }
        // Rows given way before the last that fit again come back, the
        // latest first.
        for k in (0..dropped.len().saturating_sub(1)).rev() {
            if left + dropped[k].len() <= room {
                left += dropped.remove(k).len();
            }
        }
        dropped
    };
    // Where rows give way, the last row says how many (where there are
    // two rows or more), which takes a row.
    let mut dropped = fit(rows);
    let noted = !dropped.is_empty() && rows >= 2;
    let room = if noted { rows - 1 } else { rows };
    if noted {
        dropped = fit(room);
    }
    let mut left_out: usize = dropped.iter().map(ExactSizeIterator::len).sum();
    // From the last rows up, so that each range still names its rows.
    dropped.sort_by_key(|range| std::cmp::Reverse(range.start));
    for range in dropped {
        lines.drain(range);
    }
    // What still does not fit is cut, and the last row shown says so (and
    // the count of those left out counts it).
    if lines.len() > room && room > 0 {
        left_out += lines.len() - room;
        lines.truncate(room);
        if let Some(last) = lines.last_mut() {
            let mut text = line_text(last);
            let room = width.min(text.chars().count() + 1);
            end_with_ellipsis(&mut text, room);
            *last = Line::from(text);
        }
    }
    if noted {
        let what = if left_out == 1 { "row" } else { "rows" };
        // The whole note where it fits, else its count alone, not a
        // sentence cut mid-word.
        let mut note = Some(format!(" ({left_out} more {what} in a taller terminal)"))
            .filter(|n| n.chars().count() <= width)
            .unwrap_or_else(|| format!(" ({left_out} {what} left out)"));
        if note.chars().count() > width {
            end_with_ellipsis(&mut note, width);
        }
        lines.push(Line::from(note).dim());
    }
    lines
}

/// The restitution a pair's impact used, and why when it is not the
/// step's `e`: resting contact, or the rest threshold.
fn pair_coefficient(pair: &PairReadout, c: &WorldConfig) -> (String, Option<String>) {
    let approach = pair.v_normal[0] - pair.v_normal[1];
    match pair.rule(c) {
        PairRule::Scene => (format!("{:.2}", pair.e), None),
        PairRule::RestThreshold => {
            let (approach, threshold) = format_apart(approach, c.rest_threshold);
            (
                "0: under the rest threshold".into(),
                Some(format!(
                    "approached at {approach} m/s, slower than its {threshold} m/s"
                )),
            )
        }
        PairRule::Resting => {
            let resting = c.resting(c.substep_dt()).dot(pair.normal).abs();
            let (approach, resting) = format_apart(approach, resting);
            (
                format!("0: resting contact (key {})", key_of(Action::ToggleResting)),
                Some(format!(
                    "approached at {approach} m/s, under |g\u{b7}n| dt = {resting} m/s"
                )),
            )
        }
    }
}

/// Two numbers compared, each as [`format_number`] gives it, with the
/// decimals (or figures) that tell them apart where the usual ones read
/// the same: `0.01154` against `0.01161`, not `0.012` against `0.012`.
fn format_apart(a: f64, b: f64) -> (String, String) {
    let usual = (format_number(a), format_number(b));
    if usual.0 != usual.1 || a == b {
        return usual;
    }
    let plain = (1e-3..1e4).contains(&a.abs().max(b.abs()));
    (1..=MORE_DECIMALS)
        .map(|more| {
            let at = |v: f64| {
                if plain {
                    let decimals = 3 + more;
                    unsigned_zero(format!("{v:.decimals$}"))
                } else {
                    let decimals = 2 + more;
                    format!("{v:.decimals$e}")
                }
            };
            (at(a), at(b))
        })
        .find(|(x, y)| x != y)
        .unwrap_or(usual)
}

/// Decimals [`format_apart`] may add.
const MORE_DECIMALS: usize = 6;

/// The rows of a wall impact as the wall stage resolved it, with the
/// parameters `c` of its step: what it met, the speed at the wall, the
/// coefficient and why, and the velocity out; and how many of the last
/// rows are the `why` (0 when there is none).
fn wall_rows(
    width: usize,
    wall: ImpactKind,
    i: &AxisImpact,
    more: bool,
    r: f64,
    c: &WorldConfig,
) -> (Vec<Line<'static>>, usize) {
    let v = format!("v_{}", ["x", "y", "z"][i.axis]);
    let along = c.gravity[i.axis] != 0.0;
    let mut lines = wrapped_row(
        width,
        "wall",
        format!(
            "{}: {v} = {} m/s, {}",
            wall.describe(),
            format_number(i.before),
            past_the_wall(i, r)
        ),
    );
    // The mirror with gravity along the axis works on the method's own
    // velocity in flight, `v + k g dt` (`walls.rs`, `Flight::shadow`: 1/2
    // for semi-implicit Euler, -1/2 for explicit Euler, 0 for the exact
    // parabola); `d` is the overshoot.
    let g_axis = c.gravity[i.axis];
    let name = ["x", "y", "z"][i.axis];
    let pulls_in = (g_axis < 0.0) != i.far;
    let shadow = crate::sim::walls::Flight::of(c.integrator, c.gravity, c.dt).shadow;
    let (k, undo) = if shadow > 0.0 {
        (
            format!(" + g_{name} dt/2"),
            format!(" \u{2212} g_{name} dt/2"),
        )
    } else if shadow < 0.0 {
        (
            format!(" \u{2212} g_{name} dt/2"),
            format!(" + g_{name} dt/2"),
        )
    } else {
        (String::new(), String::new())
    };
    let climb = if pulls_in { "\u{2212}" } else { "+" };
    let at_wall = format_number(i.at_wall);
    lines.extend(wrapped_row(
        width,
        "at wall",
        if i.at_crossing && along {
            // Back along the exact parabola to where it crossed the wall.
            format!(
                "w = \u{221a}({v}\u{b2} {climb} 2 |g_{name}| d) = {at_wall} m/s at the crossing, \
                 back along the parabola, g_{name} = {}, d the overshoot",
                format_number(g_axis),
            )
        } else if i.at_crossing {
            format!("w = |{v}| = {at_wall} m/s at the crossing, back along the line")
        } else if along {
            // The Euler methods' w is not a speed the sphere had but the
            // one their own energy in flight gives at the wall (explicit
            // Euler's can pass the speed the step began with). Velocity
            // Verlet and RK4 come here only past a wall their parabola did
            // not cross (a contact pushed the sphere there): the mirror on
            // the velocity itself.
            let (speed, kept) = if shadow == 0.0 {
                (format!("{v}\u{b2}"), String::new())
            } else {
                (
                    format!("({v}{k})\u{b2}"),
                    format!("; from the energy {} keeps in flight", c.integrator.name()),
                )
            };
            format!(
                "w = \u{221a}({speed} {climb} 2 |g_{name}| d) = {at_wall} m/s, g_{name} = {}, \
                 d the overshoot{kept}",
                format_number(g_axis),
            )
        } else {
            format!("w = |{v}| = {at_wall} m/s")
        },
    ));
    let coefficient = if i.coefficient == c.wall_coefficient() {
        match c.wall_mode {
            WallMode::Flip => "1 (flip walls keep the speed)".to_string(),
            _ => format!("c_r = {:.2}", i.coefficient),
        }
    } else if i.at_wall < c.rest_threshold {
        let (w, threshold) = format_apart(i.at_wall, c.rest_threshold);
        format!("0: w = {w} m/s, slower than the rest threshold, {threshold} m/s")
    } else {
        let resting = c.gravity[i.axis].abs() * c.rest_steps * c.dt;
        let (w, resting) = format_apart(i.at_wall, resting);
        format!(
            "0: resting contact, w = {w} m/s, slower than gravity's {resting} m/s into it (key {})",
            key_of(Action::ToggleResting)
        )
    };
    lines.extend(wrapped_row(width, "c", coefficient));
    let cw = format!(
        "{:.2} w = {}",
        i.coefficient,
        format_number(i.coefficient * i.at_wall)
    );
    let sign = if i.far { "\u{2212}" } else { "" };
    lines.extend(wrapped_row(
        width,
        "out",
        if i.rests {
            format!("{cw} m/s: too slow to leave the wall, it rests on it: {v} = 0")
        } else if i.stopped {
            format!("{cw} m/s, which carries it past the other wall")
        } else if i.at_crossing && more {
            format!("{cw} m/s at the wall, which carries it across the box to the other wall")
        } else if i.at_crossing && along {
            format!(
                "{cw} m/s at the wall, then g_{name} for the step's last {:.3} ms: {v} = {}",
                after_crossing(i, g_axis) * 1e3,
                format_number(i.velocity)
            )
        } else if i.at_crossing {
            format!(
                "{cw} m/s at the wall, then the rest of the step: {v} = {}",
                format_number(i.velocity)
            )
        } else if along {
            format!(
                "{cw} m/s; {v} = {sign}\u{221a}((c w)\u{b2} {climb} 2 |g_{name}| c d){undo} = {}",
                format_number(i.velocity)
            )
        } else {
            format!("{cw} m/s: {v} = {}", format_number(i.velocity))
        },
    ));
    if i.stopped {
        lines.extend(wrapped_row(
            width,
            "stopped",
            format!(
                "still past the other wall after {} walls in the step: the stage stops \
                 it on that wall, {v} = 0",
                crate::sim::walls::MAX_REFLECTIONS
            ),
        ));
    }
    // Where the mirror leaves the centre: the overshoot d reflected and
    // scaled by c, as the speed is.
    if !i.at_crossing && !i.stopped {
        lines.extend(wrapped_row(
            width,
            "back",
            if i.rests {
                format!("on the wall: moved back d = {}", format_length(i.overshoot))
            } else if more {
                format!(
                    "c d = {} back from the wall, past the other one: moved back (1 + c) d = {}",
                    format_length(i.coefficient * i.overshoot),
                    format_length((1.0 + i.coefficient) * i.overshoot)
                )
            } else if i.overshoot <= ROUNDING_AT_THE_WALL {
                // d is the roundings of the flight: the wall moves the
                // centre back by as little, which no figure shows.
                "it ends on the wall: d is 0 to rounding, so (1 + c) d is too".into()
            } else {
                format!(
                    "it ends c d = {} clear of the wall: moved back (1 + c) d = {}",
                    format_length(i.coefficient * i.overshoot),
                    format_length((1.0 + i.coefficient) * i.overshoot)
                )
            },
        ));
    }
    let before_why = lines.len();
    if along && !i.rests && !i.at_crossing {
        lines.extend(wrapped_row(
            width,
            "why",
            format!(
                "c acts on the speed at the wall, w; gravity over the overshoot \
                 d{} changes {v} on either side of it, so |{v}| out need not be \
                 c |{v}| in ({} m/s here)",
                if undo.is_empty() {
                    ""
                } else {
                    " and half a step"
                },
                format_number(i.coefficient * i.before.abs())
            ),
        ));
    }
    let why = lines.len() - before_why;
    (lines, why)
}

/// A wall impact of a sphere's step as its panel shows it: each in full,
/// or, on an axis that met more than [`WALLS_IN_FULL`] walls in the step
/// (rebounds carried across the box), the first and the last in full and
/// how many came between.
#[derive(Debug, PartialEq)]
enum WallShown<'a> {
    Impact(&'a AxisImpact),
    Between { axis: usize, walls: usize },
}

/// Walls one axis shows in full.
const WALLS_IN_FULL: usize = 3;

/// The wall impacts of a step (axis by axis, in the order met) as the
/// panel shows them.
fn walls_shown(impacts: &[AxisImpact]) -> Vec<WallShown<'_>> {
    impacts
        .chunk_by(|a, b| a.axis == b.axis)
        .flat_map(|axis| match axis {
            [first, between @ .., last] if axis.len() > WALLS_IN_FULL => vec![
                WallShown::Impact(first),
                WallShown::Between {
                    axis: first.axis,
                    walls: between.len(),
                },
                WallShown::Impact(last),
            ],
            all => all.iter().map(WallShown::Impact).collect(),
        })
        .collect()
}

/// The time left in the step after the parabola crossed the wall of
/// impact `i`, with gravity `g` (not 0) along its axis, s: the speed on the
/// parabola changes by |g| a second, from `w` at the crossing to the step's
/// end, where it was found moving into the wall at `before`.
fn after_crossing(i: &AxisImpact, g: f64) -> f64 {
    (i.before.abs() - i.at_wall).abs() / g.abs()
}

/// Two numbers as `a, b`, each by [`format_number`].
fn two([a, b]: [f64; 2]) -> String {
    format!("{}, {}", format_number(a), format_number(b))
}

/// A negative factor in parentheses: `(-0.1737)`.
fn signed(v: String) -> String {
    if v.starts_with('-') {
        format!("({v})")
    } else {
        v
    }
}

/// Two numbers as `a, b`, each by [`format_significant`].
fn two_significant([a, b]: [f64; 2]) -> String {
    format!("{}, {}", format_significant(a), format_significant(b))
}

/// A number with three significant decimals, or in exponent form when
/// very small or large.
pub fn format_number(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e4).contains(&a) {
        format!("{v:.2e}")
    } else {
        unsigned_zero(format!("{v:.3}"))
    }
}

/// `line` within `width` columns: cut, with its last column an ellipsis,
/// when longer (by display width: a wide character takes two).
pub(crate) fn cut_to(line: Line<'static>, width: usize) -> Line<'static> {
    if line.width() <= width || width == 0 {
        return line;
    }
    let mut room = width - 1;
    let mut spans = Vec::new();
    'spans: for span in line.spans {
        let mut text = String::new();
        for ch in span.content.chars() {
            let w = Span::raw(&*ch.encode_utf8(&mut [0; 4])).width();
            if w > room {
                spans.push(Span::styled(text, span.style));
                break 'spans;
            }
            room -= w;
            text.push(ch);
        }
        spans.push(Span::styled(text, span.style));
    }
    spans.push(Span::raw("\u{2026}"));
    Line::from(spans).style(line.style)
}

/// `text` cut short: said with an ellipsis, within `width` columns.
fn end_with_ellipsis(text: &mut String, width: usize) {
    // The first `width - 1` characters, found in one pass over them.
    if let Some((at, _)) = text.char_indices().nth(width.saturating_sub(1)) {
        text.truncate(at);
    }
    text.push('\u{2026}');
}

/// The text of a panel line.
pub(crate) fn line_text(line: &Line) -> String {
    line.spans.iter().map(|s| s.content.as_ref()).collect()
}

/// `v` as [`format_significant_to`] shows it to `digits` figures.
fn shown_to(v: f64, digits: usize) -> f64 {
    format_significant_to(v, digits).parse().unwrap_or(v)
}

/// The fewest significant figures, from 4 (at most 9), for which
/// `worked`, computed from its numbers as shown to that many, reads as
/// `result` does in [`format_number`]: a row that then checks by hand.
fn digits_that_give(result: f64, worked: impl Fn(usize) -> f64) -> usize {
    (4..9)
        .find(|&d| format_number(worked(d)) == format_number(result))
        .unwrap_or(9)
}

/// A coefficient as the rows write it: two decimals where they are all
/// it has (0.95, 1.00), else every digit it needs.
fn exactly(e: f64) -> String {
    let two = format!("{e:.2}");
    if two.parse() == Ok(e) {
        two
    } else {
        format!("{e}")
    }
}

/// The fewest significant digits, from four, with which the products
/// `m1 v1 + m2 v2` of the numbers as shown add up to the sum as shown
/// (four digits), so that the row checks by hand; at most nine.
fn digits_that_add_up(terms: [(f64, f64); 2], sum: f64) -> usize {
    (4..9)
        .find(|&digits| {
            let added: f64 = terms
                .iter()
                .map(|&(m, v)| shown_to(m, digits) * shown_to(v, digits))
                .sum();
            format_significant(added) == format_significant(sum)
        })
        .unwrap_or(9)
}

/// Where the step's move left the centre against the wall of impact `i`
/// of a sphere of radius `r`: the coordinate to a micrometre beside the
/// centre's limit (`r` or `1 - r`), so the overshoot checks by hand (the
/// `x` rows may give fewer decimals). An overshoot of the roundings of a
/// coordinate (a flight that ends on the wall, as the ping-pong ball's
/// does, and whose roundings add up bounce after bounce) is the wall
/// itself.
fn past_the_wall(i: &AxisImpact, r: f64) -> String {
    if i.overshoot <= ROUNDING_AT_THE_WALL {
        return "at it (to rounding)".into();
    }
    let name = ["x", "y", "z"][i.axis];
    let (limit, limit_name, moved) = if i.far {
        (1.0 - r, "1 \u{2212} r", 1.0 - r + i.overshoot)
    } else {
        (r, "r", r - i.overshoot)
    };
    format!(
        "moved to {name} = {moved:.6} m: {} past {limit_name} = {limit:.6} m",
        format_length(i.overshoot)
    )
}

/// A picometre: thousands of roundings of a coordinate of the box (of
/// size 1), m. The ping-pong ball's sixth bounce ends 8e-15 m past the
/// wall.
const ROUNDING_AT_THE_WALL: f64 = 1e-12;

/// The inverse-mass shares of a correction, to two decimals, or more
/// where the shares shown times `delta` would not give what each sphere
/// moved as the `moved` row shows it: the row checks by hand.
fn shares_that_check(share: [f64; 2], delta: f64) -> String {
    let shown = |decimals: usize| share.map(|s| format!("{s:.decimals$}"));
    // Times `by`: the delta as shown, or where no share shown checks with
    // it (its rounding alone can tip a figure), the delta itself.
    let checks = |by: f64| {
        move |text: &[String; 2]| {
            text.iter().zip(share).all(|(t, s)| {
                let read: f64 = t.parse().unwrap_or(f64::NAN);
                format_length(read * by) == format_length(s * delta)
            })
        }
    };
    let text = (2..=MOST_SHARE_DECIMALS)
        .map(shown)
        .find(checks(shown_length(delta)))
        .or_else(|| (2..=MOST_SHARE_DECIMALS).map(shown).find(checks(delta)))
        .unwrap_or_else(|| shown(MOST_SHARE_DECIMALS));
    text.join(", ")
}

/// A length as [`format_length`] shows it, read back, m.
fn shown_length(m: f64) -> f64 {
    let text = format_length(m);
    let (number, unit) = text.split_once(' ').unwrap_or((&text, "m"));
    let v: f64 = number.parse().unwrap_or(m);
    if unit == "mm" { v * 1e-3 } else { v }
}

const MOST_SHARE_DECIMALS: usize = 6;

/// A length in millimetres below a metre (anything inside the box: two
/// overlaps compare at a glance), else in metres.
fn format_length(m: f64) -> String {
    // Under half a micrometre, three decimals of a millimetre read 0.000:
    // such a length (an overlap of rounding) gets its figures.
    if m != 0.0 && m.abs() < 5e-7 {
        format!("{:.2e} mm", m * 1e3)
    } else if m.abs() < 1.0 {
        unsigned_zero(format!("{:.3} mm", m * 1e3))
    } else {
        format!("{m:.4} m")
    }
}

/// `dt` as `1/120` when a whole fraction of a second.
fn format_dt_short(dt: f64) -> String {
    let per_second = 1.0 / dt;
    if whole_per_second(per_second) {
        format!("(1/{per_second:.0})")
    } else if dt >= 1e-3 {
        format!("({dt:.4})")
    } else {
        format!("({})", format_significant(dt))
    }
}

pub(crate) fn lesson_text(app: &App) -> (String, String, String) {
    match &app.frame.scene.info {
        Some(info) => {
            let mut idea = info.idea.clone();
            let c = &app.frame.world.config;
            if let Some(note) = gravity_note(app.frame.lesson_gravity, c.gravity, c.pair_collisions)
            {
                idea.push(' ');
                idea.push_str(&note);
            }
            let equation = equation_under(
                &info.equation,
                app.frame.lesson_gravity,
                c.gravity,
                c.integrator,
            );
            (info.title.clone(), idea, equation)
        }
        None => (
            app.frame.scene.name.clone(),
            format!("A scene from {}.", app.frame.scene.origin),
            String::new(),
        ),
    }
}

/// What the lesson's text no longer says when gravity is `now`, not the
/// lesson's `lesson` (`g`, `G`, `--gravity`): the ping-pong lesson's "no
/// force acts" is not true under gravity. `pairs`: spheres collide.
fn gravity_note(lesson: Vec3, now: Vec3, pairs: bool) -> Option<String> {
    if now == lesson {
        None
    } else if lesson == Vec3::ZERO {
        Some(format!(
            "Now gravity pulls at {:.2} m/s^2: a force acts, so the velocity \
             changes every step, not only at the walls (g takes it back to 0).",
            now.length()
        ))
    } else if now == Vec3::ZERO {
        Some(format!(
            "Now gravity is off: no force acts, so the velocity changes only \
             at the walls{}.",
            if pairs { " and in collisions" } else { "" }
        ))
    } else {
        Some(format!(
            "Now gravity is {:.2} m/s^2, the lesson's {:.2} (g, G).",
            now.length(),
            lesson.length()
        ))
    }
}

/// The lesson's velocity equation, besides its position equation.
const VELOCITY_EQUATION: &str = "v(t+dt) = v(t) + F/m dt";
/// The ping-pong lesson's position equation, true of every method while
/// no force acts.
const POSITION_EQUATION: &str = "x(t+dt) = x(t) + v(t) dt";

/// A lesson's `equation` with gravity `now`: a lesson written without
/// gravity (`lesson` zero) whose equation shows only how the position
/// moves (`x(t+dt) = x(t) + v(t) dt`, true of every method while no force
/// acts) gets the lesson's velocity equation too once gravity pulls, as a
/// force then acts, and the lesson's position equation becomes the one
/// `method` then uses: the new velocity for semi-implicit Euler, the
/// force's half step for the methods exact under a constant force (a
/// scene's own equation is kept). An empty equation stays empty.
fn equation_under(equation: &str, lesson: Vec3, now: Vec3, method: Integrator) -> String {
    if lesson != Vec3::ZERO
        || now == Vec3::ZERO
        || equation.is_empty()
        || equation.contains("v(t+dt)")
    {
        return equation.to_string();
    }
    // A scene's own equation is kept, the velocity equation after it.
    if equation != POSITION_EQUATION {
        return format!("{equation};  {VELOCITY_EQUATION}");
    }
    match method {
        Integrator::ExplicitEuler => format!("{equation};  {VELOCITY_EQUATION}"),
        Integrator::SemiImplicitEuler => {
            format!("{VELOCITY_EQUATION};  x(t+dt) = x(t) + v(t+dt) dt")
        }
        Integrator::VelocityVerlet | Integrator::Rk4 | Integrator::Continuous => {
            format!("x(t+dt) = x(t) + v(t) dt + F/(2m) dt^2;  {VELOCITY_EQUATION}")
        }
    }
}

/// [`row`] with its value wrapped to a panel `width` columns wide, the
/// further lines under the value.
fn wrapped_row(width: usize, name: &str, value: String) -> Vec<Line<'static>> {
    let value_width = width.saturating_sub(LABEL_WIDTH).max(8);
    let mut parts = wrap(&value, value_width).into_iter();
    let first = row(name, parts.next().unwrap_or_default());
    std::iter::once(first)
        .chain(parts.map(|p| row("", p)))
        .collect()
}

/// Columns a row's label takes, its leading space included.
const LABEL_WIDTH: usize = 11;

fn row(name: &str, value: String) -> Line<'static> {
    Line::from(vec![Span::raw(format!(" {name:<10}")), Span::raw(value)])
}

fn parameter_lines(app: &App, width: usize) -> Vec<Line<'static>> {
    let c = &app.frame.world.config;
    let walls = match c.wall_mode {
        WallMode::Flip => "flip (keeps the speed)".to_string(),
        WallMode::Restitution => format!("c_r = {:.2}", c.wall_restitution),
    };
    let pairs = if c.pair_collisions {
        format!(
            "e = {:.2}, {}",
            c.pair_restitution,
            broad_phase_name(c.broad_phase, app.frame.world.bodies.len())
        )
    } else {
        format!("e = {:.2} (no collisions)", c.pair_restitution)
    };
    let g = app.frame.gravity();
    let gravity = match gravity_name(g) {
        "" => format!("{g:.2} m/s^2"),
        name => format!("{g:.2} m/s^2 ({name})"),
    };
    let run = if app.paused { "paused" } else { "running" };
    let mut lines = vec![
        row("walls", walls),
        row("pairs", pairs),
        row("gravity", gravity),
        row("dt", format_dt(c.dt)),
    ];
    // The speed under which an impact rests is gravity's along the
    // contact's normal, so it is a bound: the floor's, less on a slope.
    let (y, big_y) = (key_of(Action::ToggleResting), key_of(Action::ToggleSupport));
    lines.extend(wrapped_row(
        width,
        "resting",
        if c.support_runs() {
            format!("on + support pass ({y}, {big_y})")
        } else if c.rest_steps > 0.0 && c.support {
            format!("on ({y}); support pass idle ({big_y})")
        } else if c.rest_steps > 0.0 && c.gravity == Vec3::ZERO {
            format!("on, idle without gravity ({y})")
        } else if c.rest_steps > 0.0 {
            let steps = if c.rest_steps == 1.0 {
                String::new()
            } else {
                format!("{} ", c.rest_steps)
            };
            format!(
                "on ({y}), {steps}|g\u{b7}n| dt \u{2264} {:.3} m/s",
                c.gravity.length() * c.rest_steps * c.substep_dt()
            )
        } else {
            format!("off ({y} turns it on)")
        },
    ));
    lines.extend([
        row("method", c.integrator.name().to_string()),
        row(
            "spheres",
            format!(
                "{}, seed {}{}",
                thousands(app.frame.world.bodies.len() as u64),
                app.frame.scene.seed,
                if c.sleep {
                    format!(
                        ", {} asleep ({})",
                        thousands(app.frame.world.last.asleep as u64),
                        key_of(Action::ToggleSleep)
                    )
                } else {
                    String::new()
                }
            ),
        ),
        row(
            "pace",
            format!("{run}, x{}", format_scale(app.time_scale())),
        ),
    ]);
    lines
}

fn readout_lines(app: &App) -> Vec<Line<'static>> {
    let d = app
        .frame
        .energy
        .now(&app.frame.world)
        .copied()
        .unwrap_or_else(|| Sample::of(&app.frame.world));
    let ms = |v: Option<f64>| v.map_or("-".to_string(), format_ms);
    let fps = app.timing.fps.map_or("-".to_string(), |v| {
        if app.paused {
            "-, paused: drawn on change".to_string()
        } else if app.timing.draw_held {
            format!("{v:.0}, at most {BUSY_FPS:.0}: steps busy")
        } else {
            format!("{v:.0}")
        }
    });
    let mut lines = vec![
        row("time", format!("{:.3} s, step {}", d.time, d.steps)),
        row(
            "KE + PE",
            // Potential energy below the origin is negative: `- 3.5 J`,
            // not `+ -3.5 J`.
            if d.potential < 0.0 {
                format!(
                    "{} - {}",
                    format_energy(d.kinetic),
                    format_energy(-d.potential)
                )
            } else {
                format!(
                    "{} + {}",
                    format_energy(d.kinetic),
                    format_energy(d.potential)
                )
            },
        ),
        row("total", format_energy(d.total)),
        row("p, kg m/s", format_vector(d.momentum)),
        if app.frame.world.config.pair_collisions {
            row("contacts", thousands(app.frame.world.last.contacts as u64))
        } else {
            row("contacts", "0 (no pair collisions)".into())
        },
        // The computer's time, not the simulation's.
        row(
            "took",
            format!(
                "step {}, frame {}",
                ms(app.frame.pace.step_ms),
                ms(app.timing.frame_ms)
            ),
        ),
        row("fps", fps),
    ];
    let pace = &app.frame.pace;
    let behind = !app.paused && (app.timing.busy_for.is_some() || pace.behind);
    if behind {
        lines.push(row(
            "limit",
            match pace.achieved.filter(|_| app.timing.busy_for.is_none()) {
                Some(a) => format!(
                    "the step: x{a:.2} of x{} asked",
                    format_scale(app.time_scale())
                ),
                None => "the step: slower than real time".into(),
            },
        ));
    }
    lines.extend(budget_lines(&app.frame.world.last));
    if app.frame.world.config.pair_collisions {
        lines.insert(5, row("tests", pair_tests(app)));
    }
    if let Some(g) = app.frame.ghost.as_ref().filter(|_| app.frame.show_ghost) {
        let value = match (g.rms, &g.unavailable) {
            (Some(rms), _) if g.diverged => format!("RMS {rms:.2e} m: diverged"),
            (Some(rms), _) => format!("RMS {rms:.2e} m from exact"),
            (None, Some(why)) => why.short(),
            (None, None) => "-".into(),
        };
        lines.push(row("ghost", value));
        // Started part-way, the ghost is the exact motion from there.
        if g.rms.is_some() && g.anchor_step > 0 {
            lines.push(row("", format!("since step {}", g.anchor_step)));
        }
    }
    lines
}

/// A row for each remedy that ran out of its budget in the last step: the
/// step went on, and the panel says so.
fn budget_lines(last: &StepStats) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    if last.projection_unconverged {
        lines.push(row("budget", "projection passes ran out".into()));
    }
    if last.event_cap_reached {
        lines.push(row("budget", "impact cap: stages finished".into()));
    }
    if last.support_unsettled > 0 {
        lines.push(row(
            "budget",
            format!("{} short (support)", spheres(last.support_unsettled)),
        ));
    }
    lines
}

/// Pair tests of a step with the broad phase in use, and what the other
/// one makes for the same spheres: all-pairs counted, `n (n - 1) / 2`; the
/// grid's counted once a step
/// ([`Session::grid_tests`](super::session::Session::grid_tests)). The
/// continuous method predicts every pair whatever the broad phase: its own
/// count is shown instead.
fn pair_tests(app: &App) -> String {
    let c = &app.frame.world.config;
    let n = app.frame.world.bodies.len();
    let running = c.broad_phase.resolve(n);
    let grid = || app.frame.grid_tests.map_or("-".to_string(), count);
    if n > 0 && app.frame.world.last.asleep == n {
        return "0: every sphere asleep".into();
    }
    if c.integrator == Integrator::Continuous {
        return format!(
            "{} predicted; grid {}",
            count(app.frame.world.last.pair_tests),
            grid()
        );
    }
    match running {
        // Before the first step, and after a switch, what the next step makes.
        BroadPhase::Grid => format!(
            "{} grid; all-pairs {}",
            if app.frame.needs_grid_tests {
                grid()
            } else {
                count(app.frame.world.last.pair_tests)
            },
            count(all_pairs_tests(n))
        ),
        _ => format!("{} all-pairs; grid {}", count(all_pairs_tests(n)), grid()),
    }
}

/// A count in a few characters: `4,950`, or `5.0e9` from 100,000 up.
fn count(v: u64) -> String {
    if v < 100_000 {
        thousands(v)
    } else {
        format!("{:.1e}", v as f64)
    }
}

/// A time of the computer's, given in milliseconds, to three figures:
/// `4.21 µs`, `312 µs`, `3.74 ms`, `17.3 ms`, `172 ms`, `1,235 ms`.
pub(crate) fn format_ms(ms: f64) -> String {
    // Under 999.5 µs, which three figures of µs keep under 1,000.
    let (v, unit) = if ms < 0.9995 {
        (ms * 1e3, "µs")
    } else {
        (ms, "ms")
    };
    // The decimals that leave three figures once rounded (9.996 is 10.0).
    let decimals = [2, 1]
        .into_iter()
        .find(|&d| format!("{v:.d$}", d = d).len() <= 4)
        .unwrap_or(0);
    if decimals == 0 {
        format!("{} {unit}", thousands(v.round() as u64))
    } else {
        format!("{v:.decimals$} {unit}")
    }
}

/// A displacement of a few millimetres or less, in mm so that it does not
/// read as zero; larger ones in m.
fn format_length_vector(v: Vec3) -> String {
    if v.abs().max_element() < 0.01 {
        format!("{} mm", format_vector(v * 1e3))
    } else {
        format!("{} m", format_vector(v))
    }
}

fn format_vector(v: Vec3) -> String {
    format_vector_to(v, 3)
}

/// [`format_vector`] with `decimals` decimals.
fn format_vector_to(v: Vec3, decimals: usize) -> String {
    let f = |x: f64| {
        if x.abs() >= 1e6 {
            return format!("{x:.3e}");
        }
        let x = if x.abs() < 0.5 * 10f64.powi(-(decimals as i32)) {
            0.0
        } else {
            x
        };
        format!("{x:.decimals$}")
    };
    format!("({}, {}, {})", f(v.x), f(v.y), f(v.z))
}

/// What moved a sphere after its flight in the step, for the `then` rows.
/// The support pass moves spheres resting on one another and on the walls
/// alike: not told apart.
fn later_stages(c: &WorldConfig, s: &SphereReadout) -> &'static str {
    match (c.support, s.in_contact, s.wall_now.is_some()) {
        (true, ..) => "the later stages (contacts, walls, the support pass)",
        (false, true, true) => "its contacts and a wall",
        (false, true, false) => "its contacts",
        (false, false, true) => "a wall",
        (false, false, false) => "the step's later stages",
    }
}

/// The decimals, from three, with which the flight rows of each of
/// `spheres` add up by hand: its centre before, plus the velocity it moved
/// with times dt, plus the parabola's term and what the later stages moved
/// it (as those rows show them), gives its centre as shown; and with which
/// each coordinate that moved by a micrometre or more reads differently
/// before and after, where some number of them does that too. At most
/// [`MOST_FLIGHT_DECIMALS`]; `None` where no number of them adds up.
fn flight_decimals(spheres: &[&SphereReadout], c: &WorldConfig) -> Option<usize> {
    let all = |test: &dyn Fn(&SphereReadout, usize) -> bool| {
        (3..=MOST_FLIGHT_DECIMALS).find(|&d| spheres.iter().all(|s| test(s, d)))
    };
    all(&|s, d| flight_adds_up(s, c, d) && moves_show(s, d))
        .or_else(|| all(&|s, d| flight_adds_up(s, c, d)))
}

/// A vector as [`format_vector_to`] shows it to `decimals`, read back.
fn as_read(v: Vec3, decimals: usize) -> Vec3 {
    let text = format_vector_to(v, decimals);
    let parts: Vec<f64> = text
        .trim_matches(|ch| ch == '(' || ch == ')')
        .split(", ")
        .map(|x| x.parse().unwrap_or(f64::NAN))
        .collect();
    Vec3::new(parts[0], parts[1], parts[2])
}

/// Whether sphere `s`'s flight rows add up by hand at `d` decimals (see
/// [`flight_decimals`]); true for a sphere with no step before.
fn flight_adds_up(s: &SphereReadout, c: &WorldConfig, d: usize) -> bool {
    let Some((x0, v0)) = s.previous else {
        return true;
    };
    let (dt, g) = (c.dt, c.gravity);
    let (v_used, parabola) = c.integrator.position_update(v0, g, dt);
    let term = parabola.filter(|_| g != Vec3::ZERO).unwrap_or(Vec3::ZERO);
    let rest = s.position - (x0 + v_used * dt + term);
    // The rows of lengths as shown ([`format_shift`]).
    let as_shown = |v: Vec3| {
        if v.abs().max_element() < 0.01 {
            as_read(v * 1e3, 3) * 1e-3
        } else {
            as_read(v, d)
        }
    };
    let moved = if rest.abs().max_element() >= 5e-7 {
        as_shown(rest)
    } else {
        Vec3::ZERO
    };
    let sum = as_read(x0, d) + as_read(v_used, d) * dt + as_shown(term) + moved;
    format_vector_to(sum, d) == format_vector_to(s.position, d)
}

/// Whether each coordinate of sphere `s`'s centre that moved by a
/// micrometre or more in the step reads differently before and after at
/// `d` decimals.
fn moves_show(s: &SphereReadout, d: usize) -> bool {
    let Some((x0, _)) = s.previous else {
        return true;
    };
    let (before, after) = (as_read(x0, d), as_read(s.position, d));
    (0..3).all(|k| (s.position[k] - x0[k]).abs() < 1e-6 || before[k] != after[k])
}

/// A shift of a sphere's centre in a step: in millimetres below a
/// centimetre (to a micrometre), else in metres to `decimals` decimals, as
/// its centres are shown.
fn format_shift(v: Vec3, decimals: usize) -> String {
    if v.abs().max_element() < 0.01 {
        format_length_vector(v)
    } else {
        format!("{} m", format_vector_to(v, decimals))
    }
}

const MOST_FLIGHT_DECIMALS: usize = 6;

/// Word wrap to `width` columns; a word longer than the width keeps a line
/// of its own rather than being cut.
pub(crate) fn wrap(text: &str, width: usize) -> Vec<String> {
    let options = textwrap::Options::new(width.max(1)).break_words(false);
    // A unit of two words stays on one line.
    let kept = text.replace(MOMENTUM_UNIT, &MOMENTUM_UNIT.replace(' ', "\u{a0}"));
    textwrap::wrap(&kept, options)
        .into_iter()
        .filter(|l| !l.is_empty())
        .map(|l| l.replace('\u{a0}', " "))
        .collect()
}

const MOMENTUM_UNIT: &str = "kg m/s";

#[cfg(test)]
mod tests {
    #[test]
    fn a_selection_says_what_its_step_ran_with_that_has_changed_since() {
        use crate::sim::{Integrator, WorldConfig, gravity_down};
        let then = WorldConfig {
            integrator: Integrator::VelocityVerlet,
            gravity: gravity_down(9.81),
            pair_collisions: true,
            ..WorldConfig::default()
        };
        assert!(super::changed_since(&then, &then).is_empty());
        // Flip walls (the ping-pong lesson's) turned to restitution by `e`.
        let flip = WorldConfig {
            wall_mode: crate::sim::WallMode::Flip,
            ..then.clone()
        };
        assert_eq!(super::changed_since(&flip, &then), ["flip walls"]);
        // `y` and `Y` after the step: the rows that explain it by resting
        // contact say what it ran with.
        let rules = WorldConfig {
            rest_steps: 0.0,
            support: true,
            ..then.clone()
        };
        assert_eq!(
            super::changed_since(&then, &rules),
            ["resting contact on", "support pass off"]
        );
        assert_eq!(
            super::changed_since(&then, &flip),
            [format!("c_r {:.2}", then.wall_restitution)]
        );
        let now = WorldConfig {
            integrator: Integrator::Continuous,
            gravity: gravity_down(8.0),
            dt: then.dt / 2.0,
            pair_restitution: then.pair_restitution - 0.05,
            ..then.clone()
        };
        assert_eq!(
            super::changed_since(&then, &now),
            [
                "velocity-verlet",
                &format!("dt {}", super::format_dt(then.dt)),
                "g 9.81 m/s^2",
                &format!("e {:.2}", then.pair_restitution),
            ]
        );
    }

    #[test]
    fn a_tiny_dt_shows_its_figures() {
        assert_eq!(super::format_dt(1.0 / 240.0), "1/240 s (4.167 ms)");
        assert_eq!(super::format_dt(1e-9), "1/1000000000 s (1.000e-6 ms)");
        assert_eq!(super::format_dt(7.3e-6), "0.007300 ms");
        assert_eq!(super::format_dt_short(7.3e-6), "(7.300e-6)");
    }

    #[test]
    fn the_lesson_text_says_when_gravity_is_no_longer_the_lessons() {
        use super::gravity_note;
        use crate::sim::{Vec3, gravity_down};
        let earth = gravity_down(9.81);
        assert_eq!(gravity_note(Vec3::ZERO, Vec3::ZERO, false), None);
        assert_eq!(gravity_note(earth, earth, true), None);
        let note = gravity_note(Vec3::ZERO, gravity_down(1.0), false).unwrap();
        assert!(note.contains("pulls at 1.00 m/s^2") && note.contains("a force acts"));
        let note = gravity_note(earth, gravity_down(0.0), false).unwrap();
        assert!(note.contains("gravity is off") && note.ends_with("only at the walls."));
        let note = gravity_note(earth, gravity_down(0.0), true).unwrap();
        assert!(note.ends_with("at the walls and in collisions."));
        let note = gravity_note(earth, gravity_down(4.9), true).unwrap();
        assert!(note.contains("4.90 m/s^2, the lesson's 9.81"));
    }

    #[test]
    fn zero_is_never_shown_negative() {
        use super::{format_length, format_number, format_significant};
        assert_eq!(format_number(-0.0), "0.000");
        assert_eq!(format_number(-0.0004), "-4.00e-4");
        assert_eq!(format_number(-0.25), "-0.250");
        assert_eq!(format_significant(-0.0), "0");
        assert_eq!(format_significant(f64::NEG_INFINITY), "-inf");
        assert_eq!(format_length(-0.0), "0.000 mm");
        assert_eq!(format_length(-2e-7), "-2.00e-4 mm", "tiny, not zero");
        assert_eq!(format_length(-2e-6), "-0.002 mm");
    }

    #[test]
    fn a_wrapped_value_keeps_its_unit_on_one_line() {
        let value = "(-0.222, 0.391, -0.273) kg m/s";
        assert_eq!(
            super::wrap(value, 27),
            ["(-0.222, 0.391, -0.273)", "kg m/s"]
        );
        assert_eq!(super::wrap(value, 30), [value]);
    }

    #[test]
    fn a_row_too_long_for_the_panel_ends_in_an_ellipsis_within_its_width() {
        use super::{cut_to, line_text, row};
        let seed = row("spheres", "100, seed 18446744073709551615".into());
        assert_eq!(
            line_text(&cut_to(seed.clone(), 20)),
            " spheres   100, see\u{2026}"
        );
        assert_eq!(cut_to(seed.clone(), 20).width(), 20);
        assert_eq!(line_text(&cut_to(seed.clone(), 41)), line_text(&seed));
        // Wide characters count two columns each.
        let wide = Line::from("場面場面場面場面");
        assert_eq!(line_text(&cut_to(wide.clone(), 6)), "場面\u{2026}");
        assert!(cut_to(wide, 6).width() <= 6);
    }

    #[test]
    fn a_remedy_that_ran_out_of_its_budget_gets_a_row() {
        use crate::sim::StepStats;
        let text = |s: &StepStats| -> Vec<String> {
            super::budget_lines(s)
                .iter()
                .map(|l| l.spans.iter().map(|s| s.content.as_ref()).collect())
                .collect()
        };
        assert!(text(&StepStats::default()).is_empty());
        let all = StepStats {
            projection_unconverged: true,
            event_cap_reached: true,
            support_unsettled: 12,
            ..StepStats::default()
        };
        assert_eq!(
            text(&all),
            [
                " budget    projection passes ran out",
                " budget    impact cap: stages finished",
                " budget    12 spheres short (support)",
            ]
        );
        let one = StepStats {
            support_unsettled: 1,
            ..StepStats::default()
        };
        assert_eq!(text(&one), [" budget    1 sphere short (support)"]);
    }

    use super::*;

    #[test]
    fn tiny_lengths_huge_components_and_slow_paces_keep_their_figures() {
        // An overlap of rounding read 0.000 mm; a momentum of 7e10 ran to
        // fifteen digits; a pace of x0.0015 read x0.00.
        assert_eq!(format_length(3e-16), "3.00e-13 mm");
        assert_eq!(format_length(-3e-16), "-3.00e-13 mm");
        assert_eq!(format_length(1.4e-5), "0.014 mm");
        assert_eq!(format_length(0.0), "0.000 mm");
        assert_eq!(
            format_vector(Vec3::new(71877106166.902, -4166666666666.667, 0.0)),
            "(7.188e10, -4.167e12, 0.000)"
        );
        assert_eq!(super::super::view::format_achieved(0.0015), "0.0015");
        assert_eq!(super::super::view::format_achieved(0.25), "0.25");
        assert_eq!(super::super::view::format_achieved(0.015), "0.015");
    }

    #[test]
    fn the_shares_times_delta_give_what_each_sphere_moved_as_shown() {
        // Equal masses: two decimals.
        assert_eq!(shares_that_check([0.5, 0.5], 2.0e-3), "0.50, 0.50");
        // A mass ratio of 600: 1.00 and 0.00 of 2.387 mm would not give the
        // 2.383 and 0.004 mm moved.
        let light = 1.0 / 600.0;
        let share = [1.0 - light, light];
        let text = shares_that_check(share, 2.387e-3);
        assert_eq!(text, "0.9983, 0.0017");
        for (t, s) in text.split(", ").zip(share) {
            let read: f64 = t.parse().unwrap();
            assert_eq!(format_length(read * 2.387e-3), format_length(s * 2.387e-3));
        }
    }

    #[test]
    fn a_tiny_dt_reads_in_milliseconds_not_as_a_fraction_of_300_digits() {
        assert_eq!(format_dt(1.0 / 240.0), "1/240 s (4.167 ms)");
        assert_eq!(format_dt(1e-300), "1.000e-297 ms");
        assert_eq!(format_dt_short(1e-300), "(1.000e-300)");
        assert_eq!(format_dt_short(1.0 / 120.0), "(1/120)");
    }

    #[test]
    fn a_flight_adds_up_by_hand_with_the_decimals_shown() {
        // x0 = 0.28049 moving at -0.083 m/s for 1/30 s ends at 0.27772:
        // to three decimals 0.280 - 0.083/30 reads 0.277 where x reads
        // 0.278; to four, 0.2805 - 0.0830/30 = 0.2777, as x reads.
        let mut w = crate::study::stability::ball_world(
            Integrator::SemiImplicitEuler,
            1.0 / 30.0,
            0.5,
            1.0,
        );
        w.bodies.position[0] = Vec3::new(0.28049, 0.5, 0.50049);
        w.bodies.velocity[0] = Vec3::new(-0.083, 0.0, 0.0);
        let (rows, _) = rows_after_a_step(&mut w, 0);
        let vector = |row: &str| -> Vec<f64> {
            let inside = &row[row.find('(').unwrap() + 1..row.find(')').unwrap()];
            inside.split(", ").map(|x| x.parse().unwrap()).collect()
        };
        let at = rows
            .iter()
            .position(|r| r.starts_with(" x += v dt"))
            .unwrap();
        let (x0, v) = (vector(&rows[at]), vector(&rows[at + 1]));
        let x = vector(rows.iter().find(|r| r.starts_with(" x ")).unwrap());
        assert!(rows[at].contains("(0.2805, 0.5000, 0.5005)"), "{rows:?}");
        for k in 0..3 {
            let sum = x0[k] + v[k] / 30.0;
            assert_eq!(format!("{sum:.4}"), format!("{:.4}", x[k]), "{rows:?}");
        }
        // Pushed 1.8 cm by a contact, which the `then` row gives in
        // metres to a millimetre: the sum adds that row as shown.
        let scene = "[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.03333333333333333\n\
            [[body]]\nposition = [0.28049, 0.5, 0.50049]\nvelocity = [-0.083, 0.0, 0.0]\n\
            radius = 0.1\nmass = 1.0\n\
            [[body]]\nposition = [0.11449, 0.5, 0.50049]\nradius = 0.1\nmass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, _) = rows_after_a_step(&mut w, 0);
        let at = rows
            .iter()
            .position(|r| r.starts_with(" x += v dt"))
            .unwrap();
        let (x0, v) = (vector(&rows[at]), vector(&rows[at + 1]));
        let then = rows.iter().find(|r| r.starts_with(" then ")).unwrap();
        assert!(then.contains(") m by its contacts"), "{rows:?}");
        let pushed = vector(then);
        let x_row = rows.iter().find(|r| r.starts_with(" x ")).unwrap();
        let decimals = x_row.split(", ").nth(1).unwrap().len() - 2;
        let x = vector(x_row);
        for k in 0..3 {
            let sum = x0[k] + v[k] / 30.0 + pushed[k];
            assert_eq!(
                format!("{sum:.decimals$}"),
                format!("{:.decimals$}", x[k]),
                "{rows:?}"
            );
        }
    }

    #[test]
    fn two_speeds_compared_read_apart() {
        // A resting contact's approach against gravity's step: equal to
        // three decimals, so with the figures that tell them apart.
        assert_eq!(
            format_apart(0.01154, 9.81 / 240.0 * 0.284),
            ("0.0115".into(), "0.0116".into())
        );
        assert_eq!(format_apart(0.020, 0.041), ("0.020".into(), "0.041".into()));
        assert_eq!(
            format_apart(2.0e-5, 2.04e-5),
            ("2.00e-5".into(), "2.04e-5".into())
        );
        assert_eq!(
            format_apart(2.0001e-5, 2.0004e-5),
            ("2.0001e-5".into(), "2.0004e-5".into())
        );
        assert_eq!(format_apart(0.5, 0.5), ("0.500".into(), "0.500".into()));
    }

    #[test]
    fn a_coordinate_that_moved_reads_differently_before_and_after() {
        // 0.09 m/s for 1/240 s moves y by 0.375 mm: to three decimals
        // 0.028 before and after, though those rows add up; to four the
        // move shows, and they still add up.
        let scene = "[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.004166666666666667\n\
            [[body]]\nposition = [0.5, 0.02812, 0.5]\nvelocity = [-0.354, 0.09, 0.313]\n\
            radius = 0.01\nmass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, _) = rows_after_a_step(&mut w, 0);
        let vector = |row: &str| -> Vec<String> {
            let inside = &row[row.find('(').unwrap() + 1..row.find(')').unwrap()];
            inside.split(", ").map(str::to_string).collect()
        };
        let before = vector(rows.iter().find(|r| r.starts_with(" x += v dt")).unwrap());
        let after = vector(rows.iter().find(|r| r.starts_with(" x ")).unwrap());
        assert_eq!(after[1].len(), "0.0285".len(), "{rows:?}");
        for k in 0..3 {
            assert_ne!(before[k], after[k], "{rows:?}");
        }
    }

    #[test]
    fn a_bounce_at_the_crossing_gives_the_time_gravity_then_acts() {
        // Velocity Verlet and RK4 reflect at the crossing and fly the rest
        // of the step under gravity: c w less g t is the velocity out.
        for method in [Integrator::VelocityVerlet, Integrator::Rk4] {
            let (rows, inspection, _, v) = one_step(method, 0.07, Vec3::new(0.0, -2.0, 0.0), 0.9);
            let i = inspection.spheres[0].wall_impacts[0];
            assert!(i.at_crossing && !i.rests, "{rows:?}");
            let t = after_crossing(&i, -9.81);
            assert!(t > 0.0 && t < 1.0 / 30.0, "{t}");
            assert!((0.9 * i.at_wall - 9.81 * t - v.y).abs() < 1e-9, "{rows:?}");
            let out = rows.iter().find(|r| r.starts_with(" out ")).unwrap();
            assert!(
                out.contains(&format!("then g_y for the step's last {:.3} ms", t * 1e3)),
                "{out}"
            );
        }
    }

    #[test]
    fn a_parabola_method_past_a_wall_it_did_not_cross_mirrors_the_velocity_itself() {
        // Velocity Verlet and RK4 with a centre past the floor that the
        // step's parabola did not cross (a contact pushed it there): the
        // mirror on v_y itself, with no energy of the method's own.
        use crate::sim::restitution::Restitution;
        use crate::sim::walls::{Flight, axis_impact};
        use crate::tui::selection::ImpactKind;
        for method in [Integrator::VelocityVerlet, Integrator::Rk4] {
            let c = WorldConfig {
                integrator: method,
                ..WorldConfig::default()
            };
            let flight = Flight::of(method, c.gravity, c.dt);
            let i = axis_impact(0.097, -0.3, 0.1, 1, Restitution::new(0.95, 0.0), flight)
                .expect("past the floor");
            assert!(!i.at_crossing, "{method:?}");
            let wall = ImpactKind::Wall {
                axis: 1,
                far: false,
            };
            let (rows, _) = wall_rows(400, wall, &i, false, 0.1, &c);
            let rows: Vec<String> = rows.iter().map(line_text).collect();
            let at_wall = rows.iter().find(|r| r.starts_with(" at wall")).unwrap();
            assert!(
                at_wall.contains("w = \u{221a}(v_y\u{b2} \u{2212} 2 |g_y| d) = ")
                    && !at_wall.contains("keeps in flight"),
                "{method:?}: {at_wall}"
            );
        }
    }

    #[test]
    fn a_flight_that_ends_on_the_wall_to_rounding_moves_back_nothing() {
        // The ping-pong ball's flights end on the wall, give or take the
        // roundings of its coordinate: the back row says 0, not 2.9e-12 mm.
        use crate::sim::restitution::Restitution;
        use crate::sim::walls::{Flight, axis_impact};
        use crate::tui::selection::ImpactKind;
        let c = WorldConfig::default();
        let flight = Flight::of(c.integrator, c.gravity, c.dt);
        let r = 0.1;
        let i = axis_impact(r - 2.9e-15, -0.3, r, 1, Restitution::new(0.95, 0.0), flight)
            .expect("past the floor, by a rounding");
        let wall = ImpactKind::Wall {
            axis: 1,
            far: false,
        };
        let (rows, _) = wall_rows(400, wall, &i, false, r, &c);
        let rows: Vec<String> = rows.iter().map(line_text).collect();
        assert!(
            rows.contains(
                &" back      it ends on the wall: d is 0 to rounding, so (1 + c) d is too".into()
            ),
            "{rows:#?}"
        );
    }

    #[test]
    fn the_back_row_gives_what_the_wall_moved_the_centre() {
        // A bounce on the floor with the Euler methods: the overshoot d
        // mirrored and scaled by c, so the wall moved the centre (1 + c) d,
        // the `then` row's shift; and the centre ends c d above r.
        for method in [Integrator::SemiImplicitEuler, Integrator::ExplicitEuler] {
            let (rows, inspection, x, _) = one_step(method, 0.07, Vec3::new(0.0, -2.0, 0.0), 0.9);
            let i = inspection.spheres[0].wall_impacts[0];
            let d = i.overshoot;
            assert!(d > 1e-3, "{rows:?}");
            let back = rows
                .iter()
                .find(|r| r.starts_with(" back "))
                .expect("a back row");
            assert_eq!(
                back,
                &format!(
                    " back      it ends c d = {} clear of the wall: moved back (1 + c) d = {}",
                    format_length(0.9 * d),
                    format_length(1.9 * d)
                ),
                "{rows:?}"
            );
            // The `then` row's y shift, in its unit, is (1 + c) d.
            let then = rows
                .iter()
                .find(|r| r.starts_with(" then "))
                .expect("a then row");
            let inside = &then[then.find('(').unwrap() + 1..then.find(')').unwrap()];
            let y_text = inside.split(", ").nth(1).unwrap();
            let y: f64 = y_text.parse().unwrap();
            let decimals = y_text.len() - y_text.find('.').unwrap() - 1;
            let unit = if then.contains(") mm by a wall") {
                1e-3
            } else {
                1.0
            };
            let shown = 0.5 * 10f64.powi(-(decimals as i32)) * unit;
            assert!((y * unit - 1.9 * d).abs() <= shown, "{then}");
            assert!((x.y - (inspection.spheres[0].radius + 0.9 * d)).abs() < 1e-12);
        }
    }

    #[test]
    fn a_sphere_resting_on_the_floor_names_that_contact_as_its_impact() {
        // Dropped from just above the floor and slower than gravity's
        // step: held as resting contact, which the log of impacts (the
        // bounces) leaves out. The row had said "none in this step" under
        // the floor's own rows.
        let (rows, inspection, ..) = one_step(
            Integrator::SemiImplicitEuler,
            0.0505,
            Vec3::new(0.0, -0.05, 0.0),
            0.9,
        );
        assert!(inspection.spheres[0].wall_now.is_some(), "{rows:?}");
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" c ") && r.contains("resting contact")),
            "{rows:?}"
        );
        assert!(
            rows.iter()
                .any(|r| r == " impact    the floor in this step, resting contact (no bounce)"),
            "{rows:?}"
        );
    }

    /// An elastic mirrored impact on `axis` (`far`: the wall at 1 - r),
    /// found moving at `before` with the centre `overshoot` past the wall.
    fn mirrored(axis: usize, far: bool, before: f64, overshoot: f64) -> AxisImpact {
        AxisImpact {
            axis,
            far,
            at_crossing: false,
            before,
            overshoot,
            at_wall: 1.0,
            coefficient: 1.0,
            rests: false,
            flew: 0.0,
            stopped: false,
            position: 0.5,
            velocity: 1.0,
        }
    }

    #[test]
    fn an_axis_that_met_many_walls_in_a_step_shows_the_first_and_the_last() {
        let impact = |axis, far| mirrored(axis, far, 1.0, 1.0);
        let x: Vec<AxisImpact> = (0..5).map(|k| impact(0, k % 2 == 1)).collect();
        let y = [impact(1, true), impact(1, false), impact(1, true)];
        let all: Vec<AxisImpact> = x.iter().chain(&y).copied().collect();
        let shown = walls_shown(&all);
        assert_eq!(shown[0], WallShown::Impact(&all[0]));
        assert_eq!(shown[1], WallShown::Between { axis: 0, walls: 3 });
        assert_eq!(shown[2], WallShown::Impact(&all[4]));
        // Three walls on one axis are shown in full.
        assert_eq!(
            &shown[3..],
            &all[5..].iter().map(WallShown::Impact).collect::<Vec<_>>()[..]
        );
        assert_eq!(shown.len(), 6);
    }

    #[test]
    fn an_overshoot_of_rounding_is_the_wall_itself() {
        let past = |overshoot: f64, far: bool| {
            let i = mirrored(1, far, if far { 1.0 } else { -1.0 }, overshoot);
            past_the_wall(&i, 0.01266)
        };
        assert_eq!(past(1.44e-15, false), "at it (to rounding)");
        assert_eq!(past(0.0, true), "at it (to rounding)");
        assert_eq!(past(8.06e-15, true), "at it (to rounding)");
        // Past it, the centre's coordinate to a micrometre against its
        // limit, so d = 0.989194 - 0.987340 checks by hand.
        assert_eq!(
            past(1.854e-3, true),
            "moved to y = 0.989194 m: 1.854 mm past 1 \u{2212} r = 0.987340 m"
        );
        assert_eq!(
            past(1e-6, false),
            "moved to y = 0.012659 m: 0.001 mm past r = 0.012660 m"
        );
        assert_eq!(
            past(1e-9, false),
            "moved to y = 0.012660 m: 1.00e-6 mm past r = 0.012660 m"
        );
    }

    #[test]
    fn the_momentum_row_adds_up_as_shown() {
        let shown =
            |v: f64, digits: usize| -> f64 { format_significant_to(v, digits).parse().unwrap() };
        let adds_up = |m1: f64, u1: f64, m2: f64, u2: f64| {
            let digits = digits_that_add_up([(m1, u1), (m2, u2)], m1 * u1 + m2 * u2);
            let added =
                shown(m1, digits) * shown(u1, digits) + shown(m2, digits) * shown(u2, digits);
            (
                digits,
                format_significant(added) == format_significant(m1 * u1 + m2 * u2),
            )
        };
        // Light spheres add up at four figures.
        assert_eq!(adds_up(0.05, 3.0, 0.08, -2.0), (4, true));
        // A heavy sphere: 24.88 x (-0.6136) as shown makes the sum -15.03,
        // where the numbers behind them make -15.02.
        let (m2, u2) = (24.875939, -0.613553);
        let four = 0.06387 * 3.751 + shown(m2, 4) * shown(u2, 4);
        assert_ne!(
            format_significant(four),
            format_significant(0.06387 * 3.751 + m2 * u2)
        );
        let (digits, ok) = adds_up(0.06387, 3.751, m2, u2);
        assert!(digits > 4 && ok, "{digits} digits");
        // Whatever the numbers, the row adds up as shown.
        let mut rng = rand_pcg::Pcg64Mcg::new(7);
        use rand::RngExt;
        for _ in 0..10_000 {
            let mut x = || 10f64.powf(rng.random_range(-3.0..3.0)) * rng.random_range(-1.0..1.0);
            let (m1, u1, m2, u2) = (x().abs(), x(), x().abs(), x());
            let (digits, ok) = adds_up(m1, u1, m2, u2);
            assert!(ok, "{m1} {u1} {m2} {u2}: {digits} digits");
        }
    }

    #[test]
    fn the_fps_row_says_when_busy_steps_hold_the_drawing_back() {
        let mut app = App::lesson(crate::scene::Lesson::Pingpong);
        app.paused = false;
        let fps_row = |app: &App| -> String {
            super::readout_lines(app)
                .iter()
                .map(line_text)
                .find(|l| l.starts_with(" fps"))
                .expect("an fps row")
        };
        assert_eq!(fps_row(&app), " fps       -");
        app.timing.fps = Some(58.6);
        assert_eq!(fps_row(&app), " fps       59");
        app.timing.fps = Some(29.7);
        app.timing.draw_held = true;
        assert_eq!(fps_row(&app), " fps       30, at most 30: steps busy");
        // Paused, frames are drawn only when something changes.
        app.paused = true;
        app.timing.draw_held = false;
        assert_eq!(fps_row(&app), " fps       -, paused: drawn on change");
    }

    #[test]
    fn wrap_breaks_between_words_within_the_width() {
        assert_eq!(wrap("a bb ccc dddd", 6), ["a bb", "ccc", "dddd"]);
        assert_eq!(wrap("", 6), Vec::<String>::new());
        assert_eq!(wrap("toolongword x", 4), ["toolongword", "x"]);
    }

    #[test]
    fn counts_are_separated_or_in_exponent_form() {
        assert_eq!(count(99_999), "99,999");
        assert_eq!(count(4_999_950_000), "5.0e9");
    }

    #[test]
    fn the_computers_times_keep_three_figures() {
        let cases = [
            (0.00421, "4.21 µs"),
            (0.312, "312 µs"),
            (0.9996, "1.00 ms"),
            (3.742, "3.74 ms"),
            (9.996, "10.0 ms"),
            (17.26, "17.3 ms"),
            (172.07, "172 ms"),
            (999.6, "1,000 ms"),
            (1234.5, "1,235 ms"),
        ];
        for (ms, text) in cases {
            assert_eq!(format_ms(ms), text, "{ms} ms");
        }
    }

    /// The text of the selection rows of a ball in flight after one step
    /// of `method` from (0.5, 0.5, 0.5) at 1 m/s up and sideways, and where
    /// it got to.
    fn flight_rows(method: Integrator) -> (Vec<String>, Vec3) {
        let (rows, _, x, _) = one_step(method, 0.5, Vec3::new(1.0, 1.0, 0.0), 1.0);
        (rows, x)
    }

    /// A ball of radius 0.05 m at `(0.5, y, 0.5)` moving at `v`, walls with
    /// `c_r = c`, after one step of 1/30 s by `method`: its panel rows, its
    /// inspection and its velocity.
    fn one_step(
        method: Integrator,
        y: f64,
        v: Vec3,
        c: f64,
    ) -> (Vec<String>, Inspection, Vec3, Vec3) {
        let mut w = crate::study::stability::ball_world(method, 1.0 / 30.0, y, c);
        w.bodies.velocity[0] = v;
        let (rows, inspection) = rows_after_a_step(&mut w, 0);
        (rows, inspection, w.bodies.position[0], w.bodies.velocity[0])
    }

    /// The world of a scene file's `text`.
    fn scene_world(text: &str) -> crate::sim::World {
        crate::scene::parse_scene(text, "test", "test")
            .unwrap()
            .build()
            .unwrap()
    }

    /// Step `w` once and inspect sphere `id`: the panel's rows and the
    /// inspection.
    fn rows_after_a_step(w: &mut crate::sim::World, id: u32) -> (Vec<String>, Inspection) {
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        let mut history = History::new(w);
        w.step();
        history.record(w);
        let inspection = inspect(w, &history, Selection::Sphere(id), &[], 0).unwrap();
        let rows = selection_lines(&inspection, 400)
            .iter()
            .map(line_text)
            .collect();
        (rows, inspection)
    }

    #[test]
    fn a_sphere_without_impacts_says_from_when_it_is_known_to_have_none() {
        // One step of free flight in the middle of the box: no impact,
        // and the row says since when that is known, or that this step
        // comes before the log of impacts.
        let mut w = crate::study::stability::ball_world(
            Integrator::SemiImplicitEuler,
            1.0 / 30.0,
            0.5,
            0.9,
        );
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        let mut history = History::new(&w);
        w.step();
        history.record(&w);
        let impact_row = |from: u64| {
            let inspection = inspect(&w, &history, Selection::Sphere(0), &[], from).unwrap();
            let rows: Vec<String> = selection_lines(&inspection, 400)
                .iter()
                .map(line_text)
                .collect();
            rows.into_iter()
                .find(|r| r.starts_with(" impact "))
                .expect("an impact row")
        };
        assert_eq!(impact_row(0), " impact    none since step 0");
        assert_eq!(
            impact_row(1),
            " impact    none in this step (noted from here on; ',' steps back to look earlier)"
        );
        assert_eq!(
            impact_row(2),
            " impact    unknown at this step (the log starts at step 2)"
        );
    }

    #[test]
    fn gravity_turning_a_sphere_short_of_the_ceiling_is_no_wall() {
        // Up at 0.74 m/s from 0.94 m for 0.1 s: semi-implicit Euler's step
        // (v first) turns it down 0.0241 m below the ceiling at 0.95. Its
        // velocity reversed near a wall, yet it met none: no wall rows.
        let scene = "[world]\ndt = 0.1\nwall_restitution = 0.8\npair_collisions = false\n\
            rest_steps = 0.0\n[[body]]\nposition = [0.5, 0.94, 0.5]\n\
            velocity = [0.0, 0.74, 0.0]\nradius = 0.05\nmass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, inspection) = rows_after_a_step(&mut w, 0);
        assert!(w.bodies.velocity[0].y < 0.0 && w.bodies.position[0].y < 0.95);
        assert_eq!(inspection.spheres[0].wall_now, None, "{rows:?}");
        assert!(!rows.iter().any(|r| r.starts_with(" wall")), "{rows:?}");
    }

    #[test]
    fn a_chain_stopped_at_its_most_walls_says_so() {
        // 70 m/s across a box 0.1 m wide for a second: past the other wall
        // after 100 walls, it is stopped there.
        let scene = "[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 1.0\nwall_mode = \"flip\"\n\
            pair_collisions = false\nrest_steps = 0.0\n[[body]]\n\
            position = [0.5, 0.5, 0.5]\nvelocity = [70.0, 0.0, 0.0]\nradius = 0.45\nmass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, inspection) = rows_after_a_step(&mut w, 0);
        let last = inspection.spheres[0]
            .wall_impacts
            .last()
            .copied()
            .expect("walls");
        assert!(last.stopped);
        assert_eq!(
            (w.bodies.position[0].x, w.bodies.velocity[0].x),
            (last.position, 0.0)
        );
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" stopped   still past the other wall after 100 walls")),
            "{rows:?}"
        );
        assert!(
            rows.iter()
                .any(|r| r.contains("which carries it past the other wall")),
            "{rows:?}"
        );
    }

    /// [`one_step`] with walls of `c_r = 0.9`: rows, inspection, velocity.
    fn wall_step(method: Integrator, y: f64, v: Vec3) -> (Vec<String>, Inspection, Vec3) {
        let (rows, inspection, _, v) = one_step(method, y, v, 0.9);
        (rows, inspection, v)
    }

    #[test]
    fn a_sphere_s_rows_add_up_to_its_x_with_what_contacts_and_walls_moved_it() {
        // Two 1 kg spheres of r = 0.1 overlapping by 0.15 m and at rest:
        // the contact stage moves each 0.075 m apart, a push no flight row
        // shows. The rows had given x = 0.550 for a sphere at 0.625.
        let scene = "[world]\ngravity = [0.0, 0.0, 0.0]\n\
            [[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n\
            [[body]]\nposition = [0.55, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, _) = rows_after_a_step(&mut w, 1);
        assert!(
            rows.iter().any(|r| r
                == " then      (0.075, 0.000, 0.000) m by its contacts: x = (0.625, 0.500, 0.500)"),
            "{rows:?}"
        );
        // Meeting head on, elastic: the contact's velocity change too.
        let scene = "[world]\ngravity = [0.0, 0.0, 0.0]\npair_restitution = 1.0\n\
            [[body]]\nposition = [0.5, 0.5, 0.5]\nvelocity = [1.0, 0.0, 0.0]\nradius = 0.1\n\
            mass = 1.0\n\
            [[body]]\nposition = [0.69, 0.5, 0.5]\nvelocity = [-1.0, 0.0, 0.0]\nradius = 0.1\n\
            mass = 1.0\n";
        let mut w = scene_world(scene);
        let (rows, _) = rows_after_a_step(&mut w, 1);
        assert!(
            rows.iter().any(|r| r
                == " then v    + (2.000, 0.000, 0.000) m/s by its contacts: v = (1.000, 0.000, 0.000)"),
            "{rows:?}"
        );
        // A sphere in flight has nothing to add.
        let (rows, ..) = one_step(Integrator::SemiImplicitEuler, 0.5, Vec3::X, 0.9);
        assert!(!rows.iter().any(|r| r.starts_with(" then")), "{rows:?}");
        // One sent back from the floor: the wall's share.
        let (rows, ..) = one_step(Integrator::SemiImplicitEuler, 0.06, -Vec3::Y, 0.9);
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" then") && r.contains(" by a wall: x = ")),
            "{rows:?}"
        );
    }

    #[test]
    fn the_velocity_row_gives_every_component_under_sideways_gravity() {
        // Gravity along +x: the row had shown v_y alone, hiding what
        // gravity adds to v_x.
        let mut w =
            crate::study::stability::ball_world(Integrator::SemiImplicitEuler, 0.1, 0.5, 0.9);
        w.config.gravity = Vec3::new(6.0, -8.0, 0.0);
        let (rows, _) = rows_after_a_step(&mut w, 0);
        let v = w.bodies.velocity[0];
        assert!(
            rows.iter().any(|r| r.starts_with(
                " v += g dt (0.000, 0.000, 0.000) + (6.000, -8.000, 0.000) (1/10) = "
            ) && r.ends_with(&format_vector(v))),
            "{rows:?}"
        );
    }

    #[test]
    fn a_selected_sleeper_on_the_floor_meets_no_wall() {
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        let r = 0.05;
        let mut w =
            crate::study::stability::ball_world(Integrator::SemiImplicitEuler, 1.0 / 30.0, r, 0.9);
        w.config.sleep = true;
        let mut history = History::new(&w);
        for _ in 0..20 {
            w.step();
            history.record(&w);
        }
        assert_eq!(w.last.asleep, 1, "asleep on the floor");
        let inspection = inspect(&w, &history, Selection::Sphere(0), &[], 0).unwrap();
        assert!(inspection.spheres[0].wall_now.is_none());
        assert!(inspection.spheres[0].wall_impacts.is_empty());
        // It did not move: no flight over dt, and nothing moved it after.
        let rows: Vec<String> = selection_lines(&inspection, 400)
            .iter()
            .map(line_text)
            .collect();
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" asleep    the step left it")),
            "{rows:?}"
        );
        assert!(
            !rows
                .iter()
                .any(|r| r.starts_with(" then") || r.starts_with(" x += v dt")),
            "{rows:?}"
        );
    }

    #[test]
    fn a_pair_moved_by_an_earlier_contact_of_the_step_says_its_numbers_are_as_found() {
        // Three spheres in a row, each overlapping the next by 10 mm and
        // closing by 4.167 mm in the step (dt = 1/120 s): the pair 0 & 1
        // is resolved first and moves sphere 1, so the pair
        // 1 & 2 is resolved with the normal and overlap found before.
        let body = |x: f64, vx: f64| {
            format!(
                "[[body]]\nposition = [{x}, 0.5, 0.5]\nvelocity = [{vx}, 0.0, 0.0]\n\
                 radius = 0.05\nmass = 1.0\n"
            )
        };
        let text = format!(
            "[world]\ngravity = [0.0, 0.0, 0.0]\n{}{}{}",
            body(0.31, 0.5),
            body(0.40, 0.0),
            body(0.49, -0.5)
        );
        let mut w = scene_world(&text);
        let pair = |w: &mut crate::sim::World, a: u32, b: u32| {
            use crate::tui::history::History;
            use crate::tui::selection::{Selection, inspect};
            let mut w = w.clone();
            let mut history = History::new(&w);
            w.step();
            history.record(&w);
            let inspection = inspect(&w, &history, Selection::pair(a, b), &[], 0).unwrap();
            let rows: Vec<String> = selection_lines(&inspection, 400)
                .iter()
                .map(line_text)
                .collect();
            (rows, inspection)
        };
        // The first pair resolved has its numbers as found: no such row.
        let (first, _) = pair(&mut w, 0, 1);
        assert!(
            first.iter().any(|r| r.starts_with(" delta     14.167 mm")),
            "{first:?}"
        );
        assert!(!first.iter().any(|r| r.starts_with(" found")), "{first:?}");
        let (second, inspection) = pair(&mut w, 1, 2);
        let p = inspection.pair.expect("resolved");
        let then = 0.1 - (p.before[1] - p.before[0]).length();
        assert!((then - p.penetration).abs() > 1e-3, "sphere 1 moved first");
        let found = format!(
            " found     n, delta as found; earlier contacts of the step moved the pair \
             before its turn: (r1 + r2) - d = {} then",
            format_length(then)
        );
        assert!(second.contains(&found), "{found:?} in {second:?}");
    }

    #[test]
    fn the_wall_rows_give_the_velocity_the_wall_stage_gave_by_their_own_formula() {
        let (g, dt) = (9.81, 1.0 / 30.0);
        for method in [
            Integrator::ExplicitEuler,
            Integrator::SemiImplicitEuler,
            Integrator::VelocityVerlet,
            Integrator::Rk4,
        ] {
            // Onto the floor at 2 m/s, moving sideways too.
            let (rows, inspection, v) = wall_step(method, 0.09, Vec3::new(1.0, -2.0, 0.0));
            let impact = inspection.spheres[0].wall_impacts[0];
            assert_eq!((impact.axis, impact.far), (1, false), "{method:?}");
            assert_eq!(impact.velocity, v.y, "{method:?}: the step's own v_y");
            assert!(rows.iter().any(|r| r.starts_with(" wall      the floor")));
            assert!(rows.iter().any(|r| r.starts_with(" c         c_r = 0.90")));
            assert!(
                rows.iter()
                    .any(|r| r.starts_with(" out") && r.ends_with(&format_number(v.y))),
                "{method:?}: {rows:?}"
            );
            let formula = match method {
                Integrator::SemiImplicitEuler => "w = √((v_y + g_y dt/2)² − 2 |g_y| d)",
                Integrator::ExplicitEuler => "w = √((v_y − g_y dt/2)² − 2 |g_y| d)",
                _ => "w = √(v_y² − 2 |g_y| d) = ",
            };
            assert!(
                rows.iter()
                    .any(|r| r.starts_with(" at wall") && r.contains(formula)),
                "{method:?}: {rows:?}"
            );
            // The Euler methods' w is not a speed the sphere had: the row
            // says where it comes from.
            let kept = format!("from the energy {} keeps in flight", method.name());
            let euler = matches!(
                method,
                Integrator::ExplicitEuler | Integrator::SemiImplicitEuler
            );
            assert_eq!(
                rows.iter()
                    .any(|r| r.starts_with(" at wall") && r.contains(&kept)),
                euler,
                "{method:?}: {rows:?}"
            );
            if impact.at_crossing {
                // Back along the exact parabola: the formula the row gives.
                let w = (impact.before.powi(2) - 2.0 * g * impact.overshoot).sqrt();
                assert!((w - impact.at_wall).abs() < 1e-12, "{method:?}");
                assert!(
                    rows.concat()
                        .contains("at the crossing, back along the parabola"),
                    "{method:?}: {rows:?}"
                );
            } else {
                // The rows' formula, from the numbers they show: the mirror
                // works on v_y + k g_y dt/2 (k = 1/2 semi-implicit, -1/2
                // explicit), with the overshoot d.
                let k = if method == Integrator::ExplicitEuler {
                    0.5
                } else {
                    -0.5
                };
                let shadow = impact.before + k * g * dt;
                let w = (shadow * shadow - 2.0 * g * impact.overshoot).sqrt();
                assert!((w - impact.at_wall).abs() < 1e-12, "{method:?}");
                let c = impact.coefficient;
                let out = ((c * w).powi(2) - 2.0 * g * c * impact.overshoot).sqrt() - k * g * dt;
                assert!((out - v.y).abs() < 1e-12, "{method:?}: {out} {}", v.y);
                // Beside it, what c |v_y| in would have given.
                let lesson = format!(
                    "c |v_y| in ({} m/s here)",
                    format_number(c * impact.before.abs())
                );
                assert!(
                    rows.iter().any(|r| r.starts_with(" why")) && rows.concat().contains(&lesson),
                    "{method:?}: {rows:?}"
                );
            }
        }
        // At rest on the floor: resting contact, said.
        let (rows, inspection, v) = wall_step(Integrator::SemiImplicitEuler, 0.05, Vec3::ZERO);
        let impact = inspection.spheres[0].wall_impacts[0];
        assert!(impact.rests && impact.coefficient == 0.0 && v.y == 0.0);
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" c         0: resting contact")),
            "{rows:?}"
        );
        assert!(rows.iter().any(|r| r.contains("it rests on it: v_y = 0")));
        // Velocity Verlet at rest on the floor: the parabola crosses the
        // floor at the step's start, with no speed to rebound.
        let (rows, inspection, _) = wall_step(Integrator::VelocityVerlet, 0.05, Vec3::ZERO);
        let impact = inspection.spheres[0].wall_impacts[0];
        assert!(impact.at_crossing && impact.rests, "{impact:?}");
        assert!(impact.at_wall < 1e-6, "{impact:?}");
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" at wall") && r.contains("at the crossing")),
            "{rows:?}"
        );
        assert!(rows.iter().any(|r| r.contains("it rests on it: v_y = 0")));
        // No wall in reach: no wall rows.
        let (rows, inspection, _) = wall_step(Integrator::SemiImplicitEuler, 0.5, Vec3::ZERO);
        assert!(inspection.spheres[0].wall_impacts.is_empty());
        assert!(!rows.iter().any(|r| r.starts_with(" wall")));
    }

    #[test]
    fn a_resting_pair_says_why_its_e_is_0_and_an_impact_shows_its_sums() {
        use crate::sim::{Body, World};
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        // One sphere on the floor, one sinking into it from above: at
        // 0.02 m/s and then at 1 m/s.
        let pair_closing = |closing: f64| {
            let r = 0.05;
            let body = |y: f64, vy: f64| Body {
                position: Vec3::new(0.5, y, 0.5),
                velocity: Vec3::new(0.0, vy, 0.0),
                radius: r,
                mass: 1.0,
            };
            let config = WorldConfig {
                gravity: Vec3::new(0.0, -9.81, 0.0),
                dt: 1.0 / 240.0,
                pair_collisions: true,
                pair_restitution: 0.95,
                ..WorldConfig::default()
            };
            let bodies = [body(r, 0.0), body(3.0 * r - 0.001, -closing)];
            let mut w = World::new(config, bodies.into_iter().collect());
            let mut history = History::new(&w);
            w.step();
            history.record(&w);
            (w, history)
        };
        let e_and_sums = |closing: f64| -> Vec<String> {
            let (w, history) = pair_closing(closing);
            let inspection = inspect(&w, &history, Selection::pair(0, 1), &[], 0).unwrap();
            selection_lines(&inspection, 400)
                .iter()
                .map(line_text)
                .filter(|r| {
                    [" e ", " why ", " m1v1+m2v2", " V1 =", " V2 ="]
                        .iter()
                        .any(|k| r.starts_with(k))
                })
                .collect()
        };
        // Gravity adds 9.81 / 240 = 0.041 m/s along the vertical normal in
        // a step: slower than that, the impact is resting contact.
        assert_eq!(
            e_and_sums(0.02)[..2],
            [
                " e         0: resting contact (key y)",
                " why       approached at 0.020 m/s, under |g\u{b7}n| dt = 0.041 m/s"
            ]
        );
        // Faster, e is the scene's, and the lesson's sums are shown with
        // the pair's numbers: both spheres gained g dt downwards before the
        // contact, so they close at 1 m/s.
        let rows = e_and_sums(1.0);
        let g_dt = 9.81 / 240.0;
        let p = -g_dt + (-1.0 - g_dt);
        // V1 with m2 (v1 - v2) = 1, V2 with m1 (v2 - v1) = -1, as the
        // lesson writes them.
        let sum = |apart: &str, v: f64| {
            format!(
                "({} - 1.000 \u{d7} {apart} \u{d7} 0.95) / 2.000 = {}",
                format_significant(p),
                format_number(v)
            )
        };
        let (big_v1, big_v2) = ((p - 0.95) / 2.0, (p + 0.95) / 2.0);
        assert_eq!(
            rows,
            [
                " e         0.95".to_string(),
                format!(
                    " m1v1+m2v2 1.000 \u{d7} {} + 1.000 \u{d7} {} = {} kg m/s",
                    signed(format_significant(-g_dt)),
                    signed(format_significant(-1.0 - g_dt)),
                    format_significant(p)
                ),
                format!(" V1 =      {}", sum("1.000", big_v1)),
                format!(" V2 =      {}", sum("(-1.000)", big_v2)),
            ]
        );
        // Short of rows, why e is 0 gives way before the sums that check it
        // (nine rows fewer: the pair's momentum and energy, mu, J and why).
        let (w, history) = pair_closing(0.02);
        let inspection = inspect(&w, &history, Selection::pair(0, 1), &[], 0).unwrap();
        let all = selection_lines(&inspection, 40).len();
        let short: Vec<String> =
            selection_lines_within(&inspection, &inspection.config, 40, all - 9)
                .iter()
                .map(line_text)
                .collect();
        assert!(
            short.iter().any(|r| r.starts_with(" e         0: resting")),
            "{short:#?}"
        );
        assert!(!short.iter().any(|r| r.starts_with(" why ")), "{short:#?}");
        for sum in [" m1v1+m2v2", " V1 =", " V2 ="] {
            assert!(
                short.iter().any(|r| r.starts_with(sum)),
                "{sum}: {short:#?}"
            );
        }
    }

    #[test]
    fn the_worked_v1_and_v2_check_by_hand_from_the_numbers_they_show() {
        use crate::sim::{Body, World};
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        use rand::{RngExt, SeedableRng};
        // Pairs of random masses meeting head on at random speeds, without
        // gravity: the V rows' sums, done with the numbers as shown, give
        // the V shown.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
        let mut more_figures = 0;
        for k in 0..200 {
            let e = [0.95, 0.5, 1.0, 0.37][k % 4];
            let mut body = |x: f64| Body {
                position: Vec3::new(x, 0.5, 0.5),
                velocity: Vec3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-1.0..1.0),
                    0.0,
                ),
                radius: 0.05,
                mass: rng.random_range(0.01..2.0),
            };
            let mut bodies = [body(0.45), body(0.549)];
            bodies[0].velocity.x = bodies[1].velocity.x + rng.random_range(0.01..4.0);
            let config = WorldConfig {
                gravity: Vec3::ZERO,
                dt: 1e-6,
                pair_collisions: true,
                pair_restitution: e,
                ..WorldConfig::default()
            };
            let mut w = World::new(config, bodies.into_iter().collect());
            let mut history = History::new(&w);
            w.step();
            history.record(&w);
            let inspection = inspect(&w, &history, Selection::pair(0, 1), &[], 0).unwrap();
            let all: Vec<String> = selection_lines(&inspection, 400)
                .iter()
                .map(line_text)
                .collect();
            // The speeds across n (near x: the spheres moved a hair in y
            // before they met), which the step kept.
            let n = inspection.pair.as_ref().unwrap().normal;
            let across = |v: Vec3| (v - n * v.dot(n)).length();
            let before = [across(bodies[0].velocity), across(bodies[1].velocity)];
            assert!(
                all.contains(&format!(" across n  {} m/s, kept", two(before))),
                "pair {k}: {all:#?}"
            );
            for (v, was) in w.bodies.velocity.iter().zip(before) {
                assert!((across(*v) - was).abs() < 1e-12, "pair {k}");
            }
            let rows: Vec<&String> = all
                .iter()
                .filter(|r| r.starts_with(" V1 =") || r.starts_with(" V2 ="))
                .collect();
            assert_eq!(rows.len(), 2, "pair {k}");
            for row in rows {
                // " V1 =      (P - M × A × E) / T = V"
                let numbers: Vec<f64> = row[11..]
                    .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
                    .filter_map(|t| t.parse().ok())
                    .collect();
                let [p, m, a, e_shown, t, v] = numbers[..] else {
                    panic!("pair {k}: {row}");
                };
                assert_eq!(e_shown, e, "{row}");
                assert_eq!(
                    format_number((p - m * a * e_shown) / t),
                    format_number(v),
                    "pair {k}: {row}"
                );
                let p_text = row[11..].trim_start_matches('(').split(' ').next().unwrap();
                let figures = p_text.trim_start_matches(['-', '0', '.']).replace('.', "");
                more_figures += usize::from(figures.len() > 4);
            }
        }
        // Some rows needed more than four figures to check.
        assert!(more_figures > 0);
    }

    #[test]
    fn a_sphere_that_meets_two_walls_in_a_step_shows_the_rule_of_each() {
        use crate::tui::history::History;
        use crate::tui::selection::{Selection, inspect};
        // Resting on the floor, sliding into the z = 1 wall at 2 m/s.
        let mut w = crate::study::stability::ball_world(
            Integrator::SemiImplicitEuler,
            1.0 / 30.0,
            0.05,
            0.9,
        );
        let r = w.bodies.radius[0];
        w.bodies.position[0] = Vec3::new(0.5, r, 1.0 - r - 0.01);
        w.bodies.velocity[0] = Vec3::new(0.0, 0.0, 2.0);
        let mut history = History::new(&w);
        w.step();
        history.record(&w);
        let inspection = inspect(&w, &history, Selection::Sphere(0), &[], 0).unwrap();
        let impacts = &inspection.spheres[0].wall_impacts;
        let walls: Vec<_> = impacts.iter().map(|i| (i.axis, i.far)).collect();
        assert_eq!(walls, [(1, false), (2, true)]);
        assert_eq!(impacts[1].velocity, w.bodies.velocity[0].z);
        assert!(
            w.bodies.velocity[0].z < 0.0,
            "it bounced off the z = 1 wall"
        );
        let rows: Vec<String> = selection_lines(&inspection, 400)
            .iter()
            .map(line_text)
            .collect();
        for wall in [" wall      the floor", " wall      the z = 1 wall"] {
            assert!(rows.iter().any(|r| r.starts_with(wall)), "{wall}: {rows:?}");
        }
        let out = format_number(w.bodies.velocity[0].z);
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" out") && r.ends_with(&out)),
            "{rows:?}"
        );
    }

    #[test]
    fn the_continuous_method_shows_one_flight_only_where_the_step_was_one() {
        // Onto the floor: impact by impact, not the step's formulas.
        let (rows, inspection, _) =
            wall_step(Integrator::Continuous, 0.09, Vec3::new(1.0, -2.0, 0.0));
        assert!(inspection.spheres[0].wall_now.is_some());
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" motion    impact by impact")),
            "{rows:?}"
        );
        assert!(
            !rows.iter().any(|r| r.starts_with(" x += v dt")),
            "{rows:?}"
        );
        // Resting on the floor: no wall reversed, but no flight either.
        let (rows, inspection, _) = wall_step(Integrator::Continuous, 0.05, Vec3::ZERO);
        assert!(inspection.spheres[0].wall_now.is_none());
        assert!(
            rows.iter()
                .any(|r| r.starts_with(" motion    impact by impact")),
            "{rows:?}"
        );
        // In free flight the step is one parabola, and its formula shows.
        let (rows, inspection, _) =
            wall_step(Integrator::Continuous, 0.5, Vec3::new(1.0, -2.0, 0.0));
        assert!(inspection.spheres[0].wall_now.is_none());
        assert!(rows.iter().any(|r| r.starts_with(" x += v dt")), "{rows:?}");
        assert!(!rows.iter().any(|r| r.starts_with(" motion")), "{rows:?}");
    }

    #[test]
    fn a_short_selection_box_drops_the_flight_rows_before_the_wall_rows() {
        let (_, inspection, v) = wall_step(
            Integrator::SemiImplicitEuler,
            0.09,
            Vec3::new(1.0, -2.0, 0.0),
        );
        let text = |lines: Vec<Line>| -> Vec<String> { lines.iter().map(line_text).collect() };
        let full = text(selection_lines(&inspection, 38));
        let within = |rows: usize| {
            text(selection_lines_within(
                &inspection,
                &inspection.config,
                38,
                rows,
            ))
        };
        assert!(full.iter().any(|r| r.starts_with(" x += v dt")), "{full:?}");
        let short = within(full.len() - 1);
        assert!(
            !short
                .iter()
                .any(|r| r.starts_with(" x += v dt") || r.starts_with(" v += g dt"))
        );
        let out = format_number(v.y);
        assert!(
            short.iter().any(|r| r.trim_end().ends_with(&out)),
            "the velocity out stays: {short:?}"
        );
        assert!(short.len() < full.len());
        // With room, nothing is dropped.
        assert_eq!(within(full.len()), full);
        // Shorter still, the `why` goes next, and the last impact stays.
        let why = short
            .iter()
            .position(|r| r.starts_with(" why"))
            .expect("a why");
        let why_rows = 1 + short[why + 1..]
            .iter()
            .take_while(|r| r.starts_with("           "))
            .count();
        let fewer = short.len() - why_rows;
        let shorter = within(fewer);
        assert_eq!(shorter.len(), fewer, "{shorter:?}");
        assert!(
            !shorter.iter().any(|r| r.starts_with(" why")),
            "{shorter:?}"
        );
        assert!(shorter.iter().any(|r| r.trim_end().ends_with(&out)));
        // The last row says how many gave way, after the last impact.
        let [.., impact, note] = &shorter[..] else {
            panic!("{shorter:?}")
        };
        assert!(impact.starts_with(" impact"), "{shorter:?}");
        let left_out = full.len() + 1 - shorter.len();
        assert!(
            note == &format!(" ({left_out} more rows in a taller terminal)"),
            "{shorter:?}"
        );
        // Shorter again, the sphere's readout goes (its position, velocity,
        // speed, radius and mass: the wall rows name what met the wall),
        // and the wall's rows and the velocity out stay.
        let readout = shorter
            .iter()
            .position(|r| r.starts_with(" x "))
            .expect("the position");
        let readout_rows = shorter[readout..]
            .iter()
            .position(|r| r.starts_with(" r, m"))
            .expect("the radius and mass")
            + 1;
        let least = fewer - readout_rows;
        let fewest = within(least);
        assert_eq!(fewest.len(), least, "{fewest:?}");
        for gone in [" x ", " v ", " speed", " r, m"] {
            assert!(!fewest.iter().any(|r| r.starts_with(gone)), "{fewest:?}");
        }
        for kept in [" wall", " at wall", " c ", " out", " impact"] {
            assert!(fewest.iter().any(|r| r.starts_with(kept)), "{fewest:?}");
        }
        assert!(fewest.iter().any(|r| r.trim_end().ends_with(&out)));
        // Below what can give way, the rows are cut and the last of them
        // says so, above the count of those left out; a single row is cut.
        let cut = within(1);
        assert!(cut.len() == 1 && cut[0].ends_with('\u{2026}'), "{cut:?}");
        for rows in [4, least - 1] {
            let cut = within(rows);
            assert_eq!(cut.len(), rows, "{cut:?}");
            let last_cut = &cut[rows - 2];
            assert!(
                last_cut.ends_with('\u{2026}') && last_cut.chars().count() <= 38,
                "{cut:?}"
            );
            // Every row of the whole panel is shown or counted.
            assert!(
                cut[rows - 1]
                    == format!(
                        " ({} more rows in a taller terminal)",
                        full.len() - (rows - 1)
                    ),
                "{cut:?}"
            );
            assert_eq!(cut[..rows - 2], fewest[..rows - 2]);
        }
        // Where the note's sentence does not fit, its count alone shows.
        let narrow = text(selection_lines_within(
            &inspection,
            &inspection.config,
            30,
            fewer,
        ));
        let note = narrow.last().expect("rows");
        assert!(
            note.starts_with(" (") && note.ends_with(" rows left out)"),
            "{narrow:?}"
        );
    }

    #[test]
    fn a_small_displacement_is_shown_in_millimetres_not_as_zero() {
        let half_g_dt2 = 0.5 * 9.81 / (240.0 * 240.0);
        assert_eq!(
            format_length_vector(Vec3::new(0.0, -half_g_dt2, 0.0)),
            "(0.000, -0.085, 0.000) mm"
        );
        assert_eq!(
            format_length_vector(Vec3::new(0.25, 0.0, 0.0)),
            "(0.250, 0.000, 0.000) m"
        );
    }

    #[test]
    fn the_position_rows_follow_the_method_and_add_up_to_its_step() {
        let dt = 1.0 / 30.0;
        let half_g_dt2 = 0.5 * 9.81 * dt * dt;
        for (method, moved_by) in [
            (
                Integrator::ExplicitEuler,
                "(1.000, 1.000, 0.000) (1/30), the old v",
            ),
            (
                Integrator::SemiImplicitEuler,
                "(1.000, 0.673, 0.000) (1/30), the new v",
            ),
            (
                Integrator::VelocityVerlet,
                "(1.000, 1.000, 0.000) (1/30), the old v",
            ),
            (Integrator::Rk4, "(1.000, 1.000, 0.000) (1/30), the old v"),
        ] {
            let (rows, x) = flight_rows(method);
            let at = rows
                .iter()
                .position(|r| r.starts_with(" x += v dt"))
                .unwrap();
            assert_eq!(rows[at + 1].trim(), moved_by, "{method:?}: {rows:?}");
            let exact = matches!(method, Integrator::VelocityVerlet | Integrator::Rk4);
            let dy = if method == Integrator::SemiImplicitEuler {
                (1.0 - 9.81 * dt) * dt
            } else if exact {
                dt - half_g_dt2
            } else {
                dt
            };
            assert!((x.y - (0.5 + dy)).abs() < 1e-12, "{method:?}: {}", x.y);
            let parabola = rows.iter().any(|r| r.starts_with(" + g dt²/2"));
            assert_eq!(parabola, exact, "{method:?}: {rows:?}");
            if exact {
                assert!(rows.contains(&" + g dt²/2 (0.000, -5.450, 0.000) mm".to_string()));
            }
        }
    }

    #[test]
    fn a_long_row_wraps_under_its_value_within_the_panel() {
        let text = |lines: Vec<Line>| -> Vec<String> {
            lines
                .iter()
                .map(|l| l.spans.iter().map(|s| s.content.as_ref()).collect())
                .collect()
        };
        let value = "v_y -2.409 + (-9.810) (1/240) = -2.450".to_string();
        let rows = text(wrapped_row(40, "v += g dt", value.clone()));
        assert_eq!(
            rows,
            [
                " v += g dt v_y -2.409 + (-9.810) (1/240)",
                "           = -2.450"
            ]
        );
        assert!(rows.iter().all(|r| r.chars().count() <= 40), "{rows:?}");
        assert_eq!(text(wrapped_row(60, "v += g dt", value)).len(), 1);
    }

    #[test]
    fn dt_reads_as_a_fraction_when_it_is_one() {
        assert_eq!(format_dt(1.0 / 120.0), "1/120 s (8.333 ms)");
        assert_eq!(format_dt(0.003), "3.000 ms");
    }
}
