//! What a `.msh` file holds, as geoslip reads it: nodes by tag, elements with their Gmsh type and
//! physical groups, the groups by dimension, tag and name; and the errors of its readers.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A problem with a mesh file, naming the file and, where known, the line.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}{}: {message}", .path.display(), .line.map(|l| format!(", line {l}")).unwrap_or_default())]
pub struct GmshError {
    pub path: PathBuf,
    pub line: Option<usize>,
    pub message: String,
}

/// A physical group: what the user named in Gmsh (`Physical Curve("geogrid") = {…}`).
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalGroup {
    pub dim: usize,
    pub tag: i64,
    /// The name from `$PhysicalNames`, or the tag written as a number when the group has no name.
    pub name: String,
}

/// The element types geoslip reads; anything else is kept as its Gmsh type number so that the
/// message can name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GmshKind {
    Point,
    Line2,
    Line3,
    Tri3,
    Tri6,
    Quad4,
    Quad8,
    Other(u32),
}

impl GmshKind {
    pub(super) fn from_code(code: u32) -> GmshKind {
        match code {
            15 => GmshKind::Point,
            1 => GmshKind::Line2,
            8 => GmshKind::Line3,
            2 => GmshKind::Tri3,
            9 => GmshKind::Tri6,
            3 => GmshKind::Quad4,
            16 => GmshKind::Quad8,
            other => GmshKind::Other(other),
        }
    }

    /// Nodes per element of every Gmsh element type up to third order (the reference manual's
    /// §10.2 "Node ordering"), so that a reader can step over types geoslip does not use.
    pub(super) fn node_count(code: u32) -> Option<usize> {
        Some(match code {
            15 => 1,
            1 => 2,
            2 | 8 => 3,
            3 | 4 | 26 => 4,
            7 | 27 => 5,
            6 | 9 | 28 => 6,
            5 | 16 => 8,
            10 | 20 => 9,
            11 | 21 | 29 => 10,
            22 => 12,
            19 => 13,
            14 => 14,
            18 | 23 | 24 => 15,
            17 => 20,
            13 => 18,
            25 => 21,
            12 => 27,
            30 => 35,
            31 => 56,
            92 => 64,
            93 => 125,
            _ => return None,
        })
    }

    pub fn dim(self) -> Option<usize> {
        match self {
            GmshKind::Point => Some(0),
            GmshKind::Line2 | GmshKind::Line3 => Some(1),
            GmshKind::Tri3 | GmshKind::Tri6 | GmshKind::Quad4 | GmshKind::Quad8 => Some(2),
            GmshKind::Other(code) => GmshKind::dim_of_code(code),
        }
    }

    /// The dimension of every Gmsh element type up to third order (the reference manual's
    /// §10.2), so that a group of elements geoslip does not use still has its own dimension.
    pub(super) fn dim_of_code(code: u32) -> Option<usize> {
        match code {
            15 => Some(0),
            1 | 8 | 26 | 27 | 28 => Some(1),
            2 | 3 | 9 | 10 | 16 | 20 | 21 | 22 | 23 | 24 | 25 => Some(2),
            4 | 5 | 6 | 7 | 11 | 12 | 13 | 14 | 17 | 18 | 19 | 29 | 30 | 31 | 92 | 93 => Some(3),
            _ => None,
        }
    }

    /// A name a Gmsh user recognises.
    pub fn describe(self) -> String {
        match self {
            GmshKind::Point => "point".into(),
            GmshKind::Line2 => "2-node line".into(),
            GmshKind::Line3 => "3-node line".into(),
            GmshKind::Tri3 => "3-node triangle".into(),
            GmshKind::Tri6 => "6-node triangle".into(),
            GmshKind::Quad4 => "4-node quadrangle".into(),
            GmshKind::Quad8 => "8-node quadrangle".into(),
            GmshKind::Other(10) => "9-node quadrangle (Gmsh type 10)".into(),
            GmshKind::Other(c) => format!("Gmsh element type {c}"),
        }
    }
}

#[derive(Debug, Clone)]
pub struct GmshElement {
    pub tag: u64,
    pub kind: GmshKind,
    pub nodes: Vec<u64>,
    /// Indices into [`GmshMesh::groups`].
    pub groups: Vec<usize>,
}

#[derive(Debug, Clone)]
pub struct GmshMesh {
    pub path: PathBuf,
    /// `4.1` or `2.2`.
    pub format: String,
    /// Node tag and (x, y, z).
    pub nodes: Vec<(u64, [f64; 3])>,
    pub elements: Vec<GmshElement>,
    pub groups: Vec<PhysicalGroup>,
}

pub(super) fn err(path: &Path, line: Option<usize>, message: String) -> GmshError {
    GmshError { path: path.to_path_buf(), line, message }
}

/// The line (1-based) on which byte `offset` lies.
pub(super) fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count()
}

pub(super) fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

pub(super) fn rfind(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).rposition(|w| w == needle)
}

/// Refuse a node tag listed twice: the two rows could give it different coordinates, and which
/// one an element means cannot be told.
pub(super) fn refuse_duplicate_nodes(path: &Path, nodes: &[(u64, [f64; 3])]) -> Result<(), GmshError> {
    let mut tags: Vec<u64> = nodes.iter().map(|(t, _)| *t).collect();
    tags.sort_unstable();
    match tags.windows(2).find(|w| w[0] == w[1]) {
        Some(w) => Err(err(path, None, format!("node {} is listed twice in $Nodes", w[0]))),
        None => Ok(()),
    }
}

/// Collects physical groups in first-seen order.
#[derive(Default)]
pub(super) struct Groups {
    pub(super) list: Vec<PhysicalGroup>,
    index: BTreeMap<(usize, i64), usize>,
}

impl Groups {
    pub(super) fn get(&mut self, dim: usize, tag: i64, names: &BTreeMap<(usize, i64), String>) -> usize {
        *self.index.entry((dim, tag)).or_insert_with(|| {
            let name = names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string());
            self.list.push(PhysicalGroup { dim, tag, name });
            self.list.len() - 1
        })
    }
}
