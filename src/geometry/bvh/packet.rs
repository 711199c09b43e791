//! The walk of up to eight rays at once (a packet: the camera rays of one
//! pixel's block of samples), for rays that mostly cross the same boxes.
//! Each node is tested against every ray of the packet that reached it, one
//! ray's eight-box test after another: the tests do not depend on each
//! other, so they run side by side, where one ray's walk waits on each of
//! its tests in turn. The decisions of the walk (which children, in which
//! order, what to push) are made once for the packet. A ray left alone in a
//! subtree walks it as one ray does ([`Bvh::walk_from`]): rays after a
//! diffuse bounce part ways at once.
//!
//! Which leaves a ray is shown depends on the other rays of its packet and
//! on the order the packet visits them, so a caller that wants a ray's
//! answer not to depend on its packet must keep an order-free answer (the
//! nearest hit with ties to the lowest slot, as
//! [`crate::geometry::primitives::PrimitiveSet::first_hits`] does).

use arrayvec::ArrayVec;

use super::node::{node_hit, BoxRay, CHILDREN};
use super::{leaf_range, ordered_hits, unpack_key, Bvh, LEAF, STACK};
use crate::geometry::Ray;
use crate::simd::LANES;

/// The bits set in `mask`, lowest first (a packet's rays, a leaf's lanes).
#[inline(always)]
pub fn bits(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        if mask == 0 {
            return None;
        }
        let bit = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        Some(bit)
    })
}

/// The 8 × 8 bit matrix `m` (byte `r`, bit `c`) transposed: byte `c`,
/// bit `r` (Hacker's Delight, 7-3: three rounds of swapping blocks).
#[inline(always)]
fn transpose8(mut m: u64) -> u64 {
    let t = (m ^ (m >> 7)) & 0x00aa_00aa_00aa_00aa;
    m ^= t ^ (t << 7);
    let t = (m ^ (m >> 14)) & 0x0000_cccc_0000_cccc;
    m ^= t ^ (t << 14);
    let t = (m ^ (m >> 28)) & 0x0000_0000_f0f0_f0f0;
    m ^ t ^ (t << 28)
}

