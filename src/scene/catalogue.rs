//! The systems a scene can name (`[system] name = "…"`), and registration of a user's own.
//!
//! | name | keys (default) | methods beyond the general ones |
//! |---|---|---|
//! | `kepler` | `mu` (1), `eccentricity`, `semi_major_axis` (1) from periapsis, or `q`, `p` | splitting, exact flow, Hamilton–Jacobi |
//! | `pendulum` | `n` (1), `amplitude` or `gap` (π − amplitude) from rest, or `q`, `p` | splitting, exact flow, Hamilton–Jacobi, normal form, Lindstedt |
//! | `j2-orbit` | `mu` (1), `j2` (1.08e−3), `radius` (0.9), `a`, `e`, `i`, `raan`, `argp`, `mean_anomaly` | splitting, Wisdom–Holman/SABA, osculating and mean elements |
//! | `heavy-top` | `inertia` (1), `axial_inertia` (0.5), `mgl` (1), `theta` (π/3), `theta_dot` (0), `phi_dot` (0), `omega_z` (5) | exact flow and Hamilton–Jacobi (quadrature) |
//! | `expression` (default when `hamiltonian`, `lagrangian` or `disturbing_function` is given) | `hamiltonian`, `coordinates`, `momenta` (`p_<coordinate>`), `parameters` ({}), `q`, `p`, `period`; or `lagrangian`, `coordinates`, `velocities` (`v_<coordinate>`), `parameters`, `constraints`, `q`, `v`, `period`; or `disturbing_function` (`H = H_Kepler − R`), `mu` (1), `coordinates` (`x, y, z`), `parameters`, `q`, `p`, `period` | splitting when `H = T(p) + V(q)`; constrained methods with `constraints`; splitting, Wisdom–Holman/SABA for `disturbing_function` ([`super::expression`]) |
//! | `transformation-gallery` | — | none: a table of certification defects |
//! | `double-pendulum-spectrum` | `ratio_min` (0.01), `ratio_max` (100), `samples` (201), `l1` (1), `l2` (1), `g` (1) | none: λ² of the four equilibria against m₂/m₁, a table and a figure |
//! | `free-rigid-body` | `moments` ([1, 2, 3]), `spin` (1), `perturbation` (1e−3, of `spin`), `time` (100), `steps` (10000) | none: the intermediate-axis instability (growth rate, flips) and the Lie–Poisson splitting against the Euler–Poinsot flow, a table and figures |
//! | `megno-map` | `energy` (1/8), `n` (128), `time` (1000), `step` (0.1), `clip` (8) | none: the MEGNO map of the Hénon–Heiles section x = 0 on `n × n` cells, a table and a heat map |
//! | `henon-heiles-normal-form` | `degrees` ([4, 6, …, 16]), `remainder_degrees` ([4, 6, …, 12]), `periods` (55) | none: the 1:1 resonant normal form of Hénon–Heiles against frequency analysis of integrated orbits at E = 0.01 and 1/12, and its remainder against the amplitude, a table and figures ([`super::henon_heiles`]) |
//! | `struck-rods` | `mass` (1), `impulse` (1), `samples` (21) | none: velocity jumps of three hinged rods and of a rod struck at nℓ against their closed forms, a table and figures |
//! | `chaplygin-sleigh` | `m` (2), `s` (0.5), `inertia` (1, about the blade), `v` (0), `theta_dot` (√2), `push` (0), `torque` (0) | DOP853 on the multiplier form, with projection, discrete Lagrange–d'Alembert (no other) |
//! | `rolling-disk` | `m` (1), `r` (1), `g` (9.81), `a` (m r²/4), `c` (m r²/2), `v` (2.2), `lean` (0.01) | as the sleigh; the spectrum of upright rolling against the speed `v` |
//!
//! The general methods (RK4, implicit midpoint, Gauss–Legendre, DOP853) apply to every
//! Hamiltonian system. The constrained systems ([`ConstrainedCase`]) start at the origin heading
//! along x and draw the path of the contact point, the energy and the constraint residual.

use super::case::{
    exact_stepper, kepler_splitting_stepper, separable_stepper, system_invariants, Case,
    HamiltonianCase, Portrait, Table,
};
use super::constrained::ConstrainedCase;
use super::spec::{MethodKind, SceneError, TheoryKind};
use crate::error::{fmt_num, Error, Result};
use crate::hamilton_jacobi::action_angle::ActionAngle;
use crate::hamilton_jacobi::central::RadialMotion;
use crate::integrate::{integrate, Dop853, Problem};
use crate::nalgebra::{SVector, Vector3};
use crate::perturbation::brouwer::BrouwerLyddane;
use crate::perturbation::forces::{PerturbedTwoBody, J2};
use crate::perturbation::kepler_variation::{planetary_equations, ClassicalSolution, MeanElements};
use crate::perturbation::lindstedt::lindstedt_pendulum;
use crate::perturbation::normal_form::{PendulumNormalForm, PENDULUM_WARNING_MU};
use crate::perturbation::ode::Ode;
use crate::perturbation::variation::GeneralSolution;
use crate::phase::CanonicalPair;
use crate::stability::upright_rolling_spectrum;
use crate::systems::kepler::{self, elements::state_to_classical, elements::Classical};
use crate::systems::pendulum_exact::{exact_state, period_from_gap, separatrix_gap};
use crate::systems::top::motion::Nutation;
use crate::systems::{ChaplyginSleigh, HeavyTop, Invariant, Kepler2, Pendulum, RollingDisk};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::f64::consts::{PI, TAU};

/// The `[system]` table of a scene, read key by key: every read is checked (finite number,
/// positive where required, vector length), and [`Params::finish`] reports keys nobody read.
pub struct Params<'a> {
    file: &'a str,
    table: &'a toml::Table,
    used: RefCell<BTreeSet<String>>,
}

impl<'a> Params<'a> {
    /// Read `table` (the scene's `[system]`) of `file`.
    pub fn new(file: &'a str, table: &'a toml::Table) -> Self {
        let used = RefCell::new(BTreeSet::from(["name".to_string()]));
        Self { file, table, used }
    }

    /// An error at `system.<key>`.
    pub fn error(&self, key: &str, message: impl Into<String>) -> SceneError {
        SceneError::new(self.file, format!("system.{key}"), message)
    }

