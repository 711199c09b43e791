//! A bounding volume hierarchy over the lights, for choosing which light a
//! shading point samples (the idea of pbrt-v4's BVH light sampler and
//! Cycles' light tree): every node bounds its lights' positions, total
//! power and emitting normals (a cone), a shading point descends from the
//! root choosing each child in proportion to an upper bound of the light
//! the child can send it, and the probability of any given light is found
//! again by walking that light's recorded path from the root, so the MIS
//! density of an emitter hit costs O(depth).
//!
//! Nodes are four wide: a node's four children are weighed in one pass of
//! SIMD lanes, and a descent passes half the levels of a binary tree. The
//! build splits a node's lights in four by two median splits, each on the
//! widest axis of the light centres, ties broken by light index, so the
//! tree (and every image) is the same on every run.
//!
//! Everything is in f64: the bounds of huge or far lights and their
//! squared distances leave f32's range.

use glam::{DQuat, DVec3};

use super::light_lanes::{Wide, F4};

/// What a light or a set of lights can emit, bounded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    pub min: DVec3,
    pub max: DVec3,
    /// Emitted power (any consistent unit; only ratios matter).
    pub power: f64,
    /// Axis of a cone holding every emitting normal.
    pub axis: DVec3,
    /// Cosine of that cone's half angle (−1: every direction).
    pub cos_spread: f64,
    /// Whether some light emits on both sides of its normal.
    pub two_sided: bool,
}

impl LightBounds {
    fn union(&self, o: &LightBounds) -> LightBounds {
        let (axis, cos_spread) = cone_union((self.axis, self.cos_spread), (o.axis, o.cos_spread));
        LightBounds {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
            power: self.power + o.power,
            axis,
            cos_spread,
            two_sided: self.two_sided || o.two_sided,
        }
    }

    fn centre(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }
}

/// Children per inner node: a descent weighs all of a node's children at
/// once, so a wider node halves the levels (and the dependent square roots
/// and divisions) between the root and a light.
const WIDTH: usize = 4;

/// One value per child of a node.
type Lanes = [f64; WIDTH];

/// The lanes `f(0)` … `f(3)`: written once, run for every child with the
/// same instructions (the compiler pairs some of them into SIMD operations,
/// whose square roots and divisions round exactly like scalar ones, so the
/// results are bit for bit those of one child at a time).
fn lanes<T>(f: impl Fn(usize) -> T) -> [T; WIDTH] {
    [f(0), f(1), f(2), f(3)]
}

