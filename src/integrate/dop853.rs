//! Dormand–Prince 8(5,3): the explicit adaptive Runge–Kutta pair of Hairer's DOP853, with its
//! seventh-order dense output.
//!
//! # The method
//! Twelve stages `kᵢ = f(t + cᵢh, y + h Σⱼ aᵢⱼ kⱼ)` give the eighth-order solution
//!
//! ```math
//! y_1 = y_0 + h \sum_i b_i k_i ,
//! ```
//!
//! and two embedded differences estimate its local error: a fifth-order one
//! `err₅ = h Σ eᵢ kᵢ` and a third-order one `err₃ = h (Σ bᵢkᵢ − b̂₁k₁ − b̂₉k₉ − b̂₁₂k₁₂)`. With
//! `skᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|)` over the `n = 2N` components of `(q, p)`, DOP853 combines
//! them as
//!
//! ```math
//! \mathrm{err} = |h|\,\frac{E_5^2}{\sqrt{n\,(E_5^2 + 0.01\,E_3^2)}},\qquad
//! E_5^2 = \sum_i \Big(\frac{\sum_j e_j k_{j,i}}{sk_i}\Big)^2,\
//! E_3^2 = \sum_i \Big(\frac{\sum_j (b_j-\hat b_j) k_{j,i}}{sk_i}\Big)^2 ,
//! ```
//!
//! which behaves like `O(h⁸)` (`h¹²/h⁴`): the steps are those of an eighth-order-controlled
//! method, so the global error is proportional to the tolerance (tolerance proportionality).
//! A step is accepted when `err ≤ 1`.
//!
//! # Step-size control
//! As in the Fortran code: `fac₁₁ = err^{1/8 − 0.2β}`, `fac = fac₁₁ / err_old^β` (the
//! Gustafsson/Lund PI stabilisation; `β = 0` in the original DOP853, which is the default here),
//! `h_new = h / clamp(fac/0.9, 1/6, 1/0.333)`: growth at most ×6, shrink at most ×0.333, safety
//! factor 0.9; after a rejection the step may not grow; `|h| ≤ h_max` (default `|t₁ − t₀|`).
//! The initial step, unless given, is chosen by the algorithm of HNW II.4 (Fortran `HINIT`): a
//! first guess `0.01·‖y₀‖/‖f₀‖`, one explicit Euler step to estimate `‖y″‖`, and
//! `h = min(100 h_guess, (0.01 / max(‖f₀‖, ‖y″‖))^{1/8}, h_max)`.
//!
//! A step that produces non-finite stages (a singularity such as a collision) is rejected like a
//! step with `err = ∞` (shrink ×0.333). The run fails with [`Error::NotConverged`] (its message
//! names `t` and `h`; `iterations` = attempted steps, `residual` = last error estimate) when a step
//! other than the final one onto `t₁` would be shorter than `16 ε |t|` (the Fortran test is
//! `0.1|h| ≤ 2.3·10⁻¹⁶|t|`, i.e. `|h| ≲ 10 ε |t|`) or, at `t = 0`, below the smallest normal
//! number.
//!
//! # Step budget
//! The number of attempted steps (accepted + rejected) is bounded. By default the budget scales
//! with the span: with `h_init` the starting step (HNW II.4, which already reflects the tolerance
//! and the problem's time scale),
//!
//! ```math
//! n_{\max} = \operatorname{clamp}\big(10\,\lceil |t_1 - t_0| / |h_{\rm init}| \rceil,\
//! 10^5,\ 10^7\big),
//! ```
//!
//! the lower end being the Fortran default `NMAX = 10⁵` and the upper end bounding the work of one
//! call (about 20 s for the planar Kepler problem, at 2 µs per step). [`Dop853::with_max_steps`]
//! sets the budget explicitly. An exhausted budget is [`Error::WorkLimit`], which names the limit,
//! where the run stood and how many steps the pace so far would need.
//!
//! # Tolerances
//! `rtol` must lie in `[`[`Dop853::RTOL_MIN`]`, 1)`. Below `10·u`, with DOP853's unit roundoff
//! `u = 2.3·10⁻¹⁶`, the estimator's own rounding is comparable to the tolerance and the
//! controller can chase noise down to underflow — the Fortran code stops with "tolerances are too
//! small" there, and so does this one (an [`Error::OutOfDomain`] naming the range; ask for
//! `RTOL_MIN` itself for the tightest run). At `rtol ≥ 1` an accepted step may carry an error as
//! large as the state: no digit is asked for. `atol > 0` is used as given (it only adds to
//! `rtol·|y|`, and its scale is the user's units).
//!
//! # Compensated summation
//! Over `n` steps the plain update `y₁ = fl(y + h Σᵢ bᵢkᵢ)` adds up to `n` roundings of
//! `u|y|/2` each, a random walk `≈ √n u|y|/2` that sets the floor of long tight runs (on a
//! regularised Kepler orbit this floor, not the truncation error, ends a run below `rtol ≈ 10⁻¹⁴`).
//! [`Dop853::with_compensated_summation`] keeps the rounding error of each update as a carry
//! added to the next increment (Kahan's summation, Higham 2002 §4.3, by the error-free sum of
//! Knuth):
//!
//! ```math
//! \delta = h\sum_i b_i k_i + c,\qquad y_1 = \mathrm{fl}(y + \delta),\qquad
//! c \leftarrow (y + \delta) - y_1 \ \text{(exactly)},
//! ```
//!
//! so the state drifts by `O(u|y|)` however many steps are taken, at `2N` error-free sums per
//! step. The time is then carried the same way, as the double-length sum `t + t_lo` of the
//! steps (the plain `t ← fl(t + h)` makes the integrated span `Σ h` miss `t₁` by up to `n u|t|/2`,
//! which on a Kepler orbit becomes a phase error of that size); the final step is
//! `(t₁ − t) − t_lo`. The stages, the error estimate, the dense output and the observers see the
//! rounded states and times, as in the plain code; the default (off) is the Fortran code's update
//! bit for bit.
//!
//! # Dense output
//! The continuous extension of order 7 (Fortran `CONTD8`): three extra stages `k₁₄, k₁₅, k₁₆`
//! (`c = 0.1, 0.2, 7/9`) and, with `s = (t − t₀)/h`, `s₁ = 1 − s`,
//!
//! ```math
//! y(t) = r_0 + s\big(r_1 + s_1(r_2 + s(r_3 + s_1(r_4 + s(r_5 + s_1(r_6 + s\,r_7)))))\big),
//! ```
//!
//! `r₀ = y₀`, `r₁ = y₁ − y₀`, `r₂ = h k₁ − r₁`, `r₃ = r₁ − h k₁₃ − r₂`, `r₄…r₇ = h Σ dᵢⱼ kⱼ`.
//! The extra stages are computed lazily, the first time an observer asks for an interior point of
//! the step, so runs whose observers never interpolate pay nothing for them.
//!
//! # Work counted
//! `gradients` counts every evaluation of the vector field: `f(t₀, y₀)`, one more for the initial
//! step selection (unless `h0` is given), 11 per attempted step (stages 2–12), 1 per accepted step
//! (`k₁₃ = f(t₁, y₁)`, reused as the next step's `k₁`), and 3 per step whose dense output was used.
//! `steps` and `rejected` as usual (a rejection counts, unlike in the Fortran code, also before the
//! first acceptance).
//!
//! # References
//! * E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!   Springer 1993, doi:10.1007/978-3-540-78862-1: II.4 (starting step size), II.5 (the pair,
//!   Table 5.4 and the 8(5,3) estimator), II.6 (dense output), II.10 (DOP853).
//! * N. J. Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., SIAM 2002, §4.3
//!   (compensated summation).
//! * E. Hairer, G. Wanner, Fortran code `DOP853` (version of 11 Oct 2004), whose coefficients
//!   (from J. R. Dormand and P. J. Prince, *J. Comp. Appl. Math.* 6 (1980) 19–26) are reproduced
//!   below at their full 30-digit precision.

