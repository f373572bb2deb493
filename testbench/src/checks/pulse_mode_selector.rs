//! Exhaustive checks of the pulse-mode selector (K=0 pulse+direction,
//! K=1 CW/CCW): the model's three forms against the seed table, the
//! rust-hdl blocks (combinational and registered) against the model, and
//! the generated Verilog against the model.

use crate::harness::{cycle, settle, CheckReport};
use crate::verilog_sim::sim_failure;
use crate::verilog_sim::{ports_of, run_vectors, Design, Simulator, Target};
use motionhdl_hdl::{catalog, PulseModeSelector, PulseModeSelectorRegistered};
use motionhdl_model::pulse_mode_selector::{self as msel, RegisteredSelector};
use rust_hdl::prelude::*;
use std::collections::BTreeSet;

/// Every (K, S2, S1), in minterm order.
pub fn selector_inputs() -> impl Iterator<Item = (bool, bool, bool)> {
    (0u8..8).map(|m| (m & 4 != 0, m & 2 != 0, m & 1 != 0))
}

fn bits(k: bool, s2: bool, s1: bool) -> String {
    format!("K={} S2={} S1={}", u8::from(k), u8::from(s2), u8::from(s1))
}

/// The seed's equations and the one-chip wiring against its truth table.
pub fn selector_model_forms() -> Vec<CheckReport> {
    let mut minterms = CheckReport::new(
        "pulse_mode_selector",
        "Σm(1,3,5)/Σm(2,3,7) vs seed table",
        8,
    );
    let mut chip = CheckReport::new(
        "pulse_mode_selector",
        "74LS153 wiring model vs seed table",
        8,
    );
    for (k, s2, s1) in selector_inputs() {
        let t = msel::from_truth_table(k, s2, s1);
        let m = msel::from_minterms(k, s2, s1);
        let c = msel::from_chip(k, s2, s1);
        minterms
            .case((m != t).then(|| format!("{}: minterms {m:?}, table {t:?}", bits(k, s2, s1))));
        chip.case((c != t).then(|| format!("{}: chip {c:?}, table {t:?}", bits(k, s2, s1))));
    }
    vec![minterms, chip]
}

/// Every (K, S2, S1) through the rust-hdl selector.
pub fn selector_hdl() -> CheckReport {
    let mut r = CheckReport::new("pulse_mode_selector", "rust-hdl vs seed table", 8);
    let mut uut = PulseModeSelector::default();
    uut.connect_all();
    for (k, s2, s1) in selector_inputs() {
        uut.k.next = k;
        uut.s2.next = s2;
        uut.s1.next = s1;
        settle(&mut uut);
        let got = (uut.f1.val(), uut.f2.val());
        let want = msel::from_truth_table(k, s2, s1);
        // The chip inside must see exactly the pin levels the wiring model gives.
        let pins = msel::chip_inputs(k, s2, s1);
        let chip = uut.chip();
        let chip_ok = chip.a.val() == pins.a
            && chip.b.val() == pins.b
            && chip.g1_n.val() == pins.g1_n
            && chip.g2_n.val() == pins.g2_n
            && [
                chip.c1_0.val(),
                chip.c1_1.val(),
                chip.c1_2.val(),
                chip.c1_3.val(),
            ] == [pins.c1[0], pins.c1[1], pins.c1[2], pins.c1[3]]
            && [
                chip.c2_0.val(),
                chip.c2_1.val(),
                chip.c2_2.val(),
                chip.c2_3.val(),
            ] == [pins.c2[0], pins.c2[1], pins.c2[2], pins.c2[3]];
        r.case(if got != want {
            Some(format!("{}: HDL {got:?}, table {want:?}", bits(k, s2, s1)))
        } else if !chip_ok {
            Some(format!(
                "{}: chip pins differ from the wiring model {pins:?}",
                bits(k, s2, s1)
            ))
        } else {
            None
        });
    }
    r
}

/// Inputs of the registered selector for one clock: (reset, K, S2, S1).
pub type RegInputs = (bool, bool, bool, bool);

/// A vector sequence that applies every one of the 16 inputs in every one
/// of the 4 output states: a reset, then for each (state, input) a vector
/// that sets the state and the input under test. A final idle vector lets
/// the last transition be observed.
pub fn registered_vectors() -> Vec<RegInputs> {
    let mut v = vec![(true, false, false, false)];
    for state in 0u8..4 {
        for input in 0u8..16 {
            // K=0 passes S1 to F1 and S2 to F2: any state in one clock.
            v.push((false, false, state & 2 != 0, state & 1 != 0));
            v.push((
                input & 8 != 0,
                input & 4 != 0,
                input & 2 != 0,
                input & 1 != 0,
            ));
        }
    }
    v.push((false, false, false, false));
    v
}

