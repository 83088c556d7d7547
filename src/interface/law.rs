//! Tangential laws per face and per slave point (the paper's Fig. 2 and its variants).
//!
//! Every law is written on the slip s (relative tangential displacement, positive towards the slave
//! line's first node) and returns the shear stress τ that resists it:
//! - `Linear`: τ = Ks·s, no limit;
//! - `Coulomb`: elastic–perfectly plastic, τ = Ks·(s − s_p) with |τ| ≤ τp = c + σn·tan φ;
//! - `PeakResidual`: as Coulomb until the peak is passed, then |τ| ≤ τr = c_r + σn·tan φ_r;
//! - `Softening`: the strength falls linearly from τp to τr over a plastic slip `softening_slip`;
//! - `Hyperbolic`: the backbone τ = F(s) = Ks·s/(1 + Ks·|s|/τp) (initial slope Ks, asymptote τp),
//!   with Masing's rules on unloading and reloading: from the last reversal (s_r, τ_r) the curve is
//!   τ = τ_r + 2·F((s − s_r)/2) (the backbone at twice its scale); a curve that reaches the point
//!   where an earlier, enclosing curve was left continues on that curve, and the first curve joins
//!   the backbone at the mirror image of its reversal point (Masing 1926, with the extended rules of
//!   Pyke 1979 and Vucetic 1990: the memory of the open loops).
//!
//! Every other law unloads elastically with Ks from its current state and slides again at its
//! strength in the reversed direction; the plastic slip accumulated in either direction drives the
//! softening.
//!
//! σn = λ/ℓ is compression positive; a tensile σn gives the cohesion only (never a negative
//! strength).

/// A tangential law with checked parameters. Angles are stored as tangents.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ShearLaw {
    /// Multipliers in both directions: no slip.
    Tie,
    Linear {
        shear_stiffness: f64,
    },
    Coulomb {
        shear_stiffness: f64,
        cohesion: f64,
        tan_friction: f64,
    },
    PeakResidual {
        shear_stiffness: f64,
        cohesion: f64,
        tan_friction: f64,
        residual_cohesion: f64,
        residual_tan_friction: f64,
    },
    Softening {
        shear_stiffness: f64,
        cohesion: f64,
        tan_friction: f64,
        residual_cohesion: f64,
        residual_tan_friction: f64,
        softening_slip: f64,
    },
    Hyperbolic {
        shear_stiffness: f64,
        cohesion: f64,
        tan_friction: f64,
    },
}

/// The history of one point's tangential law, carried from increment to increment (and across a
/// re-association).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShearState {
    /// Accumulated slip s.
    pub slip: f64,
    /// Plastic slip s_p.
    pub plastic_slip: f64,
    /// Accumulated |Δs_p| (drives softening).
    pub plastic_path: f64,
    /// The peak has been passed: the strength is the residual one.
    pub post_peak: bool,
    /// Shear stress τ at the end of the last converged increment.
    pub tau: f64,
    /// The sign of the last change of slip (0 before any): a change against it is a reversal.
    pub direction: f64,
    /// The hyperbolic law's reversal points (s_r, τ_r) whose curves are still open, the outermost
    /// first (empty on the backbone): the current curve starts at the last.
    pub reversals: Vec<(f64, f64)>,
    /// The plastic slip of the face's passive bearing, when it has one ([`super::Bearing`]).
    pub bearing_slip: f64,
    /// The bearing part of `tau`.
    pub bearing_tau: f64,
}

/// The law evaluated at a trial slip.
#[derive(Debug, Clone, PartialEq)]
pub struct ShearResponse {
    pub tau: f64,
    /// dτ/ds at constant σn (0 while sliding on a perfectly plastic law).
    pub tangent: f64,
    /// dτ/dσn at constant slip (the friction coefficient while sliding; 0 while elastic): the
    /// coupling that makes the consistent tangent unsymmetric.
    pub d_tau_d_sigma: f64,
    /// The state this slip would leave.
    pub state: ShearState,
    /// The point is at its strength.
    pub sliding: bool,
}

impl ShearLaw {
    pub fn is_tie(&self) -> bool {
        matches!(self, ShearLaw::Tie)
    }

