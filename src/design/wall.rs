//! The wall a model builds, as the design methods see it, and each layer's checks.
//!
//! Read from the model (`model/validate/design.rs` gathers what it needs), with nothing typed twice:
//! - the reinforced fill is the `[design]` table's `reinforced_soil`: the lowest and highest nodes
//!   of its elements give the wall's base and crest (H), the nearest to the face its face;
//! - the layers are the model's reinforcement interfaces that run into the fill: each one's
//!   elevation and its length behind the face;
//! - each layer's tributary zone runs halfway to the layers above and below, from the crest for
//!   the top layer and to the base for the bottom one (FHWA-NHI-10-025 Table E4-7.1);
//! - the surcharge is the pressure of the edge tractions on the crest, unless the table gives one.

use super::parameters::{DesignParameters, ReinforcementKind, WallFace};
use super::pullout::{self, PulloutResistance};
use super::simplified::{self, SimplifiedLoad};
use crate::error::Problem;

/// The depth below which the metallic Kr/Ka and F* stay constant: 6 m.
const TRANSITION_DEPTH_M: f64 = 6.0;

/// A reinforcement layer of the wall.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// The reinforcement interface's name.
    pub name: String,
    /// Elevation y of the layer.
    pub elevation: f64,
    /// Depth Z below the crest.
    pub depth: f64,
    /// The depths of the top and bottom of its tributary zone (Svt = bottom − top).
    pub zone_top: f64,
    pub zone_bottom: f64,
    /// Length L behind the face.
    pub length: f64,
}

impl Layer {
    /// The tributary height Svt.
    pub fn spacing(&self) -> f64 {
        self.zone_bottom - self.zone_top
    }
}

/// The wall of a model with a `[design]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    pub parameters: DesignParameters,
    /// Elevation of the base and of the crest of the reinforced fill.
    pub base: f64,
    pub crest: f64,
    /// x of the face (the fill's edge: the back of a facing).
    pub face_x: f64,
    /// γ of the reinforced fill [force/length³].
    pub unit_weight: f64,
    /// φ of the reinforced fill [radians].
    pub friction_angle: f64,
    /// The surcharge q on the crest [stress], and where it came from.
    pub surcharge: f64,
    pub surcharge_source: &'static str,
    /// One metre in the model's length unit.
    pub metre: f64,
    /// From the bottom layer up.
    pub layers: Vec<Layer>,
}

/// One layer's design checks.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerCheck {
    pub layer: Layer,
    /// The largest tension in the layer from the analysis, and its distance from the face.
    pub fe_max_tension: f64,
    pub fe_distance: f64,
    pub simplified: SimplifiedLoad,
    pub pullout: PulloutResistance,
}

impl LayerCheck {
    /// Pr / T_max of the analysis.
    pub fn pullout_ratio_fe(&self) -> f64 {
        self.pullout.resistance / self.fe_max_tension
    }
    /// Pr / T_max of the Simplified Method, both unfactored.
    pub fn pullout_ratio_simplified(&self) -> f64 {
        self.pullout.resistance / self.simplified.max_tension
    }
    /// φ·Pr / (γP,EV·T_max) of the Simplified Method: the LRFD capacity-to-demand ratio.
    pub fn pullout_cdr(&self) -> f64 {
        self.pullout.factored_resistance / self.simplified.factored_max_tension
    }
}

/// What the design checks read from a model: the reinforced fill, the reinforcement interfaces and
/// the edge tractions (`model/validate/design.rs` gathers it).
#[derive(Debug, Clone, Default)]
pub struct WallInputs {
    /// γ [force/length³] and φ [degrees] of the reinforced fill.
    pub unit_weight: f64,
    pub friction_angle_degrees: f64,
    /// The nodes of the fill's elements.
    pub fill_points: Vec<[f64; 2]>,
    /// Each reinforcement interface: its name and its nodes.
    pub reinforcements: Vec<(String, Vec<[f64; 2]>)>,
    /// Each edge traction of the stages: its pressure and the elevations of its loaded sides' nodes.
    pub edge_tractions: Vec<(f64, Vec<f64>)>,
    /// One metre in the model's length unit.
    pub metre: f64,
}

