//! Normalised Taylor coefficients of every operation of a record: the jets of the Taylor method.

use super::{Op, Record};
use crate::error::{Error, Result};
use crate::series::recurrences as rec;

/// The largest order of [`Jets`].
pub const MAX_ORDER: usize = 200;

/// The normalised Taylor coefficients `v_{i,0} … v_{i,K}` (`v_i(t₀ + τ) = Σ_k v_{i,k} τ^k`) of
/// every operation `i` of a [`Record`], in one buffer allocated once: the coefficients of an
/// operation are computed from those of its operands by the recurrences of
/// [`series::recurrences`](crate::series::recurrences), `O(k)` each.
///
/// For an ordinary differential equation `ẋ = f(t, x)` recorded with inputs `(t, x₁ … x_n)` and
/// outputs `(f₁ … f_n)`, [`Jets::ode`] builds the Taylor series of the solution through
/// `(t₀, x₀)` order by order (Jorba & Zou 2005, §2):
///
/// $$ x_{k+1} = \frac{f_k(x_0, \dots, x_k)}{k + 1},\qquad k = 0, \dots, K - 1, $$
///
/// with the time input `t(t₀ + τ) = t₀ + τ`. The cost is `O(K²)` per operation and no
/// allocation.
#[derive(Clone, Debug)]
pub struct Jets {
    order: usize,
    stride: usize,
    c: Vec<f64>,
}

impl Jets {
    /// Storage for the jets of `record` up to order `order` (`1 ≤ order ≤` [`MAX_ORDER`]).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for an order outside `1 … MAX_ORDER`.
    pub fn new(record: &Record, order: usize) -> Result<Self> {
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(Error::out_of_domain(
                "Taylor order",
                order as f64,
                format!("1 … {MAX_ORDER}"),
            ));
        }
        let stride = order + 1;
        let mut c = vec![0.0; stride * record.len()];
        for (i, op) in record.ops.iter().enumerate() {
            if let Op::Const(v) = *op {
                c[i * stride] = v;
            }
        }
        Ok(Self { order, stride, c })
    }

    /// The largest order the storage holds.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The coefficients `v_{i,0} … v_{i,K}` of operation `i`.
    ///
    /// # Panics
    /// If `i` is not an operation of the record the jets were made for.
    pub fn coefficients(&self, i: usize) -> &[f64] {
        &self.c[i * self.stride..(i + 1) * self.stride]
    }

    /// The Taylor series to order `order ≤` [`order`](Self::order) of the solution of the
    /// differential equation `record` describes (inputs `(t, x)`, outputs `f(t, x)`, as many
    /// outputs as state variables) through `x(t₀) = x₀`; read them with
    /// [`coefficients`](Self::coefficients)`(1 + j)` for `x_j`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the record is not of that shape or `x₀` has the wrong length;
    /// [`Error::OutOfDomain`] when `order` is 0 or exceeds the storage; [`Error::NonFinite`] for
    /// a non-finite `t₀` or `x₀`, and for a non-finite coefficient of the solution (a
    /// singularity of the equation at `(t₀, x₀)`, e.g. a collision).
    pub fn ode(&mut self, record: &Record, t0: f64, x0: &[f64], order: usize) -> Result<()> {
        let n = record.inputs.saturating_sub(1);
        if record.inputs < 2
            || record.outputs.len() != n
            || x0.len() != n
            || self.c.len() != self.stride * record.len()
        {
            return Err(Error::invalid(
                "Taylor series of a differential equation",
                format!(
                    "the record has {} inputs and {} outputs and the state {} entries; \
                     expected (t, x₁ … x_n) in, (f₁ … f_n) out",
                    record.inputs,
                    record.outputs.len(),
                    x0.len()
                ),
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
        self.c[0] = t0;
        self.c[1] = 1.0;
        for (j, &x) in x0.iter().enumerate() {
            self.c[(1 + j) * s] = x;
        }
        for k in 0..order {
            for (i, op) in record.ops.iter().enumerate().skip(record.inputs) {
                if let Op::Const(_) = op {
                    continue;
                }
                let v = coefficient(*op, &self.c, s, i, k);
                self.c[i * s + k] = v;
            }
            let scale = 1.0 / (k + 1) as f64;
            for (j, &o) in record.outputs.iter().enumerate() {
                self.c[(1 + j) * s + k + 1] = self.c[o * s + k] * scale;
            }
        }
        for j in 1..=n {
            if let Some(k) = self.c[j * s..j * s + order + 1]
                .iter()
                .position(|c| !c.is_finite())
            {
                return Err(Error::NonFinite {
                    what: format!(
                        "Taylor coefficient {k} of state variable {} at t₀ = {t0:e}, x₀ = \
                         {x0:?} (a singularity of the equation)",
                        j - 1
                    ),
                    value: self.c[j * s + k],
                });
            }
        }
        Ok(())
    }
}

/// The `k`-th normalised coefficient of operation `i` (`op`) from the lower coefficients.
#[inline]
fn coefficient(op: Op, c: &[f64], s: usize, i: usize, k: usize) -> f64 {
    let jet = |j: usize| &c[j * s..j * s + k + 1];
    let w = jet(i);
    match op {
        Op::Input(_) | Op::Const(_) => w[k],
        Op::Add(a, b) => c[a * s + k] + c[b * s + k],
        Op::Sub(a, b) => c[a * s + k] - c[b * s + k],
        Op::Neg(a) => -c[a * s + k],
        Op::Shift(a, v) => {
            if k == 0 {
                c[a * s] + v
            } else {
                c[a * s + k]
            }
        }
        Op::Scale(a, v) => v * c[a * s + k],
        Op::Mul(a, b) => rec::product(jet(a), jet(b), k),
        Op::Div(a, b) => {
            if k == 0 {
                c[a * s] / c[b * s]
            } else {
                rec::quotient(c[a * s + k], jet(b), w, k)
            }
        }
        Op::Recip(a) => {
            if k == 0 {
                c[a * s].recip()
            } else {
                rec::quotient(0.0, jet(a), w, k)
            }
        }
        Op::Sqrt(a) => {
            if k == 0 {
                c[a * s].sqrt()
            } else {
                rec::sqrt(jet(a), w, k)
            }
        }
        Op::Exp(a) => {
            if k == 0 {
                c[a * s].exp()
            } else {
                rec::integral_w_du(jet(a), w, k)
            }
        }
        Op::Ln(a) => {
            if k == 0 {
                c[a * s].ln()
            } else {
                rec::ln(jet(a), w, k)
            }
        }
        Op::Powf(a, p) => {
            if k == 0 {
                c[a * s].powf(p)
            } else {
                rec::power(jet(a), p, w, k)
            }
        }
        Op::Sin { arg, cos } => {
            if k == 0 {
                c[arg * s].sin()
            } else {
                rec::integral_w_du(jet(arg), &c[cos * s..cos * s + k], k)
            }
        }
        Op::Cos { arg, sin } => {
            if k == 0 {
                c[arg * s].cos()
            } else {
                -rec::integral_w_du(jet(arg), &c[sin * s..sin * s + k], k)
            }
        }
        Op::Atan2 { y, x, r } => {
            if k == 0 {
                c[y * s].atan2(c[x * s])
            } else {
                rec::atan2(jet(y), jet(x), jet(r), w, k)
            }
        }
    }
}
