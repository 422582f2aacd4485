//! The spectrum of a linearised Hamiltonian system: the "box" symmetry, Krein signatures and the
//! spectral classification into elliptic, hyperbolic and complex-saddle blocks (SPEC M35, T29;
//! X10).
//!
//! * Perturbations of a reference point `z* = (q*, p*)` obey `η̇ = A η` with the Hamiltonian
//!   matrix `A = J ∇²H(z*)`, `J = [[0, I], [−I, 0]]` [Ardema 15.4, eqs. 15.22–15.24]
//!   ([`hamiltonian_linearization`]). `A` is real and `JA` symmetric, so its eigenvalues come in
//!   sets `{λ, −λ, λ̄, −λ̄}`, the corners of a box symmetric about both axes. A computed spectrum
//!   is symmetric only up to rounding, and an asymmetry (from a finite-difference Hessian, say)
//!   falsely suggests attraction or instability (SPEC X10): [`check_spectrum_symmetry`] measures
//!   it against a stated tolerance.
//! * **Krein signature.** For an eigenvalue `iω`, `ω > 0`, with eigenvector `v`, `∇²H v = −iω J v`,
//!   so the energy of the real invariant plane `span(Re v, Im v)` is
//!   `vᴴ ∇²H v = −iω vᴴ J v = 2ω K(v, v)` with the Hermitian Krein form
//!   `K(v, w) = Ω(v̄, w)/(2i)`, `Ω(u, w) = uᵀ J w`. Its sign is the Krein signature of the pair
//!   `±iω` (for a repeated eigenvalue, the inertia of `K` on the eigenspace). Two elliptic pairs of
//!   the same signature pass through each other when they meet; pairs of opposite signature can
//!   leave the imaginary axis as a complex quartet — a **Krein collision** (the Hamiltonian–Hopf
//!   bifurcation) — as at the Lagrange point L4 at Routh's mass ratio
//!   `μ_R = (1 − √(23/27))/2` (Meyer, Hall & Offin, *Introduction to Hamiltonian Dynamical
//!   Systems*, 2nd ed., §4.7 and §5.2; M. G. Krein, *Amer. Math. Soc. Transl.* (2) 1, 1955;
//!   Mackay, "Stability of equilibria of Hamiltonian systems", in *Nonlinear Phenomena and Chaos*,
//!   1986).
//! * **Classification** ([`hamiltonian_spectrum()`]): the eigenvalues of `A` in clusters (a
//!   repeated eigenvalue, semisimple or a Jordan block), each set `{λ, −λ, λ̄, −λ̄}` reported as one
//!   [`SpectralBlock`] — elliptic `±iω` with its Krein inertia, hyperbolic `±λ`, complex saddle
//!   `±a ± ib`, or zero. The equilibrium is linearly stable when every block is elliptic and
//!   semisimple, unstable when a block is hyperbolic or a saddle, undecided otherwise
//!   ([`Stability`]); it is **strongly stable** (every nearby linear Hamiltonian system is stable,
//!   Krein–Gelfand–Lidskii) when besides every repeated frequency has a definite Krein form.
//!   The normal forms of [`perturbation::birkhoff`](crate::perturbation::birkhoff) build their
//!   blocks from the same clusters and Krein form.

use super::equilibrium::phase_hessian_dense;
use super::spectrum::{Stability, C64};
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use nalgebra::{ComplexField, DMatrix, DVector, SVector};

/// Relative distance `|μ − μ'| / max(1, ‖A‖_max)` within which eigenvalues of `A = J∇²H` form one
/// cluster (a repeated eigenvalue, semisimple or a Jordan block). Rounding moves a simple
/// eigenvalue by `O(ε‖A‖)`, a double defective one by `O(√ε‖A‖) ≈ 10⁻⁸‖A‖`.
pub const EIGENVALUE_CLUSTER: f64 = 1e-6;

/// Relative size (to the largest) below which an eigenvalue of the Krein form on an eigenspace
/// counts as zero: the form is degenerate there (a Jordan block on the imaginary axis).
pub const KREIN_DEGENERACY: f64 = 1e-12;

/// `Ω(u, v) = uᵀ J v = Σ_i u_i v_{n+i} − u_{n+i} v_i` on `ℝ²ⁿ` or `ℂ²ⁿ` (`n` degrees of freedom).
pub(crate) fn symplectic_form<T: ComplexField>(u: &DVector<T>, v: &DVector<T>, n: usize) -> T {
    let mut s = T::zero();
    for i in 0..n {
        s += u[i].clone() * v[n + i].clone() - u[n + i].clone() * v[i].clone();
    }
    s
}

