//! Exhaustive checks of the 74LS153: every one of its 4096 input
//! combinations through the rust-hdl block and the generated Verilog,
//! against the model.

use crate::harness::{settle, CheckReport};
use crate::verilog_sim::{compare_vectors, sim_failure};
use crate::verilog_sim::{ports_of, Design, Simulator, Target};
use motionhdl_hdl::{catalog, Ls153};
use motionhdl_model::ls153::{self as m153, Ls153Inputs, INPUT_PINS};
use rust_hdl::prelude::*;

/// Drives every pin of the rust-hdl chip.
pub fn drive_ls153(uut: &mut Ls153, i: &Ls153Inputs) {
    uut.a.next = i.a;
    uut.b.next = i.b;
    uut.g1_n.next = i.g1_n;
    uut.g2_n.next = i.g2_n;
    uut.c1_0.next = i.c1[0];
    uut.c1_1.next = i.c1[1];
    uut.c1_2.next = i.c1[2];
    uut.c1_3.next = i.c1[3];
    uut.c2_0.next = i.c2[0];
    uut.c2_1.next = i.c2[1];
    uut.c2_2.next = i.c2[2];
    uut.c2_3.next = i.c2[3];
}

/// Every one of the 4096 input combinations of the chip, rust-hdl vs model.
pub fn ls153_hdl() -> CheckReport {
    let mut r = CheckReport::new("ls153", "rust-hdl vs model, every input", 1 << INPUT_PINS);
    let mut uut = Ls153::default();
    uut.connect_all();
    for w in 0..(1u16 << INPUT_PINS) {
        let i = Ls153Inputs::from_word(w);
        drive_ls153(&mut uut, &i);
        settle(&mut uut);
        let want = m153::ls153(&i);
        let got = (uut.y1.val(), uut.y2.val());
        r.case(
            (got != (want.y1, want.y2))
                .then(|| format!("inputs {i:?}: HDL {got:?}, model {want:?}")),
        );
    }
    r
}

/// All 4096 chip inputs through the generated `ls153.v` (or its netlist).
pub fn ls153_verilog(target: impl Into<Target>) -> CheckReport {
    let t = target.into();
    let r = CheckReport::new(
        "ls153",
        &format!("{} vs model", t.describe()),
        1 << INPUT_PINS,
    );
    let m = catalog::ls153();
    let text = match t.text(&m) {
        Ok(text) => text,
        Err(e) => return sim_failure(r, t, e),
    };
    let design = Design {
        top: m.name,
        source: &text,
        inputs: ports_of(
            &m,
            &[
                "a", "b", "g1_n", "g2_n", "c1_0", "c1_1", "c1_2", "c1_3", "c2_0", "c2_1", "c2_2",
                "c2_3",
            ],
        ),
        outputs: ports_of(&m, &["y1", "y2"]),
        clock: None,
    };
    let inputs: Vec<Ls153Inputs> = (0..(1u16 << INPUT_PINS))
        .map(Ls153Inputs::from_word)
        .collect();
    compare_vectors(
        r,
        t,
        &design,
        &inputs,
        |i| {
            [
                i.a, i.b, i.g1_n, i.g2_n, i.c1[0], i.c1[1], i.c1[2], i.c1[3], i.c2[0], i.c2[1],
                i.c2[2], i.c2[3],
            ]
            .iter()
            .map(|b| u64::from(*b))
            .collect()
        },
        |i, o| {
            let want = m153::ls153(i);
            let got = (o[0] != 0, o[1] != 0);
            (got != (want.y1, want.y2))
                .then(|| format!("inputs {i:?}: Verilog {got:?}, model {want:?}"))
        },
    )
}

/// The 74LS153's checks; external simulators only when `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = vec![ls153_hdl()];
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            v.push(ls153_verilog(sim));
        }
    }
    v
}
