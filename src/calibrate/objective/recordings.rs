//! The recordings a calibration reads, and the files they come from.

use crate::calibrate::experiments::{self, BendingRecord, ForceRecord, MarkerRecord};
use crate::calibrate::inputs::InputFile;
use crate::calibrate::CalibrateError;

/// The recordings a calibration reads: bending (required), blocked force and markers
/// (optional), with the names of their sources for messages and the record of each file read.
#[derive(Clone, Debug, Default)]
pub struct Recordings {
    /// Bending rows.
    pub bending: Vec<BendingRecord>,
    /// Blocked-force rows.
    pub force: Vec<ForceRecord>,
    /// Marker rows.
    pub markers: Vec<MarkerRecord>,
    /// Source of the bending rows.
    pub bending_source: String,
    /// Source of the force rows.
    pub force_source: String,
    /// Source of the marker rows.
    pub markers_source: String,
    /// The files the rows were read from (path, checksum, rows, default or named); empty for
    /// recordings made in memory.
    pub files: Vec<InputFile>,
}

impl Recordings {
    /// The shipped experiments (bending and blocked force, 27 configurations each), as built
    /// into the program; both files are listed as defaults.
    ///
    /// # Errors
    /// Never for the shipped files (tested).
    pub fn shipped() -> Result<Self, CalibrateError> {
        let (b, f) = experiments::shipped_files()?;
        Ok(Recordings {
            bending_source: b.file.path.clone(),
            force_source: f.file.path.clone(),
            bending: b.rows,
            force: f.rows,
            markers: Vec::new(),
            markers_source: String::new(),
            files: vec![b.file, f.file],
        })
    }

    /// Exactly the files given: bending (required), blocked force and markers where given;
    /// nothing else is read.
    ///
    /// # Errors
    /// Any file that does not read ([`experiments`]).
    pub fn read_files(
        bending: &std::path::Path,
        force: Option<&std::path::Path>,
        markers: Option<&std::path::Path>,
    ) -> Result<Self, CalibrateError> {
        use experiments::{load_bending, load_force, load_markers};
        let b = load_bending(bending)?;
        let mut rec = Recordings {
            bending_source: b.file.path.clone(),
            bending: b.rows,
            files: vec![b.file],
            ..Recordings::default()
        };
        if let Some(p) = force {
            let f = load_force(p)?;
            rec.force_source = f.file.path.clone();
            rec.force = f.rows;
            rec.files.push(f.file);
        }
        if let Some(p) = markers {
            let m = load_markers(p)?;
            rec.markers_source = m.file.path.clone();
            rec.markers = m.rows;
            rec.files.push(m.file);
        }
        Ok(rec)
    }

    /// The recordings of a directory laid out like `training_data/` (a twin's output, say):
    /// [`experiments::BENDING_FILE`] (required), and [`experiments::FORCE_FILE`] and
    /// [`experiments::MARKERS_FILE`] where they exist.
    ///
    /// # Errors
    /// A missing bending file; any file that does not read ([`experiments`]).
    pub fn read_dir(dir: &std::path::Path) -> Result<Self, CalibrateError> {
        use experiments::{BENDING_FILE, FORCE_FILE, MARKERS_FILE};
        let (b, f, m) = (
            dir.join(BENDING_FILE),
            dir.join(FORCE_FILE),
            dir.join(MARKERS_FILE),
        );
        Self::read_files(
            &b,
            f.exists().then_some(f.as_path()),
            m.exists().then_some(m.as_path()),
        )
    }

    /// The same recordings with every file marked as a documented default (read without the
    /// user naming it).
    pub fn as_defaults(mut self) -> Self {
        for f in &mut self.files {
            f.default = true;
        }
        self
    }
}
