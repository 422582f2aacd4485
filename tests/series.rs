//! The truncated power series number type against independent oracles: exact Taylor
//! coefficients (rationals), exact polynomials, num-dual's third-order duals, the evaluation
//! homomorphism, identities between elementary functions, and Bessel coefficients of a Poisson
//! series.

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::num_dual::{third_derivative, Dual3_64, DualNum};
use hamilton_jacobi::series::{fourier_taylor, scope, Polynomial, Series, MAX_SERIES_COEFFICIENTS};
use hamilton_jacobi::systems::{Kepler2, Pendulum};
use hamilton_jacobi::{hamiltonian, Error, Hamiltonian};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

fn factorial(k: u32) -> f64 {
    (1..=k).map(f64::from).product()
}

/// Univariate coefficients of `f(x)` about 0 to degree `k`.
fn univariate(k: usize, f: impl FnOnce(Series) -> Series) -> Vec<f64> {
    scope(1, k, |s| {
        let x = s.variable(0).unwrap();
        s.polynomial(f(x)).unwrap().coefficients().to_vec()
    })
    .unwrap()
}

/// `|got − want| ≤ ulps·ε·max(|want|, tiny)` for every coefficient.
fn assert_coefficients(what: &str, got: &[f64], want: &[f64], ulps: f64) {
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let tol = ulps * EPS * w.abs().max(1e-300);
        assert!(
            (g - w).abs() <= tol,
            "{what}: coefficient {k}: got {g:e}, want {w:e} (|Δ| = {:e}, tol {tol:e})",
            (g - w).abs()
        );
    }
}

#[test]
fn elementary_functions_have_the_exact_taylor_coefficients() {
    const K: usize = 20;
    let ulps = 4.0 * K as f64;
    // exp x = Σ x^k / k!
    let want: Vec<f64> = (0..=K as u32).map(|k| 1.0 / factorial(k)).collect();
    assert_coefficients("exp", &univariate(K, |x| x.exp()), &want, ulps);
    // ln(1 + x) = Σ (−1)^{k+1} x^k / k
    let mut want = vec![0.0];
    want.extend((1..=K).map(|k| if k % 2 == 1 { 1.0 } else { -1.0 } / k as f64));
    assert_coefficients("ln(1+x)", &univariate(K, |x| (x + 1.0).ln()), &want, ulps);
    assert_coefficients("ln_1p", &univariate(K, |x| x.ln_1p()), &want, ulps);
    // atan x = Σ (−1)^m x^{2m+1}/(2m+1)
    let want: Vec<f64> = (0..=K)
        .map(|k| match k % 4 {
            1 => 1.0 / k as f64,
            3 => -1.0 / k as f64,
            _ => 0.0,
        })
        .collect();
    assert_coefficients("atan", &univariate(K, |x| x.atan()), &want, ulps);
    // √(1 + x) = Σ C(1/2, k) x^k
    let mut want = vec![1.0];
    for k in 1..=K {
        let prev: f64 = want[k - 1];
        want.push(prev * (0.5 - (k - 1) as f64) / k as f64);
    }
    assert_coefficients(
        "sqrt(1+x)",
        &univariate(K, |x| (x + 1.0).sqrt()),
        &want,
        ulps,
    );
    // sin, cos, sinh, cosh
    let sin: Vec<f64> = (0..=K as u32)
        .map(|k| match k % 4 {
            1 => 1.0 / factorial(k),
            3 => -1.0 / factorial(k),
            _ => 0.0,
        })
        .collect();
    assert_coefficients("sin", &univariate(K, |x| x.sin()), &sin, ulps);
    let sinh: Vec<f64> = (0..=K as u32)
        .map(|k| if k % 2 == 1 { 1.0 / factorial(k) } else { 0.0 })
        .collect();
    assert_coefficients("sinh", &univariate(K, |x| x.sinh()), &sinh, ulps);
    // 1/(1 − x) = Σ x^k; asin x = Σ (2m)!/(4^m (m!)² (2m+1)) x^{2m+1}
    assert_coefficients(
        "recip",
        &univariate(K, |x| (-x + 1.0).recip()),
        &[1.0; K + 1],
        ulps,
    );
    let want: Vec<f64> = (0..=K as u32)
        .map(|k| {
            if k % 2 == 0 {
                0.0
            } else {
                let m = (k - 1) / 2;
                factorial(2 * m) / (4f64.powi(m as i32) * factorial(m).powi(2) * k as f64)
            }
        })
        .collect();
    assert_coefficients("asin", &univariate(K, |x| x.asin()), &want, ulps);
}

