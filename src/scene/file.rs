//! The TOML scene format: parsing and validation.
//!
//! ```toml
//! [lesson]                      # optional: shown by the visualiser
//! title = "My scene"
//! idea = "What to watch for."
//! equation = "x(t+dt) = x(t) + v(t) dt"
//!
//! [world]                       # every field optional; defaults shown
//! gravity = [0.0, -9.81, 0.0]   # m/s^2
//! dt = 0.008333333333333333     # s
//! integrator = "semi-implicit-euler"
//! wall_mode = "restitution"     # or "flip"
//! wall_restitution = 0.95
//! pair_collisions = true
//! pair_restitution = 0.95
//! substeps = 1                  # sub-steps per step, any method
//! rest_threshold = 0.0          # m/s; slower impacts are inelastic; 0 = off
//! rest_steps = 1.0              # resting contact: impacts slower than this many steps of gravity stop; 0 = off
//! projection_passes = 1         # passes over a step's contacts, 1 to 64 (deep piles)
//! support = false               # solve resting contacts together, so piles hold (needs pairs, gravity, rest_steps > 0, a discrete method)
//! sleep = false                 # spheres at rest for 0.5 s sleep until disturbed (a discrete method)
//! broad_phase = "all-pairs"     # or "grid", or "auto" (by sphere count)
//! seed = 1
//!
//! [[body]]                      # any number
//! position = [0.5, 0.5, 0.5]
//! velocity = [0.0, 1.0, 0.0]
//! radius = 0.05
//! mass = 1.0
//!
//! [[spawn]]                     # any number
//! count = 100
//! radius = [0.01, 0.02]
//! speed = [0.0, 1.0]
//! mass_law = "volume"           # m = density 4/3 pi r^3; or "constant"
//! density = 1000.0              # with "volume" (default 1000)
//! # mass = 0.01                 # with "constant"
//! overlap = false
//! ```
//!
//! Every problem is reported with the file, line and column and the field's
//! dotted name. Values are parsed into span-carrying raw structures first,
//! then checked with the shared [`rules`]. A value of the
//! wrong type is named by the path serde took to it (`serde_path_to_error`)
//! and placed by toml's span: nothing is guessed from the lines around it.

use super::error::{LineIndex, field_path};
use super::whole_number::whole_number_written;
use super::{LessonInfo, Scene, SceneError, rules};
use crate::sim::{
    Body, BroadPhase, Integrator, MassLaw, MassLawKind, Spawn, Vec3, WallMode, WorldConfig,
};
use serde::Deserialize;
use std::ops::Range;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a scene: [world], [lesson], [[body]] and [[spawn]] entries"
)]
struct RawScene {
    lesson: Option<Table<RawLesson>>,
    world: Option<Table<RawWorld>>,
    #[serde(default)]
    body: Vec<Spanned<Table<RawBody>>>,
    #[serde(default)]
    spawn: Vec<Spanned<Table<RawSpawn>>>,
}

/// A section of the scene, taken from a table only. Serde's derived
/// structs also take an array of their values in the order of their
/// fields (`world = [[0, -1, 0], 0.5, ...]`), where each value would mean
/// what its place means: a swapped pair of restitutions would go unseen.
struct Table<T>(T);

/// What a [`Table`] of this section is called in a message.
trait Section {
    const EXPECTING: &'static str;
}

impl<T> std::ops::Deref for Table<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<'de, T: Deserialize<'de> + Section> Deserialize<'de> for Table<T> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct OnlyMaps<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de> + Section> serde::de::Visitor<'de> for OnlyMaps<T> {
            type Value = T;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(T::EXPECTING)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
                T::deserialize(serde::de::value::MapAccessDeserializer::new(map))
            }
        }
        deserializer
            .deserialize_map(OnlyMaps(std::marker::PhantomData))
            .map(Table)
    }
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a [lesson] table (title, idea, equation, contacts)"
)]
struct RawLesson {
    title: Option<Spanned<String>>,
    idea: Option<Spanned<String>>,
    equation: Option<Spanned<String>>,
    contacts: Option<bool>,
}

