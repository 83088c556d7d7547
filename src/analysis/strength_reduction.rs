//! The factor of safety by strength reduction (Griffiths & Lane, Géotechnique 49 (1999) 387–403;
//! Dawson, Roth & Drescher, Géotechnique 49 (1999) 835–840): the strengths are divided by F, which
//! rises from 1 (steps of 0.1, doubling) until an increment finds no equilibrium, and the bracket
//! [F_safe, F_fail] is then halved until its width is `tolerance`·F_safe. Every F with equilibrium is
//! a step of the stage (its `strength_factor`); a trial without equilibrium is undone. The laws are
//! restored to full strength afterwards.

use super::context::Context;
use super::equilibrium::{self, Purpose};
use super::sink::{FactorOfSafety, StepSink};
use super::soil::SoilSetup;
use super::stage::{complete_increment, Increment, Stage};
use super::state::State;
use crate::element::bar::BarStates;
use crate::error::Error;
use crate::interface::{Bearing, ShearLaw};
use crate::model::{Model, StrengthReduction};
use std::time::Instant;

/// Search for the factor of safety; every factor with equilibrium goes to `sink` as a step.
///
/// # Errors
/// When not even the full strengths find equilibrium (a failure of the stages before), and when a
/// step cannot be written.
pub fn search(
    cx: &mut Context,
    state: &mut State,
    stage: &mut Stage,
    reduction: StrengthReduction,
    sink: &mut dyn StepSink,
) -> Result<FactorOfSafety, Error> {
    let model = cx.model;
    let face_laws: Vec<ShearLaw> =
        state.interfaces.iter().flat_map(|i| i.faces.iter().map(|f| f.law.clone())).collect();
    // a geogrid's passive bearing is a strength too: divided by F with the laws' c and tan φ
    let face_bearings: Vec<_> = state.interfaces.iter().flat_map(|i| i.faces.iter().map(|f| f.bearing)).collect();
    let soil_laws = cx.setup.laws.clone();
    let apply = |state: &mut State, setup: &mut SoilSetup, factor: f64| {
        let faces = state.interfaces.iter_mut().flat_map(|i| i.faces.iter_mut());
        for ((face, law), bearing) in faces.zip(&face_laws).zip(&face_bearings) {
            face.law = law.reduced(factor);
            face.bearing = bearing.map(|b| Bearing { coefficient: b.coefficient / factor, ..b });
        }
        if reduction.soil {
            setup.laws = soil_laws.iter().map(|l| l.map(|l| l.reduced(factor))).collect();
        }
    };
    let (mut safe, mut failed) = (1.0f64, None::<f64>);
    let mut failure = None;
    let mut factor = 1.0;
    let mut growth = 0.1;
    let mut trials = Vec::new();
    let mut step = 0;
    loop {
        let started = Instant::now();
        let snapshot = state.clone();
        apply(state, &mut cx.setup, factor);
        match equilibrium::increment(cx, &stage.dofs, state, Purpose::StrengthTrial) {
            Ok(report) => {
                trials.push((factor, true));
                safe = factor;
                step += 1;
                let at = Increment {
                    step,
                    load_factor: 1.0,
                    strength_factor: Some(factor),
                    cutbacks: 0,
                    started,
                    reversal: false,
                };
                complete_increment(cx, stage, state, report, &at, sink)?;
            }
            Err(e) => {
                let ruptured = ruptured_since(model, &snapshot.bars, &state.bars);
                if failed.is_none_or(|f| factor < f) {
                    failure = Some(match ruptured.is_empty() {
                        true => e.describe(),
                        false => {
                            format!("{}; reinforcement ruptured on the way: {}", e.describe(), ruptured.join(", "))
                        }
                    });
                }
                *state = snapshot;
                if factor == 1.0 {
                    // not even the full strengths hold the model: that is a failure of the stages
                    // before, not a factor of safety
                    apply(state, &mut cx.setup, 1.0);
                    return Err(e.at(&model.source, &stage.plan.name, 1, 0));
                }
                trials.push((factor, false));
                failed = Some(factor);
            }
        }
        factor = match failed {
            Some(f) if f - safe <= reduction.tolerance * safe => break,
            Some(f) => 0.5 * (safe + f),
            None if safe >= reduction.max_factor => break,
            None => {
                let next = (safe + growth).min(reduction.max_factor);
                growth *= 2.0;
                next
            }
        };
    }
    apply(state, &mut cx.setup, 1.0);
    Ok(FactorOfSafety {
        stage: stage.plan.name.clone(),
        value: safe,
        failed_at: failed,
        reduced: if reduction.soil { "soil and interfaces" } else { "interfaces" },
        trials,
        failure,
    })
}

/// Bars ruptured in `after` and not in `before`, counted per reinforcement material.
fn ruptured_since(model: &Model, before: &BarStates, after: &BarStates) -> Vec<String> {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for (i, bar) in model.mesh.bars.iter().enumerate() {
        if after.ruptured[i] && !before.ruptured[i] {
            let name = &model.reinforcements[bar.material].0;
            match counts.iter_mut().find(|(n, _)| n == name) {
                Some(c) => c.1 += 1,
                None => counts.push((name.clone(), 1)),
            }
        }
    }
    counts.into_iter().map(|(n, c)| format!("{c} bars of {n}")).collect()
}
