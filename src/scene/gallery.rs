//! The canonical transformation gallery: one table of canonicity certificates, computed by
//! dual-number AD, for maps of every kind the crate can build — generating functions of the four
//! kinds, a point transformation, explicit maps and their compositions and inverses, exact flows,
//! numerical integrator steps, Lie series — next to deliberately non-canonical maps and generators
//! that are refused at their singular points.
//!
//! See [`transformation_gallery`].

use super::case::Table;
use crate::brackets::{certify, Certificate, PhaseMap};
use crate::error::{Error, Result};
use crate::integrate::{Gauss, OneStep, Rk4, Splitting, StepMap};
use crate::nalgebra::SVector;
use crate::systems::{HarmonicOscillator, Kepler2, Pendulum};
use crate::transform::generating::{RelationPoint, Sheet};
use crate::transform::lie::{lie_flow, Ict};
use crate::transform::point::{point_transformation, Polar};
use crate::transform::{CanonicalTransformation, Compose, GeneratingFunction, Inverse, Kind};
use crate::DualNum;
use std::f64::consts::PI;

/// Column headers of the gallery.
const HEADER: [&str; 7] = [
    "transformation",
    "type",
    "at (q, p)",
    "‖MᵀJM − J‖",
    "‖MJMᵀ − J‖",
    "det M − 1",
    "verdict",
];

/// Placeholder of a numeric cell of a refused row.
const NONE: &str = "—";

// ---------------------------------------------------------------------------------------------
// The maps.

/// The oscillator's angle variables, `F₁(q, Q) = ½ m ω q² cot Q` [Goldstein §9.3; Ardema 16.5]:
/// `p = m ω q cot Q`, `P = m ω q² / (2 sin² Q)`, so `tan Q = m ω q / p` and `P = H/ω`. The relation
/// is multi-sheeted (`(−q, −p)` and `Q + kπ` satisfy it too); the sheet of
/// `q = √(2P/(mω)) sin Q`, `p = √(2mωP) cos Q` with `−π < Q ≤ π` is `q sin Q > 0`.
struct AngleVariables {
    m: f64,
    omega: f64,
}

impl GeneratingFunction<1> for AngleVariables {
    fn kind(&self) -> Kind {
        Kind::F1
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        q[0] * q[0] * (0.5 * self.m * self.omega) / big_q[0].tan()
    }
    fn sheet(&self) -> Sheet<1> {
        Sheet::satisfying("q sin Q > 0, −π < Q ≤ π", |z: &RelationPoint<1>| {
            z.q[0] * z.big_q[0].sin() > 0.0 && z.big_q[0] > -PI && z.big_q[0] <= PI
        })
    }
}

/// Free fall, `F₁(q, Q, t) = (q − Q)²/(2t) − ½ g t (q + Q) − g² t³/24` [Ardema 16.4]: Hamilton's
/// principal function of `H = p²/2 + g q`; it maps the state at time `t` to the initial state
/// `(Q, P)`, and `K = H + ∂F₁/∂t ≡ 0`.
struct FreeFall {
    g: f64,
}

impl GeneratingFunction<1> for FreeFall {
    fn kind(&self) -> Kind {
        Kind::F1
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        let d = q[0] - big_q[0];
        d * d / (t * 2.0)
            - t * (q[0] + big_q[0]) * (0.5 * self.g)
            - t * t * t * (self.g * self.g / 24.0)
    }
}

/// `F₂(q, P) = qP + h H(q, P)` with the pendulum's `H = P²/2 + 1 − cos q`: `p = P + h sin q`,
/// `Q = q + h P` — one step of the symplectic Euler method, which is canonical because it has a
/// generating function [Hairer, Lubich & Wanner §VI.5].
struct SymplecticEulerF2 {
    h: f64,
}

impl GeneratingFunction<1> for SymplecticEulerF2 {
    fn kind(&self) -> Kind {
        Kind::F2
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        big_p: &SVector<D, 1>,
    ) -> D {
        q[0] * big_p[0] + (big_p[0] * big_p[0] * 0.5 - q[0].cos() + 1.0) * self.h
    }
}

/// `F₃(p, Q) = −(e^Q − 1)² tan p`: `q = (e^Q − 1)² sec² p`, `P = 2 (e^Q − 1) e^Q tan p`, i.e.
/// `Q = ln(1 + √q cos p)`, `P = 2 (1 + √q cos p) √q sin p` [Goldstein, ch. 9 exercises].
struct LogarithmicF3;

impl GeneratingFunction<1> for LogarithmicF3 {
    fn kind(&self) -> Kind {
        Kind::F3
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        p: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        let e = big_q[0].exp() - 1.0;
        -(e * e) * p[0].tan()
    }
}

/// `F₄(p, P) = −p² tan P / (2 m ω)`: `q = p tan P/(m ω)`, `Q = −p² sec² P/(2 m ω)`, i.e.
/// `Q = −H/ω`, `P = arctan(m ω q / p)` — the oscillator's action and angle of
/// [`AngleVariables`] exchanged as `(Q, P) = (−J, φ)`.
struct ActionAngleF4 {
    m: f64,
    omega: f64,
}

