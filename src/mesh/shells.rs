//! Input: a closed, oriented, manifold mesh without self-intersections.
//! Output: the shells (connected components of its surface) whose
//! orientation disagrees with where they lie: those that do not bound the
//! material on their inner side alone (SPEC 1: faces counter-clockwise seen
//! from outside).
//!
//! Shells of such a mesh are disjoint closed surfaces, so one shell lies
//! wholly inside or wholly outside another, and the winding number of the
//! whole surface is constant off it. The faces bound a solid exactly when
//! that winding number is 0 or 1 everywhere: just outside a shell `S` it is
//! the winding number `w` of the other shells around any vertex of `S`, and
//! just inside it is `w + 1` if `S` faces outward (positive volume), `w - 1`
//! if inward. So an outward shell needs `w = 0` and an inward one (a
//! cavity) `w = 1`. Two nested outward cubes fail (the inner one has
//! `w = 1`: material counted twice), as does an inward cube standing alone.
//!
//! The winding number of a shell `T` around a point `v` off it is counted
//! along the vertical ray up from `v`, moved aside symbolically to
//! `(vx + e, vy + e^2)` for a vanishing `e > 0` (simulation of simplicity),
//! so that it meets no edge or vertex of `T`'s projection: each face whose
//! projection holds the moved point and whose plane passes above `v` counts
//! `+1` facing up, `-1` facing down. Every test is an exact orient2d,
//! orient3d or comparison of doubles.
//!
//! The faces are filed under the cells of a uniform grid in `(x, y)` (about
//! one cell per face) that their boxes cover, so each shell's ray meets only
//! the faces of its cell: the cost is about linear in the faces for meshes
//! whose shells do not stack in one column.

use crate::exact::predicates::{orient2d_xy, orient3d, Sign};
use crate::exact::volume::volume_sign_of;
use crate::ids::FaceId;
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use petgraph::unionfind::UnionFind;

/// Which way a shell faces: the sign of the exact volume it encloses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ShellFacing {
    /// Positive volume: normals point away from the region it bounds.
    Outward,
    /// Negative volume: normals point into the region it bounds.
    Inward,
    /// Zero volume.
    Flat,
}

impl std::fmt::Display for ShellFacing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ShellFacing::Outward => "outward",
            ShellFacing::Inward => "inward",
            ShellFacing::Flat => "nowhere (zero volume)",
        })
    }
}

/// A shell whose orientation disagrees with its nesting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MisnestedShell {
    /// The shell's lowest face id.
    pub face: FaceId,
    /// Which way the shell faces (the sign of its own exact volume).
    pub facing: ShellFacing,
    /// The winding number of the other shells around it.
    pub winding: i64,
}

/// The shells of a mesh (its faces joined across every shared edge), each
/// as its faces in ascending order, ordered by their lowest face. On a
/// defective edge (faces running one way, or more than two faces) every
/// face of the edge is joined too, so a flipped face is not a shell of its
/// own.
pub fn shells(mesh: &Mesh, topo: &Topology) -> Vec<Vec<FaceId>> {
    let n = mesh.num_faces();
    let mut sets = UnionFind::<u32>::new(n);
    for (f, edges) in topo.face_edges.iter().enumerate() {
        for e in edges {
            // Each face of an edge joins the edge's first face; a
            // defective edge's faces are all reached this way.
            let [g, h] = topo.edge(*e).faces;
            let first = if g.idx() < n { g } else { h };
            if first.idx() < n {
                sets.union(f as u32, first.0);
            }
        }
    }
    let mut index = vec![u32::MAX; n];
    let mut out: Vec<Vec<FaceId>> = Vec::new();
    for f in 0..n as u32 {
        let root = sets.find_mut(f) as usize;
        if index[root] == u32::MAX {
            index[root] = out.len() as u32;
            out.push(Vec::new());
        }
        out[index[root] as usize].push(FaceId(f));
    }
    out
}

