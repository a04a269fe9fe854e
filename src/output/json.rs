//! Input: level sets. Output: the `wmslice-levelset` JSON document of SPEC
//! section 9 (`levelset.schema.json`). Points are the nearest doubles of
//! the exact values; with [`Exactness::WithExact`] the exact rationals are
//! added (`exact`, `area_exact`) together with the mesh element each point
//! lies on (`on`, an extra key).

use crate::exact::rational::{rat_to_f64, rat_to_string, Rat};
use crate::levelset::{LevelSet, Loop};
use crate::mesh::Mesh;
use crate::segment::CutPoint;
use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter};
use sha2::{Digest, Sha256};
use std::io::Write;
use std::ops::Range;
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
    /// With `--weld` (an extra key, absent otherwise): how many vertices
    /// at one point were merged into an earlier one before slicing.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub welded: Option<usize>,
    /// With `--drop-collapsed` (an extra key, absent otherwise): how many
    /// faces that used one vertex twice were removed before slicing.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dropped_collapsed: Option<usize>,
}

impl MeshHeader {
    /// The header of a mesh, with its snap grid if any.
    pub fn new(mesh: &Mesh, snap: Option<&Rat>) -> Self {
        MeshHeader {
            vertices: mesh.num_vertices(),
            faces: mesh.num_faces(),
            sha256: mesh_sha256(mesh),
            snap: snap.map(rat_to_string),
            welded: None,
            dropped_collapsed: None,
        }
    }

