//! How a diagnosis is set up: the surrogate the calibration and the predictions go through,
//! the FE sensitivities of the Name and Model stages, the surrogate on another mesh whose
//! difference is the model's own mesh error ([`super::mesh_error`]), and the model's
//! approximation error against a finer discretisation ([`super::approx_error`]).
//!
//! Real recordings and the blind study on twins choose the same four things with different
//! defaults: [`DiagnosisSetup::recordings`] and [`DiagnosisSetup::blind_study`]. A choice is
//! changed field by field (the `from_flag` constructors read a command-line value), and
//! [`DiagnosisSetup::resolve`] checks the choices against the use and turns the repository's
//! defaults into paths under its root:
//!
//! ```
//! use std::path::Path;
//! use surrogate::diagnose::setup::{ApproximationSource, DiagnosisSetup};
//!
//! let root = Path::new("/repo");
//! let study = DiagnosisSetup::blind_study().resolve(root).unwrap();
//! assert_eq!(study.model.path, root.join("models/as_modelled/actuator_coarse.json"));
//! assert!(study.model.default);
//!
//! let mut recordings = DiagnosisSetup::recordings();
//! recordings.approximation_error = ApproximationSource::from_flag("nulls");
//! let e = recordings.resolve(root).unwrap_err().to_string();
//! assert!(e.starts_with("--approximation-error = nulls: expected "), "{e}");
//! ```
use std::path::{Path, PathBuf};

use super::DiagnoseError;

/// The shipped surrogate on the standard mesh, in the repository.
pub const SHIPPED_MODEL: &str = "models/actuator.json";
/// The shipped surrogate on the coarse mesh, in the repository.
pub const SHIPPED_COARSE_MODEL: &str = "models/actuator_coarse.json";
/// The shipped coarse surrogate's approximation error against FE on 4 mm elements, a
/// discretisation neither the surrogate nor a twin (5 mm) uses, in the repository
/// (`surrogate approximation-error --model models/actuator_coarse.json --mesh coarse
/// --element-size 4 --materials 4`; the file records that model's checksum).
pub const SHIPPED_APPROXIMATION_ERROR: &str =
    "data/approximation_error/identified_coarse_vs_4mm.json";
/// The committed FE sensitivities of the effect library at the material calibrated through
/// the shipped model to the shipped experiments, on the shipped models' geometry and force
/// rig, coarse mesh, in the repository (`data/README.md` gives the command).
pub const SHIPPED_SENSITIVITIES: &str = "data/sensitivities/identified_calibrated_coarse.json";

/// The coarse-mesh surrogate on the geometry as modelled (`--geometry as_modelled`), in the
/// repository: the model the blind study scores, because its twins are built on that
/// geometry.
pub const AS_MODELLED_COARSE_MODEL: &str = "models/as_modelled/actuator_coarse.json";
/// The multi-fidelity surrogate on the geometry as modelled, in the repository.
pub const AS_MODELLED_MODEL: &str = "models/as_modelled/actuator.json";
/// The approximation error of [`AS_MODELLED_COARSE_MODEL`] against FE on 4 mm elements
/// (`surrogate approximation-error --model models/as_modelled/actuator_coarse.json --mesh
/// coarse --element-size 4 --materials 4`; the file records that model's checksum).
pub const AS_MODELLED_APPROXIMATION_ERROR: &str = "data/approximation_error/coarse_vs_4mm.json";
/// The FE sensitivities at the material calibrated through [`AS_MODELLED_MODEL`], on the
/// geometry as modelled, coarse mesh.
pub const AS_MODELLED_SENSITIVITIES: &str = "data/sensitivities/calibrated_coarse.json";

/// What a setup diagnoses: its defaults and the choices it allows depend on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagnosisUse {
    /// Real recordings (`surrogate diagnose`).
    Recordings,
    /// The blind study on twins ([`super::study`], `surrogate twin-study`).
    BlindStudy,
}

/// A file a setup names: a documented default of the repository (relative to its root) or
/// a path as given (relative to the working directory).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SetupFile {
    /// A default, relative to the repository's root.
    Repository(&'static str),
    /// As given.
    Given(PathBuf),
}

impl SetupFile {
    /// The file resolved: a default under `root`, a given path as given.
    pub fn resolve(&self, root: &Path) -> ResolvedFile {
        match self {
            SetupFile::Repository(relative) => ResolvedFile {
                path: root.join(relative),
                default: true,
            },
            SetupFile::Given(p) => ResolvedFile {
                path: p.clone(),
                default: false,
            },
        }
    }
}

