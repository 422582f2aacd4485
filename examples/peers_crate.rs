//! The crate's side of the peer comparison (`benches/peers/`): one problem, every tolerance, the
//! Taylor method and DOP853, best wall time of several runs, the final state printed as JSON for
//! the script to score against its reference.
//!
//! ```text
//! cargo run --release --example peers_crate -- <problem> <runs> <tol,tol,…> <t1> <x0…>
//!   kepler   μ = 1, planar:   x0 = q₁ q₂ p₁ p₂
//!   j2 <J2>  μ = R = 1:       x0 = q₁ q₂ q₃ p₁ p₂ p₃
//!   pendulum n = 1:           x0 = q p
//! cargo run --release --example peers_crate -- nbody state
//! cargo run --release --example peers_crate -- nbody <runs> <h,h,…> <span> <outputs> <method,…>
//!   the outer Solar System (`systems::outer_solar_system`, G in AU³/(M☉ day²), days):
//!   `state` prints G, the masses and the initial inertial x, v = p/m and p; otherwise the
//!   N-body Wisdom–Holman map, method `jacobi` (kick–drift–kick, `WisdomHolman::WH`),
//!   `jacobi-dkd` (drift–kick–drift, `SABA1`), `jacobi17` (order-17 corrector) or `dh`
//!   (democratic heliocentric, kick–drift–kick), with steps h over `outputs` equal chunks of
//!   round(span / (outputs·h)) steps, the corrector applied at each output; printed: the largest
//!   relative energy error at the outputs, the final one, and the final state.
//! ```
//!
//! The Taylor method is timed without the recording of Hamilton's equations (printed apart as
//! `record_seconds`), as heyoka's timings leave out its compilation. The pendulum also runs the
//! Taylor method in double-double arithmetic (`Taylor::double_double`) at tolerances down to
//! `10⁻²²`, for the problem near the separatrix.
//!
//! Kepler and J2 also run regularised: Levi-Civita (planar Kepler) and Kustaanheimo–Stiefel
//! (spatial J2) in the fictitious time `s` (`dt = r ds`) by the Taylor method (its record of the
//! regularised equations timed apart) and by DOP853, the state at `t₁` found on `t(s)` by the
//! Illinois iteration (`integrate::regularised::propagate`); and the logarithmic-Hamiltonian
//! (Mikkola–Tanikawa) time transformation of the Kahan–Li order-8 composition over a sweep of
//! fictitious-time steps `ds` (the knob printed as `tol`).

use hamilton_jacobi::hamiltonian::PerturbedKepler;
use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate};
use hamilton_jacobi::integrate::{
    integrate, Dop853, Fixed, KustaanheimoStiefel, LeviCivita, Method, Observer,
    PlanetaryWisdomHolman, Problem, Regularisation, Report, Splitting, Taylor, TimeTransformed,
    VectorFieldRecord, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::record::Jets;
use hamilton_jacobi::systems::{outer_solar_system, Kepler, Pendulum, PlanetaryCoordinates};
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

/// `(q, p)` from the command line's `x0 = q₁ … q_N p₁ … p_N`.
fn phase_point<const N: usize>(x0: &[f64]) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
    if x0.len() != 2 * N {
        return Err(Error::invalid(
            "peers_crate",
            format!("{} initial values, {} expected", x0.len(), 2 * N),
        ));
    }
    Ok((
        SVector::from_fn(|i, _| x0[i]),
        SVector::from_fn(|i, _| x0[N + i]),
    ))
}

/// The same problem by Wisdom–Holman splittings (Kepler drift, kicks by the perturbation) with
/// `n` equal steps per period, `t1` being 100 periods.
fn run_split<S: PerturbedKepler<N> + hamilton_jacobi::Separable<N>, const N: usize>(
    system: &S,
    x0: &[f64],
    t1: f64,
    runs: usize,
) -> Result<Vec<String>> {
    let (q, p) = phase_point::<N>(x0)?;
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

/// The Taylor method on an already recorded vector field, as a [`Method`] for `propagate`.
struct Prerecorded<'a, const M: usize> {
    taylor: Taylor,
    field: &'a VectorFieldRecord<M>,
}

impl<S, const M: usize> Method<S, M> for Prerecorded<'_, M> {
    fn label(&self) -> String {
        "Taylor (recorded)".into()
    }

    fn run<O: Observer<M>>(
        &self,
        problem: &Problem<'_, S, M>,
        observer: &mut O,
    ) -> Result<Report<M>> {
        self.taylor.run_recorded(self.field, problem, observer)
    }
}

