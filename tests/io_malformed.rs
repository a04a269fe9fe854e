//! Input: hand-made files in every format, valid but unusual (binary STL
//! starting with `solid`, OBJ relative indices and quads, big-endian PLY,
//! binary OFF in each layout, 3MF transforms) or broken (truncated, lying counts, zip bombs, deep XML).
//! Output: assertions on the mesh read, the notes, or the exact error variant.

use std::io::Write;

use wmslice::exact::rational::Rat;
use wmslice::mesh::io::{
    detect_format, load, load_bytes, load_bytes_exact, BinaryOffLayout, ByteOrder, FaceColors,
    InvalidIndexReason, LoadError, LoadNote, MeshFormat,
};
use wmslice::mesh::prepare::{prepare, prepare_exact, PrepareError};
use wmslice::mesh::snap::{snap, snap_exact, SnapError};
use wmslice::mesh::Mesh;
use wmslice::VertexId;

fn ids(m: &Mesh) -> Vec<[u32; 3]> {
    m.faces.iter().map(|t| t.map(|v| v.0)).collect()
}

// ---------------------------------------------------------------- STL

/// A binary STL with the given 80-byte header start and triangles.
fn binary_stl(header: &[u8], triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b[..header.len()].copy_from_slice(header);
    b.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        b.extend_from_slice(&[0u8; 12]);
        for p in t {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
    }
    b
}

const TWO_TRIANGLES: [[[f32; 3]; 3]; 2] = [
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
];

#[test]
fn binary_stl_whose_header_starts_with_solid_is_read_as_binary() {
    let bytes = binary_stl(b"solid exported by some CAD tool", &TWO_TRIANGLES);
    for hint in [
        None,
        Some(MeshFormat::StlAscii),
        Some(MeshFormat::StlBinary),
    ] {
        let (mesh, report) = load_bytes(&bytes, hint).unwrap();
        assert_eq!(report.format, MeshFormat::StlBinary);
        assert!(report.notes.contains(&LoadNote::BinaryStlHeaderSaysSolid));
        assert_eq!(mesh.num_vertices(), 4);
        assert_eq!(ids(&mesh), vec![[0, 1, 2], [1, 3, 2]]);
    }
}

#[test]
fn binary_stl_with_solid_header_and_trailing_bytes_falls_back_to_binary() {
    let mut bytes = binary_stl(b"solid x", &TWO_TRIANGLES);
    bytes.extend_from_slice(&[0xff, 0x00, 0x13]);
    let (mesh, report) = load_bytes(&bytes, None).unwrap();
    assert_eq!(report.format, MeshFormat::StlBinary);
    assert!(report.notes.contains(&LoadNote::TrailingBytes { bytes: 3 }));
    assert_eq!(mesh.num_faces(), 2);
}

/// The count at bytes 80..84 rewritten: the records stay as they are.
fn with_count(mut bytes: Vec<u8>, n: u32) -> Vec<u8> {
    bytes[80..84].copy_from_slice(&n.to_le_bytes());
    bytes
}

/// A writer that never filled the count in: the two records are there.
#[test]
fn binary_stl_claiming_no_triangle_reads_the_records_it_holds() {
    for header in [&b"solid streamed"[..], b"streamed"] {
        let bytes = with_count(binary_stl(header, &TWO_TRIANGLES), 0);
        let (mesh, report) = load_bytes(&bytes, None).unwrap();
        assert_eq!(report.format, MeshFormat::StlBinary);
        assert!(report
            .notes
            .contains(&LoadNote::StlCountZero { triangles: 2 }));
        assert_eq!(ids(&mesh), vec![[0, 1, 2], [1, 3, 2]]);
    }
    // Not a whole number of records: nothing to read them by.
    let mut bytes = with_count(binary_stl(b"", &TWO_TRIANGLES), 0);
    bytes.push(0);
    let (mesh, report) = load_bytes(&bytes, Some(MeshFormat::StlBinary)).unwrap();
    assert_eq!(mesh.num_faces(), 0);
    assert!(report
        .notes
        .contains(&LoadNote::TrailingBytes { bytes: 101 }));
}

/// A count short of the records: the claimed ones are read, and the note
/// says how many whole records were left.
#[test]
fn binary_stl_with_records_past_its_count_names_them() {
    let bytes = with_count(binary_stl(b"solid x", &TWO_TRIANGLES), 1);
    let (mesh, report) = load_bytes(&bytes, None).unwrap();
    assert_eq!(mesh.num_faces(), 1);
    let note = LoadNote::StlUnclaimedTriangles {
        claimed: 1,
        more: 1,
    };
    assert!(report.notes.contains(&note), "{:?}", report.notes);
    assert!(note
        .to_string()
        .contains("the header claims 1 triangles, but 1 more"));
}

/// Binary content under a `solid` header whose count runs past the file:
/// the binary reader's verdict, not an ASCII parse error.
#[test]
fn binary_stl_with_solid_header_and_too_large_a_count_is_named_as_binary() {
    let bytes = with_count(binary_stl(b"solid x", &TWO_TRIANGLES), 9);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::ClaimedCountTooLarge {
                format: MeshFormat::StlBinary,
                claimed: 9,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn truncated_binary_stl_is_truncated() {
    let mut bytes = binary_stl(b"", &TWO_TRIANGLES);
    bytes.truncate(bytes.len() - 7);
    let err = load_bytes(&bytes, Some(MeshFormat::StlBinary)).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::Truncated {
                format: MeshFormat::StlBinary,
                what: "bytes",
                expected: 184,
                got: 177
            }
        ),
        "{err:?}"
    );
    let err = load_bytes(&bytes[..50], Some(MeshFormat::StlBinary)).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::Truncated {
                expected: 84,
                got: 50,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn binary_stl_claiming_four_billion_triangles_fails_at_once() {
    let mut bytes = vec![0u8; 1024];
    bytes[80..84].copy_from_slice(&4_000_000_000u32.to_le_bytes());
    let err = load_bytes(&bytes, Some(MeshFormat::StlBinary)).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::ClaimedCountTooLarge {
                format: MeshFormat::StlBinary,
                claimed: 4_000_000_000,
                available_bytes: 940,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn ascii_stl_parses_f64_text_exactly_and_fans_polygons() {
    let text = b"solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0.1 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";
    let (mesh, report) = load_bytes(text, None).unwrap();
    assert_eq!(report.format, MeshFormat::StlAscii);
    assert_eq!(mesh.positions[0], [0.1, 0.0, 0.0]);
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3]]);
    assert!(report.notes.contains(&LoadNote::Triangulated {
        polygons: 1,
        triangles: 2,
        ear_clipped: 0,
    }));
}

#[test]
fn ascii_stl_reads_the_same_with_any_line_ends() {
    // PrusaSlicer's test data holds a cube with classic Mac OS line ends
    // (a bare \r): the solid's name ends at the first one, not at the end
    // of the file.
    let unix = "solid t name\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";
    let (expect, _) = load_bytes(unix.as_bytes(), None).unwrap();
    for end in ["\r", "\r\n"] {
        let text = unix.replace('\n', end);
        let (mesh, report) = load_bytes(text.as_bytes(), None).unwrap();
        assert_eq!(report.format, MeshFormat::StlAscii);
        assert_eq!(
            (mesh.positions.clone(), ids(&mesh)),
            (expect.positions.clone(), ids(&expect))
        );
        // Errors name the line with either ending.
        let bad = text.replace("vertex 0 1 0", "vertex 0 1 zero");
        let err = load_bytes(bad.as_bytes(), None).unwrap_err();
        assert!(
            matches!(err, LoadError::Parse { line: Some(6), .. }),
            "{end:?}: {err:?}"
        );
    }
}

#[test]
fn ascii_stl_syntax_error_names_the_line() {
    let text = b"solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zero\n";
    let err = load_bytes(text, None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::Parse {
                format: MeshFormat::StlAscii,
                line: Some(4),
                ..
            }
        ),
        "{err:?}"
    );
}

/// As exporters have written them (PrusaSlicer keeps such a file among its
/// tests): normals that are not numbers, and words after `endloop` and
/// `endfacet`. The normal is not used, so the triangles are read, and
/// both are counted in notes.
#[test]
fn ascii_stl_odd_normals_and_words_after_end_tags_are_counted_not_refused() {
    let text = b"solid t\n\
facet normal +inf -inf weirdvalue\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop foo\nendfacet bar baz\n\
facet normal nan 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n\
endsolid t trailing words\n";
    let (mesh, report) = load_bytes(text, None).unwrap();
    assert_eq!(
        mesh.positions,
        vec![
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0]
        ]
    );
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3]]);
    let ignored: Vec<(String, usize)> = report
        .notes
        .iter()
        .filter_map(|n| match n {
            LoadNote::Ignored { kind, count } => Some((kind.clone(), *count)),
            _ => None,
        })
        .collect();
    // One facet's normal has a word (`nan` and the infinities are numbers);
    // `foo`, `bar` and `baz` are the three words.
    assert_eq!(ignored.len(), 2, "{ignored:?}");
    assert_eq!(ignored[0].1, 1);
    assert!(ignored[0].0.contains("normals"), "{ignored:?}");
    assert_eq!(ignored[1].1, 3);
}

