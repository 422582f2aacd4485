//! The flat register program of a record: the form in which a record is evaluated, on any
//! number type and as Taylor jets (and, feature `jit`, the form compiled to native code).

use super::{Op, Record};
use crate::special::double_double::DoubleDouble;
use num_dual::DualNum;
use std::collections::HashMap;

/// One instruction of a [`Program`]; `w`, `a`, … are offsets in the buffer of values (slot ×
/// stride: for [`Jets`](super::Jets) the coefficient `k` of a jet is `c[offset + k]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Instr {
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
    /// `w = α a b + β c`, a product whose only use is a linear combination, fused with it.
    MulAdd {
        w: usize,
        a: usize,
        b: usize,
        alpha: f64,
        c: usize,
        beta: f64,
    },
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
    /// `w = tanh a`, `s = 1 − w²` (the factor of its recurrence `w' = s a'`).
    Tanh { w: usize, s: usize, a: usize },
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

/// A [`Record`] translated once into a flat program over *slots* (registers), each operation of
/// the record being `α ×` a slot:
///
/// * the linear operations are folded into the factors `α` — `c·u`, `−u` and `u + u` make no
///   instruction, `αu + βv` one, `αu + γ` one — since a linear combination of linear
///   combinations is one;
/// * the factors pass through products and quotients, `(αu)(βv) = αβ·uv`,
///   `(αu)/(βv) = (α/β)·u/v`, `1/(αu) = α⁻¹·(1/u)`, and through `√(αu) = √α √u` and
///   `(αu)^p = α^p u^p` for `α > 0`;
/// * `sin u` and `cos u` of the same argument are one instruction, and `tanh u` one with
///   `1 − tanh² u` beside it;
/// * the operands are slot offsets resolved in advance, the constants preset in their slots.
///
/// [`eval`](Self::eval) runs the program on any [`DualNum<f64>`] type, one dispatch per
/// instruction, its slots in a buffer on the stack when they fit in [`STACK_BYTES`], with
/// the bounds checks of the slot indices proved away (each index masked by the buffer's
/// power-of-two length, which the slot count does not exceed); [`Jets`](super::Jets) runs the
/// same program order by order over Taylor coefficients, each slot a jet of `stride` coefficients.
///
/// Under the feature `jit` a program of stride 1 is also compiled to native code by the
/// Cranelift code generator (`jit::Native`, <https://cranelift.dev>), which
/// performs [`step`]'s operations on `f64` in the same order: the expression systems run it on
/// `f64`, this interpreter on every other number type and where no native code could be made.
///
/// References: A. Griewank & A. Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, §2.2
/// (the evaluation procedure as a three-part register program); À. Jorba & M. Zou,
/// Exp. Math. 14 (2005) 99–117, §2.
#[derive(Clone, Debug, Default)]
pub(super) struct Program {
    /// The number of buffer entries per slot.
    pub(super) stride: usize,
    /// The number of slots; the first `inputs` hold the inputs.
    pub(super) slots: usize,
    pub(super) inputs: usize,
    pub(super) instructions: Vec<Instr>,
    /// Constants as `(offset, value)`.
    pub(super) consts: Vec<(usize, f64)>,
    /// Every operation of the record as `(offset of a slot, α)` (empty once products are
    /// fused).
    pub(super) value: Vec<(usize, f64)>,
    /// The outputs as `(offset, α)`.
    pub(super) outputs: Vec<(usize, f64)>,
}

/// The largest buffer of slot values [`Program::eval`] keeps on the stack, in bytes (a larger
/// one is allocated on the heap for the call).
const STACK_BYTES: usize = 1 << 14;

impl Program {
    /// The program of `record` with one buffer entry per slot, for [`eval`](Self::eval): as
    /// [`with_stride`](Self::with_stride), and a product whose only use is a linear
    /// combination `α·(ab) + βc` fused with it into one instruction (the same roundings in the
    /// same order).
    pub(super) fn new(record: &Record) -> Self {
        let mut program = Self::with_stride(record, 1);
        program.fuse();
        program.allocate();
        program
    }

