//! The selection: a sphere or a pair the learner picked (a click, or `o`
//! for the next collision), and its numbers: what the lesson's equations
//! give for exactly these spheres at this step.
//!
//! A selection names spheres by scene index, so it survives stepping back
//! and forth and the slot moves of large worlds. For a selected pair in
//! contact at this step, [`inspect`] replays the step from the history's
//! previous state up to the moment the pair is resolved (integration, then
//! the contacts before it in the solver's order), and applies the lesson's
//! projection and V1/V2 to it with the same functions the solver uses: the
//! numbers shown are the step's own, not a second model. The replay is
//! exact for the discrete methods with one sub-step in worlds kept in
//! scene order (every lesson); elsewhere the panel says why there are no
//! pair numbers.
//!
//! Owns the selection's readouts; it changes neither the world nor the
//! history.

use super::history::History;
use crate::sim::contact::{approach_speed, normal_speeds_after, solve_contacts};
use crate::sim::large::{SPATIAL_ORDER_MIN_BODIES, is_large};
use crate::sim::sleep::is_asleep;
use crate::sim::support::Support;
use crate::sim::walls::{AxisImpact, wall_impacts};
use crate::sim::{Bodies, Contact, Integrator, Vec3, World, WorldConfig};

/// What the learner picked, by scene index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Selection {
    Sphere(u32),
    /// Two spheres, the lower index first.
    Pair(u32, u32),
}

impl Selection {
    pub fn pair(a: u32, b: u32) -> Self {
        Selection::Pair(a.min(b), a.max(b))
    }

    /// The scene indices selected.
    pub(crate) fn ids(self) -> Vec<u32> {
        match self {
            Selection::Sphere(a) => vec![a],
            Selection::Pair(a, b) => vec![a, b],
        }
    }

    pub(crate) fn contains(self, id: u32) -> bool {
        self.ids().contains(&id)
    }
}

/// A collision a sphere took part in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// The step that resolved it (the world's step count after it).
    pub steps: u64,
    pub time: f64,
    pub kind: ImpactKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImpactKind {
    /// A wall: the axis (0 x, 1 y, 2 z) and whether it is the far wall.
    Wall { axis: usize, far: bool },
    /// Another sphere, by scene index.
    Sphere(u32),
}

impl ImpactKind {
    pub(crate) fn describe(self) -> String {
        match self {
            ImpactKind::Wall {
                axis: 1,
                far: false,
            } => "the floor".into(),
            ImpactKind::Wall { axis: 1, far: true } => "the ceiling".into(),
            ImpactKind::Wall { axis, far } => format!(
                "the {} = {} wall",
                ["x", "y", "z"][axis],
                if far { 1 } else { 0 }
            ),
            ImpactKind::Sphere(id) => format!("sphere {id}"),
        }
    }
}

/// One selected sphere's numbers now.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereReadout {
    pub id: u32,
    pub position: Vec3,
    pub velocity: Vec3,
    pub radius: f64,
    pub mass: f64,
    /// Position and velocity one step earlier, when the history has them.
    pub previous: Option<(Vec3, Vec3)>,
    /// The newest collision it took part in, at or before this step.
    pub last_impact: Option<Impact>,
    /// It met a wall in this step (the wall stage reversed a component).
    pub wall_now: Option<ImpactKind>,
    /// It took part in one of the step's contacts (for the continuous
    /// method: an impact with another sphere).
    pub in_contact: bool,
    /// How the wall stage resolved its impacts in this step (resting
    /// contacts with a wall among them), one per wall met, in axis order,
    /// replayed from the step before where the replay is exact; empty
    /// otherwise.
    pub wall_impacts: Vec<AxisImpact>,
    /// It slept through the step, which left it where it was.
    pub asleep: bool,
}

