//! The model file as the user writes it (TOML or JSON).
//!
//! These types are the single source of truth for the format: `geoslip schema` prints a JSON Schema
//! generated from them, and `docs/model-format.md` documents them field by field. Nothing here is
//! validated beyond what serde checks; `model::validate` turns a [`ModelFile`] into a checked
//! [`crate::model::Model`] and lists every problem it finds.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

// Types the core defines and the file format uses as they are.
pub use crate::design::DesignParameters;
pub use crate::dofs::Direction;
pub use crate::element::geometry::Geometry;
pub use crate::element::mass::Lumping;
pub use crate::element::solid::SolidKind;

/// A complete geoslip model.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// Free-text title, copied into the run summary.
    #[serde(default)]
    pub title: String,
    /// The units every number in this file is written in.
    pub units: Units,
    /// Named materials.
    pub materials: Materials,
    /// A Gmsh mesh to take the nodes, soil elements and named sets from, instead of listing them here.
    #[serde(default)]
    pub mesh: Option<MeshSource>,
    /// Nodes as `[id, x, y]` (leave out when `mesh` is given).
    #[serde(default)]
    pub nodes: Vec<NodeRow>,
    /// Soil elements (tri3, tri6, quad4, quad8), counter-clockwise node order, Gmsh numbering.
    #[serde(default)]
    pub elements: Vec<SolidElementRow>,
    /// Two-node reinforcement bars that the user makes by hand (a `reinforcement` interface makes its
    /// own).
    #[serde(default)]
    pub bars: Vec<BarRow>,
    /// Named node sets.
    #[serde(default)]
    pub node_sets: BTreeMap<String, Vec<u64>>,
    /// Named edge sets: each edge is the node list of one element side, `[a, b]` or `[a, b, mid]`.
    #[serde(default)]
    pub edge_sets: BTreeMap<String, Vec<Vec<u64>>>,
    /// Named element sets (soil element ids), for staged construction. Every physical surface of a
    /// Gmsh mesh is an element set of the same name.
    #[serde(default)]
    pub element_sets: BTreeMap<String, Vec<u64>>,
    /// Permanent zero-displacement supports.
    #[serde(default)]
    pub supports: Vec<Support>,
    /// Soil–reinforcement, soil–soil and soil–base interfaces.
    #[serde(default)]
    pub interfaces: Vec<InterfaceSpec>,
    /// The loading history: stages of increments, applied in order.
    pub stages: Vec<Stage>,
    /// How the nonlinear analysis iterates (every field has a default).
    #[serde(default)]
    pub analysis: AnalysisSettings,
    /// Run the model once per value of one load (a test series).
    #[serde(default)]
    pub series: Option<Series>,
    /// Design checks of the wall the model builds, beside the analysis (`docs/design-checks.md`).
    #[serde(default)]
    pub design: Option<DesignParameters>,
}

/// An empty model in metres and kilonewtons, for models built in code: name the fields that
/// matter and take the rest from here (`ModelFile { nodes, elements, stages, ..Default::default() }`).
/// A model file must still give `units`, `materials` and `stages`.
impl Default for ModelFile {
    fn default() -> Self {
        ModelFile {
            title: String::new(),
            units: Units { length: LengthUnit::Metre, force: ForceUnit::Kilonewton },
            materials: Materials::default(),
            mesh: None,
            nodes: Vec::new(),
            elements: Vec::new(),
            bars: Vec::new(),
            node_sets: BTreeMap::new(),
            edge_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
            supports: Vec::new(),
            interfaces: Vec::new(),
            stages: Vec::new(),
            analysis: AnalysisSettings::default(),
            series: None,
            design: None,
        }
    }
}

/// A test series: the model is run once per value, with the `pressure` of the named edge-traction
/// load set to that value (for example a pull-out test at three normal stresses). Each run writes to a
/// folder of its own; the series adds `series.csv`, a plot of the peak reaction against the value
/// and, for a pull-out, the apparent interface strength fitted to the peaks.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// The `name` of an `edge-traction` load.
    pub load: String,
    /// Its pressure in each run [stress].
    pub values: Vec<f64>,
}

/// A Gmsh mesh and what its physical groups mean.
///
/// Physical surfaces become soil, each with the material `materials` gives it. Every physical curve
/// becomes a node set of the same name (for supports and prescribed displacements) and, when it lies
/// on the soil's boundary, an edge set too (for tractions); every physical point becomes a node set. A reinforcement interface can follow a
/// physical curve by `line`. Node and element ids are Gmsh's tags, so messages name what Gmsh shows.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshSource {
    /// A `.msh` file (format 4.1, ASCII or binary, or 2.2 ASCII) or a `.geo` file, which geoslip meshes
    /// with Gmsh (`gmsh` on the PATH) for each run. Relative to the model file.
    pub file: String,
    /// Physical surface name → soil material name. Every surface element must be in one of these.
    pub materials: BTreeMap<String, String>,
}

