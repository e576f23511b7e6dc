//! What a person sees: the visualiser drawn into ratatui's `TestBackend`
//! at fixed sizes and seeds, compared with committed snapshots. Timing
//! readouts are left unmeasured, so nothing depends on the clock.
#![cfg(feature = "tui")]

use lerpit::scene::Lesson;
use lerpit::tui::{Action, App};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

fn draw(app: &App, width: u16, height: u16) -> TestBackend {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).unwrap();
    terminal.draw(|f| f.render_widget(app, f.area())).unwrap();
    terminal.backend().clone()
}

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
fn too_small_message() {
    let app = lesson_after(Lesson::Pingpong, 0);
    insta::assert_snapshot!(draw(&app, 60, 20));
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
