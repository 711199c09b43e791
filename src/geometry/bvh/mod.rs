//! A bounding volume hierarchy: a binary tree built with the binned
//! surface-area heuristic ([`sah`]), collapsed into an 8-wide tree whose
//! nodes hold their children's boxes as lanes, so one node visit tests eight
//! boxes at once ([`node`]: one AVX pass where the CPU has it, two SSE passes
//! elsewhere, the same bits either way). It is traversed iteratively with a
//! fixed-size stack of inner nodes, nearest child first (visited next
//! without a push), leaves visited as soon as their box is hit, entries
//! farther than the closest hit so far skipped, without allocation. Each
//! walk is compiled twice, once with AVX enabled, and picked per call by a
//! cached CPU check. The children hit are ordered by sorting networks,
//! and the stack is an `ArrayVec` that is not zero-filled per ray.
//!
//! The hierarchy knows only boxes: the caller reorders its primitives by the
//! permutation [`Bvh::build`] returns and intersects them in a visitor closure,
//! a slot or a leaf at a time (a leaf by its first slot, or by a number the
//! caller gave it: [`Bvh::number_leaves`]); it tells the builder whether its
//! leaves are tested one primitive at a time or four at once ([`Leaves`]). Up to eight
//! rays that cross much the same boxes can walk it together ([`packet`]).

mod node;
mod packet;
mod sah;

use arrayvec::ArrayVec;

use super::{Aabb, Ray};
#[cfg(target_arch = "x86_64")]
use crate::simd::avx;
use node::{node_hit, BoxRay, BvhNode, CHILDREN};
pub use packet::bits;
use sah::BinaryNode;

/// Depth of the traversal stack: a node pushes at most 7 more entries than
/// it pops, and an 8-wide level stands for three binary SAH levels.
const STACK: usize = 128;
/// A child word with this bit is a leaf: bits 29–30 hold `count - 1`, the
/// low 29 bits its first primitive slot. Otherwise it is a node index.
const LEAF: u32 = 1 << 31;
/// Slots a leaf's first primitive can address (2^29, far beyond memory).
const SLOT_MASK: u32 = (1 << 29) - 1;

/// How the primitives of a leaf are tested, which sets what a leaf costs
/// the surface-area heuristic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Leaves<'a> {
    /// One by one: a leaf costs one test per primitive.
    Scalar,
    /// Four at once ([`crate::geometry::leaf`]): a leaf of up to four costs
    /// about one test, so leaves come out full.
    Packed,
    /// Four at once where every primitive of the leaf is flagged (the
    /// spheres of a set of several kinds), one by one elsewhere.
    PackedWhere(&'a [bool]),
}

/// The hierarchy: wide nodes (root first) and the box around everything.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
    bounds: Aabb,
}

/// A stack entry: a node index and the ray's entry distance into its box.
#[inline(always)]
fn pack(child: u32, near: f32) -> u64 {
    (u64::from(near.to_bits()) << 32) | u64::from(child)
}

#[inline(always)]
fn unpack(entry: u64) -> (u32, f32) {
    (entry as u32, f32::from_bits((entry >> 32) as u32))
}

/// Each lane's entry distance and lane number as one sortable key: the
/// distance's bits above (non-negative floats order as integers), the lane
/// below, written `7 - lane` so that equal distances keep the later lane
/// first.
#[inline(always)]
fn lane_key(dist: f32, lane: usize) -> u64 {
    (u64::from(dist.to_bits()) << 32) | (7 - lane as u64)
}

#[inline(always)]
fn unpack_key(key: u64) -> (usize, f32) {
    (7 - (key & 7) as usize, f32::from_bits((key >> 32) as u32))
}

/// Compare-exchanges that sort four keys (a sorting network).
const NETWORK4: [(usize, usize); 5] = [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)];
/// Compare-exchanges that sort eight keys (Knuth's network of nineteen).
#[rustfmt::skip]
const NETWORK8: [(usize, usize); 19] = [
    (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7), (0, 1), (2, 3),
    (4, 5), (6, 7), (2, 4), (3, 5), (1, 4), (3, 6), (1, 2), (3, 4), (5, 6),
];

