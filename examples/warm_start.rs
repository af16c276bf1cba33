//! Warm starts across cases: a ramp at a neighbouring material started from the converged
//! states of one already run, moved by their displacement sensitivities.
//!
//! Runs the coarse N = 9, T = 2 bending ramp (0, 1, 2, 3 bar) at Ogden 002 with the
//! sensitivities of its displacement to the four Ogden parameters, then the ramp with μ₁ 5 %
//! higher three ways: cold (from the undeformed actuator), warm from the neighbour's states
//! as they are, and warm from them moved by `(∂u/∂θ) Δθ`. Prints the Newton iterations per
//! output level, the wall time and the largest difference of the tips from the cold ramp.
//!
//! ```sh
//! RAYON_NUM_THREADS=1 cargo run --release --example warm_start
//! ```
//! About 3 minutes on one core.
//!
//! `-- design T_FROM T_TO` measures a warm start at a new design instead: the ramp at wall
//! thickness `T_FROM` (N = 9, Ogden 002), its states carried onto the mesh of `T_TO`
//! ([`WarmStart::carried`]), and the ramp at `T_TO` cold and warm from them: as they are
//! (zeroth order) and moved by their sensitivities to the wall bias, `(∂u/∂T) ΔT`, before
//! being carried (first order).

use std::time::Instant;

use surrogate::fe::effects::{Effect, Effects};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, MaterialLaw, Ogden2, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{ActuatorMesh, MeshLevel, MeshOptions};
use surrogate::fe::sensitivity::{sensitivities_with_fields, OgdenParameter, Parameter};
use surrogate::fe::simulate::{run_warm, Case, ContactSettings, Mode, Response};
use surrogate::fe::solver::SolverSettings;
use surrogate::fe::warm_start::{Transfer, WarmStart};

fn case(params: [f64; 4], mode: Mode) -> Result<Case, Box<dyn std::error::Error>> {
    case_at(params, 2.0, mode)
}

fn case_at(params: [f64; 4], t: f64, mode: Mode) -> Result<Case, Box<dyn std::error::Error>> {
    let [m1, a1, m2, a2] = params;
    let law = MaterialLaw::Ogden(Ogden2::new(m1, a1, m2, a2)?);
    Ok(Case {
        design: DesignParams::new(9, t).validate()?,
        material: Material::new(law, DEFAULT_BULK_RATIO)?,
        pressures_bar: vec![0.0, 1.0, 2.0, 3.0],
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Coarse),
        solver: SolverSettings {
            trace: std::env::var_os("SURROGATE_TRACE").is_some(),
            ..SolverSettings::default()
        },
        mode,
        contact: ContactSettings::default(),
        effects: Effects::neutral(),
    })
}

