//! Duncan–Chang hyperbolic soil in the E–B form of Duncan, Byrne, Wong & Mabry (1980): a stress-
//! dependent elasticity whose tangent moduli follow the hyperbola of a drained triaxial test, with
//! a stiffer unloading–reloading modulus and the Mohr–Coulomb strength as its limit.
//!
//! Compression positive in the formulas (σ1 the major, σ3 the minor principal stress, of the three;
//! the code keeps tension positive and turns signs where it reads them):
//!
//! ```text
//! Ei  = K·pa·(σ3/pa)^n                   initial tangent modulus (Janbu 1963)
//! Eur = Kur·pa·(σ3/pa)^n                 unloading–reloading modulus
//! φ   = φ0 − Δφ·log10(σ3/pa)
//! (σ1 − σ3)f = (2c·cos φ + 2σ3·sin φ)/(1 − sin φ)
//! SL  = (σ1 − σ3)/(σ1 − σ3)f             stress level, at most 1
//! Et  = (1 − Rf·SL)²·Ei                  tangent modulus in primary loading
//! B   = Kb·pa·(σ3/pa)^m,  E/3 ≤ B ≤ 17·E (0 ≤ ν ≤ 0.49)
//! ```
//!
//! Under constant σ3 these moduli integrate to the hyperbola
//! (σ1 − σ3) = ε1/(1/Ei + ε1·Rf/(σ1 − σ3)f) of Duncan & Chang (1970), up to (σ1 − σ3)f.
//!
//! **Loading criterion.** A point loads (Et) at the largest stress state SS = SL·(σ3/pa)^¼ it has
//! had, and unloads or reloads (Eur) below it (the stress-state function of Duncan et al. 1980).
//! geoslip passes from one modulus to the other over a band: E = Et at the largest state, Eur once
//! SS has dropped by [`RELOAD_BAND`] of it, linear in SS between. The modulus is then a continuous
//! function of the stresses, which Newton's method needs: with a sharp switch, a point whose stress
//! state sits at its largest switches between Et and Eur from one iteration to the next, and the
//! iteration cycles. (The band makes the first 1 % of an unloading, and the last 1 % of a
//! reloading, softer than Eur.)
//!
//! **Stress update.** The moduli change along the increment, so the strain increment is integrated
//! in equal substeps by the third-order Runge–Kutta method of Ralston, each changing the stress
//! elastically by about [`SUBSTEP`] of itself; a crossing of the loading criterion's band gets
//! [`BAND_SUBSTEPS`] over the whole band. The number of substeps x is not rounded: the update
//! blends ⌊x⌋ and ⌊x⌋ + 1 substeps, so that it is a continuous function of the strain (an
//! error-controlled partition, as in Sloan 1987, jumps as the strain changes, and Newton's
//! iteration then stalls at the size of the jumps). A substep that leaves the Mohr–Coulomb
//! surface of its σ3 is returned to it by the return map of [`super::mohr_coulomb`] with that
//! substep's mean elasticity: beyond the strength the soil is perfectly plastic, flowing with the
//! dilatancy angle ψ.
//!
//! **Tangent.** A point that ends an update on the strength gives the update's own derivative, by
//! forward differences. Below the strength the tangent is the moduli at the updated stress. The
//! update's derivative there made Newton's iteration of the triaxial test of
//! docs/verification.md §11 (tri6) converge to another equilibrium as the stress state crossed the
//! band: the modulus changes sixteenfold over 1 % of the stress state, the update is not monotone
//! in the strain there, and the reloaded curve came out 4·10⁻⁵ of strain off the hyperbola.
//!
//! **The floor of σ3.** σ3 enters the moduli and φ no smaller than [`CONFINEMENT_FLOOR`]·pa, so
//! that a point at the ground surface or in tension keeps a stiffness. The stress level is
//! measured against the Mohr–Coulomb limit at the point's true σ3, the limit the return map holds
//! the stress to, so that SL = 1 on the strength below the floor too (with the floored σ3 in it, a
//! point held on the strength near the surface had SL ≈ 0.7, its loading criterion was neutral
//! there, and two neighbouring strains could follow Et and Eur respectively).

