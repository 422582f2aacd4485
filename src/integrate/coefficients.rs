//! Coefficient tables of splitting and composition methods, as `const` data with their sources.
//!
//! A method for `H = A + B` with exactly solvable flows `φ^A_t`, `φ^B_t` is a word
//!
//! ```math
//! \Psi_h = \varphi^{X_m}_{c_m h} \circ \dots \circ \varphi^{X_2}_{c_2 h} \circ \varphi^{X_1}_{c_1 h},
//! \qquad X_i \in \{A, B\}\ \text{alternating},
//! ```
//!
//! applied from the right (`c₁` first). For explicit splitting `A = T(p)` (a *drift*) and
//! `B = V(q)` (a *kick*); for Wisdom–Holman `A` is the Kepler Hamiltonian (an exact Kepler drift)
//! and `B` the perturbation.
//!
//! Two shapes of table are stored ([`Scheme`]):
//!
//! * [`Scheme::Sequence`] — the coefficients `c₁, c₂, …` written out, the first flow named;
//! * [`Scheme::Composition`] — a symmetric composition `Ψ_h = Φ_{γ_s h} ∘ … ∘ Φ_{γ_1 h}` of the
//!   drift–kick–drift Störmer–Verlet step `Φ_h = φ^A_{h/2} ∘ φ^B_h ∘ φ^A_{h/2}`, stored as the
//!   first half `γ₁, …, γ_{(s+1)/2}` (outermost first, the middle weight last) exactly as the
//!   literature tabulates it. Adjacent half-drifts merge, so the word is
//!   `A(γ₁/2) B(γ₁) A((γ₁+γ₂)/2) B(γ₂) … B(γ_s) A(γ_s/2)`: `s` kicks and `s + 1` drifts per step.
//!
//! # Digits and their verification
//! Every table was checked against the order conditions in 50-digit arithmetic (mpmath): the
//! step map of a generic symmetric second-order method `exp(hX₁ + h³X₃ + h⁵X₅ + h⁷X₇ + h⁹X₉)`
//! with random 4×4 matrices `Xₖ` (for the compositions), or of `exp(hA)`, `exp(hB)` with random
//! `A`, `B` (for the splitting sequences), was composed as a truncated power series in `h` and its
//! logarithm compared with `h X₁` (resp. `h(A + B)`); all coefficients through `h^p` vanish to the
//! precision of the stored digits (reported per table below). Tables published with fewer than 17
//! digits were re-solved from the order conditions (Newton in 50 digits, starting from the
//! published values) and are stored with the refined digits; the unit tests below check the
//! linear conditions (consistency, symmetry, `Σγᵢᵏ = 0` for odd `k < p`) in `f64`.
#![allow(clippy::excessive_precision, clippy::unreadable_literal)]

/// Which part of the Hamiltonian a sub-step flows along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// `A`: the drift `q += h ∇T(p)` (splitting) or the Kepler flow (Wisdom–Holman).
    A,
    /// `B`: the kick `p −= h ∇V(q)` (splitting) or `p −= h ∇H₁(q)` (Wisdom–Holman).
    B,
}

/// The shape of a coefficient table (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Alternating flows starting with `first`, with the coefficients written out.
    Sequence {
        /// The flow of the first sub-step.
        first: Flow,
        /// `c₁, c₂, …` (alternating `first`, the other, `first`, …).
        coefficients: &'static [f64],
    },
    /// Symmetric composition of drift–kick–drift Störmer–Verlet, stored as its first half
    /// `γ₁, …, γ_{(s+1)/2}` (the last entry the middle weight); `s` is odd.
    Composition {
        /// The first half of the weights, outermost first, middle weight last.
        half: &'static [f64],
    },
}

/// A splitting or composition method: its family name, order, coefficients and source. Its
/// label, `"<name>, <s> stages, order <p>"` ([`Table::label`]), adds the stage count
/// ([`Table::stages`]) and the order (the naming scheme of [`methods`](super::methods)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    /// Family name, e.g. `"Kahan–Li"` (the label adds stages and order).
    pub name: &'static str,
    /// Classical order (for Wisdom–Holman: the order in `h` at fixed perturbation size).
    pub order: u32,
    /// Whether the word is a palindrome (a symmetric, time-reversible method).
    pub symmetric: bool,
    /// The coefficients.
    pub scheme: Scheme,
    /// Where the coefficients come from.
    pub reference: &'static str,
}

impl Table {
    /// Stages: force evaluations (`B` sub-steps, kicks) per step of a long run, the closing kick
    /// of a step merged with the opening kick of the next when the word begins and ends with one
    /// (both act at the same point). Verlet: 1; a composition of `s` Verlet steps: `s`;
    /// Blanes–Moan `SRKN₆ᵇ`: 6; `SABA_n`, `SBAB_n`: `n`.
    pub const fn stages(&self) -> u32 {
        match self.scheme {
            // A B A … with n sub-steps has ⌊n/2⌋ kicks; B A B … has ⌈n/2⌉, of which the last is
            // merged when n is odd (the word ends with a kick): ⌊n/2⌋ either way.
            Scheme::Sequence { coefficients, .. } => coefficients.len() as u32 / 2,
            Scheme::Composition { half } => {
                if half.is_empty() {
                    0
                } else {
                    2 * half.len() as u32 - 1
                }
            }
        }
    }