use super::methods;
use super::{
    stop_time, Control, Dense, FirstOrderSystem, Method, Observer, Problem, Report, State,
    StepView, Work,
};
use crate::error::{finite, positive, Error, Result};
use crate::phase::CanonicalPair;
use crate::special::double_double::{fast_two_sum, two_sum};
use nalgebra::SVector;
use num_dual::DualNum;
use std::cell::{Cell, OnceCell};
use std::time::Instant;

/// Sparse row of a Butcher tableau: `(stage index, coefficient)`, stages counted from 0.
type Row = &'static [(usize, f64)];

/// Nodes `c₁ … c₁₂` (stages 0–11) and `c₁₄ … c₁₆` of the dense output (stages 13–15; stage 12 is
/// `f(t + h, y₁)`, `c = 1`).
#[allow(clippy::excessive_precision)]
const C: [f64; 16] = [
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
];

/// Rows `aᵢⱼ` of stages 1–11 and of the dense-output stages 13–15 (index 12 unused: stage 12 is
/// `f(t + h, y₁)`).
#[allow(clippy::excessive_precision)]
const A: [Row; 16] = [
    &[],
    &[(0, 5.26001519587677318785587544488e-2)],
    &[
        (0, 1.97250569845378994544595329183e-2),
        (1, 5.91751709536136983633785987549e-2),
    ],
    &[
        (0, 2.95875854768068491816892993775e-2),
        (2, 8.87627564304205475450678981324e-2),
    ],
    &[
        (0, 2.41365134159266685502369798665e-1),
        (2, -8.84549479328286085344864962717e-1),
        (3, 9.24834003261792003115737966543e-1),
    ],
    &[
        (0, 3.7037037037037037037037037037e-2),
        (3, 1.70828608729473871279604482173e-1),
        (4, 1.25467687566822425016691814123e-1),
    ],
    &[
        (0, 3.7109375e-2),
        (3, 1.70252211019544039314978060272e-1),
        (4, 6.02165389804559606850219397283e-2),
        (5, -1.7578125e-2),
    ],
    &[
        (0, 3.70920001185047927108779319836e-2),
        (3, 1.70383925712239993810214054705e-1),
        (4, 1.07262030446373284651809199168e-1),
        (5, -1.53194377486244017527936158236e-2),
        (6, 8.27378916381402288758473766002e-3),
    ],
    &[
        (0, 6.24110958716075717114429577812e-1),
        (3, -3.36089262944694129406857109825),
        (4, -8.68219346841726006818189891453e-1),
        (5, 2.75920996994467083049415600797e1),
        (6, 2.01540675504778934086186788979e1),
        (7, -4.34898841810699588477366255144e1),
    ],
    &[
        (0, 4.77662536438264365890433908527e-1),
        (3, -2.48811461997166764192642586468),
        (4, -5.90290826836842996371446475743e-1),
        (5, 2.12300514481811942347288949897e1),
        (6, 1.52792336328824235832596922938e1),
        (7, -3.32882109689848629194453265587e1),
        (8, -2.03312017085086261358222928593e-2),
    ],
    &[
        (0, -9.3714243008598732571704021658e-1),
        (3, 5.18637242884406370830023853209),
        (4, 1.09143734899672957818500254654),
        (5, -8.14978701074692612513997267357),
        (6, -1.85200656599969598641566180701e1),
        (7, 2.27394870993505042818970056734e1),
        (8, 2.49360555267965238987089396762),
        (9, -3.0467644718982195003823669022),
    ],
    &[
        (0, 2.27331014751653820792359768449),
        (3, -1.05344954667372501984066689879e1),
        (4, -2.00087205822486249909675718444),
        (5, -1.79589318631187989172765950534e1),
        (6, 2.79488845294199600508499808837e1),
        (7, -2.85899827713502369474065508674),
        (8, -8.87285693353062954433549289258),
        (9, 1.23605671757943030647266201528e1),
        (10, 6.43392746015763530355970484046e-1),
    ],
    &[],
    &[
        (0, 5.61675022830479523392909219681e-2),
        (6, 2.53500210216624811088794765333e-1),
        (7, -2.46239037470802489917441475441e-1),
        (8, -1.24191423263816360469010140626e-1),
        (9, 1.5329179827876569731206322685e-1),
        (10, 8.20105229563468988491666602057e-3),
        (11, 7.56789766054569976138603589584e-3),
        (12, -8.298e-3),
    ],
    &[
        (0, 3.18346481635021405060768473261e-2),
        (5, 2.83009096723667755288322961402e-2),
        (6, 5.35419883074385676223797384372e-2),
        (7, -5.49237485713909884646569340306e-2),
        (10, -1.08347328697249322858509316994e-4),
        (11, 3.82571090835658412954920192323e-4),
        (12, -3.40465008687404560802977114492e-4),
        (13, 1.41312443674632500278074618366e-1),
    ],
    &[
        (0, -4.28896301583791923408573538692e-1),
        (5, -4.69762141536116384314449447206),
        (6, 7.68342119606259904184240953878),
        (7, 4.06898981839711007970213554331),
        (8, 3.56727187455281109270669543021e-1),
        (12, -1.39902416515901462129418009734e-3),
        (13, 2.9475147891527723389556272149),
        (14, -9.15095847217987001081870187138),
    ],
];

