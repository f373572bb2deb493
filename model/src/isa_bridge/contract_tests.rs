//! Contract tests from docs/isa_bridge.md, driven through the public API:
//! the transaction model (`IsaCard`) and both cycle models, the latter by a
//! bus-functional host that moves the pins one clock edge at a time.

use super::*;

const BASE: u8 = 0x5a;
/// A neighbour card: its ports sit right above ours.
const OTHER: u8 = BASE + 1;
/// What the external chip model returns before its access time; the prefetch
/// must never take it (test data avoids the value).
const GARBAGE: u16 = 0xdead;
/// Clocks of a command: 110 ns at 50 MHz, rounded up.
const CMD: u32 = 6;
/// Idle clocks after a strobe rises: with the 3 clocks of BALE, 12 edges
/// before the next command, more than the external build's 11.
const GAP: u32 = 9;

fn p(reg: u16) -> u16 {
    port(BASE, reg)
}

/// The pins between cycles, with SA on our DATA port so `sd_out` shows the
/// prefetch register.
fn probe() -> IsaPins {
    IsaPins {
        sa: p(reg::DATA),
        ..IsaPins::idle(BASE)
    }
}

/// What the host needs from either build.
trait Dut {
    fn edge(&mut self, pins: &IsaPins);
    /// (sd_out, sd_oe, iocs16_n).
    fn bus(&self, pins: &IsaPins) -> (u16, bool, bool);
    fn irq(&self) -> bool;
    /// High in the clock before the edge at which the PC's mailbox write lands.
    fn bell_to_dsp(&self, pins: &IsaPins) -> bool;
    fn counter(&self) -> u16;
    fn status(&self) -> u16;
    /// The DSP port's read data, where the build has one.
    fn dsp_rdata(&self) -> Option<u16>;
    fn ram(&self) -> Vec<u16>;
}

impl Dut for IsaBridgeModel {
    fn edge(&mut self, pins: &IsaPins) {
        self.clock(pins, false);
    }
    fn bus(&self, pins: &IsaPins) -> (u16, bool, bool) {
        let o = self.outputs(pins);
        (o.sd_out, o.sd_oe, o.iocs16_n)
    }
    fn irq(&self) -> bool {
        self.outputs(&probe()).irq
    }
    fn bell_to_dsp(&self, pins: &IsaPins) -> bool {
        self.outputs(pins).bell_to_dsp
    }
    fn counter(&self) -> u16 {
        IsaBridgeModel::counter(self)
    }
    fn status(&self) -> u16 {
        IsaBridgeModel::status(self)
    }
    fn dsp_rdata(&self) -> Option<u16> {
        Some(self.outputs(&probe()).dsp_rdata)
    }
    fn ram(&self) -> Vec<u16> {
        IsaBridgeModel::ram(self).to_vec()
    }
}

/// The external build beside a model of the dual-port SRAM's left port that
/// flags the faults the docs list: garbage before the 2-clock access time,
/// WE# pulses other than 2 clocks, address or data moving under WE#, missing
/// set-up or hold, and bus contention. The DSP's writes (pins `dsp_*`) go
/// straight into the chip through its other port.
struct Sram {
    m: IsaBridgeExternalModel,
    mem: Vec<u16>,
    /// The pins of the clock before the current one.
    prev: SramPins,
    we_low: u32,
}

impl Sram {
    fn new() -> Self {
        let m = IsaBridgeExternalModel::new();
        Self {
            prev: m.sram(),
            m,
            mem: vec![0; WORDS],
            we_low: 0,
        }
    }
}

fn reading(s: &SramPins) -> bool {
    !s.ce_n && !s.oe_n && s.we_n
}

