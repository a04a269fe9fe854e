//! Input: a slicer and ascending exact levels. Output: the level set of each
//! level, handed to a sink in ascending order.
//!
//! The sweep (after Minetto, Volpato, Stolfi et al., "An optimal algorithm
//! for 3D triangle mesh slicing", CAD 2017): each face is filed under the
//! first level at or above its lowest height (an interpolated guess
//! confirmed exactly, else binary search; no sort of the faces), enters
//! the active set at that level and leaves when the plane passes its
//! highest one, so each level visits only the faces that touch it; faces
//! that touch no level are dropped when filed. With T workers each takes
//! the next level no one has taken yet (so a slow level, e.g. one on many
//! flat faces, holds up no one else's), sweeps its own levels upward and
//! sends results through a bounded channel; the caller's thread hands
//! them on in level order. At most a few levels per worker are taken
//! ahead of the last one handed on, so memory is bounded by that window,
//! not by the number of levels, and every level is computed from
//! the same sorted active faces, so the output does not depend on `T`.

use crate::exact::level::Bracket;
use crate::exact::rational::{rat_div, Rat};
use crate::exact::{Level, Sign};
use crate::ids::FaceId;
use crate::levelset::{LevelSet, SliceError, Slicer};
use crate::mesh::Mesh;
use crate::par;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::{Arc, Condvar, Mutex};

/// Results each worker may compute ahead of the writer.
const AHEAD: usize = 8;

/// Buckets of entering faces merged one by one into the active set; more
/// are sorted together first.
const MERGED_BUCKETS: usize = 4;

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

/// A face in the sweep, with its highest height.
#[derive(Clone, Copy, Debug)]
struct Entry {
    face: FaceId,
    top: f64,
}

/// Each face filed under the first level at or above its lowest height,
/// with its highest height (so the sweep never looks a face up again).
/// The level is found by interpolating in the levels' approximations and
/// confirming with two exact comparisons (O(1) for evenly spaced levels),
/// else by binary search (O(log k)): O(n log k) for n faces and k levels
/// at worst, no sort. Faces above the last level, or strictly between two
/// levels, touch no level and are left out at once.
struct Heights {
    /// Shared with each level's points (no copy per level).
    grid: Vec<Arc<Level>>,
    /// The faces filed under level `l`, ascending by face:
    /// `entries[starts[l]..starts[l + 1]]`.
    entries: Vec<Entry>,
    starts: Vec<usize>,
}

/// A face filed under no level.
const UNFILED: u32 = u32::MAX;

impl Heights {
    /// Finds each face's level in parallel (on the current rayon pool) when
    /// `parallel`, else on this thread, then files the faces in one pass (a
    /// counting sort by level, so each level's faces stay ascending); the
    /// same result either way.
    fn new(mesh: &Mesh, unit: &Rat, levels: &[Rat], parallel: bool) -> Self {
        let one = num_traits::One::is_one(unit);
        let grid: Vec<Arc<Level>> = levels
            .iter()
            .map(|c| Arc::new(Level::new(if one { c.clone() } else { rat_div(c, unit) })))
            .collect();
        let brackets: Vec<Bracket> = grid.iter().map(|l| l.bracket()).collect();
        let approx: Vec<f64> = grid.iter().map(|l| l.approx()).collect();
        // The plan may be made before validation: a face with a vertex out
        // of range (a mesh validation refuses) is not filed.
        let heights = |f: usize| -> Option<(f64, f64)> {
            let z = mesh.faces[f].map(|v| mesh.positions.get(v.idx()).map(|p| p[2]));
            let [Some(a), Some(b), Some(c)] = z else {
                return None;
            };
            Some((a.min(b).min(c), a.max(b).max(c)))
        };
        let level_of = |f: usize| -> u32 {
            let Some((lo, hi)) = heights(f) else {
                return UNFILED;
            };
            let first = first_level_at_or_above(&brackets, &approx, lo);
            if first < grid.len() && brackets[first].sign_of(hi) != Sign::Negative {
                first as u32
            } else {
                UNFILED
            }
        };
        let n = mesh.num_faces();
        let filed: Vec<u32> = if parallel && n >= par::MIN_LEN {
            (0..n)
                .into_par_iter()
                .with_min_len(par::MIN_LEN)
                .map(level_of)
                .collect()
        } else {
            (0..n).map(level_of).collect()
        };
        let mut starts = vec![0usize; grid.len() + 1];
        for &l in filed.iter().filter(|&&l| l != UNFILED) {
            starts[l as usize + 1] += 1;
        }
        for l in 0..grid.len() {
            starts[l + 1] += starts[l];
        }
        let mut fill = starts.clone();
        let mut entries = vec![
            Entry {
                face: FaceId::from_idx(0),
                top: 0.0,
            };
            starts[grid.len()]
        ];
        for (f, &l) in filed.iter().enumerate() {
            // A filed face has its heights.
            let Some((_, top)) = heights(f).filter(|_| l != UNFILED) else {
                continue;
            };
            let slot = &mut fill[l as usize];
            entries[*slot] = Entry {
                face: FaceId::from_idx(f),
                top,
            };
            *slot += 1;
        }
        Heights {
            grid,
            entries,
            starts,
        }
    }

