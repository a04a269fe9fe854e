//! The pair tests against hand-derived cases and against a plain
//! big-rational reference that shares nothing with them: the meeting set of
//! two triangles is the image of a polytope `{lambda, mu >= 0, sum lambda =
//! sum mu = 1, sum lambda_i p_i = sum mu_j q_j}`, whose vertices (basic
//! solutions, found by solving every square subsystem exactly) span it;
//! the pair is improper exactly when one of those points lies outside the
//! hull of the shared vertices.

use super::narrow::{edge_faces, faces_meet, vertex_faces_overlap, EdgeOverlap, P};
use super::self_intersections;
use crate::datasets::slab::Slab;
use crate::exact::orient_filter::Filter;
use crate::exact::predicates::{is_degenerate_triangle, orient3d, Sign};
use crate::exact::rational::{rat_from_f64, Rat};
use crate::ids::{FaceId, VertexId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use num_traits::{One, Signed, Zero};
use proptest::prelude::*;

type Q3 = [Rat; 3];

/// The pair tests take points of any range here: filters check each call.
const F: Filter = Filter::CHECKING;

fn q3(p: P) -> Q3 {
    p.map(rat_from_f64)
}

/// Row-reduces `m` (rows of `cols + 1` entries, the last one the right-hand
/// side) in place; the pivot columns, or `None` when inconsistent.
fn reduce(m: &mut Vec<Vec<Rat>>, cols: usize) -> Option<Vec<usize>> {
    let mut pivots = Vec::new();
    let mut r = 0;
    for c in 0..cols {
        let Some(p) = (r..m.len()).find(|&i| !m[i][c].is_zero()) else {
            continue;
        };
        m.swap(r, p);
        let inv = Rat::one() / &m[r][c];
        for x in m[r].iter_mut() {
            *x = &*x * &inv;
        }
        let pivot_row = m[r].clone();
        for (i, row) in m.iter_mut().enumerate() {
            if i != r && !row[c].is_zero() {
                let f = row[c].clone();
                for (x, p) in row.iter_mut().zip(&pivot_row) {
                    *x = &*x - &f * p;
                }
            }
        }
        pivots.push(c);
        r += 1;
    }
    if m[r..].iter().any(|row| !row[cols].is_zero()) {
        return None;
    }
    m.truncate(r);
    Some(pivots)
}

/// The points of `p` meeting `q` at the vertices of the polytope above.
fn meeting_vertices(p: [P; 3], q: [P; 3]) -> Vec<Q3> {
    let (pq, qq) = (p.map(q3), q.map(q3));
    let mut m: Vec<Vec<Rat>> = Vec::new();
    for k in 0..3 {
        let mut row: Vec<Rat> = (0..3).map(|i| pq[i][k].clone()).collect();
        row.extend((0..3).map(|j| -qq[j][k].clone()));
        row.push(Rat::zero());
        m.push(row);
    }
    let ones = |first: bool| -> Vec<Rat> {
        let mut row: Vec<Rat> = (0..6)
            .map(|i| {
                if (i < 3) == first {
                    Rat::one()
                } else {
                    Rat::zero()
                }
            })
            .collect();
        row.push(Rat::one());
        row
    };
    m.push(ones(true));
    m.push(ones(false));
    let Some(pivots) = reduce(&mut m, 6) else {
        return Vec::new();
    };
    let r = pivots.len();
    let mut out = Vec::new();
    // Every choice of r basic columns: the square system on them.
    for mask in 0u32..64 {
        if mask.count_ones() as usize != r {
            continue;
        }
        let basis: Vec<usize> = (0..6).filter(|&c| mask >> c & 1 == 1).collect();
        let mut sub: Vec<Vec<Rat>> = m
            .iter()
            .map(|row| {
                let mut s: Vec<Rat> = basis.iter().map(|&c| row[c].clone()).collect();
                s.push(row[6].clone());
                s
            })
            .collect();
        let Some(piv) = reduce(&mut sub, r) else {
            continue;
        };
        if piv.len() < r {
            continue; // singular
        }
        let mut x = [
            Rat::zero(),
            Rat::zero(),
            Rat::zero(),
            Rat::zero(),
            Rat::zero(),
            Rat::zero(),
        ];
        for (row, &c) in sub.iter().zip(&basis) {
            x[c] = row[r].clone();
        }
        if x.iter().any(|v| v.is_negative()) {
            continue;
        }
        let point: Q3 = std::array::from_fn(|k| {
            (0..3)
                .map(|i| &x[i] * &pq[i][k])
                .fold(Rat::zero(), |s, t| s + t)
        });
        out.push(point);
    }
    out
}

/// `x` on the closed segment `ab` (a point when `a = b`), exactly.
fn on_closed_segment(a: &Q3, b: &Q3, x: &Q3) -> bool {
    let d: Vec<Rat> = (0..3).map(|k| &b[k] - &a[k]).collect();
    let e: Vec<Rat> = (0..3).map(|k| &x[k] - &a[k]).collect();
    if d.iter().all(Zero::is_zero) {
        return e.iter().all(Zero::is_zero);
    }
    // e = t d with 0 <= t <= 1.
    let k = (0..3).find(|&k| !d[k].is_zero()).unwrap();
    let t = &e[k] / &d[k];
    (0..3).all(|i| e[i] == &t * &d[i]) && !t.is_negative() && t <= Rat::one()
}

/// The reference: do the faces meet outside the hull of `shared`?
fn improper_reference(p: [P; 3], q: [P; 3], shared: &[P]) -> bool {
    let pts = meeting_vertices(p, q);
    match shared {
        [] => !pts.is_empty(),
        [v] => pts.iter().any(|x| *x != q3(*v)),
        [a, b] => pts.iter().any(|x| !on_closed_segment(&q3(*a), &q3(*b), x)),
        _ => unreachable!(),
    }
}

// ---------------------------------------------------------------------------
// Hand-derived cases.

const O: P = [0.0, 0.0, 0.0];
const X: P = [1.0, 0.0, 0.0];
const Y: P = [0.0, 1.0, 0.0];

fn shift(t: [P; 3], d: P) -> [P; 3] {
    t.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]])
}

