//! Every integration method the crate ships, described once: the table [`METHODS`].
//!
//! A [`MethodInfo`] says everything the crate says about a method — the key that scene files and
//! the command line use, the family name from which its label is made, its stages and order, the
//! knob it is swept over, whether it is symplectic, what it needs of the system
//! ([`Capability`]), its source, and how to build it ([`Construction`]). Scene parsing, the
//! labels of tables, legends and CSV files, the `hj list` output,
//! [`AnyMethod::new`](super::AnyMethod::new) / [`GeneralMethod::new`](super::GeneralMethod::new)
//! and the `name()` of every [`OneStep`](super::OneStep) method are derived from this table.
//! The entries of a splitting method take their family name, order and source from its
//! coefficient [`Table`], which is their one description.
//!
//! # How methods are named
//! * **Stages** `s`: evaluations per step of the part that costs. For a Runge–Kutta method the
//!   stages of its Butcher tableau (classical RK4: 4; Gauss–Legendre: `s` implicit stages;
//!   Dormand–Prince 8(5,3): 12; Dormand–Prince 5(4): 6, the evaluation at the step's end, which
//!   is the next step's first stage, not counted). For a splitting or composition method the force evaluations
//!   (kicks, `B` sub-steps) per step of a long run, the closing kick of a step merged with the
//!   opening kick of the next when the word begins and ends with one (they act at the same
//!   point): Störmer–Verlet 1, a composition of `s` Verlet steps `s`, Blanes–Moan `SRKN₆ᵇ` 6,
//!   Laskar–Robutel `SABA_n` and `SBAB_n` `n` (Hairer, Lubich & Wanner, *Geometric Numerical
//!   Integration*, 2nd ed., Springer 2006, §§II.1, V.3; Blanes & Moan 2002; Laskar & Robutel 2001).
//! * **Order** `p`: the global error over a fixed span is `O(hᵖ)`. For Wisdom–Holman, `SABA_n`
//!   and `SBAB_n` on `H = H_Kepler + εH₁` it is the order at fixed `ε`: their error is
//!   `O(ε h^{2n} + ε² h²)`, order 2.
//! * **Label** (tables, legends, CSV, `name()`): `"<family>, <s> stages, order <p>"`, e.g.
//!   `"Gauss–Legendre, 3 stages, order 6"`, `"Kahan–Li, 17 stages, order 8"`,
//!   `"Laskar–Robutel SABA, 3 stages, order 2"` ([`label`]); the exact flow is `"exact flow"`.
//! * **Key** (scene files, command line): the family in lower case with hyphens followed by the
//!   number of stages — `rk4`, `gauss1`, `gauss3`, `kahan-li17`, `yoshida15`, `saba3`, `sbab2`.
//!   The one-stage families name their variant instead of the number (`verlet-kdk`,
//!   `verlet-dkd`, `symplectic-euler-kd`, `symplectic-euler-dk`, `wisdom-holman`); Dormand–Prince
//!   keeps the name of its code, `dop853`, and its 5(4) pair the name of the SciPy method whose
//!   step-size control it has, `rk45`; the Taylor method is `taylor` and the exact flow is
//!   `exact`.

use super::coefficients::Table;
use crate::error::{fmt_num, Error, Result};

/// What a method needs of the system it integrates (a trait bound of its typed value).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Capability {
    /// Any [`Hamiltonian`](crate::Hamiltonian).
    Hamiltonian,
    /// A [`Separable`](crate::Separable) `H = T(p) + V(q)`.
    Separable,
    /// A perturbed Kepler problem `H = H_Kepler + H₁(t, q)`
    /// ([`PerturbedKepler`](crate::integrate::PerturbedKepler)).
    PerturbedKepler,
    /// A closed-form flow ([`ExactFlow`](crate::systems::ExactFlow)).
    ExactFlow,
}

impl Capability {
    /// The systems the capability admits, in words.
    pub fn systems(self) -> &'static str {
        match self {
            Capability::Hamiltonian => "any H",
            Capability::Separable => "separable H = T(p) + V(q)",
            Capability::PerturbedKepler => "perturbed Kepler H = H_K + H₁(q)",
            Capability::ExactFlow => "systems with a closed-form flow",
        }
    }
}

