//! The same-clock write rule, clock by clock, through the model, the
//! rust-hdl block and the generated Verilog.

use super::build_name;
use super::rust_run::{hdl_outputs, set_pins};
use super::stimulus::TEST_BASE;
use crate::bfm::isa::{self, FLOATING_BUS};
use crate::harness::{settle, CheckReport};
use crate::verilog_sim::Target;
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_hdl::{catalog, IsaBridge};
use motionhdl_model::isa_bridge::{self as m, reg, status, IsaBridgeModel, IsaPins};
use motionhdl_model::IsaRam;
use rust_hdl::prelude::{Block, Clock};

/// The same-clock write rule, clock by clock: the PC writes DATA at word
/// `A`; while its write waits, the DSP writes word `A` (or, in the control
/// case, another word) for several clocks. Returns the per-clock input
/// vectors (in [`collision_ports`] order) and what must hold at the end.
pub fn collision_vectors(same_word: bool) -> Vec<IsaPinsAndReset> {
    const A: u16 = 0x155;
    let base = TEST_BASE;
    let idle = IsaPins::idle(base);
    let mut v = Vec::new();
    let mut push = |p: IsaPins, reset: bool, n: usize| {
        for _ in 0..n {
            v.push((p, reset));
        }
    };
    // Reset; the DSP zeroes word A and the word after it.
    let mut p = idle;
    p.sa = m::port(base, reg::STATUS);
    push(p, true, 5);
    p.dsp_we = true;
    p.dsp_addr = A;
    push(p, false, 1);
    p.dsp_addr = A + 1;
    push(p, false, 1);
    p.dsp_we = false;
    p.dsp_addr = A;
    push(p, false, 2);
    // STATUS = A (AUTO_INC off).
    let bus = |v: &mut Vec<(IsaPins, bool)>, reg: u16, data: u16| {
        let mut p = idle;
        p.sa = m::port(base, reg);
        p.dsp_addr = A;
        p.bale = true;
        v.extend([(p, false); 3]);
        p.bale = false;
        v.extend([(p, false); 3]);
        p.iow_n = false;
        p.sd_in = data;
        v.extend([(p, false); 10]);
        p.iow_n = true;
        p.sd_in = FLOATING_BUS;
        v.extend([(p, false); 1]);
    };
    bus(&mut v, reg::STATUS, A);
    let mut p = idle;
    p.sa = m::port(base, reg::STATUS);
    p.dsp_addr = A;
    v.extend([(p, false); 6]);
    // DATA = 0xBEEF; its strobe ends, and three clocks later it waits to
    // be written: the DSP writes in exactly those clocks.
    bus(&mut v, reg::DATA, 0xbeef);
    v.extend([(p, false); 2]);
    let mut d = p;
    d.dsp_we = true;
    d.dsp_addr = if same_word { A } else { A + 1 };
    for i in 0..6 {
        d.dsp_wdata = 0x1000 + i;
        v.push((d, false));
    }
    // The DSP reads word A, the PC looks at STATUS and DATA (sa only: SD
    // is combinational from SA1..SA0).
    v.extend([(p, false); 4]);
    let mut q = p;
    q.sa = m::port(base, reg::DATA);
    q.ior_n = false;
    v.extend([(q, false); 2]);
    // A 1 written to STATUS.COLLISION clears it (the address stays A);
    // the PC then reads STATUS.
    v.extend([(p, false); 2]);
    bus(&mut v, reg::STATUS, A | status::COLLISION);
    v.extend([(p, false); 2]);
    let mut q = p;
    q.ior_n = false;
    v.extend([(q, false); 2]);
    v
}

/// Pins and reset for one clock.
pub type IsaPinsAndReset = (IsaPins, bool);

/// Input and output ports of `isa_bridge` for the vector testbench.
pub fn collision_ports(
    m: &VerilogModule,
) -> (Vec<crate::verilog_sim::Port>, Vec<crate::verilog_sim::Port>) {
    use crate::verilog_sim::ports_of;
    (
        ports_of(m, &isa::PINS),
        ports_of(
            m,
            &[
                "sd_out",
                "sd_oe",
                "iocs16_n",
                "dsp_rdata",
                "irq",
                "bell_to_dsp",
            ],
        ),
    )
}

fn encode_vector((p, reset): &IsaPinsAndReset) -> Vec<u64> {
    isa::pin_values(p, *reset)
}

