//! The statements of one block sorted by role: named properties (checked
//! against the names the block accepts, like pbrt's unused-parameter
//! check), transforms in order, child objects, and the `size` / `shutter`
//! forms, with typed property getters.

use crate::lang::codes::Code;
use glam::{DVec2, DVec3};

use super::value::Value;
use super::{Eval, Evaluator};
use crate::lang::ast::{Expr, Ident, Stmt};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::names;
use crate::lang::properties::{Prop, Props};
use crate::lang::source::Span;

/// What a block may contain.
pub(super) struct Allow {
    pub what: &'static str,
    /// The named properties, declared in [`crate::lang::properties`].
    pub props: &'static [Prop],
    pub transforms: bool,
    pub children: bool,
    pub size: bool,
    pub shutter: bool,
}

impl Allow {
    /// A block with the declared `props` and no children or special forms.
    pub(super) fn props(props: &'static Props, transforms: bool) -> Allow {
        Allow {
            what: props.block,
            props: props.props,
            transforms,
            children: false,
            size: false,
            shutter: false,
        }
    }

    /// A block that takes transforms and nothing else (`place`, `motion`).
    pub(super) fn transforms_only(what: &'static str) -> Allow {
        Allow {
            what,
            props: &[],
            transforms: true,
            children: false,
            size: false,
            shutter: false,
        }
    }
}

/// A block's statements sorted by role.
#[derive(Default)]
pub(super) struct Block<'a> {
    props: Vec<(&'a Ident, &'a Expr)>,
    /// Transform and motion statements, in the order written.
    pub transforms: Vec<&'a Stmt>,
    /// Objects and placements.
    pub children: Vec<&'a Stmt>,
    pub size: Option<(&'a Expr, &'a Expr)>,
    pub shutter: Option<(&'a Expr, &'a Expr)>,
    /// `flip` was given: swap the object's front and back faces.
    pub flip: bool,
}

impl Block<'_> {
    /// The expression of property `key`, if present.
    pub fn get(&self, key: &Prop) -> Option<&Expr> {
        self.props
            .iter()
            .find(|(n, _)| n.name == key.name)
            .map(|(_, e)| *e)
    }
}

