//! One finite-difference checker applied to every law, isochoric (through the trait) and
//! total, and to the print-anisotropy fibre term, alone and added to `ogden_002` and other laws
//! (along `z` and an oblique direction, `k` positive and negative): stress = ∂W/∂F and
//! tangent = ∂P/∂F by fourth-order central differences (step 10⁻⁴: truncation ~h⁴, round-off
//! ~ε/h, both far below the 10⁻⁶ tolerance); objectivity, and isotropy (transverse isotropy
//! about the fibre direction with a fibre).

use nalgebra::{Matrix3, Rotation3, Vector3};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use surrogate::fe::material::{
    Fibre, Hyperelastic, Material, MaterialLaw, MooneyRivlin5, NeoHookean, Ogden2, Tangent9,
};

/// Relative tolerance of the finite-difference checks.
const FD_TOL: f64 = 1e-6;
/// Finite-difference step on the entries of `F`.
const FD_STEP: f64 = 1e-4;
/// Bulk ratio `κ/μ0` of the total-model derivative checks (SPEC example).
const BULK_RATIO: f64 = 1000.0;

/// A hyperelastic response under test: energy, stress and tangent of `F`.
trait Response {
    fn energy(&self, f: &Matrix3<f64>) -> f64;
    fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64>;
    fn stress_tangent(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9);
    /// Stress scale below which errors are measured absolutely (`μ0`).
    fn scale(&self) -> f64;
}

/// The isochoric part of a law, through the [`Hyperelastic`] trait.
struct Iso<'a, H>(&'a H);

impl<H: Hyperelastic> Response for Iso<'_, H> {
    fn energy(&self, f: &Matrix3<f64>) -> f64 {
        self.0.iso_energy(f)
    }
    fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let mut p = Matrix3::zeros();
        self.0.iso_stress_into(f, &mut p);
        p
    }
    fn stress_tangent(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9) {
        let mut p = Matrix3::zeros();
        let mut a = Tangent9::zeros();
        self.0.iso_stress_tangent_into(f, &mut p, &mut a);
        (p, a)
    }
    fn scale(&self) -> f64 {
        self.0.initial_shear_modulus()
    }
}

/// The fibre term alone, through its adding `*_into` functions on zeroed buffers.
struct FibreTerm<'a>(&'a Fibre);

impl Response for FibreTerm<'_> {
    fn energy(&self, f: &Matrix3<f64>) -> f64 {
        self.0.energy(f)
    }
    fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let mut p = Matrix3::zeros();
        self.0.add_stress_into(f, &mut p);
        p
    }
    fn stress_tangent(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9) {
        let mut p = Matrix3::zeros();
        let mut a = Tangent9::zeros();
        self.0.add_stress_tangent_into(f, &mut p, &mut a);
        (p, a)
    }
    fn scale(&self) -> f64 {
        self.0.modulus().abs()
    }
}

/// The total model (isochoric + fibre + volumetric) of a [`Material`].
struct Total<'a>(&'a Material);

impl Response for Total<'_> {
    fn energy(&self, f: &Matrix3<f64>) -> f64 {
        self.0.energy(f)
    }
    fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        self.0.stress(f)
    }
    fn stress_tangent(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9) {
        self.0.stress_tangent(f)
    }
    fn scale(&self) -> f64 {
        self.0.mu0()
    }
}

/// `F` with entry `(i, j)` shifted by `h`.
fn perturbed(f: &Matrix3<f64>, i: usize, j: usize, h: f64) -> Matrix3<f64> {
    let mut g = *f;
    g[(i, j)] += h;
    g
}

/// Fourth-order central difference of `g` at 0 with step `h`.
fn central<T>(g: impl Fn(f64) -> T, h: f64) -> T
where
    T: std::ops::Sub<Output = T> + std::ops::Mul<f64, Output = T>,
{
    let near = g(h) - g(-h);
    let far = g(2.0 * h) - g(-2.0 * h);
    (near * 8.0 - far) * (1.0 / (12.0 * h))
}

