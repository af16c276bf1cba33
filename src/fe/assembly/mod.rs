//! The discretised model ([`FeModel`]) and its global assembly of residual and tangent.
//!
//! The residual is `r(u) = f_int(u) + f_pressure(u) − λ_g f_gravity − λ_t f_traction`
//! (pressure enters `r` with its follower sign, see [`super::loads`]), plus contact; each load
//! is scaled by its factor of the [`LoadLevel`] ([`load`]). It is the sum of physical terms,
//! one file each under [`terms`]; [`scatter`] adds their local systems into the global arrays,
//! colour by colour, so that results do not depend on the number of threads; [`dofs`] numbers
//! the unknowns and lays out the sparse pattern; [`model`] holds the data and [`assemble`]
//! runs the terms over it.

pub mod assemble;
pub mod dofs;
pub mod load;
pub mod model;
pub mod projection;
pub mod scatter;
pub mod terms;

pub use dofs::{pair_couplings, Constraint, DofMap, Pattern};
pub use load::{FactorInfo, LoadFactor, LoadFactorError, LoadLevel, LOAD_FACTORS};
pub use model::{AssemblyInfo, FeModel, PressureFace, ShiftUpdate};
pub use terms::term::{ElementContext, ElementTerm, LocalSystem, MAX_PLANES};
pub use terms::ELEMENT_TERMS;
