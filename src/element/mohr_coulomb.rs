//! Mohr–Coulomb soil with a tension cut-off and non-associated flow: the stress update (return
//! mapping in principal stresses) and its consistent tangent, in plane strain.
//!
//! Tension is positive. With principal stresses σ1 ≥ σ2 ≥ σ3 (the out-of-plane σzz is one of them)
//! the criteria are
//!
//! ```text
//! shear    f = (1 + sin φ)·σ1 − (1 − sin φ)·σ3 − 2c·cos φ ≤ 0      flow g: φ → ψ
//! tension  t = σ1 − σt ≤ 0                                        associated
//! ```
//!
//! Every criterion is a plane in principal-stress space, so the return is exact and found in one
//! step: for each candidate set of active planes (one plane, an edge where two meet, a corner or the
//! apex where three meet) the plastic multipliers solve a small linear system, and the first set
//! whose multipliers are non-negative and whose stress satisfies every criterion is taken (Clausen,
//! Damkilde & Andersen, Computers & Structures 85 (2007) 1795–1807, for linear criteria with
//! non-associated flow; de Souza Neto, Perić & Owen, Computational Methods for Plasticity (2008)
//! §8.2 for the Mohr–Coulomb corners). Trying the edges and the apex this way is what makes the
//! corners robust: no derivative of a non-smooth surface is ever needed.
//!
//! The consistent tangent follows from the same linear systems,
//! J = I − D_p·B·(Aᵀ·D_p·B)⁻¹·Aᵀ in principal space (A: the active gradients, B: their flow
//! directions, D_p: isotropic elasticity in principal axes), carried to Cartesian components with
//! the spin term of an isotropic tensor function (de Souza Neto et al. 2008, Appendix A,
//! Eq. A.43). It is unsymmetric when ψ ≠ φ.

use super::solid::PlaneStrain;
use nalgebra::{Matrix3, Matrix4, Vector3};

/// The strength and flow parameters of a Mohr–Coulomb soil.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MohrCoulomb {
    /// c [stress].
    pub cohesion: f64,
    /// φ [rad].
    pub friction_angle: f64,
    /// ψ [rad], 0 ≤ ψ ≤ φ.
    pub dilatancy_angle: f64,
    /// σt [stress]: the largest principal stress allowed; at most c·cot φ.
    pub tensile_strength: f64,
}

impl MohrCoulomb {
    /// The law with c/F and tan φ/F (strength reduction); ψ is kept unless it exceeds the reduced
    /// φ, and the tension cut-off stays below the reduced apex c·cot φ.
    pub fn reduced(&self, factor: f64) -> MohrCoulomb {
        let cohesion = self.cohesion / factor;
        let friction_angle = (self.friction_angle.tan() / factor).atan();
        let apex = if friction_angle > 0.0 { cohesion / friction_angle.tan() } else { f64::INFINITY };
        MohrCoulomb {
            cohesion,
            friction_angle,
            dilatancy_angle: self.dilatancy_angle.min(friction_angle),
            tensile_strength: self.tensile_strength.min(apex),
        }
    }
}

/// Where a stress point sits after its update.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum YieldState {
    #[default]
    Elastic,
    /// On the shear plane (one plane active).
    Shear,
    /// On an edge of the shear surface (two shear planes active: triaxial compression or extension).
    ShearEdge,
    /// On the tension cut-off, possibly with a shear plane.
    Tension,
    /// At the apex (three or more criteria meet).
    Apex,
    /// Below the strength, on a hardening soil's shear hardening surface.
    Hardening,
    /// Below the strength, on a hardening soil's cap (possibly with its shear hardening surface).
    Cap,
}

