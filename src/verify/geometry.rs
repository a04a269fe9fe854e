//! Input: one family of closed loops (S_O, L-, L+, or the dF loops of one
//! region) with exact points and the mesh element of each point. Output:
//! every pair of segments that cross, touch away from a shared element or
//! overlap; every pair of passes through a shared element that cross there;
//! and each loop's exact nesting (the loops containing it).
//!
//! Exact throughout: orientations and comparisons of rationals. Rounded
//! coordinates only feed a uniform grid, with boxes widened by one ulp on
//! each side (a rational rounded to nearest lies within one ulp of its
//! double, and rounding is monotone), so the grid never drops a candidate
//! pair; the cost stays near-linear for the loops of a big layer.

use super::doc::On;
use super::report::{Other, Problem};
use crate::exact::{Point2, Rat, Sign};
use num_bigint::BigInt;
use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};

/// A loop point: its element, its exact point, and that point rounded.
#[derive(Clone, Debug)]
pub(super) struct Pt {
    /// The element it claims.
    pub on: On,
    /// Exact point.
    pub p: Point2,
    /// Nearest doubles.
    pub f: [f64; 2],
}

impl Pt {
    /// A point with its rounding.
    pub(super) fn new(on: On, p: Point2) -> Pt {
        Pt {
            on,
            f: p.to_f64(),
            p,
        }
    }
}

/// An interval of doubles containing an exact value.
#[derive(Clone, Copy)]
struct Iv(f64, f64);

impl Iv {
    /// The nearest double of a value, widened by one ulp each way: the
    /// value lies inside.
    fn around(f: f64) -> Iv {
        Iv(f.next_down(), f.next_up())
    }

    /// Outward rounding: each result bound moved one more ulp out.
    fn sub(self, o: Iv) -> Iv {
        Iv((self.0 - o.1).next_down(), (self.1 - o.0).next_up())
    }

    fn mul(self, o: Iv) -> Iv {
        let p = [self.0 * o.0, self.0 * o.1, self.1 * o.0, self.1 * o.1];
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Iv(lo.next_down(), hi.next_up())
    }

    /// The sign, when every value in the interval has it (NaN and
    /// infinite bounds decide nothing).
    fn sign(self) -> Option<Sign> {
        if !(self.0.is_finite() && self.1.is_finite()) {
            None
        } else if self.0 > 0.0 {
            Some(Sign::Positive)
        } else if self.1 < 0.0 {
            Some(Sign::Negative)
        } else {
            None
        }
    }
}

/// The exact orientation of `(a, b, c)`: an interval filter on the rounded
/// coordinates, the exact rational determinant when it cannot decide.
pub(super) fn orient(a: &Pt, b: &Pt, c: &Pt) -> Sign {
    let same = |p: &Pt, q: &Pt| p.f == q.f && p.p == q.p;
    if same(c, a) || same(c, b) || same(a, b) {
        return Sign::Zero; // a repeated point: adjacent segments share one
    }
    let iv = |p: &Pt, k: usize| Iv::around(p.f[k]);
    let det = iv(b, 0)
        .sub(iv(a, 0))
        .mul(iv(c, 1).sub(iv(a, 1)))
        .sub(iv(b, 1).sub(iv(a, 1)).mul(iv(c, 0).sub(iv(a, 0))));
    det.sign().unwrap_or_else(|| orient_exact(&a.p, &b.p, &c.p))
}

/// The exact sign of the orientation determinant of three rational
/// points, on integers: every difference is brought to a common positive
/// denominator without reducing (no gcd), and the two products are compared.
pub(super) fn orient_exact(a: &Point2, b: &Point2, c: &Point2) -> Sign {
    let diff = |p: &Rat, q: &Rat| -> (BigInt, BigInt) {
        if p.denom() == q.denom() {
            (p.numer() - q.numer(), p.denom().clone())
        } else {
            (
                p.numer() * q.denom() - q.numer() * p.denom(),
                p.denom() * q.denom(),
            )
        }
    };
    let (n1, d1) = diff(&b.x, &a.x);
    let (n2, d2) = diff(&c.y, &a.y);
    let (n3, d3) = diff(&b.y, &a.y);
    let (n4, d4) = diff(&c.x, &a.x);
    // Denominators are positive: sign(n1 n2 / (d1 d2) - n3 n4 / (d3 d4)).
    let lhs = n1 * n2 * d3 * d4;
    let rhs = n3 * n4 * d1 * d2;
    match lhs.cmp(&rhs) {
        Ordering::Greater => Sign::Positive,
        Ordering::Less => Sign::Negative,
        Ordering::Equal => Sign::Zero,
    }
}

