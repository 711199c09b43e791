//! Typed views of values, each reporting a type error at the given span:
//! numbers, integers, vectors, colours, textures, materials, strings.

use crate::lang::codes::Code;
use glam::{DVec2, DVec3};

use super::value::Value;
use super::{Eval, Evaluator};
use crate::lang::diagnostics::Diagnostic;
use crate::scene::{Material, MaterialId, Texture, TextureId};

impl Evaluator {
    fn type_error(
        &mut self,
        span: crate::lang::source::Span,
        want: &str,
        got: &Value,
        help: &str,
    ) -> super::Fail {
        self.report(
            Diagnostic::error(
                Code::Type,
                span,
                format!("expected {want}, found {}", got.type_name()),
            )
            .label(format!("this is {}", got.type_name()))
            .help(help.to_string()),
        )
    }

    /// A number.
    pub(super) fn num(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<f64> {
        match v {
            Value::Num(x) => Ok(*x),
            _ => Err(self.type_error(span, "a number", v, "write a number such as `1` or `0.5`")),
        }
    }

    /// A non-negative whole number that fits in a `u32`.
    pub(super) fn count(
        &mut self,
        v: &Value,
        span: crate::lang::source::Span,
        what: &str,
    ) -> Eval<u32> {
        let x = self.num(v, span)?;
        if x.fract() != 0.0 || !(0.0..=u32::MAX as f64).contains(&x) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    span,
                    format!("{what} must be a whole number ≥ 0, not {x}"),
                )
                .label("not a whole number")
                .help(format!("write {what} as a whole number such as `64`")),
            ));
        }
        Ok(x as u32)
    }

    /// A 3-vector.
    pub(super) fn vec3(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<DVec3> {
        match v {
            Value::Vec3(x) => Ok(*x),
            _ => Err(self.type_error(span, "a 3-vector", v, "write a vector as `(x, y, z)`")),
        }
    }

    /// A 2-vector.
    pub(super) fn vec2(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<DVec2> {
        match v {
            Value::Vec2(x) => Ok(*x),
            _ => Err(self.type_error(span, "a 2-vector", v, "write a 2-vector as `(a, b)`")),
        }
    }

    /// A colour: a 3-vector with no negative channel.
    pub(super) fn color(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<DVec3> {
        let c = match v {
            Value::Vec3(x) => *x,
            _ => {
                return Err(self.type_error(
                    span,
                    "a colour",
                    v,
                    "write a colour as `rgb(r, g, b)`, `#rrggbb` or `(r, g, b)`",
                ))
            }
        };
        if c.min_element() < 0.0 {
            return Err(self.report(
                Diagnostic::error(Code::Range, span, "a colour channel is negative")
                    .label(format!("({}, {}, {})", c.x, c.y, c.z))
                    .help("colour channels are linear values ≥ 0"),
            ));
        }
        Ok(c)
    }

    /// A texture; a colour becomes a solid texture.
    pub(super) fn texture(
        &mut self,
        v: &Value,
        span: crate::lang::source::Span,
    ) -> Eval<TextureId> {
        match v {
            Value::Texture(id) => Ok(*id),
            Value::Vec3(_) => {
                let c = self.color(v, span)?;
                Ok(self.scene.add_texture(Texture::Solid(c.as_vec3())))
            }
            _ => Err(self.type_error(
                span,
                "a colour or a texture",
                v,
                "use `rgb(...)`, `checker(...)`, `image(...)` or `noise(...)`",
            )),
        }
    }

    /// A material.
    pub(super) fn material(
        &mut self,
        v: &Value,
        span: crate::lang::source::Span,
    ) -> Eval<MaterialId> {
        match v {
            Value::Material(id) => Ok(*id),
            Value::Vec3(_) | Value::Texture(_) => Err(self.type_error(
                span,
                "a material",
                v,
                "wrap it in a material, e.g. `lambertian(...)`",
            )),
            _ => Err(self.type_error(
                span,
                "a material",
                v,
                "use `lambertian`, `metal`, `dielectric`, `light` or `isotropic`",
            )),
        }
    }

    /// A string.
    pub(super) fn string(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<String> {
        match v {
            Value::Str(s) => Ok(s.to_string()),
            _ => Err(self.type_error(span, "a string", v, "write a string in double quotes")),
        }
    }

    /// A boolean.
    pub(super) fn boolean(&mut self, v: &Value, span: crate::lang::source::Span) -> Eval<bool> {
        match v {
            Value::Bool(b) => Ok(*b),
            _ => Err(self.type_error(span, "`true` or `false`", v, "write `true` or `false`")),
        }
    }

    /// The grey diffuse material used when an object names none.
    pub(super) fn default_material(&mut self) -> MaterialId {
        if let Some(id) = self.default_material {
            return id;
        }
        let albedo = self
            .scene
            .add_texture(Texture::Solid(glam::Vec3::splat(0.73)));
        let id = self.scene.add_material(Material::Lambertian { albedo });
        self.default_material = Some(id);
        id
    }
}
