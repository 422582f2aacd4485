//! The Chaplygin sleigh (blade) of SPEC T16, m = 2, s = 0.5, I_B = 1, force-free from v(0) = 0,
//! ϑ̇(0) = √2 (energy m v₀² with v₀ = 1):
//!
//! 1. the forward speed v and the heading ϑ by three formulations — Boltzmann–Hamel, Gibbs–Appell
//!    and Lagrange's equations with a multiplier — against the closed forms
//!    `v = v₀ tanh(v₀t/a)`, `ϑ = 2(√(I_B/m)/s) arctan(tanh(v₀t/(2a)))` (SPEC's table at
//!    t = 0.5 … 12 is these to ten digits);
//! 2. the cusp at t = 0: `x ≈ v₀²t²/(2a)`, `y ≈ v₀²ϑ̇₀t³/(3a)` (X5);
//! 3. the energy `m v² + I_B ϑ̇²` and the constraint residual of the multiplier run;
//! 4. the path of the contact point, written to `out/chaplygin-sleigh-path.svg`.
//!
//! Run with `cargo run --release --example chaplygin_sleigh`.

use hamilton_jacobi::integrate::{integrate, Dop853, FirstOrderSystem, Problem, Samples};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::{BoltzmannHamel, Constrained, GibbsAppell};
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::systems::ChaplyginSleigh;
use hamilton_jacobi::Result;

/// `(q, p)` at `t` from `(q₀, p₀)` at 0 by DOP853 at rtol 1e-12.
fn run<S: FirstOrderSystem<3>>(
    s: &S,
    q0: SVector<f64, 3>,
    p0: SVector<f64, 3>,
    t: f64,
) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
    let problem = Problem::new(s, 0.0, q0, p0, t)?;
    let report = integrate(&problem, &Dop853::new(1e-12, 1e-14)?, &mut ())?;
    Ok((report.last.q, report.last.p))
}

fn main() -> Result<()> {
    let (m, s, i_b) = (2.0, 0.5, 1.0);
    let sleigh = ChaplyginSleigh::new(m, s, i_b)?;
    let bh = BoltzmannHamel::new(sleigh, sleigh);
    let ga = GibbsAppell::new(sleigh, sleigh);
    let mult = Constrained::new(sleigh, sleigh);
    let w0 = 2f64.sqrt();
    let (q0, om0) = (SVector::zeros(), SVector::from([0.0, 0.0, w0]));
    println!("Chaplygin sleigh m = {m}, s = {s}, I_B = {i_b}: v and ϑ, DOP853 rtol 1e-12");
    println!(
        "   t   v (closed form)  ϑ (closed form)   |Δϑ| Boltzmann–Hamel, Gibbs–Appell, multipliers; |Δv| BH"
    );
    for t in [0.5, 1.0, 2.0, 4.0, 8.0, 12.0] {
        let (q1, w1) = run(&bh, q0, om0, t)?;
        let (q2, _) = run(&ga, q0, om0, t)?;
        let (q3, _) = run(&mult, q0, om0, t)?;
        let (v, _, th) = sleigh.free_motion(1.0, t)?;
        println!(
            "{t:5.1}  {v:.12}   {th:.12}    {:.1e}, {:.1e}, {:.1e}; {:.1e}",
            (q1[2] - th).abs(),
            (q2[2] - th).abs(),
            (q3[2] - th).abs(),
            (w1[1] - v).abs()
        );
    }
    let limit = std::f64::consts::FRAC_PI_2 * (i_b / m).sqrt() / s;
    println!("total turn (π/2)√(I_B/m)/s = {limit:.14} (SPEC 2.22144146907918)");

    let (q, _) = run(&bh, q0, om0, 1e-3)?;
    println!(
        "cusp at t = 1e-3: x = {:.7e} (SPEC 4.999997e-7), y = {:.7e} (SPEC 4.714043e-10)",
        q[0], q[1]
    );

    // The multiplier run's energy and constraint residual at t = 12.
    let (q, v) = run(&mult, q0, om0, 12.0)?;
    let (sn, cs) = q[2].sin_cos();
    let fwd = v[0] * cs + v[1] * sn;
    println!(
        "multipliers at t = 12: energy m v² + I_B ϑ̇² − m v₀² = {:.1e}, residual ẏ cos ϑ − ẋ sin ϑ = {:.1e}",
        m * fwd * fwd + i_b * v[2] * v[2] - m,
        v[1] * cs - v[0] * sn
    );

    // The path of the contact point.
    let problem = Problem::new(&bh, 0.0, q0, om0, 8.0)?;
    let mut samples = Samples::uniform(0.0, 8.0, 400)?;
    integrate(&problem, &Dop853::new(1e-12, 1e-14)?, &mut samples)?;
    let path: Vec<(f64, f64)> = samples.states.iter().map(|z| (z.q[0], z.q[1])).collect();
    let figure = Figure::new("Chaplygin sleigh: path of the blade", "x", "y")
        .equal_aspect()
        .caption(
            "Path of the blade's contact point of the Chaplygin sleigh (m = 2, s = 0.5, I_B = 1), \
             force-free from rest in translation with ϑ̇(0) = √2, t ∈ [0, 8], Boltzmann–Hamel \
             equations by DOP853 at rtol 1e−12; the cusp at the origin is a semicubical parabola.",
        )
        .curve("contact point", path, Style::Line);
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("directory out", e.to_string()))?;
    let files = figure.write(
        std::path::Path::new("out/chaplygin-sleigh-path"),
        &[Format::Svg],
        DataFormat::Csv,
    )?;
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}
