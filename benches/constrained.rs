//! One step of each constrained integrator on the rolling disk of SPEC T17 (m = r = 1, v = 3,
//! ψ = 0.01): the discrete Lagrange–d'Alembert step (Newton with the AD Jacobian), one DOP853
//! step of the index-reduced (multiplier) equations, and the velocity projection that the
//! projection method adds; the cost per right-hand-side evaluation of the formulations
//! (multipliers, embedding, Boltzmann–Hamel, Gibbs–Appell); and one RATTLE step on the spherical
//! pendulum.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::constraints::HolonomicConstraints;
use hamilton_jacobi::integrate::{integrate, ConstrainedHamiltonian, Dop853, Problem, Rattle};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::hamel::quasi_velocities;
use hamilton_jacobi::nonholonomic::{BoltzmannHamel, Constrained, GibbsAppell, LagrangeDAlembert};
use hamilton_jacobi::systems::RollingDisk;
use hamilton_jacobi::{DualNum, Hamiltonian, Lagrangian};
use std::hint::black_box;

/// A unit point mass under gravity 9.81, `H = ½|p|² + 9.81 z`.
struct Heavy;

impl Hamiltonian<3> for Heavy {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        p.dot(p) * 0.5 + q[2] * 9.81
    }
}

/// The unit sphere, `g = ½(|q|² − 1)`.
struct Sphere;

impl HolonomicConstraints<3, 1> for Sphere {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
    ) -> SVector<D, 1> {
        SVector::from([(q.dot(q) - 1.0) * 0.5])
    }
}

fn constrained(c: &mut Criterion) {
    let disk = RollingDisk::disk(1.0, 1.0, 9.81).unwrap();
    let sys = Constrained::new(disk, disk);
    let q = SVector::from([0.0, 0.0, 0.0, 0.01, 0.0]);
    let qd = SVector::from([3.0, 0.0, 0.0, 0.0, 3.0]);
    let p = disk.momentum(0.0, &q, &qd).unwrap();
    let h = 1e-3;
    let dla = LagrangeDAlembert::new(1).unwrap();
    c.bench_function("disk: discrete Lagrange–d'Alembert step", |b| {
        b.iter(|| {
            dla.step(&sys, 0.0, black_box(&q), black_box(&p), h)
                .unwrap()
        })
    });
    let dop = Dop853::new(1e-10, 1e-12)
        .unwrap()
        .with_h0(h)
        .unwrap()
        .with_h_max(h)
        .unwrap();
    c.bench_function("disk: DOP853 step, index-reduced", |b| {
        b.iter(|| {
            let pr = Problem::new(&sys, 0.0, black_box(q), qd, h).unwrap();
            integrate(&pr, &dop, &mut ()).unwrap()
        })
    });
    let off = qd + SVector::from([1e-9, -1e-9, 0.0, 0.0, 0.0]);
    c.bench_function("disk: velocity projection", |b| {
        b.iter(|| sys.project_velocities(0.0, &q, black_box(&off)).unwrap())
    });
    c.bench_function("disk: rhs, multipliers", |b| {
        b.iter(|| {
            sys.multiplier_accelerations(0.0, black_box(&q), &qd)
                .unwrap()
        })
    });
    c.bench_function("disk: rhs, embedding", |b| {
        b.iter(|| sys.embedded_accelerations(0.0, black_box(&q), &qd).unwrap())
    });
    let bh = BoltzmannHamel::new(disk, disk);
    let w = quasi_velocities(&disk, &q, &qd, 1e-12).unwrap();
    c.bench_function("disk: rhs, Boltzmann–Hamel", |b| {
        b.iter(|| bh.quasi_accelerations(0.0, black_box(&q), &w).unwrap())
    });
    let ga = GibbsAppell::new(disk, disk);
    c.bench_function("disk: rhs, Gibbs–Appell", |b| {
        b.iter(|| ga.quasi_accelerations(0.0, black_box(&q), &w).unwrap())
    });
    let pend = ConstrainedHamiltonian::new(Heavy, Sphere);
    let (s, co) = 0.8f64.sin_cos();
    let q3 = SVector::from([s, 0.0, -co]);
    let p3 = SVector::from([0.0, 1.7, 0.0]);
    let rattle = Rattle::new(1).unwrap();
    c.bench_function("spherical pendulum: RATTLE step", |b| {
        b.iter(|| rattle.step(&pend, 0.0, black_box(&q3), &p3, 0.01).unwrap())
    });
}

criterion_group!(benches, constrained);
criterion_main!(benches);