impl Section for RawLesson {
    const EXPECTING: &'static str = "a [lesson] table (title, idea, equation, contacts)";
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [world] table of settings")]
struct RawWorld {
    gravity: Option<Spanned<Numbers<3>>>,
    dt: Option<Spanned<f64>>,
    integrator: Option<Integrator>,
    wall_mode: Option<WallMode>,
    wall_restitution: Option<Spanned<f64>>,
    pair_collisions: Option<bool>,
    pair_restitution: Option<Spanned<f64>>,
    broad_phase: Option<BroadPhase>,
    substeps: Option<Spanned<Whole>>,
    rest_threshold: Option<Spanned<f64>>,
    rest_steps: Option<Spanned<f64>>,
    projection_passes: Option<Spanned<Whole>>,
    support: Option<Spanned<bool>>,
    sleep: Option<Spanned<bool>>,
    seed: Option<Spanned<Whole>>,
}

impl Section for RawWorld {
    const EXPECTING: &'static str = "a [world] table of settings";
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a [[body]] table (position, velocity, radius, mass)"
)]
struct RawBody {
    position: Spanned<Numbers<3>>,
    velocity: Option<Spanned<Numbers<3>>>,
    radius: Spanned<f64>,
    mass: Spanned<f64>,
}

impl Section for RawBody {
    const EXPECTING: &'static str = "a [[body]] table (position, velocity, radius, mass)";
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a [[spawn]] table (count, radius, speed, ...)"
)]
struct RawSpawn {
    count: Spanned<Whole>,
    radius: Spanned<Numbers<2>>,
    speed: Option<Spanned<Numbers<2>>>,
    mass_law: Option<MassLawKind>,
    density: Option<Spanned<f64>>,
    mass: Option<Spanned<f64>>,
    #[serde(default)]
    overlap: bool,
}

impl Section for RawSpawn {
    const EXPECTING: &'static str = "a [[spawn]] table (count, radius, speed, ...)";
}

/// A number as the command line reads it: `-0` is 0, which otherwise
/// prints with a sign (`c_r -0`). Adding +0 turns -0 into +0 and leaves
/// every other number as it is.
fn unsigned(x: f64) -> f64 {
    x + 0.0
}

/// An array of exactly `N` numbers: a longer one is refused, not cut.
#[derive(Clone, Copy, Debug)]
struct Numbers<const N: usize>([f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Numbers<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v: Vec<f64> = Vec::<f64>::deserialize(d)?
            .into_iter()
            .map(unsigned)
            .collect();
        <[f64; N]>::try_from(v.as_slice())
            .map(Numbers)
            .map_err(|_| {
                serde::de::Error::invalid_length(
                    v.len(),
                    &format!("an array of {N} numbers").as_str(),
                )
            })
    }
}

/// A number where a whole number goes (`count`, `substeps`,
/// `projection_passes`, `seed`): an integer, or a float read back from its
/// text, so that `2.0` and `1e3` are taken and `2.5` is refused as the
/// command line takes and refuses them ([`Checker::whole`]).
#[derive(Clone, Copy, Debug)]
enum Whole {
    Integer(i128),
    Float,
}

impl<'de> Deserialize<'de> for Whole {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct AnyNumber;
        impl serde::de::Visitor<'_> for AnyNumber {
            type Value = Whole;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a whole number")
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Whole, E> {
                Ok(Whole::Integer(v.into()))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Whole, E> {
                Ok(Whole::Integer(v.into()))
            }
            fn visit_i128<E: serde::de::Error>(self, v: i128) -> Result<Whole, E> {
                Ok(Whole::Integer(v))
            }
            fn visit_f64<E: serde::de::Error>(self, _: f64) -> Result<Whole, E> {
                Ok(Whole::Float)
            }
        }
        d.deserialize_any(AnyNumber)
    }
}

/// Default density of spawned spheres, kg/m^3 (water).
pub(crate) const DEFAULT_DENSITY: f64 = 1000.0;

struct Checker<'a> {
    origin: &'a str,
    source: &'a str,
}

