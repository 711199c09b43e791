//! The canonical printer: an AST back to source text in one fixed layout
//! (two-space indent, one statement per line, minimal parentheses). Used by
//! `rtlang parse` and its snapshot tests; printing and re-parsing gives the
//! same tree. `rtlang fmt` prints through the same layout with a [`Trivia`]
//! source that puts the comments and blank lines back.

use std::fmt::Write;

use super::ast::*;
use super::names::is_keyword;

/// The canonical source of a file.
pub fn file(file: &File) -> String {
    let mut p = Printer::default();
    for item in &file.items {
        p.item(item);
    }
    p.out
}

/// The canonical source of a file with the comments and blank lines that
/// `trivia` hands out around its items, statements and closing braces.
pub fn file_with(file: &File, trivia: &mut dyn Trivia) -> String {
    let mut p = Printer {
        trivia: Some(trivia),
        ..Printer::default()
    };
    for item in &file.items {
        p.item(item);
    }
    p.out
}

/// The canonical source of one expression.
pub fn expr(e: &Expr) -> String {
    let mut p = Printer::default();
    p.expr(e, 0);
    p.out
}

/// A function's usage line: `name(a, b: 2)`.
pub fn signature(f: &Function) -> String {
    let params: Vec<String> = f
        .params
        .iter()
        .map(|p| match &p.default {
            Some(d) => format!("{}: {}", p.name.name, expr(d)),
            None => p.name.name.clone(),
        })
        .collect();
    format!("{}({})", f.name.name, params.join(", "))
}

/// What the formatter interleaves with the canonical layout. Every string
/// returned is put into the output as it is.
pub trait Trivia {
    /// Whole lines (at `indent`, each ending in a newline) to print before
    /// the item or statement at `span`; `fresh` is true at the start of the
    /// file or of a block, where no blank line belongs.
    fn before(&mut self, span: Span, indent: usize, fresh: bool) -> String;
    /// Text to append to the last line of the item or statement at `span`.
    fn after(&mut self, span: Span) -> String;
    /// Whole lines (at `indent`) to print before the closing brace of the
    /// block being printed; `empty` when the block has no statement.
    fn inside(&mut self, empty: bool, indent: usize) -> String;
}

#[derive(Default)]
struct Printer<'a> {
    out: String,
    indent: usize,
    trivia: Option<&'a mut dyn Trivia>,
}