use super::mohr_coulomb::{self, MohrCoulomb, StressUpdate, YieldState};
use super::solid::PlaneStrain;
use super::substeps;

/// A substep's elastic change of the stress, as a fraction of the stress (or of the whole change,
/// if larger).
pub const SUBSTEP: f64 = 0.01;
/// The substeps an update takes across the whole band of the loading criterion.
pub const BAND_SUBSTEPS: f64 = 64.0;
/// The largest stress ratio (σ1 − σ3)/(σ1 − σ3)f the loading criterion counts, for a trial stress
/// far beyond the strength (near the apex, where the strength vanishes).
const RATIO_CAP: f64 = 10.0;
/// The smallest σ3, as a fraction of pa, that the moduli see.
pub const CONFINEMENT_FLOOR: f64 = 0.01;
/// The drop of the stress state, as a fraction of its largest value, over which the modulus
/// passes from Et to Eur.
pub const RELOAD_BAND: f64 = 0.01;
/// The band is taken of a largest stress state no smaller than this (near an isotropic state).
pub const RELOAD_BAND_FLOOR: f64 = 0.1;
/// The bulk modulus's bounds in units of E: ν from 0 (B = E/3) to 0.49 (B = E/(3·(1 − 0.98))).
const BULK_MIN: f64 = 1.0 / 3.0;
const BULK_MAX: f64 = 1.0 / (3.0 * (1.0 - 2.0 * 0.49));

/// The parameters of a Duncan–Chang soil, by their usual names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuncanChang {
    /// K: the modulus number.
    pub modulus_number: f64,
    /// n: the modulus exponent.
    pub modulus_exponent: f64,
    /// Rf: the failure ratio (σ1 − σ3)f/(σ1 − σ3)ult, 0 < Rf < 1.
    pub failure_ratio: f64,
    /// Kb: the bulk modulus number.
    pub bulk_modulus_number: f64,
    /// m: the bulk modulus exponent.
    pub bulk_modulus_exponent: f64,
    /// Kur: the unloading–reloading modulus number.
    pub unloading_modulus_number: f64,
    /// c [stress].
    pub cohesion: f64,
    /// φ0 [rad]: the friction angle at σ3 = pa.
    pub friction_angle: f64,
    /// Δφ [rad]: the drop of φ for a tenfold σ3.
    pub friction_angle_drop: f64,
    /// ψ [rad]: the dilatancy angle of flow at failure.
    pub dilatancy_angle: f64,
    /// pa [stress]: atmospheric pressure in the model's units.
    pub atmospheric_pressure: f64,
}

/// One point's stress update: the stress, its tangent, the largest stress state so far, and the
/// moduli at the end without the plastic part.
#[derive(Debug, Clone, Copy)]
pub struct HyperbolicUpdate {
    pub update: StressUpdate,
    /// The largest stress state SS the point has had, this update included.
    pub stress_state_max: f64,
    /// The moduli at the updated stress, without the plastic part.
    pub elasticity: PlaneStrain,
}

/// Principal stresses (tension positive) of (σxx, σyy, τxy, σzz): the largest and the smallest of
/// the two in-plane values and σzz.
fn extreme_principal(s: &[f64; 4]) -> (f64, f64) {
    let centre = 0.5 * (s[0] + s[1]);
    let radius = (0.25 * (s[0] - s[1]).powi(2) + s[2] * s[2]).sqrt();
    let (a, b) = (centre + radius, centre - radius);
    (a.max(s[3]), b.min(s[3]))
}

impl DuncanChang {
    /// σ3 (compression positive) as the moduli see it: the minor principal stress, floored.
    pub fn confinement(&self, stress: &[f64; 4]) -> f64 {
        let (largest, _) = extreme_principal(stress);
        (-largest).max(CONFINEMENT_FLOOR * self.atmospheric_pressure)
    }

    /// φ at confinement `sigma_3` (floored): φ0 − Δφ·log10(σ3/pa), within [0, 89°].
    pub fn friction_angle_at(&self, sigma_3: f64) -> f64 {
        let phi = self.friction_angle - self.friction_angle_drop * (sigma_3 / self.atmospheric_pressure).log10();
        phi.clamp(0.0, 89f64.to_radians())
    }

