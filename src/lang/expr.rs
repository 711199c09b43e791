//! Compiling expressions of the shutter time `t` into
//! [`scene::motion::Program`](crate::scene::motion::Program)s: a small
//! symbolic tree whose constant parts fold as it is built, flattened into
//! stack-machine code.

use crate::scene::motion::{Fn1, Fn2, Fn3, Op, Program};

/// A scalar expression of `t`.
#[derive(Clone, Debug, PartialEq)]
pub enum Sym {
    Const(f64),
    Time,
    Add(Box<Sym>, Box<Sym>),
    Sub(Box<Sym>, Box<Sym>),
    Mul(Box<Sym>, Box<Sym>),
    Div(Box<Sym>, Box<Sym>),
    Neg(Box<Sym>),
    Call1(Fn1, Box<Sym>),
    Call2(Fn2, Box<Sym>, Box<Sym>),
    Call3(Fn3, Box<Sym>, Box<Sym>, Box<Sym>),
    Keyframes {
        x: Box<Sym>,
        keys: Vec<(f64, f64)>,
        smooth: bool,
    },
}

impl Sym {
    /// The constant value, if the expression does not depend on `t`.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Sym::Const(c) => Some(*c),
            _ => None,
        }
    }

    /// Flattens to stack code.
    pub fn compile(&self) -> Program {
        let mut program = Program::default();
        self.emit(&mut program);
        program
    }

    fn emit(&self, p: &mut Program) {
        match self {
            Sym::Const(c) => p.ops.push(Op::Const(*c as f32)),
            Sym::Time => p.ops.push(Op::Time),
            Sym::Add(a, b) | Sym::Sub(a, b) | Sym::Mul(a, b) | Sym::Div(a, b) => {
                a.emit(p);
                b.emit(p);
                p.ops.push(match self {
                    Sym::Add(..) => Op::Add,
                    Sym::Sub(..) => Op::Sub,
                    Sym::Mul(..) => Op::Mul,
                    _ => Op::Div,
                });
            }
            Sym::Neg(a) => {
                a.emit(p);
                p.ops.push(Op::Neg);
            }
            Sym::Call1(f, a) => {
                a.emit(p);
                p.ops.push(Op::Call1(*f));
            }
            Sym::Call2(f, a, b) => {
                a.emit(p);
                b.emit(p);
                p.ops.push(Op::Call2(*f));
            }
            Sym::Call3(f, a, b, c) => {
                a.emit(p);
                b.emit(p);
                c.emit(p);
                p.ops.push(Op::Call3(*f));
            }
            Sym::Keyframes { x, keys, smooth } => {
                x.emit(p);
                let start = p.keys.len() as u32;
                p.keys
                    .extend(keys.iter().map(|&(t, v)| (t as f32, v as f32)));
                p.ops.push(Op::Keyframes {
                    start,
                    len: keys.len() as u32,
                    smooth: *smooth,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn emits_postfix_code() {
        let s = Sym::Mul(Box::new(Sym::Const(30.0)), Box::new(Sym::Time));
        assert_eq!(s.compile().ops, vec![Op::Const(30.0), Op::Time, Op::Mul]);
    }

    #[test]
    fn keyframe_tables_are_appended() {
        let s = Sym::Add(
            Box::new(Sym::Keyframes {
                x: Box::new(Sym::Time),
                keys: vec![(0.0, 0.0), (1.0, 3.0)],
                smooth: false,
            }),
            Box::new(Sym::Keyframes {
                x: Box::new(Sym::Time),
                keys: vec![(0.0, 1.0)],
                smooth: true,
            }),
        );
        let p = s.compile();
        assert_eq!(p.keys.len(), 3);
        assert!(p.ops.contains(&Op::Keyframes {
            start: 2,
            len: 1,
            smooth: true
        }));
    }
}
