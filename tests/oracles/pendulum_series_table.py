# Exact-rational oracle for every order the crate's pendulum series accept (tests/normal_form.rs,
# `coefficients_match_exact_rationals_at_every_order`). Python `fractions` only: independent of the
# crate. Writes tests/oracles/pendulum_series_table.txt with lines
#     <series> <k> <hi> <lo>
# where hi = float(exact) (correctly rounded) and lo = float(exact - hi), so hi + lo represents
# the exact rational to about 1e-32 relative. Series:
#   c     tau/(2pi/n) = 2K(k)/pi = sum c_k a^(2k), k = 0..64     (DLMF 19.5.1, m = sin^2(a/2))
#   f     omega/n = 1/(2K/pi)    = sum f_k a^(2k), k = 0..64     (series reciprocal of c)
#   sigma (omega/n)^2            = sum sigma_k a^(2k), k = 0..64 (f squared)
#   h     Hbar(J) = sum h_j J^j (n = 1), j = 1..41, by reverting the action
#         J(m) = (8/pi)[E(m) - (1-m)K(m)] (DLMF 19.5.2), energy 2m.
# Usage: python3 tests/oracles/pendulum_series_table.py > tests/oracles/pendulum_series_table.txt
from fractions import Fraction as F
from math import factorial

NC = 64   # MAX_LINDSTEDT_ORDER (also covers MAX_PENDULUM_ORDER = 40 for c)
NH = 41   # MAX_PENDULUM_ORDER + 1: the energy of the order-40 normal form reaches J^41


def mul(a, b, n):
    out = [F(0)] * n
    for i, x in enumerate(a[:n]):
        if x == 0:
            continue
        for j, y in enumerate(b[:n - i]):
            out[i + j] += x * y
    return out


def rf(x, j):
    p = F(1)
    for i in range(j):
        p *= x + i
    return p


def compose(c, s, n):
    """sum_j c_j s(x)^j truncated to n terms (s_0 = 0)."""
    out = [F(0)] * n
    p = [F(1)] + [F(0)] * (n - 1)
    for cj in c[:n]:
        for i in range(n):
            out[i] += cj * p[i]
        p = mul(p, s, n)
    return out


def emit(name, k, x):
    hi = float(x)
    lo = float(x - F(hi))
    print(name, k, repr(hi), repr(lo))


L = NC + 1
Kc = [(rf(F(1, 2), j) / factorial(j)) ** 2 for j in range(L)]
mx = [F(0)] + [F((-1) ** (j + 1), 2 * factorial(2 * j)) for j in range(1, L)]
c = compose(Kc, mx, L)
# reciprocal f = 1/c (c_0 = 1)
f = [F(1)] + [F(0)] * (L - 1)
for k in range(1, L):
    f[k] = -sum(c[j] * f[k - j] for j in range(1, k + 1))
sigma = mul(f, f, L)
for k in range(L):
    emit("c", k, c[k])
for k in range(L):
    emit("f", k, f[k])
for k in range(L):
    emit("sigma", k, sigma[k])

# Energy: J(m) = 4 (E - (1-m) K) coefficients (with the 8/pi, 2E/pi and 2K/pi series).
LH = NH + 1
Ec = [rf(F(-1, 2), j) * rf(F(1, 2), j) / factorial(j) ** 2 for j in range(LH)]
Kh = Kc[:LH]
Jm = [4 * (Ec[j] - Kh[j] + (Kh[j - 1] if j >= 1 else 0)) for j in range(LH)]
assert Jm[0] == 0 and Jm[1] == 2
# reversion m(J) = sum b_i J^i with J(m(J)) = J, order by order
b = [F(0), F(1, 2)] + [F(0)] * (LH - 2)
for i in range(2, LH):
    Jc = compose(Jm, b, i + 1)
    b[i] -= Jc[i] / 2
for j in range(1, LH):
    emit("h", j, 2 * b[j])