/// The Hermitian Krein form `K_ab = Ω(v̄_a, v_b)/(2i)` on the span of the vectors `v`
/// (Hermitian part, to remove rounding).
pub(crate) fn krein_form(v: &[DVector<C64>], n: usize) -> DMatrix<C64> {
    let m = v.len();
    let k = DMatrix::<C64>::from_fn(m, m, |a, b| {
        symplectic_form(&v[a].conjugate(), &v[b], n) / C64::new(0.0, 2.0)
    });
    (&k + k.adjoint()) * C64::new(0.5, 0.0)
}

/// The eigenvalues `eig` grouped into clusters of mutual distance (to the running mean) at most
/// `tol`: `(mean, multiplicity)` in order of first appearance.
pub(crate) fn eigenvalue_clusters(eig: &[C64], tol: f64) -> Vec<(C64, usize)> {
    let mut clusters: Vec<(C64, usize)> = Vec::new();
    for &e in eig {
        if let Some(c) = clusters
            .iter_mut()
            .find(|(c, k)| (*c / *k as f64 - e).norm() <= tol)
        {
            c.0 += e;
            c.1 += 1;
        } else {
            clusters.push((e, 1));
        }
    }
    clusters
        .into_iter()
        .map(|(s, k)| (s / k as f64, k))
        .collect()
}

/// `J S` for a `2n × 2n` matrix `S`: rows `(S_{n+i,·}, −S_{i,·})`.
pub(crate) fn j_times(s: &DMatrix<f64>) -> DMatrix<f64> {
    let dim = s.nrows();
    let n = dim / 2;
    let mut m = DMatrix::<f64>::zeros(dim, s.ncols());
    for i in 0..n {
        for j in 0..s.ncols() {
            m[(i, j)] = s[(n + i, j)];
            m[(n + i, j)] = -s[(i, j)];
        }
    }
    m
}

/// The Hamiltonian matrix `A = J ∇²H(t, q, p)` of the variational equations about `(q, p)`
/// [Ardema eq. 15.22] (SPEC M35: `hamiltonian_linearization`), the Hessian by AD. Non-conservative
/// forces are not part of it (the linearisation of a forced system is
/// [`Hamiltonian::tangent_matrix`]).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in `t`, `q`, `p` or the Hessian.
pub fn hamiltonian_linearization<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<DMatrix<f64>> {
    crate::phase::check_phase(t, q, p)?;
    let z = DVector::from_iterator(2 * N, q.iter().chain(p.iter()).copied());
    let s = phase_hessian_dense(h, t, &z)?;
    Ok(j_times(&s))
}

/// The outcome of [`check_spectrum_symmetry`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BoxSymmetry {
    /// The eigenvalues of `A`.
    pub eigenvalues: Vec<C64>,
    /// `max` over the reflections `λ ↦ −λ, λ̄, −λ̄` of the distance between the reflected and the
    /// computed spectrum (eigenvalues matched one to one), divided by `max(1, ‖A‖_F)`.
    pub defect: f64,
}

fn check_square(a: &DMatrix<f64>, what: &str) -> Result<()> {
    if a.nrows() != a.ncols() || a.nrows() == 0 || !a.nrows().is_multiple_of(2) {
        return Err(Error::invalid(
            what,
            format!(
                "{}×{}: need a square matrix of even size",
                a.nrows(),
                a.ncols()
            ),
        ));
    }
    all_finite(what, a.as_slice())
}

/// Eigenvalues of `a` computed from `a / ‖a‖_max` (no overflow for any finite `a`), rescaled.
fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<C64>> {
    let scale = a.amax();
    if scale == 0.0 {
        return Ok(vec![C64::new(0.0, 0.0); a.nrows()]);
    }
    let e: Vec<C64> = (a / scale)
        .complex_eigenvalues()
        .iter()
        .map(|l| l * scale)
        .collect();
    for l in &e {
        finite("eigenvalue (real part)", l.re)?;
        finite("eigenvalue (imaginary part)", l.im)?;
    }
    Ok(e)
}

