//! Equilibria `f(z*) = 0` of a first-order system `ż = f(t, z)` and of Hamilton's equations
//! (`∇H(z*) = 0`), by Newton's method with the AD Jacobian and the simplex method of `argmin`
//! (Nelder–Mead on `|f|²`) as the fallback from a poor guess [Ardema 12.3; SPEC M34].
//!
//! A point counts as an equilibrium when `|f(z)| ≤ 10⁻¹⁰ max(1, ‖∂f/∂z‖_max)`: the residual
//! vanishes on the scale of the Jacobian (far from the origin, where the rounding of `z` itself
//! moves `f` by more, no equilibrium is resolved).

use super::linearization::linearize;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamilton_jacobi::VectorField;
use crate::hamiltonian::Hamiltonian;
use nalgebra::{DMatrix, DVector, SVector};

/// Relative residual `|f| / max(1, ‖∂f/∂z‖_max)` at which a point is an equilibrium.
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-10;

/// Newton iterations per run (from the guess, and again from the Nelder–Mead minimum).
const NEWTON_ITERATIONS: usize = 50;

/// Nelder–Mead iterations of the fallback.
const SIMPLEX_ITERATIONS: u64 = 4000;

/// An equilibrium `f(z*) = 0` of `ż = f(t, z)`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Equilibrium<const M: usize> {
    /// `z*`.
    pub z: SVector<f64, M>,
    /// `|f(z*)|`.
    pub residual: f64,
    /// Newton iterations of the final (polishing) run.
    pub iterations: usize,
    /// Whether the Nelder–Mead fallback was needed.
    pub used_fallback: bool,
}

/// An equilibrium `∇H(q*, p*) = 0` of Hamilton's equations.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PhaseEquilibrium<const N: usize> {
    /// `q*`.
    pub q: SVector<f64, N>,
    /// `p*`.
    pub p: SVector<f64, N>,
    /// `|∇H(z*)|` at the returned point.
    pub gradient_norm: f64,
    /// Newton iterations of the final (polishing) run.
    pub iterations: usize,
    /// Whether the Nelder–Mead fallback was needed.
    pub used_fallback: bool,
}

/// A zero found by [`zero`]: the point, `|F|` there, Newton iterations, fallback used.
struct Zero {
    z: DVector<f64>,
    residual: f64,
    iterations: usize,
    used_fallback: bool,
}

/// The map `F` whose zero is sought, with its Jacobian.
trait ZeroProblem {
    /// `F(z)`, an error outside the domain.
    fn value(&self, z: &DVector<f64>) -> Result<DVector<f64>>;
    /// `∂F/∂z`.
    fn jacobian(&self, z: &DVector<f64>) -> Result<DMatrix<f64>>;
}

fn residual_norm<P: ZeroProblem + ?Sized>(p: &P, z: &DVector<f64>) -> Result<(DVector<f64>, f64)> {
    all_finite("point", z.as_slice())?;
    let g = p.value(z)?;
    let n = g.norm();
    finite("|F|", n)?;
    Ok((g, n))
}

/// Whether `|F(z)| ≤ EQUILIBRIUM_TOLERANCE · max(1, ‖∂F/∂z‖_max)`.
fn resolved<P: ZeroProblem + ?Sized>(p: &P, z: &DVector<f64>, gn: f64) -> bool {
    p.jacobian(z)
        .is_ok_and(|a| gn <= EQUILIBRIUM_TOLERANCE * a.amax().max(1.0))
}

/// Newton's method on `F = 0`; `Ok(None)` when it does not converge.
fn newton<P: ZeroProblem + ?Sized>(
    p: &P,
    z0: &DVector<f64>,
    max_iter: usize,
) -> Result<Option<(DVector<f64>, f64, usize)>> {
    let mut z = z0.clone();
    let (mut g, mut gn) = residual_norm(p, &z)?;
    for it in 0..max_iter {
        let Ok(a) = p.jacobian(&z) else {
            return Ok(None);
        };
        let scale = 1.0 + z.norm();
        let Some(step) = a.lu().solve(&g) else {
            return Ok(None);
        };
        if !step.iter().all(|s| s.is_finite()) {
            return Ok(None);
        }
        let zn = &z - &step;
        let Ok((g_new, gn_new)) = residual_norm(p, &zn) else {
            return Ok(None);
        };
        z = zn;
        g = g_new;
        let small_step = step.norm() <= 1e-14 * scale;
        let converged = small_step || gn_new == 0.0 || (gn_new >= gn && gn_new < 1e-12 * scale);
        gn = gn_new;
        if converged {
            return Ok(resolved(p, &z, gn).then_some((z, gn, it + 1)));
        }
    }
    Ok(resolved(p, &z, gn).then_some((z, gn, max_iter)))
}

