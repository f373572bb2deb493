//! The model against docs/servo_dac.md's tables, from the bus and the pins
//! alone: the write sequence, the serial frames, the tick, the events, the
//! safe input and the register file. (The testbench compares the model
//! with the HDL every clock; these say the model is the documented block.)

use super::*;

const CLOCK_HZ: u64 = 50_000_000;

/// The block after reset, its reset transfer run out, and the clocks since.
struct Bench {
    dac: ServoDac,
    safe: bool,
}

impl Bench {
    fn new() -> Self {
        let mut dac = ServoDac::new(CLOCK_HZ);
        dac.clock(true, &BusCycle::default(), false);
        let mut bench = Self { dac, safe: false };
        bench.settle();
        bench
    }

    fn offset(&self, name: &str) -> u32 {
        self.dac.map().register(name).offset
    }

    fn channel(&self, n: u32, name: &str) -> u32 {
        self.dac.map().array("CH").address(n, name)
    }

    fn clock(&mut self, bus: BusCycle) {
        self.dac.clock(false, &bus, self.safe);
    }

    fn idle(&mut self) {
        self.clock(BusCycle::default());
    }

    fn write(&mut self, name: &str, value: u32) {
        self.clock(BusCycle::write(self.offset(name), value));
    }

    fn write_code(&mut self, n: u32, value: u32) {
        self.clock(BusCycle::write(self.channel(n, "CODE"), value));
    }

    /// A read of word `addr`: its value as `rdata` holds it two edges on.
    fn read_addr(&mut self, addr: u32) -> u32 {
        self.clock(BusCycle::read(addr));
        self.idle();
        self.dac.rdata()
    }

    fn read(&mut self, name: &str) -> u32 {
        self.read_addr(self.offset(name))
    }

    fn busy(&self) -> bool {
        self.dac.read_value(self.offset("STATUS")) & 1 == 1
    }

    /// Runs idle clocks until no transfer runs or waits.
    fn settle(&mut self) {
        for _ in 0..10_000 {
            if self.dac.read_value(self.offset("STATUS")) & 3 == 0 {
                return;
            }
            self.idle();
        }
        panic!("the transfer never ended");
    }

    /// The pins after each edge from the one ending the current clock
    /// (the start edge, `bus` in it) to the edge where LOADDACS rises.
    fn transfer(&mut self, bus: BusCycle) -> Vec<DacPins> {
        let mut pins = Vec::new();
        self.clock(bus);
        while self.busy() {
            pins.push(self.dac.pins());
            assert!(pins.len() < 10_000, "the transfer never ended");
            self.idle();
        }
        pins.push(self.dac.pins());
        pins
    }

    fn update(&mut self) -> Vec<DacPins> {
        self.transfer(BusCycle::write(self.offset("UPDATE"), 0))
    }
}

const CODES: [u32; CHANNELS] = [0x1234, 0xfedc, 0x0001, 0x8001];

/// Parallel mode: each channel a setup clock, W clocks of CS low, a hold
/// clock, then L clocks of LOADDACS low; the outputs change at its rise.
#[test]
fn parallel_transfer_follows_the_write_table() {
    let mut cases = 0;
    for cs_low in [0, 1, 2, 5] {
        for ldac_low in [0, 1, 3] {
            let mut b = Bench::new();
            for (n, code) in CODES.iter().enumerate() {
                b.write_code(n as u32, *code);
            }
            b.write("TIMING", cs_low | ldac_low << 8);
            assert_eq!(b.dac.outputs(), [SAFE_CODE; CHANNELS]);
            let pins = b.update();
            let (w, l) = (cs_low as usize + 1, ldac_low as usize + 1);
            let case = format!("CS_LOW {cs_low} LDAC_LOW {ldac_low}");
            assert_eq!(pins.len(), 4 * (w + 2) + l + 1, "{case}");
            assert_eq!(pins.len() - 1, update_latency(cs_low, ldac_low) as usize);
            for (k, p) in pins.iter().enumerate() {
                let n = (k / (w + 2)).min(3);
                let writing = k < 4 * (w + 2) && (1..=w).contains(&(k % (w + 2)));
                let loading = (4 * (w + 2)..4 * (w + 2) + l).contains(&k);
                assert_eq!((p.addr, p.data), (n as u32, CODES[n]), "{case} clock {k}");
                assert_eq!(p.cs_n, !writing, "{case} CS in clock {k}");
                assert_eq!(p.ldac_n, !loading, "{case} LOADDACS in clock {k}");
                assert!(!p.rw_n && p.sclk && p.sync_n, "{case} clock {k}: {p:?}");
            }
            assert_eq!(b.dac.outputs(), CODES, "{case}");
            cases += 1;
        }
    }
    assert_eq!(cases, 12);
}

