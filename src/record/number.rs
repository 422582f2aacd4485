//! The recording number [`Recorded`] and the thread-local record it writes to.

use super::{op_at, Op, MAX_OPERATIONS};
use crate::error::{Error, Result};
use crate::series::number_traits;
use crate::series::power_by_squaring;
use num_dual::DualNum;
use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Rem, Sub};
use std::sync::atomic::{AtomicU32, Ordering};

/// The node of a constant (not on any record).
pub(super) const CONST: u32 = u32::MAX;

/// A value of the running operation record ([`record`](super::record)): the index of the
/// operation that made it and its value at the recording point. `Copy`, 16 bytes; implements
/// [`DualNum<f64>`], so functions written once for the crate's number types record unchanged.
/// Constants are not recorded until they meet a recorded value.
#[derive(Clone, Copy)]
pub struct Recorded {
    pub(super) tape: u32,
    pub(super) node: u32,
    pub(super) re: f64,
}

impl Recorded {
    /// The constant `c` (valid in every record).
    pub const fn constant(c: f64) -> Self {
        Self {
            tape: 0,
            node: CONST,
            re: c,
        }
    }

    /// The value at the recording point.
    pub fn value(&self) -> f64 {
        self.re
    }

    /// Whether this value is a constant (depends on no input).
    pub fn is_constant(&self) -> bool {
        self.node == CONST
    }
}

/// Key of an operation for hash-consing: kind, operands and constant (by its bits).
type Key = (u8, usize, usize, u64);

fn key(op: &Op) -> Option<Key> {
    Some(match *op {
        Op::Input(_) | Op::Const(_) | Op::Cos { .. } => return None,
        Op::Add(a, b) => (0, a.min(b), a.max(b), 0),
        Op::Sub(a, b) => (1, a, b, 0),
        Op::Mul(a, b) => (2, a.min(b), a.max(b), 0),
        Op::Div(a, b) => (3, a, b, 0),
        Op::Neg(a) => (4, a, 0, 0),
        Op::Shift(a, c) => (5, a, 0, c.to_bits()),
        Op::Scale(a, c) => (6, a, 0, c.to_bits()),
        Op::Recip(a) => (7, a, 0, 0),
        Op::Sqrt(a) => (8, a, 0, 0),
        Op::Exp(a) => (9, a, 0, 0),
        Op::Ln(a) => (10, a, 0, 0),
        Op::Sin { arg, .. } => (11, arg, 0, 0),
        Op::Powf(a, c) => (12, a, 0, c.to_bits()),
        Op::Atan2 { y, x, .. } => (13, y, x, 0),
        Op::Tanh(a) => (14, a, 0, 0),
    })
}

pub(crate) struct Tape {
    pub(super) id: u32,
    pub(super) ops: Vec<Op>,
    pub(super) values: Vec<f64>,
    memo: HashMap<Key, u32>,
    pub(super) fault: Option<String>,
}

thread_local! {
    static TAPE: RefCell<Option<Tape>> = const { RefCell::new(None) };
}

static NEXT_ID: AtomicU32 = AtomicU32::new(1);

/// Begin a record on this thread.
pub(super) fn open() -> Result<u32> {
    TAPE.with(|t| {
        let mut t = t.borrow_mut();
        if t.is_some() {
            return Err(Error::invalid(
                "operation record",
                "a record was begun while another is running on this thread",
            ));
        }
        let id = NEXT_ID.fetch_add(1, Ordering::Relaxed).max(1);
        *t = Some(Tape {
            id,
            ops: Vec::new(),
            values: Vec::new(),
            memo: HashMap::new(),
            fault: None,
        });
        Ok(id)
    })
}

/// End the record `id` and return it.
pub(super) fn close(id: u32) -> Result<Tape> {
    TAPE.with(|t| match t.borrow_mut().take() {
        Some(tape) if tape.id == id => Ok(tape),
        _ => Err(Error::invalid(
            "operation record",
            "the record was closed from inside its own function",
        )),
    })
}

pub(super) fn with_tape<R>(f: impl FnOnce(&mut Tape) -> R) -> Option<R> {
    TAPE.with(|t| t.borrow_mut().as_mut().map(f))
}

