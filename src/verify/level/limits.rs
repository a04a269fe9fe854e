//! The checks of L- and L+ (SPEC section 6) against the verifier's own
//! limit loops ([`crate::verify::limits`]): the same loops (each the limit
//! of a loop of the contour at `c -/+ epsilon`, compared as cyclic
//! sequences of mesh elements), pieces each once, roles and parents by
//! containment for small `epsilon > 0`, orientation by the first non-zero
//! term of the area in `epsilon`, and the collapsed flags by the exact
//! limit areas of the regions each loop bounds.

use super::{Geom, LevelCheck, Role};
use crate::exact::rational::Rat;
use crate::exact::Sign;
use crate::verify::doc::{LoopDoc, On};
use crate::verify::facts::{Pieces, Side};
use crate::verify::geometry::{Family as Loops, Pt};
use crate::verify::limits::{area_sign, canonical, containers, limit_loops, LimitLoop, Moving};
use crate::verify::report::{Family, Problem};
use num_traits::Zero;
use std::collections::HashMap;

impl LevelCheck<'_, '_> {
    /// Every check of one one-sided family.
    pub(super) fn check_limit(&mut self, family: Family, docs: &[LoopDoc], side: Side) {
        let ours = match limit_loops(self.m.mesh, &self.m.topo, &self.facts().signs, side) {
            Ok(l) => l,
            Err(edge) => {
                let place = self.at(family, None, None, None);
                self.push(place, Problem::LimitNotChained(edge.into()));
                return;
            }
        };
        let mut pieces: Pieces = HashMap::new();
        for l in &ours {
            let n = l.on.len();
            if n > 1 {
                for k in 0..n {
                    *pieces.entry((l.on[k], l.on[(k + 1) % n])).or_default() += 1;
                }
            }
        }
        self.check_pieces(family, None, docs, pieces);
        let geoms = self.loops(family, None, docs);
        // The two sides of a thin band run back along each other.
        let pts: Vec<Vec<Pt>> = geoms.iter().map(|g| g.pts.clone()).collect();
        self.check_contacts(family, &geoms, &Loops::new(&pts), true);

        // The same loops: each written loop is the limit of one of ours.
        let mut by_shape: HashMap<Vec<On>, Vec<usize>> = HashMap::new();
        for (i, l) in ours.iter().enumerate() {
            by_shape.entry(canonical(&l.on)).or_default().push(i);
        }
        let mut matched: Vec<Option<&LimitLoop>> = Vec::with_capacity(docs.len());
        for (i, d) in docs.iter().enumerate() {
            let found = by_shape.get_mut(&canonical(&d.on)).and_then(Vec::pop);
            if found.is_none() {
                let place = self.at(family, Some(i), None, None);
                self.push(place, Problem::NotALimitLoop);
            }
            matched.push(found.map(|k| &ours[k]));
        }
        let mut missing: Vec<usize> = by_shape.into_values().flatten().collect();
        missing.sort_unstable();
        for k in missing {
            let place = self.at(family, None, None, None);
            let l = &ours[k];
            self.push(
                place,
                Problem::LimitLoopMissing {
                    first: l.on[0],
                    points: l.on.len(),
                },
            );
        }
        // Orientation, nesting and collapse need every loop, placed and
        // matched.
        let matched: Option<Vec<&LimitLoop>> = matched.into_iter().collect();
        let (Some(matched), true) = (matched, geoms.len() == docs.len()) else {
            return;
        };
        self.check_limit_nesting(family, docs, &geoms, &matched, side);
    }

    fn check_limit_nesting(
        &mut self,
        family: Family,
        docs: &[LoopDoc],
        geoms: &[Geom],
        matched: &[&LimitLoop],
        side: Side,
    ) {
        let c = self.level.value().clone();
        let moving: Vec<Moving> = matched
            .iter()
            .map(|l| Moving::new(self.m.mesh, &self.m.topo, &c, &l.crossings, side))
            .collect();
        let pts: Vec<Vec<_>> = moving.iter().map(|m| m.points(self.m.frame)).collect();
        for (i, g) in geoms.iter().enumerate() {
            let Some(role) = g.role else { continue };
            let sign = area_sign(&g.area, &pts[i]);
            let want = match role {
                Role::Outer => Sign::Positive,
                Role::Hole => Sign::Negative,
            };
            if sign != want {
                let place = self.at(family, Some(i), None, None);
                self.push(
                    place,
                    Problem::LimitOrientation {
                        role: role.name().to_owned(),
                        sign,
                    },
                );
            }
        }
        // Containment at c -/+ epsilon, where the loops are disjoint
        // simple polygons: any crossing represents its loop.
        let n = pts.len();
        let containers = containers(&pts);
        let depth: Vec<Option<usize>> = containers.iter().map(|c| Some(c.len())).collect();
        let index: Vec<usize> = (0..n).collect();
        for (i, g) in geoms.iter().enumerate() {
            let place = self.at(family, Some(i), None, None);
            self.check_nesting(place, g, n, &containers[i], &depth, &index);
        }
        // Collapsed: a region the loop bounds (the loop minus its
        // children, or its parent minus the parent's children) has zero
        // limit area. Parents as written (checked above).
        let parent: Vec<Option<usize>> = geoms
            .iter()
            .map(|g| {
                g.parent
                    .and_then(|p| usize::try_from(p).ok())
                    .filter(|&p| p < n)
            })
            .collect();
        let mut region: Vec<Rat> = geoms.iter().map(|g| g.area.clone()).collect();
        for (i, p) in parent.iter().enumerate() {
            if let Some(p) = *p {
                region[p] += &geoms[i].area;
            }
        }
        for (i, d) in docs.iter().enumerate() {
            let expect = region[i].is_zero() || parent[i].is_some_and(|p| region[p].is_zero());
            if d.collapsed != expect {
                let place = self.at(family, Some(i), None, None);
                self.push(
                    place,
                    Problem::WrongCollapsed {
                        claimed: d.collapsed,
                    },
                );
            }
        }
    }
}
