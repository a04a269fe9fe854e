//! Input: 3MF bytes (a zip package). Output: one [`Mesh`] holding every
//! object that the `<build>` places, each `<item>` and `<component>`
//! transform applied exactly; and a minimal 3MF writer.
//!
//! Reading: `zip` (deflate only) opens the package; the root model part is
//! the one `_rels/.rels` names (default `3D/3dmodel.model`). Each part is
//! inflated only if its declared size is under [`MAX_PART_BYTES`] and under
//! [`MAX_RATIO`] times its compressed size (parts under [`RATIO_FREE_BYTES`]
//! are exempt), and is read through `take`, so a lying header cannot inflate
//! more. `quick-xml` parses the model with a depth limit ([`MAX_XML_DEPTH`]).
//! Components are expanded recursively (depth limit [`MAX_COMPONENT_DEPTH`],
//! cycles refused) and the instanced element count is bounded. A component
//! or item of the root part may name the object's model part (the
//! production extension's `p:path`, as Bambu Studio writes every object);
//! each part named is read once, under the same limits (and all parts
//! together under [`MAX_RATIO`] times the package's size), and may not name
//! others itself (as the extension requires).
//!
//! Coordinates and transform entries are read as the nearest `f64` (like
//! every text format here); transforms are then applied exactly, and a
//! vertex whose exact image is not an `f64` keeps that image
//! ([`ExactPositions`]: only snapping may place it).
//! Each placed object keeps its own vertices (nothing is welded), so
//! out-of-range triangle indices are an error here, not left to validation.

use std::collections::HashMap;
use std::io::{Cursor, Read, Seek, Write};

use quick_xml::events::{BytesStart, Event};
use quick_xml::XmlVersion;

use super::exact_positions::{ExactPositions, PlacedVertex};
use super::exact_transform::{apply_chain, Affine, Image};
use super::{write_err, LoadError, LoadNote, LoadReport, MeshFormat, SaveError, MAX_ELEMENTS};
use crate::exact::rational::rat_to_f64;
use crate::ids::VertexId;
use crate::mesh::Mesh;

const FORMAT: MeshFormat = MeshFormat::ThreeMf;

/// The largest declared uncompressed size of a part: 2 GiB.
pub const MAX_PART_BYTES: u64 = 2 << 30;
/// The largest accepted ratio of uncompressed to compressed size.
pub const MAX_RATIO: u64 = 200;
/// Parts up to this size are not held to [`MAX_RATIO`].
pub const RATIO_FREE_BYTES: u64 = 1 << 20;
/// The deepest accepted XML nesting.
pub const MAX_XML_DEPTH: usize = 64;
/// The deepest accepted nesting of components.
pub const MAX_COMPONENT_DEPTH: usize = 32;
/// Instancing may multiply the parsed elements by at most this factor
/// (plus [`INSTANCE_ALLOWANCE`]), so a small file cannot expand without bound.
pub const MAX_INSTANCE_FACTOR: u64 = 256;
/// Instanced elements always allowed, whatever the file size.
pub const INSTANCE_ALLOWANCE: u64 = 1 << 20;

const ROOT_MODEL: &str = "3D/3dmodel.model";
const MODEL_REL_TYPE: &str = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";

