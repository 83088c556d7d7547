//! A lift compacted under K0 conditions keeps a lateral stress after the compaction pressure is
//! removed.
//!
//! Reference: the Mohr–Coulomb soil in one-dimensional compression and unloading (Broms 1971,
//! "Lateral earth pressures due to compaction of cohesionless soils"; docs/verification.md §13).
//! A column of soil between two smooth rigid walls (εx = 0; plane strain, εz = 0) carries
//! σv = γ·d + q at depth d under a surface pressure q, and σh = σz by symmetry. With
//! K0,el = ν/(1 − ν) < Ka = tan²(45° − φ/2):
//!
//! ```text
//! loading:   σh = max(K0,el·σv, Ka·σv − 2c·√Ka)       (elastic, then on the active yield line)
//! unloading: σh = min(σh,max − K0,el·Δσv, Kp·σv + 2c·√Kp)   (elastic, capped by passive yield)
//! ```
//!
//! The lift (1 m of soil, γ = 18 kN/m³, c = 3 kPa, φ = 34°, ψ = 0, ν = 0.1) is placed in one stage
//! with `compaction = { pressure = 30.0 }`: its weight (elastic throughout: the active line is met
//! at σv = 18.6 kPa), then 30 kPa on its surface (every point on the active line at the peak), then
//! the pressure removed (elastic unloading, far from the passive line). It then holds
//! σh = Ka·(γd + q) − 2c·√Ka − K0,el·q, from 2.0 kPa (top Gauss point) to 5.0 kPa (bottom) more than
//! before. Checked at every Gauss point of the three stages on every backend: σv, σh and σz within
//! 5·10⁻⁸ kPa (measured 9.0·10⁻⁹: the iterations' tolerance).

mod common;

use geoslip::linsol::Backend;
use geoslip::model::Model;

const GAMMA: f64 = 18.0;
const COHESION: f64 = 3.0;
const POISSON: f64 = 0.1;
const PRESSURE: f64 = 30.0;
const HEIGHT: f64 = 1.0;
/// Elements in the column, 0.25 m each.
const LAYERS: usize = 4;

/// A column of quad8 elements 0.5 m wide between smooth walls, placed in one stage and compacted.
fn column() -> String {
    let h = HEIGHT / LAYERS as f64;
    // per row of corners j: nodes 3j+1 (x = 0), 3j+2 (0.25, mid-side), 3j+3 (0.5); per row of
    // mid-sides: 100 + 2j + 1 (x = 0), 100 + 2j + 2 (x = 0.5)
    let mut nodes = Vec::new();
    for j in 0..=LAYERS {
        let y = j as f64 * h;
        nodes.push(format!("[{}, 0.0, {y}], [{}, 0.25, {y}], [{}, 0.5, {y}]", 3 * j + 1, 3 * j + 2, 3 * j + 3));
        if j < LAYERS {
            let ym = y + 0.5 * h;
            nodes.push(format!("[{}, 0.0, {ym}], [{}, 0.5, {ym}]", 100 + 2 * j + 1, 100 + 2 * j + 2));
        }
    }
    let elements: Vec<String> = (0..LAYERS)
        .map(|j| {
            let (a, b) = (3 * j, 3 * (j + 1));
            format!(
                "{{ id = {}, type = \"quad8\", nodes = [{}, {}, {}, {}, {}, {}, {}, {}], material = \"fill\" }}",
                j + 1,
                a + 1,
                a + 3,
                b + 3,
                b + 1,
                a + 2,
                100 + 2 * j + 2,
                b + 2,
                100 + 2 * j + 1
            )
        })
        .collect();
    let left: Vec<String> = (0..=LAYERS)
        .map(|j| (3 * j + 1).to_string())
        .chain((0..LAYERS).map(|j| (100 + 2 * j + 1).to_string()))
        .collect();
    let right: Vec<String> = (0..=LAYERS)
        .map(|j| (3 * j + 3).to_string())
        .chain((0..LAYERS).map(|j| (100 + 2 * j + 2).to_string()))
        .collect();
    format!(
        r#"title = "a compacted lift between smooth walls"
units = {{ length = "m", force = "kN" }}
nodes = [{nodes}]
elements = [{elements}]

[materials.soil.fill]
model = "mohr-coulomb"
youngs_modulus = 20000.0
poissons_ratio = {POISSON}
unit_weight = {GAMMA}
cohesion = {COHESION}
friction_angle = 34.0

[node_sets]
base = [1, 2, 3]
walls = [{walls}]

[element_sets]
lift = [{lift}]

[[supports]]
set = "base"
fix = ["x", "y"]

[[supports]]
set = "walls"
fix = ["x"]

[[stages]]
name = "lift"
load_factors = [0.5, 1.0]
loads = [{{ type = "gravity" }}]
activate = ["lift"]
compaction = {{ pressure = {PRESSURE} }}
"#,
        nodes = nodes.join(", "),
        elements = elements.join(", "),
        walls = left.into_iter().chain(right).collect::<Vec<_>>().join(", "),
        lift = (1..=LAYERS).map(|e| e.to_string()).collect::<Vec<_>>().join(", "),
    )
}

