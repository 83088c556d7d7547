//! The kept unknowns K: the equations the soil is condensed onto, sorted and distinct, and each
//! equation's position among them.

use crate::linsol::csc::Triplets;

/// Marks an equation of the interior in [`KeptUnknowns`]'s position map.
const INTERIOR: u32 = u32::MAX;

/// The kept unknowns: sorted, distinct equation numbers of a system of `n` equations, and each
/// equation's position among them. Positions are 32-bit (4 bytes an equation, 6.4 MB at 1.6·10⁶
/// unknowns), since at most a few thousand equations are kept.
#[derive(Debug, Clone)]
pub struct KeptUnknowns {
    equations: Vec<usize>,
    position: Vec<u32>,
}

impl KeptUnknowns {
    /// The equations marked `true` in `keep` (one flag per equation).
    pub fn from_marks(keep: &[bool]) -> KeptUnknowns {
        let equations: Vec<usize> = keep.iter().enumerate().filter(|(_, &k)| k).map(|(e, _)| e).collect();
        KeptUnknowns::new(keep.len(), equations)
    }

    /// `equations` (sorted, distinct, each below `n`) of a system of `n` equations.
    pub fn new(n: usize, equations: Vec<usize>) -> KeptUnknowns {
        debug_assert!(equations.windows(2).all(|w| w[0] < w[1]) && equations.last().is_none_or(|&e| e < n));
        let mut position = vec![INTERIOR; n];
        for (k, &e) in equations.iter().enumerate() {
            position[e] = k as u32;
        }
        KeptUnknowns { equations, position }
    }

    /// The kept equations, increasing.
    pub fn equations(&self) -> &[usize] {
        &self.equations
    }

    pub fn len(&self) -> usize {
        self.equations.len()
    }

    pub fn is_empty(&self) -> bool {
        self.equations.is_empty()
    }

    /// The number of equations of the whole system.
    pub fn n(&self) -> usize {
        self.position.len()
    }

    /// The position of equation `eq` among the kept unknowns; `None` for an interior one.
    pub fn position(&self, eq: usize) -> Option<usize> {
        self.position.get(eq).copied().filter(|&p| p != INTERIOR).map(|p| p as usize)
    }

    pub fn contains(&self, eq: usize) -> bool {
        self.position(eq).is_some()
    }

    /// Whether every entry of `triplets` lies in the kept rows and columns.
    pub fn holds(&self, triplets: &Triplets) -> bool {
        let inside = |&e: &u32| self.contains(e as usize);
        triplets.rows.iter().all(inside) && triplets.cols.iter().all(inside)
    }

    /// `v` on the kept unknowns, in their order.
    pub fn gather(&self, v: &[f64]) -> Vec<f64> {
        self.equations.iter().map(|&e| v[e]).collect()
    }

    /// ‖v‖₂ over the interior equations (the kept ones left out), summed in equation order.
    pub fn interior_norm(&self, v: &[f64]) -> f64 {
        v.iter().enumerate().filter(|&(e, _)| !self.contains(e)).map(|(_, r)| r * r).sum::<f64>().sqrt()
    }
}

impl PartialEq for KeptUnknowns {
    fn eq(&self, other: &Self) -> bool {
        self.position.len() == other.position.len() && self.equations == other.equations
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_gather_and_the_interior_norm() {
        let kept = KeptUnknowns::from_marks(&[false, true, false, true, true, false]);
        assert_eq!(kept.equations(), &[1, 3, 4]);
        assert_eq!((kept.len(), kept.n()), (3, 6));
        assert_eq!([0, 1, 3, 4, 5, 9].map(|e| kept.position(e)), [None, Some(0), Some(1), Some(2), None, None]);
        let v = [3.0, 10.0, 4.0, 20.0, 30.0, 12.0];
        assert_eq!(kept.gather(&v), vec![10.0, 20.0, 30.0]);
        // the interior 3, 4, 12: a 3-4-12-13 quadruple
        assert_eq!(kept.interior_norm(&v), 13.0);
        let mut t = Triplets::default();
        t.push(1, 4, 1.0);
        assert!(kept.holds(&t));
        t.push(3, 5, 1.0);
        assert!(!kept.holds(&t));
    }
}