/// The problem regularised by `reg` (named `name`), in `s` by the Taylor method and DOP853 at
/// every tolerance, the physical state at exactly `t1`.
fn run_regularised<R: Regularisation<N, M>, const N: usize, const M: usize>(
    reg: &R,
    name: &str,
    x0: &[f64],
    t1: f64,
    tols: &[f64],
    runs: usize,
) -> Result<Vec<String>> {
    let (q, p) = phase_point::<N>(x0)?;
    let start = State::new(0.0, q, p)?;
    let span = fictitious_span(reg, &start, t1)?;
    let y0 = reg.to_regular(&start)?;
    let (rec_time, field) = best(runs, || VectorFieldRecord::new(reg, &y0))?;
    let mut lines = Vec::new();
    for &tol in tols {
        let taylor = Taylor::new(tol)?.with_max_steps(10_000_000)?;
        let method = Prerecorded {
            taylor,
            field: &field,
        };
        match best(runs, || propagate(reg, &method, &start, &[t1], span)) {
            Ok((t, r)) => lines.push(json_line(
                &format!("crate {name} Taylor (order {})", taylor.order()),
                tol,
                r.work.steps,
                t,
                rec_time.as_secs_f64(),
                &r.states[0],
            )),
            Err(e) => eprintln!("{name} Taylor at tol {tol:e}: {e}"),
        }
        lines.extend(regularised_dop853(reg, name, &start, t1, span, tol, runs));
    }
    // DOP853 in `s` keeps gaining below 1e−14 (on J₂ e = 0.7 it reaches 2e−12 at 3e−15): two
    // tolerances between 1e−14 and its smallest, 10u.
    for tol in [5e-15, 3e-15] {
        lines.extend(regularised_dop853(reg, name, &start, t1, span, tol, runs));
    }
    Ok(lines)
}

/// DOP853 on the regularised problem at `tol` (a line, or nothing with the reason on stderr).
fn regularised_dop853<R: Regularisation<N, M>, const N: usize, const M: usize>(
    reg: &R,
    name: &str,
    start: &State<N>,
    t1: f64,
    span: f64,
    tol: f64,
    runs: usize,
) -> Option<String> {
    let dop = Dop853::new(tol, tol)
        .and_then(|m| m.with_max_steps(10_000_000))
        .map(|m| m.with_compensated_summation(true));
    match dop.and_then(|dop| best(runs, || propagate(reg, &dop, start, &[t1], span))) {
        Ok((t, r)) => Some(json_line(
            &format!("crate {name} DOP853"),
            tol,
            r.work.steps,
            t,
            0.0,
            &r.states[0],
        )),
        Err(e) => {
            eprintln!("{name} DOP853 at tol {tol:e}: {e}");
            None
        }
    }
}

/// The logarithmic-Hamiltonian time transformation (Mikkola–Tanikawa) of the Kahan–Li order-8
/// composition over a sweep of fictitious-time steps `ds` (printed as the knob).
fn run_log_h<S: hamilton_jacobi::Separable<N>, const N: usize>(
    system: &S,
    x0: &[f64],
    t1: f64,
    runs: usize,
) -> Result<Vec<String>> {
    let (q, p) = phase_point::<N>(x0)?;
    let problem = Problem::new(system, 0.0, q, p, t1)?;
    let mut lines = Vec::new();
    for ds in [0.4, 0.2, 0.1, 0.05, 0.025] {
        let method = TimeTransformed::logarithmic(Splitting::KAHAN_LI17, ds)?;
        match best(runs, || integrate(&problem, &method, &mut ())) {
            Ok((t, r)) => lines.push(json_line(
                "crate log-H Kahan–Li 17",
                ds,
                r.work.steps,
                t,
                0.0,
                &r.last,
            )),
            Err(e) => eprintln!("log-H Kahan–Li 17 at ds {ds}: {e}"),
        }
    }
    Ok(lines)
}

/// A JSON array of numbers (shortest round-trip decimal form).
fn json_array(x: impl Iterator<Item = f64>) -> String {
    let v: Vec<String> = x.map(|v| format!("{v:?}")).collect();
    format!("[{}]", v.join(","))
}

