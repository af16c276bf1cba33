//! Export of a surrogate to the embedded predictor (the `surrogate-predict` crate,
//! [`surrogate_predict`]): owned tables in `f32` or `f64`, their borrowed [`EmbeddedModel`]
//! view, and the text of a Rust source file of `static` tables (with an `extern "C"` entry
//! point) and of the matching C header.
//!
//! The exported file is a module of the controller's crate, which depends on
//! `surrogate-predict` (`no_std`, no dependencies); it refers to it as `surrogate_predict`.
//! Beside the tables, the file and the header carry the model's model-form error
//! ([`super::model_form`]; [`model_form_rust`], [`model_form_c`]).

use std::fmt::Write as _;

use super::model_form::{ModelFormError, LABEL};
use super::regression::EmbeddedRegressor;
use super::surrogate::Surrogate;
use super::{RomError, QUANTITY_NAMES};
use crate::case::Query;
use surrogate_predict::{BlockTables, EmbeddedModel, GpTables, PolyTables, Real, MAX_COEFS};

/// Owned tables of one block.
#[derive(Debug, Clone)]
pub struct OwnedBlock<F> {
    n_quantities: usize,
    n_modes: usize,
    coef_offset: usize,
    regressor: u8,
    mean: Vec<F>,
    scale: Vec<F>,
    modes: Vec<F>,
}

/// Owned tables of an exported model in precision `F`.
#[derive(Debug, Clone)]
pub struct EmbeddedTables<F> {
    n_allowed: Vec<u32>,
    feature_index: Vec<u8>,
    feature_center: Vec<F>,
    feature_inv_half: Vec<F>,
    pressures: Vec<f64>,
    n_coefs: usize,
    gp_groups: Vec<u16>,
    gp_inv_len: Vec<f64>,
    gp_xs: Vec<f64>,
    gp_alpha: Vec<f64>,
    poly_exponents: Vec<u8>,
    poly_coef: Vec<F>,
    blocks: Vec<OwnedBlock<F>>,
    output_block: Vec<u8>,
    output_slot: Vec<u8>,
}

fn conv<F: Real>(v: &[f64]) -> Vec<F> {
    v.iter().map(|&x| F::from_f64(x)).collect()
}

impl<F: Real> EmbeddedTables<F> {
    /// Converts a surrogate (regressors that no block uses are left out).
    ///
    /// # Errors
    /// More regression outputs than [`MAX_COEFS`]; [`RomError::NotExportable`] for a block
    /// whose regressor the embedded predictor cannot evaluate.
    pub fn from_surrogate(s: &Surrogate) -> Result<Self, RomError> {
        let m = s.n_coefs();
        if m > MAX_COEFS {
            return Err(RomError::invalid(
                "number of POD coefficients",
                m,
                &format!("≤ {MAX_COEFS} for the embedded predictor"),
            ));
        }
        let (gp, poly, codes) = embedded_regressors(s)?;
        let mut blocks = Vec::with_capacity(s.blocks.len());
        for b in &s.blocks {
            let code = s.regressors.position(&b.regressor).map(|r| codes[r]);
            blocks.push(OwnedBlock {
                n_quantities: b.pod.quantities.len(),
                n_modes: b.pod.n_modes,
                coef_offset: b.coef_offset,
                regressor: code
                    .ok_or_else(|| not_exportable(b.regressor.name(), "not in the model"))?,
                mean: conv(&b.pod.mean),
                scale: conv(&b.pod.scale),
                modes: conv(&b.pod.modes),
            });
        }
        let (gp_groups, gp_inv_len, gp_xs, gp_alpha) = match gp {
            Some(EmbeddedRegressor::Gp {
                groups,
                inv_len,
                xs,
                alpha,
            }) => (groups, inv_len, xs, alpha),
            _ => Default::default(),
        };
        let (poly_exponents, poly_coef) = match poly {
            Some(EmbeddedRegressor::Poly { exponents, coef }) => (exponents, conv(&coef)),
            _ => Default::default(),
        };
        Ok(EmbeddedTables {
            n_allowed: s.n_allowed.clone(),
            feature_index: s.features.index.iter().map(|&i| i as u8).collect(),
            feature_center: conv(&s.features.center),
            feature_inv_half: conv(&s.features.inv_half),
            pressures: s.pressures.clone(),
            n_coefs: m,
            gp_groups,
            gp_inv_len,
            gp_xs,
            gp_alpha,
            poly_exponents,
            poly_coef,
            blocks,
            output_block: s.output_block.iter().map(|&b| b as u8).collect(),
            output_slot: s.output_slot.iter().map(|&b| b as u8).collect(),
        })
    }