/// Weights `bᵢ` of the eighth-order solution.
#[allow(clippy::excessive_precision)]
const B: [(usize, f64); 8] = [
    (0, 5.42937341165687622380535766363e-2),
    (5, 4.45031289275240888144113950566),
    (6, 1.89151789931450038304281599044),
    (7, -5.8012039600105847814672114227),
    (8, 3.1116436695781989440891606237e-1),
    (9, -1.52160949662516078556178806805e-1),
    (10, 2.01365400804030348374776537501e-1),
    (11, 4.47106157277725905176885569043e-2),
];

/// `b̂₁, b̂₉, b̂₁₂` (Fortran `BHH1..3`): `Σ bᵢkᵢ − b̂₁k₁ − b̂₉k₉ − b̂₁₂k₁₂` is the third-order
/// error estimate.
#[allow(clippy::excessive_precision)]
const BHH: [(usize, f64); 3] = [
    (0, 0.244094488188976377952755905512),
    (8, 0.733846688281611857341361741547),
    (11, 0.220588235294117647058823529412e-1),
];

/// `eᵢ` of the fifth-order error estimate (Fortran `ER1, ER6..ER12`).
#[allow(clippy::excessive_precision)]
const E5: [(usize, f64); 8] = [
    (0, 0.1312004499419488073250102996e-1),
    (5, -0.1225156446376204440720569753e1),
    (6, -0.4957589496572501915214079952),
    (7, 0.1664377182454986536961530415e1),
    (8, -0.3503288487499736816886487290),
    (9, 0.3341791187130174790297318841),
    (10, 0.8192320648511571246570742613e-1),
    (11, -0.2235530786388629525884427845e-1),
];

/// `dᵢⱼ` of the dense output coefficients `r₄ … r₇` (Fortran `D41 … D716`).
#[allow(clippy::excessive_precision)]
const D: [[(usize, f64); 12]; 4] = [
    [
        (0, -0.84289382761090128651353491142e1),
        (5, 0.56671495351937776962531783590),
        (6, -0.30689499459498916912797304727e1),
        (7, 0.23846676565120698287728149680e1),
        (8, 0.21170345824450282767155149946e1),
        (9, -0.87139158377797299206789907490),
        (10, 0.22404374302607882758541771650e1),
        (11, 0.63157877876946881815570249290),
        (12, -0.88990336451333310820698117400e-1),
        (13, 0.18148505520854727256656404962e2),
        (14, -0.91946323924783554000451984436e1),
        (15, -0.44360363875948939664310572000e1),
    ],
    [
        (0, 0.10427508642579134603413151009e2),
        (5, 0.24228349177525818288430175319e3),
        (6, 0.16520045171727028198505394887e3),
        (7, -0.37454675472269020279518312152e3),
        (8, -0.22113666853125306036270938578e2),
        (9, 0.77334326684722638389603898808e1),
        (10, -0.30674084731089398182061213626e2),
        (11, -0.93321305264302278729567221706e1),
        (12, 0.15697238121770843886131091075e2),
        (13, -0.31139403219565177677282850411e2),
        (14, -0.93529243588444783865713862664e1),
        (15, 0.35816841486394083752465898540e2),
    ],
    [
        (0, 0.19985053242002433820987653617e2),
        (5, -0.38703730874935176555105901742e3),
        (6, -0.18917813819516756882830838328e3),
        (7, 0.52780815920542364900561016686e3),
        (8, -0.11573902539959630126141871134e2),
        (9, 0.68812326946963000169666922661e1),
        (10, -0.10006050966910838403183860980e1),
        (11, 0.77771377980534432092869265740),
        (12, -0.27782057523535084065932004339e1),
        (13, -0.60196695231264120758267380846e2),
        (14, 0.84320405506677161018159903784e2),
        (15, 0.11992291136182789328035130030e2),
    ],
    [
        (0, -0.25693933462703749003312586129e2),
        (5, -0.15418974869023643374053993627e3),
        (6, -0.23152937917604549567536039109e3),
        (7, 0.35763911791061412378285349910e3),
        (8, 0.93405324183624310003907691704e2),
        (9, -0.37458323136451633156875139351e2),
        (10, 0.10409964950896230045147246184e3),
        (11, 0.29840293426660503123344363579e2),
        (12, -0.43533456590011143754432175058e2),
        (13, 0.96324553959188282948394950600e2),
        (14, -0.39177261675615439165231486172e2),
        (15, -0.14972683625798562581422125276e3),
    ],
];

/// Hairer's unit roundoff `UROUND = 2.3·10⁻¹⁶` (slightly above `ε/2`).
const UROUND: f64 = 2.3e-16;

/// `Σⱼ coeffs_j k_j` (without the factor `h`), for any number type (the step is differentiated
/// by replaying it on dual numbers: [`super::tangent`]).
#[inline(always)]
pub(crate) fn combine<D: DualNum<f64> + Copy, const N: usize>(
    coeffs: &[(usize, f64)],
    k: &[CanonicalPair<N, D>],
) -> CanonicalPair<N, D> {
    let mut q = SVector::<D, N>::zeros();
    let mut p = SVector::<D, N>::zeros();
    for &(j, a) in coeffs {
        for i in 0..N {
            q[i] += k[j].0[i] * a;
            p[i] += k[j].1[i] * a;
        }
    }
    (q, p)
}

