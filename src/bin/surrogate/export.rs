//! `surrogate export`: model file → Rust source of const tables + C header.
use anyhow::{Context, Result};
use surrogate::case::Query;
use surrogate::rom::batch::material_params;
use surrogate::rom::export::{c_header, ramp_c_header, ramp_rust_source, rust_source, Precision};

use crate::args::{ExportArgs, PrecisionArg};

pub fn run(a: ExportArgs) -> Result<()> {
    let model = crate::files::load_model(&a.model)?;
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
        let q = Query::new(n, t, model.pressures[0], material_params(material)?);
        model.check_query(&q)?;
        let (q, snapped) = model.snap_to_domain(&q);
        for s in &snapped {
            eprintln!("note: {s}; the ramp is exported at the end");
        }
        let outside = model.check_domain(&q, a.allow_extrapolation).map_err(|e| {
            anyhow::anyhow!(
                "{e}; give --allow-extrapolation to export it anyway (the header then says which \
                 inputs are outside: SURROGATE_RAMP_IN_DOMAIN 0)"
            )
        })?;
        for v in &outside {
            eprintln!("warning: {v}; the exported ramp says so in its header");
        }
        (
            ramp_rust_source(&model, &q, precision, &sum)?,
            ramp_c_header(&model, precision, &sum, &q),
        )
    } else {
        anyhow::ensure!(
            a.n.is_none() && a.t.is_none() && a.material.is_none(),
            "--n, --t and --material select the design of --ramp: give --ramp too"
        );
        (
            rust_source(&model, precision, &sum)?,
            c_header(&model, precision, &sum),
        )
    };
    crate::files::write_file(&a.rust, src.as_bytes())
        .with_context(|| format!("writing {}", a.rust.display()))?;
    let header = a
        .header
        .clone()
        .unwrap_or_else(|| a.rust.with_extension("h"));
    crate::files::write_file(&header, c.as_bytes())
        .with_context(|| format!("writing {}", header.display()))?;
    eprintln!(
        "wrote {} -> {} + {}",
        a.model.display(),
        a.rust.display(),
        header.display()
    );
    Ok(())
}