    /// (σ1 − σ3)f at confinement `sigma_3`.
    pub fn strength(&self, sigma_3: f64) -> f64 {
        self.strength_with_friction_of(sigma_3, sigma_3)
    }

    /// (σ1 − σ3)f at confinement `sigma_3` (not floored: below zero in tension), with φ at the
    /// confinement `friction_of`.
    fn strength_with_friction_of(&self, sigma_3: f64, friction_of: f64) -> f64 {
        let (s, c) = self.friction_angle_at(friction_of).sin_cos();
        (2.0 * self.cohesion * c + 2.0 * sigma_3 * s) / (1.0 - s)
    }

    /// The stress level SL = (σ1 − σ3)/(σ1 − σ3)f, within [0, 1].
    pub fn stress_level(&self, stress: &[f64; 4]) -> f64 {
        self.stress_ratio(stress).min(1.0)
    }

    /// (σ1 − σ3)/(σ1 − σ3)f, above 1 for a stress beyond the strength (at most [`RATIO_CAP`]).
    /// The strength is the Mohr–Coulomb limit's at the point's own σ3, with φ at the floored one:
    /// the ratio is 1 exactly where the return map holds the stress, below the floor of σ3 too.
    fn stress_ratio(&self, stress: &[f64; 4]) -> f64 {
        let (largest, smallest) = extreme_principal(stress);
        let strength = self.strength_with_friction_of(-largest, self.confinement(stress)).max(0.0);
        ((largest - smallest) / strength.max(f64::MIN_POSITIVE)).min(RATIO_CAP)
    }

    /// The stress state SS = SL·(σ3/pa)^¼ of the loading criterion. A trial stress beyond the
    /// strength counts with its SL above 1, so that a step past failure counts as loading.
    pub fn stress_state(&self, stress: &[f64; 4]) -> f64 {
        self.stress_ratio(stress) * (self.confinement(stress) / self.atmospheric_pressure).powf(0.25)
    }

    /// Ei at confinement `sigma_3`.
    pub fn initial_modulus(&self, sigma_3: f64) -> f64 {
        let pa = self.atmospheric_pressure;
        self.modulus_number * pa * (sigma_3 / pa).powf(self.modulus_exponent)
    }

    /// Eur at confinement `sigma_3`.
    pub fn unloading_modulus(&self, sigma_3: f64) -> f64 {
        let pa = self.atmospheric_pressure;
        self.unloading_modulus_number * pa * (sigma_3 / pa).powf(self.modulus_exponent)
    }

    /// B at confinement `sigma_3`, before its bounds.
    pub fn bulk_modulus(&self, sigma_3: f64) -> f64 {
        let pa = self.atmospheric_pressure;
        self.bulk_modulus_number * pa * (sigma_3 / pa).powf(self.bulk_modulus_exponent)
    }

    /// The tangent elasticity at `stress` for a point whose largest stress state so far is
    /// `largest`: Et at its largest state, Eur below (1 − [`RELOAD_BAND`]) of it, and in between
    /// linear in the stress state; B within its bounds.
    pub fn moduli(&self, stress: &[f64; 4], largest: f64) -> PlaneStrain {
        let sigma_3 = self.confinement(stress);
        let primary = (1.0 - self.failure_ratio * self.stress_level(stress)).powi(2) * self.initial_modulus(sigma_3);
        let unloading = self.unloading_modulus(sigma_3);
        let band = RELOAD_BAND * largest.max(RELOAD_BAND_FLOOR);
        let below = (largest - self.stress_state(stress)) / band;
        let young = primary + (unloading - primary) * below.clamp(0.0, 1.0);
        let bulk = self.bulk_modulus(sigma_3).clamp(BULK_MIN * young, BULK_MAX * young);
        PlaneStrain { youngs_modulus: young, poissons_ratio: (3.0 * bulk - young) / (6.0 * bulk) }
    }