    /// Block views (borrowing the tables).
    pub fn block_tables(&self) -> Vec<BlockTables<'_, F>> {
        self.blocks
            .iter()
            .map(|b| BlockTables {
                n_quantities: b.n_quantities,
                n_modes: b.n_modes,
                coef_offset: b.coef_offset,
                regressor: b.regressor,
                mean: &b.mean,
                scale: &b.scale,
                modes: &b.modes,
            })
            .collect()
    }

    /// The borrowed embedded model; `blocks` comes from [`Self::block_tables`].
    pub fn view<'a>(&'a self, blocks: &'a [BlockTables<'a, F>]) -> EmbeddedModel<'a, F> {
        EmbeddedModel {
            n_allowed: &self.n_allowed,
            feature_index: &self.feature_index,
            feature_center: &self.feature_center,
            feature_inv_half: &self.feature_inv_half,
            pressures: &self.pressures,
            n_coefs: self.n_coefs,
            gp: GpTables {
                groups: &self.gp_groups,
                inv_len: &self.gp_inv_len,
                xs: &self.gp_xs,
                alpha: &self.gp_alpha,
            },
            poly: PolyTables {
                exponents: &self.poly_exponents,
                coef: &self.poly_coef,
            },
            blocks,
            output_block: &self.output_block,
            output_slot: &self.output_slot,
        }
    }
}

fn not_exportable(regressor: &str, reason: &str) -> RomError {
    RomError::NotExportable {
        regressor: regressor.to_string(),
        reason: reason.to_string(),
    }
}

/// The embedded tables of the regressors the blocks use: the Gaussian process's, the
/// polynomial's, and each regressor's block code (by index in the model's regressors).
type UsedTables = (
    Option<EmbeddedRegressor>,
    Option<EmbeddedRegressor>,
    Vec<u8>,
);

fn embedded_regressors(s: &Surrogate) -> Result<UsedTables, RomError> {
    let (mut gp, mut poly) = (None, None);
    let mut codes = vec![0u8; s.regressors.len()];
    for (r, reg) in s.regressors.iter().enumerate() {
        if !s.blocks.iter().any(|b| b.regressor.name() == reg.name()) {
            continue;
        }
        let tables = reg.embedded().ok_or_else(|| {
            not_exportable(
                reg.name(),
                "the embedded predictor (surrogate-predict) evaluates only a Gaussian process \
                 and a polynomial",
            )
        })?;
        codes[r] = tables.code();
        let slot = match tables {
            EmbeddedRegressor::Gp { .. } => &mut gp,
            EmbeddedRegressor::Poly { .. } => &mut poly,
        };
        if slot.is_some() {
            return Err(not_exportable(
                reg.name(),
                "the embedded predictor holds one regressor of each family, and another block \
                 uses one of the same family",
            ));
        }
        *slot = Some(tables);
    }
    Ok((gp, poly, codes))
}

/// Precision of an export.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// Single precision tables and sums.
    F32,
    /// Double precision.
    F64,
}

impl Precision {
    fn ty(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
    fn c_ty(self) -> &'static str {
        match self {
            Precision::F32 => "float",
            Precision::F64 => "double",
        }
    }
}

