//! Systems defined by expressions in text: a Hamiltonian such as `"p^2/2 - cos(q)"` with named
//! coordinates, momenta and parameters, parsed once ([`parse`]), compiled once to an operation
//! [`Record`] and evaluated generically over [`DualNum<f64>`], so that every method that applies
//! to a Rust-written system — AD, brackets, integrators, Taylor jets, normal forms, action–angle
//! variables — applies to it.
//!
//! An [`Expression`] is a scalar function `f(x₁, …, x_n)` of named variables, its parameters
//! replaced by their values. [`ExpressionHamiltonian`] is `H(t, q, p)` with Hamilton's equations
//!
//! ```math
//! \dot q = \frac{\partial H}{\partial p},\qquad \dot p = -\frac{\partial H}{\partial q}
//! ```
//!
//! taken from a second record holding `H` and its gradient, made by the adjoint sweep of
//! [`crate::record::gradient`] (Griewank & Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008,
//! ch. 3.2), so that the vector field costs one pass over a flat list of operations.
//! [`ExpressionSeparable`] is `H = T(t, p) + V(t, q)`, which the explicit splitting methods need
//! ([`ExpressionHamiltonian::separable`] splits a Hamiltonian whose terms each depend on `p` or
//! on `q` only). [`ExpressionLagrangian`] is `L(t, q, q̇)`, a Hamiltonian system through the
//! Legendre transform [`Legendre`](crate::Legendre). [`ExpressionDisturbingFunction`] is a
//! disturbing function `R(t, q)` of the Kepler problem ([`disturbing`]), [`ExpressionConstraints`]
//! holonomic constraints `g(t, q) = 0` and [`ExpressionPfaffian`] Pfaffian constraints
//! `a(t, q) q̇ + b(t, q) = 0` ([`constraints`]).
//!
//! # Cost
//! The records are evaluated by the register program of [`crate::record`] (operations folded
//! and fused, slots reused). On `f64` — the vector field, the gradient, the drift and the kick
//! that integrators call — the programs of [`ExpressionHamiltonian`] and [`ExpressionSeparable`]
//! are compiled once, at construction, to native code by the Cranelift code generator
//! (<https://cranelift.dev>; feature `jit`, on by default): each slot a variable of the code
//! generator, each instruction the same IEEE-754 operations in the same order as the interpreter
//! (no fused multiply–add), `exp`, `ln`, `powf`, `tanh`, `sin_cos` and `atan2` calls of the same
//! Rust functions, so the native code gives the interpreter's values bit for bit. The vector field
//! reads `q`, `p` and writes `q̇`, `ṗ` in place; the drift and the kick read `p` (or `q`), write
//! `∂T/∂p` (or `∂V/∂q`) in place and return `T` (or `V`) in a register, each pair of components
//! by one 16-byte store, which the caller's 16-byte reads are forwarded from; the call is inlined
//! into the caller, so that an evaluation costs the native code and an indirect call
//! (`examples/expression_cost.rs` counts the instructions). The Hénon–Heiles vector field by
//! expression takes 1.3–1.5× the time of the Rust-written one, as much as the same field written
//! in Rust and called through a function pointer (`benches/expression.rs`). Dual numbers,
//! recorded values and Taylor jets run the interpreter; so does `f64` without the feature, on a
//! host Cranelift does not support, or where compilation fails (silently: a speed path, not a
//! change of values). [`ExpressionHamiltonian::interpreted`] gives the interpreted system, for
//! verification; [`ExpressionHamiltonian::is_native`] tells which runs.
//!
//! The number of degrees of freedom is a const generic of the systems; a number known only at run
//! time is dispatched to `N = 1 … MAX_DOF` by [`with_dof!`](crate::with_dof).
//!
//! Names: the variables are the names given (coordinates, momenta or velocities, parameters) and
//! `t`; the constant `pi`; the functions of [`parse::FUNCTIONS`]. The momentum of the coordinate
//! `x` is `p_x` and its velocity `v_x` unless other names are given.

pub mod constraints;
pub mod disturbing;
pub mod parse;

pub use constraints::{ExpressionConstraints, ExpressionPfaffian};
pub use disturbing::ExpressionDisturbingFunction;

use crate::error::{Error, Result};
use crate::hamiltonian::{Hamiltonian, Separable};
use crate::lagrangian::Lagrangian;
use crate::record::{self, Compiled, Record};
use nalgebra::SVector;
use num_dual::DualNum;
use parse::{BinOp, Expr, FUNCTIONS};

