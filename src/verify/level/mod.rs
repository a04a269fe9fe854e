//! Input: one level of a result ([`LevelDoc`]) and the mesh. Output: its
//! violations of SPEC section 7, invariants 1 to 4: every point on the
//! element and level it claims with the exact crossing as its value and the
//! nearest doubles as its rounding; the pieces of every family exactly the
//! ones the mesh gives ([`Facts`]), each once, in the right direction
//! (cover, closure, orientation by the face walk); signed areas against
//! roles; roles and parents against exact containment; no crossing.

mod kinds;
mod limits;
mod regions;

use crate::exact::area::AreaSum;
use crate::exact::frame::Frame;
use crate::exact::rational::{parse_rational, rat_to_f64, rat_to_string, Rat};
use crate::exact::{Level, Point2, Sign};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::verify::doc::{LevelDoc, LoopDoc, On};
use crate::verify::facts::{Facing, Facts, Pieces, Side};
use crate::verify::geometry::{Family as Loops, Pt};
use crate::verify::report::{Checked, Family, Other, Place, Problem, Violation};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::One;
use std::cell::OnceCell;
use std::collections::{HashMap, HashSet};

/// The mesh side of a verification, shared by every level.
pub(super) struct MeshCtx<'a> {
    /// The mesh in stored units.
    pub mesh: &'a Mesh,
    /// Its edge table.
    pub topo: Topology,
    /// The grid step: true coordinate = stored * unit.
    pub unit: Rat,
    /// The power of two in which the moving points' filters work (the
    /// slicer's choice for the same mesh: the identity but at the ends of
    /// the double range). No answer depends on it.
    pub frame: Frame,
    /// Edge id by sorted vertex pair, built when a level has ridges.
    pub edge_index: OnceCell<HashMap<(u32, u32), u32>>,
}

impl MeshCtx<'_> {
    fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        let index = self.edge_index.get_or_init(|| {
            self.topo
                .edges
                .iter()
                .enumerate()
                .map(|(i, e)| ((e.v[0].0, e.v[1].0), i as u32))
                .collect()
        });
        index.get(&(a.min(b), a.max(b))).copied()
    }
}

/// Outer or hole.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Outer,
    Hole,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::Outer => "outer",
            Role::Hole => "hole",
        }
    }
}

/// A loop whose points could all be placed.
struct Geom {
    item: usize,
    sub: Option<usize>,
    pts: Vec<Pt>,
    area: Rat,
    role: Option<Role>,
    role_text: String,
    parent: Option<u64>,
}

/// What the sign of a loop's area must be.
#[derive(Clone, Copy)]
enum Orientation {
    /// S_O: outer > 0, hole < 0.
    Contour,
    /// dF of a region with this (claimed) facing.
    Region(Facing),
}

fn xy_text(p: &Point2) -> String {
    format!("({}, {})", rat_to_string(&p.x), rat_to_string(&p.y))
}

/// Checks one level; appends violations to `out`.
pub(super) fn check_level(
    m: &MeshCtx,
    index: usize,
    doc: &LevelDoc,
    out: &mut Vec<Violation>,
    checked: &mut Checked,
) {
    checked.levels += 1;
    let place = Place {
        level: Some((index, doc.z.clone())),
        family: Family::Level,
        item: None,
        sub: None,
        point: None,
    };
    let Some(z) = exact_field(out, place.clone(), "z", &doc.z) else {
        return;
    };
    let level = Level::new(&z / &m.unit);
    let facts = Facts::new(m.mesh, &m.topo, &level);
    let mut c = LevelCheck {
        m,
        level,
        facts,
        place,
        out,
        checked,
        cache: HashMap::new(),
    };
    c.run(doc);
}

/// An exact rational field: parsed, and canonical.
fn exact_field(
    out: &mut Vec<Violation>,
    place: Place,
    what: &'static str,
    text: &str,
) -> Option<Rat> {
    let problem = match parse_rational(text) {
        Err(_) => Problem::BadRational {
            what,
            text: text.to_owned(),
        },
        Ok(r) => {
            let canonical = rat_to_string(&r);
            if canonical == text {
                return Some(r);
            }
            out.push(Violation {
                place,
                problem: Problem::NotCanonical {
                    what,
                    text: text.to_owned(),
                    canonical,
                },
            });
            return Some(r);
        }
    };
    out.push(Violation { place, problem });
    None
}

