//! The scene of the free rigid body spun about its intermediate axis (SPEC T30; Ardema
//! Prob. 12/4; Marsden & Ratiu, *Introduction to Mechanics and Symmetry*, 2nd ed., §15.10).
//!
//! A steady spin `Ω` about principal axis 2 of a body with `I₁ < I₂ < I₃` is unstable: a small
//! perturbation grows as `e^{λt}` with
//!
//! ```math
//! \lambda = \Omega\,\sqrt{\frac{(I_2 - I_1)(I_3 - I_2)}{I_1 I_3}}
//! ```
//!
//! ([`intermediate_axis_growth_rate`]; `0.577350269…` for `I = (1, 2, 3)`, `Ω = 1`), and the
//! body angular momentum `Π` then runs along the separatrix of the momentum sphere and back: the
//! body flips over and over. The scene measures `λ` three ways (the eigenvalue of the AD
//! linearisation of Euler's equations, the growth of `|Π₁|` along the Euler–Poinsot exact flow
//! and along the Lie–Poisson integrator), draws the flips, and the errors of the Lie–Poisson
//! splitting ([`LiePoisson`]) in `Π` and in the attitude against the exact flow
//! ([`EulerPoinsot`]).

use super::case::Table;
use crate::error::{finite, fmt_num, positive, Error, Result};
use crate::integrate::coefficients::YOSHIDA3;
use crate::integrate::LiePoisson;
use crate::plot::{Figure, Style};
use crate::systems::rigid_body::{
    euler_jacobian, intermediate_axis_growth_rate, EulerPoinsot, FreeRigidBody, InertiaTensor,
};
use nalgebra::{UnitQuaternion, Vector3};

/// The `what` of the figure of `Π(t)` (the flips): `figures/<scene>-momentum`.
pub const MOMENTUM_FIGURE: &str = "momentum";
/// The `what` of the figure of the linear growth of the perturbation.
pub const GROWTH_FIGURE: &str = "growth";
/// The `what` of the figure of the Lie–Poisson error against the exact flow.
pub const ERROR_FIGURE: &str = "lie-poisson-error";

/// Points drawn per curve.
const SAMPLES: usize = 1000;
/// The perturbation of the linear-growth measurement, relative to `Ω`: small enough that the
/// perturbation stays below `10⁻³ Ω` (relative corrections `≤ 10⁻⁶`) up to `t_b`.
const LINEAR_PERTURBATION: f64 = 1e-9;
/// The times `t_a < t_b` of the measured rate `ln(Π₁(t_b)/Π₁(t_a))/(t_b − t_a)`, in units of
/// `1/λ`: where `cosh λt = e^{λt}(1 + e^{−2λt})/2` grows as `e^{λt}/2` to `10⁻⁷`.
const RATE_TIMES: (f64, f64) = (8.0, 14.0);
/// Lie–Poisson steps per unit `1/λ` in the growth measurement (a whole number).
const STEPS_PER_E_FOLD: f64 = 200.0;

/// The body angular momentum `Π = I ω` of the spin `Ω` about axis 2 perturbed by `ε` about
/// axis 1: `ω = (ε, Ω, 0)`.
fn perturbed_spin(moments: &Vector3<f64>, spin: f64, eps: f64) -> Vector3<f64> {
    Vector3::new(eps, spin, 0.0).component_mul(moments)
}

