//! A planetary system: a central mass `m₀` and `n` planets under their mutual gravitation, in
//! inertial Cartesian coordinates,
//!
//! ```math
//! H(x, p) = \sum_{i=0}^{n} \frac{|p_i|^2}{2 m_i} - \sum_{0 \le i < j \le n} \frac{G m_i m_j}{|x_i - x_j|},
//! ```
//!
//! with the state `q = (x₀, x₁, …, xₙ)`, `p = (p₀, …, pₙ)` stacked in `N = 3(n + 1)` entries.
//! The Hamiltonian is written once ([`Separable`]) and used by every general integrator; the
//! Wisdom–Holman splits are declared on it through two canonical changes of coordinates
//! ([`PlanetaryCoordinates`]), with the interaction part defined as the same potential `V`
//! minus the Kepler potentials (J. Wisdom & M. Holman, Astron. J. 102 (1991) 1528, §3;
//! M. J. Duncan, H. F. Levison & M. H. Lee, Astron. J. 116 (1998) 2067, §2).

use crate::ad::gradient;
use crate::brackets::PhaseMap;
use crate::error::{positive, Error, Result};
use crate::hamiltonian::Separable;
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

/// Canonical coordinates of a planetary system in which `H` splits into Kepler problems plus a
/// small interaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanetaryCoordinates {
    /// Jacobi coordinates (Wisdom & Holman 1991): `q'₀` the centre of mass,
    /// `q'ᵢ = xᵢ − Rᵢ₋₁` with `Rᵢ` the centre of mass of bodies `0…i`; momenta
    /// `p'ᵢ = m'ᵢ q̇'ᵢ`, `m'ᵢ = mᵢ ηᵢ₋₁/ηᵢ`, `ηᵢ = m₀ + … + mᵢ`, `m'₀ = ηₙ`. Then
    ///
    /// ```math
    /// H = \frac{|p'_0|^2}{2\eta_n} + \sum_{i\ge1}\Big(\frac{|p'_i|^2}{2m'_i}
    ///   - \frac{G m_i \eta_{i-1}}{|q'_i|}\Big) + H_I(q'),\qquad
    /// H_I = V(x(q')) + \sum_{i\ge1}\frac{G m_i\eta_{i-1}}{|q'_i|}.
    /// ```
    Jacobi,
    /// Democratic heliocentric coordinates (Duncan, Levison & Lee 1998): heliocentric positions
    /// `qᵢ = xᵢ − x₀`, barycentric momenta `pᵢ = mᵢ(ẋᵢ − Ẋ)`, `q₀` the centre of mass and `p₀`
    /// the total momentum. Then
    ///
    /// ```math
    /// H = \frac{|p_0|^2}{2M} + \sum_{i\ge1}\Big(\frac{|p_i|^2}{2m_i} - \frac{G m_0 m_i}{|q_i|}\Big)
    ///   + \frac{|\sum_{i\ge1} p_i|^2}{2m_0} + H_I(q),\qquad
    /// H_I = V(x(q)) + \sum_{i\ge1}\frac{G m_0 m_i}{|q_i|},
    /// ```
    ///
    /// the third term the *jump* (a shift of every heliocentric position).
    DemocraticHeliocentric,
}

/// A central mass and `n ≥ 1` planets, `N = 3(n + 1)`, with the constant of gravitation `G`.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanetarySystem<const N: usize> {
    g: f64,
    masses: Vec<f64>,
}

/// The position (or momentum) `(v₃ᵢ, v₃ᵢ₊₁, v₃ᵢ₊₂)` of body `i` in a stacked vector.
#[inline]
pub(crate) fn body<D: DualNum<f64> + Copy, const N: usize>(
    v: &SVector<D, N>,
    i: usize,
) -> Vector3<D> {
    Vector3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2])
}

#[inline]
fn norm2<D: DualNum<f64> + Copy>(v: &Vector3<D>) -> D {
    v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
}

