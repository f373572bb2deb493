//! `FsmcBridgeModel` driven through its pins with the mode-1 waveform, one
//! FPGA clock per step, against docs/fsmc_bridge.md ("Pins and ports",
//! "Accesses", "Synchronisers and latency").

use super::*;

/// Clocks of the address phase (NOE#/NWE# high, NE1# low): one is the
/// least an FPGA edge is sure to sample (ADDSET 4 = 23.8 ns).
const ADDSET_CLOCKS: usize = 1;
/// Clocks of the strobe (DATAST 21 = 125 ns): the read data must be on
/// `d_out` before the last one's edge.
const DATAST_CLOCKS: usize = 6;
/// Clocks with NE1# high after a transaction: the write lands at the
/// third edge after NWE# is first sampled high.
const IDLE_CLOCKS: usize = 4;
/// Live registers, as the testbench's slave: words 0x3f0..=0x3ff change
/// every clock and have equal halves.
const LIVE_WORDS: u16 = 0x3f0;

/// A slave with the register port's two-edge read and the RAM port's
/// "word at the previous edge's address" read; it counts every strobe.
struct Slave {
    regs: Vec<u32>,
    ram: Vec<u16>,
    clocks: u32,
    pending: Option<u16>,
    reg_rdata: u32,
    ram_rdata: u16,
    reg_reads: usize,
    reg_writes: usize,
    ram_writes: usize,
}

impl Slave {
    fn value(&self, word: u16) -> u32 {
        if word >= LIVE_WORDS {
            (self.clocks & 0xffff) * 0x1_0001
        } else {
            self.regs[usize::from(word)]
        }
    }

    fn clock(&mut self, out: &FsmcOutputs) {
        if let Some(w) = self.pending {
            self.reg_rdata = self.value(w);
        }
        self.pending = out.reg_re.then_some(out.reg_addr);
        self.reg_reads += usize::from(out.reg_re);
        if out.reg_we {
            self.regs[usize::from(out.reg_addr)] = out.reg_wdata;
            self.reg_writes += 1;
        }
        self.ram_rdata = self.ram[usize::from(out.ram_addr)];
        if out.ram_we {
            self.ram[usize::from(out.ram_addr)] = out.ram_wdata;
            self.ram_writes += 1;
        }
        self.clocks += 1;
    }
}

/// One half of an FSMC transaction.
#[derive(Clone, Copy, Debug)]
enum Half {
    Read(u16),
    Write(u16, u16),
}

/// What the bench saw before one edge.
#[derive(Clone, Copy, Debug)]
struct Seen {
    pins: FsmcPins,
    out: FsmcOutputs,
    read_pending: bool,
}

struct Bench {
    bridge: FsmcBridgeModel,
    slave: Slave,
    pins: FsmcPins,
    trace: Vec<Seen>,
}

impl Bench {
    /// After a reset; registers hold distinct halves, RAM words their
    /// address with a tag.
    fn new() -> Self {
        let mut b = Self {
            bridge: FsmcBridgeModel::new(),
            slave: Slave {
                regs: (0..REG_WORDS)
                    .map(|w| 0xa000_0000 | w << 16 | 0x5000 | w)
                    .collect(),
                ram: (0..RAM_WORDS).map(|w| 0xc000 | w as u16).collect(),
                clocks: 0,
                pending: None,
                reg_rdata: 0,
                ram_rdata: 0,
                reg_reads: 0,
                reg_writes: 0,
                ram_writes: 0,
            },
            pins: FsmcPins::idle(),
            trace: Vec::new(),
        };
        b.reset();
        b
    }

    fn edge_with(&mut self, reset: bool) {
        let out = self.bridge.outputs(&self.pins);
        assert_eq!(
            out.d_oe,
            !self.pins.ne_n && !self.pins.noe_n,
            "d_oe is NE1# low AND NOE# low from the pins: {:?}",
            self.pins
        );
        self.trace.push(Seen {
            pins: self.pins,
            out,
            read_pending: self.bridge.read_pending(),
        });
        let s = &self.slave;
        self.bridge
            .clock(&self.pins, reset, s.reg_rdata, s.ram_rdata);
        self.slave.clock(&out);
    }

