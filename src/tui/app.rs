//! The visualiser's view state and its state machine: [`App::apply`] takes
//! an [`Action`], changes what belongs to the view (camera, overlays,
//! help, chart, pause and time scale asked for) and hands what changes the
//! simulation to the session. Nothing here reads a terminal or a clock, so
//! every transition is testable with plain values.
//!
//! The session is reached through a link: in the running program a worker
//! thread owns it (`worker.rs`) and the app draws the newest [`Frame`] the
//! worker published; in tests (and the drawing benchmark) the app owns
//! the session itself and every action takes effect before `apply`
//! returns. Either way the view draws only from `frame`.
//!
//! Actions are numbered; a frame says which it has carried out, so the
//! view knows when the world is still working on one, and a message is
//! shown only for the newest action (until the next).

use super::action::Action;
use super::camera::Camera;
use super::camera::Projection;
use super::frame::Frame;
use super::keymap::{Mode, key_of};
use super::palette::Colouring;
use super::selection::Selection;
use super::session::{Session, neighbour_lesson};
use super::work_chart::{Source, WorkCharts};
use super::worker::{Command, Worker};
use crate::scene::{Lesson, Scene, SceneError};
use crate::sim::{Bodies, Vec3};
use ratatui::layout::{Position, Rect, Size};
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Duration;

/// Time scales `<` and `>` move between: slow motion to fast.
pub const TIME_SCALES: &[f64] = &[1.0 / 16.0, 1.0 / 8.0, 0.25, 0.5, 1.0, 2.0, 4.0];

/// The terminal size assumed until the first draw.
pub(crate) const DEFAULT_SCREEN: Size = Size::new(80, 24);

/// Frame figures measured by the event loop. Left empty in tests, so
/// renders never show wall-clock values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Wall time to draw the last frame, ms.
    pub frame_ms: Option<f64>,
    /// Frames drawn per second.
    pub fps: Option<f64>,
    /// The world has been working on an action for a while.
    pub waiting: bool,
    /// How long the step (or action) in progress has run, s, once it is
    /// long enough to say.
    pub busy_for: Option<f64>,
    /// Input may wait for the end of an escape sequence (`input.rs`).
    pub keys_held: bool,
    /// The view draws fewer frames, to leave the cores to busy steps
    /// (`draw_rate.rs`).
    pub draw_held: bool,
}

/// Where the session is.
#[derive(Debug)]
enum Link {
    /// Owned here: actions take effect at once.
    Local(Box<Session>),
    /// On the worker thread.
    Worker(Worker),
}

#[derive(Debug)]
pub struct App {
    /// The newest state of the simulation: what the view draws.
    pub frame: Arc<Frame>,
    link: Link,
    /// The lesson asked for last (the frame follows once carried out);
    /// `None`: the scene opened from a file.
    pub lesson: Option<Lesson>,
    /// The spheres of the scene opened from a file, if one was, and
    /// whether it marks the contacts from the start.
    opened: Option<(usize, bool)>,
    /// Paused, as asked.
    pub paused: bool,
    /// Index into [`TIME_SCALES`].
    pub time_scale: usize,
    pub show_vectors: bool,
    pub show_trails: bool,
    /// Contacts marked and their normals drawn.
    pub show_contacts: bool,
    /// The sphere count `show_contacts` was last chosen for by
    /// [`contacts_by_default`], or `None` once `d` chose it in this
    /// lesson: while it is `Some`, a world grown or shrunk past the
    /// default's threshold (`+`, `-`) takes the default again, as a world
    /// opened with that many spheres would.
    contacts_default_for: Option<usize>,
    /// The side panel is shown.
    pub show_panel: bool,
    /// A grid drawn on the floor.
    pub show_floor_grid: bool,
    pub colouring: Colouring,
    /// False when NO_COLOR is set.
    pub colour: bool,
    pub camera: Camera,
    pub help_open: bool,
    pub help_scroll: u16,
    /// The terminal's size at the last draw (the help scrolls within it).
    pub screen: Size,
    /// The work-precision chart screen is open.
    pub chart_open: bool,
    /// Work-precision data per lesson, computed on demand.
    pub charts: WorkCharts,
    /// A one-line message shown until the next action (a move of the
    /// camera keeps it shown: `status_kept`).
    pub status: Option<String>,
    /// The message a move of the camera took the place of, still shown
    /// while nothing else is: turning and zooming to look at a collision
    /// keep its description.
    pub status_kept: Option<String>,
    pub should_quit: bool,
    pub timing: Timing,
    /// Actions taken so far (the number of the newest).
    actions: u64,
    /// Actions handed to the session so far (the number of the newest).
    sent: u64,
    /// The actions handed to the session and not yet known to be carried
    /// out, with their numbers, oldest first: the first is the one the
    /// world works on.
    pending: VecDeque<(u64, Action)>,
    /// The newest session message seen.
    seen_message: u64,
    /// The selection's box in the side panel as last drawn
    /// (`panel::render_panel`): kept from frame to frame while the same
    /// selection is drawn at the same size.
    pub(crate) selection_box: std::cell::Cell<Option<SelectionBox>>,
}

/// The rows the side panel last gave a selection, and whether the lesson's
/// equation gave its row to them: while the simulation runs, a selection's
/// rows change from frame to frame (a number wraps onto a second row, a
/// pair comes into contact), and the box keeps the most rows it has needed
/// for that selection at that size, so that the rows above it stay put.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SelectionBox {
    pub selection: crate::tui::selection::Selection,
    pub area: ratatui::layout::Rect,
    pub rows: usize,
    pub equation_given_up: bool,
}

/// How long the steps forward waiting on the world may take: a press
/// beyond them is not added ([`App::steps_forward_full`]), so that a held
/// `n` stops within about this time of being let go, however long a step
/// takes, while presses as fast as the steps are each taken.
const MAX_STEPS_WAITING: Duration = Duration::from_secs(1);

/// Zoomed in this many times or more, the view follows the selection
/// ([`App::projection`]).
const FOLLOW_FROM: f64 = 1.0;

impl App {
    /// An app showing `scene` (a lesson's when `lesson` is set), running,
    /// with the session owned here.
    pub fn new(scene: Scene, lesson: Option<Lesson>) -> Result<Self, SceneError> {
        Ok(Self::with_session(Session::new(scene, lesson)?))
    }

    /// An app showing `session`, running.
    pub(crate) fn with_session(mut session: Session) -> Self {
        let status = session.take_message();
        let frame = Arc::new(session.frame(false, None));
        let bodies = session.world.bodies.len();
        let marks = session.scene.marks_contacts();
        let show_contacts = contacts_by_default(marks, bodies);
        session.show_contacts(show_contacts);
        Self {
            opened: session.has_opened().then_some((bodies, marks)),
            show_contacts,
            contacts_default_for: Some(bodies),
            show_panel: true,
            lesson: session.lesson,
            frame,
            link: Link::Local(Box::new(session)),
            paused: false,
            time_scale: TIME_SCALES.iter().position(|&s| s == 1.0).unwrap_or(0),
            show_vectors: false,
            show_trails: false,
            show_floor_grid: false,
            colouring: Colouring::Speed,
            colour: true,
            camera: Camera::default(),
            help_open: false,
            help_scroll: 0,
            screen: DEFAULT_SCREEN,
            chart_open: false,
            charts: WorkCharts::new(crate::study::work_precision),
            status,
            status_kept: None,
            should_quit: false,
            timing: Timing::default(),
            actions: 0,
            sent: 0,
            pending: VecDeque::new(),
            seen_message: 0,
            selection_box: std::cell::Cell::new(None),
        }
    }

