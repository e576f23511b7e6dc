//! The event loop.
//!
//! The terminal's modes and the signals are `terminal.rs`'s: the loop looks
//! for a signal once an iteration and hands Ctrl-Z to it.
//!
//! The physics runs on the worker thread (`worker.rs`), and keys and the
//! mouse are read on the input thread (`input.rs`); this loop, on the main
//! thread, only takes their events, hands actions to the app and draws the
//! newest published frame, at most as often as `draw_rate.rs` says. It never
//! waits for a step: while running, or while the world is still working
//! on an action, it looks for input and frames once a frame; when paused
//! and idle it sleeps until the next event (or, while the chart's data is
//! being computed, until the next look for it). It fills in the app's
//! timing readouts; nothing else here changes the app except through
//! `App::apply` and `App::poll_background`.

use super::action::Action;
use super::app::App;
use super::draw_rate::{DrawRate, FrameRate};
use super::input::Input;
use super::keymap::{Key, dispatch, mouse_action, unbound};
use super::terminal::{self, Screen, SignalEvent, Signals};
use super::view;
use ratatui::crossterm::event::{Event, KeyEventKind};
use std::io;
use std::time::{Duration, Instant};

/// How often a paused, idle loop looks for finished background work.
pub(crate) const BACKGROUND_POLL: Duration = Duration::from_millis(100);
/// The header says the world is working once an action has waited this
/// long.
pub(crate) const WAITING_SHOWN_AFTER: Duration = Duration::from_millis(150);
/// The header says how long a step has run once it has run this long.
pub(crate) const LONG_STEP_SHOWN_AFTER: Duration = Duration::from_millis(500);

/// Run `app` full-screen until it quits; the terminal is restored however
/// this returns. `building`, the line said while the scene was built, is
/// cleared once the signals are handled here, before the screen opens.
pub(crate) fn run_in_terminal(
    app: App,
    building: Option<crate::process::progress::Progress>,
) -> io::Result<()> {
    let signals = Signals::install()?;
    drop(building);
    let mut screen = Screen::enter(&signals)?;
    let input = Input::start()?;
    let mut app = app.start_worker();
    let ran = run(&mut screen, &signals, &input, &mut app);
    if ran.is_err() {
        // A terminal closed under the program (its window or pane) fails
        // the next write, and sends SIGHUP, which may come just after:
        // the program then ends as the signal asks (129), not as a
        // failure of its own.
        if let Some(SignalEvent::Exit(signal)) = signals.wait(HANG_UP_WAIT) {
            screen.exit(signal);
        }
    }
    ran
}

/// How long a failed terminal waits for the hang-up that may follow.
const HANG_UP_WAIT: Duration = Duration::from_millis(250);

