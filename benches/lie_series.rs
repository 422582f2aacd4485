//! Lie series `Σ_{k≤n} ε^k/k! L_ρ^k z` ([`LieSeries`]): the checked real evaluation (with the
//! error estimate's extra order) and the Jacobian of the map through the dual-number path
//! ([`certify`]), for a smooth 2-DOF generator, the 3-DOF rotation generator and the pendulum.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::brackets::certify;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::transform::lie::{lie_flow, LieSeries};
use hamilton_jacobi::{hamiltonian, DualNum, PhaseFunction};
use std::hint::black_box;

/// The smooth 2-DOF generator of `tests/lie.rs` (nonlinear in every variable).
#[derive(Clone, Copy, Debug)]
struct Gen([f64; 6]);
impl PhaseFunction<2> for Gen {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
        let c = &self.0;
        (q[0] + p[1] * 0.5).sin() * c[0]
            + (q[1] - p[0]).cos() * c[1]
            + q[0] * p[0] * c[2]
            + ((q[1] + p[1]) * 0.3).exp() * c[3]
            + (p[0] * p[0] + q[1] * q[1]) * (0.5 * c[4])
            + q[0] * q[1] * p[1] * (c[5] / 3.0)
    }
}

/// `h_z = x p_y − y p_x`.
#[derive(Clone, Copy, Debug)]
struct Hz;
impl PhaseFunction<3> for Hz {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>, p: &SVector<D, 3>) -> D {
        q[0] * p[1] - q[1] * p[0]
    }
}

hamiltonian!(
    /// The pendulum `p²/2 − cos q`.
    Pendulum<1> |_s, _t, q, p| p[0] * p[0] * 0.5 - q[0].cos()
);

fn bench(c: &mut Criterion) {
    let g = Gen([0.8, -0.6, 0.5, 0.9, -0.7, 0.4]);
    let (q2, p2) = (SVector::from([0.3, -0.2]), SVector::from([0.4, 0.1]));
    let (q3, p3) = (
        SVector::from([1.0, 0.0, 0.5]),
        SVector::from([0.0, 2.0, 0.0]),
    );
    let (q1, p1) = (SVector::from([0.5]), SVector::from([0.1]));
    let mut group = c.benchmark_group("lie_series");
    for n in [3usize, 8] {
        let s = LieSeries::new(g, 0.05, n).unwrap();
        group.bench_function(format!("2dof_transform_order{n}"), |b| {
            b.iter(|| black_box(s.transform(0.0, &q2, &p2).unwrap()))
        });
        group.bench_function(format!("2dof_with_error_order{n}"), |b| {
            b.iter(|| black_box(s.apply_with_error(0.0, &q2, &p2).unwrap()))
        });
        group.bench_function(format!("2dof_certify_order{n}"), |b| {
            b.iter(|| black_box(certify(&s, 0.0, &q2, &p2).unwrap().symplectic_defect))
        });
    }
    let hz = LieSeries::new(Hz, 0.1, 8).unwrap();
    group.bench_function("3dof_rotation_with_error_order8", |b| {
        b.iter(|| black_box(hz.apply_with_error(0.0, &q3, &p3).unwrap()))
    });
    let pend = lie_flow(Pendulum, 0.02, 8).unwrap();
    group.bench_function("pendulum_transform_order8", |b| {
        b.iter(|| black_box(pend.transform(0.0, &q1, &p1).unwrap()))
    });
    let pend3 = lie_flow(Pendulum, 0.02, 3).unwrap();
    group.bench_function("pendulum_certify_order3", |b| {
        b.iter(|| black_box(certify(&pend3, 0.0, &q1, &p1).unwrap().symplectic_defect))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