    fn number(&self, key: &str, v: &toml::Value) -> std::result::Result<f64, SceneError> {
        let x = match v {
            toml::Value::Float(x) => *x,
            toml::Value::Integer(i) => *i as f64,
            other => {
                return Err(self.error(
                    key,
                    format!("expected a number, found {}", other.type_str()),
                ))
            }
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(
                key,
                format!("expected a finite number, found {}", fmt_num(x)),
            ))
        }
    }

    /// An optional finite number.
    ///
    /// # Errors
    /// Wrong type or non-finite.
    pub fn opt(&self, key: &str) -> std::result::Result<Option<f64>, SceneError> {
        self.used.borrow_mut().insert(key.to_string());
        self.table.get(key).map(|v| self.number(key, v)).transpose()
    }

    /// A finite number with a default.
    ///
    /// # Errors
    /// Wrong type or non-finite.
    pub fn or(&self, key: &str, default: f64) -> std::result::Result<f64, SceneError> {
        Ok(self.opt(key)?.unwrap_or(default))
    }

    /// A positive finite number with a default.
    ///
    /// # Errors
    /// Wrong type, non-finite or not positive.
    pub fn positive_or(&self, key: &str, default: f64) -> std::result::Result<f64, SceneError> {
        let x = self.or(key, default)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.error(
                key,
                format!("expected a positive number, found {}", fmt_num(x)),
            ))
        }
    }

    /// An optional vector of `N` finite numbers.
    ///
    /// # Errors
    /// Wrong type, length or non-finite entries.
    pub fn vector<const N: usize>(
        &self,
        key: &str,
    ) -> std::result::Result<Option<SVector<f64, N>>, SceneError> {
        self.used.borrow_mut().insert(key.to_string());
        let Some(v) = self.table.get(key) else {
            return Ok(None);
        };
        let toml::Value::Array(a) = v else {
            return Err(self.error(
                key,
                format!("expected an array of {N} numbers, found {}", v.type_str()),
            ));
        };
        if a.len() != N {
            return Err(self.error(
                key,
                format!(
                    "expected an array of {N} numbers, found {} entries",
                    a.len()
                ),
            ));
        }
        let mut out = SVector::<f64, N>::zeros();
        for (i, x) in a.iter().enumerate() {
            out[i] = self.number(&format!("{key}[{i}]"), x)?;
        }
        Ok(Some(out))
    }

    /// An optional string.
    ///
    /// # Errors
    /// Wrong type.
    pub fn text(&self, key: &str) -> std::result::Result<Option<String>, SceneError> {
        self.used.borrow_mut().insert(key.to_string());
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.clone())),
            Some(v) => Err(self.error(key, format!("expected a string, found {}", v.type_str()))),
        }
    }

    /// The entries of the array at `key`, if given.
    fn array(
        &self,
        key: &str,
        of: &str,
    ) -> std::result::Result<Option<&'a [toml::Value]>, SceneError> {
        self.used.borrow_mut().insert(key.to_string());
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::Array(a)) => Ok(Some(a.as_slice())),
            Some(v) => Err(self.error(
                key,
                format!("expected an array of {of}, found {}", v.type_str()),
            )),
        }
    }

    /// An optional array of strings (names).
    ///
    /// # Errors
    /// Wrong type of the array or of an entry.
    pub fn texts(&self, key: &str) -> std::result::Result<Option<Vec<String>>, SceneError> {
        let Some(a) = self.array(key, "strings")? else {
            return Ok(None);
        };
        a.iter()
            .enumerate()
            .map(|(i, x)| match x {
                toml::Value::String(s) => Ok(s.clone()),
                other => Err(self.error(
                    &format!("{key}[{i}]"),
                    format!("expected a string, found {}", other.type_str()),
                )),
            })
            .collect::<std::result::Result<Vec<_>, _>>()
            .map(Some)
    }

    /// An optional array of arrays of strings (the rows of a matrix of expressions).
    ///
    /// # Errors
    /// Wrong type of the array, of a row or of an entry (naming it).
    pub fn text_rows(
        &self,
        key: &str,
    ) -> std::result::Result<Option<Vec<Vec<String>>>, SceneError> {
        let Some(a) = self.array(key, "arrays of strings")? else {
            return Ok(None);
        };
        a.iter()
            .enumerate()
            .map(|(r, row)| match row {
                toml::Value::Array(row) => row
                    .iter()
                    .enumerate()
                    .map(|(c, x)| match x {
                        toml::Value::String(s) => Ok(s.clone()),
                        other => Err(self.error(
                            &format!("{key}[{r}][{c}]"),
                            format!("expected a string, found {}", other.type_str()),
                        )),
                    })
                    .collect(),
                other => Err(self.error(
                    &format!("{key}[{r}]"),
                    format!(
                        "expected an array of strings (a row), found {}",
                        other.type_str()
                    ),
                )),
            })
            .collect::<std::result::Result<Vec<_>, _>>()
            .map(Some)
    }

    /// An optional array of finite numbers of any length.
    ///
    /// # Errors
    /// Wrong type or non-finite entries.
    pub fn numbers(&self, key: &str) -> std::result::Result<Option<Vec<f64>>, SceneError> {
        let Some(a) = self.array(key, "numbers")? else {
            return Ok(None);
        };
        a.iter()
            .enumerate()
            .map(|(i, x)| self.number(&format!("{key}[{i}]"), x))
            .collect::<std::result::Result<Vec<_>, _>>()
            .map(Some)
    }

    /// A table of named finite numbers, `{ a = 1.0, b = 2 }` (empty when absent), in the
    /// table's order.
    ///
    /// # Errors
    /// Wrong type or non-finite values.
    pub fn named_numbers(&self, key: &str) -> std::result::Result<Vec<(String, f64)>, SceneError> {
        self.used.borrow_mut().insert(key.to_string());
        match self.table.get(key) {
            None => Ok(Vec::new()),
            Some(toml::Value::Table(t)) => t
                .iter()
                .map(|(k, v)| Ok((k.clone(), self.number(&format!("{key}.{k}"), v)?)))
                .collect(),
            Some(v) => Err(self.error(
                key,
                format!("expected a table of numbers, found {}", v.type_str()),
            )),
        }
    }

    /// Both `q` and `p`, or neither.
    ///
    /// # Errors
    /// Only one of them given, or [`Params::vector`] errors.
    pub fn state<const N: usize>(
        &self,
    ) -> std::result::Result<Option<CanonicalPair<N>>, SceneError> {
        match (self.vector::<N>("q")?, self.vector::<N>("p")?) {
            (Some(q), Some(p)) => Ok(Some((q, p))),
            (None, None) => Ok(None),
            (Some(_), None) => Err(self.error("p", "missing: `q` is given, so `p` is needed too")),
            (None, Some(_)) => Err(self.error("q", "missing: `p` is given, so `q` is needed too")),
        }
    }

    /// Reject keys that were never read.
    ///
    /// # Errors
    /// The first unknown key, with the known ones.
    pub fn finish(&self) -> std::result::Result<(), SceneError> {
        let used = self.used.borrow();
        if let Some(k) = self.table.keys().find(|k| !used.contains(*k)) {
            let known: Vec<&str> = used.iter().map(String::as_str).collect();
            return Err(self.error(
                k,
                format!("unknown key; this system takes: {}", known.join(", ")),
            ));
        }
        Ok(())
    }

    /// A library error while building the system, attributed to the `[system]` table.
    pub fn library(&self, e: Error) -> SceneError {
        SceneError::new(self.file, "system", e.to_string())
    }
}

