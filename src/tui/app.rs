//! The visualiser's state and its state machine: [`App::apply`] takes an
//! [`Action`] and changes the state; nothing here reads a terminal or a
//! clock, so every transition is testable with plain values.
//!
//! Owns the scene being shown, its world, the step-back history, the
//! energy log, the live parameters, the view settings, the ghost of the
//! exact reference (`ghost`) and the work-precision data per lesson
//! (`work_chart`, whose background threads are the only thing here that
//! runs apart from the caller; their results come in through
//! [`App::poll_background`]). Parameters are written to both the world's
//! config (so they act on the next step) and the scene (so a restart keeps
//! them); choosing a lesson loads it with its own parameters.

use super::action::Action;
use super::camera::Camera;
use super::energy_chart::EnergyLog;
use super::ghost::Ghost;
use super::history::History;
use super::keymap::Mode;
use super::palette::Colouring;
use super::work_chart::{Source, WorkCharts};
use crate::scene::{Lesson, Scene, SceneError, rules};
use crate::sim::{BroadPhase, Integrator, Vec3, WallMode, World, WorldConfig};
use ratatui::layout::Size;

/// Restitution changes by this much per key press.
pub const RESTITUTION_STEP: f64 = 0.05;
/// Gravity magnitudes the `g`/`G` keys move between, m/s^2, with a name
/// where the value is a body's surface gravity.
pub const GRAVITY_LADDER: &[(f64, &str)] = &[
    (0.0, "none"),
    (1.0, ""),
    (1.62, "Moon"),
    (3.71, "Mars"),
    (5.0, ""),
    (8.0, ""),
    (9.81, "Earth"),
    (12.0, ""),
    (15.0, ""),
    (20.0, ""),
];
pub const GRAVITY_MAX: f64 = 20.0;
/// `dt` stays within these bounds, s: the largest keeps a sphere falling
/// from the ceiling (about 4.5 m/s at the floor) under 15 cm a step; the
/// smallest keeps a frame's worth of steps affordable.
pub const DT_MIN: f64 = 1.0 / 7680.0;
pub const DT_MAX: f64 = 1.0 / 30.0;
/// Time scales `<` and `>` move between: slow motion to fast.
pub const TIME_SCALES: &[f64] = &[1.0 / 16.0, 1.0 / 8.0, 0.25, 0.5, 1.0, 2.0, 4.0];
/// Most spheres `+` adds: drawing stays interactive up to here.
pub const MAX_SPHERES: usize = 100_000;
/// Most spheres when every pair is tested each step (n^2 / 2 tests).
pub const MAX_SPHERES_ALL_PAIRS: usize = 5_000;

/// The terminal size assumed until the first draw.
pub const DEFAULT_SCREEN: Size = Size::new(80, 24);

/// Frame figures measured by the event loop. Left empty in tests, so
/// renders never show wall-clock values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// Wall time of the last physics step, ms.
    pub step_ms: Option<f64>,
    /// Wall time to draw the last frame, ms.
    pub frame_ms: Option<f64>,
    /// Frames drawn per second.
    pub fps: Option<f64>,
}

#[derive(Debug)]
pub struct App {
    /// The recipe of the world shown, with the live parameters.
    pub scene: Scene,
    /// The lesson shown, or `None` for a scene file.
    pub lesson: Option<Lesson>,
    pub world: World,
    pub history: History,
    pub energy: EnergyLog,
    pub paused: bool,
    /// Index into [`TIME_SCALES`].
    pub time_scale: usize,
    pub show_vectors: bool,
    pub show_trails: bool,
    pub colouring: Colouring,
    /// False when NO_COLOR is set.
    pub colour: bool,
    pub camera: Camera,
    pub help_open: bool,
    pub help_scroll: u16,
    /// The terminal's size at the last draw (the help scrolls within it).
    pub screen: Size,
    /// The exact reference is drawn as a ghost.
    pub show_ghost: bool,
    /// The ghost's anchor and positions while `show_ghost` (see `ghost`).
    pub ghost: Option<Ghost>,
    /// The work-precision chart screen is open.
    pub chart_open: bool,
    /// Work-precision data per lesson, computed on demand.
    pub charts: WorkCharts,
    /// A one-line message shown until the next action.
    pub status: Option<String>,
    pub should_quit: bool,
    /// The speed drawn in the hottest colour, m/s.
    pub speed_scale: f64,
    pub timing: Timing,
    /// The grid's pair tests over the present spheres, for the panel's
    /// comparison of broad phases (see [`App::refresh_grid_tests`]).
    grid_tests: Option<(GridTestsKey, u64)>,
}

/// What a grid pair-test count was made for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GridTestsKey {
    steps: u64,
    bodies: usize,
    broad_phase: BroadPhase,
    integrator: Integrator,
}

