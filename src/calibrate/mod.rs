//! Fitting the model to the experiments. So far: the experimental records and the study's
//! error measures (the calibrator itself builds on these).
pub mod baseline;
pub mod experiments;