/// Reads a 3MF package.
pub(super) fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport, ExactPositions), LoadError> {
    if is_xml(bytes) {
        // A model part taken out of its package (test suites keep them so):
        // named as such rather than as a zip archive without a directory.
        return Err(LoadError::Parse {
            format: FORMAT,
            line: None,
            message: format!(
                "the file is XML, not a zip package (a 3MF file is a zip package holding the model part `{ROOT_MODEL}`)"
            ),
        });
    }
    let mut archive = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|source| LoadError::ZipArchive { source })?;
    let root = root_model_name(&mut archive)?;
    let xml = read_part(&mut archive, &root)?;
    let model = parse_model(&xml, &root, true)?;
    // The other parts the root refers to, each read once. Each part small
    // enough to be free of the ratio limit, many of them could still
    // inflate without bound: all parts together are held to the ratio
    // against the whole package.
    let package = bytes.len() as u64;
    let cap = RATIO_FREE_BYTES.max(package.saturating_mul(MAX_RATIO));
    let mut inflated = xml.len() as u64;
    drop(xml);
    // In name order: which part an error names does not depend on the
    // objects' (hashed) order.
    let mut referred: Vec<&str> = model
        .items
        .iter()
        .chain(model.objects.values().flat_map(|o| &o.components))
        .filter_map(|p| p.part.as_deref())
        .collect();
    referred.sort_unstable();
    referred.dedup();
    let mut parts = HashMap::new();
    for name in referred {
        let xml = read_part(&mut archive, name)?;
        inflated = inflated.saturating_add(xml.len() as u64);
        if inflated > cap {
            return Err(LoadError::ZipBomb {
                name: name.to_owned(),
                compressed: package,
                inflated,
                ratio_limit: MAX_RATIO,
            });
        }
        parts.insert(name.to_owned(), parse_model(&xml, name, false)?);
    }
    build(&model, &parts)
}

/// Whether `bytes` start as XML does: a `<` first, after an optional UTF-8
/// byte-order mark and white space (a zip package starts with `PK`).
fn is_xml(bytes: &[u8]) -> bool {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    text.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'<')
}

/// The root model part named by `_rels/.rels`, or the default.
fn root_model_name<R: Read + Seek>(archive: &mut zip::ZipArchive<R>) -> Result<String, LoadError> {
    let rels_name = "_rels/.rels";
    if archive.index_for_name(rels_name).is_none() {
        return Ok(ROOT_MODEL.to_owned());
    }
    let rels = read_part(archive, rels_name)?;
    let mut reader = quick_xml::Reader::from_reader(rels.as_slice());
    let mut depth = 0usize;
    loop {
        let event = reader.read_event().map_err(|source| LoadError::Xml {
            part: rels_name.to_owned(),
            position: reader.error_position(),
            source,
        })?;
        // The element and the level it stands at. An empty element closes
        // itself: its siblings (a `<Relationship/>` each) do not add up.
        let (e, level) = match event {
            Event::Start(e) => {
                depth += 1;
                (e, depth)
            }
            Event::Empty(e) => (e, depth + 1),
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        if level > MAX_XML_DEPTH {
            return Err(LoadError::XmlTooDeep {
                part: rels_name.to_owned(),
                limit: MAX_XML_DEPTH,
            });
        }
        if e.local_name().as_ref() == "Relationship" {
            let attrs = attributes(&e, rels_name)?;
            let is_model = attrs
                .iter()
                .any(|(k, v)| k == "Type" && v == MODEL_REL_TYPE);
            if let Some(target) = get(&attrs, "Target").filter(|_| is_model) {
                return Ok(target.trim_start_matches('/').to_owned());
            }
        }
    }
    Ok(ROOT_MODEL.to_owned())
}

/// Inflates one part under the size and ratio limits.
fn read_part<R: Read + Seek>(
    archive: &mut zip::ZipArchive<R>,
    name: &str,
) -> Result<Vec<u8>, LoadError> {
    let file = match archive.by_name(name) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => {
            return Err(LoadError::ZipEntryMissing {
                name: name.to_owned(),
            })
        }
        Err(source) => return Err(LoadError::ZipArchive { source }),
    };
    let declared = file.size();
    let compressed = file.compressed_size();
    if declared > MAX_PART_BYTES {
        return Err(LoadError::EntryTooLarge {
            name: name.to_owned(),
            declared,
            limit: MAX_PART_BYTES,
        });
    }
    let ratio_cap = RATIO_FREE_BYTES.max(compressed.saturating_mul(MAX_RATIO));
    if declared > ratio_cap {
        return Err(LoadError::ZipBomb {
            name: name.to_owned(),
            compressed,
            inflated: declared,
            ratio_limit: MAX_RATIO,
        });
    }
    let bomb = |inflated: u64| LoadError::ZipBomb {
        name: name.to_owned(),
        compressed,
        inflated,
        ratio_limit: MAX_RATIO,
    };
    let mut buf = Vec::new();
    // `zip` stops a part at its declared size too (an `InvalidData` error
    // saying so); `take` makes the bound ours whatever the reader does.
    if let Err(e) = file.take(declared + 1).read_to_end(&mut buf) {
        let past_declared = e.kind() == std::io::ErrorKind::InvalidData
            && e.to_string().contains("larger than its declared");
        return Err(if past_declared {
            bomb(declared + 1)
        } else {
            LoadError::ZipArchive {
                source: zip::result::ZipError::Io(e),
            }
        });
    }
    if buf.len() as u64 > declared {
        return Err(bomb(buf.len() as u64));
    }
    Ok(buf)
}