    /// The faces filed under level `l`, ascending.
    fn bucket(&self, l: usize) -> &[Entry] {
        &self.entries[self.starts[l]..self.starts[l + 1]]
    }
}

/// The first level `c` with `h <= c`, exactly (`brackets` ascending;
/// `approx` their nearest doubles, used only to guess).
fn first_level_at_or_above(brackets: &[Bracket], approx: &[f64], h: f64) -> usize {
    // Whether level i lies strictly below h.
    let below = |i: usize| brackets[i].sign_of(h) == Sign::Positive;
    let k = brackets.len();
    if k == 0 {
        return 0;
    }
    let (a, b) = (approx[0], approx[k - 1]);
    // The guess is only a guess (confirmed exactly below): its ceiling by
    // a truncating conversion (saturating; NaN gives 0) and one step, as
    // `f64::ceil` is a library call on baseline x86-64.
    let t = (h - a) / (b - a) * (k - 1) as f64;
    let trunc = t as i64;
    let ceil = trunc.saturating_add(i64::from((trunc as f64) < t));
    let guess = ceil.clamp(0, k as i64) as usize;
    let left_ok = guess == 0 || below(guess - 1);
    let right_ok = guess == k || !below(guess);
    let search = |part: &[Bracket]| part.partition_point(|l| l.sign_of(h) == Sign::Positive);
    match (left_ok, right_ok) {
        (true, true) => guess,
        // Level `guess` is below h: the answer lies above it.
        (true, false) => guess + 1 + search(&brackets[guess + 1..]),
        // Level `guess - 1` is not below h: the answer lies at or below it.
        (false, _) => search(&brackets[..guess]),
    }
}

/// One worker's sweep state.
struct Sweep<'h> {
    heights: &'h Heights,
    next: usize,
    /// The faces touching the current level, ascending by face.
    active: Vec<Entry>,
    /// Scratch for merging entering faces into `active`.
    merged: Vec<Entry>,
    /// The active faces alone, as the slicer takes them.
    faces: Vec<FaceId>,
}

impl<'h> Sweep<'h> {
    fn new(heights: &'h Heights) -> Self {
        Sweep {
            heights,
            next: 0,
            active: Vec::new(),
            merged: Vec::new(),
            faces: Vec::new(),
        }
    }

    /// Moves the plane up to level `index`: faces the plane has passed
    /// leave, faces filed up to `index` enter, and `active` stays
    /// ascending (no sort of the active set). Indices must come in
    /// ascending order.
    fn advance(&mut self, index: usize) {
        let h = self.heights;
        let level = h.grid[index].bracket();
        let touching = |e: &Entry| level.sign_of(e.top) != Sign::Negative;
        self.active.retain(touching);
        let buckets = (self.next.min(index + 1)..=index).map(|l| h.bucket(l));
        self.next = self.next.max(index + 1);
        // Each bucket is ascending. A worker that skipped a few levels (the
        // others took them) merges their buckets one by one; after many,
        // one sort of them all is cheaper.
        if buckets.clone().filter(|b| !b.is_empty()).count() <= MERGED_BUCKETS {
            for bucket in buckets {
                self.merge_in(bucket.iter().copied().filter(touching));
            }
        } else {
            let mut entering: Vec<Entry> = buckets.flatten().copied().filter(touching).collect();
            entering.sort_unstable_by_key(|e| e.face);
            self.merge_in(entering.into_iter());
        }
        self.faces.clear();
        self.faces.extend(self.active.iter().map(|e| e.face));
    }

    /// Merges entries ascending by face (none of them active) into `active`.
    fn merge_in(&mut self, mut entering: impl Iterator<Item = Entry>) {
        let Some(mut next) = entering.next() else {
            return;
        };
        self.merged.clear();
        self.merged
            .reserve(self.active.len() + entering.size_hint().0 + 1);
        let mut i = 0;
        loop {
            while i < self.active.len() && self.active[i].face < next.face {
                self.merged.push(self.active[i]);
                i += 1;
            }
            self.merged.push(next);
            match entering.next() {
                Some(e) => next = e,
                None => break,
            }
        }
        self.merged.extend_from_slice(&self.active[i..]);
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
        slicer.slice_active(c, &self.heights.grid[index], &self.faces)
    }
}

