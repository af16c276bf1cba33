//! Material-point checks against the incompressible closed forms (uniaxial, equibiaxial,
//! planar): from the isochoric stress at `J = 1`, and by a traction-free Newton solve of the
//! total model with `κ = 10⁶ μ0`.

use nalgebra::{Matrix3, Vector3};
use surrogate::fe::material::{Material, MaterialLaw, MooneyRivlin5, NeoHookean, Ogden2};

/// Homogeneous incompressible test modes, stretch `λ` along x.
#[derive(Clone, Copy, Debug)]
enum Mode {
    /// `diag(λ, λ^{-1/2}, λ^{-1/2})`, lateral faces free.
    Uniaxial,
    /// `diag(λ, λ, λ^{-2})`, z free.
    Equibiaxial,
    /// `diag(λ, 1, λ^{-1})` (pure shear), z free.
    Planar,
}

const MODES: [Mode; 3] = [Mode::Uniaxial, Mode::Equibiaxial, Mode::Planar];
const STRETCHES: [f64; 6] = [0.7, 0.9, 1.05, 1.3, 1.8, 2.5];

impl Mode {
    /// Incompressible principal stretches.
    fn stretches(self, l: f64) -> [f64; 3] {
        match self {
            Mode::Uniaxial => [l, l.powf(-0.5), l.powf(-0.5)],
            Mode::Equibiaxial => [l, l, l.powi(-2)],
            Mode::Planar => [l, 1.0, 1.0 / l],
        }
    }

    /// Index of the traction-free direction.
    fn free(self) -> usize {
        match self {
            Mode::Uniaxial => 1,
            Mode::Equibiaxial | Mode::Planar => 2,
        }
    }
}

/// Closed-form incompressible nominal stress `P_xx` of Ogden: with `σ_a − σ_b`
/// `= Σ μ_i (λ_a^α_i − λ_b^α_i)`: uniaxial `Σ μ_i (λ^{α_i−1} − λ^{−α_i/2−1})`, equibiaxial
/// `Σ μ_i (λ^{α_i−1} − λ^{−2α_i−1})`, planar `Σ μ_i (λ^{α_i−1} − λ^{−α_i−1})`.
fn ogden_nominal(mu: [f64; 2], alpha: [f64; 2], mode: Mode, l: f64) -> f64 {
    (0..2)
        .map(|i| {
            let (m, a) = (mu[i], alpha[i]);
            m * match mode {
                Mode::Uniaxial => l.powf(a - 1.0) - l.powf(-a / 2.0 - 1.0),
                Mode::Equibiaxial => l.powf(a - 1.0) - l.powf(-2.0 * a - 1.0),
                Mode::Planar => l.powf(a - 1.0) - l.powf(-a - 1.0),
            }
        })
        .sum()
}

/// Closed-form incompressible nominal stress of Mooney–Rivlin from
/// `σ_a − σ_b = 2 (λ_a² − λ_b²)(W1 + λ_c² W2)` (`c` the third direction):
/// uniaxial `2(λ − λ⁻²)(W1 + W2/λ)`, equibiaxial `2(λ − λ⁻⁵)(W1 + λ² W2)`,
/// planar `2(λ − λ⁻³)(W1 + W2)`.
fn mooney_rivlin_nominal(c: [f64; 5], mode: Mode, l: f64) -> f64 {
    let [c10, c01, c20, c11, c02] = c;
    let s = mode.stretches(l);
    let i1 = s.iter().map(|x| x * x).sum::<f64>() - 3.0;
    let i2 = s.iter().map(|x| x.powi(-2)).sum::<f64>() - 3.0;
    let w1 = c10 + 2.0 * c20 * i1 + c11 * i2;
    let w2 = c01 + c11 * i1 + 2.0 * c02 * i2;
    match mode {
        Mode::Uniaxial => 2.0 * (l - l.powi(-2)) * (w1 + w2 / l),
        Mode::Equibiaxial => 2.0 * (l - l.powi(-5)) * (w1 + l * l * w2),
        Mode::Planar => 2.0 * (l - l.powi(-3)) * (w1 + w2),
    }
}

/// Closed-form incompressible nominal stress `P_xx(mode, λ)`.
type ClosedForm = Box<dyn Fn(Mode, f64) -> f64>;

/// The analytic cases: name, material law, closed form.
fn analytic_cases() -> Vec<(&'static str, MaterialLaw, ClosedForm)> {
    let (mu, alpha) = ([1.13, -13.17], [3.11, -0.6]);
    let mr = [-0.233, 2.562, 0.116, -0.561, 0.900];
    let (mu5, alpha5) = ([0.13, -1214.0], [3.05, -0.0054]);
    vec![
        (
            "ogden_002",
            Ogden2::new(mu[0], alpha[0], mu[1], alpha[1])
                .unwrap()
                .into(),
            Box::new(move |m, l| ogden_nominal(mu, alpha, m, l)),
        ),
        (
            "ogden_005",
            Ogden2::new(mu5[0], alpha5[0], mu5[1], alpha5[1])
                .unwrap()
                .into(),
            Box::new(move |m, l| ogden_nominal(mu5, alpha5, m, l)),
        ),
        (
            "mooney_rivlin_5",
            MooneyRivlin5::new(mr[0], mr[1], mr[2], mr[3], mr[4])
                .unwrap()
                .into(),
            Box::new(move |m, l| mooney_rivlin_nominal(mr, m, l)),
        ),
        (
            "neo_hookean",
            NeoHookean::new(2.5).unwrap().into(),
            Box::new(move |m, l| ogden_nominal([2.5, 0.0], [2.0, 1.0], m, l)),
        ),
    ]
}