impl Checker<'_> {
    fn error(&self, span: Range<usize>, field: String, message: String) -> SceneError {
        SceneError::new(self.origin, message)
            .field(field)
            .at_offset(self.source, span.start)
    }

    fn check(
        &self,
        value: &Spanned<f64>,
        field: impl Into<String>,
        rule: impl Fn(f64) -> Result<f64, String>,
    ) -> Result<f64, SceneError> {
        let field = field.into();
        let text = self.source.get(value.span()).unwrap_or("");
        self.read_as_typed(text, value.span(), &field)?;
        rule(unsigned(*value.get_ref())).map_err(|m| self.error(value.span(), field, m))
    }

    /// A whole number in `min..=max`, read exactly as written
    /// ([`whole_number_written`]): the integer, or the float's own text;
    /// a message quotes the text.
    fn whole<T: TryFrom<u64>>(
        &self,
        value: &Spanned<Whole>,
        field: &str,
        min: u64,
        max: u64,
    ) -> Result<T, SceneError> {
        let written = self.source.get(value.span()).unwrap_or("");
        let text = match value.get_ref() {
            Whole::Integer(n) => n.to_string(),
            Whole::Float => written.replace('_', ""),
        };
        whole_number_written(&text, written, min, max)
            .map_err(|m| self.error(value.span(), field.into(), m))
    }

    /// A text of the `[lesson]` table, at most `most` characters.
    fn text(&self, text: Spanned<String>, field: &str, most: usize) -> Result<String, SceneError> {
        let chars = text.get_ref().chars().count();
        if chars > most {
            return Err(self.error(
                text.span(),
                field.into(),
                format!("at most {most} characters, got {chars}"),
            ));
        }
        // A tab is a space between words: the panel wraps at spaces, and
        // a terminal cell shows no tab.
        Ok(text.into_inner().replace('\t', " "))
    }

    /// [`Checker::check`] for an array of numbers.
    fn check_numbers<const N: usize>(
        &self,
        value: &Spanned<Numbers<N>>,
        field: impl Into<String>,
        rule: impl Fn([f64; N]) -> Result<[f64; N], String>,
    ) -> Result<[f64; N], SceneError> {
        let field = field.into();
        let text = self.source.get(value.span()).unwrap_or("");
        // The array's numbers, its comments (to each line's end) left out
        // first: a comment may hold commas and numbers of its own.
        let bare: String = text
            .lines()
            .map(|l| l.split('#').next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join(" ");
        let inside = bare.trim().trim_start_matches('[').trim_end_matches(']');
        for item in inside.split(',') {
            self.read_as_typed(item.trim(), value.span(), &field)?;
        }
        rule(value.get_ref().0).map_err(|m| self.error(value.span(), field, m))
    }

    /// A number typed as something other than 0 that the reader took as 0,
    /// as 64-bit numbers hold nothing nearer 0 than about 5e-324
    /// (`rest_threshold = 1e-400` turned the threshold off).
    fn read_as_typed(&self, text: &str, span: Range<usize>, field: &str) -> Result<(), SceneError> {
        let plain = text.replace('_', "");
        match plain.parse::<f64>() {
            Ok(v) if v == 0.0 && !rules::typed_as_zero(&plain) => Err(self.error(
                span,
                field.to_string(),
                format!("{}; write 0 if 0 is meant", rules::read_as_zero(text)),
            )),
            _ => Ok(()),
        }
    }
}

/// Parts of a dotted key or table name the TOML reader takes at most; it
/// refuses more with a bare "recursion limit" that names no place.
const MOST_KEY_PARTS: usize = 80;

/// The TOML reader's "recursion limit", said and placed: at the first
/// line whose key or table name has more than [`MOST_KEY_PARTS`] parts
/// (counting its dots outside quotes), where there is one.
fn deep_key(source: &str, origin: &str) -> SceneError {
    let error = SceneError::new(
        origin,
        format!(
            "a key or table name of more than {MOST_KEY_PARTS} dotted parts, more than the TOML \
             reader takes (a scene's names have at most two: world.dt)"
        ),
    );
    let mut offset = 0;
    for line in source.split_inclusive('\n') {
        let name = line.split('=').next().unwrap_or(line);
        let mut quoted = None;
        let dots = name
            .chars()
            .filter(|&c| {
                match quoted {
                    Some(q) if c == q => quoted = None,
                    None if c == '"' || c == '\'' => quoted = Some(c),
                    _ => {}
                }
                quoted.is_none() && c == '.'
            })
            .count();
        if dots >= MOST_KEY_PARTS {
            let indent = line.len() - line.trim_start().len();
            return error.at_offset(source, offset + indent);
        }
        offset += line.len();
    }
    error
}

