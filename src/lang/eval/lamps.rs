//! The lights that are not shapes: `sun`, `point_light` and `spot_light`
//! blocks, checked and made into [`Lamp`] nodes.

use glam::{DVec3, Vec3};

use super::props::Block;
use super::{Eval, Evaluator};
use crate::lang::ast::Object;
use crate::lang::properties::{point_light, spot_light, sun, Prop};
use crate::scene::{Lamp, Node};

impl Evaluator {
    /// A colour property with a default of white.
    fn lamp_color(&mut self, b: &Block, key: &Prop) -> Eval<Vec3> {
        match self.prop(b, key)? {
            Some((v, s)) => Ok(self.color(&v, s)?.as_vec3()),
            None => Ok(Vec3::ONE),
        }
    }

    /// An angle property in degrees within `[lo, hi]` (`lo` itself only
    /// if `lo_ok`).
    fn lamp_angle(
        &mut self,
        b: &Block,
        key: &Prop,
        default: f64,
        (lo, lo_ok, hi): (f64, bool, f64),
        help: &str,
    ) -> Eval<f64> {
        let (d, s) = self.prop_num(b, key, default)?;
        let ok = (d > lo || (lo_ok && d == lo)) && d <= hi;
        let open = if lo_ok { "from" } else { "above" };
        self.range(
            ok,
            s,
            format!(
                "the {} must be {open} {lo} up to {hi} degrees, not {d}",
                key.name
            ),
            help,
        )?;
        Ok(d)
    }

    pub(super) fn sun(&mut self, b: &Block) -> Eval<Node> {
        let (direction, ds) = self.prop_vec3(b, &sun::DIRECTION, DVec3::Y)?;
        self.range(
            direction != DVec3::ZERO && direction.is_finite(),
            ds,
            "the direction towards the sun cannot be zero".into(),
            "give a vector pointing at the sun, e.g. `direction (1, 2, 1)`",
        )?;
        let irradiance = self.lamp_color(b, &sun::COLOR)?;
        let diameter = self.lamp_angle(
            b,
            &sun::DIAMETER,
            0.0,
            (0.0, true, 90.0),
            "the real sun is about 0.53 degrees across; 0 makes sharp shadows",
        )?;
        Ok(Node::Lamp(Lamp::Sun {
            direction: direction.as_vec3(),
            irradiance,
            diameter: diameter.to_radians() as f32,
        }))
    }

    pub(super) fn point_light(&mut self, b: &Block) -> Eval<Node> {
        let (at, _) = self.prop_vec3(b, &point_light::AT, DVec3::ZERO)?;
        let intensity = self.lamp_color(b, &point_light::INTENSITY)?;
        Ok(Node::Lamp(Lamp::Point {
            at: at.as_vec3(),
            intensity,
        }))
    }

    pub(super) fn spot_light(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        let (at, _) = self.prop_vec3(b, &spot_light::AT, DVec3::ZERO)?;
        let (to, ts) = self.prop_vec3(b, &spot_light::TO, at - DVec3::Y)?;
        let span = if ts == Default::default() { o.head } else { ts };
        self.range(
            to != at,
            span,
            "the spot light's `to` is its own position".into(),
            "`to` is a point the light shines towards, away from `at`",
        )?;
        let intensity = self.lamp_color(b, &spot_light::INTENSITY)?;
        let cutoff = self.lamp_angle(
            b,
            &spot_light::ANGLE,
            30.0,
            (0.0, false, 180.0),
            "the angle is the cone's half angle, e.g. `angle 30`",
        )?;
        let beam = self.lamp_angle(
            b,
            &spot_light::FALLOFF,
            0.75 * cutoff,
            (0.0, true, cutoff),
            "the falloff is the half angle of full light, at most `angle`, e.g. `falloff 25`",
        )?;
        Ok(Node::Lamp(Lamp::Spot {
            at: at.as_vec3(),
            to: to.as_vec3(),
            intensity,
            cutoff: cutoff.to_radians() as f32,
            beam: beam.to_radians() as f32,
        }))
    }
}
