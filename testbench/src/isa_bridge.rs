//! Checks of the ISA bridge (docs/isa_bridge.md).
//!
//! One stimulus language, [`Op`], drives everything: an ISA bus-functional
//! model turns each I/O cycle into pin changes at real times (8.33 MHz bus,
//! BALE, AEN, IOR#/IOW# of a chosen length) against the 50 MHz FPGA clock.
//! The same op list runs
//! * through the rust-hdl block and the cycle-accurate model together, in
//!   continuous time here ([`run_rust`]: HDL vs model at every clock edge),
//! * through the generated Verilog under a Verilog ISA bus-functional model
//!   in Icarus and Verilator ([`run_verilog`]),
//!
//! and what the PC and the DSP observe is compared with the
//! transaction-level model ([`expected`]).

use crate::harness::{settle, CheckReport};
use crate::verilog_sim::{build_and_run, Simulator, Target};
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_hdl::{catalog, IsaBridge, IsaBridgeExternal};
use motionhdl_model::isa_bridge::{
    self as m, reg, status, IsaBridgeExternalModel, IsaBridgeModel, IsaCard, IsaPins, SramPins,
};
use motionhdl_model::regmap::ISA_RAM_WORDS;
use motionhdl_model::IsaRam;
use rust_hdl::prelude::*;
use std::fmt::Write as _;
use std::fs;

/// FPGA clock period (50 MHz).
pub const CLOCK_PS: u64 = 20_000;
/// First rising clock edge; edges follow every [`CLOCK_PS`].
pub const FIRST_EDGE_PS: u64 = 10_000;
/// ISA bus clock period (8.33 MHz).
pub const BCLK_NS: u64 = 120;
/// BALE high time at the start of a cycle (half a BCLK).
pub const BALE_NS: u64 = 60;
/// Command starts one BCLK after the cycle (BALE rising).
pub const COMMAND_DELAY_NS: u64 = BCLK_NS;
/// The bus drives write data this long after IOW# falls (pessimistic).
pub const WRITE_DATA_DELAY_NS: u64 = 15;
/// Write data held after IOW# rises.
pub const WRITE_DATA_HOLD_NS: u64 = 25;
/// SA and AEN held after the command ends, before the next cycle.
pub const ADDRESS_HOLD_NS: u64 = 60;
/// The host needs read data this long before IOR# rises.
pub const READ_SETUP_NS: u64 = 20;
/// Command (IOR#/IOW# low) lengths the checks cover: from 110 ns, shorter
/// than a 16-bit I/O cycle without wait states on an 8.33 MHz bus, to
/// 600 ns, an 8-bit-style cycle with four wait states.
pub const COMMAND_NS: [u64; 5] = [110, 180, 240, 360, 600];
/// Command length of the set-up and read-back cycles around a case.
pub const STANDARD_COMMAND_NS: u64 = 240;
/// Half a nanosecond: bus events sit this far off the clock edges.
const HALF_NS: u64 = 500;
/// What the PC sees on undriven SD lines.
pub const FLOATING_BUS: u16 = 0xffff;

/// One step of stimulus.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// An ISA I/O write (OUT) cycle.
    IoWrite {
        port: u16,
        aen: bool,
        data: u16,
        command_ns: u64,
    },
    /// An ISA I/O read (IN) cycle.
    IoRead {
        port: u16,
        aen: bool,
        command_ns: u64,
    },
    /// The DSP writes one word (one clock, set up at a falling edge).
    DspWrite { addr: u16, data: u16 },
    /// The DSP reads one word; the data is taken one clock later.
    DspRead { addr: u16 },
    /// Wait for the next rising edge, then `offset_ps` more: sets the phase
    /// of whatever follows against the FPGA clock.
    Align { offset_ps: u64 },
    /// Synchronous reset for 5 clocks (the RAM keeps its contents).
    Reset,
}

/// What a read observes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observation {
    /// An I/O read: SD drive and data [`READ_SETUP_NS`] before IOR# rises
    /// and 1 ns before it rises.
    Io {
        oe_setup: bool,
        oe_end: bool,
        data_setup: u16,
        data_end: u16,
    },
    /// A DSP read.
    Dsp { data: u16 },
}

/// What the transaction model says each read returns.
pub fn expected(base: u8, ops: &[Op]) -> Vec<Observation> {
    let mut card = IsaCard::new(base);
    let mut out = Vec::new();
    for op in ops {
        match *op {
            Op::IoWrite {
                port, aen, data, ..
            } => {
                card.io_write(port, aen, data);
            }
            Op::IoRead { port, aen, .. } => out.push(match card.io_read(port, aen) {
                Some(v) => Observation::Io {
                    oe_setup: true,
                    oe_end: true,
                    data_setup: v,
                    data_end: v,
                },
                None => Observation::Io {
                    oe_setup: false,
                    oe_end: false,
                    data_setup: 0,
                    data_end: 0,
                },
            }),
            Op::DspWrite { addr, data } => card.dsp_write(addr, data),
            Op::DspRead { addr } => out.push(Observation::Dsp {
                data: card.dsp_read(addr),
            }),
            Op::Align { .. } => {}
            Op::Reset => {
                let ram = card.ram().to_vec();
                card = IsaCard::new(base);
                for (a, w) in ram.iter().enumerate() {
                    card.dsp_write(a as u16, *w);
                }
            }
        }
    }
    out
}

/// Reads compared as the PC sees them: data only matters when driven.
pub fn same(got: &Observation, want: &Observation) -> bool {
    match (got, want) {
        (
            Observation::Io {
                oe_setup,
                oe_end,
                data_setup,
                data_end,
            },
            Observation::Io {
                oe_setup: w_oe,
                data_end: w_data,
                ..
            },
        ) => {
            *oe_setup == *w_oe
                && *oe_end == *w_oe
                && (!w_oe || (*data_setup == *w_data && *data_end == *w_data))
        }
        (a, b) => a == b,
    }
}

/// A pin change at a time, or an observation point.
#[derive(Clone, Copy, Debug)]
enum Event {
    Pins(IsaPins, bool),
    ObserveIo { setup: bool },
    ObserveDsp,
}

fn next_rising(t: u64) -> u64 {
    if t < FIRST_EDGE_PS {
        FIRST_EDGE_PS
    } else {
        FIRST_EDGE_PS + ((t - FIRST_EDGE_PS) / CLOCK_PS + 1) * CLOCK_PS
    }
}

fn next_falling(t: u64) -> u64 {
    (t / CLOCK_PS + 1) * CLOCK_PS
}

