//! Input: one mesh file, a plan of levels, an output path, and optionally a
//! range of the plan (a shard). Output: the JSON document (SPEC 9) written
//! atomically with its certificate (`wmslice::output::certificate`), or a
//! shard's level texts in a temporary file for [`join_shards`] to join in
//! order. `wmslice.batch` sends one call per part (or per shard of a large
//! part) to a dask cluster, or runs them on the local cores.
//!
//! Levels are streamed from the threaded sweep to the output (memory does
//! not grow with the number of levels); with a certificate, each level's
//! exact text is hashed as the exact document's and verified in chunks of
//! levels by one `Verifier` (validation and topology once per part), and a
//! shard's verdict is passed on by its counts (every check is per level).

use crate::errors::{load_error, slice_error, snap_error, InternalError};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sha2::{Digest, Sha256};
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use wmslice::exact::rational::Rat;
use wmslice::layers::{height_range, plan_levels, slice_levels_then, LayerPlan, SweepError};
use wmslice::levelset::LevelSet;
use wmslice::mesh::io::{load_bytes_exact, read_file, LoadError, MeshFormat};
use wmslice::mesh::prepare::{prepare_exact_with, PrepareError, Prepared, Repairs};
use wmslice::output::atomic::AtomicFile;
use wmslice::output::certificate::{
    sha256_hex, Certificate, CertificateError, InputPart, LevelPart, Numeric, Options, ResultPart,
    Tool, Verdict, Verification,
};
use wmslice::output::json::{level_text, Exactness, JsonWriter, LevelText, MeshHeader};
use wmslice::verify::{Checked, Verifier};
use wmslice::Slicer;

/// Exact level texts verified together (bytes): one chunk is one document
/// for the verifier.
const CHUNK: usize = 64 << 20;

/// A writer that hashes and counts what passes through.
struct Hashing<W> {
    inner: W,
    hasher: Sha256,
    bytes: usize,
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.update(&buf[..n]);
        self.bytes += n;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

fn hashing<W>(inner: W) -> Hashing<W> {
    Hashing {
        inner,
        hasher: Sha256::new(),
        bytes: 0,
    }
}

/// What went wrong in a part.
enum PartError {
    Load(String, LoadError),
    Snap(wmslice::mesh::snap::SnapError),
    Slice(wmslice::SliceError),
    Plan(String),
    Io(String, std::io::Error),
    Certificate(CertificateError),
    Threads(String),
    Mismatch(String),
}

impl PartError {
    fn into_py(self, py: Python<'_>) -> PyErr {
        match self {
            PartError::Load(p, e) => load_error(&p, e),
            PartError::Snap(e) => snap_error(py, e),
            PartError::Slice(e) => slice_error(py, e),
            PartError::Plan(e) => PyValueError::new_err(e),
            PartError::Io(p, e) => crate::errors::io_error(&p, &e),
            PartError::Certificate(e) => InternalError::new_err(e.to_string()),
            PartError::Threads(e) => PyOSError::new_err(e),
            PartError::Mismatch(e) => PyValueError::new_err(e),
        }
    }
}

/// A sink failure inside the sweep.
#[derive(Debug)]
struct SinkError(String, std::io::Error);

impl std::fmt::Display for SinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.0, self.1)
    }
}

impl std::error::Error for SinkError {}

/// The plan of a part.
struct PlanArgs {
    height: Option<Rat>,
    first: Option<Rat>,
    last: Option<Rat>,
    explicit: Vec<Rat>,
}

/// The file, read and prepared.
struct Part {
    name: String,
    bytes: Vec<u8>,
    prepared: Prepared,
}

fn read_part(path: &Path, snap: Option<&Rat>, repairs: Repairs) -> Result<Part, PartError> {
    let name = path.display().to_string();
    let bytes = read_file(path).map_err(|source| {
        PartError::Load(
            name.clone(),
            LoadError::Io {
                path: path.to_owned(),
                source,
            },
        )
    })?;
    let hint = path
        .extension()
        .and_then(|e| e.to_str())
        .and_then(MeshFormat::from_extension);
    let (mesh, _, exact) =
        load_bytes_exact(&bytes, hint).map_err(|e| PartError::Load(name.clone(), e))?;
    let prepared = prepare_exact_with(mesh, &exact, snap, repairs).map_err(|e| match e {
        PrepareError::NotDoubles(e) => PartError::Load(name.clone(), e),
        PrepareError::Snap(e) => PartError::Snap(e),
    })?;
    Ok(Part {
        name,
        bytes,
        prepared,
    })
}

