//! Input: an exact level set with its JSON header. Output: bytes (for
//! pickling), and back. Every value is kept exactly: rationals as their
//! integers' bytes, loop points as the integers the slicer holds (or exact
//! rationals), the rounded areas as their bits, so a level unpickled
//! writes the same JSON, byte for byte. The layout is private to this
//! version of the package (a version tag is checked).

use num_bigint::{BigInt, Sign as BigSign};
use std::sync::Arc;
use wmslice::classify::{ExtremumKind, Facing, RidgeKind};
use wmslice::exact::point::LoopPoint;
use wmslice::exact::rational::Rat;
use wmslice::exact::{Point2, Sign};
use wmslice::ids::{EdgeId, FaceId, VertexId};
use wmslice::levelset::{ExtremalPoint, FaceRegion, LevelSet, Loop, Ridge, Saddle};
use wmslice::nest::Role;
use wmslice::output::json::MeshHeader;
use wmslice::segment::CutPoint;

const TAG: &[u8] = b"wmslice-level-v2";

struct W(Vec<u8>);

impl W {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn len(&mut self, v: usize) {
        self.u64(v as u64);
    }
    fn i128(&mut self, v: i128) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn bytes(&mut self, b: &[u8]) {
        self.len(b.len());
        self.0.extend_from_slice(b);
    }
    fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }
    fn int(&mut self, i: &BigInt) {
        self.bytes(&i.to_signed_bytes_le());
    }
    fn rat(&mut self, r: &Rat) {
        self.int(r.numer());
        self.int(r.denom());
    }
    fn point2(&mut self, p: &Point2) {
        self.rat(&p.x);
        self.rat(&p.y);
    }
    fn loop_point(&mut self, p: &LoopPoint) {
        match p.as_integers() {
            Some((x, y, w, e)) => {
                self.u8(0);
                self.i128(x);
                self.i128(y);
                self.i128(w);
                self.u32(e as u32);
            }
            None => {
                self.u8(1);
                self.point2(&p.exact());
            }
        }
    }
    fn lp(&mut self, l: &Loop) {
        self.len(l.cuts.len());
        for c in &l.cuts {
            match c {
                CutPoint::OnEdge(e) => {
                    self.u8(0);
                    self.u32(e.0);
                }
                CutPoint::AtVertex(v) => {
                    self.u8(1);
                    self.u32(v.0);
                }
            }
        }
        self.len(l.points.len());
        for p in &l.points {
            self.loop_point(p);
        }
        self.u8(match l.orientation {
            Sign::Negative => 0,
            Sign::Zero => 1,
            Sign::Positive => 2,
        });
        self.u8(match l.role {
            Role::Outer => 0,
            Role::Hole => 1,
        });
        match l.parent {
            None => self.u8(0),
            Some(p) => {
                self.u8(1);
                self.len(p);
            }
        }
        self.u8(l.collapsed.into());
        self.len(l.crossings.len());
        for e in &l.crossings {
            self.u32(e.0);
        }
    }
    fn loops(&mut self, ls: &[Loop]) {
        self.len(ls.len());
        for l in ls {
            self.lp(l);
        }
    }
}

/// The bytes of a level, its header and whether it was sliced exact.
pub fn encode(ls: &LevelSet, header: &MeshHeader, exact: bool) -> Vec<u8> {
    let mut w = W(Vec::new());
    w.0.extend_from_slice(TAG);
    w.len(header.vertices);
    w.len(header.faces);
    w.str(&header.sha256);
    // Bit 0: a snap grid follows; bit 1: a count of dropped collapsed
    // faces follows; bit 2: a count of welded vertices follows, after it
    // (older encodings write 0 to 3).
    let flags = u8::from(header.snap.is_some())
        | (u8::from(header.dropped_collapsed.is_some()) << 1)
        | (u8::from(header.welded.is_some()) << 2);
    w.u8(flags);
    if let Some(s) = &header.snap {
        w.str(s);
    }
    if let Some(n) = header.dropped_collapsed {
        w.len(n);
    }
    if let Some(n) = header.welded {
        w.len(n);
    }
    w.u8(exact.into());
    w.rat(&ls.level);
    w.loops(&ls.contours);
    w.len(ls.regions.len());
    for r in &ls.regions {
        w.u8(match r.facing {
            Facing::Up => 0,
            Facing::Down => 1,
            Facing::Flat => 2,
        });
        w.len(r.faces.len());
        for f in &r.faces {
            w.u32(f.0);
        }
        w.rat(&r.area);
        w.loops(&r.boundary);
    }
    w.len(ls.ridges.len());
    for r in &ls.ridges {
        w.u8(match r.kind {
            RidgeKind::Ridge => 0,
            RidgeKind::Valley => 1,
        });
        w.u8(r.closed.into());
        w.len(r.vertices.len());
        for v in &r.vertices {
            w.u32(v.0);
        }
        w.len(r.points.len());
        for p in &r.points {
            w.point2(p);
        }
    }
    w.len(ls.extrema.len());
    for e in &ls.extrema {
        w.u32(e.vertex.0);
        w.u8(match e.kind {
            ExtremumKind::Min => 0,
            ExtremumKind::Max => 1,
        });
        w.point2(&e.point);
    }
    w.len(ls.saddles.len());
    for s in &ls.saddles {
        w.u32(s.vertex.0);
        w.u32(s.branches);
    }
    let shared = Arc::ptr_eq(&ls.contours, &ls.below) && Arc::ptr_eq(&ls.contours, &ls.above);
    w.u8(shared.into());
    if !shared {
        w.loops(&ls.below);
        w.loops(&ls.above);
    }
    w.0
}

