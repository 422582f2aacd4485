//! The Hénon–Heiles Hamiltonian `H = ½(p_x² + p_y² + x² + y²) + x²y − y³/3` about its minimum:
//! the 1:1 resonant (Gustavson) normal form from the Hamiltonian written once, its size per
//! degree, the remainder `|H ∘ φ − K|` against the amplitude, and the construction time per degree;
//! then two figures in `out/`: the remainder against the amplitude per degree, and the section
//! points (`x = 0`, `p_x > 0`) of five regular orbits at `E = 1/12` beside the level curves of
//! the second integral `L = I₁ + I₂ = ½|w'|²` of the degree-16 form through them.
//!
//! Run with `cargo run --release --example normal_form_henon_heiles`.

use hamilton_jacobi::integrate::{integrate, Crossing, Dop853, Problem, Section};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::perturbation::birkhoff::{normal_form, BirkhoffNormalForm, NormalFormKind};
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::stability::hamiltonian_equilibrium;
use hamilton_jacobi::systems::HenonHeiles;
use hamilton_jacobi::Error;
use std::time::Instant;

/// `L = ½|w'|²` at the section point `(0, y, p_x(y, p_y), p_y)` of energy `e`, `w'` by the
/// truncated series of the normal-form coordinates; `None` outside the energy's region.
fn second_integral(nf: &BirkhoffNormalForm, e: f64, y: f64, py: f64) -> Option<f64> {
    let s = HenonHeiles::section_start(e, y, py).ok()?;
    let w = nf
        .linear_coordinates(&[s.q[0], s.q[1], s.p[0], s.p[1]])
        .ok()?;
    let wn = nf.to_normal(&w).ok()?;
    Some(0.5 * wn.iter().map(|x| x * x).sum::<f64>())
}

/// The component of the level curve `L = level` through the section point nearest to `start`,
/// by continuation: steps of length `h` along the tangent `(−∂L/∂p_y, ∂L/∂y)`, each followed by
/// Newton corrections along `∇L` back to the level, until the curve closes or leaves the energy's
/// region.
fn level_curve(nf: &BirkhoffNormalForm, e: f64, start: (f64, f64), level: f64) -> Vec<(f64, f64)> {
    let l = |p: (f64, f64)| second_integral(nf, e, p.0, p.1);
    let grad = |p: (f64, f64)| -> Option<(f64, f64)> {
        let d = 1e-6;
        Some((
            (l((p.0 + d, p.1))? - l((p.0 - d, p.1))?) / (2.0 * d),
            (l((p.0, p.1 + d))? - l((p.0, p.1 - d))?) / (2.0 * d),
        ))
    };
    let project = |mut p: (f64, f64)| -> Option<(f64, f64)> {
        for _ in 0..8 {
            let g = grad(p)?;
            let r = (l(p)? - level) / (g.0 * g.0 + g.1 * g.1);
            p = (p.0 - r * g.0, p.1 - r * g.1);
        }
        Some(p)
    };
    let h = 0.004;
    let Some(first) = project(start) else {
        return Vec::new();
    };
    let mut out = vec![first];
    let mut p = first;
    for k in 0..5000 {
        let Some(g) = grad(p) else { break };
        let n = g.0.hypot(g.1);
        let Some(next) = project((p.0 - h * g.1 / n, p.1 + h * g.0 / n)) else {
            break;
        };
        out.push(next);
        p = next;
        if k > 10 && (p.0 - first.0).hypot(p.1 - first.1) < h {
            out.push(first);
            break;
        }
    }
    out
}

