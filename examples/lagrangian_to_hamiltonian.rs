//! From a Lagrangian to a Hamiltonian: the Legendre transform by Newton's method with the AD mass
//! matrix, the Jacobi integral of the bead on a rotating hoop [Ardema 8.2], and Routh's reduction.
//!
//! Run with `cargo run --release --example lagrangian_to_hamiltonian`.

use hamilton_jacobi::lagrangian::Routhian;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::BeadOnHoop;
use hamilton_jacobi::{DualNum, Hamiltonian, Lagrangian, Legendre, Result};

// ANCHOR: relativistic
/// Relativistic particle in a uniform magnetic field: L = −m√(1 − |v|²) + A(q)·v − |q|²/2.
struct Relativistic {
    m: f64,
    b: f64,
}
impl Lagrangian<2> for Relativistic {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let a = SVector::from([-q[1] * (0.5 * self.b), q[0] * (0.5 * self.b)]);
        (-(v.dot(v)) + 1.0).sqrt() * -self.m + a.dot(v) - q.dot(q) * 0.5
    }
}
// ANCHOR_END: relativistic

/// Two masses joined by a spring, L = ½m₁ẋ² + ½m₂(ẋ + ẏ)² − ½k(y − ℓ)²; x is ignorable.
struct TwoMasses;
impl Lagrangian<2> for TwoMasses {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let s = v[0] + v[1];
        v[0] * v[0] * 0.5 + s * s - (q[1] - 1.0) * (q[1] - 1.0) * 2.5
    }
}

fn main() -> Result<()> {
    let sys = Relativistic { m: 1.0, b: 0.8 };
    let h = Legendre(Relativistic { m: 1.0, b: 0.8 });
    let (q, v) = (SVector::from([0.3, -0.5]), SVector::from([0.6, 0.7]));
    let p = sys.momentum(0.0, &q, &v)?;
    println!("Relativistic particle: q̇ = {v:?} ↦ p = ∂L/∂q̇ = {p:?}");
    println!(
        "  H(q, p) = {:.15} by Newton; closed form √(m² + |p − A|²) + |q|²/2 = {:.15}",
        h.value(0.0, &q, &p)?,
        {
            let a = SVector::from([-q[1] * 0.4, q[0] * 0.4]);
            (1.0 + (p - a).norm_squared()).sqrt() + 0.5 * q.dot(&q)
        }
    );
    let (qdot, pdot) = h.vector_field(0.0, &q, &p)?;
    println!("  Hamilton's equations: q̇ = {qdot:?}, ṗ = {pdot:?}");

    let bead = BeadOnHoop::new(1.0, 0.5, 9.81, 6.0)?;
    let (th, v0) = (SVector::from([0.3]), SVector::from([0.0]));
    println!(
        "\nBead on a hoop (a = 0.5, ω = 6): Jacobi integral h = {:.11}",
        bead.jacobi_integral(0.0, &th, &v0)?
    );
    if let Some((theta, freq)) = bead.relative_equilibrium() {
        println!("  relative equilibrium θ* = {theta:.15}, small-oscillation frequency {freq:.14}");
    }

    let r: Routhian<_, 2, 1> = Routhian::new(TwoMasses, &[0], &[1.2])?;
    let (y, yd) = (SVector::from([1.0]), SVector::from([0.0]));
    let mass = r.mass_matrix(0.0, &y, &yd)?[(0, 0)];
    println!(
        "\nRouthian of two masses and a spring (C = 1.2): reduced mass {mass:.15} = m₁m₂/(m₁ + m₂)"
    );
    println!(
        "  ẋ recovered from C: {:?}",
        r.ignorable_velocities(0.0, &y, &yd)?
    );
    Ok(())
}