impl GridTestsKey {
    fn of(world: &World) -> Self {
        Self {
            steps: world.steps,
            bodies: world.bodies.len(),
            broad_phase: world.config.broad_phase,
            integrator: world.config.integrator,
        }
    }
}

impl App {
    /// An app showing `scene` (a lesson's when `lesson` is set), running.
    pub fn new(scene: Scene, lesson: Option<Lesson>) -> Result<Self, SceneError> {
        let world = scene.build()?;
        let mut app = Self {
            history: History::new(&world),
            energy: EnergyLog::new(&world),
            speed_scale: speed_scale(&world),
            scene,
            lesson,
            world,
            paused: false,
            time_scale: TIME_SCALES.iter().position(|&s| s == 1.0).unwrap_or(0),
            show_vectors: false,
            show_trails: false,
            colouring: Colouring::Speed,
            colour: true,
            camera: Camera::default(),
            help_open: false,
            help_scroll: 0,
            screen: DEFAULT_SCREEN,
            show_ghost: false,
            ghost: None,
            chart_open: false,
            charts: WorkCharts::new(crate::study::work_precision),
            status: None,
            should_quit: false,
            timing: Timing::default(),
            grid_tests: None,
        };
        app.note_capacity();
        app.refresh_grid_tests();
        Ok(app)
    }

    /// A lesson, paused at its start (the tests' starting point).
    pub fn lesson(lesson: Lesson) -> Self {
        Self::new(lesson.scene(), Some(lesson)).expect("the built-in lessons build (tested)")
    }

    /// The same app with work-precision data from `source` instead of the
    /// study's sweep.
    pub fn with_chart_source(mut self, source: Source) -> Self {
        self.charts = WorkCharts::new(source);
        self
    }

    pub fn mode(&self) -> Mode {
        Mode {
            paused: self.paused,
            help_open: self.help_open,
            chart_open: self.chart_open,
        }
    }

    pub fn time_scale(&self) -> f64 {
        TIME_SCALES[self.time_scale]
    }

    /// The wall restitution in effect: `flip` walls keep the speed.
    pub fn wall_restitution(&self) -> f64 {
        self.world.config.wall_coefficient()
    }

    /// Gravity's magnitude, m/s^2.
    pub fn gravity(&self) -> f64 {
        self.world.config.gravity.length()
    }

    /// One physics step, remembered for stepping back.
    pub fn step(&mut self) {
        self.world.step();
        self.history.record(&self.world);
        self.energy.record(&self.world);
    }

    pub fn apply(&mut self, action: Action) {
        self.status = None;
        match action {
            Action::Quit => self.should_quit = true,
            Action::TogglePause => self.paused = !self.paused,
            Action::StepForward => {
                self.paused = true;
                self.step();
            }
            Action::StepBack => {
                self.paused = true;
                if self.history.step_back(&mut self.world) {
                    self.energy.truncate_after(self.world.steps);
                    if self
                        .ghost
                        .as_ref()
                        .is_some_and(|g| g.is_before_anchor(&self.world))
                    {
                        self.ghost = None;
                        self.status = Some("the ghost starts again from this earlier step".into());
                    }
                } else {
                    self.status = Some(format!(
                        "no earlier step kept: the history holds the last {} steps",
                        self.history.capacity() - 1
                    ));
                }
            }
            Action::Lesson(lesson) => self.open_lesson(lesson),
            Action::NextLesson => self.open_lesson(self.neighbour_lesson(1)),
            Action::PreviousLesson => self.open_lesson(self.neighbour_lesson(-1)),
            Action::WallRestitutionDown => self.nudge_wall_restitution(-RESTITUTION_STEP),
            Action::WallRestitutionUp => self.nudge_wall_restitution(RESTITUTION_STEP),
            Action::PairRestitutionDown => self.nudge_pair_restitution(-RESTITUTION_STEP),
            Action::PairRestitutionUp => self.nudge_pair_restitution(RESTITUTION_STEP),
            Action::GravityDown => self.move_gravity(false),
            Action::GravityUp => self.move_gravity(true),
            Action::NextIntegrator => {
                let next = self.world.config.integrator.next();
                self.configure(|c| c.integrator = next);
            }
            Action::NextBroadPhase => self.next_broad_phase(),
            Action::HalveDt => self.scale_dt(0.5),
            Action::DoubleDt => self.scale_dt(2.0),
            Action::MoreSpheres => self.resize(true),
            Action::FewerSpheres => self.resize(false),
            Action::Slower => self.time_scale = self.time_scale.saturating_sub(1),
            Action::Faster => self.time_scale = (self.time_scale + 1).min(TIME_SCALES.len() - 1),
            Action::Restart => self.rebuild(),
            Action::Reseed => self.reseed(),
            Action::ToggleVectors => self.show_vectors = !self.show_vectors,
            Action::ToggleTrails => self.show_trails = !self.show_trails,
            Action::ToggleColouring => self.colouring = self.colouring.other(),
            Action::ToggleGhost => {
                self.show_ghost = !self.show_ghost;
                self.ghost = None;
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
                    .min(super::help::max_scroll(self.screen));
            }
        }
        self.refresh_ghost();
        self.refresh_grid_tests();
    }

