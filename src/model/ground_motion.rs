//! A base acceleration record: read from a PEER NGA `.AT2` file or a CSV file (both may come from
//! anyone: read bounded, every count checked against what is there before it is believed), or
//! given inline; checked, scaled and held as samples (t, a) in the model's units.

use std::path::Path;

/// The most samples a record may hold.
pub const MAX_MOTION_SAMPLES: usize = 1_000_000;
/// The largest record file read, bytes (a million samples in 16 characters each, and room).
const MAX_RECORD_BYTES: u64 = 64 << 20;

/// A base acceleration: samples (t, a) with t increasing from 0 and a = 0 at t = 0 (the ground at
/// rest when the stage starts); linear between samples, zero after the last.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundMotion {
    samples: Vec<[f64; 2]>,
    /// The velocity at each sample: the acceleration integrated from rest.
    velocities: Vec<f64>,
}

impl GroundMotion {
    /// The acceleration at time `t` (zero before 0 and after the last sample).
    pub fn at(&self, t: f64) -> f64 {
        let s = &self.samples;
        let Some(last) = s.last() else { return 0.0 };
        if !(t >= 0.0) || t > last[0] {
            return 0.0;
        }
        let k = s.partition_point(|p| p[0] <= t);
        if k == 0 {
            return s[0][1];
        }
        if k == s.len() {
            return last[1];
        }
        let (a, b) = (s[k - 1], s[k]);
        a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
    }

    /// The velocity at time `t`: the acceleration, linear between samples, integrated from rest
    /// (constant after the last sample, where the acceleration is zero).
    pub fn velocity(&self, t: f64) -> f64 {
        let s = &self.samples;
        if !(t > 0.0) || s.is_empty() {
            return 0.0;
        }
        let k = s.partition_point(|p| p[0] <= t);
        if k == s.len() {
            return self.velocities[k - 1];
        }
        if k == 0 {
            return 0.0;
        }
        let (a, b) = (s[k - 1], s[k]);
        let tau = t - a[0];
        self.velocities[k - 1] + a[1] * tau + (b[1] - a[1]) * tau * tau / (2.0 * (b[0] - a[0]))
    }

    /// The samples (t, a).
    pub fn samples(&self) -> &[[f64; 2]] {
        &self.samples
    }

    /// The largest |a|.
    pub fn peak(&self) -> f64 {
        self.samples.iter().fold(0.0, |m, p| m.max(p[1].abs()))
    }

    /// Checked samples times `factor`: finite, t strictly increasing from t ≥ 0, a = 0 at t = 0
    /// (a sample (0, 0) is put in front of a series that starts later).
    ///
    /// # Errors
    /// What is wrong, naming the row (1-based).
    pub fn from_samples(samples: &[[f64; 2]], factor: f64) -> Result<GroundMotion, String> {
        if samples.is_empty() {
            return Err("the record has no samples".into());
        }
        if samples.len() > MAX_MOTION_SAMPLES {
            return Err(format!("at most {MAX_MOTION_SAMPLES} samples, found {}", samples.len()));
        }
        for (i, p) in samples.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(format!("sample {} is not a finite (t, a): {p:?}", i + 1));
            }
            if i == 0 && p[0] < 0.0 {
                return Err(format!("the first sample's time is {} s: times start at 0 or later", p[0]));
            }
            if i > 0 && !(p[0] > samples[i - 1][0]) {
                return Err(format!(
                    "times must increase: sample {} is at {} s after {} s",
                    i + 1,
                    p[0],
                    samples[i - 1][0]
                ));
            }
        }
        if samples[0][0] == 0.0 && samples[0][1] != 0.0 {
            return Err(format!(
                "the ground is at rest when the stage starts, but the record's acceleration at t = 0 is {}: start it with 0",
                samples[0][1]
            ));
        }
        let mut scaled = Vec::with_capacity(samples.len() + 1);
        if samples[0][0] > 0.0 {
            scaled.push([0.0, 0.0]);
        }
        scaled.extend(samples.iter().map(|p| [p[0], p[1] * factor]));
        let mut velocities = vec![0.0; scaled.len()];
        for k in 1..scaled.len() {
            let (a, b) = (scaled[k - 1], scaled[k]);
            velocities[k] = velocities[k - 1] + 0.5 * (a[1] + b[1]) * (b[0] - a[0]);
        }
        Ok(GroundMotion { samples: scaled, velocities })
    }
}

