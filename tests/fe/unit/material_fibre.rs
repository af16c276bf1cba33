//! The unit tests of `src/fe/material/fibre/mod.rs`.
//!
//! Unit tests of the fibre term and of [`Material`] with and without it. The finite-difference
//! checks of its stress and tangent are in the generic checker, `tests/fe/materials/derivatives.rs`.

use nalgebra::{Matrix3, Rotation3, SMatrix, SVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::Serialize;

use surrogate::fe::material::fibre::*;
use surrogate::fe::material::{jacobian_and_inverse_transpose, MaterialError, Tangent9};
use surrogate::fe::material::{literature_sets, Material, MaterialLaw, NeoHookean};

/// A generic direction, deliberately not normalised.
const OBLIQUE: [f64; 3] = [0.3, -0.5, 0.8];

fn ogden_002() -> MaterialLaw {
    literature_sets()
        .unwrap()
        .into_iter()
        .find(|(name, _)| name == "ogden_002")
        .unwrap()
        .1
}

/// `ogden_002` with `κ = bulk_ratio μ0` and a fibre `k = ratio μ0` along `direction`.
fn ogden_with_fibre(direction: [f64; 3], ratio: f64, bulk_ratio: f64) -> Material {
    let m = Material::new(ogden_002(), bulk_ratio).unwrap();
    let k = ratio * m.mu0();
    m.with_fibre(Fibre::new(direction, k).unwrap()).unwrap()
}

/// Random deformation gradients with `det F > 0.2` (seeded).
fn random_gradients(seed: u64, count: usize) -> Vec<Matrix3<f64>> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let f = Matrix3::identity() + Matrix3::from_fn(|_, _| rng.gen_range(-0.3..0.3));
        if f.determinant() > 0.2 {
            out.push(f);
        }
    }
    out
}

fn random_rotation(rng: &mut impl Rng) -> Matrix3<f64> {
    let axis = Vector3::from_fn(|_, _| rng.gen_range(-1.0..1.0));
    Rotation3::from_scaled_axis(axis * 2.0).into_inner()
}

fn fibre_stress_tangent(fibre: &Fibre, f: &Matrix3<f64>) -> (Matrix3<f64>, Tangent9) {
    let (mut p, mut a) = (Matrix3::zeros(), Tangent9::zeros());
    fibre.add_stress_tangent_into(f, &mut p, &mut a);
    (p, a)
}

#[test]
fn direction_is_normalised_and_kept_as_given() {
    let fibre = Fibre::new([0.0, 3.0, 4.0], 2.0).unwrap();
    assert!((fibre.direction() - Vector3::new(0.0, 0.6, 0.8)).norm() < 1e-15);
    assert_eq!(fibre.params().direction, [0.0, 3.0, 4.0]);
    assert_eq!(fibre.modulus(), 2.0);
    for tiny_or_huge in [
        [1e-300, 0.0, 0.0],
        [1e300, 1e300, 0.0],
        [5e-324, 0.0, -5e-324],
    ] {
        let a0 = *Fibre::new(tiny_or_huge, 1.0).unwrap().direction();
        assert!((a0.norm() - 1.0).abs() < 1e-15, "{tiny_or_huge:?}: {a0}");
    }
    assert_eq!(
        Fibre::new(Fibre::ALONG_LENGTH, 1.0).unwrap().direction(),
        &Vector3::z()
    );
}

#[test]
fn vanishes_in_the_reference_state_and_under_rotations() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    for direction in [Fibre::ALONG_LENGTH, OBLIQUE] {
        for k in [5.7, -1.4] {
            let fibre = Fibre::new(direction, k).unwrap();
            let material = ogden_with_fibre(direction, k / 5.708, 1000.0);
            let rotations: Vec<_> = std::iter::once(Matrix3::identity())
                .chain((0..10).map(|_| random_rotation(&mut rng)))
                .collect();
            for q in rotations {
                let w = fibre.energy(&q);
                let (p, a) = fibre_stress_tangent(&fibre, &q);
                assert!(w.abs() <= 1e-28 * k.abs(), "W_f = {w} at {q}");
                assert!(p.norm() <= 1e-13 * k.abs(), "P_f = {p} at {q}");
                assert!(a.iter().all(|x| x.is_finite()));
                let total = material.stress(&q);
                assert!(total.norm() <= 1e-11 * material.mu0(), "P = {total}");
                assert!(material.energy(&q).abs() <= 1e-24 * material.mu0());
            }
        }
    }
}