    /// Reuse the slots of values no longer read: a linear scan over the straight-line program
    /// that frees a slot after the last instruction reading it and gives an instruction's
    /// results the slots freed so far (its own operands' included, since an instruction reads
    /// all its operands before it writes), the inputs, constants and outputs kept throughout
    /// (the register allocation of a basic block; Griewank & Walther, §4.1, the reuse of
    /// locations of the evaluation procedure). The values computed are the same, in the same
    /// order; the buffer needed shrinks to the number of values live at once.
    fn allocate(&mut self) {
        debug_assert_eq!(self.stride, 1);
        const KEPT: usize = usize::MAX;
        // The last instruction reading each slot (KEPT: never freed, None: never read).
        let mut last: Vec<Option<usize>> = vec![None; self.slots];
        for (k, ins) in self.instructions.iter().enumerate() {
            for r in ins.reads() {
                last[r] = Some(k);
            }
        }
        let mut map = vec![usize::MAX; self.slots];
        let mut next = 0;
        let kept = (0..self.inputs)
            .chain(self.consts.iter().map(|c| c.0))
            .chain(self.outputs.iter().map(|o| o.0));
        for s in kept {
            last[s] = Some(KEPT);
            if map[s] == usize::MAX {
                map[s] = next;
                next += 1;
            }
        }
        let mut free: Vec<usize> = Vec::new();
        for k in 0..self.instructions.len() {
            let ins = self.instructions[k];
            for r in ins.reads() {
                if last[r] == Some(k) {
                    last[r] = None;
                    free.push(map[r]);
                }
            }
            for w in ins.writes() {
                if map[w] == usize::MAX {
                    map[w] = free.pop().unwrap_or_else(|| {
                        next += 1;
                        next - 1
                    });
                }
            }
            // A result nobody reads (the partner of `sin`/`cos`, `1 − tanh²`) frees its slot
            // at once.
            for w in ins.writes() {
                if last[w].is_none() {
                    free.push(map[w]);
                }
            }
            self.instructions[k] = ins.map(|o| map[o]);
        }
        for c in &mut self.consts {
            c.0 = map[c.0];
        }
        for o in &mut self.outputs {
            o.0 = map[o.0];
        }
        self.slots = next;
    }

    /// Fuse each product used once, by a linear combination, into it; the operations' slots
    /// ([`value`](Self::value)) are dropped, since a fused product has none.
    fn fuse(&mut self) {
        let mut uses = vec![0usize; self.slots];
        for ins in &self.instructions {
            for r in ins.reads() {
                uses[r] += 1;
            }
        }
        for &(o, _) in &self.outputs {
            uses[o] += 1;
        }
        // The instruction writing each slot.
        let mut writer = vec![usize::MAX; self.slots];
        for (k, ins) in self.instructions.iter().enumerate() {
            if let Instr::Mul { w, .. } = *ins {
                writer[w] = k;
            }
        }
        let mut dead = vec![false; self.instructions.len()];
        for k in 0..self.instructions.len() {
            let Instr::Lin {
                w,
                a,
                alpha,
                b,
                beta,
            } = self.instructions[k]
            else {
                continue;
            };
            let single = |s: usize| uses[s] == 1 && writer[s] != usize::MAX;
            let (t, alpha, c, beta) = if single(a) {
                (a, alpha, b, beta)
            } else if single(b) {
                (b, beta, a, alpha)
            } else {
                continue;
            };
            let Instr::Mul { a, b, .. } = self.instructions[writer[t]] else {
                continue;
            };
            dead[writer[t]] = true;
            self.instructions[k] = Instr::MulAdd {
                w,
                a,
                b,
                alpha,
                c,
                beta,
            };
        }
        let mut k = 0;
        self.instructions.retain(|_| {
            k += 1;
            !dead[k - 1]
        });
        self.value = Vec::new();
    }

