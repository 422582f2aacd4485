//! Eigenvalues of a linearisation and the stability they decide (SPEC M33–M34), with the zero
//! eigenvalues that come from a family of steady motions identified and reported, not
//! classified.
//!
//! * The roots of `det(A − λI) = 0` decide [Ardema 12.3]: some `Re λ > 0` — unstable; all
//!   `Re λ < 0` — asymptotically stable; `Re λ ≤ 0` with the roots on the imaginary axis distinct
//!   and non-zero — stable (not asymptotically) in the linear approximation; otherwise (a zero
//!   root not explained by a family, or a repeated root on the axis) — undecided by the linear
//!   terms.
//! * Steady motions of non-holonomic systems come in families (the rolling disk at every speed
//!   and every steady turn, the sleigh at every speed [Hamel art. 244]). Along such a family
//!   `f(z*(c)) = 0`, so its tangent `∂z*/∂c` lies in the kernel of `A`: these zero eigenvalues
//!   carry no stability information. A kernel direction `n` belongs to the family when the
//!   equations `f(z) = 0`, `nᵀ(z − z*) = ±h` have solutions (found by Gauss–Newton); the
//!   remaining eigenvalues are those of `A` on the quotient `ℝᴹ / T` by the family's tangent space
//!   `T`, the matrix `Wᵀ A W` for an orthonormal basis `W` of `T^⊥` ([`Spectrum::transverse`]).
//!   With all of them in the left half plane the steady motion attracts the transverse
//!   variables while it is only stable, not asymptotically stable, in the full state (the sleigh,
//!   SPEC X5).
//! * Hamilton's "box" symmetry of the spectrum (SPEC M35) is not assumed: the classification
//!   holds for any first-order system, non-holonomic systems included, which are not
//!   Hamiltonian.

use super::equilibrium::EQUILIBRIUM_TOLERANCE;
use super::linearization::linearize;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamilton_jacobi::VectorField;
use nalgebra::{Complex, DMatrix, DVector, SVector, SymmetricEigen};

/// Complex `f64`.
pub type C64 = Complex<f64>;

/// Relative size `σ / max(1, σ_max)` of a singular value of `A` below which its direction is in
/// the kernel. `A` comes from AD, exact up to rounding; a singular value that vanishes in exact
/// arithmetic comes out of order `ε σ_max ≈ 10⁻¹⁶ σ_max`, so six orders of magnitude are left.
pub const KERNEL_TOLERANCE: f64 = 1e-10;

/// Relative distance `|Re λ| / max(1, ‖A‖_F)` from the imaginary axis within which an eigenvalue
/// counts as on the axis: `8 √ε`. A simple eigenvalue moves by `O(ε ‖A‖)` under rounding, a
/// double defective one (two eigenvalues meeting on the axis, as at a stability threshold) by
/// `O(√ε ‖A‖)`.
pub const AXIS_TOLERANCE: f64 = 8.0 * 1.4901161193847656e-8;

/// Stability of an equilibrium (steady motion) decided by its linearisation (SPEC M33–M34).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Stability {
    /// All eigenvalues (no family) have `Re λ < 0`.
    AsymptoticallyStable,
    /// No eigenvalue with `Re λ > 0`; those on the imaginary axis distinct and non-zero, besides
    /// the zeros of a family of steady motions.
    Stable,
    /// Some eigenvalue with `Re λ > 0`.
    Unstable,
    /// No eigenvalue with `Re λ > 0`, but a zero eigenvalue not explained by a family or a
    /// repeated eigenvalue on the axis: the non-linear terms decide.
    Undecided,
}

/// The spectrum of a linearisation `A` with the family of steady motions factored out.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Spectrum {
    /// The eigenvalues of `A`, by decreasing real part.
    pub eigenvalues: Vec<C64>,
    /// Orthonormal basis (columns) of the tangent space `T` of the family of steady motions
    /// through the point: as many zero eigenvalues of `A` come from the family.
    pub family: DMatrix<f64>,
    /// `Wᵀ A W`, the map induced by `A` on `ℝᴹ / T` (`W` an orthonormal basis of `T^⊥`).
    pub transverse_matrix: DMatrix<f64>,
    /// The eigenvalues of [`Spectrum::transverse_matrix`] (those of `A` without the family's
    /// zeros), by decreasing real part.
    pub transverse: Vec<C64>,
    /// The stability decided by the transverse eigenvalues.
    pub stability: Stability,
    /// Whether there are transverse eigenvalues and every one has `Re λ < −tolerance`:
    /// perturbations decay onto the family (attracting in the transverse variables).
    pub attracting: bool,
    /// The distance from the imaginary axis within which an eigenvalue counts as on it
    /// ([`AXIS_TOLERANCE`] `· max(1, ‖A‖_F)`).
    pub tolerance: f64,
}

