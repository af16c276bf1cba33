//! `surrogate design`: the number of bellows and the wall thickness that reach target outputs,
//! through the surrogate (`surrogate::design::search`): a table with the best wall per N, the
//! pick with its surrogate std and model-form error; `--json` writes the report.
use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{ArgGroup, Args};
use surrogate::design::{
    search, DesignBounds, DesignError, DesignReport, DesignSearch, Output, Target,
};
use surrogate::rom::batch::material_params;
use surrogate::rom::{model_form, Surrogate};

/// `surrogate design`.
#[derive(Debug, Args)]
#[command(group(
    ArgGroup::new("targets")
        .required(true)
        .multiple(true)
        .args(["angle", "force", "tip_uz", "tip_uy"])
))]
pub struct DesignArgs {
    /// Material: a name (ogden_002, ogden_005), `mu1,alpha1,mu2,alpha2` or a calibration
    /// report `DIR/report.json` (its calibrated set). Required: the design depends on it.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::files::material_spec)]
    pub material: String,
    /// Model file (default: the shipped models/actuator.json of the repository the program
    /// was built from, from any working directory).
    #[arg(long, default_value_os_t = crate::files::repository_file(crate::files::DEFAULT_MODEL))]
    pub model: PathBuf,
    /// Target bending angle, DEG@BAR (45@2: 45° at 2 bar); repeatable.
    #[arg(long, value_name = "DEG@BAR", allow_hyphen_values = true)]
    pub angle: Vec<String>,
    /// Target blocked force, N@BAR (1.0@2); repeatable.
    #[arg(long, value_name = "N@BAR", allow_hyphen_values = true)]
    pub force: Vec<String>,
    /// Target tip Uz, MM@BAR; repeatable.
    #[arg(long, value_name = "MM@BAR", allow_hyphen_values = true)]
    pub tip_uz: Vec<String>,
    /// Target tip Uy, MM@BAR (negative: the tip moves down); repeatable.
    #[arg(long, value_name = "MM@BAR", allow_hyphen_values = true)]
    pub tip_uy: Vec<String>,
    /// The scale of an angle residual, degrees.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub angle_tolerance: f64,
    /// The scale of a force residual, N.
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub force_tolerance: f64,
    /// The scale of a tip residual (Uz and Uy), mm.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub tip_tolerance: f64,
    /// `--n` and `--t`.
    #[command(flatten)]
    pub ranges: DesignRanges,
    /// Starting values of T per N.
    #[arg(long, default_value_t = 13)]
    pub starts: usize,
    /// Also write the report as JSON (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// `--n` and `--t`: the numbers of bellows and the wall thicknesses of `surrogate design` and
/// `surrogate maps`, the model's where not given.
#[derive(Debug, Args)]
pub struct DesignRanges {
    /// Numbers of bellows MIN..MAX (or one N) [default: the model's]; only those the model
    /// predicts.
    #[arg(long, value_name = "MIN..MAX")]
    pub n: Option<String>,
    /// Wall thickness MIN..MAX in mm [default: the model's range]; walls that leave no cavity
    /// are left out.
    #[arg(long, value_name = "MIN..MAX")]
    pub t: Option<String>,
}

/// A target as given: its flag and text, for messages.
struct Given {
    flag: &'static str,
    text: String,
    tolerance_flag: &'static str,
}

pub fn run(a: DesignArgs) -> Result<()> {
    crate::files::announce_default("model", &a.model, crate::files::DEFAULT_MODEL);
    let model = crate::files::load_model(&a.model)?;
    let material = material_params(&a.material).context("--material")?;
    let (targets, given) = targets(&a)?;
    let bounds = a.ranges.bounds(&model)?;
    let settings = DesignSearch {
        starts: a.starts,
        ..Default::default()
    };
    let report =
        search(&model, material, &targets, &bounds, &settings).map_err(|e| named(e, &given))?;
    print!("{}", table(&report, &model));
    if let Some(path) = &a.json {
        let text = serde_json::to_string_pretty(&report)?;
        crate::files::write_file(path, text.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// The targets of every target flag, in the order angle, force, tip Uz, tip Uy.
fn targets(a: &DesignArgs) -> Result<(Vec<Target>, Vec<Given>)> {
    let flags: [(&'static str, &[String], Output, f64, &'static str); 4] = [
        (
            "angle",
            &a.angle,
            Output::AngleDeg,
            a.angle_tolerance,
            "angle-tolerance",
        ),
        (
            "force",
            &a.force,
            Output::ForceN,
            a.force_tolerance,
            "force-tolerance",
        ),
        (
            "tip-uz",
            &a.tip_uz,
            Output::TipUzMm,
            a.tip_tolerance,
            "tip-tolerance",
        ),
        (
            "tip-uy",
            &a.tip_uy,
            Output::TipUyMm,
            a.tip_tolerance,
            "tip-tolerance",
        ),
    ];
    let (mut targets, mut given) = (Vec::new(), Vec::new());
    for (flag, values, output, tolerance, tolerance_flag) in flags {
        for text in values {
            let (value, p_bar) = value_at(flag, output, text)?;
            targets.push(Target::new(output, p_bar, value, tolerance));
            given.push(Given {
                flag,
                text: text.clone(),
                tolerance_flag,
            });
        }
    }
    Ok((targets, given))
}

/// `VALUE@PRESSURE` of flag `--flag`.
fn value_at(flag: &str, output: Output, text: &str) -> Result<(f64, f64)> {
    let expected = || {
        format!(
            "--{flag} {text:?}: expected VALUE@PRESSURE, {} at bar (e.g. --{flag} 1.5@2)",
            output.unit()
        )
    };
    let (v, p) = text.split_once('@').with_context(expected)?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .with_context(|| format!("{:?} is not a number", s.trim()))
            .with_context(expected)
    };
    Ok((number(v)?, number(p)?))
}

/// `MIN..MAX`, `MIN..=MAX` or one value, of flag `--flag`.
pub fn range<T: std::str::FromStr + Copy>(flag: &str, text: &str) -> Result<(T, T)> {
    let expected = || {
        format!(
            "--{flag} {text:?}: expected MIN..MAX or one value (e.g. --{flag} {})",
            if flag == "n" { "9..13" } else { "1.4..2.6" }
        )
    };
    let parse = |s: &str| s.trim().parse::<T>().ok().with_context(expected);
    match text.split_once("..") {
        Some((a, b)) => Ok((parse(a)?, parse(b.trim_start_matches('='))?)),
        None => {
            let v = parse(text)?;
            Ok((v, v))
        }
    }
}

impl DesignRanges {
    /// The bounds of `--n` and `--t`, the model's where not given.
    pub fn bounds(&self, model: &Surrogate) -> Result<DesignBounds> {
        let mut b = DesignBounds::of_model(model);
        if let Some(n) = &self.n {
            b.n = range("n", n)?;
        }
        if let Some(t) = &self.t {
            b.t_mm = range("t", t)?;
        }
        Ok(b)
    }
}

/// A library error with the flag it comes from.
fn named(e: DesignError, given: &[Given]) -> anyhow::Error {
    let DesignError::Invalid {
        field,
        value,
        expected,
    } = &e
    else {
        return e.into();
    };
    let flag = |name: &str| -> String {
        match name {
            "bounds.n" => "--n".into(),
            "bounds.t_mm" => "--t".into(),
            "material" => "--material".into(),
            "settings.starts" => "--starts".into(),
            other => other.into(),
        }
    };
    let target = field
        .strip_prefix("targets[")
        .and_then(|s| s.split_once("]."))
        .and_then(|(i, part)| Some((given.get(i.parse::<usize>().ok()?)?, part)));
    match target {
        Some((g, "tolerance")) => {
            anyhow::anyhow!(
                "--{} {value} (for --{} {}): expected {expected}",
                g.tolerance_flag,
                g.flag,
                g.text
            )
        }
        Some((g, part)) => anyhow::anyhow!(
            "--{} {}: {part} = {value}: expected {expected}",
            g.flag,
            g.text
        ),
        None => anyhow::anyhow!("{} {value}: expected {expected}", flag(field)),
    }
}

/// The report as a table: a row per N, the pick and its errors.
fn table(r: &DesignReport, model: &Surrogate) -> String {
    let mut s = String::new();
    let wanted: Vec<String> = r
        .targets
        .iter()
        .map(|t| {
            format!(
                "{} {} {} at {} bar (±{})",
                t.output,
                t.value,
                t.output.unit(),
                t.p_bar,
                t.tolerance
            )
        })
        .collect();
    let m = r.material.as_array();
    let _ = writeln!(s, "targets: {}", wanted.join(", "));
    let _ = writeln!(
        s,
        "material: mu1 {:.4} MPa, alpha1 {:.4}, mu2 {:.4} MPa, alpha2 {:.4}; geometry for buildability: {}; model N {:?}",
        m[0], m[1], m[2], m[3], r.geometry, model.n_allowed
    );
    let _ = write!(s, "\n{:>3} {:>8}", "N", "T (mm)");
    for t in &r.targets {
        let _ = write!(s, " {:>15}", format!("{}@{}", t.output, t.p_bar));
    }
    let _ = writeln!(s, " {:>10}  note", "cost");
    for d in &r.designs {
        let _ = write!(s, "{:>3} ", d.n);
        let Some(c) = &d.best else {
            let _ = writeln!(
                s,
                "{:>8}  no buildable wall in [{:.3}, {:.3}] mm ({} {:.3} mm)",
                "-", d.t_min_mm, d.t_max_mm, d.t_max_limit, d.t_max_mm
            );
            continue;
        };
        let _ = write!(s, "{:>8.3}", c.t_mm);
        for v in &c.predicted {
            let _ = write!(s, " {v:>15.3}");
        }
        let note = c.bound.map_or(String::new(), |b| b.to_string());
        let mark = if d.n == r.pick.n { "  <- pick" } else { "" };
        let _ = writeln!(s, " {:>10.3}  {note}{mark}", c.cost);
    }
    s.push_str(&pick(r));
    s
}

/// The pick with its surrogate std and model-form error per target.
fn pick(r: &DesignReport) -> String {
    let p = &r.pick;
    let mut s = format!(
        "\npick: N = {}, T = {:.3} mm (cost {:.3}{})\n",
        p.n,
        p.t_mm,
        p.cost,
        p.bound.map_or(String::new(), |b| format!(", {b}"))
    );
    for o in &p.outputs {
        let t = &o.target;
        let unit = t.output.unit();
        let form = o
            .model_form
            .map_or("unknown".to_string(), |e| format!("±{e:.3} {unit}"));
        let _ = writeln!(
            s,
            "  {} at {} bar: {:.3} {unit} (target {}); {} ±{:.3} {unit}; {}: {form}",
            t.output,
            t.p_bar,
            o.predicted,
            t.value,
            model_form::STD_LABEL,
            o.surrogate_std,
            model_form::LABEL
        );
    }
    let _ = writeln!(s, "  {}", r.accuracy);
    s
}