fn array<T: std::fmt::Debug>(out: &mut String, name: &str, ty: &str, v: &[T]) {
    let _ = write!(out, "static {name}: [{ty}; {}] = [", v.len());
    for (i, x) in v.iter().enumerate() {
        if i % 8 == 0 {
            out.push_str("\n    ");
        }
        let _ = write!(out, "{x:?}, ");
    }
    out.push_str("\n];\n");
}

fn rust_body<F: Real + std::fmt::Debug>(t: &EmbeddedTables<F>, p: Precision, out: &mut String) {
    let ty = p.ty();
    array(out, "N_ALLOWED", "u32", &t.n_allowed);
    array(out, "FEATURE_INDEX", "u8", &t.feature_index);
    array(out, "FEATURE_CENTER", ty, &t.feature_center);
    array(out, "FEATURE_INV_HALF", ty, &t.feature_inv_half);
    array(out, "PRESSURES", "f64", &t.pressures);
    array(out, "GP_GROUPS", "u16", &t.gp_groups);
    array(out, "GP_INV_LEN", "f64", &t.gp_inv_len);
    array(out, "GP_XS", "f64", &t.gp_xs);
    array(out, "GP_ALPHA", "f64", &t.gp_alpha);
    array(out, "POLY_EXPONENTS", "u8", &t.poly_exponents);
    array(out, "POLY_COEF", ty, &t.poly_coef);
    array(out, "OUTPUT_BLOCK", "u8", &t.output_block);
    array(out, "OUTPUT_SLOT", "u8", &t.output_slot);
    for (i, b) in t.blocks.iter().enumerate() {
        array(out, &format!("B{i}_MEAN"), ty, &b.mean);
        array(out, &format!("B{i}_SCALE"), ty, &b.scale);
        array(out, &format!("B{i}_MODES"), ty, &b.modes);
    }
    let _ = writeln!(
        out,
        "static BLOCKS: [BlockTables<'static, {ty}>; {}] = [",
        t.blocks.len()
    );
    for (i, b) in t.blocks.iter().enumerate() {
        let _ = writeln!(
            out,
            "    BlockTables {{ n_quantities: {}, n_modes: {}, coef_offset: {}, regressor: {}, mean: &B{i}_MEAN, scale: &B{i}_SCALE, modes: &B{i}_MODES }},",
            b.n_quantities, b.n_modes, b.coef_offset, b.regressor
        );
    }
    out.push_str("];\n\n");
    let _ = write!(
        out,
        "/// The exported model.\npub static MODEL: EmbeddedModel<'static, {ty}> = EmbeddedModel {{\n    n_allowed: &N_ALLOWED,\n    feature_index: &FEATURE_INDEX,\n    feature_center: &FEATURE_CENTER,\n    feature_inv_half: &FEATURE_INV_HALF,\n    pressures: &PRESSURES,\n    n_coefs: {},\n    gp: GpTables {{ groups: &GP_GROUPS, inv_len: &GP_INV_LEN, xs: &GP_XS, alpha: &GP_ALPHA }},\n    poly: PolyTables {{ exponents: &POLY_EXPONENTS, coef: &POLY_COEF }},\n    blocks: &BLOCKS,\n    output_block: &OUTPUT_BLOCK,\n    output_slot: &OUTPUT_SLOT,\n}};\n\n",
        t.n_coefs
    );
}

/// Name of the C entry point for a precision.
pub fn c_symbol(p: Precision) -> String {
    format!("surrogate_predict_{}", p.ty())
}