/// Settings of the equilibrium iteration.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct AnalysisSettings {
    /// `constant-stiffness` (the paper's Fig. 3: Ks in the matrix, the factorisation reused),
    /// `newton` (the consistent tangent, unsymmetric when τp depends on σn) or `newton-symmetric`
    /// (the law's tangent with σn lagged one iteration).
    pub scheme: Scheme,
    /// After each increment: `segment` (closest-point projection onto the deformed master face),
    /// `nearest-node` (the paper's approximation) or `none` (small slip: the pairing never changes).
    pub reassociation: ReassociationRule,
    /// Out-of-balance force relative to the applied and reaction forces.
    pub force_tolerance: f64,
    /// Displacement correction relative to the increment.
    pub displacement_tolerance: f64,
    pub max_iterations: usize,
    /// Give an increment up (and cut it back) after this many iterations in which its
    /// out-of-balance force did not fall below 99 % of its value at the last iteration that made
    /// progress (0: never).
    pub stall_iterations: usize,
    /// How many times a failing increment may be halved.
    pub max_cutbacks: usize,
    /// Hold σn at its value at the start of each stage (a stage's own `freeze_normal_stress`
    /// overrides it).
    pub freeze_normal_stress: bool,
    /// Master segments reserved on either side of each interface point in the sparsity pattern, so
    /// that sliding within them needs no new symbolic analysis (0: none).
    pub reserved_segments: usize,
    /// Integrate quad8 elements with 2×2 Gauss points instead of 3×3 (the usual choice for collapse
    /// loads of nearly incompressible plastic flow, e.g. undrained bearing capacity).
    pub reduced_integration: bool,
    /// `plane-strain` (per metre width) or `axisymmetric` (x = r ≥ 0 about the y axis; forces are
    /// totals over the circumference).
    pub geometry: Geometry,
    /// The first iterate of an increment: `none` (the last converged state, the prescribed
    /// displacements moved) or `linear` (the last increment of the stage carried on, scaled to the
    /// new step: fewer iterations under a steady pull; the same answer to the tolerances).
    pub extrapolation: Extrapolation,
}

