//! The binary tree the BVH starts from: binned surface-area-heuristic
//! splits over the primitives' boxes, with the leaf cost set by how leaves
//! are tested ([`Leaves`]). The wide tree is collapsed from it. Large
//! trees are built on all threads, into the same tree as on one.

use glam::Vec3;
use rayon::prelude::*;

use super::super::Aabb;
use super::Leaves;

/// Number of centroid bins per axis when searching for a split.
const BINS: usize = 12;
/// Largest number of primitives a leaf may hold (at most 4: the leaf
/// encoding keeps `count - 1` in two bits).
const MAX_LEAF: usize = 4;
/// Relative cost of a box test against a primitive test.
const TRAVERSAL_COST: f32 = 0.5;

/// One node of the binary tree the builder makes: its box, and either two
/// children (`count == 0`: the left child follows this node, the right one
/// is at `offset`) or a leaf of `count` primitives starting at `offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BinaryNode {
    pub(super) bounds: Aabb,
    pub(super) offset: u32,
    pub(super) count: u32,
}

struct BuildItem {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

/// The binary tree over `bounds` (root first, depth first, each left child
/// right after its parent; empty for no boxes) and the permutation to apply
/// to the primitives: leaf slot `i` holds the primitive that was at
/// `order[i]`.
pub(super) fn binary_tree(bounds: &[Aabb], leaves: Leaves) -> (Vec<BinaryNode>, Vec<u32>) {
    let mut items: Vec<BuildItem> = bounds
        .iter()
        .enumerate()
        .map(|(i, b)| BuildItem {
            bounds: *b,
            centroid: b.centroid(),
            index: i as u32,
        })
        .collect();
    let mut binary = Vec::with_capacity(2 * items.len());
    if !items.is_empty() {
        build_node(&mut binary, &mut items, 0, leaves);
    }
    (binary, items.iter().map(|it| it.index).collect())
}

/// Item counts from which the two halves of a split are built on two
/// threads: below it, a subtree costs less than handing it to another.
const PARALLEL_ITEMS: usize = 4096;

/// Appends the binary subtree over `items` (whose first primitive slot is
/// `first`) to `nodes`, depth first, left child right after its parent.
/// Large subtrees build their two halves in parallel (rayon) into nodes of
/// their own, joined in the same order, so the tree is the same on any
/// number of threads.
fn build_node(nodes: &mut Vec<BinaryNode>, items: &mut [BuildItem], first: usize, leaves: Leaves) {
    let (bounds, centroids) = extents(items);
    let leaf = |nodes: &mut Vec<BinaryNode>| {
        nodes.push(BinaryNode {
            bounds,
            offset: first as u32,
            count: items.len() as u32,
        })
    };
    if items.len() <= 1 {
        leaf(nodes);
        return;
    }
    let split = best_split(items, &centroids, bounds.area());
    let packed = match leaves {
        Leaves::Scalar => false,
        Leaves::Packed => true,
        Leaves::PackedWhere(flags) => items.iter().all(|it| flags[it.index as usize]),
    };
    let leaf_cost = if packed { 1.0 } else { items.len() as f32 };
    if items.len() <= MAX_LEAF && split.is_none_or(|(_, _, cost)| cost >= leaf_cost) {
        leaf(nodes);
        return;
    }
    let (axis, mut mid) = match split {
        Some((axis, boundary, _)) => (
            axis,
            partition(items, |it| bin_of(it.centroid, &centroids, axis) < boundary),
        ),
        None => (bounds.extent().max_position(), 0),
    };
    if mid == 0 || mid == items.len() {
        // All centroids coincide: halve by order along the widest axis.
        items.sort_by(|a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
        mid = items.len() / 2;
    }
    let me = nodes.len();
    nodes.push(BinaryNode {
        bounds,
        offset: 0,
        count: 0,
    });
    let parallel = items.len() >= PARALLEL_ITEMS;
    let (left, right) = items.split_at_mut(mid);
    if parallel {
        let (mut right_nodes, ()) = rayon::join(
            || {
                let mut own = Vec::with_capacity(2 * right.len());
                build_node(&mut own, right, first + mid, leaves);
                own
            },
            || build_node(nodes, left, first, leaves),
        );
        let base = nodes.len() as u32;
        nodes[me].offset = base;
        // Inner nodes point at their right child by index; leaves at
        // primitive slots, which do not move.
        for n in &mut right_nodes {
            if n.count == 0 {
                n.offset += base;
            }
        }
        nodes.append(&mut right_nodes);
    } else {
        build_node(nodes, left, first, leaves);
        nodes[me].offset = nodes.len() as u32;
        build_node(nodes, right, first + mid, leaves);
    }
}

fn bin_of(c: Vec3, centroids: &Aabb, axis: usize) -> usize {
    let lo = centroids.min[axis];
    let ext = centroids.max[axis] - lo;
    if ext <= 0.0 {
        return 0;
    }
    (((c[axis] - lo) / ext * BINS as f32) as usize).min(BINS - 1)
}

/// Item counts from which a node's scans over its items run on all
/// threads, in chunks of [`SCAN_CHUNK`]: boxes merge exactly (minima and
/// maxima) and counts add, so the result is the sequential scan's.
const PARALLEL_SCAN: usize = 1 << 16;
const SCAN_CHUNK: usize = 1 << 14;

/// A scan over `items` that folds chunks with `scan` and merges their
/// results with `merge`: on all threads when there are many items.
fn scan<T: Send>(
    items: &[BuildItem],
    scan: impl Fn(&[BuildItem]) -> T + Sync,
    merge: impl Fn(T, T) -> T + Sync,
) -> T {
    if items.len() < PARALLEL_SCAN {
        return scan(items);
    }
    items
        .par_chunks(SCAN_CHUNK)
        .map(&scan)
        .reduce_with(&merge)
        .expect("a large scan has chunks")
}

/// The box around the items and the box around their centroids.
fn extents(items: &[BuildItem]) -> (Aabb, Aabb) {
    scan(
        items,
        |chunk| {
            chunk.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), it| {
                (b.union(&it.bounds), c.grow(it.centroid))
            })
        },
        |(a, b), (c, d)| (a.union(&c), b.union(&d)),
    )
}