/// Largest distance of a greedy one-to-one matching of `a` to `b`.
fn matching_distance(a: &[C64], b: &[C64]) -> f64 {
    let mut used = vec![false; b.len()];
    let mut worst = 0.0f64;
    for x in a {
        let best = (0..b.len())
            .filter(|&j| !used[j])
            .min_by(|&i, &j| (b[i] - x).norm().total_cmp(&(b[j] - x).norm()));
        if let Some(j) = best {
            used[j] = true;
            worst = worst.max((b[j] - x).norm());
        }
    }
    worst
}

/// The distance of the spectrum `e` of `a` from its reflections `−λ`, `λ̄`, `−λ̄`, relative to
/// `max(1, ‖A‖_F)`.
fn box_defect(a: &DMatrix<f64>, e: &[C64]) -> f64 {
    let scale = a.norm().max(1.0);
    [|l: C64| -l, |l: C64| l.conj(), |l: C64| -l.conj()]
        .iter()
        .map(|f| matching_distance(&e.iter().map(|&l| f(l)).collect::<Vec<_>>(), e) / scale)
        .fold(0.0, f64::max)
}

/// The box symmetry of the spectrum of `a` (SPEC M35): the distance between the spectrum and its
/// reflections `λ ↦ −λ`, `λ ↦ λ̄`, `λ ↦ −λ̄`, relative to `max(1, ‖A‖_F)`, checked against `tol`.
/// For `A = J∇²H` from an AD Hessian the defect is of order `ε` for simple eigenvalues and `√ε`
/// at a collision (a Jordan block); an asymmetry far above that means `A` is not Hamiltonian
/// (SPEC X10).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ entries or tolerance; [`Error::InvalidInput`] for a matrix that
/// is not square of even size, `tol ≤ 0`, or a defect above `tol` (the message gives it).
pub fn check_spectrum_symmetry(a: &DMatrix<f64>, tol: f64) -> Result<BoxSymmetry> {
    check_square(a, "Hamiltonian matrix A")?;
    let tol = finite("symmetry tolerance", tol)?;
    if tol <= 0.0 {
        return Err(Error::invalid(
            "symmetry tolerance",
            format!("{tol}: need > 0"),
        ));
    }
    let e = eigenvalues(a)?;
    let defect = box_defect(a, &e);
    if defect.is_nan() || defect > tol {
        return Err(Error::invalid(
            "spectrum of A",
            format!(
                "not symmetric under λ ↦ −λ, λ̄: defect {defect:e} (relative to max(1, ‖A‖_F)) \
                 above the tolerance {tol:e} — A is not a Hamiltonian matrix to that accuracy"
            ),
        ));
    }
    Ok(BoxSymmetry {
        eigenvalues: e,
        defect,
    })
}

/// One set `{λ, −λ, λ̄, −λ̄}` of the spectrum of `A = J∇²H`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SpectralBlock {
    /// `±iω`, `ω > 0`, each of multiplicity `multiplicity`; the Krein form on the eigenspace of
    /// `iω` has `positive` positive and `negative` negative eigenvalues (`positive + negative <
    /// multiplicity` for a Jordan block, a degenerate form).
    Elliptic {
        /// `ω > 0`.
        frequency: f64,
        /// Algebraic multiplicity of `iω`.
        multiplicity: usize,
        /// Positive eigenvalues of the Krein form (pairs of positive signature).
        positive: usize,
        /// Negative eigenvalues of the Krein form.
        negative: usize,
    },
    /// `±λ`, `λ > 0`.
    Hyperbolic {
        /// `λ`.
        rate: f64,
        /// Algebraic multiplicity of `λ`.
        multiplicity: usize,
    },
    /// `±a ± ib`, `a, b > 0`.
    ComplexSaddle {
        /// `a`.
        re: f64,
        /// `b`.
        im: f64,
        /// Algebraic multiplicity of `a + ib`.
        multiplicity: usize,
    },
    /// The eigenvalue zero.
    Zero {
        /// Algebraic multiplicity.
        multiplicity: usize,
    },
}

impl SpectralBlock {
    /// Whether the block is elliptic and semisimple with a definite Krein form (all pairs of one
    /// signature).
    pub fn is_definite(&self) -> bool {
        matches!(*self, SpectralBlock::Elliptic { multiplicity, positive, negative, .. }
            if positive == multiplicity || negative == multiplicity)
    }
}