/// `message` with what the source holds where it points (`at`, in the
/// line `line`): the key given twice, as its line writes it (a dotted key
/// whole), or a date or time where a number goes (which the parser calls
/// a map).
fn in_source_words(message: &str, at: &str, line: &str) -> String {
    let line = line.trim();
    let key = match line.strip_prefix('[') {
        Some(header) => header.trim_start_matches('[').split(']').next(),
        None => line.split('=').next(),
    }
    .unwrap_or("")
    .trim();
    if message == "duplicate key" && !key.is_empty() && key.len() <= 100 {
        return format!("duplicate key: {key} is given twice");
    }
    if message.starts_with("invalid type: map,")
        && at.trim().starts_with(|c: char| c.is_ascii_digit())
    {
        return message.replacen("map", "a date or time", 1);
    }
    message.to_string()
}

/// A message of the TOML reader in the words of the scene format: Rust's
/// type names (`f64`, `i128`) become what the field takes.
fn in_plain_words(message: &str) -> String {
    let mut m = message.to_string();
    // An integer too large for any type: out of the field's range.
    if m.contains(" as i128") {
        m = m
            .replace(" as i128", "")
            .replace("invalid type:", "invalid value:");
    }
    for (rust, plain) in [
        ("expected f64", "expected a number"),
        ("expected a boolean", "expected true or false"),
        (
            "floating-point number overflowed",
            "the number is beyond the largest there is (about 1.8e308)",
        ),
        (
            "integer number overflowed",
            "a whole number too large to read (none of the format's whole numbers goes past \
             18446744073709551615); where any number goes, write it with a point or an \
             exponent",
        ),
    ] {
        m = m.replace(rust, plain);
    }
    // A whole number past 64 bits where a number (f64) goes: TOML reads
    // digits without a point or exponent as an integer.
    if let Some(digits) = m
        .strip_prefix("invalid value: integer `")
        .and_then(|rest| rest.strip_suffix("`, expected a number"))
    {
        m = format!(
            "{digits} is a whole number too large to read as one (TOML reads digits without a \
             point as a 64-bit integer); write it with a point or an exponent, as {:e}",
            digits.parse::<f64>().unwrap_or(f64::NAN)
        );
    }
    m
}

/// A bound on the memory (bytes) reading `text` as a scene takes: the
/// reader holds every table, key and value with its place in the file, so
/// the cost follows what the text holds more than its length. Counted
/// from the characters that make each: a table (a header, `{`, a dot
/// between keys), a key (`=`), a value in a list (`,`), and each byte.
/// Measured on files of 3 MB of one shape each, refused after reading (an
/// unknown key at the end), from their peak resident memory: about 1,250
/// bytes a table of dotted keys, 150 to 200 a value in a list, 360 a key,
/// 50 to 60 a byte for `[[body]]` entries; the bound is 1.2 to 4.9 times
/// what twelve such shapes took. A dot between two digits is a number's
/// (a key of digits alone, as `1.2.3`, is counted as a number).
pub(crate) fn reading_bytes(text: &[u8]) -> f64 {
    let (mut tables, mut keys, mut items) = (0u64, 0u64, 0u64);
    let mut line_start = true;
    for (k, &c) in text.iter().enumerate() {
        let digit = |at: Option<&u8>| at.is_some_and(u8::is_ascii_digit);
        match c {
            b'[' if line_start => tables += 1,
            b'{' => tables += 1,
            b'.' if !(k > 0 && digit(text.get(k - 1)) && digit(text.get(k + 1))) => tables += 1,
            b'=' => keys += 1,
            b',' => items += 1,
            _ => {}
        }
        // A header's `[` is the first of its line (`[[` counts once).
        line_start = c == b'\n' || (line_start && c.is_ascii_whitespace());
    }
    READ_TABLE_BYTES * tables as f64
        + READ_KEY_BYTES * keys as f64
        + READ_ITEM_BYTES * items as f64
        + READ_BYTES_PER_BYTE * text.len() as f64
}

