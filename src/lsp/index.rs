//! What the editor features need from one file's syntax tree: definitions
//! (`let`, `param`, `fn` and its parameters, `repeat` variables with their scope), every use of a
//! name, includes, property names, callees and the outline.

use crate::lang::ast::*;

/// What a definition is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DefKind {
    Let,
    Param,
    /// A `repeat` variable, visible only in its loop.
    Loop,
    /// A user-defined function (`fn`).
    Function,
    /// A function's parameter, visible only in its body.
    Argument,
}

impl DefKind {
    /// Whether the name is visible only inside its definition's span.
    pub fn is_scoped(self) -> bool {
        matches!(self, DefKind::Loop | DefKind::Argument)
    }
}

/// A name defined in the file.
#[derive(Clone, Debug)]
pub struct Def {
    pub name: String,
    pub kind: DefKind,
    /// The span of the name where it is defined.
    pub name_span: Span,
    /// The whole definition (the `repeat` object for a loop variable).
    pub span: Span,
    /// The canonical source of the value (`None` for a loop variable).
    pub value: Option<String>,
}

/// The index of one file.
#[derive(Debug, Default)]
pub struct Index {
    pub defs: Vec<Def>,
    /// Every name used in an expression or a `place`, with its span.
    pub uses: Vec<(String, Span)>,
    /// `include` paths with the span of the whole item.
    pub includes: Vec<(String, Span)>,
    /// The name spans of properties.
    pub properties: Vec<Span>,
    /// The spans of called function names.
    pub callees: Vec<Span>,
    /// Top-level items worth an outline entry: (label, kind, span).
    pub outline: Vec<(String, &'static str, Span)>,
}

impl Index {
    /// Indexes a parsed file.
    pub fn new(file: &File) -> Index {
        let mut index = Index::default();
        for item in &file.items {
            index.item(item);
        }
        index
    }

    /// The definition a name at byte `at` refers to (or defines).
    pub fn resolve(&self, at: usize) -> Option<&Def> {
        if let Some(def) = self
            .defs
            .iter()
            .find(|d| contains(d.name_span, at) && !d.kind.is_scoped())
        {
            return Some(def);
        }
        let (name, span) = self
            .uses
            .iter()
            .find(|(_, s)| contains(*s, at))
            .map(|(n, s)| (n.as_str(), *s))
            .or_else(|| {
                self.defs
                    .iter()
                    .find(|d| contains(d.name_span, at))
                    .map(|d| (d.name.as_str(), d.name_span))
            })?;
        self.lookup(name, span.start as usize)
    }

    /// The definition `name` means at byte `at`: the innermost loop
    /// variable in scope, else the top-level definition.
    pub fn lookup(&self, name: &str, at: usize) -> Option<&Def> {
        self.defs
            .iter()
            .filter(|d| d.name == name && d.kind.is_scoped() && contains(d.span, at))
            .min_by_key(|d| d.span.len())
            .or_else(|| {
                self.defs
                    .iter()
                    .find(|d| d.name == name && !d.kind.is_scoped())
            })
    }

    /// The spans of `def`'s name where it is defined and everywhere it is used.
    pub fn occurrences(&self, def: &Def) -> Vec<Span> {
        let mut spans = vec![def.name_span];
        spans.extend(
            self.uses
                .iter()
                .filter(|(n, s)| {
                    *n == def.name
                        && self
                            .lookup(n, s.start as usize)
                            .is_some_and(|d| d.name_span == def.name_span)
                })
                .map(|(_, s)| *s),
        );
        spans
    }

    /// The names visible at byte `at`.
    pub fn in_scope(&self, at: usize) -> impl Iterator<Item = &Def> {
        self.defs
            .iter()
            .filter(move |d| !d.kind.is_scoped() || contains(d.span, at))
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Let { name, value, span } | Item::Param { name, value, span } => {
                let kind = if matches!(item, Item::Let { .. }) {
                    DefKind::Let
                } else {
                    DefKind::Param
                };
                self.defs.push(Def {
                    name: name.name.clone(),
                    kind,
                    name_span: name.span,
                    span: *span,
                    value: Some(crate::lang::pretty::expr(value)),
                });
                let label = if kind == DefKind::Let { "let" } else { "param" };
                self.outline.push((name.name.clone(), label, *span));
                self.expr(value);
            }
            Item::Fn(f) => self.function(f),
            Item::Include { path, span } => self.includes.push((path.clone(), *span)),
            Item::Render { body, span } | Item::Camera { body, span } => {
                let kind = if matches!(item, Item::Render { .. }) {
                    "render"
                } else {
                    "camera"
                };
                self.outline.push((kind.to_string(), kind, *span));
                self.stmts(body);
            }
            Item::Stmt(stmt) => {
                if let Stmt::Object(o) = stmt {
                    let kind = object_keyword(&o.kind);
                    self.outline.push((kind.to_string(), "object", o.span));
                }
                self.stmt(stmt);
            }
        }
    }

    /// A function: its name, its parameters (visible in the body only) and
    /// the uses in their defaults and the body.
    fn function(&mut self, f: &Function) {
        self.defs.push(Def {
            name: f.name.name.clone(),
            kind: DefKind::Function,
            name_span: f.name.span,
            span: f.span,
            value: Some(format!(
                "{} = {}",
                crate::lang::pretty::signature(f),
                crate::lang::pretty::expr(&f.body)
            )),
        });
        self.outline.push((f.name.name.clone(), "fn", f.span));
        for p in &f.params {
            self.defs.push(Def {
                name: p.name.name.clone(),
                kind: DefKind::Argument,
                name_span: p.name.span,
                span: f.span,
                value: None,
            });
            if let Some(d) = &p.default {
                self.expr(d);
            }
        }
        self.expr(&f.body);
    }

