//! Input: a [`ReebGraph`]. Output: an SVG picture of it: each node at its
//! height (vertical axis, `z` up), coloured by kind; each arc a curve in
//! its own lane from its lower to its upper node, so arcs that run beside
//! each other never overlap. Positions are rounded to 0.01 px for drawing
//! only.

use super::svg::{level_label, xml_escape as escape};
use crate::critical::{NodeKind, ReebGraph};
use crate::exact::rational::{rat_to_f64, rat_to_string};
use std::fmt::Write;

const WIDTH: f64 = 640.0;
const HEIGHT: f64 = 480.0;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 130.0;
const MARGIN: f64 = 24.0;
/// At most this many height labels on the axis (evenly picked).
const MAX_LABELS: usize = 24;

/// The fill colour of a node kind.
pub fn kind_colour(kind: NodeKind) -> &'static str {
    match kind {
        NodeKind::Min => "#1f77b4",
        NodeKind::Max => "#d62728",
        NodeKind::Saddle => "#2ca02c",
        NodeKind::Plateau => "#9467bd",
        NodeKind::Ridge => "#ff7f0e",
        NodeKind::Valley => "#17becf",
        NodeKind::Mixed => "#7f7f7f",
    }
}

const KINDS: [NodeKind; 7] = [
    NodeKind::Min,
    NodeKind::Max,
    NodeKind::Saddle,
    NodeKind::Plateau,
    NodeKind::Ridge,
    NodeKind::Valley,
    NodeKind::Mixed,
];

/// A lane for each arc (arcs whose open height spans overlap get different
/// lanes; the smallest free lane, arcs taken by their lower node), and a
/// horizontal position for each node (the mean lane of its arcs).
fn layout(graph: &ReebGraph) -> (Vec<usize>, Vec<f64>) {
    let level = |n: usize| graph.nodes[n].level;
    let mut order: Vec<usize> = (0..graph.arcs.len()).collect();
    order.sort_by_key(|&a| (level(graph.arcs[a][0]), graph.arcs[a]));
    let mut free_from: Vec<usize> = Vec::new();
    let mut lanes = vec![0; graph.arcs.len()];
    for a in order {
        let [lo, hi] = graph.arcs[a];
        let lane = match free_from.iter().position(|&f| f <= level(lo)) {
            Some(l) => l,
            None => {
                free_from.push(0);
                free_from.len() - 1
            }
        };
        free_from[lane] = level(hi);
        lanes[a] = lane;
    }
    let mut sum = vec![(0.0, 0usize); graph.nodes.len()];
    for (a, &lane) in graph.arcs.iter().zip(&lanes) {
        for &n in a {
            sum[n].0 += lane as f64;
            sum[n].1 += 1;
        }
    }
    let xs = sum
        .iter()
        .map(|&(s, k)| if k == 0 { 0.0 } else { s / k as f64 })
        .collect();
    (lanes, xs)
}

/// The SVG document (newline-terminated).
pub fn reeb_svg(graph: &ReebGraph, title: &str) -> String {
    let nodes = &graph.nodes;
    let zs: Vec<f64> = nodes.iter().map(|n| rat_to_f64(&n.z)).collect();
    let (lanes, xs) = layout(graph);
    let width = lanes.iter().copied().max().unwrap_or(0).max(1) as f64;
    let z0 = zs.iter().copied().fold(f64::INFINITY, f64::min);
    let z1 = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (z0, z1) = if z1 > z0 {
        (z0, z1)
    } else {
        (z0 - 1.0, z0 + 1.0)
    };
    let px = |x: f64| LEFT + 20.0 + x / width * (WIDTH - LEFT - RIGHT - 40.0);
    // Halved, so that no difference of heights near ±f64::MAX overflows.
    let py = |z: f64| {
        HEIGHT - MARGIN - (z / 2.0 - z0 / 2.0) / (z1 / 2.0 - z0 / 2.0) * (HEIGHT - 2.0 * MARGIN)
    };
    let mut t = String::new();
    let _ = writeln!(
        t,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(t, "<title>{}</title>", escape(title));
    let _ = writeln!(t, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    // Height axis: the distinct node heights, at most MAX_LABELS labelled.
    let mut levels: Vec<usize> = (0..nodes.len()).collect();
    levels.dedup_by(|a, b| nodes[*a].level == nodes[*b].level);
    let stride = levels.len().div_ceil(MAX_LABELS).max(1);
    for (k, &i) in levels.iter().enumerate() {
        let y = py(zs[i]);
        let _ = writeln!(
            t,
            r##"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="#e6e6e6"/>"##,
            LEFT - 10.0,
            WIDTH - RIGHT + 10.0
        );
        if k % stride == 0 || k + 1 == levels.len() {
            let _ = writeln!(
                t,
                r##"<text x="{:.2}" y="{:.2}" text-anchor="end" fill="#444">{}</text>"##,
                LEFT - 14.0,
                y + 4.0,
                // The axis's margin holds 8 characters of a height.
                escape(&level_label(&nodes[i].z, 8, 2))
            );
        }
    }
    // Arcs: each runs in its own lane between its nodes.
    for (a, &lane) in graph.arcs.iter().zip(&lanes) {
        let (xa, ya) = (px(xs[a[0]]), py(zs[a[0]]));
        let (xb, yb) = (px(xs[a[1]]), py(zs[a[1]]));
        let xl = px(lane as f64);
        let (c1, c2) = (ya + (yb - ya) / 3.0, yb - (yb - ya) / 3.0);
        let _ = writeln!(
            t,
            r##"<path d="M {xa:.2} {ya:.2} C {xl:.2} {c1:.2} {xl:.2} {c2:.2} {xb:.2} {yb:.2}" fill="none" stroke="#555" stroke-width="1.5"/>"##
        );
    }
    for (i, n) in nodes.iter().enumerate() {
        let _ = writeln!(
            t,
            r##"<circle cx="{:.2}" cy="{:.2}" r="6" fill="{}" stroke="#222"><title>node {i}: {} at z = {}</title></circle>"##,
            px(xs[i]),
            py(zs[i]),
            kind_colour(n.kind),
            n.kind.name(),
            escape(&rat_to_string(&n.z))
        );
    }
    for (k, kind) in KINDS.iter().enumerate() {
        let y = MARGIN + 18.0 * k as f64;
        let x = WIDTH - RIGHT + 30.0;
        let _ = writeln!(
            t,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="6" fill="{}" stroke="#222"/><text x="{:.2}" y="{:.2}">{}</text>"##,
            kind_colour(*kind),
            x + 12.0,
            y + 4.0,
            kind.name()
        );
    }
    t.push_str("</svg>\n");
    t
}