/// Leniency stays on the line of the end tag, and a normal still has three
/// parts: a missing `endfacet`, or a normal of two numbers, is refused
/// with its line.
#[test]
fn ascii_stl_missing_endfacet_or_short_normal_is_still_refused() {
    for (text, line) in [
        (
            &b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nfacet normal 0 0 1\n"[..],
            8,
        ),
        (
            &b"solid t\nfacet normal 0 1\nouter loop\nvertex 0 0 0\n"[..],
            3,
        ),
    ] {
        let err = load_bytes(text, None).unwrap_err();
        assert!(
            matches!(err, LoadError::Parse { format: MeshFormat::StlAscii, line: Some(l), .. } if l == line),
            "{err:?}"
        );
    }
}

#[test]
fn ascii_stl_ending_after_a_whole_facet_without_endsolid_is_refused_saying_so() {
    // OpenMesh's test file `cube1.stl` ends this way. A file cut off
    // between two facets looks the same, and if whole bodies were lost
    // nothing would be open to show it: refused, with what to do if the
    // file is whole (before: only "expected `facet` or `endsolid`").
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let text = format!("solid t\n{facet}{facet}");
    let err = load_bytes(text.as_bytes(), None).unwrap_err();
    let said = err.to_string();
    assert!(
        matches!(
            err,
            LoadError::Parse {
                format: MeshFormat::StlAscii,
                line: Some(15),
                ..
            }
        ),
        "{err:?}"
    );
    assert!(
        said.contains("ends after 2 whole facets without `endsolid`")
            && said.contains("add `endsolid`"),
        "{said}"
    );
    // With it, read.
    assert!(load_bytes(format!("{text}endsolid t\n").as_bytes(), None).is_ok());
    // A solid with no facet at all says only what it expected.
    let err = load_bytes(b"solid t\n", None).unwrap_err().to_string();
    assert!(!err.contains("whole facets"), "{err}");
}

#[test]
fn ascii_stl_facet_with_two_vertices_cannot_be_triangulated() {
    let text = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n";
    let err = load_bytes(text, None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::NonTriangleFace {
                format: MeshFormat::StlAscii,
                face: 0,
                arity: 2
            }
        ),
        "{err:?}"
    );
}

/// A `facet` with no `normal` (`facet` then `outer loop`, as
/// Online3DViewer's test files have it) is read: the normal is not used.
/// It is counted in a note; a facet with a normal beside it is not.
#[test]
fn ascii_stl_facet_without_a_normal_is_read_and_counted() {
    let text = b"solid t\nfacet\n outer loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n\
facet normal 0 0 1 outer loop vertex 0 0 0 vertex 0 0 1 vertex 1 0 0 endloop endfacet\nendsolid t\n";
    let (mesh, report) = load_bytes(text, None).unwrap();
    assert_eq!(report.format, MeshFormat::StlAscii);
    assert_eq!(
        mesh.positions,
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0]
        ]
    );
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 3, 1]]);
    assert!(
        report.notes.contains(&LoadNote::Ignored {
            kind: "facets without a normal (normals are not used)".into(),
            count: 1
        }),
        "{:?}",
        report.notes
    );
}

/// Text that does not start with `solid` and is no binary STL of its size
/// (here: comments before `solid`) is refused as ASCII STL at line 1,
/// naming the word, not as a binary file whose "triangle count" is four
/// characters of text.
#[test]
fn text_stl_not_starting_with_solid_is_named_as_ascii() {
    let text = b"# comment\nsolid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n# padding to pass the 84-byte binary header\n";
    let err = load_bytes(text, Some(MeshFormat::StlBinary)).unwrap_err();
    match err {
        LoadError::Parse {
            format: MeshFormat::StlAscii,
            line: Some(1),
            message,
        } => assert!(message.contains("expected `solid`, found `#`"), "{message}"),
        e => panic!("{e:?}"),
    }
}

/// What follows an `endsolid` must be another `solid`: a facet there is
/// outside any solid (gmsh's `multi_solid.stl` ends its first solid after
/// two facets and goes on with more), and text that is not STL (gmsh's
/// `Coupe.stl` appends a `.geo` script) is refused too; both messages say
/// where the last solid ended.
#[test]
fn after_endsolid_only_a_solid_may_follow() {
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    for (tail, line, says) in [
        (
            facet,
            17,
            "expected `solid`, found `facet` after `endsolid` on line 16: a facet outside any solid",
        ),
        (
            "Surface Loop(2) = {1};\n",
            17,
            "expected `solid`, found `Surface` after `endsolid` on line 16: what follows the last solid is not STL",
        ),
    ] {
        let text = format!("solid a\n{facet}{facet}endsolid a\n{tail}");
        match load_bytes(text.as_bytes(), Some(MeshFormat::StlAscii)).unwrap_err() {
            LoadError::Parse {
                format: MeshFormat::StlAscii,
                line: Some(l),
                message,
            } => {
                assert_eq!(l, line, "{message}");
                assert!(message.contains(says), "{message}");
            }
            e => panic!("{e:?}"),
        }
    }
}

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_negative_indices_count_back_from_the_last_vertex() {
    let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf 1/1/1 -3//2 4\n";
    let (mesh, report) = load_bytes(text, Some(MeshFormat::Obj)).unwrap();
    assert_eq!(report.format, MeshFormat::Obj);
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 1, 3]]);
}

#[test]
fn obj_quad_is_triangulated_with_a_note() {
    let text = b"o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng b\nf 1 2 3 4\nl 1 2\n";
    let (mesh, report) = load_bytes(text, None).unwrap();
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3]]);
    assert!(report.notes.contains(&LoadNote::Triangulated {
        polygons: 1,
        triangles: 2,
        ear_clipped: 0,
    }));
    assert!(report.notes.contains(&LoadNote::Ignored {
        kind: "line and point elements".into(),
        count: 1
    }));
}

/// Unrecognized statements are counted and the first is named with its
/// line: a file of another format named `.obj` (an MNI surface, pyvista's
/// `mni-surface-mesh.obj`, starts `P 0.3 0.3 0.4 10 1 1558`) then says
/// what it holds, beside "the mesh has no faces".
#[test]
fn obj_unrecognized_statements_name_the_first() {
    let text = b"# MNI\nP 0.3 0.3 0.4 10 1 1558\n -18 -16.85 2.5\nv 0 0 0\nQ 1\n";
    let (mesh, report) = load_bytes(text, Some(MeshFormat::Obj)).unwrap();
    assert_eq!(mesh.positions.len(), 1);
    assert_eq!(
        report.notes,
        vec![LoadNote::Ignored {
            kind: "unrecognized statements (the first, on line 2: `P`)".into(),
            count: 3
        }]
    );
}

/// A `#` after a face's ids starts a comment (Online3DViewer's
/// `cube_with_materials_comments.obj`); before, the `#` was read as an id.
#[test]
fn obj_comment_after_face_ids_is_a_comment() {
    let text = b"v 0 0 0 # a\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 # inline comment 4\nf 1/1/1 4/2/2 2/3/3 #tight\n";
    let (mesh, _) = load_bytes(text, Some(MeshFormat::Obj)).unwrap();
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 3, 1]]);
    // A `#` glued to an id is not a comment: the id is not an integer.
    let err = load_bytes(b"v 0 0 0\nf 1 1#c 1\n", Some(MeshFormat::Obj)).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::InvalidIndex {
                reason: InvalidIndexReason::NotAnInteger,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn obj_out_of_range_index_loads_for_validation_to_report() {
    let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    let (mesh, _) = load_bytes(text, Some(MeshFormat::Obj)).unwrap();
    assert_eq!(mesh.faces[0][2], VertexId(8));
}

#[test]
fn obj_invalid_indices_are_typed_errors() {
    let cases: [(&[u8], InvalidIndexReason); 4] = [
        (b"v 0 0 0\nf 1 0 1\n", InvalidIndexReason::Zero),
        (
            b"v 0 0 0\nf 1 -2 1\n",
            InvalidIndexReason::BeforeFirstVertex,
        ),
        (b"v 0 0 0\nf 1 4294967297 1\n", InvalidIndexReason::TooLarge),
        (b"v 0 0 0\nf 1 x 1\n", InvalidIndexReason::NotAnInteger),
    ];
    for (text, expected) in cases {
        let err = load_bytes(text, Some(MeshFormat::Obj)).unwrap_err();
        assert!(
            matches!(err, LoadError::InvalidIndex { format: MeshFormat::Obj, line: Some(2), reason, .. } if reason == expected),
            "{err:?}"
        );
    }
}

#[test]
fn obj_face_with_two_vertices_is_refused() {
    let err = load_bytes(b"v 0 0 0\nv 1 1 1\nf 1 2\n", Some(MeshFormat::Obj)).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::NonTriangleFace {
                format: MeshFormat::Obj,
                face: 0,
                arity: 2
            }
        ),
        "{err:?}"
    );
}

// ---------------------------------------------------------------- OFF

