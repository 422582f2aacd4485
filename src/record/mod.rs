//! The operation record: a function written once for every [`DualNum<f64>`] type, evaluated once
//! on the recording number [`Recorded`], as a flat list of elementary operations.
//!
//! A function `y = F(x)`, `x ∈ ℝⁿ`, is a composition of elementary operations
//! (the *evaluation trace* or *Kantorovich graph* of Griewank & Walther, ch. 2):
//!
//! ```math
//! v_i = x_i \ (i < n),\qquad v_i = \varphi_i(v_{j}, v_{k}),\ j, k < i,\qquad
//! y_m = v_{o_m},
//! ```
//!
//! each `φᵢ` one of the operations of [`Op`] (sum, difference, product, quotient, negation,
//! shift and scaling by a constant, reciprocal, `√`, `exp`, `ln`, `sin`, `cos`, `tanh`, `u^a`,
//! `atan2`). [`record`] runs the user's code once on [`Recorded`] values, which implement
//! [`DualNum<f64>`] and `Copy`: every arithmetic operation appends its `φᵢ` to the record of the
//! running thread, so a [`Hamiltonian`](crate::Hamiltonian) written once runs unchanged. The other
//! functions of `DualNum` are written in these operations (`tan = sin/cos`, `sinh = (eᵘ − e⁻ᵘ)/2`,
//! `asin u = atan2(u, √(1 − u²))`, `log_b = ln/ln b`, …); `sinh` and `cosh` so written overflow
//! to `±∞` where `eᵘ` does, `|u| > 709.78` (a little before the functions themselves, at
//! `|u| > 710.48`), while `tanh` is an operation of its own and is `±1` there; the spherical Bessel functions
//! `sph_j0…2` and the remainder `%` of non-constants have none, and [`record`] refuses a function
//! that uses them ([`Error::InvalidInput`] naming the operation).
//!
//! While recording, operations on constants are folded (`2·3 → 6`), a sum with the constant 0
//! and a product with the constants 0, ±1 collapse, and an operation already recorded with the
//! same operands is not recorded twice (hash-consing: common subexpressions are shared). The
//! finished [`Record`] keeps only the operations its outputs depend on.
//!
//! # Derivatives
//! [`gradient`] appends to the running record the operations of the adjoint (reverse) sweep
//! over the operations recorded so far (Griewank & Walther, ch. 3.2, the *adjoint* of the
//! trace):
//!
//! ```math
//! \bar v_{\text{out}} = 1,\qquad \bar v_j \mathrel{+}= \bar v_i\,\frac{\partial\varphi_i}{\partial v_j}
//! \quad (i = \text{out}, \dots, 0), \qquad \frac{\partial y}{\partial x_i} = \bar v_i ,
//! ```
//!
//! each partial itself a recorded operation (`∂ sin u/∂u` is the recorded `cos u`, `∂eᵘ/∂u` the
//! recorded `eᵘ`). The gradient of a Hamiltonian therefore costs a small multiple of the
//! operations of `H` whatever the number of variables — the record of Hamilton's equations is built
//! this way, not by forward-mode dual numbers over recorded values, whose size grows with `2N`.
//!
//! # Branches
//! [`Recorded`] values carry the value at the recording point, and comparisons look at it (as for
//! every number type of num-dual), so code that branches on values records the branch taken
//! there. `abs` and `signum` record `±u` and a constant. A record so made is valid where the
//! branches go the same way; the functions of the crate's catalogue branch on the dimension `N`
//! only.
//!
//! # Uses
//! [`Record::eval`] evaluates a record on any `DualNum<f64>` type (so a record — for instance one
//! compiled from an expression — is again a function written once for every number type) by a
//! register program made once from it ([`Record::eval_into`]), and [`Jets`] propagates
//! normalised Taylor coefficients through the same program, which is the Taylor method
//! ([`crate::integrate::taylor`]).
//! The expression systems ([`crate::expression`]) also compile the program, once, to native
//! code by the Cranelift code generator (feature `jit`; <https://cranelift.dev>), which they run
//! on `f64` with the interpreter's values bit for bit (see [the expression module's
//! cost](crate::expression#cost)).
//!
//! References: A. Griewank & A. Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, chs. 2–3
//! and 13; À. Jorba & M. Zou, "A software package for the numerical integration of ODEs by means
//! of high-order Taylor methods", Exp. Math. 14 (2005) 99–117, §2 (the decomposition into
//! elementary operations).

