//! The stress update of [`HardeningSoil`].
//!
//! **Substeps.** The rates are integrated explicitly by Heun's (modified Euler) method in
//! substeps of equal size, each changing the stress elastically by about [`SUBSTEP`] of itself
//! (after Sloan, Abbo & Sheng 2001, Eng. Computations 18, 121–154, without their error control).
//! Their number x is not rounded: the update blends ⌊x⌋ and ⌊x⌋ + 1 substeps, so that it is a
//! continuous function of the strain, as Newton's method needs (an error-controlled or rounded
//! partition jumps as the strain changes, and its noise, about 10⁻⁸ of the stress, stops the
//! iteration short of a tight tolerance). Where a substep carries a point onto a surface it was off,
//! the point goes first to where it meets it, found by bisection. A stress past the Mohr–Coulomb
//! strength is returned to it by the return map of [`mohr_coulomb`] with the substep's
//! elasticity, and a substep that starts there is taken whole (the return moves the point inside
//! the hardening surface it pushes against, which it would meet again in every substep).
//!
//! **Corners.** Where two principal stresses are equal (σ2 = σ3 in triaxial compression, σ1 = σ2 in
//! extension), both orders of the two are yield surfaces: two shear hardening surfaces sharing γp
//! and two caps sharing pp, each loading with its own multiplier (Koiter's rule). Under a strain
//! that keeps the corner both load and the two stresses stay equal, so an iteration's rounding
//! cannot split a corner that the loading keeps. Within [`CORNER`] of the stress's size two
//! principal stresses count as a corner. A plastic substep that would bring the out-of-plane stress
//! level with an in-plane one, or past it, goes first to where they meet (found by bisection, as for
//! a surface, on the substep's end and on its Euler predictor), and on from there at the corner:
//! without it a point whose flow drives it into the corner, as in plane strain where σzz follows
//! the in-plane stresses, overshot the corner in one substep and bounced back in the next, and its
//! update jumped by 10⁻³ of the stress as the strain changed by 10⁻⁵ of itself. Where it meets the
//! corner the stress is put onto it (the two principal stresses set to their mean, within the
//! corner's width of where they were; γp and pp as they were, unless the move passed a surface):
//! Heun's step to there averages a rate on each side of the corner and ends short of it, so that
//! each further located part halved the gap without closing it, and the point then left the
//! surfaces and met them again substep after substep; a point of a placed lift so jumped by a third of its stress as the
//! strain changed by 10⁻⁶ of itself, and Newton's iteration on the wall stalled.

use super::{HardeningSoil, Integrated, Point, Rate, CONFINEMENT_FLOOR, SUBSTEP};
use crate::element::mohr_coulomb::{self, YieldState};
use crate::element::substeps;
use crate::element::yield_mechanisms::{Principal, Surfaces, CORNER};
use nalgebra::Vector4;

/// The events a substep is split at, at most: reaching the shear surface, the cap, and the two
/// corners of the out-of-plane stress with the in-plane ones, and meeting a surface again after
/// the move onto a corner left the point inside it.
const EVENTS: usize = 8;
/// Halvings of the bisection that finds an event: to 2⁻³⁶ of a substep.
const BISECTIONS: usize = 36;
/// The events an integration locates, at most; past them its substeps are taken whole. A point
/// that meets a surface or a corner in every substep (as a cohesionless soil near zero stress can)
/// would otherwise cost a bisection per substep, tens of times the integration itself; the update
/// is then no longer smooth in the strain there.
const LOCATED_EVENTS: usize = 64;
/// A point is at the Mohr–Coulomb strength within this fraction of its stress.
const AT_STRENGTH: f64 = 1e-9;

impl HardeningSoil {
    /// Integrate the strain `total` from `start`.
    pub(super) fn integrate(&self, start: Point, total: Vector4<f64>) -> Integrated {
        // substeps of equal size, each changing the stress elastically by about SUBSTEP of itself
        // (or of the whole change, if larger: at most 1/SUBSTEP of them). Their number x is not
        // a whole number: the update is the blend of ⌊x⌋ and ⌊x⌋ + 1 substeps, so that it is a
        // continuous function of the strain, which Newton's method needs (a whole number of
        // substeps, or an error-controlled partition, jumps as the strain changes)
        let pref = self.parameters.reference_pressure;
        let elastic_change = (self.elasticity(&start.stress).d_matrix_with_hoop() * total).amax();
        let scale = start.stress.iter().fold(CONFINEMENT_FLOOR * pref, |m, v| m.max(v.abs())).max(elastic_change);
        let count = (elastic_change / scale / SUBSTEP).max(1.0);
        substeps::blended(
            count,
            |n| self.integrate_in(start, total, n),
            |coarse, fine, share| {
                let blend = |a: f64, b: f64| a + share * (b - a);
                Integrated {
                    point: Point {
                        stress: std::array::from_fn(|i| blend(coarse.point.stress[i], fine.point.stress[i])),
                        shear_hardening: blend(coarse.point.shear_hardening, fine.point.shear_hardening),
                        preconsolidation: blend(coarse.point.preconsolidation, fine.point.preconsolidation),
                    },
                    plastic_strain: blend(coarse.plastic_strain, fine.plastic_strain),
                    state: fine.state,
                }
            },
        )
    }