/// Rust source of the exported model: `static` tables, `pub static MODEL`, and the C entry point
/// `surrogate_predict_f32/f64`. It is a module of a crate that depends on the
/// `surrogate-predict` crate (`use surrogate_predict::…`) and compiles under `#![no_std]`.
///
/// # Errors
/// See [`EmbeddedTables::from_surrogate`].
pub fn rust_source(s: &Surrogate, p: Precision, checksum: &str) -> Result<String, RomError> {
    let mut out = format!(
        "//! Surrogate model exported by `surrogate export` (model {checksum}, precision {}).\n//! Needs the `surrogate-predict` crate (a dependency of the crate this module is in); `core` only.\n//! Outputs (22): {}; their indices are named in `surrogate_predict` (`TIP_UZ`, `ANGLE`, `FORCE`, `marker_uz(k)` …).\n#![allow(clippy::all, clippy::excessive_precision, missing_docs)]\n\nuse surrogate_predict::{{evaluate, BlockTables, EmbeddedModel, GpTables, ModelFormTables, PolyTables}};\n\n",
        p.ty(),
        QUANTITY_NAMES.join(", ")
    );
    match p {
        Precision::F32 => rust_body(&EmbeddedTables::<f32>::from_surrogate(s)?, p, &mut out),
        Precision::F64 => rust_body(&EmbeddedTables::<f64>::from_surrogate(s)?, p, &mut out),
    }
    model_form_rust(s, &mut out);
    let ty = p.ty();
    let _ = write!(
        out,
        "/// C entry point: writes the 22 outputs to `out`; returns 0 on success, 1 non-finite input,\n/// 2 untrained N, 3 inadmissible material, 4 bad model, 5 null pointer.\n///\n/// # Safety\n/// `out` must point to 22 writable `{ty}`.\n#[no_mangle]\npub unsafe extern \"C\" fn {}(n: u32, t_mm: {ty}, p_bar: {ty}, mu1: {ty}, alpha1: {ty}, mu2: {ty}, alpha2: {ty}, out: *mut {ty}) -> i32 {{\n    if out.is_null() {{\n        return 5;\n    }}\n    let input = [n as {ty}, t_mm, p_bar, mu1, alpha1, mu2, alpha2];\n    let mut values = [0.0 as {ty}; 22];\n    match evaluate(&MODEL, &input, &mut values) {{\n        Ok(()) => {{\n            let mut i = 0;\n            while i < 22 {{\n                *out.add(i) = values[i];\n                i += 1;\n            }}\n            0\n        }}\n        Err(e) => e.code(),\n    }}\n}}\n",
        c_symbol(p)
    );
    Ok(out)
}

/// The C name of an output's index: `SURROGATE_` and the output's column without its unit
/// suffix, in capitals (`tip_uz_mm` → `SURROGATE_TIP_UZ`, `m1_uz_mm` → `SURROGATE_M1_UZ`,
/// `angle_deg` → `SURROGATE_ANGLE`): the names of the `surrogate-predict` crate's constants
/// ([`surrogate_predict::TIP_UZ`] …) with the prefix.
pub fn c_output_macro(column: &str) -> String {
    let stem = column.rsplit_once('_').map_or(column, |(stem, _)| stem);
    format!("SURROGATE_{}", stem.to_ascii_uppercase())
}

/// The named output indices (`#define SURROGATE_TIP_UZ 18` …, guarded so that a model's and a
/// ramp's header can be included together), then the output order inside a C comment.
fn c_output_order(out: &mut String) {
    out.push_str("#ifndef SURROGATE_OUTPUT_INDICES\n#define SURROGATE_OUTPUT_INDICES\n/* Index of each output in `out` (markers 1 … 9 as in the columns m1 … m9; 9 is the tip). */\n");
    for (i, q) in QUANTITY_NAMES.iter().enumerate() {
        let _ = writeln!(out, "#define {} {i}", c_output_macro(q));
    }
    out.push_str("#endif\n/* Output order:\n");
    for (i, q) in QUANTITY_NAMES.iter().enumerate() {
        let _ = writeln!(out, " *  {i:2}: {q}");
    }
}