    /// The elasticity of a soil at rest under σ3 = pa, unloading: what the elastic predictor and a
    /// model's reference element matrices use.
    pub fn reference_elasticity(&self) -> PlaneStrain {
        let pa = self.atmospheric_pressure;
        self.moduli(&[-pa, -pa, 0.0, -pa], 1.0)
    }

    /// The Mohr–Coulomb limit at confinement `sigma_3`: c, φ(σ3), ψ (at most φ), and the tension
    /// cut-off at the apex.
    pub fn limit(&self, sigma_3: f64) -> MohrCoulomb {
        let phi = self.friction_angle_at(sigma_3);
        let apex = if phi > 0.0 { self.cohesion / phi.tan() } else { f64::INFINITY };
        MohrCoulomb {
            cohesion: self.cohesion,
            friction_angle: phi,
            dilatancy_angle: self.dilatancy_angle.min(phi),
            tensile_strength: apex,
        }
    }

    /// The law with c/F and tan φ0/F (strength reduction); ψ is kept unless it exceeds the
    /// reduced φ0.
    pub fn reduced(&self, factor: f64) -> DuncanChang {
        let friction_angle = (self.friction_angle.tan() / factor).atan();
        DuncanChang {
            cohesion: self.cohesion / factor,
            friction_angle,
            dilatancy_angle: self.dilatancy_angle.min(friction_angle),
            ..*self
        }
    }

    /// Update the stress of one point for the strain increment `d_strain` (εxx, εyy, γxy, εzz; εzz
    /// zero in plane strain, the hoop strain in axisymmetry) from its committed `stress`, with the
    /// largest stress state it has had (`stress_state_max`). See the module's notes for the method.
    /// With `differentiate`, the tangent is the update's own derivative by the strain (four more
    /// integrations, [`substeps::difference_tangent`]); without, it is the moduli at the new stress,
    /// or on the strength the Mohr–Coulomb return's tangent of the last substep.
    pub fn update(
        &self,
        stress: [f64; 4],
        stress_state_max: f64,
        d_strain: [f64; 4],
        differentiate: bool,
    ) -> HyperbolicUpdate {
        let start = Path {
            sigma: stress,
            largest: stress_state_max.max(self.stress_state(&stress)),
            plastic_strain: 0.0,
            last: None,
        };
        let path = self.integrate(&start, d_strain);
        let elasticity = self.moduli(&path.sigma, path.largest);
        let plastic = path.last.filter(|r| r.state.is_plastic());
        let tangent = match plastic {
            Some(_) if differentiate => {
                substeps::difference_tangent(d_strain, &path.sigma, |e| self.integrate(&start, e).sigma)
            }
            Some(returned) => returned.tangent,
            None => elasticity.d_matrix_with_hoop(),
        };
        let update = StressUpdate {
            stress: path.sigma,
            tangent,
            state: plastic.map_or(YieldState::Elastic, |r| r.state),
            plastic_strain: path.plastic_strain,
        };
        HyperbolicUpdate { update, stress_state_max: path.largest, elasticity }
    }

    /// Integrate the strain `d_strain` from `start` in equal substeps, each changing the stress
    /// elastically by about [`SUBSTEP`] of itself (or of the whole change, if larger: at most
    /// 1/[`SUBSTEP`] of them). Their number x is not rounded: the result blends ⌊x⌋ and ⌊x⌋ + 1
    /// substeps, so that it is a continuous function of the strain.
    fn integrate(&self, start: &Path, d_strain: [f64; 4]) -> Path {
        let pa = self.atmospheric_pressure;
        let elastic = self.moduli(&start.sigma, start.largest);
        let trial_change = mohr_coulomb::trial_stress(&elastic, [0.0; 4], d_strain);
        let elastic_change = trial_change.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale = start.sigma.iter().fold(CONFINEMENT_FLOOR * pa, |m, v| m.max(v.abs())).max(elastic_change);
        // the band of the loading criterion, where the modulus passes from Et to Eur over a small
        // change of the stress state, gets BAND_SUBSTEPS of its own: the part of it that the
        // elastic trial's stress state crosses (a length, continuous in the strain)
        let trial: [f64; 4] = std::array::from_fn(|i| start.sigma[i] + trial_change[i]);
        let (before, after) = (self.stress_state(&start.sigma), self.stress_state(&trial));
        let band = RELOAD_BAND * start.largest.max(RELOAD_BAND_FLOOR);
        let crossed = (before.max(after).min(start.largest) - before.min(after).max(start.largest - band)).max(0.0);
        let count = (elastic_change / scale / SUBSTEP).max(BAND_SUBSTEPS * crossed / band).max(1.0);
        substeps::blended(
            count,
            |n| self.integrate_in(start, d_strain, n),
            |coarse, fine, share| {
                let blend = |a: f64, b: f64| a + share * (b - a);
                Path {
                    sigma: std::array::from_fn(|i| blend(coarse.sigma[i], fine.sigma[i])),
                    largest: blend(coarse.largest, fine.largest),
                    plastic_strain: blend(coarse.plastic_strain, fine.plastic_strain),
                    last: fine.last,
                }
            },
        )
    }

