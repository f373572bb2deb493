//! The ISA bridge's scenario traces, from the rust-hdl block.

use crate::bfm::isa::{Op, CLOCK_PS};
use crate::checks::isa_bridge::{
    expected, run_rust, same, standard_read, standard_write, TracePoint, TEST_BASE,
};
use motionhdl_model::isa_bridge::{self as m, mailbox, reg, status};
use motionhdl_model::IsaRam;

/// A scenario trace of `ops`: the ISA pins at their real times (ps), the
/// clock, the DSP port and the counter, all from the rust-hdl block. Panics
/// if the block disagrees with either model on the way.
fn scenario_trace(name: &str, ops: &[Op]) -> crate::trace::Trace {
    use crate::trace::Trace;
    let mut t = Trace::new_ps(format!(
        "{} | scenario {name} | clock 50000000 Hz | ISA base port {:#x}",
        motionhdl_hdl::banner_ascii(),
        m::port(TEST_BASE, 0)
    ));
    let top = ["isa_bridge"];
    let clock = t.signal(&top, "clock", 1);
    let reset = t.signal(&top, "reset", 1);
    let sa = t.signal(&top, "sa", 10);
    let sd = t.signal(&top, "sd", 16);
    let sd_oe = t.signal(&top, "sd_oe", 1);
    let ior_n = t.signal(&top, "ior_n", 1);
    let iow_n = t.signal(&top, "iow_n", 1);
    let aen = t.signal(&top, "aen", 1);
    let bale = t.signal(&top, "bale", 1);
    let iocs16_n = t.signal(&top, "iocs16_n", 1);
    let dsp_addr = t.signal(&top, "dsp_addr", 10);
    let dsp_wdata = t.signal(&top, "dsp_wdata", 16);
    let dsp_we = t.signal(&top, "dsp_we", 1);
    let dsp_rdata = t.signal(&top, "dsp_rdata", 16);
    let irq = t.signal(&top, "irq", 1);
    let bell_to_dsp = t.signal(&top, "bell_to_dsp", 1);
    let inside = ["isa_bridge", "state"];
    let counter = t.signal(&inside, "address_counter", 10);
    let pending = t.signal(&inside, "pc_write_waiting", 1);
    let mut hook = |tp: &TracePoint| {
        let (p, o) = (tp.pins, &tp.outputs);
        let bus = if o.sd_oe { o.sd_out } else { p.sd_in };
        for (id, v) in [
            (reset, u64::from(tp.reset)),
            (sa, u64::from(p.sa)),
            (sd, u64::from(bus)),
            (sd_oe, u64::from(o.sd_oe)),
            (ior_n, u64::from(p.ior_n)),
            (iow_n, u64::from(p.iow_n)),
            (aen, u64::from(p.aen)),
            (bale, u64::from(p.bale)),
            (iocs16_n, u64::from(o.iocs16_n)),
            (dsp_addr, u64::from(p.dsp_addr)),
            (dsp_wdata, u64::from(p.dsp_wdata)),
            (dsp_we, u64::from(p.dsp_we)),
            (dsp_rdata, u64::from(o.dsp_rdata)),
            (irq, u64::from(o.irq)),
            (bell_to_dsp, u64::from(o.bell_to_dsp)),
            (counter, u64::from(tp.counter)),
            (pending, u64::from(tp.write_pending)),
        ] {
            t.set(tp.time, id, v);
        }
        if tp.edge {
            t.set(tp.time, clock, 1);
            t.set(tp.time + CLOCK_PS / 2, clock, 0);
        }
    };
    let run = run_rust(IsaRam::Internal, TEST_BASE, ops, Some(&mut hook));
    assert!(run.mismatches.is_empty(), "{name}: {:?}", run.mismatches);
    let want = expected(IsaRam::Internal, TEST_BASE, ops);
    assert_eq!(run.observations.len(), want.len());
    for (g, w) in run.observations.iter().zip(&want) {
        assert!(
            same(g, w),
            "{name}: observed {g:?}, transaction model {w:?}"
        );
    }
    t
}

const SCENARIO_WORDS: u16 = 8;