fn describe(name: &str, r: &Response, cold: Option<&Response>, seconds: f64) {
    let its: Vec<String> = r
        .steps
        .iter()
        .map(|s| {
            format!(
                "{}{}",
                s.newton_iterations,
                if s.warm_start { "w" } else { "" }
            )
        })
        .collect();
    let diff = cold.map_or(String::new(), |c| {
        let d = r
            .steps
            .iter()
            .zip(&c.steps)
            .map(|(a, b)| {
                let tip = (a.tip_uz_mm - b.tip_uz_mm).hypot(a.tip_uy_mm - b.tip_uy_mm);
                tip / b.tip_uz_mm.hypot(b.tip_uy_mm).max(1e-9)
            })
            .fold(0.0, f64::max);
        let per: Vec<String> = r
            .steps
            .iter()
            .zip(&c.steps)
            .map(|(a, b)| {
                format!(
                    "{:.1e}",
                    (a.tip_uz_mm - b.tip_uz_mm).hypot(a.tip_uy_mm - b.tip_uy_mm)
                )
            })
            .collect();
        format!(
            ", largest tip difference from cold {d:.2e} (relative), per level (mm) [{}]",
            per.join(", ")
        )
    });
    println!(
        "{name:<28} iterations per level [{}] = {}, {seconds:.1} s{diff}",
        its.join(", "),
        r.steps.iter().map(|s| s.newton_iterations).sum::<usize>()
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let base = Material::from_spec("ogden_002", DEFAULT_BULK_RATIO)?
        .ogden_set()
        .ok_or("ogden_002 is an Ogden law")?
        .as_array();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [what, from, to] = args.as_slice() {
        if what == "design" {
            return across_designs(base, from.parse()?, to.parse()?);
        }
    }
    let parameters = [
        OgdenParameter::Mu1,
        OgdenParameter::Alpha1,
        OgdenParameter::Mu2,
        OgdenParameter::Alpha2,
    ]
    .map(Parameter::Material);
    let t = Instant::now();
    let neighbour = sensitivities_with_fields(
        &case(base, Mode::Bending)?,
        &parameters,
        None,
        |_, _| {},
        |_, _, _| {},
    )?;
    describe(
        "neighbour (Ogden 002)",
        &neighbour.response,
        None,
        t.elapsed().as_secs_f64(),
    );

    // the step: μ₁ + 5 % by default; `-- mu0 0.15` scales μ0 (μ₁ and μ₂) by 1.15 instead
    let mut moved = base;
    match args.as_slice() {
        [what, step] if what == "mu0" => {
            let f = 1.0 + step.parse::<f64>()?;
            moved[0] *= f;
            moved[2] *= f;
        }
        [] => moved[0] *= 1.05,
        _ => return Err("usage: warm_start [mu0 STEP | design T_FROM T_TO]".into()),
    }
    let delta: Vec<f64> = moved.iter().zip(&base).map(|(a, b)| a - b).collect();
    let target = case(moved, Mode::Bending)?;

    let t = Instant::now();
    let cold = run_warm(&target, None, |_, _| {}, |_, _, _| {}, false)?.response;
    describe("cold, stepped", &cold, None, t.elapsed().as_secs_f64());

    let zeroth = WarmStart::new(neighbour.states.clone());
    let t = Instant::now();
    let r = run_warm(&target, Some(&zeroth), |_, _| {}, |_, _, _| {}, false)?.response;
    describe(
        "warm, zeroth order",
        &r,
        Some(&cold),
        t.elapsed().as_secs_f64(),
    );

    let first = neighbour.warm_start(&delta)?;
    let t = Instant::now();
    let r = run_warm(&target, Some(&first), |_, _| {}, |_, _, _| {}, false)?.response;
    describe(
        "warm, first order",
        &r,
        Some(&cold),
        t.elapsed().as_secs_f64(),
    );
    Ok(())
}

/// The ramp at wall thickness `t_from`, then the one at `t_to` cold and warm from the
/// former's states carried onto its mesh.
fn across_designs(
    material: [f64; 4],
    t_from: f64,
    t_to: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let from = case_at(material, t_from, Mode::Bending)?;
    // the sensitivities to the wall bias (every bellow wall and the skin T + bias): ∂u/∂T
    let neighbour = sensitivities_with_fields(
        &from,
        &[Parameter::Effect(Effect::WallBias)],
        None,
        |_, _| {},
        |_, _, _| {},
    )?;
    describe(
        &format!("neighbour (T = {t_from}) + ∂u/∂T"),
        &neighbour.response,
        None,
        t.elapsed().as_secs_f64(),
    );

    let target = case_at(material, t_to, Mode::Bending)?;
    let t = Instant::now();
    let cold_ran = run_warm(&target, None, |_, _| {}, |_, _, _| {}, true)?;
    let cold = cold_ran.response;
    describe(
        &format!("cold (T = {t_to})"),
        &cold,
        None,
        t.elapsed().as_secs_f64(),
    );

    let t = Instant::now();
    let (design_a, design) = (from.printed_design()?, target.printed_design()?);
    let mesh_a = ActuatorMesh::new(&design_a, &from.mesh);
    let mesh = ActuatorMesh::new(&design, &target.mesh);
    let transfer = Transfer::new(&mesh_a, &design_a, &mesh, &design)?;
    let warm = WarmStart::new(neighbour.states.clone()).carried(&transfer)?;
    let carried = t.elapsed().as_secs_f64();
    println!(
        "states carried from T = {t_from} onto T = {t_to} in {carried:.2} s ({} nodes to {}; \
         {})",
        mesh_a.mesh().n_nodes(),
        mesh.mesh().n_nodes(),
        if transfer.same_topology() {
            "same topology: the contact gap shifts carried over"
        } else {
            "another topology: the contact gap shifts from the cold path"
        }
    );
    // how far each carried state is from the cold solution at its level
    let gaps: Vec<String> = warm
        .states
        .iter()
        .zip(&cold_ran.states)
        .map(|(w, c)| {
            let d = w.u.iter().zip(&c.u).map(|(a, b)| (a - b).abs());
            let scale = c.u.iter().map(|a| a.abs()).fold(0.0, f64::max);
            format!("{:.2e} of {scale:.1}", d.fold(0.0, f64::max))
        })
        .collect();
    println!(
        "largest nodal difference of the carried states from the cold solution (mm) [{}]",
        gaps.join(", ")
    );
    let t = Instant::now();
    let r = run_warm(&target, Some(&warm), |_, _| {}, |_, _, _| {}, false)?.response;
    describe(
        "warm, zeroth order",
        &r,
        Some(&cold),
        t.elapsed().as_secs_f64() + carried,
    );

    let t = Instant::now();
    let first = neighbour.warm_start(&[t_to - t_from])?.carried(&transfer)?;
    let r = run_warm(&target, Some(&first), |_, _| {}, |_, _, _| {}, false)?.response;
    describe(
        "warm, first order",
        &r,
        Some(&cold),
        t.elapsed().as_secs_f64(),
    );
    Ok(())
}