/// Every shell of `shells` (of a closed, oriented, manifold mesh with
/// finite coordinates and no self-intersection) whose orientation
/// disagrees with its nesting, in the order given.
pub fn misnested_shells(mesh: &Mesh, shells: &[Vec<FaceId>]) -> Vec<MisnestedShell> {
    if shells.len() < 2 {
        return Vec::new();
    }
    let mut shell_of = vec![0u32; mesh.num_faces()];
    for (i, shell) in shells.iter().enumerate() {
        for &f in shell {
            shell_of[f.idx()] = i as u32;
        }
    }
    let grid = FaceGrid::new(mesh);
    let mut out = Vec::new();
    for (i, shell) in shells.iter().enumerate() {
        let v = mesh.pos(mesh.faces[shell[0].idx()][0]);
        // The other shells' faces that may hold the ray: those filed in
        // its cell (every face whose box holds the ray's x and y is).
        let winding: i64 = grid
            .at(v)
            .iter()
            .filter(|f| shell_of[f.idx()] != i as u32)
            .map(|&f| crossing(mesh, f, v))
            .sum();
        let facing = match volume_sign_of(mesh, shell) {
            Sign::Positive => ShellFacing::Outward,
            Sign::Negative => ShellFacing::Inward,
            Sign::Zero => ShellFacing::Flat,
        };
        // A closed surface without self-intersection bounds a region of
        // positive volume; no winding number is right for a flat one.
        let expected = match facing {
            ShellFacing::Outward => Some(0),
            ShellFacing::Inward => Some(1),
            ShellFacing::Flat => None,
        };
        if expected != Some(winding) {
            out.push(MisnestedShell {
                face: shell[0],
                facing,
                winding,
            });
        }
    }
    out
}

/// Faces filed under the cells of a uniform grid in `(x, y)` that their
/// boxes cover. A cell's index is a monotone function of a coordinate
/// (a rounded subtraction, a rounded product, a floor), so a face whose
/// box holds a point's `x` and `y` is filed under that point's cell,
/// however the roundings fall.
struct FaceGrid {
    lo: [f64; 2],
    scale: [f64; 2],
    n: usize,
    /// `faces[start[c]..start[c + 1]]` are filed under cell `c`.
    start: Vec<usize>,
    faces: Vec<FaceId>,
}

impl FaceGrid {
    /// About one cell per face, coarser while the faces would be filed
    /// more than 8 times each on average (big faces cover many cells).
    fn new(mesh: &Mesh) -> FaceGrid {
        let boxes: Vec<[[f64; 2]; 2]> = mesh
            .faces
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.pos(v));
                let k = |i: usize| [a[i].min(b[i]).min(c[i]), a[i].max(b[i]).max(c[i])];
                let (x, y) = (k(0), k(1));
                [[x[0], y[0]], [x[1], y[1]]]
            })
            .collect();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for b in &boxes {
            for k in 0..2 {
                lo[k] = lo[k].min(b[0][k]);
                hi[k] = hi[k].max(b[1][k]);
            }
        }
        let mut n = ((boxes.len() as f64).sqrt().ceil() as usize).clamp(1, 4096);
        loop {
            let grid = FaceGrid {
                lo,
                scale: [0, 1].map(|k| n as f64 / (hi[k] - lo[k])),
                n,
                start: Vec::new(),
                faces: Vec::new(),
            };
            let span = |b: &[[f64; 2]; 2]| {
                let [x0, y0] = grid.cell(b[0]);
                let [x1, y1] = grid.cell(b[1]);
                (x0, y0, x1, y1)
            };
            let filed: u64 = boxes
                .iter()
                .map(|b| {
                    let (x0, y0, x1, y1) = span(b);
                    ((x1 - x0 + 1) * (y1 - y0 + 1)) as u64
                })
                .sum();
            if n > 1 && filed > 8 * boxes.len() as u64 + (n * n) as u64 {
                n /= 2;
                continue;
            }
            let mut count = vec![0usize; n * n + 1];
            for b in &boxes {
                let (x0, y0, x1, y1) = span(b);
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        count[y * n + x + 1] += 1;
                    }
                }
            }
            for c in 1..count.len() {
                count[c] += count[c - 1];
            }
            let mut next = count.clone();
            let mut faces = vec![FaceId(0); filed as usize];
            for (f, b) in boxes.iter().enumerate() {
                let (x0, y0, x1, y1) = span(b);
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        faces[next[y * n + x]] = FaceId(f as u32);
                        next[y * n + x] += 1;
                    }
                }
            }
            return FaceGrid {
                start: count,
                faces,
                ..grid
            };
        }
    }

    /// The cell of point `p` (`[x, y]` indices, each below `n`).
    fn cell(&self, p: [f64; 2]) -> [usize; 2] {
        // Monotone in each coordinate; NaN (0 times infinity when every
        // face has one x) and negative values floor to 0.
        [0, 1].map(|k| (((p[k] - self.lo[k]) * self.scale[k]) as usize).min(self.n - 1))
    }

    /// The faces filed under the cell of `v`'s `(x, y)`.
    fn at(&self, v: [f64; 3]) -> &[FaceId] {
        let [x, y] = self.cell([v[0], v[1]]);
        let c = y * self.n + x;
        &self.faces[self.start[c]..self.start[c + 1]]
    }
}