/// A segment: loop `l`, from point `k` to the next.
#[derive(Clone, Copy)]
struct Seg {
    l: u32,
    k: u32,
    lo: [f64; 2],
    hi: [f64; 2],
}

struct Grid {
    lo: [f64; 2],
    span: [f64; 2],
    n: usize,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn cell(&self, x: f64, k: usize) -> usize {
        if self.span[k].partial_cmp(&0.0) != Some(Ordering::Greater) {
            return 0;
        }
        // Monotone in x; saturating (NaN and negatives go to 0).
        (((x - self.lo[k]) / self.span[k] * self.n as f64) as usize).min(self.n - 1)
    }

    fn range(&self, s: &Seg) -> [std::ops::RangeInclusive<usize>; 2] {
        [
            self.cell(s.lo[0], 0)..=self.cell(s.hi[0], 0),
            self.cell(s.lo[1], 1)..=self.cell(s.hi[1], 1),
        ]
    }
}

/// A family of loops with its segment grid.
pub(super) struct Family<'a> {
    loops: &'a [Vec<Pt>],
    segs: Vec<Seg>,
    grid: Grid,
}

fn widen(x: f64) -> (f64, f64) {
    (x.next_down(), x.next_up())
}

impl<'a> Family<'a> {
    /// Indexes the segments of `loops`.
    pub(super) fn new(loops: &'a [Vec<Pt>]) -> Family<'a> {
        let mut segs = Vec::new();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for (l, pts) in loops.iter().enumerate() {
            let n = pts.len();
            for k in 0..n {
                let (a, b) = (&pts[k].f, &pts[(k + 1) % n].f);
                let mut s = Seg {
                    l: l as u32,
                    k: k as u32,
                    lo: [0.0; 2],
                    hi: [0.0; 2],
                };
                for axis in 0..2 {
                    s.lo[axis] = widen(a[axis].min(b[axis])).0;
                    s.hi[axis] = widen(a[axis].max(b[axis])).1;
                    if s.lo[axis].is_finite() {
                        lo[axis] = lo[axis].min(s.lo[axis]);
                    }
                    if s.hi[axis].is_finite() {
                        hi[axis] = hi[axis].max(s.hi[axis]);
                    }
                }
                segs.push(s);
            }
        }
        let span = [hi[0] - lo[0], hi[1] - lo[1]];
        let mut n = ((segs.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        // Coarsen while long segments would register in too many cells.
        let grid = loop {
            let mut g = Grid {
                lo,
                span,
                n,
                cells: Vec::new(),
            };
            let total: usize = segs
                .iter()
                .map(|s| {
                    let [x, y] = g.range(s);
                    x.count() * y.count()
                })
                .sum();
            if n == 1 || total <= 16 * segs.len() + 4096 {
                g.cells = vec![Vec::new(); n * n];
                for (i, s) in segs.iter().enumerate() {
                    let [xs, ys] = g.range(s);
                    for cy in ys {
                        for cx in xs.clone() {
                            g.cells[cy * n + cx].push(i as u32);
                        }
                    }
                }
                break g;
            }
            n /= 2;
        };
        Family { loops, segs, grid }
    }

    fn ends(&self, s: &Seg) -> (&Pt, &Pt) {
        let pts = &self.loops[s.l as usize];
        let k = s.k as usize;
        (&pts[k], &pts[(k + 1) % pts.len()])
    }

    /// Every pair of segments that meet other than at a shared element:
    /// `(loop, point, problem)`, reported once per pair on the later
    /// segment. `both_ways` allows two segments to run exactly back along
    /// each other (L- and L+).
    pub(super) fn contacts(&self, both_ways: bool) -> Vec<(usize, usize, Problem)> {
        let mut out = Vec::new();
        let g = &self.grid;
        for (c, cell) in g.cells.iter().enumerate() {
            for (x, &i) in cell.iter().enumerate() {
                let si = &self.segs[i as usize];
                for &j in &cell[x + 1..] {
                    let sj = &self.segs[j as usize];
                    if si.hi[0] < sj.lo[0]
                        || sj.hi[0] < si.lo[0]
                        || si.hi[1] < sj.lo[1]
                        || sj.hi[1] < si.lo[1]
                    {
                        continue;
                    }
                    // Test each pair in one cell only: the one holding the
                    // lower-left corner of the boxes' intersection.
                    let cx = g.cell(si.lo[0].max(sj.lo[0]), 0);
                    let cy = g.cell(si.lo[1].max(sj.lo[1]), 1);
                    if cy * g.n + cx != c {
                        continue;
                    }
                    let (first, second) = if (si.l, si.k) < (sj.l, sj.k) {
                        (si, sj)
                    } else {
                        (sj, si)
                    };
                    if let Some(p) = self.contact(first, second, both_ways) {
                        out.push((second.l as usize, second.k as usize, p));
                    }
                }
            }
        }
        out.sort();
        out
    }

    fn contact(&self, s: &Seg, t: &Seg, both_ways: bool) -> Option<Problem> {
        let (a, b) = self.ends(s);
        let (c, d) = self.ends(t);
        if a.p == b.p || c.p == d.p {
            return None; // a zero-length segment: reported by the cover check
        }
        let other = Other {
            item: s.l as usize,
            point: s.k as usize,
        };
        let shared = [a.on, b.on].iter().any(|x| *x == c.on || *x == d.on);
        let back = (a.on == d.on && b.on == c.on) || (a.p == d.p && b.p == c.p);
        let same_side = |x: Sign, y: Sign| x != Sign::Zero && x == y;
        let (o0, o1) = (orient(a, b, c), orient(a, b, d));
        if same_side(o0, o1) {
            return None; // c and d strictly on one side of line ab
        }
        let (o2, o3) = (orient(c, d, a), orient(c, d, b));
        if same_side(o2, o3) {
            return None;
        }
        let o = [o0, o1, o2, o3];
        if o.iter().all(|&x| x == Sign::Zero) {
            // Collinear: compare the intervals along the line.
            let axis = if a.p.x != b.p.x { 0 } else { 1 };
            let t_of = |p: &Point2| if axis == 0 { p.x.clone() } else { p.y.clone() };
            let (ta, tb, tc, td) = (t_of(&a.p), t_of(&b.p), t_of(&c.p), t_of(&d.p));
            let lo = (&ta).min(&tb).max((&tc).min(&td));
            let hi = (&ta).max(&tb).min((&tc).max(&td));
            return match lo.cmp(hi) {
                Ordering::Greater => None,
                Ordering::Equal => (!shared).then_some(Problem::Touching(other)),
                Ordering::Less => (!(both_ways && back)).then_some(Problem::Overlap(other)),
            };
        }
        let proper = o.iter().all(|&x| x != Sign::Zero);
        if proper {
            Some(Problem::Crossing(other))
        } else if shared {
            None
        } else {
            Some(Problem::Touching(other))
        }
    }

    /// Passes of different loops (or of one loop twice) through one mesh
    /// element that cross there: one pass has its two neighbours on both
    /// sides of the other. Reported on the later pass.
    pub(super) fn crossings_at_elements(&self) -> Vec<(usize, usize, Problem)> {
        let mut at: HashMap<On, Vec<(usize, usize)>> = HashMap::new();
        for (l, pts) in self.loops.iter().enumerate() {
            for (k, p) in pts.iter().enumerate() {
                at.entry(p.on).or_default().push((l, k));
            }
        }
        let mut shared: Vec<(On, Vec<(usize, usize)>)> =
            at.into_iter().filter(|(_, v)| v.len() > 1).collect();
        shared.sort();
        let mut out = Vec::new();
        for (on, passes) in shared {
            // Each pass: the directions to its previous and next points.
            let mut dirs: Vec<(Point2, usize, bool)> = Vec::new();
            for (i, &(l, k)) in passes.iter().enumerate() {
                let pts = &self.loops[l];
                let n = pts.len();
                let c = &pts[k].p;
                for (prev, q) in [
                    (true, &pts[(k + n - 1) % n].p),
                    (false, &pts[(k + 1) % n].p),
                ] {
                    dirs.push((
                        Point2 {
                            x: &q.x - &c.x,
                            y: &q.y - &c.y,
                        },
                        i,
                        prev,
                    ));
                }
            }
            dirs.sort_by(|a, b| angle_cmp(&a.0, &b.0));
            let mut rank = vec![[usize::MAX; 2]; passes.len()];
            let mut r = 0;
            for w in 0..dirs.len() {
                if w > 0 && angle_cmp(&dirs[w - 1].0, &dirs[w].0) != Ordering::Equal {
                    r += 1;
                }
                let (d, i, prev) = &dirs[w];
                if d.x != Default::default() || d.y != Default::default() {
                    rank[*i][usize::from(!*prev)] = r;
                }
            }
            for j in 1..passes.len() {
                let [b1, b2] = rank[j];
                for i in 0..j {
                    let [a1, a2] = rank[i];
                    if [a1, a2, b1, b2].contains(&usize::MAX) || a1 == a2 {
                        continue;
                    }
                    if [a1, a2].contains(&b1) || [a1, a2].contains(&b2) {
                        continue; // touching along a shared direction
                    }
                    let inside = |x: usize| {
                        if a1 < a2 {
                            a1 < x && x < a2
                        } else {
                            x > a1 || x < a2
                        }
                    };
                    if inside(b1) != inside(b2) {
                        let (l, k) = passes[j];
                        let (ol, ok) = passes[i];
                        out.push((
                            l,
                            k,
                            Problem::CrossingAt {
                                at: on,
                                other: Other {
                                    item: ol,
                                    point: ok,
                                },
                            },
                        ));
                    }
                }
            }
        }
        out.sort();
        out
    }

    /// For each loop, the loops that contain it (exact crossing parity of
    /// a ray to +x from the midpoint of one of its segments that no other
    /// segment runs back along), or `None` when it has no such segment.
    pub(super) fn containers(&self) -> Vec<Option<Vec<usize>>> {
        let mut pairs: HashSet<(On, On)> = HashSet::new();
        for pts in self.loops {
            for k in 0..pts.len() {
                pairs.insert((pts[k].on, pts[(k + 1) % pts.len()].on));
            }
        }
        let half = crate::exact::Rat::new(1.into(), 2.into());
        let g = &self.grid;
        let mut stamp = vec![u32::MAX; self.segs.len()];
        let mut out = Vec::with_capacity(self.loops.len());
        for (l, pts) in self.loops.iter().enumerate() {
            let n = pts.len();
            let rep = (0..n).find_map(|k| {
                let (a, b) = (&pts[k], &pts[(k + 1) % n]);
                (a.p != b.p && !pairs.contains(&(b.on, a.on))).then(|| Point2 {
                    x: (&a.p.x + &b.p.x) * &half,
                    y: (&a.p.y + &b.p.y) * &half,
                })
            });
            let Some(r) = rep else {
                out.push(None);
                continue;
            };
            let r = Pt::new(pts[0].on, r);
            let rf = r.f;
            let row = g.cell(rf[1], 1);
            let mut parity: HashMap<u32, bool> = HashMap::new();
            for col in g.cell(rf[0], 0)..g.n {
                for &i in &g.cells[row * g.n + col] {
                    let s = &self.segs[i as usize];
                    if stamp[i as usize] == l as u32 || s.l as usize == l {
                        continue;
                    }
                    stamp[i as usize] = l as u32;
                    if s.hi[0] < rf[0].next_down() {
                        continue; // exactly left of r
                    }
                    let (p, q) = self.ends(s);
                    let p_above = above(p, &r);
                    let q_above = above(q, &r);
                    if p_above == q_above {
                        continue;
                    }
                    let o = orient(p, q, &r);
                    let right = if q_above {
                        o == Sign::Positive
                    } else {
                        o == Sign::Negative
                    };
                    if right {
                        *parity.entry(s.l).or_default() ^= true;
                    }
                }
            }
            let mut inside: Vec<usize> = parity
                .into_iter()
                .filter(|&(_, odd)| odd)
                .map(|(j, _)| j as usize)
                .collect();
            inside.sort_unstable();
            out.push(Some(inside));
        }
        out
    }
}

/// Whether `p.y > r.y`, exactly (the doubles decide when they differ:
/// rounding to nearest is monotone).
fn above(p: &Pt, r: &Pt) -> bool {
    match p.f[1].partial_cmp(&r.f[1]) {
        Some(Ordering::Greater) => true,
        Some(Ordering::Less) => false,
        _ => p.p.y > r.p.y,
    }
}

/// Counter-clockwise angular order of direction vectors, starting at +x.
fn angle_cmp(a: &Point2, b: &Point2) -> Ordering {
    let half = |d: &Point2| {
        let zero = crate::exact::Rat::default();
        !(d.y > zero || (d.y == zero && d.x > zero))
    };
    half(a).cmp(&half(b)).then_with(|| {
        let cross = &a.x * &b.y - &a.y * &b.x;
        match Sign::of_rat(&cross) {
            Sign::Positive => Ordering::Less,
            Sign::Negative => Ordering::Greater,
            Sign::Zero => Ordering::Equal,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(id: u64, x: i64, y: i64) -> Pt {
        let p = Point2 {
            x: Rat::from_integer(x.into()),
            y: Rat::from_integer(y.into()),
        };
        Pt::new(On::Vertex(id), p)
    }

    fn square(id: u64, x: i64, y: i64, s: i64) -> Vec<Pt> {
        vec![
            pt(id, x, y),
            pt(id + 1, x + s, y),
            pt(id + 2, x + s, y + s),
            pt(id + 3, x, y + s),
        ]
    }

    #[test]
    fn integer_orientation_equals_the_rational_one() {
        use crate::exact::predicates::orient2d_rat;
        let r = |p: i64, q: i64| Rat::new(p.into(), q.into());
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |m: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % (2 * m as u64 + 1)) as i64 - m
        };
        for _ in 0..2000 {
            let p = |next: &mut dyn FnMut(i64) -> i64| Point2 {
                x: r(next(50), next(6).abs() + 1),
                y: r(next(50), next(6).abs() + 1),
            };
            let (a, b) = (p(&mut next), p(&mut next));
            // c on the line ab half the time.
            let c = if next(1) == 0 {
                let t = r(next(9), 4);
                Point2 {
                    x: &a.x + (&b.x - &a.x) * &t,
                    y: &a.y + (&b.y - &a.y) * &t,
                }
            } else {
                p(&mut next)
            };
            assert_eq!(orient_exact(&a, &b, &c), orient2d_rat(&a, &b, &c));
        }
    }

    #[test]
    fn nested_squares_do_not_cross_and_nest() {
        let loops = vec![
            square(0, 0, 0, 10),
            square(10, 2, 2, 4),
            square(20, 3, 3, 1),
        ];
        let fam = Family::new(&loops);
        assert!(fam.contacts(false).is_empty());
        assert!(fam.crossings_at_elements().is_empty());
        let c = fam.containers();
        assert_eq!(c, vec![Some(vec![]), Some(vec![0]), Some(vec![0, 1])]);
    }

    #[test]
    fn crossing_and_touching_squares_are_found() {
        let loops = vec![square(0, 0, 0, 4), square(10, 2, 2, 4)];
        let c = Family::new(&loops).contacts(false);
        assert_eq!(c.len(), 2, "{c:?}");
        assert!(c.iter().all(|x| matches!(x.2, Problem::Crossing(_))));
        // Touching at a corner that is not a shared element.
        let loops = vec![square(0, 0, 0, 2), square(10, 2, 2, 2)];
        let c = Family::new(&loops).contacts(false);
        assert!(
            c.iter().any(|x| matches!(x.2, Problem::Touching(_))),
            "{c:?}"
        );
    }

    #[test]
    fn two_loops_crossing_at_a_shared_vertex_are_found() {
        // Two diamonds through the shared vertex 99 at the origin: one
        // passes left to right, the other bottom to top.
        let o = |id| pt(id, 0, 0);
        let a = vec![pt(1, -2, 0), pt(2, -1, -1), o(99), pt(3, 2, 0), pt(4, 1, 1)];
        let b = vec![pt(5, 0, -2), pt(6, 1, -1), o(99), pt(7, 0, 2), pt(8, -1, 1)];
        let loops = vec![a, b];
        let x = Family::new(&loops).crossings_at_elements();
        assert_eq!(x.len(), 1, "{x:?}");
        // Touching (a saddle's two loops): no crossing.
        let a = vec![pt(1, -2, -1), o(99), pt(2, -2, 1)];
        let b = vec![pt(3, 2, 1), o(99), pt(4, 2, -1)];
        let loops = vec![a, b];
        assert!(Family::new(&loops).crossings_at_elements().is_empty());
    }
}