/// The rational `text` writes in the canonical syntax (`"p"` or `"p/q"`,
/// `q > 1`, no sign but a leading `-`, no leading zeros, no `-0`), as
/// written: not reduced, so lowest terms are the caller's to check.
fn canonical_rational(text: &str) -> Option<Rat> {
    let digits = |t: &str| {
        !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) && (t == "0" || !t.starts_with('0'))
    };
    let (num, den) = match text.split_once('/') {
        Some((n, d)) => (n, Some(d)),
        None => (text, None),
    };
    let magnitude = num.strip_prefix('-').unwrap_or(num);
    if !digits(magnitude) || num == "-0" {
        return None;
    }
    let p = num.parse::<BigInt>().ok()?;
    let q = match den {
        None => BigInt::one(),
        Some(d) if digits(d) && d != "0" && d != "1" => d.parse::<BigInt>().ok()?,
        Some(_) => return None,
    };
    Some(Rat::new_raw(p, q))
}

/// Whether `text` is the canonical text of `r` (see
/// [`canonical_rational`]; lowest terms, as `r` is): the text is checked
/// for that syntax and its integers compared with `r`'s, which is cheaper
/// than formatting `r`.
fn is_text_of(text: &str, r: &Rat) -> bool {
    canonical_rational(text).is_some_and(|t| t.numer() == r.numer() && t.denom() == r.denom())
}

struct LevelCheck<'a, 'o> {
    m: &'a MeshCtx<'a>,
    level: Level,
    facts: Facts,
    place: Place,
    out: &'o mut Vec<Violation>,
    checked: &'o mut Checked,
    cache: HashMap<On, Result<Point2, Problem>>,
}

impl LevelCheck<'_, '_> {
    fn facts(&self) -> &Facts {
        &self.facts
    }

    fn at(
        &self,
        family: Family,
        item: Option<usize>,
        sub: Option<usize>,
        point: Option<usize>,
    ) -> Place {
        Place {
            family,
            item,
            sub,
            point,
            ..self.place.clone()
        }
    }

    fn push(&mut self, place: Place, problem: Problem) {
        self.out.push(Violation { place, problem });
    }

    fn exact(&mut self, place: Place, what: &'static str, text: &str) -> Option<Rat> {
        exact_field(self.out, place, what, text)
    }

    /// A rounded field: the decimal written must round to the double
    /// nearest to `exact` (the finite one: `f64::MAX` of its sign when the
    /// value is beyond it, as JSON has no infinity). The text is read by
    /// Rust's float parser, which rounds correctly (unlike a best-effort
    /// JSON number parser).
    fn nearest(&mut self, place: Place, what: &'static str, text: &str, exact: &Rat) {
        let want = rat_to_f64(exact).clamp(f64::MIN, f64::MAX);
        let ok = text.parse::<f64>().is_ok_and(|r| r == want);
        if !ok {
            self.push(
                place,
                Problem::NotNearest {
                    what,
                    claimed: text.to_owned(),
                    nearest: format!("{want:?}"),
                },
            );
        }
    }

    fn scaled(&self, p: Point2) -> Point2 {
        if self.m.unit.is_one() {
            p
        } else {
            p.scaled(&self.m.unit)
        }
    }

    fn vertex_point(&self, v: usize) -> Point2 {
        self.scaled(Point2::of_vertex(self.m.mesh.positions[v]))
    }

    /// The exact point of an element at this level, if the element exists
    /// and is a valid place for a contour point (a strictly crossed edge,
    /// or a vertex on the plane).
    fn element_point(&mut self, on: On) -> Result<Point2, Problem> {
        if let Some(r) = self.cache.get(&on) {
            return r.clone();
        }
        let mesh = self.m.mesh;
        let signs = &self.facts().signs;
        let r = match on {
            On::Vertex(v) => match usize::try_from(v).ok().filter(|&v| v < mesh.num_vertices()) {
                None => Err(Problem::NoSuchVertex(v)),
                Some(i) if signs[i] != Sign::Zero => Err(Problem::VertexOffPlane {
                    vertex: v,
                    sign: signs[i],
                }),
                Some(i) => Ok(self.vertex_point(i)),
            },
            On::Edge(e) => match usize::try_from(e)
                .ok()
                .filter(|&e| e < self.m.topo.edges.len())
            {
                None => Err(Problem::NoSuchEdge(e)),
                Some(i) => {
                    let [a, b] = self.m.topo.edges[i].v;
                    let s = [signs[a.idx()], signs[b.idx()]];
                    let crossed = matches!(
                        s,
                        [Sign::Positive, Sign::Negative] | [Sign::Negative, Sign::Positive]
                    );
                    if crossed {
                        let p = Point2::on_edge(mesh.pos(a), mesh.pos(b), &self.level);
                        Ok(self.scaled(p))
                    } else {
                        Err(Problem::EdgeNotCrossed { edge: e, signs: s })
                    }
                }
            },
        };
        self.cache.insert(on, r.clone());
        r
    }

