//! Atomic file writes: a reader never sees a half-written file.
//!
//! Every file the library and the command-line tool write (snapshot case files, plans, model
//! files, tables, VTK output) goes through [`write_atomic`].

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically: a hidden temporary file `.{name}.{pid}-{k}.tmp` in
/// the same directory (`k` counts this process's writes, so that threads writing the same
/// file never share a temporary), `fsync`, rename over
/// `path`, `fsync` of the directory (so the rename itself is durable). An existing file is
/// replaced; the directory must exist; the last rename wins.
///
/// A temporary file left by a killed process keeps that name (a `.`-prefixed `.tmp`), so
/// whoever owns the directory can recognise and remove it (the snapshot store does on resume).
///
/// # Errors
/// The I/O error of creating, writing, syncing or renaming the temporary file (which is then
/// removed).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    static WRITES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let pid = std::process::id();
    let tmp = dir.join(format!(".{name}.{pid}-{k}.tmp"));
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    });
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    // make the rename itself durable
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
