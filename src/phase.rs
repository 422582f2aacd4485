//! Phase space: points `(t, q, p)`, block matrices on `ℝ²ᴺ`, and the symplectic matrix `J`.
//!
//! Phase-space vectors are ordered `z = (q, p)`; linear maps of phase space are stored as four
//! `N × N` blocks so that everything stays statically sized:
//!
//! ```math
//! M = \begin{pmatrix} M_{qq} & M_{qp} \\ M_{pq} & M_{pp} \end{pmatrix},\qquad
//! J = \begin{pmatrix} 0 & I \\ -I & 0 \end{pmatrix} \quad\text{[Ardema eq. 15.21]}.
//! ```

use crate::error::{all_finite, finite, Error, Result};
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, OMatrix, OVector, SMatrix, SVector, U1};

/// A point of extended phase space `(t, q, p)`.
///
/// [`State::new`] rejects NaN or infinite components with the component named; the fields are
/// public, so a state built by hand is the caller's to keep finite.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct State<const N: usize> {
    /// Time.
    pub t: f64,
    /// Coordinates.
    pub q: SVector<f64, N>,
    /// Momenta.
    pub p: SVector<f64, N>,
}

impl<const N: usize> State<N> {
    /// A state; NaN or infinite components are rejected with the component named.
    pub fn new(t: f64, q: SVector<f64, N>, p: SVector<f64, N>) -> Result<Self> {
        finite("t", t)?;
        all_finite("q", q.as_slice())?;
        all_finite("p", p.as_slice())?;
        Ok(Self { t, q, p })
    }

    /// Same as [`State::new`] from arrays.
    pub fn from_arrays(t: f64, q: [f64; N], p: [f64; N]) -> Result<Self> {
        Self::new(t, SVector::from(q), SVector::from(p))
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.t.is_finite()
            && self.q.iter().all(|v| v.is_finite())
            && self.p.iter().all(|v| v.is_finite())
    }
}

/// The canonical pair `(q, p)` of coordinates and momenta, in any number type `D`.
pub type CanonicalPair<const N: usize, D = f64> = (SVector<D, N>, SVector<D, N>);

/// A linear map of phase space `ℝ²ᴺ → ℝ²ᴺ` in `N × N` blocks (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseMatrix<const N: usize> {
    /// Upper-left block `∂Q/∂q`.
    pub qq: SMatrix<f64, N, N>,
    /// Upper-right block `∂Q/∂p`.
    pub qp: SMatrix<f64, N, N>,
    /// Lower-left block `∂P/∂q`.
    pub pq: SMatrix<f64, N, N>,
    /// Lower-right block `∂P/∂p`.
    pub pp: SMatrix<f64, N, N>,
}

impl<const N: usize> PhaseMatrix<N> {
    /// The identity of `ℝ²ᴺ`.
    pub fn identity() -> Self {
        Self {
            qq: SMatrix::identity(),
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: SMatrix::identity(),
        }
    }

    /// The symplectic matrix `J = [[0, I], [−I, 0]]`.
    pub fn symplectic_j() -> Self {
        Self {
            qq: SMatrix::zeros(),
            qp: SMatrix::identity(),
            pq: -SMatrix::identity(),
            pp: SMatrix::zeros(),
        }
    }

    /// Build from a dense `2N × 2N` matrix; errors if the shape is wrong or an entry is not finite.
    pub fn from_dmatrix(m: &DMatrix<f64>) -> Result<Self> {
        if m.nrows() != 2 * N || m.ncols() != 2 * N {
            return Err(crate::Error::invalid(
                "matrix",
                format!("expected {0}×{0}, got {1}×{2}", 2 * N, m.nrows(), m.ncols()),
            ));
        }
        all_finite("matrix", m.as_slice())?;
        Ok(Self {
            qq: m.fixed_view::<N, N>(0, 0).into_owned(),
            qp: m.fixed_view::<N, N>(0, N).into_owned(),
            pq: m.fixed_view::<N, N>(N, 0).into_owned(),
            pp: m.fixed_view::<N, N>(N, N).into_owned(),
        })
    }