/// `k/|d|`: the pair potential `−G mᵢ mⱼ/|xᵢ − xⱼ|` (with `k = G mᵢ mⱼ`, subtracted) and the
/// Kepler potentials taken out of the interaction (`k = G mᵢ ηᵢ₋₁` or `G m₀ mᵢ`, added) in one
/// formula, shared by the values and their gradients.
#[inline]
fn inverse_distance<D: DualNum<f64> + Copy>(k: f64, d: &Vector3<D>) -> D {
    D::from(k) / norm2(d).sqrt()
}

/// `∇(k/|d|)` with respect to `d`, by AD of [`inverse_distance`] in three variables.
#[inline]
fn inverse_distance_gradient<D: DualNum<f64> + Copy>(k: f64, d: &Vector3<D>) -> Vector3<D> {
    gradient(|v| inverse_distance(k, v), d).1
}

/// Adds `b` to the three components of body `i` in a stacked vector.
#[inline]
pub(crate) fn add_body<D: DualNum<f64> + Copy, const N: usize>(
    v: &mut SVector<D, N>,
    i: usize,
    b: Vector3<D>,
) {
    v[3 * i] += b[0];
    v[3 * i + 1] += b[1];
    v[3 * i + 2] += b[2];
}

#[inline]
fn set_body<D: DualNum<f64> + Copy, const N: usize>(
    v: &mut SVector<D, N>,
    i: usize,
    b: Vector3<D>,
) {
    v[3 * i] = b[0];
    v[3 * i + 1] = b[1];
    v[3 * i + 2] = b[2];
}

impl<const N: usize> PlanetarySystem<N> {
    /// Bodies of masses `masses = [m₀, m₁, …, mₙ]` (the central mass first) with the constant of
    /// gravitation `G`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] unless `N = 3·masses.len()` with at least two bodies;
    /// [`Error::OutOfDomain`] / [`Error::NonFinite`] for a mass or `G` not positive and finite.
    pub fn new(g: f64, masses: &[f64]) -> Result<Self> {
        if masses.len() < 2 || N != 3 * masses.len() {
            return Err(Error::invalid(
                "planetary system",
                format!(
                    "{} masses for a state of dimension {N}: need N = 3 × (number of bodies) with \
                     at least two bodies",
                    masses.len()
                ),
            ));
        }
        let g = positive("constant of gravitation G", g)?;
        let masses = masses
            .iter()
            .map(|&m| positive("mass", m))
            .collect::<Result<Vec<_>>>()?;
        let total: f64 = masses.iter().sum();
        positive("total mass", total)?;
        positive("G times total mass", g * total)?;
        Ok(Self { g, masses })
    }

    /// The constant of gravitation `G`.
    pub fn g(&self) -> f64 {
        self.g
    }

    /// The masses, the central mass first.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// Number of bodies `n + 1`.
    pub fn bodies(&self) -> usize {
        self.masses.len()
    }

    /// `ηᵢ = m₀ + … + mᵢ`.
    fn eta(&self, i: usize) -> f64 {
        self.masses[..=i].iter().sum()
    }

    /// The Jacobi masses `m'ᵢ = mᵢ ηᵢ₋₁/ηᵢ` (`m'₀ = ηₙ`, the total mass).
    pub fn jacobi_masses(&self) -> Vec<f64> {
        let n = self.bodies();
        (0..n)
            .map(|i| {
                if i == 0 {
                    self.eta(n - 1)
                } else {
                    self.masses[i] * self.eta(i - 1) / self.eta(i)
                }
            })
            .collect()
    }

    /// The gravitational parameter of the Kepler problem of body `i ≥ 1` in `coordinates`:
    /// `G ηᵢ` (Jacobi) or `G m₀` (democratic heliocentric), for the velocity `p'ᵢ/m'ᵢ`
    /// resp. `pᵢ/mᵢ`.
    pub fn kepler_mu(&self, coordinates: PlanetaryCoordinates, i: usize) -> f64 {
        match coordinates {
            PlanetaryCoordinates::Jacobi => self.g * self.eta(i),
            PlanetaryCoordinates::DemocraticHeliocentric => self.g * self.masses[0],
        }
    }