#[test]
fn cauchy_stress_is_deviatoric_at_every_deformation() {
    let fibre = Fibre::new(OBLIQUE, 3.0).unwrap();
    for f in random_gradients(11, 30) {
        let mut p = Matrix3::zeros();
        fibre.add_stress_into(&f, &mut p);
        let trace = (p * f.transpose()).trace();
        assert!(
            trace.abs() <= 1e-13 * p.norm() * f.norm(),
            "tr(P Fᵀ) = {trace} at {f}"
        );
    }
}

#[test]
fn adds_into_the_callers_buffers() {
    let fibre = Fibre::new(OBLIQUE, -1.2).unwrap();
    let f = random_gradients(5, 1)[0];
    let (p_f, a_f) = fibre_stress_tangent(&fibre, &f);
    let p0 = Matrix3::from_fn(|i, j| (i + 3 * j) as f64);
    let a0 = Tangent9::from_fn(|i, j| (i as f64) - (j as f64));
    let (mut p, mut a) = (p0, a0);
    fibre.add_stress_tangent_into(&f, &mut p, &mut a);
    assert!((p - (p0 + p_f)).norm() < 1e-14 * p.norm());
    assert!((a - (a0 + a_f)).norm() < 1e-14 * a.norm());
    let mut p = p0;
    fibre.add_stress_into(&f, &mut p);
    assert!((p - (p0 + p_f)).norm() < 1e-14 * p.norm());
}

#[test]
fn inverted_deformations_give_infinite_energy_and_nan_stress() {
    let fibre = Fibre::new(Fibre::ALONG_LENGTH, 2.0).unwrap();
    let material = ogden_with_fibre(Fibre::ALONG_LENGTH, 0.5, 1000.0);
    let inverted = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -0.5));
    for f in [inverted, Matrix3::zeros(), Matrix3::from_element(f64::NAN)] {
        assert_eq!(fibre.energy(&f), f64::INFINITY);
        assert_eq!(fibre.pseudo_invariant(&f), None);
        let (mut p, mut a) = (Matrix3::zeros(), Tangent9::zeros());
        fibre.add_stress_tangent_into(&f, &mut p, &mut a);
        assert!(p.iter().chain(a.iter()).all(|x| x.is_nan()));
        let mut p = Matrix3::zeros();
        fibre.add_stress_into(&f, &mut p);
        assert!(p.iter().all(|x| x.is_nan()));
        assert_eq!(material.iso_energy(&f), f64::INFINITY);
        let (p, a) = material.stress_tangent(&f);
        assert!(p.iter().chain(a.iter()).all(|x| x.is_nan()));
    }
}

/// The Mandel basis of symmetric tensors.
fn mandel_basis() -> [Matrix3<f64>; 6] {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let pair = |i: usize, j: usize| {
        Matrix3::from_fn(|r, c| {
            if (r, c) == (i, j) || (r, c) == (j, i) {
                s
            } else {
                0.0
            }
        })
    };
    [
        Matrix3::from_diagonal(&Vector3::x()),
        Matrix3::from_diagonal(&Vector3::y()),
        Matrix3::from_diagonal(&Vector3::z()),
        pair(1, 2),
        pair(0, 2),
        pair(0, 1),
    ]
}

/// `X : A : Y` of a 9×9 tangent.
fn contract(x: &Matrix3<f64>, a: &Tangent9, y: &Matrix3<f64>) -> f64 {
    let xv = SVector::<f64, 9>::from_fn(|r, _| x[(r / 3, r % 3)]);
    let yv = SVector::<f64, 9>::from_fn(|r, _| y[(r / 3, r % 3)]);
    (xv.transpose() * a * yv)[0]
}

/// Small-strain Young's modulus along `n` of a stress-free tangent `a` (uniaxial stress).
fn uniaxial_modulus(a: &Tangent9, n: &Vector3<f64>) -> f64 {
    let basis = mandel_basis();
    let stiffness = SMatrix::<f64, 6, 6>::from_fn(|p, q| contract(&basis[p], a, &basis[q]));
    let compliance = stiffness.try_inverse().unwrap();
    let nn = n * n.transpose();
    let v = SVector::<f64, 6>::from_fn(|p, _| basis[p].component_mul(&nn).sum());
    1.0 / (v.transpose() * compliance * v)[0]
}