    /// The dense `2N × 2N` matrix.
    pub fn to_dmatrix(&self) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(2 * N, 2 * N);
        m.fixed_view_mut::<N, N>(0, 0).copy_from(&self.qq);
        m.fixed_view_mut::<N, N>(0, N).copy_from(&self.qp);
        m.fixed_view_mut::<N, N>(N, 0).copy_from(&self.pq);
        m.fixed_view_mut::<N, N>(N, N).copy_from(&self.pp);
        m
    }

    /// Transpose.
    pub fn transpose(&self) -> Self {
        Self {
            qq: self.qq.transpose(),
            qp: self.pq.transpose(),
            pq: self.qp.transpose(),
            pp: self.pp.transpose(),
        }
    }

    /// Matrix product `self · other`.
    pub fn mul(&self, o: &Self) -> Self {
        Self {
            qq: self.qq * o.qq + self.qp * o.pq,
            qp: self.qq * o.qp + self.qp * o.pp,
            pq: self.pq * o.qq + self.pp * o.pq,
            pp: self.pq * o.qp + self.pp * o.pp,
        }
    }

    /// Difference `self − other`.
    pub fn sub(&self, o: &Self) -> Self {
        Self {
            qq: self.qq - o.qq,
            qp: self.qp - o.qp,
            pq: self.pq - o.pq,
            pp: self.pp - o.pp,
        }
    }

    /// Apply to a phase-space vector `(δq, δp)`.
    pub fn apply(
        &self,
        dq: &SVector<f64, N>,
        dp: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        (self.qq * dq + self.qp * dp, self.pq * dq + self.pp * dp)
    }

    /// All entries finite (no NaN, no ±∞).
    pub fn is_finite(&self) -> bool {
        [self.qq, self.qp, self.pq, self.pp]
            .iter()
            .all(|b| b.iter().all(|x| x.is_finite()))
    }

    /// Largest absolute entry, `‖M‖_max` (NaN if any entry is NaN).
    pub fn max_abs(&self) -> f64 {
        [self.qq, self.qp, self.pq, self.pp]
            .iter()
            .flat_map(|b| b.iter().copied())
            .fold(0.0, |m: f64, x| {
                if x.is_nan() || m.is_nan() {
                    f64::NAN
                } else {
                    m.max(x.abs())
                }
            })
    }

    /// Determinant (LU of the dense matrix).
    pub fn determinant(&self) -> f64 {
        self.to_dmatrix().determinant()
    }

    /// Inverse, or `None` if singular.
    pub fn try_inverse(&self) -> Option<Self> {
        let inv = self.to_dmatrix().try_inverse()?;
        Self::from_dmatrix(&inv).ok()
    }

    /// Inverse with a conditioning check (as [`checked_inverse`], on the dense matrix).
    pub fn checked_inverse(&self, what: &str, at: impl FnOnce() -> String) -> Result<Self> {
        Self::from_dmatrix(&checked_inverse_dim(&self.to_dmatrix(), what, at)?)
    }

    /// `MᵀJM`: equals `J` exactly when `M` is symplectic; its entries are the Lagrange brackets
    /// when `M` is the Jacobian of `(q, p)` with respect to parameters [Ardema eq. 16.24].
    pub fn symplectic_form(&self) -> Self {
        self.transpose().mul(&Self::symplectic_j()).mul(self)
    }

    /// `MJMᵀ`: the Poisson brackets of the image coordinates when `M = ∂(Q, P)/∂(q, p)`
    /// [Ardema eq. 16.28].
    pub fn cosymplectic_form(&self) -> Self {
        self.mul(&Self::symplectic_j()).mul(&self.transpose())
    }

    /// Symplectic defect `‖MᵀJM − J‖_max`; zero for a canonical Jacobian [Ardema 16.4].
    pub fn symplectic_defect(&self) -> f64 {
        self.symplectic_form().sub(&Self::symplectic_j()).max_abs()
    }
}

/// Inverse of a square matrix with a conditioning check; [`Error::Singular`] (naming `what` and the
/// point `at()`) if it is singular or too ill-conditioned to trust.
///
/// The reciprocal condition is estimated in the 1-norm after scaling every column and then every
/// row to unit max-norm, `rcond = 1/(‖RAC‖₁ ‖(RAC)⁻¹‖₁)`, so that badly scaled but well-posed
/// systems (SI units, a mass matrix `diag(1, r²)` with `r ~ 10¹¹`, polar coordinates at
/// nanometre radii) are not rejected; the threshold is `64 ε`.
pub fn checked_inverse<const N: usize>(
    a: &SMatrix<f64, N, N>,
    what: &str,
    at: impl FnOnce() -> String,
) -> Result<SMatrix<f64, N, N>> {
    checked_inverse_dim(a, what, at)
}

