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
