//! Input: a parsed JSON [`Value`]. Output: the typed `wmslice-levelset`
//! [`Document`] of SPEC section 9, with every number still as its text, or
//! a [`FormatError`] naming the JSON path that does not have the fixed
//! shape (missing key, wrong type, written without `--exact`).
//!
//! Only the shape is checked here; whether the content is right (ids in
//! range, exact values, counts) is the verifier's job, reported as
//! violations.

use super::json::Value;

/// The document does not have the `wmslice-levelset` shape.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FormatError {
    /// `format` is not `"wmslice-levelset"`.
    #[error("not a wmslice-levelset document (`format` is {found})")]
    NotLevelset {
        /// What `format` holds (as JSON).
        found: String,
    },
    /// An unsupported `version`.
    #[error("unsupported version {found}: this verifier reads version 1")]
    Version {
        /// What `version` holds (as JSON).
        found: String,
    },
    /// A fixed key is missing.
    #[error("{path}: missing key `{key}`")]
    Missing {
        /// Where.
        path: String,
        /// The key.
        key: &'static str,
    },
    /// A key of exact output is missing: the result was written without
    /// `--exact`.
    #[error("{path}: missing key `{key}`: the result was written without --exact (slice again with --exact)")]
    NotExact {
        /// Where.
        path: String,
        /// The key.
        key: &'static str,
    },
    /// A value of the wrong type.
    #[error("{path}: expected {expected}")]
    Shape {
        /// Where.
        path: String,
        /// What the format requires there.
        expected: &'static str,
    },
}

/// The mesh a point lies on, as the result claims (`on`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum On {
    /// `{"edge": id}`: the crossing of an edge.
    Edge(u64),
    /// `{"vertex": id}`: a vertex on the plane.
    Vertex(u64),
}

/// An `(x, y)` pair of number texts.
pub type XyText = [String; 2];

/// A loop as written (`Loop` of SPEC section 9, with exact output).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoopDoc {
    /// Rounded points (number texts).
    pub points: Vec<XyText>,
    /// Exact points (`"p/q"` texts).
    pub exact: Vec<XyText>,
    /// The mesh element of each point.
    pub on: Vec<On>,
    /// Rounded signed area (number text).
    pub area: String,
    /// Exact signed area text.
    pub area_exact: String,
    /// `"outer"` or `"hole"`.
    pub role: String,
    /// Parent index.
    pub parent: Option<u64>,
    /// `"collapsed": true` (L-, L+ only); false when absent.
    pub collapsed: bool,
}

/// A face region (`faces` entry).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegionDoc {
    /// `"up"`, `"down"` or `"flat"`.
    pub facing: String,
    /// Face ids.
    pub faces: Vec<u64>,
    /// Exact area text.
    pub area: String,
    /// Boundary loops dF.
    pub boundary: Vec<LoopDoc>,
}

/// A ridge or valley polyline.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RidgeDoc {
    /// `"ridge"` or `"valley"`.
    pub kind: String,
    /// Closed cycle.
    pub closed: bool,
    /// Vertex ids in order.
    pub vertices: Vec<u64>,
    /// Rounded points.
    pub points: Vec<XyText>,
}

/// An extremal point.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PointDoc {
    /// Vertex id.
    pub vertex: u64,
    /// `"min"` or `"max"`.
    pub kind: String,
    /// Rounded point.
    pub point: XyText,
}

/// A saddle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SaddleDoc {
    /// Vertex id.
    pub vertex: u64,
    /// Claimed number of branches `2m`.
    pub branches: u64,
}

/// One level as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LevelDoc {
    /// The level text.
    pub z: String,
    /// S_O.
    pub contours: Vec<LoopDoc>,
    /// F with dF.
    pub faces: Vec<RegionDoc>,
    /// S_NO.
    pub ridges: Vec<RidgeDoc>,
    /// P.
    pub points: Vec<PointDoc>,
    /// Saddles.
    pub saddles: Vec<SaddleDoc>,
    /// L-.
    pub below: Vec<LoopDoc>,
    /// L+.
    pub above: Vec<LoopDoc>,
}