    /// The label, `"<name>, <s> stages, order <p>"`, e.g. `"Kahan–Li, 17 stages, order 8"`.
    pub fn label(&self) -> String {
        super::methods::label(self.name, self.stages(), self.order)
    }

    /// Number of composition weights `s` (1 for a plain sequence).
    pub fn composition_stages(&self) -> usize {
        match self.scheme {
            Scheme::Sequence { .. } => 1,
            Scheme::Composition { half } => 2 * half.len() - 1,
        }
    }

    /// The composition weights `γ₁ … γ_s` in full (empty for a plain sequence).
    pub fn composition_weights(&self) -> Vec<f64> {
        match self.scheme {
            Scheme::Sequence { .. } => Vec::new(),
            Scheme::Composition { half } => {
                let s = 2 * half.len() - 1;
                (0..s).map(|i| half[i.min(s - 1 - i)]).collect()
            }
        }
    }

    /// Call `f(flow, c)` for every sub-step in order, adjacent sub-steps of the same flow merged
    /// (`c` multiplies the step size). Stops at the first error.
    #[inline]
    pub fn for_each_sub_step<E>(
        &self,
        mut f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        match self.scheme {
            Scheme::Sequence {
                first,
                coefficients,
            } => {
                let mut flow = first;
                for &c in coefficients {
                    f(flow, c)?;
                    flow = match flow {
                        Flow::A => Flow::B,
                        Flow::B => Flow::A,
                    };
                }
                Ok(())
            }
            Scheme::Composition { half } => {
                let s = 2 * half.len() - 1;
                let gamma = |i: usize| half[i.min(s - 1 - i)];
                let mut previous = 0.0;
                for i in 0..s {
                    let g = gamma(i);
                    f(Flow::A, 0.5 * (previous + g))?;
                    f(Flow::B, g)?;
                    previous = g;
                }
                f(Flow::A, 0.5 * previous)
            }
        }
    }

    /// The sub-steps as a list `(flow, c)` (merged as in
    /// [`for_each_sub_step`](Self::for_each_sub_step)).
    pub fn sub_steps(&self) -> Vec<(Flow, f64)> {
        let mut out = Vec::new();
        let _ = self.for_each_sub_step(|flow, c| {
            out.push((flow, c));
            Ok::<(), ()>(())
        });
        out
    }

    /// Number of `A` and `B` sub-steps per step, `(drifts, kicks)`: the evaluations one step of the
    /// stateless [`OneStep`](super::OneStep) costs. (When the word begins and ends with a `B`
    /// sub-step — kick–drift–kick Verlet, Blanes–Moan, `SBAB_n` — a long run with FSAL would save
    /// one kick per step: the last kick of a step and the first of the next act at the same `q`.)
    pub fn evaluations(&self) -> (usize, usize) {
        let (mut a, mut b) = (0, 0);
        for (flow, _) in self.sub_steps() {
            match flow {
                Flow::A => a += 1,
                Flow::B => b += 1,
            }
        }
        (a, b)
    }
}

// ---------------------------------------------------------------------------------------------
// First- and second-order splittings
// ---------------------------------------------------------------------------------------------

/// Symplectic Euler, kick then drift: `p₁ = p₀ − h∇V(q₀)`, `q₁ = q₀ + h∇T(p₁)` (Hairer, Lubich &
/// Wanner, *Geometric Numerical Integration*, 2nd ed., Springer 2006, eq. I.1.9;
/// doi:10.1007/3-540-30666-8). Order 1.
pub const SYMPLECTIC_EULER_KD: Table = Table {
    name: "symplectic Euler (kick–drift)",
    order: 1,
    symmetric: false,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[1.0, 1.0],
    },
    reference: "Hairer, Lubich & Wanner 2006, eq. I.1.9",
};

/// Symplectic Euler, drift then kick: `q₁ = q₀ + h∇T(p₀)`, `p₁ = p₀ − h∇V(q₁)` — the adjoint of
/// [`SYMPLECTIC_EULER_KD`] (Hairer, Lubich & Wanner 2006, eq. I.1.10). Order 1.
pub const SYMPLECTIC_EULER_DK: Table = Table {
    name: "symplectic Euler (drift–kick)",
    order: 1,
    symmetric: false,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[1.0, 1.0],
    },
    reference: "Hairer, Lubich & Wanner 2006, eq. I.1.10",
};

/// Störmer–Verlet, kick–drift–kick (velocity Verlet): `B(½) A(1) B(½)` (Hairer, Lubich & Wanner
/// 2003, "Geometric numerical integration illustrated by the Störmer–Verlet method", Acta Numerica
/// 12, 399–450, doi:10.1017/S0962492902000144). Order 2; two kicks per stateless step, one per step
/// in a long run with FSAL.
pub const VERLET_KDK: Table = Table {
    name: "Störmer–Verlet (kick–drift–kick)",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[0.5, 1.0, 0.5],
    },
    reference: "Hairer, Lubich & Wanner 2003, Acta Numerica 12, 399",
};