impl Bvh {
    /// Visits, for each ray `rays[r]`, every leaf whose box it enters before
    /// `t_max[r]`, and maybe leaves it does not enter (for another ray of
    /// the packet). `visit(first, count, rays, t_max)` tests the leaf's
    /// slots for the rays of the mask `rays` (bit `r` for `rays[r]`) and
    /// lowers the `t_max` of those it finds a hit for. At most [`LANES`]
    /// rays; the entries of `t_max` past `rays.len()` are not read.
    #[inline]
    pub fn traverse_packet(
        &self,
        rays: &[Ray],
        t_max: &mut [f32; LANES],
        visit: impl FnMut(usize, usize, u32, &mut [f32; LANES]),
    ) {
        assert!(rays.len() <= LANES, "a packet holds {LANES} rays");
        if self.nodes.is_empty() || rays.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.walk_packet_avx(rays, t_max, visit) };
        }
        self.walk_packet::<false>(rays, t_max, visit);
    }

    /// [`Bvh::walk_packet`] compiled with AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn walk_packet_avx(
        &self,
        rays: &[Ray],
        t_max: &mut [f32; LANES],
        visit: impl FnMut(usize, usize, u32, &mut [f32; LANES]),
    ) {
        self.walk_packet::<true>(rays, t_max, visit);
    }

    /// The packet walk of [`Bvh::traverse_packet`] over a non-empty tree:
    /// a node's children are taken nearest first by the nearest entry of
    /// any ray, each with the mask of the rays that enter it; leaves at
    /// once, for the rays whose `t_max` still reaches them, the nearest
    /// inner child next and the others pushed with their masks.
    #[inline(always)]
    fn walk_packet<const AVX: bool>(
        &self,
        rays: &[Ray],
        t_max: &mut [f32; LANES],
        mut visit: impl FnMut(usize, usize, u32, &mut [f32; LANES]),
    ) {
        let live = (1u32 << rays.len()) - 1;
        if let Some((first, count)) = self.single_leaf() {
            // A few primitives in one leaf: its box culls no ray that the
            // leaf's own tests would keep, so the rays meet it at once,
            // without a box to set up for each.
            visit(first, count, live, t_max);
            return;
        }
        let box_rays: [BoxRay; LANES] =
            std::array::from_fn(|r| BoxRay::new(&rays[r.min(rays.len() - 1)]));
        let mut stack = ArrayVec::<(u32, u32), STACK>::new();
        let mut current = Some((0u32, live));
        while let Some((index, mask)) = current.take().or_else(|| stack.pop()) {
            if mask & (mask - 1) == 0 {
                // One ray left in this subtree: its own walk, without the
                // packet's bookkeeping (the rays a packet's walk holds
                // after their first bounce part ways at once).
                let r = mask.trailing_zeros() as usize;
                let t_max_r = t_max[r];
                self.walk_from::<AVX>(index, &box_rays[r], t_max_r, |first, count, t: f32| {
                    visit(first, count, mask, t_max);
                    (t_max[r] < t).then_some(t_max[r])
                });
                continue;
            }
            let node = &self.nodes[index as usize];
            let mut dist = [[f32::INFINITY; CHILDREN]; LANES];
            // Per child, the nearest entry of any ray (a select the
            // compiler makes one vector minimum: no distance is NaN).
            let mut near = [f32::INFINITY; CHILDREN];
            // Byte `r` of `entered`: the children ray `r` enters.
            let (mut entered, mut children) = (0u64, 0u32);
            for r in bits(mask) {
                let (d, m) = node_hit::<AVX>(node, &box_rays[r], t_max[r]);
                for (n, &e) in near.iter_mut().zip(&d) {
                    *n = if e < *n { e } else { *n };
                }
                dist[r] = d;
                entered |= u64::from(m) << (8 * r);
                children |= m;
            }
            if children == 0 {
                continue;
            }
            // Byte `c`: the rays that enter child `c`.
            let by_child = transpose8(entered).to_le_bytes();
            let (order, n) = if children & (children - 1) == 0 {
                let c = children.trailing_zeros() as usize;
                let mut one = [0u64; CHILDREN];
                one[0] = super::lane_key(near[c], c);
                (one, 1)
            } else {
                ordered_hits(near, children)
            };
            // Leaves at once, nearest first, each for the rays whose hits
            // so far do not end before its box.
            for &key in &order[..n] {
                let (c, _) = unpack_key(key);
                let word = node.child[c];
                if word & LEAF == 0 {
                    continue;
                }
                let reach = bits(u32::from(by_child[c]))
                    .filter(|&r| dist[r][c] <= t_max[r])
                    .fold(0u32, |m, r| m | 1 << r);
                if reach != 0 {
                    let (first, count) = leaf_range(word);
                    visit(first, count, reach, t_max);
                }
            }
            // Inner children: the nearest next, the others onto the stack
            // farthest first.
            let mut nearest = None;
            for &key in order[..n].iter().rev() {
                let (c, _) = unpack_key(key);
                let word = node.child[c];
                if word & LEAF == 0 {
                    let entry = (word, u32::from(by_child[c]));
                    if let Some(farther) = nearest.replace(entry) {
                        // A full stack (a degenerate tree) drops the entry.
                        let _ = stack.try_push(farther);
                    }
                }
            }
            current = nearest;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Aabb;
    use crate::sampling::rng::numbers;
    use glam::Vec3;

    #[test]
    fn the_bit_matrix_is_transposed() {
        let mut r = numbers(2);
        for _ in 0..200 {
            let m = (0..4).fold(0u64, |m, _| m << 16 | (r() * 65536.0) as u64);
            let t = transpose8(m);
            for row in 0..8 {
                for col in 0..8 {
                    assert_eq!(m >> (8 * row + col) & 1, t >> (8 * col + row) & 1);
                }
            }
        }
    }

    /// Every ray of a packet is shown every leaf whose box it enters before
    /// its `t_max`, whatever rays share its packet, with `t_max` narrowed
    /// as hits would narrow it.
    #[test]
    fn each_ray_meets_every_box_it_crosses_whatever_its_packet() {
        let mut r = numbers(9);
        let boxes: Vec<Aabb> = (0..600)
            .map(|_| {
                let c = Vec3::new(r(), r(), r()) * 20.0;
                let h = Vec3::new(r(), r(), r()) * 0.6;
                Aabb::new(c - h, c + h)
            })
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        for _ in 0..300 {
            let n = 1 + (r() * LANES as f32) as usize % LANES;
            // Rays of one packet: from near one point towards near another,
            // or anywhere for every third packet.
            let from = Vec3::new(r(), r(), r()) * 30.0 - 5.0;
            let to = Vec3::new(r(), r(), r()) * 20.0;
            let spread = if r() < 0.33 { 20.0 } else { 0.5 };
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let jitter = Vec3::new(r(), r(), r()) * spread;
                    Ray::new(from, (to + jitter - from).normalize(), 0.0)
                })
                .collect();
            // A leaf slot is "hit" at its box's entry distance (if beyond 0).
            let entry = |ray: &Ray, slot: usize| {
                boxes[order[slot] as usize]
                    .hit(ray, ray.dir.recip(), 0.0, f32::INFINITY)
                    .filter(|&t| t > 0.0)
            };
            let mut t_max = [f32::INFINITY; LANES];
            let mut seen = vec![Vec::new(); n];
            bvh.traverse_packet(&rays, &mut t_max, |first, count, mask, t_max| {
                for k in bits(mask) {
                    for slot in first..first + count {
                        seen[k].push(slot);
                        if let Some(t) = entry(&rays[k], slot) {
                            t_max[k] = t_max[k].min(t);
                        }
                    }
                }
            });
            for (k, ray) in rays.iter().enumerate() {
                let nearest = (0..boxes.len())
                    .filter_map(|s| entry(ray, s))
                    .fold(f32::INFINITY, f32::min);
                assert_eq!(t_max[k], nearest, "ray {k} of {n}");
                // Alone, it meets the same nearest box.
                let mut alone = [f32::INFINITY; LANES];
                bvh.traverse_packet(
                    std::slice::from_ref(ray),
                    &mut alone,
                    |first, count, _, t| {
                        for slot in first..first + count {
                            if let Some(e) = entry(ray, slot) {
                                t[0] = t[0].min(e);
                            }
                        }
                    },
                );
                assert_eq!(alone[0], nearest);
                // Each slot is shown at most once per ray.
                let mut slots = seen[k].clone();
                slots.sort_unstable();
                slots.dedup();
                assert_eq!(slots.len(), seen[k].len());
            }
        }
    }
}
