//! The diagnosing model's own discretisation error, as a candidate the Name stage tests
//! beside the effects of the library.
//!
//! A surrogate trained on FE snapshots of one mesh carries that mesh's discretisation error:
//! on the coarse mesh (one quadratic element through a wall) the actuator is stiffer than on
//! the standard mesh, its bellows touch at another pressure and its blocked force is far from
//! converged (`fe_reference/convergence/table.md`). Recordings of a real actuator (or of a
//! twin simulated on another mesh) differ from the model by that error as well as by any
//! missing physics, and an effect whose signature resembles it would be named for it.
//!
//! Mesh refinement measures the error's shape. With a reference surrogate of the same plan on
//! another mesh (`models/as_modelled/actuator.json`, standard-mesh values, beside the coarse
//! `models/as_modelled/actuator_coarse.json`), every cell `i` gets
//!
//! ```text
//!   dᵢ = ŷᵢ,reference(θ) − ŷᵢ,model(θ)        (unit of the output, at the calibrated material θ)
//! ```
//!
//! Refinement of a mesh with one element through the wall converges along about this
//! direction (the error is dominated by the through-wall stiffening the coarse meshes
//! share), so the model's error against a finer mesh or a real actuator is about `ν d` for
//! some `ν`. The Name stage tests `d / σ` like an effect's signature (material projected
//! out, same F test and Holm family): when it explains the residual best, at a plausible
//! `|ν| ≤ 1.5` (Richardson extrapolation of `fe_reference/convergence/` puts the converged
//! solution at `ν ≈ 1.2` from the coarse mesh), the verdict says that the residual looks
//! like the model's own mesh error and names no physics. The direction is scale-free: it
//! serves a standard-mesh model too (with the coarse model as the reference, `ν` changes
//! sign).

use serde::{Deserialize, Serialize};

use super::cells::Cell;
use super::DiagnoseError;
use crate::calibrate::objective::Evaluator;
use crate::calibrate::params::ParamSpace;
use crate::case::OgdenSet;
use crate::rom::Surrogate;

/// The unit of a model error's size: multiples of `d` (reference − model).
pub const MODEL_ERROR_UNIT: &str = "× (reference − model)";

/// The sizes of a model error taken as plausible.
pub const PLAUSIBLE_MODEL_ERROR: (f64, f64) = (-1.5, 1.5);

/// A model-error direction over the cells of a residual table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorDirection {
    /// Its name in reports.
    pub name: String,
    /// Per cell of the table (in its order), the column in the unit of the cell's output
    /// (none: the cell does not carry it; it then counts as 0).
    pub per_cell: Vec<Option<f64>>,
}

impl ErrorDirection {
    /// The column of cell `i` (0 where none).
    pub fn at(&self, i: usize) -> f64 {
        self.per_cell.get(i).copied().flatten().unwrap_or(0.0)
    }
}

/// The mesh-refinement direction of a diagnosis (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshError {
    /// What the reference surrogate is (its file, as given).
    pub reference: String,
    /// The material at which the two surrogates were compared.
    pub material: OgdenSet,
    /// `rms(dᵢ / σᵢ)` over the cells: how large the refinement is against the recordings' σ.
    pub rms_sigma: f64,
    /// `rms(dᵢ / σᵢ)` per output family, in the table's family order.
    pub rms_sigma_by_output: Vec<(String, f64)>,
    /// The direction, per cell.
    pub direction: ErrorDirection,
}

/// `d = reference − model` at `material` for every cell of `cells` (see the [module
/// docs](self)); `reference_name` names the reference in the report.
///
/// # Errors
/// [`DiagnoseError::Input`] when `material` lies outside the reference's training domain or
/// the two surrogates predict different outputs; a surrogate error.
pub fn mesh_error(
    cells: &[Cell],
    model: &Surrogate,
    reference: &Surrogate,
    reference_name: &str,
    material: &OgdenSet,
) -> Result<MeshError, DiagnoseError> {
    if cells.is_empty() {
        return Err(DiagnoseError::input(
            "cells",
            0,
            "a residual table with at least one cell",
        ));
    }
    let set = super::cells::observations(cells);
    let predict = |m: &Surrogate, what: &str| -> Result<Vec<f64>, DiagnoseError> {
        let space = ParamSpace::training_domain(m)?;
        let u = space.unit(material);
        if u.iter().any(|v| !(-1e-9..=1.0 + 1e-9).contains(v)) {
            return Err(DiagnoseError::input(
                "material",
                material.spec(),
                &format!("a material inside the {what} surrogate's training domain"),
            ));
        }
        let u = u.map(|v| v.clamp(0.0, 1.0));
        Ok(Evaluator::new(m, &set, space).predictions(&u)?)
    };
    let y_model = predict(model, "diagnosing")?;
    let y_ref = predict(reference, "reference")?;
    // the observation set keeps the cells' order
    let d: Vec<f64> = y_ref.iter().zip(&y_model).map(|(a, b)| a - b).collect();
    let z: Vec<f64> = d.iter().zip(cells).map(|(v, c)| v / c.sigma).collect();
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let mut by_output = Vec::new();
    for f in super::cells::Family::ALL {
        let zs: Vec<f64> = cells
            .iter()
            .zip(&z)
            .filter(|(c, _)| c.family == f)
            .map(|(_, v)| *v)
            .collect();
        if !zs.is_empty() {
            by_output.push((f.label().to_string(), rms(&zs)));
        }
    }
    Ok(MeshError {
        reference: reference_name.to_string(),
        material: *material,
        rms_sigma: rms(&z),
        rms_sigma_by_output: by_output,
        direction: ErrorDirection {
            name: "model_mesh".into(),
            per_cell: d.into_iter().map(Some).collect(),
        },
    })
}