/// Builds a case from the `[system]` table. `Send + Sync`, so that sweeps build cases on every
/// core.
pub type Builder =
    Box<dyn Fn(&Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> + Send + Sync>;

/// The named systems scenes can use: the built-in ones and any registered from Rust. Cloning
/// shares the builders.
#[derive(Clone)]
pub struct Catalogue {
    entries: Vec<(String, String, SharedBuilder)>,
}

type SharedBuilder = std::sync::Arc<
    dyn Fn(&Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> + Send + Sync,
>;

impl Default for Catalogue {
    fn default() -> Self {
        Self::builtin()
    }
}

impl Catalogue {
    /// The built-in systems (see the [module docs](self)).
    pub fn builtin() -> Self {
        let mut c = Self {
            entries: Vec::new(),
        };
        c.register(
            "kepler",
            "planar Kepler problem (exact solution by Kepler's equation)",
            Box::new(kepler),
        );
        c.register(
            "pendulum",
            "plane pendulum H = p²/2 + n²(1 − cos q) (exact solution by elliptic functions)",
            Box::new(pendulum),
        );
        c.register(
            "j2-orbit",
            "orbit about an oblate body (J₂), spatial",
            Box::new(j2_orbit),
        );
        c.register(
            "heavy-top",
            "heavy symmetric top in Euler angles (solution by quadrature)",
            Box::new(heavy_top),
        );
        c.register(
            "chaplygin-sleigh",
            "Chaplygin sleigh (blade), one non-holonomic constraint",
            Box::new(chaplygin_sleigh),
        );
        c.register(
            "rolling-disk",
            "disk rolling upright on a plane, two non-holonomic constraints",
            Box::new(rolling_disk),
        );
        c.register(
            "expression",
            "a system given by an expression: `hamiltonian`, `lagrangian` (with `constraints`) \
             or `disturbing_function` of Kepler (the default when the table has one)",
            Box::new(super::expression::expression_system),
        );
        c.register(
            "transformation-gallery",
            "canonical transformations certified by AD (table only)",
            Box::new(gallery),
        );
        c.register(
            "double-pendulum-spectrum",
            "eigenvalues of the double pendulum's equilibria against the mass ratio (table and figure)",
            Box::new(double_pendulum_spectrum),
        );
        c.register(
            "free-rigid-body",
            "free rigid body spun about its intermediate axis, Lie–Poisson against Euler–Poinsot (table and figures)",
            Box::new(free_rigid_body),
        );
        c.register(
            "megno-map",
            "MEGNO map of the Hénon–Heiles surface of section (table and heat map)",
            Box::new(megno_map),
        );
        c.register(
            "henon-heiles-normal-form",
            "1:1 resonant normal form of Hénon–Heiles: frequency error against degree, remainder against amplitude (table and figures)",
            Box::new(henon_heiles_normal_form),
        );
        c.register(
            "struck-rods",
            "velocity jumps of struck hinged rods against their closed forms (table and figures)",
            Box::new(struck_rods),
        );
        c
    }

    /// Add (or replace) a system under `name`.
    pub fn register(&mut self, name: &str, description: &str, builder: Builder) {
        self.entries.retain(|(n, _, _)| n != name);
        self.entries
            .push((name.to_string(), description.to_string(), builder.into()));
    }

    /// Names and descriptions, in registration order.
    pub fn list(&self) -> impl Iterator<Item = (&str, &str)> {
        self.entries
            .iter()
            .map(|(n, d, _)| (n.as_str(), d.as_str()))
    }

    /// Build the case a `[system]` table describes.
    ///
    /// # Errors
    /// Missing or unknown `name`, and every error of the system's own keys.
    pub fn build(
        &self,
        file: &str,
        table: &toml::Table,
    ) -> std::result::Result<Box<dyn Case>, SceneError> {
        let name = match table.get("name") {
            None if ["hamiltonian", "lagrangian", "disturbing_function"]
                .iter()
                .any(|k| table.contains_key(*k)) =>
            {
                "expression"
            }
            Some(toml::Value::String(s)) => s.as_str(),
            Some(v) => {
                return Err(SceneError::new(
                    file,
                    "system.name",
                    format!("expected a string, found {}", v.type_str()),
                ))
            }
            None => {
                return Err(SceneError::new(
                    file,
                    "system.name",
                    "missing: which system (e.g. \"kepler\")",
                ))
            }
        };
        let Some((_, _, builder)) = self.entries.iter().find(|(n, _, _)| n == name) else {
            let known: Vec<&str> = self.entries.iter().map(|(n, _, _)| n.as_str()).collect();
            return Err(SceneError::new(
                file,
                "system.name",
                format!(
                    "unknown system `{name}`, expected one of: {}",
                    known.join(", ")
                ),
            ));
        };
        let params = Params::new(file, table);
        let case = builder(&params)?;
        params.finish()?;
        Ok(case)
    }
}

fn xy(q: &[f64], _p: &[f64]) -> (f64, f64) {
    (q[0], q[1])
}

/// Planar Kepler problem.
fn kepler(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let mu = s.positive_or("mu", 1.0)?;
    let e_key = s.opt("eccentricity")?;
    let a_key = s.opt("semi_major_axis")?;
    let explicit = s.state::<2>()?;
    if a_key.is_some() && explicit.is_some() {
        return Err(s.error(
            "semi_major_axis",
            "goes with `eccentricity`; with `q` and `p` the orbit follows from the state",
        ));
    }
    let a = s.positive_or("semi_major_axis", 1.0)?;
    let (q0, p0, from_elements) = match (e_key, explicit) {
        (Some(_), Some(_)) => {
            return Err(s.error(
                "eccentricity",
                "give either `eccentricity` (start at periapsis) or `q` and `p`, not both",
            ))
        }
        (None, None) => {
            return Err(s.error(
                "eccentricity",
                "missing: give `eccentricity` (start at periapsis) or `q` and `p`",
            ))
        }
        (Some(e), None) => {
            if !(0.0..1.0).contains(&e) {
                return Err(s.error(
                    "eccentricity",
                    format!("expected an eccentricity in [0, 1), found {}", fmt_num(e)),
                ));
            }
            let q0 = SVector::from([a * (1.0 - e), 0.0]);
            let p0 = SVector::from([0.0, (mu / a * (1.0 + e) / (1.0 - e)).sqrt()]);
            (q0, p0, Some(e))
        }
        (None, Some((q, p))) => (q, p, None),
    };
    // Semi-major axis and eccentricity of the state, for the period and the description.
    let r = q0.norm();
    let inv_a = 2.0 / r - p0.norm_squared() / mu;
    if inv_a.is_nan() || inv_a <= 0.0 || r == 0.0 {
        return Err(s.error(
            "q",
            "the initial state (q, p) is not on a bound (elliptic) orbit: 2/|q| − |p|²/μ ≤ 0",
        ));
    }
    if q0[0] * p0[1] - q0[1] * p0[0] == 0.0 {
        return Err(s.error(
            "p",
            "the initial state (q, p) has zero angular momentum (rectilinear motion into the \
             centre)",
        ));
    }
    let a_state = 1.0 / inv_a;
    let period = TAU * (a_state.powi(3) / mu).sqrt();
    let sys = Kepler2::new(mu).map_err(|e| s.library(e))?;
    let description = match from_elements {
        Some(e) => format!(
            "planar Kepler problem, μ = {}, a = {}, e = {}, from periapsis",
            fmt_num(mu),
            fmt_num(a),
            fmt_num(e)
        ),
        None => format!(
            "planar Kepler problem, μ = {}, q₀ = ({}, {}), p₀ = ({}, {})",
            fmt_num(mu),
            fmt_num(q0[0]),
            fmt_num(q0[1]),
            fmt_num(p0[0]),
            fmt_num(p0[1])
        ),
    };
    let reference = Box::new(move |t: f64| {
        Ok((
            kepler::propagate(mu, &q0, &p0, t)?,
            "reference: exact solution (Kepler's equation)".to_string(),
        ))
    });
    let mut case = HamiltonianCase::new(sys, q0, p0, description)
        .map_err(|e| s.library(e))?
        .with_period(period)
        .with_stepper(separable_stepper::<Kepler2, 2>())
        .with_stepper(exact_stepper::<Kepler2, 2>())
        .with_invariants(system_invariants::<Kepler2, 2>)
        .with_reference(reference)
        .with_portrait(Portrait {
            title: "orbit",
            x_label: "x",
            y_label: "y",
            equal_aspect: true,
            project: xy,
        })
        .with_elements(
            &["a", "e", "ϖ"],
            Box::new(move |q, p| {
                let el = state_to_classical(
                    mu,
                    &Vector3::new(q[0], q[1], 0.0),
                    &Vector3::new(p[0], p[1], 0.0),
                )?;
                Ok(vec![el.a, el.e, el.raan + el.argp])
            }),
        );
    if let Some(e) = from_elements {
        // Hamilton–Jacobi: the radial quadrature through the apsides, time law inverted.
        let h = (mu * a * (1.0 - e * e)).sqrt();
        case = case.with_theory(
            TheoryKind::HamiltonJacobi,
            Box::new(move |_, t| {
                let motion = RadialMotion::kepler_elements(mu, a, e)?;
                let (r, rdot, theta) = motion.state_at(t)?;
                let (st, ct) = theta.sin_cos();
                Ok((
                    SVector::from([r * ct, r * st]),
                    SVector::from([rdot * ct - h / r * st, rdot * st + h / r * ct]),
                ))
            }),
        );
    }
    Ok(Box::new(case))
}

/// Plane pendulum.
fn pendulum(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let n = s.positive_or("n", 1.0)?;
    let amplitude = s.opt("amplitude")?;
    let gap = s.opt("gap")?;
    let explicit = s.state::<1>()?;
    let given = [amplitude.is_some(), gap.is_some(), explicit.is_some()];
    if given.iter().filter(|&&g| g).count() != 1 {
        return Err(s.error(
            "amplitude",
            "give exactly one of `amplitude` (from rest), `gap` (π − amplitude, from rest), \
             or `q` and `p`",
        ));
    }
    // The gap δ = π − a is what the exact solution, the period and the action–angle variables
    // need near the separatrix; for a start from rest at the double q₀ it is measured from q₀ to
    // the true π.
    let (q0, p0, delta, amp) = if let Some(a) = amplitude {
        if !(a > 0.0 && a < PI) {
            return Err(s.error(
                "amplitude",
                format!("expected an amplitude in (0, π), found {}", fmt_num(a)),
            ));
        }
        (a, 0.0, separatrix_gap(a).map_err(|e| s.library(e))?, a)
    } else if let Some(d) = gap {
        if !(d > 0.0 && d < PI) {
            return Err(s.error(
                "gap",
                format!(
                    "expected a gap π − amplitude in (0, π), found {}",
                    fmt_num(d)
                ),
            ));
        }
        let q0 = PI - d;
        if q0 >= PI {
            return Err(s.error(
                "gap",
                format!(
                    "a gap of {} does not change the double nearest π: the smallest                      representable gap is about 1.2e−16 + 4.4e−16",
                    fmt_num(d)
                ),
            ));
        }
        (q0, 0.0, separatrix_gap(q0).map_err(|e| s.library(e))?, q0)
    } else {
        let (q, p) = explicit.unwrap_or_default();
        let (q, p) = (q[0], p[0]);
        if q.abs() > PI {
            return Err(s.error(
                "q",
                format!("expected an angle in [−π, π], found {}", fmt_num(q)),
            ));
        }
        // sin(a/2)² = sin(q/2)² + p²/(4n²), without the cancellation of cos a = cos q − p²/2n².
        let sin_half = ((q / 2.0).sin().powi(2) + p * p / (4.0 * n * n)).sqrt();
        if sin_half >= 1.0 {
            return Err(s.error(
                "p",
                "the state (q, p) is on or above the separatrix (a rotation); this scene needs a \
                 libration",
            ));
        }
        if sin_half == 0.0 {
            return Err(s.error(
                "q",
                "the state (q, p) = (0, 0) is the stable equilibrium: there is no motion to compare",
            ));
        }
        let a = 2.0 * sin_half.asin();
        let delta = if p == 0.0 {
            separatrix_gap(q).map_err(|e| s.library(e))?
        } else {
            2.0 * sin_half.acos()
        };
        (q, p, delta, a)
    };
    let period = period_from_gap(n, delta).map_err(|e| s.library(e))?;
    let sys = Pendulum::new(n).map_err(|e| s.library(e))?;
    let description = if p0 == 0.0 {
        format!(
            "pendulum, n = {}, released from rest at amplitude {} (gap to the separatrix {delta:.3e})",
            fmt_num(n),
            fmt_num(amp)
        )
    } else {
        format!(
            "pendulum, n = {}, q₀ = {}, p₀ = {} (amplitude {})",
            fmt_num(n),
            fmt_num(q0),
            fmt_num(p0),
            fmt_num(amp)
        )
    };
    let reference = Box::new(move |t: f64| {
        let (q, p) = exact_state(n, q0, p0, t)?;
        Ok((
            (SVector::from([q]), SVector::from([p])),
            "reference: exact solution (Jacobi elliptic functions)".to_string(),
        ))
    });
    let order_of = |knob: f64| -> Result<usize> {
        if knob >= 1.0 && knob.fract() == 0.0 && knob <= 64.0 {
            Ok(knob as usize)
        } else {
            Err(Error::invalid(
                "order",
                format!("expected an order in 1..=64, got {}", fmt_num(knob)),
            ))
        }
    };
    let mut case = HamiltonianCase::new(sys, SVector::from([q0]), SVector::from([p0]), description)
        .map_err(|e| s.library(e))?
        .with_period(period)
        .with_error_label("final angle error |Δq|")
        .with_stepper(separable_stepper::<Pendulum, 1>())
        .with_stepper(exact_stepper::<Pendulum, 1>())
        .with_invariants(system_invariants::<Pendulum, 1>)
        .with_reference(reference)
        .with_theory(
            TheoryKind::HamiltonJacobi,
            Box::new(move |_, t| {
                let aa = ActionAngle::pendulum(Pendulum::new(n)?, delta)?;
                let w0 = aa.angle(q0, p0)?;
                let (q, p) = aa.state(w0 + aa.frequency() * t)?;
                Ok((SVector::from([q]), SVector::from([p])))
            }),
        )
        .with_theory(
            TheoryKind::NormalForm,
            Box::new(move |knob, t| {
                let nf = PendulumNormalForm::new(n, order_of(knob)?)?;
                let (q, p) = nf.state_at(q0, p0, t)?;
                Ok((SVector::from([q]), SVector::from([p])))
            }),
        );
    // Both series are in μ = (a/π)²; beyond μ = ½ their omitted tail may exceed the last term
    // as the amplitude nears the separatrix: the results are shown with that warning.
    let mu_small = (amp / PI).powi(2);
    if mu_small > PENDULUM_WARNING_MU {
        let note = format!(
            "warning: μ = (a/π)² = {mu_small:.7} > {PENDULUM_WARNING_MU}, the series may not converge"
        );
        case = case
            .with_note(TheoryKind::NormalForm.into(), note.clone())
            .with_note(TheoryKind::Lindstedt.into(), note);
    }
    if p0 == 0.0 {
        case = case.with_theory(
            TheoryKind::Lindstedt,
            Box::new(move |knob, t| {
                let series = lindstedt_pendulum(order_of(knob)?)?;
                // The series starts at +a; a start at −a is its mirror image.
                let q = q0.signum() * series.theta(n, amp, t)?;
                // The series gives θ(t); its momentum is not part of the comparison.
                Ok((SVector::from([q]), SVector::from([f64::NAN])))
            }),
        );
    }
    Ok(Box::new(case))
}

/// Orbit about an oblate body.
fn j2_orbit(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let mu = s.positive_or("mu", 1.0)?;
    let j2v = s.or("j2", 1.08e-3)?;
    let radius = s.positive_or("radius", 0.9)?;
    let a = s.positive_or("a", 1.2)?;
    let e = s.or("e", 0.05)?;
    let inc = s.or("i", 0.5)?;
    let raan = s.or("raan", 0.3)?;
    let argp = s.or("argp", 0.7)?;
    let m0 = s.or("mean_anomaly", 0.2)?;
    if !(0.0..1.0).contains(&e) {
        return Err(s.error(
            "e",
            format!("expected an eccentricity in [0, 1), found {}", fmt_num(e)),
        ));
    }
    if !(0.0..=PI).contains(&inc) {
        return Err(s.error(
            "i",
            format!("expected an inclination in [0, π], found {}", fmt_num(inc)),
        ));
    }
    let el = Classical::new(a, e, inc, raan, argp, m0).map_err(|x| s.library(x))?;
    let model = J2::new(mu, j2v, radius).map_err(|x| s.library(x))?;
    let sys = PerturbedTwoBody::conservative(mu, model).map_err(|x| s.library(x))?;
    let (q0, p0) = el.to_state(mu).map_err(|x| s.library(x))?;
    let period = TAU * (a.powi(3) / mu).sqrt();
    let description = format!(
        "orbit about an oblate body, μ = {}, J₂ = {}, R = {}; a = {}, e = {}, i = {}",
        fmt_num(mu),
        fmt_num(j2v),
        fmt_num(radius),
        fmt_num(a),
        fmt_num(e),
        fmt_num(inc)
    );
    let case = HamiltonianCase::new(sys, q0, p0, description)
        .map_err(|x| s.library(x))?
        .with_period(period)
        .with_stepper(separable_stepper::<PerturbedTwoBody<J2>, 3>())
        .with_stepper(kepler_splitting_stepper::<PerturbedTwoBody<J2>, 3>())
        .with_invariants(axisymmetric_invariants)
        .with_portrait(Portrait {
            title: "orbit",
            x_label: "x",
            y_label: "y",
            equal_aspect: true,
            project: xy,
        })
        .with_elements(
            &["a", "e", "i", "Ω", "ω"],
            Box::new(move |q, p| {
                let el = state_to_classical(
                    mu,
                    &Vector3::new(q[0], q[1], q[2]),
                    &Vector3::new(p[0], p[1], p[2]),
                )?;
                Ok(vec![el.a, el.e, el.i, el.raan, el.argp])
            }),
        )
        .with_theory(
            TheoryKind::OsculatingElements,
            Box::new(move |rtol, t| {
                let sol = ClassicalSolution::new(mu, 0.0)?;
                let (g1, g2) = sol.constants(&el, 0.0)?;
                let ode = Ode(planetary_equations(sol, model));
                let pr = Problem::new(&ode, 0.0, g1, g2, t)?;
                let run = integrate(&pr, &Dop853::new(rtol, rtol)?, &mut ())?;
                Ok(sol.state(t, &run.last.q, &run.last.p))
            }),
        )
        .with_theory(
            TheoryKind::MeanElements,
            Box::new(move |_, t| MeanElements::j2(&model, 0.0, el)?.state(t)),
        )
        .with_theory(
            TheoryKind::BrouwerLyddane,
            // From the initial state each time: the cost includes the osculating → mean
            // conversion.
            Box::new(move |_, t| BrouwerLyddane::from_state(&model, 0.0, &q0, &p0)?.state(t)),
        );
    Ok(Box::new(case))
}

/// Energy and the polar angular momentum `h_z = x p_y − y p_x`: the integrals of motion about an
/// axisymmetric body.
fn axisymmetric_invariants(
    sys: &PerturbedTwoBody<J2>,
    t: f64,
    q: &SVector<f64, 3>,
    p: &SVector<f64, 3>,
) -> Result<Vec<Invariant>> {
    use crate::Hamiltonian;
    Ok(vec![
        Invariant {
            name: "energy",
            value: sys.value(t, q, p)?,
        },
        Invariant {
            name: "h_z",
            value: q[0] * p[1] - q[1] * p[0],
        },
    ])
}

fn theta_ptheta(q: &[f64], p: &[f64]) -> (f64, f64) {
    (q[1], p[1])
}

/// Heavy symmetric top.
fn heavy_top(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let i1 = s.positive_or("inertia", 1.0)?;
    let i3 = s.positive_or("axial_inertia", 0.5)?;
    let mgl = s.positive_or("mgl", 1.0)?;
    let theta = s.or("theta", PI / 3.0)?;
    let theta_dot = s.or("theta_dot", 0.0)?;
    let phi_dot = s.or("phi_dot", 0.0)?;
    let omega_z = s.or("omega_z", 5.0)?;
    if !(theta > 0.0 && theta < PI) {
        return Err(s.error(
            "theta",
            format!("expected a tilt in (0, π), found {}", fmt_num(theta)),
        ));
    }
    let top = HeavyTop::new(i1, i3, mgl).map_err(|x| s.library(x))?;
    let q0 = SVector::from([0.0, theta, 0.0]);
    let p0 = top
        .momenta_from_spin(theta, theta_dot, phi_dot, omega_z)
        .map_err(|x| s.library(x))?;
    let nutation = Nutation::from_state(&top, &q0, &p0).map_err(|x| s.library(x))?;
    let period = nutation.period().map_err(|x| s.library(x))?.value;
    let description = format!(
        "heavy symmetric top, I = {}, J = {}, mgℓ = {}; θ₀ = {}, θ̇₀ = {}, φ̇₀ = {}, ω_z = {}",
        fmt_num(i1),
        fmt_num(i3),
        fmt_num(mgl),
        fmt_num(theta),
        fmt_num(theta_dot),
        fmt_num(phi_dot),
        fmt_num(omega_z)
    );
    let hj = move |t: f64| -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        let top = HeavyTop::new(i1, i3, mgl)?;
        Nutation::from_state(&top, &q0, &p0)?.propagate(&q0, &p0, t)
    };
    let case = HamiltonianCase::new(top, q0, p0, description)
        .map_err(|x| s.library(x))?
        .with_period(period)
        .with_error_label("final angle error ‖Δ(φ, θ, ψ)‖")
        .with_stepper(exact_stepper::<HeavyTop, 3>())
        .with_invariants(system_invariants::<HeavyTop, 3>)
        .with_portrait(Portrait {
            title: "phase portrait",
            x_label: "θ",
            y_label: "p_θ",
            equal_aspect: false,
            project: theta_ptheta,
        })
        .with_theory(TheoryKind::HamiltonJacobi, Box::new(move |_, t| hj(t)));
    Ok(Box::new(case))
}

/// The computed output of a case without motion: a table and its figures `(what, figure)`.
type Computed = Result<(Table, Vec<(String, crate::plot::Figure)>)>;

/// A case without motion or methods that computes its own table and figures (the transformation
/// gallery, the spectra of equilibria against a parameter).
struct TableCase {
    /// What the case is, for its description.
    description: String,
    /// How it is named in refusals (`"the transformation gallery"`).
    what: &'static str,
    /// The `what` of each figure the computation returns.
    figures: Vec<&'static str>,
    /// The computation.
    compute: Box<dyn Fn() -> Computed>,
}

impl TableCase {
    fn no_motion(&self, what: &str) -> Error {
        Error::invalid(what, format!("{} has no motion", self.what))
    }
}

impl Case for TableCase {
    fn describe(&self) -> String {
        self.description.clone()
    }
    fn period(&self) -> Option<f64> {
        None
    }
    fn supports(&self, _kind: MethodKind) -> bool {
        false
    }
    fn error_label(&self) -> String {
        String::new()
    }
    fn prepare(&mut self, _t1: f64) -> Result<()> {
        Ok(())
    }
    fn reference_note(&self) -> String {
        String::new()
    }
    fn run(&self, kind: MethodKind, _knob: f64) -> Result<super::case::Outcome> {
        Err(Error::invalid(
            format!("method {}", kind.key()),
            format!("{} runs no methods", self.what),
        ))
    }
    fn history(
        &self,
        kind: MethodKind,
        knob: f64,
        _samples: usize,
    ) -> Result<super::case::History> {
        self.run(kind, knob).map(|_| Default::default())
    }
    fn energy(&self, _t: f64, _q: &[f64], _p: &[f64]) -> Result<f64> {
        Err(self.no_motion("energy"))
    }
    fn reference_coordinates(&self, _times: &[f64]) -> Result<Vec<Vec<f64>>> {
        Err(self.no_motion("reference solution"))
    }
    fn portrait(&self) -> Portrait {
        Portrait {
            title: "phase portrait",
            x_label: "q",
            y_label: "p",
            equal_aspect: false,
            project: |q, p| (q[0], p[0]),
        }
    }
    fn has_table(&self) -> bool {
        true
    }
    fn table(&self) -> Option<Computed> {
        Some((self.compute)())
    }
    fn table_figures(&self) -> Vec<&'static str> {
        self.figures.clone()
    }
}