/// An increment's first iterate (see `AnalysisSettings::extrapolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Extrapolation {
    /// The last converged displacements and multipliers.
    #[default]
    None,
    /// The last increment of the stage carried on over the new load-factor step.
    Linear,
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        AnalysisSettings {
            scheme: Scheme::ConstantStiffness,
            reassociation: ReassociationRule::Segment,
            force_tolerance: 1e-9,
            displacement_tolerance: 1e-9,
            max_iterations: 300,
            stall_iterations: 30,
            max_cutbacks: 8,
            freeze_normal_stress: false,
            reserved_segments: 2,
            reduced_integration: false,
            geometry: Geometry::PlaneStrain,
            extrapolation: Extrapolation::None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// The paper's Fig. 3: Ks in the matrix, the factorisation reused through an increment.
    ConstantStiffness,
    /// The consistent tangent, with ∂τ/∂σn: unsymmetric when the strength depends on σn (MUMPS then
    /// factorises with SYM=0).
    Newton,
    /// The law's tangent with σn lagged one iteration: symmetric.
    NewtonSymmetric,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ReassociationRule {
    /// Each point tied to the master point it faces: N_i(ξ) on that segment (node-to-segment).
    Segment,
    /// The paper's approximation: tied to the nearer node of that segment.
    NearestNode,
    /// Each point tied to the master face averaged over its part of the slave line (segment to
    /// segment, with the dual mortar basis of the slave line).
    Mortar,
    /// Small slip: the pairing never changes.
    None,
}

/// Units stated in the file. geoslip does not convert: every number must be written in these units,
/// and output column headers carry them. Stress is force/length².
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Units {
    pub length: LengthUnit,
    pub force: ForceUnit,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum LengthUnit {
    #[serde(rename = "m")]
    Metre,
    #[serde(rename = "mm")]
    Millimetre,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum ForceUnit {
    #[serde(rename = "N")]
    Newton,
    #[serde(rename = "kN")]
    Kilonewton,
    #[serde(rename = "MN")]
    Meganewton,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Materials {
    /// Soil materials by name.
    #[serde(default)]
    pub soil: BTreeMap<String, SoilMaterial>,
    /// Reinforcement (geogrid, geotextile, strip) materials by name.
    #[serde(default)]
    pub reinforcement: BTreeMap<String, ReinforcementMaterial>,
}

/// Plane-strain soil: linear elastic, elastic–perfectly plastic Mohr–Coulomb with a tension
/// cut-off, Duncan–Chang hyperbolic or hardening soil, these two with the Mohr–Coulomb strength as
/// their limit. Stresses are effective stresses; pore pressures come from a stage's `water`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SoilMaterial {
    /// `linear-elastic` (default), `mohr-coulomb`, `duncan-chang` or `hardening-soil`.
    #[serde(default)]
    pub model: SoilModel,
    /// Young's modulus E [stress]: linear-elastic and Mohr–Coulomb soil.
    #[serde(default)]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio ν, 0 ≤ ν < 0.5: linear-elastic and Mohr–Coulomb soil.
    #[serde(default)]
    pub poissons_ratio: Option<f64>,
    /// Duncan–Chang soil: the hyperbolic stiffness parameters (E–B form).
    #[serde(default)]
    pub hyperbolic: Option<HyperbolicParameters>,
    /// Hardening soil: its stiffness parameters (Schanz, Vermeer & Bonnier 1999).
    #[serde(default)]
    pub hardening: Option<HardeningSoilParameters>,
    /// Unit weight γ [force/length³] above the water table, used by `gravity` loads.
    #[serde(default)]
    pub unit_weight: f64,
    /// Unit weight below the water table [force/length³]; default `unit_weight`.
    #[serde(default)]
    pub saturated_unit_weight: Option<f64>,
    /// Mohr–Coulomb, Duncan–Chang and hardening soil: effective cohesion c′ [stress] (the undrained
    /// strength c_u with φ = 0).
    #[serde(default)]
    pub cohesion: f64,
    /// Mohr–Coulomb, Duncan–Chang and hardening soil: effective friction angle φ′ [degrees]
    /// (Duncan–Chang: φ0, at σ3 = pa; hardening soil: above zero).
    #[serde(default)]
    pub friction_angle: f64,
    /// Mohr–Coulomb, Duncan–Chang and hardening soil: dilatancy angle ψ [degrees], 0 ≤ ψ ≤ φ (ψ <
    /// φ: non-associated flow; hardening soil: the dilatancy at failure).
    #[serde(default)]
    pub dilatancy_angle: f64,
    /// Mohr–Coulomb: tension cut-off σt [stress], the largest principal stress allowed. Default and
    /// upper bound c·cot φ (no cut-off below the apex); with φ = 0 the default is no cut-off.
    #[serde(default)]
    pub tensile_strength: Option<f64>,
    /// Earth pressure coefficient at rest for the `k0` initial stresses: σ′h = K0·σ′v. Default
    /// 1 − sin φ (Jáky) for Mohr–Coulomb and Duncan–Chang soil, the hardening soil's K0nc, ν/(1 − ν)
    /// for linear-elastic soil.
    #[serde(default)]
    pub k0: Option<f64>,
}

/// The stiffness of a Duncan–Chang soil by the parameters' usual names (Duncan, Byrne, Wong &
/// Mabry 1980): Ei = K·pa·(σ3/pa)^n, Eur = Kur·pa·(σ3/pa)^n, B = Kb·pa·(σ3/pa)^m,
/// Et = (1 − Rf·SL)²·Ei, φ = φ0 − Δφ·log10(σ3/pa). docs/soil.md has the whole law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HyperbolicParameters {
    /// The modulus number K.
    #[serde(rename = "K")]
    pub modulus_number: f64,
    /// The modulus exponent n.
    pub n: f64,
    /// The failure ratio Rf, 0 < Rf < 1.
    #[serde(rename = "Rf")]
    pub failure_ratio: f64,
    /// The bulk modulus number Kb.
    #[serde(rename = "Kb")]
    pub bulk_modulus_number: f64,
    /// The bulk modulus exponent m.
    pub m: f64,
    /// The unloading–reloading modulus number Kur (at least K).
    #[serde(rename = "Kur")]
    pub unloading_modulus_number: f64,
    /// Δφ [degrees]: the drop of φ for a tenfold σ3 (0: a straight envelope).
    #[serde(default)]
    pub delta_phi: f64,
    /// Atmospheric pressure pa [stress]; default 101.325 kPa in the file's units.
    #[serde(default)]
    pub pa: Option<f64>,
}

/// The stiffness of a hardening soil by the names PLAXIS users know (Schanz, Vermeer & Bonnier
/// 1999): E50 = E50ref·r^m, Eur = Eurref·r^m and Eoed = Eoedref·r^m, r = (c·cos φ + σ3·sin φ)/(c·cos
/// φ + pref·sin φ) (σ1 for Eoed). docs/soil.md has the whole law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HardeningSoilParameters {
    /// E50ref [stress]: the secant modulus at half the strength in drained triaxial compression at
    /// σ3 = pref.
    #[serde(rename = "E50_ref")]
    pub secant_modulus: f64,
    /// Eoedref [stress]: the tangent modulus of one-dimensional compression at σ1 = pref; default
    /// E50ref.
    #[serde(rename = "Eoed_ref", default)]
    pub oedometer_modulus: Option<f64>,
    /// Eurref [stress]: the unloading–reloading modulus at σ3 = pref; default 3·E50ref.
    #[serde(rename = "Eur_ref", default)]
    pub unloading_modulus: Option<f64>,
    /// m: the power of the stress dependency, in (0, 1].
    pub m: f64,
    /// pref [stress]; default 100 kPa in the file's units.
    #[serde(default)]
    pub p_ref: Option<f64>,
    /// νur: Poisson's ratio of unloading and reloading; default 0.2.
    #[serde(default)]
    pub nu_ur: Option<f64>,
    /// Rf = qf/qa, in (0, 1); default 0.9.
    #[serde(rename = "Rf", default)]
    pub failure_ratio: Option<f64>,
    /// K0nc: σ′h/σ′v in normally consolidated one-dimensional compression; default 1 − sin φ.
    #[serde(rename = "K0nc", default)]
    pub k0_nc: Option<f64>,
}

impl SoilMaterial {
    /// A linear-elastic soil with E, ν and γ.
    pub fn linear_elastic(youngs_modulus: f64, poissons_ratio: f64, unit_weight: f64) -> SoilMaterial {
        SoilMaterial {
            model: SoilModel::LinearElastic,
            youngs_modulus: Some(youngs_modulus),
            poissons_ratio: Some(poissons_ratio),
            hyperbolic: None,
            hardening: None,
            unit_weight,
            saturated_unit_weight: None,
            cohesion: 0.0,
            friction_angle: 0.0,
            dilatancy_angle: 0.0,
            tensile_strength: None,
            k0: None,
        }
    }

    /// K0 for the `k0` initial stresses (the default when the file gives none).
    pub fn k0(&self) -> f64 {
        self.k0.unwrap_or(match self.model {
            SoilModel::MohrCoulomb | SoilModel::DuncanChang => 1.0 - self.friction_angle.to_radians().sin(),
            SoilModel::HardeningSoil => self
                .hardening
                .as_ref()
                .and_then(|h| h.k0_nc)
                .unwrap_or_else(|| 1.0 - self.friction_angle.to_radians().sin()),
            SoilModel::LinearElastic => {
                let nu = self.poissons_ratio.unwrap_or(0.0);
                nu / (1.0 - nu)
            }
        })
    }

    /// γ below the water table.
    pub fn saturated_weight(&self) -> f64 {
        self.saturated_unit_weight.unwrap_or(self.unit_weight)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SoilModel {
    #[default]
    LinearElastic,
    MohrCoulomb,
    DuncanChang,
    HardeningSoil,
}

/// A reinforcement, per metre width out of plane.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReinforcementMaterial {
    /// Axial stiffness EA per metre width [force/length].
    pub axial_stiffness: f64,
    /// Carries no compression (geogrids). Accepted now; applied by the slip mechanics.
    #[serde(default)]
    pub tension_only: bool,
    /// Rupture strength T_ult per metre width [force/length]. Accepted now; applied by the slip
    /// mechanics.
    #[serde(default)]
    pub rupture_strength: Option<f64>,
    /// Its weight per unit length of the member, per metre width as `axial_stiffness` (a
    /// geogrid's weight per unit area; in axisymmetry, the member's weight per metre)
    /// [force/length²]: its mass in a dynamic stage is the weight over g. Default none: no mass.
    #[serde(default)]
    pub weight: Option<f64>,
}

/// `[id, x, y]` (read to its exact length: `rows.rs`).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct NodeRow(pub u64, pub f64, pub f64);

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolidElementRow {
    pub id: u64,
    #[serde(rename = "type")]
    pub kind: SolidKind,
    /// Corner nodes counter-clockwise, then mid-side nodes (Gmsh order).
    pub nodes: Vec<u64>,
    /// Name of a soil material.
    pub material: String,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BarRow {
    pub id: u64,
    #[serde(deserialize_with = "crate::model::rows::pair")]
    pub nodes: [u64; 2],
    /// Name of a reinforcement material.
    pub material: String,
}

/// A geosynthetic laid on the layer beneath it along the same path.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StackedLayer {
    /// Its name: node sets `<name>.head`, `<name>.tail` and `<name>.reinforcement` hold its nodes.
    pub name: String,
    /// Name of a reinforcement material.
    pub material: String,
    /// The law of this layer sliding on the one beneath it.
    pub law: ShearLawSpec,
}

/// Where a support, load or prescribed displacement acts: exactly one of `node`, `nodes` or `set`.
#[derive(Debug, Clone, Copy)]
pub struct NodeTarget<'a> {
    pub node: Option<u64>,
    pub nodes: Option<&'a [u64]>,
    pub set: Option<&'a str>,
}

impl Support {
    pub fn target(&self) -> NodeTarget<'_> {
        NodeTarget { node: self.node, nodes: self.nodes.as_deref(), set: self.set.as_deref() }
    }
}