/// The attributes of an element as (local name, normalized value).
fn attributes(e: &BytesStart<'_>, part: &str) -> Result<Vec<(String, String)>, LoadError> {
    let xml_err = |source: quick_xml::Error| LoadError::Xml {
        part: part.to_owned(),
        position: 0,
        source,
    };
    let mut out = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| xml_err(err.into()))?;
        let key = a.key.local_name().as_ref().to_owned();
        let value = a
            .normalized_value(XmlVersion::Implicit1_0)
            .map_err(xml_err)?
            .into_owned();
        out.push((key, value));
    }
    Ok(out)
}

/// What an object is for (its `type`; the 3MF core specification's five).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum ObjectType {
    /// A part (the default).
    #[default]
    Model,
    /// A solid support, printed as a solid: sliced with the parts.
    SolidSupport,
    /// A support structure, which need not be closed: not sliced.
    Support,
    /// A surface, which need not be closed: not sliced.
    Surface,
    /// Not to be printed: a build item may not place it.
    Other,
}

impl ObjectType {
    fn parse(attrs: &[(String, String)]) -> Result<ObjectType, LoadError> {
        Ok(match get(attrs, "type").map(str::trim) {
            None | Some("model") => ObjectType::Model,
            Some("solidsupport") => ObjectType::SolidSupport,
            Some("support") => ObjectType::Support,
            Some("surface") => ObjectType::Surface,
            Some("other") => ObjectType::Other,
            Some(t) => {
                return Err(bad_attr(
                    "object",
                    "type",
                    format!(
                    "is not an object type: `{t}` (model, solidsupport, support, surface or other)"
                ),
                ))
            }
        })
    }

    /// Whether objects of this type are sliced (a closed solid is expected).
    fn is_solid(self) -> bool {
        matches!(self, ObjectType::Model | ObjectType::SolidSupport)
    }
}

/// One `<object>`: a mesh, or components, or nothing this reader uses.
#[derive(Debug, Default)]
struct Object {
    kind: ObjectType,
    /// Its mesh has a beam lattice (the beam lattice extension).
    beam_lattice: bool,
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    components: Vec<Placement>,
}

/// A reference to an object with its transform (an item or a component).
#[derive(Debug)]
struct Placement {
    /// The model part holding the object, when another than the referring
    /// one (the production extension's `p:path`, without its leading `/`).
    part: Option<String>,
    object: u64,
    transform: Affine,
}

#[derive(Debug, Default)]
struct Model {
    unit: Option<String>,
    objects: HashMap<u64, Object>,
    items: Vec<Placement>,
    /// Elements parsed (vertices + triangles), to bound instancing.
    parsed: u64,
}

fn bad_attr(element: &'static str, attribute: &'static str, problem: String) -> LoadError {
    LoadError::BadAttribute {
        element,
        attribute,
        problem,
    }
}

fn get<'a>(attrs: &'a [(String, String)], name: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.as_str())
}