fn fail(reason: impl FnOnce() -> String) {
    with_tape(|t| {
        if t.fault.is_none() {
            t.fault = Some(reason());
        }
    });
}

/// Append `op` with value `v` (or find it already recorded).
pub(super) fn push(op: Op, v: f64) -> Recorded {
    with_tape(|t| {
        let k = key(&op);
        if let Some(&node) = k.as_ref().and_then(|k| t.memo.get(k)) {
            return Recorded {
                tape: t.id,
                node,
                re: t.values[node as usize],
            };
        }
        if t.ops.len() >= MAX_OPERATIONS {
            if t.fault.is_none() {
                t.fault = Some(format!("more than {MAX_OPERATIONS} operations"));
            }
            return Recorded::constant(f64::NAN);
        }
        let node = t.ops.len() as u32;
        t.ops.push(op);
        t.values.push(v);
        if let Some(k) = k {
            t.memo.insert(k, node);
        }
        Recorded {
            tape: t.id,
            node,
            re: v,
        }
    })
    .unwrap_or_else(|| Recorded::constant(f64::NAN))
}

/// The operation index of a recorded (non-constant) value, checked to belong to the running
/// record; `None` (and a fault) otherwise.
fn node(x: Recorded) -> Option<usize> {
    let ok = with_tape(|t| {
        if x.tape == t.id && (x.node as usize) < t.ops.len() {
            true
        } else {
            if t.fault.is_none() {
                t.fault = Some("a value of another record (or of none) was used".into());
            }
            false
        }
    });
    (ok == Some(true)).then_some(x.node as usize)
}

/// A constant made an operation (for operations without a constant form).
fn materialise(x: Recorded) -> Option<usize> {
    if x.node == CONST {
        node(push(Op::Const(x.re), x.re))
    } else {
        node(x)
    }
}

fn unary(x: Recorded, make: impl FnOnce(usize) -> Op, f: impl FnOnce(f64) -> f64) -> Recorded {
    let v = f(x.re);
    if x.node == CONST {
        return Recorded::constant(v);
    }
    match node(x) {
        Some(a) => push(make(a), v),
        None => Recorded::constant(f64::NAN),
    }
}

fn is(x: Recorded, c: f64) -> bool {
    x.node == CONST && x.re == c
}

fn add(a: Recorded, b: Recorded) -> Recorded {
    let v = a.re + b.re;
    match (a.node == CONST, b.node == CONST) {
        (true, true) => Recorded::constant(v),
        _ if is(a, 0.0) => b,
        _ if is(b, 0.0) => a,
        (true, false) => unary(b, |j| Op::Shift(j, a.re), |_| v),
        (false, true) => unary(a, |j| Op::Shift(j, b.re), |_| v),
        (false, false) => binary(a, b, Op::Add, v),
    }
}

fn sub(a: Recorded, b: Recorded) -> Recorded {
    let v = a.re - b.re;
    match (a.node == CONST, b.node == CONST) {
        (true, true) => Recorded::constant(v),
        _ if is(b, 0.0) => a,
        _ if is(a, 0.0) => neg(b),
        (true, false) => add(neg(b), a),
        (false, true) => unary(a, |j| Op::Shift(j, -b.re), |_| v),
        (false, false) => binary(a, b, Op::Sub, v),
    }
}

fn mul(a: Recorded, b: Recorded) -> Recorded {
    let v = a.re * b.re;
    match (a.node == CONST, b.node == CONST) {
        (true, true) => Recorded::constant(v),
        _ if is(a, 0.0) || is(b, 0.0) => Recorded::constant(0.0),
        _ if is(a, 1.0) => b,
        _ if is(b, 1.0) => a,
        _ if is(a, -1.0) => neg(b),
        _ if is(b, -1.0) => neg(a),
        (true, false) => unary(b, |j| Op::Scale(j, a.re), |_| v),
        (false, true) => unary(a, |j| Op::Scale(j, b.re), |_| v),
        (false, false) => binary(a, b, Op::Mul, v),
    }
}

