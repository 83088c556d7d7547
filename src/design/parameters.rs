//! The design parameters a model gives in its `[design]` table.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What the design checks need beyond what the model holds: which soil is the reinforced fill,
/// what kind of reinforcement it is, and the pull-out parameters where the manual's defaults do not
/// apply.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignParameters {
    /// The soil material of the reinforced fill: its elements give the wall's height and face, its
    /// unit weight and friction angle enter the methods.
    pub reinforced_soil: String,
    /// `geogrid`, `geotextile` (extensible) or `bar-mat` (a steel bar mat or welded-wire grid,
    /// inextensible): Kr/Ka, the failure surface, F* and α depend on it.
    pub reinforcement: ReinforcementKind,
    /// The side the wall faces: `left` (default; the reinforced fill lies at x greater than its
    /// face) or `right`.
    #[serde(default)]
    pub face: WallFace,
    /// The pull-out resistance factor F* at every depth; default 0.67·tan φ of the reinforced fill
    /// for a geosynthetic without a pull-out test, and 20·t/St → 10·t/St for a bar mat.
    #[serde(default)]
    pub pullout_factor: Option<f64>,
    /// A bar mat's transverse bars: their thickness t and spacing St [length], for its default F*.
    #[serde(default)]
    pub transverse_bar_thickness: Option<f64>,
    #[serde(default)]
    pub transverse_bar_spacing: Option<f64>,
    /// The scale-effect correction α; default 0.8 for a geogrid, 0.6 for a geotextile, 1 for a bar
    /// mat.
    #[serde(default)]
    pub scale_correction: Option<f64>,
    /// The coverage ratio Rc = b/Sh of the reinforcement; default 1 (continuous sheets or grids).
    #[serde(default)]
    pub coverage_ratio: Option<f64>,
    /// A uniform surcharge on the crest [stress]: in T_max, not in the pull-out resistance;
    /// default: the pressure of the model's edge tractions on the crest.
    #[serde(default)]
    pub surcharge: Option<f64>,
}

/// The kind of reinforcement, for the defaults that depend on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ReinforcementKind {
    Geogrid,
    Geotextile,
    /// A steel bar mat or welded-wire grid.
    BarMat,
}

impl ReinforcementKind {
    /// The default scale-effect correction α (AASHTO LRFD Table 11.10.6.3.2-1).
    pub fn scale_correction(self) -> f64 {
        match self {
            ReinforcementKind::Geogrid => 0.8,
            ReinforcementKind::Geotextile => 0.6,
            ReinforcementKind::BarMat => 1.0,
        }
    }

    /// Geosynthetics stretch enough for the fill to reach its active state: Rankine's failure
    /// plane and Kr = Ka.
    pub fn is_extensible(self) -> bool {
        self != ReinforcementKind::BarMat
    }

    pub fn name(self) -> &'static str {
        match self {
            ReinforcementKind::Geogrid => "geogrid",
            ReinforcementKind::Geotextile => "geotextile",
            ReinforcementKind::BarMat => "bar-mat",
        }
    }
}

/// The side a wall faces.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum WallFace {
    #[default]
    Left,
    Right,
}
