//! Sleeping: spheres at rest are neither integrated nor solved until
//! something disturbs them, and a world at rest costs nothing
//! (`WorldConfig::sleep`; the discrete methods).
//!
//! - A sphere slower than [`SLEEP_SPEED`] counts the time it has stayed
//!   so (`Bodies::rest`); any faster step sets the count back to zero. At
//!   [`TIME_TO_SLEEP`] it is ready to sleep.
//! - The step's pairs link spheres: those overlapping, and with the
//!   support pass those within its margin of touching. Walls link nothing.
//! - Under gravity, sleep spreads from the ground up. From the lowest
//!   ready sphere up, one falls asleep if it rests on something (the
//!   ground, a wall gravity presses it against, or a neighbour lower than
//!   it), every neighbour it lies on ([`lies_on`]: the line of their
//!   centres within 60 degrees of the vertical) sleeps or falls asleep
//!   now, and every lower neighbour it leans on from the side sleeps or is
//!   ready. So a sphere in flight, slow at the top of its arc, does not
//!   sleep, nor one whose support still moves; but one that others slide
//!   on sleeps under them. Box2D puts whole islands to sleep, so that a
//!   pile sleeps only once its last sphere is still; in a pile without
//!   friction a few spheres on top slide on for seconds.
//! - Without gravity, nothing lies on anything: an island (the spheres
//!   linked to one another) whose every sphere is ready, touching no
//!   sphere that is not, falls asleep whole, as in Box2D.
//! - A sleeper's velocity is set to zero. It is not integrated, and the
//!   solvers hold it still while they move the spheres awake against it,
//!   as against a wall (`contact::Held`). The pairs of two sleepers are
//!   kept aside, unsolved, while both sleep (`sleeping_pairs.rs`): the
//!   narrow phase does not look for them again, and a sleeper that wakes
//!   gives its pairs back to the step's lists.
//! - A sleeper wakes ([`touch`]) when a sphere awake runs into it faster
//!   than [`SLEEP_SPEED`] (counting the velocity it had before the
//!   sub-step's gravity), lies under it, or moves faster than that lower
//!   than it, beside it; or when it rests on nothing any more. With it
//!   wake the sleepers lying on it, and those on them. A blow (faster than
//!   the resting window and a sub-step's gravity) wakes every sleeper
//!   linked to the one it strikes, in turn, so that the group passes it
//!   on. Without gravity any touch wakes every sleeper. A change of any
//!   parameter of the world (gravity, restitution, the method...) wakes
//!   every sleeper too. A sleeper woken in a sub-step takes the
//!   integration it missed there, from rest, and its pairs are taken
//!   again where it then is: it meets the spheres that woke it as a sphere
//!   that never slept would.
//! - While every sphere sleeps, a step only advances the clock: the
//!   spheres cost nothing. While some are awake, the sleepers still take
//!   their part of the broad phase and of a few passes over every sphere
//!   (which sleep, which rest on a kept pair), but the narrow phase tests
//!   a sleeper only against the cells that hold a sphere awake.
//!
//! Which spheres sleep and wake depends only on the step's pairs, as sets
//! (the islands are connected parts of a graph; the order from the ground
//! up sorts by height, then slot), not on the order they come in: the same
//! contacts give the same sleepers for any number of threads and either
//! broad phase.

use super::contact::{in_contact_list, test_pair_within};
use super::grid::Grid;
use super::integrator::Integrator;
use super::sleeping_pairs::SleepingPairs;
use super::support::ordered_bits;
use super::{Bodies, Contact, Vec3};
use rayon::prelude::*;

/// Speed below which a sphere counts as at rest, m/s (Box2D's default
/// sleep threshold, for bodies of about a metre: here the box).
pub const SLEEP_SPEED: f64 = 0.05;
/// Time a sphere must stay at rest before it may sleep, s (Box2D's).
pub const TIME_TO_SLEEP: f32 = 0.5;
/// `Bodies::rest` of a sleeping sphere.
pub(crate) const ASLEEP: f32 = f32::INFINITY;

/// Spheres per parallel task.
const CHUNK: usize = 4096;

/// Whether a sphere with this `rest` sleeps.
#[inline]
pub(crate) fn is_asleep(rest: f32) -> bool {
    rest == ASLEEP
}

/// How many spheres sleep.
pub(crate) fn asleep_count(rest: &[f32]) -> usize {
    // A world all asleep pays for this count and nothing else each step:
    // up to a few chunks it is counted on the thread that asks, where
    // waking the others would cost more than the count.
    if rest.len() <= SEQUENTIAL_COUNT {
        return count_asleep_in(rest);
    }
    rest.par_chunks(CHUNK).map(count_asleep_in).sum()
}

/// Spheres up to which [`asleep_count`] counts on one thread.
const SEQUENTIAL_COUNT: usize = 4 * CHUNK;

/// [`asleep_count`] of at most `u32::MAX` spheres on this thread: a
/// comparison of each entry and a sum of 32-bit counts, which the
/// compiler turns into vector instructions (eight entries at a time with
/// AVX2, chosen at run time).
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn count_asleep_in(rest: &[f32]) -> usize {
    rest.iter().map(|&r| u32::from(is_asleep(r))).sum::<u32>() as usize
}

/// Whether a step of `dt` s can end with some sphere ready to sleep (its
/// time at rest reaching [`TIME_TO_SLEEP`], counted as [`settle`] counts
/// it): only then does [`settle`] read the step's links. A sleeper counts
/// as ready.
pub(crate) fn may_fall_asleep(rest: &[f32], dt: f64) -> bool {
    let dt = dt as f32;
    rest.par_iter()
        .with_min_len(CHUNK)
        .any(|&r| r + dt >= TIME_TO_SLEEP)
}

/// Wake every sphere, and start every count of time at rest afresh.
pub(crate) fn wake_all(rest: &mut [f32]) {
    rest.par_iter_mut()
        .with_min_len(CHUNK)
        .for_each(|r| *r = 0.0);
}

/// Into `held`: each sphere's inverse mass, or 0 for a sleeper, which
/// the solvers then hold still (`BodiesMut::held`).
pub(crate) fn held_inverse_masses(bodies: &Bodies, held: &mut Vec<f64>) {
    held.clear();
    held.par_extend(
        bodies
            .inverse_mass
            .par_iter()
            .zip(bodies.rest.par_iter())
            .with_min_len(CHUNK)
            .map(|(&w, &r)| if is_asleep(r) { 0.0 } else { w }),
    );
}

/// Whether a sphere centred at `upper` lies on one at `lower` under
/// gravity along `-up`: the line of their centres is within 60 degrees of
/// the vertical. A neighbour lower by less, beside it, carries little of
/// its weight (half of it at 60 degrees, with no friction).
fn lies_on(upper: Vec3, lower: Vec3, up: Vec3) -> bool {
    let d = upper - lower;
    d.dot(up) > LIES_ON * d.length()
}

/// The cosine of [`lies_on`]'s angle from the vertical.
const LIES_ON: f64 = 0.5;

/// What [`touch`] did to the sleepers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Touch {
    /// Every sleeper woke.
    All,
    /// This many woke (maybe none); the pairs of two sleepers were kept
    /// aside.
    Some(usize),
}

