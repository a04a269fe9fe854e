//! Input: closed loops that never cross (they may touch at points, and a
//! loop may touch itself), each with its exact orientation. Output: each
//! loop's parent, the smallest loop enclosing it, in `O(n log n)` for `n`
//! points in all, however deep the nesting.
//!
//! A sweep line moves up in the exact order of [`Planar::cmp_yx`] (by y,
//! then by x: a line turned by an infinitesimal angle, so no segment is
//! horizontal to it). The segments crossing it are kept in their left to
//! right order, decided by exact orientation only when a segment is
//! inserted (segments never cross, so their order never changes). When
//! the line reaches a loop's lowest point, the loop's leftmost segment
//! there is inserted, and the segment just left of it (of another loop,
//! since nothing of this loop lies further left on that line) decides:
//! the point between the two lies outside this loop, and inside that
//! segment's loop exactly when that loop's interior is on the segment's
//! right (it runs downwards in a counter-clockwise loop, upwards in a
//! clockwise one). If it is inside, that loop is the parent; otherwise the
//! two loops are siblings and share a parent. No segment to the left: the
//! loop is outermost.

use super::order::{Handle, Order};
use crate::exact::planar::Planar;
use crate::exact::Sign;
use std::cmp::Ordering;

/// A segment of loop `l` from its point `k` to point `k + 1`.
#[derive(Clone, Copy, Debug)]
struct Seg {
    l: u32,
    k: u32,
}

/// What the segment just left of a loop's lowest point says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Left {
    /// Nothing: the loop is outermost.
    Nothing,
    /// The loop is inside this one.
    Inside(usize),
    /// The loop is beside this one: same parent.
    Beside(usize),
}

/// The parent of every loop. `orientation[i]` is the exact sign of loop
/// `i`'s area (a loop of zero area encloses nothing).
pub fn parents<P: Planar, L: AsRef<[P]>>(loops: &[L], orientation: &[Sign]) -> Vec<Option<usize>> {
    let pts = |s: Seg| -> (&P, &P) {
        let poly = loops[s.l as usize].as_ref();
        let k = s.k as usize;
        (&poly[k], &poly[(k + 1) % poly.len()])
    };
    // Every point, in sweep order; equal points (loops touching) form one
    // event.
    let mut order: Vec<(u32, u32)> = loops
        .iter()
        .enumerate()
        .flat_map(|(l, p)| (0..p.as_ref().len() as u32).map(move |k| (l as u32, k)))
        .collect();
    let point = |(l, k): (u32, u32)| &loops[l as usize].as_ref()[k as usize];
    order.sort_by(|&a, &b| point(a).cmp_yx(point(b)));
    let mut event_of: Vec<Vec<u32>> = loops.iter().map(|p| vec![0; p.as_ref().len()]).collect();
    let mut events = 0u32;
    for (i, &pk) in order.iter().enumerate() {
        if i > 0 && point(order[i - 1]).cmp_yx(point(pk)) != Ordering::Equal {
            events += 1;
        }
        event_of[pk.0 as usize][pk.1 as usize] = events;
    }
    let events = events as usize + 1;

    // Segments by the event of their lower and upper ends (counting sort).
    let mut starts: Vec<Vec<Seg>> = vec![Vec::new(); events];
    let mut ends: Vec<Vec<Seg>> = vec![Vec::new(); events];
    let mut lowest: Vec<Vec<u32>> = vec![Vec::new(); events];
    for (l, ev) in event_of.iter().enumerate() {
        let n = ev.len();
        if let Some(&low) = ev.iter().min() {
            lowest[low as usize].push(l as u32);
        }
        for k in 0..n {
            let (a, b) = (ev[k], ev[(k + 1) % n]);
            if a == b {
                continue; // zero length
            }
            let s = Seg {
                l: l as u32,
                k: k as u32,
            };
            starts[a.min(b) as usize].push(s);
            ends[a.max(b) as usize].push(s);
        }
    }

    let lower = |s: Seg| {
        let (a, b) = pts(s);
        if a.cmp_yx(b) == Ordering::Less {
            (a, b)
        } else {
            (b, a)
        }
    };
    // Where segment `s`, starting at the current event point, goes
    // relative to segment `t` already crossing the line.
    let cmp = |s: Seg, t: Seg| -> Ordering {
        let (p, q) = lower(s);
        let (c, d) = lower(t);
        let side = if c.cmp_yx(p) == Ordering::Equal {
            P::orient(c, d, q)
        } else {
            P::orient(c, d, p)
        };
        match side {
            Sign::Positive => Ordering::Less,
            // Zero would be an overlap or a touch inside a segment, which
            // the callers' loops never have; any answer keeps the tree sound.
            Sign::Negative | Sign::Zero => Ordering::Greater,
        }
    };

    let mut line: Order<Seg> = Order::new();
    let mut handle: Vec<Vec<Handle>> = loops
        .iter()
        .map(|p| vec![Handle::MAX; p.as_ref().len()])
        .collect();
    let mut left = vec![Left::Nothing; loops.len()];
    for e in 0..events {
        for &s in &ends[e] {
            line.remove(handle[s.l as usize][s.k as usize]);
        }
        for &s in &starts[e] {
            handle[s.l as usize][s.k as usize] = line.insert(s, |t| cmp(s, t));
        }
        for &l in &lowest[e] {
            let leftmost = starts[e]
                .iter()
                .filter(|s| s.l == l)
                .copied()
                .reduce(|a, b| if cmp(b, a) == Ordering::Less { b } else { a });
            let Some(s) = leftmost else { continue };
            let Some(t) = line
                .prev(handle[l as usize][s.k as usize])
                .map(|h| line.get(h))
            else {
                continue;
            };
            let (a, b) = pts(t);
            let downwards = a.cmp_yx(b) == Ordering::Greater;
            let inside = match orientation[t.l as usize] {
                Sign::Positive => downwards,
                Sign::Negative => !downwards,
                Sign::Zero => false,
            };
            left[l as usize] = if inside {
                Left::Inside(t.l as usize)
            } else {
                Left::Beside(t.l as usize)
            };
        }
    }
    resolve(&left)
}

/// Parents from the left neighbours: `Beside(k)` takes `k`'s parent. Each
/// `Beside` points to a loop whose lowest point comes no later, and to the
/// left of it when they share it, so the chains end.
fn resolve(left: &[Left]) -> Vec<Option<usize>> {
    let mut parent: Vec<Option<Option<usize>>> = vec![None; left.len()];
    let mut path = Vec::new();
    for start in 0..left.len() {
        let mut at = start;
        let found = loop {
            if let Some(p) = parent[at] {
                break p;
            }
            match left[at] {
                Left::Nothing => break None,
                Left::Inside(k) => break Some(k),
                Left::Beside(k) => {
                    path.push(at);
                    at = k;
                }
            }
        };
        parent[at] = Some(found);
        for p in path.drain(..) {
            parent[p] = Some(found);
        }
    }
    parent.into_iter().map(|p| p.flatten()).collect()
}