/// `‖x − y‖ / max(‖y‖, scale)` (Frobenius norms).
fn rel_err<const R: usize, const C: usize>(
    x: &nalgebra::SMatrix<f64, R, C>,
    y: &nalgebra::SMatrix<f64, R, C>,
    scale: f64,
) -> f64 {
    (x - y).norm() / y.norm().max(scale)
}

/// Stress = ∂W/∂F and tangent = ∂P/∂F by finite differences at `f`; returns the worst error.
fn check_derivatives(label: &str, r: &impl Response, f: &Matrix3<f64>) -> f64 {
    let (p, a) = r.stress_tangent(f);
    let scale = r.scale();
    let p_alone = r.stress(f);
    let e_alone = rel_err(&p_alone, &p, scale);
    assert!(
        e_alone < 1e-13,
        "{label}: stress_into and stress_tangent_into differ by {e_alone:e}"
    );
    let p_fd = Matrix3::from_fn(|i, j| central(|h| r.energy(&perturbed(f, i, j, h)), FD_STEP));
    let mut a_fd = Tangent9::zeros();
    for k in 0..3 {
        for l in 0..3 {
            let column = central(|h| r.stress(&perturbed(f, k, l, h)), FD_STEP);
            for i in 0..3 {
                for j in 0..3 {
                    a_fd[(3 * i + j, 3 * k + l)] = column[(i, j)];
                }
            }
        }
    }
    let e_p = rel_err(&p, &p_fd, scale);
    let e_a = rel_err(&a, &a_fd, scale);
    assert!(
        e_p < FD_TOL,
        "{label}: stress vs dW/dF relative error {e_p:e} at F = {f}"
    );
    assert!(
        e_a < FD_TOL,
        "{label}: tangent vs dP/dF relative error {e_a:e} at F = {f}"
    );
    let sym = rel_err(&a, &a.transpose(), scale);
    assert!(
        sym < 1e-10,
        "{label}: tangent not major-symmetric ({sym:e}) at F = {f}"
    );
    e_p.max(e_a)
}

/// Deformation gradients of the derivative checks, with a label each.
fn check_points() -> Vec<(String, Matrix3<f64>)> {
    let q = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.5, 0.7)).into_inner();
    let s = 1.3_f64;
    let uniaxial = Matrix3::from_diagonal(&Vector3::new(s, 1.0 / s.sqrt(), 1.0 / s.sqrt()));
    let mut points = vec![
        ("identity".to_owned(), Matrix3::identity()),
        ("uniaxial".to_owned(), uniaxial),
        ("rotated uniaxial".to_owned(), q * uniaxial),
        (
            "equibiaxial".to_owned(),
            Matrix3::from_diagonal(&Vector3::new(1.2, 1.2, 1.0 / 1.44)),
        ),
        (
            "planar".to_owned(),
            Matrix3::from_diagonal(&Vector3::new(1.25, 1.0, 0.8)),
        ),
        (
            "compressed dilated".to_owned(),
            Matrix3::from_diagonal(&Vector3::new(0.8, 1.1, 1.1)),
        ),
        (
            "rotation*diag".to_owned(),
            q * Matrix3::from_diagonal(&Vector3::new(1.3, 0.9, 1.1)),
        ),
        // just inside and just outside the coalescence tolerance of the spectral tangent
        (
            "near-equal 1e-8".to_owned(),
            Matrix3::from_diagonal(&Vector3::new(1.2, 1.0, 1.0 + 1e-8)),
        ),
        (
            "near-equal 1e-5".to_owned(),
            Matrix3::from_diagonal(&Vector3::new(1.2, 1.0, 1.0 + 1e-5)),
        ),
    ];
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(20_240_611);
    while points.len() < 17 {
        let f = Matrix3::identity() + Matrix3::from_fn(|_, _| rng.gen_range(-0.25..0.25));
        if f.determinant() > 0.2 {
            points.push((format!("random #{}", points.len()), f));
        }
    }
    points
}

/// A random rotation.
fn random_rotation(rng: &mut impl Rng) -> Matrix3<f64> {
    let axis = Vector3::from_fn(|_, _| rng.gen_range(-1.0..1.0));
    Rotation3::from_scaled_axis(axis * 2.0).into_inner()
}