    pub fn name(&self) -> &'static str {
        match self {
            ShearLaw::Tie => "tie",
            ShearLaw::Linear { .. } => "linear",
            ShearLaw::Coulomb { .. } => "coulomb",
            ShearLaw::PeakResidual { .. } => "peak-residual",
            ShearLaw::Softening { .. } => "softening",
            ShearLaw::Hyperbolic { .. } => "hyperbolic",
        }
    }

    /// Whether the law's strength grows with the normal stress (some friction coefficient is not
    /// zero): then the consistent tangent couples τ to σn, and the matrix is unsymmetric.
    pub fn is_frictional(&self) -> bool {
        match self {
            ShearLaw::Tie | ShearLaw::Linear { .. } => false,
            ShearLaw::Coulomb { tan_friction, .. } | ShearLaw::Hyperbolic { tan_friction, .. } => *tan_friction != 0.0,
            ShearLaw::PeakResidual { tan_friction, residual_tan_friction, .. }
            | ShearLaw::Softening { tan_friction, residual_tan_friction, .. } => {
                *tan_friction != 0.0 || *residual_tan_friction != 0.0
            }
        }
    }

    /// The law with its strengths divided by `factor` (c/F and tan φ/F, peak and residual alike),
    /// for the factor of safety by strength reduction. `tie` and `linear` have no strength.
    pub fn reduced(&self, factor: f64) -> ShearLaw {
        let mut law = self.clone();
        match &mut law {
            ShearLaw::Tie | ShearLaw::Linear { .. } => {}
            ShearLaw::Coulomb { cohesion, tan_friction, .. } | ShearLaw::Hyperbolic { cohesion, tan_friction, .. } => {
                *cohesion /= factor;
                *tan_friction /= factor;
            }
            ShearLaw::PeakResidual { cohesion, tan_friction, residual_cohesion, residual_tan_friction, .. }
            | ShearLaw::Softening { cohesion, tan_friction, residual_cohesion, residual_tan_friction, .. } => {
                *cohesion /= factor;
                *tan_friction /= factor;
                *residual_cohesion /= factor;
                *residual_tan_friction /= factor;
            }
        }
        law
    }

    /// Ks per face, the initial slope of every law but `tie`.
    pub fn shear_stiffness(&self) -> Option<f64> {
        match self {
            ShearLaw::Tie => None,
            ShearLaw::Linear { shear_stiffness }
            | ShearLaw::Coulomb { shear_stiffness, .. }
            | ShearLaw::PeakResidual { shear_stiffness, .. }
            | ShearLaw::Softening { shear_stiffness, .. }
            | ShearLaw::Hyperbolic { shear_stiffness, .. } => Some(*shear_stiffness),
        }
    }

    /// Peak strength τp = c + σn·tan φ (never negative), or ∞ for a law without one.
    pub fn peak_strength(&self, sigma_n: f64) -> f64 {
        let s = sigma_n.max(0.0);
        match self {
            ShearLaw::Tie | ShearLaw::Linear { .. } => f64::INFINITY,
            ShearLaw::Coulomb { cohesion, tan_friction, .. }
            | ShearLaw::PeakResidual { cohesion, tan_friction, .. }
            | ShearLaw::Softening { cohesion, tan_friction, .. }
            | ShearLaw::Hyperbolic { cohesion, tan_friction, .. } => cohesion + s * tan_friction,
        }
    }

    /// Residual strength τr = c_r + σn·tan φ_r (the peak one for laws without a residual).
    pub fn residual_strength(&self, sigma_n: f64) -> f64 {
        let s = sigma_n.max(0.0);
        match self {
            ShearLaw::PeakResidual { residual_cohesion, residual_tan_friction, .. }
            | ShearLaw::Softening { residual_cohesion, residual_tan_friction, .. } => {
                residual_cohesion + s * residual_tan_friction
            }
            other => other.peak_strength(sigma_n),
        }
    }

    /// Evaluate the law at total slip `slip` from the committed state, with normal stress `sigma_n`.
    pub fn response(&self, committed: &ShearState, slip: f64, sigma_n: f64) -> ShearResponse {
        let Some(ks) = self.shear_stiffness() else {
            return ShearResponse {
                tau: 0.0,
                tangent: 0.0,
                d_tau_d_sigma: 0.0,
                state: committed.clone(),
                sliding: false,
            };
        };
        let mut state = committed.clone();
        state.slip = slip;
        let elastic = slip - committed.plastic_slip;
        match self {
            ShearLaw::Linear { .. } => {
                state.tau = ks * slip;
                ShearResponse { tau: state.tau, tangent: ks, d_tau_d_sigma: 0.0, state, sliding: false }
            }
            ShearLaw::Hyperbolic { tan_friction, .. } => {
                let tf = self.peak_strength(sigma_n).max(f64::MIN_POSITIVE);
                let tan_phi = if sigma_n > 0.0 { *tan_friction } else { 0.0 };
                let change = slip - committed.slip;
                let direction = if change == 0.0 { committed.direction } else { change.signum() };
                state.direction = direction;
                // against the last change of slip, the committed state is a reversal point
                if committed.direction != 0.0 && direction == -committed.direction {
                    state.reversals.push((committed.slip, committed.tau));
                }
                // curves closed by this slip: past the reversal point where the enclosing curve was
                // left, the current curve joins that one (it passes through the point, by Masing's
                // rule); past the mirror image (−s_r) of the first reversal, the backbone
                loop {
                    let n = state.reversals.len();
                    let closes_at = match n {
                        0 => break,
                        1 => -state.reversals[0].0,
                        _ => state.reversals[n - 2].0,
                    };
                    if direction * (slip - closes_at) > 0.0 {
                        state.reversals.truncate(n.saturating_sub(2));
                    } else {
                        break;
                    }
                }
                let r = match state.reversals.last() {
                    None => hyperbola(ks, tf, tan_phi, slip, 1.0),
                    Some(&(s_r, tau_r)) => {
                        let (t, slope, coupling) = hyperbola(ks, tf, tan_phi, slip - s_r, 2.0);
                        (tau_r + t, slope, coupling)
                    }
                };
                state.tau = r.0;
                ShearResponse { tau: r.0, tangent: r.1, d_tau_d_sigma: r.2, state, sliding: false }
            }
            _ => {
                let trial = ks * elastic;
                let strength = self.current_strength(committed, sigma_n);
                if trial.abs() <= strength {
                    state.tau = trial;
                    return ShearResponse { tau: trial, tangent: ks, d_tau_d_sigma: 0.0, state, sliding: false };
                }
                let sign = trial.signum();
                let (tau_abs, tangent) = match self {
                    ShearLaw::Coulomb { .. } => (strength, 0.0),
                    ShearLaw::PeakResidual { .. } => {
                        // Passing the peak drops the strength to the residual (the paper's Fig. 2).
                        // Sliding at no strength at all (no adhesion, no normal stress: a sheet laid
                        // before anything bears on it) passes no peak.
                        state.post_peak = self.peak_strength(sigma_n) > 0.0;
                        (self.residual_strength(sigma_n), 0.0)
                    }
                    ShearLaw::Softening { softening_slip, .. } => {
                        let (tp, tr) = (self.peak_strength(sigma_n), self.residual_strength(sigma_n));
                        let h = (tp - tr) / softening_slip; // strength lost per unit plastic slip
                        let kappa = committed.plastic_path;
                        // |trial| − Ks·Δκ = tp − h·(κ + Δκ), while κ + Δκ < softening_slip
                        let dk = if ks > h { (trial.abs() - tp + h * kappa) / (ks - h) } else { f64::INFINITY };
                        if kappa + dk < *softening_slip {
                            state.post_peak = kappa + dk > 0.0;
                            (tp - h * (kappa + dk), -h * ks / (ks - h))
                        } else {
                            state.post_peak = true;
                            (tr, 0.0)
                        }
                    }
                    _ => (strength, 0.0),
                };
                let tau = sign * tau_abs.max(0.0);
                let new_plastic = slip - tau / ks;
                state.plastic_path = committed.plastic_path + (new_plastic - committed.plastic_slip).abs();
                state.plastic_slip = new_plastic;
                state.tau = tau;
                // the strength the point slides on grows with σn by its friction coefficient
                let friction = if sigma_n <= 0.0 {
                    0.0
                } else {
                    match self {
                        ShearLaw::Coulomb { tan_friction, .. } => *tan_friction,
                        ShearLaw::PeakResidual { residual_tan_friction, .. } => *residual_tan_friction,
                        ShearLaw::Softening { tan_friction, residual_tan_friction, softening_slip, .. } => {
                            let f = (state.plastic_path / softening_slip).min(1.0);
                            tan_friction - (tan_friction - residual_tan_friction) * f
                        }
                        _ => 0.0,
                    }
                };
                ShearResponse { tau, tangent, d_tau_d_sigma: sign * friction, state, sliding: true }
            }
        }
    }

    /// The strength that limits the committed state (peak, residual, or on the softening branch).
    fn current_strength(&self, committed: &ShearState, sigma_n: f64) -> f64 {
        match self {
            ShearLaw::PeakResidual { .. } if committed.post_peak => self.residual_strength(sigma_n),
            ShearLaw::Softening { softening_slip, .. } => {
                let (tp, tr) = (self.peak_strength(sigma_n), self.residual_strength(sigma_n));
                let f = (committed.plastic_path / softening_slip).min(1.0);
                tp - (tp - tr) * f
            }
            _ => self.peak_strength(sigma_n),
        }
    }
}

