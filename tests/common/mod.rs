//! Verification cases of the FE solver against analytic and reference solutions.
//!
//! Shared by the `verification_*` modules of the FE tests (`tests/fe/`, which assert the
//! tolerances at one refinement) and by `benches/verification.rs` (which runs every refinement
//! level and writes `fe_reference/verification.json`). Each case module builds its mesh,
//! solves, measures and returns [`Check`]s: a computed value, its reference, the error and,
//! where it is asserted, the tolerance.
#![allow(dead_code)] // the FE tests and the bench each use only some of the helpers

pub mod cantilever;
pub mod cook;
pub mod cylinder;
pub mod homogeneous;
pub mod patch;

use serde::Serialize;
use surrogate::fe::assembly::{Constraint, FeModel, LoadLevel};
use surrogate::fe::mesh::{GridMesh, TensorGrid};
use surrogate::fe::solver::{solve_path, SolverSettings};

/// One verified quantity.
#[derive(Clone, Debug, Serialize)]
pub struct Check {
    /// Verification case (e.g. `cook_membrane`).
    pub case: String,
    /// Mesh or load description (e.g. `16x16`).
    pub refinement: String,
    /// What is compared.
    pub quantity: String,
    /// FE value.
    pub computed: f64,
    /// Analytic or reference value.
    pub reference: f64,
    /// `|computed − reference| / scale` (scale = |reference| unless stated in `quantity`).
    pub relative_error: f64,
    /// Asserted bound on `relative_error` (None: reported for the convergence study only).
    pub tolerance: Option<f64>,
}

impl Check {
    /// A check with error relative to `|reference|`.
    pub fn relative(
        case: &str,
        refinement: &str,
        quantity: &str,
        computed: f64,
        reference: f64,
    ) -> Self {
        Self::scaled(
            case,
            refinement,
            quantity,
            computed,
            reference,
            reference.abs(),
        )
    }

    /// A check with error `|computed − reference| / scale`.
    pub fn scaled(
        case: &str,
        refinement: &str,
        quantity: &str,
        computed: f64,
        reference: f64,
        scale: f64,
    ) -> Self {
        Self {
            case: case.to_owned(),
            refinement: refinement.to_owned(),
            quantity: quantity.to_owned(),
            computed,
            reference,
            relative_error: (computed - reference).abs() / scale,
            tolerance: None,
        }
    }

    /// The same check, asserted at `tol`.
    pub fn with_tolerance(mut self, tol: f64) -> Self {
        self.tolerance = Some(tol);
        self
    }

    /// Whether the check holds (always true when no tolerance is asserted).
    pub fn passes(&self) -> bool {
        self.tolerance
            .is_none_or(|t| self.relative_error.is_finite() && self.relative_error <= t)
    }

    /// One table row.
    pub fn row(&self) -> String {
        let tol = self
            .tolerance
            .map_or("-".to_owned(), |t| format!("{t:.0e}"));
        let mark = match (self.tolerance, self.passes()) {
            (None, _) => "",
            (Some(_), true) => "ok",
            (Some(_), false) => "FAIL",
        };
        format!(
            "{:<30} {:<12} {:<42} {:>14.7e} {:>14.7e} {:>10.2e} {:>6} {}",
            self.case,
            self.refinement,
            self.quantity,
            self.computed,
            self.reference,
            self.relative_error,
            tol,
            mark
        )
    }
}

/// Prints the checks and asserts every tolerance.
pub fn assert_checks(checks: &[Check]) {
    for c in checks {
        println!("{}", c.row());
    }
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.passes())
        .map(Check::row)
        .collect();
    assert!(
        failed.is_empty(),
        "verification failed:\n{}",
        failed.join("\n")
    );
    assert!(
        checks.iter().any(|c| c.tolerance.is_some()),
        "no asserted check"
    );
}

/// Constraints `u[node][comp] = value` for every node and component given.
pub fn fix(nodes: &[usize], comps: &[usize], value: f64) -> Vec<Constraint> {
    nodes
        .iter()
        .flat_map(|&node| {
            comps
                .iter()
                .map(move |&comp| Constraint { node, comp, value })
        })
        .collect()
}

/// `n + 1` evenly spaced grid lines from `a` to `b`.
pub fn uniform(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect()
}

/// A solid block meshed on the grid `lines` (parameter space; map the nodes afterwards).
pub fn block(lines: [Vec<f64>; 3]) -> GridMesh<bool> {
    GridMesh::new(TensorGrid { lines }, |_| true, |s| s)
}

/// Plane strain in the x–y plane: one element layer `z ∈ [0, 1]` over the grid `(xs, ys)`,
/// with the constraints `u_z = 0` on every node.
pub fn plane_strain_layer(xs: Vec<f64>, ys: Vec<f64>) -> (GridMesh<bool>, Vec<Constraint>) {
    let gm = block([xs, ys, vec![0.0, 1.0]]);
    let all: Vec<usize> = (0..gm.mesh.n_nodes()).collect();
    let cons = fix(&all, &[2], 0.0);
    (gm, cons)
}

/// Node ids on the intersection of parameter planes `(axis, value)`.
pub fn nodes_on<K: Copy + PartialEq>(gm: &GridMesh<K>, planes: &[(usize, f64)]) -> Vec<usize> {
    let mut nodes = gm.nodes_on_plane(planes[0].0, planes[0].1);
    for &(axis, value) in &planes[1..] {
        let on = gm.nodes_on_plane(axis, value);
        nodes.retain(|n| on.contains(n));
    }
    nodes
}

/// The unique node at parameter point `p`.
pub fn node_at<K: Copy + PartialEq>(gm: &GridMesh<K>, p: [f64; 3]) -> usize {
    let nodes = nodes_on(gm, &[(0, p[0]), (1, p[1]), (2, p[2])]);
    assert_eq!(nodes.len(), 1, "no unique node at {p:?}");
    nodes[0]
}

/// Solves the load path and returns the full displacement vector after every output level.
///
/// Panics (naming `case`) if the solver does not converge: a verification case must solve.
pub fn solve(
    case: &str,
    model: &FeModel,
    settings: SolverSettings,
    levels: &[LoadLevel],
) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(levels.len());
    solve_path(model, settings, levels, |_, state, _| {
        out.push(state.u_full.clone())
    })
    .unwrap_or_else(|e| panic!("{case}: solver failed: {e}"));
    out
}

/// Residual over all dofs at `u`: at constrained dofs, the reaction forces on the body.
pub fn residual(model: &FeModel, u: &[f64], level: &LoadLevel) -> Vec<f64> {
    let mut r = vec![0.0; u.len()];
    model
        .assemble(u, level, &mut r, None)
        .expect("converged state is admissible");
    r
}

/// Evenly spaced load levels `k/n · full` for k = 1..=n.
pub fn ramp(full: LoadLevel, n: usize) -> Vec<LoadLevel> {
    (1..=n)
        .map(|k| LoadLevel::default().lerp(&full, k as f64 / n as f64))
        .collect()
}