    /// Whether the panel compares with the grid's pair tests counted
    /// afresh: always but when the grid ran the last step itself (and the
    /// step's own count stands).
    pub fn needs_grid_tests(&self) -> bool {
        let c = &self.world.config;
        let running = c.broad_phase.resolve(self.world.bodies.len());
        let measured = self.world.steps > 0 && self.world.last.broad_phase == Some(running);
        c.pair_collisions
            && (c.integrator == Integrator::Continuous || running != BroadPhase::Grid || !measured)
    }

    /// Count the grid's pair tests over the present spheres if the panel
    /// needs them and they were not counted for this step yet: at most
    /// once a step, never while drawing. `apply` calls it; the event loop
    /// calls it before drawing.
    pub fn refresh_grid_tests(&mut self) {
        let key = GridTestsKey::of(&self.world);
        if !self.needs_grid_tests() || self.grid_tests.is_some_and(|(k, _)| k == key) {
            return;
        }
        let tests = BroadPhase::Grid.find_contacts(&self.world.bodies, &mut Vec::new());
        self.grid_tests = Some((key, tests));
    }

    /// The grid's pair tests over the present spheres, if counted.
    pub fn grid_tests(&self) -> Option<u64> {
        let key = GridTestsKey::of(&self.world);
        self.grid_tests.filter(|(k, _)| *k == key).map(|(_, t)| t)
    }

    /// The terminal now has this size: keep the help's scroll within it.
    pub fn set_screen(&mut self, screen: Size) {
        self.screen = screen;
        self.help_scroll = self.help_scroll.min(super::help::max_scroll(screen));
    }

    /// Anchor the ghost if it is on and has no anchor, and bring it to the
    /// world's present time. `apply` calls it; the event loop calls it
    /// before drawing, after the steps of a frame.
    pub fn refresh_ghost(&mut self) {
        if !self.show_ghost {
            self.ghost = None;
            return;
        }
        if self.ghost.is_none() {
            match Ghost::anchor(&self.world) {
                Ok(g) => self.ghost = Some(g),
                Err(why) => {
                    self.show_ghost = false;
                    self.status = Some(why);
                    return;
                }
            }
        }
        if let Some(g) = &mut self.ghost {
            let was_shown = g.unavailable.is_none();
            g.update(&self.world);
            if let (true, Some(why)) = (was_shown, g.unavailable) {
                self.status = Some(why.message());
            }
        }
    }

    /// Take in finished background work; true if the picture changed.
    pub fn poll_background(&mut self) -> bool {
        self.charts.poll()
    }

    /// Start the chart's computation for the lesson shown, if open.
    fn request_chart(&mut self) {
        if let (true, Some(lesson)) = (self.chart_open, self.lesson) {
            self.charts.request(lesson);
        }
    }

    /// The physics changed under the ghost: anchor it again here.
    fn restart_ghost(&mut self) {
        if self.show_ghost && self.ghost.take().is_some() {
            self.status = Some("the ghost starts again from here, with the new parameters".into());
        }
    }

    fn next_broad_phase(&mut self) {
        let n = self.world.bodies.len();
        let mut next = self.world.config.broad_phase.next();
        let too_many = next == BroadPhase::AllPairs
            && self.world.config.pair_collisions
            && n > MAX_SPHERES_ALL_PAIRS;
        if too_many {
            next = next.next();
        }
        self.configure(|c| c.broad_phase = next);
        self.status = Some(if !self.world.config.pair_collisions {
            format!(
                "broad phase {}: this scene has no sphere-sphere collisions to test",
                next.name()
            )
        } else if too_many {
            format!(
                "broad phase {}: all-pairs would test {} pairs a step (at most {MAX_SPHERES_ALL_PAIRS} spheres)",
                next.name(),
                all_pairs_tests(n)
            )
        } else {
            format!(
                "broad phase {} (from the next step)",
                super::panel::broad_phase_name(next, n)
            )
        });
    }

    fn neighbour_lesson(&self, d: isize) -> Lesson {
        let n = Lesson::ALL.len() as isize;
        match self
            .lesson
            .and_then(|l| Lesson::ALL.iter().position(|&x| x == l))
        {
            Some(i) => Lesson::ALL[(i as isize + d).rem_euclid(n) as usize],
            None if d > 0 => Lesson::ALL[0],
            None => Lesson::ALL[Lesson::ALL.len() - 1],
        }
    }

