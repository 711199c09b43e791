//! Convergence and throughput measurements behind `rtlang bench`: renders a
//! high-spp reference, then each method at increasing spp, recording wall
//! time and the error against the reference (RMSE, relative MSE), under
//! each sampler; returns the numbers and a markdown table (the CLI plots).

use std::time::Duration;

use glam::Vec3;

use super::lights::LightSelection;
use super::options::RenderOptions;
use super::tiles::{render, RenderError, RenderOutput};
use crate::geometry::World;
use crate::picture::metrics::{compare, Metrics};
use crate::picture::{LinearImage, PictureError};
use crate::sampling::SamplerKind;
use crate::scene::Scene;

/// A way of rendering whose convergence is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Plain path tracing.
    Path,
    /// Next-event estimation with MIS, lights chosen by the light tree.
    Nee,
    /// Next-event estimation with MIS, lights chosen by power.
    NeePower,
    /// Light sampling with adaptive sampling: at a nominal `n` spp, pixels
    /// may trace up to `4n` samples and stop at relative error `1/√n`.
    NeeAdaptive,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Path => "path",
            Method::Nee => "nee",
            Method::NeePower => "nee, power",
            Method::NeeAdaptive => "nee+adaptive",
        }
    }

    /// Sets `options` for this method at a nominal `spp`.
    fn apply(self, options: &mut RenderOptions, spp: u32) {
        options.light_sampling = self != Method::Path;
        options.light_selection = match self {
            Method::NeePower => LightSelection::Power,
            _ => LightSelection::Tree,
        };
        options.spp = spp;
        options.noise = None;
        if self == Method::NeeAdaptive {
            options.spp = spp.saturating_mul(4);
            options.noise = Some(1.0 / (spp as f32).sqrt());
        }
    }
}

/// One measured render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    pub method: Method,
    pub sampler: SamplerKind,
    /// The nominal spp.
    pub spp: u32,
    /// Samples actually traced per pixel, on average.
    pub mean_spp: f64,
    pub wall: Duration,
    pub metrics: Metrics,
}

/// A convergence study of one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Convergence {
    pub reference_spp: u32,
    pub reference_wall: Duration,
    pub measurements: Vec<Measurement>,
}