impl Spectrum {
    /// The dimension of the family of steady motions (the number of zero eigenvalues reported,
    /// not classified).
    pub fn family_dimension(&self) -> usize {
        self.family.ncols()
    }

    /// The number of transverse eigenvalues with `Re λ > tolerance`.
    pub fn unstable_count(&self) -> usize {
        self.transverse
            .iter()
            .filter(|l| l.re > self.tolerance)
            .count()
    }
}

fn by_real_part(mut v: Vec<C64>) -> Vec<C64> {
    v.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
    v
}

/// The spectrum of `A` with the family tangent space spanned by the columns of `family`
/// (possibly none), classified as in the [module docs](self).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ entries; [`Error::InvalidInput`] for a non-square `A`, a
/// family basis of the wrong height or of dependent columns, or a family direction `n` with
/// `|A n| > KERNEL_TOLERANCE · max(1, ‖A‖_F) |n|` (not a zero eigenvector).
pub fn spectrum(a: &DMatrix<f64>, family: &DMatrix<f64>) -> Result<Spectrum> {
    let m = a.nrows();
    if a.ncols() != m || family.nrows() != m || family.ncols() > m {
        return Err(Error::invalid(
            "linearisation",
            format!(
                "A is {}×{}, the family basis {}×{}: need A square and the basis M × k, k ≤ M",
                a.nrows(),
                a.ncols(),
                family.nrows(),
                family.ncols()
            ),
        ));
    }
    all_finite("A", a.as_slice())?;
    all_finite("family basis", family.as_slice())?;
    let scale = finite("‖A‖_F", a.norm())?.max(1.0);
    // Orthonormal family basis.
    let k = family.ncols();
    let t = if k == 0 {
        DMatrix::zeros(m, 0)
    } else {
        let svd = family.clone().svd(true, false);
        let u = svd
            .u
            .ok_or_else(|| Error::invalid("family basis", "SVD failed"))?;
        if svd.singular_values.min() <= KERNEL_TOLERANCE * svd.singular_values.max() {
            return Err(Error::invalid(
                "family basis",
                "its columns are dependent".to_string(),
            ));
        }
        u.columns(0, k).into_owned()
    };
    for j in 0..k {
        let r = (a * t.column(j)).norm();
        if r > KERNEL_TOLERANCE * scale {
            return Err(Error::invalid(
                "family basis",
                format!("direction {j} is not in the kernel of A: |A n| = {r:e}"),
            ));
        }
    }
    // Orthonormal basis W of the complement: eigenvectors of I − T Tᵀ with eigenvalue one.
    let proj = DMatrix::<f64>::identity(m, m) - &t * t.transpose();
    let eig = SymmetricEigen::new(proj);
    let cols: Vec<DVector<f64>> = (0..m)
        .filter(|&i| eig.eigenvalues[i] > 0.5)
        .map(|i| eig.eigenvectors.column(i).into_owned())
        .collect();
    let w = if cols.is_empty() {
        DMatrix::zeros(m, 0)
    } else {
        DMatrix::from_columns(&cols)
    };
    let r = w.transpose() * a * &w;
    let eigenvalues_of = |x: &DMatrix<f64>| -> Vec<C64> {
        if x.nrows() == 0 {
            Vec::new()
        } else {
            by_real_part(x.complex_eigenvalues().iter().copied().collect())
        }
    };
    let eigenvalues = eigenvalues_of(a);
    let transverse = eigenvalues_of(&r);
    for l in eigenvalues.iter().chain(transverse.iter()) {
        finite("eigenvalue (real part)", l.re)?;
        finite("eigenvalue (imaginary part)", l.im)?;
    }
    let tol = AXIS_TOLERANCE * scale;
    let unstable = transverse.iter().any(|l| l.re > tol);
    let attracting = !transverse.is_empty() && transverse.iter().all(|l| l.re < -tol);
    let on_axis: Vec<C64> = transverse
        .iter()
        .copied()
        .filter(|l| l.re.abs() <= tol)
        .collect();
    let zero = on_axis.iter().any(|l| l.norm() <= tol);
    let repeated = on_axis
        .iter()
        .enumerate()
        .any(|(i, x)| on_axis[..i].iter().any(|y| (x - y).norm() <= tol));
    let stability = if unstable {
        Stability::Unstable
    } else if attracting && k == 0 {
        Stability::AsymptoticallyStable
    } else if zero || repeated {
        Stability::Undecided
    } else {
        Stability::Stable
    };
    Ok(Spectrum {
        eigenvalues,
        family: t,
        transverse_matrix: r,
        transverse,
        stability,
        attracting,
        tolerance: tol,
    })
}