/// The same-clock write rule in the model alone, checked against the
/// documented rule (not against the model): after the collision the word
/// holds the PC's value, STATUS.COLLISION is set; without it, both words
/// hold what was written and COLLISION is clear. Either way a 1 written to
/// COLLISION leaves it clear in the STATUS read that ends the vectors.
/// Returns the model's outputs per vector for the HDL comparisons.
pub fn collision_expected(same_word: bool) -> Result<Vec<m::IsaOutputs>, String> {
    let vectors = collision_vectors(same_word);
    let data_port = m::port(TEST_BASE, reg::DATA);
    let mut model = IsaBridgeModel::new();
    let mut outs = Vec::new();
    let (mut saw_wait, mut collided, mut data_read) = (false, false, None);
    for (p, reset) in &vectors {
        outs.push(model.outputs(p));
        if model.write_pending() && p.dsp_we {
            saw_wait = true;
        }
        if p.sa == data_port && !p.ior_n {
            data_read = outs.last().copied();
        }
        model.clock(p, *reset);
        collided |= model.status() & status::COLLISION != 0;
    }
    let read = data_read.unwrap_or_default();
    let cleared = outs
        .last()
        .is_some_and(|o| o.sd_out & status::COLLISION == 0);
    let (a, b) = (model.ram()[0x155], model.ram()[0x156]);
    let ok = cleared
        && if same_word {
            saw_wait && a == 0xbeef && collided && read.dsp_rdata == 0xbeef && read.sd_out == 0xbeef
        } else {
            saw_wait && a == 0xbeef && b == 0x1005 && !collided
        };
    if ok {
        Ok(outs)
    } else {
        Err(format!(
            "same word {same_word}: DSP wrote while the PC write waited {saw_wait}, \
             word A {a:#06x}, word A+1 {b:#06x}, COLLISION {collided}, cleared {cleared}, \
             DATA read {read:?}"
        ))
    }
}

/// The same-clock rule: model vs the documented rule, then rust-hdl and
/// (when `sim` is given) the generated Verilog vs the model every clock.
pub fn collision_check(sim: Option<Target>) -> CheckReport {
    let what = match sim {
        None => "rust-hdl".to_string(),
        Some(t) => t.describe(),
    };
    let mut r = CheckReport::new(
        build_name(IsaRam::Internal),
        &format!("same-clock writes from both ports (rule, model, {what}), per clock"),
        0,
    );
    for same_word in [true, false] {
        let vectors = collision_vectors(same_word);
        r.expected += vectors.len() as u64;
        let want = match collision_expected(same_word) {
            Ok(w) => w,
            Err(e) => {
                r.failures.push(e);
                continue;
            }
        };
        let got: Vec<m::IsaOutputs> = match sim {
            None => {
                let mut uut = IsaBridge::new();
                uut.connect_all();
                vectors
                    .iter()
                    .map(|(p, reset)| {
                        set_pins(&mut uut, p, *reset);
                        settle(&mut uut);
                        let o = hdl_outputs(&uut);
                        uut.clock.next = Clock::from(true);
                        settle(&mut uut);
                        uut.clock.next = Clock::from(false);
                        settle(&mut uut);
                        o
                    })
                    .collect()
            }
            Some(t) => {
                let m = catalog::isa_bridge(IsaRam::Internal);
                let (inputs, outputs) = collision_ports(&m);
                let text = match t.text(&m) {
                    Ok(text) => text,
                    Err(e) if t.available().is_err() => return r.skip(e),
                    Err(e) => {
                        r.failures.push(e);
                        continue;
                    }
                };
                let design = crate::verilog_sim::Design {
                    top: m.name,
                    source: &text,
                    inputs,
                    outputs,
                    clock: Some("clock"),
                };
                let enc: Vec<Vec<u64>> = vectors.iter().map(encode_vector).collect();
                match crate::verilog_sim::run_vectors(t.sim, &design, &enc) {
                    Ok(rows) => rows
                        .iter()
                        .map(|o| m::IsaOutputs {
                            sd_out: o[0] as u16,
                            sd_oe: o[1] != 0,
                            iocs16_n: o[2] != 0,
                            dsp_rdata: o[3] as u16,
                            irq: o[4] != 0,
                            bell_to_dsp: o[5] != 0,
                        })
                        .collect(),
                    Err(e) if t.available().is_err() => return r.skip(e),
                    Err(e) => {
                        r.failures.push(e);
                        continue;
                    }
                }
            }
        };
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            r.case((g != w).then(|| {
                format!(
                    "same word {same_word}, clock {k}, pins {:?}: got {g:?}, model {w:?}",
                    vectors[k]
                )
            }));
        }
    }
    r
}
