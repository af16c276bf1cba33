//! The unit tests of `src/fe/assembly/terms/mod.rs`.

// index loops mirror the CSC layout
#![allow(clippy::needless_range_loop)]

use surrogate::fe::assembly::model::FeModel;
use surrogate::fe::assembly::terms::term::{ElementContext, ElementTerm, LocalSystem};
use surrogate::fe::assembly::LoadLevel;
use surrogate::fe::element::{ElementError, DOFS};

/// A linear spring `k · u` on every node of every element (counted once per element it
/// belongs to): an added term in the simplest form.
struct Springs(f64);

impl ElementTerm<FeModel> for Springs {
    fn name(&self) -> &'static str {
        "test springs"
    }
    fn add(
        &self,
        _model: &FeModel,
        cx: &ElementContext<'_>,
        local: &mut LocalSystem,
    ) -> Result<(), ElementError> {
        for a in 0..27 {
            for i in 0..3 {
                let d = 3 * a + i;
                local.work.r[d] += self.0 * cx.ue[a][i];
                if cx.with_tangent {
                    local.work.k[d * DOFS + d] += self.0;
                }
                if cx.with_energy {
                    local.energy += 0.5 * self.0 * cx.ue[a][i] * cx.ue[a][i];
                }
            }
        }
        Ok(())
    }
}

fn block() -> FeModel {
    super::assembly_model::clamped_block(2)
}

/// The assembled lower-triangular tangent `k` of `model` at `u` times a direction
/// (`cos(w·d)` on the free dofs) matches central differences of the residual (h = 1e-6)
/// to 1e-5 of their largest entry.
fn assert_tangent_matches_differences(model: &FeModel, u: &[f64], k: &[f64], w: f64) {
    let n = u.len();
    let level = LoadLevel::default();
    let dir: Vec<f64> = (0..n)
        .map(|d| match model.dofs.eq(d) {
            Some(_) => ((d as f64) * w).cos(),
            None => 0.0,
        })
        .collect();
    let h = 1e-6;
    let res = |s: f64| {
        let v: Vec<f64> = u.iter().zip(&dir).map(|(a, b)| a + s * b).collect();
        let mut r = vec![0.0; n];
        model.assemble(&v, &level, &mut r, None).unwrap();
        r
    };
    let (rp, rm) = (res(h), res(-h));
    let nf = model.dofs.n_free;
    let (mut dfree, mut kd) = (vec![0.0; nf], vec![0.0; nf]);
    model.restrict(&dir, &mut dfree);
    for col in 0..nf {
        for p in model.pattern.col_ptr[col]..model.pattern.col_ptr[col + 1] {
            let row = model.pattern.row_idx[p];
            kd[row] += k[p] * dfree[col];
            if row != col {
                kd[col] += k[p] * dfree[row];
            }
        }
    }
    let fd: Vec<f64> = rp
        .iter()
        .zip(&rm)
        .map(|(a, b)| (a - b) / (2.0 * h))
        .collect();
    let mut fd_free = vec![0.0; nf];
    model.restrict(&fd, &mut fd_free);
    let scale = fd_free.iter().map(|v| v.abs()).fold(0.0, f64::max);
    for (a, b) in kd.iter().zip(&fd_free) {
        assert!((a - b).abs() <= 1e-5 * scale, "{a} vs {b}");
    }
}