/// A selected pair's contact at this step, in the lesson's terms. Sphere
/// 1 is the lower scene index; `n` points from sphere 1 to sphere 2.
#[derive(Clone, Debug, PartialEq)]
pub struct PairReadout {
    pub normal: Vec3,
    /// `delta = (r1 + r2) - d` when the step found the contact, m.
    pub penetration: f64,
    pub mass: [f64; 2],
    /// `w_k / (w1 + w2)`: each sphere's share of the correction.
    pub share: [f64; 2],
    /// Centres when the pair was resolved: before and after the correction.
    pub before: [Vec3; 2],
    pub after: [Vec3; 2],
    /// Normal speeds `v1 = v_1 . n`, `v2 = v_2 . n` before the impulse.
    pub v_normal: [f64; 2],
    /// Each sphere's speed across `n`, `|v - (v . n) n|`, which the
    /// impulse, along `n`, leaves as it was.
    pub v_across: [f64; 2],
    /// The restitution used (0 below the rest threshold).
    pub e: f64,
    /// The lesson's `V1`, `V2`; `None` when the pair was already separating
    /// (no impulse).
    pub v_after: Option<[f64; 2]>,
    /// The pair's momentum and kinetic energy before and after resolving.
    pub momentum: [Vec3; 2],
    pub kinetic: [f64; 2],
    /// With the support pass: the normal speeds the pair ended the step
    /// with, after that pass held the step's resting contacts together.
    pub step_end: Option<[f64; 2]>,
}

/// Why a pair's impact used the restitution it did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairRule {
    /// The scene's `e`.
    Scene,
    /// 0: slower than the rest threshold.
    RestThreshold,
    /// 0: resting contact, slower than gravity adds along the normal in
    /// the resting window.
    Resting,
}

impl PairReadout {
    /// The rule that chose this impact's restitution, under the step's
    /// parameters `c`.
    pub fn rule(&self, c: &WorldConfig) -> PairRule {
        if self.e == c.pair_restitution {
            PairRule::Scene
        } else if self.v_normal[0] - self.v_normal[1] < c.rest_threshold {
            PairRule::RestThreshold
        } else {
            PairRule::Resting
        }
    }
}

/// What the panel shows of a selection.
#[derive(Clone, Debug, PartialEq)]
pub struct Inspection {
    pub selection: Selection,
    pub spheres: Vec<SphereReadout>,
    pub pair: Option<PairReadout>,
    /// Why a selected pair has no numbers at this step.
    pub pair_note: Option<String>,
    /// The parameters the step to this state ran with (the world's own
    /// before any step): the readouts describe that step as it ran.
    pub config: WorldConfig,
    /// The first step whose impacts are among those given: a sphere's
    /// `last_impact` of `None` means none from that step on.
    pub impacts_known_from: u64,
    /// The steps taken to this state.
    pub steps: u64,
}

/// The slot of each selected sphere, or `None` when a sphere is gone (a
/// restart with fewer spheres).
fn slots_of(world: &World, selection: Selection) -> Option<Vec<usize>> {
    let ids = selection.ids();
    let b = &world.bodies;
    if ids.iter().any(|&id| id as usize >= b.len()) {
        return None;
    }
    let in_order = b.id.iter().enumerate().all(|(k, &s)| k == s as usize);
    Some(
        ids.iter()
            .map(|&id| {
                if in_order {
                    id as usize
                } else {
                    b.id.iter()
                        .position(|&s| s == id)
                        .expect("every id has a slot")
                }
            })
            .collect(),
    )
}

/// Whether `selection` names spheres the world has.
pub(crate) fn exists(world: &World, selection: Selection) -> bool {
    slots_of(world, selection).is_some()
}

