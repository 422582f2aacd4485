//! The rolling disk of SPEC T17 (M70), m = r = 1, g = 9.81:
//!
//! 1. the thresholds of oscillatory upright rolling, `v_c² = A m g r³/(C(C + m r²))`, for the
//!    disk (1.80831413200251) and the hoop (1.56604597633658);
//! 2. the runs of SPEC T17 over 10 s from a lean ψ(0) = 0.01 at the speeds v = 1.5, 2.2, 3 by the
//!    full non-linear multiplier equations (DOP853, rtol 1e-10): the largest lean against SPEC's
//!    0.668, 0.051, 0.021, the energy drift and the constraint residual (SPEC's reference run:
//!    drift ≤ 1e-12, residual ≤ 4e-13), and the Boltzmann–Hamel equations in
//!    the quasi-velocities beside them;
//! 3. the lean period at v = 3 between successive maxima of ψ against the linear 1.69432584875506 s.
//!
//! Run with `cargo run --release --example rolling_disk`.

use hamilton_jacobi::constraints::PfaffianConstraints;
use hamilton_jacobi::integrate::{integrate, Control, Dop853, Observer, Problem, StepView};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::hamel::quasi_velocities;
use hamilton_jacobi::nonholonomic::{BoltzmannHamel, Constrained};
use hamilton_jacobi::systems::RollingDisk;
use hamilton_jacobi::Result;

/// The lean ψ sampled ten times per step on the dense output: its largest modulus and the times
/// of its local maxima.
#[derive(Default)]
struct Lean {
    largest: f64,
    last: [(f64, f64); 2],
    maxima: Vec<f64>,
}

impl Observer<5> for Lean {
    fn step(&mut self, step: &StepView<'_, 5>) -> Control {
        for k in 1..=10 {
            let t = step.prev.t + (step.next.t - step.prev.t) * k as f64 / 10.0;
            let psi = step.dense.at(t).q[3];
            self.largest = self.largest.max(psi.abs());
            let [(t0, a), (t1, b)] = self.last;
            if t1 > t0 && b > a && b >= psi {
                // Vertex of the parabola through the last three samples.
                let (u, w) = (t1 - t0, t1 - t);
                let num = u * u * (b - psi) - w * w * (b - a);
                let den = u * (b - psi) - w * (b - a);
                self.maxima.push(t1 - 0.5 * num / den);
            }
            self.last = [(t1, b), (t, psi)];
        }
        Control::Continue
    }
}

fn main() -> Result<()> {
    let disk = RollingDisk::disk(1.0, 1.0, 9.81)?;
    let hoop = RollingDisk::hoop(1.0, 1.0, 9.81)?;
    println!(
        "critical speeds: disk {:.14} (SPEC 1.80831413200251), hoop {:.14} (SPEC 1.56604597633658)",
        disk.critical_speed()?,
        hoop.critical_speed()?
    );
    let mult = Constrained::new(disk, disk);
    let bh = BoltzmannHamel::new(disk, disk);
    let method = Dop853::new(1e-10, 1e-12)?;
    println!("\n  v    max|ψ|   SPEC    energy drift   constraint residual   |Δq| Boltzmann–Hamel vs multipliers");
    for (v, spec) in [(1.5, 0.668), (2.2, 0.051), (3.0, 0.021)] {
        let q0 = SVector::from([0.0, 0.0, 0.0, 0.01, 0.0]);
        let qd0 = SVector::from([v, 0.0, 0.0, 0.0, v]);
        let mut lean = Lean::default();
        let report = mult.integrate(&method, 0.0, q0, qd0, 10.0, 1e-14, &mut lean)?;
        let (q1, v1) = (report.last.q, report.last.p);
        let drift = disk.energy(&q1, &v1)? - disk.energy(&q0, &qd0)?;
        let (b, _) = disk.forms(10.0, &q1);
        let w0 = quasi_velocities(&disk, &q0, &qd0, 1e-14)?;
        let problem = Problem::new(&bh, 0.0, q0, w0, 10.0)?;
        let q2 = integrate(&problem, &method, &mut ())?.last.q;
        println!(
            "{v:4.1}   {:.4}   {spec:.3}   {drift:+.2e}      {:.2e}              {:.2e}",
            lean.largest,
            (b * v1).amax(),
            (q2 - q1).amax()
        );
        if v == 3.0 && lean.maxima.len() >= 2 {
            let n = lean.maxima.len() - 1;
            println!(
                "      lean period between maxima {:.4} s (linear 1.69432584875506 s, SPEC ≈ 1.694)",
                (lean.maxima[n] - lean.maxima[0]) / n as f64
            );
        }
    }
    Ok(())
}