/// After the narrow phase of a world with sleepers, in a sub-step of `h`
/// s under `gravity`: wake the sleepers that the pairs of `lists` show
/// disturbed (by those pairs and by the pairs of two sleepers `kept`),
/// keep the pairs of two sleepers still asleep aside, out of `lists`
/// (`SleepingPairs::keep`), and put the pairs `kept` of a sleeper woken
/// back in `lists`, in their places.
///
/// Without gravity, any pair of a sleeper and a sphere awake disturbs:
/// then every sleeper wakes ([`Touch::All`]). Under gravity a sleeper is
/// disturbed when a sphere awake runs into it faster than [`SLEEP_SPEED`]
/// along the line of their centres (by its velocity before this
/// sub-step's gravity, `v - g h`: a sphere at rest on a sleeper falls
/// `g h` into it each sub-step, and that is its weight, not a blow), when
/// a sphere awake lies under it ([`lies_on`]) or moves faster than that
/// lower than it, beside it, or when it rests on nothing any more (no pair
/// with a lower sphere, off the ground). With it wake
/// the sleepers lying on it, and those lying on them, at once. A blow,
/// faster than `blow` (m/s), wakes every sleeper linked to the one it
/// strikes, and every one linked to those, so that the group passes it
/// on. Sleepers not woken hold still, as walls do, until a later
/// sub-step finds them disturbed. `work`: the rules' memory.
///
/// A sleeper woken under gravity then takes the sub-step's integration
/// that it missed asleep, from rest, as every sphere awake took it, and
/// its pairs are taken again where it now is, as the narrow phase takes
/// them (`catch`, [`CatchUp`]): a sphere that slides along the floor into
/// a sleeper meets it level, as one awake, and an elastic blow keeps its
/// energy.
pub(crate) fn touch(
    bodies: &mut Bodies,
    lists: [&mut Vec<Contact>; 2],
    kept: &mut SleepingPairs,
    rule: (Vec3, f64, f64),
    catch: CatchUp,
    work: &mut SleepWork,
) -> Touch {
    work.woken.clear();
    let touched = wake(bodies, &lists, kept, rule, work);
    let [contacts, near] = lists;
    let (gravity, h, _) = rule;
    // Integrated from rest, a woken sphere moves by `fall`: the same for
    // every one (explicit Euler: nothing, its pairs stay as they are).
    let (v, parabola) = catch.method.position_update(Vec3::ZERO, gravity, h);
    let fall = v * h + parabola.unwrap_or(Vec3::ZERO);
    let woke = !work.woken.is_empty();
    // The pairs that go (back) to the lists: those moved between them, the
    // kept pairs of sleepers woken, and the new pairs of the spheres woken.
    let mut back: Vec<Contact> = Vec::new();
    if woke {
        work.woken.sort_unstable();
        work.woken.dedup();
        catch
            .method
            .integrate_slots(bodies, &work.woken, gravity, h);
        work.was_woken.clear();
        work.was_woken.resize(bodies.len(), false);
        for &k in &work.woken {
            work.was_woken[k as usize] = true;
        }
        if fall != Vec3::ZERO {
            back = catch.again(bodies, [&mut *contacts, &mut *near], &work.was_woken);
        }
    }
    kept.keep(
        bodies,
        [&mut *contacts, &mut *near],
        touched,
        up_of(gravity),
        &mut back,
    );
    if woke && fall != Vec3::ZERO {
        let met = catch.meet(
            bodies,
            [contacts, near],
            &back,
            (&work.woken, &work.was_woken),
            fall,
        );
        back.extend(met);
    }
    // What goes back to the lists, merged in once.
    catch.add([contacts, near], back);
    touched
}

/// What [`touch`] needs to bring the sleepers it wakes up to the
/// sub-step: the method that integrates them, the narrow phase's margin
/// (m), and the grid the broad phase built this sub-step, if any.
#[derive(Clone, Copy)]
pub(crate) struct CatchUp<'a> {
    pub method: Integrator,
    pub margin: f64,
    pub grid: Option<&'a Grid>,
}

impl CatchUp<'_> {
    /// Each pair of `lists` with a sphere just woken and moved
    /// (`was_woken`, per slot) taken again where it now is
    /// ([`test_pair_within`] with the margin): kept with its new contact,
    /// taken out to go to the other list (overlapping, or only within the
    /// margin, as the narrow phase splits them: returned, for
    /// [`CatchUp::add`]), or dropped when no longer within the margin. The
    /// lists stay sorted by `(i, j)`.
    fn again(
        self,
        bodies: &Bodies,
        mut lists: [&mut Vec<Contact>; 2],
        was_woken: &[bool],
    ) -> Vec<Contact> {
        let margin = self.margin;
        let mut moved: Vec<Contact> = Vec::new();
        for (k, list) in lists.iter_mut().enumerate() {
            let first = k == 0;
            // Taken again in parallel: a pair that stays in its list is
            // updated in place; one that leaves it is noted, in order,
            // with the contact it moves to the other list if any.
            let out: Vec<(usize, Option<Contact>)> = list
                .par_iter_mut()
                .with_min_len(LINK_CHUNK)
                .enumerate()
                .filter_map(|(at, c)| {
                    if !was_woken[c.i as usize] && !was_woken[c.j as usize] {
                        return None;
                    }
                    let Some(again) = test_pair_within(bodies, c.i as usize, c.j as usize, margin)
                    else {
                        return Some((at, None));
                    };
                    if self.overlaps(&again) == first {
                        *c = again;
                        None
                    } else {
                        Some((at, Some(again)))
                    }
                })
                .collect();
            moved.extend(out.iter().filter_map(|&(_, c)| c));
            remove_at(list, out.iter().map(|&(at, _)| at));
        }
        moved
    }

    /// The pairs within the margin that the woken spheres (`woken`, the
    /// slots sorted, and `was_woken` per slot), moved by `fall`, make where
    /// they now are and that neither `lists` nor `going` (the contacts on
    /// their way back to the lists) hold yet, returned for
    /// [`CatchUp::add`]. They are found among the spheres near each in the
    /// grid, which holds every other sphere where the narrow phase tested
    /// it, and a woken one where it was before it fell: the search spans
    /// the sphere's reach about where it is and about where it was.
    /// Without a grid, among every sphere. The same pairs either way.
    fn meet(
        self,
        bodies: &Bodies,
        lists: [&Vec<Contact>; 2],
        going: &[Contact],
        (woken, was_woken): (&[u32], &[bool]),
        fall: Vec3,
    ) -> Vec<Contact> {
        let mut listed: Vec<(u32, u32)> = each_link([&lists[0][..], &lists[1][..]])
            .filter(|c| was_woken[c.i as usize] || was_woken[c.j as usize])
            .map(|c| (c.i, c.j))
            .collect();
        listed.extend(going.iter().map(|c| (c.i, c.j)));
        listed.par_sort_unstable();
        let largest = bodies.max_radius();
        // Each woken sphere's search on its own: the pairs in the order of
        // the woken spheres, then of the slots near each.
        let found: Vec<Contact> = woken
            .par_iter()
            .with_min_len(WOKEN_CHUNK)
            .map_init(Vec::new, |near, &w| {
                let p = bodies.position[w as usize];
                let reach = Vec3::splat(
                    (bodies.radius[w as usize] + largest + self.margin) * (1.0 + SEARCH_SLACK),
                );
                let (before, slack) = (p - fall, fall.abs() * SEARCH_SLACK);
                let (lo, hi) = (p.min(before) - reach - slack, p.max(before) + reach + slack);
                let searched = self.grid.is_some_and(|g| g.slots_within(lo, hi, near));
                if !searched {
                    near.clear();
                    near.extend(0..bodies.len() as u32);
                }
                let mut found = Vec::new();
                for &k in near.iter() {
                    // A pair of two woken spheres is met from the lower one.
                    if k == w || (k < w && was_woken[k as usize]) {
                        continue;
                    }
                    let (i, j) = (w.min(k), w.max(k));
                    let Some(c) = test_pair_within(bodies, i as usize, j as usize, self.margin)
                    else {
                        continue;
                    };
                    if listed.binary_search(&(i, j)).is_err() {
                        found.push(c);
                    }
                }
                found
            })
            .flatten_iter()
            .collect();
        found
    }

    /// Whether `c` goes to the first list, as the narrow phase splits them.
    fn overlaps(self, c: &Contact) -> bool {
        in_contact_list(c, self.margin)
    }

    /// `more` merged into their lists, which stay sorted by `(i, j)`.
    fn add(self, lists: [&mut Vec<Contact>; 2], more: Vec<Contact>) {
        let (mut first, mut second): (Vec<Contact>, Vec<Contact>) =
            more.into_iter().partition(|c| self.overlaps(c));
        for (list, more) in lists.into_iter().zip([&mut first, &mut second]) {
            if more.is_empty() {
                continue;
            }
            more.sort_unstable_by_key(|c| (c.i, c.j));
            // Merged in place from the back, the list's own contact before
            // one of `more` for the same pair: the list, hundreds of
            // thousands of contacts in a pile, is not copied to new memory
            // each time (which cost a pile of 100,000 spheres a quarter of
            // its step in page faults).
            let (mut a, mut b) = (list.len(), more.len());
            list.extend_from_slice(more);
            let mut out = list.len();
            while b > 0 {
                out -= 1;
                let y = more[b - 1];
                if a > 0 && (list[a - 1].i, list[a - 1].j) > (y.i, y.j) {
                    a -= 1;
                    list[out] = list[a];
                } else {
                    b -= 1;
                    list[out] = y;
                }
            }
        }
    }
}

