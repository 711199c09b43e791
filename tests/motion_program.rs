//! Program evaluation: analytic values of every op, validation errors, and a
//! property test that interval bounds contain every sampled value.

mod motion_support;

use motion_support::{expr, Expr};
use proptest::prelude::*;
use rtlang::scene::motion::{Fn1, Fn2, Fn3, Op, Program, ProgramError, MAX_STACK};

fn run(ops: Vec<Op>, keys: Vec<(f32, f32)>, t: f32) -> f32 {
    Program::new(ops, keys).expect("valid program").eval(t)
}

#[test]
fn arithmetic_and_builtins_evaluate_exactly() {
    use Op::*;
    // (2 * t + 1) / 4 - 3 at t = 5
    let ops = vec![
        Const(2.0),
        Time,
        Mul,
        Const(1.0),
        Add,
        Const(4.0),
        Div,
        Const(3.0),
        Sub,
    ];
    assert_eq!(run(ops, vec![], 5.0), -0.25);
    assert_eq!(run(vec![Time, Neg], vec![], 2.0), -2.0);
    assert_eq!(run(vec![Time, Call1(Fn1::Sqrt)], vec![], 9.0), 3.0);
    assert_eq!(run(vec![Time, Call1(Fn1::Floor)], vec![], -1.5), -2.0);
    assert_eq!(run(vec![Time, Call1(Fn1::Abs)], vec![], -1.5), 1.5);
    assert!(
        (run(vec![Time, Call1(Fn1::Radians)], vec![], 180.0) - std::f32::consts::PI).abs() < 1e-6
    );
    assert!((run(vec![Time, Call1(Fn1::Sin)], vec![], 0.5) - 0.5f32.sin()).abs() < 1e-7);
    assert_eq!(
        run(vec![Time, Const(3.0), Call2(Fn2::Pow)], vec![], 2.0),
        8.0
    );
    assert_eq!(
        run(vec![Time, Const(3.0), Call2(Fn2::Min)], vec![], 2.0),
        2.0
    );
    assert_eq!(
        run(vec![Time, Const(3.0), Call2(Fn2::Max)], vec![], 2.0),
        3.0
    );
    let lerp = vec![Const(10.0), Const(20.0), Time, Call3(Fn3::Lerp)];
    assert_eq!(run(lerp, vec![], 0.25), 12.5);
    let clamp = vec![Time, Const(0.0), Const(1.0), Call3(Fn3::Clamp)];
    assert_eq!(run(clamp.clone(), vec![], 7.0), 1.0);
    assert_eq!(run(clamp, vec![], -7.0), 0.0);
}

#[test]
fn smoothstep_is_the_cubic_hermite_step() {
    let ops = vec![
        Op::Const(0.0),
        Op::Const(2.0),
        Op::Time,
        Op::Call3(Fn3::Smoothstep),
    ];
    let p = Program::new(ops, vec![]).expect("valid");
    assert_eq!(p.eval(-1.0), 0.0);
    assert_eq!(p.eval(1.0), 0.5);
    assert_eq!(p.eval(0.5), 0.15625); // u = 1/4: 3u² − 2u³
    assert_eq!(p.eval(3.0), 1.0);
    let hard = vec![
        Op::Const(1.0),
        Op::Const(1.0),
        Op::Time,
        Op::Call3(Fn3::Smoothstep),
    ];
    let hard = Program::new(hard, vec![]).expect("valid");
    assert_eq!((hard.eval(0.999), hard.eval(1.0)), (0.0, 1.0));
}

#[test]
fn keyframes_interpolate_and_hold_outside_the_table() {
    let keys = vec![(0.0, 1.0), (1.0, 3.0), (1.0, 5.0), (3.0, 9.0)];
    let table = |smooth| Op::Keyframes {
        start: 0,
        len: 4,
        smooth,
    };
    let linear = Program::new(vec![Op::Time, table(false)], keys.clone()).expect("valid");
    assert_eq!(linear.eval(-5.0), 1.0);
    assert_eq!(linear.eval(0.5), 2.0);
    assert_eq!(
        linear.eval(1.0),
        5.0,
        "a repeated key time jumps to the later key"
    );
    assert_eq!(linear.eval(2.0), 7.0);
    assert_eq!(linear.eval(10.0), 9.0);
    let smooth = Program::new(vec![Op::Time, table(true)], keys).expect("valid");
    assert_eq!(smooth.eval(0.5), 2.0, "eased midpoint is still the middle");
    assert_eq!(smooth.eval(0.25), 1.0 + 2.0 * 0.15625);
}

