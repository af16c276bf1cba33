use surrogate::fe::assembly::LoadLevel;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::ActuatorModel;
use surrogate::fe::solver::LinearSolver;
fn main() {
    let design = DesignParams::new(11, 2.0).validate().unwrap();
    let mat = Material::from_spec("neo_hookean:5.7", 1000.0).unwrap();
    let model = ActuatorModel::new(&design, &mat, &MeshOptions::level(MeshLevel::Coarse)).unwrap();
    let fe = &model.fe;
    let n = 3 * fe.mesh.n_nodes();
    let nf = fe.dofs.n_free;
    let level = LoadLevel {
        pressure: 0.002,
        ..Default::default()
    };
    let u = vec![0.0; n];
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; fe.pattern.nnz()];
    fe.assemble(&u, &level, &mut r, Some(&mut k)).unwrap();
    let mut rf = vec![0.0; nf];
    fe.restrict(&r, &mut rf);
    let mut du: Vec<f64> = rf.iter().map(|v| -v).collect();
    let mut ls = LinearSolver::new(fe).unwrap();
    ls.solve(&k, &mut du).unwrap();
    let mut full = vec![0.0; n];
    fe.expand(&du, &level, &mut full);
    let (imax, vmax) =
        full.iter().enumerate().fold(
            (0, 0.0f64),
            |(i, m), (j, v)| if v.abs() > m { (j, v.abs()) } else { (i, m) },
        );
    println!(
        "max |du| = {vmax} at node {} comp {} x = {:?}",
        imax / 3,
        imax % 3,
        fe.mesh.nodes[imax / 3]
    );
    // residual along the line
    for a in [0.25, 0.5, 1.0] {
        let uu: Vec<f64> = full.iter().map(|v| a * v).collect();
        let mut rr = vec![0.0; n];
        fe.assemble(&uu, &level, &mut rr, None).unwrap();
        let mut rrf = vec![0.0; nf];
        fe.restrict(&rr, &mut rrf);
        let nr = rrf.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (i2, v2) = rrf.iter().enumerate().fold((0, 0.0f64), |(i, m), (j, v)| {
            if v.abs() > m {
                (j, v.abs())
            } else {
                (i, m)
            }
        });
        let d = fe.dofs.free.iter().position(|&f| f as usize == i2).unwrap();
        println!(
            "alpha {a}: |r| = {nr:e}, max {v2:e} at node {} comp {} x = {:?}",
            d / 3,
            d % 3,
            fe.mesh.nodes[d / 3]
        );
    }
    let tip = model.marker_displacement(8, &full);
    println!("tip du = {tip:?}");
}