/// The `mesh` header as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HeaderDoc {
    /// Vertex count.
    pub vertices: u64,
    /// Face count.
    pub faces: u64,
    /// SHA-256 text.
    pub sha256: String,
    /// Snap grid text, or `None` for null.
    pub snap: Option<String>,
    /// `welded` when present: the result was computed with the vertices at
    /// one point merged, and this many were.
    pub welded: Option<u64>,
    /// `dropped_collapsed` when present: the result was computed with the
    /// faces that use one vertex twice removed, and this many were.
    pub dropped_collapsed: Option<u64>,
}

/// A whole `wmslice-levelset` document.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Document {
    /// The mesh header.
    pub mesh: HeaderDoc,
    /// The levels in file order.
    pub levels: Vec<LevelDoc>,
}

/// Reads the header (`format`, `version`, `mesh`) of a document and checks
/// that `levels` is an array.
pub fn header(v: &Value) -> Result<HeaderDoc, FormatError> {
    let root = Ctx::root();
    object(v, &root)?;
    let get = |key: &'static str| {
        v.get(key).ok_or(FormatError::Missing {
            path: "$".into(),
            key,
        })
    };
    let format = get("format")?;
    if format.as_str() != Some("wmslice-levelset") {
        return Err(FormatError::NotLevelset {
            found: format.to_json(),
        });
    }
    let version = get("version")?;
    if version.as_number() != Some("1") {
        return Err(FormatError::Version {
            found: version.to_json(),
        });
    }
    let mut m = get("mesh")?.clone();
    let mc = root.key("mesh");
    object(&m, &mc)?;
    let vertices = integer(field(&mut m, &mc, "vertices")?, &mc.key("vertices"))?;
    let faces = integer(field(&mut m, &mc, "faces")?, &mc.key("faces"))?;
    let sha256 = string(field(&mut m, &mc, "sha256")?, &mc.key("sha256"))?;
    let snap = match field(&mut m, &mc, "snap")? {
        Value::Null => None,
        s => Some(string(s, &mc.key("snap"))?),
    };
    let welded = match m.get_mut("welded") {
        Some(v) => Some(integer(v, &mc.key("welded"))?),
        None => None,
    };
    let dropped_collapsed = match m.get_mut("dropped_collapsed") {
        Some(v) => Some(integer(v, &mc.key("dropped_collapsed"))?),
        None => None,
    };
    if get("levels")?.as_array().is_none() {
        return Err(root.key("levels").shape("an array"));
    }
    Ok(HeaderDoc {
        vertices,
        faces,
        sha256,
        snap,
        welded,
        dropped_collapsed,
    })
}

/// Reads level `index` of a document from its JSON value (consumed: the
/// strings move into the typed level).
pub fn level(mut v: Value, index: usize) -> Result<LevelDoc, FormatError> {
    let root = Ctx::root();
    let levels = root.key("levels");
    level_at(&mut v, &levels.index(index))
}

/// Reads the typed document from a JSON value.
pub fn document(v: &Value) -> Result<Document, FormatError> {
    let mesh = header(v)?;
    let levels = match v.get("levels").and_then(Value::as_array) {
        Some(items) => items
            .iter()
            .enumerate()
            .map(|(i, l)| level(l.clone(), i))
            .collect::<Result<_, _>>()?,
        None => Vec::new(),
    };
    Ok(Document { mesh, levels })
}

/// A JSON path being read, for error messages: a chain of borrowed frames,
/// turned into text only when an error is reported.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    parent: Option<&'a Ctx<'a>>,
    seg: Seg<'a>,
}

#[derive(Clone, Copy)]
enum Seg<'a> {
    Root,
    Key(&'a str),
    Index(usize),
}

impl<'a> Ctx<'a> {
    fn root() -> Ctx<'static> {
        Ctx {
            parent: None,
            seg: Seg::Root,
        }
    }
    fn key(&'a self, k: &'a str) -> Ctx<'a> {
        Ctx {
            parent: Some(self),
            seg: Seg::Key(k),
        }
    }
    fn index(&'a self, i: usize) -> Ctx<'a> {
        Ctx {
            parent: Some(self),
            seg: Seg::Index(i),
        }
    }
    fn path(&self) -> String {
        let mut segs = Vec::new();
        let mut at = Some(self);
        while let Some(c) = at {
            segs.push(c.seg);
            at = c.parent;
        }
        let mut out = String::new();
        for s in segs.iter().rev() {
            match s {
                Seg::Root => out.push('$'),
                Seg::Key(k) => {
                    out.push('.');
                    out.push_str(k);
                }
                Seg::Index(i) => out.push_str(&format!("[{i}]")),
            }
        }
        out
    }
    fn shape(&self, expected: &'static str) -> FormatError {
        FormatError::Shape {
            path: self.path(),
            expected,
        }
    }
}