/// The coordinates `f(0)`, `f(1)`, `f(2)` (not `[0, 1, 2].map(f)`, which
/// the compiler left as a call per use, 5% of a lamps.rt render).
fn xyz<T>(f: impl Fn(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// The bounds of a lane without a child: no power, so it weighs nothing.
const NOTHING: LightBounds = LightBounds {
    min: DVec3::ZERO,
    max: DVec3::ZERO,
    power: 0.0,
    axis: DVec3::Z,
    cos_spread: 1.0,
    two_sided: false,
};

/// An inner node's children's bounds as the descent reads them, in lanes
/// (lane k: child k): each box as its bounding sphere (centre, squared
/// radius) and each normal cone with its sine, all worked out when the tree
/// is built rather than at every shading point.
#[derive(Clone, Copy, Debug)]
struct Quad {
    centre: [Lanes; 3],
    r2: Lanes,
    /// The radius, `r2`'s square root.
    r: Lanes,
    power: Lanes,
    axis: [Lanes; 3],
    cos_spread: Lanes,
    sin_spread: Lanes,
    two_sided: [bool; WIDTH],
}

impl Quad {
    /// The lanes of up to [`WIDTH`] children's bounds; lanes past them
    /// weigh nothing.
    fn of(b: &[LightBounds]) -> Quad {
        let b = lanes(|k| b.get(k).copied().unwrap_or(NOTHING));
        let centre = lanes(|k| b[k].centre());
        Quad {
            centre: xyz(|j| lanes(|k| centre[k][j])),
            r2: lanes(|k| 0.25 * (b[k].max - b[k].min).length_squared()),
            r: lanes(|k| 0.5 * (b[k].max - b[k].min).length()),
            power: lanes(|k| b[k].power),
            axis: xyz(|j| lanes(|k| b[k].axis[j])),
            cos_spread: lanes(|k| b[k].cos_spread),
            sin_spread: lanes(|k| (1.0 - b[k].cos_spread * b[k].cos_spread).max(0.0).sqrt()),
            two_sided: lanes(|k| b[k].two_sided),
        }
    }

    /// Per child, an upper bound (up to a common factor) of the light its
    /// bounds can send to a point `p` whose surface has normal `n` (zero
    /// inside a medium): power over squared distance (at least the
    /// bounding sphere's radius), times the best cosine any emitting normal
    /// can make with the direction to `p` and the best cosine at `p`'s
    /// surface. All emitters here are diffuse, so nothing is emitted beyond
    /// 90° from a normal. All children are weighed at once in SIMD
    /// lanes ([`Wide`]), whose square roots, divisions and comparisons
    /// round exactly as scalar ones: every branch of the one-child formula
    /// is a lane mask and a blend, and the special cases are chosen at the
    /// end.
    #[inline(always)]
    fn importance<V: Wide>(&self, p: DVec3, n: DVec3) -> Lanes {
        let splat = V::splat;
        let (zero, one) = (splat(0.0), splat(1.0));
        let r2 = V::new(self.r2);
        let to = xyz(|j| splat(p[j]) - V::new(self.centre[j]));
        let dist2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
        let d2 = dist2.max(r2);
        let inv = one / dist2.sqrt();
        let away = dist2.gt(zero);
        // Each cosine is a dot product with `to` over its length, and each
        // sine the root of `|to|² − dot²` over it: the roots start as soon
        // as the dot products are done, beside `|to|`'s, not after it. At
        // `to = 0` (p inside the bounds) the angles do not matter.
        let dot = |v: [V; 3]| v[0] * to[0] + v[1] * to[1] + v[2] * to[2];
        let along = |d: V| V::blend(away, d * inv, one);
        let across = |d: V| V::blend(away, (dist2 - d * d).max(zero).sqrt() * inv, zero);
        // The angle the bounds subtend from p (everything if p is inside).
        let inside = dist2.le(r2);
        let sin_b = V::blend(inside, zero, V::new(self.r) * inv);
        let cos_b = V::blend(inside, -one, (dist2 - r2).max(zero).sqrt() * inv);
        let c = dot(xyz(|j| V::new(self.axis[j])));
        let c = V::blend(V::flags(self.two_sided), c.abs(), c);
        let (cos_w, sin_w) = (along(c), across(c));
        let spread = (V::new(self.sin_spread), V::new(self.cos_spread));
        let x = angle_minus((sin_w, cos_w), spread);
        let cos_p = angle_minus(x, (sin_b, cos_b)).1;
        let mut importance = V::new(self.power) * cos_p / d2;
        if n != DVec3::ZERO {
            let dn = dot(xyz(|j| splat(n[j]))).abs();
            let (cos_i, sin_i) = (along(dn), across(dn));
            importance = importance * angle_minus((sin_i, cos_i), (sin_b, cos_b)).1;
        }
        let usable = d2.gt(zero) & d2.lt(splat(f64::INFINITY));
        let weighed = V::blend(cos_p.le(zero), zero, importance.max(zero));
        V::blend(usable, weighed, V::new(self.power)).lanes()
    }

    /// [`Quad::importance`] compiled for AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn importance_avx(&self, p: DVec3, n: DVec3) -> Lanes {
        self.importance::<super::light_lanes::Avx4>(p, n)
    }
}

/// Per lane, (sin, cos) of max(0, a − b) for angles in [0, π] given as
/// (sin, cos).
#[inline(always)]
fn angle_minus<V: Wide>((sin_a, cos_a): (V, V), (sin_b, cos_b): (V, V)) -> (V, V) {
    let none = cos_a.gt(cos_b);
    let sin = clamp_unit(sin_a * cos_b - cos_a * sin_b);
    let cos = clamp_unit(cos_a * cos_b + sin_a * sin_b);
    (
        V::blend(none, V::splat(0.0), sin),
        V::blend(none, V::splat(1.0), cos),
    )
}

/// `f64::clamp(x, -1, 1)` per lane (a NaN stays NaN).
#[inline(always)]
fn clamp_unit<V: Wide>(x: V) -> V {
    let one = V::splat(1.0);
    let x = V::blend(x.lt(-one), -one, x);
    V::blend(x.gt(one), one, x)
}

/// The smallest cone (axis, cos half angle) found by widening `a` to hold
/// `b` (pbrt-v4's direction cone union).
fn cone_union(a: (DVec3, f64), b: (DVec3, f64)) -> (DVec3, f64) {
    let (theta_a, theta_b) = (a.1.clamp(-1.0, 1.0).acos(), b.1.clamp(-1.0, 1.0).acos());
    let theta_d = a.0.angle_between(b.0);
    let pi = std::f64::consts::PI;
    if (theta_d + theta_b).min(pi) <= theta_a {
        return a;
    }
    if (theta_d + theta_a).min(pi) <= theta_b {
        return b;
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b);
    let whole = (DVec3::Z, -1.0);
    if theta_o >= pi {
        return whole;
    }
    let Some(w) = a.0.cross(b.0).try_normalize() else {
        return whole;
    };
    let axis = DQuat::from_axis_angle(w, theta_o - theta_a) * a.0;
    (axis, theta_o.cos())
}

/// Where a child link leads.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Child {
    Leaf(u32),
    Inner(u32),
}

