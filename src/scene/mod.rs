//! Scenes as data: which bodies, which stages, which parameters.
//!
//! A [`Scene`] is the recipe a [`World`] is built from: explicit bodies,
//! seeded random spawns and a [`WorldConfig`]. The three lessons are scene
//! files compiled into the program (`lessons/*.toml`); users write their own
//! in the same format (see [`file`](mod@file)).

//!
//! | file              | concept                                                           |
//! |-------------------|-------------------------------------------------------------------|
//! | `rules.rs`        | what a valid value is, shared by scene files and flags            |
//! | `whole_number.rs` | whole numbers read exactly as written (`1e6`), in files and flags |
//! | `file.rs`         | the TOML format: parsing and validation                           |
//! | `error.rs`        | what is wrong with a scene, and where                             |
//! | `lessons.rs`      | the three lessons, compiled in                                    |
//! | `crowding.rs`     | spheres piled on one another, refused before the first step       |
//! | `memory.rs`       | what a scene's first step will hold, against what the system has  |
//! | `bench.rs`        | the benchmark scene: equal spheres at any count                   |
//!
//! Reading a file is bounded: only a regular file of at most
//! [`MAX_SCENE_BYTES`] is read (a device, a pipe or a folder is refused
//! before it is opened).

pub mod bench;
pub(crate) mod crowding;
pub(crate) mod error;
pub(crate) mod file;
pub(crate) mod lessons;
pub(crate) mod memory;
pub mod rules;
pub(crate) mod whole_number;

pub use error::SceneError;
pub use file::parse_scene;
pub use lessons::Lesson;

use crate::sim::spawn::{SpawnError, check_packing, spawn_bodies_telling};
use crate::sim::{Bodies, Body, MassLaw, Spawn, World, WorldConfig};
use crowding::{MAX_CONTACTS_PER_SPHERE, count_overlaps, largest_shared_point};
use std::io::Read;
use std::path::Path;

/// "1 sphere", "n spheres".
pub(crate) fn spheres(n: usize) -> String {
    if n == 1 {
        "1 sphere".to_string()
    } else {
        format!("{} spheres", thousands(n as u64))
    }
}

pub(crate) use crate::sim::thousands;

/// Largest scene file read, bytes (16 MiB): about 350,000 `[[body]]`
/// entries.
pub(crate) const MAX_SCENE_BYTES: u64 = 16 * 1024 * 1024;

/// What the visualiser's side panel says about a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LessonInfo {
    pub title: String,
    pub idea: String,
    pub equation: String,
    /// The contacts are marked from the start (in a world small enough
    /// that the marks say something: see the visualiser's `d`).
    pub contacts: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name: the lesson's, or the file's stem.
    pub name: String,
    /// Where it came from, for messages: a path or `lesson NAME`.
    pub origin: String,
    pub info: Option<LessonInfo>,
    pub world: WorldConfig,
    /// Seed of every random choice the scene makes.
    pub seed: u64,
    pub bodies: Vec<Body>,
    pub spawns: Vec<Spawn>,
    /// Source line of each `[[spawn]]`, for messages.
    pub spawn_lines: Vec<usize>,
    /// How [`Scene::with_count`] sized the spheres, if it did: a placement
    /// that fails then says so, as fewer spheres would not help.
    pub sized_for: Option<Sizing>,
}

/// What [`Scene::with_count`] did to a scene's spheres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sizing {
    /// Spheres in all.
    pub spheres: usize,
    /// The factor every radius was scaled by.
    pub scale: f64,
}

