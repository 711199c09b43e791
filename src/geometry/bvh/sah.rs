//! The binary tree the BVH starts from: binned surface-area-heuristic
//! splits over the primitives' boxes, with the leaf cost set by how leaves
//! are tested ([`Leaves`]). The wide tree is collapsed from it.

use glam::Vec3;

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
#[derive(Clone, Copy, Debug)]
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

/// Appends the binary subtree over `items` (whose first primitive slot is
/// `first`) to `nodes`, depth first, left child right after its parent.
fn build_node(nodes: &mut Vec<BinaryNode>, items: &mut [BuildItem], first: usize, leaves: Leaves) {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(&it.bounds));
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
    let centroids = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let split = best_split(items, &centroids);
    let leaf_cost = match leaves {
        Leaves::Scalar => items.len() as f32,
        Leaves::Packed => 1.0,
    };
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
    let (left, right) = items.split_at_mut(mid);
    build_node(nodes, left, first, leaves);
    nodes[me].offset = nodes.len() as u32;
    build_node(nodes, right, first + mid, leaves);
}

fn bin_of(c: Vec3, centroids: &Aabb, axis: usize) -> usize {
    let lo = centroids.min[axis];
    let ext = centroids.max[axis] - lo;
    if ext <= 0.0 {
        return 0;
    }
    (((c[axis] - lo) / ext * BINS as f32) as usize).min(BINS - 1)
}

/// The best (axis, first bin of the right side, SAH cost in units of one
/// primitive test) over all binned splits, if any splits the items.
fn best_split(items: &[BuildItem], centroids: &Aabb) -> Option<(usize, usize, f32)> {
    let parent_area = items
        .iter()
        .fold(Aabb::EMPTY, |b, it| b.union(&it.bounds))
        .area();
    let mut best: Option<(usize, usize, f32)> = None;
    for axis in 0..3 {
        if centroids.extent()[axis] <= 0.0 {
            continue;
        }
        let mut boxes = [Aabb::EMPTY; BINS];
        let mut counts = [0usize; BINS];
        for it in items {
            let b = bin_of(it.centroid, centroids, axis);
            boxes[b] = boxes[b].union(&it.bounds);
            counts[b] += 1;
        }
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