/// `y + h Σⱼ coeffs_j k_j`.
#[inline(always)]
pub(crate) fn advance<D: DualNum<f64> + Copy, const N: usize>(
    y: &CanonicalPair<N, D>,
    h: D,
    coeffs: &[(usize, f64)],
    k: &[CanonicalPair<N, D>],
) -> CanonicalPair<N, D> {
    let (dq, dp) = combine(coeffs, k);
    (
        SVector::from_fn(|i, _| y.0[i] + dq[i] * h),
        SVector::from_fn(|i, _| y.1[i] + dp[i] * h),
    )
}

/// Stages 2–12 of one step of size `h` from `(t, y)`, with `k[0] = f(t, y)` given, and the
/// eighth-order solution `y₁ = y + h Σᵢ bᵢ kᵢ` together with `Σᵢ bᵢ kᵢ` (which the error
/// estimate reuses): the step written once for every number type, run on reals by [`Dop853`] and
/// on dual numbers over a frozen step sequence by [`super::tangent`].
///
/// The eleven stages are written out (not looped over), so that each row `aᵢⱼ` is a constant of
/// known length: the compiler unrolls the sums and folds the coefficients and the indices into
/// the code. The sums are formed in the same order as by a loop, so the result is the same to
/// the last bit.
#[inline(always)]
pub(crate) fn stages<D, F, const N: usize>(
    field: &mut F,
    t: D,
    y: &CanonicalPair<N, D>,
    h: D,
    k: &mut [CanonicalPair<N, D>; 16],
) -> Result<(CanonicalPair<N, D>, CanonicalPair<N, D>)>
where
    D: DualNum<f64> + Copy,
    F: FnMut(D, &SVector<D, N>, &SVector<D, N>) -> Result<CanonicalPair<N, D>>,
{
    macro_rules! stage {
        ($($i:literal)*) => {$(
            let (q, p) = advance(y, h, A[$i], &k[..]);
            k[$i] = field(t + h * C[$i], &q, &p)?;
        )*};
    }
    stage!(1 2 3 4 5 6 7 8 9 10 11);
    let sum_b = combine(&B, &k[..]);
    let y1 = (
        SVector::from_fn(|i, _| y.0[i] + sum_b.0[i] * h),
        SVector::from_fn(|i, _| y.1[i] + sum_b.1[i] * h),
    );
    Ok((y1, sum_b))
}

/// `y + h s` with Kahan's compensation (Higham 2002 §4.3): the increment `δ = h s + carry` is
/// added to `y` by the error-free sum (`two_sum`), whose rounding error becomes the new `carry`.
fn compensated_update<const N: usize>(
    y: &CanonicalPair<N>,
    s: &CanonicalPair<N>,
    h: f64,
    carry: &mut CanonicalPair<N>,
) -> CanonicalPair<N> {
    let add = |y: f64, s: f64, c: &mut f64| {
        let (x, e) = two_sum(y, s * h + *c);
        *c = e;
        x
    };
    let (cq, cp) = carry;
    (
        SVector::from_fn(|i, _| add(y.0[i], s.0[i], &mut cq[i])),
        SVector::from_fn(|i, _| add(y.1[i], s.1[i], &mut cp[i])),
    )
}

/// The `2N` components of `(q, p)`.
#[inline(always)]
pub(crate) fn flat<const N: usize>(v: &CanonicalPair<N>) -> impl Iterator<Item = f64> + Clone + '_ {
    v.0.iter().chain(v.1.iter()).copied()
}