#[test]
fn separate_triangles_meet_exactly_when_their_point_sets_do() {
    let t = [O, X, Y];
    // Parallel planes: apart.
    assert!(!faces_meet(F, t, shift(t, [0.0, 0.0, 1.0])));
    // A vertical triangle standing on t's hypotenuse midpoint: touches.
    let stand = [[0.5, 0.5, 0.0], [0.5, 0.5, 1.0], [2.0, 2.0, 1.0]];
    assert!(faces_meet(F, t, stand));
    // The same lifted by the smallest step: apart.
    let lifted = stand.map(|p| [p[0], p[1], p[2] + f64::EPSILON]);
    assert!(!faces_meet(F, t, lifted));
    // Piercing t's interior.
    assert!(faces_meet(
        F,
        t,
        [[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [3.0, 3.0, 0.5]]
    ));
    // Crossing t's plane beside it (x + y > 1 everywhere on the segment).
    assert!(!faces_meet(
        F,
        t,
        [[0.6, 0.6, -1.0], [0.6, 0.6, 1.0], [3.0, 3.0, 0.5]]
    ));
    // Coplanar: overlapping, sharing only an edge's point set, corner to
    // corner, and apart by the smallest step.
    assert!(faces_meet(F, t, shift(t, [0.5, 0.0, 0.0])));
    assert!(faces_meet(F, t, [X, Y, [1.0, 1.0, 0.0]]));
    assert!(faces_meet(F, t, shift(t, [1.0, 0.0, 0.0])));
    assert!(!faces_meet(F, t, shift(t, [1.0f64.next_up(), 0.0, 0.0])));
    // Zero-area faces: a segment through t, a segment beside it, a point
    // on its edge, a point just off it.
    assert!(faces_meet(
        F,
        t,
        [[0.25, 0.25, -1.0], [0.25, 0.25, 0.0], [0.25, 0.25, 1.0]]
    ));
    assert!(!faces_meet(
        F,
        t,
        [[2.0, 2.0, -1.0], [2.0, 2.0, 0.0], [2.0, 2.0, 1.0]]
    ));
    assert!(faces_meet(F, t, [[0.5, 0.5, 0.0]; 3]));
    assert!(!faces_meet(F, t, [[0.5, 0.5f64.next_up(), 0.0]; 3]));
    // Two collinear segments, overlapping and apart.
    let seg = |a: f64, b: f64| [[a, 7.0, 7.0], [b, 7.0, 7.0], [(a + b) / 2.0, 7.0, 7.0]];
    assert!(faces_meet(F, seg(0.0, 2.0), seg(2.0, 3.0)));
    assert!(!faces_meet(F, seg(0.0, 2.0), seg(2.5, 3.0)));
}

#[test]
fn faces_sharing_a_vertex_overlap_only_beyond_it() {
    // Fan around O in the plane z = 0.
    let (a, b) = (X, [1.0, 1.0, 0.0]);
    // A neighbour wedge on the other side: only O in common.
    assert!(!vertex_faces_overlap(F, O, a, b, Y, [-1.0, 1.0, 0.0]));
    // Wedges sharing the ray through b (a segment in common).
    assert!(vertex_faces_overlap(F, O, a, b, [2.0, 2.0, 0.0], Y));
    // Overlapping wedges.
    assert!(vertex_faces_overlap(F, O, a, b, [2.0, 1.0, 0.0], Y));
    // Out of the plane: a face standing up on the ray through (1, 1/2)
    // lies over the first wedge and crosses it only along that ray.
    assert!(vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [2.0, 1.0, 1.0],
        [2.0, 1.0, -1.0]
    ));
    // The same standing face over the ray through (1, 2): outside.
    assert!(!vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [1.0, 2.0, 1.0],
        [1.0, 2.0, -1.0]
    ));
    // A face whose opposite edge pierces the first face's interior.
    assert!(vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [0.5, 0.2, -1.0],
        [0.5, 0.2, 1.0]
    ));
    // Its edge crosses the plane beyond the edge ab, but the ray from O to
    // that crossing (towards (1.5, 0.2)) runs inside the first wedge.
    assert!(vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [1.5, 0.2, -1.0],
        [1.5, 0.2, 1.0]
    ));
    // Crossing towards (0.2, 1.5): outside the wedge.
    assert!(!vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [0.2, 1.5, -1.0],
        [0.2, 1.5, 1.0]
    ));
    // Zero-area faces: a segment from O along the first face, and away.
    assert!(vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [0.5, 0.25, 0.0],
        [1.0, 0.5, 0.0]
    ));
    assert!(!vertex_faces_overlap(
        F,
        O,
        a,
        b,
        [-0.5, -0.25, 0.0],
        [-1.0, -0.5, 0.0]
    ));
    // A zero-area face with both other vertices at O's position: a point.
    assert!(!vertex_faces_overlap(F, O, a, b, O, O));
    // A vertex at another vertex's position with its own id.
    assert!(vertex_faces_overlap(F, O, a, b, a, [0.0, -1.0, 0.0]));
}

