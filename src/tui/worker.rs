//! The worker thread: the simulation session runs here, apart from the
//! terminal, so that drawing and input never wait for a step.
//!
//! It runs on a thread of a pool of its own (one thread a core), so that
//! each stage of a step starts its parallel work on the thread that asks
//! for it. Asked from a thread outside the pool, every stage was handed
//! over and waited for, and the pool's threads woken for it: a step of
//! 100,000 settled spheres of the collisions lesson took about a sixth
//! longer that way (timed in runs by turns).
//!
//! The drawing thread sends [`Command`]s over a channel and counts them as
//! waiting; the worker carries them out in order, steps the world in
//! fixed steps through the [`Accumulator`] while running, and publishes a
//! [`Frame`] after its work: into a one-frame mailbox that the drawing
//! thread empties (the lock is held only to swap a pointer, never while
//! stepping or drawing).
//!
//! A step that has run for [`INTERRUPT_AFTER`] is abandoned when a command
//! that changes the simulation or its pace is waiting (not one that only
//! says what the frames carry; checked between sub-steps and between the continuous
//! method's impacts): the session puts the state back exactly as it was
//! before the step, so history and determinism are kept, and the command
//! takes effect at once. Shorter steps finish first, so a held key cannot
//! starve a world whose steps are merely slow. A step forward (`n`) waiting
//! does not stop a step forward in progress: it waits its turn, so five
//! presses take five steps (any other such command stops them, one after
//! the other, each at once).
//!
//! Owns the stepping policy and the pace figures; the physics is the
//! session's and the drawing the view's.

use super::accumulator::{Accumulator, MAX_FRAME_SECONDS, MAX_STEPS_PER_FRAME};
use super::action::Action;
use super::frame::{Frame, Message, Pace};
use super::session::Session;
use crate::sim::threads::thread_pool;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, TryRecvError, channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A step that has run this long is abandoned when a command waits.
pub(crate) const INTERRUPT_AFTER: Duration = Duration::from_millis(20);
/// The achieved time scale is measured over windows of this length.
pub(crate) const PACE_WINDOW: Duration = Duration::from_millis(1000);
/// Published frames kept for their buffers.
const SPARE_FRAMES: usize = 3;
/// The longest a paused, idle worker sleeps before looking again.
const IDLE_WAIT: Duration = Duration::from_millis(500);

/// What the drawing thread asks of the worker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Command {
    /// Carry out `action` (numbered by the app, see `App::apply`).
    Apply { seq: u64, action: Action },
    /// Run or pause, and at which time scale.
    Run { paused: bool, time_scale: f64 },
    /// Put the trails in the frames, or leave them out.
    Trails(bool),
    /// The view marks each step's contacts, or does not
    /// (`Session::show_contacts`).
    Contacts(bool),
    /// The process was stopped (Ctrl-Z, SIGSTOP) and runs again: the time
    /// it stood still is neither owed steps nor a slow pace.
    Resumed,
}

impl Command {
    /// Whether a long step gives way to this command while it waits: not
    /// for what only chooses what the frames carry or the steps list,
    /// which can wait for the step (or the search for a collision) to end.
    fn interrupts(self) -> bool {
        !matches!(self, Command::Trails(_) | Command::Contacts(_))
    }

    /// Whether this is a step forward (`n`): one waiting does not stop a
    /// step forward in progress but waits its turn, so five presses take
    /// five steps (the drawing thread adds no more than a second's worth,
    /// `App::steps_forward_full`). It stops anything else (a search, the
    /// running steps).
    fn steps_forward(self) -> bool {
        matches!(
            self,
            Command::Apply {
                action: Action::StepForward,
                ..
            }
        )
    }
}

/// What both threads hold.
struct Shared {
    mailbox: Mutex<Option<Arc<Frame>>>,
    /// Commands sent and not yet received: while any waits, a long step
    /// gives way. Raised before each send and lowered on each receipt, so
    /// it never misses a command and never counts one being carried out.
    waiting: AtomicU64,
    /// Of those, the steps forward. Raised before `waiting` and lowered
    /// after it, so that `waiting` less this never counts one too many.
    waiting_steps: AtomicU64,
    /// When the step in progress began, in nanoseconds after `epoch` (plus
    /// one, so that 0 means no step is in progress).
    step_began: AtomicU64,
    epoch: Instant,
}