/// How a method is built: the typed value behind its entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Construction {
    /// [`Rk4`](super::Rk4) under [`Fixed`](super::Fixed).
    Rk4,
    /// [`Gauss`](super::Gauss) with this many stages under [`Fixed`](super::Fixed).
    Gauss(usize),
    /// [`Dop853`](super::Dop853) with `rtol = atol`.
    Dop853,
    /// [`Rk45`](super::Rk45) with `rtol = atol`.
    Rk45,
    /// [`Splitting`](super::Splitting) over this table under [`Fixed`](super::Fixed).
    Splitting(&'static Table),
    /// [`WisdomHolman`](super::WisdomHolman) over this table under [`Fixed`](super::Fixed).
    KeplerSplitting(&'static Table),
    /// [`ExactStep`](super::ExactStep) under [`Fixed`](super::Fixed).
    Exact,
    /// [`Taylor`](super::Taylor) with its tolerance (order and step after Jorba & Zou).
    Taylor,
    /// [`Taylor`](super::Taylor) in double-double arithmetic
    /// ([`Precision::DoubleDouble`](super::Precision::DoubleDouble)) with its tolerance.
    TaylorDd,
    /// [`TimeTransformed`](super::TimeTransformed): the logarithmic Hamiltonian
    /// (Mikkola–Tanikawa) over this table's word, with its step in fictitious time.
    TimeTransformed(&'static Table),
}

impl Construction {
    /// What the method needs of the system.
    pub fn capability(self) -> Capability {
        match self {
            Construction::Rk4
            | Construction::Gauss(_)
            | Construction::Dop853
            | Construction::Rk45
            | Construction::Taylor
            | Construction::TaylorDd => Capability::Hamiltonian,
            Construction::Splitting(_) | Construction::TimeTransformed(_) => Capability::Separable,
            Construction::KeplerSplitting(_) => Capability::PerturbedKepler,
            Construction::Exact => Capability::ExactFlow,
        }
    }
}

/// The knob a method is swept over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Knob {
    /// A whole number of fixed steps over the span.
    Steps,
    /// A tolerance, used as both `rtol` and `atol` of the step-size control.
    Tolerance,
    /// The step `ds` in fictitious time of a time-transformed method (its steps in physical
    /// time follow the motion).
    FictitiousStep,
}

/// One integration method, described once (see the [module docs](self) for the naming scheme).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodInfo {
    /// Key in scene files and on the command line, e.g. `"gauss3"`.
    pub key: &'static str,
    /// Family name, the first part of the label, e.g. `"Gauss–Legendre"`.
    pub family: &'static str,
    /// Stages per step.
    pub stages: u32,
    /// Order; `None` for the exact flow (no truncation error) and for the Taylor method (its
    /// order follows the tolerance).
    pub order: Option<u32>,
    /// The knob the method is swept over.
    pub knob: Knob,
    /// Whether every step is a symplectic map.
    pub symplectic: bool,
    /// How the method is built.
    pub construction: Construction,
    /// Where the method comes from.
    pub reference: &'static str,
}

/// The label of a method of `family` with `stages` stages and order `order`:
/// `"<family>, <s> stages, order <p>"` (`"1 stage"` for one).
pub fn label(family: &str, stages: u32, order: u32) -> String {
    let plural = if stages == 1 { "" } else { "s" };
    format!("{family}, {stages} stage{plural}, order {order}")
}

const fn fixed(
    key: &'static str,
    family: &'static str,
    stages: u32,
    order: u32,
    symplectic: bool,
    construction: Construction,
    reference: &'static str,
) -> MethodInfo {
    MethodInfo {
        key,
        family,
        stages,
        order: Some(order),
        knob: Knob::Steps,
        symplectic,
        construction,
        reference,
    }
}

const fn gauss(key: &'static str, stages: u32) -> MethodInfo {
    fixed(
        key,
        "Gauss–Legendre",
        stages,
        2 * stages,
        true,
        Construction::Gauss(stages as usize),
        "Hairer, Lubich & Wanner 2006, §II.1.3, Theorems II.1.5 and VI.4.3",
    )
}