#[test]
fn off_with_colors_comments_and_polygons_loads() {
    let text = b"COFF\n# a comment\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n4 0 1 2 3 1 0 0\n";
    let (mesh, report) = load_bytes(text, None).unwrap();
    assert_eq!(report.format, MeshFormat::Off);
    assert_eq!(mesh.positions[2], [1.0, 1.0, 0.0]);
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3]]);
}

/// ModelNet's OFF files glue the vertex count to the keyword.
#[test]
fn off_with_the_vertex_count_glued_to_the_keyword_loads() {
    let text = b"OFF4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    assert_eq!(detect_format(text), Some(MeshFormat::Off));
    let (mesh, _) = load_bytes(text, None).unwrap();
    assert_eq!(mesh.positions.len(), 4);
    assert_eq!(ids(&mesh)[3], [0, 3, 2]);
    // Anything but digits after the keyword is not OFF.
    let err = load_bytes(b"OFFx 4 4 6\n", Some(MeshFormat::Off)).unwrap_err();
    assert!(
        err.to_string().contains("expected `OFF`, found `OFFx`"),
        "{err}"
    );
}

/// A whole mesh on the header line is refused as such, not as a count
/// the file cannot hold.
#[test]
fn off_data_on_the_header_line_is_named() {
    let text = b"OFF 4 4 6 0 0 0 1 0 0 0 1 0 0 0 1 3 0 2 1 3 0 1 3 3 1 2 3 3 0 3 2\n";
    let err = load_bytes(text, None).unwrap_err();
    assert!(
        err.to_string()
            .contains("31 numbers where the vertex, face and edge counts belong"),
        "{err}"
    );
}

#[test]
fn off_out_of_range_index_loads() {
    let text = b"OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    let (mesh, _) = load_bytes(text, None).unwrap();
    assert_eq!(mesh.faces[0][2], VertexId(7));
}

#[test]
fn off_lying_count_fails_before_allocating() {
    let text = b"OFF\n4000000000 1 0\n0 0 0\n";
    let err = load_bytes(text, None).unwrap_err();
    assert!(
        matches!(err, LoadError::ClaimedCountTooLarge { format: MeshFormat::Off, claimed: 4_000_000_000, ref element, .. } if element == "vertex"),
        "{err:?}"
    );
}

#[test]
fn off_missing_faces_is_truncated() {
    let missing = b"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n                     \n";
    // `3 0 1` takes the next line's `3` as its third index and the rest of
    // that line as color: the second face line is missing.
    let short = b"OFF\n3 2 0\n0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n3 0 1\n3 0 1 2\n";
    for text in [&missing[..], &short[..]] {
        let err = load_bytes(text, None).unwrap_err();
        assert!(
            matches!(
                err,
                LoadError::Truncated {
                    format: MeshFormat::Off,
                    what: "faces",
                    expected: 2,
                    got: 1
                }
            ),
            "{err:?}"
        );
    }
}

#[test]
fn off_face_indices_run_on_over_lines() {
    // The first face's indices take three lines (a comment between), the
    // second's two; the color after the last index is ignored.
    let text =
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0\n1 # c\n2\n3 255 0 0\n3 0\n2 3 0.5 0.5 0.5\n";
    let (mesh, _) = load_bytes(text, None).unwrap();
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
}

#[test]
fn off_last_face_listing_too_few_indices_is_refused() {
    // Nothing follows to complete it.
    let text = b"OFF\n3 1 0\n0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n3 0 1\n";
    let err = load_bytes(text, None).unwrap_err();
    assert!(
        matches!(err, LoadError::Parse { format: MeshFormat::Off, line: Some(6), ref message } if message.contains("lists fewer")),
        "{err:?}"
    );
}

// ---------------------------------------------------------------- binary OFF

/// A binary OFF file: the header line, then 32-bit values in `layout`.
/// `extra` values follow each vertex's `x y z` (the keyword's prefixes);
/// with per-face color counts, face `i` carries `i % 5` color values.
fn binary_off(
    keyword: &str,
    layout: BinaryOffLayout,
    pos: &[[f32; 3]],
    extra: usize,
    faces: &[&[u32]],
) -> Vec<u8> {
    let mut b = format!("{keyword} BINARY\n").into_bytes();
    let mut put = |w: u32| match layout.byte_order {
        ByteOrder::Big => b.extend_from_slice(&w.to_be_bytes()),
        ByteOrder::Little => b.extend_from_slice(&w.to_le_bytes()),
    };
    for n in [pos.len(), faces.len(), 0] {
        put(n as u32);
    }
    for p in pos {
        for c in p {
            put(c.to_bits());
        }
        for e in 0..extra {
            put((0.25 * e as f32).to_bits());
        }
    }
    for (i, f) in faces.iter().enumerate() {
        put(f.len() as u32);
        f.iter().for_each(|&v| put(v));
        if layout.face_colors == FaceColors::Counted {
            let colors = (i % 5) as u32;
            put(colors);
            (0..colors).for_each(|_| put(0.5f32.to_bits()));
        }
    }
    b
}

/// A tetrahedron whose coordinates are `f32` values of every magnitude.
const BIN_TETRA_POS: [[f32; 3]; 4] = [
    [0.0, -3.5e-38, 1.0e30],
    [1.25, 0.0, -7.0],
    [-0.1, 6.5e4, 0.0],
    [3.0e-45, 2.0, 0.375],
];
const BIN_TETRA: [&[u32]; 4] = [&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]];

#[test]
fn binary_off_reads_in_the_one_layout_that_fits_as_ascii_off_does() {
    let ascii = {
        let mut t = String::from("OFF\n4 4 0\n");
        for p in BIN_TETRA_POS {
            // The f32 as an f64, in text that reads back as that double.
            let [x, y, z] = p.map(f64::from);
            t += &format!("{x} {y} {z}\n");
        }
        for f in BIN_TETRA {
            t += &format!("3 {} {} {}\n", f[0], f[1], f[2]);
        }
        load_bytes(t.as_bytes(), Some(MeshFormat::Off)).unwrap().0
    };
    let geomview = BinaryOffLayout::ALL[0];
    let cases = BinaryOffLayout::ALL.iter().map(|&l| ("OFF", l, 0)).chain([
        ("NOFF", geomview, 3),
        ("COFF", geomview, 4),
        ("STOFF", geomview, 2),
        ("STCNOFF", geomview, 9),
    ]);
    for (keyword, layout, extra) in cases {
        let bytes = binary_off(keyword, layout, &BIN_TETRA_POS, extra, &BIN_TETRA);
        let (mesh, report) =
            load_bytes(&bytes, None).unwrap_or_else(|e| panic!("{keyword} {layout}: {e}"));
        assert_eq!(report.format, MeshFormat::Off);
        assert_eq!(mesh, ascii, "{keyword} {layout}");
        assert_eq!(report.notes, vec![LoadNote::BinaryOffLayout(layout)]);
    }
}

#[test]
fn binary_off_polygons_become_fans() {
    let pos = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
    ];
    let faces: [&[u32]; 5] = [
        &[0, 3, 2, 1],
        &[0, 1, 4],
        &[1, 2, 4],
        &[2, 3, 4],
        &[3, 0, 4],
    ];
    for layout in BinaryOffLayout::ALL {
        let (mesh, report) = load_bytes(&binary_off("OFF", layout, &pos, 0, &faces), None).unwrap();
        assert_eq!(ids(&mesh)[..2], [[0, 3, 2], [0, 2, 1]]);
        assert_eq!(mesh.faces.len(), 6);
        assert!(report.notes.contains(&LoadNote::Triangulated {
            polygons: 1,
            triangles: 2,
            ear_clipped: 0,
        }));
    }
}

fn binary_off_error(bytes: &[u8]) -> String {
    match load_bytes(bytes, Some(MeshFormat::Off)) {
        Err(LoadError::Parse {
            format: MeshFormat::Off,
            line: None,
            message,
        }) => message,
        other => panic!("{other:?}"),
    }
}

#[test]
fn binary_off_that_no_layout_reads_to_its_end_is_refused() {
    let whole = binary_off(
        "OFF",
        BinaryOffLayout::ALL[1],
        &BIN_TETRA_POS,
        0,
        &BIN_TETRA,
    );
    // One byte short, one byte over, a face of two vertices, and counts
    // that claim more than the file holds (refused before allocating).
    let mut over = whole.clone();
    over.push(b'\n');
    let mut two = whole.clone();
    let last_face = whole.len() - 16;
    two[last_face..last_face + 4].copy_from_slice(&2u32.to_be_bytes());
    let mut lying = whole.clone();
    lying[11..15].copy_from_slice(&0x7fff_ffffu32.to_be_bytes());
    for bytes in [
        &whole[..whole.len() - 1],
        &over[..],
        &two[..],
        &lying[..],
        b"OFF BINARY\n\0\0\0\x03",
    ] {
        assert!(
            binary_off_error(bytes).starts_with("binary OFF: no layout"),
            "{bytes:?}"
        );
    }
}

#[test]
fn binary_off_without_faces_is_refused_for_it() {
    let empty = binary_off("OFF", BinaryOffLayout::ALL[0], &[], 0, &[]);
    assert_eq!(
        binary_off_error(&empty),
        "binary OFF: the file declares no faces"
    );
}

