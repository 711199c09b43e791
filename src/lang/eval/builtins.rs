//! Calls of built-in functions: checked against the signatures of
//! [`crate::lang::builtins::TABLE`] before the call, then numeric
//! functions, colours, textures and materials.

use crate::lang::codes::Code;
use std::rc::Rc;

use glam::DVec3;

use super::math;
use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{Arg, Ident};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::names;
use crate::lang::source::Span;
use crate::scene::texture::CheckerSpace;
use crate::scene::{Material, Texture};

/// Whether `name` is a built-in function.
pub fn is_function(name: &str) -> bool {
    crate::lang::builtins::get(name).is_some()
}

/// Evaluated arguments of one call.
pub(super) struct Args {
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
    /// Checks a call against its signature; `None` when `name` is no function.
    pub(super) fn check_call(&mut self, callee: &Ident, args: &[Arg], span: Span) -> Eval<()> {
        let Some(sig) = crate::lang::builtins::get(&callee.name) else {
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
                .help(format!("usage: {}", sig.usage)),
            );
            failed = true;
        }
        let mut seen_named = false;
        let mut names_seen: Vec<&str> = Vec::new();
        for arg in args {
            match &arg.name {
                None if seen_named => {
                    self.report(
                        Diagnostic::error(
                            Code::ArgumentOrder,
                            arg.value.span,
                            "a positional argument after a keyword argument",
                        )
                        .label("positional")
                        .help("put positional arguments first"),
                    );
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
            Ok(())
        }
    }

    /// Evaluates a call of a built-in function.
    pub(super) fn call(&mut self, callee: &Ident, args: &[Arg], span: Span) -> Eval<Value> {
        if let Some(&index) = self.func_index.get(&callee.name) {
            return self.user_call(index, args, span);
        }
        self.check_call(callee, args, span)?;
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
        self.apply(&callee.name, &mut a, span)
    }

    fn nums(&mut self, a: &Args) -> Eval<Vec<f64>> {
        let results: Vec<Eval<f64>> = a.positional.iter().map(|(v, s)| self.num(v, *s)).collect();
        results.into_iter().collect()
    }

    fn apply(&mut self, name: &str, a: &mut Args, span: Span) -> Eval<Value> {
        if let Some(f) = math::fn1(name) {
            let x = self.nums(a)?[0];
            let r = math::apply1(f, x).and_then(super::value::finite);
            return self.at(span, r).map(Value::Num);
        }
        if let Some(f) = math::fn2(name) {
            let x = self.nums(a)?;
            let r = super::value::finite(math::apply2(f, x[0], x[1]));
            return self.at(span, r).map(Value::Num);
        }
        if let Some(f) = math::fn3(name) {
            let x = self.nums(a)?;
            let r = super::value::finite(math::apply3(f, x[0], x[1], x[2]));
            return self.at(span, r).map(Value::Num);
        }
        match name {
            "random" => Ok(Value::Num(math::random(self.nums(a)?[0]))),
            "keyframes" => {
                let (xv, xs) = a.positional[0].clone();
                let x = self.num(&xv, xs)?;
                let (list, ls) = a.positional[1].clone();
                let keys = self.keys(&list, ls)?;
                let smooth = self.keyword_bool(a, "smooth", false)?;
                Ok(Value::Num(math::keyframes(&keys, x, smooth)))
            }
            "rgb" => {
                let x = self.nums(a)?;
                let c = DVec3::new(x[0], x[1], x[2]);
                self.color(&Value::Vec3(c), span).map(Value::Vec3)
            }
            "hex" => {
                let (v, s) = a.positional[0].clone();
                let text = self.string(&v, s)?;
                let r = super::exprs::hex_color(&text);
                self.at(s, r).map(Value::Vec3)
            }
            "gradient" => {
                let (b, bs) = a.positional[0].clone();
                let (t, ts) = a.positional[1].clone();
                let bottom = self.color(&b, bs);
                let top = self.color(&t, ts);
                Ok(Value::Gradient(bottom?, top?))
            }
            _ => self.texture_or_material(name, a, span),
        }
    }

    fn keyword_bool(&mut self, a: &mut Args, name: &str, default: bool) -> Eval<bool> {
        match a.keyword(name) {
            Some((v, s)) => self.boolean(&v, s),
            None => Ok(default),
        }
    }

    fn keyword_num(&mut self, a: &mut Args, name: &str, default: f64) -> Eval<(f64, Span)> {
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

    fn texture_or_material(&mut self, name: &str, a: &mut Args, span: Span) -> Eval<Value> {
        let first = a.positional.first().cloned();
        let first_tex = |ev: &mut Evaluator| {
            let (v, s) = first.clone().unwrap_or((Value::Num(0.0), span));
            ev.texture(&v, s)
        };
        Ok(match name {
            "solid" => {
                let (v, s) = a.positional[0].clone();
                let c = self.color(&v, s)?;
                Value::Texture(self.scene.add_texture(Texture::Solid(c.as_vec3())))
            }
            "checker" => {
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
                Value::Texture(self.scene.add_texture(Texture::Checker {
                    even: even?,
                    odd: odd?,
                    scale: scale as f32,
                    space,
                }))
            }
            "image" => {
                let (v, s) = a.positional[0].clone();
                let path = self.string(&v, s)?;
                Value::Texture(self.image_texture(&path, s)?)
            }
            "noise" => {
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
                Value::Texture(self.scene.add_texture(Texture::Noise {
                    scale: scale as f32,
                    color: color.as_vec3(),
                }))
            }
            "lambertian" => {
                let albedo = first_tex(self)?;
                Value::Material(self.scene.add_material(Material::Lambertian { albedo }))
            }
            "metal" => {
                let albedo = first_tex(self);
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
                Value::Material(self.scene.add_material(Material::Metal {
                    albedo: albedo?,
                    fuzz: fuzz as f32,
                }))
            }
            "dielectric" => {
                let ior = self.nums(a)?[0];
                let s = a.positional[0].1;
                let ior = self.positive(
                    ior,
                    s,
                    "the index of refraction",
                    "glass is about 1.5, water 1.33, air 1",
                )?;
                Value::Material(
                    self.scene
                        .add_material(Material::Dielectric { ior: ior as f32 }),
                )
            }
            "light" => {
                let emit = first_tex(self);
                let two_sided = self.keyword_bool(a, "two_sided", false)?;
                Value::Material(self.scene.add_material(Material::Light {
                    emit: emit?,
                    two_sided,
                }))
            }
            _ => {
                let albedo = first_tex(self)?;
                Value::Material(self.scene.add_material(Material::Isotropic { albedo }))
            }
        })
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
