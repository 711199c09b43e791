//! The `render` and `camera` blocks → [`Settings`](crate::scene::Settings)
//! and [`Camera`](crate::scene::Camera), with range checks and the refusal
//! of images too large to hold in memory.

use super::props::Allow;
use super::value::Value;
use super::{Eval, Evaluator};
use crate::lang::ast::{Item, Stmt};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::properties::{self, camera, render};
use crate::scene::Background;

/// Bytes the renderer keeps per pixel (accumulator and output), for the
/// memory estimate.
const BYTES_PER_PIXEL: f64 = 32.0;
/// The most pixel memory a scene may ask for.
const MAX_PIXEL_BYTES: f64 = 16.0 * (1u64 << 30) as f64;
/// The most samples (pixels × samples per pixel) a scene may ask for.
const MAX_SAMPLES: f64 = 1e13;

impl Evaluator {
    /// `fps` of the first `render` block, read before anything else is
    /// evaluated so that every use of the name `fps` sees it.
    pub(super) fn clock(&mut self, items: &[Item]) {
        let fps = items
            .iter()
            .find_map(|item| match item {
                Item::Render { body, .. } => Some(body),
                _ => None,
            })
            .and_then(|body| {
                body.iter().find_map(|stmt| match stmt {
                    Stmt::Property { name, value, .. } if name.name == render::FPS.name => {
                        Some(value)
                    }
                    _ => None,
                })
            });
        let Some(e) = fps else { return };
        let Ok(v) = self.expr(e).and_then(|v| self.num(&v, e.span)) else {
            return;
        };
        if self
            .range(
                v > 0.0 && v <= 1000.0,
                e.span,
                format!("the frame rate must be in (0, 1000], not {v}"),
                "the frame rate is frames per second, e.g. `fps 24`",
            )
            .is_ok()
        {
            self.options.fps = v;
        }
    }

    pub(super) fn render(&mut self, body: &[Stmt]) {
        let allow = Allow {
            size: true,
            ..Allow::props(&properties::RENDER, false)
        };
        let b = self.block(body, &allow);
        if let Some((w, h)) = b.size {
            let width = self
                .expr(w)
                .and_then(|v| self.count(&v, w.span, "the width"));
            let height = self
                .expr(h)
                .and_then(|v| self.count(&v, h.span, "the height"));
            if let (Ok(width), Ok(height)) = (width, height) {
                let span = w.span.to(h.span);
                if self
                    .range(
                        width > 0 && height > 0,
                        span,
                        format!("the image size {width} x {height} is empty"),
                        "width and height must be at least 1",
                    )
                    .is_ok()
                {
                    self.scene.settings.width = width;
                    self.scene.settings.height = height;
                    self.size_span = Some(span);
                }
            }
        }
        if let Ok((spp, s)) = self.prop_count(&b, &render::SAMPLES, self.scene.settings.spp) {
            if self
                .range(
                    spp > 0,
                    s,
                    "samples per pixel must be at least 1, not 0".into(),
                    "use e.g. `samples 64`",
                )
                .is_ok()
            {
                self.scene.settings.spp = spp;
                self.samples_span = Some(s);
            }
        }
        if let Ok((depth, s)) = self.prop_count(&b, &render::DEPTH, self.scene.settings.max_depth) {
            if self
                .range(
                    depth > 0,
                    s,
                    "the depth must be at least 1, not 0".into(),
                    "the depth is the most bounces a path makes, e.g. `depth 50`",
                )
                .is_ok()
            {
                self.scene.settings.max_depth = depth;
            }
        }
        if let Ok((seed, _)) = self.prop_count(&b, &render::SEED, 0) {
            self.scene.settings.seed = seed as u64;
        }
        if let Ok(Some((v, s))) = self.prop(&b, &render::BACKGROUND) {
            let bg = match v {
                Value::Gradient(bottom, top) => Ok(Background::Gradient {
                    bottom: bottom.as_vec3(),
                    top: top.as_vec3(),
                }),
                Value::Environment(env) => Ok(Background::Environment((*env).clone())),
                other => self
                    .color(&other, s)
                    .map(|c| Background::Solid(c.as_vec3())),
            };
            if let Ok(bg) = bg {
                self.scene.settings.background = bg;
            }
        }
    }

