//! Rounding floors of the regularised and time-transformed schemes on the two hard problems of
//! the peer comparison (issue 18): Kepler e = 0.99 (planar, μ = 1, from periapsis) and
//! Kepler + J₂ = 1e−3, e = 0.7 (a = 2, i = 0.5, R = 1), both over 100 periods.
//!
//! For each scheme at a tight knob:
//! * (a) the spread of the final states when each input (q, p) is moved by 1 ulp up and down:
//!   the largest max-norm distance to the final state of the unmoved start;
//! * (b) the energy: the regularisations form `p_t = −H` in double-double and round it once; the
//!   same run with `p_t` formed in plain double shows what that buys (the distance between the
//!   two final states). The Taylor method and DOP853 have no compensated-summation option; the
//!   logarithmic-Hamiltonian splitting always sums compensated (Kahan).
//!
//! Kepler errors are against the exact flow of the double start (`ExactFlow`); J₂ has no closed
//! form here (the peer script scores it against heyoka in quadruple precision).
//!
//! Run with `cargo run --release --example regularised_floors`.

use hamilton_jacobi::hamiltonian::PerturbedKepler;
use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate};
use hamilton_jacobi::integrate::{
    integrate, Dop853, KustaanheimoStiefel, LeviCivita, Method, Problem, Regularisation, Splitting,
    Taylor, TimeTransformed,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::num_dual::DualNum;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::{ExactFlow, Kepler2};
use hamilton_jacobi::{Hamiltonian, Result};
use std::f64::consts::TAU;

/// A regularisation whose initial `p_t = −H` is formed in plain double (for comparison with the
/// double-double one of the crate's maps).
struct PlainEnergy<'a, R, S> {
    reg: R,
    system: &'a S,
}

impl<R: Hamiltonian<M>, S, const M: usize> Hamiltonian<M> for PlainEnergy<'_, R, S> {
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, s: D, q: &SVector<D, M>, p: &SVector<D, M>) -> D {
        self.reg.hamiltonian(s, q, p)
    }
}

impl<R, S, const N: usize, const M: usize> Regularisation<N, M> for PlainEnergy<'_, R, S>
where
    R: Regularisation<N, M>,
    S: PerturbedKepler<N> + Hamiltonian<N>,
{
    fn to_regular(&self, x: &State<N>) -> Result<State<M>> {
        let mut y = self.reg.to_regular(x)?;
        y.p[M - 1] = -self.system.value(x.t, &x.q, &x.p)?;
        Ok(y)
    }

    fn to_physical(&self, y: &State<M>) -> Result<State<N>> {
        self.reg.to_physical(y)
    }

    fn bilinear(&self, y: &State<M>) -> f64 {
        self.reg.bilinear(y)
    }

    fn mu(&self) -> f64 {
        self.reg.mu()
    }
}

fn distance<const N: usize>(a: &State<N>, b: &State<N>) -> f64 {
    (a.q - b.q).amax().max((a.p - b.p).amax())
}

/// Starts moved by one ulp in each component, up and down.
fn ulp_neighbours<const N: usize>(s: &State<N>) -> Vec<State<N>> {
    let mut out = Vec::new();
    for i in 0..2 * N {
        for up in [true, false] {
            let mut x = *s;
            let v = if i < N { &mut x.q[i] } else { &mut x.p[i - N] };
            *v = if up { v.next_up() } else { v.next_down() };
            out.push(x);
        }
    }
    out
}

/// The final state of `run` from `start` and the 1-ulp spread of its final states.
fn floor<const N: usize>(
    start: &State<N>,
    run: impl Fn(&State<N>) -> Result<State<N>>,
) -> Result<(State<N>, f64)> {
    let x = run(start)?;
    let mut spread = 0.0f64;
    for s in ulp_neighbours(start) {
        spread = spread.max(distance(&run(&s)?, &x));
    }
    Ok((x, spread))
}

/// Regularised run of `method` from `start` to `t1`, the physical state at `t1`.
fn regularised<R, Me, const N: usize, const M: usize>(
    reg: &R,
    method: &Me,
    start: &State<N>,
    t1: f64,
) -> Result<State<N>>
where
    R: Regularisation<N, M>,
    Me: Method<R, M>,
{
    let span = fictitious_span(reg, start, t1)?;
    Ok(propagate(reg, method, start, &[t1], span)?.states[0])
}