mod jets;
#[cfg(feature = "jit")]
mod jit;
mod number;
mod program;
#[cfg(feature = "jit")]
mod taylor_jit;

pub(crate) use jets::JetCoefficient;
pub use jets::{Jets, MAX_ORDER};
pub use number::Recorded;

use crate::error::{Error, Result};
use nalgebra::SVector;
use num_dual::DualNum;
use number::{with_tape, Tape, CONST};
use program::Program;

/// One elementary operation of a [`Record`]; operands are indices of earlier operations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// The independent variable `x_i`.
    Input(usize),
    /// A constant.
    Const(f64),
    /// `a + b`.
    Add(usize, usize),
    /// `a − b`.
    Sub(usize, usize),
    /// `a · b`.
    Mul(usize, usize),
    /// `a / b`.
    Div(usize, usize),
    /// `−a`.
    Neg(usize),
    /// `a + c`, `c` a constant.
    Shift(usize, f64),
    /// `c · a`, `c` a constant.
    Scale(usize, f64),
    /// `1 / a`.
    Recip(usize),
    /// `√a`.
    Sqrt(usize),
    /// `exp a`.
    Exp(usize),
    /// `ln a`.
    Ln(usize),
    /// `tanh a`; its recurrence reads `1 − tanh² a`, which the program keeps beside it.
    Tanh(usize),
    /// `sin a`; `cos` is the operation of the same argument that the recurrence of `sin` needs.
    Sin {
        /// The argument.
        arg: usize,
        /// The operation `cos arg`.
        cos: usize,
    },
    /// `cos a`; `sin` is the operation of the same argument.
    Cos {
        /// The argument.
        arg: usize,
        /// The operation `sin arg`.
        sin: usize,
    },
    /// `a^c`, `c` a constant that is not an integer of at most 64 in magnitude (those are
    /// recorded as products and reciprocals).
    Powf(usize, f64),
    /// `atan2(y, x)`; `r` is the operation `x² + y²` of its recurrence.
    Atan2 {
        /// The first argument (ordinate).
        y: usize,
        /// The second argument (abscissa).
        x: usize,
        /// The operation `x² + y²`.
        r: usize,
    },
}

impl Op {
    /// The operations this one reads (its operands, and the partner of `sin`/`cos` and the
    /// radius of `atan2`, which their recurrences read).
    pub fn operands(&self) -> impl Iterator<Item = usize> {
        let (a, b, c) = match *self {
            Op::Input(_) | Op::Const(_) => (None, None, None),
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => {
                (Some(a), Some(b), None)
            }
            Op::Neg(a)
            | Op::Shift(a, _)
            | Op::Scale(a, _)
            | Op::Recip(a)
            | Op::Sqrt(a)
            | Op::Exp(a)
            | Op::Ln(a)
            | Op::Tanh(a)
            | Op::Powf(a, _) => (Some(a), None, None),
            Op::Sin { arg, cos } => (Some(arg), Some(cos), None),
            Op::Cos { arg, sin } => (Some(arg), Some(sin), None),
            Op::Atan2 { y, x, r } => (Some(y), Some(x), Some(r)),
        };
        a.into_iter().chain(b).chain(c)
    }

    fn map(self, f: impl Fn(usize) -> usize) -> Op {
        match self {
            Op::Input(i) => Op::Input(i),
            Op::Const(c) => Op::Const(c),
            Op::Add(a, b) => Op::Add(f(a), f(b)),
            Op::Sub(a, b) => Op::Sub(f(a), f(b)),
            Op::Mul(a, b) => Op::Mul(f(a), f(b)),
            Op::Div(a, b) => Op::Div(f(a), f(b)),
            Op::Neg(a) => Op::Neg(f(a)),
            Op::Shift(a, c) => Op::Shift(f(a), c),
            Op::Scale(a, c) => Op::Scale(f(a), c),
            Op::Recip(a) => Op::Recip(f(a)),
            Op::Sqrt(a) => Op::Sqrt(f(a)),
            Op::Exp(a) => Op::Exp(f(a)),
            Op::Ln(a) => Op::Ln(f(a)),
            Op::Tanh(a) => Op::Tanh(f(a)),
            Op::Powf(a, c) => Op::Powf(f(a), c),
            Op::Sin { arg, cos } => Op::Sin {
                arg: f(arg),
                cos: f(cos),
            },
            Op::Cos { arg, sin } => Op::Cos {
                arg: f(arg),
                sin: f(sin),
            },
            Op::Atan2 { y, x, r } => Op::Atan2 {
                y: f(y),
                x: f(x),
                r: f(r),
            },
        }
    }
}