fn gallery(_s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    Ok(Box::new(TableCase {
        description: "canonical transformations certified by AD: MᵀJM − J, MJMᵀ − J, det M − 1"
            .into(),
        what: "the transformation gallery",
        figures: Vec::new(),
        compute: Box::new(|| Ok((super::gallery::transformation_gallery()?, Vec::new()))),
    }))
}

/// The spectra of the double pendulum's four equilibria (SPEC T27) against the mass ratio
/// `m₂/m₁` on `[ratio_min, ratio_max]` (logarithmic, `samples` values), lengths `l1`, `l2`,
/// gravity `g`.
fn double_pendulum_spectrum(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let lo = s.positive_or("ratio_min", 0.01)?;
    let hi = s.positive_or("ratio_max", 100.0)?;
    let l1 = s.positive_or("l1", 1.0)?;
    let l2 = s.positive_or("l2", 1.0)?;
    let g = s.positive_or("g", 1.0)?;
    let samples = s.positive_or("samples", 201.0)?;
    s.finish()?;
    if lo >= hi || samples.fract() != 0.0 || !(2.0..=100_000.0).contains(&samples) {
        return Err(s.error(
            "samples",
            "need ratio_min < ratio_max and an integer number of samples in [2, 100000]",
        ));
    }
    let description = format!(
        "double pendulum of point masses, ℓ₁ = {}, ℓ₂ = {}, g = {}: eigenvalues of the four \
         equilibria against m₂/m₁ ∈ [{}, {}]",
        fmt_num(l1),
        fmt_num(l2),
        fmt_num(g),
        fmt_num(lo),
        fmt_num(hi)
    );
    Ok(Box::new(TableCase {
        description,
        what: "the spectrum scene",
        figures: vec![super::stability::SPECTRUM_FIGURE],
        compute: Box::new(move || {
            super::stability::double_pendulum_spectrum(lo, hi, samples as usize, l1, l2, g)
        }),
    }))
}

