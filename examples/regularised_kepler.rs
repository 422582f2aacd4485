//! Kepler e = 0.99 over 100 periods, three ways, against the exact flow: DOP853 in Cartesian
//! coordinates, DOP853 on the Levi-Civita regularised problem (`dt = r ds`), and the
//! logarithmic-Hamiltonian Kahan–Li composition (Mikkola–Tanikawa time transformation).
//!
//! Run with `cargo run --release --example regularised_kepler`.

use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate};
use hamilton_jacobi::integrate::{
    integrate, Dop853, LeviCivita, Problem, Splitting, TimeTransformed,
};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::{ExactFlow, Kepler2};
use std::f64::consts::TAU;

fn main() -> hamilton_jacobi::Result<()> {
    let e = 0.99f64;
    let kepler = Kepler2::new(1.0)?;
    let start = State::from_arrays(0.0, [1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()])?;
    let t1 = 100.0 * TAU;
    let (qe, pe) = kepler.exact_flow(0.0, &start.q, &start.p, t1)?;
    let error = |s: &State<2>| (s.q - qe).amax().max((s.p - pe).amax());
    let problem = Problem::new(&kepler, 0.0, start.q, start.p, t1)?;
    let lc = LeviCivita::new(&kepler)?;
    let span = fictitious_span(&lc, &start, t1)?;
    println!("Kepler e = {e}, 100 periods: final error against the exact flow");
    for tol in [1e-8, 1e-10, 1e-12, 1e-13] {
        let dop = Dop853::new(tol, tol)?;
        let cart = integrate(&problem, &dop, &mut ())?;
        let reg = propagate(&lc, &dop, &start, &[t1], span)?;
        println!(
            "  DOP853 tol {tol:.0e}: Cartesian {:.2e} ({:>7} gradients, {:>9.2?}); \
             Levi-Civita {:.2e} ({:>6} gradients, {:>9.2?})",
            error(&cart.last),
            cart.work.gradients,
            cart.elapsed,
            error(&reg.states[0]),
            reg.work.gradients,
            reg.elapsed
        );
    }
    for ds in [0.2, 0.1, 0.05] {
        let m = TimeTransformed::logarithmic(Splitting::KAHAN_LI17, ds)?;
        let run = integrate(&problem, &m, &mut ())?;
        println!(
            "  logarithmic Hamiltonian, Kahan–Li 17, ds = {ds}: {:.2e} ({:>6} gradients, {:>9.2?})",
            error(&run.last),
            run.work.gradients,
            run.elapsed
        );
    }
    Ok(())
}