    /// A lesson at its start, running (the tests' starting point).
    pub fn lesson(lesson: Lesson) -> Self {
        Self::with_session(Session::lesson(lesson))
    }

    /// The same app with work-precision data from `source` instead of the
    /// study's sweep.
    pub fn with_chart_source(mut self, source: Source) -> Self {
        self.charts = WorkCharts::new(source);
        self
    }

    /// Move the session to a worker thread, which steps it in real time
    /// from now on.
    pub(crate) fn start_worker(mut self) -> Self {
        let (paused, scale, trails) = (self.paused, self.time_scale(), self.show_trails);
        if let Link::Local(session) = self.link {
            let worker = Worker::spawn(*session, paused, scale, trails);
            self.link = Link::Worker(worker);
        }
        self
    }

    /// The session, when owned here (tests and the drawing benchmark).
    pub fn session(&self) -> Option<&Session> {
        match &self.link {
            Link::Local(s) => Some(s),
            Link::Worker(_) => None,
        }
    }

    pub fn mode(&self) -> Mode {
        Mode {
            paused: self.paused,
            help_open: self.help_open,
            chart_open: self.chart_open,
            selected: self.frame.selection.is_some(),
            working: self.working_on_a_step(),
            pairs: self.frame.world.config.pair_collisions,
        }
    }

    pub fn time_scale(&self) -> f64 {
        TIME_SCALES[self.time_scale]
    }

    /// The world is still working on an action already taken.
    pub(crate) fn awaiting(&self) -> bool {
        self.frame.applied < self.sent
    }

    /// The action the world works on: the oldest it has not carried out
    /// (it takes them in turn).
    fn working_on(&self) -> Option<Action> {
        let applied = self.frame.applied;
        self.pending
            .iter()
            .find(|&&(seq, _)| seq > applied)
            .map(|&(_, action)| action)
    }

    /// Whether a further step forward would wait too long: the steps
    /// forward handed to the world and not yet known to be taken (at least
    /// two: one under way and one more) would take [`MAX_STEPS_WAITING`]
    /// or more at the pace of the last step (any time, before one is
    /// timed).
    fn steps_forward_full(&self) -> bool {
        let applied = self.frame.applied;
        let waiting = self
            .pending
            .iter()
            .filter(|&&(seq, action)| seq > applied && action == Action::StepForward)
            .count();
        let step = self.frame.pace.step_ms.map_or(Duration::MAX, |ms| {
            Duration::from_secs_f64(ms.max(0.0) * 1e-3)
        });
        waiting >= 2 && step.saturating_mul(waiting as u32) >= MAX_STEPS_WAITING
    }

    /// The world works on an action a newer key stops: a search for a
    /// collision or a step (building a world does not give way).
    pub(crate) fn working_on_a_step(&self) -> bool {
        matches!(
            self.working_on(),
            Some(Action::NextCollision | Action::StepForward)
        )
    }

    /// What the footer says while the world works on an action for a
    /// while (`Timing::waiting`): which, and how to stop it.
    pub(crate) fn working_note(&self) -> Option<String> {
        let action = self.working_on()?;
        let what = match action {
            // Its key's description is too long for the footer.
            Action::NextCollision => "the search for the next collision",
            _ => super::keymap::describe(action)?,
        };
        // Esc stops a step where it is the world's key; over the help or
        // the chart it closes them.
        let stop = key_of(Action::StopWork);
        let esc = match (self.working_on_a_step(), self.mode()) {
            (false, _) => String::new(),
            (true, m) if m.help_open || m.chart_open => String::new(),
            (true, m) if m.selected => format!("{stop} stops it and forgets the selection, "),
            (true, _) => format!("{stop} stops it, "),
        };
        Some(format!(
            "working on: {what}... ({esc}{} quits)",
            key_of(Action::Quit)
        ))
    }

    /// One physics step of an owned session, outside the action history
    /// (the drawing benchmark); a worker is asked for a step forward.
    pub fn step(&mut self) {
        match &mut self.link {
            Link::Local(session) => {
                session.step();
                session.refresh_ghost();
                session.refresh_grid_tests();
                self.republish();
            }
            Link::Worker(_) => self.apply(Action::StepForward),
        }
    }

