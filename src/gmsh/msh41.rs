//! Format 4.1, ASCII and binary (Gmsh reference manual, §10.1 "MSH file format"): `$Entities`
//! (which physical groups each geometrical entity belongs to), `$Nodes` and `$Elements`, each read
//! in blocks of one entity. Every other section is skipped.
//!
//! Nodes are kept with the tag the file gives each of them, in file order, whatever the order of
//! the tags: a file is free to list them in any order, and elements refer to nodes by tag only. A
//! count in a header is never trusted for an allocation: every block is read item by item, and the
//! file ends before any count larger than it could hold is reached.

use super::types::{err, line_of, GmshElement, GmshError, GmshKind, GmshMesh, Groups};
use std::collections::BTreeMap;
use std::path::Path;

/// A reader over a 4.1 file's bytes, in its ASCII or binary encoding.
struct Cursor<'a> {
    path: &'a Path,
    bytes: &'a [u8],
    at: usize,
    binary: bool,
}

impl<'a> Cursor<'a> {
    fn fail(&self, message: String) -> GmshError {
        err(self.path, Some(line_of(self.bytes, self.at)), message)
    }

    /// The next whitespace-separated word (ASCII files).
    fn word(&mut self, what: &str) -> Result<&'a str, GmshError> {
        while self.at < self.bytes.len() && self.bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        let start = self.at;
        while self.at < self.bytes.len() && !self.bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        if start == self.at {
            return Err(self.fail(format!("the file ends where {what} should be")));
        }
        std::str::from_utf8(&self.bytes[start..self.at]).map_err(|_| self.fail(format!("{what} is not a number")))
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], GmshError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else { return Err(self.fail(format!("the file ends where {what} should be"))) };
        let slice = &self.bytes[self.at..end];
        self.at = end;
        Ok(slice)
    }

    /// A `size_t` (binary: 8 bytes, little-endian) or a non-negative whole number (ASCII).
    fn size(&mut self, what: &str) -> Result<u64, GmshError> {
        if self.binary {
            let b = self.take(8, what)?;
            Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
        } else {
            let w = self.word(what)?;
            w.parse().map_err(|_| self.fail(format!("{what} must be a whole number ≥ 0, not `{w}`")))
        }
    }

    /// An `int` (binary: 4 bytes, little-endian) or a whole number (ASCII).
    fn int(&mut self, what: &str) -> Result<i32, GmshError> {
        if self.binary {
            let b = self.take(4, what)?;
            Ok(i32::from_le_bytes(b.try_into().expect("4 bytes")))
        } else {
            let w = self.word(what)?;
            w.parse().map_err(|_| self.fail(format!("{what} must be a whole number, not `{w}`")))
        }
    }

    /// A `double` (binary: 8 bytes, little-endian) or a number (ASCII); a finite one.
    fn real(&mut self, what: &str) -> Result<f64, GmshError> {
        let value = if self.binary {
            let b = self.take(8, what)?;
            f64::from_le_bytes(b.try_into().expect("8 bytes"))
        } else {
            let w = self.word(what)?;
            w.parse().map_err(|_| self.fail(format!("{what} must be a number, not `{w}`")))?
        };
        if !value.is_finite() {
            return Err(self.fail(format!("{what} is {value}; a coordinate is a finite number")));
        }
        Ok(value)
    }

    /// A count of items that each hold at least `min_words` numbers: refused when the rest of the
    /// file could not hold them (a number takes at least 2 bytes as text, 4 in binary).
    fn count(&mut self, what: &str, min_words: usize) -> Result<usize, GmshError> {
        let n = self.size(what)?;
        let word = if self.binary { 4 } else { 2 };
        let room = (self.bytes.len() - self.at) / (word * min_words.max(1));
        if n > room as u64 {
            return Err(self.fail(format!("{what} is {n}, more than the rest of the file can hold")));
        }
        Ok(n as usize)
    }

    /// The entity dimension of a block: 0 to 3.
    fn dim(&mut self, what: &str) -> Result<usize, GmshError> {
        let d = self.int(what)?;
        usize::try_from(d).ok().filter(|&d| d <= 3).ok_or_else(|| self.fail(format!("{what} is {d}; it must be 0–3")))
    }

    /// A node or element tag: a whole number from 1.
    fn tag(&mut self, what: &str) -> Result<u64, GmshError> {
        let t = self.size(what)?;
        if t == 0 {
            return Err(self.fail(format!("{what} is 0; tags start at 1")));
        }
        Ok(t)
    }
}