/// An added term is assembled after the built-in ones: its residual, tangent and energy
/// add exactly to the model's, and the tangent of the sum matches finite differences.
#[test]
fn an_added_term_adds_its_residual_tangent_and_energy() {
    let plain = block();
    let mut sprung = block();
    let k = 0.37;
    sprung.add_element_term(Box::new(Springs(k)));
    assert_eq!(
        sprung.element_term_names(),
        ["volume", "pressure", "plane contact", "test springs"]
    );
    let n = 3 * plain.mesh.n_nodes();
    let u: Vec<f64> = (0..n)
        .map(|d| {
            let node = plain.mesh.nodes[d / 3];
            // zero on the clamped face
            1e-2 * node[2] * ((d as f64) * 0.7).sin()
        })
        .collect();
    let level = LoadLevel::default();
    let nnz = plain.pattern.nnz();
    let (mut r0, mut k0) = (vec![0.0; n], vec![0.0; nnz]);
    let (mut r1, mut k1) = (vec![0.0; n], vec![0.0; nnz]);
    let i0 = plain
        .assemble_with_energy(&u, &level, &mut r0, Some(&mut k0))
        .unwrap();
    let i1 = sprung
        .assemble_with_energy(&u, &level, &mut r1, Some(&mut k1))
        .unwrap();
    // element multiplicity of each node
    let mut count = vec![0.0; plain.mesh.n_nodes()];
    for conn in &plain.mesh.elements {
        for &a in conn {
            count[a] += 1.0;
        }
    }
    let mut spring_energy = 0.0;
    for d in 0..n {
        let want = r0[d] + k * count[d / 3] * u[d];
        assert!(
            (r1[d] - want).abs() <= 1e-12 * (1.0 + want.abs()),
            "dof {d}"
        );
        spring_energy += 0.5 * k * count[d / 3] * u[d] * u[d];
    }
    assert!((i1.energy - i0.energy - spring_energy).abs() <= 1e-12 * i0.energy.abs().max(1.0));
    // the tangent's diagonal gains k per element of the node
    for d in 0..n {
        if let Some(e) = plain.dofs.eq(d) {
            let p = plain.pattern.col_ptr[e];
            let want = k0[p] + k * count[d / 3];
            assert!((k1[p] - want).abs() <= 1e-12 * want.abs(), "dof {d}");
        }
    }
    // finite differences of the summed residual along a direction
    assert_tangent_matches_differences(&sprung, &u, &k1, 1.3);
}

/// A part's stiffness factor scales its elements' residual, tangent and energy exactly,
/// and a model with parts of different factors has a tangent that matches finite
/// differences of its residual.
#[test]
fn a_stiffness_factor_scales_the_volume_term_of_its_elements() {
    let plain = block();
    let mut stiff = block();
    stiff.set_stiffness(|_| 2.5);
    let n = 3 * plain.mesh.n_nodes();
    let u: Vec<f64> = (0..n)
        .map(|d| 2e-2 * plain.mesh.nodes[d / 3][2] * ((d as f64) * 0.9).sin())
        .collect();
    let level = LoadLevel::default();
    let nnz = plain.pattern.nnz();
    let (mut r0, mut k0) = (vec![0.0; n], vec![0.0; nnz]);
    let (mut r1, mut k1) = (vec![0.0; n], vec![0.0; nnz]);
    let i0 = plain
        .assemble_with_energy(&u, &level, &mut r0, Some(&mut k0))
        .unwrap();
    let i1 = stiff
        .assemble_with_energy(&u, &level, &mut r1, Some(&mut k1))
        .unwrap();
    for (a, b) in r1.iter().zip(&r0) {
        assert!((a - 2.5 * b).abs() <= 1e-12 * (1.0 + b.abs()));
    }
    for (a, b) in k1.iter().zip(&k0) {
        assert!((a - 2.5 * b).abs() <= 1e-12 * (1.0 + b.abs()));
    }
    assert!((i1.energy - 2.5 * i0.energy).abs() <= 1e-12 * i0.energy.abs());
    // two parts: the lower layer of elements 3 times stiffer; tangent against differences
    let mut parts = block();
    parts.set_stiffness(|c| if c[2] < 1.0 { 3.0 } else { 1.0 });
    assert!(parts.stiffness.contains(&3.0) && parts.stiffness.contains(&1.0));
    let mut k = vec![0.0; nnz];
    let mut r = vec![0.0; n];
    parts.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
    assert_tangent_matches_differences(&parts, &u, &k, 1.7);
}