/// Woken spheres per parallel task in the search for their new pairs.
const WOKEN_CHUNK: usize = 64;

/// What the search for a woken sphere's new pairs reaches beyond its
/// reach to the largest sphere and its fall, as a fraction of each: far
/// beyond the rounding of a centre.
const SEARCH_SLACK: f64 = 1e-9;

/// The way up under `gravity`: against it, or zero without gravity.
pub(crate) fn up_of(gravity: Vec3) -> Vec3 {
    if gravity == Vec3::ZERO {
        Vec3::ZERO
    } else {
        -gravity.normalize()
    }
}

/// [`touch`]'s waking, by the pairs of `lists` and the pairs of two
/// sleepers kept. Each look over the pairs runs in parallel and gathers
/// what it finds in the pairs' order (or sorts it), so the same pairs wake
/// the same sleepers for any number of threads.
fn wake(
    bodies: &mut Bodies,
    lists: &[&mut Vec<Contact>; 2],
    kept: &mut SleepingPairs,
    (gravity, h, blow): (Vec3, f64, f64),
    work: &mut SleepWork,
) -> Touch {
    let links = [&lists[0][..], &lists[1][..]];
    let asleep = |rest: &[f32], k: u32| is_asleep(rest[k as usize]);
    if gravity == Vec3::ZERO {
        let rest = &bodies.rest;
        if each_link(links).any(|c| asleep(rest, c.i) != asleep(rest, c.j)) {
            wake_all(&mut bodies.rest);
            return Touch::All;
        }
        return Touch::Some(0);
    }
    let up = -gravity.normalize();
    let (position, velocity) = (&bodies.position, &bodies.velocity);
    let rest: &[f32] = &bodies.rest;
    // The listed pairs with a sleeper, gathered in one look: all that the
    // rules below read of the lists (a sleeper woken below was asleep
    // here).
    let sleepy: Vec<(u32, u32)> = each_link(links)
        .filter(|c| asleep(rest, c.i) || asleep(rest, c.j))
        .map(|c| (c.i, c.j))
        .collect();
    // A sleeper left resting on nothing (what held it up moved away)
    // wakes, and falls. What a kept pair holds up stays held.
    let higher = mark_higher(
        &mut work.higher,
        position,
        sleepy.par_iter().copied(),
        up,
        |k| asleep(rest, k),
    );
    let rests = kept.rests();
    let mut lifted: Vec<u32> = (0..rest.len() as u32)
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&k| {
            let k = k as usize;
            is_asleep(rest[k])
                && !higher[k]
                && !rests.get(k).copied().unwrap_or(false)
                && !on_the_ground(position[k], bodies.radius[k], gravity)
        })
        .collect();
    // Each pair of a sleeper and a sphere awake: `(sleeper, struck)` when
    // it disturbs the sleeper, struck by a blow or not.
    let disturbed: Vec<(u32, bool)> = sleepy
        .par_iter()
        .with_min_len(LINK_CHUNK)
        .filter(|&&(i, j)| asleep(rest, i) != asleep(rest, j))
        .filter_map(|&(i, j)| {
            let (s, m) = if asleep(rest, i) { (i, j) } else { (j, i) };
            let (xs, xm) = (position[s as usize], position[m as usize]);
            let d = xs - xm;
            let v = velocity[m as usize] - gravity * h;
            let approach = v.dot(d);
            if approach > blow * d.length() || d == Vec3::ZERO {
                Some((s, true))
            } else if approach > SLEEP_SPEED * d.length()
                || lies_on(xs, xm, up)
                || (d.dot(up) > 0.0 && v.length_squared() > SLEEP_SPEED * SLEEP_SPEED)
            {
                // A slower touch, or a sphere that may hold the sleeper up.
                Some((s, false))
            } else {
                None
            }
        })
        .collect();
    let mut struck: Vec<u32> = disturbed.iter().filter(|d| d.1).map(|d| d.0).collect();
    lifted.extend(disturbed.iter().filter(|d| !d.1).map(|d| d.0));
    let mut woken = 0;
    if struck.is_empty() && lifted.is_empty() {
        return Touch::Some(0);
    }
    let kept = kept.slots();
    let pairs = || {
        let listed = sleepy.par_iter().with_min_len(LINK_CHUNK);
        listed
            .chain(kept.par_iter().with_min_len(LINK_CHUNK))
            .copied()
    };
    let rest = &mut bodies.rest;
    if !struck.is_empty() {
        // A blow wakes the struck sphere's whole group of sleepers, which
        // passes it on: every sleeper linked to a woken one, in turn.
        let asleep_now: &[f32] = rest;
        let mut links: Vec<(u32, u32)> = pairs()
            .filter(|&(i, j)| asleep(asleep_now, i) && asleep(asleep_now, j))
            .flat_map_iter(|(i, j)| [(i, j), (j, i)])
            .collect();
        links.par_sort_unstable();
        struck.retain(|&s| is_asleep(rest[s as usize]));
        struck.sort_unstable();
        struck.dedup();
        for &s in &struck {
            rest[s as usize] = 0.0;
            work.woken.push(s);
        }
        let mut next = 0;
        while let Some(&k) = struck.get(next) {
            next += 1;
            let at = links.partition_point(|&(from, _)| from < k);
            for &(_, to) in links[at..].iter().take_while(|&&(from, _)| from == k) {
                if is_asleep(rest[to as usize]) {
                    rest[to as usize] = 0.0;
                    work.woken.push(to);
                    struck.push(to);
                }
            }
        }
        woken += struck.len();
    }
    // The sleepers lying on spheres awake wake, and then those lying on
    // them, layer by layer: each layer a look over the pairs.
    let mut layer = lifted;
    loop {
        layer.retain(|&s| is_asleep(rest[s as usize]));
        layer.par_sort_unstable();
        layer.dedup();
        if layer.is_empty() {
            break;
        }
        for &s in &layer {
            rest[s as usize] = 0.0;
        }
        work.woken.extend_from_slice(&layer);
        woken += layer.len();
        let under = |k: u32| layer.binary_search(&k).is_ok();
        let rest: &[f32] = rest;
        layer = pairs()
            .filter_map(|(i, j)| {
                let (s, m) = match (asleep(rest, i), asleep(rest, j)) {
                    (true, false) => (i, j),
                    (false, true) => (j, i),
                    _ => return None,
                };
                let (xs, xm) = (position[s as usize], position[m as usize]);
                (under(m) && lies_on(xs, xm, up)).then_some(s)
            })
            .collect();
    }
    Touch::Some(woken)
}

/// Into `higher`, per slot: whether the sphere is higher along `up` than
/// some sphere a pair of `pairs` links it to (it rests on something),
/// marked only for the spheres `mark` picks (false for the others). The
/// pairs are looked at in parallel, and the marks set after in their
/// order.
pub(crate) fn mark_higher<'a>(
    higher: &'a mut Vec<bool>,
    position: &[Vec3],
    pairs: impl ParallelIterator<Item = (u32, u32)>,
    up: Vec3,
    mark: impl Fn(u32) -> bool + Sync,
) -> &'a [bool] {
    let marks: Vec<u32> = pairs
        .filter_map(|(i, j)| {
            let rise = (position[i as usize] - position[j as usize]).dot(up);
            let upper = if rise > 0.0 {
                i
            } else if rise < 0.0 {
                j
            } else {
                return None;
            };
            mark(upper).then_some(upper)
        })
        .collect();
    higher.clear();
    higher.resize(position.len(), false);
    for k in marks {
        higher[k as usize] = true;
    }
    higher
}

