//! Conservative interval arithmetic over programs: [`Program::eval_interval`]
//! bounds every value [`Program::eval`] can return for `t` in an interval.
//!
//! Bounds are computed in f64 and every result is widened by a few f32 ulps of
//! its magnitude, so they also contain the rounding of the f32 evaluation.
//! Values that are NaN in f32 (the square root or logarithm of a negative
//! number, `pow` of a negative base) are not numbers and are not bounded;
//! every other result is, as long as no NaN is swallowed on the way (`min`
//! and `max` of a NaN return the other operand, which the bounds of that
//! `min`/`max` need not cover).

use std::f64::consts::{PI, TAU};
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::{smoothstep, Fn1, Fn2, Fn3, Op, Program, MAX_STACK};

/// A closed interval `[lo, hi]` of reals; infinite ends mean unbounded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

/// Relative widening applied to every result: 8 f32 ulps, covering the f32
/// rounding of the evaluation and the error of f32 `sin`, `exp` and `powf`.
const REL: f64 = 8.0 * f32::EPSILON as f64;
/// Absolute widening, so results near zero are widened too.
const ABS: f64 = 1e-30;

impl Interval {
    /// Every real number.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The interval between `a` and `b` (in either order); NaN gives
    /// [`Interval::ENTIRE`].
    pub fn new(a: f64, b: f64) -> Interval {
        if a.is_nan() || b.is_nan() {
            return Interval::ENTIRE;
        }
        Interval {
            lo: a.min(b),
            hi: a.max(b),
        }
    }

    /// The single point `x`.
    pub fn point(x: f64) -> Interval {
        Interval::new(x, x)
    }