/// Slices every level (ascending, distinct) with `threads` workers and hands
/// each level set, with its index, to `sink` in order.
pub fn slice_levels<E, S>(
    slicer: &Slicer<'_>,
    levels: &[Rat],
    threads: usize,
    sink: S,
) -> Result<(), SweepError<E>>
where
    E: std::error::Error + 'static,
    S: FnMut(usize, LevelSet) -> Result<(), E>,
{
    let finish = |_: usize, ls: LevelSet| ls;
    slice_levels_then(slicer, levels, threads, &finish, sink)
}

/// A mesh's faces filed under the levels of a plan: the sweep's setup,
/// which needs neither validation nor topology, so a caller may make it
/// beside them (e.g. in a `rayon::join` with [`Slicer::with_unit`]) and
/// hand it to [`slice_plan_then`].
pub struct SweepPlan<'a> {
    mesh: &'a Mesh,
    unit: Rat,
    levels: &'a [Rat],
    heights: Heights,
}

impl<'a> SweepPlan<'a> {
    /// Files `mesh`'s faces under `levels` (ascending, distinct, exact, in
    /// the units of [`Slicer::with_unit`]'s `unit`), in parallel on the
    /// current rayon pool for a large mesh.
    pub fn new(mesh: &'a Mesh, unit: &Rat, levels: &'a [Rat]) -> Self {
        let parallel = mesh.num_faces() >= par::MIN_LEN;
        Self::filed(mesh, unit, levels, parallel)
    }

    fn filed(mesh: &'a Mesh, unit: &Rat, levels: &'a [Rat], parallel: bool) -> Self {
        SweepPlan {
            mesh,
            unit: unit.clone(),
            levels,
            heights: Heights::new(mesh, unit, levels, parallel),
        }
    }

    /// Whether the plan was made for this slicer's mesh and units.
    fn fits(&self, slicer: &Slicer<'_>) -> bool {
        std::ptr::eq(self.mesh, slicer.mesh()) && self.unit == *slicer.unit()
    }
}

/// The most worker threads a pool is given: 4 a core, and never fewer
/// than 256 (a script written for a large machine runs on a small one).
/// Past a few a core, idle workers spend their time searching each
/// other's queues for work (rayon's stealing visits every worker): on 2
/// cores, 1 000 workers took 4.3 s for a job one does in 0.01 s, and
/// 40 000 did not finish in 100 s. The command line and the Python
/// package refuse more ([`thread_count`]); the functions here take at
/// most this many.
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    cores.saturating_mul(4).max(256)
}

/// A worker count above [`max_threads`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{asked}: at most {most} here (4 a core, and never fewer than 256); \
     more workers than that spend their time looking for work"
)]
pub struct TooManyThreads {
    /// The count asked for.
    pub asked: usize,
    /// [`max_threads`] on this machine.
    pub most: usize,
}

/// `asked` when it is at most [`max_threads`].
pub fn thread_count(asked: usize) -> Result<usize, TooManyThreads> {
    let most = max_threads();
    if asked > most {
        return Err(TooManyThreads { asked, most });
    }
    Ok(asked)
}

/// [`slice_levels`] with a step run on the workers: `finish` turns each
/// level set into what `sink` takes (e.g. its serialized text), so that
/// work is spread over the threads too; `sink` still sees the results in
/// level order, one at a time.
pub fn slice_levels_then<T, E, F, S>(
    slicer: &Slicer<'_>,
    levels: &[Rat],
    threads: usize,
    finish: &F,
    sink: S,
) -> Result<(), SweepError<E>>
where
    T: Send,
    E: std::error::Error + 'static,
    F: Fn(usize, LevelSet) -> T + Sync,
    S: FnMut(usize, T) -> Result<(), E>,
{
    let (mesh, unit) = (slicer.mesh(), slicer.unit());
    let threads = threads.clamp(1, levels.len().clamp(1, max_threads()));
    if threads == 1 {
        let plan = SweepPlan::filed(mesh, unit, levels, false);
        return sweep(slicer, &plan, None, finish, sink);
    }
    let pool = pool(threads)?;
    let plan = pool.install(|| SweepPlan::new(mesh, unit, levels));
    sweep(slicer, &plan, Some(pool), finish, sink)
}