#[test]
fn small_strain_tangent_is_4k_dev_a0_outer_dev_a0() {
    for (direction, k) in [(Fibre::ALONG_LENGTH, 2.5), (OBLIQUE, -0.9)] {
        let fibre = Fibre::new(direction, k).unwrap();
        let a0 = fibre.direction();
        let d = a0 * a0.transpose() - Matrix3::identity() / 3.0;
        let want = Tangent9::from_fn(|r, c| 4.0 * k * d[(r / 3, r % 3)] * d[(c / 3, c % 3)]);
        let (_, a) = fibre_stress_tangent(&fibre, &Matrix3::identity());
        assert!((a - want).norm() < 1e-14 * k.abs(), "{direction:?}");
        // a pure volume change is unresisted, and so is any shear along or across a0
        let b = a0.cross(&Vector3::new(0.1, 0.7, -0.2)).normalize();
        let c = a0.cross(&b);
        let shears = [
            a0 * b.transpose() + b * a0.transpose(),
            b * c.transpose() + c * b.transpose(),
            b * b.transpose() - c * c.transpose(),
        ];
        for x in std::iter::once(Matrix3::identity()).chain(shears) {
            assert!(contract(&x, &a, &x).abs() < 1e-14 * k.abs());
        }
    }
}

#[test]
fn uniaxial_small_strain_moduli_follow_the_documented_formulas() {
    for ratio in [-0.25, -0.1, 0.5, 1.0, 4.0] {
        for bulk_ratio in [1000.0, 1e7] {
            let m = ogden_with_fibre(OBLIQUE, ratio, bulk_ratio);
            let (mu0, kappa, k) = (m.mu0(), m.kappa, ratio * m.mu0());
            let (_, a) = m.stress_tangent(&Matrix3::identity());
            let a0 = *m.fibre.as_ref().unwrap().direction();
            let e_along = uniaxial_modulus(&a, &a0);
            let mu_eff = mu0 + 4.0 * k / 3.0;
            let want = 9.0 * kappa * mu_eff / (3.0 * kappa + mu_eff);
            assert!((e_along - want).abs() < 1e-8 * want, "{e_along} vs {want}");
            let across = a0.cross(&Vector3::x()).normalize();
            let e_across = uniaxial_modulus(&a, &across);
            if bulk_ratio > 1e6 {
                let (e_a, e_t) = (3.0 * mu0 + 4.0 * k, mu0 * (3.0 * mu0 + 4.0 * k) / (mu0 + k));
                assert!(
                    (e_along - e_a).abs() < 1e-6 * e_a,
                    "{e_along} vs 3μ0 + 4k = {e_a}"
                );
                assert!((e_across - e_t).abs() < 1e-6 * e_t, "{e_across} vs {e_t}");
            }
            assert_eq!(
                e_along > e_across,
                k > 0.0,
                "k = {k}: {e_along} vs {e_across}"
            );
        }
    }
}