/// A splitting (explicit or Kepler): family, stages, order and source from its coefficient
/// table. Evaluated at compile time only (the table is a `static`): a construction without a
/// table does not compile.
const fn from_table(key: &'static str, construction: Construction) -> MethodInfo {
    let table = match construction {
        Construction::Splitting(t) | Construction::KeplerSplitting(t) => t,
        _ => panic!("a splitting entry needs its coefficient table"),
    };
    fixed(
        key,
        table.name,
        table.stages(),
        table.order,
        true,
        construction,
        table.reference,
    )
}

/// Classical Runge–Kutta: `rk4`, 4 stages, order 4.
pub const RK4: MethodInfo = fixed(
    "rk4",
    "classical Runge–Kutta",
    4,
    4,
    false,
    Construction::Rk4,
    "Hairer, Nørsett & Wanner, Solving ODEs I, 2nd ed., §II.1",
);

/// Gauss–Legendre collocation with `s = 1 … 6` stages (`GAUSS[s − 1]`): `gauss<s>`, order `2s`.
pub const GAUSS: [MethodInfo; 6] = [
    gauss("gauss1", 1),
    gauss("gauss2", 2),
    gauss("gauss3", 3),
    gauss("gauss4", 4),
    gauss("gauss5", 5),
    gauss("gauss6", 6),
];

/// Dormand–Prince 8(5,3) with step-size control: `dop853`, 12 stages, order 8.
pub const DOP853: MethodInfo = MethodInfo {
    key: "dop853",
    family: "Dormand–Prince",
    stages: 12,
    order: Some(8),
    knob: Knob::Tolerance,
    symplectic: false,
    construction: Construction::Dop853,
    reference: "Hairer, Nørsett & Wanner, Solving ODEs I, 2nd ed., §II.10 (DOP853)",
};

/// Dormand–Prince 5(4) with the step-size control of SciPy's `RK45`: `rk45`, 6 stages (and a
/// seventh evaluation, first same as last), order 5.
pub const RK45: MethodInfo = MethodInfo {
    key: "rk45",
    family: "Dormand–Prince",
    stages: 6,
    order: Some(5),
    knob: Knob::Tolerance,
    symplectic: false,
    construction: Construction::Rk45,
    reference: "Dormand & Prince, J. Comp. Appl. Math. 6 (1980) 19–26; step-size control of \
                SciPy's RK45 (scipy.integrate)",
};

/// The Taylor method over the record of Hamilton's equations, order and step from the
/// tolerance (Jorba & Zou): `taylor`, one propagation of the record per step.
pub const TAYLOR: MethodInfo = MethodInfo {
    key: "taylor",
    family: "Taylor (Jorba–Zou)",
    stages: 1,
    order: None,
    knob: Knob::Tolerance,
    symplectic: false,
    construction: Construction::Taylor,
    reference: "Jorba & Zou, Exp. Math. 14 (2005) 99–117",
};

/// The Taylor method in double-double arithmetic (series, state and time; about 106 bits):
/// `taylor-dd`, for final errors below what double rounding allows (near a separatrix).
pub const TAYLOR_DD: MethodInfo = MethodInfo {
    key: "taylor-dd",
    family: "Taylor (Jorba–Zou), double-double",
    stages: 1,
    order: None,
    knob: Knob::Tolerance,
    symplectic: false,
    construction: Construction::TaylorDd,
    reference: "Jorba & Zou, Exp. Math. 14 (2005) 99–117; double-double arithmetic: Joldes, \
                Muller & Popescu, ACM TOMS 44 (2017) 15res",
};

/// The system's exact flow, composed over fixed steps: `exact`.
pub const EXACT: MethodInfo = MethodInfo {
    key: "exact",
    family: "exact flow",
    stages: 1,
    order: None,
    knob: Knob::Steps,
    symplectic: true,
    construction: Construction::Exact,
    reference: "the system's closed-form flow (ExactFlow)",
};

