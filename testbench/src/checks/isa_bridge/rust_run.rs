//! The rust-hdl bridge and its cycle model stepped together through the
//! bus-functional model's events, in continuous time: HDL vs model at
//! every clock edge, with the external build's RAM chip modelled here.

use crate::bfm::isa::{timeline, Event, Observation, Op, CLOCK_PS, FIRST_EDGE_PS, FLOATING_BUS};
use crate::harness::settle;
use motionhdl_hdl::{IsaBridge, IsaBridgeExternal};
use motionhdl_model::isa_bridge::{
    self as m, IsaBridgeExternalModel, IsaBridgeModel, IsaPins, SramPins,
};
use motionhdl_model::regmap::ISA_RAM_WORDS;
use motionhdl_model::IsaRam;
use rust_hdl::prelude::{Block, Clock, In, Signal};

/// The rust-hdl block and the cycle model stepped together through `ops`.
pub struct RustRun {
    /// What the reads observed (from the HDL).
    pub observations: Vec<Observation>,
    /// Clock edges simulated.
    pub clocks: u64,
    /// HDL/model disagreements and SRAM contract violations (first few),
    /// with the time.
    pub mismatches: Vec<String>,
    /// Rises of the HDL's `irq` line (the DSP rang, IRQ enabled).
    pub irq_rises: u64,
    /// Clocks with the HDL's `bell_to_dsp` high (the PC rang).
    pub bells_to_dsp: u64,
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
pub(super) trait Bench {
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

pub(super) fn set_pins(uut: &mut IsaBridge, p: &IsaPins, reset: bool) {
    set_bus_pins!(&mut *uut, p, reset);
    uut.dsp_addr.next = u64::from(p.dsp_addr).into();
    uut.dsp_wdata.next = u64::from(p.dsp_wdata).into();
    uut.dsp_we.next = p.dsp_we;
}

pub(super) fn hdl_outputs(uut: &IsaBridge) -> m::IsaOutputs {
    m::IsaOutputs {
        sd_out: uut.sd_out.val().index() as u16,
        sd_oe: uut.sd_oe.val(),
        iocs16_n: uut.iocs16_n.val(),
        dsp_rdata: uut.dsp_rdata.val().index() as u16,
        irq: uut.irq.val(),
        bell_to_dsp: uut.bell_to_dsp.val(),
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

/// The ISA side of a build with the external SRAM: the bridge alone, or
/// a top that contains it (its ISA and SRAM pins must then behave as the
/// bridge's).
pub(super) trait ExternalIsa: Block {
    /// The bus pins, reset and the SRAM's data pins; settles.
    fn set(&mut self, pins: &IsaPins, reset: bool, d_in: u16);
    /// (sd_out, sd_oe, iocs16_n, irq, bell_to_dsp).
    fn bus(&self) -> (u16, bool, bool, bool, bool);
    fn sram_pins(&self) -> SramPins;
    fn counter(&self) -> u16;
    fn clock_pin(&mut self) -> &mut Signal<In, Clock>;
}

impl ExternalIsa for IsaBridgeExternal {
    fn set(&mut self, pins: &IsaPins, reset: bool, d_in: u16) {
        set_bus_pins!(&mut *self, pins, reset);
        self.ram_d_in.next = u64::from(d_in).into();
        settle(self);
    }
    fn bus(&self) -> (u16, bool, bool, bool, bool) {
        (
            self.sd_out.val().index() as u16,
            self.sd_oe.val(),
            self.iocs16_n.val(),
            self.irq.val(),
            self.bell_to_dsp.val(),
        )
    }
    fn sram_pins(&self) -> SramPins {
        SramPins {
            addr: self.ram_addr.val().index() as u16,
            d_out: self.ram_d_out.val().index() as u16,
            d_oe: self.ram_d_oe.val(),
            ce_n: self.ram_ce_n.val(),
            oe_n: self.ram_oe_n.val(),
            we_n: self.ram_we_n.val(),
        }
    }
    fn counter(&self) -> u16 {
        IsaBridgeExternal::counter(self)
    }
    fn clock_pin(&mut self) -> &mut Signal<In, Clock> {
        &mut self.clock
    }
}

/// The build for an external dual-port SRAM, with the chip.
pub(super) struct ExternalBench<U: ExternalIsa> {
    uut: U,
    model: IsaBridgeExternalModel,
    chip: DualPortSram,
    /// The data pins were valid RAM data at the previous edge.
    sample_valid: bool,
}

impl<U: ExternalIsa> ExternalBench<U> {
    /// `uut` (connected) beside a fresh model and SRAM chip.
    pub(super) fn new(mut uut: U) -> Self {
        uut.connect_all();
        Self {
            uut,
            model: IsaBridgeExternalModel::new(),
            chip: DualPortSram::new(),
            sample_valid: false,
        }
    }
    fn set(&mut self, pins: &IsaPins, reset: bool, k: u64) {
        let d_in = self.chip.data_pins(k);
        self.uut.set(pins, reset, d_in);
    }
    fn outputs(&self) -> m::IsaOutputs {
        let (sd_out, sd_oe, iocs16_n, irq, bell_to_dsp) = self.uut.bus();
        m::IsaOutputs {
            sd_out,
            sd_oe,
            iocs16_n,
            dsp_rdata: self.chip.dsp_rdata,
            irq,
            bell_to_dsp,
        }
    }
}

impl<U: ExternalIsa> Bench for ExternalBench<U> {
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
                irq: self.model.irq(),
                bell_to_dsp: self.model.bell_to_dsp(),
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
        rising_edge(&mut self.uut, |u| u.clock_pin());
        self.model.clock(pins, reset, d_in);
        let hdl = self.uut.sram_pins();
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
        Some(self.uut.sram_pins())
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
        IsaRam::External => run_bench(
            ExternalBench::new(IsaBridgeExternal::new()),
            base,
            ops,
            hook,
        ),
    }
}

pub(super) fn run_bench(
    mut bench: impl Bench,
    base: u8,
    ops: &[Op],
    mut hook: Option<EdgeHook>,
) -> RustRun {
    let (events, end) = timeline(base, ops);
    let mut pins = IsaPins::idle(base);
    let mut reset = false;
    let mut run = RustRun {
        observations: Vec::new(),
        clocks: 0,
        mismatches: Vec::new(),
        irq_rises: 0,
        bells_to_dsp: 0,
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
    let mut last_irq = false;
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
        run.irq_rises += u64::from(o.irq && !last_irq);
        run.bells_to_dsp += u64::from(o.bell_to_dsp);
        last_irq = o.irq;
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