/// The keys of the children hit (the set bits of `mask`, at least two) in
/// ascending order, nearest first, and how many there are. Two (the most
/// common case) take one compare-exchange, three or four [`NETWORK4`],
/// five to eight [`NETWORK8`]. A compare-exchange of two keys compiles to
/// conditional moves, so no branch follows the distances: an insertion
/// sort's branches mispredicted on incoherent rays (random rays through
/// the 28k bunny run 1.06–1.13× as fast with the networks). Sorting all
/// eight lanes' keys with the large network, missed children last, saves
/// the gathering loop but was slower.
#[inline(always)]
fn ordered_hits(dist: [f32; CHILDREN], mut mask: u32) -> ([u64; CHILDREN], usize) {
    debug_assert!(mask.count_ones() >= 2);
    let mut keys = [u64::MAX; CHILDREN];
    let exchange = |keys: &mut [u64; CHILDREN], (i, j): (usize, usize)| {
        let (a, b) = (keys[i], keys[j]);
        keys[i] = a.min(b);
        keys[j] = a.max(b);
    };
    let first = mask.trailing_zeros() as usize;
    let rest = mask & mask.wrapping_sub(1);
    if rest & rest.wrapping_sub(1) == 0 {
        let second = rest.trailing_zeros() as usize;
        keys[0] = lane_key(dist[first], first);
        keys[1] = lane_key(dist[second], second);
        exchange(&mut keys, (0, 1));
        return (keys, 2);
    }
    let n = mask.count_ones() as usize;
    for key in &mut keys[..n] {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        *key = lane_key(dist[lane], lane);
    }
    // Each loop runs a fixed count, unrolled into straight code.
    if n <= 4 {
        NETWORK4
            .into_iter()
            .for_each(|pair| exchange(&mut keys, pair));
    } else {
        NETWORK8
            .into_iter()
            .for_each(|pair| exchange(&mut keys, pair));
    }
    (keys, n)
}