/// The PC writes 8 words with AUTO_INC (one OUT per word), then the DSP
/// reads them.
pub fn block_write_trace() -> crate::trace::Trace {
    let mut ops = vec![Op::Reset, Op::Align { offset_ps: 3_500 }];
    ops.push(standard_write(reg::STATUS, status::AUTO_INC));
    for i in 0..SCENARIO_WORDS {
        ops.push(standard_write(reg::DATA, 0x1100 + i));
    }
    ops.push(standard_read(reg::STATUS));
    ops.extend((0..SCENARIO_WORDS).map(|addr| Op::DspRead { addr }));
    let mut t = scenario_trace("isa_block_write", &ops);
    let w = t.mark_edge("isa_bridge.iow_n", 0, 0, "PC: OUT STATUS (AUTO_INC)");
    t.mark_edge(
        "isa_bridge.ior_n",
        0,
        w,
        "PC: IN STATUS, then the DSP reads",
    );
    t
}

/// The DSP writes 8 words, the PC reads them back, first the seed's way
/// (DATA then ADDR_INC) for 4 words, then with AUTO_INC.
pub fn block_read_trace() -> crate::trace::Trace {
    let mut ops = vec![Op::Reset];
    ops.extend((0..SCENARIO_WORDS).map(|addr| Op::DspWrite {
        addr,
        data: 0x2200 + addr,
    }));
    ops.push(Op::Align { offset_ps: 7_500 });
    ops.push(standard_write(reg::ADDR_CLEAR, 0));
    for _ in 0..SCENARIO_WORDS / 2 {
        ops.push(standard_read(reg::DATA));
        ops.push(standard_read(reg::ADDR_INC));
    }
    ops.push(standard_write(
        reg::STATUS,
        status::AUTO_INC | (SCENARIO_WORDS / 2),
    ));
    for _ in SCENARIO_WORDS / 2..SCENARIO_WORDS {
        ops.push(standard_read(reg::DATA));
    }
    ops.push(standard_read(reg::STATUS));
    let mut t = scenario_trace("isa_block_read", &ops);
    let w = t.mark_edge("isa_bridge.dsp_we", 1, 0, "DSP writes the block");
    let clear = t.mark_edge("isa_bridge.iow_n", 0, w, "PC: OUT ADDR_CLEAR");
    t.mark_edge("isa_bridge.ior_n", 0, clear, "PC: IN DATA, IN ADDR_INC");
    t
}

/// The doorbells (IDT7130-style mailbox words): the DSP writes 4 words and
/// rings the PC by writing the PC's mailbox word; the PC, its IRQ enabled,
/// reads STATUS (BELL set) and the mailbox (which answers the bell and
/// drops IRQ), reads the block, and rings the DSP back by writing the DSP's
/// mailbox word (`bell_to_dsp` pulses as the write lands).
pub fn doorbell_trace() -> crate::trace::Trace {
    let mut ops = vec![Op::Reset, Op::Align { offset_ps: 7_500 }];
    ops.push(standard_write(
        reg::STATUS,
        status::IRQ_EN | status::AUTO_INC | mailbox::TO_PC,
    ));
    ops.extend((0..4).map(|addr| Op::DspWrite {
        addr,
        data: 0x3300 + addr,
    }));
    ops.push(Op::DspWrite {
        addr: mailbox::TO_PC,
        data: 4,
    });
    ops.push(Op::Align { offset_ps: 7_500 });
    ops.push(standard_read(reg::STATUS));
    ops.push(standard_read(reg::DATA));
    ops.push(standard_read(reg::STATUS));
    ops.push(standard_write(reg::ADDR_CLEAR, 0));
    ops.extend((0..4).map(|_| standard_read(reg::DATA)));
    ops.push(standard_write(
        reg::STATUS,
        status::IRQ_EN | status::AUTO_INC | mailbox::TO_DSP,
    ));
    ops.push(standard_write(reg::DATA, 0x00ac));
    ops.push(standard_read(reg::STATUS));
    ops.push(Op::DspRead {
        addr: mailbox::TO_DSP,
    });
    let mut t = scenario_trace("isa_doorbell", &ops);
    t.mark_edge("isa_bridge.irq", 1, 0, "DSP rings the PC: IRQ");
    t.mark_edge("isa_bridge.bell_to_dsp", 1, 0, "PC rings the DSP");
    t
}
