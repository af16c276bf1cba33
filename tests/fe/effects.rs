//! The effect library on the coarse actuator: neutral values change nothing, and each effect
//! moves the outputs the way its physics says (signs and rough sizes, not snapshots of numbers).
//!
//! Bending runs go to 0.5 bar without bellow contact (the walls do not meet below about 1 bar
//! on N = 9, T = 2), so each costs seconds; the force runs need the plate's contact.

use surrogate::fe::effects::{Effect, Effects};
use surrogate::fe::geometry::DesignParams;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::fe::simulate::{simulate, Case, ContactSettings, Mode, StepResult};
use surrogate::fe::solver::SolverSettings;

fn case(mode: Mode, effects: &[(Effect, f64)]) -> Case {
    let mut e = Effects::neutral();
    for &(k, v) in effects {
        e.set(k, v).unwrap();
    }
    Case {
        design: DesignParams::new(9, 2.0).validate().unwrap(),
        material: Material::from_spec("ogden_002", DEFAULT_BULK_RATIO).unwrap(),
        pressures_bar: vec![0.0, 0.5],
        gravity: true,
        mesh: MeshOptions::level(MeshLevel::Coarse),
        solver: SolverSettings::default(),
        mode,
        contact: ContactSettings {
            enabled: mode == Mode::Force,
            ..ContactSettings::default()
        },
        effects: e,
    }
}

fn run(mode: Mode, effects: &[(Effect, f64)]) -> Vec<StepResult> {
    simulate(&case(mode, effects)).unwrap().steps
}

/// The bending run without effects, which every bending test compares with (run once).
fn plain_bending() -> Vec<StepResult> {
    crate::shared_runs::steps(&case(Mode::Bending, &[]))
}

/// The bending angle at 0.5 bar and the tip's sag `Uy` at 0 bar.
fn angle_and_sag(s: &[StepResult]) -> (f64, f64) {
    (s[1].angle_deg, s[0].tip_uy_mm)
}

#[test]
fn neutral_effects_give_the_results_of_the_model_without_them() {
    let plain = plain_bending();
    let neutral = run(
        Mode::Bending,
        &[
            (Effect::WallBias, 0.0),
            (Effect::GapBias, 0.0),
            (Effect::ClampCompliance, 0.0),
            (Effect::PressureLoss, 0.0),
            (Effect::PressureOffset, 0.0),
            (Effect::Density, 1.0),
            (Effect::Anisotropy, 0.0),
            (Effect::PlateCompliance, 0.0),
        ],
    );
    assert_eq!(plain, neutral);
    // a neutral case writes no effects (plans and caches keep their hashes)
    let json = serde_json::to_value(case(Mode::Bending, &[(Effect::Density, 1.0)])).unwrap();
    assert!(json.get("effects").is_none(), "{json}");
    let json = serde_json::to_value(case(Mode::Bending, &[(Effect::Density, 1.2)])).unwrap();
    assert_eq!(json["effects"]["density"], 1.2);
}

#[test]
fn geometric_effects_move_the_bending_the_way_their_physics_says() {
    let (a0, s0) = angle_and_sag(&plain_bending());
    assert!(a0 > 1.0 && s0 < 0.0, "baseline {a0} deg, sag {s0} mm");
    let moved = |e: Effect, v: f64| angle_and_sag(&run(Mode::Bending, &[(e, v)]));
    // thicker walls stiffen, thinner soften: ±0.2 mm on T = 2 moves the angle by about 3 %
    // (the base carries much of the bending stiffness)
    let (thick, _) = moved(Effect::WallBias, 0.2);
    let (thin, _) = moved(Effect::WallBias, -0.2);
    assert!(
        thick < 0.99 * a0 && thin > 1.01 * a0,
        "{thin} > {a0} > {thick}"
    );
    // the outer skin carries the bending stiffness; the bellow walls between the chambers hardly
    // change it (measured: +0.3 % for +0.2 mm). At this small bias the two families' changes add
    // up to the change of all walls together.
    let (bellows, _) = moved(Effect::WallBiasBellows, 0.2);
    let (skin, _) = moved(Effect::WallBiasSkin, 0.2);
    let msg = format!("bellows {bellows}, skin {skin}, all {thick}, nominal {a0} (deg)");
    assert!(skin < 0.98 * a0, "{msg}");
    assert!((bellows - a0).abs() < 0.01 * a0, "{msg}");
    let additivity = (bellows - a0) + (skin - a0) - (thick - a0);
    assert!(additivity.abs() < 0.15 * (a0 - thick), "{msg}");
    // a thicker strain-limiting base resists the bending
    let (base, _) = moved(Effect::BaseBias, 0.4);
    assert!(base < a0, "{base} vs {a0}");
    // a longer free length bends further at the tip
    let (long, long_sag) = moved(Effect::FreeLengthBias, 2.0);
    assert!(
        long > a0 && long_sag < s0,
        "{long} vs {a0}, {long_sag} vs {s0}"
    );
}