/// The Taylor method and DOP853 at each of `tols`, and the Taylor method in double-double
/// arithmetic at each of `double_double_tols`, on the problem `system`, `x0`, `t1`.
fn run<S: Hamiltonian<N>, const N: usize>(
    system: &S,
    x0: &[f64],
    t1: f64,
    tols: &[f64],
    double_double_tols: &[f64],
    runs: usize,
) -> Result<Vec<String>> {
    let (q, p) = phase_point::<N>(x0)?;
    let problem = Problem::new(system, 0.0, q, p, t1)?;
    let start = State::new(0.0, q, p)?;
    let (rec_time, field) = best(runs, || VectorFieldRecord::new(system, &start))?;
    let mut lines = Vec::new();
    let line = json_line::<N>;
    for &tol in tols {
        let taylor = Taylor::new(tol)?;
        // The pass of this order compiled (once per record and order, kept with the record)
        // before the timed runs, its time reported apart.
        let jets = Jets::new(field.record(), taylor.order())?;
        if let Some(compile) = jets.compile_time() {
            eprintln!(
                "Taylor order {}: pass compiled in {:.1} ms",
                taylor.order(),
                compile.as_secs_f64() * 1e3
            );
        }
        let (tt, rt) = best(runs, || taylor.run_recorded(&field, &problem, &mut ()))?;
        lines.push(line(
            &format!("crate Taylor (order {})", taylor.order()),
            tol,
            rt.work.steps,
            tt,
            rec_time.as_secs_f64(),
            &rt.last,
        ));
        let dop = Dop853::new(tol, tol)
            .and_then(|m| m.with_max_steps(10_000_000))
            .map(|m| m.with_compensated_summation(true));
        match dop.and_then(|dop| best(runs, || integrate(&problem, &dop, &mut ()))) {
            Ok((td, rd)) => lines.push(line("crate DOP853", tol, rd.work.steps, td, 0.0, &rd.last)),
            Err(e) => eprintln!("DOP853 at tol {tol:e}: {e}"),
        }
    }
    // The Taylor method in double-double arithmetic (`Taylor::double_double`) on the same
    // recorded field, timed without the recording (printed apart, as for the double one).
    for &tol in double_double_tols {
        let taylor = Taylor::new(tol)?.double_double();
        match best(runs, || taylor.run_recorded(&field, &problem, &mut ())) {
            Ok((t, r)) => lines.push(line(
                &format!("crate Taylor double-double (order {})", taylor.order()),
                tol,
                r.work.steps,
                t,
                rec_time.as_secs_f64(),
                &r.last,
            )),
            Err(e) => eprintln!("Taylor double-double at tol {tol:e}: {e}"),
        }
    }
    Ok(lines)
}

/// The tolerances of the double-double Taylor method on the pendulum: beyond those of the
/// double methods, down to where its energy is held to about `10⁻¹⁸` (the separatrix problem).
const DOUBLE_DOUBLE_TOLS: [f64; 6] = [1e-9, 1e-12, 1e-15, 1e-18, 1e-20, 1e-22];

/// The outer Solar System's initial state as JSON: `G`, the masses, and the inertial positions,
/// velocities `v = p/m` and momenta `p`, body by body.
fn nbody_state() -> String {
    let (sys, q, p) = outer_solar_system();
    let m = sys.masses();
    let rows = |f: &dyn Fn(usize) -> f64| {
        let v: Vec<String> = (0..m.len())
            .map(|i| json_array((0..3).map(|k| f(3 * i + k))))
            .collect();
        format!("[{}]", v.join(","))
    };
    format!(
        "{{\"G\":{:?},\"masses\":{},\"x\":{},\"v\":{},\"p\":{}}}",
        sys.g(),
        json_array(m.iter().copied()),
        rows(&|k| q[k]),
        rows(&|k| p[k] / m[k / 3]),
        rows(&|k| p[k])
    )
}

