//! Physics the nominal model leaves out, as switchable effects of a case.
//!
//! Each effect is a named parameter with a unit, a neutral value and a plausible range. At its
//! neutral value an effect changes nothing: the case runs exactly the floating-point operations
//! of a case without it (tested bit for bit). The diagnoser ranks these effects as candidate
//! explanations of a mismatch between the model and the recordings.
//!
//! | effect | unit | neutral | range | kind | what it changes |
//! |---|---|---|---|---|---|
//! | `wall_bias` | mm | 0 | −0.4 … 0.4 | tolerance | every bellow wall printed `T + bias` thick |
//! | `wall_bias_bellows` | mm | 0 | −0.4 … 0.4 | tolerance | only the walls facing the gaps (normal ±z) |
//! | `wall_bias_skin` | mm | 0 | −0.4 … 0.4 | tolerance | only the outer skin (side wall and top) |
//! | `wall_bias_side` | mm | 0 | −1.8 … 1.8 | unstated | only the side walls (normal ±x), within 0.6 … 3.4 mm |
//! | `gap_bias` | mm | 0 | −0.8 … 1.0 | unstated | gap between bellows `g + bias` (modelled 1 mm): 0.2 … 2 mm |
//! | `base_bias` | mm | 0 | −0.8 … 3.0 | unstated | base thickness `b + bias` (modelled 4 mm): 3.2 … 7 mm |
//! | `duct_bias` | mm | 0 | −1.5 … 2.0 | unstated | duct half-width `d + bias` (modelled 2 mm): 0.5 … 4 mm |
//! | `free_length_bias` | mm | 0 | −6 … 6 | unstated | free length `Lf + bias` (modelled 92 mm) |
//! | `clamp_compliance` | mm/MPa | 0 | 0 … 0.5 | tolerance | clamped face on normal springs `k = 1/c` |
//! | `clamp_shear_compliance` | mm/MPa | 0 | 0 … 0.5 | tolerance | clamped face on tangential springs |
//! | `pressure_loss` | 1 | 0 | 0 … 0.3 | tolerance | effective pressure `(1 − f)·P − p₀` |
//! | `pressure_offset` | bar | 0 | 0 … 0.3 | tolerance | the `p₀` above |
//! | `density` | 1 | 1 | 0.5 … 1.5 | tolerance | self-weight scaled |
//! | `anisotropy` | 1 | 0 | −0.25 … 1 | tolerance | fibre term along the length, `k = a·μ0` |
//! | `plate_offset` | mm | 0 | −4.5 … 2 | unstated | plate `5 + offset` mm below the sagged tip (a printed square of unstated height on the scale) |
//! | `plate_compliance` | mm/N | 0 | 0 … 1 | tolerance | plate yields `c·F` under the blocked force |
//! | `force_scale` | 1 | 1 | 0.7 … 1.3 | tolerance | reported blocked force scaled (load-cell calibration) |
//!
//! **Tolerances and unstated dimensions** ([`Kind`]). A tolerance is a print or rig error around
//! a value the reference study states (the wall thickness `T` is 4, 5 or 6 perimeters of a
//! 0.4 mm nozzle); its range is what a printer or a rig can miss. An unstated dimension is one
//! the study does not give (the gap, the base, the duct, the side walls' solid layers, the
//! clamped length, the height of the printed square under the tip in the force rig): the
//! model's value is an assumption, and the range is what is physically possible for this
//! actuator. Each entry's [`EffectInfo::source`] quotes the study's sentence or states its
//! silence. A combination that leaves no valid actuator (gap ≤ 0, walls meeting, a closed
//! cavity, a duct above the base) is refused by [`DesignParams::validate`](crate::fe::geometry::DesignParams::validate) before any FE.
//!
//! Why each is plausible, from the printing process and the rigs:
//!
//! * **Walls** — FDM prints a wall as whole extrusion lines: a 1.6 mm wall with a 0.4 mm nozzle
//!   is four lines, and over- or under-extrusion, line overlap and the slicer's rounding move
//!   the printed thickness by a tenth of a millimetre or more. The walls facing the gaps and
//!   the outer skin are sliced differently (perimeters vs. the top surface), so they can err
//!   differently. The bending stiffness goes with `T³`: the thin walls are hit hardest, which is
//!   a pattern over `T`.
//! * **Dimensions** — the gap, base and duct are small features printed near the nozzle's
//!   resolution; the free length depends on where the clamp grips.
//! * **Clamp** — the actuator's base is held between printed or metal jaws; the TPU under the
//!   jaws and the jaws themselves yield. A compliance `c` (displacement per traction) of
//!   `ℓ/E` for a held length `ℓ` of material of modulus `E` gives ≈ 0.3 mm/MPa for 5 mm of TPU.
//!   It adds sag at P = 0 and rotation under pressure.
//! * **Pressure** — the gauge reads at the regulator; tubing, fittings and the inlet duct lose
//!   some pressure when flowing and a small offset to leaks or a zero error.
//! * **Density** — the print is not fully dense (infill, voids between lines), and the
//!   recorded mass of TPU varies by grade.
//! * **Print anisotropy** — the actuators are printed lying on their side, the bending plane
//!   parallel to the build plate, so the perimeter lines of the skin and the base run along
//!   the length `z`; lines bond to each other less well than a line holds together, which
//!   makes the print stiffer (`a > 0`) or, with poor fusion of the lines' ends, softer
//!   (`a < 0`) along `z` than across. Modelled as a transversely isotropic fibre term
//!   `W_f = k/2 (Ī₄ − 1)²` along `z` ([`Fibre`](crate::fe::material::Fibre)) with `k = a·μ0`:
//!   the small-strain modulus along `z` becomes `3μ0 + 4k`, the shear moduli stay `μ0`.
//! * **Force rig** — the plate is set 5 mm below the hanging tip by eye; the load cell's
//!   calibration is a scale factor; the load cell and the plate's mount deflect under the
//!   force (a beam load cell with a cantilevered plate yields tenths of a millimetre per
//!   newton), which lowers the force the tip builds up against it.

