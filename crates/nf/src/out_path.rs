//! An output path checked before any work: a run or a fit that ends on a path it cannot write
//! loses its result.

/// Why `path` cannot be written, where that shows before writing: it names a folder, or its
/// folder does not exist or is a file. `None` where it may be written (permissions show only
/// at the write).
pub fn unwritable(path: &str) -> Option<String> {
    let p = std::path::Path::new(path);
    if p.is_dir() {
        return Some("it is a folder".into());
    }
    match p.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) if dir.exists() && !dir.is_dir() => Some(format!("{} is a file, not a folder", dir.display())),
        Some(dir) if !dir.is_dir() => Some(format!("the folder {} does not exist", dir.display())),
        _ => None,
    }
}