struct R<'a>(&'a [u8]);

type Res<T> = Result<T, String>;

impl<'a> R<'a> {
    fn take(&mut self, n: usize) -> Res<&'a [u8]> {
        if self.0.len() < n {
            return Err("truncated".into());
        }
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        Ok(a)
    }
    fn u8(&mut self) -> Res<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Res<u32> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().map_err(|_| "u32")?,
        ))
    }
    fn u64(&mut self) -> Res<u64> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().map_err(|_| "u64")?,
        ))
    }
    fn len(&mut self) -> Res<usize> {
        let n = usize::try_from(self.u64()?).map_err(|_| "length")?;
        // Every item takes at least one byte: refuse lengths beyond the
        // data before allocating for them.
        if n > self.0.len() {
            return Err("length beyond the data".into());
        }
        Ok(n)
    }
    fn i128(&mut self) -> Res<i128> {
        Ok(i128::from_le_bytes(
            self.take(16)?.try_into().map_err(|_| "i128")?,
        ))
    }
    fn bool(&mut self) -> Res<bool> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err("bool".into()),
        }
    }
    fn bytes(&mut self) -> Res<&'a [u8]> {
        let n = self.len()?;
        self.take(n)
    }
    fn str(&mut self) -> Res<String> {
        String::from_utf8(self.bytes()?.to_vec()).map_err(|_| "utf-8".into())
    }
    fn int(&mut self) -> Res<BigInt> {
        Ok(BigInt::from_signed_bytes_le(self.bytes()?))
    }
    fn rat(&mut self) -> Res<Rat> {
        let n = self.int()?;
        let d = self.int()?;
        if d.sign() != BigSign::Plus {
            return Err("denominator".into());
        }
        Ok(Rat::new(n, d))
    }
    fn point2(&mut self) -> Res<Point2> {
        Ok(Point2 {
            x: self.rat()?,
            y: self.rat()?,
        })
    }
    fn loop_point(&mut self) -> Res<LoopPoint> {
        match self.u8()? {
            0 => {
                let (x, y, w) = (self.i128()?, self.i128()?, self.i128()?);
                let e = self.u32()? as i32;
                // A sliced point's exponent comes from doubles (2^-1074 ..
                // 2^1024) and a snap grid's power of two (a grid outside
                // 2^-1200 .. 2^1200 collapses every double): |e| stays below
                // 2^12. Beyond 2^14 the bytes were not written by `encode`,
                // and the exact value (2^e wide) would take forever.
                if !(-(1 << 14)..=(1 << 14)).contains(&e) {
                    return Err("point exponent".into());
                }
                LoopPoint::from_integers(x, y, w, e).ok_or_else(|| "point".into())
            }
            1 => Ok(LoopPoint::from(self.point2()?)),
            _ => Err("point tag".into()),
        }
    }
    fn lp(&mut self) -> Res<Loop> {
        let n = self.len()?;
        let mut cuts = Vec::with_capacity(n);
        for _ in 0..n {
            cuts.push(match self.u8()? {
                0 => CutPoint::OnEdge(EdgeId(self.u32()?)),
                1 => CutPoint::AtVertex(VertexId(self.u32()?)),
                _ => return Err("cut tag".into()),
            });
        }
        let n = self.len()?;
        let mut points = Vec::with_capacity(n);
        for _ in 0..n {
            points.push(self.loop_point()?);
        }
        let orientation = match self.u8()? {
            0 => Sign::Negative,
            1 => Sign::Zero,
            2 => Sign::Positive,
            _ => return Err("sign".into()),
        };
        let role = match self.u8()? {
            0 => Role::Outer,
            1 => Role::Hole,
            _ => return Err("role".into()),
        };
        let parent = if self.bool()? {
            Some(self.len_value()?)
        } else {
            None
        };
        let collapsed = self.bool()?;
        let n = self.len()?;
        let mut crossings = Vec::with_capacity(n);
        for _ in 0..n {
            crossings.push(EdgeId(self.u32()?));
        }
        Ok(Loop {
            cuts,
            points,
            orientation,
            role,
            parent,
            collapsed,
            crossings,
        })
    }
    /// A plain number (not a length of what follows).
    fn len_value(&mut self) -> Res<usize> {
        usize::try_from(self.u64()?).map_err(|_| "index".into())
    }
    fn loops(&mut self) -> Res<Vec<Loop>> {
        let n = self.len()?;
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            out.push(self.lp()?);
        }
        Ok(out)
    }
}