#[test]
fn faces_on_an_edge_fold_or_run_on_along_it() {
    let (a, b) = (O, X);
    // Flat neighbours (one plane, opposite sides), a fold, a crease.
    assert_eq!(
        edge_faces(F, a, b, Y, [0.5, -1.0, 0.0]),
        (EdgeOverlap::Proper, true)
    );
    assert_eq!(
        edge_faces(F, a, b, Y, [0.5, 1.0, 0.0]),
        (EdgeOverlap::Fold, false)
    );
    assert_eq!(
        edge_faces(F, a, b, Y, [0.5, 1.0, 1.0]),
        (EdgeOverlap::Proper, false)
    );
    // In the oblique plane z = y: flat neighbours, then a fold.
    let (c, d) = ([0.0, 1.0, 1.0], [2.0, -1.0, -1.0]);
    assert_eq!(edge_faces(F, a, b, c, d), (EdgeOverlap::Proper, true));
    let d = [2.0, 1.0, 1.0];
    assert_eq!(edge_faces(F, a, b, c, d), (EdgeOverlap::Fold, false));
    // Zero-area faces on the line: running on past the same end, past
    // different ends, one inside the edge.
    let on = |x: f64| [x, 0.0, 0.0];
    assert_eq!(
        edge_faces(F, a, b, on(2.0), on(3.0)).0,
        EdgeOverlap::Collinear
    );
    assert_eq!(
        edge_faces(F, a, b, on(-2.0), on(-1.0)).0,
        EdgeOverlap::Collinear
    );
    assert_eq!(
        edge_faces(F, a, b, on(2.0), on(-1.0)).0,
        EdgeOverlap::Proper
    );
    assert_eq!(edge_faces(F, a, b, on(0.5), on(2.0)).0, EdgeOverlap::Proper);
    // One zero-area face past the end, a proper one: only the edge.
    assert_eq!(edge_faces(F, a, b, on(2.0), Y).0, EdgeOverlap::Proper);
}

