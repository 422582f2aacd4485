//! The register program of a record compiled to native code (feature `jit`): each slot of the
//! [`Program`] (stride 1, products fused, slots allocated) a variable of the Cranelift code
//! generator, each instruction the same IEEE-754 operations in the same order as the
//! interpreter's [`step`](super::program::step) on `f64` — `+`, `−`, `×`, `/` and `√` as machine
//! instructions (correctly rounded, no fused multiply–add), `exp`, `ln`, `powf`, `tanh`,
//! `sin_cos` and `atan2` as calls of the very Rust functions the interpreter calls — so that the
//! native code and the interpreter agree bit for bit. The function reads its inputs and writes
//! its outputs in one of three layouts ([`Layout`]): flat arrays `x` and `y`; the state vectors
//! of Hamilton's equations, `(t, q, p) → (q̇, ṗ)`; or a vector and a gradient, `(t, z) → ∂f/∂z`
//! with `f` returned in a register. Its slots are machine registers or its own stack frame, which
//! holds the two results of `sin_cos` only when the program has one. The components `2j, 2j + 1`
//! of an output vector of the phase and gradient layouts are written by one 16-byte store: their
//! Rust callers read the vectors back with 16-byte loads, which a processor forwards from a store
//! of the same width but not from two 8-byte stores (the load then waits until the stores reach
//! the cache; `benches/expression.rs` measures both, 3.5× the time of the Hénon–Heiles field). The callers of the phase
//! and gradient layouts ([`Native::call_phase`], [`Native::call_gradient`]) are inlined into
//! theirs, checking only the layout and `n` against the vectors' static length.
//!
//! Compilation happens once (at the construction of an expression system); a host Cranelift does
//! not support, a program larger than [`MAX_INSTRUCTIONS`] or any error of the code generator
//! gives `None`, and the interpreter runs instead.
//!
//! Reference: the Cranelift code generator, <https://cranelift.dev> (Bytecode Alliance),
//! crates `cranelift-codegen`, `cranelift-frontend`, `cranelift-jit`.

#![allow(unsafe_code)]

use super::program::{tanh, Instr, Program};
use cranelift_codegen::ir::{
    types::{F64, F64X2},
    AbiParam, FuncRef, InstBuilder, MemFlags, StackSlot, StackSlotData, StackSlotKind, Value,
};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext, Variable};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, Linkage, Module};
use nalgebra::SVector;
use num_dual::DualNum;
use std::sync::Mutex;

/// The largest program compiled (larger ones are interpreted): bounds the work and memory of the
/// code generator.
pub(super) const MAX_INSTRUCTIONS: usize = 1 << 16;

/// How the compiled function receives the program's inputs and returns its outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Layout {
    /// `f(x, y)`: input `k` at `x[k]`, output `k` to `y[k]`.
    Flat,
    /// `f(t, q, p, a, b)` for a program of inputs `(t, q₁ … qₙ, p₁ … pₙ)` and outputs
    /// `(a₁ … aₙ, b₁ … bₙ)`: Hamilton's equations read from and written to the state vectors
    /// themselves, with no array of inputs built for the call.
    Phase(usize),
    /// `f(t, z, g) → v` for a program of inputs `(t, z₁ … zₙ)` and outputs `(v, g₁ … gₙ)`: a
    /// function and its gradient (the drift `(T, ∂T/∂p)` and the kick `(V, ∂V/∂q)` of a
    /// separable Hamiltonian), `z` read from and `g` written to the vectors themselves, `v`
    /// returned in a register.
    Gradient(usize),
}

/// The signature of a compiled program of [`Layout::Flat`].
type FlatEntry = unsafe extern "C" fn(x: *const f64, y: *mut f64);

/// The signature of a compiled program of [`Layout::Phase`].
type PhaseEntry =
    unsafe extern "C" fn(t: f64, q: *const f64, p: *const f64, a: *mut f64, b: *mut f64);

/// The signature of a compiled program of [`Layout::Gradient`].
type GradientEntry = unsafe extern "C" fn(t: f64, z: *const f64, g: *mut f64) -> f64;

