"""Reference states of the pendulum H = p^2/2 + 1 - cos q near its separatrix, for
tests/taylor_dd.rs: q0 = 3.14159 (the double), p0 = 0, at t = n periods (n = 1, 5, 100; the
times rounded to doubles exactly as peers.py rounds its span) and at t = 20.

Route 1: sin(q/2) = k sn(t + K, k), k = sin(q0/2), p = 2 k cn dn / sqrt(1 - k^2 sn^2)
(Jacobi elliptic functions, mpmath) at 50 and at 80 digits.
Route 2 (independent): mpmath.odefun (Taylor series of Hamilton's equations at working
precision) at 50 digits up to t = 20 and over one period.

Run: benches/peers/.venv/bin/python benches/peers/separatrix_reference.py
"""
import sys
import mpmath as mp


def elliptic(q0, t):
    q0 = mp.mpf(q0)
    k = mp.sin(q0 / 2)
    m = k * k
    u = mp.mpf(t) + mp.ellipk(m)
    sn, cn, dn = (mp.ellipfun(w, u, m=m) for w in ("sn", "cn", "dn"))
    s = k * sn
    return 2 * mp.asin(s), 2 * k * cn * dn / mp.sqrt(1 - s * s)


def main():
    q0 = 3.14159
    mp.mp.dps = 50
    k = mp.sin(mp.mpf(q0) / 2)
    period = 4 * mp.ellipk(k * k)
    times = [20.0] + [float(n * period) for n in (1, 5, 100)]
    print("// q0 =", repr(q0), "period =", mp.nstr(period, 30))
    for t in times:
        mp.mp.dps = 50
        q50, p50 = elliptic(q0, t)
        mp.mp.dps = 80
        q80, p80 = elliptic(q0, t)
        d = max(abs(q50 - q80), abs(p50 - p80))
        mp.mp.dps = 50
        e = (p80 * p80 / 2 + 1 - mp.cos(q80)) - (1 - mp.cos(mp.mpf(q0)))
        print(f"// t = {t!r}: q = {mp.nstr(q80, 40)}, p = {mp.nstr(p80, 40)}; "
              f"50 vs 80 digits {mp.nstr(d, 3)}, energy defect {mp.nstr(e, 3)}")
        print(f"({t!r}, {float(q80)!r}, {float(p80)!r}),")
    if len(sys.argv) > 1 and sys.argv[1] == "--odefun":
        mp.mp.dps = 50
        f = mp.odefun(lambda t, y: [y[1], -mp.sin(y[0])], 0, [mp.mpf(q0), mp.mpf(0)])
        for t in times[:2]:
            y = f(mp.mpf(t))
            q, p = elliptic(q0, t)
            print(f"// odefun t = {t!r}: |dq| = {mp.nstr(abs(y[0] - q), 3)}, "
                  f"|dp| = {mp.nstr(abs(y[1] - p), 3)}")


main()