/// What face `f` adds to the winding number around `v`, a point off it:
/// `+1` facing up or `-1` facing down when the moved vertical ray from
/// `v` crosses it, else 0 (see the module documentation).
fn crossing(mesh: &Mesh, f: FaceId, v: [f64; 3]) -> i64 {
    let [a, b, c] = mesh.faces[f.idx()].map(|u| mesh.pos(u));
    // Cheap rejections first (exact comparisons): the face's box must
    // reach the ray.
    if a[2].max(b[2]).max(c[2]) < v[2]
        || a[0].max(b[0]).max(c[0]) < v[0]
        || a[0].min(b[0]).min(c[0]) > v[0]
        || a[1].max(b[1]).max(c[1]) < v[1]
        || a[1].min(b[1]).min(c[1]) > v[1]
    {
        return 0;
    }
    let facing = orient2d_xy(a, b, c);
    if facing == Sign::Zero {
        // A vertical face: the moved ray misses its projection.
        return 0;
    }
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(p, q)| moved_orient(p, q, v) == facing);
    // The plane passes above v when v lies on the side the face's normal
    // points away from: orient3d(a, b, c, v) is the opposite of the facing.
    if inside && orient3d(a, b, c, v) == facing.flip() {
        if facing == Sign::Positive {
            1
        } else {
            -1
        }
    } else {
        0
    }
}

