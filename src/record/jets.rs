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
/// `order + 1` coefficients.
///
/// Under the feature `jit` (on by default) the pass of [`Jets::ode`] to the storage's order is
/// **compiled once per record and order by the Cranelift code generator** into one native
/// function of straight-line code — the recurrences unrolled for every instruction and order,
/// each coefficient a register value stored once, the Cauchy sums summed pairwise, the
/// products `j·u_j` shared by the sums that read them (`sin` and `cos` both), `1/k` constants
/// (the module `taylor_jit`; heyoka's approach, Biscani & Izzo 2021). The passes of the latest
/// 32 (record, order) pairs are kept, so that later [`Jets`] of an equal record and the same
/// order do not compile again; [`compile_time`](Jets::compile_time) reports what compiling took.
/// Its order-0 values are the interpreter's bit for bit, its higher coefficients differ from
/// the interpreter's by the reordering of the sums only (`≲ 3kε` of the sum of the terms'
/// magnitudes, tested).
///
/// The **interpreter** runs otherwise — the feature off, a pass larger than `instructions × K²
/// ≤ 2¹⁸`, a host Cranelift does not support, or an [`ode`](Jets::ode) to a lower order than
/// the storage's: order by order over the program, one dispatch per instruction and order,
/// the operands' offsets resolved in advance.
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
/// SIAM 2008, §13.2 (Taylor arithmetic over an evaluation trace); F. Biscani & D. Izzo,
/// MNRAS 504 (2021) 2614–2628 (the compiled Taylor decomposition of heyoka).
#[derive(Clone, Debug)]
pub struct Jets<C = f64> {
    order: usize,
    stride: usize,
    c: Vec<C>,
    program: Program,
    /// The pass to `order` compiled to native code, when there is one.
    #[cfg(feature = "jit")]
    native: Option<std::sync::Arc<super::taylor_jit::TaylorPass>>,
}

/// The compiled passes made so far, at most [`CACHED`]: record, order, pass (`None`: not
/// compilable), the latest last.
#[cfg(feature = "jit")]
type Cache = Vec<(
    Record,
    usize,
    Option<std::sync::Arc<super::taylor_jit::TaylorPass>>,
)>;

/// The number of compiled passes kept for reuse.
#[cfg(feature = "jit")]
const CACHED: usize = 32;

/// The compiled pass of `record` to `order` (its program `program`): compiled at the first
/// request and kept, with those of the latest [`CACHED`] (record, order) pairs, for every later
/// [`Jets`] of an equal record and the same order (a run of the Taylor method records its
/// equations anew; its repetitions do not compile again).
#[cfg(feature = "jit")]
fn compiled(
    record: &Record,
    program: &Program,
    order: usize,
) -> Option<std::sync::Arc<super::taylor_jit::TaylorPass>> {
    static CACHE: std::sync::Mutex<Cache> = std::sync::Mutex::new(Vec::new());
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(at) = cache
        .iter()
        .position(|(r, o, _)| *o == order && r == record)
    {
        let entry = cache.remove(at);
        let pass = entry.2.clone();
        cache.push(entry);
        return pass;
    }
    let pass = super::taylor_jit::TaylorPass::compile(program, order).map(std::sync::Arc::new);
    if cache.len() >= CACHED {
        cache.remove(0);
    }
    cache.push((record.clone(), order, pass.clone()));
    pass
}

/// The coefficient types of [`Jets`]: `f64` and double-double numbers, each with its evaluation
/// of order 0 and its pass over the program for the orders above.
pub(crate) trait JetCoefficient: Field {
    /// The value (coefficient of order 0) of one instruction.
    fn order_zero(ins: Instr, c: &mut [Self]);
    /// The coefficients of order `k ≥ 1` of every instruction of `program`.
    fn pass(program: &[Instr], c: &mut [Self], k: usize);
    /// The pass to `order` from the loaded coefficients of order 0 by compiled code, with the
    /// check of the state's series, when the jets have a compiled pass to that order; `None`
    /// for the interpreter.
    fn compiled(_jets: &mut Jets<Self>, _order: usize) -> Option<Result<()>> {
        None
    }
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
    #[cfg(feature = "jit")]
    #[inline]
    fn compiled(jets: &mut Jets<Self>, order: usize) -> Option<Result<()>> {
        let native = jets.native.as_ref().filter(|_| order == jets.order)?;
        if native.run(&mut jets.c) == 0.0 {
            return Some(Ok(()));
        }
        let (s, n) = (jets.stride, jets.program.outputs.len());
        let x0: Vec<f64> = (1..=n).map(|j| jets.c[j * s]).collect();
        Some(non_finite(&jets.c, s, n, order, jets.c[0], &x0))
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
        #[allow(unused_mut)]
        let mut jets = Self::with_storage(record, order)?;
        #[cfg(feature = "jit")]
        {
            jets.native = compiled(record, &jets.program, order);
        }
        Ok(jets)
    }