fn main() -> hamilton_jacobi::Result<()> {
    let eq = hamiltonian_equilibrium(
        &HenonHeiles,
        0.0,
        &Vector2::new(0.1, -0.1),
        &Vector2::zeros(),
    )?;
    println!(
        "equilibrium q = {:?}, |∇H| = {:e}",
        eq.q.as_slice(),
        eq.gradient_norm
    );
    let resonance = NormalFormKind::Resonant(vec![vec![1, -1]]);
    let amplitudes: Vec<f64> = (0..=12)
        .map(|k| 0.02 * 20f64.powf(f64::from(k) / 12.0))
        .collect();
    let mut remainder_fig = Figure::new(
        "Hénon–Heiles, 1:1 resonant normal form: remainder against amplitude",
        "amplitude ρ = |w'|",
        "max |H ∘ φ − K| on |w'| = ρ",
    )
    .log_x()
    .log_y()
    .caption(
        "The largest |H ∘ φ − K| over 64 points of the sphere |w'| = ρ in the normal-form \
         coordinates, φ the truncated series of the near-identity map, for the 1:1 resonant \
         (Gustavson) normal form of degree K: slope K + 1 at small ρ; the degrees cross where \
         the series stops converging.",
    );
    println!("degree  time        ‖K_K‖        remainder(ρ=0.05)  remainder(ρ=0.1)  optimal degree at ρ=0.3");
    let mut form16 = None;
    for degree in [4usize, 6, 8, 10, 12, 14, 16, 20, 24] {
        let clock = Instant::now();
        let nf = normal_form(&HenonHeiles, 0.0, &eq, degree, resonance.clone())?;
        let elapsed = clock.elapsed();
        let r1 = nf.remainder(&HenonHeiles, 0.0, 0.05, 64)?;
        let r2 = nf.remainder(&HenonHeiles, 0.0, 0.1, 64)?;
        let d = nf.diagnostics(0.3)?;
        println!(
            "{degree:6}  {:>9.3?}  {:11.3e}  {r1:17.3e}  {r2:16.3e}  {}",
            elapsed,
            nf.normal_form().part_norm(degree),
            d.optimal_degree
        );
        if [4, 8, 12, 16, 20].contains(&degree) {
            let pts: Vec<(f64, f64)> = amplitudes
                .iter()
                .map(|&r| Ok((r, nf.remainder(&HenonHeiles, 0.0, r, 64)?)))
                .collect::<hamilton_jacobi::Result<Vec<_>>>()?
                .into_iter()
                .filter(|p| p.1 > 0.0)
                .collect();
            remainder_fig = remainder_fig.curve(format!("K = {degree}"), pts, Style::LineMarkers);
        }
        if degree == 16 {
            form16 = Some(nf);
        }
    }
    let nf = form16.expect("degree 16 is in the list");
    // Five regular orbits at E = 1/12 (MEGNO ⟨Y⟩ ≤ 2.05, tests/normal_form.rs).
    let e = 1.0 / 12.0;
    let orbits = [
        ("QP1", 0.0, 0.25),
        ("QP2", 0.0, 0.3),
        ("QP3", -0.2, 0.1),
        ("QP4", 0.15, -0.2),
        ("QP5", 0.23, 0.0),
    ];
    let mut section_fig = Figure::new(
        "Hénon–Heiles, E = 1/12: section points and level curves of the second integral",
        "y",
        "p_y",
    )
    .equal_aspect()
    .caption(
        "Points of five regular orbits on the section x = 0, p_x > 0 (DOP853, tolerance \
         1e−13, 200 crossings each) and, through each, the level curve L = L̄ of the second \
         integral L = I₁ + I₂ of the degree-16 1:1 resonant normal form (L̄ the mid-range of L \
         over the orbit's points), traced by continuation from the first point.",
    );
    let dop = Dop853::new(1e-13, 1e-16)?.with_max_steps(10_000_000)?;
    for (name, y, py) in orbits {
        let s = HenonHeiles::section_start(e, y, py)?;
        let problem = Problem::new(&HenonHeiles, 0.0, s.q, s.p, 1e6)?;
        let mut section =
            Section::new(|_t, q: &SVector<f64, 2>, _p| q[0], Crossing::Up).stop_after(200);
        integrate(&problem, &dop, &mut section)?;
        let pts: Vec<(f64, f64)> = section.points.iter().map(|z| (z.q[1], z.p[1])).collect();
        let vals: Vec<f64> = pts
            .iter()
            .filter_map(|&(y, py)| second_integral(&nf, e, y, py))
            .collect();
        let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let curve = level_curve(&nf, e, pts[0], 0.5 * (lo + hi));
        println!(
            "{name}: L from {lo:.9} to {hi:.9} on {} section points; level curve of {} points",
            pts.len(),
            curve.len()
        );
        section_fig = section_fig
            .curve(format!("{name}: section points"), pts, Style::Dots)
            .curve(format!("{name}: L = L̄, K = 16"), curve, Style::Line);
    }
    std::fs::create_dir_all("out").map_err(|e| Error::invalid("directory out", e.to_string()))?;
    for (fig, stem) in [
        (&remainder_fig, "out/henon-heiles-remainder"),
        (&section_fig, "out/henon-heiles-level-curves"),
    ] {
        for f in fig.write(
            std::path::Path::new(stem),
            &[Format::Svg, Format::Png],
            DataFormat::Csv,
        )? {
            println!("figure: {}", f.display());
        }
    }
    Ok(())
}