/// The classified spectrum of `A = J∇²H`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HamiltonianSpectrum {
    /// The eigenvalues of `A`.
    pub eigenvalues: Vec<C64>,
    /// One block per set `{λ, −λ, λ̄, −λ̄}`: hyperbolic, complex saddles, elliptic (by increasing
    /// frequency), zero.
    pub blocks: Vec<SpectralBlock>,
    /// The box-symmetry defect ([`BoxSymmetry::defect`]).
    pub symmetry_defect: f64,
    /// The cluster and axis tolerance `EIGENVALUE_CLUSTER · max(1, ‖A‖_max)`.
    pub tolerance: f64,
    /// Linear stability: stable when all blocks are elliptic and semisimple, unstable with a
    /// hyperbolic or saddle block, undecided otherwise (zero eigenvalue, Jordan block on the axis).
    pub stability: Stability,
}

impl HamiltonianSpectrum {
    /// Whether the spectrum is stable and stays so under every small Hamiltonian perturbation:
    /// every elliptic block definite (Krein–Gelfand–Lidskii).
    pub fn strongly_stable(&self) -> bool {
        self.stability == Stability::Stable && self.blocks.iter().all(SpectralBlock::is_definite)
    }
    /// The number of eigenvalues with `Re λ > tolerance`.
    pub fn unstable_count(&self) -> usize {
        self.eigenvalues
            .iter()
            .filter(|l| l.re > self.tolerance)
            .count()
    }
    /// The numbers of eigenvalues in elliptic, hyperbolic, complex-saddle and zero blocks: the
    /// spectral type.
    pub fn spectral_type(&self) -> [usize; 4] {
        let mut out = [0; 4];
        for b in &self.blocks {
            match *b {
                SpectralBlock::Elliptic { multiplicity, .. } => out[0] += 2 * multiplicity,
                SpectralBlock::Hyperbolic { multiplicity, .. } => out[1] += 2 * multiplicity,
                SpectralBlock::ComplexSaddle { multiplicity, .. } => out[2] += 4 * multiplicity,
                SpectralBlock::Zero { multiplicity } => out[3] += multiplicity,
            }
        }
        out
    }
    /// The elliptic pairs as `(ω, κ)` with the Krein signature `κ = ±1` (one entry per
    /// non-degenerate direction of the Krein form), by increasing `ω`.
    pub fn krein_signatures(&self) -> Vec<(f64, i8)> {
        let mut out = Vec::new();
        for b in &self.blocks {
            if let SpectralBlock::Elliptic {
                frequency,
                positive,
                negative,
                ..
            } = *b
            {
                out.extend(std::iter::repeat_n((frequency, 1i8), positive));
                out.extend(std::iter::repeat_n((frequency, -1i8), negative));
            }
        }
        out
    }
}

/// The null space of a complex square matrix: right singular vectors of singular values at most
/// `tol`.
pub(crate) fn complex_null_space(a: DMatrix<C64>, tol: f64) -> Vec<DVector<C64>> {
    let n = a.ncols();
    let svd = a.svd(false, true);
    let Some(vt) = svd.v_t else {
        return Vec::new();
    };
    (0..n)
        .filter(|&k| svd.singular_values[k] <= tol)
        .map(|k| vt.row(k).adjoint().into_owned())
        .collect()
}

