//! Periodic orbits: the monodromy matrix from the variational equations, its Floquet
//! multipliers, and the trivial multipliers of an autonomous Hamiltonian system identified
//! [Ardema 12.3; Meyer, Hall & Offin, *Introduction to Hamiltonian Dynamical Systems*, 2nd ed.,
//! §4.5 and §8.2] (SPEC M34).
//!
//! * Along a motion `z(t)` of `ż = J∇H + (0, Q^nc)` the perturbations obey the variational
//!   equations `Φ̇ = A(t) Φ`, `Φ(t₀) = I`, `A = ∂f/∂z` on the motion, integrated with the state
//!   by [`variational_tangent_map`] (each column `Φ e_j` the directional derivative of the one
//!   vector field along it, by AD), so that [`Dop853`] controls their error together with that of
//!   the state.
//! * For a periodic orbit of period `T` the **monodromy matrix** is `M = Φ(t₀ + T)`, its
//!   eigenvalues the **Floquet multipliers**. For an autonomous Hamiltonian the flow direction
//!   `X = J∇H(z₀)` is invariant, `M X = X`, and energy is conserved, `∇H(z₀)ᵀ M = ∇H(z₀)ᵀ`: two
//!   multipliers equal one. In the basis `(X, η, W)` with `∇H · η = 1` and `W` a basis of the
//!   invariant complement `{w : ∇H · w = 0, Ω(η, w) = 0}`, the monodromy is block triangular with
//!   the **trivial block** `[[1, −T′(E)], [0, 1]]` in `(X, η)` — the shear `−T′(E)` is the change
//!   of the period with the energy along the family of orbits — and the reduced monodromy on `W`,
//!   whose eigenvalues are the non-trivial multipliers (orbital stability in the linear
//!   approximation when they lie on the unit circle and are semisimple).
//!
//! Stable Rust cannot write the augmented dimension `N(1 + 2N)` from a generic `N`, so it is a
//! second const parameter `K`, checked at run time (as for
//! [`ParameterSensitivity`](crate::integrate::ParameterSensitivity), which integrates them).

use super::hamiltonian_spectrum::j_times;
use super::spectrum::C64;
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::integrate::{variational_tangent_map, Dop853, Problem};
use nalgebra::{DMatrix, DVector, Matrix2, SVector};

/// The monodromy matrix of a periodic orbit and its Floquet multipliers.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Monodromy {
    /// `M = Φ(t₀ + T)`, `2N × 2N` in the order `(q, p)`.
    pub matrix: DMatrix<f64>,
    /// The Floquet multipliers (eigenvalues of `M`).
    pub multipliers: Vec<C64>,
    /// `|z(t₀ + T) − z₀| / max(1, |z₀|)`: how well the orbit closes.
    pub closure_defect: f64,
    /// `|M X − X| / |X|` for the flow direction `X = J∇H(z₀)`.
    pub flow_defect: f64,
    /// The basis `(X, η, W)` (columns) of the [module docs](self).
    pub basis: DMatrix<f64>,
    /// The monodromy in that basis on `(X, η)`: `[[1, −T′(E)], [0, 1]]` up to the integration
    /// error.
    pub trivial_block: Matrix2<f64>,
    /// The shear `trivial_block[(0, 1)] = −T′(E)`.
    pub shear: f64,
    /// The reduced monodromy on `W` (`2N − 2` square).
    pub reduced: DMatrix<f64>,
    /// The non-trivial multipliers (eigenvalues of [`Monodromy::reduced`]).
    pub nontrivial: Vec<C64>,
}