/// The JSON header of a prepared part.
fn header_of(p: &Prepared) -> MeshHeader {
    MeshHeader::new(&p.mesh, p.unit.as_ref())
        .with_repairs(p.welded, p.dropped.as_ref().map(Vec::len))
}

fn unit_of(p: &Prepared) -> Rat {
    p.unit
        .clone()
        .unwrap_or_else(|| Rat::from_integer(1.into()))
}

fn plan(part: &Part, args: &PlanArgs) -> Result<Vec<Rat>, PartError> {
    let uniform = args.height.clone().map(|height| LayerPlan {
        height,
        first: args.first.clone(),
        last: args.last.clone(),
    });
    let (lo, hi) = height_range(&part.prepared.mesh, &unit_of(&part.prepared));
    plan_levels(uniform.as_ref(), &args.explicit, (&lo, &hi))
        .map_err(|e| PartError::Plan(e.to_string()))
}

fn exactness(exact: bool) -> Exactness {
    if exact {
        Exactness::WithExact
    } else {
        Exactness::Rounded
    }
}

/// Where a part's levels go.
enum Out {
    /// The whole document, to be committed.
    Document(JsonWriter<Hashing<BufWriter<AtomicFile>>>),
    /// A shard: each level's text with its length, to be committed.
    Shard(Hashing<BufWriter<AtomicFile>>),
}

/// Exact texts collected for the verifier, and the exact document's hash.
struct Checking<'m> {
    verifier: Verifier<'m>,
    header: MeshHeader,
    chunk: Vec<Vec<u8>>,
    chunk_bytes: usize,
    verdict: Verdict,
    /// The exact document, hashed (when the output is not that document).
    exact_doc: Option<JsonWriter<Hashing<std::io::Sink>>>,
    /// A shard's exact texts, when the output is not exact.
    exact_shard: Option<Hashing<BufWriter<AtomicFile>>>,
    parts: Vec<LevelPart>,
}

impl Checking<'_> {
    fn add(&mut self, exact_text: Vec<u8>, part: LevelPart) -> std::io::Result<()> {
        if let Some(d) = &mut self.exact_doc {
            d.level_bytes(&exact_text)?;
        }
        if let Some(s) = &mut self.exact_shard {
            s.write_all(&(exact_text.len() as u64).to_le_bytes())?;
            s.write_all(&exact_text)?;
        }
        self.parts.push(part);
        self.chunk_bytes += exact_text.len();
        self.chunk.push(exact_text);
        if self.chunk_bytes >= CHUNK {
            self.verify_chunk()?;
        }
        Ok(())
    }

    fn verify_chunk(&mut self) -> std::io::Result<()> {
        if self.chunk.is_empty() {
            return Ok(());
        }
        let mut w = JsonWriter::begin(Vec::new(), &self.header, Exactness::WithExact)?;
        for t in self.chunk.drain(..) {
            w.level_bytes(&t)?;
        }
        self.chunk_bytes = 0;
        let doc = String::from_utf8(w.finish()?).map_err(std::io::Error::other)?;
        let v = Verdict::of(&self.verifier, &doc).map_err(std::io::Error::other)?;
        self.verdict = std::mem::take(&mut self.verdict).merge(v);
        Ok(())
    }
}

/// The result of one call, for Python.
struct Done {
    output: String,
    levels: usize,
    bytes: usize,
    sha256: String,
    certificate: Option<String>,
    mesh_sha256: String,
    input_sha256: String,
    exact_shard: Option<String>,
    parts: Option<String>,
    checked: Option<Checked>,
}

/// The options the certificate records (as the command line names them).
fn options(exact: bool, output: &str) -> Options {
    Options {
        format: "json".into(),
        exact,
        output: Some(output.to_owned()),
        side: "below".into(),
        with_ridges: false,
        arrows: false,
    }
}