/// The compiled function, of any layout (with its `n`).
#[derive(Clone, Copy)]
enum Entry {
    Flat(FlatEntry),
    Phase(PhaseEntry, usize),
    Gradient(GradientEntry, usize),
}

/// A program compiled to native code, with the module owning the code's memory.
pub(super) struct Native {
    entry: Entry,
    inputs: usize,
    outputs: usize,
    /// The owner of the code memory.
    _code: Code,
}

/// The owner of a module's code memory, freed when dropped. After `finalize_definitions` the
/// module is never used again but by [`Drop`]; the mutex only makes the (`Send`, not `Sync`)
/// module shareable. The owner of the `Code` holds the only pointers into it.
pub(super) struct Code(Mutex<Option<JITModule>>);

impl Code {
    /// The owner of `module`'s memory.
    pub(super) fn new(module: JITModule) -> Self {
        Self(Mutex::new(Some(module)))
    }
}

impl std::fmt::Debug for Native {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Native")
            .field("inputs", &self.inputs)
            .field("outputs", &self.outputs)
            .finish_non_exhaustive()
    }
}

impl Drop for Code {
    fn drop(&mut self) {
        let module = match self.0.get_mut() {
            Ok(m) => m.take(),
            Err(poisoned) => poisoned.into_inner().take(),
        };
        if let Some(module) = module {
            // SAFETY: the only pointers into the module's code live in the owner of `self`
            // (a `Native` or a compiled Taylor pass), which is being dropped: no call of them
            // is running or can follow.
            unsafe { module.free_memory() }
        }
    }
}

impl Native {
    /// Whether the function is of [`Layout::Flat`] (for [`call`](Self::call)).
    pub(super) fn is_flat(&self) -> bool {
        matches!(self.entry, Entry::Flat(_))
    }

    /// The outputs at `x` into `y`, as [`Program::eval`] on `f64`.
    ///
    /// # Panics
    /// If `x` holds fewer values than the program has inputs or `y` fewer than it has outputs,
    /// or if the function is not of [`Layout::Flat`].
    #[inline]
    pub(super) fn call(&self, x: &[f64], y: &mut [f64]) {
        let Entry::Flat(entry) = self.entry else {
            panic!("a native program of another layout called with flat arrays");
        };
        assert!(x.len() >= self.inputs && y.len() >= self.outputs);
        // SAFETY: `entry` was compiled by `compile` with the signature `FlatEntry` for the
        // host's C calling convention; it reads `x[0 .. inputs]` and writes `y[0 .. outputs]`
        // only, which the assertion keeps in bounds; its code memory is owned by `self.module`,
        // which lives as long as `self`.
        unsafe { entry(x.as_ptr(), y.as_mut_ptr()) }
    }

    /// The outputs at `(t, q, p)` into `(a, b)`, for a function of [`Layout::Phase`] with
    /// `n = N`; `false` (nothing written) for a function of another layout or size.
    #[inline(always)]
    pub(super) fn call_phase<const N: usize>(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        a: &mut SVector<f64, N>,
        b: &mut SVector<f64, N>,
    ) -> bool {
        let Entry::Phase(entry, n) = self.entry else {
            return false;
        };
        if n != N {
            return false;
        }
        // SAFETY: `entry` was compiled by `compile` with the signature `PhaseEntry`; it reads
        // `q[0 .. n]`, `p[0 .. n]` and writes `a[0 .. n]`, `b[0 .. n]` only, `n = N` the length
        // of each vector (contiguous storage); its code memory is owned by `self.module`.
        unsafe { entry(t, q.as_ptr(), p.as_ptr(), a.as_mut_ptr(), b.as_mut_ptr()) };
        true
    }