/// The readouts of `selection` in `world` at its present step, with
/// `history` holding the step before (if it does) and `impacts` the
/// collisions logged for the selected spheres.
pub(crate) fn inspect(
    world: &World,
    history: &History,
    selection: Selection,
    impacts: &[(u32, Impact)],
    impacts_known_from: u64,
) -> Option<Inspection> {
    let slots = slots_of(world, selection)?;
    let b = &world.bodies;
    let previous = history.previous();
    let config = stepped_with(world, history);
    let spheres = selection
        .ids()
        .iter()
        .zip(&slots)
        .map(|(&id, &k)| {
            let before = previous.and_then(|p| p.of(id));
            let in_contact = in_contact(world, k);
            // A sphere that slept through the step met no wall: the step
            // left it where it was.
            let asleep =
                previous.is_some_and(|p| p.was_asleep(id)) && is_asleep(world.bodies.rest[k]);
            let replayed = before
                .filter(|_| !in_contact && !asleep)
                .and_then(|b| replayed_walls(world, config, k, b));
            SphereReadout {
                id,
                position: b.position[k],
                velocity: b.velocity[k],
                radius: b.radius[k],
                mass: b.mass[k],
                previous: before,
                last_impact: impacts
                    .iter()
                    .rev()
                    .find(|(s, i)| *s == id && i.steps <= world.steps)
                    .map(|(_, i)| *i),
                // A replay that ends where the sphere is tells; else the
                // velocity the step reversed near a wall.
                wall_now: match &replayed {
                    Some(impacts) => impacts.first().map(|i| ImpactKind::Wall {
                        axis: i.axis,
                        far: i.far,
                    }),
                    None => before.and_then(|(_, v0)| wall_met(world, config.dt, k, v0)),
                },
                wall_impacts: replayed.unwrap_or_default(),
                in_contact,
                // Asleep before and after: woken in the step, it moved.
                asleep: asleep && crate::sim::sleep::is_asleep(b.rest[k]),
            }
        })
        .collect();
    let (pair, pair_note) = match selection {
        Selection::Sphere(_) => (None, None),
        Selection::Pair(..) => match pair_readout(world, config, history, &slots) {
            Ok(p) => (Some(p), None),
            Err(why) => (None, Some(why)),
        },
    };
    Some(Inspection {
        selection,
        spheres,
        pair,
        pair_note,
        config: config.clone(),
        impacts_known_from,
        steps: world.steps,
    })
}

/// The wall a sphere met in the last step, judged from its velocity one
/// step earlier (`v0`) and now: a component reversed towards the inside
/// while the sphere is within that step's reach of the wall.
pub(crate) fn wall_reversal(v0: Vec3, x: Vec3, v: Vec3, r: f64, dt: f64) -> Option<ImpactKind> {
    (0..3).find_map(|axis| {
        let reach = (v0[axis].abs() + v[axis].abs()) * dt + 1e-9;
        if v0[axis] < 0.0 && v[axis] >= 0.0 && x[axis] - r <= reach {
            Some(ImpactKind::Wall { axis, far: false })
        } else if v0[axis] > 0.0 && v[axis] <= 0.0 && (1.0 - r) - x[axis] <= reach {
            Some(ImpactKind::Wall { axis, far: true })
        } else {
            None
        }
    })
}

/// The wall the sphere in slot `k` met in the world's last step of `dt`,
/// given its velocity `v0` one step earlier (see [`wall_reversal`]).
fn wall_met(world: &World, dt: f64, k: usize, v0: Vec3) -> Option<ImpactKind> {
    let b = &world.bodies;
    wall_reversal(v0, b.position[k], b.velocity[k], b.radius[k], dt)
}

/// Whether the sphere in slot `k` is in one of the last step's contacts.
fn in_contact(world: &World, k: usize) -> bool {
    world
        .contacts()
        .iter()
        .any(|p| p.i as usize == k || p.j as usize == k)
}

/// The wall impacts of the sphere in slot `k` in `world`'s last step, run
/// with the parameters `c` from its position and velocity `(x0, v0)` one
/// step earlier: its own integration, then the wall stage, for a sphere
/// in none of the step's contacts: empty when it met none. `None` when
/// something else moved it in that step (the support pass, sub-steps, the
/// continuous method's events): the replay must end where the sphere is,
/// to the bit.
fn replayed_walls(
    world: &World,
    c: &WorldConfig,
    k: usize,
    (x0, v0): (Vec3, Vec3),
) -> Option<Vec<AxisImpact>> {
    let supported = c.support_runs();
    if !c.integrator.is_discrete() || c.substeps > 1 || supported {
        return None;
    }
    let b = &world.bodies;
    let mut one: Bodies = std::iter::once(crate::sim::Body {
        position: x0,
        velocity: v0,
        radius: b.radius[k],
        mass: b.mass[k],
    })
    .collect();
    c.integrator.integrate(&mut one, c.gravity, c.dt);
    let (mut x, mut v) = (one.position[0], one.velocity[0]);
    let impacts = wall_impacts(x, v, b.radius[k], c, c.dt);
    for i in &impacts {
        (x[i.axis], v[i.axis]) = (i.position, i.velocity);
    }
    let r = b.radius[k];
    x = x.clamp(Vec3::splat(r), Vec3::splat(1.0 - r));
    let exact = x == b.position[k] && v == b.velocity[k];
    exact.then_some(impacts)
}

