//! Stability of equilibria and steady motions (SPEC M33–M34, M70; T16, T17, T27; X2, X5): the
//! linearisation by AD of the one definition, the family of steady motions factored out, the
//! classification, and the stability boundary against a parameter located by Brent's method.

use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Recorder};
use hamilton_jacobi::nalgebra::{DMatrix, SVector, Vector2, Vector3};
use hamilton_jacobi::nonholonomic::BoltzmannHamel;
use hamilton_jacobi::stability::{
    equilibrium, linearize, real_part_crossings, spectra, spectrum, steady_motion_spectrum,
    upright_rolling, upright_rolling_spectrum, CrossingKind, Reduced, Slot, Stability,
};
use hamilton_jacobi::systems::{ChaplyginSleigh, DoublePendulum, RollingDisk};
use hamilton_jacobi::{DualNum, Hamiltonian};

const G: f64 = 9.81;

/// M70: `a² = (BD − AF)/(AE)` with `B = Cv/r`, `D = (mr + C/r)v`, `E = A + mr²`, `F = mgr`.
fn a_squared(a: f64, c: f64, v: f64) -> f64 {
    let (m, r) = (1.0, 1.0);
    let (b, d, e, f) = (c / r * v, (m * r + c / r) * v, a + m * r * r, m * G * r);
    (b * d - a * f) / (a * e)
}

#[test]
fn m70_disk_linearisation_against_speed_matches_hamels_frequency() {
    let disk = RollingDisk::disk(1.0, 1.0, G).unwrap();
    let bh = BoltzmannHamel::new(disk, disk);
    for v in [0.3, 1.0, 1.5, 1.7, 1.9, 2.2, 3.0, 6.0] {
        let reduced = upright_rolling(&bh, v).unwrap();
        // x, y, ϑ, φ are cyclic and the constrained quasi-velocities at rest: a valid reduction.
        let (defect, rate) = reduced.cyclic_defect(0.0, &reduced.state()).unwrap();
        assert!(
            defect <= 1e-14 && rate <= 1e-14,
            "v = {v}: {defect:e}, {rate:e}"
        );
        let s = upright_rolling_spectrum(disk, v).unwrap();
        // Steady rolling at every speed and steady turning at constant lean: a double zero of
        // the family, reported and not classified [Hamel art. 244].
        assert_eq!(s.family_dimension(), 2, "v = {v}");
        assert_eq!(s.eigenvalues.len(), 4);
        assert_eq!(s.transverse.len(), 2);
        // The transverse pair ±√(−a²): their product is a².
        let want = a_squared(0.25, 0.5, v);
        let det = s.transverse_matrix.determinant();
        let scale = s.transverse_matrix.norm().powi(2);
        assert!(
            (det - want).abs() <= 1e-13 * scale.max(1.0),
            "v = {v}: det = {det:e}, a² = {want:e}"
        );
        for l in &s.transverse {
            let lambda2 = (l * l).re;
            assert!(
                (lambda2 + want).abs() <= 1e-12 * scale.max(1.0),
                "v = {v}: λ² = {lambda2:e}, −a² = {:e}",
                -want
            );
        }
        let expected = if want < 0.0 {
            Stability::Unstable
        } else {
            Stability::Stable
        };
        assert_eq!(s.stability, expected, "v = {v}: {:?}", s.transverse);
        assert!(!s.attracting);
    }
    // T17: v = 1.5, a² = −2.448 (growth rate 1.5646 s⁻¹); v = 3, a = 3.70836891368699 rad/s.
    let s = upright_rolling_spectrum(disk, 1.5).unwrap();
    assert!(
        (s.transverse[0].re - 1.5646).abs() < 5e-5,
        "{:?}",
        s.transverse
    );
    assert!((a_squared(0.25, 0.5, 1.5) + 2.448).abs() < 5e-4);
    let s = upright_rolling_spectrum(disk, 3.0).unwrap();
    let omega = s.transverse[0].im.abs();
    assert!((omega - 3.70836891368699).abs() < 1e-12, "{omega}");
}

