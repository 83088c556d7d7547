//! Materials: soil and reinforcement properties, and the interfaces' shear laws.

use super::Draft;
use crate::interface::ShearLaw;
use crate::model::file::*;
use crate::model::problems::Problems;

/// The largest Poisson's ratio a soil may have (bulk / shear modulus about 500).
pub const MAX_POISSONS_RATIO: f64 = 0.499;

/// The soil and reinforcement materials.
pub(super) fn materials(d: &mut Draft, file: &ModelFile, p: &mut Problems) {
    let units = &file.units;
    d.soils = file.materials.soil.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    for (name, m) in &d.soils {
        let entity = format!("soil material \"{name}\"");
        let f = |field: &str| format!("materials.soil.{name}.{field}");
        let stiffness_table = match m.model {
            SoilModel::DuncanChang => Some(("hyperbolic", "a Duncan–Chang", "K, n, Kb, m and Kur in `hyperbolic`")),
            SoilModel::HardeningSoil => {
                Some(("hardening", "a hardening", "E50_ref, Eoed_ref, Eur_ref and m in `hardening`"))
            }
            _ => None,
        };
        if let Some((_, soil, what)) = stiffness_table {
            for (field, given) in
                [("youngs_modulus", m.youngs_modulus.is_some()), ("poissons_ratio", m.poissons_ratio.is_some())]
            {
                if given {
                    p.push(
                        f(field),
                        &entity,
                        format!("{soil} soil's stiffness follows its stresses: give {what}, not E and ν"),
                    );
                }
            }
        }
        for (table, soil, model, given) in [
            (
                "hyperbolic",
                "a Duncan–Chang",
                "duncan-chang",
                m.hyperbolic.is_some() && m.model != SoilModel::DuncanChang,
            ),
            (
                "hardening",
                "a hardening",
                "hardening-soil",
                m.hardening.is_some() && m.model != SoilModel::HardeningSoil,
            ),
        ] {
            if given {
                p.push(f(table), &entity, format!("applies to {soil} soil: set model = \"{model}\" to use it"));
            }
        }
        if m.model == SoilModel::DuncanChang {
            match &m.hyperbolic {
                Some(h) => hyperbolic(h, &f("hyperbolic"), &entity, p),
                None => p.push(
                    f("hyperbolic"),
                    &entity,
                    "a Duncan–Chang soil needs its stiffness parameters: hyperbolic = { K, n, Rf, Kb, m, Kur }",
                ),
            }
        } else if m.model == SoilModel::HardeningSoil {
            match &m.hardening {
                Some(h) => hardening(m, h, &f("hardening"), &entity, units, p),
                None => p.push(
                    f("hardening"),
                    &entity,
                    "a hardening soil needs its stiffness parameters: hardening = { E50_ref, m } at least \
                     (Eoed_ref, Eur_ref, p_ref, nu_ur, Rf and K0nc have defaults)",
                ),
            }
        } else {
            match m.youngs_modulus {
                Some(e) if !(e.is_finite() && e > 0.0) => {
                    p.push(f("youngs_modulus"), &entity, format!("must be a positive number, found {e}"))
                }
                Some(_) => {}
                None => p.push(f("youngs_modulus"), &entity, "is required"),
            }
            match m.poissons_ratio {
                Some(nu) if !(nu.is_finite() && (0.0..0.5).contains(&nu)) => {
                    p.push(f("poissons_ratio"), &entity, format!("must be in [0, 0.5), found {nu}"))
                }
                Some(nu) if nu > MAX_POISSONS_RATIO => p.push(
                    f("poissons_ratio"),
                    &entity,
                    format!(
                        "{nu} is too close to 0.5: the bulk modulus would be {:.1e} times the shear modulus, which \
                         locks the displacement elements and leaves the stiffness matrix too ill-conditioned to \
                         solve; geoslip takes at most {MAX_POISSONS_RATIO} (an undrained analysis is usually run at \
                         0.495)",
                        2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))
                    ),
                ),
                Some(_) => {}
                None => p.push(f("poissons_ratio"), &entity, "is required"),
            }
        }
        if !(m.unit_weight.is_finite() && m.unit_weight >= 0.0) {
            p.push(f("unit_weight"), &entity, format!("must be zero or positive, found {}", m.unit_weight));
        }
        if let Some(g) = m.saturated_unit_weight {
            if !(g.is_finite() && g >= 0.0) {
                p.push(f("saturated_unit_weight"), &entity, format!("must be zero or positive, found {g}"));
            }
        }
        if let Some(k0) = m.k0 {
            if !(k0.is_finite() && k0 > 0.0) {
                p.push(f("k0"), &entity, format!("must be a positive number, found {k0}"));
            }
        }
        let plastic = m.model != SoilModel::LinearElastic;
        if plastic {
            if !(m.cohesion.is_finite() && m.cohesion >= 0.0) {
                p.push(f("cohesion"), &entity, format!("must be zero or positive, found {}", m.cohesion));
            }
            if !(m.friction_angle.is_finite() && (0.0..90.0).contains(&m.friction_angle)) {
                p.push(f("friction_angle"), &entity, format!("must be in [0, 90) degrees, found {}", m.friction_angle));
            } else if m.cohesion == 0.0 && m.friction_angle == 0.0 {
                p.push(f("cohesion"), &entity, "a soil with c = 0 and φ = 0 has no strength");
            }
            if !(m.dilatancy_angle.is_finite() && m.dilatancy_angle >= 0.0 && m.dilatancy_angle <= m.friction_angle) {
                p.push(
                    f("dilatancy_angle"),
                    &entity,
                    format!(
                        "must be in [0, friction_angle = {}] degrees, found {}",
                        m.friction_angle, m.dilatancy_angle
                    ),
                );
            }
            if let (Some((_, soil, _)), Some(_)) = (stiffness_table, m.tensile_strength) {
                p.push(f("tensile_strength"), &entity, format!("{soil} soil's tension limit is the apex c·cot φ"));
            }
            if m.model == SoilModel::HardeningSoil && m.friction_angle == 0.0 {
                p.push(
                    f("friction_angle"),
                    &entity,
                    "a hardening soil's stiffness and strength grow with c·cos φ + σ3·sin φ: φ must be above zero",
                );
            }
            if let Some(t) = m.tensile_strength {
                if !(t.is_finite() && t >= 0.0) {
                    p.push(f("tensile_strength"), &entity, format!("must be zero or positive, found {t}"));
                }
            }
        } else {
            for (field, given) in [
                ("cohesion", m.cohesion != 0.0),
                ("friction_angle", m.friction_angle != 0.0),
                ("dilatancy_angle", m.dilatancy_angle != 0.0),
                ("tensile_strength", m.tensile_strength.is_some()),
            ] {
                if given {
                    p.push(
                        f(field),
                        &entity,
                        "is a strength parameter: set model = \"mohr-coulomb\", \"duncan-chang\" or \"hardening-soil\" \
                         to use it",
                    );
                }
            }
        }
    }
    d.reinforcements = file.materials.reinforcement.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    for (name, m) in &d.reinforcements {
        let entity = format!("reinforcement material \"{name}\"");
        let f = |field: &str| format!("materials.reinforcement.{name}.{field}");
        if !(m.axial_stiffness.is_finite() && m.axial_stiffness > 0.0) {
            p.push(f("axial_stiffness"), &entity, format!("must be a positive number, found {}", m.axial_stiffness));
        }
        if let Some(t) = m.rupture_strength {
            if !(t.is_finite() && t > 0.0) {
                p.push(f("rupture_strength"), &entity, format!("must be a positive number, found {t}"));
            }
        }
        if let Some(w) = m.weight {
            if !(w.is_finite() && w >= 0.0) {
                p.push(f("weight"), &entity, format!("must be a number ≥ 0, found {w}"));
            }
        }
    }
    d.soil_index = d.soils.iter().enumerate().map(|(i, (n, _))| (n.clone(), i)).collect();
    d.reinf_index = d.reinforcements.iter().enumerate().map(|(i, (n, _))| (n.clone(), i)).collect();
}

