//! Input: a [`CriticalReport`] and, optionally, a layer plan. Output: the
//! `wmslice-critical` JSON document and the readable text of `wmslice
//! critical`.
//!
//! Heights are exact `"p/q"` strings in the mesh's units; the text also
//! shows each height rounded to the nearest `f64` (marked `~`), for
//! reading only.

use super::json::MeshHeader;
use crate::classify::Facing;
use crate::critical::fit::PlanReport;
use crate::critical::{CriticalLevel, CriticalReport, ReebNode};
use crate::exact::rational::{rat_to_f64, rat_to_string, Rat};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt::Write;

fn s(r: &Rat) -> String {
    rat_to_string(r)
}

fn level_json(l: &CriticalLevel) -> Value {
    json!({
        "z": s(&l.z),
        "faces_up": l.faces_up,
        "faces_down": l.faces_down,
        "ridges": l.ridges,
        "valleys": l.valleys,
        "minima": l.minima,
        "maxima": l.maxima,
        "saddles": l.saddles,
        "below": l.below,
        "above": l.above,
    })
}

fn node_json(n: &ReebNode) -> Value {
    json!({
        "z": s(&n.z),
        "kind": n.kind.name(),
        "vertex": n.vertex.0,
        "faces_up": n.faces_up,
        "faces_down": n.faces_down,
        "ridges": n.ridges,
        "valleys": n.valleys,
        "minima": n.minima,
        "maxima": n.maxima,
        "saddles": n.saddles,
        "below": n.below,
        "above": n.above,
        "genus": n.genus,
        "bbox": [[s(&n.bbox[0][0]), s(&n.bbox[0][1])], [s(&n.bbox[1][0]), s(&n.bbox[1][1])]],
    })
}

fn facing_name(f: Facing) -> &'static str {
    match f {
        Facing::Up => "up",
        Facing::Down => "down",
        Facing::Flat => "flat",
    }
}

/// A cluster: its heights and the nodes at them (what is involved), in
/// node order; `nodes_at[l]` lists the nodes at level `l`.
fn cluster_json(report: &CriticalReport, nodes_at: &[Vec<usize>], c: &[usize]) -> Value {
    let mut nodes: Vec<usize> = c
        .iter()
        .flat_map(|&l| nodes_at[l].iter().copied())
        .collect();
    nodes.sort_unstable();
    json!({
        "heights": c.iter().map(|&i| s(&report.levels[i].z)).collect::<Vec<_>>(),
        "nodes": nodes,
    })
}

/// A JSON array of values made and written one at a time: a mesh with
/// hundreds of thousands of critical points never holds them all as
/// `Value`s (several hundred bytes of maps each), only as text.
fn array_text(items: impl IntoIterator<Item = Value>) -> String {
    let mut t = String::from("[");
    for (i, v) in items.into_iter().enumerate() {
        if i > 0 {
            t.push(',');
        }
        t.push_str(&v.to_string());
    }
    t.push(']');
    t
}

/// The `wmslice-critical` JSON document (one line, newline-terminated).
/// Keys in byte order at every level, as `serde_json`'s maps write them.
pub fn critical_json(
    header: &MeshHeader,
    report: &CriticalReport,
    plan: Option<&PlanReport>,
) -> String {
    let text = |v: Value| v.to_string();
    let mut doc: BTreeMap<&str, String> = BTreeMap::new();
    doc.insert("format", text(json!("wmslice-critical")));
    doc.insert("version", text(json!(1)));
    doc.insert("mesh", text(json!(header)));
    doc.insert("genus", text(json!(report.genus)));
    doc.insert("components", text(json!(report.components)));
    doc.insert("critical", array_text(report.levels.iter().map(level_json)));
    doc.insert(
        "reeb",
        format!(
            "{{\"arcs\":{},\"nodes\":{}}}",
            text(json!(report.reeb.arcs)),
            array_text(report.reeb.nodes.iter().map(node_json))
        ),
    );
    if let Some(plan) = plan {
        let mut nodes_at = vec![Vec::new(); report.levels.len()];
        for (i, n) in report.reeb.nodes.iter().enumerate() {
            nodes_at[n.level].push(i);
        }
        let clusters = plan
            .clusters()
            .iter()
            .map(|c| cluster_json(report, &nodes_at, c));
        doc.insert("clusters", array_text(clusters));
        match plan {
            PlanReport::Fitted { height, layers, .. } => {
                doc.insert("layer_height", text(json!(s(height))));
                doc.insert(
                    "layers",
                    array_text(layers.iter().map(|l| json!([s(&l[0]), s(&l[1])]))),
                );
            }
            PlanReport::Uniform {
                height,
                first,
                audit,
                ..
            } => {
                doc.insert("layer_height", text(json!(s(height))));
                doc.insert("first", text(json!(s(first))));
                doc.insert(
                    "audit",
                    array_text(audit.iter().map(|a| {
                        json!({
                            "z": s(&report.levels[a.level].z),
                            "facing": facing_name(a.facing),
                            "regions": a.regions,
                            "layer": a.layer,
                            "bounds": [s(&a.bounds[0]), s(&a.bounds[1])],
                            "printed_at": s(&a.printed_at),
                            "offset": s(&a.offset),
                        })
                    })),
                );
            }
        }
    }
    let mut out = String::from("{");
    for (i, (key, value)) in doc.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        // The keys are plain ASCII names: no escaping.
        let _ = write!(out, "\"{key}\":{value}");
    }
    out.push_str("}\n");
    out
}

