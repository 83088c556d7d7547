//! The two-wedge factor of safety of a veneer cover (docs/verification.md §7.2, Koerner & Soong
//! 1998), written from the document, for the tests that compare a strength reduction with it.

/// A cover of unit weight `gamma` and thickness `h` (normal to the slope), cohesion `c` and friction
/// angle `phi` [°], on a slope of `beta` [°] whose two-wedge length is `length`, sliding on a liner
/// interface of friction `phi_i` [°] with no adhesion, pulled up the slope by a geosynthetic force
/// `t`: the root of A·FS² + B·FS + C₀ = 0.
pub struct Cover {
    pub gamma: f64,
    pub h: f64,
    pub c: f64,
    pub phi: f64,
}

impl Cover {
    pub fn factor_of_safety(&self, beta: f64, length: f64, phi_i: f64, t: f64) -> f64 {
        let Cover { gamma, h, c, phi } = *self;
        let b = beta.to_radians();
        let (sb, cb) = (b.sin(), b.cos());
        let w_a = gamma * h * h * (length / h - 1.0 / sb - b.tan() / 2.0);
        let n_a = w_a * cb;
        let w_p = gamma * h * h / (2.0 * b).sin();
        let (tan_phi, tan_phi_i) = (phi.to_radians().tan(), phi_i.to_radians().tan());
        let x = w_a - n_a * cb - t * sb;
        let a = x * cb;
        let bq = -(x * sb * tan_phi + n_a * tan_phi_i * sb * cb + sb * (c * h / sb + w_p * tan_phi));
        let c0 = n_a * tan_phi_i * sb * sb * tan_phi;
        (-bq + (bq * bq - 4.0 * a * c0).sqrt()) / (2.0 * a)
    }
}