    fn edge(&mut self) {
        self.edge_with(false);
    }

    fn reset(&mut self) {
        self.pins = FsmcPins::idle();
        for _ in 0..4 {
            self.edge_with(true);
        }
        for _ in 0..2 {
            self.edge();
        }
    }

    /// One transaction (NE1# low across its halves); the read data as the
    /// MCU samples it at the end of each read strobe.
    fn transaction(&mut self, halves: &[Half]) -> Vec<u16> {
        let mut data = Vec::new();
        for &half in halves {
            let (a, d) = match half {
                Half::Read(a) => (a, None),
                Half::Write(a, d) => (a, Some(d)),
            };
            // Address phase: the strobes high, D not yet valid.
            self.pins = FsmcPins {
                ne_n: false,
                noe_n: true,
                nwe_n: true,
                a,
                d_in: !d.unwrap_or(0),
            };
            for _ in 0..ADDSET_CLOCKS {
                self.edge();
            }
            for k in 0..DATAST_CLOCKS {
                match d {
                    // D is valid only from a few ns after NWE# falls.
                    Some(d) => {
                        self.pins.nwe_n = false;
                        self.pins.d_in = if k == 0 { !d } else { d };
                    }
                    None => self.pins.noe_n = false,
                }
                if k == DATAST_CLOCKS - 1 && d.is_none() {
                    let out = self.bridge.outputs(&self.pins);
                    assert!(out.d_oe, "reading {a:#x}");
                    data.push(out.d_out);
                }
                self.edge();
            }
            // The strobe rises with the next half's address and garbage on
            // D, or NE1# high (the FSMC holds them one HCLK, less than a
            // clock).
        }
        self.pins = FsmcPins {
            a: 0x5a5,
            ..FsmcPins::idle()
        };
        for _ in 0..IDLE_CLOCKS {
            self.edge();
        }
        data
    }

    fn read16(&mut self, a: u16) -> u16 {
        self.transaction(&[Half::Read(a)])[0]
    }

    fn read32(&mut self, a: u16) -> u32 {
        let d = self.transaction(&[Half::Read(a), Half::Read(a + 1)]);
        u32::from(d[1]) << 16 | u32::from(d[0])
    }

    fn write16(&mut self, a: u16, d: u16) {
        self.transaction(&[Half::Write(a, d)]);
    }

    fn write32(&mut self, a: u16, d: u32) {
        self.transaction(&[
            Half::Write(a, d as u16),
            Half::Write(a + 1, (d >> 16) as u16),
        ]);
    }

    /// (register reads, register writes, RAM writes) so far.
    fn counts(&self) -> (usize, usize, usize) {
        let s = &self.slave;
        (s.reg_reads, s.reg_writes, s.ram_writes)
    }
}

#[test]
fn register_read_latency_is_five_edges() {
    let mut b = Bench::new();
    let start = b.trace.len();
    let v = b.slave.regs[0x123];
    assert_eq!(b.read16(0x246), v as u16);
    // Edge numbers count from the first edge that samples NOE# low.
    let seen = &b.trace[start..];
    let first_low = seen.iter().position(|s| !s.pins.noe_n).unwrap();
    let before_edge = |n: usize| &seen[first_low + n - 1];
    let re: Vec<usize> = (1..=DATAST_CLOCKS)
        .filter(|&n| before_edge(n).out.reg_re)
        .collect();
    assert_eq!(re, [3], "reg_re is high until edge 3");
    assert_eq!(before_edge(3).out.reg_addr, 0x123);
    let pending: Vec<usize> = (1..=DATAST_CLOCKS)
        .filter(|&n| before_edge(n).read_pending)
        .collect();
    assert_eq!(
        pending,
        [3, 4, 5],
        "from the start to the edge loading d_out"
    );
    assert_ne!(before_edge(5).out.d_out, v as u16, "not before edge 5");
    assert_eq!(before_edge(6).out.d_out, v as u16, "loaded at edge 5");
    assert!(!seen.last().unwrap().read_pending);
}