impl Wall {
    /// The wall that `parameters` describe in a model that holds `inputs`.
    ///
    /// # Errors
    /// A problem naming the `[design]` field when a value is out of range, the fill has no element
    /// or no friction angle, no reinforcement layer runs into it, a layer is not horizontal, or a
    /// bar mat's F* cannot be found.
    pub fn new(parameters: &DesignParameters, inputs: &WallInputs) -> Result<Wall, Problem> {
        let problem = |field: &str, entity: Option<String>, message: String| Problem {
            field: format!("design.{field}"),
            entity,
            message,
        };
        let ranges = [
            ("pullout_factor", parameters.pullout_factor, 10.0),
            ("scale_correction", parameters.scale_correction, 1.0),
            ("coverage_ratio", parameters.coverage_ratio, 1.0),
            ("transverse_bar_thickness", parameters.transverse_bar_thickness, f64::INFINITY),
            ("transverse_bar_spacing", parameters.transverse_bar_spacing, f64::INFINITY),
        ];
        for (field, value, high) in ranges {
            if let Some(v) = value {
                if !(v.is_finite() && v > 0.0 && v <= high) {
                    let range =
                        if high.is_finite() { format!("> 0 and ≤ {high}") } else { "a finite number > 0".into() };
                    return Err(problem(field, None, format!("is {v}; it must be {range}")));
                }
            }
        }
        if let Some(q) = parameters.surcharge {
            if !(q.is_finite() && q >= 0.0) {
                return Err(problem("surcharge", None, format!("is {q}; it must be a finite pressure ≥ 0")));
            }
        }
        if parameters.reinforcement == ReinforcementKind::BarMat
            && parameters.pullout_factor.is_none()
            && (parameters.transverse_bar_thickness.is_none() || parameters.transverse_bar_spacing.is_none())
        {
            return Err(problem(
                "reinforcement",
                None,
                "a bar mat's F* comes from its transverse bars: give transverse_bar_thickness and transverse_bar_spacing, or pullout_factor".into(),
            ));
        }
        let fill_name = &parameters.reinforced_soil;
        let fill_entity = || Some(format!("material \"{fill_name}\""));
        let toward_fill = match parameters.face {
            WallFace::Left => 1.0,
            WallFace::Right => -1.0,
        };
        let (mut base, mut crest, mut face) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        for &[x, y] in &inputs.fill_points {
            base = base.min(y);
            crest = crest.max(y);
            face = face.min(toward_fill * x);
        }
        if !base.is_finite() {
            return Err(problem("reinforced_soil", fill_entity(), "has no soil element in the mesh".into()));
        }
        let height = crest - base;
        let face_x = toward_fill * face;
        if !(inputs.friction_angle_degrees > 0.0) {
            return Err(problem(
                "reinforced_soil",
                fill_entity(),
                "has no friction angle: the design methods need φ of the reinforced fill (give a Mohr–Coulomb or Duncan–Chang soil)"
                    .into(),
            ));
        }

        // the layers: reinforcement interfaces at a height inside the fill's that run behind its face
        let mut layers = Vec::new();
        for (name, points) in &inputs.reinforcements {
            let (mut y_min, mut y_max, mut far) = (f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
            for &[x, y] in points {
                y_min = y_min.min(y);
                y_max = y_max.max(y);
                far = far.max(toward_fill * x - face);
            }
            let elevation = 0.5 * (y_min + y_max);
            if !(elevation > base && elevation < crest) || far <= 0.0 {
                continue;
            }
            if y_max - y_min > 1e-6 * height {
                return Err(problem(
                    "reinforced_soil",
                    Some(format!("interface \"{name}\"")),
                    format!(
                        "runs into the reinforced fill but is not horizontal (y from {y_min} to {y_max}): the design methods take horizontal layers"
                    ),
                ));
            }
            layers.push(Layer {
                name: name.clone(),
                elevation,
                depth: crest - elevation,
                zone_top: 0.0,
                zone_bottom: 0.0,
                length: far,
            });
        }
        if layers.is_empty() {
            return Err(problem(
                "reinforced_soil",
                fill_entity(),
                "no reinforcement interface runs into this fill: the design checks need the wall's layers".into(),
            ));
        }
        // from the top layer down: each zone from halfway to the layer above (the crest for the
        // top one) to halfway to the layer below (the base for the bottom one)
        layers.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        let depths: Vec<f64> = layers.iter().map(|l| l.depth).collect();
        for (k, layer) in layers.iter_mut().enumerate() {
            layer.zone_top = if k == 0 { 0.0 } else { 0.5 * (depths[k - 1] + depths[k]) };
            layer.zone_bottom = if k + 1 == depths.len() { height } else { 0.5 * (depths[k] + depths[k + 1]) };
        }
        layers.reverse();

        let (surcharge, surcharge_source) = match parameters.surcharge {
            Some(q) => (q, "the [design] table"),
            None => {
                // the edge tractions whose every loaded node lies on the crest
                let on_crest = |ys: &Vec<f64>| !ys.is_empty() && ys.iter().all(|y| (y - crest).abs() <= 1e-6 * height);
                let q = inputs.edge_tractions.iter().filter(|(_, ys)| on_crest(ys)).map(|(p, _)| p).sum();
                (q, "the model's edge tractions on the crest")
            }
        };
        Ok(Wall {
            parameters: parameters.clone(),
            base,
            crest,
            face_x,
            unit_weight: inputs.unit_weight,
            friction_angle: inputs.friction_angle_degrees.to_radians(),
            surcharge,
            surcharge_source,
            metre: inputs.metre,
            layers,
        })
    }

    /// H: the height of the reinforced fill.
    pub fn height(&self) -> f64 {
        self.crest - self.base
    }

    pub fn reinforcement(&self) -> ReinforcementKind {
        self.parameters.reinforcement
    }

    /// α, the given one or the default of the kind of reinforcement.
    pub fn scale_correction(&self) -> f64 {
        self.parameters.scale_correction.unwrap_or_else(|| self.parameters.reinforcement.scale_correction())
    }

    pub fn coverage_ratio(&self) -> f64 {
        self.parameters.coverage_ratio.unwrap_or(1.0)
    }

    /// F* at depth `depth`: the given one, or the default of the kind of reinforcement.
    pub fn pullout_factor(&self, depth: f64) -> f64 {
        let p = &self.parameters;
        match (p.pullout_factor, p.reinforcement, p.transverse_bar_thickness, p.transverse_bar_spacing) {
            (Some(f), ..) => f,
            (None, ReinforcementKind::BarMat, Some(t), Some(s)) => {
                pullout::bar_mat_pullout_factor(t, s, depth, TRANSITION_DEPTH_M * self.metre)
            }
            _ => pullout::geosynthetic_pullout_factor(self.friction_angle),
        }
    }

    /// Each layer's checks, with the largest tension the analysis found in it: `fe_tension` gives,
    /// by layer name, the largest tension and the x of the bar that carries it (none: zero).
    pub fn checks(&self, fe_tension: &dyn Fn(&str) -> Option<(f64, f64)>) -> Vec<LayerCheck> {
        let ka = simplified::active_coefficient(self.friction_angle);
        let kind = self.reinforcement();
        let transition = TRANSITION_DEPTH_M * self.metre;
        let toward_fill = if self.parameters.face == WallFace::Left { 1.0 } else { -1.0 };
        self.layers
            .iter()
            .map(|layer| {
                let (fe_max_tension, fe_x) = fe_tension(&layer.name).unwrap_or((0.0, self.face_x));
                let active = pullout::active_zone_width(kind, self.height(), layer.depth, self.friction_angle);
                LayerCheck {
                    layer: layer.clone(),
                    fe_max_tension,
                    fe_distance: toward_fill * (fe_x - self.face_x),
                    simplified: simplified::layer_load(
                        kind,
                        ka,
                        self.unit_weight,
                        layer.zone_top,
                        layer.zone_bottom,
                        self.surcharge,
                        transition,
                    ),
                    pullout: pullout::resistance(
                        self.pullout_factor(layer.depth),
                        self.scale_correction(),
                        self.unit_weight * layer.depth,
                        layer.length,
                        active,
                        self.coverage_ratio(),
                    ),
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    //! Reference: a wall whose geometry is known by construction, facing left and mirrored to face
    //! right: H = 3 m, layers at y = 0.5, 1.5 and 2.5 m running 2.0, 2.5 and 3.0 m behind the face
    //! (and an interface outside the fill, which is not a layer), a 12 kPa edge traction on the
    //! crest and one below it.
    use super::*;

    fn inputs(mirror: bool) -> WallInputs {
        let x = |x: f64| if mirror { 10.0 - x } else { x };
        let mut fill_points = Vec::new();
        for i in 0..=8 {
            for j in 0..=6 {
                fill_points.push([x(1.0 + 0.5 * i as f64), 0.5 * j as f64]);
            }
        }
        let layer = |y: f64, length: f64| (0..=4).map(|k| [x(1.0 + length * k as f64 / 4.0), y]).collect();
        WallInputs {
            unit_weight: 18.0,
            friction_angle_degrees: 30.0,
            fill_points,
            reinforcements: vec![
                ("grid-b".into(), layer(0.5, 2.0)),
                ("grid-t".into(), layer(2.5, 3.0)),
                ("grid-m".into(), layer(1.5, 2.5)),
                ("liner".into(), vec![[x(1.0), -1.0], [x(5.0), -1.0]]),
            ],
            edge_tractions: vec![(12.0, vec![3.0, 3.0, 3.0]), (5.0, vec![3.0, 2.5])],
            metre: 1.0,
        }
    }

    fn parameters(face: WallFace) -> DesignParameters {
        DesignParameters {
            reinforced_soil: "fill".into(),
            reinforcement: ReinforcementKind::Geogrid,
            face,
            pullout_factor: None,
            transverse_bar_thickness: None,
            transverse_bar_spacing: None,
            scale_correction: None,
            coverage_ratio: None,
            surcharge: None,
        }
    }

    #[test]
    fn a_wall_facing_either_way_has_the_same_layers() {
        for (face, mirror, face_x) in [(WallFace::Left, false, 1.0), (WallFace::Right, true, 9.0)] {
            let wall = Wall::new(&parameters(face), &inputs(mirror)).unwrap();
            assert!((wall.height() - 3.0).abs() < 1e-12 && (wall.face_x - face_x).abs() < 1e-12, "{wall:?}");
            assert!((wall.surcharge - 12.0).abs() < 1e-12, "only the traction on the crest: {}", wall.surcharge);
            let got: Vec<(&str, f64, f64, f64, f64)> =
                wall.layers.iter().map(|l| (l.name.as_str(), l.depth, l.zone_top, l.zone_bottom, l.length)).collect();
            let expected =
                [("grid-b", 2.5, 2.0, 3.0, 2.0), ("grid-m", 1.5, 1.0, 2.0, 2.5), ("grid-t", 0.5, 0.0, 1.0, 3.0)];
            assert_eq!(got.len(), 3, "{got:?}");
            for (g, e) in got.iter().zip(expected) {
                assert!(
                    g.0 == e.0 && [g.1 - e.1, g.2 - e.2, g.3 - e.3, g.4 - e.4].iter().all(|d| d.abs() < 1e-12),
                    "{face:?}: {g:?} against {e:?}"
                );
            }
        }
    }

    #[test]
    fn a_layer_that_is_not_horizontal_is_named() {
        let mut inputs = inputs(false);
        inputs.reinforcements[1].1[4][1] = 2.6;
        let problem = Wall::new(&parameters(WallFace::Left), &inputs).unwrap_err();
        assert!(
            problem.entity.as_deref() == Some("interface \"grid-t\"") && problem.message.contains("not horizontal")
        );
    }
}
