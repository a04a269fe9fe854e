//! Input: nothing. Output: the hand-derived level sets of every built-in
//! dataset at each of its degenerate heights and at a regular height next
//! to each one, for tests of the slicer.
//!
//! Every number here is derived by hand from the construction (see the
//! `why` of each row, the comments in `shapes.rs` and `DATASETS.md`), using
//! the rules of `SPEC.md`: S_O excludes the flat regions themselves, a flat
//! region's boundary edge is also in S_O when material lies on both sides,
//! S_O is the oriented boundary of reg(R- ∩ R+), L- and L+ are the contours
//! just below and just above the level. Areas are exact rationals
//! `(numerator, denominator)`; the signed area of a loop set is the sum of
//! its outer areas minus its hole areas, i.e. the material cross-section.
//! Loops through a saddle are counted as the pairing rule of `SPEC.md`
//! section 5 chains them (each incoming branch joined to the next outgoing
//! one, across a sector below the plane).

/// Hand-derived level set of one dataset at one height.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Expected {
    /// Dataset name (see [`super::by_name`]).
    pub dataset: &'static str,
    /// The height `z = num / den`.
    pub level: (i64, u64),
    /// S_O loops with positive signed area (counter-clockwise).
    pub contours_outer: usize,
    /// S_O loops with negative signed area (clockwise).
    pub contours_hole: usize,
    /// F regions facing up (material below).
    pub faces_up: usize,
    /// F regions facing down (material above).
    pub faces_down: usize,
    /// F regions of zero projected area (none in these datasets).
    pub faces_flat: usize,
    /// Open S_NO ridge polylines (neighbours below).
    pub ridges_open: usize,
    /// Closed S_NO ridge polylines.
    pub ridges_closed: usize,
    /// Open S_NO valley polylines (neighbours above).
    pub valleys_open: usize,
    /// Closed S_NO valley polylines.
    pub valleys_closed: usize,
    /// Isolated minima (P).
    pub minima: usize,
    /// Isolated maxima (P).
    pub maxima: usize,
    /// Branch counts `2m` of the saddles, sorted.
    pub saddles: &'static [u32],
    /// Signed area of S_O (sum over loops).
    pub area_contours: (i128, u128),
    /// Signed area of L- (the contour just below).
    pub area_below: (i128, u128),
    /// Signed area of L+ (the contour just above).
    pub area_above: (i128, u128),
    /// Total area of the up-facing F regions.
    pub area_faces_up: (i128, u128),
    /// Total area of the down-facing F regions.
    pub area_faces_down: (i128, u128),
    /// The hand derivation.
    pub why: &'static str,
}

/// Exact volume and counts of one dataset, derived by hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Solid {
    /// Dataset name.
    pub dataset: &'static str,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of faces.
    pub faces: usize,
    /// Exact volume `(numerator, denominator)`.
    pub volume: (i128, u128),
    /// Euler characteristic `V - E + F` (2 per sphere, 0 per torus, -2 for
    /// the double torus; the internal torus is a sphere plus a torus).
    pub euler: i64,
    /// How the volume follows from the construction.
    pub why: &'static str,
}

const ZERO: Expected = Expected {
    dataset: "",
    level: (0, 1),
    contours_outer: 0,
    contours_hole: 0,
    faces_up: 0,
    faces_down: 0,
    faces_flat: 0,
    ridges_open: 0,
    ridges_closed: 0,
    valleys_open: 0,
    valleys_closed: 0,
    minima: 0,
    maxima: 0,
    saddles: &[],
    area_contours: (0, 1),
    area_below: (0, 1),
    area_above: (0, 1),
    area_faces_up: (0, 1),
    area_faces_down: (0, 1),
    why: "",
};

/// Every hand-derived row, grouped by dataset, in increasing height.
pub fn expected() -> &'static [Expected] {
    &EXPECTED
}

/// Volume, counts and Euler characteristic of every dataset.
pub fn solids() -> &'static [Solid] {
    &SOLIDS
}

