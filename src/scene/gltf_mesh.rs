//! One glTF triangle primitive as a [`MeshData`]: every accessor it reads
//! is checked against its buffer view and buffer first (the `gltf` crate's
//! reader trusts them), indices against the vertex count, and positions
//! for finite values within [`MAX_COORDINATE`].
//!
//! glTF's texture coordinates have v down from the image's top row; the
//! mesh's v is up (rtlang's images have v = 1 at the top), so v becomes
//! 1 − v. Without normals the mesh is flat-shaded, as glTF asks. Tangents
//! are not read: maps take their frame from ∂p/∂u and ∂p/∂v.

use glam::{Vec2, Vec3};

use super::object::MAX_COORDINATE;
use super::MeshData;

/// The mesh of `p`, whose buffers' bytes are `buffers`.
pub fn primitive_mesh(p: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<MeshData, String> {
    let positions = p
        .get(&gltf::Semantic::Positions)
        .ok_or("it has no POSITION attribute")?;
    check(&positions, buffers, "POSITION")?;
    let n = positions.count();
    for (semantic, name) in [
        (gltf::Semantic::Normals, "NORMAL"),
        (gltf::Semantic::TexCoords(0), "TEXCOORD_0"),
    ] {
        if let Some(a) = p.get(&semantic) {
            check(&a, buffers, name)?;
            if a.count() != n {
                return Err(format!("{name} has {} items for {n} positions", a.count()));
            }
        }
    }
    if let Some(a) = p.indices() {
        check(&a, buffers, "the indices")?;
    }
    let reader = p.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or("its POSITION cannot be read as 3 floats")?
        .map(Vec3::from)
        .collect();
    if let Some(bad) = positions
        .iter()
        .flat_map(|p| p.to_array())
        .find(|c| !c.is_finite())
    {
        return Err(format!("a position is not a finite number ({bad})"));
    }
    if let Some(far) = positions
        .iter()
        .flat_map(|p| p.to_array())
        .find(|c| c.abs() > MAX_COORDINATE)
    {
        return Err(format!(
            "a position coordinate {far:e} is beyond the limit ±{MAX_COORDINATE:e}"
        ));
    }
    let normals: Vec<Vec3> = match reader.read_normals() {
        Some(it) => it.map(|v| Vec3::from(v).normalize_or_zero()).collect(),
        None => Vec::new(),
    };
    let uvs: Vec<Vec2> = match reader.read_tex_coords(0) {
        Some(it) => it
            .into_f32()
            .map(|[u, v]| Vec2::new(u, 1.0 - v))
            .map(|uv| Vec2::select(uv.is_finite_mask(), uv, Vec2::ZERO))
            .collect(),
        None => Vec::new(),
    };
    let flat: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if !flat.len().is_multiple_of(3) {
        return Err(format!(
            "it has {} indices, not a multiple of 3 for triangles",
            flat.len()
        ));
    }
    if let Some(&i) = flat.iter().find(|&&i| i as usize >= n) {
        return Err(format!("an index {i} is past its {n} vertices"));
    }
    let triangles: Vec<[u32; 3]> = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    if triangles.is_empty() {
        return Err("it has no triangles".into());
    }
    Ok(MeshData {
        positions,
        normals,
        uvs,
        triangles,
        ..MeshData::default()
    })
}

/// An error unless `a` is a dense accessor whose every item lies inside
/// its buffer view, and the view inside its buffer.
fn check(a: &gltf::Accessor, buffers: &[Vec<u8>], name: &str) -> Result<(), String> {
    if a.sparse().is_some() {
        return Err(format!(
            "{name} is a sparse accessor, which rtlang does not read"
        ));
    }
    let view = a
        .view()
        .ok_or_else(|| format!("{name} has no buffer view"))?;
    let count = a.count();
    if count == 0 {
        return Err(format!("{name} has no items"));
    }
    let size = a.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{name}'s stride {stride} is less than its item's {size} bytes"
        ));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(size))
        .and_then(|x| x.checked_add(a.offset()));
    let fits = end.is_some_and(|e| e <= view.length());
    if !fits {
        return Err(format!(
            "{name} has {count} items, more than its buffer view of {} bytes holds",
            view.length()
        ));
    }
    let buffer = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|e| e > buffer) {
        return Err(format!("{name}'s buffer view reaches past its buffer"));
    }
    Ok(())
}