    pub fn apply(&mut self, action: Action) {
        if action.moves_the_camera() {
            if let Some(said) = self.status.take() {
                self.status_kept = Some(said);
            }
        } else {
            self.status = None;
            self.status_kept = None;
        }
        self.actions += 1;
        // What covers the view declines what would change the hidden.
        let covered = if self.help_open && !action.acts_over_help() {
            Some(("help", "?"))
        } else if self.chart_open && !action.acts_over_chart() {
            Some(("chart", "c"))
        } else {
            None
        };
        if let Some((what, key)) = covered {
            self.status = Some(match super::keymap::describe(action) {
                Some(asked) => {
                    format!(
                        "not done while the {what} covers the view ({asked}): {key} or Esc closes it"
                    )
                }
                None => format!("the {what} covers the view: {key} or Esc closes it"),
            });
            return;
        }
        match action {
            Action::Quit => self.should_quit = true,
            // The event loop stops the program, or draws the screen
            // again; nothing changes here.
            Action::Suspend | Action::Redraw => {}
            Action::TogglePause => {
                self.paused = !self.paused;
                self.send_run();
            }
            Action::PauseToStep => {
                if !self.paused {
                    self.paused = true;
                    self.send_run();
                }
            }
            Action::StepForward if self.steps_forward_full() => {
                // A held key repeats faster than a slow world steps: the
                // steps it asked would go on long after it is let go.
                let each = match self.frame.pace.step_ms {
                    Some(ms) => format!(" (a step takes {})", super::panel::format_ms(ms)),
                    None => String::new(),
                };
                self.status = Some(format!(
                    "the steps forward asked take a second or more{each}: this one is not added (Esc stops them)"
                ));
            }
            Action::StepForward | Action::StepBack => {
                if !self.paused {
                    self.paused = true;
                    self.send_run();
                }
                self.send(action);
            }
            Action::Lesson(_)
            | Action::OpenedScene
            | Action::NextLesson
            | Action::PreviousLesson => {
                let shown = match action {
                    Action::Lesson(l) => Some(l),
                    Action::OpenedScene => None,
                    Action::NextLesson => neighbour_lesson(self.lesson, 1, self.opened.is_some()),
                    _ => neighbour_lesson(self.lesson, -1, self.opened.is_some()),
                };
                let opened = |l: Lesson| {
                    let scene = l.scene();
                    Some((scene.body_count(), scene.marks_contacts()))
                };
                let Some((bodies, marks)) = shown.map_or(self.opened, opened) else {
                    self.status = Some("no scene file was opened".into());
                    return;
                };
                self.lesson = shown;
                // What belongs to a lesson starts afresh; camera and
                // colours stay.
                self.show_trails = false;
                self.show_vectors = false;
                self.show_contacts = contacts_by_default(marks, bodies);
                self.contacts_default_for = Some(bodies);
                self.send_contacts();
                self.send(shown.map_or(Action::OpenedScene, Action::Lesson));
                self.send_trails();
                self.request_chart();
            }
            Action::Slower | Action::Faster => {
                let next = if action == Action::Slower {
                    self.time_scale.saturating_sub(1)
                } else {
                    (self.time_scale + 1).min(TIME_SCALES.len() - 1)
                };
                if next == self.time_scale {
                    self.status = Some(format!(
                        "x{} is already the {} time scale",
                        super::view::format_scale(self.time_scale()),
                        if action == Action::Slower {
                            "slowest"
                        } else {
                            "fastest"
                        }
                    ));
                }
                self.time_scale = next;
                self.send_run();
            }
            // The view's switches say what they did in the footer: a
            // narrow legend leaves out what does not fit.
            Action::ToggleVectors => {
                self.show_vectors = !self.show_vectors;
                self.status = Some(on_off(
                    "velocity vectors",
                    self.show_vectors,
                    Action::ToggleVectors,
                ));
            }
            Action::ToggleFloorGrid => {
                self.show_floor_grid = !self.show_floor_grid;
                self.status = Some(on_off(
                    "floor grid",
                    self.show_floor_grid,
                    Action::ToggleFloorGrid,
                ));
            }
            Action::ToggleTrails => {
                self.show_trails = !self.show_trails;
                self.send_trails();
                self.status = Some(on_off("trails", self.show_trails, Action::ToggleTrails));
            }
            Action::ToggleColouring => {
                self.colouring = self.colouring.other();
                let (now, other) = match self.colouring {
                    Colouring::Speed => ("speed", "depth"),
                    Colouring::Depth => ("depth", "speed"),
                };
                let m = key_of(Action::ToggleColouring);
                self.status = Some(format!("colour by {now} ({m}: by {other})"));
            }
            Action::ToggleChart => {
                self.chart_open = !self.chart_open;
                self.request_chart();
            }
            Action::CloseChart => self.chart_open = false,
            Action::Orbit { yaw, pitch } => self.camera.orbit(yaw, pitch),
            Action::Zoom(f) => self.camera.zoom_by(f),
            Action::View(preset) => self.camera.look(preset),
            Action::ResetView => self.camera = Camera::default(),
            Action::ToggleHelp => {
                self.help_open = !self.help_open;
                self.help_scroll = 0;
            }
            Action::CloseHelp => self.help_open = false,
            Action::ScrollHelp(d) => {
                self.help_scroll = self
                    .help_scroll
                    .saturating_add_signed(d)
                    .min(super::help::max_scroll(self, self.help_space()));
            }
            Action::ScrollHelpPage(pages) => {
                let page = super::help::page(self, self.help_space()).max(1);
                self.help_scroll = self
                    .help_scroll
                    .saturating_add_signed(pages.saturating_mul(page as i16))
                    .min(super::help::max_scroll(self, self.help_space()));
            }
            Action::ScrollHelpTo(end) => {
                self.help_scroll = if end {
                    super::help::max_scroll(self, self.help_space())
                } else {
                    0
                };
            }
            Action::WallRestitutionDown
            | Action::WallRestitutionUp
            | Action::PairRestitutionDown
            | Action::PairRestitutionUp
            | Action::GravityDown
            | Action::GravityUp
            | Action::NextIntegrator
            | Action::NextBroadPhase
            | Action::HalveDt
            | Action::DoubleDt
            | Action::MoreSpheres
            | Action::FewerSpheres
            | Action::Restart
            | Action::Reseed
            | Action::ToggleGhost
            | Action::ToggleResting
            | Action::ToggleSupport
            | Action::ToggleSleep
            | Action::Select(_)
            | Action::PickNext
            | Action::PickPrevious
            | Action::ClearSelection
            | Action::StopWork => self.send(action),
            Action::NextCollision => {
                if !self.paused {
                    self.paused = true;
                    self.send_run();
                }
                self.send(action);
            }
            Action::ToggleContacts => {
                self.show_contacts = !self.show_contacts;
                self.contacts_default_for = None;
                self.send_contacts();
                self.status = Some(on_off(
                    "contact marks",
                    self.show_contacts,
                    Action::ToggleContacts,
                ));
            }
            Action::TogglePanel => {
                self.show_panel = !self.show_panel;
                self.status = Some(on_off("side panel", self.show_panel, Action::TogglePanel));
            }
            Action::Pick { column, row } => self.pick(column, row),
        }
    }

    /// Select the sphere drawn under the terminal cell `(column, row)`:
    /// of those whose disc covers the cell's centre, the nearest to the
    /// viewer; else the one whose centre is nearest, within a few dots.
    fn pick(&mut self, column: u16, row: u16) {
        let screen = Rect::new(0, 0, self.screen.width, self.screen.height);
        let canvas = self.areas(screen).canvas();
        let Some(canvas) = canvas.filter(|c| c.contains(Position::new(column, row))) else {
            self.status = Some("click on a sphere in the box to select it".into());
            return;
        };
        let (w, h) = (
            usize::from(canvas.width) * 2,
            usize::from(canvas.height) * 4,
        );
        let projection = self.projection(w, h);
        let at = (
            f64::from(column - canvas.x) * 2.0 + 1.0,
            f64::from(row - canvas.y) * 4.0 + 2.0,
        );
        match pick_sphere(&self.frame.world.bodies, &projection, at) {
            Some(id) => self.send(Action::Select(Some(Selection::Sphere(id)))),
            None => self.status = Some("no sphere there: click on a sphere to select it".into()),
        }
    }

    /// The view's projection onto a `w x h` dot grid: the box centre in
    /// the middle, or, zoomed in with spheres selected, their middle (from
    /// [`FOLLOW_FROM`] times up, fully at twice that zoom), so that
    /// zooming in on a pick keeps it in view as it moves.
    pub(crate) fn projection(&self, w: usize, h: usize) -> Projection {
        let following = self.frame.selection.is_some() && self.camera.zoom > FOLLOW_FROM;
        let selected = if following {
            self.frame.selected_slots()
        } else {
            Vec::new()
        };
        self.projection_of(w, h, &selected)
    }

    /// [`App::projection`], for the selected spheres in `selected` (their
    /// slots, [`Frame::selected_slots`](super::frame::Frame::selected_slots),
    /// which the view has found already).
    pub(crate) fn projection_of(&self, w: usize, h: usize, selected: &[usize]) -> Projection {
        let centre = Vec3::splat(0.5);
        let follow = ((self.camera.zoom - FOLLOW_FROM) / FOLLOW_FROM).clamp(0.0, 1.0);
        let target = if follow > 0.0 && !selected.is_empty() {
            let position = &self.frame.world.bodies.position;
            let middle =
                selected.iter().map(|&k| position[k]).sum::<Vec3>() / selected.len() as f64;
            centre + (middle - centre) * follow
        } else {
            centre
        };
        self.camera.projection_at(w, h, target)
    }