/// C header declaring the entry point of [`rust_source`], with the model-form error
/// ([`model_form_c`]).
pub fn c_header(s: &Surrogate, p: Precision, checksum: &str) -> String {
    let ty = p.c_ty();
    let mut out = format!(
        "/* Surrogate model exported by `surrogate export` (model {checksum}). */\n#ifndef SURROGATE_MODEL_H\n#define SURROGATE_MODEL_H\n#include <stdint.h>\n#ifdef __cplusplus\nextern \"C\" {{\n#endif\n\n#define SURROGATE_N_OUTPUTS 22\n"
    );
    model_form_c(s, &mut out);
    c_output_order(&mut out);
    let _ = write!(
        out,
        " * Returns 0 on success, 1 non-finite input, 2 untrained N, 3 inadmissible material,\n * 4 bad model, 5 null pointer. */\nint32_t {}(uint32_t n, {ty} t_mm, {ty} p_bar, {ty} mu1, {ty} alpha1, {ty} mu2, {ty} alpha2, {ty} *out);\n\n#ifdef __cplusplus\n}}\n#endif\n#endif /* SURROGATE_MODEL_H */\n",
        c_symbol(p)
    );
    out
}

/// The model-form error's description, one line per output with its value at each level.
fn model_form_lines(m: &ModelFormError) -> Vec<String> {
    let c = &m.calibration;
    let mut lines = vec![
        format!(
            "{LABEL}: rms of the calibrated model minus the recordings of {} (objective {}, {} configurations),",
            c.report, c.objective, c.configurations
        ),
        "per recorded pressure, linear in P between the levels and held at the ends; the \
         surrogate's own error against the FE model is far smaller."
            .into(),
    ];
    for o in &m.outputs {
        let at: Vec<String> = m
            .pressures
            .iter()
            .zip(&o.at_levels)
            .map(|(p, e)| format!("{e:.4} at {p} bar"))
            .collect();
        lines.push(format!("  {}: {}", o.name, at.join(", ")));
    }
    lines
}

/// The model-form error of an exported model or ramp as Rust: `pub static MODEL_FORM:
/// Option<ModelFormTables>` ([`surrogate_predict::ModelFormTables::error`]), `None` when the
/// model file carries none.
pub fn model_form_rust(s: &Surrogate, out: &mut String) {
    let Some(m) = s.model_form() else {
        out.push_str("/// The model-form error (calibration residuals): none, the model file carries none; how far\n/// the model misses real actuators is not known here.\npub static MODEL_FORM: Option<ModelFormTables<'static>> = None;\n\n");
        return;
    };
    let (pressures, outputs, values) = m.tables();
    array(out, "MODEL_FORM_PRESSURES", "f64", &pressures);
    array(out, "MODEL_FORM_OUTPUTS", "u8", &outputs);
    array(out, "MODEL_FORM_VALUES", "f64", &values);
    for l in model_form_lines(m) {
        let _ = writeln!(out, "/// {l}");
    }
    out.push_str("/// `MODEL_FORM.unwrap().error(ANGLE, p_bar)`: the error of one output at a pressure.\npub static MODEL_FORM: Option<ModelFormTables<'static>> = Some(ModelFormTables { pressures: &MODEL_FORM_PRESSURES, outputs: &MODEL_FORM_OUTPUTS, values: &MODEL_FORM_VALUES });\n\n");
}

/// The model-form error in a C header: a comment with its values, and (guarded, so that a
/// model's and a ramp's header can be included together) `SURROGATE_MODEL_FORM_N_LEVELS`, the
/// levels `SURROGATE_MODEL_FORM_P_BAR` and per output `SURROGATE_MODEL_FORM_TIP_UZ` … as
/// initialiser lists (`static const double e[] = SURROGATE_MODEL_FORM_ANGLE;`); with no
/// model-form error, `SURROGATE_MODEL_FORM_N_LEVELS 0`.
pub fn model_form_c(s: &Surrogate, out: &mut String) {
    out.push_str("#ifndef SURROGATE_MODEL_FORM_TABLES\n#define SURROGATE_MODEL_FORM_TABLES\n");
    let Some(m) = s.model_form() else {
        let _ = write!(out, "/* {LABEL}: none, the model file carries none. */\n#define SURROGATE_MODEL_FORM_N_LEVELS 0\n#endif\n");
        return;
    };
    out.push_str("/*\n");
    for l in model_form_lines(m) {
        let _ = writeln!(out, " * {l}");
    }
    let list = |v: &[f64]| {
        let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        format!("{{{}}}", items.join(", "))
    };
    let _ = write!(
        out,
        " */\n#define SURROGATE_MODEL_FORM_N_LEVELS {}\n#define SURROGATE_MODEL_FORM_P_BAR {}\n",
        m.pressures.len(),
        list(&m.pressures)
    );
    for o in &m.outputs {
        let name = c_output_macro(&o.name).replacen("SURROGATE_", "SURROGATE_MODEL_FORM_", 1);
        let _ = writeln!(out, "#define {name} {}", list(&o.at_levels));
    }
    out.push_str("#endif\n");
}

