//! The domain a surrogate trained on a plan's cases accepts, and what its model file states.

use super::cases::case_name;
use super::format::Plan;
use crate::case::{CaseInputs, Domain, DomainViolation, OgdenSet, PlanDomain, Query};
use crate::fe::material::{literature_sets, MaterialError, MaterialLaw};

impl Plan {
    /// The domain a surrogate trained on all cases of this plan accepts: the box its cases
    /// span in the regression's coordinates ([`Domain::of_cases`], as the surrogate builds
    /// its own), reaching the plan's nominal end wherever the cases come within one stratum
    /// of it ([`Domain::with_plan_ends`]), as the model file states it
    /// ([`Self::stated_domain`]), so the two agree on every query.
    pub fn sampled_domain(&self) -> Domain {
        self.cases_domain()
            .with_plan_ends(&self.ranges.domain(&[0.0]), self.cases.len())
    }

    /// What a model trained on this plan's cases states of its domain
    /// ([`PlanDomain`]): `sampled`, the box of its training cases
    /// ([`crate::rom::Surrogate::sampled_domain`]), with the plan's nominal ends where the
    /// cases come within one stratum of them; `label` names the plan (its file), to which the
    /// plan's hash is added.
    pub fn stated_domain(&self, sampled: &Domain, label: &str) -> PlanDomain {
        PlanDomain {
            plan: format!("{label} (plan {})", self.hash()),
            plan_cases: self.cases.len(),
            ranges: sampled
                .with_plan_ends(&self.ranges.domain(&[0.0]), self.cases.len())
                .stated_ranges(),
        }
    }

    /// Whether this plan holds a case of id `case_id` (`case_000012`) with the design and
    /// material `inputs` (a snapshot set's case, checked before the plan states its domain).
    pub fn holds(&self, case_id: &str, inputs: &CaseInputs) -> bool {
        self.cases.iter().any(|c| {
            case_name(c.id) == case_id
                && c.n_bellows as u32 == inputs.n_bellows
                && c.wall_thickness_mm == inputs.wall_thickness_mm
                && c.material == inputs.material
        })
    }

    /// The box the cases span ([`Domain::of_cases`]).
    fn cases_domain(&self) -> Domain {
        let cases: Vec<CaseInputs> = self
            .cases
            .iter()
            .map(|c| CaseInputs {
                n_bellows: c.n_bellows as u32,
                wall_thickness_mm: c.wall_thickness_mm,
                material: c.material,
            })
            .collect();
        Domain::of_cases(&cases, &self.settings.pressures_bar)
    }

    /// The literature Ogden sets and the material inputs of each outside
    /// [`Self::sampled_domain`] (an empty list: inside).
    ///
    /// # Errors
    /// If the shipped literature file cannot be read.
    pub fn literature_in_sampled_domain(
        &self,
    ) -> Result<Vec<(String, Vec<DomainViolation>)>, MaterialError> {
        let domain = self.sampled_domain();
        let (n, t, p) = (
            domain.n_bellows.first().copied().unwrap_or(0),
            domain.ranges[1].map_or(0.0, |r| r[0]),
            domain.ranges[2].map_or(0.0, |r| r[0]),
        );
        Ok(literature_sets()?
            .into_iter()
            .filter_map(|(name, law)| match law {
                MaterialLaw::Ogden(o) => {
                    let v = domain.violations(&Query::new(n, t, p, OgdenSet::from(&o)));
                    Some((name, v))
                }
                _ => None,
            })
            .collect())
    }
}
