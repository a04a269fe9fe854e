//! Input: bytes and a target path. Output: the file, written whole or not
//! at all: a temporary file in the target directory, then a rename.

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically, creating parent directories. On
/// any error no partial file is left behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}

/// A file being written: a temporary file in the target directory that
/// becomes `path` only on [`AtomicFile::commit`]. Dropped uncommitted, it
/// vanishes.
pub struct AtomicFile {
    tmp: tempfile::NamedTempFile,
    path: std::path::PathBuf,
    /// Bytes written so far.
    written: u64,
    /// Bytes already handed to the disk (see [`start_writeback`]).
    flushed: u64,
}

impl AtomicFile {
    /// Starts writing `path` (parent directories are created).
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(dir)?;
        Ok(AtomicFile {
            tmp: tempfile::NamedTempFile::new_in(dir)?,
            path: path.to_path_buf(),
            written: 0,
            flushed: 0,
        })
    }

    /// Flushes and renames the file into place, readable by others like a
    /// file the user created (temporary files start owner-only).
    pub fn commit(mut self) -> std::io::Result<()> {
        self.tmp.flush()?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            self.tmp
                .as_file()
                .set_permissions(std::fs::Permissions::from_mode(0o644))?;
        }
        self.tmp.as_file().sync_all()?;
        self.tmp.persist(&self.path).map_err(|e| e.error)?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.tmp.write(buf)?;
        self.written += n as u64;
        if self.written - self.flushed >= WRITEBACK_STEP {
            start_writeback(
                self.tmp.as_file(),
                self.flushed,
                self.written - self.flushed,
            );
            self.flushed = self.written;
        }
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.tmp.flush()
    }
}

/// Bytes after which the written part is handed to the disk.
const WRITEBACK_STEP: u64 = 8 << 20;

/// Starts writing `len` bytes at `offset` to the disk without waiting
/// (Linux `sync_file_range`), so the final `fsync` of a large output finds
/// little left to do. A hint: errors are ignored (the `fsync` reports them).
#[cfg(target_os = "linux")]
fn start_writeback(file: &std::fs::File, offset: u64, len: u64) {
    use std::os::fd::AsRawFd;
    // SAFETY: a plain system call on an open descriptor; no memory is passed.
    unsafe {
        libc::sync_file_range(
            file.as_raw_fd(),
            offset as libc::off64_t,
            len as libc::off64_t,
            libc::SYNC_FILE_RANGE_WRITE,
        );
    }
}

#[cfg(not(target_os = "linux"))]
fn start_writeback(_: &std::fs::File, _: u64, _: u64) {}
