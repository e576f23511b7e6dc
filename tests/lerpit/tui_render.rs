//! What a person sees: the visualiser drawn into ratatui's `TestBackend`
//! at fixed sizes and seeds, compared with committed snapshots. Timing
//! readouts are left unmeasured, so nothing depends on the clock.

use crate::support::{README, draw};
use lerpit::scene::Lesson;
use lerpit::sim::Integrator;
use lerpit::study::Row;
use lerpit::tui::{Action, App};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

/// A lesson paused after `steps` steps.
fn lesson_after(lesson: Lesson, steps: usize) -> App {
    let mut app = App::lesson(lesson);
    for _ in 0..steps {
        app.apply(Action::StepForward);
    }
    app
}

#[test]
fn pingpong_lesson() {
    let app = lesson_after(Lesson::Pingpong, 20);
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn gravity_lesson_with_trails() {
    let mut app = lesson_after(Lesson::Gravity, 40);
    app.apply(Action::ToggleTrails);
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn collisions_lesson_with_vectors_from_the_front() {
    let mut app = lesson_after(Lesson::Collisions, 60);
    app.apply(Action::ToggleVectors);
    app.apply(Action::View(lerpit::tui::camera::Preset::Front));
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn smallest_layout_with_a_status_message() {
    let mut app = lesson_after(Lesson::Pingpong, 5);
    app.apply(Action::MoreSpheres);
    insta::assert_snapshot!(draw(&app, 80, 24));
}

#[test]
fn help_overlay() {
    let mut app = lesson_after(Lesson::Pingpong, 0);
    app.apply(Action::ToggleHelp);
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn help_overlay_in_a_small_terminal_scrolls() {
    let mut app = lesson_after(Lesson::Pingpong, 0);
    app.apply(Action::ToggleHelp);
    app.apply(Action::ScrollHelp(8));
    insta::assert_snapshot!(draw(&app, 80, 24));
}

#[test]
fn the_help_holds_the_lesson_s_whole_text_that_a_small_panel_cuts() {
    // At the README's 110x36 the collisions lesson's idea ends in an
    // ellipsis in the panel; the help begins with all of it.
    let mut app = lesson_after(Lesson::Collisions, 0);
    let idea = lerpit::scene::Lesson::Collisions.scene().info.unwrap().idea;
    let last_words: String = idea
        .split_whitespace()
        .rev()
        .take(3)
        .collect::<Vec<_>>()
        .join(" ");
    let panel = screen_text(&draw(&app, 110, 36));
    assert!(panel.contains('…'), "the panel cuts the idea:\n{panel}");
    app.apply(Action::ToggleHelp);
    let help: String = screen_rows(&draw(&app, 110, 36))
        .iter()
        .map(|l| l.trim_matches(|c: char| c == '│' || c == ' '))
        .collect::<Vec<_>>()
        .join(" ");
    let last: Vec<&str> = last_words.split(' ').rev().collect();
    let wanted = last.join(" ");
    assert!(
        help.split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .contains(&wanted),
        "the help lacks {wanted:?}:\n{help}"
    );
}

/// Keys do not act behind the help, which leaves the footer in view: it
/// says what was not done and how to close the help.
#[test]
fn a_key_pressed_behind_the_help_is_answered_in_view() {
    let mut app = lesson_after(Lesson::Gravity, 0);
    let method = app.frame.world.config.integrator;
    app.apply(Action::ToggleHelp);
    app.apply(Action::NextIntegrator);
    assert_eq!(app.frame.world.config.integrator, method);
    let screen = draw(&app, 80, 24).to_string();
    let footer: String = screen.lines().rev().take(3).collect::<Vec<_>>().join(" ");
    assert!(
        footer.contains("not done while the help covers the view")
            && footer.contains("? or Esc closes it"),
        "the footer says the key was not done:\n{screen}"
    );
}

/// A world busy with an action (a million spheres placed anew after `-`)
/// says in the footer what it is working on, and how to get out: the
/// oldest action it has not carried out, as it takes them in turn, and
/// Esc where Esc stops it (a search or a step, not the building of a
/// world), unless Esc closes the help there.
#[test]
fn while_the_world_works_on_an_action_the_footer_says_which() {
    let mut app = lesson_after(Lesson::Gravity, 0);
    let before = app.frame.applied;
    // As the worker's frames say while it still places the spheres (the
    // search sent meanwhile), then once it searches.
    app.apply(Action::FewerSpheres);
    let fewer = app.frame.applied;
    std::sync::Arc::make_mut(&mut app.frame).applied = before;
    app.apply(Action::NextCollision);
    assert!(before < fewer && fewer < app.frame.applied);
    let footer = |app: &App| draw(app, 120, 30).to_string();
    std::sync::Arc::make_mut(&mut app.frame).applied = before;
    app.timing.waiting = true;
    let screen = footer(&app);
    assert!(
        screen.contains("working on: fewer spheres (restarts)... (q quits)"),
        "{screen}"
    );
    assert!(!app.mode().working, "Esc does not stop the building");
    app.timing.waiting = false;
    assert!(!footer(&app).contains("working on"));
    app.timing.waiting = true;
    std::sync::Arc::make_mut(&mut app.frame).applied = fewer;
    let screen = footer(&app);
    assert!(
        screen.contains(
            "working on: the search for the next collision... (Esc stops it and forgets the \
             selection, q quits)"
        ),
        "{screen}"
    );
    assert!(app.mode().working);
    app.apply(Action::ToggleHelp);
    let screen = footer(&app);
    assert!(
        screen.contains("working on: the search for the next collision... (q quits)"),
        "{screen}"
    );
}

#[test]
fn too_small_message() {
    let app = lesson_after(Lesson::Pingpong, 0);
    insta::assert_snapshot!(draw(&app, 60, 20));
}

#[test]
fn a_tiny_terminal_still_shows_the_size_needed_and_the_way_out() {
    let app = lesson_after(Lesson::Pingpong, 0);
    let screen = draw(&app, 20, 5).to_string();
    for needed in ["too small: 20x5", "needs ", "q quits"] {
        assert!(screen.contains(needed), "{needed:?} in\n{screen}");
    }
}

#[test]
fn no_color_legend() {
    let mut app = lesson_after(Lesson::Gravity, 0);
    app.colour = false;
    let screen = draw(&app, 120, 40).to_string();
    assert!(
        screen.contains("colour off (NO_COLOR)"),
        "the legend says colour is off:\n{screen}"
    );
}

#[test]
fn pingpong_lesson_with_the_exact_ghost() {
    let mut app = lesson_after(Lesson::Pingpong, 10);
    app.apply(Action::ToggleGhost);
    for _ in 0..15 {
        app.apply(Action::StepForward);
    }
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn the_ghost_shows_without_colour() {
    let mut app = lesson_after(Lesson::Gravity, 30);
    app.colour = false;
    app.apply(Action::ToggleGhost);
    app.apply(Action::StepForward);
    let plain_next = {
        let mut without = lesson_after(Lesson::Gravity, 31);
        without.colour = false;
        draw(&without, 120, 40).to_string()
    };
    let ghosted = draw(&app, 120, 40).to_string();
    let view = |s: &str| -> String {
        s.lines()
            .skip(1)
            .take(30)
            .map(|l| l.chars().take(76).collect::<String>())
            .collect()
    };
    assert_ne!(
        view(&ghosted),
        view(&plain_next),
        "the ghost's marks differ from the spheres' alone"
    );
    assert!(ghosted.contains("+ exact ghost"), "the legend names it");
    assert!(
        ghosted.contains(" ghost    "),
        "the panel shows its distance"
    );
}

#[test]
fn a_ghost_past_its_horizon_leaves_the_legend() {
    // The collisions lesson's ghost stops 1 s after it starts (colliding
    // spheres are chaotic): the legend no longer names a ghost drawn.
    let mut app = lesson_after(Lesson::Collisions, 0);
    app.apply(Action::ToggleGhost);
    let before = draw(&app, 120, 40).to_string();
    assert!(before.contains("+ exact ghost"), "drawn at its start");
    let steps = (1.2 / app.frame.world.config.dt).ceil() as usize;
    for _ in 0..steps {
        app.apply(Action::StepForward);
    }
    let after = draw(&app, 120, 40).to_string();
    assert!(after.contains("off: past 1 s"), "the panel says why");
    assert!(!after.contains("+ exact ghost"), "{after}");
    assert!(after.contains("no ghost now"), "{after}");
}

/// Still spheres without gravity, each `(position, radius)`.
fn still_spheres(spheres: &[([f64; 3], f64)]) -> App {
    let mut toml = String::from("[world]\ngravity = [0.0, 0.0, 0.0]\npair_collisions = false\n");
    for (p, r) in spheres {
        toml += &format!("[[body]]\nposition = {p:?}\nradius = {r}\nmass = 1.0\n");
    }
    let scene = lerpit::scene::parse_scene(&toml, "test", "still spheres").unwrap();
    let mut app = App::new(scene, None).unwrap();
    app.apply(Action::TogglePause);
    app
}

#[test]
fn a_long_title_ends_in_an_ellipsis_before_the_state() {
    // Cut by the header's room, the title ends in an ellipsis, as the side
    // panel's do; it was cut mid-word.
    let toml = "[lesson]\ntitle = \"An extraordinarily long lesson title that keeps going well \
                past the width of any sensible side panel\"\n[[body]]\n\
                position = [0.5, 0.5, 0.5]\nradius = 0.05\nmass = 1.0\n";
    let scene = lerpit::scene::parse_scene(toml, "test", "long").unwrap();
    let mut app = App::new(scene, None).unwrap();
    app.apply(Action::TogglePause);
    for width in [80, 101, 120] {
        let drawn = draw(&app, width, 30).to_string();
        let top = drawn.lines().next().unwrap();
        assert!(
            top.contains("lerpit: An extraordinarily")
                && top.contains("\u{2026} ")
                && top.contains(" paused "),
            "{width} columns: {top}"
        );
    }
}

#[test]
fn a_near_sphere_hides_a_far_one() {
    // From the three-quarter view the near sphere (z = 0.7) covers part of
    // the far one (z = 0.25); both cast a shadow on the floor.
    let app = still_spheres(&[([0.6, 0.4, 0.25], 0.15), ([0.45, 0.45, 0.7], 0.15)]);
    insta::assert_snapshot!(draw(&app, 120, 40));
}

#[test]
fn views_from_above_and_below_differ_by_the_shadow_on_the_floor() {
    use lerpit::tui::camera::Preset;
    use ratatui::buffer::Buffer;
    use ratatui::layout::Rect;
    let mut app = still_spheres(&[([0.5, 0.7, 0.5], 0.06)]);
    let area = Rect::new(0, 0, 60, 30);
    let (w, h) = (usize::from(area.width) * 2, usize::from(area.height) * 4);
    // What the box view draws in the cell showing the point of the floor
    // under the sphere.
    let under_the_sphere = |app: &App| {
        let mut buf = Buffer::empty(area);
        lerpit::tui::view::render_box(app, area, &mut buf);
        let floor = lerpit::sim::Vec3::new(0.5, 0.0, 0.5);
        let (x, y) = app.camera.projection(w, h).to_screen(floor);
        let cell = ((x / 2.0) as u16, (y / 4.0) as u16);
        buf[cell].symbol().to_string()
    };
    app.apply(Action::View(Preset::ThreeQuarter));
    let above = under_the_sphere(&app);
    app.apply(Action::Orbit {
        yaw: 0.0,
        pitch: -50f64.to_radians(),
    });
    assert!(app.camera.pitch < -0.4, "now looking from below");
    let below = under_the_sphere(&app);
    assert_ne!(
        above.trim(),
        "",
        "from above the shadow is drawn on the floor"
    );
    assert_eq!(
        below.trim(),
        "",
        "from below the floor's upper side, and the shadow, face away"
    );
}

#[test]
fn the_hash_key_draws_the_floor_grid() {
    use lerpit::tui::keymap::{Key, dispatch};
    use ratatui::crossterm::event::KeyCode;
    let mut app = still_spheres(&[([0.5, 0.5, 0.5], 0.05)]);
    // The picture, without the footer (which says what the key did).
    let picture = |app: &App| -> Vec<String> {
        let drawn = draw(app, 120, 40).to_string();
        let rows: Vec<String> = drawn.lines().map(String::from).collect();
        rows[..rows.len() - 1].to_vec()
    };
    let without = picture(&app);
    let hash = Key {
        code: KeyCode::Char('#'),
        ctrl: false,
    };
    let action = dispatch(hash, app.mode()).expect("# is bound");
    app.apply(action);
    assert!(app.show_floor_grid);
    assert_ne!(picture(&app), without, "the grid shows");
    assert!(
        draw(&app, 120, 40)
            .to_string()
            .contains("floor grid on (#: off)")
    );
    app.apply(action);
    assert_eq!(picture(&app), without, "and goes again");
}

/// Work-precision rows with fixed figures: cost grows as 1/dt, error as
/// dt^p (p = 1 for the discrete methods, flat at 1e-15 for continuous).
fn synthetic_rows(lesson: Lesson) -> Vec<Row> {
    let dts = lerpit::study::sweep::log_spaced(1.0 / 30.0, 2.0, 8);
    let mut rows = Vec::new();
    for (k, &method) in Integrator::ALL.iter().enumerate() {
        for &dt in &dts {
            let cost = (1.0 + k as f64) * 1e-5 / dt;
            let error = if method == Integrator::Continuous {
                1e-15
            } else {
                (0.5 + k as f64) * dt
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

fn no_sweep(_: Lesson) -> Result<Vec<Row>, String> {
    Err("not computed in this test".into())
}

/// The chart screen alone, as the app draws it above the footer of a
/// `width` x `height + 1` terminal.
fn draw_chart_screen(app: &App, width: u16, height: u16) -> TestBackend {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).unwrap();
    terminal
        .draw(|f| lerpit::tui::work_chart::render_work_chart(app, f.area(), f.buffer_mut()))
        .unwrap();
    terminal.backend().clone()
}

/// A lesson's chart open on the synthetic rows, paused.
fn chart_of(lesson: Lesson) -> App {
    let mut app = App::lesson(lesson).with_chart_source(no_sweep);
    app.charts.insert(lesson, synthetic_rows(lesson));
    app.apply(Action::TogglePause);
    app.apply(Action::ToggleChart);
    assert_eq!(app.charts.started, 0, "known data is not computed again");
    app
}

#[test]
fn work_precision_chart_screen() {
    let app = chart_of(Lesson::Gravity);
    insta::assert_snapshot!(draw_chart_screen(&app, 120, 39));
}

#[test]
fn work_precision_chart_without_colour_in_the_smallest_layout() {
    let mut app = chart_of(Lesson::Collisions);
    app.colour = false;
    insta::assert_snapshot!(draw_chart_screen(&app, 80, 23));
}

static GATE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn gated_sweep(lesson: Lesson) -> Result<Vec<Row>, String> {
    let _open = GATE.lock().unwrap_or_else(|e| e.into_inner());
    Ok(synthetic_rows(lesson))
}

#[test]
fn the_chart_says_computing_until_its_data_arrives() {
    let mut app = App::lesson(Lesson::Pingpong).with_chart_source(gated_sweep);
    let gate = GATE.lock().unwrap();
    app.apply(Action::ToggleChart);
    let screen = draw(&app, 120, 40).to_string();
    assert!(screen.contains("computing..."), "{screen}");
    drop(gate);
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !app.poll_background() {
        assert!(std::time::Instant::now() < deadline, "no result came back");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let screen = draw(&app, 120, 40).to_string();
    assert!(
        screen.contains("wall time per simulated second"),
        "{screen}"
    );
    assert!(screen.contains("continuous"), "{screen}");
    app.apply(Action::CloseChart);
    let screen = draw(&app, 120, 40).to_string();
    assert!(screen.contains("lerpit: Ping-pong"), "the view is back");
}

#[test]
fn the_chart_of_a_scene_file_says_it_covers_the_lessons_only() {
    let app = App::lesson(Lesson::Gravity);
    let mut app = App::new((*app.frame.scene).clone(), None)
        .unwrap()
        .with_chart_source(no_sweep);
    app.apply(Action::ToggleChart);
    assert_eq!(app.charts.started, 0);
    let screen = draw(&app, 120, 40).to_string();
    assert!(screen.contains("covers the lessons only"), "{screen}");
}

#[test]
fn the_readme_key_table_is_the_programs() {
    let readme = README;
    let table = lerpit::tui::help::markdown_table();
    assert!(
        readme.contains(&table),
        "README.md's key table differs from the program's; paste this one:\n{table}"
    );
}

#[test]
fn a_selected_pairs_panel_shows_the_lessons_formulas_with_its_numbers() {
    use lerpit::tui::panel::format_number;
    let mut app = App::lesson(Lesson::Collisions);
    app.apply(Action::NextCollision);
    let inspection = app.frame.inspection.clone().expect("o selects a pair");
    let pair = inspection.pair.expect("in contact at this step");
    let ([m1, m2], [v1, v2], e) = (pair.mass, pair.v_normal, pair.e);
    let big_v1 = (m1 * v1 + m2 * v2 - m2 * (v1 - v2) * e) / (m1 + m2);
    let big_v2 = (m1 * v1 + m2 * v2 - m1 * (v2 - v1) * e) / (m1 + m2);
    let screen = draw(&app, 120, 40);
    let text = screen_text(&screen);
    let shown = format!(
        "V1, V2    {}, {} m/s",
        format_number(big_v1),
        format_number(big_v2)
    );
    assert!(text.contains(&shown), "the panel shows {shown:?}");
    assert!(text.contains(&format!("e         {e:.2}")));
    // The impulse on 1 is m1 (V1 - v1), and 2 takes its opposite: the
    // momentum along n is kept.
    let j = m1 * (big_v1 - v1);
    assert!((m2 * (big_v2 - v2) + j).abs() <= 1e-12 * j.abs(), "{j}");
    // The panel writes it -(1 + e) mu (v1 - v2), mu = m1 m2 / (m1 + m2).
    let written = -(1.0 + e) * m1 * m2 / (m1 + m2) * (v1 - v2);
    assert!((written - j).abs() <= 1e-12 * j.abs(), "{j} {written}");
    let shown = format!(
        "J         -(1+e)\u{3bc}(v1-v2) = {} N s",
        lerpit::tui::numbers::format_significant_to(written, 3)
    );
    assert!(text.contains(&shown), "the panel shows {shown:?}:\n{text}");
    let shown = format!(
        "\u{3bc}         m1m2/(m1+m2) = {} kg",
        lerpit::tui::numbers::format_significant(m1 * m2 / (m1 + m2))
    );
    assert!(text.contains(&shown), "the panel shows {shown:?}:\n{text}");
    insta::assert_snapshot!(screen);
}

#[test]
fn a_selection_takes_the_panels_rows_before_the_readouts_in_a_small_terminal() {
    let mut app = App::lesson(Lesson::Collisions);
    app.apply(Action::NextCollision);
    for (width, height) in [(80, 24), (100, 30)] {
        let screen = draw(&app, width, height);
        let text = screen_text(&screen);
        for row in [
            "Pair ",
            "m1, m2",
            "V1, V2",
            "m1v1+m2v2",
            " V1 =   ",
            " V2 =   ",
        ] {
            assert!(text.contains(row), "{width}x{height} lacks {row:?}");
        }
    }
    // At 100x31 everything fits; at 80x24 the pair's momentum and energy
    // give way first, then mu, J, the speeds across n, how far each
    // sphere moved and their radii, so that the lesson's sums stay (and
    // those that fit again with them come back), and the last row says
    // how many rows were left out.
    let text = screen_text(&draw(&app, 100, 31));
    for row in [
        "r1, r2",
        "moved",
        "p after",
        "KE  ",
        " \u{3bc}    ",
        "across n",
    ] {
        assert!(text.contains(row), "100x31 lacks {row:?}");
    }
    let text = screen_text(&draw(&app, 80, 24));
    for row in ["p after", " J    ", " \u{3bc}    ", "moved"] {
        assert!(!text.contains(row), "80x24 has {row:?} before the sums");
    }
    assert!(text.contains("more rows in a taller terminal)"), "{text}");
    // There the lesson's equation gives its row to the sums, which write
    // it out with the pair's numbers; the title and the time stay.
    assert!(
        !text.contains("V1 = (m1 v1") && text.contains("Collisions") && text.contains(" time "),
        "80x24 keeps the title and time, not the equation:\n{text}"
    );
    // Between, mu gives way before the J it defines.
    let text = screen_text(&draw(&app, 100, 27));
    assert!(
        text.contains(" J    ") && !text.contains(" \u{3bc}    "),
        "at 100x27 J without mu:\n{text}"
    );
    // At 80x30 the lesson's equation is cut short, and says so.
    let text = screen_text(&draw(&app, 80, 30));
    assert!(
        text.contains("V1 = (m1 v1 + m2 v2 - m2 (v1 - v2) e)\u{2026}"),
        "the cut equation ends in an ellipsis:\n{text}"
    );
}

#[test]
fn every_picked_collisions_sums_show_whole_at_80x24() {
    // Pair after pair, whatever else their rows hold (the note that
    // earlier contacts moved them, masses to seven figures that wrap each
    // sum onto three rows), the lesson's sums show whole at 80x24 with the
    // found collision's message on two lines of the footer.
    let mut app = App::lesson(Lesson::Collisions);
    for k in 1..=20 {
        app.apply(Action::NextCollision);
        let text = screen_text(&draw(&app, 80, 24));
        for row in ["m1v1+m2v2", " V1 =   ", " V2 =   "] {
            assert!(text.contains(row), "collision {k} lacks {row:?}:\n{text}");
        }
        assert!(
            !text.contains("\u{2026}\u{2502}"),
            "collision {k}: a row cut short:\n{text}"
        );
    }
}

#[test]
fn a_selections_box_only_grows_while_its_numbers_change() {
    // Stepping on from a picked collision, the pair's rows change (out of
    // contact: each sphere's rows instead of the sums), but its box only
    // ever grows: rows above it that gave way do not come back to go
    // again at the next step.
    let mut app = App::lesson(Lesson::Collisions);
    app.apply(Action::NextCollision);
    for (width, height) in [(80, 24), (100, 31), (120, 40)] {
        let top = |app: &App| {
            screen_rows(&draw(app, width, height))
                .iter()
                .position(|r| r.contains("\u{250c} selection"))
                .expect("a selection box")
        };
        let mut last = top(&app);
        let mut contents = std::collections::HashSet::new();
        for step in 1..=12 {
            app.apply(Action::StepForward);
            let now = top(&app);
            assert!(
                now <= last,
                "{width}x{height}, step {step}: {last} then {now}"
            );
            last = now;
            contents.insert(screen_text(&draw(&app, width, height)).contains("m1v1+m2v2"));
        }
        assert!(
            contents.contains(&false),
            "{width}x{height}: the rows changed"
        );
    }
}

#[test]
fn a_narrow_legend_leaves_out_what_is_off_before_the_selection() {
    // With a pair picked, the legend names the selection's colour in every
    // size the panel is drawn at; the overlays that are off, then the colour
    // scale, give way first, and what is left keeps its order.
    let mut app = App::lesson(Lesson::Collisions);
    app.apply(Action::NextCollision);
    let legend = |width: u16, height: u16| {
        let rows = screen_rows(&draw(&app, width, height));
        rows.into_iter()
            .find(|r| r.contains("selected"))
            .unwrap_or_else(|| panic!("{width}x{height}: no legend names the selection"))
    };
    let wide = legend(200, 60);
    for item in [
        "speed 0 ",
        "trails off",
        "vectors off",
        "contacts",
        "selected",
    ] {
        assert!(wide.contains(item), "200x60 lacks {item:?}: {wide}");
    }
    // At 100x30 `vectors off` gives way, so that `selected` fits; at
    // 80x24 the scale too, and what room is left takes `trails off` back.
    let narrow = legend(100, 30);
    assert!(
        narrow.contains("│speed 0 ██████ 5 m/s  trails off  contacts  selected  "),
        "{narrow}"
    );
    assert!(legend(80, 24).contains("│trails off  contacts  selected  "));
    for (width, height) in [(100, 30), (80, 24)] {
        let narrow = legend(width, height);
        let contacts = narrow
            .find("contacts")
            .expect("the contacts drawn are named");
        assert!(contacts < narrow.find("selected").unwrap(), "{narrow}");
    }
}

#[test]
fn a_wall_collision_keeps_its_coefficient_and_velocity_out_at_80x24() {
    // `o` in the gravity lesson stops on a wall: in the smallest terminal
    // the sphere's position, velocity, speed, radius and mass give way so
    // that the wall, the speed at it, the c_r used and the velocity out
    // show.
    let mut app = App::lesson(Lesson::Gravity);
    app.apply(Action::TogglePause);
    app.apply(Action::NextCollision);
    let text = screen_text(&draw(&app, 80, 24));
    for row in [
        " wall      the ",
        " at wall   w = ",
        " c         c_r = 0.95 ",
        " out       0.95 w = ",
        " more rows in a taller terminal)",
    ] {
        assert!(text.contains(row), "80x24 lacks {row:?}:\n{text}");
    }
    assert!(!text.contains(" speed     "), "{text}");
    // With room, the readout is back.
    let text = screen_text(&draw(&app, 120, 40));
    assert!(text.contains(" speed     ") && text.contains(" c         c_r = 0.95 "));
}

#[test]
fn a_long_message_takes_more_footer_rows_and_a_longer_one_says_it_is_cut() {
    let row = |screen: &TestBackend, y: u16| -> String {
        (0..80)
            .map(|x| screen.buffer()[(x, y)].symbol().to_string())
            .collect()
    };
    let mut app = lesson_after(Lesson::Pingpong, 0);
    // 127 characters: two rows of 80 columns.
    app.status = Some(format!("{}the end", "a long message ".repeat(8)));
    let screen = draw(&app, 80, 24);
    let (above, last) = (row(&screen, 22), row(&screen, 23));
    assert!(
        above.starts_with(" a long message") && last.contains("the end"),
        "{above}\n{last}"
    );
    assert!(!above.contains('\u{2026}') && !last.contains('\u{2026}'));
    assert!(last.contains("? help"), "the key hints follow: {last}");
    // Three rows at most: a longer message ends with an ellipsis.
    app.status = Some(format!("{}the end", "a long message ".repeat(20)));
    let screen = draw(&app, 80, 24);
    assert!(row(&screen, 21).starts_with(" a long message"));
    assert!(row(&screen, 23).contains('\u{2026}') && !row(&screen, 23).contains("the end"));
    app.status = Some("short".into());
    let screen = draw(&app, 80, 24);
    let footer = row(&screen, 23);
    assert!(
        footer.contains("short") && footer.contains("q quit"),
        "{footer}"
    );
    assert!(
        !row(&screen, 22).contains("a long message"),
        "one row again"
    );
}

/// Every cell of `screen`, row after row, as one string.
/// The screen's rows, each its own string.
fn screen_rows(screen: &TestBackend) -> Vec<String> {
    let buffer = screen.buffer();
    let width = usize::from(buffer.area.width).max(1);
    buffer
        .content()
        .chunks(width)
        .map(|row| row.iter().map(|c| c.symbol()).collect())
        .collect()
}

fn screen_text(screen: &TestBackend) -> String {
    screen
        .buffer()
        .content()
        .iter()
        .map(|c| c.symbol())
        .collect()
}

#[test]
fn the_ping_pong_lessons_text_says_a_force_acts_once_gravity_is_on() {
    let mut app = App::lesson(Lesson::Pingpong);
    let before = screen_text(&draw(&app, 120, 40));
    assert!(before.contains("No force acts") && !before.contains("a force acts"));
    assert!(!before.contains("v(t+dt)"), "{before}");
    app.apply(Action::GravityUp);
    let text = screen_text(&draw(&app, 120, 40));
    assert!(
        text.contains("Now gravity pulls at") && text.contains("a force acts"),
        "{text}"
    );
    // The equation gains the lesson's velocity equation (wrapped), and
    // the position moves as the method moves it: semi-implicit Euler (the
    // lesson's) with the new velocity.
    assert!(
        text.contains("v(t+dt) = v(t) + F/m dt;  x(t+dt) =") && text.contains("+ v(t+dt) dt"),
        "{text}"
    );
    // Velocity Verlet, RK4 and the continuous method, exact under a
    // constant force, then explicit Euler with the old velocity.
    let exact = (
        "x(t+dt) = x(t) + v(t) dt + F/(2m) dt^2;",
        "v(t+dt) = v(t) + F/m dt",
    );
    let methods = [
        exact,
        exact,
        exact,
        ("x(t+dt) = x(t) + v(t) dt;  v(t+dt) =", "v(t) + F/m dt"),
    ];
    for (first, second) in methods {
        app.apply(Action::NextIntegrator);
        let text = screen_text(&draw(&app, 120, 40));
        assert!(text.contains(first) && text.contains(second), "{text}");
    }
    // Back to semi-implicit Euler.
    app.apply(Action::NextIntegrator);
    app.apply(Action::GravityDown);
    let text = screen_text(&draw(&app, 120, 40));
    assert!(
        !text.contains("Now gravity") && !text.contains("v(t+dt)"),
        "back to the lesson's: {text}"
    );
}

#[test]
fn the_ping_pong_lesson_opened_with_gravity_says_a_force_acts() {
    // `lerpit --lesson pingpong --gravity 9.81`: the text was written for
    // no gravity, whatever the command line asked.
    let mut scene = Lesson::Pingpong.scene();
    scene.world.gravity = lerpit::sim::gravity_down(9.81);
    let app = App::new(scene, Some(Lesson::Pingpong)).unwrap();
    let text = screen_text(&draw(&app, 120, 40));
    assert!(text.contains("Now gravity pulls at 9.81"), "{text}");
}