/// A whole number in `[lo, hi]` under `key`, `default` if absent.
fn count_or(
    s: &Params<'_>,
    key: &str,
    default: usize,
    (lo, hi): (usize, usize),
) -> std::result::Result<usize, SceneError> {
    let x = s.positive_or(key, default as f64)?;
    if x.fract() != 0.0 || !(lo as f64..=hi as f64).contains(&x) {
        return Err(s.error(key, format!("expected a whole number in [{lo}, {hi}]")));
    }
    Ok(x as usize)
}

/// The free rigid body (SPEC T30) of principal `moments` spun at `spin` about axis 2 with the
/// perturbation `perturbation · spin` about axis 1, over `[0, time]`, Lie–Poisson with `steps`
/// steps.
fn free_rigid_body(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let moments = s
        .vector::<3>("moments")?
        .unwrap_or_else(|| Vector3::new(1.0, 2.0, 3.0));
    let spin = s.positive_or("spin", 1.0)?;
    let eps = s.positive_or("perturbation", 1e-3)?;
    let time = s.positive_or("time", 100.0)?;
    let steps = count_or(s, "steps", 10_000, (1, 10_000_000))?;
    s.finish()?;
    let rate = crate::systems::rigid_body::intermediate_axis_growth_rate(&moments, spin)
        .map_err(|x| s.library(x))?;
    if rate == 0.0 {
        return Err(s.error(
            "moments",
            "expected I₂ strictly between I₁ and I₃ (the spin about axis 2 is otherwise stable)",
        ));
    }
    let description = format!(
        "free rigid body, I = ({}, {}, {}), spin Ω = {} about axis 2 perturbed by {}Ω about \
         axis 1, t ∈ [0, {}]",
        fmt_num(moments[0]),
        fmt_num(moments[1]),
        fmt_num(moments[2]),
        fmt_num(spin),
        fmt_num(eps),
        fmt_num(time)
    );
    Ok(Box::new(TableCase {
        description,
        what: "the free rigid body scene",
        figures: vec![
            super::rigid_body::MOMENTUM_FIGURE,
            super::rigid_body::GROWTH_FIGURE,
            super::rigid_body::ERROR_FIGURE,
        ],
        compute: Box::new(move || {
            super::rigid_body::intermediate_axis(moments, spin, eps, time, steps)
        }),
    }))
}