    fn open_lesson(&mut self, lesson: Lesson) {
        self.scene = lesson.scene();
        self.lesson = Some(lesson);
        self.rebuild();
        self.request_chart();
    }

    /// Build the scene afresh: step 0, an empty history.
    fn rebuild(&mut self) {
        match self.scene.build() {
            Ok(world) => self.show(world),
            Err(e) => self.status = Some(e.message),
        }
    }

    /// Build the scene with the next seed; keep the seed only if it builds.
    fn reseed(&mut self) {
        let mut scene = self.scene.clone();
        scene.seed = scene.seed.wrapping_add(1);
        match scene.build() {
            Ok(world) => {
                self.scene = scene;
                self.show(world);
                self.status = Some(if self.scene.spawns.is_empty() {
                    "restarted (this scene places no random spheres)".into()
                } else {
                    format!("new seed {}", self.scene.seed)
                });
            }
            Err(e) => {
                self.status = Some(format!("seed {}: {}", scene.seed, e.message));
            }
        }
    }

    fn show(&mut self, world: World) {
        self.ghost = None;
        self.grid_tests = None;
        self.history = History::new(&world);
        self.energy = EnergyLog::new(&world);
        self.speed_scale = speed_scale(&world);
        self.world = world;
        self.note_capacity();
    }

    fn note_capacity(&mut self) {
        if self.history.capacity() < super::history::STEPS {
            self.status = Some(format!(
                "{} spheres: step back reaches {} steps (memory budget)",
                self.world.bodies.len(),
                self.history.capacity() - 1
            ));
        }
    }

    /// Change the live config and the scene's alike.
    fn configure(&mut self, change: impl Fn(&mut WorldConfig)) {
        change(&mut self.world.config);
        change(&mut self.scene.world);
    }

    fn nudge_wall_restitution(&mut self, d: f64) {
        let c = step_restitution(self.wall_restitution(), d);
        self.configure(|w| {
            w.wall_mode = WallMode::Restitution;
            w.wall_restitution = c;
        });
        self.restart_ghost();
    }

    fn nudge_pair_restitution(&mut self, d: f64) {
        let e = step_restitution(self.world.config.pair_restitution, d);
        self.configure(|w| w.pair_restitution = e);
        if self.world.config.pair_collisions {
            self.restart_ghost();
        } else {
            self.status = Some(format!(
                "pair restitution e = {e:.2}; this scene has no sphere-sphere collisions"
            ));
        }
    }

    fn move_gravity(&mut self, up: bool) {
        let g = next_gravity(self.gravity(), up);
        self.configure(|w| w.gravity = Vec3::new(0.0, -g, 0.0));
        self.energy.record_again(&self.world);
        self.restart_ghost();
        self.speed_scale = self.speed_scale.max(speed_scale(&self.world));
    }

    fn scale_dt(&mut self, factor: f64) {
        let dt = self.world.config.dt * factor;
        match rules::dt(dt) {
            Ok(dt) if (DT_MIN..=DT_MAX).contains(&dt) => self.configure(|w| w.dt = dt),
            _ => {
                self.status = Some(format!(
                    "dt stays between 1/{:.0} s and 1/{:.0} s",
                    1.0 / DT_MIN,
                    1.0 / DT_MAX
                ));
            }
        }
    }

    /// The most spheres this scene may hold here.
    pub fn max_spheres(&self) -> usize {
        let c = &self.world.config;
        if c.pair_collisions && matches!(c.broad_phase, BroadPhase::AllPairs) {
            MAX_SPHERES_ALL_PAIRS
        } else {
            MAX_SPHERES
        }
    }

    fn resize(&mut self, more: bool) {
        if self.scene.spawns.is_empty() {
            self.status = Some(format!(
                "the {} scene has exactly {} sphere{}: it places none at random",
                self.scene.name,
                self.scene.bodies.len(),
                if self.scene.bodies.len() == 1 {
                    ""
                } else {
                    "s"
                }
            ));
            return;
        }
        let now = self.scene.spawned();
        let fixed = self.scene.bodies.len();
        let limit = self.max_spheres().saturating_sub(fixed).max(1);
        let target = if more {
            next_count(now, true).min(limit).max(now)
        } else {
            next_count(now, false).max(1)
        };
        if target == now {
            self.status = Some(if more && now > limit {
                format!(
                    "{} spheres is already past the most for this scene here ({})",
                    now + fixed,
                    limit + fixed
                )
            } else if more {
                format!("{} spheres is the most for this scene here", now + fixed)
            } else {
                "one sphere is the fewest".into()
            });
            return;
        }
        let before = self.scene.clone();
        let built = self
            .scene
            .set_particles(target)
            .and_then(|()| self.scene.build().map_err(|e| e.message));
        match built {
            Ok(world) => {
                self.show(world);
                if self.status.is_none() {
                    self.status = Some(format!("{} spheres", self.world.bodies.len()));
                }
            }
            Err(message) => {
                self.scene = before;
                self.status = Some(format!("{target} spheres: {message}"));
            }
        }
    }
}

