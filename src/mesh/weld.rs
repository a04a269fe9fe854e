//! Input: a triangle soup (three corner positions per triangle, as STL holds
//! it). Output: an indexed [`Mesh`] whose vertices are the distinct corner
//! positions, merged by EXACT equality of coordinate values. Also, on
//! request (`--weld`), the same merge for an indexed mesh whose distinct
//! vertices share a point ([`weld_coincident`]).
//!
//! Exact equality means `==` on `f64`: `-0.0` and `+0.0` are one coordinate,
//! and a NaN equals nothing, so every corner with a NaN coordinate becomes a
//! vertex of its own (validation reports non-finite coordinates later). No
//! distance tolerance is ever used. Vertex ids are given in first-seen order,
//! so the result is deterministic, whatever the number of threads. Linear
//! time (one hash lookup per corner, and one per vertex of each parallel
//! run when the runs are merged, with a randomly keyed hash so that no file
//! can be crafted to collide).

use rayon::prelude::*;

mod table;
use table::Table;

use super::io::ExactPositions;
use super::Mesh;
use crate::ids::VertexId;
use crate::par;

/// The largest number of vertices (and of faces) a mesh may have.
pub const MAX_ELEMENTS: usize = (u32::MAX - 1) as usize;

/// A welded mesh and what welding did.
#[derive(Clone, Debug, PartialEq)]
pub struct Welded {
    /// The indexed mesh: faces in input order, vertices in first-seen order.
    pub mesh: Mesh,
    /// Corners read (three per triangle).
    pub corners: usize,
    /// Distinct vertices kept.
    pub vertices: usize,
}

/// Welding failed: the soup has more distinct corners than ids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum WeldError {
    /// More than [`MAX_ELEMENTS`] triangles or distinct vertices.
    #[error("too many {what} to weld: more than {limit}")]
    TooManyElements {
        /// "triangles" or "vertices".
        what: &'static str,
        /// The limit exceeded.
        limit: usize,
    },
}

/// The hash key of one coordinate: its bit pattern with `-0.0` folded onto
/// `+0.0`. Only called for non-NaN values (NaN corners are never looked up).
#[inline]
pub(crate) fn coordinate_key(x: f64) -> u64 {
    if x == 0.0 {
        0
    } else {
        x.to_bits()
    }
}

/// Welds a triangle soup by exact coordinate equality.
///
/// # Panics
///
/// Only when the soup has more than [`MAX_ELEMENTS`] triangles or distinct
/// vertices (over 100 GB of input); the loaders call [`try_weld_exact`],
/// which returns an error instead.
pub fn weld_exact(triangles: &[[[f64; 3]; 3]]) -> Welded {
    match try_weld_exact(triangles) {
        Ok(w) => w,
        Err(e) => panic!("weld_exact: {e}"),
    }
}

/// Welds a triangle soup by exact coordinate equality, failing (instead of
/// panicking) when the ids would not fit in `u32`.
pub fn try_weld_exact(triangles: &[[[f64; 3]; 3]]) -> Result<Welded, WeldError> {
    weld_corners(triangles.len(), |i| triangles[i / 3][i % 3])
}

/// Welds the `n` triangles whose corner `c` of triangle `t` is
/// `corner(3 t + c)`, by exact coordinate equality, without a soup in
/// memory: the binary STL reader passes a view of the file's records.
///
/// Large inputs are welded in parallel on the caller's rayon pool: each
/// run of consecutive triangles on its own (corners of nearby triangles
/// are mostly the same vertices, so each table stays hot in cache), then
/// each run's vertices are looked up in the earlier runs' tables (in
/// parallel) and numbered in first-seen order. The result does not
/// depend on the number of threads.
pub fn weld_corners(
    n: usize,
    corner: impl Fn(usize) -> [f64; 3] + Sync,
) -> Result<Welded, WeldError> {
    if n > MAX_ELEMENTS {
        return Err(WeldError::TooManyElements {
            what: "triangles",
            limit: MAX_ELEMENTS,
        });
    }
    let runs = if n >= PARALLEL_FROM {
        rayon::current_num_threads()
    } else {
        1
    };
    weld_in_runs(n, &corner, runs)
}

