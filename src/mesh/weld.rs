//! Input: a triangle soup (three corner positions per triangle, as STL holds
//! it). Output: an indexed [`Mesh`] whose vertices are the distinct corner
//! positions, merged by EXACT equality of coordinate values.
//!
//! Exact equality means `==` on `f64`: `-0.0` and `+0.0` are one coordinate,
//! and a NaN equals nothing, so every corner with a NaN coordinate becomes a
//! vertex of its own (validation reports non-finite coordinates later). No
//! distance tolerance is ever used. Vertex ids are given in first-seen order,
//! so the result is deterministic. Linear time (one hash lookup per corner,
//! with a randomly keyed hash so that no file can be crafted to collide).

use hashbrown::HashTable;

use super::Mesh;
use crate::ids::VertexId;

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
fn coordinate_key(x: f64) -> u64 {
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
    weld_triangles(triangles.len(), |t| triangles[t])
}

/// Welds the `n` triangles whose corners `corners(t)` gives (`t < n`), by
/// exact coordinate equality, without a soup in memory: the binary STL
/// reader passes a view of the file's records.
///
/// The table holds vertex ids only (four bytes a slot); a lookup compares
/// the corner with the kept vertex's coordinates, so the hot data is the
/// table and the vertices seen so far, not one key copy per vertex.
pub fn weld_triangles(
    n: usize,
    corners: impl Fn(usize) -> [[f64; 3]; 3],
) -> Result<Welded, WeldError> {
    if n > MAX_ELEMENTS {
        return Err(WeldError::TooManyElements {
            what: "triangles",
            limit: MAX_ELEMENTS,
        });
    }
    let hasher = ahash::RandomState::new();
    // A closed mesh has about half as many vertices as faces.
    let mut index: HashTable<u32> = HashTable::with_capacity(n / 2 + 4);
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(n / 2 + 4);
    let mut faces: Vec<[VertexId; 3]> = Vec::with_capacity(n);
    let too_many = WeldError::TooManyElements {
        what: "vertices",
        limit: MAX_ELEMENTS,
    };
    for t in 0..n {
        let mut face = [VertexId(0); 3];
        for (slot, p) in face.iter_mut().zip(corners(t)) {
            let key = corner_key(&p);
            let hash = key.map(|k| hasher.hash_one(k));
            if let (Some(k), Some(h)) = (key, hash) {
                if let Some(&id) = index.find(h, |&id| kept_key(&positions, id) == k) {
                    *slot = VertexId(id);
                    continue;
                }
            }
            let id = u32::try_from(positions.len())
                .ok()
                .filter(|&id| (id as usize) < MAX_ELEMENTS)
                .ok_or(too_many)?;
            positions.push(p);
            if let Some(h) = hash {
                index.insert_unique(h, id, |&id| hasher.hash_one(kept_key(&positions, id)));
            }
            *slot = VertexId(id);
        }
        faces.push(face);
    }
    let vertices = positions.len();
    Ok(Welded {
        mesh: Mesh { positions, faces },
        corners: n * 3,
        vertices,
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
            let w = weld_exact(&soup);
            let (positions, faces) = weld_by_search(&soup);
            proptest::prop_assert_eq!(&w.mesh.faces, &faces);
            let bits = |v: &[[f64; 3]]| -> Vec<[u64; 3]> {
                v.iter().map(|p| p.map(f64::to_bits)).collect()
            };
            proptest::prop_assert_eq!(bits(&w.mesh.positions), bits(&positions));
        }
    }
}
