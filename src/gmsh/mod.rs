//! Gmsh meshes: read `.msh` files (format 4.1, ASCII or binary, through the `mshio` crate; format 2.2
//! ASCII by the small reader here), read the `$PhysicalNames` section that `mshio` skips, and run
//! Debian's `gmsh` on a `.geo` file.
//!
//! The result is a flat [`GmshMesh`]: node tags with x–y coordinates, elements with their Gmsh type
//! and the physical groups they belong to, and the physical groups by dimension, tag and name. Turning
//! that into soil elements, node and edge sets and reinforcement paths is the model's job
//! (`model::import`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

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
    fn from_code(code: u32) -> GmshKind {
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

    /// Nodes per element, for the types whose count this reader must know (format 2.2).
    fn node_count(code: u32) -> Option<usize> {
        Some(match code {
            15 => 1,
            1 => 2,
            2 | 8 => 3,
            3 => 4,
            9 => 6,
            10 => 9,
            16 => 8,
            4 => 4,
            5 => 8,
            6 => 6,
            7 => 5,
            11 => 10,
            17 => 20,
            _ => return None,
        })
    }

    pub fn dim(self) -> Option<usize> {
        match self {
            GmshKind::Point => Some(0),
            GmshKind::Line2 | GmshKind::Line3 => Some(1),
            GmshKind::Tri3 | GmshKind::Tri6 | GmshKind::Quad4 | GmshKind::Quad8 => Some(2),
            GmshKind::Other(_) => None,
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
        if let (Some(limit), Ok(meta)) = (limit_mb, std::fs::metadata(path)) {
            let mb = meta.len() as f64 / (1024.0 * 1024.0);
            if mb > limit {
                return Err(err(
                    path,
                    None,
                    format!("the mesh file is {mb:.1} MB and this run may use {limit:.1} MB in all (--memory-limit, or what the machine has available)"),
                ));
            }
        }
        let bytes = std::fs::read(path).map_err(|e| err(path, None, format!("cannot read the mesh file: {e}")))?;
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
            read_v41(path, bytes, &names)
        } else if version.starts_with("2.") {
            if binary {
                return Err(err(
                    path,
                    None,
                    "binary files of format 2.2 are not read; save the mesh as format 4.1 (gmsh -format msh41) or as ASCII 2.2"
                        .into(),
                ));
            }
            read_v22(path, bytes, &names)
        } else {
            Err(err(
                path,
                Some(2),
                format!("mesh format {version} is not read; save the mesh as format 4.1 (gmsh -format msh41) or 2.2"),
            ))
        }
    }
}

fn err(path: &Path, line: Option<usize>, message: String) -> GmshError {
    GmshError { path: path.to_path_buf(), line, message }
}

/// The line (1-based) on which byte `offset` lies.
fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count()
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
    Ok((fields[0].to_string(), fields[1] == "1"))
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

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// Collects physical groups in first-seen order.
#[derive(Default)]
struct Groups {
    list: Vec<PhysicalGroup>,
    index: BTreeMap<(usize, i64), usize>,
}

impl Groups {
    fn get(&mut self, dim: usize, tag: i64, names: &BTreeMap<(usize, i64), String>) -> usize {
        *self.index.entry((dim, tag)).or_insert_with(|| {
            let name = names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string());
            self.list.push(PhysicalGroup { dim, tag, name });
            self.list.len() - 1
        })
    }
}