    /// The first output at `(t, z)`, the others into `g`, for a function of
    /// [`Layout::Gradient`] with `n = N`; `None` (nothing written) for a function of another
    /// layout or size.
    #[inline(always)]
    pub(super) fn call_gradient<const N: usize>(
        &self,
        t: f64,
        z: &SVector<f64, N>,
        g: &mut SVector<f64, N>,
    ) -> Option<f64> {
        let Entry::Gradient(entry, n) = self.entry else {
            return None;
        };
        if n != N {
            return None;
        }
        // SAFETY: `entry` was compiled by `compile` with the signature `GradientEntry`; it
        // reads `z[0 .. n]` and writes `g[0 .. n]` only, `n = N` the length of each vector
        // (contiguous storage); its code memory is owned by `self.module`.
        Some(unsafe { entry(t, z.as_ptr(), g.as_mut_ptr()) })
    }

    /// The program compiled with `layout`, or `None` when it cannot be (see the
    /// [module docs](self)) or when the program's inputs and outputs do not fit the layout.
    pub(super) fn compile(program: &Program, layout: Layout) -> Option<Native> {
        if program.stride != 1 || program.instructions.len() > MAX_INSTRUCTIONS {
            return None;
        }
        let fits = match layout {
            Layout::Flat => true,
            Layout::Phase(n) => program.inputs == 1 + 2 * n && program.outputs.len() == 2 * n,
            Layout::Gradient(n) => program.inputs == 1 + n && program.outputs.len() == 1 + n,
        };
        if !fits {
            return None;
        }
        let mut module = new_module()?;
        let address = translate(&mut module, program, layout)?;
        // SAFETY: `translate` defined and finalized the function with the signature of
        // `layout` (`FlatEntry`: two pointer parameters, no result; `PhaseEntry`: an `f64` and
        // four pointers, no result; `GradientEntry`: an `f64` and two pointers, an `f64`
        // result; the default calling convention of the host, which is its C convention).
        let entry = match layout {
            Layout::Flat => {
                Entry::Flat(unsafe { std::mem::transmute::<*const u8, FlatEntry>(address) })
            }
            Layout::Phase(n) => Entry::Phase(
                unsafe { std::mem::transmute::<*const u8, PhaseEntry>(address) },
                n,
            ),
            Layout::Gradient(n) => Entry::Gradient(
                unsafe { std::mem::transmute::<*const u8, GradientEntry>(address) },
                n,
            ),
        };
        Some(Native {
            entry,
            inputs: program.inputs,
            outputs: program.outputs.len(),
            _code: Code::new(module),
        })
    }
}

/// A module for the host's instruction set (optimised for speed, absolute addresses) in which
/// the [shims](SHIMS) are defined; `None` when Cranelift does not support the host.
pub(super) fn new_module() -> Option<JITModule> {
    let mut flags = settings::builder();
    flags.set("use_colocated_libcalls", "false").ok()?;
    flags.set("is_pic", "false").ok()?;
    flags.set("opt_level", "speed").ok()?;
    let isa = cranelift_native::builder()
        .ok()?
        .finish(settings::Flags::new(flags))
        .ok()?;
    let mut builder = JITBuilder::with_isa(isa, default_libcall_names());
    for (name, _, address) in SHIMS {
        builder.symbol(*name, *address);
    }
    Some(JITModule::new(builder))
}

/// The functions the native code calls: name, `(parameters, results)` in `f64`s (the
/// parameter of `sin_cos` is followed by a pointer to its two results), address.
const SHIMS: &[(&str, (usize, usize), *const u8)] = &[
    ("hj_exp", (1, 1), exp as *const u8),
    ("hj_ln", (1, 1), ln as *const u8),
    ("hj_powf", (2, 1), powf as *const u8),
    ("hj_tanh", (1, 1), tanh_f64 as *const u8),
    ("hj_sin_cos", (1, 0), sin_cos as *const u8),
    ("hj_atan2", (2, 1), atan2 as *const u8),
];

extern "C" fn exp(a: f64) -> f64 {
    DualNum::<f64>::exp(&a)
}

extern "C" fn ln(a: f64) -> f64 {
    DualNum::<f64>::ln(&a)
}

extern "C" fn powf(a: f64, p: f64) -> f64 {
    DualNum::<f64>::powf(&a, p)
}