/// The largest number of degrees of freedom [`with_dof!`](crate::with_dof) dispatches to.
pub const MAX_DOF: usize = 6;

/// Run `$body` with the const `$n` bound to the run-time number of degrees of freedom
/// `$dof ∈ 1 … MAX_DOF`, `$other` otherwise:
///
/// ```
/// use hamilton_jacobi::with_dof;
/// use hamilton_jacobi::expression::ExpressionHamiltonian;
/// use hamilton_jacobi::Hamiltonian;
/// use hamilton_jacobi::nalgebra::SVector;
/// let coordinates = ["x", "y"];
/// let e = with_dof!(coordinates.len(), N => {
///     let h = ExpressionHamiltonian::<N>::new("(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2", &coordinates, None, &[])?;
///     h.value(0.0, &SVector::repeat(1.0), &SVector::repeat(0.0))
/// }, Err(hamilton_jacobi::Error::invalid("dof", "not in 1 … 6")));
/// assert_eq!(e.unwrap(), 1.0);
/// # Ok::<(), hamilton_jacobi::Error>(())
/// ```
#[macro_export]
macro_rules! with_dof {
    ($dof:expr, $n:ident => $body:expr, $other:expr) => {
        match $dof {
            1 => {
                const $n: usize = 1;
                $body
            }
            2 => {
                const $n: usize = 2;
                $body
            }
            3 => {
                const $n: usize = 3;
                $body
            }
            4 => {
                const $n: usize = 4;
                $body
            }
            5 => {
                const $n: usize = 5;
                $body
            }
            6 => {
                const $n: usize = 6;
                $body
            }
            _ => $other,
        }
    };
}

/// A scalar function of named variables, parsed from text and compiled to an operation record
/// whose inputs are the variables in the order given.
#[derive(Clone, Debug)]
pub struct Expression {
    text: String,
    variables: Vec<String>,
    expr: Expr,
    record: Record,
}

/// Whether `name` can name a variable or parameter: a letter or `_` then letters, digits and
/// `_`, not a function.
fn check_name(name: &str, what: &str) -> Result<()> {
    let mut chars = name.chars();
    let first_ok = chars.next().is_some_and(|c| c.is_alphabetic() || c == '_');
    if !first_ok || !chars.all(|c| c.is_alphanumeric() || c == '_') {
        return Err(Error::invalid(
            format!("{what} name `{name}`"),
            "a name is a letter or `_` followed by letters, digits and `_`",
        ));
    }
    if FUNCTIONS.iter().any(|f| f.0 == name) {
        return Err(Error::invalid(
            format!("{what} name `{name}`"),
            "is the name of a function",
        ));
    }
    Ok(())
}

impl Expression {
    /// Parse `text` as a function of `variables` (in this order the inputs of the record), the
    /// `parameters` replaced by their values, and compile it.
    ///
    /// # Errors
    /// [`Error::Parse`] as [`parse::parse`]; [`Error::InvalidInput`] for no variables, a name
    /// that is not an identifier, a function name or given twice; [`Error::NonFinite`] for a
    /// parameter value.
    pub fn new(text: &str, variables: &[&str], parameters: &[(&str, f64)]) -> Result<Self> {
        if variables.is_empty() {
            return Err(Error::invalid("expression variables", "none given"));
        }
        let mut names: Vec<&str> = Vec::with_capacity(variables.len() + parameters.len());
        for (name, what) in variables
            .iter()
            .map(|v| (*v, "variable"))
            .chain(parameters.iter().map(|p| (p.0, "parameter")))
        {
            check_name(name, what)?;
            if names.contains(&name) {
                return Err(Error::invalid(
                    format!("{what} name `{name}`"),
                    "given twice",
                ));
            }
            names.push(name);
        }
        for (name, value) in parameters {
            crate::error::finite(format_args!("parameter `{name}`"), *value)?;
        }
        let parsed = parse::parse(text, &names)?;
        let values: Vec<f64> = parameters.iter().map(|p| p.1).collect();
        let expr = substitute(parsed, variables.len(), &values);
        let record = record::record(&vec![0.5; variables.len()], |x| Ok(vec![expr.eval(x)]))?;
        Ok(Self {
            text: text.to_string(),
            variables: variables.iter().map(|v| v.to_string()).collect(),
            expr,
            record,
        })
    }