/// Name of the C entry point of an exported ramp ([`ramp_rust_source`]).
pub fn ramp_c_symbol(p: Precision) -> String {
    format!("surrogate_ramp_{}", p.ty())
}

/// Rust source of one design and material exported as its reconstructed pressure ramp
/// ([`crate::rom::Ramp`]): `static` tables (the grid and 22 × n_p values), `pub static RAMP`
/// and the C entry point `surrogate_ramp_f32/f64(p_bar, out)`. Like [`rust_source`] it
/// needs the `surrogate-predict` crate and compiles under `#![no_std]`.
///
/// # Errors
/// Invalid query ([`Surrogate::check_query`]).
pub fn ramp_rust_source(
    s: &Surrogate,
    q: &Query,
    p: Precision,
    checksum: &str,
) -> Result<String, RomError> {
    let ramp = s.ramp(q)?;
    let ty = p.ty();
    let domain = ramp_domain_lines(s, q);
    let mut out = format!(
        "//! Pressure ramp exported by `surrogate export --ramp` (model {checksum}, precision {ty}):\n//! N = {}, T = {} mm, Ogden μ₁ = {} MPa, α₁ = {}, μ₂ = {} MPa, α₂ = {}.\n{}//! Needs the `surrogate-predict` crate (a dependency of the crate this module is in); `core` only.\n//! Outputs (22): {}; their indices are named in `surrogate_predict` (`TIP_UZ`, `ANGLE`, `FORCE`, `marker_uz(k)` …).\n#![allow(clippy::all, clippy::excessive_precision, missing_docs)]\n\nuse surrogate_predict::{{evaluate_ramp, ModelFormTables, RampTables}};\n\n",
        q.n,
        q.t_mm,
        q.material.mu1_mpa,
        q.material.alpha1,
        q.material.mu2_mpa,
        q.material.alpha2,
        domain.iter().map(|l| format!("//! {l}\n")).collect::<String>(),
        QUANTITY_NAMES.join(", ")
    );
    let outside = s.domain_violations(q);
    let listed: Vec<String> = outside.iter().map(|v| v.short()).collect();
    let _ = write!(
        out,
        "/// Whether the design and material lie in the model's training domain.\npub const IN_DOMAIN: bool = {};\n/// The inputs outside it (`name=value (extrapolated)`), empty when inside.\npub const OUTSIDE_DOMAIN: &str = {:?};\n\n",
        outside.is_empty(),
        listed.join("; ")
    );
    model_form_rust(s, &mut out);
    array(&mut out, "PRESSURES", "f64", ramp.pressures());
    match p {
        Precision::F32 => {
            let v: Vec<f32> = ramp.values().iter().map(|&x| x as f32).collect();
            array(&mut out, "VALUES", ty, &v);
        }
        Precision::F64 => array(&mut out, "VALUES", ty, ramp.values()),
    }
    let _ = write!(
        out,
        "\n/// The exported ramp.\npub static RAMP: RampTables<'static, {ty}> = RampTables {{ pressures: &PRESSURES, values: &VALUES }};\n\n/// C entry point: writes the 22 outputs at `p_bar` (clamped to the grid) to `out`; returns 0 on\n/// success, 1 non-finite pressure, 4 bad tables, 5 null pointer.\n///\n/// # Safety\n/// `out` must point to 22 writable `{ty}`.\n#[no_mangle]\npub unsafe extern \"C\" fn {}(p_bar: {ty}, out: *mut {ty}) -> i32 {{\n    if out.is_null() {{\n        return 5;\n    }}\n    let mut values = [0.0 as {ty}; 22];\n    match evaluate_ramp(&RAMP, p_bar, &mut values) {{\n        Ok(()) => {{\n            let mut i = 0;\n            while i < 22 {{\n                *out.add(i) = values[i];\n                i += 1;\n            }}\n            0\n        }}\n        Err(e) => e.code(),\n    }}\n}}\n",
        ramp_c_symbol(p)
    );
    Ok(out)
}