fn read_v41(path: &Path, bytes: &[u8], names: &BTreeMap<(usize, i64), String>) -> Result<GmshMesh, GmshError> {
    let msh = mshio::parse_msh_bytes(bytes).map_err(|e| {
        let at = e.filtered_backtrace().first().map(|(rest, _)| bytes.len() - rest.len());
        let what = e.first_msh_error().map(|k| k.to_string()).unwrap_or_else(|| "malformed section".to_string());
        err(path, at.map(|o| line_of(bytes, o)), format!("cannot read the mesh (format 4.1): {what}"))
    })?;
    let data = msh.data;

    // Entity (dim, tag) → physical tags.
    let mut entity_groups: BTreeMap<(usize, i32), Vec<i32>> = BTreeMap::new();
    if let Some(entities) = &data.entities {
        for p in &entities.points {
            entity_groups.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &entities.curves {
            entity_groups.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &entities.surfaces {
            entity_groups.insert((2, s.tag), s.physical_tags.clone());
        }
        for v in &entities.volumes {
            entity_groups.insert((3, v.tag), v.physical_tags.clone());
        }
    }

    let mut nodes = Vec::new();
    if let Some(n) = &data.nodes {
        // mshio keeps a block's tags only when the file's tags are sparse; otherwise they run from
        // min_node_tag in file order.
        let mut next = n.min_node_tag;
        for block in &n.node_blocks {
            let mut tags = vec![0u64; block.nodes.len()];
            match &block.node_tags {
                Some(map) => {
                    for (&tag, &i) in map {
                        tags[i] = tag;
                    }
                }
                None => {
                    for t in tags.iter_mut() {
                        *t = next;
                        next += 1;
                    }
                }
            }
            for (node, tag) in block.nodes.iter().zip(tags) {
                nodes.push((tag, [node.x, node.y, node.z]));
            }
        }
    }

    let mut groups = Groups::default();
    let mut elements = Vec::new();
    if let Some(e) = &data.elements {
        for block in &e.element_blocks {
            let dim = block.entity_dim.max(0) as usize;
            let kind = GmshKind::from_code(block.element_type as u32);
            let physical = entity_groups.get(&(dim, block.entity_tag)).cloned().unwrap_or_default();
            let group_ids: Vec<usize> = physical.iter().map(|&t| groups.get(dim, i64::from(t.abs()), names)).collect();
            for el in &block.elements {
                elements.push(GmshElement {
                    tag: el.element_tag,
                    kind,
                    nodes: el.nodes.clone(),
                    groups: group_ids.clone(),
                });
            }
        }
    }
    // Named groups that no saved element uses are listed too, so that a message can offer them.
    for &(dim, tag) in names.keys() {
        groups.get(dim, tag, names);
    }
    Ok(GmshMesh { path: path.to_path_buf(), format: "4.1".into(), nodes, elements, groups: groups.list })
}

/// Format 2.2, ASCII: `$Nodes` rows `tag x y z`; `$Elements` rows
/// `tag type ntags physical elementary [partitions…] nodes…`.
fn read_v22(path: &Path, bytes: &[u8], names: &BTreeMap<(usize, i64), String>) -> Result<GmshMesh, GmshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| err(path, None, format!("the file is not text: {e}")))?;
    let lines: Vec<&str> = text.lines().collect();
    let section = |name: &str| lines.iter().position(|l| l.trim() == name);
    let mut nodes = Vec::new();
    let mut elements = Vec::new();
    let mut groups = Groups::default();

    if let Some(start) = section("$Nodes") {
        let count = parse_count(path, &lines, start + 1)?;
        for k in 0..count {
            let n = start + 2 + k;
            let line = lines.get(n).copied().unwrap_or("");
            let f: Vec<&str> = line.split_whitespace().collect();
            let bad = || err(path, Some(n + 1), format!("expected `tag x y z`, found `{line}`"));
            if f.len() < 4 {
                return Err(bad());
            }
            let tag: u64 = f[0].parse().map_err(|_| bad())?;
            let mut x = [0.0; 3];
            for d in 0..3 {
                x[d] = f[1 + d].parse().map_err(|_| bad())?;
            }
            nodes.push((tag, x));
        }
    }
    if let Some(start) = section("$Elements") {
        let count = parse_count(path, &lines, start + 1)?;
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
            let (tag, code, ntags) = (f[0], f[1] as u32, f[2] as usize);
            let Some(count) = GmshKind::node_count(code) else {
                return Err(bad(&format!("unknown element type {code}")));
            };
            if f.len() != 3 + ntags + count {
                return Err(bad(&format!("expected {} fields", 3 + ntags + count)));
            }
            let kind = GmshKind::from_code(code);
            let dim = kind.dim().unwrap_or(3);
            let group_ids = if ntags >= 1 && f[3] != 0 { vec![groups.get(dim, f[3] as i64, names)] } else { vec![] };
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
    line.trim().parse().map_err(|_| err(path, Some(n + 1), format!("expected a count, found `{line}`")))
}

/// A mesh that Gmsh made from a `.geo` file for this run.
#[derive(Debug, Clone)]
pub struct GeneratedMesh {
    pub geometry: PathBuf,
    /// `gmsh --version`.
    pub gmsh_version: String,
    /// The `.msh` file's bytes (format 4.1), kept so that the run can save the mesh it used.
    pub msh: Vec<u8>,
}

/// Mesh a `.geo` file in 2-D with Debian's `gmsh` (format 4.1), and read the result. Unless
/// `trust_script`, a script that starts programs or touches files (see [`crate::geo_script`]) is
/// refused before Gmsh is started.
///
/// # Errors
/// A [`GmshError`] when the script is refused, or when `gmsh` is not installed, fails, or writes a
/// mesh that cannot be read.
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
    bytes.windows(header.len()).position(|w| w == header).map(|p| p + header.len())
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

/// Refuse a `.geo` script that runs programs or touches files (see `geo_script`).
///
/// # Errors
/// The first such command's file and line, with up to five of them listed.
pub fn refuse_script_actions(geometry: &Path) -> Result<(), GmshError> {
    let actions = crate::geo_script::actions(geometry);
    let Some(first) = actions.first() else { return Ok(()) };
    let list: Vec<String> =
        actions.iter().take(5).map(|a| format!("{}:{}: {}", a.file.display(), a.line, a.what)).collect();
    Err(err(
        &first.file,
        Some(first.line),
        format!(
            "the mesh script does what geoslip does not run unasked (a .geo file is a program):\n    {}\n\
             Read the script; if you trust it, pass --trust-geo, or mesh it yourself and point mesh.file at the .msh",
            list.join("\n    ")
        ),
    ))
}

pub fn mesh_geometry(
    geometry: &Path,
    trust_script: bool,
    limit_mb: Option<f64>,
) -> Result<(GmshMesh, GeneratedMesh), GmshError> {
    if !trust_script {
        refuse_script_actions(geometry)?;
    }
    let gmsh = std::env::var_os("GEOSLIP_GMSH").unwrap_or_else(|| "gmsh".into());
    let version = Command::new(&gmsh).arg("--version").output().map_err(|e| {
        err(
            geometry,
            None,
            format!(
                "meshing a .geo file needs Gmsh, which could not be started ({e}); install it (Debian: apt-get install gmsh) \
                 or point mesh.file at a .msh file"
            ),
        )
    })?;
    let version_text = String::from_utf8_lossy(&version.stdout).trim().to_string();
    let version_text = if version_text.is_empty() {
        String::from_utf8_lossy(&version.stderr).trim().to_string()
    } else {
        version_text
    };
    let dir = tempfile::tempdir().map_err(|e| err(geometry, None, format!("cannot make a scratch folder: {e}")))?;
    let out = dir.path().join("mesh.msh");
    let run = Command::new(&gmsh)
        .arg(geometry)
        .args(["-2", "-format", "msh41", "-v", "2", "-o"])
        .arg(&out)
        .output()
        .map_err(|e| err(geometry, None, format!("cannot run gmsh: {e}")))?;
    let log = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    if !run.status.success() || !out.exists() {
        let tail: Vec<&str> = log.lines().rev().take(8).collect::<Vec<_>>().into_iter().rev().collect();
        return Err(err(geometry, None, format!("gmsh could not mesh the geometry:\n    {}", tail.join("\n    "))));
    }
    let bytes = std::fs::read(&out).map_err(|e| err(geometry, None, format!("cannot read gmsh's output: {e}")))?;
    check_declared_size(geometry, &bytes, limit_mb)?;
    let mut mesh = GmshMesh::from_bytes(&out, &bytes)?;
    mesh.path = geometry.to_path_buf();
    Ok((mesh, GeneratedMesh { geometry: geometry.to_path_buf(), gmsh_version: version_text, msh: bytes }))
}
