//! `surrogate export`: model file → Rust source of const tables + C header.
use anyhow::{Context, Result};
use surrogate::rom::batch::material_params;
use surrogate::rom::export::{c_header, ramp_c_header, ramp_rust_source, rust_source, Precision};
use surrogate::rom::{Query, Surrogate};

use crate::args::{ExportArgs, PrecisionArg};

pub fn run(a: ExportArgs) -> Result<()> {
    let model = Surrogate::load(&a.model)?;
    let precision = match a.precision {
        PrecisionArg::F32 => Precision::F32,
        PrecisionArg::F64 => Precision::F64,
    };
    let sum = model.checksum()?;
    let (src, c) = if a.ramp {
        let (Some(n), Some(t), Some(material)) = (a.n, a.t, a.material.as_deref()) else {
            anyhow::bail!(
                "--ramp needs --n, --t and --material (the design and material to export)"
            );
        };
        let q = Query::new(n, t, 0.0, material_params(material)?);
        for v in model.domain_violations(&q) {
            eprintln!("warning: {v}");
        }
        (
            ramp_rust_source(&model, &q, precision, &sum)?,
            ramp_c_header(precision, &sum, &q),
        )
    } else {
        anyhow::ensure!(
            a.n.is_none() && a.t.is_none() && a.material.is_none(),
            "--n, --t and --material select the design of --ramp: give --ramp too"
        );
        (
            rust_source(&model, precision, &sum)?,
            c_header(precision, &sum),
        )
    };
    std::fs::write(&a.rust, src).with_context(|| format!("writing {}", a.rust.display()))?;
    let header = a
        .header
        .clone()
        .unwrap_or_else(|| a.rust.with_extension("h"));
    std::fs::write(&header, c).with_context(|| format!("writing {}", header.display()))?;
    println!(
        "exported {} -> {} + {}",
        a.model.display(),
        a.rust.display(),
        header.display()
    );
    Ok(())
}