    /// The text the expression was parsed from.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The variables, in the order of the inputs.
    pub fn variables(&self) -> &[String] {
        &self.variables
    }

    /// The parsed expression, parameters replaced by their values.
    pub fn tree(&self) -> &Expr {
        &self.expr
    }

    /// The compiled record (one output).
    pub fn record(&self) -> &Record {
        &self.record
    }

    /// The value at `x` (the variables in order) on any number type, without validation.
    ///
    /// # Panics
    /// If `x` holds fewer values than there are variables.
    pub fn eval<D: DualNum<f64> + Copy>(&self, x: &[D]) -> D {
        let mut y = [D::zero()];
        self.record.eval_into(x, &mut y);
        y[0]
    }

    /// The value at `x` on reals.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for the wrong number of values; [`Error::NonFinite`] for a
    /// non-finite input or value (naming the expression).
    pub fn value(&self, x: &[f64]) -> Result<f64> {
        let y = self.record.eval(x).map_err(|e| match e {
            Error::NonFinite { value, .. } if x.iter().all(|v| v.is_finite()) => Error::NonFinite {
                what: format!("`{}` at {}", self.text, self.at(x)),
                value,
            },
            e => e,
        })?;
        Ok(y[0])
    }

    fn at(&self, x: &[f64]) -> String {
        self.variables
            .iter()
            .zip(x)
            .map(|(n, v)| format!("{n} = {}", crate::error::fmt_num(*v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `expr` with the variables `i ≥ first` replaced by `values[i − first]`.
fn substitute(expr: Expr, first: usize, values: &[f64]) -> Expr {
    match expr {
        Expr::Var(i) if i >= first => Expr::Num(values[i - first]),
        Expr::Num(_) | Expr::Var(_) => expr,
        Expr::Neg(a) => Expr::Neg(Box::new(substitute(*a, first, values))),
        Expr::Bin(op, a, b) => Expr::Bin(
            op,
            Box::new(substitute(*a, first, values)),
            Box::new(substitute(*b, first, values)),
        ),
        Expr::Call(f, args) => Expr::Call(
            f,
            args.into_iter()
                .map(|a| substitute(a, first, values))
                .collect(),
        ),
    }
}

/// The expression `text` in the variables `t`, `coordinates` (`N` names), and `second`
/// (momenta or velocities: `N` names, default the coordinate's name under `default`), with the
/// `parameters`.
fn phase_expression<const N: usize>(
    text: &str,
    coordinates: &[&str],
    second: Option<&[&str]>,
    (what, default): (&str, fn(&str) -> String),
    parameters: &[(&str, f64)],
) -> Result<Expression> {
    if N == 0 || N > MAX_DOF {
        return Err(Error::invalid(
            "degrees of freedom",
            format!("{N}; expression systems have 1 … {MAX_DOF}"),
        ));
    }
    for (names, what) in [(Some(coordinates), "coordinates"), (second, what)] {
        if let Some(names) = names.filter(|n| n.len() != N) {
            return Err(Error::invalid(
                what,
                format!("{} names for {N} degrees of freedom", names.len()),
            ));
        }
    }
    let second: Vec<String> = match second {
        Some(m) => m.iter().map(|s| s.to_string()).collect(),
        None => coordinates.iter().map(|q| default(q)).collect(),
    };
    let names: Vec<&str> = std::iter::once("t")
        .chain(coordinates.iter().copied())
        .chain(second.iter().map(String::as_str))
        .collect();
    Expression::new(text, &names, parameters)
}

/// The inputs `(t, q, p)` of a record, on the stack.
#[inline]
fn inputs<D: DualNum<f64> + Copy, const N: usize>(
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
) -> [D; 1 + 2 * MAX_DOF] {
    let mut x = [t; 1 + 2 * MAX_DOF];
    x[1..=N].copy_from_slice(q.as_slice());
    x[1 + N..1 + 2 * N].copy_from_slice(p.as_slice());
    x
}

/// A Hamiltonian `H(t, q, p)` given by an expression in named coordinates, momenta and
/// parameters; Hamilton's equations by the recorded gradient (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ExpressionHamiltonian<const N: usize> {
    h: Expression,
    gradient: Compiled,
    /// Hamilton's equations `(∂H/∂p, −∂H/∂q)`.
    field: Compiled,
}

impl<const N: usize> ExpressionHamiltonian<N> {
    /// `H` from `text` in the `coordinates` (`N` names), the `momenta` (default `p_<name>` for
    /// each coordinate), the time `t` and the `parameters` with their values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF` or a number of names that is not
    /// `N`; the errors of [`Expression::new`].
    pub fn new(
        text: &str,
        coordinates: &[&str],
        momenta: Option<&[&str]>,
        parameters: &[(&str, f64)],
    ) -> Result<Self> {
        let h = phase_expression::<N>(
            text,
            coordinates,
            momenta,
            ("momenta", |q| format!("p_{q}")),
            parameters,
        )?;
        let gradient = record::record(&vec![0.5; 1 + 2 * N], |x| {
            let y = h.tree().eval(x);
            let mut out = vec![y];
            out.extend(record::gradient(y, &x[1..]));
            Ok(out)
        })?;
        let field = record::record(&vec![0.5; 1 + 2 * N], |x| {
            let g = record::gradient(h.tree().eval(x), &x[1..]);
            Ok(g[N..]
                .iter()
                .copied()
                .chain(g[..N].iter().map(|d| -*d))
                .collect())
        })?;
        Ok(Self {
            h,
            gradient: Compiled::new(gradient),
            field: Compiled::phase(field, N),
        })
    }

    /// The same system with its gradient and vector field on `f64` evaluated by the interpreter
    /// of the register program instead of native code (see the [module docs](self#cost)): the
    /// same values bit for bit, more slowly; for verifying the native code.
    pub fn interpreted(&self) -> Self {
        Self {
            h: self.h.clone(),
            gradient: self.gradient.interpreted(),
            field: self.field.interpreted(),
        }
    }

    /// Whether the gradient and vector field on `f64` run native code (feature `jit`, on a host
    /// Cranelift supports; see the [module docs](self#cost)).
    pub fn is_native(&self) -> bool {
        self.gradient.is_native() && self.field.is_native()
    }

    /// The expression of `H`; its variables are `t`, the coordinates, the momenta.
    pub fn expression(&self) -> &Expression {
        &self.h
    }

    /// The record of `(H, ∂H/∂q, ∂H/∂p)`, inputs `(t, q, p)`.
    pub fn gradient_record(&self) -> &Record {
        self.gradient.record()
    }

    /// `H` and its gradient at a state, refused when any of them is not finite: the check of an
    /// initial state.
    ///
    /// # Errors
    /// [`Error::NonFinite`] naming the expression, the quantity (`H`, `∂H/∂<name>`) and the
    /// state.
    pub fn check_state(&self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        crate::phase::check_phase(t, q, p)?;
        let x = inputs(t, q, p);
        let mut y = [0.0; 1 + 2 * MAX_DOF];
        let y = &mut y[..1 + 2 * N];
        self.gradient.eval_f64(&x[..1 + 2 * N], y);
        let names = self.h.variables();
        for (k, v) in y.iter().enumerate() {
            if !v.is_finite() {
                let what = if k == 0 {
                    "H".to_string()
                } else {
                    format!("∂H/∂{}", names[k])
                };
                return Err(Error::NonFinite {
                    what: format!(
                        "{what} of `{}` at {}",
                        self.h.text(),
                        self.h.at(&x[..1 + 2 * N])
                    ),
                    value: *v,
                });
            }
        }
        Ok(y[0])
    }

    /// `H = T(t, p) + V(t, q)` when every term of the sum at the top of `H` depends on the
    /// momenta only or on the coordinates only (constants go to `V`); `None` otherwise.
    pub fn separable(&self) -> Option<ExpressionSeparable<N>> {
        let mut terms = Vec::new();
        additive_terms(self.h.tree(), false, &mut terms);
        let uses = |e: &Expr, range: std::ops::Range<usize>| range.into_iter().any(|i| e.uses(i));
        let (mut kinetic, mut potential) = (None, None);
        for (negative, term) in terms {
            let on_q = uses(term, 1..1 + N);
            let on_p = uses(term, 1 + N..1 + 2 * N);
            let slot = match (on_q, on_p) {
                (true, true) => return None,
                (false, true) => &mut kinetic,
                _ => &mut potential,
            };
            *slot = Some(match slot.take() {
                None if negative => Expr::Neg(Box::new(term.clone())),
                None => term.clone(),
                Some(sum) => Expr::Bin(
                    if negative { BinOp::Sub } else { BinOp::Add },
                    Box::new(sum),
                    Box::new(term.clone()),
                ),
            });
        }
        let names = self.h.variables();
        let compile = |e: Option<Expr>,
                       range: std::ops::Range<usize>,
                       part: &str|
         -> Option<(Expression, Compiled)> {
            let e = e.unwrap_or(Expr::Num(0.0));
            // The part's own variables: t and one half of the phase variables.
            let mut map = vec![usize::MAX; 1 + 2 * N];
            map[0] = 0;
            for (k, i) in range.clone().enumerate() {
                map[i] = k + 1;
            }
            let e = renumber(e, &map);
            let vars: Vec<&str> = std::iter::once("t")
                .chain(range.map(|i| names[i].as_str()))
                .collect();
            let text = format!("{part} of `{}`", self.h.text());
            let record = record::record(&vec![0.5; vars.len()], |x| Ok(vec![e.eval(x)])).ok()?;
            let gradient = record::record(&vec![0.5; vars.len()], |x| {
                let y = e.eval(x);
                let mut out = vec![y];
                out.extend(record::gradient(y, &x[1..]));
                Ok(out)
            })
            .ok()?;
            let expression = Expression {
                text,
                variables: vars.iter().map(|v| v.to_string()).collect(),
                expr: e,
                record,
            };
            Some((expression, Compiled::gradient(gradient, N)))
        };
        let (kinetic, kinetic_gradient) =
            compile(kinetic, 1 + N..1 + 2 * N, "the kinetic part T(t, p)")?;
        let (potential, potential_gradient) =
            compile(potential, 1..1 + N, "the potential part V(t, q)")?;
        Some(ExpressionSeparable {
            hamiltonian: self.clone(),
            kinetic,
            potential,
            kinetic_gradient,
            potential_gradient,
        })
    }
}

/// The terms of the sums and differences at the top of `e`, with their signs.
fn additive_terms<'e>(e: &'e Expr, negative: bool, out: &mut Vec<(bool, &'e Expr)>) {
    match e {
        Expr::Bin(BinOp::Add, a, b) => {
            additive_terms(a, negative, out);
            additive_terms(b, negative, out);
        }
        Expr::Bin(BinOp::Sub, a, b) => {
            additive_terms(a, negative, out);
            additive_terms(b, !negative, out);
        }
        Expr::Neg(a) => additive_terms(a, !negative, out),
        _ => out.push((negative, e)),
    }
}

/// `e` with variable `i` renamed `map[i]`.
fn renumber(e: Expr, map: &[usize]) -> Expr {
    match e {
        Expr::Var(i) => Expr::Var(map[i]),
        Expr::Num(_) => e,
        Expr::Neg(a) => Expr::Neg(Box::new(renumber(*a, map))),
        Expr::Bin(op, a, b) => {
            Expr::Bin(op, Box::new(renumber(*a, map)), Box::new(renumber(*b, map)))
        }
        Expr::Call(f, args) => Expr::Call(f, args.into_iter().map(|a| renumber(a, map)).collect()),
    }
}

impl<const N: usize> Hamiltonian<N> for ExpressionHamiltonian<N> {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        let x = inputs(t, q, p);
        self.h.eval(&x[..1 + 2 * N])
    }

    #[inline]
    fn gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>, SVector<D, N>) {
        let x = inputs(t, q, p);
        let mut y = [D::zero(); 1 + 2 * MAX_DOF];
        self.gradient.eval_into(&x[..1 + 2 * N], &mut y);
        (
            y[0],
            SVector::from_fn(|i, _| y[1 + i]),
            SVector::from_fn(|i, _| y[1 + N + i]),
        )
    }

    #[inline]
    fn vector_field_unchecked(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        // The native code reads q and p and writes the two halves of the field in place.
        let (mut a, mut b) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        self.field.eval_phase(t, q, p, &mut a, &mut b);
        (a, b)
    }
}

/// A separable Hamiltonian `H = T(t, p) + V(t, q)` given by expressions (see
/// [`ExpressionHamiltonian::separable`]); the explicit splitting methods apply to it. The
/// drift `∂T/∂p` and the kick `∂V/∂q` are recorded once each with their function, by the
/// adjoint sweep (Griewank & Walther, ch. 3.2), and cost one pass of a register program.
#[derive(Clone, Debug)]
pub struct ExpressionSeparable<const N: usize> {
    hamiltonian: ExpressionHamiltonian<N>,
    kinetic: Expression,
    potential: Expression,
    /// `(T, ∂T/∂p)`, inputs `(t, p)`.
    kinetic_gradient: Compiled,
    /// `(V, ∂V/∂q)`, inputs `(t, q)`.
    potential_gradient: Compiled,
}

impl<const N: usize> ExpressionSeparable<N> {
    /// The Hamiltonian `T + V` as one expression.
    pub fn hamiltonian(&self) -> &ExpressionHamiltonian<N> {
        &self.hamiltonian
    }

    /// The same system with the drift `∂T/∂p`, the kick `∂V/∂q` (and the Hamiltonian's gradient)
    /// on `f64` evaluated by the interpreter instead of native code, as
    /// [`ExpressionHamiltonian::interpreted`]: for verifying the native code.
    pub fn interpreted(&self) -> Self {
        Self {
            hamiltonian: self.hamiltonian.interpreted(),
            kinetic: self.kinetic.clone(),
            potential: self.potential.clone(),
            kinetic_gradient: self.kinetic_gradient.interpreted(),
            potential_gradient: self.potential_gradient.interpreted(),
        }
    }

    /// Whether the drift and the kick on `f64` run native code (see
    /// [`ExpressionHamiltonian::is_native`]).
    pub fn is_native(&self) -> bool {
        self.kinetic_gradient.is_native() && self.potential_gradient.is_native()
    }
}

impl<const N: usize> Separable<N> for ExpressionSeparable<N> {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, t: D, p: &SVector<D, N>) -> D {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(p.as_slice());
        self.kinetic.eval(&x[..=N])
    }

    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(q.as_slice());
        self.potential.eval(&x[..=N])
    }

