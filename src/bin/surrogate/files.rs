//! The files the subcommands share: the model they read, the documented defaults of the
//! repository, and the outputs they write.
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use surrogate::calibrate::inputs::InputFile;
use surrogate::diagnose::setup::ResolvedFile;
use surrogate::fe::mesh::{MeshLevel, MeshOptions};
use surrogate::rom::Surrogate;

/// The repository this program was built from: where its documented defaults (the shipped
/// models, experiments and FE references) are found, from any working directory.
pub fn repository_file(relative: &str) -> PathBuf {
    repository_root().join(relative)
}

/// The repository's root ([`repository_file`]).
pub fn repository_root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The surrogate every command reads without `--model`, in the repository.
pub const DEFAULT_MODEL: &str = surrogate::diagnose::setup::SHIPPED_MODEL;

/// The file of an optional flag: as the user gave it (`false`), or the documented default
/// `relative` of the repository (`true`).
pub fn given_or_default(given: Option<&Path>, relative: &str) -> (PathBuf, bool) {
    match given {
        Some(p) => (p.to_path_buf(), false),
        None => (repository_file(relative), true),
    }
}

/// For a flag whose clap default is the repository's `relative` ([`repository_file`]): when
/// `path` is that file, says so on stderr with its path, and returns whether it is.
pub fn announce_default(flag: &str, path: &Path, relative: &str) -> bool {
    let default = path == repository_file(relative);
    if default {
        eprintln!("--{flag}: reading {} (the default)", path.display());
    }
    default
}

/// [`given_or_default`] for the flag `--flag`, a default said on stderr with its path
/// (`no --model: reading /…/models/actuator.json (the default)`).
pub fn given_or_announced(flag: &str, given: Option<&Path>, relative: &str) -> (PathBuf, bool) {
    let (path, default) = given_or_default(given, relative);
    if default {
        eprintln!("no --{flag}: reading {} (the default)", path.display());
    }
    (path, default)
}

/// A file of a diagnosis setup, a default said on stderr with its path (`no --model: reading
/// /…/models/actuator.json (the default)`).
pub fn announced<'a>(flag: &str, file: &'a ResolvedFile) -> &'a Path {
    if file.default {
        eprintln!("no --{flag}: reading {} (the default)", file.path.display());
    }
    &file.path
}

/// The record of an input file for the reports (path, checksum, named or default).
pub fn input_file(role: &str, path: &Path, default: bool) -> Result<InputFile> {
    let f = InputFile::read(role, path).with_context(|| format!("reading {}", path.display()))?;
    Ok(if default { f.as_default() } else { f })
}

/// The mesh of `--mesh LEVEL [--element-size H] [--wall-elements K]`, validated; a bad value
/// names its flag.
pub fn mesh_options(
    level: &str,
    element_size: Option<f64>,
    wall_elements: Option<usize>,
) -> Result<MeshOptions> {
    let level: MeshLevel = level
        .parse()
        .map_err(|e: String| anyhow::anyhow!("--mesh {level}: {e}"))?;
    let mesh = MeshOptions {
        level,
        element_size,
        wall_elements,
    };
    mesh.validate().map_err(|e| {
        anyhow::anyhow!(
            "--{} {}: expected {}",
            e.field.replace('_', "-"),
            e.value,
            e.expected
        )
    })?;
    Ok(mesh)
}

/// Loads a model file; a missing one says where it was looked for and what to give instead.
pub fn load_model(path: &Path) -> Result<Surrogate> {
    Surrogate::load(path).map_err(|e| {
        if path.exists() {
            anyhow::Error::from(e)
        } else {
            anyhow::anyhow!(
                "{e}; give --model PATH (the shipped models are {} and {})",
                repository_file(DEFAULT_MODEL).display(),
                repository_file(surrogate::diagnose::setup::SHIPPED_COARSE_MODEL).display()
            )
        }
    })
}

/// The mesh reference at `path` ([`surrogate::diagnose::setup::ResolvedSetup::mesh_reference`])
/// and its name for the report.
pub fn load_mesh_reference(path: &Path) -> Result<(Surrogate, String)> {
    let m = load_model(path).with_context(|| {
        format!(
            "--mesh-reference {}: expected auto, none or a surrogate model file",
            path.display()
        )
    })?;
    Ok((m, path.display().to_string()))
}

/// Writes `bytes` to a file atomically ([`surrogate::io::write_atomic`]), creating its
/// directory.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    surrogate::io::write_atomic(path, bytes).with_context(|| format!("writing {}", path.display()))
}

/// A `--material` value with a calibration report (`DIR/report.json`) replaced by its
/// calibrated set at full precision (`surrogate::rom::material_spec`); any other spec as given.
pub fn material_spec(spec: &str) -> Result<String, String> {
    surrogate::rom::material_spec::expand(spec).map_err(|e| e.to_string())
}
