//! Input: bytes and a target path. Output: the file, written whole or not
//! at all: a temporary file in the target directory, then a rename.
//!
//! On Linux the bytes go to the disk straight from an aligned buffer
//! (`O_DIRECT`) where the file system allows it: a large output then costs
//! no page-cache copy and no write-back work on the CPUs that slice, and
//! the final `fsync` finds the data already on the disk. Elsewhere (or
//! when the file system refuses direct writes) the writes are buffered,
//! and write-back is started every few megabytes so that the `fsync`
//! does not wait for all of it at the end.

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
    /// The bytes not yet written, while writes are direct.
    direct: Option<direct::Chunk>,
}

impl AtomicFile {
    /// Starts writing `path` (parent directories are created).
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(dir)?;
        let tmp = tempfile::NamedTempFile::new_in(dir)?;
        let direct = direct::start(tmp.as_file());
        Ok(AtomicFile {
            tmp,
            path: path.to_path_buf(),
            written: 0,
            flushed: 0,
            direct,
        })
    }

    /// Flushes and renames the file into place, readable by others like a
    /// file the user created (temporary files start owner-only).
    pub fn commit(mut self) -> std::io::Result<()> {
        if let Some(mut chunk) = self.direct.take() {
            chunk.finish(self.tmp.as_file(), self.written)?;
        }
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
        if let Some(chunk) = &mut self.direct {
            let n = chunk.push(buf);
            self.written += n as u64;
            if chunk.is_full() {
                let kept = chunk.write_full(self.tmp.as_file(), self.written)?;
                if !kept {
                    // The file system refused: buffered from here on.
                    self.direct = None;
                    self.flushed = self.written;
                }
            }
            return Ok(n);
        }
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
        // Direct writes keep their partial chunk until it fills or the
        // file is committed (a direct write must be whole blocks).
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

#[cfg(target_os = "linux")]
mod direct {
    //! Direct writes: whole chunks of whole blocks from an aligned buffer,
    //! each at its offset; the tail (less than a block) buffered at the end.

    use std::fs::File;
    use std::os::fd::AsRawFd;
    use std::os::unix::fs::FileExt;

    /// Alignment of buffer, offsets and lengths: 4096 covers disks with
    /// 512- and 4096-byte blocks.
    const ALIGN: usize = 4096;
    /// Bytes per direct write.
    const CHUNK: usize = 4 << 20;

    /// A buffer of `CHUNK` bytes at an `ALIGN`ed address, filling up.
    pub(super) struct Chunk {
        /// `CHUNK + ALIGN` bytes, of which `start..start + CHUNK` are used.
        bytes: Vec<u8>,
        start: usize,
        len: usize,
    }

    /// Turns on direct writes for `file`, or `None` when the file system
    /// does not take them.
    pub(super) fn start(file: &File) -> Option<Chunk> {
        set_direct(file, true).then(|| {
            let bytes = vec![0u8; CHUNK + ALIGN];
            let start = bytes.as_ptr().align_offset(ALIGN);
            Chunk {
                bytes,
                start,
                len: 0,
            }
        })
    }

    /// Sets or clears `O_DIRECT`; whether it is now as asked.
    fn set_direct(file: &File, on: bool) -> bool {
        let fd = file.as_raw_fd();
        // SAFETY: plain system calls on an open descriptor; no memory is
        // passed.
        unsafe {
            let flags = libc::fcntl(fd, libc::F_GETFL);
            if flags < 0 {
                return false;
            }
            let flags = if on {
                flags | libc::O_DIRECT
            } else {
                flags & !libc::O_DIRECT
            };
            libc::fcntl(fd, libc::F_SETFL, flags) == 0
        }
    }

    impl Chunk {
        fn used(&self) -> &[u8] {
            &self.bytes[self.start..self.start + self.len]
        }

        /// Takes as much of `buf` as fits; how much.
        pub(super) fn push(&mut self, buf: &[u8]) -> usize {
            let n = (CHUNK - self.len).min(buf.len());
            let at = self.start + self.len;
            self.bytes[at..at + n].copy_from_slice(&buf[..n]);
            self.len += n;
            n
        }

        pub(super) fn is_full(&self) -> bool {
            self.len == CHUNK
        }

        /// Writes the full chunk, which ends at `end`. `Ok(false)` when the
        /// file system refused the direct write: the chunk was then
        /// written buffered, direct writes are off, and the file position
        /// is at `end`.
        pub(super) fn write_full(&mut self, file: &File, end: u64) -> std::io::Result<bool> {
            let at = end - self.len as u64;
            let kept = match file.write_all_at(self.used(), at) {
                Ok(()) => true,
                Err(e) if e.raw_os_error() == Some(libc::EINVAL) => {
                    self.buffered(file, at)?;
                    false
                }
                Err(e) => return Err(e),
            };
            self.len = 0;
            Ok(kept)
        }

        /// Writes what is left (the file ends at `end`): whole blocks
        /// directly, the last partial block buffered.
        pub(super) fn finish(&mut self, file: &File, end: u64) -> std::io::Result<()> {
            let at = end - self.len as u64;
            let whole = self.len / ALIGN * ALIGN;
            let direct = &self.bytes[self.start..self.start + whole];
            let done = whole == 0 || file.write_all_at(direct, at).is_ok();
            let from = if done { whole } else { 0 };
            let tail = self.start + from..self.start + self.len;
            set_direct(file, false);
            file.write_all_at(&self.bytes[tail], at + from as u64)?;
            self.len = 0;
            Ok(())
        }

        /// Moves the buffer one byte off its alignment (tests the refusal).
        #[cfg(test)]
        pub(super) fn misalign(&mut self) {
            self.start += 1;
        }

        /// Writes the chunk at `at` without direct writes, and leaves the
        /// file position after it.
        fn buffered(&self, file: &File, at: u64) -> std::io::Result<()> {
            use std::io::{Seek, SeekFrom};
            if !set_direct(file, false) {
                return Err(std::io::Error::other("cannot turn off direct writes"));
            }
            file.write_all_at(self.used(), at)?;
            let mut f = file;
            f.seek(SeekFrom::Start(at + self.len as u64))?;
            Ok(())
        }
    }
}

#[cfg(not(target_os = "linux"))]
mod direct {
    //! No direct writes: every write is buffered.

    /// Never made: [`start`] always returns `None`.
    pub(super) enum Chunk {}

    pub(super) fn start(_: &std::fs::File) -> Option<Chunk> {
        None
    }

    impl Chunk {
        pub(super) fn push(&mut self, _: &[u8]) -> usize {
            match *self {}
        }
        pub(super) fn is_full(&self) -> bool {
            match *self {}
        }
        pub(super) fn write_full(&mut self, _: &std::fs::File, _: u64) -> std::io::Result<bool> {
            match *self {}
        }
        pub(super) fn finish(&mut self, _: &std::fs::File, _: u64) -> std::io::Result<()> {
            match *self {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sizes around the block and chunk boundaries, written in uneven
    /// pieces: the file holds exactly the bytes, with direct writes (where
    /// the file system takes them) or without.
    #[test]
    fn every_size_arrives_whole() {
        let dir = tempfile::tempdir().unwrap();
        let chunk = 4 << 20;
        for (i, size) in [
            0,
            1,
            4095,
            4096,
            4097,
            chunk - 1,
            chunk,
            chunk + 1,
            2 * chunk + 4099,
        ]
        .into_iter()
        .enumerate()
        {
            let bytes: Vec<u8> = (0..size).map(|k| (k * 7 + k / 4096) as u8).collect();
            let path = dir.path().join(format!("out{i}.bin"));
            let mut f = AtomicFile::create(&path).unwrap();
            let mut rest = &bytes[..];
            let mut piece = 1;
            while !rest.is_empty() {
                let n = piece.min(rest.len());
                f.write_all(&rest[..n]).unwrap();
                rest = &rest[n..];
                piece = piece * 3 + 1000;
            }
            assert!(!path.exists(), "visible before commit");
            f.commit().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), bytes, "size {size}");
        }
    }

    #[test]
    fn a_dropped_file_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.bin");
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(&vec![1u8; 5 << 20]).unwrap();
        drop(f);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// A direct write the file system refuses (here: from a misaligned
    /// buffer, which ext4 and xfs reject) is written buffered instead, and
    /// the writes after it land after it.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_refused_direct_write_is_written_buffered() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.bin");
        let mut f = AtomicFile::create(&path).unwrap();
        if let Some(chunk) = &mut f.direct {
            chunk.misalign();
        }
        let bytes: Vec<u8> = (0..(9 << 20) + 5).map(|k| (k % 251) as u8).collect();
        f.write_all(&bytes).unwrap();
        f.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
    }
}