/// Störmer–Verlet, drift–kick–drift (position Verlet): `A(½) B(1) A(½)`; one kick per step. Order 2.
/// The base method of every [`Scheme::Composition`].
pub const VERLET_DKD: Table = Table {
    name: "Störmer–Verlet (drift–kick–drift)",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[0.5, 1.0, 0.5],
    },
    reference: "Hairer, Lubich & Wanner 2003, Acta Numerica 12, 399",
};

// ---------------------------------------------------------------------------------------------
// Symmetric compositions of Störmer–Verlet
// ---------------------------------------------------------------------------------------------

/// Yoshida's fourth-order triple jump, `γ₁ = γ₃ = 1/(2 − 2^{1/3})`, `γ₂ = −2^{1/3}/(2 − 2^{1/3})`
/// (H. Yoshida, "Construction of higher order symplectic integrators", Phys. Lett. A 150 (1990)
/// 262–268, doi:10.1016/0375-9601(90)90092-3; also Creutz & Gocksch 1989, Suzuki 1990).
/// Digits from the closed form in 50-digit arithmetic; order conditions vanish to 1e−50.
pub const YOSHIDA3: Table = Table {
    name: "Yoshida triple jump",
    order: 4,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[1.351207191959657634047688, -1.702414383919315268095376],
    },
    reference: "Yoshida 1990, Phys. Lett. A 150, 262, eq. (4.14)",
};

/// Suzuki's five-stage fourth-order composition `(p, p, 1 − 4p, p, p)`, `p = 1/(4 − 4^{1/3})`
/// (M. Suzuki, "Fractal decomposition of exponential operators with applications to many-body
/// theories and Monte Carlo simulations", Phys. Lett. A 146 (1990) 319–323,
/// doi:10.1016/0375-9601(90)90962-N). Digits from the closed form (50 digits).
pub const SUZUKI5: Table = Table {
    name: "Suzuki",
    order: 4,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.4144907717943757371423541,
            0.4144907717943757371423541,
            -0.6579630871775029485694163,
        ],
    },
    reference: "Suzuki 1990, Phys. Lett. A 146, 319",
};

/// Yoshida's sixth-order composition, solution A (s = 7): `w₃, w₂, w₁, w₀, w₁, w₂, w₃` with
/// `w₀ = 1 − 2(w₁ + w₂ + w₃)` (Yoshida 1990, Table 1). Yoshida printed 15 digits; the 26-digit
/// values are those tabulated by Hairer, Lubich & Wanner 2006, §V.3.2 (also in SeLaLib's
/// `sll_m_time_composition`, whose middle weight carries the wrong sign); the middle weight is
/// `1 − 2Σ` in 50 digits. Order conditions through `h⁶` vanish to 2e−25 (26-digit rounding).
pub const YOSHIDA7: Table = Table {
    name: "Yoshida (solution A)",
    order: 6,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.78451361047755726381949763,
            0.23557321335935813368479318,
            -1.17767998417887100694641568,
            1.31518632068391121888424974,
        ],
    },
    reference: "Yoshida 1990, Phys. Lett. A 150, 262, Table 1 (A); digits HLW 2006 §V.3.2",
};

/// Yoshida's eighth-order composition, solution D (s = 15): `w₇, …, w₁, w₀, w₁, …, w₇`
/// (Yoshida 1990, Table 2). The published 15-digit values satisfy the order conditions only to
/// 3e−12 (they are accurate to about 13 digits); these are the solution of the conditions
/// re-solved by Newton in 50 digits from the published values (the nearest root; largest change
/// 2.3e−13), with residuals below 1e−47.
pub const YOSHIDA15: Table = Table {
    name: "Yoshida (solution D)",
    order: 8,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.9148442462297915667487935,
            0.253693336566211354146146,
            -1.444852236860605157694731,
            -0.1582406353680501752040668,
            1.938139137622525986579186,
            -1.960610232975310807607633,
            0.1027998493917964406981151,
            1.708453070787281584668379,
        ],
    },
    reference: "Yoshida 1990, Phys. Lett. A 150, 262, Table 2 (D); refined to 25 digits",
};

/// Kahan & Li's sixth-order composition with s = 9 (W. Kahan & R.-C. Li, "Composition constants
/// for raising the orders of unconventional schemes for ordinary differential equations", Math.
/// Comp. 66 (1997) 1089–1099, doi:10.1090/S0025-5718-97-00873-9; 26 digits as tabulated in Hairer,
/// Lubich & Wanner 2006, eq. V.3.13, and in SeLaLib). Order conditions vanish to 1e−26.
pub const KAHAN_LI9: Table = Table {
    name: "Kahan–Li",
    order: 6,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.39216144400731413927925056,
            0.33259913678935943859974864,
            -0.70624617255763935980996482,
            0.08221359629355080023149045,
            0.79854399093482996339895035,
        ],
    },
    reference: "Kahan & Li 1997, Math. Comp. 66, 1089; HLW 2006 eq. V.3.13",
};