/// Pair tests the lesson's all-pairs method makes a step: `n (n - 1) / 2`.
pub fn all_pairs_tests(n: usize) -> u64 {
    let n = n as u64;
    n * n.saturating_sub(1) / 2
}

/// `c + d` rounded to hundredths and clamped to [0, 1].
pub fn step_restitution(c: f64, d: f64) -> f64 {
    let v = ((c + d) * 100.0).round() / 100.0;
    rules::restitution(v.clamp(0.0, 1.0)).unwrap_or(c)
}

/// The next rung of [`GRAVITY_LADDER`] above or below `g`.
pub fn next_gravity(g: f64, up: bool) -> f64 {
    let eps = 1e-9;
    let rungs = GRAVITY_LADDER.iter().map(|&(v, _)| v);
    let next = if up {
        rungs.clone().find(|&v| v > g + eps)
    } else {
        rungs.clone().rev().find(|&v| v < g - eps)
    };
    next.unwrap_or(if up { GRAVITY_MAX } else { 0.0 })
        .clamp(0.0, GRAVITY_MAX)
}

/// The name of a gravity magnitude, if it is a known body's.
pub fn gravity_name(g: f64) -> &'static str {
    GRAVITY_LADDER
        .iter()
        .find(|&&(v, _)| (v - g).abs() < 1e-9)
        .map_or("", |&(_, n)| n)
}

/// The next count on the 1-2-5 ladder above or below `n`.
pub fn next_count(n: usize, up: bool) -> usize {
    let mut rungs = Vec::new();
    let mut p = 1usize;
    while p <= MAX_SPHERES * 10 {
        rungs.extend([p, 2 * p, 5 * p]);
        p *= 10;
    }
    if up {
        rungs.into_iter().find(|&r| r > n).unwrap_or(n)
    } else {
        rungs.into_iter().rev().find(|&r| r < n).unwrap_or(1)
    }
}

/// The colour scale's top speed: the fastest a sphere could go by falling
/// to the floor from where it is, rounded up to 1, 2 or 5 times a power
/// of ten.
pub fn speed_scale(world: &World) -> f64 {
    let g = world.config.gravity.length();
    let b = &world.bodies;
    let top = (0..b.len())
        .map(|i| (b.velocity[i].length_squared() + 2.0 * g * b.position[i].y).sqrt())
        .fold(0.0, f64::max);
    nice_ceiling(top.max(0.1))
}

