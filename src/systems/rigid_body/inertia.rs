//! Inertia tensors, principal axes and the kinetic energy of a rigid body [Ardema 1.4, 11.1].
//!
//! The inertia tensor about a point `A` of a body of mass elements `m_r` at `ρ_r` (from `A`) is
//!
//! ```math
//! I_A = \sum_r m_r \left( |\rho_r|^2 E - \rho_r \rho_r^{\mathsf T} \right),
//! ```
//!
//! the kinetic energy of a rotation at `ω` about `A` is `T = ½ ωᵀ I_A ω`, and the parallel-axis
//! theorem moves the tensor from the mass centre `G` to `A = G − d`:
//! `I_A = I_G + m(|d|² E − d dᵀ)` (Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §5.3).

use crate::error::{all_finite, finite, positive, Error, Result};
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// Relative tolerance under which two principal moments are treated as equal (a degenerate
/// eigenvalue): the eigenvectors of a symmetric matrix are determined only to
/// `ε‖I‖ / gap`, so below a gap of `64 ε‖I‖` they carry no information.
const DEGENERACY_TOL: f64 = 64.0 * f64::EPSILON;

/// A symmetric, positive semi-definite inertia tensor `I` (kg m²) satisfying the triangle
/// inequalities of its principal moments, `I_i ≤ I_j + I_k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InertiaTensor {
    matrix: Matrix3<f64>,
}

/// Principal moments `I₁ ≤ I₂ ≤ I₃` and a right-handed orthonormal frame of principal axes (the
/// columns of `axes`), so that `I = axes · diag(moments) · axesᵀ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalAxes {
    /// The principal moments in ascending order.
    pub moments: Vector3<f64>,
    /// The principal axes as the columns of a rotation matrix (`det = +1`).
    pub axes: Matrix3<f64>,
}

impl InertiaTensor {
    /// The tensor `matrix`, checked: finite, symmetric (to `64 ε ‖I‖`), with non-negative
    /// principal moments obeying the triangle inequalities (to the same tolerance), not zero.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite entry; [`Error::InvalidInput`] for an asymmetric
    /// matrix, the zero matrix or a matrix that is not the inertia tensor of any mass distribution.
    pub fn new(matrix: Matrix3<f64>) -> Result<Self> {
        all_finite("inertia tensor", matrix.as_slice())?;
        let scale = matrix.abs().max();
        if scale == 0.0 {
            return Err(Error::invalid(
                "inertia tensor",
                "the zero tensor (no mass)",
            ));
        }
        if !(scale * 8.0).is_finite() {
            return Err(Error::out_of_domain(
                "inertia tensor entry",
                scale,
                "|I_ij| ≤ f64::MAX / 8",
            ));
        }
        let tol = DEGENERACY_TOL * scale;
        if (matrix - matrix.transpose()).abs().max() > tol {
            return Err(Error::invalid("inertia tensor", "not symmetric"));
        }
        let sym = (matrix + matrix.transpose()) * 0.5;
        let m = SymmetricEigen::new(sym).eigenvalues;
        let (a, b, c) = (m[0], m[1], m[2]);
        if a < -tol || b < -tol || c < -tol || a > b + c + tol || b > a + c + tol || c > a + b + tol
        {
            return Err(Error::invalid(
                "inertia tensor",
                format!(
                    "principal moments {a:e}, {b:e}, {c:e} are not those of a mass distribution \
                     (each must be ≥ 0 and ≤ the sum of the other two)"
                ),
            ));
        }
        Ok(Self { matrix: sym })
    }

    /// The diagonal tensor `diag(I₁, I₂, I₃)` in principal axes.
    ///
    /// # Errors
    /// As [`InertiaTensor::new`].
    pub fn principal(moments: Vector3<f64>) -> Result<Self> {
        Self::new(Matrix3::from_diagonal(&moments))
    }

