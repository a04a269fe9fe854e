//! Input: PLY bytes (ASCII, binary little or big endian). Output: a
//! [`Mesh`] from the `vertex` element (`x`, `y`, `z` of any numeric type,
//! converted to `f64` exactly) and the `face` element (`vertex_indices` or
//! `vertex_index`, a list of any integer type), polygons split into fans
//! (or, flat ones whose fan would fold, by ear clipping: `polygon.rs`),
//! or from the `tristrips` element of scanned models (strips separated by
//! `-1`, every other triangle turned, joints with a repeated id
//! dropped); and the PLY writer (doubles, `uint` indices).
//! Both through `ply-rs-bw`.
//!
//! What real exporters write that `ply-rs-bw` refuses is made readable
//! first (`readable_header`, `keywordless_as_comments`): lone `\r` line
//! ends, indented header lines, and header lines without a keyword before
//! the first element (old Blender), the last with a note.
//!
//! Before the payload is parsed, the element counts are checked against the
//! bytes that follow (each element takes at least its binary size, or two
//! bytes per property in ASCII), so a lying header fails before allocating.

use std::io::{Cursor, Write};

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    Addable, ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult, PropertyDef,
    PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;

use super::text::{is_lone_cr, FaceSink};
use super::{write_err, LoadError, LoadNote, LoadReport, MeshFormat, SaveError, MAX_ELEMENTS};
use crate::mesh::Mesh;

/// The format (encoding) a PLY header announces, for format detection;
/// ASCII when the `format` line is missing or unknown.
pub(super) fn encoding_hint(bytes: &[u8]) -> MeshFormat {
    let head = &bytes[..bytes.len().min(512)];
    let has = |s: &[u8]| head.windows(s.len()).any(|w| w == s);
    if has(b"binary_little_endian") {
        MeshFormat::PlyBinaryLittleEndian
    } else if has(b"binary_big_endian") {
        MeshFormat::PlyBinaryBigEndian
    } else {
        MeshFormat::PlyAscii
    }
}

fn format_of(encoding: Encoding) -> MeshFormat {
    match encoding {
        Encoding::Ascii => MeshFormat::PlyAscii,
        Encoding::BinaryLittleEndian => MeshFormat::PlyBinaryLittleEndian,
        Encoding::BinaryBigEndian => MeshFormat::PlyBinaryBigEndian,
    }
}

/// One parsed element of any kind: coordinates and an index list, the
/// properties this reader uses; everything else is ignored.
#[derive(Debug, Default)]
struct Element {
    xyz: [f64; 3],
    indices: Vec<u32>,
    /// The negative values of the index list (no vertex id; `-1` separates
    /// triangle strips), each with the number of ids before it.
    negatives: Vec<(usize, i64)>,
}

