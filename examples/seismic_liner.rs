//! A cover soil on a geomembrane-lined slope under an earthquake: its permanent slip on the liner
//! by geoslip, beside Newmark's rigid sliding block whose yield acceleration comes from geoslip's
//! own pseudo-static runs.
//!
//! Description: runs `examples/seismic-liner/seismic-liner.toml` (the standard results, with the
//! report's Shaking section and `motion.csv`, go to `results/seismic-liner/`), then:
//! 1. the yield acceleration: the same model with a pseudo-static stage (the cover's weight times
//!    kh towards the slope's foot) and a strength-reduction stage of the interface; kh is bisected
//!    until FS = 1: k_y at the interface's peak strength, and again with its residual strength;
//! 2. Newmark's rigid block on the slope (s̈ = κ·(a − k_y·g) down the slope while it slides, κ =
//!    cos(φ − β)/cos φ) under the same record, integrated here with both yield accelerations;
//! 3. `results/seismic-liner/newmark.md`: the three slips side by side, and why they differ.
//!
//! Sample run:
//!   cargo run --release --example seismic_liner

use geoslip::analysis::results::StepResults;
use geoslip::analysis::{self, Collect, RunOptions, RunStats, StepRecord, StepSink};
use geoslip::model::file::*;
use geoslip::model::Model;
use geoslip::output::run_and_write;
use geoslip::Error;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const PEAK: f64 = 24.0;
const RESIDUAL: f64 = 20.0;

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The cover's mean slip on the liner at the end of the shaking, and before it.
#[derive(Default)]
struct Slip {
    before: Option<f64>,
    end: Option<f64>,
}