/// How the note of a pair the support pass caught as it landed begins
/// ([`pair_readout`]).
pub(crate) const LANDED: &str = "landed: ";

/// The contact of the pair in `slots` at this step, replayed with the
/// parameters `c` the step ran with.
fn pair_readout(
    world: &World,
    c: &WorldConfig,
    history: &History,
    slots: &[usize],
) -> Result<PairReadout, String> {
    let (s1, s2) = (slots[0], slots[1]);
    let (lo, hi) = (s1.min(s2), s1.max(s2));
    // The lesson's pass runs before the support pass and leaves it the
    // resting pairs: it is replayed as it ran, and the support pass's
    // part is the pair's speeds at the end of the step.
    let supported = c.support_runs();
    // A large world's pairs are never replayed, and its step shown may
    // keep no list (a step back, or nothing read it): say why first.
    if is_large(world.bodies.len())
        && let Some(why) = unreplayable(world, c)
    {
        return Err(why);
    }
    let Some(k) = world
        .contacts()
        .iter()
        .position(|c| c.i as usize == lo && c.j as usize == hi)
    else {
        let caught = near_landings(world, c, history);
        let near = world.near_pairs();
        if caught
            .iter()
            .any(|&k| near[k].i as usize == lo && near[k].j as usize == hi)
        {
            return Err(format!(
                "{LANDED}apart when the step began and closing slower than the \
                 resting speed, the support pass (Y) caught the pair within its margin of \
                 touching and held it as a resting contact, solved with the pile's others \
                 (so it may still close a little at the step's end): no lesson's V1/V2"
            ));
        }
        return Err("not in contact at this step".into());
    };
    if let Some(why) = unreplayable(world, c) {
        return Err(why);
    }
    let Some(mut bodies) = integrated(world, c, history) else {
        return Err("the state before this step is no longer kept".into());
    };
    let contacts = world.contacts();
    let rule = c
        .pair_rule()
        .with_resting(c.resting(c.dt))
        .with_support(supported);
    solve_contacts(&mut bodies, &contacts[..k], rule);
    let contact = &contacts[k];
    let n = contact.contact_normal;
    let u = approach_speed(bodies.velocity[lo], bodies.velocity[hi], n);
    // The lesson's pass leaves such a pair whole to the support pass: its
    // overlap as well as its speed. One parting slower than the figures
    // show (0.000 m/s) is at rest along n, as one closing that slowly is.
    if rule.left_to_support(u, n) && (u >= 0.0 || -u < 0.0005) {
        return Err(format!(
            "resting contact: closing at {:.3} m/s along n, under the {:.3} m/s \
             gravity adds along n in the resting window; the support pass (Y) \
             holds it with its neighbours, not the lesson's V1/V2",
            u.max(0.0),
            rule.resting.dot(n).abs()
        ));
    }
    if rule.left_to_support(u, n) {
        return Err(format!(
            "separating at {:.3} m/s along n: no impulse, and the lesson's pass \
             leaves its overlap to the support pass (Y)",
            -u
        ));
    }
    let mut readout = resolve_one(&bodies, contact, rule, s1 > s2);
    if supported {
        let end = |s: usize| world.bodies.velocity[s].dot(readout.normal);
        readout.step_end = Some([end(s1), end(s2)]);
    }
    Ok(readout)
}

/// Why the lesson's pass over the contacts of `world`'s last step, taken
/// with the parameters `c`, cannot be replayed pair by pair; `None` when
/// it can. The support pass runs after it and is left out: its part is
/// the pair's speeds at the end of the step.
fn unreplayable(world: &World, c: &WorldConfig) -> Option<String> {
    if c.integrator == Integrator::Continuous {
        return Some(
            "the continuous method resolves this impact at its own time \
                    inside the step: pair numbers are shown for the other methods"
                .into(),
        );
    }
    if c.projection_passes > 1 {
        return Some(format!(
            "{} projection passes move the pair again after its V1/V2: \
             pair numbers are shown only with one pass",
            c.projection_passes
        ));
    }
    if c.substeps > 1 {
        return Some(format!(
            "with {} sub-steps the contact is resolved in each: pair numbers \
             are shown only without sub-steps",
            c.substeps
        ));
    }
    if is_large(world.bodies.len()) {
        return Some(format!(
            "the lesson's V1/V2 with this pair's numbers are worked for worlds under \
             {} spheres",
            crate::scene::thousands(SPATIAL_ORDER_MIN_BODIES as u64)
        ));
    }
    None
}