impl YieldState {
    /// The code written to the output: 0 elastic, 1 shear, 2 shear edge, 3 tension, 4 apex, 5
    /// hardening, 6 cap.
    pub fn code(self) -> u8 {
        match self {
            YieldState::Elastic => 0,
            YieldState::Shear => 1,
            YieldState::ShearEdge => 2,
            YieldState::Tension => 3,
            YieldState::Apex => 4,
            YieldState::Hardening => 5,
            YieldState::Cap => 6,
        }
    }

    /// The name written to the output.
    pub fn name(self) -> &'static str {
        match self {
            YieldState::Elastic => "elastic",
            YieldState::Shear => "shear",
            YieldState::ShearEdge => "shear-edge",
            YieldState::Tension => "tension",
            YieldState::Apex => "apex",
            YieldState::Hardening => "hardening",
            YieldState::Cap => "cap",
        }
    }

    pub fn is_plastic(self) -> bool {
        self != YieldState::Elastic
    }
}

/// The result of one stress update.
#[derive(Debug, Clone, Copy)]
pub struct StressUpdate {
    /// σxx, σyy, τxy, σzz.
    pub stress: [f64; 4],
    /// dσ/dε: rows σxx, σyy, τxy, σzz; columns εxx, εyy, γxy, εzz (εzz = 0 in plane strain, the
    /// hoop strain in axisymmetry).
    pub tangent: Matrix4<f64>,
    pub state: YieldState,
    /// Increment of the equivalent plastic strain √(2/3·Δεᵖ:Δεᵖ).
    pub plastic_strain: f64,
}

/// The six criteria in sorted principal space (σ1 ≥ σ2 ≥ σ3): three shear planes (pairs 1–3, 2–3
/// and 1–2) and three tension planes. Each is (gradient a, flow b, constant k): f = a·σ − k.
struct Planes {
    planes: [(Vector3<f64>, Vector3<f64>, f64, bool); 6],
}

impl Planes {
    fn new(m: &MohrCoulomb) -> Planes {
        let (sf, cf) = m.friction_angle.sin_cos();
        let sp = m.dilatancy_angle.sin();
        let k = 2.0 * m.cohesion * cf;
        let pair = |i: usize, j: usize, s: f64| {
            let mut v = Vector3::zeros();
            v[i] = 1.0 + s;
            v[j] = -(1.0 - s);
            v
        };
        let unit = |i: usize| {
            let mut v = Vector3::zeros();
            v[i] = 1.0;
            v
        };
        let t = m.tensile_strength;
        Planes {
            planes: [
                (pair(0, 2, sf), pair(0, 2, sp), k, true),
                (unit(0), unit(0), t, false),
                (pair(1, 2, sf), pair(1, 2, sp), k, true),
                (pair(0, 1, sf), pair(0, 1, sp), k, true),
                (unit(1), unit(1), t, false),
                (unit(2), unit(2), t, false),
            ],
        }
    }
}

/// Every shear pair and every tension plane satisfied (principal values in any order).
fn admissible(m: &MohrCoulomb, s: &Vector3<f64>, tol: f64) -> bool {
    let (sf, cf) = m.friction_angle.sin_cos();
    let k = 2.0 * m.cohesion * cf;
    for i in 0..3 {
        if s[i] - m.tensile_strength > tol {
            return false;
        }
        for j in 0..3 {
            if i != j && (1.0 + sf) * s[i] - (1.0 - sf) * s[j] - k > tol {
                return false;
            }
        }
    }
    true
}

/// Isotropic elasticity in principal axes (plane strain: εzz is a principal strain held at zero by
/// the kinematics, not by the law).
fn principal_elasticity(e: &PlaneStrain) -> Matrix3<f64> {
    let (lambda, mu) = lame(e);
    Matrix3::from_fn(|i, j| lambda + if i == j { 2.0 * mu } else { 0.0 })
}

fn lame(e: &PlaneStrain) -> (f64, f64) {
    let (young, nu) = (e.youngs_modulus, e.poissons_ratio);
    (young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), young / (2.0 * (1.0 + nu)))
}

