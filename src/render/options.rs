//! What to render: image size, samples, depth, seed, threads and crop, with
//! the scene's settings as defaults.

use super::lights::LightSelection;
use crate::sampling::SamplerKind;
use crate::scene::Settings;

/// A half-open pixel rectangle `x0..x1 × y0..y1` of the full image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

impl Crop {
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }
}

/// Everything that decides the pixels besides the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub max_depth: u32,
    pub seed: u64,
    /// Where the sample numbers come from (Sobol' by default).
    pub sampler: SamplerKind,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    pub crop: Option<Crop>,
    /// Next-event estimation with multiple importance sampling (on by
    /// default); off gives plain path tracing.
    pub light_sampling: bool,
    /// How light sampling chooses a light (the light tree by default).
    pub light_selection: LightSelection,
    /// Caps each sample's radiance at this maximum component (biased; off by
    /// default).
    pub clamp: Option<f32>,
    /// Adaptive sampling: a pixel stops once the relative standard error of
    /// its mean luminance is below this; `spp` is then the cap.
    pub noise: Option<f32>,
    /// Added to every sample index (progressive rounds of `--time` draw
    /// new samples this way).
    pub sample_offset: u32,
    /// Independent sample set: pass `p` takes the sample indices
    /// `p·spp .. (p+1)·spp` of every pixel's stream.
    pub pass: u32,
    /// Trace the samples of each sampler block side by side where the
    /// scene allows it (`render::lanes`: the same image, faster); off, one
    /// path at a time everywhere (on by default).
    pub lanes: bool,
    /// Whether the first round of samples is one per pixel, a coarse image
    /// of the whole frame at once (for the preview, and for a time budget
    /// or an interruption that may come before a block of samples is
    /// done); otherwise the first round is a whole block of the sampler,
    /// which a render that runs to its end spends less on (on by default).
    pub coarse_first: bool,
    /// The most bytes the film of the rendered region may take (the same
    /// budget `--memory-budget` gives the scene's evaluation), checked
    /// after the command line's size overrides.
    pub memory_budget: u64,
}

/// Why options cannot be rendered.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum OptionsError {
    #[error("the image size {0}×{1} is empty")]
    EmptyImage(u32, u32),
    #[error("samples per pixel must be at least 1")]
    NoSamples,
    #[error("crop {x0},{x1},{y0},{y1} is empty or outside the {width}×{height} image")]
    BadCrop {
        x0: u32,
        x1: u32,
        y0: u32,
        y1: u32,
        width: u32,
        height: u32,
    },
    #[error("{0} threads requested; need at least 1")]
    NoThreads(usize),
    #[error("{0} threads requested; at most {max} may be started", max = MAX_THREADS)]
    TooManyThreads(usize),
    #[error("the clamp {0} must be a positive number")]
    BadClamp(f32),
    #[error("the noise target {0} must be a positive number")]
    BadNoise(f32),
    #[error("pass {pass} of {spp} spp needs sample indices beyond 2^32")]
    PassTooLarge { pass: u32, spp: u32 },
    #[error(
        "the {width}×{height} image would need about {gib:.1} GiB for its film \
         (the memory budget is {max_gib:.1} GiB); lower --width/--height, use --crop \
         or raise --memory-budget"
    )]
    TooLarge {
        width: u32,
        height: u32,
        gib: f64,
        max_gib: f64,
    },
    #[error(
        "{samples:.3e} samples ({spp} per pixel) is more than the {max:.0e} a render may trace; \
         lower --spp or the image size"
    )]
    TooManySamples { samples: f64, spp: u32, max: f64 },
}

/// Bytes a rendered pixel costs at the peak (film sums and counts, tile
/// results, output pixels and the encoded image); the scene evaluator
/// charges the same figure (`lang::eval::budget`), measured with
/// `/usr/bin/time -f %M` (64 was too low for a 2047² render).
pub const BYTES_PER_PIXEL: u64 = 128;
/// The memory budget when none is given: 16 GiB, as the scene evaluator's.
pub const DEFAULT_MEMORY_BUDGET: u64 = 16 << 30;
/// The most samples (pixels × samples per pixel) a render may trace.
const MAX_SAMPLES: f64 = 1e13;
/// The most worker threads a render may start.
const MAX_THREADS: usize = 4096;

impl RenderOptions {
    /// The scene's own settings, whole image, every core.
    pub fn from_settings(s: &Settings) -> RenderOptions {
        RenderOptions {
            width: s.width,
            height: s.height,
            spp: s.spp,
            max_depth: s.max_depth,
            seed: s.seed,
            sampler: SamplerKind::default(),
            threads: None,
            crop: None,
            light_sampling: true,
            light_selection: LightSelection::default(),
            clamp: None,
            noise: None,
            sample_offset: 0,
            pass: 0,
            lanes: true,
            coarse_first: true,
            memory_budget: DEFAULT_MEMORY_BUDGET,
        }
    }

    /// The rendered region (the crop, or the whole image), after checking
    /// that the options make sense.
    pub fn region(&self) -> Result<Crop, OptionsError> {
        if self.width == 0 || self.height == 0 {
            return Err(OptionsError::EmptyImage(self.width, self.height));
        }
        if self.spp == 0 {
            return Err(OptionsError::NoSamples);
        }
        if let Some(c) = self.clamp.filter(|c| c.is_nan() || *c <= 0.0) {
            return Err(OptionsError::BadClamp(c));
        }
        if let Some(n) = self.noise.filter(|n| n.is_nan() || *n <= 0.0) {
            return Err(OptionsError::BadNoise(n));
        }
        match self.threads {
            Some(0) => return Err(OptionsError::NoThreads(0)),
            Some(n) if n > MAX_THREADS => return Err(OptionsError::TooManyThreads(n)),
            _ => {}
        }
        if self.first_sample().is_none() {
            return Err(OptionsError::PassTooLarge {
                pass: self.pass,
                spp: self.spp,
            });
        }
        let whole = Crop {
            x0: 0,
            x1: self.width,
            y0: 0,
            y1: self.height,
        };
        let c = self.crop.unwrap_or(whole);
        if c.x0 >= c.x1 || c.y0 >= c.y1 || c.x1 > self.width || c.y1 > self.height {
            return Err(OptionsError::BadCrop {
                x0: c.x0,
                x1: c.x1,
                y0: c.y0,
                y1: c.y1,
                width: self.width,
                height: self.height,
            });
        }
        let pixels = u64::from(c.x1 - c.x0) * u64::from(c.y1 - c.y0);
        let bytes = pixels.saturating_mul(BYTES_PER_PIXEL);
        if bytes > self.memory_budget {
            let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
            return Err(OptionsError::TooLarge {
                width: c.x1 - c.x0,
                height: c.y1 - c.y0,
                gib: gib(bytes),
                max_gib: gib(self.memory_budget),
            });
        }
        let samples = pixels as f64 * f64::from(self.spp);
        if samples > MAX_SAMPLES {
            return Err(OptionsError::TooManySamples {
                samples,
                spp: self.spp,
                max: MAX_SAMPLES,
            });
        }
        Ok(c)
    }

    /// The first sample index of this pass: `pass · spp`, if every index of
    /// the pass fits the stream's 32-bit sample counter.
    pub fn first_sample(&self) -> Option<u32> {
        let first = self
            .pass
            .checked_mul(self.spp)?
            .checked_add(self.sample_offset)?;
        first.checked_add(self.spp).map(|_| first)
    }
}