    /// Integrate the strain `d_strain` from `start` in `substeps` equal substeps, each by the
    /// third-order Runge–Kutta method of Ralston and returned to the strength if it leaves it.
    fn integrate_in(&self, start: &Path, d_strain: [f64; 4], substeps: usize) -> Path {
        let mut path = *start;
        let de = d_strain.map(|e| e / substeps as f64);
        for _ in 0..substeps {
            let sigma = path.sigma;
            let rate = |s: &[f64; 4]| -> ([f64; 4], PlaneStrain) {
                let moduli = self.moduli(s, path.largest.max(self.stress_state(s)));
                (mohr_coulomb::trial_stress(&moduli, [0.0; 4], de), moduli)
            };
            let at = |k: &[(f64, &[f64; 4])]| -> [f64; 4] {
                std::array::from_fn(|i| sigma[i] + k.iter().map(|(c, d)| c * d[i]).sum::<f64>())
            };
            let (k1, first) = rate(&sigma);
            let (k2, _) = rate(&at(&[(0.5, &k1)]));
            let (k3, _) = rate(&at(&[(0.75, &k2)]));
            let next = at(&[(2.0 / 9.0, &k1), (1.0 / 3.0, &k2), (4.0 / 9.0, &k3)]);
            // the strength: a substep that leaves the surface goes back to it, with the substep's
            // mean elasticity
            let second = self.moduli(&next, path.largest.max(self.stress_state(&next)));
            let average = PlaneStrain {
                youngs_modulus: 0.5 * (first.youngs_modulus + second.youngs_modulus),
                poissons_ratio: 0.5 * (first.poissons_ratio + second.poissons_ratio),
            };
            let limit = self.limit(self.confinement(&sigma));
            let returned = mohr_coulomb::update_with_hoop(&limit, &average, next, [0.0; 4]);
            path.plastic_strain += returned.plastic_strain;
            path.sigma = returned.stress;
            path.largest = path.largest.max(self.stress_state(&path.sigma));
            path.last = Some(returned);
        }
        path
    }
}

/// A stress update on its way: the stress so far, the largest stress state so far, the plastic
/// strain and the last substep's return.
#[derive(Clone, Copy)]
struct Path {
    sigma: [f64; 4],
    largest: f64,
    plastic_strain: f64,
    last: Option<StressUpdate>,
}

#[cfg(test)]
mod tests {
    //! Reference: the hyperbola of Duncan & Chang (1970) under constant σ3,
    //! (σ1 − σ3) = ε1/(1/Ei + ε1·Rf/(σ1 − σ3)f), up to (σ1 − σ3)f; Δ(σ1 − σ3) = Eur·Δε1 on
    //! unloading; and Δεv = Δ(σ1 − σ3)/(3B) (docs/verification.md §11). One point
    //! of an axisymmetric body driven like a triaxial sample: εz given, εr = εθ found so that
    //! σr = σθ = −σ3.
    use super::*;

    fn sand(friction_angle_drop: f64) -> DuncanChang {
        DuncanChang {
            modulus_number: 500.0,
            modulus_exponent: 0.5,
            failure_ratio: 0.8,
            bulk_modulus_number: 300.0,
            bulk_modulus_exponent: 0.25,
            unloading_modulus_number: 1200.0,
            cohesion: 5.0,
            friction_angle: 36f64.to_radians(),
            friction_angle_drop: friction_angle_drop.to_radians(),
            dilatancy_angle: 0.0,
            atmospheric_pressure: 100.0,
        }
    }