fn div(a: Recorded, b: Recorded) -> Recorded {
    let v = a.re / b.re;
    match (a.node == CONST, b.node == CONST) {
        (true, true) => Recorded::constant(v),
        _ if is(b, 1.0) => a,
        _ if is(b, -1.0) => neg(a),
        _ if is(a, 0.0) => Recorded::constant(0.0),
        (false, true) => unary(a, |j| Op::Scale(j, b.re.recip()), |_| v),
        (true, false) => {
            let r = recip(b);
            if is(a, 1.0) {
                r
            } else {
                mul(r, a)
            }
        }
        (false, false) => binary(a, b, Op::Div, v),
    }
}

fn neg(a: Recorded) -> Recorded {
    if a.node != CONST {
        if let Some((Op::Neg(j), _)) = op_at(a.node) {
            return Recorded {
                node: j as u32,
                re: -a.re,
                ..a
            };
        }
    }
    unary(a, Op::Neg, |x| -x)
}

fn recip(a: Recorded) -> Recorded {
    unary(a, Op::Recip, f64::recip)
}

fn binary(a: Recorded, b: Recorded, make: fn(usize, usize) -> Op, v: f64) -> Recorded {
    match (node(a), node(b)) {
        (Some(i), Some(j)) => push(make(i, j), v),
        _ => Recorded::constant(f64::NAN),
    }
}

fn sin_cos(a: Recorded) -> (Recorded, Recorded) {
    let (s, c) = a.re.sin_cos();
    if a.node == CONST {
        return (Recorded::constant(s), Recorded::constant(c));
    }
    let Some(arg) = node(a) else {
        return (Recorded::constant(f64::NAN), Recorded::constant(f64::NAN));
    };
    let found = with_tape(|t| t.memo.get(&(11, arg, 0, 0)).copied()).flatten();
    let sin = match found {
        Some(n) => n as usize,
        None => {
            let n = with_tape(|t| t.ops.len()).unwrap_or(0);
            let sn = push(Op::Sin { arg, cos: n + 1 }, s);
            push(Op::Cos { arg, sin: n }, c);
            sn.node as usize
        }
    };
    let mk = |node: usize, re: f64| Recorded {
        tape: a.tape,
        node: node as u32,
        re,
    };
    (mk(sin, s), mk(sin + 1, c))
}

fn powi(x: Recorded, n: i32) -> Recorded {
    if x.node == CONST {
        return Recorded::constant(x.re.powi(n));
    }
    power_by_squaring(x, n, Recorded::constant(1.0), recip, mul)
}

fn powf(x: Recorded, a: f64) -> Recorded {
    if a.is_finite() && a.fract() == 0.0 && a.abs() <= 64.0 {
        return powi(x, a as i32);
    }
    if a == 0.5 {
        return unary(x, Op::Sqrt, f64::sqrt);
    }
    unary(x, |j| Op::Powf(j, a), |v| v.powf(a))
}

fn atan2(y: Recorded, x: Recorded) -> Recorded {
    let v = y.re.atan2(x.re);
    if y.node == CONST && x.node == CONST {
        return Recorded::constant(v);
    }
    let r = add(mul(x, x), mul(y, y));
    match (materialise(y), materialise(x), node(r)) {
        (Some(y), Some(x), Some(r)) => push(Op::Atan2 { y, x, r }, v),
        _ => Recorded::constant(f64::NAN),
    }
}

fn unsupported(what: &str) -> Recorded {
    let what = what.to_string();
    fail(|| format!("{what} has no operation in the record (no Taylor recurrence)"));
    Recorded::constant(f64::NAN)
}