//!
//! **An open library.** Each effect implements [`CaseEffect`] in a file of its own here (the
//! three wall biases as values of one shape, `walls.rs`, each file naming its walls): its
//! description ([`EffectInfo`]), the part of the case it acts on ([`Target`]: geometry,
//! pressure, self-weight, material, clamp, force plate, reported force), how it is applied
//! there (a hook of the trait) and how it is differentiated ([`Differentiation`], by default
//! its target's). [`BUILTIN_EFFECTS`] lists the library's, one line each, in the order they
//! are listed and applied; [`Effect`] is the handle the rest of the crate passes around. A
//! program adds its own without changing the crate: `Effect::new(&MINE)` can be set into
//! [`Effects`] and differentiated like the library's, and [`EffectRegistry::with`] makes its
//! name known to the program's parsing.

mod effect;
mod registry;
mod set;

mod anisotropy;
mod base_bias;
mod clamp_compliance;
mod clamp_shear_compliance;
mod density;
mod duct_bias;
mod force_scale;
mod free_length_bias;
mod gap_bias;
mod plate_compliance;
mod plate_offset;
mod pressure_loss;
mod pressure_offset;
mod wall_bias;
mod wall_bias_bellows;
mod wall_bias_side;
mod wall_bias_skin;
mod walls;

