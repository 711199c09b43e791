//! Random expression trees of `t` for the motion property tests, compiled to
//! [`Program`]s the way the language does: operands in post-order.

use proptest::prelude::*;
use rtlang::scene::motion::{Fn1, Fn2, Fn3, Op, Program};

/// An expression tree; [`Expr::compile`] flattens it to stack code.
#[derive(Clone, Debug)]
pub enum Expr {
    Const(f32),
    Time,
    Neg(Box<Expr>),
    Call1(Fn1, Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
    Pow(Box<Expr>, f32),
    Call3(Fn3, Box<Expr>, Box<Expr>, Box<Expr>),
    Keys(Vec<(f32, f32)>, bool, Box<Expr>),
}

impl Expr {
    pub fn compile(&self) -> Program {
        let mut p = Program::default();
        self.emit(&mut p);
        p
    }

    fn emit(&self, p: &mut Program) {
        match self {
            Expr::Const(c) => p.ops.push(Op::Const(*c)),
            Expr::Time => p.ops.push(Op::Time),
            Expr::Neg(a) => {
                a.emit(p);
                p.ops.push(Op::Neg);
            }
            Expr::Call1(f, a) => {
                // sqrt and ln see |a| so the tree stays free of NaN.
                a.emit(p);
                if matches!(f, Fn1::Sqrt | Fn1::Ln) {
                    p.ops.push(Op::Call1(Fn1::Abs));
                }
                p.ops.push(Op::Call1(*f));
            }
            Expr::Bin(op, a, b) => {
                a.emit(p);
                b.emit(p);
                p.ops.push(*op);
            }
            Expr::Pow(a, n) => {
                a.emit(p);
                if n.fract() != 0.0 {
                    p.ops.push(Op::Call1(Fn1::Abs));
                }
                p.ops.push(Op::Const(*n));
                p.ops.push(Op::Call2(Fn2::Pow));
            }
            Expr::Call3(f, a, b, c) => {
                a.emit(p);
                b.emit(p);
                c.emit(p);
                p.ops.push(Op::Call3(*f));
            }
            Expr::Keys(table, smooth, x) => {
                x.emit(p);
                let start = p.keys.len() as u32;
                p.keys.extend_from_slice(table);
                p.ops.push(Op::Keyframes {
                    start,
                    len: table.len() as u32,
                    smooth: *smooth,
                });
            }
        }
    }
}

/// A sorted keyframe table of 1 to 5 keys.
pub fn key_table() -> impl Strategy<Value = Vec<(f32, f32)>> {
    prop::collection::vec((-3.0f32..3.0, -5.0f32..5.0), 1..6).prop_map(|mut keys| {
        keys.sort_by(|a, b| a.0.total_cmp(&b.0));
        keys
    })
}

/// A random expression of `t` up to a few levels deep.
pub fn expr() -> impl Strategy<Value = Expr> {
    let leaf = prop_oneof![(-3.0f32..3.0).prop_map(Expr::Const), Just(Expr::Time)];
    leaf.prop_recursive(4, 24, 3, |inner| {
        let fn1 = prop_oneof![
            Just(Fn1::Sin),
            Just(Fn1::Cos),
            Just(Fn1::Tan),
            Just(Fn1::Sqrt),
            Just(Fn1::Abs),
            Just(Fn1::Radians),
            Just(Fn1::Degrees),
            Just(Fn1::Exp),
            Just(Fn1::Ln),
            Just(Fn1::Floor),
        ];
        let bin = prop_oneof![
            Just(Op::Add),
            Just(Op::Sub),
            Just(Op::Mul),
            Just(Op::Div),
            Just(Op::Call2(Fn2::Min)),
            Just(Op::Call2(Fn2::Max)),
        ];
        let fn3 = prop_oneof![Just(Fn3::Lerp), Just(Fn3::Clamp), Just(Fn3::Smoothstep)];
        let exponent = prop_oneof![(-3i32..5).prop_map(|n| n as f32), 0.1f32..3.0];
        prop_oneof![
            inner.clone().prop_map(|a| Expr::Neg(Box::new(a))),
            (fn1, inner.clone()).prop_map(|(f, a)| Expr::Call1(f, Box::new(a))),
            (bin, inner.clone(), inner.clone()).prop_map(|(op, a, b)| Expr::Bin(
                op,
                Box::new(a),
                Box::new(b)
            )),
            (inner.clone(), exponent).prop_map(|(a, n)| Expr::Pow(Box::new(a), n)),
            (fn3, inner.clone(), inner.clone(), inner.clone())
                .prop_map(|(f, a, b, c)| { Expr::Call3(f, Box::new(a), Box::new(b), Box::new(c)) }),
            (key_table(), any::<bool>(), inner).prop_map(|(k, s, x)| Expr::Keys(k, s, Box::new(x))),
        ]
    })
}
