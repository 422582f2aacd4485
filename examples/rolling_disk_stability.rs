//! Upright rolling of a disk and of a hoop (SPEC M70, T17): the eigenvalues of the linearisation
//! in the reduced variables `(ψ, ϑ̇, ψ̇, φ̇)` of the Boltzmann–Hamel equations against the speed
//! `v`, the two zeros of the family of steady motions factored out, and the critical speed where
//! the real part of the lean mode reaches zero, located by Brent's method and compared with
//! `v_c² = A m g r³/(C(C + m r²))` [Hamel art. 244].
//!
//! Writes `out/rolling-disk-stability.{svg,png}` with the data beside them.

use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::stability::{parameter_study, upright_rolling_spectrum};
use hamilton_jacobi::systems::RollingDisk;
use hamilton_jacobi::Result;

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
        // ANCHOR: spectrum
        let study = parameter_study(|v| upright_rolling_spectrum(body, v), 0.5, 3.5, 241, 1e-14)?;
        // ANCHOR_END: spectrum
        let branch = |k: usize| -> Vec<(f64, f64)> {
            study
                .spectra
                .iter()
                .map(|s| (s.parameter, s.spectrum.transverse[k].re))
                .collect()
        };
        fig = fig
            .curve(format!("{name}: Re λ₁"), branch(0), Style::Line)
            .curve(format!("{name}: Re λ₂"), branch(1), Style::Line);
        let crossings = &study.crossings;
        for c in crossings {
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
        let s = upright_rolling_spectrum(body, 3.0)?;
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
