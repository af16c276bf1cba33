//! `surrogate export`: model file → Rust source of const tables + C header.
use anyhow::{Context, Result};
use surrogate::rom::export::{c_header, rust_source, Precision};
use surrogate::rom::Surrogate;

use crate::args::{ExportArgs, PrecisionArg};

pub fn run(a: ExportArgs) -> Result<()> {
    let model = Surrogate::load(&a.model)?;
    let precision = match a.precision {
        PrecisionArg::F32 => Precision::F32,
        PrecisionArg::F64 => Precision::F64,
    };
    let sum = model.checksum()?;
    let src = rust_source(&model, precision, &sum)?;
    std::fs::write(&a.rust, src).with_context(|| format!("writing {}", a.rust.display()))?;
    let header = a
        .header
        .clone()
        .unwrap_or_else(|| a.rust.with_extension("h"));
    std::fs::write(&header, c_header(precision, &sum))
        .with_context(|| format!("writing {}", header.display()))?;
    println!(
        "exported {} -> {} + {}",
        a.model.display(),
        a.rust.display(),
        header.display()
    );
    Ok(())
}