    /// The time the code generator took to compile the pass of this order for the record
    /// (once per record and order, at the first [`Jets::new`] of them; see
    /// [the program](Self#the-program)), `None` when the pass is interpreted.
    pub fn compile_time(&self) -> Option<std::time::Duration> {
        #[cfg(feature = "jit")]
        if let Some(native) = &self.native {
            return Some(native.compile_time());
        }
        None
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
            #[cfg(feature = "jit")]
            native: None,
            program,
        })
    }

    /// [`Jets::ode`] over the coefficient field `C`: by the compiled pass when there is one to
    /// `order` (doubles only), by the interpreter otherwise.
    pub(crate) fn propagate(&mut self, t0: C, x0: &[C], order: usize) -> Result<()>
    where
        C: JetCoefficient,
    {
        self.load(t0, x0, order)?;
        if let Some(result) = C::compiled(self, order) {
            return result;
        }
        self.interpret(order)
    }

    /// Check `(t₀, x₀)` and `order` and write them as the coefficients of order 0.
    fn load(&mut self, t0: C, x0: &[C], order: usize) -> Result<()>
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
        self.c[0] = t0;
        for (j, &x) in x0.iter().enumerate() {
            self.c[(1 + j) * s] = x;
        }
        Ok(())
    }

    /// The interpreted pass to `order` from the loaded coefficients of order 0, and the check of
    /// the state's series.
    fn interpret(&mut self, order: usize) -> Result<()>
    where
        C: JetCoefficient,
    {
        let (s, n) = (self.stride, self.program.outputs.len());
        let Jets { c, program, .. } = self;
        let (field, program) = (&program.outputs, &program.instructions);
        for &ins in program.iter() {
            C::order_zero(ins, c);
        }
        advance(field, c, s, 0);
        for k in 1..order {
            C::pass(program, c, k);
            advance(field, c, s, k);
        }
        // `v·0` is ±0 for a finite `v` and NaN otherwise: one branch for the state.
        let flag = (1..=n).fold(0.0, |a, j| {
            c[j * s + 1..=j * s + order]
                .iter()
                .fold(a, |a, v| a + v.value() * 0.0)
        });
        if flag == 0.0 {
            return Ok(());
        }
        let t0 = c[0].value();
        let x0: Vec<f64> = (1..=n).map(|j| c[j * s].value()).collect();
        non_finite(c, s, n, order, t0, &x0)
    }
}