    fn run(&mut self, doc: &LevelDoc) {
        // S_O.
        let so = std::mem::take(&mut self.facts.so);
        self.check_pieces(Family::Contours, None, &doc.contours, so);
        let geoms = self.loops(Family::Contours, None, &doc.contours);
        self.check_family(
            Family::Contours,
            doc.contours.len(),
            geoms,
            Orientation::Contour,
        );

        // F and dF.
        self.check_regions(&doc.faces);

        // S_NO, P, saddles.
        self.check_ridges(doc);
        self.check_extrema(doc);
        self.check_saddles(doc);

        // L- and L+.
        self.check_limit(Family::Below, &doc.below, Side::Below);
        self.check_limit(Family::Above, &doc.above, Side::Above);

        self.check_extrema_elsewhere(doc);
    }

    /// Per-loop checks; the loops whose points could all be placed.
    fn loops(&mut self, family: Family, region: Option<usize>, docs: &[LoopDoc]) -> Vec<Geom> {
        let mut out = Vec::new();
        for (i, d) in docs.iter().enumerate() {
            let (item, sub) = match region {
                Some(r) => (r, Some(i)),
                None => (i, None),
            };
            if let Some(g) = self.check_loop(family, item, sub, d) {
                out.push(g);
            }
        }
        out
    }

    fn check_loop(
        &mut self,
        family: Family,
        item: usize,
        sub: Option<usize>,
        d: &LoopDoc,
    ) -> Option<Geom> {
        let n = d.on.len();
        let whole = self.at(family, Some(item), sub, None);
        if d.points.len() != n || d.exact.len() != n {
            self.push(
                whole,
                Problem::Lengths {
                    points: d.points.len(),
                    exact: d.exact.len(),
                    on: n,
                },
            );
            return None;
        }
        if n == 0 {
            self.push(whole, Problem::EmptyLoop);
            return None;
        }
        self.checked.loops += 1;
        self.checked.points += n;
        let mut pts = Vec::with_capacity(n);
        let mut placed = true;
        for k in 0..n {
            let on = d.on[k];
            let here = self.at(family, Some(item), sub, Some(k));
            let truth = match self.element_point(on) {
                Ok(p) => Some(p),
                Err(problem) => {
                    self.push(here.clone(), problem);
                    None
                }
            };
            // The canonical text of the true point is the only right text:
            // compare texts first, parse only what differs.
            let same_text = truth.as_ref().is_some_and(|t| {
                is_text_of(&d.exact[k][0], &t.x) && is_text_of(&d.exact[k][1], &t.y)
            });
            let claimed = if same_text {
                truth.clone()
            } else {
                let x = self.exact(here.clone(), "exact x", &d.exact[k][0]);
                let y = self.exact(here.clone(), "exact y", &d.exact[k][1]);
                match (x, y) {
                    (Some(x), Some(y)) => Some(Point2 { x, y }),
                    _ => None,
                }
            };
            if let (Some(t), Some(c)) = (&truth, &claimed) {
                if t != c {
                    self.push(
                        here.clone(),
                        Problem::WrongPoint {
                            on,
                            claimed: xy_text(c),
                            actual: xy_text(t),
                        },
                    );
                }
            }
            if let Some(r) = truth.as_ref().or(claimed.as_ref()) {
                self.nearest(here.clone(), "rounded x", &d.points[k][0], &r.x);
                self.nearest(here, "rounded y", &d.points[k][1], &r.y);
            }
            match claimed.or(truth) {
                Some(p) => pts.push(Pt::new(on, p)),
                None => placed = false,
            }
        }
        let role = match d.role.as_str() {
            "outer" => Some(Role::Outer),
            "hole" => Some(Role::Hole),
            other => {
                self.push(whole.clone(), Problem::BadRole(other.to_owned()));
                None
            }
        };
        if !placed {
            return None;
        }
        let exact: Vec<Point2> = pts.iter().map(|p| p.p.clone()).collect();
        // The claimed area is taken when it is written in lowest terms and
        // equals the exact sum (one cross-multiplication); else the sum is
        // reduced and the claim reported against it.
        let sum = AreaSum::of([&exact[..]]);
        let in_lowest_terms =
            canonical_rational(&d.area_exact).filter(|r| r.numer().gcd(r.denom()).is_one());
        let area = match in_lowest_terms {
            // Exact and canonical.
            Some(r) if sum.is(&r) => r,
            _ => {
                let area = sum.reduce();
                let claimed = self.exact(whole.clone(), "area_exact", &d.area_exact);
                if let Some(claimed) = claimed.filter(|c| *c != area) {
                    self.push(
                        whole.clone(),
                        Problem::WrongArea {
                            claimed: rat_to_string(&claimed),
                            actual: rat_to_string(&area),
                        },
                    );
                }
                area
            }
        };
        self.nearest(whole, "rounded area", &d.area, &area);
        Some(Geom {
            item,
            sub,
            pts,
            area,
            role,
            role_text: d.role.clone(),
            parent: d.parent,
        })
    }