static SOLIDS: [Solid; 13] = [
    Solid {
        dataset: "unit_cube",
        vertices: 8,
        faces: 12,
        volume: (1, 1),
        euler: 2,
        why: "[0,1]^3",
    },
    Solid {
        dataset: "octahedron",
        vertices: 6,
        faces: 8,
        volume: (4, 3),
        euler: 2,
        why: "two pyramids of base area 2 and height 1: 2 * 2/3",
    },
    Solid {
        dataset: "pyramid",
        vertices: 6,
        faces: 8,
        volume: (4, 3),
        euler: 2,
        why: "base 4, height 1: 4/3",
    },
    Solid {
        dataset: "upright_torus",
        vertices: 16,
        faces: 32,
        volume: (16, 1),
        euler: 0,
        why: "int_tube 4 s ds dy = 4 * area 2 * centroid s 2",
    },
    Solid {
        dataset: "lying_torus",
        vertices: 32,
        faces: 64,
        volume: (168, 1),
        euler: 0,
        why: "int_tube 2 * 14 * s ds dz = 28 * area 3 * centroid s 2",
    },
    Solid {
        dataset: "double_torus",
        vertices: 70,
        faces: 144,
        volume: (71, 1),
        euler: -2,
        why: "4 * 20 minus the dimple deficit (2*6 + 3*6 + 3*5 + 3*3)/6 = 9",
    },
    Solid {
        dataset: "grid",
        vertices: 50,
        faces: 96,
        volume: (15, 1),
        euler: 2,
        why: "3*3*2 minus nine pits of volume 1/3",
    },
    Solid {
        dataset: "cylinder",
        vertices: 18,
        faces: 32,
        volume: (28, 1),
        euler: 2,
        why: "14 * 2",
    },
    Solid {
        dataset: "internal_torus",
        vertices: 24,
        faces: 44,
        volume: (272, 1),
        euler: 2,
        why: "8*8*5 = 320 minus the cavity 8 * area 3 * centroid 2 = 48",
    },
    Solid {
        dataset: "peg_cube",
        vertices: 48,
        faces: 92,
        volume: (74, 1),
        euler: 2,
        why: "64 + 2*2*2 + 2*2*1/2",
    },
    Solid {
        dataset: "chamfered_cylinder",
        vertices: 26,
        faces: 48,
        volume: (217, 6),
        euler: 2,
        why: "14 * 2 + 14 * int_0^1 (1 - t/2)^2 dt = 28 + 49/6",
    },
    Solid {
        dataset: "platform_grid",
        vertices: 88,
        faces: 172,
        volume: (45, 1),
        euler: 2,
        why: "36 * 1 + (1 + 2 + 2 + 4) * 1",
    },
    Solid {
        dataset: "saddle8",
        vertices: 18,
        faces: 32,
        volume: (32, 1),
        euler: 2,
        why: "8 top triangles of area 2 and mean height 2",
    },
];

