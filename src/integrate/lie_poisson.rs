//! A Lie–Poisson splitting integrator for the free rigid body.
//!
//! The energy `H = Σ Π_i²/(2I_i)` of the body angular momentum splits into three parts
//! `H_i = Π_i²/(2I_i)`, each exactly solvable under the rigid-body bracket
//! `Π̇ = Π × ∇H`: the flow of `H_i` keeps `Π_i` and rotates `Π` about the body axis `e_i` by the
//! angle `−Π_i t/I_i` (McLachlan, *Explicit Lie–Poisson integration and the Euler equations*,
//! Phys. Rev. Lett. 71 (1993) 3043; Touma & Wisdom, Astron. J. 107 (1994) 1189). The symmetric
//! (Strang) composition
//!
//! ```math
//! \Phi_h = \varphi^{1}_{h/2} \circ \varphi^{2}_{h/2} \circ \varphi^{3}_{h}
//!         \circ \varphi^{2}_{h/2} \circ \varphi^{1}_{h/2}
//! ```
//!
//! is a Poisson map of order 2; composing it with the weights of a symmetric composition table
//! ([`coefficients`](super::coefficients), [`Scheme::Composition`]) raises the order to the
//! table's. Every sub-step is a rotation, so the Casimir `|Π|²` is conserved to rounding, and the
//! energy error stays bounded (backward error analysis of Poisson integrators, Hairer, Lubich &
//! Wanner, *Geometric Numerical Integration*, 2nd ed., VII.4–5, IX.8).
//!
//! # The attitude
//! On `T*SO(3)` the flow of `H_i` also turns the attitude `R` (body to space, `Ṙ = R ω̂`) about
//! the body axis `e_i` at the constant rate `ω_i = Π_i/I_i`:
//!
//! ```math
//! \Pi \leftarrow \exp(-t\,\omega_i \hat e_i)\,\Pi ,\qquad
//! R \leftarrow R\,\exp(t\,\omega_i \hat e_i),
//! ```
//!
//! which keeps the spatial angular momentum `RΠ` exactly; [`LiePoisson::run_with_attitude`]
//! carries `R` as a unit quaternion through the same sub-steps (Touma & Wisdom 1994; Dullweber,
//! Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997) 5840), so the attitude has the order of the
//! composition too.

use super::coefficients::{Scheme, Table};
use crate::error::{all_finite, finite, Error, Result};
use crate::systems::rigid_body::FreeRigidBody;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// The Lie–Poisson splitting method for a [`FreeRigidBody`] (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LiePoisson {
    body: FreeRigidBody,
    /// Composition weights of the Strang step (`[1]` for Strang itself).
    weights: Vec<f64>,
    order: u32,
}

impl LiePoisson {
    /// The Strang splitting (order 2).
    pub fn strang(body: &FreeRigidBody) -> Self {
        Self {
            body: *body,
            weights: vec![1.0],
            order: 2,
        }
    }

    /// The Strang step composed with the weights of a symmetric composition `table` (e.g.
    /// [`coefficients::YOSHIDA3`](super::coefficients::YOSHIDA3), order 4).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a table that is not a composition of a second-order step.
    pub fn composition(body: &FreeRigidBody, table: &'static Table) -> Result<Self> {
        match table.scheme {
            Scheme::Composition { half } if !half.is_empty() => Ok(Self {
                body: *body,
                weights: table.composition_weights(),
                order: table.order,
            }),
            _ => Err(Error::invalid(
                "Lie–Poisson composition table",
                format!(
                    "{} is not a symmetric composition of a second-order step",
                    table.label()
                ),
            )),
        }
    }

    /// The order of the method.
    pub fn order(&self) -> u32 {
        self.order
    }

    /// The exact flow of `H_i = Π_i²/(2I_i)` over `t`: a rotation about `e_i` by
    /// `α = −Π_i t/I_i`, applied as the increments `Δa = b sin α' − 2a sin²(α'/2)`,
    /// `Δb = −a sin α' − 2b sin²(α'/2)` (`α' = −α`) of the other two components, added with
    /// Kahan-compensated summation (`carry`), so that the rounding of the stored state does not
    /// accumulate over long runs.
    /// With an attitude quaternion, it is turned by `exp(α e_i)` on the right (module docs).
    #[inline]
    fn rotate(
        &self,
        x: &mut Vector3<f64>,
        carry: &mut Vector3<f64>,
        attitude: Option<&mut Quaternion<f64>>,
        i: usize,
        t: f64,
    ) {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let angle = x[i] / self.body.moments()[i] * t;
        let s = angle.sin();
        let (h, ch) = (0.5 * angle).sin_cos();
        if let Some(q) = attitude {
            let mut axis = Vector3::zeros();
            axis[i] = h;
            *q *= Quaternion::from_parts(ch, axis);
        }
        let one_minus_c = 2.0 * h * h;
        let (a, b) = (x[j], x[k]);
        let da = s * b - one_minus_c * a;
        let db = -s * a - one_minus_c * b;
        for (n, d) in [(j, da), (k, db)] {
            let y = d - carry[n];
            let sum = x[n] + y;
            carry[n] = (sum - x[n]) - y;
            x[n] = sum;
        }
    }

