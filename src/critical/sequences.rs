//! Input: edge ids. Output: sequences of edges held as implicit treaps
//! (balanced search trees keyed by position), so that finding the
//! sequence of an edge, its position, splitting and concatenating take
//! `O(log n)` expected time each.
//!
//! This is the data structure of Cole-McLean, Edelsbrunner, Harer,
//! Natarajan and Pascucci, "Loops in Reeb graphs of 2-manifolds" (2003):
//! each contour of the sweep is a cyclic sequence of the edges it crosses,
//! stored as one tree. A node is an edge id; an edge is in at most one
//! sequence at a time. Priorities are a fixed hash of the edge id, so the
//! trees (and everything computed from them) are deterministic. Every
//! operation is iterative: no recursion, whatever the depth.
//!
//! Nothing here reads a coordinate.

use crate::ids::EdgeId;

/// "No node".
pub(super) const NIL: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Node {
    left: u32,
    right: u32,
    parent: u32,
    /// Nodes in the subtree; 0 when the edge is in no sequence.
    size: u32,
    priority: u32,
    /// A tag kept at roots (the sweep stores the contour's Reeb arc here).
    tag: u32,
}

/// A forest of sequences of edges.
pub(super) struct Sequences {
    nodes: Vec<Node>,
}

/// The finalizer of SplitMix64: a fixed, well-mixed priority per edge.
fn priority(e: u32) -> u32 {
    let mut z = u64::from(e).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

impl Sequences {
    /// Room for edges `0..edges`, none in a sequence.
    pub(super) fn new(edges: usize) -> Self {
        let nodes = (0..edges)
            .map(|e| Node {
                left: NIL,
                right: NIL,
                parent: NIL,
                size: 0,
                priority: priority(e as u32),
                tag: NIL,
            })
            .collect();
        Sequences { nodes }
    }

    #[inline]
    fn size(&self, t: u32) -> u32 {
        if t == NIL {
            0
        } else {
            self.nodes[t as usize].size
        }
    }

    #[inline]
    fn update(&mut self, t: u32) {
        let n = self.nodes[t as usize];
        self.nodes[t as usize].size = 1 + self.size(n.left) + self.size(n.right);
    }

    /// Whether `a` goes above `b` in the heap order (ties by id).
    #[inline]
    fn above(&self, a: u32, b: u32) -> bool {
        (self.nodes[a as usize].priority, a) > (self.nodes[b as usize].priority, b)
    }

    /// Whether edge `e` is in a sequence.
    #[inline]
    pub(super) fn contains(&self, e: EdgeId) -> bool {
        self.nodes[e.idx()].size > 0
    }

    /// Number of edges in the sequence whose root is `t`.
    #[inline]
    pub(super) fn len(&self, t: u32) -> u32 {
        self.size(t)
    }

    /// A one-edge sequence; `None` when the edge already is in one.
    pub(super) fn single(&mut self, e: EdgeId) -> Option<u32> {
        let n = &mut self.nodes[e.idx()];
        if n.size != 0 {
            return None;
        }
        n.left = NIL;
        n.right = NIL;
        n.parent = NIL;
        n.size = 1;
        n.tag = NIL;
        Some(e.0)
    }

    /// The root of the sequence holding `e` and the position of `e` in it.
    pub(super) fn locate(&self, e: EdgeId) -> (u32, u32) {
        let mut x = e.0;
        let mut pos = self.size(self.nodes[x as usize].left);
        loop {
            let p = self.nodes[x as usize].parent;
            if p == NIL {
                return (x, pos);
            }
            if self.nodes[p as usize].right == x {
                pos += self.size(self.nodes[p as usize].left) + 1;
            }
            x = p;
        }
    }

    /// The tag kept at root `t`.
    #[inline]
    pub(super) fn tag(&self, t: u32) -> u32 {
        self.nodes[t as usize].tag
    }

    /// Sets the tag of root `t`.
    #[inline]
    pub(super) fn set_tag(&mut self, t: u32, tag: u32) {
        self.nodes[t as usize].tag = tag;
    }

    /// The first edge of the sequence rooted at `t` (`t != NIL`).
    pub(super) fn first(&self, mut t: u32) -> u32 {
        while self.nodes[t as usize].left != NIL {
            t = self.nodes[t as usize].left;
        }
        t
    }

    /// The last edge of the sequence rooted at `t` (`t != NIL`).
    pub(super) fn last(&self, mut t: u32) -> u32 {
        while self.nodes[t as usize].right != NIL {
            t = self.nodes[t as usize].right;
        }
        t
    }

    /// The concatenation of the sequences rooted at `a` and `b` (either may
    /// be `NIL`); returns its root.
    pub(super) fn concat(&mut self, mut a: u32, mut b: u32) -> u32 {
        if a == NIL {
            return b;
        }
        if b == NIL {
            return a;
        }
        // Walk down the right spine of `a` and the left spine of `b`,
        // attaching whichever root is higher in the heap order.
        let root = if self.above(a, b) { a } else { b };
        self.nodes[root as usize].parent = NIL;
        let mut attach = NIL; // node whose child is attached next
        let mut attach_right = false;
        let last;
        loop {
            let take_a = if a == NIL {
                false
            } else if b == NIL {
                true
            } else {
                self.above(a, b)
            };
            let x = if take_a { a } else { b };
            if attach != NIL {
                if attach_right {
                    self.nodes[attach as usize].right = x;
                } else {
                    self.nodes[attach as usize].left = x;
                }
                self.nodes[x as usize].parent = attach;
            }
            if a == NIL || b == NIL {
                last = x;
                break;
            }
            if take_a {
                attach = a;
                attach_right = true;
                a = self.nodes[a as usize].right;
            } else {
                attach = b;
                attach_right = false;
                b = self.nodes[b as usize].left;
            }
        }
        // The last attached subtree is intact; fix sizes above it.
        let mut x = self.nodes[last as usize].parent;
        while x != NIL {
            self.update(x);
            x = self.nodes[x as usize].parent;
        }
        root
    }

    /// Splits the sequence rooted at `t` into its first `k` edges and the
    /// rest; returns both roots (`NIL` for an empty part).
    pub(super) fn split(&mut self, t: u32, mut k: u32) -> (u32, u32) {
        let (mut lroot, mut rroot) = (NIL, NIL);
        let (mut llast, mut rlast) = (NIL, NIL);
        let mut cur = t;
        while cur != NIL {
            let ls = self.size(self.nodes[cur as usize].left);
            if k > ls {
                // `cur` and its left subtree go left.
                k -= ls + 1;
                if llast == NIL {
                    lroot = cur;
                    self.nodes[cur as usize].parent = NIL;
                } else {
                    self.nodes[llast as usize].right = cur;
                    self.nodes[cur as usize].parent = llast;
                }
                llast = cur;
                cur = self.nodes[cur as usize].right;
            } else {
                if rlast == NIL {
                    rroot = cur;
                    self.nodes[cur as usize].parent = NIL;
                } else {
                    self.nodes[rlast as usize].left = cur;
                    self.nodes[cur as usize].parent = rlast;
                }
                rlast = cur;
                cur = self.nodes[cur as usize].left;
            }
        }
        for (last, right) in [(llast, true), (rlast, false)] {
            if last == NIL {
                continue;
            }
            if right {
                self.nodes[last as usize].right = NIL;
            } else {
                self.nodes[last as usize].left = NIL;
            }
            let mut x = last;
            while x != NIL {
                self.update(x);
                x = self.nodes[x as usize].parent;
            }
        }
        (lroot, rroot)
    }

    /// The edges of the sequence rooted at `t`, in order, appended to `out`.
    pub(super) fn collect(&self, t: u32, out: &mut Vec<u32>) {
        let mut stack: Vec<u32> = Vec::new();
        let mut cur = t;
        while cur != NIL || !stack.is_empty() {
            while cur != NIL {
                stack.push(cur);
                cur = self.nodes[cur as usize].left;
            }
            if let Some(x) = stack.pop() {
                out.push(x);
                cur = self.nodes[x as usize].right;
            }
        }
    }

    /// Removes every edge of the sequence rooted at `t` from the forest.
    pub(super) fn release(&mut self, t: u32, scratch: &mut Vec<u32>) {
        scratch.clear();
        self.collect(t, scratch);
        for &x in scratch.iter() {
            let n = &mut self.nodes[x as usize];
            n.size = 0;
            n.left = NIL;
            n.right = NIL;
            n.parent = NIL;
            n.tag = NIL;
        }
    }

    /// The sequence of `edges`, in order, as a new tree; `None` when one of
    /// them already is in a sequence (or is repeated).
    pub(super) fn build(&mut self, edges: impl IntoIterator<Item = EdgeId>) -> Option<u32> {
        let mut t = NIL;
        for e in edges {
            let s = self.single(e)?;
            t = self.concat(t, s);
        }
        Some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seq(s: &Sequences, t: u32) -> Vec<u32> {
        let mut v = Vec::new();
        s.collect(t, &mut v);
        v
    }

    /// Checks the heap order, the sizes and the parent links.
    fn check(s: &Sequences, t: u32) {
        fn walk(s: &Sequences, x: u32, parent: u32) -> u32 {
            if x == NIL {
                return 0;
            }
            let n = s.nodes[x as usize];
            assert_eq!(n.parent, parent);
            if parent != NIL {
                assert!(s.above(parent, x));
            }
            let size = 1 + walk(s, n.left, x) + walk(s, n.right, x);
            assert_eq!(n.size, size);
            size
        }
        walk(s, t, NIL);
    }

    #[test]
    fn split_concat_and_locate_agree_with_a_vector() {
        let n = 200u32;
        let mut s = Sequences::new(n as usize);
        let t = s.build((0..n).map(EdgeId)).unwrap();
        check(&s, t);
        assert_eq!(seq(&s, t), (0..n).collect::<Vec<_>>());
        for e in [0u32, 1, 57, 199] {
            assert_eq!(s.locate(EdgeId(e)), (t, e));
        }
        // Rotate by 73, then cut out 10 edges from position 50.
        let (a, b) = s.split(t, 73);
        check(&s, a);
        check(&s, b);
        let r = s.concat(b, a);
        check(&s, r);
        let mut want: Vec<u32> = (73..n).chain(0..73).collect();
        assert_eq!(seq(&s, r), want);
        let (head, rest) = s.split(r, 50);
        let (piece, tail) = s.split(rest, 10);
        assert_eq!(seq(&s, piece), want[50..60].to_vec());
        let mut scratch = Vec::new();
        s.release(piece, &mut scratch);
        let r = s.concat(head, tail);
        check(&s, r);
        want.drain(50..60);
        assert_eq!(seq(&s, r), want);
        // Released edges can be used again; live ones cannot.
        let again = s.build(want.iter().take(1).map(|&e| EdgeId(e)));
        assert!(again.is_none());
        let freed: Vec<u32> = (0..n).filter(|&e| !s.contains(EdgeId(e))).collect();
        assert_eq!(freed.len(), 10);
        let u = s.build(freed.iter().rev().map(|&e| EdgeId(e))).unwrap();
        let both = s.concat(r, u);
        check(&s, both);
        assert_eq!(s.len(both), n);
        let (root, pos) = s.locate(EdgeId(freed[9]));
        assert_eq!((root, pos), (both, n - 10));
        assert_eq!(s.first(both), want[0]);
        assert_eq!(s.last(both), freed[0]);
    }
}