    /// The mass dividing the momentum of body `i` in `coordinates` to give the velocity of its
    /// Kepler drift: `m'ᵢ` (Jacobi) or `mᵢ` (democratic heliocentric); `M` for `i = 0` (the
    /// centre of mass).
    pub fn kepler_mass(&self, coordinates: PlanetaryCoordinates, i: usize) -> f64 {
        match coordinates {
            PlanetaryCoordinates::Jacobi => {
                if i == 0 {
                    self.eta(self.bodies() - 1)
                } else {
                    self.masses[i] * self.eta(i - 1) / self.eta(i)
                }
            }
            PlanetaryCoordinates::DemocraticHeliocentric => {
                if i == 0 {
                    self.eta(self.bodies() - 1)
                } else {
                    self.masses[i]
                }
            }
        }
    }

    /// The linear map of positions (or velocities) `x ↦ x'` of `coordinates`.
    fn positions_to<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        x: &SVector<D, N>,
    ) -> SVector<D, N> {
        let n = self.bodies();
        let mut out = SVector::<D, N>::zeros();
        match coordinates {
            PlanetaryCoordinates::Jacobi => {
                // R₀ = x₀; q'ᵢ = xᵢ − Rᵢ₋₁; Rᵢ = Rᵢ₋₁ + (mᵢ/ηᵢ) q'ᵢ; q'₀ = Rₙ.
                let mut r = body(x, 0);
                for i in 1..n {
                    let qi = body(x, i) - r;
                    r += qi * D::from(self.masses[i] / self.eta(i));
                    set_body(&mut out, i, qi);
                }
                set_body(&mut out, 0, r);
            }
            PlanetaryCoordinates::DemocraticHeliocentric => {
                let x0 = body(x, 0);
                let mut com = x0 * D::from(self.masses[0]);
                for i in 1..n {
                    let xi = body(x, i);
                    com += xi * D::from(self.masses[i]);
                    set_body(&mut out, i, xi - x0);
                }
                set_body(&mut out, 0, com / D::from(self.eta(n - 1)));
            }
        }
        out
    }

    /// The inverse of [`Self::positions_to`].
    fn positions_from<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        y: &SVector<D, N>,
    ) -> SVector<D, N> {
        let n = self.bodies();
        let mut x = SVector::<D, N>::zeros();
        match coordinates {
            PlanetaryCoordinates::Jacobi => {
                // Rᵢ₋₁ = Rᵢ − (mᵢ/ηᵢ) q'ᵢ, xᵢ = q'ᵢ + Rᵢ₋₁, from i = n down; x₀ = R₀.
                let mut r = body(y, 0);
                for i in (1..n).rev() {
                    let qi = body(y, i);
                    r -= qi * D::from(self.masses[i] / self.eta(i));
                    set_body(&mut x, i, qi + r);
                }
                set_body(&mut x, 0, r);
            }
            PlanetaryCoordinates::DemocraticHeliocentric => {
                // x₀ = q₀ − Σ mᵢ qᵢ / M, xᵢ = qᵢ + x₀.
                let mut shift = Vector3::<D>::zeros();
                for i in 1..n {
                    shift += body(y, i) * D::from(self.masses[i]);
                }
                let x0 = body(y, 0) - shift / D::from(self.eta(n - 1));
                for i in 1..n {
                    set_body(&mut x, i, body(y, i) + x0);
                }
                set_body(&mut x, 0, x0);
            }
        }
        x
    }

    /// The canonical map from inertial `(x, p)` to `coordinates`: positions by the linear map
    /// `x' = A x`, momenta by `p' = A⁻ᵀ p` — for Jacobi coordinates `p'ᵢ = m'ᵢ (A ẋ)ᵢ`; for
    /// democratic heliocentric ones `p'₀ = Σ pₖ`, `p'ᵢ = pᵢ − mᵢ p'₀/M`.
    #[allow(clippy::type_complexity)]
    pub fn to_coordinates<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        x: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        (
            self.positions_to(coordinates, x),
            self.momenta_to(coordinates, p),
        )
    }

    /// The map of momenta (covectors) `p ↦ p' = A⁻ᵀ p` of [`Self::to_coordinates`]; it also
    /// carries a gradient `∂f/∂x` to `∂f/∂x' = A⁻ᵀ ∂f/∂x`.
    fn momenta_to<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        let n = self.bodies();
        let mut pp = SVector::<D, N>::zeros();
        match coordinates {
            PlanetaryCoordinates::Jacobi => {
                let mut v = SVector::<D, N>::zeros();
                for i in 0..n {
                    set_body(&mut v, i, body(p, i) / D::from(self.masses[i]));
                }
                let w = self.positions_to(coordinates, &v);
                for i in 0..n {
                    let m = self.kepler_mass(coordinates, i);
                    set_body(&mut pp, i, body(&w, i) * D::from(m));
                }
            }
            PlanetaryCoordinates::DemocraticHeliocentric => {
                let total: Vector3<D> = (0..n).map(|i| body(p, i)).sum();
                let m = self.eta(n - 1);
                for i in 1..n {
                    set_body(&mut pp, i, body(p, i) - total * D::from(self.masses[i] / m));
                }
                set_body(&mut pp, 0, total);
            }
        }
        pp
    }

    /// The inverse of [`Self::to_coordinates`].
    #[allow(clippy::type_complexity)]
    pub fn from_coordinates<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        q: &SVector<D, N>,
        pp: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let n = self.bodies();
        let x = self.positions_from(coordinates, q);
        let mut p = SVector::<D, N>::zeros();
        match coordinates {
            PlanetaryCoordinates::Jacobi => {
                let mut w = SVector::<D, N>::zeros();
                for i in 0..n {
                    let m = self.kepler_mass(coordinates, i);
                    set_body(&mut w, i, body(pp, i) / D::from(m));
                }
                let v = self.positions_from(coordinates, &w);
                for i in 0..n {
                    set_body(&mut p, i, body(&v, i) * D::from(self.masses[i]));
                }
            }
            PlanetaryCoordinates::DemocraticHeliocentric => {
                // pᵢ = p'ᵢ + mᵢ p'₀/M (i ≥ 1), p₀ = p'₀ − Σᵢ≥₁ pᵢ.
                let total = body(pp, 0);
                let m = self.eta(n - 1);
                let mut rest = Vector3::<D>::zeros();
                for i in 1..n {
                    let pi = body(pp, i) + total * D::from(self.masses[i] / m);
                    rest += pi;
                    set_body(&mut p, i, pi);
                }
                set_body(&mut p, 0, total - rest);
            }
        }
        (x, p)
    }

    /// The interaction part `H_I(q')` of the split in `coordinates` (see
    /// [`PlanetaryCoordinates`]): the potential `V` of the inertial positions `x(q')` plus the
    /// Kepler potentials taken out, `O(ε)` relative to the Kepler part for planet masses
    /// `mᵢ = O(ε m₀)`.
    pub fn interaction<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        q: &SVector<D, N>,
    ) -> D {
        let x = self.positions_from(coordinates, q);
        let mut h = self.potential(D::from(0.0), &x);
        for i in 1..self.bodies() {
            h += inverse_distance(self.kepler_coupling(coordinates, i), &body(q, i));
        }
        h
    }

    /// `k` of the Kepler potential `k/|q'ᵢ|` taken out of the interaction: `G mᵢ ηᵢ₋₁`
    /// (Jacobi) or `G m₀ mᵢ` (democratic heliocentric).
    fn kepler_coupling(&self, coordinates: PlanetaryCoordinates, i: usize) -> f64 {
        match coordinates {
            PlanetaryCoordinates::Jacobi => self.g * self.masses[i] * self.eta(i - 1),
            PlanetaryCoordinates::DemocraticHeliocentric => {
                self.g * self.masses[0] * self.masses[i]
            }
        }
    }

    /// The gradient `∂H_I/∂q'` of [`Self::interaction`], assembled from the terms of its one
    /// definition: each pair term `−G mᵢ mⱼ/|xᵢ − xⱼ|` and each Kepler term `k/|q'ᵢ|` is
    /// differentiated by AD in its own three variables ([`gradient`]), and the inertial part is
    /// carried to the split coordinates by the chain rule through the linear map `x = A⁻¹ q'`,
    /// `∂V/∂q' = A⁻ᵀ ∂V/∂x`, the map of momenta of [`Self::to_coordinates`]. The `q'₀` block
    /// (the centre of mass, on which `H_I` does not depend: `V` sees differences of positions
    /// only) is exactly zero. The same numbers as AD of the whole of [`Self::interaction`] in
    /// `N` variables, to rounding, at a small fraction of its cost (the Wisdom–Holman kick).
    pub(crate) fn interaction_gradient<D: DualNum<f64> + Copy>(
        &self,
        coordinates: PlanetaryCoordinates,
        q: &SVector<D, N>,
    ) -> SVector<D, N> {
        let n = self.bodies();
        let x = self.positions_from(coordinates, q);
        let mut gx = SVector::<D, N>::zeros();
        for i in 0..n {
            let xi = body(&x, i);
            for j in i + 1..n {
                let k = self.g * self.masses[i] * self.masses[j];
                // V ∋ −k/|d|, d = xᵢ − xⱼ.
                let g = inverse_distance_gradient(k, &(xi - body(&x, j)));
                add_body(&mut gx, j, g);
                add_body(&mut gx, i, -g);
            }
        }
        let mut gq = self.momenta_to(coordinates, &gx);
        set_body(&mut gq, 0, Vector3::zeros());
        for i in 1..n {
            let g = inverse_distance_gradient(self.kepler_coupling(coordinates, i), &body(q, i));
            add_body(&mut gq, i, g);
        }
        gq
    }

    /// Total linear momentum `Σ pᵢ`.
    pub fn momentum(&self, p: &SVector<f64, N>) -> Vector3<f64> {
        (0..self.bodies()).map(|i| body(p, i)).sum()
    }

    /// Total angular momentum `Σ xᵢ × pᵢ`.
    pub fn angular_momentum(&self, x: &SVector<f64, N>, p: &SVector<f64, N>) -> Vector3<f64> {
        (0..self.bodies())
            .map(|i| body(x, i).cross(&body(p, i)))
            .sum()
    }
}