/// `A'_iJkL = Q_ia Q_kb A_aJbL`.
fn rotate_tangent(q: &Matrix3<f64>, a: &Tangent9) -> Tangent9 {
    Tangent9::from_fn(|r, c| {
        let (i, jj, k, l) = (r / 3, r % 3, c / 3, c % 3);
        let mut sum = 0.0;
        for m in 0..3 {
            for n in 0..3 {
                sum += q[(i, m)] * q[(k, n)] * a[(3 * m + jj, 3 * n + l)];
            }
        }
        sum
    })
}

/// The material symmetry group of a response.
#[derive(Clone, Copy)]
enum Symmetry {
    /// Every rotation.
    Isotropic,
    /// Rotations about a direction, and its reversal.
    Transverse(Vector3<f64>),
}

impl Symmetry {
    /// A random element of the group.
    fn random_element(self, rng: &mut impl Rng) -> Matrix3<f64> {
        match self {
            Symmetry::Isotropic => random_rotation(rng),
            Symmetry::Transverse(a0) => {
                let about = Rotation3::from_axis_angle(
                    &nalgebra::Unit::new_normalize(a0),
                    rng.gen_range(-3.0..3.0),
                );
                // a half turn about an axis normal to a0 maps a0 to −a0
                let normal = nalgebra::Unit::new_normalize(a0.cross(&Vector3::new(0.3, 0.9, 0.1)));
                let flip = Rotation3::from_axis_angle(&normal, std::f64::consts::PI);
                if rng.gen_bool(0.5) {
                    (about * flip).into_inner()
                } else {
                    about.into_inner()
                }
            }
        }
    }
}

/// Objectivity `W(QF) = W(F)`, `P(QF) = Q P(F)`, `A(QF) = Q·A(F)·Q`, and material symmetry
/// `W(FQ) = W(F)`, `P(FQ) = P(F) Q` for `Q` in the symmetry group.
fn check_objectivity(label: &str, r: &impl Response, symmetry: Symmetry) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    for (name, f) in check_points() {
        let q = random_rotation(&mut rng);
        let (w, (p, a)) = (r.energy(&f), r.stress_tangent(&f));
        let scale = r.scale();
        let (wq, (pq, aq)) = (r.energy(&(q * f)), r.stress_tangent(&(q * f)));
        assert!(
            (wq - w).abs() <= 1e-12 * scale,
            "{label} {name}: W(QF) = {wq} != W(F) = {w}"
        );
        let e_p = rel_err(&pq, &(q * p), scale);
        assert!(e_p < 1e-10, "{label} {name}: P(QF) != Q P(F) ({e_p:e})");
        let e_a = rel_err(&aq, &rotate_tangent(&q, &a), scale);
        assert!(e_a < 1e-10, "{label} {name}: A(QF) != Q A(F) Q ({e_a:e})");
        let q = symmetry.random_element(&mut rng);
        let w_iso = r.energy(&(f * q));
        assert!(
            (w_iso - w).abs() <= 1e-12 * scale,
            "{label} {name}: W(FQ) != W(F)"
        );
        let e_iso = rel_err(&r.stress(&(f * q)), &(p * q), scale);
        assert!(e_iso < 1e-10, "{label} {name}: P(FQ) != P(F) Q ({e_iso:e})");
    }
}

/// Derivative and objectivity tests for one law, isochoric (through the trait) and total.
macro_rules! law_tests {
    ($($name:ident: $law:expr;)+) => {$(
        mod $name {
            use super::*;

            #[test]
            fn iso_stress_and_tangent_match_finite_differences() {
                let law = $law.unwrap();
                let worst = check_points()
                    .iter()
                    .map(|(point, f)| check_derivatives(&format!("iso {point}"), &Iso(&law), f))
                    .fold(0.0, f64::max);
                println!("{}: worst iso FD error {worst:e}", stringify!($name));
            }

            #[test]
            fn total_stress_and_tangent_match_finite_differences() {
                let material = Material::new(MaterialLaw::from($law.unwrap()), BULK_RATIO).unwrap();
                let worst = check_points()
                    .iter()
                    .map(|(point, f)| check_derivatives(&format!("total {point}"), &Total(&material), f))
                    .fold(0.0, f64::max);
                println!("{}: worst total FD error {worst:e}", stringify!($name));
            }

            #[test]
            fn objective_and_isotropic() {
                let law = $law.unwrap();
                check_objectivity("iso", &Iso(&law), Symmetry::Isotropic);
                let material = Material::new(MaterialLaw::from(law), BULK_RATIO).unwrap();
                check_objectivity("total", &Total(&material), Symmetry::Isotropic);
            }
        }
    )+};
}