/// Welds a list of points by exact coordinate equality, in one run (one
/// thread): the distinct points in first-seen order and each point's id
/// among them. Snapping merges the vertices that land on one grid point
/// with it ([`crate::mesh::snap`]).
pub(crate) fn weld_points(points: &[[f64; 3]]) -> Result<(Vec<[f64; 3]>, Vec<u32>), WeldError> {
    if points.len() > MAX_ELEMENTS {
        return Err(TOO_MANY_VERTICES);
    }
    let hasher = ahash::RandomState::new();
    let run = weld_run(0..points.len(), points.len(), &|i| points[i], &hasher)?;
    Ok((run.positions, run.ids))
}

/// An indexed mesh with its vertices at exactly one point merged
/// ([`weld_coincident`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CoincidentWelded {
    /// The mesh: vertices in first-seen order, faces in input order.
    pub mesh: Mesh,
    /// The exact positions, renumbered as the vertices were.
    pub exact: ExactPositions,
    /// Vertices merged into an earlier one at the same point.
    pub merged: usize,
}

/// Merges the vertices of an indexed mesh that lie at exactly one point
/// (`==` on every coordinate, so `-0` and `+0` are one): each face corner
/// goes to the first vertex at its point, and the vertices are renumbered
/// in first-seen order. Never merged: a vertex with a NaN coordinate
/// (validation names it) and a vertex in `exact`, whose double is not its
/// position. A face index out of range stays out of range (validation
/// names it).
pub fn weld_coincident(mesh: &Mesh, exact: &ExactPositions) -> CoincidentWelded {
    let n = mesh.num_vertices();
    let mut apart = vec![false; n];
    for (v, _) in exact.iter() {
        if let Some(a) = apart.get_mut(v.idx()) {
            *a = true;
        }
    }
    let mut first: std::collections::HashMap<[u64; 3], u32, ahash::RandomState> =
        std::collections::HashMap::with_capacity_and_hasher(n, ahash::RandomState::new());
    let mut positions = Vec::with_capacity(n);
    let mut new_id = Vec::with_capacity(n);
    for (p, &apart) in mesh.positions.iter().zip(&apart) {
        let fresh = |positions: &mut Vec<[f64; 3]>| {
            positions.push(*p);
            (positions.len() - 1) as u32
        };
        let id = if apart || p.iter().any(|x| x.is_nan()) {
            fresh(&mut positions)
        } else {
            *first
                .entry(p.map(coordinate_key))
                .or_insert_with(|| fresh(&mut positions))
        };
        new_id.push(id);
    }
    let faces = mesh
        .faces
        .iter()
        .map(|t| t.map(|v| new_id.get(v.idx()).map_or(v, |&id| VertexId(id))))
        .collect();
    CoincidentWelded {
        merged: n - positions.len(),
        exact: exact.renumbered(&new_id),
        mesh: Mesh { positions, faces },
    }
}

/// Triangles from which welding is split into runs.
const PARALLEL_FROM: usize = 1 << 14;

const TOO_MANY_VERTICES: WeldError = WeldError::TooManyElements {
    what: "vertices",
    limit: MAX_ELEMENTS,
};

/// Corners `range` welded with one table of vertex ids (eight bytes a
/// slot; a lookup compares the corner with the kept vertex's
/// coordinates): the distinct positions in first-seen order, each
/// corner's id among them, and the table.
struct Run {
    positions: Vec<[f64; 3]>,
    ids: Vec<u32>,
    index: Table,
}

/// A corner read, with its key and the key's hash (`None`: a NaN
/// coordinate, never merged).
#[derive(Clone, Copy)]
struct Corner {
    p: [f64; 3],
    key: Option<([u64; 3], u64)>,
}

/// How many corners ahead of the one being welded the table's slot is
/// asked for (a 1 M-triangle STL: 4 slower; 8, 16 and 32 alike).
const AHEAD: usize = 16;

/// `vertices`: the room to make for distinct positions.
fn weld_run(
    range: std::ops::Range<usize>,
    vertices: usize,
    corner: &impl Fn(usize) -> [f64; 3],
    hasher: &ahash::RandomState,
) -> Result<Run, WeldError> {
    let mut run = Run {
        positions: Vec::with_capacity(vertices),
        ids: Vec::with_capacity(range.len()),
        index: Table::with_capacity(vertices),
    };
    let read = |i: usize| {
        let p = corner(i);
        let key = corner_key(&p).map(|k| (k, hasher.hash_one(k)));
        Corner { p, key }
    };
    // The next AHEAD corners, read and their slots asked for: corner i is
    // at i % AHEAD until it is welded.
    let mut ahead = [Corner {
        p: [0.0; 3],
        key: None,
    }; AHEAD];
    for i in range.clone().take(AHEAD) {
        ahead[i % AHEAD] = read(i);
        run.prefetch(&ahead[i % AHEAD]);
    }
    for i in range.clone() {
        let c = ahead[i % AHEAD];
        if i + AHEAD < range.end {
            ahead[i % AHEAD] = read(i + AHEAD);
            run.prefetch(&ahead[i % AHEAD]);
        }
        let id = run.id_of(c, hasher)?;
        run.ids.push(id);
    }
    Ok(run)
}