impl Dut for Sram {
    fn edge(&mut self, pins: &IsaPins) {
        let cur = self.m.sram();
        assert!(!(cur.d_oe && reading(&cur)), "bus contention: {cur:?}");
        let d_in = if cur.d_oe {
            cur.d_out
        } else if reading(&cur) && reading(&self.prev) && cur.addr == self.prev.addr {
            self.mem[usize::from(cur.addr)]
        } else {
            GARBAGE
        };
        self.m.clock(pins, false, d_in);
        if pins.dsp_we {
            self.mem[usize::from(pins.dsp_addr)] = pins.dsp_wdata;
        }
        let next = self.m.sram();
        let held = (next.addr, next.d_out, next.d_oe) == (cur.addr, cur.d_out, true);
        if !next.we_n {
            // Under WE#: OE# high, and address and data as in the clock
            // before (the set-up clock, then the first pulse clock).
            assert!(
                held && cur.oe_n && next.oe_n && !next.ce_n,
                "{cur:?} -> {next:?}"
            );
            self.we_low += 1;
        } else if !cur.we_n {
            assert_eq!(self.we_low, 2, "WE# pulse length, ending {cur:?}");
            assert!(held, "no hold after WE#: {cur:?} -> {next:?}");
            self.mem[usize::from(cur.addr)] = cur.d_out;
            self.we_low = 0;
        }
        self.prev = cur;
        let (prefetch, _, _) = self.m.outputs(&probe());
        assert_ne!(prefetch, GARBAGE, "the prefetch took garbage");
    }
    fn bus(&self, pins: &IsaPins) -> (u16, bool, bool) {
        self.m.outputs(pins)
    }
    fn irq(&self) -> bool {
        self.m.irq()
    }
    fn bell_to_dsp(&self, _: &IsaPins) -> bool {
        self.m.bell_to_dsp()
    }
    fn counter(&self) -> u16 {
        self.m.counter()
    }
    fn status(&self) -> u16 {
        self.m.core().status()
    }
    fn dsp_rdata(&self) -> Option<u16> {
        None
    }
    fn ram(&self) -> Vec<u16> {
        self.mem.clone()
    }
}

/// A bus-functional ISA host: sets the pins and clocks the bridge.
struct Host<D> {
    dut: D,
    pins: IsaPins,
    /// Clocks in which `bell_to_dsp` was high.
    bells: u32,
}

impl<D: Dut> Host<D> {
    fn new(dut: D) -> Self {
        Self {
            dut,
            pins: IsaPins::idle(BASE),
            bells: 0,
        }
    }

    fn edge(&mut self) {
        self.bells += u32::from(self.dut.bell_to_dsp(&self.pins));
        self.dut.edge(&self.pins);
        self.pins.dsp_we = false;
    }

    fn edges(&mut self, n: u32) {
        (0..n).for_each(|_| self.edge());
    }

    /// BALE with the address, then the strobe low for `CMD` edges; SD is not
    /// valid yet at the first edge of a write. Stops with the strobe still
    /// low and returns IOCS16# as seen during the command.
    fn command(&mut self, port: u16, aen: bool, write: Option<u16>) -> bool {
        self.pins.sa = port;
        self.pins.aen = aen;
        self.pins.bale = true;
        self.edges(3);
        self.pins.bale = false;
        match write {
            Some(data) => {
                self.pins.iow_n = false;
                self.pins.sd_in = !data;
                self.edge();
                self.pins.sd_in = data;
                self.edges(CMD - 1);
            }
            None => {
                self.pins.ior_n = false;
                self.edges(CMD);
            }
        }
        self.dut.bus(&self.pins).2
    }

    /// The strobe rises (no edge yet); SD turns to garbage and SA moves on.
    fn rise(&mut self) {
        self.pins.ior_n = true;
        self.pins.iow_n = true;
        self.pins.sd_in ^= 0x5555;
        self.pins.sa = 0;
        self.pins.aen = false;
    }

    /// A whole cycle: returns (answered, read data when the card drove SD).
    fn cycle(&mut self, port: u16, aen: bool, write: Option<u16>) -> (bool, Option<u16>) {
        let iocs16_n = self.command(port, aen, write);
        let (sd, oe, _) = self.dut.bus(&self.pins);
        self.rise();
        self.edges(GAP);
        (!iocs16_n, oe.then_some(sd))
    }