/// `√(Σ xᵢ²)`, rescaled by `max |xᵢ|` when the plain sum of squares overflows or underflows (a
/// tiny `atol` on a component near zero makes `xᵢ/skᵢ` huge); NaN propagates.
pub(crate) fn norm2(xs: impl Iterator<Item = f64> + Clone) -> f64 {
    let s: f64 = xs.clone().map(|x| x * x).sum();
    if s.is_nan() || (s.is_finite() && (s == 0.0 || s >= f64::MIN_POSITIVE)) {
        return s.sqrt();
    }
    let m = xs.clone().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * xs.map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// The weighted norms `(‖err₅‖, ‖err₃‖)` of the 8(5,3) estimator (without the factor `h`), with
/// `skᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|)`: `‖err₅‖ = √(Σᵢ (e5ᵢ/skᵢ)²)`,
/// `‖err₃‖ = √(Σᵢ (((Σbk)ᵢ − (b̂k)ᵢ)/skᵢ)²)`, the components taken in the order `q₁ … q_N,
/// p₁ … p_N`. One pass over the components; only when a sum of squares overflows or underflows
/// is it formed again by [`norm2`], rescaled.
#[inline(always)]
fn error_norms<const N: usize>(
    y: &CanonicalPair<N>,
    y1: &CanonicalPair<N>,
    e5: &CanonicalPair<N>,
    sum_b: &CanonicalPair<N>,
    bhh: &CanonicalPair<N>,
    rtol: f64,
    atol: f64,
) -> (f64, f64) {
    let (mut s5, mut s3) = (0.0f64, 0.0f64);
    let mut add = |y0: f64, y1: f64, e: f64, b: f64, bh: f64| {
        let w = atol + rtol * y0.abs().max(y1.abs());
        let x5 = e / w;
        let x3 = (b - bh) / w;
        s5 += x5 * x5;
        s3 += x3 * x3;
    };
    for i in 0..N {
        add(y.0[i], y1.0[i], e5.0[i], sum_b.0[i], bhh.0[i]);
    }
    for i in 0..N {
        add(y.1[i], y1.1[i], e5.1[i], sum_b.1[i], bhh.1[i]);
    }
    let plain = |s: f64| s.is_nan() || (s.is_finite() && (s == 0.0 || s >= f64::MIN_POSITIVE));
    if plain(s5) && plain(s3) {
        return (s5.sqrt(), s3.sqrt());
    }
    let sk = flat(y)
        .zip(flat(y1))
        .map(|(a, b): (f64, f64)| atol + rtol * a.abs().max(b.abs()));
    let err5 = norm2(flat(e5).zip(sk.clone()).map(|(e, w)| e / w));
    let err3 = norm2(
        flat(sum_b)
            .zip(flat(bhh))
            .zip(sk)
            .map(|((a, b), w)| (a - b) / w),
    );
    (err5, err3)
}

/// The start of an adaptive run of the method `name` (DOP853, RK45): the initial state, the
/// final time `t₁` and the vector field at the start, checked — `t₁` finite, `t₁ − t₀` finite
/// and non-zero, the field finite (one evaluation, which the caller counts).
///
/// # Errors
/// [`Error::NonFinite`] / [`Error::OutOfDomain`] naming what was wrong; the system's own error.
pub(crate) fn adaptive_start<S: FirstOrderSystem<N>, const N: usize>(
    name: &str,
    problem: &Problem<'_, S, N>,
) -> Result<(State<N>, f64, CanonicalPair<N>)> {
    let t1 = finite("final time t₁", problem.t1)?;
    let state = State::new(problem.start.t, problem.start.q, problem.start.p)?;
    let span = t1 - state.t;
    if !(span.is_finite() && span != 0.0) {
        return Err(Error::out_of_domain(
            "time span t₁ − t₀",
            span,
            "finite and non-zero",
        ));
    }
    let f0 = problem.system.field(state.t, &state.q, &state.p)?;
    if !pair_finite(&f0) {
        return Err(Error::NonFinite {
            what: format!(
                "{name}: vector field at the initial state t = {}, q = {:?}, p = {:?}",
                state.t, state.q, state.p
            ),
            value: f64::NAN,
        });
    }
    Ok((state, t1, f0))
}

pub(crate) fn pair_finite<const N: usize>(y: &CanonicalPair<N>) -> bool {
    y.0.iter().chain(y.1.iter()).all(|v| v.is_finite())
}

/// The DOP853 integrator (see the [module documentation](self)).
///
/// The fields are public knobs; [`Dop853::new`] and the `with_*` builders check them, and
/// [`Method::run`] checks them again (so a hand-built value with a bad knob yields an error, not a
/// panic or an endless loop).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dop853 {
    /// Relative tolerance, in `[`[`Dop853::RTOL_MIN`]`, 1)`.
    pub rtol: f64,
    /// Absolute tolerance (`> 0`).
    pub atol: f64,
    /// Initial step size magnitude; `None` selects it automatically (HNW II.4).
    pub h0: Option<f64>,
    /// Largest step size magnitude; `None` for `|t₁ − t₀|`.
    pub h_max: Option<f64>,
    /// Maximum number of attempted steps (Fortran `NMAX`); `None` (the default) for the budget
    /// that scales with the span (see the [module documentation](self#step-budget)).
    pub max_steps: Option<usize>,
    /// Safety factor (Fortran `SAFE`, default 0.9), in `(10⁻⁴, 1)`.
    pub safety: f64,
    /// Smallest step ratio `h_new/h` (Fortran `FAC1`, default 0.333), in `(0, 1]`.
    pub fac_min: f64,
    /// Largest step ratio `h_new/h` (Fortran `FAC2`, default 6), `≥ 1`.
    pub fac_max: f64,
    /// PI stabilisation exponent `β` (Fortran `BETA`; 0 in DOP853, which is the default; up to 0.2
    /// is allowed, 0.04–0.1 damps step-size oscillations).
    pub beta: f64,
    /// Whether the state update `y₁ = y + h Σᵢ bᵢkᵢ` is summed with Kahan's compensation
    /// (default `false`, the Fortran code's plain update; see the
    /// [module documentation](self#compensated-summation)).
    pub compensated: bool,
}

impl Dop853 {
    /// Smallest relative tolerance accepted: `10 u`, `u = 2.3·10⁻¹⁶` (below it the Fortran code
    /// stops with "tolerances are too small", and so does this one).
    pub const RTOL_MIN: f64 = 10.0 * UROUND;

    /// Lower end of the default step budget (the Fortran `NMAX`).
    pub const AUTO_STEPS_MIN: usize = 100_000;

    /// Upper end of the default step budget.
    pub const AUTO_STEPS_MAX: usize = 10_000_000;

    /// DOP853 with tolerances `rtol ∈ [RTOL_MIN, 1)`, `atol > 0`, the step budget that scales
    /// with the span and the Fortran defaults for everything else.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] for a non-finite tolerance or one outside its
    /// range.
    pub fn new(rtol: f64, atol: f64) -> Result<Self> {
        let m = Self {
            rtol: check_rtol(rtol)?,
            atol: positive("DOP853 absolute tolerance atol", atol)?,
            h0: None,
            h_max: None,
            max_steps: None,
            safety: 0.9,
            fac_min: 0.333,
            fac_max: 6.0,
            beta: 0.0,
            compensated: false,
        };
        m.validate()?;
        Ok(m)
    }

    /// The same with a given initial step size magnitude `h0 > 0`.
    pub fn with_h0(mut self, h0: f64) -> Result<Self> {
        self.h0 = Some(positive("DOP853 initial step h0", h0)?);
        Ok(self)
    }

    /// The same with a largest step size magnitude `h_max > 0`.
    pub fn with_h_max(mut self, h_max: f64) -> Result<Self> {
        self.h_max = Some(positive("DOP853 largest step h_max", h_max)?);
        Ok(self)
    }

    /// The same with at most `max_steps ≥ 1` attempted steps (instead of the budget that scales
    /// with the span; `usize::MAX` for no limit — the caller's choice).
    pub fn with_max_steps(mut self, max_steps: usize) -> Result<Self> {
        self.max_steps = Some(max_steps);
        self.validate()?;
        Ok(self)
    }

    /// The same with the PI exponent `β ∈ [0, 0.2]`.
    pub fn with_beta(mut self, beta: f64) -> Result<Self> {
        self.beta = beta;
        self.validate()?;
        Ok(self)
    }

    /// The same with safety factor and step ratio limits (Fortran `SAFE, FAC1, FAC2`).
    pub fn with_factors(mut self, safety: f64, fac_min: f64, fac_max: f64) -> Result<Self> {
        self.safety = safety;
        self.fac_min = fac_min;
        self.fac_max = fac_max;
        self.validate()?;
        Ok(self)
    }

    /// The same with the state update compensated (`true`) or plain (`false`, the default):
    /// see the [module documentation](self#compensated-summation).
    pub fn with_compensated_summation(mut self, compensated: bool) -> Self {
        self.compensated = compensated;
        self
    }

    /// The step budget of a run over `span` whose first step is `h_init`: `max_steps` if set,
    /// otherwise `clamp(10 ⌈|span|/|h_init|⌉, AUTO_STEPS_MIN, AUTO_STEPS_MAX)`.
    pub fn step_budget(&self, span: f64, h_init: f64) -> usize {
        step_budget(self.max_steps, span, h_init)
    }

