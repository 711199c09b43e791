//! Normal and bump maps at a hit: the tangent frame from the hit's
//! ∂p/∂u and ∂p/∂v (or, where the surface has none, any frame about the
//! normal), the mapped shading normal, and the rules that keep it
//! consistent with the geometric surface.
//!
//! - A normal map's texel (r, g, b) is the tangent-space normal
//!   (2r − 1, 2g − 1, 2b − 1) along (∂p/∂u, ∂p/∂v, outward normal), the
//!   OpenGL convention glTF uses (green up the image, v = 1 at its top);
//!   `strength` scales its tilt (x and y) before it is normalised.
//! - A bump map moves the surface by `scale` × the texture's mean channel
//!   along the normal; the shading normal is the cross product of the
//!   moved surface's derivatives (the slope from central differences half
//!   a texel apart, 1/2048 for textures that are not images), as pbrt's
//!   and Mitsuba's bump maps do, without the curvature term.
//! - The map is applied to the outward normal and the result turned to the
//!   side the ray came from, so a surface seen from behind shows the mirror
//!   image of its relief.
//! - A mapped normal that faces away from the viewer (or within 0.01 of
//!   grazing) is bent towards it, `n + (0.01 − n·wo)·wo` normalised, so the
//!   surface never turns black for the viewer's side.
//! - A direction a mapped material samples is kept only when it is on the
//!   same side of the geometric surface as of the mapped normal
//!   ([`keeps_side`], Mitsuba's `normalmap` rule with the geometric normal
//!   as the reference): no light leaks through the surface.

use glam::{Vec2, Vec3};

use super::texture::lookup;
use crate::geometry::{Hit, Tangents};
use crate::scene::{Scene, Texture, TextureId};

/// How far a mapped normal must face the viewer: n·wo ≥ this.
const MIN_FACING: f32 = 0.01;

/// The uv step of a bump map's slope on a texture that is not an image.
const BUMP_STEP: f32 = 1.0 / 2048.0;

/// The unit tangent `t` and bitangent `b` about unit normal `n`: ∂p/∂u
/// made perpendicular to `n`, and `n × t` turned along ∂p/∂v.
fn frame(n: Vec3, tangents: Tangents) -> (Vec3, Vec3) {
    let t = (tangents.dpdu - n * n.dot(tangents.dpdu)).normalize_or_zero();
    if t == Vec3::ZERO {
        return n.any_orthonormal_pair();
    }
    let b = n.cross(t);
    if b.dot(tangents.dpdv) < 0.0 {
        (t, -b)
    } else {
        (t, b)
    }
}

/// The hit's shading normal turned outwards, and the sign that turns a
/// normal back to the ray's side.
fn outward(hit: &Hit) -> (Vec3, f32) {
    let sign = if hit.front_face { 1.0 } else { -1.0 };
    (hit.normal * sign, sign)
}

/// `n` bent towards the viewer `wo` until n·wo ≥ [`MIN_FACING`]; unit.
fn toward_viewer(n: Vec3, wo: Vec3) -> Vec3 {
    let c = n.dot(wo);
    if c >= MIN_FACING {
        return n;
    }
    (n + (MIN_FACING - c) * wo).normalize_or(wo)
}

/// The shading normal of `hit` read from the normal map `map`, facing the
/// ray's side; `p` is the hit's scene point (for 3-D textures).
pub fn normal_mapped(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    p: Vec3,
    map: TextureId,
    strength: f32,
) -> Vec3 {
    let (n, sign) = outward(hit);
    let (t, b) = frame(n, hit.tangents);
    let c = lookup(scene, map, hit.uv, p) * 2.0 - Vec3::ONE;
    let mapped = (t * (c.x * strength) + b * (c.y * strength) + n * c.z).normalize_or(n);
    toward_viewer(mapped * sign, wo)
}

/// The shading normal of `hit` tilted by the height field `scale` ×
/// `height`, facing the ray's side.
pub fn bumped(scene: &Scene, hit: &Hit, wo: Vec3, p: Vec3, height: TextureId, scale: f32) -> Vec3 {
    let (n, sign) = outward(hit);
    let (dpdu, dpdv) = if hit.tangents == Tangents::NONE {
        n.any_orthonormal_pair()
    } else {
        (hit.tangents.dpdu, hit.tangents.dpdv)
    };
    let step = match scene.texture(height) {
        Texture::Image(img) | Texture::Data(img) => {
            Vec2::new(0.5 / img.width as f32, 0.5 / img.height as f32)
        }
        _ => Vec2::splat(BUMP_STEP),
    };
    let uv = hit.uv.get();
    let h = |d: Vec2| {
        let c = lookup(scene, height, (uv + d).into(), p);
        scale * (c.x + c.y + c.z) / 3.0
    };
    let dhdu = (h(Vec2::new(step.x, 0.0)) - h(Vec2::new(-step.x, 0.0))) / (2.0 * step.x);
    let dhdv = (h(Vec2::new(0.0, step.y)) - h(Vec2::new(0.0, -step.y))) / (2.0 * step.y);
    let moved = (dpdu + dhdu * n).cross(dpdv + dhdv * n);
    let mut bumped = moved.normalize_or(n);
    if bumped.dot(n) < 0.0 {
        bumped = -bumped;
    }
    toward_viewer(bumped * sign, wo)
}