/// The byte range of section `name` (after its header line, up to its `$End` line).
fn section(bytes: &[u8], name: &str) -> Option<(usize, Option<usize>)> {
    let head = format!("\n${name}");
    let end = format!("\n$End{name}");
    let mut from = 0;
    // a header is `$Name` alone on its line (binary data may contain the bytes by chance, but a
    // section starts where the text says it does: the first header that is a whole line)
    let start = loop {
        let p = super::types::find(&bytes[from..], head.as_bytes())? + from;
        let after = p + head.len();
        match bytes.get(after) {
            Some(b'\n') => break after + 1,
            Some(b'\r') if bytes.get(after + 1) == Some(&b'\n') => break after + 2,
            _ => from = after,
        }
    };
    let stop = super::types::rfind(&bytes[start..], end.as_bytes()).map(|p| p + start + 1);
    Some((start, stop))
}

/// The byte range of section `name`: `None` when the file has none; an error when it has no end.
fn whole_section(path: &Path, bytes: &[u8], name: &str) -> Result<Option<(usize, usize)>, GmshError> {
    match section(bytes, name) {
        None => Ok(None),
        Some((start, Some(stop))) => Ok(Some((start, stop))),
        Some((start, None)) => Err(err(
            path,
            Some(line_of(bytes, start)),
            format!("the ${name} section has no $End{name}: the file is cut short"),
        )),
    }
}

pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    binary: bool,
    names: &BTreeMap<(usize, i64), String>,
) -> Result<GmshMesh, GmshError> {
    if binary {
        check_binary_header(path, bytes)?;
    }
    if section(bytes, "PartitionedEntities").is_some() {
        return Err(err(
            path,
            None,
            "the mesh is partitioned ($PartitionedEntities); save it unpartitioned (Mesh.PartitionSplitMeshFiles = 0, no -part)".into(),
        ));
    }
    let cursor_at = |(start, end): (usize, usize)| Cursor { path, bytes: &bytes[..end], at: start, binary };

    let entity_groups = match whole_section(path, bytes, "Entities")? {
        Some(range) => entities(&mut cursor_at(range))?,
        None => BTreeMap::new(),
    };
    let Some(node_range) = whole_section(path, bytes, "Nodes")? else {
        return Err(err(path, None, "the file has no $Nodes section".into()));
    };
    let nodes = nodes(&mut cursor_at(node_range))?;
    let mut groups = Groups::default();
    let elements = match whole_section(path, bytes, "Elements")? {
        Some(range) => elements(&mut cursor_at(range), &entity_groups, &mut groups, names)?,
        None => Vec::new(),
    };
    for &(dim, tag) in names.keys() {
        groups.get(dim, tag, names);
    }
    Ok(GmshMesh { path: path.to_path_buf(), format: "4.1".into(), nodes, elements, groups: groups.list })
}

/// A binary file starts with `4.1 1 8`, then the integer 1 in the writer's byte order: geoslip
/// reads little-endian files with 8-byte sizes (what Gmsh writes on every platform it runs on).
fn check_binary_header(path: &Path, bytes: &[u8]) -> Result<(), GmshError> {
    // the end of the second line (`4.1 1 8`), after `$MeshFormat` and its line end
    let first = bytes.iter().position(|&b| b == b'\n');
    let line_end = first.and_then(|f| bytes.iter().skip(f + 1).position(|&b| b == b'\n').map(|p| p + f + 1));
    let Some(end) = line_end else { return Err(err(path, Some(2), "the $MeshFormat line does not end".into())) };
    let one = bytes.get(end + 1..end + 5).map(|b| i32::from_le_bytes(b.try_into().expect("4 bytes")));
    match one {
        Some(1) => Ok(()),
        Some(v) if v.swap_bytes() == 1 => Err(err(
            path,
            Some(3),
            "the binary mesh is big-endian; geoslip reads little-endian files (save it as ASCII, or on a little-endian machine)".into(),
        )),
        _ => Err(err(path, Some(3), "a binary file of format 4.1 must hold the integer 1 after its $MeshFormat line".into())),
    }
}