#[test]
fn isochoric_stress_matches_incompressible_closed_forms() {
    for (name, law, nominal) in analytic_cases() {
        let material = Material::with_kappa(law, 1.0).unwrap();
        for mode in MODES {
            for l in STRETCHES {
                let s = mode.stretches(l);
                let f = Matrix3::from_diagonal(&Vector3::from(s));
                let mut p = Matrix3::zeros();
                material.iso_stress_into(&f, &mut p);
                // J = 1: Cauchy σ_a = P_aa λ_a; the pressure cancels in σ_x − σ_free.
                let free = mode.free();
                let got = (p[(0, 0)] * s[0] - p[(free, free)] * s[free]) / l;
                let want = nominal(mode, l);
                let err = (got - want).abs() / want.abs().max(material.mu0());
                assert!(
                    err < 1e-10,
                    "{name} {mode:?} λ = {l}: {got} vs {want} ({err:e})"
                );
            }
        }
    }
}

/// Total-model state with stretch `l` along x and the free direction solved for
/// zero traction by Newton; returns `(P_xx, J)`.
fn traction_free_state(material: &Material, mode: Mode, l: f64) -> (f64, f64) {
    let mut s = mode.stretches(l);
    let free = mode.free();
    let diagonal = |s: &[f64; 3]| Matrix3::from_diagonal(&Vector3::from(*s));
    for _ in 0..50 {
        let (p, a) = material.stress_tangent(&diagonal(&s));
        let row = 4 * free;
        // uniaxial: both lateral stretches move together
        let slope = match mode {
            Mode::Uniaxial => a[(row, 4)] + a[(row, 8)],
            Mode::Equibiaxial | Mode::Planar => a[(row, row)],
        };
        let step = p[(free, free)] / slope;
        s[free] -= step;
        if matches!(mode, Mode::Uniaxial) {
            s[2] = s[1];
        }
        if step.abs() < 1e-15 {
            break;
        }
    }
    let f = diagonal(&s);
    let p = material.stress(&f);
    // round-off floor: ε κ ≈ 2e-10 μ0 for κ = 1e6 μ0
    let residual = p[(free, free)].abs() / material.mu0();
    assert!(
        residual < 1e-8,
        "{mode:?} λ = {l}: Newton stopped at |P_free|/μ0 = {residual:e}"
    );
    (p[(0, 0)], f.determinant())
}

/// Total model with `κ = 10⁶ μ0`, lateral stretch from zero traction. The compressible
/// nominal stress differs from the incompressible one by a term of first order in `|J − 1|`,
/// itself `~ |p|/κ` with `p` the hydrostatic stress, so: `|J − 1| ≤ 3 |P| λ / κ`, the raw
/// relative difference is below `5 |J − 1|`, and the Richardson extrapolation
/// `2 P(2κ) − P(κ)`, which removes the `1/κ` term, matches the closed form to second order:
/// `10⁻⁸ + 20 |J − 1|²` (the constant term is the round-off floor `~50 ε κ/μ0`).
#[test]
fn traction_free_newton_matches_incompressible_closed_forms() {
    const RATIO: f64 = 1e6;
    for (name, law, nominal) in analytic_cases() {
        let stiff = Material::new(law.clone(), 2.0 * RATIO).unwrap();
        let material = Material::new(law, RATIO).unwrap();
        let mu0 = material.mu0();
        for mode in MODES {
            for l in STRETCHES {
                let want = nominal(mode, l);
                let scale = want.abs().max(mu0);
                let (got, j) = traction_free_state(&material, mode, l);
                let (got_stiff, _) = traction_free_state(&stiff, mode, l);
                let dj = (j - 1.0).abs();
                let pressure_bound = 3.0 * scale * l / material.kappa;
                assert!(
                    dj < pressure_bound,
                    "{name} {mode:?} λ = {l}: |J − 1| = {dj:e}"
                );
                let raw = (got - want).abs() / scale;
                assert!(
                    raw < 5.0 * dj + 1e-9,
                    "{name} {mode:?} λ = {l}: {got} vs {want} ({raw:e})"
                );
                let extrapolated = 2.0 * got_stiff - got;
                let err = (extrapolated - want).abs() / scale;
                let second_order = 1e-8 + 20.0 * dj * dj;
                assert!(
                    err < second_order,
                    "{name} {mode:?} λ = {l}: extrapolated {extrapolated} vs {want} ({err:e})"
                );
            }
        }
    }
}