fn coordinate_slot(name: &str) -> Option<usize> {
    match name {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl Element {
    fn set_coordinate(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        match coordinate_slot(name) {
            Some(i) => {
                self.xyz[i] = value;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }

    fn set_indices<T: Copy + Into<i64>>(
        &mut self,
        name: &str,
        values: &[T],
    ) -> PropertyAccessResult {
        if !is_index_list(name) {
            return PropertyAccessResult::Ignored;
        }
        self.indices.clear();
        self.negatives.clear();
        self.indices.reserve(values.len());
        for &v in values {
            let v: i64 = v.into();
            match u32::try_from(v) {
                Ok(i) => self.indices.push(i),
                Err(_) => self.negatives.push((self.indices.len(), v)),
            }
        }
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Element {
    fn new() -> Self {
        Element::default()
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set_coordinate(name, f64::from(value))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set_coordinate(name, value)
    }
    fn set_list_char(&mut self, name: &str, value: Vec<i8>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_uchar(&mut self, name: &str, value: Vec<u8>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_short(&mut self, name: &str, value: Vec<i16>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_ushort(&mut self, name: &str, value: Vec<u16>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_int(&mut self, name: &str, value: Vec<i32>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_uint(&mut self, name: &str, value: Vec<u32>) -> PropertyAccessResult {
        self.set_indices(name, &value)
    }
    fn set_list_float(&mut self, name: &str, _value: Vec<f32>) -> PropertyAccessResult {
        if is_index_list(name) {
            PropertyAccessResult::UnsupportedType
        } else {
            PropertyAccessResult::Ignored
        }
    }
    fn set_list_double(&mut self, name: &str, _value: Vec<f64>) -> PropertyAccessResult {
        self.set_list_float(name, Vec::new())
    }
}

fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

fn is_integer(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

/// The fewest bytes one element of `def` can take in `encoding`.
fn min_element_bytes(def: &ElementDef, encoding: Encoding) -> u64 {
    let n = match encoding {
        Encoding::Ascii => 2 * def.properties.len() as u64,
        Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => def
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(t) => scalar_size(t),
                PropertyType::List(count, _) => scalar_size(count),
            })
            .sum(),
    };
    n.max(1)
}

fn parse_err(format: MeshFormat, e: &ply_rs_bw::parser::ParseError) -> LoadError {
    LoadError::Parse {
        format,
        line: e.line(),
        message: readable(&e.to_string()),
    }
}

/// The longest piece of an offending line quoted in an error.
const QUOTE_CHARS: usize = 80;

/// `ply-rs`'s message on one line: its `Line N: ` prefix dropped (the
/// error names the line), the offending line quoted (cut to
/// [`QUOTE_CHARS`]), and a header grammar error's debug dump replaced by
/// the column and the keywords or types it expected there.
fn readable(raw: &str) -> String {
    let body = raw
        .strip_prefix("Line ")
        .and_then(|r| r.split_once(": "))
        .filter(|(n, _)| n.bytes().all(|b| b.is_ascii_digit()))
        .map_or(raw, |(_, rest)| rest);
    let mut parts = body.split("\n\t");
    let mut out = parts
        .next()
        .unwrap_or_default()
        .trim_end_matches('.')
        .to_owned();
    for part in parts {
        if let Some(text) = part.strip_prefix("String: ") {
            let text = text.trim_matches('\'').trim_end();
            let cut: String = text.chars().take(QUOTE_CHARS).collect();
            let more = if cut.len() < text.len() { "..." } else { "" };
            out += &format!(" `{}{more}`", cut.escape_debug());
        } else if let Some(err) = part.strip_prefix("Error: ") {
            out += &match grammar_expectation(err) {
                Some(expected) => format!(": {expected}"),
                None => format!(": {}", err.trim_end_matches('.')),
            };
        }
    }
    out
}

/// From the debug dump of a header grammar error (`ParseError { location:
/// LineCol { .., column: C, .. }, expected: ExpectedSet { expected: {..} }
/// }`): "at column C, expected one of a, b, c" with the tokens sorted.
fn grammar_expectation(dump: &str) -> Option<String> {
    let column = dump.split_once("column: ")?.1;
    let column = &column[..column.find(|c: char| !c.is_ascii_digit())?];
    let set = dump.split_once("expected: {")?.1.split_once('}')?.0;
    let mut tokens: Vec<String> = set
        .split(", ")
        .map(|t| t.replace(['"', '\\'], ""))
        // A character class (`[' '|'\t']`): the blanks between words.
        .map(|t| {
            if t.starts_with('[') {
                "a blank".to_owned()
            } else {
                t
            }
        })
        .filter(|t| !t.is_empty())
        .collect();
    tokens.sort();
    Some(format!(
        "at column {column}, expected one of {}",
        tokens.join(", ")
    ))
}

/// Reads PLY in any encoding.
pub(super) fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let guess = encoding_hint(bytes);
    if !(bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r")) {
        return Err(LoadError::Parse {
            format: guess,
            line: Some(1),
            message: "a PLY file starts with the line `ply`".to_owned(),
        });
    }
    let normalized = readable_header(bytes);
    let bytes = normalized.as_deref().unwrap_or(bytes);
    let (commented, header_note) = keywordless_as_comments(bytes).unzip();
    let bytes = commented.as_deref().unwrap_or(bytes);
    let parser = Parser::<Element>::new();
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| parse_err(guess, &e))?;
    let format = format_of(header.encoding);
    check_header(&header, format)?;

    let payload_start = reader.get_ref().position();
    let available = (bytes.len() as u64).saturating_sub(payload_start);
    let mut need: u128 = 0;
    for def in header.elements.values() {
        need += def.count as u128 * u128::from(min_element_bytes(def, header.encoding));
        // ASCII: the last line may lack its newline.
        if need > u128::from(available) + 1 {
            return Err(LoadError::ClaimedCountTooLarge {
                format,
                element: def.name.clone(),
                claimed: def.count as u64,
                available_bytes: available,
            });
        }
    }

    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut sink = FaceSink::new(format, 0);
    let mut strips = StripSink::default();
    let mut have_vertices = false;
    let mut ignored: Vec<(String, usize)> = Vec::new();
    for def in header.elements.values() {
        let elements = parser
            .read_payload_for_element(&mut reader, def, &header)
            .map_err(|e| parse_err(format, &e))?;
        match def.name.as_str() {
            "vertex" if !have_vertices => {
                have_vertices = true;
                if elements.len() > MAX_ELEMENTS {
                    return Err(LoadError::TooManyElements {
                        format,
                        what: "vertices",
                        limit: MAX_ELEMENTS as u64,
                    });
                }
                positions = elements.iter().map(|e| e.xyz).collect();
            }
            "face" => {
                for e in &elements {
                    if let Some(&(_, v)) = e.negatives.first() {
                        return Err(negative_index(format, v));
                    }
                    sink.push(&e.indices)?;
                }
            }
            "tristrips" => {
                for e in &elements {
                    if let Some(&(_, v)) = e.negatives.iter().find(|(_, v)| *v != -1) {
                        return Err(negative_index(format, v));
                    }
                    strips.push(&e.indices, &e.negatives, &mut sink)?;
                }
            }
            _ => ignored.push((def.name.clone(), elements.len())),
        }
    }
    if !have_vertices {
        return Err(LoadError::Parse {
            format,
            line: None,
            message: "the header declares no `vertex` element".to_owned(),
        });
    }

    let mut notes: Vec<LoadNote> = Vec::new();
    notes.extend(header_note);
    let (faces, triangulated) = sink.finish(&positions);
    notes.extend(triangulated);
    notes.extend(strips.note());
    for (name, count) in ignored {
        notes.push(LoadNote::Ignored {
            kind: format!("`{name}` elements"),
            count,
        });
    }
    let end = reader.get_ref().position();
    if (bytes.len() as u64) > end && format != MeshFormat::PlyAscii {
        notes.push(LoadNote::TrailingBytes {
            bytes: bytes.len() as u64 - end,
        });
    }
    let mesh = Mesh { positions, faces };
    Ok((mesh, LoadReport { format, notes }))
}

/// A copy of a file with what `ply-rs-bw` cannot read in a header made
/// what it can, or `None` when nothing needs it. Byte for byte the same
/// length, so the payload and the line numbers do not move:
/// - lines ended by a lone `\r` (classic Mac OS line ends, as Rhino 6
///   writes PLY headers) end in `\n`: in the header of a binary file,
///   everywhere in an ASCII one;
/// - a header line's leading spaces and tabs (draco reads such files) go
///   to its end, where they are allowed.
fn readable_header(bytes: &[u8]) -> Option<Vec<u8>> {
    let lone_cr = bytes.starts_with(b"ply\r") && bytes.get(4) != Some(&b'\n');
    let header_end = header_end(bytes);
    let indented = bytes[..header_end]
        .split(|&b| b == b'\n' || b == b'\r')
        .any(|line| line.first().is_some_and(|&b| b == b' ' || b == b'\t'));
    if !lone_cr && !indented {
        return None;
    }
    let mut out = bytes.to_vec();
    if lone_cr {
        let end = match encoding_hint(bytes) {
            MeshFormat::PlyAscii => bytes.len(),
            _ => header_end,
        };
        for i in (0..end).filter(|&i| is_lone_cr(bytes, i)) {
            out[i] = b'\n';
        }
    }
    let mut start = 0;
    while start < header_end {
        let len = out[start..header_end]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(header_end - start);
        let line = &mut out[start..start + len];
        let indent = line
            .iter()
            .take_while(|&&b| b == b' ' || b == b'\t')
            .count();
        line.rotate_left(indent);
        start += len + 1;
    }
    Some(out)
}

/// The keywords that start a PLY header line.
const KEYWORDS: [&[u8]; 7] = [
    b"ply",
    b"format",
    b"comment",
    b"obj_info",
    b"element",
    b"property",
    b"end_header",
];

/// A copy of a file whose header lines before the first `element` that
/// start with no PLY keyword are made comments, with a note; `None` when
/// there is none. Blender 2.4's exporter wrote `Created by Blender3D 247 -
/// www.blender.org, source file: ...` after the `format` line, which
/// `ply-rs-bw` refuses. Before the first element no line describes the
/// data, so reading such a line as a comment cannot change what is read
/// (a misspelt `element` there leaves its properties without an element,
/// an error still); after it, a line without a keyword stays an error: a
/// misspelt `property` would move every number. No line is added, so the
/// line numbers of errors do not move.
fn keywordless_as_comments(bytes: &[u8]) -> Option<(Vec<u8>, LoadNote)> {
    let header = &bytes[..header_end(bytes)];
    let mut starts = Vec::new();
    let mut first = None;
    let mut at = 0;
    for (i, line) in header.split_inclusive(|&b| b == b'\n').enumerate() {
        let word = line
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty())
            .unwrap_or_default();
        if word == b"element" {
            break;
        }
        if i > 0 && !word.is_empty() && !KEYWORDS.contains(&word) {
            starts.push(at);
            first.get_or_insert_with(|| {
                (
                    i + 1,
                    String::from_utf8_lossy(line.trim_ascii()).into_owned(),
                )
            });
        }
        at += line.len();
    }
    let (line, text) = first?;
    let mut out = Vec::with_capacity(bytes.len() + 8 * starts.len());
    let mut from = 0;
    for start in &starts {
        out.extend_from_slice(&bytes[from..*start]);
        out.extend_from_slice(b"comment ");
        from = *start;
    }
    out.extend_from_slice(&bytes[from..]);
    let (lines, comments) = match starts.len() {
        1 => ("line", "a comment"),
        _ => ("lines", "comments"),
    };
    let note = LoadNote::Ignored {
        kind: format!(
            "header {lines} without a PLY keyword before the first element, read as {comments} (the first, on line {line}: `{text}`)"
        ),
        count: starts.len(),
    };
    Some((out, note))
}

/// Where the header ends: just past the line that holds `end_header`
/// (the whole file when there is none, for the parser to name).
fn header_end(bytes: &[u8]) -> usize {
    const END: &[u8] = b"end_header";
    match bytes.windows(END.len()).position(|w| w == END) {
        None => bytes.len(),
        Some(at) => {
            let after = at + END.len();
            bytes[after..]
                .iter()
                .position(|&b| b == b'\n' || b == b'\r')
                .map_or(bytes.len(), |n| after + n + 1)
        }
    }
}

fn negative_index(format: MeshFormat, v: i64) -> LoadError {
    LoadError::InvalidIndex {
        format,
        line: None,
        text: v.to_string(),
        reason: super::InvalidIndexReason::Negative,
    }
}

/// Triangle strips (the `tristrips` element of scanned models, as the
/// Stanford range-scan tools write it): each element's index list holds
/// strips separated by `-1`; strip `s0 s1 s2 s3 ...` is the triangles
/// `(s0 s1 s2)`, `(s2 s1 s3)`, `(s2 s3 s4)`, ... (every other one turned so
/// that all keep the first one's orientation). A triangle with a repeated
/// vertex id is how strips are joined, not a face: it is dropped (a
/// decision on ids alone) and counted in the note.
#[derive(Debug, Default)]
struct StripSink {
    strips: usize,
    triangles: usize,
    joints: usize,
}

impl StripSink {
    /// Adds the strips of one element: `ids` with the `-1` separators
    /// taken out, `breaks` saying how many ids come before each.
    fn push(
        &mut self,
        ids: &[u32],
        breaks: &[(usize, i64)],
        sink: &mut FaceSink,
    ) -> Result<(), LoadError> {
        let mut start = 0;
        let ends = breaks.iter().map(|&(at, _)| at).chain([ids.len()]);
        for end in ends {
            let strip = &ids[start..end];
            start = end;
            if strip.is_empty() {
                continue;
            }
            self.strips += 1;
            for (k, w) in strip.windows(3).enumerate() {
                if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
                    self.joints += 1;
                    continue;
                }
                let triangle = if k % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                };
                sink.push(&triangle)?;
                self.triangles += 1;
            }
        }
        Ok(())
    }

    fn note(&self) -> Option<LoadNote> {
        (self.strips > 0).then_some(LoadNote::Strips {
            strips: self.strips,
            triangles: self.triangles,
            joints: self.joints,
        })
    }
}

/// The vertex element needs scalar `x`, `y`, `z`; the face and tristrips
/// elements an integer list `vertex_indices` (or `vertex_index`).
fn check_header(header: &Header, format: MeshFormat) -> Result<(), LoadError> {
    let missing = |message: String| LoadError::Parse {
        format,
        line: None,
        message,
    };
    if let Some(v) = header.elements.get("vertex") {
        for name in ["x", "y", "z"] {
            match v.properties.get(name).map(|p| &p.data_type) {
                Some(PropertyType::Scalar(_)) => {}
                Some(PropertyType::List(..)) => {
                    return Err(missing(format!(
                        "vertex property `{name}` is a list, not a number"
                    )))
                }
                None => {
                    return Err(missing(format!(
                        "the vertex element has no property `{name}`"
                    )))
                }
            }
        }
    }
    for f in ["face", "tristrips"]
        .iter()
        .filter_map(|n| header.elements.get(*n))
    {
        let list = f
            .properties
            .iter()
            .find(|(name, _)| is_index_list(name))
            .map(|(_, p)| &p.data_type);
        match list {
            Some(PropertyType::List(count, item)) if is_integer(count) && is_integer(item) => {}
            Some(_) => {
                return Err(missing(format!(
                    "the {} index list must be a list of integers",
                    f.name
                )))
            }
            None => {
                return Err(missing(format!(
                    "the {} element has no `vertex_indices` list",
                    f.name
                )))
            }
        }
    }
    Ok(())
}

/// What the writer hands to `ply-rs-bw`: one vertex or one face.
#[derive(Debug)]
enum OutElement {
    Vertex([f64; 3]),
    Face([u32; 3]),
}

impl PropertyAccess for OutElement {
    fn new() -> Self {
        OutElement::Vertex([0.0; 3])
    }
    fn get_double(&self, name: &str) -> Option<f64> {
        match self {
            OutElement::Vertex(p) => coordinate_slot(name).map(|i| p[i]),
            OutElement::Face(_) => None,
        }
    }
    fn get_list_uint(&self, name: &str) -> Option<&[u32]> {
        match self {
            OutElement::Face(ids) if name == "vertex_indices" => Some(ids),
            _ => None,
        }
    }
}

/// Writes PLY in the encoding `format` names: `double` coordinates,
/// `list uchar uint vertex_indices`.
pub(super) fn write<W: Write>(
    mesh: &Mesh,
    format: MeshFormat,
    out: &mut W,
) -> Result<(), SaveError> {
    let encoding = match format {
        MeshFormat::PlyAscii => Encoding::Ascii,
        MeshFormat::PlyBinaryBigEndian => Encoding::BinaryBigEndian,
        _ => Encoding::BinaryLittleEndian,
    };
    let mut header = Header::new();
    header.encoding = encoding;
    header.comments.push("written by wmslice".to_owned());
    let mut vertex = ElementDef::new("vertex".to_owned());
    vertex.count = mesh.positions.len();
    for name in ["x", "y", "z"] {
        vertex.properties.add(PropertyDef::new(
            name.to_owned(),
            PropertyType::Scalar(ScalarType::Double),
        ));
    }
    let mut face = ElementDef::new("face".to_owned());
    face.count = mesh.faces.len();
    face.properties.add(PropertyDef::new(
        "vertex_indices".to_owned(),
        PropertyType::List(ScalarType::UChar, ScalarType::UInt),
    ));
    header.elements.add(vertex.clone());
    header.elements.add(face.clone());

    let writer = Writer::<OutElement>::new();
    let io = |e: std::io::Error| write_err(e);
    writer.write_header(out, &header).map_err(io)?;
    let mut put = |e: &OutElement, def: &ElementDef| -> std::io::Result<usize> {
        match encoding {
            Encoding::Ascii => writer.write_ascii_element(out, e, def),
            Encoding::BinaryLittleEndian => writer.write_little_endian_element(out, e, def),
            Encoding::BinaryBigEndian => writer.write_big_endian_element(out, e, def),
        }
    };
    for p in &mesh.positions {
        put(&OutElement::Vertex(*p), &vertex).map_err(io)?;
    }
    for [a, b, c] in &mesh.faces {
        put(&OutElement::Face([a.0, b.0, c.0]), &face).map_err(io)?;
    }
    Ok(())
}
