//! The vector width the tracer is written for. Everything that works on
//! several values side by side (the rays of a packet, the samples of a
//! sampler block, the faces of a flat pass, the lanes of an AVX register)
//! uses this one width, so that a block of samples is one packet of rays
//! and one register of floats. It sits below every other module, which
//! may all use it.

/// Values processed side by side: eight `f32`s fill one AVX register.
pub const LANES: usize = 8;