/// The result part of a certificate for a written file.
fn file_result(sha256: String, bytes: usize, verified_document_sha256: String) -> ResultPart {
    ResultPart {
        destination: "file",
        sha256,
        bytes,
        verified_document_sha256,
    }
}

/// Writes a part's certificate (atomically) and returns its path as shown.
#[allow(clippy::too_many_arguments)]
fn write_certificate(
    path: &Path,
    part: &Part,
    mesh: MeshHeader,
    exact: bool,
    out_name: &str,
    result: ResultPart,
    levels: Vec<LevelPart>,
    verification: Verification,
) -> Result<String, PartError> {
    let cert = Certificate {
        format: "wmslice-certificate",
        version: 1,
        tool: Tool::this(),
        input: InputPart::file(part.name.clone(), &part.bytes),
        mesh,
        numeric: Numeric::new(part.prepared.snap.as_ref(), part.prepared.flips.len()),
        options: options(exact, out_name),
        result,
        levels,
        verification,
    };
    let shown = path.display().to_string();
    wmslice::output::atomic::write_atomic(path, cert.to_json().as_bytes())
        .map_err(|e| PartError::Io(shown.clone(), e))?;
    Ok(shown)
}

#[allow(clippy::too_many_arguments)]
fn run_part(
    path: &Path,
    out: &Path,
    certificate: Option<&Path>,
    snap: Option<&Rat>,
    repairs: Repairs,
    args: &PlanArgs,
    exact: bool,
    threads: usize,
    shard: Option<(usize, usize)>,
    max_levels: Option<usize>,
) -> Result<Result<Done, usize>, PartError> {
    let part = read_part(path, snap, repairs)?;
    let levels = plan(&part, args)?;
    let all = levels.len();
    if shard.is_none() && max_levels.is_some_and(|m| all > m) {
        return Ok(Err(all));
    }
    let (start, stop) = shard.unwrap_or((0, all));
    if start > stop || stop > all {
        return Err(PartError::Plan(format!(
            "shard {start}..{stop} is not within the plan's {all} levels"
        )));
    }
    let mine = &levels[start..stop];
    let mesh = &part.prepared.mesh;
    let unit = unit_of(&part.prepared);
    let grid = part.prepared.unit.as_ref();
    let slicer = Slicer::with_unit(mesh, unit.clone()).map_err(PartError::Slice)?;
    let header = header_of(&part.prepared);
    let ex = exactness(exact);
    let out_name = out.display().to_string();
    let io = |e: std::io::Error| PartError::Io(out_name.clone(), e);
    let file = hashing(BufWriter::new(AtomicFile::create(out).map_err(io)?));
    let mut sink = match shard {
        None => Out::Document(JsonWriter::begin(file, &header, ex).map_err(io)?),
        Some(_) => Out::Shard(file),
    };
    let exact_shard_path = out.with_extension(format!(
        "{}.exact",
        out.extension().and_then(|e| e.to_str()).unwrap_or("")
    ));
    let mut checking = match certificate {
        None => None,
        Some(_) => Some(Checking {
            verifier: Verifier::new(mesh, grid)
                .map_err(|e| PartError::Certificate(CertificateError::from(e)))?,
            header: header.clone(),
            chunk: Vec::new(),
            chunk_bytes: 0,
            verdict: Verdict::default(),
            exact_doc: match (shard, exact) {
                (None, false) => Some(
                    JsonWriter::begin(hashing(std::io::sink()), &header, Exactness::WithExact)
                        .map_err(io)?,
                ),
                _ => None,
            },
            exact_shard: match (shard, exact) {
                (Some(_), false) => Some(hashing(BufWriter::new(
                    AtomicFile::create(&exact_shard_path).map_err(io)?,
                ))),
                _ => None,
            },
            parts: Vec::new(),
        }),
    };
    let certify = checking.is_some();
    let finish = |i: usize, ls: LevelSet| -> (LevelText, Option<(Vec<u8>, LevelPart)>) {
        let text = level_text(&ls, ex);
        let check = certify.then(|| {
            let exact_text = if exact {
                text.to_bytes()
            } else {
                level_text(&ls, Exactness::WithExact).to_bytes()
            };
            (exact_text, LevelPart::at(&mine[i], &ls))
        });
        (text, check)
    };
    let written = slice_levels_then(&slicer, mine, threads, &finish, |_, (text, check)| {
        let e = |e| SinkError(out_name.clone(), e);
        match &mut sink {
            Out::Document(w) => w.level_text(&text).map_err(e)?,
            Out::Shard(w) => {
                let b = text.to_bytes();
                w.write_all(&(b.len() as u64).to_le_bytes()).map_err(e)?;
                w.write_all(&b).map_err(e)?;
            }
        }
        if let (Some(c), Some((t, p))) = (&mut checking, check) {
            c.add(t, p).map_err(e)?;
        }
        Ok::<(), SinkError>(())
    });
    match written {
        Ok(()) => {}
        Err(SweepError::Slice { source, .. }) => return Err(PartError::Slice(source)),
        Err(SweepError::Sink(SinkError(p, e))) => return Err(PartError::Io(p, e)),
        Err(SweepError::Threads(t)) => return Err(PartError::Threads(t)),
    }
    let file = match sink {
        Out::Document(w) => w.finish().map_err(io)?,
        Out::Shard(w) => w,
    };
    let (sha, bytes) = (hex(file.hasher.clone().finalize().as_slice()), file.bytes);
    let Hashing { inner, .. } = file;
    inner
        .into_inner()
        .map_err(|e| io(e.into_error()))?
        .commit()
        .map_err(io)?;
    let input_sha256 = sha256_hex(&part.bytes);
    let mut done = Done {
        output: out_name.clone(),
        levels: mine.len(),
        bytes,
        sha256: sha.clone(),
        certificate: None,
        mesh_sha256: header.sha256.clone(),
        input_sha256,
        exact_shard: None,
        parts: None,
        checked: None,
    };
    let Some(mut c) = checking else {
        return Ok(Ok(done));
    };
    c.verify_chunk().map_err(io)?;
    if shard.is_some() {
        // Violations end the shard here; a shard that passed hands on its
        // counts, its level parts and its exact texts (when not written).
        let verdict = std::mem::take(&mut c.verdict);
        let checked = verdict.checked();
        verdict
            .into_verification()
            .map_err(PartError::Certificate)?;
        if let Some(s) = c.exact_shard.take() {
            s.inner
                .into_inner()
                .map_err(|e| io(e.into_error()))?
                .commit()
                .map_err(io)?;
            done.exact_shard = Some(exact_shard_path.display().to_string());
        }
        done.parts = Some(serde_json::to_string(&c.parts).unwrap_or_default());
        done.checked = Some(checked);
        return Ok(Ok(done));
    }
    let verified_sha = match c.exact_doc.take() {
        Some(d) => hex(d.finish().map_err(io)?.hasher.finalize().as_slice()),
        None => sha.clone(),
    };
    let verification = std::mem::take(&mut c.verdict)
        .into_verification()
        .map_err(PartError::Certificate)?;
    if let Some(cp) = certificate {
        let result = file_result(sha, bytes, verified_sha);
        done.certificate = Some(write_certificate(
            cp,
            &part,
            header,
            exact,
            &out_name,
            result,
            c.parts,
            verification,
        )?);
    }
    Ok(Ok(done))
}