/// An inner node: its children's bounds side by side (a descent weighs all
/// at once, from one place in memory) and where each leads; the first
/// `count` lanes hold children.
#[derive(Clone, Copy, Debug)]
struct Inner {
    bounds: Quad,
    children: [Child; WIDTH],
    count: usize,
}

impl Inner {
    /// The children's weights from `p` (normal `n`) and their sum; `None`
    /// if none of them can send `p` any light.
    fn weights(&self, p: DVec3, n: DVec3) -> Option<(Lanes, f64)> {
        #[cfg(target_arch = "x86_64")]
        let w = if crate::simd::avx() {
            // SAFETY: the CPU has AVX.
            unsafe { self.bounds.importance_avx(p, n) }
        } else {
            self.bounds.importance::<F4>(p, n)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let w = self.bounds.importance::<F4>(p, n);
        let sum: f64 = w.iter().sum();
        (sum > 0.0 && sum.is_finite()).then_some((w, sum))
    }
}

/// The hierarchy (inner nodes, the root first; none for fewer than two
/// lights), and each light's path from the root.
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    inner: Vec<Inner>,
    /// Per light: the child taken at each level (bits 2k and 2k + 1: the
    /// lane at level k) and the number of levels.
    paths: Vec<(u64, u32)>,
}

/// Below u = 1 in f64, for rescaled selection numbers.
const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON;

/// Bits of a light's path per level.
const LANE_BITS: u32 = WIDTH.trailing_zeros();

impl LightTree {
    /// Builds the tree over `lights` (indexed as given).
    pub fn build(lights: &[LightBounds]) -> LightTree {
        let mut tree = LightTree {
            inner: Vec::with_capacity(lights.len() / 2),
            paths: vec![(0, 0); lights.len()],
        };
        let mut order: Vec<u32> = (0..lights.len() as u32).collect();
        if !order.is_empty() {
            tree.split(lights, &mut order, 0, 0);
        }
        tree
    }