    /// The pieces of a family's loops against the pieces the mesh gives:
    /// each used exactly once, in its direction. (A loop of one point, a
    /// collapsed limit around an extremum, has no piece.)
    fn check_pieces(
        &mut self,
        family: Family,
        region: Option<usize>,
        docs: &[LoopDoc],
        mut expected: Pieces,
    ) {
        let mut reversed: HashSet<(On, On)> = HashSet::new();
        for (i, d) in docs.iter().enumerate() {
            let (item, sub) = match region {
                Some(r) => (r, Some(i)),
                None => (i, None),
            };
            let n = if d.on.len() == 1 { 0 } else { d.on.len() };
            let mut found = Vec::new();
            for k in 0..n {
                let (from, to) = (d.on[k], d.on[(k + 1) % n]);
                let problem = if let Some(c) = expected.get_mut(&(from, to)) {
                    if *c > 0 {
                        *c -= 1;
                        continue;
                    }
                    Problem::Repeated { from, to }
                } else if expected.contains_key(&(to, from)) {
                    reversed.insert((to, from));
                    Problem::Reversed { from, to }
                } else {
                    Problem::NotAPiece { from, to }
                };
                found.push((k, problem));
            }
            let all_reversed = n > 0
                && found.len() == n
                && found
                    .iter()
                    .all(|(_, p)| matches!(p, Problem::Reversed { .. }));
            if all_reversed {
                let place = self.at(family, Some(item), sub, None);
                self.push(place, Problem::LoopReversed { segments: n });
                continue;
            }
            for (k, problem) in found {
                let here = self.at(family, Some(item), sub, Some(k));
                self.push(here, problem);
            }
        }
        let mut left: Vec<(On, On)> = expected
            .into_iter()
            .flat_map(|(k, c)| std::iter::repeat_n(k, c as usize))
            .collect();
        left.sort();
        for (from, to) in left {
            if reversed.contains(&(from, to)) {
                continue; // reported as the reversed segment
            }
            let place = self.at(family, region, None, None);
            self.push(place, Problem::Missing { from, to });
        }
    }

    /// Orientation, crossings and nesting of one family.
    fn check_family(
        &mut self,
        family: Family,
        count: usize,
        geoms: Vec<Geom>,
        orientation: Orientation,
    ) {
        for g in &geoms {
            let Some(role) = g.role else { continue };
            let sign = Sign::of_rat(&g.area);
            let (want, facing) = match orientation {
                Orientation::Contour => (Some(role == Role::Outer), None),
                Orientation::Region(Facing::Up) => (Some(role == Role::Outer), Some("up")),
                Orientation::Region(Facing::Down) => (Some(role == Role::Hole), Some("down")),
                Orientation::Region(Facing::Flat) => (None, Some("flat")),
            };
            let ok = match want {
                Some(true) => sign == Sign::Positive,
                Some(false) => sign == Sign::Negative,
                None => sign == Sign::Zero,
            };
            if !ok {
                let place = self.at(family, Some(g.item), g.sub, None);
                self.push(
                    place,
                    Problem::Orientation {
                        role: role.name().to_owned(),
                        area: rat_to_string(&g.area),
                        facing,
                    },
                );
            }
        }
        let pts: Vec<Vec<Pt>> = geoms.iter().map(|g| g.pts.clone()).collect();
        let loops = Loops::new(&pts);
        self.check_contacts(family, &geoms, &loops, false);
        if matches!(orientation, Orientation::Region(Facing::Flat)) {
            return; // zero-area loops have no inside
        }
        let index: Vec<usize> = geoms.iter().map(|g| g.sub.unwrap_or(g.item)).collect();
        let containers = loops.containers();
        let depth: Vec<Option<usize>> = containers
            .iter()
            .map(|c| c.as_ref().map(Vec::len))
            .collect();
        for (l, g) in geoms.iter().enumerate() {
            let place = self.at(family, Some(g.item), g.sub, None);
            let Some(inside) = &containers[l] else {
                self.push(place, Problem::NoInteriorSegment);
                continue;
            };
            self.check_nesting(place, g, count, inside, &depth, &index);
        }
    }

