//! Per-call cost of motion evaluation: `Program::eval` for a typical
//! expression and keyframe table, and `matrix_at` for a moving object's
//! motion, both plain and compiled (constant steps folded).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::Vec3;
use rtlang::scene::motion::{Fn3, MotionStep, Op, Program};
use rtlang::scene::Motion;

/// `360 * smoothstep(0, 1, t)`
fn spin() -> Program {
    let ops = vec![
        Op::Const(360.0),
        Op::Const(0.0),
        Op::Const(1.0),
        Op::Time,
        Op::Call3(Fn3::Smoothstep),
        Op::Mul,
    ];
    Program::new(ops, vec![]).expect("valid")
}

fn keyframes() -> Program {
    let keys = (0..8).map(|i| (i as f32 / 7.0, (i * i) as f32)).collect();
    let ops = vec![
        Op::Time,
        Op::Keyframes {
            start: 0,
            len: 8,
            smooth: true,
        },
    ];
    Program::new(ops, keys).expect("valid")
}

/// A static scale and rotation, then a spin and a linear move.
fn motion() -> Motion {
    let c = Program::constant;
    let slide = Program::new(vec![Op::Const(0.2), Op::Time, Op::Mul], vec![]).expect("valid");
    Motion {
        steps: vec![
            MotionStep::Scale([c(2.0), c(2.0), c(2.0)]),
            MotionStep::Rotate {
                axis: Vec3::X,
                degrees: c(-90.0),
            },
            MotionStep::Rotate {
                axis: Vec3::Y,
                degrees: spin(),
            },
            MotionStep::Translate([slide, c(0.0), c(1.0)]),
        ],
    }
}

fn bench(c: &mut Criterion) {
    let (spin, keys, motion) = (spin(), keyframes(), motion());
    let compiled = motion.compile();
    c.bench_function("Program::eval 360*smoothstep(0,1,t)", |b| {
        b.iter(|| spin.eval(black_box(0.37)))
    });
    c.bench_function("Program::eval 8 smooth keyframes", |b| {
        b.iter(|| keys.eval(black_box(0.37)))
    });
    c.bench_function("Motion::matrix_at 4 steps", |b| {
        b.iter(|| motion.matrix_at(black_box(0.37)))
    });
    c.bench_function("CompiledMotion::matrix_at 4 steps (2 folded)", |b| {
        b.iter(|| compiled.matrix_at(black_box(0.37)))
    });
    c.bench_function("CompiledMotion::matrices_at 4 steps (with inverse)", |b| {
        b.iter(|| compiled.matrices_at(black_box(0.37)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