/// The MEGNO map (issue §2) of Hénon–Heiles at `energy` on `n × n` cells of the section
/// `x = 0`, Verlet with step `step` to `time`, `⟨Y⟩` clipped at `clip`.
fn megno_map(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let energy = s.positive_or("energy", 0.125)?;
    let n = count_or(s, "n", 128, (2, 4096))?;
    let time = s.positive_or("time", 1000.0)?;
    let step = s.positive_or("step", 0.1)?;
    let clip = s.positive_or("clip", 8.0)?;
    s.finish()?;
    let description = format!(
        "Hénon–Heiles at E = {}: mean MEGNO ⟨Y⟩ at t = {} on {n} × {n} cells of the section x = 0 \
         (Störmer–Verlet, h = {})",
        fmt_num(energy),
        fmt_num(time),
        fmt_num(step)
    );
    Ok(Box::new(TableCase {
        description,
        what: "the MEGNO map",
        figures: vec![super::megno::MAP_FIGURE],
        compute: Box::new(move || {
            let map = super::megno::henon_heiles_megno_map(energy, n, time, step, clip)?;
            Ok((
                map.table(),
                vec![(
                    super::megno::MAP_FIGURE.to_string(),
                    map.figure(energy, time, step),
                )],
            ))
        }),
    }))
}