impl GeneratingFunction<1> for ActionAngleF4 {
    fn kind(&self) -> Kind {
        Kind::F4
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        p: &SVector<D, 1>,
        big_p: &SVector<D, 1>,
    ) -> D {
        -(p[0] * p[0]) * big_p[0].tan() / (2.0 * self.m * self.omega)
    }
    fn forward_guess(
        &self,
        _t: f64,
        q: &SVector<f64, 1>,
        p: &SVector<f64, 1>,
    ) -> Option<SVector<f64, 1>> {
        // The principal branch P ∈ (−π/2, π/2).
        Some(SVector::from([(self.m * self.omega * q[0] / p[0]).atan()]))
    }
}

/// `Q = ln(sin p / q)`, `P = q cot p` [Ardema Prob. 16/2; Goldstein, ch. 9 exercises]: canonical.
#[derive(Clone, Copy)]
struct Prob16_2;

impl PhaseMap<1> for Prob16_2 {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        (
            SVector::from([(p[0].sin() / q[0]).ln()]),
            SVector::from([q[0] / p[0].tan()]),
        )
    }
}

/// `Q = √q cos p`, `P = √q sin p` [Ardema Prob. 16/3 with α = ½, β = 1]: `(Q, P) = ½`, not
/// canonical (canonical only for β = 2).
struct Prob16_3HalfAngle;

impl PhaseMap<1> for Prob16_3HalfAngle {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let r = q[0].sqrt();
        let (s, c) = p[0].sin_cos();
        (SVector::from([r * c]), SVector::from([r * s]))
    }
}

/// `(q, p) ↦ (q + p², p + q)`: `det M = 1 − 2p`, not canonical.
struct ShearMap;

impl PhaseMap<1> for ShearMap {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        (
            SVector::from([q[0] + p[0] * p[0]]),
            SVector::from([p[0] + q[0]]),
        )
    }
}

/// `(x, y, p_x, p_y) ↦ (2x, y, p_x, p_y/2)`: volume-preserving (`det M = 1`) but not canonical
/// (`(X, P_X) = 2`, `(Y, P_Y) = ½`): Liouville's theorem is necessary, not sufficient, for
/// `N ≥ 2`.
struct Squeeze;

impl PhaseMap<2> for Squeeze {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> (SVector<D, 2>, SVector<D, 2>) {
        (
            SVector::from([q[0] * 2.0, q[1]]),
            SVector::from([p[0], p[1] * 0.5]),
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Rows.

/// What the certificate of one row found.
#[derive(Clone, Debug, PartialEq)]
enum Outcome {
    /// Certified at the point.
    Certified {
        /// `‖MᵀJM − J‖_max`.
        symplectic: f64,
        /// `‖MJMᵀ − J‖_max`.
        poisson: f64,
        /// `det M − 1`.
        det_minus_one: f64,
        /// The rounding tolerance of the symplectic defect ([`rounding_tolerance`]).
        tolerance: f64,
    },
    /// The map refused to be evaluated there (the error message, on one line).
    Refused(String),
}

/// One row of the gallery, before formatting.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    transformation: String,
    kind: &'static str,
    at: String,
    outcome: Outcome,
}

impl Entry {
    fn verdict(&self) -> String {
        match &self.outcome {
            Outcome::Certified {
                symplectic,
                tolerance,
                ..
            } => {
                if symplectic <= tolerance {
                    "canonical".into()
                } else {
                    "not canonical".into()
                }
            }
            Outcome::Refused(message) => format!("refused: {message}"),
        }
    }

