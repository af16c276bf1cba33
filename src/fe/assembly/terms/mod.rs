//! The physical terms of the residual and tangent, one file each.
//!
//! | term | file | kind |
//! |---|---|---|
//! | hyperelastic volume (Ogden, Mooney–Rivlin, neo-Hookean; mixed u–θ–π) | [`volume`] | element |
//! | follower pressure on the cavity faces | [`pressure`] | element |
//! | contact with rigid planes (the clamp block, the force plate) | [`plane_contact`] | element |
//! | deformable–deformable contact between facing bellow walls | [`pair_contact`] | face pair |
//! | gravity and dead tractions | [`dead_load`] | load vector |
//! | elastic foundation of a compliant clamp (added by a case's effects) | [`foundation`] | element, added |
//! | log-barrier contact law of the minimisation solver (replaces the penalty of both contacts) | [`barrier`] | law |
//!
//! An element term adds its contribution of one element to that element's local system
//! ([`term::LocalSystem`]); the assembly evaluates [`ELEMENT_TERMS`] and then the model's added terms
//! ([`FeModel::add_element_term`]) on every element, in that order, and scatters the sum once.
//! A new physical term is one new file implementing [`term::ElementTerm`] and one entry in that list
//! (or one call to `add_element_term` where a case builds its model). A load term with its own
//! load factor declares it ([`term::ElementTerm::load_factor`]) and reads it from the level
//! (`cx.level[factor]`); the factor is one more line in
//! [`LOAD_FACTORS`](crate::fe::assembly::LOAD_FACTORS) (or one
//! [`LoadFactor::register`](crate::fe::assembly::LoadFactor::register) call), and the solver
//! ramps it with the others (`tests/fe/toy_load_term.rs` adds one from outside the crate).

pub mod barrier;
pub mod dead_load;
pub mod foundation;
pub mod pair_contact;
pub mod plane_contact;
pub mod pressure;
pub mod term;
pub mod volume;

use crate::fe::assembly::model::FeModel;
use term::ElementTerm;

/// The element terms of every model, in evaluation order.
pub const ELEMENT_TERMS: &[&dyn ElementTerm<FeModel>] = &[
    &volume::Volume,
    &pressure::Pressure,
    &plane_contact::PlaneContact,
];
