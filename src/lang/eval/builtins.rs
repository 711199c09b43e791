//! Calls of built-in functions: checked against the signatures of
//! [`crate::lang::builtins::TABLE`], then evaluated through its entries; the
//! evaluators of colours, textures and materials the table points at.
//! The table imports this module's functions back (see the header of
//! [`crate::lang::builtins`] for why that circle is kept).

use crate::lang::codes::Code;
use std::rc::Rc;

use glam::DVec3;

use super::math;
use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{Arg, Expr, Ident};
use crate::lang::builtins::{Body, Builtin};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::names;
use crate::lang::pretty;
use crate::lang::source::Span;
use crate::scene::texture::CheckerSpace;
use crate::scene::{Encoding, Environment, Material, Texture};

/// Whether `name` is a built-in function.
pub fn is_function(name: &str) -> bool {
    crate::lang::builtins::get(name).is_some()
}

/// Evaluated arguments of one call.
pub(crate) struct Args {
    pub positional: Vec<(Value, Span)>,
    named: Vec<(String, Value, Span)>,
}

impl Args {
    /// Takes the keyword argument `name`, if given.
    pub fn keyword(&mut self, name: &str) -> Option<(Value, Span)> {
        let i = self.named.iter().position(|(n, _, _)| n == name)?;
        let (_, v, s) = self.named.swap_remove(i);
        Some((v, s))
    }
}