#[test]
fn load_and_support_effects_move_the_bending_the_way_their_physics_says() {
    let plain = plain_bending();
    let (a0, s0) = angle_and_sag(&plain);
    // pressure loss: less bending under pressure, nothing at P = 0
    let lost = run(Mode::Bending, &[(Effect::PressureLoss, 0.2)]);
    let (a, s) = angle_and_sag(&lost);
    assert_eq!(s, s0);
    // the angle the pressure adds to the sagged state's: 20 % less pressure, about 20 % less
    // (nearly linear at 0.5 bar)
    let (d0, d) = (a0 - plain[0].angle_deg, a - plain[0].angle_deg);
    assert!(d < 0.9 * d0 && d > 0.7 * d0, "{d} vs {d0}");
    // self-weight: the sag at P = 0 scales with the density (small sag, nearly linear)
    let (_, heavy) = angle_and_sag(&run(Mode::Bending, &[(Effect::Density, 1.5)]));
    let ratio = heavy / s0;
    assert!((1.35..=1.65).contains(&ratio), "sag ratio {ratio}");
    // print anisotropy: a stiffer print along the length bends less, a softer one more
    let (stiff, _) = angle_and_sag(&run(Mode::Bending, &[(Effect::Anisotropy, 0.5)]));
    let (soft, _) = angle_and_sag(&run(Mode::Bending, &[(Effect::Anisotropy, -0.2)]));
    assert!(
        stiff < 0.98 * a0 && soft > 1.01 * a0,
        "{soft} > {a0} > {stiff}"
    );
    // a yielding clamp adds sag at P = 0
    let (_, soft) = angle_and_sag(&run(
        Mode::Bending,
        &[
            (Effect::ClampCompliance, 0.3),
            (Effect::ClampShearCompliance, 0.3),
        ],
    ));
    assert!(soft < s0 - 0.05, "sag {soft} vs rigid {s0}");
}

#[test]
fn force_rig_effects_move_the_blocked_force_the_way_their_physics_says() {
    let force = |s: &[StepResult]| s[1].force_n.unwrap();
    let f0 = force(&run(Mode::Force, &[]));
    assert!(f0 > 0.0, "{f0}");
    // a closer plate is reached earlier: more force at the same pressure
    let closer = force(&run(Mode::Force, &[(Effect::PlateOffset, -1.5)]));
    assert!(closer > f0, "{closer} vs {f0}");
    // the load cell's scale multiplies the reading (to the ramp's round-off: the parallel
    // assembly sums in an order that depends on the threads, and the force at 0.5 bar is a
    // small difference of contact forces, so two runs agree to about 1e-10, not bit for bit)
    let scaled = force(&run(Mode::Force, &[(Effect::ForceScale, 1.2)]));
    assert!((scaled / f0 - 1.2).abs() < 1e-6, "{scaled} vs {f0}");
    // (the pressure loss acts on the pressure before the rig sees it: checked in bending)
    // a plate on a spring yields c·F: less force, and the same force as a rigid plate set
    // c·F further away (the equilibrium does not depend on how the plate got there)
    let c = 1.0;
    let yielding = force(&run(Mode::Force, &[(Effect::PlateCompliance, c)]));
    assert!(yielding < f0 && yielding > 0.0, "{yielding} vs {f0}");
    let moved = force(&run(Mode::Force, &[(Effect::PlateOffset, c * yielding)]));
    assert!(
        (moved - yielding).abs() < 0.01 * yielding,
        "compliant {yielding} N, rigid plate {} mm further {moved} N",
        c * yielding
    );
}
