//! Input: level sets of built-in datasets, hand-written CLI files, and
//! damaged ones. Output: checks that the Common Layer Interface writer and
//! reader round-trip (ASCII exactly, binary as `f32`), read a hand-written
//! file as written, pick the loops `--side` asks for, and turn every defect
//! into a typed error without panicking.

use std::process::Command;
use wmslice::exact::parse_rational;
use wmslice::output::cli_layers::{
    date_ddmmyy, from_level_sets, read, write_ascii, write_binary, CliError, CliFile, CliOptions,
    Direction, Encoding, LoopChoice, Problem,
};
use wmslice::output::svg::Bounds;
use wmslice::{datasets, LevelSet, Slicer};

fn levels(name: &str, zs: &[&str]) -> (Bounds, Vec<LevelSet>) {
    let mesh = datasets::by_name(name).unwrap().build();
    let slicer = Slicer::new(&mesh).unwrap();
    let sets = zs
        .iter()
        .map(|z| slicer.slice_at(&parse_rational(z).unwrap()).unwrap())
        .collect();
    (Bounds::of_mesh(&mesh, None), sets)
}

fn opts(encoding: Encoding, side: LoopChoice, with_ridges: bool) -> CliOptions {
    CliOptions {
        encoding,
        side,
        with_ridges,
        label: "part".into(),
        date: "010125".into(),
    }
}

fn sample(encoding: Encoding) -> CliFile {
    let (b, sets) = levels("double_torus", &["4", "2", "1/2", "1", "3"]);
    from_level_sets(&sets, &b, &opts(encoding, LoopChoice::Below, true))
}

#[test]
fn ascii_round_trip_is_exact() {
    let file = sample(Encoding::Ascii);
    let text = write_ascii(&file);
    let back = read(text.as_bytes()).expect("reads back");
    assert_eq!(back, file);
    assert!(text.starts_with("$$HEADERSTART\n$$ASCII\n$$UNITS/1\n$$VERSION/200\n$$LABEL/1,part\n$$DATE/010125\n$$DIMENSION/-3,-2,0,3,2,4\n$$LAYERS/5\n$$HEADEREND\n$$GEOMETRYSTART\n$$LAYER/0.5\n"), "{}", &text[..200]);
    assert!(text.ends_with("$$GEOMETRYEND\n"));
}

#[test]
fn binary_round_trip_keeps_layers_dirs_and_f32_points() {
    let file = sample(Encoding::Binary);
    let bytes = write_binary(&file);
    let back = read(&bytes).expect("reads back");
    assert_eq!(back.header, file.header);
    assert_eq!(back.layers.len(), file.layers.len());
    for (a, b) in file.layers.iter().zip(&back.layers) {
        assert_eq!(b.z, f64::from(a.z as f32));
        assert_eq!(a.polylines.len(), b.polylines.len());
        for (p, q) in a.polylines.iter().zip(&b.polylines) {
            assert_eq!((p.id, p.dir), (q.id, q.dir));
            let f32s: Vec<[f64; 2]> = p
                .points
                .iter()
                .map(|[x, y]| [f64::from(*x as f32), f64::from(*y as f32)])
                .collect();
            assert_eq!(q.points, f32s);
        }
    }
    // The binary data starts right after $$HEADEREND with code 127.
    let end = bytes.windows(11).position(|w| w == b"$$HEADEREND").unwrap() + 11;
    assert_eq!(&bytes[end..end + 2], &127u16.to_le_bytes());
}

#[test]
fn layers_follow_the_exact_levels_ascending_and_loops_close_on_their_first_point() {
    let (b, sets) = levels("double_torus", &["2", "1/2", "2"]);
    let file = from_level_sets(
        &sets,
        &b,
        &opts(Encoding::Ascii, LoopChoice::Contour, false),
    );
    let zs: Vec<f64> = file.layers.iter().map(|l| l.z).collect();
    assert_eq!(zs, [0.5, 2.0], "sorted, equal levels once");
    // At the monkey saddle: one outer (dir 1) and three holes (dir 0).
    let top = &file.layers[1];
    let dirs: Vec<Direction> = top.polylines.iter().map(|p| p.dir).collect();
    assert_eq!(
        dirs.iter()
            .filter(|d| **d == Direction::CounterClockwise)
            .count(),
        1
    );
    assert_eq!(
        dirs.iter().filter(|d| **d == Direction::Clockwise).count(),
        3
    );
    let so = &sets[0].contours;
    for (p, l) in top.polylines.iter().zip(so.iter()) {
        assert_eq!(p.points.len(), l.points.len() + 1);
        assert_eq!(p.points.first(), p.points.last());
        let exact: Vec<[f64; 2]> = l.points.iter().map(|q| q.to_f64()).collect();
        assert_eq!(&p.points[..l.points.len()], &exact[..]);
    }
}