#[test]
fn t17_disk_and_hoop_thresholds_by_root_finding_the_real_part_crossing() {
    for (body, v_c) in [
        (RollingDisk::disk(1.0, 1.0, G).unwrap(), 1.80831413200251),
        (RollingDisk::hoop(1.0, 1.0, G).unwrap(), 1.56604597633658),
    ] {
        // Brent's tolerance 1e−14 in v: its stopping rule bounds the error by
        // 2ε|v| + 0.5e−14 ≈ 1e−14; the test function det(WᵀAW) = a² has slope
        // d(a²)/dv = O(1) at v_c and is computed to O(ε‖A‖²), so the root is good to ~1e−15.
        let crossings =
            real_part_crossings(|v| upright_rolling_spectrum(body, v), 0.5, 4.0, 15, 1e-14)
                .unwrap();
        assert_eq!(crossings.len(), 1, "{crossings:?}");
        let c = &crossings[0];
        assert_eq!(c.kind, CrossingKind::ThroughZero);
        assert_eq!(c.unstable_counts, (1, 0));
        assert!(
            (c.parameter - v_c).abs() <= 1e-12,
            "v_c = {:.15}, expected {v_c}",
            c.parameter
        );
        assert!((c.parameter - body.critical_speed().unwrap()).abs() <= 1e-12);
        // At the threshold both transverse eigenvalues are at zero (to √ε, a defective pair).
        assert!(
            c.eigenvalues.iter().all(|l| l.norm() < 1e-6),
            "{:?}",
            c.eigenvalues
        );
    }
    // X2: just below and just above the disk's threshold.
    let disk = RollingDisk::disk(1.0, 1.0, G).unwrap();
    let sweep = spectra(|v| upright_rolling_spectrum(disk, v), &[1.7, 1.9]).unwrap();
    assert_eq!(sweep[0].spectrum.stability, Stability::Unstable);
    assert_eq!(sweep[1].spectrum.stability, Stability::Stable);
}

/// The sleigh's reduced variables `(v, ϑ̇)`, its coordinates `x, y, ϑ` cyclic.
fn straight(
    sleigh: ChaplyginSleigh,
    v0: f64,
) -> (
    BoltzmannHamel<ChaplyginSleigh, ChaplyginSleigh, 3>,
    SVector<f64, 3>,
) {
    (
        BoltzmannHamel::new(sleigh, sleigh),
        SVector::from([0.0, v0, 0.0]),
    )
}

#[test]
fn x5_sleigh_straight_motion_attracts_with_the_centre_ahead_and_repels_behind() {
    let (m, i_b, v0) = (2.0, 1.0, 1.0);
    for s in [0.5, -0.5] {
        let sleigh = ChaplyginSleigh::new(m, s, i_b).unwrap();
        let (bh, w) = straight(sleigh, v0);
        let reduced = Reduced::new(&bh, &SVector::zeros(), &w, [Slot::P(1), Slot::P(2)]).unwrap();
        let z = reduced.state();
        let sp = steady_motion_spectrum(&reduced, 0.0, &z).unwrap();
        // Straight motion at every speed: one zero of the family.
        assert_eq!(sp.family_dimension(), 1);
        assert!(sp.family[(1, 0)].abs() < 1e-14, "the family is along v");
        // The transverse eigenvalue −m s v₀/I_B of I_B ϑ̈ + m s v ϑ̇ = 0.
        let want = -m * s * v0 / i_b;
        assert_eq!(sp.transverse.len(), 1);
        assert!(
            (sp.transverse[0].re - want).abs() < 1e-14,
            "{:?}",
            sp.transverse
        );
        // Energy m v² + I_B ϑ̇² is conserved to first order: ∇E · A = 0.
        let a = linearize(&reduced, 0.0, &z).unwrap();
        let grad_e = Vector2::new(2.0 * m * v0, 0.0);
        assert!((grad_e.transpose() * a).amax() < 1e-14);
        if s > 0.0 {
            assert_eq!(sp.stability, Stability::Stable);
            assert!(sp.attracting);
        } else {
            assert_eq!(sp.stability, Stability::Unstable);
            assert!(!sp.attracting);
        }
        // The non-linear motion from a perturbed straight motion: ϑ̇ decays (centre ahead) or
        // grows (centre behind) while the energy stays at its initial value.
        let w0 = Vector3::new(0.0, v0, 1e-3);
        let problem = Problem::new(&bh, 0.0, SVector::zeros(), w0, 8.0).unwrap();
        let mut rec = Recorder::<3>::every(1);
        integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut rec).unwrap();
        let e0 = m * v0 * v0 + i_b * 1e-6;
        for st in &rec.states {
            let e = m * st.p[1] * st.p[1] + i_b * st.p[2] * st.p[2];
            assert!((e - e0).abs() < 1e-10, "t = {}: energy {e} vs {e0}", st.t);
        }
        let last = rec.states.last().unwrap().p[2].abs();
        let peak = rec
            .states
            .iter()
            .map(|st| st.p[2].abs())
            .fold(0.0, f64::max);
        if s > 0.0 {
            // ϑ̇ ≈ ϑ̇₀ e^{−m s v₀ t/I_B} = 1e−3 e^{−8}.
            assert!(last < 1e-3 * (-7.9f64).exp(), "{last:e}");
        } else {
            // ϑ̇ grows from 1e−3 until the energy has gone into the turn: at the cusp (v = 0,
            // t ≈ ½ ln(2/ε) ≈ 7.9 with ε = I_B ϑ̇₀²/(2 m v₀²)) ϑ̇ = v₀ √(m/I_B) (SPEC X5).
            let top = v0 * (m / i_b).sqrt();
            assert!(peak > 0.9 * top && peak <= top * (1.0 + 1e-9), "{peak:e}");
        }
    }
    // X2: s → 0, no relaxation: with the mass centre on the blade every (v, ϑ̇) is a steady
    // motion (uniform motion on a circle), a family of dimension two; nothing is attracted.
    let sleigh = ChaplyginSleigh::new(m, 0.0, i_b).unwrap();
    let (bh, w) = straight(sleigh, v0);
    let reduced = Reduced::new(&bh, &SVector::zeros(), &w, [Slot::P(1), Slot::P(2)]).unwrap();
    let sp = steady_motion_spectrum(&reduced, 0.0, &reduced.state()).unwrap();
    assert_eq!(sp.family_dimension(), 2, "{sp:?}");
    assert!(sp.transverse.is_empty() && !sp.attracting);
    assert_eq!(sp.stability, Stability::Stable);
}