fn model() -> Model {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("column.toml");
    std::fs::write(&path, column()).unwrap();
    Model::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// (Ka, Kp, K0,el)
fn coefficients() -> (f64, f64, f64) {
    let phi = 34f64.to_radians();
    let ka = (std::f64::consts::FRAC_PI_4 - 0.5 * phi).tan().powi(2);
    (ka, 1.0 / ka, POISSON / (1.0 - POISSON))
}

#[test]
fn the_stage_is_followed_by_the_compaction_and_its_removal() {
    let model = model();
    let names: Vec<&str> = model.stages.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["lift", "lift: compaction", "lift: compaction removed"]);
}

#[test]
fn the_compacted_column_keeps_the_lateral_stress_of_the_closed_form() {
    let model = model();
    let (ka, kp, k0) = coefficients();
    let active = |sv: f64| ka * sv - 2.0 * COHESION * ka.sqrt();
    let passive = |sv: f64| kp * sv + 2.0 * COHESION * kp.sqrt();
    for backend in Backend::available() {
        let c = common::run(&model, backend);
        let last_of = |stage: &str| &c.steps.iter().rfind(|(r, _)| r.stage == stage).expect("the stage ran").1;
        let (placed, loaded, removed) =
            (last_of("lift"), last_of("lift: compaction"), last_of("lift: compaction removed"));
        let (mut locked, mut worst) = (f64::INFINITY, 0.0f64);
        for ((p0, p1), p2) in placed.stresses(&model).iter().zip(loaded.stresses(&model)).zip(removed.stresses(&model))
        {
            let depth = HEIGHT - p0.x[1];
            let sv0 = GAMMA * depth;
            let (sv1, sv2) = (sv0 + PRESSURE, sv0);
            let sh0 = (k0 * sv0).max(active(sv0));
            let sh1 = (k0 * sv1).max(active(sv1));
            assert!(sh1 == active(sv1), "every point reaches the active line at the peak");
            let sh2 = (sh1 - k0 * PRESSURE).min(passive(sv2));
            for (p, sv, sh, when) in [(p0, sv0, sh0, "placed"), (p1, sv1, sh1, "compacted"), (p2, sv2, sh2, "after")] {
                let [sxx, syy, _, szz] = p.stress;
                worst = worst.max((-syy - sv).abs()).max((-sxx - sh).abs()).max((-szz - sh).abs());
                assert!(
                    (-syy - sv).abs() < 5e-8 && (-sxx - sh).abs() < 5e-8 && (-szz - sh).abs() < 5e-8,
                    "{backend:?}, {when}, depth {depth:.4}: σv {:.6} σh {:.6} σz {:.6}, expected {sv:.6} {sh:.6}",
                    -syy,
                    -sxx,
                    -szz
                );
            }
            locked = locked.min(sh2 - sh0);
        }
        // the lateral stress compaction leaves, (Ka − K0,el)·(γd + q) − 2c·√Ka: 2.04 kPa at the top
        // Gauss point
        assert!(locked > 2.0, "{backend:?}: locked-in σh at least {locked:.3} kPa");
        eprintln!("{backend:?}: largest stress error {worst:.1e} kPa; lateral stress left at least {locked:.4} kPa");
    }
}