/// The samples of a record file: `.AT2` (PEER NGA: four header lines, the fourth giving NPTS and
/// DT, then NPTS accelerations; sample i at t = i·DT, i from 1) or CSV (rows `t, a`, separated by
/// a comma, semicolon or blanks; `#` comments and one header line allowed).
///
/// # Errors
/// The file cannot be read, or what is wrong in it (with its line).
pub fn read_record(path: &Path) -> Result<Vec<[f64; 2]>, String> {
    let limit = crate::input_file::SizeLimit { bytes: MAX_RECORD_BYTES, why: "a record file's limit" };
    let bytes = crate::input_file::read(path, limit).map_err(|e| format!("cannot read it: {e}"))?;
    let text = String::from_utf8(bytes).map_err(|_| "it is not text (UTF-8)".to_string())?;
    if is_at2(path) {
        at2(&text)
    } else {
        csv(&text)
    }
}

/// Whether the file is a PEER `.AT2` record (by its extension).
pub fn is_at2(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("at2"))
}

fn at2(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.by_ref().take(4).collect();
    if header.len() < 4 {
        return Err("an .AT2 record has four header lines; this one ends before".into());
    }
    let (count, dt) = at2_count_and_step(header[3]).ok_or_else(|| {
        format!("line 4 should give NPTS and DT (\"NPTS= 4000, DT= .0050 SEC\"), found \"{}\"", shown(header[3]))
    })?;
    if count == 0 || count > MAX_MOTION_SAMPLES {
        return Err(format!("NPTS must be in [1, {MAX_MOTION_SAMPLES}], found {count}"));
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(format!("DT must be a positive time step, found {dt}"));
    }
    let mut samples = Vec::new();
    for (k, line) in lines.enumerate() {
        for word in line.split(|c: char| c.is_whitespace() || c == ',').filter(|w| !w.is_empty()) {
            let a: f64 = word.parse().map_err(|_| format!("line {}: \"{}\" is not a number", k + 5, shown(word)))?;
            if samples.len() == count {
                return Err(format!("the record holds more than its NPTS = {count} values (line {})", k + 5));
            }
            samples.push([(samples.len() + 1) as f64 * dt, a]);
        }
    }
    if samples.len() != count {
        return Err(format!("NPTS = {count}, but the record holds {} values", samples.len()));
    }
    Ok(samples)
}

/// NPTS and DT from an `.AT2` record's fourth line: `NPTS= 4000, DT= .0050 SEC` or, in the older
/// layout, `4000 .0050 NPTS, DT`.
fn at2_count_and_step(line: &str) -> Option<(usize, f64)> {
    let upper = line.to_ascii_uppercase();
    let after = |key: &str| -> Option<&str> {
        let at = upper.find(key)? + key.len();
        line[at..]
            .trim_start_matches(|c: char| c == '=' || c.is_whitespace())
            .split(|c: char| c == ',' || c.is_whitespace())
            .next()
    };
    if let (Some(n), Some(dt)) = (after("NPTS"), after("DT")) {
        if let (Ok(n), Ok(dt)) = (n.parse::<usize>(), dt.parse::<f64>()) {
            return Some((n, dt));
        }
    }
    let mut words = line.split(|c: char| c == ',' || c.is_whitespace()).filter(|w| !w.is_empty());
    let n = words.next()?.parse::<usize>().ok()?;
    let dt = words.next()?.parse::<f64>().ok()?;
    Some((n, dt))
}