fn report<const N: usize>(name: &str, x: &State<N>, spread: f64, exact: Option<&State<N>>) {
    let err = exact.map_or(String::from("—"), |e| format!("{:.2e}", distance(x, e)));
    println!(
        "  {name:<44} error {err:>9}  1-ulp spread {spread:.2e}  max(1e-12, 3 × spread) {:.2e}",
        (3.0 * spread).max(1e-12)
    );
}

fn main() -> Result<()> {
    // Kepler e = 0.99.
    let e = 0.99f64;
    let kepler = Kepler2::new(1.0)?;
    let start = State::from_arrays(0.0, [1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()])?;
    let t1 = 100.0 * TAU;
    let exact = |s: &State<2>| -> Result<State<2>> {
        let (q, p) = kepler.exact_flow(s.t, &s.q, &s.p, t1)?;
        State::new(t1, q, p)
    };
    println!("Kepler e = {e}, 100 periods (errors against the exact flow of the double start)");
    let (xe, spread) = floor(&start, exact)?;
    report(
        "exact flow (the problem's own conditioning)",
        &xe,
        spread,
        None,
    );
    let lc = LeviCivita::new(&kepler)?;
    let plain = PlainEnergy {
        reg: lc,
        system: &kepler,
    };
    for tol in [1e-13, 1e-15] {
        let taylor = Taylor::new(tol)?.with_max_steps(10_000_000)?;
        let (x, s) = floor(&start, |s| regularised(&lc, &taylor, s, t1))?;
        report(&format!("Levi-Civita Taylor tol {tol:e}"), &x, s, Some(&xe));
        let xp = regularised(&plain, &taylor, &start, t1)?;
        println!(
            "    p_t in plain double instead of double-double: error {:.2e}, moves the end by \
             {:.2e}",
            distance(&xp, &xe),
            distance(&xp, &x)
        );
    }
    let dop = Dop853::new(1e-13, 1e-13)?.with_max_steps(10_000_000)?;
    let (x, s) = floor(&start, |s| regularised(&lc, &dop, s, t1))?;
    report("Levi-Civita DOP853 tol 1e-13", &x, s, Some(&xe));
    let log_h = TimeTransformed::logarithmic(Splitting::KAHAN_LI17, 0.05)?;
    let (x, s) = floor(&start, |s| {
        let pb = Problem::new(&kepler, s.t, s.q, s.p, t1)?;
        Ok(integrate(&pb, &log_h, &mut ())?.last)
    })?;
    report("log-H Kahan–Li 17 ds 0.05", &x, s, Some(&xe));

    // Kepler + J2 = 1e-3, e = 0.7.
    let model = J2::new(1.0, 1e-3, 1.0)?;
    let sys = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, model)?;
    let (a, e, inc) = (2.0f64, 0.7, 0.5f64);
    let r = a * (1.0 - e);
    let v = ((1.0 + e) / r).sqrt();
    let start = State::from_arrays(0.0, [r, 0.0, 0.0], [0.0, v * inc.cos(), v * inc.sin()])?;
    let t1 = 100.0 * TAU * a.powf(1.5);
    println!("Kepler + J2 = 1e-3, e = {e}, 100 periods");
    let ks = KustaanheimoStiefel::new(&sys)?;
    let plain = PlainEnergy {
        reg: ks,
        system: &sys,
    };
    let mut tightest = None;
    for tol in [1e-13, 1e-15] {
        let taylor = Taylor::new(tol)?.with_max_steps(10_000_000)?;
        let (x, s) = floor(&start, |s| regularised(&ks, &taylor, s, t1))?;
        report(
            &format!("Kustaanheimo–Stiefel Taylor tol {tol:e}"),
            &x,
            s,
            None,
        );
        let xp = regularised(&plain, &taylor, &start, t1)?;
        println!(
            "    p_t in plain double instead of double-double: moves the end by {:.2e}",
            distance(&xp, &x)
        );
        tightest = Some(x);
    }
    for tol in [1e-13, 3e-15] {
        let dop = Dop853::new(tol, tol)?.with_max_steps(10_000_000)?;
        let (x, s) = floor(&start, |s| regularised(&ks, &dop, s, t1))?;
        report(
            &format!("Kustaanheimo–Stiefel DOP853 tol {tol:e}"),
            &x,
            s,
            None,
        );
        if let Some(xt) = tightest {
            println!(
                "    distance to KS Taylor 1e-15: {:.2e} (its final state {:?} {:?})",
                distance(&x, &xt),
                xt.q.as_slice(),
                xt.p.as_slice()
            );
        }
    }
    Ok(())
}