// ---------------------------------------------------------------------------
// Against the reference.

/// How a small integer becomes a coordinate: `(k + offset 2^20) 2^e`
/// (exact), so ties stay ties at any scale and offset.
#[derive(Clone, Copy, Debug)]
struct CoordSet {
    e: i32,
    offset: i64,
}

impl CoordSet {
    fn set(&self, k: i8) -> f64 {
        (f64::from(k) + (self.offset << 20) as f64) * 2f64.powi(self.e)
    }
}

/// Plain small integers, or scaled and shifted by powers of two.
fn coord_set() -> impl Strategy<Value = CoordSet> {
    prop_oneof![
        Just(CoordSet { e: 0, offset: 0 }),
        (-60i32..60, -8i64..8).prop_map(|(e, offset)| CoordSet { e, offset }),
    ]
}

fn point() -> impl Strategy<Value = [i8; 3]> {
    [0i8..4, 0i8..4, 0i8..4]
}

fn f32_point() -> impl Strategy<Value = P> {
    proptest::array::uniform3(any::<f32>().prop_filter("finite", |x| x.is_finite()))
        .prop_map(|p| p.map(f64::from))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1500))]

    #[test]
    fn separate_faces_agree_with_the_reference(
        set in coord_set(),
        pts in proptest::array::uniform6(point()),
    ) {
        let p: Vec<P> = pts.iter().map(|c| c.map(|k| set.set(k))).collect();
        let (t1, t2) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        prop_assert_eq!(faces_meet(F, t1, t2), improper_reference(t1, t2, &[]), "{:?} {:?}", t1, t2);
        prop_assert_eq!(faces_meet(F, t2, t1), faces_meet(F, t1, t2));
    }

    #[test]
    fn faces_sharing_a_vertex_agree_with_the_reference(
        set in coord_set(),
        pts in proptest::array::uniform5(point()),
    ) {
        let p: Vec<P> = pts.iter().map(|c| c.map(|k| set.set(k))).collect();
        let (v, a, b, c, d) = (p[0], p[1], p[2], p[3], p[4]);
        let got = vertex_faces_overlap(F, v, a, b, c, d);
        prop_assert_eq!(got, improper_reference([v, a, b], [v, c, d], &[v]), "{:?}", p);
        prop_assert_eq!(vertex_faces_overlap(F, v, c, d, a, b), got);
        prop_assert_eq!(vertex_faces_overlap(F, v, b, a, d, c), got);
    }

    #[test]
    fn faces_sharing_an_edge_agree_with_the_reference(
        set in coord_set(),
        pts in proptest::array::uniform4(point()),
    ) {
        let p: Vec<P> = pts.iter().map(|c| c.map(|k| set.set(k))).collect();
        let (a, b, c, d) = (p[0], p[1], p[2], p[3]);
        let got = edge_faces(F, a, b, c, d);
        prop_assert_eq!(
            got.0 != EdgeOverlap::Proper,
            improper_reference([a, b, c], [b, a, d], &[a, b]),
            "{:?}", p
        );
        // Flat neighbours: proper, both of non-zero area, in one plane.
        let flat = got.0 == EdgeOverlap::Proper
            && !is_degenerate_triangle(a, b, c)
            && !is_degenerate_triangle(b, a, d)
            && orient3d(a, b, c, d) == Sign::Zero;
        prop_assert_eq!(got.1, flat, "{:?}", p);
        prop_assert_eq!(edge_faces(F, b, a, d, c), got);
    }

}