#[test]
fn side_picks_below_above_or_contour_at_the_cylinder_top() {
    let (b, sets) = levels("cylinder", &["2"]);
    let count = |side| {
        from_level_sets(&sets, &b, &opts(Encoding::Ascii, side, false)).layers[0]
            .polylines
            .len()
    };
    assert_eq!(count(LoopChoice::Below), 1, "L-: the rim is printed");
    assert_eq!(count(LoopChoice::Above), 0);
    assert_eq!(count(LoopChoice::Contour), 0);
    let rim = &from_level_sets(&sets, &b, &opts(Encoding::Ascii, LoopChoice::Below, false)).layers
        [0]
    .polylines[0];
    assert_eq!(rim.dir, Direction::CounterClockwise);
    assert_eq!(rim.points.len(), 9, "octagon, first point repeated");
}

#[test]
fn ridges_are_open_lines_on_request() {
    let (b, sets) = levels("lying_torus", &["2"]);
    let plain = from_level_sets(&sets, &b, &opts(Encoding::Ascii, LoopChoice::Below, false));
    assert!(plain.layers[0].polylines.is_empty());
    let with = from_level_sets(&sets, &b, &opts(Encoding::Ascii, LoopChoice::Below, true));
    let p = &with.layers[0].polylines;
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].dir, Direction::Open);
    assert_eq!(
        p[0].points.first(),
        p[0].points.last(),
        "a closed ridge returns"
    );
}

const HAND_WRITTEN: &str = "// a part written by hand //\r
$$HEADERSTART\r
$$ASCII\r
$$UNITS/00000000.005000\r
$$VERSION/200\r
$$LABEL/1,bracket, left\r
$$DATE/240125\r
$$DIMENSION/0.0,0.0,0.0,10.0,10.0,0.2\r
$$LAYERS/2\r
$$USERDATA/acme,3,xyz\r
$$HEADEREND\r
$$GEOMETRYSTART // geometry follows\r
$$LAYER/0.1\r
$$POLYLINE/1,1,5,0,0,10,0,10,10,0,10,0,0\r
$$POLYLINE/1,0,5,2,2,2,8,8,8,\r
   8,2,2,2 // continued on the next line\r
$$LAYER/0.2 $$POLYLINE/1,2,2,0,5,10,5\r
$$HATCHES/1,2,0,1,10,1,0,2,10,2\r
$$GEOMETRYEND\r
";

#[test]
fn hand_written_ascii_file_reads_as_written() {
    let f = read(HAND_WRITTEN.as_bytes()).expect("valid");
    let h = &f.header;
    assert_eq!(h.encoding, Encoding::Ascii);
    assert_eq!(h.units, 0.005);
    assert_eq!(h.version, 200);
    assert_eq!(h.labels, [(1, "bracket, left".to_string())]);
    assert_eq!(h.date.as_deref(), Some("240125"));
    assert_eq!(h.dimension, Some([0.0, 0.0, 0.0, 10.0, 10.0, 0.2]));
    assert_eq!(h.layers, Some(2));
    assert_eq!(h.other, ["USERDATA/acme,3,xyz"]);
    assert_eq!(f.layers.len(), 2);
    let l0 = &f.layers[0];
    assert_eq!(l0.z, 0.1);
    assert_eq!(l0.polylines.len(), 2);
    assert_eq!(l0.polylines[0].dir, Direction::CounterClockwise);
    assert_eq!(
        l0.polylines[0].points,
        [
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [0.0, 10.0],
            [0.0, 0.0]
        ]
    );
    assert_eq!(l0.polylines[1].dir, Direction::Clockwise);
    assert_eq!(l0.polylines[1].points[3], [8.0, 2.0]);
    let l1 = &f.layers[1];
    assert_eq!(l1.z, 0.2);
    assert_eq!(l1.polylines[0].dir, Direction::Open);
    assert_eq!(l1.polylines[0].points, [[0.0, 5.0], [10.0, 5.0]]);
    assert_eq!(
        l1.hatches[0].lines,
        [[[0.0, 1.0], [10.0, 1.0]], [[0.0, 2.0], [10.0, 2.0]]]
    );
    // Written again and read back: the same file.
    assert_eq!(read(write_ascii(&f).as_bytes()).unwrap(), f);
    assert_eq!(
        read(&write_binary(&f)).unwrap().layers[1].hatches,
        l1.hatches
    );
}