#[test]
fn binary_off_negative_index_is_refused() {
    let faces: [&[u32]; 4] = [&[0, 2, 1], &[0, 1, u32::MAX], &[0, 3, 2], &[1, 2, 3]];
    let bytes = binary_off("OFF", BinaryOffLayout::ALL[3], &BIN_TETRA_POS, 0, &faces);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(
            &err,
            LoadError::InvalidIndex { format: MeshFormat::Off, text, reason: InvalidIndexReason::Negative, .. }
                if text == "-1 (face 1)"
        ),
        "{err:?}"
    );
}

/// A Git LFS pointer in place of a mesh (a repository cloned without
/// `git lfs`; meshio's test meshes are such) is named as one whatever the
/// extension says, with the size it points to, where the readers said
/// "expected `solid`" or read an OBJ without faces. A binary STL whose
/// 80-byte header happens to start with the pointer's line is an STL.
#[test]
fn a_git_lfs_pointer_is_named_as_one() {
    let pointer = b"version https://git-lfs.github.com/spec/v1\n\
        oid sha256:863bb0ad077f2af5c05e70338b9a2643c840208d26984141c731e95b7bcc1b6a\n\
        size 76928\n";
    let hints = [
        None,
        Some(MeshFormat::StlBinary),
        Some(MeshFormat::StlAscii),
        Some(MeshFormat::Obj),
        Some(MeshFormat::Off),
        Some(MeshFormat::PlyAscii),
        Some(MeshFormat::ThreeMf),
    ];
    for hint in hints {
        match load_bytes(pointer, hint) {
            Err(LoadError::GitLfsPointer { size }) => assert_eq!(size, Some(76928), "{hint:?}"),
            other => panic!("{hint:?}: {other:?}"),
        }
    }
    let err = load_bytes(&pointer[..44], Some(MeshFormat::Obj)).unwrap_err();
    assert!(
        matches!(err, LoadError::GitLfsPointer { size: None }),
        "{err:?}"
    );
    assert!(err.to_string().contains("git lfs pull"), "{err}");

    let stl = binary_stl(&pointer[..80], &TWO_TRIANGLES);
    let (mesh, report) = load_bytes(&stl, None).unwrap();
    assert_eq!(report.format, MeshFormat::StlBinary);
    assert_eq!(mesh.faces.len(), 2);
}

// ---------------------------------------------------------------- PLY

fn ply_header(format: &str, vertex_props: &str, nv: usize, face_prop: &str, nf: usize) -> Vec<u8> {
    format!(
        "ply\nformat {format} 1.0\ncomment test\nelement vertex {nv}\n{vertex_props}element face {nf}\n{face_prop}\nend_header\n"
    )
    .into_bytes()
}

/// An ASCII PLY of four vertices and the faces (0 2 1) and (0 1 3), for
/// the header tests to edit.
fn ply_ascii_two_faces() -> Vec<u8> {
    let mut b = ply_header(
        "ascii",
        "property double x\nproperty double y\nproperty double z\n",
        4,
        "property list uchar int vertex_indices",
        2,
    );
    b.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n0 0 0.1\n3 0 2 1\n3 0 1 3\n");
    b
}

/// A binary little-endian PLY of one triangle, as its header and its
/// payload; the first vertex's x is `x0` (whose bytes may look like text).
fn ply_binary_triangle(x0: f32) -> (Vec<u8>, Vec<u8>) {
    let header = ply_header(
        "binary_little_endian",
        "property float x\nproperty float y\nproperty float z\n",
        3,
        "property list uchar int vertex_indices",
        1,
    );
    let mut payload = Vec::new();
    for p in [[x0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.0, 1.0, 13.0]] {
        for c in p {
            payload.extend_from_slice(&c.to_le_bytes());
        }
    }
    payload.push(3);
    for i in [0i32, 1, 2] {
        payload.extend_from_slice(&i.to_le_bytes());
    }
    (header, payload)
}

/// The bytes with every `\n` made a lone `\r`.
fn lone_cr(b: &[u8]) -> Vec<u8> {
    b.iter()
        .map(|&c| if c == b'\n' { b'\r' } else { c })
        .collect()
}

/// Header lines indented by spaces and tabs (draco's
/// `test_extra_whitespace.ply`; `ply-rs-bw` refuses a header line that
/// does not start with its keyword) read as without: ASCII, and binary
/// with `\r` line ends too, where the payload must not move.
#[test]
fn ply_with_indented_header_lines_reads_as_without() {
    let indent = |b: &[u8]| -> Vec<u8> {
        let text = String::from_utf8(b.to_vec()).unwrap();
        let (head, body) = text.split_at(text.find("end_header").unwrap());
        let head: String = head
            .lines()
            .enumerate()
            .map(|(i, l)| match i {
                0 => format!("{l}\n"),
                _ => format!("{}{l}\n", [" ", "\t", " \t  "][i % 3]),
            })
            .collect();
        format!("{head}\t{body}").into_bytes()
    };
    let ascii = ply_ascii_two_faces();
    let (want, _) = load_bytes(&ascii, None).unwrap();
    let indented = indent(&ascii);
    assert!(indented.starts_with(b"ply\n\tformat ascii 1.0\n \t  comment"));
    let (got, report) = load_bytes(&indented, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyAscii);
    assert_eq!(got.positions, want.positions);
    assert_eq!(ids(&got), vec![[0, 2, 1], [0, 1, 3]]);

    // Binary, header lines ended by a lone `\r` and indented; a payload
    // that starts with a space and a tab (as the x of the first vertex)
    // stays as it is.
    let odd = f32::from_le_bytes([b' ', b'\t', b' ', 0x3f]);
    let (header, payload) = ply_binary_triangle(odd);
    let mut file = lone_cr(&indent(&header));
    file.extend_from_slice(&payload);
    let (got, report) = load_bytes(&file, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyBinaryLittleEndian);
    assert_eq!(got.positions[0][0], f64::from(odd));
    assert_eq!(got.positions[2], [0.0, 1.0, 13.0]);
    assert_eq!(ids(&got), vec![[0, 1, 2]]);
}

/// A header line with no PLY keyword before the first element (Blender
/// 2.4's exporter wrote `Created by Blender3D 247 - ...` after `format`;
/// assimp keeps such a file) is read as a comment, with a note naming it,
/// in ASCII and binary files; after the first element such a line still
/// fails (a misspelt `property` would move every number).
#[test]
fn ply_header_line_without_a_keyword_before_the_elements_is_a_comment() {
    let blender = |b: &[u8]| -> Vec<u8> {
        let text = String::from_utf8_lossy(b).into_owned();
        let at = text.find("comment test").unwrap();
        let mut out = b[..at].to_vec();
        out.extend_from_slice(b"Created by Blender3D 247 - www.blender.org, source file: \n");
        out.extend_from_slice(&b[at..]);
        out
    };
    let ascii = ply_ascii_two_faces();
    let (want, _) = load_bytes(&ascii, None).unwrap();
    let (got, report) = load_bytes(&blender(&ascii), None).unwrap();
    assert_eq!(got.positions, want.positions);
    assert_eq!(ids(&got), vec![[0, 2, 1], [0, 1, 3]]);
    let notes: Vec<String> = report.notes.iter().map(|n| n.to_string()).collect();
    assert!(
        notes
            .iter()
            .any(|n| n.contains("1 header line without a PLY keyword")
                && n.contains(
                    "on line 3: `Created by Blender3D 247 - www.blender.org, source file:`"
                )),
        "{notes:?}"
    );
    // A line number of an error is the file's own: the second face of the
    // Blender file is on line 17 (11 header lines, 4 vertices, a face).
    let mut broken = blender(&ascii);
    let at = broken.len() - 2;
    broken[at] = b'x';
    match load_bytes(&broken, None).unwrap_err() {
        LoadError::Parse { line, .. } => assert_eq!(line, Some(17)),
        e => panic!("{e:?}"),
    }

    let (header, payload) = ply_binary_triangle(0.0);
    let binary = [header.clone(), payload.clone()].concat();
    let blended = [blender(&header), payload].concat();
    let (want, _) = load_bytes(&binary, None).unwrap();
    let (got, report) = load_bytes(&blended, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyBinaryLittleEndian);
    assert_eq!(got.positions, want.positions);
    assert_eq!(ids(&got), vec![[0, 1, 2]]);

    // After the first element: still an error.
    let text = String::from_utf8(ascii.clone()).unwrap();
    let late = text.replacen("property double y\n", "propery double y\n", 1);
    assert!(matches!(
        load_bytes(late.as_bytes(), None).unwrap_err(),
        LoadError::Parse { .. }
    ));
}