/// [`slice_levels_then`] for the levels of a plan made beforehand. A plan
/// made for another mesh, or other units, is made again.
pub fn slice_plan_then<T, E, F, S>(
    slicer: &Slicer<'_>,
    plan: &SweepPlan<'_>,
    threads: usize,
    finish: &F,
    sink: S,
) -> Result<(), SweepError<E>>
where
    T: Send,
    E: std::error::Error + 'static,
    F: Fn(usize, LevelSet) -> T + Sync,
    S: FnMut(usize, T) -> Result<(), E>,
{
    if !plan.fits(slicer) {
        return slice_levels_then(slicer, plan.levels, threads, finish, sink);
    }
    let threads = threads.clamp(1, plan.levels.len().clamp(1, max_threads()));
    let pool = if threads > 1 {
        Some(pool(threads)?)
    } else {
        None
    };
    sweep(slicer, plan, pool, finish, sink)
}

fn pool<E: std::error::Error + 'static>(
    threads: usize,
) -> Result<rayon::ThreadPool, SweepError<E>> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Threads(e.to_string()))
}

/// Slices the plan's levels: on this thread without a pool, else on the
/// pool's threads with this one handing the results on.
fn sweep<T, E, F, S>(
    slicer: &Slicer<'_>,
    plan: &SweepPlan<'_>,
    pool: Option<rayon::ThreadPool>,
    finish: &F,
    mut sink: S,
) -> Result<(), SweepError<E>>
where
    T: Send,
    E: std::error::Error + 'static,
    F: Fn(usize, LevelSet) -> T + Sync,
    S: FnMut(usize, T) -> Result<(), E>,
{
    let (levels, heights) = (plan.levels, &plan.heights);
    let Some(pool) = pool else {
        let mut sweep = Sweep::new(heights);
        for (index, c) in levels.iter().enumerate() {
            let ls = sweep
                .slice(slicer, index, c)
                .map_err(|source| SweepError::Slice { index, source })?;
            sink(index, finish(index, ls)).map_err(SweepError::Sink)?;
        }
        return Ok(());
    };
    let threads = pool.current_num_threads();
    let window = Window::new(AHEAD * threads);
    let (tx, rx) = sync_channel::<(usize, Result<T, SliceError>)>(AHEAD * threads);
    let worker = |tx: SyncSender<(usize, Result<T, SliceError>)>| {
        let mut sweep = Sweep::new(heights);
        while let Some(index) = window.claim(levels.len()) {
            let result = sweep
                .slice(slicer, index, &levels[index])
                .map(|ls| finish(index, ls));
            let failed = result.is_err();
            if tx.send((index, result)).is_err() || failed {
                return;
            }
        }
    };
    pool.in_place_scope(|scope| {
        for _ in 0..threads {
            let (worker, tx) = (&worker, tx.clone());
            scope.spawn(move |_| worker(tx));
        }
        drop(tx);
        // Results arrive in any order; they are handed on in level order.
        let mut early: HashMap<usize, Result<T, SliceError>> = HashMap::new();
        let mut outcome = Ok(());
        for index in 0..levels.len() {
            let result = loop {
                if let Some(r) = early.remove(&index) {
                    break Some(r);
                }
                match rx.recv() {
                    Ok((i, r)) if i == index => break Some(r),
                    Ok((i, r)) => {
                        early.insert(i, r);
                    }
                    Err(_) => break None,
                }
            };
            let step = match result {
                Some(Ok(done)) => sink(index, done).map_err(SweepError::Sink),
                Some(Err(source)) => Err(SweepError::Slice { index, source }),
                None => Err(SweepError::Threads("a worker stopped early".into())),
            };
            if let Err(e) = step {
                outcome = Err(e);
                break;
            }
            window.handed_on(index + 1);
        }
        // Workers waiting for room, or to send, stop.
        window.close();
        drop(rx);
        outcome
    })
}

/// Which level each worker takes next: the next one not yet taken (so a
/// slow level does not hold up the others' share), but at most `ahead`
/// levels past the last one handed on, which bounds the results waiting
/// to be handed on.
struct Window {
    state: Mutex<WindowState>,
    room: Condvar,
    ahead: usize,
}

struct WindowState {
    next: usize,
    handed_on: usize,
    closed: bool,
}

impl Window {
    fn new(ahead: usize) -> Self {
        Window {
            state: Mutex::new(WindowState {
                next: 0,
                handed_on: 0,
                closed: false,
            }),
            room: Condvar::new(),
            ahead: ahead.max(1),
        }
    }

