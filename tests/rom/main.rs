//! The POD surrogate (`surrogate::rom`) and the embedded predictor: snapshot data, model files,
//! gradients, the allocation-free and fast paths, ramps, exports, the training domain, the
//! shared output schema, the shipped models, and a regressor registered from outside the crate.
//!
//! One test binary; each module is one subject.

#[path = "../shared/counting_alloc.rs"]
mod counting_alloc;
#[path = "../rom_common/mod.rs"]
mod rom_common;

mod domain;
mod fuzz_parsers;
mod model_form;
mod ordinal_n;
mod output_schema;
mod rom_alloc;
mod rom_data;
mod rom_embedded;
mod rom_fast;
mod rom_gradients;
mod rom_model;
mod rom_ramp;
mod shipped_model;
mod sparse_gp;
mod toy_regressor;
mod unseen;