    /// Hand `action` to the session.
    fn send(&mut self, action: Action) {
        let applied = self.frame.applied;
        self.pending.retain(|&(seq, _)| seq > applied);
        self.pending.push_back((self.actions, action));
        self.sent = self.actions;
        let seq = self.actions;
        match &mut self.link {
            Link::Local(session) => {
                session.apply(action);
                self.status = session.take_message();
                self.republish();
                self.follow_contact_default();
            }
            Link::Worker(w) => w.send(Command::Apply { seq, action }),
        }
    }

    /// A world that now has another number of spheres than the contact
    /// marks were chosen for takes their default for its size, unless `d`
    /// chose them; the status line says so when that turns them on or off.
    fn follow_contact_default(&mut self) {
        let bodies = self.frame.world.bodies.len();
        let Some(chosen_for) = self.contacts_default_for else {
            return;
        };
        // A frame from before the newest action (a lesson's world still
        // showing after another was asked for) says nothing of it.
        if chosen_for == bodies || self.frame.applied < self.sent {
            return;
        }
        self.contacts_default_for = Some(bodies);
        let wanted = contacts_by_default(self.frame.scene.marks_contacts(), bodies);
        if wanted == self.show_contacts {
            return;
        }
        self.show_contacts = wanted;
        self.send_contacts();
        let d = key_of(Action::ToggleContacts);
        let note = if wanted {
            format!("contact marks on ({d} hides them)")
        } else {
            format!(
                "contact marks off from {} spheres ({d} shows them)",
                crate::scene::thousands(crate::sim::large::SPATIAL_ORDER_MIN_BODIES as u64)
            )
        };
        self.status = Some(match self.status.take() {
            Some(s) => format!("{s}; {note}"),
            None => note,
        });
    }

    fn send_run(&mut self) {
        if let Link::Worker(w) = &self.link {
            w.send(Command::Run {
                paused: self.paused,
                time_scale: self.time_scale(),
            });
        }
    }

    /// The process ran again after a stop: the worker forgets the time it
    /// stood still, so the header does not call the pace behind.
    pub(crate) fn resumed(&mut self) {
        if let Link::Worker(w) = &self.link {
            w.send(Command::Resumed);
        }
    }

    /// Tell the session whether the view marks contacts, so that a large
    /// world lists them only while something reads them.
    fn send_contacts(&mut self) {
        match &mut self.link {
            Link::Local(session) => session.show_contacts(self.show_contacts),
            Link::Worker(w) => w.send(Command::Contacts(self.show_contacts)),
        }
    }

    fn send_trails(&mut self) {
        match &self.link {
            Link::Local(_) => self.republish(),
            Link::Worker(w) => w.send(Command::Trails(self.show_trails)),
        }
    }

    /// A fresh frame of an owned session.
    fn republish(&mut self) {
        if let Link::Local(session) = &self.link {
            let mut frame = session.frame(self.show_trails, None);
            frame.applied = self.sent;
            self.frame = Arc::new(frame);
        }
    }

    /// How long the worker's step (or action) in progress has run.
    pub(crate) fn step_running_for(&self) -> Option<std::time::Duration> {
        match &self.link {
            Link::Worker(w) => w.step_running_for(),
            Link::Local(_) => None,
        }
    }

    /// Take in the worker's newest frame and finished background work;
    /// true if the picture changed.
    pub fn poll_background(&mut self) -> bool {
        let mut changed = self.charts.poll();
        if let Link::Worker(w) = &self.link
            && let Some(frame) = w.take_frame()
        {
            self.take_message(&frame);
            self.frame = frame;
            self.follow_contact_default();
            changed = true;
        }
        changed
    }

    /// Show the frame's message if it is new and answers the newest action
    /// (or is the simulation's own). One that answers the newest action
    /// sent to the world shows too when only actions of the view followed
    /// it and none of them said anything: the collision `o` found is still
    /// the one on screen after `w` or a turn of the camera.
    fn take_message(&mut self, frame: &Frame) {
        if let Some(m) = &frame.message
            && m.id > self.seen_message
        {
            self.seen_message = m.id;
            let answers = |a: u64| a == self.actions || (a == self.sent && self.status.is_none());
            if m.after.is_none_or(answers) {
                self.status = Some(m.text.clone());
            }
        }
    }

    /// The terminal now has this size: keep the help's scroll within it.
    /// Asked before every frame; the help is laid out again only when the
    /// size changed (drawing it clamps the scroll too).
    pub(crate) fn set_screen(&mut self, screen: Size) {
        if screen == self.screen {
            return;
        }
        self.screen = screen;
        self.help_scroll = self
            .help_scroll
            .min(super::help::max_scroll(self, self.help_space()));
    }

    /// Start the chart's computation for the lesson shown, if open.
    fn request_chart(&mut self) {
        if let (true, Some(lesson)) = (self.chart_open, self.lesson) {
            self.charts.request(lesson);
        }
    }
}

/// What a view switch's footer says: `what` on or off, and the key that
/// turns it back.
fn on_off(what: &str, on: bool, toggle: Action) -> String {
    let key = key_of(toggle);
    if on {
        format!("{what} on ({key}: off)")
    } else {
        format!("{what} off ({key}: on)")
    }
}

/// Contacts are marked from the start where a scene asks for it
/// (`contacts = true` in its `[lesson]`: the collisions lesson's), in a
/// world of `bodies` spheres: in one of thousands (`--particles`) the few
/// hundred marks drawn say little, and listing the contacts slows the
/// steps (`Session::show_contacts`).
fn contacts_by_default(asked: bool, bodies: usize) -> bool {
    asked && !crate::sim::large::is_large(bodies)
}

/// Dots beyond a sphere's drawn disc that a click may still land to pick
/// it (small spheres are a dot or two across).
pub(crate) const PICK_SLACK_DOTS: f64 = 3.0;

/// The scene index of the sphere drawn at dot `at` by `projection`: of the
/// discs covering it, the nearest to the viewer; else the disc whose edge
/// is nearest, within [`PICK_SLACK_DOTS`].
pub(crate) fn pick_sphere(bodies: &Bodies, projection: &Projection, at: (f64, f64)) -> Option<u32> {
    let mut covering: Option<(f64, u32)> = None;
    let mut near: Option<(f64, u32)> = None;
    for k in 0..bodies.len() {
        let (x, y) = projection.to_screen(bodies.position[k]);
        let gap =
            ((x - at.0).powi(2) + (y - at.1).powi(2)).sqrt() - bodies.radius[k] * projection.scale;
        if !gap.is_finite() {
            continue;
        }
        let id = bodies.id[k];
        if gap <= 0.0 {
            let depth = projection.depth(bodies.position[k]);
            if covering.is_none_or(|(d, _)| depth > d) {
                covering = Some((depth, id));
            }
        } else if gap <= PICK_SLACK_DOTS && near.is_none_or(|(g, _)| gap < g) {
            near = Some((gap, id));
        }
    }
    covering.or(near).map(|(_, id)| id)
}