/// Why a study failed.
#[derive(Debug, thiserror::Error)]
pub enum ConvergenceError {
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Picture(#[from] PictureError),
}

/// The pixels of a render as a picture.
pub fn to_image(out: &RenderOutput) -> LinearImage {
    LinearImage {
        width: out.width,
        height: out.height,
        pixels: out.pixels.iter().map(|p: &Vec3| p.to_array()).collect(),
    }
}

/// Renders the reference with `base` at `reference_spp` (light sampling,
/// the Sobol' sampler, seed `base.seed + 1`, so independent of the measured
/// renders), then every method under every sampler at every spp of `spps`
/// with `base.seed`.
pub fn study(
    scene: &Scene,
    world: &World,
    base: &RenderOptions,
    reference_spp: u32,
    methods: &[Method],
    samplers: &[SamplerKind],
    spps: &[u32],
) -> Result<Convergence, ConvergenceError> {
    let mut options = base.clone();
    options.spp = reference_spp;
    options.seed = base.seed.wrapping_add(1);
    options.light_sampling = true;
    options.sampler = SamplerKind::Sobol;
    options.noise = None;
    let reference = render(scene, world, &options, &|_| {})?;
    let reference_image = to_image(&reference);
    let mut measurements = Vec::new();
    for &method in methods {
        for &sampler in samplers {
            for &spp in spps {
                let mut options = base.clone();
                method.apply(&mut options, spp);
                options.sampler = sampler;
                let out = render(scene, world, &options, &|_| {})?;
                let pixels = (out.width as u64 * out.height as u64).max(1);
                measurements.push(Measurement {
                    method,
                    sampler,
                    spp,
                    mean_spp: out.stats.samples as f64 / pixels as f64,
                    wall: out.stats.wall,
                    metrics: compare(&to_image(&out), &reference_image)?,
                });
            }
        }
    }
    Ok(Convergence {
        reference_spp,
        reference_wall: reference.stats.wall,
        measurements,
    })
}

impl Convergence {
    /// A markdown table: method, sampler, spp, seconds, RMSE, relative MSE.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "Reference: {} spp with light sampling, {:.2} s.\n\n\
             | method | sampler | spp | mean spp | time (s) | RMSE | relMSE |\n\
             |---|---|---:|---:|---:|---:|---:|\n",
            self.reference_spp,
            self.reference_wall.as_secs_f64()
        );
        for m in &self.measurements {
            s += &format!(
                "| {} | {} | {} | {:.1} | {:.3} | {:.4e} | {:.4e} |\n",
                m.method.name(),
                m.sampler.name(),
                m.spp,
                m.mean_spp,
                m.wall.as_secs_f64(),
                m.metrics.rmse,
                m.metrics.rel_mse
            );
        }
        s
    }

    /// The measurements of `method` under `sampler`, in spp order.
    pub fn series(
        &self,
        method: Method,
        sampler: SamplerKind,
    ) -> impl Iterator<Item = &Measurement> + '_ {
        self.measurements
            .iter()
            .filter(move |m| m.method == method && m.sampler == sampler)
    }

    /// Relative MSE of `method` under `sampler` at nominal `spp`.
    pub fn rel_mse_at_spp(&self, method: Method, sampler: SamplerKind, spp: u32) -> Option<f64> {
        self.series(method, sampler)
            .find(|m| m.spp == spp)
            .map(|m| m.metrics.rel_mse)
    }

    /// Relative MSE of `method` under `sampler` at `seconds`, interpolated
    /// log-log between its measurements (`None` outside their time range).
    pub fn rel_mse_at(&self, method: Method, sampler: SamplerKind, seconds: f64) -> Option<f64> {
        let pts: Vec<(f64, f64)> = self
            .series(method, sampler)
            .map(|m| (m.wall.as_secs_f64(), m.metrics.rel_mse))
            .collect();
        pts.windows(2).find_map(|w| {
            let ((t0, e0), (t1, e1)) = (w[0], w[1]);
            if !(t0 <= seconds && seconds <= t1) || t0 <= 0.0 || e0 <= 0.0 || e1 <= 0.0 {
                return None;
            }
            let f = if t1 > t0 {
                (seconds.ln() - t0.ln()) / (t1.ln() - t0.ln())
            } else {
                0.0
            };
            Some((e0.ln() + f * (e1.ln() - e0.ln())).exp())
        })
    }
}

/// Samples and rays per second of one render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Throughput {
    pub threads: usize,
    pub wall: Duration,
    pub samples_per_second: f64,
    pub rays_per_second: f64,
}

/// Renders with `options` on `threads` threads and reports the throughput.
pub fn throughput(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    threads: usize,
) -> Result<Throughput, RenderError> {
    let mut options = options.clone();
    options.threads = Some(threads);
    let out = render(scene, world, &options, &|_| {})?;
    let secs = out.stats.wall.as_secs_f64().max(1e-9);
    Ok(Throughput {
        threads,
        wall: out.stats.wall,
        samples_per_second: out.stats.samples as f64 / secs,
        rays_per_second: out.stats.rays as f64 / secs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::scenes::cornell_box;

    #[test]
    fn errors_fall_with_samples_and_light_sampling_beats_path_tracing() {
        let scene = cornell_box(24, 1);
        let world = World::build(&scene).expect("builds");
        let base = RenderOptions::from_settings(&scene.settings);
        let study = study(
            &scene,
            &world,
            &base,
            256,
            &[Method::Path, Method::Nee],
            &[SamplerKind::Independent],
            &[4, 16],
        )
        .expect("runs");
        assert_eq!(study.measurements.len(), 4);
        let e = |i: usize| study.measurements[i].metrics.rel_mse;
        assert!(e(1) < e(0), "path: {} then {}", e(0), e(1));
        assert!(e(3) < e(2), "nee: {} then {}", e(2), e(3));
        assert!(e(3) < e(1), "nee {} vs path {} at 16 spp", e(3), e(1));
        let table = study.markdown();
        assert!(
            table.contains("| path | independent | 16 |")
                && table.contains("| nee | independent | 4 |")
        );
    }
}