#[test]
fn thirty_two_bit_register_read_is_one_register_read() {
    let mut b = Bench::new();
    let v = b.slave.regs[0x2a5];
    assert_eq!(b.read32(0x54a), v);
    assert_eq!(b.counts(), (1, 0, 0));
    // The live registers change every clock: still one sample.
    for word in [LIVE_WORDS, 0x3ff] {
        let live = b.read32(word * 2);
        assert_eq!(
            live >> 16,
            live & 0xffff,
            "word {word:#x}: {live:#010x} tore"
        );
    }
    let first = b.read32(LIVE_WORDS * 2);
    let second = b.read32(LIVE_WORDS * 2);
    assert_ne!(first, second, "two 32-bit reads are two samples");
    assert_eq!(b.counts(), (5, 0, 0));
}

#[test]
fn kept_high_half_is_visible_until_the_next_access() {
    let mut b = Bench::new();
    assert_eq!(b.bridge.hold(), None, "after reset");
    let v = b.slave.regs[0x2a5];
    b.read16(0x54a);
    assert_eq!(b.bridge.hold(), Some((0x2a5, (v >> 16) as u16)));
    b.read16(0x54b);
    assert_eq!(b.bridge.hold(), None, "used by the high half");
    b.read16(0x54a);
    b.write16(0x900, 3);
    assert_eq!(b.bridge.hold(), None, "dropped by a write");
    // Two low halves in a row: two samples, the high half from the second.
    let halves = b.transaction(&[Half::Read(0x7e0), Half::Read(0x7e0), Half::Read(0x7e1)]);
    assert_eq!(b.counts().0, 4, "{halves:x?}");
    assert_ne!(halves[0], halves[1], "{halves:x?}");
    assert_eq!(halves[1], halves[2], "{halves:x?}");
    b.read16(0x54a);
    b.reset();
    assert_eq!(b.bridge.hold(), None, "dropped by reset");
}

#[test]
fn lone_high_half_reads_the_register_afresh() {
    // (what comes before the high half of word 0x3f0, its register reads)
    let cases: [(&str, &[Half], usize); 5] = [
        ("nothing", &[], 0),
        ("low half of the next word", &[Half::Read(0x7e2)], 1),
        (
            "32-bit read of the same word",
            &[Half::Read(0x7e0), Half::Read(0x7e1)],
            1,
        ),
        (
            "RAM read after the low half",
            &[Half::Read(0x7e0), Half::Read(0x801)],
            1,
        ),
        (
            "register write after the low half",
            &[Half::Read(0x7e0), Half::Write(0x20, 1)],
            1,
        ),
    ];
    for (what, before, reads) in cases {
        let mut b = Bench::new();
        b.transaction(before);
        assert_eq!(b.counts().0, reads, "{what}");
        let at = b.slave.clocks;
        let hi = b.read16(0x7e1);
        assert_eq!(b.counts().0, reads + 1, "{what}: a fresh register read");
        // The live value's high half, sampled during this access.
        assert!(
            hi > at as u16 && hi < b.slave.clocks as u16,
            "{what}: {hi} not in {at}.."
        );
    }
    assert_eq!(cases.len(), 5);
}

#[test]
fn ram_reads_and_writes_are_one_word_each() {
    let mut b = Bench::new();
    assert_eq!(b.read16(0x800), 0xc000);
    assert_eq!(b.read16(0xbff), 0xc3ff);
    assert_eq!(b.read16(0xc07), 0xc007, "A10 not decoded");
    assert_eq!(b.read32(0x812), 0xc013_c012);
    assert_eq!(b.counts(), (0, 0, 0));
    b.write16(0x807, 0x1234);
    b.write32(0xa20, 0xabcd_5678);
    assert_eq!(b.counts(), (0, 0, 3));
    assert_eq!(b.slave.ram[7], 0x1234);
    assert_eq!(&b.slave.ram[0x220..0x222], &[0x5678, 0xabcd]);
    assert_eq!(b.read16(0x807), 0x1234);
    assert_eq!(b.read32(0xa20), 0xabcd_5678);
}