/// The box and the count of the items in each centroid bin along one axis.
type Bins = ([Aabb; BINS], [usize; BINS]);

/// The items' bins along `axis`, on all threads when there are many.
fn binned(items: &[BuildItem], centroids: &Aabb, axis: usize) -> Bins {
    scan(
        items,
        |chunk| {
            let (mut boxes, mut counts) = ([Aabb::EMPTY; BINS], [0usize; BINS]);
            for it in chunk {
                let b = bin_of(it.centroid, centroids, axis);
                boxes[b] = boxes[b].union(&it.bounds);
                counts[b] += 1;
            }
            (boxes, counts)
        },
        |(mut boxes, mut counts), (other_boxes, other_counts)| {
            for k in 0..BINS {
                boxes[k] = boxes[k].union(&other_boxes[k]);
                counts[k] += other_counts[k];
            }
            (boxes, counts)
        },
    )
}

/// The best (axis, first bin of the right side, SAH cost in units of one
/// primitive test) over all binned splits, if any splits the items.
fn best_split(
    items: &[BuildItem],
    centroids: &Aabb,
    parent_area: f32,
) -> Option<(usize, usize, f32)> {
    let mut best: Option<(usize, usize, f32)> = None;
    for axis in 0..3 {
        if centroids.extent()[axis] <= 0.0 {
            continue;
        }
        let (boxes, counts) = binned(items, centroids, axis);
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for b in (1..BINS).rev() {
            acc = acc.union(&boxes[b]);
            n += counts[b];
            right_area[b] = acc.area();
            right_count[b] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for b in 1..BINS {
            acc = acc.union(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || right_count[b] == 0 {
                continue;
            }
            let cost = TRAVERSAL_COST
                + (acc.area() * n as f32 + right_area[b] * right_count[b] as f32)
                    / parent_area.max(f32::MIN_POSITIVE);
            if best.is_none_or(|(_, _, c)| cost < c) {
                best = Some((axis, b, cost));
            }
        }
    }
    best
}

/// Moves the items satisfying `left` to the front; returns how many there are.
fn partition(items: &mut [BuildItem], left: impl Fn(&BuildItem) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::numbers;

    /// Checks the subtree at `i` against the items' boxes: every child's
    /// box inside its parent's, the left child right after its parent, and
    /// each leaf's slots marked in `seen`; returns the index past it.
    fn check(
        nodes: &[BinaryNode],
        i: usize,
        boxes: &[Aabb],
        order: &[u32],
        seen: &mut [bool],
    ) -> usize {
        let n = nodes[i];
        let inside = |b: &Aabb| n.bounds.union(b) == n.bounds;
        if n.count > 0 {
            for slot in n.offset..n.offset + n.count {
                assert!(!seen[slot as usize], "slot {slot} in two leaves");
                seen[slot as usize] = true;
                assert!(inside(&boxes[order[slot as usize] as usize]));
            }
            return i + 1;
        }
        assert!(inside(&nodes[i + 1].bounds) && inside(&nodes[n.offset as usize].bounds));
        let end = check(nodes, i + 1, boxes, order, seen);
        assert_eq!(
            end, n.offset as usize,
            "the right child follows the left subtree"
        );
        check(nodes, end, boxes, order, seen)
    }

    #[test]
    fn a_large_tree_built_on_several_threads_is_the_one_thread_tree_and_sound() {
        // Enough boxes that the root's scans run in chunks on all threads
        // and subtrees are built in parallel, a third of them at one point
        // (whose split falls back to halving by order).
        let mut u = numbers(7);
        let boxes: Vec<Aabb> = (0..200_000)
            .map(|i| {
                let c = if i % 3 == 0 {
                    Vec3::splat(0.5)
                } else {
                    Vec3::new(u(), u(), u())
                };
                Aabb::new(c - Vec3::splat(1e-3 * u()), c + Vec3::splat(1e-3))
            })
            .collect();
        let build = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool")
                .install(|| binary_tree(&boxes, Leaves::Scalar))
        };
        let (nodes, order) = build(1);
        assert_eq!(build(4), (nodes.clone(), order.clone()));
        let mut seen = vec![false; boxes.len()];
        assert_eq!(check(&nodes, 0, &boxes, &order, &mut seen), nodes.len());
        assert!(seen.iter().all(|&s| s), "every slot in a leaf");
    }

    /// The primitive indices of each leaf, as sets.
    fn leaf_sets(nodes: &[BinaryNode], order: &[u32]) -> Vec<Vec<u32>> {
        let mut out: Vec<Vec<u32>> = nodes
            .iter()
            .filter(|n| n.count > 0)
            .map(|n| {
                let mut leaf = order[n.offset as usize..(n.offset + n.count) as usize].to_vec();
                leaf.sort_unstable();
                leaf
            })
            .collect();
        out.sort();
        out
    }

    #[test]
    fn flagged_items_fill_their_leaves_and_the_others_keep_the_scalar_leaves() {
        // Overlapping flagged boxes in one half of the unit cube, unflagged
        // ones in the other, so the root's split separates the two kinds.
        let mut u = numbers(3);
        let boxes: Vec<Aabb> = (0..2000)
            .map(|i| {
                let x = 0.5 * u() + if i % 2 == 0 { 0.0 } else { 0.5 };
                let c = Vec3::new(x, u(), u());
                Aabb::new(c - Vec3::splat(0.05), c + Vec3::splat(0.05))
            })
            .collect();
        let flags: Vec<bool> = (0..boxes.len()).map(|i| i % 2 == 0).collect();
        let mean_size = |leaves: &[Vec<u32>], flagged: bool| {
            let kind: Vec<&Vec<u32>> = leaves
                .iter()
                .filter(|l| flags[l[0] as usize] == flagged)
                .collect();
            kind.iter().map(|l| l.len()).sum::<usize>() as f32 / kind.len() as f32
        };
        let (scalar_nodes, scalar_order) = binary_tree(&boxes, Leaves::Scalar);
        let (nodes, order) = binary_tree(&boxes, Leaves::PackedWhere(&flags));
        let (scalar, mixed) = (
            leaf_sets(&scalar_nodes, &scalar_order),
            leaf_sets(&nodes, &order),
        );
        // No leaf mixes the kinds here, and the flagged leaves come out fuller.
        for leaf in &mixed {
            assert!(leaf
                .iter()
                .all(|&i| flags[i as usize] == flags[leaf[0] as usize]));
        }
        eprintln!(
            "flagged leaves: {} packed, {} scalar",
            mean_size(&mixed, true),
            mean_size(&scalar, true)
        );
        assert!(
            mean_size(&scalar, true) < 1.5,
            "{}",
            mean_size(&scalar, true)
        );
        assert!(mean_size(&mixed, true) > 2.5, "{}", mean_size(&mixed, true));
        let unflagged = |sets: &[Vec<u32>]| -> Vec<Vec<u32>> {
            sets.iter()
                .filter(|l| !flags[l[0] as usize])
                .cloned()
                .collect()
        };
        assert_eq!(unflagged(&mixed), unflagged(&scalar));
        let mut seen = vec![false; boxes.len()];
        assert_eq!(check(&nodes, 0, &boxes, &order, &mut seen), nodes.len());
        assert!(seen.iter().all(|&s| s), "every slot in a leaf");
    }
}