    /// A triaxial point: its stress, its largest stress state, its axial strain (compression
    /// positive) and its radial strain (extension positive).
    struct Sample {
        stress: [f64; 4],
        ss_max: f64,
        axial: f64,
        radial: f64,
    }

    impl Sample {
        fn isotropic(sigma_3: f64) -> Sample {
            Sample { stress: [-sigma_3, -sigma_3, 0.0, -sigma_3], ss_max: 0.0, axial: 0.0, radial: 0.0 }
        }

        fn deviator(&self) -> f64 {
            self.stress[0] - self.stress[1]
        }

        /// Shorten the sample by `d_axial` (compression positive) in one update: the radial strain
        /// by regula falsi (σr rises with it) to 1e-13 of σ3.
        fn compress(&mut self, law: &DuncanChang, d_axial: f64) {
            let target = self.stress[0];
            let at = |er: f64| law.update(self.stress, self.ss_max, [er, -d_axial, 0.0, er], false);
            let residual = |er: f64| at(er).update.stress[0] - target;
            let er = crate::element::radial_strain_holding(residual, d_axial.abs(), 1e-13, target.abs());
            let next = at(er);
            self.stress = next.update.stress;
            self.ss_max = next.stress_state_max;
            self.axial += d_axial;
            self.radial += er;
        }
    }

    #[test]
    fn primary_loading_follows_the_hyperbola_at_three_confining_stresses() {
        let law = sand(4.0);
        let (mut worst, mut worst_volume) = (0.0f64, 0.0f64);
        for sigma_3 in [50.0, 200.0, 800.0] {
            let ei = law.initial_modulus(sigma_3);
            let qf = law.strength(sigma_3);
            let hyperbola = |e: f64| e / (1.0 / ei + e * law.failure_ratio / qf);
            let at_failure = qf / (ei * (1.0 - law.failure_ratio));
            let mut sample = Sample::isotropic(sigma_3);
            let step = at_failure / 400.0;
            for k in 1..=600 {
                sample.compress(&law, step);
                let expected = if sample.axial < at_failure { hyperbola(sample.axial) } else { qf };
                let q = sample.deviator();
                worst = worst.max((q - expected).abs() / qf);
                assert!((q - expected).abs() < 1e-5 * qf, "σ3 {sigma_3}, step {k}: q {q} against {expected}");
                assert!((sample.stress[0] + sigma_3).abs() < 1e-9 * sigma_3);
                assert!((sample.stress[3] + sigma_3).abs() < 1e-9 * sigma_3);
                if sample.axial < 0.9 * at_failure {
                    // volume: Δεv = Δp/B with Δp = q/3 (B within its bounds here)
                    let b = law.bulk_modulus(sigma_3);
                    assert!(b <= BULK_MAX * law.moduli(&sample.stress, sample.ss_max).youngs_modulus);
                    let volume = sample.axial - 2.0 * sample.radial;
                    let expected = q / (3.0 * b);
                    worst_volume = worst_volume.max((volume - expected).abs() / expected);
                    assert!(
                        (volume - expected).abs() < 3e-5 * expected,
                        "σ3 {sigma_3}, step {k}: εv {volume} against {expected}"
                    );
                }
            }
        }
        eprintln!(
            "largest error of the deviator: {worst:.2e} of its strength; of the volume strain: {worst_volume:.2e}"
        );
    }