/// Kahan & Li's eighth-order composition with s = 17 (Kahan & Li 1997; 26 digits as in Hairer,
/// Lubich & Wanner 2006, eq. V.3.14, DifferentialEquations.jl `KahanLi8`, SeLaLib). Order
/// conditions vanish to 2e−27.
pub const KAHAN_LI17: Table = Table {
    name: "Kahan–Li",
    order: 8,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.13020248308889008087881763,
            0.56116298177510838456196441,
            -0.38947496264484728640807860,
            0.15884190655515560089621075,
            -0.39590389413323757733623154,
            0.18453964097831570709183254,
            0.25837438768632204729397911,
            0.29501172360931029887096624,
            -0.60550853383003451169892108,
        ],
    },
    reference: "Kahan & Li 1997, Math. Comp. 66, 1089; HLW 2006 eq. V.3.14",
};

/// Tenth-order composition with s = 35 (M. Sofroniou & G. Spaletta, "Derivation of symmetric
/// composition constants for symmetric integrators", Optim. Methods Softw. 20 (2005) 597–613;
/// tabulated in Hairer, Lubich & Wanner 2006, eq. V.3.15). Often filed under Kahan & Li (the
/// method family is theirs; this s = 35 set is Sofroniou & Spaletta's, cf.
/// DifferentialEquations.jl `SofSpa10`). 32-digit values (Huayno's `SS_m35`, which agree with the
/// 26-digit table of HLW/SeLaLib to 4e−27); order conditions through `h¹⁰` vanish to 2e−32.
pub const SOFRONIOU_SPALETTA35: Table = Table {
    name: "Sofroniou–Spaletta",
    order: 10,
    symmetric: true,
    scheme: Scheme::Composition {
        half: &[
            0.078795722521686419263907679337684,
            0.31309610341510852776481247192647,
            0.027918383235078066109520273275299,
            -0.22959284159390709415121339679655,
            0.13096206107716486317465685927961,
            -0.26973340565451071434460973222411,
            0.074973343155891435666137105641410,
            0.11199342399981020488957508073640,
            0.36613344954622675119314812353150,
            -0.39910563013603589787862981058340,
            0.10308739852747107731580277001372,
            0.41143087395589023782070411897608,
            -0.0048663605831352617621956593099771,
            -0.39203335370863990644808193642610,
            0.051942502962449647037182904015976,
            0.050665090759924496335874344156866,
            0.049674370639729879054568800279461,
            0.049317735759594537917680008339338,
        ],
    },
    reference: "Sofroniou & Spaletta 2005, Optim. Methods Softw. 20, 597; HLW 2006 eq. V.3.15",
};

// ---------------------------------------------------------------------------------------------
// Optimised splitting
// ---------------------------------------------------------------------------------------------

/// Blanes & Moan's optimised fourth-order method `SRKN₆ᵇ` (S. Blanes & P. C. Moan, "Practical
/// symplectic partitioned Runge–Kutta and Runge–Kutta–Nyström methods", J. Comput. Appl. Math. 142
/// (2002) 313–330, doi:10.1016/S0377-0427(01)00492-7, Table 3):
/// `B(b₁) A(a₁) B(b₂) A(a₂) B(b₃) A(a₃) B(b₄) A(a₃) B(b₃) A(a₂) B(b₂) A(a₁) B(b₁)`,
/// `a₃ = ½ − a₁ − a₂`, `b₄ = 1 − 2(b₁ + b₂ + b₃)`. Fourth order for any `A + B` (a symmetric
/// method needs only the two third-degree conditions beyond consistency), with an error constant
/// optimised for `T` quadratic in `p`. The paper prints 15 digits of `a₁, a₂, b₁, b₂, b₃`; they
/// satisfy the order conditions to 1.4e−16. Here `a₁, b₁, b₂` are the published decimals (taken as
/// exact) and `a₂, b₃` are re-solved from the two conditions in 50 digits (changes 1.4e−14 and
/// 2.8e−15); residual below 1e−50. Seven kicks per stateless step (six with FSAL).
pub const BLANES_MOAN6: Table = Table {
    name: "Blanes–Moan SRKN6b",
    order: 4,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[
            0.0829844064174052,
            0.245298957184271,
            0.396309801498368,
            0.6048726657110944231093285,
            -0.03905630492234584477961968,
            -0.3501716228953654231093285,
            0.1195241940131452895592394,
            -0.3501716228953654231093285,
            -0.03905630492234584477961968,
            0.6048726657110944231093285,
            0.396309801498368,
            0.245298957184271,
            0.0829844064174052,
        ],
    },
    reference: "Blanes & Moan 2002, J. Comput. Appl. Math. 142, 313, Table 3 (SRKN6b)",
};

// ---------------------------------------------------------------------------------------------
// Laskar–Robutel SABA_n / SBAB_n (for Wisdom–Holman: A = Kepler, B = perturbation)
// ---------------------------------------------------------------------------------------------

// The B sub-steps of SABA_n sit at the n Gauss–Legendre nodes of [0, 1] with the Gauss weights;
// those of SBAB_n at the n + 1 Gauss–Lobatto nodes with the Lobatto weights (J. Laskar & P.
// Robutel, "High order symplectic integrators for perturbed Hamiltonian systems", Celest. Mech.
// Dyn. Astron. 80 (2001) 39–62, doi:10.1023/A:1012098603882, Tables 1–2). Error
// O(ε h^{2n} + ε² h²) for H = A + εB. Irrational entries in 25 digits from the closed forms.

