//! Input: a [`Slicer`]. Output: the critical levels found the slow,
//! independent way: the complete level set at every distinct vertex height
//! ([`Slicer::slice_at`]), classified from what it holds (face regions,
//! ridges and valleys, extrema, saddles) with its L- and L+ loop counts.
//!
//! `O(n)` per height, so `O(n^2)` for a mesh: the reference answer for
//! tests and adversarial generators, not for large meshes. It shares no
//! code with [`super::analyze`] beyond the slicer itself.

use super::CriticalLevel;
use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::rational::rat_from_f64;
use crate::levelset::{LevelSet, SliceError, Slicer};

/// The [`CriticalLevel`] of one level set, or `None` when it holds no
/// critical element (no face region, ridge, valley, extremum or saddle).
pub fn classify_level(ls: &LevelSet) -> Option<CriticalLevel> {
    let critical = !ls.regions.is_empty()
        || !ls.ridges.is_empty()
        || !ls.extrema.is_empty()
        || !ls.saddles.is_empty();
    if !critical {
        return None;
    }
    let facing = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
    let ridges = |k: RidgeKind| ls.ridges.iter().filter(|r| r.kind == k).count();
    let points = |k: ExtremumKind| ls.extrema.iter().filter(|p| p.kind == k).count();
    let mut saddles = ls.saddles.clone();
    saddles.sort_unstable_by_key(|s| s.vertex);
    Some(CriticalLevel {
        z: ls.level.clone(),
        faces_up: facing(Facing::Up),
        faces_down: facing(Facing::Down),
        ridges: ridges(RidgeKind::Ridge),
        valleys: ridges(RidgeKind::Valley),
        minima: points(ExtremumKind::Min),
        maxima: points(ExtremumKind::Max),
        saddles: saddles.iter().map(|s| s.m()).collect(),
        below: ls.below.len(),
        above: ls.above.len(),
    })
}

/// Every critical level of the mesh, ascending, by slicing at every
/// distinct height of a vertex that some face uses.
///
/// ```
/// use wmslice::{critical, datasets, Slicer};
/// let mesh = datasets::by_name("double_torus").unwrap().build();
/// let slicer = Slicer::new(&mesh).unwrap();
/// let slow = critical::brute_force::classify_all(&slicer).unwrap();
/// assert_eq!(slow, critical::analyze(&slicer).unwrap().levels);
/// // z = 2: the monkey saddle (m = 3), four loops below and two above.
/// assert_eq!(slow[2].saddles, [3]);
/// ```
pub fn classify_all(slicer: &Slicer<'_>) -> Result<Vec<CriticalLevel>, SliceError> {
    let mesh = slicer.mesh();
    let mut used = vec![false; mesh.num_vertices()];
    for f in &mesh.faces {
        for v in f {
            used[v.idx()] = true;
        }
    }
    let mut heights: Vec<f64> = mesh
        .positions
        .iter()
        .zip(&used)
        .filter(|(_, &u)| u)
        .map(|(p, _)| p[2] + 0.0)
        .collect();
    heights.sort_unstable_by(f64::total_cmp);
    heights.dedup();
    let mut out = Vec::new();
    for z in heights {
        let c = rat_from_f64(z) * slicer.unit();
        let ls = slicer.slice_at(&c)?;
        out.extend(classify_level(&ls));
    }
    Ok(out)
}
