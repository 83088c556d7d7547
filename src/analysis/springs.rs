//! The interface springs' shear laws evaluated at an iterate: each point's slip since the last
//! converged increment, its normal stress (current, or frozen at the start of the stage, less the
//! pore pressure), and the law's response.

use super::soil;
use super::state::State;
use crate::interface::reassociate::clip_tributaries;
use crate::interface::rows::{InterfaceRows, Spring};
use crate::interface::{Dilation, MultiplierRef, NormalState, ShearResponse, ShearState};
use crate::model::{Model, ReassociationRule};

/// The interfaces at one iterate: the rows of the current association, every spring's law
/// evaluated there, and the normal rows of dilating faces held open by their opening.
pub struct InterfaceIterate {
    pub rows: InterfaceRows,
    pub springs: Vec<SpringResult>,
}

impl InterfaceIterate {
    /// The interfaces of `state` at its displacements, with the multipliers of `multipliers`.
    pub fn at(model: &Model, state: &State, multipliers: &[MultiplierRef]) -> Self {
        let mut rows = InterfaceRows::new(&model.mesh, &state.interfaces, multipliers);
        let springs = evaluate(model, state, &rows);
        rows.dilate(springs.iter().map(|r| r.dilation));
        InterfaceIterate { rows, springs }
    }

    /// The interfaces at the current iterate, each tributary length first clipped to the part of
    /// its slave line that still faces the master face (under large slip: the embedded length
    /// changes as the slave slides, and the resistance follows it within the increment).
    pub fn clipped(model: &Model, rule: ReassociationRule, state: &mut State, multipliers: &[MultiplierRef]) -> Self {
        if rule != ReassociationRule::None {
            clip_tributaries(&model.mesh, &mut state.interfaces, &state.u);
        }
        Self::at(model, state, multipliers)
    }

    /// Each spring's shear stress τ, in `rows.springs` order.
    pub fn taus(&self) -> Vec<f64> {
        self.springs.iter().map(|r| r.tau).collect()
    }
}

/// One spring's law evaluated at the current iterate.
#[derive(Debug, Clone)]
pub struct SpringResult {
    pub interface: usize,
    pub face: usize,
    pub point: usize,
    pub response: ShearResponse,
    pub tau: f64,
    /// The total normal stress the law used (current, frozen, or a slit tip's neighbour's); the
    /// law itself takes it less the pore pressure.
    pub sigma_n: f64,
    pub sliding: bool,
    /// The passive bearing's part of `tau` (zero on a face without one).
    pub bearing: f64,
    /// The face's opening by dilatancy at this slip (zero on a face that does not dilate).
    pub dilation: f64,
    /// ∂d/∂s and ∂d/∂σn′ of that opening (zero while the point sticks, or at the largest dilation):
    /// the normal row's linearisation.
    pub dilation_rates: [f64; 2],
    /// The slope of the point's law from its current state while elastic: Ks, plus the bearing's
    /// τb,max/δb (the constant-stiffness scheme's spring).
    pub elastic_stiffness: f64,
}

/// σn = λ/ℓ of a spring's point (compression positive); a redundant row's force is carried by
/// another row, whose σn it shares; a point at a slit tip, in contact, takes its neighbour's
/// ([`crate::interface::ContactPoint::pressure_from`]).
///
/// A point of an embedded reinforcement takes the soil's normal stress across its segment
/// ([`soil::normal_stress_across`]): its row only holds it on the line, and carries about nothing.
/// That stress is the one of `State::soil_sigma_from` (or the last converged increment), settled
/// by passes over the increment (`equilibrium/settle.rs`).
pub fn normal_stress(model: &Model, state: &State, rows: &InterfaceRows, spring: &Spring) -> f64 {
    let face = &state.interfaces[spring.interface].faces[spring.face];
    let p = &face.points[spring.point];
    if let Some(embedding) = &face.embedded {
        if !p.in_contact() {
            return 0.0;
        }
        let n = face.normal(&model.mesh, p.segment);
        let hosts = &embedding.hosts[p.segment];
        let u = state.soil_sigma_from.as_deref().unwrap_or(&state.u_committed);
        return soil::normal_stress_across(model, &state.soil, u, hosts, n).unwrap_or(0.0);
    }
    if let Some(from) = p.pressure_from.filter(|_| p.in_contact()) {
        let neighbour = rows.springs.iter().find(|s| {
            (s.interface, s.face, s.point) == (spring.interface, spring.face, from)
                && state.interfaces[s.interface].faces[s.face].points[s.point].pressure_from.is_none()
        });
        if let Some(neighbour) = neighbour {
            return normal_stress(model, state, rows, neighbour);
        }
    }
    match &p.normal_state {
        NormalState::Active => state.lambda[spring.normal_multiplier] / spring.tributary.max(f64::MIN_POSITIVE),
        NormalState::Redundant { multiplier: Some(carrier), .. } => {
            let owner = rows.springs.iter().find(|s| s.normal_multiplier == *carrier);
            let l = owner.map(|s| s.tributary).unwrap_or(spring.tributary).max(f64::MIN_POSITIVE);
            state.lambda[*carrier].abs() / l
        }
        _ => 0.0,
    }
}