proptest! {
    // Rationals with 2^149 denominators: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn f32_faces_agree_with_the_reference(
        p in proptest::array::uniform6(f32_point()),
    ) {
        let (t1, t2) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        prop_assert_eq!(faces_meet(F, t1, t2), improper_reference(t1, t2, &[]));
        let got = vertex_faces_overlap(F, p[0], p[1], p[2], p[3], p[4]);
        prop_assert_eq!(got, improper_reference([p[0], p[1], p[2]], [p[0], p[3], p[4]], &[p[0]]));
    }
}

// ---------------------------------------------------------------------------
// The whole search against every pair.

/// Every improper pair, by testing all pairs of faces.
pub(super) fn all_pairs(mesh: &Mesh) -> Vec<(FaceId, FaceId)> {
    let mut out = Vec::new();
    let pos = |v: VertexId| mesh.pos(v);
    for i in 0..mesh.num_faces() {
        for j in i + 1..mesh.num_faces() {
            let (s, t) = (mesh.faces[i], mesh.faces[j]);
            let shared: Vec<usize> = (0..3).filter(|&k| t.contains(&s[k])).collect();
            let improper = match shared[..] {
                [] => faces_meet(F, s.map(pos), t.map(pos)),
                [k] => {
                    // Both faces rotated to start at the shared vertex.
                    let l = (0..3).find(|&l| t[l] == s[k]).unwrap();
                    vertex_faces_overlap(
                        F,
                        pos(s[k]),
                        pos(s[(k + 1) % 3]),
                        pos(s[(k + 2) % 3]),
                        pos(t[(l + 1) % 3]),
                        pos(t[(l + 2) % 3]),
                    )
                }
                [k, m] => {
                    // s runs a -> b along the edge; t runs b -> a.
                    let (a, b) = if (k + 1) % 3 == m {
                        (s[k], s[m])
                    } else {
                        (s[m], s[k])
                    };
                    let c = s.iter().copied().find(|&v| v != a && v != b).unwrap();
                    let d = t.iter().copied().find(|&v| v != a && v != b).unwrap();
                    edge_faces(F, pos(a), pos(b), pos(c), pos(d)).0 != EdgeOverlap::Proper
                }
                _ => unreachable!("duplicate faces"),
            };
            if improper {
                out.push((FaceId::from_idx(i), FaceId::from_idx(j)));
            }
        }
    }
    out
}