fn object(v: &Value, c: &Ctx) -> Result<(), FormatError> {
    match v {
        Value::Object(_) => Ok(()),
        _ => Err(c.shape("an object")),
    }
}

fn field<'v>(v: &'v mut Value, c: &Ctx, key: &'static str) -> Result<&'v mut Value, FormatError> {
    object(v, c)?;
    v.get_mut(key).ok_or_else(|| FormatError::Missing {
        path: c.path(),
        key,
    })
}

/// A key that only exact output writes.
fn exact_field<'v>(
    v: &'v mut Value,
    c: &Ctx,
    key: &'static str,
) -> Result<&'v mut Value, FormatError> {
    object(v, c)?;
    v.get_mut(key).ok_or_else(|| FormatError::NotExact {
        path: c.path(),
        key,
    })
}

fn string(v: &mut Value, c: &Ctx) -> Result<String, FormatError> {
    match v {
        Value::String(s) => Ok(std::mem::take(s)),
        _ => Err(c.shape("a string")),
    }
}

fn number(v: &mut Value, c: &Ctx) -> Result<String, FormatError> {
    match v {
        Value::Number(s) => Ok(std::mem::take(s)),
        _ => Err(c.shape("a number")),
    }
}

fn boolean(v: &mut Value, c: &Ctx) -> Result<bool, FormatError> {
    match v {
        Value::Bool(b) => Ok(*b),
        _ => Err(c.shape("true or false")),
    }
}

fn integer(v: &mut Value, c: &Ctx) -> Result<u64, FormatError> {
    v.as_number()
        .filter(|t| t.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|t| t.parse().ok())
        .ok_or_else(|| c.shape("a non-negative integer"))
}

fn array<T>(
    v: &mut Value,
    c: &Ctx,
    item: impl Fn(&mut Value, &Ctx) -> Result<T, FormatError>,
) -> Result<Vec<T>, FormatError> {
    let items = v.as_array_mut().ok_or_else(|| c.shape("an array"))?;
    items
        .iter_mut()
        .enumerate()
        .map(|(i, x)| item(x, &c.index(i)))
        .collect()
}

fn pair(
    v: &mut Value,
    c: &Ctx,
    what: fn(&mut Value, &Ctx) -> Result<String, FormatError>,
) -> Result<XyText, FormatError> {
    match v.as_array_mut().map(Vec::as_mut_slice) {
        Some([x, y]) => Ok([what(x, &c.index(0))?, what(y, &c.index(1))?]),
        _ => Err(c.shape("an [x, y] pair")),
    }
}

fn xy(v: &mut Value, c: &Ctx) -> Result<XyText, FormatError> {
    pair(v, c, number)
}

fn xy_exact(v: &mut Value, c: &Ctx) -> Result<XyText, FormatError> {
    pair(v, c, string)
}

fn on(v: &mut Value, c: &Ctx) -> Result<On, FormatError> {
    const SHAPE: &str = "{\"edge\": id} or {\"vertex\": id}";
    match v {
        Value::Object(fields) if fields.len() == 1 => {
            let (k, id) = &mut fields[0];
            let id = integer(id, &c.key(k))?;
            match k.as_str() {
                "edge" => Ok(On::Edge(id)),
                "vertex" => Ok(On::Vertex(id)),
                _ => Err(c.shape(SHAPE)),
            }
        }
        _ => Err(c.shape(SHAPE)),
    }
}

fn loop_doc(v: &mut Value, c: &Ctx) -> Result<LoopDoc, FormatError> {
    let parent = match field(v, c, "parent")? {
        Value::Null => None,
        p => Some(integer(p, &c.key("parent"))?),
    };
    Ok(LoopDoc {
        points: array(field(v, c, "points")?, &c.key("points"), xy)?,
        exact: array(exact_field(v, c, "exact")?, &c.key("exact"), xy_exact)?,
        on: array(exact_field(v, c, "on")?, &c.key("on"), on)?,
        area: number(field(v, c, "area")?, &c.key("area"))?,
        area_exact: string(exact_field(v, c, "area_exact")?, &c.key("area_exact"))?,
        role: string(field(v, c, "role")?, &c.key("role"))?,
        parent,
        collapsed: match v.get_mut("collapsed") {
            None => false,
            Some(b) => boolean(b, &c.key("collapsed"))?,
        },
    })
}

