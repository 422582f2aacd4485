//! The scene of struck rods (SPEC T35, T36; Ardema 13.3): velocity jumps by the impulsive
//! Lagrange equations ([`apply_impulse`]) against their closed forms.
//!
//! * Three uniform rods `AB`, `BC`, `CD` of mass `M`, hinged in a line and at rest, struck at `A`
//!   by an impulse `P` normal to the line: the normal velocities of `A, B, C, D` after the blow
//!   are `(52, −14, 4, −2) P/(15M)`.
//! * One rod of mass `M` struck normally at `nℓ` from its end `A`: the end velocities are
//!   `v_A = (4 − 6n) P/M` and `v_B = (6n − 2) P/M` (the end `B` stays at rest for `n = 1/3`: the
//!   centre of percussion).

use super::case::Table;
use crate::error::{fmt_num, positive, Error, Result};
use crate::impulse::{apply_impulse, generalized_impulse, ImpactPoint};
use crate::plot::{Figure, Style};
use crate::systems::HingedRods;
use nalgebra::SVector;
use num_dual::DualNum;

/// The `what` of the figure of the three rods: `figures/<scene>-three-rods`.
pub const THREE_RODS_FIGURE: &str = "three-rods";
/// The `what` of the figure of the rod struck at `nℓ`: `figures/<scene>-one-rod`.
pub const ONE_ROD_FIGURE: &str = "one-rod";

/// The point at `nℓ` from the end `A` of a rod whose ends have the normal displacements
/// `q = (q_A, q_B)`: `x = (1 − n) q_A + n q_B`.
struct AlongRod(f64);

impl ImpactPoint<2, 1> for AlongRod {
    fn position<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SVector<D, 1> {
        SVector::from([q[0] * (1.0 - self.0) + q[1] * self.0])
    }
}