/// The classified spectrum of the linearisation about an equilibrium with Hessian
/// `hessian = ∇²H` (`2N × 2N`, blocks `[[H_qq, H_qp], [H_pq, H_pp]]`): the eigenvalues of
/// `A = J∇²H`, the box-symmetry defect, the blocks with the Krein inertia of each elliptic one
/// (see the [module docs](self)).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ entries; [`Error::InvalidInput`] for a matrix that is not
/// square of even size or not symmetric (relative `10⁻¹⁰`).
pub fn hamiltonian_spectrum(hessian: &DMatrix<f64>) -> Result<HamiltonianSpectrum> {
    check_square(hessian, "Hessian ∇²H")?;
    let dim = hessian.nrows();
    let n = dim / 2;
    let scale = hessian.amax();
    if (hessian - hessian.transpose()).amax() > 1e-10 * scale {
        return Err(Error::invalid("Hessian ∇²H", "not symmetric"));
    }
    let a = j_times(hessian);
    let eig = eigenvalues(&a)?;
    let anorm = a.amax();
    let tol = EIGENVALUE_CLUSTER * anorm.max(1.0);
    let defect = box_defect(&a, &eig);
    let clusters = eigenvalue_clusters(&eig, tol);
    // Work on A/‖A‖_max for the eigenspaces.
    let unit = if anorm > 0.0 { anorm } else { 1.0 };
    let ac: DMatrix<C64> = (&a / unit).map(|x| C64::new(x, 0.0));
    let mut hyper = Vec::new();
    let mut saddle = Vec::new();
    let mut ellip = Vec::new();
    let mut zero = 0usize;
    for &(mu, mult) in &clusters {
        let (on_re, on_im) = (mu.im.abs() <= tol, mu.re.abs() <= tol);
        if on_re && on_im {
            zero += mult;
        } else if on_im && mu.im > 0.0 {
            let w = mu.im / unit;
            let shifted = &ac - DMatrix::<C64>::identity(dim, dim) * C64::new(0.0, w);
            let v = complex_null_space(shifted, 1e-7);
            let (mut positive, mut negative) = (0, 0);
            if !v.is_empty() {
                let k = krein_form(&v, n).symmetric_eigen();
                let kmax = k.eigenvalues.amax();
                for &kk in k.eigenvalues.iter() {
                    if kk > KREIN_DEGENERACY * kmax {
                        positive += 1;
                    } else if kk < -KREIN_DEGENERACY * kmax {
                        negative += 1;
                    }
                }
            }
            ellip.push(SpectralBlock::Elliptic {
                frequency: mu.im,
                multiplicity: mult,
                positive: positive.min(mult),
                negative: negative.min(mult - positive.min(mult)),
            });
        } else if on_re && mu.re > 0.0 {
            hyper.push(SpectralBlock::Hyperbolic {
                rate: mu.re,
                multiplicity: mult,
            });
        } else if mu.re > 0.0 && mu.im > 0.0 {
            saddle.push(SpectralBlock::ComplexSaddle {
                re: mu.re,
                im: mu.im,
                multiplicity: mult,
            });
        }
    }
    let key = |b: &SpectralBlock| match *b {
        SpectralBlock::Elliptic { frequency, .. } => frequency,
        SpectralBlock::Hyperbolic { rate, .. } => rate,
        SpectralBlock::ComplexSaddle { im, .. } => im,
        SpectralBlock::Zero { .. } => 0.0,
    };
    for v in [&mut hyper, &mut saddle, &mut ellip] {
        v.sort_by(|a, b| key(a).total_cmp(&key(b)));
    }
    let unstable = !hyper.is_empty() || !saddle.is_empty();
    let degenerate = zero > 0
        || ellip.iter().any(|b| {
            matches!(*b, SpectralBlock::Elliptic { multiplicity, positive, negative, .. }
                if positive + negative < multiplicity)
        });
    let stability = if unstable {
        Stability::Unstable
    } else if degenerate {
        Stability::Undecided
    } else {
        Stability::Stable
    };
    let mut blocks = hyper;
    blocks.append(&mut saddle);
    blocks.append(&mut ellip);
    if zero > 0 {
        blocks.push(SpectralBlock::Zero { multiplicity: zero });
    }
    Ok(HamiltonianSpectrum {
        eigenvalues: eig,
        blocks,
        symmetry_defect: defect,
        tolerance: tol,
        stability,
    })
}

/// The discriminant `Π_{i<j} (s_i − s_j)²` of the characteristic polynomial in `s = λ²` of a
/// `2N × 2N` Hamiltonian matrix `A` (whose eigenvalues `±√s_i` come in pairs), scaled to
/// `A/‖A‖_max`: the Hankel determinant `det[p_{i+j}]_{i,j<N}` of the power sums
/// `p_m = Σ s_i^m = tr(A^{2m})/2`. Real and a polynomial in the entries of `A`, it is computed to
/// `O(ε)` even where eigenvalues collide (where the eigenvalues themselves are only good to
/// `O(√ε)`); its sign is `(−1)^c` with `c` the number of complex-conjugate pairs among the `s_i`,
/// so it changes sign where two elliptic (or two hyperbolic) pairs collide and leave their axis.
pub(crate) fn collision_discriminant(a: &DMatrix<f64>) -> f64 {
    let n = a.nrows() / 2;
    let scale = a.amax();
    if n == 0 || scale == 0.0 || !scale.is_finite() {
        return if n <= 1 { 1.0 } else { 0.0 };
    }
    let b = {
        let u = a / scale;
        &u * &u
    };
    let mut p = vec![n as f64];
    let mut power = DMatrix::<f64>::identity(2 * n, 2 * n);
    for _ in 1..(2 * n - 1) {
        power = &power * &b;
        p.push(0.5 * power.trace());
    }
    DMatrix::from_fn(n, n, |i, j| p[i + j]).determinant()
}
