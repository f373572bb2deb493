//! Exhaustive checks of the 74LS688: every one of the 2^17 input
//! combinations through the rust-hdl block and the generated Verilog,
//! against the model.

use crate::harness::{settle, CheckReport};
use crate::verilog_sim::{compare_vectors, sim_failure};
use crate::verilog_sim::{ports_of, Design, Simulator, Target};
use motionhdl_hdl::{catalog, Ls688};
use motionhdl_model::ls688::{self as m688, Ls688Inputs, INPUT_PINS};
use rust_hdl::prelude::*;

fn every_input() -> impl Iterator<Item = Ls688Inputs> {
    (0..(1u32 << INPUT_PINS)).map(Ls688Inputs::from_word)
}

/// Every input combination, rust-hdl vs model.
pub fn ls688_hdl() -> CheckReport {
    let mut r = CheckReport::new("ls688", "rust-hdl vs model, every input", 1 << INPUT_PINS);
    let mut uut = Ls688::default();
    uut.connect_all();
    for i in every_input() {
        uut.p.next = u64::from(i.p).into();
        uut.q.next = u64::from(i.q).into();
        uut.g_n.next = i.g_n;
        settle(&mut uut);
        let (got, want) = (uut.p_eq_q_n.val(), m688::ls688(&i));
        r.case((got != want).then(|| format!("inputs {i:?}: HDL P=Q̅ {got}, model {want}")));
    }
    r
}

/// Every input combination through the generated `ls688.v` (or its
/// netlist).
pub fn ls688_verilog(target: impl Into<Target>) -> CheckReport {
    let t = target.into();
    let r = CheckReport::new(
        "ls688",
        &format!("{} vs model", t.describe()),
        1 << INPUT_PINS,
    );
    let m = catalog::ls688();
    let text = match t.text(&m) {
        Ok(text) => text,
        Err(e) => return sim_failure(r, t, e),
    };
    let design = Design {
        top: m.name,
        source: &text,
        inputs: ports_of(&m, &["p", "q", "g_n"]),
        outputs: ports_of(&m, &["p_eq_q_n"]),
        clock: None,
    };
    let inputs: Vec<Ls688Inputs> = every_input().collect();
    compare_vectors(
        r,
        t,
        &design,
        &inputs,
        |i| vec![u64::from(i.p), u64::from(i.q), u64::from(i.g_n)],
        |i, o| {
            let (got, want) = (o[0] != 0, m688::ls688(i));
            (got != want).then(|| format!("inputs {i:?}: Verilog P=Q̅ {got}, model {want}"))
        },
    )
}

/// The 74LS688 checks; external simulators only when `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![ls688_hdl()];
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            v.push(ls688_verilog(sim));
        }
    }
    v
}