/// `SABA₁` (drift–kick–drift): `A(½) B(1) A(½)`.
pub const SABA1: Table = Table {
    name: "Laskar–Robutel SABA",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[0.5, 1.0, 0.5],
    },
    reference: "Laskar & Robutel 2001, Celest. Mech. Dyn. Astron. 80, 39, Table 1",
};

/// `SABA₂`: `c₁ = ½ − √3/6`, `c₂ = √3/3`, `d₁ = ½`.
pub const SABA2: Table = Table {
    name: "Laskar–Robutel SABA",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[
            0.2113248654051871177454256,
            0.5,
            0.5773502691896257645091488,
            0.5,
            0.2113248654051871177454256,
        ],
    },
    reference: "Laskar & Robutel 2001, Table 1",
};

/// `SABA₃`: `c₁ = ½ − √15/10`, `c₂ = √15/10`, `d₁ = 5/18`, `d₂ = 4/9`.
pub const SABA3: Table = Table {
    name: "Laskar–Robutel SABA",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[
            0.1127016653792583114820735,
            5.0 / 18.0,
            0.3872983346207416885179265,
            4.0 / 9.0,
            0.3872983346207416885179265,
            5.0 / 18.0,
            0.1127016653792583114820735,
        ],
    },
    reference: "Laskar & Robutel 2001, Table 1",
};

/// `SABA₄`: `c₁ = ½ − √(525 + 70√30)/70`, `c₂ = (√(525 + 70√30) − √(525 − 70√30))/70`,
/// `c₃ = √(525 − 70√30)/35`, `d₁ = ¼ − √30/72`, `d₂ = ¼ + √30/72`.
pub const SABA4: Table = Table {
    name: "Laskar–Robutel SABA",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::A,
        coefficients: &[
            0.06943184420297371238802676,
            0.173927422568726928686532,
            0.2605776340045981552106404,
            0.326072577431273071313468,
            0.3399810435848562648026658,
            0.326072577431273071313468,
            0.2605776340045981552106404,
            0.173927422568726928686532,
            0.06943184420297371238802676,
        ],
    },
    reference: "Laskar & Robutel 2001, Table 1",
};

/// `SBAB₁` (kick–drift–kick; the classical Wisdom–Holman map): `B(½) A(1) B(½)`.
pub const SBAB1: Table = Table {
    name: "Wisdom–Holman",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[0.5, 1.0, 0.5],
    },
    reference: "Wisdom & Holman 1991, Astron. J. 102, 1528; Laskar & Robutel 2001, Table 2",
};

/// `SBAB₂`: `c₂ = ½`, `d₁ = 1/6`, `d₂ = 2/3`.
pub const SBAB2: Table = Table {
    name: "Laskar–Robutel SBAB",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[1.0 / 6.0, 0.5, 2.0 / 3.0, 0.5, 1.0 / 6.0],
    },
    reference: "Laskar & Robutel 2001, Table 2",
};

/// `SBAB₃`: `c₂ = ½ − √5/10`, `c₃ = √5/5`, `d₁ = 1/12`, `d₂ = 5/12`.
pub const SBAB3: Table = Table {
    name: "Laskar–Robutel SBAB",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[
            1.0 / 12.0,
            0.2763932022500210303590826,
            5.0 / 12.0,
            0.4472135954999579392818347,
            5.0 / 12.0,
            0.2763932022500210303590826,
            1.0 / 12.0,
        ],
    },
    reference: "Laskar & Robutel 2001, Table 2",
};

/// `SBAB₄`: `c₂ = ½ − √21/14`, `c₃ = √21/14`, `d₁ = 1/20`, `d₂ = 49/180`, `d₃ = 16/45`.
pub const SBAB4: Table = Table {
    name: "Laskar–Robutel SBAB",
    order: 2,
    symmetric: true,
    scheme: Scheme::Sequence {
        first: Flow::B,
        coefficients: &[
            1.0 / 20.0,
            0.1726731646460114281008538,
            49.0 / 180.0,
            0.3273268353539885718991462,
            16.0 / 45.0,
            0.3273268353539885718991462,
            49.0 / 180.0,
            0.1726731646460114281008538,
            1.0 / 20.0,
        ],
    },
    reference: "Laskar & Robutel 2001, Table 2",
};

// ---------------------------------------------------------------------------------------------
// Symplectic correctors of the Wisdom–Holman map (drift–kick–drift kernel)
// ---------------------------------------------------------------------------------------------

