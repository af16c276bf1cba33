//! The unit tests of `src/io.rs`.

use surrogate::io::write_atomic;

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
