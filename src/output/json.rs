//! Input: level sets. Output: the `wmslice-levelset` JSON document of SPEC
//! section 9 (`levelset.schema.json`). Points are the nearest doubles of
//! the exact values; with [`Exactness::WithExact`] the exact rationals are
//! added (`exact`, `area_exact`) together with the mesh element each point
//! lies on (`on`, an extra key).

use crate::exact::point::LoopPoint;
use crate::exact::rational::{rat_to_f64, rat_to_string, Rat};
use crate::exact::Point2;
use crate::levelset::{LevelSet, Loop};
use crate::mesh::Mesh;
use crate::nest::Role;
use crate::segment::CutPoint;
use serde::Serialize;
use sha2::{Digest, Sha256};
use std::io::Write;
use std::sync::Arc;

/// Whether exact rationals are written beside the rounded values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Exactness {
    /// Rounded doubles only.
    #[default]
    Rounded,
    /// Rounded doubles plus exact `"p/q"` strings.
    WithExact,
}

/// The `mesh` header.
#[derive(Clone, Debug, Serialize)]
pub struct MeshHeader {
    /// Vertex count.
    pub vertices: usize,
    /// Face count.
    pub faces: usize,
    /// SHA-256 of the mesh as sliced (see [`mesh_sha256`]).
    pub sha256: String,
    /// The snap grid, or null.
    pub snap: Option<String>,
}

impl MeshHeader {
    /// The header of a mesh, with its snap grid if any.
    pub fn new(mesh: &Mesh, snap: Option<&Rat>) -> Self {
        MeshHeader {
            vertices: mesh.num_vertices(),
            faces: mesh.num_faces(),
            sha256: mesh_sha256(mesh),
            snap: snap.map(rat_to_string),
        }
    }
}

/// SHA-256 of a mesh's canonical bytes: `"wmslice-mesh-v1"`, vertex and face
/// counts as u64 LE, every coordinate as f64 LE bits, every index as u32
/// LE. Independent of the file format the mesh came from.
pub fn mesh_sha256(mesh: &Mesh) -> String {
    let mut h = Sha256::new();
    h.update(b"wmslice-mesh-v1");
    h.update((mesh.num_vertices() as u64).to_le_bytes());
    h.update((mesh.num_faces() as u64).to_le_bytes());
    for p in &mesh.positions {
        for x in p {
            h.update(x.to_le_bytes());
        }
    }
    for t in &mesh.faces {
        for v in t {
            h.update(v.0.to_le_bytes());
        }
    }
    hex(&h.finalize())
}

/// Lower-case hex of bytes.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[derive(Serialize)]
#[serde(rename_all = "lowercase")]
enum On {
    Edge(u32),
    Vertex(u32),
}

#[derive(Serialize)]
struct JsonLoop {
    points: Vec<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    exact: Option<Vec<[String; 2]>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    on: Option<Vec<On>>,
    area: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    area_exact: Option<String>,
    role: Role,
    parent: Option<usize>,
}

#[derive(Serialize)]
struct JsonRegion {
    facing: crate::classify::Facing,
    faces: Vec<u32>,
    area: String,
    boundary: Vec<JsonLoop>,
}

#[derive(Serialize)]
struct JsonRidge {
    kind: crate::classify::RidgeKind,
    closed: bool,
    vertices: Vec<u32>,
    points: Vec<[f64; 2]>,
}

#[derive(Serialize)]
struct JsonPoint {
    vertex: u32,
    kind: crate::classify::ExtremumKind,
    point: [f64; 2],
}

#[derive(Serialize)]
struct JsonSaddle {
    vertex: u32,
    branches: u32,
}

fn exact_xy(p: &Point2) -> [String; 2] {
    [rat_to_string(&p.x), rat_to_string(&p.y)]
}

/// With exact output, `area` is the nearest double of `area_exact`
/// (computed anyway); without, the loop's certified rounding
/// ([`Loop::area_approx`]: of the exact sign, within a few ulps of the
/// largest shoelace partial sum per point), so the exact area is never
/// computed.
fn json_loop(l: &Loop, ex: Exactness) -> JsonLoop {
    let with = ex == Exactness::WithExact;
    let exact_area = with.then(|| l.area());
    JsonLoop {
        points: l.points.iter().map(LoopPoint::to_f64).collect(),
        exact: with.then(|| l.points.iter().map(|p| exact_xy(&p.exact())).collect()),
        on: with.then(|| {
            l.cuts
                .iter()
                .map(|c| match c {
                    CutPoint::OnEdge(e) => On::Edge(e.0),
                    CutPoint::AtVertex(v) => On::Vertex(v.0),
                })
                .collect()
        }),
        area: exact_area.as_ref().map_or(l.area_approx, rat_to_f64),
        area_exact: exact_area.as_ref().map(rat_to_string),
        role: l.role,
        parent: l.parent,
    }
}

