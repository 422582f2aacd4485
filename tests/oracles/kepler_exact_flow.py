# Oracle for tests/kepler_precision.rs: the exact Kepler flow (mu = 1, planar) of given double
# states, in mpmath at 60 digits, by the classical route, independent of the crate: elements from
# the state, Kepler's equation M = E - e sin E solved by Newton's method, Lagrange's f and g in the
# eccentric anomaly (Danby 1988, 6.8; Battin 1999, 4.3).
#
# States: the 100-period problem of benches/peers (q = (1 - e, 0), p = (0, sqrt((1 + e)/(1 - e))),
# t1 = 100 * 2 * pi in doubles) for e = 0, 0.5, 0.9, 0.99, each also with every input component
# moved up by one ulp (the sensitivity of the flow to its input), and at two more times
# (100.25 and 100.5 periods, in doubles).
#
# Each line: e tag q1 q2 p1 p2 t then the final state x = (q1, q2, p1, p2) as 4 pairs hi lo
# (hi the double nearest to x, lo the double nearest to x - hi), all in Python's shortest
# round-trip repr. Run: python3 tests/oracles/kepler_exact_flow.py > tests/oracles/kepler_exact_flow.txt
import math

import mpmath as mp

mp.mp.dps = 60


def flow(x0, t):
    qx, qy, px, py = (mp.mpf(v) for v in x0)
    t = mp.mpf(t)
    r0 = mp.sqrt(qx * qx + qy * qy)
    a = 1 / (2 / r0 - (px * px + py * py))
    n = a ** mp.mpf(-1.5)
    rv = qx * px + qy * py
    ecos = 1 - r0 / a
    esin = rv / mp.sqrt(a)
    e = mp.sqrt(ecos * ecos + esin * esin)
    e0 = mp.atan2(esin, ecos) if e != 0 else mp.mpf(0)
    m = e0 - esin + n * t
    big = mp.floor(m / (2 * mp.pi) + mp.mpf(0.5)) * 2 * mp.pi
    mr = m - big
    ecc = mp.mpf(0) if e == 0 else e
    ea = mr + (ecc if mr >= 0 else -ecc) * mp.mpf(0.85)
    for _ in range(300):
        d = (ea - ecc * mp.sin(ea) - mr) / (1 - ecc * mp.cos(ea))
        ea -= d
        if abs(d) < mp.mpf(10) ** -57:
            break
    else:
        raise RuntimeError("Kepler's equation did not converge")
    de = ea + big - e0
    s, c = mp.sin(de), mp.cos(de)
    r = a + (r0 - a) * c + rv * mp.sqrt(a) * s
    f = 1 - a / r0 * (1 - c)
    g = t - (de - s) / n
    fd = -mp.sqrt(a) / (r * r0) * s
    gd = 1 - a / r * (1 - c)
    return [f * qx + g * px, f * qy + g * py, fd * qx + gd * px, fd * qy + gd * py]


def pair(x):
    hi = float(x)
    return hi, float(x - mp.mpf(hi))


def main():
    out = []
    for e in (0.0, 0.5, 0.9, 0.99):
        x0 = [1.0 - e, 0.0, 0.0, math.sqrt((1.0 + e) / (1.0 - e))]
        t1 = 100 * 2.0 * math.pi
        cases = [("base", x0, t1)]
        for i, name in enumerate(("q1", "q2", "p1", "p2")):
            x = list(x0)
            x[i] = math.nextafter(x[i], math.inf)
            cases.append(("ulp_" + name, x, t1))
        cases.append(("t100.25", x0, 100.25 * 2.0 * math.pi))
        cases.append(("t100.5", x0, 100.5 * 2.0 * math.pi))
        for tag, x, t in cases:
            vals = [v for xi in flow(x, t) for v in pair(xi)]
            out.append(" ".join([repr(e), tag] + [repr(v) for v in x + [t] + vals]))
    print("\n".join(out))


if __name__ == "__main__":
    main()