#[cfg(test)]
mod tests {
    use super::super::frame::Message;
    use super::super::view::{Areas, FOOTER_MAX_ROWS};
    use super::*;

    fn synthetic(lesson: Lesson) -> Result<Vec<crate::study::Row>, String> {
        Err(format!("synthetic {}", lesson.name()))
    }

    #[test]
    fn pause_and_step_forward() {
        let mut app = App::lesson(Lesson::Pingpong);
        assert!(!app.paused, "a lesson opens running");
        app.apply(Action::TogglePause);
        assert!(app.paused);
        app.apply(Action::StepForward);
        app.apply(Action::StepForward);
        assert_eq!(app.frame.world.steps, 2);
        assert!(app.paused, "stepping keeps the pause");
        let dt = app.frame.world.config.dt;
        assert!((app.frame.world.bodies.position[0].y - (0.5 + 2.0 * dt)).abs() < 1e-12);
    }

    #[test]
    fn time_scale_is_clamped() {
        let mut app = App::lesson(Lesson::Pingpong);
        for _ in 0..10 {
            app.apply(Action::Faster);
        }
        assert_eq!(app.time_scale(), 4.0);
        for _ in 0..10 {
            app.apply(Action::Slower);
        }
        assert_eq!(app.time_scale(), 1.0 / 16.0);
    }

