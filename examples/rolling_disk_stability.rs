//! Upright rolling of a disk and of a hoop (SPEC M70, T17): the eigenvalues of the linearisation
//! in the reduced variables `(ψ, ϑ̇, ψ̇, φ̇)` of the Boltzmann–Hamel equations against the speed
//! `v`, the two zeros of the family of steady motions factored out, and the critical speed where
//! the real part of the lean mode reaches zero, located by Brent's method and compared with
//! `v_c² = A m g r³/(C(C + m r²))` [Hamel art. 244].
//!
//! Writes `out/rolling-disk-stability.{svg,png}` with the data beside them.

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::BoltzmannHamel;
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::stability::{
    real_part_crossings, spectra, steady_motion_spectrum, Reduced, Slot, Spectrum,
};
use hamilton_jacobi::systems::RollingDisk;
use hamilton_jacobi::Result;

// ANCHOR: spectrum
/// The spectrum of upright rolling at speed `v`: `x, y, ϑ, φ` cyclic, `(ψ, ϑ̇, ψ̇, φ̇)` kept.
fn upright(body: RollingDisk, v: f64) -> Result<Spectrum> {
    let equations = BoltzmannHamel::new(body, body);
    let omega = SVector::<f64, 5>::from([0.0, 0.0, 0.0, 0.0, v]);
    let kept = [Slot::Q(3), Slot::P(2), Slot::P(3), Slot::P(4)];
    let reduced = Reduced::new(&equations, &SVector::zeros(), &omega, kept)?;
    steady_motion_spectrum(&reduced, 0.0, &reduced.state())
}
// ANCHOR_END: spectrum

fn main() -> Result<()> {
    let g = 9.81;
    let mut fig = Figure::new(
        "Upright rolling (m = r = 1, g = 9.81): transverse eigenvalues against speed",
        "v",
        "Re λ",
    );
    for (name, body, oracle) in [
        ("disk", RollingDisk::disk(1.0, 1.0, g)?, 1.80831413200251),
        ("hoop", RollingDisk::hoop(1.0, 1.0, g)?, 1.56604597633658),
    ] {
        let speeds: Vec<f64> = (0..=240).map(|i| 0.5 + 3.0 * i as f64 / 240.0).collect();
        let sweep = spectra(|v| upright(body, v), &speeds)?;
        let branch = |k: usize| -> Vec<(f64, f64)> {
            sweep
                .iter()
                .map(|s| (s.parameter, s.spectrum.transverse[k].re))
                .collect()
        };
        fig = fig
            .curve(format!("{name}: Re λ₁"), branch(0), Style::Line)
            .curve(format!("{name}: Re λ₂"), branch(1), Style::Line);
        let crossings = real_part_crossings(|v| upright(body, v), 0.5, 3.5, 13, 1e-14)?;
        for c in &crossings {
            println!(
                "{name}: Re λ crosses zero at v = {:.15} (Brent, {} iterations); \
                 v_c = {:.15} from A m g r³/(C(C + m r²)); SPEC {oracle}; difference {:.1e}",
                c.parameter,
                c.iterations,
                body.critical_speed()?,
                c.parameter - oracle
            );
            fig = fig.curve(
                format!("{name}: v_c = {:.12}", c.parameter),
                vec![(c.parameter, 0.0)],
                Style::Markers,
            );
        }
        let s = upright(body, 3.0)?;
        println!(
            "{name} at v = 3: family of steady motions of dimension {}, transverse {:?}, {:?}",
            s.family_dimension(),
            s.transverse,
            s.stability
        );
    }
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("directory out", e.to_string()))?;
    for f in fig.write(
        std::path::Path::new("out/rolling-disk-stability"),
        &[Format::Svg, Format::Png],
        DataFormat::Csv,
    )? {
        println!("  {}", f.display());
    }
    Ok(())
}