impl<const N: usize> Separable<N> for PlanetarySystem<N> {
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, N>) -> D {
        let mut t = D::from(0.0);
        for (i, &m) in self.masses.iter().enumerate() {
            t += norm2(&body(p, i)) / D::from(2.0 * m);
        }
        t
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, N>) -> D {
        let n = self.bodies();
        let mut v = D::from(0.0);
        for i in 0..n {
            let xi = body(x, i);
            for j in i + 1..n {
                v -= inverse_distance(self.g * self.masses[i] * self.masses[j], &(xi - body(x, j)));
            }
        }
        v
    }
}

/// The change of coordinates [`PlanetarySystem::to_coordinates`] (or its inverse) as a map of
/// phase space, for certification as canonical ([`crate::brackets::certify`]).
pub struct CoordinateMap<'a, const N: usize> {
    /// The system.
    pub system: &'a PlanetarySystem<N>,
    /// The coordinates mapped to (or from).
    pub coordinates: PlanetaryCoordinates,
    /// Whether the map is the inverse (from `coordinates` to inertial).
    pub inverse: bool,
}

impl<const N: usize> PhaseMap<N> for CoordinateMap<'_, N> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        if self.inverse {
            self.system.from_coordinates(self.coordinates, q, p)
        } else {
            self.system.to_coordinates(self.coordinates, q, p)
        }
    }
}

