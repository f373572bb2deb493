//! The bank: register bus, PRESET, SNAPSHOT and reset.

use super::*;
use crate::regmap::{mode, Block};

struct BankRig {
    bank: Bank,
    pins: Vec<(bool, bool, bool)>,
}

impl BankRig {
    fn new(axes: u32, width: u32) -> Self {
        let mut r = BankRig {
            bank: Bank::new(axes, CounterParams::new(width, 8)),
            pins: vec![(false, false, false); axes as usize],
        };
        for _ in 0..4 {
            r.clock(true, BusCycle::default());
        }
        r
    }
    fn map(&self) -> Block {
        self.bank.regmap().clone()
    }
    fn clock(&mut self, reset: bool, bus: BusCycle) {
        let pins = self.pins.clone();
        self.bank.clock(&pins, reset, &bus);
    }
    fn idle(&mut self, n: usize) {
        for _ in 0..n {
            self.clock(false, BusCycle::default());
        }
    }
    fn write(&mut self, addr: u32, wdata: u32) {
        self.clock(false, BusCycle::write(addr, wdata));
    }
    fn read(&mut self, addr: u32) -> u32 {
        self.clock(false, BusCycle::read(addr));
        self.clock(false, BusCycle::default());
        self.bank.rdata()
    }
    fn ch(&self, i: u32, reg: &str) -> u32 {
        self.map().array("CH").address(i, reg)
    }
    fn reg(&self, reg: &str) -> u32 {
        self.map().register(reg).offset
    }
}

#[test]
fn bank_reads_info_preset_and_unmapped() {
    let mut r = BankRig::new(3, 28);
    let info = r.reg("INFO");
    let preset = r.reg("PRESET");
    let snapshot = r.reg("SNAPSHOT");
    // AXES, WIDTH, ERR_BITS and the four feature bits (every feature in).
    assert_eq!(r.read(info), 3 | (28 << 8) | (8 << 16) | (0xf << 24));
    r.write(info, 0);
    assert_eq!(r.read(info), r.map().register("INFO").reset);

    r.write(preset, 0x0800_0000);
    assert_eq!(r.bank.preset(), 0x0800_0000);
    assert_eq!(r.read(preset), 0xf800_0000);
    r.write(preset, 0x1000_0005);
    assert_eq!(r.bank.preset(), 0x1000_0005, "stored as written");
    assert_eq!(r.read(preset), 5);
    r.write(preset, 0xffff_ffff);
    assert_eq!(r.read(preset), 0xffff_ffff);

    assert_eq!(r.read(snapshot), 0, "write-only");
    assert_eq!(r.read(r.ch(1, "CMD")), 0, "write-only");
    let mapped: Vec<u32> = r.map().decoded().iter().map(|d| d.0).collect();
    let unmapped = (0..256).find(|a| !mapped.contains(a)).unwrap();
    assert_eq!(r.bank.read_value(unmapped), 0);
    // Only addr[7:0] reaches the decoder.
    assert_eq!(r.bank.read_value(0x100 | preset), 0xffff_ffff);
}

#[test]
fn bank_rdata_has_two_edge_latency_pipelines_and_holds() {
    let mut r = BankRig::new(1, 28);
    let (preset, info) = (r.reg("PRESET"), r.reg("INFO"));
    r.write(preset, 42);
    assert_eq!(r.bank.rdata(), 0);
    // Read and write in the same clock: the read takes the register as
    // it stands in that clock, before the write lands at the edge.
    r.clock(
        false,
        BusCycle {
            addr: preset,
            wdata: 7,
            we: true,
            re: true,
        },
    );
    assert_eq!(r.bank.rdata(), 0, "not yet after one edge");
    // Back-to-back reads come out in order, one per clock.
    r.clock(false, BusCycle::read(preset));
    assert_eq!(r.bank.rdata(), 42, "PRESET before the write");
    r.clock(false, BusCycle::read(info));
    assert_eq!(r.bank.rdata(), 7);
    r.idle(1);
    assert_eq!(r.bank.rdata(), r.map().register("INFO").reset);
    r.idle(3);
    assert_eq!(
        r.bank.rdata(),
        r.map().register("INFO").reset,
        "rdata holds without re"
    );
    // Reset drops a read in flight.
    r.clock(false, BusCycle::read(preset));
    r.clock(true, BusCycle::default());
    assert_eq!(r.bank.rdata(), 0);
    r.idle(1);
    assert_eq!(r.bank.rdata(), 0, "the read before reset never lands");
    assert_eq!(r.bank.preset(), 0);
}

#[test]
fn bank_load_and_count_read_sign_extended() {
    let mut r = BankRig::new(2, 28);
    let (preset, snapshot) = (r.reg("PRESET"), r.reg("SNAPSHOT"));
    r.write(preset, 0xf800_0000); // -2^27: the most negative 28-bit count
    r.write(r.ch(1, "CMD"), cmd_bit("LOAD"));
    r.idle(1); // LOAD's second edge
    assert_eq!(r.bank.channel(1).state().count, 0x0800_0000);
    assert_eq!(r.bank.channel(0).state().count, 0, "CMD is per channel");
    r.write(snapshot, 0);
    assert_eq!(r.read(r.ch(1, "COUNT")), 0xf800_0000);
    // One step down wraps to the most positive count.
    r.write(r.ch(1, "CTRL"), ctrl_field("REVERSE", 1));
    r.pins[1] = (true, false, false);
    r.idle(PIN_TO_COUNT);
    r.write(snapshot, 0);
    assert_eq!(r.read(r.ch(1, "COUNT")), 0x07ff_ffff);
}