    /// Check every knob.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] naming the bad knob.
    pub fn validate(&self) -> Result<()> {
        check_rtol(self.rtol)?;
        positive("DOP853 absolute tolerance atol", self.atol)?;
        if let Some(h0) = self.h0 {
            positive("DOP853 initial step h0", h0)?;
        }
        if let Some(h) = self.h_max {
            positive("DOP853 largest step h_max", h)?;
        }
        if self.max_steps == Some(0) {
            return Err(Error::out_of_domain("DOP853 max_steps", 0.0, "≥ 1"));
        }
        let s = finite("DOP853 safety factor", self.safety)?;
        if !(s > 1e-4 && s < 1.0) {
            return Err(Error::out_of_domain("DOP853 safety factor", s, "(1e-4, 1)"));
        }
        let f1 = finite("DOP853 fac_min", self.fac_min)?;
        if !(f1 > 0.0 && f1 <= 1.0) {
            return Err(Error::out_of_domain("DOP853 fac_min", f1, "(0, 1]"));
        }
        let f2 = finite("DOP853 fac_max", self.fac_max)?;
        if f2 < 1.0 {
            return Err(Error::out_of_domain("DOP853 fac_max", f2, "[1, ∞)"));
        }
        let b = finite("DOP853 beta", self.beta)?;
        if !(0.0..=0.2).contains(&b) {
            return Err(Error::out_of_domain("DOP853 beta", b, "[0, 0.2]"));
        }
        Ok(())
    }
}

/// The step budget of an adaptive run over `span` whose first step is `h_init` (see the
/// [module documentation](self#step-budget)): `max_steps` if set, otherwise
/// `clamp(10 ⌈|span|/|h_init|⌉, AUTO_STEPS_MIN, AUTO_STEPS_MAX)`.
pub(crate) fn step_budget(max_steps: Option<usize>, span: f64, h_init: f64) -> usize {
    if let Some(n) = max_steps {
        return n;
    }
    let estimate = 10.0 * (span / h_init).abs().ceil();
    if estimate.is_nan() {
        return Dop853::AUTO_STEPS_MAX;
    }
    // `as` saturates; the clamp bounds it.
    (estimate as usize).clamp(Dop853::AUTO_STEPS_MIN, Dop853::AUTO_STEPS_MAX)
}

/// The [`Error::WorkLimit`] of an adaptive run (`method` its name, `builder` its type) that has
/// used its budget of `limit` attempted steps at `t` of `[t₀, t₁]` (`times = [t₀, t, t₁]`); `auto`
/// when the budget is the default one.
pub(crate) fn budget_exhausted(
    method: &str,
    builder: &str,
    auto: bool,
    limit: usize,
    times: [f64; 3],
) -> Error {
    let [t0, t, t1] = times;
    let done = ((t - t0) / (t1 - t0)).abs();
    let pace = if done > 0.0 {
        format!(
            "at the pace so far about {:e} steps would reach t₁",
            (limit as f64 / done).ceil()
        )
    } else {
        "no step was accepted".to_string()
    };
    Error::WorkLimit {
        what: format!("{method} attempted steps"),
        limit,
        detail: format!(
            "at t = {t:e} of [{t0:e}, {t1:e}], {:.3}% of the span; {pace}",
            100.0 * done
        ),
        hint: format!(
            "raise it with {builder}::with_max_steps(n){}, or shorten the span",
            if auto {
                " (the default budget 10·|t₁ − t₀|/h_init lies between 1e5 and 1e7)"
            } else {
                ""
            }
        ),
    }
}

/// `rtol ∈ [RTOL_MIN, 1)` (see the [module documentation](self#tolerances)).
fn check_rtol(rtol: f64) -> Result<f64> {
    let r = finite("DOP853 relative tolerance rtol", rtol)?;
    if (Dop853::RTOL_MIN..1.0).contains(&r) {
        Ok(r)
    } else {
        Err(Error::out_of_domain(
            "DOP853 relative tolerance rtol",
            r,
            format!(
                "[{:e}, 1): below 10u = {:e} the error estimate is rounding noise (use \
                 Dop853::RTOL_MIN for the tightest run); at 1 or above no digit is asked for",
                Dop853::RTOL_MIN,
                Dop853::RTOL_MIN
            ),
        ))
    }
}

/// Dense output of one DOP853 step (Fortran `CONTD8`); the three extra stages and the
/// coefficients `r₀ … r₇` are formed on the first call of [`Dense::at`].
struct Dop853Dense<'a, S, const N: usize> {
    system: &'a S,
    prev: &'a State<N>,
    next: &'a State<N>,
    h: f64,
    /// Stages `k₁ … k₁₃` of the step (slots 13–15 are filled lazily in `rcont`).
    k: &'a [CanonicalPair<N>; 16],
    rcont: OnceCell<[CanonicalPair<N>; 8]>,
    evaluations: Cell<usize>,
}

impl<S: FirstOrderSystem<N>, const N: usize> Dop853Dense<'_, S, N> {
    fn coefficients(&self) -> [CanonicalPair<N>; 8] {
        let (t0, h) = (self.prev.t, self.h);
        let y0 = (self.prev.q, self.prev.p);
        let mut k = *self.k;
        for i in 13..16 {
            let (q, p) = advance(&y0, h, A[i], &k[..]);
            // A failure inside the dense output shows as NaN in the interpolant.
            k[i] = self.system.field(t0 + C[i] * h, &q, &p).unwrap_or((
                SVector::from_element(f64::NAN),
                SVector::from_element(f64::NAN),
            ));
        }
        self.evaluations.set(self.evaluations.get() + 3);
        let ydiff = (self.next.q - self.prev.q, self.next.p - self.prev.p);
        let bspl = (k[0].0 * h - ydiff.0, k[0].1 * h - ydiff.1);
        let r3 = (
            ydiff.0 - k[12].0 * h - bspl.0,
            ydiff.1 - k[12].1 * h - bspl.1,
        );
        let mut r = [y0, ydiff, bspl, r3, y0, y0, y0, y0];
        for (slot, d) in r[4..].iter_mut().zip(D.iter()) {
            let (q, p) = combine(d, &k[..]);
            *slot = (q * h, p * h);
        }
        r
    }
}