impl PrescribedDisplacement {
    pub fn target(&self) -> NodeTarget<'_> {
        NodeTarget { node: self.node, nodes: self.nodes.as_deref(), set: self.set.as_deref() }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Support {
    #[serde(default)]
    pub node: Option<u64>,
    #[serde(default)]
    pub nodes: Option<Vec<u64>>,
    #[serde(default)]
    pub set: Option<String>,
    /// Directions held at zero displacement.
    pub fix: Vec<Direction>,
}

/// An interface: a slave line pressed against a master face, with a shear law.
///
/// Give either `reinforcement` (geoslip splits the soil along a node path and creates the bars, both
/// faces and one contact pair per face) or `slave` and `master` (the mesh already carries the double
/// nodes).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    pub name: String,
    #[serde(default)]
    pub reinforcement: Option<ReinforcementPath>,
    /// Slave line: ordered node ids. Slip is positive when the slave moves towards its first node.
    #[serde(default)]
    pub slave: Option<Vec<u64>>,
    /// Master face: ordered node ids along element sides.
    #[serde(default)]
    pub master: Option<Vec<u64>>,
    /// Unit-free direction pointing into the master side, required only when the master face is not on
    /// any soil element (a rigid base).
    #[serde(default, deserialize_with = "crate::model::rows::optional_pair")]
    pub master_normal: Option<[f64; 2]>,
    /// The shear law of every face of this interface; for a reinforcement, of the soil above it
    /// against its top layer.
    pub law: ShearLawSpec,
    /// For a reinforcement: the law of its bottom layer against the soil below, when it differs
    /// from `law` (a geomembrane on a clay liner under a geotextile, say).
    #[serde(default)]
    pub lower_law: Option<ShearLawSpec>,
    /// Dilatancy of the interface's faces against the soil: the faces move apart by tan ψ times
    /// the plastic slip, up to a largest dilation (a dense sand that dilates as the reinforcement
    /// slides).
    #[serde(default)]
    pub dilation: Option<DilationSpec>,
    /// Passive bearing of a geogrid's transverse members, a resistance added to each face's shear
    /// law and reported apart from friction. Only for a reinforcement.
    #[serde(default)]
    pub bearing: Option<BearingSpec>,
}