#[test]
fn snapshot_is_coherent_across_channels() {
    let mut r = BankRig::new(3, 28);
    let snapshot = r.reg("SNAPSHOT");
    let ctrl_x4 = ctrl_field("MODE", mode::X4) | ctrl_field("IDX_LATCH", 1);
    for i in 0..3 {
        r.write(r.ch(i, "CTRL"), ctrl_x4);
    }
    // Channel 0 runs forward, 1 backward, 2 forward at half speed.
    let mut phase = [0usize; 3];
    let mut t = 0;
    let mut advance = |r: &mut BankRig| {
        t += 1;
        for (i, p) in phase.iter_mut().enumerate() {
            if i == 2 && t % 2 == 0 {
                continue;
            }
            let (a, b) = if i == 1 { BWD[*p % 4] } else { FWD[*p % 4] };
            *p += 1;
            // Z is high with the tenth pin change.
            r.pins[i] = (a, b, *p == 10);
        }
    };
    for _ in 0..20 {
        advance(&mut r);
        r.idle(1);
    }
    // The snapshot edge, while every channel is still counting.
    advance(&mut r);
    let before: Vec<ChannelState> = (0..3).map(|i| *r.bank.channel(i).state()).collect();
    let status: Vec<u32> = (0..3).map(|i| r.bank.channel(i).status()).collect();
    r.write(snapshot, 0xdead_beef);
    for i in 0..3 {
        let s = r.bank.channel(i).state();
        assert_eq!(s.snap_count, before[i].count);
        assert_eq!(s.snap_index, before[i].index);
        assert_eq!(s.snap_status, status[i]);
        assert_ne!(
            s.count, before[i].count,
            "channel {i} counted in the snapshot clock"
        );
    }
    let expect: Vec<[u32; 3]> = (0..3)
        .map(|i| {
            [
                sign_extend(before[i].count, 28),
                sign_extend(before[i].index, 28),
                status[i],
            ]
        })
        .collect();
    // Pin changes 1..=21 were applied before edges 1..=21 (channel 2 on
    // the odd ones); a change reaches the count at its fifth edge, so the
    // 20 edges before the snapshot counted changes 1..=16: 16, -16, 8.
    // The index event is detected one clock after the tenth change is
    // accepted (`zg_q`), when the tenth step is in the count: INDEX =
    // 10, -10; channel 2's tenth change (edge 19) latches only after the
    // snapshot edge.
    let counts: Vec<i32> = expect.iter().map(|e| e[0] as i32).collect();
    let indexes: Vec<i32> = expect.iter().map(|e| e[1] as i32).collect();
    assert_eq!(counts, vec![16, -16, 8]);
    assert_eq!(indexes, vec![10, -10, 0]);
    // Keep counting and read in scrambled order: nothing changes.
    for round in 0..3u32 {
        for k in 0..9u32 {
            let j = (k * 4 + round) % 9;
            let (i, reg) = (j / 3, ["COUNT", "INDEX", "STATUS"][(j % 3) as usize]);
            advance(&mut r);
            let got = r.read(r.ch(i, reg));
            assert_eq!(got, expect[i as usize][(j % 3) as usize], "CH{i}.{reg}");
        }
    }
    // A new snapshot takes the new values.
    r.idle(PIN_TO_COUNT);
    r.write(snapshot, 0);
    for i in 0..3 {
        let count = r.bank.channel(i as usize).state().count;
        assert_eq!(r.read(r.ch(i, "COUNT")), sign_extend(count, 28));
        assert_ne!(sign_extend(count, 28), expect[i as usize][0]);
    }
}

#[test]
fn reset_with_encoder_resting_at_one_one_does_not_count() {
    let mut r = BankRig::new(1, 28);
    r.pins[0] = (true, true, false);
    // Power-up state is all zero; reset for four clocks with the pins high.
    r.bank = Bank::new(1, CounterParams::new(28, 8));
    for _ in 0..4 {
        r.clock(true, BusCycle::default());
    }
    let s = r.bank.channel(0).state();
    assert!(s.fa.level && s.fb.level && s.a_prev && s.b_prev);
    r.write(
        r.ch(0, "CTRL"),
        ctrl_field("MODE", mode::X4) | ctrl_field("ERR_EN", 1),
    );
    r.idle(10);
    let s = r.bank.channel(0).state();
    assert_eq!((s.count, s.err, s.err_count), (0, false, 0));
    // And after running: an illegal move latches ERR, then reset at (1,1).
    r.pins[0] = (false, false, false);
    r.idle(PIN_TO_COUNT);
    assert!(r.bank.channel(0).state().err);
    r.pins[0] = (true, true, false);
    for _ in 0..4 {
        r.clock(true, BusCycle::default());
    }
    r.write(r.ch(0, "CTRL"), ctrl_field("ERR_EN", 1));
    r.idle(10);
    let s = r.bank.channel(0).state();
    assert_eq!(
        (s.count, s.err, s.err_count, s.up_q, s.down_q),
        (0, false, 0, false, false)
    );
}

