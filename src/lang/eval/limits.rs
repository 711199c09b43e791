//! The coordinate limit, checked once the whole file is read (the shutter
//! that motion sweeps over may come last): every top-level object and the
//! camera stay within ±`MAX_COORDINATE` of the origin, where the renderer's
//! f32 squared distances cannot overflow. It runs only on a file without
//! other errors: a motion that is not finite, or a triangle corner past the
//! limit, already has its own diagnostic at a narrower span.

use super::Evaluator;
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::object::MAX_COORDINATE;
use crate::scene::reach::Reach;

const HELP: &str = "rtlang traces rays in f32, whose squared distances overflow beyond about \
                    1.8e19, and an object out there would vanish from the picture; keep the \
                    scene within ±1e18 of the origin (scale the whole scene down)";

impl Evaluator {
    pub(super) fn check_limits(&mut self) {
        if self.diagnostics.iter().any(|d| d.is_error()) {
            return;
        }
        let limit = f64::from(MAX_COORDINATE);
        let mut reach = Reach::new(&self.scene, self.scene.camera.shutter);
        let far: Vec<(f64, usize)> = self
            .scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, node)| (reach.of(node), i))
            .filter(|(r, _)| *r > limit)
            .collect();
        for (r, i) in far {
            self.too_far(self.object_spans[i], "this object reaches", r);
        }
        let cam = &self.scene.camera;
        let away = cam.from.as_dvec3().length().max(cam.at.as_dvec3().length());
        if let (Some(span), true) = (self.camera_seen, away > limit) {
            self.too_far(span, "the camera is", away);
        }
    }

    /// The error for `what` (a sentence's start) at `distance` from the origin.
    fn too_far(&mut self, span: Span, what: &str, distance: f64) {
        let distance = if distance.is_finite() {
            format!("{distance:.1e}")
        } else {
            "farther than f32 can say".to_string()
        };
        self.diagnostics.push(
            Diagnostic::error(
                Code::Range,
                span,
                format!(
                    "{what} {distance} from the origin, beyond the coordinate limit \
                     ±{MAX_COORDINATE:e}"
                ),
            )
            .label("too far from the origin")
            .help(HELP.to_string()),
        );
    }
}