/// Gauss–Newton iterations on the equations of a neighbouring steady motion.
const FAMILY_ITERATIONS: usize = 30;

/// Relative offset `h / max(1, |z*|)` of the neighbouring steady motions sought along a kernel
/// direction.
pub const FAMILY_STEP: f64 = 1e-2;

/// Whether the equations `f(z) = 0`, `nᵀ(z − z*) = s` have a solution near `z* + s n` (Gauss–Newton
/// with least-squares steps, the Jacobian `[A(z); nᵀ]` being rank-deficient along the family).
fn continues<X: VectorField<M> + ?Sized, const M: usize>(
    field: &X,
    t: f64,
    z0: &SVector<f64, M>,
    n: &SVector<f64, M>,
    s: f64,
) -> bool {
    let mut z = z0 + n * s;
    for _ in 0..FAMILY_ITERATIONS {
        let Ok(a) = linearize(field, t, &z) else {
            return false;
        };
        let f = field.field(t, &z);
        let mut g = DVector::zeros(M + 1);
        let mut j = DMatrix::zeros(M + 1, M);
        for r in 0..M {
            g[r] = f[r];
            for c in 0..M {
                j[(r, c)] = a[(r, c)];
            }
        }
        g[M] = n.dot(&(z - z0)) - s;
        for c in 0..M {
            j[(M, c)] = n[c];
        }
        let scale = a.amax().max(1.0);
        if f.norm() <= EQUILIBRIUM_TOLERANCE * scale && g[M].abs() <= 1e-12 * s.abs() {
            return true;
        }
        let Ok(step) = j.svd(true, true).solve(&g, KERNEL_TOLERANCE * scale) else {
            return false;
        };
        if !step.iter().all(|x| x.is_finite()) {
            return false;
        }
        z -= SVector::<f64, M>::from_column_slice(step.as_slice());
    }
    false
}

/// The spectrum of the steady motion (equilibrium) `z*` of `ż = f(t, z)`: the linearisation by
/// AD ([`linearize`]), the family of steady motions through `z*` found from the kernel of `A`
/// (see the [module docs](self)), and the classification of the remaining eigenvalues.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in `t`, `z*` or the field; [`Error::InvalidInput`] when `z*` is
/// not an equilibrium (`|f| > 10⁻¹⁰ max(1, ‖A‖_max)`, see
/// [`equilibrium`](super::equilibrium())).
pub fn steady_motion_spectrum<X: VectorField<M> + ?Sized, const M: usize>(
    field: &X,
    t: f64,
    z: &SVector<f64, M>,
) -> Result<Spectrum> {
    let a = linearize(field, t, z)?;
    let f = field.field(t, z);
    let residual = finite("|f|", f.norm())?;
    if residual > EQUILIBRIUM_TOLERANCE * a.amax().max(1.0) {
        return Err(Error::invalid(
            "steady motion",
            format!("|f| = {residual:e} at z = {z:?}: not an equilibrium (use `equilibrium`)"),
        ));
    }
    let ad = DMatrix::from_column_slice(M, M, a.as_slice());
    let svd = ad.clone().svd(false, true);
    let v_t = svd
        .v_t
        .ok_or_else(|| Error::invalid("linearisation", "SVD failed"))?;
    let top = svd.singular_values.max().max(1.0);
    let h = FAMILY_STEP * z.norm().max(1.0);
    let mut tangents: Vec<DVector<f64>> = Vec::new();
    for (i, sv) in svd.singular_values.iter().enumerate() {
        if *sv > KERNEL_TOLERANCE * top {
            continue;
        }
        let n = SVector::<f64, M>::from_iterator(v_t.row(i).iter().copied());
        if continues(field, t, z, &n, h) && continues(field, t, z, &n, -h) {
            tangents.push(DVector::from_column_slice(n.as_slice()));
        }
    }
    let family = if tangents.is_empty() {
        DMatrix::zeros(M, 0)
    } else {
        DMatrix::from_columns(&tangents)
    };
    spectrum(&ad, &family)
}