/// Evaluate every spring's law at the current displacements.
pub fn evaluate(model: &Model, state: &State, rows: &InterfaceRows) -> Vec<SpringResult> {
    rows.springs
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let interface = &state.interfaces[s.interface];
            let p = &interface.faces[s.face].points[s.point];
            let slip_increment: f64 = s.row.iter().map(|&(d, c)| c * (state.u[d] - state.u_committed[d])).sum();
            let slip = p.shear.slip + slip_increment;
            let sigma_n = match &state.frozen_sigma_n {
                Some(frozen) => frozen.get(k).copied().unwrap_or(0.0),
                None => normal_stress(model, state, rows, s),
            };
            // the strength acts on the effective normal stress σn′ = σn − p
            let effective = match &state.soil.water {
                Some(w) => {
                    let at = [s.position[0] + state.u[2 * s.slave], s.position[1] + state.u[2 * s.slave + 1]];
                    sigma_n - w.pressure(at)
                }
                None => sigma_n,
            };
            let face = &interface.faces[s.face];
            let mut elastic_stiffness = face.law.shear_stiffness().unwrap_or(0.0);
            let mut dilation_rates = [0.0; 2];
            let response = if p.in_contact() {
                let mut response = face.law.response(&p.shear, slip, effective);
                if let (Some(d), true) = (&face.dilation, response.sliding) {
                    dilation_rates =
                        dilation_rates_of(d, face.law.shear_stiffness().unwrap_or(0.0), &p.shear, &response);
                }
                response.state.bearing_tau = 0.0;
                if let Some(bearing) = &face.bearing {
                    // the members bear on top of the face's friction, from the same slip
                    let b = bearing.response(p.shear.bearing_slip, slip, effective);
                    response.tau += b.tau;
                    response.tangent += b.tangent;
                    response.d_tau_d_sigma += b.d_tau_d_sigma;
                    response.state.bearing_slip = b.plastic_slip;
                    response.state.bearing_tau = b.tau;
                    elastic_stiffness += bearing.stiffness(effective);
                }
                response
            } else {
                // Out of contact: no shear; the slip goes on accumulating and restarts elastic.
                let mut st = p.shear.clone();
                st.slip = slip;
                st.plastic_slip = slip;
                st.bearing_slip = slip;
                st.bearing_tau = 0.0;
                st.tau = 0.0;
                ShearResponse { tau: 0.0, tangent: 0.0, d_tau_d_sigma: 0.0, state: st, sliding: false }
            };
            let dilation = face.dilation.map_or(0.0, |d| d.opening(response.state.plastic_path));
            SpringResult {
                interface: s.interface,
                face: s.face,
                point: s.point,
                tau: response.tau,
                sliding: response.sliding,
                sigma_n,
                bearing: response.state.bearing_tau,
                dilation,
                dilation_rates,
                elastic_stiffness,
                response,
            }
        })
        .collect()
}

/// ∂d/∂s and ∂d/∂σn′ of a sliding point's opening d = tan ψ·κ below the largest dilation: κ grows by
/// the plastic slip's change |Δs_p|, and while sliding Δs_p = Δs − Δτ/Ks with Δτ = (∂τ/∂s)·Δs +
/// (∂τ/∂σn′)·Δσn′.
fn dilation_rates_of(d: &Dilation, ks: f64, committed: &ShearState, response: &ShearResponse) -> [f64; 2] {
    if ks <= 0.0 || d.opening(response.state.plastic_path) >= d.max {
        return [0.0; 2];
    }
    let change = response.state.plastic_slip - committed.plastic_slip;
    let sign = if change != 0.0 { change.signum() } else { response.tau.signum() };
    [d.tan_angle * sign * (1.0 - response.tangent / ks), -d.tan_angle * sign * response.d_tau_d_sigma / ks]
}

/// Store each spring's converged law state in its point.
pub fn commit(state: &mut State, springs: &[SpringResult]) {
    for r in springs {
        state.interfaces[r.interface].faces[r.face].points[r.point].shear = r.response.state.clone();
    }
}
