//! Result types stored and reloaded through `serde` (TOML): every field comes back bit for bit.
#![cfg(feature = "serde")]

use hamilton_jacobi::integrate::{integrate, Fixed, Problem, Report, Rk4, Work};
use hamilton_jacobi::nalgebra::{DMatrix, DVector, Matrix2, SVector};
use hamilton_jacobi::nonholonomic::integrators::{DiscreteRun, DiscreteStep, Drift, DriftSample};
use hamilton_jacobi::perturbation::birkhoff::{Block, Diagnostics, NormalFormKind};
use hamilton_jacobi::perturbation::brouwer::TheoryWarning;
use hamilton_jacobi::perturbation::lindstedt::{lindstedt_pendulum, LindstedtSeries};
use hamilton_jacobi::perturbation::normal_form::{
    ConvergenceWarning, FrequencyAmplitude, PendulumNormalForm, SeriesEstimate,
};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::stability::{
    hamiltonian_spectrum, spectrum, Crossing, CrossingKind, Equilibrium, HamiltonianSpectrum,
    Monodromy, ParameterStudy, PhaseEquilibrium, Spectrum, SpectrumAt, C64,
};
use hamilton_jacobi::systems::kepler::elements::{
    Classical, Delaunay, Equinoctial, ModifiedEquinoctial,
};
use hamilton_jacobi::systems::Pendulum;
use hamilton_jacobi::workprecision::{Comparison, Sample, Series, Timing};
use serde::{de::DeserializeOwned, Serialize};
use std::fmt::Debug;
use std::time::Duration;

/// Writes `x` as TOML, reads it back, and checks that every field is equal.
fn round_trip<T: Serialize + DeserializeOwned + PartialEq + Debug>(x: &T) -> T {
    let text = toml::to_string(x).expect("serialises");
    let back: T = toml::from_str(&text).expect("deserialises");
    assert_eq!(&back, x, "TOML:\n{text}");
    back
}

#[test]
fn integration_report() {
    let pendulum = Pendulum::new(1.0).unwrap();
    let problem = Problem::new(
        &pendulum,
        0.0,
        SVector::from([1.0]),
        SVector::from([0.0]),
        2.5,
    )
    .unwrap();
    let report: Report<1> = integrate(&problem, &Fixed::new(Rk4, 37).unwrap(), &mut ()).unwrap();
    assert_eq!(report.work.steps, 37);
    round_trip(&report);
    round_trip(&State::<3> {
        t: -0.125,
        q: SVector::from([1.0 / 3.0, -2.0e-300, 7.0e12]),
        p: SVector::from([f64::MIN_POSITIVE, 0.1, -0.0]),
    });
}

#[test]
fn orbital_elements() {
    round_trip(&Classical {
        a: 7000.0e3,
        e: 0.1 / 3.0,
        i: 0.9,
        raan: 1.0e-17,
        argp: 2.0_f64.sqrt(),
        mean_anomaly: -3.0,
    });
    round_trip(&Equinoctial {
        a: 1.5,
        h: 0.01,
        k: -0.02,
        p: 0.3,
        q: 0.4,
        lambda: 6.0,
    });
    round_trip(&ModifiedEquinoctial {
        p: 1.1,
        f: 0.01,
        g: 0.02,
        h: -0.3,
        k: 0.4,
        l: 1.0e3,
    });
    round_trip(&Delaunay {
        l: 0.1,
        g: 0.2,
        h: 0.3,
        big_l: 1.0,
        big_g: 0.9,
        big_h: 0.5,
    });
}

#[test]
fn normal_forms() {
    // The pendulum's frequency–amplitude relation as built.
    let pendulum = PendulumNormalForm::new(1.0, 6).unwrap();
    let relation = pendulum.normal_form().frequency_amplitude();
    let back = round_trip(relation);
    assert_eq!(back.energy(0.3).unwrap(), relation.energy(0.3).unwrap());
    assert_eq!(
        back.frequency_coefficients(),
        relation.frequency_coefficients()
    );
    // A stored relation that `FrequencyAmplitude::new` would refuse is refused.
    let text = toml::to_string(relation).unwrap();
    for (from, to) in [
        (
            "energy_coefficients = [0.0, 1.0,",
            "energy_coefficients = [0.0, -1.0,",
        ),
        (
            "energy_coefficients = [0.0, 1.0,",
            "energy_coefficients = [0.0, nan,",
        ),
    ] {
        let tampered = text.replacen(from, to, 1);
        assert_ne!(tampered, text, "{text}");
        assert!(toml::from_str::<FrequencyAmplitude>(&tampered).is_err());
    }
    assert!(toml::from_str::<FrequencyAmplitude>("energy_coefficients = [0.0]").is_err());

    #[derive(serde::Serialize, serde::Deserialize, PartialEq, Debug)]
    struct Terms {
        relation: FrequencyAmplitude,
        estimate: SeriesEstimate,
        kinds: Vec<NormalFormKind>,
        blocks: Vec<Block>,
        warnings: Vec<TheoryWarning>,
    }
    round_trip(&Terms {
        relation: relation.clone(),
        estimate: pendulum.period(0.5).unwrap(),
        kinds: vec![
            NormalFormKind::Birkhoff,
            NormalFormKind::Resonant(vec![vec![1, -2], vec![3, 0]]),
            NormalFormKind::CentreManifold,
        ],
        blocks: vec![
            Block::Elliptic {
                dof: 0,
                frequency: 1.0,
            },
            Block::Hyperbolic { dof: 1, rate: 0.5 },
            Block::ComplexSaddle {
                dof: 2,
                re: 0.1,
                im: 0.2,
            },
        ],
        warnings: vec![TheoryWarning::PerigeeInsideBody {
            perigee: 6000.0e3,
            radius: 6378.137e3,
        }],
    });
    round_trip(&SeriesEstimate {
        value: 1.0,
        small_parameter: 0.9,
        last_term: 1.0e-3,
        tail_bound: 2.0e-3,
        warning: Some(ConvergenceWarning::SlowTerms {
            ratio: 0.9,
            limit: 0.8,
            order: 6,
        }),
    });
    round_trip(&Diagnostics {
        amplitude: 0.1,
        generator_terms: vec![(3, 1.0e-2), (4, 1.0e-3)],
        normal_form_terms: vec![(4, 0.5)],
        optimal_degree: 4,
        diverged: false,
    });
    let lindstedt: LindstedtSeries = lindstedt_pendulum(6).unwrap();
    round_trip(&lindstedt);
}