/// A symplectic corrector of the drift–kick–drift Wisdom–Holman map
/// `Φ_h = φ^A_{h/2} ∘ φ^B_h ∘ φ^A_{h/2}` for `H = A + εB` (J. Wisdom, M. Holman & J. Touma,
/// "Symplectic correctors", Fields Inst. Commun. 10 (1996) 217–244; J. Wisdom, Astron. J. 131
/// (2006) 2294; the coefficients of orders 3, 5, 7, 11, 17 from H. Rein & D. Tamayo, "WHFast",
/// Mon. Not. R. Astron. Soc. 452 (2015) 376–388, doi:10.1093/mnras/stv1257, §2.3). The
/// corrector is a near-identity symplectic map built from the same two flows,
///
/// ```math
/// C_h = Z(a_m h, b_m h) \circ \dots \circ Z(a_1 h, b_1 h),\qquad
/// Z(a, b) = \varphi^A_{a} \circ \varphi^B_{-b} \circ \varphi^A_{-2a} \circ \varphi^B_{b}
///   \circ \varphi^A_{a},
/// ```
///
/// (`Z(a₁h, b₁h)` applied first; inside `Z` the right-most flow first), chosen so that
/// `C_h ∘ Φ_h ∘ C_h⁻¹ = φ^H_h + O(ε h^{k+1} + ε² h³)` per step: a run `C ∘ Φⁿ ∘ C⁻¹` has error
/// `O(ε h^{k} + ε² h²)` over a fixed span for a corrector of order `k`, against `O(ε h²)` for
/// `Φⁿ` alone. `Z(a, b)⁻¹ = Z(−a, b)`, so `C⁻¹` is the reversed word with `a ↦ −a`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corrector {
    /// The order `k` of the corrector.
    pub order: u32,
    /// The pairs `(a_i, b_i)`, `Z(a₁h, b₁h)` first.
    pub stages: &'static [(f64, f64)],
    /// Where the coefficients come from.
    pub reference: &'static str,
}

impl Corrector {
    /// Kepler drifts and kicks of one application of `C` or `C⁻¹`, adjacent drifts merged and
    /// the drifts that merge to zero left out (at most `(2m + 1, 2m)` for `m` stages).
    pub fn evaluations(&self) -> (usize, usize) {
        let (mut drifts, mut kicks) = (0, 0);
        let counted: Result<(), ()> = self.for_each_sub_step(false, |flow, c| {
            if c != 0.0 {
                match flow {
                    Flow::A => drifts += 1,
                    Flow::B => kicks += 1,
                }
            }
            Ok(())
        });
        debug_assert!(counted.is_ok());
        (drifts, kicks)
    }

    /// Run the word of `C` (or of `C⁻¹` when `inverse`) over the step `h`: `f(flow, c)` for each
    /// sub-step `φ^{flow}_{c h}` in the order applied, adjacent drifts merged.
    pub fn for_each_sub_step<E>(
        &self,
        inverse: bool,
        mut f: impl FnMut(Flow, f64) -> Result<(), E>,
    ) -> Result<(), E> {
        let m = self.stages.len();
        let mut pending = 0.0;
        for i in 0..m {
            let (a, b) = if inverse {
                let (a, b) = self.stages[m - 1 - i];
                (-a, b)
            } else {
                self.stages[i]
            };
            // Z(a, b) in the order applied: A(a) B(b) A(−2a) B(−b) A(a).
            f(Flow::A, pending + a)?;
            f(Flow::B, b)?;
            f(Flow::A, -2.0 * a)?;
            f(Flow::B, -b)?;
            pending = a;
        }
        if m > 0 {
            f(Flow::A, pending)?;
        }
        Ok(())
    }
}

// a_k = k √(7/40); the b's in 50 digits (Rein & Tamayo 2015, Table 1 digits).
const CA1: f64 = 0.41833001326703777398908601289259374469640768464934;
const CA2: f64 = 0.83666002653407554797817202578518748939281536929867;
const CA3: f64 = 1.2549900398011133219672580386777812340892230539480;
const CA4: f64 = 1.6733200530681510959563440515703749787856307385973;
const CA5: f64 = 2.0916500663351888699454300644629687234820384232467;
const CA6: f64 = 2.5099800796022266439345160773555624681784461078960;
const CA7: f64 = 2.9283100928692644179236020902481562128748537925454;
const CA8: f64 = 3.3466401061363021919126881031407499575712614771947;
const CB31: f64 = -0.024900596027799867499350357910273437184309981229127;
const CB51: f64 = -0.0083001986759332891664501193034244790614366604097090;
const CB52: f64 = 0.041500993379666445832250596517122395307183302048545;
const CB71: f64 = 0.0024926811426922105779030593952776964450539008582219;
const CB72: f64 = -0.018270923246702131478062356884535264841652263842597;
const CB73: f64 = 0.053964399093127498721765893493510877532452806339655;
const CB111: f64 = 0.00020361579647854651301632818774633716473696537436847;
const CB112: f64 = -0.0023487215292295354188307328851055489876255097419754;
const CB113: f64 = 0.012309078592019946317544564763237909911330686448336;
const CB114: f64 = -0.038121613681288650508647613260247372125243616270670;
const CB115: f64 = 0.072593394748842738674253180742744961827622366521517;
const CB171: f64 = -0.0000043347415473373580190650223498124944896789841432241;
const CB172: f64 = 0.000076436355227935738363241846979413475106795392377415;
const CB173: f64 = -0.00063599983075817658983166881625078545864140848560259;
const CB174: f64 = 0.0033132577069380655655490196833451994080066801611459;
const CB175: f64 = -0.012071760822342291062449751726959664253913904872527;
const CB176: f64 = 0.032422198864713580293681523029577130832258806467604;
const CB177: f64 = -0.065192863576377893658290760803725762027864651086787;
const CB178: f64 = 0.093056103771425958591541059067553547100903397724386;