/// The spec says "hold reset for at least 3 clocks"; literally, from the
/// all-zero power-up state, `level` reaches the pin at the third reset
/// edge and `a_prev` only at the fourth. So three reset clocks with the
/// encoder resting at (1,0) leave one X4 step (CTRL resets to X4).
#[test]
fn three_reset_clocks_from_power_up_leave_one_step() {
    let mut ch = Channel::new(CounterParams::new(28, 8));
    let pins = ChannelInputs {
        a: true,
        ..Default::default()
    };
    for _ in 0..3 {
        ch.clock(&ChannelInputs {
            reset: true,
            ..pins
        });
    }
    assert!(ch.state().fa.level && !ch.state().a_prev);
    for _ in 0..3 {
        ch.clock(&pins);
    }
    assert_eq!(ch.state().count, 1);
}

#[test]
fn reset_clears_what_the_spec_lists() {
    let mut ch = Channel::new(CounterParams::new(28, 8));
    let z = InputFilter {
        s1: true,
        s2: true,
        level: true,
        cnt: 0,
    };
    ch.set_state(ChannelState {
        fa: z,
        fz: z,
        up_q: true,
        down_q: false,
        count: 77,
        index: 5,
        err: true,
        err_count: 3,
        seen: true,
        armed: true,
        ctrl: ctrl_field("IDX_INVERT", 1),
        snap_count: 1,
        snap_index: 2,
        snap_status: 3,
        ..Default::default()
    });
    ch.clock(&ChannelInputs {
        a: true,
        z: true,
        reset: true,
        ctrl_write: Some(u32::MAX),
        cmd_write: Some(u32::MAX),
        snapshot: true,
        ..Default::default()
    });
    assert_eq!(
        *ch.state(),
        ChannelState {
            fa: z,
            fz: z,
            a_prev: true,
            b_prev: false,
            // zg with the pre-edge CTRL: z = 1 inverted.
            zg_prev: false,
            zg_q: false,
            err_q: false,
            ..Default::default()
        }
    );
}

/// The safety block's counter-event inputs (`flags`: STATUS.ERR and SEEN
/// per channel, live) and HOME_COUNT: bit i of `home` captures channel i's
/// count as it stands before the edge, and only channel i's.
#[test]
fn flags_and_home_count_are_per_channel() {
    let mut r = BankRig::new(3, 28);
    assert_eq!(r.bank.channels(), 3);
    let x4 = ctrl_field("MODE", mode::X4);
    let idx = ctrl_field("IDX_LATCH", 1);
    r.write(r.ch(0, "CTRL"), x4);
    r.write(r.ch(1, "CTRL"), x4 | ctrl_field("ERR_EN", 1) | idx);
    r.write(r.ch(2, "CTRL"), x4 | ctrl_field("ERR_EN", 1));
    // Channel 1 jumps 00 -> 11: an illegal transition.
    r.pins[1] = (true, true, false);
    r.idle(PIN_TO_COUNT);
    assert_eq!(r.bank.flags(), (0b010, 0));
    // Channel 1 sees its index (a channel above 0: the bit's place shows).
    r.pins[1] = (true, true, true);
    r.idle(PIN_TO_COUNT);
    r.pins[1] = (true, true, false);
    r.idle(PIN_TO_COUNT);
    assert_eq!(r.bank.flags(), (0b010, 0b010));
    // Channel 2 counts three X4 steps up.
    for p in [
        (true, false, false),
        (true, true, false),
        (false, true, false),
    ] {
        r.pins[2] = p;
        r.idle(PIN_TO_COUNT);
    }
    assert_eq!(r.bank.channel(2).state().count, 3);
    let pins = r.pins.clone();
    r.bank
        .clock_homing(&pins, false, &BusCycle::default(), 0b100);
    r.pins[2] = (false, false, false);
    r.idle(PIN_TO_COUNT);
    assert_eq!(r.bank.channel(2).state().count, 4);
    for (i, kept) in [(0, 0), (1, 0), (2, 3)] {
        assert_eq!(r.read(r.ch(i, "HOME_COUNT")), kept, "HOME_COUNT[{i}]");
    }
}

/// Reset drops a read in flight and takes none: `rdata` is 0 after it and
/// holds until a read, whatever the address lines show.
#[test]
fn rdata_is_zero_after_reset_until_a_read() {
    let mut r = BankRig::new(2, 28);
    let info = r.reg("INFO");
    let on_info = BusCycle {
        addr: info,
        ..Default::default()
    };
    assert_ne!(r.read(info), 0);
    r.clock(true, on_info);
    r.clock(true, on_info);
    for _ in 0..3 {
        r.clock(false, on_info);
        assert_eq!(r.bank.rdata(), 0);
    }
}