/// A recorded function `ℝⁿ → ℝᵐ`: operations in evaluation order, the first `n` the inputs,
/// and the register program they are evaluated by (see [`Record::eval_into`]).
#[derive(Clone, Debug)]
pub struct Record {
    ops: Vec<Op>,
    inputs: usize,
    outputs: Vec<usize>,
    program: Program,
}

/// Records are equal when their operations, inputs and outputs are (the program is made from
/// them).
impl PartialEq for Record {
    fn eq(&self, other: &Self) -> bool {
        self.ops == other.ops && self.inputs == other.inputs && self.outputs == other.outputs
    }
}

/// The largest number of operations one record may hold, `2²⁴`: a function that records more
/// (a loop that runs away) gives an error instead of exhausting memory.
pub const MAX_OPERATIONS: usize = 1 << 24;

/// Record `f` at the point `x`: `f` receives the `n = x.len()` inputs as [`Recorded`] values
/// (with the values `x`) and returns the outputs.
///
/// # Errors
/// [`Error::InvalidInput`] for no inputs, a record begun while another is running on this
/// thread, an operation the record cannot represent (`sph_j0…2`, `%` of non-constants; the
/// message names it), a value of another record, more than [`MAX_OPERATIONS`] operations, or no
/// outputs; the error `f` returns. A non-finite `x` is allowed (the record does not depend on
/// the values except through branches).
pub fn record<F>(x: &[f64], f: F) -> Result<Record>
where
    F: FnOnce(&[Recorded]) -> Result<Vec<Recorded>>,
{
    if x.is_empty() {
        return Err(Error::invalid("operation record", "no inputs"));
    }
    let id = number::open()?;
    let inputs: Vec<Recorded> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| number::push(Op::Input(i), v))
        .collect();
    let result = f(&inputs);
    let tape = number::close(id);
    let outputs = result?;
    let mut tape = tape?;
    if let Some(fault) = tape.fault.take() {
        return Err(Error::invalid("operation record", fault));
    }
    if outputs.is_empty() {
        return Err(Error::invalid("operation record", "no outputs"));
    }
    let mut out = Vec::with_capacity(outputs.len());
    for y in &outputs {
        out.push(tape.node_of(y)?);
    }
    Ok(Record::pruned(tape.ops, x.len(), out))
}

/// `∂y/∂wᵢ` for each `wᵢ` of `wrt` (inputs of the running record), by the adjoint sweep over the
/// operations recorded so far; the partials are recorded operations (see the
/// [module docs](self#derivatives)). Outside a record, or for values that are not inputs of the
/// running record, the running record (if any) fails with the reason and the result is zeros.
pub fn gradient(y: Recorded, wrt: &[Recorded]) -> Vec<Recorded> {
    number::gradient(y, wrt)
}

impl Record {
    /// The record with the operations the outputs do not depend on removed (inputs kept).
    fn pruned(ops: Vec<Op>, inputs: usize, outputs: Vec<usize>) -> Record {
        let mut live = vec![false; ops.len()];
        live[..inputs].iter_mut().for_each(|l| *l = true);
        for &o in &outputs {
            live[o] = true;
        }
        for i in (0..ops.len()).rev() {
            if live[i] {
                for j in ops[i].operands() {
                    live[j] = true;
                }
            }
        }
        let mut index = vec![usize::MAX; ops.len()];
        let mut kept = Vec::new();
        for (i, op) in ops.into_iter().enumerate() {
            if live[i] {
                index[i] = kept.len();
                kept.push(op);
            }
        }
        // Operands of `sin`/`cos` may point forward to their partner: map after numbering.
        let mut record = Record {
            ops: kept.into_iter().map(|op| op.map(|j| index[j])).collect(),
            inputs,
            outputs: outputs.into_iter().map(|o| index[o]).collect(),
            program: Program::default(),
        };
        record.program = Program::new(&record);
        record
    }