fn run(screen: &mut Screen, signals: &Signals, input: &Input, app: &mut App) -> io::Result<()> {
    let mut rate = DrawRate::default();
    let mut measured = FrameRate::default();
    let mut drag = None;
    let mut dirty = true;
    let mut next_draw = Instant::now();
    let mut last_draw: Option<Instant> = None;
    let mut waiting_since: Option<Instant> = None;
    let mut size = screen.found_size()?;

    while !app.should_quit {
        match signals.poll() {
            Some(SignalEvent::Exit(signal)) => screen.exit(signal),
            Some(SignalEvent::Suspend) => {
                screen.suspend(signals)?;
                app.resumed();
                dirty = true;
            }
            Some(SignalEvent::Resume) => {
                screen.resume(signals)?;
                app.resumed();
                dirty = true;
            }
            None => {}
        }
        if app.poll_background() {
            dirty = true;
        }
        let now = Instant::now();
        let busy_for = app
            .step_running_for()
            .filter(|d| *d >= LONG_STEP_SHOWN_AFTER)
            .map(|d| (d.as_secs_f64() * 10.0).floor() / 10.0);
        dirty |= busy_for != app.timing.busy_for;
        app.timing.busy_for = busy_for;
        if app.awaiting() {
            let since = *waiting_since.get_or_insert(now);
            let waiting = now - since >= WAITING_SHOWN_AFTER;
            dirty |= waiting != app.timing.waiting;
            app.timing.waiting = waiting;
        } else {
            waiting_since = None;
            dirty |= app.timing.waiting;
            app.timing.waiting = false;
        }
        rate.update(
            !app.paused,
            &app.frame.pace,
            app.frame.world.config.dt,
            app.time_scale(),
        );
        dirty |= rate.held() != app.timing.draw_held;
        app.timing.draw_held = rate.held();
        let held = input.held();
        dirty |= held != app.timing.keys_held;
        app.timing.keys_held = held;
        // A resize is also an input event, which held input holds back:
        // look at the size itself.
        let now_size = screen.found_size()?;
        dirty |= now_size != size;
        size = now_size;
        if dirty && now >= next_draw {
            app.set_screen(screen.fit()?);
            screen
                .terminal()
                .draw(|f| f.render_widget(&*app, f.area()))?;
            let drawn = Instant::now();
            app.timing.frame_ms = Some((drawn - now).as_secs_f64() * 1e3);
            // Paused, a frame is drawn only when something changes: the
            // rate is that of the frames drawn running.
            if let Some(prev) = last_draw
                && !app.paused
            {
                app.timing.fps = measured.record((drawn - prev).as_secs_f64(), rate.fps());
            }
            last_draw = (!app.paused).then_some(drawn);
            next_draw = now + rate.interval();
            dirty = false;
        }

        // Running, or waiting for the world: look again by the next frame.
        let timeout = if dirty || !app.paused || app.awaiting() || busy_for.is_some() {
            next_draw
                .saturating_duration_since(Instant::now())
                .max(Duration::from_millis(1))
        } else if app.charts.busy() {
            BACKGROUND_POLL
        } else {
            terminal::SIGNAL_POLL
        };
        if let Some(first) = input.next(timeout) {
            let mut next = Some(first);
            while let Some(event) = next {
                match event? {
                    Event::Key(k) if k.kind == KeyEventKind::Press => {
                        match Key::from_event(&k).and_then(|key| dispatch(key, app.mode())) {
                            Some(Action::Suspend) => {
                                screen.suspend(signals)?;
                                app.resumed();
                            }
                            // Every cell is sent at the next frame, even
                            // where the last frame says it is there.
                            Some(Action::Redraw) => screen.terminal().clear()?,
                            // The too-small screen shows only the size and
                            // the way out: nothing else acts unseen.
                            Some(action) if action != Action::Quit && too_small(screen)? => {}
                            Some(action) => app.apply(action),
                            None => {
                                // Esc and a key typed at once arrive as
                                // Alt and that key, which does nothing.
                                if let Some(key) = Key::without_alt(&k)
                                    .filter(|&key| dispatch(key, app.mode()).is_some())
                                {
                                    app.status = Some(format!(
                                        "Alt-{} does nothing: no key is bound with Alt (Esc \
                                         and a key typed at once arrive as Alt and that key)",
                                        key.label()
                                    ));
                                } else if let Some(key) = Key::from_event(&k) {
                                    app.status = Some(unbound(key, app.mode()));
                                }
                            }
                        }
                        dirty = true;
                    }
                    Event::Mouse(_) if too_small(screen)? => {}
                    Event::Mouse(m) if !app.help_open => {
                        if let Some(action) = mouse_action(&m, &mut drag) {
                            app.apply(action);
                            dirty = true;
                        }
                    }
                    Event::Resize(..) => dirty = true,
                    // Pasted text is not keys: nothing in it acts.
                    Event::Paste(_) => {}
                    _ => {}
                }
                next = if app.should_quit { None } else { input.ready() };
            }
        }
    }
    Ok(())
}

/// Whether the terminal is below the size the visualiser draws in
/// (`view::too_small`).
fn too_small(screen: &mut Screen) -> io::Result<bool> {
    let size = screen.size()?;
    Ok(view::too_small(size.width, size.height))
}