fn required<'a>(
    attrs: &'a [(String, String)],
    element: &'static str,
    name: &'static str,
) -> Result<&'a str, LoadError> {
    get(attrs, name).ok_or_else(|| bad_attr(element, name, "is missing".to_owned()))
}

fn number(
    attrs: &[(String, String)],
    element: &'static str,
    name: &'static str,
) -> Result<f64, LoadError> {
    let text = required(attrs, element, name)?;
    text.trim()
        .parse::<f64>()
        .map_err(|_| bad_attr(element, name, format!("is not a number: `{text}`")))
}

fn id(
    attrs: &[(String, String)],
    element: &'static str,
    name: &'static str,
) -> Result<u64, LoadError> {
    let text = required(attrs, element, name)?;
    text.trim()
        .parse::<u64>()
        .map_err(|_| bad_attr(element, name, format!("is not an id: `{text}`")))
}

fn index(attrs: &[(String, String)], name: &'static str) -> Result<u32, LoadError> {
    let text = required(attrs, "triangle", name)?;
    text.trim()
        .parse::<u32>()
        .map_err(|_| bad_attr("triangle", name, format!("is not a vertex index: `{text}`")))
}

/// Parses `transform="m00 ... m32"` of an `<item>` or `<component>`.
fn transform(attrs: &[(String, String)], element: &'static str) -> Result<Affine, LoadError> {
    let Some(text) = get(attrs, "transform") else {
        return Ok(Affine::IDENTITY);
    };
    let invalid = || LoadError::InvalidTransform {
        element,
        text: text.to_owned(),
    };
    let mut m = [0.0; 12];
    let mut parts = text.split_ascii_whitespace();
    for slot in &mut m {
        let v: f64 = parts
            .next()
            .and_then(|t| t.parse().ok())
            .ok_or_else(invalid)?;
        if !v.is_finite() {
            return Err(invalid());
        }
        *slot = v;
    }
    if parts.next().is_some() {
        return Err(invalid());
    }
    Ok(Affine(m))
}

/// The model part an item or component refers to (the production
/// extension's `p:path`, as Bambu Studio writes every object), `None` for
/// its own part. Only the root part may refer to others (as the extension
/// requires of its non-root parts).
fn part_path(
    attrs: &[(String, String)],
    part: &str,
    root: bool,
) -> Result<Option<String>, LoadError> {
    match get(attrs, "path") {
        None => Ok(None),
        Some(p) if root => {
            let p = p.trim().trim_start_matches('/');
            Ok((p != part).then(|| p.to_owned()))
        }
        Some(p) => Err(LoadError::Unsupported {
            format: FORMAT,
            feature: format!(
                "reference to model part `{p}` from the non-root part `{part}` (production extension)"
            ),
        }),
    }
}

