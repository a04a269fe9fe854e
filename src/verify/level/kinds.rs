//! Input: the S_NO polylines, extremal points P and saddles of a level as
//! written. Output: their violations: every ridge or valley edge in exactly
//! one maximal polyline of its kind, split only at junctions; every
//! isolated extremum in P with its kind and nowhere else; every vertex with
//! four or more S_O branches listed as a saddle with its exact count.

use super::LevelCheck;
use crate::exact::Sign;
use crate::verify::doc::{LevelDoc, LoopDoc, On};
use crate::verify::facts::{Extremum, RidgeKind, NONE};
use crate::verify::report::{Family, Problem};
use std::collections::{BTreeSet, HashMap};

impl LevelCheck<'_, '_> {
    /// Whether S_NO polylines end at `v` (more or fewer than two S_NO
    /// edges there, or two of different kinds).
    fn junctions(&self) -> HashMap<u32, (usize, bool)> {
        let mut at: HashMap<u32, (usize, Option<RidgeKind>, bool)> = HashMap::new();
        for (&e, &kind) in &self.facts().sno {
            for v in self.m.topo.edges[e as usize].v {
                let slot = at.entry(v.0).or_insert((0, None, false));
                slot.0 += 1;
                if slot.1.is_some_and(|k| k != kind) {
                    slot.2 = true;
                }
                slot.1 = Some(kind);
            }
        }
        at.into_iter()
            .map(|(v, (deg, _, mixed))| (v, (deg, deg != 2 || mixed)))
            .collect()
    }

