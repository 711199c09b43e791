//! Where a ray runs inside participating media: the segments a query
//! collects as it passes through objects, groups and instances down to a
//! medium's boundary. Plain data, below every kind of object that carries
//! it, so that none of them needs the medium itself.

use arrayvec::ArrayVec;

use crate::scene::MaterialId;

/// Boundary crossings looked for per ray before giving up (a ray weaving
/// through a non-convex boundary), and the segments one query can hold.
pub(super) const MAX_SEGMENTS: usize = 16;

/// A stretch `t0..t1` of a ray inside a medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumSegment {
    pub t0: f32,
    pub t1: f32,
    pub density: f32,
    pub material: MaterialId,
}

/// The medium segments a query found, in a fixed-capacity array (no
/// allocation, and not zero-filled: a query that meets no medium writes
/// nothing); segments past its capacity are dropped, as crossings past
/// `MAX_SEGMENTS` always were.
#[derive(Clone, Debug, Default)]
pub struct MediumSegments {
    items: ArrayVec<MediumSegment, MAX_SEGMENTS>,
}

impl MediumSegments {
    #[inline]
    pub fn clear(&mut self) {
        self.items.clear();
    }

    #[inline]
    pub(super) fn push(&mut self, s: MediumSegment) {
        let _ = self.items.try_push(s);
    }

    /// The segments found.
    #[inline]
    pub fn as_slice(&self) -> &[MediumSegment] {
        &self.items
    }
}