struct ResidualSquared<'a, P: ?Sized>(&'a P);

impl<P: ZeroProblem + ?Sized> argmin::core::CostFunction for ResidualSquared<'_, P> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, z: &DVector<f64>) -> std::result::Result<f64, argmin::core::Error> {
        Ok(match residual_norm(self.0, z) {
            Ok((_, n)) => n * n,
            Err(_) => f64::MAX,
        })
    }
}

/// The zero of `F` nearest (in the sense of the iteration) to `z0`: Newton; when Newton fails,
/// Nelder–Mead on `|F|²` from a simplex about `z0`, then Newton again to polish.
fn zero<P: ZeroProblem + ?Sized>(p: &P, z0: &DVector<f64>, what: &str) -> Result<Zero> {
    if let Some((z, residual, iterations)) = newton(p, z0, NEWTON_ITERATIONS)? {
        return Ok(Zero {
            z,
            residual,
            iterations,
            used_fallback: false,
        });
    }
    let scale = 0.1 * (1.0 + z0.amax());
    let mut simplex = vec![z0.clone()];
    for i in 0..z0.len() {
        let mut v = z0.clone();
        v[i] += scale;
        simplex.push(v);
    }
    let solver = argmin::solver::neldermead::NelderMead::new(simplex)
        .with_sd_tolerance(1e-30)
        .map_err(|e| Error::invalid("Nelder–Mead set-up", e.to_string()))?;
    let res = argmin::core::Executor::new(ResidualSquared(p), solver)
        .configure(|s| s.max_iters(SIMPLEX_ITERATIONS))
        .run()
        .map_err(|e| Error::NotConverged {
            what: format!("Nelder–Mead on |F|² for the {what} ({e})"),
            iterations: SIMPLEX_ITERATIONS as usize,
            residual: f64::NAN,
        })?;
    let best = res.state().best_param.clone().unwrap_or_else(|| z0.clone());
    match newton(p, &best, NEWTON_ITERATIONS)? {
        Some((z, residual, iterations)) => Ok(Zero {
            z,
            residual,
            iterations,
            used_fallback: true,
        }),
        None => {
            let (_, gn) = residual_norm(p, &best)?;
            Err(Error::NotConverged {
                what: format!(
                    "{what} (Newton from the guess and from the Nelder–Mead minimum of |F|²)"
                ),
                iterations: NEWTON_ITERATIONS,
                residual: gn,
            })
        }
    }
}

/// `F = f(t, ·)` of a vector field.
struct FieldZero<'a, X: ?Sized, const M: usize> {
    field: &'a X,
    t: f64,
}

impl<X: VectorField<M> + ?Sized, const M: usize> ZeroProblem for FieldZero<'_, X, M> {
    fn value(&self, z: &DVector<f64>) -> Result<DVector<f64>> {
        let z = SVector::<f64, M>::from_column_slice(z.as_slice());
        let f = self.field.field(self.t, &z);
        all_finite(format_args!("f at t = {}, z = {z:?}", self.t), f.as_slice())?;
        Ok(DVector::from_column_slice(f.as_slice()))
    }
    fn jacobian(&self, z: &DVector<f64>) -> Result<DMatrix<f64>> {
        let z = SVector::<f64, M>::from_column_slice(z.as_slice());
        let a = linearize(self.field, self.t, &z)?;
        Ok(DMatrix::from_column_slice(M, M, a.as_slice()))
    }
}

/// `F = ∇H(t, ·)` over phase space `z = (q, p)`.
struct GradientZero<'a, H: ?Sized, const N: usize> {
    h: &'a H,
    t: f64,
}