static EXPECTED: [Expected; 83] = [
    Expected {
        dataset: "unit_cube",
        level: (0, 1),
        faces_down: 1,
        area_above: (1, 1),
        area_faces_down: (1, 1),
        why: "bottom square [0,1]^2: two faces in the plane, projected clockwise -> one down region of area 1; its boundary edges have side faces going up (neighbour above), so no S_O; nothing below (L- empty), L+ is the unit square",
        ..ZERO
    },
    Expected {
        dataset: "unit_cube",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (1, 1),
        area_below: (1, 1),
        area_above: (1, 1),
        why: "regular: one square loop around the four side faces, area 1",
        ..ZERO
    },
    Expected {
        dataset: "unit_cube",
        level: (1, 1),
        faces_up: 1,
        area_below: (1, 1),
        area_faces_up: (1, 1),
        why: "top square: one up region of area 1; side faces go down from its boundary (neighbour below), so no S_O; L- is the rim square (area 1), L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "octahedron",
        level: (-1, 1),
        minima: 1,
        why: "bottom vertex (0,0,-1): its four neighbours are at z=0, all above -> one minimum; the contour just above shrinks to it (area 0)",
        ..ZERO
    },
    Expected {
        dataset: "octahedron",
        level: (-1, 2),
        contours_outer: 1,
        area_contours: (1, 2),
        area_below: (1, 2),
        area_above: (1, 2),
        why: "regular: one square |x|+|y| <= 1/2, area 2*(1/2)^2 = 1/2",
        ..ZERO
    },
    Expected {
        dataset: "octahedron",
        level: (0, 1),
        contours_outer: 1,
        area_contours: (2, 1),
        area_below: (2, 1),
        area_above: (2, 1),
        why: "the four equator edges lie in the plane, each between an upper face (opposite (0,0,1) above) and a lower face (opposite (0,0,-1) below): transversal, in S_O; one loop |x|+|y| = 1 of area 2, equal to the slices just below and above; each equator vertex has 2 branches (no saddle)",
        ..ZERO
    },
    Expected {
        dataset: "octahedron",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (1, 2),
        area_below: (1, 2),
        area_above: (1, 2),
        why: "regular: one square |x|+|y| <= 1/2, area 1/2",
        ..ZERO
    },
    Expected {
        dataset: "octahedron",
        level: (1, 1),
        maxima: 1,
        why: "top vertex (0,0,1): all four neighbours below -> one maximum; L- shrinks to it (area 0)",
        ..ZERO
    },
    Expected {
        dataset: "pyramid",
        level: (0, 1),
        faces_down: 1,
        area_above: (4, 1),
        area_faces_down: (4, 1),
        why: "base [-1,1]^2 (fan of 4 faces around (0,0,0)) lies in the plane, clockwise from above -> one down region of area 4; the side faces rise from its boundary (neighbour above), no S_O; L- empty, L+ the base square",
        ..ZERO
    },
    Expected {
        dataset: "pyramid",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (1, 1),
        area_below: (1, 1),
        area_above: (1, 1),
        why: "regular: square [-1/2,1/2]^2, area 1",
        ..ZERO
    },
    Expected {
        dataset: "pyramid",
        level: (1, 1),
        maxima: 1,
        why: "apex (0,0,1): its four neighbours (the base corners) are below -> one maximum; L- shrinks to it",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (-3, 1),
        minima: 1,
        why: "bottom vertex (0,0,-3): neighbours at z=0 and z=-2, all above -> one minimum; L+ shrinks to it",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (-5, 2),
        contours_outer: 1,
        area_contours: (1, 2),
        area_below: (1, 2),
        area_above: (1, 2),
        why: "slice at height z is {(x,y): ||x| + |z| - 2| + |y| <= 1}; for 2 <= |z| <= 3 this is the single diamond |x| + |y| <= 3 - |z|, area 2(3-|z|)^2 = 1/2, one loop",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (-2, 1),
        contours_outer: 1,
        area_contours: (2, 1),
        area_below: (2, 1),
        area_above: (2, 1),
        why: "vertices (0,+-1,-2) lie in the plane; each has exactly one neighbour below ((0,0,-3)) and all others above, so its link changes sign twice: regular, 2 branches; one loop of area 2(3-2)^2 = 2",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (-1, 1),
        contours_outer: 1,
        saddles: &[4],
        area_contours: (4, 1),
        area_below: (4, 1),
        area_above: (4, 1),
        why: "bottom of the hole: vertex (0,0,-1) has tube neighbours (0,+-1,-2) below and ring neighbours (+-1,0,0) above: ordinary saddle, 4 branches. The slice is two diamonds ||x|-1|+|y| <= 1 touching at the origin (area 4 = L- = L+). Material lies in the sectors toward +-x (above neighbours); the pairing rule joins across the sectors below (+-y), so the two diamonds are ONE weakly simple outer loop through the saddle twice",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (-1, 2),
        contours_outer: 2,
        area_contours: (4, 1),
        area_below: (4, 1),
        area_above: (4, 1),
        why: "slice at height z is {(x,y): ||x| + |z| - 2| + |y| <= 1}; for |z| <= 1 two disjoint diamonds of area 2 each (left and right columns)",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (0, 1),
        contours_outer: 2,
        area_contours: (4, 1),
        area_below: (4, 1),
        area_above: (4, 1),
        why: "the two tube sections at x = +-s (4 vertices each, all at z=0) consist of transversal edges (faces above and below): two outer loops, the diamonds |x-+2| + |y| <= 1, area 2 each; 2 branches per vertex",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (1, 2),
        contours_outer: 2,
        area_contours: (4, 1),
        area_below: (4, 1),
        area_above: (4, 1),
        why: "slice at height z is {(x,y): ||x| + |z| - 2| + |y| <= 1}; two disjoint diamonds, area 4",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (1, 1),
        contours_outer: 2,
        saddles: &[4],
        area_contours: (4, 1),
        area_below: (4, 1),
        area_above: (4, 1),
        why: "top of the hole: vertex (0,0,1) has ring neighbours (+-1,0,0) below and tube neighbours (0,+-1,2) above: ordinary saddle, 4 branches. Slice = two diamonds touching at the origin, area 4 on both sides. Material lies in the sectors toward +-x, which are the sectors below, so the pairing joins each diamond to itself: TWO outer loops touching at the saddle",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (3, 2),
        contours_outer: 1,
        area_contours: (7, 2),
        area_below: (7, 2),
        area_above: (7, 2),
        why: "slice at height z is {(x,y): ||x| + |z| - 2| + |y| <= 1}; for 1 <= z <= 2 the two diamonds overlap: one loop of area 2(2 - (z-1)^2) = 7/2",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (2, 1),
        contours_outer: 1,
        area_contours: (2, 1),
        area_below: (2, 1),
        area_above: (2, 1),
        why: "vertices (0,+-1,2) lie in the plane, each with one neighbour above ((0,0,3)) and the rest below: regular, 2 branches; one loop of area 2(3-2)^2 = 2",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (5, 2),
        contours_outer: 1,
        area_contours: (1, 2),
        area_below: (1, 2),
        area_above: (1, 2),
        why: "slice at height z is {(x,y): ||x| + |z| - 2| + |y| <= 1}; for 2 <= z <= 3 the single diamond |x| + |y| <= 3 - z, area 2(3-z)^2 = 1/2",
        ..ZERO
    },
    Expected {
        dataset: "upright_torus",
        level: (3, 1),
        maxima: 1,
        why: "top vertex (0,0,3): all neighbours below -> one maximum; L- shrinks to it",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (-1, 1),
        valleys_closed: 1,
        why: "bottom ring: 8 vertices at z=-1 (s=2); each ring edge has both opposite vertices above (z=0 and z=1 rings) -> one closed valley of 8 edges; no vertex is P (each has two in-plane neighbours); nothing below, the slice just above has area 14(b^2-a^2) -> 0",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (-1, 2),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (315, 8),
        area_below: (315, 8),
        area_above: (315, 8),
        why: "slice = octagonal annulus a(z) <= gauge <= b(z), area 14(b^2-a^2); a = 3/2, b = 9/4: 14 * 45/16 = 315/8; outer loop and hole loop",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (0, 1),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (147, 2),
        area_below: (147, 2),
        area_above: (147, 2),
        why: "inner equator ring (s=1, 8 vertices at z=0): every ring edge lies between a face above (top ring side) and a face below (bottom ring side): transversal, one HOLE loop of area -14; the outer loop crosses faces at s = b(0) = 5/2: area 14*25/4; total 14(25/4 - 1) = 147/2, continuous (L- = L+)",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (1, 2),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (84, 1),
        area_below: (84, 1),
        area_above: (84, 1),
        why: "slice = octagonal annulus a(z) <= gauge <= b(z), area 14(b^2-a^2); a = 5/4, b = 11/4: 14 * 6 = 84",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (1, 1),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (189, 2),
        area_below: (189, 2),
        area_above: (189, 2),
        why: "outer equator ring (s=3) at z=1: transversal ring edges form the OUTER loop (area 14*9 = 126); the hole crosses faces at a(1) = 3/2 (area 14*9/4); total 189/2 = L- = L+",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (3, 2),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (357, 8),
        area_below: (357, 8),
        area_above: (357, 8),
        why: "slice = octagonal annulus a(z) <= gauge <= b(z), area 14(b^2-a^2); a = 7/4, b = 5/2: 14 * 51/16 = 357/8",
        ..ZERO
    },
    Expected {
        dataset: "lying_torus",
        level: (2, 1),
        ridges_closed: 1,
        why: "top ring: 8 vertices at z=2 (s=2) whose ring edges have both opposite vertices below -> one closed ridge of 8 edges; the annulus just below collapses onto it (area 0), nothing above",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (0, 1),
        faces_down: 1,
        area_above: (20, 1),
        area_faces_down: (20, 1),
        why: "bottom (40 faces, the domain of area 20 with 2 holes) lies in the plane, clockwise -> one down region of area 20; walls rise from its boundary, no S_O; L- empty, L+ = domain (outer + 2 holes, area 20)",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (1, 2),
        contours_outer: 1,
        contours_hole: 2,
        area_contours: (20, 1),
        area_below: (20, 1),
        area_above: (20, 1),
        why: "regular: the domain itself (f >= 1 everywhere): outer rectangle 6x4 and the two 1x2 holes, area 24 - 4 = 20",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (1, 1),
        contours_outer: 1,
        contours_hole: 2,
        minima: 1,
        area_contours: (20, 1),
        area_below: (20, 1),
        area_above: (20, 1),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; (0,-1) is interior and its 6 neighbours are above -> one minimum (pit); (1,1) (corner of hole E) and (-1,0) (side of hole W) have top neighbours above and wall-bottom neighbours below: regular, 2 branches. Slice = domain: 1 outer + 2 holes, area 20 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (3, 2),
        contours_outer: 1,
        contours_hole: 3,
        area_contours: (707, 36),
        area_below: (707, 36),
        area_above: (707, 36),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; {f < 3/2} = three notches around the L vertices: per triangle (L, a, b) the corner with parameters t = (c-1)/(f-1) has area t_a t_b / 2; t = 1/2 toward v, 1/6 toward a 4. Notch areas: (0,-1) 2/24 + 4/72 = 5/36, (1,1) 2/24 + 3/72 = 1/8, (-1,0) 2/24 + 1/72 = 7/72; total 13/36. The notches at (1,1) and (-1,0) open into holes E and W; the one at (0,-1) is a new interior hole: 1 outer + 3 holes, area 20 - 13/36 = 707/36",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (2, 1),
        contours_outer: 1,
        contours_hole: 3,
        saddles: &[6],
        area_contours: (167, 9),
        area_below: (167, 9),
        area_above: (167, 9),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; monkey saddle at v: link heights 4 1 4 1 4 1 around z(v) = 2, six branches (m = 3). Notches {f < 2} (t = (2-1)/(f-1): 1 toward v, 1/3 toward a 4): (0,-1) 2/6 + 4/18 = 5/9, (1,1) 2/6 + 3/18 = 1/2, (-1,0) 2/6 + 1/18 = 7/18, total 13/9; area 20 - 13/9 = 167/9 (continuous). The three notches (hole E + notch, hole W + notch, pit notch) all touch v; the pairing joins across the sectors below (the L directions), so each notch closes on itself: 1 outer + 3 holes touching at v",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (5, 2),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (137, 8),
        area_below: (137, 8),
        area_above: (137, 8),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; {f < 5/2}: the 6 triangles at v (values 2,4,1) lose 5/8 of their area each (5/16), the 8 other dimple triangles (1,4,4) lose 1/4 (1/8): 15/8 + 1 = 23/8; the notches now meet around v and join holes W and E: 1 outer + 1 hole, area 20 - 23/8 = 137/8",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (7, 2),
        contours_outer: 1,
        contours_hole: 1,
        area_contours: (1033, 72),
        area_below: (1033, 72),
        area_above: (1033, 72),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; material: the 26 flat triangles (area 13) + corners of the dimple triangles: (2,4,1)-triangles keep 1/24 of their area (6 * 1/48 = 1/8), (1,4,4)-triangles keep 11/36 (8 * 11/72 = 11/9): 13 + 1/8 + 11/9 = 1033/72; the outer rim (all at 4) keeps it connected: 1 outer + 1 hole (holes W, E and the dimple)",
        ..ZERO
    },
    Expected {
        dataset: "double_torus",
        level: (4, 1),
        faces_up: 2,
        ridges_open: 3,
        area_below: (13, 1),
        area_faces_up: (13, 1),
        why: "top height f: 4 except v=(0,0) at 2 and L = (1,1),(-1,0),(0,-1) at 1; every top triangle has area 1/2; the 14 top faces touching v or an L dip below; the other 26 (area 13) lie in the plane, counter-clockwise -> up. Writing cell (i,j) for [i,i+1]x[j,j+1], cells (1,1) and (-1,-2) are fully dipped and cut the top into a left part (x=-3 column, the top row up to cell (0,1)'s upper triangle, cell (-2,-2): area 15/2) and a right part (x=2 column, cells (1,-2) and (0,-2)'s lower triangle: area 11/2) -> 2 up regions, area 13. Ridges: edges at 4 whose two faces both dip: (1,-1)-(1,0) (dimple face + hole E wall), (1,2)-(2,2) and (-1,-2)-(0,-2) (dimple face + outer wall): 3 open ridges, no junctions. No S_O (nothing above 4); L- = the flat area 13",
        ..ZERO
    },
    Expected {
        dataset: "grid",
        level: (0, 1),
        faces_down: 1,
        area_above: (9, 1),
        area_faces_down: (9, 1),
        why: "bottom [0,3]^2 (36 faces) in the plane, clockwise -> one down region of area 9; L- empty, L+ = 9",
        ..ZERO
    },
    Expected {
        dataset: "grid",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (9, 1),
        area_below: (9, 1),
        area_above: (9, 1),
        why: "regular: one square [0,3]^2 around the walls, area 9",
        ..ZERO
    },
    Expected {
        dataset: "grid",
        level: (1, 1),
        contours_outer: 1,
        minima: 9,
        area_contours: (9, 1),
        area_below: (9, 1),
        area_above: (9, 1),
        why: "the nine cell centres at z=1 have their four corner neighbours at z=2 (above) -> 9 minima (pits); the slice is still the full square, area 9 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "grid",
        level: (3, 2),
        contours_outer: 1,
        contours_hole: 9,
        area_contours: (27, 4),
        area_below: (27, 4),
        area_above: (27, 4),
        why: "regular: each pit is a square hole of side z-1 = 1/2: 1 outer + 9 holes, area 9 - 9/4 = 27/4",
        ..ZERO
    },
    Expected {
        dataset: "grid",
        level: (2, 1),
        ridges_open: 20,
        why: "all 24 grid edges of the top are at z=2 with both opposite vertices below (pit centres at 1, wall bottoms at 0) -> ridges. Junctions (more than two ridge edges): 4 interior grid points (4 edges) and 8 boundary non-corner points (3 edges); corners have 2. Polylines: 4 corner polylines of 2 edges + 16 single edges between junctions = 20 open ridges. The material shrinks to the ridge network: L- area 0, L+ empty, no S_O",
        ..ZERO
    },
    Expected {
        dataset: "cylinder",
        level: (0, 1),
        faces_down: 1,
        area_above: (14, 1),
        area_faces_down: (14, 1),
        why: "bottom octagon (fan of 8) in the plane, clockwise -> one down region of area 14; no S_O; L- empty, L+ = 14",
        ..ZERO
    },
    Expected {
        dataset: "cylinder",
        level: (1, 1),
        contours_outer: 1,
        area_contours: (14, 1),
        area_below: (14, 1),
        area_above: (14, 1),
        why: "regular: one octagon loop, area 14",
        ..ZERO
    },
    Expected {
        dataset: "cylinder",
        level: (2, 1),
        faces_up: 1,
        area_below: (14, 1),
        area_faces_up: (14, 1),
        why: "top octagon (fan of 8) -> one up region of area 14; its boundary edges have side faces going down (neighbour below): not S_O, so no contour; L- = rim octagon (14), L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (-2, 1),
        faces_down: 1,
        area_above: (64, 1),
        area_faces_down: (64, 1),
        why: "box bottom (2 faces) in the plane, clockwise -> one down region of area 64; L- empty, L+ = 64",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (-3, 2),
        contours_outer: 1,
        area_contours: (64, 1),
        area_below: (64, 1),
        area_above: (64, 1),
        why: "regular: box square only, area 64",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (-1, 1),
        contours_outer: 1,
        valleys_closed: 1,
        area_contours: (64, 1),
        area_below: (64, 1),
        area_above: (64, 1),
        why: "cavity bottom ring (4 vertices, s=2): each ring edge has both opposite vertices above (rings at z=0, z=1) -> one closed valley (inside the material); the cavity has zero area here: one outer loop (box), area 64 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (-1, 2),
        contours_outer: 2,
        contours_hole: 1,
        area_contours: (211, 4),
        area_below: (211, 4),
        area_above: (211, 4),
        why: "box 8x8 (area 64) minus the cavity annulus of area 4(b^2-a^2); a = 3/2, b = 9/4: 64 - 45/4 = 211/4; loops: box (outer), cavity outer wall (hole), cavity inner wall around the central pillar (outer)",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (0, 1),
        contours_outer: 2,
        contours_hole: 1,
        area_contours: (43, 1),
        area_below: (43, 1),
        area_above: (43, 1),
        why: "box 8x8 (area 64) minus the cavity annulus of area 4(b^2-a^2); inner equator ring (s=1) of transversal edges bounds the central pillar (outer loop, area 4); the cavity's outer wall is crossed at s = 5/2 (hole, area 25); 64 - 25 + 4 = 43 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (1, 2),
        contours_outer: 2,
        contours_hole: 1,
        area_contours: (40, 1),
        area_below: (40, 1),
        area_above: (40, 1),
        why: "box 8x8 (area 64) minus the cavity annulus of area 4(b^2-a^2); a = 5/4, b = 11/4: 64 - 24 = 40",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (1, 1),
        contours_outer: 2,
        contours_hole: 1,
        area_contours: (37, 1),
        area_below: (37, 1),
        area_above: (37, 1),
        why: "box 8x8 (area 64) minus the cavity annulus of area 4(b^2-a^2); outer equator ring (s=3) of transversal edges is the hole loop (area 36); the pillar is crossed at s = 3/2 (area 9); 64 - 36 + 9 = 37 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (3, 2),
        contours_outer: 2,
        contours_hole: 1,
        area_contours: (205, 4),
        area_below: (205, 4),
        area_above: (205, 4),
        why: "box 8x8 (area 64) minus the cavity annulus of area 4(b^2-a^2); a = 7/4, b = 5/2: 64 - 51/4 = 205/4",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (2, 1),
        contours_outer: 1,
        ridges_closed: 1,
        area_contours: (64, 1),
        area_below: (64, 1),
        area_above: (64, 1),
        why: "cavity top ring (s=2): ring edges have both opposite vertices below -> one closed ridge; the cavity closes here: one outer loop (box), area 64 on both sides",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (5, 2),
        contours_outer: 1,
        area_contours: (64, 1),
        area_below: (64, 1),
        area_above: (64, 1),
        why: "regular: box square only, area 64",
        ..ZERO
    },
    Expected {
        dataset: "internal_torus",
        level: (3, 1),
        faces_up: 1,
        area_below: (64, 1),
        area_faces_up: (64, 1),
        why: "box top -> one up region of area 64; no S_O; L- = 64, L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (0, 1),
        faces_down: 1,
        area_above: (16, 1),
        area_faces_down: (16, 1),
        why: "cube bottom [0,4]^2 (3 grid rectangles) -> one down region of area 16; L- empty, L+ = 16",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (16, 1),
        area_below: (16, 1),
        area_above: (16, 1),
        why: "regular: cube square, area 16",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (1, 1),
        contours_outer: 1,
        faces_down: 1,
        area_contours: (16, 1),
        area_below: (16, 1),
        area_above: (20, 1),
        area_faces_down: (4, 1),
        why: "peg bottom [4,6]x[1,3] -> one down region of area 4; its edge x=4 has the cube wall going DOWN (material on both sides): shared with S_O; the cube's grid edges at z=1 are transversal. S_O = boundary of [0,4]^2 (R- cube, R+ cube + peg): area 16; L- = 16, L+ = 20",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (2, 1),
        contours_outer: 1,
        area_contours: (20, 1),
        area_below: (20, 1),
        area_above: (20, 1),
        why: "regular: cube + right peg, one loop, area 20",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (3, 1),
        contours_outer: 1,
        faces_up: 1,
        faces_down: 1,
        area_contours: (16, 1),
        area_below: (20, 1),
        area_above: (20, 1),
        area_faces_up: (4, 1),
        area_faces_down: (4, 1),
        why: "right peg top [4,6]x[1,3] -> up region (area 4), its edge x=4 has the cube wall going UP: shared with S_O; left peg bottom [-2,0]x[1,3] -> down region (area 4), its edge x=0 has the cube wall going DOWN: shared with S_O. S_O = boundary of [0,4]^2, area 16; L- = cube + right peg = 20, L+ = cube + left peg = 20",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (13, 4),
        contours_outer: 1,
        area_contours: (20, 1),
        area_below: (20, 1),
        area_above: (20, 1),
        why: "regular: cube + left peg, area 20",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (7, 2),
        contours_outer: 1,
        faces_up: 1,
        area_contours: (16, 1),
        area_below: (20, 1),
        area_above: (16, 1),
        area_faces_up: (4, 1),
        why: "left peg top -> up region of area 4, edge x=0 shared with S_O (cube wall goes up); S_O = [0,4]^2 boundary, area 16; L- = 20, L+ = 16",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (15, 4),
        contours_outer: 1,
        area_contours: (16, 1),
        area_below: (16, 1),
        area_above: (16, 1),
        why: "regular: cube only, area 16",
        ..ZERO
    },
    Expected {
        dataset: "peg_cube",
        level: (4, 1),
        faces_up: 1,
        area_below: (16, 1),
        area_faces_up: (16, 1),
        why: "cube top -> one up region of area 16; no S_O; L- = 16, L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "chamfered_cylinder",
        level: (0, 1),
        faces_down: 1,
        area_above: (14, 1),
        area_faces_down: (14, 1),
        why: "bottom octagon -> one down region of area 14; L- empty, L+ = 14",
        ..ZERO
    },
    Expected {
        dataset: "chamfered_cylinder",
        level: (1, 1),
        contours_outer: 1,
        area_contours: (14, 1),
        area_below: (14, 1),
        area_above: (14, 1),
        why: "regular: octagon, area 14",
        ..ZERO
    },
    Expected {
        dataset: "chamfered_cylinder",
        level: (2, 1),
        contours_outer: 1,
        area_contours: (14, 1),
        area_below: (14, 1),
        area_above: (14, 1),
        why: "the ring at z=2 (start of the chamfer): every ring edge lies between a side face (opposite vertex at z=0, below) and a chamfer face (opposite at z=3, above): transversal, one loop of mesh edges, area 14 = L- = L+",
        ..ZERO
    },
    Expected {
        dataset: "chamfered_cylinder",
        level: (5, 2),
        contours_outer: 1,
        area_contours: (63, 8),
        area_below: (63, 8),
        area_above: (63, 8),
        why: "regular: octagon scaled by 3/4, area 14 * 9/16 = 63/8",
        ..ZERO
    },
    Expected {
        dataset: "chamfered_cylinder",
        level: (3, 1),
        faces_up: 1,
        area_below: (7, 2),
        area_faces_up: (7, 2),
        why: "top half-size octagon -> one up region of area 14/4 = 7/2; chamfer faces go down from it: no S_O; L- = 7/2, L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "platform_grid",
        level: (0, 1),
        faces_down: 1,
        area_above: (36, 1),
        area_faces_down: (36, 1),
        why: "bottom [0,6]^2 -> one down region of area 36; L- empty, L+ = 36",
        ..ZERO
    },
    Expected {
        dataset: "platform_grid",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (36, 1),
        area_below: (36, 1),
        area_above: (36, 1),
        why: "regular: one square, area 36",
        ..ZERO
    },
    Expected {
        dataset: "platform_grid",
        level: (1, 1),
        contours_outer: 4,
        faces_up: 1,
        area_contours: (9, 1),
        area_below: (36, 1),
        area_above: (9, 1),
        area_faces_up: (27, 1),
        why: "platform top minus the 4 plateau footprints -> ONE up region (area 36 - 9 = 27) with four holes; the hole edges have plateau walls going up: shared with S_O, giving 4 outer loops (the footprints, area 1+2+2+4 = 9); L- = 36, L+ = 9",
        ..ZERO
    },
    Expected {
        dataset: "platform_grid",
        level: (3, 2),
        contours_outer: 4,
        area_contours: (9, 1),
        area_below: (9, 1),
        area_above: (9, 1),
        why: "regular: the four plateaus, 4 loops, area 9",
        ..ZERO
    },
    Expected {
        dataset: "platform_grid",
        level: (2, 1),
        faces_up: 4,
        area_below: (9, 1),
        area_faces_up: (9, 1),
        why: "four plateau tops -> 4 separate up regions of total area 9; no S_O; L- = 9, L+ empty",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (0, 1),
        faces_down: 1,
        area_above: (16, 1),
        area_faces_down: (16, 1),
        why: "bottom [-2,2]^2 (fan of 8) -> one down region of area 16; L- empty, L+ = 16",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (1, 2),
        contours_outer: 1,
        area_contours: (16, 1),
        area_below: (16, 1),
        area_above: (16, 1),
        why: "regular: the square, area 16",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (1, 1),
        contours_outer: 1,
        area_contours: (16, 1),
        area_below: (16, 1),
        area_above: (16, 1),
        why: "the four corners (+-2,+-2,1) lie in the plane; each has top neighbours above and wall-bottom neighbours below: regular, 2 branches. Slice = full square, area 16",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (3, 2),
        contours_outer: 1,
        area_contours: (14, 1),
        area_below: (14, 1),
        area_above: (14, 1),
        why: "slice {f >= z} of the top height field over [-2,2]^2; {f < z} is four notches at the low corners (f = 1): in each of its two triangles (area 2) a corner cut at parameters z-1 toward v (f = 2) and (z-1)/2 toward a midpoint (f = 3), area (z-1)^2; total 16 - 8(z-1)^2 = 14; the notches open to the boundary: one loop",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (2, 1),
        contours_outer: 1,
        saddles: &[8],
        area_contours: (8, 1),
        area_below: (8, 1),
        area_above: (8, 1),
        why: "v = (0,0,2): link 3 1 3 1 3 1 3 1, eight branches (m = 4). Slice = four triangles (v, (2,-1), (2,1)) etc. of area 2 each touching at v: area 8 (continuous). Material lies in the sectors above; the pairing joins across the sectors below, which links the four triangles into ONE weakly simple outer loop through v four times",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (5, 2),
        contours_outer: 4,
        area_contours: (2, 1),
        area_below: (2, 1),
        area_above: (2, 1),
        why: "slice {f >= z} of the top height field over [-2,2]^2; four separate triangles, area 8(3-z)^2 = 2",
        ..ZERO
    },
    Expected {
        dataset: "saddle8",
        level: (3, 1),
        maxima: 4,
        why: "the four side midpoints (2,0,3), (0,2,3), ... have all neighbours below -> 4 maxima; L- shrinks to them",
        ..ZERO
    },
];