law_tests! {
    ogden_002: Ogden2::new(1.13, 3.11, -13.17, -0.6);
    ogden_005: Ogden2::new(0.13, 3.05, -1214.0, -0.0054);
    ogden_positive_exponents: Ogden2::new(0.6, 2.4, 0.02, 7.0);
    mooney_rivlin_5: MooneyRivlin5::new(-0.233, 2.562, 0.116, -0.561, 0.900);
    mooney_rivlin_two_term: MooneyRivlin5::new(0.4, 0.1, 0.0, 0.0, 0.0);
    neo_hookean: NeoHookean::new(2.5);
}

/// Derivative and symmetry tests of a fibre term `k = ratio · μ0` along `direction`, alone and
/// added to a law (total model).
macro_rules! fibre_tests {
    ($($name:ident: $law:expr, $direction:expr, $ratio:expr;)+) => {$(
        mod $name {
            use super::*;

            fn material() -> Material {
                let material = Material::new(MaterialLaw::from($law.unwrap()), BULK_RATIO).unwrap();
                let fibre = Fibre::new($direction, $ratio * material.mu0()).unwrap();
                material.with_fibre(fibre).unwrap()
            }

            #[test]
            fn fibre_stress_and_tangent_match_finite_differences() {
                let material = material();
                let fibre = material.fibre.as_ref().unwrap();
                let worst = check_points()
                    .iter()
                    .map(|(point, f)| check_derivatives(&format!("fibre {point}"), &FibreTerm(fibre), f))
                    .fold(0.0, f64::max);
                println!("{}: worst fibre FD error {worst:e}", stringify!($name));
            }

            #[test]
            fn total_stress_and_tangent_match_finite_differences() {
                let material = material();
                let worst = check_points()
                    .iter()
                    .map(|(point, f)| check_derivatives(&format!("total {point}"), &Total(&material), f))
                    .fold(0.0, f64::max);
                println!("{}: worst total FD error {worst:e}", stringify!($name));
            }

            #[test]
            fn objective_and_transversely_isotropic() {
                let material = material();
                let fibre = material.fibre.as_ref().unwrap();
                let symmetry = Symmetry::Transverse(*fibre.direction());
                check_objectivity("fibre", &FibreTerm(fibre), symmetry);
                check_objectivity("total", &Total(&material), symmetry);
            }
        }
    )+};
}

/// A generic oblique direction, not normalised.
const OBLIQUE: [f64; 3] = [0.3, -0.5, 0.8];

fibre_tests! {
    ogden_002_fibre_along_z_stiffer: Ogden2::new(1.13, 3.11, -13.17, -0.6), Fibre::ALONG_LENGTH, 1.0;
    ogden_002_fibre_along_z_softer: Ogden2::new(1.13, 3.11, -13.17, -0.6), Fibre::ALONG_LENGTH, -0.25;
    ogden_002_fibre_oblique_stiffer: Ogden2::new(1.13, 3.11, -13.17, -0.6), OBLIQUE, 4.0;
    ogden_002_fibre_oblique_softer: Ogden2::new(1.13, 3.11, -13.17, -0.6), OBLIQUE, -0.2;
    ogden_002_fibre_in_build_plane: Ogden2::new(1.13, 3.11, -13.17, -0.6), [0.0, 1.0, 1.0], 0.5;
    mooney_rivlin_5_fibre_oblique: MooneyRivlin5::new(-0.233, 2.562, 0.116, -0.561, 0.900), OBLIQUE, -0.25;
    neo_hookean_fibre_along_z: NeoHookean::new(2.5), Fibre::ALONG_LENGTH, 2.0;
}
