//! The test helper of `src/fe/assembly/model.rs` (no tests of its own): the small model that
//! the unit tests of the assembly and the solver share.

use surrogate::fe::assembly::dofs::Constraint;
use surrogate::fe::assembly::model::FeModel;
use surrogate::fe::material::Material;

/// A block of `cells`³ unit Q2 hexahedra clamped at z = 0, Ogden 002, no load: the small model
/// that unit tests of the assembly and the solver share.
pub(crate) fn clamped_block(cells: usize) -> FeModel {
    use surrogate::fe::material::DEFAULT_BULK_RATIO;
    use surrogate::fe::mesh::{GridMesh, TensorGrid};
    let line = || (0..=cells).map(|i| i as f64).collect::<Vec<_>>();
    let mesh = GridMesh::new(
        TensorGrid {
            lines: [line(), line(), line()],
        },
        |_| true,
        |s| s,
    )
    .mesh;
    let constraints: Vec<_> = (0..mesh.n_nodes())
        .filter(|&n| mesh.nodes[n][2] == 0.0)
        .flat_map(|node| {
            (0..3).map(move |comp| Constraint {
                node,
                comp,
                value: 0.0,
            })
        })
        .collect();
    let material = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).expect("literature set");
    FeModel::new(mesh, material, &constraints, &[], &[]).expect("model")
}