    pub(super) fn camera(&mut self, body: &[Stmt]) {
        let allow = Allow {
            shutter: true,
            ..Allow::props(&properties::CAMERA, false)
        };
        let b = self.block(body, &allow);
        let mut cam = self.scene.camera;
        if let Ok(Some((v, s))) = self.prop(&b, &camera::GLTF) {
            let Ok(path) = self.string(&v, s) else {
                return;
            };
            let Ok((from, at, up, fov)) = self.gltf_camera(&path, s) else {
                return;
            };
            (cam.from, cam.at, cam.up, cam.vfov) = (from, at, up, fov);
            self.scene.camera.up = up;
            self.scene.camera.vfov = fov;
        }
        let from = self.prop_vec3(&b, &camera::FROM, cam.from.as_dvec3());
        let at = self.prop_vec3(&b, &camera::AT, cam.at.as_dvec3());
        let up = self.prop_vec3(&b, &camera::UP, cam.up.as_dvec3());
        let fov = self
            .prop_num(&b, &camera::FOV, cam.vfov as f64)
            .and_then(|(f, s)| {
                self.range(
                    f > 0.0 && f < 180.0,
                    s,
                    format!("the field of view must be in (0, 180) degrees, not {f}"),
                    "the vertical field of view is in degrees, e.g. `fov 40`",
                )?;
                Ok(f)
            });
        let aperture = self
            .prop_num(&b, &camera::APERTURE, 0.0)
            .and_then(|(a, s)| {
                self.range(
                    a >= 0.0,
                    s,
                    format!("the aperture must not be negative, not {a}"),
                    "0 is a pinhole camera",
                )?;
                Ok(a)
            });
        let focus = match self.prop(&b, &camera::FOCUS) {
            Ok(Some((v, s))) => self.num(&v, s).and_then(|f| {
                self.range(
                    f > 0.0,
                    s,
                    format!("the focus distance must be positive, not {f}"),
                    "it is the distance from the camera to the sharp plane",
                )?;
                Ok(Some(f as f32))
            }),
            Ok(None) => Ok(None),
            Err(f) => Err(f),
        };
        let shutter = self.shutter(b.shutter);
        let (Ok((from, fs)), Ok((at, ats))) = (from, at) else {
            return;
        };
        // Relative to where the camera is: at 1e8 a step of 1 is lost in f32.
        let (from32, at32) = (from.as_vec3().as_dvec3(), at.as_vec3().as_dvec3());
        let size = from32.length().max(at32.length());
        let gap = (at32 - from32).length();
        if gap.is_nan() || gap <= 1e-6 * size {
            let span = if ats.is_empty() { fs } else { ats };
            let _ = self.range(
                false,
                span,
                "the camera looks from and at the same point".into(),
                "`at` must differ from `from` by more than a millionth of their distance from the origin",
            );
            return;
        }
        if let Ok((up, us)) = up {
            let dir = (at - from).normalize();
            if up.length() < 1e-12 || up.normalize().cross(dir).length() < 1e-9 {
                let _ = self.range(
                    false,
                    us,
                    "`up` is zero or parallel to the view direction".into(),
                    "give an up direction not along `at - from`, e.g. (0, 1, 0)",
                );
                return;
            }
            self.scene.camera.up = up.as_vec3();
        }
        self.scene.camera.from = from.as_vec3();
        self.scene.camera.at = at.as_vec3();
        if let Ok(fov) = fov {
            self.scene.camera.vfov = fov as f32;
        }
        if let Ok(a) = aperture {
            self.scene.camera.aperture = a as f32;
        }
        if let Ok(f) = focus {
            self.scene.camera.focus_distance = f;
        }
        if let Ok(Some(s)) = shutter {
            self.scene.camera.shutter = s;
        }
    }

    fn shutter(
        &mut self,
        pair: Option<(&crate::lang::ast::Expr, &crate::lang::ast::Expr)>,
    ) -> Eval<Option<(f32, f32)>> {
        let Some((open, close)) = pair else {
            return Ok(None);
        };
        let o = self.expr(open).and_then(|v| self.num(&v, open.span));
        let c = self.expr(close).and_then(|v| self.num(&v, close.span));
        let (o, c) = (o?, c?);
        self.range(
            o <= c,
            open.span.to(close.span),
            format!("the shutter closes ({c}) before it opens ({o})"),
            "write `shutter OPEN CLOSE` with OPEN ≤ CLOSE",
        )?;
        Ok(Some((o as f32, c as f32)))
    }

    /// Refuses images whose pixels or samples would not fit.
    pub(super) fn finish_settings(&mut self) {
        let s = &self.scene.settings;
        let pixels = s.width as f64 * s.height as f64;
        let bytes = pixels * BYTES_PER_PIXEL;
        let samples = pixels * s.spp as f64;
        let span = self.size_span;
        if bytes > MAX_PIXEL_BYTES {
            let d = match span {
                Some(span) => {
                    Diagnostic::error(Code::TooLarge, span, "the image would not fit in memory")
                }
                None => Diagnostic::global(Code::TooLarge, "the image would not fit in memory"),
            };
            self.report(
                d.label(format!(
                    "needs about {:.1} GiB for pixels",
                    bytes / (1u64 << 30) as f64
                ))
                .help(format!(
                    "at most {:.0} GiB of pixels are allowed; lower the size",
                    MAX_PIXEL_BYTES / (1u64 << 30) as f64
                )),
            );
        } else if samples > MAX_SAMPLES {
            let span = self.samples_span.or(span);
            let message = format!(
                "{samples:.2e} samples in total is more than the {MAX_SAMPLES:.0e} allowed"
            );
            let d = match span {
                Some(span) => Diagnostic::error(Code::TooLarge, span, message),
                None => Diagnostic::global(Code::TooLarge, message),
            };
            self.report(
                d.label("too many samples")
                    .help("lower the size or the samples per pixel"),
            );
        } else {
            self.charge_film();
        }
    }
}
