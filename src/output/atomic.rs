//! Input: bytes and a target path. Output: the file, written whole or not
//! at all: a temporary file in the target directory, then a rename.

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically, creating parent directories. On
/// any error no partial file is left behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::NamedTempFile::new_in(dir)?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}