fn approx(r: &Rat) -> String {
    format!("~{}", rat_to_f64(r))
}

/// What a level holds, in words (`"1 up flat, 2 saddles (m = 2, 3)"`).
pub fn holds(l: &CriticalLevel) -> String {
    let mut parts = Vec::new();
    let mut count = |n: usize, one: &str, many: &str| {
        if n > 0 {
            parts.push(format!("{n} {}", if n == 1 { one } else { many }));
        }
    };
    count(l.faces_up, "up flat", "up flats");
    count(l.faces_down, "down flat", "down flats");
    count(l.ridges, "ridge", "ridges");
    count(l.valleys, "valley", "valleys");
    count(l.minima, "minimum", "minima");
    count(l.maxima, "maximum", "maxima");
    if !l.saddles.is_empty() {
        let ms: Vec<String> = l.saddles.iter().map(u32::to_string).collect();
        parts.push(format!(
            "{} saddle{} (m = {})",
            l.saddles.len(),
            if l.saddles.len() == 1 { "" } else { "s" },
            ms.join(", ")
        ));
    }
    parts.join(", ")
}

/// The readable report of `wmslice critical`.
pub fn critical_text(report: &CriticalReport, plan: Option<&PlanReport>) -> String {
    let mut t = String::new();
    let r = &report.reeb;
    let _ = writeln!(
        t,
        "{} critical heights; genus {}, {} component{}",
        report.levels.len(),
        report.genus,
        report.components,
        if report.components == 1 { "" } else { "s" }
    );
    for l in &report.levels {
        let _ = writeln!(
            t,
            "  z = {} ({}): {}; loops {} below, {} above",
            s(&l.z),
            approx(&l.z),
            holds(l),
            l.below,
            l.above
        );
    }
    let _ = writeln!(
        t,
        "Reeb graph: {} nodes, {} arcs, {} cycles",
        r.nodes.len(),
        r.arcs.len(),
        r.cycles()
    );
    for (i, n) in r.nodes.iter().enumerate() {
        let up: Vec<String> = r
            .arcs
            .iter()
            .filter(|a| a[0] == i)
            .map(|a| a[1].to_string())
            .collect();
        let genus = if n.genus > 0 {
            format!(", genus {}", n.genus)
        } else {
            String::new()
        };
        let _ = writeln!(
            t,
            "  node {i}: {} at z = {} (vertex {}{genus}){}",
            n.kind.name(),
            s(&n.z),
            n.vertex.0,
            if up.is_empty() {
                String::new()
            } else {
                format!(" -> {}", up.join(", "))
            }
        );
    }
    match plan {
        None => {}
        Some(PlanReport::Fitted { height, layers, .. }) => {
            let _ = writeln!(
                t,
                "fitted plan: {} layers for layer height {} (each between H/2 and 3H/2, every flat on a boundary)",
                layers.len(),
                s(height)
            );
            for l in layers {
                let _ = writeln!(
                    t,
                    "  [{}, {}]  thickness {}",
                    s(&l[0]),
                    s(&l[1]),
                    approx(&(&l[1] - &l[0]))
                );
            }
        }
        Some(PlanReport::Uniform {
            height,
            first,
            audit,
            ..
        }) => {
            let _ = writeln!(
                t,
                "uniform plan: planes {} + k * {}, each printing [p - H/2, p + H/2]",
                s(first),
                s(height)
            );
            for a in audit {
                let z = &report.levels[a.level].z;
                let _ = writeln!(
                    t,
                    "  {} flat at z = {}: printed by layer {} [{}, {}] at {} (off by {}, {})",
                    facing_name(a.facing),
                    s(z),
                    a.layer,
                    s(&a.bounds[0]),
                    s(&a.bounds[1]),
                    s(&a.printed_at),
                    s(&a.offset),
                    approx(&a.offset)
                );
            }
        }
    }
    if let Some(plan) = plan {
        for c in plan.clusters() {
            let zs: Vec<String> = c.iter().map(|&i| s(&report.levels[i].z)).collect();
            let what: Vec<String> = c.iter().map(|&i| holds(&report.levels[i])).collect();
            let _ = writeln!(
                t,
                "warning: critical heights closer than the layer height: z = {} ({}); a nearly flat surface in steps prints as stray partial layers",
                zs.join(", "),
                what.join("; ")
            );
        }
    }
    t
}
