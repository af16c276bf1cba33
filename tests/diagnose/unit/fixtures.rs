//! What the unit tests of the Name, Measure and Refit stages build their sweeps from: the
//! study's nine designs, random outputs and one entry per parameter of the library.

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::calibrate::baseline::{
    DesignSensitivities, SweepSensitivities, SWEEP_SENSITIVITY_FORMAT,
};
use surrogate::fe::effects::Effects;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;
use surrogate::fe::sensitivity::{
    Outputs, Parameter, ParameterInfo, Sensitivities, SensitivityCost, StepSensitivities,
};
use surrogate::fe::simulate::Mode;

/// The nine designs of the shipped experiments (N, T in mm).
pub const DESIGNS: [(u32, f64); 9] = [
    (9, 1.6),
    (9, 2.0),
    (9, 2.4),
    (11, 1.6),
    (11, 2.0),
    (11, 2.4),
    (13, 1.6),
    (13, 2.0),
    (13, 2.4),
];

/// Bending outputs (tip, angle, 9 markers, no force) drawn uniformly in [−1, 1).
pub fn random_outputs(rng: &mut Xoshiro256PlusPlus) -> Outputs {
    let mut g = || rng.gen_range(-1.0..1.0);
    Outputs {
        tip_uz_mm: g(),
        tip_uy_mm: g(),
        angle_deg: g(),
        markers: (0..9).map(|_| [g(), g()]).collect(),
        force_n: None,
    }
}

/// One entry per parameter of the library, at 0 with a tiny step (a sweep's header).
pub fn every_parameter() -> Vec<ParameterInfo> {
    Parameter::all()
        .into_iter()
        .map(|p| ParameterInfo {
            parameter: p,
            unit: p.unit().into(),
            value: 0.0,
            step: 1e-6,
            how: String::new(),
        })
        .collect()
}

/// A bending sweep at Ogden 002 on the coarse mesh, the geometry as modelled, no fixed
/// effect: `designs` as (N, T in mm, its steps), each step with one derivative per entry of
/// `parameters`.
pub fn bending_sweep(
    parameters: &[ParameterInfo],
    designs: Vec<(usize, f64, Vec<StepSensitivities>)>,
) -> SweepSensitivities {
    let designs = designs
        .into_iter()
        .map(|(n, t, steps)| DesignSensitivities {
            n_bellows: n,
            wall_thickness_mm: t,
            mode: Mode::Bending,
            sensitivities: Sensitivities {
                format: String::new(),
                version: 1,
                mode: Mode::Bending,
                parameters: parameters.to_vec(),
                steps,
                cost: SensitivityCost::default(),
            },
        })
        .collect();
    SweepSensitivities {
        format: SWEEP_SENSITIVITY_FORMAT.into(),
        version: 1,
        material: Material::from_spec("ogden_002", 1000.0).unwrap(),
        mesh: MeshOptions::level(MeshLevel::Coarse),
        geometry: Geometry::as_modelled(),
        effects: Effects::neutral(),
        designs,
        missing: Vec::new(),
    }
}