/// The elastic trial stress: committed stress plus D·Δε for Δε = (εxx, εyy, γxy, εzz) (εzz = 0 in
/// plane strain, so σzz grows by λ·tr Δε; the hoop strain in axisymmetry).
pub fn trial_stress(elastic: &PlaneStrain, committed: [f64; 4], d_strain: [f64; 4]) -> [f64; 4] {
    let (lambda, mu) = lame(elastic);
    let tr = d_strain[0] + d_strain[1] + d_strain[3];
    [
        committed[0] + lambda * tr + 2.0 * mu * d_strain[0],
        committed[1] + lambda * tr + 2.0 * mu * d_strain[1],
        committed[2] + mu * d_strain[2],
        committed[3] + lambda * tr + 2.0 * mu * d_strain[3],
    ]
}

/// The candidate active sets, fewest planes first, in the order of the `Planes` list (the 1–3 shear
/// plane, then tension, then the edges and corners): made once.
fn candidate_sets() -> &'static [Vec<usize>] {
    static SETS: std::sync::OnceLock<Vec<Vec<usize>>> = std::sync::OnceLock::new();
    SETS.get_or_init(|| {
        let mut sets = Vec::new();
        for a in 0..6 {
            sets.push(vec![a]);
        }
        for a in 0..6 {
            for b in a + 1..6 {
                sets.push(vec![a, b]);
            }
        }
        for a in 0..6 {
            for b in a + 1..6 {
                for c in b + 1..6 {
                    sets.push(vec![a, b, c]);
                }
            }
        }
        sets
    })
}

/// [`update_with_hoop`] in plane strain (εzz = 0).
pub fn update(law: &MohrCoulomb, elastic: &PlaneStrain, committed: [f64; 4], d_strain: [f64; 3]) -> StressUpdate {
    update_with_hoop(law, elastic, committed, [d_strain[0], d_strain[1], d_strain[2], 0.0])
}

