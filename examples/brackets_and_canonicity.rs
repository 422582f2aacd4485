//! Poisson brackets of integrals and canonicity certificates of maps, all by AD.
//!
//! Run with `cargo run --release --example brackets_and_canonicity`.

use hamilton_jacobi::brackets::{certify, poisson_bracket, PhaseMap, PoissonBracket};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{AngularMomentum, Kepler3};
use hamilton_jacobi::{DualNum, PhaseFunction, Result};

// ANCHOR: map
/// [Ardema Prob. 16/3]: Q = q^α cos βp, P = q^α sin βp — canonical only for α = ½, β = 2.
struct PowerMap {
    alpha: f64,
    beta: f64,
}
impl PhaseMap<1> for PowerMap {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let qa = q[0].powf(self.alpha);
        let (s, c) = (p[0] * self.beta).sin_cos();
        (SVector::from([qa * c]), SVector::from([qa * s]))
    }
}
// ANCHOR_END: map

fn main() -> Result<()> {
    let kepler = Kepler3::new(1.0)?;
    let (q, p) = (
        SVector::from([1.0, 0.2, -0.3]),
        SVector::from([0.1, 0.9, 0.4]),
    );
    println!("Kepler problem at q = {q:?}, p = {p:?}");
    for k in 0..3 {
        let hk_h = poisson_bracket(&AngularMomentum::new(k)?, &kepler, 0.0, &q, &p)?;
        println!("  (h_{k}, H) = {hk_h:e}");
    }
    let hxy = poisson_bracket(
        &AngularMomentum::new(0)?,
        &AngularMomentum::new(1)?,
        0.0,
        &q,
        &p,
    )?;
    let hz = AngularMomentum::new(2)?.eval(0.0, &q, &p);
    println!("  (h_x, h_y) = {hxy}, h_z = {hz}");
    let poisson_theorem = poisson_bracket(
        &PoissonBracket(AngularMomentum::new(0)?, AngularMomentum::new(1)?),
        &kepler,
        0.0,
        &q,
        &p,
    )?;
    println!("  ((h_x, h_y), H) = {poisson_theorem:e}   (Poisson's theorem)");

    println!("\nCanonicity of Q = q^α cos βp, P = q^α sin βp at (q, p) = (0.7, 1.1):");
    for (alpha, beta) in [(0.5, 2.0), (0.5, 1.0), (1.0, 2.0)] {
        let c = certify(
            &PowerMap { alpha, beta },
            0.0,
            &SVector::from([0.7]),
            &SVector::from([1.1]),
        )?;
        println!(
            "  α = {alpha}, β = {beta}: (Q, P) = {:.6}, ‖MᵀJM − J‖ = {:.2e}, det M − 1 = {:.2e}, canonical: {}",
            c.poisson.qp[(0, 0)],
            c.symplectic_defect,
            c.det_minus_one,
            c.is_canonical(1e-12)
        );
    }
    Ok(())
}