    /// The same header, saying how many vertices were welded and how many
    /// collapsed faces were removed (`None`: not asked for).
    pub fn with_repairs(self, welded: Option<usize>, dropped: Option<usize>) -> Self {
        MeshHeader {
            welded,
            dropped_collapsed: dropped,
            ..self
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

/// One level's JSON text (see [`level_text`]): byte ranges of one buffer,
/// written in order. L- and L+ that are S_O's loops are S_O's range again,
/// so their text is neither formatted nor copied twice.
#[derive(Clone, Debug, Default)]
pub struct LevelText {
    bytes: Vec<u8>,
    parts: Vec<Range<usize>>,
    /// Start of the part being written.
    open: usize,
}

impl LevelText {
    /// Writes the text.
    pub fn write_to<W: Write + ?Sized>(&self, out: &mut W) -> std::io::Result<()> {
        for r in &self.parts {
            out.write_all(&self.bytes[r.clone()])?;
        }
        Ok(())
    }

    /// The text as one byte string.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.parts.iter().map(|r| r.len()).sum());
        self.parts
            .iter()
            .for_each(|r| out.extend_from_slice(&self.bytes[r.clone()]));
        out
    }

    /// Ends the part being written at the end of the buffer.
    fn close(&mut self) {
        let end = self.bytes.len();
        if end > self.open {
            self.parts.push(self.open..end);
        }
        self.open = end;
    }

    /// Writes an earlier range again, by reference.
    fn repeat(&mut self, range: Range<usize>) {
        self.close();
        self.parts.push(range);
    }
}

/// Writes a double as `serde_json` does (shortest round-trip text;
/// `null` when not finite).
fn number(out: &mut Vec<u8>, v: f64) {
    if v.is_finite() {
        // Writing into a `Vec` cannot fail.
        let _ = CompactFormatter.write_f64(out, v);
    } else {
        out.extend_from_slice(b"null");
    }
}

/// The nearest finite double of a rational whose nearest double
/// overflows (a loop's area on a mesh near `2^1000`): `f64::MAX` of its
/// sign. JSON has no infinity (`number` would write `null`, losing the
/// sign, and many readers refuse a decimal beyond `f64::MAX`); the exact
/// value is `area_exact`. The verifier expects the same saturation.
fn overflowed(out: &mut Vec<u8>, r: &Rat) {
    use num_traits::Signed;
    number(out, if r.is_negative() { f64::MIN } else { f64::MAX });
}

/// Writes an unsigned integer.
fn integer(out: &mut Vec<u8>, v: u64) {
    let _ = CompactFormatter.write_u64(out, v);
}

/// Writes `[x,y]`, each number as [`number`] writes it.
///
/// Both coordinates are formatted before either is copied out: copying a
/// number's text straight after `zmij` wrote it loads bytes that are still
/// in the store buffer in pieces, a stall that cost about as much as the
/// formatting on a small part (`bench/RESULTS.md`).
fn pair(out: &mut Vec<u8>, [x, y]: [f64; 2]) {
    if !(x.is_finite() && y.is_finite()) {
        out.push(b'[');
        number(out, x);
        out.push(b',');
        number(out, y);
        out.push(b']');
        return;
    }
    let (mut bx, mut by) = (zmij::Buffer::new(), zmij::Buffer::new());
    let (tx, ty) = (
        bx.format_finite(x).as_bytes(),
        by.format_finite(y).as_bytes(),
    );
    out.reserve(tx.len() + ty.len() + 3);
    out.push(b'[');
    out.extend_from_slice(tx);
    out.push(b',');
    out.extend_from_slice(ty);
    out.push(b']');
}

/// Writes a string that needs no escaping (rationals, enum names).
fn plain_string(out: &mut Vec<u8>, s: &str) {
    out.push(b'"');
    out.extend_from_slice(s.as_bytes());
    out.push(b'"');
}

/// Writes a unit enum as `serde` names it.
fn name<T: Serialize>(out: &mut Vec<u8>, v: &T) {
    // Unit variants with plain names: cannot fail.
    let _ = serde_json::to_writer(&mut *out, v);
}

/// Writes `[a,b,...]`, each item by `item`.
fn array<T>(out: &mut Vec<u8>, items: &[T], mut item: impl FnMut(&mut Vec<u8>, &T)) {
    out.push(b'[');
    for (i, x) in items.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        item(out, x);
    }
    out.push(b']');
}

/// Writes `,"key":` (`"key":` when `first`).
fn key(out: &mut Vec<u8>, key: &str, first: bool) {
    if !first {
        out.push(b',');
    }
    plain_string(out, key);
    out.push(b':');
}

/// Writes one loop. With exact output, `area` is the nearest double of
/// `area_exact` (computed anyway); without, the certified rounding from
/// the written points ([`Loop::rounded_area`]: of the exact sign, within a
/// bound relative to the loop's size), so the exact area is computed only
/// where that bound cannot show the sign.
fn json_loop(out: &mut Vec<u8>, l: &Loop, ex: Exactness) {
    out.push(b'{');
    key(out, "points", true);
    let rounded: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
    array(out, &rounded, |o, p| pair(o, *p));
    let exact_area = (ex == Exactness::WithExact).then(|| l.area());
    if ex == Exactness::WithExact {
        key(out, "exact", false);
        array(out, &l.points, |o, p| {
            let p = p.exact();
            o.push(b'[');
            plain_string(o, &rat_to_string(&p.x));
            o.push(b',');
            plain_string(o, &rat_to_string(&p.y));
            o.push(b']');
        });
        key(out, "on", false);
        array(out, &l.cuts, |o, c| {
            let (kind, id) = match c {
                CutPoint::OnEdge(e) => ("edge", e.0),
                CutPoint::AtVertex(v) => ("vertex", v.0),
            };
            o.push(b'{');
            key(o, kind, true);
            integer(o, id.into());
            o.push(b'}');
        });
    }
    key(out, "area", false);
    let rounded = match &exact_area {
        Some(a) => rat_to_f64(a),
        None => l.rounded_area(&rounded),
    };
    if rounded.is_finite() {
        number(out, rounded);
    } else {
        match &exact_area {
            Some(a) => overflowed(out, a),
            None => overflowed(out, &l.area()),
        }
    }
    if let Some(a) = &exact_area {
        key(out, "area_exact", false);
        plain_string(out, &rat_to_string(a));
    }
    key(out, "role", false);
    name(out, &l.role);
    key(out, "parent", false);
    match l.parent {
        Some(p) => integer(out, p as u64),
        None => out.extend_from_slice(b"null"),
    }
    if l.collapsed {
        key(out, "collapsed", false);
        out.extend_from_slice(b"true");
    }
    out.push(b'}');
}

/// Writes a family of loops.
fn loops(out: &mut Vec<u8>, family: &[Loop], ex: Exactness) {
    array(out, family, |o, l| json_loop(o, l, ex));
}

/// One level's JSON text, as [`JsonWriter::level`] writes it: an object
/// with the keys of SPEC section 9 in order, numbers formatted as
/// `serde_json` formats them.
pub fn level_text(ls: &LevelSet, ex: Exactness) -> LevelText {
    // A rounded point `[x,y],` takes about 40 bytes, rarely over 48: room
    // for S_O once, mostly without growing.
    let points: usize = ls.contours.iter().map(|l| l.points.len()).sum();
    let mut t = LevelText {
        bytes: Vec::with_capacity(256 + 48 * points),
        ..LevelText::default()
    };
    let out = &mut t.bytes;
    out.push(b'{');
    key(out, "z", true);
    plain_string(out, &rat_to_string(&ls.level));
    key(out, "contours", false);
    let start = out.len();
    loops(out, &ls.contours, ex);
    let contours = start..out.len();
    key(out, "faces", false);
    array(out, &ls.regions, |o, r| {
        o.push(b'{');
        key(o, "facing", true);
        name(o, &r.facing);
        key(o, "faces", false);
        array(o, &r.faces, |o, f| integer(o, f.0.into()));
        key(o, "area", false);
        plain_string(o, &rat_to_string(&r.area));
        key(o, "boundary", false);
        loops(o, &r.boundary, ex);
        o.push(b'}');
    });
    key(out, "ridges", false);
    array(out, &ls.ridges, |o, r| {
        o.push(b'{');
        key(o, "kind", true);
        name(o, &r.kind);
        key(o, "closed", false);
        o.extend_from_slice(if r.closed { b"true" } else { b"false" });
        key(o, "vertices", false);
        array(o, &r.vertices, |o, v| integer(o, v.0.into()));
        key(o, "points", false);
        array(o, &r.points, |o, p| pair(o, p.to_f64()));
        o.push(b'}');
    });
    key(out, "points", false);
    array(out, &ls.extrema, |o, p| {
        o.push(b'{');
        key(o, "vertex", true);
        integer(o, p.vertex.0.into());
        key(o, "kind", false);
        name(o, &p.kind);
        key(o, "point", false);
        pair(o, p.point.to_f64());
        o.push(b'}');
    });
    key(out, "saddles", false);
    array(out, &ls.saddles, |o, s| {
        o.push(b'{');
        key(o, "vertex", true);
        integer(o, s.vertex.0.into());
        key(o, "branches", false);
        integer(o, s.branches.into());
        o.push(b'}');
    });
    for (name, family) in [("below", &ls.below), ("above", &ls.above)] {
        key(&mut t.bytes, name, false);
        if Arc::ptr_eq(family, &ls.contours) {
            t.repeat(contours.clone());
        } else {
            loops(&mut t.bytes, family, ex);
        }
    }
    t.bytes.push(b'}');
    t.close();
    t
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
        self.level_text(&level_text(ls, self.ex))
    }