/// The frames SDIN carries, sampled at SCLK's falls while SYNC is low, and
/// the clocks SYNC is high before each and SCLK's half lengths.
fn frames(pins: &[DacPins]) -> (Vec<u32>, Vec<usize>, Vec<usize>) {
    let (mut frames, mut sync_highs, mut halves) = (Vec::new(), Vec::new(), Vec::new());
    let (mut high_run, mut half_run, mut frame, mut bits) = (0, 0, 0u32, 0);
    let mut before = pins[0];
    for p in pins {
        assert!(p.cs_n, "CS stays high in serial mode: {p:?}");
        assert!(p.sclk || !p.sync_n, "SCLK low outside a frame: {p:?}");
        if p.sclk != before.sclk && !p.sync_n {
            halves.push(half_run);
            half_run = 0;
        }
        half_run += 1;
        if p.sync_n {
            high_run += 1;
        } else if before.sync_n {
            sync_highs.push(high_run);
            high_run = 0;
            (half_run, frame, bits) = (1, 0, 0);
        }
        if before.sclk && !p.sclk {
            frame = frame << 1 | u32::from(p.sdin);
            bits += 1;
        }
        if p.sync_n && !before.sync_n {
            assert_eq!(bits, FRAME_BITS, "bits in frame {}", frames.len());
            frames.push(frame);
        }
        before = *p;
    }
    (frames, sync_highs, halves)
}

