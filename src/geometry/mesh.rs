//! Triangle meshes under their own BVH: the shared [`MeshData`] arrays plus
//! each leaf's triangles packed for a four-lane test ([`super::leaf`]) with
//! their corners and triangle numbers, the tree's leaves numbered by their
//! packs. A hit takes its corners and triangle from its leaf, and reads the
//! mesh's arrays only for what the leaf lacks (vertex normals, uvs).

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::bvh::Leaves;
use super::emitter::LightId;
use super::hit::facing;
use super::leaf::TriangleLeaf;
use super::shapes::triangle::{unit_normal, ShearedRay};
use super::shapes::ShapeHit;
use super::tangents::{self, Tangents};
use super::{Aabb, Bvh, Hit, Ray};
use crate::scene::{MaterialId, MeshData};

/// A mesh ready for intersection.
#[derive(Debug)]
pub struct MeshGeometry {
    data: Arc<MeshData>,
    /// Scene material of each material slot of the mesh.
    materials: Vec<MaterialId>,
    /// Light id of each triangle (by index in `data`); empty when none emits.
    lights: Vec<LightId>,
    /// The hierarchy, its leaves numbered by their place in `leaves`.
    bvh: Bvh,
    /// Every leaf's triangles packed for a four-lane coverage test.
    leaves: Vec<TriangleLeaf>,
}

/// A mesh hit: the surface hit with the shading normal, the material and
/// the light id.
pub struct MeshHit {
    pub hit: ShapeHit,
    pub shading_normal: Vec3,
    pub material: MaterialId,
    pub light: LightId,
    /// ∂p/∂u and ∂p/∂v when the material reads them.
    pub tangents: Tangents,
}

impl MeshGeometry {
    /// Builds the BVH over `data`'s triangles; `materials` maps slots to
    /// scene materials and must not be empty.
    pub fn new(data: Arc<MeshData>, materials: Vec<MaterialId>) -> MeshGeometry {
        let bounds: Vec<Aabb> = data
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| data.positions[i as usize]);
                Aabb::new(a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let (mut bvh, order) = Bvh::build_leaves(&bounds, Leaves::Packed);
        // The packs in the order the leaves are listed (the nodes', so
        // nearby leaves lie nearby), each leaf numbered by its pack.
        let mut leaves = Vec::new();
        bvh.number_leaves(|first, count| {
            let ids = &order[first..first + count];
            let tris: Vec<[Vec3; 3]> = ids
                .iter()
                .map(|&t| data.triangles[t as usize].map(|i| data.positions[i as usize]))
                .collect();
            leaves.push(TriangleLeaf::new(&tris, ids));
            (leaves.len() - 1) as u32
        });
        MeshGeometry {
            leaves,
            data,
            materials,
            lights: Vec::new(),
            bvh,
        }
    }

    /// The mesh with triangle `i` emitting as light `lights[i]`.
    pub fn with_lights(self, lights: Vec<LightId>) -> MeshGeometry {
        MeshGeometry { lights, ..self }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Bytes this structure adds to the shared mesh data.
    pub fn memory(&self) -> usize {
        self.bvh.memory()
            + self.lights.len() * 4
            + self.leaves.len() * std::mem::size_of::<TriangleLeaf>()
    }

    /// Whether any triangle is hit with `t` in `(t_min, t_max)`: the walk
    /// ends at the first leaf with a hit, and no surface data is built.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        // Built at the first leaf: most rays that miss never reach one.
        let mut sheared = None;
        self.bvh.traverse_any_leaves(
            ray,
            t_max,
            #[inline(always)]
            |pack, _, t_max| {
                let sheared = sheared.get_or_insert_with(|| ShearedRay::new(ray));
                let leaf = &self.leaves[pack];
                let scalar = |lane, t_max| {
                    let p = leaf.corners(lane);
                    sheared.intersect(p, t_min, t_max).is_some()
                };
                leaf.any(sheared, t_min, t_max, scalar)
            },
        )
    }

    /// The tangents of the triangle of corners `p` and vertex indices
    /// `idx`, over its uvs (or its barycentrics when the mesh has none).
    #[inline(never)]
    fn tangents(&self, p: [Vec3; 3], idx: [usize; 3]) -> Tangents {
        let uv = if self.data.uvs.is_empty() {
            [Vec2::ZERO, Vec2::X, Vec2::Y]
        } else {
            idx.map(|i| self.data.uvs[i])
        };
        tangents::triangle(p, uv)
    }

    /// The nearest hit with `t` in `(t_min, t_max)` as the [`Hit`] facing
    /// the ray, what the world asks a mesh for.
    #[inline(always)]
    pub fn intersect_facing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let h = self.intersect(ray, t_min, t_max)?;
        let mut hit = facing(h.hit, h.shading_normal, ray.dir, h.material, h.light);
        hit.tangents = h.tangents;
        Some(hit)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<MeshHit> {
        let mut sheared = None;
        let mut best = None;
        self.bvh.traverse_leaves(
            ray,
            t_max,
            #[inline(always)]
            |pack, _, t_max| {
                let sheared = sheared.get_or_insert_with(|| ShearedRay::new(ray));
                let leaf = &self.leaves[pack];
                let scalar = |lane, t_max| sheared.intersect(leaf.corners(lane), t_min, t_max);
                let (lane, h) = leaf.nearest(sheared, t_min, t_max, scalar)?;
                best = Some((pack, lane, h));
                Some(h.t)
            },
        );
        let (pack, lane, h) = best?;
        let leaf = &self.leaves[pack];
        let tri = leaf.id(lane);
        let [a, b, c] = leaf.corners(lane);
        let w = h.bary;
        let normal = unit_normal(a, b, c).unwrap_or(Vec3::Y);
        let slot = self
            .data
            .triangle_material
            .get(tri as usize)
            .copied()
            .unwrap_or(0);
        let material = self.materials[(slot as usize).min(self.materials.len() - 1)];
        // The vertex indices, read only for the arrays that need them.
        let data = &self.data;
        let idx = || data.triangles[tri as usize].map(|i| i as usize);
        let shading_normal = if data.normals.is_empty() {
            normal
        } else {
            let (n, idx) = (&data.normals, idx());
            (w.x * n[idx[0]] + w.y * n[idx[1]] + w.z * n[idx[2]]).normalize_or(normal)
        };
        let uv = if data.uvs.is_empty() {
            Vec2::new(w.y, w.z)
        } else {
            let (t, idx) = (&data.uvs, idx());
            w.x * t[idx[0]] + w.y * t[idx[1]] + w.z * t[idx[2]]
        };
        let tangents = if material.needs_tangents() {
            self.tangents([a, b, c], idx())
        } else {
            Tangents::NONE
        };
        Some(MeshHit {
            tangents,
            hit: ShapeHit {
                t: h.t,
                point: w.x * a + w.y * b + w.z * c,
                error: h.error([a, b, c]),
                normal,
                uv: uv.into(),
            },
            shading_normal,
            material,
            light: self
                .lights
                .get(tri as usize)
                .copied()
                .unwrap_or(LightId::NONE),
        })
    }
}