fn loops(v: &mut Value, c: &Ctx, key: &'static str) -> Result<Vec<LoopDoc>, FormatError> {
    array(field(v, c, key)?, &c.key(key), loop_doc)
}

fn region(v: &mut Value, c: &Ctx) -> Result<RegionDoc, FormatError> {
    Ok(RegionDoc {
        facing: string(field(v, c, "facing")?, &c.key("facing"))?,
        faces: array(field(v, c, "faces")?, &c.key("faces"), integer)?,
        area: string(field(v, c, "area")?, &c.key("area"))?,
        boundary: loops(v, c, "boundary")?,
    })
}

fn ridge(v: &mut Value, c: &Ctx) -> Result<RidgeDoc, FormatError> {
    Ok(RidgeDoc {
        kind: string(field(v, c, "kind")?, &c.key("kind"))?,
        closed: boolean(field(v, c, "closed")?, &c.key("closed"))?,
        vertices: array(field(v, c, "vertices")?, &c.key("vertices"), integer)?,
        points: array(field(v, c, "points")?, &c.key("points"), xy)?,
    })
}

fn point(v: &mut Value, c: &Ctx) -> Result<PointDoc, FormatError> {
    Ok(PointDoc {
        vertex: integer(field(v, c, "vertex")?, &c.key("vertex"))?,
        kind: string(field(v, c, "kind")?, &c.key("kind"))?,
        point: xy(field(v, c, "point")?, &c.key("point"))?,
    })
}

fn saddle(v: &mut Value, c: &Ctx) -> Result<SaddleDoc, FormatError> {
    Ok(SaddleDoc {
        vertex: integer(field(v, c, "vertex")?, &c.key("vertex"))?,
        branches: integer(field(v, c, "branches")?, &c.key("branches"))?,
    })
}

fn level_at(v: &mut Value, c: &Ctx) -> Result<LevelDoc, FormatError> {
    Ok(LevelDoc {
        z: string(field(v, c, "z")?, &c.key("z"))?,
        contours: loops(v, c, "contours")?,
        faces: array(field(v, c, "faces")?, &c.key("faces"), region)?,
        ridges: array(field(v, c, "ridges")?, &c.key("ridges"), ridge)?,
        points: array(field(v, c, "points")?, &c.key("points"), point)?,
        saddles: array(field(v, c, "saddles")?, &c.key("saddles"), saddle)?,
        below: loops(v, c, "below")?,
        above: loops(v, c, "above")?,
    })
}

#[cfg(test)]
mod tests {
    use super::super::json::parse;
    use super::*;

    #[test]
    fn wrong_shapes_name_their_path() {
        let e = document(&parse(r#"{"format":"x"}"#).unwrap()).unwrap_err();
        assert!(matches!(e, FormatError::NotLevelset { .. }));
        let head = r#""format":"wmslice-levelset","version":1,"mesh":{"vertices":4,"faces":4,"sha256":"00","snap":null}"#;
        let e = document(&parse(&format!("{{{head}}}")).unwrap()).unwrap_err();
        assert_eq!(
            e,
            FormatError::Missing {
                path: "$".into(),
                key: "levels"
            }
        );
        let lvl = r#"{"z":"0","contours":[{"points":[[0,0]],"area":0,"role":"outer","parent":null}],"faces":[],"ridges":[],"points":[],"saddles":[],"below":[],"above":[]}"#;
        let e = document(&parse(&format!("{{{head},\"levels\":[{lvl}]}}")).unwrap()).unwrap_err();
        assert_eq!(
            e,
            FormatError::NotExact {
                path: "$.levels[0].contours[0]".into(),
                key: "exact"
            }
        );
        let e =
            document(&parse(&format!("{{{head},\"levels\":[{{\"z\":3}}]}}")).unwrap()).unwrap_err();
        assert_eq!(e.to_string(), "$.levels[0].z: expected a string");
    }
}
