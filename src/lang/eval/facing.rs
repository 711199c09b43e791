//! The warning for a one-sided light that faces away from every other
//! surface (found by [`crate::scene::facing`] on the evaluated scene): the
//! picture would be black but for the light itself.

use super::Evaluator;
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::scene::facing::lights_facing_away;

impl Evaluator {
    /// Warns at each top-level statement holding such a light; only on a
    /// scene without errors (whose objects are all there).
    pub(super) fn check_light_facing(&mut self) {
        if self.diagnostics.iter().any(|d| d.is_error()) {
            return;
        }
        for i in lights_facing_away(&self.scene) {
            self.diagnostics.push(
                Diagnostic::warning(
                    Code::LightFacingAway,
                    self.object_spans[i],
                    "this one-sided light faces away from every other surface",
                )
                .label("lights nothing")
                .help(
                    "a light emits from its front face only: turn it (for a rect, `flip` \
                     makes it emit toward -axis), or give it `light(..., two_sided: true)`",
                ),
            );
        }
    }
}