    fn cells(&self) -> Vec<String> {
        let numbers = match &self.outcome {
            Outcome::Certified {
                symplectic,
                poisson,
                det_minus_one,
                ..
            } => [symplectic, poisson, det_minus_one].map(|v| format!("{v:.1e}")),
            Outcome::Refused(_) => [NONE; 3].map(String::from),
        };
        let [a, b, c] = numbers;
        vec![
            self.transformation.clone(),
            self.kind.to_string(),
            self.at.clone(),
            a,
            b,
            c,
            self.verdict(),
        ]
    }
}

/// Tolerance of the symplectic defect of a map whose computed Jacobian has largest entry
/// `max_entry = ‖M‖_max`: `64 ε max(‖M‖_max, 1)²`.
///
/// Derivation (a first-order rounding model). Each entry of `MᵀJM − J` is a signed sum of `2N`
/// products `M_ki M_lj` minus an entry of `J` (0 or ±1, exact). Let each computed entry of `M`
/// carry an absolute error of at most `c ε m`, `m = ‖M‖_max`, where `c` counts the roundings along
/// its AD evaluation (a handful for explicit maps; for maps defined by Newton's method — generating
/// functions, inverses, implicit steps — the derivatives come from the converged, frozen-Jacobian
/// iteration and carry the same few roundings). Then each product errs by at most `(2c + 1) ε m²`
/// (propagated errors plus its own rounding), summing `2N` terms of total magnitude at most
/// `2N m²` adds at most `2N ε · 2N m²`, and the subtraction of `J` adds `ε`: in all
/// `2N (2c + 1 + 2N) ε m² + ε`. For `N ≤ 2` and `c ≤ 3` this is at most `44 ε m² + ε`, below
/// `64 ε max(m, 1)²`. A canonical map evaluated in floating point stays below this bound; a map whose
/// defect exceeds it is not canonical at that point (its defect is then a genuine `O(1)` or
/// truncation-order quantity, far above the bound in every non-canonical row of the gallery).
fn rounding_tolerance(max_entry: f64) -> f64 {
    64.0 * f64::EPSILON * max_entry.max(1.0).powi(2)
}

/// A refused map's message on one line, with `|` (a Markdown cell separator) replaced by `∣`.
fn one_line(message: &str) -> String {
    message
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace('|', "∣")
}

/// A coordinate as text: shortest round-trip decimal, in exponent form when tiny or huge.
fn number(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `(q₁, …, q_N, p₁, …, p_N)` as text, with the time appended when it is not zero.
fn point<const N: usize>(t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> String {
    let parts: Vec<String> = q.iter().chain(p.iter()).map(|&v| number(v)).collect();
    if t == 0.0 {
        format!("({})", parts.join(", "))
    } else {
        format!("({}), t = {}", parts.join(", "), number(t))
    }
}

/// A row from a certificate. A map that refuses the point with [`Error::Singular`] or
/// [`Error::IllConditioned`] (a singular or ill-conditioned generator) becomes a refused row; any
/// other error is returned.
fn entry<const N: usize>(
    transformation: &str,
    kind: &'static str,
    (t, q, p): (f64, SVector<f64, N>, SVector<f64, N>),
    certificate: impl FnOnce(f64, &SVector<f64, N>, &SVector<f64, N>) -> Result<Certificate<N>>,
) -> Result<Entry> {
    let outcome = match certificate(t, &q, &p) {
        Ok(c) => Outcome::Certified {
            symplectic: c.symplectic_defect,
            poisson: c.poisson_defect,
            det_minus_one: c.det_minus_one,
            tolerance: rounding_tolerance(c.jacobian.max_abs()),
        },
        Err(e @ (Error::Singular { .. } | Error::IllConditioned { .. })) => {
            Outcome::Refused(one_line(&e.to_string()))
        }
        Err(e) => return Err(e),
    };
    Ok(Entry {
        transformation: transformation.into(),
        kind,
        at: point(t, &q, &p),
        outcome,
    })
}

/// A point `(t, q, p)` of one degree of freedom.
fn at1(t: f64, q: f64, p: f64) -> (f64, SVector<f64, 1>, SVector<f64, 1>) {
    (t, SVector::from([q]), SVector::from([p]))
}

/// A point `(t, q, p)` of two degrees of freedom.
fn at2(t: f64, q: [f64; 2], p: [f64; 2]) -> (f64, SVector<f64, 2>, SVector<f64, 2>) {
    (t, SVector::from(q), SVector::from(p))
}

/// Certify a [`PhaseMap`] (a closure for [`entry`]).
fn map_certificate<'a, M: PhaseMap<N>, const N: usize>(
    map: &'a M,
) -> impl FnOnce(f64, &SVector<f64, N>, &SVector<f64, N>) -> Result<Certificate<N>> + 'a {
    move |t, q, p| certify(map, t, q, p)
}

/// Certify the forward map of a generating function (a closure for [`entry`]); the forward map is
/// evaluated first with its singularity checks, so a singular generator is refused with
/// [`Error::Singular`].
fn generated_certificate<'a, G: GeneratingFunction<N>, const N: usize>(
    ct: &'a CanonicalTransformation<G, N>,
) -> impl FnOnce(f64, &SVector<f64, N>, &SVector<f64, N>) -> Result<Certificate<N>> + 'a {
    move |t, q, p| ct.certify(t, q, p)
}