/// The adjoint sweep (see [`gradient`](super::gradient)).
pub(super) fn gradient(y: Recorded, wrt: &[Recorded]) -> Vec<Recorded> {
    let zero = Recorded::constant(0.0);
    let mut out = vec![zero; wrt.len()];
    if y.node == CONST {
        return out;
    }
    let Some(top) = node(y) else {
        return out;
    };
    let mut inputs = Vec::with_capacity(wrt.len());
    for w in wrt {
        match node(*w).and_then(|i| op_at(i as u32).map(|(op, _)| (i, op))) {
            Some((i, Op::Input(_))) => inputs.push(i),
            _ => {
                fail(|| "gradient taken with respect to a value that is not an input".into());
                return out;
            }
        }
    }
    let mut adj: Vec<Recorded> = vec![zero; top + 1];
    adj[top] = Recorded::constant(1.0);
    let at = |i: usize| -> Recorded {
        let re = op_at(i as u32).map_or(f64::NAN, |(_, v)| v);
        Recorded {
            tape: y.tape,
            node: i as u32,
            re,
        }
    };
    for i in (0..=top).rev() {
        let w = adj[i];
        if is(w, 0.0) {
            continue;
        }
        let Some((op, _)) = op_at(i as u32) else {
            break;
        };
        let mut acc = |j: usize, d: Recorded| adj[j] = add(adj[j], d);
        match op {
            Op::Input(_) | Op::Const(_) => {}
            Op::Add(a, b) => {
                acc(a, w);
                acc(b, w);
            }
            Op::Sub(a, b) => {
                acc(a, w);
                acc(b, neg(w));
            }
            Op::Mul(a, b) => {
                acc(a, mul(w, at(b)));
                acc(b, mul(w, at(a)));
            }
            Op::Div(a, b) => {
                let q = div(w, at(b));
                acc(a, q);
                acc(b, neg(mul(q, at(i))));
            }
            Op::Neg(a) => acc(a, neg(w)),
            Op::Shift(a, _) => acc(a, w),
            Op::Scale(a, c) => acc(a, mul(w, Recorded::constant(c))),
            Op::Recip(a) => {
                let r = at(i);
                acc(a, neg(mul(w, mul(r, r))));
            }
            Op::Sqrt(a) => acc(a, div(mul(w, Recorded::constant(0.5)), at(i))),
            Op::Exp(a) => acc(a, mul(w, at(i))),
            Op::Ln(a) => acc(a, div(w, at(a))),
            Op::Tanh(a) => {
                let t = at(i);
                acc(a, mul(w, sub(Recorded::constant(1.0), mul(t, t))))
            }
            Op::Sin { arg, cos } => acc(arg, mul(w, at(cos))),
            Op::Cos { arg, sin } => acc(arg, neg(mul(w, at(sin)))),
            Op::Powf(a, c) => acc(a, mul(w, mul(powf(at(a), c - 1.0), Recorded::constant(c)))),
            Op::Atan2 { y, x, r } => {
                let q = div(w, at(r));
                acc(y, mul(q, at(x)));
                acc(x, neg(mul(q, at(y))));
            }
        }
    }
    for (o, &i) in out.iter_mut().zip(&inputs) {
        // An input recorded after `y` (which therefore does not depend on it) has adjoint 0.
        *o = adj.get(i).copied().unwrap_or(zero);
    }
    out
}

impl Add for Recorded {
    type Output = Recorded;
    fn add(self, rhs: Recorded) -> Recorded {
        add(self, rhs)
    }
}
impl Sub for Recorded {
    type Output = Recorded;
    fn sub(self, rhs: Recorded) -> Recorded {
        sub(self, rhs)
    }
}
impl Mul for Recorded {
    type Output = Recorded;
    fn mul(self, rhs: Recorded) -> Recorded {
        mul(self, rhs)
    }
}
impl Div for Recorded {
    type Output = Recorded;
    fn div(self, rhs: Recorded) -> Recorded {
        div(self, rhs)
    }
}
/// The remainder of constants; of recorded values it has no operation, and the record fails.
impl Rem for Recorded {
    type Output = Recorded;
    fn rem(self, rhs: Recorded) -> Recorded {
        if self.node == CONST && rhs.node == CONST {
            return Recorded::constant(self.re % rhs.re);
        }
        unsupported("the remainder `%`")
    }
}
impl Neg for Recorded {
    type Output = Recorded;
    fn neg(self) -> Recorded {
        neg(self)
    }
}
impl Neg for &Recorded {
    type Output = Recorded;
    fn neg(self) -> Recorded {
        neg(*self)
    }
}

number_traits!(Recorded);

impl fmt::Debug for Recorded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.node == CONST {
            write!(f, "Recorded::constant({:?})", self.re)
        } else {
            write!(
                f,
                "Recorded {{ record: {}, operation: {}, value: {:?} }}",
                self.tape, self.node, self.re
            )
        }
    }
}
impl fmt::Display for Recorded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.re)
    }
}