const CORRECTOR_REFERENCE: &str =
    "Wisdom, Holman & Touma 1996, Fields Inst. Commun. 10, 217; Rein & Tamayo 2015, MNRAS 452, 376";

/// Third-order corrector: 2 stages.
pub const CORRECTOR3: Corrector = Corrector {
    order: 3,
    stages: &[(CA1, -CB31), (-CA1, CB31)],
    reference: CORRECTOR_REFERENCE,
};

/// Fifth-order corrector: 4 stages.
pub const CORRECTOR5: Corrector = Corrector {
    order: 5,
    stages: &[(-CA2, -CB51), (-CA1, -CB52), (CA1, CB52), (CA2, CB51)],
    reference: CORRECTOR_REFERENCE,
};

/// Seventh-order corrector: 6 stages.
pub const CORRECTOR7: Corrector = Corrector {
    order: 7,
    stages: &[
        (-CA3, -CB71),
        (-CA2, -CB72),
        (-CA1, -CB73),
        (CA1, CB73),
        (CA2, CB72),
        (CA3, CB71),
    ],
    reference: CORRECTOR_REFERENCE,
};

/// Eleventh-order corrector: 10 stages.
pub const CORRECTOR11: Corrector = Corrector {
    order: 11,
    stages: &[
        (-CA5, -CB111),
        (-CA4, -CB112),
        (-CA3, -CB113),
        (-CA2, -CB114),
        (-CA1, -CB115),
        (CA1, CB115),
        (CA2, CB114),
        (CA3, CB113),
        (CA4, CB112),
        (CA5, CB111),
    ],
    reference: CORRECTOR_REFERENCE,
};

/// Seventeenth-order corrector: 16 stages.
pub const CORRECTOR17: Corrector = Corrector {
    order: 17,
    stages: &[
        (-CA8, -CB171),
        (-CA7, -CB172),
        (-CA6, -CB173),
        (-CA5, -CB174),
        (-CA4, -CB175),
        (-CA3, -CB176),
        (-CA2, -CB177),
        (-CA1, -CB178),
        (CA1, CB178),
        (CA2, CB177),
        (CA3, CB176),
        (CA4, CB175),
        (CA5, CB174),
        (CA6, CB173),
        (CA7, CB172),
        (CA8, CB171),
    ],
    reference: CORRECTOR_REFERENCE,
};

/// The shipped correctors, lowest order first.
pub const CORRECTORS: [&Corrector; 5] = [
    &CORRECTOR3,
    &CORRECTOR5,
    &CORRECTOR7,
    &CORRECTOR11,
    &CORRECTOR17,
];

#[cfg(test)]
mod tests {
    use super::super::methods::{Construction, METHODS};
    use super::*;

    /// The coefficient tables of the crate's methods ([`METHODS`]), and whether each is a Kepler
    /// splitting.
    fn tables() -> impl Iterator<Item = (&'static Table, bool)> {
        METHODS.iter().filter_map(|m| match m.construction {
            Construction::Splitting(t) => Some((t, false)),
            Construction::KeplerSplitting(t) => Some((t, true)),
            _ => None,
        })
    }

    fn sums(t: &Table) -> (f64, f64) {
        let (mut a, mut b) = (0.0, 0.0);
        for (flow, c) in t.sub_steps() {
            match flow {
                Flow::A => a += c,
                Flow::B => b += c,
            }
        }
        (a, b)
    }

    /// Consistency `Σ a = Σ b = 1` and palindromic symmetry, for every table; `f64` sums of at most
    /// 71 terms of size ≤ 2 round to within 71·2·2⁻⁵³ ≈ 2e−14 (bound 1e−14 × the Σ|c| actually seen).
    #[test]
    fn every_table_is_consistent_and_symmetric() {
        assert_eq!(tables().count(), 20);
        for (t, _) in tables() {
            let (a, b) = sums(t);
            let scale: f64 = t.sub_steps().iter().map(|(_, c)| c.abs()).sum();
            let tol = 4.0 * f64::EPSILON * scale;
            assert!(
                (a - 1.0).abs() <= tol,
                "{}: Σa − 1 = {:e}",
                t.label(),
                a - 1.0
            );
            assert!(
                (b - 1.0).abs() <= tol,
                "{}: Σb − 1 = {:e}",
                t.label(),
                b - 1.0
            );
            let st = t.sub_steps();
            let palindrome = (0..st.len()).all(|i| {
                let (f, c) = st[i];
                let (g, d) = st[st.len() - 1 - i];
                f == g && c == d
            });
            assert_eq!(palindrome, t.symmetric, "{}", t.label());
            if let Scheme::Composition { .. } = t.scheme {
                let w = t.composition_weights();
                let s: f64 = w.iter().sum();
                assert!(
                    (s - 1.0).abs() <= tol,
                    "{}: Σγ − 1 = {:e}",
                    t.label(),
                    s - 1.0
                );
            }
        }
    }