#[test]
fn multivariate_exp_has_coefficients_one_over_alpha_factorial() {
    let p = scope(3, 8, |s| {
        let v = s.variables().unwrap();
        s.polynomial((v[0] + v[1] + v[2]).exp()).unwrap()
    })
    .unwrap();
    for (alpha, c) in p.terms() {
        let want: f64 = alpha.iter().map(|&a| 1.0 / factorial(a as u32)).product();
        assert!(
            (c - want).abs() <= 32.0 * EPS * want,
            "{alpha:?}: {c} vs {want}"
        );
    }
    assert_eq!(p.terms().count(), p.monomials().len());
}

/// The maximum |coefficient| of every non-constant term of `p`.
fn non_constant(p: &Polynomial) -> f64 {
    p.coefficients()[1..]
        .iter()
        .fold(0.0f64, |m, c| m.max(c.abs()))
}

#[test]
fn identities_hold_to_rounding_at_every_degree() {
    for k in [1, 4, 8, 12] {
        let (pyth, explog, at2, tanh, powf) = scope(2, k, |s| {
            let (x, y) = (s.variable(0).unwrap(), s.variable(1).unwrap());
            let u = x + y * 2.0 - x * y + 0.3;
            let (sn, cs) = u.sin_cos();
            let pyth = s.polynomial(sn * sn + cs * cs).unwrap();
            let w = x + y + 1.5;
            let explog = s.polynomial(w.ln().exp() - w).unwrap();
            let (a, b) = (y * 0.5 + 0.2, x + 1.1);
            let at2 = s.polynomial(a.atan2(b) - (a / b).atan()).unwrap();
            let tanh = s.polynomial(u.tanh() - u.sinh() / u.cosh()).unwrap();
            let powf = s.polynomial(w.powf(1.5) - w * w.sqrt()).unwrap();
            (pyth, explog, at2, tanh, powf)
        })
        .unwrap();
        let tol = 64.0 * EPS * k as f64;
        assert!((pyth.coefficients()[0] - 1.0).abs() < tol, "K = {k}");
        for (name, p) in [
            ("sin² + cos² − 1", &pyth),
            ("exp(ln w) − w", &explog),
            ("atan2 − atan", &at2),
            ("tanh − sinh/cosh", &tanh),
            ("w^1.5 − w√w", &powf),
        ] {
            let m = non_constant(p).max(if name.starts_with("sin") {
                0.0
            } else {
                p.coefficients()[0].abs()
            });
            assert!(
                m <= tol * 100.0,
                "K = {k}: {name}: largest coefficient {m:e}"
            );
        }
    }
}

#[test]
fn pendulum_potential_has_the_cosine_coefficients() {
    // H = p²/2 + n²(1 − cos q) = p²/2 + n² Σ_{m≥1} (−1)^{m+1} q^{2m}/(2m)!
    let n = 1.3;
    let k = 16;
    let h = Pendulum::new(n)
        .unwrap()
        .taylor_expansion(0.0, &SVector::from([0.0]), &SVector::from([0.0]), k)
        .unwrap();
    assert_eq!(h.coefficient(&[0, 2]).unwrap(), 0.5);
    for m in 1..=(k as u32 / 2) {
        let want = n * n * if m % 2 == 1 { 1.0 } else { -1.0 } / factorial(2 * m);
        let got = h.coefficient(&[2 * m, 0]).unwrap();
        assert!(
            (got - want).abs() <= 8.0 * k as f64 * EPS * want.abs(),
            "q^{}: {got:e} vs {want:e}",
            2 * m
        );
        assert_eq!(h.coefficient(&[2 * m - 1, 0]).unwrap().abs(), 0.0);
    }
}

hamiltonian!(HenonHeiles<2> |_s, _t, q, p|
    kinetic = p.dot(p) * 0.5,
    potential = q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0);