/// Whole numbers in `[lo, hi]` at `key` (1 to 32 of them), or `default`.
fn counts_or(
    s: &Params<'_>,
    key: &str,
    default: &[usize],
    (lo, hi): (usize, usize),
) -> std::result::Result<Vec<usize>, SceneError> {
    let Some(xs) = s.numbers(key)? else {
        return Ok(default.to_vec());
    };
    if xs.is_empty() || xs.len() > 32 {
        return Err(s.error(key, "expected 1 to 32 whole numbers"));
    }
    xs.iter()
        .map(|&x| {
            if x.fract() != 0.0 || !(lo as f64..=hi as f64).contains(&x) {
                Err(s.error(
                    key,
                    format!(
                        "expected whole numbers in [{lo}, {hi}], found {}",
                        fmt_num(x)
                    ),
                ))
            } else {
                Ok(x as usize)
            }
        })
        .collect()
}

/// The 1:1 resonant normal form of Hénon–Heiles (issue 15 §3) at the `degrees` against frequency
/// analysis of orbits integrated over `periods` slow periods, and the remainder slopes of the
/// `remainder_degrees`.
fn henon_heiles_normal_form(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let degrees = counts_or(s, "degrees", &[4, 6, 8, 10, 12, 14, 16], (4, 30))?;
    let remainder_degrees = counts_or(s, "remainder_degrees", &[4, 6, 8, 10, 12], (4, 30))?;
    let periods = s.positive_or("periods", 55.0)?;
    s.finish()?;
    if !(10.0..=1e4).contains(&periods) {
        return Err(s.error("periods", "expected a number of slow periods in [10, 10⁴]"));
    }
    let description = format!(
        "Hénon–Heiles, 1:1 resonant (Gustavson) normal form at degrees {degrees:?}: torus          frequencies against frequency analysis over {} slow periods at E = 0.01 and 1/12;          remainder against amplitude at degrees {remainder_degrees:?}",
        fmt_num(periods)
    );
    Ok(Box::new(TableCase {
        description,
        what: "the Hénon–Heiles normal form",
        figures: vec![
            super::henon_heiles::FREQUENCY_FIGURE,
            super::henon_heiles::REMAINDER_FIGURE,
        ],
        compute: Box::new(move || {
            super::henon_heiles::henon_heiles_normal_form(&degrees, &remainder_degrees, periods)
        }),
    }))
}