/// Update the stress of one point for a strain increment `d_strain` (εxx, εyy, γxy, εzz) from its
/// committed stress, and give the consistent tangent. zz is a principal direction either way: the
/// out-of-plane axis of plane strain, or the hoop direction of an axisymmetric body.
///
/// One function of some 170 lines on purpose: the trial state in sorted principal axes, the search
/// over the sets of active planes, the plastic strain and the consistent tangent with its spin term
/// share every intermediate, and the steps follow the module's references in the order they are
/// written there; split, they would pass a dozen matrices between them.
pub fn update_with_hoop(
    law: &MohrCoulomb,
    elastic: &PlaneStrain,
    committed: [f64; 4],
    d_strain: [f64; 4],
) -> StressUpdate {
    let trial = trial_stress(elastic, committed, d_strain);
    let d = elastic.d_matrix_with_hoop();
    // In-plane principal stresses and directions of the trial stress.
    let centre = 0.5 * (trial[0] + trial[1]);
    let half = 0.5 * (trial[0] - trial[1]);
    let radius = (half * half + trial[2] * trial[2]).sqrt();
    let theta = 0.5 * trial[2].atan2(half);
    // principal values in axis order (a, b, z)
    let x = Vector3::new(centre + radius, centre - radius, trial[3]);
    let scale = x
        .amax()
        .max(law.cohesion.abs())
        .max(committed.iter().fold(0.0f64, |m, v| m.max(v.abs())))
        .max(f64::MIN_POSITIVE);
    let tol = 1e-12 * scale;
    if admissible(law, &x, tol) {
        return StressUpdate { stress: trial, tangent: d, state: YieldState::Elastic, plastic_strain: 0.0 };
    }
    // Sorted principal space: rank[axis] is the sorted position of each axis.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| x[j].total_cmp(&x[i]));
    let mut rank = [0usize; 3];
    for (position, &axis) in order.iter().enumerate() {
        rank[axis] = position;
    }
    let sorted = Vector3::new(x[order[0]], x[order[1]], x[order[2]]);
    let dp = principal_elasticity(elastic);
    let planes = Planes::new(law);
    // (returned principal stresses, J in sorted axes, active planes)
    let mut found: Option<(Vector3<f64>, Matrix3<f64>, Vec<usize>)> = None;
    for set in candidate_sets() {
        let n = set.len();
        if set.iter().any(|&i| !planes.planes[i].2.is_finite()) {
            continue; // no tension cut-off
        }
        // Aᵀ·D_p·B Δλ = f(trial), in the leading n×n block of a 3×3 system padded with the
        // identity (the padding leaves the block's inverse and determinant as they are)
        let mut g = Matrix3::identity();
        let mut rhs = Vector3::zeros();
        let mut g_max = 0.0f64;
        for (r, &i) in set.iter().enumerate() {
            let (a, _, k, _) = &planes.planes[i];
            rhs[r] = a.dot(&sorted) - k;
            for (c, &j) in set.iter().enumerate() {
                g[(r, c)] = a.dot(&(dp * planes.planes[j].1));
                g_max = g_max.max(g[(r, c)].abs());
            }
        }
        let Some(inverse) = g.try_inverse() else { continue };
        if !(inverse.amax().is_finite()) || g.determinant().abs() < 1e-12 * g_max.powi(n as i32) {
            continue;
        }
        let dl = inverse * rhs;
        if dl.iter().any(|l| !l.is_finite()) || dl.iter().any(|&l| l < -1e-12 * scale / g_max.max(f64::MIN_POSITIVE)) {
            continue;
        }
        let mut flow = Vector3::zeros();
        for (c, &j) in set.iter().enumerate() {
            flow += planes.planes[j].1 * dl[c];
        }
        let s = sorted - dp * flow;
        if !admissible(law, &s, 1e-9 * scale) {
            continue;
        }
        // J = I − D_p·B·(Aᵀ·D_p·B)⁻¹·Aᵀ (the padding's columns of D_p·B and rows of Aᵀ are zero)
        let mut db = Matrix3::zeros();
        let mut at = Matrix3::zeros();
        for (c, &j) in set.iter().enumerate() {
            let b = dp * planes.planes[j].1;
            for r in 0..3 {
                db[(r, c)] = b[r];
                at[(c, r)] = planes.planes[j].0[r];
            }
        }
        let j = Matrix3::identity() - db * inverse * at;
        found = Some((s, j, set.clone()));
        break;
    }
    let (sorted_new, j_sorted, set) = match found {
        Some(f) => f,
        None => {
            // No set of planes holds the stress (non-associated flow near the apex): return to the
            // apex itself, with a small stiffness so that the point is not a mechanism on its own.
            let apex = if law.friction_angle > 0.0 {
                (law.cohesion / law.friction_angle.tan()).min(law.tensile_strength)
            } else {
                law.tensile_strength
            };
            (Vector3::repeat(apex), Matrix3::identity() * 1e-6, vec![0, 2, 3])
        }
    };
    let state = if set.len() == 3 && set.iter().filter(|&&i| planes.planes[i].3).count() == 3 {
        YieldState::Apex
    } else if set.iter().any(|&i| !planes.planes[i].3) {
        if set.len() == 3 {
            YieldState::Apex
        } else {
            YieldState::Tension
        }
    } else if set.len() == 1 {
        YieldState::Shear
    } else {
        YieldState::ShearEdge
    };
    // Plastic strain increment in principal axes: D_p⁻¹·(trial − new).
    let dp_inv = dp.try_inverse().unwrap_or_else(Matrix3::zeros);
    let de_p = dp_inv * (sorted - sorted_new);
    let mean = de_p.sum() / 3.0;
    let dev2: f64 = de_p.iter().map(|e| (e - mean).powi(2)).sum::<f64>() + 3.0 * mean * mean;
    let plastic_strain = (2.0 / 3.0 * dev2).sqrt();
    // Back to axis order (a, b, z).
    let y = Vector3::new(sorted_new[rank[0]], sorted_new[rank[1]], sorted_new[rank[2]]);
    let j = Matrix3::from_fn(|r, c| j_sorted[(rank[r], rank[c])]);
    let (c, s) = (theta.cos(), theta.sin());
    // E_a = e_a⊗e_a, E_b = e_b⊗e_b in Voigt (xx, yy, xy) with e_a = (c, s), e_b = (−s, c).
    let ea = [c * c, s * s, c * s];
    let eb = [s * s, c * c, -c * s];
    let stress = [y[0] * ea[0] + y[1] * eb[0], y[0] * ea[1] + y[1] * eb[1], y[0] * ea[2] + y[1] * eb[2], y[2]];
    // Spin term: (y_a − y_b)/(x_a − x_b), or its limit when the in-plane values coincide.
    let spin = if (x[0] - x[1]).abs() > 1e-10 * scale { (y[0] - y[1]) / (x[0] - x[1]) } else { j[(0, 0)] - j[(0, 1)] };
    // M = dσ/dσ_trial on Voigt stress (xx, yy, xy, zz); columns are unit tensor perturbations.
    let mut m = nalgebra::Matrix4::zeros();
    for col in 0..4 {
        let mut dx = [[0.0; 2]; 2];
        let mut dzz = 0.0;
        match col {
            0 => dx[0][0] = 1.0,
            1 => dx[1][1] = 1.0,
            2 => {
                dx[0][1] = 1.0;
                dx[1][0] = 1.0;
            }
            _ => dzz = 1.0,
        }
        let va = [c, s];
        let vb = [-s, c];
        let quad = |u: [f64; 2], v: [f64; 2]| {
            u[0] * (dx[0][0] * v[0] + dx[0][1] * v[1]) + u[1] * (dx[1][0] * v[0] + dx[1][1] * v[1])
        };
        let dxp = Vector3::new(quad(va, va), quad(vb, vb), dzz);
        let dab = quad(va, vb);
        let dy = j * dxp;
        // e_a⊗e_b + e_b⊗e_a in Voigt: (2·c·(−s), 2·s·c, c·c − s·s)
        let cross = [-2.0 * c * s, 2.0 * c * s, c * c - s * s];
        for r in 0..3 {
            m[(r, col)] = dy[0] * ea[r] + dy[1] * eb[r] + spin * dab * cross[r];
        }
        m[(3, col)] = dy[2];
    }
    // dσ_trial/dε (Voigt stress ← εxx, εyy, γxy, εzz)
    let (lambda, mu) = lame(elastic);
    #[rustfmt::skip]
    let d4 = Matrix4::new(
        lambda + 2.0 * mu, lambda, 0.0, lambda,
        lambda, lambda + 2.0 * mu, 0.0, lambda,
        0.0, 0.0, mu, 0.0,
        lambda, lambda, 0.0, lambda + 2.0 * mu,
    );
    let tangent = m * d4;
    StressUpdate { stress, tangent, state, plastic_strain }
}