    /// What an in-plane edge is, for messages.
    fn edge_is(&self, e: usize) -> &'static str {
        let edge = &self.m.topo.edges[e];
        let f = self.facts();
        if edge.v.iter().any(|v| f.signs[v.idx()] != Sign::Zero) {
            return "not in the plane";
        }
        let inside = edge.faces.map(|x| f.component[x.idx()] != NONE);
        match inside {
            [true, true] => "inside a face region",
            [true, false] | [false, true] => "a face region's boundary",
            _ => "a transversal contour edge (S_O)",
        }
    }

    pub(super) fn check_ridges(&mut self, doc: &LevelDoc) {
        let nv = self.m.mesh.num_vertices();
        let junction = self.junctions();
        let is_junction = |v: u64| junction.get(&(v as u32)).is_none_or(|j| j.1);
        let mut used: HashMap<u32, usize> = HashMap::new();
        for (r, ridge) in doc.ridges.iter().enumerate() {
            self.checked.ridges += 1;
            let here = self.at(Family::Ridges, Some(r), None, None);
            let kind = match ridge.kind.as_str() {
                "ridge" => Some(RidgeKind::Ridge),
                "valley" => Some(RidgeKind::Valley),
                k => {
                    self.push(here.clone(), Problem::BadKind(k.to_owned()));
                    None
                }
            };
            let n = ridge.vertices.len();
            if n < 2 || (ridge.closed && n < 3) {
                self.push(here.clone(), Problem::TooShort);
                continue;
            }
            if ridge.points.len() != n {
                self.push(
                    here.clone(),
                    Problem::PointCount {
                        points: ridge.points.len(),
                        vertices: n,
                    },
                );
            }
            let mut valid = true;
            for (k, &v) in ridge.vertices.iter().enumerate() {
                let at = self.at(Family::Ridges, Some(r), None, Some(k));
                if v >= nv as u64 {
                    self.push(at, Problem::NoSuchVertex(v));
                    valid = false;
                    continue;
                }
                if let Some(pt) = ridge.points.get(k) {
                    let p = self.vertex_point(v as usize);
                    self.nearest(at.clone(), "rounded x", &pt[0], &p.x);
                    self.nearest(at.clone(), "rounded y", &pt[1], &p.y);
                }
                let end = k == 0 || k == n - 1;
                if ridge.closed || !end {
                    if is_junction(v) {
                        self.push(at, Problem::ThroughJunction(v));
                    }
                } else if !is_junction(v) {
                    self.push(at, Problem::NotMaximal(v));
                }
            }
            if !valid {
                continue;
            }
            let steps = if ridge.closed { n } else { n - 1 };
            for k in 0..steps {
                let at = self.at(Family::Ridges, Some(r), None, Some(k));
                let (a, b) = (ridge.vertices[k], ridge.vertices[(k + 1) % n]);
                let Some(e) = self.m.edge_between(a as u32, b as u32) else {
                    self.push(at, Problem::NotAnEdge(a, b));
                    continue;
                };
                match self.facts().sno.get(&e).copied() {
                    None => {
                        let is = self.edge_is(e as usize);
                        self.push(at, Problem::NotRidgeEdge { edge: e.into(), is });
                    }
                    Some(expected) => {
                        let count = used.entry(e).or_default();
                        *count += 1;
                        if *count > 1 {
                            self.push(at.clone(), Problem::RidgeEdgeRepeated(e.into()));
                        }
                        if kind.is_some_and(|k| k != expected) {
                            self.push(
                                at,
                                Problem::WrongRidgeKind {
                                    edge: e.into(),
                                    claimed: ridge.kind.clone(),
                                    expected: expected.name(),
                                },
                            );
                        }
                    }
                }
            }
        }
        let missing: Vec<(u32, &'static str)> = self
            .facts()
            .sno
            .iter()
            .filter(|(e, _)| !used.contains_key(e))
            .map(|(&e, k)| (e, k.name()))
            .collect();
        for (edge, kind) in missing {
            let place = self.at(Family::Ridges, None, None, None);
            self.push(
                place,
                Problem::RidgeEdgeMissing {
                    edge: edge.into(),
                    kind,
                },
            );
        }
    }

    pub(super) fn check_extrema(&mut self, doc: &LevelDoc) {
        let nv = self.m.mesh.num_vertices() as u64;
        let mut seen: BTreeSet<u64> = BTreeSet::new();
        for (i, p) in doc.points.iter().enumerate() {
            self.checked.extrema += 1;
            let here = self.at(Family::Points, Some(i), None, None);
            if p.vertex >= nv {
                self.push(here, Problem::NoSuchVertex(p.vertex));
                continue;
            }
            if !seen.insert(p.vertex) {
                self.push(here.clone(), Problem::VertexRepeated(p.vertex));
            }
            let at = self.vertex_point(p.vertex as usize);
            self.nearest(here.clone(), "rounded x", &p.point[0], &at.x);
            self.nearest(here.clone(), "rounded y", &p.point[1], &at.y);
            let claimed = match p.kind.as_str() {
                "min" => Some(Extremum::Min),
                "max" => Some(Extremum::Max),
                k => {
                    self.push(here.clone(), Problem::BadKind(k.to_owned()));
                    None
                }
            };
            match self.facts().extrema.get(&(p.vertex as u32)).copied() {
                None => self.push(here, Problem::NotExtremum(p.vertex)),
                Some(k) if claimed.is_some_and(|c| c != k) => self.push(
                    here,
                    Problem::WrongExtremum {
                        vertex: p.vertex,
                        claimed: p.kind.clone(),
                        expected: k.name(),
                    },
                ),
                Some(_) => {}
            }
        }
        let missing: Vec<(u32, &'static str)> = self
            .facts()
            .extrema
            .iter()
            .filter(|(v, _)| !seen.contains(&u64::from(**v)))
            .map(|(&v, k)| (v, k.name()))
            .collect();
        for (v, kind) in missing {
            let place = self.at(Family::Points, None, None, None);
            self.push(
                place,
                Problem::ExtremumMissing {
                    vertex: v.into(),
                    kind,
                },
            );
        }
    }

    pub(super) fn check_saddles(&mut self, doc: &LevelDoc) {
        let mut seen: BTreeSet<u64> = BTreeSet::new();
        for (i, s) in doc.saddles.iter().enumerate() {
            self.checked.saddles += 1;
            let here = self.at(Family::Saddles, Some(i), None, None);
            if !seen.insert(s.vertex) {
                self.push(here.clone(), Problem::VertexRepeated(s.vertex));
            }
            let actual = u32::try_from(s.vertex)
                .ok()
                .and_then(|v| self.facts().branches.get(&v).copied())
                .unwrap_or(0);
            if actual < 4 {
                self.push(
                    here,
                    Problem::NotSaddle {
                        vertex: s.vertex,
                        branches: actual,
                    },
                );
            } else if s.branches != actual as u64 {
                self.push(
                    here,
                    Problem::WrongBranches {
                        vertex: s.vertex,
                        claimed: s.branches,
                        actual,
                    },
                );
            }
        }
        let mut missing: Vec<(u32, usize)> = self
            .facts()
            .branches
            .iter()
            .filter(|&(v, &b)| b >= 4 && !seen.contains(&u64::from(*v)))
            .map(|(&v, &b)| (v, b))
            .collect();
        missing.sort_unstable();
        for (v, branches) in missing {
            let place = self.at(Family::Saddles, None, None, None);
            self.push(
                place,
                Problem::SaddleMissing {
                    vertex: v.into(),
                    branches,
                },
            );
        }
    }

    /// An isolated extremum is in P and nothing else of the classification
    /// (SPEC 7.1): no S_O or dF point and no ridge vertex may be one. (The
    /// one-sided limits are not part of it: a limit collapses onto an
    /// extremum.)
    pub(super) fn check_extrema_elsewhere(&mut self, doc: &LevelDoc) {
        if self.facts().extrema.is_empty() {
            return;
        }
        let is_ext = |v: u64| {
            u32::try_from(v)
                .ok()
                .is_some_and(|v| self.facts().extrema.contains_key(&v))
        };
        let mut found = Vec::new();
        let mut scan = |family: Family, item: usize, sub: Option<usize>, l: &LoopDoc| {
            for (k, on) in l.on.iter().enumerate() {
                if let On::Vertex(v) = *on {
                    if is_ext(v) {
                        found.push((family, item, sub, k, v));
                    }
                }
            }
        };
        for (i, l) in doc.contours.iter().enumerate() {
            scan(Family::Contours, i, None, l);
        }
        for (r, reg) in doc.faces.iter().enumerate() {
            for (i, l) in reg.boundary.iter().enumerate() {
                scan(Family::Boundary, r, Some(i), l);
            }
        }
        for (r, ridge) in doc.ridges.iter().enumerate() {
            for (k, &v) in ridge.vertices.iter().enumerate() {
                if is_ext(v) {
                    found.push((Family::Ridges, r, None, k, v));
                }
            }
        }
        for (family, item, sub, k, v) in found {
            let place = self.at(family, Some(item), sub, Some(k));
            self.push(place, Problem::ExtremumElsewhere(v));
        }
    }
}
