//! Measured curves from a CSV file whose header carries the units: `normal_stress [kPa],slip
//! [mm],shear_stress [kPa]` for direct-shear tests, `surcharge [kPa],displacement [mm],force [kN/m]`
//! for pull-out tests. Rows with the same first quantity (σn or the surcharge) form one curve, in
//! the order of the file. Values are converted to m, kPa and kN/m.

use super::error::CalibrationError;
use super::spec::TestKind;
use std::collections::HashMap;
use std::path::Path;

/// The most rows a curve file may have.
pub const MAX_ROWS: usize = 1_000_000;
/// The fewest points a curve must have.
pub const MIN_POINTS: usize = 3;

/// One measured curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// σn [kPa] of a direct-shear curve, the surcharge [kPa] of a pull-out curve.
    pub condition: f64,
    /// Slip or head displacement [m].
    pub x: Vec<f64>,
    /// Shear stress [kPa] or pull-out force [kN/m].
    pub y: Vec<f64>,
}

/// The three quantities of a test's curve file: name, and the factor of each accepted unit to m,
/// kPa or kN/m.
struct Quantity {
    names: &'static [&'static str],
    units: &'static [(&'static str, f64)],
}

const STRESS: &[(&str, f64)] = &[("Pa", 1e-3), ("kPa", 1.0), ("MPa", 1e3)];
const LENGTH: &[(&str, f64)] = &[("m", 1.0), ("cm", 1e-2), ("mm", 1e-3)];
const FORCE_PER_WIDTH: &[(&str, f64)] = &[("N/m", 1e-3), ("kN/m", 1.0)];

fn quantities(kind: TestKind) -> [Quantity; 3] {
    match kind {
        TestKind::DirectShear => [
            Quantity { names: &["normal_stress"], units: STRESS },
            Quantity { names: &["slip", "displacement"], units: LENGTH },
            Quantity { names: &["shear_stress"], units: STRESS },
        ],
        TestKind::PullOut => [
            Quantity { names: &["surcharge", "normal_stress"], units: STRESS },
            Quantity { names: &["displacement"], units: LENGTH },
            Quantity { names: &["force"], units: FORCE_PER_WIDTH },
        ],
    }
}

/// The header a test's curve file must have (in this order or any other), for messages and docs.
pub fn expected_header(kind: TestKind) -> &'static str {
    match kind {
        TestKind::DirectShear => "normal_stress [kPa],slip [mm],shear_stress [kPa]",
        TestKind::PullOut => "surcharge [kPa],displacement [mm],force [kN/m]",
    }
}

/// Read the curves of a test from `path`.
///
/// # Errors
/// [`CalibrationError::Data`] naming the line and column: a quantity missing from the header or
/// without a unit in brackets, an unknown unit, a value that is not a finite number, a negative
/// normal stress, more than [`MAX_ROWS`] rows, or a curve of fewer than [`MIN_POINTS`] points.
pub fn read(path: &Path, kind: TestKind) -> Result<Vec<Curve>, CalibrationError> {
    let read = |source| CalibrationError::Read { path: path.into(), source };
    let bytes = crate::input_file::read(path, crate::input_file::SizeLimit::of_memory(None)).map_err(read)?;
    let text =
        String::from_utf8(bytes).map_err(|e| read(std::io::Error::new(std::io::ErrorKind::InvalidData, e).into()))?;
    parse(path, &text, kind)
}

/// [`read`] on text already read.
///
/// # Errors
/// As [`read`].
pub fn parse(path: &Path, text: &str, kind: TestKind) -> Result<Vec<Curve>, CalibrationError> {
    let error = |line: Option<usize>, column: Option<&str>, message: String| CalibrationError::Data {
        path: path.into(),
        line,
        column: column.map(str::to_string),
        message,
    };
    let mut reader = csv::ReaderBuilder::new().comment(Some(b'#')).trim(csv::Trim::All).from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| error(Some(1), None, format!("cannot read the header: {e}")))?.clone();
    // each quantity's column and its factor to m / kPa / kN/m
    let mut columns = Vec::new();
    for q in quantities(kind) {
        let found = header.iter().enumerate().find_map(|(i, h)| {
            let name = h.split('[').next().unwrap_or("").trim();
            q.names.contains(&name).then_some((i, h))
        });
        let Some((index, title)) = found else {
            return Err(error(
                Some(1),
                None,
                format!(
                    "no column \"{}\" (a {} curve file's header is `{}`, with the units in brackets)",
                    q.names[0],
                    kind.name(),
                    expected_header(kind)
                ),
            ));
        };
        let unit = title.split_once('[').and_then(|(_, rest)| rest.split_once(']')).map(|(u, _)| u.trim());
        let accepted = q.units.iter().map(|(u, _)| *u).collect::<Vec<_>>().join(", ");
        let Some(unit) = unit else {
            return Err(error(Some(1), Some(title), format!("give the unit in brackets, one of {accepted}")));
        };
        let Some(&(_, factor)) = q.units.iter().find(|(u, _)| *u == unit) else {
            return Err(error(Some(1), Some(title), format!("unknown unit \"{unit}\": one of {accepted}")));
        };
        columns.push((index, title.to_string(), factor));
    }
    let mut curves: Vec<Curve> = Vec::new();
    // each condition's curve, by the condition's bits (+0.0 for −0.0, which compares equal to it):
    // one look-up per row, not a search of every curve so far
    let mut index: HashMap<u64, usize> = HashMap::new();
    for (row, record) in reader.records().enumerate() {
        let line = record.as_ref().ok().and_then(|r| r.position()).map(|p| p.line() as usize).unwrap_or(row + 2);
        if row >= MAX_ROWS {
            return Err(error(Some(line), None, format!("more than {MAX_ROWS} rows: a curve file is limited to that")));
        }
        let record = record.map_err(|e| error(Some(line), None, format!("cannot read the row: {e}")))?;
        let mut values = [0.0; 3];
        for (k, (index, title, factor)) in columns.iter().enumerate() {
            let cell = record.get(*index).unwrap_or("");
            let v: f64 = cell
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| error(Some(line), Some(title), format!("\"{cell}\" is not a finite number")))?;
            values[k] = v * factor;
        }
        if values[0] < 0.0 {
            return Err(error(
                Some(line),
                Some(&columns[0].1),
                format!("a negative normal stress ({}): compression is positive", values[0]),
            ));
        }
        push_point(&mut curves, &mut index, values);
    }
    if curves.is_empty() {
        return Err(error(None, None, "no data rows".into()));
    }
    for c in &curves {
        if c.x.len() < MIN_POINTS {
            return Err(error(
                None,
                Some(&columns[0].1),
                format!(
                    "the curve at {} kPa has {} point{}; a curve needs at least {MIN_POINTS}",
                    c.condition,
                    c.x.len(),
                    if c.x.len() == 1 { "" } else { "s" }
                ),
            ));
        }
    }
    Ok(curves)
}