impl Shared {
    fn new() -> Self {
        Self {
            mailbox: Mutex::new(None),
            waiting: AtomicU64::new(0),
            waiting_steps: AtomicU64::new(0),
            step_began: AtomicU64::new(0),
            epoch: Instant::now(),
        }
    }

    /// Whether a step begun at `started` should give way now.
    fn interrupted(&self, started: Instant) -> bool {
        self.waiting.load(Ordering::Acquire) > 0 && started.elapsed() >= INTERRUPT_AFTER
    }

    /// Whether a step forward begun at `started` should give way now: a
    /// command other than a further step forward waits.
    fn interrupted_step_forward(&self, started: Instant) -> bool {
        let waiting = self.waiting.load(Ordering::Acquire);
        let steps = self.waiting_steps.load(Ordering::Acquire);
        waiting.saturating_sub(steps) > 0 && started.elapsed() >= INTERRUPT_AFTER
    }

    fn mark_step(&self, began: Option<Instant>) {
        let ns = began.map_or(0, |t| (t - self.epoch).as_nanos() as u64 + 1);
        self.step_began.store(ns, Ordering::Release);
    }
}

/// The drawing thread's handle on the worker. Dropping it ends the worker
/// at its next look at the channel (an abandoned step at most).
pub(crate) struct Worker {
    commands: Sender<Command>,
    shared: Arc<Shared>,
}

impl std::fmt::Debug for Worker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Worker")
    }
}

impl Worker {
    /// Start the worker on `session`, paused or running at `time_scale`,
    /// with trails in its frames or not.
    pub(crate) fn spawn(session: Session, paused: bool, time_scale: f64, trails: bool) -> Worker {
        let (commands, inbox) = channel();
        let shared = Arc::new(Shared::new());
        let mut state = State {
            session,
            inbox,
            shared: Arc::clone(&shared),
            paused,
            time_scale,
            trails,
            accumulator: Accumulator::default(),
            owed: 0,
            last_tick: Instant::now(),
            applied: 0,
            message: None,
            messages: 0,
            pace: Pace::default(),
            window: (Instant::now(), 0.0),
            dropped_at: None,
            fresh: true,
            spare: Vec::new(),
        };
        std::thread::Builder::new()
            .name("lerpit-sim".into())
            .spawn(move || match thread_pool(None) {
                Ok(pool) => pool.install(|| state.run()),
                // No pool of its own: rayon's global one does the work.
                Err(_) => state.run(),
            })
            .expect("the simulation thread starts");
        Worker { commands, shared }
    }

    /// Send `command`, and ask a long step in progress to give way.
    pub(crate) fn send(&self, command: Command) {
        // A send fails only when the worker has ended (a panic there): the
        // drawing thread then keeps showing the last frame.
        if command.steps_forward() {
            self.shared.waiting_steps.fetch_add(1, Ordering::AcqRel);
        }
        if command.interrupts() {
            self.shared.waiting.fetch_add(1, Ordering::AcqRel);
        }
        let _ = self.commands.send(command);
    }

    /// How long the step in progress has run, if one is.
    pub(crate) fn step_running_for(&self) -> Option<Duration> {
        match self.shared.step_began.load(Ordering::Acquire) {
            0 => None,
            ns => {
                let began = self.shared.epoch + Duration::from_nanos(ns - 1);
                Some(Instant::now().saturating_duration_since(began))
            }
        }
    }

    /// The newest frame published since the last call, if any.
    pub(crate) fn take_frame(&self) -> Option<Arc<Frame>> {
        self.shared
            .mailbox
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // The channel closes with `commands`; a long step gives way first.
        self.shared.waiting.fetch_add(1, Ordering::AcqRel);
    }
}

struct State {
    session: Session,
    inbox: Receiver<Command>,
    shared: Arc<Shared>,
    paused: bool,
    time_scale: f64,
    trails: bool,
    accumulator: Accumulator,
    /// Steps due and not yet taken.
    owed: u32,
    last_tick: Instant,
    /// The number of the last action carried out.
    applied: u64,
    message: Option<Message>,
    messages: u64,
    pace: Pace,
    /// Start of the pace window and the simulated seconds stepped in it.
    window: (Instant, f64),
    /// When steps owed were last dropped.
    dropped_at: Option<Instant>,
    /// The state changed since the last frame was published.
    fresh: bool,
    /// Frames published lately, whose buffers are reused once the
    /// drawing thread has let go of them.
    spare: Vec<Arc<Frame>>,
}

