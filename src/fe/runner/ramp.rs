//! The FE ramp as the runner sees it: a case with its parameter point and the parameters to
//! differentiate ([`RampCase`]), what its run gives ([`Ramp`]), and how it starts ([`Start`]:
//! cold, from its tree parent's states, or from a warm pool's).

use super::batch::{Outcome, Solved, Solver};
use super::pool::WarmPool;
use crate::fe::sensitivity::{
    sensitivities_with, sensitivities_with_fields, Parameter, Sensitivities, WithFields,
};
use crate::fe::simulate::{simulate_with, Case, Response, StepResult};
use crate::fe::warm_start::WarmStart;

/// One case of a campaign: the FE case, its parameter point (one value per parameter of the
/// campaign; what a warm start's step is measured in), and the parameters to differentiate
/// its outputs with respect to (none: a plain ramp).
#[derive(Clone, Debug)]
pub struct RampCase {
    /// The FE case.
    pub case: Case,
    /// Its parameter point (empty when its start needs none).
    pub point: Vec<f64>,
    /// The parameters of its sensitivities ([`crate::fe::sensitivity`]; none: no sensitivities).
    pub sensitivities: Vec<Parameter>,
}

impl RampCase {
    /// A plain ramp of `case`: no point, no sensitivities.
    pub fn plain(case: Case) -> Self {
        Self {
            case,
            point: Vec::new(),
            sensitivities: Vec::new(),
        }
    }
}

/// What the run of a ramp gives: the steps reached, the solver's message if it stopped, the
/// sensitivities when asked for and the ramp finished, and the solver's account of a ramp
/// that finished now (not kept by a store).
#[derive(Clone, Debug, Default)]
pub struct Ramp {
    /// The steps reached, in pressure order.
    pub steps: Vec<StepResult>,
    /// Why the ramp stopped early (`None`: it did not).
    pub error: Option<String>,
    /// The sensitivities of the steps, if asked for and the ramp finished.
    pub sensitivities: Option<Sensitivities>,
    /// The solver's account (mesh size, factorisations, times) of a ramp that finished now.
    pub response: Option<Response>,
}

impl Outcome for Ramp {
    fn failure(&self) -> Option<&str> {
        self.error.as_deref()
    }
}

/// How the cases of a tree campaign start from their parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WarmOrder {
    /// From the undeformed actuator (every ramp independent).
    Cold,
    /// From the tree parent's converged states.
    Zeroth,
    /// From the tree parent's states moved by their displacement sensitivities.
    First,
}

/// How each ramp of a run starts.
#[derive(Clone, Debug)]
pub enum Start {
    /// From the undeformed actuator; nothing is kept for another ramp.
    Cold,
    /// From its parent in the run's order ([`super::spanning_order`]), as [`WarmOrder`] says;
    /// every ramp keeps its converged states for its children. With [`WarmOrder::Cold`] the
    /// parents are not used: the same ramps as the warm orders, started cold (the reference a
    /// warm campaign is measured against).
    Tree(WarmOrder),
    /// From the pool's ramp of the same model (an earlier iteration of a calibration), moved
    /// to the case's point by its displacement sensitivities, and kept there for the next.
    Pool(WarmPool),
}

impl Solver<RampCase> for Start {
    type Ramp = Ramp;
    type Kept = WithFields;

    fn solve(
        &self,
        case: &RampCase,
        parent: Option<(&RampCase, &WithFields)>,
    ) -> Solved<Ramp, WithFields> {
        match self {
            Start::Cold => Solved {
                ramp: cold_ramp(&case.case, &case.sensitivities),
                kept: None,
                from_parent: false,
            },
            Start::Pool(pool) => Solved {
                ramp: pooled_ramp(case, pool),
                kept: None,
                from_parent: false,
            },
            Start::Tree(order) => tree_ramp(case, parent, *order),
        }
    }
}

/// A ramp from the undeformed actuator, with the sensitivities to `parameters` if any are
/// asked for (and the ramp finished).
pub fn cold_ramp(case: &Case, parameters: &[Parameter]) -> Ramp {
    let mut steps = Vec::new();
    if parameters.is_empty() {
        let outcome = simulate_with(case, |_, _| {}, |_, r, _| steps.push(r.clone()));
        return match outcome {
            Ok(response) => Ramp {
                steps,
                response: Some(response),
                ..Ramp::default()
            },
            Err(e) => Ramp {
                steps,
                error: Some(e.to_string()),
                ..Ramp::default()
            },
        };
    }
    match sensitivities_with(case, parameters, |_, _| {}, |_, r, _| steps.push(r.clone())) {
        Ok((response, sens)) => Ramp {
            steps,
            error: None,
            sensitivities: Some(sens),
            response: Some(response),
        },
        Err(e) => Ramp {
            steps,
            error: Some(e.to_string()),
            ..Ramp::default()
        },
    }
}

/// A ramp started from `pool`'s ramp of the same model, kept there for the next.
fn pooled_ramp(c: &RampCase, pool: &WarmPool) -> Ramp {
    let warm = pool.start_for(&c.case, &c.point);
    let (ramp, ran) = warm_ramp(c, warm.as_ref());
    if let Some(ran) = ran {
        pool.keep(&c.case, c.point.clone(), ran);
    }
    ramp
}

/// A ramp of a tree campaign, from its parent's kept states when it has them.
fn tree_ramp(
    c: &RampCase,
    parent: Option<(&RampCase, &WithFields)>,
    order: WarmOrder,
) -> Solved<Ramp, WithFields> {
    let warm = parent.and_then(|(p, kept)| match order {
        WarmOrder::Cold => None,
        WarmOrder::Zeroth => Some(WarmStart::new(kept.states.clone())),
        WarmOrder::First => {
            let delta: Vec<f64> = c.point.iter().zip(&p.point).map(|(a, b)| a - b).collect();
            kept.warm_start(&delta).ok()
        }
    });
    let (ramp, ran) = warm_ramp(c, warm.as_ref());
    Solved {
        ramp,
        kept: ran.filter(|_| order != WarmOrder::Cold),
        from_parent: warm.is_some(),
    }
}

/// A ramp from `warm` (cold without), keeping its converged states and their displacement
/// sensitivities when it finishes.
fn warm_ramp(c: &RampCase, warm: Option<&WarmStart>) -> (Ramp, Option<WithFields>) {
    let mut steps = Vec::new();
    match sensitivities_with_fields(
        &c.case,
        &c.sensitivities,
        warm,
        |_, _| {},
        |_, r, _| steps.push(r.clone()),
    ) {
        Ok(ran) => {
            let ramp = Ramp {
                steps,
                error: None,
                sensitivities: (!c.sensitivities.is_empty()).then(|| ran.sensitivities.clone()),
                response: Some(ran.response.clone()),
            };
            (ramp, Some(ran))
        }
        Err(e) => (
            Ramp {
                steps,
                error: Some(e.to_string()),
                ..Ramp::default()
            },
            None,
        ),
    }
}
