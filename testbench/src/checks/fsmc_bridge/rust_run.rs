//! The rust-hdl bridge, its cycle model and the test slave stepped
//! together through the FSMC bus-functional model's events.

use super::{Counts, TestSlave};
use crate::bfm::fsmc::{timeline, Event, Observation, Op, CLOCK_TICKS, FIRST_EDGE_TICKS};
use crate::harness::settle;
use motionhdl_hdl::FsmcBridge;
use motionhdl_model::fsmc_bridge::{FsmcBridgeModel, FsmcOutputs, FsmcPins, FsmcTiming};
use rust_hdl::prelude::*;

/// The rust-hdl block, the cycle model and the test slave stepped through
/// `ops`.
pub struct RustRun {
    /// What the reads observed (from the HDL).
    pub observations: Vec<Observation>,
    /// Clock edges simulated.
    pub clocks: u64,
    /// HDL/model disagreements (first few), with the time.
    pub mismatches: Vec<String>,
    pub counts: Counts,
}

fn set_pins(uut: &mut FsmcBridge, p: &FsmcPins, reset: bool) {
    uut.ne_n.next = p.ne_n;
    uut.noe_n.next = p.noe_n;
    uut.nwe_n.next = p.nwe_n;
    uut.a.next = u64::from(p.a).into();
    uut.d_in.next = u64::from(p.d_in).into();
    uut.reset.next = reset;
}

fn hdl_outputs(uut: &FsmcBridge) -> FsmcOutputs {
    FsmcOutputs {
        d_out: uut.d_out.val().index() as u16,
        d_oe: uut.d_oe.val(),
        reg_addr: uut.reg_addr.val().index() as u16,
        reg_wdata: uut.reg_wdata.val().index() as u32,
        reg_we: uut.reg_we.val(),
        reg_re: uut.reg_re.val(),
        ram_addr: uut.ram_addr.val().index() as u16,
        ram_wdata: uut.ram_wdata.val().index() as u16,
        ram_we: uut.ram_we.val(),
    }
}

/// Runs `ops` with `timing` through the rust-hdl block and the cycle model
/// (every output compared before every edge and at every observation),
/// with the test slave behind both.
pub fn run_rust(ops: &[Op], timing: &FsmcTiming) -> RustRun {
    let (events, end) = timeline(ops, timing);
    let mut uut = FsmcBridge::new();
    uut.connect_all();
    let mut model = FsmcBridgeModel::new();
    let mut slave = TestSlave::new();
    let mut pins = FsmcPins::idle();
    let mut reset = false;
    let mut run = RustRun {
        observations: Vec::new(),
        clocks: 0,
        mismatches: Vec::new(),
        counts: Counts::default(),
    };
    let mismatch = |run: &mut RustRun, s: String| {
        if run.mismatches.len() < 10 {
            run.mismatches.push(s);
        }
    };
    let mut pending: Option<(bool, u16)> = None;
    let mut edge = FIRST_EDGE_TICKS;
    let mut i = 0;
    let observe = |uut: &mut FsmcBridge, pins: &FsmcPins, reset: bool| {
        set_pins(uut, pins, reset);
        settle(uut);
        hdl_outputs(uut)
    };
    while edge <= end || i < events.len() {
        while i < events.len() && events[i].0 < edge {
            let (t, e) = events[i];
            match e {
                Event::Pins(p, r) => {
                    pins = p;
                    reset = r;
                }
                Event::ObserveSetup | Event::ObserveEnd => {
                    let o = observe(&mut uut, &pins, reset);
                    let mo = model.outputs(&pins);
                    if o != mo {
                        mismatch(&mut run, format!("t={t}: outputs HDL {o:?} model {mo:?}"));
                    }
                    if matches!(e, Event::ObserveSetup) {
                        pending = Some((o.d_oe, o.d_out));
                    } else {
                        let (oe_setup, data_setup) = pending.take().expect("setup first");
                        run.observations.push(Observation {
                            oe_setup,
                            oe_end: o.d_oe,
                            data_setup,
                            data_end: o.d_out,
                        });
                    }
                }
            }
            assert_ne!(t, edge, "an event at a clock edge");
            i += 1;
        }
        if edge > end {
            break;
        }
        let o = observe(&mut uut, &pins, reset);
        let mo = model.outputs(&pins);
        if o != mo {
            let k = run.clocks;
            mismatch(
                &mut run,
                format!("t={edge} before edge {k}: HDL {o:?} model {mo:?}"),
            );
        }
        let (rdata, ram_rdata) = (slave.rdata, slave.ram_rdata);
        uut.clock.next = Clock::from(true);
        settle(&mut uut);
        uut.clock.next = Clock::from(false);
        settle(&mut uut);
        model.clock(&pins, reset, rdata, ram_rdata);
        slave.edge(&o);
        uut.reg_rdata.next = u64::from(slave.rdata).into();
        uut.ram_rdata.next = u64::from(slave.ram_rdata).into();
        run.clocks += 1;
        edge += CLOCK_TICKS;
    }
    run.counts = slave.counts;
    run
}