    fn write(&mut self, reg: u16, data: u16) {
        self.cycle(p(reg), false, Some(data));
    }

    fn read(&mut self, reg: u16) -> u16 {
        let (_, data) = self.cycle(p(reg), false, None);
        data.unwrap_or_else(|| panic!("no data from register {reg}"))
    }

    /// The DSP writes one word at the next edge.
    fn dsp_write(&mut self, addr: u16, data: u16) {
        self.pins.dsp_addr = addr;
        self.pins.dsp_wdata = data;
        self.pins.dsp_we = true;
        self.edge();
    }

    /// What `sd_out` shows on the DATA port now.
    fn prefetch(&self) -> u16 {
        self.dut.bus(&probe()).0
    }
}

fn internal() -> Host<IsaBridgeModel> {
    Host::new(IsaBridgeModel::new())
}

/// xorshift64: a fixed-seed source of bus traffic.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u16 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n) as u16
    }
    fn data(&mut self) -> u16 {
        match self.below(1 << 16) {
            GARBAGE => 0,
            d => d,
        }
    }
}

/// How often the random traffic hit each feature of the contract.
#[derive(Debug, Default)]
struct Coverage {
    steps: u32,
    answered: u32,
    ignored: u32,
    nonzero_reads: u32,
    dsp_bells: u32,
    irq_high: u32,
    wrapped: u32,
    dsp_reads: u32,
}

/// Random ISA cycles (every register, DMA cycles, other cards' ports) with
/// DSP traffic between them; after each step the cycle model must agree with
/// the transaction model on the read data, STATUS, the counter, the IRQ line
/// and the DSP doorbell, and at the end on the whole RAM.
fn random_traffic_matches_the_card<D: Dut>(dut: D, mut card: IsaCard, steps: u32) -> Coverage {
    let mut host = Host::new(dut);
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut cov = Coverage::default();
    for step in 0..steps {
        let reg = rng.below(4);
        let aen = rng.below(8) == 0;
        let port = if rng.below(8) == 0 {
            port(OTHER, reg)
        } else {
            p(reg)
        };
        let write = (rng.below(2) == 0).then(|| match reg {
            // STATUS loads aimed at the top words, where the counter wraps
            // and the mailboxes sit.
            reg::STATUS => {
                let top = [rng.below(1024), 0x3fd, mailbox::TO_PC, mailbox::TO_DSP];
                top[usize::from(rng.below(4))] | (rng.data() & !status::ADDR_MASK)
            }
            _ => rng.data(),
        });
        let (answered, got) = host.cycle(port, aen, write);
        let want_answer = match write {
            Some(data) => card.io_write(port, aen, data),
            None => {
                let want = card.io_read(port, aen);
                cov.nonzero_reads += u32::from(want.is_some_and(|w| w > 1));
                assert_eq!(got, want, "step {step}: read {port:#x} aen {aen}");
                want.is_some()
            }
        };
        let ctx = format!("step {step}: {port:#x} aen {aen} write {write:x?}");
        assert_eq!(answered, want_answer, "{ctx}");
        cov.answered += u32::from(answered);
        cov.ignored += u32::from(!answered);
        let rang = std::mem::take(&mut host.bells);
        assert!(rang <= 1, "{ctx}: {rang} bell clocks");
        assert_eq!(rang == 1, card.take_dsp_bell(), "{ctx}: bell_to_dsp");
        cov.dsp_bells += rang;
        if rng.below(4) == 0 {
            let targets = [
                mailbox::TO_PC,
                mailbox::TO_DSP,
                card.address(),
                rng.below(1024),
            ];
            let (addr, data) = (targets[usize::from(rng.below(4))], rng.data());
            host.dsp_write(addr, data);
            card.dsp_write(addr, data);
        }
        if rng.below(4) == 0 {
            let addr = rng.below(1024);
            host.pins.dsp_addr = addr;
            host.edge();
            if let Some(rdata) = host.dut.dsp_rdata() {
                assert_eq!(
                    rdata,
                    card.dsp_read(addr),
                    "step {step}: DSP read {addr:#x}"
                );
                cov.dsp_reads += 1;
            }
        }
        assert_eq!(host.dut.status(), card.status(), "{ctx}: STATUS");
        assert_eq!(host.dut.counter(), card.address(), "{ctx}: counter");
        assert_eq!(host.dut.irq(), card.irq(), "{ctx}: irq");
        cov.irq_high += u32::from(card.irq());
        cov.wrapped += u32::from(card.status() & status::WRAPPED != 0);
        cov.steps += 1;
    }
    assert!(
        host.dut.ram() == card.ram(),
        "RAM differs after {steps} steps"
    );
    cov
}