/// A binary file assembled by hand: layer short and long, polyline short
/// and long, hatches short.
#[test]
fn hand_assembled_binary_file_reads_every_command() {
    let mut b =
        b"$$HEADERSTART\n$$BINARY\n$$UNITS/0.01\n$$VERSION/200\n$$LAYERS/2\n$$HEADEREND\r\n"
            .to_vec();
    let u16s =
        |b: &mut Vec<u8>, v: &[u16]| v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    u16s(&mut b, &[128, 10]); // layer short z = 10
    u16s(&mut b, &[129, 7, 1, 3, 0, 0, 100, 0, 0, 0]); // polyline short
    u16s(&mut b, &[131, 7, 1, 1, 2, 3, 4]); // hatches short
    u16s(&mut b, &[127]);
    b.extend_from_slice(&20.5f32.to_le_bytes());
    u16s(&mut b, &[130]);
    for x in [9i32, 2, 2] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    for x in [0.25f32, -1.5, 3.0, 4.0] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    let f = read(&b).expect("valid");
    assert_eq!(f.header.units, 0.01);
    assert_eq!(f.layers.len(), 2);
    assert_eq!(f.layers[0].z, 10.0);
    assert_eq!(f.layers[0].polylines[0].id, 7);
    assert_eq!(
        f.layers[0].polylines[0].points,
        [[0.0, 0.0], [100.0, 0.0], [0.0, 0.0]]
    );
    assert_eq!(f.layers[0].hatches[0].lines, [[[1.0, 2.0], [3.0, 4.0]]]);
    assert_eq!(f.layers[1].z, 20.5);
    assert_eq!(f.layers[1].polylines[0].dir, Direction::Open);
    assert_eq!(f.layers[1].polylines[0].points, [[0.25, -1.5], [3.0, 4.0]]);
}

fn binary_header() -> Vec<u8> {
    b"$$HEADERSTART\n$$BINARY\n$$UNITS/1\n$$VERSION/200\n$$HEADEREND".to_vec()
}

#[test]
fn hostile_counts_are_rejected_before_allocating() {
    let mut b = binary_header();
    b.extend_from_slice(&127u16.to_le_bytes());
    b.extend_from_slice(&1f32.to_le_bytes());
    b.extend_from_slice(&130u16.to_le_bytes());
    for x in [1i32, 1, i32::MAX] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    match read(&b) {
        Err(CliError::Truncated {
            needed, available, ..
        }) => {
            assert_eq!(needed, 8 * i32::MAX as u64);
            assert_eq!(available, 0);
        }
        other => panic!("{other:?}"),
    }
    let mut neg = binary_header();
    neg.extend_from_slice(&127u16.to_le_bytes());
    neg.extend_from_slice(&1f32.to_le_bytes());
    neg.extend_from_slice(&132u16.to_le_bytes());
    for x in [1i32, -5] {
        neg.extend_from_slice(&x.to_le_bytes());
    }
    assert!(matches!(
        read(&neg),
        Err(CliError::BadBinary {
            problem: Problem::NegativeCount(-5),
            ..
        })
    ));
}

/// What an error case expects.
type Expect = fn(&CliError) -> bool;