    /// The smallest interval holding all of `values`.
    fn hull(values: &[f64]) -> Interval {
        if values.iter().any(|v| v.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval { lo, hi }
    }

    /// Whether `x` lies in the interval.
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// The smallest interval holding both.
    pub fn union(&self, o: &Interval) -> Interval {
        Interval {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Widened outward by the rounding allowance of an f32 operation; an end
    /// beyond the f32 range becomes infinite, as the f32 result overflows.
    pub fn widen(self) -> Interval {
        let lo = self.lo - REL * self.lo.abs() - ABS;
        let hi = self.hi + REL * self.hi.abs() + ABS;
        let max = f32::MAX as f64;
        Interval {
            lo: if lo < -max { f64::NEG_INFINITY } else { lo },
            hi: if hi > max { f64::INFINITY } else { hi },
        }
    }

    pub fn min(self, o: Interval) -> Interval {
        Interval::new(self.lo.min(o.lo), self.hi.min(o.hi))
    }

    pub fn max(self, o: Interval) -> Interval {
        Interval::new(self.lo.max(o.lo), self.hi.max(o.hi))
    }

    /// Image under a non-decreasing function.
    fn monotone(self, f: impl Fn(f64) -> f64) -> Interval {
        Interval::new(f(self.lo), f(self.hi)).widen()
    }

    /// The image under `sin`.
    pub fn sin(self) -> Interval {
        self.periodic(f64::sin, PI / 2.0)
    }

    /// The image under `cos`.
    pub fn cos(self) -> Interval {
        self.periodic(f64::cos, 0.0)
    }

    /// A sine-like function with its extrema: `peak` is where the function is 1 (π/2 for
    /// sin, 0 for cos); the minimum lies π further on.
    fn periodic(self, f: impl Fn(f64) -> f64, peak: f64) -> Interval {
        if self.hi - self.lo >= TAU {
            return Interval::new(-1.0, 1.0);
        }
        let hits = |at: f64| {
            let k = ((self.lo - at) / TAU).ceil();
            at + k * TAU <= self.hi
        };
        let ends = Interval::new(f(self.lo), f(self.hi)).widen();
        let hi = if hits(peak) { 1.0 } else { ends.hi.min(1.0) };
        let lo = if hits(peak + PI) {
            -1.0
        } else {
            ends.lo.max(-1.0)
        };
        Interval { lo, hi }
    }

    fn tan(self) -> Interval {
        // Poles at π/2 + kπ; between two poles tan increases.
        let k = ((self.lo - PI / 2.0) / PI).ceil();
        if self.hi - self.lo >= PI || PI / 2.0 + k * PI <= self.hi {
            return Interval::ENTIRE;
        }
        self.monotone(f64::tan)
    }

    fn abs(self) -> Interval {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            self.neg()
        } else {
            Interval::new(0.0, self.hi.max(-self.lo))
        }
    }

    /// `x^y`: exact powers by integer constants, `exp(y·ln x)` for positive
    /// bases, and unbounded where the base may be negative.
    fn pow(self, y: Interval) -> Interval {
        if y.lo == y.hi && y.lo.fract() == 0.0 && y.lo.abs() <= 64.0 {
            return self.powi(y.lo as i32);
        }
        if self.lo > 0.0 {
            return y.mul(self.monotone(f64::ln)).monotone(f64::exp);
        }
        if self.lo >= 0.0 && y.lo > 0.0 {
            let top = self.hi.powf(y.lo).max(self.hi.powf(y.hi));
            return Interval::new(0.0, top).widen();
        }
        Interval::ENTIRE
    }

    fn powi(self, n: i32) -> Interval {
        if n == 0 {
            return Interval::point(1.0);
        }
        if self.contains(0.0) && self.lo != self.hi {
            if n < 0 {
                return Interval::ENTIRE;
            }
            if n % 2 == 0 {
                return Interval::new(0.0, self.lo.powi(n).max(self.hi.powi(n))).widen();
            }
        }
        // On an interval of one sign (or any interval for odd positive n)
        // x^n is monotone.
        Interval::new(self.lo.powi(n), self.hi.powi(n)).widen()
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, o: Interval) -> Interval {
        Interval::new(self.lo + o.lo, self.hi + o.hi).widen()
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, o: Interval) -> Interval {
        Interval::new(self.lo - o.hi, self.hi - o.lo).widen()
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, o: Interval) -> Interval {
        let p = |a: f64, b: f64| if a == 0.0 || b == 0.0 { 0.0 } else { a * b };
        Interval::hull(&[
            p(self.lo, o.lo),
            p(self.lo, o.hi),
            p(self.hi, o.lo),
            p(self.hi, o.hi),
        ])
        .widen()
    }
}

impl Div for Interval {
    type Output = Interval;
    /// Division; a divisor that contains 0 gives [`Interval::ENTIRE`].
    fn div(self, o: Interval) -> Interval {
        if o.contains(0.0) {
            return Interval::ENTIRE;
        }
        self * Interval::new(1.0 / o.lo, 1.0 / o.hi).widen()
    }
}

impl Program {
    /// Bounds of [`Program::eval`] over every `t` in `[lo, hi]` (see the
    /// module doc for how NaN is treated). Allocation-free.
    pub fn eval_interval(&self, lo: f32, hi: f32) -> (f64, f64) {
        let r = self.interval(Interval::new(lo as f64, hi as f64));
        (r.lo, r.hi)
    }

    /// Bounds of [`Program::eval`] over every `t` in `time`.
    pub fn interval(&self, time: Interval) -> Interval {
        self.bounds(time).0
    }

    /// Whether [`Program::eval`] is a finite f32 for every `t` in
    /// `[lo, hi]`: proved with bounds on ever smaller pieces of the interval
    /// (down to 2⁻¹⁰ of it), and disproved by a time where it is not.
    pub fn finiteness(&self, lo: f32, hi: f32) -> Finiteness {
        self.finiteness_in(lo as f64, hi as f64, 0)
    }

    fn finiteness_in(&self, lo: f64, hi: f64, depth: u32) -> Finiteness {
        let (r, in_domain) = self.bounds(Interval::new(lo, hi));
        if in_domain && r.lo.is_finite() && r.hi.is_finite() {
            return Finiteness::Finite;
        }
        let mid = lo + (hi - lo) / 2.0;
        for t in [lo, mid, hi] {
            if !self.eval(t as f32).is_finite() {
                return Finiteness::NotFiniteAt(t as f32);
            }
        }
        if depth == FINITENESS_SPLITS || mid <= lo || mid >= hi {
            return Finiteness::Unproven;
        }
        match self.finiteness_in(lo, mid, depth + 1) {
            Finiteness::Finite => self.finiteness_in(mid, hi, depth + 1),
            other => other,
        }
    }

    /// Bounds over `time`, and whether every operation stays inside its
    /// domain there (no square root or logarithm of a possibly negative
    /// number, no `pow` of a possibly negative base by a non-integer, no
    /// smoothstep of unbounded arguments): where one may not, the f32 value
    /// can be NaN although the bounds, which skip NaN, are finite.
    fn bounds(&self, time: Interval) -> (Interval, bool) {
        let mut stack = [Interval::ENTIRE; MAX_STACK];
        let mut sp = 0usize;
        let mut in_domain = true;
        for op in &self.ops {
            in_domain &= stays_in_domain(*op, &stack[..sp]);
            match *op {
                Op::Const(c) => {
                    stack[sp] = Interval::point(c as f64);
                    sp += 1;
                }
                Op::Time => {
                    stack[sp] = time;
                    sp += 1;
                }
                Op::Neg => stack[sp - 1] = stack[sp - 1].neg(),
                Op::Call1(f) => stack[sp - 1] = call1(f, stack[sp - 1]),
                Op::Keyframes { start, len, smooth } => {
                    let table = &self.keys[start as usize..(start + len) as usize];
                    stack[sp - 1] = keyframes(table, smooth, stack[sp - 1]);
                }
                Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Call2(_) => {
                    sp -= 1;
                    let (a, b) = (stack[sp - 1], stack[sp]);
                    stack[sp - 1] = match *op {
                        Op::Add => a.add(b),
                        Op::Sub => a.sub(b),
                        Op::Mul => a.mul(b),
                        Op::Div => a.div(b),
                        Op::Call2(Fn2::Min) => a.min(b),
                        Op::Call2(Fn2::Max) => a.max(b),
                        Op::Call2(Fn2::Pow) => a.pow(b),
                        _ => unreachable!("matched as a binary op above"),
                    };
                }
                Op::Call3(f) => {
                    sp -= 2;
                    stack[sp - 1] = call3(f, stack[sp - 1], stack[sp], stack[sp + 1]);
                }
            }
        }
        (stack[0], in_domain)
    }
}

/// How many times [`Program::finiteness`] may halve the interval.
const FINITENESS_SPLITS: u32 = 10;

/// What [`Program::finiteness`] finds over an interval of times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Finiteness {
    /// Every value is a finite f32.
    Finite,
    /// At this time the value is NaN or infinite.
    NotFiniteAt(f32),
    /// Not proved finite, and no time tried gives a non-finite value.
    Unproven,
}

/// Whether `op`, applied to operands bounded by the top of `stack`, cannot
/// produce a NaN that its bounds skip.
fn stays_in_domain(op: Op, stack: &[Interval]) -> bool {
    let top = |k: usize| stack[stack.len() - k];
    match op {
        Op::Call1(Fn1::Sqrt) => top(1).lo >= 0.0,
        Op::Call1(Fn1::Ln) => top(1).lo > 0.0,
        Op::Call2(Fn2::Pow) => {
            let y = top(1);
            top(2).lo >= 0.0 || (y.lo == y.hi && y.lo.fract() == 0.0)
        }
        Op::Call3(Fn3::Smoothstep) => {
            (1..=3).all(|k| top(k).lo.is_finite() && top(k).hi.is_finite())
        }
        _ => true,
    }
}

fn call1(f: Fn1, x: Interval) -> Interval {
    match f {
        Fn1::Sin => x.sin(),
        Fn1::Cos => x.cos(),
        Fn1::Tan => x.tan(),
        Fn1::Sqrt => {
            if x.hi < 0.0 {
                Interval::ENTIRE
            } else {
                Interval::new(x.lo.max(0.0), x.hi).monotone(f64::sqrt)
            }
        }
        Fn1::Abs => x.abs(),
        Fn1::Radians => x.mul(Interval::point(f32::to_radians(1.0) as f64)),
        Fn1::Degrees => x.mul(Interval::point(f32::to_degrees(1.0) as f64)),
        Fn1::Exp => x.monotone(f64::exp),
        Fn1::Ln => {
            if x.hi < 0.0 {
                Interval::ENTIRE
            } else {
                Interval::new(x.lo.max(0.0), x.hi).monotone(f64::ln)
            }
        }
        Fn1::Floor => Interval::new(x.lo.floor(), x.hi.floor()),
    }
}

fn call3(f: Fn3, a: Interval, b: Interval, c: Interval) -> Interval {
    match f {
        Fn3::Lerp => a.add(b.sub(a).mul(c)),
        Fn3::Clamp => a.max(b).min(c),
        Fn3::Smoothstep => smoothstep_interval(a, b, c),
    }
}

/// Where the edges cannot cross, smoothstep is monotone in each argument, so
/// its extrema over the box lie at the eight corners; otherwise [0, 1].
fn smoothstep_interval(e0: Interval, e1: Interval, x: Interval) -> Interval {
    let overlap = e0.lo <= e1.hi && e1.lo <= e0.hi;
    let finite = [e0.lo, e0.hi, e1.lo, e1.hi, x.lo, x.hi]
        .iter()
        .all(|v| v.is_finite());
    if overlap || !finite {
        return Interval::new(0.0, 1.0);
    }
    let mut corners = [0.0f64; 8];
    for (i, c) in corners.iter_mut().enumerate() {
        let pick = |iv: Interval, bit: usize| if i & bit == 0 { iv.lo } else { iv.hi };
        *c = smoothstep(pick(e0, 1) as f32, pick(e1, 2) as f32, pick(x, 4) as f32) as f64;
    }
    let r = Interval::hull(&corners).widen();
    Interval::new(r.lo.max(0.0), r.hi.min(1.0))
}

/// The keyframe function is monotone between keys and constant outside the
/// table, so its range over `x` is spanned by the values at the ends of `x`
/// and at every key time inside it. The ends are rounded to f32 first, as the
/// evaluation sees them: no f32 input lies outside the rounded ends.
fn keyframes(table: &[(f32, f32)], smooth: bool, x: Interval) -> Interval {
    let (lo, hi) = (x.lo as f32, x.hi as f32);
    let at = |v: f32| super::keyframes(table, smooth, v) as f64;
    let mut r = Interval::new(at(lo), at(hi));
    for &(time, value) in table {
        if lo <= time && time <= hi {
            r = r.union(&Interval::point(value as f64));
        }
    }
    r.widen()
}