#[test]
fn internal_build_follows_the_transaction_model_under_random_traffic() {
    let cov = random_traffic_matches_the_card(IsaBridgeModel::new(), IsaCard::new(BASE), 1500);
    assert_eq!(cov.steps, 1500, "{cov:?}");
    for (what, n) in [
        ("answered", cov.answered),
        ("ignored", cov.ignored),
        ("nonzero reads", cov.nonzero_reads),
        ("DSP bells", cov.dsp_bells),
        ("IRQ high", cov.irq_high),
        ("WRAPPED", cov.wrapped),
        ("DSP reads", cov.dsp_reads),
    ] {
        assert!(n >= 5, "{what} covered only {n} times: {cov:?}");
    }
}

#[test]
fn external_build_follows_the_transaction_model_under_random_traffic() {
    let card = IsaCard::with_external_ram(BASE);
    let cov = random_traffic_matches_the_card(Sram::new(), card, 1500);
    assert_eq!(cov.steps, 1500, "{cov:?}");
    assert_eq!(cov.irq_high, 0, "the external build never rings the PC");
    for (what, n) in [
        ("answered", cov.answered),
        ("ignored", cov.ignored),
        ("nonzero reads", cov.nonzero_reads),
        ("DSP bells", cov.dsp_bells),
        ("WRAPPED", cov.wrapped),
    ] {
        assert!(n >= 5, "{what} covered only {n} times: {cov:?}");
    }
}

#[test]
fn the_idle_bus_drives_nothing_and_iocs16_follows_sa_and_aen_only() {
    let (int_model, ext_model) = (IsaBridgeModel::new(), IsaBridgeExternalModel::new());
    let mut cases = 0;
    for sa in 0..1024 {
        for aen in [false, true] {
            let idle = IsaPins {
                sa,
                aen,
                ..IsaPins::idle(BASE)
            };
            let reading = IsaPins {
                ior_n: false,
                ..idle
            };
            let decoded = sa >> 2 == u16::from(BASE) && !aen;
            // Idle: no strobe, so SD stays undriven; IOR# low drives it on a match.
            for (pins, sd_oe) in [(idle, false), (reading, decoded)] {
                let want = (sd_oe, !decoded);
                let int = int_model.outputs(&pins);
                let (_, ext_oe, ext_cs) = ext_model.outputs(&pins);
                assert_eq!((int.sd_oe, int.iocs16_n), want, "internal {pins:x?}");
                assert_eq!((ext_oe, ext_cs), want, "external {pins:x?}");
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 2048);
}

#[test]
fn a_read_cycle_does_not_take_the_data_on_sd_as_a_write() {
    // Another device drives SD while this card only sees IOR# pulses.
    let mut host = internal();
    host.pins.sd_in = 0x1155;
    host.edges(4);
    let mut reads = vec![];
    for reg in [reg::STATUS, reg::ADDR_CLEAR, reg::DATA] {
        host.pins.sd_in = 0x1155;
        reads.push(host.read(reg));
    }
    assert_eq!(reads, [0, 0, 0]);
    assert_eq!((host.dut.status(), host.dut.ram()[0]), (0, 0));
}

/// Cycle-level timing of the internal build (docs: Timing, Doorbells, The
/// DSP port and same-clock writes), clock edge by clock edge.
mod timing;

/// The transaction model's own contract, and the external build's SRAM port.
mod card_and_sram;