    /// The operations, the first [`inputs`](Self::inputs) of them the inputs.
    pub fn ops(&self) -> &[Op] {
        &self.ops
    }

    /// The number of inputs `n`.
    pub fn inputs(&self) -> usize {
        self.inputs
    }

    /// The operations whose values are the outputs.
    pub fn outputs(&self) -> &[usize] {
        &self.outputs
    }

    /// The number of operations.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the record holds no operation (never true for a record [`record`] made).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// The number of instructions of the register program the record is evaluated by (see
    /// [`eval_into`](Self::eval_into)).
    pub fn instructions(&self) -> usize {
        self.program.len()
    }

    /// The outputs at `x`, evaluated on any number type (see [`eval_into`](Self::eval_into)).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `x.len()` is not the number of inputs; [`Error::NonFinite`]
    /// for an input or an output whose value (real part) is NaN or infinite.
    pub fn eval<D: DualNum<f64> + Copy>(&self, x: &[D]) -> Result<Vec<D>> {
        if x.len() != self.inputs {
            return Err(Error::invalid(
                "record inputs",
                format!("{} values for {} inputs", x.len(), self.inputs),
            ));
        }
        for (i, v) in x.iter().enumerate() {
            crate::error::finite(format_args!("record input {i}"), v.re())?;
        }
        let mut y = vec![D::zero(); self.outputs.len()];
        self.eval_into(x, &mut y);
        for (i, v) in y.iter().enumerate() {
            crate::error::finite(
                format_args!("record output {i} (outside the function's domain?)"),
                v.re(),
            )?;
        }
        Ok(y)
    }

    /// The outputs at `x` into `y` (`y[k]` the `k`-th output) on any number type, without
    /// validation (NaN in gives NaN out).
    ///
    /// The record is evaluated by a register program made once when it is recorded: the linear
    /// operations folded into scale factors of the slots (`c·u`, `−u` and `u + u` make no
    /// instruction, `αu + βv` and `αu + γ` one; the factors pass through products, quotients,
    /// reciprocals and, for `α > 0`, roots and powers), `sin` and `cos` of one argument one
    /// instruction, a product used only by a linear combination `α·ab + βc` fused with it,
    /// operands resolved to slots in advance, one dispatch per instruction, the slot of a value
    /// no longer read reused by a later one. The slots live in a buffer on the stack sized to
    /// the program, of 16, 32, 64 or 512 values of `D` in at most 16 KiB (the indices masked by
    /// its power-of-two length, so that no bounds check remains), on the heap otherwise
    /// (Griewank & Walther, §2.2, the evaluation procedure as a register program).
    ///
    /// # Panics
    /// If `x` holds fewer values than the record has inputs, or `y` fewer than it has outputs.
    #[inline]
    pub fn eval_into<D: DualNum<f64> + Copy>(&self, x: &[D], y: &mut [D]) {
        self.program.eval(x, y)
    }
}

/// A record with, under the feature `jit`, its register program compiled to native code once
/// (by the Cranelift code generator; see `jit::Native`): [`eval_into`](Self::eval_into)
/// on `f64` runs the native code, on every other number type (dual numbers, recorded values,
/// jets) the interpreter of [`Record::eval_into`]. Both give the same values bit for bit; where
/// the code cannot be compiled (a host Cranelift does not support, a program too large, an error
/// of the code generator) the interpreter runs on `f64` too.
#[derive(Clone, Debug)]
pub(crate) struct Compiled {
    record: Record,
    #[cfg(feature = "jit")]
    native: Option<std::sync::Arc<jit::Native>>,
}

/// Whether `D` is `f64` (a real number type without derivatives, of the size of `f64`, named
/// `f64`): then `D::re` and `D::from` are the identity.
#[inline(always)]
pub(crate) fn is_f64<D: DualNum<f64>>() -> bool {
    D::NDERIV == 0
        && std::mem::size_of::<D>() == std::mem::size_of::<f64>()
        && std::any::type_name::<D>() == "f64"
}

