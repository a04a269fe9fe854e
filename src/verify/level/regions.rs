//! Input: the face regions F of a level as written, with their boundary
//! loops dF. Output: their violations: every in-plane face in exactly one
//! region, regions maximal and connected, facing from exact orient2d, exact
//! areas, boundary loops made of exactly the regions' boundary half-edges,
//! oriented as the facing demands, nested and not crossing.

use super::{LevelCheck, Orientation};
use crate::exact::rational::{rat_to_string, Rat};
use crate::verify::doc::{On, RegionDoc};
use crate::verify::facts::{Facing, Facts, Pieces, NONE};
use crate::verify::report::{Family, Problem};
use num_traits::Zero;
use std::collections::{BTreeMap, HashMap};

impl LevelCheck<'_, '_> {
    pub(super) fn check_regions(&mut self, docs: &[RegionDoc]) {
        let nf = self.m.mesh.num_faces();
        let mut owner = vec![NONE; nf];
        let mut faces_of: Vec<Vec<usize>> = Vec::with_capacity(docs.len());
        for (r, reg) in docs.iter().enumerate() {
            self.checked.regions += 1;
            let here = self.at(Family::Regions, Some(r), None, None);
            let mut mine = Vec::new();
            for &f in &reg.faces {
                let problem = match usize::try_from(f).ok().filter(|&f| f < nf) {
                    None => Problem::NoSuchFace(f),
                    Some(i) if self.facts().component[i] == NONE => Problem::FaceNotInPlane(f),
                    Some(i) if owner[i] != NONE => Problem::FaceRepeated(f),
                    Some(i) => {
                        owner[i] = r as u32;
                        mine.push(i);
                        continue;
                    }
                };
                self.push(here.clone(), problem);
            }
            let claimed = Facing::parse(&reg.facing);
            if claimed.is_none() {
                self.push(here.clone(), Problem::BadFacing(reg.facing.clone()));
            }
            if let Some(&first) = mine.first() {
                let comp = self.facts().component[first];
                let reached = mine
                    .iter()
                    .filter(|&&f| self.facts().component[f] == comp)
                    .count();
                if reached != mine.len() {
                    self.push(
                        here.clone(),
                        Problem::Disconnected {
                            reached,
                            faces: mine.len(),
                        },
                    );
                }
                let (facing, mixed) = self.facts().facing[comp as usize];
                if mixed {
                    self.push(here.clone(), Problem::MixedFacing);
                }
                if claimed.is_some_and(|c| c != facing) {
                    self.push(
                        here.clone(),
                        Problem::WrongFacing {
                            claimed: reg.facing.clone(),
                            expected: facing.name(),
                        },
                    );
                }
            }
            faces_of.push(mine);
        }
        let missing: Vec<u32> = self
            .facts()
            .in_plane
            .iter()
            .copied()
            .filter(|&f| owner[f as usize] == NONE)
            .collect();
        for f in missing {
            let place = self.at(Family::Regions, None, None, None);
            self.push(place, Problem::FaceMissing(f.into()));
        }
        let mut joined: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        for (id, e) in self.m.topo.edges.iter().enumerate() {
            let [o0, o1] = e.faces.map(|f| owner[f.idx()]);
            if o0 != NONE && o1 != NONE && o0 != o1 {
                joined.entry((o0.max(o1), o0.min(o1))).or_insert(id as u32);
            }
        }
        for ((r, other), edge) in joined {
            let place = self.at(Family::Regions, Some(r as usize), None, None);
            self.push(
                place,
                Problem::RegionsJoined {
                    edge: edge.into(),
                    other: other as usize,
                },
            );
        }
        let u2 = &self.m.unit * &self.m.unit;
        for (r, reg) in docs.iter().enumerate() {
            let here = self.at(Family::Regions, Some(r), None, None);
            let mine = &faces_of[r];
            let area = Facts::area_of(self.m.mesh, mine.iter().copied()) * &u2;
            if let Some(claimed) = self.exact(here.clone(), "area", &reg.area) {
                if claimed != area {
                    self.push(
                        here.clone(),
                        Problem::WrongRegionArea {
                            claimed: rat_to_string(&claimed),
                            actual: rat_to_string(&area),
                        },
                    );
                }
            }
            // dF: each boundary half-edge as its region face runs it.
            let mut pieces: Pieces = HashMap::new();
            for &f in mine {
                let tri = self.m.mesh.faces[f];
                for (i, e) in self.m.topo.face_edges[f].iter().enumerate() {
                    let edge = self.m.topo.edge(*e);
                    let other = if edge.faces[0].idx() == f {
                        edge.faces[1]
                    } else {
                        edge.faces[0]
                    };
                    if owner[other.idx()] != r as u32 {
                        let from = On::Vertex(tri[i].0.into());
                        let to = On::Vertex(tri[(i + 1) % 3].0.into());
                        *pieces.entry((from, to)).or_default() += 1;
                    }
                }
            }
            self.check_pieces(Family::Boundary, Some(r), &reg.boundary, pieces);
            let geoms = self.loops(Family::Boundary, Some(r), &reg.boundary);
            let Some(facing) = Facing::parse(&reg.facing) else {
                continue;
            };
            if geoms.len() == reg.boundary.len() {
                let sum = geoms.iter().fold(Rat::zero(), |s, g| s + &g.area);
                let expected = match facing {
                    Facing::Up => area.clone(),
                    Facing::Down => -area.clone(),
                    Facing::Flat => Rat::zero(),
                };
                if sum != expected {
                    self.push(
                        here,
                        Problem::BoundarySum {
                            sum: rat_to_string(&sum),
                            expected: rat_to_string(&expected),
                        },
                    );
                }
            }
            self.check_family(
                Family::Boundary,
                reg.boundary.len(),
                geoms,
                Orientation::Region(facing),
            );
        }
    }
}