/// Compares observed outputs (one pair per vector, read before that
/// vector's clock edge) with the model, counting distinct (state, input)
/// pairs whose result was observed.
pub fn check_registered(
    check: &str,
    vectors: &[RegInputs],
    outputs: &[(bool, bool)],
) -> CheckReport {
    let mut r = CheckReport::new("pulse_mode_selector_registered", check, 64);
    let mut model = RegisteredSelector::default();
    let mut pairs = BTreeSet::new();
    let mut prev: Option<((bool, bool), RegInputs)> = None;
    for (n, (inp, got)) in vectors.iter().zip(outputs).enumerate() {
        let want = model.outputs();
        if *got != want {
            let f = format!("vector {n} {inp:?}: outputs {got:?}, model {want:?} (after {prev:?})");
            if r.failures.len() < 20 {
                r.failures.push(f);
            }
        } else if let Some(p) = prev {
            pairs.insert(p);
        }
        prev = Some((want, *inp));
        let (reset, k, s2, s1) = *inp;
        model.clock(reset, k, s2, s1);
    }
    r.covered = pairs.len() as u64;
    r
}

/// Every (state, input) pair through the rust-hdl registered selector.
pub fn registered_hdl() -> CheckReport {
    let vectors = registered_vectors();
    let mut uut = PulseModeSelectorRegistered::default();
    uut.connect_all();
    let mut outputs = Vec::new();
    for &(reset, k, s2, s1) in &vectors {
        uut.reset.next = reset;
        uut.k.next = k;
        uut.s2.next = s2;
        uut.s1.next = s1;
        settle(&mut uut);
        outputs.push((uut.f1.val(), uut.f2.val()));
        cycle(&mut uut, |u| &mut u.clock);
    }
    check_registered("rust-hdl vs model, every state × input", &vectors, &outputs)
}

/// Every (K, S2, S1) through the generated `pulse_mode_selector.v` (or its
/// netlist).
pub fn selector_verilog(target: impl Into<Target>) -> CheckReport {
    let t = target.into();
    let r = CheckReport::new(
        "pulse_mode_selector",
        &format!("{} vs seed table", t.describe()),
        8,
    );
    let m = catalog::pulse_mode_selector();
    let text = match t.text(&m) {
        Ok(text) => text,
        Err(e) => return sim_failure(r, t, e),
    };
    let design = Design {
        top: m.name,
        source: &text,
        inputs: ports_of(&m, &["k", "s2", "s1"]),
        outputs: ports_of(&m, &["f1", "f2"]),
        clock: None,
    };
    let inputs: Vec<(bool, bool, bool)> = selector_inputs().collect();
    let vectors: Vec<Vec<u64>> = inputs
        .iter()
        .map(|&(k, s2, s1)| vec![k.into(), s2.into(), s1.into()])
        .collect();
    match run_vectors(t.sim, &design, &vectors) {
        Err(e) => sim_failure(r, t, e),
        Ok(out) => {
            let mut r = r;
            for (&(k, s2, s1), o) in inputs.iter().zip(out) {
                let got = (o[0] != 0, o[1] != 0);
                let want = msel::from_truth_table(k, s2, s1);
                r.case(
                    (got != want)
                        .then(|| format!("{}: Verilog {got:?}, table {want:?}", bits(k, s2, s1))),
                );
            }
            r
        }
    }
}

/// Every (state, input) pair through the generated
/// `pulse_mode_selector_registered.v` (or its netlist).
pub fn registered_verilog(target: impl Into<Target>) -> CheckReport {
    let t = target.into();
    let check = format!("{} vs model, every state × input", t.describe());
    let m = catalog::pulse_mode_selector_registered();
    let text = match t.text(&m) {
        Ok(text) => text,
        Err(e) => {
            return sim_failure(
                CheckReport::new("pulse_mode_selector_registered", &check, 64),
                t,
                e,
            )
        }
    };
    let design = Design {
        top: m.name,
        source: &text,
        inputs: ports_of(&m, &["reset", "k", "s2", "s1"]),
        outputs: ports_of(&m, &["f1", "f2"]),
        clock: Some("clock"),
    };
    let vectors = registered_vectors();
    let raw: Vec<Vec<u64>> = vectors
        .iter()
        .map(|&(r, k, s2, s1)| vec![r.into(), k.into(), s2.into(), s1.into()])
        .collect();
    match run_vectors(t.sim, &design, &raw) {
        Err(e) => sim_failure(
            CheckReport::new("pulse_mode_selector_registered", &check, 64),
            t,
            e,
        ),
        Ok(out) => {
            let outputs: Vec<(bool, bool)> = out.iter().map(|o| (o[0] != 0, o[1] != 0)).collect();
            check_registered(&check, &vectors, &outputs)
        }
    }
}

/// The selector's checks; external simulators only when `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = selector_model_forms();
    v.push(selector_hdl());
    v.push(registered_hdl());
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            v.push(selector_verilog(sim));
            v.push(registered_verilog(sim));
        }
    }
    v
}
