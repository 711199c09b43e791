//! Bézier math of the profile: evaluation, derivative, de Casteljau
//! splitting and control-point bounds, for degrees 1 to 5.

use glam::DVec2;
use rtlang::scene::curve::{control_bounds, derivative, point, split, sub_curve};

fn curves() -> Vec<Vec<DVec2>> {
    let all = [
        (-2.0, 2.0),
        (-4.0, 0.0),
        (0.0, 0.0),
        (-2.0, -2.0),
        (1.5, 3.0),
        (0.0, -1.0),
    ]
    .map(|(x, y)| DVec2::new(x, y));
    (2..=6).map(|n| all[..n].to_vec()).collect()
}

#[test]
fn endpoints_and_a_straight_line_are_exact() {
    for c in curves() {
        assert_eq!(point(&c, 0.0), c[0]);
        assert!((point(&c, 1.0) - c[c.len() - 1]).length() < 1e-12);
    }
    let line = [DVec2::new(0.0, 0.0), DVec2::new(2.0, 4.0)];
    assert_eq!(point(&line, 0.25), DVec2::new(0.5, 1.0));
    assert_eq!(derivative(&line, 0.7), DVec2::new(2.0, 4.0));
}

#[test]
fn derivative_matches_finite_differences() {
    for c in curves() {
        for s in [0.0, 0.3, 0.5, 0.99] {
            let h = 1e-6;
            let fd = (point(&c, s + h) - point(&c, s - h)) / (2.0 * h);
            assert!(
                (derivative(&c, s) - fd).length() < 1e-6,
                "degree {}",
                c.len() - 1
            );
        }
    }
}

#[test]
fn split_and_sub_curves_trace_the_same_curve() {
    for c in curves() {
        let (left, right) = split(&c, 0.3);
        let piece = sub_curve(&c, 0.2, 0.7);
        for u in [0.0, 0.25, 0.5, 1.0] {
            assert!((point(&left, u) - point(&c, 0.3 * u)).length() < 1e-12);
            assert!((point(&right, u) - point(&c, 0.3 + 0.7 * u)).length() < 1e-12);
            assert!((point(&piece, u) - point(&c, 0.2 + 0.5 * u)).length() < 1e-12);
        }
    }
}

#[test]
fn control_bounds_hold_the_curve_and_are_the_control_box() {
    for c in curves() {
        let (lo, hi) = control_bounds(&c);
        for i in 0..=100 {
            let p = point(&c, i as f64 / 100.0);
            assert!(p.cmpge(lo - 1e-12).all() && p.cmple(hi + 1e-12).all());
        }
    }
    let (lo, hi) = control_bounds(&curves()[2]);
    assert_eq!((lo, hi), (DVec2::new(-4.0, -2.0), DVec2::new(0.0, 2.0)));
}