/// The bus-functional model: every op as timed pin changes (ps). Returns the
/// events and the end time.
fn timeline(base: u8, ops: &[Op]) -> (Vec<(u64, Event)>, u64) {
    let mut pins = IsaPins::idle(base);
    pins.sd_in = FLOATING_BUS;
    let mut reset = false;
    // Bus events fall on whole nanoseconds plus half a nanosecond, clock
    // edges on whole nanoseconds: no event shares a time with an edge.
    let mut t: u64 = HALF_NS;
    let mut ev: Vec<(u64, Event)> = vec![(0, Event::Pins(pins, reset))];
    let ns = 1000;
    for op in ops {
        match *op {
            Op::IoWrite { .. } | Op::IoRead { .. } => {
                let (port, aen, command_ns, write, data) = match *op {
                    Op::IoWrite {
                        port,
                        aen,
                        data,
                        command_ns,
                    } => (port, aen, command_ns, true, data),
                    Op::IoRead {
                        port,
                        aen,
                        command_ns,
                    } => (port, aen, command_ns, false, 0),
                    _ => unreachable!(),
                };
                assert!(command_ns > READ_SETUP_NS.max(WRITE_DATA_DELAY_NS) + 1);
                pins.sa = port & 0x3ff;
                pins.aen = aen;
                pins.bale = true;
                ev.push((t, Event::Pins(pins, reset)));
                // BALE stays high through DMA cycles.
                pins.bale = aen;
                t += BALE_NS * ns;
                ev.push((t, Event::Pins(pins, reset)));
                t += (COMMAND_DELAY_NS - BALE_NS) * ns;
                if write {
                    pins.iow_n = false;
                    ev.push((t, Event::Pins(pins, reset)));
                    pins.sd_in = data;
                    ev.push((t + WRITE_DATA_DELAY_NS * ns, Event::Pins(pins, reset)));
                    t += command_ns * ns;
                    pins.iow_n = true;
                    ev.push((t, Event::Pins(pins, reset)));
                    pins.sd_in = FLOATING_BUS;
                    ev.push((t + WRITE_DATA_HOLD_NS * ns, Event::Pins(pins, reset)));
                } else {
                    pins.ior_n = false;
                    ev.push((t, Event::Pins(pins, reset)));
                    let rise = t + command_ns * ns;
                    ev.push((rise - READ_SETUP_NS * ns, Event::ObserveIo { setup: true }));
                    ev.push((rise - ns, Event::ObserveIo { setup: false }));
                    t = rise;
                    pins.ior_n = true;
                    ev.push((t, Event::Pins(pins, reset)));
                }
                t += ADDRESS_HOLD_NS * ns;
                pins.bale = false;
                ev.push((t, Event::Pins(pins, reset)));
            }
            Op::DspWrite { addr, data } => {
                t = next_falling(t);
                pins.dsp_addr = addr;
                pins.dsp_wdata = data;
                pins.dsp_we = true;
                ev.push((t, Event::Pins(pins, reset)));
                t = next_falling(t);
                pins.dsp_we = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += HALF_NS;
            }
            Op::DspRead { addr } => {
                t = next_falling(t);
                pins.dsp_addr = addr;
                ev.push((t, Event::Pins(pins, reset)));
                t = next_falling(t);
                ev.push((t, Event::ObserveDsp));
                t += HALF_NS;
            }
            Op::Align { offset_ps } => {
                assert!(offset_ps < CLOCK_PS);
                t = next_rising(t) + offset_ps;
            }
            Op::Reset => {
                t = next_falling(t);
                reset = true;
                ev.push((t, Event::Pins(pins, reset)));
                t += 5 * CLOCK_PS;
                reset = false;
                ev.push((t, Event::Pins(pins, reset)));
                t += HALF_NS;
            }
        }
    }
    (ev, t + 4 * CLOCK_PS)
}

/// The rust-hdl block and the cycle model stepped together through `ops`.
pub struct RustRun {
    /// What the reads observed (from the HDL).
    pub observations: Vec<Observation>,
    /// Clock edges simulated.
    pub clocks: u64,
    /// HDL/model disagreements and SRAM contract violations (first few),
    /// with the time.
    pub mismatches: Vec<String>,
}

/// What a trace sees at one instant.
pub struct TracePoint<'a> {
    /// Time in ps.
    pub time: u64,
    /// A rising clock edge is about to happen (else: a pin changed).
    pub edge: bool,
    pub pins: &'a IsaPins,
    pub reset: bool,
    pub outputs: m::IsaOutputs,
    pub counter: u16,
    pub write_pending: bool,
    /// The SRAM pins, for the external-RAM build.
    pub sram: Option<SramPins>,
}

/// A hook for traces, called before every clock edge and after every pin
/// change.
pub type EdgeHook<'a> = &'a mut dyn FnMut(&TracePoint);

/// One build of the bridge with its model and surroundings, stepped by
/// [`run_rust`].
trait Bench {
    /// Applies the pins, settles; (HDL outputs, model outputs).
    fn observe(&mut self, pins: &IsaPins, reset: bool) -> (m::IsaOutputs, m::IsaOutputs);
    /// One rising edge of both; problems found at it.
    fn edge(&mut self, pins: &IsaPins, reset: bool, edge_index: u64) -> Vec<String>;
    fn counter(&self) -> u16;
    fn write_pending(&self) -> bool;
    fn sram(&self) -> Option<SramPins>;
}

macro_rules! set_bus_pins {
    ($uut:expr, $p:expr, $reset:expr) => {{
        let (uut, p) = ($uut, $p);
        uut.sa.next = u64::from(p.sa).into();
        uut.sd_in.next = u64::from(p.sd_in).into();
        uut.ior_n.next = p.ior_n;
        uut.iow_n.next = p.iow_n;
        uut.aen.next = p.aen;
        uut.bale.next = p.bale;
        uut.base.next = u64::from(p.base).into();
        uut.reset.next = $reset;
    }};
}

fn set_pins(uut: &mut IsaBridge, p: &IsaPins, reset: bool) {
    set_bus_pins!(&mut *uut, p, reset);
    uut.dsp_addr.next = u64::from(p.dsp_addr).into();
    uut.dsp_wdata.next = u64::from(p.dsp_wdata).into();
    uut.dsp_we.next = p.dsp_we;
}

fn hdl_outputs(uut: &IsaBridge) -> m::IsaOutputs {
    m::IsaOutputs {
        sd_out: uut.sd_out.val().index() as u16,
        sd_oe: uut.sd_oe.val(),
        iocs16_n: uut.iocs16_n.val(),
        dsp_rdata: uut.dsp_rdata.val().index() as u16,
    }
}