#[test]
fn every_defect_is_a_typed_error() {
    let ascii = |geometry: &str| {
        format!("$$HEADERSTART\n$$ASCII\n$$UNITS/1\n$$HEADEREND\n$$GEOMETRYSTART\n{geometry}$$GEOMETRYEND\n")
    };
    let cases: Vec<(Vec<u8>, Expect)> = vec![
        (b"solid x".to_vec(), |e| *e == CliError::NotCli),
        (b"$$HEADERSTART\n$$ASCII\n".to_vec(), |e| *e == CliError::MissingHeaderEnd),
        (b"// $$HEADEREND //\n$$HEADERSTART\n$$ASCII\n".to_vec(), |e| *e == CliError::MissingHeaderEnd),
        (b"$$HEADERSTART\n$$UNITS/1\n$$HEADEREND".to_vec(), |e| *e == CliError::MissingEncoding),
        (b"$$HEADERSTART\n$$ASCII\n$$BINARY\n$$HEADEREND".to_vec(), |e| *e == CliError::ConflictingEncoding),
        (b"$$HEADERSTART\n$$BINARY\n$$ALIGN\n$$HEADEREND".to_vec(), |e| *e == CliError::AlignUnsupported),
        (b"$$HEADERSTART\n$$ASCII\n$$UNITS/0\n$$HEADEREND".to_vec(), |e| matches!(e, CliError::BadParameters { problem: Problem::NonPositiveUnits, line: 3, .. })),
        (b"$$HEADERSTART\n$$ASCII\n$$UNITS/1\n$$LAYERS/3\n$$HEADEREND\n$$GEOMETRYSTART\n$$GEOMETRYEND\n".to_vec(), |e| *e == CliError::LayerCount { declared: 3, found: 0 }),
        (ascii("$$LAYER/1\n$$POLYLINE/1,3,1,0,0\n").into_bytes(), |e| matches!(e, CliError::BadParameters { problem: Problem::Direction(3), line: 7, .. })),
        (ascii("$$LAYER/1\n$$POLYLINE/1,1,3,0,0,1,1\n").into_bytes(), |e| matches!(e, CliError::BadParameters { problem: Problem::ValueCount { expected: 9, found: 7 }, .. })),
        (ascii("$$LAYER/1\n$$POLYLINE/1,1,1,0,nan\n").into_bytes(), |e| matches!(e, CliError::BadParameters { problem: Problem::NotFinite, .. })),
        (ascii("$$LAYER/1\n$$POLYLINE/1,1,1,0,zero\n").into_bytes(), |e| matches!(e, CliError::BadParameters { problem: Problem::NotANumber, .. })),
        (ascii("$$POLYLINE/1,1,1,0,0\n").into_bytes(), |e| matches!(e, CliError::OutsideLayer { line: 6, .. })),
        (ascii("$$LAYER/2\n$$LAYER/1\n").into_bytes(), |e| matches!(e, CliError::NotAscending { index: 1, .. })),
        (ascii("$$LAYER/1\n$$CIRCLE/1\n").into_bytes(), |e| matches!(e, CliError::UnknownCommand { line: 7, .. })),
        (b"$$HEADERSTART\n$$ASCII\n$$HEADEREND\n$$LAYER/1\n".to_vec(), |e| matches!(e, CliError::MissingGeometryStart { line: 4 })),
        (b"$$HEADERSTART\n$$ASCII\n$$HEADEREND\n$$GEOMETRYSTART\n$$LAYER/1\n".to_vec(), |e| *e == CliError::MissingGeometryEnd),
        (format!("{}$$LAYER/2\n", ascii("")).into_bytes(), |e| matches!(e, CliError::AfterGeometryEnd { .. })),
        ({ let mut b = binary_header(); b.extend_from_slice(&[200, 0]); b }, |e| matches!(e, CliError::UnknownCode { code: 200, .. })),
        ({ let mut b = binary_header(); b.extend_from_slice(&[127, 0, 0, 0, 192]); b }, |e| matches!(e, CliError::Truncated { what: "layer long", .. })),
        ({ let mut b = binary_header(); b.extend_from_slice(&[127, 0]); b.extend_from_slice(&f32::NAN.to_le_bytes()); b }, |e| matches!(e, CliError::BadBinary { problem: Problem::NotFinite, .. })),
        ({ let mut b = binary_header(); b.extend_from_slice(&[129, 0, 1, 0, 1, 0, 0, 0]); b }, |e| matches!(e, CliError::OutsideLayerAt { .. })),
    ];
    for (i, (bytes, ok)) in cases.iter().enumerate() {
        match read(bytes) {
            Err(e) => assert!(ok(&e), "case {i}: unexpected error {e:?}"),
            Ok(f) => panic!("case {i}: accepted {f:?}"),
        }
    }
}