    /// The next level to slice (below `len`), once there is room for it;
    /// `None` when all are taken or the window is closed.
    fn claim(&self, len: usize) -> Option<usize> {
        let mut s = self.state.lock().ok()?;
        loop {
            if s.closed || s.next >= len {
                return None;
            }
            if s.next < s.handed_on + self.ahead {
                s.next += 1;
                return Some(s.next - 1);
            }
            s = self.room.wait(s).ok()?;
        }
    }

    /// Levels below `count` have been handed on.
    fn handed_on(&self, count: usize) {
        if let Ok(mut s) = self.state.lock() {
            s.handed_on = count;
        }
        self.room.notify_all();
    }

    /// No more levels are taken.
    fn close(&self) {
        if let Ok(mut s) = self.state.lock() {
            s.closed = true;
        }
        self.room.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;

    proptest::proptest! {
        /// The guessed search equals a plain binary search, for evenly
        /// spaced and irregular levels (some not doubles), at heights on,
        /// next to and between them.
        #[test]
        fn guessed_level_search_is_the_binary_search(
            steps in proptest::collection::vec(1i64..50, 0..40), even in proptest::bool::ANY,
            third in proptest::bool::ANY, pick in 0usize..200, nudge in -1i8..=1
        ) {
            let mut levels: Vec<Rat> = Vec::new();
            let mut at = Rat::from_integer((-7).into());
            for s in &steps {
                let s = if even { 3 } else { *s };
                let d = if third { 3 } else { 4 };
                at += Rat::new(s.into(), d.into());
                levels.push(at.clone());
            }
            let grid: Vec<Level> = levels.iter().cloned().map(Level::new).collect();
            let brackets: Vec<Bracket> = grid.iter().map(Level::bracket).collect();
            let approx: Vec<f64> = grid.iter().map(Level::approx).collect();
            let mut h = approx.get(pick % (approx.len() + 1)).copied().unwrap_or(100.0);
            h = match nudge {
                -1 => h.next_down(),
                1 => h.next_up(),
                _ => h,
            };
            let plain = levels.partition_point(|c| rat_from_f64(h) > *c);
            proptest::prop_assert_eq!(first_level_at_or_above(&brackets, &approx, h), plain);
            for h in [-1e300, 1e300, -7.0, f64::MIN_POSITIVE] {
                let plain = levels.partition_point(|c| rat_from_f64(h) > *c);
                proptest::prop_assert_eq!(first_level_at_or_above(&brackets, &approx, h), plain);
            }
        }

        /// However a worker skips levels (one bucket at a time, a few merged
        /// one by one, or many sorted together), its active faces at each
        /// level it visits are exactly the faces whose heights span the
        /// level, ascending. Faces: random height ranges on a coarse grid
        /// (many on levels, many spanning several).
        #[test]
        fn advancing_gives_the_faces_touching_each_level(
            spans in proptest::collection::vec((0i32..40, 0i32..12), 1..300),
            skips in proptest::collection::vec(1usize..12, 1..40),
        ) {
            // Face f is a vertical triangle spanning heights lo..=lo+len (in
            // quarters); levels at every half.
            let mut positions = Vec::new();
            let mut faces = Vec::new();
            for (f, &(lo, len)) in spans.iter().enumerate() {
                let (a, b) = (f64::from(lo) / 4.0, f64::from(lo + len) / 4.0);
                positions.extend([[f as f64, 0.0, a], [f as f64, 1.0, a], [f as f64, 0.0, b]]);
                let v = 3 * f as u32;
                faces.push([v, v + 1, v + 2]);
            }
            let mesh = Mesh::from_raw(positions, faces);
            let levels: Vec<Rat> = (0..30).map(|k| Rat::new(k.into(), 2.into())).collect();
            let heights = Heights::new(&mesh, &Rat::from_integer(1.into()), &levels, false);
            let mut sweep = Sweep::new(&heights);
            let mut index = 0;
            for skip in skips {
                index += skip - 1;
                if index >= levels.len() {
                    break;
                }
                sweep.advance(index);
                let c = &levels[index];
                let touching: Vec<FaceId> = spans
                    .iter()
                    .enumerate()
                    .filter(|(_, &(lo, len))| {
                        Rat::new(lo.into(), 4.into()) <= *c && *c <= Rat::new((lo + len).into(), 4.into())
                    })
                    .map(|(f, _)| FaceId::from_idx(f))
                    .collect();
                proptest::prop_assert_eq!(&sweep.faces, &touching, "level {}", index);
                index += 1;
            }
        }
    }
}