    /// The program of `record` with `stride` buffer entries per slot.
    pub(super) fn with_stride(record: &Record, stride: usize) -> Self {
        let mut compiler = Compiler {
            stride,
            slots: 0,
            program: Vec::new(),
            consts: Vec::new(),
            scaled: HashMap::new(),
        };
        let value = compiler.translate(record);
        let outputs = record.outputs.iter().map(|&o| value[o]).collect();
        Self {
            stride,
            slots: compiler.slots,
            inputs: record.inputs,
            instructions: compiler.program,
            consts: compiler.consts,
            value,
            outputs,
        }
    }

    /// The number of instructions.
    pub(super) fn len(&self) -> usize {
        self.instructions.len()
    }

    /// The outputs at `x` into `y` (`y[k]` for the `k`-th output), without validation: NaN in
    /// gives NaN out. No allocation when the slots fit in [`STACK_BYTES`].
    ///
    /// The buffer is sized to the program: the evaluators of 16, 32, 64 and 512 slots are separate
    /// functions (not inlined here), so that a small program pays neither the stack probe of a
    /// large frame nor the clearing of slots it does not have.
    ///
    /// # Panics
    /// If `x` holds fewer values than the record has inputs or `y` fewer than it has outputs.
    #[inline]
    pub(super) fn eval<D: DualNum<f64> + Copy>(&self, x: &[D], y: &mut [D]) {
        let n = self.slots * self.stride;
        let fits = |s: usize| n <= s && s * std::mem::size_of::<D>() <= STACK_BYTES;
        if fits(16) {
            self.run::<D, 16>(x, y)
        } else if fits(32) {
            self.run::<D, 32>(x, y)
        } else if fits(64) {
            self.run::<D, 64>(x, y)
        } else if fits(512) {
            self.run::<D, 512>(x, y)
        } else {
            self.run_heap(x, y)
        }
    }

    /// [`eval`](Self::eval) with the slots in an array of `S ≥ slots` (a power of two) values.
    #[inline(never)]
    fn run<D: DualNum<f64> + Copy, const S: usize>(&self, x: &[D], y: &mut [D]) {
        let mut v = [D::zero(); S];
        self.exec(&mut v, S - 1, x, y)
    }

    /// [`eval`](Self::eval) with the slots on the heap (a program too large for the stack).
    #[inline(never)]
    fn run_heap<D: DualNum<f64> + Copy>(&self, x: &[D], y: &mut [D]) {
        let mut v = vec![D::zero(); self.slots * self.stride];
        self.exec(&mut v, usize::MAX, x, y)
    }

    /// The program (of stride 1) over the buffer `v`, every offset taken `& mask` (the identity
    /// on offsets below `v.len()`, which `mask + 1` bounds when `v.len()` is a power of two).
    #[inline(always)]
    fn exec<D: DualNum<f64> + Copy>(&self, v: &mut [D], mask: usize, x: &[D], y: &mut [D]) {
        for (vi, &xi) in v.iter_mut().zip(&x[..self.inputs]) {
            *vi = xi;
        }
        for &(w, c) in &self.consts {
            v[w & mask] = D::from(c);
        }
        for &ins in &self.instructions {
            step(ins, v, mask);
        }
        for (yk, &(o, alpha)) in y[..self.outputs.len()].iter_mut().zip(&self.outputs) {
            *yk = v[o & mask] * alpha;
        }
    }
}

impl Instr {
    /// The offsets the instruction writes.
    pub(super) fn writes(&self) -> impl Iterator<Item = usize> {
        let (a, b) = match *self {
            Instr::Lin { w, .. }
            | Instr::Affine { w, .. }
            | Instr::Mul { w, .. }
            | Instr::MulAdd { w, .. }
            | Instr::Div { w, .. }
            | Instr::Recip { w, .. }
            | Instr::Sqrt { w, .. }
            | Instr::Exp { w, .. }
            | Instr::Ln { w, .. }
            | Instr::Powf { w, .. }
            | Instr::Atan2 { w, .. } => (w, None),
            Instr::Tanh { w, s, .. } => (w, Some(s)),
            Instr::SinCos { s, c, .. } => (s, Some(c)),
        };
        std::iter::once(a).chain(b)
    }

