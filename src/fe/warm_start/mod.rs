//! A ramp's converged states, and warm starts of another ramp from them.
//!
//! A [`WarmStart`] holds a neighbouring case's converged states (the same design, mesh and rig
//! at another material, effect or nearby dimension), optionally moved to the new parameters
//! by their first-order displacement sensitivities, `u(θ + Δθ) ≈ u(θ) + (∂u/∂θ) Δθ`
//! ([`FieldSensitivities`], from [`crate::fe::sensitivity::sensitivities_with_fields`]).
//! [`crate::fe::simulate::run_warm`] then starts each output level's Newton iteration from the
//! matching state ([`crate::fe::solver::warm`]): same tolerances, same answers, fewer
//! iterations. A state of another mesh (another number of unknowns) is not used: those levels
//! take the load path as usual.
//!
//! A new design of the same layout (another wall thickness at the same `N`) has another mesh:
//! [`WarmStart::transferred`] carries the states onto it first ([`transfer`]: each node's
//! material point in the other design, by the piecewise-linear map between their features,
//! interpolated with the other mesh's shape functions).

use crate::fe::assembly::LoadLevel;
use crate::fe::geometry::Design;
use crate::fe::mesh::ActuatorMesh;
use crate::fe::solver::LevelGuess;

mod transfer;

pub use transfer::{material_map, transfer, Transfer, TransferError};

/// A converged state of a ramp, kept for what is computed after it (the sensitivities,
/// [`crate::fe::sensitivity`], and warm starts): the displacement with everything it was in
/// equilibrium with.
#[derive(Clone, Debug)]
pub struct ConvergedState {
    /// Gauge pressure (bar) as requested (0 for the self-weight state).
    pub pressure_bar: f64,
    /// The load level it is in equilibrium at (the effective pressure, MPa).
    pub level: LoadLevel,
    /// Full displacement vector.
    pub u: Vec<f64>,
    /// The contact gap shifts it was solved with
    /// ([`FeModel::contact_shifts`](crate::fe::assembly::FeModel::contact_shifts)).
    pub shifts: Vec<f64>,
    /// The force plate's height (mm), in the blocked-force rig.
    pub plate_y: Option<f64>,
    /// Whether it is one of the reported steps; the self-weight state of a ramp that does not
    /// start at 0 bar is kept but not reported.
    pub reported: bool,
}

/// Displacement sensitivities `∂u/∂θⱼ` of a ramp's converged states.
#[derive(Clone, Debug, Default)]
pub struct FieldSensitivities {
    /// The parameters' names, in the order of `du`'s inner index.
    pub parameters: Vec<String>,
    /// `du[s][j]`: `∂u/∂θⱼ` (all dofs) at converged state `s` (the order of the ramp's states);
    /// empty where it was not computed (a state that is not differentiated, a parameter that
    /// does not move the displacement).
    pub du: Vec<Vec<Vec<f64>>>,
}

/// Why a warm start cannot be built.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum WarmStartError {
    /// The sensitivities do not belong to the states.
    #[error(
        "the displacement sensitivities have {fields} states and {parameters} parameters, the \
         warm start {states} states and {deltas} parameter steps"
    )]
    Mismatch {
        /// States of the sensitivities.
        fields: usize,
        /// Parameters of the sensitivities.
        parameters: usize,
        /// States given.
        states: usize,
        /// Steps given.
        deltas: usize,
    },
    /// A parameter step is not finite.
    #[error("parameter step {index} ({name}) is {value}: expected a finite number")]
    NotFinite {
        /// Its index.
        index: usize,
        /// Its name.
        name: String,
        /// Its value.
        value: f64,
    },
}

/// The converged states of a neighbouring case, to start a ramp's levels from.
#[derive(Clone, Debug, Default)]
pub struct WarmStart {
    /// The self-weight state first, then one per pressure level (as
    /// [`Ran::states`](crate::fe::simulate::Ran::states)).
    pub states: Vec<ConvergedState>,
    /// The displacements before [`WarmStart::moved`] moved them (one per state), tried where
    /// Newton fails from the moved ones.
    pub unmoved: Option<Vec<Vec<f64>>>,
}

impl WarmStart {
    /// The neighbour's states as they are (zeroth order).
    pub fn new(states: Vec<ConvergedState>) -> Self {
        Self {
            states,
            unmoved: None,
        }
    }

