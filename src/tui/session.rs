//! The simulation session: the scene shown, its world, the step-back
//! history, the energy log, the ghost of the exact reference and the
//! grid's pair-test count for the panel. In the visualiser it lives on the
//! worker thread (`worker.rs`); tests drive it directly.
//!
//! [`Session::apply`] carries out the actions that change the simulation
//! (stepping, parameters, lessons, sphere counts, the ghost) and returns
//! the message to show, if any; [`Session::frame`] copies out what the
//! view draws. Parameters are written to both the world's config (so they
//! act on the next step) and the scene (so a restart keeps them); choosing
//! a lesson loads it with its own parameters.
//!
//! Owns the physics state only: nothing here draws, reads a terminal or a
//! clock.

use super::action::Action;
use super::energy_log::EnergyLog;
use super::frame::Frame;
use super::ghost::Ghost;
use super::history::History;
use super::numbers::{broad_phase_name, format_dt, format_energy, format_significant};
use super::selection::{self, Impact, Inspection, Selection};
use crate::scene::{Lesson, Scene, SceneError, rules, spheres, thousands};
use crate::sim::broad_phase::{MAX_SPHERES_ALL_PAIRS, all_pairs_tests, grid_tests, grid_too_slow};
use crate::sim::config::STANDARD_GRAVITY;
use crate::sim::{BroadPhase, Integrator, Vec3, WallMode, World, WorldConfig, gravity_along};
use std::sync::Arc;

/// Spheres from which a step's snapshot and energy sample are taken on
/// two threads at once (in a smaller world both take microseconds, and
/// run in turn).
const RECORD_SIDE_BY_SIDE: usize = 10_000;