/// The monodromy matrix of the periodic orbit of the autonomous Hamiltonian `h` through
/// `(q₀, p₀)` at `t₀` with period `T`: the variational equations (`K = N(1 + 2N)`)
/// integrated over one period by `method`, the Floquet multipliers, and the trivial block and the
/// non-trivial multipliers in the basis `(X, η, W)` (see the [module docs](self)). The period is
/// the caller's (from a closed form, or from a section crossing); [`Monodromy::closure_defect`]
/// reports how well the orbit closes with it.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ input or a non-finite motion; [`Error::OutOfDomain`] for
/// `T ≤ 0`; [`Error::InvalidInput`] for `K ≠ N(1 + 2N)` or a point where `∇H = 0` (an
/// equilibrium, no orbit); the errors of the integration.
pub fn monodromy<H: Hamiltonian<N>, const N: usize, const K: usize>(
    h: &H,
    t0: f64,
    q0: &SVector<f64, N>,
    p0: &SVector<f64, N>,
    period: f64,
    method: &Dop853,
) -> Result<Monodromy> {
    crate::phase::check_phase(t0, q0, p0)?;
    let period = finite("period T", period)?;
    if period <= 0.0 {
        return Err(Error::out_of_domain("period T", period, "(0, ∞)"));
    }
    let problem = Problem::new(h, t0, *q0, *p0, t0 + period)?;
    let run = variational_tangent_map::<H, N, K>(&problem, method)?;
    let (q1, p1, m) = (run.last.q, run.last.p, run.jacobian.to_dmatrix());
    crate::error::all_finite("monodromy matrix", m.as_slice())?;
    let dim = 2 * N;
    let z0 = DVector::from_iterator(dim, q0.iter().chain(p0.iter()).copied());
    let z1 = DVector::from_iterator(dim, q1.iter().chain(p1.iter()).copied());
    let closure_defect = (&z1 - &z0).norm() / z0.norm().max(1.0);
    let (_, hq, hp) = h.gradient(t0, q0, p0);
    let grad = DVector::from_iterator(dim, hq.iter().chain(hp.iter()).copied());
    let g2 = grad.norm_squared();
    if g2 <= 0.0 || !g2.is_finite() {
        return Err(Error::invalid(
            "periodic orbit",
            format!("∇H = {grad:?} at the initial point: an equilibrium, not a periodic orbit"),
        ));
    }
    // X = J∇H, η = ∇H/|∇H|².
    let x = j_times(&DMatrix::from_column_slice(dim, 1, grad.as_slice()))
        .column(0)
        .into_owned();
    let eta = &grad / g2;
    // W: the null space of the rows ∇Hᵀ and ηᵀJ (Ω(η, w) = ηᵀ J w).
    let jt_eta = -j_times(&DMatrix::from_column_slice(dim, 1, eta.as_slice()));
    let mut c = DMatrix::<f64>::zeros(dim, dim);
    c.set_row(0, &grad.transpose());
    c.set_row(1, &jt_eta.column(0).transpose());
    let svd = c.svd(false, true);
    let vt = svd
        .v_t
        .ok_or_else(|| Error::invalid("basis of the complement", "SVD failed"))?;
    let mut rows: Vec<usize> = (0..dim).collect();
    rows.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
    let mut basis = DMatrix::<f64>::zeros(dim, dim);
    basis.set_column(0, &x);
    basis.set_column(1, &eta);
    for (k, &r) in rows.iter().take(dim - 2).enumerate() {
        basis.set_column(2 + k, &vt.row(r).transpose());
    }
    let inv = basis
        .clone()
        .try_inverse()
        .ok_or_else(|| Error::invalid("basis (X, η, W)", "singular: X and η are dependent"))?;
    let mb = &inv * &m * &basis;
    let trivial_block = Matrix2::new(mb[(0, 0)], mb[(0, 1)], mb[(1, 0)], mb[(1, 1)]);
    let reduced = mb.view((2, 2), (dim - 2, dim - 2)).into_owned();
    let eig = |a: &DMatrix<f64>| -> Vec<C64> {
        if a.nrows() == 0 {
            Vec::new()
        } else {
            a.complex_eigenvalues().iter().copied().collect()
        }
    };
    let flow_defect = (&m * &x - &x).norm() / x.norm();
    Ok(Monodromy {
        multipliers: eig(&m),
        nontrivial: eig(&reduced),
        matrix: m,
        closure_defect,
        flow_defect,
        basis,
        shear: trivial_block[(0, 1)],
        trivial_block,
        reduced,
    })
}
