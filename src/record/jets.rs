//! Normalised Taylor coefficients of every operation of a record: the jets of the Taylor method.

use super::{Op, Record};
use crate::error::{Error, Result};
use crate::series::recurrences as rec;
use std::collections::HashMap;

/// The largest order of [`Jets`].
pub const MAX_ORDER: usize = 200;

/// One instruction of the program [`Jets`] runs; `w`, `a`, … are offsets of jets in the
/// coefficient buffer (slot × stride), so that the coefficient `k` of a jet is `c[offset + k]`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Instr {
    /// `w = α a + β b`.
    Lin {
        w: usize,
        a: usize,
        alpha: f64,
        b: usize,
        beta: f64,
    },
    /// `w = α a + γ` (`γ` enters the coefficient of order 0 only).
    Affine {
        w: usize,
        a: usize,
        alpha: f64,
        gamma: f64,
    },
    /// `w = a b`.
    Mul { w: usize, a: usize, b: usize },
    /// `w = a / b`.
    Div { w: usize, a: usize, b: usize },
    /// `w = 1 / a`.
    Recip { w: usize, a: usize },
    /// `w = √a`.
    Sqrt { w: usize, a: usize },
    /// `w = eᵃ`.
    Exp { w: usize, a: usize },
    /// `w = ln a`.
    Ln { w: usize, a: usize },
    /// `w = aᵖ`.
    Powf { w: usize, a: usize, p: f64 },
    /// `s = sin a`, `c = cos a`, the pair whose recurrences read each other.
    SinCos { s: usize, c: usize, a: usize },
    /// `w = atan2(y, x)`, `r = x² + y²`.
    Atan2 {
        w: usize,
        y: usize,
        x: usize,
        r: usize,
    },
}

/// The normalised Taylor coefficients `v_{i,0} … v_{i,K}` (`v_i(t₀ + τ) = Σ_k v_{i,k} τ^k`) of
/// every operation `i` of a [`Record`] of a differential equation, in one buffer allocated once:
/// the coefficients of an operation are computed from those of its operands by the recurrences
/// of [`series::recurrences`](crate::series::recurrences), `O(k)` each.
///
/// For an ordinary differential equation `ẋ = f(t, x)` recorded with inputs `(t, x₁ … x_n)` and
/// outputs `(f₁ … f_n)`, [`Jets::ode`] builds the Taylor series of the solution through
/// `(t₀, x₀)` order by order (Jorba & Zou 2005, §2):
///
/// ```math
/// x_{k+1} = \frac{f_k(x_0, \dots, x_k)}{k + 1},\qquad k = 0, \dots, K - 1,
/// ```
///
/// with the time input `t(t₀ + τ) = t₀ + τ`. The cost is `O(K²)` per nonlinear operation and no
/// allocation.
///
/// # The program
/// [`Jets::new`] translates the record once into a flat program over *slots* (jets in the
/// buffer), each operation of the record being `α ×` a slot:
///
/// * the linear operations are folded into the factors `α` — `c·u`, `−u` and `u + u` make no
///   instruction, `αu + βv` one, `αu + γ` one — since the coefficients of a linear combination
///   are the combinations of the coefficients;
/// * the factors pass through products and quotients, `(αu)(βv) = αβ·uv`,
///   `(αu)/(βv) = (α/β)·u/v`, `1/(αu) = α⁻¹·(1/u)`, and through `√(αu) = √α √u` and
///   `(αu)^p = α^p u^p` for `α > 0`;
/// * `sin u` and `cos u`, whose recurrences read each other, are one instruction over one
///   Cauchy sum of the argument.
///
/// [`Jets::ode`] then runs order by order over the program, one dispatch per instruction and
/// order, the operands' offsets resolved in advance.
///
/// References: À. Jorba & M. Zou, Exp. Math. 14 (2005) 99–117, §2 (the decomposition and the
/// order-by-order evaluation); A. Griewank & A. Walther, *Evaluating Derivatives*, 2nd ed.,
/// SIAM 2008, §13.2 (Taylor arithmetic over an evaluation trace).
#[derive(Clone, Debug)]
pub struct Jets {
    order: usize,
    stride: usize,
    c: Vec<f64>,
    program: Vec<Instr>,
    /// Every operation of the record as `(offset of a slot, α)`.
    value: Vec<(usize, f64)>,
    /// The outputs `f₁ … f_n` as `(offset, α)`.
    field: Vec<(usize, f64)>,
}

/// The translation of a record into slots and instructions (see [`Jets`]).
struct Compiler {
    stride: usize,
    slots: usize,
    program: Vec<Instr>,
    consts: Vec<(usize, f64)>,
    /// Slots holding `α × slot`, made when an operation needs its operand itself.
    scaled: HashMap<(usize, u64), usize>,
}

