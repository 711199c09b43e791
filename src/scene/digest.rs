//! A 64-bit FNV-1a digest of plain data. Large arrays (mesh vertices and
//! indices, image pixels) show in `Debug` output as their length and digest
//! rather than as millions of formatted numbers; the same hash takes a
//! scene's serialized bytes for its identity (`render::piece::scene_identity`).

use std::fmt;

use glam::{Vec2, Vec3};

/// A running FNV-1a hash; also a [`fmt::Write`] sink, so anything `Debug`
/// can be hashed without building the string.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

/// So that a serializer can write straight into the hash.
impl std::io::Write for Fnv {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.bytes(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// How a large array prints in `Debug`: `[N × digest]`.
pub struct Summary {
    len: usize,
    digest: u64,
}

impl fmt::Debug for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{} × {:016x}]", self.len, self.digest)
    }
}

/// Values whose exact bits a digest can take.
pub trait Bits {
    fn feed(&self, h: &mut Fnv);
}

impl Bits for Vec3 {
    fn feed(&self, h: &mut Fnv) {
        for x in self.to_array() {
            h.bytes(&x.to_bits().to_le_bytes());
        }
    }
}

impl Bits for Vec2 {
    fn feed(&self, h: &mut Fnv) {
        for x in self.to_array() {
            h.bytes(&x.to_bits().to_le_bytes());
        }
    }
}

impl Bits for [u32; 3] {
    fn feed(&self, h: &mut Fnv) {
        for x in self {
            h.bytes(&x.to_le_bytes());
        }
    }
}

impl Bits for u16 {
    fn feed(&self, h: &mut Fnv) {
        h.bytes(&self.to_le_bytes());
    }
}

/// The length and digest of `values`, for a `Debug` field.
pub fn summary<T: Bits>(values: &[T]) -> Summary {
    let mut h = Fnv::default();
    values.iter().for_each(|v| v.feed(&mut h));
    Summary {
        len: values.len(),
        digest: h.finish(),
    }
}

/// Serializes a large array as its length and digest (`serde`'s
/// `serialize_with`): the scene identity then hashes each array's bits in one
/// tight loop instead of encoding every number (the CBOR of a 2048 × 1024
/// texture was 40 % of a render's start-up).
pub fn serialize_summary<T: Bits, S: serde::Serializer>(
    values: &[T],
    s: S,
) -> Result<S::Ok, S::Error> {
    let Summary { len, digest } = summary(values);
    serde::Serialize::serialize(&(len, digest), s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_summary_changes_with_any_bit_and_with_the_length() {
        let a = [Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO];
        let mut b = a;
        b[1].z = -0.0;
        let show = |v: &[Vec3]| format!("{:?}", summary(v));
        assert_eq!(show(&a), show(&a.clone()));
        assert_ne!(show(&a), show(&b), "−0 and +0 differ in their bits");
        assert_ne!(show(&a), show(&a[..1]));
        assert!(show(&a).starts_with("[2 × "));
    }
}