impl Printer<'_> {
    /// The trivia's lines before the item or statement at `span`.
    fn before(&mut self, span: Span) {
        if let Some(trivia) = self.trivia.as_deref_mut() {
            let fresh = self.out.is_empty() || self.out.ends_with("{\n");
            self.out.push_str(&trivia.before(span, self.indent, fresh));
        }
    }

    /// The trivia's text at the end of the item or statement at `span`.
    fn after(&mut self, span: Span) {
        if let Some(trivia) = self.trivia.as_deref_mut() {
            self.out.push_str(&trivia.after(span));
        }
    }

    /// The trivia's lines before a closing brace (at `indent`).
    fn inside(&mut self, empty: bool, indent: usize) -> String {
        match self.trivia.as_deref_mut() {
            Some(trivia) => trivia.inside(empty, indent),
            None => String::new(),
        }
    }

    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
    }

    fn item(&mut self, item: &Item) {
        if !matches!(item, Item::Stmt(_)) {
            self.before(item.span());
        }
        match item {
            Item::Let { name, value, .. } | Item::Param { name, value, .. } => {
                let kw = if matches!(item, Item::Let { .. }) {
                    "let"
                } else {
                    "param"
                };
                self.line(&format!("{kw} {} = ", name.name));
                self.expr(value, 0);
            }
            Item::Fn(f) => self.function(f),
            Item::Include { path, .. } => {
                self.line(&format!("include {}", quote(path)));
            }
            Item::Render { body, .. } => {
                self.line("render");
                self.block(body);
            }
            Item::Camera { body, .. } => {
                self.line("camera");
                self.block(body);
            }
            Item::Stmt(stmt) => return self.stmt(stmt),
        }
        self.after(item.span());
        self.out.push('\n');
    }

    fn block(&mut self, body: &[Stmt]) {
        if body.is_empty() {
            let inside = self.inside(true, self.indent + 1);
            if inside.is_empty() {
                self.out.push_str(" {}");
            } else {
                self.out.push_str(" {\n");
                self.out.push_str(&inside);
                self.line("}");
            }
            return;
        }
        self.out.push_str(" {\n");
        self.indent += 1;
        for stmt in body {
            self.stmt(stmt);
        }
        let inside = self.inside(false, self.indent);
        self.out.push_str(&inside);
        self.indent -= 1;
        self.line("}");
    }

    fn stmt(&mut self, stmt: &Stmt) {
        self.before(stmt.span());
        match stmt {
            Stmt::Property { name, value, .. } => {
                self.line(&format!("{} ", name.name));
                self.expr(value, 0);
            }
            Stmt::Size { width, height, .. } => {
                self.line("size ");
                self.expr(width, 0);
                self.out.push_str(" x ");
                self.expr(height, 0);
            }
            Stmt::Shutter { open, close, .. } => {
                self.line("shutter ");
                self.expr(open, 0);
                self.out.push(' ');
                self.atom(close);
            }
            Stmt::Transform(t) => self.transform(t),
            Stmt::Motion { body, .. } => {
                self.line("motion");
                self.block(body);
            }
            Stmt::Object(object) => {
                self.line("");
                self.object(object);
            }
            Stmt::Place {
                name, args, body, ..
            } => {
                self.line(&format!("place {}", name.name));
                if let Some(args) = args {
                    self.args(args);
                }
                if !body.is_empty() {
                    self.block(body);
                }
            }
            Stmt::Flip { .. } => self.line("flip"),
            Stmt::If { .. } => {
                self.line("");
                self.if_stmt(stmt);
            }
        }
        self.after(stmt.span());
        self.out.push('\n');
    }

    /// `fn NAME(a, b: 2) = EXPR`, or the block form.
    fn function(&mut self, f: &Function) {
        self.line(&format!("fn {}(", f.name.name));
        for (i, param) in f.params.iter().enumerate() {
            if i > 0 {
                self.out.push_str(", ");
            }
            self.out.push_str(&param.name.name);
            if let Some(default) = &param.default {
                self.out.push_str(": ");
                self.expr(default, 0);
            }
        }
        self.out.push(')');
        match &f.body.kind {
            ExprKind::Object(o) if f.block => self.block(&o.body),
            _ => {
                self.out.push_str(" = ");
                self.expr(&f.body, 0);
            }
        }
    }

    /// `(a, name: b)`: the arguments of a call.
    fn args(&mut self, args: &[Arg]) {
        self.out.push('(');
        for (i, arg) in args.iter().enumerate() {
            if i > 0 {
                self.out.push_str(", ");
            }
            if let Some(name) = &arg.name {
                let _ = write!(self.out, "{}: ", name.name);
            }
            self.expr(&arg.value, 0);
        }
        self.out.push(')');
    }

    /// `if COND { ... }`, then `else if ...` or `else { ... }` if present.
    fn if_stmt(&mut self, stmt: &Stmt) {
        let Stmt::If {
            cond,
            then,
            otherwise,
            ..
        } = stmt
        else {
            return;
        };
        self.out.push_str("if ");
        self.expr(cond, 0);
        self.block(then);
        match &otherwise[..] {
            [] => {}
            [inner @ Stmt::If { .. }] => {
                self.out.push_str(" else ");
                self.if_stmt(inner);
            }
            body => {
                self.out.push_str(" else");
                self.block(body);
            }
        }
    }

    fn transform(&mut self, t: &Transform) {
        match &t.kind {
            TransformKind::Translate(e) => {
                self.line("translate ");
                self.expr(e, 0);
            }
            TransformKind::RotateAxis(axis, e) => {
                let a = match axis {
                    Axis::X => "x",
                    Axis::Y => "y",
                    Axis::Z => "z",
                };
                self.line(&format!("rotate {a} "));
                self.atom(e);
            }
            TransformKind::Rotate(axis, e) => {
                self.line("rotate ");
                self.expr(axis, 0);
                self.out.push(' ');
                self.atom(e);
            }
            TransformKind::Scale(e) => {
                self.line("scale ");
                self.expr(e, 0);
            }
            TransformKind::Matrix(e) => {
                self.line("matrix ");
                self.expr(e, 0);
            }
        }
    }

    /// An expression that follows another one directly, or sits where only
    /// a primary may: parenthesised unless it is a single token, so a
    /// leading `-` cannot join the previous one, and a keyword read as a
    /// name (an error later, as `mesh medium`) cannot join the block after
    /// it into an object (`mesh medium {}` is the mesh of a medium).
    fn atom(&mut self, e: &Expr) {
        let keyword = matches!(&e.kind, ExprKind::Name(n) if is_keyword(n));
        if keyword
            || matches!(
                e.kind,
                ExprKind::Neg(_) | ExprKind::Not(_) | ExprKind::Binary(..) | ExprKind::If(..)
            )
        {
            self.out.push('(');
            self.expr(e, 0);
            self.out.push(')');
        } else {
            self.expr(e, 0);
        }
    }

    fn object(&mut self, o: &Object) {
        match &o.kind {
            ObjectKind::Sphere => self.out.push_str("sphere"),
            ObjectKind::Plane => self.out.push_str("plane"),
            ObjectKind::Box => self.out.push_str("box"),
            ObjectKind::Triangle => self.out.push_str("triangle"),
            ObjectKind::Medium => self.out.push_str("medium"),
            ObjectKind::Group => self.out.push_str("group"),
            ObjectKind::Sun => self.out.push_str("sun"),
            ObjectKind::PointLight => self.out.push_str("point_light"),
            ObjectKind::SpotLight => self.out.push_str("spot_light"),
            ObjectKind::Rect(plane) => self.out.push_str(match plane {
                RectPlane::Xy => "rect xy",
                RectPlane::Xz => "rect xz",
                RectPlane::Yz => "rect yz",
            }),
            ObjectKind::Mesh(e) | ObjectKind::Revolve(e) => {
                let kw = if matches!(o.kind, ObjectKind::Mesh(_)) {
                    "mesh "
                } else {
                    "revolve "
                };
                self.out.push_str(kw);
                self.atom(e);
            }
            ObjectKind::Repeat { var, from, to } => {
                let _ = write!(self.out, "repeat {} in ", var.name);
                self.expr(from, 0);
                self.out.push_str("..");
                self.expr(to, 0);
            }
        }
        self.block(&o.body);
    }

    /// Prints `e`, parenthesised if its precedence is below `min`.
    fn expr(&mut self, e: &Expr, min: u8) {
        let prec = precedence(e);
        let paren = prec < min;
        if paren {
            self.out.push('(');
        }
        match &e.kind {
            ExprKind::Number(v) => self.number(*v),
            ExprKind::Str(s) => self.out.push_str(&quote(s)),
            ExprKind::Bool(b) => {
                let _ = write!(self.out, "{b}");
            }
            ExprKind::Hex(h) => {
                let _ = write!(self.out, "#{h}");
            }
            ExprKind::Name(n) => self.out.push_str(n),
            ExprKind::Tuple(items) => {
                self.out.push('(');
                self.list(items);
                self.out.push(')');
            }
            ExprKind::List(items) => {
                self.out.push('[');
                self.list(items);
                self.out.push(']');
            }
            ExprKind::Bezier(items) => {
                self.out.push_str("bezier [");
                self.list(items);
                self.out.push(']');
            }
            ExprKind::Call { callee, args } => {
                self.out.push_str(&callee.name);
                self.args(args);
            }
            ExprKind::Neg(x) => {
                self.out.push('-');
                self.expr(x, 7);
            }
            ExprKind::Not(x) => {
                self.out.push_str("not ");
                self.expr(x, 3);
            }
            ExprKind::If(cond, then, otherwise) => {
                self.out.push_str("if ");
                self.expr(cond, 0);
                self.out.push_str(" then ");
                self.expr(then, 0);
                self.out.push_str(" else ");
                self.expr(otherwise, 0);
            }
            ExprKind::Binary(op, a, b) => {
                let (sym, left, right) = match op {
                    BinOp::Or => (" or ", 1, 2),
                    BinOp::And => (" and ", 2, 3),
                    BinOp::Lt => (" < ", 5, 5),
                    BinOp::Le => (" <= ", 5, 5),
                    BinOp::Gt => (" > ", 5, 5),
                    BinOp::Ge => (" >= ", 5, 5),
                    BinOp::Eq => (" == ", 5, 5),
                    BinOp::Ne => (" != ", 5, 5),
                    BinOp::Add => (" + ", 5, 6),
                    BinOp::Sub => (" - ", 5, 6),
                    BinOp::Mul => (" * ", 6, 7),
                    BinOp::Div => (" / ", 6, 7),
                    BinOp::Pow => ("^", 9, 8),
                };
                self.expr(a, left);
                self.out.push_str(sym);
                self.expr(b, right);
            }
            ExprKind::Object(o) => {
                let indent = self.indent;
                self.object(o);
                self.indent = indent;
            }
            ExprKind::Error => self.out.push_str("<error>"),
        }
        if paren {
            self.out.push(')');
        }
    }

    fn number(&mut self, v: f64) {
        let a = v.abs();
        if a != 0.0 && !(1e-5..1e16).contains(&a) {
            let _ = write!(self.out, "{v:e}");
        } else {
            let _ = write!(self.out, "{v}");
        }
    }

    fn list(&mut self, items: &[Expr]) {
        for (i, item) in items.iter().enumerate() {
            if i > 0 {
                self.out.push_str(", ");
            }
            self.expr(item, 0);
        }
    }
}

/// Binding strength: 0 `if`, 1 `or`, 2 `and`, 3 `not`, 4 comparison,
/// 5 sum, 6 product, 7 negation, 8 power, 9 atom.
fn precedence(e: &Expr) -> u8 {
    match &e.kind {
        ExprKind::If(..) => 0,
        ExprKind::Binary(BinOp::Or, ..) => 1,
        ExprKind::Binary(BinOp::And, ..) => 2,
        ExprKind::Not(_) => 3,
        ExprKind::Binary(
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne,
            ..,
        ) => 4,
        ExprKind::Binary(BinOp::Add | BinOp::Sub, ..) => 5,
        ExprKind::Binary(BinOp::Mul | BinOp::Div, ..) => 6,
        ExprKind::Neg(_) => 7,
        ExprKind::Binary(BinOp::Pow, ..) => 8,
        _ => 9,
    }
}

/// A string literal with `"` and `\` escaped.
fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