impl Run {
    fn prefetch(&self, c: &Corner) {
        if let Some((_, h)) = c.key {
            self.index.prefetch(h);
        }
    }

    /// The id of the vertex at `c`, a new one if it was not seen (or has a
    /// NaN coordinate).
    fn id_of(&mut self, c: Corner, hasher: &ahash::RandomState) -> Result<u32, WeldError> {
        let positions = &self.positions;
        if let Some((k, h)) = c.key {
            if let Some(id) = self.index.find(h, |id| kept_key(positions, id) == k) {
                return Ok(id);
            }
        }
        let id = u32::try_from(self.positions.len())
            .ok()
            .filter(|&id| (id as usize) < MAX_ELEMENTS)
            .ok_or(TOO_MANY_VERTICES)?;
        self.positions.push(c.p);
        if let Some((_, h)) = c.key {
            let positions = &self.positions;
            self.index
                .insert(h, id, |id| hasher.hash_one(kept_key(positions, id)));
        }
        Ok(id)
    }
}

/// Welds in `runs` runs of consecutive triangles, in parallel, then numbers
/// the runs' vertices in order.
fn weld_in_runs(
    n: usize,
    corner: &(impl Fn(usize) -> [f64; 3] + Sync),
    runs: usize,
) -> Result<Welded, WeldError> {
    let hasher = ahash::RandomState::new();
    let per_run = n.div_ceil(runs.max(1)).max(1) * 3;
    let ranges: Vec<std::ops::Range<usize>> = (0..3 * n)
        .step_by(per_run)
        .map(|s| s..(s + per_run).min(3 * n))
        .collect();
    // A closed mesh has about half as many vertices as faces, a sixth of
    // its corners.
    let weld = |r: std::ops::Range<usize>| weld_run(r.clone(), r.len() / 5 + 4, corner, &hasher);
    // One run stays on this thread (no hand-over to the pool).
    let parts: Result<Vec<Run>, WeldError> = if ranges.len() > 1 {
        ranges.into_par_iter().map(weld).collect()
    } else {
        ranges.into_iter().map(weld).collect()
    };
    let parts = parts?;
    // Each later run's vertices looked up in the earlier runs' tables (in
    // parallel: the tables are only read), then numbered in order: a
    // vertex takes the id it has in the first run holding it, and one no
    // earlier run holds takes the next new id. That is the first-seen
    // order of a weld in one run.
    let found: Vec<Vec<Option<(u32, u32)>>> = parts
        .iter()
        .skip(1)
        .enumerate()
        .map(|(k, part)| {
            let earlier = &parts[..=k];
            let look = |p: &[f64; 3]| {
                let key = corner_key(p)?;
                let hash = hasher.hash_one(key);
                earlier.iter().enumerate().find_map(|(j, run)| {
                    let id = run
                        .index
                        .find(hash, |id| kept_key(&run.positions, id) == key)?;
                    Some((j as u32, id))
                })
            };
            if part.positions.len() >= par::MIN_LEN {
                part.positions
                    .par_iter()
                    .with_min_len(par::MIN_LEN)
                    .map(look)
                    .collect()
            } else {
                part.positions.iter().map(look).collect()
            }
        })
        .collect();
    let runs = parts.len();
    let mut parts = parts.into_iter();
    let Some(first) = parts.next() else {
        return Ok(Welded {
            vertices: 0,
            corners: 0,
            mesh: Mesh::default(),
        });
    };
    let mut global: Vec<Vec<u32>> = vec![(0..first.positions.len() as u32).collect()];
    let mut local: Vec<Vec<u32>> = vec![first.ids];
    let mut positions = first.positions;
    for (part, found) in parts.zip(&found) {
        let mut ids = Vec::with_capacity(found.len());
        for (p, f) in part.positions.iter().zip(found) {
            ids.push(match *f {
                Some((j, id)) => global[j as usize][id as usize],
                None => {
                    let id = u32::try_from(positions.len())
                        .ok()
                        .filter(|&id| (id as usize) < MAX_ELEMENTS)
                        .ok_or(TOO_MANY_VERTICES)?;
                    positions.push(*p);
                    id
                }
            });
        }
        global.push(ids);
        local.push(part.ids);
    }
    // Corner ids through each run's numbering, run by run in parallel.
    let mut faces = par::filled([VertexId(0); 3], n);
    let mut rest = &mut faces[..];
    let mut pieces = Vec::with_capacity(runs);
    for (local, ids) in local.iter().zip(&global) {
        let (mine, more) = rest.split_at_mut(local.len() / 3);
        pieces.push((mine, local, ids));
        rest = more;
    }
    let fill = |(faces, local, ids): (&mut [[VertexId; 3]], &Vec<u32>, &Vec<u32>)| {
        for (f, c) in faces.iter_mut().zip(local.chunks_exact(3)) {
            *f = [c[0], c[1], c[2]].map(|l| VertexId(ids[l as usize]));
        }
    };
    if pieces.len() > 1 {
        pieces.into_par_iter().for_each(fill);
    } else {
        pieces.into_iter().for_each(fill);
    }
    Ok(Welded {
        vertices: positions.len(),
        corners: 3 * n,
        mesh: Mesh { positions, faces },
    })
}

