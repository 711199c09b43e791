//! The material wrappers that tilt a material's shading normal: a
//! tangent-space normal map (`normal_map`) and a height field (`bump`),
//! with their checks: the wrapped material scatters (no light or medium
//! phase function, no wrapper of a wrapper), a normal map is read as
//! data, and the strength or scale is a finite number ≥ 0.

use super::{Args, Eval, Evaluator, Value};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::{Material, MaterialId, Texture, TextureId};

impl Evaluator {
    /// `normal_map(material, image("n.png", raw: true), strength: 1)`.
    pub(crate) fn normal_map_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let base = self.mapped_base(a);
        let map = self.map_texture(a);
        let strength = self.map_factor(a, "strength", "the normal map's strength");
        let (base, map, strength) = (base?, map?, strength?);
        Ok(Value::Material(self.scene.add_material(
            Material::NormalMap {
                base,
                map,
                strength,
            },
        )))
    }

    /// `bump(material, texture, scale: 1)`.
    pub(crate) fn bump_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let base = self.mapped_base(a);
        let (v, s) = a.positional[1].clone();
        let height = self.texture(&v, s);
        let scale = self.map_factor(a, "scale", "the bump scale");
        let (base, height, scale) = (base?, height?, scale?);
        Ok(Value::Material(self.scene.add_material(Material::Bump {
            base,
            height,
            scale,
        })))
    }

    /// The material a map wraps: one that scatters at a surface.
    fn mapped_base(&mut self, a: &Args) -> Eval<MaterialId> {
        let (v, s) = a.positional[0].clone();
        let id = self.material(&v, s)?;
        let refused = match self.scene.material(id) {
            Material::Light { .. } => Some("a light"),
            Material::Isotropic { .. } => Some("a medium's phase function"),
            Material::NormalMap { .. } | Material::Bump { .. } => Some("a mapped material"),
            _ => None,
        };
        match refused {
            None => Ok(id),
            Some(what) => Err(self.report(
                Diagnostic::error(Code::Type, s, format!("{what} cannot be mapped"))
                    .label("this material")
                    .help(
                        "map a material that scatters at a surface (any but a light or \
                         `isotropic`), with at most one map",
                    ),
            )),
        }
    }

    /// A normal map's texture: an image read as data, or any other texture
    /// (whose colour is then taken as the encoded normal).
    fn map_texture(&mut self, a: &Args) -> Eval<TextureId> {
        let (v, s) = a.positional[1].clone();
        let id = self.texture(&v, s)?;
        if !self.dry && matches!(self.scene.texture(id), Texture::Image(_)) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    s,
                    "a normal map must be read as data, not as an sRGB colour",
                )
                .label("an image decoded as colour")
                .help("read it with `image(\"file.png\", raw: true)`"),
            ));
        }
        Ok(id)
    }

    /// The keyword `name` (default 1): a finite number ≥ 0.
    fn map_factor(&mut self, a: &mut Args, name: &str, what: &str) -> Eval<f32> {
        let (x, s) = self.keyword_num(a, name, 1.0)?;
        if (0.0..=1e6).contains(&x) {
            return Ok(x as f32);
        }
        Err(self.report(
            Diagnostic::error(
                Code::Range,
                s,
                format!("{what} must be in [0, 1e6], not {x}"),
            )
            .label("out of range")
            .help("0 leaves the material's normal as it is, 1 applies the map as stored"),
        ))
    }
}