    /// One Strang step, or the composition of Strang steps, on the compensated state.
    /// With an attitude quaternion, it is advanced by the same sub-steps and renormalised.
    #[inline]
    fn advance(
        &self,
        x: &mut Vector3<f64>,
        carry: &mut Vector3<f64>,
        mut attitude: Option<&mut Quaternion<f64>>,
        h: f64,
    ) {
        for &g in &self.weights {
            let t = g * h;
            for (i, f) in [(0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)] {
                self.rotate(x, carry, attitude.as_deref_mut(), i, f * t);
            }
        }
        if let Some(q) = attitude {
            *q /= q.norm();
        }
    }

    /// One step of size `h` from `Π` (no validation).
    #[inline]
    pub fn step_unchecked(&self, pi: &Vector3<f64>, h: f64) -> Vector3<f64> {
        let (mut x, mut carry) = (*pi, Vector3::zeros());
        self.advance(&mut x, &mut carry, None, h);
        x - carry
    }

    /// `steps ≤ 10⁹` steps of size `h` from `Π₀`, calling `observe(n, Π_n)` after each.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite `Π₀` or `h`, or a state that overflows;
    /// [`Error::OutOfDomain`] for `h = 0`; [`Error::WorkLimit`] above 10⁹ steps.
    pub fn run(
        &self,
        pi0: &Vector3<f64>,
        h: f64,
        steps: usize,
        mut observe: impl FnMut(usize, &Vector3<f64>),
    ) -> Result<Vector3<f64>> {
        self.check_run(pi0, h, steps)?;
        let (mut x, mut carry) = (*pi0, Vector3::zeros());
        for n in 1..=steps {
            self.advance(&mut x, &mut carry, None, h);
            observe(n, &x);
        }
        all_finite("final body angular momentum Π", x.as_slice())?;
        Ok(x)
    }

    /// As [`LiePoisson::run`], carrying the attitude `R` (body to space) from `R₀ = r0` through the
    /// same sub-steps (module docs); `observe(n, Π_n, R_n)` after each step.
    ///
    /// # Errors
    /// As [`LiePoisson::run`]; [`Error::NonFinite`] for a non-finite `r0`.
    pub fn run_with_attitude(
        &self,
        pi0: &Vector3<f64>,
        r0: &UnitQuaternion<f64>,
        h: f64,
        steps: usize,
        mut observe: impl FnMut(usize, &Vector3<f64>, &UnitQuaternion<f64>),
    ) -> Result<(Vector3<f64>, UnitQuaternion<f64>)> {
        all_finite("initial attitude quaternion", r0.as_vector().as_slice())?;
        self.check_run(pi0, h, steps)?;
        let (mut x, mut carry) = (*pi0, Vector3::zeros());
        let mut q = r0.into_inner();
        for n in 1..=steps {
            self.advance(&mut x, &mut carry, Some(&mut q), h);
            observe(n, &x, &UnitQuaternion::new_unchecked(q));
        }
        all_finite("final body angular momentum Π", x.as_slice())?;
        all_finite("final attitude quaternion", q.as_vector().as_slice())?;
        Ok((x, UnitQuaternion::new_unchecked(q)))
    }

    /// The checks of a run (see [`LiePoisson::run`]).
    fn check_run(&self, pi0: &Vector3<f64>, h: f64, steps: usize) -> Result<()> {
        const MAX_STEPS: usize = 1_000_000_000;
        all_finite("initial body angular momentum Π₀", pi0.as_slice())?;
        let h = finite("step size h", h)?;
        if h == 0.0 {
            return Err(Error::out_of_domain("step size h", h, "non-zero"));
        }
        if steps > MAX_STEPS {
            return Err(Error::WorkLimit {
                what: "Lie–Poisson run".into(),
                limit: MAX_STEPS,
                detail: format!("{steps} steps requested"),
                hint: "use fewer steps".into(),
            });
        }
        // The largest rotation angle per step must be finite.
        let w = pi0.component_div(self.body.moments()).amax();
        finite("rotation angle per step max |Π_i/I_i| h", w * h)?;
        Ok(())
    }
}