    /// The instruction with every offset `o` replaced by `f(o)`.
    fn map(self, f: impl Fn(usize) -> usize) -> Instr {
        match self {
            Instr::Lin {
                w,
                a,
                alpha,
                b,
                beta,
            } => Instr::Lin {
                w: f(w),
                a: f(a),
                alpha,
                b: f(b),
                beta,
            },
            Instr::Affine { w, a, alpha, gamma } => Instr::Affine {
                w: f(w),
                a: f(a),
                alpha,
                gamma,
            },
            Instr::Mul { w, a, b } => Instr::Mul {
                w: f(w),
                a: f(a),
                b: f(b),
            },
            Instr::MulAdd {
                w,
                a,
                b,
                alpha,
                c,
                beta,
            } => Instr::MulAdd {
                w: f(w),
                a: f(a),
                b: f(b),
                alpha,
                c: f(c),
                beta,
            },
            Instr::Div { w, a, b } => Instr::Div {
                w: f(w),
                a: f(a),
                b: f(b),
            },
            Instr::Recip { w, a } => Instr::Recip { w: f(w), a: f(a) },
            Instr::Sqrt { w, a } => Instr::Sqrt { w: f(w), a: f(a) },
            Instr::Exp { w, a } => Instr::Exp { w: f(w), a: f(a) },
            Instr::Ln { w, a } => Instr::Ln { w: f(w), a: f(a) },
            Instr::Powf { w, a, p } => Instr::Powf {
                w: f(w),
                a: f(a),
                p,
            },
            Instr::Tanh { w, s, a } => Instr::Tanh {
                w: f(w),
                s: f(s),
                a: f(a),
            },
            Instr::SinCos { s, c, a } => Instr::SinCos {
                s: f(s),
                c: f(c),
                a: f(a),
            },
            Instr::Atan2 { w, y, x, r } => Instr::Atan2 {
                w: f(w),
                y: f(y),
                x: f(x),
                r: f(r),
            },
        }
    }

    /// The offsets the instruction reads.
    fn reads(&self) -> impl Iterator<Item = usize> {
        let (a, b, c) = match *self {
            Instr::Lin { a, b, .. } | Instr::Mul { a, b, .. } | Instr::Div { a, b, .. } => {
                (Some(a), Some(b), None)
            }
            Instr::MulAdd { a, b, c, .. } => (Some(a), Some(b), Some(c)),
            Instr::Affine { a, .. }
            | Instr::Recip { a, .. }
            | Instr::Sqrt { a, .. }
            | Instr::Exp { a, .. }
            | Instr::Ln { a, .. }
            | Instr::Powf { a, .. }
            | Instr::Tanh { a, .. }
            | Instr::SinCos { a, .. } => (Some(a), None, None),
            Instr::Atan2 { y, x, r, .. } => (Some(y), Some(x), Some(r)),
        };
        a.into_iter().chain(b).chain(c)
    }
}