fn hex(b: &[u8]) -> String {
    wmslice::output::json::hex(b)
}

fn opt_rat(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Rat>> {
    v.filter(|v| !v.is_none())
        .map(|v| crate::values::exact(name, v))
        .transpose()
}

fn done_dict<'py>(py: Python<'py>, d: Done) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("output", d.output)?;
    out.set_item("levels", d.levels)?;
    out.set_item("bytes", d.bytes)?;
    out.set_item("sha256", d.sha256)?;
    out.set_item("certificate", d.certificate)?;
    out.set_item("mesh_sha256", d.mesh_sha256)?;
    out.set_item("input_sha256", d.input_sha256)?;
    out.set_item("exact_shard", d.exact_shard)?;
    out.set_item("parts", d.parts)?;
    out.set_item(
        "checked",
        d.checked.map(|c| {
            [
                c.levels, c.loops, c.points, c.regions, c.ridges, c.extrema, c.saddles,
            ]
        }),
    )?;
    Ok(out)
}

/// Slices one mesh file at a plan of levels (uniform layers `layer_height`
/// from `first` to `last`, and/or explicit `levels`) and writes the JSON
/// document to `output` atomically, with its certificate at `certificate`
/// when given. With `shard=(start, stop)`, slices only those levels of the
/// plan and writes their texts for [`join_shards`]. With `max_levels`, a
/// part whose plan has more levels is not sliced: `{"split": n}` tells
/// the caller to shard it. Returns what was written.
#[pyfunction]
#[pyo3(signature = (path, output, certificate=None, snap=None, layer_height=None, first=None,
    last=None, levels=None, exact=false, threads=None, shard=None, max_levels=None,
    drop_collapsed=false, weld=false))]