fn nice_ceiling(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&v| v >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pause_and_step_forward() {
        let mut app = App::lesson(Lesson::Pingpong);
        assert!(!app.paused, "a lesson opens running");
        app.apply(Action::TogglePause);
        assert!(app.paused);
        app.apply(Action::StepForward);
        app.apply(Action::StepForward);
        assert_eq!(app.world.steps, 2);
        assert!(app.paused, "stepping keeps the pause");
        let dt = app.world.config.dt;
        assert!((app.world.bodies.position[0].y - (0.5 + 2.0 * dt)).abs() < 1e-12);
    }

    #[test]
    fn step_back_restores_the_exact_earlier_state() {
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::WallRestitutionDown);
        app.apply(Action::PairRestitutionDown);
        let mut hashes = Vec::new();
        let mut bodies = Vec::new();
        for _ in 0..30 {
            hashes.push(app.world.state_hash());
            bodies.push(app.world.bodies.clone());
            app.apply(Action::StepForward);
        }
        for k in (0..30).rev() {
            app.apply(Action::StepBack);
            assert_eq!(app.world.state_hash(), hashes[k], "state hash at step {k}");
            assert_eq!(app.world.bodies, bodies[k], "bodies at step {k}");
        }
        app.apply(Action::StepBack);
        assert_eq!(app.world.steps, 0);
        assert!(app.status.as_deref().unwrap().contains("no earlier step"));
        assert_eq!(app.energy.len(), 1, "the energy log steps back too");
    }

    #[test]
    fn restitution_is_clamped_and_turns_flip_walls_into_restitution_walls() {
        let mut app = App::lesson(Lesson::Pingpong);
        assert_eq!(app.world.config.wall_mode, WallMode::Flip);
        app.apply(Action::WallRestitutionUp);
        assert_eq!(app.world.config.wall_mode, WallMode::Restitution);
        assert_eq!(app.world.config.wall_restitution, 1.0);
        for _ in 0..25 {
            app.apply(Action::WallRestitutionDown);
        }
        assert_eq!(app.world.config.wall_restitution, 0.0);
        app.apply(Action::WallRestitutionUp);
        assert_eq!(app.world.config.wall_restitution, 0.05);
        assert_eq!(app.scene.world.wall_restitution, 0.05, "a restart keeps it");
        for _ in 0..30 {
            app.apply(Action::PairRestitutionUp);
        }
        assert_eq!(app.world.config.pair_restitution, 1.0);
    }

    #[test]
    fn gravity_moves_along_its_ladder_within_0_and_20() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::GravityUp);
        assert_eq!(app.world.config.gravity, Vec3::new(0.0, -12.0, 0.0));
        for _ in 0..20 {
            app.apply(Action::GravityUp);
        }
        assert_eq!(app.gravity(), GRAVITY_MAX);
        for _ in 0..20 {
            app.apply(Action::GravityDown);
        }
        assert_eq!(app.gravity(), 0.0);
        assert_eq!(next_gravity(9.0, false), 8.0, "from off the ladder");
        assert_eq!(gravity_name(1.62), "Moon");
    }

    #[test]
    fn a_parameter_acts_on_the_next_step_without_a_restart() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::StepForward);
        let v0 = app.world.bodies.velocity.clone();
        app.apply(Action::GravityDown);
        app.apply(Action::StepForward);
        assert_eq!(app.world.steps, 2, "no restart");
        let dt = app.world.config.dt;
        // Spheres that met no wall this step gained exactly -g dt with g = 8.
        let pulled_at_8 = v0
            .iter()
            .zip(&app.world.bodies.velocity)
            .filter(|(a, b)| (b.y - a.y + 8.0 * dt).abs() < 1e-12)
            .count();
        assert!(
            pulled_at_8 + app.world.last.wall_impacts >= 150,
            "only {pulled_at_8} of 150 spheres felt the new gravity"
        );
    }

    #[test]
    fn dt_halves_and_doubles_within_its_bounds() {
        let mut app = App::lesson(Lesson::Pingpong);
        let dt0 = app.world.config.dt;
        app.apply(Action::HalveDt);
        assert_eq!(app.world.config.dt, dt0 / 2.0);
        for _ in 0..20 {
            app.apply(Action::HalveDt);
        }
        assert!(app.world.config.dt >= DT_MIN);
        assert!(app.status.is_some(), "the refusal is explained");
        for _ in 0..20 {
            app.apply(Action::DoubleDt);
        }
        assert!(app.world.config.dt <= DT_MAX);
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
        assert_eq!(app.world.bodies.len(), 150);
        assert_eq!(app.world.config.wall_restitution, 0.95);
        assert_eq!(app.world.steps, 0);
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
        app.apply(Action::NextLesson);
        assert_eq!(app.lesson, Some(Lesson::Pingpong));
        app.apply(Action::PreviousLesson);
        assert_eq!(app.lesson, Some(Lesson::Collisions));
    }

    #[test]
    fn restart_keeps_parameters_and_reseed_changes_the_bodies() {
        let mut app = App::lesson(Lesson::Gravity);
        let start = app.world.bodies.clone();
        app.apply(Action::WallRestitutionDown);
        app.world.run(10);
        app.apply(Action::Restart);
        assert_eq!(app.world.steps, 0);
        assert_eq!(app.world.bodies, start);
        assert_eq!(app.world.config.wall_restitution, 0.9);
        app.apply(Action::Reseed);
        assert_eq!(app.scene.seed, 2);
        assert_ne!(app.world.bodies.position, start.position);
    }

    #[test]
    fn a_reseed_that_cannot_build_keeps_the_seed_the_world_and_the_error() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::StepForward);
        let bodies = app.world.bodies.clone();
        // 400 spheres of radius 0.07 cannot be placed apart in the box.
        app.scene.spawns[0].count = 400;
        app.scene.spawns[0].radius = [0.07, 0.07];
        app.scene.spawns[0].overlap = false;
        app.apply(Action::Reseed);
        assert_eq!(app.scene.seed, 1, "the seed is kept");
        assert_eq!(
            (app.world.steps, &app.world.bodies),
            (1, &bodies),
            "the world is kept"
        );
        let status = app.status.as_deref().unwrap();
        assert!(status.contains("seed 2:"), "the error is shown: {status}");
    }

    #[test]
    fn sphere_count_follows_the_ladder_and_pingpong_explains_why_not() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::MoreSpheres);
        assert_eq!(app.world.bodies.len(), 200);
        app.apply(Action::FewerSpheres);
        assert_eq!(app.world.bodies.len(), 100);
        let mut app = App::lesson(Lesson::Pingpong);
        app.apply(Action::MoreSpheres);
        assert_eq!(app.world.bodies.len(), 1);
        assert!(
            app.status
                .as_deref()
                .unwrap()
                .contains("places none at random")
        );
    }

    #[test]
    fn the_collisions_lesson_stops_at_the_all_pairs_limit() {
        let mut scene = Lesson::Collisions.scene();
        for s in &mut scene.spawns {
            s.overlap = true;
        }
        scene.set_particles(MAX_SPHERES_ALL_PAIRS).unwrap();
        assert_eq!(next_count(MAX_SPHERES_ALL_PAIRS, true), 10_000);
        let mut app = App::new(scene, Some(Lesson::Collisions)).unwrap();
        assert_eq!(app.world.bodies.len(), MAX_SPHERES_ALL_PAIRS);
        app.apply(Action::MoreSpheres);
        assert_eq!(app.world.bodies.len(), MAX_SPHERES_ALL_PAIRS);
        let status = app.status.as_deref().unwrap();
        assert!(status.contains("is the most"), "{status}");
    }

    #[test]
    fn more_spheres_never_lowers_a_count_already_past_the_limit() {
        let mut scene = Lesson::Collisions.scene();
        for s in &mut scene.spawns {
            s.overlap = true;
        }
        scene.set_particles(2 * MAX_SPHERES_ALL_PAIRS).unwrap();
        let mut app = App::new(scene, Some(Lesson::Collisions)).unwrap();
        let n = app.world.bodies.len();
        assert!(n > MAX_SPHERES_ALL_PAIRS);
        app.apply(Action::MoreSpheres);
        assert_eq!(app.world.bodies.len(), n, "the count is kept");
        let status = app.status.as_deref().unwrap();
        assert!(status.contains("already past the most"), "{status}");
    }

    #[test]
    fn b_cycles_the_broad_phase_and_the_next_step_uses_it() {
        let mut app = App::lesson(Lesson::Collisions);
        assert_eq!(app.world.config.broad_phase, BroadPhase::AllPairs);
        app.apply(Action::StepForward);
        assert_eq!(app.world.last.pair_tests, 4950, "100 spheres: 100 x 99 / 2");
        app.apply(Action::NextBroadPhase);
        assert_eq!(app.world.config.broad_phase, BroadPhase::Grid);
        assert_eq!(
            app.scene.world.broad_phase,
            BroadPhase::Grid,
            "a restart keeps it"
        );
        assert_eq!(app.world.steps, 1, "no restart");
        app.apply(Action::StepForward);
        assert_eq!(app.world.last.broad_phase, Some(BroadPhase::Grid));
        assert!(
            app.world.last.pair_tests < 4950,
            "the grid tests fewer pairs: {}",
            app.world.last.pair_tests
        );
        app.apply(Action::NextBroadPhase);
        assert_eq!(app.world.config.broad_phase, BroadPhase::Auto);
        app.apply(Action::StepForward);
        assert_eq!(
            app.world.last.broad_phase,
            Some(BroadPhase::AllPairs),
            "auto runs all-pairs below its crossover"
        );
        app.apply(Action::NextBroadPhase);
        assert_eq!(app.world.config.broad_phase, BroadPhase::AllPairs);
    }

    #[test]
    fn b_skips_all_pairs_where_it_would_test_too_many_pairs() {
        let mut app = App::lesson(Lesson::Collisions);
        app.show(crate::cli::bench::bench_world(
            MAX_SPHERES_ALL_PAIRS + 1,
            BroadPhase::Grid,
        ));
        let n = app.world.bodies.len();
        assert!(n > MAX_SPHERES_ALL_PAIRS);
        app.apply(Action::NextBroadPhase);
        app.apply(Action::NextBroadPhase);
        assert_eq!(app.world.config.broad_phase, BroadPhase::Grid);
        assert!(
            app.status
                .as_deref()
                .unwrap()
                .contains("all-pairs would test")
        );
    }

    #[test]
    fn the_ghost_is_the_exact_reference_from_where_it_was_switched_on() {
        use crate::sim::reference::exact_positions;
        let mut app = App::lesson(Lesson::Pingpong);
        app.apply(Action::TogglePause);
        for _ in 0..7 {
            app.apply(Action::StepForward);
        }
        let anchor = app.world.clone();
        app.apply(Action::ToggleGhost);
        assert!(app.show_ghost);
        for _ in 0..40 {
            app.apply(Action::StepForward);
        }
        let expected = exact_positions(&anchor, app.world.time - anchor.time).unwrap();
        let ghost = app.ghost.as_ref().unwrap();
        assert_eq!(ghost.positions, expected);
        assert!(
            ghost.rms.unwrap() < 1e-12,
            "the ping-pong method is exact: RMS {:e}",
            ghost.rms.unwrap()
        );
        // Back within the anchored stretch: the same anchor, an earlier time.
        for _ in 0..10 {
            app.apply(Action::StepBack);
        }
        let expected = exact_positions(&anchor, app.world.time - anchor.time).unwrap();
        assert_eq!(app.ghost.as_ref().unwrap().positions, expected);
        // Back past the anchor: it starts again from there.
        for _ in 0..35 {
            app.apply(Action::StepBack);
        }
        assert_eq!(app.world.steps, 2);
        let now = app.world.clone();
        app.apply(Action::StepForward);
        let expected = exact_positions(&now, app.world.time - now.time).unwrap();
        assert_eq!(app.ghost.as_ref().unwrap().positions, expected);
        app.apply(Action::ToggleGhost);
        assert!(!app.show_ghost && app.ghost.is_none());
    }

    #[test]
    fn the_ghost_of_colliding_spheres_stops_at_the_predictability_horizon() {
        use super::super::ghost::PAIR_HORIZON;
        let mut app = App::lesson(Lesson::Collisions);
        app.apply(Action::TogglePause);
        app.apply(Action::ToggleGhost);
        app.apply(Action::StepForward);
        let g = app.ghost.as_ref().unwrap();
        assert!(g.unavailable.is_none() && g.rms.is_some());
        let dt = app.world.config.dt;
        let steps = (PAIR_HORIZON / dt).ceil() as u64 + 1;
        app.world.run(steps);
        app.refresh_ghost();
        let g = app.ghost.as_ref().unwrap();
        assert!(g.positions.is_empty());
        assert_eq!(
            g.unavailable,
            Some(super::super::ghost::Unavailable::PastHorizon)
        );
        assert!(
            app.status.as_deref().unwrap().contains("chaotic"),
            "said once"
        );
        // A parameter of the physics anchors it again.
        app.apply(Action::GravityDown);
        assert!(app.ghost.as_ref().unwrap().unavailable.is_none());
    }

    #[test]
    fn the_ghost_follows_a_restart_and_refuses_worlds_too_big_for_it() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::ToggleGhost);
        app.world.run(20);
        app.apply(Action::Restart);
        let g = app.ghost.as_ref().unwrap();
        assert_eq!(g.rms, Some(0.0), "anchored at the new start");
        let mut app = App::lesson(Lesson::Collisions);
        let n = super::super::ghost::MAX_PAIR_GHOST_SPHERES + 1;
        app.show(crate::cli::bench::bench_world(n, BroadPhase::Grid));
        app.apply(Action::ToggleGhost);
        assert!(!app.show_ghost);
        assert!(app.status.as_deref().unwrap().contains("no ghost for"));
    }

    fn synthetic(lesson: Lesson) -> Result<Vec<crate::study::Row>, String> {
        Err(format!("synthetic {}", lesson.name()))
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
        let end = super::super::help::max_scroll(app.screen);
        assert!(end > 0, "the help does not fit in 80x24");
        app.apply(Action::ToggleHelp);
        for _ in 0..300 {
            app.apply(Action::ScrollHelp(1));
        }
        assert_eq!(app.help_scroll, end);
        app.apply(Action::ScrollHelp(-1));
        assert_eq!(app.help_scroll, end - 1, "one press up moves it");
        app.set_screen(Size::new(200, 60));
        assert_eq!(app.help_scroll, 0, "it all fits on a big screen");
    }

    #[test]
    fn the_newest_energy_sample_follows_a_gravity_change() {
        let mut app = App::lesson(Lesson::Gravity);
        app.apply(Action::StepForward);
        app.apply(Action::GravityDown);
        let d = app.world.diagnostics();
        let s = app.energy.now(&app.world).unwrap();
        assert_eq!(
            (s.steps, s.potential, s.total, s.momentum),
            (1, d.potential_energy, d.total_energy, d.momentum)
        );
        assert_eq!(app.energy.len(), 2, "the sample is replaced, not added");
    }

    #[test]
    fn the_grid_comparison_is_counted_once_per_step_and_only_when_shown() {
        let mut app = App::lesson(Lesson::Collisions);
        let count = |app: &App| BroadPhase::Grid.find_contacts(&app.world.bodies, &mut Vec::new());
        assert_eq!(app.grid_tests(), Some(count(&app)), "all-pairs runs");
        app.world.run(1);
        assert_eq!(
            app.grid_tests(),
            None,
            "a step outside apply: not counted yet"
        );
        app.refresh_grid_tests();
        assert_eq!(app.grid_tests(), Some(count(&app)));
        app.apply(Action::NextBroadPhase);
        app.apply(Action::StepForward);
        assert!(
            !app.needs_grid_tests(),
            "the grid ran: its own count stands"
        );
        assert_eq!(app.grid_tests(), None);
    }

    #[test]
    fn the_speed_scale_rounds_up_to_1_2_5() {
        assert_eq!(nice_ceiling(0.7), 1.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
        assert_eq!(nice_ceiling(3.2), 5.0);
        assert_eq!(nice_ceiling(12.0), 20.0);
    }
}
