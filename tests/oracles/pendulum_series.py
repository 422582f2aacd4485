# Oracle for tests/normal_form.rs (exact rational arithmetic, Python fractions; independent of the
# crate): series of
#  (1) tau/(2pi/n) = 2K(k)/pi, k = sin(a/2), in powers of a^2 (DLMF 19.5.1:
#      2K/pi = sum_j ((1/2)_j / j!)^2 m^j, m = k^2 = sin^2(a/2) = (1 - cos a)/2);
#  (2) the pendulum energy as a function of the action (n = 1): the action is
#      J(m) = (8/pi)[E(m) - (1-m)K(m)] (2E/pi = sum_j (-1/2)_j (1/2)_j/(j!)^2 m^j, DLMF 19.5.2),
#      energy 2m; Hbar(J) = 2 m(J) by series reversion.
from fractions import Fraction as F
from math import factorial
import mpmath
N = 14  # number of terms beyond the leading one

def mul(a, b):
    out = [F(0)]*len(a)
    for i, x in enumerate(a):
        if x == 0: continue
        for j, y in enumerate(b[:len(a)-i]):
            out[i+j] += x*y
    return out

def rf(x, j):
    p = F(1)
    for i in range(j): p *= (x + i)
    return p

L = N + 1
Kc = [(rf(F(1,2), j)/factorial(j))**2 for j in range(L)]
Ec = [rf(F(-1,2), j)*rf(F(1,2), j)/factorial(j)**2 for j in range(L)]
# m(x) with x = a^2: (1 - cos a)/2 = sum_{j>=1} (-1)^{j+1} x^j / (2 (2j)!)
mx = [F(0)] + [F((-1)**(j+1), 2*factorial(2*j)) for j in range(1, L)]
ratio = [F(0)]*L
p = [F(1)] + [F(0)]*(L-1)
for j in range(L):
    for i in range(L): ratio[i] += Kc[j]*p[i]
    p = mul(p, mx)
print("# tau/(2pi/n) = sum c_k a^(2k)")
for k, c in enumerate(ratio):
    print(k, c, mpmath.nstr(mpmath.mpf(c.numerator)/c.denominator, 20))
# J(m) = 4 (E - (1-m) K) coefficients
Jm = [4*(Ec[j] - Kc[j] + (Kc[j-1] if j >= 1 else 0)) for j in range(L)]
assert Jm[0] == 0 and Jm[1] == 2, Jm[:3]
# reversion: m(J) = sum b_i J^i, solve J(m(J)) = J order by order
b = [F(0), F(1,2)] + [F(0)]*(L-1)
LL = L + 1
def compose(c, s, n):
    out = [F(0)]*n; p = [F(1)] + [F(0)]*(n-1)
    for j in range(len(c)):
        for i in range(n): out[i] += c[j]*p[i]
        p = mul(p, s)
    return out
for i in range(2, LL):
    Jc = compose(Jm + [F(0)]*(LL-len(Jm)), b[:LL] + [F(0)]*(LL-len(b)), LL)
    b[i] -= Jc[i]/2
print("# Hbar(J) = sum h_j J^j (n = 1)")
for j in range(1, LL):
    c = 2*b[j]
    print(j, c, mpmath.nstr(mpmath.mpf(c.numerator)/c.denominator, 20))