#[test]
fn truncated_and_mutated_files_never_panic() {
    let files = [
        write_binary(&sample(Encoding::Binary)),
        write_ascii(&sample(Encoding::Ascii)).into_bytes(),
    ];
    for bytes in &files {
        for n in 0..bytes.len() {
            let _ = read(&bytes[..n]);
        }
        // Deterministic byte flips (a small LCG).
        let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..3000 {
            let mut m = bytes.clone();
            for _ in 0..3 {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let i = (s >> 33) as usize % m.len();
                m[i] = (s >> 13) as u8;
            }
            let _ = read(&m);
        }
    }
}

#[test]
fn dates_are_ddmmyy_in_utc() {
    assert_eq!(date_ddmmyy(0), "010170");
    assert_eq!(date_ddmmyy(1_709_164_800), "290224");
    assert_eq!(date_ddmmyy(951_782_400 + 86_399), "290200");
    assert_eq!(date_ddmmyy(-1), "311269");
}

fn run(args: &[&str]) -> (i32, Vec<u8>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .env("SOURCE_DATE_EPOCH", "1709164800")
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        out.stdout,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn slice_writes_cli_files_with_the_chosen_side() {
    let dir = std::env::temp_dir().join(format!("wmslice-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let f = dir.join("deep").join("cyl.cli");
    let (code, _, err) = run(&[
        "slice",
        "cylinder",
        "--at",
        "2",
        "--at",
        "1",
        "--format",
        "cli-binary",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let file = read(&std::fs::read(&f).unwrap()).unwrap();
    assert_eq!(file.header.encoding, Encoding::Binary);
    assert_eq!(file.header.date.as_deref(), Some("290224"));
    assert_eq!(file.header.labels, [(1, "cylinder".to_string())]);
    assert_eq!(
        file.header.dimension,
        Some([-2.0, -2.0, 0.0, 2.0, 2.0, 2.0])
    );
    let zs: Vec<f64> = file.layers.iter().map(|l| l.z).collect();
    assert_eq!(zs, [1.0, 2.0]);
    assert_eq!(file.layers[1].polylines.len(), 1, "below: the rim");
    let (code, out, _) = run(&[
        "slice", "cylinder", "--at", "2", "--format", "cli", "--side", "above",
    ]);
    assert_eq!(code, 0);
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("$$LAYER/2\n$$GEOMETRYEND"), "{text}");
    let (code, out, _) = run(&[
        "slice",
        "lying_torus",
        "--at",
        "2",
        "--format",
        "cli",
        "--side",
        "contour",
        "--with-ridges",
    ]);
    assert_eq!(code, 0);
    let file = read(&out).unwrap();
    assert_eq!(file.layers[0].polylines.len(), 1);
    assert_eq!(file.layers[0].polylines[0].dir, Direction::Open);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Binary CLI holds `f32`: a part at `1e-300` (lost below the `f32`
/// subnormals) or a layer at `1e300` (an infinity) is refused by name,
/// before any file is made; ASCII CLI writes the same part exactly.
#[test]
fn binary_cli_refuses_what_f32_cannot_hold() {
    let dir = std::env::temp_dir().join(format!("wmslice-cli-f32-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A tetrahedron of side 1e-300 (decimal OBJ).
    let tiny = dir.join("tiny.obj");
    std::fs::write(
        &tiny,
        "v 0 0 0\nv 1e-300 0 0\nv 0 1e-300 0\nv 0 0 1e-300\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let out = dir.join("tiny.cli");
    let at = ["--at", "5e-301"];
    let (code, _, err) = run(&[
        &[
            "slice",
            tiny.to_str().unwrap(),
            "--format",
            "cli-binary",
            "-o",
        ],
        &[out.to_str().unwrap()][..],
        &at,
    ]
    .concat());
    assert_eq!(code, 5, "{err}");
    assert!(err.contains("binary CLI holds f32 values"), "{err}");
    assert!(!out.exists(), "no partial file");
    let (code, text, err) = run(&[
        &["slice", tiny.to_str().unwrap(), "--format", "cli"][..],
        &at,
    ]
    .concat());
    assert_eq!(code, 0, "{err}");
    let file = read(&text).unwrap();
    // The triangle x + y <= 5e-301 at z = 5e-301, exactly as doubles.
    let layer = &file.layers[0];
    assert_eq!(layer.z, 5e-301);
    let mut xs: Vec<f64> = layer.polylines[0]
        .points
        .iter()
        .flatten()
        .copied()
        .collect();
    xs.sort_by(f64::total_cmp);
    assert_eq!(xs.last(), Some(&5e-301));
    let (code, _, err) = run(&[
        "slice",
        "cylinder",
        "--at",
        "1e300",
        "--format",
        "cli-binary",
    ]);
    assert_eq!(code, 5, "{err}");
    assert!(err.contains("1e300 lies beyond them"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Binary CLI also refuses what `f32` would write as a different part: a
/// part far from the origin for its size (its points `f32`'s steps
/// apart), and layers closer than `f32`'s step at their height (written
/// at one height). A block 1 wide at 14678, where `f32` steps by
/// `2^-10`, is written, its corners exactly.
#[test]
fn binary_cli_refuses_a_part_or_layers_f32_cannot_tell_apart() {
    let dir = std::env::temp_dir().join(format!("wmslice-cli-coarse-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let block = |name: &str, x0: u64| {
        let path = dir.join(name);
        let (a, b) = (x0, x0 + 1);
        let v = |x: u64, y: u32, z: u32| format!("v {x} {y} {z}\n");
        let text = [
            v(a, 0, 0),
            v(b, 0, 0),
            v(b, 1, 0),
            v(a, 1, 0),
            v(a, 0, 3),
            v(b, 0, 3),
            v(b, 1, 3),
            v(a, 1, 3),
            "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n".into(),
        ]
        .concat();
        std::fs::write(&path, text).unwrap();
        path
    };
    let slice = |mesh: &std::path::Path, extra: &[&str], out: &std::path::Path| {
        run(&[
            &[
                "slice",
                mesh.to_str().unwrap(),
                "--quiet",
                "--format",
                "cli-binary",
                "-o",
            ],
            &[out.to_str().unwrap()][..],
            extra,
        ]
        .concat())
    };

    let near = block("near.obj", 14678);
    let out = dir.join("near.cli");
    let (code, _, err) = slice(&near, &["--at", "3/2"], &out);
    assert_eq!(code, 0, "{err}");
    let file = read(&std::fs::read(&out).unwrap()).unwrap();
    let mut points: Vec<[f64; 2]> = file.layers[0].polylines[0].points.clone();
    points.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    points.dedup();
    // The four corners, and the midpoints of the four sides, where each
    // side's quad, split along a diagonal, crosses z = 3/2.
    assert_eq!(
        points,
        [
            [14678.0, 0.0],
            [14678.0, 0.5],
            [14678.0, 1.0],
            [14678.5, 0.0],
            [14678.5, 1.0],
            [14679.0, 0.0],
            [14679.0, 0.5],
            [14679.0, 1.0]
        ]
    );

    // At 2^40, f32 steps by 2^17: the block would be one point.
    let far = block("far.obj", 1 << 40);
    let out = dir.join("far.cli");
    let (code, _, err) = slice(&far, &["--at", "3/2"], &out);
    assert_eq!(code, 5, "{err}");
    assert!(
        err.contains("1.31072e5 apart at 1.099511627777e12"),
        "{err}"
    );
    assert!(err.contains("only 1e0 wide"), "{err}");
    assert!(!out.exists(), "no file");

    // Layers 1e-8 apart near z = 1, where f32 steps by 2^-23 (1.2e-7).
    let out = dir.join("thin.cli");
    let thin = [
        "--layer-height",
        "1e-8",
        "--first",
        "1",
        "--last",
        "1.000001",
    ];
    let (code, _, err) = slice(&near, &thin, &out);
    assert_eq!(code, 5, "{err}");
    assert!(
        err.contains("the layers at z = 1e0 and z = 1.00000001e0 would both be written at 1e0"),
        "{err}"
    );
    assert!(!out.exists(), "no file");
    // ASCII CLI writes both.
    let (code, _, err) = run(&[
        &[
            "slice",
            near.to_str().unwrap(),
            "--quiet",
            "--format",
            "cli",
            "-o",
        ][..],
        &[out.to_str().unwrap()],
        &thin,
    ]
    .concat());
    assert_eq!(code, 0, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