impl Evaluator {
    /// Checks a call against the signature of its built-in, which it returns.
    pub(super) fn check_call(
        &mut self,
        callee: &Ident,
        args: &[Arg],
        span: Span,
    ) -> Eval<&'static Builtin> {
        let Some(sig) = crate::lang::builtins::get(&callee.name) else {
            if let Some(fail) = self.not_a_function(callee, args) {
                return Err(fail);
            }
            let mut candidates: Vec<&str> = crate::lang::builtins::names().collect();
            candidates.extend(self.funcs.iter().map(|f| f.def.name.name.as_str()));
            let help = match names::suggest(&callee.name, candidates) {
                Some(s) => format!("did you mean `{s}`?"),
                None => "see docs/language.md for the built-in functions".to_string(),
            };
            return Err(self.report(
                Diagnostic::error(
                    Code::UnknownFunction,
                    callee.span,
                    format!("no function named `{}`", callee.name),
                )
                .label("unknown function")
                .help(help),
            ));
        };
        if let Some(d) = misnamed_positional(callee, sig, args) {
            return Err(self.report(d));
        }
        let mut failed = false;
        let positional = args.iter().filter(|a| a.name.is_none()).count();
        if positional < sig.min || positional > sig.max {
            let want = if sig.min == sig.max {
                format!("{}", sig.min)
            } else {
                format!("{} to {}", sig.min, sig.max)
            };
            self.report(
                Diagnostic::error(
                    Code::Arity,
                    span,
                    format!(
                        "`{}` takes {want} positional argument{}, {positional} given",
                        callee.name,
                        if sig.max == 1 { "" } else { "s" }
                    ),
                )
                .label("wrong number of arguments")
                .help(extra_as_keywords(callee, sig, args)),
            );
            failed = true;
        }
        let mut seen_named = false;
        let mut names_seen: Vec<&str> = Vec::new();
        for arg in args {
            match &arg.name {
                None if seen_named => {
                    self.report(positional_after_keyword(arg.value.span));
                    failed = true;
                }
                None => {}
                Some(name) => {
                    seen_named = true;
                    if !sig.keywords.contains(&name.name.as_str()) {
                        let help = match names::suggest(&name.name, sig.keywords.iter().copied()) {
                            Some(s) => format!("did you mean `{s}`? usage: {}", sig.usage),
                            None => format!("usage: {}", sig.usage),
                        };
                        self.report(
                            Diagnostic::error(
                                Code::UnknownArgument,
                                name.span,
                                format!("`{}` has no argument named `{}`", callee.name, name.name),
                            )
                            .label("unknown argument")
                            .help(help),
                        );
                        failed = true;
                    } else if names_seen.contains(&name.name.as_str()) {
                        self.report(
                            Diagnostic::error(
                                Code::Duplicate,
                                name.span,
                                format!("argument `{}` given twice", name.name),
                            )
                            .label("again")
                            .help("give each argument once"),
                        );
                        failed = true;
                    }
                    names_seen.push(&name.name);
                }
            }
        }
        if failed {
            Err(Fail)
        } else {
            Ok(sig)
        }
    }

    /// Evaluates a call of a built-in function.
    pub(super) fn call(&mut self, callee: &Ident, args: &[Arg], span: Span) -> Eval<Value> {
        if let Some(&index) = self.func_index.get(&callee.name) {
            return self.user_call(index, args, span);
        }
        let sig = self.check_call(callee, args, span).inspect_err(|_| {
            self.mark_used(args);
        })?;
        let mut positional = Vec::new();
        let mut named = Vec::new();
        let mut failed = false;
        for arg in args {
            match self.expr(&arg.value) {
                Ok(v) => match &arg.name {
                    None => positional.push((v, arg.value.span)),
                    Some(n) => named.push((n.name.clone(), v, arg.value.span)),
                },
                Err(_) => failed = true,
            }
        }
        if failed {
            return Err(Fail);
        }
        let mut a = Args { positional, named };
        self.apply(sig.body, &mut a, span)
    }

    fn nums(&mut self, a: &Args) -> Eval<Vec<f64>> {
        let results: Vec<Eval<f64>> = a.positional.iter().map(|(v, s)| self.num(v, *s)).collect();
        results.into_iter().collect()
    }

    /// Evaluates a checked call through its entry of the table.
    fn apply(&mut self, body: Body, a: &mut Args, span: Span) -> Eval<Value> {
        let r = match body {
            Body::Num1(f) => {
                let x = self.nums(a)?[0];
                math::apply1(f, x).and_then(super::value::finite)
            }
            Body::Num2(f) => {
                let x = self.nums(a)?;
                super::value::finite(math::apply2(f, x[0], x[1]))
            }
            Body::Num3(f) => {
                let x = self.nums(a)?;
                super::value::finite(math::apply3(f, x[0], x[1], x[2]))
            }
            Body::Call(f) => return f(self, a, span),
        };
        self.at(span, r).map(Value::Num)
    }

    pub(crate) fn random_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        Ok(Value::Num(math::random(self.nums(a)?[0])))
    }

    pub(crate) fn keyframes_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (xv, xs) = a.positional[0].clone();
        let x = self.num(&xv, xs)?;
        let (list, ls) = a.positional[1].clone();
        let keys = self.keys(&list, ls)?;
        let smooth = self.keyword_bool(a, "smooth", false)?;
        Ok(Value::Num(math::keyframes(&keys, x, smooth)))
    }

    pub(crate) fn rgb_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let x = self.nums(a)?;
        let c = DVec3::new(x[0], x[1], x[2]);
        self.color(&Value::Vec3(c), span).map(Value::Vec3)
    }

    pub(crate) fn hex_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (v, s) = a.positional[0].clone();
        let text = self.string(&v, s)?;
        let r = super::exprs::hex_color(&text);
        self.at(s, r).map(Value::Vec3)
    }

    pub(crate) fn gradient_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (b, bs) = a.positional[0].clone();
        let (t, ts) = a.positional[1].clone();
        let bottom = self.color(&b, bs);
        let top = self.color(&t, ts);
        Ok(Value::Gradient(bottom?, top?))
    }

    pub(crate) fn environment_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (v, s) = a.positional[0].clone();
        let path = self.string(&v, s);
        let (rotate, rs) = self.keyword_num(a, "rotate", 0.0)?;
        self.range(
            rotate.is_finite(),
            rs,
            format!("the rotation must be a finite angle, not {rotate}"),
            "the rotation is in degrees about +y, e.g. `rotate: 90`",
        )?;
        let (strength, ss) = self.keyword_num(a, "strength", 1.0)?;
        self.range(
            strength.is_finite() && strength >= 0.0,
            ss,
            format!("the strength must be at least 0 and finite, not {strength}"),
            "the strength scales the image's radiance, e.g. `strength: 1.5`",
        )?;
        let image = self.environment_image(&path?, s)?;
        Ok(Value::Environment(Rc::new(Environment {
            image,
            rotate: rotate as f32,
            strength: strength as f32,
        })))
    }

    fn keyword_bool(&mut self, a: &mut Args, name: &str, default: bool) -> Eval<bool> {
        match a.keyword(name) {
            Some((v, s)) => self.boolean(&v, s),
            None => Ok(default),
        }
    }

    pub(super) fn keyword_num(
        &mut self,
        a: &mut Args,
        name: &str,
        default: f64,
    ) -> Eval<(f64, Span)> {
        match a.keyword(name) {
            Some((v, s)) => Ok((self.num(&v, s)?, s)),
            None => Ok((default, Span::default())),
        }
    }

    /// A keyframe table: a list of `(time, value)` with increasing times.
    pub(super) fn keys(&mut self, list: &Value, span: Span) -> Eval<Vec<(f64, f64)>> {
        let Value::List(items) = list else {
            return Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    span,
                    format!("expected a list of keys, found {}", list.type_name()),
                )
                .help("write keys as `[(time, value), ...]`"),
            ));
        };
        let mut keys = Vec::with_capacity(items.len());
        for item in items.iter() {
            keys.push(self.vec2(item, span)?);
        }
        let sorted = keys.windows(2).all(|w| w[0].x < w[1].x);
        if keys.is_empty() || !sorted {
            return Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    span,
                    "keyframe times must be strictly increasing, with at least one key",
                )
                .label("bad key table")
                .help("sort the keys by time and remove repeated times"),
            ));
        }
        Ok(keys.iter().map(|k| (k.x, k.y)).collect())
    }

    fn positive(&mut self, x: f64, span: Span, what: &str, help: &str) -> Eval<f64> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    span,
                    format!("{what} must be positive, not {x}"),
                )
                .label("out of range")
                .help(help.to_string()),
            ))
        }
    }

    /// The texture of the first positional argument.
    fn first_texture(&mut self, a: &Args, span: Span) -> Eval<crate::scene::TextureId> {
        let (v, s) = a
            .positional
            .first()
            .cloned()
            .unwrap_or((Value::Num(0.0), span));
        self.texture(&v, s)
    }

    fn new_material(&mut self, m: Material) -> Value {
        Value::Material(self.scene.add_material(m))
    }

    pub(crate) fn solid_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (v, s) = a.positional[0].clone();
        let c = self.color(&v, s)?;
        Ok(Value::Texture(
            self.scene.add_texture(Texture::Solid(c.as_vec3())),
        ))
    }

    pub(crate) fn checker_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (even, es) = a.positional[0].clone();
        let (odd, os) = a.positional[1].clone();
        let even = self.texture(&even, es);
        let odd = self.texture(&odd, os);
        let (scale, ss) = self.keyword_num(a, "scale", 10.0)?;
        let scale = self.positive(
            scale,
            ss,
            "the checker scale",
            "the scale is the frequency of the squares, e.g. `scale: 10`",
        )?;
        let uv = self.keyword_bool(a, "uv", false)?;
        let space = if uv {
            CheckerSpace::Uv
        } else {
            CheckerSpace::Solid
        };
        Ok(Value::Texture(self.scene.add_texture(Texture::Checker {
            even: even?,
            odd: odd?,
            scale: scale as f32,
            space,
        })))
    }

    pub(crate) fn image_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (v, s) = a.positional[0].clone();
        let path = self.string(&v, s)?;
        let encoding = if self.keyword_bool(a, "raw", false)? {
            Encoding::Data
        } else {
            Encoding::Srgb
        };
        Ok(Value::Texture(self.image_texture(&path, s, encoding)?))
    }

    pub(crate) fn noise_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let (scale, ss) = self.keyword_num(a, "scale", 1.0)?;
        let scale = self.positive(
            scale,
            ss,
            "the noise scale",
            "the scale is the frequency of the noise, e.g. `scale: 4`",
        )?;
        let color = match a.keyword("color") {
            Some((v, s)) => self.color(&v, s)?,
            None => DVec3::ONE,
        };
        Ok(Value::Texture(self.scene.add_texture(Texture::Noise {
            scale: scale as f32,
            color: color.as_vec3(),
        })))
    }

    pub(crate) fn lambertian_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let albedo = self.first_texture(a, span)?;
        Ok(self.new_material(Material::Lambertian { albedo }))
    }

    pub(crate) fn metal_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let albedo = self.first_texture(a, span);
        let (fuzz, fs) = self.keyword_num(a, "fuzz", 0.0)?;
        if !(0.0..=1.0).contains(&fuzz) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    fs,
                    format!("fuzz must be in [0, 1], not {fuzz}"),
                )
                .label("out of range")
                .help("0 is a perfect mirror, 1 the roughest metal"),
            ));
        }
        Ok(self.new_material(Material::Metal {
            albedo: albedo?,
            fuzz: fuzz as f32,
        }))
    }

    pub(crate) fn dielectric_call(&mut self, a: &mut Args, _: Span) -> Eval<Value> {
        let ior = self.nums(a)?[0];
        let s = a.positional[0].1;
        let ior = self.positive(
            ior,
            s,
            "the index of refraction",
            "glass is about 1.5, water 1.33, air 1",
        )?;
        let alpha = self.roughness(a, "roughness", 0.0)?;
        Ok(self.new_material(if alpha > 0.0 {
            Material::RoughDielectric {
                ior: ior as f32,
                alpha,
            }
        } else {
            Material::Dielectric { ior: ior as f32 }
        }))
    }

    /// A GGX roughness keyword: finite and at least 0.
    fn roughness(&mut self, a: &mut Args, name: &str, default: f64) -> Eval<f32> {
        let (r, rs) = self.keyword_num(a, name, default)?;
        if r.is_finite() && r >= 0.0 {
            return Ok(r as f32);
        }
        Err(self.report(
            Diagnostic::error(
                Code::Range,
                rs,
                format!("{name} must be a finite number of at least 0, not {r}"),
            )
            .label("out of range")
            .help("roughness is the GGX α: 0 is smooth, 0.1 glossy, 1 very rough"),
        ))
    }

    /// A number keyword in [0, 1].
    fn unit_keyword(&mut self, a: &mut Args, name: &str, default: f64, help: &str) -> Eval<f32> {
        let (x, xs) = self.keyword_num(a, name, default)?;
        if (0.0..=1.0).contains(&x) {
            return Ok(x as f32);
        }
        Err(self.report(
            Diagnostic::error(
                Code::Range,
                xs,
                format!("{name} must be in [0, 1], not {x}"),
            )
            .label("out of range")
            .help(help.to_string()),
        ))
    }

    pub(crate) fn conductor_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let alpha = self.roughness(a, "roughness", 0.1);
        let (alpha_u, alpha_v) = match alpha {
            Ok(r) => (
                self.roughness(a, "roughness_u", r as f64),
                self.roughness(a, "roughness_v", r as f64),
            ),
            Err(e) => (Err(e), Err(e)),
        };
        let eta = a.keyword("eta");
        let k = a.keyword("k");
        let fresnel = match (a.positional.first().cloned(), eta, k) {
            (Some((Value::Str(name), s)), None, None) => self.conductor_preset(&name, s),
            (Some((v, s)), None, None) => self
                .texture(&v, s)
                .map(crate::scene::material::ConductorFresnel::Reflectance),
            (None, Some((e, es)), Some((k, ks))) => {
                let eta = self.color(&e, es);
                let k = self.color(&k, ks);
                let eta = eta?;
                match self.positive(
                    eta.min_element(),
                    es,
                    "each channel of eta",
                    "metals have η between about 0.1 and 3",
                ) {
                    Ok(_) => Ok(crate::scene::material::ConductorFresnel::Ior {
                        eta: eta.as_vec3(),
                        k: k?.as_vec3(),
                    }),
                    Err(e) => Err(e),
                }
            }
            (_, eta, k) => {
                let at = eta.or(k).map_or(span, |(_, s)| s);
                Err(self.report(
                    Diagnostic::error(
                        Code::Range,
                        at,
                        "a conductor takes either a name or colour, or both `eta` and `k`",
                    )
                    .label("ambiguous conductor")
                    .help("write conductor(\"Au\"), conductor(rgb(0.9, 0.6, 0.3)) or conductor(eta: rgb(..), k: rgb(..))"),
                ))
            }
        };
        Ok(self.new_material(Material::Conductor {
            fresnel: fresnel?,
            alpha: glam::Vec2::new(alpha_u?, alpha_v?),
        }))
    }

    /// The complex index of the named conductor.
    fn conductor_preset(
        &mut self,
        name: &str,
        span: Span,
    ) -> Eval<crate::scene::material::ConductorFresnel> {
        let presets = crate::scene::material::CONDUCTORS;
        if let Some(&(_, eta, k)) = presets.iter().find(|(n, _, _)| *n == name) {
            return Ok(crate::scene::material::ConductorFresnel::Ior { eta, k });
        }
        let names: Vec<&str> = presets.iter().map(|(n, _, _)| *n).collect();
        let help = match names::suggest(name, names.iter().copied()) {
            Some(s) => format!("did you mean \"{s}\"? known metals: {}", names.join(", ")),
            None => format!("known metals: {}", names.join(", ")),
        };
        Err(self.report(
            Diagnostic::error(Code::Range, span, format!("no conductor named \"{name}\""))
                .label("unknown metal")
                .help(help),
        ))
    }

    pub(crate) fn plastic_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let albedo = self.first_texture(a, span);
        let (ior, is) = self.keyword_num(a, "ior", 1.5)?;
        let ior = self.positive(
            ior,
            is,
            "the index of refraction",
            "varnish and plastics are about 1.5",
        );
        let alpha = self.roughness(a, "roughness", 0.1);
        Ok(self.new_material(Material::Plastic {
            albedo: albedo?,
            ior: ior? as f32,
            alpha: alpha?,
        }))
    }

    pub(crate) fn pbr_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let base = self.first_texture(a, span);
        let metallic = self.unit_keyword(a, "metallic", 0.0, "0 is a dielectric, 1 a metal");
        let roughness = self.unit_keyword(
            a,
            "roughness",
            0.5,
            "glTF's perceptual roughness: 0 is smooth, 1 fully rough (α = roughness²)",
        );
        let map = a
            .keyword("metallic_roughness")
            .map(|(v, s)| self.texture(&v, s));
        Ok(self.new_material(Material::MetalRough {
            base: base?,
            metallic: metallic?,
            roughness: roughness?,
            metallic_roughness: map.transpose()?,
        }))
    }

    pub(crate) fn light_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let emit = self.first_texture(a, span);
        let two_sided = self.keyword_bool(a, "two_sided", false)?;
        Ok(self.new_material(Material::Light {
            emit: emit?,
            two_sided,
        }))
    }

    pub(crate) fn isotropic_call(&mut self, a: &mut Args, span: Span) -> Eval<Value> {
        let albedo = self.first_texture(a, span)?;
        Ok(self.new_material(Material::Isotropic { albedo }))
    }

    /// `bezier [points]`: at least two `(radius, height)` points.
    pub(super) fn bezier(&mut self, points: &[crate::lang::ast::Expr], span: Span) -> Eval<Value> {
        let values = self.all(points)?;
        let mut pts = Vec::with_capacity(values.len());
        for (v, e) in values.iter().zip(points) {
            pts.push(self.vec2(v, e.span)?);
        }
        if pts.len() < 2 {
            return Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    span,
                    format!(
                        "a Bézier curve needs at least 2 control points, found {}",
                        pts.len()
                    ),
                )
                .label("too few points")
                .help("give the curve's control points as `bezier [(r0, h0), (r1, h1), ...]`"),
            ));
        }
        if pts.iter().all(|p| *p == pts[0]) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Degenerate,
                    span,
                    "all control points of the curve coincide",
                )
                .label("a single point")
                .help("the profile needs at least two distinct points"),
            ));
        }
        Ok(Value::Curve(Rc::new(crate::scene::Bezier {
            points: pts.iter().map(|p| p.as_vec2()).collect(),
        })))
    }
}