#[allow(clippy::too_many_arguments)]
pub fn slice_part<'py>(
    py: Python<'py>,
    path: PathBuf,
    output: PathBuf,
    certificate: Option<PathBuf>,
    snap: Option<&Bound<'py, PyAny>>,
    layer_height: Option<&Bound<'py, PyAny>>,
    first: Option<&Bound<'py, PyAny>>,
    last: Option<&Bound<'py, PyAny>>,
    levels: Option<&Bound<'py, PyAny>>,
    exact: bool,
    threads: Option<usize>,
    shard: Option<(usize, usize)>,
    max_levels: Option<usize>,
    drop_collapsed: bool,
    weld: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let q = opt_rat("snap grid", snap)?;
    let args = PlanArgs {
        height: opt_rat("layer height", layer_height)?,
        first: opt_rat("first", first)?,
        last: opt_rat("last", last)?,
        explicit: match levels.filter(|l| !l.is_none()) {
            Some(l) => crate::values::levels(l)?,
            None => Vec::new(),
        },
    };
    let threads = crate::mesh::thread_count(threads.map(|t| t.max(1)))?;
    let r = py.detach(|| {
        run_part(
            &path,
            &output,
            certificate.as_deref(),
            q.as_ref(),
            Repairs::from_flags(weld, drop_collapsed),
            &args,
            exact,
            threads,
            shard,
            max_levels,
        )
    });
    match r.map_err(|e| e.into_py(py))? {
        Ok(done) => done_dict(py, done),
        Err(count) => {
            let d = PyDict::new(py);
            d.set_item("split", count)?;
            Ok(d)
        }
    }
}

/// Reads a shard file's level texts in order.
fn shard_texts(
    path: &Path,
    mut each: impl FnMut(&[u8]) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut f = std::io::BufReader::new(std::fs::File::open(path)?);
    let mut len = [0u8; 8];
    let mut buf = Vec::new();
    loop {
        match f.read_exact(&mut len) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(()),
            Err(e) => return Err(e),
        }
        let n = usize::try_from(u64::from_le_bytes(len)).map_err(std::io::Error::other)?;
        buf.resize(n, 0);
        f.read_exact(&mut buf)?;
        each(&buf)?;
    }
}

/// Joins the shards of one part (the dicts [`slice_part`] returned, in
/// level order) into its JSON document at `output`, atomically, with its
/// certificate when the shards were made with one; the shard files are
/// removed. The file is read again for the header and the certificate's
/// input hash, and must be the one the shards sliced.
#[pyfunction]
#[pyo3(signature = (path, output, shards, certificate=None, snap=None, exact=false,
    drop_collapsed=false, weld=false))]