#[test]
fn validation_rejects_malformed_programs() {
    let err = |ops: Vec<Op>, keys: Vec<(f32, f32)>| Program::new(ops, keys).unwrap_err();
    assert_eq!(
        err(vec![Op::Add], vec![]),
        ProgramError::Underflow { at: 0 }
    );
    assert_eq!(err(vec![], vec![]), ProgramError::NotOneResult { left: 0 });
    assert_eq!(
        err(vec![Op::Time, Op::Time], vec![]),
        ProgramError::NotOneResult { left: 2 }
    );
    let deep = vec![Op::Time; MAX_STACK + 1];
    assert!(matches!(err(deep, vec![]), ProgramError::TooDeep { .. }));
    let kf = |start, len| {
        vec![
            Op::Time,
            Op::Keyframes {
                start,
                len,
                smooth: false,
            },
        ]
    };
    assert!(matches!(
        err(kf(1, 2), vec![(0.0, 0.0), (1.0, 1.0)]),
        ProgramError::KeysOutOfRange { .. }
    ));
    assert!(matches!(
        err(kf(u32::MAX, 2), vec![]),
        ProgramError::KeysOutOfRange { .. }
    ));
    assert!(matches!(
        err(kf(0, 0), vec![(0.0, 0.0)]),
        ProgramError::KeysEmpty { .. }
    ));
    assert!(matches!(
        err(kf(0, 2), vec![(1.0, 0.0), (0.0, 1.0)]),
        ProgramError::KeysUnsorted { .. }
    ));
    assert!(matches!(
        err(kf(0, 1), vec![(f32::NAN, 0.0)]),
        ProgramError::KeysUnsorted { .. }
    ));
    // Exactly MAX_STACK deep is fine.
    let mut ops = vec![Op::Time; MAX_STACK];
    ops.extend(std::iter::repeat_n(Op::Add, MAX_STACK - 1));
    assert_eq!(run(ops, vec![], 1.0), MAX_STACK as f32);
}

#[test]
fn interval_bounds_are_tight_where_the_answer_is_known() {
    use Op::*;
    let sin = Program::new(vec![Time, Call1(Fn1::Sin)], vec![]).expect("valid");
    let (lo, hi) = sin.eval_interval(0.0, 2.0);
    assert!(
        (lo - 0.0).abs() < 1e-5 && hi == 1.0,
        "sin over [0, 2]: {lo} {hi}"
    );
    let (lo, hi) = sin.eval_interval(-2.0, -1.0);
    assert!(lo == -1.0 && (hi - (-1.0f64).sin()).abs() < 1e-5);
    let cos = Program::new(vec![Time, Call1(Fn1::Cos)], vec![]).expect("valid");
    assert_eq!(cos.eval_interval(-0.1, 100.0), (-1.0, 1.0));
    let (lo, hi) = cos.eval_interval(0.1, 0.2);
    assert!((lo - 0.2f64.cos()).abs() < 1e-5 && (hi - 0.1f64.cos()).abs() < 1e-5);
    let inv = Program::new(vec![Const(1.0), Time, Div], vec![]).expect("valid");
    assert_eq!(
        inv.eval_interval(-1.0, 1.0),
        (f64::NEG_INFINITY, f64::INFINITY)
    );
    let (lo, hi) = inv.eval_interval(2.0, 4.0);
    assert!((lo - 0.25).abs() < 1e-6 && (hi - 0.5).abs() < 1e-6);
    let square = Program::new(vec![Time, Const(2.0), Call2(Fn2::Pow)], vec![]).expect("valid");
    let (lo, hi) = square.eval_interval(-1.0, 3.0);
    assert!(lo <= 0.0 && lo > -1e-6 && (hi - 9.0).abs() < 1e-5);
    let keys = vec![(0.0, 0.0), (1.0, 5.0), (2.0, -1.0)];
    let kf = Program::new(
        vec![
            Time,
            Keyframes {
                start: 0,
                len: 3,
                smooth: true,
            },
        ],
        keys,
    )
    .expect("valid");
    let (lo, hi) = kf.eval_interval(0.5, 1.5);
    assert!(
        (hi - 5.0).abs() < 1e-5 && (lo - 2.0).abs() < 1e-5,
        "{lo} {hi}"
    );
}

fn check_interval(e: &Expr, t0: f32, t1: f32) -> Result<(), TestCaseError> {
    let p = e.compile();
    prop_assert!(p.validate().is_ok());
    let (lo, hi) = p.eval_interval(t0, t1);
    for i in 0..=200 {
        let t = t0 + (t1 - t0) * i as f32 / 200.0;
        let v = p.eval(t.clamp(t0, t1)) as f64;
        if !v.is_nan() {
            prop_assert!(
                lo <= v && v <= hi,
                "{e:?} at t={t}: {v} outside [{lo}, {hi}]"
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

    #[test]
    fn interval_bounds_contain_every_sampled_value(e in expr(), a in -4.0f32..4.0, w in 0.0f32..3.0) {
        check_interval(&e, a, a + w)?;
    }
}