/// The bodies of `world`'s last step (taken with the parameters `c`) after
/// its integration, from the state before it; `None` when that state is no
/// longer kept.
fn integrated(world: &World, c: &WorldConfig, history: &History) -> Option<Bodies> {
    let previous = history.previous()?;
    let mut bodies: Bodies = world.bodies.clone();
    bodies.position.copy_from_slice(previous.position);
    bodies.velocity.copy_from_slice(previous.velocity);
    bodies.rest.copy_from_slice(previous.rest);
    // The step integrated the spheres that were awake, and those it woke
    // (at its start, or as a pair touched them: `sleep::touch`), from rest.
    c.integrator.integrate_awake(&mut bodies, c.gravity, c.dt);
    let woken: Vec<u32> = (0..bodies.len())
        .filter(|&k| is_asleep(previous.rest[k]) && !is_asleep(world.bodies.rest[k]))
        .map(|k| k as u32)
        .collect();
    c.integrator
        .integrate_slots(&mut bodies, &woken, c.gravity, c.dt);
    Some(bodies)
}

/// The lesson's resolution of contact `c` in `bodies`, reported for the
/// pair with sphere 1 the lower scene index (`swapped` when that is `c.j`).
pub(crate) fn resolve_one(
    bodies: &Bodies,
    c: &Contact,
    rule: crate::sim::restitution::Restitution,
    swapped: bool,
) -> PairReadout {
    let (i, j) = (c.i as usize, c.j as usize);
    let n = c.contact_normal;
    let (w1, w2) = (bodies.inverse_mass[i], bodies.inverse_mass[j]);
    let (m1, m2) = (bodies.mass[i], bodies.mass[j]);
    let share = [w1 / (w1 + w2), w2 / (w1 + w2)];
    let before = [bodies.position[i], bodies.position[j]];
    let corr = c.penetration / (w1 + w2);
    let after = [before[0] - n * (w1 * corr), before[1] + n * (w2 * corr)];
    let (vi, vj) = (bodies.velocity[i], bodies.velocity[j]);
    let (v1, v2) = (vi.dot(n), vj.dot(n));
    // Whether the pair approaches, and its restitution, as the step
    // decided them (`contact::apply_pair_impulse`); the numbers shown are
    // the lesson's, from v1 and v2.
    let u = approach_speed(vi, vj, n);
    let approaching = u > 0.0;
    let e = if approaching { rule.at_pair(u, n) } else { 0.0 };
    let v_after = approaching.then(|| {
        let (a, b) = normal_speeds_after(m1, m2, v1, v2, e);
        [a, b]
    });
    let (vi2, vj2) = match v_after {
        Some([a, b]) => (vi + n * (a - v1), vj + n * (b - v2)),
        None => (vi, vj),
    };
    let ke = |a: Vec3, b: Vec3| 0.5 * m1 * a.length_squared() + 0.5 * m2 * b.length_squared();
    let readout = PairReadout {
        normal: n,
        penetration: c.penetration,
        mass: [m1, m2],
        share,
        before,
        after,
        v_normal: [v1, v2],
        v_across: [(vi - n * v1).length(), (vj - n * v2).length()],
        e,
        v_after,
        momentum: [vi * m1 + vj * m2, vi2 * m1 + vj2 * m2],
        kinetic: [ke(vi, vj), ke(vi2, vj2)],
        step_end: None,
    };
    if swapped { readout.swapped() } else { readout }
}

impl PairReadout {
    /// The same contact seen from the other sphere: `n` reversed.
    fn swapped(self) -> Self {
        let sw = |[a, b]: [f64; 2]| [b, a];
        let swv = |[a, b]: [Vec3; 2]| [b, a];
        Self {
            normal: -self.normal,
            mass: sw(self.mass),
            share: sw(self.share),
            before: swv(self.before),
            after: swv(self.after),
            v_normal: [-self.v_normal[1], -self.v_normal[0]],
            v_across: sw(self.v_across),
            v_after: self.v_after.map(|[a, b]| [-b, -a]),
            ..self
        }
    }
}