fn csv(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut samples = Vec::new();
    let mut header_seen = false;
    for (k, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> =
            line.split(|c: char| c == ',' || c == ';' || c.is_whitespace()).filter(|w| !w.is_empty()).collect();
        let numbers: Option<Vec<f64>> = words.iter().map(|w| w.parse::<f64>().ok()).collect();
        match numbers {
            Some(v) if v.len() == 2 => {
                if samples.len() == MAX_MOTION_SAMPLES {
                    return Err(format!("at most {MAX_MOTION_SAMPLES} samples (line {})", k + 1));
                }
                samples.push([v[0], v[1]]);
            }
            None if samples.is_empty() && !header_seen => header_seen = true,
            _ => return Err(format!("line {}: expected two numbers `t, a`, found \"{}\"", k + 1, shown(line))),
        }
    }
    Ok(samples)
}

/// At most 60 characters of a line from a file, for a message.
fn shown(text: &str) -> String {
    let cut: String = text.chars().take(60).collect();
    if cut.len() < text.len() {
        format!("{cut}…")
    } else {
        cut
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_at2_record_is_read_in_both_header_layouts() {
        let new = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    5, DT=   .0100 SEC\n  .1E-02  .2E-02 -.3E-02\n  .4E-02  .5E-02\n";
        let samples = at2(new).unwrap();
        assert_eq!(samples.len(), 5);
        assert_eq!(samples[0], [0.01, 0.001]);
        assert!((samples[4][0] - 0.05).abs() < 1e-15 && samples[4][1] == 0.005);
        let old = "PEER\nTEST\nUNITS OF G\n    3    0.0200    NPTS, DT\n 1.0 2.0 3.0\n";
        assert_eq!(at2(old).unwrap(), vec![[0.02, 1.0], [0.04, 2.0], [0.06, 3.0]]);
    }

    #[test]
    fn an_at2_record_whose_count_is_wrong_is_refused() {
        let short = "a\nb\nc\nNPTS= 4, DT= .01 SEC\n 1 2 3\n";
        assert!(at2(short).unwrap_err().contains("holds 3 values"));
        let long = "a\nb\nc\nNPTS= 2, DT= .01 SEC\n 1 2 3\n";
        assert!(at2(long).unwrap_err().contains("more than its NPTS = 2"));
        let huge = "a\nb\nc\nNPTS= 999999999999, DT= .01 SEC\n 1\n";
        assert!(at2(huge).unwrap_err().contains("NPTS must be in"));
    }

    #[test]
    fn a_csv_record_takes_a_header_and_comments() {
        let text = "time, acceleration\n# a comment\n0, 0\n0.1; 0.5\n0.2 -0.25\n";
        assert_eq!(csv(text).unwrap(), vec![[0.0, 0.0], [0.1, 0.5], [0.2, -0.25]]);
        assert!(csv("0, 0\n0.1, x\n").unwrap_err().contains("line 2"));
    }

    #[test]
    fn a_motion_is_linear_between_samples_and_zero_after_them() {
        let m = GroundMotion::from_samples(&[[0.1, 1.0], [0.3, -1.0]], 2.0).unwrap();
        assert_eq!(m.at(0.0), 0.0);
        assert!((m.at(0.05) - 1.0).abs() < 1e-15);
        assert!((m.at(0.2) - 0.0).abs() < 1e-15);
        assert_eq!(m.at(0.3), -2.0);
        assert_eq!(m.at(0.31), 0.0);
        assert!(GroundMotion::from_samples(&[[0.0, 1.0]], 1.0).unwrap_err().contains("at rest"));
        assert!(GroundMotion::from_samples(&[[0.1, 1.0], [0.1, 2.0]], 1.0).unwrap_err().contains("increase"));
    }

    #[test]
    fn a_motion_s_velocity_is_its_acceleration_integrated_from_rest() {
        // a = 20·t up to 0.1 s (v = 10·t²), then down to −2 at 0.3 s, then nothing
        let m = GroundMotion::from_samples(&[[0.1, 1.0], [0.3, -1.0]], 2.0).unwrap();
        for (t, v) in [(0.0, 0.0), (0.05, 0.025), (0.1, 0.1), (0.2, 0.2), (0.3, 0.1), (1.0, 0.1)] {
            assert!((m.velocity(t) - v).abs() < 1e-15, "v({t}) = {} against {v}", m.velocity(t));
        }
    }
}