fn rising_edge<B: Block>(uut: &mut B, clock: fn(&mut B) -> &mut Signal<In, Clock>) {
    clock(uut).next = Clock::from(true);
    settle(uut);
    clock(uut).next = Clock::from(false);
    settle(uut);
}

/// The build with block RAM and the DSP port.
struct InternalBench {
    uut: IsaBridge,
    model: IsaBridgeModel,
}

impl Bench for InternalBench {
    fn observe(&mut self, pins: &IsaPins, reset: bool) -> (m::IsaOutputs, m::IsaOutputs) {
        set_pins(&mut self.uut, pins, reset);
        settle(&mut self.uut);
        (hdl_outputs(&self.uut), self.model.outputs(pins))
    }
    fn edge(&mut self, pins: &IsaPins, reset: bool, _: u64) -> Vec<String> {
        set_pins(&mut self.uut, pins, reset);
        settle(&mut self.uut);
        rising_edge(&mut self.uut, |u| &mut u.clock);
        self.model.clock(pins, reset);
        let (h, m) = (self.uut.counter(), self.model.counter());
        if h != m {
            vec![format!("counter HDL {h} model {m}")]
        } else {
            vec![]
        }
    }
    fn counter(&self) -> u16 {
        self.uut.counter()
    }
    fn write_pending(&self) -> bool {
        self.uut.write_pending()
    }
    fn sram(&self) -> Option<SramPins> {
        None
    }
}

/// An IDT7025-style asynchronous dual-port SRAM, left port on the FPGA,
/// right port on the DSP (modelled as synchronous to the FPGA clock, as
/// the `dsp_*` pins of the internal build). It checks the left port's
/// write timing and bus contention.
#[derive(Clone, Debug)]
pub struct DualPortSram {
    mem: Vec<u16>,
    pins: SramPins,
    /// Edge at which the address pins last changed.
    addr_changed: u64,
    /// Edge at which WE# fell (while low).
    we_fell: Option<u64>,
    write_data: Option<u16>,
    dsp_rdata: u16,
}

/// Read access time in clocks: data is valid two edges after the address
/// changes (35 ns parts at 50 MHz).
pub const SRAM_ACCESS_CLOCKS: u64 = 2;
/// Shortest WE# pulse, in clocks (tWP 25 ns: two clocks at 50 MHz).
pub const SRAM_WRITE_PULSE_CLOCKS: u64 = 2;
/// What the FPGA reads on its data pins while the chip's output is not yet
/// valid: never a plausible word in the checks.
pub const SRAM_INVALID: u16 = 0xdead;

impl DualPortSram {
    pub fn new() -> Self {
        Self {
            mem: vec![0; ISA_RAM_WORDS as usize],
            pins: SramPins {
                we_n: true,
                ..Default::default()
            },
            addr_changed: 0,
            we_fell: None,
            write_data: None,
            dsp_rdata: 0,
        }
    }

    /// What the data pins show at edge `k` with the current FPGA pins.
    pub fn data_pins(&self, k: u64) -> u16 {
        let p = &self.pins;
        if p.d_oe {
            p.d_out
        } else if !p.ce_n && !p.oe_n && p.we_n {
            if k >= self.addr_changed + SRAM_ACCESS_CLOCKS {
                self.mem[usize::from(p.addr)]
            } else {
                SRAM_INVALID
            }
        } else {
            FLOATING_BUS
        }
    }

    /// The data pins show RAM data (not garbage or a floating bus) at `k`.
    pub fn data_valid(&self, k: u64) -> bool {
        let p = &self.pins;
        !p.d_oe && !p.ce_n && !p.oe_n && p.we_n && k >= self.addr_changed + SRAM_ACCESS_CLOCKS
    }

    /// Edge `k`: the DSP side acts, then the FPGA's new pins (driven from
    /// flops updated at this edge) take effect. Returns contract violations.
    pub fn edge(&mut self, k: u64, dsp: &IsaPins, new: SramPins) -> Vec<String> {
        let mut bad = Vec::new();
        let dsp_addr = usize::from(dsp.dsp_addr & 0x3ff);
        self.dsp_rdata = self.mem[dsp_addr];
        if dsp.dsp_we {
            self.mem[dsp_addr] = dsp.dsp_wdata;
        }
        let old = self.pins;
        if new.addr != old.addr {
            self.addr_changed = k;
        }
        if old.we_n && !new.we_n {
            if new.addr != old.addr {
                bad.push(format!(
                    "edge {k}: WE# fell as the address changed (no set-up)"
                ));
            }
            self.we_fell = Some(k);
            self.write_data = new.d_oe.then_some(new.d_out);
        }
        if !old.we_n {
            if new.addr != old.addr {
                bad.push(format!("edge {k}: address changed while WE# was low"));
            }
            if !new.d_oe || Some(new.d_out) != self.write_data {
                bad.push(format!("edge {k}: write data not held while WE# was low"));
            }
        }
        if !old.we_n && new.we_n {
            let fell = self.we_fell.take().unwrap_or(k);
            if k - fell < SRAM_WRITE_PULSE_CLOCKS {
                bad.push(format!("edge {k}: WE# pulse of {} clocks", k - fell));
            }
            if old.ce_n {
                bad.push(format!("edge {k}: write with CE# high"));
            }
            match self.write_data {
                Some(d) => self.mem[usize::from(old.addr)] = d,
                None => bad.push(format!("edge {k}: write with the data pins undriven")),
            }
        }
        if new.d_oe && !new.ce_n && !new.oe_n && new.we_n {
            bad.push(format!("edge {k}: FPGA and SRAM both drive the data pins"));
        }
        self.pins = new;
        bad
    }

    pub fn mem(&self) -> &[u16] {
        &self.mem
    }
}

impl Default for DualPortSram {
    fn default() -> Self {
        Self::new()
    }
}

/// The build for an external dual-port SRAM, with the chip.
struct ExternalBench {
    uut: IsaBridgeExternal,
    model: IsaBridgeExternalModel,
    chip: DualPortSram,
    /// The data pins were valid RAM data at the previous edge.
    sample_valid: bool,
}

fn sram_pins_of(uut: &IsaBridgeExternal) -> SramPins {
    SramPins {
        addr: uut.ram_addr.val().index() as u16,
        d_out: uut.ram_d_out.val().index() as u16,
        d_oe: uut.ram_d_oe.val(),
        ce_n: uut.ram_ce_n.val(),
        oe_n: uut.ram_oe_n.val(),
        we_n: uut.ram_we_n.val(),
    }
}