/// Whether a direction `wi` sampled at `hit` under the mapped normal
/// `normal` lies on the same side of the geometric surface as of `normal`.
#[inline]
pub fn keeps_side(hit: &Hit, normal: Vec3, wi: Vec3) -> bool {
    (wi.dot(hit.geo_normal) > 0.0) == (wi.dot(normal) > 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::SurfaceUv;
    use crate::scene::{ImageData, MaterialId};
    use std::sync::Arc;

    fn hit(front_face: bool) -> Hit {
        let n = if front_face { Vec3::Y } else { -Vec3::Y };
        Hit {
            t: 1.0,
            point: Vec3::ZERO,
            error: Vec3::ZERO,
            geo_normal: n,
            normal: n,
            uv: SurfaceUv::At(Vec2::new(0.3, 0.6)),
            front_face,
            material: MaterialId(0),
            tangents: Tangents {
                dpdu: Vec3::X * 2.0,
                dpdv: -Vec3::Z * 3.0,
            },
            light: crate::geometry::emitter::LightId::NONE,
        }
    }

    fn solid(scene: &mut Scene, c: Vec3) -> TextureId {
        scene.add_texture(Texture::Solid(c))
    }

    /// A texel encodes the normal in the frame (∂p/∂u, ∂p/∂v, n): one
    /// pointing along +x of tangent space tilts towards ∂p/∂u, and its
    /// strength scales the tilt.
    #[test]
    fn a_normal_map_tilts_along_the_tangents() {
        let mut scene = Scene::default();
        let flat = solid(&mut scene, Vec3::new(0.5, 0.5, 1.0));
        let along_u = solid(&mut scene, Vec3::new(1.0, 0.5, 0.5 + 0.5f32.sqrt() / 2.0));
        let along_v = solid(&mut scene, Vec3::new(0.5, 1.0, 0.5 + 0.5f32.sqrt() / 2.0));
        let up = Vec3::Y;
        let h = hit(true);
        let n = normal_mapped(&scene, &h, up, Vec3::ZERO, flat, 1.0);
        assert!((n - Vec3::Y).length() < 1e-6, "{n}");
        let n = normal_mapped(&scene, &h, up, Vec3::ZERO, along_u, 1.0);
        assert!(
            (n - Vec3::new(1.0, 0.5f32.sqrt(), 0.0).normalize()).length() < 1e-5,
            "{n}"
        );
        let n = normal_mapped(&scene, &h, up, Vec3::ZERO, along_v, 1.0);
        assert!(
            (n - Vec3::new(0.0, 0.5f32.sqrt(), -1.0).normalize()).length() < 1e-5,
            "{n}"
        );
        let n = normal_mapped(&scene, &h, up, Vec3::ZERO, along_u, 0.0);
        assert!((n - Vec3::Y).length() < 1e-6, "{n}");
        // From behind, the relief is mirrored and the normal faces the ray.
        let back = hit(false);
        let n = normal_mapped(&scene, &back, -up, Vec3::ZERO, along_u, 1.0);
        assert!(
            (n - Vec3::new(-1.0, -(0.5f32.sqrt()), 0.0).normalize()).length() < 1e-5,
            "{n}"
        );
    }

    /// Whatever the texel, even one pointing into the surface or one that
    /// decodes to zero, the mapped normal is unit, finite and faces the
    /// viewer by at least `MIN_FACING`.
    #[test]
    fn a_mapped_normal_always_faces_the_viewer() {
        let mut scene = Scene::default();
        let mut r = crate::sampling::rng::numbers(3);
        for k in 0..5000 {
            let texel = match k {
                0 => Vec3::splat(0.5),
                1 => Vec3::new(0.5, 0.5, 0.0),
                2 => Vec3::new(1.0, 0.0, 0.5),
                _ => Vec3::new(r(), r(), r()),
            };
            let tex = solid(&mut scene, texel);
            let e = (r() * 89.0 + 0.5).to_radians();
            let a = r() * std::f32::consts::TAU;
            let wo = Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
            for strength in [0.0, 1.0, 10.0] {
                let n = normal_mapped(&scene, &hit(true), wo, Vec3::ZERO, tex, strength);
                assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-4, "{n}");
                assert!(n.dot(wo) >= MIN_FACING * 0.99, "{texel} {wo}: {n}");
            }
        }
    }

    /// A height field rising along u by `slope` per unit of u tilts the
    /// normal back against ∂p/∂u by atan(slope / |∂p/∂u|).
    #[test]
    fn a_bump_map_tilts_against_the_slope() {
        let mut scene = Scene::default();
        let ramp = scene.add_texture(Texture::Data(Arc::new(ImageData {
            width: 64,
            height: 1,
            pixels: (0..64).map(|x| Vec3::splat(x as f32 / 64.0)).collect(),
        })));
        let h = hit(true);
        let n = bumped(&scene, &h, Vec3::Y, Vec3::ZERO, ramp, 2.0);
        // dh/du = 2, |dp/du| = 2: the normal leans 45° towards −x.
        let want = Vec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((n - want).length() < 1e-3, "{n}");
        let flat = solid(&mut scene, Vec3::splat(0.3));
        let n = bumped(&scene, &h, Vec3::Y, Vec3::ZERO, flat, 5.0);
        assert!((n - Vec3::Y).length() < 1e-6, "{n}");
    }

    #[test]
    fn a_direction_through_the_surface_is_refused() {
        let h = hit(true);
        let tilted = Vec3::new(1.0, 0.2, 0.0).normalize();
        // Above the mapped normal's horizon but below the surface.
        let wi = Vec3::new(0.9, -0.1, 0.0).normalize();
        assert!(!keeps_side(&h, tilted, wi));
        assert!(keeps_side(&h, tilted, Vec3::Y));
        assert!(keeps_side(&h, Vec3::Y, -Vec3::Y));
    }
}
