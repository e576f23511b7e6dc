//! The event loop.
//!
//! The terminal's modes and the signals are `terminal.rs`'s: the loop looks
//! for a signal once an iteration and hands Ctrl-Z to it.
//!
//! The loop draws at most [`FPS`] frames a second, reads input between
//! frames, and advances physics in fixed steps through the
//! [`Accumulator`]; stepping that runs past [`STEP_BUDGET`] in a frame
//! drops the backlog. When paused and nothing changes it sleeps until the
//! next event (or, while the chart's data is being computed, until the
//! next look for it). Before each frame it takes in finished background
//! work and brings the ghost to the present step. It fills in the app's
//! timing readouts; nothing else here changes the app except through
//! `App::apply`, `App::step`, `App::poll_background` and
//! `App::refresh_ghost`.

use super::accumulator::Accumulator;
use super::app::App;
use super::keymap::{Key, dispatch, mouse_action};
use super::terminal::{self, Session, SignalEvent, Signals};
use ratatui::crossterm::event::{self, Event, KeyEventKind};
use std::io;
use std::time::{Duration, Instant};

/// Most frames drawn per second.
pub const FPS: f64 = 60.0;
/// How often a paused, idle loop looks for finished background work.
pub const BACKGROUND_POLL: Duration = Duration::from_millis(100);
/// Wall time stepping may take in one frame before the backlog is dropped.
pub const STEP_BUDGET: Duration = Duration::from_millis(25);

/// Run `app` full-screen until it quits; the terminal is restored however
/// this returns.
pub fn run_in_terminal(app: &mut App) -> io::Result<()> {
    let signals = Signals::install()?;
    let mut session = Session::enter()?;
    run(&mut session, &signals, app)
}

fn run(session: &mut Session, signals: &Signals, app: &mut App) -> io::Result<()> {
    let frame = Duration::from_secs_f64(1.0 / FPS);
    let mut accumulator = Accumulator::default();
    let mut drag = None;
    let mut dirty = true;
    let mut last_advance = Instant::now();
    let mut next_draw = Instant::now();
    let mut last_draw: Option<Instant> = None;

    while !app.should_quit {
        match signals.poll() {
            Some(SignalEvent::Exit(signal)) => session.exit(signal),
            Some(SignalEvent::Suspend) => {
                session.suspend()?;
                dirty = true;
            }
            Some(SignalEvent::Resume) => {
                session.resume()?;
                dirty = true;
            }
            None => {}
        }
        if app.poll_background() {
            dirty = true;
        }
        let now = Instant::now();
        if dirty && now >= next_draw {
            app.refresh_ghost();
            app.refresh_grid_tests();
            app.set_screen(session.terminal().size()?);
            session
                .terminal()
                .draw(|f| f.render_widget(&*app, f.area()))?;
            let drawn = Instant::now();
            app.timing.frame_ms = Some((drawn - now).as_secs_f64() * 1e3);
            if let Some(prev) = last_draw {
                let rate = 1.0 / (drawn - prev).as_secs_f64().max(1e-6);
                let fps = app.timing.fps.map_or(rate, |f| 0.9 * f + 0.1 * rate);
                app.timing.fps = Some(fps);
            }
            last_draw = Some(drawn);
            next_draw = now + frame;
            dirty = false;
        }

        let timeout = if dirty || !app.paused {
            next_draw.saturating_duration_since(Instant::now())
        } else if app.charts.busy() {
            BACKGROUND_POLL
        } else {
            terminal::SIGNAL_POLL
        };
        if event::poll(timeout)? {
            loop {
                match event::read()? {
                    Event::Key(k) if terminal::is_suspend_key(&k) => {
                        session.suspend()?;
                        dirty = true;
                    }
                    Event::Key(k) if k.kind == KeyEventKind::Press => {
                        if let Some(action) = dispatch(Key::from_event(&k), app.mode()) {
                            let (steps, t) = (app.world.steps, Instant::now());
                            app.apply(action);
                            if app.world.steps == steps + 1 {
                                app.timing.step_ms = Some(t.elapsed().as_secs_f64() * 1e3);
                            }
                        }
                        dirty = true;
                    }
                    Event::Mouse(m) if !app.help_open => {
                        if let Some(action) = mouse_action(&m, &mut drag) {
                            app.apply(action);
                            dirty = true;
                        }
                    }
                    Event::Resize(..) => dirty = true,
                    _ => {}
                }
                if app.should_quit || !event::poll(Duration::ZERO)? {
                    break;
                }
            }
        }

        let now = Instant::now();
        let elapsed = (now - last_advance).as_secs_f64();
        last_advance = now;
        if app.paused {
            accumulator.drop_backlog();
            continue;
        }
        let due = accumulator.advance(elapsed, app.time_scale(), app.world.config.dt);
        let mut taken = 0u32;
        while taken < due {
            app.step();
            taken += 1;
            if now.elapsed() > STEP_BUDGET {
                accumulator.drop_backlog();
                break;
            }
        }
        if taken > 0 {
            app.timing.step_ms = Some(now.elapsed().as_secs_f64() * 1e3 / f64::from(taken));
        }
        dirty = true;
    }
    Ok(())
}
