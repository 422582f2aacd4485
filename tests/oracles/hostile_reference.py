#!/usr/bin/env python3
"""Reference values for tests/hostile.rs: Kepler, pendulum and heavy-top entry points called with
hostile arguments (NaN, ±inf, ±0, the smallest subnormal, ±f64::MAX and out-of-domain values),
each computed with mpmath at 400 significant digits from the defining equations (not from the
crate's formulas), then rounded to the nearest double.

A call whose mathematical answer does not exist as a finite double (an argument outside the
function's domain, a NaN/inf argument, or a result beyond f64::MAX) gets no value: the library must
return a typed error there. Angles are given unreduced and reduced to (-pi, pi].

Usage: python3 tests/oracles/hostile_reference.py > tests/oracles/hostile_reference.rs
"""
import math
from mpmath import mp, mpf, sin, cos, sinh, asinh, atan, atan2, tan, tanh, sqrt, asin, pi, agm, \
    ellipf, ellipfun, findroot, log, cbrt, fmod

mp.dps = 400
MAX = 1.7976931348623157e308
HOSTILE = [math.nan, math.inf, -math.inf, 0.0, -0.0, 5e-324, MAX, -MAX]


class NoAnswer(Exception):
    pass


def lab(x):
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if x == 0.0:
        return "-0" if math.copysign(1.0, x) < 0 else "0"
    if x == 5e-324:
        return "5e-324"
    if abs(x) == MAX:
        return "MAX" if x > 0 else "-MAX"
    return repr(x)


def lit(x):
    if math.isnan(x):
        return "f64::NAN"
    if math.isinf(x):
        return "f64::INFINITY" if x > 0 else "f64::NEG_INFINITY"
    if abs(x) == MAX:
        return "f64::MAX" if x > 0 else "f64::MIN"
    r = repr(x)
    if x == 0.0 and r.startswith("-"):
        return "-0.0"
    return r


def need_finite(*xs):
    for x in xs:
        if not math.isfinite(x):
            raise NoAnswer


def to_double(v):
    # Round to nearest; beyond MAX + ulp(MAX)/2 the double overflows.
    x = float(mpf(v))
    if math.isinf(x):
        raise NoAnswer
    return x


def reduce_angle(v):
    r = fmod(mpf(v), 2 * pi)
    if r > pi:
        r -= 2 * pi
    if r <= -pi:
        r += 2 * pi
    return r


# --- Kepler ---------------------------------------------------------------------------------


def root_increasing(f, lo, hi):
    """Root of an increasing f in [lo, hi]: bisection to a narrow bracket, then secant steps."""
    lo, hi = mpf(lo), mpf(hi)
    for _ in range(200):
        mid = (lo + hi) / 2
        if f(mid) > 0:
            hi = mid
        else:
            lo = mid
    x = findroot(f, (lo, hi), solver="secant", verify=False)
    assert abs(f(x)) <= mpf(10) ** (-mp.dps + 20) * (1 + abs(x)), "root not converged"
    return x


def kepler_E(M, e):
    M, e = mpf(M), mpf(e)
    if M == 0:
        return mpf(0)
    # E − e sin E − M is increasing and E − M = e sin E lies in [−e, e].
    return root_increasing(lambda E: E - e * sin(E) - M, M - e - 1, M + e + 1)


def true_from_E(E, e):
    beta = e / (1 + sqrt(1 - e * e))
    return E + 2 * atan(beta * sin(E) / (1 - beta * cos(E)))


def E_from_true(nu, e):
    beta = e / (1 + sqrt(1 - e * e))
    return nu - 2 * atan(beta * sin(nu) / (1 + beta * cos(nu)))


def elliptic(e):
    need_finite(e)
    if not (0 <= e < 1):
        raise NoAnswer
    return mpf(e)


def solve_kepler(M, e):
    need_finite(M)
    return [kepler_E(M, elliptic(e))], False


def mean_to_true(M, e):
    need_finite(M)
    e = elliptic(e)
    return [true_from_E(kepler_E(M, e), e)], True


def eccentric_to_true(E, e):
    need_finite(E)
    return [true_from_E(mpf(E), elliptic(e))], True


def true_to_eccentric(nu, e):
    need_finite(nu)
    return [E_from_true(mpf(nu), elliptic(e))], True


def positive(*xs):
    for x in xs:
        need_finite(x)
        if not x > 0:
            raise NoAnswer


def mean_motion(mu, a):
    positive(mu, a)
    return [sqrt(mpf(mu) / mpf(a) ** 3)], False


def orbit_period(mu, a):
    positive(mu, a)
    return [2 * pi * sqrt(mpf(a) ** 3 / mpf(mu))], False