pub use effect::{
    Acts, CaseEffect, Differentiation, Effect, EffectError, EffectInfo, Kind, Target,
};
pub use registry::{EffectRegistry, BUILTIN_EFFECTS};
pub use set::Effects;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::geometry::DesignParams;
    use crate::fe::material::{Fibre, Material};

    #[test]
    fn the_library_lists_every_effect_once_with_its_neutral_value_inside_the_range() {
        let mut names: Vec<_> = BUILTIN_EFFECTS.iter().map(|e| e.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), BUILTIN_EFFECTS.len());
        for (k, &e) in BUILTIN_EFFECTS.iter().enumerate() {
            // the handle's rank is its place in the list
            assert_eq!(e.rank(), Some(k), "{e} out of order");
            assert_eq!(Effect::from_name(e.name()), Ok(e));
            assert_eq!(e.check(), Ok(()));
            assert_eq!(Effect::all().nth(k), Some(e));
            let i = e.info();
            assert!(i.range.0 <= i.neutral && i.neutral <= i.range.1, "{e}");
            assert!(i.range.0 < i.range.1);
        }
        // the library is ordered as listed
        assert!(BUILTIN_EFFECTS.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn neutral_effects_leave_the_design_and_the_pressure_unchanged() {
        let nominal = DesignParams::new(9, 1.6);
        let e = Effects::neutral()
            .with(Effect::WallBias, 0.0)
            .unwrap()
            .with(Effect::Density, 1.0)
            .unwrap();
        assert!(e.is_neutral());
        assert_eq!(e.printed_design(&nominal), nominal);
        for p in [0.0, 0.1, 1.7, 3.5] {
            assert_eq!(e.effective_pressure_bar(p).to_bits(), p.to_bits());
        }
        assert_eq!(e.clamp_springs(), [None, None, None]);
        // a neutral set writes nothing
        assert_eq!(serde_json::to_string(&Effects::neutral()).unwrap(), "{}");
    }

    #[test]
    fn biases_reach_the_printed_design() {
        let nominal = DesignParams::new(11, 2.0);
        let e = Effects::parse(["wall_bias=0.1", "wall_bias_skin=-0.3", "gap_bias=0.2"]).unwrap();
        let p = e.printed_design(&nominal);
        assert_eq!(p.wall_thickness, 2.0);
        assert!((p.bellow_wall_thickness.unwrap() - 2.1).abs() < 1e-12);
        assert!((p.skin_thickness.unwrap() - 1.8).abs() < 1e-12);
        assert!((p.gap - 1.2).abs() < 1e-12);
        assert!(p.validate().is_ok());
        let e = Effects::parse(["pressure_loss=0.1", "pressure_offset=0.05"]).unwrap();
        assert!((e.effective_pressure_bar(2.0) - 1.75).abs() < 1e-12);
        assert_eq!(e.effective_pressure_bar(0.0), 0.0);
        let e = Effects::parse(["clamp_compliance=0.2"]).unwrap();
        assert_eq!(e.clamp_springs(), [None, None, Some(5.0)]);
    }

    #[test]
    fn anisotropy_adds_a_fibre_along_the_length_and_refuses_to_replace_one() {
        let m = Material::from_spec("ogden_002", crate::fe::material::DEFAULT_BULK_RATIO).unwrap();
        assert_eq!(Effects::neutral().printed_material(&m).unwrap(), m);
        let e = Effects::parse(["anisotropy=0.5"]).unwrap();
        let printed = e.printed_material(&m).unwrap();
        let fibre = printed.fibre.as_ref().unwrap();
        assert!((fibre.modulus() - 0.5 * m.mu0()).abs() < 1e-12);
        assert_eq!(fibre.params().direction, Fibre::ALONG_LENGTH);
        let err = e.printed_material(&printed).unwrap_err().to_string();
        assert!(err.contains("fibre") && err.contains("anisotropy"), "{err}");
    }

    /// Fuzz-style: every malformed assignment is an error naming the effect and its range.
    #[test]
    fn bad_assignments_are_errors_naming_the_effect_and_its_range() {
        let cases: &[(&[&str], &str)] = &[
            (
                &["wal_bias=0.1"],
                "unknown effect \"wal_bias\": expected one of wall_bias",
            ),
            (&["wall_bias"], "expected NAME=VALUE"),
            (&["wall_bias=abc"], "expected NAME=VALUE"),
            (&["=0.1"], "unknown effect \"\""),
            (
                &["wall_bias=NaN"],
                "effect wall_bias = NaN mm: expected a value in [-0.4, 0.4] mm",
            ),
            (&["wall_bias=inf"], "effect wall_bias = inf mm"),
            (&["wall_bias=0.5"], "expected a value in [-0.4, 0.4] mm"),
            (
                &["density=0"],
                "effect density = 0 1: expected a value in [0.5, 1.5]",
            ),
            (&["clamp_compliance=-0.1"], "clamp_compliance = -0.1 mm/MPa"),
            (
                &["pressure_loss=0.1", "pressure_loss=0.2"],
                "given twice (0.1 and 0.2)",
            ),
        ];
        for (items, want) in cases {
            let e = Effects::parse(items.iter().copied())
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{items:?}: {e}");
        }
        // random strings never panic
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let alphabet: Vec<char> = "wall_bias=0.1-e+NaN,;= xyz".chars().collect();
        for _ in 0..2000 {
            let len = (state % 24) as usize;
            let s: String = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    alphabet[(state % alphabet.len() as u64) as usize]
                })
                .collect();
            let _ = Effects::parse([s.as_str()]);
        }
    }

    #[test]
    fn effects_round_trip_through_json_and_refuse_bad_files() {
        let e = Effects::parse(["wall_bias=-0.1", "plate_offset=1"]).unwrap();
        let s = serde_json::to_string(&e).unwrap();
        assert_eq!(s, r#"{"plate_offset":1.0,"wall_bias":-0.1}"#);
        assert_eq!(serde_json::from_str::<Effects>(&s).unwrap(), e);
        let bad = serde_json::from_str::<Effects>(r#"{"wall_bias":3}"#).unwrap_err();
        assert!(bad.to_string().contains("[-0.4, 0.4]"), "{bad}");
    }
}