/// Lines ended by a lone `\r` (classic Mac OS; Rhino 6 writes PLY headers
/// so, draco keeps such a file) read as with `\n`: a binary file whose
/// header ends its lines with `\r` (and whose payload holds `\r` bytes,
/// which stay as they are), and an ASCII file with `\r` everywhere.
#[test]
fn ply_with_carriage_return_line_ends_reads_as_with_newlines() {
    // A vertex whose x is 0x0d0d0d0d as little-endian f32 bytes: a `\r`
    // in the payload.
    let odd = f32::from_le_bytes([b'\r'; 4]);
    let (header, payload) = ply_binary_triangle(odd);
    let lf = [header.clone(), payload.clone()].concat();
    let header = [lone_cr(&header), payload].concat();
    let (want, _) = load_bytes(&lf, None).unwrap();
    let (got, report) = load_bytes(&header, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyBinaryLittleEndian);
    assert_eq!(got.positions, want.positions);
    assert_eq!(got.positions[0][0], f64::from(odd));
    assert_eq!(ids(&got), vec![[0, 1, 2]]);

    let ascii = ply_ascii_two_faces();
    let (want, _) = load_bytes(&ascii, None).unwrap();
    let (got, report) = load_bytes(&lone_cr(&ascii), None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyAscii);
    assert_eq!(got.positions, want.positions);
    assert_eq!(ids(&got), vec![[0, 2, 1], [0, 1, 3]]);
    // A parse error names the line counted by `\r`: the header's 10 lines,
    // 4 vertices, then the second face, line 16.
    let mut broken = lone_cr(&ascii);
    let at = broken.len() - 2;
    broken[at] = b'x';
    match load_bytes(&broken, None).unwrap_err() {
        LoadError::Parse { line, .. } => assert_eq!(line, Some(16)),
        e => panic!("{e:?}"),
    }
}

#[test]
fn ply_big_endian_with_float_coordinates_and_int_indices() {
    let mut b = ply_header(
        "binary_big_endian",
        "property float x\nproperty float y\nproperty float z\n",
        3,
        "property list uchar int vertex_indices",
        1,
    );
    for p in [[0.5f32, 0.0, 0.0], [1.0, 0.1, 0.0], [0.0, 1.0, -0.0]] {
        for c in p {
            b.extend_from_slice(&c.to_be_bytes());
        }
    }
    b.push(3);
    for i in [0i32, 1, 2] {
        b.extend_from_slice(&i.to_be_bytes());
    }
    let (mesh, report) = load_bytes(&b, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyBinaryBigEndian);
    assert_eq!(mesh.positions[1], [1.0, f64::from(0.1f32), 0.0]);
    assert_eq!(ids(&mesh), vec![[0, 1, 2]]);
}

#[test]
fn ply_little_endian_ushort_coordinates_and_vertex_index_name() {
    let mut b = ply_header(
        "binary_little_endian",
        "property ushort x\nproperty short y\nproperty uchar z\nproperty uchar red\n",
        3,
        "property list uchar ushort vertex_index",
        1,
    );
    for (x, y, z) in [(0u16, -1i16, 0u8), (7, 0, 1), (0, 5, 2)] {
        b.extend_from_slice(&x.to_le_bytes());
        b.extend_from_slice(&y.to_le_bytes());
        b.push(z);
        b.push(200);
    }
    b.push(3);
    for i in [2u16, 1, 0] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let (mesh, report) = load_bytes(&b, Some(MeshFormat::PlyAscii)).unwrap();
    assert_eq!(report.format, MeshFormat::PlyBinaryLittleEndian);
    assert_eq!(
        mesh.positions,
        vec![[0.0, -1.0, 0.0], [7.0, 0.0, 1.0], [0.0, 5.0, 2.0]]
    );
    assert_eq!(ids(&mesh), vec![[2, 1, 0]]);
}

#[test]
fn ply_with_a_lying_element_count_fails_before_parsing() {
    let mut b = ply_header(
        "binary_little_endian",
        "property double x\nproperty double y\nproperty double z\n",
        1_000_000_000,
        "property list uchar int vertex_indices",
        1,
    );
    b.extend_from_slice(&[0u8; 100]);
    let err = load_bytes(&b, None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::ClaimedCountTooLarge {
                format: MeshFormat::PlyBinaryLittleEndian,
                claimed: 1_000_000_000,
                available_bytes: 100,
                ref element,
            } if element == "vertex"
        ),
        "{err:?}"
    );
}

#[test]
fn ply_ascii_polygon_and_out_of_range_index() {
    let mut b = ply_header(
        "ascii",
        "property double x\nproperty double y\nproperty double z\n",
        4,
        "property list uchar uint vertex_indices",
        2,
    );
    b.extend_from_slice(b"0 0 0\n1 0 0\n1 1 0\n0.1 1 -0\n4 0 1 2 3\n3 0 1 10\n");
    let (mesh, report) = load_bytes(&b, None).unwrap();
    assert_eq!(report.format, MeshFormat::PlyAscii);
    assert_eq!(mesh.positions[3], [0.1, 1.0, 0.0]);
    assert_eq!(ids(&mesh), vec![[0, 1, 2], [0, 2, 3], [0, 1, 10]]);
}

#[test]
fn ply_negative_index_is_a_typed_error() {
    let mut b = ply_header(
        "ascii",
        "property float x\nproperty float y\nproperty float z\n",
        3,
        "property list uchar int vertex_indices",
        1,
    );
    b.extend_from_slice(b"0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n");
    let err = load_bytes(&b, None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::InvalidIndex {
                format: MeshFormat::PlyAscii,
                reason: InvalidIndexReason::Negative,
                ..
            }
        ),
        "{err:?}"
    );
}

/// The message of a PLY parse error, asserted to be one readable line.
fn ply_parse_message(bytes: &[u8], line: usize) -> String {
    match load_bytes(bytes, None).unwrap_err() {
        LoadError::Parse {
            line: Some(l),
            message,
            ..
        } if l == line => {
            assert!(!message.contains('\n'), "{message:?}");
            assert!(!message.contains("ParseError"), "{message:?}");
            message
        }
        e => panic!("expected a parse error at line {line}, got {e:?}"),
    }
}

/// A header line without a keyword after the first element (before it,
/// as an old Blender wrote one, it is a comment): the line is quoted and
/// the keywords a header line may start with listed.
#[test]
fn ply_header_line_without_keyword_is_named_with_the_keywords_expected() {
    let b =
        b"ply\nformat ascii 1.0\nelement vertex 0\nCreated by hand, source file: \nend_header\n";
    let m = ply_parse_message(b, 4);
    assert!(m.contains("`Created by hand, source file:`"), "{m}");
    assert!(
        m.contains("at column 1, expected one of comment, element, end_header, format, obj_info, ply, property"),
        "{m}"
    );
}

/// A property of an unknown type: the column of the type and the types
/// PLY has.
#[test]
fn ply_unknown_property_type_names_the_types() {
    let b = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n0\n";
    let m = ply_parse_message(b, 4);
    assert!(m.contains("`property real x`"), "{m}");
    assert!(m.contains("at column 10, expected one of"), "{m}");
    assert!(m.contains("float32") && m.contains("uchar"), "{m}");
}

/// A vertex line shorter than its element's properties (a face list
/// declared under `vertex`): the line is quoted with what was missing.
#[test]
fn ply_short_element_line_is_quoted() {
    let b = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
property float z\nproperty list uchar uint vertex_indices\nend_header\n7.5 0 1\n";
    let m = ply_parse_message(b, 9);
    assert!(m.contains("`7.5 0 1`"), "{m}");
    assert!(m.contains("List(UChar, UInt)"), "{m}");
}

/// A PLY with the corners of a tetrahedron and one `tristrips` element
/// holding `strips` (an `int` list: `-1` separates strips).
fn ply_tristrips(format: &str, strips: &[i32]) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let corners: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    if format == "ascii" {
        for p in corners {
            b.extend_from_slice(format!("{} {} {}\n", p[0], p[1], p[2]).as_bytes());
        }
        let list: Vec<String> = strips.iter().map(i32::to_string).collect();
        b.extend_from_slice(format!("{} {}\n", strips.len(), list.join(" ")).as_bytes());
    } else {
        for v in corners.iter().flatten() {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&(strips.len() as i32).to_le_bytes());
        for v in strips {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    b
}

#[test]
fn ply_tristrips_become_triangles_of_one_orientation() {
    // Two strips: `1 0 2` is the triangle (1 0 2) (facing -z, outward);
    // `2 0 3 1 2 2` is (2 0 3), then (0 3 1) turned to (3 0 1), then
    // (3 1 2) kept, then (1 2 2), a joint with a repeated id, dropped.
    let strips = [1, 0, 2, -1, 2, 0, 3, 1, 2, 2];
    for format in ["ascii", "binary_little_endian"] {
        let (mesh, report) = load_bytes(&ply_tristrips(format, &strips), None).unwrap();
        assert_eq!(
            ids(&mesh),
            vec![[1, 0, 2], [2, 0, 3], [3, 0, 1], [3, 1, 2]],
            "{format}"
        );
        assert!(
            report.notes.contains(&LoadNote::Strips {
                strips: 2,
                triangles: 4,
                joints: 1
            }),
            "{:?}",
            report.notes
        );
        // Every edge in both directions once: the closed tetrahedron,
        // facing outward.
        let v = wmslice::mesh::validate::validate(&mesh);
        assert!(v.is_accepted(), "{format}: {:?}", v.defects);
        assert!(v.defects.is_empty(), "{format}: {:?}", v.defects);
    }
}

#[test]
fn ply_tristrips_refuse_other_negative_ids() {
    let err = load_bytes(&ply_tristrips("ascii", &[1, 0, 2, -2, 3]), None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::InvalidIndex {
                reason: InvalidIndexReason::Negative,
                ..
            }
        ),
        "{err:?}"
    );
}