/// Parses a model part into objects and build items; `root` for the root
/// part, the only one whose references may name other parts.
fn parse_model(xml: &[u8], part: &str, root: bool) -> Result<Model, LoadError> {
    let mut reader = quick_xml::Reader::from_reader(xml);
    let mut model = Model::default();
    // Local names of the open elements, outermost first.
    let mut stack: Vec<String> = Vec::new();
    let mut current: Option<(u64, Object)> = None;

    loop {
        let event = reader.read_event().map_err(|source| LoadError::Xml {
            part: part.to_owned(),
            position: reader.error_position(),
            source,
        })?;
        let (e, empty) = match event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if stack.pop().as_deref() == Some("object") {
                    finish_object(&mut model, current.take())?;
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        if stack.len() >= MAX_XML_DEPTH {
            return Err(LoadError::XmlTooDeep {
                part: part.to_owned(),
                limit: MAX_XML_DEPTH,
            });
        }
        let name = e.local_name().as_ref().to_owned();
        let parent = |k: usize| {
            stack
                .len()
                .checked_sub(k)
                .and_then(|i| stack.get(i))
                .map(String::as_str)
        };
        match name.as_str() {
            "model" if stack.is_empty() => {
                let attrs = attributes(&e, part)?;
                model.unit = get(&attrs, "unit").map(str::to_owned);
            }
            "object" if parent(1) == Some("resources") => {
                let attrs = attributes(&e, part)?;
                let oid = id(&attrs, "object", "id")?;
                let kind = ObjectType::parse(&attrs)?;
                finish_object(&mut model, current.take())?;
                current = Some((
                    oid,
                    Object {
                        kind,
                        ..Object::default()
                    },
                ));
                if empty {
                    finish_object(&mut model, current.take())?;
                }
            }
            "vertex" if parent(1) == Some("vertices") && parent(2) == Some("mesh") => {
                if let Some((_, obj)) = current.as_mut() {
                    let attrs = attributes(&e, part)?;
                    let p = [
                        number(&attrs, "vertex", "x")?,
                        number(&attrs, "vertex", "y")?,
                        number(&attrs, "vertex", "z")?,
                    ];
                    if obj.positions.len() >= MAX_ELEMENTS {
                        return Err(too_many("vertices"));
                    }
                    obj.positions.push(p);
                    model.parsed += 1;
                }
            }
            "triangle" if parent(1) == Some("triangles") && parent(2) == Some("mesh") => {
                if let Some((_, obj)) = current.as_mut() {
                    let attrs = attributes(&e, part)?;
                    let t = [
                        index(&attrs, "v1")?,
                        index(&attrs, "v2")?,
                        index(&attrs, "v3")?,
                    ];
                    if obj.triangles.len() >= MAX_ELEMENTS {
                        return Err(too_many("triangles"));
                    }
                    obj.triangles.push(t);
                    model.parsed += 1;
                }
            }
            "beamlattice" if parent(1) == Some("mesh") => {
                if let Some((_, obj)) = current.as_mut() {
                    obj.beam_lattice = true;
                }
            }
            "component" if parent(1) == Some("components") => {
                if let Some((_, obj)) = current.as_mut() {
                    let attrs = attributes(&e, part)?;
                    obj.components.push(Placement {
                        part: part_path(&attrs, part, root)?,
                        object: id(&attrs, "component", "objectid")?,
                        transform: transform(&attrs, "component")?,
                    });
                    model.parsed += 1;
                }
            }
            "item" if parent(1) == Some("build") => {
                let attrs = attributes(&e, part)?;
                model.items.push(Placement {
                    part: part_path(&attrs, part, root)?,
                    object: id(&attrs, "item", "objectid")?,
                    transform: transform(&attrs, "item")?,
                });
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    finish_object(&mut model, current.take())?;
    Ok(model)
}

fn too_many(what: &'static str) -> LoadError {
    LoadError::TooManyElements {
        format: FORMAT,
        what,
        limit: MAX_ELEMENTS as u64,
    }
}

fn finish_object(model: &mut Model, object: Option<(u64, Object)>) -> Result<(), LoadError> {
    if let Some((oid, obj)) = object {
        if model.objects.insert(oid, obj).is_some() {
            return Err(LoadError::DuplicateObject { id: oid });
        }
    }
    Ok(())
}

/// Places every build item's object into one mesh; `parts` are the model
/// parts other than the root, by name.
fn build(
    model: &Model,
    parts: &HashMap<String, Model>,
) -> Result<(Mesh, LoadReport, ExactPositions), LoadError> {
    let parsed = parts
        .values()
        .fold(model.parsed, |n, m| n.saturating_add(m.parsed));
    let budget = parsed
        .saturating_mul(MAX_INSTANCE_FACTOR)
        .saturating_add(INSTANCE_ALLOWANCE)
        .min(MAX_ELEMENTS as u64);
    let mut out = Builder {
        model,
        parts,
        positions: Vec::new(),
        faces: Vec::new(),
        budget,
        non_identity: false,
        exact: ExactPositions::default(),
    };
    let mut notes = Vec::new();
    if let Some(unit) = &model.unit {
        if unit != "millimeter" {
            notes.push(LoadNote::Unit { unit: unit.clone() });
        }
    }
    let mut not_solid = 0;
    for (item, placement) in model.items.iter().enumerate() {
        let kind = out
            .object(placement.part.as_deref(), placement.object)?
            .kind;
        if kind == ObjectType::Other {
            return Err(LoadError::PlacesOther {
                item,
                object: placement.object,
            });
        }
        if !kind.is_solid() {
            not_solid += 1;
            continue;
        }
        out.non_identity = false;
        let mut chain = vec![placement.transform];
        let mut path = Vec::new();
        let at = (placement.part.as_deref(), placement.object);
        out.place(item, at, &mut chain, &mut path)?;
        if out.non_identity {
            notes.push(LoadNote::TransformApplied {
                item,
                object: placement.object,
            });
        }
    }
    if not_solid > 0 {
        notes.push(LoadNote::Ignored {
            kind: "build items placing a support or a surface (not solids)".to_owned(),
            count: not_solid,
        });
    }
    let mesh = Mesh {
        positions: out.positions,
        faces: out.faces,
    };
    Ok((
        mesh,
        LoadReport {
            format: FORMAT,
            notes,
        },
        out.exact,
    ))
}

struct Builder<'a> {
    model: &'a Model,
    parts: &'a HashMap<String, Model>,
    positions: Vec<[f64; 3]>,
    faces: Vec<[VertexId; 3]>,
    budget: u64,
    non_identity: bool,
    exact: ExactPositions,
}

impl<'a> Builder<'a> {
    /// Object `object` of model `part` (`None`: the root).
    fn object(&self, part: Option<&str>, object: u64) -> Result<&'a Object, LoadError> {
        let model: &'a Model = match part {
            None => self.model,
            // Every part referred to was read before building.
            Some(name) => self
                .parts
                .get(name)
                .ok_or_else(|| LoadError::ZipEntryMissing {
                    name: name.to_owned(),
                })?,
        };
        model
            .objects
            .get(&object)
            .ok_or(LoadError::UnknownObject { id: object })
    }

    /// Places `object` of model `part` (`None`: the root) under `chain`
    /// (outermost transform first); `path` holds the objects being
    /// expanded, to refuse cycles.
    fn place(
        &mut self,
        item: usize,
        (part, object): (Option<&'a str>, u64),
        chain: &mut Vec<Affine>,
        path: &mut Vec<(Option<&'a str>, u64)>,
    ) -> Result<(), LoadError> {
        if path.contains(&(part, object)) {
            return Err(LoadError::ComponentCycle { object });
        }
        if path.len() >= MAX_COMPONENT_DEPTH {
            return Err(LoadError::ComponentsTooDeep {
                object,
                limit: MAX_COMPONENT_DEPTH,
            });
        }
        let obj = self.object(part, object)?;
        if obj.beam_lattice {
            // Its beams are part of the solid: slicing the triangles alone
            // would answer for another part.
            return Err(LoadError::Unsupported {
                format: FORMAT,
                feature: format!(
                    "object {object} is a beam lattice (beam lattice extension): its beams are part of the solid"
                ),
            });
        }

        if !obj.positions.is_empty() || !obj.triangles.is_empty() {
            self.place_mesh(item, object, obj, chain)?;
        }
        path.push((part, object));
        for c in &obj.components {
            chain.push(c.transform);
            // A component without a path is in its object's own part.
            let at = (c.part.as_deref().or(part), c.object);
            let r = self.place(item, at, chain, path);
            chain.pop();
            r?;
        }
        path.pop();
        Ok(())
    }

    fn place_mesh(
        &mut self,
        item: usize,
        object: u64,
        obj: &Object,
        chain: &[Affine],
    ) -> Result<(), LoadError> {
        let n = obj.positions.len();
        let added = (n as u64).saturating_add(obj.triangles.len() as u64);
        let used = (self.positions.len() as u64).saturating_add(self.faces.len() as u64);
        if used.saturating_add(added) > self.budget {
            return Err(LoadError::TooManyElements {
                format: FORMAT,
                what: "instanced vertices and triangles",
                limit: self.budget,
            });
        }
        let base = self.positions.len();
        // Innermost transform first.
        let inner_first: Vec<Affine> = chain.iter().rev().copied().collect();
        if inner_first.iter().any(|t| !t.is_identity()) {
            self.non_identity = true;
        }
        for (vertex, &p) in obj.positions.iter().enumerate() {
            let at = PlacedVertex {
                item,
                object,
                vertex,
            };
            // A non-finite coordinate under a transform has no image.
            match apply_chain(p, &inner_first).ok_or_else(|| at.error())? {
                Image::Doubles(q) => self.positions.push(q),
                Image::Exact(q) => {
                    // base + vertex < budget <= MAX_ELEMENTS < u32::MAX.
                    let id = VertexId((base + vertex) as u32);
                    self.positions.push(q.each_ref().map(rat_to_f64));
                    self.exact.push(id, at, q);
                }
            }
        }
        for (triangle, t) in obj.triangles.iter().enumerate() {
            let mut face = [VertexId(0); 3];
            for (slot, &v) in face.iter_mut().zip(t) {
                if v as usize >= n {
                    return Err(LoadError::IndexOutOfRange {
                        format: FORMAT,
                        object,
                        triangle,
                        index: u64::from(v),
                        vertices: n,
                    });
                }
                // base + v < budget <= MAX_ELEMENTS < u32::MAX.
                *slot = VertexId((base + v as usize) as u32);
            }
            self.faces.push(face);
        }
        Ok(())
    }
}

/// Writes a minimal 3MF package: one object, one build item, coordinates
/// with shortest round-trip formatting (non-finite values are refused).
pub(super) fn write<W: Write>(mesh: &Mesh, out: &mut W) -> Result<(), SaveError> {
    for (v, p) in mesh.positions.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(SaveError::NonFinite {
                format: FORMAT,
                vertex: VertexId::from_idx(v),
            });
        }
    }
    let mut model: Vec<u8> = Vec::new();
    model.extend_from_slice(
        b"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n\
 <resources>\n  <object id=\"1\" type=\"model\">\n   <mesh>\n    <vertices>\n",
    );
    for p in &mesh.positions {
        model.extend_from_slice(
            format!(
                "     <vertex x=\"{:?}\" y=\"{:?}\" z=\"{:?}\"/>\n",
                p[0], p[1], p[2]
            )
            .as_bytes(),
        );
    }
    model.extend_from_slice(b"    </vertices>\n    <triangles>\n");
    for [a, b, c] in &mesh.faces {
        model.extend_from_slice(
            format!(
                "     <triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n",
                a.0, b.0, c.0
            )
            .as_bytes(),
        );
    }
    model.extend_from_slice(
        b"    </triangles>\n   </mesh>\n  </object>\n </resources>\n <build>\n  <item objectid=\"1\"/>\n </build>\n</model>\n",
    );

    let content_types = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">\n\
 <Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>\n\
 <Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>\n\
</Types>\n";
    let rels = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">\n\
 <Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>\n\
</Relationships>\n";

    let zip_err = |source| SaveError::Zip { source };
    let mut zw = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    zw.start_file("[Content_Types].xml", options)
        .map_err(zip_err)?;
    zw.write_all(content_types.as_bytes()).map_err(write_err)?;
    zw.start_file("_rels/.rels", options).map_err(zip_err)?;
    zw.write_all(rels.as_bytes()).map_err(write_err)?;
    zw.start_file(ROOT_MODEL, options).map_err(zip_err)?;
    zw.write_all(&model).map_err(write_err)?;
    let bytes = zw.finish().map_err(zip_err)?.into_inner();
    out.write_all(&bytes).map_err(write_err)
}