/// The key of a kept vertex (never NaN: NaN corners are not in the table).
#[inline]
fn kept_key(positions: &[[f64; 3]], id: u32) -> [u64; 3] {
    positions[id as usize].map(coordinate_key)
}

/// The key of a corner, or `None` when a coordinate is NaN (never merged).
#[inline]
fn corner_key(p: &[f64; 3]) -> Option<[u64; 3]> {
    if p.iter().any(|x| x.is_nan()) {
        None
    } else {
        Some([
            coordinate_key(p[0]),
            coordinate_key(p[1]),
            coordinate_key(p[2]),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_zeros_merge_and_nans_stay_apart() {
        let soup = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [
                [-0.0, 0.0, -0.0],
                [f64::NAN, 0.0, 0.0],
                [f64::NAN, 0.0, 0.0],
            ],
        ];
        let w = weld_exact(&soup);
        assert_eq!(w.corners, 6);
        assert_eq!(w.vertices, 5);
        assert_eq!(w.mesh.faces[1][0], VertexId(0));
        assert_eq!(w.mesh.faces[1][1], VertexId(3));
        assert_eq!(w.mesh.faces[1][2], VertexId(4));
    }

    #[test]
    fn ids_follow_first_seen_order() {
        let soup = [
            [[2.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [5.0, 5.0, 5.0]],
        ];
        let w = weld_exact(&soup);
        assert_eq!(
            w.mesh.positions,
            vec![
                [2.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [5.0, 5.0, 5.0]
            ]
        );
        assert_eq!(w.mesh.faces[1], [VertexId(2), VertexId(1), VertexId(3)]);
    }

    /// A reference weld: a linear search over the vertices kept so far.
    fn weld_by_search(soup: &[[[f64; 3]; 3]]) -> (Vec<[f64; 3]>, Vec<[VertexId; 3]>) {
        let mut positions: Vec<[f64; 3]> = Vec::new();
        let faces = soup
            .iter()
            .map(|tri| {
                tri.map(|p| {
                    let same = |q: &[f64; 3]| (0..3).all(|k| p[k] == q[k]);
                    let found = positions.iter().position(same);
                    VertexId::from_idx(found.unwrap_or_else(|| {
                        positions.push(p);
                        positions.len() - 1
                    }))
                })
            })
            .collect();
        (positions, faces)
    }

    /// Runs on many threads (of a pool of 3): the weld equals the linear
    /// search on 20000 triangles over a few hundred distinct corners.
    #[test]
    fn sharded_weld_over_many_blocks_agrees_with_linear_search() {
        // Enough distinct corners that each run looks its vertices up in
        // parallel, and enough repeats that runs share many.
        let values: Vec<f64> = (0..40)
            .map(|k| f64::from(k) * 0.1)
            .chain([-0.0, f64::NAN])
            .collect();
        let mut state = 12345u64;
        let mut pick = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            values[(state >> 33) as usize % values.len()]
        };
        let soup: Vec<[[f64; 3]; 3]> = (0..20_000)
            .map(|_| {
                [
                    [pick(), pick(), pick()],
                    [pick(), pick(), pick()],
                    [pick(), pick(), pick()],
                ]
            })
            .collect();
        assert!(soup.len() >= PARALLEL_FROM);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let w = pool.install(|| weld_exact(&soup));
        let (positions, faces) = weld_by_search(&soup);
        assert!(positions.len() > 3 * par::MIN_LEN);
        assert_eq!(w.mesh.faces, faces);
        assert_eq!(w.mesh.positions.len(), positions.len());
    }

    /// A soup whose corners are mostly distinct (three times the room the
    /// table is made with, so it grows while corners are asked for ahead):
    /// the weld still equals the linear search.
    #[test]
    fn mostly_distinct_corners_grow_the_table() {
        let soup: Vec<[[f64; 3]; 3]> = (0..1000u32)
            .map(|t| {
                let p = |k: u32| {
                    let v = f64::from((t * 3 + k) % 2500);
                    [v, -v * 0.5, f64::from(k)]
                };
                [p(0), p(1), p(2)]
            })
            .collect();
        let (positions, faces) = weld_by_search(&soup);
        assert!(positions.len() > 2000);
        let w = weld_exact(&soup);
        assert_eq!(w.mesh.faces, faces);
        assert_eq!(w.mesh.positions, positions);
    }

    /// Coordinates across the whole `f64` and `f32` range, decimals, both
    /// zeros, NaN, and a few values that repeat (so that the mesh itself
    /// has coincident vertices).
    fn coordinate() -> impl proptest::strategy::Strategy<Value = f64> {
        use proptest::prelude::*;
        prop_oneof![
            any::<u64>().prop_map(f64::from_bits),
            any::<u32>().prop_map(|b| f64::from(f32::from_bits(b))),
            (-1000i32..1000).prop_map(|k| f64::from(k) * 0.001),
            proptest::sample::select(vec![0.0, -0.0, 1.0, f64::NAN, 3.6e-16]),
        ]
    }

    /// The vertices of an indexed mesh by linear search: each vertex goes
    /// to the first vertex equal to it (`==` on every coordinate; NaN
    /// equals nothing).
    fn weld_indexed_by_search(positions: &[[f64; 3]]) -> Vec<usize> {
        (0..positions.len())
            .map(|i| (0..i).find(|&j| positions[j] == positions[i]).unwrap_or(i))
            .collect()
    }

    #[test]
    fn vertices_with_exact_positions_or_nan_are_never_welded() {
        use crate::exact::rational::Rat;
        // Vertex 2's double equals vertex 0's, but its exact position is
        // not that double (a 3MF transform's image); vertices 3 and 4 hold
        // a NaN. Only vertex 5 (vertex 1 with -0 for +0) merges.
        let nan = f64::NAN;
        let m = Mesh::from_raw(
            vec![
                [0.5, 0.0, 1.0],
                [0.0, 2.0, 0.0],
                [0.5, 0.0, 1.0],
                [nan, 0.0, 0.0],
                [nan, 0.0, 0.0],
                [-0.0, 2.0, 0.0],
                [7.0, 7.0, 7.0],
            ],
            vec![[0, 1, 2], [3, 4, 5], [5, 6, 2], [9, 5, 0]],
        );
        let third = Rat::new(1.into(), 3.into());
        let mut exact = ExactPositions::default();
        exact.push_for_test(VertexId(2), [third.clone(), third.clone(), third.clone()]);
        exact.push_for_test(VertexId(6), [third.clone(), third.clone(), third.clone()]);
        let w = weld_coincident(&m, &exact);
        assert_eq!(w.merged, 1);
        let ids = |f: [u32; 3]| f.map(VertexId);
        // Renumbered 0 1 2 3 4 (1) 5; index 9 stays out of range.
        assert_eq!(
            w.mesh.faces,
            [[0, 1, 2], [3, 4, 1], [1, 5, 2], [9, 1, 0]].map(ids)
        );
        assert_eq!(
            w.mesh.positions[1].map(f64::to_bits),
            [0.0, 2.0, 0.0].map(f64::to_bits)
        );
        assert_eq!(w.mesh.positions[5], [7.0, 7.0, 7.0]);
        let renamed: Vec<VertexId> = w.exact.iter().map(|(v, _)| *v).collect();
        assert_eq!(renamed, [VertexId(2), VertexId(5)]);
        assert_eq!(
            w.exact.iter().next().map(|(_, p)| p[0].clone()),
            Some(third)
        );
    }

    proptest::proptest! {
        /// Coordinates from a small set (with both zeros and NaN), so that
        /// corners repeat often: the table agrees with the linear search,
        /// bit for bit, including which of `-0.0` and `0.0` is kept.
        #[test]
        fn table_agrees_with_linear_search(
            picks in proptest::collection::vec(0usize..6, 0..300)
        ) {
            let values = [0.0, -0.0, 1.0, 0.1f32 as f64, f64::NAN, -3.5];
            let soup: Vec<[[f64; 3]; 3]> = picks
                .chunks_exact(9)
                .map(|c| {
                    let p = |k: usize| [values[c[k]], values[c[k + 1]], values[c[k + 2]]];
                    [p(0), p(3), p(6)]
                })
                .collect();
            let (positions, faces) = weld_by_search(&soup);
            let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                v.iter().map(|p| p.map(f64::to_bits)).collect()
            };
            let corner = |i: usize| soup[i / 3][i % 3];
            let n = soup.len();
            // One run and several, whatever weld_exact would pick here.
            for w in (1..5).map(|runs| weld_in_runs(n, &corner, runs)) {
                let w = w.unwrap();
                proptest::prop_assert_eq!(&w.mesh.faces, &faces);
                proptest::prop_assert_eq!(bits(&w.mesh.positions), bits(&positions));
                proptest::prop_assert_eq!(w.corners, 3 * n);
            }
            // The corners as a list of points: the same vertices and ids.
            let points: Vec<[f64; 3]> = (0..3 * n).map(corner).collect();
            let (kept, ids) = weld_points(&points).unwrap();
            let ids: Vec<[VertexId; 3]> = ids
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]].map(VertexId))
                .collect();
            proptest::prop_assert_eq!(&ids, &faces);
            proptest::prop_assert_eq!(bits(&kept), bits(&positions));
        }

        /// Seams made on purpose: a mesh over coordinates drawn across the
        /// whole `f64` and `f32` range, some vertices copied (zeros turned
        /// to `-0`) and some face corners moved onto the copies. Welding
        /// agrees with the linear search; where the original vertices were
        /// distinct and free of NaN, it gives back the original mesh, bit
        /// for bit.
        #[test]
        fn welding_undoes_copied_vertices(
            base in proptest::collection::vec(
                proptest::array::uniform3(coordinate()), 3..12),
            faces in proptest::collection::vec(proptest::array::uniform3(0usize..100), 1..16),
            copies in proptest::collection::vec((0usize..100, 0usize..100), 0..20),
        ) {
            let n = base.len();
            let faces: Vec<[u32; 3]> = faces.iter().map(|f| f.map(|i| (i % n) as u32)).collect();
            let mut positions = base.clone();
            let mut moved = faces.clone();
            for &(v, corner) in &copies {
                let v = v % n;
                positions.push(base[v].map(|x| if x == 0.0 { -x } else { x }));
                let c = corner % (3 * moved.len());
                if moved[c / 3][c % 3] as usize == v {
                    moved[c / 3][c % 3] = (positions.len() - 1) as u32;
                }
            }
            let seamed = Mesh::from_raw(positions.clone(), moved.clone());
            let w = weld_coincident(&seamed, &ExactPositions::default());
            let first = weld_indexed_by_search(&positions);
            // First-seen numbering of the linear search's representatives.
            let mut number = vec![None; positions.len()];
            let mut kept = Vec::new();
            for (i, &r) in first.iter().enumerate() {
                if r == i {
                    number[i] = Some(kept.len() as u32);
                    kept.push(positions[i]);
                }
            }
            let want: Vec<[VertexId; 3]> = moved
                .iter()
                .map(|f| f.map(|v| VertexId(number[first[v as usize]].unwrap())))
                .collect();
            let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                v.iter().map(|p| p.map(f64::to_bits)).collect()
            };
            proptest::prop_assert_eq!(&w.mesh.faces, &want);
            proptest::prop_assert_eq!(bits(&w.mesh.positions), bits(&kept));
            proptest::prop_assert_eq!(w.merged, positions.len() - kept.len());
            // The original vertices distinct and every copy merged (a copy
            // of a vertex with a NaN coordinate is not): the original mesh.
            if kept.len() == n {
                let original = Mesh::from_raw(base.clone(), faces.clone());
                proptest::prop_assert_eq!(&w.mesh.faces, &original.faces);
                proptest::prop_assert_eq!(bits(&w.mesh.positions), bits(&original.positions));
            }
        }
    }
}