/// The rules' working memory (reused from step to step).
#[derive(Clone, Debug, Default)]
pub(crate) struct SleepWork {
    /// Union-find forest over the slots.
    parent: Vec<u32>,
    /// Without gravity, per slot: the slot, or (at a root) its island,
    /// touches a sphere that is not ready to sleep.
    blocked: Vec<bool>,
    /// Per slot: at rest for [`TIME_TO_SLEEP`], not yet asleep.
    ready: Vec<bool>,
    /// Under gravity: each ready sphere's lower neighbours, `(upper,
    /// lower, upper lies on lower)`, as found.
    found: Vec<(u32, u32, bool)>,
    /// The same as `(lower, lies on)`, grouped by the upper sphere.
    on: Vec<(u32, bool)>,
    /// Per slot: where its group in `on` ends.
    start: Vec<u32>,
    /// Under gravity: the ready spheres by height.
    order: Vec<(u64, u32)>,
    /// Under gravity, per slot: a sleeper higher than a neighbour a
    /// listed pair links it to ([`mark_higher`], in [`touch`]).
    higher: Vec<bool>,
    /// The scene ids of the spheres the last [`settle`] put to sleep.
    pub(crate) fell: Vec<u32>,
    /// The slots of the sleepers the last [`touch`] woke under gravity,
    /// and per slot whether it is one of them.
    woken: Vec<u32>,
    was_woken: Vec<bool>,
}

/// A sphere closer than this fraction of its radius to a wall touches it.
const GROUND_TOLERANCE: f64 = 0.05;

/// Whether a sphere at `x` of radius `r` touches a wall that `gravity`
/// presses it against (the floor, for gravity down).
fn on_the_ground(x: Vec3, r: f64, gravity: Vec3) -> bool {
    (0..3).any(|axis| {
        let g = gravity[axis];
        (g < 0.0 && x[axis] - r <= GROUND_TOLERANCE * r)
            || (g > 0.0 && 1.0 - r - x[axis] <= GROUND_TOLERANCE * r)
    })
}

/// End of a step of `dt` s under `gravity`: count each awake sphere's time
/// at rest, then put to sleep the spheres ready that may sleep, by
/// `links` (the step's pairs, none of two sleepers): from the ground up
/// under gravity ([`from_the_ground_up`]), by islands without
/// ([`islands`]). Returns how many spheres fell asleep.
pub(crate) fn settle(
    bodies: &mut Bodies,
    links: [&[Contact]; 2],
    (dt, gravity): (f64, Vec3),
    work: &mut SleepWork,
) -> usize {
    work.fell.clear();
    let slow2 = SLEEP_SPEED * SLEEP_SPEED;
    let dt = dt as f32;
    let waiting = bodies
        .rest
        .par_iter_mut()
        .zip(bodies.velocity.par_iter())
        .with_min_len(CHUNK)
        .filter_map(|(r, v)| {
            if is_asleep(*r) {
                return None;
            }
            *r = if v.length_squared() < slow2 {
                *r + dt
            } else {
                0.0
            };
            (*r >= TIME_TO_SLEEP).then_some(())
        })
        .count();
    if waiting == 0 {
        return 0;
    }
    if gravity == Vec3::ZERO {
        islands(bodies, links, work)
    } else {
        from_the_ground_up(bodies, links, -gravity.normalize(), work)
    }
}

/// Without gravity: every island of spheres ready to sleep (all of them at
/// rest for [`TIME_TO_SLEEP`]) that touches no sphere awake and not ready
/// falls asleep. Returns how many fell asleep.
fn islands(bodies: &mut Bodies, links: [&[Contact]; 2], work: &mut SleepWork) -> usize {
    let n = bodies.len();
    let SleepWork {
        parent,
        blocked,
        ready,
        fell: fallen,
        ..
    } = work;
    ready.clear();
    ready.extend(bodies.rest.iter().map(|&r| is_ready(r)));
    parent.clear();
    parent.extend(0..n as u32);
    blocked.clear();
    blocked.resize(n, false);
    // One that touches a sphere not ready is blocked (the whole island
    // then is: following the links out of a part of an island, the first
    // sphere met that is not in it is one not ready).
    for c in links.iter().flat_map(|l| l.iter()) {
        let (i, j) = (c.i as usize, c.j as usize);
        match (ready[i], ready[j]) {
            (true, true) => union(parent, i, j),
            (true, false) => blocked[i] = true,
            (false, true) => blocked[j] = true,
            (false, false) => {}
        }
    }
    for k in 0..n {
        if ready[k] && blocked[k] {
            let root = find(parent, k);
            blocked[root] = true;
        }
    }
    let mut fell = 0;
    for k in 0..n {
        if ready[k] && !blocked[find(parent, k)] {
            fall_asleep(bodies, k, fallen);
            fell += 1;
        }
    }
    fell
}

/// Under gravity along `-up`: from the lowest sphere ready to sleep up,
/// each falls asleep if it rests on the ground or is higher than some
/// sphere it is linked to (by the step's `links`), every sphere it lies on
/// ([`lies_on`]) sleeps or falls asleep now, and every other lower sphere
/// it is linked to (beside it) sleeps or is ready. A sphere in mid-air,
/// or leaning on one that moves, stays awake; one that others lie on
/// sleeps whether they move or not, and holds them up as the ground does.
/// Returns how many fell asleep.
fn from_the_ground_up(
    bodies: &mut Bodies,
    links: [&[Contact]; 2],
    up: Vec3,
    work: &mut SleepWork,
) -> usize {
    let SleepWork {
        ready,
        on,
        found,
        start,
        order,
        fell: fallen,
        ..
    } = work;
    let (rest, position) = (&bodies.rest, &bodies.position);
    ready.clear();
    ready.par_extend(rest.par_iter().with_min_len(CHUNK).map(|&r| is_ready(r)));
    // Each ready sphere's lower neighbours, `(upper, lower, upper lies on
    // lower)`, in the order of the links; a ready sphere rests on a
    // neighbour when it has any.
    let ready_now: &[bool] = ready;
    found.clear();
    found.par_extend(each_link(links).filter_map(|c| {
        let (i, j) = (c.i as usize, c.j as usize);
        if !ready_now[i] && !ready_now[j] {
            return None;
        }
        let (xi, xj) = (position[i], position[j]);
        let rise = (xi - xj).dot(up);
        if ready_now[i] && rise > 0.0 {
            Some((c.i, c.j, lies_on(xi, xj, up)))
        } else if ready_now[j] && rise < 0.0 {
            Some((c.j, c.i, lies_on(xj, xi, up)))
        } else {
            None
        }
    }));
    // Grouped by the upper sphere (a counting sort; the order within a
    // group does not matter): sphere `k`'s are `on[start[k - 1]..start[k]]`
    // (from 0 for the first).
    let n = bodies.len();
    start.clear();
    start.resize(n + 1, 0);
    for &(upper, _, _) in found.iter() {
        start[upper as usize + 1] += 1;
    }
    for k in 1..=n {
        start[k] += start[k - 1];
    }
    on.clear();
    on.resize(found.len(), (0, false));
    for &(upper, lower, steep) in found.iter() {
        let at = &mut start[upper as usize];
        on[*at as usize] = (lower, steep);
        *at += 1;
    }
    order.clear();
    order.par_extend(
        (0..n as u32)
            .into_par_iter()
            .with_min_len(CHUNK)
            .filter(|&k| ready_now[k as usize])
            .map(|k| (ordered_bits(position[k as usize].dot(up)), k)),
    );
    order.par_sort_unstable();
    let mut fell = 0;
    for &(_, k) in order.iter() {
        let k = k as usize;
        let from = if k == 0 { 0 } else { start[k - 1] as usize };
        let lower = &on[from..start[k] as usize];
        let rests = !lower.is_empty() || on_the_ground(bodies.position[k], bodies.radius[k], -up);
        // What it lies on sleeps; what it leans on beside it at least
        // keeps still.
        let steady = |&(l, steep): &(u32, bool)| {
            let l = l as usize;
            is_asleep(bodies.rest[l]) || (!steep && ready[l])
        };
        if rests && lower.iter().all(steady) {
            fall_asleep(bodies, k, fallen);
            fell += 1;
        }
    }
    fell
}

/// Take the entries at the places `at` (ascending) out of `list`.
pub(crate) fn remove_at<T>(list: &mut Vec<T>, at: impl Iterator<Item = usize>) {
    let (mut k, mut at) = (0, at.peekable());
    if at.peek().is_none() {
        return;
    }
    list.retain(|_| {
        let out = at.next_if_eq(&k).is_some();
        k += 1;
        !out
    });
}