/// A Duncan–Chang soil's stiffness parameters, each within the range the method's tables span
/// (Duncan et al. 1980).
fn hyperbolic(h: &HyperbolicParameters, field: &str, entity: &str, p: &mut Problems) {
    let mut check = |name: &str, v: f64, ok: bool, range: &str| {
        if !(v.is_finite() && ok) {
            p.push(format!("{field}.{name}"), entity, format!("must be {range}, found {v}"));
        }
    };
    check("K", h.modulus_number, h.modulus_number > 0.0, "a positive number");
    check("n", h.n, (0.0..=2.0).contains(&h.n), "in [0, 2]");
    check("Rf", h.failure_ratio, h.failure_ratio > 0.0 && h.failure_ratio < 1.0, "in (0, 1)");
    check("Kb", h.bulk_modulus_number, h.bulk_modulus_number > 0.0, "a positive number");
    check("m", h.m, (0.0..=2.0).contains(&h.m), "in [0, 2]");
    check(
        "Kur",
        h.unloading_modulus_number,
        h.unloading_modulus_number >= h.modulus_number,
        &format!("at least K = {} (unloading is stiffer than loading)", h.modulus_number),
    );
    check("delta_phi", h.delta_phi, (0.0..30.0).contains(&h.delta_phi), "in [0, 30) degrees");
    if let Some(pa) = h.pa {
        check("pa", pa, pa > 0.0, "a positive number");
    }
}