/// The value of one instruction (for jets: the coefficient of order 0), each offset `& mask`.
#[inline(always)]
pub(super) fn step<D: DualNum<f64> + Copy>(ins: Instr, v: &mut [D], mask: usize) {
    match ins {
        Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        } => v[w & mask] = v[a & mask] * alpha + v[b & mask] * beta,
        Instr::Affine { w, a, alpha, gamma } => v[w & mask] = v[a & mask] * alpha + gamma,
        Instr::Mul { w, a, b } => v[w & mask] = v[a & mask] * v[b & mask],
        Instr::MulAdd {
            w,
            a,
            b,
            alpha,
            c,
            beta,
        } => v[w & mask] = v[a & mask] * v[b & mask] * alpha + v[c & mask] * beta,
        Instr::Div { w, a, b } => v[w & mask] = v[a & mask] / v[b & mask],
        Instr::Recip { w, a } => v[w & mask] = v[a & mask].recip(),
        Instr::Sqrt { w, a } => v[w & mask] = v[a & mask].sqrt(),
        Instr::Exp { w, a } => v[w & mask] = v[a & mask].exp(),
        Instr::Ln { w, a } => v[w & mask] = v[a & mask].ln(),
        Instr::Powf { w, a, p } => v[w & mask] = v[a & mask].powf(p),
        Instr::Tanh { w, s, a } => {
            let t = tanh(v[a & mask]);
            (v[w & mask], v[s & mask]) = (t, D::one() - t * t)
        }
        Instr::SinCos { s, c, a } => (v[s & mask], v[c & mask]) = v[a & mask].sin_cos(),
        Instr::Atan2 { w, y, x, .. } => v[w & mask] = v[y & mask].atan2(v[x & mask]),
    }
}

/// [`step`] on double-double numbers: the value of one instruction with the elementary
/// functions of [`DoubleDouble`] (`sin`/`cos`, `exp`, `ln`, `tanh`, `atan2`, `xᵖ` to a few
/// `u²`), for the jets of the double-double Taylor method.
#[inline]
pub(super) fn step_double_double(ins: Instr, v: &mut [DoubleDouble]) {
    match ins {
        Instr::Lin {
            w,
            a,
            alpha,
            b,
            beta,
        } => v[w] = v[a] * alpha + v[b] * beta,
        Instr::Affine { w, a, alpha, gamma } => v[w] = v[a] * alpha + DoubleDouble::from(gamma),
        Instr::Mul { w, a, b } => v[w] = v[a] * v[b],
        Instr::MulAdd {
            w,
            a,
            b,
            alpha,
            c,
            beta,
        } => v[w] = v[a] * v[b] * alpha + v[c] * beta,
        Instr::Div { w, a, b } => v[w] = v[a] / v[b],
        Instr::Recip { w, a } => v[w] = v[a].recip(),
        Instr::Sqrt { w, a } => v[w] = v[a].sqrt(),
        Instr::Exp { w, a } => v[w] = v[a].exp(),
        Instr::Ln { w, a } => v[w] = v[a].ln(),
        Instr::Powf { w, a, p } => v[w] = v[a].powf(p),
        Instr::Tanh { w, s, a } => {
            let t = v[a].tanh();
            (v[w], v[s]) = (t, DoubleDouble::from(1.0) - t * t)
        }
        Instr::SinCos { s, c, a } => (v[s], v[c]) = v[a].sin_cos(),
        Instr::Atan2 { w, y, x, .. } => v[w] = v[y].atan2(v[x]),
    }
}

/// `tanh u` on any number type, finite for every finite `u`: the type's own `tanh` for
/// `|u| ≤ 20`, and `sign(u) (1 − z)/(1 + z)`, `z = e^{−2|u|} < 10⁻¹⁷`, beyond, where the former
/// may be `sinh/cosh = ∞/∞` for dual numbers (on `f64` both give `±1` exactly there, since
/// `1 − tanh|u| < 2z` is below half an ulp of 1).
#[inline(always)]
pub(super) fn tanh<D: DualNum<f64> + Copy>(u: D) -> D {
    let x = u.re();
    if x.abs() <= 20.0 {
        return u.tanh();
    }
    let sign = x.signum();
    let z = (u * (-2.0 * sign)).exp();
    (D::one() - z) / (D::one() + z) * sign
}

/// The translation of a record into slots and instructions (see [`Program`]).
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
                Op::Tanh(a) => {
                    let a = self.materialise(at(&value, a));
                    let (w, s) = (self.slot(), self.slot());
                    self.program.push(Instr::Tanh { w, s, a });
                    (w, 1.0)
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