#[cfg(test)]
mod tests {
    //! Reference: the criteria themselves (the returned stress must lie on them, with the flow
    //! direction of the law) and a central-difference derivative of the update (the consistent
    //! tangent). Tresca limit: φ = 0, (σ1 − σ3)/2 = c_u (de Souza Neto et al. 2008 §6.2).
    use super::*;

    const ELASTIC: PlaneStrain = PlaneStrain { youngs_modulus: 3.0e4, poissons_ratio: 0.3 };

    fn law(c: f64, phi: f64, psi: f64) -> MohrCoulomb {
        let (phi, psi) = (phi.to_radians(), psi.to_radians());
        let apex = if phi > 0.0 { c / phi.tan() } else { f64::INFINITY };
        MohrCoulomb { cohesion: c, friction_angle: phi, dilatancy_angle: psi, tensile_strength: apex.min(1e30) }
    }

    fn principal(s: [f64; 4]) -> [f64; 3] {
        let c = 0.5 * (s[0] + s[1]);
        let r = (0.25 * (s[0] - s[1]).powi(2) + s[2] * s[2]).sqrt();
        let mut p = [c + r, c - r, s[3]];
        p.sort_by(|a, b| b.total_cmp(a));
        p
    }

    fn shear_f(m: &MohrCoulomb, s: [f64; 4]) -> f64 {
        let p = principal(s);
        let sf = m.friction_angle.sin();
        (1.0 + sf) * p[0] - (1.0 - sf) * p[2] - 2.0 * m.cohesion * m.friction_angle.cos()
    }