/// A hardening soil's stiffness parameters, each within its physical range, and the cap that
/// they and K0nc imply.
fn hardening(
    m: &SoilMaterial,
    h: &HardeningSoilParameters,
    field: &str,
    entity: &str,
    units: &Units,
    p: &mut Problems,
) {
    let before = p.len();
    let mut check = |name: &str, v: f64, ok: bool, range: &str| {
        if !(v.is_finite() && ok) {
            p.push(format!("{field}.{name}"), entity, format!("must be {range}, found {v}"));
        }
    };
    check("E50_ref", h.secant_modulus, h.secant_modulus > 0.0, "a positive number");
    if let Some(e) = h.oedometer_modulus {
        check("Eoed_ref", e, e > 0.0, "a positive number");
    }
    let rf = h.failure_ratio.unwrap_or(0.9);
    check("Rf", rf, rf > 0.0 && rf < 1.0, "in (0, 1)");
    // Eur at least Ei: the shear hardening surface then grows with q from the isotropic state
    let initial = 2.0 * h.secant_modulus / (2.0 - rf);
    let eur = h.unloading_modulus.unwrap_or(3.0 * h.secant_modulus);
    check(
        "Eur_ref",
        eur,
        eur >= initial,
        &format!(
            "at least the initial modulus Ei = 2·E50_ref/(2 − Rf) = {initial} (unloading is stiffer than loading)"
        ),
    );
    check("m", h.m, h.m > 0.0 && h.m <= 1.0, "in (0, 1]");
    if let Some(pref) = h.p_ref {
        check("p_ref", pref, pref > 0.0, "a positive number");
    }
    if let Some(nu) = h.nu_ur {
        check("nu_ur", nu, (0.0..0.5).contains(&nu), "in [0, 0.5)");
    }
    if let Some(k) = h.k0_nc {
        check("K0nc", k, k > 0.0 && k < 1.0, "in (0, 1)");
    }
    if m.k0.is_some() && h.k0_nc.is_some() && m.k0 != h.k0_nc {
        p.push(
            format!("{field}.K0nc"),
            entity,
            "differs from the material's k0: a hardening soil starts normally consolidated, so its initial K0 is K0nc \
             (give one of them)",
        );
    }
    let strength_ok = m.friction_angle.is_finite() && m.friction_angle > 0.0 && m.friction_angle < 90.0;
    if p.len() == before && strength_ok {
        if let Some(Err(misfit)) = crate::model::Model::hardening_soil(m, units) {
            p.push(field.to_string(), entity, misfit.to_string());
        }
    }
}

/// A shear law as the file gives it, checked; `None` when it has a problem.
pub(super) fn shear_law(spec: &ShearLawSpec, field: &str, entity: &str, p: &mut Problems) -> Option<ShearLaw> {
    let before = p.len();
    let positive = |name: &str, v: f64, p: &mut Problems| {
        if !(v.is_finite() && v > 0.0) {
            p.push(format!("{field}.{name}"), entity, format!("must be a positive number, found {v}"));
        }
    };
    let non_negative = |name: &str, v: f64, p: &mut Problems| {
        if !(v.is_finite() && v >= 0.0) {
            p.push(format!("{field}.{name}"), entity, format!("must be zero or positive, found {v}"));
        }
    };
    let angle = |name: &str, v: f64, p: &mut Problems| -> f64 {
        if !(v.is_finite() && (0.0..90.0).contains(&v)) {
            p.push(format!("{field}.{name}"), entity, format!("must be an angle in degrees within [0, 90), found {v}"));
        }
        v.to_radians().tan()
    };
    let law = match *spec {
        ShearLawSpec::Tie => ShearLaw::Tie,
        ShearLawSpec::Linear { shear_stiffness } => {
            positive("shear_stiffness", shear_stiffness, p);
            ShearLaw::Linear { shear_stiffness }
        }
        ShearLawSpec::Coulomb { shear_stiffness, cohesion, friction_angle } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            ShearLaw::Coulomb { shear_stiffness, cohesion, tan_friction }
        }
        ShearLawSpec::Hyperbolic { shear_stiffness, cohesion, friction_angle } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            ShearLaw::Hyperbolic { shear_stiffness, cohesion, tan_friction }
        }
        ShearLawSpec::PeakResidual {
            shear_stiffness,
            cohesion,
            friction_angle,
            residual_cohesion,
            residual_friction_angle,
        }
        | ShearLawSpec::Softening {
            shear_stiffness,
            cohesion,
            friction_angle,
            residual_cohesion,
            residual_friction_angle,
            ..
        } => {
            positive("shear_stiffness", shear_stiffness, p);
            non_negative("cohesion", cohesion, p);
            non_negative("residual_cohesion", residual_cohesion, p);
            let tan_friction = angle("friction_angle", friction_angle, p);
            let residual_tan_friction = angle("residual_friction_angle", residual_friction_angle, p);
            if residual_cohesion > cohesion || residual_friction_angle > friction_angle {
                p.push(
                    field,
                    entity,
                    "the residual strength must not exceed the peak: residual_cohesion ≤ cohesion and residual_friction_angle ≤ friction_angle",
                );
            }
            match *spec {
                ShearLawSpec::Softening { softening_slip, .. } => {
                    positive("softening_slip", softening_slip, p);
                    ShearLaw::Softening {
                        shear_stiffness,
                        cohesion,
                        tan_friction,
                        residual_cohesion,
                        residual_tan_friction,
                        softening_slip,
                    }
                }
                _ => ShearLaw::PeakResidual {
                    shear_stiffness,
                    cohesion,
                    tan_friction,
                    residual_cohesion,
                    residual_tan_friction,
                },
            }
        }
    };
    if p.len() > before {
        return None;
    }
    Some(law)
}