#[test]
fn work_precision_records() {
    let work = Work {
        steps: 10,
        rejected: 1,
        gradients: 70,
        hamiltonians: 2,
        hessians: 3,
        newton_iterations: 4,
        flows: 5,
    };
    round_trip(&Comparison {
        title: "Kepler e = 0.5".into(),
        error_label: "relative energy error".into(),
        series: vec![Series {
            label: "DOP853".into(),
            knob: "tol".into(),
            samples: vec![
                Sample {
                    knob: 1.0e-6,
                    error: 3.1e-7,
                    seconds: 1.5e-4,
                    median: 1.6e-4,
                    work,
                },
                Sample {
                    knob: 1.0e-9,
                    error: 2.9e-10,
                    seconds: 3.5e-4,
                    median: 3.7e-4,
                    work,
                },
            ],
        }],
    });
    round_trip(&Timing {
        min_time: Duration::from_millis(250),
        max_runs: 9,
    });
}

#[test]
fn stability_spectra() {
    // Harmonic oscillator ⊕ inverted oscillator: one elliptic and one hyperbolic block.
    let hessian = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, -2.0, 3.0, 1.0]));
    let hs: HamiltonianSpectrum = hamiltonian_spectrum(&hessian).unwrap();
    round_trip(&hs);
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -4.0, -0.1]);
    let s: Spectrum = spectrum(&a, &DMatrix::zeros(2, 0)).unwrap();
    round_trip(&s);
    round_trip(&ParameterStudy {
        spectra: vec![SpectrumAt {
            parameter: 0.5,
            spectrum: s.clone(),
        }],
        crossings: vec![Crossing {
            parameter: 0.75,
            kind: CrossingKind::ComplexPair,
            bracket: (0.5, 1.0),
            unstable_counts: (0, 2),
            eigenvalues: vec![C64::new(1.0e-12, 2.0), C64::new(1.0e-12, -2.0)],
            iterations: 40,
        }],
    });
    round_trip(&Monodromy {
        matrix: DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]),
        multipliers: vec![C64::new(1.0, 0.0), C64::new(1.0, 0.0)],
        closure_defect: 1.0e-13,
        flow_defect: 2.0e-13,
        basis: DMatrix::identity(2, 2),
        trivial_block: Matrix2::new(1.0, 0.5, 0.0, 1.0),
        shear: 0.5,
        reduced: DMatrix::zeros(0, 0),
        nontrivial: vec![],
    });
    round_trip(&Equilibrium::<2> {
        z: SVector::from([0.0, 1.0]),
        residual: 1.0e-15,
        iterations: 3,
        used_fallback: false,
    });
    round_trip(&PhaseEquilibrium::<1> {
        q: SVector::from([std::f64::consts::PI]),
        p: SVector::from([0.0]),
        gradient_norm: 1.0e-16,
        iterations: 2,
        used_fallback: true,
    });
}

#[test]
fn constrained_runs() {
    let work = Work {
        steps: 100,
        ..Work::default()
    };
    round_trip(&DiscreteRun::<2> {
        last: State {
            t: 1.0,
            q: SVector::from([0.1, 0.2]),
            p: SVector::from([0.3, 0.4]),
        },
        stopped: false,
        work,
    });
    round_trip(&DiscreteStep::<2, 1> {
        q: SVector::from([0.1, 0.2]),
        p: SVector::from([0.3, 0.4]),
        velocity: SVector::from([0.5, 0.6]),
        lambda: SVector::from([0.7]),
        iterations: 4,
    });
    round_trip(&Drift {
        method: "RATTLE".into(),
        energy: -0.5,
        samples: vec![DriftSample {
            t: 1.0,
            energy_error: 1.0e-12,
            residual: 3.0e-15,
        }],
        work,
    });
}