/// Add the point (x, y) = `values[1..]` to the curve of the condition `values[0]`, opening one for a
/// condition not seen before (curves in the order their first rows come).
fn push_point(curves: &mut Vec<Curve>, index: &mut HashMap<u64, usize>, values: [f64; 3]) {
    let key = (values[0] + 0.0).to_bits();
    let k = *index.entry(key).or_insert_with(|| {
        curves.push(Curve { condition: values[0] + 0.0, x: Vec::new(), y: Vec::new() });
        curves.len() - 1
    });
    curves[k].x.push(values[1]);
    curves[k].y.push(values[2]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_in_the_header_convert_to_metres_and_kilopascals() {
        let text = "slip [mm], shear_stress [Pa], normal_stress [MPa]\n0,0,0.05\n1,2000,0.05\n2,3000,0.05\n0,0,0.1\n1,2,0.1\n3,4,0.1\n";
        let curves = parse(Path::new("ds.csv"), text, TestKind::DirectShear).unwrap();
        assert_eq!(curves.len(), 2);
        assert_eq!(curves[0].condition, 50.0);
        assert_eq!(curves[0].x, vec![0.0, 1e-3, 2e-3]);
        assert_eq!(curves[0].y, vec![0.0, 2.0, 3.0]);
        assert_eq!(curves[1].y[2], 4e-3);
    }

    #[test]
    fn a_header_without_units_or_a_bad_cell_is_named() {
        let e =
            parse(Path::new("po.csv"), "surcharge,displacement [mm],force [kN/m]\n", TestKind::PullOut).unwrap_err();
        assert!(e.to_string().contains("po.csv, line 1, column \"surcharge\": give the unit in brackets"), "{e}");
        let e = parse(Path::new("po.csv"), "surcharge [kPa],displacement [in],force [kN/m]\n", TestKind::PullOut)
            .unwrap_err();
        assert!(e.to_string().contains("unknown unit \"in\""), "{e}");
        let text = "surcharge [kPa],displacement [mm],force [kN/m]\n10,0,0\n10,1,x\n";
        let e = parse(Path::new("po.csv"), text, TestKind::PullOut).unwrap_err();
        assert!(e.to_string().contains("line 3, column \"force [kN/m]\": \"x\" is not a finite number"), "{e}");
        let text = "surcharge [kPa],displacement [mm],force [kN/m]\n10,0,0\n10,1,1\n";
        let e = parse(Path::new("po.csv"), text, TestKind::PullOut).unwrap_err();
        assert!(e.to_string().contains("the curve at 10 kPa has 2 points"), "{e}");
    }

    /// Rows of `curves` conditions, `points` each, interleaved (row k is point k / curves of the
    /// curve k % curves, at σn = 1 + (k % curves)/100 kPa), or curve after curve.
    fn many_curves(curves: usize, points: usize, interleaved: bool) -> String {
        let mut text = String::from("normal_stress [kPa],slip [mm],shear_stress [kPa]\n");
        for k in 0..curves * points {
            let (curve, point) = if interleaved { (k % curves, k / curves) } else { (k / points, k % points) };
            text.push_str(&format!("{},{point},{}\n", 1.0 + curve as f64 / 100.0, curve));
        }
        text
    }

    #[test]
    fn interleaved_rows_of_many_conditions_form_one_curve_each_in_the_order_they_first_come() {
        // 5000 curves of 3 points, their rows taken in turn: every curve gets its own 3 points in
        // order, whatever lies between them
        let curves = parse(Path::new("ds.csv"), &many_curves(5000, 3, true), TestKind::DirectShear).unwrap();
        assert_eq!(curves.len(), 5000);
        for (k, c) in curves.iter().enumerate() {
            assert_eq!(c.condition, 1.0 + k as f64 / 100.0, "curve {k}");
            assert_eq!(c.x, vec![0.0, 1e-3, 2e-3], "curve {k}");
            assert_eq!(c.y, vec![k as f64; 3], "curve {k}");
        }
        // −0 kPa is the curve at 0 kPa
        let text = "normal_stress [kPa],slip [mm],shear_stress [kPa]\n0,0,0\n-0,1,1\n0.0,2,2\n";
        let curves = parse(Path::new("ds.csv"), text, TestKind::DirectShear).unwrap();
        assert_eq!(curves.len(), 1);
        assert_eq!(curves[0].y, vec![0.0, 1.0, 2.0]);
    }
}
