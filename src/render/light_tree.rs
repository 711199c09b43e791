//! A bounding volume hierarchy over the lights, for choosing which light a
//! shading point samples (the idea of pbrt-v4's BVH light sampler and
//! Cycles' light tree): every node bounds its lights' positions, total
//! power and emitting normals (a cone), a shading point descends from the
//! root choosing each child in proportion to an upper bound of the light
//! the child can send it, and the probability of any given light is found
//! again by walking that light's recorded path from the root, so the MIS
//! density of an emitter hit costs O(depth).
//!
//! Everything is in f64: the bounds of huge or far lights and their
//! squared distances leave f32's range. The build is a median split on the
//! widest axis of the light centres, ties broken by light index, so the
//! tree (and every image) is the same on every run.

use glam::{DQuat, DVec3};

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

    /// What a query reads of these bounds, with the parts that do not
    /// depend on the shading point worked out once.
    fn cached(&self) -> NodeBounds {
        NodeBounds {
            centre: self.centre(),
            r2: 0.25 * (self.max - self.min).length_squared(),
            power: self.power,
            axis: self.axis,
            cos_spread: self.cos_spread,
            sin_spread: (1.0 - self.cos_spread * self.cos_spread).max(0.0).sqrt(),
            two_sided: self.two_sided,
        }
    }
}

/// A node's bounds as the descent reads them: the box as its bounding
/// sphere (centre, squared radius) and the normal cone with its sine, all
/// computed when the tree is built rather than at every shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
struct NodeBounds {
    centre: DVec3,
    r2: f64,
    power: f64,
    axis: DVec3,
    cos_spread: f64,
    sin_spread: f64,
    two_sided: bool,
}

impl NodeBounds {
    /// An upper bound (up to a common factor) of the light these bounds
    /// can send to a point `p` whose surface has normal `n` (zero inside a
    /// medium): power over squared distance (at least the bounding
    /// sphere's radius), times the best cosine any emitting normal can make
    /// with the direction to `p` and the best cosine at `p`'s surface. All
    /// emitters here are diffuse, so nothing is emitted beyond 90° from a
    /// normal.
    fn importance(&self, p: DVec3, n: DVec3) -> f64 {
        let r2 = self.r2;
        let to = p - self.centre;
        let dist2 = to.length_squared();
        let d2 = dist2.max(r2);
        if !(d2 > 0.0 && d2.is_finite()) {
            return self.power;
        }
        let wi = if dist2 > 0.0 {
            to / dist2.sqrt()
        } else {
            DVec3::Z
        };
        // The angle the bounds subtend from p (everything if p is inside).
        let (sin_b, cos_b) = if dist2 <= r2 {
            (0.0, -1.0)
        } else {
            let sin2 = r2 / dist2;
            (sin2.sqrt(), (1.0 - sin2).sqrt())
        };
        let mut cos_w = self.axis.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let (sin_x, cos_x) = angle_minus((sin_w, cos_w), (self.sin_spread, self.cos_spread));
        let (_, cos_p) = angle_minus((sin_x, cos_x), (sin_b, cos_b));
        if cos_p <= 0.0 {
            return 0.0;
        }
        let mut importance = self.power * cos_p / d2;
        if n != DVec3::ZERO {
            let cos_i = n.dot(wi).abs();
            let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
            importance *= angle_minus((sin_i, cos_i), (sin_b, cos_b)).1;
        }
        importance.max(0.0)
    }
}

/// (sin, cos) of max(0, a − b) for angles in [0, π] given as (sin, cos).
fn angle_minus((sin_a, cos_a): (f64, f64), (sin_b, cos_b): (f64, f64)) -> (f64, f64) {
    if cos_a > cos_b {
        (0.0, 1.0)
    } else {
        (
            (sin_a * cos_b - cos_a * sin_b).clamp(-1.0, 1.0),
            (cos_a * cos_b + sin_a * sin_b).clamp(-1.0, 1.0),
        )
    }
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

/// An inner node: its two children's bounds side by side (a descent weighs
/// both at once, from one place in memory) and where each leads.
#[derive(Clone, Copy, Debug)]
struct Inner {
    bounds: [NodeBounds; 2],
    children: [Child; 2],
}

/// The hierarchy (inner nodes, the root first; none for fewer than two
/// lights), and each light's path from the root.
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    inner: Vec<Inner>,
    lights: usize,
    /// Per light: the child taken at each level (bit k: 1 = second child)
    /// and the number of levels.
    paths: Vec<(u64, u32)>,
}

/// Below u = 1 in f64, for rescaled selection numbers.
const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON;

impl LightTree {
    /// Builds the tree over `lights` (indexed as given).
    pub fn build(lights: &[LightBounds]) -> LightTree {
        let mut tree = LightTree {
            inner: Vec::with_capacity(lights.len().saturating_sub(1)),
            lights: lights.len(),
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
        let here = self.inner.len();
        let placeholder = lights[order[0] as usize].cached();
        self.inner.push(Inner {
            bounds: [placeholder; 2],
            children: [Child::Leaf(0); 2],
        });
        let (first, second) = order.split_at_mut(order.len() / 2);
        let (a, first) = self.split(lights, first, path, depth + 1);
        let (b, second) = self.split(lights, second, path | (1 << depth), depth + 1);
        self.inner[here] = Inner {
            bounds: [a.cached(), b.cached()],
            children: [first, second],
        };
        (a.union(&b), Child::Inner(here as u32))
    }

    /// The probability of descending into the first child of `node` from
    /// `p` (normal `n`); `None` if neither child can send `p` any light.
    fn first_share(node: &Inner, p: DVec3, n: DVec3) -> Option<f64> {
        let a = node.bounds[0].importance(p, n);
        let b = node.bounds[1].importance(p, n);
        let sum = a + b;
        (sum > 0.0 && sum.is_finite()).then(|| a / sum)
    }

    /// Chooses a light for `p` (normal `n`, zero in a medium) with the
    /// uniform number `u`: its index and the probability of choosing it.
    pub fn sample(&self, p: DVec3, n: DVec3, u: f64) -> Option<(usize, f64)> {
        if self.lights == 1 {
            return Some((0, 1.0));
        }
        let mut u = u.min(ONE_MINUS_EPSILON);
        let mut node = self.inner.first()?;
        let mut prob = 1.0;
        loop {
            let first = Self::first_share(node, p, n)?;
            let next = if u < first {
                u = (u / first).min(ONE_MINUS_EPSILON);
                prob *= first;
                node.children[0]
            } else {
                u = ((u - first) / (1.0 - first)).min(ONE_MINUS_EPSILON);
                prob *= 1.0 - first;
                node.children[1]
            };
            match next {
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
            let Some(first) = Self::first_share(node, p, n) else {
                return 0.0;
            };
            let side = usize::from(path & (1 << level) != 0);
            prob *= if side == 0 { first } else { 1.0 - first };
            match node.children[side] {
                Child::Inner(next) => at = next as usize,
                Child::Leaf(_) => break,
            }
        }
        prob
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        for child in a.inner.iter().flat_map(|node| node.children) {
            if let Child::Leaf(i) = child {
                assert!(!seen[i as usize]);
                seen[i as usize] = true;
            }
        }
        assert!(seen.iter().all(|s| *s));
        assert_eq!(a.inner.len(), lights.len() - 1);
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