impl Scene {
    /// Read a scene file.
    pub(crate) fn from_file(path: &Path) -> Result<Scene, SceneError> {
        // A control character in the name (a line break) is shown escaped,
        // so that a message stays on its lines.
        let mut origin = String::new();
        for c in path.display().to_string().chars() {
            if c.is_control() {
                origin.extend(c.escape_default());
            } else {
                origin.push(c);
            }
        }
        let source = read_scene_file(path)
            .map_err(|m| SceneError::new(&origin, format!("cannot read the scene file: {m}")))?;
        let name = path
            .file_stem()
            .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned());
        parse_scene(&source, &origin, &name)
    }

    /// How many spheres the spawns place.
    pub(crate) fn spawned(&self) -> usize {
        self.spawns.iter().map(|s| s.count).sum()
    }

    /// Whether the scene's `[lesson]` asks for its contacts to be marked
    /// from the start ([`LessonInfo::contacts`]).
    pub fn marks_contacts(&self) -> bool {
        self.info.as_ref().is_some_and(|i| i.contacts)
    }

    /// How many spheres the built world holds.
    pub fn body_count(&self) -> usize {
        self.bodies.len() + self.spawned()
    }

    /// The largest radius the built world can hold: its bodies', and the
    /// top of each placing spawn's range.
    pub fn max_radius(&self) -> f64 {
        let bodies = self.bodies.iter().map(|b| b.radius);
        let spawns = self
            .spawns
            .iter()
            .filter(|s| s.count > 0)
            .map(|s| s.radius[1]);
        bodies.chain(spawns).fold(0.0, f64::max)
    }

    /// Resize the spawns to place `n` spheres in all, keeping their
    /// proportions (largest remainder, ties to the earlier spawn). Refused
    /// when the scene has no spawns.
    pub(crate) fn set_particles(&mut self, n: usize) -> Result<(), String> {
        let total = self.spawned();
        if self.spawns.is_empty() {
            return Err(format!(
                "the scene '{}' places no random spheres (it has no [[spawn]] entries)",
                self.name
            ));
        }
        let weights: Vec<f64> = if total == 0 {
            vec![1.0; self.spawns.len()]
        } else {
            self.spawns.iter().map(|s| s.count as f64).collect()
        };
        let sum: f64 = weights.iter().sum();
        let exact: Vec<f64> = weights.iter().map(|w| w / sum * n as f64).collect();
        let mut counts: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
        let mut order: Vec<usize> = (0..counts.len()).collect();
        order.sort_by(|&a, &b| {
            let (fa, fb) = (exact[a] - exact[a].floor(), exact[b] - exact[b].floor());
            fb.total_cmp(&fa).then(a.cmp(&b))
        });
        let short = n - counts.iter().sum::<usize>();
        for &k in order.iter().take(short) {
            counts[k] += 1;
        }
        for (s, c) in self.spawns.iter_mut().zip(counts) {
            s.count = c;
        }
        self.check_size().map_err(|e| e.message)
    }

    /// `live` (its parameters and seed) with `n` spheres in all, placed as
    /// this scene places its own: its bodies, then its spawns in their
    /// proportions (a scene of bodies only adds random spheres like its
    /// first body). Every radius is scaled by one factor so that together
    /// they fill the same fraction of the box as this scene's, in
    /// expectation over the random radii; constant masses scale by its
    /// cube, so densities stay. Refused below the scene's own bodies, or
    /// when a sphere so sized breaks a scene file's rules. The visualiser's
    /// `+` and `-` and the flag `--particles` resize a scene this way.
    pub(crate) fn with_count(&self, live: &Scene, n: usize) -> Result<Scene, String> {
        let base = self;
        let mut scene = live.clone();
        scene.bodies = base.bodies.clone();
        scene.spawns = base.spawns.clone();
        scene.spawn_lines = base.spawn_lines.clone();
        let fixed = scene.bodies.len();
        if base.body_count() == 0 {
            return Err("the scene has no spheres to size the others by".into());
        }
        if n < fixed {
            return Err(format!(
                "the scene has {fixed} bodies of its own, so at least {fixed} spheres"
            ));
        }
        if scene.spawns.is_empty() {
            let first = scene.bodies[0];
            let speed = first.velocity.length();
            scene.spawns.push(Spawn {
                count: 0,
                radius: [first.radius; 2],
                speed: [speed; 2],
                mass_law: MassLaw::Constant { mass: first.mass },
                overlap: false,
            });
            scene.spawn_lines.push(0);
        }
        if n > fixed {
            scene.set_particles(n - fixed)?;
        } else {
            for s in &mut scene.spawns {
                s.count = 0;
            }
        }
        // Radii in units of the largest, so that the cubes of tiny radii
        // (down to the smallest number) neither vanish nor make 0/0.
        let unit = base.largest_radius();
        let f = (base.expected_volume(unit) / scene.expected_volume(unit)).cbrt();
        for b in &mut scene.bodies {
            b.radius *= f;
            b.mass *= f.powi(3);
        }
        for s in &mut scene.spawns {
            s.radius = s.radius.map(|r| r * f);
            if let MassLaw::Constant { mass } = &mut s.mass_law {
                *mass *= f.powi(3);
            }
        }
        scene.check_sizes(n)?;
        scene.sized_for = Some(Sizing {
            spheres: n,
            scale: f,
        });
        Ok(scene)
    }

    /// The largest radius of the scene's bodies and of its spawns that
    /// place any sphere (0 for none).
    fn largest_radius(&self) -> f64 {
        let bodies = self.bodies.iter().map(|b| b.radius);
        let spawns = self
            .spawns
            .iter()
            .filter(|s| s.count > 0)
            .map(|s| s.radius[0].max(s.radius[1]));
        bodies.chain(spawns).fold(0.0, f64::max)
    }

    /// The spheres' volume over `4/3 pi`, with radii in units of `unit`
    /// (m): the bodies' `r^3`, and for each spawn its count times the mean
    /// of `r^3` over its uniform radii.
    fn expected_volume(&self, unit: f64) -> f64 {
        let bodies: f64 = self.bodies.iter().map(|b| (b.radius / unit).powi(3)).sum();
        let spawns: f64 = self
            .spawns
            .iter()
            .filter(|s| s.count > 0)
            .map(|s| {
                let [a, b] = s.radius.map(|r| r / unit);
                let mean = if b > a {
                    (b.powi(4) - a.powi(4)) / (4.0 * (b - a))
                } else {
                    a.powi(3)
                };
                s.count as f64 * mean
            })
            .sum();
        bodies + spawns
    }

    /// The rules of a scene file for what [`Scene::with_count`] sized for
    /// `n` spheres: fewer spheres are larger, and an explicit body may no
    /// longer fit where it is.
    fn check_sizes(&self, n: usize) -> Result<(), String> {
        for (k, b) in self.bodies.iter().enumerate() {
            rules::radius(b.radius)
                .and_then(|r| rules::inside_box(b.position.to_array(), r))
                .and_then(|_| rules::mass(b.mass))
                .map_err(|m| format!("body[{k}] sized for {}: {m}", spheres(n)))?;
        }
        for (k, s) in self.spawns.iter().enumerate().filter(|(_, s)| s.count > 0) {
            rules::range(s.radius, rules::radius)
                .map_err(|m| format!("spawn[{k}] sized for {}: radius {m}", spheres(n)))?;
            if let MassLaw::Constant { mass } = s.mass_law {
                rules::mass(mass)
                    .map_err(|m| format!("spawn[{k}] sized for {}: mass {m}", spheres(n)))?;
            }
        }
        Ok(())
    }

    /// A scene must hold at least one and at most [`rules::MAX_BODIES`] spheres.
    pub(crate) fn check_size(&self) -> Result<(), SceneError> {
        let n = self.body_count();
        if n == 0 {
            return Err(SceneError::new(
                &self.origin,
                "the scene has no bodies: add a [[body]] or a [[spawn]] entry",
            ));
        }
        if n > rules::MAX_BODIES {
            return Err(SceneError::new(
                &self.origin,
                format!(
                    "the scene holds {}; at most {} are allowed",
                    spheres(n),
                    thousands(rules::MAX_BODIES as u64)
                ),
            ));
        }
        Ok(())
    }

    /// The lesson this scene is, unchanged or with overrides; `None` for a
    /// scene file.
    pub(crate) fn lesson(&self) -> Option<Lesson> {
        Lesson::ALL
            .into_iter()
            .find(|l| self.origin == Lesson::origin(l.name()))
    }

    /// Build the world: explicit bodies first, then each spawn in order.
    /// Refused when the spheres cannot be placed, or (with pair collisions)
    /// start crowded past [`MAX_CONTACTS_PER_SPHERE`] overlaps a sphere or
    /// past what memory can hold.
    pub fn build(&self) -> Result<World, SceneError> {
        self.build_telling(&|_| {})
    }

    /// [`Scene::build`], telling `placed` how many of the spawns' spheres
    /// are placed so far, every few thousand (`spawn::PLACED_TOLD_EVERY`).
    pub(crate) fn build_telling(&self, placed: &dyn Fn(usize)) -> Result<World, SceneError> {
        memory::check_spheres(self.body_count() as u64, memory::available_memory())
            .map_err(|why| SceneError::new(&self.origin, why))?;
        let mut bodies = Bodies::with_capacity(self.body_count());
        for &b in &self.bodies {
            bodies.push(b);
        }
        spawn_bodies_telling(&mut bodies, &self.spawns, self.seed, placed)
            .map_err(|e| self.spawn_error(&e))?;
        if self.world.pair_collisions {
            self.check_crowding(&bodies)?;
        }
        Ok(World::new(self.world.clone(), bodies))
    }

    /// Refuse, before anything is placed, spawns denser than placement
    /// reaches (`spawn::check_packing`): the cheap part of [`Scene::build`]'s
    /// checks, which the commands make before weighing a run's cost.
    pub(crate) fn check_packing(&self) -> Result<(), SceneError> {
        check_packing(&self.spawns, !self.bodies.is_empty()).map_err(|e| self.spawn_error(&e))
    }

    /// Whether the spheres may start piled on one another past what
    /// [`Scene::build`] allows (64 overlapping pairs a sphere), judged
    /// before they are placed from a bound on the overlapping pairs to
    /// expect: every pair of explicit bodies; and for the spheres spawned
    /// with `overlap`, placed at random over the box, the mean number of
    /// others within reach of each (explicit bodies, and spawned spheres
    /// as large as the largest). Held to be when that bound reaches a
    /// quarter of the allowance.
    pub(crate) fn may_start_crowded(&self) -> bool {
        let ball = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let (mut scattered, mut placed, mut r_scattered, mut r_placed) = (0.0, 0.0, 0.0, 0.0);
        for s in &self.spawns {
            if s.overlap {
                scattered += s.count as f64;
                r_scattered = f64::max(r_scattered, s.radius[1]);
            } else {
                placed += s.count as f64;
                r_placed = f64::max(r_placed, s.radius[1]);
            }
        }
        let bodies = self.bodies.len() as f64;
        let with_bodies: f64 = self
            .bodies
            .iter()
            .map(|b| scattered * ball(b.radius + r_scattered))
            .sum();
        let spawned =
            scattered * (scattered / 2.0 + placed) * ball(2.0 * f64::max(r_scattered, r_placed));
        let pairs = bodies * (bodies - 1.0) / 2.0 + with_bodies + spawned;
        pairs >= MAX_CONTACTS_PER_SPHERE as f64 / 4.0 * self.body_count() as f64
    }

    /// The scene's error for a spawn that could not be placed, at its
    /// entry of the file.
    fn spawn_error(&self, e: &SpawnError) -> SceneError {
        // A scene of bodies only, sized with more spheres, adds a spawn
        // of its own (line 0): no entry of the file to point at.
        match self.spawn_lines.get(e.spawn()) {
            Some(&line) if line > 0 => {
                let mut error = SceneError::new(&self.origin, self.spawn_message(e))
                    .field(format!("spawn[{}]", e.spawn()));
                error.at = Some((line, 1));
                error
            }
            _ => SceneError::new(&self.origin, self.spawn_message(e))
                .field("the spheres added like body[0]".to_string()),
        }
    }

    /// What went wrong placing spheres, and what to do: a lesson's spawns
    /// can only be changed in a scene file of their own (`--particles`
    /// keeps the lesson's solid fraction, so it never crowds one).
    fn spawn_message(&self, e: &SpawnError) -> String {
        let lesson = self.lesson().map(|l| l.name());
        let whose = lesson.map_or(String::new(), |name| format!(" of the {name} lesson"));
        let what = match (e, self.sized_for) {
            (SpawnError::CannotFit { count, placed, .. }, Some(sizing)) => {
                let solid = self.expected_volume(1.0) * 4.0 / 3.0 * std::f64::consts::PI;
                let advice = if sizing.scale > 1.0 {
                    "each is larger than the scene's own: ask for more spheres (each is \
                     then smaller)"
                } else {
                    "at this size they fit only if they may overlap"
                };
                let spheres_word = if *count == 1 { "sphere" } else { "spheres" };
                format!(
                    "cannot fit {} non-overlapping {spheres_word}{whose} in the box (found \
                     room for {}): sized for {} in all, so that they fill the scene's \
                     {:.0}% of the box, {advice}",
                    thousands(*count as u64),
                    thousands(*placed as u64),
                    spheres(sizing.spheres),
                    solid * 100.0
                )
            }
            _ if lesson.is_none() => return e.to_string(),
            (SpawnError::CannotFit { count, placed, .. }, None) => format!(
                "cannot fit {} non-overlapping spheres{whose} in the box (found room for {})",
                thousands(*count as u64),
                thousands(*placed as u64)
            ),
            (
                SpawnError::TooDense {
                    count,
                    fraction,
                    limit,
                    ..
                },
                _,
            ) => format!(
                "{} spheres{whose} would fill {:.0}% of the box, beyond {}",
                thousands(*count as u64),
                fraction * 100.0,
                crate::sim::spawn::packing_limit(*limit)
            ),
        };
        match lesson {
            Some(name) => format!(
                "{what}. To let them start overlapping: `lerpit scene {name} > {name}.toml`, \
                 set overlap = true in its [[spawn]] entries, and run it with --scene \
                 {name}.toml"
            ),
            None if self.spawn_lines.iter().all(|&line| line == 0) => {
                format!("{what}; or add a [[spawn]] entry with overlap = true to the scene")
            }
            None => format!("{what}; or set overlap = true in the scene's [[spawn]] entries"),
        }
    }

    /// Refuse spheres piled on one another (see [`crowding`]), or with more
    /// overlapping pairs than memory can hold (see [`memory`]).
    fn check_crowding(&self, bodies: &Bodies) -> Result<(), SceneError> {
        let n = bodies.len() as u64;
        let limit = MAX_CONTACTS_PER_SPHERE.saturating_mul(n);
        let found = count_overlaps(bodies, limit);
        if !found.exceeded {
            return memory::check_first_step(n, found.pairs, memory::available_memory())
                .map_err(|why| SceneError::new(&self.origin, why));
        }
        let detail = match largest_shared_point(bodies) {
            Some((p, k)) if k > 1 => format!(
                "{k} bodies share the point [{}, {}, {}] ({} pairs among them alone)",
                p.x,
                p.y,
                p.z,
                thousands(crate::sim::broad_phase::all_pairs_tests(k))
            ),
            _ => match found.most {
                Some((_, m)) => format!(
                    "no two share a point, and one sphere overlaps at least {} others",
                    thousands(u64::from(m))
                ),
                None => String::new(),
            },
        };
        Err(SceneError::new(
            &self.origin,
            format!(
                "the {} spheres start piled on one another: more than {} overlapping \
                 pairs ({MAX_CONTACTS_PER_SPHERE} a sphere is the most allowed; the first step \
                 would hold every pair in memory); {detail}. Spread the bodies out",
                thousands(n),
                thousands(limit),
            ),
        ))
    }
}