/// A file of a resolved setup: its path, and whether it is a default (the reports say so).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResolvedFile {
    /// Where it is.
    pub path: PathBuf,
    /// Whether it is a default rather than a file given.
    pub default: bool,
}

/// The FE sensitivities of the Name and Model stages (`F`: the file, named or resolved).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Sensitivities<F = SetupFile> {
    /// None: the Name and Model stages are not run (real recordings only).
    None,
    /// The sweep at the material just calibrated, run by FE (real recordings only).
    Calibrated,
    /// A sweep's file, as `validate --sensitivities all` writes it.
    File(F),
}

impl Sensitivities {
    /// A command-line value: `none`, `calibrated` or a file.
    pub fn from_flag(value: &str) -> Self {
        match value {
            "none" => Sensitivities::None,
            "calibrated" => Sensitivities::Calibrated,
            file => Sensitivities::File(SetupFile::Given(file.into())),
        }
    }
}

/// The surrogate on another mesh whose difference to the model is tested as the model's own
/// mesh error.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MeshReference {
    /// Not tested.
    None,
    /// The other shipped model ([`other_shipped_model`]); none for another model.
    Auto,
    /// A surrogate model file.
    File(SetupFile),
}

impl MeshReference {
    /// A command-line value: `none`, `auto` or a file.
    pub fn from_flag(value: &str) -> Self {
        match value {
            "none" => MeshReference::None,
            "auto" => MeshReference::Auto,
            file => MeshReference::File(SetupFile::Given(file.into())),
        }
    }
}

/// Where the model's approximation error comes from (`F`: the file, named or resolved).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ApproximationSource<F = SetupFile> {
    /// No approximation error: the recordings' σ alone weigh the residual.
    None,
    /// Sampled from the null twins' noise-free FE (the blind study only,
    /// [`super::study::null_approximation_error`]).
    Nulls,
    /// A file of [`super::approx_error::ApproximationError::write`].
    File(F),
}

impl ApproximationSource {
    /// A command-line value: `none`, `nulls` or a file.
    pub fn from_flag(value: &str) -> Self {
        match value {
            "none" => ApproximationSource::None,
            "nulls" => ApproximationSource::Nulls,
            file => ApproximationSource::File(SetupFile::Given(file.into())),
        }
    }
}

/// How a diagnosis is set up, before its defaults are found in the repository.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DiagnosisSetup {
    /// What is diagnosed.
    pub used_for: DiagnosisUse,
    /// The diagnosing surrogate.
    pub model: SetupFile,
    /// The FE sensitivities.
    pub sensitivities: Sensitivities,
    /// The mesh reference.
    pub mesh_reference: MeshReference,
    /// The approximation error.
    pub approximation_error: ApproximationSource,
}

impl DiagnosisSetup {
    /// The setup of real recordings (`surrogate diagnose`): the shipped coarse-mesh model, the
    /// committed sweep at the shipped experiments' calibrated material
    /// ([`SHIPPED_SENSITIVITIES`]), no mesh reference (the approximation error holds the
    /// model's mesh error), the shipped approximation error ([`SHIPPED_APPROXIMATION_ERROR`]).
    pub fn recordings() -> Self {
        DiagnosisSetup {
            used_for: DiagnosisUse::Recordings,
            model: SetupFile::Repository(SHIPPED_COARSE_MODEL),
            sensitivities: Sensitivities::File(SetupFile::Repository(SHIPPED_SENSITIVITIES)),
            mesh_reference: MeshReference::None,
            approximation_error: ApproximationSource::File(SetupFile::Repository(
                SHIPPED_APPROXIMATION_ERROR,
            )),
        }
    }

    /// The setup of the blind study (`surrogate twin-study`), whose twins are built on the
    /// geometry as modelled: the coarse-mesh model on that geometry
    /// ([`AS_MODELLED_COARSE_MODEL`]), the committed sweep at Ogden 002
    /// (`data/sensitivities/ogden002_coarse.json`), around which the twins' materials are
    /// drawn, no mesh reference, and that model's approximation error
    /// ([`AS_MODELLED_APPROXIMATION_ERROR`]). `--approximation-error nulls` samples the error
    /// from the null twins instead (the study's setup until 2026-12-06).
    pub fn blind_study() -> Self {
        DiagnosisSetup {
            used_for: DiagnosisUse::BlindStudy,
            model: SetupFile::Repository(AS_MODELLED_COARSE_MODEL),
            sensitivities: Sensitivities::File(SetupFile::Repository(
                "data/sensitivities/ogden002_coarse.json",
            )),
            mesh_reference: MeshReference::None,
            approximation_error: ApproximationSource::File(SetupFile::Repository(
                AS_MODELLED_APPROXIMATION_ERROR,
            )),
        }
    }

