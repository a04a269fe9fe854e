//! When to hand work to rayon's pool. Called from outside the pool (a
//! library user's thread, a fuzzer), every parallel step hands its work to
//! the pool's threads and waits for them: tens of microseconds, more than
//! the whole validation of a small mesh. Small inputs stay on the calling
//! thread; results never depend on which way they ran.

/// Items below which a parallel iterator is not split
/// (`with_min_len(MIN_LEN)`), so that it runs on the calling thread.
pub(crate) const MIN_LEN: usize = 1 << 12;

/// `rayon::join(a, b)` when `parallel`, else `a` then `b` on this thread.
pub(crate) fn join<A, B, RA, RB>(parallel: bool, a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA + Send,
    B: FnOnce() -> RB + Send,
    RA: Send,
    RB: Send,
{
    if parallel {
        rayon::join(a, b)
    } else {
        (a(), b())
    }
}

/// `vec![value; n]`, filled in parallel when long: the first write to each
/// page of a fresh allocation is a page fault, and a large table's faults
/// are then shared by the threads instead of taken one after another.
pub(crate) fn filled<T: Clone + Send + Sync>(value: T, n: usize) -> Vec<T> {
    use rayon::prelude::*;
    if n >= MIN_LEN {
        rayon::iter::repeat_n(value, n).collect()
    } else {
        vec![value; n]
    }
}
