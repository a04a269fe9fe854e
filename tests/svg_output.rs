//! Input: built-in datasets at their degenerate levels. Output: checks that
//! every kind of the level set appears in the SVG with its class (the SVG
//! parsed back with quick-xml), and that `slice --format svg|html` writes
//! the files where asked, atomically.

mod common;
use common::wmslice as run;

use quick_xml::events::{BytesStart, Event};
use quick_xml::XmlVersion;
use std::collections::HashMap;
use std::path::Path;
use wmslice::exact::{parse_rational, Rat};
use wmslice::output::html::{viewer, Counts, ViewerLayer, ViewerOptions};
use wmslice::output::svg::{is_level_file_name, level_file_name, level_svg, Scene, SvgOptions};
use wmslice::{datasets, LevelSet, Slicer};

/// One parsed element.
#[derive(Debug)]
struct El {
    name: String,
    classes: Vec<String>,
    attrs: HashMap<String, String>,
    text: String,
    parent: Option<usize>,
}

fn element(e: &BytesStart, parent: Option<usize>) -> El {
    let mut attrs = HashMap::new();
    for a in e.attributes() {
        let a = a.expect("attribute");
        let key = a.key.as_ref().to_string();
        let value = a
            .normalized_value(XmlVersion::Implicit1_0)
            .expect("attribute value")
            .into_owned();
        attrs.insert(key, value);
    }
    let classes = attrs
        .get("class")
        .map(|c| c.split_whitespace().map(String::from).collect())
        .unwrap_or_default();
    El {
        name: e.name().as_ref().to_string(),
        classes,
        attrs,
        text: String::new(),
        parent,
    }
}

