//! The stages of a step, named once. [`World::step`](super::World::step)
//! runs them in this order (the continuous method's events, or the narrow
//! phase and the solve as one stage, in place of those they replace); the
//! benchmark times each
//! ([`World::time_stages`](super::World::time_stages)).

use serde::Serialize;

/// One stage of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::VariantArray, strum::IntoStaticStr)]
#[strum(serialize_all = "snake_case")]
pub enum Stage {
    /// Forces and integration: `v += F/m dt`, `x += v dt`, in the order
    /// the method prescribes.
    Integrate,
    /// Which pairs may touch: the grid's cells (and, for large worlds, the
    /// spheres sorted into cell order); nothing for all-pairs.
    BroadPhase,
    /// Which pairs do touch: the overlap test of every candidate pair.
    NarrowPhase,
    /// The lesson's position projection and `V1`/`V2` per contact, then
    /// any further projection passes.
    SolveContacts,
    /// [`Stage::NarrowPhase`] and [`Stage::SolveContacts`] in one sweep,
    /// each contact resolved as it is found (and listed, when the list is
    /// kept: [`World::keep_contacts`](super::World::keep_contacts)): a
    /// large world on the grid in which nothing reads the contacts before
    /// they are all resolved.
    NarrowAndSolve,
    /// The box: centres back inside, velocities reflected.
    Walls,
    /// Resting contacts solved together (`support.rs`).
    Support,
    /// The continuous method's free flights and impacts, which replace the
    /// stages above (and run them only when a step reaches its impact cap).
    Events,
}

impl Stage {
    /// The name in output (`broad_phase`).
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// Seconds spent in each stage, summed over the steps timed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct StageSeconds {
    pub integrate: f64,
    pub broad_phase: f64,
    pub narrow_phase: f64,
    pub solve_contacts: f64,
    pub narrow_and_solve: f64,
    pub walls: f64,
    pub support: f64,
    pub events: f64,
}

impl StageSeconds {
    /// The seconds of `stage`.
    pub fn get(self, stage: Stage) -> f64 {
        let mut copy = self;
        *copy.of(stage)
    }

    /// The seconds of `stage`, to add to.
    pub fn of(&mut self, stage: Stage) -> &mut f64 {
        match stage {
            Stage::Integrate => &mut self.integrate,
            Stage::BroadPhase => &mut self.broad_phase,
            Stage::NarrowPhase => &mut self.narrow_phase,
            Stage::SolveContacts => &mut self.solve_contacts,
            Stage::NarrowAndSolve => &mut self.narrow_and_solve,
            Stage::Walls => &mut self.walls,
            Stage::Support => &mut self.support,
            Stage::Events => &mut self.events,
        }
    }

    /// Add `other`'s seconds, stage by stage.
    pub fn add(&mut self, other: StageSeconds) {
        for &s in <Stage as strum::VariantArray>::VARIANTS {
            *self.of(s) += other.get(s);
        }
    }

    /// The sum over the stages.
    pub fn total(self) -> f64 {
        <Stage as strum::VariantArray>::VARIANTS
            .iter()
            .map(|&s| self.get(s))
            .sum()
    }
}
