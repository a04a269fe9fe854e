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

use std::collections::HashMap;

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
    if triangles.len() > MAX_ELEMENTS {
        return Err(WeldError::TooManyElements {
            what: "triangles",
            limit: MAX_ELEMENTS,
        });
    }
    let corners = triangles.len().saturating_mul(3);
    let mut index: HashMap<[u64; 3], u32, ahash::RandomState> =
        HashMap::with_capacity_and_hasher(triangles.len(), ahash::RandomState::new());
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(triangles.len());
    let mut faces: Vec<[VertexId; 3]> = Vec::with_capacity(triangles.len());

    for tri in triangles {
        let mut face = [VertexId(0); 3];
        for (slot, p) in face.iter_mut().zip(tri.iter()) {
            let key = corner_key(p);
            if let Some(&id) = key.as_ref().and_then(|k| index.get(k)) {
                *slot = VertexId(id);
                continue;
            }
            let id = u32::try_from(positions.len())
                .ok()
                .filter(|&id| (id as usize) < MAX_ELEMENTS)
                .ok_or(WeldError::TooManyElements {
                    what: "vertices",
                    limit: MAX_ELEMENTS,
                })?;
            if let Some(k) = key {
                index.insert(k, id);
            }
            positions.push(*p);
            *slot = VertexId(id);
        }
        faces.push(face);
    }

    let vertices = positions.len();
    Ok(Welded {
        mesh: Mesh { positions, faces },
        corners,
        vertices,
    })
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
}