/// Whether `o` looks for collisions between spheres in `world` (it has
/// pair collisions and at least two spheres), rather than with the walls.
pub(crate) fn seeks_pairs(world: &World) -> bool {
    world.config.pair_collisions && world.bodies.len() >= 2
}

/// The collisions of the last step, for `o`, and how many of its pair
/// contacts took no impulse.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Collisions {
    /// In order, each once.
    pub found: Vec<Selection>,
    /// Pair contacts the replay of the lesson's pass met that took no
    /// impulse because their spheres were not approaching, and those left
    /// resting to the support pass; both 0 where the step was not replayed
    /// pair by pair.
    pub apart: usize,
    pub resting: usize,
    /// Whether the step was replayed pair by pair; when not, `found`
    /// holds only its first contact.
    pub replayed: bool,
}

/// [`collisions`] as `o` counts them while it follows sphere `follow`:
/// where spheres collide with each other, that sphere's wall collision in
/// the step counts too (the wall stage runs after the contacts). A wall is
/// told by the velocity it reversed, which a pair's impulse can reverse
/// too: for a sphere in one of the step's contacts it is not told (as the
/// panel's wall rows are not), and a collision with another sphere in the
/// step stops `o` there. Where the step was not replayed pair by pair
/// (only its first contact is known to be a collision), the sphere's
/// first contact of the step counts when something besides gravity
/// changed its velocity along that contact ([`pushed_by`]).
pub(crate) fn collisions_following(
    world: &World,
    history: &History,
    follow: Option<u32>,
) -> Collisions {
    let mut found = collisions(world, history);
    let (Some(a), true) = (follow, seeks_pairs(world)) else {
        return found;
    };
    let Some(k) = slots_of(world, Selection::Sphere(a)).map(|slots| slots[0]) else {
        return found;
    };
    if !in_contact(world, k) {
        if impacts_now(world, history, Selection::Sphere(a))
            .iter()
            .any(|(_, i)| matches!(i.kind, ImpactKind::Wall { .. }))
        {
            found.found.push(Selection::Sphere(a));
        }
    } else if !found.replayed && !found.found.iter().any(|c| c.contains(a)) {
        found.found.extend(pushed_by(world, history, k));
    }
    found
}

/// The first of the last step's contacts of the sphere in slot `k` that
/// pushed it: over the step, something besides gravity changed its
/// velocity (its velocity is not the one it began with plus `g dt`,
/// beyond rounding), and the change has a part along that contact's
/// normal, away from the other sphere. `None` when there is none, or that
/// velocity is no longer kept.
fn pushed_by(world: &World, history: &History, k: usize) -> Option<Selection> {
    let c = stepped_with(world, history);
    let (_, v0) = history.previous()?.of(world.bodies.id[k])?;
    let change = world.bodies.velocity[k] - (v0 + c.gravity * c.dt);
    let rounding = 1e-9 * (v0.length() + c.gravity.length() * c.dt) + f64::MIN_POSITIVE;
    let id = &world.bodies.id;
    world
        .contacts()
        .iter()
        .find(|p| {
            // The normal runs from i to j: i is pushed against it, j along it.
            let away = change.dot(p.contact_normal);
            (p.i as usize == k && away < -rounding) || (p.j as usize == k && away > rounding)
        })
        .map(|p| Selection::pair(id[p.i as usize], id[p.j as usize]))
}