/// `$Entities`: (dim, entity tag) → its physical tags.
fn entities(c: &mut Cursor) -> Result<BTreeMap<(usize, i32), Vec<i32>>, GmshError> {
    let mut counts = [0usize; 4];
    for (d, name) in ["points", "curves", "surfaces", "volumes"].iter().enumerate() {
        counts[d] = c.count(&format!("the number of {name} in $Entities"), 5)?;
    }
    let mut groups = BTreeMap::new();
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let tag = c.int("an entity's tag")?;
            // a point: X Y Z; a curve, surface or volume: its bounding box (6 numbers)
            for _ in 0..if dim == 0 { 3 } else { 6 } {
                c.real("an entity's coordinate")?;
            }
            let n = c.count("an entity's number of physical tags", 1)?;
            let physical: Vec<i32> = (0..n).map(|_| c.int("a physical tag")).collect::<Result<_, _>>()?;
            if dim > 0 {
                let bounding = c.count("an entity's number of bounding entities", 1)?;
                for _ in 0..bounding {
                    c.int("a bounding entity's tag")?;
                }
            }
            if groups.insert((dim, tag), physical).is_some() {
                return Err(c.fail(format!("$Entities lists the {dim}-D entity {tag} twice")));
            }
        }
    }
    Ok(groups)
}

/// `$Nodes`: every node's tag and coordinates, in file order; a tag listed twice is refused.
fn nodes(c: &mut Cursor) -> Result<Vec<(u64, [f64; 3])>, GmshError> {
    let blocks = c.count("the number of node blocks", 4)?;
    let total = c.count("the number of nodes", 4)?;
    let (_min, _max) = (c.size("the smallest node tag")?, c.size("the largest node tag")?);
    let mut nodes = Vec::with_capacity(total.min(1 << 20));
    for _ in 0..blocks {
        let dim = c.dim("a node block's entity dimension")?;
        c.int("a node block's entity tag")?;
        let parametric = c.int("a node block's parametric flag")?;
        let in_block = c.count("a node block's number of nodes", 4)?;
        let params = match parametric {
            0 => 0,
            1 => dim,
            p => return Err(c.fail(format!("a node block's parametric flag is {p}; it must be 0 or 1"))),
        };
        let mut tags = Vec::with_capacity(in_block.min(1 << 20));
        for _ in 0..in_block {
            tags.push(c.tag("a node tag")?);
        }
        for tag in tags {
            let x = [c.real("a node's x")?, c.real("a node's y")?, c.real("a node's z")?];
            for _ in 0..params {
                c.real("a node's parametric coordinate")?;
            }
            nodes.push((tag, x));
        }
    }
    if nodes.len() != total {
        return Err(c.fail(format!("$Nodes declares {total} nodes and its blocks hold {}", nodes.len())));
    }
    super::types::refuse_duplicate_nodes(c.path, &nodes)?;
    Ok(nodes)
}

/// `$Elements`: every element's tag, type, nodes and the physical groups of its entity.
fn elements(
    c: &mut Cursor,
    entity_groups: &BTreeMap<(usize, i32), Vec<i32>>,
    groups: &mut Groups,
    names: &BTreeMap<(usize, i64), String>,
) -> Result<Vec<GmshElement>, GmshError> {
    let blocks = c.count("the number of element blocks", 4)?;
    let total = c.count("the number of elements", 2)?;
    let (_min, _max) = (c.size("the smallest element tag")?, c.size("the largest element tag")?);
    let mut elements = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for _ in 0..blocks {
        let dim = c.dim("an element block's entity dimension")?;
        let entity = c.int("an element block's entity tag")?;
        let code = c.int("an element block's element type")?;
        let Some(per_element) = u32::try_from(code).ok().and_then(GmshKind::node_count) else {
            return Err(c.fail(format!("element type {code} is not a Gmsh element type")));
        };
        let in_block = c.count("an element block's number of elements", 1 + per_element)?;
        let kind = GmshKind::from_code(code as u32);
        let physical = entity_groups.get(&(dim, entity)).cloned().unwrap_or_default();
        let group_ids: Vec<usize> = physical.iter().map(|&t| groups.get(dim, i64::from(t).abs(), names)).collect();
        for _ in 0..in_block {
            let tag = c.tag("an element tag")?;
            if !seen.insert(tag) {
                return Err(c.fail(format!("element {tag} is listed twice")));
            }
            let nodes: Vec<u64> = (0..per_element).map(|_| c.tag("an element's node tag")).collect::<Result<_, _>>()?;
            elements.push(GmshElement { tag, kind, nodes, groups: group_ids.clone() });
        }
    }
    if elements.len() != total {
        return Err(c.fail(format!("$Elements declares {total} elements and its blocks hold {}", elements.len())));
    }
    Ok(elements)
}