impl State {
    fn run(&mut self) {
        loop {
            let wait = self.wait();
            if !wait.is_zero() && self.fresh {
                self.publish();
            }
            let first = if wait.is_zero() {
                match self.inbox.try_recv() {
                    Ok(c) => Some(c),
                    Err(TryRecvError::Empty) => None,
                    Err(TryRecvError::Disconnected) => return,
                }
            } else {
                match self.inbox.recv_timeout(wait) {
                    Ok(c) => Some(c),
                    Err(RecvTimeoutError::Timeout) => None,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            };
            if let Some(command) = first {
                let mut next = command;
                loop {
                    self.carry_out(next);
                    match self.inbox.try_recv() {
                        Ok(c) => {
                            // A step forward with more commands behind it
                            // shows as it is taken (steps forward queued
                            // behind each other), once the last frame has
                            // been taken for drawing.
                            if next.steps_forward() && self.mailbox_empty() {
                                self.publish();
                            }
                            next = c;
                        }
                        Err(TryRecvError::Empty) => break,
                        Err(TryRecvError::Disconnected) => return,
                    }
                }
                self.fresh = true;
                // The change shows at once, not after the next step, which
                // may be a long one.
                if self.mailbox_empty() {
                    self.publish();
                }
            }
            if !self.paused {
                self.tick();
                if self.owed > 0 {
                    self.step_once();
                }
            }
            if self.fresh && self.mailbox_empty() {
                self.publish();
            }
        }
    }

    /// How long to wait for a command before the next step is due.
    fn wait(&self) -> Duration {
        if self.paused {
            return IDLE_WAIT;
        }
        if self.owed > 0 {
            return Duration::ZERO;
        }
        let dt = self.session.world.config.dt;
        let owed_time = (dt - self.accumulator.pending()).max(0.0);
        let seconds = owed_time / self.time_scale.max(1e-9);
        Duration::from_secs_f64(seconds.min(IDLE_WAIT.as_secs_f64()))
    }

    /// Add the real time since the last tick to the steps owed; drop what
    /// the world cannot catch up with.
    fn tick(&mut self) {
        let now = Instant::now();
        let elapsed = (now - self.last_tick).as_secs_f64();
        self.last_tick = now;
        let dt = self.session.world.config.dt;
        let due = self.accumulator.advance(elapsed, self.time_scale, dt);
        let most = ((MAX_FRAME_SECONDS * self.time_scale / dt).ceil() as u32)
            .clamp(1, MAX_STEPS_PER_FRAME);
        self.owed = self.owed.saturating_add(due);
        if self.owed > most {
            self.owed = most;
            self.accumulator.drop_backlog();
            self.dropped_at = Some(now);
        }
    }

    fn step_once(&mut self) {
        let started = Instant::now();
        let interrupted = || self.shared.interrupted(started);
        self.shared.mark_step(Some(started));
        let finished = self.session.try_step(&interrupted);
        self.shared.mark_step(None);
        if finished {
            self.owed -= 1;
            self.pace.step_ms = Some(started.elapsed().as_secs_f64() * 1e3);
            self.window.1 += self.session.world.config.dt;
            self.fresh = true;
        } else {
            self.pace.abandoned += 1;
        }
        let now = Instant::now();
        let span = now - self.window.0;
        if span >= PACE_WINDOW {
            self.pace.achieved = Some(self.window.1 / span.as_secs_f64());
            self.window = (now, 0.0);
        }
        self.pace.behind = self.dropped_at.is_some_and(|t| now - t < 2 * PACE_WINDOW)
            || self
                .pace
                .achieved
                .is_some_and(|a| a < 0.9 * self.time_scale);
    }

    /// Measure the pace afresh: no steps owed, none dropped, no window.
    fn restart_pace(&mut self) {
        self.accumulator.drop_backlog();
        self.owed = 0;
        self.pace = Pace {
            step_ms: self.pace.step_ms,
            abandoned: self.pace.abandoned,
            ..Pace::default()
        };
        self.window = (Instant::now(), 0.0);
        self.dropped_at = None;
    }

    fn carry_out(&mut self, command: Command) {
        if command.interrupts() {
            self.shared.waiting.fetch_sub(1, Ordering::AcqRel);
        }
        if command.steps_forward() {
            self.shared.waiting_steps.fetch_sub(1, Ordering::AcqRel);
        }
        match command {
            Command::Apply { seq, action } => {
                let started = Instant::now();
                let (steps, worlds) = (self.session.world.steps, self.session.worlds);
                let interrupted = || {
                    if action == Action::StepForward {
                        self.shared.interrupted_step_forward(started)
                    } else {
                        self.shared.interrupted(started)
                    }
                };
                self.shared.mark_step(Some(started));
                self.session.apply_unless(action, &interrupted);
                self.shared.mark_step(None);
                if action == Action::StepForward && self.session.world.steps == steps {
                    self.pace.abandoned += 1;
                }
                if self.session.world.steps == steps + 1 {
                    self.pace.step_ms = Some(started.elapsed().as_secs_f64() * 1e3);
                }
                self.applied = seq;
                if self.session.worlds != worlds {
                    // A new world: the pace of the old one says nothing, and
                    // the steps it owed are not this one's to catch up.
                    self.restart_pace();
                    self.pace.step_ms = None;
                    self.last_tick = Instant::now();
                }
                if let Some(text) = self.session.take_message() {
                    self.messages += 1;
                    self.message = Some(Message {
                        id: self.messages,
                        after: Some(seq),
                        text,
                    });
                }
            }
            Command::Run { paused, time_scale } => {
                self.session.say_stopped_search();
                if paused != self.paused || time_scale != self.time_scale {
                    self.restart_pace();
                }
                self.paused = paused;
                self.time_scale = time_scale;
                self.last_tick = Instant::now();
            }
            Command::Trails(on) => self.trails = on,
            Command::Contacts(on) => self.session.show_contacts(on),
            Command::Resumed => {
                self.session.say_stopped_search();
                self.restart_pace();
                self.last_tick = Instant::now();
            }
        }
    }

    fn mailbox_empty(&self) -> bool {
        self.shared
            .mailbox
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_none()
    }

    /// Copy the session's state into a frame and put it in the mailbox,
    /// replacing one the drawing thread has not taken.
    fn publish(&mut self) {
        self.session.refresh_ghost();
        self.session.refresh_grid_tests();
        if let Some(text) = self.session.take_message() {
            self.messages += 1;
            self.message = Some(Message {
                id: self.messages,
                after: None,
                text,
            });
        }
        let reuse = self
            .spare
            .iter()
            .position(|f| Arc::strong_count(f) == 1)
            .and_then(|k| Arc::try_unwrap(self.spare.swap_remove(k)).ok());
        let mut frame = self.session.frame(self.trails, reuse);
        frame.applied = self.applied;
        frame.pace = self.pace;
        frame.message = self.message.clone();
        let frame = Arc::new(frame);
        let replaced = self
            .shared
            .mailbox
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .replace(Arc::clone(&frame));
        self.spare.extend(replaced);
        self.spare.push(frame);
        if self.spare.len() > SPARE_FRAMES {
            self.spare.remove(0);
        }
        self.fresh = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Lesson;

    /// Frames until one has carried out action `seq`.
    fn frame_after(worker: &Worker, seq: u64) -> Arc<Frame> {
        let patience = Instant::now() + Duration::from_secs(120);
        loop {
            if let Some(f) = worker.take_frame()
                && f.applied >= seq
            {
                return f;
            }
            assert!(Instant::now() < patience, "no frame after action {seq}");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Wait until the worker is in a step (`Worker::step_running_for`).
    fn step_begun(worker: &Worker) {
        let patience = Instant::now() + Duration::from_secs(120);
        while worker.step_running_for().is_none() {
            assert!(Instant::now() < patience, "no step began");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn the_worker_reaches_the_same_bits_as_a_session_stepped_in_place() {
        let actions = [
            Action::StepForward,
            Action::StepForward,
            Action::GravityDown,
            Action::StepForward,
            Action::PairRestitutionDown,
            Action::StepForward,
            Action::StepBack,
            Action::NextBroadPhase,
            Action::StepForward,
            Action::StepForward,
            Action::ToggleGhost,
            Action::StepForward,
        ];
        let mut here = Session::lesson(Lesson::Collisions);
        let worker = Worker::spawn(Session::lesson(Lesson::Collisions), true, 1.0, false);
        // Each action once the last is carried out: with none waiting, no
        // step gives way (`INTERRUPT_AFTER`), however slowly a loaded
        // machine runs it.
        let mut frame = None;
        for (k, &action) in actions.iter().enumerate() {
            here.apply(action);
            let seq = k as u64 + 1;
            worker.send(Command::Apply { seq, action });
            frame = Some(frame_after(&worker, seq));
        }
        let frame = frame.expect("actions were sent");
        assert_eq!(frame.world.steps, 6);
        assert_eq!(frame.world.state_hash(), here.world.state_hash());
        assert_eq!(frame.world.config, here.world.config);
        assert_eq!(
            frame.ghost.as_ref().map(|g| &g.positions),
            here.ghost.as_ref().map(|g| &g.positions)
        );
    }

    /// The collisions lesson with `particles` spheres (started overlapping),
    /// `broad_phase` and `substeps`.
    fn heavy_session(
        particles: usize,
        broad_phase: crate::sim::BroadPhase,
        substeps: u32,
    ) -> Session {
        let mut scene = Lesson::Collisions.scene();
        for s in &mut scene.spawns {
            s.overlap = true;
        }
        scene.set_particles(particles).unwrap();
        scene.world.broad_phase = broad_phase;
        scene.world.substeps = substeps;
        Session::new(scene, Some(Lesson::Collisions)).unwrap()
    }

    /// Two thousand spheres and ten thousand sub-steps: one step takes
    /// seconds.
    fn slow_session() -> Session {
        heavy_session(2000, crate::sim::BroadPhase::Grid, 10_000)
    }

    /// Change the gravity while a step runs: the step gives way, no step
    /// is taken, the bodies are as they were (`start`), the change acts.
    fn assert_gives_way(worker: &Worker, start: u64) {
        worker.send(Command::Apply {
            seq: 1,
            action: Action::GravityDown,
        });
        let frame = frame_after(worker, 1);
        assert_eq!(frame.pace.abandoned, 1, "the step in progress gave way");
        assert_eq!(frame.world.steps, 0, "no step was taken");
        assert_eq!(
            frame.world.state_hash(),
            start,
            "the bodies are as they were"
        );
        assert_eq!(frame.gravity(), 8.0, "the change took effect");
    }

    #[test]
    fn an_action_abandons_a_long_step_and_leaves_the_state_as_it_was() {
        let session = slow_session();
        let start = session.world.state_hash();
        let worker = Worker::spawn(session, false, 1.0, false);
        let first = frame_after(&worker, 0);
        assert_eq!(first.world.steps, 0);
        // Once the first step has begun, ask for a pause and a change.
        step_begun(&worker);
        worker.send(Command::Run {
            paused: true,
            time_scale: 1.0,
        });
        assert_gives_way(&worker, start);
    }

    #[test]
    fn an_action_abandons_a_long_step_of_one_sub_step_part_way() {
        // One sub-step, all of it the all-pairs narrow phase of 60,000
        // spheres (1.8e9 pair tests: seconds).
        let session = heavy_session(60_000, crate::sim::BroadPhase::AllPairs, 1);
        let start = session.world.state_hash();
        let worker = Worker::spawn(session, false, 1.0, false);
        frame_after(&worker, 0);
        step_begun(&worker);
        assert_gives_way(&worker, start);
    }

    #[test]
    fn a_step_forward_waits_for_the_one_in_progress_and_other_keys_stop_it() {
        // Steps of a few hundred sub-steps: far longer than
        // INTERRUPT_AFTER. Three presses of n while the first runs take
        // three steps; a change of gravity still stops a step forward.
        let session = heavy_session(2000, crate::sim::BroadPhase::Grid, 300);
        let worker = Worker::spawn(session, true, 1.0, false);
        frame_after(&worker, 0);
        let step = |seq| Command::Apply {
            seq,
            action: Action::StepForward,
        };
        worker.send(step(1));
        step_begun(&worker);
        worker.send(step(2));
        worker.send(step(3));
        let frame = frame_after(&worker, 3);
        assert_eq!(frame.world.steps, 3, "one step a press");
        assert_eq!(frame.pace.abandoned, 0, "no step gave way");
        let before = frame.world.state_hash();
        worker.send(step(4));
        step_begun(&worker);
        worker.send(Command::Apply {
            seq: 5,
            action: Action::GravityDown,
        });
        let frame = frame_after(&worker, 5);
        assert_eq!(frame.pace.abandoned, 1, "the step forward gave way");
        assert_eq!(frame.world.steps, 3);
        assert_eq!(frame.world.state_hash(), before);
        assert_eq!(frame.gravity(), 8.0);
    }

    #[test]
    fn what_only_chooses_what_frames_carry_waits_for_the_step() {
        // Trails on and the contact marks off while a step of seconds
        // runs: it finishes, and the step after it runs on too.
        let worker = Worker::spawn(slow_session(), false, 1.0, false);
        frame_after(&worker, 0);
        step_begun(&worker);
        worker.send(Command::Trails(true));
        worker.send(Command::Contacts(false));
        let patience = Instant::now() + Duration::from_secs(120);
        let frame = loop {
            if let Some(f) = worker.take_frame()
                && f.world.steps >= 1
            {
                break f;
            }
            assert!(Instant::now() < patience, "the step never finished");
            std::thread::sleep(Duration::from_millis(5));
        };
        assert_eq!(frame.pace.abandoned, 0, "no step gave way");
        assert_eq!(worker.shared.waiting.load(Ordering::Acquire), 0);
    }

    #[test]
    fn after_a_stop_the_pace_is_measured_afresh() {
        let worker = Worker::spawn(Session::lesson(Lesson::Pingpong), false, 1.0, false);
        let patience = Instant::now() + Duration::from_secs(60);
        while worker
            .take_frame()
            .is_none_or(|f| f.pace.achieved.is_none())
        {
            assert!(Instant::now() < patience, "no pace measured while running");
            std::thread::sleep(Duration::from_millis(20));
        }
        // What the event loop sends once the process runs again.
        worker.send(Command::Resumed);
        worker.send(Command::Apply {
            seq: 1,
            action: Action::ToggleGhost,
        });
        let frame = frame_after(&worker, 1);
        assert_eq!(frame.pace.achieved, None, "the window began again");
        assert!(!frame.pace.behind, "no steps were dropped for the stop");
    }

    #[test]
    fn a_new_world_owes_nothing_for_the_slow_one_before_it() {
        // Running a step far slower than real time: steps are owed and
        // dropped, and the pace is behind.
        let worker = Worker::spawn(slow_session(), false, 1.0, false);
        let patience = Instant::now() + Duration::from_secs(120);
        while worker.take_frame().is_none_or(|f| !f.pace.behind) {
            assert!(
                Instant::now() < patience,
                "the slow world never fell behind"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        worker.send(Command::Apply {
            seq: 1,
            action: Action::Lesson(Lesson::Pingpong),
        });
        let patience = Instant::now() + Duration::from_secs(60);
        let frame = loop {
            if let Some(f) = worker.take_frame()
                && f.applied >= 1
                && f.world.steps >= 1
            {
                break f;
            }
            assert!(Instant::now() < patience, "the new world never stepped");
            std::thread::sleep(Duration::from_millis(2));
        };
        assert!(
            !frame.pace.behind,
            "the ping-pong ball keeps up from its first step"
        );
    }

    #[test]
    fn a_change_while_running_shows_before_the_next_long_step_ends() {
        // Seconds-long steps, running: the frame after the change carries
        // it while the next step is still under way.
        let session = slow_session();
        let worker = Worker::spawn(session, false, 1.0, false);
        frame_after(&worker, 0);
        step_begun(&worker);
        worker.send(Command::Apply {
            seq: 1,
            action: Action::PairRestitutionDown,
        });
        let frame = frame_after(&worker, 1);
        assert_eq!(frame.world.config.pair_restitution, 0.9);
        assert_eq!(frame.world.steps, 0, "shown before any step finished");
    }
}