/// [`checked_inverse`] for any nalgebra dimension.
fn checked_inverse_dim<D: Dim>(
    a: &OMatrix<f64, D, D>,
    what: &str,
    at: impl FnOnce() -> String,
) -> Result<OMatrix<f64, D, D>>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let singular = |rcond: f64, at: String| Error::Singular {
        what: what.to_string(),
        at,
        rcond,
    };
    let (r, c) = a.shape_generic();
    if !a.iter().all(|x| x.is_finite()) {
        return Err(singular(0.0, at()));
    }
    // Two-sided equilibration: columns to unit max-norm, then rows (variables and equations may
    // carry different units), so only genuine near-singularity is reported.
    let col_max = OVector::<f64, D>::from_fn_generic(c, U1, |j, _| a.column(j).amax());
    if col_max.iter().any(|&m| m == 0.0) {
        return Err(singular(0.0, at()));
    }
    let cols = OMatrix::<f64, D, D>::from_fn_generic(r, c, |i, j| a[(i, j)] / col_max[j]);
    let row_max = OVector::<f64, D>::from_fn_generic(r, U1, |i, _| cols.row(i).amax());
    if row_max.iter().any(|&m| m == 0.0) {
        return Err(singular(0.0, at()));
    }
    let scaled = OMatrix::<f64, D, D>::from_fn_generic(r, c, |i, j| cols[(i, j)] / row_max[i]);
    let norm1 = |m: &OMatrix<f64, D, D>| m.column_iter().map(|c| c.abs().sum()).fold(0.0, f64::max);
    let Some(inv_scaled) = scaled.clone().try_inverse() else {
        return Err(singular(0.0, at()));
    };
    let rcond = 1.0 / (norm1(&scaled) * norm1(&inv_scaled));
    if !(rcond.is_finite() && rcond > 64.0 * f64::EPSILON) {
        return Err(singular(if rcond.is_finite() { rcond } else { 0.0 }, at()));
    }
    // RAC = S  ⇒  A⁻¹ = C S⁻¹ R.
    Ok(OMatrix::<f64, D, D>::from_fn_generic(r, c, |i, j| {
        inv_scaled[(i, j)] / (col_max[i] * row_max[j])
    }))
}

/// Check the components of a phase vector for NaN/∞, naming them `q[i]`/`p[i]`.
pub fn check_phase<const N: usize>(t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<()> {
    finite("t", t)?;
    all_finite("q", q.as_slice())?;
    all_finite("p", p.as_slice())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn j_is_symplectic_and_squares_to_minus_identity() {
        let j = PhaseMatrix::<3>::symplectic_j();
        assert_eq!(j.symplectic_defect(), 0.0);
        let jj = j.mul(&j);
        assert_eq!(
            jj.sub(&PhaseMatrix::identity().mul(&PhaseMatrix {
                qq: -SMatrix::identity(),
                qp: SMatrix::zeros(),
                pq: SMatrix::zeros(),
                pp: -SMatrix::identity(),
            }))
            .max_abs(),
            0.0
        );
    }

    #[test]
    fn dense_round_trip_and_determinant() {
        let m = DMatrix::from_row_slice(
            4,
            4,
            &[
                2.0, 1.0, 0.0, 0.5, //
                0.0, 1.0, 3.0, 0.0, //
                1.0, 0.0, 1.0, 0.0, //
                0.0, 2.0, 0.0, 1.0,
            ],
        );
        let b = PhaseMatrix::<2>::from_dmatrix(&m).unwrap();
        assert_eq!(b.to_dmatrix(), m);
        assert!((b.determinant() - m.determinant()).abs() < 1e-14);
        assert!(PhaseMatrix::<3>::from_dmatrix(&m).is_err());
    }

    #[test]
    fn phase_point_rejects_nan() {
        assert!(State::from_arrays(0.0, [1.0], [f64::NAN]).is_err());
        assert!(State::from_arrays(f64::INFINITY, [1.0], [0.0]).is_err());
        let e = State::from_arrays(0.0, [1.0, f64::NAN], [0.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("q[1]"));
    }
}
