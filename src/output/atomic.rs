//! Input: bytes and a target path. Output: the file, written whole or not
//! at all: a temporary file in the target directory, then a rename. A
//! target that exists and is not a regular file (`/dev/null`, a terminal,
//! a named pipe, `/dev/stdout`) is written in place instead: renaming over
//! it would replace a device with a file.
//!
//! On Linux a large output goes to the disk straight from aligned 1 MB
//! buffers (`O_DIRECT`) where the file system allows it, written by a
//! thread of its own while the next buffer fills: it then costs no
//! page-cache copy, no write-back work on the CPUs that slice and no wait
//! for the disk, and the final `fsync` finds the data already there. An
//! output smaller than one buffer is written in one buffered write.
//! Elsewhere (or when the file system refuses direct writes) the writes
//! are buffered, and write-back is started every few megabytes so that
//! the `fsync` does not wait for all of it at the end.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files being written now, in the order they were started:
/// what [`remove_unfinished`] removes.
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every output still being written (the temporary files of
/// uncommitted [`AtomicFile`]s) and returns how many it removed. For a
/// program stopped from outside (Ctrl-C, `SIGTERM`): it calls this and
/// exits, and leaves no unfinished file behind. A file committed at the
/// same moment stays whole: its temporary is already renamed, or the
/// rename fails.
pub fn remove_unfinished() -> usize {
    let paths = std::mem::take(&mut *UNFINISHED.lock().unwrap_or_else(|e| e.into_inner()));
    paths
        .iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// A temporary file's entry in [`UNFINISHED`], removed when it drops
/// (committed or abandoned).
struct Unfinished(PathBuf);

impl Unfinished {
    fn new(path: &Path) -> Self {
        let mut list = UNFINISHED.lock().unwrap_or_else(|e| e.into_inner());
        list.push(path.to_path_buf());
        Unfinished(path.to_path_buf())
    }
}

impl Drop for Unfinished {
    fn drop(&mut self) {
        let mut list = UNFINISHED.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = list.iter().position(|p| *p == self.0) {
            list.swap_remove(i);
        }
    }
}

/// Writes `bytes` to `path` atomically, creating parent directories. On
/// any error no partial file is left behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}

/// The target opened for writing in place when it exists and is not a
/// regular file or a directory (a device, a pipe or a socket; symbolic
/// links followed).
fn special_target(path: &Path) -> std::io::Result<Option<std::fs::File>> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() && !m.is_dir() => {
            std::fs::OpenOptions::new().write(true).open(path).map(Some)
        }
        _ => Ok(None),
    }
}

/// A file being written: a temporary file in the target directory that
/// becomes `path` only on [`AtomicFile::commit`]. Dropped uncommitted, it
/// vanishes. A target that is not a regular file (a device, a pipe) is
/// written in place (see the module documentation).
pub struct AtomicFile(Target);

enum Target {
    Temporary(Box<TempTarget>),
    InPlace(std::fs::File),
}

/// The temporary file and where it goes.
struct TempTarget {
    tmp: tempfile::NamedTempFile,
    path: PathBuf,
    /// Listed until committed or dropped (declared after `tmp`, dropped
    /// after it: listed while the file exists).
    _unfinished: Unfinished,
    /// Bytes written so far.
    written: u64,
    /// Bytes already handed to the disk (see [`start_writeback`]).
    flushed: u64,
    /// The direct writer, when writes are direct.
    direct: Option<direct::Writer>,
}

impl AtomicFile {
    /// Starts writing `path` (parent directories are created).
    pub fn create(path: &Path) -> std::io::Result<Self> {
        if let Some(f) = special_target(path)? {
            return Ok(AtomicFile(Target::InPlace(f)));
        }
        TempTarget::create(path).map(|t| AtomicFile(Target::Temporary(Box::new(t))))
    }