/// "`ior` is positional" when a keyword argument names one of the
/// built-in's positional parameters (as in `dielectric(ior: 1.5)`), with
/// the call written without that name as the help.
fn misnamed_positional(callee: &Ident, sig: &Builtin, args: &[Arg]) -> Option<Diagnostic> {
    let params = sig.usage.split_once('(')?.1.trim_end_matches(')');
    let positional: Vec<&str> = params
        .split(',')
        .map(str::trim)
        .filter(|p| !p.contains(':'))
        .collect();
    let name = args.iter().find_map(|a| {
        a.name
            .as_ref()
            .filter(|n| !sig.keywords.contains(&n.name.as_str()))
            .filter(|n| positional.contains(&n.name.as_str()))
    })?;
    let fixed: Vec<String> = args
        .iter()
        .map(|a| match &a.name {
            Some(n) if positional.contains(&n.name.as_str()) => pretty::expr(&a.value),
            Some(n) => format!("{}: {}", n.name, pretty::expr(&a.value)),
            None => pretty::expr(&a.value),
        })
        .collect();
    Some(
        Diagnostic::error(
            Code::UnknownArgument,
            name.span,
            format!(
                "`{}` is a positional argument of `{}`, not a keyword",
                name.name, callee.name
            ),
        )
        .label("give it without the name")
        .help(format!(
            "write `{}({})`; usage: {}",
            callee.name,
            fixed.join(", "),
            sig.usage
        )),
    )
}

