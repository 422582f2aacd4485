//! Using known integrals to lower the order of a problem: Whittaker's reduction with the energy
//! integral, Jacobi's last multiplier and Liouville's determinant, the two-degree-of-freedom
//! quadrature for the Kepler problem [Ardema 15.6], and the separated integrals of a Liouville
//! system [Ardema 8.4].
//!
//! Run with `cargo run --release --example hj_reduction`.

use hamilton_jacobi::hamilton_jacobi::{
    liouville_separated_integrals, two_dof_quadrature, variational_flow, LiouvilleSystem,
    TwoDofMomenta, Whittaker,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::Pendulum;
use hamilton_jacobi::{hamiltonian, DualNum, Hamiltonian, Result};

hamiltonian!(
    /// H = ½(p_x² + p_y²) + g x + ½ k² y² [Ardema 15.6].
    FallOscillator<2> { g: f64, k: f64 } |s, _t, q, p| p.dot(p) * 0.5 + q[0] * s.g + q[1] * q[1] * (0.5 * s.k * s.k)
);

/// θ̈ = −sin θ − c θ̇ as H = p²/2 − cos θ with the force Q = −c p.
struct DampedPendulum {
    c: f64,
}
impl Hamiltonian<1> for DampedPendulum {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> D {
        p[0] * p[0] * 0.5 - q[0].cos()
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> Option<SVector<D, 1>> {
        Some(SVector::from([p[0] * -self.c]))
    }
}

/// Central force with μ = 1 in polar coordinates: p_r = √(2h + 2/r − a²/r²), p_θ = a.
struct Kepler;
impl TwoDofMomenta for Kepler {
    fn momenta<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>, h: D, a: D) -> SVector<D, 2> {
        let r = q[0];
        SVector::from([(h * 2.0 + r.recip() * 2.0 - a * a / (r * r)).sqrt(), a])
    }
}

/// A Liouville system [Ardema 8.4]: U = q₁² + q₂², v = 1, W = q₁⁴ + q₂⁴.
struct QuarticLiouville;
impl LiouvilleSystem<2> for QuarticLiouville {
    fn u<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q * q
    }
    fn v<D: DualNum<f64> + Copy>(&self, _s: usize, _q: D) -> D {
        D::from(1.0)
    }
    fn w<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q.powi(4)
    }
}

fn main() -> Result<()> {
    // --- Whittaker: eliminate x, integrate in p_x, recover x and t. ---
    let (g, k) = (2.0, 3.0);
    let sys = FallOscillator { g, k };
    let (q0, p0) = (SVector::from([1.0, 0.5]), SVector::from([0.4, -0.3]));
    let energy = sys.value(0.0, &q0, &p0)?;
    let w = Whittaker::new(sys, energy, 0)?;
    println!(
        "Projectile reduced on p_x: y(p_x) is a sinusoid of wavenumber k/g = {}; t = (p_x0 − p_x)/g",
        k / g
    );
    println!("| p_x | y (reduced, RK4 in p_x) | y exact | x = φ | t | y(t) exact |");
    println!("|---|---|---|---|---|---|");
    let ds = -2e-3;
    let (mut q, mut p, mut t) = (q0, p0, 0.0);
    for step in 1..=2000 {
        // One RK4 step of (q, p, t) in the independent variable p_x.
        let rate = |q: &SVector<f64, 2>, p: &SVector<f64, 2>| w.reduced_field(q, p);
        let k1 = rate(&q, &p)?;
        let k2 = rate(&(q + k1.dq * (0.5 * ds)), &(p + k1.dp * (0.5 * ds)))?;
        let k3 = rate(&(q + k2.dq * (0.5 * ds)), &(p + k2.dp * (0.5 * ds)))?;
        let k4 = rate(&(q + k3.dq * ds), &(p + k3.dp * ds))?;
        q += (k1.dq + (k2.dq + k3.dq) * 2.0 + k4.dq) * (ds / 6.0);
        p += (k1.dp + (k2.dp + k3.dp) * 2.0 + k4.dp) * (ds / 6.0);
        t += (k1.dt + (k2.dt + k3.dt) * 2.0 + k4.dt) * (ds / 6.0);
        if step % 250 == 0 {
            let s = (p[0] - p0[0]) * k / g;
            let y_exact = q0[1] * s.cos() - p0[1] / k * s.sin();
            let y_t = q0[1] * (k * t).cos() + p0[1] / k * (k * t).sin();
            let x = w.eliminated_coordinate(&q, &p)?;
            println!(
                "| {:.3} | {:.15} | {y_exact:.15} | {x:.12} | {t:.3} | {y_t:.15} |",
                p[0], q[1]
            );
        }
    }

    // --- Liouville's determinant and the last multiplier [Ardema 15.6, 16.4]. ---
    let (t_end, c) = (7.3, 0.2);
    let (th, om) = (SVector::from([2.0]), SVector::from([0.5]));
    let f = variational_flow(&Pendulum::new(1.0)?, 0.0, &th, &om, t_end, 7300)?;
    let d = variational_flow(&DampedPendulum { c }, 0.0, &th, &om, t_end, 7300)?;
    println!("\nLiouville's theorem by the variational equations (RK4, 7300 steps):");
    println!(
        "  pendulum: det Φ − 1 = {:.1e};  damped: det Φ = {:.15} (e^(−cT) = {:.15}), M det Φ − 1 = {:.1e}",
        f.jacobian.determinant() - 1.0,
        d.jacobian.determinant(),
        (-c * t_end).exp(),
        (c * t_end).exp() * d.jacobian.determinant() - 1.0
    );

    // --- Two degrees of freedom: Kepler time of flight and orbit from K = ∫ p_r dr + a θ. ---
    let (h, a) = (-0.5, 0.8);
    let radial = two_dof_quadrature(
        &Kepler,
        h,
        a,
        &[SVector::from([0.6, 0.0]), SVector::from([1.2, 0.0])],
    )?;
    let theta1 = -radial.dk_da;
    let e: f64 = (1.0 + 2.0 * h * a * a).sqrt();
    let anomaly = |r: f64| ((1.0 - r) / e).acos();
    let mean = |ea: f64| ea - e * ea.sin();
    println!("\nKepler (μ = 1, h = −½, a = 0.8, e = {e:.1}) from r = 0.6 to r = 1.2:");
    println!(
        "  ∂K/∂h = t₁ − t₀ = {:.15} (Kepler's equation: {:.15}); θ₁ from ∂K/∂a = 0: {theta1:.15}",
        radial.dk_dh,
        mean(anomaly(1.2)) - mean(anomaly(0.6))
    );

    // --- Liouville system [Ardema 8.4]. ---
    let (h39, gam) = liouville_separated_integrals(
        &QuarticLiouville,
        &SVector::from([1.0, 0.5]),
        &SVector::from([0.2, -0.3]),
    )?;
    println!(
        "\nQuartic Liouville system: h = {h39}, γ = ({:.15}, {:.15}), Σγ = {:.1e}",
        gam[0],
        gam[1],
        gam.sum()
    );
    Ok(())
}
