//! Canonical transformations, end to end: generating functions of the four kinds, the transformed
//! Hamiltonian, singular generators, point transformations, composition and inversion,
//! infinitesimal transformations and Lie series, and certification of every map by AD.
//!
//! Run with `cargo run --release --example canonical_transformations`.

use hamilton_jacobi::brackets::{certify, exactness_defect, PhaseMap};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{AngularMomentum, ExactFlow, HarmonicOscillator, Kepler2};
use hamilton_jacobi::transform::lie::{lie_flow, symmetry_defect, Ict, LieSeries};
use hamilton_jacobi::transform::point::{point_transformation, Polar};
use hamilton_jacobi::transform::{
    CanonicalTransformation, Compose, GeneratingFunction, Inverse, Kind,
};
use hamilton_jacobi::{DualNum, Hamiltonian, Result};

// ANCHOR: generator
/// The oscillator's angle variables: F₁(q, Q) = ½ m ω q² cot Q [Ardema 16.5].
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
}
// ANCHOR_END: generator

/// Free fall: F₁(q, Q, t) = (q − Q)²/(2t) − ½ g t (q + Q) − g² t³/24 [Ardema 16.4].
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

/// Q = ln(sin p / q), P = q cot p [Ardema Prob. 16/2].
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

fn main() -> Result<()> {
    println!("1. Generating function F₁ = ½mωq² cot Q (m = 2, ω = 3)");
    // ANCHOR: forward
    let ct = CanonicalTransformation::new(AngleVariables { m: 2.0, omega: 3.0 });
    let (q, p) = (SVector::from([0.5]), SVector::from([1.2]));
    let (big_q, big_p) = ct.forward(0.0, &q, &p)?;
    let osc = HarmonicOscillator::new(2.0, 3.0)?;
    let k = ct.transform(&osc); // K(Q, P) = H + ∂F/∂t, a Hamiltonian in the new variables
    let (qdot, pdot) = k.vector_field(0.0, &big_q, &big_p)?;
    // ANCHOR_END: forward
    println!(
        "   (q, p) = (0.5, 1.2) ↦ (Q, P) = ({:.14}, {:.14})",
        big_q[0], big_p[0]
    );
    println!(
        "   K(Q, P) = {:.14} = ωP;  Q̇ = {:.14}, Ṗ = {:.1e}",
        k.value(0.0, &big_q, &big_p)?,
        qdot[0],
        pdot[0]
    );
    let c = ct.certify(0.0, &q, &p)?;
    println!(
        "   certificate: ‖MᵀJM − J‖ = {:.1e}, det M − 1 = {:.1e}",
        c.symplectic_defect, c.det_minus_one
    );

    println!("\n2. Free fall with its time-dependent F₁: K = H + ∂F₁/∂t ≡ 0");
    let ff = CanonicalTransformation::new(FreeFall { g: 9.81 });
    for t in [0.5, 2.0] {
        let (bq, bp) = ff.forward(t, &SVector::from([1.0]), &SVector::from([0.5]))?;
        println!(
            "   state (1, 0.5) at t = {t} came from (Q, P) = ({:.12}, {:.12})",
            bq[0], bp[0]
        );
    }

    println!("\n3. Singular generators are refused, with the point and the conditioning");
    for t in [1e-3, 1e-9] {
        match ff.forward(t, &SVector::from([1.0]), &SVector::from([0.5])) {
            Ok((bq, bp)) => println!("   t = {t:e}: (Q, P) = ({:.9}, {:.9})", bq[0], bp[0]),
            Err(e) => println!("   t = {t:e}: {e}"),
        }
    }

    println!(
        "\n4. Point transformation to polar coordinates [Ardema 16.3], and Kepler's K in them"
    );
    let polar = point_transformation(Polar);
    let (q2, p2) = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    let (bq, bp) = polar.forward(0.0, &q2, &p2)?;
    println!("   (x, y, p_x, p_y) = (1, 0.5, 0.3, −0.7) ↦ (r, θ, P_r, P_θ) = ({:.12}, {:.12}, {:.12}, {:.12})", bq[0], bq[1], bp[0], bp[1]);
    let kep = Kepler2::new(1.0)?;
    println!(
        "   K = {:.15}  (H = {:.15})",
        polar.transform(&kep).value(0.0, &bq, &bp)?,
        kep.value(0.0, &q2, &p2)?
    );

    println!("\n5. Composition and inversion; the three tests of canonicity");
    let id = Compose(Prob16_2, Inverse::new(Prob16_2));
    let (q1, p1) = id.apply(0.0, &SVector::from([0.7]), &SVector::from([1.1]));
    println!(
        "   (16/2)⁻¹ ∘ (16/2) at (0.7, 1.1) = ({:.15}, {:.15})",
        q1[0], p1[0]
    );
    let (qa, pa) = (SVector::from([0.7]), SVector::from([1.1]));
    let c = certify(&Prob16_2, 0.0, &qa, &pa)?;
    println!(
        "   16/2: definition (dθ = 0) defect {:.1e}, Liouville det − 1 = {:.1e}, (Q, P) − 1 = {:.1e}",
        exactness_defect(&Prob16_2, 0.0, &qa, &pa)?,
        c.det_minus_one,
        c.poisson.qp[(0, 0)] - 1.0
    );

    println!("\n6. Infinitesimal transformations and Lie series");
    let kep = Kepler2::new(1.0)?;
    let (q, p) = (SVector::from([1.0, 0.2]), SVector::from([0.1, 0.9]));
    println!(
        "   ∂h_z/∂t + (h_z, H) = {:.1e}: rotations leave Kepler's H invariant (Noether)",
        symmetry_defect(&AngularMomentum::z(), &kep, 0.0, &q, &p)?
    );
    let (bq, _) = Ict::new(AngularMomentum::z(), 1e-3)?.transform(0.0, &q, &p)?;
    println!(
        "   ICT ε = 1e−3 generated by h_z: δq = {:?}",
        (bq - q).as_slice()
    );
    for order in [2, 4, 8] {
        let (bq, _, est) =
            LieSeries::new(AngularMomentum::z(), 0.5, order)?.apply_with_error(0.0, &q, &p)?;
        let exact = SVector::from([
            q[0] * 0.5f64.cos() - q[1] * 0.5f64.sin(),
            q[0] * 0.5f64.sin() + q[1] * 0.5f64.cos(),
        ]);
        println!(
            "   exp(ε L_h_z), ε = 0.5, order {order}: error {:.1e}, estimate {est:.1e}",
            (bq - exact).norm()
        );
    }
    let osc1 = HarmonicOscillator::new(1.0, 1.0)?;
    let (q1, p1) = (SVector::from([1.0]), SVector::from([0.0]));
    let (ql, _) = lie_flow(osc1, 0.1, 8)?.transform(0.0, &q1, &p1)?;
    let (qe, _) = osc1.exact_flow(0.0, &q1, &p1, 0.1)?;
    println!(
        "   flow of H as the Lie series of H (Δt = 0.1, order 8): q error {:.1e}",
        (ql[0] - qe[0]).abs()
    );
    Ok(())
}