/// The outer Solar System by the N-body Wisdom–Holman map: for each method and step `h`,
/// `outputs` chunks of `round(span / (outputs h))` steps (a `propagate` each: the corrector and the
/// coordinate maps at every output), the relative energy error at each output; best wall time of
/// `runs` runs, energy evaluations included.
fn run_nbody(
    runs: usize,
    hs: &[f64],
    span: f64,
    outputs: usize,
    methods: &[&str],
) -> Result<Vec<String>> {
    let (sys, q0, p0) = outer_solar_system();
    let h0 = sys.value(0.0, &q0, &p0)?;
    let mut lines = Vec::new();
    for name in methods {
        let (wh, coordinates) = match *name {
            "jacobi" => (WisdomHolman::WH, PlanetaryCoordinates::Jacobi),
            "jacobi-dkd" => (WisdomHolman::SABA1, PlanetaryCoordinates::Jacobi),
            "jacobi17" => (
                WisdomHolman::WH.with_corrector(17)?,
                PlanetaryCoordinates::Jacobi,
            ),
            "dh" => (
                WisdomHolman::WH,
                PlanetaryCoordinates::DemocraticHeliocentric,
            ),
            _ => {
                return Err(Error::invalid(
                    "peers_crate nbody",
                    format!("unknown method {name}"),
                ))
            }
        };
        let m = PlanetaryWisdomHolman::new(wh, coordinates)?;
        for &h in hs {
            let chunk = (span / (outputs as f64 * h)).round().max(1.0) as usize;
            let (time, (worst, last, flows, gradients)) = best(runs, || {
                let (mut q, mut p, mut worst) = (q0, p0, 0.0f64);
                let (mut flows, mut gradients) = (0, 0);
                for k in 0..outputs {
                    let (ta, tb) = ((k * chunk) as f64 * h, ((k + 1) * chunk) as f64 * h);
                    let r = m.propagate(&Problem::new(&sys, ta, q, p, tb)?, chunk)?;
                    (q, p) = (r.last.q, r.last.p);
                    flows += r.work.flows;
                    gradients += r.work.gradients;
                    worst = worst.max(((sys.value(tb, &q, &p)? - h0) / h0).abs());
                }
                Ok((worst, (q, p), flows, gradients))
            })?;
            let t1 = (outputs * chunk) as f64 * h;
            let fin = ((sys.value(t1, &last.0, &last.1)? - h0) / h0).abs();
            lines.push(format!(
                "{{\"method\":\"{name}\",\"h\":{h:?},\"steps\":{},\"outputs\":{outputs},\
                 \"t1\":{t1:?},\"seconds\":{:?},\"max_energy\":{worst:?},\
                 \"final_energy\":{fin:?},\"flows\":{flows},\"gradients\":{gradients},\
                 \"x\":{},\"p\":{}}}",
                outputs * chunk,
                time.as_secs_f64(),
                json_array(last.0.iter().copied()),
                json_array(last.1.iter().copied())
            ));
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
            "usage: peers_crate kepler|j2 <J2>|pendulum <runs> <tol,…> <t1> <x0…>, or \
             peers_crate nbody state | <runs> <h,…> <span> <outputs> <method,…>",
        )
    };
    let (kind, rest) = args.split_first().ok_or_else(usage)?;
    if kind == "nbody" {
        if rest.first().map(String::as_str) == Some("state") {
            println!("{}", nbody_state());
            return Ok(());
        }
        if rest.len() != 5 {
            return Err(usage());
        }
        let hs = rest[1].split(',').map(num).collect::<Result<Vec<f64>>>()?;
        let methods: Vec<&str> = rest[4].split(',').collect();
        let lines = run_nbody(
            num(&rest[0])? as usize,
            &hs,
            num(&rest[2])?,
            num(&rest[3])? as usize,
            &methods,
        )?;
        println!("[{}]", lines.join(",\n"));
        return Ok(());
    }
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
            let mut lines = run(&sys, &x0, t1, &tols, &[], runs)?;
            lines.extend(run_split(&sys, &x0, t1, runs)?);
            let lc = LeviCivita::new(&sys)?;
            lines.extend(run_regularised(&lc, "Levi-Civita", &x0, t1, &tols, runs)?);
            lines.extend(run_log_h(&sys, &x0, t1, runs)?);
            lines
        }
        "j2" => {
            let sys = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, J2::new(1.0, j2, 1.0)?)?;
            let mut lines = run(&sys, &x0, t1, &tols, &[], runs)?;
            lines.extend(run_split(&sys, &x0, t1, runs)?);
            let ks = KustaanheimoStiefel::new(&sys)?;
            lines.extend(run_regularised(
                &ks,
                "Kustaanheimo–Stiefel",
                &x0,
                t1,
                &tols,
                runs,
            )?);
            lines
        }
        "pendulum" => {
            let sys = Pendulum::new(1.0)?;
            run(&sys, &x0, t1, &tols, &DOUBLE_DOUBLE_TOLS, runs)?
        }
        _ => return Err(usage()),
    };
    println!("[{}]", lines.join(",\n"));
    Ok(())
}