    #[test]
    fn lesson_switch_loads_the_lesson_with_its_own_parameters() {
        let mut app = App::lesson(Lesson::Pingpong);
        app.apply(Action::WallRestitutionDown);
        app.apply(Action::Lesson(Lesson::Gravity));
        assert_eq!(app.lesson, Some(Lesson::Gravity));
        assert_eq!(app.frame.world.bodies.len(), 150);
        assert_eq!(app.frame.world.config.wall_restitution, 0.95);
        assert_eq!(app.frame.world.steps, 0);
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Pingpong));
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
    }

    #[test]
    fn a_scene_file_marks_the_contacts_from_the_start_when_its_lesson_asks() {
        let scene = |lesson: &str| {
            let text = format!(
                "{lesson}[world]\ngravity = [0.0, -9.81, 0.0]\n\
                 [[spawn]]\ncount = 20\nradius = [0.02, 0.03]\n"
            );
            crate::scene::file::parse_scene(&text, "pairs.toml", "pairs").unwrap()
        };
        let asked = App::new(scene("[lesson]\ncontacts = true\n"), None).unwrap();
        assert!(asked.show_contacts);
        for lesson in [
            "",
            "[lesson]\ntitle = \"Pairs\"\n",
            "[lesson]\ncontacts = false\n",
        ] {
            assert!(
                !App::new(scene(lesson), None).unwrap().show_contacts,
                "{lesson}"
            );
        }
        // Tab to a lesson and back: each takes its own default afresh.
        let mut app = asked;
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Pingpong));
        assert!(!app.show_contacts);
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, None);
        assert!(app.show_contacts);
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
        assert!(app.show_contacts);
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, Some(Lesson::Gravity));
        assert!(!app.show_contacts);
    }

    #[test]
    fn tab_comes_back_to_the_scene_file_opened_with_its_own_parameters() {
        // A scene file's world is one stop of Tab's cycle, before the
        // lessons; it was dropped at the first Tab, with no way back.
        let text = "[world]\ngravity = [0.0, 0.0, 0.0]\nwall_restitution = 0.5\n\
                    [[body]]\nposition = [0.3, 0.5, 0.5]\nradius = 0.1\nmass = 2.0\n\
                    velocity = [1.0, 0.0, 0.0]\n";
        let scene = crate::scene::file::parse_scene(text, "one.toml", "One ball").unwrap();
        let mut app = App::new(scene, None).unwrap();
        app.apply(Action::WallRestitutionDown);
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Pingpong));
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, None);
        let world = &app.frame.world;
        assert_eq!(world.bodies.len(), 1);
        assert_eq!(world.bodies.mass[0], 2.0);
        assert_eq!(world.config.wall_restitution, 0.5, "the file's, afresh");
        assert_eq!(world.steps, 0);
        for lesson in [Lesson::Collisions, Lesson::Gravity, Lesson::Pingpong] {
            app.apply(Action::PreviousLesson);
            assert_eq!(app.lesson, Some(lesson));
        }
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, None, "the cycle wraps to the scene file");
        assert_eq!(app.frame.world.bodies.mass[0], 2.0);
        // Started from a lesson, there is no scene file to come back to.
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::OpenedScene);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
        assert_eq!(app.status.as_deref(), Some("no scene file was opened"));
    }

    #[test]
    fn c_opens_and_closes_the_chart_and_computes_each_lesson_once() {
        use super::super::work_chart::ChartData;
        let mut app = App::lesson(Lesson::Gravity).with_chart_source(synthetic);
        app.apply(Action::ToggleChart);
        assert!(app.chart_open);
        assert_eq!(app.charts.started, 1);
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
        while !app.poll_background() {
            assert!(std::time::Instant::now() < deadline, "no result came back");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(matches!(
            app.charts.get(Lesson::Gravity),
            Some(ChartData::Failed(e)) if e == "synthetic gravity"
        ));
        app.apply(Action::CloseChart);
        assert!(!app.chart_open);
        app.apply(Action::ToggleChart);
        app.apply(Action::ToggleChart);
        app.apply(Action::ToggleChart);
        assert_eq!(app.charts.started, 1, "the result is kept");
        app.apply(Action::Lesson(Lesson::Pingpong));
        assert_eq!(app.charts.started, 2, "an open chart follows the lesson");
        while !matches!(
            app.charts.get(Lesson::Pingpong),
            Some(ChartData::Failed(e)) if e == "synthetic pingpong"
        ) {
            assert!(
                std::time::Instant::now() < deadline,
                "no pingpong result came back: {:?}",
                app.charts.get(Lesson::Pingpong)
            );
            app.poll_background();
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    }

    #[test]
    fn the_help_scrolls_no_further_than_its_end() {
        let mut app = App::lesson(Lesson::Pingpong);
        app.set_screen(Size::new(80, 24));
        let end = super::super::help::max_scroll(&app, app.help_space());
        assert!(end > 0, "the help does not fit in 80x24");
        app.apply(Action::ToggleHelp);
        for _ in 0..300 {
            app.apply(Action::ScrollHelp(1));
        }
        assert_eq!(app.help_scroll, end);
        app.apply(Action::ScrollHelp(-1));
        assert_eq!(app.help_scroll, end - 1, "one press up moves it");
        app.apply(Action::ScrollHelpTo(false));
        assert_eq!(app.help_scroll, 0, "Home goes to the top");
        let page = super::super::help::page(&app, app.help_space());
        assert!(
            page > 1 && page < end,
            "a page of {page} lines, the help {end} more"
        );
        app.apply(Action::ScrollHelpPage(1));
        assert_eq!(app.help_scroll, page, "one page down");
        app.apply(Action::ScrollHelpPage(10));
        assert_eq!(app.help_scroll, end, "no further than the end");
        app.apply(Action::ScrollHelpPage(-1));
        assert_eq!(app.help_scroll, end - page, "one page up");
        app.apply(Action::ScrollHelpTo(true));
        assert_eq!(app.help_scroll, end, "End goes to the end");
        app.set_screen(Size::new(240, 200));
        assert_eq!(app.help_scroll, 0, "it all fits on a big screen");
    }

    #[test]
    fn keys_behind_the_help_say_so_and_change_nothing_it_hides() {
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::TogglePause);
        app.apply(Action::ToggleHelp);
        let (steps, e) = (
            app.frame.world.steps,
            app.frame.world.config.pair_restitution,
        );
        for action in [
            Action::StepForward,
            Action::PairRestitutionDown,
            Action::Lesson(Lesson::Gravity),
            Action::TogglePause,
        ] {
            app.apply(action);
            let status = app.status.clone().unwrap_or_default();
            assert!(
                status.contains("? or Esc closes it"),
                "{action:?}: {status}"
            );
        }
        assert!(app.help_open && app.paused);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
        assert_eq!(app.frame.world.steps, steps);
        assert_eq!(app.frame.world.config.pair_restitution, e);
        // Closed, the same keys act.
        app.apply(Action::CloseHelp);
        app.apply(Action::PairRestitutionDown);
        assert!(app.frame.world.config.pair_restitution < e);
        // The ways out still work behind it.
        app.apply(Action::ToggleHelp);
        app.apply(Action::Quit);
        assert!(app.should_quit);
    }

    #[test]
    fn the_step_keys_of_a_running_world_pause_it_only_where_it_shows() {
        // n, . and , pause a running world so that they step it; over the
        // help or the chart they are declined, as the steps are, and the
        // world runs on.
        let mut app = App::lesson(Lesson::Collisions).with_chart_source(synthetic);
        app.set_screen(Size::new(110, 36));
        for (open, close, key) in [
            (Action::ToggleHelp, Action::CloseHelp, "?"),
            (Action::ToggleChart, Action::CloseChart, "c"),
        ] {
            app.apply(open);
            app.apply(Action::PauseToStep);
            let status = app.status.clone().unwrap_or_default();
            assert!(
                status.contains("(pause to step)") && status.contains(&format!("{key} or Esc")),
                "{status}"
            );
            assert!(!app.paused, "still running under {key}");
            app.apply(close);
        }
        app.apply(Action::PauseToStep);
        assert!(app.paused && app.status.is_none());
        // Already paused, it leaves the world paused.
        app.apply(Action::PauseToStep);
        assert!(app.paused);
    }

    #[test]
    fn keys_behind_the_chart_say_so_and_change_nothing_it_hides() {
        let mut app = App::lesson(Lesson::Collisions).with_chart_source(synthetic);
        app.set_screen(Size::new(110, 36));
        app.apply(Action::TogglePause);
        app.apply(Action::ToggleChart);
        let (steps, e, ghost) = (
            app.frame.world.steps,
            app.frame.world.config.pair_restitution,
            app.frame.show_ghost,
        );
        let (vectors, contacts, panel) = (app.show_vectors, app.show_contacts, app.show_panel);
        for action in [
            Action::StepForward,
            Action::NextCollision,
            Action::PairRestitutionDown,
            Action::ToggleGhost,
            Action::ToggleContacts,
            Action::ToggleVectors,
            Action::TogglePanel,
            Action::Pick {
                column: 30,
                row: 15,
            },
        ] {
            app.apply(action);
            let status = app.status.clone().unwrap_or_default();
            assert!(
                status.contains("chart covers the view") && status.contains("c or Esc closes it"),
                "{action:?}: {status}"
            );
        }
        assert!(app.chart_open && app.paused);
        assert_eq!(app.frame.world.steps, steps);
        assert_eq!(app.frame.world.config.pair_restitution, e);
        assert_eq!(app.frame.show_ghost, ghost);
        assert_eq!(
            (app.show_vectors, app.show_contacts, app.show_panel),
            (vectors, contacts, panel)
        );
        assert!(app.frame.selection.is_none());
        // The footer offers only what acts.
        let offered: Vec<String> = super::super::keymap::footer(app.mode())
            .into_iter()
            .map(|(keys, _)| keys)
            .collect();
        assert!(offered.contains(&"c".to_string()), "{offered:?}");
        assert!(!offered.contains(&"x".to_string()), "{offered:?}");
        assert!(!offered.contains(&"n".to_string()), "{offered:?}");
        // Pausing and the lessons act: the chart follows the lesson.
        app.apply(Action::TogglePause);
        assert!(!app.paused && app.status.is_none());
        app.apply(Action::Lesson(Lesson::Gravity));
        assert_eq!(app.lesson, Some(Lesson::Gravity));
        assert!(app.chart_open);
        // Closed, the same keys act.
        app.apply(Action::CloseChart);
        app.apply(Action::ToggleContacts);
        assert!(
            app.status
                .clone()
                .unwrap_or_default()
                .contains("contact marks")
        );
    }

    #[test]
    fn a_long_message_grows_the_footer_and_clicks_follow_the_smaller_canvas() {
        let mut app = App::lesson(Lesson::Pingpong);
        app.set_screen(Size::new(80, 24));
        let screen = Rect::new(0, 0, 80, 24);
        assert_eq!(app.footer_rows(80), 1);
        app.status = Some("x".repeat(78));
        assert_eq!(app.footer_rows(80), 1, "78 columns fit between the margins");
        app.status = Some(" ".repeat(200));
        assert_eq!(app.footer_rows(80), 1, "spaces only");
        app.status = Some("word ".repeat(20));
        assert_eq!(app.footer_rows(80), 2);
        app.status = Some("word ".repeat(200));
        assert_eq!(app.footer_rows(80), FOOTER_MAX_ROWS);
        let one = Areas::of(screen, true).canvas().unwrap();
        let grown = app.areas(screen).canvas().unwrap();
        assert_eq!(grown.height + 2, one.height, "two more footer rows");
        // A click on the row the grown footer took from the canvas is
        // outside the box.
        app.apply(Action::Pick {
            column: one.x + one.width / 2,
            row: one.y + one.height - 1,
        });
        assert!(app.status.as_deref().unwrap().contains("click on a sphere"));
    }

    #[test]
    fn zoomed_in_the_view_follows_the_selection() {
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::NextCollision);
        let picked = app.frame.selection.expect("o picks a pair");
        // Turning and zooming to look at it keep the footer's word on it.
        let said = app.status.clone().expect("o says which collision");
        assert!(said.contains("collide"), "{said}");
        let footer = |app: &App| app.footer_status().map(|s| s.into_owned());
        for look in [
            Action::Zoom(1.5),
            Action::Orbit {
                yaw: 0.1,
                pitch: 0.0,
            },
            Action::View(crate::tui::camera::Preset::Front),
            Action::ResetView,
        ] {
            app.apply(look);
            assert_eq!(footer(&app).as_ref(), Some(&said), "{look:?}");
        }
        app.apply(Action::ToggleVectors);
        assert_ne!(
            footer(&app).as_ref(),
            Some(&said),
            "another key has its say"
        );
        let middle = |app: &App| -> Vec3 {
            let b = &app.frame.world.bodies;
            let at: Vec<Vec3> = picked
                .ids()
                .iter()
                .map(|&id| b.position[b.id.iter().position(|&k| k == id).unwrap()])
                .collect();
            (at[0] + at[1]) / 2.0
        };
        assert_eq!(app.projection(200, 100).target, Vec3::splat(0.5));
        // Zoomed in 1.5 times, half way; twice, the pair is in the middle.
        app.apply(Action::Zoom(1.5));
        let half = Vec3::splat(0.5) + (middle(&app) - Vec3::splat(0.5)) * 0.5;
        assert!(app.projection(200, 100).target.abs_diff_eq(half, 1e-12));
        app.apply(Action::Zoom(2.0 / 1.5));
        let (x, y) = app.projection(200, 100).to_screen(middle(&app));
        assert!(
            (x - 100.0).abs() < 1e-9 && (y - 50.0).abs() < 1e-9,
            "{x}, {y}"
        );
        // It follows the pair as the world steps.
        app.apply(Action::StepForward);
        let (x, y) = app.projection(200, 100).to_screen(middle(&app));
        assert!(
            (x - 100.0).abs() < 1e-9 && (y - 50.0).abs() < 1e-9,
            "{x}, {y}"
        );
        app.apply(Action::ClearSelection);
        assert_eq!(app.projection(200, 100).target, Vec3::splat(0.5));
    }

    #[test]
    fn a_click_selects_the_sphere_drawn_there_and_esc_forgets_it() {
        let mut app = App::lesson(Lesson::Pingpong);
        app.set_screen(Size::new(120, 40));
        let canvas = Areas::of(Rect::new(0, 0, 120, 40), true).canvas().unwrap();
        let projection = app.camera.projection(
            usize::from(canvas.width) * 2,
            usize::from(canvas.height) * 4,
        );
        let (x, y) = projection.to_screen(app.frame.world.bodies.position[0]);
        let (column, row) = (canvas.x + (x / 2.0) as u16, canvas.y + (y / 4.0) as u16);
        app.apply(Action::Pick { column, row });
        assert_eq!(app.frame.selection, Some(Selection::Sphere(0)));
        assert!(app.mode().selected);
        let readout = &app.frame.inspection.as_ref().unwrap().spheres[0];
        assert_eq!(readout.mass, app.frame.world.bodies.mass[0]);
        app.apply(Action::StepForward);
        app.apply(Action::StepBack);
        assert_eq!(app.frame.selection, Some(Selection::Sphere(0)), "kept");
        app.apply(Action::ClearSelection);
        assert_eq!(app.frame.selection, None);

        app.apply(Action::Pick {
            column: 119,
            row: 39,
        });
        assert!(app.status.as_deref().unwrap().contains("click on a sphere"));
        app.apply(Action::Pick {
            column: canvas.x,
            row: canvas.y,
        });
        assert!(app.status.as_deref().unwrap().contains("no sphere there"));
        app.apply(Action::ToggleHelp);
        app.apply(Action::Pick { column, row });
        assert!(
            app.status
                .as_deref()
                .unwrap()
                .contains("? or Esc closes it")
        );
        assert_eq!(app.frame.selection, None);
    }

    #[test]
    fn o_pauses_on_the_next_collision_and_selects_it() {
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::NextCollision);
        assert!(app.paused);
        let Some(Selection::Pair(a, b)) = app.frame.selection else {
            panic!("a pair is selected: {:?}", app.status)
        };
        assert!(a < b);
        let ids: Vec<(u32, u32)> = app
            .frame
            .world
            .contacts()
            .iter()
            .map(|c| {
                let id = &app.frame.world.bodies.id;
                (id[c.i as usize], id[c.j as usize])
            })
            .collect();
        assert!(ids.contains(&(a, b)), "the pair is in contact at this step");
        let readout = app.frame.inspection.as_ref().unwrap().pair.clone();
        assert!(
            readout.is_some_and(|p| p.v_after.is_some()),
            "o stops on a pair that took an impulse"
        );
        assert!(app.status.as_deref().unwrap().contains("collide"));
        // The readouts describe the step as it ran: new parameters change
        // the steps to come, not the numbers of this one.
        let seen = app.frame.inspection.clone();
        for change in [
            Action::PairRestitutionDown,
            Action::GravityUp,
            Action::HalveDt,
            Action::NextIntegrator,
        ] {
            app.apply(change);
            assert_eq!(app.frame.inspection, seen, "after {change:?}");
        }
        assert_ne!(app.frame.world.config, seen.unwrap().config);

        // The continuous method: its impacts are the step's contacts.
        let mut app = App::lesson(Lesson::Collisions);
        while app.frame.world.config.integrator != crate::sim::Integrator::Continuous {
            app.apply(Action::NextIntegrator);
        }
        app.apply(Action::NextCollision);
        let Some(Selection::Pair(a, b)) = app.frame.selection else {
            panic!("a pair is selected: {:?}", app.status)
        };
        let id = &app.frame.world.bodies.id;
        let first = app.frame.world.contacts()[0];
        assert_eq!((id[first.i as usize], id[first.j as usize]), (a, b));
        let note = app.frame.inspection.as_ref().unwrap().pair_note.clone();
        assert!(note.unwrap().contains("continuous method"));

        // Ping-pong: the next collision is the ball's wall impact.
        let mut app = App::lesson(Lesson::Pingpong);
        app.apply(Action::NextCollision);
        assert_eq!(app.frame.selection, Some(Selection::Sphere(0)));
        assert!(app.status.as_deref().unwrap().contains("meets the"));
        // Without gravity and at rest, no collision comes: said, not hung.
        let mut scene = Lesson::Pingpong.scene();
        scene.bodies[0].velocity = crate::sim::Vec3::ZERO;
        let mut app = App::new(scene, Some(Lesson::Pingpong)).unwrap();
        app.apply(Action::NextCollision);
        assert!(app.status.as_deref().unwrap().contains("no collision"));
        // The collisions lesson with one sphere left: its walls'.
        let mut app = App::lesson(Lesson::Collisions);
        while app.frame.world.bodies.len() > 1 {
            app.apply(Action::FewerSpheres);
        }
        app.apply(Action::NextCollision);
        assert_eq!(app.frame.selection, Some(Selection::Sphere(0)));
        assert!(app.status.as_deref().unwrap().contains("meets the"));
    }

    #[test]
    fn a_lesson_switch_resets_what_belongs_to_the_lesson() {
        let mut app = App::lesson(Lesson::Collisions);
        assert!(app.show_contacts, "on by default in the collisions lesson");
        app.apply(Action::ToggleTrails);
        app.apply(Action::ToggleVectors);
        app.apply(Action::NextCollision);
        app.apply(Action::Zoom(2.0));
        app.apply(Action::Lesson(Lesson::Gravity));
        assert!(!app.show_trails && !app.show_vectors && !app.show_contacts);
        assert_eq!(app.frame.selection, None);
        assert_eq!(app.camera.zoom, 2.0, "the camera stays");
    }

    fn drawn(app: &App) -> String {
        let mut terminal =
            ratatui::Terminal::new(ratatui::backend::TestBackend::new(160, 40)).unwrap();
        terminal.draw(|f| f.render_widget(app, f.area())).unwrap();
        terminal.backend().to_string()
    }

    #[test]
    fn a_held_step_key_adds_at_most_a_seconds_steps_to_the_worker() {
        // The worker's frames say which actions it has taken; until one
        // comes in, every step forward asked still waits. Before a step is
        // timed the third is not added, and says so; once the world has
        // taken them, the key steps again, and at 300 ms a step four wait.
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::TogglePause);
        let mut app = app.start_worker();
        // Before a step is timed: one under way and one more.
        for _ in 0..2 {
            app.apply(Action::StepForward);
            assert_eq!(app.status, None);
        }
        let sent = app.sent;
        app.apply(Action::StepForward);
        assert_eq!(app.sent, sent, "the third press is not handed on");
        assert_eq!(
            app.status.as_deref(),
            Some(
                "the steps forward asked take a second or more: this one is not added (Esc stops them)"
            )
        );
        let give_up = std::time::Instant::now() + std::time::Duration::from_secs(60);
        while app.frame.applied < sent {
            assert!(
                std::time::Instant::now() < give_up,
                "the worker took its steps"
            );
            app.poll_background();
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        assert_eq!(app.frame.world.steps, 2);
        // Steps of 300 ms: four wait, as 1.2 s.
        let mut frame = (*app.frame).clone();
        frame.pace.step_ms = Some(300.0);
        app.frame = Arc::new(frame);
        for _ in 0..4 {
            app.apply(Action::StepForward);
            assert_eq!(app.status, None);
        }
        let sent = app.sent;
        app.apply(Action::StepForward);
        assert_eq!(app.sent, sent, "the fifth press is not handed on");
        assert!(
            app.status
                .as_deref()
                .unwrap()
                .contains("(a step takes 300 ms)"),
            "{:?}",
            app.status
        );
    }

    #[test]
    fn a_late_answer_shows_after_actions_of_the_view_but_not_after_the_world_moved_on() {
        // As from the worker: the answer to the newest action sent to the
        // world comes in a later frame, after other keys.
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::NextCollision);
        let asked = app.sent;
        let answer = |app: &App, after: u64| {
            let mut frame = (*app.frame).clone();
            frame.message = Some(Message {
                id: app.seen_message + 1,
                after: Some(after),
                text: "the answer".into(),
            });
            frame
        };
        // A turn of the camera says nothing of its own (what the footer
        // said stays shown until something else is): the answer shows.
        app.apply(Action::Orbit {
            yaw: 0.1,
            pitch: 0.0,
        });
        assert_eq!(app.status, None);
        app.take_message(&answer(&app, asked));
        assert_eq!(app.status.as_deref(), Some("the answer"));
        // A key of the view that says something of its own keeps its say.
        app.apply(Action::NextCollision);
        let asked = app.sent;
        app.apply(Action::Pick { column: 0, row: 0 });
        let own = app.status.clone();
        assert!(own.is_some(), "a click beside the box says so");
        app.take_message(&answer(&app, asked));
        assert_eq!(app.status, own);
        // After another action sent to the world, the old answer is stale.
        app.apply(Action::NextCollision);
        app.apply(Action::StepForward);
        let stale = app.sent - 1;
        app.apply(Action::Orbit {
            yaw: 0.1,
            pitch: 0.0,
        });
        app.take_message(&answer(&app, stale));
        assert_eq!(app.status, None);
    }

    #[test]
    fn growing_past_thousands_of_spheres_turns_the_marks_off_unless_d_chose() {
        // `+` takes the marks' default for the new size, as opening a world
        // that large would, and says so; `-` back takes it again. Once `d`
        // has chosen, sizes keep the choice.
        let grow_past = |app: &mut App, more: bool| {
            let large = |app: &App| crate::sim::large::is_large(app.frame.world.bodies.len());
            for _ in 0..20 {
                if large(app) == more {
                    return;
                }
                app.apply(if more {
                    Action::MoreSpheres
                } else {
                    Action::FewerSpheres
                });
            }
            panic!("{} spheres after 20 presses", app.frame.world.bodies.len());
        };
        let mut app = App::lesson(Lesson::Collisions);
        assert!(app.show_contacts);
        app.apply(Action::MoreSpheres);
        assert!(
            app.show_contacts,
            "{} spheres",
            app.frame.world.bodies.len()
        );
        grow_past(&mut app, true);
        assert!(!app.show_contacts);
        let status = app.status.clone().unwrap_or_default();
        assert!(
            status.contains("contact marks off from 4,096 spheres"),
            "{status}"
        );
        grow_past(&mut app, false);
        assert!(app.show_contacts);
        assert!(app.status.as_deref().unwrap().contains("contact marks on"));
        // Chosen with `d`: kept at any size.
        app.apply(Action::ToggleContacts);
        app.apply(Action::ToggleContacts);
        grow_past(&mut app, true);
        assert!(app.show_contacts);
        // A new lesson chooses afresh.
        app.apply(Action::Lesson(Lesson::Collisions));
        assert!(app.show_contacts);
        grow_past(&mut app, true);
        assert!(!app.show_contacts);
    }

    #[test]
    fn a_large_world_opens_without_contact_marks_and_says_when_none_are_listed() {
        // Opened with thousands of spheres, the collisions lesson marks no
        // contacts (and so lists none); marked while paused, the step shown
        // has no list, and the legend says so until the next step.
        let text = "[lesson]\ncontacts = true\n\n\
                    [world]\ngravity = [0.0, -9.81, 0.0]\npair_collisions = true\n\
                    broad_phase = \"grid\"\n\n[[spawn]]\ncount = 5000\nradius = [0.012, 0.016]\n";
        let big = crate::scene::file::parse_scene(text, "big.toml", "big").unwrap();
        let mut app = App::new(big, Some(Lesson::Collisions)).unwrap();
        assert!(!app.show_contacts);
        assert!(App::lesson(Lesson::Collisions).show_contacts);
        for _ in 0..5 {
            app.apply(Action::StepForward);
        }
        assert!(app.frame.world.last.contacts > 0);
        app.apply(Action::ToggleContacts);
        let screen = drawn(&app);
        assert!(
            screen.contains("contacts (none listed for this step)"),
            "{screen}"
        );
        app.apply(Action::StepForward);
        let screen = drawn(&app);
        assert!(!screen.contains("none listed"), "{screen}");
        assert_eq!(
            app.frame.world.contacts().len(),
            app.frame.world.last.contacts
        );
    }
}