/// The hyperbola at `scale` times the backbone's size, τ = scale·F(x/scale) = Ks·x/(1 + Ks·|x|/(scale·τf)),
/// with its slope and its derivative with respect to σn (τf = c + σn·tan φ): (τ, dτ/dx, ∂τ/∂σn).
fn hyperbola(ks: f64, tf: f64, tan_phi: f64, x: f64, scale: f64) -> (f64, f64, f64) {
    let d = 1.0 + ks * x.abs() / (scale * tf);
    // ∂τ/∂τf = scale·(Ks·x/span)·(Ks·|x|/span), span = scale·τf + Ks·|x|: as two factors of
    // magnitude at most 1, so that x = 0 at τf = 0 (no adhesion, no normal stress) gives 0, not 0/0
    let (ke, span) = (ks * x, scale * tf + ks * x.abs());
    (ks * x / d, ks / (d * d), tan_phi * scale * (ke / span) * (ke.abs() / span))
}

#[cfg(test)]
mod tests {
    //! The laws of the paper's Fig. 2 and their variants, point by point.
    use super::*;

    const KS: f64 = 100.0;

    #[test]
    fn coulomb_is_elastic_then_perfectly_plastic_and_unloads_elastically() {
        let law = ShearLaw::Coulomb { shear_stiffness: KS, cohesion: 2.0, tan_friction: 0.5 };
        // σn = 10: τp = 2 + 5 = 7, reached at s = 0.07
        let s0 = ShearState::default();
        let r = law.response(&s0, 0.05, 10.0);
        assert!((r.tau - 5.0).abs() < 1e-12 && !r.sliding);
        let r = law.response(&s0, 0.2, 10.0);
        assert!((r.tau - 7.0).abs() < 1e-12 && r.sliding && r.tangent == 0.0);
        assert!((r.state.plastic_slip - 0.13).abs() < 1e-12);
        // unloading from s = 0.2 by 0.01 takes Ks·0.01 off
        let u = law.response(&r.state, 0.19, 10.0);
        assert!((u.tau - 6.0).abs() < 1e-12 && !u.sliding);
        // a tensile σn leaves the cohesion only
        assert!((law.response(&s0, 1.0, -3.0).tau - 2.0).abs() < 1e-12);
    }

