//! The blocked-force plate meets every outer face of the tip region (SPEC: the plate lies under
//! z ∈ [Lf − 25, Lf + 5], the whole width): the bottom layer that touches it first, and the end
//! cap and bellow flanks that reach it once the tip has turned past vertical. Faces on the
//! symmetry plane and faces outside the tip region are not in its search.

use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{ActuatorModel, ContactSettings, Mode, PLATE_REACH};

#[test]
fn plate_search_covers_the_outer_faces_of_the_tip_region() {
    let design = DesignParams::new(11, 2.0).validate().expect("valid design");
    let mat = Material::from_spec("ogden_002", 1000.0).expect("literature set");
    let model = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Force,
        &ContactSettings::default(),
    )
    .expect("model");
    let plate = model.plate.expect("force mode has a plate");
    let fe = &model.fe;
    let lf = design.free_length();
    let (w2, h) = (design.width() / 2.0, design.params().height);
    let mut faces = Vec::new();
    for (e, list) in fe.contact_faces.iter().enumerate() {
        for (plane, local) in list {
            if *plane == plate {
                faces.push(local.map(|l| fe.mesh.nodes[fe.mesh.elements[e][l]]));
            }
        }
    }
    let on = |f: &[[f64; 3]; 9], axis: usize, value: f64| {
        f.iter().all(|x| (x[axis] - value).abs() < 1e-9)
    };
    let count = |axis: usize, value: f64| faces.iter().filter(|f| on(f, axis, value)).count();
    // the tip region only, never the symmetry plane
    for f in &faces {
        assert!(f.iter().all(|x| x[2] >= lf - PLATE_REACH.0 - 1e-9), "{f:?}");
        assert!(!on(f, 0, w2), "symmetry-plane face {f:?}");
    }
    // bottom layer, end cap, bellow tops and the outer side wall are all searched
    assert!(count(1, 0.0) > 0, "bottom layer");
    assert!(count(2, lf) > 0, "end cap");
    assert!(count(1, h) > 0, "bellow tops");
    assert!(count(0, 0.0) > 0, "side wall");
    // bending mode has no plate
    let bending = ActuatorModel::new(
        &design,
        &mat,
        &MeshOptions::level(MeshLevel::Coarse),
        Mode::Bending,
        &ContactSettings::default(),
    )
    .expect("model");
    assert!(bending.plate.is_none());
}