/// A splitting word run in fictitious time under the logarithmic Hamiltonian (Mikkola &
/// Tanikawa 1999): stages and order from the table (the order in `s`), knob the step `ds`.
const fn log_hamiltonian(
    key: &'static str,
    family: &'static str,
    table: &'static Table,
) -> MethodInfo {
    MethodInfo {
        key,
        family,
        stages: table.stages(),
        order: Some(table.order),
        knob: Knob::FictitiousStep,
        symplectic: true,
        construction: Construction::TimeTransformed(table),
        reference: "Mikkola & Tanikawa, MNRAS 310 (1999) 745–749; Preto & Tremaine, AJ 118 \
                    (1999) 2532–2541",
    }
}

/// Every integration method of the crate, in the order `hj list` shows them: the methods for
/// any Hamiltonian (Taylor last of them), the explicit splittings (lowest order first), the
/// time-transformed splittings, the Kepler splittings, the exact flow.
pub static METHODS: [MethodInfo; 35] = {
    use super::coefficients as c;
    use Construction::{KeplerSplitting, Splitting};
    [
        RK4,
        GAUSS[0],
        GAUSS[1],
        GAUSS[2],
        GAUSS[3],
        GAUSS[4],
        GAUSS[5],
        RK45,
        DOP853,
        TAYLOR,
        TAYLOR_DD,
        from_table("symplectic-euler-kd", Splitting(&c::SYMPLECTIC_EULER_KD)),
        from_table("symplectic-euler-dk", Splitting(&c::SYMPLECTIC_EULER_DK)),
        from_table("verlet-kdk", Splitting(&c::VERLET_KDK)),
        from_table("verlet-dkd", Splitting(&c::VERLET_DKD)),
        from_table("yoshida3", Splitting(&c::YOSHIDA3)),
        from_table("suzuki5", Splitting(&c::SUZUKI5)),
        from_table("blanes-moan6", Splitting(&c::BLANES_MOAN6)),
        from_table("yoshida7", Splitting(&c::YOSHIDA7)),
        from_table("kahan-li9", Splitting(&c::KAHAN_LI9)),
        from_table("yoshida15", Splitting(&c::YOSHIDA15)),
        from_table("kahan-li17", Splitting(&c::KAHAN_LI17)),
        from_table("sofroniou-spaletta35", Splitting(&c::SOFRONIOU_SPALETTA35)),
        log_hamiltonian(
            "log-h-verlet-dkd",
            "logarithmic-Hamiltonian leapfrog",
            &c::VERLET_DKD,
        ),
        log_hamiltonian(
            "log-h-kahan-li9",
            "logarithmic-Hamiltonian Kahan–Li",
            &c::KAHAN_LI9,
        ),
        log_hamiltonian(
            "log-h-kahan-li17",
            "logarithmic-Hamiltonian Kahan–Li",
            &c::KAHAN_LI17,
        ),
        from_table("wisdom-holman", KeplerSplitting(&c::SBAB1)),
        from_table("saba1", KeplerSplitting(&c::SABA1)),
        from_table("saba2", KeplerSplitting(&c::SABA2)),
        from_table("saba3", KeplerSplitting(&c::SABA3)),
        from_table("saba4", KeplerSplitting(&c::SABA4)),
        from_table("sbab2", KeplerSplitting(&c::SBAB2)),
        from_table("sbab3", KeplerSplitting(&c::SBAB3)),
        from_table("sbab4", KeplerSplitting(&c::SBAB4)),
        EXACT,
    ]
};

impl MethodInfo {
    /// The label of tables, legends and CSV files, e.g. `"Gauss–Legendre, 3 stages, order 6"`
    /// ([`label`]); the family alone for the exact flow and the Taylor method.
    pub fn label(&self) -> String {
        match self.order {
            Some(order) => label(self.family, self.stages, order),
            None => self.family.to_string(),
        }
    }

    /// What the method needs of the system.
    pub fn capability(&self) -> Capability {
        self.construction.capability()
    }

    /// One line for `hj list`: the label, whether it is symplectic, the systems it applies to.
    pub fn description(&self) -> String {
        format!(
            "{}; {}; {}",
            self.label(),
            if self.symplectic {
                "symplectic"
            } else {
                "not symplectic"
            },
            self.capability().systems()
        )
    }