/// The most degrees of freedom of the interpreted forms of [`Compiled::eval_phase`] and
/// [`Compiled::eval_gradient`] (their buffers).
const PHASE_DOF: usize = 16;

/// The most inputs and outputs of a record whose native code the generic
/// [`Compiled::eval_into`] calls (it copies them through arrays on the stack).
#[cfg(feature = "jit")]
const NATIVE_VALUES: usize = 16;

impl Compiled {
    /// `record` and, under the feature `jit`, its native code.
    pub(crate) fn new(record: Record) -> Self {
        Self {
            #[cfg(feature = "jit")]
            native: jit::Native::compile(&record.program, jit::Layout::Flat)
                .map(std::sync::Arc::new),
            record,
        }
    }

    /// `record` of inputs `(t, q₁ … qₙ, p₁ … pₙ)` and outputs `(a₁ … aₙ, b₁ … bₙ)` (Hamilton's
    /// equations), its native code under the feature `jit` reading and writing the state
    /// vectors themselves ([`eval_phase`](Self::eval_phase)); [`eval_into`](Self::eval_into)
    /// and [`eval_f64`](Self::eval_f64) interpret it.
    #[cfg_attr(not(feature = "jit"), allow(unused_variables))]
    pub(crate) fn phase(record: Record, n: usize) -> Self {
        Self {
            #[cfg(feature = "jit")]
            native: jit::Native::compile(&record.program, jit::Layout::Phase(n))
                .map(std::sync::Arc::new),
            record,
        }
    }

    /// The outputs at `(t, q, p)` into `(a, b)` on `f64` for a record made by
    /// [`phase`](Self::phase) with `n = N`: the native code when there is one, the interpreter
    /// otherwise.
    ///
    /// # Panics
    /// If `N` exceeds 16 (the interpreted form's buffers) or the record's inputs and outputs
    /// are not `1 + 2N` and `2N`, when the interpreter runs.
    #[inline(always)]
    pub(crate) fn eval_phase<const N: usize>(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        a: &mut SVector<f64, N>,
        b: &mut SVector<f64, N>,
    ) {
        #[cfg(feature = "jit")]
        if let Some(native) = &self.native {
            if native.call_phase(t, q, p, a, b) {
                return;
            }
        }
        self.eval_phase_interpreted(t, q, p, a, b)
    }

    /// [`eval_phase`](Self::eval_phase) by the interpreter (kept out of line, so that the
    /// native call inlined in its callers carries no frame for the interpreter's buffers).
    #[inline(never)]
    fn eval_phase_interpreted<const N: usize>(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        a: &mut SVector<f64, N>,
        b: &mut SVector<f64, N>,
    ) {
        let mut x = [0.0; 1 + 2 * PHASE_DOF];
        let mut y = [0.0; 2 * PHASE_DOF];
        x[0] = t;
        x[1..=N].copy_from_slice(q.as_slice());
        x[1 + N..=2 * N].copy_from_slice(p.as_slice());
        self.record.eval_into(&x[..1 + 2 * N], &mut y[..2 * N]);
        a.copy_from_slice(&y[..N]);
        b.copy_from_slice(&y[N..2 * N]);
    }

    /// `record` of inputs `(t, z₁ … zₙ)` and outputs `(v, g₁ … gₙ)` (a function and its
    /// gradient), its native code under the feature `jit` reading and writing the vectors
    /// themselves ([`eval_gradient`](Self::eval_gradient)); [`eval_into`](Self::eval_into)
    /// and [`eval_f64`](Self::eval_f64) interpret it.
    #[cfg_attr(not(feature = "jit"), allow(unused_variables))]
    pub(crate) fn gradient(record: Record, n: usize) -> Self {
        Self {
            #[cfg(feature = "jit")]
            native: jit::Native::compile(&record.program, jit::Layout::Gradient(n))
                .map(std::sync::Arc::new),
            record,
        }
    }