impl Bvh {
    /// Builds a hierarchy over the given primitive boxes. Returns it with
    /// the permutation to apply to the primitives: leaf slot `i` holds the
    /// primitive that was at `order[i]`.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        Bvh::build_leaves(bounds, Leaves::Scalar)
    }

    /// [`Bvh::build`] for primitives whose leaves are tested as `leaves` says.
    pub fn build_leaves(bounds: &[Aabb], leaves: Leaves) -> (Bvh, Vec<u32>) {
        let (binary, order) = sah::binary_tree(bounds, leaves);
        let Some(root) = binary.first() else {
            return (Bvh::default(), Vec::new());
        };
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(binary.len() / 3 + 1),
            bounds: root.bounds,
        };
        bvh.collapse(&binary, 0);
        (bvh, order)
    }

    /// Bytes held by the nodes.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<BvhNode>()
    }

    /// The box of everything in the hierarchy.
    pub fn bounds(&self) -> Aabb {
        if self.nodes.is_empty() {
            Aabb::EMPTY
        } else {
            self.bounds
        }
    }

    /// Makes the wide node for binary node `b` (and, recursively, those
    /// below it) and returns its index. Its children are `b`'s, each inner
    /// one with the largest surface area replaced by its own two children
    /// while there is room; a binary leaf at the root is the root's only lane.
    fn collapse(&mut self, binary: &[BinaryNode], b: usize) -> u32 {
        let me = self.nodes.len();
        self.nodes.push(BvhNode::EMPTY);
        let children = |n: usize| [n + 1, binary[n].offset as usize];
        let mut kids = [0usize; CHILDREN];
        let mut len;
        if binary[b].count == 0 {
            kids[..2].copy_from_slice(&children(b));
            len = 2;
        } else {
            kids[0] = b;
            len = 1;
        }
        while len < CHILDREN {
            let widest = (0..len)
                .filter(|&i| binary[kids[i]].count == 0)
                .max_by(|&i, &j| {
                    let area = |k: usize| binary[kids[k]].bounds.area();
                    area(i).total_cmp(&area(j)).then(j.cmp(&i))
                });
            let Some(i) = widest else { break };
            let [l, r] = children(kids[i]);
            kids[i] = l;
            kids[len] = r;
            len += 1;
        }
        for (lane, &k) in kids[..len].iter().enumerate() {
            let n = binary[k];
            let word = if n.count > 0 {
                LEAF | ((n.count - 1) << 29) | (n.offset & SLOT_MASK)
            } else {
                self.collapse(binary, k)
            };
            self.nodes[me].set_lane(lane, &n.bounds, word);
        }
        me as u32
    }

    /// The one leaf as `(first slot, count)` when the whole tree is one
    /// leaf (the root's only lane).
    #[inline(always)]
    fn single_leaf(&self) -> Option<(usize, usize)> {
        let [root] = self.nodes.as_slice() else {
            return None;
        };
        // An unused lane's word is 0, which names the root: never a child.
        let alone = root.child[1..].iter().all(|&w| w == 0);
        (root.child[0] & LEAF != 0 && alone).then(|| leaf_range(root.child[0]))
    }

    /// Gives each leaf `number(first, count)` (below 2^29) in place of its
    /// first slot, visiting the leaves as [`Bvh::leaves`] lists them: the
    /// walks then pass a leaf's number where they passed its first slot. A
    /// caller whose leaves all have a packed form numbers them by their
    /// place in its array of packs, and finds a leaf's pack with no table
    /// from slots to packs (a load fewer per leaf visited).
    pub fn number_leaves(&mut self, mut number: impl FnMut(usize, usize) -> u32) {
        for node in &mut self.nodes {
            for word in &mut node.child {
                if *word & LEAF != 0 {
                    let (first, count) = leaf_range(*word);
                    let n = number(first, count);
                    assert!(n <= SLOT_MASK, "a leaf number fits in 29 bits");
                    *word = (*word & !SLOT_MASK) | n;
                }
            }
        }
    }

    /// The leaves as `(first slot, count)`, each once, in no set order.
    pub fn leaves(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.nodes
            .iter()
            .flat_map(|n| n.child)
            .filter(|&word| word & LEAF != 0)
            .map(leaf_range)
    }

    /// Visits, nearest first as far as the tree tells, every leaf primitive
    /// whose box the ray enters before `t_max`. `visit(slot, t_max)` returns
    /// a new, closer `t_max` when it found a hit. Shadow rays use
    /// [`Bvh::traverse_any`] instead.
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        t_max: f32,
        mut visit: impl FnMut(usize, f32) -> Option<f32>,
    ) {
        self.traverse_leaves(ray, t_max, |first, count, mut t_max| {
            let mut found = None;
            for slot in first..first + count {
                if let Some(t) = visit(slot, t_max) {
                    (t_max, found) = (t, Some(t));
                }
            }
            found
        });
    }

    /// [`Bvh::traverse`] a leaf at a time: `visit(first, count, t_max)`
    /// tests the leaf's slots `first..first + count` (in slot order, so ties
    /// go as they do slot by slot) and returns the closer `t_max` it found.
    #[inline]
    pub fn traverse_leaves(
        &self,
        ray: &Ray,
        t_max: f32,
        visit: impl FnMut(usize, usize, f32) -> Option<f32>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if avx() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.walk_avx(ray, t_max, visit) };
        }
        self.walk::<false>(ray, t_max, visit);
    }

    /// [`Bvh::walk`] compiled with AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn walk_avx(
        &self,
        ray: &Ray,
        t_max: f32,
        visit: impl FnMut(usize, usize, f32) -> Option<f32>,
    ) {
        self.walk::<true>(ray, t_max, visit);
    }

    /// The closest-hit walk of [`Bvh::traverse_leaves`] over a non-empty
    /// tree, with the AVX box test or the SSE one.
    #[inline(always)]
    fn walk<const AVX: bool>(
        &self,
        ray: &Ray,
        t_max: f32,
        visit: impl FnMut(usize, usize, f32) -> Option<f32>,
    ) {
        self.walk_from::<AVX>(0, &BoxRay::new(ray), t_max, visit);
    }

    /// [`Bvh::walk`] of the subtree under node `start` (a packet's walk
    /// goes on so for a ray left alone in it).
    #[inline(always)]
    fn walk_from<const AVX: bool>(
        &self,
        start: u32,
        box_ray: &BoxRay,
        mut t_max: f32,
        mut visit: impl FnMut(usize, usize, f32) -> Option<f32>,
    ) {
        // Not zero-filled: the stack is 1 KiB and most rays need a few entries.
        let mut stack = ArrayVec::<u64, STACK>::new();
        let mut current = Some(start);
        while let Some(index) = current.take().or_else(|| {
            while let Some(entry) = stack.pop() {
                let (index, near) = unpack(entry);
                if near <= t_max {
                    return Some(index);
                }
            }
            None
        }) {
            let node = &self.nodes[index as usize];
            let (dist, mask) = node_hit::<AVX>(node, box_ray, t_max);
            if mask & mask.wrapping_sub(1) == 0 {
                if mask == 0 {
                    continue;
                }
                // One child (most nodes a coherent ray visits): nothing to
                // order. (Sending it through the loop below instead, so that
                // `visit` has one call site, cost Cornell 3 % more
                // instructions.)
                let lane = mask.trailing_zeros() as usize;
                let word = node.child[lane];
                if dist[lane] <= t_max {
                    if word & LEAF == 0 {
                        current = Some(word);
                    } else {
                        let (first, count) = leaf_range(word);
                        if let Some(t) = visit(first, count, t_max) {
                            t_max = t;
                        }
                    }
                }
                continue;
            }
            let (order, n) = ordered_hits(dist, mask);
            // Leaves at once, nearest first, so their hits cull what follows.
            for &key in &order[..n] {
                let (lane, d) = unpack_key(key);
                let word = node.child[lane];
                if word & LEAF == 0 || d > t_max {
                    continue;
                }
                let (first, count) = leaf_range(word);
                if let Some(t) = visit(first, count, t_max) {
                    t_max = t;
                }
            }
            // Inner children: the nearest is visited next, the others go onto
            // the stack farthest first, so the nearer pop first.
            let mut nearest = None;
            for &key in order[..n].iter().rev() {
                let (lane, d) = unpack_key(key);
                let word = node.child[lane];
                if word & LEAF == 0 && d <= t_max {
                    if let Some(farther) = nearest.replace(pack(word, d)) {
                        // A full stack (a degenerate tree) drops the entry.
                        let _ = stack.try_push(farther);
                    }
                }
            }
            current = nearest.map(|entry| unpack(entry).0);
        }
    }

    /// Whether `hit(slot, t_max)` is true for some leaf primitive whose box
    /// the ray enters before `t_max`: the any-hit walk of shadow rays. The
    /// answer does not depend on the order of the visits, so nothing is
    /// sorted: a node's leaves are tested as their lanes come, one inner
    /// child is visited next and the others are pushed, and the walk ends at
    /// the first hit. With no hit it visits exactly the leaves
    /// [`Bvh::traverse`] visits (neither narrows `t_max` on a miss).
    #[inline]
    pub fn traverse_any(
        &self,
        ray: &Ray,
        t_max: f32,
        mut hit: impl FnMut(usize, f32) -> bool,
    ) -> bool {
        self.traverse_any_leaves(ray, t_max, |first, count, t_max| {
            (first..first + count).any(|slot| hit(slot, t_max))
        })
    }

    /// [`Bvh::traverse_any`] a leaf at a time: `hit(first, count, t_max)`
    /// says whether one of the leaf's slots `first..first + count` is hit.
    #[inline]
    pub fn traverse_any_leaves(
        &self,
        ray: &Ray,
        t_max: f32,
        hit: impl FnMut(usize, usize, f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        #[cfg(target_arch = "x86_64")]
        if avx() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.walk_any_avx(ray, t_max, hit) };
        }
        self.walk_any::<false>(ray, t_max, hit)
    }

    /// [`Bvh::walk_any`] compiled with AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn walk_any_avx(
        &self,
        ray: &Ray,
        t_max: f32,
        hit: impl FnMut(usize, usize, f32) -> bool,
    ) -> bool {
        self.walk_any::<true>(ray, t_max, hit)
    }

    /// The any-hit walk of [`Bvh::traverse_any_leaves`] over a non-empty tree.
    #[inline(always)]
    fn walk_any<const AVX: bool>(
        &self,
        ray: &Ray,
        t_max: f32,
        mut hit: impl FnMut(usize, usize, f32) -> bool,
    ) -> bool {
        let box_ray = BoxRay::new(ray);
        let mut stack = ArrayVec::<u32, STACK>::new();
        let mut index = 0u32;
        loop {
            let node = &self.nodes[index as usize];
            let (_, mut mask) = node_hit::<AVX>(node, &box_ray, t_max);
            let mut next = None;
            while mask != 0 {
                let word = node.child[mask.trailing_zeros() as usize];
                mask &= mask - 1;
                if word & LEAF == 0 {
                    if let Some(other) = next.replace(word) {
                        // A full stack (a degenerate tree) drops the entry.
                        let _ = stack.try_push(other);
                    }
                    continue;
                }
                let (first, count) = leaf_range(word);
                if hit(first, count, t_max) {
                    return true;
                }
            }
            match next.or_else(|| stack.pop()) {
                Some(i) => index = i,
                None => return false,
            }
        }
    }
}