    /// The neighbour's states moved by `Σⱼ (∂u/∂θⱼ) Δθⱼ` (first order), `delta` in the order
    /// of `fields.parameters` (the new case's parameters minus the neighbour's).
    ///
    /// # Errors
    /// Sensitivities of another number of states or parameters; a step that is not finite.
    pub fn moved(
        mut states: Vec<ConvergedState>,
        fields: &FieldSensitivities,
        delta: &[f64],
    ) -> Result<Self, WarmStartError> {
        if fields.du.len() != states.len() || fields.parameters.len() != delta.len() {
            return Err(WarmStartError::Mismatch {
                fields: fields.du.len(),
                parameters: fields.parameters.len(),
                states: states.len(),
                deltas: delta.len(),
            });
        }
        if let Some((index, &value)) = delta.iter().enumerate().find(|(_, d)| !d.is_finite()) {
            return Err(WarmStartError::NotFinite {
                index,
                name: fields.parameters[index].clone(),
                value,
            });
        }
        let unmoved = states.iter().map(|st| st.u.clone()).collect();
        for (st, du) in states.iter_mut().zip(&fields.du) {
            for (d, &step) in du.iter().zip(delta) {
                if d.len() == st.u.len() && step != 0.0 {
                    for (u, v) in st.u.iter_mut().zip(d) {
                        *u += step * v;
                    }
                }
            }
        }
        Ok(Self {
            states,
            unmoved: Some(unmoved),
        })
    }

    /// The states of design A (on `mesh_a`) carried onto the mesh of design B of the same
    /// layout (`mesh_b`, the mesh [`crate::fe::simulate::run_warm`] builds for B: the printed
    /// design's, at the case's mesh options), zeroth order ([`Transfer`]; the contact gap
    /// shifts kept only where the meshes have the same topology, see [`transfer`]).
    ///
    /// # Errors
    /// [`TransferError`]: designs of different layouts, a node of B outside A's solid, a
    /// state that is not of `mesh_a`.
    pub fn transferred(
        states: &[ConvergedState],
        (mesh_a, design_a): (&ActuatorMesh, &Design),
        (mesh_b, design_b): (&ActuatorMesh, &Design),
    ) -> Result<Self, TransferError> {
        let transfer = Transfer::new(mesh_a, design_a, mesh_b, design_b)?;
        Self::new(states.to_vec()).carried(&transfer)
    }

    /// This warm start (its states and, if moved, the unmoved displacements) carried onto
    /// another design's mesh by `transfer` ([`Transfer::new`] from this warm start's mesh):
    /// a first-order warm start moved by the sensitivities to the wall thickness, then
    /// carried onto the new design's mesh.
    ///
    /// # Errors
    /// [`TransferError::Length`] for a state or displacement not of the transfer's source mesh.
    pub fn carried(&self, transfer: &Transfer) -> Result<Self, TransferError> {
        let states = self
            .states
            .iter()
            .enumerate()
            .map(|(k, st)| transfer.state(k, st))
            .collect::<Result<_, _>>()?;
        let unmoved = match &self.unmoved {
            Some(us) => Some(
                us.iter()
                    .enumerate()
                    .map(|(k, u)| {
                        transfer.displacement(u).ok_or(TransferError::Length {
                            state: k,
                            len: u.len(),
                            expected: transfer.source_len(),
                        })
                    })
                    .collect::<Result<_, _>>()?,
            ),
            None => None,
        };
        Ok(Self { states, unmoved })
    }

    /// The guess for each level of a ramp: `levels_bar[0]` is the self-weight state, the
    /// others the pressure levels (bar) matched to the neighbour's states of the same
    /// requested pressure. `None` where the neighbour has no such state.
    pub fn guesses(&self, pressure_levels_bar: &[f64]) -> Vec<Option<LevelGuess>> {
        let guess = |k: usize| {
            let st = &self.states[k];
            LevelGuess {
                u_full: st.u.clone(),
                shifts: st.shifts.clone(),
                fallback: self.unmoved.as_ref().and_then(|u| u.get(k).cloned()),
            }
        };
        let mut out = vec![(!self.states.is_empty()).then(|| guess(0))];
        out.extend(pressure_levels_bar.iter().map(|&p| {
            (1..self.states.len())
                .find(|&k| self.states[k].pressure_bar == p)
                .map(guess)
        }));
        out
    }
}
