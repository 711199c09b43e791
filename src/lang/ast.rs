//! The syntax tree of a scene file. Every node carries the byte [`Span`] of
//! the text it came from, so evaluation can point at the exact expression.

pub use super::source::Span;

/// A name as written, with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A whole file: its top-level items in order.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct File {
    pub items: Vec<Item>,
}

/// A top-level item.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// `let NAME = EXPR`
    Let {
        name: Ident,
        value: Expr,
        span: Span,
    },
    /// `param NAME = EXPR`
    Param {
        name: Ident,
        value: Expr,
        span: Span,
    },
    /// `fn NAME(a, b: 2) = EXPR`, or `fn NAME(...) { ... }` whose body is
    /// a group (then `block` is set and `body` is that group object).
    Fn(Function),
    /// `include "PATH"`
    Include { path: String, span: Span },
    /// `render { ... }`
    Render { body: Vec<Stmt>, span: Span },
    /// `camera { ... }`
    Camera { body: Vec<Stmt>, span: Span },
    /// An object or a `place` placed in the world.
    Stmt(Stmt),
}

/// A user-defined function.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    pub name: Ident,
    pub params: Vec<Param>,
    pub body: Expr,
    /// Written in the block form `fn NAME(...) { ... }`.
    pub block: bool,
    pub span: Span,
}

/// A parameter of a function, with its default value if it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: Ident,
    pub default: Option<Expr>,
}

/// A statement inside a block (or an object/place at top level).
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `NAME VALUE`
    Property {
        name: Ident,
        value: Expr,
        span: Span,
    },
    /// `size W x H`
    Size {
        width: Expr,
        height: Expr,
        span: Span,
    },
    /// `shutter OPEN CLOSE`
    Shutter {
        open: Expr,
        close: Expr,
        span: Span,
    },
    Transform(Transform),
    /// `motion { transforms }`
    Motion {
        body: Vec<Stmt>,
        span: Span,
    },
    Object(Object),
    /// `place NAME { transforms }`, or `place NAME(args) { transforms }`
    /// for a function that returns an object.
    Place {
        name: Ident,
        args: Option<Vec<Arg>>,
        body: Vec<Stmt>,
        span: Span,
    },
    /// `flip`: swap the front and back faces of the enclosing object.
    Flip {
        span: Span,
    },
    /// `if COND { ... } else { ... }`; `else if` is an `If` alone in `otherwise`.
    If {
        cond: Expr,
        then: Vec<Stmt>,
        otherwise: Vec<Stmt>,
        span: Span,
    },
}

/// A coordinate axis named in `rotate x|y|z`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

/// A transform statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Transform {
    pub kind: TransformKind,
    pub span: Span,
}

/// What a transform statement does.
#[derive(Clone, Debug, PartialEq)]
pub enum TransformKind {
    Translate(Expr),
    /// `rotate x|y|z DEGREES`
    RotateAxis(Axis, Expr),
    /// `rotate (ax, ay, az) DEGREES`
    Rotate(Expr, Expr),
    Scale(Expr),
    Matrix(Expr),
}

/// An object block.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub kind: ObjectKind,
    pub body: Vec<Stmt>,
    pub span: Span,
    /// The span of the head (keyword and arguments before the block).
    pub head: Span,
}

/// Which plane a `rect` lies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RectPlane {
    Xy,
    Xz,
    Yz,
}

/// The kind of an object block and the arguments of its head.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectKind {
    Sphere,
    Plane,
    Box,
    Triangle,
    Medium,
    Group,
    Sun,
    PointLight,
    SpotLight,
    Rect(RectPlane),
    /// `mesh PATH`
    Mesh(Expr),
    /// `revolve CURVE`
    Revolve(Expr),
    /// `repeat VAR in FROM..TO`
    Repeat {
        var: Ident,
        from: Expr,
        to: Expr,
    },
}

/// An expression with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

impl BinOp {
    /// `+ - * / ^`, as opposed to comparisons and `and` / `or`.
    pub fn is_arithmetic(self) -> bool {
        matches!(
            self,
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Pow
        )
    }
}

/// A call argument: positional (`name` is `None`) or `name: value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub name: Option<Ident>,
    pub value: Expr,
}

/// The kinds of expression.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Str(String),
    Bool(bool),
    /// `#rrggbb`, the six hex digits.
    Hex(String),
    Name(String),
    /// `(a, b, ...)`; one element is a parenthesised expression.
    Tuple(Vec<Expr>),
    /// `[a, b, ...]`
    List(Vec<Expr>),
    Call {
        callee: Ident,
        args: Vec<Arg>,
    },
    /// `bezier [points]`
    Bezier(Vec<Expr>),
    Neg(Box<Expr>),
    /// `not x`
    Not(Box<Expr>),
    /// `if COND then A else B`
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Object(Box<Object>),
    /// A node cut off because the expression nests too deeply (reported).
    Error,
}

impl Item {
    /// The span of the whole item.
    pub fn span(&self) -> Span {
        match self {
            Item::Let { span, .. }
            | Item::Param { span, .. }
            | Item::Include { span, .. }
            | Item::Render { span, .. }
            | Item::Camera { span, .. } => *span,
            Item::Fn(f) => f.span,
            Item::Stmt(stmt) => stmt.span(),
        }
    }
}

impl Stmt {
    /// The span of the whole statement.
    pub fn span(&self) -> Span {
        match self {
            Stmt::Property { span, .. }
            | Stmt::Size { span, .. }
            | Stmt::Shutter { span, .. }
            | Stmt::Motion { span, .. }
            | Stmt::Place { span, .. }
            | Stmt::Flip { span }
            | Stmt::If { span, .. } => *span,
            Stmt::Transform(t) => t.span,
            Stmt::Object(o) => o.span,
        }
    }
}