#[test]
fn henon_heiles_expansion_is_the_cubic_itself() {
    let (q0, p0) = (SVector::from([0.3, -0.2]), SVector::from([0.1, 0.4]));
    let h = HenonHeiles.taylor_expansion(0.0, &q0, &p0, 6).unwrap();
    for d in 4..=6 {
        assert_eq!(h.part_norm(d), 0.0, "degree {d}");
    }
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for _ in 0..50 {
        let x = [rnd(), rnd(), rnd(), rnd()];
        let q = SVector::from([q0[0] + x[0], q0[1] + x[1]]);
        let p = SVector::from([p0[0] + x[2], p0[1] + x[3]]);
        let want = HenonHeiles.value(0.0, &q, &p).unwrap();
        let got = h.eval(&x).unwrap();
        assert!(
            (got - want).abs() <= 16.0 * EPS * (1.0 + want.abs()),
            "{got} vs {want}"
        );
    }
}

#[test]
fn kepler_expansion_agrees_with_third_order_duals_along_directions() {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([1.0, 0.2]), SVector::from([-0.1, 1.0]));
    let h = kep.taylor_expansion(0.0, &q0, &p0, 3).unwrap();
    let hess = kep.hessian(0.0, &q0, &p0).unwrap().to_dmatrix();
    let ph = h.hessian();
    for i in 0..4 {
        for j in 0..4 {
            assert!((ph[i][j] - hess[(i, j)]).abs() <= 1e-14 * (1.0 + hess[(i, j)].abs()));
        }
    }
    for v in [
        [1.0, 0.0, 0.0, 0.0],
        [0.3, -0.7, 0.2, 0.5],
        [-0.4, 0.9, -1.0, 0.1],
    ] {
        let (_, d1, d2, d3) = third_derivative(
            |t: Dual3_64| {
                let q = SVector::from([t * v[0] + q0[0], t * v[1] + q0[1]]);
                let p = SVector::from([t * v[2] + p0[0], t * v[3] + p0[1]]);
                kep.hamiltonian(Dual3_64::from(0.0), &q, &p)
            },
            0.0,
        );
        for (d, want) in [(1usize, d1), (2, d2 / 2.0), (3, d3 / 6.0)] {
            let got: f64 = h
                .monomials()
                .of_degree(d)
                .map(|i| {
                    let a = h.monomials().exponents(i).unwrap();
                    h.coefficients()[i] * (0..4).map(|k| v[k].powi(a[k] as i32)).product::<f64>()
                })
                .sum();
            assert!(
                (got - want).abs() <= 1e-14 * (1.0 + want.abs()),
                "degree {d}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn non_analytic_point_and_bad_input_are_typed_errors() {
    let kep = Kepler2::new(1.0).unwrap();
    let zero = SVector::from([0.0, 0.0]);
    match kep.taylor_expansion(0.0, &zero, &SVector::from([0.0, 1.0]), 3) {
        Err(Error::NonFinite { what, .. }) => assert!(what.contains("q = [0.0, 0.0]"), "{what}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        scope(4, 1000, |_| ()),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        scope(40, 40, |_| ()),
        Err(Error::WorkLimit { .. })
    ));
    assert!(matches!(
        scope(0, 3, |_| ()),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        scope(usize::MAX, usize::MAX, |_| ()),
        Err(Error::OutOfDomain { .. })
    ));
    // n = 4, K = 24 (C(28, 4) = 20475 coefficients) fits.
    let fits = scope(4, 24, |s| s.monomials().len()).unwrap();
    assert!(fits == 20475 && fits <= MAX_SERIES_COEFFICIENTS);
    // A handle from one scope used in another.
    let stale = scope(2, 3, |s| s.variable(0).unwrap()).unwrap();
    let r = scope(2, 3, |s| {
        let x = s.variable(0).unwrap();
        s.polynomial(x * stale)
    });
    assert!(matches!(r, Err(Error::InvalidInput { .. })), "{r:?}");
    // A handle moved to another thread.
    let r = scope(2, 3, |s| {
        let x = s.variable(0).unwrap();
        let y = std::thread::spawn(move || (x * x).sin()).join().unwrap();
        assert!(y.is_poisoned());
        s.polynomial(y)
    });
    assert!(matches!(r, Err(Error::InvalidInput { .. })), "{r:?}");
    // `%` of series.
    let r = scope(1, 3, |s| {
        let x = s.variable(0).unwrap();
        let _ = x % x;
    });
    assert!(matches!(r, Err(Error::InvalidInput { .. })), "{r:?}");
}

#[test]
fn poisson_series_of_exp_eps_cos_has_bessel_coefficients() {
    // J² exp(ε cos θ) = J² [I₀(ε) + 2 Σ_k I_k(ε) cos kθ],  I_k(ε) = Σ_m (ε/2)^{2m+k}/(m!(m+k)!)
    let j0 = 1.5;
    let (h, k) = (8, 6);
    let f = fourier_taylor(&SVector::from([j0]), h, k, |j, th, e| {
        j[0] * j[0] * (e * th[0].cos()).exp()
    })
    .unwrap();
    for harm in &f.harmonics {
        let kk = harm.k[0] as u32;
        for d in 0..=k as u32 {
            for a in 0..=(k as u32 - d) {
                // coefficient of ΔJ^a ε^d
                let jfac = match a {
                    0 => j0 * j0,
                    1 => 2.0 * j0,
                    2 => 1.0,
                    _ => 0.0,
                };
                let want = if d >= kk && (d - kk) & 1 == 0 {
                    let m = (d - kk) / 2;
                    let two = if kk == 0 { 1.0 } else { 2.0 };
                    jfac * two * 0.5f64.powi(d as i32) / (factorial(m) * factorial(m + kk))
                } else {
                    0.0
                };
                let got = harm.cos.coefficient(&[a, d]).unwrap();
                assert!(
                    (got - want).abs() <= 1e-14,
                    "k = {kk}, ΔJ^{a} ε^{d}: {got:e} vs {want:e}"
                );
                assert!(harm.sin.coefficient(&[a, d]).unwrap().abs() <= 1e-14);
            }
        }
    }
    // Harmonics beyond degree K in ε vanish: the estimated tail is rounding.
    assert!(f.truncation_error() < 1e-13, "{}", f.truncation_error());
    // Truncating at H = 3 < K drops the harmonics 4..6: the estimate sees them.
    let g = fourier_taylor(&SVector::from([j0]), 3, k, |j, th, e| {
        j[0] * j[0] * (e * th[0].cos()).exp()
    })
    .unwrap();
    // dropped: k = 4 (ε⁴: 2·J₀²/2⁴/4!), k = 5, k = 6, largest single coefficient sum over k.
    let want = j0 * j0 * 2.0 * 0.5f64.powi(4) / factorial(4);
    assert!(
        g.fourier_tail >= 0.9 * want && g.fourier_tail <= 1.5 * want,
        "tail {} vs {want}",
        g.fourier_tail
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Evaluation is a ring homomorphism below the truncation degree: for `a`, `b` of degree
    /// ≤ 2 in 3 variables and K = 4, `(ab)(x) = a(x) b(x)` and `(a + b)(x) = a(x) + b(x)`.
    #[test]
    fn products_evaluate_to_products(
        ca in prop::collection::vec(-2.0f64..2.0, 10),
        cb in prop::collection::vec(-2.0f64..2.0, 10),
        x in prop::collection::vec(-1.0f64..1.0, 3),
    ) {
        let (pa, pb, prod, sum, quot) = scope(3, 4, |s| {
            let v = s.variables().unwrap();
            let mons = [Series::constant(1.0), v[0], v[1], v[2], v[0] * v[0], v[0] * v[1],
                        v[0] * v[2], v[1] * v[1], v[1] * v[2], v[2] * v[2]];
            let a: Series = ca.iter().zip(&mons).map(|(c, m)| *m * *c).sum();
            let b: Series = cb.iter().zip(&mons).map(|(c, m)| *m * *c).sum();
            let b1 = b + 10.0;
            let q = (a * b1) / b1 - a;
            (s.polynomial(a).unwrap(), s.polynomial(b).unwrap(), s.polynomial(a * b).unwrap(),
             s.polynomial(a + b).unwrap(), s.polynomial(q).unwrap())
        }).unwrap();
        let (va, vb) = (pa.eval(&x).unwrap(), pb.eval(&x).unwrap());
        prop_assert!((prod.eval(&x).unwrap() - va * vb).abs() <= 1e-13);
        prop_assert!((sum.eval(&x).unwrap() - (va + vb)).abs() <= 1e-13);
        // (ab)/b − a vanishes to rounding in every coefficient.
        prop_assert!(quot.coefficients().iter().all(|c| c.abs() <= 1e-12));
    }
}

#[test]
fn degree_24_in_four_variables_completes() {
    // Hénon–Heiles about a phase point to degree 24 (a cubic: every part of degree > 3 is zero),
    // and the dense exp(x₁ + x₂ + x₃ + x₄) against 1/α!.
    let t0 = std::time::Instant::now();
    let (q0, p0) = (SVector::from([0.1, -0.05]), SVector::from([0.2, 0.1]));
    let h = HenonHeiles.taylor_expansion(0.0, &q0, &p0, 24).unwrap();
    assert_eq!(h.monomials().len(), 20475);
    for d in 4..=24 {
        assert_eq!(h.part_norm(d), 0.0);
    }
    let hh = t0.elapsed();
    let t1 = std::time::Instant::now();
    let p = scope(4, 24, |s| {
        let v = s.variables().unwrap();
        s.polynomial((v[0] + v[1] + v[2] + v[3]).exp()).unwrap()
    })
    .unwrap();
    for (alpha, c) in p.terms().step_by(97) {
        let want: f64 = alpha.iter().map(|&a| 1.0 / factorial(a as u32)).product();
        assert!(
            (c - want).abs() <= 64.0 * EPS * want,
            "{alpha:?}: {c:e} vs {want:e}"
        );
    }
    println!(
        "n = 4, K = 24: Hénon–Heiles expansion {:.1} ms, dense exp {:.1} ms",
        hh.as_secs_f64() * 1e3,
        t1.elapsed().as_secs_f64() * 1e3
    );
}

/// `max_α |got_α − want_α|` over the coefficients of degree `≤ top`, and `max_α |want_α|`.
fn deviation(got: &Polynomial, want: &Polynomial, top: usize) -> (f64, f64) {
    let table = got.monomials();
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for i in 0..table.of_degree(top).end {
        err = err.max((got.coefficients()[i] - want.coefficients()[i]).abs());
        size = size.max(want.coefficients()[i].abs());
    }
    (err, size)
}

/// The derivation `∂/∂x_v` of the truncated algebra against the expansion of the closed-form
/// derivative: `f = exp(x + 2y) sin(z + 0.3)` about `(0.2, −0.1, 0.4)`, degree 8;
/// `∂f/∂x = f`, `∂f/∂y = 2f`, `∂f/∂z = exp(x + 2y) cos(z + 0.3)`, equal to degree 7, and the
/// derivative's degree-8 part is zero. Tolerance: every coefficient of either side comes from
/// the exp and sin/cos recurrences (≤ K steps, each a few roundings of the running coefficient
/// scale) and one truncated product, so both are within `(4K + 4)·ε·M` of the exact Taylor
/// coefficients, `M` the largest coefficient (the factor `α_v ≤ K` of the derivative is exact
/// and multiplies one rounding): `tol = 2·(4K + 4)·K·ε·M`.
#[test]
fn derivative_is_the_expansion_of_the_closed_form_derivative() {
    let k = 8;
    let (f, fz) = scope(3, k, |s| {
        let x = s.variable_at(0, 0.2).unwrap();
        let y = s.variable_at(1, -0.1).unwrap();
        let z = s.variable_at(2, 0.4).unwrap();
        let e = (x + y * 2.0).exp();
        (
            s.polynomial(e * (z + 0.3).sin()).unwrap(),
            s.polynomial(e * (z + 0.3).cos()).unwrap(),
        )
    })
    .unwrap();
    let mut two_f = f.clone();
    two_f.coefficients_mut().iter_mut().for_each(|c| *c *= 2.0);
    for (v, want) in [(0, &f), (1, &two_f), (2, &fz)] {
        let d = f.derivative(v).unwrap();
        let (err, size) = deviation(&d, want, k - 1);
        let tol = 2.0 * (4 * k + 4) as f64 * k as f64 * EPS * size;
        eprintln!("∂f/∂x_{v}: max deviation {err:e} (tolerance {tol:e})");
        assert!(err <= tol, "∂/∂x_{v}: {err:e} > {tol:e}");
        assert_eq!(d.part_norm(k), 0.0, "degree-{k} part of ∂/∂x_{v}");
    }
    assert!(f.derivative(3).is_err());
}

/// The Poisson bracket of truncated polynomials against the expansion of the bracket worked out
/// by hand. Two degrees of freedom `(q₁, q₂, p₁, p₂) = (x₀, x₁, x₂, x₃)` and a parameter
/// `λ = x₄` (a passive variable), about `(0.3, −0.2, 0.5, 0.7, 1.1)`, degree 7:
///
/// `f = q₁² p₂ + λ sin(q₂) p₁`, `g = exp(q₁) p₁ p₂ + q₂ p₂²`,
/// `{f, g} = 2q₁p₂·e^{q₁}p₂ − λ sin q₂·e^{q₁}p₁p₂ + λ cos q₂·p₁(e^{q₁}p₁ + 2q₂p₂) − q₁²p₂²`,
///
/// equal to degree 6 (the bracket differentiates once); the value at the point also against the
/// crate's AD bracket [`hamilton_jacobi::brackets::poisson_bracket`] (λ fixed). Tolerance as in
/// the derivative test, with four products of derivatives summed: `tol = 8·(4K + 4)·K·ε·M`.
#[test]
fn poisson_bracket_is_the_expansion_of_the_closed_form_bracket() {
    let k = 7;
    let at = [0.3, -0.2, 0.5, 0.7, 1.1];
    let (f, g, want) = scope(5, k, |s| {
        let x: Vec<Series> = (0..5).map(|i| s.variable_at(i, at[i]).unwrap()).collect();
        let (q1, q2, p1, p2, lam) = (x[0], x[1], x[2], x[3], x[4]);
        let f = q1 * q1 * p2 + lam * q2.sin() * p1;
        let e = q1.exp();
        let g = e * p1 * p2 + q2 * p2 * p2;
        let want = q1 * p2 * e * p2 * 2.0 - lam * q2.sin() * e * p1 * p2
            + lam * q2.cos() * p1 * (e * p1 + q2 * p2 * 2.0)
            - q1 * q1 * p2 * p2;
        (
            s.polynomial(f).unwrap(),
            s.polynomial(g).unwrap(),
            s.polynomial(want).unwrap(),
        )
    })
    .unwrap();
    // Exact to degree K − 1 only: ask for that, so the degree-K part is empty.
    let b = f.poisson_bracket(&g, 2, k - 1).unwrap();
    let (err, size) = deviation(&b, &want, k - 1);
    let tol = 8.0 * (4 * k + 4) as f64 * k as f64 * EPS * size;
    eprintln!("{{f, g}}: max deviation {err:e} (tolerance {tol:e})");
    assert!(err <= tol, "{err:e} > {tol:e}");
    assert_eq!(b.part_norm(k), 0.0);
    // Antisymmetry: the same products with the opposite sign, summed in another order.
    let mut ba = g.poisson_bracket(&f, 2, k - 1).unwrap();
    ba.coefficients_mut().iter_mut().for_each(|c| *c = -*c);
    let (anti, _) = deviation(&ba, &b, k);
    assert!(anti <= tol, "antisymmetry defect {anti:e} > {tol:e}");
    // Truncation at a lower degree keeps exactly the coefficients of degree ≤ 3.
    let b3 = f.poisson_bracket(&g, 2, 3).unwrap();
    let top3 = b.monomials().of_degree(3).end;
    assert_eq!(&b3.coefficients()[..top3], &b.coefficients()[..top3]);
    assert_eq!(b3.part_norm(4), 0.0);
    // The value at the point against the AD bracket with λ = 1.1 fixed.
    struct F;
    impl hamilton_jacobi::PhaseFunction<2> for F {
        fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
            q[0] * q[0] * p[1] + q[1].sin() * p[0] * 1.1
        }
    }
    struct G;
    impl hamilton_jacobi::PhaseFunction<2> for G {
        fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
            q[0].exp() * p[0] * p[1] + q[1] * p[1] * p[1]
        }
    }
    let ad = hamilton_jacobi::brackets::poisson_bracket(
        &F,
        &G,
        0.0,
        &SVector::from([at[0], at[1]]),
        &SVector::from([at[2], at[3]]),
    )
    .unwrap();
    let c0 = b.coefficients()[0];
    eprintln!("{{f, g}} at the point: series {c0:e}, AD {ad:e}");
    assert!((c0 - ad).abs() <= tol, "{c0:e} against AD {ad:e}");
    assert!(f.poisson_bracket(&g, 3, k).is_err());
    assert!(f.poisson_bracket(&g, 0, k).is_err());
    let other = Polynomial::zero(5, k - 1).unwrap();
    assert!(f.poisson_bracket(&other, 2, k).is_err());
}
