//! The order of the triangles in the leaves: Morton order of their
//! centroids' cells (a heuristic that shapes the tree, never the answer),
//! a group's triangles kept together.

use super::NO_GROUP;

/// Spreads the low 10 bits of `x` to every third bit.
pub(super) fn spread(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | x << 16) & 0x030000ff;
    x = (x | x << 8) & 0x0300f00f;
    x = (x | x << 4) & 0x030c30c3;
    x = (x | x << 2) & 0x09249249;
    x
}

/// The positions `0..codes.len()` in ascending order of their codes, ties
/// by position (a stable least-significant-digit radix sort of `code << 32
/// | position`, four passes of 8 bits).
pub(super) fn morton_order(codes: &[u32]) -> Vec<u32> {
    let mut keys: Vec<u64> = codes
        .iter()
        .enumerate()
        .map(|(t, &c)| u64::from(c) << 32 | t as u64)
        .collect();
    let mut other = vec![0u64; keys.len()];
    for pass in 0..4 {
        let shift = 32 + 8 * pass;
        let mut count = [0usize; 257];
        for &k in keys.iter() {
            count[((k >> shift) & 0xff) as usize + 1] += 1;
        }
        for d in 0..256 {
            count[d + 1] += count[d];
        }
        for &k in keys.iter() {
            let d = ((k >> shift) & 0xff) as usize;
            other[count[d]] = k;
            count[d] += 1;
        }
        std::mem::swap(&mut keys, &mut other);
    }
    keys.into_iter().map(|k| k as u32).collect()
}

/// The positions ordered as [`morton_order`], except that the triangles of
/// a group follow one another (in that order) at the place of the group's
/// first triangle in it. Groups are numbered from 0.
pub(super) fn grouped_order(codes: &[u32], groups: &[u32]) -> Vec<u32> {
    let morton = morton_order(codes);
    // Each group's triangles in Morton order, by a counting sort.
    let n_groups = groups
        .iter()
        .filter(|&&g| g != NO_GROUP)
        .max()
        .map_or(0, |&g| g as usize + 1);
    let mut start = vec![0usize; n_groups + 1];
    for &g in groups.iter().filter(|&&g| g != NO_GROUP) {
        start[g as usize + 1] += 1;
    }
    for g in 0..n_groups {
        start[g + 1] += start[g];
    }
    let mut fill = start.clone();
    let mut by_group = vec![0u32; start[n_groups]];
    for &t in &morton {
        let g = groups[t as usize];
        if g != NO_GROUP {
            by_group[fill[g as usize]] = t;
            fill[g as usize] += 1;
        }
    }
    let mut placed = vec![false; n_groups];
    let mut order = Vec::with_capacity(morton.len());
    for &t in &morton {
        match groups[t as usize] {
            NO_GROUP => order.push(t),
            g if !placed[g as usize] => {
                placed[g as usize] = true;
                order.extend_from_slice(&by_group[start[g as usize]..start[g as usize + 1]]);
            }
            _ => {}
        }
    }
    order
}