/// Restitution changes by this much per key press.
pub(crate) const RESTITUTION_STEP: f64 = 0.05;
/// Gravity magnitudes the `g`/`G` keys move between, m/s^2, with a name
/// where the value is a body's surface gravity.
pub(crate) const GRAVITY_LADDER: &[(f64, &str)] = &[
    (0.0, "none"),
    (1.0, ""),
    (1.62, "Moon"),
    (3.71, "Mars"),
    (5.0, ""),
    (8.0, ""),
    (STANDARD_GRAVITY, "Earth"),
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
/// Most spheres `+` adds: drawing stays interactive up to here.
pub(crate) const MAX_SPHERES: usize = 100_000;
/// `o` looks this far ahead for a collision, simulated s, within
/// [`COLLISION_SEARCH_STEPS`].
pub(crate) const COLLISION_SEARCH_SECONDS: f64 = 10.0;
/// And at most this many steps (76,800): the 10 s at the smallest `dt`
/// the keys reach, [`DT_MIN`]. A finer `dt` (from `--dt` or a scene) looks
/// less far ahead, and says so, rather than search for hours.
pub(crate) const COLLISION_SEARCH_STEPS: u64 = (COLLISION_SEARCH_SECONDS / DT_MIN) as u64;

#[derive(Debug)]
pub struct Session {
    /// The recipe of the world shown, with the live parameters (shared
    /// with the frames that show it; copied only when it changes).
    pub scene: Arc<Scene>,
    /// The scene opened from a file, as opened (`None`: a lesson was):
    /// Tab and Shift-Tab come back to it.
    opened: Option<Arc<Scene>>,
    /// The scene as opened: `+` and `-` size its spheres anew from it.
    base: Arc<Scene>,
    /// The gravity the lesson's text was written for: the lesson's own
    /// (whatever `--gravity` asked), or a scene file's as opened.
    pub(crate) lesson_gravity: Vec3,
    /// The lesson shown, or `None` for a scene file.
    pub lesson: Option<Lesson>,
    pub world: World,
    /// Worlds shown since the session began: each new one (a lesson, a
    /// restart, a new seed, + or -) counts one.
    pub worlds: u64,
    pub history: History,
    pub energy: EnergyLog,
    /// The exact reference is drawn as a ghost.
    pub show_ghost: bool,
    /// The ghost's anchor and positions while `show_ghost` (see `ghost`).
    pub ghost: Option<Ghost>,
    /// The speed drawn in the hottest colour, m/s.
    pub speed_scale: f64,
    /// The grid's pair tests over the present spheres, for the panel's
    /// comparison of broad phases (see [`Session::refresh_grid_tests`]).
    grid_tests: Option<(GridTestsKey, u64)>,
    /// The sphere or pair picked, by scene index.
    pub selection: Option<Selection>,
    /// Collisions of the selected spheres since they were picked, or
    /// since an earlier step stepped back to, in the order of their steps.
    impacts: Vec<(u32, Impact)>,
    /// The first step whose impacts are in `impacts`: the step of the
    /// pick (the next one when its contacts were not listed), or the
    /// earliest step back to since, while each step's impacts could be
    /// told.
    impacts_from: u64,
    /// A message for the person, taken by [`Session::take_message`].
    message: Option<String>,
    /// The view marks each step's contacts ([`Session::show_contacts`]).
    contacts_shown: bool,
    /// `o` is looking for a collision among the coming steps' contacts.
    seeking: bool,
    /// A search for a collision that gave way to a newer key: how many
    /// steps it had searched, and the step it went back to. The key that
    /// stopped it says so (the search's own message answers the search,
    /// which that key replaced).
    stopped_search: Option<(u64, u64)>,
    /// The sphere `o` follows: picked when `o` was pressed, it stays
    /// followed while the selection is one of its collisions.
    following: Option<u32>,
    /// The collision `o` selected last: while it is the selection, `o`
    /// walks on from it (a sphere `o` selected at a wall is not a pick).
    found: Option<Selection>,
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

impl Session {
    /// A session showing `scene` (a lesson's when `lesson` is set).
    pub fn new(scene: Scene, lesson: Option<Lesson>) -> Result<Self, SceneError> {
        Self::new_telling(scene, lesson, &|_| {})
    }

    /// [`Session::new`], telling `placed` how the placing of the scene's
    /// spheres goes ([`Scene::build_telling`]).
    pub(crate) fn new_telling(
        scene: Scene,
        lesson: Option<Lesson>,
        placed: &dyn Fn(usize),
    ) -> Result<Self, SceneError> {
        let world = scene.build_telling(placed)?;
        let base = Arc::new(scene.clone());
        let mut session = Self {
            history: History::new(&world),
            energy: EnergyLog::new(&world),
            speed_scale: speed_scale(&world),
            opened: lesson.is_none().then(|| Arc::clone(&base)),
            base,
            lesson_gravity: lesson.map_or(scene.world.gravity, |l| l.scene().world.gravity),
            scene: Arc::new(scene),
            lesson,
            world,
            worlds: 1,
            show_ghost: false,
            ghost: None,
            grid_tests: None,
            selection: None,
            impacts: Vec::new(),
            impacts_from: 0,
            message: None,
            contacts_shown: true,
            seeking: false,
            stopped_search: None,
            following: None,
            found: None,
        };
        session.note_capacity();
        session.refresh_grid_tests();
        Ok(session)
    }

    /// A lesson at its start (the tests' starting point).
    pub fn lesson(lesson: Lesson) -> Self {
        Self::new(lesson.scene(), Some(lesson)).expect("the built-in lessons build (tested)")
    }

    /// The message of the last action, if any; it is given once.
    pub(crate) fn take_message(&mut self) -> Option<String> {
        self.message.take()
    }

    /// Gravity's magnitude, m/s^2.
    pub fn gravity(&self) -> f64 {
        self.world.config.gravity.length()
    }

    /// Say whether the view marks each step's contacts (on until said
    /// otherwise).
    pub(crate) fn show_contacts(&mut self, on: bool) {
        self.contacts_shown = on;
    }

    /// Whether the world lists each step's contacts: the view marks them,
    /// a sphere or pair is picked (its impacts are found among them), or
    /// `o` looks for a collision. Otherwise a large world resolves them
    /// without listing them, which is faster and lighter
    /// ([`World::keep_contacts`]); the panel still counts them.
    fn lists_contacts(&self) -> bool {
        self.contacts_shown || self.selection.is_some() || self.seeking
    }

    /// One physics step, remembered for stepping back.
    pub fn step(&mut self) {
        self.world.keep_contacts(self.lists_contacts());
        self.world.step();
        self.recorded();
    }

    /// One physics step unless `interrupted` says to stop part-way; an
    /// abandoned step leaves the state exactly as it was before it (the
    /// newest snapshot of the history is that state). Returns true when
    /// the step finished.
    pub fn try_step(&mut self, interrupted: &dyn Fn() -> bool) -> bool {
        self.world.keep_contacts(self.lists_contacts());
        if self.world.try_step(interrupted) {
            self.recorded();
            true
        } else {
            self.history.restore_newest(&mut self.world);
            self.find_contacts_again();
            false
        }
    }

    fn recorded(&mut self) {
        let kept = self.history.capacity();
        // The snapshot's copy waits on memory and the energies' pass on
        // arithmetic: in a large world the two run side by side. Either
        // way the same values are recorded.
        let (history, energy, world) = (&mut self.history, &mut self.energy, &self.world);
        if world.bodies.len() >= RECORD_SIDE_BY_SIDE {
            rayon::join(|| history.record(world), || energy.record(world));
        } else {
            history.record(world);
            energy.record(world);
        }
        if self.history.capacity() < kept {
            // The support pass's impulses took the snapshots past the
            // budget: the history keeps fewer steps from now on.
            self.message = Some(format!(
                "{}: step back now reaches {} (memory budget, with the support pass's impulses)",
                spheres(self.world.bodies.len()),
                steps_back(self.history.capacity())
            ));
        }
        if let Some(s) = self.selection {
            let now = selection::impacts_now(&self.world, &self.history, s);
            self.impacts.extend(now);
        }
    }

    /// The selection's numbers at the present step.
    pub fn inspection(&self) -> Option<Inspection> {
        selection::inspect(
            &self.world,
            &self.history,
            self.selection?,
            &self.impacts,
            self.impacts_from,
        )
    }

    /// The person's own pick (or none): `o` follows a sphere picked, and
    /// forgets what it found and followed.
    fn pick(&mut self, s: Option<Selection>) {
        self.following = None;
        self.found = None;
        self.select(s);
    }

    /// Pick the sphere numbered after the one picked, or before it
    /// (`forward` false), round the scene; from a pair its first sphere,
    /// or its second; from none sphere 0, or the last.
    fn pick_by_number(&mut self, forward: bool) {
        let n = self.world.bodies.len() as u32;
        if n == 0 {
            self.message = Some("no sphere to pick: this scene has none".into());
            return;
        }
        let next = match (self.selection, forward) {
            (Some(Selection::Sphere(a)), true) => (a + 1) % n,
            (Some(Selection::Sphere(a)), false) => (a + n - 1) % n,
            (Some(Selection::Pair(a, _)), true) => a,
            (Some(Selection::Pair(_, b)), false) => b,
            (None, true) => 0,
            (None, false) => n - 1,
        };
        self.pick(Some(Selection::Sphere(next)));
        self.message = Some(format!(
            "picked sphere {next} (of 0 to {}): {{ and }} step through them, o runs to its \
             next collision",
            n - 1
        ));
    }

    fn select(&mut self, s: Option<Selection>) {
        match s {
            Some(s) if !selection::exists(&self.world, s) => {
                self.message = Some(format!(
                    "no such sphere: this scene has {} (numbered 0 to {})",
                    self.world.bodies.len(),
                    self.world.bodies.len().saturating_sub(1)
                ));
            }
            _ => {
                let changed = s != self.selection;
                self.selection = s;
                if changed {
                    self.impacts.clear();
                    self.note_impacts_now();
                }
            }
        }
    }

    /// Take the present step's impacts of the selection into account when
    /// they can be told, else start from the next step.
    fn note_impacts_now(&mut self) {
        self.impacts_from = self.world.steps;
        if !self.noted_impacts_now() {
            self.impacts_from += 1;
        }
    }

    /// Add the present step's impacts of the selection when they can be
    /// told; whether they were.
    fn noted_impacts_now(&mut self) -> bool {
        match self.selection {
            Some(s) if selection::impacts_known(&self.world, &self.history) => {
                let now = selection::impacts_now(&self.world, &self.history, s);
                self.impacts.extend(now);
                true
            }
            _ => false,
        }
    }

    /// The next of this step's collisions after the selected one, else step
    /// until a collision (see `selection::collisions`), at most
    /// [`COLLISION_SEARCH_SECONDS`] of simulated time and
    /// [`COLLISION_SEARCH_STEPS`] steps; select it.
    fn run_to_collision(&mut self, interrupted: &dyn Fn() -> bool) {
        self.seeking = true;
        self.seek_collision(interrupted);
        self.seeking = false;
    }

    /// [`Session::run_to_collision`], while the steps list their contacts.
    /// With a sphere picked, or followed ([`Session::following`]) to one
    /// of its collisions, only that sphere's collisions count.
    fn seek_collision(&mut self, interrupted: &dyn Fn() -> bool) {
        let by_o = self.selection.is_some() && self.selection == self.found;
        let follow = match self.selection {
            Some(s) if by_o => self.following.filter(|&a| s.contains(a)),
            Some(Selection::Sphere(a)) => Some(a),
            _ => None,
        };
        let counts = |c: &Selection| follow.is_none_or(|a| c.contains(a));
        // The selection is the collision `o` found in this step: the next
        // of this step's collisions.
        let now = selection::collisions_following(&self.world, &self.history, follow);
        if by_o
            && let Some(k) = self
                .selection
                .and_then(|s| now.found.iter().position(|&c| c == s))
            && let Some(next) = now.found[k + 1..].iter().position(counts)
        {
            self.following = follow;
            self.show_collision(&now, k + 1 + next);
            return;
        }
        let dt = self.world.config.dt;
        let most = ((COLLISION_SEARCH_SECONDS / dt).ceil() as u64).min(COLLISION_SEARCH_STEPS);
        // A search that finds nothing, or gives way to a newer key, goes
        // back to where it began: the history keeps what it held (moved
        // aside, not copied, as the search pushes it out), the energy log
        // is copied (it is small).
        self.history.mark();
        let energy = self.energy.clone();
        let began = self.world.steps;
        let back = |s: &mut Self, energy| {
            s.history.rewind();
            s.energy = energy;
            s.history.restore_newest(&mut s.world);
            s.arrived_back();
        };
        // Steps whose replay met pairs only pushed apart, not approaching:
        // no collision, but the lesson's position correction at work
        // (pairs left resting to the support pass are not counted).
        let mut pushed_apart = 0;
        for _ in 0..most {
            if !self.try_step(interrupted) {
                let searched = self.world.steps - began;
                back(self, energy);
                self.stopped_search = Some((searched, began));
                return;
            }
            let now = selection::collisions_following(&self.world, &self.history, follow);
            if let Some(k) = now.found.iter().position(counts) {
                self.history.unmark();
                self.following = follow;
                self.show_collision(&now, k);
                return;
            }
            pushed_apart += u64::from(now.apart > 0);
        }
        let what = match (follow, selection::seeks_pairs(&self.world)) {
            (Some(a), true) => format!("collision of sphere {a} with another sphere or a wall"),
            (Some(a), false) => format!("collision of sphere {a}"),
            (None, true) => "collision between spheres".to_string(),
            (None, false) => "collision".to_string(),
        };
        back(self, energy);
        let pushed = match (follow, pushed_apart) {
            (None, 1..) => format!(
                " (in {pushed_apart} of those steps overlapping spheres were only pushed apart, \
                 not approaching: d marks contacts)"
            ),
            _ => String::new(),
        };
        // Cut short by the steps, not by a rounding of the last one.
        let ahead = if most as f64 * dt < COLLISION_SEARCH_SECONDS * (1.0 - 1e-9) {
            format!(
                "{} steps ({} s of simulated time, at dt = {})",
                thousands(most),
                format_significant(most as f64 * dt),
                format_dt(dt)
            )
        } else {
            format!("{COLLISION_SEARCH_SECONDS} s of simulated time")
        };
        self.message = Some(format!(
            "no {what} in the next {ahead}: back at step {}{pushed}",
            self.world.steps
        ));
    }

    /// Select collision `k` (from 0) of the step's `collisions`, and say
    /// so.
    fn show_collision(&mut self, collisions: &selection::Collisions, k: usize) {
        let found = collisions.found[k];
        // A new pick notes the step's impacts; those of the pick kept were
        // noted when the step was taken.
        self.select(Some(found));
        self.found = Some(found);
        let now = selection::impacts_now(&self.world, &self.history, found);
        let wall = now.last().map(|(_, i)| i.kind.describe());
        self.message = Some(self.collision_message(collisions, k, wall));
    }

    /// After `n` or `,`: when the step arrived at is one of the selection's
    /// collisions, say which, as `o` did on finding it (the message of an
    /// action lasts until the next one, so walking away and back would
    /// otherwise lose it).
    fn note_selected_collision(&mut self) {
        let Some(selected) = self.selection else {
            return;
        };
        if self.message.is_some() || self.world.steps == 0 {
            return;
        }
        let follow = match selected {
            Selection::Sphere(a) => Some(a),
            Selection::Pair(..) => None,
        };
        let now = selection::collisions_following(&self.world, &self.history, follow);
        if let Some(k) = now.found.iter().position(|&c| c == selected) {
            // Only a sphere's message names what it met.
            let wall = match selected {
                Selection::Sphere(_) => {
                    selection::impacts_now(&self.world, &self.history, selected)
                        .last()
                        .map(|(_, i)| i.kind.describe())
                }
                Selection::Pair(..) => None,
            };
            self.message = Some(self.collision_message(&now, k, wall));
        }
    }

    /// What [`Session::show_collision`] says of collision `k` of
    /// `collisions` (`wall`: what a sphere's impact met).
    fn collision_message(
        &self,
        collisions: &selection::Collisions,
        k: usize,
        wall: Option<String>,
    ) -> String {
        let (found, of) = (collisions.found[k], collisions.found.len());
        let what = match found {
            // A resting contact is resolved as the lesson resolves an
            // impact, with e = 0: say so (the panel says why).
            Selection::Pair(a, b) => {
                let inspection = self.inspection();
                let rule = inspection
                    .as_ref()
                    .and_then(|i| Some(i.pair.as_ref()?.rule(&i.config)));
                let landed = inspection
                    .as_ref()
                    .and_then(|i| i.pair_note.as_deref())
                    .is_some_and(|note| note.starts_with(selection::LANDED));
                match rule {
                    None if landed => format!(
                        "spheres {a} and {b} land in resting contact, held by the support pass"
                    ),
                    Some(selection::PairRule::Resting) => {
                        format!("spheres {a} and {b} meet in resting contact (e = 0)")
                    }
                    Some(selection::PairRule::RestThreshold) => {
                        format!("spheres {a} and {b} meet slower than the rest threshold (e = 0)")
                    }
                    _ => format!("spheres {a} and {b} collide"),
                }
            }
            Selection::Sphere(a) => {
                format!(
                    "sphere {a} meets {}",
                    wall.unwrap_or_else(|| "a wall".into())
                )
            }
        };
        // While `o` follows a sphere, it walks that sphere's collisions:
        // count those.
        let following = self.following.filter(|&a| found.contains(a));
        let (k, of) = match following {
            Some(a) => {
                let theirs = |c: &&Selection| c.contains(a);
                let before = collisions.found[..k].iter().filter(theirs).count();
                (before, collisions.found.iter().filter(theirs).count())
            }
            None => (k, of),
        };
        let mut which = match (of, following) {
            (0 | 1, _) => String::new(),
            (_, Some(_)) => format!(", its collision {} of {of}", k + 1),
            (_, None) => format!(", collision {} of {of}", k + 1),
        };
        // The panel counts every contact; say why some are not collisions.
        let more = |n: usize, why: &str| match n {
            0 => String::new(),
            1 => format!("; 1 more contact {why}"),
            n => format!("; {n} more contacts {why}"),
        };
        // Those are the step's, also while `o` follows one sphere.
        let in_step = if following.is_some() {
            "in the step "
        } else {
            ""
        };
        which += &more(
            collisions.apart,
            &format!("{in_step}took no impulse: not approaching"),
        );
        which += &more(
            collisions.resting,
            &format!("{in_step}rested on the support pass"),
        );
        // While `o` follows a sphere, say whose collisions it walks.
        let whose = match following {
            Some(a) => format!("sphere {a}'s next: "),
            None => String::new(),
        };
        // The continuous method meets it at its own time inside the step.
        let stepped = self.history.stepped_with().unwrap_or(&self.world.config);
        let (t, n) = (self.world.time, self.world.steps);
        if stepped.integrator == Integrator::Continuous {
            format!(
                "{whose}{what} within step {n} (t = {:.3} to {t:.3} s{which}): 'n' steps on, ',' \
                 back",
                t - stepped.dt
            )
        } else {
            format!("{whose}{what} at t = {t:.3} s (step {n}{which}): 'n' steps on, ',' back")
        }
    }

    /// Carry out `action` if it changes the simulation; the others (view,
    /// camera, help, pausing) are the view's and change nothing here.
    pub fn apply(&mut self, action: Action) {
        self.apply_unless(action, &|| false);
    }

    /// [`Session::apply`], with a step forward abandoned (and the state
    /// left as it was) when `interrupted` says so part-way.
    pub(crate) fn apply_unless(&mut self, action: Action, interrupted: &dyn Fn() -> bool) {
        let stopped_search = self.stopped_search.take();
        self.carry_out(action, interrupted);
        if let Some((searched, began)) = stopped_search {
            let back = back_from_search(searched, began);
            self.message = Some(match (action, self.message.take()) {
                (Action::StopWork, _) => format!("Esc stopped the search for a collision {back}"),
                (Action::ClearSelection, _) => format!(
                    "Esc stopped the search for a collision {back}, and forgot the selection"
                ),
                (_, None) => format!("this key stopped the search for a collision {back}"),
                (_, Some(own)) => format!("the search for a collision stopped {back}; {own}"),
            });
        }
    }

    /// Where a search for a collision gave way to what is not an action of
    /// the session (a change of pace, the program continued after a
    /// stop): say so now, as the world takes that.
    pub(crate) fn say_stopped_search(&mut self) {
        if let Some((searched, began)) = self.stopped_search.take() {
            self.message = Some(format!(
                "a newer key stopped the search for a collision {}",
                back_from_search(searched, began)
            ));
        }
    }

    /// [`Session::apply_unless`], but for the word on a stopped search.
    fn carry_out(&mut self, action: Action, interrupted: &dyn Fn() -> bool) {
        match action {
            Action::StepForward => {
                if !self.try_step(interrupted) {
                    return;
                }
                self.note_selected_collision();
            }
            Action::StepBack => {
                self.step_back();
                self.note_selected_collision();
            }
            Action::Lesson(lesson) => self.open_lesson(lesson),
            Action::OpenedScene => self.open_opened(),
            Action::NextLesson => self.open(neighbour_lesson(self.lesson, 1, self.has_opened())),
            Action::PreviousLesson => {
                self.open(neighbour_lesson(self.lesson, -1, self.has_opened()))
            }
            Action::WallRestitutionDown => self.nudge_wall_restitution(-RESTITUTION_STEP),
            Action::WallRestitutionUp => self.nudge_wall_restitution(RESTITUTION_STEP),
            Action::PairRestitutionDown => self.nudge_pair_restitution(-RESTITUTION_STEP),
            Action::PairRestitutionUp => self.nudge_pair_restitution(RESTITUTION_STEP),
            Action::GravityDown => self.move_gravity(false),
            Action::GravityUp => self.move_gravity(true),
            Action::NextIntegrator => {
                let next = self.world.config.integrator.next();
                self.configure(|c| c.integrator = next);
                self.message = Some(match self.world.config.support_idle() {
                    Some(why) => format!("method: {next}; the support pass is idle: {why}"),
                    None => format!("method: {next} (i for the next one)"),
                });
            }
            Action::NextBroadPhase => self.next_broad_phase(),
            Action::HalveDt => self.scale_dt(0.5),
            Action::DoubleDt => self.scale_dt(2.0),
            Action::MoreSpheres => self.resize(true),
            Action::FewerSpheres => self.resize(false),
            Action::Restart => {
                if self.rebuild() {
                    self.message = Some(format!(
                        "restarted: step 0, seed {}, the parameters kept (R: a new seed)",
                        self.scene.seed
                    ));
                }
            }
            Action::Reseed => self.reseed(),
            Action::ToggleGhost => {
                self.show_ghost = !self.show_ghost;
                self.ghost = None;
                // Where there is no exact motion to draw, the ghost says
                // why instead as it starts.
                self.message = Some(if self.show_ghost {
                    "exact ghost on: the exact motion from this step, drawn over the spheres (x hides it)".into()
                } else {
                    "exact ghost off (x shows it)".into()
                });
            }
            Action::ToggleSupport => {
                let on = !self.world.config.support;
                self.configure(|c| c.support = on);
                self.message = Some(match (on, self.world.config.support_idle()) {
                    (false, _) => "support pass off: each contact once, as the lesson does".into(),
                    (true, None) => {
                        "support pass on: resting contacts solved together, so piles carry their weight".into()
                    }
                    (true, Some(why)) => format!("support pass on, but idle: {why}"),
                });
            }
            Action::ToggleSleep => {
                let on = !self.world.config.sleep;
                self.configure(|c| c.sleep = on);
                self.message = Some(match (on, self.world.config.sleeps()) {
                    (false, _) => "sleeping off: every sphere steps".into(),
                    (true, true) => format!(
                        "sleeping on: spheres slower than {} m/s for {} s sleep until disturbed",
                        crate::sim::sleep::SLEEP_SPEED,
                        crate::sim::sleep::TIME_TO_SLEEP
                    ),
                    (true, false) => "sleeping on, but idle: the continuous method".into(),
                });
            }
            Action::ToggleResting => {
                let on = self.world.config.rest_steps > 0.0;
                let steps = if on {
                    0.0
                } else {
                    WorldConfig::default().rest_steps
                };
                self.configure(|c| c.rest_steps = steps);
                let c = &self.world.config;
                let mut message = match (on, c.integrator) {
                    (true, Integrator::ExplicitEuler) => "resting contact off: every impact \
                        follows c_r and e, however slow; explicit Euler's bounces never end"
                        .to_string(),
                    (true, _) => "resting contact off: every impact follows c_r and e, however \
                        slow; this method's wall rule still ends a bounce on the floor"
                        .to_string(),
                    (false, _) => "resting contact on: impacts slower than a step of gravity \
                        keep no normal speed"
                        .to_string(),
                };
                if let (true, Some(why)) = (c.support, c.support_idle()) {
                    message.push_str(&format!("; the support pass is idle: {why}"));
                }
                self.message = Some(message);
            }
            Action::Select(s) => self.pick(s),
            Action::ClearSelection => self.pick(None),
            Action::PickNext => self.pick_by_number(true),
            Action::PickPrevious => self.pick_by_number(false),
            Action::NextCollision => self.run_to_collision(interrupted),
            Action::Quit
            | Action::StopWork
            | Action::Pick { .. }
            | Action::ToggleContacts
            | Action::TogglePanel
            | Action::Suspend
            | Action::Redraw
            | Action::TogglePause
            | Action::PauseToStep
            | Action::Slower
            | Action::Faster
            | Action::ToggleVectors
            | Action::ToggleTrails
            | Action::ToggleFloorGrid
            | Action::ToggleColouring
            | Action::ToggleChart
            | Action::CloseChart
            | Action::Orbit { .. }
            | Action::Zoom(_)
            | Action::View(_)
            | Action::ResetView
            | Action::ToggleHelp
            | Action::CloseHelp
            | Action::ScrollHelp(_)
            | Action::ScrollHelpPage(_)
            | Action::ScrollHelpTo(_) => return,
        }
        self.refresh_ghost();
        self.refresh_grid_tests();
    }

    /// What the view draws of the present state; `trails` asks for the
    /// recent paths of the sampled spheres. `into` is reused when given.
    pub(crate) fn frame(&self, trails: bool, into: Option<Frame>) -> Frame {
        Frame::of(self, trails, into)
    }

    /// The contacts of the step that led to the present state, found
    /// again from the state before it: exact where the step is one
    /// integration and one detection in scene order (the discrete methods
    /// with one sub-step, under `SPATIAL_ORDER_MIN_BODIES` spheres, the
    /// sleepers it woke woken, fallen and met, and the pairs of two
    /// sleepers dropped, as the step did: `sleep::touch`); elsewhere none
    /// are shown. With sleepers and the support pass,
    /// a pair within its margin may have woken them, which the replay does
    /// not see: none are shown either.
    fn find_contacts_again(&mut self) {
        let c = &self.world.config;
        let replayable = c.pair_collisions
            && c.integrator != Integrator::Continuous
            && c.substeps == 1
            && !crate::sim::large::is_large(self.world.bodies.len())
            && self.world.steps > 0;
        let supported = c.support_runs();
        let Some(previous) = self
            .history
            .previous()
            .filter(|p| replayable && !(supported && p.any_asleep()))
        else {
            self.world.forget_contacts();
            return;
        };
        let mut bodies = self.world.bodies.clone();
        bodies.position.copy_from_slice(previous.position);
        bodies.velocity.copy_from_slice(previous.velocity);
        bodies.rest.copy_from_slice(previous.rest);
        let asleep = previous.any_asleep();
        c.integrator.integrate_awake(&mut bodies, c.gravity, c.dt);
        let mut contacts = Vec::new();
        c.broad_phase
            .resolve(bodies.len())
            .find_contacts(&bodies, &mut contacts);
        if asleep {
            let lists = [&mut contacts, &mut Vec::new()];
            let blow = c.resting(c.dt).length() + c.gravity.length() * c.dt;
            let mut work = crate::sim::sleep::SleepWork::default();
            let mut kept = crate::sim::sleeping_pairs::SleepingPairs::default();
            let rule = (c.gravity, c.dt, blow);
            let catch_up = crate::sim::sleep::CatchUp {
                method: c.integrator,
                margin: 0.0,
                grid: None,
            };
            crate::sim::sleep::touch(&mut bodies, lists, &mut kept, rule, catch_up, &mut work);
        }
        self.world.restore_contacts(&contacts);
    }

    fn step_back(&mut self) {
        if self.history.step_back(&mut self.world) {
            self.arrived_back();
        } else if self.world.steps == 0 {
            self.message = Some("this is the start: there is no earlier step".into());
        } else {
            self.message = Some(match self.history.capacity().saturating_sub(1) {
                1 => "no earlier step kept: the history holds the last step".into(),
                back => format!("no earlier step kept: the history holds the last {back} steps"),
            });
        }
    }

    /// Back at an earlier state of the history (the world restored from
    /// it): the step's contacts, impacts and energy are those of that state.
    fn arrived_back(&mut self) {
        self.find_contacts_again();
        let now = self.world.steps;
        self.impacts.retain(|(_, i)| i.steps <= now);
        // Back past the first step noted: this one's impacts too, so
        // that the record runs on without a gap.
        if now + 1 == self.impacts_from && self.noted_impacts_now() {
            self.impacts_from = now;
        }
        self.energy.truncate_after(self.world.steps);
        if self
            .ghost
            .as_ref()
            .is_some_and(|g| g.is_before_anchor(&self.world))
        {
            self.ghost = None;
            self.message = Some("the ghost starts again from this earlier step".into());
        }
    }

    /// Whether the panel compares with the grid's pair tests counted
    /// afresh: always but when the grid ran the last step itself (and the
    /// step's own count stands), or every sphere slept through it.
    pub(crate) fn needs_grid_tests(&self) -> bool {
        let c = &self.world.config;
        let n = self.world.bodies.len();
        if n > 0 && self.world.last.asleep == n {
            return false;
        }
        let running = c.broad_phase.resolve(self.world.bodies.len());
        let measured = self.world.steps > 0 && self.world.last.broad_phase == Some(running);
        c.pair_collisions
            && (c.integrator == Integrator::Continuous || running != BroadPhase::Grid || !measured)
    }

    /// Count the grid's pair tests over the present spheres if the panel
    /// needs them and they were not counted for this step yet: at most
    /// once a step.
    pub(crate) fn refresh_grid_tests(&mut self) {
        let key = GridTestsKey::of(&self.world);
        if !self.needs_grid_tests() || self.grid_tests.is_some_and(|(k, _)| k == key) {
            return;
        }
        let tests = BroadPhase::Grid.find_contacts(&self.world.bodies, &mut Vec::new());
        self.grid_tests = Some((key, tests));
    }

    /// The grid's pair tests over the present spheres, if counted.
    pub(crate) fn grid_tests(&self) -> Option<u64> {
        let key = GridTestsKey::of(&self.world);
        self.grid_tests.filter(|(k, _)| *k == key).map(|(_, t)| t)
    }

    /// Anchor the ghost if it is on and has no anchor, and bring it to the
    /// world's present time.
    pub(crate) fn refresh_ghost(&mut self) {
        if !self.show_ghost {
            self.ghost = None;
            return;
        }
        if self.ghost.is_none() {
            match Ghost::anchor(&self.world) {
                Ok(g) => self.ghost = Some(g),
                Err(why) => {
                    self.show_ghost = false;
                    self.message = Some(why);
                    return;
                }
            }
        }
        if let Some(g) = &mut self.ghost {
            let (was_shown, was_diverged) = (g.unavailable.is_none(), g.diverged());
            g.update(&self.world);
            let news = if let (true, Some(why)) = (was_shown, g.unavailable) {
                Some(why.message())
            } else if !was_diverged && g.diverged() {
                Some(g.divergence())
            } else {
                None
            };
            // After what the step's action said (o's collision), not in
            // its place.
            if let Some(news) = news {
                self.message = Some(match self.message.take() {
                    Some(said) => format!("{said}; {news}"),
                    None => news,
                });
            }
        }
    }

    /// The physics changed under the ghost: anchor it again here.
    /// After a parameter changed (and said so in the message): the ghost,
    /// if shown, starts again from here.
    fn restart_ghost(&mut self) {
        if self.show_ghost && self.ghost.take().is_some() {
            self.message = Some(match self.message.take() {
                Some(changed) => format!("{changed}; the ghost starts again from here"),
                None => "the ghost starts again from here, with the new parameters".into(),
            });
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
        self.message = Some(if !self.world.config.pair_collisions {
            format!(
                "broad phase {}: this scene has no sphere-sphere collisions to test",
                next.name()
            )
        } else if too_many {
            format!(
                "broad phase {}: all-pairs would test {} pairs a step (at most {})",
                next.name(),
                thousands(all_pairs_tests(n)),
                spheres(MAX_SPHERES_ALL_PAIRS)
            )
        } else {
            format!(
                "broad phase {} (from the next step)",
                broad_phase_name(next, n)
            )
        });
    }

    fn open_lesson(&mut self, lesson: Lesson) {
        let again = self.lesson == Some(lesson);
        self.open_scene(Arc::new(lesson.scene()), Some(lesson));
        // The same lesson's key starts it afresh, with its own parameters:
        // say so, as what was changed is gone.
        if again && self.message.is_none() {
            self.message = Some(format!(
                "the {} lesson from the start, with its own parameters (r restarts keeping \
                 the ones changed)",
                lesson.name()
            ));
        }
    }

    /// The scene opened from a file at the start, with its own parameters.
    fn open_opened(&mut self) {
        match self.opened.clone() {
            Some(opened) => self.open_scene(opened, None),
            None => self.message = Some("no scene file was opened".into()),
        }
    }

    /// A lesson (`Some`), or the scene opened from a file.
    fn open(&mut self, shown: Option<Lesson>) {
        match shown {
            Some(lesson) => self.open_lesson(lesson),
            None => self.open_opened(),
        }
    }

    /// Whether a scene was opened from a file: Tab and Shift-Tab reach it.
    pub(crate) fn has_opened(&self) -> bool {
        self.opened.is_some()
    }

    fn open_scene(&mut self, scene: Arc<Scene>, lesson: Option<Lesson>) {
        self.selection = None;
        self.following = None;
        self.found = None;
        self.show_ghost = false;
        self.scene = scene;
        self.base = Arc::clone(&self.scene);
        self.lesson_gravity = self.scene.world.gravity;
        self.lesson = lesson;
        self.rebuild();
    }

    /// Build the scene afresh: step 0, an empty history.
    /// Whether it built (else the message says why).
    fn rebuild(&mut self) -> bool {
        match self.scene.build() {
            Ok(world) => {
                self.show(world);
                true
            }
            Err(e) => {
                self.message = Some(e.message);
                false
            }
        }
    }

    /// Build the scene with the next seed; keep the seed only if it builds.
    fn reseed(&mut self) {
        if self.scene.spawns.is_empty() {
            // No spawn draws from the seed: a restart, the seed kept.
            if self.rebuild() {
                self.message = Some("restarted (this scene places no random spheres)".into());
            }
            return;
        }
        let mut scene = (*self.scene).clone();
        scene.seed = scene.seed.wrapping_add(1);
        match scene.build() {
            Ok(world) => {
                self.scene = Arc::new(scene);
                self.show(world);
                self.message = Some(format!("new seed {}", self.scene.seed));
            }
            Err(e) => {
                self.message = Some(format!("seed {}: {}", scene.seed, e.message));
            }
        }
    }

    /// Show `world` from its start: an empty history and energy log.
    pub(crate) fn show(&mut self, world: World) {
        self.impacts.clear();
        self.impacts_from = world.steps;
        if let Some(s) = self.selection.filter(|&s| !selection::exists(&world, s)) {
            self.selection = None;
            self.message = Some(format!(
                "the selection ({}) is gone: the scene now has {}",
                s.ids()
                    .iter()
                    .map(|id| format!("sphere {id}"))
                    .collect::<Vec<_>>()
                    .join(" and "),
                spheres(world.bodies.len())
            ));
        }
        self.ghost = None;
        self.grid_tests = None;
        self.history = History::new(&world);
        self.energy = EnergyLog::new(&world);
        self.speed_scale = speed_scale(&world);
        self.world = world;
        self.worlds += 1;
        self.note_capacity();
    }

    fn note_capacity(&mut self) {
        if self.history.capacity() < super::history::STEPS {
            let count = spheres(self.world.bodies.len());
            let back = steps_back(self.history.capacity());
            self.message = Some(format!("{count}: step back reaches {back} (memory budget)"));
        }
    }

    /// Change the live config and the scene's alike.
    fn configure(&mut self, change: impl Fn(&mut WorldConfig)) {
        change(&mut self.world.config);
        change(&mut Arc::make_mut(&mut self.scene).world);
    }

    fn nudge_wall_restitution(&mut self, d: f64) {
        let now = self.world.config.wall_coefficient();
        let c = step_restitution(now, d);
        if c == now && self.world.config.wall_mode == WallMode::Restitution {
            self.message = Some(format!("c_r is already {c:.2}"));
            return;
        }
        let was = match self.world.config.wall_mode {
            WallMode::Restitution => format!("was {now:.2}"),
            WallMode::Flip => "the walls flipped the velocity: c_r = 1".to_string(),
        };
        self.configure(|w| {
            w.wall_mode = WallMode::Restitution;
            w.wall_restitution = c;
        });
        self.message = Some(format!(
            "wall restitution c_r = {c:.2} from the next step on ({was})"
        ));
        self.restart_ghost();
    }

    fn nudge_pair_restitution(&mut self, d: f64) {
        let e = step_restitution(self.world.config.pair_restitution, d);
        if e == self.world.config.pair_restitution {
            self.message = Some(format!("e is already {e:.2}"));
            return;
        }
        let was = self.world.config.pair_restitution;
        self.configure(|w| w.pair_restitution = e);
        if self.world.config.pair_collisions {
            self.message = Some(format!(
                "pair restitution e = {e:.2} from the next step on (was {was:.2})"
            ));
            self.restart_ghost();
        } else {
            self.message = Some(format!(
                "pair restitution e = {e:.2}; this scene has no sphere-sphere collisions"
            ));
        }
    }

    fn move_gravity(&mut self, up: bool) {
        let g = next_gravity(self.gravity(), up);
        if g == self.gravity() {
            self.message = Some(if g > GRAVITY_MAX {
                format!(
                    "gravity stays {g:.2} m/s^2: G goes no higher than {GRAVITY_MAX} \
                     (g lowers it)"
                )
            } else {
                format!("gravity is already {g:.2} m/s^2 (g and G stay within 0 and {GRAVITY_MAX})")
            });
            return;
        }
        let was = self.gravity();
        // Along the gravity there is, or, from none, the lesson's own.
        let now = self.world.config.gravity;
        let toward = if now == Vec3::ZERO {
            self.lesson_gravity
        } else {
            now
        };
        let total = self.world.diagnostics().total_energy;
        self.configure(|w| w.gravity = gravity_along(g, toward));
        self.energy.record_again(&self.world);
        // The motion changes from the next step, but the potential energy
        // of the state shown, m g h, changes at once: said, as the step's
        // total moves with it.
        let now = self.world.diagnostics().total_energy;
        let energy = if format_energy(total) == format_energy(now) {
            String::new()
        } else {
            format!(
                "; PE = m g h now with it: total {} -> {}",
                format_energy(total),
                format_energy(now)
            )
        };
        self.message = Some(format!(
            "gravity {g:.2} m/s^2 from the next step on (was {was:.2}){energy}"
        ));
        self.restart_ghost();
        self.speed_scale = self.speed_scale.max(speed_scale(&self.world));
    }

    /// Scale dt by `factor`, into the keys' range: a dt set outside it
    /// (`--dt 1`) comes to its nearer end, and stays there.
    fn scale_dt(&mut self, factor: f64) {
        let now = self.world.config.dt;
        let dt = (now * factor).clamp(DT_MIN, DT_MAX);
        let toward = (dt - now) * (factor - 1.0) > 0.0;
        match rules::dt(dt) {
            Ok(dt) if toward => {
                self.configure(|w| w.dt = dt);
                // Held to the bounds, it is not half or twice what it was.
                let bound = if dt == DT_MAX && now * factor > DT_MAX {
                    ", the largest here,"
                } else if dt == DT_MIN && now * factor < DT_MIN {
                    ", the smallest here,"
                } else {
                    ""
                };
                self.message = Some(format!(
                    "dt = {}{bound} from the next step on (was {})",
                    format_dt(dt),
                    format_dt(now)
                ));
            }
            _ => {
                self.message = Some(format!(
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
        let (now, home) = (self.world.bodies.len(), self.base.body_count());
        let target = if more {
            next_count(now, true, home).min(MAX_SPHERES).max(now)
        } else {
            next_count(now, false, home).max(1)
        };
        if target == now {
            self.message = Some(if more {
                format!(
                    "{} is already the most + makes (it stops at {MAX_SPHERES}; \
                     --particles starts with more)",
                    spheres(now)
                )
            } else {
                "one sphere is the fewest".into()
            });
            return;
        }
        let mut scene = match self.base.with_count(&self.scene, target) {
            Ok(scene) => scene,
            Err(message) => {
                self.message = Some(format!("{}: {message}", spheres(target)));
                return;
            }
        };
        // All-pairs tests n^2 / 2 pairs a step: past its limit the grid
        // takes over, and says so.
        let w = &mut scene.world;
        let switched = w.pair_collisions
            && w.broad_phase == BroadPhase::AllPairs
            && target > MAX_SPHERES_ALL_PAIRS;
        if switched {
            w.broad_phase = BroadPhase::Auto;
        }
        let on_grid = w.pair_collisions && w.broad_phase.resolve(target) == BroadPhase::Grid;
        let r = scene.max_radius();
        // Only growing is refused: fewer spheres are always a way out.
        if more && on_grid && grid_too_slow(target, r) {
            self.message = Some(format!(
                "{}: the grid would test about {} pairs a step, its cells sized by the \
                 largest sphere (radius {} m)",
                spheres(target),
                thousands(grid_tests(target, r)),
                format_significant(r)
            ));
            return;
        }
        match scene.build() {
            Ok(world) => {
                self.scene = Arc::new(scene);
                self.show(world);
                if self.message.is_none() {
                    self.message = Some(if switched {
                        format!(
                            "{}: broad phase auto (all-pairs tests at most {}; b switches)",
                            spheres(target),
                            thousands(MAX_SPHERES_ALL_PAIRS as u64)
                        )
                    } else {
                        format!(
                            "{}, sized to keep the lesson's solid fraction",
                            spheres(target)
                        )
                    });
                }
            }
            Err(e) => {
                self.message = Some(format!("{}: {}", spheres(target), e.message));
            }
        }
    }
}

/// What `d` places after `shown` (a lesson, or `None`: the scene opened
/// from a file) in the cycle of Tab: the scene opened, if `opened`, then
/// [`Lesson::ALL`], wrapping.
pub(crate) fn neighbour_lesson(shown: Option<Lesson>, d: isize, opened: bool) -> Option<Lesson> {
    let cycle: Vec<Option<Lesson>> = opened
        .then_some(None)
        .into_iter()
        .chain(Lesson::ALL.iter().copied().map(Some))
        .collect();
    let n = cycle.len() as isize;
    match cycle.iter().position(|&x| x == shown) {
        Some(i) => cycle[(i as isize + d).rem_euclid(n) as usize],
        None if d > 0 => Some(Lesson::ALL[0]),
        None => Some(Lesson::ALL[Lesson::ALL.len() - 1]),
    }
}

/// `c + d` rounded to hundredths and clamped to [0, 1].
pub(crate) fn step_restitution(c: f64, d: f64) -> f64 {
    let v = ((c + d) * 100.0).round() / 100.0;
    rules::restitution(v.clamp(0.0, 1.0)).unwrap_or(c)
}

/// The next rung of [`GRAVITY_LADDER`] above or below `g`; above the
/// ladder (a scene's or flag's gravity), up leaves `g` as it is.
pub(crate) fn next_gravity(g: f64, up: bool) -> f64 {
    let eps = 1e-9;
    let rungs = GRAVITY_LADDER.iter().map(|&(v, _)| v);
    let next = if up {
        rungs.clone().find(|&v| v > g + eps)
    } else {
        rungs.clone().rev().find(|&v| v < g - eps)
    };
    match next {
        Some(v) => v.clamp(0.0, GRAVITY_MAX),
        None if up => g,
        None => 0.0,
    }
}

/// The name of a gravity magnitude, if it is a known body's.
pub(crate) fn gravity_name(g: f64) -> &'static str {
    GRAVITY_LADDER
        .iter()
        .find(|&&(v, _)| (v - g).abs() < 1e-9)
        .map_or("", |&(_, n)| n)
}

/// The next count above or below `n` on the 1-2-5 ladder with the scene's
/// own count `home` on it, so that `+` then `-` comes back to the scene.
pub(crate) fn next_count(n: usize, up: bool, home: usize) -> usize {
    let mut rungs = vec![home];
    let mut p = 1usize;
    while p <= MAX_SPHERES * 10 {
        rungs.extend([p, 2 * p, 5 * p]);
        p *= 10;
    }
    rungs.sort_unstable();
    if up {
        rungs.into_iter().find(|&r| r > n).unwrap_or(n)
    } else {
        rungs.into_iter().rev().find(|&r| r < n).unwrap_or(1)
    }
}

/// The colour scale's top speed: the fastest a sphere could go by falling
/// to the floor from where it is, rounded up to 1, 2 or 5 times a power
/// of ten.
pub(crate) fn speed_scale(world: &World) -> f64 {
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

/// How far a stopped search for a collision had got, and where it went
/// back to.
fn back_from_search(searched: u64, began: u64) -> String {
    format!(
        "after {searched} step{}: back at step {began}, where it began",
        if searched == 1 { "" } else { "s" }
    )
}

/// The steps a history of `capacity` snapshots reaches back: it keeps the
/// present state and at least one before.
fn steps_back(capacity: usize) -> String {
    match capacity.saturating_sub(1) {
        1 => "1 step".to_string(),
        back => format!("{back} steps"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Vec3;

    /// The collisions lesson's world holding only `bodies` (position and
    /// velocity), each 5 cm in radius and 1 kg.
    fn balls(bodies: &[(Vec3, Vec3)]) -> Scene {
        let mut scene = Lesson::Collisions.scene();
        scene.spawns.clear();
        scene.spawn_lines.clear();
        scene.bodies = bodies
            .iter()
            .map(|&(position, velocity)| crate::sim::Body {
                position,
                velocity,
                radius: 0.05,
                mass: 1.0,
            })
            .collect();
        scene
    }

    #[test]
    fn with_the_support_pass_o_skips_resting_pairs_for_the_next_impact() {
        // Sphere 1 rests on sphere 0 on the floor; sphere 2 falls onto
        // sphere 1 at 2 m/s. The resting pair is in contact every step, and
        // first in the solver's order, but the support pass holds it: the
        // collision is the falling sphere's.
        let sphere = |y: f64, vy: f64| (Vec3::new(0.5, y, 0.5), Vec3::new(0.0, vy, 0.0));
        let mut scene = balls(&[sphere(0.05, 0.0), sphere(0.1499, 0.0), sphere(0.6, -2.0)]);
        scene.world.support = true;
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::NextCollision);
        let message = s.take_message();
        assert_eq!(s.selection, Some(Selection::Pair(1, 2)), "{message:?}");
        // The footer says what became of the resting pair.
        assert!(
            message
                .as_deref()
                .is_some_and(|m| m.contains("; 1 more contact rested on the support pass)")),
            "{message:?}"
        );
        // Closed form: the gap of 0.3501 m closes under 2 m/s and gravity,
        // and the step that ends first after it finds the contact.
        let (t, dt, g) = (s.world.time, s.world.config.dt, STANDARD_GRAVITY);
        let meet = (-2.0 + (4.0 + 2.0 * g * 0.3501_f64).sqrt()) / g;
        assert!(
            t >= meet - 1e-4 && t <= meet + dt + 1e-4,
            "met at {t} s, not {meet} s"
        );
    }

    /// The collisions lesson without gravity or its spawns: spheres of
    /// radius 0.05 m and 1 kg at `(x, 0.5, z)` moving at `vx` along x, one
    /// for each `(x, z, vx)`.
    fn along_x(spheres: &[(f64, f64, f64)]) -> Scene {
        let bodies: Vec<_> = spheres
            .iter()
            .map(|&(x, z, vx)| (Vec3::new(x, 0.5, z), Vec3::new(vx, 0.0, 0.0)))
            .collect();
        let mut scene = balls(&bodies);
        scene.world.gravity = Vec3::ZERO;
        scene
    }

    /// Two head-on pairs without gravity, mirror images in z, which meet in
    /// the same step.
    fn two_head_on_pairs() -> Scene {
        along_x(&[
            (0.3, 0.2, 1.0),
            (0.5, 0.2, -1.0),
            (0.3, 0.8, 1.0),
            (0.5, 0.8, -1.0),
        ])
    }

    /// [`two_head_on_pairs`] after the first `o`: paused on the first pair.
    fn at_two_head_on_collisions() -> Session {
        let mut s = Session::new(two_head_on_pairs(), None).unwrap();
        s.apply(Action::NextCollision);
        s
    }

    #[test]
    fn a_search_says_where_overlapping_spheres_were_only_pushed_apart() {
        // Two spheres at rest, 50 mm into each other: the first step's
        // contact pushes them apart (the lesson's correction) but they do
        // not approach, so there is no collision to stop on; the message
        // says what the step did. Apart, they do not touch again.
        let scene = along_x(&[(0.5, 0.5, 0.0), (0.55, 0.5, 0.0)]);
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(
            said,
            "no collision between spheres in the next 10 s of simulated time: back at step 0 \
             (in 1 of those steps overlapping spheres were only pushed apart, not approaching: \
             d marks contacts)"
        );
        // A stack of two held by the support pass: its pair closes slowly
        // every step, left resting to the pass, and is not said to be
        // pushed apart.
        let mut scene = balls(&[0.05, 0.1502].map(|y| (Vec3::new(0.5, y, 0.5), Vec3::ZERO)));
        scene.world.support = true;
        let mut s = Session::new(scene, None).unwrap();
        for _ in 0..180 {
            s.apply(Action::StepForward);
        }
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(
            said,
            "no collision between spheres in the next 10 s of simulated time: back at step 180"
        );
    }

    #[test]
    fn a_search_that_finds_no_collision_goes_back_to_where_it_began() {
        // Two spheres running side by side between the walls never meet:
        // o searches 10 s, says so, and leaves the world as it was, with
        // the steps before still there to go back to. It had left the
        // world 10 s on, past the history's reach (the first dt keeps
        // every step of the search in the history, the others do not).
        for dt in [1.0 / 30.0, 1.0 / 60.0, 1.0 / 240.0] {
            let mut scene = along_x(&[(0.3, 0.2, 1.0), (0.3, 0.8, 1.0)]);
            scene.world.dt = dt;
            let mut s = Session::new(scene, None).unwrap();
            for _ in 0..5 {
                s.apply(Action::StepForward);
            }
            let before = (s.world.bodies.clone(), s.world.time, s.energy.len());
            s.apply(Action::NextCollision);
            let said = s.take_message().unwrap();
            assert_eq!(
                said,
                "no collision between spheres in the next 10 s of simulated time: back at step 5"
            );
            assert_eq!(s.world.steps, 5, "dt {dt}");
            assert_eq!(
                (s.world.bodies.clone(), s.world.time, s.energy.len()),
                before,
                "dt {dt}"
            );
            assert_eq!(s.history.steps_back(), 5, "dt {dt}");
            s.apply(Action::StepBack);
            assert_eq!(s.world.steps, 4, "dt {dt}");
        }
    }

    #[test]
    fn a_search_that_gives_way_to_a_newer_key_goes_back_to_where_it_began() {
        // The spheres that never meet: a newer key arriving during the
        // 40th step of the search stops it, and the world is the one the
        // search began from, so the key acts from there (`n`: one step).
        let mut s = Session::new(along_x(&[(0.3, 0.2, 1.0), (0.3, 0.8, 1.0)]), None).unwrap();
        for _ in 0..5 {
            s.apply(Action::StepForward);
        }
        let before = (s.world.bodies.clone(), s.world.time, s.energy.len());
        let asked = std::cell::Cell::new(0);
        // Each step asks a few times; the count at which it gives way is
        // well inside the 40th step's asking.
        let per_step = {
            let mut probe = s.world.clone();
            let counted = std::cell::Cell::new(0);
            assert!(probe.try_step(&|| {
                counted.set(counted.get() + 1);
                false
            }));
            counted.get()
        };
        assert!(per_step > 0);
        s.apply_unless(Action::NextCollision, &|| {
            asked.set(asked.get() + 1);
            asked.get() > 39 * per_step
        });
        assert_eq!(
            (s.world.bodies.clone(), s.world.time, s.energy.len()),
            before
        );
        assert_eq!(s.history.steps_back(), 5);
        // The key that stopped it says so (the search's own message would
        // answer the search, which the key replaced): Esc, Esc with a
        // selection, a key with nothing to say (n: it steps on from there)
        // and one with its own word. The key after has nothing of it to
        // say.
        let back = "after 39 steps: back at step 5, where it began";
        s.apply(Action::StopWork);
        assert_eq!(
            s.take_message(),
            Some(format!("Esc stopped the search for a collision {back}"))
        );
        s.apply(Action::StopWork);
        assert_eq!(s.take_message(), None);
        s.apply(Action::StepForward);
        assert_eq!(s.world.steps, 6);
        // A change of pace (Space, < or >) is not an action of the session.
        s.stopped_search = Some((1, 5));
        s.say_stopped_search();
        assert_eq!(
            s.take_message().as_deref(),
            Some(
                "a newer key stopped the search for a collision after 1 step: back at step 5, \
                 where it began"
            )
        );
        s.say_stopped_search();
        assert_eq!(s.take_message(), None);
        for (key, said) in [
            (
                Action::ClearSelection,
                format!("Esc stopped the search for a collision {back}, and forgot the selection"),
            ),
            (
                Action::StepForward,
                format!("this key stopped the search for a collision {back}"),
            ),
            (
                Action::WallRestitutionUp,
                format!("the search for a collision stopped {back}; wall restitution c_r = "),
            ),
        ] {
            s.stopped_search = Some((39, 5));
            s.apply(key);
            let message = s.take_message().unwrap();
            assert!(message.starts_with(&said), "{message}");
        }
    }

    #[test]
    fn o_stops_where_a_sphere_lands_on_another_that_the_support_pass_holds() {
        // The upper sphere, 1 mm above the lower one on the floor, lands
        // at 0.12 m/s, slower than the resting speed: the lesson's pass
        // leaves the pair to the support pass, which holds it. No impulse,
        // but a landing: o stops there, and the pair says why it has no
        // V1 and V2. Without the pass the lesson's pass strikes it (e = 0).
        for support in [true, false] {
            let body = |y: f64, vy: f64| (Vec3::new(0.5, y, 0.5), Vec3::new(0.0, vy, 0.0));
            let mut scene = balls(&[body(0.05, 0.0), body(0.151, -0.12)]);
            scene.world.support = support;
            scene.world.dt = 1.0 / 60.0;
            let mut s = Session::new(scene, None).unwrap();
            s.apply(Action::NextCollision);
            assert_eq!(s.world.steps, 1, "support {support}");
            assert_eq!(s.selection, Some(Selection::pair(0, 1)));
            let inspection = s.inspection().expect("the pair");
            if support {
                assert_eq!(inspection.pair, None);
                let note = inspection.pair_note.expect("why no V1 and V2");
                assert!(
                    note.starts_with("resting contact: closing at 0.120 m/s"),
                    "{note}"
                );
            } else {
                let pair = inspection.pair.expect("the lesson's numbers");
                assert_eq!(pair.e, 0.0, "resting contact");
            }
            // Held at rest on each other, the pair meets no more (without
            // the pass, the lesson's pass strikes it again every step).
            if support {
                s.apply(Action::NextCollision);
                let said = s.take_message().unwrap();
                assert!(
                    said.starts_with("no collision between spheres in the next 10 s"),
                    "{said}"
                );
            }
        }
    }

    #[test]
    fn o_stops_where_a_sphere_dropped_from_rest_lands_and_the_support_pass_catches_it() {
        // Dropped from rest 2 mm above the lower sphere (1 mm for the
        // second), within the support pass's margin after the step's
        // fall, the upper one closes slower than the resting speed: the
        // pass takes the pair while still apart and brings it to rest in
        // that step. The pair never overlaps after integration; o stops
        // where it lands all the same, and the pair says why it has no V1
        // and V2.
        for drop in [2e-3, 1e-3] {
            let body = |y: f64| (Vec3::new(0.5, y, 0.5), Vec3::ZERO);
            let mut scene = balls(&[body(0.05), body(0.15 + drop)]);
            scene.world.support = true;
            scene.world.dt = 1.0 / 60.0;
            let mut s = Session::new(scene, None).unwrap();
            s.apply(Action::NextCollision);
            let said = s.take_message().unwrap_or_default();
            assert_eq!(s.selection, Some(Selection::pair(0, 1)), "{said}");
            assert_eq!(s.world.steps, 1, "{said}");
            assert!(
                said.starts_with(
                    "spheres 0 and 1 land in resting contact, held by the support pass"
                ),
                "{said}"
            );
            assert!(s.world.contacts().is_empty(), "caught apart");
            let note = s.inspection().and_then(|i| i.pair_note).expect("a note");
            assert!(
                note.starts_with("landed: apart when the step began"),
                "{note}"
            );
            let b = &s.world.bodies;
            let gap = b.position[0].distance(b.position[1]) - 0.1;
            assert!(gap.abs() < 5e-4, "at rest on it: {gap}");
            s.apply(Action::NextCollision);
            let said = s.take_message().unwrap();
            assert!(said.starts_with("no collision between spheres"), "{said}");
        }
    }

    #[test]
    fn a_pair_the_support_pass_leaves_to_the_lessons_rules_has_not_landed() {
        // Sliding on the floor at 0.6 m/s, faster than the resting speed
        // (2 g dt = 0.33 m/s at dt = 1/60 s), the left sphere ends its
        // first step 0.2 mm from the right one: within the support pass's
        // margin and a hundredth of a radius, but the pass leaves an
        // approach that fast to the lesson's rules, and the pair is still
        // closing. o passes over that step to the impact in the next.
        let body = |x: f64, v: f64| (Vec3::new(x, 0.05, 0.5), Vec3::new(v, 0.0, 0.0));
        let mut scene = balls(&[body(0.3, 0.6), body(0.4102, 0.0)]);
        scene.world.support = true;
        scene.world.dt = 1.0 / 60.0;
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::StepForward);
        let b = &s.world.bodies;
        let gap = b.position[1].x - b.position[0].x - 0.1;
        assert!(gap > 0.0 && gap < 5e-4, "within touching, apart: {gap}");
        assert_eq!(b.velocity[0].x, 0.6, "still closing");
        assert!(s.world.near_pairs().len() == 1, "within the margin");
        s.apply(Action::Select(Some(Selection::pair(0, 1))));
        let note = s.inspection().and_then(|i| i.pair_note).expect("a note");
        assert_eq!(note, "not in contact at this step");
        s.apply(Action::Restart);
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap_or_default();
        assert_eq!(s.world.steps, 2, "{said}");
        assert_eq!(s.selection, Some(Selection::pair(0, 1)), "{said}");
        let pair = s
            .inspection()
            .and_then(|i| i.pair)
            .expect("the lesson's V1 and V2");
        assert!(pair.e > 0.0, "an impact, not resting contact: {pair:?}");
    }

    #[test]
    fn o_following_a_sphere_counts_that_sphere_s_collisions_in_the_step() {
        // Two pairs meet in the same step. With sphere 3 followed, o stops
        // on its pair, and the footer counts sphere 3's collisions of the
        // step (one), not the step's (two); o alone counts the step's.
        let mut any = at_two_head_on_collisions();
        let said = any.take_message().unwrap();
        assert!(said.contains(", collision 1 of 2)"), "{said}");
        let mut s = Session::new((*any.scene).clone(), None).unwrap();
        s.apply(Action::Select(Some(Selection::Sphere(3))));
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Pair(2, 3)), "{said}");
        assert_eq!(s.world.steps, any.world.steps, "{said}");
        assert!(
            said.starts_with("sphere 3's next: spheres 2 and 3 collide") && !said.contains(" of 2"),
            "{said}"
        );
        // A sphere at rest struck from both sides in one step: its two
        // collisions, one after the other.
        let scene = along_x(&[(0.3, 0.5, 1.0), (0.5, 0.5, 0.0), (0.7, 0.5, -1.0)]);
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::Select(Some(Selection::Sphere(1))));
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert!(said.contains(", its collision 1 of 2)"), "{said}");
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert!(said.contains(", its collision 2 of 2)"), "{said}");
    }

    /// `o` on `scene` with nothing picked, which must stop on pair (0, 1),
    /// and with sphere 3 picked, which must stop on pair (2, 3), and what
    /// the second said.
    fn o_alone_and_following_sphere_3(scene: Scene) -> (Session, Session, String) {
        let mut any = Session::new(scene.clone(), None).unwrap();
        any.apply(Action::NextCollision);
        assert_eq!(any.selection, Some(Selection::Pair(0, 1)));
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::Select(Some(Selection::Sphere(3))));
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Pair(2, 3)), "{said}");
        (any, s, said)
    }

    #[test]
    fn o_following_a_sphere_finds_its_collisions_where_the_step_is_not_replayed() {
        // With two projection passes (as with 4,096 spheres or more) the
        // step is not replayed pair by pair, and only its first contact
        // is known to be a collision: pair (0, 1). A followed sphere of
        // the other pair, meeting in the same step, is found by the push
        // its contact gave it.
        let mut scene = two_head_on_pairs();
        scene.world.projection_passes = 2;
        let (any, s, said) = o_alone_and_following_sphere_3(scene);
        assert_eq!(s.world.steps, any.world.steps, "{said}");
        assert!(
            said.starts_with("sphere 3's next: spheres 2 and 3 collide"),
            "{said}"
        );
    }

    #[test]
    fn o_follows_the_picked_sphere_through_its_collisions() {
        // Pair (0, 1) meets first, pair (2, 3) later. With sphere 3 picked,
        // o passes over the first pair's collision to sphere 3's, and
        // pressed again (the pair selected) to sphere 3's next one, after
        // the walls sent the pair back: never to the other pair's.
        let scene = along_x(&[
            (0.3, 0.2, 1.0),
            (0.5, 0.2, -1.0),
            (0.1, 0.8, 1.0),
            (0.7, 0.8, -1.0),
        ]);
        let (first, mut s, said) = o_alone_and_following_sphere_3(scene);
        assert!(s.world.steps > first.world.steps, "{said}");
        assert!(
            said.starts_with("sphere 3's next: spheres 2 and 3 collide"),
            "{said}"
        );
        // Pressed again, sphere 3's next is the far x wall the pair sent it
        // to, then the pair once more.
        let met = s.world.steps;
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Sphere(3)), "{said}");
        assert!(s.world.steps > met + 1, "{said}");
        assert!(
            said.starts_with("sphere 3's next: sphere 3 meets the x = 1 wall"),
            "{said}"
        );
        assert!(s.world.bodies.velocity[3].x < 0.0, "{said}");
        let walled = s.world.steps;
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Pair(2, 3)), "{said}");
        assert!(s.world.steps > walled + 1, "{said}");
        // Cleared, o takes any collision again.
        s.apply(Action::ClearSelection);
        s.apply(Action::NextCollision);
        assert!(!s.take_message().unwrap().starts_with("sphere "));

        // A picked sphere that meets none (at rest, with no gravity): said,
        // and back where it began.
        let alone = along_x(&[(0.3, 0.2, 0.0), (0.3, 0.8, 1.0), (0.6, 0.8, 1.0)]);
        let mut s = Session::new(alone, None).unwrap();
        s.apply(Action::Select(Some(Selection::Sphere(0))));
        s.apply(Action::NextCollision);
        assert_eq!(
            s.take_message().unwrap(),
            "no collision of sphere 0 with another sphere or a wall in the next 10 s of \
             simulated time: back at step 0"
        );
        assert_eq!(s.world.steps, 0);

        // With a dt finer than the keys reach, the search takes at most
        // the steps of 10 s at the finest they reach, and says how far
        // that looked.
        let mut fine = along_x(&[(0.3, 0.2, 0.0), (0.6, 0.8, 0.0)]);
        fine.world.dt = 1e-7;
        let mut s = Session::new(fine, None).unwrap();
        s.apply(Action::NextCollision);
        assert_eq!(
            s.take_message().unwrap(),
            "no collision between spheres in the next 76,800 steps (0.007680 s of simulated \
             time, at dt = 1/10000000 s (1.000e-4 ms)): back at step 0"
        );
        assert_eq!(s.world.steps, 0);
        // Just finer than the keys reach, 76,800 steps are 9.6 s; at the
        // finest they reach, 10 s.
        for (dt, ahead) in [
            (
                1.0 / 8000.0,
                "76,800 steps (9.600 s of simulated time, at dt = 1/8000 s (0.125 ms))",
            ),
            (DT_MIN, "10 s of simulated time"),
        ] {
            let mut fine = along_x(&[(0.3, 0.2, 0.0), (0.6, 0.8, 0.0)]);
            fine.world.dt = dt;
            let mut s = Session::new(fine, None).unwrap();
            s.apply(Action::NextCollision);
            assert_eq!(
                s.take_message().unwrap(),
                format!("no collision between spheres in the next {ahead}: back at step 0")
            );
        }
    }

    #[test]
    fn braces_pick_the_spheres_by_number_round_the_scene() {
        let mut s = Session::new(
            along_x(&[(0.2, 0.5, 0.0), (0.5, 0.5, 0.0), (0.8, 0.5, 0.0)]),
            None,
        )
        .unwrap();
        let picked = |s: &mut Session, action| {
            s.apply(action);
            s.selection
        };
        assert_eq!(picked(&mut s, Action::PickNext), Some(Selection::Sphere(0)));
        assert_eq!(
            s.take_message().unwrap(),
            "picked sphere 0 (of 0 to 2): { and } step through them, o runs to its next collision"
        );
        assert_eq!(picked(&mut s, Action::PickNext), Some(Selection::Sphere(1)));
        assert_eq!(picked(&mut s, Action::PickNext), Some(Selection::Sphere(2)));
        assert_eq!(picked(&mut s, Action::PickNext), Some(Selection::Sphere(0)));
        assert_eq!(
            picked(&mut s, Action::PickPrevious),
            Some(Selection::Sphere(2))
        );
        s.apply(Action::ClearSelection);
        assert_eq!(
            picked(&mut s, Action::PickPrevious),
            Some(Selection::Sphere(2))
        );
        // Of a pair, } picks its first sphere and { its second: the one o
        // then follows.
        s.apply(Action::Select(Some(Selection::Pair(0, 2))));
        assert_eq!(picked(&mut s, Action::PickNext), Some(Selection::Sphere(0)));
        s.apply(Action::Select(Some(Selection::Pair(0, 2))));
        assert_eq!(
            picked(&mut s, Action::PickPrevious),
            Some(Selection::Sphere(2))
        );
    }

    #[test]
    fn a_pair_that_reverses_a_sphere_beside_a_wall_is_not_a_wall_collision() {
        // Sphere 0, 2 mm from the z = 0 wall and drifting toward it, is
        // struck from the side and a little below by sphere 1, which turns
        // its z velocity round, in the step in which sphere 2 meets the
        // x = 1 wall. Followed by o, sphere 0's next is that pair, and then
        // not "sphere 0 meets the z = 0 wall" in the same step: it never
        // reached it.
        let mut scene = along_x(&[]);
        let body = |p: [f64; 3], v: [f64; 3], radius: f64| crate::sim::Body {
            position: Vec3::from_array(p),
            velocity: Vec3::from_array(v),
            radius,
            mass: 1.0,
        };
        scene.bodies = vec![
            body([0.5, 0.5, 0.0505], [0.0, 0.0, -0.01], 0.05),
            body([0.425, 0.5, 0.0335], [1.0, 0.0, 0.0], 0.02),
            body([0.944, 0.2, 0.5], [1.0, 0.0, 0.0], 0.05),
        ];
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::Select(Some(Selection::Sphere(0))));
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Pair(0, 1)), "{said}");
        let met = s.world.steps;
        assert!(
            s.world.last.wall_impacts > 0,
            "sphere 2 meets its wall in step {met}"
        );
        assert!(
            s.world.bodies.velocity[0].z > 0.0,
            "turned round by the pair"
        );
        assert!(
            s.world.bodies.position[0].z - 0.05 > 1e-4,
            "short of the wall"
        );
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert!(s.world.steps > met, "{said}");
        assert!(!said.contains("z = 0 wall"), "{said}");
    }

    #[test]
    fn o_walks_a_step_s_wall_collisions_and_follows_a_sphere_picked_at_walls() {
        // The gravity lesson: spheres meet only walls, and o selects the
        // sphere. Pressed again, o takes the step's next wall collision (a
        // sphere o selected is not a pick to follow).
        let mut s = Session::lesson(Lesson::Gravity);
        let (step, said) = loop {
            s.apply(Action::NextCollision);
            let said = s.take_message().unwrap();
            if !said.contains("collision 1 of") {
                continue;
            }
            break (s.world.steps, said);
        };
        s.apply(Action::NextCollision);
        let next = s.take_message().unwrap();
        assert_eq!(s.world.steps, step, "{said} / {next}");
        assert!(next.contains(", collision 2 of"), "{next}");
        assert!(
            !next.starts_with("sphere ") || !next.contains("'s next"),
            "{next}"
        );
        // A sphere picked: its own next wall collision, said so.
        let Some(Selection::Sphere(a)) = s.selection else {
            panic!("a sphere is selected");
        };
        s.apply(Action::Select(Some(Selection::Sphere(a))));
        s.apply(Action::NextCollision);
        let said = s.take_message().unwrap();
        assert!(
            said.starts_with(&format!("sphere {a}'s next: sphere {a} meets")),
            "{said}"
        );
        assert!(s.world.steps > step, "{said}");
        // Another lesson forgets whom o followed.
        s.apply(Action::Lesson(Lesson::Collisions));
        assert_eq!((s.following, s.found), (None, None));
    }

    #[test]
    fn o_walks_through_every_collision_of_a_step_before_stepping_on() {
        // Two head-on pairs without gravity, mirror images in z: both meet
        // in the same step. The first o stops on the first pair, the second
        // o on the other pair at the same step, the third steps on.
        let mut s = at_two_head_on_collisions();
        let (step, first) = (s.world.steps, s.take_message().unwrap());
        assert_eq!(s.selection, Some(Selection::Pair(0, 1)), "{first}");
        assert!(first.contains(", collision 1 of 2)"), "{first}");
        s.apply(Action::NextCollision);
        let second = s.take_message().unwrap();
        assert_eq!(s.selection, Some(Selection::Pair(2, 3)), "{second}");
        assert_eq!(s.world.steps, step, "{second}");
        assert!(
            second.contains(&format!("(step {step}, collision 2 of 2)")),
            "{second}"
        );
        s.apply(Action::NextCollision);
        assert!(s.world.steps > step, "{:?}", s.take_message());

        // A step that cannot be replayed pair by pair (the continuous
        // method's) gives o its first collision only: o steps on.
        let mut scene = s.base.as_ref().clone();
        scene.world.integrator = Integrator::Continuous;
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::NextCollision);
        let (step, first) = (s.world.steps, s.take_message().unwrap());
        // Met at its own time inside the step: o says which step, and
        // the time the step spans.
        let (t, dt) = (s.world.time, s.world.config.dt);
        assert!(
            first.contains(&format!(
                "within step {step} (t = {:.3} to {t:.3} s): ",
                t - dt
            )),
            "{first}"
        );
        s.apply(Action::NextCollision);
        assert!(s.world.steps > step, "{:?}", s.take_message());
    }

    #[test]
    fn stepping_back_onto_a_collision_says_which_it_is_again() {
        // o finds the first of two collisions of a step; n steps past it
        // (the pair now moves apart: nothing said), and , back says again
        // which collision of the step the picked pair is.
        let mut s = at_two_head_on_collisions();
        let found = s.take_message().unwrap();
        s.apply(Action::StepForward);
        assert_eq!(s.take_message(), None);
        s.apply(Action::StepBack);
        assert_eq!(s.take_message().as_deref(), Some(found.as_str()));
        // A sphere's wall impact, in the ping-pong lesson.
        let mut s = Session::lesson(Lesson::Pingpong);
        s.apply(Action::NextCollision);
        let found = s.take_message().unwrap();
        assert!(found.contains("sphere 0 meets the"), "{found}");
        s.apply(Action::StepForward);
        assert_eq!(s.take_message(), None);
        s.apply(Action::StepBack);
        assert_eq!(s.take_message().as_deref(), Some(found.as_str()));
    }

    #[test]
    fn o_says_which_contacts_of_the_step_took_no_impulse() {
        // Without gravity at dt = 1/60 s: spheres 0 and 1 close 0.05 m at
        // 2 m/s and meet in step 2. In the same step sphere 2, at 9 m/s,
        // lands past the centre of sphere 3: a contact whose spheres move
        // apart along its normal, which takes no impulse.
        let mut scene = along_x(&[
            (0.3, 0.8, 1.0),
            (0.45, 0.8, -1.0),
            (0.21, 0.2, 9.0),
            (0.5, 0.2, 0.0),
        ]);
        scene.world.dt = 1.0 / 60.0;
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::NextCollision);
        let message = s.take_message().unwrap();
        assert_eq!(s.world.steps, 2, "{message}");
        assert_eq!(s.world.contacts().len(), 2, "{message}");
        assert_eq!(s.selection, Some(Selection::Pair(0, 1)), "{message}");
        assert!(
            message.contains("(step 2; 1 more contact took no impulse: not approaching)"),
            "{message}"
        );
    }

    #[test]
    fn step_back_restores_the_exact_earlier_state() {
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::WallRestitutionDown);
        s.apply(Action::PairRestitutionDown);
        let mut hashes = Vec::new();
        let mut bodies = Vec::new();
        for _ in 0..30 {
            hashes.push(s.world.state_hash());
            bodies.push(s.world.bodies.clone());
            s.apply(Action::StepForward);
        }
        for k in (0..30).rev() {
            s.apply(Action::StepBack);
            assert_eq!(s.world.state_hash(), hashes[k], "state hash at step {k}");
            assert_eq!(s.world.bodies, bodies[k], "bodies at step {k}");
        }
        s.apply(Action::StepBack);
        assert_eq!(s.world.steps, 0);
        assert!(s.take_message().unwrap().contains("no earlier step"));
        assert_eq!(s.energy.len(), 1, "the energy log steps back too");
    }

    #[test]
    fn a_step_back_among_sleepers_shows_the_contacts_the_step_had() {
        for support in [false, true] {
            let mut s = Session::lesson(Lesson::Collisions);
            s.apply(Action::ToggleSleep);
            if support {
                s.apply(Action::ToggleSupport);
            }
            s.world.run(60 * 240);
            let n = s.world.bodies.len();
            assert_eq!(s.world.last.asleep, n, "support {support}");
            for _ in 0..3 {
                s.apply(Action::StepForward);
            }
            assert!(
                s.world.contacts().is_empty(),
                "a step asleep has no contacts"
            );
            s.apply(Action::StepBack);
            assert_eq!(s.world.contacts(), &[], "replayed (support {support})");
            assert!(!s.needs_grid_tests(), "nothing to count while all sleep");
        }
    }

    #[test]
    fn restitution_is_clamped_and_turns_flip_walls_into_restitution_walls() {
        let mut s = Session::lesson(Lesson::Pingpong);
        assert_eq!(s.world.config.wall_mode, WallMode::Flip);
        s.apply(Action::WallRestitutionUp);
        assert_eq!(s.world.config.wall_mode, WallMode::Restitution);
        assert_eq!(s.world.config.wall_restitution, 1.0);
        for _ in 0..25 {
            s.apply(Action::WallRestitutionDown);
        }
        assert_eq!(s.world.config.wall_restitution, 0.0);
        s.apply(Action::WallRestitutionUp);
        assert_eq!(s.world.config.wall_restitution, 0.05);
        assert_eq!(s.scene.world.wall_restitution, 0.05, "a restart keeps it");
        for _ in 0..30 {
            s.apply(Action::PairRestitutionUp);
        }
        assert_eq!(s.world.config.pair_restitution, 1.0);
    }

    #[test]
    fn o_says_when_the_pair_it_found_met_in_resting_contact() {
        // Late in the collisions lesson most contacts are resting ones: `o`
        // finds them too, and says so, with the panel's e 0.
        let mut s = Session::lesson(Lesson::Collisions);
        s.world.run(240 * 30);
        let (mut resting, mut impacts) = (0, 0);
        for _ in 0..40 {
            s.apply(Action::NextCollision);
            let message = s.message.take().expect("o says what it found");
            let e = s.inspection().and_then(|i| i.pair).map(|p| p.e);
            if message.contains("meet in resting contact (e = 0)") {
                assert_eq!(e, Some(0.0), "{message}");
                resting += 1;
            } else if message.contains(" collide at t =") {
                assert_eq!(e, Some(0.95), "{message}");
                impacts += 1;
            }
        }
        assert!(
            resting > 0 && impacts > 0,
            "{resting} resting, {impacts} impacts"
        );
    }

    #[test]
    fn a_changed_parameter_says_what_it_was_and_when_it_acts() {
        let mut s = Session::lesson(Lesson::Collisions);
        let said = |s: &mut Session, action| {
            s.apply(action);
            s.message.take().expect("a message")
        };
        assert_eq!(
            said(&mut s, Action::PairRestitutionDown),
            "pair restitution e = 0.90 from the next step on (was 0.95)"
        );
        assert_eq!(
            said(&mut s, Action::WallRestitutionUp),
            "wall restitution c_r = 1.00 from the next step on (was 0.95)"
        );
        assert_eq!(
            said(&mut s, Action::GravityDown),
            "gravity 8.00 m/s^2 from the next step on (was 9.81); PE = m g h now with it: \
             total 866.8 J -> 709.3 J"
        );
        assert_eq!(
            said(&mut s, Action::DoubleDt),
            "dt = 1/120 s (8.333 ms) from the next step on (was 1/240 s (4.167 ms))"
        );
        assert_eq!(
            said(&mut s, Action::Restart),
            "restarted: step 0, seed 1, the parameters kept (R: a new seed)"
        );
        // A scene's dt beyond the bounds comes to the bound, and says so;
        // the help names the bounds.
        let mut scene = Lesson::Gravity.scene();
        scene.world.dt = 0.1;
        let mut coarse = Session::new(scene, None).unwrap();
        assert_eq!(
            said(&mut coarse, Action::HalveDt),
            "dt = 1/30 s (33.333 ms), the largest here, from the next step on \
             (was 1/10 s (100.000 ms))"
        );
        let bounds = [(Action::HalveDt, DT_MIN), (Action::DoubleDt, DT_MAX)];
        for (action, bound) in bounds {
            let named = format!("1/{:.0} s", 1.0 / bound);
            let binding = super::super::keymap::BINDINGS
                .iter()
                .find(|b| b.action == action)
                .unwrap();
            assert!(
                binding.description.contains(&named),
                "{}",
                binding.description
            );
        }
        let mut flip = Session::lesson(Lesson::Pingpong);
        assert_eq!(
            said(&mut flip, Action::WallRestitutionDown),
            "wall restitution c_r = 0.95 from the next step on (the walls flipped the velocity: c_r = 1)"
        );
        s.apply(Action::ToggleGhost);
        s.apply(Action::StepForward);
        assert_eq!(
            said(&mut s, Action::PairRestitutionUp),
            "pair restitution e = 0.95 from the next step on (was 0.90); the ghost starts again from here"
        );
    }

    #[test]
    fn gravity_moves_along_its_ladder_within_0_and_20() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::GravityUp);
        assert_eq!(s.world.config.gravity, Vec3::new(0.0, -12.0, 0.0));
        for _ in 0..20 {
            s.apply(Action::GravityUp);
        }
        assert_eq!(s.gravity(), GRAVITY_MAX);
        for _ in 0..20 {
            s.apply(Action::GravityDown);
        }
        assert_eq!(s.gravity(), 0.0);
        assert_eq!(next_gravity(9.0, false), 8.0, "from off the ladder");
        assert_eq!(gravity_name(1.62), "Moon");
        // Above the ladder (a flag's 1000), G never weakens it; g does.
        assert_eq!(next_gravity(1000.0, true), 1000.0);
        assert_eq!(next_gravity(1000.0, false), GRAVITY_MAX);
        s.configure(|w| w.gravity = Vec3::new(0.0, -1000.0, 0.0));
        s.apply(Action::GravityUp);
        assert_eq!(s.gravity(), 1000.0);
        let said = s.take_message().unwrap();
        assert!(said.contains("G goes no higher than 20"), "{said}");
    }

    #[test]
    fn the_lesson_s_own_key_says_it_starts_it_afresh() {
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::GravityDown);
        s.apply(Action::StepForward);
        s.take_message();
        s.apply(Action::Lesson(Lesson::Collisions));
        assert_eq!(s.world.steps, 0);
        assert_eq!(s.gravity(), 9.81);
        assert_eq!(
            s.take_message().unwrap(),
            "the collisions lesson from the start, with its own parameters (r restarts \
             keeping the ones changed)"
        );
        // Another lesson's key says nothing: its title says it.
        s.apply(Action::Lesson(Lesson::Gravity));
        assert_eq!(s.take_message(), None);
    }

    #[test]
    fn gravity_keys_keep_a_sideways_gravity_s_direction() {
        // A scene whose gravity points along (3, 0, -4)/5: g and G change
        // its strength, not its direction, and from none it comes back
        // along the scene's own.
        let mut scene = Lesson::Gravity.scene();
        scene.world.gravity = Vec3::new(3.0, 0.0, -4.0);
        let mut s = Session::new(scene, None).unwrap();
        let along = |s: &Session| {
            let g = s.world.config.gravity;
            (g / s.gravity(), s.gravity())
        };
        s.apply(Action::GravityUp);
        let (unit, strength) = along(&s);
        assert!(strength > 5.0, "{strength}");
        assert!(
            (unit - Vec3::new(0.6, 0.0, -0.8)).length() < 1e-15,
            "{unit}"
        );
        assert_eq!(s.world.config.gravity.y.to_bits(), 0, "+0, not -0");
        for _ in 0..20 {
            s.apply(Action::GravityDown);
        }
        assert_eq!(s.world.config.gravity, Vec3::ZERO);
        s.apply(Action::GravityUp);
        let (unit, strength) = along(&s);
        assert!(strength > 0.0);
        assert!(
            (unit - Vec3::new(0.6, 0.0, -0.8)).length() < 1e-15,
            "{unit}"
        );
    }

    #[test]
    fn a_parameter_acts_on_the_next_step_without_a_restart() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::StepForward);
        let v0 = s.world.bodies.velocity.clone();
        s.apply(Action::GravityDown);
        s.apply(Action::StepForward);
        assert_eq!(s.world.steps, 2, "no restart");
        let dt = s.world.config.dt;
        // Spheres that met no wall this step gained exactly -g dt with g = 8.
        let pulled_at_8 = v0
            .iter()
            .zip(&s.world.bodies.velocity)
            .filter(|(a, b)| (b.y - a.y + 8.0 * dt).abs() < 1e-12)
            .count();
        assert!(
            pulled_at_8 + s.world.last.wall_impacts >= 150,
            "only {pulled_at_8} of 150 spheres felt the new gravity"
        );
    }

    #[test]
    fn dt_halves_and_doubles_within_its_bounds() {
        let mut s = Session::lesson(Lesson::Pingpong);
        let dt0 = s.world.config.dt;
        s.apply(Action::HalveDt);
        assert_eq!(s.world.config.dt, dt0 / 2.0);
        for _ in 0..20 {
            s.apply(Action::HalveDt);
        }
        assert!(s.world.config.dt >= DT_MIN);
        assert!(s.take_message().is_some(), "the refusal is explained");
        for _ in 0..20 {
            s.apply(Action::DoubleDt);
        }
        assert!(s.world.config.dt <= DT_MAX);
        // A dt set beyond the keys' range (`--dt 1`, `--dt 1e-6`) comes back
        // to its nearer end, and no further out.
        for (dt, toward, away, end) in [
            (1.0, Action::HalveDt, Action::DoubleDt, DT_MAX),
            (1e-6, Action::DoubleDt, Action::HalveDt, DT_MIN),
        ] {
            s.configure(|w| w.dt = dt);
            s.take_message();
            s.apply(away);
            assert_eq!(s.world.config.dt, dt, "{dt}: not further out");
            assert!(s.take_message().unwrap().starts_with("dt stays between"));
            s.apply(toward);
            assert_eq!(s.world.config.dt, end, "{dt}");
        }
    }

    #[test]
    fn restart_keeps_parameters_and_reseed_changes_the_bodies() {
        let mut s = Session::lesson(Lesson::Gravity);
        let start = s.world.bodies.clone();
        s.apply(Action::WallRestitutionDown);
        s.world.run(10);
        s.apply(Action::Restart);
        assert_eq!(s.world.steps, 0);
        assert_eq!(s.world.bodies, start);
        assert_eq!(s.world.config.wall_restitution, 0.9);
        s.apply(Action::Reseed);
        assert_eq!(s.scene.seed, 2);
        assert_ne!(s.world.bodies.position, start.position);
    }

    #[test]
    fn a_reseed_with_nothing_random_restarts_and_keeps_the_seed() {
        let mut s = Session::lesson(Lesson::Pingpong);
        let start = s.world.bodies.clone();
        s.world.run(10);
        s.apply(Action::Reseed);
        assert_eq!(s.scene.seed, 1, "no spawn draws from it");
        assert_eq!((s.world.steps, &s.world.bodies), (0, &start));
        let status = s.take_message().unwrap();
        assert!(status.contains("places no random spheres"), "{status}");
    }

    #[test]
    fn a_reseed_that_cannot_build_keeps_the_seed_the_world_and_the_error() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::StepForward);
        let bodies = s.world.bodies.clone();
        // 400 spheres of radius 0.07 cannot be placed apart in the box.
        Arc::make_mut(&mut s.scene).spawns[0].count = 400;
        Arc::make_mut(&mut s.scene).spawns[0].radius = [0.07, 0.07];
        Arc::make_mut(&mut s.scene).spawns[0].overlap = false;
        s.apply(Action::Reseed);
        assert_eq!(s.scene.seed, 1, "the seed is kept");
        assert_eq!(
            (s.world.steps, &s.world.bodies),
            (1, &bodies),
            "the world is kept"
        );
        let status = s.take_message().unwrap();
        assert!(status.contains("seed 2:"), "the error is shown: {status}");
    }

    #[test]
    fn b_cycles_the_broad_phase_and_the_next_step_uses_it() {
        let mut s = Session::lesson(Lesson::Collisions);
        assert_eq!(s.world.config.broad_phase, BroadPhase::AllPairs);
        s.apply(Action::StepForward);
        assert_eq!(s.world.last.pair_tests, 4950, "100 spheres: 100 x 99 / 2");
        s.apply(Action::NextBroadPhase);
        assert_eq!(s.world.config.broad_phase, BroadPhase::Grid);
        assert_eq!(
            s.scene.world.broad_phase,
            BroadPhase::Grid,
            "a restart keeps it"
        );
        assert_eq!(s.world.steps, 1, "no restart");
        s.apply(Action::StepForward);
        assert_eq!(s.world.last.broad_phase, Some(BroadPhase::Grid));
        assert!(
            s.world.last.pair_tests < 4950,
            "the grid tests fewer pairs: {}",
            s.world.last.pair_tests
        );
        s.apply(Action::NextBroadPhase);
        assert_eq!(s.world.config.broad_phase, BroadPhase::Auto);
        s.apply(Action::StepForward);
        assert_eq!(
            s.world.last.broad_phase,
            Some(BroadPhase::AllPairs),
            "auto runs all-pairs below its crossover"
        );
        s.apply(Action::NextBroadPhase);
        assert_eq!(s.world.config.broad_phase, BroadPhase::AllPairs);
    }

    #[test]
    fn b_skips_all_pairs_where_it_would_test_too_many_pairs() {
        let mut s = Session::lesson(Lesson::Collisions);
        s.show(crate::scene::bench::bench_world(
            MAX_SPHERES_ALL_PAIRS + 1,
            BroadPhase::Grid,
        ));
        let n = s.world.bodies.len();
        assert!(n > MAX_SPHERES_ALL_PAIRS);
        s.apply(Action::NextBroadPhase);
        s.apply(Action::NextBroadPhase);
        assert_eq!(s.world.config.broad_phase, BroadPhase::Grid);
        assert!(s.take_message().unwrap().contains("all-pairs would test"));
    }

    #[test]
    fn the_ghost_is_the_exact_reference_from_where_it_was_switched_on() {
        use crate::sim::reference::exact_positions;
        let mut s = Session::lesson(Lesson::Pingpong);
        s.apply(Action::TogglePause);
        for _ in 0..7 {
            s.apply(Action::StepForward);
        }
        let anchor = s.world.clone();
        s.apply(Action::ToggleGhost);
        assert!(s.show_ghost);
        for _ in 0..40 {
            s.apply(Action::StepForward);
        }
        let expected = exact_positions(&anchor, s.world.time - anchor.time).unwrap();
        let ghost = s.ghost.as_ref().unwrap();
        assert_eq!(ghost.positions, expected);
        assert!(
            ghost.rms.unwrap() < 1e-12,
            "the ping-pong method is exact: RMS {:e}",
            ghost.rms.unwrap()
        );
        // Back within the anchored stretch: the same anchor, an earlier time.
        for _ in 0..10 {
            s.apply(Action::StepBack);
        }
        let expected = exact_positions(&anchor, s.world.time - anchor.time).unwrap();
        assert_eq!(s.ghost.as_ref().unwrap().positions, expected);
        // Back past the anchor: it starts again from there.
        for _ in 0..35 {
            s.apply(Action::StepBack);
        }
        assert_eq!(s.world.steps, 2);
        let now = s.world.clone();
        s.apply(Action::StepForward);
        let expected = exact_positions(&now, s.world.time - now.time).unwrap();
        assert_eq!(s.ghost.as_ref().unwrap().positions, expected);
        s.apply(Action::ToggleGhost);
        assert!(!s.show_ghost && s.ghost.is_none());
    }

    #[test]
    fn the_ghost_of_colliding_spheres_stops_at_the_predictability_horizon() {
        use super::super::ghost::PAIR_HORIZON;
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::TogglePause);
        s.apply(Action::ToggleGhost);
        s.apply(Action::StepForward);
        let g = s.ghost.as_ref().unwrap();
        assert!(g.unavailable.is_none() && g.rms.is_some());
        let dt = s.world.config.dt;
        let steps = (PAIR_HORIZON / dt).ceil() as u64 + 1;
        s.world.run(steps);
        s.refresh_ghost();
        let g = s.ghost.as_ref().unwrap();
        assert!(g.positions.is_empty());
        assert_eq!(
            g.unavailable,
            Some(super::super::ghost::Unavailable::PastHorizon)
        );
        assert!(s.take_message().unwrap().contains("chaotic"), "said once");
        // A parameter of the physics anchors it again.
        s.apply(Action::GravityDown);
        assert!(s.ghost.as_ref().unwrap().unavailable.is_none());
    }

    #[test]
    fn the_ghost_says_once_when_the_run_has_diverged_from_it() {
        // The collisions lesson with semi-implicit Euler parts from its
        // exact motion within the ghost's horizon: a collision goes
        // another way.
        use super::super::ghost::PAIR_HORIZON;
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::TogglePause);
        s.apply(Action::ToggleGhost);
        let steps = (PAIR_HORIZON / s.world.config.dt).floor() as u64;
        let mut said = Vec::new();
        for _ in 0..steps {
            s.apply(Action::StepForward);
            said.extend(s.take_message());
        }
        let g = s.ghost.as_ref().unwrap();
        assert!(g.diverged(), "RMS {:?}", g.rms);
        let mean = g.radius.iter().sum::<f64>() / g.radius.len() as f64;
        assert!(g.rms.unwrap() > mean);
        let told: Vec<_> = said
            .iter()
            .filter(|m| m.contains("than a sphere's radius"))
            .collect();
        assert_eq!(told.len(), 1, "{said:?}");
        assert!(
            told[0].contains("a collision went another way"),
            "{}",
            told[0]
        );
    }

    #[test]
    fn the_ghost_follows_a_restart_and_refuses_worlds_too_big_for_it() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::ToggleGhost);
        s.world.run(20);
        s.apply(Action::Restart);
        let g = s.ghost.as_ref().unwrap();
        assert_eq!(g.rms, Some(0.0), "anchored at the new start");
        let mut s = Session::lesson(Lesson::Collisions);
        let n = super::super::ghost::MAX_PAIR_GHOST_SPHERES + 1;
        s.show(crate::scene::bench::bench_world(n, BroadPhase::Grid));
        s.apply(Action::ToggleGhost);
        assert!(!s.show_ghost);
        assert!(s.take_message().unwrap().contains("no ghost for"));
    }

    #[test]
    fn the_newest_energy_sample_follows_a_gravity_change() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::StepForward);
        s.apply(Action::GravityDown);
        let d = s.world.diagnostics();
        let sample = s.energy.now(&s.world).unwrap();
        assert_eq!(
            (
                sample.steps,
                sample.potential,
                sample.total,
                sample.momentum
            ),
            (1, d.potential_energy, d.total_energy, d.momentum)
        );
        assert_eq!(s.energy.len(), 2, "the sample is replaced, not added");
    }

    #[test]
    fn the_grid_comparison_is_counted_once_per_step_and_only_when_shown() {
        let mut s = Session::lesson(Lesson::Collisions);
        let count = |s: &Session| BroadPhase::Grid.find_contacts(&s.world.bodies, &mut Vec::new());
        assert_eq!(s.grid_tests(), Some(count(&s)), "all-pairs runs");
        s.world.run(1);
        assert_eq!(
            s.grid_tests(),
            None,
            "a step outside apply: not counted yet"
        );
        s.refresh_grid_tests();
        assert_eq!(s.grid_tests(), Some(count(&s)));
        s.apply(Action::NextBroadPhase);
        s.apply(Action::StepForward);
        assert!(!s.needs_grid_tests(), "the grid ran: its own count stands");
        assert_eq!(s.grid_tests(), None);
    }

    #[test]
    fn the_speed_scale_rounds_up_to_1_2_5() {
        assert_eq!(nice_ceiling(0.7), 1.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
        assert_eq!(nice_ceiling(3.2), 5.0);
        assert_eq!(nice_ceiling(12.0), 20.0);
    }

    /// The fraction of the box the spheres fill.
    fn solid_fraction(world: &World) -> f64 {
        world
            .bodies
            .radius
            .iter()
            .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
            .sum()
    }

    #[test]
    fn sphere_count_follows_the_ladder_and_keeps_the_solid_fraction() {
        for lesson in Lesson::ALL {
            let mut s = Session::lesson(lesson);
            let fraction = solid_fraction(&s.world);
            s.apply(Action::MoreSpheres);
            let n = s.world.bodies.len();
            let home = Session::lesson(lesson).world.bodies.len();
            assert_eq!(n, next_count(home, true, home));
            let now = solid_fraction(&s.world);
            assert!(
                (now - fraction).abs() <= 0.1 * fraction,
                "{lesson:?}: {n} spheres fill {now:.4}, the lesson {fraction:.4}"
            );
            s.apply(Action::FewerSpheres);
            assert_eq!(s.world.bodies.len(), home, "{lesson:?}: - undoes +");
            s.apply(Action::FewerSpheres);
            assert!(s.world.bodies.len() < home.max(2));
        }
        // The gravity lesson's 150 is a rung between 100 and 200.
        assert_eq!(next_count(150, true, 150), 200);
        assert_eq!(next_count(200, false, 150), 150);
        assert_eq!(next_count(150, false, 150), 100);
        let mut s = Session::lesson(Lesson::Pingpong);
        s.apply(Action::FewerSpheres);
        assert_eq!(s.world.bodies.len(), 1);
        assert_eq!(s.take_message().unwrap(), "one sphere is the fewest");
    }

    #[test]
    fn the_collisions_lesson_reaches_ten_thousand_spheres_on_the_grid() {
        let mut s = Session::lesson(Lesson::Collisions);
        let fraction = solid_fraction(&s.world);
        while s.world.bodies.len() < 10_000 {
            s.apply(Action::MoreSpheres);
            let message = s.take_message().unwrap();
            assert!(
                message.starts_with(&spheres(s.world.bodies.len())),
                "{message}"
            );
        }
        assert_eq!(s.world.bodies.len(), 10_000);
        assert_eq!(s.world.config.broad_phase, BroadPhase::Auto);
        assert_eq!(s.world.config.broad_phase.resolve(10_000), BroadPhase::Grid);
        let now = solid_fraction(&s.world);
        assert!(
            (now - fraction).abs() <= 0.1 * fraction,
            "{now} against {fraction}"
        );
        let (hash, bodies) = (s.world.state_hash(), s.world.bodies.clone());
        s.step();
        assert!(s.world.last.pair_tests < all_pairs_tests(10_000));
        // A world this large takes its snapshot and its energy sample side
        // by side: both of the step just taken.
        assert!(s.world.bodies.len() >= RECORD_SIDE_BY_SIDE);
        let d = s.world.diagnostics();
        let sample = s.energy.now(&s.world).expect("a sample of this step");
        assert_eq!(
            (sample.kinetic, sample.potential, sample.momentum),
            (d.kinetic_energy, d.potential_energy, d.momentum)
        );
        s.apply(Action::StepBack);
        assert_eq!(s.world.state_hash(), hash);
        assert_eq!(s.world.bodies, bodies);
    }

    #[test]
    fn more_spheres_stop_where_one_large_sphere_would_make_the_grid_all_pairs() {
        // The large sphere sizes the grid's one cell; the small ones hardly
        // change the solid fraction, so it stays that large.
        let text = "[world]\npair_collisions = true\nbroad_phase = \"grid\"\n\n[[body]]\n\
                    position = [0.5, 0.5, 0.5]\nradius = 0.3\nmass = 1.0\n\n[[spawn]]\n\
                    count = 2000\nradius = [0.002, 0.003]\n";
        let scene = crate::scene::file::parse_scene(text, "t.toml", "t").unwrap();
        let mut s = Session::new(scene, None).unwrap();
        let mut counts = vec![s.world.bodies.len()];
        loop {
            s.apply(Action::MoreSpheres);
            let message = s.take_message().unwrap();
            if message.contains("the grid would test") {
                break;
            }
            counts.push(s.world.bodies.len());
            assert!(counts.len() < 10, "{counts:?}: + never stopped");
        }
        let n = *counts.last().unwrap();
        assert!(grid_tests(n, s.scene.max_radius()) <= all_pairs_tests(MAX_SPHERES_ALL_PAIRS));
        assert!(n <= MAX_SPHERES_ALL_PAIRS + 1, "{counts:?}");
        s.step();
        assert!(s.world.last.pair_tests <= all_pairs_tests(MAX_SPHERES_ALL_PAIRS + 1));
        // Opened beyond the limit (`--allow-slow`), `-` is still a way out.
        let scene = crate::scene::file::parse_scene(
            &text.replace("count = 2000", "count = 20000"),
            "t.toml",
            "t",
        )
        .unwrap();
        let mut s = Session::new(scene, None).unwrap();
        s.apply(Action::FewerSpheres);
        assert!(s.world.bodies.len() < 20_001, "{:?}", s.take_message());
    }

    #[test]
    fn more_spheres_stops_at_the_most_and_says_so_once_more_costs_nothing() {
        let mut s = Session::lesson(Lesson::Gravity);
        let big = s.base.with_count(&s.scene, MAX_SPHERES).unwrap();
        let world = big.build().unwrap();
        s.scene = Arc::new(big);
        s.show(world);
        s.take_message();
        let hash = s.world.state_hash();
        s.apply(Action::MoreSpheres);
        assert_eq!(s.world.state_hash(), hash, "nothing rebuilt");
        assert!(s.take_message().unwrap().contains("already the most"));
    }

    #[test]
    fn a_large_world_lists_its_contacts_only_while_something_reads_them() {
        let big = |shown: bool| {
            let mut s = Session::lesson(Lesson::Collisions);
            let mut scene = s.base.with_count(&s.scene, 5000).unwrap();
            scene.world.broad_phase = BroadPhase::Grid;
            let world = scene.build().unwrap();
            s.scene = Arc::new(scene);
            s.show(world);
            s.show_contacts(shown);
            s
        };
        let (mut shown, mut hidden) = (big(true), big(false));
        assert!(hidden.world.bodies.len() >= crate::sim::large::SPATIAL_ORDER_MIN_BODIES);
        for _ in 0..20 {
            shown.step();
            hidden.step();
        }
        assert_eq!(hidden.world.state_hash(), shown.world.state_hash());
        assert_eq!(hidden.world.last, shown.world.last);
        assert!(shown.world.last.contacts > 0);
        assert_eq!(shown.world.contacts().len(), shown.world.last.contacts);
        assert!(hidden.world.contacts().is_empty(), "nothing reads the list");
        // A pick's impacts are found among them: listed from the next step.
        hidden.apply(Action::Select(Some(Selection::Sphere(0))));
        hidden.step();
        assert_eq!(hidden.world.contacts().len(), hidden.world.last.contacts);
        hidden.apply(Action::Select(None));
        hidden.step();
        assert!(hidden.world.contacts().is_empty());
        // `o` finds the collision it finds with the contacts marked.
        let (mut shown, mut hidden) = (big(true), big(false));
        shown.apply(Action::NextCollision);
        hidden.apply(Action::NextCollision);
        assert!(
            matches!(shown.selection, Some(Selection::Pair(..))),
            "{:?}",
            shown.selection
        );
        assert_eq!(hidden.selection, shown.selection);
        assert_eq!(hidden.world.steps, shown.world.steps);
        // A step back keeps no list in a large world: the pair's note says
        // why its numbers are not shown, not that it is out of contact.
        hidden.apply(Action::StepBack);
        let note = hidden.inspection().and_then(|i| i.pair_note);
        assert!(
            note.as_deref().is_some_and(|n| n.contains("worlds under")),
            "{note:?}"
        );
    }

    #[test]
    fn stepping_back_finds_the_steps_contacts_again() {
        let mut s = Session::lesson(Lesson::Collisions);
        let mut seen = Vec::new();
        for _ in 0..60 {
            s.step();
            seen.push(s.world.contacts().to_vec());
        }
        assert!(
            seen.iter().any(|c| !c.is_empty()),
            "the lesson's spheres meet"
        );
        for k in (0..59).rev() {
            s.apply(Action::StepBack);
            assert_eq!(s.world.contacts(), seen[k].as_slice(), "step {}", k + 1);
        }
    }

    #[test]
    fn a_pick_knows_the_impacts_of_the_steps_stepped_back_to() {
        // A sphere in a contact at some step and in none after, up to the
        // step it is picked at.
        let mut s = Session::lesson(Lesson::Collisions);
        let mut seen: Vec<Vec<u32>> = Vec::new();
        for _ in 0..60 {
            s.step();
            let b = &s.world.bodies;
            let ids = s.world.contacts().iter();
            seen.push(
                ids.flat_map(|c| [b.id[c.i as usize], b.id[c.j as usize]])
                    .collect(),
            );
        }
        let met_last = |id: u32| seen.iter().rposition(|ids| ids.contains(&id));
        let (id, k) = (0..s.world.bodies.len() as u32)
            .find_map(|id| met_last(id).filter(|&k| k < 58).map(|k| (id, k)))
            .expect("a sphere of the lesson met another and then none for a while");
        s.apply(Action::Select(Some(Selection::Sphere(id))));
        let known = |s: &Session| s.inspection().map(|i| i.impacts_known_from);
        assert_eq!(known(&s), Some(60), "the pick's own step is noted");
        // Back to the step of the contact (k + 1): its last impact, found
        // on the way back.
        for _ in (k + 1)..60 {
            s.apply(Action::StepBack);
        }
        assert_eq!(s.world.steps, k as u64 + 1);
        let i = s.inspection().unwrap();
        assert_eq!(i.impacts_known_from, k as u64 + 1);
        assert_eq!(
            i.spheres[0].last_impact.map(|m| m.steps),
            Some(k as u64 + 1),
            "sphere {id} met another at step {}",
            k + 1
        );
        let rows: Vec<String> = super::super::panel::selection_lines(&i, 400)
            .iter()
            .map(super::super::panel::line_text)
            .collect();
        assert!(
            rows.iter()
                .any(|r| r.contains(&format!("at step {}", k + 1))),
            "{rows:?}"
        );
    }

    #[test]
    fn the_support_pass_says_why_it_is_idle() {
        let mut s = Session::lesson(Lesson::Gravity);
        s.apply(Action::ToggleSupport);
        let message = s.take_message().unwrap();
        assert!(
            message.contains("idle: there are no pair collisions"),
            "{message}"
        );
        s.apply(Action::ToggleSupport);
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::ToggleResting);
        s.apply(Action::ToggleSupport);
        let message = s.take_message().unwrap();
        assert!(
            message.contains("idle: it needs resting contact"),
            "{message}"
        );
        s.apply(Action::ToggleResting);
        assert_eq!(s.world.config.support_idle(), None);
    }

    #[test]
    fn i_says_which_method_runs_now() {
        let mut s = Session::lesson(Lesson::Collisions);
        let next = s.world.config.integrator.next();
        s.apply(Action::NextIntegrator);
        assert_eq!(s.world.config.integrator, next);
        let said = s.message.clone().unwrap();
        assert!(said.contains(&format!("method: {next}")), "{said}");
    }

    #[test]
    fn shift_y_switches_the_support_pass_on_and_off() {
        let mut s = Session::lesson(Lesson::Collisions);
        assert!(!s.world.config.support, "off by default");
        s.apply(Action::ToggleSupport);
        assert!(s.world.config.support);
        assert!(s.scene.world.support, "a restart keeps it");
        assert!(s.take_message().unwrap().contains("support pass on"));
        s.apply(Action::ToggleSupport);
        assert!(!s.world.config.support);
        assert!(s.take_message().unwrap().contains("off"));
    }

    #[test]
    fn shift_s_lets_spheres_at_rest_sleep_and_wakes_them() {
        let mut s = Session::lesson(Lesson::Collisions);
        assert!(!s.world.config.sleep, "off by default");
        s.apply(Action::ToggleSleep);
        assert!(
            s.world.config.sleep && s.scene.world.sleep,
            "on, and kept by a restart"
        );
        assert!(s.take_message().unwrap().contains("sleeping on"));
        // The collisions lesson's pile is at rest well within a minute.
        s.world.run(60 * 240);
        assert_eq!(s.world.last.asleep, s.world.bodies.len());
        s.apply(Action::ToggleSleep);
        assert!(s.take_message().unwrap().contains("sleeping off"));
        s.world.step();
        assert_eq!(s.world.last.asleep, 0, "off wakes every sphere");
    }

    #[test]
    fn y_switches_resting_contact_off_and_on_for_the_next_step_and_a_restart() {
        let mut s = Session::lesson(Lesson::Gravity);
        assert!(s.world.config.rest_steps > 0.0, "on by default");
        s.apply(Action::ToggleResting);
        assert_eq!(s.world.config.rest_steps, 0.0);
        assert_eq!(s.scene.world.rest_steps, 0.0, "a restart keeps it");
        let said = s.take_message().unwrap();
        // The default method's wall rule still ends a dropped ball's bounces
        // (`study --stability`, the rest rows); explicit Euler's never end.
        assert!(said.contains("still ends a bounce on the floor"), "{said}");
        s.apply(Action::ToggleResting);
        assert_eq!(s.world.config.rest_steps, WorldConfig::default().rest_steps);
        s.configure(|c| c.integrator = Integrator::ExplicitEuler);
        s.apply(Action::ToggleResting);
        let said = s.take_message().unwrap();
        assert!(
            said.contains("explicit Euler's bounces never end"),
            "{said}"
        );
        // With the support pass on, y also says that it stops.
        let mut s = Session::lesson(Lesson::Collisions);
        s.apply(Action::ToggleSupport);
        s.apply(Action::ToggleResting);
        let said = s.take_message().unwrap();
        assert!(
            said.contains("the support pass is idle: it needs resting"),
            "{said}"
        );
    }
}