/// The error of the first non-finite coefficient of the state's series in `c` (of stride
/// `s`, `n` variables, to `order`), if any.
fn non_finite<C: Field>(
    c: &[C],
    s: usize,
    n: usize,
    order: usize,
    t0: f64,
    x0: &[f64],
) -> Result<()> {
    for j in 1..=n {
        let jet = &c[j * s..=j * s + order];
        if let Some(k) = jet.iter().position(|c| !c.finite()) {
            return Err(Error::NonFinite {
                what: format!(
                    "Taylor coefficient {k} of state variable {} at t₀ = {t0:e}, x₀ = \
                     {x0:?} (a singularity of the equation)",
                    j - 1
                ),
                value: c[j * s + k].value(),
            });
        }
    }
    Ok(())
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

#[cfg(all(test, feature = "jit"))]
mod tests {
    use super::*;
    use crate::record::{gradient, record, Recorded};
    use num_dual::DualNum;

    /// `Σ_{j=lo}^{hi} w_j |u_j| |v_{k−j}|` over the buffer `c` (weights `w_j = j` when
    /// `weighted`, 1 otherwise).
    fn mag(c: &[f64], u: usize, v: usize, lo: usize, hi: usize, k: usize, weighted: bool) -> f64 {
        (lo..=hi)
            .map(|j| {
                let w = if weighted { j as f64 } else { 1.0 };
                w * c[u + j].abs() * c[v + k - j].abs()
            })
            .sum()
    }

    /// The sum of the magnitudes of the terms of the recurrence of order `k` of `ins` (for its
    /// first and its second result), its divisor divided out: the scale of the rounding of
    /// any order of summation of those terms.
    fn magnitudes(ins: Instr, c: &[f64], k: usize) -> (f64, f64) {
        let kf = k as f64;
        let a = |o: usize| c[o].abs();
        match ins {
            Instr::Lin {
                a: x,
                alpha,
                b,
                beta,
                ..
            } => ((alpha * c[x + k]).abs() + (beta * c[b + k]).abs(), 0.0),
            Instr::Affine { a: x, alpha, .. } => ((alpha * c[x + k]).abs(), 0.0),
            Instr::Mul { a: x, b, .. } => (mag(c, x, b, 0, k, k, false), 0.0),
            Instr::MulAdd {
                a: x,
                b,
                alpha,
                c: d,
                beta,
                ..
            } => (
                alpha.abs() * mag(c, x, b, 0, k, k, false) + (beta * c[d + k]).abs(),
                0.0,
            ),
            Instr::Div { w, a: x, b } => ((a(x + k) + mag(c, b, w, 1, k, k, false)) / a(b), 0.0),
            Instr::Recip { w, a: x } => (mag(c, x, w, 1, k, k, false) / a(x), 0.0),
            Instr::Sqrt { w, a: x } => (
                (a(x + k) + mag(c, w, w, 1, k - 1, k, false)) / (2.0 * a(w)),
                0.0,
            ),
            Instr::Exp { w, a: x } => (mag(c, x, w, 1, k, k, true) / kf, 0.0),
            Instr::Ln { w, a: x } => (
                (a(x + k) + mag(c, w, x, 1, k - 1, k, true) / kf) / a(x),
                0.0,
            ),
            Instr::Powf { w, a: x, p } => (
                ((p + 1.0).abs() * mag(c, x, w, 1, k, k, true) + kf * mag(c, x, w, 1, k, k, false))
                    / (kf * a(x)),
                0.0,
            ),
            Instr::Tanh { w, s, a: x } => (
                mag(c, x, s, 1, k, k, true) / kf,
                mag(c, w, w, 0, k, k, false),
            ),
            Instr::SinCos { s, c: co, a: x } => (
                mag(c, x, co, 1, k, k, true) / kf,
                mag(c, x, s, 1, k, k, true) / kf,
            ),
            Instr::Atan2 { w, y, x, r } => (
                (mag(c, y, x, 1, k, k, true)
                    + mag(c, x, y, 1, k, k, true)
                    + mag(c, w, r, 1, k - 1, k, true))
                    / (kf * a(r)),
                0.0,
            ),
        }
    }

    /// The compiled pass against the interpreter, instruction by instruction: the order-0
    /// values and the solution's `x_{k+1} = (α/(k+1)) f_k` bit for bit; each coefficient of
    /// order `k ≥ 1` recomputed by the interpreter's recurrence ([`kth`]) from the compiled
    /// lower coefficients, the two within `2γ_{3k+6} M`, `M` the sum of the magnitudes of the
    /// recurrence's terms (each of the two orders of summation is within `γ_n M` of the exact
    /// sum of its `n ≤ 3k + 1` products and `≤ 5` further roundings; Higham 2002, §3.1). The
    /// worst ratio of difference to bound.
    fn compiled_against_interpreter(rec: &Record, order: usize, t0: f64, x0: &[f64]) -> f64 {
        let mut jets = Jets::new(rec, order).unwrap();
        assert!(jets.native.is_some(), "no compiled pass");
        let mut interpreted = jets.clone();
        interpreted.native = None;
        jets.ode(t0, x0, order).unwrap();
        interpreted.ode(t0, x0, order).unwrap();
        let (s, c) = (jets.stride, &jets.c);
        for slot in 0..jets.program.slots {
            assert_eq!(
                c[slot * s].to_bits(),
                interpreted.c[slot * s].to_bits(),
                "order 0 of slot {slot}"
            );
        }
        let mut worst: f64 = 0.0;
        for k in 0..order {
            for (j, &(o, alpha)) in jets.program.outputs.iter().enumerate() {
                let want = alpha * (1.0 / (k + 1) as f64) * c[o + k];
                assert_eq!(
                    c[(1 + j) * s + k + 1].to_bits(),
                    want.to_bits(),
                    "x_{j},{k}"
                );
            }
            if k == 0 {
                continue;
            }
            for &ins in &jets.program.instructions {
                let mut again = c.clone();
                kth(ins, &mut again, k);
                let (m1, m2) = magnitudes(ins, c, k);
                let gamma = 2.0 * (3 * k + 6) as f64 * f64::EPSILON;
                let mut writes = ins.writes();
                let w = writes.next().unwrap();
                let d = (again[w + k] - c[w + k]).abs();
                worst = worst.max(d / (gamma * m1).max(f64::MIN_POSITIVE));
                assert!(d <= gamma * m1, "{ins:?} k = {k}: {d:e} > {:e}", gamma * m1);
                if let Some(w2) = writes.next() {
                    // The second result from the compiled first (`1 − tanh²` reads `tanh`'s
                    // order k).
                    let second = match ins {
                        Instr::Tanh { w, .. } => -rec::product(&c[w..=w + k], &c[w..=w + k], k),
                        _ => again[w2 + k],
                    };
                    let d = (second - c[w2 + k]).abs();
                    worst = worst.max(d / (gamma * m2).max(f64::MIN_POSITIVE));
                    assert!(
                        d <= gamma * m2,
                        "{ins:?}/2 k = {k}: {d:e} > {:e}",
                        gamma * m2
                    );
                }
            }
        }
        worst
    }

    #[test]
    fn compiled_pass_agrees_with_the_interpreter() {
        // The pendulum, H = p²/2 − cos q.
        let pendulum = record(&[0.0, 1.0, 0.0], |v| {
            let h = v[2] * v[2] * 0.5 - v[1].cos();
            let g = gradient(h, &v[1..]);
            Ok(vec![g[1], -g[0]])
        })
        .unwrap();
        let worst = compiled_against_interpreter(&pendulum, 12, 0.3, &[1.0, 0.2]);
        println!("pendulum, order 12: worst difference / bound {worst:.3}");
        // Kepler + J₂ (μ = R = 1, J₂ = 10⁻³): V = −1/r − (J₂/2r³)(1 − 3z²/r²).
        let x0 = [0.0, 1.8, 0.0, 0.1, 0.0, 0.66, 0.36];
        let j2 = record(&x0, |v| {
            let (q, p) = (&v[1..4], &v[4..7]);
            let r2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
            let r = r2.sqrt();
            let v = -r.recip() - (r * r2).recip() * 0.5e-3 * (-(q[2] * q[2] / r2) * 3.0 + 1.0);
            let h = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) * 0.5 + v;
            let g = gradient(h, &[q, p].concat());
            Ok(vec![g[3], g[4], g[5], -g[0], -g[1], -g[2]])
        })
        .unwrap();
        let worst = compiled_against_interpreter(&j2, 16, 0.0, &x0[1..]);
        println!("Kepler + J2, order 16: worst difference / bound {worst:.3}");
        // Every instruction kind of a Taylor program.
        let every = record(&[0.1, 0.4, -0.3], |v| {
            let (t, x, y) = (v[0], v[1], v[2]);
            let one = Recorded::constant(1.0);
            let f = x / (y * y + 1.0)
                + (t + 2.0).recip()
                + (x * x + 2.0).sqrt()
                + (y * 0.3).exp()
                + (x + 3.0).ln();
            let g =
                (y * y + 1.5).powf(0.3) + x.tanh() + y.sin() * y.cos() * 2.0 + x.atan2(y * y + one)
                    - t * 3.0;
            Ok(vec![f, g])
        })
        .unwrap();
        let program = Program::with_stride(&every, 13);
        for kind in [
            "Div", "Recip", "Sqrt", "Exp", "Ln", "Powf", "Tanh", "SinCos", "Atan2", "Mul", "Lin",
            "Affine",
        ] {
            assert!(
                program
                    .instructions
                    .iter()
                    .any(|i| format!("{i:?}").starts_with(kind)),
                "no {kind}"
            );
        }
        let worst = compiled_against_interpreter(&every, 12, 0.1, &[0.4, -0.3]);
        println!("every instruction, order 12: worst difference / bound {worst:.3}");
    }
}