    #[inline]
    fn kinetic_gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        half_gradient(&self.kinetic_gradient, t, p)
    }

    #[inline]
    fn potential_gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        half_gradient(&self.potential_gradient, t, q)
    }
}

/// `(f, ∂f/∂z)` from the record of a function of `(t, z)` and its gradient.
#[inline(always)]
fn half_gradient<D: DualNum<f64> + Copy, const N: usize>(
    record: &Compiled,
    t: D,
    z: &SVector<D, N>,
) -> (D, SVector<D, N>) {
    if record::is_f64::<D>() {
        // On `f64` (`re` and `from` the identity): `z` read and `∂f/∂z` written in place by
        // the native code, `f` returned in a register.
        let z = z.map(|v| v.re());
        let mut g = SVector::<f64, N>::zeros();
        let v = record.eval_gradient(t.re(), &z, &mut g);
        return (D::from(v), g.map(D::from));
    }
    let mut x = [t; 1 + MAX_DOF];
    x[1..=N].copy_from_slice(z.as_slice());
    let mut y = [D::zero(); 1 + MAX_DOF];
    record.eval_into(&x[..=N], &mut y[..=N]);
    (y[0], SVector::from_fn(|i, _| y[1 + i]))
}

/// A Lagrangian `L(t, q, q̇)` given by an expression in named coordinates, velocities and
/// parameters; the Euler–Lagrange equations and the Legendre transform follow by AD
/// ([`Lagrangian`]).
#[derive(Clone, Debug)]
pub struct ExpressionLagrangian<const N: usize> {
    l: Expression,
}

impl<const N: usize> ExpressionLagrangian<N> {
    /// `L` from `text` in the `coordinates` (`N` names), the `velocities` (default
    /// `v_<name>` for each coordinate), the time `t` and the `parameters` with their values.
    ///
    /// # Errors
    /// As [`ExpressionHamiltonian::new`].
    pub fn new(
        text: &str,
        coordinates: &[&str],
        velocities: Option<&[&str]>,
        parameters: &[(&str, f64)],
    ) -> Result<Self> {
        Ok(Self {
            l: phase_expression::<N>(
                text,
                coordinates,
                velocities,
                ("velocities", |q| format!("v_{q}")),
                parameters,
            )?,
        })
    }

    /// The expression of `L`; its variables are `t`, the coordinates, the velocities.
    pub fn expression(&self) -> &Expression {
        &self.l
    }
}

impl<const N: usize> Lagrangian<N> for ExpressionLagrangian<N> {
    #[inline]
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> D {
        let x = inputs(t, q, qdot);
        self.l.eval(&x[..1 + 2 * N])
    }
}
