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

#[cfg(test)]
mod tests {
    use super::write_atomic;

    #[test]
    fn replaces_the_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("surrogate_io_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.txt");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["out.txt"]);
        // a missing directory is an error, and leaves nothing behind
        assert!(write_atomic(&dir.join("missing/out.txt"), b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
