//! Input: edge ids. Output: sequences of edges held as implicit treaps
//! (balanced search trees keyed by position), so that finding the
//! sequence of an edge, its position, splitting and concatenating take
//! `O(log n)` expected time each.
//!
//! This is the data structure of Cole-McLean, Edelsbrunner, Harer,
//! Natarajan and Pascucci, "Loops in Reeb graphs of 2-manifolds" (2003):
//! each contour of the sweep is a cyclic sequence of the edges it crosses,
//! stored as one tree. An edge is in at most one sequence at a time. Tree
//! nodes are a pool separate from the edges, so that the common step of
//! the sweep, a run of edges replaced by another run in place
//! ([`Sequences::replace_run`]), relabels nodes instead of rebuilding the
//! tree. Priorities are a fixed hash of the node id and nodes are taken
//! from the pool in a fixed order, so the trees (and everything computed
//! from them) are deterministic. Every operation is iterative: no
//! recursion, whatever the depth.
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
    /// Nodes in the subtree.
    size: u32,
    priority: u32,
    /// The edge this node holds.
    edge: u32,
    /// A tag kept at roots (the sweep stores the contour's Reeb arc here).
    tag: u32,
}

/// A forest of sequences of edges.
pub(super) struct Sequences {
    nodes: Vec<Node>,
    /// The node holding each edge, `NIL` when the edge is in no sequence.
    node_of: Vec<u32>,
    /// Released nodes, reused first.
    free: Vec<u32>,
    /// Scratch of [`Sequences::replace_run`].
    run: Vec<u32>,
}

/// Why [`Sequences::replace_run`] refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ReplaceError {
    /// The old edges are not consecutive (cyclically) in one sequence.
    NotARun,
    /// A new edge already is in a sequence.
    InUse,
}

/// The finalizer of SplitMix64: a fixed, well-mixed priority per node.
fn priority(e: u32) -> u32 {
    let mut z = u64::from(e).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (z ^ (z >> 31)) as u32
}

impl Sequences {
    /// Room for edges `0..edges`, none in a sequence.
    pub(super) fn new(edges: usize) -> Self {
        Sequences {
            nodes: Vec::new(),
            node_of: vec![NIL; edges],
            free: Vec::new(),
            run: Vec::new(),
        }
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
        self.node_of[e.idx()] != NIL
    }

    /// Number of edges in the sequence whose root is `t`.
    #[inline]
    pub(super) fn len(&self, t: u32) -> u32 {
        self.size(t)
    }

    /// A one-edge sequence; `None` when the edge already is in one.
    pub(super) fn single(&mut self, e: EdgeId) -> Option<u32> {
        if self.node_of[e.idx()] != NIL {
            return None;
        }
        let fresh = |id: u32| Node {
            left: NIL,
            right: NIL,
            parent: NIL,
            size: 1,
            priority: priority(id),
            edge: e.0,
            tag: NIL,
        };
        let x = match self.free.pop() {
            Some(x) => {
                self.nodes[x as usize] = fresh(x);
                x
            }
            None => {
                let x = self.nodes.len() as u32;
                self.nodes.push(fresh(x));
                x
            }
        };
        self.node_of[e.idx()] = x;
        Some(x)
    }