    /// The first output at `(t, z)`, the others into `g`, on `f64` for a record made by
    /// [`gradient`](Self::gradient) with `n = N`: the native code when there is one, the
    /// interpreter otherwise.
    ///
    /// # Panics
    /// If `N` exceeds 16 (the interpreted form's buffers) or the record's inputs and outputs
    /// are not `1 + N` each, when the interpreter runs.
    #[inline(always)]
    pub(crate) fn eval_gradient<const N: usize>(
        &self,
        t: f64,
        z: &SVector<f64, N>,
        g: &mut SVector<f64, N>,
    ) -> f64 {
        #[cfg(feature = "jit")]
        if let Some(native) = &self.native {
            if let Some(v) = native.call_gradient(t, z, g) {
                return v;
            }
        }
        self.eval_gradient_interpreted(t, z, g)
    }

    /// [`eval_gradient`](Self::eval_gradient) by the interpreter (out of line, as
    /// [`eval_phase_interpreted`](Self::eval_phase_interpreted)).
    #[inline(never)]
    fn eval_gradient_interpreted<const N: usize>(
        &self,
        t: f64,
        z: &SVector<f64, N>,
        g: &mut SVector<f64, N>,
    ) -> f64 {
        let mut x = [0.0; 1 + PHASE_DOF];
        let mut y = [0.0; 1 + PHASE_DOF];
        x[0] = t;
        x[1..=N].copy_from_slice(z.as_slice());
        self.record.eval_into(&x[..=N], &mut y[..=N]);
        g.copy_from_slice(&y[1..=N]);
        y[0]
    }

    /// The same record evaluated by the interpreter only.
    pub(crate) fn interpreted(&self) -> Self {
        Self {
            record: self.record.clone(),
            #[cfg(feature = "jit")]
            native: None,
        }
    }

    /// Whether `f64` evaluations run native code.
    pub(crate) fn is_native(&self) -> bool {
        #[cfg(feature = "jit")]
        return self.native.is_some();
        #[cfg(not(feature = "jit"))]
        false
    }

    /// The record.
    pub(crate) fn record(&self) -> &Record {
        &self.record
    }

    /// The outputs at `x` into `y`, as [`Record::eval_into`]; on `f64` by the native code when
    /// there is one.
    ///
    /// # Panics
    /// If `x` holds fewer values than the record has inputs, or `y` fewer than it has outputs.
    #[inline]
    pub(crate) fn eval_into<D: DualNum<f64> + Copy>(&self, x: &[D], y: &mut [D]) {
        #[cfg(feature = "jit")]
        if let Some(native) = self.native.as_ref().filter(|n| n.is_flat()) {
            let (n, m) = (self.record.inputs, self.record.outputs.len());
            if is_f64::<D>() && n <= NATIVE_VALUES && m <= NATIVE_VALUES {
                let mut xf = [0.0; NATIVE_VALUES];
                for (a, b) in xf.iter_mut().zip(&x[..n]) {
                    *a = b.re();
                }
                let mut yf = [0.0; NATIVE_VALUES];
                native.call(&xf[..n], &mut yf[..m]);
                for (a, b) in y[..m].iter_mut().zip(&yf) {
                    *a = D::from(*b);
                }
                return;
            }
        }
        self.record.eval_into(x, y)
    }

    /// The outputs at `x` into `y` on `f64`, as [`eval_into`](Self::eval_into) without the
    /// copies of the generic form.
    ///
    /// # Panics
    /// As [`eval_into`](Self::eval_into).
    #[inline]
    pub(crate) fn eval_f64(&self, x: &[f64], y: &mut [f64]) {
        #[cfg(feature = "jit")]
        if let Some(native) = self.native.as_ref().filter(|n| n.is_flat()) {
            return native.call(x, y);
        }
        self.record.eval_into(x, y)
    }
}

impl Tape {
    /// The operation of an output value (a constant is recorded as one).
    fn node_of(&mut self, y: &Recorded) -> Result<usize> {
        if y.node == CONST {
            self.ops.push(Op::Const(y.re));
            self.values.push(y.re);
            return Ok(self.ops.len() - 1);
        }
        if y.tape != self.id || y.node as usize >= self.ops.len() {
            return Err(Error::invalid(
                "operation record",
                "an output is a value of another record",
            ));
        }
        Ok(y.node as usize)
    }
}

/// The running record's operations, for the adjoint sweep of [`gradient`].
pub(crate) fn op_at(node: u32) -> Option<(Op, f64)> {
    with_tape(|t| {
        t.ops
            .get(node as usize)
            .map(|op| (*op, t.values[node as usize]))
    })
    .flatten()
}
