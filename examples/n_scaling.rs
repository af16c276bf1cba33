//! How the model's bending scales with the number of bellows N, under a geometry preset and an
//! optional print anisotropy along y (the direction the filament runs in the walls facing the
//! gaps).
//!
//! The recorded actuators bend most at N = 11 at every T and pressure; the model's bending
//! rises with N. This runs the coarse bending ramps (0, 1, 2, 3 bar) of N = 9, 11, 13 at the
//! given wall thicknesses and prints the angles and the ratios to N = 11, the quantity a
//! mechanism must move to explain the recordings (`fe_reference/identification/n_scaling/`).
//!
//! ```sh
//! RAYON_NUM_THREADS=1 cargo run --release --example n_scaling -- \
//!     GEOMETRY.json MU1,ALPHA1,MU2,ALPHA2 T[,T…] [FIBRE_Y_K_OVER_MU0]
//! ```
//! About 40 s per ramp on one core (three per T).

use surrogate::fe::effects::Effects;
use surrogate::fe::material::{Fibre, Material, MaterialLaw, Ogden2, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::preset::Geometry;
use surrogate::fe::simulate::{run, Case, ContactSettings, Mode};
use surrogate::fe::solver::SolverSettings;

type Error = Box<dyn std::error::Error>;

fn numbers(field: &str, text: &str) -> Result<Vec<f64>, Error> {
    text.split(',')
        .map(|s| {
            s.trim()
                .parse()
                .map_err(|_| format!("{field}: '{s}' is not a number").into())
        })
        .collect()
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        return Err("usage: n_scaling GEOMETRY.json MU1,ALPHA1,MU2,ALPHA2 T[,T…] [FIBRE_Y]".into());
    }
    let geometry = Geometry::from_name(&args[0])?;
    let p = numbers("material", &args[1])?;
    if p.len() != 4 {
        return Err(format!("material: expected 4 numbers, got {}", p.len()).into());
    }
    let ts = numbers("T", &args[2])?;
    let fibre_y = args.get(3).map(|s| numbers("fibre", s)).transpose()?;
    let law = MaterialLaw::Ogden(Ogden2::new(p[0], p[1], p[2], p[3])?);
    let mut material = Material::new(law, DEFAULT_BULK_RATIO)?;
    if let Some(k) = fibre_y.as_ref().and_then(|k| k.first().copied()) {
        let mu0 = material.mu0();
        material = material.with_fibre(Fibre::new([0.0, 1.0, 0.0], k * mu0)?)?;
    }
    println!(
        "geometry {}, fibre along y {:?} (k / μ0)",
        geometry.name, fibre_y
    );
    for &t in &ts {
        let mut at_3_bar = Vec::new();
        for n in [9usize, 11, 13] {
            let case = Case {
                design: geometry.design(n, t)?,
                material: material.clone(),
                pressures_bar: vec![0.0, 1.0, 2.0, 3.0],
                gravity: true,
                mesh: MeshOptions::level(MeshLevel::Coarse),
                solver: SolverSettings::default(),
                mode: Mode::Bending,
                contact: ContactSettings::default(),
                effects: Effects::neutral(),
            };
            let r = run(&case, |_, _| {}, |_, _, _| {}, false)?;
            let angles: Vec<String> = r
                .response
                .steps
                .iter()
                .map(|s| format!("{:.2}", s.angle_deg))
                .collect();
            println!(
                "N {n:2} T {t}: angle at 0 / 1 / 2 / 3 bar {} deg",
                angles.join(" / ")
            );
            at_3_bar.push(r.response.steps.last().map_or(f64::NAN, |s| s.angle_deg));
        }
        println!(
            "T {t}: at 3 bar N 9 / N 11 = {:.3}, N 13 / N 11 = {:.3}",
            at_3_bar[0] / at_3_bar[1],
            at_3_bar[2] / at_3_bar[1]
        );
    }
    Ok(())
}
