//! A model file read and parsed: its text (UTF-8, within the memory limit), TOML or JSON into the
//! file format, with numbers too large for their fields and the parser's messages named by their
//! place in the file.

use super::file::ModelFile;
use crate::error::{Error, ModelError, Problem};
use std::path::Path;

/// A model file's text. A file that is not UTF-8 is named with the line, column and byte of its
/// first invalid byte.
///
/// # Errors
/// [`Error::Read`] when it cannot be read; [`Error::Parse`] when it is not UTF-8.
pub fn read_text(path: &Path) -> Result<String, Error> {
    read_text_within(path, None)
}

/// [`read_text`], refusing a file larger than `limit_mb` (the run's `--memory-limit`; `None`: the
/// memory this machine has available) before it is read.
///
/// # Errors
/// As [`read_text`].
pub fn read_text_within(path: &Path, limit_mb: Option<f64>) -> Result<String, Error> {
    let limit = crate::input_file::SizeLimit::of_memory(limit_mb);
    let bytes =
        crate::input_file::read(path, limit).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let before = &e.as_bytes()[..at];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let column = std::str::from_utf8(&before[before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)..])
            .map_or(0, |l| l.chars().count())
            + 1;
        Error::Parse {
            path: path.to_path_buf(),
            message: format!(
                "line {line}, column {column} (byte {at}): byte 0x{:02x} is not UTF-8; a model file is UTF-8 text",
                e.as_bytes()[at]
            ),
        }
    })
}

/// Parse a model file's text, by extension.
///
/// # Errors
/// [`Error::Parse`] with the field path (`materials.soil.clay`) and the parser's message, which
/// carries the line and column.
pub fn parse(path: &Path, text: &str) -> Result<ModelFile, Error> {
    let file = parse_schema(path, text)?;
    let huge = huge_numbers(path, text);
    if !huge.is_empty() {
        return Err(Error::Model(ModelError { file: path.to_path_buf(), problems: huge }));
    }
    Ok(file)
}

fn parse_schema(path: &Path, text: &str) -> Result<ModelFile, Error> {
    let fail = |field: String, message: String| {
        let message = if field.is_empty() || field == "." { message } else { format!("{field}: {message}") };
        Error::Parse { path: path.to_path_buf(), message }
    };
    let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_json {
        let mut de = serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(&mut de)
            .map_err(|e| fail(e.path().to_string(), shorten_lines(&e.into_inner().to_string())))
    } else {
        let de = toml::Deserializer::parse(text).map_err(|e| fail(String::new(), shorten_lines(&e.to_string())))?;
        // (its rows read to their exact length, as JSON reads them: `rows.rs`)
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let mut inner = e.into_inner();
            inner.set_input(Some(text)); // so that the message shows the line and column
            fail(field, shorten_lines(&inner.to_string()))
        })
    }
}

/// The largest magnitude a number in a model file may have. No quantity in any unit system a
/// model uses comes near it, and the squares and sums of numbers beyond it overflow double
/// precision (1e308), which would turn a run's arithmetic into infinities.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// Numbers in the file beyond ±[`MAX_MAGNITUDE`], by field.
fn huge_numbers(path: &Path, text: &str) -> Vec<Problem> {
    if !may_hold_huge_numbers(text) {
        return Vec::new();
    }
    let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let mut found = Vec::new();
    if is_json {
        if let Ok(v) = serde_json::from_str::<serde_json::Value>(text) {
            walk_json(&v, String::new(), &mut found);
        }
    } else if let Ok(v) = text.parse::<toml::Table>() {
        walk_toml(&toml::Value::Table(v), String::new(), &mut found);
    }
    found
        .into_iter()
        .map(|(field, x)| Problem {
            field,
            entity: None,
            message: format!(
                "{x:e} is beyond the ±{MAX_MAGNITUDE:e} a model's numbers may have (the arithmetic of a run would \
                 overflow): check the value and its units"
            ),
        })
        .collect()
}