/// Parses an SVG document into a flat list of elements (well-formedness
/// checked by quick-xml: every end tag must match).
fn parse(svg: &str) -> Vec<El> {
    let mut reader = quick_xml::Reader::from_str(svg);
    reader.config_mut().check_end_names = true;
    let mut els: Vec<El> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    loop {
        match reader.read_event().expect("well-formed SVG") {
            Event::Start(e) => {
                els.push(element(&e, stack.last().copied()));
                stack.push(els.len() - 1);
            }
            Event::Empty(e) => els.push(element(&e, stack.last().copied())),
            Event::End(_) => {
                stack.pop().expect("balanced tags");
            }
            Event::Text(t) => {
                if let Some(&i) = stack.last() {
                    els[i].text.push_str(&t.xml10_content());
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert!(stack.is_empty(), "unclosed elements");
    els
}

fn has(e: &El, classes: &[&str]) -> bool {
    classes.iter().all(|c| e.classes.iter().any(|x| x == c))
}

fn with<'a>(els: &'a [El], classes: &[&str]) -> Vec<&'a El> {
    els.iter().filter(|e| has(e, classes)).collect()
}

fn count(els: &[El], classes: &[&str]) -> usize {
    with(els, classes).len()
}

fn level(name: &str, z: &str) -> (wmslice::Mesh, LevelSet) {
    let mesh = datasets::by_name(name).expect("dataset").build();
    let ls = Slicer::new(&mesh)
        .expect("valid")
        .slice_at(&parse_rational(z).expect("level"))
        .expect("slice");
    (mesh, ls)
}

fn svg_of(name: &str, z: &str, arrows: bool) -> (String, Vec<El>) {
    let (mesh, ls) = level(name, z);
    let scene = Scene::new(&mesh, None);
    let text = level_svg(&ls, &scene, name, &SvgOptions { arrows });
    let els = parse(&text);
    (text, els)
}

/// Number of subpaths (`M` commands) in a path's `d`.
fn subpaths(e: &El) -> usize {
    e.attrs["d"].matches('M').count()
}

/// Every number of a path's data, in order.
fn path_numbers(d: &str) -> Vec<f64> {
    d.split(|c: char| c.is_ascii_alphabetic() || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("number"))
        .collect()
}

/// Every (x, y) of a path's `d`.
fn coords(e: &El) -> Vec<[f64; 2]> {
    path_numbers(&e.attrs["d"])
        .chunks_exact(2)
        .map(|p| [p[0], p[1]])
        .collect()
}

#[test]
fn cylinder_top_is_one_up_region_with_its_outline_and_no_contour() {
    let (_, els) = svg_of("cylinder", "2", false);
    assert_eq!(count(&els, &["f", "up"]), 1);
    assert_eq!(count(&els, &["f", "down"]), 0);
    assert_eq!(count(&els, &["df"]), 1);
    assert_eq!(count(&els, &["so"]), 0, "no S_O path at the top cap");
    assert_eq!(count(&els, &["lminus"]), 1, "L- is the rim");
    assert_eq!(count(&els, &["lplus"]), 0, "nothing above the top");
    let f = with(&els, &["f", "up"])[0];
    assert_eq!(f.attrs["fill-rule"], "evenodd");
    assert_eq!(f.attrs["data-area"], "14");
}

#[test]
fn cylinder_bottom_is_one_down_region() {
    let (_, els) = svg_of("cylinder", "0", false);
    assert_eq!(count(&els, &["f", "down"]), 1);
    assert_eq!(count(&els, &["f", "up"]), 0);
    assert_eq!(count(&els, &["so"]), 0);
    assert_eq!(count(&els, &["lplus"]), 1);
    assert_eq!(count(&els, &["lminus"]), 0);
}

#[test]
fn double_torus_monkey_saddle_is_marked_m3_and_holes_are_cut_out() {
    let (_, els) = svg_of("double_torus", "2", false);
    let saddles = with(&els, &["saddle"]);
    assert_eq!(saddles.len(), 1);
    assert_eq!(saddles[0].attrs["data-m"], "3");
    let idx = els
        .iter()
        .position(|e| std::ptr::eq(e, saddles[0]))
        .expect("saddle index");
    let label: Vec<&El> = els
        .iter()
        .filter(|e| e.parent == Some(idx) && e.name == "text")
        .collect();
    assert_eq!(label.len(), 1);
    assert_eq!(label[0].text, "m=3");
    // One filled outer path holding the outer loop and its three holes.
    let outer = with(&els, &["so", "outer"]);
    assert_eq!(outer.len(), 1);
    assert_eq!(outer[0].attrs["fill-rule"], "evenodd");
    assert_eq!(subpaths(outer[0]), 4);
    assert_eq!(count(&els, &["so", "hole"]), 3);
    assert_eq!(count(&els, &["f"]), 0);
    assert_eq!(count(&els, &["sno"]), 0);
}

#[test]
fn saddle8_is_marked_m4_and_its_maxima_are_max_dots() {
    let (_, els) = svg_of("saddle8", "2", false);
    let s = with(&els, &["saddle"]);
    assert_eq!(s.len(), 1);
    assert_eq!(s[0].attrs["data-m"], "4");
    let (_, top) = svg_of("saddle8", "3", false);
    assert_eq!(count(&top, &["p", "max"]), 4);
    assert_eq!(count(&top, &["p", "min"]), 0);
}

#[test]
fn lying_torus_top_ring_is_one_closed_ridge() {
    let (_, els) = svg_of("lying_torus", "2", false);
    let r = with(&els, &["sno", "ridge"]);
    assert_eq!(r.len(), 1);
    assert_eq!(r[0].attrs["data-closed"], "true");
    assert!(r[0].attrs["d"].ends_with('Z'));
    assert_eq!(count(&els, &["sno", "valley"]), 0);
    assert_eq!(count(&els, &["so"]), 0);
}

#[test]
fn lying_torus_bottom_ring_is_one_closed_valley() {
    let (_, els) = svg_of("lying_torus", "-1", false);
    assert_eq!(count(&els, &["sno", "valley"]), 1);
    assert_eq!(count(&els, &["sno", "ridge"]), 0);
}

#[test]
fn grid_pits_are_nine_min_dots_and_its_top_is_twenty_open_ridges() {
    let (_, els) = svg_of("grid", "1", false);
    assert_eq!(count(&els, &["p", "min"]), 9);
    assert_eq!(count(&els, &["p", "max"]), 0);
    assert_eq!(count(&els, &["so", "outer"]), 1);
    let (_, top) = svg_of("grid", "2", false);
    let r = with(&top, &["sno", "ridge"]);
    assert_eq!(r.len(), 20);
    assert!(r.iter().all(|e| e.attrs["data-closed"] == "false"));
}

#[test]
fn peg_cube_shoulder_has_up_and_down_regions_beside_the_contour() {
    let (_, els) = svg_of("peg_cube", "3", false);
    assert_eq!(count(&els, &["f", "up"]), 1);
    assert_eq!(count(&els, &["f", "down"]), 1);
    assert_eq!(count(&els, &["df"]), 2);
    assert_eq!(count(&els, &["so", "outer"]), 1);
}

#[test]
fn platform_grid_below_and_above_differ() {
    let (_, els) = svg_of("platform_grid", "1", false);
    assert_eq!(count(&els, &["lminus"]), 1);
    assert_eq!(count(&els, &["lplus"]), 4);
    assert_eq!(count(&els, &["so", "outer"]), 4);
    let f = with(&els, &["f", "up"]);
    assert_eq!(f.len(), 1);
    assert_eq!(subpaths(f[0]), 5, "the region with its four holes");
}

#[test]
fn title_holds_the_exact_level_and_the_legend_uses_no_kind_class() {
    let (text, els) = svg_of("peg_cube", "7/2", false);
    let title = els.iter().find(|e| e.name == "title").expect("title");
    assert!(title.text.contains("z = 7/2"), "{}", title.text);
    assert!(text.contains("data-level=\"7/2\""));
    // The legend exists and none of its elements carries a kind's class.
    let legend = els
        .iter()
        .position(|e| has(e, &["legend"]))
        .expect("legend");
    assert!(els
        .iter()
        .filter(|e| e.parent == Some(legend))
        .all(|e| e.classes.is_empty()));
    assert!(els.iter().any(|e| e.text == "S_NO valley"));
}

#[test]
fn view_box_frames_the_mesh_with_y_up() {
    let (_, els) = svg_of("unit_cube", "1/2", false);
    let inner = els
        .iter()
        .filter(|e| e.name == "svg")
        .nth(1)
        .expect("nested drawing");
    let vb: Vec<f64> = inner.attrs["viewBox"]
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    // x in [0, 1] and y in [0, 1], padded by 6 %, y negated.
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(vb[0], -0.06) && close(vb[1], -1.06), "{vb:?}");
    assert!(close(vb[2], 1.12) && close(vb[3], 1.12), "{vb:?}");
    let outer = with(&els, &["so", "outer"])[0];
    for [x, y] in coords(outer) {
        assert!((0.0..=1.0).contains(&x) && (-1.0..=0.0).contains(&y));
    }
    // Counter-clockwise in model coordinates is clockwise on screen: the
    // shoelace sum of the screen points is negative.
    let p = coords(outer);
    let twice: f64 = (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    assert!(twice < 0.0);
}

#[test]
fn arrows_only_on_request_and_pointing_along_the_loop() {
    let (_, plain) = svg_of("unit_cube", "1/2", false);
    assert_eq!(count(&plain, &["arrow"]), 0);
    let (_, els) = svg_of("unit_cube", "1/2", true);
    let arrows = with(&els, &["arrow", "on-so"]);
    assert!(!arrows.is_empty());
    // The unit square's outer loop is counter-clockwise: on its bottom edge
    // (screen y = 0) an arrow points towards +x (its tip has the largest x).
    let bottom = arrows
        .iter()
        .map(|a| coords(a))
        .find(|c| {
            c.iter()
                .all(|p| p[1].abs() < 0.02 && p[0] > 0.1 && p[0] < 0.9)
        })
        .expect("an arrow on the bottom edge");
    assert!(bottom[0][0] > bottom[1][0] && bottom[0][0] > bottom[2][0]);
    let (_, df) = svg_of("cylinder", "2", true);
    assert!(count(&df, &["arrow", "on-df"]) > 0);
}

#[test]
fn snapped_mesh_is_drawn_in_true_units() {
    let mesh = datasets::by_name("double_torus").unwrap().build();
    let unit = parse_rational("1/8").unwrap();
    let snapped = wmslice::mesh::snap::snap(&mesh, &unit).expect("snap");
    let slicer = Slicer::with_unit(&snapped.mesh, snapped.unit.clone()).unwrap();
    let ls = slicer.slice_at(&parse_rational("2").unwrap()).unwrap();
    let scene = Scene::new(&snapped.mesh, Some(&snapped.unit));
    let a = parse(&level_svg(&ls, &scene, "x", &SvgOptions::default()));
    let (_, b) = svg_of("double_torus", "2", false);
    let d = |els: &[El]| {
        (
            els.iter().filter(|e| e.name == "svg").nth(1).unwrap().attrs["viewBox"].clone(),
            with(els, &["saddle"])[0].attrs.get("data-vertex").cloned(),
            els.iter()
                .find(|e| e.parent.is_some_and(|p| has(&els[p], &["saddle"])) && e.name == "path")
                .unwrap()
                .attrs["d"]
                .clone(),
        )
    };
    let (va, _, sa) = d(&a);
    let (vb, _, sb) = d(&b);
    assert_eq!(va, vb);
    assert_eq!(sa, sb, "the saddle mark sits at the same place");
}

#[test]
fn file_names_carry_index_and_exact_level() {
    assert_eq!(
        level_file_name(3, &parse_rational("0.6").unwrap()),
        "layer-0003_z=3_5.svg"
    );
    assert_eq!(
        level_file_name(0, &parse_rational("-1/3").unwrap()),
        "layer-0000_z=-1_3.svg"
    );
    // A level of a mesh at 1e-300: hundreds of digits, named by its
    // nearest double (a file name longer than 255 bytes cannot be written).
    let tiny = parse_rational("-7.25e-301").unwrap() / Rat::from_integer(3.into());
    let name = level_file_name(12, &tiny);
    assert_eq!(name, "layer-0012_z~-2.4166666666666666e-301.svg");
    // At the limit (64 characters) still exact.
    let long = parse_rational(&format!("{}/7", "9".repeat(62))).unwrap();
    assert_eq!(
        level_file_name(1, &long),
        format!("layer-0001_z={}_7.svg", "9".repeat(62))
    );
}

#[test]
fn viewer_is_self_contained_and_embeds_every_layer() {
    let (mesh, a) = level("cylinder", "1");
    let (_, b) = level("cylinder", "2");
    let scene = Scene::new(&mesh, None);
    let layers = [
        ViewerLayer {
            heading: "cylinder".into(),
            note: "<b>&".into(),
            level: &a,
            scene: &scene,
        },
        ViewerLayer {
            heading: "cylinder".into(),
            note: String::new(),
            level: &b,
            scene: &scene,
        },
    ];
    let page = viewer(
        &layers,
        &ViewerOptions {
            title: "t".into(),
            arrows: false,
            ..Default::default()
        },
    );
    for banned in ["<link", "src=", "@import", "url(", "https://", "http://w"] {
        let hits: Vec<_> = page.match_indices(banned).collect();
        let allowed = banned == "http://w"
            && page.matches("http://www.w3.org/2000/svg").count() == hits.len();
        assert!(hits.is_empty() || allowed, "{banned} in the page");
    }
    let start = page
        .find(r#"<script type="application/json" id="data">"#)
        .unwrap();
    let json_text = &page[start..];
    let json_text =
        &json_text[json_text.find('>').unwrap() + 1..json_text.find("</script>").unwrap()];
    assert!(!json_text.contains('<'), "every < is escaped in the data");
    let data: serde_json::Value = serde_json::from_str(json_text).unwrap();
    let l = data["layers"].as_array().unwrap();
    assert_eq!(l.len(), 2);
    assert_eq!(l[1]["z"], "2");
    assert_eq!(l[0]["note"], "<b>&");
    assert_eq!(l[1]["counts"]["f_up"], 1);
    assert_eq!(l[1]["counts"]["so_outer"], 0);
    assert_eq!(l[1]["counts"]["lminus_area"], "14");
    assert!(l[1]["svg"].as_str().unwrap().contains("class=\"f up\""));
    let c = Counts::of(&b);
    assert_eq!((c.f_up, c.df, c.lminus_outer, c.lplus_outer), (1, 1, 1, 0));
}

fn tmp(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("wmslice-svg-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn slice_writes_one_svg_per_level_sorted_into_a_new_directory() {
    let dir = tmp("dir").join("a").join("b");
    let d = dir.to_str().unwrap();
    let (code, _, err) = run(&[
        "slice",
        "unit_cube",
        "--at",
        "1",
        "--at",
        "0.25",
        "--at",
        "1/2",
        "--format",
        "svg",
        "-o",
        d,
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "layer-0000_z=1_4.svg",
            "layer-0001_z=1_2.svg",
            "layer-0002_z=1.svg"
        ]
    );
    let top = parse(&std::fs::read_to_string(dir.join("layer-0002_z=1.svg")).unwrap());
    assert_eq!(count(&top, &["f", "up"]), 1);
    let _ = std::fs::remove_dir_all(tmp("dir"));
}

/// The names a level's SVG gets are recognised, and names a user might
/// give are not.
#[test]
fn level_file_names_are_told_from_other_names() {
    let tiny = parse_rational("-7.25e-301").unwrap() / Rat::from_integer(3.into());
    for (i, z) in [(0, parse_rational("1/4").unwrap()), (12_345, tiny)] {
        assert!(is_level_file_name(&level_file_name(i, &z)), "{i}");
    }
    for other in [
        "layer-notes.svg",
        "layer-12_z=1.svg",
        "layer-0001_z=.svg",
        "layer-0001_z=1_2.svg.bak",
        "layer-0001-z=1.svg",
        "notes.txt",
        "Layer-0001_z=1.svg",
    ] {
        assert!(!is_level_file_name(other), "{other}");
    }
}

/// Slicing again into a directory leaves this run's levels in it and no
/// others: the earlier run's level files go, files of other names stay.
#[test]
fn slicing_again_into_a_directory_removes_the_earlier_levels_only() {
    let dir = tmp("again");
    let d = dir.to_str().unwrap();
    let svgs = |args: &[&str]| {
        let mut all = vec!["slice", "unit_cube", "--format", "svg", "-o", d];
        all.extend_from_slice(args);
        run(&all)
    };
    let (code, _, err) = svgs(&["--layer-height", "0.1"]);
    assert_eq!(code, 0, "{err}");
    let names = || {
        let mut n: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    };
    assert_eq!(names().len(), 10);
    for kept in ["notes.txt", "layer-notes.svg"] {
        std::fs::write(dir.join(kept), "mine").unwrap();
    }
    let (code, _, err) = svgs(&["--at", "1/4", "--at", "3/4"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("removed 10 level SVG files of an earlier run"),
        "{err}"
    );
    assert_eq!(
        names(),
        [
            "layer-0000_z=1_4.svg",
            "layer-0001_z=3_4.svg",
            "layer-notes.svg",
            "notes.txt"
        ]
    );
    // One level into the directory: the same.
    let (code, _, err) = svgs(&["--at", "1/2"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        names(),
        ["layer-0000_z=1_2.svg", "layer-notes.svg", "notes.txt"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn slice_writes_a_single_level_to_a_file_or_stdout() {
    let dir = tmp("one");
    let f = dir.join("cyl.svg");
    let (code, _, err) = run(&[
        "slice",
        "cylinder",
        "--at",
        "2",
        "--format",
        "svg",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("wrote"), "{err}");
    assert_eq!(
        count(&parse(&std::fs::read_to_string(&f).unwrap()), &["f", "up"]),
        1
    );
    let (code, out, _) = run(&[
        "slice",
        "lying_torus",
        "--at",
        "2",
        "--format",
        "svg",
        "--arrows",
        "--quiet",
    ]);
    assert_eq!(code, 0);
    assert_eq!(count(&parse(&out), &["sno", "ridge"]), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn several_levels_without_a_directory_is_a_usage_error() {
    let (code, _, err) = run(&[
        "slice",
        "unit_cube",
        "--at",
        "0",
        "--at",
        "1",
        "--format",
        "svg",
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("-o DIR"), "{err}");
}

#[test]
fn unwritable_output_exits_5_and_leaves_no_file() {
    let dir = tmp("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let blocker = dir.join("file");
    std::fs::write(&blocker, b"x").unwrap();
    // A directory cannot be created below a file.
    let target = blocker.join("sub").join("out.html");
    let (code, _, err) = run(&[
        "slice",
        "cylinder",
        "--at",
        "1",
        "--at",
        "2",
        "--format",
        "html",
        "-o",
        target.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 5, "{err}");
    // Several SVGs into a path that is a file.
    let (code, _, _) = run(&[
        "slice",
        "cylinder",
        "--at",
        "1",
        "--at",
        "2",
        "--format",
        "svg",
        "-o",
        blocker.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 5);
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(left.len(), 1, "only the blocker remains");
    assert_eq!(std::fs::read(&blocker).unwrap(), b"x");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn slice_html_holds_every_level_ascending() {
    let dir = tmp("html");
    let f = dir.join("v.html");
    let (code, _, err) = run(&[
        "slice",
        "double_torus",
        "--at",
        "4",
        "--at",
        "2",
        "--at",
        "1",
        "--format",
        "html",
        "-o",
        f.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let page = std::fs::read_to_string(&f).unwrap();
    let i = |z: &str| page.find(&format!("\"z\":\"{z}\"")).unwrap();
    assert!(i("1") < i("2") && i("2") < i("4"));
    assert!(Path::new(&f).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The inner `<svg>` (the drawing) of a standalone SVG.
fn drawing_of(els: &[El]) -> &El {
    els.iter()
        .filter(|e| e.name == "svg")
        .nth(1)
        .expect("nested drawing")
}

/// Every number of the drawing's elements (path data, circle centres and
/// radii), in document order: what a browser reads as 32-bit floats.
fn drawn_numbers<'a>(els: impl IntoIterator<Item = &'a El>) -> Vec<f64> {
    let mut out = Vec::new();
    for e in els {
        if let Some(d) = e.attrs.get("d") {
            out.extend(path_numbers(d));
        }
        for k in ["cx", "cy", "r"] {
            if let Some(v) = e.attrs.get(k) {
                out.push(v.parse().expect("number"));
            }
        }
    }
    out
}

#[test]
fn a_part_far_out_or_at_either_end_of_the_double_range_is_drawn_in_a_frame() {
    use wmslice::datasets::cross_check::{far_offset, scaled};
    use wmslice::exact::rational::rat_from_f64;
    let mesh = datasets::by_name("double_torus").unwrap().build();
    let c = parse_rational("2").unwrap();
    let draw = |m: &wmslice::Mesh, z: &Rat| {
        let ls = Slicer::new(m).expect("valid").slice_at(z).expect("slice");
        let text = level_svg(&ls, &Scene::new(m, None), "x", &SvgOptions::default());
        (ls, parse(&text))
    };
    // As it is: model coordinates (y negated), said by the identity frame.
    let (_, plain) = draw(&mesh, &c);
    assert_eq!(drawing_of(&plain).attrs["data-frame"], "0 0 0");

    // Moved to 2^50 (every coordinate still exact): 32-bit floats are
    // 2^26 apart there, so model coordinates would put every point on one.
    let (t, far) = far_offset(&mesh).expect("a far offset");
    assert!(t >= 2f64.powi(40), "{t}");
    let (ls, els) = draw(&far, &(c.clone() + rat_from_f64(t)));
    let inner = drawing_of(&els);
    let frame: Vec<f64> = inner.attrs["data-frame"]
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    let (x0, y0, k) = (frame[0], frame[1], frame[2] as i32);
    assert!(x0 > 2f64.powi(40) && k != 0, "{frame:?}");
    // Each drawn point of S_O reads back, through the frame, as the
    // nearest double of its exact point. Exactly: near 2^50 a point and the
    // frame's origin are within a factor 2, so their difference is a
    // double (Sterbenz), and scaling by 2^k is exact.
    let outer = with(&els, &["so", "outer"]);
    let drawn: Vec<[f64; 2]> = outer.iter().flat_map(|e| coords(e)).collect();
    let rounded: Vec<[f64; 2]> = ls
        .contours
        .iter()
        .enumerate()
        .filter(|(_, l)| l.role == wmslice::nest::Role::Outer)
        .flat_map(|(i, l)| {
            let holes = ls.contours.iter().filter(move |h| h.parent == Some(i));
            l.points
                .iter()
                .chain(holes.flat_map(|h| &h.points))
                .map(|p| p.to_f64())
        })
        .collect();
    assert!(rounded.len() > 50);
    assert_eq!(drawn.len(), rounded.len());
    let unit = 2f64.powi(-k);
    for ([sx, sy], [x, y]) in drawn.iter().zip(&rounded) {
        assert_eq!(
            [x0 + sx * unit, y0 - sy * unit],
            [*x, *y],
            "drawn as ({sx}, {sy})"
        );
    }
    // The numbers are small: 32-bit floats keep them to 1/16384 of the
    // drawing, whose box is 512 to 1024 units wide.
    let vb: Vec<f64> = inner.attrs["viewBox"]
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!((512.0..1200.0).contains(&vb[2].max(vb[3])), "{vb:?}");
    let numbers = drawn_numbers(&els);
    assert!(!numbers.is_empty());
    assert!(numbers.iter().all(|v| v.abs() < 2048.0), "{numbers:?}");

    // Scaled by a power of two towards either end of the double range
    // (the loop points' nearest doubles still normal, so they scale with
    // the mesh): the frame takes the scale back exactly, so the drawing
    // is the same.
    let mut drawings = Vec::new();
    for s in [-960, 1000] {
        let m = scaled(&mesh, s).expect("exact scale");
        let z = &c * Rat::from_integer(2.into()).pow(s);
        let (_, els) = draw(&m, &z);
        let f = &drawing_of(&els).attrs["data-frame"];
        assert!(!f.ends_with(" 0"), "scaled by 2^{s}: frame {f}");
        drawings.push(drawn_numbers(&els));
    }
    assert_eq!(drawings.len(), 2);
    assert!(drawings[0].len() > 100);
    assert_eq!(drawings[0], drawings[1]);
}

#[test]
fn the_legend_shows_a_long_level_by_its_nearest_double() {
    let mesh = datasets::by_name("unit_cube").unwrap().build();
    let title_and_heading = |z: &str| {
        let level = parse_rational(z).unwrap();
        let ls = Slicer::new(&mesh).unwrap().slice_at(&level).unwrap();
        let els = parse(&level_svg(
            &ls,
            &Scene::new(&mesh, None),
            "cube",
            &SvgOptions::default(),
        ));
        let title = els.iter().find(|e| e.name == "title").unwrap().text.clone();
        let legend = els.iter().position(|e| has(e, &["legend"])).unwrap();
        let heading = els
            .iter()
            .find(|e| e.parent == Some(legend) && e.name == "text")
            .unwrap()
            .text
            .clone();
        (title, heading)
    };
    assert_eq!(title_and_heading("1/3").1, "z = 1/3");
    // 17 characters still fit the legend's column.
    assert_eq!(
        title_and_heading("12345678/12345679").1,
        "z = 12345678/12345679"
    );
    let (title, heading) = title_and_heading("123456789/1234567891");
    assert_eq!(heading, "z \u{2248} 1.000000e-1");
    assert!(title.ends_with("z = 123456789/1234567891"), "{title}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, ..Default::default() })]

    /// Wherever in the double range a part lies (a random family's mesh
    /// scaled by `2^k`, then moved `2^shift` times that scale away), its
    /// drawing survives a browser's 32-bit floats: each number of the
    /// view box and the elements moves, as an `f32`, by at most 1/16384
    /// of the view box.
    #[test]
    fn drawings_survive_32_bit_floats_across_the_double_range(
        family in 0usize..5,
        seed in 0u64..1000,
        k in -1000i32..1000,
        shift in 0i32..64,
        at in 0.0f64..1.0,
    ) {
        use wmslice::datasets::cross_check::{scaled, translated};
        use wmslice::exact::rational::rat_from_f64;
        let mesh = datasets::families::all()[family].generate(seed);
        let moved = scaled(&mesh, k).and_then(|m| translated(&m, 2f64.powi(k + shift)));
        proptest::prop_assume!(moved.is_some());
        let m = moved.unwrap();
        let slicer = Slicer::new(&m);
        proptest::prop_assume!(slicer.is_ok());
        let (lo, hi) = m.positions.iter().fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p[2]), h.max(p[2])));
        let z = lo + at * (hi - lo);
        let ls = slicer.unwrap().slice_at(&rat_from_f64(z)).expect("slice");
        let els = parse(&level_svg(&ls, &Scene::new(&m, None), "x", &SvgOptions { arrows: true }));
        let vb: Vec<f64> = drawing_of(&els).attrs["viewBox"].split(' ').map(|v| v.parse().unwrap()).collect();
        let span = vb[2].max(vb[3]);
        proptest::prop_assert!(span.is_finite() && span > 0.0, "{vb:?}");
        // The drawing's elements: those inside the inner <svg>.
        let inner = els.iter().position(|e| e.attrs.contains_key("data-frame")).unwrap();
        let inside = |mut i: usize| loop {
            match els[i].parent {
                Some(p) if p == inner => break true,
                Some(p) => i = p,
                None => break false,
            }
        };
        let numbers = drawn_numbers((0..els.len()).filter(|&i| inside(i)).map(|i| &els[i]));
        proptest::prop_assert!(!numbers.is_empty() || ls.contours.is_empty());
        for v in vb.iter().chain(&numbers) {
            proptest::prop_assert!(v.is_finite(), "{v}");
            proptest::prop_assert!((v - f64::from(*v as f32)).abs() <= span / 16384.0, "{v} in a box {span} wide");
        }
    }
}