impl<S: FirstOrderSystem<N>, const N: usize> Dense<N> for Dop853Dense<'_, S, N> {
    fn at(&self, t: f64) -> State<N> {
        if t == self.prev.t {
            return *self.prev;
        }
        if t == self.next.t {
            return *self.next;
        }
        let r = self.rcont.get_or_init(|| self.coefficients());
        let s = (t - self.prev.t) / self.h;
        let s1 = 1.0 - s;
        let eval = |c: usize| -> SVector<f64, N> {
            let pick = |i: usize| if c == 0 { r[i].0 } else { r[i].1 };
            let conpar = pick(4) + (pick(5) + (pick(6) + pick(7) * s) * s1) * s;
            pick(0) + (pick(1) + (pick(2) + (pick(3) + conpar * s1) * s) * s1) * s
        };
        State {
            t,
            q: eval(0),
            p: eval(1),
        }
    }
}

/// How [`initial_step`] measures vectors and which power it takes: the weighted norm, plain
/// (`‖x‖ = √(Σ xᵢ²)`, Fortran `HINIT`) or root mean square (`‖x‖ = √(Σ xᵢ²/n)`, SciPy's
/// `select_initial_step`), and the exponent `1/(p̂ + 1)`, `p̂` the order of the error estimate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StartRule {
    /// Root-mean-square norm instead of the plain one.
    pub rms: bool,
    /// `1/(p̂ + 1)`.
    pub exponent: f64,
}

/// Starting step size (HNW II.4: Fortran `HINIT`, and SciPy's `select_initial_step`, which
/// differ in the norm only, [`StartRule`]), signed like `dir`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<S: FirstOrderSystem<N>, const N: usize>(
    system: &S,
    y0: &State<N>,
    f0: &CanonicalPair<N>,
    dir: f64,
    h_max: f64,
    rtol: f64,
    atol: f64,
    rule: StartRule,
    work: &mut Work,
) -> Result<f64> {
    let sk = |v: f64| atol + rtol * v.abs();
    let y = (y0.q, y0.p);
    let root_n = if rule.rms {
        ((2 * N) as f64).sqrt()
    } else {
        1.0
    };
    // ‖f₀‖ and ‖y₀‖ in the weighted norm (Fortran DNF = ‖f₀‖², DNY = ‖y₀‖²).
    let dnf = norm2(flat(&y).zip(flat(f0)).map(|(yi, fi)| fi / sk(yi))) / root_n;
    let dny = norm2(flat(&y).map(|yi| yi / sk(yi))) / root_n;
    let mut h = if dnf <= 1e-5 || dny <= 1e-5 {
        1e-6
    } else {
        (dny / dnf) * 0.01
    };
    if !(h > 0.0 && h.is_finite()) {
        h = 1e-6;
    }
    h = h.min(h_max);
    let h_signed = h * dir;
    let y1 = (y.0 + f0.0 * h_signed, y.1 + f0.1 * h_signed);
    let f1 = system.field(y0.t + h_signed, &y1.0, &y1.1)?;
    work.gradients += 1;
    let der2 = norm2(
        flat(&y)
            .zip(flat(&f1).zip(flat(f0)))
            .map(|(yi, (f1i, f0i))| (f1i - f0i) / sk(yi)),
    ) / root_n
        / h;
    let der12 = der2.max(dnf);
    let h1 = if !der12.is_finite() {
        // The Euler probe hit a singularity or overflowed: fall back on the first guess, reduced.
        1e-3 * h
    } else if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(rule.exponent)
    };
    let h = (100.0 * h).min(h1).min(h_max);
    if h > 0.0 && h.is_finite() {
        Ok(h * dir)
    } else {
        Ok(1e-6f64.min(h_max) * dir)
    }
}

