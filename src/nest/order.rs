//! An ordered sequence whose order is given by a comparison supplied at
//! each insertion (a treap with parent links, in an arena). The plane
//! sweep keeps the segments that cross the sweep line in it: their order
//! is defined only relative to the current sweep position, never as a key
//! of their own, which is why no keyed map (`BTreeMap`) fits.
//!
//! Insertion, removal and the predecessor take `O(log n)` expected time.
//! Priorities come from a fixed hash of the node's slot, so the shape (and
//! every result) is the same on every run.

const NIL: u32 = u32::MAX;

/// Aligned to a cache line: a step down the tree then reads one line (for
/// values of up to 52 bytes).
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Node<T> {
    value: T,
    left: u32,
    right: u32,
    parent: u32,
}

/// A handle to an element of an [`Order`].
pub type Handle = u32;

/// The sequence.
#[derive(Debug)]
pub struct Order<T> {
    nodes: Vec<Node<T>>,
    free: Vec<u32>,
    root: u32,
}

/// A slot's priority: splitmix64's finaliser of its index, fixed and well
/// spread (computed, not stored: a smaller node is fewer cache misses).
fn priority(h: u32) -> u64 {
    let mut x = u64::from(h).wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

impl<T: Copy> Order<T> {
    /// An empty sequence.
    pub fn new() -> Self {
        Order {
            nodes: Vec::new(),
            free: Vec::new(),
            root: NIL,
        }
    }

    /// The value at a handle.
    pub fn get(&self, h: Handle) -> T {
        self.nodes[h as usize].value
    }

    /// Inserts `value` where `cmp(existing)` says: `Less` when `value`
    /// goes before `existing`, `Greater` after (`Equal` is read as
    /// after). Returns its handle.
    pub fn insert(&mut self, value: T, mut cmp: impl FnMut(&T) -> std::cmp::Ordering) -> Handle {
        let h = match self.free.pop() {
            Some(h) => h,
            None => {
                self.nodes.push(Node {
                    value,
                    left: NIL,
                    right: NIL,
                    parent: NIL,
                });
                (self.nodes.len() - 1) as u32
            }
        };
        self.nodes[h as usize] = Node {
            value,
            left: NIL,
            right: NIL,
            parent: NIL,
        };
        // Descend to a leaf position.
        let mut parent = NIL;
        let mut at = self.root;
        let mut go_left = false;
        while at != NIL {
            parent = at;
            go_left = cmp(&self.nodes[at as usize].value) == std::cmp::Ordering::Less;
            at = if go_left {
                self.nodes[at as usize].left
            } else {
                self.nodes[at as usize].right
            };
        }
        self.nodes[h as usize].parent = parent;
        if parent == NIL {
            self.root = h;
        } else if go_left {
            self.nodes[parent as usize].left = h;
        } else {
            self.nodes[parent as usize].right = h;
        }
        // Rotate up while the parent has a lower priority.
        while let Some(p) = self.parent(h) {
            if priority(p) >= priority(h) {
                break;
            }
            self.rotate_up(h);
        }
        h
    }

    /// Removes the element at `h`.
    pub fn remove(&mut self, h: Handle) {
        // Rotate down until it is a leaf (the child of higher priority
        // goes up), then unlink it.
        loop {
            let n = self.nodes[h as usize];
            let child = match (n.left, n.right) {
                (NIL, NIL) => break,
                (l, NIL) => l,
                (NIL, r) => r,
                (l, r) => {
                    if priority(l) > priority(r) {
                        l
                    } else {
                        r
                    }
                }
            };
            self.rotate_up(child);
        }
        let p = self.nodes[h as usize].parent;
        if p == NIL {
            self.root = NIL;
        } else if self.nodes[p as usize].left == h {
            self.nodes[p as usize].left = NIL;
        } else {
            self.nodes[p as usize].right = NIL;
        }
        self.free.push(h);
    }

    /// The element just before `h`, if any.
    pub fn prev(&self, h: Handle) -> Option<Handle> {
        let n = &self.nodes[h as usize];
        if n.left != NIL {
            let mut at = n.left;
            while self.nodes[at as usize].right != NIL {
                at = self.nodes[at as usize].right;
            }
            return Some(at);
        }
        let mut child = h;
        let mut at = n.parent;
        while at != NIL {
            if self.nodes[at as usize].right == child {
                return Some(at);
            }
            child = at;
            at = self.nodes[at as usize].parent;
        }
        None
    }

    fn parent(&self, h: u32) -> Option<u32> {
        let p = self.nodes[h as usize].parent;
        (p != NIL).then_some(p)
    }

    /// Rotates `h` above its parent, keeping the in-order sequence.
    fn rotate_up(&mut self, h: u32) {
        let p = self.nodes[h as usize].parent;
        let g = self.nodes[p as usize].parent;
        if self.nodes[p as usize].left == h {
            let moved = self.nodes[h as usize].right;
            self.nodes[p as usize].left = moved;
            if moved != NIL {
                self.nodes[moved as usize].parent = p;
            }
            self.nodes[h as usize].right = p;
        } else {
            let moved = self.nodes[h as usize].left;
            self.nodes[p as usize].right = moved;
            if moved != NIL {
                self.nodes[moved as usize].parent = p;
            }
            self.nodes[h as usize].left = p;
        }
        self.nodes[p as usize].parent = h;
        self.nodes[h as usize].parent = g;
        if g == NIL {
            self.root = h;
        } else if self.nodes[g as usize].left == p {
            self.nodes[g as usize].left = h;
        } else {
            self.nodes[g as usize].right = h;
        }
    }

    #[cfg(test)]
    fn in_order(&self) -> Vec<T> {
        let mut out = Vec::new();
        let mut stack = Vec::new();
        let mut at = self.root;
        while at != NIL || !stack.is_empty() {
            while at != NIL {
                stack.push(at);
                at = self.nodes[at as usize].left;
            }
            let h = stack.pop().unwrap_or(NIL);
            out.push(self.nodes[h as usize].value);
            at = self.nodes[h as usize].right;
        }
        out
    }
}

impl<T: Copy> Default for Order<T> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Against a sorted vector: any mix of insertions (by key) and
        /// removals keeps the same sequence, and `prev` is the element
        /// before.
        #[test]
        fn behaves_as_a_sorted_sequence(ops in proptest::collection::vec((0u8..3, 0i32..50), 1..300)) {
            let mut order: Order<i32> = Order::new();
            let mut model: Vec<(i32, Handle)> = Vec::new();
            for (op, key) in ops {
                if op < 2 || model.is_empty() {
                    let h = order.insert(key, |&e| if key < e { std::cmp::Ordering::Less } else { std::cmp::Ordering::Greater });
                    let at = model.partition_point(|&(k, _)| k <= key);
                    model.insert(at, (key, h));
                } else {
                    let (_, h) = model.remove(key as usize % model.len());
                    order.remove(h);
                }
                let keys: Vec<i32> = model.iter().map(|&(k, _)| k).collect();
                prop_assert_eq!(order.in_order(), keys);
                for (i, &(_, h)) in model.iter().enumerate() {
                    let expect = i.checked_sub(1).map(|j| model[j].1);
                    prop_assert_eq!(order.prev(h), expect);
                    prop_assert_eq!(order.get(h), model[i].0);
                }
            }
        }
    }
}