    fn check_tangent(m: &MohrCoulomb, committed: [f64; 4], de: [f64; 3], expect: YieldState) {
        let base = update(m, &ELASTIC, committed, de);
        assert_eq!(base.state, expect, "state for {committed:?} + {de:?}");
        let h = 1e-7 * de.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-9);
        for col in 0..3 {
            let mut plus = de;
            let mut minus = de;
            plus[col] += h;
            minus[col] -= h;
            let sp = update(m, &ELASTIC, committed, plus).stress;
            let sm = update(m, &ELASTIC, committed, minus).stress;
            for row in 0..3 {
                let fd = (sp[row] - sm[row]) / (2.0 * h);
                let an = base.tangent[(row, col)];
                let size = base.tangent.amax();
                assert!(
                    (fd - an).abs() < 1e-5 * size,
                    "{expect:?}: dσ{row}/dε{col}: analytic {an}, central difference {fd}"
                );
            }
        }
    }

    /// The 4 × 4 tangent of an axisymmetric point (εzz the hoop strain) against central differences,
    /// in shear, on an edge and at tension.
    #[test]
    fn tangent_with_the_hoop_strain_matches_central_differences() {
        let cases: [(MohrCoulomb, [f64; 4], [f64; 4]); 3] = [
            (law(5.0, 30.0, 10.0), [-50.0, -100.0, 10.0, -70.0], [2e-3, -3e-3, 1e-3, 1.5e-3]),
            (law(0.0, 35.0, 35.0), [-100.0, -100.0, 0.0, -100.0], [4e-3, -8e-3, 0.0, 4e-3]),
            (law(10.0, 25.0, 0.0), [-80.0, -40.0, 5.0, -60.0], [-1e-3, 4e-3, 2e-3, 3e-3]),
        ];
        for (m, committed, de) in cases {
            let base = update_with_hoop(&m, &ELASTIC, committed, de);
            assert!(base.state.is_plastic(), "{committed:?} + {de:?} stays elastic");
            let h = 1e-9;
            for col in 0..4 {
                let (mut plus, mut minus) = (de, de);
                plus[col] += h;
                minus[col] -= h;
                let sp = update_with_hoop(&m, &ELASTIC, committed, plus).stress;
                let sm = update_with_hoop(&m, &ELASTIC, committed, minus).stress;
                for row in 0..4 {
                    let fd = (sp[row] - sm[row]) / (2.0 * h);
                    let an = base.tangent[(row, col)];
                    assert!(
                        (fd - an).abs() < 1e-5 * base.tangent.amax().max(ELASTIC.youngs_modulus),
                        "{:?}: dσ{row}/dε{col}: analytic {an}, central difference {fd}",
                        base.state
                    );
                }
            }
            // and the returned stress lies on the surface
            let f = shear_f(&m, base.stress);
            assert!(f < 1e-9 * 100.0, "{:?}: f = {f}", base.state);
        }
    }

    #[test]
    fn elastic_inside_the_surface() {
        let m = law(10.0, 30.0, 0.0);
        let u = update(&m, &ELASTIC, [-100.0, -100.0, 0.0, -100.0], [1e-5, -1e-5, 0.0]);
        assert_eq!(u.state, YieldState::Elastic);
        assert!((u.tangent - ELASTIC.d_matrix_with_hoop()).amax() < 1e-9);
    }

    #[test]
    fn plane_return_lands_on_the_surface_with_the_consistent_tangent() {
        for (phi, psi) in [(30.0, 30.0), (30.0, 0.0), (35.0, 10.0)] {
            let m = law(5.0, phi, psi);
            let committed = [-50.0, -100.0, 10.0, -70.0];
            let de = [2e-3, -3e-3, 1e-3];
            let u = update(&m, &ELASTIC, committed, de);
            assert!(u.state.is_plastic());
            assert!(shear_f(&m, u.stress).abs() < 1e-9 * 100.0, "f = {}", shear_f(&m, u.stress));
            check_tangent(&m, committed, de, u.state);
        }
    }

    #[test]
    fn non_associated_tangent_is_unsymmetric() {
        let m = law(5.0, 30.0, 0.0);
        let u = update(&m, &ELASTIC, [-50.0, -100.0, 10.0, -70.0], [2e-3, -3e-3, 1e-3]);
        assert!((u.tangent - u.tangent.transpose()).amax() > 1e-3 * u.tangent.amax());
        let a = update(&law(5.0, 30.0, 30.0), &ELASTIC, [-50.0, -100.0, 10.0, -70.0], [2e-3, -3e-3, 1e-3]);
        assert!((a.tangent - a.tangent.transpose()).amax() < 1e-9 * a.tangent.amax());
    }

    #[test]
    fn tresca_limit_gives_the_undrained_strength() {
        let cu = 20.0;
        let m = law(cu, 0.0, 0.0);
        // simple shear far past yield
        let u = update(&m, &ELASTIC, [-100.0, -100.0, 0.0, -100.0], [0.0, 0.0, 0.05]);
        let p = principal(u.stress);
        assert!(((p[0] - p[2]) / 2.0 - cu).abs() < 1e-9 * cu);
        // pure shear: the in-plane radius equals c_u
        assert!((u.stress[2].abs() - cu).abs() < 1e-9 * cu);
        check_tangent(&m, [-100.0, -100.0, 0.0, -100.0], [0.0, 0.0, 0.05], YieldState::Shear);
    }

    #[test]
    fn edge_return_when_two_principal_stresses_meet() {
        // On the surface with σxx just above σzz (σ1 ≈ σ2 > σ3 = σyy), stretched in x: the
        // plane return alone would lower σ1 below σ2, so the stress must go to the edge σ1 = σ2.
        let m = law(0.0, 30.0, 0.0);
        let committed = [-99.5, -300.0, 0.0, -100.0];
        let de = [5e-4, 0.0, 0.0];
        let u = update(&m, &ELASTIC, committed, de);
        assert_eq!(u.state, YieldState::ShearEdge);
        let p = principal(u.stress);
        assert!((p[0] - p[1]).abs() < 1e-8 * p[2].abs(), "σ1 = σ2 on the edge: {p:?}");
        assert!(shear_f(&m, u.stress).abs() < 1e-8 * 100.0);
        check_tangent(&m, committed, de, YieldState::ShearEdge);
    }

    #[test]
    fn tension_cut_off_and_apex() {
        let mut m = law(30.0, 30.0, 0.0);
        m.tensile_strength = 2.0;
        // a mild pull in x: only σxx reaches the cut-off
        let u = update(&m, &ELASTIC, [0.0, -40.0, 0.0, -20.0], [1e-4, 0.0, 0.0]);
        assert_eq!(u.state, YieldState::Tension);
        assert!((principal(u.stress)[0] - 2.0).abs() < 1e-9);
        check_tangent(&m, [0.0, -40.0, 0.0, -20.0], [1e-4, 0.0, 0.0], YieldState::Tension);
        // in-plane extension: both in-plane stresses at the cut-off, σzz (held by εzz = 0) below it
        let u = update(&m, &ELASTIC, [0.0, 0.0, 0.0, 0.0], [1e-2, 1e-2, 0.0]);
        assert_eq!(u.state, YieldState::Tension);
        assert!((u.stress[0] - 2.0).abs() < 1e-9 && (u.stress[1] - 2.0).abs() < 1e-9, "{:?}", u.stress);
        assert!(u.stress[3] <= 2.0 + 1e-9);
        // cohesionless soil pulled apart ends at the stress-free apex
        let sand = law(0.0, 30.0, 0.0);
        let u = update(&sand, &ELASTIC, [-10.0, -10.0, 0.0, -10.0], [5e-3, 5e-3, 0.0]);
        assert!(u.stress.iter().all(|s| s.abs() < 1e-9), "{:?}", u.stress);
    }

    #[test]
    fn the_returned_stress_never_violates_a_criterion() {
        // a sweep of strain directions and sizes from a K0 state
        let mut m = law(3.0, 32.0, 2.0);
        m.tensile_strength = 1.0;
        let committed = [-30.0, -60.0, 0.0, -30.0];
        for i in 0..48 {
            let a = i as f64 * std::f64::consts::PI / 24.0;
            for size in [1e-4, 1e-3, 1e-2] {
                let de = [size * a.cos(), size * a.sin(), size * (2.0 * a).sin()];
                let u = update(&m, &ELASTIC, committed, de);
                let p = principal(u.stress);
                assert!(shear_f(&m, u.stress) < 1e-7 * 60.0, "shear violated at {de:?}: {p:?}");
                assert!(p[0] < 1.0 + 1e-7 * 60.0, "tension violated at {de:?}: {p:?}");
            }
        }
    }
}