#[test]
fn thirty_two_bit_write_is_one_register_write() {
    let mut b = Bench::new();
    b.write32(0x10, 0x8765_4321);
    assert_eq!(b.counts(), (0, 1, 0));
    assert_eq!(b.slave.regs[8], 0x8765_4321);
    assert_eq!(b.read32(0x10), 0x8765_4321);
    // Low half alone: kept, nothing written, even across a RAM write and
    // a reset; the lone high half of another word writes both.
    b.write16(0x20, 0x00ff);
    b.write16(0x830, 0x7777);
    b.reset();
    assert_eq!(b.counts(), (1, 1, 1));
    b.write16(0x41, 0xff00);
    assert_eq!(b.counts(), (1, 2, 1));
    assert_eq!(b.slave.regs[0x20], 0xff00_00ff);
    assert_eq!(
        b.slave.regs[0x10], 0xa010_5010,
        "the low half's word untouched"
    );
    // A high half does not become the kept low half.
    b.write16(0x43, 0x0001);
    assert_eq!(b.slave.regs[0x21], 0x0001_00ff);
}

#[test]
fn lone_high_half_write_after_power_up_uses_zero() {
    let mut b = Bench::new();
    b.write16(0x7ff, 0x1357);
    assert_eq!(b.slave.regs[0x3ff], 0x1357_0000);
    assert_eq!(b.counts(), (0, 1, 0));
}

#[test]
fn write_lands_at_the_third_edge_after_nwe_is_seen_high() {
    let mut b = Bench::new();
    let start = b.trace.len();
    b.write16(0x801, 0x4242);
    let seen = &b.trace[start..];
    let last_low = seen.iter().rposition(|s| !s.pins.nwe_n).unwrap();
    // The edge after the last low sample is the first to see NWE# high.
    let we: Vec<usize> = (last_low + 1..seen.len())
        .filter(|&i| seen[i].out.ram_we)
        .map(|i| i - last_low)
        .collect();
    assert_eq!(we, [3], "ram_we before the write's edge only");
    let at = &seen[last_low + 3].out;
    assert_eq!((at.ram_addr, at.ram_wdata), (1, 0x4242));
    assert!(!at.reg_we);
}

#[test]
fn write_data_comes_only_from_two_low_samples_in_a_row() {
    let mut b = Bench::new();
    b.write16(0x800, 0x1111);
    // A strobe seen low at one edge only: no sample qualifies, so the
    // RAM gets the last data taken, not what D shows.
    b.pins = FsmcPins {
        ne_n: false,
        a: 0x802,
        d_in: 0x2222,
        ..FsmcPins::idle()
    };
    b.edge();
    b.pins.nwe_n = false;
    b.edge();
    b.pins.nwe_n = true;
    b.pins.ne_n = true;
    for _ in 0..IDLE_CLOCKS {
        b.edge();
    }
    assert_eq!(b.counts(), (0, 0, 2));
    assert_eq!(b.slave.ram[2], 0x1111);
}

#[test]
fn other_banks_cycles_are_ignored() {
    let mut b = Bench::new();
    for noe_first in [true, false] {
        b.pins = FsmcPins {
            a: 0x10,
            d_in: 0x1234,
            ..FsmcPins::idle()
        };
        b.edge();
        for _ in 0..DATAST_CLOCKS {
            if noe_first {
                b.pins.noe_n = false;
            } else {
                b.pins.nwe_n = false;
            }
            b.edge();
        }
        b.pins = FsmcPins::idle();
        for _ in 0..IDLE_CLOCKS {
            b.edge();
        }
    }
    assert_eq!(b.counts(), (0, 0, 0));
    assert!(b.trace.iter().all(|s| !s.out.d_oe));
}

#[test]
fn only_a11_to_a0_are_pins() {
    let mut b = Bench::new();
    let v = b.slave.regs[0x3a];
    assert_eq!(b.read32(0xf074), v);
    b.write16(0x7805, 0x9999);
    assert_eq!(b.slave.ram[5], 0x9999);
    assert_eq!(b.counts(), (1, 0, 1));
}
