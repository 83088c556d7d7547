//! `geoslip calibrate`: fit an interface law to measured curves and write the report, the plots and
//! the law ready for a model.

use super::exit;
use crate::calibration::{self, report, CalibrationError};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

pub fn calibrate(spec: &Path, out: Option<PathBuf>) -> ExitCode {
    match run(spec, out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                CalibrationError::Write { .. } => exit::WRITE,
                CalibrationError::NotConverged { .. } | CalibrationError::Model { .. } => exit::NOT_CONVERGED,
                _ => exit::BAD_INPUT,
            })
        }
    }
}

fn run(spec: &Path, out: Option<PathBuf>) -> Result<(), CalibrationError> {
    let spec = calibration::spec::load(spec)?;
    let c = calibration::calibrate(&spec)?;
    let out = out.unwrap_or_else(|| Path::new("results").join(crate::output::path_component(&spec.title)));
    report::write(&c, &out)?;
    println!("{} law fitted to {} curves ({} points):", c.spec.law.name(), c.curves.len(), c.fit.points);
    for p in &c.parameters {
        match (p.standard_error, p.interval) {
            (Some(se), Some((lo, hi))) => println!(
                "  {:<24} {:>12} {:<6} ± {} (95 %: {} … {})",
                p.name,
                report::significant(p.value, 5),
                p.unit,
                report::significant(se, 3),
                report::significant(lo, 5),
                report::significant(hi, 5)
            ),
            _ => println!(
                "  {:<24} {:>12} {:<6} {}",
                p.name,
                report::significant(p.value, 5),
                p.unit,
                if p.at_bound { "(at a bound of its range)" } else { "(fixed)" }
            ),
        }
    }
    for w in &c.warnings {
        println!("warning: {w}");
    }
    print!("{}", report::law_block(&c));
    println!(
        "written to {} (calibration.md, calibration.json, interface-law.toml, fitted-curves.png/.svg)",
        out.display()
    );
    Ok(())
}