    /// The tensor about the origin of point masses `m_r > 0` at `x_r`:
    /// `I = Σ m_r (|x_r|² E − x_r x_rᵀ)` [Ardema 11.1].
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for no masses or masses all on one line through the origin (a zero
    /// tensor); [`Error::NonFinite`]/[`Error::OutOfDomain`] for bad masses or positions.
    pub fn of_point_masses(masses: &[(f64, Vector3<f64>)]) -> Result<Self> {
        let mut i = Matrix3::zeros();
        for (m, x) in masses {
            positive("point mass", *m)?;
            all_finite("point-mass position", x.as_slice())?;
            i += (Matrix3::identity() * x.norm_squared() - x * x.transpose()) * *m;
        }
        Self::new(i)
    }

    /// Uniform solid sphere of mass `m` and radius `r` about its centre: `I = (2/5) m r² E`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`]/[`Error::NonFinite`] unless `m, r > 0` and finite.
    pub fn solid_sphere(m: f64, r: f64) -> Result<Self> {
        let (m, r) = (positive("mass m", m)?, positive("radius r", r)?);
        let i = finite("moment 2mr²/5", 0.4 * m * r * r)?;
        Self::principal(Vector3::from_element(i))
    }

    /// Uniform solid cuboid of mass `m` with edges `a, b, c` along `x, y, z`, about its centre:
    /// `I = (m/12) diag(b² + c², a² + c², a² + b²)`.
    ///
    /// # Errors
    /// As [`InertiaTensor::solid_sphere`].
    pub fn cuboid(m: f64, a: f64, b: f64, c: f64) -> Result<Self> {
        let m = positive("mass m", m)?;
        let (a, b, c) = (
            positive("edge a", a)?,
            positive("edge b", b)?,
            positive("edge c", c)?,
        );
        let d = Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0);
        all_finite("cuboid moments", d.as_slice())?;
        Self::principal(d)
    }

    /// Uniform solid circular cylinder of mass `m`, radius `r` and height `h` along `z`, about its
    /// centre: `I = diag(m(3r² + h²)/12, m(3r² + h²)/12, m r²/2)`.
    ///
    /// # Errors
    /// As [`InertiaTensor::solid_sphere`].
    pub fn solid_cylinder(m: f64, r: f64, h: f64) -> Result<Self> {
        let m = positive("mass m", m)?;
        let (r, h) = (positive("radius r", r)?, positive("height h", h)?);
        let t = m * (3.0 * r * r + h * h) / 12.0;
        let d = Vector3::new(t, t, 0.5 * m * r * r);
        all_finite("cylinder moments", d.as_slice())?;
        Self::principal(d)
    }