/// The text of the scene file at `path`, read only if it is a regular file
/// of at most [`MAX_SCENE_BYTES`]; the reason otherwise.
fn read_scene_file(path: &Path) -> Result<String, String> {
    let regular = |m: &std::fs::Metadata| -> Result<(), String> {
        if m.is_file() {
            return Ok(());
        }
        Err(format!(
            "it is {}, not a regular file",
            file_kind(&m.file_type())
        ))
    };
    let too_large = |bytes: u64| {
        format!("it holds {bytes} bytes; a scene file may hold at most {MAX_SCENE_BYTES} (16 MiB)")
    };
    // Look before opening: opening a pipe waits for a writer.
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    regular(&meta)?;
    if meta.len() > MAX_SCENE_BYTES {
        return Err(too_large(meta.len()));
    }
    // Without waiting: a file of the system that waits for its data
    // (/proc/kmsg) is a regular file of no length, and a path made a pipe
    // since the look opens at once.
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut open, libc::O_NONBLOCK);
    let file = open.open(path).map_err(|e| e.to_string())?;
    regular(&file.metadata().map_err(|e| e.to_string())?)?;
    // Memory that runs out while reading is an error naming the file,
    // worded once the reading is over.
    let mut bytes = Vec::new();
    let read = {
        let _told = memory::Recoverable::hold();
        bytes
            .try_reserve_exact(meta.len() as usize)
            .map_err(std::io::Error::from)
            // A file that grows while it is read stops here all the same.
            .and_then(|()| file.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
    };
    read.map_err(|e| match e.kind() {
        std::io::ErrorKind::WouldBlock => {
            "it has nothing to read yet: a file that waits for its data".to_string()
        }
        _ => e.to_string(),
    })?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(format!(
            "{} (it grew while being read)",
            too_large(bytes.len() as u64)
        ));
    }
    // Reading it takes many times its size: refused here, not aborted by
    // the allocator part-way through.
    let need = file::reading_bytes(&bytes);
    if let Some(available) = memory::available_memory()
        && !available.fits(need)
    {
        return Err(format!(
            "reading its {} may take up to {} of memory, and {available}. {}",
            memory::memory_size(bytes.len() as f64),
            memory::memory_size(need),
            available.way_out(need, "Use a smaller file")
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "it is not UTF-8 text (an invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// What kind of file this is, for a message.
fn file_kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "something other than a file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_of_spheres_have_thousands_separators() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(4950), "4,950");
        assert_eq!(thousands(1_234_567), "1,234,567");
        assert_eq!(spheres(1), "1 sphere");
        assert_eq!(spheres(999), "999 spheres");
        assert_eq!(spheres(10_000), "10,000 spheres");
    }

    #[test]
    fn crowding_is_weighed_before_placing_only_where_it_may_be_found() {
        let scene = |text: &str| parse_scene(text, "t.toml", "t").unwrap();
        let spawn = |count: u32, r: f64, overlap: bool| {
            format!("[[spawn]]\ncount = {count}\nradius = [{r}, {r}]\noverlap = {overlap}\n")
        };
        // 40,000 of 5 cm at random: 167 others within reach of each.
        assert!(scene(&spawn(40_000, 0.05, true)).may_start_crowded());
        // 3,000,000 of 1 mm: 0.1 within reach; and one large body among
        // them overlaps 340,000 of them, far from 48 million.
        let big = format!("{BIG}{}", spawn(3_000_000, 0.001, true));
        assert!(!scene(&big).may_start_crowded());
        // Placed without overlaps, none can crowd.
        assert!(!scene(&spawn(40_000, 0.01, false)).may_start_crowded());
        // Bodies may be anywhere: one body is no pair; 40 bodies may be
        // 780 pairs, past a quarter of 64 a sphere (640), and 30 (435)
        // not.
        assert!(!scene(BIG).may_start_crowded());
        assert!(scene(&BIG.repeat(40)).may_start_crowded());
        assert!(!scene(&BIG.repeat(30)).may_start_crowded());
    }

    const BIG: &str = "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.3\nmass = 1.0\n";

    #[test]
    fn every_lesson_parses_and_builds() {
        for lesson in Lesson::ALL {
            let scene = lesson.scene();
            let world = scene.build().unwrap();
            assert_eq!(world.bodies.len(), scene.body_count());
            assert!(
                scene.info.is_some(),
                "{} has its lesson text",
                lesson.name()
            );
        }
    }

    #[test]
    fn the_lesson_files_write_out_standard_gravity_or_none() {
        use crate::sim::{STANDARD_GRAVITY, Vec3};
        for lesson in Lesson::ALL {
            let g = lesson.scene().world.gravity;
            assert!(
                g == Vec3::ZERO || g == Vec3::new(0.0, -STANDARD_GRAVITY, 0.0),
                "{}: {g}",
                lesson.name()
            );
        }
    }

    #[test]
    fn spheres_sized_too_large_to_place_say_so_rather_than_ask_for_fewer() {
        // 200 spheres fill 18% of the box; two so sized have r = 0.28, and
        // random placement finds no room for the second (only the box's
        // diagonals have it).
        let text = "[world]\npair_collisions = true\n\n[[spawn]]\ncount = 200\n\
                    radius = [0.06, 0.06]\n";
        let base = parse_scene(text, "t.toml", "t").unwrap();
        let two = base.with_count(&base, 2).unwrap();
        assert!(two.sized_for.unwrap().scale > 1.0);
        let message = two.build().unwrap_err().message;
        assert_eq!(
            message,
            "cannot fit 2 non-overlapping spheres in the box (found room for 1): sized for \
             2 spheres in all, so that they fill the scene's 18% of the box, each is larger \
             than the scene's own: ask for more spheres (each is then smaller); or set \
             overlap = true in the scene's [[spawn]] entries"
        );
        // The scene itself, unsized, still gives the placement's own advice.
        let mut crowded = base.clone();
        crowded.spawns[0].radius = [0.3, 0.3];
        crowded.spawns[0].count = 2;
        let message = crowded.build().unwrap_err().message;
        assert!(
            message.contains("use fewer or smaller spheres"),
            "{message}"
        );
    }

    #[test]
    fn a_crowded_lesson_says_how_to_let_its_spheres_overlap() {
        let mut scene = Lesson::Gravity.scene();
        scene.set_particles(15000).unwrap();
        let message = scene.build().unwrap_err().message;
        for needle in [
            "cannot fit 15,000 non-overlapping spheres of the gravity lesson",
            "`lerpit scene gravity > gravity.toml`",
            "overlap = true",
            "--scene gravity.toml",
        ] {
            assert!(message.contains(needle), "lacks {needle:?}: {message}");
        }
    }

    #[test]
    fn with_count_keeps_the_solid_fraction_and_the_parameters() {
        let base = Lesson::Collisions.scene();
        let mut live = base.clone();
        live.seed = 7;
        live.world.pair_restitution = 0.5;
        let scene = base.with_count(&live, 800).unwrap();
        assert_eq!((scene.body_count(), scene.seed), (800, 7));
        assert_eq!(scene.world.pair_restitution, 0.5);
        let f = (100.0_f64 / 800.0).cbrt();
        for (s, b) in scene.spawns.iter().zip(&base.spawns) {
            for (got, was) in s.radius.iter().zip(b.radius) {
                assert!((got - was * f).abs() < 1e-15, "{got} against {}", was * f);
            }
        }
    }

    #[test]
    fn with_count_keeps_bodies_first_and_refuses_what_no_longer_fits() {
        // Two bodies and ten random spheres, all r = 0.09.
        let mut base = Lesson::Collisions.scene();
        base.spawns.truncate(1);
        base.spawn_lines.truncate(1);
        base.spawns[0].count = 10;
        base.spawns[0].radius = [0.09, 0.09];
        let body = |x: f64| Body {
            position: crate::sim::Vec3::new(x, 0.5, 0.5),
            velocity: crate::sim::Vec3::ZERO,
            radius: 0.09,
            mass: 1.0,
        };
        base.bodies = vec![body(0.1), body(0.3)];
        // More spheres: both bodies, smaller, and the rest spawned.
        let more = base.with_count(&base, 24).unwrap();
        assert_eq!((more.bodies.len(), more.spawned()), (2, 22));
        let f = 0.5_f64.cbrt();
        assert!((more.bodies[1].radius - 0.09 * f).abs() < 1e-15);
        // Fewer: the bodies grow, and the first no longer fits at x = 0.1.
        let err = base.with_count(&base, 3).unwrap_err();
        assert!(
            err.contains("body[0] sized for 3 spheres") && err.contains("outside the box"),
            "{err}"
        );
        // No body is dropped without a word.
        let err = base.with_count(&base, 1).unwrap_err();
        assert!(err.contains("2 bodies of its own, so at least 2"), "{err}");
    }

    #[test]
    fn with_count_sizes_spheres_whose_cubes_are_below_the_smallest_number() {
        // r^3 of 1e-110 m is 0 in double precision: the sizing takes the
        // radii in units of the largest, and scales them all the same.
        let body = crate::sim::Body {
            position: crate::sim::Vec3::splat(0.5),
            velocity: crate::sim::Vec3::ZERO,
            radius: 1e-110,
            mass: 1.0,
        };
        let spawn = |count, r| crate::scene::Spawn {
            count,
            radius: [r, r],
            speed: [0.0, 0.0],
            mass_law: crate::scene::MassLaw::Constant { mass: 1.0 },
            overlap: false,
        };
        // One body, more like it.
        let mut base = Lesson::Gravity.scene();
        (base.bodies, base.spawns, base.spawn_lines) = (vec![body], vec![], vec![]);
        for n in [1, 5, 40] {
            let scene = base.with_count(&base, n).expect("sized");
            let r = scene.bodies[0].radius;
            let want = 1e-110 * (1.0 / n as f64).cbrt();
            assert!((r - want).abs() <= 1e-12 * want, "{n}: {r} against {want}");
        }
        // Ten from a spawn, beside a spawn of large spheres that places
        // none and so sizes nothing.
        (base.bodies, base.spawns, base.spawn_lines) =
            (vec![], vec![spawn(0, 0.1), spawn(10, 1e-110)], vec![1, 5]);
        for n in [10, 20, 40] {
            let scene = base.with_count(&base, n).expect("sized");
            let r = scene.spawns[1].radius[0];
            let want = 1e-110 * (10.0 / n as f64).cbrt();
            assert!((r - want).abs() <= 1e-12 * want, "{n}: {r} against {want}");
        }
    }

    #[test]
    fn with_count_keeps_the_expected_solid_volume_whatever_the_mix() {
        // Seven spheres of the collisions lesson round its 80/15/5 mix to
        // 6/1/0: the volume in expectation stays the lesson's all the same.
        let base = Lesson::Collisions.scene();
        for n in [1, 7, 100, 1000, 12345] {
            let scene = base.with_count(&base, n).unwrap();
            let (got, want) = (scene.expected_volume(1.0), base.expected_volume(1.0));
            assert!(
                (got - want).abs() < 1e-12 * want,
                "{n}: {got} against {want}"
            );
        }
    }

    #[test]
    fn set_particles_keeps_the_spawn_proportions_and_the_total() {
        let mut scene = Lesson::Collisions.scene();
        scene.set_particles(1000).unwrap();
        let counts: Vec<usize> = scene.spawns.iter().map(|s| s.count).collect();
        assert_eq!(counts, [800, 150, 50]);
        scene.set_particles(7).unwrap();
        let counts: Vec<usize> = scene.spawns.iter().map(|s| s.count).collect();
        assert_eq!(counts.iter().sum::<usize>(), 7);
        assert_eq!(counts, [6, 1, 0]);
        assert!(Lesson::Pingpong.scene().set_particles(3).is_err());
    }

    #[test]
    fn a_wrong_type_is_named_by_its_real_path_not_by_lines_that_look_like_tables() {
        let text = "[lesson]\nidea = \"\"\"\n[[body]]\n[world]\n\"\"\"\n\n\
                    [[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = \"heavy\"\n";
        let err = parse_scene(text, "t.toml", "t").unwrap_err();
        assert_eq!(err.field.as_deref(), Some("body[0].mass"), "{err}");
        assert_eq!(err.at, Some((10, 8)), "{err}");
        assert_eq!(err.source_line.as_deref(), Some("mass = \"heavy\""));
    }

    #[test]
    fn a_spawn_that_cannot_fit_is_reported_at_its_line() {
        let text = "[world]\ndt = 0.01\n\n[[spawn]]\ncount = 400\nradius = [0.07, 0.07]\n";
        let scene = parse_scene(text, "t.toml", "t").unwrap();
        let err = scene.build().unwrap_err();
        assert_eq!(err.at, Some((4, 1)));
        assert_eq!(err.field.as_deref(), Some("spawn[0]"));
    }
}
