//! The vector width the tracer is written for, and which vector
//! instructions the CPU at hand runs. Everything that works on several
//! values side by side (the rays of a packet, the samples of a sampler
//! block, the faces of a flat pass, the lanes of an AVX register) uses one
//! width, so that a block of samples is one packet of rays and one
//! register of floats. Every `#[target_feature]` copy of a hot loop is
//! chosen by the one answer detected here. This module sits below every
//! other and imports nothing from the crate.

/// Values processed side by side: eight `f32`s fill one AVX register.
pub const LANES: usize = 8;

#[cfg(target_arch = "x86_64")]
pub use features::{avx, avx2, avx512f};

/// The CPU features the `#[target_feature]` copies of the hot loops need,
/// detected on first use and kept in one byte. Every dispatch site asks
/// here, so a process decides once which copies it runs. The answer
/// never changes, so a racing first use that detects twice stores the same
/// byte twice, and relaxed loads suffice.
#[cfg(target_arch = "x86_64")]
mod features {
    use std::sync::atomic::{AtomicU8, Ordering};

    /// Set once the other bits hold the detected features.
    const KNOWN: u8 = 1;
    const AVX: u8 = 2;
    const AVX2: u8 = 4;
    const AVX512F: u8 = 8;

    static FEATURES: AtomicU8 = AtomicU8::new(0);

    /// The feature bits, detecting them on the first call.
    #[inline(always)]
    fn features() -> u8 {
        let bits = FEATURES.load(Ordering::Relaxed);
        if bits & KNOWN != 0 {
            bits
        } else {
            detect()
        }
    }

    #[cold]
    #[inline(never)]
    fn detect() -> u8 {
        let flag = |has: bool, bit: u8| if has { bit } else { 0 };
        let bits = KNOWN
            | flag(std::arch::is_x86_feature_detected!("avx"), AVX)
            | flag(std::arch::is_x86_feature_detected!("avx2"), AVX2)
            | flag(std::arch::is_x86_feature_detected!("avx512f"), AVX512F);
        FEATURES.store(bits, Ordering::Relaxed);
        bits
    }

    /// Whether the CPU runs AVX: the BVH's eight-box test in one register.
    #[inline(always)]
    pub fn avx() -> bool {
        features() & AVX != 0
    }

    /// Whether the CPU runs AVX2: eight 32-bit integer lanes (masks, the
    /// Sobol' scrambles) in one register, which AVX alone splits in halves.
    #[inline(always)]
    pub fn avx2() -> bool {
        features() & AVX2 != 0
    }

    /// Whether the CPU runs AVX-512F: sixteen-lane flat-face passes.
    #[inline(always)]
    pub fn avx512f() -> bool {
        features() & AVX512F != 0
    }
}