    /// The matrix `I`.
    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.matrix
    }

    /// The parallel-axis theorem: the tensor about the point `A` from which the mass centre
    /// (about which `self` is taken) lies at `d`: `I_A = I_G + m(|d|² E − d dᵀ)`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`]/[`Error::NonFinite`] for `m ≤ 0` or a non-finite `d` or result.
    pub fn parallel_axis(&self, m: f64, d: &Vector3<f64>) -> Result<Self> {
        positive("mass m", m)?;
        all_finite("offset d", d.as_slice())?;
        let shift = (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * m;
        Self::new(self.matrix + shift)
    }

    /// Kinetic energy of rotation `T = ½ ωᵀ I ω` [Ardema 11.1].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `ω` or an overflowing `T`.
    pub fn kinetic_energy(&self, omega: &Vector3<f64>) -> Result<f64> {
        all_finite("angular velocity ω", omega.as_slice())?;
        finite(
            "kinetic energy ½ωᵀIω",
            0.5 * omega.dot(&(self.matrix * omega)),
        )
    }

    /// The angular momentum `L = I ω`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `ω` or result.
    pub fn angular_momentum(&self, omega: &Vector3<f64>) -> Result<Vector3<f64>> {
        all_finite("angular velocity ω", omega.as_slice())?;
        let l = self.matrix * omega;
        all_finite("angular momentum Iω", l.as_slice())?;
        Ok(l)
    }

    /// Principal moments (ascending) and axes by the symmetric eigen-decomposition.
    ///
    /// Degenerate moments (equal within `64 ε ‖I‖`) have no preferred axes within their
    /// eigenspace; a well-defined frame is returned instead: for three equal moments the
    /// coordinate axes; for two, the distinct axis `e` (sign: its largest component positive)
    /// completed by `u`, the coordinate axis least aligned with `e` made orthogonal to `e`, and
    /// `e × u`. Non-degenerate axes have their largest component positive, except the last,
    /// which is the cross product of the first two (a right-handed frame).
    pub fn principal_axes(&self) -> PrincipalAxes {
        let eig = SymmetricEigen::new(self.matrix);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        let moments = Vector3::from_fn(|i, _| eig.eigenvalues[order[i]]);
        let vec = |i: usize| canonical_sign(eig.eigenvectors.column(order[i]).into_owned());
        let tol = DEGENERACY_TOL * self.matrix.abs().max();
        let low = moments[1] - moments[0] <= tol;
        let high = moments[2] - moments[1] <= tol;
        let axes = match (low, high) {
            (true, true) => Matrix3::identity(),
            (true, false) => {
                // I₁ = I₂ < I₃: the distinct axis is the third.
                let e = vec(2);
                let u = orthogonal_to(&e);
                Matrix3::from_columns(&[u, e.cross(&u), e])
            }
            (false, true) => {
                let e = vec(0);
                let u = orthogonal_to(&e);
                Matrix3::from_columns(&[e, u, e.cross(&u)])
            }
            (false, false) => {
                let (a, b) = (vec(0), vec(1));
                Matrix3::from_columns(&[a, b, a.cross(&b)])
            }
        };
        PrincipalAxes { moments, axes }
    }
}

/// `v` with the sign that makes its largest-magnitude component positive.
fn canonical_sign(v: Vector3<f64>) -> Vector3<f64> {
    let i = v.iamax();
    if v[i] < 0.0 {
        -v
    } else {
        v
    }
}

/// The unit vector along the coordinate axis least aligned with the unit vector `e`, made
/// orthogonal to `e` (Gram–Schmidt).
fn orthogonal_to(e: &Vector3<f64>) -> Vector3<f64> {
    let a = Vector3::ith(e.iamin(), 1.0);
    (a - e * e.dot(&a)).normalize()
}

/// Kinetic energy of a uniform thin rod of mass `m` whose end points move with velocities `u`
/// and `v` (the velocity varies linearly along the rod): `T = (m/6)(u·u + u·v + v·v)`
/// [Ardema eq. 1.59].
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for `m ≤ 0` or non-finite velocities or result.
pub fn rod_kinetic_energy(m: f64, u: &Vector3<f64>, v: &Vector3<f64>) -> Result<f64> {
    positive("rod mass m", m)?;
    all_finite("end-point velocity u", u.as_slice())?;
    all_finite("end-point velocity v", v.as_slice())?;
    finite(
        "rod kinetic energy",
        m / 6.0 * (u.dot(u) + u.dot(v) + v.dot(v)),
    )
}

/// Koenig's decomposition: the kinetic energy of a body of mass `m` whose mass centre moves at
/// `v_G`, with kinetic energy `t_internal` of the motion relative to the mass centre:
/// `T = ½ m v_G² + T_rel` [Ardema 1.4, eq. 1.55].
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for `m ≤ 0`, `t_internal < 0` or non-finite input.
pub fn koenig_t(m: f64, v_g: &Vector3<f64>, t_internal: f64) -> Result<f64> {
    positive("mass m", m)?;
    all_finite("mass-centre velocity v_G", v_g.as_slice())?;
    crate::error::non_negative("kinetic energy relative to the mass centre", t_internal)?;
    finite(
        "kinetic energy (Koenig)",
        0.5 * m * v_g.norm_squared() + t_internal,
    )
}