/// An unnamed tied interface with nothing else set, for interfaces built in code: name the fields
/// that matter (`InterfaceSpec { name, reinforcement, law, ..Default::default() }`). A model file
/// must still give `name` and `law`.
impl Default for InterfaceSpec {
    fn default() -> Self {
        InterfaceSpec {
            name: String::new(),
            reinforcement: None,
            slave: None,
            master: None,
            master_normal: None,
            law: ShearLawSpec::Tie,
            lower_law: None,
            dilation: None,
            bearing: None,
        }
    }
}

/// Dilatancy on the normal tie: u_n,reinforcement − u_n,soil = min(tan ψ·κ, `max_dilation`), κ the
/// plastic slip accumulated in either direction.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DilationSpec {
    /// Dilation angle ψ [degrees], 0 ≤ ψ < 45.
    pub angle: f64,
    /// Largest dilation, the opening at which the soil has reached its critical state [length].
    pub max_dilation: f64,
}

/// Passive bearing of transverse members: members of thickness B every S along the reinforcement,
/// a fraction αb of the width bearing, each bearing σb = (σb/σn)·σn′ mobilised linearly over a
/// displacement. Per unit length of reinforcement the bearing force is (αb·B/S)·σb, half on each
/// face.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BearingSpec {
    /// Spacing S of the transverse members along the reinforcement [length].
    pub member_spacing: f64,
    /// Thickness B of a transverse member (its height facing the soil) [length].
    pub member_thickness: f64,
    /// Fraction αb of the reinforcement's width that bears (0 < αb ≤ 1). Default 1.
    #[serde(default = "one")]
    pub bearing_fraction: f64,
    /// How σb/σn is found: `general-shear` or `punching-shear` (Jewell et al. 1984, from
    /// `friction_angle`), or `ratio` (given directly).
    pub formula: BearingFormula,
    /// The soil's friction angle φ′ [degrees] for the `general-shear` and `punching-shear` formulas.
    #[serde(default)]
    pub friction_angle: Option<f64>,
    /// σb/σn for the `ratio` formula.
    #[serde(default)]
    pub ratio: Option<f64>,
    /// The relative displacement over which the bearing is mobilised linearly to its full value
    /// [length].
    pub mobilisation_displacement: f64,
}

/// The bearing-capacity formula of a transverse member.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum BearingFormula {
    /// Upper bound (general shear; Jewell et al. 1984): σb/σn = exp(π·tan φ)·tan²(π/4 + φ/2).
    GeneralShear,
    /// Lower bound (punching shear; Jewell et al. 1984): σb/σn = exp((π/2 + φ)·tan φ)·tan(π/4 + φ/2).
    PunchingShear,
    /// σb/σn given as `ratio` (from the user's own tests).
    Ratio,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReinforcementPath {
    /// Soil node ids along the reinforcement, from the head (on the front face) to the tail.
    #[serde(default)]
    pub path: Vec<u64>,
    /// Instead of `path`: the name of a physical curve of the Gmsh mesh. Its segments are chained
    /// into a path whose head is the end on the soil's boundary.
    #[serde(default)]
    pub line: Option<String>,
    /// With `line`: a point near the head end, needed only when both ends (or neither) lie on the
    /// boundary.
    #[serde(default, deserialize_with = "crate::model::rows::optional_pair")]
    pub head: Option<[f64; 2]>,
    /// Name of a reinforcement material.
    pub material: String,
    /// Further geosynthetics laid on this one, from the bottom up (a geotextile on a geomembrane):
    /// each slides on the layer beneath it by its own law.
    #[serde(default)]
    pub stack: Vec<StackedLayer>,
    /// A length of reinforcement in front of the head, outside the soil (up to a grip or clamp)
    /// [length]: its nodes are added on the line of the first segment, spaced at most as that
    /// segment; `<name>.head` is then its front end. Its points touch no soil until they enter it.
    #[serde(default)]
    pub free_length: Option<f64>,
    /// `split` (the default): the soil is split along the path into two bodies that touch the
    /// reinforcement's two faces and may separate (geomembranes, liners). `embedded`: the soil stays
    /// one continuous body and the reinforcement is tied into it (geogrids, strips in fill).
    #[serde(default)]
    pub mode: ReinforcementMode,
}