    /// Writes one level's text, made by [`level_text`] (possibly on another
    /// thread) with this writer's exactness.
    pub fn level_text(&mut self, text: &LevelText) -> std::io::Result<()> {
        if self.count > 0 {
            self.out.write_all(b",\n")?;
        }
        text.write_to(&mut self.out)?;
        self.count += 1;
        Ok(())
    }

    /// Writes one level's text given as bytes: [`LevelText::to_bytes`] of a
    /// level made with this writer's exactness (e.g. in another process).
    pub fn level_bytes(&mut self, text: &[u8]) -> std::io::Result<()> {
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

#[cfg(test)]
mod tests {
    #[test]
    fn overflowed_areas_saturate_to_the_largest_double_of_their_sign() {
        let big = Rat::from_integer(2.into()).pow(2000);
        for (r, text) in [
            (big.clone(), "1.7976931348623157e+308"),
            (-big, "-1.7976931348623157e+308"),
        ] {
            let mut out = Vec::new();
            super::overflowed(&mut out, &r);
            assert_eq!(String::from_utf8(out).unwrap(), text);
        }
    }

    /// A point's text equals `serde_json`'s for any two doubles, every
    /// exponent, subnormals, zeros of both signs and non-finite values
    /// (`null`), whole bit patterns drawn.
    #[test]
    fn a_point_is_written_as_serde_json_writes_it() {
        use proptest::prelude::*;
        let special = prop::sample::select(vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
            // Where the shortest text switches between plain digits and
            // an exponent (sample values of the output, not tolerances).
            1e16,
            1e-7,
        ]);
        let any = prop_oneof![any::<u64>().prop_map(f64::from_bits), special];
        proptest!(ProptestConfig::with_cases(20_000), |(x in any.clone(), y in any)| {
            let mut out = Vec::new();
            super::pair(&mut out, [x, y]);
            prop_assert_eq!(out, serde_json::to_vec(&[x, y]).unwrap());
        });
    }

    use super::*;
    use crate::classify::{ExtremumKind, Facing, RidgeKind};
    use crate::exact::Point2;
    use crate::levelset::Slicer;
    use crate::nest::Role;

    // The level's text as `serde` derives it: the reference the hand-written
    // text must equal byte for byte.
    #[derive(Serialize)]
    #[serde(rename_all = "lowercase")]
    enum On {
        Edge(u32),
        Vertex(u32),
    }

    #[derive(Serialize)]
    struct RefLoop {
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
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        collapsed: bool,
    }

    #[derive(Serialize)]
    struct RefRegion {
        facing: Facing,
        faces: Vec<u32>,
        area: String,
        boundary: Vec<RefLoop>,
    }

    #[derive(Serialize)]
    struct RefRidge {
        kind: RidgeKind,
        closed: bool,
        vertices: Vec<u32>,
        points: Vec<[f64; 2]>,
    }

    #[derive(Serialize)]
    struct RefPoint {
        vertex: u32,
        kind: ExtremumKind,
        point: [f64; 2],
    }

    #[derive(Serialize)]
    struct RefSaddle {
        vertex: u32,
        branches: u32,
    }

    #[derive(Serialize)]
    struct RefLevel {
        z: String,
        contours: Vec<RefLoop>,
        faces: Vec<RefRegion>,
        ridges: Vec<RefRidge>,
        points: Vec<RefPoint>,
        saddles: Vec<RefSaddle>,
        below: Vec<RefLoop>,
        above: Vec<RefLoop>,
    }

    fn ref_loop(l: &Loop, ex: Exactness) -> RefLoop {
        let with = ex == Exactness::WithExact;
        let exact_area = with.then(|| l.area());
        RefLoop {
            points: l.points.iter().map(|p| p.to_f64()).collect(),
            exact: with.then(|| {
                l.points
                    .iter()
                    .map(|p| {
                        let p = p.exact();
                        [rat_to_string(&p.x), rat_to_string(&p.y)]
                    })
                    .collect()
            }),
            on: with.then(|| {
                l.cuts
                    .iter()
                    .map(|c| match c {
                        CutPoint::OnEdge(e) => On::Edge(e.0),
                        CutPoint::AtVertex(v) => On::Vertex(v.0),
                    })
                    .collect()
            }),
            area: exact_area.as_ref().map_or_else(
                || {
                    let q: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
                    l.rounded_area(&q)
                },
                rat_to_f64,
            ),
            area_exact: exact_area.as_ref().map(rat_to_string),
            role: l.role,
            parent: l.parent,
            collapsed: l.collapsed,
        }
    }

    fn reference(ls: &LevelSet, ex: Exactness) -> Vec<u8> {
        let loops = |v: &[Loop]| v.iter().map(|l| ref_loop(l, ex)).collect();
        let level = RefLevel {
            z: rat_to_string(&ls.level),
            contours: loops(&ls.contours),
            faces: ls
                .regions
                .iter()
                .map(|r| RefRegion {
                    facing: r.facing,
                    faces: r.faces.iter().map(|f| f.0).collect(),
                    area: rat_to_string(&r.area),
                    boundary: loops(&r.boundary),
                })
                .collect(),
            ridges: ls
                .ridges
                .iter()
                .map(|r| RefRidge {
                    kind: r.kind,
                    closed: r.closed,
                    vertices: r.vertices.iter().map(|v| v.0).collect(),
                    points: r.points.iter().map(Point2::to_f64).collect(),
                })
                .collect(),
            points: ls
                .extrema
                .iter()
                .map(|p| RefPoint {
                    vertex: p.vertex.0,
                    kind: p.kind,
                    point: p.point.to_f64(),
                })
                .collect(),
            saddles: ls
                .saddles
                .iter()
                .map(|s| RefSaddle {
                    vertex: s.vertex.0,
                    branches: s.branches,
                })
                .collect(),
            below: loops(&ls.below),
            above: loops(&ls.above),
        };
        serde_json::to_vec(&level).unwrap()
    }

    /// Every dataset at its degenerate levels and between them (flats,
    /// ridges, extrema, saddles, L- and L+ apart from S_O and equal to
    /// it), in both exactness modes: the written text equals `serde`'s.
    #[test]
    fn level_text_equals_serde_serialization() {
        let mut compared = 0;
        for d in crate::datasets::all() {
            let mesh = d.build();
            let slicer = Slicer::new(&mesh).unwrap();
            for &(p, q) in d.degenerate_levels {
                for shift in [Rat::new(0.into(), 1.into()), Rat::new(1.into(), 7.into())] {
                    let c = Rat::new(p.into(), q.into()) + shift;
                    let ls = slicer.slice_at(&c).unwrap();
                    for ex in [Exactness::Rounded, Exactness::WithExact] {
                        let text = level_text(&ls, ex);
                        assert_eq!(
                            String::from_utf8(text.to_bytes()).unwrap(),
                            String::from_utf8(reference(&ls, ex)).unwrap(),
                            "{} at {}",
                            d.name,
                            rat_to_string(&c)
                        );
                        let mut written = Vec::new();
                        text.write_to(&mut written).unwrap();
                        assert_eq!(written, text.to_bytes());
                        compared += 1;
                    }
                }
            }
        }
        assert!(compared > 50);
    }
}
