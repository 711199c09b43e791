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

    /// An upper bound (up to a common factor) of the light these bounds
    /// can send to a point `p` whose surface has normal `n` (zero inside a
    /// medium): power over squared distance (at least the bounding
    /// sphere's radius), times the best cosine any emitting normal can make
    /// with the direction to `p` and the best cosine at `p`'s surface. All
    /// emitters here are diffuse, so nothing is emitted beyond 90° from a
    /// normal.
    pub fn importance(&self, p: DVec3, n: DVec3) -> f64 {
        let c = self.centre();
        let r2 = 0.25 * (self.max - self.min).length_squared();
        let to = p - c;
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
        let sin_o = (1.0 - self.cos_spread * self.cos_spread).max(0.0).sqrt();
        let (sin_x, cos_x) = angle_minus((sin_w, cos_w), (sin_o, self.cos_spread));
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

#[derive(Clone, Copy, Debug)]
enum Kind {
    Leaf(u32),
    /// An inner node; its first child follows it, this is the second.
    Inner(u32),
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: LightBounds,
    kind: Kind,
}

/// The hierarchy, and each light's path from the root.
#[derive(Clone, Debug, Default)]
pub struct LightTree {
    nodes: Vec<Node>,
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
            nodes: Vec::with_capacity(2 * lights.len()),
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
    ) -> LightBounds {
        if let [one] = order {
            let bounds = lights[*one as usize];
            self.nodes.push(Node {
                bounds,
                kind: Kind::Leaf(*one),
            });
            self.paths[*one as usize] = (path, depth);
            return bounds;
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
        let here = self.nodes.len();
        self.nodes.push(Node {
            bounds: lights[order[0] as usize],
            kind: Kind::Leaf(0),
        });
        let (first, second) = order.split_at_mut(order.len() / 2);
        let a = self.split(lights, first, path, depth + 1);
        let right = self.nodes.len() as u32;
        let b = self.split(lights, second, path | (1 << depth), depth + 1);
        let bounds = a.union(&b);
        self.nodes[here] = Node {
            bounds,
            kind: Kind::Inner(right),
        };
        bounds
    }

    /// The probability of descending into the first child of the inner
    /// node at `at` (whose second child is `second`) from `p` (normal `n`);
    /// `None` if neither child can send `p` any light.
    fn first_share(&self, at: usize, second: usize, p: DVec3, n: DVec3) -> Option<f64> {
        let a = self.nodes[at + 1].bounds.importance(p, n);
        let b = self.nodes[second].bounds.importance(p, n);
        let sum = a + b;
        (sum > 0.0 && sum.is_finite()).then(|| a / sum)
    }

    /// Chooses a light for `p` (normal `n`, zero in a medium) with the
    /// uniform number `u`: its index and the probability of choosing it.
    pub fn sample(&self, p: DVec3, n: DVec3, u: f64) -> Option<(usize, f64)> {
        let mut u = u.min(ONE_MINUS_EPSILON);
        let mut at = 0;
        let mut prob = 1.0;
        loop {
            match self.nodes.get(at)?.kind {
                Kind::Leaf(i) => return Some((i as usize, prob)),
                Kind::Inner(second) => {
                    let first = self.first_share(at, second as usize, p, n)?;
                    if u < first {
                        u = (u / first).min(ONE_MINUS_EPSILON);
                        prob *= first;
                        at += 1;
                    } else {
                        u = ((u - first) / (1.0 - first)).min(ONE_MINUS_EPSILON);
                        prob *= 1.0 - first;
                        at = second as usize;
                    }
                }
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
            let Some(Kind::Inner(second)) = self.nodes.get(at).map(|n| n.kind) else {
                return 0.0;
            };
            let Some(first) = self.first_share(at, second as usize, p, n) else {
                return 0.0;
            };
            if path & (1 << level) == 0 {
                prob *= first;
                at += 1;
            } else {
                prob *= 1.0 - first;
                at = second as usize;
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
        for node in &a.nodes {
            if let Kind::Leaf(i) = node.kind {
                assert!(!seen[i as usize]);
                seen[i as usize] = true;
            }
        }
        assert!(seen.iter().all(|s| *s));
        assert_eq!(a.nodes.len(), 2 * lights.len() - 1);
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
