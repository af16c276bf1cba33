//! Synthetic snapshot sets for tests and demos (no FE involved).
//!
//! The actuator is idealised as a constant-curvature arc of length `L = 92 mm` whose tip
//! tangent turns by `φ(N, T, material, P)`. Marker `k` at arc length `s_k = kL/9` moves to
//! `z_k = sin(κ s_k)/κ`, `y_k = −(1 − cos κ s_k)/κ` with `κ = φ/L`, so
//! `Uz_k = s_k − z_k`, `Uy_k = y_k`, and the angle is `α = atan2(−y_9, z_9)`. The turn has a
//! gravity part and a saturating pressure part that grows with compliance
//! `c ∝ (2/T)^1.5 (N/11)^0.5 (μ₀ref/μ₀)^0.8`, with a smooth "contact onset" stiffening whose
//! pressure grows with `T`; the blocked force grows like `P^1.3` with stiffness and thickness.
//! Magnitudes follow the SPEC (tip Uz 0..~70 mm, Uy 0..~−70 mm, angle 0..~75°, force 0..~5 N).

use std::io::Write;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::{Q_ANGLE, Q_FORCE, Q_TIP_UY, Q_TIP_UZ};
use crate::case::{CaseInputs, OgdenSet};
use crate::schema;
use crate::schema::SNAPSHOT_COLUMN_NAMES;

/// Settings of a synthetic snapshot set.
#[derive(Debug, Clone)]
pub struct SyntheticConfig {
    /// Number of cases.
    pub n_cases: usize,
    /// RNG seed.
    pub seed: u64,
    /// Numbers of bellows to draw from.
    pub n_values: Vec<u32>,
    /// Standard deviation of additive noise on displacements (mm); angle and force get
    /// proportional noise. Zero for exact data.
    pub noise_mm: f64,
    /// Fraction of cases whose last pressure steps are reported as unconverged.
    pub unconverged_fraction: f64,
    /// Pressure grid, bar.
    pub pressures: Vec<f64>,
    /// One Ogden set for every case instead of random ones.
    pub fixed_material: Option<OgdenSet>,
}

impl Default for SyntheticConfig {
    fn default() -> Self {
        SyntheticConfig {
            n_cases: 60,
            seed: 7,
            n_values: vec![9, 11, 13],
            noise_mm: 0.0,
            unconverged_fraction: 0.0,
            pressures: (0..15).map(|i| 0.25 * i as f64).collect(),
            fixed_material: None,
        }
    }
}

/// Free length, mm.
const L: f64 = 92.0;

/// The exact synthetic response (22 quantities, [`super::QUANTITY_NAMES`] order).
pub fn response(c: &CaseInputs, p: f64) -> [f64; 22] {
    let m = &c.material;
    let mu0 = 0.5 * (m.mu1_mpa * m.alpha1 + m.mu2_mpa * m.alpha2);
    let stiff = (5.708 / mu0).powf(0.8);
    let t = c.wall_thickness_mm;
    let n = c.n_bellows as f64;
    let compliance = (2.0 / t).powf(1.5) * (n / 11.0).sqrt() * stiff;
    let exponent_effect = 1.0 + 0.04 * (m.alpha1 - 3.0) - 0.1 * (m.alpha2 + 0.6);
    let p_contact = 0.5 + 1.9 * (t - 1.6) / 0.8;
    let softplus = |x: f64| if x > 30.0 { x } else { (1.0 + x.exp()).ln() };
    let stiffening = 0.12 * softplus((p - p_contact) / 0.3) * 0.3;
    let phi_p = 2.7 * (1.0 - (-0.45 * p * compliance * exponent_effect).exp()) - stiffening;
    let phi_g = 0.2 * stiff * (2.0 / t).powf(1.5) / (1.0 + 0.3 * p);
    let phi = (phi_p + phi_g).max(1e-6);
    let kappa = phi / L;
    let mut v = [0.0; 22];
    for k in 1..=9 {
        let s = k as f64 * L / 9.0;
        let z = (kappa * s).sin() / kappa;
        let y = -(1.0 - (kappa * s).cos()) / kappa;
        v[2 * (k - 1)] = s - z;
        v[2 * (k - 1) + 1] = y;
    }
    v[Q_TIP_UZ] = v[16];
    v[Q_TIP_UY] = v[17];
    let (z9, y9) = (L - v[16], v[17]);
    v[Q_ANGLE] = (-y9).atan2(z9).to_degrees();
    let p_eff = p.max(0.0);
    v[Q_FORCE] = 1.2
        * (mu0 / 5.708).powf(0.3)
        * (t / 2.0).powf(0.8)
        * (n / 11.0).powf(0.2)
        * p_eff.powf(1.3)
        / (1.0 + 0.15 * p_eff);
    v
}

/// Draws the cases of a synthetic set (deterministic for a seed).
pub fn sample_cases(cfg: &SyntheticConfig) -> Vec<CaseInputs> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(cfg.seed);
    (0..cfg.n_cases)
        .map(|i| {
            let t = rng.gen_range(1.2..2.8);
            let m = OgdenSet::from_array([
                rng.gen_range(0.6..1.8),
                rng.gen_range(2.6..3.6),
                rng.gen_range(-18.0..-9.0),
                rng.gen_range(-0.8..-0.4),
            ]);
            CaseInputs {
                n_bellows: cfg.n_values[i % cfg.n_values.len()],
                wall_thickness_mm: t,
                material: cfg.fixed_material.unwrap_or(m),
            }
        })
        .collect()
}

/// Writes a synthetic snapshot CSV following the snapshot contract, with trailing provenance
/// columns (`newton_iterations, mesh, code_version`).
///
/// # Errors
/// Write failures.
pub fn write_csv<W: Write>(cfg: &SyntheticConfig, out: W) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(out);
    writeln!(
        w,
        "{},{},{},{}",
        SNAPSHOT_COLUMN_NAMES.join(","),
        schema::NEWTON_ITERATIONS.name,
        schema::MESH.name,
        schema::CODE_VERSION.name
    )?;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(cfg.seed ^ 0x5eed);
    let cases = sample_cases(cfg);
    for (i, c) in cases.iter().enumerate() {
        let truncate = rng.gen::<f64>() < cfg.unconverged_fraction;
        for (j, &p) in cfg.pressures.iter().enumerate() {
            let converged = !(truncate && j + 2 >= cfg.pressures.len());
            let mut v = response(c, p);
            if cfg.noise_mm > 0.0 {
                for (q, x) in v.iter_mut().enumerate() {
                    let sd = match q {
                        Q_ANGLE => 0.05 * cfg.noise_mm,
                        Q_FORCE => 0.01 * cfg.noise_mm,
                        _ => cfg.noise_mm,
                    };
                    *x += sd * (rng.gen::<f64>() - 0.5) * 3.464;
                }
            }
            write!(
                w,
                "case{i:04},{},{},{},{},{},{},{},{}",
                c.n_bellows,
                c.wall_thickness_mm,
                c.material.mu1_mpa,
                c.material.alpha1,
                c.material.mu2_mpa,
                c.material.alpha2,
                p,
                converged
            )?;
            let order = [Q_TIP_UZ, Q_TIP_UY, Q_ANGLE, Q_FORCE];
            for q in order.iter().copied().chain(0..18) {
                if converged {
                    write!(w, ",{}", v[q])?;
                } else {
                    write!(w, ",NaN")?;
                }
            }
            writeln!(w, ",{},hex8-coarse,synthetic", 5 + j / 4)?;
        }
    }
    w.flush()
}
