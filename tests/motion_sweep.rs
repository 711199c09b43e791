//! Swept bounds against brute force: every transformed sample of the box at
//! every sampled time lies inside the swept box, and simple motions get a box
//! that is exact (translation) or close (rotation).

mod motion_support;

use glam::{Mat4, Vec3};
use motion_support::{expr, key_table, Expr};
use proptest::prelude::*;
use rtlang::geometry::sweep::swept_bounds;
use rtlang::geometry::Aabb;
use rtlang::scene::motion::{MotionStep, Op, Program};
use rtlang::scene::Motion;

/// A program mild enough to keep boxes finite: affine, sine or keyframes.
fn mild_program() -> impl Strategy<Value = Program> {
    let affine = (-2.0f32..2.0, -2.0f32..2.0).prop_map(|(a, b)| {
        Program::new(
            vec![Op::Const(a), Op::Const(b), Op::Time, Op::Mul, Op::Add],
            vec![],
        )
        .expect("valid")
    });
    let keyed = (key_table(), any::<bool>())
        .prop_map(|(k, smooth)| Expr::Keys(k, smooth, Box::new(Expr::Time)).compile());
    prop_oneof![affine, keyed, expr().prop_map(|e| e.compile())]
}

fn step() -> impl Strategy<Value = MotionStep> {
    let p3 = || [mild_program(), mild_program(), mild_program()];
    let axis = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_filter("non-zero axis", |(x, y, z)| x * x + y * y + z * z > 0.01)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z).normalize());
    prop_oneof![
        p3().prop_map(MotionStep::Translate),
        p3().prop_map(MotionStep::Scale),
        (axis, mild_program()).prop_map(|(axis, degrees)| MotionStep::Rotate { axis, degrees }),
        prop::array::uniform16(mild_program()).prop_map(|m| MotionStep::Matrix(Box::new(m))),
    ]
}

fn corners_and_points(b: &Aabb, seed: u32) -> Vec<Vec3> {
    let mut points: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            )
        })
        .collect();
    // A fixed low-discrepancy set of interior points.
    for k in 1..=8u32 {
        let f = |m: u32| ((k * m + seed) % 97) as f32 / 97.0;
        points.push(b.min + (b.max - b.min) * Vec3::new(f(13), f(29), f(61)));
    }
    points
}

fn sample_inside(motion: &Motion, local: &Aabb, t0: f32, t1: f32) -> Result<(), TestCaseError> {
    let swept = swept_bounds(motion, local, t0, t1);
    let compiled = motion.compile();
    let points = corners_and_points(local, 5);
    for i in 0..=300 {
        let t = (t0 + (t1 - t0) * i as f32 / 300.0).clamp(t0, t1);
        for m in [motion.matrix_at(t), compiled.matrix_at(t)] {
            for p in &points {
                let q = m.transform_point3(*p);
                if q.is_finite() {
                    prop_assert!(swept.contains(q), "t={t}: {q} outside {swept:?}");
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, rng_seed: proptest::test_runner::RngSeed::Fixed(11), ..ProptestConfig::default() })]

    #[test]
    fn swept_box_holds_every_sampled_point(
        steps in prop::collection::vec(step(), 1..4),
        lo in (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0),
        size in (0.0f32..3.0, 0.0f32..3.0, 0.0f32..3.0),
        t0 in -1.0f32..1.0,
        dt in 0.0f32..2.0,
    ) {
        let min = Vec3::new(lo.0, lo.1, lo.2);
        let local = Aabb::new(min, min + Vec3::new(size.0, size.1, size.2));
        sample_inside(&Motion { steps }, &local, t0, t0 + dt)?;
    }
}

fn affine(a: f32, b: f32) -> Program {
    Program::new(
        vec![Op::Const(a), Op::Const(b), Op::Time, Op::Mul, Op::Add],
        vec![],
    )
    .expect("valid")
}

#[test]
fn pure_translation_bound_is_the_exact_swept_box() {
    let local = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 0.5, 3.0));
    let motion = Motion {
        steps: vec![MotionStep::Translate([
            affine(0.0, 2.0),
            affine(1.0, -1.0),
            affine(0.0, 0.0),
        ])],
    };
    let swept = swept_bounds(&motion, &local, 0.0, 1.0);
    let exact = local
        .transformed(&Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)))
        .union(&local.transformed(&Mat4::from_translation(Vec3::new(2.0, 0.0, 0.0))));
    assert!(
        (swept.min - exact.min).abs().max_element() < 1e-4,
        "{swept:?} vs {exact:?}"
    );
    assert!(
        (swept.max - exact.max).abs().max_element() < 1e-4,
        "{swept:?} vs {exact:?}"
    );
}

