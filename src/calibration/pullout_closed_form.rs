//! The pull-out force of a Coulomb interface on a rigid soil at σn = the surcharge
//! (docs/verification.md §1–2), with the embedded length shortened as the reinforcement
//! leaves the soil through the front face.
//!
//! Of an embedded length L' with head displacement d: elastic up to u_y = τmax/Ks,
//! P = EA·α·tanh(αL')·d; then a slip front s_f from the head,
//! d = u_y + T_e·s_f/EA + n_f·τmax·s_f²/(2EA), T_e = (n_f·τmax/α)·tanh(α(L' − s_f)),
//! P = n_f·τmax·[s_f + tanh(α(L' − s_f))/α]; and n_f·τmax·L' once all of it slides. The material
//! point ξ* of the reinforcement that is at the front face has moved ξ* (u(ξ*) = ξ*); what lies in
//! front of it is out of the soil, carries P and stretches by P·ξ*/EA, so the head is at
//! u_h = ξ*·(1 + P/EA) with P that of the length L − ξ* at d = ξ*.

/// The reinforcement of a pull-out test.
#[derive(Debug, Clone, Copy)]
pub struct Reinforcement {
    /// Embedded length at the start [m].
    pub length: f64,
    /// EA [kN/m].
    pub axial_stiffness: f64,
    /// Faces in contact (n_f).
    pub faces: f64,
}

const BISECTIONS: usize = 80;

/// The x in [lo, hi] where the increasing `f` reaches `target`, by bisection.
fn bisect(f: impl Fn(f64) -> f64, target: f64, (mut lo, mut hi): (f64, f64)) -> f64 {
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// P of an embedded length `length` whose head moved `d`, with shear stiffness `ks` and strength
/// `tau_max` per face.
fn embedded_force(r: &Reinforcement, length: f64, ks: f64, tau_max: f64, d: f64) -> f64 {
    if d <= 0.0 || length <= 0.0 {
        return 0.0;
    }
    let (ea, nf) = (r.axial_stiffness, r.faces);
    let alpha = (nf * ks / ea).sqrt();
    if tau_max <= 0.0 {
        return 0.0;
    }
    let u_y = tau_max / ks;
    if d <= u_y {
        return ea * alpha * (alpha * length).tanh() * d;
    }
    let head = |s: f64| {
        let t_e = nf * tau_max / alpha * (alpha * (length - s)).tanh();
        u_y + t_e * s / ea + nf * tau_max * s * s / (2.0 * ea)
    };
    if d >= head(length) {
        return nf * tau_max * length;
    }
    let s = bisect(head, d, (0.0, length));
    nf * tau_max * (s + (alpha * (length - s)).tanh() / alpha)
}

/// The pull-out force at the head displacement `u_head` (a magnitude).
pub fn force(r: &Reinforcement, ks: f64, tau_max: f64, u_head: f64) -> f64 {
    let u_head = u_head.abs();
    if u_head == 0.0 {
        return 0.0;
    }
    // u_h(ξ*) = ξ*·(1 + P(ξ*)/EA) grows with ξ* ∈ [0, u_h]
    let head_of = |xi: f64| xi * (1.0 + embedded_force(r, r.length - xi, ks, tau_max, xi) / r.axial_stiffness);
    let xi = bisect(head_of, u_head, (0.0, u_head.min(r.length)));
    embedded_force(r, r.length - xi, ks, tau_max, xi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/verification.md §1's example: EA = 1000 kN/m, Ks = 2000 kPa/m, L = 1 m, n_f = 2: K = 1928.055
    /// kN/m per m, so P = 10 kN/m at d = 5.18657 mm (elastic: τmax large); and with the head pulled
    /// out of the soil, the stiffness of what is left, K(L − ξ), at the face's displacement ξ, where
    /// u_h = ξ·(1 + P/EA).
    #[test]
    fn the_elastic_head_stiffness_is_the_shear_lag_one() {
        let r = Reinforcement { length: 1.0, axial_stiffness: 1000.0, faces: 2.0 };
        assert!((embedded_force(&r, 1.0, 2000.0, 1e9, 5.18657e-3) - 10.0).abs() < 1e-4);
        let k = |l: f64| 1000.0 * 2.0 * (2.0 * l).tanh();
        let u_h = 5.18657e-3;
        let mut xi = u_h;
        for _ in 0..50 {
            xi = u_h / (1.0 + k(1.0 - xi) * xi / 1000.0);
        }
        let p = force(&r, 2000.0, 1e9, u_h);
        assert!((p - k(1.0 - xi) * xi).abs() < 1e-9, "{p} against {}", k(1.0 - xi) * xi);
    }

    #[test]
    fn a_sliding_nearly_rigid_bar_carries_two_tau_times_what_is_left_in_the_soil() {
        // §2, large slip: P = n_f·τmax·(L − u) for EA ≫ n_f·τmax·L
        let r = Reinforcement { length: 1.6, axial_stiffness: 1e9, faces: 2.0 };
        let tau = 20.0 * 30f64.to_radians().tan();
        for u in [0.01, 0.05, 0.2] {
            let p = force(&r, 2000.0, tau, u);
            let expected = 2.0 * tau * (1.6 - u);
            assert!((p - expected).abs() < 1e-6 * expected, "{u}: {p} vs {expected}");
        }
    }

    #[test]
    fn the_first_slip_and_the_progressive_branch_meet() {
        // §2: P_y = n_f·τmax·tanh(αL)/α at u_y, continuous across it
        let r = Reinforcement { length: 1.0, axial_stiffness: 1000.0, faces: 2.0 };
        let (ks, tau) = (2000.0, 10.0);
        let u_y = tau / ks;
        let below = embedded_force(&r, 1.0, ks, tau, u_y * (1.0 - 1e-9));
        let above = embedded_force(&r, 1.0, ks, tau, u_y * (1.0 + 1e-9));
        let p_y = 2.0 * tau * 2f64.tanh() / 2.0;
        assert!((below - p_y).abs() < 1e-6 && (above - p_y).abs() < 1e-6, "{below} {above} {p_y}");
    }
}