/// Serial mode: four 24-bit frames (PREFIX.CHn, then the code), SYNC high
/// Y clocks before each and before LOADDACS, SCLK halves of S clocks, and
/// LOADDACS low L clocks ending at serial_update_latency.
#[test]
fn serial_transfer_sends_the_prefixed_frames() {
    let prefix = 0xa5c3_1e07;
    let mut cases = 0;
    for sclk_half in [0, 1, 2] {
        for sync_high in [0, 2] {
            for ldac_low in [0, 1] {
                let mut b = Bench::new();
                for (n, code) in CODES.iter().enumerate() {
                    b.write_code(n as u32, *code);
                }
                b.write("TIMING", 7 | ldac_low << 8);
                b.write("PREFIX", prefix);
                b.write("SERIAL", 1 | sclk_half << 8 | sync_high << 16);
                let pins = b.update();
                let case = format!("SCLK_HALF {sclk_half} SYNC_HIGH {sync_high} LDAC {ldac_low}");
                let latency = serial_update_latency(sclk_half, sync_high, ldac_low) as usize;
                assert_eq!(pins.len() - 1, latency, "{case}");
                let (frames, sync_highs, halves) = frames(&pins);
                let expected: Vec<u32> = (0..4)
                    .map(|n| (prefix >> (8 * n) & 0xff) << 16 | CODES[n])
                    .collect();
                assert_eq!(frames, expected, "{case}");
                assert_eq!(sync_highs, vec![sync_high as usize + 1; 4], "{case}");
                // Per frame 48 halves, each ended by an SCLK edge (the
                // last by the rise into the clock of SYNC low after it).
                let s = sclk_half as usize + 1;
                assert_eq!(halves.len(), 4 * 48, "{case}");
                assert!(halves.iter().all(|&h| h == s), "{case}: {halves:?}");
                let ldac: Vec<usize> = (0..pins.len()).filter(|&k| !pins[k].ldac_n).collect();
                let l = ldac_low as usize + 1;
                assert_eq!(ldac, (latency - l..latency).collect::<Vec<_>>(), "{case}");
                let last_sync = (0..pins.len()).rfind(|&k| !pins[k].sync_n).unwrap();
                assert_eq!(
                    latency - l - last_sync - 1,
                    sync_high as usize + 1,
                    "{case}"
                );
                assert_eq!(b.dac.outputs(), CODES, "{case}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 12);
}

/// A TICK_PERIOD write in clock j gives ticks in clocks j + 1 + V, then
/// every V; each starts a transfer and sets EVENTS.TICK; a tick during a
/// transfer sets OVERRUN; 0 stops the tick.
#[test]
fn tick_period_ticks_and_starts_transfers() {
    for period in [1u32, 2, 5, 40] {
        let mut clocks = Vec::new();
        let mut b = Bench::new();
        b.write("TICK_PERIOD", period);
        for k in 1..=200u32 {
            if b.dac.tick() {
                clocks.push(k);
            }
            b.idle();
        }
        let expected: Vec<u32> = (0..)
            .map(|i| 1 + period + i * period)
            .take_while(|&c| c <= 200)
            .collect();
        assert_eq!(clocks, expected, "TICK_PERIOD {period}");
        let events = b.read("EVENTS");
        let overrun = period < update_latency(2, 2);
        assert_eq!(events, 1 | u32::from(overrun) << 1, "TICK_PERIOD {period}");
        b.write("EVENTS", 3);
        b.write("TICK_PERIOD", 0);
        b.settle();
        b.write("EVENTS", 3);
        assert_eq!(b.read("EVENTS"), 0);
        for _ in 0..100 {
            assert!(!b.dac.tick(), "TICK_PERIOD 0 ticks");
            b.idle();
        }
        assert_eq!(b.read("TICK_PERIOD"), 0);
    }
}

/// The tick's transfer: LOADDACS rises update_latency edges after the edge
/// ending the tick's clock, every period (zero jitter).
#[test]
fn a_tick_updates_the_outputs_after_the_latency() {
    let mut b = Bench::new();
    let period = 60;
    b.write("TICK_PERIOD", period);
    let mut rises = Vec::new();
    let mut ticks = Vec::new();
    let mut before = b.dac.pins().ldac_n;
    for k in 0..400u32 {
        if b.dac.tick() {
            ticks.push(k);
        }
        b.idle();
        let ldac = b.dac.pins().ldac_n;
        if ldac && !before {
            rises.push(k);
        }
        before = ldac;
    }
    let latency = update_latency(2, 2);
    let expected: Vec<u32> = ticks
        .iter()
        .map(|t| t + latency)
        .filter(|&r| r < 400)
        .collect();
    assert_eq!(rises, expected, "ticks {ticks:?}");
    assert!(rises.len() >= 5);
}

/// EVENTS is write-1-to-clear, and an event in the clock of a clear wins.
#[test]
fn events_clear_by_writing_one_and_a_new_event_wins() {
    let mut b = Bench::new();
    b.write("TICK_PERIOD", 4);
    for _ in 0..40 {
        b.idle();
    }
    assert_eq!(b.read("EVENTS"), 3);
    b.write("TICK_PERIOD", 0);
    b.write("EVENTS", 2);
    assert_eq!(b.read("EVENTS"), 1);
    b.write("EVENTS", 1);
    assert_eq!(b.read("EVENTS"), 0);
    // A clear in the clock the tick is high: the tick's event stays.
    b.settle();
    b.write("TICK_PERIOD", 3);
    for _ in 0..3 {
        b.idle();
    }
    assert!(b.dac.tick());
    b.write("EVENTS", 1);
    assert_eq!(b.read("EVENTS") & 1, 1);
}

/// The rise of `safe` starts a transfer of SAFE_CODE to all four channels;
/// while it stays high every transfer sends SAFE_CODE; the staged codes are
/// kept and go out with the first transfer after it falls.
#[test]
fn safe_sends_the_safe_code_and_keeps_the_staged_codes() {
    let mut b = Bench::new();
    for (n, code) in CODES.iter().enumerate() {
        b.write_code(n as u32, *code);
    }
    b.update();
    assert_eq!(b.dac.outputs(), CODES);
    b.safe = true;
    let pins = b.transfer(BusCycle::default());
    assert_eq!(pins.len() - 1, update_latency(2, 2) as usize);
    assert!(pins.iter().all(|p| p.data == SAFE_CODE));
    assert_eq!(b.dac.outputs(), [SAFE_CODE; CHANNELS]);
    assert_eq!(b.read("STATUS"), 4, "STATUS.SAFE");
    b.update();
    assert_eq!(b.dac.outputs(), [SAFE_CODE; CHANNELS]);
    for n in 0..4 {
        assert_eq!(b.read_addr(b.channel(n, "CODE")), CODES[n as usize]);
    }
    b.safe = false;
    b.idle();
    assert_eq!(b.read("STATUS"), 0);
    assert_eq!(
        b.dac.outputs(),
        [SAFE_CODE; CHANNELS],
        "the fall starts nothing"
    );
    b.update();
    assert_eq!(b.dac.outputs(), CODES);
}

/// Requests while a transfer runs wait one deep (STATUS.PENDING) and merge;
/// the waiting one starts at the edge the running one ends.
#[test]
fn requests_during_a_transfer_wait_one_deep() {
    let mut b = Bench::new();
    b.write_code(0, 0x4444);
    b.write("UPDATE", 0);
    assert_eq!(b.read("STATUS"), 1, "BUSY");
    b.write_code(0, 0x5555);
    b.write("UPDATE", 0);
    b.write_code(0, 0x6666);
    b.write("UPDATE", 0);
    assert_eq!(b.read("STATUS"), 3, "BUSY and PENDING");
    let mut transfers = 0;
    let mut before = b.dac.pins().ldac_n;
    let mut outputs = Vec::new();
    for _ in 0..100 {
        b.idle();
        let ldac = b.dac.pins().ldac_n;
        if ldac && !before {
            transfers += 1;
            outputs.push(b.dac.outputs()[0]);
            assert!(b.busy() || transfers == 2, "the waiting one starts at once");
        }
        before = ldac;
    }
    assert_eq!(outputs, vec![0x4444, 0x6666]);
    assert_eq!(b.read("STATUS"), 0);
}

/// Reset: TIMING and SERIAL from the data sheets at 50 MHz, the codes at
/// SAFE_CODE, and a transfer waiting so the DAC is driven right away.
#[test]
fn reset_values_and_the_reset_transfer() {
    let mut dac = ServoDac::new(CLOCK_HZ);
    dac.clock(true, &BusCycle::default(), false);
    let status = dac.map().register("STATUS").offset;
    assert_eq!(dac.read_value(status), 2, "PENDING after reset");
    dac.clock(false, &BusCycle::default(), false);
    assert_eq!(dac.read_value(status), 1, "BUSY one clock after reset");
    let mut b = Bench::new();
    assert_eq!(b.read("TIMING"), 2 | 2 << 8);
    assert_eq!(b.read("SERIAL"), 1 << 16);
    assert_eq!(b.read("PREFIX"), 0x1814_1211);
    assert_eq!(b.read("INFO"), 4);
    assert_eq!(b.dac.outputs(), [SAFE_CODE; CHANNELS]);
}

/// Every RW register keeps exactly its fields' bits; read-only and
/// undecoded words ignore writes; `rdata` loads at the edge after the one
/// taking the address and then holds.
#[test]
fn registers_keep_their_fields_and_reads_take_two_edges() {
    let mut b = Bench::new();
    let ones = u32::MAX;
    for (name, kept) in [
        ("TICK_PERIOD", ones),
        ("TIMING", 0xffff),
        ("SERIAL", 0xff_ff01),
        ("PREFIX", ones),
    ] {
        b.write(name, ones);
        assert_eq!(b.read(name), kept, "{name}");
        b.write(name, 0);
        assert_eq!(b.read(name), 0, "{name}");
    }
    b.write("SERIAL", 0x0002_0300);
    assert_eq!(b.read("SERIAL"), 0x0002_0300);
    b.write("TIMING", 0x0304);
    assert_eq!(b.read("TIMING"), 0x0304);
    for n in 0..4 {
        b.write_code(n, ones - n);
        assert_eq!(b.read_addr(b.channel(n, "CODE")), (ones - n) & 0xffff);
        assert_eq!(b.read_addr(b.channel(n, "OUTPUT")), SAFE_CODE);
    }
    b.write("UPDATE", ones);
    assert_eq!(b.read("UPDATE"), 0);
    b.write("INFO", 0);
    assert_eq!(b.read("INFO"), 4);
    let decoded: Vec<u32> = b.dac.map().decoded().iter().map(|d| d.0).collect();
    for addr in (0..16).filter(|a| !decoded.contains(a)) {
        assert_eq!(b.read_addr(addr), 0, "word {addr}");
    }
    // The edge with `re` takes the address; the next loads; rdata holds.
    b.settle();
    b.write("PREFIX", 0x1111_2222);
    b.clock(BusCycle::read(b.offset("PREFIX")));
    let held = b.dac.rdata();
    b.write("PREFIX", 0x3333_4444);
    assert_ne!(held, 0x1111_2222);
    assert_eq!(b.dac.rdata(), 0x1111_2222, "the value before the next edge");
    b.idle();
    assert_eq!(b.dac.rdata(), 0x1111_2222, "rdata holds");
}

/// The exhaustive checks put states in ordered sets: two states order as
/// their flip-flops do, and `<` agrees with that order.
#[test]
fn states_order_by_their_flip_flops() {
    let reset = ServoDac::new(CLOCK_HZ);
    let mut started = reset.clone();
    started.clock(false, &BusCycle::default(), false);
    assert_eq!(reset.cmp(&reset.clone()), std::cmp::Ordering::Equal);
    assert_ne!(reset.cmp(&started), std::cmp::Ordering::Equal);
    assert_eq!(reset.partial_cmp(&started), Some(reset.cmp(&started)));
    assert_eq!(started.cmp(&reset), reset.cmp(&started).reverse());
}
