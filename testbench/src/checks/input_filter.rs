//! Input filter checks: every reachable (state, input) pair of the
//! rust-hdl filter beside the model's, for every setting.

use crate::harness::{cycle, settle, CheckReport};
use crate::state_map;
use crate::tour::{explore, tour};
use motionhdl_hdl::InputFilter as HdlFilter;
use motionhdl_model::counter::InputFilter;
use rust_hdl::prelude::*;
use std::collections::BTreeSet;

/// Every reachable (state, input) pair of the input filter, for every
/// setting F in 0..=15, rust-hdl vs model every clock.
pub fn filter_exhaustive() -> CheckReport {
    filter_exhaustive_built(true)
}

/// [`filter_exhaustive`] for a filter built with or without `filtering` (a
/// build without the filter ignores every setting).
pub fn filter_exhaustive_built(filtering: bool) -> CheckReport {
    let inputs: Vec<(bool, bool)> =
        vec![(false, false), (true, false), (false, true), (true, true)];
    let mut total_expected = 0;
    let mut covered = 0;
    let mut failures = Vec::new();
    for setting in 0u8..16 {
        let step = |s: &InputFilter, &(pin, reset): &(bool, bool)| {
            let mut n = *s;
            n.clock(pin, setting, reset, filtering);
            n
        };
        let g = explore(InputFilter::default(), &inputs, step, 1 << 16).expect("small state space");
        total_expected += g.pairs() as u64;
        let mut hdl = HdlFilter::with_filtering(filtering);
        hdl.connect_all();
        hdl.setting.next = (setting as u64).into();
        settle(&mut hdl);
        let mut model = InputFilter::default();
        let mut pairs = BTreeSet::new();
        for (n, inp) in tour(&g).into_iter().enumerate() {
            let (pin, reset) = inputs[inp];
            pairs.insert((model, inp));
            hdl.pin.next = pin;
            hdl.reset.next = reset;
            settle(&mut hdl);
            cycle(&mut hdl, |h| &mut h.clock);
            model.clock(pin, setting, reset, filtering);
            if state_map::filter(hdl.probe()) != model {
                failures.push(format!(
                    "F={setting} step {n} pin={pin} reset={reset}: HDL {:?}, model {model:?}",
                    state_map::filter(hdl.probe())
                ));
                break;
            }
        }
        covered += pairs.len() as u64;
    }
    let label = if filtering {
        "input filter, every reachable state × input, F=0..15"
    } else {
        "input filter left out of the build (synchroniser only), every reachable state × input, F=0..15"
    };
    let mut r = CheckReport::new("counter_bank", label, total_expected);
    r.covered = covered;
    r.failures = failures;
    r
}

/// The input filter's checks `motionhdl verify` runs.
pub fn all(_external: bool) -> Vec<CheckReport> {
    vec![filter_exhaustive(), filter_exhaustive_built(false)]
}