#[cfg(test)]
mod sweep {
    use super::*;

    #[test]
    fn tangent_matches_central_differences_over_a_sweep() {
        let elastic = PlaneStrain { youngs_modulus: 3.0e4, poissons_ratio: 0.45 };
        let laws = [
            MohrCoulomb { cohesion: 100.0, friction_angle: 0.0, dilatancy_angle: 0.0, tensile_strength: f64::INFINITY },
            MohrCoulomb {
                cohesion: 5.0,
                friction_angle: 30f64.to_radians(),
                dilatancy_angle: 0.0,
                tensile_strength: 5.0 / 30f64.to_radians().tan(),
            },
        ];
        let mut failures = Vec::new();
        for law in &laws {
            for i in 0..60 {
                let a = i as f64 * 0.37;
                let committed = [-50.0 - 30.0 * a.sin(), -80.0 + 20.0 * a.cos(), 15.0 * (2.0 * a).sin(), -60.0];
                let de = [3e-3 * (1.3 * a).cos(), -4e-3 * (0.7 * a).sin(), 5e-3 * (1.9 * a).cos()];
                let base = update(law, &elastic, committed, de);
                if !base.state.is_plastic() {
                    continue;
                }
                let h = 1e-8;
                for col in 0..3 {
                    let (mut p, mut m) = (de, de);
                    p[col] += h;
                    m[col] -= h;
                    let (up, um) = (update(law, &elastic, committed, p), update(law, &elastic, committed, m));
                    if up.state != base.state || um.state != base.state {
                        continue;
                    }
                    for row in 0..3 {
                        let fd = (up.stress[row] - um.stress[row]) / (2.0 * h);
                        let an = base.tangent[(row, col)];
                        if (fd - an).abs() > 1e-5 * elastic.d_matrix().amax() {
                            failures.push(format!(
                                "{:?} {:?} {i} [{row},{col}] an {an} fd {fd}",
                                law.friction_angle, base.state
                            ));
                        }
                    }
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
}