fn split<const N: usize>(z: &DVector<f64>) -> (SVector<f64, N>, SVector<f64, N>) {
    (
        SVector::from_iterator(z.iter().take(N).copied()),
        SVector::from_iterator(z.iter().skip(N).copied()),
    )
}

/// `(∇H, |∇H|)` at the phase point `z = (q, p)`, NaN/∞ rejected.
pub(crate) fn phase_gradient_dense<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    z: &DVector<f64>,
) -> Result<(DVector<f64>, f64)> {
    all_finite("phase point", z.as_slice())?;
    let (q, p) = split::<N>(z);
    let (_, hq, hp) = h.gradient(t, &q, &p);
    let g = DVector::from_iterator(2 * N, hq.iter().chain(hp.iter()).copied());
    let n = finite("|∇H|", g.norm())?;
    Ok((g, n))
}

/// The Hessian `∇²H` at the phase point `z = (q, p)`, in the order `(q, p)`.
pub(crate) fn phase_hessian_dense<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    z: &DVector<f64>,
) -> Result<DMatrix<f64>> {
    let (q, p) = split::<N>(z);
    let m = h.hessian(t, &q, &p)?;
    let mut a = DMatrix::zeros(2 * N, 2 * N);
    for i in 0..N {
        for j in 0..N {
            a[(i, j)] = m.qq[(i, j)];
            a[(i, N + j)] = m.qp[(i, j)];
            a[(N + i, j)] = m.pq[(i, j)];
            a[(N + i, N + j)] = m.pp[(i, j)];
        }
    }
    Ok(a)
}

impl<H: Hamiltonian<N> + ?Sized, const N: usize> ZeroProblem for GradientZero<'_, H, N> {
    fn value(&self, z: &DVector<f64>) -> Result<DVector<f64>> {
        Ok(phase_gradient_dense(self.h, self.t, z)?.0)
    }
    fn jacobian(&self, z: &DVector<f64>) -> Result<DMatrix<f64>> {
        phase_hessian_dense(self.h, self.t, z)
    }
}

/// The equilibrium of `ż = f(t, z)` at time `t` nearest (in the sense of the iteration) to the
/// guess `z₀`: Newton's method on `f = 0` with the AD Jacobian; when Newton fails from the guess,
/// Nelder–Mead (`argmin`) on `|f|²` from the guess, then Newton again to polish. For a steady
/// motion of a system with cyclic coordinates, `f` is the field of the remaining variables
/// ([`Reduced`](super::Reduced)).
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite guess or time; [`Error::NotConverged`] when neither
/// route reaches `|f| ≤ 10⁻¹⁰ max(1, ‖∂f/∂z‖_max)`.
pub fn equilibrium<X: VectorField<M> + ?Sized, const M: usize>(
    field: &X,
    t: f64,
    z: &SVector<f64, M>,
) -> Result<Equilibrium<M>> {
    finite("t", t)?;
    all_finite("z", z.as_slice())?;
    let found = zero(
        &FieldZero { field, t },
        &DVector::from_column_slice(z.as_slice()),
        "equilibrium f(z) = 0",
    )?;
    Ok(Equilibrium {
        z: SVector::from_column_slice(found.z.as_slice()),
        residual: found.residual,
        iterations: found.iterations,
        used_fallback: found.used_fallback,
    })
}

/// The equilibrium `∇H = 0` of `H` at time `t` nearest (in the sense of the iteration) to the
/// guess `(q, p)`: Newton's method with the AD Hessian; when Newton fails from the guess,
/// Nelder–Mead (`argmin`) on `|∇H|²` from the guess, then Newton again to polish.
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite guess or time; [`Error::NotConverged`] when neither
/// route reaches `|∇H| ≤ 10⁻¹⁰ max(1, ‖∇²H‖_max)`.
pub fn hamiltonian_equilibrium<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<PhaseEquilibrium<N>> {
    crate::phase::check_phase(t, q, p)?;
    let z0 = DVector::from_iterator(2 * N, q.iter().chain(p.iter()).copied());
    let found = zero(&GradientZero { h, t }, &z0, "equilibrium ∇H = 0")?;
    let (q, p) = split::<N>(&found.z);
    Ok(PhaseEquilibrium {
        q,
        p,
        gradient_norm: found.residual,
        iterations: found.iterations,
        used_fallback: found.used_fallback,
    })
}