    /// The setup with its defaults as paths under the repository's `root`, `auto` replaced by
    /// the mesh reference it stands for (looked for on disk), checked against its use.
    ///
    /// # Errors
    /// A choice its use does not allow, naming the flag, the value and what is expected:
    /// `--approximation-error nulls` for real recordings (there are no null twins);
    /// `--sensitivities none` or `calibrated` for the blind study (every twin is named with
    /// a committed sweep).
    pub fn resolve(&self, root: &Path) -> Result<ResolvedSetup, DiagnoseError> {
        let model = self.model.resolve(root);
        let sensitivities = match (&self.sensitivities, self.used_for) {
            (Sensitivities::File(f), _) => Sensitivities::File(f.resolve(root)),
            (Sensitivities::None, DiagnosisUse::Recordings) => Sensitivities::None,
            (Sensitivities::Calibrated, DiagnosisUse::Recordings) => Sensitivities::Calibrated,
            (s, DiagnosisUse::BlindStudy) => {
                return Err(DiagnoseError::input(
                    "--sensitivities",
                    if *s == Sensitivities::None {
                        "none"
                    } else {
                        "calibrated"
                    },
                    "a file of FE sensitivities (`none` and `calibrated` are for real \
                     recordings, `diagnose`: the blind study names every twin with a \
                     committed sweep)",
                ))
            }
        };
        let mesh_reference = match &self.mesh_reference {
            MeshReference::None => None,
            MeshReference::Auto => other_shipped_model(&model.path).map(|path| ResolvedFile {
                path,
                default: true,
            }),
            MeshReference::File(f) => Some(f.resolve(root)),
        };
        let approximation_error = match (&self.approximation_error, self.used_for) {
            (ApproximationSource::None, _) => ApproximationSource::None,
            (ApproximationSource::File(f), _) => ApproximationSource::File(f.resolve(root)),
            (ApproximationSource::Nulls, DiagnosisUse::BlindStudy) => ApproximationSource::Nulls,
            (ApproximationSource::Nulls, DiagnosisUse::Recordings) => {
                return Err(DiagnoseError::input(
                    "--approximation-error",
                    "nulls",
                    "none or an approximation error file (`nulls`, sampled from the null \
                     twins, is for the blind study, `twin-study`)",
                ))
            }
        };
        Ok(ResolvedSetup {
            used_for: self.used_for,
            model,
            sensitivities,
            mesh_reference,
            approximation_error,
        })
    }
}

/// A setup whose files are paths: what a diagnosis reads.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResolvedSetup {
    /// What is diagnosed.
    pub used_for: DiagnosisUse,
    /// The diagnosing surrogate.
    pub model: ResolvedFile,
    /// The FE sensitivities (`none` and `calibrated` for real recordings only).
    pub sensitivities: Sensitivities<ResolvedFile>,
    /// The mesh reference, if any (`auto` resolved: a default).
    pub mesh_reference: Option<ResolvedFile>,
    /// The approximation error (`nulls` for the blind study only).
    pub approximation_error: ApproximationSource<ResolvedFile>,
}

/// The other shipped model beside `model` when `model` is one of [`SHIPPED_MODEL`]
/// (standard mesh) and [`SHIPPED_COARSE_MODEL`] (coarse mesh) by its file name and the other
/// exists in its directory; none otherwise.
pub fn other_shipped_model(model: &Path) -> Option<PathBuf> {
    fn name(p: &'static str) -> Option<&'static std::ffi::OsStr> {
        Path::new(p).file_name()
    }
    let (standard, coarse) = (name(SHIPPED_MODEL)?, name(SHIPPED_COARSE_MODEL)?);
    let other = match model.file_name()? {
        f if f == standard => coarse,
        f if f == coarse => standard,
        _ => return None,
    };
    Some(model.with_file_name(other)).filter(|p| p.exists())
}