extern "C" fn tanh_f64(a: f64) -> f64 {
    tanh(a)
}

extern "C" fn sin_cos(a: f64, out: *mut [f64; 2]) {
    let (s, c) = DualNum::<f64>::sin_cos(&a);
    // SAFETY: the native code passes the address of a stack slot of its own frame of two
    // `f64`s, 8-aligned, for this call only.
    unsafe { *out = [s, c] }
}

extern "C" fn atan2(y: f64, x: f64) -> f64 {
    DualNum::<f64>::atan2(&y, x)
}

/// Define and finalize the function of `program` in `module`; its address.
fn translate(module: &mut JITModule, program: &Program, layout: Layout) -> Option<*const u8> {
    let pointer = module.target_config().pointer_type();
    let mut ctx = module.make_context();
    let params = &mut ctx.func.signature.params;
    match layout {
        Layout::Flat => params.extend([AbiParam::new(pointer); 2]),
        Layout::Phase(_) => {
            params.push(AbiParam::new(F64));
            params.extend([AbiParam::new(pointer); 4]);
        }
        Layout::Gradient(_) => {
            params.push(AbiParam::new(F64));
            params.extend([AbiParam::new(pointer); 2]);
            ctx.func.signature.returns.push(AbiParam::new(F64));
        }
    }
    let mut fctx = FunctionBuilderContext::new();
    let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
    let shims = Shims::import(module, &mut b)?;
    let block = b.create_block();
    b.append_block_params_for_function_params(block);
    b.switch_to_block(block);
    b.seal_block(block);
    let params = b.block_params(block).to_vec();
    // The two results of `sin_cos`, in a slot of the frame only when the program has one (a
    // function with no slot and no call needs no frame).
    let pair = pair_slot(&mut b, &program.instructions);
    let slot: Vec<Variable> = (0..program.slots).map(|_| b.declare_var(F64)).collect();
    let flags = MemFlags::trusted();
    let offset = |k: usize| i32::try_from(8 * k).ok();
    // Input `k` and output `k`: a pointer parameter and an offset (input 0 of the phase and
    // gradient layouts, `t`, is the parameter itself, and output 0 of the gradient layout the
    // result, which are not looked up here).
    let input = |k: usize| match layout {
        Layout::Flat => (0, k),
        Layout::Phase(n) if k <= n => (1, k - 1),
        Layout::Phase(n) => (2, k - 1 - n),
        Layout::Gradient(_) => (1, k - 1),
    };
    let output = |k: usize| match layout {
        Layout::Flat => (1, k),
        Layout::Phase(n) if k < n => (3, k),
        Layout::Phase(n) => (4, k - n),
        Layout::Gradient(_) => (2, k - 1),
    };
    for (k, &var) in slot.iter().enumerate().take(program.inputs) {
        let v = match (layout, k) {
            (Layout::Phase(_) | Layout::Gradient(_), 0) => params[0],
            _ => {
                let (base, at) = input(k);
                b.ins().load(F64, flags, params[base], offset(at)?)
            }
        };
        b.def_var(var, v);
    }
    for &(w, c) in &program.consts {
        let v = b.ins().f64const(c);
        b.def_var(slot[w], v);
    }
    for &ins in &program.instructions {
        let (first, second) = shims.step(&mut b, ins, pair, |b, s| b.use_var(slot[s]))?;
        let mut writes = ins.writes();
        if let Some(w) = writes.next() {
            b.def_var(slot[w], first);
        }
        if let (Some(o), Some(v)) = (writes.next(), second) {
            b.def_var(slot[o], v);
        }
    }
    let mut result = Vec::with_capacity(1);
    // The stores of the outputs, `(parameter, index, value)`.
    let mut stores = Vec::with_capacity(program.outputs.len());
    for (k, &(o, alpha)) in program.outputs.iter().enumerate() {
        let v = b.use_var(slot[o]);
        let r = scale(&mut b, v, alpha);
        if matches!(layout, Layout::Gradient(_)) && k == 0 {
            result.push(r);
            continue;
        }
        let (base, at) = output(k);
        stores.push((base, at, r));
    }
    // The vectors of the phase and gradient layouts are read back by their (Rust) callers with
    // 16-byte loads, which the processor forwards from a 16-byte store but not from two 8-byte
    // ones (a stall until the stores reach the cache): components `2j, 2j + 1` of an output
    // vector are stored together, as one `f64x2` (the same bits).
    let paired = !matches!(layout, Layout::Flat);
    let mut k = 0;
    while k < stores.len() {
        let (base, at, r) = stores[k];
        match stores.get(k + 1) {
            Some(&(next, at1, r1)) if paired && at % 2 == 0 && next == base && at1 == at + 1 => {
                let v = b.ins().scalar_to_vector(F64X2, r);
                let v = b.ins().insertlane(v, r1, 1);
                // In bounds and not trapping, but only 8-aligned.
                let unaligned = MemFlags::new().with_notrap();
                b.ins().store(unaligned, v, params[base], offset(at)?);
                k += 2;
            }
            _ => {
                b.ins().store(flags, r, params[base], offset(at)?);
                k += 1;
            }
        }
    }
    b.ins().return_(&result);
    b.finalize();
    define(module, &mut ctx)
}