// ---------------------------------------------------------------- 3MF

const NS: &str = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";

/// A tetrahedron object with the given id and coordinate scale.
fn tetra_object(id: u32, s: &str) -> String {
    format!(
        r#"<object id="{id}" type="model"><mesh><vertices>
<vertex x="0" y="0" z="0"/><vertex x="{s}" y="0" z="0"/><vertex x="0" y="{s}" z="0"/><vertex x="0" y="0" z="{s}"/>
</vertices><triangles>
<triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="1" v2="2" v3="3"/><triangle v1="2" v2="0" v3="3"/>
</triangles></mesh></object>"#
    )
}

fn model(resources: &str, build: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="{NS}"><resources>{resources}</resources><build>{build}</build></model>"#
    )
}

fn zip_parts(parts: &[(&str, &[u8])]) -> Vec<u8> {
    let mut zw = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, data) in parts {
        zw.start_file(*name, options).unwrap();
        zw.write_all(data).unwrap();
    }
    zw.finish().unwrap().into_inner()
}

fn three_mf(model_xml: &str) -> Vec<u8> {
    zip_parts(&[("3D/3dmodel.model", model_xml.as_bytes())])
}

#[test]
fn three_mf_item_transform_is_applied_exactly() {
    let xml = model(
        &tetra_object(1, "1.5"),
        r#"<item objectid="1" transform="2 0 0 0 1 0 0 0 1 10 -0.25 0.5"/>"#,
    );
    let (mesh, report) = load_bytes(&three_mf(&xml), None).unwrap();
    assert_eq!(report.format, MeshFormat::ThreeMf);
    assert_eq!(
        mesh.positions,
        vec![
            [10.0, -0.25, 0.5],
            [13.0, -0.25, 0.5],
            [10.0, 1.25, 0.5],
            [10.0, -0.25, 2.0]
        ]
    );
    assert_eq!(ids(&mesh)[0], [0, 2, 1]);
    assert!(report
        .notes
        .contains(&LoadNote::TransformApplied { item: 0, object: 1 }));
}

#[test]
fn three_mf_components_compose_and_instances_stay_separate() {
    let resources = format!(
        r#"{}<object id="2"><components><component objectid="1" transform="0 1 0 -1 0 0 0 0 1 0 0 5"/></components></object>"#,
        tetra_object(1, "1")
    );
    let xml = model(
        &resources,
        r#"<item objectid="2" transform="1 0 0 0 1 0 0 0 1 100 0 0"/><item objectid="1"/>"#,
    );
    let rels = br#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/other.model" Id="r0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>"#;
    let bytes = zip_parts(&[("_rels/.rels", rels), ("3D/other.model", xml.as_bytes())]);
    let (mesh, _) = load(&write_temp("c.3mf", &bytes)).unwrap();
    assert_eq!(mesh.num_vertices(), 8);
    assert_eq!(mesh.num_faces(), 8);
    // (x, y, z) -> (-y, x, z + 5) -> (-y + 100, x, z + 5)
    assert_eq!(mesh.positions[1], [100.0, 1.0, 5.0]);
    assert_eq!(mesh.positions[2], [99.0, 0.0, 5.0]);
    assert_eq!(mesh.positions[5], [1.0, 0.0, 0.0]);
    assert_eq!(ids(&mesh)[4], [4, 6, 5]);
}

/// Many relationships before the model's (thumbnails, metadata) are
/// siblings, not nesting: an empty `<Relationship/>` closes itself. The
/// relationships part counted each as a level and refused the package as
/// nesting deeper than 64.
#[test]
fn three_mf_many_relationships_before_the_models_are_not_nesting() {
    let xml = model(&tetra_object(1, "1"), r#"<item objectid="1"/>"#);
    let thumbnails: String = (0..100)
        .map(|k| {
            format!(
                r#"<Relationship Target="/Metadata/t{k}.png" Id="t{k}" Type="http://schemas.openxmlformats.org/package/2006/relationships/metadata/thumbnail"/>"#
            )
        })
        .collect();
    let rels = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">{thumbnails}<Relationship Target="/3D/part.model" Id="r0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>"#
    );
    let bytes = zip_parts(&[
        ("_rels/.rels", rels.as_bytes()),
        ("3D/part.model", xml.as_bytes()),
    ]);
    let (mesh, _) = load_bytes(&bytes, None).unwrap();
    assert_eq!((mesh.num_vertices(), mesh.num_faces()), (4, 4));
    // Real nesting past the limit is still refused.
    let deep = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">{}{}</Relationships>"#,
        "<a>".repeat(70),
        "</a>".repeat(70)
    );
    let bytes = zip_parts(&[
        ("_rels/.rels", deep.as_bytes()),
        ("3D/part.model", xml.as_bytes()),
    ]);
    assert!(matches!(
        load_bytes(&bytes, None),
        Err(LoadError::XmlTooDeep { ref part, .. }) if part == "_rels/.rels"
    ));
}

fn write_temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = tempfile::tempdir().unwrap().keep();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn three_mf_transform_that_would_round_is_refused() {
    let xml = model(
        &tetra_object(1, "0.1"),
        r#"<item objectid="1" transform="3 0 0 0 1 0 0 0 1 0 0 0"/>"#,
    );
    let err = load_bytes(&three_mf(&xml), None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::InexactTransform {
                item: 0,
                object: 1,
                vertex: 1
            }
        ),
        "{err:?}"
    );
}

/// The exact image kept beside the mesh: `load_bytes` refuses it, and
/// snapping places it from its exact value, which its nearest double
/// would not. `2^-60 + 0.5` is not a double (61 bits), and its nearest
/// double is `0.5`: on the grid 1 that is a tie, which goes to the even
/// 0, while the exact image is past the half and goes to 1.
#[test]
fn three_mf_transform_that_rounds_is_snapped_from_the_exact_image() {
    let tiny = 2f64.powi(-60);
    let xml = model(
        &tetra_object(1, &tiny.to_string()),
        r#"<item objectid="1" transform="1 0 0 0 1 0 0 0 1 0.5 0 0"/>"#,
    );
    let bytes = three_mf(&xml);
    assert!(matches!(
        load_bytes(&bytes, None),
        Err(LoadError::InexactTransform {
            item: 0,
            object: 1,
            vertex: 1
        })
    ));
    let (mesh, _, exact) = load_bytes_exact(&bytes, None).unwrap();
    // Only vertex 1, (0.5 + 2^-60, 0, 0), has no exact double; the mesh
    // holds its nearest one.
    let r = |x: f64| Rat::from_float(x).unwrap();
    let kept: Vec<_> = exact.iter().cloned().collect();
    assert_eq!(
        kept,
        vec![(VertexId(1), [r(0.5) + r(tiny), r(0.0), r(0.0)])]
    );
    assert_eq!(mesh.positions[1], [0.5, 0.0, 0.0]);
    // Without a grid there is no exact place for it.
    assert!(matches!(
        prepare_exact(mesh.clone(), &exact, None),
        Err(PrepareError::NotDoubles(LoadError::InexactTransform {
            vertex: 1,
            ..
        }))
    ));
    let one = Rat::from_integer(1.into());
    // (0.5, 0, 0) -> 0 (a tie, to even); (0.5 + 2^-60, 0, 0) -> 1;
    // (0.5, 2^-60, 0) and (0.5, 0, 2^-60) -> the origin.
    let s = snap_exact(&mesh, &exact, &one).unwrap();
    assert_eq!(s.mesh.positions, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    assert_eq!((s.merged, s.max_move), (2, r(0.5)));
    // The nearest doubles alone would put every vertex on the origin.
    assert_eq!(snap(&mesh, &one).unwrap().mesh.positions, vec![[0.0; 3]]);
    // Either way three corners of the tetrahedron meet, and every face
    // collapses: preparing refuses it once, by the grid.
    for p in [
        prepare_exact(mesh.clone(), &exact, Some(&one)),
        prepare(mesh, Some(&one)).map_err(PrepareError::Snap),
    ] {
        assert!(matches!(
            p,
            Err(PrepareError::Snap(SnapError::CollapsedEverything {
                faces: 4,
                ..
            }))
        ));
    }
}

/// The production extension as Bambu Studio writes it: the root part's
/// object gathers components held in other model parts (`p:path`), which
/// reuse each other's object ids.
#[test]
fn three_mf_components_in_other_parts_are_placed_from_their_part() {
    const PROD: &str = "http://schemas.microsoft.com/3dmanufacturing/production/2015/06";
    let root = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="{NS}" xmlns:p="{PROD}"><resources>
<object id="2"><components>
<component p:path="/3D/Objects/a.model" objectid="1" transform="1 0 0 0 1 0 0 0 1 10 0 0"/>
<component p:path="/3D/Objects/b.model" objectid="1"/>
</components></object></resources>
<build><item objectid="2" transform="1 0 0 0 1 0 0 0 1 0 0 5"/></build></model>"#
    );
    let a = model(&tetra_object(1, "1"), "");
    let b = model(&tetra_object(1, "2"), "");
    let bytes = zip_parts(&[
        ("3D/3dmodel.model", root.as_bytes()),
        ("3D/Objects/a.model", a.as_bytes()),
        ("3D/Objects/b.model", b.as_bytes()),
    ]);
    let (mesh, _) = load_bytes(&bytes, None).unwrap();
    assert_eq!(mesh.num_faces(), 8);
    // a's tetrahedron of size 1 moved by (10, 0, 5); b's of size 2 by (0, 0, 5).
    assert_eq!(
        mesh.positions,
        vec![
            [10.0, 0.0, 5.0],
            [11.0, 0.0, 5.0],
            [10.0, 1.0, 5.0],
            [10.0, 0.0, 6.0],
            [0.0, 0.0, 5.0],
            [2.0, 0.0, 5.0],
            [0.0, 2.0, 5.0],
            [0.0, 0.0, 7.0]
        ]
    );
    assert_eq!(ids(&mesh)[4], [4, 6, 5]);

    // A part that is not in the package is named.
    let bytes = zip_parts(&[
        ("3D/3dmodel.model", root.as_bytes()),
        ("3D/Objects/a.model", a.as_bytes()),
    ]);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(&err, LoadError::ZipEntryMissing { name } if name == "3D/Objects/b.model"),
        "{err:?}"
    );

    // A non-root part may not refer to another part (the extension's rule).
    let nested = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="{NS}" xmlns:p="{PROD}"><resources>