#[test]
fn t27_double_pendulum_equilibria_and_their_eigenvalues() {
    // Equal point masses and lengths, g/ℓ = 1.
    let double = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 1.0).unwrap();
    use std::f64::consts::PI;
    let s2 = 2f64.sqrt();
    let (fast, slow, quartic) = ((2.0 + s2).sqrt(), (2.0 - s2).sqrt(), s2.sqrt());
    let cases = [
        (
            [0.1, -0.1],
            [0.0, 0.0],
            Stability::Stable,
            [0.0, 0.0, fast, slow],
        ),
        (
            [3.0, 0.1],
            [PI, 0.0],
            Stability::Unstable,
            [quartic, 0.0, 0.0, quartic],
        ),
        (
            [0.1, 3.0],
            [0.0, PI],
            Stability::Unstable,
            [quartic, 0.0, 0.0, quartic],
        ),
        (
            [3.0, 3.3],
            [PI, PI],
            Stability::Unstable,
            [fast, slow, 0.0, 0.0],
        ),
    ];
    for (guess, at, stability, [re1, re2, im1, im2]) in cases {
        let reduced = Reduced::new(
            &double,
            &SVector::zeros(),
            &SVector::zeros(),
            [Slot::Q(0), Slot::Q(1), Slot::P(0), Slot::P(1)],
        )
        .unwrap();
        let z0 = SVector::<f64, 4>::from([guess[0], guess[1], 0.05, -0.05]);
        let eq = equilibrium(&reduced, 0.0, &z0).unwrap();
        assert!(
            (eq.z[0] - at[0]).abs() < 1e-12 && (eq.z[1] - at[1]).abs() < 1e-12,
            "{eq:?}"
        );
        let sp = steady_motion_spectrum(&reduced, 0.0, &eq.z).unwrap();
        assert_eq!(sp.family_dimension(), 0);
        assert_eq!(sp.stability, stability, "{at:?}: {:?}", sp.eigenvalues);
        let mut re: Vec<f64> = sp.eigenvalues.iter().map(|l| l.re.abs()).collect();
        let mut im: Vec<f64> = sp.eigenvalues.iter().map(|l| l.im.abs()).collect();
        re.sort_by(|a, b| b.total_cmp(a));
        im.sort_by(|a, b| b.total_cmp(a));
        let mut want_re = [re1, re1, re2, re2];
        let mut want_im = [im1, im1, im2, im2];
        want_re.sort_by(|a, b| b.total_cmp(a));
        want_im.sort_by(|a, b| b.total_cmp(a));
        for k in 0..4 {
            assert!(
                (re[k] - want_re[k]).abs() < 1e-12,
                "{at:?}: {:?}",
                sp.eigenvalues
            );
            assert!(
                (im[k] - want_im[k]).abs() < 1e-12,
                "{at:?}: {:?}",
                sp.eigenvalues
            );
        }
    }
}