/// The help of a call with too many positional arguments: when the
/// built-in takes keyword arguments, the extra values written with their
/// names in order (`metal(c, 0.3)` → `metal(c, fuzz: 0.3)`).
fn extra_as_keywords(callee: &Ident, sig: &Builtin, args: &[Arg]) -> String {
    let usage = format!("usage: {}", sig.usage);
    let values: Vec<&Expr> = args
        .iter()
        .filter(|a| a.name.is_none())
        .map(|a| &a.value)
        .collect();
    let extra = values.len().saturating_sub(sig.max);
    let named = args.iter().any(|a| a.name.is_some());
    if extra == 0 || extra > sig.keywords.len() || named {
        return usage;
    }
    let fixed: Vec<String> = values
        .iter()
        .enumerate()
        .map(|(i, v)| match i.checked_sub(sig.max) {
            Some(k) => format!("{}: {}", sig.keywords[k], pretty::expr(v)),
            None => pretty::expr(v),
        })
        .collect();
    format!(
        "give the extra argument{} by name: `{}({})`; {usage}",
        if extra == 1 { "" } else { "s" },
        callee.name,
        fixed.join(", ")
    )
}

/// The error of a positional argument written after a keyword argument, in
/// a call of a built-in or of a user function.
pub(super) fn positional_after_keyword(span: Span) -> Diagnostic {
    Diagnostic::error(
        Code::ArgumentOrder,
        span,
        "a positional argument after a keyword argument",
    )
    .label("positional")
    .help("put positional arguments first")
}