/// How a reinforcement meets the soil it lies in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ReinforcementMode {
    /// The soil split along the path: two bodies, one contact face each side, release in tension.
    #[default]
    Split,
    /// The soil continuous: the reinforcement's points tied normally to the soil's sides they lie
    /// on, two faces' shear from the soil's own normal stress there.
    Embedded,
}

/// Tangential law per face and per slave point.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShearLawSpec {
    /// Both directions tied by Lagrange multipliers (no slip at all).
    Tie,
    /// τ = Ks·s with no strength limit (the paper's illustrative example).
    Linear {
        /// Ks per face [stress/length].
        shear_stiffness: f64,
    },
    /// Elastic–perfectly plastic, τp = c + σn·tan φ.
    Coulomb {
        shear_stiffness: f64,
        cohesion: f64,
        /// Degrees.
        friction_angle: f64,
    },
    /// Peak then residual (the paper's Fig. 2).
    PeakResidual {
        shear_stiffness: f64,
        cohesion: f64,
        friction_angle: f64,
        residual_cohesion: f64,
        residual_friction_angle: f64,
    },
    /// Peak, then linear softening to the residual over `softening_slip`.
    Softening {
        shear_stiffness: f64,
        cohesion: f64,
        friction_angle: f64,
        residual_cohesion: f64,
        residual_friction_angle: f64,
        /// Slip over which the strength drops from peak to residual [length].
        softening_slip: f64,
    },
    /// Hyperbolic before the peak: initial slope Ks, asymptote τp.
    Hyperbolic { shear_stiffness: f64, cohesion: f64, friction_angle: f64 },
}

/// One stage of the loading history. Loads and prescribed displacements listed here are added to
/// those of earlier stages and ramped in by `load_factors` (cumulative fractions of this stage's
/// additions, ending at 1).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Stage {
    pub name: String,
    /// Cumulative fractions of this stage's additions, increasing, ending at 1.0. Default `[1.0]`.
    #[serde(default = "default_load_factors")]
    pub load_factors: Vec<f64>,
    /// Instead of `load_factors`: a loading history, rows of (time, factor). The factor multiplies
    /// this stage's loads and prescribed displacements from the stage's start (factor 0) and may
    /// rise, fall and change sign (cyclic loading); the times increase and only order the rows (the
    /// analysis is rate-independent). Every row is a step, and every reversal of the factor is an
    /// event of the outputs. The loads and displacements stay at the last row's factor.
    #[serde(default, deserialize_with = "crate::model::rows::optional_pairs")]
    pub history: Option<Vec<[f64; 2]>>,
    /// With `history`: the largest change of the factor in one step; each segment between rows is
    /// divided into equal steps no larger than it (default: one step per row).
    #[serde(default)]
    pub history_increment: Option<f64>,
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Displacements added in this stage; the DOFs stay held at the reached value afterwards.
    #[serde(default)]
    pub prescribed: Vec<PrescribedDisplacement>,
    /// Element sets placed in this stage (fill lifts). An element set named here is absent before
    /// this stage; it is placed stress-free on the deformed ground, and its weight is applied over
    /// this stage's load factors when gravity is on.
    #[serde(default)]
    pub activate: Vec<String>,
    /// Element sets removed in this stage (excavation). The forces they exerted on the rest are
    /// released over this stage's load factors.
    #[serde(default)]
    pub deactivate: Vec<String>,
    /// `k0`: at the start of this stage, set the stresses of the soil present from the weight of
    /// the soil column above each Gauss point (σ′v = ∫γ dz − p, σ′h = K0·σ′v, no shear). Use with a
    /// `gravity` load in the same stage; it is exact for horizontal ground and layers.
    #[serde(default)]
    pub initial_stress: Option<InitialStress>,
    /// The water table from this stage on: hydrostatic pore pressure below it. Soil strength and
    /// interface strength use effective stress.
    #[serde(default)]
    pub water: Option<WaterTable>,
    /// Make this stage a search for the factor of safety by strength reduction (it takes no loads):
    /// the strengths are divided by a factor F, raised until no equilibrium exists.
    #[serde(default)]
    pub strength_reduction: Option<StrengthReductionSpec>,
    /// Hold each interface point's σn at its value at the start of this stage (`true`) or let it
    /// follow the multipliers (`false`); absent: the analysis's `freeze_normal_stress`.
    #[serde(default)]
    pub freeze_normal_stress: Option<bool>,
    /// Compact the lift this stage places: once it is placed and its weight is on, a pressure on its
    /// surface is applied and removed again, in two stages that follow this one (docs/soil.md,
    /// "Compaction").
    #[serde(default)]
    pub compaction: Option<CompactionSpec>,
    /// Make this stage dynamic: time steps of the equations of motion under a base acceleration,
    /// from the state the stages before it left (docs/dynamics.md). It takes no loads.
    #[serde(default)]
    pub dynamic: Option<DynamicSpec>,
}