#[allow(clippy::too_many_arguments)]
pub fn join_shards<'py>(
    py: Python<'py>,
    path: PathBuf,
    output: PathBuf,
    shards: Vec<Bound<'py, PyDict>>,
    certificate: Option<PathBuf>,
    snap: Option<&Bound<'py, PyAny>>,
    exact: bool,
    drop_collapsed: bool,
    weld: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let q = opt_rat("snap grid", snap)?;
    struct Shard {
        output: PathBuf,
        exact: Option<PathBuf>,
        mesh_sha256: String,
        input_sha256: String,
        parts: Option<String>,
        checked: Option<[usize; 7]>,
    }
    let mut list = Vec::new();
    for s in &shards {
        let get = |k: &str| -> PyResult<Bound<'py, PyAny>> {
            s.get_item(k)?
                .ok_or_else(|| PyValueError::new_err(format!("shard result without {k:?}")))
        };
        list.push(Shard {
            output: get("output")?.extract()?,
            exact: get("exact_shard")?.extract()?,
            mesh_sha256: get("mesh_sha256")?.extract()?,
            input_sha256: get("input_sha256")?.extract()?,
            parts: get("parts")?.extract()?,
            checked: get("checked")?.extract()?,
        });
    }
    let r = py.detach(|| -> Result<Done, PartError> {
        let part = read_part(&path, q.as_ref(), Repairs::from_flags(weld, drop_collapsed))?;
        let header = header_of(&part.prepared);
        let input_sha256 = sha256_hex(&part.bytes);
        for s in &list {
            if s.mesh_sha256 != header.sha256 || s.input_sha256 != input_sha256 {
                return Err(PartError::Mismatch(format!(
                    "{} changed while it was sliced (a shard saw other bytes)",
                    part.name
                )));
            }
        }
        let out_name = output.display().to_string();
        let io = |e: std::io::Error| PartError::Io(out_name.clone(), e);
        let ex = exactness(exact);
        let file = hashing(BufWriter::new(AtomicFile::create(&output).map_err(io)?));
        let mut w = JsonWriter::begin(file, &header, ex).map_err(io)?;
        let mut levels = 0;
        for s in &list {
            shard_texts(&s.output, |t| {
                levels += 1;
                w.level_bytes(t)
            })
            .map_err(|e| PartError::Io(s.output.display().to_string(), e))?;
        }
        let file = w.finish().map_err(io)?;
        let (sha, bytes) = (hex(file.hasher.clone().finalize().as_slice()), file.bytes);
        file.inner
            .into_inner()
            .map_err(|e| io(e.into_error()))?
            .commit()
            .map_err(io)?;
        let mut done = Done {
            output: out_name.clone(),
            levels,
            bytes,
            sha256: sha.clone(),
            certificate: None,
            mesh_sha256: header.sha256.clone(),
            input_sha256,
            exact_shard: None,
            parts: None,
            checked: None,
        };
        if let Some(cp) = &certificate {
            let verified_sha = if exact {
                sha.clone()
            } else {
                let mut d =
                    JsonWriter::begin(hashing(std::io::sink()), &header, Exactness::WithExact)
                        .map_err(io)?;
                for s in &list {
                    let p = s.exact.as_ref().ok_or_else(|| {
                        PartError::Mismatch("a shard was made without its exact texts".into())
                    })?;
                    shard_texts(p, |t| d.level_bytes(t))
                        .map_err(|e| PartError::Io(p.display().to_string(), e))?;
                }
                hex(d.finish().map_err(io)?.hasher.finalize().as_slice())
            };
            let mut verdict = Verdict::default();
            let mut parts: Vec<LevelPart> = Vec::new();
            for s in &list {
                let (Some(c), Some(p)) = (s.checked, &s.parts) else {
                    return Err(PartError::Mismatch(
                        "a shard was made without a certificate".into(),
                    ));
                };
                let [levels, loops, points, regions, ridges, extrema, saddles] = c;
                verdict = verdict.merge(Verdict::passed(Checked {
                    levels,
                    loops,
                    points,
                    regions,
                    ridges,
                    extrema,
                    saddles,
                }));
                let more: Vec<LevelPart> =
                    serde_json::from_str(p).map_err(|e| PartError::Mismatch(e.to_string()))?;
                parts.extend(more);
            }
            let result = file_result(sha, bytes, verified_sha);
            let verification = verdict
                .into_verification()
                .map_err(PartError::Certificate)?;
            done.certificate = Some(write_certificate(
                cp,
                &part,
                header,
                exact,
                &out_name,
                result,
                parts,
                verification,
            )?);
        }
        for s in &list {
            let _ = std::fs::remove_file(&s.output);
            if let Some(p) = &s.exact {
                let _ = std::fs::remove_file(p);
            }
        }
        Ok(done)
    });
    done_dict(py, r.map_err(|e| e.into_py(py))?)
}