const READ_TABLE_BYTES: f64 = 1500.0;
const READ_KEY_BYTES: f64 = 450.0;
const READ_ITEM_BYTES: f64 = 250.0;
const READ_BYTES_PER_BYTE: f64 = 8.0;

/// Parse and check a scene. `origin` names the source in messages (a path,
/// or `lesson NAME`); `name` is the scene's short name.
pub fn parse_scene(source: &str, origin: &str, name: &str) -> Result<Scene, SceneError> {
    let toml_error = |e: toml::de::Error, field: Option<String>| {
        let message = e.message().trim_end();
        if e.span().is_none() && message == "recursion limit" {
            return deep_key(source, origin);
        }
        let at = e.span().and_then(|span| source.get(span)).unwrap_or("");
        // The line the error points into.
        let line = e
            .span()
            .and_then(|span| {
                let start = source.get(..span.start)?.rfind('\n').map_or(0, |k| k + 1);
                source[start..].lines().next()
            })
            .unwrap_or("");
        let said = in_source_words(&in_plain_words(message), at, line);
        let mut error = SceneError::new(origin, said);
        error.field = field;
        match e.span() {
            Some(span) => error.at_offset(source, span.start),
            None => error,
        }
    };
    let document = toml::Deserializer::parse(source).map_err(|e| toml_error(e, None))?;
    let raw: RawScene = serde_path_to_error::deserialize(document).map_err(|e| {
        let field = field_path(e.path());
        toml_error(e.into_inner(), field)
    })?;
    let ck = Checker { origin, source };

    let mut world = WorldConfig::default();
    let mut seed = 1;
    if let Some(w) = raw.world {
        if let Some(g) = &w.gravity {
            world.gravity =
                Vec3::from_array(ck.check_numbers(g, "world.gravity", rules::gravity)?);
        }
        if let Some(dt) = &w.dt {
            world.dt = ck.check(dt, "world.dt", rules::dt)?;
        }
        if let Some(c) = &w.wall_restitution {
            world.wall_restitution = ck.check(c, "world.wall_restitution", rules::restitution)?;
        }
        if let Some(e) = &w.pair_restitution {
            world.pair_restitution = ck.check(e, "world.pair_restitution", rules::restitution)?;
        }
        if let Some(k) = &w.substeps {
            world.substeps = ck.whole(k, "world.substeps", 1, rules::MAX_SUBSTEPS.into())?;
        }
        if let Some(v) = &w.rest_threshold {
            world.rest_threshold = ck.check(v, "world.rest_threshold", rules::non_negative)?;
        }
        if let Some(v) = &w.rest_steps {
            world.rest_steps = ck.check(v, "world.rest_steps", rules::rest_steps)?;
        }
        if let Some(k) = &w.projection_passes {
            world.projection_passes = ck.whole(
                k,
                "world.projection_passes",
                1,
                rules::MAX_PROJECTION_PASSES.into(),
            )?;
        }
        world.integrator = w.integrator.unwrap_or(world.integrator);
        world.wall_mode = w.wall_mode.unwrap_or(world.wall_mode);
        world.pair_collisions = w.pair_collisions.unwrap_or(world.pair_collisions);
        world.support = w.support.as_ref().map_or(world.support, |s| *s.get_ref());
        world.sleep = w.sleep.as_ref().map_or(world.sleep, |s| *s.get_ref());
        world.broad_phase = w.broad_phase.unwrap_or(world.broad_phase);
        if let Some(s) = &w.seed {
            seed = ck.whole(s, "world.seed", 0, u64::MAX)?;
        }
        if let Some(asked) = &w.support
            && world.support
            && let Some(why) = world.support_idle()
        {
            return Err(ck.error(
                asked.span(),
                "world.support".into(),
                format!("support = true, but the support pass would not run: {why}"),
            ));
        }
        if let Some(asked) = &w.sleep
            && let Some(why) = world.sleep_idle()
        {
            return Err(ck.error(
                asked.span(),
                "world.sleep".into(),
                format!("sleep = true, but no sphere would sleep: {why}"),
            ));
        }
    }

    let mut bodies = Vec::with_capacity(raw.body.len());
    for (k, b) in raw.body.iter().enumerate() {
        let f = |name: &str| format!("body[{k}].{name}");
        let raw = b.get_ref();
        let radius = ck.check(&raw.radius, f("radius"), rules::radius)?;
        let position = ck.check_numbers(&raw.position, f("position"), |p| {
            rules::inside_box(p, radius)
        })?;
        let velocity = match &raw.velocity {
            Some(v) => ck.check_numbers(v, f("velocity"), rules::velocity)?,
            None => [0.0; 3],
        };
        let mass = ck.check(&raw.mass, f("mass"), rules::mass)?;
        bodies.push(Body {
            position: Vec3::from_array(position),
            velocity: Vec3::from_array(velocity),
            radius,
            mass,
        });
    }

    let mut spawns = Vec::with_capacity(raw.spawn.len());
    let mut spawn_offsets = Vec::with_capacity(raw.spawn.len());
    for (k, s) in raw.spawn.iter().enumerate() {
        let f = |name: &str| format!("spawn[{k}].{name}");
        let raw = s.get_ref();
        let count = ck.whole(&raw.count, &f("count"), 0, rules::MAX_BODIES as u64)?;
        let radius =
            ck.check_numbers(&raw.radius, f("radius"), |r| rules::range(r, rules::radius))?;
        let speed = match &raw.speed {
            Some(v) => ck.check_numbers(v, f("speed"), |r| rules::range(r, rules::speed))?,
            None => [0.0, 0.0],
        };
        let here = |field: String, message: &str| ck.error(s.span(), field, message.to_string());
        let (volume, constant) = (MassLawKind::Volume, MassLawKind::Constant);
        let mass_law = match raw.mass_law.unwrap_or(volume) {
            MassLawKind::Volume => {
                if raw.mass.is_some() {
                    return Err(here(
                        f("mass"),
                        &format!(
                            "applies only with mass_law = \"{constant}\"; with \"{volume}\" set density"
                        ),
                    ));
                }
                let law = |density| MassLaw::Volume { density };
                // The masses the law gives at both ends of the radius range
                // must be valid masses.
                let density_rule = |d: f64| {
                    rules::positive(d)?;
                    for r in radius {
                        rules::mass(law(d).mass(r)).map_err(|m| {
                            format!(
                                "gives a sphere of radius {} a mass that {m}",
                                rules::show(r)
                            )
                        })?;
                    }
                    Ok(d)
                };
                let density = match &raw.density {
                    Some(d) => ck.check(d, f("density"), density_rule)?,
                    None => density_rule(DEFAULT_DENSITY).map_err(|m| {
                        here(
                            f("density"),
                            &format!("{DEFAULT_DENSITY} (the default) {m}"),
                        )
                    })?,
                };
                law(density)
            }
            MassLawKind::Constant => {
                if raw.density.is_some() {
                    return Err(here(
                        f("density"),
                        &format!(
                            "applies only with mass_law = \"{volume}\"; with \"{constant}\" set mass"
                        ),
                    ));
                }
                let Some(mass) = &raw.mass else {
                    return Err(here(
                        f("mass"),
                        &format!("is required with mass_law = \"{constant}\""),
                    ));
                };
                MassLaw::Constant {
                    mass: ck.check(mass, f("mass"), rules::mass)?,
                }
            }
        };
        spawns.push(Spawn {
            count,
            radius,
            speed,
            mass_law,
            overlap: raw.overlap,
        });
        spawn_offsets.push(s.span().start);
    }

    let info = match raw.lesson {
        Some(Table(l)) => {
            let text = |t: Option<Spanned<String>>, field: &str, most: usize| {
                t.map(|t| ck.text(t, field, most)).transpose()
            };
            Some(LessonInfo {
                title: text(l.title, "lesson.title", rules::MAX_TITLE_CHARS)?
                    .unwrap_or_else(|| name.to_string()),
                idea: text(l.idea, "lesson.idea", rules::MAX_LESSON_TEXT_CHARS)?
                    .unwrap_or_default(),
                equation: text(l.equation, "lesson.equation", rules::MAX_LESSON_TEXT_CHARS)?
                    .unwrap_or_default(),
                contacts: l.contacts.unwrap_or(false),
            })
        }
        None => None,
    };

    let lines = LineIndex::new(source);
    let scene = Scene {
        name: name.to_string(),
        origin: origin.to_string(),
        info,
        world,
        seed,
        bodies,
        spawns,
        spawn_lines: spawn_offsets.iter().map(|&o| lines.line(o)).collect(),
        sized_for: None,
    };
    scene.check_size()?;
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_given_twice_and_a_date_for_a_number_are_named_as_the_file_has_them() {
        let said = |text: &str| {
            parse_scene(text, "t.toml", "t")
                .expect_err("refused")
                .to_string()
        };
        assert!(
            said("[world]\ndt = 0.01\ndt = 0.02\n")
                .starts_with("t.toml:3:1: duplicate key: dt is given twice"),
            "{}",
            said("[world]\ndt = 0.01\ndt = 0.02\n")
        );
        assert!(
            said("[world]\n[world]\n")
                .starts_with("t.toml:2:2: duplicate key: world is given twice")
        );
        // A dotted key and a dotted header are named whole.
        let e = said("[world]\ngravity.x = 1\ngravity.x = 2\n");
        assert!(e.contains("duplicate key: gravity.x is given twice"), "{e}");
        let e = said("[world.sub]\n[world.sub]\n");
        assert!(e.contains("duplicate key: world.sub is given twice"), "{e}");
        for value in ["1979-05-27", "07:32:00", "1979-05-27T07:32:00Z"] {
            let e = said(&format!("[world]\ndt = {value}\n"));
            assert!(
                e.contains("world.dt: invalid type: a date or time, expected a number"),
                "{e}"
            );
        }
        // A table where a number goes is still called one.
        let e = said("[world]\ndt = { a = 1 }\n");
        assert!(e.contains("invalid type: map, expected a number"), "{e}");
    }

    #[test]
    fn minus_zero_is_read_as_zero_as_the_command_line_reads_it() {
        let s = parse_scene(
            "[world]\nwall_restitution = -0.0\nrest_threshold = -0.0\n\
             gravity = [-0.0, -9.81, -0.0]\n\
             [[body]]\nposition = [0.5, 0.5, 0.5]\nvelocity = [-0.0, 1.0, -0.0]\n\
             radius = 0.1\nmass = 1.0\n",
            "t.toml",
            "t",
        )
        .expect("valid");
        let zero = 0.0_f64.to_bits();
        assert_eq!(s.world.wall_restitution.to_bits(), zero);
        assert_eq!(s.world.rest_threshold.to_bits(), zero);
        assert_eq!(s.world.gravity.x.to_bits(), zero);
        assert_eq!(s.world.gravity.z.to_bits(), zero);
        assert_eq!(s.bodies[0].velocity.x.to_bits(), zero);
        assert_eq!(s.bodies[0].velocity.y, 1.0);
    }

    #[test]
    fn the_lesson_texts_are_bounded_in_characters() {
        let body = "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n";
        let read =
            |lesson: &str| parse_scene(&format!("[lesson]\n{lesson}\n{body}"), "t.toml", "t");
        // Characters, not bytes: a thousand of two bytes each is a title.
        let title = "\u{e9}".repeat(1000);
        let s = read(&format!("title = \"{title}\"")).expect("at the bound");
        assert_eq!(s.info.expect("lesson").title, title);
        let e = read(&format!("title = \"{}\"", "a".repeat(1001)))
            .expect_err("past it")
            .to_string();
        assert!(
            e.starts_with("t.toml:2:9: lesson.title: at most 1000 characters, got 1001"),
            "{e}"
        );
        for field in ["idea", "equation"] {
            assert!(read(&format!("{field} = \"{}\"", "b ".repeat(5000))).is_ok());
            let e = read(&format!("{field} = \"{}\"", "b ".repeat(5001)))
                .expect_err("past it")
                .to_string();
            assert!(
                e.contains(&format!(
                    "lesson.{field}: at most 10000 characters, got 10002"
                )),
                "{e}"
            );
        }
        // A tab between words is a space, which the panel wraps at.
        let s = read("title = \"a\\tb\"\nidea = \"tab\\there\"").expect("tabs");
        let info = s.info.expect("lesson");
        assert_eq!((&info.title[..], &info.idea[..]), ("a b", "tab here"));
    }

    #[test]
    fn whole_numbers_are_taken_in_the_notations_of_the_command_line_and_of_toml() {
        let body = "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n";
        let read = |world: &str| parse_scene(&format!("[world]\n{world}\n{body}"), "t.toml", "t");
        let s = read("substeps = 2.0\nprojection_passes = 1e1\nseed = 3e0").expect("whole");
        assert_eq!(
            (s.world.substeps, s.world.projection_passes, s.seed),
            (2, 10, 3)
        );
        // TOML's other ways of writing an integer, and underscores in a float.
        let s = read("substeps = 0x10\nprojection_passes = 1_2.0\nseed = 1.8446744073709551615e19")
            .expect("whole");
        assert_eq!(
            (s.world.substeps, s.world.projection_passes, s.seed),
            (16, 12, u64::MAX)
        );
        // The float's text is read, not its rounded value.
        for (world, said) in [
            (
                "substeps = 2.5",
                "world.substeps: must be a whole number from 1 to 10000, got 2.5",
            ),
            ("substeps = 2.0000000000000001", "got 2.0000000000000001"),
            (
                "projection_passes = inf",
                "world.projection_passes: must be a whole number from 1 to 64 (digits, or a \
                 form such as 1e6), got 'inf'",
            ),
            (
                "seed = -1.0",
                "world.seed: must be a whole number from 0 to 18446744073709551615, got -1.0",
            ),
            (
                "seed = 1.8446744073709551616e19",
                "got 1.8446744073709551616e19",
            ),
            (
                "seed = \"x\"",
                "world.seed: invalid type: string \"x\", expected a whole number",
            ),
            // Quoted as written.
            ("substeps = 0xFFFFF", "got 0xFFFFF"),
            ("substeps = 1e1_0", "got 1e1_0"),
            (
                "substeps = 1_0.5",
                "world.substeps: must be a whole number from 1 to 10000, got 1_0.5",
            ),
        ] {
            let e = read(world).expect_err(world).to_string();
            assert!(e.contains(said), "{world}: {e}");
        }
        // A spawn's count too.
        let spawn = |count: &str| {
            parse_scene(
                &format!("[[spawn]]\ncount = {count}\nradius = [0.01, 0.02]\n"),
                "t.toml",
                "t",
            )
        };
        assert_eq!(spawn("1e1").expect("whole").spawns[0].count, 10);
        let e = spawn("2.0000000000000001")
            .expect_err("not whole")
            .to_string();
        assert!(
            e.contains(
                "spawn[0].count: must be a whole number from 0 to 10000000, got 2.0000000000000001"
            ),
            "{e}"
        );
    }

    #[test]
    fn the_memory_reading_takes_is_counted_from_what_the_text_holds() {
        let bound = |tables: f64, keys: f64, items: f64, text: &str| {
            READ_TABLE_BYTES * tables
                + READ_KEY_BYTES * keys
                + READ_ITEM_BYTES * items
                + READ_BYTES_PER_BYTE * text.len() as f64
        };
        // A header is one table (`[[` once), its numbers' points none.
        let body = "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n";
        assert_eq!(reading_bytes(body.as_bytes()), bound(1.0, 3.0, 2.0, body));
        // Dotted keys and inline tables are tables each; a `[` inside a
        // line is a list's.
        let dotted = "a.b.c = 1\nx = [{y = {}}]\n  [t]\n";
        assert_eq!(
            reading_bytes(dotted.as_bytes()),
            bound(5.0, 3.0, 0.0, dotted)
        );
    }
}