/// The table and figures of the scene `struck-rods`: rods of mass `mass`, the impulse `impulse`,
/// and `samples` points `n ∈ [0, 1]` for the single rod.
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for a mass that is not positive and finite, a
/// non-finite or zero impulse, `samples ∉ [2, 10⁵]`; the errors of [`apply_impulse`].
pub fn struck_rods(
    mass: f64,
    impulse: f64,
    samples: usize,
) -> Result<(Table, Vec<(String, Figure)>)> {
    let mass = positive("rod mass M", mass)?;
    let p = crate::error::finite("impulse P", impulse)?;
    if p == 0.0 {
        return Err(Error::out_of_domain("impulse P", p, "non-zero"));
    }
    if !(2..=100_000).contains(&samples) {
        return Err(Error::out_of_domain(
            "samples of n",
            samples as f64,
            "[2, 10⁵]",
        ));
    }
    let unit = p / mass;
    let mut rows = Vec::new();

    // T35: three rods, the impulse at A.
    let rods = HingedRods::<4>::new(mass)?;
    let jump = apply_impulse(
        &rods,
        0.0,
        &SVector::zeros(),
        &SVector::zeros(),
        &SVector::from([p, 0.0, 0.0, 0.0]),
    )?;
    let closed = [52.0, -14.0, 4.0, -2.0].map(|c| c * p / (15.0 * mass));
    for (k, joint) in ["A", "B", "C", "D"].iter().enumerate() {
        let v = jump.velocity_after[k];
        rows.push(vec![
            "three rods, struck at A".into(),
            format!("v_{joint}"),
            fmt_num(v),
            fmt_num(closed[k]),
            fmt_num(v - closed[k]),
        ]);
    }
    rows.push(vec![
        "three rods, struck at A".into(),
        "T⁺".into(),
        fmt_num(jump.energy_after),
        fmt_num(26.0 * p * p / (15.0 * mass)),
        fmt_num(jump.energy_after - 26.0 * p * p / (15.0 * mass)),
    ]);
    let x = |k: usize| k as f64;
    let three = Figure::new(
        "Three hinged rods struck at one end: velocities after the blow",
        "position along the rods (units of ℓ)",
        "normal velocity · M/P",
    )
    .curve(
        "closed form (52, −14, 4, −2)/15",
        closed.iter().enumerate().map(|(k, v)| (x(k), v / unit)),
        Style::Line,
    )
    .curve(
        "impulsive Lagrange equations",
        jump.velocity_after
            .iter()
            .enumerate()
            .map(|(k, v)| (x(k), v / unit)),
        Style::Markers,
    )
    .caption(format!(
        "Three uniform rods AB, BC, CD of mass M = {} hinged in a line at rest, struck at A by an \
         impulse P = {} normal to the line: the normal velocities of A, B, C, D after the blow \
         from the impulsive Lagrange equations [∂L/∂q̇]₋⁺ = P̂ (markers) against the closed form \
         (52, −14, 4, −2)·P/(15M) of Ardema 13.3 (line through its values); the kinetic energy \
         after the blow is 26P²/(15M).",
        fmt_num(mass),
        fmt_num(p)
    ));

    // T36: one rod struck at nℓ.
    let rod = HingedRods::<2>::new(mass)?;
    let mut computed = (Vec::new(), Vec::new());
    let mut worst: f64 = 0.0;
    for k in 0..samples {
        let n = k as f64 / (samples - 1) as f64;
        let p_hat = generalized_impulse(&AlongRod(n), 0.0, &SVector::zeros(), &SVector::from([p]))?;
        let jump = apply_impulse(&rod, 0.0, &SVector::zeros(), &SVector::zeros(), &p_hat)?;
        let expected = [(4.0 - 6.0 * n) * unit, (6.0 * n - 2.0) * unit];
        worst = worst
            .max((jump.velocity_after[0] - expected[0]).abs())
            .max((jump.velocity_after[1] - expected[1]).abs());
        computed.0.push((n, jump.velocity_after[0] / unit));
        computed.1.push((n, jump.velocity_after[1] / unit));
    }
    for n in [0.0, 0.25, 1.0 / 3.0, 0.5, 1.0] {
        let p_hat = generalized_impulse(&AlongRod(n), 0.0, &SVector::zeros(), &SVector::from([p]))?;
        let jump = apply_impulse(&rod, 0.0, &SVector::zeros(), &SVector::zeros(), &p_hat)?;
        for (e, (name, c)) in [("v_A", 4.0 - 6.0 * n), ("v_B", 6.0 * n - 2.0)]
            .iter()
            .enumerate()
        {
            rows.push(vec![
                format!("one rod, struck at n = {}", fmt_num(n)),
                (*name).into(),
                fmt_num(jump.velocity_after[e]),
                fmt_num(c * unit),
                fmt_num(jump.velocity_after[e] - c * unit),
            ]);
        }
    }
    let line = |f: fn(f64) -> f64| [(0.0, f(0.0)), (1.0, f(1.0))];
    let one = Figure::new(
        "A rod struck at nℓ from its end A: end velocities after the blow",
        "n (point of impact / ℓ)",
        "end velocity · M/P",
    )
    .curve("v_A = (4 − 6n) P/M", line(|n| 4.0 - 6.0 * n), Style::Line)
    .curve("v_B = (6n − 2) P/M", line(|n| 6.0 * n - 2.0), Style::Line)
    .curve(
        "v_A, impulsive Lagrange equations",
        computed.0,
        Style::Markers,
    )
    .curve(
        "v_B, impulsive Lagrange equations",
        computed.1,
        Style::Markers,
    )
    .caption(format!(
        "A uniform rod of mass M = {} at rest struck normally at nℓ from its end A by an impulse \
         P = {}: the end velocities from the impulsive Lagrange equations with the generalized \
         impulse P̂ = (∂x/∂q)ᵀP = ((1 − n)P, nP) (markers, {samples} values of n) against the \
         closed forms (4 − 6n)P/M and (6n − 2)P/M (lines); largest difference {}. B stays at \
         rest for n = 1/3 (the centre of percussion of A), A for n = 2/3.",
        fmt_num(mass),
        fmt_num(p),
        fmt_num(worst)
    ));
    let table = Table {
        header: vec![
            "system".into(),
            "velocity".into(),
            "impulsive Lagrange equations".into(),
            "closed form".into(),
            "difference".into(),
        ],
        rows,
    };
    Ok((
        table,
        vec![
            (THREE_RODS_FIGURE.to_string(), three),
            (ONE_ROD_FIGURE.to_string(), one),
        ],
    ))
}