/// A level, its header and its exactness from [`encode`]'s bytes.
pub fn decode(data: &[u8]) -> Res<(LevelSet, MeshHeader, bool)> {
    let mut r = R(data);
    if r.take(TAG.len())? != TAG {
        return Err("not this package's level format".into());
    }
    let (vertices, faces, sha256) = (r.len_value()?, r.len_value()?, r.str()?);
    let flags = r.u8()?;
    if flags > 7 {
        return Err("not this package's level format (header flags)".into());
    }
    let snap = if flags & 1 == 1 { Some(r.str()?) } else { None };
    let dropped_collapsed = if flags & 2 == 2 {
        Some(r.len_value()?)
    } else {
        None
    };
    let welded = if flags & 4 == 4 {
        Some(r.len_value()?)
    } else {
        None
    };
    let header = MeshHeader {
        vertices,
        faces,
        sha256,
        snap,
        welded,
        dropped_collapsed,
    };
    let exact = r.bool()?;
    let level = r.rat()?;
    let contours = Arc::new(r.loops()?);
    let n = r.len()?;
    let mut regions = Vec::with_capacity(n);
    for _ in 0..n {
        let facing = match r.u8()? {
            0 => Facing::Up,
            1 => Facing::Down,
            2 => Facing::Flat,
            _ => return Err("facing".into()),
        };
        let k = r.len()?;
        let mut faces = Vec::with_capacity(k);
        for _ in 0..k {
            faces.push(FaceId(r.u32()?));
        }
        regions.push(FaceRegion {
            facing,
            faces,
            area: r.rat()?,
            boundary: r.loops()?,
        });
    }
    let n = r.len()?;
    let mut ridges = Vec::with_capacity(n);
    for _ in 0..n {
        let kind = match r.u8()? {
            0 => RidgeKind::Ridge,
            1 => RidgeKind::Valley,
            _ => return Err("ridge kind".into()),
        };
        let closed = r.bool()?;
        let k = r.len()?;
        let mut vertices = Vec::with_capacity(k);
        for _ in 0..k {
            vertices.push(VertexId(r.u32()?));
        }
        let k = r.len()?;
        let mut points = Vec::with_capacity(k);
        for _ in 0..k {
            points.push(r.point2()?);
        }
        ridges.push(Ridge {
            kind,
            closed,
            vertices,
            points,
        });
    }
    let n = r.len()?;
    let mut extrema = Vec::with_capacity(n);
    for _ in 0..n {
        let vertex = VertexId(r.u32()?);
        let kind = match r.u8()? {
            0 => ExtremumKind::Min,
            1 => ExtremumKind::Max,
            _ => return Err("extremum kind".into()),
        };
        extrema.push(ExtremalPoint {
            vertex,
            kind,
            point: r.point2()?,
        });
    }
    let n = r.len()?;
    let mut saddles = Vec::with_capacity(n);
    for _ in 0..n {
        saddles.push(Saddle {
            vertex: VertexId(r.u32()?),
            branches: r.u32()?,
        });
    }
    let (below, above) = if r.bool()? {
        (Arc::clone(&contours), Arc::clone(&contours))
    } else {
        (Arc::new(r.loops()?), Arc::new(r.loops()?))
    };
    if !r.0.is_empty() {
        return Err("trailing bytes".into());
    }
    Ok((
        LevelSet {
            level,
            contours,
            regions,
            ridges,
            extrema,
            saddles,
            below,
            above,
        },
        header,
        exact,
    ))
}
