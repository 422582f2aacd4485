//! Normalised Taylor coefficients of every operation of a record: the jets of the Taylor method.

use super::program::{step, step_double_double, Instr, Program};
use super::Record;
use crate::error::{Error, Result};
use crate::series::ball::Field;
use crate::series::recurrences as rec;
use crate::special::double_double::DoubleDouble;

/// The largest order of [`Jets`].
pub const MAX_ORDER: usize = 200;

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
/// [`Jets::new`] translates the record once into its register program (see
/// [`Record::eval_into`]:
/// linear operations folded into scale factors, `sin`/`cos` pairs fused), each slot a jet of
/// `order + 1` coefficients. [`Jets::ode`] then runs order by order over the program, one
/// dispatch per instruction and order, the operands' offsets resolved in advance.
///
/// # Coefficients
/// The coefficients are doubles (`Jets<f64>`, the default), or, for the double-double Taylor
/// method, double-double numbers (crate-internal): the same program and the same recurrences
/// (generic over the coefficient field), the values of order 0 by the double-double elementary
/// functions. The record's constants and the scale factors folded into the program are
/// doubles in both (products of the record's constants rounded to double: exact for constants
/// such as `½`, `2`, `−1`).
///
/// References: À. Jorba & M. Zou, Exp. Math. 14 (2005) 99–117, §2 (the decomposition and the
/// order-by-order evaluation); A. Griewank & A. Walther, *Evaluating Derivatives*, 2nd ed.,
/// SIAM 2008, §13.2 (Taylor arithmetic over an evaluation trace).
#[derive(Clone, Debug)]
pub struct Jets<C = f64> {
    order: usize,
    stride: usize,
    c: Vec<C>,
    program: Program,
}

/// The coefficient types of [`Jets`]: `f64` and double-double numbers, each with its evaluation
/// of order 0 and its pass over the program for the orders above.
pub(crate) trait JetCoefficient: Field {
    /// The value (coefficient of order 0) of one instruction.
    fn order_zero(ins: Instr, c: &mut [Self]);
    /// The coefficients of order `k ≥ 1` of every instruction of `program`.
    fn pass(program: &[Instr], c: &mut [Self], k: usize);
}

impl JetCoefficient for f64 {
    #[inline]
    fn order_zero(ins: Instr, c: &mut [Self]) {
        step(ins, c, usize::MAX);
    }
    #[inline]
    fn pass(program: &[Instr], c: &mut [Self], k: usize) {
        pass(program, c, k);
    }
}

impl JetCoefficient for DoubleDouble {
    #[inline]
    fn order_zero(ins: Instr, c: &mut [Self]) {
        step_double_double(ins, c);
    }
    fn pass(program: &[Instr], c: &mut [Self], k: usize) {
        for ins in program {
            kth(*ins, c, k);
        }
    }
}

impl Jets<DoubleDouble> {
    /// [`Jets::new`] with double-double coefficients.
    ///
    /// # Errors
    /// As [`Jets::new`].
    pub(crate) fn double_double(record: &Record, order: usize) -> Result<Self> {
        Self::with_storage(record, order)
    }
}

impl<C> Jets<C> {
    /// The largest order the storage holds.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The number of instructions of the program (see [the program](Self#the-program)).
    pub fn instructions(&self) -> usize {
        self.program.len()
    }

    /// The series `x_{j,0} … x_{j,K}` of state variable `j` (`0 ≤ j < n`) from the last
    /// [`ode`](Jets::ode).
    ///
    /// # Panics
    /// If `j` is not a state variable.
    pub fn series(&self, j: usize) -> &[C] {
        assert!(
            j < self.program.outputs.len(),
            "state variable {j} of {}",
            self.program.outputs.len()
        );
        &self.c[(1 + j) * self.stride..(2 + j) * self.stride]
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
        Self::with_storage(record, order)
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
        let (o, alpha) = self.program.value[i];
        alpha * self.c[o + k]
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
        self.propagate(t0, x0, order)
    }
}

impl<C> Jets<C> {
    /// The program of `record` and storage for its jets (see [`Jets::new`]).
    fn with_storage(record: &Record, order: usize) -> Result<Self>
    where
        C: JetCoefficient,
    {
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
        let program = Program::with_stride(record, stride);
        let mut c = vec![C::default(); stride * program.slots];
        for &(w, x) in &program.consts {
            c[w] = C::exact(x);
        }
        // The time input t₀ + τ.
        c[1] = C::exact(1.0);
        Ok(Self {
            order,
            stride,
            c,
            program,
        })
    }

