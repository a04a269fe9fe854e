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
use crate::exact::predicates::orient2d_points;
use crate::exact::Sign;
use std::cmp::Ordering;

/// A segment of loop `l`: from its lower end (in sweep order) to its
/// upper end, global point indices; `down` when the loop runs from upper
/// to lower.
#[derive(Clone, Copy, Debug)]
struct Seg {
    l: u32,
    lower: u32,
    upper: u32,
    /// The event of the lower end.
    start: u32,
    down: bool,
    /// Both ends as doubles, `[x0, y0, x1, y1]` (lower end first), when the
    /// points are exactly their doubles: comparisons then read the segment
    /// alone (the sweep is bound by memory, not arithmetic).
    doubles: Option<[f64; 4]>,
}

/// A segment as the sweep line holds it: small, so that with the tree's
/// links it fits one cache line (the line holds every segment it crosses,
/// tens of thousands for deep nesting, and each step down the tree reads
/// one). `d` are the ends as doubles when every segment has them.
#[derive(Clone, Copy, Debug)]
struct OnLine {
    d: [f64; 4],
    seg: u32,
    start: u32,
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

/// Groups `items` by a key below `n` (counting sort): the items of key
/// `k` are `out[start[k]..start[k + 1]]`, in input order.
fn bucket<T: Copy>(n: usize, items: &[T], key: impl Fn(&T) -> usize) -> (Vec<usize>, Vec<T>) {
    let mut start = vec![0usize; n + 1];
    for it in items {
        start[key(it) + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut next = start.clone();
    let mut out: Vec<T> = Vec::with_capacity(items.len());
    // Every slot is written once below.
    out.extend(items.iter().copied());
    for it in items {
        let k = key(it);
        out[next[k]] = *it;
        next[k] += 1;
    }
    (start, out)
}

/// The parent of every loop. `orientation[i]` is the exact sign of loop
/// `i`'s area (a loop of zero area encloses nothing).
pub fn parents<P: Planar, L: AsRef<[P]>>(loops: &[L], orientation: &[Sign]) -> Vec<Option<usize>> {
    // Points by global index: loop `l`'s point `k` is `first[l] + k`.
    let mut first = Vec::with_capacity(loops.len() + 1);
    let mut points: Vec<&P> = Vec::new();
    for poly in loops {
        first.push(points.len());
        for p in poly.as_ref() {
            points.push(p);
        }
    }
    first.push(points.len());
    // Every point, in sweep order; equal points (loops touching) form one
    // event.
    let event = events_in_sweep_order(&points);
    let events = event.iter().max().map_or(0, |&e| e as usize + 1);

    // Segments (zero-length ones left out), and each loop's lowest event.
    let mut segs: Vec<Seg> = Vec::with_capacity(points.len());
    let mut lowest: Vec<(u32, u32)> = Vec::with_capacity(loops.len());
    for l in 0..loops.len() {
        let (a, n) = (first[l], first[l + 1] - first[l]);
        if n == 0 {
            continue;
        }
        let low = (a..a + n).map(|g| event[g]).min().unwrap_or(0);
        lowest.push((low, l as u32));
        for k in 0..n {
            let (p, q) = ((a + k) as u32, (a + (k + 1) % n) as u32);
            let (ep, eq) = (event[p as usize], event[q as usize]);
            if ep == eq {
                continue;
            }
            let down = ep > eq;
            let (lower, upper) = if down { (q, p) } else { (p, q) };
            let doubles = points[lower as usize]
                .as_double()
                .zip(points[upper as usize].as_double())
                .map(|([x0, y0], [x1, y1])| [x0, y0, x1, y1]);
            segs.push(Seg {
                l: l as u32,
                lower,
                upper,
                start: ep.min(eq),
                down,
                doubles,
            });
        }
    }
    // Segments in the order they start (those starting at event `e` are
    // `segs[start_at[e]..start_at[e + 1]]`, read in turn), and by end.
    let (start_at, segs) = bucket(events, &segs, |s| s.start as usize);
    let ids: Vec<u32> = (0..segs.len() as u32).collect();
    let (end_at, ends) = bucket(events, &ids, |&i| {
        event[segs[i as usize].upper as usize] as usize
    });
    let (low_at, lows) = bucket(events, &lowest, |&(e, _)| e as usize);

    let all_doubles = segs.iter().all(|s| s.doubles.is_some());
    let on_line = |i: usize| OnLine {
        d: segs[i].doubles.unwrap_or_default(),
        seg: i as u32,
        start: segs[i].start,
    };
    // Where segment `s`, starting at the current event point, goes
    // relative to segment `t` already crossing the line.
    let cmp = |s: &OnLine, t: &OnLine| -> Ordering {
        let shared = t.start == s.start;
        let side = if all_doubles {
            let (sd, td) = (s.d, t.d);
            let r = if shared {
                [sd[2], sd[3]]
            } else {
                [sd[0], sd[1]]
            };
            orient2d_points([td[0], td[1]], [td[2], td[3]], r)
        } else {
            let (s, t) = (&segs[s.seg as usize], &segs[t.seg as usize]);
            let (c, d) = (points[t.lower as usize], points[t.upper as usize]);
            let r = if shared { s.upper } else { s.lower };
            P::orient(c, d, points[r as usize])
        };
        match side {
            Sign::Positive => Ordering::Less,
            // Zero would be an overlap or a touch inside a segment, which
            // the callers' loops never have; any answer keeps the tree sound.
            Sign::Negative | Sign::Zero => Ordering::Greater,
        }
    };

    let mut line: Order<OnLine> = Order::new();
    let mut handle: Vec<Handle> = vec![Handle::MAX; segs.len()];
    let mut left = vec![Left::Nothing; loops.len()];
    for e in 0..events {
        for &i in &ends[end_at[e]..end_at[e + 1]] {
            line.remove(handle[i as usize]);
        }
        let starting = start_at[e]..start_at[e + 1];
        for i in starting.clone() {
            let s = on_line(i);
            handle[i] = line.insert(s, |t| cmp(&s, t));
        }
        for &(_, l) in &lows[low_at[e]..low_at[e + 1]] {
            let mine = starting.clone().filter(|&i| segs[i].l == l);
            let leftmost = mine.reduce(|a, b| {
                if cmp(&on_line(b), &on_line(a)) == Ordering::Less {
                    b
                } else {
                    a
                }
            });
            let Some(i) = leftmost else { continue };
            let Some(t) = line.prev(handle[i]).map(|h| segs[line.get(h).seg as usize]) else {
                continue;
            };
            let inside = match orientation[t.l as usize] {
                Sign::Positive => t.down,
                Sign::Negative => !t.down,
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

/// Each point's event: its rank in the sweep order, equal points sharing
/// one. Points that are all doubles are sorted as doubles (exact: they are
/// their values); others through the exact comparisons.
fn events_in_sweep_order<P: Planar>(points: &[&P]) -> Vec<u32> {
    let mut event = vec![0u32; points.len()];
    let doubles: Option<Vec<[f64; 2]>> = points.iter().map(|p| p.as_double()).collect();
    let mut assign = |order: &[u32], same: &dyn Fn(u32, u32) -> bool| {
        let mut e = 0u32;
        for (i, &g) in order.iter().enumerate() {
            if i > 0 && !same(order[i - 1], g) {
                e += 1;
            }
            event[g as usize] = e;
        }
    };
    match doubles {
        Some(d) => {
            let mut keyed: Vec<(f64, f64, u32)> = d
                .iter()
                .enumerate()
                .map(|(g, &[x, y])| (y, x, g as u32))
                .collect();
            // Finite doubles: partial_cmp is total here.
            keyed.sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(Ordering::Equal));
            let order: Vec<u32> = keyed.iter().map(|k| k.2).collect();
            assign(&order, &|a, b| d[a as usize] == d[b as usize]);
        }
        None => {
            let mut order: Vec<u32> = (0..points.len() as u32).collect();
            order.sort_by(|&a, &b| points[a as usize].cmp_yx(points[b as usize]));
            assign(&order, &|a, b| {
                points[a as usize].cmp_yx(points[b as usize]) == Ordering::Equal
            });
        }
    }
    event
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
