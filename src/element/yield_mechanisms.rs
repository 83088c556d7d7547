//! The yield mechanisms of a multi-surface soil law at one point, in principal stresses: the
//! principal stresses of a stress and their gradients, each mechanism's gradient and flow, and the
//! multipliers of those that load (with hardening shared within a family). Used by
//! [`super::hardening_soil`].

use nalgebra::{Matrix4, Vector4};

/// The width of a corner, as a fraction of the stress's size: two principal stresses closer than
/// this are a corner, where both of their orders are yield surfaces.
pub const CORNER: f64 = 1e-4;

/// The principal stresses of (σxx, σyy, τxy, σzz), compression positive and sorted (σ1 ≥ σ2 ≥ σ3),
/// with the gradient of each with respect to the tension-positive components.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Principal {
    pub(crate) values: [f64; 3],
    pub(crate) gradients: [Vector4<f64>; 3],
}

impl Principal {
    pub(crate) fn of(s: &[f64; 4]) -> Principal {
        let centre = 0.5 * (s[0] + s[1]);
        let half = 0.5 * (s[0] - s[1]);
        let radius = (half * half + s[2] * s[2]).sqrt();
        let (cos2, sin2) = if radius > 0.0 { (half / radius, s[2] / radius) } else { (1.0, 0.0) };
        // tension positive: λ+ = centre + radius, λ− = centre − radius, λz = σzz; compression
        // positive values are their negatives, and so are the gradients
        let plus = Vector4::new(-0.5 - 0.5 * cos2, -0.5 + 0.5 * cos2, -sin2, 0.0);
        let minus = Vector4::new(-0.5 + 0.5 * cos2, -0.5 - 0.5 * cos2, sin2, 0.0);
        let zz = Vector4::new(0.0, 0.0, 0.0, -1.0);
        let mut pairs = [(-(centre - radius), minus), (-(centre + radius), plus), (-s[3], zz)];
        pairs.sort_by(|a, b| b.0.total_cmp(&a.0));
        Principal { values: pairs.map(|p| p.0), gradients: pairs.map(|p| p.1) }
    }

    /// The gradient, with respect to the tension-positive components, of a function whose
    /// derivatives by σ1, σ2, σ3 are `d`.
    pub(crate) fn gradient(&self, d: [f64; 3]) -> Vector4<f64> {
        self.gradients[0] * d[0] + self.gradients[1] * d[1] + self.gradients[2] * d[2]
    }

    /// Whether principal stresses `a` and `b` (sorted indices) form a corner: within [`CORNER`] of
    /// the stress's size.
    pub(crate) fn corner(&self, a: usize, b: usize) -> bool {
        let scale = self.values.iter().fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()));
        (self.values[a] - self.values[b]).abs() <= CORNER * scale
    }
}

/// The family of a yield mechanism: the shear hardening surfaces share γp, the caps pp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Family {
    Shear,
    Cap,
}

/// One yield mechanism at a point: its gradient n, its flow m and its family.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mechanism {
    pub(crate) n: Vector4<f64>,
    pub(crate) m: Vector4<f64>,
    pub(crate) family: Family,
}

/// The mechanisms at a point: elasticity D; one shear hardening surface and one cap, or at a corner
/// two of each (one for each order of the two equal principal stresses, so that the corner is kept
/// as two active surfaces, Koiter's rule); the cap's hardening modulus (dpp per unit of the caps'
/// multipliers); and which surfaces the point is on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mechanisms {
    pub(crate) d: Matrix4<f64>,
    pub(crate) list: [Option<Mechanism>; 4],
    pub(crate) h_cap: f64,
    pub(crate) on: Surfaces,
}

impl Mechanisms {
    /// The multipliers of the `active` mechanisms for the elastic stress rate `elastic`, from the
    /// consistency of each: n·dσ = dγp = Σλ over the shear surfaces, n·dσ = dpp = H·Σλ over the caps.
    /// Inactive ones get zero.
    pub(crate) fn multipliers(&self, elastic: &Vector4<f64>, active: [bool; 4]) -> [f64; 4] {
        let mut a = Matrix4::identity();
        let mut b = Vector4::zeros();
        for (i, mi) in self.list.iter().enumerate() {
            let (Some(mi), true) = (mi, active[i]) else { continue };
            b[i] = mi.n.dot(elastic);
            for (j, mj) in self.list.iter().enumerate() {
                let (Some(mj), true) = (mj, active[j]) else { continue };
                let coupling = match (mi.family, mj.family) {
                    (Family::Shear, Family::Shear) => 1.0,
                    (Family::Cap, Family::Cap) => self.h_cap,
                    _ => 0.0,
                };
                a[(i, j)] = mi.n.dot(&(self.d * mj.m)) + coupling;
            }
        }
        // at a corner with both families loading, four mechanisms act in the three principal
        // directions: the system is singular along equal and opposite splits of each pair, and
        // the least-squares multipliers of least size split each pair evenly where the loading is
        // even
        let count = active.iter().filter(|a| **a).count();
        let x = if count > 2 {
            a.svd(true, true).solve(&b, 1e-10 * a.amax()).unwrap_or_else(|_| Vector4::zeros())
        } else {
            a.lu().solve(&b).unwrap_or_else(Vector4::zeros)
        };
        std::array::from_fn(|i| if active[i] { x[i] } else { 0.0 })
    }

    /// The plastic strain rate and the changes of γp and pp for `multipliers`.
    pub(crate) fn flow(&self, multipliers: &[f64; 4]) -> (Vector4<f64>, f64, f64) {
        let (mut plastic, mut shear, mut cap) = (Vector4::zeros(), 0.0, 0.0);
        for (mechanism, l) in self.list.iter().zip(multipliers) {
            if let Some(m) = mechanism {
                plastic += m.m * *l;
                match m.family {
                    Family::Shear => shear += l,
                    Family::Cap => cap += l,
                }
            }
        }
        (plastic, shear, self.h_cap * cap)
    }
}

/// Which of the two hardening surfaces: on them, or allowed to load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Surfaces {
    pub(crate) shear: bool,
    pub(crate) cap: bool,
}
