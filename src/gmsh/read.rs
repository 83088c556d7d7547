//! Reading a `.msh` file: its `$MeshFormat` and `$PhysicalNames`, then the reader of its format
//! (`msh41`, `msh22`); and the size a file declares, checked against the memory limit before it is
//! parsed.

use super::types::{err, find, line_of, GmshError, GmshMesh};
use super::{msh22, msh41};
use std::collections::BTreeMap;
use std::path::Path;

impl GmshMesh {
    /// Read a `.msh` file of format 4.1 or 2.2.
    ///
    /// # Errors
    /// A [`GmshError`] naming the file, and the line where the reader stopped when it knows it.
    pub fn read(path: &Path) -> Result<GmshMesh, GmshError> {
        GmshMesh::read_within(path, None)
    }

    /// [`GmshMesh::read`], refusing before it reads a file, or parses a mesh, that the model built
    /// on it would not fit in `limit_mb` of memory (see [`check_declared_size`]).
    ///
    /// # Errors
    /// As [`GmshMesh::read`]; a mesh too large for the limit, with its size and the limit.
    pub fn read_within(path: &Path, limit_mb: Option<f64>) -> Result<GmshMesh, GmshError> {
        let limit = crate::input_file::SizeLimit::of_memory(limit_mb);
        let bytes = crate::input_file::read(path, limit)
            .map_err(|e| err(path, None, format!("cannot read the mesh file: {e}")))?;
        check_declared_size(path, &bytes, limit_mb)?;
        GmshMesh::from_bytes(path, &bytes)
    }

    /// Read a mesh already in memory; `path` names it in messages.
    ///
    /// # Errors
    /// As [`GmshMesh::read`].
    pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<GmshMesh, GmshError> {
        let (version, binary) = mesh_format(path, bytes)?;
        let names = physical_names(path, bytes)?;
        if version.starts_with("4.1") {
            msh41::read(path, bytes, binary, &names)
        } else if version.starts_with("2.") {
            if binary {
                return Err(err(
                    path,
                    None,
                    "binary files of format 2.2 are not read; save the mesh as format 4.1 (gmsh -format msh41) or as ASCII 2.2"
                        .into(),
                ));
            }
            msh22::read(path, bytes, &names)
        } else {
            Err(err(
                path,
                Some(2),
                format!("mesh format {version} is not read; save the mesh as format 4.1 (gmsh -format msh41) or 2.2"),
            ))
        }
    }
}

/// `$MeshFormat`: the version string and whether the file is binary.
fn mesh_format(path: &Path, bytes: &[u8]) -> Result<(String, bool), GmshError> {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]).into_owned();
    let mut lines = head.lines().map(str::trim);
    if lines.next() != Some("$MeshFormat") {
        return Err(err(path, Some(1), "not a Gmsh mesh file: it does not start with $MeshFormat".into()));
    }
    let fields: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
    if fields.len() < 3 {
        return Err(err(path, Some(2), "the $MeshFormat line must read `version file-type data-size`".into()));
    }
    let binary = match fields[1] {
        "0" => false,
        "1" => true,
        other => {
            return Err(err(path, Some(2), format!("the file type is `{other}`; it must be 0 (ASCII) or 1 (binary)")))
        }
    };
    if fields[2] != "8" {
        return Err(err(
            path,
            Some(2),
            format!(
                "the data size is `{}`; geoslip reads files written with 8-byte sizes, as Gmsh writes them",
                fields[2]
            ),
        ));
    }
    Ok((fields[0].to_string(), binary))
}