/// A leaf word's first slot and primitive count.
#[inline(always)]
fn leaf_range(word: u32) -> (usize, usize) {
    ((word & SLOT_MASK) as usize, ((word >> 29) & 3) as usize + 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::numbers;
    use glam::Vec3;

    #[test]
    fn children_hit_come_nearest_first_whatever_their_number() {
        let mut r = numbers(3);
        for mask in (0u32..256).filter(|m| m.count_ones() >= 2) {
            for _ in 0..20 {
                // Distances with ties, so that the lane order is tested too.
                let dist: [f32; CHILDREN] = std::array::from_fn(|_| (r() * 4.0).floor());
                let mut want: Vec<u64> = (0..CHILDREN)
                    .filter(|&l| mask >> l & 1 != 0)
                    .map(|l| lane_key(dist[l], l))
                    .collect();
                want.sort_unstable();
                let (keys, n) = ordered_hits(dist, mask);
                assert_eq!(&keys[..n], &want[..], "mask {mask:#b}, {dist:?}");
            }
        }
    }

    #[test]
    fn nodes_are_four_cache_lines() {
        assert_eq!(std::mem::size_of::<BvhNode>(), 256);
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

    /// `count` boxes with centres in [0, 20]³ and half-sizes up to `half`.
    fn random_boxes(r: &mut impl FnMut() -> f32, count: usize, half: f32) -> Vec<Aabb> {
        (0..count)
            .map(|_| {
                let c = Vec3::new(r(), r(), r()) * 20.0;
                let h = Vec3::new(r(), r(), r()) * half;
                Aabb::new(c - h, c + h)
            })
            .collect()
    }

    /// A ray from around the boxes of [`random_boxes`] towards a point among
    /// them, with the reciprocal of its direction.
    fn random_ray(r: &mut impl FnMut() -> f32) -> (Ray, Vec3) {
        let origin = Vec3::new(r(), r(), r()) * 30.0 - 5.0;
        let dir = (Vec3::new(r(), r(), r()) * 20.0 - origin).normalize();
        (Ray::new(origin, dir, 0.0), dir.recip())
    }

    /// The "hit" of the primitive in `slot` (`order` maps slots to
    /// boxes): its box's entry distance along the ray, if beyond 0.
    fn slot_entry(boxes: &[Aabb], order: &[u32], ray: &Ray, inv: Vec3, slot: usize) -> Option<f32> {
        boxes[order[slot] as usize]
            .hit(ray, inv, 0.0, f32::INFINITY)
            .filter(|&t| t > 0.0)
    }

    #[test]
    fn nearest_hit_matches_brute_force_on_random_boxes() {
        let mut r = numbers(7);
        let boxes = random_boxes(&mut r, 1000, 0.7);
        let (bvh, order) = Bvh::build(&boxes);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..1000).collect::<Vec<u32>>());
        let mut hits = 0;
        for _ in 0..500 {
            let (ray, inv) = random_ray(&mut r);
            // The entry distance stands in for a primitive's hit distance.
            let entry = |i: usize| boxes[i].hit(&ray, inv, 0.0, f32::INFINITY);
            let expected = (0..boxes.len())
                .filter_map(|i| entry(i).map(|t| (t, i)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let mut found: Option<(f32, usize)> = None;
            bvh.traverse(&ray, f32::INFINITY, |slot, t_max| {
                let i = order[slot] as usize;
                let t = entry(i).filter(|&t| t < t_max)?;
                found = Some((t, i));
                Some(t)
            });
            assert_eq!(found.map(|f| f.0), expected.map(|e| e.0));
            hits += usize::from(expected.is_some());
        }
        assert!(hits > 100, "the test rays mostly miss: {hits}");
    }

    /// Numbered leaves are walked as before: each visit passes the number
    /// given to the leaf it passed before, with its count, in the same
    /// order and with the same `t_max`, for the closest-hit and the
    /// any-hit walks.
    #[test]
    fn numbered_leaves_are_walked_as_their_slots_were() {
        let mut r = numbers(5);
        let boxes = random_boxes(&mut r, 900, 0.6);
        let (bvh, order) = Bvh::build_leaves(&boxes, Leaves::Packed);
        let mut numbered = bvh.clone();
        let mut firsts = Vec::new();
        numbered.number_leaves(|first, count| {
            firsts.push((first, count));
            // Numbers unlike the slots: from the top down.
            (10_000 - firsts.len()) as u32
        });
        let slot_of = |n: usize| firsts[10_000 - 1 - n];
        assert_eq!(firsts.len(), bvh.leaves().count());
        let (mut visits, mut any) = (0, 0);
        for _ in 0..300 {
            let (ray, inv) = random_ray(&mut r);
            let entry = |slot| slot_entry(&boxes, &order, &ray, inv, slot);
            // A leaf's "hit": its slots' nearest entry.
            let leaf_hit = |first: usize, count: usize, t_max: f32| {
                (first..first + count)
                    .filter_map(entry)
                    .filter(|&t| t < t_max)
                    .reduce(f32::min)
            };
            let mut before = Vec::new();
            bvh.traverse_leaves(&ray, f32::INFINITY, |first, count, t_max| {
                before.push((first, count, t_max));
                leaf_hit(first, count, t_max)
            });
            let mut after = Vec::new();
            numbered.traverse_leaves(&ray, f32::INFINITY, |n, count, t_max| {
                let (first, listed) = slot_of(n);
                assert_eq!(count, listed);
                after.push((first, count, t_max));
                leaf_hit(first, count, t_max)
            });
            assert_eq!(before, after);
            visits += before.len();
            for end in [1.0, 10.0, f32::INFINITY] {
                let blocked = bvh.traverse_any_leaves(&ray, end, |first, count, t| {
                    leaf_hit(first, count, t).is_some()
                });
                let numbered_blocked = numbered.traverse_any_leaves(&ray, end, |n, count, t| {
                    let (first, _) = slot_of(n);
                    leaf_hit(first, count, t).is_some()
                });
                assert_eq!(blocked, numbered_blocked);
                any += usize::from(blocked);
            }
        }
        assert!(visits > 400 && any > 100, "{visits} visits, {any} blocked");
    }

    /// The any-hit walk answers "is there a closest hit" for rays whose
    /// `t_max` ends just before, at and just after the nearest hit, and with
    /// no hit it visits the same leaves as the closest-hit walk.
    #[test]
    fn any_hit_agrees_with_the_closest_hit_on_random_boxes() {
        let mut r = numbers(11);
        let boxes = random_boxes(&mut r, 700, 0.6);
        let (bvh, order) = Bvh::build(&boxes);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..600 {
            let (ray, inv) = random_ray(&mut r);
            let entry = |slot| slot_entry(&boxes, &order, &ray, inv, slot);
            let closest = |t_max: f32| {
                let mut best = None;
                bvh.traverse(&ray, t_max, |slot, t_max| {
                    let t = entry(slot).filter(|&t| t < t_max)?;
                    best = Some(t);
                    Some(t)
                });
                best
            };
            let any = |t_max: f32| {
                bvh.traverse_any(&ray, t_max, |slot, t_max| {
                    entry(slot).is_some_and(|t| t < t_max)
                })
            };
            let nearest = closest(f32::INFINITY);
            let ends = match nearest {
                Some(t) => vec![t.next_down(), t, t.next_up(), f32::INFINITY],
                None => vec![f32::INFINITY, 10.0],
            };
            for t_max in ends {
                assert_eq!(any(t_max), closest(t_max).is_some(), "t_max {t_max}");
            }
            if let Some(t) = nearest {
                assert!(!any(t) && any(t.next_up()));
                hits += 1;
            } else {
                let visited = |any_walk: bool| {
                    let mut seen = Vec::new();
                    if any_walk {
                        bvh.traverse_any(&ray, f32::INFINITY, |slot, _| {
                            seen.push(slot);
                            false
                        });
                    } else {
                        bvh.traverse(&ray, f32::INFINITY, |slot, _| {
                            seen.push(slot);
                            None
                        });
                    }
                    seen.sort_unstable();
                    seen
                };
                assert_eq!(visited(true), visited(false));
                misses += 1;
            }
        }
        assert!(hits > 100 && misses > 50, "{hits} hits, {misses} misses");
    }

    /// The AVX box test gives the SSE one's distances and masks bit for bit,
    /// and the AVX walks (closest and any hit) visit the same leaves in the
    /// same order as the SSE walks, for rays from anywhere (among them
    /// axis-parallel rays starting on a box's face, whose slab distances are
    /// NaN, and rays through a box's corner, which only the rounding
    /// allowance keeps) at boxes from 1e-3 to 1e4.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx_walk_is_the_sse_walk_bit_for_bit() {
        if !avx() {
            eprintln!("this CPU has no AVX: only the SSE walk runs here");
            return;
        }
        let mut r = numbers(5);
        for scale in [1e-3f32, 1.0, 1e4] {
            let boxes: Vec<Aabb> = random_boxes(&mut r, 300, 0.8)
                .iter()
                .map(|b| Aabb::new(b.min * scale, b.max * scale))
                .collect();
            let (bvh, _) = Bvh::build(&boxes);
            for k in 0..400 {
                let (mut ray, _) = random_ray(&mut r);
                ray.origin *= scale;
                let b = boxes[k % boxes.len()];
                if k % 4 == 0 {
                    // Along an axis, from a corner of some box.
                    ray = Ray::new(b.min, [Vec3::X, Vec3::NEG_Y, Vec3::Z][k % 3], 0.0);
                } else if k % 4 == 1 {
                    // At a corner of some box, where entry and exit meet
                    // up to rounding.
                    let corner = Vec3::new(b.min.x, b.max.y, b.min.z);
                    ray = Ray::new(ray.origin, (corner - ray.origin).normalize(), 0.0);
                }
                let box_ray = BoxRay::new(&ray);
                for node in &bvh.nodes {
                    let t_max = if k % 2 == 0 {
                        f32::INFINITY
                    } else {
                        10.0 * scale
                    };
                    let (d0, m0) = node.hit(&box_ray, t_max);
                    // SAFETY: `avx()` said the CPU has AVX.
                    let (d1, m1) = unsafe { node.hit_avx(&box_ray, t_max) };
                    assert_eq!(m0, m1);
                    assert_eq!(d0.map(f32::to_bits), d1.map(f32::to_bits));
                }
                let visits = |use_avx: bool| {
                    let mut seen = Vec::new();
                    let visit = |first: usize, count: usize, t_max: f32| {
                        seen.push((first, count, t_max.to_bits()));
                        // Narrow every other leaf, as a hit would.
                        (seen.len() % 2 == 0).then_some(t_max * 0.9)
                    };
                    if use_avx {
                        // SAFETY: as above.
                        unsafe { bvh.walk_avx(&ray, f32::INFINITY, visit) }
                    } else {
                        bvh.walk::<false>(&ray, f32::INFINITY, visit)
                    }
                    seen
                };
                assert_eq!(visits(true), visits(false));
                let any = |use_avx: bool, t_max: f32| {
                    let mut seen = Vec::new();
                    let hit = |first: usize, count: usize, _| {
                        (first..first + count).any(|slot| {
                            seen.push(slot);
                            slot.is_multiple_of(7)
                        })
                    };
                    let found = if use_avx {
                        // SAFETY: as above.
                        unsafe { bvh.walk_any_avx(&ray, t_max, hit) }
                    } else {
                        bvh.walk_any::<false>(&ray, t_max, hit)
                    };
                    (found, seen)
                };
                for t_max in [f32::INFINITY, 5.0 * scale] {
                    assert_eq!(any(true, t_max), any(false, t_max));
                }
            }
        }
    }

    #[test]
    fn a_single_box_is_one_leaf_lane_and_the_bounds_are_kept() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(2.0));
        let (bvh, order) = Bvh::build(&[b]);
        assert_eq!((bvh.nodes.len(), order), (1, vec![0]));
        assert_eq!(bvh.bounds(), b);
        assert_eq!(Bvh::build(&[]).0.bounds(), Aabb::EMPTY);
    }
}