impl Compiler {
    /// A new slot's offset.
    fn slot(&mut self) -> usize {
        self.slots += 1;
        (self.slots - 1) * self.stride
    }

    /// The offset of a slot holding `α × slot` itself.
    fn materialise(&mut self, (a, alpha): (usize, f64)) -> usize {
        if alpha == 1.0 {
            return a;
        }
        if let Some(&w) = self.scaled.get(&(a, alpha.to_bits())) {
            return w;
        }
        let w = self.slot();
        self.program.push(Instr::Affine {
            w,
            a,
            alpha,
            gamma: 0.0,
        });
        self.scaled.insert((a, alpha.to_bits()), w);
        w
    }

    /// `αu + βv` of two values.
    fn lin(&mut self, (a, alpha): (usize, f64), (b, beta): (usize, f64)) -> (usize, f64) {
        if a == b {
            return (a, alpha + beta);
        }
        let w = self.slot();
        self.program.push(Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        });
        (w, 1.0)
    }

    /// A new slot computed by `make(w)`, with factor 1.
    fn emit(&mut self, make: impl FnOnce(usize) -> Instr) -> (usize, f64) {
        let w = self.slot();
        self.program.push(make(w));
        (w, 1.0)
    }

    /// The program of `record`: every operation as `(offset, α)`.
    fn translate(&mut self, record: &Record) -> Vec<(usize, f64)> {
        let mut value: Vec<Option<(usize, f64)>> = vec![None; record.len()];
        for v in value.iter_mut().take(record.inputs) {
            *v = Some((self.slot(), 1.0));
        }
        let at = |value: &[Option<(usize, f64)>], j: usize| value[j].unwrap_or((0, f64::NAN));
        for (i, op) in record.ops.iter().enumerate().skip(record.inputs) {
            if value[i].is_some() {
                // The partner of a `sin`/`cos` pair already made.
                continue;
            }
            let v = match *op {
                Op::Input(j) => at(&value, j),
                Op::Const(x) => {
                    let w = self.slot();
                    self.consts.push((w, x));
                    (w, 1.0)
                }
                Op::Add(a, b) => self.lin(at(&value, a), at(&value, b)),
                Op::Sub(a, b) => {
                    let (b, beta) = at(&value, b);
                    self.lin(at(&value, a), (b, -beta))
                }
                Op::Neg(a) => {
                    let (a, alpha) = at(&value, a);
                    (a, -alpha)
                }
                Op::Scale(a, x) => {
                    let (a, alpha) = at(&value, a);
                    (a, alpha * x)
                }
                Op::Shift(a, gamma) => {
                    let (a, alpha) = at(&value, a);
                    self.emit(|w| Instr::Affine { w, a, alpha, gamma })
                }
                Op::Mul(a, b) => {
                    let ((a, alpha), (b, beta)) = (at(&value, a), at(&value, b));
                    let (w, _) = self.emit(|w| Instr::Mul { w, a, b });
                    (w, alpha * beta)
                }
                Op::Div(a, b) => {
                    let ((a, alpha), (b, beta)) = (at(&value, a), at(&value, b));
                    let (w, _) = self.emit(|w| Instr::Div { w, a, b });
                    (w, alpha / beta)
                }
                Op::Recip(a) => {
                    let (a, alpha) = at(&value, a);
                    let (w, _) = self.emit(|w| Instr::Recip { w, a });
                    (w, alpha.recip())
                }
                Op::Sqrt(a) => match at(&value, a) {
                    (a, alpha) if alpha > 0.0 => {
                        let (w, _) = self.emit(|w| Instr::Sqrt { w, a });
                        (w, alpha.sqrt())
                    }
                    av => {
                        let a = self.materialise(av);
                        self.emit(|w| Instr::Sqrt { w, a })
                    }
                },
                Op::Powf(a, p) => match at(&value, a) {
                    (a, alpha) if alpha > 0.0 => {
                        let (w, _) = self.emit(|w| Instr::Powf { w, a, p });
                        (w, alpha.powf(p))
                    }
                    av => {
                        let a = self.materialise(av);
                        self.emit(|w| Instr::Powf { w, a, p })
                    }
                },
                Op::Exp(a) => {
                    let a = self.materialise(at(&value, a));
                    self.emit(|w| Instr::Exp { w, a })
                }
                Op::Ln(a) => {
                    let a = self.materialise(at(&value, a));
                    self.emit(|w| Instr::Ln { w, a })
                }
                Op::Sin { arg, cos: partner } | Op::Cos { arg, sin: partner } => {
                    let a = self.materialise(at(&value, arg));
                    let (s, c) = (self.slot(), self.slot());
                    self.program.push(Instr::SinCos { s, c, a });
                    let (this, other) = match op {
                        Op::Sin { .. } => (s, c),
                        _ => (c, s),
                    };
                    value[partner] = Some((other, 1.0));
                    (this, 1.0)
                }
                Op::Atan2 { y, x, r } => {
                    let y = self.materialise(at(&value, y));
                    let x = self.materialise(at(&value, x));
                    let r = self.materialise(at(&value, r));
                    self.emit(|w| Instr::Atan2 { w, y, x, r })
                }
            };
            value[i] = Some(v);
        }
        value
            .into_iter()
            .map(|v| v.unwrap_or((0, f64::NAN)))
            .collect()
    }
}