<object id="1"><components><component p:path="/3D/Objects/b.model" objectid="1"/></components></object>
</resources><build/></model>"#
    );
    let bytes = zip_parts(&[
        ("3D/3dmodel.model", root.as_bytes()),
        ("3D/Objects/a.model", nested.as_bytes()),
        ("3D/Objects/b.model", b.as_bytes()),
    ]);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(&err, LoadError::Unsupported { feature, .. } if feature.contains("non-root part `3D/Objects/a.model`")),
        "{err:?}"
    );
}

/// Parts small enough to be free of the ratio limit one by one are held to
/// it together: three of 600 kB that deflate to almost nothing.
#[test]
fn three_mf_many_small_parts_are_a_zip_bomb_together() {
    const PROD: &str = "http://schemas.microsoft.com/3dmanufacturing/production/2015/06";
    let components: String = ["a", "b", "c"]
        .iter()
        .map(|p| format!(r#"<component p:path="/3D/{p}.model" objectid="1"/>"#))
        .collect();
    let root = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="{NS}" xmlns:p="{PROD}"><resources>
<object id="2"><components>{components}</components></object></resources>
<build><item objectid="2"/></build></model>"#
    );
    let padded = format!(
        "{}<!-- {} -->",
        model(&tetra_object(1, "1"), ""),
        "x".repeat(600_000)
    );
    let bytes = zip_parts(&[
        ("3D/3dmodel.model", root.as_bytes()),
        ("3D/a.model", padded.as_bytes()),
        ("3D/b.model", padded.as_bytes()),
        ("3D/c.model", padded.as_bytes()),
    ]);
    assert!(bytes.len() < 20_000, "{}", bytes.len());
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(&err, LoadError::ZipBomb { name, .. } if name == "3D/b.model"),
        "{err:?}"
    );
}