#[test]
fn keyframed_translation_bound_is_exact_including_inner_keys() {
    let local = Aabb::new(Vec3::ZERO, Vec3::ONE);
    let keys = vec![(0.0, 0.0), (0.5, 4.0), (1.0, 1.0)];
    let x = Expr::Keys(keys, true, Box::new(Expr::Time)).compile();
    let motion = Motion {
        steps: vec![MotionStep::Translate([
            x,
            Program::constant(0.0),
            Program::constant(0.0),
        ])],
    };
    let swept = swept_bounds(&motion, &local, 0.0, 1.0);
    assert!(
        (swept.min.x - 0.0).abs() < 1e-4 && (swept.max.x - 5.0).abs() < 1e-4,
        "{swept:?}"
    );
}

#[test]
fn rotation_bound_is_close_to_the_sampled_box() {
    let local = Aabb::new(Vec3::new(1.0, -0.5, -0.5), Vec3::new(2.0, 0.5, 0.5));
    let degrees = affine(0.0, 90.0);
    let motion = Motion {
        steps: vec![
            MotionStep::Rotate {
                axis: Vec3::Y,
                degrees,
            },
            MotionStep::Translate([affine(0.0, 0.0), affine(0.0, 0.0), affine(3.0, 0.0)]),
        ],
    };
    let swept = swept_bounds(&motion, &local, 0.0, 1.0);
    let mut sampled = Aabb::EMPTY;
    for i in 0..=2000 {
        sampled = sampled.union(&local.transformed(&motion.matrix_at(i as f32 / 2000.0)));
    }
    let slack = (swept.extent() - sampled.extent()).max_element();
    assert!(
        slack >= 0.0 && slack < 0.1,
        "swept {swept:?} sampled {sampled:?}"
    );
}

#[test]
fn static_and_empty_cases() {
    let local = Aabb::new(Vec3::ZERO, Vec3::ONE);
    let identity = Motion::default();
    let swept = swept_bounds(&identity, &local, 0.0, 1.0);
    assert!((swept.min - local.min).abs().max_element() < 1e-5);
    assert!((swept.max - local.max).abs().max_element() < 1e-5);
    assert!(swept_bounds(&identity, &Aabb::EMPTY, 0.0, 1.0).is_empty());
    let c = identity.compile();
    assert!(c.is_identity() && c.fixed() == Some(Mat4::IDENTITY));
}

#[test]
fn compiled_motion_folds_constant_steps_and_matches() {
    let motion = Motion {
        steps: vec![
            MotionStep::Scale([
                Program::constant(2.0),
                Program::constant(2.0),
                Program::constant(2.0),
            ]),
            MotionStep::Rotate {
                axis: Vec3::Z,
                degrees: Program::constant(30.0),
            },
            MotionStep::Translate([
                affine(0.0, 1.0),
                Program::constant(0.0),
                Program::constant(0.0),
            ]),
            MotionStep::Translate([
                Program::constant(0.0),
                Program::constant(5.0),
                Program::constant(0.0),
            ]),
        ],
    };
    let compiled = motion.compile();
    assert!(compiled.fixed().is_none() && !motion.is_static());
    for t in [0.0f32, 0.3, 1.0] {
        let (a, b) = (motion.matrix_at(t), compiled.matrix_at(t));
        assert!(a.abs_diff_eq(b, 1e-5), "{a} vs {b}");
    }
    // The first step is applied first: scale then move by (t, 5, 0).
    let p = motion.matrix_at(1.0).transform_point3(Vec3::ZERO);
    assert!((p - Vec3::new(1.0, 5.0, 0.0)).length() < 1e-5);
    let q = motion.matrix_at(0.0).transform_point3(Vec3::X);
    let r = 30f32.to_radians();
    assert!((q - Vec3::new(2.0 * r.cos(), 2.0 * r.sin() + 5.0, 0.0)).length() < 1e-5);
    let still = Motion {
        steps: motion.steps[..2].to_vec(),
    };
    assert!(still.is_static() && still.compile().fixed().is_some());
}