impl Jets {
    /// The program of the differential equation `record` (inputs `(t, x₁ … x_n)`, outputs
    /// `(f₁ … f_n)`; see [the program](Self#the-program)) and storage for its jets up to order
    /// `order` (`1 ≤ order ≤` [`MAX_ORDER`]).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for an order outside `1 … MAX_ORDER`; [`Error::InvalidInput`] when
    /// the record is not of that shape.
    pub fn new(record: &Record, order: usize) -> Result<Self> {
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(Error::out_of_domain(
                "Taylor order",
                order as f64,
                format!("1 … {MAX_ORDER}"),
            ));
        }
        let n = record.inputs.saturating_sub(1);
        if record.inputs < 2 || record.outputs.len() != n {
            return Err(Error::invalid(
                "Taylor series of a differential equation",
                format!(
                    "the record has {} inputs and {} outputs; expected (t, x₁ … x_n) in, \
                     (f₁ … f_n) out",
                    record.inputs,
                    record.outputs.len(),
                ),
            ));
        }
        let stride = order + 1;
        let mut compiler = Compiler {
            stride,
            slots: 0,
            program: Vec::new(),
            consts: Vec::new(),
            scaled: HashMap::new(),
        };
        let value = compiler.translate(record);
        let mut c = vec![0.0; stride * compiler.slots];
        for &(w, x) in &compiler.consts {
            c[w] = x;
        }
        // The time input t₀ + τ.
        c[1] = 1.0;
        let field = record.outputs.iter().map(|&o| value[o]).collect();
        Ok(Self {
            order,
            stride,
            c,
            program: compiler.program,
            value,
            field,
        })
    }

    /// The largest order the storage holds.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The number of instructions of the program (see [the program](Self#the-program)).
    pub fn instructions(&self) -> usize {
        self.program.len()
    }

    /// The coefficient `v_{i,k}` of operation `i` of the record (`k ≤` [`order`](Self::order);
    /// of the last [`ode`](Self::ode): orders below its `order` for every operation, up to it
    /// for the inputs).
    ///
    /// # Panics
    /// If `i` is not an operation of the record the jets were made for, or `k` exceeds the
    /// order.
    pub fn coefficient(&self, i: usize, k: usize) -> f64 {
        assert!(
            k <= self.order,
            "coefficient {k} beyond order {}",
            self.order
        );
        let (o, alpha) = self.value[i];
        alpha * self.c[o + k]
    }

    /// The series `x_{j,0} … x_{j,K}` of state variable `j` (`0 ≤ j < n`) from the last
    /// [`ode`](Self::ode).
    ///
    /// # Panics
    /// If `j` is not a state variable.
    pub fn series(&self, j: usize) -> &[f64] {
        assert!(
            j < self.field.len(),
            "state variable {j} of {}",
            self.field.len()
        );
        &self.c[(1 + j) * self.stride..(2 + j) * self.stride]
    }

    /// The Taylor series to order `order ≤` [`order`](Self::order) of the solution of the
    /// differential equation through `x(t₀) = x₀`; read them with [`series`](Self::series).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `x₀` has the wrong length; [`Error::OutOfDomain`] when
    /// `order` is 0 or exceeds the storage; [`Error::NonFinite`] for a non-finite `t₀` or `x₀`,
    /// and for a non-finite coefficient of the solution (a singularity of the equation at
    /// `(t₀, x₀)`, e.g. a collision).
    pub fn ode(&mut self, t0: f64, x0: &[f64], order: usize) -> Result<()> {
        let n = self.field.len();
        if x0.len() != n {
            return Err(Error::invalid(
                "Taylor series of a differential equation",
                format!("the state has {} entries for {n} equations", x0.len()),
            ));
        }
        if order > self.order || order == 0 {
            return Err(Error::out_of_domain(
                "Taylor order",
                order as f64,
                format!("1 … {} (the storage)", self.order),
            ));
        }
        crate::error::finite("Taylor series: initial time t₀", t0)?;
        crate::error::all_finite("Taylor series: initial state x₀", x0)?;
        let s = self.stride;
        let Jets {
            c, program, field, ..
        } = self;
        c[0] = t0;
        for (j, &x) in x0.iter().enumerate() {
            c[(1 + j) * s] = x;
        }
        for ins in program.iter() {
            zeroth(*ins, c);
        }
        advance(field, c, s, 0);
        for k in 1..order {
            pass(program, c, k);
            advance(field, c, s, k);
        }
        for j in 1..=n {
            if let Some(k) = c[j * s..j * s + order + 1]
                .iter()
                .position(|c| !c.is_finite())
            {
                return Err(Error::NonFinite {
                    what: format!(
                        "Taylor coefficient {k} of state variable {} at t₀ = {t0:e}, x₀ = \
                         {x0:?} (a singularity of the equation)",
                        j - 1
                    ),
                    value: c[j * s + k],
                });
            }
        }
        Ok(())
    }
}