/// Define the function built in `ctx` in `module` and finalize it; its address.
pub(super) fn define(
    module: &mut JITModule,
    ctx: &mut cranelift_codegen::Context,
) -> Option<*const u8> {
    let id = module
        .declare_function("program", Linkage::Export, &ctx.func.signature)
        .ok()?;
    module.define_function(id, ctx).ok()?;
    module.clear_context(ctx);
    module.finalize_definitions().ok()?;
    Some(module.get_finalized_function(id))
}

/// `α v` with the interpreter's rounding: `v · 1 = v` and `v · (−1) = −v` exactly (NaNs aside,
/// whose payload is not compared), so those factors make no multiplication.
pub(super) fn scale(b: &mut FunctionBuilder, v: Value, alpha: f64) -> Value {
    if alpha == 1.0 {
        v
    } else if alpha == -1.0 {
        b.ins().fneg(v)
    } else {
        let k = b.ins().f64const(alpha);
        b.ins().fmul(v, k)
    }
}

/// The two results of `sin_cos`, in a slot of the frame only when `program` has a
/// [`Instr::SinCos`] (a function with no slot and no call needs no frame).
pub(super) fn pair_slot(b: &mut FunctionBuilder, program: &[Instr]) -> Option<StackSlot> {
    program
        .iter()
        .any(|i| matches!(i, Instr::SinCos { .. }))
        .then(|| b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 16, 3)))
}

/// The [shims](SHIMS) imported into a function being built.
pub(super) struct Shims {
    exp: FuncRef,
    ln: FuncRef,
    powf: FuncRef,
    tanh: FuncRef,
    sin_cos: FuncRef,
    atan2: FuncRef,
    pointer: cranelift_codegen::ir::Type,
}

impl Shims {
    /// Declare the shims in `module` and import them into the function of `b`.
    pub(super) fn import(module: &mut JITModule, b: &mut FunctionBuilder) -> Option<Self> {
        let pointer = module.target_config().pointer_type();
        let mut refs = Vec::with_capacity(SHIMS.len());
        for (name, (params, results), _) in SHIMS {
            let mut sig = module.make_signature();
            sig.params.extend((0..*params).map(|_| AbiParam::new(F64)));
            if *results == 0 {
                sig.params.push(AbiParam::new(pointer));
            }
            sig.returns
                .extend((0..*results).map(|_| AbiParam::new(F64)));
            let id = module.declare_function(name, Linkage::Import, &sig).ok()?;
            refs.push(module.declare_func_in_func(id, b.func));
        }
        let [exp, ln, powf, tanh, sin_cos, atan2] = refs[..] else {
            return None;
        };
        Some(Self {
            exp,
            ln,
            powf,
            tanh,
            sin_cos,
            atan2,
            pointer,
        })
    }