/// `$PhysicalNames` (written as text in ASCII and binary files alike): (dim, tag) → name.
fn physical_names(path: &Path, bytes: &[u8]) -> Result<BTreeMap<(usize, i64), String>, GmshError> {
    let mut names = BTreeMap::new();
    let Some(start) = find(bytes, b"$PhysicalNames") else { return Ok(names) };
    let Some(len) = find(&bytes[start..], b"$EndPhysicalNames") else {
        return Err(err(path, Some(line_of(bytes, start)), "$PhysicalNames has no $EndPhysicalNames".into()));
    };
    let text = String::from_utf8_lossy(&bytes[start..start + len]);
    let first_line = line_of(bytes, start);
    for (k, line) in text.lines().enumerate().skip(2) {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let bad = || err(path, Some(first_line + k), format!("cannot read the physical name `{line}`"));
        let (dim, rest) = line.split_once(char::is_whitespace).ok_or_else(bad)?;
        let (tag, name) = rest.trim().split_once(char::is_whitespace).ok_or_else(bad)?;
        let dim: usize = dim.parse().map_err(|_| bad())?;
        let tag: i64 = tag.parse().map_err(|_| bad())?;
        let name = name.trim().trim_matches('"').to_string();
        names.insert((dim, tag), name);
    }
    Ok(names)
}

/// The node and element counts a `.msh` file declares in its section headers, read without parsing
/// it: ASCII 2.2 and 4.1 give both, binary 4.1 the nodes (the elements then taken as many).
pub fn declared_counts(bytes: &[u8]) -> Option<(usize, usize)> {
    // "4.1 0 8": version, file type (1: binary), data size
    let format = section_start(bytes, b"$MeshFormat\n")
        .and_then(|at| bytes[at..].split(|&b| b == b'\n').next())
        .and_then(|line| std::str::from_utf8(line).ok())
        .unwrap_or("");
    let binary = format.split_whitespace().nth(1) == Some("1");
    let v41 = format.starts_with('4');
    let ascii_count = |section: &[u8]| -> Option<usize> {
        let at = section_start(bytes, section)?;
        let line = std::str::from_utf8(bytes[at..].split(|&b| b == b'\n').next()?).ok()?;
        let fields: Vec<&str> = line.split_whitespace().collect();
        // 4.1: numEntityBlocks numX minTag maxTag; 2.2: numX
        fields.get(usize::from(v41)).and_then(|f| f.parse().ok())
    };
    if binary {
        let at = section_start(bytes, b"$Nodes\n")?;
        let n = u64::from_le_bytes(bytes.get(at + 8..at + 16)?.try_into().ok()?) as usize;
        return Some((n, n));
    }
    Some((ascii_count(b"$Nodes\n")?, ascii_count(b"$Elements\n").unwrap_or(0)))
}

/// Where the line after a section header starts.
fn section_start(bytes: &[u8], header: &[u8]) -> Option<usize> {
    // a header given with its `\n`, found also when the file's lines end in `\r\n`
    let name = header.strip_suffix(b"\n").unwrap_or(header);
    let at = bytes.windows(name.len()).position(|w| w == name)? + name.len();
    match bytes.get(at..at + 2) {
        Some(b"\r\n") => Some(at + 2),
        _ if bytes.get(at) == Some(&b'\n') => Some(at + 1),
        _ => None,
    }
}

/// Refuse a mesh whose declared size would not fit: the model built on it (as if every element
/// were a quad4) and the file's own parse, against `limit_mb`.
///
/// # Errors
/// The counts, the estimate and the limit.
pub fn check_declared_size(path: &Path, bytes: &[u8], limit_mb: Option<f64>) -> Result<(), GmshError> {
    let (Some(limit), Some((nodes, elements))) = (limit_mb, declared_counts(bytes)) else { return Ok(()) };
    let needed = crate::mesh::memory_estimate_mb(nodes, 64.0 * elements as f64) + 2.0 * bytes.len() as f64 / 1048576.0;
    if needed > limit {
        return Err(err(
            path,
            None,
            format!(
                "the mesh has {nodes} nodes and {elements} elements: a model that size needs about {needed:.1} MB and \
                 this run may use {limit:.1} MB in all (--memory-limit, or what the machine has available); coarsen \
                 the mesh or use a machine with more memory"
            ),
        ));
    }
    Ok(())
}
