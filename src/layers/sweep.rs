//! Input: a slicer and ascending exact levels. Output: the level set of each
//! level, handed to a sink in ascending order.
//!
//! The sweep (after Minetto, Volpato, Stolfi et al., "An optimal algorithm
//! for 3D triangle mesh slicing", CAD 2017): each face is filed under the
//! first level at or above its lowest height (binary search, no sort of
//! the faces), enters the active set at that level and leaves when the
//! plane passes its highest one, so each level visits only the faces that
//! touch it; faces that touch no level are dropped when filed. Level `i` is computed by worker `i mod T`, each worker sweeping
//! its own levels upward and sending results through a bounded channel;
//! the caller's thread takes them in order. Memory is bounded by the
//! channels, not by the number of levels, and every level is computed from
//! the same sorted active faces, so the output does not depend on `T`.

use crate::exact::level::Bracket;
use crate::exact::rational::Rat;
use crate::exact::{Level, Sign};
use crate::ids::FaceId;
use crate::levelset::{LevelSet, SliceError, Slicer};
use std::sync::mpsc::{sync_channel, Receiver};

/// Results each worker may compute ahead of the writer.
const AHEAD: usize = 4;

/// Why a sweep stopped.
#[derive(Debug, thiserror::Error)]
pub enum SweepError<E: std::error::Error + 'static> {
    /// Slicing one level failed.
    #[error("level {index}: {source}")]
    Slice {
        /// The level's index in the plan.
        index: usize,
        /// The failure.
        #[source]
        source: SliceError,
    },
    /// The sink refused a level (e.g. an output error).
    #[error(transparent)]
    Sink(E),
    /// The worker threads could not be started.
    #[error("cannot start worker threads: {0}")]
    Threads(String),
}

/// Each face filed under the first level at or above its lowest height
/// (found by binary search over the levels: O(n log k) for n faces and k
/// levels, no sort), with each face's highest height. Faces above the
/// last level, or strictly between two levels, touch no level and are
/// left out at once.
struct Heights {
    grid: Vec<Level>,
    entering: Vec<Vec<FaceId>>,
    max: Vec<f64>,
}

impl Heights {
    fn new(slicer: &Slicer<'_>, levels: &[Rat]) -> Self {
        let mesh = slicer.mesh();
        let grid: Vec<Level> = levels.iter().map(|c| slicer.grid_level(c)).collect();
        let brackets: Vec<Bracket> = grid.iter().map(Level::bracket).collect();
        let mut entering = vec![Vec::new(); grid.len()];
        let mut max = Vec::with_capacity(mesh.num_faces());
        for (f, tri) in mesh.faces.iter().enumerate() {
            let z = tri.map(|v| mesh.positions[v.idx()][2]);
            let (lo, hi) = (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]));
            max.push(hi);
            // Levels below the face's lowest point: z_min > c, exactly.
            let first = brackets.partition_point(|l| l.sign_of(lo) == Sign::Positive);
            if first < grid.len() && brackets[first].sign_of(hi) != Sign::Negative {
                entering[first].push(FaceId::from_idx(f));
            }
        }
        Heights {
            grid,
            entering,
            max,
        }
    }
}

/// One worker's sweep state.
struct Sweep<'h> {
    heights: &'h Heights,
    next: usize,
    /// The faces touching the current level, ascending.
    active: Vec<FaceId>,
    /// Scratch for merging entering faces into `active`.
    merged: Vec<FaceId>,
}

impl<'h> Sweep<'h> {
    fn new(heights: &'h Heights) -> Self {
        Sweep {
            heights,
            next: 0,
            active: Vec::new(),
            merged: Vec::new(),
        }
    }

    /// Moves the plane up to level `index`: faces the plane has passed
    /// leave, faces filed up to `index` enter, and `active` stays
    /// ascending (one merge, no sort of the active set). Indices must come
    /// in ascending order.
    fn advance(&mut self, index: usize) {
        let h = self.heights;
        let level = &h.grid[index];
        let touching = |f: &FaceId| level.sign_of(h.max[f.idx()]) != Sign::Negative;
        self.active.retain(touching);
        let mut entering: Vec<FaceId> = h.entering[self.next.min(index + 1)..=index]
            .iter()
            .flatten()
            .copied()
            .filter(touching)
            .collect();
        self.next = self.next.max(index + 1);
        if entering.is_empty() {
            return;
        }
        // Each bucket is ascending; several (a worker skipping levels) are not.
        entering.sort_unstable();
        self.merged.clear();
        self.merged.reserve(self.active.len() + entering.len());
        let (mut i, mut j) = (0, 0);
        while i < self.active.len() && j < entering.len() {
            if self.active[i] < entering[j] {
                self.merged.push(self.active[i]);
                i += 1;
            } else {
                self.merged.push(entering[j]);
                j += 1;
            }
        }
        self.merged.extend_from_slice(&self.active[i..]);
        self.merged.extend_from_slice(&entering[j..]);
        std::mem::swap(&mut self.active, &mut self.merged);
    }

    /// Advances to level `index` (`c` in the mesh's units) and slices it.
    fn slice(
        &mut self,
        slicer: &Slicer<'_>,
        index: usize,
        c: &Rat,
    ) -> Result<LevelSet, SliceError> {
        self.advance(index);
        slicer.slice_active(c, &self.heights.grid[index], &self.active)
    }
}

/// Slices every level (ascending, distinct) with `threads` workers and hands
/// each level set, with its index, to `sink` in order.
pub fn slice_levels<E, S>(
    slicer: &Slicer<'_>,
    levels: &[Rat],
    threads: usize,
    mut sink: S,
) -> Result<(), SweepError<E>>
where
    E: std::error::Error + 'static,
    S: FnMut(usize, LevelSet) -> Result<(), E>,
{
    let threads = threads.clamp(1, levels.len().max(1));
    let heights = Heights::new(slicer, levels);
    let worker = |t: usize, tx: std::sync::mpsc::SyncSender<Result<LevelSet, SliceError>>| {
        let mut sweep = Sweep::new(&heights);
        for (index, c) in levels.iter().enumerate().skip(t).step_by(threads) {
            let result = sweep.slice(slicer, index, c);
            let failed = result.is_err();
            if tx.send(result).is_err() || failed {
                return;
            }
        }
    };
    if threads == 1 {
        // The same sweep on the caller's thread.
        let mut sweep = Sweep::new(&heights);
        for (index, c) in levels.iter().enumerate() {
            let ls = sweep
                .slice(slicer, index, c)
                .map_err(|source| SweepError::Slice { index, source })?;
            sink(index, ls).map_err(SweepError::Sink)?;
        }
        return Ok(());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Threads(e.to_string()))?;
    pool.in_place_scope(|scope| {
        let mut receivers: Vec<Receiver<Result<LevelSet, SliceError>>> =
            Vec::with_capacity(threads);
        for t in 0..threads {
            let (tx, rx) = sync_channel(AHEAD);
            receivers.push(rx);
            let worker = &worker;
            scope.spawn(move |_| worker(t, tx));
        }
        let mut outcome = Ok(());
        for index in 0..levels.len() {
            let received = receivers[index % threads].recv();
            let step = match received {
                Ok(Ok(ls)) => sink(index, ls).map_err(SweepError::Sink),
                Ok(Err(source)) => Err(SweepError::Slice { index, source }),
                Err(_) => Err(SweepError::Threads("a worker stopped early".into())),
            };
            if let Err(e) = step {
                outcome = Err(e);
                break;
            }
        }
        // Dropping the receivers unblocks any worker still sending.
        drop(receivers);
        outcome
    })
}
