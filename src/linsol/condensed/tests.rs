//! A whole solve after the kept system was solved alone: L was let go by then and its product
//! comes from the caller; the solution meets (L + C) x = b to round-off on every backend.
use super::*;
use crate::linsol::csc::Triplets;

/// A chain of 12 springs fixed at one end (L), and a spring between the kept unknowns 3 and 11
/// (C).
fn chain() -> (Triplets, Triplets, Vec<usize>) {
    let mut l = Triplets::default();
    for i in 0..12 {
        l.push(i, i, if i == 11 { 1.5 } else { 2.5 });
        if i + 1 < 12 {
            l.push(i, i + 1, -1.0);
            l.push(i + 1, i, -1.0);
        }
    }
    let mut c = Triplets::default();
    for (i, j, v) in [(3, 3, 0.7), (11, 11, 0.7), (3, 11, -0.7), (11, 3, -0.7)] {
        c.push(i, j, v);
    }
    (l, c, vec![3, 8, 11])
}

#[test]
fn a_whole_solve_after_a_kept_one_checks_its_residual_with_the_callers_product() {
    let (l, c, kept) = chain();
    let n = 12;
    let rhs: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.61).cos()).collect();
    let (whole, _) = PatternCache::default().assemble(
        n,
        &Triplets {
            rows: l.rows.iter().chain(&c.rows).copied().collect(),
            cols: l.cols.iter().chain(&c.cols).copied().collect(),
            values: l.values.iter().chain(&c.values).copied().collect(),
        },
    );
    let meets = |x: &[f64]| {
        let ax = whole.mul_vec(x);
        ax.iter().zip(&rhs).all(|(a, b)| (a - b).abs() < 1e-12 * b.abs().max(1.0))
    };
    for backend in Backend::available() {
        let mut system = CondensedSystem::new(backend, &SolverOptions::default()).expect("backend starts");
        let mut stats = SolverStats::default();
        let linear = || l.clone();
        let l_matrix = PatternCache::default().assemble(n, &l).0;
        let products = std::cell::Cell::new(0);
        let linear_times = |x: &[f64]| {
            products.set(products.get() + 1);
            l_matrix.mul_vec(x)
        };
        let kept = Rc::new(KeptUnknowns::new(n, kept.clone()));
        let soil = SoilPart { kept: &kept, key: 1, assemble: &linear, times: &linear_times };
        let interface = InterfacePart { key: 2, assemble: &|| c.clone() };
        let (x, _) = system.solve(&mut stats, &soil, &interface, &rhs).expect("first whole solve");
        assert!(meets(&x), "{}: first whole solve", backend.name());
        let rhs_kept = kept.gather(&rhs);
        system.solve_kept(&mut stats, 1, &interface, &rhs_kept).expect("kept solve");
        assert!(system.soil.as_ref().is_some_and(|p| p.matrix.is_none()), "{}: L let go", backend.name());
        assert_eq!(products.get(), 0, "{}: L's own matrix checks the first solve", backend.name());
        let (x, residual) = system.solve(&mut stats, &soil, &interface, &rhs).expect("second whole solve");
        assert!(meets(&x) && residual < 1e-12, "{}: whole solve after the kept one: {residual}", backend.name());
        assert!(products.get() >= 1, "{}: the caller's product checks the second", backend.name());
        assert!(system.soil.as_ref().is_some_and(|p| p.matrix.is_none()), "{}: L not assembled again", backend.name());
    }
}