/// The pairs of `lists`, in order, as a parallel iterator.
fn each_link(lists: [&[Contact]; 2]) -> impl IndexedParallelIterator<Item = &Contact> {
    let [a, b] = lists;
    a.par_iter()
        .with_min_len(LINK_CHUNK)
        .chain(b.par_iter().with_min_len(LINK_CHUNK))
}

/// Pairs per parallel task in a pass over a step's pairs.
pub(crate) const LINK_CHUNK: usize = 16_384;

/// Whether a sphere awake with this `rest` has been at rest long enough
/// to sleep.
fn is_ready(rest: f32) -> bool {
    rest >= TIME_TO_SLEEP && !is_asleep(rest)
}

/// Put the sphere in slot `k` to sleep, noting its scene id in `fell`.
fn fall_asleep(bodies: &mut Bodies, k: usize, fell: &mut Vec<u32>) {
    bodies.velocity[k] = Vec3::ZERO;
    bodies.rest[k] = ASLEEP;
    fell.push(bodies.id[k]);
}

/// The root of `k`'s tree, halving the path on the way.
fn find(parent: &mut [u32], mut k: usize) -> usize {
    while parent[k] as usize != k {
        let up = parent[parent[k] as usize];
        parent[k] = up;
        k = up as usize;
    }
    k
}