/// Incompressible uniaxial nominal stress (MPa) along axis `axis` at stretch `l`, from the
/// isochoric stress at `J = 1` (the pressure eliminated by the traction-free lateral faces,
/// their stretches solved by bisection).
fn uniaxial_nominal(m: &Material, axis: usize, l: f64) -> f64 {
    let (p_dir, q_dir) = ((axis + 1) % 3, (axis + 2) % 3);
    let cauchy = |s: f64| {
        let mut d = Vector3::zeros();
        d[axis] = l;
        d[p_dir] = s;
        d[q_dir] = 1.0 / (l * s);
        let f = Matrix3::from_diagonal(&d);
        let mut p = Matrix3::zeros();
        m.iso_stress_into(&f, &mut p);
        p * f.transpose()
    };
    let lateral = |s: f64| {
        let sigma = cauchy(s);
        sigma[(p_dir, p_dir)] - sigma[(q_dir, q_dir)]
    };
    let (mut lo, mut hi) = (0.2 / l.sqrt(), 5.0 / l.sqrt());
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if lateral(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let sigma = cauchy(0.5 * (lo + hi));
    (sigma[(axis, axis)] - sigma[(p_dir, p_dir)]) / l
}

#[test]
fn uniaxial_stretch_along_the_fibre_is_stiffer_than_across_for_positive_k() {
    let isotropic = Material::new(ogden_002(), 1000.0).unwrap();
    for ratio in [0.5, 2.0, -0.25] {
        let m = ogden_with_fibre([1.0, 0.0, 0.0], ratio, 1000.0);
        let k = ratio * m.mu0();
        for l in [0.8, 1.1, 1.2, 1.5, 2.0] {
            let (along, across) = (uniaxial_nominal(&m, 0, l), uniaxial_nominal(&m, 1, l));
            let iso = uniaxial_nominal(&isotropic, 0, l);
            // incompressible closed form of the fibre's share: d/dλ (k/2)(λ² − 1)²
            let fibre_share = 2.0 * k * l * (l * l - 1.0);
            assert!(
                (along - iso - fibre_share).abs() < 1e-9 * (iso.abs() + fibre_share.abs()),
                "λ = {l}: {along} − {iso} vs {fibre_share}"
            );
            if l > 1.0 && k > 0.0 {
                assert!(
                    along > across && across > iso,
                    "λ = {l}: {along}, {across}, {iso}"
                );
            }
            if l > 1.0 && k < 0.0 {
                assert!(
                    along < across && across < iso,
                    "λ = {l}: {along}, {across}, {iso}"
                );
            }
        }
    }
}

/// First stretch in `(1, 3]` at which the nominal stress along the fibre stops growing.
fn tension_limit_point(m: &Material) -> Option<f64> {
    let step = 1e-3;
    let mut previous = uniaxial_nominal(m, 0, 1.0);
    (1..=2000).map(|n| 1.0 + n as f64 * step).find(|&l| {
        let p = uniaxial_nominal(m, 0, l);
        let stalled = p <= previous;
        previous = p;
        stalled
    })
}

#[test]
fn negative_modulus_has_the_documented_tension_limit_point() {
    let at = |ratio| tension_limit_point(&ogden_with_fibre([1.0, 0.0, 0.0], ratio, 1000.0));
    assert_eq!(at(0.0), None);
    let quarter = at(-0.25).unwrap();
    assert!((1.22..1.24).contains(&quarter), "{quarter}");
    let tenth = at(-0.1).unwrap();
    assert!((1.53..1.55).contains(&tenth), "{tenth}");
}

#[test]
fn without_fibre_the_material_is_bit_identical_to_its_law() {
    let bits = |m: &Matrix3<f64>| m.map(f64::to_bits);
    for (name, law) in literature_sets().unwrap() {
        let plain = Material::new(law.clone(), 1000.0).unwrap();
        assert_eq!(plain.fibre, None);
        let mut dropped = ogden_with_fibre(OBLIQUE, 1.0, 1000.0);
        dropped.law = law.clone();
        dropped.kappa = plain.kappa;
        dropped.fibre = None;
        for f in random_gradients(17, 10) {
            let (j, g) = jacobian_and_inverse_transpose(&f).unwrap();
            let w = law.iso_energy(&f);
            assert_eq!(plain.iso_energy(&f).to_bits(), w.to_bits(), "{name}");
            let total = w + plain.vol_energy(f.determinant());
            assert_eq!(plain.energy(&f).to_bits(), total.to_bits(), "{name}");
            let (mut p_law, mut a_law) = (Matrix3::zeros(), Tangent9::zeros());
            law.iso_stress_tangent_into(&f, &mut p_law, &mut a_law);
            let (mut p, mut a) = (Matrix3::zeros(), Tangent9::zeros());
            plain.iso_stress_tangent_into(&f, &mut p, &mut a);
            assert_eq!(bits(&p), bits(&p_law), "{name}");
            assert_eq!(a.map(f64::to_bits), a_law.map(f64::to_bits), "{name}");
            plain.iso_stress_into(&f, &mut p);
            law.iso_stress_into(&f, &mut p_law);
            assert_eq!(bits(&p), bits(&p_law), "{name}");
            let p_total = p_law + g * (plain.vol_pressure(j) * j);
            assert_eq!(bits(&plain.stress(&f)), bits(&p_total), "{name}");
            let (p_d, a_d) = dropped.stress_tangent(&f);
            let (p_p, a_p) = plain.stress_tangent(&f);
            assert_eq!(bits(&p_d), bits(&p_p), "{name}");
            assert_eq!(a_d.map(f64::to_bits), a_p.map(f64::to_bits), "{name}");
        }
    }
}

/// The `field` of an [`MaterialError::Inadmissible`], checking that the message names the
/// field, the value and the expectation.
fn inadmissible_field<T: std::fmt::Debug>(result: Result<T, MaterialError>) -> String {
    match result {
        Err(e @ MaterialError::Inadmissible { .. }) => {
            let message = e.to_string();
            let MaterialError::Inadmissible { field, value, .. } = e else {
                unreachable!()
            };
            assert!(message.contains(&field), "{message}");
            assert!(message.contains(&value.to_string()), "{message}");
            assert!(message.contains("expected"), "{message}");
            field
        }
        other => panic!("expected an Inadmissible error, got {other:?}"),
    }
}

#[test]
fn inadmissible_fibres_are_errors_naming_the_field() {
    for k in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            inadmissible_field(Fibre::new([0.0, 0.0, 1.0], k)),
            "fibre.modulus"
        );
    }
    for direction in [
        [0.0, 0.0, 0.0],
        [0.0, -0.0, 0.0],
        [f64::NAN, 0.0, 1.0],
        [0.0, f64::INFINITY, 1.0],
    ] {
        assert_eq!(
            inadmissible_field(Fibre::new(direction, 1.0)),
            "fibre.direction"
        );
    }
    let m = Material::new(ogden_002(), 1000.0).unwrap();
    let mu0 = m.mu0();
    let (lo, hi) = Fibre::admissible_modulus(mu0);
    assert_eq!((lo, hi), (-0.25 * mu0, 4.0 * mu0));
    for k in [lo, 0.0, hi] {
        let fibre = Fibre::new(OBLIQUE, k).unwrap();
        assert_eq!(
            m.clone().with_fibre(fibre.clone()).unwrap().fibre,
            Some(fibre)
        );
    }
    for k in [-0.26 * mu0, -0.75 * mu0, 4.01 * mu0, 1e6] {
        let fibre = Fibre::new(OBLIQUE, k).unwrap();
        assert_eq!(
            inadmissible_field(m.clone().with_fibre(fibre)),
            "fibre.modulus"
        );
    }
    let nh = Material::new(NeoHookean::new(2.0).unwrap().into(), 10.0).unwrap();
    let too_soft = Fibre::new(OBLIQUE, -0.6).unwrap();
    assert_eq!(inadmissible_field(nh.with_fibre(too_soft)), "fibre.modulus");
}