/// The domain lines of an exported ramp's header: the pressure grid (queries outside it are
/// clamped to its ends) and, for a design or material outside the training domain, which
/// inputs and that the whole ramp is extrapolated.
pub fn ramp_domain_lines(s: &Surrogate, q: &Query) -> Vec<String> {
    let (p0, p1) = (s.pressures[0], s.pressures[s.pressures.len() - 1]);
    let mut lines = vec![format!(
        "Pressure grid {p0} .. {p1} bar: a pressure outside it is clamped to the nearer end (the values there are returned)."
    )];
    let outside = s.domain_violations(q);
    if outside.is_empty() {
        lines.push("Design and material inside the training domain.".into());
    } else {
        let listed: Vec<String> = outside.iter().map(|v| v.to_string()).collect();
        lines.push(format!(
            "OUTSIDE THE TRAINING DOMAIN, every value of this ramp is extrapolated: {}.",
            listed.join("; ")
        ));
    }
    lines
}

/// C header declaring the entry point of [`ramp_rust_source`], with the ramp's domain:
/// `SURROGATE_RAMP_IN_DOMAIN` (1 or 0), the pressure grid's ends
/// (`SURROGATE_RAMP_P_MIN_BAR`, `SURROGATE_RAMP_P_MAX_BAR`) and the lines of
/// [`ramp_domain_lines`].
pub fn ramp_c_header(s: &Surrogate, p: Precision, checksum: &str, q: &Query) -> String {
    let ty = p.c_ty();
    let domain: String = ramp_domain_lines(s, q)
        .iter()
        .map(|l| format!(" * {l}\n"))
        .collect();
    let mut out = format!(
        "/* Pressure ramp exported by `surrogate export --ramp` (model {checksum}):\n * N = {}, T = {} mm, Ogden mu1 = {} MPa, alpha1 = {}, mu2 = {} MPa, alpha2 = {}.\n{domain} */\n#ifndef SURROGATE_RAMP_H\n#define SURROGATE_RAMP_H\n#include <stdint.h>\n#ifdef __cplusplus\nextern \"C\" {{\n#endif\n\n#define SURROGATE_N_OUTPUTS 22\n#define SURROGATE_RAMP_IN_DOMAIN {}\n#define SURROGATE_RAMP_P_MIN_BAR {:?}\n#define SURROGATE_RAMP_P_MAX_BAR {:?}\n",
        q.n,
        q.t_mm,
        q.material.mu1_mpa,
        q.material.alpha1,
        q.material.mu2_mpa,
        q.material.alpha2,
        i32::from(s.domain_violations(q).is_empty()),
        s.pressures[0],
        s.pressures[s.pressures.len() - 1]
    );
    model_form_c(s, &mut out);
    c_output_order(&mut out);
    let _ = write!(
        out,
        " * Returns 0 on success, 1 non-finite pressure, 4 bad tables, 5 null pointer. */\nint32_t {}({ty} p_bar, {ty} *out);\n\n#ifdef __cplusplus\n}}\n#endif\n#endif /* SURROGATE_RAMP_H */\n",
        ramp_c_symbol(p)
    );
    out
}