    /// Role and parent of one loop against its containers (indices into
    /// the family's geoms; `depth` of each, `index` into the document).
    fn check_nesting(
        &mut self,
        place: Place,
        g: &Geom,
        count: usize,
        inside: &[usize],
        depth: &[Option<usize>],
        index: &[usize],
    ) {
        let d = inside.len();
        let expected = if d % 2 == 0 { Role::Outer } else { Role::Hole };
        if g.role.is_some_and(|r| r != expected) {
            self.push(
                place.clone(),
                Problem::WrongRole {
                    claimed: g.role_text.clone(),
                    expected: expected.name(),
                    depth: d,
                },
            );
        }
        // The parent is the deepest container (containers nest).
        let deepest = inside.iter().filter_map(|&j| depth[j]).max();
        let candidates: Vec<usize> = inside
            .iter()
            .filter(|&&j| depth[j] == deepest)
            .map(|&j| index[j])
            .collect();
        let ok = match g.parent {
            None => candidates.is_empty(),
            Some(p) => candidates.iter().any(|&c| c as u64 == p),
        };
        if !ok || g.parent.is_some_and(|p| p >= count as u64) {
            self.push(
                place,
                Problem::WrongParent {
                    claimed: g.parent,
                    expected: candidates.first().copied(),
                },
            );
        }
    }

    /// Crossings, touches and overlaps within a family (`both_ways`: two
    /// segments may run back along each other).
    fn check_contacts(&mut self, family: Family, geoms: &[Geom], loops: &Loops, both_ways: bool) {
        let index: Vec<usize> = geoms.iter().map(|g| g.sub.unwrap_or(g.item)).collect();
        let remap = |p: Problem| -> Problem {
            let fix = |o: Other| Other {
                item: index[o.item],
                point: o.point,
            };
            match p {
                Problem::Crossing(o) => Problem::Crossing(fix(o)),
                Problem::Touching(o) => Problem::Touching(fix(o)),
                Problem::Overlap(o) => Problem::Overlap(fix(o)),
                Problem::CrossingAt { at, other } => Problem::CrossingAt {
                    at,
                    other: fix(other),
                },
                p => p,
            }
        };
        let mut found = loops.contacts(both_ways);
        found.extend(loops.crossings_at_elements());
        for (l, k, p) in found {
            let g = &geoms[l];
            let place = self.at(family, Some(g.item), g.sub, Some(k));
            self.push(place, remap(p));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::exact::rational::{rat_from_f64, Rat};
    use crate::exact::{Level, Point2};

    #[test]
    fn canonical_text_is_recognized_exactly() {
        use super::is_text_of;
        let r = |p: i64, q: i64| Rat::new(p.into(), q.into());
        assert!(is_text_of("3/5", &r(3, 5)));
        assert!(is_text_of("-3/5", &r(-3, 5)));
        assert!(is_text_of("7", &r(7, 1)));
        assert!(is_text_of("0", &r(0, 1)));
        for bad in [
            "6/10", "+3/5", "03/5", "3/05", "-0", "7/1", "3/-5", "3/5 ", "0.6", "", "/5",
        ] {
            assert!(
                !is_text_of(bad, &r(3, 5)) && !is_text_of(bad, &r(7, 1)),
                "{bad}"
            );
        }
        assert!(!is_text_of("-0", &r(0, 1)));
    }

    /// The verifier takes edge crossings from `Point2::on_edge`; this pins
    /// that function to SPEC section 2's formula
    /// `p = (a (h(b) - c) + b (c - h(a))) / (h(b) - h(a))`, written out here
    /// independently, on awkward doubles and levels.
    #[test]
    fn edge_crossings_follow_the_spec_formula() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for _ in 0..500 {
            let mut coord = || (next() % 2001) as f64 / 7.0 - 140.0;
            let a = [coord(), coord(), coord()];
            let b = [coord(), coord(), coord()];
            if a[2] == b[2] {
                continue;
            }
            let c = Rat::new(
                ((next() % 4001) as i64 - 2000).into(),
                ((next() % 97) + 1).into(),
            );
            let (ha, hb) = (rat_from_f64(a[2]), rat_from_f64(b[2]));
            let spec = |pa: f64, pb: f64| {
                (rat_from_f64(pa) * (&hb - &c) + rat_from_f64(pb) * (&c - &ha)) / (&hb - &ha)
            };
            let want = Point2 {
                x: spec(a[0], b[0]),
                y: spec(a[1], b[1]),
            };
            assert_eq!(Point2::on_edge(a, b, &Level::new(c.clone())), want);
        }
    }
}