def hyperbolic_F(M, e):
    M, e = mpf(M), mpf(e)
    if M == 0:
        return mpf(0)
    s = 1 if M > 0 else -1
    M = abs(M)
    # e sinh F - F = M, increasing; F in [asinh(M/e), asinh(M/(e-1))].
    lo, hi = asinh(M / e), asinh(M / (e - 1))
    return s * root_increasing(lambda F: e * sinh(F) - F - M, lo * (1 - mpf(10) ** -10), hi * (1 + mpf(10) ** -10))


def solve_kepler_hyperbolic(M, e):
    need_finite(M, e)
    if not e > 1:
        raise NoAnswer
    return [hyperbolic_F(M, e)], False


def solve_barker(M):
    need_finite(M)
    M = mpf(M)
    # B + B^3/3 = M: the real root of B^3 + 3B - 3M = 0 (Cardano), odd in M.
    q = 3 * abs(M) / 2
    w = cbrt(q + sqrt(q * q + 1))
    return [(w - 1 / w) * (1 if M >= 0 else -1)], False


def conic_mean_to_true(M, e):
    need_finite(M, e)
    if e < 1:
        return mean_to_true(M, e)
    if e == 1:
        return [2 * atan(solve_barker(M)[0][0])], True
    F = hyperbolic_F(M, e)
    e = mpf(e)
    return [2 * atan2(sqrt(e + 1) * sinh(F / 2), sqrt(e - 1) * math_cosh(F / 2))], True


def math_cosh(x):
    from mpmath import cosh
    return cosh(x)


# --- Pendulum -------------------------------------------------------------------------------


def agm_ref(a, b):
    need_finite(a, b)
    if a < 0 or b < 0:
        raise NoAnswer
    return [agm(mpf(a), mpf(b))], False


def k_from_kc(kc):
    need_finite(kc)
    if not (0 < kc <= 1):
        raise NoAnswer
    return [pi / (2 * agm(1, mpf(kc)))], False


def sn_cn_dn(u, k, kc):
    need_finite(u, k, kc)
    if not (0 <= k <= 1 and 0 <= kc <= 1):
        raise NoAnswer
    if abs(k * k + kc * kc - 1) > 16 * 2.0 ** -52:
        raise NoAnswer
    u, k, kc = mpf(u), mpf(k), mpf(kc)
    m = k * k
    if kc == 0:
        from mpmath import sech
        return [tanh(u), sech(u), sech(u)], False
    K = pi / (2 * agm(1, kc))
    ur = fmod(u, 4 * K)
    return [ellipfun("sn", ur, m=m), ellipfun("cn", ur, m=m), ellipfun("dn", ur, m=m)], False


def separatrix_gap(a):
    need_finite(a)
    return [pi - abs(mpf(a))], False


def pendulum_period(n, a):
    positive(n)
    need_finite(a)
    if not (0 <= a < math.pi):
        raise NoAnswer
    kc = cos(mpf(a) / 2)
    return [2 * pi / (mpf(n) * agm(1, kc))], False


def period_from_gap(n, d):
    positive(n)
    need_finite(d)
    if not (0 < d <= math.pi):
        raise NoAnswer
    return [2 * pi / (mpf(n) * agm(1, sin(mpf(d) / 2)))], False


def pendulum_energy(n, th, p):
    need_finite(n, th, p)
    n, th, p = mpf(n), mpf(th), mpf(p)
    return [p * p / 2 + 2 * n * n * sin(th / 2) ** 2], False


def amplitude_from_state(n, th, p):
    positive(n)
    need_finite(th, p)
    n, th, p = mpf(n), mpf(th), mpf(p)
    k2 = sin(th / 2) ** 2 + p * p / (4 * n * n)
    if k2 >= 1:
        raise NoAnswer
    return [2 * asin(sqrt(k2))], False