/// `x_{j,k+1} = f_{j,k} / (k + 1)`.
#[inline]
fn advance(field: &[(usize, f64)], c: &mut [f64], s: usize, k: usize) {
    let scale = 1.0 / (k + 1) as f64;
    for (j, &(o, alpha)) in field.iter().enumerate() {
        c[(1 + j) * s + k + 1] = alpha * scale * c[o + k];
    }
}

/// The coefficient of order 0 of an instruction: its function at the point.
#[inline]
fn zeroth(ins: Instr, c: &mut [f64]) {
    match ins {
        Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        } => c[w] = alpha * c[a] + beta * c[b],
        Instr::Affine { w, a, alpha, gamma } => c[w] = alpha * c[a] + gamma,
        Instr::Mul { w, a, b } => c[w] = c[a] * c[b],
        Instr::Div { w, a, b } => c[w] = c[a] / c[b],
        Instr::Recip { w, a } => c[w] = c[a].recip(),
        Instr::Sqrt { w, a } => c[w] = c[a].sqrt(),
        Instr::Exp { w, a } => c[w] = c[a].exp(),
        Instr::Ln { w, a } => c[w] = c[a].ln(),
        Instr::Powf { w, a, p } => c[w] = c[a].powf(p),
        Instr::SinCos { s, c: co, a } => (c[s], c[co]) = c[a].sin_cos(),
        Instr::Atan2 { w, y, x, .. } => c[w] = c[y].atan2(c[x]),
    }
}

/// The coefficients of order `k ≥ 1` of every instruction of `program`: for `k ≤ 24` (orders of
/// tolerances down to about 10⁻²⁰) by the pass monomorphised for `k`, whose Cauchy sums have a
/// fixed length and are unrolled (one dispatch per order).
fn pass(program: &[Instr], c: &mut [f64], k: usize) {
    /// The pass for the order `K`.
    fn fixed<const K: usize>(program: &[Instr], c: &mut [f64]) {
        for ins in program {
            kth(*ins, c, K);
        }
    }
    macro_rules! dispatch {
        ($($k:literal)*) => {
            match k {
                $($k => fixed::<$k>(program, c),)*
                _ => {
                    for ins in program {
                        kth(*ins, c, k);
                    }
                }
            }
        };
    }
    dispatch!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24)
}

/// The coefficient of order `k ≥ 1` of an instruction from the lower ones.
#[inline(always)]
fn kth(ins: Instr, c: &mut [f64], k: usize) {
    let jet = |o: usize| &c[o..=o + k];
    let low = |o: usize| &c[o..o + k];
    match ins {
        Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        } => c[w + k] = alpha * c[a + k] + beta * c[b + k],
        Instr::Affine { w, a, alpha, .. } => c[w + k] = alpha * c[a + k],
        Instr::Mul { w, a, b } => c[w + k] = rec::product(jet(a), jet(b), k),
        Instr::Div { w, a, b } => c[w + k] = rec::quotient(c[a + k], jet(b), low(w), k),
        Instr::Recip { w, a } => c[w + k] = rec::quotient(0.0, jet(a), low(w), k),
        Instr::Sqrt { w, a } => c[w + k] = rec::sqrt(jet(a), low(w), k),
        Instr::Exp { w, a } => c[w + k] = rec::integral_w_du(jet(a), low(w), k),
        Instr::Ln { w, a } => c[w + k] = rec::ln(jet(a), low(w), k),
        Instr::Powf { w, a, p } => c[w + k] = rec::power(jet(a), p, low(w), k),
        Instr::SinCos { s, c: co, a } => {
            (c[s + k], c[co + k]) = rec::sin_cos(jet(a), low(s), low(co), -1.0, k)
        }
        Instr::Atan2 { w, y, x, r } => c[w + k] = rec::atan2(jet(y), jet(x), jet(r), low(w), k),
    }
}