    #[test]
    fn peak_residual_drops_to_the_residual_once_the_peak_is_passed() {
        let law = ShearLaw::PeakResidual {
            shear_stiffness: KS,
            cohesion: 4.0,
            tan_friction: 0.0,
            residual_cohesion: 2.0,
            residual_tan_friction: 0.0,
        };
        let s0 = ShearState::default();
        assert!((law.response(&s0, 0.039, 0.0).tau - 3.9).abs() < 1e-12);
        let r = law.response(&s0, 0.05, 0.0);
        assert!(r.state.post_peak && (r.tau - 2.0).abs() < 1e-12);
        // it stays at the residual when reloaded
        let again = law.response(&r.state, 0.5, 0.0);
        assert!((again.tau - 2.0).abs() < 1e-12);
    }

    #[test]
    fn softening_reaches_the_residual_after_the_softening_slip() {
        let law = ShearLaw::Softening {
            shear_stiffness: KS,
            cohesion: 4.0,
            tan_friction: 0.0,
            residual_cohesion: 2.0,
            residual_tan_friction: 0.0,
            softening_slip: 0.1,
        };
        let s0 = ShearState::default();
        // on the softening branch τ = 4 − 20·κ with κ = s − τ/Ks: at s = 0.1, κ = 0.075, τ = 2.5
        let r = law.response(&s0, 0.1, 0.0);
        assert!((r.tau - 2.5).abs() < 1e-12 && (r.state.plastic_path - 0.075).abs() < 1e-12, "{r:?}");
        let far = law.response(&s0, 1.0, 0.0);
        assert!((far.tau - 2.0).abs() < 1e-12 && far.state.post_peak);
    }

    #[test]
    fn hyperbolic_without_strength_at_no_slip_is_finite() {
        // no adhesion and no normal stress: τf = 0, and at e = 0 the slope and the coupling are 0/0
        // in the textbook form; the law must give finite numbers (τ = 0, ∂τ/∂σn = 0)
        let law = ShearLaw::Hyperbolic { shear_stiffness: KS, cohesion: 0.0, tan_friction: 0.5 };
        for sigma_n in [0.0, -1.0, 1e-300] {
            let r = law.response(&ShearState::default(), 0.0, sigma_n);
            assert!(r.tau == 0.0 && r.d_tau_d_sigma == 0.0 && r.tangent.is_finite(), "{sigma_n}: {r:?}");
        }
    }

    #[test]
    fn hyperbolic_starts_at_ks_and_tends_to_the_peak() {
        let law = ShearLaw::Hyperbolic { shear_stiffness: KS, cohesion: 5.0, tan_friction: 0.0 };
        let s0 = ShearState::default();
        let r = law.response(&s0, 1e-9, 0.0);
        assert!((r.tangent - KS).abs() < 1e-3);
        let big = law.response(&s0, 1e3, 0.0);
        assert!(big.tau < 5.0 && big.tau > 4.99);
        // τ(s = τp/Ks) = τp/2
        assert!((law.response(&s0, 0.05, 0.0).tau - 2.5).abs() < 1e-12);
    }
}
