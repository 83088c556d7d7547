//! Format 2.2, ASCII (Gmsh reference manual, §10.3 "Legacy formats"): `$Nodes` rows `tag x y z`;
//! `$Elements` rows `tag type ntags physical elementary [partitions…] nodes…`.

use super::types::{err, GmshElement, GmshError, GmshKind, GmshMesh, Groups};
use std::collections::BTreeMap;
use std::path::Path;

pub(super) fn read(path: &Path, bytes: &[u8], names: &BTreeMap<(usize, i64), String>) -> Result<GmshMesh, GmshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| err(path, None, format!("the file is not text: {e}")))?;
    let lines: Vec<&str> = text.lines().collect();
    let section = |name: &str| lines.iter().position(|l| l.trim() == name);
    let mut nodes = Vec::new();
    let mut elements = Vec::new();
    let mut groups = Groups::default();

    let Some(start) = section("$Nodes") else {
        return Err(err(path, None, "the file has no $Nodes section".into()));
    };
    let count = parse_count(path, &lines, start + 1)?;
    for k in 0..count {
        let n = start + 2 + k;
        let line = lines.get(n).copied().unwrap_or("");
        let f: Vec<&str> = line.split_whitespace().collect();
        let bad = || err(path, Some(n + 1), format!("expected `tag x y z`, found `{line}`"));
        if f.len() != 4 {
            return Err(bad());
        }
        let tag: u64 = f[0].parse().ok().filter(|&t| t > 0).ok_or_else(bad)?;
        let mut x = [0.0; 3];
        for d in 0..3 {
            x[d] = f[1 + d].parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(bad)?;
        }
        nodes.push((tag, x));
    }
    super::types::refuse_duplicate_nodes(path, &nodes)?;
    if let Some(start) = section("$Elements") {
        let count = parse_count(path, &lines, start + 1)?;
        let mut seen = std::collections::HashSet::new();
        for k in 0..count {
            let n = start + 2 + k;
            let line = lines.get(n).copied().unwrap_or("");
            let bad = |what: &str| err(path, Some(n + 1), format!("{what} in the element row `{line}`"));
            let f: Vec<u64> = line
                .split_whitespace()
                .map(|s| s.parse::<u64>())
                .collect::<Result<_, _>>()
                .map_err(|_| bad("a field that is not a whole number"))?;
            if f.len() < 3 {
                return Err(bad("too few fields"));
            }
            let (tag, code) = (f[0], f[1]);
            let Some(count) = u32::try_from(code).ok().and_then(GmshKind::node_count) else {
                return Err(bad(&format!("unknown element type {code}")));
            };
            // the row's own length bounds the tag count, so the sum below cannot overflow
            let ntags = usize::try_from(f[2])
                .ok()
                .filter(|&t| t <= f.len())
                .ok_or_else(|| bad("a tag count longer than the row"))?;
            if f.len() != 3 + ntags + count {
                return Err(bad(&format!("expected {} fields", 3 + ntags + count)));
            }
            if tag == 0 || !seen.insert(tag) {
                return Err(bad(&format!("element tag {tag} is 0 or listed twice")));
            }
            let kind = GmshKind::from_code(code as u32);
            let dim = kind.dim().unwrap_or(3);
            let physical = if ntags >= 1 { i64::try_from(f[3]).ok().filter(|&t| t != 0) } else { None };
            let group_ids = physical.map(|t| vec![groups.get(dim, t, names)]).unwrap_or_default();
            elements.push(GmshElement { tag, kind, nodes: f[3 + ntags..].to_vec(), groups: group_ids });
        }
    }
    for &(dim, tag) in names.keys() {
        groups.get(dim, tag, names);
    }
    Ok(GmshMesh { path: path.to_path_buf(), format: "2.2".into(), nodes, elements, groups: groups.list })
}

fn parse_count(path: &Path, lines: &[&str], n: usize) -> Result<usize, GmshError> {
    let line = lines.get(n).copied().unwrap_or("");
    let count: usize =
        line.trim().parse().map_err(|_| err(path, Some(n + 1), format!("expected a count, found `{line}`")))?;
    // every row takes a line of its own
    if count > lines.len().saturating_sub(n + 1) {
        return Err(err(path, Some(n + 1), format!("the count {count} is more than the lines that follow")));
    }
    Ok(count)
}