/// Every row of the gallery, unformatted.
fn entries() -> Result<Vec<Entry>> {
    let (m, omega) = (2.0, 3.0);
    let angle = CanonicalTransformation::new(AngleVariables { m, omega });
    let free_fall = CanonicalTransformation::new(FreeFall { g: 9.81 });
    let euler_f2 = CanonicalTransformation::new(SymplecticEulerF2 { h: 0.3 });
    let log_f3 = CanonicalTransformation::new(LogarithmicF3);
    let action_f4 = CanonicalTransformation::new(ActionAngleF4 { m, omega });
    let polar = point_transformation(Polar);
    let pendulum = Pendulum::new(1.0)?;
    let kepler = Kepler2::new(1.0)?;
    let oscillator = HarmonicOscillator::new(m, omega)?;
    let gauss = Gauss::<3>::new()?;
    let h = 0.1;
    let verlet = StepMap {
        system: &pendulum,
        method: &Splitting::VERLET_KDK,
        dt: h,
    };
    let gauss_step = StepMap {
        system: &kepler,
        method: &gauss,
        dt: h,
    };
    let rk4 = StepMap {
        system: &pendulum,
        method: &Rk4,
        dt: h,
    };
    let verlet_label = OneStep::<Pendulum, 1>::name(verlet.method);
    let gauss_label = OneStep::<Kepler2, 2>::name(gauss_step.method);
    let rk4_label = OneStep::<Pendulum, 1>::name(rk4.method);
    let lie8 = lie_flow(pendulum, 0.02, 8)?;
    let lie3 = lie_flow(pendulum, 0.02, 3)?;
    let euler_ict = Ict::new(pendulum, h)?;
    let flow = oscillator.flow_map(0.7);
    // The point of the torus P = 0.5 at Q = π − 1e−9, where q → 0 (the caustic of F₁), mapped
    // forward on the sheet through the point Q = 3π/4 of the same quadrant (q > 0, p < 0).
    let torus = |big_q: f64, big_p: f64| {
        (
            SVector::from([(2.0 * big_p / (m * omega)).sqrt() * big_q.sin()]),
            SVector::from([(2.0 * m * omega * big_p).sqrt() * big_q.cos()]),
        )
    };
    let caustic = torus(PI - 1e-9, 0.5);
    let reference = torus(0.75 * PI, 0.5);
    let angle_caustic = CanonicalTransformation::new(AngleVariables { m, omega }).with_sheet(
        Sheet::through(RelationPoint {
            t: 0.0,
            q: reference.0,
            p: reference.1,
            big_q: SVector::from([0.75 * PI]),
            big_p: SVector::from([0.5]),
        })?,
    );
    let identity = Compose(Prob16_2, Inverse::new(Prob16_2));

    Ok(vec![
        entry(
            "oscillator angle variables F₁ = ½mωq² cot Q (m = 2, ω = 3)",
            "F₁ generating function",
            at1(0.0, 0.5, 1.2),
            generated_certificate(&angle),
        )?,
        entry(
            "free fall F₁ = (q − Q)²/(2t) − ½gt(q + Q) − g²t³/24 (g = 9.81)",
            "F₁ generating function",
            at1(0.3, 1.0, 0.5),
            generated_certificate(&free_fall),
        )?,
        entry(
            "symplectic Euler step of the pendulum, F₂ = qP + h(P²/2 + 1 − cos q) (h = 0.3)",
            "F₂ generating function",
            at1(0.0, 1.0, 0.5),
            generated_certificate(&euler_f2),
        )?,
        entry(
            "Q = ln(1 + √q cos p), P = 2(1 + √q cos p)√q sin p from F₃ = −(e^Q − 1)² tan p",
            "F₃ generating function",
            at1(0.0, 0.5, 0.4),
            generated_certificate(&log_f3),
        )?,
        entry(
            "oscillator (−action, angle) from F₄ = −p² tan P/(2mω) (m = 2, ω = 3)",
            "F₄ generating function",
            at1(0.0, 0.5, 1.2),
            generated_certificate(&action_f4),
        )?,
        entry(
            "polar coordinates (x, y, p_x, p_y) ↦ (r, θ, P_r, P_θ)",
            "point transformation",
            at2(0.0, [1.0, 0.5], [0.3, -0.7]),
            generated_certificate(&polar),
        )?,
        entry(
            "Q = ln(sin p / q), P = q cot p (Ardema Prob. 16/2)",
            "explicit map",
            at1(0.0, 0.7, 1.1),
            map_certificate(&Prob16_2),
        )?,
        entry(
            "(16/2)⁻¹ ∘ (16/2), inverse by Newton's method",
            "composition",
            at1(0.0, 0.7, 1.1),
            map_certificate(&identity),
        )?,
        entry(
            "Q = √q cos p, P = √q sin p (Ardema Prob. 16/3, α = ½, β = 1)",
            "explicit map",
            at1(0.0, 0.7, 1.1),
            map_certificate(&Prob16_3HalfAngle),
        )?,
        entry(
            "(q, p) ↦ (q + p², p + q)",
            "explicit map",
            at1(0.0, 0.7, 1.1),
            map_certificate(&ShearMap),
        )?,
        entry(
            "(x, y, p_x, p_y) ↦ (2x, y, p_x, p_y/2): det M = 1",
            "explicit map",
            at2(0.0, [1.0, 0.5], [0.3, -0.7]),
            map_certificate(&Squeeze),
        )?,
        entry(
            "harmonic oscillator flow over τ = 0.7 (m = 2, ω = 3)",
            "exact flow",
            at1(0.0, 0.5, 1.2),
            map_certificate(&flow),
        )?,
        entry(
            &format!("{}: one step of the pendulum, h = 0.1", verlet_label),
            "numerical step",
            at1(0.0, 1.0, 0.5),
            map_certificate(&verlet),
        )?,
        entry(
            &format!("{}: one step of Kepler, h = 0.1", gauss_label),
            "numerical step",
            at2(0.0, [1.2, -0.4], [0.3, 0.9]),
            map_certificate(&gauss_step),
        )?,
        entry(
            &format!(
                "{}: one step of the pendulum, h = 0.1 (defect O(h⁶))",
                rk4_label
            ),
            "numerical step",
            at1(0.0, 1.0, 0.5),
            map_certificate(&rk4),
        )?,
        entry(
            "pendulum flow as the Lie series exp(h L_H), h = 0.02, order 8",
            "Lie series",
            at1(0.0, 1.0, 0.5),
            map_certificate(&lie8),
        )?,
        entry(
            "pendulum flow as the Lie series exp(h L_H), h = 0.02, order 3 (defect O(h⁴))",
            "Lie series",
            at1(0.0, 1.0, 0.5),
            map_certificate(&lie3),
        )?,
        entry(
            "ICT generated by the pendulum's H, ε = 0.1 (explicit Euler step, defect O(ε²))",
            "infinitesimal transformation",
            at1(0.0, 1.0, 0.5),
            map_certificate(&euler_ict),
        )?,
        Entry {
            // The inverse map's arguments are the new variables: label them as such.
            at: "(q, p) at (Q, P) = (π − 1e-9, 0.5)".into(),
            ..entry(
                "oscillator angle variables F₁, forward map at Q → π (q → 0, the caustic of F₁)",
                "F₁ generating function",
                (0.0, caustic.0, caustic.1),
                generated_certificate(&angle_caustic),
            )?
        },
        entry(
            "free fall F₁ as t → 0 (the identity has no type-1 generator)",
            "F₁ generating function",
            at1(1e-9, 1.0, 0.5),
            generated_certificate(&free_fall),
        )?,
    ])
}

