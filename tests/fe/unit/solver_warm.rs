//! The unit tests of `src/fe/solver/warm.rs`.

use super::assembly_model::clamped_block;
use surrogate::fe::assembly::LoadLevel;
use surrogate::fe::assembly::{FeModel, LoadFactor};
use surrogate::fe::solver::solve_path_from;
use surrogate::fe::solver::warm::*;
use surrogate::fe::solver::{PathState, Solver, SolverSettings, StepReport};

/// A clamped block under a large oblique body force, its elements' stiffness scaled.
fn block(stiffness: f64) -> FeModel {
    let mut fe = clamped_block(3);
    fe.set_body_force([0.5, 0.15, 0.0]);
    fe.set_stiffness(|_| stiffness);
    fe
}

/// From a neighbour more than three times as stiff Newton fails; the homotopy from the
/// neighbour's state reaches the cold solve's solution, and its iterations are counted
/// with the failed jump's in the step's report.
#[test]
fn the_homotopy_reaches_the_cold_solution_where_the_jump_fails() {
    let level = LoadLevel::ZERO.with(LoadFactor::GRAVITY, 1.0);
    let settings = SolverSettings {
        rtol: 1e-10,
        augmented_updates: 0,
        ..SolverSettings::default()
    };
    let neighbour = block(1.0);
    let mut state = PathState::new(&neighbour);
    solve_path_from(
        &neighbour,
        settings.clone(),
        &mut state,
        &[level],
        |_, _, _| {},
    )
    .expect("neighbour");
    let guess = LevelGuess {
        u_full: state.u_full.clone(),
        shifts: Vec::new(),
        fallback: None,
    };

    let fe = block(0.3);
    let mut cold = PathState::new(&fe);
    solve_path_from(&fe, settings.clone(), &mut cold, &[level], |_, _, _| {}).expect("cold");

    // the parts one at a time: the jump fails, the homotopy converges
    let mut solver = Solver::new(&fe, settings.clone()).expect("solver");
    let mut state = PathState::new(&fe);
    let Err(jumped) = solver.jump(&mut state, level, &guess).expect("jump") else {
        panic!("the direct jump was expected to fail");
    };
    assert!(jumped > 0);
    assert_eq!(state.level, LoadLevel::default(), "state restored");
    assert!(state.u_free.iter().all(|&u| u == 0.0), "state restored");
    let rep = solver
        .homotopy(&mut state, level, &[&guess.u_full], &guess.shifts)
        .expect("homotopy")
        .expect("the homotopy was expected to converge");
    assert!(rep.warm_start && rep.converged);
    assert!(rep.homotopy_steps >= 2, "{rep:?}");
    // every homotopy step takes at least one iteration
    assert!(rep.newton_iterations >= rep.homotopy_steps, "{rep:?}");
    assert_eq!(state.level, level);
    let (homotopy, steps) = (rep.newton_iterations, rep.homotopy_steps);

    // the same through the path driver: one report counting both
    let mut warm = PathState::new(&fe);
    let reports = solve_path_guided(
        &fe,
        settings,
        &mut warm,
        &[level],
        &[Some(&guess)],
        |_, _, _| {},
    )
    .expect("warm");
    let rep = &reports[0];
    assert!(rep.warm_start, "{rep:?}");
    assert_eq!(rep.homotopy_steps, steps);
    assert_eq!(rep.newton_iterations, jumped + homotopy, "{rep:?}");

    let scale = cold.u_full.iter().fold(0.0f64, |m, u| m.max(u.abs()));
    assert!(scale > 0.5, "a large deformation: {scale}");
    let diff = warm
        .u_full
        .iter()
        .zip(&cold.u_full)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff <= 1e-8 * scale, "{diff:e} of {scale}");
    assert_eq!(warm.u_full, state.u_full);
}

/// A homotopy whose steps all fail halves its step a bounded number of times, counts
/// every solve and iteration, and leaves the state and the contact shifts as they were;
/// the load path then starts from there as usual.
#[test]
fn a_failing_homotopy_gives_up_and_restores_the_state() {
    let level = LoadLevel::ZERO.with(LoadFactor::GRAVITY, 1.0);
    let settings = SolverSettings {
        rtol: 1e-10,
        augmented_updates: 0,
        max_iterations: 20,
        ..SolverSettings::default()
    };
    let neighbour = block(1.0);
    let mut state = PathState::new(&neighbour);
    solve_path_from(
        &neighbour,
        settings.clone(),
        &mut state,
        &[level],
        |_, _, _| {},
    )
    .expect("neighbour");
    let guess = state.u_full.clone();
    let fe = block(0.3);
    // one iteration per Newton solve: no step can converge
    let mut solver = Solver::new(
        &fe,
        SolverSettings {
            max_iterations: 1,
            ..settings
        },
    )
    .expect("solver");
    let mut state = PathState::new(&fe);
    let spent = solver
        .homotopy(&mut state, level, &[&guess], &[])
        .expect("homotopy")
        .expect_err("no step converges");
    assert_eq!(spent.homotopy_steps, HOMOTOPY_MAX_HALVINGS + 1);
    assert_eq!(spent.iterations, HOMOTOPY_MAX_HALVINGS + 1);
    assert_eq!(solver.homotopy_weight(), 0.0);
    assert_eq!(solver.settings().rtol, 1e-10);
    assert_eq!(state.level, LoadLevel::default());
    assert!(state.u_free.iter().chain(&state.u_full).all(|&u| u == 0.0));
    solver.settings_mut().max_iterations = 20;
    let rep = solver.advance(&mut state, level).expect("the path");
    assert!(rep.converged && !rep.warm_start);
}

/// Reports written before the homotopy's count existed read as 0; a report without
/// homotopy steps is written as before.
#[test]
fn reports_without_the_homotopy_count_read_as_zero() {
    let rep = StepReport {
        level: LoadLevel::default(),
        newton_iterations: 3,
        substeps: 1,
        cutbacks: 0,
        residual: 1e-9,
        update: 1e-12,
        converged: true,
        factor_seconds: 0.0,
        assembly_seconds: 0.0,
        augmented_updates: 0,
        augmented_failed: false,
        factorizations: 3,
        stabilized: false,
        warm_start: true,
        homotopy_steps: 0,
    };
    let text = serde_json::to_string(&rep).expect("write");
    assert!(!text.contains("homotopy"), "{text}");
    assert_eq!(
        serde_json::from_str::<StepReport>(&text).expect("read"),
        rep
    );
    let with = StepReport {
        homotopy_steps: 4,
        ..rep
    };
    let text = serde_json::to_string(&with).expect("write");
    assert!(text.contains("\"homotopy_steps\":4"), "{text}");
    assert_eq!(
        serde_json::from_str::<StepReport>(&text).expect("read"),
        with
    );
}