/// orient2d of `(p, q, v')` in `(x, y)`, `v' = (vx + e, vy + e^2)` for a
/// vanishing `e > 0`: the first non-zero of `orient2d(p, q, v)`,
/// `qy - py` times `-1` (the `e` term) and `qx - px` (the `e^2` term).
/// Never zero when `p != q` in `(x, y)`.
fn moved_orient(p: [f64; 3], q: [f64; 3], v: [f64; 3]) -> Sign {
    let s = orient2d_xy(p, q, v);
    if s != Sign::Zero {
        return s;
    }
    let dy = Sign::of_cmp(p[1].partial_cmp(&q[1]));
    if dy != Sign::Zero {
        return dy;
    }
    Sign::of_cmp(q[0].partial_cmp(&p[0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::validate::{validate, Defect};

    /// Appends the box `[lo, hi]` (12 faces) facing outward or inward,
    /// each square split along one diagonal or the other (`flip`).
    fn add_box(
        pos: &mut Vec<[f64; 3]>,
        faces: &mut Vec<[u32; 3]>,
        lo: [f64; 3],
        hi: [f64; 3],
        outward: bool,
        flip: bool,
    ) {
        let base = pos.len() as u32;
        for k in 0..8 {
            let pick = |axis: usize| {
                if k >> axis & 1 == 1 {
                    hi[axis]
                } else {
                    lo[axis]
                }
            };
            pos.push([pick(0), pick(1), pick(2)]);
        }
        // Each side as four corners counter-clockwise seen from outside.
        let sides = [
            [0, 2, 3, 1], // z = lo
            [4, 5, 7, 6], // z = hi
            [0, 1, 5, 4], // y = lo
            [2, 6, 7, 3], // y = hi
            [0, 4, 6, 2], // x = lo
            [1, 3, 7, 5], // x = hi
        ];
        for [a, b, c, d] in sides {
            let tris = if flip {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            };
            for t in tris {
                let t = t.map(|i| base + i);
                faces.push(if outward { t } else { [t[0], t[2], t[1]] });
            }
        }
    }

    fn mesh_of(boxes: &[([f64; 3], [f64; 3], bool, bool)]) -> Mesh {
        let (mut pos, mut faces) = (Vec::new(), Vec::new());
        for &(lo, hi, outward, flip) in boxes {
            add_box(&mut pos, &mut faces, lo, hi, outward, flip);
        }
        Mesh::from_raw(pos, faces)
    }

    fn misnested(m: &Mesh) -> Vec<(u32, ShellFacing, i64)> {
        let r = validate(m);
        let topo = r.topology.as_ref().expect("closed");
        misnested_shells(m, &shells(m, topo))
            .iter()
            .map(|s| (s.face.0, s.facing, s.winding))
            .collect()
    }

    const OUTER: ([f64; 3], [f64; 3]) = ([0.0; 3], [4.0; 3]);

    /// Counted by hand: one box is one piece, turning one of its faces
    /// over (three edges now run the same way twice) leaves it one piece,
    /// and a second box apart makes two.
    #[test]
    fn a_flipped_face_stays_in_its_shell() {
        let mut m = mesh_of(&[(OUTER.0, OUTER.1, true, false)]);
        assert_eq!(validate(&m).stats.components, Some(1));
        m.faces[5].swap(1, 2);
        let r = validate(&m);
        assert!(!r.is_accepted());
        assert_eq!(r.stats.components, Some(1));
        let mut apart = mesh_of(&[
            (OUTER.0, OUTER.1, true, false),
            ([5.0; 3], [6.0; 3], true, false),
        ]);
        apart.faces[5].swap(1, 2);
        assert_eq!(validate(&apart).stats.components, Some(2));
    }

    #[test]
    fn a_solid_inside_a_solid_is_named() {
        for flip in [false, true] {
            // The inner box's first vertex (1, 1, 1) lies under the outer
            // top's diagonal from (0, 0) to (4, 4) in one split: the moved
            // ray decides.
            let m = mesh_of(&[
                (OUTER.0, OUTER.1, true, flip),
                ([1.0; 3], [2.0; 3], true, !flip),
            ]);
            assert_eq!(misnested(&m), vec![(12, ShellFacing::Outward, 1)]);
            let r = validate(&m);
            assert!(r.defects.contains(&Defect::MisnestedShell {
                face: FaceId(12),
                facing: ShellFacing::Outward,
                winding: 1,
            }));
            assert!(!r.is_accepted());
        }
    }

    #[test]
    fn a_cavity_facing_inward_is_accepted() {
        for flip in [false, true] {
            let m = mesh_of(&[
                (OUTER.0, OUTER.1, true, flip),
                ([1.0; 3], [2.0; 3], false, flip),
            ]);
            assert_eq!(misnested(&m), vec![]);
            assert!(validate(&m).is_accepted());
            // A solid in the cavity, facing outward, is fine too.
            let m = mesh_of(&[
                (OUTER.0, OUTER.1, true, flip),
                ([1.0; 3], [3.0; 3], false, !flip),
                ([1.5; 3], [2.5; 3], true, flip),
            ]);
            assert_eq!(misnested(&m), vec![]);
            // Facing inward, it is a cavity in empty space.
            let m = mesh_of(&[
                (OUTER.0, OUTER.1, true, flip),
                ([1.0; 3], [3.0; 3], false, !flip),
                ([1.5; 3], [2.5; 3], false, flip),
            ]);
            assert_eq!(misnested(&m), vec![(24, ShellFacing::Inward, 0)]);
        }
    }

    #[test]
    fn an_inward_box_beside_a_solid_is_named() {
        // The total volume stays positive (64 - 1): the volume sign alone
        // would accept it.
        let m = mesh_of(&[
            (OUTER.0, OUTER.1, true, false),
            ([5.0; 3], [6.0; 3], false, false),
        ]);
        assert_eq!(misnested(&m), vec![(12, ShellFacing::Inward, 0)]);
        assert!(!validate(&m).is_accepted());
        // Side by side, both outward: no defect.
        let m = mesh_of(&[
            (OUTER.0, OUTER.1, true, false),
            ([5.0; 3], [6.0; 3], true, true),
        ]);
        assert_eq!(misnested(&m), vec![]);
    }

    /// A porous part: one box holding 100 cavities in a 10 x 10 array, a
    /// solid in one of them, and one cavity turned outward (a solid inside
    /// the solid): only that one is named, through the grid's cells.
    #[test]
    fn a_porous_part_names_its_one_wrong_cavity() {
        let mut boxes = vec![([0.0; 3], [21.0, 21.0, 3.0], true, false)];
        for i in 0..10 {
            for j in 0..10 {
                let lo = [1.0 + 2.0 * i as f64, 1.0 + 2.0 * j as f64, 1.0];
                let hi = [lo[0] + 1.0, lo[1] + 1.0, 2.0];
                boxes.push((lo, hi, i == 3 && j == 7, (i + j) % 2 == 0));
            }
        }
        boxes.push(([1.25, 1.25, 1.25], [1.75, 1.75, 1.75], true, false));
        let m = mesh_of(&boxes);
        assert_eq!(
            misnested(&m),
            vec![((12 * (1 + 3 * 10 + 7)) as u32, ShellFacing::Outward, 1)]
        );
    }

    proptest::proptest! {
        /// Concentric boxes of any orientation, on a lattice (so that
        /// vertices line up with the diagonals and sides of the boxes
        /// around them), and one box beside them: the named shells are
        /// those whose facing disagrees with the orientations of the boxes
        /// around them, summed by hand.
        #[test]
        fn nested_boxes_follow_the_hand_rule(
            depth in 1usize..5,
            outward in proptest::array::uniform5(proptest::bool::ANY),
            flips in proptest::array::uniform5(proptest::bool::ANY),
            jitter in proptest::array::uniform5(proptest::array::uniform3(0u8..2)),
        ) {
            let mut boxes = Vec::new();
            for k in 0..depth {
                let lo = std::array::from_fn(|a| (2 * k) as f64 + f64::from(jitter[k][a]));
                let hi = std::array::from_fn(|a| 20.0 - (2 * k) as f64 - f64::from(jitter[k][a]));
                boxes.push((lo, hi, outward[k], flips[k]));
            }
            boxes.push(([30.0, 0.0, 0.0], [31.0, 1.0, 1.0], outward[4], flips[4]));
            let m = mesh_of(&boxes);
            let mut expect = Vec::new();
            let mut around = 0i64;
            for (k, b) in boxes.iter().enumerate() {
                // The box beside the others has none around it.
                let w = if k == depth { 0 } else { around };
                let ok = if b.2 { w == 0 } else { w == 1 };
                if !ok {
                    expect.push(((12 * k) as u32, if b.2 { ShellFacing::Outward } else { ShellFacing::Inward }, w));
                }
                if k < depth {
                    around += if b.2 { 1 } else { -1 };
                }
            }
            proptest::prop_assert_eq!(misnested(&m), expect);
        }
    }
}
