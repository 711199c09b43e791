//! A bounding volume hierarchy built with the binned surface-area heuristic,
//! stored as a flat array of 32-byte nodes and traversed iteratively with a
//! fixed-size stack, nearest child first, without allocation.
//!
//! The hierarchy knows only boxes: the caller reorders its primitives by
//! [`Bvh::order`] after building and intersects them in a visitor closure.

use glam::Vec3;

use super::{Aabb, Ray};

/// Number of centroid bins per axis when searching for a split.
const BINS: usize = 12;
/// Largest number of primitives a leaf may hold.
const MAX_LEAF: usize = 4;
/// Depth of the traversal stack; a SAH tree over 2^32 items stays below it.
const STACK: usize = 64;
/// Relative cost of a box test against a primitive test.
const TRAVERSAL_COST: f32 = 0.5;

/// One node: its box, and either two children (`count == 0`: the left child
/// follows this node, the right one is at `offset`) or a leaf of `count`
/// primitives starting at `offset`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct BvhNode {
    min: [f32; 3],
    offset: u32,
    max: [f32; 3],
    count: u16,
    axis: u16,
}

/// The hierarchy: nodes (root first) and the primitive order its leaves use.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
}

struct BuildItem {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

impl BvhNode {
    fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::from(self.min),
            max: Vec3::from(self.max),
        }
    }

    #[inline]
    fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<f32> {
        let t0 = (Vec3::from(self.min) - origin) * inv_dir;
        let t1 = (Vec3::from(self.max) - origin) * inv_dir;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max);
        // The factor absorbs the rounding of the slab distances (robust
        // traversal, Ize 2013), so rays grazing a box edge are not lost.
        if near <= far * (1.0 + 2.0 * f32::EPSILON * 2.0) {
            Some(near)
        } else {
            None
        }
    }
}

impl Bvh {
    /// Builds a hierarchy over the given primitive boxes. Returns it with
    /// the permutation to apply to the primitives: leaf slot `i` holds the
    /// primitive that was at `order[i]`.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        let mut items: Vec<BuildItem> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| BuildItem {
                bounds: *b,
                centroid: b.centroid(),
                index: i as u32,
            })
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * bounds.len().max(1)),
        };
        if items.is_empty() {
            return (bvh, Vec::new());
        }
        bvh.build_node(&mut items, 0);
        let order = items.iter().map(|it| it.index).collect();
        (bvh, order)
    }

    /// Bytes held by the nodes.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<BvhNode>()
    }

    /// The box of everything in the hierarchy.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, BvhNode::bounds)
    }

    fn push_leaf(&mut self, bounds: Aabb, first: usize, count: usize) {
        self.nodes.push(BvhNode {
            min: bounds.min.into(),
            offset: first as u32,
            max: bounds.max.into(),
            count: count as u16,
            axis: 0,
        });
    }

    fn build_node(&mut self, items: &mut [BuildItem], first: usize) {
        let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(&it.bounds));
        if items.len() <= 1 {
            self.push_leaf(bounds, first, items.len());
            return;
        }
        let centroids = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
        let split = best_split(items, &centroids);
        let leaf_cost = items.len() as f32;
        if items.len() <= MAX_LEAF && split.is_none_or(|(_, _, cost)| cost >= leaf_cost) {
            self.push_leaf(bounds, first, items.len());
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
        let me = self.nodes.len();
        self.nodes.push(BvhNode {
            min: bounds.min.into(),
            offset: 0,
            max: bounds.max.into(),
            count: 0,
            axis: axis as u16,
        });
        let (left, right) = items.split_at_mut(mid);
        self.build_node(left, first);
        self.nodes[me].offset = self.nodes.len() as u32;
        self.build_node(right, first + mid);
    }

    /// Visits, nearest first as far as the tree tells, every leaf primitive
    /// whose box the ray enters before `t_max`. `visit(slot, t_max)` returns
    /// a new, closer `t_max` when it found a hit.
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut visit: impl FnMut(usize, f32) -> Option<f32>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let inv_dir = ray.dir.recip();
        let negative = [ray.dir.x < 0.0, ray.dir.y < 0.0, ray.dir.z < 0.0];
        let mut stack = [0u32; STACK];
        let mut top = 0usize;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.hit(ray.origin, inv_dir, t_max).is_some() {
                if node.count > 0 {
                    let start = node.offset as usize;
                    for slot in start..start + node.count as usize {
                        if let Some(t) = visit(slot, t_max) {
                            t_max = t;
                        }
                    }
                } else {
                    let (near, far) = if negative[node.axis as usize] {
                        (node.offset as usize, current + 1)
                    } else {
                        (current + 1, node.offset as usize)
                    };
                    if top < STACK {
                        stack[top] = far as u32;
                        top += 1;
                    }
                    current = near;
                    continue;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            current = stack[top] as usize;
        }
    }

    /// Whether `hit(slot, t_max)` is true for some leaf primitive whose box
    /// the ray enters before `t_max`: an any-hit walk for shadow rays that
    /// stops visiting primitives at the first hit (the rest of the walk only
    /// drains the stack, every box now failing against a negative `t_max`).
    #[inline]
    pub fn traverse_any(
        &self,
        ray: &Ray,
        t_max: f32,
        mut hit: impl FnMut(usize, f32) -> bool,
    ) -> bool {
        let mut found = false;
        self.traverse(ray, t_max, |slot, t| {
            if found || !hit(slot, t) {
                return None;
            }
            found = true;
            Some(-1.0)
        });
        found
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_are_32_bytes() {
        assert_eq!(std::mem::size_of::<BvhNode>(), 32);
    }

    #[test]
    fn traversal_finds_every_box_a_ray_crosses() {
        let boxes: Vec<Aabb> = (0..200)
            .map(|i| {
                let x = i as f32 * 1.5;
                Aabb::new(Vec3::new(x, -1.0, -1.0), Vec3::new(x + 1.0, 1.0, 1.0))
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, 0.0);
        let mut seen = Vec::new();
        bvh.traverse(&ray, f32::INFINITY, |slot, _| {
            seen.push(order[slot]);
            None
        });
        seen.sort_unstable();
        assert_eq!(seen, (0..200).collect::<Vec<u32>>());
        let miss = Ray::new(Vec3::new(-5.0, 3.0, 0.0), Vec3::X, 0.0);
        let mut any = false;
        bvh.traverse(&miss, f32::INFINITY, |_, _| {
            any = true;
            None
        });
        assert!(!any);
    }
}
