//! The crate's side of the peer comparison (`benches/peers/`): one problem, every tolerance, the
//! Taylor method and DOP853, best wall time of several runs, the final state printed as JSON for
//! the script to score against its reference.
//!
//! ```text
//! cargo run --release --example peers_crate -- <problem> <runs> <tol,tol,…> <t1> <x0…>
//!   kepler   μ = 1, planar:   x0 = q₁ q₂ p₁ p₂
//!   j2 <J2>  μ = R = 1:       x0 = q₁ q₂ q₃ p₁ p₂ p₃
//!   pendulum n = 1:           x0 = q p
//! ```
//!
//! The Taylor method is timed without the recording of Hamilton's equations (printed apart as
//! `record_seconds`), as heyoka's timings leave out its compilation.

use hamilton_jacobi::hamiltonian::PerturbedKepler;
use hamilton_jacobi::integrate::{
    integrate, Dop853, Fixed, Problem, Taylor, VectorFieldRecord, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::{Kepler, Pendulum};
use hamilton_jacobi::{Error, Hamiltonian, Result};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Best wall time of `f` over `runs` runs, and its last result.
fn best<R>(runs: usize, mut f: impl FnMut() -> Result<R>) -> Result<(Duration, R)> {
    let mut t_best = Duration::MAX;
    let mut out = None;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let r = black_box(f()?);
        t_best = t_best.min(t.elapsed());
        out = Some(r);
    }
    Ok((t_best, out.expect("at least one run")))
}

/// One result as a JSON object.
fn json_line<const N: usize>(
    method: &str,
    knob: f64,
    steps: usize,
    time: Duration,
    record: f64,
    s: &State<N>,
) -> String {
    format!(
        "{{\"method\":\"{method}\",\"tol\":{knob:?},\"steps\":{steps},\"seconds\":{:?},\
         \"record_seconds\":{record:?},\"t\":{:?},\"x\":{}}}",
        time.as_secs_f64(),
        s.t,
        json_array(s.q.iter().chain(s.p.iter()).copied())
    )
}

/// The same problem by Wisdom–Holman splittings (Kepler drift, kicks by the perturbation) with
/// `n` equal steps per period, `t1` being 100 periods.
fn run_split<S: PerturbedKepler<N> + hamilton_jacobi::Separable<N>, const N: usize>(
    system: &S,
    x0: &[f64],
    t1: f64,
    runs: usize,
) -> Result<Vec<String>> {
    let q = SVector::<f64, N>::from_fn(|i, _| x0[i]);
    let p = SVector::<f64, N>::from_fn(|i, _| x0[N + i]);
    let problem = Problem::new(system, 0.0, q, p, t1)?;
    let mut lines = Vec::new();
    for (name, wh) in [("WH", WisdomHolman::WH), ("SABA2", WisdomHolman::SABA2)] {
        for n in [30usize, 100, 300, 1000, 3000] {
            let method = Fixed::new(wh, 100 * n)?;
            let (t, r) = best(runs, || integrate(&problem, &method, &mut ()))?;
            lines.push(json_line(
                &format!("crate Wisdom–Holman {name}"),
                1.0 / n as f64,
                r.work.steps,
                t,
                0.0,
                &r.last,
            ));
        }
    }
    Ok(lines)
}

/// A JSON array of numbers (shortest round-trip decimal form).
fn json_array(x: impl Iterator<Item = f64>) -> String {
    let v: Vec<String> = x.map(|v| format!("{v:?}")).collect();
    format!("[{}]", v.join(","))
}

fn run<S: Hamiltonian<N>, const N: usize>(
    system: &S,
    x0: &[f64],
    t1: f64,
    tols: &[f64],
    runs: usize,
) -> Result<Vec<String>> {
    if x0.len() != 2 * N {
        return Err(Error::invalid(
            "peers_crate",
            format!("{} initial values, {} expected", x0.len(), 2 * N),
        ));
    }
    let q = SVector::<f64, N>::from_fn(|i, _| x0[i]);
    let p = SVector::<f64, N>::from_fn(|i, _| x0[N + i]);
    let problem = Problem::new(system, 0.0, q, p, t1)?;
    let start = State::new(0.0, q, p)?;
    let (rec_time, field) = best(runs, || VectorFieldRecord::new(system, &start))?;
    let mut lines = Vec::new();
    let line = json_line::<N>;
    for &tol in tols {
        let taylor = Taylor::new(tol)?;
        let (tt, rt) = best(runs, || taylor.run_recorded(&field, &problem, &mut ()))?;
        lines.push(line(
            &format!("crate Taylor (order {})", taylor.order()),
            tol,
            rt.work.steps,
            tt,
            rec_time.as_secs_f64(),
            &rt.last,
        ));
        let dop = Dop853::new(tol, tol).and_then(|m| m.with_max_steps(10_000_000));
        match dop.and_then(|dop| best(runs, || integrate(&problem, &dop, &mut ()))) {
            Ok((td, rd)) => lines.push(line("crate DOP853", tol, rd.work.steps, td, 0.0, &rd.last)),
            Err(e) => eprintln!("DOP853 at tol {tol:e}: {e}"),
        }
    }
    Ok(lines)
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |s: &str| -> Result<f64> {
        s.parse::<f64>()
            .map_err(|_| Error::invalid("peers_crate", format!("not a number: {s}")))
    };
    let usage = || {
        Error::invalid(
            "peers_crate",
            "usage: peers_crate kepler|j2 <J2>|pendulum <runs> <tol,…> <t1> <x0…>",
        )
    };
    let (kind, rest) = args.split_first().ok_or_else(usage)?;
    let (j2, rest) = if kind == "j2" {
        let (v, r) = rest.split_first().ok_or_else(usage)?;
        (num(v)?, r)
    } else {
        (0.0, rest)
    };
    if rest.len() < 3 {
        return Err(usage());
    }
    let runs = num(&rest[0])? as usize;
    let tols = rest[1].split(',').map(num).collect::<Result<Vec<f64>>>()?;
    let t1 = num(&rest[2])?;
    let x0 = rest[3..]
        .iter()
        .map(|s| num(s))
        .collect::<Result<Vec<f64>>>()?;
    let lines = match kind.as_str() {
        "kepler" => {
            let sys = Kepler::<2>::new(1.0)?;
            let mut lines = run(&sys, &x0, t1, &tols, runs)?;
            lines.extend(run_split(&sys, &x0, t1, runs)?);
            lines
        }
        "j2" => {
            let sys = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, J2::new(1.0, j2, 1.0)?)?;
            let mut lines = run(&sys, &x0, t1, &tols, runs)?;
            lines.extend(run_split(&sys, &x0, t1, runs)?);
            lines
        }
        "pendulum" => run(&Pendulum::new(1.0)?, &x0, t1, &tols, runs)?,
        _ => return Err(usage()),
    };
    println!("[{}]", lines.join(",\n"));
    Ok(())
}