/// The collisions of the last step, in order, each once, for `o`. Where
/// spheres collide with each other ([`seeks_pairs`]): the pair contacts in
/// the solver's order that took an impulse of the lesson's pass (their
/// spheres approaching when they were resolved, faster than the resting
/// speed when the support pass holds the slower ones; where the step
/// cannot be replayed pair by pair, only its first contact), with the
/// slower ones' landings: pairs apart when the step began that the support
/// pass held as they met (overlapping, then those it caught within its
/// margin, [`near_landings`]). Elsewhere: the spheres (by scene index)
/// whose velocity a wall reversed.
pub(crate) fn collisions(world: &World, history: &History) -> Collisions {
    let c = stepped_with(world, history);
    if seeks_pairs(world) {
        let contacts = world.contacts();
        let id = &world.bodies.id;
        let mut found: Vec<Selection> = Vec::new();
        let Replay {
            impulses,
            landings,
            resting,
        } = impulses(world, c, history).unwrap_or(Replay {
            impulses: (0..contacts.len().min(1)).collect(),
            landings: Vec::new(),
            resting: None,
        });
        let mut met = [&impulses[..], &landings[..]].concat();
        met.sort_unstable();
        // Then the pairs the support pass caught still apart and brought
        // to rest on each other in the step.
        let near = world.near_pairs();
        let caught = near_landings(world, c, history);
        let pairs = met.iter().map(|&k| &contacts[k]);
        for contact in pairs.chain(caught.iter().map(|&k| &near[k])) {
            let pair = Selection::pair(id[contact.i as usize], id[contact.j as usize]);
            // The continuous method lists a pair once for each impact.
            if !found.contains(&pair) {
                found.push(pair);
            }
        }
        let replayed = resting.is_some();
        let (apart, resting) = match resting {
            Some(resting) => (contacts.len() - met.len() - resting, resting),
            None => (0, 0),
        };
        return Collisions {
            found,
            apart,
            resting,
            replayed,
        };
    }
    if world.last.wall_impacts == 0 {
        return Collisions::default();
    }
    let Some(previous) = history.previous() else {
        return Collisions::default();
    };
    let b = &world.bodies;
    let mut hit: Vec<u32> = (0..b.len())
        .filter(|&k| {
            previous
                .of(b.id[k])
                .is_some_and(|(_, v0)| wall_met(world, c.dt, k, v0).is_some())
        })
        .map(|k| b.id[k])
        .collect();
    hit.sort_unstable();
    Collisions {
        found: hit.into_iter().map(Selection::Sphere).collect(),
        ..Collisions::default()
    }
}

/// What the replay of a step's lesson pass found.
struct Replay {
    /// The contacts that took an impulse, by index.
    impulses: Vec<usize>,
    /// The contacts the lesson's pass left to the support pass whose
    /// spheres were apart when the step began and met approaching: a
    /// landing the pass holds as resting contact, by index.
    landings: Vec<usize>,
    /// How many others rested, and the lesson's pass left them to the
    /// support pass (`None`: the step was not replayed).
    resting: Option<usize>,
}

/// The contacts of the last step that took an impulse of the lesson's
/// pass, found by replaying that pass; `None` when the step cannot be
/// replayed. The support pass runs after the lesson's pass,
/// so the pass itself replays with it on: the contacts it leaves to the
/// support pass (resting) took no impulse of it, and are collisions only
/// where two spheres apart at the step's start met approaching (a sphere
/// landing on another, slower than the resting speed).
fn impulses(world: &World, c: &WorldConfig, history: &History) -> Option<Replay> {
    let contacts = world.contacts();
    let start = history.previous()?.position;
    let supported = c.support_runs();
    let replayed = match unreplayable(world, c) {
        None => integrated(world, c, history),
        Some(_) => None,
    };
    let mut bodies = replayed?;
    let rule = c
        .pair_rule()
        .with_resting(c.resting(c.dt))
        .with_support(supported);
    let (mut impulses, mut landings, mut resting) = (Vec::new(), Vec::new(), 0);
    for (k, contact) in contacts.iter().enumerate() {
        let n = contact.contact_normal;
        let (i, j) = (contact.i as usize, contact.j as usize);
        let approaching = bodies.velocity[i].dot(n) > bodies.velocity[j].dot(n);
        let approach = (bodies.velocity[i] - bodies.velocity[j]).dot(n);
        // In the solver's order: a pair resting on the support pass is left
        // to it whichever way it moves.
        if rule.left_to_support(approach, n) {
            if approaching && landed_from(start[i].distance(start[j]), &bodies, i, j) {
                landings.push(k);
            } else {
                resting += 1;
            }
        } else if approaching {
            impulses.push(k);
        }
        solve_contacts(&mut bodies, std::slice::from_ref(contact), rule);
    }
    Some(Replay {
        impulses,
        landings,
        resting: Some(resting),
    })
}

/// How far apart two spheres count as touching: a hundredth of the
/// smaller radius, far beyond the hair by which a pair at rest under the
/// support pass parts and meets again from step to step.
fn touching(b: &Bodies, i: usize, j: usize) -> f64 {
    0.01 * b.radius[i].min(b.radius[j])
}