/// A dynamic stage: the soil's inertia (its density is its unit weight over g), Rayleigh damping
/// and a base acceleration, integrated by the HHT-α method (Hilber, Hughes & Taylor 1977), of
/// which Newmark's average acceleration is α = 0. Times are in seconds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicSpec {
    /// The time step Δt [s], > 0.
    pub time_step: f64,
    /// The stage's duration [s], > 0: it takes duration/Δt steps (the last one shorter when they
    /// do not divide).
    pub duration: f64,
    /// HHT-α's α, in [−1/3, 0]: 0 is Newmark's average acceleration (no numerical damping); below
    /// it, the highest frequencies are damped most (the multipliers' spurious oscillation). Default
    /// −0.05.
    #[serde(default = "default_hht_alpha")]
    pub alpha: f64,
    /// Rayleigh damping, C = a0·M + a1·K (K the soil's elastic stiffness). Default none.
    #[serde(default)]
    pub damping: Option<RayleighDamping>,
    /// `lumped` (default) or `consistent` mass.
    #[serde(default)]
    pub mass: Lumping,
    /// The base's acceleration, at most one motion per direction. On a rigid base (the default)
    /// the base is the model's supports and the displacements are relative to it; with a
    /// `compliant_base` it is the outcrop motion of the half-space.
    #[serde(default)]
    pub base_motion: Vec<BaseMotion>,
    /// Node sets whose mean displacement, velocity and acceleration `motion.csv` records at every
    /// step.
    #[serde(default)]
    pub record: Vec<String>,
    /// Sides of the soil that let waves out: Lysmer–Kuhlemeyer dashpots (ρ·Vp normal, ρ·Vs
    /// tangential, the adjacent soil's) in place of their nodes' supports, whose reactions at the
    /// stage's start stay on as forces.
    #[serde(default)]
    pub absorbing: Vec<AbsorbingEdges>,
    /// A base that is not rigid: its edges get the dashpots of the half-space below them, the base
    /// motion (then the outcrop motion) enters as the force ρ·V·A·v_g(t) through them, and the
    /// displacements are absolute (from the stage's start), not relative to a rigid base.
    #[serde(default)]
    pub compliant_base: Option<CompliantBase>,
}

/// An edge set of absorbing sides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AbsorbingEdges {
    /// The edge set.
    pub edges: String,
    /// The directions its dashpots act in and its nodes' supports are freed in. Default both.
    #[serde(default = "both_directions")]
    pub directions: Vec<Direction>,
}

fn both_directions() -> Vec<Direction> {
    vec![Direction::X, Direction::Y]
}

/// A compliant base (Joyner & Chen 1975; Lysmer & Kuhlemeyer 1969): an edge set and the elastic
/// half-space beneath it, by default the soil above each of its edges.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CompliantBase {
    /// The edge set of the base.
    pub edges: String,
    /// The directions its dashpots act in and its nodes' supports are freed in. Default both.
    #[serde(default = "both_directions")]
    pub directions: Vec<Direction>,
    /// The half-space's unit weight [force/length³]; with `shear_wave_velocity` and
    /// `poissons_ratio`, or none of the three (the soil's own).
    #[serde(default)]
    pub unit_weight: Option<f64>,
    /// The half-space's shear-wave velocity [length/s].
    #[serde(default)]
    pub shear_wave_velocity: Option<f64>,
    /// The half-space's Poisson's ratio, for its P-wave velocity.
    #[serde(default)]
    pub poissons_ratio: Option<f64>,
}

fn default_hht_alpha() -> f64 {
    -0.05
}

/// Rayleigh damping: a ratio ξ at two frequencies (a0 = 2ξω1ω2/(ω1 + ω2), a1 = 2ξ/(ω1 + ω2)),
/// or the two coefficients themselves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RayleighDamping {
    /// The damping ratio ξ at the two frequencies, in [0, 1).
    #[serde(default)]
    pub ratio: Option<f64>,
    /// The two frequencies f1 < f2 [Hz] where the ratio is ξ.
    #[serde(default)]
    pub frequencies: Option<[f64; 2]>,
    /// Instead of a ratio: a0 [1/s], the mass-proportional coefficient.
    #[serde(default)]
    pub mass_coefficient: Option<f64>,
    /// Instead of a ratio: a1 [s], the stiffness-proportional coefficient.
    #[serde(default)]
    pub stiffness_coefficient: Option<f64>,
}

/// One direction's base acceleration: from a file (a PEER NGA `.AT2` record, or CSV rows `t, a`)
/// or inline `samples`; linear between samples, zero after the last. The ground is at rest when
/// the stage starts: an `.AT2` record's first sample is at t = DT, and a CSV or inline series
/// starting at t = 0 must start with a = 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BaseMotion {
    /// `x` or `y`.
    pub direction: Direction,
    /// The record's file, relative to the model file: `.AT2` (PEER NGA) or CSV.
    #[serde(default)]
    pub file: Option<String>,
    /// Instead of a file: rows `[t, a]`, t increasing from t ≥ 0.
    #[serde(default, deserialize_with = "crate::model::rows::optional_pairs")]
    pub samples: Option<Vec<[f64; 2]>>,
    /// The accelerations' unit: `g` (an `.AT2` record's, its default) or `m/s2` (required for a
    /// CSV file or inline samples).
    #[serde(default)]
    pub unit: Option<AccelerationUnit>,
    /// A factor on the record. Default 1.
    #[serde(default = "one")]
    pub scale: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum AccelerationUnit {
    /// The standard acceleration of gravity, 9.80665 m/s².
    #[serde(rename = "g")]
    G,
    #[serde(rename = "m/s2")]
    MetrePerSecondSquared,
}