    /// The value(s) of `ins` on `f64` — [`step`](super::program::step)'s operations in its
    /// order — from its operands' values `get(b, offset)`: the result written to its first
    /// offset, and for [`Instr::Tanh`] and [`Instr::SinCos`] the second (`pair` the frame slot
    /// of [`pair_slot`]). `None` for a `SinCos` without that slot.
    pub(super) fn step(
        &self,
        b: &mut FunctionBuilder,
        ins: Instr,
        pair: Option<StackSlot>,
        mut get: impl FnMut(&mut FunctionBuilder, usize) -> Value,
    ) -> Option<(Value, Option<Value>)> {
        let call = |b: &mut FunctionBuilder, f: FuncRef, args: &[Value]| -> Value {
            let inst = b.ins().call(f, args);
            b.inst_results(inst)[0]
        };
        let one = |v: Value| Some((v, None));
        match ins {
            Instr::Lin {
                a,
                alpha,
                b: bb,
                beta,
                ..
            } => {
                let (va, vb) = (get(b, a), get(b, bb));
                let ta = scale(b, va, alpha);
                // `x + (−1)·y = x − y` exactly.
                if beta == -1.0 {
                    one(b.ins().fsub(ta, vb))
                } else {
                    let tb = scale(b, vb, beta);
                    one(b.ins().fadd(ta, tb))
                }
            }
            Instr::Affine {
                a, alpha, gamma, ..
            } => {
                let va = get(b, a);
                let ta = scale(b, va, alpha);
                let kg = b.ins().f64const(gamma);
                one(b.ins().fadd(ta, kg))
            }
            Instr::Mul { a, b: bb, .. } => {
                let (va, vb) = (get(b, a), get(b, bb));
                one(b.ins().fmul(va, vb))
            }
            Instr::MulAdd {
                a,
                b: bb,
                alpha,
                c,
                beta,
                ..
            } => {
                let (va, vb, vc) = (get(b, a), get(b, bb), get(b, c));
                let ab = b.ins().fmul(va, vb);
                let ta = scale(b, ab, alpha);
                if beta == -1.0 {
                    one(b.ins().fsub(ta, vc))
                } else {
                    let tc = scale(b, vc, beta);
                    one(b.ins().fadd(ta, tc))
                }
            }
            Instr::Div { a, b: bb, .. } => {
                let (va, vb) = (get(b, a), get(b, bb));
                one(b.ins().fdiv(va, vb))
            }
            Instr::Recip { a, .. } => {
                // `f64::recip` is `1 / a`.
                let va = get(b, a);
                let k1 = b.ins().f64const(1.0);
                one(b.ins().fdiv(k1, va))
            }
            Instr::Sqrt { a, .. } => {
                let va = get(b, a);
                one(b.ins().sqrt(va))
            }
            Instr::Exp { a, .. } => {
                let va = get(b, a);
                one(call(b, self.exp, &[va]))
            }
            Instr::Ln { a, .. } => {
                let va = get(b, a);
                one(call(b, self.ln, &[va]))
            }
            Instr::Powf { a, p, .. } => {
                let va = get(b, a);
                let kp = b.ins().f64const(p);
                one(call(b, self.powf, &[va, kp]))
            }
            Instr::Tanh { a, .. } => {
                let va = get(b, a);
                let t = call(b, self.tanh, &[va]);
                let k1 = b.ins().f64const(1.0);
                let tt = b.ins().fmul(t, t);
                let r = b.ins().fsub(k1, tt);
                Some((t, Some(r)))
            }
            Instr::SinCos { a, .. } => {
                let va = get(b, a);
                let address = b.ins().stack_addr(self.pointer, pair?, 0);
                b.ins().call(self.sin_cos, &[va, address]);
                let vs = b.ins().stack_load(F64, pair?, 0);
                let vc = b.ins().stack_load(F64, pair?, 8);
                Some((vs, Some(vc)))
            }
            Instr::Atan2 { y, x, .. } => {
                let (vy, vx) = (get(b, y), get(b, x));
                one(call(b, self.atan2, &[vy, vx]))
            }
        }
    }
}