/// The serialised form of a material before the fibre field existed.
#[derive(Serialize)]
struct MaterialBefore<'a> {
    law: &'a MaterialLaw,
    kappa: f64,
}

#[test]
fn serde_round_trips_with_and_without_fibre() {
    for (_, law) in literature_sets().unwrap() {
        let plain = Material::new(law, 1000.0).unwrap();
        let json = serde_json::to_string(&plain).unwrap();
        let before = MaterialBefore {
            law: &plain.law,
            kappa: plain.kappa,
        };
        assert_eq!(json, serde_json::to_string(&before).unwrap());
        assert!(!json.contains("fibre"), "{json}");
        let back: Material = serde_json::from_str(&json).unwrap();
        assert_eq!(back, plain);
        let with = ogden_with_fibre(OBLIQUE, -0.2, 1000.0);
        let json = serde_json::to_string(&with).unwrap();
        assert!(
            json.contains(r#""fibre":{"direction":[0.3,-0.5,0.8],"modulus":"#),
            "{json}"
        );
        let back: Material = serde_json::from_str(&json).unwrap();
        assert_eq!(back, with);
        assert_eq!(serde_json::to_string(&back).unwrap(), json);
    }
    let nh = Material::from_spec("neo_hookean:2.5", 10.0).unwrap();
    let legacy = r#"{"law":{"NeoHookean":{"mu":2.5}},"kappa":25.0}"#;
    assert_eq!(serde_json::to_string(&nh).unwrap(), legacy);
    assert_eq!(serde_json::from_str::<Material>(legacy).unwrap(), nh);
    let null = r#"{"law":{"NeoHookean":{"mu":2.5}},"kappa":25.0,"fibre":null}"#;
    assert_eq!(serde_json::from_str::<Material>(null).unwrap(), nh);
}

#[test]
fn deserialisation_validates_the_fibre() {
    let with = |fibre: &str| {
        let json =
            format!(r#"{{"law":{{"NeoHookean":{{"mu":2.0}}}},"kappa":20.0,"fibre":{fibre}}}"#);
        serde_json::from_str::<Material>(&json).map_err(|e| e.to_string())
    };
    let ok = with(r#"{"direction":[0,0,2],"modulus":8.0}"#).unwrap();
    let fibre = ok.fibre.as_ref().unwrap();
    assert_eq!(fibre.direction(), &Vector3::z());
    assert_eq!(fibre.params().direction, [0.0, 0.0, 2.0]);
    for (fibre, field) in [
        (r#"{"direction":[0,0,1],"modulus":8.5}"#, "fibre.modulus"),
        (r#"{"direction":[0,0,1],"modulus":-0.6}"#, "fibre.modulus"),
        (r#"{"direction":[0,0,0],"modulus":1.0}"#, "fibre.direction"),
    ] {
        let err = with(fibre).unwrap_err();
        assert!(err.contains(field), "{fibre}: {err}");
    }
}