impl DualNum<f64> for Recorded {
    /// The largest order of the record's jets ([`MAX_ORDER`](super::MAX_ORDER)): an implicit
    /// function lifted by `NDERIV` frozen-Jacobian Newton steps in this type ([`crate::implicit`])
    /// is recorded with its Taylor coefficients exact to that order.
    const NDERIV: usize = super::MAX_ORDER;

    fn recip(&self) -> Self {
        recip(*self)
    }
    fn powi(&self, n: i32) -> Self {
        powi(*self, n)
    }
    fn powf(&self, a: f64) -> Self {
        powf(*self, a)
    }
    fn sqrt(&self) -> Self {
        unary(*self, Op::Sqrt, f64::sqrt)
    }
    fn cbrt(&self) -> Self {
        // ∛u = sign(u)·|u|^{1/3}, the sign taken at the recording point.
        if self.re < 0.0 {
            neg(powf(neg(*self), 1.0 / 3.0))
        } else {
            powf(*self, 1.0 / 3.0)
        }
    }
    fn exp(&self) -> Self {
        unary(*self, Op::Exp, f64::exp)
    }
    fn exp2(&self) -> Self {
        mul(*self, Recorded::constant(std::f64::consts::LN_2)).exp()
    }
    fn exp_m1(&self) -> Self {
        sub(self.exp(), Recorded::constant(1.0))
    }
    fn ln(&self) -> Self {
        unary(*self, Op::Ln, f64::ln)
    }
    fn log(&self, base: f64) -> Self {
        div(self.ln(), Recorded::constant(base.ln()))
    }
    fn log2(&self) -> Self {
        mul(self.ln(), Recorded::constant(std::f64::consts::LOG2_E))
    }
    fn log10(&self) -> Self {
        mul(self.ln(), Recorded::constant(std::f64::consts::LOG10_E))
    }
    fn ln_1p(&self) -> Self {
        add(*self, Recorded::constant(1.0)).ln()
    }
    fn sin(&self) -> Self {
        sin_cos(*self).0
    }
    fn cos(&self) -> Self {
        sin_cos(*self).1
    }
    fn tan(&self) -> Self {
        let (s, c) = sin_cos(*self);
        div(s, c)
    }
    fn sin_cos(&self) -> (Self, Self) {
        sin_cos(*self)
    }
    fn asin(&self) -> Self {
        let one = Recorded::constant(1.0);
        atan2(*self, sub(one, mul(*self, *self)).sqrt())
    }
    fn acos(&self) -> Self {
        let one = Recorded::constant(1.0);
        atan2(sub(one, mul(*self, *self)).sqrt(), *self)
    }
    fn atan(&self) -> Self {
        atan2(*self, Recorded::constant(1.0))
    }
    fn atan2(&self, other: Self) -> Self {
        atan2(*self, other)
    }
    fn sinh(&self) -> Self {
        let (e, f) = (self.exp(), neg(*self).exp());
        mul(sub(e, f), Recorded::constant(0.5))
    }
    fn cosh(&self) -> Self {
        let (e, f) = (self.exp(), neg(*self).exp());
        mul(add(e, f), Recorded::constant(0.5))
    }
    fn tanh(&self) -> Self {
        unary(*self, Op::Tanh, f64::tanh)
    }
    fn asinh(&self) -> Self {
        let r = add(mul(*self, *self), Recorded::constant(1.0)).sqrt();
        add(*self, r).ln()
    }
    fn acosh(&self) -> Self {
        let r = sub(mul(*self, *self), Recorded::constant(1.0)).sqrt();
        add(*self, r).ln()
    }
    fn atanh(&self) -> Self {
        let one = Recorded::constant(1.0);
        mul(
            div(add(one, *self), sub(one, *self)).ln(),
            Recorded::constant(0.5),
        )
    }
    fn sph_j0(&self) -> Self {
        if self.node == CONST {
            return Recorded::constant(self.re.sph_j0());
        }
        unsupported("the spherical Bessel function j₀")
    }
    fn sph_j1(&self) -> Self {
        if self.node == CONST {
            return Recorded::constant(self.re.sph_j1());
        }
        unsupported("the spherical Bessel function j₁")
    }
    fn sph_j2(&self) -> Self {
        if self.node == CONST {
            return Recorded::constant(self.re.sph_j2());
        }
        unsupported("the spherical Bessel function j₂")
    }
}