impl<S: FirstOrderSystem<N>, const N: usize> Method<S, N> for Dop853 {
    fn label(&self) -> String {
        format!(
            "{} rtol={:e} atol={:e}",
            methods::DOP853.label(),
            self.rtol,
            self.atol
        )
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.validate()?;
        let clock = Instant::now();
        let system = problem.system;
        let mut work = Work::default();
        let (rtol, atol) = (self.rtol, self.atol);
        let (mut state, t1, f0) = adaptive_start("DOP853", problem)?;
        let span = t1 - state.t;
        let dir = span.signum();
        let h_max = self.h_max.unwrap_or(f64::INFINITY).min(span.abs());
        let expo1 = 1.0 / 8.0 - self.beta * 0.2;
        let (facc1, facc2) = (1.0 / self.fac_min, 1.0 / self.fac_max);
        let n_comp = (2 * N) as f64;

        // k[0..12] stages of the step, k[12] = f(t + h, y₁); 13..16 for dense output.
        let zero = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        let mut k: [CanonicalPair<N>; 16] = [zero; 16];
        k[0] = f0;
        work.gradients += 1;
        let mut h = match self.h0 {
            Some(h0) => h0.min(h_max) * dir,
            None => initial_step(
                system,
                &state,
                &k[0],
                dir,
                h_max,
                rtol,
                atol,
                StartRule {
                    rms: false,
                    exponent: 1.0 / 8.0,
                },
                &mut work,
            )?,
        };
        let max_steps = self.step_budget(span, h);
        let t0 = state.t;
        observer.start(&state);

        // The low-order parts of the compensated state update (zero when it is off).
        let mut carry = zero;
        let mut t_lo = 0.0;
        let mut facold: f64 = 1e-4;
        let mut reject = false;
        let mut attempts = 0usize;
        let mut last_err = f64::NAN;
        loop {
            if attempts >= max_steps {
                return Err(budget_exhausted(
                    "DOP853",
                    "Dop853",
                    self.max_steps.is_none(),
                    max_steps,
                    [t0, state.t, t1],
                ));
            }
            // The final step ends exactly at t₁ whatever its size (a span shorter than 16ε|t| is
            // still integrated); every other step must be resolvable at t.
            let mut last = false;
            // Fortran: (x + 1.01h − x_end)·sign > 0; compared on the remaining span so that
            // rounding t + 1.01h at large |t| cannot leave a sliver behind.
            // With compensation the time is the double-length sum `state.t + t_lo`.
            let remaining = (t1 - state.t) - t_lo;
            if 1.01 * h.abs() >= remaining.abs() {
                h = remaining;
                last = true;
            }
            let h_min = (16.0 * f64::EPSILON * state.t.abs()).max(f64::MIN_POSITIVE);
            if !last && (h.is_nan() || h.abs() < h_min) {
                return Err(Error::NotConverged {
                    what: format!(
                        "DOP853 step size at t = {}: |h| = {:e} < 16ε|t| (singularity or \
                         stiffness; last error estimate {:e})",
                        state.t,
                        h.abs(),
                        last_err
                    ),
                    iterations: attempts,
                    residual: last_err,
                });
            }
            attempts += 1;

            // Stages 2–12.
            let y = (state.q, state.p);
            let (y1, sum_b) = stages(&mut |t, q, p| system.field(t, q, p), state.t, &y, h, &mut k)?;
            work.gradients += 11;
            let (t_new, t_lo_new) = match (last, self.compensated) {
                (true, _) => (t1, 0.0),
                (false, false) => (state.t + h, 0.0),
                (false, true) => {
                    let (t, e) = two_sum(state.t, h);
                    fast_two_sum(t, t_lo + e)
                }
            };

            // Error estimate (8(5,3)).
            let bhh = combine(&BHH, &k);
            let e5 = combine(&E5, &k);
            let (err5, err3) = error_norms(&y, &y1, &e5, &sum_b, &bhh, rtol, atol);
            let mut err = if err5 == 0.0 {
                0.0
            } else {
                h.abs() * err5 * (err5 / err5.hypot(0.1 * err3)) / n_comp.sqrt()
            };
            let mut k13 = zero;
            if err.is_finite() && err <= 1.0 && pair_finite(&y1) {
                k13 = system.field(t_new, &y1.0, &y1.1)?;
                work.gradients += 1;
                if !pair_finite(&k13) {
                    err = f64::INFINITY;
                }
            }
            if !err.is_finite() || !pair_finite(&y1) {
                err = f64::INFINITY;
            }
            last_err = err;

            let fac11 = err.powf(expo1);
            // `x⁰ = 1` exactly: DOP853's default β = 0 costs no second power.
            let fac = if self.beta == 0.0 {
                fac11
            } else {
                fac11 / facold.powf(self.beta)
            };
            let fac = (fac / self.safety).min(facc1).max(facc2);
            let mut h_new = h / fac;
            if err <= 1.0 {
                facold = err.max(1e-4);
                work.steps += 1;
                k[12] = k13;
                let y1 = match self.compensated {
                    true => match compensated_update(&y, &sum_b, h, &mut carry) {
                        // Near overflow the carry may not be representable: the plain update.
                        y1c if pair_finite(&y1c) => y1c,
                        _ => {
                            carry = zero;
                            y1
                        }
                    },
                    false => y1,
                };
                let next = State {
                    t: t_new,
                    q: y1.0,
                    p: y1.1,
                };
                let control;
                let mut stop_state = None;
                {
                    let dense = Dop853Dense {
                        system,
                        prev: &state,
                        next: &next,
                        h,
                        k: &k,
                        rcont: OnceCell::new(),
                        evaluations: Cell::new(0),
                    };
                    control = observer.step(&StepView {
                        prev: &state,
                        next: &next,
                        dense: &dense,
                    });
                    if let Control::StopAt(ts) = control {
                        let ts = stop_time(ts, &state, &next)?;
                        stop_state = Some(dense.at(ts));
                    }
                    work.gradients += dense.evaluations.get();
                }
                match control {
                    Control::Continue => {}
                    Control::Stop => {
                        return Ok(Report {
                            last: next,
                            stopped: !last,
                            work,
                            elapsed: clock.elapsed(),
                        });
                    }
                    Control::StopAt(_) => {
                        let last = stop_state.unwrap_or(next);
                        return Ok(Report {
                            stopped: last.t != t1,
                            last,
                            work,
                            elapsed: clock.elapsed(),
                        });
                    }
                }
                if last {
                    return Ok(Report {
                        last: next,
                        stopped: false,
                        work,
                        elapsed: clock.elapsed(),
                    });
                }
                state = next;
                t_lo = t_lo_new;
                k[0] = k13;
                if h_new.abs() > h_max {
                    h_new = dir * h_max;
                }
                if reject {
                    h_new = dir * h_new.abs().min(h.abs());
                }
                reject = false;
            } else {
                h_new = h / facc1.min(fac11 / self.safety);
                reject = true;
                work.rejected += 1;
            }
            h = h_new;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Row sums `Σⱼ aᵢⱼ = cᵢ` and the quadrature conditions `Σ bᵢ cᵢ^m = 1/(m+1)`, `m ≤ 7`, of the
    /// eighth-order weights; the error weights integrate constants exactly to zero
    /// (`Σ eᵢ = 0`, `Σ bᵢ − b̂ = 0` to rounding). Catches a mistyped coefficient.
    #[test]
    fn tableau_conditions() {
        for i in 1..16 {
            if i == 12 {
                continue;
            }
            let s: f64 = A[i].iter().map(|&(_, a)| a).sum();
            let scale: f64 = A[i].iter().map(|&(_, a)| a.abs()).sum();
            assert!(
                (s - C[i]).abs() <= 4.0 * f64::EPSILON * scale,
                "row {i}: {s} vs {}",
                C[i]
            );
        }
        for m in 0..8 {
            let s: f64 = B.iter().map(|&(j, b)| b * C[j].powi(m)).sum();
            assert!((s - 1.0 / (m as f64 + 1.0)).abs() <= 1e-14, "m = {m}: {s}");
        }
        let s: f64 = E5.iter().map(|&(_, e)| e).sum();
        assert!(s.abs() <= 1e-14, "Σe = {s}");
        let s: f64 = BHH.iter().map(|&(_, b)| b).sum();
        assert!((s - 1.0).abs() <= 1e-14, "Σb̂ = {s}");
        // Σ bᵢ aᵢⱼ-type condition (order 3): Σ bᵢ cᵢ Σⱼ aᵢⱼ cⱼ = 1/8.
        let s: f64 = B
            .iter()
            .map(|&(i, b)| b * C[i] * A[i].iter().map(|&(j, a)| a * C[j]).sum::<f64>())
            .sum();
        assert!((s - 1.0 / 8.0).abs() <= 1e-14, "{s}");
    }
}