    fn split(
        &mut self,
        lights: &[LightBounds],
        order: &mut [u32],
        path: u64,
        depth: u32,
    ) -> (LightBounds, Child) {
        if let [one] = order {
            self.paths[*one as usize] = (path, depth);
            return (lights[*one as usize], Child::Leaf(*one));
        }
        let here = self.inner.len();
        self.inner.push(Inner {
            bounds: Quad::of(&[]),
            children: [Child::Leaf(0); WIDTH],
            count: 0,
        });
        let mut groups: Vec<&mut [u32]> = Vec::with_capacity(WIDTH);
        if order.len() <= WIDTH {
            groups.extend(order.chunks_mut(1));
        } else {
            let (a, b) = halve(lights, order);
            let (a0, a1) = halve(lights, a);
            let (b0, b1) = halve(lights, b);
            groups.extend([a0, a1, b0, b1]);
        }
        let mut bounds = Vec::with_capacity(WIDTH);
        let mut children = [Child::Leaf(0); WIDTH];
        for (k, group) in groups.into_iter().enumerate() {
            let lane_path = path | ((k as u64) << (LANE_BITS * depth));
            let (b, child) = self.split(lights, group, lane_path, depth + 1);
            bounds.push(b);
            children[k] = child;
        }
        self.inner[here] = Inner {
            bounds: Quad::of(&bounds),
            children,
            count: bounds.len(),
        };
        let union = bounds[1..].iter().fold(bounds[0], |u, b| u.union(b));
        (union, Child::Inner(here as u32))
    }

    /// Chooses a light for `p` (normal `n`, zero in a medium) with the
    /// uniform number `u`: its index and the probability of choosing it.
    pub fn sample(&self, p: DVec3, n: DVec3, u: f64) -> Option<(usize, f64)> {
        if self.paths.len() == 1 {
            return Some((0, 1.0));
        }
        let mut u = u.min(ONE_MINUS_EPSILON);
        let mut node = self.inner.first()?;
        let mut prob = 1.0;
        loop {
            let (w, sum) = node.weights(p, n)?;
            // The lane whose stretch of [0, sum) holds u·sum; rounding past
            // the last stretch keeps the last lane with any weight.
            let x = u * sum;
            let mut pick = None;
            let mut before = 0.0;
            for (k, &wk) in w.iter().enumerate().take(node.count) {
                if wk > 0.0 {
                    pick = Some((k, before));
                    if x < before + wk {
                        break;
                    }
                    before += wk;
                }
            }
            let (k, start) = pick?;
            prob *= w[k] / sum;
            u = ((x - start) / w[k]).clamp(0.0, ONE_MINUS_EPSILON);
            match node.children[k] {
                Child::Leaf(i) => return Some((i as usize, prob)),
                Child::Inner(at) => node = self.inner.get(at as usize)?,
            }
        }
    }

    /// The probability with which [`LightTree::sample`] from `p` (normal
    /// `n`) chooses light `light`.
    pub fn probability(&self, light: usize, p: DVec3, n: DVec3) -> f64 {
        let Some(&(path, depth)) = self.paths.get(light) else {
            return 0.0;
        };
        let mut at = 0;
        let mut prob = 1.0;
        for level in 0..depth {
            let Some(node) = self.inner.get(at) else {
                return 0.0;
            };
            let Some((w, sum)) = node.weights(p, n) else {
                return 0.0;
            };
            let lane = ((path >> (LANE_BITS * level)) as usize) & (WIDTH - 1);
            prob *= w[lane] / sum;
            match node.children[lane] {
                Child::Inner(next) => at = next as usize,
                Child::Leaf(_) => break,
            }
        }
        prob
    }
}

