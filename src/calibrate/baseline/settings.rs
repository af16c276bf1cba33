//! The settings shared by every ramp of a sweep (material, geometry, mesh, contact, effects,
//! solver, gravity, sensitivities, warm start), the solver settings of a sensitivity sweep,
//! and the designs of a sweep with the pressures of their ramps.

use crate::calibrate::experiments::BendingRecord;
use crate::fe::campaign::WarmPool;
use crate::fe::effects::Effects;
use crate::fe::geometry::DesignParams;
use crate::fe::material::Material;
use crate::fe::mesh::MeshOptions;
use crate::fe::preset::Geometry;
use crate::fe::sensitivity::Parameter;
use crate::fe::simulate::{Case, ContactSettings, Mode, SimulateError};
use crate::fe::solver::SolverSettings;
use crate::rom::provenance::BuiltWith;

/// Largest pressure increment of a sensitivity sweep's load steps (bar; the diagnoser's sweep
/// at the calibrated state and the identification's sweeps), four times the solver's
/// default: only the states at the recorded pressures are used, and a converged state does
/// not depend on the path to it. Measured on the coarse N = 11, T = 2.0 actuator, 0 → 3 bar
/// with all 20 sensitivities, one core each: bending 96.6 → 60.5 s, blocked force 102.6 →
/// 65.7 s; tip, force and every derivative the same to 10⁻⁸ relative. Over the whole sweep
/// at the calibrated state every derivative of tip, angle and force is within 2.8 % of the
/// committed sweep in steps of 0.05 bar (`data/sensitivities/calibrated_coarse.json`)
/// and the verdict is the same: `fe_reference/diagnosis/bench.md`.
pub const SWEEP_MAX_PRESSURE_INCREMENT: f64 = 0.2;

/// Newton tolerance of a sensitivity sweep's ramps (normalised residual), ten times the
/// solver's default: the last Newton iteration of a load step takes the residual from about
/// 10⁻⁶ to 10⁻¹⁰, and the sensitivities do not need it. Measured on the coarse N = 13,
/// T = 1.6 mm actuator at the shipped experiments' calibrated set, 0 → 3 bar with all 20
/// sensitivities: bending 210 → 206 Newton iterations, blocked force 218 → 201; tip and force
/// the same to 10⁻⁵, every derivative of tip, angle and markers within 6·10⁻⁶ relative, of the
/// force within 0.05 % (one derivative of −1.5·10⁻⁴ N per unit within 0.5 %).
pub const SWEEP_RTOL: f64 = 1e-6;

/// The settings of a sweep, shared by every ramp: everything but the design and the pressures.
///
/// [`SweepSettings::new`] gives the baseline's own (gravity, default contact and solver, no
/// effect); a cached ramp is keyed by every field, and a neutral [`Effects`] leaves the key
/// as it was before effects existed, so committed caches stay valid.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSettings {
    /// The material.
    pub material: Material,
    /// The dimensions the reference study leaves unstated ([`Geometry`]); the historical
    /// [`Geometry::as_modelled`] leaves every design, and so every cache key, as it was.
    pub geometry: Geometry,
    /// Mesh level and options.
    pub mesh: MeshOptions,
    /// Contact settings (bellows, clamp, force plate).
    pub contact: ContactSettings,
    /// Physics beyond the nominal model, the same for every ramp.
    pub effects: Effects,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
    /// Self-weight on/off.
    pub gravity: bool,
    /// Differentiate every ramp's outputs with respect to these parameters
    /// ([`crate::fe::sensitivity`]; none by default). Such ramps are cached apart from the
    /// plain ones (their key names the parameters).
    pub sensitivities: Vec<Parameter>,
    /// Start each ramp that is not in the cache from the pool's ramp of the same design and
    /// rig (an earlier iteration of a calibration), moved to [`Self::warm_point`] by its
    /// displacement sensitivities ([`crate::fe::campaign::WarmPool`]), and keep it there for
    /// the next; `None`: every ramp starts cold. Not part of the cache key: a warm ramp gives
    /// the cold one's answers to the solver's tolerance.
    pub warm: Option<WarmPool>,
    /// The sweep's parameter point, one value per entry of [`Self::sensitivities`] (the step
    /// of a warm start is this minus the pooled ramp's point).
    pub warm_point: Vec<f64>,
    /// Run each design's blocked-force ramp beside its bending ramp (the default); `false`:
    /// bending only, for recordings without forces.
    pub force: bool,
}

impl SweepSettings {
    /// The baseline's settings for `material` on `mesh`: gravity, default contact and solver,
    /// no effect.
    pub fn new(material: Material, mesh: MeshOptions) -> Self {
        Self {
            material,
            geometry: Geometry::as_modelled(),
            mesh,
            contact: ContactSettings::default(),
            effects: Effects::default(),
            solver: SolverSettings::default(),
            gravity: true,
            sensitivities: Vec::new(),
            warm: None,
            warm_point: Vec::new(),
            force: true,
        }
    }

    /// These settings with the geometry and the fixed effects a surrogate's training cases
    /// were built with ([`BuiltWith`], from the model's training information), so that its
    /// FE runs are the model's own; `None` (the geometry as modelled, no fixed effect) leaves
    /// them as they are.
    pub fn built_as(mut self, built: Option<&BuiltWith>) -> Self {
        if let Some(b) = built {
            self.geometry = b.geometry.clone();
            self.effects = b.effects.clone();
        }
        self
    }

    /// The FE case of design `(n, t)` in `mode` through `pressures_bar`.
    ///
    /// # Errors
    /// [`SimulateError`] for a design outside the model's range or one the geometry cannot
    /// build.
    pub fn case(
        &self,
        n: usize,
        t: f64,
        pressures_bar: Vec<f64>,
        mode: Mode,
    ) -> Result<Case, SimulateError> {
        let design = if self.geometry.is_as_modelled() {
            DesignParams::new(n, t)
                .validate()
                .map_err(SimulateError::from)?
        } else {
            self.geometry.design(n, t).map_err(SimulateError::from)?
        };
        Ok(Case {
            design,
            material: self.material.clone(),
            pressures_bar,
            gravity: self.gravity,
            mesh: self.mesh,
            solver: self.solver.clone(),
            mode,
            contact: self.contact,
            effects: self.effects.clone(),
        })
    }
}

/// One design of a sweep and the pressures of its ramps (bar, increasing, from 0).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepDesign {
    /// Number of bellows.
    pub n_bellows: usize,
    /// Wall thickness (mm).
    pub wall_thickness_mm: f64,
    /// The ramp's pressures (bar): 0 and the recorded ones.
    pub pressures_bar: Vec<f64>,
}

/// The designs of `bending` (sorted by N, then T), each with 0 and its recorded pressures.
pub fn recorded_designs(bending: &[BendingRecord]) -> Vec<SweepDesign> {
    let mut designs: Vec<(usize, f64)> = bending
        .iter()
        .map(|r| (r.n_bellows, r.wall_thickness_mm))
        .collect();
    designs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    designs.dedup();
    designs
        .into_iter()
        .map(|(n, t)| {
            let mut pressures: Vec<f64> = bending
                .iter()
                .filter(|r| r.n_bellows == n && r.wall_thickness_mm == t)
                .map(|r| r.pressure_bar)
                .collect();
            pressures.sort_by(f64::total_cmp);
            pressures.insert(0, 0.0);
            pressures.dedup();
            SweepDesign {
                n_bellows: n,
                wall_thickness_mm: t,
                pressures_bar: pressures,
            }
        })
        .collect()
}