def exact_state(n, th0, p0, t):
    positive(n)
    need_finite(th0, p0, t)
    n, th0, p0, t = mpf(n), mpf(th0), mpf(p0), mpf(t)
    k2 = sin(th0 / 2) ** 2 + p0 * p0 / (4 * n * n)
    if k2 < 1:
        th0 = reduce_angle(th0)
        # Libration: sin(θ/2) = k sn(u), p = 2nk cn(u), u = u0 + n t.
        k = sqrt(k2)
        m = k2
        K = pi / (2 * agm(1, sqrt(1 - m)))
        phi0 = atan2(sin(th0 / 2) / k, p0 / (2 * n * k))
        u = fmod(ellipf(phi0, m) + n * t, 4 * K)
        sn, cn = ellipfun("sn", u, m=m), ellipfun("cn", u, m=m)
        return [2 * asin(k * sn), 2 * n * k * cn], True
    if k2 == 1:
        raise NoAnswer
    # Rotation: θ/2 = am(w, κ²), κ = 1/k, w = w0 + s n k t, p = s 2nk dn(w).
    k = sqrt(k2)
    m = 1 / k2
    s = 1 if p0 > 0 else -1
    half = th0 / 2
    # Reduce θ0/2 to (−π/2, π/2] plus a multiple of π (am is quasi-periodic: am(w + 2K) = am(w) + π).
    K = pi / (2 * agm(1, sqrt(1 - m)))
    j = mp.nint(half / pi)
    w = ellipf(half - j * pi, m) + 2 * K * j + s * n * k * t
    jj = mp.floor(w / (2 * K))
    wr = w - 2 * K * jj
    am = asin(ellipfun("sn", wr, m=m))
    # am on (−K, K) from asin, continued to [K, 2K) by symmetry am(2K − w) = π − am(w).
    if wr > K:
        am = pi - am
    theta = 2 * (am + jj * pi)
    return [theta, s * 2 * n * k * ellipfun("dn", wr, m=m)], True


# --- Heavy top ------------------------------------------------------------------------------
# HeavyTop(I, J, mgl): beta = 2 mgl / I, gamma = J omega_z / I.


def top_critical_spin(i, j, mgl):
    positive(i, j, mgl)
    return [2 * sqrt(mpf(i) * mpf(mgl)) / mpf(j)], False


TOP = (1.0, 0.5, 2.0)


def release_from_rest(u2, wz):
    need_finite(u2, wz)
    if not (-1 <= u2 <= 1):
        raise NoAnswer
    i, j, mgl = map(mpf, TOP)
    beta, gamma = 2 * mgl / i, j * mpf(wz) / i
    c = gamma * gamma / (2 * beta)
    u2 = mpf(u2)
    # The other root of the cubic f(u) = (1 − u²) β (u₂ − u) − γ² (u₂ − u)² through u₂ (θ̇ = 0,
    # p_φ = p_ψ = J ω_z): β(1 − u²) = γ²(u₂ − u) → u² − 2cu + 2cu₂ − 1 = 0, the root in [−1, u₂].
    root = c - sqrt(c * c - 2 * c * u2 + 1)
    return [root], False


def fast_top_width(u2, wz):
    need_finite(u2, wz)
    if not (-1 <= u2 <= 1) or wz == 0:
        raise NoAnswer
    i, j, mgl = map(mpf, TOP)
    beta, gamma = 2 * mgl / i, j * mpf(wz) / i
    return [beta * (1 - mpf(u2) ** 2) / gamma ** 2], False


def min_spin(theta0):
    need_finite(theta0)
    if not (0 < theta0 < math.pi):
        raise NoAnswer
    i, j, mgl = map(mpf, TOP)
    c = cos(mpf(theta0))
    return [2 * sqrt(i * mgl * c) / j if c > 0 else mpf(0)], False


def steady_slow(theta0, wz):
    need_finite(theta0, wz)
    if not (0 < theta0 < math.pi):
        raise NoAnswer
    i, j, mgl = map(mpf, TOP)
    beta, gamma = 2 * mgl / i, j * mpf(wz) / i
    c = cos(mpf(theta0))
    disc = gamma * gamma - 2 * beta * c
    if disc < 0:
        raise NoAnswer
    # cos θ₀ φ̇² − γ φ̇ + β/2 = 0: the root of smaller magnitude.
    if c == 0:
        return [beta / (2 * gamma)], False
    r1, r2 = (gamma + sqrt(disc)) / (2 * c), (gamma - sqrt(disc)) / (2 * c)
    return [r1 if abs(r1) < abs(r2) else r2], False


