//! Random numbers and the warps that turn them into points and directions: a
//! leaf module (it imports nothing from the crate) used by the renderer, the
//! scene generators and the tests. Geometry needs none of it.

pub mod distribution;
pub mod rng;
pub mod sampler;
pub mod sobol;
pub mod sobol8;
pub mod warp;

pub use rng::Rng;
pub use sampler::{Dim, Sampler, SamplerKind};