/// The outer Solar System of Hairer, Lubich & Wanner (*Geometric Numerical Integration*, 2nd ed.,
/// §I.2.4, Table 2.2): the Sun (with the inner planets' mass) and Jupiter, Saturn, Uranus,
/// Neptune on 5 September 1994; masses in solar masses, distances in AU, time in days,
/// `G = 2.95912208286·10⁻⁴`. Returns the system and the inertial `(x, p)`, `p = m ẋ`.
pub fn outer_solar_system() -> (PlanetarySystem<15>, SVector<f64, 15>, SVector<f64, 15>) {
    let masses = [
        1.00000597682,
        0.000954786104043,
        0.000285583733151,
        0.0000437273164546,
        0.0000517759138449,
    ];
    let x = [
        [0.0, 0.0, 0.0],
        [-3.5023653, -3.8169847, -1.5507963],
        [9.0755314, -3.0458353, -1.6483708],
        [8.3101420, -16.2901086, -7.2521278],
        [11.4707666, -25.7294829, -10.8169456],
    ];
    let v = [
        [0.0, 0.0, 0.0],
        [0.00565429, -0.00412490, -0.00190589],
        [0.00168318, 0.00483525, 0.00192462],
        [0.00354178, 0.00137102, 0.00055029],
        [0.00288930, 0.00114527, 0.00039677],
    ];
    let system = PlanetarySystem {
        g: 2.95912208286e-4,
        masses: masses.to_vec(),
    };
    let q = SVector::<f64, 15>::from_fn(|k, _| x[k / 3][k % 3]);
    let p = SVector::<f64, 15>::from_fn(|k, _| masses[k / 3] * v[k / 3][k % 3]);
    (system, q, p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The assembled gradient of the interaction against AD of the whole of
    /// [`PlanetarySystem::interaction`] in all `N` variables through the coordinate map (a second
    /// formulation), in both coordinates, at the outer Solar System and at a state with every
    /// planet moved. Bound: the two sum the same 14 terms in different orders, and the Sun–planet
    /// pair and Kepler terms cancel to `O(mᵢ/m₀)`, so the difference is a few ulps of the largest
    /// term `kᵢ/|q'ᵢ|²` per term: `16 × 14 × ε × maxᵢ kᵢ/|q'ᵢ|²`.
    #[test]
    fn interaction_gradient_matches_full_ad() {
        let (sys, x, p) = outer_solar_system();
        let mut moved = x;
        for k in 3..15 {
            moved[k] *= 1.0 + 0.1 * (k as f64).sin();
        }
        for c in [
            PlanetaryCoordinates::Jacobi,
            PlanetaryCoordinates::DemocraticHeliocentric,
        ] {
            for x in [x, moved] {
                let (q, _) = sys.to_coordinates(c, &x, &p);
                let (_, full) = gradient(|qd| sys.interaction(c, qd), &q);
                let split = sys.interaction_gradient(c, &q);
                let largest = (1..sys.bodies())
                    .map(|i| sys.kepler_coupling(c, i) / norm2(&body(&q, i)))
                    .fold(0.0, f64::max);
                let bound = 16.0 * 14.0 * f64::EPSILON * largest;
                let d = (split - full).amax();
                println!(
                    "{c:?}: |Δ∇H_I| = {d:.1e} (bound {bound:.1e}, |∇H_I| = {:.1e})",
                    full.amax()
                );
                assert!(d <= bound, "{c:?}: {d:e} > {bound:e}");
                assert_eq!(split.fixed_rows::<3>(0).amax(), 0.0);
            }
        }
    }
}
