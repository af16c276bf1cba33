//! The design loop (`surrogate::design`): the search recovers designs, reports targets out of
//! reach on a bound, visits every `N`, refuses bad input by name, does not allocate in its
//! loop; the maps.
//!
//! One test binary; each module is one subject.

mod alloc;
mod common;
#[path = "../shared/counting_alloc.rs"]
mod counting_alloc;
mod maps;
mod search;
mod validation;