impl Evaluator {
    /// Sorts `body`, reporting unknown, duplicate and misplaced statements.
    pub(super) fn block<'a>(&mut self, body: &'a [Stmt], allow: &Allow) -> Block<'a> {
        let mut block = Block::default();
        for stmt in body {
            match stmt {
                Stmt::Property { name, value, .. } => {
                    if !allow.props.iter().any(|p| p.name == name.name) {
                        self.unknown_property(name, allow);
                    } else if let Some((first, _)) =
                        block.props.iter().find(|(n, _)| n.name == name.name)
                    {
                        let first = first.span;
                        self.report(
                            Diagnostic::error(
                                Code::Duplicate,
                                name.span,
                                format!("`{}` is given twice", name.name),
                            )
                            .label("second time")
                            .related(first, "first time")
                            .help("give each property once"),
                        );
                    } else {
                        block.props.push((name, value));
                    }
                }
                Stmt::Flip { .. } if allow.transforms => block.flip = true,
                Stmt::Transform(_) | Stmt::Motion { .. } if allow.transforms => {
                    block.transforms.push(stmt)
                }
                Stmt::Object(_) | Stmt::Place { .. } | Stmt::If { .. } if allow.children => {
                    block.children.push(stmt)
                }
                Stmt::Size { width, height, .. } if allow.size && block.size.is_none() => {
                    block.size = Some((width, height))
                }
                Stmt::Shutter { open, close, .. } if allow.shutter && block.shutter.is_none() => {
                    block.shutter = Some((open, close))
                }
                other => self.misplaced(other, allow),
            }
        }
        block
    }

    fn unknown_property(&mut self, name: &Ident, allow: &Allow) {
        let mut known: Vec<&str> = allow.props.iter().map(|p| p.name).collect();
        if allow.size {
            known.push("size");
        }
        if allow.shutter {
            known.push("shutter");
        }
        let is_material = known.contains(&"material")
            && crate::lang::properties::MATERIAL_ALIASES.contains(&name.name.as_str());
        let special = if is_material {
            Some("the surface is set with `material`, e.g. `material lambertian(rgb(1, 0, 0))`")
        } else if name.name == "size" && allow.size {
            Some("write the image size as `size WIDTH x HEIGHT`, e.g. `size 800 x 600`")
        } else {
            None
        };
        let help = match (special, names::suggest(&name.name, known.iter().copied())) {
            (Some(h), _) => h.to_string(),
            (None, Some(s)) => format!("did you mean `{s}`?"),
            (None, None) if known.is_empty() => format!("`{}` takes no properties", allow.what),
            (None, None) => format!("`{}` knows: {}", allow.what, known.join(", ")),
        };
        self.report(
            Diagnostic::error(
                Code::UnknownProperty,
                name.span,
                if name.name == "size" && allow.size {
                    "`size` takes a width and a height: `size W x H`".to_string()
                } else {
                    format!("`{}` has no property `{}`", allow.what, name.name)
                },
            )
            .label("unknown property")
            .help(help),
        );
    }

    fn misplaced(&mut self, stmt: &Stmt, allow: &Allow) {
        let (span, what) = match stmt {
            Stmt::Transform(t) => (t.span, "a transform"),
            Stmt::Motion { span, .. } => (*span, "a motion block"),
            Stmt::Object(o) => (o.head, "an object"),
            Stmt::Place { span, .. } => (*span, "a `place`"),
            Stmt::If { span, .. } => (*span, "an `if`"),
            Stmt::Flip { span } => (*span, "`flip`"),
            Stmt::Size { span, .. } => (*span, "`size`"),
            Stmt::Shutter { span, .. } => (*span, "`shutter`"),
            Stmt::Property { span, .. } => (*span, "a property"),
        };
        let twice = matches!(stmt, Stmt::Size { .. } | Stmt::Shutter { .. })
            && ((allow.size && matches!(stmt, Stmt::Size { .. }))
                || (allow.shutter && matches!(stmt, Stmt::Shutter { .. })));
        let d = if twice {
            Diagnostic::error(Code::Duplicate, span, format!("{what} is given twice"))
                .label("second time")
                .help("give each property once")
        } else {
            Diagnostic::error(
                Code::Misplaced,
                span,
                format!("{what} cannot appear in `{}`", allow.what),
            )
            .label("not allowed here")
            .help(match stmt {
                Stmt::Object(_) | Stmt::Place { .. } | Stmt::If { .. } => {
                    "put objects at top level or inside a `group`"
                }
                Stmt::Size { .. } | Stmt::Shutter { .. } => {
                    "`size` belongs in `render`, `shutter` in `camera`"
                }
                _ => "see docs/language.md for what each block accepts",
            })
        };
        self.report(d);
    }

    /// Property `key` evaluated, if present.
    pub(super) fn prop(&mut self, b: &Block, key: &Prop) -> Eval<Option<(Value, Span)>> {
        match b.get(key) {
            Some(e) => Ok(Some((self.expr(e)?, e.span))),
            None => Ok(None),
        }
    }

    /// A number property with a default.
    pub(super) fn prop_num(&mut self, b: &Block, key: &Prop, default: f64) -> Eval<(f64, Span)> {
        match self.prop(b, key)? {
            Some((v, s)) => Ok((self.num(&v, s)?, s)),
            None => Ok((default, Span::default())),
        }
    }

    /// A 3-vector property with a default.
    pub(super) fn prop_vec3(
        &mut self,
        b: &Block,
        key: &Prop,
        default: DVec3,
    ) -> Eval<(DVec3, Span)> {
        match self.prop(b, key)? {
            Some((v, s)) => Ok((self.vec3(&v, s)?, s)),
            None => Ok((default, Span::default())),
        }
    }

    /// A 2-vector property with a default.
    pub(super) fn prop_vec2(
        &mut self,
        b: &Block,
        key: &Prop,
        default: DVec2,
    ) -> Eval<(DVec2, Span)> {
        match self.prop(b, key)? {
            Some((v, s)) => Ok((self.vec2(&v, s)?, s)),
            None => Ok((default, Span::default())),
        }
    }

    /// A whole-number property with a default.
    pub(super) fn prop_count(&mut self, b: &Block, key: &Prop, default: u32) -> Eval<(u32, Span)> {
        match self.prop(b, key)? {
            Some((v, s)) => Ok((self.count(&v, s, &format!("`{}`", key.name))?, s)),
            None => Ok((default, Span::default())),
        }
    }

    /// An error unless `ok`: `what` is out of range.
    pub(super) fn range(&mut self, ok: bool, span: Span, message: String, help: &str) -> Eval<()> {
        if ok {
            Ok(())
        } else {
            Err(self.report(
                Diagnostic::error(Code::Range, span, message)
                    .label("out of range")
                    .help(help.to_string()),
            ))
        }
    }
}