    /// The method with key `key`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for an unknown key, listing the keys ([`keys`](Self::keys)).
    pub fn find(key: &str) -> Result<&'static MethodInfo> {
        METHODS.iter().find(|m| m.key == key).ok_or_else(|| {
            Error::invalid(
                "integration method key",
                format!("unknown key {key:?}; the keys are: {}", Self::keys()),
            )
        })
    }

    /// The entry of the method built as `construction`, if the crate lists it.
    pub fn of(construction: Construction) -> Option<&'static MethodInfo> {
        METHODS.iter().find(|m| m.construction == construction)
    }

    /// Every key, comma-separated, in table order.
    pub fn keys() -> String {
        METHODS.iter().map(|m| m.key).collect::<Vec<_>>().join(", ")
    }
}

/// A knob value as a number of steps: a whole number `1 ≤ n ≤ 10¹²`.
///
/// # Errors
/// [`Error::InvalidInput`] otherwise (NaN, infinite, fractional, below 1 or above 10¹²).
pub fn whole_steps(knob: f64) -> Result<usize> {
    if knob.is_finite() && knob >= 1.0 && knob.fract() == 0.0 && knob <= 1e12 {
        Ok(knob as usize)
    } else {
        Err(Error::invalid(
            "steps",
            format!(
                "expected a whole number of steps ≥ 1, got {}",
                fmt_num(knob)
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::super::coefficients::Flow;
    use super::*;

    /// Keys are unique, labels are unique, and every label spells its stages and order.
    #[test]
    fn keys_and_labels_are_unique_and_follow_the_scheme() {
        for (i, a) in METHODS.iter().enumerate() {
            for b in &METHODS[i + 1..] {
                assert_ne!(a.key, b.key);
                assert_ne!(a.label(), b.label());
                assert_ne!(a.construction, b.construction, "{} and {}", a.key, b.key);
            }
            assert!(a
                .key
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'));
            if let Some(p) = a.order {
                let stages = if a.stages == 1 {
                    "1 stage,".to_string()
                } else {
                    format!("{} stages,", a.stages)
                };
                let label = a.label();
                assert!(label.contains(&stages), "{label}");
                assert!(label.ends_with(&format!(", order {p}")), "{label}");
            }
            assert!(std::ptr::eq(MethodInfo::find(a.key).unwrap(), a));
        }
        let e = MethodInfo::find("gauss-3").unwrap_err().to_string();
        assert!(e.contains("gauss3") && e.contains("kahan-li17"), "{e}");
    }

    /// A splitting's stage count is its number of kicks per step with the closing kick merged
    /// into the next step's opening kick.
    #[test]
    fn splitting_stages_count_the_kicks() {
        for m in &METHODS {
            if let Construction::Splitting(t) | Construction::KeplerSplitting(t) = m.construction {
                let steps = t.sub_steps();
                let (_, kicks) = t.evaluations();
                let merged = matches!(
                    (steps.first(), steps.last()),
                    (Some((Flow::B, _)), Some((Flow::B, _)))
                );
                assert_eq!(m.stages as usize, kicks - usize::from(merged), "{}", m.key);
            }
        }
    }

    /// A key's trailing number is the stage count; every method of more than one stage has one
    /// (DOP853 and RK45, named after their codes, excepted).
    #[test]
    fn keys_carry_the_stage_count() {
        for m in METHODS
            .iter()
            .filter(|m| !["dop853", "rk45"].contains(&m.key))
        {
            let digits: String = m
                .key
                .chars()
                .rev()
                .take_while(char::is_ascii_digit)
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            if digits.is_empty() {
                assert_eq!(m.stages, 1, "{}", m.key);
            } else {
                assert_eq!(digits, m.stages.to_string(), "{}", m.key);
            }
        }
    }

    #[test]
    fn whole_steps_refuses_what_is_not_a_count() {
        assert_eq!(whole_steps(12.0).unwrap(), 12);
        for bad in [0.0, 0.5, 1.5, -3.0, f64::NAN, f64::INFINITY, 2e12] {
            assert!(whole_steps(bad).is_err(), "{bad}");
        }
    }
}