    fn stmts(&mut self, body: &[Stmt]) {
        for stmt in body {
            self.stmt(stmt);
        }
    }

    fn stmt(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Property { name, value, .. } => {
                self.properties.push(name.span);
                self.expr(value);
            }
            Stmt::Size { width, height, .. } => {
                self.expr(width);
                self.expr(height);
            }
            Stmt::Shutter { open, close, .. } => {
                self.expr(open);
                self.expr(close);
            }
            Stmt::Transform(t) => match &t.kind {
                TransformKind::Translate(e)
                | TransformKind::RotateAxis(_, e)
                | TransformKind::Scale(e)
                | TransformKind::Matrix(e) => self.expr(e),
                TransformKind::Rotate(a, e) => {
                    self.expr(a);
                    self.expr(e);
                }
            },
            Stmt::Motion { body, .. } => {
                self.stmts(body);
            }
            Stmt::Object(o) => self.object(o),
            Stmt::Place {
                name, args, body, ..
            } => {
                self.uses.push((name.name.clone(), name.span));
                args.iter().flatten().for_each(|a| self.expr(&a.value));
                self.stmts(body);
            }
            Stmt::Flip { .. } => {}
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => {
                self.expr(cond);
                self.stmts(then);
                self.stmts(otherwise);
            }
        }
    }

    fn object(&mut self, o: &Object) {
        match &o.kind {
            ObjectKind::Mesh(e) | ObjectKind::Revolve(e) => self.expr(e),
            ObjectKind::Repeat { var, from, to } => {
                self.expr(from);
                self.expr(to);
                self.defs.push(Def {
                    name: var.name.clone(),
                    kind: DefKind::Loop,
                    name_span: var.span,
                    span: o.span,
                    value: None,
                });
            }
            _ => {}
        }
        self.stmts(&o.body);
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Name(n) => self.uses.push((n.clone(), e.span)),
            ExprKind::Tuple(items) | ExprKind::List(items) | ExprKind::Bezier(items) => {
                items.iter().for_each(|i| self.expr(i));
            }
            ExprKind::Call { callee, args } => {
                self.callees.push(callee.span);
                // A user function's call is a use of its name (a built-in's
                // finds no definition).
                self.uses.push((callee.name.clone(), callee.span));
                args.iter().for_each(|a| self.expr(&a.value));
            }
            ExprKind::Neg(x) | ExprKind::Not(x) => self.expr(x),
            ExprKind::If(c, a, b) => {
                self.expr(c);
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Binary(_, a, b) => {
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Object(o) => self.object(o),
            ExprKind::Number(_)
            | ExprKind::Str(_)
            | ExprKind::Bool(_)
            | ExprKind::Hex(_)
            | ExprKind::Error => {}
        }
    }
}

/// The keyword that begins an object of this kind.
pub fn object_keyword(kind: &ObjectKind) -> &'static str {
    match kind {
        ObjectKind::Sphere => "sphere",
        ObjectKind::Plane => "plane",
        ObjectKind::Box => "box",
        ObjectKind::Triangle => "triangle",
        ObjectKind::Medium => "medium",
        ObjectKind::Sun => "sun",
        ObjectKind::PointLight => "point_light",
        ObjectKind::SpotLight => "spot_light",
        ObjectKind::Group => "group",
        ObjectKind::Rect(_) => "rect",
        ObjectKind::Mesh(_) => "mesh",
        ObjectKind::Revolve(_) => "revolve",
        ObjectKind::Repeat { .. } => "repeat",
    }
}

/// Whether byte `at` is in `span` (its end included, where a cursor sits
/// right after a name).
pub fn contains(span: Span, at: usize) -> bool {
    span.start as usize <= at && at <= span.end as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::syntax;

    fn index(text: &str) -> Index {
        let (file, _) = syntax::parse_file(text, 0).expect("the test scene parses");
        Index::new(&file)
    }

    #[test]
    fn a_call_resolves_to_its_function_and_a_parameter_to_its_own_scope() {
        let text = "let n = 1\nfn size(n, k: 2) = n * k\nsphere { radius size(n) }\n";
        let index = index(text);
        // The call `size(` on line 3 goes to the `fn`.
        let call = text.rfind("size(").expect("the call");
        let def = index.resolve(call + 1).expect("the call resolves");
        assert_eq!(def.kind, DefKind::Function);
        assert_eq!(
            def.name_span.start as usize,
            text.find("size").expect("the fn")
        );
        // `n` in the body is the parameter, `n` in the call is the `let`.
        let in_body = text.find("n * k").expect("the body");
        assert_eq!(
            index.resolve(in_body).map(|d| d.kind),
            Some(DefKind::Argument)
        );
        let in_call = text.rfind("(n)").expect("the argument") + 1;
        assert_eq!(index.resolve(in_call).map(|d| d.kind), Some(DefKind::Let));
        // The outline lists the function.
        assert!(index
            .outline
            .iter()
            .any(|(name, kind, _)| name == "size" && *kind == "fn"));
    }
}