/// The struck rods (SPEC T35, T36): rods of mass `mass`, impulse `impulse`, `samples` points of
/// impact along the single rod.
fn struck_rods(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let mass = s.positive_or("mass", 1.0)?;
    let impulse = s.or("impulse", 1.0)?;
    let samples = count_or(s, "samples", 21, (2, 100_000))?;
    s.finish()?;
    if impulse == 0.0 {
        return Err(s.error("impulse", "expected a non-zero impulse"));
    }
    let description = format!(
        "hinged rods of mass M = {} struck by the impulse P = {}",
        fmt_num(mass),
        fmt_num(impulse)
    );
    Ok(Box::new(TableCase {
        description,
        what: "the struck rods",
        figures: vec![
            super::impulse::THREE_RODS_FIGURE,
            super::impulse::ONE_ROD_FIGURE,
        ],
        compute: Box::new(move || super::impulse::struck_rods(mass, impulse, samples)),
    }))
}

/// The Chaplygin sleigh (SPEC T16) from the origin heading along x with forward speed `v` and
/// turning rate `theta_dot`.
fn chaplygin_sleigh(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let m = s.positive_or("m", 2.0)?;
    let offset = s.or("s", 0.5)?;
    let inertia = s.positive_or("inertia", 1.0)?;
    let v = s.or("v", 0.0)?;
    let w = s.or("theta_dot", 2f64.sqrt())?;
    let (push, torque) = (s.or("push", 0.0)?, s.or("torque", 0.0)?);
    s.finish()?;
    let sleigh = ChaplyginSleigh::new(m, offset, inertia)
        .and_then(|x| x.with_forces(push, torque))
        .map_err(|x| s.library(x))?;
    let description = format!(
        "Chaplygin sleigh, m = {}, s = {}, I_B = {}, Z = {}, M = {}; v₀ = {}, ϑ̇₀ = {}",
        fmt_num(m),
        fmt_num(offset),
        fmt_num(inertia),
        fmt_num(push),
        fmt_num(torque),
        fmt_num(v),
        fmt_num(w)
    );
    let case = ConstrainedCase::new(
        sleigh,
        sleigh,
        SVector::zeros(),
        SVector::from([v, 0.0, w]),
        description,
    )
    .map_err(|x| s.library(x))?;
    Ok(Box::new(case))
}

/// The rolling disk (SPEC T17) from the origin rolling along x at speed `v` with the lean `lean`.
fn rolling_disk(s: &Params<'_>) -> std::result::Result<Box<dyn Case>, SceneError> {
    let m = s.positive_or("m", 1.0)?;
    let r = s.positive_or("r", 1.0)?;
    let g = s.or("g", 9.81)?;
    let a = s.positive_or("a", 0.25 * m * r * r)?;
    let c = s.positive_or("c", 0.5 * m * r * r)?;
    let v = s.or("v", 2.2)?;
    let lean = s.or("lean", 0.01)?;
    s.finish()?;
    let disk = RollingDisk::new(m, r, a, c, g).map_err(|x| s.library(x))?;
    let description = format!(
        "rolling disk, m = {}, r = {}, A = {}, C = {}, g = {}; v = {}, ψ₀ = {}",
        fmt_num(m),
        fmt_num(r),
        fmt_num(a),
        fmt_num(c),
        fmt_num(g),
        fmt_num(v),
        fmt_num(lean)
    );
    let case = ConstrainedCase::new(
        disk,
        disk,
        SVector::from([0.0, 0.0, 0.0, lean, 0.0]),
        SVector::from([v, 0.0, 0.0, 0.0, v / r]),
        description,
    )
    .map_err(|x| s.library(x))?
    .with_steady_motions("v", Box::new(move |v| upright_rolling_spectrum(disk, v)));
    Ok(Box::new(case))
}