/// A random slab with small integer coordinates.
fn slab() -> impl Strategy<Value = Slab> {
    (1usize..=4, 1usize..=4).prop_flat_map(|(nx, ny)| {
        let n = (nx + 1) * (ny + 1);
        (
            proptest::collection::vec(-2i32..=2, n),
            proptest::collection::vec(1i32..=3, n),
            proptest::collection::vec(any::<bool>(), nx * ny),
            0u8..3,
        )
            .prop_map(move |(bot, thick, diag, rot)| Slab {
                nx,
                ny,
                bot,
                thick,
                diag,
                rot,
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    /// Two random slabs, the second moved by a small offset (often
    /// overlapping, touching, or apart): the fans, the tree and the edge
    /// table find exactly the pairs that testing every pair finds.
    #[test]
    fn the_search_finds_what_testing_every_pair_finds(
        a in slab(),
        b in slab(),
        d in proptest::array::uniform3(-8i32..8),
    ) {
        let (ma, mb) = (a.mesh(), b.mesh());
        let n = ma.positions.len() as u32;
        let mut m = ma.clone();
        m.positions.extend(mb.positions.iter().map(|p| {
            [p[0] + f64::from(d[0]) / 2.0, p[1] + f64::from(d[1]) / 2.0, p[2] + f64::from(d[2]) / 2.0]
        }));
        m.faces.extend(mb.faces.iter().map(|t| t.map(|v| VertexId(v.0 + n))));
        let (topo, issues) = Topology::build(&m);
        prop_assert!(issues.is_empty());
        prop_assert_eq!(self_intersections(&m, &topo), all_pairs(&m));
        prop_assert!(self_intersections(&ma, &Topology::build(&ma).0).is_empty());
    }
}

/// The rows of the rotation by `angle` about `axis` (rounded).
pub(super) fn rotation(angle: f64, axis: [f64; 3]) -> [[f64; 3]; 3] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|c| c / n);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Two flat plates of long thin faces, turned off the axes together (a
    /// plate exported in its assembly's frame, rounded), the second moved
    /// by a small step (into the first, or apart across its thickness)
    /// and then, often, one of its corners put exactly on a corner of the
    /// first (touching it there, when apart) or at the rounded midpoint of
    /// one of its edges (on it, or a rounding off it):
    /// the search, whose volumes are built along the plates' own axes (a
    /// turned frame), finds exactly the pairs that testing every pair
    /// finds.
    #[test]
    fn turned_plates_agree_with_every_pair(
        (nx, ny, mx, my) in (1usize..=5, 1usize..=4, 1usize..=4, 1usize..=3),
        diag in proptest::collection::vec(any::<bool>(), 20),
        stretch in 2u32..12,
        angle in 0.2f64..1.4,
        axis in proptest::array::uniform3(1u8..9),
        step in (-3i32..=3, -3i32..=3, -8i32..=8).prop_map(|(x, y, z)| [x, y, z]),
        touch in 0u8..3,
        (which, corner) in (any::<u16>(), any::<u16>()),
    ) {
        let plate = |nx: usize, ny: usize| {
            let n = (nx + 1) * (ny + 1);
            Slab { nx, ny, bot: vec![0; n], thick: vec![1; n], diag: diag[..nx * ny].to_vec(), rot: 0 }
                .mesh()
        };
        let r = rotation(angle, axis.map(f64::from));
        let turned = |p: [f64; 3], by: [i32; 3]| {
            let q = [
                (p[0] + f64::from(by[0]) / 2.0) * f64::from(stretch),
                p[1] + f64::from(by[1]) / 2.0,
                p[2] + f64::from(by[2]) / 4.0,
            ];
            r.map(|row| row[0] * q[0] + row[1] * q[1] + row[2] * q[2])
        };
        let (ma, mb) = (plate(nx, ny), plate(mx, my));
        let n = ma.positions.len();
        let mut m = ma.clone();
        m.positions = ma.positions.iter().map(|&p| turned(p, [0; 3])).collect();
        m.positions.extend(mb.positions.iter().map(|&p| turned(p, step)));
        m.faces.extend(mb.faces.iter().map(|t| t.map(|v| VertexId(v.0 + n as u32))));
        // One corner of the second plate on a corner of the first
        // (exactly), or at an edge's midpoint (rounded: the sum may not be
        // exact).
        let b = n + usize::from(which) % mb.positions.len();
        let f = ma.faces[usize::from(corner) % ma.faces.len()];
        let (p, q) = (m.pos(f[0]), m.pos(f[1]));
        match touch {
            1 => m.positions[b] = p,
            2 => m.positions[b] = std::array::from_fn(|k| (p[k] + q[k]) / 2.0),
            _ => {}
        }
        let (topo, issues) = Topology::build(&m);
        prop_assert!(issues.is_empty());
        prop_assert!(super::bvh::Bvh::build(&m, &m.faces, None, false).is_turned());
        prop_assert_eq!(self_intersections(&m, &topo), all_pairs(&m));
    }
}
