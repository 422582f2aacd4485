//! Perturbation methods [Ardema ch. 18]: variation of constants in its general form and in
//! Lagrange-bracket form [Ardema 18.1], canonical variation of elements [Ardema 18.2], the equations of motion of
//! the Kepler element sets ([`crate::systems::kepler::elements`]), higher-order normal forms, and
//! the integration of element equations.
//!
//! * [`forces`]: perturbation models written once for dual numbers — `J₂`, a third body (fixed or
//!   on a circle, with the indirect term), linear drag, constant thrust (inertial or RTN), sums and
//!   user-defined models — and the Cartesian system `H = |p|²/2 − μ/|q| + U` with forces;
//!   [`kepler_variation`]: the Kepler general solution in classical and equinoctial elements for
//!   [`variation`] (Lagrange's planetary equations for any disturbing function), secular rates by
//!   averaging, Brouwer's first-order `J₂` rates, mean-element propagation.
//! * [`gauss_variational`]: Gauss's variational equations for a perturbing acceleration in the RTN
//!   frame, in modified equinoctial elements (regular at `e = 0`, `i = 0`) and in classical
//!   elements; the rotating exponential atmosphere.
//! * [`variation`]: `γ̇ = (∂φ/∂γ)⁻¹ g` for any unperturbed general solution `x = φ(γ, t)` and
//!   perturbation `g(x, t)`; the Lagrange-bracket matrix `[γ_j, γ_s]`, its time independence,
//!   and `Σ_s [γ_j, γ_s] γ̇_s = Σ_r R_r ∂F_r/∂γ_j = −∂U*/∂γ_j` (Lagrange's planetary
//!   equations).
//! * [`canonical`]: `α̇ = ∂K*/∂β`, `β̇ = −∂K*/∂α` from a complete integral of the unperturbed
//!   Hamilton–Jacobi equation (or any closed-form canonical element map) with the derivatives of
//!   `K* = K(q(α, β, t), p(α, β, t), t)` by AD through the implicit solve; averaging over a
//!   fast phase.
//! * [`ode`]: the element equations are general first-order ODEs; [`ode::Ode`] hands them to the
//!   crate's adaptive integrator ([`Dop853`](crate::integrate::Dop853) runs any
//!   [`FirstOrderSystem`](crate::integrate::FirstOrderSystem)), and [`ode`] also has classical RK4
//!   with a Richardson error estimate for fixed-step runs.
//! * [`birkhoff`]: normal forms of the user's Hamiltonian about an equilibrium in `N` degrees of
//!   freedom — the equilibrium, the real symplectic normal form of the quadratic part, Birkhoff,
//!   resonant (Gustavson) and centre-manifold normal forms by Lie transforms, the near-identity
//!   map (truncated series and exact generator flow) and convergence diagnostics.
//! * [`normal_form`]: the Lie-series normal form of a perturbed oscillator to any order (the
//!   frequency–amplitude series and the near-identity transformation), with a convergence
//!   warning near the separatrix; [`lie_deprit`]: Deprit's triangle for a Hamiltonian given in
//!   action–angle variables, `H(J, θ; ε)`, with small divisors named by their resonance; [`lindstedt`]: the Lindstedt–Poincaré expansion that
//!   cross-checks it.
//! * [`brouwer`]: Brouwer's analytic `J₂` theory closed in the eccentricity, with Lyddane's
//!   non-singular variables: second-order secular rates, first-order long- and short-period
//!   terms, mean ↔ osculating elements, the osculating state at any time.

pub mod birkhoff;
pub mod brouwer;
pub mod canonical;
pub mod forces;
pub mod gauss_variational;
pub mod kepler_variation;
pub mod lie_deprit;
pub mod lindstedt;
pub mod normal_form;
pub mod ode;
pub mod variation;