    /// [`Jets::ode`] over the coefficient field `C`.
    pub(crate) fn propagate(&mut self, t0: C, x0: &[C], order: usize) -> Result<()>
    where
        C: JetCoefficient,
    {
        let n = self.program.outputs.len();
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
        let values = |x: &[C]| x.iter().map(|v| v.value()).collect::<Vec<f64>>();
        crate::error::finite("Taylor series: initial time t₀", t0.value())?;
        if !t0.finite() {
            return Err(Error::NonFinite {
                what: "Taylor series: initial time t₀ (its low part)".into(),
                value: f64::NAN,
            });
        }
        if x0.iter().any(|v| !v.finite()) {
            crate::error::all_finite("Taylor series: initial state x₀", &values(x0))?;
            return Err(Error::NonFinite {
                what: "Taylor series: initial state x₀ (a low part)".into(),
                value: f64::NAN,
            });
        }
        let s = self.stride;
        let Jets { c, program, .. } = self;
        let (field, program) = (&program.outputs, &program.instructions);
        c[0] = t0;
        for (j, &x) in x0.iter().enumerate() {
            c[(1 + j) * s] = x;
        }
        for &ins in program.iter() {
            C::order_zero(ins, c);
        }
        advance(field, c, s, 0);
        for k in 1..order {
            C::pass(program, c, k);
            advance(field, c, s, k);
        }
        for j in 1..=n {
            let jet = &c[j * s..j * s + order + 1];
            // `v·0` is ±0 for a finite `v` and NaN otherwise: one branch per variable.
            if jet.iter().fold(0.0, |a, v| a + v.value() * 0.0) == 0.0 {
                continue;
            }
            if let Some(k) = jet.iter().position(|c| !c.finite()) {
                return Err(Error::NonFinite {
                    what: format!(
                        "Taylor coefficient {k} of state variable {} at t₀ = {:e}, x₀ = \
                         {:?} (a singularity of the equation)",
                        j - 1,
                        t0.value(),
                        values(x0),
                    ),
                    value: c[j * s + k].value(),
                });
            }
        }
        Ok(())
    }
}

/// `x_{j,k+1} = f_{j,k} / (k + 1)`.
#[inline]
fn advance<C: Field>(field: &[(usize, f64)], c: &mut [C], s: usize, k: usize) {
    for (j, &(o, alpha)) in field.iter().enumerate() {
        c[(1 + j) * s + k + 1] = c[o + k].scale_over_index(alpha, k + 1);
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
fn kth<C: Field>(ins: Instr, c: &mut [C], k: usize) {
    let jet = |o: usize| &c[o..=o + k];
    let low = |o: usize| &c[o..o + k];
    match ins {
        Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        } => c[w + k] = c[a + k].scale(alpha).add(c[b + k].scale(beta)),
        Instr::Affine { w, a, alpha, .. } => c[w + k] = c[a + k].scale(alpha),
        Instr::Mul { w, a, b } => c[w + k] = rec::product(jet(a), jet(b), k),
        Instr::MulAdd {
            w,
            a,
            b,
            alpha,
            c: d,
            beta,
        } => {
            c[w + k] = rec::product(jet(a), jet(b), k)
                .scale(alpha)
                .add(c[d + k].scale(beta))
        }
        Instr::Div { w, a, b } => c[w + k] = rec::quotient(c[a + k], jet(b), low(w), k),
        Instr::Recip { w, a } => c[w + k] = rec::quotient(C::default(), jet(a), low(w), k),
        Instr::Sqrt { w, a } => c[w + k] = rec::sqrt(jet(a), low(w), k),
        Instr::Exp { w, a } => c[w + k] = rec::integral_w_du(jet(a), low(w), k),
        Instr::Ln { w, a } => c[w + k] = rec::ln(jet(a), low(w), k),
        Instr::Powf { w, a, p } => c[w + k] = rec::power(jet(a), p, low(w), k),
        Instr::Tanh { w, s, a } => {
            c[w + k] = rec::integral_w_du(jet(a), low(s), k);
            c[s + k] = rec::product(&c[w..=w + k], &c[w..=w + k], k).neg();
        }
        Instr::SinCos { s, c: co, a } => {
            (c[s + k], c[co + k]) = rec::sin_cos(jet(a), low(s), low(co), -1.0, k)
        }
        Instr::Atan2 { w, y, x, r } => c[w + k] = rec::atan2(jet(y), jet(x), jet(r), low(w), k),
    }
}