    /// Integrate the strain `total` from `start` in `substeps` equal substeps.
    fn integrate_in(&self, start: Point, total: Vector4<f64>, substeps: usize) -> Integrated {
        let mut point = start;
        let step = total / substeps as f64;
        let mut plastic_strain = 0.0;
        let mut state = YieldState::Elastic;
        let mut located = 0;
        for _ in 0..substeps {
            // a substep that carries the point onto a surface it was off goes first to where it
            // meets it (the fraction found by bisection, so to rounding: the update stays smooth in
            // the strain), then on from there with that surface too; so does a plastic substep
            // that brings the out-of-plane stress level with an in-plane one (or past it, which
            // its Euler predictor may do where the end does not), then on from there at the
            // corner. The last of EVENTS + 1 parts takes the rest whatever it meets, and so does every
            // substep once LOCATED_EVENTS have been located.
            let mut de = step;
            // a point held to the strength by the last substep's return takes this one whole: the
            // return moves it inside the hardening surfaces it pushes against (the cap, as the
            // stress climbs the failure line), and it would meet them again in every substep
            let at_strength = self.failure(&Principal::of(&point.stress).values)
                >= -AT_STRENGTH * point.stress.iter().fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()));
            for event in 0..=EVENTS {
                let last = event == EVENTS;
                let allowed = if last { Surfaces { shear: true, cap: true } } else { self.on(&point) };
                let (mut next, mut averaged, predicted) = self.heun(&point, &de, allowed);
                let plastic = allowed.shear || allowed.cap;
                let before = out_of_plane_gaps(&point.stress);
                let meets_surface = |end: &Point| {
                    let on = self.on(end);
                    (on.shear && !allowed.shear) || (on.cap && !allowed.cap)
                };
                let reaches = |(end, _, predicted): &(Point, Rate, Point)| {
                    meets_surface(end) || (plastic && met_corner(before, &end.stress, &predicted.stress).is_some())
                };
                let whole = last || located == LOCATED_EVENTS || at_strength || !reaches(&(next, averaged, predicted));
                if !whole {
                    located += 1;
                    let (mut lo, mut hi) = (0.0f64, 1.0f64);
                    for _ in 0..BISECTIONS {
                        let mid = 0.5 * (lo + hi);
                        if reaches(&self.heun(&point, &(de * mid), allowed)) {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    let predicted;
                    (next, averaged, predicted) = self.heun(&point, &(de * hi), allowed);
                    de *= 1.0 - hi;
                    // a corner met: the stress goes onto it. Heun's average of a rate on each
                    // side of the corner ends short of it, and the next located part would again
                    // end short, approaching it without reaching it
                    let corner = if plastic && !meets_surface(&next) {
                        met_corner(before, &next.stress, &predicted.stress)
                    } else {
                        None
                    };
                    if let Some(k) = corner {
                        // (a move within the corner's width; γp and pp stay, and a surface the
                        // move passes goes through the stress below. A surface the move leaves
                        // the point inside is met again as a located event, as it is where the
                        // substep meets the corner first: setting the surfaces the point was on
                        // through the moved stress lowered γp, and the update then depended on
                        // which of the two events came first)
                        next.stress = onto_corner(&next.stress, k);
                    }
                }
                plastic_strain += equivalent(&averaged.plastic_strain);
                state = match (averaged.shear, averaged.cap) {
                    (_, true) => YieldState::Cap,
                    (true, false) => YieldState::Hardening,
                    (false, false) => YieldState::Elastic,
                };
                // the strength: a stress past it goes back to it with the substep's elasticity
                let returned = mohr_coulomb::update_with_hoop(
                    &self.limit(),
                    &self.elasticity(&point.stress),
                    next.stress,
                    [0.0; 4],
                );
                if returned.state.is_plastic() {
                    next.stress = returned.stress;
                    plastic_strain += returned.plastic_strain;
                    state = returned.state;
                }
                point = self.through(&next.stress, next.shear_hardening, next.preconsolidation);
                if whole {
                    break;
                }
            }
        }
        Integrated { point, plastic_strain, state }
    }

    /// The surfaces the stress of `point` is on ([`HardeningSoil::surfaces_at`]).
    fn on(&self, point: &Point) -> Surfaces {
        self.surfaces_at(&Principal::of(&point.stress).values, point)
    }