/// Join the trees of `a` and `b` (the smaller root under the larger: any
/// rule gives the same islands).
fn union(parent: &mut [u32], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi] = lo as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Body, BroadPhase, World, WorldConfig};

    fn sphere(position: Vec3, velocity: Vec3, radius: f64) -> Body {
        Body {
            position,
            velocity,
            radius,
            mass: 1.0,
        }
    }

    #[test]
    fn pairs_taken_again_are_merged_into_their_lists_in_order() {
        // Random pairs, some in both: each list comes out sorted by (i, j),
        // its own contact of a pair before the one added, with nothing lost.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let catch = CatchUp {
            method: Integrator::SemiImplicitEuler,
            margin: 0.01,
            grid: None,
        };
        for round in 0..50 {
            let mut pair = |from: f64, overlapping: bool| Contact {
                i: rng.random_range(0..20),
                j: rng.random_range(20..40),
                contact_normal: Vec3::new(from, 0.0, 0.0),
                penetration: if overlapping { 0.001 } else { -0.001 },
            };
            let mut lists: [Vec<Contact>; 2] = [0, 1].map(|k| {
                let mut l: Vec<Contact> = (0..round).map(|_| pair(1.0, k == 0)).collect();
                l.sort_by_key(|c| (c.i, c.j));
                l
            });
            let more: Vec<Contact> = (0..round % 7 * 3).map(|k| pair(2.0, k % 2 == 0)).collect();
            let mut expected = lists.clone();
            for c in &more {
                expected[usize::from(!catch.overlaps(c))].push(*c);
            }
            for e in &mut expected {
                // By pair, the list's own (1) before those added (2).
                e.sort_by(|a, b| {
                    (a.i, a.j)
                        .cmp(&(b.i, b.j))
                        .then(a.contact_normal.x.total_cmp(&b.contact_normal.x))
                });
            }
            let [a, b] = &mut lists;
            catch.add([a, b], more);
            let key = |l: &[Contact]| -> Vec<(u32, u32, f64)> {
                l.iter().map(|c| (c.i, c.j, c.contact_normal.x)).collect()
            };
            assert_eq!(key(&lists[0]), key(&expected[0]), "round {round}");
            assert_eq!(key(&lists[1]), key(&expected[1]), "round {round}");
        }
    }

    fn sleeping_world(bodies: Vec<Body>) -> World {
        let config = WorldConfig {
            dt: 1.0 / 60.0,
            sleep: true,
            ..WorldConfig::default()
        };
        World::new(config, bodies.into_iter().collect())
    }

    /// Steps until every sphere sleeps; `None` if not within `limit`.
    fn steps_to_sleep(w: &mut World, limit: u64) -> Option<u64> {
        (1..=limit).find(|_| {
            w.step();
            w.last.asleep == w.bodies.len()
        })
    }

    #[test]
    fn entries_are_taken_out_at_the_places_given_and_nowhere_else() {
        let taken = |at: &[usize]| {
            let mut list: Vec<u32> = (0..6).collect();
            remove_at(&mut list, at.iter().copied());
            list
        };
        assert_eq!(taken(&[]), [0, 1, 2, 3, 4, 5]);
        assert_eq!(taken(&[0]), [1, 2, 3, 4, 5]);
        assert_eq!(taken(&[5]), [0, 1, 2, 3, 4]);
        assert_eq!(taken(&[1, 2, 4]), [0, 3, 5]);
        assert_eq!(taken(&[0, 1, 2, 3, 4, 5]), [] as [u32; 0]);
    }

    #[test]
    fn sleepers_are_counted_in_every_chunk() {
        // Sleepers at the first and last slot of the chunks, and times
        // at rest that are not asleep (finite, however long, or not a
        // time), counted on one thread and in parallel.
        assert_eq!(asleep_count(&[]), 0);
        for n in [3 * CHUNK + 5, SEQUENTIAL_COUNT + 2 * CHUNK + 5] {
            let mut rest = vec![0.25_f32; n];
            assert_eq!(asleep_count(&rest), 0);
            for k in [0, CHUNK - 1, CHUNK, 3 * CHUNK, n - 1] {
                rest[k] = ASLEEP;
            }
            rest[1] = f32::MAX;
            rest[2] = f32::NEG_INFINITY;
            rest[3] = f32::NAN;
            assert_eq!(asleep_count(&rest), 5, "{n} spheres");
            assert_eq!(asleep_count(&vec![ASLEEP; n]), n);
        }
    }

    #[test]
    fn a_sphere_at_rest_sleeps_after_half_a_second_and_then_stays_put() {
        let r = 0.05;
        for method in crate::sim::Integrator::ALL
            .into_iter()
            .filter(|m| m.is_discrete())
        {
            let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
            w.config.integrator = method;
            // At rest on the floor from the first step: 0.5 s is 30 steps.
            let steps = steps_to_sleep(&mut w, 100).expect("it falls asleep");
            assert_eq!(steps, 30, "{method}");
            let (x, e) = (w.bodies.position[0], w.diagnostics().total_energy);
            w.run(600);
            assert_eq!(
                w.bodies.position[0], x,
                "a sleeper does not move ({method})"
            );
            assert_eq!(w.bodies.velocity[0], Vec3::ZERO);
            assert_eq!(w.diagnostics().total_energy, e);
            assert_eq!(w.steps, 630, "the clock goes on");
        }
    }

    #[test]
    fn a_sphere_at_rest_on_the_ceiling_under_gravity_up_sleeps_after_half_a_second() {
        // The floor's test turned upside down: gravity presses the sphere
        // against the ceiling, which holds it up, so it lies on the ground
        // there. In mid-air it would not sleep (the test of the slow arc).
        let r = 0.05;
        for method in crate::sim::Integrator::ALL
            .into_iter()
            .filter(|m| m.is_discrete())
        {
            let at = Vec3::new(0.3, 1.0 - r, 0.6);
            let mut w = sleeping_world(vec![sphere(at, Vec3::ZERO, r)]);
            w.config.integrator = method;
            w.config.gravity = -w.config.gravity;
            let steps = steps_to_sleep(&mut w, 100).expect("it falls asleep");
            assert_eq!(steps, 30, "{method}");
            let x = w.bodies.position[0];
            assert!(1.0 - r - x.y <= GROUND_TOLERANCE * r, "{method}: at {x}");
            w.run(600);
            assert_eq!(
                w.bodies.position[0], x,
                "a sleeper does not move ({method})"
            );
            assert_eq!(w.bodies.velocity[0], Vec3::ZERO);
        }
    }

    #[test]
    fn a_sphere_sliding_faster_than_the_threshold_never_sleeps() {
        // No friction: it slides along the floor from wall to wall.
        let r = 0.05;
        let v = Vec3::new(2.0 * SLEEP_SPEED, 0.0, 0.0);
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), v, r)]);
        assert_eq!(steps_to_sleep(&mut w, 600), None);
        // Slowed by the walls' c_r = 0.95 only.
        assert!(w.bodies.velocity[0].length() > 0.9 * v.length());
    }

    #[test]
    fn an_island_with_one_moving_sphere_stays_awake_whole() {
        // Three spheres overlapping in a row, without gravity: the outer
        // ones at rest, the middle one moving. Linked, none may sleep,
        // though two are slow.
        let mut bodies: Bodies = (0..3)
            .map(|k| {
                let v = if k == 1 { Vec3::X } else { Vec3::ZERO };
                sphere(Vec3::new(0.3 + 0.09 * k as f64, 0.5, 0.5), v, 0.05)
            })
            .collect();
        bodies.rest = vec![TIME_TO_SLEEP; 3];
        let mut links = Vec::new();
        crate::sim::broad_phase::all_pairs_within(&bodies, &mut links, 0.0);
        assert_eq!(links.len(), 2, "a chain of three");
        let mut work = SleepWork::default();
        assert_eq!(
            settle(
                &mut bodies,
                [&links, &[]],
                (1.0 / 60.0, Vec3::ZERO),
                &mut work
            ),
            0
        );
        assert_eq!(
            bodies.rest,
            [TIME_TO_SLEEP + 1.0 / 60.0, 0.0, TIME_TO_SLEEP + 1.0 / 60.0]
        );
        // Unlinked, the slow ones sleep and the moving one does not.
        assert_eq!(
            settle(&mut bodies, [&[], &[]], (1.0 / 60.0, Vec3::ZERO), &mut work),
            2
        );
        assert!(is_asleep(bodies.rest[0]) && is_asleep(bodies.rest[2]));
        assert!(!is_asleep(bodies.rest[1]));
        // The middle one now at rest too, and linked again to the two
        // asleep: a sleeper is not ready to sleep (it sleeps already), so
        // the links block the middle one, which stays awake with its time
        // at rest counted. (In a world such links never reach `settle`:
        // the narrow phase's `touch` wakes every sleeper first.) Unlinked,
        // it falls asleep alone.
        links.clear();
        let mut mid = bodies.clone();
        mid.rest[1] = TIME_TO_SLEEP;
        mid.velocity[1] = Vec3::ZERO;
        crate::sim::broad_phase::all_pairs_within(&mid, &mut links, 0.0);
        assert_eq!(links.len(), 2, "the same chain");
        let mut linked = mid.clone();
        assert_eq!(
            settle(
                &mut linked,
                [&links, &[]],
                (1.0 / 60.0, Vec3::ZERO),
                &mut work
            ),
            0
        );
        assert_eq!(linked.rest, [ASLEEP, TIME_TO_SLEEP + 1.0 / 60.0, ASLEEP]);
        assert_eq!(
            settle(&mut mid, [&[], &[]], (1.0 / 60.0, Vec3::ZERO), &mut work),
            1
        );
        assert_eq!(mid.rest, [ASLEEP; 3]);
    }

    #[test]
    fn a_sphere_in_flight_beside_a_sleeper_flies_the_bits_it_flies_alone() {
        // While some spheres sleep and others do not, the step integrates
        // only those awake, by a copy of each method's formula
        // (`Integrator::integrate_awake`). A sphere thrown up at x = 0.7
        // beside one at rest on the floor at x = 0.2, which falls asleep
        // in step 30, flies with the same bits as alone: up to 0.77 m
        // and back, free until it lands (step 44 to 46, by the method), then
        // off the floor.
        let r = 0.05;
        let thrown = sphere(Vec3::new(0.7, 0.15, 0.5), Vec3::new(0.0, 3.5, 0.0), r);
        let resting = sphere(Vec3::new(0.2, r, 0.5), Vec3::ZERO, r);
        for method in crate::sim::Integrator::DISCRETE {
            let mut alone = sleeping_world(vec![thrown]);
            let mut beside = sleeping_world(vec![thrown, resting]);
            alone.config.integrator = method;
            beside.config.integrator = method;
            for step in 1..=60 {
                alone.step();
                beside.step();
                assert_eq!(
                    beside.last.asleep,
                    usize::from(step >= 30),
                    "{method}, step {step}"
                );
                assert_eq!(
                    (beside.bodies.position[0], beside.bodies.velocity[0]),
                    (alone.bodies.position[0], alone.bodies.velocity[0]),
                    "{method}, step {step}"
                );
            }
            assert_eq!(beside.bodies.position[1], resting.position, "{method}");
        }
    }

    #[test]
    fn a_sphere_rolling_into_a_sleeper_wakes_it_and_pushes_it() {
        // A sphere at rest on the floor, and one sliding towards it along
        // the floor at 0.5 m/s with a gap of 0.3 m: the first falls asleep
        // (0.5 s) before the second arrives (0.6 s, step 36).
        let r = 0.05;
        let mut w = sleeping_world(vec![
            sphere(Vec3::new(0.6, r, 0.5), Vec3::ZERO, r),
            sphere(Vec3::new(0.2, r, 0.5), Vec3::new(0.5, 0.0, 0.0), r),
        ]);
        w.run(30);
        assert!(is_asleep(w.bodies.rest[0]) && !is_asleep(w.bodies.rest[1]));
        let mut touched = None;
        for k in 30..120 {
            w.step();
            if !is_asleep(w.bodies.rest[0]) {
                touched = Some(k);
                break;
            }
            assert_eq!(w.bodies.position[0], Vec3::new(0.6, r, 0.5));
        }
        let k = touched.expect("the touch woke the sleeper");
        assert_eq!(k, 36, "woken at the step of the touch");
        w.run(2);
        assert!(
            w.bodies.velocity[0].x > 0.4,
            "the impact passed the momentum on (e = 0.95): v = {}",
            w.bodies.velocity[0]
        );
    }

    #[test]
    fn a_sphere_at_the_top_of_a_slow_arc_does_not_sleep_in_mid_air() {
        // Under 0.1 m/s^2 a sphere thrown up at 0.04 m/s stays slower than
        // 0.05 m/s for 0.9 s about the top of its arc: slow, not at rest.
        let r = 0.05;
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.5, 0.5, 0.5), 0.04 * Vec3::Y, r)]);
        w.config.gravity = Vec3::new(0.0, -0.1, 0.0);
        let mut longest: f32 = 0.0;
        for _ in 0..150 {
            w.step();
            assert_eq!(w.last.asleep, 0, "asleep at y = {}", w.bodies.position[0].y);
            longest = longest.max(w.bodies.rest[0]);
        }
        assert!(
            longest >= TIME_TO_SLEEP,
            "it was slow long enough: {longest} s"
        );
        // Without gravity, the same slow sphere sleeps where it is.
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.5, 0.5, 0.5), 0.04 * Vec3::Y, r)]);
        w.config.gravity = Vec3::ZERO;
        assert_eq!(steps_to_sleep(&mut w, 100), Some(30));
    }

    /// A column of ten spheres held by the support pass on the floor at
    /// x = 0.3, and a sphere sliding to and fro along the floor at z = 0.9,
    /// which never sleeps.
    fn column_and_slider(broad_phase: BroadPhase) -> World {
        let r = 0.04;
        let mut bodies: Vec<Body> = (0..10)
            .map(|k| {
                let y = r + k as f64 * 2.0 * r * (1.0 - crate::sim::support::RESTING_OVERLAP);
                sphere(Vec3::new(0.3, y, 0.5), Vec3::ZERO, r)
            })
            .collect();
        bodies.push(sphere(Vec3::new(0.5, r, 0.9), Vec3::new(1.0, 0.0, 0.0), r));
        let mut w = sleeping_world(bodies);
        w.config.support = true;
        w.config.broad_phase = broad_phase;
        w
    }

    #[test]
    fn with_some_spheres_asleep_the_readouts_are_the_same_for_either_broad_phase() {
        let mut worlds = [BroadPhase::AllPairs, BroadPhase::Grid].map(column_and_slider);
        for step in 0..120 {
            for w in &mut worlds {
                w.step();
            }
            let [a, b] = [0, 1].map(|k| {
                let d = worlds[k].diagnostics();
                (
                    d.contacts,
                    d.max_overlap,
                    d.asleep,
                    d.wall_impacts,
                    d.total_energy,
                )
            });
            assert_eq!(a, b, "step {step}");
            assert_eq!(
                worlds[0].state_hash(),
                worlds[1].state_hash(),
                "step {step}"
            );
        }
        assert_eq!(
            worlds[0].last.asleep, 10,
            "the column sleeps, the slider does not"
        );
    }

    #[test]
    fn a_held_column_woken_from_sleep_goes_on_as_if_it_had_never_slept() {
        // Asleep while the slider moves, its support impulses are kept, so
        // that woken it carries its weight at once: it goes on settling as
        // the same column kept awake did from the step it fell asleep
        // (step 30), where without its impulses it would sink by a hundredth
        // of a radius within five steps.
        let r = 0.04;
        let mut slept = column_and_slider(BroadPhase::Grid);
        slept.run(120);
        assert_eq!(slept.last.asleep, 10);
        slept.config.sleep = false;
        let mut awake = column_and_slider(BroadPhase::Grid);
        awake.config.sleep = false;
        awake.run(30);
        let (top_slept, top_awake) = (slept.bodies.position[9], awake.bodies.position[9]);
        assert_eq!(top_slept, top_awake, "asleep where it stopped at step 30");
        for k in 0..40 {
            slept.step();
            awake.step();
            let moved = |w: &World, top: Vec3| (w.bodies.position[9] - top).length();
            let (a, b) = (moved(&slept, top_slept), moved(&awake, top_awake));
            assert!(
                (a - b).abs() < 1e-6 * r,
                "step {k} after waking: {a:.3e} m against {b:.3e} m"
            );
        }
    }

    #[test]
    fn changing_gravity_wakes_the_sleepers() {
        let r = 0.05;
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
        steps_to_sleep(&mut w, 100).expect("it falls asleep");
        w.config.gravity = -w.config.gravity;
        w.step();
        assert!(!is_asleep(w.bodies.rest[0]));
        assert!(w.bodies.velocity[0].y > 0.0, "it falls up");
        // And switching sleeping off wakes them too.
        let mut w = sleeping_world(vec![sphere(Vec3::new(0.3, r, 0.6), Vec3::ZERO, r)]);
        steps_to_sleep(&mut w, 100).expect("it falls asleep");
        w.config.sleep = false;
        w.step();
        assert_eq!(w.bodies.rest[0], 0.0);
        assert_eq!(w.last.asleep, 0);
    }

    #[test]
    fn a_pile_sleeps_the_same_for_either_broad_phase() {
        // The collisions lesson's kind of pile, small: 60 spheres dropped.
        let mut worlds: Vec<World> = [BroadPhase::AllPairs, BroadPhase::Grid]
            .into_iter()
            .map(|bp| {
                let bodies: Vec<Body> = (0..60)
                    .map(|k| {
                        let (x, z) = ((k % 8) as f64, ((k / 8) % 8) as f64);
                        let p = Vec3::new(0.1 + 0.1 * x, 0.1 + 0.011 * k as f64, 0.1 + 0.1 * z);
                        sphere(p, Vec3::new(0.3, 0.0, -0.2), 0.06)
                    })
                    .collect();
                let mut w = sleeping_world(bodies);
                w.config.broad_phase = bp;
                w.config.support = true;
                w
            })
            .collect();
        // Step by step the same sleepers, some while others still move.
        let mut partly = 0;
        let slept = (1..=3000).find(|step| {
            for w in &mut worlds {
                w.step();
            }
            let asleep = worlds[0].last.asleep;
            assert_eq!(asleep, worlds[1].last.asleep, "step {step}");
            partly += usize::from(asleep > 0 && asleep < 60);
            asleep == 60
        });
        assert!(slept.is_some(), "the pile comes to rest and sleeps");
        assert!(partly > 0, "its lower spheres sleep first");
        assert_eq!(worlds[0].state_hash(), worlds[1].state_hash());
    }

    /// Spheres of radius `r` and their overlapping pairs, all awake with
    /// `rest` each.
    fn linked(centres: &[Vec3], r: f64, rest: &[f32]) -> (Bodies, Vec<Contact>) {
        let mut bodies: Bodies = centres.iter().map(|&x| sphere(x, Vec3::ZERO, r)).collect();
        bodies.rest = rest.to_vec();
        let mut links = Vec::new();
        crate::sim::broad_phase::all_pairs_within(&bodies, &mut links, 0.0);
        (bodies, links)
    }

    /// [`touch`] with `links` the only list, from fresh memory.
    fn touch_once(bodies: &mut Bodies, links: &mut Vec<Contact>, rule: (Vec3, f64, f64)) -> Touch {
        touch(
            bodies,
            [links, &mut Vec::new()],
            &mut SleepingPairs::default(),
            rule,
            CatchUp {
                method: crate::sim::Integrator::SemiImplicitEuler,
                margin: 0.0,
                grid: None,
            },
            &mut SleepWork::default(),
        )
    }

    #[test]
    fn a_woken_sleeper_that_falls_into_a_sphere_it_did_not_touch_meets_it() {
        // b sleeps on the floor; a sleeps 1 mm clear of it, up and to the
        // side at 45 degrees, resting on nothing: a wakes and takes the
        // sub-step's fall, g h^2, 1.9 mm towards b along the line of their
        // centres. The narrow phase did not list the pair; the touch adds
        // it, found with the grid as without it.
        let (r, h) = (0.05, 1.0 / 60.0);
        let g = Vec3::new(0.0, -9.81, 0.0);
        let b = Vec3::new(0.5, r, 0.5);
        let a = b + (2.0 * r + 1e-3) * Vec3::new(1.0, 1.0, 0.0).normalize();
        let lists_after = |with_grid: bool| {
            let (mut bodies, mut links) = linked(&[a, b], r, &[ASLEEP, ASLEEP]);
            assert!(links.is_empty(), "apart at first");
            let mut grid = Grid::new();
            grid.build(&bodies, crate::sim::grid::CellLayout::of(&bodies));
            let touched = touch(
                &mut bodies,
                [&mut links, &mut Vec::new()],
                &mut SleepingPairs::default(),
                (g, h, 2.0 * 9.81 * h),
                CatchUp {
                    method: crate::sim::Integrator::SemiImplicitEuler,
                    margin: 0.0,
                    grid: with_grid.then_some(&grid),
                },
                &mut SleepWork::default(),
            );
            assert_eq!(touched, Touch::Some(1), "a wakes, b sleeps on");
            assert_eq!(bodies.position[0], a + (g * h) * h, "a fell");
            links
        };
        let found = lists_after(true);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].i, found[0].j), (0, 1));
        assert!(found[0].penetration > 5e-4, "{found:?}");
        assert_eq!(lists_after(false), found, "the same without the grid");
    }

    #[test]
    fn a_sphere_sliding_into_a_sleeper_meets_it_as_one_awake() {
        // Two equal spheres on the floor, e = 1: b asleep, a sliding into
        // it at 0.3 m/s along x. Woken by the blow, b takes the step's
        // integration it missed, so the two meet level, as if b had never
        // slept: their velocities swap and the energy stays. (Woken
        // without it, b met a, which had sunk g dt^2 and fell at g dt, a
        // millimetre higher: the normal tilted, half the energy went.)
        let (r, dt) = (0.02, 1.0 / 30.0);
        for method in crate::sim::Integrator::DISCRETE {
            let world = |sleep: bool| {
                let config = WorldConfig {
                    dt,
                    integrator: method,
                    pair_restitution: 1.0,
                    sleep,
                    ..WorldConfig::default()
                };
                let bodies = [
                    sphere(Vec3::new(0.2563, r, 0.5), Vec3::new(0.3, 0.0, 0.0), r),
                    sphere(Vec3::new(0.6, r, 0.5), Vec3::ZERO, r),
                ];
                World::new(config, bodies.into_iter().collect())
            };
            let (mut sleeping, mut awake) = (world(true), world(false));
            // b sleeps after 0.5 s; a reaches it about 1 s in.
            let mut hit = None;
            for step in 1..=60 {
                sleeping.step();
                awake.step();
                if step == 20 {
                    assert_eq!(sleeping.last.asleep, 1, "{method}: b sleeps");
                }
                if sleeping.bodies.velocity[1].x != 0.0 {
                    hit = Some(step);
                    break;
                }
            }
            let hit = hit.unwrap_or_else(|| panic!("{method}: a never reached b"));
            let v = &sleeping.bodies.velocity;
            assert!(
                (v[0].x - 0.0).abs() < 1e-12 && (v[1].x - 0.3).abs() < 1e-12,
                "{method}, step {hit}: {v:?}"
            );
            assert_eq!(
                (&sleeping.bodies.position, &sleeping.bodies.velocity),
                (&awake.bodies.position, &awake.bodies.velocity),
                "{method}, step {hit}: as without sleeping"
            );
        }
    }

    /// `from` moved by `2 r` (less a little overlap) at `degrees` from the
    /// vertical, up, towards `x`.
    fn on_top(from: Vec3, r: f64, degrees: f64) -> Vec3 {
        let a = degrees.to_radians();
        from + 2.0 * r * 0.999 * Vec3::new(a.sin(), a.cos(), 0.0)
    }

    #[test]
    fn under_gravity_spheres_fall_asleep_from_the_ground_up() {
        // A column: a on the floor, b on a, c on b; d lower than c,
        // touching it, awake. Beside c (70 degrees from the vertical), d
        // must keep still (ready) for c to sleep; under it (45 degrees), d
        // must sleep. Below c, a and b sleep either way. Without gravity,
        // the island of the four sleeps whole once d is ready, and d
        // moving blocks it.
        let r = 0.05;
        let g = Vec3::new(0.0, -9.81, 0.0);
        let a = Vec3::new(0.5, r, 0.5);
        let (b, ready) = (on_top(a, r, 0.0), TIME_TO_SLEEP);
        let c = on_top(b, r, 0.0);
        for (degrees, d_rest, fell) in [(70.0, ready, 3), (70.0, 0.0, 2), (45.0, ready, 2)] {
            let d = c - (on_top(c, r, degrees) - c);
            let what = format!("{degrees} degrees, d at rest for {d_rest} s");
            let (mut bodies, mut links) = linked(&[a, b, c, d], r, &[ready, ready, ready, d_rest]);
            assert!(links.iter().any(|l| (l.i, l.j) == (2, 3)), "c touches d");
            // Under 60 degrees d would touch b too and rest on it: it is
            // held apart (in mid-air, it cannot sleep).
            links.retain(|l| (l.i, l.j) != (1, 3));
            let mut work = SleepWork::default();
            let dt = 1.0 / 60.0;
            let fallen = settle(&mut bodies, [&links, &[]], (dt, g), &mut work);
            assert_eq!(fallen, fell, "{what}");
            let asleep: Vec<bool> = bodies.rest.iter().map(|&r| is_asleep(r)).collect();
            assert_eq!(asleep, [true, true, fell == 3, false], "{what}");
            let (mut bodies, links) = linked(&[a, b, c, d], r, &[ready, ready, ready, d_rest]);
            let flat = settle(&mut bodies, [&links, &[]], (dt, Vec3::ZERO), &mut work);
            let whole = if d_rest == ready { 4 } else { 0 };
            assert_eq!(flat, whole, "without gravity, {what}");
        }
        // Alone in mid-air, at rest or not, nothing sleeps.
        let (mut bodies, links) = linked(&[b], r, &[ready]);
        assert_eq!(
            settle(
                &mut bodies,
                [&links, &[]],
                (0.01, g),
                &mut SleepWork::default()
            ),
            0
        );
    }

    #[test]
    fn a_sleeper_wakes_when_touched_in_ways_that_move_it_and_a_blow_wakes_its_group() {
        // Sleepers: a on the floor, b on a, f on the floor beside a; one
        // sphere awake, m, placed and moving in turn. `blow` as a world
        // at dt = 1/60 s with one resting step has it.
        let (r, h) = (0.05, 1.0 / 60.0);
        let g = Vec3::new(0.0, -9.81, 0.0);
        let blow = 2.0 * 9.81 * h;
        let a = Vec3::new(0.5, r, 0.5);
        let b = on_top(a, r, 0.0);
        let f = on_top(a, r, 90.0);
        let beside_a = a - (f - a);
        let toward_a = (a - beside_a).normalize();
        // `m` at rest pre-gravity has the velocity `g h` after it.
        let cases = [
            ("resting on b", on_top(b, r, 0.0), Vec3::ZERO, vec![]),
            ("leaning on b", on_top(b, r, 80.0), Vec3::ZERO, vec![]),
            ("sliding on b", on_top(b, r, 0.0), 0.2 * Vec3::Z, vec![]),
            (
                "still beside b, lower",
                b - (on_top(b, r, 80.0) - b),
                Vec3::ZERO,
                vec![],
            ),
            (
                "sliding beside b, lower",
                b - (on_top(b, r, 80.0) - b),
                0.2 * Vec3::Z,
                vec![1],
            ),
            (
                "touching a slowly",
                beside_a,
                0.5 * SLEEP_SPEED * toward_a,
                vec![],
            ),
            ("striking a", beside_a, 0.2 * toward_a, vec![0, 1]),
            ("striking a hard", beside_a, 0.5 * toward_a, vec![0, 1, 2]),
        ];
        for (what, m, v, woken) in cases {
            let (mut bodies, mut links) = linked(&[a, b, f, m], r, &[ASLEEP, ASLEEP, ASLEEP, 0.0]);
            bodies.velocity[3] = v + g * h;
            let all = links.clone();
            let touched = touch_once(&mut bodies, &mut links, (g, h, blow));
            assert_eq!(touched, Touch::Some(woken.len()), "{what}");
            for k in 0..3 {
                assert_eq!(
                    !is_asleep(bodies.rest[k]),
                    woken.contains(&k),
                    "{what}: {k}"
                );
            }
            // The pairs of two sleepers are taken out of the list (kept
            // aside); the rest stay, those of a sphere woken taken again
            // where it fell to with the sub-step's gravity (`catch_up`).
            let sleepers = |c: &&Contact| {
                is_asleep(bodies.rest[c.i as usize]) && is_asleep(bodies.rest[c.j as usize])
            };
            let kept: Vec<Contact> = all
                .iter()
                .filter(|c| !sleepers(c))
                .filter_map(|c| {
                    let moved = [c.i, c.j].iter().any(|k| woken.contains(&(*k as usize)));
                    if moved {
                        test_pair_within(&bodies, c.i as usize, c.j as usize, 0.0)
                    } else {
                        Some(*c)
                    }
                })
                .collect();
            assert_eq!(links, kept, "{what}");
            for &k in &woken {
                // Semi-implicit Euler from rest: v = g h, then x += v h.
                assert_eq!(
                    (bodies.position[k], bodies.velocity[k]),
                    ([a, b, f][k] + (g * h) * h, g * h),
                    "{what}: {k} fell as one awake"
                );
            }
        }
        // And a sleeper lying on a sphere awake wakes with what lies on
        // it: b on m (in a's place), at rest.
        let (mut bodies, mut links) = linked(&[a, b, on_top(b, r, 0.0)], r, &[0.0, ASLEEP, ASLEEP]);
        bodies.velocity[0] = g * h;
        let touched = touch_once(&mut bodies, &mut links, (g, h, blow));
        assert_eq!(touched, Touch::Some(2));
        // A sleeper left resting on nothing wakes: b alone in mid-air.
        let (mut bodies, mut links) = linked(&[b, a + 0.5 * Vec3::X], r, &[ASLEEP, 0.0]);
        let touched = touch_once(&mut bodies, &mut links, (g, h, blow));
        assert_eq!(touched, Touch::Some(1));
        // Without gravity, any touch wakes every sleeper.
        let (mut bodies, mut links) = linked(
            &[a, b, f, on_top(b, r, 0.0)],
            r,
            &[ASLEEP, ASLEEP, ASLEEP, 0.0],
        );
        let touched = touch_once(&mut bodies, &mut links, (Vec3::ZERO, h, blow));
        assert_eq!(touched, Touch::All);
        assert!(bodies.rest.iter().all(|&r| r == 0.0));
    }
}