/// Whether spheres `i` and `j` of `b`, `distance` apart when the step
/// began, were apart then: by more than [`touching`], so that a pair at
/// rest on each other is not taken to land again and again.
fn landed_from(distance: f64, b: &Bodies, i: usize, j: usize) -> bool {
    distance > b.radius[i] + b.radius[j] + touching(b, i, j)
}

/// The pairs of `world`'s last step that its support pass took within its
/// margin while still apart (`World::near_pairs`, by index) and that
/// landed: apart by more than [`touching`] when the step began, and
/// within it of touching at its end, the pass having brought the one to
/// rest on the other. A pair within the margin that closes as fast as an
/// impact (`(rest_steps + 1) g dt` in a sub-step) the pass leaves to the
/// lesson's rules when it meets, and it ends the step still closing: no
/// landing. Empty where the pass did not run or the state before the step
/// is not kept.
fn near_landings(world: &World, c: &WorldConfig, history: &History) -> Vec<usize> {
    // The pass's own speed from which an approach is an impact.
    let impact = Support::of(c, c.substep_dt(), || f64::INFINITY).map(|s| s.impact());
    let (Some(impact), Some(previous)) = (impact, history.previous()) else {
        return Vec::new();
    };
    // A large world's slots are not those of the state kept before it.
    if is_large(world.bodies.len()) {
        return Vec::new();
    }
    let b = &world.bodies;
    let x0 = previous.position;
    world
        .near_pairs()
        .iter()
        .enumerate()
        .filter(|(_, p)| {
            let (i, j) = (p.i as usize, p.j as usize);
            let reach = b.radius[i] + b.radius[j];
            let d = b.position[i] - b.position[j];
            let end = d.length();
            let closing = (b.velocity[j] - b.velocity[i]).dot(d / end);
            landed_from(x0[i].distance(x0[j]), b, i, j)
                && end <= reach + touching(b, i, j)
                && closing < impact
        })
        .map(|(k, _)| k)
        .collect()
}

/// The parameters `world`'s last step ran with: as the history noted them,
/// else the world's own.
fn stepped_with<'a>(world: &'a World, history: &'a History) -> &'a WorldConfig {
    history.stepped_with().unwrap_or(&world.config)
}

/// The collisions of the last step that involve `selection`'s spheres.
/// Whether the impacts of the step that led to `world` can be told
/// ([`impacts_now`]): its contacts are listed (or it has no pair
/// collisions), and the state before it is kept (or it is the start).
pub(crate) fn impacts_known(world: &World, history: &History) -> bool {
    let contacts = !world.config.pair_collisions || world.contacts().len() == world.last.contacts;
    contacts && (world.steps == 0 || history.previous().is_some())
}

pub(crate) fn impacts_now(
    world: &World,
    history: &History,
    selection: Selection,
) -> Vec<(u32, Impact)> {
    let mut out = Vec::new();
    let b = &world.bodies;
    let at = |kind| Impact {
        steps: world.steps,
        time: world.time,
        kind,
    };
    for c in world.contacts() {
        let (a, z) = (b.id[c.i as usize], b.id[c.j as usize]);
        if selection.contains(a) {
            out.push((a, at(ImpactKind::Sphere(z))));
        }
        if selection.contains(z) {
            out.push((z, at(ImpactKind::Sphere(a))));
        }
    }
    if world.last.wall_impacts > 0
        && let (Some(slots), Some(previous)) = (slots_of(world, selection), history.previous())
    {
        let config = stepped_with(world, history);
        for (&id, &k) in selection.ids().iter().zip(&slots) {
            // The wall the replayed step met on the first axis that met
            // one, the last of them where a rebound carried it across the
            // box (it may end moving as it began); else the wall whose
            // velocity component the step reversed.
            let Some(before) = previous.of(id) else {
                continue;
            };
            // A chain stopped at its most walls ends on the wall past the
            // last one it met.
            let met = match replayed_walls(world, config, k, before) {
                Some(impacts) => impacts
                    .first()
                    .map(|i| i.axis)
                    .and_then(|first| impacts.into_iter().take_while(|i| i.axis == first).last())
                    .map(|i| ImpactKind::Wall {
                        axis: i.axis,
                        far: i.far != i.stopped,
                    }),
                None => wall_met(world, config.dt, k, before.1),
            };
            if let Some(kind) = met {
                out.push((id, at(kind)));
            }
        }
    }
    out
}