/// Sorts `order` by the light centres along their widest axis (ties by
/// light index, so the tree is the same on every run) and splits it at the
/// median.
fn halve<'a>(lights: &[LightBounds], order: &'a mut [u32]) -> (&'a mut [u32], &'a mut [u32]) {
    let (lo, hi) = order.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &i| {
            let c = lights[i as usize].centre();
            (lo.min(c), hi.max(c))
        },
    );
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    order.sort_by(|&a, &b| {
        let (ca, cb) = (
            lights[a as usize].centre()[axis],
            lights[b as usize].centre()[axis],
        );
        ca.total_cmp(&cb).then(a.cmp(&b))
    });
    let half = order.len() / 2;
    order.split_at_mut(half)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::numbers;

    /// A small downward lamp at `c` of power `power`.
    fn lamp(c: DVec3, power: f64) -> LightBounds {
        LightBounds {
            min: c - DVec3::new(0.1, 0.0, 0.1),
            max: c + DVec3::new(0.1, 0.0, 0.1),
            power,
            axis: DVec3::NEG_Y,
            cos_spread: 1.0,
            two_sided: false,
        }
    }

    fn field() -> Vec<LightBounds> {
        (0..37)
            .map(|i| {
                let (x, z) = ((i % 7) as f64, (i / 7) as f64);
                lamp(
                    DVec3::new(x, 1.0 + 0.1 * (i % 3) as f64, z),
                    1.0 + (i % 5) as f64,
                )
            })
            .collect()
    }

    #[test]
    fn the_probabilities_of_all_lights_sum_to_one_and_match_sampling() {
        let lights = field();
        let tree = LightTree::build(&lights);
        for (p, n) in [
            (DVec3::new(3.0, 0.0, 2.0), DVec3::Y),
            (DVec3::new(-5.0, 0.5, 9.0), DVec3::ZERO),
            (DVec3::new(2.5, 1.05, 2.5), DVec3::X),
        ] {
            let probs: Vec<f64> = (0..lights.len())
                .map(|i| tree.probability(i, p, n))
                .collect();
            let sum: f64 = probs.iter().sum();
            assert!((sum - 1.0).abs() < 1e-9, "{sum}");
            // Stratified u: each light is chosen with its probability, and
            // sample() reports the same probability it is chosen with.
            let m = 200_000;
            let mut count = vec![0u32; lights.len()];
            for k in 0..m {
                let (i, prob) = tree
                    .sample(p, n, (k as f64 + 0.5) / m as f64)
                    .expect("a light");
                assert!((prob - probs[i]).abs() <= 1e-12 * probs[i].max(1.0));
                count[i] += 1;
            }
            for (c, q) in count.iter().zip(&probs) {
                assert!((*c as f64 / m as f64 - q).abs() < 1e-4, "{c} vs {q}");
            }
        }
    }

    #[test]
    fn lights_facing_away_are_never_chosen_and_near_ones_are_preferred() {
        let mut lights = field();
        // A bright lamp facing down, under the floor: a point above it
        // cannot see its emitting side.
        lights.push(lamp(DVec3::new(3.0, -5.0, 2.0), 100.0));
        let tree = LightTree::build(&lights);
        let p = DVec3::new(0.0, 0.0, 0.0);
        assert_eq!(
            tree.probability(lights.len() - 1, DVec3::new(3.0, 0.0, 2.0), DVec3::Y),
            0.0
        );
        // From under lamp 0, lamp 0 is likelier than the far lamp 36.
        assert!(tree.probability(0, p, DVec3::Y) > 4.0 * tree.probability(36, p, DVec3::Y));
    }

    #[test]
    fn the_build_is_deterministic_and_every_light_is_a_leaf() {
        let lights = field();
        let (a, b) = (LightTree::build(&lights), LightTree::build(&lights));
        assert_eq!(a.paths, b.paths);
        let mut seen = vec![false; lights.len()];
        for child in a
            .inner
            .iter()
            .flat_map(|node| node.children[..node.count].to_vec())
        {
            if let Child::Leaf(i) = child {
                assert!(!seen[i as usize]);
                seen[i as usize] = true;
            }
        }
        assert!(seen.iter().all(|s| *s));
        // 37 lights: a root of four, four nodes of nine or ten lights, and
        // below those nodes of two or three: 1 + 4 + 16 inner nodes.
        assert_eq!(a.inner.len(), 21);
        assert!(a.paths.iter().all(|&(_, depth)| depth == 3));
    }

    #[test]
    fn each_lane_weighs_its_own_child_alone() {
        let mut lights = field();
        let mut facing_up = lamp(DVec3::new(0.5, -2.0, 0.5), 3.0);
        facing_up.axis = DVec3::Y;
        facing_up.two_sided = true;
        lights.push(facing_up);
        let (a, b) = (lights[0].union(&lights[8]), lights[36]);
        for (p, n) in [
            (DVec3::new(3.0, 0.0, 2.0), DVec3::Y),
            (DVec3::new(0.0, 1.0, 0.0), DVec3::ZERO),
            (DVec3::new(0.5, -2.0, 0.5), DVec3::X),
        ] {
            for c in [a, b, facing_up] {
                let alone = |x: LightBounds| Quad::of(&[x]).importance::<F4>(p, n)[0].to_bits();
                let got = Quad::of(&[c, b, a, c]).importance::<F4>(p, n);
                assert_eq!(got.map(f64::to_bits), [c, b, a, c].map(alone));
                let got = Quad::of(&[b, c]).importance::<F4>(p, n);
                assert_eq!(got.map(f64::to_bits), [alone(b), alone(c), 0, 0]);
            }
        }
    }

    /// The one-child-at-a-time formula the lanes of [`Quad::importance`]
    /// must reproduce bit for bit (the form it had before it was written in
    /// SIMD lanes).
    fn scalar_importance(this: &Quad, p: DVec3, n: DVec3) -> Lanes {
        let r2 = this.r2;
        let to = xyz(|j| lanes(|k| p[j] - this.centre[j][k]));
        let dist2 = lanes(|k| to[0][k] * to[0][k] + to[1][k] * to[1][k] + to[2][k] * to[2][k]);
        let d2 = lanes(|k| dist2[k].max(r2[k]));
        let inv = lanes(|k| 1.0 / dist2[k].sqrt());
        let away = lanes(|k| dist2[k] > 0.0);
        let dot = |v: [f64; 3], k: usize| v[0] * to[0][k] + v[1] * to[1][k] + v[2] * to[2][k];
        let along = |d: f64, k: usize| if away[k] { d * inv[k] } else { 1.0 };
        let across = |d: f64, k: usize| {
            if away[k] {
                (dist2[k] - d * d).max(0.0).sqrt() * inv[k]
            } else {
                0.0
            }
        };
        // The angle the bounds subtend from p (everything if p is inside).
        let inside = lanes(|k| dist2[k] <= r2[k]);
        let sin_b = lanes(|k| if inside[k] { 0.0 } else { this.r[k] * inv[k] });
        let cos_b = lanes(|k| {
            if inside[k] {
                -1.0
            } else {
                (dist2[k] - r2[k]).max(0.0).sqrt() * inv[k]
            }
        });
        let c = lanes(|k| {
            let c = dot(xyz(|j| this.axis[j][k]), k);
            if this.two_sided[k] {
                c.abs()
            } else {
                c
            }
        });
        let cos_w = lanes(|k| along(c[k], k));
        let sin_w = lanes(|k| across(c[k], k));
        let x = lanes(|k| {
            scalar_angle_minus(
                (sin_w[k], cos_w[k]),
                (this.sin_spread[k], this.cos_spread[k]),
            )
        });
        let cos_p = lanes(|k| scalar_angle_minus(x[k], (sin_b[k], cos_b[k])).1);
        let mut importance = lanes(|k| this.power[k] * cos_p[k] / d2[k]);
        if n != DVec3::ZERO {
            let dn = lanes(|k| dot(n.to_array(), k).abs());
            let (cos_i, sin_i) = (lanes(|k| along(dn[k], k)), lanes(|k| across(dn[k], k)));
            importance = lanes(|k| {
                importance[k] * scalar_angle_minus((sin_i[k], cos_i[k]), (sin_b[k], cos_b[k])).1
            });
        }
        lanes(|k| {
            if !(d2[k] > 0.0 && d2[k].is_finite()) {
                this.power[k]
            } else if cos_p[k] <= 0.0 {
                0.0
            } else {
                importance[k].max(0.0)
            }
        })
    }

    /// (sin, cos) of max(0, a − b), one angle pair at a time.
    fn scalar_angle_minus((sin_a, cos_a): (f64, f64), (sin_b, cos_b): (f64, f64)) -> (f64, f64) {
        if cos_a > cos_b {
            (0.0, 1.0)
        } else {
            (
                (sin_a * cos_b - cos_a * sin_b).clamp(-1.0, 1.0),
                (cos_a * cos_b + sin_a * sin_b).clamp(-1.0, 1.0),
            )
        }
    }

    /// Random quadruples of bounds (wide and point-like, one- and
    /// two-sided, narrow and full cones) seen from random points (inside
    /// some bounds, on a centre) with random and zero normals.
    #[test]
    fn every_lane_is_the_scalar_formula_bit_for_bit() {
        let mut next = numbers(0x1234);
        let mut r = move || f64::from(next());
        let v =
            |r: &mut dyn FnMut() -> f64, s: f64| DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * s;
        let mut checked = [0usize; 3];
        for round in 0..4000 {
            let bounds: Vec<LightBounds> = (0..WIDTH)
                .map(|k| {
                    let c = v(&mut r, 8.0);
                    let h = if (round + k) % 5 == 0 {
                        DVec3::ZERO
                    } else {
                        v(&mut r, 2.0).abs()
                    };
                    LightBounds {
                        min: c - h,
                        max: c + h,
                        power: r() * 10.0,
                        axis: v(&mut r, 1.0).try_normalize().unwrap_or(DVec3::Y),
                        cos_spread: [1.0, -1.0, 2.0 * r() - 1.0][(round + k) % 3],
                        two_sided: r() < 0.3,
                    }
                })
                .collect();
            let quad = Quad::of(&bounds);
            let p = match round % 7 {
                0 => bounds[0].centre(),
                1 => bounds[1].centre() + 0.1 * v(&mut r, 1.0),
                _ => v(&mut r, 12.0),
            };
            let n = match round % 4 {
                0 => DVec3::ZERO,
                _ => v(&mut r, 1.0).try_normalize().unwrap_or(DVec3::X),
            };
            let (got, want) = (quad.importance::<F4>(p, n), scalar_importance(&quad, p, n));
            #[cfg(target_arch = "x86_64")]
            if crate::simd::avx() {
                // SAFETY: the CPU has AVX.
                let avx = unsafe { quad.importance_avx(p, n) };
                assert_eq!(
                    avx.map(f64::to_bits),
                    got.map(f64::to_bits),
                    "round {round}"
                );
            }
            for k in 0..WIDTH {
                assert_eq!(
                    got[k].to_bits(),
                    want[k].to_bits(),
                    "lane {k}, round {round}"
                );
                checked[usize::from(want[k] > 0.0) + usize::from(want[k] == quad.power[k])] += 1;
            }
        }
        // Zero, weighed and whole-power (inside the bounds) answers all occur.
        assert!(checked.iter().all(|&c| c > 100), "{checked:?}");
    }

    #[test]
    fn a_cone_union_holds_both_cones() {
        let (axis, cos) = cone_union((DVec3::Y, 1.0), (DVec3::X, 1.0));
        assert!(
            (axis.dot(DVec3::Y) - cos).abs() < 1e-12 && (axis.dot(DVec3::X) - cos).abs() < 1e-12
        );
        assert!((cos - std::f64::consts::FRAC_PI_4.cos()).abs() < 1e-12);
        assert_eq!(cone_union((DVec3::Y, 1.0), (DVec3::NEG_Y, 1.0)).1, -1.0);
    }
}