/// The bead on a hoop turning at `ω` about its vertical diameter (radius a, m = 1) in the rotating
/// frame: `H = p²/(2a²) − ½a²ω² sin²θ − g a cos θ`.
struct Bead {
    a: f64,
    omega: f64,
}

impl Hamiltonian<1> for Bead {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> D {
        let s = q[0].sin();
        p[0] * p[0] / (2.0 * self.a * self.a)
            - s * s * (0.5 * self.a * self.a * self.omega * self.omega)
            - q[0].cos() * (G * self.a)
    }
}

#[test]
fn x2_bead_on_a_hoop_bottom_is_undecided_at_the_bifurcation() {
    let a = 0.5;
    let critical = (G / a).sqrt();
    for (omega, want) in [
        (0.5 * critical, Stability::Stable),
        (critical, Stability::Undecided),
        (1.5 * critical, Stability::Unstable),
    ] {
        let bead = Bead { a, omega };
        let reduced = Reduced::new(
            &bead,
            &SVector::zeros(),
            &SVector::zeros(),
            [Slot::Q(0), Slot::P(0)],
        )
        .unwrap();
        let sp = steady_motion_spectrum(&reduced, 0.0, &reduced.state()).unwrap();
        assert_eq!(sp.stability, want, "ω = {omega}: {:?}", sp.eigenvalues);
        // An isolated equilibrium: no family, even where both eigenvalues vanish.
        assert_eq!(sp.family_dimension(), 0);
    }
}

#[test]
fn m34_classification_of_given_spectra() {
    let family = DMatrix::<f64>::zeros(2, 0);
    let cases = [
        (
            DMatrix::from_row_slice(2, 2, &[-1.0, 0.0, 0.0, -2.0]),
            Stability::AsymptoticallyStable,
        ),
        (
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]),
            Stability::Stable,
        ),
        (
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]),
            Stability::Unstable,
        ),
        // Free fall (T41): a double zero with a Jordan block.
        (
            DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
            Stability::Undecided,
        ),
    ];
    for (a, want) in cases {
        assert_eq!(spectrum(&a, &family).unwrap().stability, want, "{a}");
    }
    // A family direction that is not in the kernel is refused.
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 0.0, 0.0, -1.0]);
    let bad = DMatrix::from_column_slice(2, 1, &[0.0, 1.0]);
    assert!(spectrum(&a, &bad).is_err());
    let good = DMatrix::from_column_slice(2, 1, &[1.0, 0.0]);
    let s = spectrum(&a, &good).unwrap();
    assert_eq!(s.stability, Stability::Stable);
    assert!(s.attracting);
}

/// The speed of upright rolling is `v = r φ̇`: for a disk of radius 2 the crossing of the
/// spectrum against `v` is the critical speed `v_c² = A m g r³/(C(C + m r²))` [Hamel art. 244],
/// here `√(2g/3)`.
#[test]
fn upright_rolling_threshold_scales_with_the_radius() {
    let disk = RollingDisk::disk(1.0, 2.0, G).unwrap();
    let v_c = disk.critical_speed().unwrap();
    assert!((v_c - (2.0 * G / 3.0).sqrt()).abs() < 1e-14);
    let study = hamilton_jacobi::stability::parameter_study(
        |v| upright_rolling_spectrum(disk, v),
        1.0,
        4.0,
        31,
        1e-14,
    )
    .unwrap();
    assert_eq!(study.spectra.len(), 31);
    assert_eq!(study.crossings.len(), 1, "{:?}", study.crossings);
    let c = &study.crossings[0];
    assert!(
        (c.parameter - v_c).abs() < 1e-11,
        "{} vs {v_c}",
        c.parameter
    );
    // The grid spectra are those of the function at the grid values.
    let direct = upright_rolling_spectrum(disk, study.spectra[7].parameter).unwrap();
    assert_eq!(direct, study.spectra[7].spectrum);
}