    /// For a symmetric composition of a symmetric second-order method, order p needs
    /// `Σγᵢᵏ = 0` for odd k = 3, 5, …, p − 1 (the coefficients of the single-generator terms
    /// `h^k X_k` of the modified vector field; Hairer, Lubich & Wanner 2006, §V.3.2). These are
    /// the linear-in-`X_k` conditions; the others (nested brackets) were verified in 50-digit
    /// arithmetic (module docs) and show in the observed orders. Each sum is checked to
    /// 8ε·Σ|γᵢ|ᵏ (its rounding error bound with margin).
    #[test]
    fn composition_power_sums_vanish() {
        for (t, _) in tables() {
            if let Scheme::Composition { .. } = t.scheme {
                let w = t.composition_weights();
                let mut k = 3;
                while k < t.order {
                    let s: f64 = w.iter().map(|g| g.powi(k as i32)).sum();
                    let scale: f64 = w.iter().map(|g| g.abs().powi(k as i32)).sum();
                    assert!(
                        s.abs() <= 8.0 * f64::EPSILON * scale * w.len() as f64,
                        "{}: Σγ^{k} = {s:e}",
                        t.label()
                    );
                    k += 2;
                }
            }
        }
    }

    /// The B nodes and weights of SABA_n are the Gauss–Legendre rule on [0, 1] (exact for
    /// polynomials of degree ≤ 2n − 1), those of SBAB_n the Lobatto rule with n + 1 nodes (degree
    /// ≤ 2n − 1): Σ dᵢ xᵢᵏ = 1/(k + 1), xᵢ the time at which the i-th kick acts. Checked to 1e−15.
    /// `n` is the stage count ([`Table::stages`]), so this also checks that it is Laskar &
    /// Robutel's index.
    #[test]
    fn laskar_robutel_kicks_form_quadrature_rules() {
        let kepler: Vec<&Table> = tables().filter(|(_, k)| *k).map(|(t, _)| t).collect();
        assert_eq!(kepler.len(), 8);
        for t in kepler {
            let n = t.stages() as i32;
            let mut x = 0.0;
            let mut nodes = Vec::new();
            for (flow, c) in t.sub_steps() {
                match flow {
                    Flow::A => x += c,
                    Flow::B => nodes.push((x, c)),
                }
            }
            for k in 0..(2 * n) {
                let s: f64 = nodes.iter().map(|(x, d)| d * x.powi(k)).sum();
                let exact = 1.0 / (k as f64 + 1.0);
                assert!(
                    (s - exact).abs() <= 1e-15,
                    "{}: Σ d x^{k} = {s} vs {exact}",
                    t.label()
                );
            }
        }
    }

    #[test]
    fn evaluation_counts() {
        assert_eq!(VERLET_DKD.evaluations(), (2, 1));
        assert_eq!(VERLET_KDK.evaluations(), (1, 2));
        assert_eq!(KAHAN_LI17.evaluations(), (18, 17));
        assert_eq!(SOFRONIOU_SPALETTA35.evaluations(), (36, 35));
        assert_eq!(BLANES_MOAN6.evaluations(), (6, 7));
        assert_eq!(YOSHIDA15.composition_stages(), 15);
        let stages: Vec<u32> = [
            &SYMPLECTIC_EULER_KD,
            &SYMPLECTIC_EULER_DK,
            &VERLET_KDK,
            &VERLET_DKD,
            &BLANES_MOAN6,
            &YOSHIDA15,
            &SBAB1,
            &SBAB4,
            &SABA4,
        ]
        .iter()
        .map(|t| t.stages())
        .collect();
        assert_eq!(stages, [1, 1, 1, 1, 6, 15, 1, 4, 4]);
        assert_eq!(KAHAN_LI17.label(), "Kahan–Li, 17 stages, order 8");
        assert_eq!(
            VERLET_KDK.label(),
            "Störmer–Verlet (kick–drift–kick), 1 stage, order 2"
        );
    }

    /// `a_k = k √(7/40)`, and the corrector word composed with its inverse is the identity word
    /// (the drifts of each application sum to zero).
    #[test]
    fn corrector_coefficients() {
        let alpha = (7.0f64 / 40.0).sqrt();
        for (k, a) in [CA1, CA2, CA3, CA4, CA5, CA6, CA7, CA8].iter().enumerate() {
            assert!((a - (k + 1) as f64 * alpha).abs() < 4e-16 * (k + 1) as f64);
        }
        for c in CORRECTORS {
            for inverse in [false, true] {
                let (mut drift, mut kick, mut na, mut nb) = (0.0, 0.0, 0, 0);
                c.for_each_sub_step::<()>(inverse, |flow, x| {
                    if x == 0.0 {
                        return Ok(());
                    }
                    match flow {
                        Flow::A => {
                            drift += x;
                            na += 1;
                        }
                        Flow::B => {
                            kick += x;
                            nb += 1;
                        }
                    }
                    Ok(())
                })
                .unwrap();
                assert!(drift.abs() < 1e-14 && kick.abs() < 1e-15, "{}", c.order);
                assert_eq!((na, nb), c.evaluations());
            }
        }
    }
}