impl StepSink for Slip {
    fn step_done(
        &mut self,
        _: &geoslip::model::Model,
        step: &StepResults,
        record: &StepRecord,
        _: &RunStats,
    ) -> Result<(), Error> {
        let points: Vec<f64> =
            step.interface_points.iter().filter(|p| p.interface == "liner").map(|p| p.slip).collect();
        let mean = points.iter().sum::<f64>() / points.len().max(1) as f64;
        match record.time {
            Some(_) => self.end = Some(mean),
            None if self.end.is_none() => self.before = Some(mean),
            None => {}
        }
        Ok(())
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/seismic-liner/seismic-liner.toml");
    let out = PathBuf::from("results/seismic-liner");
    let model = Model::load(&path)?;
    let mut slip = Slip::default();
    run_and_write(&model, &out, &Default::default(), &mut slip)?;
    // the slip along the slave line counts towards its first node, up the slope: down is −slip
    let fe = -(slip.end.ok_or("the shaking completed no step")? - slip.before.unwrap_or(0.0));

    let text = std::fs::read_to_string(&path)?;
    let file = geoslip::model::parse(&path, &text)?;
    let beta = slope_of(&model);
    let ky_peak = yield_coefficient(&path, &file, None)?;
    let ky_residual = yield_coefficient(&path, &file, Some(RESIDUAL))?;
    let dynamic = model.stages.iter().find_map(|s| s.dynamic.as_ref()).ok_or("no dynamic stage")?;
    let (_, ground) = &dynamic.base_motion[0];
    let g = dynamic.gravity;
    // the ground's acceleration towards −x drives the cover down the slope (towards +x)
    let drive = |t: f64| -ground.at(t);
    let newmark_peak = newmark(&drive, ky_peak * g, beta, PEAK, dynamic.duration);
    let newmark_residual = newmark(&drive, ky_residual * g, beta, RESIDUAL, dynamic.duration);

    let mut r = String::new();
    let _ = writeln!(r, "# The cover's permanent slip: geoslip beside Newmark's sliding block\n");
    let _ = writeln!(
        r,
        "Model: `{}`; slope β = {:.2}°; the record's peak {:.3} g.\n",
        path.display(),
        beta,
        ground.peak() / g
    );
    let _ = writeln!(r, "| | yield coefficient k_y | permanent slip down the slope [m] |");
    let _ = writeln!(r, "|---|---:|---:|");
    let _ = writeln!(r, "| geoslip (peak → residual interface, elastic cover) | | {fe:.4} |");
    let _ = writeln!(r, "| Newmark, k_y at the peak strength | {ky_peak:.4} | {newmark_peak:.4} |");
    let _ = writeln!(r, "| Newmark, k_y at the residual strength | {ky_residual:.4} | {newmark_residual:.4} |");
    let _ = writeln!(
        r,
        "\nk_y is the seismic coefficient at which geoslip's pseudo-static run (the cover's weight times kh \
         towards the slope's foot) has a factor of safety of 1 by strength reduction of the interface, found \
         by bisection; the infinite slope's tan(φ − β) is {:.4} at the peak and {:.4} at the residual angle.\n",
        (PEAK - beta).to_radians().tan(),
        (RESIDUAL - beta).to_radians().tan()
    );
    let _ = writeln!(r, "Why they differ:\n");
    let infinite_peak = (PEAK - beta).to_radians().tan();
    if ky_peak < 0.98 * infinite_peak {
        let _ = writeln!(
            r,
            "- The pseudo-static k_y at the peak strength, {ky_peak:.4}, is below the infinite slope's {infinite_peak:.4}: \
             under the seismic force the strip's ends slip first, drop to the residual strength and pass their load \
             on, so the peak is never mobilised everywhere at once (a progressive failure of a brittle interface). \
             At the residual strength, which has no peak to lose, geoslip's k_y is the infinite slope's."
        );
    }
    let _ = writeln!(
        r,
        "- Newmark's block has one yield acceleration. The interface here has two strengths: once a point \
         slips past its peak it keeps only the residual, so after the first slip the cover slides at the \
         residual's lower yield acceleration. geoslip's slip therefore lies between the block's at the peak \
         and at the residual strength, nearer the residual's the more of the shaking comes after the first slip."
    );
    let _ = writeln!(
        r,
        "- The cover is elastic and the interface has a shear stiffness Ks: it moves before it slides, and \
         waves along the 12 m strip make the slip start at one end. The rigid block does neither."
    );
    let _ = writeln!(
        r,
        "- The block's relative acceleration while sliding is κ·(a − a_y) with κ = cos(φ − β)/cos φ, for a \
         block whose normal force changes with the horizontal shaking; in geoslip the normal stress follows \
         the cover's own equilibrium at every step."
    );
    std::fs::write(out.join("newmark.md"), &r)?;
    println!("{r}");
    println!("written: {}", out.join("newmark.md").display());
    Ok(())
}

/// The slope of the liner, degrees, from its first and last node.
fn slope_of(model: &Model) -> f64 {
    let liner = &model.node_sets["liner"];
    let (a, b) = (model.mesh.position(liner[0]), model.mesh.position(liner[liner.len() - 1]));
    ((a[1] - b[1]) / (b[0] - a[0])).atan().to_degrees()
}

/// The seismic coefficient kh at which the cover's factor of safety by strength reduction of the
/// interface is 1: bisected on the model with its dynamic stages replaced by a pseudo-static stage
/// and a strength-reduction stage (with the interface's friction angle `angle` at peak and
/// residual, when given).
fn yield_coefficient(path: &Path, file: &ModelFile, angle: Option<f64>) -> Result<f64, Box<dyn std::error::Error>> {
    let factor_of_safety = |kh: f64| -> Result<f64, Box<dyn std::error::Error>> {
        let mut f = file.clone();
        if let Some(angle) = angle {
            for i in &mut f.interfaces {
                i.law = ShearLawSpec::Coulomb { shear_stiffness: 20_000.0, cohesion: 0.0, friction_angle: angle };
            }
        }
        f.stages.retain(|s| s.dynamic.is_none() && s.loads.iter().any(|l| matches!(l, LoadSpec::Gravity { .. })));
        f.stages.push(Stage {
            name: "pseudo-static".into(),
            loads: vec![LoadSpec::PseudoStatic { kh, kv: 0.0 }],
            ..Default::default()
        });
        f.stages.push(Stage {
            name: "factor of safety".into(),
            strength_reduction: Some(StrengthReductionSpec {
                reduce: ReducedStrengths::Interfaces,
                tolerance: Some(1e-4),
                max_factor: Some(3.0),
            }),
            ..Default::default()
        });
        let model = Model::from_file(path, &f)?;
        let mut c = Collect::default();
        match analysis::run(&model, &RunOptions::for_model(&model, geoslip::linsol::Backend::Auto), &mut c) {
            Ok(_) => Ok(c.factors_of_safety.last().ok_or("no factor of safety")?.value),
            // no equilibrium under kh with the full strengths: FS < 1
            Err(e) if e.to_string().contains("stage \"pseudo-static\"") => Ok(0.0),
            Err(e) => Err(e.into()),
        }
    };
    let (mut low, mut high) = (0.0, 0.5);
    if factor_of_safety(low)? < 1.0 {
        return Err("the cover does not stand without shaking".into());
    }
    while high - low > 1e-4 {
        let mid = 0.5 * (low + high);
        if factor_of_safety(mid)? >= 1.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    Ok(0.5 * (low + high))
}

/// Newmark's rigid block on a plane inclined at `beta` (friction angle `phi`) under the
/// acceleration `drive` towards its foot: s̈ = κ·(a − a_y) while it slides down (κ = cos(φ − β)/
/// cos φ); up the slope it would need the ground to pull past g·tan(φ + β), which this record does
/// not. Integrated by the midpoint rule in steps of 0.1 ms.
fn newmark(drive: &dyn Fn(f64) -> f64, a_y: f64, beta: f64, phi: f64, duration: f64) -> f64 {
    let kappa = (phi - beta).to_radians().cos() / phi.to_radians().cos();
    let step = 1e-4;
    let (mut v, mut d, mut t) = (0.0f64, 0.0, 0.0);
    while t < duration {
        let a = drive(t + step / 2.0);
        let dv = if v > 0.0 || a > a_y { kappa * (a - a_y) * step } else { 0.0 };
        let next = (v + dv).max(0.0);
        d += 0.5 * (v + next) * step;
        v = next;
        t += step;
    }
    d
}
