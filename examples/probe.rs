use surrogate::fe::assembly::LoadLevel;
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::Material;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::ActuatorModel;
use surrogate::fe::solver::{solve_path, SolverSettings};
fn main() {
    let design = DesignParams::new(11, 2.0).validate().unwrap();
    let mat = Material::from_spec("ogden_002", 100.0).unwrap();
    let model = ActuatorModel::new(&design, &mat, &MeshOptions::level(MeshLevel::Coarse)).unwrap();
    let fe = &model.fe;
    let n = 3 * fe.mesh.n_nodes();
    let levels: Vec<LoadLevel> = [0.02, 0.03, 0.04].iter().map(|&p| LoadLevel { pressure: p, ..Default::default() }).collect();
    let mut us = Vec::new();
    solve_path(fe, SolverSettings::default(), &levels, |_, st, _| us.push(st.u_full.clone())).unwrap();
    let eval = |u: &[f64], p: f64| {
        let mut r = vec![0.0; n];
        let info = fe.assemble(u, &LoadLevel { pressure: p, ..Default::default() }, &mut r, None).unwrap();
        let mut rf = vec![0.0; fe.dofs.n_free];
        fe.restrict(&r, &mut rf);
        (rf.iter().map(|x| x * x).sum::<f64>().sqrt(), info.external_norm)
    };
    println!("converged 0.02: {:?}", eval(&us[0], 0.02));
    println!("converged 0.03: {:?}", eval(&us[1], 0.03));
    println!("u(0.02) at 0.03: {:?}", eval(&us[0], 0.03));
    let pred: Vec<f64> = us[1].iter().zip(&us[0]).map(|(a, b)| 2.0 * a - b).collect();
    println!("secant pred at 0.04: {:?}", eval(&pred, 0.04));
    println!("converged 0.04: {:?}", eval(&us[2], 0.04));
    let d: f64 = pred.iter().zip(&us[2]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    println!("max |pred - sol| = {d}");
}