/// Whether `text` may hold a number beyond ±[`MAX_MAGNITUDE`]: any run of the characters a number
/// is written with (digits, `.`, `_`, `e`, `E`, `+`, `-`) that reads as such a number. A text with
/// none holds none, and is not parsed again to look for one and name its field.
fn may_hold_huge_numbers(text: &str) -> bool {
    let in_number = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'_' | b'e' | b'E' | b'+' | b'-');
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if !bytes[i].is_ascii_digit() {
            i += 1;
            continue;
        }
        let end = bytes[i..].iter().position(|&b| !in_number(b)).map_or(bytes.len(), |n| i + n);
        let token = &text[i..end];
        let token: std::borrow::Cow<str> =
            if token.contains('_') { token.replace('_', "").into() } else { token.into() };
        if token.parse::<f64>().is_ok_and(|x| x.is_finite() && x.abs() > MAX_MAGNITUDE) {
            return true;
        }
        i = end;
    }
    false
}

fn child(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

fn walk_toml(v: &toml::Value, path: String, found: &mut Vec<(String, f64)>) {
    match v {
        toml::Value::Float(x) if x.abs() > MAX_MAGNITUDE && x.is_finite() => found.push((path, *x)),
        toml::Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| walk_toml(x, format!("{path}[{i}]"), found)),
        toml::Value::Table(t) => t.iter().for_each(|(k, x)| walk_toml(x, child(&path, k), found)),
        _ => {}
    }
}

fn walk_json(v: &serde_json::Value, path: String, found: &mut Vec<(String, f64)>) {
    match v {
        serde_json::Value::Number(n) => {
            if let Some(x) = n.as_f64().filter(|x| x.abs() > MAX_MAGNITUDE && x.is_finite()) {
                found.push((path, x));
            }
        }
        serde_json::Value::Array(a) => {
            a.iter().enumerate().for_each(|(i, x)| walk_json(x, format!("{path}[{i}]"), found))
        }
        serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| walk_json(x, child(&path, k), found)),
        _ => {}
    }
}

/// A parser's message with every long line cut to a window around the column it points at (the
/// `^` under the snippet), or to its first 200 characters: a model line can be megabytes long (an
/// inline mesh on one line), and the message only needs to show where.
fn shorten_lines(message: &str) -> String {
    const WIDTH: usize = 200;
    let lines: Vec<Vec<char>> = message.lines().map(|l| l.chars().collect()).collect();
    // the caret line of a snippet: "  |      ^"
    let caret = lines.iter().find_map(|l| {
        let bar = l.iter().position(|&c| c == '|')?;
        let rest = &l[bar + 1..];
        (rest.iter().all(|&c| c == ' ' || c == '^') && rest.contains(&'^'))
            .then(|| (bar + 2, l.iter().position(|&c| c == '^').unwrap_or(0)))
    });
    lines
        .iter()
        .map(|l| {
            if l.len() <= WIDTH {
                return l.iter().collect::<String>();
            }
            let (prefix, start) = match caret {
                Some((prefix, at)) if l.len() > prefix && l[..prefix].contains(&'|') => {
                    (prefix, at.saturating_sub(WIDTH / 2).max(prefix))
                }
                _ => (0, 0),
            };
            let end = (start + WIDTH).min(l.len());
            let head: String = l[..prefix].iter().collect();
            let body: String = l[start..end].iter().collect();
            let before = if start > prefix { "…" } else { "" };
            let after = if end < l.len() { format!(" … ({} more characters)", l.len() - end) } else { String::new() };
            format!("{head}{before}{body}{after}")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_number_beyond_the_largest_magnitude_is_found_however_it_is_written() {
        let long = format!("x = 1{}", "0".repeat(101));
        for huge in ["x = 1e101", "x = 2.5E+0101", "x = -123456789e95", "[0, 1_000e98]", long.as_str()] {
            assert!(may_hold_huge_numbers(huge), "{huge}");
        }
        for fine in ["x = 1e100", "nodes = [[1, 0.0, 2.5e-300], [2, 1e99, 3]]", "when = 1979-05-27", "name = \"e123\""]
        {
            assert!(!may_hold_huge_numbers(fine), "{fine}");
        }
    }
}