/// Object types (3MF core): a part and a solid support are sliced, a
/// support or a surface (which need not be closed) is skipped with a note,
/// an item placing an `other` object or an unknown type is refused.
#[test]
fn three_mf_object_types_decide_what_is_sliced() {
    let typed = |id: u32, kind: &str, s: &str| {
        tetra_object(id, s).replacen(r#"type="model""#, &format!(r#"type="{kind}""#), 1)
    };
    let resources = format!(
        "{}{}{}{}",
        typed(1, "model", "1"),
        typed(2, "support", "2"),
        typed(3, "solidsupport", "3"),
        typed(4, "surface", "4")
    );
    let items =
        r#"<item objectid="1"/><item objectid="2"/><item objectid="3"/><item objectid="4"/>"#;
    let (mesh, report) = load_bytes(&three_mf(&model(&resources, items)), None).unwrap();
    // The tetrahedra of size 1 and 3; sizes 2 and 4 are skipped.
    assert_eq!(mesh.num_vertices(), 8);
    assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
    assert_eq!(mesh.positions[5], [3.0, 0.0, 0.0]);
    assert!(report.notes.contains(&LoadNote::Ignored {
        kind: "build items placing a support or a surface (not solids)".to_owned(),
        count: 2
    }));

    let other = format!("{}{}", typed(1, "model", "1"), typed(2, "other", "2"));
    let err = load_bytes(
        &three_mf(&model(
            &other,
            r#"<item objectid="1"/><item objectid="2"/>"#,
        )),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(err, LoadError::PlacesOther { item: 1, object: 2 }),
        "{err:?}"
    );
    // An `other` object no item places is fine.
    assert!(load_bytes(&three_mf(&model(&other, r#"<item objectid="1"/>"#)), None).is_ok());

    let bad = typed(1, "invalidtype", "1");
    let err = load_bytes(&three_mf(&model(&bad, r#"<item objectid="1"/>"#)), None).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::BadAttribute {
                element: "object",
                attribute: "type",
                ..
            }
        ),
        "{err:?}"
    );
}

/// A beam lattice's beams are part of its object's solid: an object with
/// one is refused by name when placed (its triangles alone are another
/// part), and ignored when no item places it.
#[test]
fn three_mf_beam_lattice_is_refused_when_placed() {
    let lattice = tetra_object(2, "1").replace(
        "</triangles></mesh>",
        r#"</triangles><beamlattice minlength="0.1" radius="0.5"><beams><beam v1="0" v2="3"/></beams></beamlattice></mesh>"#,
    );
    let resources = format!("{}{lattice}", tetra_object(1, "1"));
    let err = load_bytes(
        &three_mf(&model(&resources, r#"<item objectid="2"/>"#)),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(&err, LoadError::Unsupported { feature, .. } if feature.contains("object 2 is a beam lattice")),
        "{err:?}"
    );
    let (mesh, _) = load_bytes(
        &three_mf(&model(&resources, r#"<item objectid="1"/>"#)),
        None,
    )
    .unwrap();
    assert_eq!(mesh.num_faces(), 4);
}

#[test]
fn three_mf_component_cycle_is_refused() {
    let resources = r#"<object id="1"><components><component objectid="2"/></components></object><object id="2"><components><component objectid="1"/></components></object>"#;
    let err = load_bytes(
        &three_mf(&model(resources, r#"<item objectid="1"/>"#)),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(err, LoadError::ComponentCycle { object: 1 }),
        "{err:?}"
    );
}

#[test]
fn three_mf_out_of_range_triangle_is_refused() {
    let resources = r#"<object id="7"><mesh><vertices><vertex x="0" y="0" z="0"/></vertices><triangles><triangle v1="0" v2="0" v3="3"/></triangles></mesh></object>"#;
    let err = load_bytes(
        &three_mf(&model(resources, r#"<item objectid="7"/>"#)),
        None,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::IndexOutOfRange {
                format: MeshFormat::ThreeMf,
                object: 7,
                triangle: 0,
                index: 3,
                vertices: 1
            }
        ),
        "{err:?}"
    );
}

#[test]
fn three_mf_highly_compressible_part_is_a_zip_bomb() {
    let mut xml = model(&tetra_object(1, "1"), r#"<item objectid="1"/>"#);
    xml.push_str(&" ".repeat(4 << 20));
    let err = load_bytes(&three_mf(&xml), None).unwrap_err();
    assert!(
        matches!(err, LoadError::ZipBomb { ref name, ratio_limit: 200, .. } if name == "3D/3dmodel.model"),
        "{err:?}"
    );
}

/// Rewrites the uncompressed size of every zip entry (local and central
/// headers), as a forged archive would.
fn forge_uncompressed_size(mut zip: Vec<u8>, size: u32) -> Vec<u8> {
    let mut i = 0;
    while i + 4 <= zip.len() {
        let sig = &zip[i..i + 4];
        if sig == b"PK\x03\x04" {
            zip[i + 22..i + 26].copy_from_slice(&size.to_le_bytes());
        } else if sig == b"PK\x01\x02" {
            zip[i + 24..i + 28].copy_from_slice(&size.to_le_bytes());
        }
        i += 1;
    }
    zip
}

#[test]
fn three_mf_part_declaring_three_gigabytes_is_refused_before_inflating() {
    let xml = model(&tetra_object(1, "1"), r#"<item objectid="1"/>"#);
    let bytes = forge_uncompressed_size(three_mf(&xml), 3 << 30);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(err, LoadError::EntryTooLarge { declared, limit, .. } if declared == 3 << 30 && limit == 2 << 30),
        "{err:?}"
    );
}

#[test]
fn three_mf_part_inflating_past_its_declared_size_is_stopped() {
    let xml = model(&tetra_object(1, "1"), r#"<item objectid="1"/>"#);
    let bytes = forge_uncompressed_size(three_mf(&xml), 40);
    let err = load_bytes(&bytes, None).unwrap_err();
    assert!(
        matches!(err, LoadError::ZipBomb { inflated: 41, .. }),
        "{err:?}"
    );
}

#[test]
fn three_mf_deeply_nested_xml_is_refused() {
    let deep = format!("{}{}", "<a>".repeat(10_000), "</a>".repeat(10_000));
    let xml = model(
        &tetra_object(1, "1"),
        &format!(r#"<item objectid="1"/>{deep}"#),
    );
    let err = load_bytes(&three_mf(&xml), None).unwrap_err();
    assert!(
        matches!(err, LoadError::XmlTooDeep { limit: 64, .. }),
        "{err:?}"
    );
}

#[test]
fn three_mf_without_model_part_is_a_missing_entry() {
    let bytes = zip_parts(&[("readme.txt", b"hello")]);
    let err = load_bytes(&bytes, Some(MeshFormat::ThreeMf)).unwrap_err();
    assert!(
        matches!(err, LoadError::ZipEntryMissing { ref name } if name == "3D/3dmodel.model"),
        "{err:?}"
    );
}

#[test]
fn three_mf_that_is_not_a_zip_is_a_broken_archive() {
    let err = load_bytes(b"PK\x03\x04 not really", Some(MeshFormat::ThreeMf)).unwrap_err();
    assert!(matches!(err, LoadError::ZipArchive { .. }), "{err:?}");
}

#[test]
fn three_mf_model_part_outside_its_package_is_named_as_xml() {
    let xml = model(&tetra_object(1, "1"), r#"<item objectid="1"/>"#);
    for bytes in [
        xml.clone().into_bytes(),
        format!("\u{feff}\r\n  {xml}").into_bytes(),
    ] {
        let err = load_bytes(&bytes, Some(MeshFormat::ThreeMf)).unwrap_err();
        assert!(
            matches!(&err, LoadError::Parse { format: MeshFormat::ThreeMf, line: None, message }
                if message.starts_with("the file is XML, not a zip package")),
            "{err:?}"
        );
    }
}

// ---------------------------------------------------------------- UTF-16

/// `text` as UTF-16 with its byte-order mark, big- or little-endian.
fn utf16(text: &str, big: bool) -> Vec<u8> {
    let units = std::iter::once(0xFEFF).chain(text.encode_utf16());
    units
        .flat_map(|u| {
            if big {
                u.to_be_bytes()
            } else {
                u.to_le_bytes()
            }
        })
        .collect()
}

/// The unit tetrahedron as OBJ and OFF text, and one facet as ASCII STL:
/// plain texts the encoding and line-end tests wrap.
const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
const TETRA_OFF: &str =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const FACET_STL: &str = "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";

#[test]
fn utf16_text_is_named_as_such_in_every_text_format() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 0\nelement face 0\nend_header\n";
    let cases = [
        (TETRA_OBJ, MeshFormat::Obj),
        (TETRA_OFF, MeshFormat::Off),
        (FACET_STL, MeshFormat::StlAscii),
        (ply, MeshFormat::PlyAscii),
    ];
    for (text, format) in cases {
        // Read as UTF-8, the same text loads (or, for the empty PLY, fails
        // for another reason).
        let plain = load_bytes(text.as_bytes(), Some(format));
        assert!(
            !matches!(&plain, Err(LoadError::Parse { message, .. }) if message.contains("UTF-16"))
        );
        for big in [true, false] {
            let err = load_bytes(&utf16(text, big), Some(format)).unwrap_err();
            assert!(
                matches!(&err, LoadError::Parse { line: Some(1), message, .. }
                    if message.starts_with("the file is UTF-16 text")),
                "{format:?} {big}: {err:?}"
            );
        }
    }
    // A binary STL's header may start with the same two bytes: read as
    // binary when its size is a binary STL's, or when the text after them
    // is not `solid` in UTF-16 (bytes after the triangles are a note).
    let utf16_solid = binary_stl(b"\xFF\xFEs\0o\0l\0i\0d\0", &TWO_TRIANGLES);
    let mut bytes_solid = binary_stl(b"\xFF\xFEsolid", &TWO_TRIANGLES);
    bytes_solid.push(0);
    for bytes in [&utf16_solid, &bytes_solid] {
        for hint in [MeshFormat::StlBinary, MeshFormat::StlAscii] {
            let (mesh, _) = load_bytes(bytes, Some(hint)).unwrap();
            assert_eq!(mesh.faces.len(), 2);
        }
    }
    let mut longer = utf16_solid.clone();
    longer.push(0);
    let err = load_bytes(&longer, Some(MeshFormat::StlBinary)).unwrap_err();
    assert!(
        matches!(&err, LoadError::Parse { message, .. } if message.contains("UTF-16")),
        "{err:?}"
    );
}

/// A UTF-8 byte-order mark before the text is skipped in every text format
/// (recognized by content too): the mesh is the one read without it.
/// Before, an OBJ's first `v` glued to the mark went unread (every index
/// then named the next vertex), and STL, OFF and PLY were refused. A
/// binary STL whose header starts with the same three bytes is read as
/// binary.
#[test]
fn utf8_byte_order_mark_is_skipped_in_every_text_format() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (text, format) in [
        (TETRA_OBJ, MeshFormat::Obj),
        (TETRA_OFF, MeshFormat::Off),
        (FACET_STL, MeshFormat::StlAscii),
        (ply, MeshFormat::PlyAscii),
    ] {
        let (want, _) = load_bytes(text.as_bytes(), Some(format)).unwrap();
        let marked = [b"\xEF\xBB\xBF".as_slice(), text.as_bytes()].concat();
        for hint in [Some(format), None] {
            let (got, report) =
                load_bytes(&marked, hint).unwrap_or_else(|e| panic!("{format:?} {hint:?}: {e}"));
            assert_eq!(report.format, format);
            assert_eq!(got.positions, want.positions, "{format:?}");
            assert_eq!(ids(&got), ids(&want), "{format:?}");
        }
    }
    let binary = binary_stl(b"\xEF\xBB\xBFsolid", &TWO_TRIANGLES);
    let (mesh, report) = load_bytes(&binary, Some(MeshFormat::StlAscii)).unwrap();
    assert_eq!(report.format, MeshFormat::StlBinary);
    assert_eq!(mesh.faces.len(), 2);
}

/// OBJ and OFF whose lines end in a lone `\r` (classic Mac OS) read as
/// their `\n` twins, and so do mixed line ends; an error names the line
/// counted by any of them. Before, an OBJ so written was one line: one
/// vertex, no face.
#[test]
fn obj_and_off_with_lone_carriage_returns_read_as_with_newlines() {
    for (text, format) in [(TETRA_OBJ, MeshFormat::Obj), (TETRA_OFF, MeshFormat::Off)] {
        let (want, _) = load_bytes(text.as_bytes(), Some(format)).unwrap();
        assert_eq!(want.faces.len(), 4);
        let cr = text.replace('\n', "\r");
        // Every third line end `\r\n`, every other one of the rest `\r`.
        let mixed: String = text
            .split_inclusive('\n')
            .enumerate()
            .map(|(i, l)| match i % 3 {
                0 => l.replace('\n', "\r\n"),
                1 => l.replace('\n', "\r"),
                _ => l.to_owned(),
            })
            .collect();
        for bytes in [cr, mixed] {
            for hint in [Some(format), None] {
                let (got, report) = load_bytes(bytes.as_bytes(), hint)
                    .unwrap_or_else(|e| panic!("{format:?} {bytes:?}: {e}"));
                assert_eq!(report.format, format);
                assert_eq!(got.positions, want.positions);
                assert_eq!(ids(&got), ids(&want));
            }
        }
    }
    // Line 6 of the `\r` file holds the bad index.
    let bad = TETRA_OBJ.replace("f 1 2 4", "f 1 2 x").replace('\n', "\r");
    match load_bytes(bad.as_bytes(), Some(MeshFormat::Obj)).unwrap_err() {
        LoadError::InvalidIndex { line, .. } => assert_eq!(line, Some(6)),
        e => panic!("{e:?}"),
    }
}

// ---------------------------------------------------------------- detection

#[test]
fn unknown_content_is_an_unknown_format() {
    let err = load_bytes(b"\x00\x01\x02 hello", None).unwrap_err();
    assert!(
        matches!(err, LoadError::UnknownFormat { extension: None }),
        "{err:?}"
    );
    let path = write_temp("mesh.xyz", b"\x00\x01\x02 hello");
    let err = load(&path).unwrap_err();
    assert!(
        matches!(err, LoadError::UnknownFormat { extension: Some(ref e) } if e == "xyz"),
        "{err:?}"
    );
}

#[test]
fn missing_file_is_an_io_error_with_its_path() {
    let err = load(std::path::Path::new("/nonexistent/dir/m.stl")).unwrap_err();
    assert!(
        matches!(err, LoadError::Io { ref path, .. } if path.ends_with("m.stl")),
        "{err:?}"
    );
}