# (name, reference, nominal arguments, extra out-of-domain / edge arguments as (position, value))
FUNCTIONS = [
    ("kepler_equation::solve_kepler", solve_kepler, [1.0, 0.5], [(1, 1.0), (1, 1.5), (1, -0.25), (1, 0.999999999)]),
    ("kepler_equation::eccentric_to_true", eccentric_to_true, [1.0, 0.5], [(1, 1.0), (1, 2.0)]),
    ("kepler_equation::true_to_eccentric", true_to_eccentric, [1.0, 0.5], [(1, 1.0), (1, 2.0)]),
    ("kepler::orbit::mean_motion", mean_motion, [1.0, 2.0], [(0, -1.0), (1, -2.0), (0, 1e300)]),
    ("kepler::orbit::period", orbit_period, [1.0, 2.0], [(0, -1.0), (1, -2.0), (1, 1e200)]),
    ("kepler_equation::solve_kepler_hyperbolic", solve_kepler_hyperbolic, [1.0, 2.0], [(1, 1.0), (1, 0.5), (1, 1.000000000000001)]),
    ("kepler_equation::solve_barker", solve_barker, [1.0], [(0, 1e308), (0, -1e200)]),
    ("kepler_equation::eccentric_anomaly", solve_kepler, [1.0, 0.5], [(1, 1.0), (1, 1.5)]),
    ("kepler_equation::hyperbolic_anomaly", solve_kepler_hyperbolic, [1.0, 2.0], [(1, 1.0), (1, 0.5)]),
    ("kepler_equation::mean_to_true", conic_mean_to_true, [1.0, 0.5], [(1, 1.0), (1, 2.0), (1, -0.25)]),
    ("kepler_equation::mean_to_true[hyperbolic]", conic_mean_to_true, [1.0, 2.0], [(1, 1.5), (1, 1e10)]),
    ("elliptic::agm", agm_ref, [1.0, 0.5], [(0, -1.0), (1, -0.5), (0, 1e300)]),
    ("elliptic::complete_k_from_complementary", k_from_kc, [0.6], [(0, 1.5), (0, -0.5), (0, 1.0), (0, 1e-300)]),
    ("elliptic::jacobi_sn_cn_dn", sn_cn_dn, [0.7, 0.6, 0.8], [(1, 1.2), (1, 0.0), (2, 1.0), (0, 1e6)]),
    ("pendulum_exact::separatrix_gap", separatrix_gap, [2.0], [(0, math.pi), (0, -2.0)]),
    ("pendulum_exact::period", pendulum_period, [1.0, 2.0], [(1, -1.0), (1, 4.0), (1, math.pi), (0, -1.0), (1, 3.141592653589792)]),
    ("pendulum_exact::period_from_gap", period_from_gap, [1.0, 1.0], [(1, 4.0), (1, -1.0), (1, math.pi), (1, 1e-300)]),
    ("pendulum_exact::energy", pendulum_energy, [1.0, 1.0, 0.5], [(1, 1e300)]),
    ("pendulum_exact::amplitude_from_state", amplitude_from_state, [1.0, 0.5, 0.3], [(1, math.pi), (2, 5.0), (0, -1.0), (1, 1e10)]),
    ("pendulum_exact::exact_state", exact_state, [1.0, 0.5, 0.3, 2.0], [(2, 5.0), (0, -1.0), (3, 1e10), (1, 1e10)]),
    ("top::HeavyTop::critical_spin", top_critical_spin, [1.0, 0.5, 2.0], [(0, -1.0), (1, -0.5), (2, -2.0)]),
    ("top_motion::release_from_rest", release_from_rest, [0.5, 10.0], [(0, 2.0), (0, -1.5), (0, 1.0), (1, 1e200)]),
    ("top_motion::fast_top_width", fast_top_width, [0.5, 10.0], [(0, 2.0), (0, -1.5), (1, 1e-200)]),
    ("top::HeavyTop::min_spin_for_steady_precession", min_spin, [1.0], [(0, 4.0), (0, -1.0), (0, 2.0)]),
    ("top::HeavyTop::steady_precession", steady_slow, [1.0, 10.0], [(0, 4.0), (1, 0.1), (0, 2.0)]),
]


def calls():
    for name, f, nominal, extra in FUNCTIONS:
        arglists = [list(nominal)]
        for i in range(len(nominal)):
            for h in HOSTILE:
                a = list(nominal)
                a[i] = h
                arglists.append(a)
        for i, v in extra:
            a = list(nominal)
            a[i] = v
            arglists.append(a)
        for a in arglists:
            try:
                vals, angle = f(*a)
                vals = [to_double(v) for v in vals]
                red = [to_double(reduce_angle(v)) for v in f(*a)[0]] if angle else []
            except NoAnswer:
                vals, red, angle = [], [], False
            yield name, a, vals, red


def main():
    print("// Generated by tests/oracles/hostile_reference.py (mpmath, 400 digits); do not edit.")
    print("// (function, arguments, reference values — empty when no finite answer exists —,")
    print("// the same values reduced to (−π, π] when they are angles).")
    print("#[allow(clippy::approx_constant, clippy::excessive_precision)]")
    print("const REFERENCE: &[Reference] = &[")
    for name, a, vals, red in calls():
        label = f"{name}({', '.join(lab(x) for x in a)})"
        print(f"    Reference {{ function: {name!r}, label: {label!r}, args: &[{', '.join(lit(x) for x in a)}], "
              f"values: &[{', '.join(lit(v) for v in vals)}], reduced: &[{', '.join(lit(v) for v in red)}] }},"
              .replace("'", '"'))
    print("];")


if __name__ == "__main__":
    main()