/// The compaction of a lift: a vertical pressure on its surface, applied then removed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CompactionSpec {
    /// The compaction pressure [stress], > 0: the equivalent static pressure of the roller or plate.
    pub pressure: f64,
    /// The sides it acts on. Default: the lift's surface, every upward-facing side of the elements
    /// this stage places that no element present after it covers.
    #[serde(default)]
    pub edge_set: Option<String>,
    /// With the default surface: only the elements of this soil material (for example the fill
    /// behind a facing, not the facing's blocks).
    #[serde(default)]
    pub material: Option<String>,
    /// The cumulative fractions of the pressure applied, and then of it removed, step by step
    /// (increasing, ending at 1). Default `[0.5, 1.0]`.
    #[serde(default = "default_compaction_factors")]
    pub load_factors: Vec<f64>,
}

fn default_compaction_factors() -> Vec<f64> {
    vec![0.5, 1.0]
}

/// The factor of safety by strength reduction: c and tan φ are divided by F (c/F, tan φ/F) in the
/// interfaces (peak and residual) and, with `reduce = "soil-and-interfaces"`, in the Mohr–Coulomb
/// soil too (as limit equilibrium assumes). F rises from 1 until no equilibrium is found, then the
/// bracket is halved: FS is the largest F with equilibrium. The state at FS is the last step of the
/// stage (the mechanism: which interfaces slip, the reinforcement forces); later stages go on from it
/// with the full strengths.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrengthReductionSpec {
    pub reduce: ReducedStrengths,
    /// Relative width of the final bracket [F_safe, F_fail] (default 0.002).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Stop searching above this factor (default 10).
    #[serde(default)]
    pub max_factor: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ReducedStrengths {
    /// The interfaces' strengths only.
    Interfaces,
    /// The soil's and the interfaces' strengths together.
    SoilAndInterfaces,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum InitialStress {
    K0,
}

/// A phreatic line: give `level` (horizontal) or `line` (points in increasing x; constant beyond
/// its ends), or `none = true` to remove the water.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WaterTable {
    /// Elevation y of a horizontal water table [length].
    #[serde(default)]
    pub level: Option<f64>,
    /// The phreatic line as `[x, y]` points, x increasing [length].
    #[serde(default, deserialize_with = "crate::model::rows::optional_pairs")]
    pub line: Option<Vec<[f64; 2]>>,
    /// No water from this stage on.
    #[serde(default)]
    pub none: bool,
    /// γw [force/length³]; default 9.81 kN/m³ in the file's units.
    #[serde(default)]
    pub unit_weight: Option<f64>,
}

fn default_load_factors() -> Vec<f64> {
    vec![1.0]
}

impl Default for Stage {
    /// An empty stage with one increment (the file's defaults).
    fn default() -> Stage {
        Stage {
            name: String::new(),
            load_factors: default_load_factors(),
            history: None,
            history_increment: None,
            loads: Vec::new(),
            prescribed: Vec::new(),
            activate: Vec::new(),
            deactivate: Vec::new(),
            initial_stress: None,
            water: None,
            strength_reduction: None,
            freeze_normal_stress: None,
            compaction: None,
            dynamic: None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LoadSpec {
    /// Uniform traction on the edges of an edge set [stress]. `pressure` acts against the outward
    /// normal (positive pushes into the soil); `shear` acts along the edge, positive from its first node
    /// to its second.
    EdgeTraction {
        /// A name, so that a `series` can vary this load.
        #[serde(default)]
        name: Option<String>,
        edge_set: String,
        #[serde(default)]
        pressure: f64,
        #[serde(default)]
        shear: f64,
    },
    /// Point load per metre width out of plane [force per metre width].
    Point {
        #[serde(default)]
        node: Option<u64>,
        #[serde(default)]
        nodes: Option<Vec<u64>>,
        #[serde(default)]
        set: Option<String>,
        #[serde(default)]
        fx: f64,
        #[serde(default)]
        fy: f64,
    },
    /// Self-weight of the soil (−y), from each material's unit weight, times `factor`.
    Gravity {
        #[serde(default = "one")]
        factor: f64,
    },
    /// The pseudo-static force of an earthquake on the soil present in this stage: its weight
    /// (each material's unit weight, saturated below the water table) times the seismic
    /// coefficients kh (towards +x) and kv (towards +y), as a body force (docs/dynamics.md).
    PseudoStatic {
        #[serde(default)]
        kh: f64,
        #[serde(default)]
        kv: f64,
    },
}

fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PrescribedDisplacement {
    #[serde(default)]
    pub node: Option<u64>,
    #[serde(default)]
    pub nodes: Option<Vec<u64>>,
    #[serde(default)]
    pub set: Option<String>,
    /// Displacement added in x during this stage [length].
    #[serde(default)]
    pub ux: Option<f64>,
    /// Displacement added in y during this stage [length].
    #[serde(default)]
    pub uy: Option<f64>,
}