    #[test]
    fn unloading_and_reloading_take_eur_and_rejoin_the_hyperbola() {
        let law = sand(0.0);
        let sigma_3 = 200.0;
        let (ei, qf) = (law.initial_modulus(sigma_3), law.strength(sigma_3));
        // the strain on the hyperbola at deviator q
        let strain_at = |q: f64| q / (ei * (1.0 - law.failure_ratio * q / qf));
        let mut sample = Sample::isotropic(sigma_3);
        for _ in 0..20 {
            sample.compress(&law, 1e-4);
        }
        // unloading: past the band (5 % of the stress state, here of q, in the first step), at Eur
        let eur = law.unloading_modulus(sigma_3);
        let mut deviators = Vec::new();
        for _ in 0..6 {
            sample.compress(&law, -1e-4);
            deviators.push(sample.deviator());
        }
        for w in deviators[1..].windows(2) {
            let slope = (w[0] - w[1]) / 1e-4;
            assert!((slope - eur).abs() < 1e-6 * eur, "unloading slope {slope} against Eur {eur}");
        }
        // reloading, past where unloading began: the hyperbola again. Along the same stress path
        // the moduli are the same both ways (the band's too: a function of the stress and of the
        // largest stress state, which does not change below it), so the path is reversible and
        // the reloaded curve rejoins the hyperbola where unloading left it: no offset in strain,
        // and the same at every point (dq/dε depends on q alone), to the integration's error
        // (measured 1.8·10⁻⁸ to 2.8·10⁻⁸, growing by about 10⁻⁹ a step)
        for _ in 0..12 {
            sample.compress(&law, 1e-4);
        }
        let mut offsets = Vec::new();
        for _ in 0..10 {
            sample.compress(&law, 1e-4);
            offsets.push(sample.axial - strain_at(sample.deviator()));
        }
        let (lo, hi) = offsets.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &o| (a.min(o), b.max(o)));
        eprintln!("reloaded curve's offset from the hyperbola: {lo:.3e} to {hi:.3e}");
        assert!(lo > -1e-7 && hi < 1e-7, "offsets {offsets:?}");
        assert!(hi - lo < 3e-8, "the reloaded curve is not the hyperbola: offsets {offsets:?}");
    }

    /// The backfill of examples/reinforced-wall made hyperbolic (docs/soil.md).
    fn wall_fill() -> DuncanChang {
        DuncanChang {
            modulus_number: 500.0,
            modulus_exponent: 0.5,
            failure_ratio: 0.75,
            bulk_modulus_number: 250.0,
            bulk_modulus_exponent: 0.25,
            unloading_modulus_number: 1000.0,
            cohesion: 1.0,
            friction_angle: 34f64.to_radians(),
            friction_angle_drop: 0.0,
            dilatancy_angle: 4f64.to_radians(),
            atmospheric_pressure: 101.325,
        }
    }

    /// Newton's method needs the update to be a continuous function of the strain: sampled along
    /// εxx in steps of 10⁻⁹, its largest change between neighbours is of the size of the others.
    /// A point of the hyperbolic wall with its lifts compacted (docs/soil.md, Limitations), in
    /// lift 5 as it stood in the iteration, on the strength with σ3 = 0.19 kPa, below the floor of
    /// σ3 (docs/verification.md §11): with the stress level measured against the strength at the
    /// floored σ3 it was 0.67 there, the loading criterion was neutral along the strength, and the
    /// update jumped by 0.17 kPa (1.8·10⁴ times the median change) between neighbouring strains
    /// that followed Et and Eur respectively.
    #[test]
    fn a_point_on_the_strength_below_the_floor_updates_continuously() {
        let law = wall_fill();
        let stress = [-1.9883225047553617, -2.618324647445352, -2.0934736004563326, -1.454262645052578];
        let (largest, d_strain) =
            (0.2114483273529356, [0.001290361166704881, -0.0004195394812919831, -0.012370906266717554, 0.0]);
        let updates: Vec<[f64; 4]> = (0..=100)
            .map(|k| {
                let mut e = d_strain;
                e[0] += 1e-9 * (k as f64 - 50.0);
                law.update(stress, largest, e, false).update.stress
            })
            .collect();
        let mut changes: Vec<f64> =
            updates.windows(2).map(|w| (0..4).map(|i| (w[1][i] - w[0][i]).abs()).fold(0.0, f64::max)).collect();
        changes.sort_by(f64::total_cmp);
        let ratio = changes[changes.len() - 1] / changes[changes.len() / 2];
        eprintln!("largest change against the median: {ratio:.3}");
        assert!(ratio < 3.0, "largest change against the median: {ratio}");
    }
}