/// The canonical transformation gallery: canonicity certificates, by AD, of one map of every kind
/// the crate builds, with deliberately non-canonical maps and refused singular generators as
/// controls.
///
/// # What each row measures
///
/// Each row is a map `(q, p) ↦ (Q, P)` of phase space at one point `(q, p)` (and time `t`, printed
/// when not zero). Its exact Jacobian
///
/// ```math
/// M = \frac{\partial(Q, P)}{\partial(q, p)},\qquad
/// J = \begin{pmatrix} 0 & I \\ -I & 0 \end{pmatrix},
/// ```
///
/// is computed by dual-number AD ([`crate::brackets::certify`]) — through Newton's method by implicit
/// differentiation where the map is defined implicitly (generating functions, inverses, implicit
/// integrator steps) — and the row reports
///
/// * `‖MᵀJM − J‖` (max-norm): the Lagrange brackets `[u_i, u_j]` of the old variables as functions
///   of the new ones minus their canonical values [Ardema eqs. 16.24–16.25]; zero iff the map is
///   canonical (symplectic) at the point [Goldstein §9.4];
/// * `‖MJMᵀ − J‖`: the Poisson brackets `(u_i, u_j)` of the new variables as functions of the old
///   ones minus `J` [Ardema eq. 16.28], the same criterion computed independently (`MᵀJM = J` ⇔
///   `MJMᵀ = J`);
/// * `det M − 1`: Liouville's theorem [Ardema eq. 16.23], necessary for canonicity and, for one
///   degree of freedom, sufficient (`MᵀJM = (det M) J` when `N = 1`), but not for `N ≥ 2` (see the
///   volume-preserving squeeze row);
/// * the verdict: `canonical` if `‖MᵀJM − J‖ ≤ 64 ε max(‖M‖_max, 1)²` — the rounding bound of
///   the computed defect of an exactly canonical map (derivation at the tolerance function in the
///   source) — `not canonical` otherwise, and `refused: …` with the one-line message of
///   [`Error::Singular`] or [`Error::IllConditioned`] where the map cannot be evaluated to the required accuracy (the numeric
///   cells are then `—`).
///
/// # The rows
///
/// 1. Generating functions, with `p = ∂F₁/∂q`, `P = −∂F₁/∂Q` (F₁), `p = ∂F₂/∂q`, `Q = ∂F₂/∂P` (F₂),
///    `q = −∂F₃/∂p`, `P = −∂F₃/∂Q` (F₃), `q = −∂F₄/∂p`, `Q = ∂F₄/∂P` (F₄) [Ardema eqs. 16.4–16.18;
///    Goldstein §9.1]: the oscillator's angle variables `F₁ = ½mωq² cot Q` [Goldstein §9.3;
///    Ardema 16.5]; free fall, `F₁ = (q − Q)²/(2t) − ½gt(q + Q) − g²t³/24`, time-dependent, mapping
///    the state at `t` to the initial state [Ardema 16.4]; the pendulum's symplectic Euler step as
///    `F₂ = qP + hH(q, P)` [Hairer, Lubich & Wanner §VI.5]; `F₃ = −(e^Q − 1)² tan p`, giving
///    `Q = ln(1 + √q cos p)`, `P = 2(1 + √q cos p)√q sin p` [Goldstein, ch. 9 exercises]; and
///    `F₄ = −p² tan P/(2mω)`, giving `(Q, P) = (−H/ω, arctan(mωq/p))`, the oscillator's action and
///    angle exchanged.
/// 2. The polar point transformation `x = r cos θ`, `y = r sin θ` with `P = (∂q/∂Q)ᵀ p`
///    [Ardema 16.3, eq. 16.22].
/// 3. Explicit maps: `Q = ln(sin p / q)`, `P = q cot p` [Ardema Prob. 16/2], canonical, and its
///    composition with its Newton inverse (the identity); the non-canonical controls
///    `Q = √q cos p`, `P = √q sin p` [Ardema Prob. 16/3 with β = 1: `(Q, P) = ½`],
///    `(q, p) ↦ (q + p², p + q)` (`det M = 1 − 2p`) and the squeeze
///    `(x, y, p_x, p_y) ↦ (2x, y, p_x, p_y/2)` (`det M = 1`, yet `(X, P_X) = 2`).
/// 4. The harmonic oscillator's exact flow over `τ`, `q = q₀ cos ωτ + p₀ sin ωτ/(mω)`,
///    `p = p₀ cos ωτ − mωq₀ sin ωτ`: canonical, as every Hamiltonian flow [Goldstein §9.6].
/// 5. One step of numerical integrators: Störmer–Verlet and Gauss–Legendre are symplectic
///    [Hairer, Lubich & Wanner §§VI.3–VI.4] and certify to rounding; the classical Runge–Kutta
///    method is not: its step at `h = 0.1` has a defect far above rounding, which falls as `h⁶`
///    (by a factor of about 64 per halving of `h`, measured here for the pendulum; for the linear
///    oscillator `det M = |R(iωh)|² = 1 − (ωh)⁶/72 + (ωh)⁸/576` with `R` the stability function).
/// 6. Lie series `exp(h L_H) z = Σₖ hᵏ/k! L_Hᵏ z`, `L_H f = (f, H)` — the pendulum's flow over `h`
///    as a Taylor series [Deprit 1969; Ardema 18.3]: canonical to its truncation, `O(h^{n+1})`
///    for order `n` (below rounding at order 8 for `h = 0.02`, visible at order 3); and the
///    infinitesimal contact transformation `Q = q + ε ∂ρ/∂p`, `P = p − ε ∂ρ/∂q` with `ρ = H`
///    [Ardema eqs. 18.38–18.39], one explicit Euler step, canonical to first order only
///    (`MᵀJM − J = ε² AᵀJA`).
/// 7. Refusals ([`Error::IllConditioned`], naming the measured condition number and the threshold
///    [`crate::transform::generating::DEFAULT_MAX_CONDITION`]): the forward map of the
///    angle-variable `F₁` at the point of the torus `P = 0.5`, `Q = π − 10⁻⁹`, where
///    `q = √(2P/(mω)) sin Q → 0` (the caustic of the type-1 description, which cannot represent the
///    oscillator's passages through `q = 0`): `Q` is solved to `ε π` but `P = mωq²/(2 sin² Q)` is
///    then formed from `sin Q`, so its relative error is about `π ε/(π − Q)`; and the free-fall `F₁`
///    at `t = 10⁻⁹`, where the map tends to the identity, which has no type-1 generator
///    (`∂²F₁/∂q∂Q = −1/t`). The sheet of the angle variables is `q sin Q > 0`, `−π < Q ≤ π` (the
///    relation also holds for `(−q, −p)` and for `Q + kπ`); the refused row follows the sheet
///    through the point `Q = 3π/4` of the same quadrant by continuation.
///
/// # References
/// * M. D. Ardema, *Analytical Dynamics: Theory and Applications*, Kluwer/Plenum 2005, ch. 16
///   and §18.3.
/// * H. Goldstein, C. Poole and J. Safko, *Classical Mechanics*, 3rd ed., Addison-Wesley 2002,
///   ch. 9.
/// * E. Hairer, C. Lubich and G. Wanner, *Geometric Numerical Integration*, 2nd ed., Springer
///   2006, ch. VI.
/// * A. Deprit, "Canonical transformations depending on a small parameter", *Celestial Mechanics*
///   1, 12–30 (1969).
///
/// # Errors
/// Any error of a row other than the refusal of a singular or ill-conditioned generator
/// ([`Error::Singular`], [`Error::IllConditioned`]), which is reported in the row itself.
pub fn transformation_gallery() -> Result<Table> {
    Ok(Table {
        header: HEADER.iter().map(|s| s.to_string()).collect(),
        rows: entries()?.iter().map(Entry::cells).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PhaseMatrix;

    /// The expected verdict of every row, identified by the start of its `transformation` cell.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Expect {
        Canonical,
        NotCanonical,
        Refused,
    }

    const EXPECTED: [(&str, Expect); 20] = [
        ("oscillator angle variables F₁ = ", Expect::Canonical),
        ("free fall F₁ = ", Expect::Canonical),
        ("symplectic Euler step", Expect::Canonical),
        ("Q = ln(1 + √q cos p)", Expect::Canonical),
        ("oscillator (−action, angle)", Expect::Canonical),
        ("polar coordinates", Expect::Canonical),
        ("Q = ln(sin p / q)", Expect::Canonical),
        ("(16/2)⁻¹ ∘ (16/2)", Expect::Canonical),
        ("Q = √q cos p", Expect::NotCanonical),
        ("(q, p) ↦ (q + p², p + q)", Expect::NotCanonical),
        ("(x, y, p_x, p_y) ↦ (2x", Expect::NotCanonical),
        ("harmonic oscillator flow", Expect::Canonical),
        (
            "Störmer–Verlet (kick–drift–kick), 1 stage",
            Expect::Canonical,
        ),
        ("Gauss–Legendre, 3 stages, order 6", Expect::Canonical),
        ("classical Runge–Kutta, 4 stages", Expect::NotCanonical),
        (
            "pendulum flow as the Lie series exp(h L_H), h = 0.02, order 8",
            Expect::Canonical,
        ),
        (
            "pendulum flow as the Lie series exp(h L_H), h = 0.02, order 3",
            Expect::NotCanonical,
        ),
        ("ICT generated", Expect::NotCanonical),
        (
            "oscillator angle variables F₁, forward map at Q → π",
            Expect::Refused,
        ),
        ("free fall F₁ as t → 0", Expect::Refused),
    ];

    #[test]
    fn every_row_has_its_expected_verdict() -> Result<()> {
        let rows = entries()?;
        assert_eq!(rows.len(), EXPECTED.len());
        for (row, (name, expect)) in rows.iter().zip(EXPECTED) {
            assert!(
                row.transformation.starts_with(name),
                "row {:?} where {name:?} was expected",
                row.transformation
            );
            let verdict = row.verdict();
            match (&row.outcome, expect) {
                (
                    Outcome::Certified {
                        symplectic,
                        poisson,
                        tolerance,
                        ..
                    },
                    Expect::Canonical,
                ) => {
                    assert!(
                        symplectic <= tolerance,
                        "{name}: {symplectic:e} > {tolerance:e}"
                    );
                    assert!(poisson <= tolerance, "{name}: {poisson:e} > {tolerance:e}");
                    assert_eq!(verdict, "canonical", "{name}");
                }
                (
                    Outcome::Certified {
                        symplectic,
                        poisson,
                        tolerance,
                        ..
                    },
                    Expect::NotCanonical,
                ) => {
                    // Far above rounding, not marginally: a genuine defect.
                    assert!(
                        *symplectic > 1e3 * tolerance,
                        "{name}: {symplectic:e} vs {tolerance:e}"
                    );
                    assert!(*poisson > 1e3 * tolerance, "{name}");
                    assert_eq!(verdict, "not canonical", "{name}");
                }
                (Outcome::Refused(message), Expect::Refused) => {
                    assert!(verdict.starts_with("refused: "), "{name}: {verdict}");
                    assert!(
                        message.contains("singular") || message.contains("ill-conditioned"),
                        "{name}: {message}"
                    );
                    assert!(!message.contains('\n'), "{name}: {message}");
                }
                (outcome, expect) => panic!("{name}: expected {expect:?}, got {outcome:?}"),
            }
        }
        Ok(())
    }

    #[test]
    fn defects_match_their_closed_forms() -> Result<()> {
        let rows = entries()?;
        let find = |name: &str| {
            rows.iter()
                .find(|r| r.transformation.starts_with(name))
                .map(|r| r.outcome.clone())
        };
        // N = 1: MᵀJM = (det M) J, so the defect is |det M − 1|.
        // 16/3 with β = 1: det M = ½. Shear at p = 1.1: det M = 1 − 2p = −1.2.
        // Squeeze: det M = 1, defect max(|2 − 1|, |½ − 1|) = 1.
        for (name, defect, det_minus_one) in [
            ("Q = √q cos p", 0.5, -0.5),
            ("(q, p) ↦ (q + p², p + q)", 2.2, -2.2),
            ("(x, y, p_x, p_y) ↦ (2x", 1.0, 0.0),
        ] {
            match find(name) {
                Some(Outcome::Certified {
                    symplectic,
                    poisson,
                    det_minus_one: d,
                    ..
                }) => {
                    assert!((symplectic - defect).abs() <= 1e-15, "{name}: {symplectic}");
                    assert!((poisson - defect).abs() <= 1e-15, "{name}: {poisson}");
                    assert!((d - det_minus_one).abs() <= 1e-15, "{name}: {d}");
                }
                other => panic!("{name}: {other:?}"),
            }
        }
        // ICT with ρ = H = p²/2 + 1 − cos q: A = [[0, 1], [−cos q, 0]], MᵀJM − J = ε² det(A) J.
        match find("ICT generated") {
            Some(Outcome::Certified { symplectic, .. }) => {
                let expected = 0.01 * 1f64.cos();
                assert!((symplectic - expected).abs() <= 1e-15, "{symplectic}");
            }
            other => panic!("ICT: {other:?}"),
        }
        Ok(())
    }

    /// The generating-function rows compute the maps their documentation states.
    #[test]
    fn generated_maps_match_their_closed_forms() -> Result<()> {
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * (1.0 + b.abs());
        // F₂ = qP + h(P²/2 + 1 − cos q): P = p − h sin q, Q = q + hP.
        let h = 0.3;
        let (q, p) = (1.0f64, 0.5f64);
        let (bq, bp) = CanonicalTransformation::new(SymplecticEulerF2 { h }).forward(
            0.0,
            &SVector::from([q]),
            &SVector::from([p]),
        )?;
        let big_p = p - h * q.sin();
        assert!(
            close(bp[0], big_p) && close(bq[0], q + h * big_p),
            "F₂: {bq} {bp}"
        );
        // F₃ = −(e^Q − 1)² tan p: Q = ln(1 + √q cos p), P = 2(1 + √q cos p)√q sin p.
        let (q, p) = (0.5f64, 0.4f64);
        let (bq, bp) = CanonicalTransformation::new(LogarithmicF3).forward(
            0.0,
            &SVector::from([q]),
            &SVector::from([p]),
        )?;
        let a = 1.0 + q.sqrt() * p.cos();
        assert!(close(bq[0], a.ln()), "F₃: Q = {bq}");
        assert!(close(bp[0], 2.0 * a * q.sqrt() * p.sin()), "F₃: P = {bp}");
        // F₄ = −p² tan P/(2mω): Q = −H/ω, P = arctan(mωq/p).
        let (m, w, q, p) = (2.0f64, 3.0f64, 0.5f64, 1.2f64);
        let (bq, bp) = CanonicalTransformation::new(ActionAngleF4 { m, omega: w }).forward(
            0.0,
            &SVector::from([q]),
            &SVector::from([p]),
        )?;
        let energy = p * p / (2.0 * m) + 0.5 * m * w * w * q * q;
        assert!(close(bq[0], -energy / w), "F₄: Q = {bq}");
        assert!(close(bp[0], (m * w * q / p).atan()), "F₄: P = {bp}");
        Ok(())
    }

    #[test]
    fn truncation_orders_of_the_non_canonical_steps() -> Result<()> {
        let (q, p) = (SVector::from([1.0]), SVector::from([0.5]));
        // Lie series of order 3: defect O(h⁴), halving h divides it by about 2⁴ = 16.
        let pendulum = Pendulum::new(1.0)?;
        let lie = |dt: f64| -> Result<f64> {
            Ok(certify(&lie_flow(pendulum, dt, 3)?, 0.0, &q, &p)?.symplectic_defect)
        };
        let ratio = lie(0.02)? / lie(0.01)?;
        assert!((14.0..=18.0).contains(&ratio), "Lie ratio {ratio}");
        // RK4: halving h divides the step's defect by about 2⁶ = 64.
        let pendulum = Pendulum::new(1.0)?;
        let (q, p) = (SVector::from([1.0]), SVector::from([0.5]));
        let defect = |dt: f64| -> Result<f64> {
            let map = StepMap {
                system: &pendulum,
                method: &Rk4,
                dt,
            };
            Ok(certify(&map, 0.0, &q, &p)?.symplectic_defect)
        };
        let ratio = defect(0.1)? / defect(0.05)?;
        assert!((54.0..=72.0).contains(&ratio), "RK4 ratio {ratio}");
        Ok(())
    }

    #[test]
    fn table_is_complete() -> Result<()> {
        let table = transformation_gallery()?;
        assert_eq!(table.header, HEADER.map(String::from).to_vec());
        assert_eq!(table.rows.len(), EXPECTED.len());
        for row in &table.rows {
            assert_eq!(row.len(), HEADER.len(), "{row:?}");
            for cell in row {
                assert!(!cell.is_empty(), "{row:?}");
                assert!(!cell.contains(['|', '\n']), "{cell}");
            }
            let verdict = &row[6];
            if verdict.starts_with("refused: ") {
                assert_eq!(&row[3..6], [NONE; 3].map(String::from).as_slice());
            } else {
                assert!(verdict == "canonical" || verdict == "not canonical");
                for cell in &row[3..6] {
                    let v: f64 = cell.parse().map_err(|_| Error::invalid("cell", cell))?;
                    assert!(v.is_finite(), "{cell}");
                    assert_eq!(*cell, format!("{v:.1e}"));
                }
            }
        }
        let md = table.to_markdown();
        assert_eq!(md.lines().count(), EXPECTED.len() + 2);
        assert!(md
            .lines()
            .all(|l| l.matches('|').count() == HEADER.len() + 1));
        Ok(())
    }

    /// Independent oracle: the Jacobian of the polar transformation by central differences of the
    /// real forward map (Newton's method on reals, no AD) converges to the AD Jacobian as `O(δ²)`,
    /// and so does its symplectic defect to the AD defect.
    #[test]
    fn polar_defect_agrees_with_central_differences() -> Result<()> {
        let polar = point_transformation(Polar);
        let (q, p) = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
        let ad = polar.certify(0.0, &q, &p)?;
        let central = |delta: f64| -> Result<PhaseMatrix<2>> {
            let mut cols = crate::nalgebra::DMatrix::zeros(4, 4);
            for j in 0..4 {
                let (mut qa, mut pa, mut qb, mut pb) = (q, p, q, p);
                if j < 2 {
                    qa[j] += delta;
                    qb[j] -= delta;
                } else {
                    pa[j - 2] += delta;
                    pb[j - 2] -= delta;
                }
                let (qa, pa) = polar.forward(0.0, &qa, &pa)?;
                let (qb, pb) = polar.forward(0.0, &qb, &pb)?;
                for i in 0..2 {
                    cols[(i, j)] = (qa[i] - qb[i]) / (2.0 * delta);
                    cols[(i + 2, j)] = (pa[i] - pb[i]) / (2.0 * delta);
                }
            }
            PhaseMatrix::from_dmatrix(&cols)
        };
        // Truncation δ²/6 |∂³u| with third derivatives of size ≲ 3/r³ ≈ 2 at r = 1.12 (bound 1·δ²
        // with margin); rounding ε|u|/δ ≈ 1e−13 at δ = 1e−3, negligible.
        let mut previous: Option<(f64, f64)> = None;
        for delta in [1e-2, 1e-3] {
            let fd = central(delta)?;
            let jacobian_error = fd.sub(&ad.jacobian).max_abs();
            let defect_gap = (fd.symplectic_defect() - ad.symplectic_defect).abs();
            assert!(
                jacobian_error <= delta * delta,
                "δ = {delta}: {jacobian_error:e}"
            );
            assert!(
                defect_gap <= 4.0 * delta * delta,
                "δ = {delta}: {defect_gap:e}"
            );
            if let Some((e, d)) = previous {
                // Tenfold smaller δ: errors about a hundredfold smaller.
                assert!(
                    (50.0..=200.0).contains(&(e / jacobian_error)),
                    "{e:e} → {jacobian_error:e}"
                );
                assert!(
                    (50.0..=200.0).contains(&(d / defect_gap)),
                    "{d:e} → {defect_gap:e}"
                );
            }
            previous = Some((jacobian_error, defect_gap));
        }
        // And the AD defect itself is at rounding level.
        assert!(ad.symplectic_defect <= rounding_tolerance(ad.jacobian.max_abs()));
        Ok(())
    }
}