impl ExternalBench {
    fn set(&mut self, pins: &IsaPins, reset: bool, k: u64) {
        set_bus_pins!(&mut self.uut, pins, reset);
        self.uut.ram_d_in.next = u64::from(self.chip.data_pins(k)).into();
        settle(&mut self.uut);
    }
    fn outputs(&self) -> m::IsaOutputs {
        m::IsaOutputs {
            sd_out: self.uut.sd_out.val().index() as u16,
            sd_oe: self.uut.sd_oe.val(),
            iocs16_n: self.uut.iocs16_n.val(),
            dsp_rdata: self.chip.dsp_rdata,
        }
    }
}

impl Bench for ExternalBench {
    fn observe(&mut self, pins: &IsaPins, reset: bool) -> (m::IsaOutputs, m::IsaOutputs) {
        // Between edges the data pins read as at the next edge: only the
        // bus outputs matter here, and they do not depend on them.
        self.set(pins, reset, u64::MAX / 2);
        let (sd_out, sd_oe, iocs16_n) = self.model.outputs(pins);
        (
            self.outputs(),
            m::IsaOutputs {
                sd_out,
                sd_oe,
                iocs16_n,
                dsp_rdata: self.chip.dsp_rdata,
            },
        )
    }
    fn edge(&mut self, pins: &IsaPins, reset: bool, k: u64) -> Vec<String> {
        self.set(pins, reset, k);
        let d_in = self.chip.data_pins(k);
        let mut bad = Vec::new();
        // Contract: the prefetch only takes data the SRAM really drove.
        if self.model.takes_sample() && !self.sample_valid {
            bad.push("the prefetch took data sampled before the SRAM's access time".to_string());
        }
        self.sample_valid = self.chip.data_valid(k);
        rising_edge(&mut self.uut, |u| &mut u.clock);
        self.model.clock(pins, reset, d_in);
        let hdl = sram_pins_of(&self.uut);
        bad.extend(self.chip.edge(k, pins, hdl));
        if hdl != self.model.sram() {
            bad.push(format!(
                "SRAM pins HDL {hdl:?} model {:?}",
                self.model.sram()
            ));
        }
        let (h, m) = (self.uut.counter(), self.model.counter());
        if h != m {
            bad.push(format!("counter HDL {h} model {m}"));
        }
        bad
    }
    fn counter(&self) -> u16 {
        self.uut.counter()
    }
    fn write_pending(&self) -> bool {
        self.model.core().queued_write().is_some()
    }
    fn sram(&self) -> Option<SramPins> {
        Some(sram_pins_of(&self.uut))
    }
}

/// Runs `ops` through the rust-hdl block of the `ram` build and its cycle
/// model, comparing every output before every edge and the counter (and
/// the SRAM pins) after it.
pub fn run_rust(ram: IsaRam, base: u8, ops: &[Op], hook: Option<EdgeHook>) -> RustRun {
    match ram {
        IsaRam::Internal => {
            let mut uut = IsaBridge::new();
            uut.connect_all();
            run_bench(
                InternalBench {
                    uut,
                    model: IsaBridgeModel::new(),
                },
                base,
                ops,
                hook,
            )
        }
        IsaRam::External => {
            let mut uut = IsaBridgeExternal::new();
            uut.connect_all();
            run_bench(
                ExternalBench {
                    uut,
                    model: IsaBridgeExternalModel::new(),
                    chip: DualPortSram::new(),
                    sample_valid: false,
                },
                base,
                ops,
                hook,
            )
        }
    }
}

fn run_bench(mut bench: impl Bench, base: u8, ops: &[Op], mut hook: Option<EdgeHook>) -> RustRun {
    let (events, end) = timeline(base, ops);
    let mut pins = IsaPins::idle(base);
    let mut reset = false;
    let mut run = RustRun {
        observations: Vec::new(),
        clocks: 0,
        mismatches: Vec::new(),
    };
    let mut pending_setup: Option<(bool, u16)> = None;
    let mut edge = FIRST_EDGE_PS;
    let mut i = 0;
    let mismatch = |run: &mut RustRun, s: String| {
        if run.mismatches.len() < 10 {
            run.mismatches.push(s);
        }
    };
    let mut last_dsp_rdata = 0;
    while edge <= end || i < events.len() {
        // Events strictly before the edge happen first; none share its time.
        while i < events.len() && events[i].0 < edge {
            let (t, e) = events[i];
            match e {
                Event::Pins(p, r) => {
                    pins = p;
                    reset = r;
                    if let Some(h) = hook.as_mut() {
                        let (outputs, _) = bench.observe(&pins, reset);
                        h(&TracePoint {
                            time: t,
                            edge: false,
                            pins: &pins,
                            reset,
                            outputs,
                            counter: bench.counter(),
                            write_pending: bench.write_pending(),
                            sram: bench.sram(),
                        });
                    }
                }
                Event::ObserveIo { setup } => {
                    let (o, mo) = bench.observe(&pins, reset);
                    if o != mo {
                        mismatch(&mut run, format!("t={t}ps outputs HDL {o:?} model {mo:?}"));
                    }
                    if setup {
                        pending_setup = Some((o.sd_oe, o.sd_out));
                    } else {
                        let (oe_setup, data_setup) =
                            pending_setup.take().expect("setup observation first");
                        run.observations.push(Observation::Io {
                            oe_setup,
                            oe_end: o.sd_oe,
                            data_setup,
                            data_end: o.sd_out,
                        });
                    }
                }
                Event::ObserveDsp => {
                    run.observations.push(Observation::Dsp {
                        data: last_dsp_rdata,
                    });
                }
            }
            assert_ne!(t, edge, "an event at a clock edge");
            i += 1;
        }
        if edge > end {
            break;
        }
        let (o, mo) = bench.observe(&pins, reset);
        if o != mo {
            mismatch(
                &mut run,
                format!("t={edge}ps before edge: HDL {o:?} model {mo:?}"),
            );
        }
        if let Some(h) = hook.as_mut() {
            h(&TracePoint {
                time: edge,
                edge: true,
                pins: &pins,
                reset,
                outputs: o,
                counter: bench.counter(),
                write_pending: bench.write_pending(),
                sram: bench.sram(),
            });
        }
        for bad in bench.edge(&pins, reset, run.clocks) {
            mismatch(&mut run, format!("t={edge}ps: {bad}"));
        }
        last_dsp_rdata = bench.observe(&pins, reset).0.dsp_rdata;
        run.clocks += 1;
        edge += CLOCK_PS;
    }
    run
}