    /// The root of the sequence holding `e` (which must be in one) and the
    /// position of `e` in it.
    pub(super) fn locate(&self, e: EdgeId) -> (u32, u32) {
        let mut x = self.node_of[e.idx()];
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

    fn leftmost(&self, mut t: u32) -> u32 {
        while self.nodes[t as usize].left != NIL {
            t = self.nodes[t as usize].left;
        }
        t
    }

    /// The first edge of the sequence rooted at `t` (`t != NIL`).
    pub(super) fn first(&self, t: u32) -> u32 {
        self.nodes[self.leftmost(t) as usize].edge
    }

    /// The last edge of the sequence rooted at `t` (`t != NIL`).
    pub(super) fn last(&self, mut t: u32) -> u32 {
        while self.nodes[t as usize].right != NIL {
            t = self.nodes[t as usize].right;
        }
        self.nodes[t as usize].edge
    }

    /// The node after `x` in its sequence, read cyclically (the first
    /// after the last).
    fn next_cyclic(&self, mut x: u32) -> u32 {
        let right = self.nodes[x as usize].right;
        if right != NIL {
            return self.leftmost(right);
        }
        loop {
            let p = self.nodes[x as usize].parent;
            if p == NIL {
                return self.leftmost(x);
            }
            if self.nodes[p as usize].left == x {
                return p;
            }
            x = p;
        }
    }

    /// Moves `y` above its parent (a tree rotation); the parent's tag goes
    /// with the root.
    fn rotate_up(&mut self, y: u32) {
        let p = self.nodes[y as usize].parent;
        let g = self.nodes[p as usize].parent;
        if self.nodes[p as usize].left == y {
            let b = self.nodes[y as usize].right;
            self.nodes[p as usize].left = b;
            if b != NIL {
                self.nodes[b as usize].parent = p;
            }
            self.nodes[y as usize].right = p;
        } else {
            let b = self.nodes[y as usize].left;
            self.nodes[p as usize].right = b;
            if b != NIL {
                self.nodes[b as usize].parent = p;
            }
            self.nodes[y as usize].left = p;
        }
        self.nodes[p as usize].parent = y;
        self.nodes[y as usize].parent = g;
        if g == NIL {
            self.nodes[y as usize].tag = self.nodes[p as usize].tag;
        } else if self.nodes[g as usize].left == p {
            self.nodes[g as usize].left = y;
        } else {
            self.nodes[g as usize].right = y;
        }
        self.update(p);
        self.update(y);
    }

    /// Inserts edge `e` right after node `x`; returns its node.
    fn insert_after(&mut self, x: u32, e: EdgeId) -> Option<u32> {
        let y = self.single(e)?;
        let right = self.nodes[x as usize].right;
        let p = if right == NIL {
            self.nodes[x as usize].right = y;
            x
        } else {
            let p = self.leftmost(right);
            self.nodes[p as usize].left = y;
            p
        };
        self.nodes[y as usize].parent = p;
        let mut a = p;
        while a != NIL {
            self.nodes[a as usize].size += 1;
            a = self.nodes[a as usize].parent;
        }
        while self.nodes[y as usize].parent != NIL && self.above(y, self.nodes[y as usize].parent) {
            self.rotate_up(y);
        }
        Some(y)
    }

    /// Removes node `x` (not the only node of its sequence) and frees it.
    fn remove(&mut self, x: u32) {
        loop {
            let Node { left, right, .. } = self.nodes[x as usize];
            let c = match (left, right) {
                (NIL, NIL) => break,
                (NIL, c) | (c, NIL) => c,
                (l, r) if self.above(l, r) => l,
                (_, r) => r,
            };
            self.rotate_up(c);
        }
        let p = self.nodes[x as usize].parent;
        if self.nodes[p as usize].left == x {
            self.nodes[p as usize].left = NIL;
        } else {
            self.nodes[p as usize].right = NIL;
        }
        let mut a = p;
        while a != NIL {
            self.nodes[a as usize].size -= 1;
            a = self.nodes[a as usize].parent;
        }
        let edge = self.nodes[x as usize].edge;
        if self.node_of[edge as usize] == x {
            self.node_of[edge as usize] = NIL;
        }
        self.free.push(x);
    }

    /// Replaces the run `old` (edges consecutive in this order, cyclically,
    /// in one sequence) by the edges `new`, in place: the sequence keeps its
    /// tag and every other edge its neighbours. `old` and `new` are not
    /// empty and share no edge.
    pub(super) fn replace_run(
        &mut self,
        old: &[EdgeId],
        new: &[EdgeId],
    ) -> Result<(), ReplaceError> {
        let mut run = std::mem::take(&mut self.run);
        run.clear();
        let mut x = self.node_of[old[0].idx()];
        for (i, e) in old.iter().enumerate() {
            if i > 0 {
                x = self.next_cyclic(x);
            }
            if x == NIL || self.nodes[x as usize].edge != e.0 {
                self.run = run;
                return Err(ReplaceError::NotARun);
            }
            run.push(x);
        }
        for e in old {
            self.node_of[e.idx()] = NIL;
        }
        let result = self.relabel(&run, new);
        self.run = run;
        result
    }

    fn relabel(&mut self, run: &[u32], new: &[EdgeId]) -> Result<(), ReplaceError> {
        let common = run.len().min(new.len());
        for (&x, e) in run.iter().zip(new) {
            if self.node_of[e.idx()] != NIL {
                return Err(ReplaceError::InUse);
            }
            self.node_of[e.idx()] = x;
            self.nodes[x as usize].edge = e.0;
        }
        let mut last = run[common - 1];
        for &e in &new[common..] {
            last = self.insert_after(last, e).ok_or(ReplaceError::InUse)?;
        }
        for &x in &run[common..] {
            self.remove(x);
        }
        Ok(())
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

    /// The nodes of the tree rooted at `t`, in order, appended to `out`.
    fn collect_nodes(&self, t: u32, out: &mut Vec<u32>) {
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

    /// The edges of the sequence rooted at `t`, in order, appended to `out`.
    pub(super) fn collect(&self, t: u32, out: &mut Vec<u32>) {
        let from = out.len();
        self.collect_nodes(t, out);
        for x in &mut out[from..] {
            *x = self.nodes[*x as usize].edge;
        }
    }

    /// Removes every edge of the sequence rooted at `t` from the forest.
    pub(super) fn release(&mut self, t: u32, scratch: &mut Vec<u32>) {
        scratch.clear();
        self.collect_nodes(t, scratch);
        for &x in scratch.iter() {
            let edge = self.nodes[x as usize].edge;
            self.node_of[edge as usize] = NIL;
            self.free.push(x);
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

    /// The cyclic sequence holding `e`, read from `e`.
    fn cycle_from(s: &Sequences, e: u32) -> Vec<u32> {
        let (root, pos) = s.locate(EdgeId(e));
        let mut v = seq(s, root);
        v.rotate_left(pos as usize);
        v
    }

    #[test]
    fn replace_run_agrees_with_a_vector_and_keeps_the_tag() {
        let edges = 400u32;
        let mut s = Sequences::new(edges as usize);
        let mut model: Vec<u32> = (0..40).collect();
        let t = s.build(model.iter().map(|&e| EdgeId(e))).unwrap();
        s.set_tag(t, 7);
        let mut state = 1u64;
        let mut rand = |n: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            ((state >> 33) as usize) % n
        };
        for step in 0..3000 {
            let len = model.len();
            let p = rand(len);
            let r = 1 + rand(len.min(6));
            let u = 1 + rand(6);
            let old: Vec<u32> = (0..r).map(|i| model[(p + i) % len]).collect();
            let free: Vec<u32> = (0..edges).filter(|e| !model.contains(e)).collect();
            let start = rand(free.len() - u);
            let new: Vec<u32> = free[start..start + u].to_vec();
            let old_ids: Vec<EdgeId> = old.iter().map(|&e| EdgeId(e)).collect();
            let new_ids: Vec<EdgeId> = new.iter().map(|&e| EdgeId(e)).collect();
            assert_eq!(s.replace_run(&old_ids, &new_ids), Ok(()), "step {step}");
            // The model: rotate the run to the front, swap it for `new`.
            model.rotate_left(p);
            model.splice(0..r, new.iter().copied());
            assert_eq!(cycle_from(&s, new[0]), model, "step {step}");
            let (root, _) = s.locate(EdgeId(new[0]));
            check(&s, root);
            assert_eq!(s.tag(root), 7, "step {step}");
            for &e in &old {
                assert!(!s.contains(EdgeId(e)));
            }
            // Keep the sequence between 10 and 60 edges.
            if model.len() > 60 || model.len() < 10 {
                let keep = if model.len() > 60 { 30 } else { model.len() };
                let (root, _) = s.locate(EdgeId(model[0]));
                let mut scratch = Vec::new();
                s.release(root, &mut scratch);
                model.truncate(keep);
                while model.len() < 10 {
                    let e = (0..edges).find(|e| !model.contains(e)).unwrap();
                    model.push(e);
                }
                let t = s.build(model.iter().map(|&e| EdgeId(e))).unwrap();
                s.set_tag(t, 7);
            }
        }
    }

    #[test]
    fn replace_run_refuses_a_broken_run_and_an_edge_in_use() {
        let mut s = Sequences::new(20);
        let t = s.build((0..10).map(EdgeId)).unwrap();
        let other = s.build((10..12).map(EdgeId)).unwrap();
        assert_ne!(t, other);
        let ids = |v: &[u32]| v.iter().map(|&e| EdgeId(e)).collect::<Vec<_>>();
        assert_eq!(
            s.replace_run(&ids(&[3, 5]), &ids(&[15])),
            Err(ReplaceError::NotARun)
        );
        assert_eq!(
            s.replace_run(&ids(&[9, 10]), &ids(&[15])),
            Err(ReplaceError::NotARun)
        );
        assert_eq!(
            s.replace_run(&ids(&[3, 4]), &ids(&[11])),
            Err(ReplaceError::InUse)
        );
        // A run may wrap around the end of the sequence.
        let mut s = Sequences::new(20);
        s.build((0..10).map(EdgeId)).unwrap();
        assert_eq!(s.replace_run(&ids(&[9, 0, 1]), &ids(&[15, 16])), Ok(()));
        assert_eq!(cycle_from(&s, 15), [15, 16, 2, 3, 4, 5, 6, 7, 8]);
    }
}
