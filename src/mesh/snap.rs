//! Input: a mesh and a rational grid step `q`. Output: the mesh snapped to
//! the grid, stored as integer multiples of `q` (so every stored value is an
//! exact integer double), with vertices that land on one grid point welded.
//!
//! Snapping is the one explicit, reported rounding of coordinates (SPEC
//! section 2): each coordinate moves to the nearest multiple of `q` (ties
//! to even), by at most `q / 2`.

use crate::exact::rational::{rat_from_f64, rat_to_string, Rat};
use crate::ids::VertexId;
use crate::mesh::Mesh;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{Signed, ToPrimitive, Zero};
use std::collections::HashMap;

/// The largest grid index that a double holds exactly.
pub const MAX_GRID_INDEX: i64 = 1 << 53;

/// Why snapping failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SnapError {
    /// The grid step is zero or negative.
    #[error("snap grid must be positive, got {0}")]
    NonPositive(String),
    /// A coordinate is not finite.
    #[error("vertex {0} has a non-finite coordinate")]
    NonFinite(VertexId),
    /// A coordinate is too far from zero for this grid.
    #[error("vertex {vertex} is more than 2^53 grid steps of {q} from the origin: choose a coarser grid")]
    OutOfRange {
        /// The vertex.
        vertex: VertexId,
        /// The grid, as `p/q`.
        q: String,
    },
}

/// A snapped mesh and what snapping did.
#[derive(Debug, Clone)]
pub struct Snapped {
    /// The mesh in grid units: true coordinate = stored value * `unit`.
    pub mesh: Mesh,
    /// The grid step `q`.
    pub unit: Rat,
    /// Vertices whose position changed.
    pub moved: usize,
    /// The largest change of a single coordinate, exact.
    pub max_move: Rat,
    /// Vertices merged into another one that landed on the same point.
    pub merged: usize,
}

/// Nearest integer to `r`, ties to even.
fn round_half_even(r: &Rat) -> BigInt {
    let (q, rem): (BigInt, BigInt) = r.numer().div_mod_floor(r.denom());
    let twice: BigInt = rem * 2;
    match twice.cmp(r.denom()) {
        std::cmp::Ordering::Less => q,
        std::cmp::Ordering::Greater => q + 1,
        std::cmp::Ordering::Equal => {
            if q.is_even() {
                q
            } else {
                q + 1
            }
        }
    }
}

/// Snaps every coordinate to the nearest multiple of `q` and welds vertices
/// that coincide afterwards (exact equality). Faces keep their order.
pub fn snap(mesh: &Mesh, q: &Rat) -> Result<Snapped, SnapError> {
    if !q.is_positive() {
        return Err(SnapError::NonPositive(rat_to_string(q)));
    }
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(mesh.num_vertices());
    let mut remap: Vec<VertexId> = Vec::with_capacity(mesh.num_vertices());
    let mut seen: HashMap<[u64; 3], VertexId, ahash::RandomState> =
        HashMap::with_capacity_and_hasher(mesh.num_vertices(), ahash::RandomState::new());
    let mut moved = 0;
    let mut max_move = Rat::zero();
    for (v, p) in mesh.positions.iter().enumerate() {
        let vid = VertexId::from_idx(v);
        let mut out = [0.0f64; 3];
        let mut changed = false;
        for k in 0..3 {
            if !p[k].is_finite() {
                return Err(SnapError::NonFinite(vid));
            }
            let x = rat_from_f64(p[k]);
            let n = round_half_even(&(&x / q));
            let n64 = n
                .to_i64()
                .filter(|n| n.abs() <= MAX_GRID_INDEX)
                .ok_or_else(|| SnapError::OutOfRange {
                    vertex: vid,
                    q: rat_to_string(q),
                })?;
            let delta = (Rat::from_integer(n) * q - x).abs();
            if !delta.is_zero() {
                changed = true;
                if delta > max_move {
                    max_move = delta;
                }
            }
            // |n| <= 2^53: exact as a double; +0.0 for zero.
            out[k] = n64 as f64 + 0.0;
        }
        moved += changed as usize;
        let key = out.map(f64::to_bits);
        let id = *seen.entry(key).or_insert_with(|| {
            positions.push(out);
            VertexId::from_idx(positions.len() - 1)
        });
        remap.push(id);
    }
    let merged = mesh.num_vertices() - positions.len();
    let faces = mesh
        .faces
        .iter()
        .map(|t| t.map(|v| remap.get(v.idx()).copied().unwrap_or(v)))
        .collect();
    Ok(Snapped {
        mesh: Mesh { positions, faces },
        unit: q.clone(),
        moved,
        max_move,
        merged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;

    #[test]
    fn cad_plane_becomes_exact() {
        let m = Mesh::from_raw(vec![[0.6f32 as f64, 0.0, 1.0], [0.5, -0.25, 0.6]], vec![]);
        let q = parse_rational("1/10000").unwrap();
        let s = snap(&m, &q).unwrap();
        assert_eq!(s.mesh.positions[0], [6000.0, 0.0, 10000.0]);
        assert_eq!(s.mesh.positions[1], [5000.0, -2500.0, 6000.0]);
        assert_eq!(s.moved, 2);
        assert!(s.max_move <= &q / Rat::from_integer(2.into()));
        assert!(s.max_move.is_positive());
    }

    #[test]
    fn unwelded_corners_merge() {
        let a = 1.0f64;
        let m = Mesh::from_raw(
            vec![[a, 0.0, 0.0], [a.next_up(), 0.0, 0.0], [0.0, 0.0, 0.0]],
            vec![[0, 2, 1]],
        );
        let s = snap(&m, &parse_rational("0.001").unwrap()).unwrap();
        assert_eq!(s.merged, 1);
        assert_eq!(s.mesh.faces[0], [VertexId(0), VertexId(1), VertexId(0)]);
    }

    #[test]
    fn ties_go_to_even_and_range_is_checked() {
        assert_eq!(
            round_half_even(&parse_rational("5/2").unwrap()),
            BigInt::from(2)
        );
        assert_eq!(
            round_half_even(&parse_rational("-5/2").unwrap()),
            BigInt::from(-2)
        );
        assert_eq!(
            round_half_even(&parse_rational("7/2").unwrap()),
            BigInt::from(4)
        );
        let m = Mesh::from_raw(vec![[1e300, 0.0, 0.0]], vec![]);
        assert!(matches!(
            snap(&m, &parse_rational("1").unwrap()),
            Err(SnapError::OutOfRange { .. })
        ));
    }
}