/// The table and figures of the scene `free-rigid-body`: the body of principal `moments`
/// spun at `spin` about axis 2, perturbed by `perturbation · Ω` about axis 1, over `[0, time]`;
/// the Lie–Poisson splitting (Strang, order 2, and its Yoshida composition, order 4) with
/// `steps` steps against the Euler–Poinsot flow.
///
/// # Errors
/// [`Error::InvalidInput`] when axis 2 is not the intermediate one (no growth); the domain
/// errors of [`FreeRigidBody::new`], [`EulerPoinsot`] and [`LiePoisson::run`] (non-finite,
/// non-positive moments, spin, time, perturbation outside `(0, 0.5]`, `steps` outside
/// `[1, 10⁷]`, a spin so small or large that `|Π|²` or the energy underflows or overflows).
pub fn intermediate_axis(
    moments: Vector3<f64>,
    spin: f64,
    perturbation: f64,
    time: f64,
    steps: usize,
) -> Result<(Table, Vec<(String, Figure)>)> {
    let body = FreeRigidBody::new(moments)?;
    let spin = positive("spin Ω", spin)?;
    let eps = positive("perturbation ε/Ω", perturbation)?;
    if eps > 0.5 {
        return Err(Error::out_of_domain("perturbation ε/Ω", eps, "(0, 0.5]"));
    }
    let time = positive("time span", time)?;
    if !(1..=10_000_000).contains(&steps) {
        return Err(Error::out_of_domain(
            "Lie–Poisson steps",
            steps as f64,
            "[1, 10⁷]",
        ));
    }
    let lambda = intermediate_axis_growth_rate(&moments, spin)?;
    if lambda == 0.0 {
        return Err(Error::invalid(
            "principal moments",
            format!(
                "I₂ = {} is not strictly between I₁ = {} and I₃ = {}: the spin about axis 2 is \
                 stable",
                fmt_num(moments[1]),
                fmt_num(moments[0]),
                fmt_num(moments[2])
            ),
        ));
    }
    let strang = LiePoisson::strang(&body);
    let yoshida = LiePoisson::composition(&body, &YOSHIDA3)?;

    // λ from the AD linearisation of Euler's equations at the steady spin.
    let inertia = InertiaTensor::principal(moments)?;
    let jac = euler_jacobian(&inertia, &Vector3::zeros(), &Vector3::new(0.0, spin, 0.0))?;
    let lambda_ad = jac
        .complex_eigenvalues()
        .iter()
        .map(|z| z.re)
        .fold(f64::NEG_INFINITY, f64::max);

    // λ from the growth of |Π₁| of a tiny perturbation, exact and integrated.
    let pi_lin = perturbed_spin(&moments, spin, LINEAR_PERTURBATION * spin);
    let linear = EulerPoinsot::new(&body, &pi_lin)?;
    let (ta, tb) = (RATE_TIMES.0 / lambda, RATE_TIMES.1 / lambda);
    let rate = |a: f64, b: f64| (b.abs() / a.abs()).ln() / (tb - ta);
    let lambda_exact = finite(
        "growth rate of the exact flow",
        rate(linear.momentum_at(ta)?[0], linear.momentum_at(tb)?[0]),
    )?;
    let n_lin = (RATE_TIMES.1 * STEPS_PER_E_FOLD) as usize;
    let h_lin = tb / n_lin as f64;
    let n_a = (RATE_TIMES.0 * STEPS_PER_E_FOLD) as usize;
    let mut at_a = Vector3::zeros();
    let at_b = yoshida.run(&pi_lin, h_lin, n_lin, |n, pi| {
        if n == n_a {
            at_a = *pi;
        }
    })?;
    let lambda_lp = finite("growth rate of the Lie–Poisson run", rate(at_a[0], at_b[0]))?;
    let growth_t1 = 1.2 * tb;
    let growth: Vec<(f64, f64)> = (0..=SAMPLES)
        .map(|k| {
            let t = growth_t1 * k as f64 / SAMPLES as f64;
            Ok((t, linear.momentum_at(t)?[0] / pi_lin[0]))
        })
        .collect::<Result<_>>()?;
    let cosh: Vec<(f64, f64)> = growth
        .iter()
        .map(|&(t, _)| (t, (lambda * t).cosh()))
        .collect();

    // The flips, and the splitting's error against the exact flow along them.
    let pi0 = perturbed_spin(&moments, spin, eps * spin);
    let exact = EulerPoinsot::new(&body, &pi0)?;
    let flip_period = exact.period()?;
    let every = steps.div_ceil(SAMPLES).max(1);
    let h = time / steps as f64;
    let (c0, e0) = (pi0.norm_squared(), body.energy_generic(&pi0));
    if !(c0.is_normal() && e0.is_normal() && pi_lin[0].is_normal()) {
        return Err(Error::out_of_domain(
            "spin Ω",
            spin,
            "a spin whose |Π|², energy and perturbation are normal floating-point numbers",
        ));
    }
    let mut errors = Vec::new();
    let r0 = UnitQuaternion::identity();
    for (name, method) in [("Strang, order 2", &strang), ("Yoshida, order 4", &yoshida)] {
        let mut times = Vec::new();
        let mut states = Vec::new();
        let mut drift: (f64, f64) = (0.0, 0.0);
        method.run_with_attitude(&pi0, &r0, h, steps, |n, pi, r| {
            drift.0 = drift.0.max((pi.norm_squared() - c0).abs() / c0);
            drift.1 = drift.1.max((body.energy_generic(pi) - e0).abs() / e0);
            if n % every == 0 || n == steps {
                times.push(n as f64 * h);
                states.push((*pi, *r));
            }
        })?;
        let curve = times
            .iter()
            .zip(&states)
            .map(|(&t, (pi, _))| Ok((t, (pi - exact.momentum_at(t)?).norm() / pi0.norm())))
            .collect::<Result<Vec<_>>>()?;
        let attitude = times
            .iter()
            .zip(&states)
            .map(|(&t, (_, r))| Ok((t, r.angle_to(&exact.attitude_at(&r0, t)?))))
            .collect::<Result<Vec<_>>>()?;
        errors.push((name, curve, drift, attitude));
    }
    let mut momentum = Figure::new(
        format!(
            "Free rigid body I = ({}, {}, {}): spin Ω = {} about the intermediate axis",
            fmt_num(moments[0]),
            fmt_num(moments[1]),
            fmt_num(moments[2]),
            fmt_num(spin)
        ),
        "t",
        "Π_i / |Π|",
    );
    let samples: Vec<(f64, Vector3<f64>)> = (0..=SAMPLES)
        .map(|k| {
            let t = time * k as f64 / SAMPLES as f64;
            Ok((t, exact.momentum_at(t)? / pi0.norm()))
        })
        .collect::<Result<_>>()?;
    for (i, label) in ["Π₁", "Π₂", "Π₃"].iter().enumerate() {
        momentum = momentum.curve(
            *label,
            samples.iter().map(|(t, pi)| (*t, pi[i])),
            Style::Line,
        );
    }
    momentum = momentum.caption(format!(
        "The body angular momentum Π(t) of the free rigid body with principal moments I = ({}, \
         {}, {}), started at ω = (ε, Ω, 0) with Ω = {}, ε = {}Ω, by the Euler–Poinsot exact flow \
         in Jacobi elliptic functions. The spin about the intermediate axis is unstable: Π leaves \
         it at the rate λ = Ω√((I₂−I₁)(I₃−I₂)/(I₁I₃)) = {} and runs along the separatrix of the \
         momentum sphere to −Π₂ and back; the flip repeats with the period 4K(k)/λ_EP = {} of the \
         flow.",
        fmt_num(moments[0]),
        fmt_num(moments[1]),
        fmt_num(moments[2]),
        fmt_num(spin),
        fmt_num(eps),
        fmt_num(lambda),
        fmt_num(flip_period)
    ));
    let growth_fig = Figure::new(
        "Intermediate axis: growth of a small perturbation",
        "t",
        "Π₁(t)/Π₁(0)",
    )
    .log_y()
    .curve("Euler–Poinsot exact flow", growth, Style::Line)
    .curve(
        format!("linear theory cosh λt, λ = {lambda:.9}"),
        cosh,
        Style::Line,
    )
    .caption(format!(
        "The perturbation Π₁ of the spin Ω = {} about the intermediate axis, started at \
         ω = ({}Ω, Ω, 0), along the Euler–Poinsot flow, against the solution cosh λt of the \
         linearised Euler equations. The rate ln(Π₁(t_b)/Π₁(t_a))/(t_b − t_a) with t_a = {}, t_b = {} gives λ = {} (exact \
         flow) and {} (Lie–Poisson, order 4), the AD linearisation {}, the closed form {}.",
        fmt_num(spin),
        fmt_num(LINEAR_PERTURBATION),
        fmt_num(ta),
        fmt_num(tb),
        fmt_num(lambda_exact),
        fmt_num(lambda_lp),
        fmt_num(lambda_ad),
        fmt_num(lambda)
    ));
    let mut error_fig = Figure::new(
        "Lie–Poisson splitting against the Euler–Poinsot flow",
        "t",
        "|Π − Π_exact| / |Π₀|;  attitude error (rad)",
    )
    .log_y();
    for (name, curve, _, attitude) in &errors {
        error_fig = error_fig
            .curve(
                format!("{name}, h = {}: Π", fmt_num(h)),
                curve.clone(),
                Style::Line,
            )
            .curve(format!("{name}: attitude"), attitude.clone(), Style::Line);
    }
    error_fig = error_fig.caption(format!(
        "The error of the Lie–Poisson splitting of H = Σ Π_i²/(2I_i) into exactly solvable \
         rotations (Strang, and its Yoshida composition) with {steps} steps over t ∈ [0, {}], \
         against the Euler–Poinsot exact flow, along the flipping motion of the momentum figure: \
         the relative error of Π (lines) and the angle of R_exact⁻¹R between the attitude \
         carried through the same sub-rotations and the exact attitude (legend: attitude; precession by \
         the elliptic integral of the third kind). The error grows with the phase error of the flips; the Casimir |Π|² is kept to \
         rounding (max relative drift {} and {}) and the energy error stays bounded ({} and {}).",
        fmt_num(time),
        fmt_num(errors[0].2 .0),
        fmt_num(errors[1].2 .0),
        fmt_num(errors[0].2 .1),
        fmt_num(errors[1].2 .1)
    ));
    let rel = |x: f64| fmt_num((x - lambda) / lambda);
    let mut rows = vec![
        vec![
            "growth rate λ, closed form Ω√((I₂−I₁)(I₃−I₂)/(I₁I₃))".to_string(),
            fmt_num(lambda),
            "0".to_string(),
        ],
        vec![
            "λ, eigenvalue of the AD linearisation of Euler's equations".to_string(),
            fmt_num(lambda_ad),
            rel(lambda_ad),
        ],
        vec![
            "λ, growth of |Π₁| over [8/λ, 14/λ], Euler–Poinsot exact flow".to_string(),
            fmt_num(lambda_exact),
            rel(lambda_exact),
        ],
        vec![
            format!(
                "λ, growth of |Π₁| over [8/λ, 14/λ], Lie–Poisson order 4 (h = {})",
                fmt_num(h_lin)
            ),
            fmt_num(lambda_lp),
            rel(lambda_lp),
        ],
        vec![
            "flip period 4K(k)/λ_EP".to_string(),
            fmt_num(flip_period),
            String::new(),
        ],
    ];
    for (name, curve, drift, _) in &errors {
        let end = curve.last().map_or(f64::NAN, |p| p.1);
        rows.push(vec![
            format!("{name}: |ΔΠ|/|Π₀| at t = {}", fmt_num(time)),
            fmt_num(end),
            String::new(),
        ]);

        rows.push(vec![
            format!("{name}: max relative drift of |Π|², of the energy"),
            format!("{}, {}", fmt_num(drift.0), fmt_num(drift.1)),
            String::new(),
        ]);
    }
    for (name, _, _, attitude) in &errors {
        rows.push(vec![
            format!("{name}: attitude error (rad) at t = {}", fmt_num(time)),
            fmt_num(attitude.last().map_or(f64::NAN, |p| p.1)),
            String::new(),
        ]);
    }
    let table = Table {
        header: vec![
            "quantity".into(),
            "value".into(),
            "relative to the closed form".into(),
        ],
        rows,
    };
    Ok((
        table,
        vec![
            (MOMENTUM_FIGURE.to_string(), momentum),
            (GROWTH_FIGURE.to_string(), growth_fig),
            (ERROR_FIGURE.to_string(), error_fig),
        ],
    ))
}