    /// One step of Heun's method from `point` for the strain `de`, the `allowed` mechanisms
    /// loading where they are on their surfaces: the point reached and the averaged rate.
    fn heun(&self, point: &Point, de: &Vector4<f64>, allowed: Surfaces) -> (Point, Rate, Point) {
        let first = self.rate(point, de, allowed);
        let middle = self.advance(point, &first);
        let second = self.rate(&middle, de, allowed);
        let averaged = Rate {
            stress: (first.stress + second.stress) * 0.5,
            shear_hardening: 0.5 * (first.shear_hardening + second.shear_hardening),
            preconsolidation: 0.5 * (first.preconsolidation + second.preconsolidation),
            plastic_strain: (first.plastic_strain + second.plastic_strain) * 0.5,
            shear: first.shear || second.shear,
            cap: first.cap || second.cap,
        };
        (self.advance(point, &averaged), averaged, middle)
    }

    /// The point after `rate`: stress added, γp and pp grown, and both surfaces through the stress
    /// if it has passed them.
    fn advance(&self, point: &Point, rate: &Rate) -> Point {
        let stress: [f64; 4] = std::array::from_fn(|i| point.stress[i] + rate.stress[i]);
        let v = Principal::of(&stress).values;
        let mut next = Point {
            stress,
            shear_hardening: point.shear_hardening + rate.shear_hardening,
            preconsolidation: point.preconsolidation + rate.preconsolidation,
        };
        // a loading surface passes through the stress: γp and pp are those of the stress reached
        if rate.shear {
            next.shear_hardening = self.shear_function(&v).max(point.shear_hardening);
        }
        if rate.cap {
            next.preconsolidation = self.equivalent_pressure(&v).max(point.preconsolidation);
        }
        next
    }
}

/// The in-plane principal stresses less the out-of-plane one (σ+ − σzz, σ− − σzz), and the
/// stress's size.
fn out_of_plane_gaps(s: &[f64; 4]) -> ([f64; 2], f64) {
    let centre = 0.5 * (s[0] + s[1]);
    let half = 0.5 * (s[0] - s[1]);
    let radius = (half * half + s[2] * s[2]).sqrt();
    let scale = (centre.abs() + radius).max(s[3].abs()).max(f64::MIN_POSITIVE);
    ([centre + radius - s[3], centre - radius - s[3]], scale)
}

/// Which out-of-plane gap (0: σ+ − σzz, 1: σ− − σzz) of `before` (the gaps and the stress's size,
/// [`out_of_plane_gaps`]) the stress `end`, or its predictor `predicted`, has closed to within
/// [`CORNER`]: the one nearest zero at the end.
fn met_corner(before: ([f64; 2], f64), end: &[f64; 4], predicted: &[f64; 4]) -> Option<usize> {
    let (before, scale_before) = before;
    let (gaps, scale) = out_of_plane_gaps(end);
    let (predicted_gaps, predicted_scale) = out_of_plane_gaps(predicted);
    (0..2)
        .filter(|&k| {
            before[k].abs() > CORNER * scale_before
                && (gaps[k] * before[k].signum() <= CORNER * scale
                    || predicted_gaps[k] * before[k].signum() <= CORNER * predicted_scale)
        })
        .min_by(|&a, &b| gaps[a].abs().total_cmp(&gaps[b].abs()))
}

/// The stress `s` with its in-plane principal stress `k` (0: σ+, 1: σ−) and σzz both set to their
/// mean, the principal directions kept.
fn onto_corner(s: &[f64; 4], k: usize) -> [f64; 4] {
    let centre = 0.5 * (s[0] + s[1]);
    let half = 0.5 * (s[0] - s[1]);
    let radius = (half * half + s[2] * s[2]).sqrt();
    let (cos2, sin2) = if radius > 0.0 { (half / radius, s[2] / radius) } else { (1.0, 0.0) };
    let (mut plus, mut minus) = (centre + radius, centre - radius);
    let zz = if k == 0 {
        plus = 0.5 * (plus + s[3]);
        plus
    } else {
        minus = 0.5 * (minus + s[3]);
        minus
    };
    let (centre, radius) = (0.5 * (plus + minus), (0.5 * (plus - minus)).max(0.0));
    [centre + radius * cos2, centre - radius * cos2, radius * sin2, zz]
}

/// √(2/3·εᵖ:εᵖ) of an engineering strain (εxx, εyy, γxy, εzz).
fn equivalent(e: &Vector4<f64>) -> f64 {
    (2.0 / 3.0 * (e[0] * e[0] + e[1] * e[1] + e[3] * e[3] + 0.5 * e[2] * e[2])).sqrt()
}