    /// Flushes and renames the file into place, readable by others like a
    /// file the user created (temporary files start owner-only).
    pub fn commit(self) -> std::io::Result<()> {
        match self.0 {
            Target::Temporary(t) => t.commit(),
            Target::InPlace(mut f) => f.flush(),
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.0 {
            Target::Temporary(t) => t.write(buf),
            Target::InPlace(f) => f.write(buf),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.0 {
            Target::Temporary(t) => t.flush(),
            Target::InPlace(f) => f.flush(),
        }
    }
}

impl TempTarget {
    fn create(path: &Path) -> std::io::Result<Self> {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(dir)?;
        // `.NAME.XXXXXX.partial`: a file left by a killed run says what it
        // was. NAME cut to at most 100 bytes: a target name near the file
        // system's limit (255 bytes) must not make the temporary's too long.
        let mut name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let cut = (0..=name.len().min(100))
            .rev()
            .find(|&i| name.is_char_boundary(i))
            .unwrap_or(0);
        name.truncate(cut);
        let tmp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".partial")
            .tempfile_in(dir)?;
        let direct = direct::start(tmp.as_file());
        Ok(TempTarget {
            _unfinished: Unfinished::new(tmp.path()),
            tmp,
            path: path.to_path_buf(),
            written: 0,
            flushed: 0,
            direct,
        })
    }

    fn commit(mut self) -> std::io::Result<()> {
        if let Some(w) = self.direct.take() {
            w.finish()?;
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

impl Write for TempTarget {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if let Some(w) = &mut self.direct {
            let (n, direct) = w.write(buf)?;
            self.written += n as u64;
            if !direct {
                self.direct = None;
                self.flushed = self.written;
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
    //! Direct writes: whole chunks of whole blocks from aligned buffers,
    //! each at its offset, by a writer thread while the next chunk fills;
    //! the tail (less than a block) buffered at the end. Nothing starts
    //! before the first chunk fills: a file smaller than a chunk is one
    //! buffered write. A direct write the file system refuses (`EINVAL`)
    //! turns direct writes off for the file and is made again, buffered.

    use std::fs::File;
    use std::io::Result;
    use std::os::fd::AsRawFd;
    use std::os::unix::fs::FileExt;
    use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
    use std::thread::JoinHandle;

    /// Alignment of buffers, offsets and lengths: 4096 covers disks with
    /// 512- and 4096-byte blocks.
    const ALIGN: usize = 4096;
    /// Bytes per direct write. The buffers are recycled once SPARE + 1
    /// have filled, so their page faults are paid for at most 4 MB: an 11
    /// MB JSON (fuze.obj x 2000 layers) took 3 289 page faults with 4 MB
    /// chunks, 1 576 with these. Wall time, median of 5, one CPU:
    /// fandisk.obj 0.115 -> 0.107 s, torus.STL 0.239 -> 0.220 s, ico4.obj
    /// 0.066 -> 0.058 s, fuze.obj unchanged within noise, a 314 MB output
    /// unchanged.
    pub(super) const CHUNK: usize = 1 << 20;
    /// Chunks besides the one filling: room for bursts of output while the
    /// disk catches up.
    const SPARE: usize = 3;

    /// A buffer of `CHUNK` bytes at an `ALIGN`ed address, filling up.
    pub(super) struct Chunk {
        /// `CHUNK + ALIGN` bytes, of which `start..start + CHUNK` are used.
        bytes: Vec<u8>,
        start: usize,
        len: usize,
    }

    impl Chunk {
        fn new() -> Chunk {
            let bytes = vec![0u8; CHUNK + ALIGN];
            let start = bytes.as_ptr().align_offset(ALIGN);
            Chunk {
                bytes,
                start,
                len: 0,
            }
        }

        fn used(&self) -> &[u8] {
            &self.bytes[self.start..self.start + self.len]
        }
    }

    /// What the writer thread is handed: a chunk and the file offset of
    /// its first byte; `last` for the final, partial one.
    struct Job {
        chunk: Chunk,
        at: u64,
        last: bool,
    }

    /// The filling side: the chunk being filled and, once one chunk has
    /// filled (smaller files are written in one buffered write at the
    /// end), the writer thread with the chunks it hands back.
    pub(super) struct Writer {
        chunk: Chunk,
        /// File offset of `chunk`'s first byte.
        at: u64,
        /// A second descriptor of the file, for the writer thread.
        file: File,
        running: Option<Running>,
        /// Tests: behave as a file system without direct writes.
        #[cfg(test)]
        refuse: bool,
    }

    /// The writer thread and its two channels.
    struct Running {
        jobs: SyncSender<Job>,
        done: Receiver<Result<Chunk>>,
        thread: JoinHandle<()>,
    }

    /// A writer for `file` (nothing is written, and direct writes are not
    /// turned on, before a chunk fills), or `None` without a second
    /// descriptor.
    pub(super) fn start(file: &File) -> Option<Writer> {
        Some(Writer {
            chunk: Chunk::new(),
            at: 0,
            file: file.try_clone().ok()?,
            running: None,
            #[cfg(test)]
            refuse: false,
        })
    }

    /// Turns on direct writes and starts the writer thread; `None` when
    /// the file system does not take direct writes (or no thread starts).
    fn run(file: &File) -> Option<Running> {
        let own = file.try_clone().ok()?;
        if !set_direct(file, true) {
            return None;
        }
        let (jobs, inbox) = sync_channel::<Job>(SPARE);
        let (done_tx, done) = sync_channel::<Result<Chunk>>(SPARE + 1);
        // Chunks to fill while others wait for the disk.
        for _ in 0..SPARE {
            done_tx.send(Ok(Chunk::new())).ok()?;
        }
        let thread = std::thread::Builder::new()
            .name("wmslice-write".into())
            .spawn(move || {
                for job in inbox {
                    let result = write_job(&own, &job).map(|()| job.chunk);
                    let failed = result.is_err();
                    if done_tx.send(result).is_err() || failed {
                        return;
                    }
                }
            });
        let Ok(thread) = thread else {
            set_direct(file, false);
            return None;
        };
        Some(Running { jobs, done, thread })
    }

    /// Writes a job's bytes at its offset: whole blocks directly, the
    /// last job's partial block buffered.
    fn write_job(file: &File, job: &Job) -> Result<()> {
        let bytes = job.chunk.used();
        let whole = if job.last {
            bytes.len() / ALIGN * ALIGN
        } else {
            bytes.len()
        };
        match file.write_all_at(&bytes[..whole], job.at) {
            Err(e) if e.raw_os_error() == Some(libc::EINVAL) => {
                // Refused (alignment, or the file system): buffered from
                // here on, this chunk included.
                if !set_direct(file, false) {
                    return Err(e);
                }
                file.write_all_at(&bytes[..whole], job.at)?;
            }
            other => other?,
        }
        if whole < bytes.len() {
            set_direct(file, false);
            file.write_all_at(&bytes[whole..], job.at + whole as u64)?;
        }
        Ok(())
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

    impl Writer {
        /// Takes as much of `buf` as fits in the chunk (how much); a full
        /// chunk goes to the writer thread and the next one is filled.
        /// With `false` the file system refused direct writes: the bytes
        /// so far are written, buffered, the file position is after them,
        /// and the caller writes the rest itself.
        pub(super) fn write(&mut self, buf: &[u8]) -> Result<(usize, bool)> {
            let c = &mut self.chunk;
            let n = (CHUNK - c.len).min(buf.len());
            let at = c.start + c.len;
            c.bytes[at..at + n].copy_from_slice(&buf[..n]);
            c.len += n;
            if c.len < CHUNK {
                return Ok((n, true));
            }
            #[cfg(test)]
            let refused = self.refuse;
            #[cfg(not(test))]
            let refused = false;
            if self.running.is_none() && !refused {
                self.running = run(&self.file);
            }
            let Some(running) = &self.running else {
                self.buffered()?;
                return Ok((n, false));
            };
            let next = running.done.recv().map_err(|_| stopped())??;
            let full = std::mem::replace(&mut self.chunk, next);
            self.chunk.len = 0;
            let at = self.at;
            self.at += CHUNK as u64;
            running
                .jobs
                .send(Job {
                    chunk: full,
                    at,
                    last: false,
                })
                .map_err(|_| why_stopped(&running.done))?;
            Ok((n, true))
        }

        /// Writes the chunk buffered at its offset and leaves the file
        /// position after it.
        fn buffered(&mut self) -> Result<()> {
            use std::io::{Seek, SeekFrom};
            self.file.write_all_at(self.chunk.used(), self.at)?;
            self.file
                .seek(SeekFrom::Start(self.at + self.chunk.len as u64))?;
            Ok(())
        }

        /// Writes the rest and waits for every write to be done.
        pub(super) fn finish(mut self) -> Result<()> {
            let Some(Running { jobs, done, thread }) = self.running.take() else {
                // Less than a chunk in all: one buffered write.
                return self.buffered();
            };
            jobs.send(Job {
                chunk: self.chunk,
                at: self.at,
                last: true,
            })
            .map_err(|_| why_stopped(&done))?;
            drop(jobs);
            let mut outcome = Ok(());
            for r in done {
                if let Err(e) = r {
                    outcome = Err(e);
                }
            }
            thread.join().map_err(|_| stopped())?;
            outcome
        }

        /// Moves the chunk being filled one byte off its alignment (tests
        /// the refusal of a direct write).
        #[cfg(test)]
        pub(super) fn misalign(&mut self) {
            self.chunk.start += 1;
        }

        /// Behaves as on a file system that refuses to turn direct
        /// writes on.
        #[cfg(test)]
        pub(super) fn refuse_direct(&mut self) {
            self.refuse = true;
        }
    }

    /// The writer thread ended without saying why (it panicked).
    fn stopped() -> std::io::Error {
        std::io::Error::other("the output writer thread stopped")
    }

    /// Why the writer thread ended, once it has (a job could not be sent):
    /// the write error it reported (a full disk, say), queued behind the
    /// chunks it returned.
    fn why_stopped(done: &Receiver<Result<Chunk>>) -> std::io::Error {
        done.iter().find_map(|r| r.err()).unwrap_or_else(stopped)
    }
}

#[cfg(not(target_os = "linux"))]
mod direct {
    //! No direct writes: every write is buffered.

    /// Never made: [`start`] always returns `None`.
    pub(super) enum Writer {}

    pub(super) fn start(_: &std::fs::File) -> Option<Writer> {
        None
    }

    impl Writer {
        pub(super) fn write(&mut self, _: &[u8]) -> std::io::Result<(usize, bool)> {
            match *self {}
        }
        pub(super) fn finish(self) -> std::io::Result<()> {
            match self {}
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
        #[cfg(target_os = "linux")]
        let chunk = direct::CHUNK;
        #[cfg(not(target_os = "linux"))]
        let chunk = 1 << 20;
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

    /// The temporary file is named after the target, cut so that a
    /// target name at the file system's limit (255 bytes, here of 2- and
    /// 4-byte characters) still has a temporary file.
    #[test]
    fn names_at_the_length_limit_are_written() {
        let dir = tempfile::tempdir().unwrap();
        for name in [
            "a".repeat(250) + ".json",
            "é".repeat(125) + ".j",
            "😀".repeat(63),
        ] {
            assert!(name.len() <= 255 && name.len() > 250, "{}", name.len());
            let path = dir.path().join(&name);
            let mut f = AtomicFile::create(&path).unwrap();
            let listed: Vec<String> = std::fs::read_dir(dir.path())
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".partial"))
                .collect();
            assert_eq!(listed.len(), 1, "{listed:?}");
            assert!(listed[0].starts_with(&format!(".{}", &name[..40])));
            f.write_all(b"whole").unwrap();
            f.commit().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), b"whole");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
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
    /// buffer, which ext4 and xfs reject), or a file system that will not
    /// turn direct writes on: the bytes are written buffered instead, and
    /// the writes after them land after them.
    #[cfg(target_os = "linux")]
    #[test]
    fn refused_direct_writes_are_written_buffered() {
        let dir = tempfile::tempdir().unwrap();
        let bytes: Vec<u8> = (0..(9 << 20) + 5).map(|k| (k % 251) as u8).collect();
        for refusal in 0..2 {
            let path = dir.path().join(format!("out{refusal}.bin"));
            let mut f = TempTarget::create(&path).unwrap();
            let w = f.direct.as_mut().unwrap();
            if refusal == 0 {
                w.misalign();
            } else {
                w.refuse_direct();
            }
            f.write_all(&bytes).unwrap();
            if refusal == 1 {
                assert!(f.direct.is_none(), "buffered from the first chunk on");
            }
            f.commit().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), bytes);
        }
    }

    /// A write the disk refuses in the writer thread (here: the file
    /// opened read-only, so every write fails with EBADF, as a full disk
    /// fails with ENOSPC) is reported as that error, not as a thread that
    /// stopped.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_failed_direct_write_reports_its_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("read-only.bin");
        std::fs::write(&path, b"").unwrap();
        let file = std::fs::File::open(&path).unwrap();
        let mut w = direct::start(&file).unwrap();
        let piece = vec![7u8; 1 << 20];
        let err = (0..64)
            .find_map(|_| w.write(&piece).err())
            .expect("a write fails");
        assert_eq!(err.raw_os_error(), Some(libc::EBADF), "{err}");
    }

    /// A named pipe stays a pipe and gets the bytes (renaming over it, as
    /// over `/dev/null`, would put a regular file in its place). The reader
    /// does not block, so a regression fails instead of hanging.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_pipe_is_written_in_place_not_replaced() {
        use std::io::Read;
        use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("pipe");
        let name = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
        // SAFETY: a plain system call on a valid C string.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        let mut reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(&path)
            .unwrap();
        let target = path.clone();
        let writer = std::thread::spawn(move || write_atomic(&target, b"through the pipe"));
        let (mut got, mut buf) = (Vec::new(), [0u8; 64]);
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
        loop {
            let done = writer.is_finished();
            match reader.read(&mut buf) {
                Ok(0) if done => break,
                Ok(n) => got.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
                Err(e) => panic!("{e}"),
            }
            assert!(
                std::time::Instant::now() < deadline,
                "the writer never finished"
            );
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        writer.join().unwrap().unwrap();
        assert_eq!(got, b"through the pipe");
        let kind = std::fs::metadata(&path).unwrap().file_type();
        assert!(kind.is_fifo(), "the pipe was replaced by a file");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "a file was left beside it"
        );
    }
}