/// Writes `,"key":`.
fn key(out: &mut Vec<u8>, key: &str) {
    out.extend_from_slice(b",\"");
    out.extend_from_slice(key.as_bytes());
    out.extend_from_slice(b"\":");
}

/// Writes `,"key":value`.
fn field<T: Serialize>(out: &mut Vec<u8>, name: &str, value: &T) -> serde_json::Result<()> {
    key(out, name);
    serde_json::to_writer(&mut *out, value)
}

/// One level's JSON text, as [`JsonWriter::level`] writes it: an object
/// with the keys of SPEC section 9 in order. L- and L+ that are S_O's loops
/// (no vertex on the plane) repeat its text instead of formatting every
/// point again.
pub fn level_text(ls: &LevelSet, ex: Exactness) -> serde_json::Result<Vec<u8>> {
    let loops = |v: &[Loop]| -> Vec<JsonLoop> { v.iter().map(|l| json_loop(l, ex)).collect() };
    // About 40 bytes a rounded point: room for S_O once.
    let points: usize = ls.contours.iter().map(|l| l.points.len()).sum();
    let mut out = Vec::with_capacity(64 + 40 * points);
    out.extend_from_slice(b"{\"z\":");
    serde_json::to_writer(&mut out, &rat_to_string(&ls.level))?;
    let start = out.len() + b",\"contours\":".len();
    field(&mut out, "contours", &loops(&ls.contours))?;
    let contours = start..out.len();
    let regions: Vec<JsonRegion> = ls
        .regions
        .iter()
        .map(|r| JsonRegion {
            facing: r.facing,
            faces: r.faces.iter().map(|f| f.0).collect(),
            area: rat_to_string(&r.area),
            boundary: loops(&r.boundary),
        })
        .collect();
    field(&mut out, "faces", &regions)?;
    let ridges: Vec<JsonRidge> = ls
        .ridges
        .iter()
        .map(|r| JsonRidge {
            kind: r.kind,
            closed: r.closed,
            vertices: r.vertices.iter().map(|v| v.0).collect(),
            points: r.points.iter().map(Point2::to_f64).collect(),
        })
        .collect();
    field(&mut out, "ridges", &ridges)?;
    let extrema: Vec<JsonPoint> = ls
        .extrema
        .iter()
        .map(|p| JsonPoint {
            vertex: p.vertex.0,
            kind: p.kind,
            point: p.point.to_f64(),
        })
        .collect();
    field(&mut out, "points", &extrema)?;
    let saddles: Vec<JsonSaddle> = ls
        .saddles
        .iter()
        .map(|s| JsonSaddle {
            vertex: s.vertex.0,
            branches: s.branches,
        })
        .collect();
    field(&mut out, "saddles", &saddles)?;
    for (name, family) in [("below", &ls.below), ("above", &ls.above)] {
        if Arc::ptr_eq(family, &ls.contours) {
            key(&mut out, name);
            out.extend_from_within(contours.clone());
        } else {
            field(&mut out, name, &loops(family))?;
        }
    }
    out.push(b'}');
    Ok(out)
}

/// Writes one `wmslice-levelset` document level by level, so memory does
/// not grow with the number of levels. The bytes equal [`to_json`]'s.
pub struct JsonWriter<W: Write> {
    out: W,
    ex: Exactness,
    count: usize,
}

impl<W: Write> JsonWriter<W> {
    /// Writes the header and opens the `levels` array.
    pub fn begin(mut out: W, header: &MeshHeader, ex: Exactness) -> std::io::Result<Self> {
        out.write_all(b"{\"format\":\"wmslice-levelset\",\"version\":1,\"mesh\":")?;
        serde_json::to_writer(&mut out, header)?;
        out.write_all(b",\"levels\":[\n")?;
        Ok(JsonWriter { out, ex, count: 0 })
    }

    /// Writes one level.
    pub fn level(&mut self, ls: &LevelSet) -> std::io::Result<()> {
        self.level_text(&level_text(ls, self.ex)?)
    }

    /// Writes one level's text, made by [`level_text`] (possibly on another
    /// thread) with this writer's exactness.
    pub fn level_text(&mut self, text: &[u8]) -> std::io::Result<()> {
        if self.count > 0 {
            self.out.write_all(b",\n")?;
        }
        self.out.write_all(text)?;
        self.count += 1;
        Ok(())
    }

    /// Closes the document and returns the writer.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.out.write_all(b"\n]}\n")?;
        Ok(self.out)
    }
}

/// Serializes level sets as one `wmslice-levelset` document.
pub fn to_json(header: &MeshHeader, levels: &[LevelSet], ex: Exactness) -> String {
    let write = || -> std::io::Result<Vec<u8>> {
        let mut w = JsonWriter::begin(Vec::new(), header, ex)?;
        for ls in levels {
            w.level(ls)?;
        }
        w.finish()
    };
    // Writing plain data with string keys into memory cannot fail.
    String::from_utf8(write().unwrap_or_default()).unwrap_or_default()
}
