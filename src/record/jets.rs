//! Normalised Taylor coefficients of every operation of a record: the jets of the Taylor method.

use super::program::{step, Instr, Program};
use super::Record;
use crate::error::{Error, Result};
use crate::series::recurrences as rec;

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
/// References: À. Jorba & M. Zou, Exp. Math. 14 (2005) 99–117, §2 (the decomposition and the
/// order-by-order evaluation); A. Griewank & A. Walther, *Evaluating Derivatives*, 2nd ed.,
/// SIAM 2008, §13.2 (Taylor arithmetic over an evaluation trace).
#[derive(Clone, Debug)]
pub struct Jets {
    order: usize,
    stride: usize,
    c: Vec<f64>,
    program: Program,
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
        let program = Program::with_stride(record, stride);
        let mut c = vec![0.0; stride * program.slots];
        for &(w, x) in &program.consts {
            c[w] = x;
        }
        // The time input t₀ + τ.
        c[1] = 1.0;
        Ok(Self {
            order,
            stride,
            c,
            program,
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
        let (o, alpha) = self.program.value[i];
        alpha * self.c[o + k]
    }

    /// The series `x_{j,0} … x_{j,K}` of state variable `j` (`0 ≤ j < n`) from the last
    /// [`ode`](Self::ode).
    ///
    /// # Panics
    /// If `j` is not a state variable.
    pub fn series(&self, j: usize) -> &[f64] {
        assert!(
            j < self.program.outputs.len(),
            "state variable {j} of {}",
            self.program.outputs.len()
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
        crate::error::finite("Taylor series: initial time t₀", t0)?;
        crate::error::all_finite("Taylor series: initial state x₀", x0)?;
        let s = self.stride;
        let Jets { c, program, .. } = self;
        let (field, program) = (&program.outputs, &program.instructions);
        c[0] = t0;
        for (j, &x) in x0.iter().enumerate() {
            c[(1 + j) * s] = x;
        }
        for &ins in program.iter() {
            step(ins, c, usize::MAX);
        }
        advance(field, c, s, 0);
        for k in 1..order {
            pass(program, c, k);
            advance(field, c, s, k);
        }
        for j in 1..=n {
            let jet = &c[j * s..j * s + order + 1];
            // `v·0` is ±0 for a finite `v` and NaN otherwise: one branch per variable.
            if jet.iter().fold(0.0, |a, &v| a + v * 0.0) == 0.0 {
                continue;
            }
            if let Some(k) = jet.iter().position(|c| !c.is_finite()) {
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
        Instr::MulAdd {
            w,
            a,
            b,
            alpha,
            c: d,
            beta,
        } => c[w + k] = alpha * rec::product(jet(a), jet(b), k) + beta * c[d + k],
        Instr::Div { w, a, b } => c[w + k] = rec::quotient(c[a + k], jet(b), low(w), k),
        Instr::Recip { w, a } => c[w + k] = rec::quotient(0.0, jet(a), low(w), k),
        Instr::Sqrt { w, a } => c[w + k] = rec::sqrt(jet(a), low(w), k),
        Instr::Exp { w, a } => c[w + k] = rec::integral_w_du(jet(a), low(w), k),
        Instr::Ln { w, a } => c[w + k] = rec::ln(jet(a), low(w), k),
        Instr::Powf { w, a, p } => c[w + k] = rec::power(jet(a), p, low(w), k),
        Instr::Tanh { w, s, a } => {
            c[w + k] = rec::integral_w_du(jet(a), low(s), k);
            c[s + k] = -rec::product(&c[w..=w + k], &c[w..=w + k], k);
        }
        Instr::SinCos { s, c: co, a } => {
            (c[s + k], c[co + k]) = rec::sin_cos(jet(a), low(s), low(co), -1.0, k)
        }
        Instr::Atan2 { w, y, x, r } => c[w + k] = rec::atan2(jet(y), jet(x), jet(r), low(w), k),
    }
}
