//! The domain a surrogate states from the snapshot plan its training cases were run with.
use super::data::CaseSet;
use super::provenance::BuiltWith;
use super::Surrogate;
use crate::snapshots::plan::Plan;

impl Surrogate {
    /// States the domain of the snapshot `plan` the training `cases` were run with (`label`
    /// names the plan, its file) in the model's training information
    /// ([`TrainingInfo::plan_domain`](super::provenance::TrainingInfo::plan_domain)): the
    /// plan's nominal ends where the cases come within one stratum of them
    /// ([`Plan::stated_domain`]). A plan that does not hold every case (another plan's) states
    /// nothing, and `false` is returned: the domain stays the box of the cases.
    ///
    /// A plan with a geometry preset or fixed effects also states them
    /// ([`TrainingInfo::built_with`](super::provenance::TrainingInfo::built_with)).
    pub fn state_plan_domain(&mut self, plan: &Plan, cases: &CaseSet, label: &str) -> bool {
        let held = cases
            .cases
            .iter()
            .all(|c| plan.holds(&c.case_id, &c.inputs));
        if held {
            let sampled = self.sampled_domain();
            self.training.plan_domain = Some(plan.stated_domain(&sampled, label));
            self.training.built_with = BuiltWith::of_plan(plan);
        }
        held
    }
}

impl BuiltWith {
    /// How the cases of every plan of `plans` are built (as [`Self::of_plan`]), when they are
    /// all built alike: the sets of several plans can then train one model
    /// ([`SnapshotSet::append`](super::data::SnapshotSet::append)).
    ///
    /// # Errors
    /// The index of the first plan that builds its cases otherwise than `plans[0]`.
    pub fn of_plans(plans: &[&Plan]) -> Result<Option<Self>, usize> {
        let built = plans.first().and_then(|p| Self::of_plan(p));
        match plans.iter().position(|p| Self::of_plan(p) != built) {
            Some(i) => Err(i),
            None => Ok(built),
        }
    }

    /// How the cases of `plan` are built: its geometry preset and fixed effects, or `None`
    /// for the geometry as modelled without a fixed effect.
    pub fn of_plan(plan: &Plan) -> Option<Self> {
        let fixed = plan.settings.effects.clone();
        (plan.settings.geometry.is_some() || fixed.iter().next().is_some()).then(|| BuiltWith {
            geometry: plan.settings.geometry(),
            effects: fixed,
        })
    }
}