/// The Verilog ISA bus-functional model and testbench: it reads the ops
/// from `ops.hex` and prints one line per read. Timing constants are the
/// ones above, so both bus models run the same waveforms.
pub fn verilog_testbench(ram: IsaRam, base: u8, ops: usize) -> String {
    let dut = match ram {
        IsaRam::Internal => INTERNAL_DUT,
        IsaRam::External => EXTERNAL_DUT,
    };
    format!(
        r#"// ISA bus-functional model and testbench for isa_bridge (motionhdl).
`timescale 1ns / 1ps
`default_nettype none
module isa_bfm_tb;
    localparam integer BALE_NS = {BALE_NS};
    localparam integer COMMAND_DELAY_NS = {COMMAND_DELAY_NS};
    localparam integer WRITE_DATA_DELAY_NS = {WRITE_DATA_DELAY_NS};
    localparam integer WRITE_DATA_HOLD_NS = {WRITE_DATA_HOLD_NS};
    localparam integer ADDRESS_HOLD_NS = {ADDRESS_HOLD_NS};
    localparam integer READ_SETUP_NS = {READ_SETUP_NS};
    localparam [15:0] FLOATING_BUS = 16'h{FLOATING_BUS:04x};

    reg clock = 1'b0;
    reg reset = 1'b0;
    reg [9:0] sa = 10'h0;
    reg [15:0] sd_in = FLOATING_BUS;
    reg ior_n = 1'b1;
    reg iow_n = 1'b1;
    reg aen = 1'b0;
    reg bale = 1'b0;
    reg [7:0] base = 8'h{base:02x};
    reg [9:0] dsp_addr = 10'h0;
    reg [15:0] dsp_wdata = 16'h0;
    reg dsp_we = 1'b0;
    wire [15:0] sd_out;
    wire sd_oe;
    wire iocs16_n;
{dut}
    // 50 MHz: rising edges at 10 ns + k * 20 ns.
    always #10 clock = ~clock;

    reg [63:0] ops [0:{depth}];
    reg [63:0] op;
    reg [15:0] data_setup;
    reg oe_setup;
    integer i;
    integer command_ns;
    integer offset_ps;

    // op: [63:60] kind, [59] AEN, [58:48] command ns, [47:38] port or
    // address, [37:22] data, [21:0] alignment offset in ps.
    initial begin
        $readmemh("ops.hex", ops);
        #0.5;
        for (i = 0; ops[i][63:60] != 4'd0; i = i + 1) begin
            op = ops[i];
            command_ns = {{21'd0, op[58:48]}};
            offset_ps = {{10'd0, op[21:0]}};
            case (op[63:60])
                4'd1, 4'd2: begin
                    sa = op[47:38];
                    aen = op[59];
                    bale = 1'b1;
                    #(BALE_NS);
                    bale = op[59];
                    #(COMMAND_DELAY_NS - BALE_NS);
                    if (op[63:60] == 4'd1) begin
                        iow_n = 1'b0;
                        #(WRITE_DATA_DELAY_NS);
                        sd_in = op[37:22];
                        #(command_ns - WRITE_DATA_DELAY_NS);
                        iow_n = 1'b1;
                        #(WRITE_DATA_HOLD_NS);
                        sd_in = FLOATING_BUS;
                        #(ADDRESS_HOLD_NS - WRITE_DATA_HOLD_NS);
                    end else begin
                        ior_n = 1'b0;
                        #(command_ns - READ_SETUP_NS);
                        oe_setup = sd_oe;
                        data_setup = sd_out;
                        #(READ_SETUP_NS - 1);
                        $display("IO %b %b %h %h", oe_setup, sd_oe, data_setup, sd_out);
                        #1;
                        ior_n = 1'b1;
                        #(ADDRESS_HOLD_NS);
                    end
                    bale = 1'b0;
                end
                4'd3: begin
                    @(negedge clock);
                    dsp_addr = op[47:38];
                    dsp_wdata = op[37:22];
                    dsp_we = 1'b1;
                    @(negedge clock);
                    dsp_we = 1'b0;
                    #0.5;
                end
                4'd4: begin
                    @(negedge clock);
                    dsp_addr = op[47:38];
                    @(negedge clock);
                    $display("DSP %h", dsp_rdata);
                    #0.5;
                end
                4'd5: begin
                    @(posedge clock);
                    #(offset_ps / 1000.0);
                end
                4'd6: begin
                    @(negedge clock);
                    reset = 1'b1;
                    #100;
                    reset = 1'b0;
                    #0.5;
                end
                default: begin
                    $display("bad op %h", op);
                    $finish;
                end
            endcase
        end
        #80;
        $display("DONE");
        $finish;
    end
endmodule
`default_nettype wire
"#,
        depth = ops,
    )
}

fn encode(op: &Op) -> u64 {
    let f = |kind: u64, aen: bool, ns: u64, addr: u16, data: u16, off: u64| {
        assert!(ns < 2048 && off < (1 << 22));
        (kind << 60)
            | (u64::from(aen) << 59)
            | (ns << 48)
            | (u64::from(addr & 0x3ff) << 38)
            | (u64::from(data) << 22)
            | off
    };
    match *op {
        Op::IoWrite {
            port,
            aen,
            data,
            command_ns,
        } => f(1, aen, command_ns, port, data, 0),
        Op::IoRead {
            port,
            aen,
            command_ns,
        } => f(2, aen, command_ns, port, 0, 0),
        Op::DspWrite { addr, data } => f(3, false, 0, addr, data, 0),
        Op::DspRead { addr } => f(4, false, 0, addr, 0, 0),
        Op::Align { offset_ps } => f(5, false, 0, 0, 0, offset_ps),
        Op::Reset => f(6, false, 0, 0, 0, 0),
    }
}

const INTERNAL_DUT: &str = r#"    wire [15:0] dsp_rdata;

    isa_bridge dut (
        .clock(clock), .reset(reset), .sa(sa), .sd_in(sd_in), .sd_out(sd_out),
        .sd_oe(sd_oe), .ior_n(ior_n), .iow_n(iow_n), .aen(aen), .bale(bale),
        .base(base), .iocs16_n(iocs16_n), .dsp_addr(dsp_addr),
        .dsp_wdata(dsp_wdata), .dsp_we(dsp_we), .dsp_rdata(dsp_rdata)
    );
"#;

// The external build with an asynchronous dual-port SRAM model: 35 ns
// access time (garbage, 16'hdead, until then), written when WE# rises; its
// right port is the DSP, clocked here like the internal build's DSP port.
// The array starts undefined; run_verilog zeroes it through the DSP port.
const EXTERNAL_DUT: &str = r#"    wire [9:0] ram_addr;
    wire [15:0] ram_d_out;
    wire ram_d_oe;
    wire ram_ce_n;
    wire ram_oe_n;
    wire ram_we_n;
    reg [15:0] chip_mem [0:1023];
    reg [15:0] chip_q = 16'hdead;
    reg [15:0] dsp_rdata = 16'h0;
    reg [31:0] pc_writes = 0;
    reg [31:0] dsp_writes = 0;
    reg we_n_seen = 1'b1;
    wire [15:0] ram_d_in = ram_d_oe ? ram_d_out
        : (!ram_ce_n && !ram_oe_n && ram_we_n) ? chip_q : 16'hffff;
    always @(ram_addr or ram_oe_n or ram_ce_n or pc_writes or dsp_writes) begin
        chip_q <= 16'hdead;
        chip_q <= #35 chip_mem[ram_addr];
    end
    // One process writes the array: the DSP port, and the left port's
    // write seen one clock after WE# rose (address and data still held).
    always @(posedge clock) begin
        dsp_rdata <= chip_mem[dsp_addr];
        we_n_seen <= ram_we_n;
        if (!we_n_seen && ram_we_n && !ram_ce_n) begin
            chip_mem[ram_addr] <= ram_d_out;
            pc_writes <= pc_writes + 1;
        end
        if (dsp_we) begin
            chip_mem[dsp_addr] <= dsp_wdata;
            dsp_writes <= dsp_writes + 1;
        end
    end

    isa_bridge dut (
        .clock(clock), .reset(reset), .sa(sa), .sd_in(sd_in), .sd_out(sd_out),
        .sd_oe(sd_oe), .ior_n(ior_n), .iow_n(iow_n), .aen(aen), .bale(bale),
        .base(base), .iocs16_n(iocs16_n), .ram_addr(ram_addr), .ram_d_in(ram_d_in),
        .ram_d_out(ram_d_out), .ram_d_oe(ram_d_oe), .ram_ce_n(ram_ce_n),
        .ram_oe_n(ram_oe_n), .ram_we_n(ram_we_n)
    );
"#;

/// Runs `ops` through the generated `isa_bridge.v` under the Verilog ISA
/// bus-functional model. The Verilog RAM starts undefined, so the DSP port
/// first writes 0 to every word (the transaction model starts at 0).
pub fn run_verilog(
    target: impl Into<Target>,
    ram: IsaRam,
    base: u8,
    ops: &[Op],
) -> Result<Vec<Observation>, String> {
    let t = target.into();
    t.available()?;
    let text = t.text(&catalog::isa_bridge(ram))?;
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    let mut all: Vec<Op> = vec![Op::Reset];
    all.extend((0..ISA_RAM_WORDS as u16).map(|addr| Op::DspWrite { addr, data: 0 }));
    all.extend_from_slice(ops);
    let mut hex = String::new();
    for op in &all {
        let _ = writeln!(hex, "{:016x}", encode(op));
    }
    let _ = writeln!(hex, "{:016x}", 0);
    let tb = verilog_testbench(ram, base, all.len());
    fs::write(d.join("tb.v"), tb).map_err(|e| e.to_string())?;
    fs::write(d.join("isa_bridge.v"), text).map_err(|e| e.to_string())?;
    fs::write(d.join("ops.hex"), hex).map_err(|e| e.to_string())?;
    let (stdout, _) = build_and_run(t.sim, d, "isa_bfm_tb", &["tb.v", "isa_bridge.v"], true)?;
    if !stdout.lines().any(|l| l == "DONE") {
        return Err(format!("testbench did not finish:\n{stdout}"));
    }
    stdout
        .lines()
        .filter(|l| l.starts_with("IO ") || l.starts_with("DSP "))
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            let hex16 = |s: &str| {
                u16::from_str_radix(s, 16).map_err(|_| format!("bad value `{s}` in `{l}`"))
            };
            let bit = |s: &str| match s {
                "1" => Ok(true),
                "0" => Ok(false),
                _ => Err(format!("bad bit `{s}` in `{l}`")),
            };
            if w[0] == "IO" {
                let oe_setup = bit(w[1])?;
                let oe_end = bit(w[2])?;
                // Undriven data may print as x; it is not compared.
                Ok(Observation::Io {
                    oe_setup,
                    oe_end,
                    data_setup: if oe_setup { hex16(w[3])? } else { 0 },
                    data_end: if oe_end { hex16(w[4])? } else { 0 },
                })
            } else {
                Ok(Observation::Dsp { data: hex16(w[1])? })
            }
        })
        .collect()
}

/// The base used by the checks: ports 0x300..=0x303, the classic
/// prototype-card range.
pub const TEST_BASE: u8 = 0xc0;

fn port_of(reg: u16) -> u16 {
    m::port(TEST_BASE, reg)
}

/// A port on another card: SA9..SA2 differ from the base.
fn other_port(reg: u16) -> u16 {
    m::port(TEST_BASE ^ 0x5a, reg)
}

fn standard_write(reg: u16, data: u16) -> Op {
    Op::IoWrite {
        port: port_of(reg),
        aen: false,
        data,
        command_ns: STANDARD_COMMAND_NS,
    }
}

fn standard_read(reg: u16) -> Op {
    Op::IoRead {
        port: port_of(reg),
        aen: false,
        command_ns: STANDARD_COMMAND_NS,
    }
}

/// Phases of the bus against the FPGA clock: every whole nanosecond of the
/// 20 ns period, half a nanosecond off the edges (events are whole ns, so
/// these are all the distinct sampling patterns).
pub fn phases() -> impl Iterator<Item = u64> {
    (0..CLOCK_PS / 1000).map(|ns| ns * 1000 + 500)
}

/// Number of cases of [`exhaustive_ops`]:
/// register × read/write × AEN × match × phase × command length × AUTO_INC.
pub const EXHAUSTIVE_CASES: u64 = 4 * 2 * 2 * 2 * 20 * COMMAND_NS.len() as u64 * 2;

/// Every register × read/write × AEN × address match × strobe phase ×
/// command length × AUTO_INC, each case set up from reset, then observed by
/// reading STATUS and DATA from the PC and three words from the DSP.
pub fn exhaustive_ops() -> (Vec<Op>, u64) {
    let mut ops = Vec::new();
    let mut cases = 0;
    for phase in phases() {
        for &command_ns in &COMMAND_NS {
            for reg in 0..4u16 {
                for write in [false, true] {
                    for aen in [false, true] {
                        for matched in [false, true] {
                            for auto_inc in [false, true] {
                                let port = if matched {
                                    port_of(reg)
                                } else {
                                    other_port(reg)
                                };
                                let start = 5 | if auto_inc { status::AUTO_INC } else { 0 };
                                ops.extend([
                                    Op::Reset,
                                    Op::DspWrite {
                                        addr: 0,
                                        data: 0x9abc,
                                    },
                                    Op::DspWrite {
                                        addr: 5,
                                        data: 0x1234,
                                    },
                                    Op::DspWrite {
                                        addr: 6,
                                        data: 0x5678,
                                    },
                                    Op::Align { offset_ps: phase },
                                    standard_write(reg::STATUS, start),
                                    Op::Align { offset_ps: phase },
                                    if write {
                                        Op::IoWrite {
                                            port,
                                            aen,
                                            data: 0xc3a5,
                                            command_ns,
                                        }
                                    } else {
                                        Op::IoRead {
                                            port,
                                            aen,
                                            command_ns,
                                        }
                                    },
                                    Op::Align { offset_ps: phase },
                                    standard_read(reg::STATUS),
                                    Op::Align { offset_ps: phase },
                                    standard_read(reg::DATA),
                                    Op::DspRead { addr: 0 },
                                    Op::DspRead { addr: 5 },
                                    Op::DspRead { addr: 6 },
                                ]);
                                cases += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    (ops, cases)
}

/// A whole 2 KB block from the PC, read back by the PC and by the DSP;
/// then a block from the DSP read by the PC. `auto_inc` false is the seed's
/// way (DATA then ADDR_INC for every word), true the one-access-per-word
/// extension. `pattern` makes every run's data distinct.
pub fn block_transfer_ops(auto_inc: bool, pattern: u16) -> Vec<Op> {
    let word = |i: u16| i.wrapping_mul(0x9e37) ^ pattern;
    let mut ops = vec![Op::Reset];
    let start = |ops: &mut Vec<Op>| {
        ops.push(standard_write(reg::ADDR_CLEAR, 0));
        if auto_inc {
            ops.push(standard_write(reg::STATUS, status::AUTO_INC));
        }
    };
    start(&mut ops);
    for i in 0..ISA_RAM_WORDS as u16 {
        ops.push(standard_write(reg::DATA, word(i)));
        if !auto_inc {
            ops.push(standard_write(reg::ADDR_INC, 0));
        }
    }
    ops.push(standard_read(reg::STATUS));
    start(&mut ops);
    for _ in 0..ISA_RAM_WORDS {
        ops.push(standard_read(reg::DATA));
        if !auto_inc {
            ops.push(standard_read(reg::ADDR_INC));
        }
    }
    for addr in 0..ISA_RAM_WORDS as u16 {
        ops.push(Op::DspRead { addr });
    }
    // The other way: the DSP fills the RAM, the PC reads it.
    for addr in 0..ISA_RAM_WORDS as u16 {
        ops.push(Op::DspWrite {
            addr,
            data: !word(addr),
        });
    }
    start(&mut ops);
    for _ in 0..ISA_RAM_WORDS {
        ops.push(standard_read(reg::DATA));
        if !auto_inc {
            ops.push(standard_write(reg::ADDR_INC, 0));
        }
    }
    ops.push(standard_read(reg::STATUS));
    ops
}

/// Compares observations with the transaction model, one case per read.
fn compare(r: &mut CheckReport, got: &[Observation], want: &[Observation], ops: &[Op]) {
    if got.len() != want.len() {
        r.case(Some(format!(
            "{} reads observed, {} expected",
            got.len(),
            want.len()
        )));
        return;
    }
    let reads: Vec<&Op> = ops
        .iter()
        .filter(|o| matches!(o, Op::IoRead { .. } | Op::DspRead { .. }))
        .collect();
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        if !same(g, w) {
            r.failures.push(format!(
                "read #{k} ({:?}): observed {g:?}, transaction model {w:?}",
                reads.get(k)
            ));
        }
    }
}

fn build_name(ram: IsaRam) -> &'static str {
    match ram {
        IsaRam::Internal => "isa_bridge (internal RAM)",
        IsaRam::External => "isa_bridge (external SRAM)",
    }
}

/// Runs `ops` in the rust-hdl block of the `ram` build against its cycle
/// model and the transaction model; `cases` is how many cases the ops make.
pub fn check_rust(ram: IsaRam, name: &str, ops: &[Op], cases: u64) -> (CheckReport, RustRun) {
    let mut r = CheckReport::new(
        build_name(ram),
        &format!("{name}: rust-hdl vs cycle model every clock, reads vs transaction model"),
        cases,
    );
    let run = run_rust(ram, TEST_BASE, ops, None);
    r.failures.extend(run.mismatches.iter().cloned());
    compare(&mut r, &run.observations, &expected(TEST_BASE, ops), ops);
    r.covered = cases;
    (r, run)
}

/// Runs `ops` in the generated Verilog against the transaction model.
pub fn check_verilog(
    target: impl Into<Target>,
    ram: IsaRam,
    name: &str,
    ops: &[Op],
    cases: u64,
) -> CheckReport {
    let t = target.into();
    let mut r = CheckReport::new(
        build_name(ram),
        &format!(
            "{name}: {} under the Verilog ISA BFM vs transaction model",
            t.describe()
        ),
        cases,
    );
    match run_verilog(t, ram, TEST_BASE, ops) {
        Ok(got) => {
            compare(&mut r, &got, &expected(TEST_BASE, ops), ops);
            r.covered = cases;
        }
        Err(e) if t.available().is_err() => return r.skip(e),
        Err(e) => r.failures.push(e),
    }
    r
}

const EXHAUSTIVE_NAME: &str =
    "register x read/write x AEN x match x phase x command length x AUTO_INC";

/// The exhaustive case set in the rust-hdl block.
pub fn exhaustive_rust(ram: IsaRam) -> CheckReport {
    let (ops, cases) = exhaustive_ops();
    assert_eq!(cases, EXHAUSTIVE_CASES);
    check_rust(ram, EXHAUSTIVE_NAME, &ops, cases).0
}

/// The exhaustive case set in the generated Verilog.
pub fn exhaustive_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let (ops, cases) = exhaustive_ops();
    assert_eq!(cases, EXHAUSTIVE_CASES);
    check_verilog(target, ram, EXHAUSTIVE_NAME, &ops, cases)
}

/// Words moved and checked by [`block_transfers`]: 2 runs × 3 × 1024.
pub const BLOCK_TRANSFER_WORDS: u64 = 2 * 3 * ISA_RAM_WORDS as u64;

fn block_transfers(pattern: u16) -> Vec<Op> {
    let mut ops = block_transfer_ops(false, pattern);
    ops.extend(block_transfer_ops(true, pattern ^ 0x5555));
    ops
}

/// Block transfers, both ways, both counter styles; one case per word
/// moved and checked.
pub fn block_transfer_rust(ram: IsaRam) -> CheckReport {
    let ops = block_transfers(0x1111);
    check_rust(
        ram,
        "2 KB block transfers both ways",
        &ops,
        BLOCK_TRANSFER_WORDS,
    )
    .0
}

/// Block transfers in the generated Verilog.
pub fn block_transfer_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let ops = block_transfers(0x3333);
    check_verilog(
        target,
        ram,
        "2 KB block transfers both ways",
        &ops,
        BLOCK_TRANSFER_WORDS,
    )
}

/// Every ISA bridge check for both builds; external simulators only when
/// `external` is set.
pub fn all(external: bool) -> Vec<CheckReport> {
    let mut v = Vec::new();
    for ram in [IsaRam::Internal, IsaRam::External] {
        v.push(exhaustive_rust(ram));
        v.push(block_transfer_rust(ram));
        v.push(random_rust(ram));
    }
    v.push(collision_check(None));
    if external {
        for sim in [Simulator::Icarus, Simulator::Verilator] {
            for ram in [IsaRam::Internal, IsaRam::External] {
                v.push(exhaustive_verilog(sim, ram));
                v.push(block_transfer_verilog(sim, ram));
                v.push(random_verilog(sim, ram));
            }
            v.push(collision_check(Some(sim.into())));
        }
    }
    v
}

pub use crate::harness::Rng;

/// Random bus traffic: I/O reads and writes of every register with random
/// data, command lengths (110..=600 ns) and phases; cycles to other cards'
/// ports and DMA cycles (AEN high) to this card's ports, which must change
/// nothing; DSP reads and writes between bus cycles (a DSP write lands
/// three clocks clear of any PC write, so the order is the op order).
pub fn random_ops(seed: u64, n: usize) -> Vec<Op> {
    let mut rng = Rng::new(seed);
    let mut ops = vec![Op::Reset];
    for _ in 0..n {
        let offset_ps = rng.below(20) * 1000 + HALF_NS;
        match rng.below(10) {
            0..=6 => {
                let reg = rng.below(4) as u16;
                let (port, aen) = match rng.below(10) {
                    0 => (other_port(reg), false),
                    1 => (port_of(reg), true),
                    _ => (port_of(reg), false),
                };
                let command_ns = 110 + rng.below(491);
                // STATUS writes mostly turn AUTO_INC on, so runs move.
                let data = rng.next_u64() as u16;
                ops.push(Op::Align { offset_ps });
                ops.push(if rng.below(2) == 0 {
                    Op::IoRead {
                        port,
                        aen,
                        command_ns,
                    }
                } else {
                    Op::IoWrite {
                        port,
                        aen,
                        data,
                        command_ns,
                    }
                });
            }
            7 => {
                ops.push(Op::Align { offset_ps });
                ops.push(Op::Align { offset_ps });
                ops.push(Op::DspWrite {
                    addr: rng.below(u64::from(ISA_RAM_WORDS)) as u16,
                    data: rng.next_u64() as u16,
                });
            }
            8 => ops.push(Op::DspRead {
                addr: rng.below(u64::from(ISA_RAM_WORDS)) as u16,
            }),
            _ => {
                // Concentrate on a few words so reads meet earlier writes.
                ops.push(Op::Align { offset_ps });
                ops.push(standard_write(
                    reg::STATUS,
                    rng.below(4) as u16 | status::AUTO_INC,
                ));
            }
        }
    }
    ops.push(Op::Align { offset_ps: HALF_NS });
    ops.push(standard_read(reg::STATUS));
    ops
}

/// Seed and length of the long random run that goes through every simulator.
pub const LONG_RANDOM: (u64, usize) = (0x15a_b1d6e, 3000);

/// The long random run in the rust-hdl block; one case per op.
pub fn random_rust(ram: IsaRam) -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_rust(ram, "random bus traffic", &ops, ops.len() as u64).0
}

/// The long random run in the generated Verilog.
pub fn random_verilog(target: impl Into<Target>, ram: IsaRam) -> CheckReport {
    let ops = random_ops(LONG_RANDOM.0, LONG_RANDOM.1);
    check_verilog(target, ram, "random bus traffic", &ops, ops.len() as u64)
}

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
        ports_of(
            m,
            &[
                "reset",
                "sa",
                "sd_in",
                "ior_n",
                "iow_n",
                "aen",
                "bale",
                "base",
                "dsp_addr",
                "dsp_wdata",
                "dsp_we",
            ],
        ),
        ports_of(m, &["sd_out", "sd_oe", "iocs16_n", "dsp_rdata"]),
    )
}

fn encode_vector((p, reset): &IsaPinsAndReset) -> Vec<u64> {
    vec![
        u64::from(*reset),
        u64::from(p.sa),
        u64::from(p.sd_in),
        u64::from(p.ior_n),
        u64::from(p.iow_n),
        u64::from(p.aen),
        u64::from(p.bale),
        u64::from(p.base),
        u64::from(p.dsp_addr),
        u64::from(p.dsp_wdata),
        u64::from(p.dsp_we),
    ]
}

/// The same-clock write rule in the model alone, checked against the
/// documented rule (not against the model): after the collision the word
/// holds the PC's value, STATUS.COLLISION is set; without it, both words
/// hold what was written and COLLISION is clear. Returns the model's
/// outputs per vector for the HDL comparisons.
pub fn collision_expected(same_word: bool) -> Result<Vec<m::IsaOutputs>, String> {
    let vectors = collision_vectors(same_word);
    let mut model = IsaBridgeModel::new();
    let mut outs = Vec::new();
    let mut saw_wait = false;
    for (p, reset) in &vectors {
        outs.push(model.outputs(p));
        if model.write_pending() && p.dsp_we {
            saw_wait = true;
        }
        model.clock(p, *reset);
    }
    let last = outs.last().copied().unwrap_or_default();
    let (a, b) = (model.ram()[0x155], model.ram()[0x156]);
    let collided = model.status() & status::COLLISION != 0;
    let ok = if same_word {
        saw_wait && a == 0xbeef && collided && last.dsp_rdata == 0xbeef && last.sd_out == 0xbeef
    } else {
        saw_wait && a == 0xbeef && b == 0x1005 && !collided
    };
    if ok {
        Ok(outs)
    } else {
        Err(format!(
            "same word {same_word}: DSP wrote while the PC write waited {saw_wait}, \
             word A {a:#06x}, word A+1 {b:#06x}, COLLISION {collided}, last outputs {last:?}"
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
    let want = expected(TEST_BASE, ops);
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
    scenario_trace("isa_block_write", &ops)
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
    scenario_trace("isa_block_read", &ops)
}
