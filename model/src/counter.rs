//! Cycle model of the quadrature/pulse counter bank (docs/counter_bank.md).
//!
//! Every register of the specification is a field of [`ChannelState`] (or of
//! [`Bank`]), and [`Channel::clock`] computes every next value from the
//! values before the edge, exactly as the flip-flops do, so the testbench can
//! compare the model with the HDL every clock and exhaustive checks can put
//! whole states into sets.
//!
//! Addresses, field positions and masks all come from
//! [`regmap::counter_bank`]; nothing here restates a number the map owns.

use std::sync::OnceLock;

use crate::regmap::{self, Access, Block, Field};
pub use motionhdl_spec::bus::{mask_bits, sign_extend, wrap, BusCycle, CounterParams};

/// Synchroniser + digital filter for one input (spec "Input conditioning").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InputFilter {
    /// First synchroniser flop.
    pub s1: bool,
    /// Second synchroniser flop: the sample the filter judges.
    pub s2: bool,
    /// Accepted level.
    pub level: bool,
    /// Clocks still to see before a change of `s2` is accepted (a 4-bit
    /// register counting down from F).
    pub cnt: u8,
}

impl InputFilter {
    /// Width of `cnt` and of the FILTER_AB / FILTER_Z settings.
    const CNT_MASK: u8 = 0xf;

    /// One rising edge. `setting` is F; only its low 4 bits exist in
    /// hardware. `cnt` counts down: it is loaded with F on every clock where
    /// `s2` equals `level` (and when a change is accepted), and a change is
    /// accepted when it reaches 0. So F is taken on the last clock before a
    /// change starts; writing CTRL during a change does not alter it.
    pub fn clock(&mut self, pin: bool, setting: u8, reset: bool) {
        let f = setting & Self::CNT_MASK;
        let before = *self;
        self.s1 = pin;
        self.s2 = before.s1;
        if reset {
            self.level = before.s2;
            self.cnt = 0;
        } else if before.s2 == before.level {
            self.cnt = f;
        } else if before.cnt == 0 {
            self.level = before.s2;
            self.cnt = f;
        } else {
            self.cnt = before.cnt - 1;
        }
    }
}

/// What one channel sees in one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChannelInputs {
    /// Raw A pin.
    pub a: bool,
    /// Raw B pin.
    pub b: bool,
    /// Raw Z (index) pin.
    pub z: bool,
    /// Synchronous reset, active high.
    pub reset: bool,
    /// Data written to this channel's CTRL this clock.
    pub ctrl_write: Option<u32>,
    /// Data written to this channel's CMD this clock.
    pub cmd_write: Option<u32>,
    /// SNAPSHOT written this clock (bank-wide).
    pub snapshot: bool,
    /// The bank's PRESET register (raw 32 bits as stored).
    pub preset: u32,
}

/// One channel's complete state: every register of the specification.
///
/// W-bit values are stored zero-extended (upper bits 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ChannelState {
    pub fa: InputFilter,
    pub fb: InputFilter,
    pub fz: InputFilter,
    /// Accepted A of the previous clock.
    pub a_prev: bool,
    /// Accepted B of the previous clock.
    pub b_prev: bool,
    /// `zg_q` of the previous clock (`zg` in reset).
    pub zg_prev: bool,
    /// `zg` registered: the index edge detector reads it, one clock after
    /// the levels it is computed from.
    pub zg_q: bool,
    /// Registered up decision: the adder's input (spec "Counting").
    pub up_q: bool,
    /// Registered down decision.
    pub down_q: bool,
    /// Second edge of a LOAD pending: the adder adds PRESET instead of the step.
    pub load_q: bool,
    /// Registered illegal transition with CTRL.ERR_EN: ERR and ERR_COUNT
    /// latch at the next edge.
    pub err_q: bool,
    /// Registered index action: latch the count at the next edge.
    pub index_latch_q: bool,
    /// Registered index action: clear the count at the next edge.
    pub index_clear_q: bool,
    pub count: u32,
    pub index: u32,
    pub err: bool,
    pub err_count: u32,
    pub seen: bool,
    pub armed: bool,
    pub ctrl: u32,
    pub snap_count: u32,
    pub snap_index: u32,
    /// The status word at the last SNAPSHOT.
    pub snap_status: u32,
}

/// A field's position, copied out of the register map so the per-clock code
/// does not search it by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Bits {
    lsb: u32,
    mask: u32,
}

impl Bits {
    fn of(f: &Field) -> Self {
        Self {
            lsb: f.lsb,
            mask: f.mask(),
        }
    }
    fn get(self, reg: u32) -> u32 {
        (reg & self.mask) >> self.lsb
    }
    fn flag(self, reg: u32) -> bool {
        self.get(reg) != 0
    }
    fn put(self, value: u32) -> u32 {
        (value << self.lsb) & self.mask
    }
}

/// Every CTRL, CMD and STATUS field the channel logic uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Layout {
    mode: Bits,
    reverse: Bits,
    err_en: Bits,
    idx_invert: Bits,
    idx_latch: Bits,
    idx_clear: Bits,
    idx_gate: Bits,
    idx_oneshot: Bits,
    filter_ab: Bits,
    filter_z: Bits,
    ctrl_writable: u32,
    clear: Bits,
    load: Bits,
    arm: Bits,
    clear_status: Bits,
    st_err: Bits,
    st_armed: Bits,
    st_seen: Bits,
    st_a: Bits,
    st_b: Bits,
    st_z: Bits,
    st_err_count: Bits,
}

impl Layout {
    fn from_map(map: &Block) -> Self {
        let ch = map.array("CH");
        let ctrl = ch.register("CTRL");
        let cmd = ch.register("CMD");
        let status = ch.register("STATUS");
        let c = |n: &str| Bits::of(ctrl.field(n));
        let k = |n: &str| Bits::of(cmd.field(n));
        let s = |n: &str| Bits::of(status.field(n));
        Self {
            mode: c("MODE"),
            reverse: c("REVERSE"),
            err_en: c("ERR_EN"),
            idx_invert: c("IDX_INVERT"),
            idx_latch: c("IDX_LATCH"),
            idx_clear: c("IDX_CLEAR"),
            idx_gate: c("IDX_GATE"),
            idx_oneshot: c("IDX_ONESHOT"),
            filter_ab: c("FILTER_AB"),
            filter_z: c("FILTER_Z"),
            ctrl_writable: ctrl.writable_mask(),
            clear: k("CLEAR"),
            load: k("LOAD"),
            arm: k("ARM"),
            clear_status: k("CLEAR_STATUS"),
            st_err: s("ERR"),
            st_armed: s("ARMED"),
            st_seen: s("SEEN"),
            st_a: s("A"),
            st_b: s("B"),
            st_z: s("Z"),
            st_err_count: s("ERR_COUNT"),
        }
    }

    /// The layout for counters of `width` bits. Built once per width: exhaustive
    /// checks create a channel per explored transition, and the map allocates.
    fn for_width(width: u32) -> Self {
        static LAYOUTS: OnceLock<Vec<Layout>> = OnceLock::new();
        let all = LAYOUTS.get_or_init(|| {
            (2..=32)
                .map(|w| Layout::from_map(&regmap::counter_bank(1, w)))
                .collect()
        });
        all[(width - 2) as usize]
    }
}

/// The combinational values of one clock, from the registers before the edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Decision {
    up: bool,
    down: bool,
    illegal: bool,
    zg: bool,
    event: bool,
    act: bool,
}

/// Place of (a, b) in the forward Gray order 00 → 10 → 11 → 01.
fn gray_position(a: bool, b: bool) -> u8 {
    match (a, b) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

/// One counter channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Channel {
    params: CounterParams,
    layout: Layout,
    state: ChannelState,
}

impl Channel {
    /// A channel at power-up: every flop 0, as the HDL's flops start.
    pub fn new(params: CounterParams) -> Self {
        // Re-validate: the fields are public, so params may not come from new().
        let params = CounterParams::new(params.width, params.err_bits);
        Self {
            params,
            layout: Layout::for_width(params.width),
            state: ChannelState::default(),
        }
    }

    pub fn params(&self) -> CounterParams {
        self.params
    }

    pub fn state(&self) -> &ChannelState {
        &self.state
    }

    /// Replaces the whole state (exhaustive checks start from chosen states).
    pub fn set_state(&mut self, s: ChannelState) {
        self.state = s;
    }

    /// The live status word (what a SNAPSHOT in this clock would capture).
    pub fn status(&self) -> u32 {
        let s = &self.state;
        let l = &self.layout;
        l.st_err.put(u32::from(s.err))
            | l.st_armed.put(u32::from(s.armed))
            | l.st_seen.put(u32::from(s.seen))
            | l.st_a.put(u32::from(s.fa.level))
            | l.st_b.put(u32::from(s.fb.level))
            | l.st_z.put(u32::from(s.fz.level))
            | l.st_err_count.put(s.err_count)
    }

    /// Counting, error and index logic of the current clock. It reads only
    /// registers; the inputs of this clock reach it one edge later.
    fn decide(&self) -> Decision {
        let s = &self.state;
        let l = &self.layout;
        let (a, b, z) = (s.fa.level, s.fb.level, s.fz.level);
        let (ap, bp) = (s.a_prev, s.b_prev);
        let mode = l.mode.get(s.ctrl);

        let from = gray_position(ap, bp);
        let to = gray_position(a, b);
        let forward = to == (from + 1) % 4;
        let backward = to == (from + 3) % 4;
        let a_changed = a != ap;
        let rise_a = a && !ap;
        let rise_b = b && !bp;

        let (up, down) = match mode {
            regmap::mode::X4 => (forward, backward),
            regmap::mode::X2 => (forward && a_changed, backward && a_changed),
            regmap::mode::X1 => ((!ap && !bp) && (a && !b), (ap && !bp) && (!a && !b)),
            regmap::mode::PULSE_DIR => (rise_a && !b, rise_a && b),
            regmap::mode::CW_CCW => (rise_a && !rise_b, rise_b && !rise_a),
            _ => (false, false),
        };
        let quadrature = matches!(mode, regmap::mode::X4 | regmap::mode::X2 | regmap::mode::X1);
        let illegal = quadrature && a != ap && b != bp;
        // A Gray step never changes both inputs, so X4/X2/X1 cannot decide a
        // step on an illegal transition; the mask states the rule anyway.
        let (up, down) = if illegal { (false, false) } else { (up, down) };
        let (up, down) = if l.reverse.flag(s.ctrl) {
            (down, up)
        } else {
            (up, down)
        };

        let zi = z ^ l.idx_invert.flag(s.ctrl);
        let zg = zi && (!l.idx_gate.flag(s.ctrl) || (a && b));
        let event = s.zg_q && !s.zg_prev;
        let act = event && (!l.idx_oneshot.flag(s.ctrl) || s.armed);
        Decision {
            up,
            down,
            illegal,
            zg,
            event,
            act,
        }
    }

    /// The (up, down) decision of this clock from the current state; it is
    /// registered into `up_q`/`down_q` at the edge (0 in reset) and reaches
    /// the count one clock later. The inputs do not affect it.
    pub fn step(&self, _inp: &ChannelInputs) -> (bool, bool) {
        let d = self.decide();
        (d.up, d.down)
    }

    /// One rising clock edge.
    pub fn clock(&mut self, inp: &ChannelInputs) {
        let s = self.state;
        let l = self.layout;
        let w = self.params.width;
        let d = self.decide();
        let mut n = s;

        n.fa.clock(inp.a, l.filter_ab.get(s.ctrl) as u8, inp.reset);
        n.fb.clock(inp.b, l.filter_ab.get(s.ctrl) as u8, inp.reset);
        n.fz.clock(inp.z, l.filter_z.get(s.ctrl) as u8, inp.reset);
        // In reset too: the previous-value flops load the current values, so
        // no step or index event follows reset.
        n.a_prev = s.fa.level;
        n.b_prev = s.fb.level;
        n.zg_q = d.zg;
        n.zg_prev = if inp.reset { d.zg } else { s.zg_q };

        if inp.reset {
            n.up_q = false;
            n.down_q = false;
            n.load_q = false;
            n.err_q = false;
            n.index_latch_q = false;
            n.index_clear_q = false;
            n.count = 0;
            n.index = 0;
            n.err = false;
            n.err_count = 0;
            n.seen = false;
            n.armed = false;
            n.ctrl = 0;
            n.snap_count = 0;
            n.snap_index = 0;
            n.snap_status = 0;
            self.state = n;
            return;
        }

        let cmd = inp.cmd_write.unwrap_or(0);
        let clear = l.clear.flag(cmd);
        let load = l.load.flag(cmd);

        // LOAD's second edge adds PRESET in place of a step: the step decided
        // in the LOAD clock is dropped.
        n.up_q = d.up && !load;
        n.down_q = d.down && !load;
        let arm = l.arm.flag(cmd);
        let clear_status = l.clear_status.flag(cmd);

        // The adder: + PRESET on LOAD's second edge (the count is 0 then,
        // cleared by the first), else +1 if up_q, −1 if down_q.
        let stepped = if s.load_q {
            wrap(s.count.wrapping_add(inp.preset), w)
        } else if s.up_q {
            wrap(s.count.wrapping_add(1), w)
        } else if s.down_q {
            wrap(s.count.wrapping_sub(1), w)
        } else {
            wrap(s.count, w)
        };

        n.count = if clear || load || s.index_clear_q {
            0
        } else {
            stepped
        };
        n.load_q = load && !clear;
        n.index_latch_q = d.act && l.idx_latch.flag(s.ctrl);
        n.index_clear_q = d.act && l.idx_clear.flag(s.ctrl);
        if s.index_latch_q {
            n.index = s.count;
        }

        n.err_q = d.illegal && l.err_en.flag(s.ctrl);
        if clear_status {
            n.err = false;
            n.err_count = 0;
        } else if s.err_q {
            n.err = true;
            n.err_count = s.err_count.saturating_add(1).min(self.params.err_max());
        }
        if clear_status {
            n.seen = false;
        } else if d.event {
            n.seen = true;
        }
        if arm {
            n.armed = true;
        } else if d.act && l.idx_oneshot.flag(s.ctrl) {
            n.armed = false;
        }

        if let Some(data) = inp.ctrl_write {
            n.ctrl = data & l.ctrl_writable;
        }
        if inp.snapshot {
            n.snap_count = s.count;
            n.snap_index = s.index;
            n.snap_status = self.status();
        }
        self.state = n;
    }

    /// A channel register as the bus reads it: CTRL live, CMD 0 (write-only),
    /// COUNT / INDEX / STATUS from the snapshot registers, COUNT and INDEX
    /// sign-extended from W bits. Panics on a name the map does not have.
    pub fn read(&self, register: &str) -> u32 {
        let s = &self.state;
        let w = self.params.width;
        match register {
            "CTRL" => s.ctrl,
            "CMD" => 0,
            "COUNT" => sign_extend(s.snap_count, w),
            "INDEX" => sign_extend(s.snap_index, w),
            "STATUS" => s.snap_status,
            other => panic!("channel has no register {other}"),
        }
    }
}

/// A channel register, decoded once from the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ChReg {
    Ctrl,
    Cmd,
    Count,
    Index,
    Status,
}

impl ChReg {
    fn name(self) -> &'static str {
        match self {
            ChReg::Ctrl => "CTRL",
            ChReg::Cmd => "CMD",
            ChReg::Count => "COUNT",
            ChReg::Index => "INDEX",
            ChReg::Status => "STATUS",
        }
    }
}

/// What an address selects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    Unmapped,
    Info,
    Snapshot,
    Preset,
    Channel(usize, ChReg),
}

/// The bank: N channels, the PRESET register and the register bus.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bank {
    params: CounterParams,
    map: Block,
    /// Slot of every decodable address, indexed by address.
    decode: Vec<Slot>,
    channels: Vec<Channel>,
    preset: u32,
    /// The value a read captured at the last edge (stage 1 of the
    /// two-edge read).
    read_pending: Option<u32>,
    rdata: u32,
}

impl Bank {
    /// A bank at power-up (every flop 0), decoding `regmap::counter_bank`.
    pub fn new(axes: u32, params: CounterParams) -> Self {
        let map = regmap::counter_bank(axes, params.width);
        let mut decode = vec![Slot::Unmapped; 1usize << map.address_bits];
        for (addr, reg, element) in map.decoded() {
            let slot = match (element, reg.name) {
                (None, "INFO") => Slot::Info,
                (None, "SNAPSHOT") => Slot::Snapshot,
                (None, "PRESET") => Slot::Preset,
                (Some(i), name) => {
                    let r = [
                        ChReg::Ctrl,
                        ChReg::Cmd,
                        ChReg::Count,
                        ChReg::Index,
                        ChReg::Status,
                    ]
                    .into_iter()
                    .find(|r| r.name() == name)
                    .unwrap_or_else(|| {
                        panic!("the model does not implement channel register {name}")
                    });
                    Slot::Channel(i as usize, r)
                }
                (None, name) => panic!("the model does not implement bank register {name}"),
            };
            decode[addr as usize] = slot;
        }
        let channels = (0..axes).map(|_| Channel::new(params)).collect();
        Self {
            params,
            map,
            decode,
            channels,
            preset: 0,
            read_pending: None,
            rdata: 0,
        }
    }

    /// The register map this bank decodes.
    pub fn regmap(&self) -> &Block {
        &self.map
    }

    pub fn params(&self) -> CounterParams {
        self.params
    }

    pub fn channel(&self, i: usize) -> &Channel {
        &self.channels[i]
    }

    pub fn channels(&self) -> usize {
        self.channels.len()
    }

    /// The PRESET register as stored (raw 32 bits).
    pub fn preset(&self) -> u32 {
        self.preset
    }

    /// The registered read data.
    pub fn rdata(&self) -> u32 {
        self.rdata
    }

    /// The bus port is `addr[7:0]`: upper bits never reach the decoder.
    fn slot(&self, addr: u32) -> Slot {
        self.decode[wrap(addr, self.map.address_bits) as usize]
    }

    /// What a read of `addr` with `re` high in this clock returns: the
    /// register as it stands now, before this clock's edge (0 for unmapped
    /// and write-only addresses).
    pub fn read_value(&self, addr: u32) -> u32 {
        match self.slot(addr) {
            Slot::Unmapped | Slot::Snapshot => 0,
            Slot::Info => self.map.register("INFO").reset,
            Slot::Preset => sign_extend(self.preset, self.params.width),
            Slot::Channel(i, r) => {
                if self.map.array("CH").register(r.name()).access == Access::WriteOnly {
                    0
                } else {
                    self.channels[i].read(r.name())
                }
            }
        }
    }

    /// One rising clock edge; `pins[i]` = (a, b, z) of channel i.
    pub fn clock(&mut self, pins: &[(bool, bool, bool)], reset: bool, bus: &BusCycle) {
        assert_eq!(
            pins.len(),
            self.channels.len(),
            "pins for {} channels given to a bank of {}",
            pins.len(),
            self.channels.len()
        );
        let written = if bus.we {
            self.slot(bus.addr)
        } else {
            Slot::Unmapped
        };
        // Reads take two edges: the edge with `re` captures the addressed
        // register's value as it stands in that clock (before this edge's
        // write), the next one loads it into `rdata`.
        let rdata = match (reset, self.read_pending) {
            (true, _) => 0,
            (false, Some(value)) => value,
            (false, None) => self.rdata,
        };
        self.read_pending = (!reset && bus.re).then(|| self.read_value(bus.addr));
        let preset = self.preset;
        for (i, (ch, &(a, b, z))) in self.channels.iter_mut().zip(pins).enumerate() {
            ch.clock(&ChannelInputs {
                a,
                b,
                z,
                reset,
                ctrl_write: (written == Slot::Channel(i, ChReg::Ctrl)).then_some(bus.wdata),
                cmd_write: (written == Slot::Channel(i, ChReg::Cmd)).then_some(bus.wdata),
                snapshot: written == Slot::Snapshot,
                preset,
            });
        }
        if reset {
            self.preset = 0;
        } else if written == Slot::Preset {
            self.preset = bus.wdata;
        }
        self.rdata = rdata;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regmap::mode;

    /// Edges from a pin change to the count with F = 0: two synchroniser
    /// flops, the filter's accept, `up_q`, the count.
    const PIN_TO_COUNT: usize = 5;

    /// Edges from a Z change to INDEX with F = 0: two synchroniser flops,
    /// the filter's accept, `zg_q`, `index_latch_q`, the index register.
    const PIN_TO_INDEX: usize = 6;

    fn ctrl_field(name: &str, value: u32) -> u32 {
        let map = regmap::counter_bank(1, 28);
        let f = map.array("CH").register("CTRL").field(name);
        (value << f.lsb) & f.mask()
    }

    fn cmd_bit(name: &str) -> u32 {
        regmap::counter_bank(1, 28)
            .array("CH")
            .register("CMD")
            .field(name)
            .mask()
    }

    fn status_field(name: &str, status: u32) -> u32 {
        regmap::counter_bank(1, 28)
            .array("CH")
            .register("STATUS")
            .field(name)
            .get(status)
    }

    /// A channel driven through its pins, like the bank drives it.
    struct Rig {
        ch: Channel,
        pins: (bool, bool, bool),
        preset: u32,
    }

    impl Rig {
        /// Reset for 4 clocks with the pins at (a, b, z), then CTRL = ctrl,
        /// then enough idle clocks for the pipeline to be quiet.
        fn at(width: u32, err_bits: u32, ctrl: u32, pins: (bool, bool, bool)) -> Self {
            let mut r = Rig {
                ch: Channel::new(CounterParams::new(width, err_bits)),
                pins,
                preset: 0,
            };
            for _ in 0..4 {
                r.clock(ChannelInputs {
                    reset: true,
                    ..Default::default()
                });
            }
            r.clock(ChannelInputs {
                ctrl_write: Some(ctrl),
                ..Default::default()
            });
            r.idle(PIN_TO_COUNT);
            r
        }

        fn new(width: u32, ctrl: u32) -> Self {
            Self::at(width, 8, ctrl, (false, false, false))
        }

        fn clock(&mut self, extra: ChannelInputs) {
            let (a, b, z) = self.pins;
            self.ch.clock(&ChannelInputs {
                a,
                b,
                z,
                preset: self.preset,
                ..extra
            });
        }

        fn idle(&mut self, n: usize) {
            for _ in 0..n {
                self.clock(ChannelInputs::default());
            }
        }

        /// Applies each (a, b) for one clock, then lets the pipeline drain.
        fn walk(&mut self, ab: &[(bool, bool)]) {
            for &(a, b) in ab {
                self.pins.0 = a;
                self.pins.1 = b;
                self.idle(1);
            }
            self.idle(PIN_TO_INDEX);
        }

        fn z(&mut self, z: bool) {
            self.pins.2 = z;
            self.idle(PIN_TO_INDEX);
        }

        fn cmd(&mut self, name: &str) {
            self.cmd_word(cmd_bit(name));
        }

        /// A CMD write, then one idle clock so that a LOAD completes.
        fn cmd_word(&mut self, word: u32) {
            self.clock(ChannelInputs {
                cmd_write: Some(word),
                ..Default::default()
            });
            self.idle(1);
        }

        fn count(&self) -> i64 {
            i64::from(sign_extend(self.ch.state().count, self.ch.params().width) as i32)
        }
    }

    /// Pin levels (a, b).
    type Ab = (bool, bool);

    const FWD: [(bool, bool); 4] = [(true, false), (true, true), (false, true), (false, false)];
    const BWD: [(bool, bool); 4] = [(false, true), (true, true), (true, false), (false, false)];

    fn cycles(pattern: &[(bool, bool); 4], n: usize) -> Vec<(bool, bool)> {
        pattern.iter().copied().cycle().take(4 * n).collect()
    }

    #[test]
    fn params_are_checked() {
        assert_eq!(CounterParams::new(2, 1).count_mask(), 3);
        assert_eq!(CounterParams::new(32, 8).count_mask(), u32::MAX);
        assert_eq!(CounterParams::new(4, 2).err_max(), 3);
        let e = std::panic::catch_unwind(|| CounterParams::new(33, 8)).unwrap_err();
        assert_eq!(
            e.downcast_ref::<String>().unwrap(),
            "counter width = 33 out of range 2..=32"
        );
        let e = std::panic::catch_unwind(|| CounterParams::new(28, 0)).unwrap_err();
        assert_eq!(
            e.downcast_ref::<String>().unwrap(),
            "err_bits = 0 out of range 1..=8"
        );
    }

    #[test]
    fn x4_full_cycle_counts_plus_and_minus_four() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
        r.walk(&FWD);
        assert_eq!(r.count(), 4);
        r.walk(&BWD);
        assert_eq!(r.count(), 0);
        r.walk(&BWD);
        assert_eq!(r.count(), -4);
        assert_eq!(r.ch.state().count, (1 << 28) - 4);
        assert!(!r.ch.state().err);
    }

    #[test]
    fn x4_counts_each_gray_step() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
        for (i, &ab) in FWD.iter().enumerate() {
            r.walk(&[ab]);
            assert_eq!(r.count(), i as i64 + 1);
        }
    }

    #[test]
    fn x2_and_x1_count_two_and_one_per_cycle() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::X2));
        r.walk(&FWD);
        assert_eq!(r.count(), 2);
        r.walk(&BWD);
        r.walk(&BWD);
        assert_eq!(r.count(), -2);

        let mut r = Rig::new(28, ctrl_field("MODE", mode::X1));
        // X1 counts only 00 -> 10 up and 10 -> 00 down.
        r.walk(&FWD[..1]);
        assert_eq!(r.count(), 1);
        r.walk(&FWD[1..]);
        assert_eq!(r.count(), 1);
        r.walk(&BWD);
        assert_eq!(r.count(), 0);
        r.walk(&BWD);
        assert_eq!(r.count(), -1);
    }

    #[test]
    fn x4_x2_x1_agree_on_position() {
        let mut path = cycles(&FWD, 3);
        path.extend(cycles(&BWD, 1));
        path.extend(&FWD[..3]);
        path.extend(&BWD[1..]); // back to 00: net +2 cycles
        path.extend(cycles(&BWD, 5));
        path.extend(cycles(&FWD, 1)); // net -2 cycles
        let mut got = Vec::new();
        for m in [mode::X4, mode::X2, mode::X1] {
            let mut r = Rig::new(28, ctrl_field("MODE", m));
            r.walk(&path);
            got.push(r.count());
        }
        assert_eq!(got, vec![-8, -4, -2]);
    }

    #[test]
    fn reverse_negates_every_mode() {
        let gray = cycles(&FWD, 2);
        // Pulses on A only, B low: up in both pulse modes.
        let pulses = [(true, false), (false, false), (true, false), (false, false)];
        let cases: [(u32, &[Ab], i64); 5] = [
            (mode::X4, &gray, 8),
            (mode::X2, &gray, 4),
            (mode::X1, &gray, 2),
            (mode::PULSE_DIR, &pulses, 2),
            (mode::CW_CCW, &pulses, 2),
        ];
        for (m, path, expect) in cases {
            let mut r = Rig::new(28, ctrl_field("MODE", m));
            r.walk(path);
            let mut rev = Rig::new(28, ctrl_field("MODE", m) | ctrl_field("REVERSE", 1));
            rev.walk(path);
            assert_eq!(r.count(), expect, "mode {m}");
            assert_eq!(rev.count(), -expect, "mode {m}");
        }
    }

    #[test]
    fn pulse_direction_counts_rising_a_by_level_of_b() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::PULSE_DIR));
        // Three pulses with B = 0: up.
        r.walk(&[
            (true, false),
            (false, false),
            (true, false),
            (false, false),
            (true, false),
            (false, false),
        ]);
        assert_eq!(r.count(), 3);
        // B goes high on its own: no count. Then two pulses down.
        r.walk(&[(false, true)]);
        assert_eq!(r.count(), 3);
        r.walk(&[(true, true), (false, true), (true, true), (false, true)]);
        assert_eq!(r.count(), 1);
        // A falling never counts; the direction seen is B at the rising edge.
        r.walk(&[(true, false), (false, true)]);
        assert_eq!(r.count(), 2);
        assert!(!r.ch.state().err);
    }

    #[test]
    fn cw_ccw_counts_and_simultaneous_rise_does_not() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::CW_CCW));
        r.walk(&[(true, false), (false, false), (true, false), (false, false)]);
        assert_eq!(r.count(), 2);
        r.walk(&[(false, true), (false, false)]);
        assert_eq!(r.count(), 1);
        // Both rise in the same clock: nothing.
        r.walk(&[(true, true), (false, false)]);
        assert_eq!(r.count(), 1);
        // A rises while B is already high: up.
        r.walk(&[(false, true), (true, true)]);
        assert_eq!(r.count(), 1);
        assert!(!r.ch.state().err, "CW/CCW is not a quadrature mode");
    }

    #[test]
    fn illegal_transition_latches_error_and_saturates() {
        let ctrl = ctrl_field("MODE", mode::X4) | ctrl_field("ERR_EN", 1);
        let mut r = Rig::at(28, 2, ctrl, (false, false, false));
        let mut expect = [1, 2, 3, 3, 3].into_iter();
        for ab in [
            (true, true),
            (false, false),
            (true, true),
            (false, false),
            (true, true),
        ] {
            r.walk(&[ab]);
            assert_eq!(r.count(), 0, "an illegal transition never counts");
            assert!(r.ch.state().err);
            assert_eq!(r.ch.state().err_count, expect.next().unwrap());
        }
        // A legal step after it counts normally: (1,1) -> (0,1) is forward.
        r.walk(&[(false, true)]);
        assert_eq!(r.count(), 1);
        assert_eq!(r.ch.state().err_count, 3);
        assert_eq!(status_field("ERR_COUNT", r.ch.status()), 3);
        assert_eq!(status_field("ERR", r.ch.status()), 1);

        r.cmd("CLEAR_STATUS");
        assert!(!r.ch.state().err);
        assert_eq!(r.ch.state().err_count, 0);
        assert_eq!(r.count(), 1, "CLEAR_STATUS leaves the count alone");
    }

    #[test]
    fn illegal_without_err_en_latches_nothing() {
        for m in [mode::X4, mode::X2, mode::X1] {
            let mut r = Rig::new(28, ctrl_field("MODE", m));
            r.walk(&[(true, true), (false, false), (true, true)]);
            assert_eq!(r.count(), 0);
            assert!(!r.ch.state().err);
            assert_eq!(r.ch.state().err_count, 0);
        }
    }

    #[test]
    fn reserved_modes_never_count_nor_raise_errors() {
        for m in 5..=7 {
            let mut r = Rig::new(28, ctrl_field("MODE", m) | ctrl_field("ERR_EN", 1));
            r.walk(&cycles(&FWD, 2));
            r.walk(&[(true, true), (false, false), (true, false)]);
            assert_eq!(r.count(), 0, "mode {m}");
            assert!(!r.ch.state().err, "mode {m}");
        }
    }

    #[test]
    fn filter_rejects_f_clocks_and_accepts_f_plus_one() {
        for f in 0u8..=15 {
            // Drive s2 directly: a pulse of `len` clocks at s2, from the
            // idle state of setting F (`cnt` = F).
            let run = |len: u8| {
                let mut flt = InputFilter {
                    cnt: f,
                    ..Default::default()
                };
                let mut accepted = false;
                for t in 0..(len as usize + 20) {
                    flt.s2 = t < len as usize;
                    flt.clock(false, f, false);
                    accepted |= flt.level;
                    // Keep s2 under the test's control.
                    flt.s1 = false;
                }
                accepted
            };
            if f > 0 {
                assert!(!run(f), "F = {f}: a pulse of F clocks passed");
            }
            assert!(run(f + 1), "F = {f}: a pulse of F+1 clocks was rejected");
        }
    }

    #[test]
    fn filter_latency_pin_to_level_is_f_plus_three() {
        for f in [0u8, 1, 7, 15] {
            let mut flt = InputFilter::default();
            let mut edges = 0;
            while !flt.level {
                flt.clock(true, f, false);
                edges += 1;
                assert!(edges < 40);
            }
            assert_eq!(edges, u32::from(f) + 3, "F = {f}");
            assert_eq!(flt.cnt, f, "reloaded with F on acceptance");
        }
    }

    #[test]
    fn filter_takes_f_before_the_change_starts() {
        // Idle: cnt follows F every clock.
        let mut flt = InputFilter::default();
        flt.clock(false, 9, false);
        assert_eq!(flt.cnt, 9);
        flt.clock(false, 3, false);
        assert_eq!(flt.cnt, 3, "reloaded while s2 equals level");
        // A change starts: F is lowered to 0 mid-count, the change still
        // needs the 3 + 1 clocks of the F it started with.
        flt.s2 = true;
        flt.s1 = true;
        for left in [2, 1, 0] {
            flt.clock(true, 0, false);
            assert!(!flt.level);
            assert_eq!(flt.cnt, left);
        }
        flt.clock(true, 0, false);
        assert!(flt.level, "accepted on the fourth clock");
        assert_eq!(flt.cnt, 0, "and reloaded with the F of that clock");
        // Raised mid-count: the change is accepted after the old F too.
        let mut flt = InputFilter {
            s1: true,
            s2: true,
            level: false,
            cnt: 1,
        };
        flt.clock(true, 15, false);
        assert!(!flt.level);
        flt.clock(true, 15, false);
        assert!(flt.level);
        assert_eq!(flt.cnt, 15);
    }

    #[test]
    fn filter_follows_s2_during_reset() {
        let mut flt = InputFilter {
            s1: true,
            s2: true,
            level: false,
            cnt: 9,
        };
        flt.clock(false, 15, true);
        assert_eq!(
            flt,
            InputFilter {
                s1: false,
                s2: true,
                level: true,
                cnt: 0
            }
        );
    }

    #[test]
    fn pin_to_count_latency_and_one_step_per_clock() {
        let mut r = Rig::new(28, ctrl_field("MODE", mode::X4));
        r.pins.0 = true;
        let mut seen = Vec::new();
        for _ in 0..PIN_TO_COUNT {
            seen.push(r.count());
            r.idle(1);
        }
        seen.push(r.count());
        assert_eq!(seen, vec![0, 0, 0, 0, 0, 1]);
        // Filter setting F delays by F more clocks.
        let f = 6;
        let mut r = Rig::new(28, ctrl_field("FILTER_AB", f));
        r.pins.0 = true;
        r.idle(PIN_TO_COUNT + f as usize - 1);
        assert_eq!(r.count(), 0);
        r.idle(1);
        assert_eq!(r.count(), 1);
    }

    #[test]
    fn up_q_reaches_count_one_clock_later() {
        let mut ch = Channel::new(CounterParams::new(28, 8));
        let mut s = ChannelState::default();
        s.fa.level = true; // 00 -> 10: forward
        ch.set_state(s);
        assert_eq!(ch.step(&ChannelInputs::default()), (true, false));
        ch.clock(&ChannelInputs::default());
        assert!(ch.state().up_q);
        assert_eq!(ch.state().count, 0);
        ch.clock(&ChannelInputs::default());
        assert!(!ch.state().up_q);
        assert_eq!(ch.state().count, 1);
    }

    #[test]
    fn index_latch_records_the_count_one_clock_after_the_event() {
        let ctrl = ctrl_field("IDX_LATCH", 1);
        let mut ch = Channel::new(CounterParams::new(28, 8));
        ch.set_state(ChannelState {
            ctrl,
            count: 5,
            up_q: true,
            fz: InputFilter {
                level: true,
                s1: true,
                s2: true,
                cnt: 0,
            },
            zg_q: true,
            ..Default::default()
        });
        let z_high = ChannelInputs {
            z: true,
            ..Default::default()
        };
        ch.clock(&z_high);
        assert_eq!(ch.state().count, 6);
        assert!(ch.state().seen);
        assert!(ch.state().index_latch_q, "the action is registered");
        assert_eq!(ch.state().index, 0, "and lands one edge later");
        ch.clock(&z_high);
        assert_eq!(ch.state().index, 6);
        // Level, not edge: no second event while Z stays high.
        ch.set_state(ChannelState {
            count: 9,
            ..*ch.state()
        });
        ch.clock(&z_high);
        ch.clock(&z_high);
        assert_eq!(ch.state().index, 6);

        // Through the pins: index pulse at count 4.
        let mut r = Rig::new(28, ctrl);
        r.walk(&FWD);
        r.z(true);
        r.z(false);
        r.walk(&FWD[..2]);
        assert_eq!(r.count(), 6);
        assert_eq!(r.ch.state().index, 4);
    }

    #[test]
    fn index_clear_zeroes_count_after_the_latch_took_it() {
        let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_CLEAR", 1);
        let mut ch = Channel::new(CounterParams::new(28, 8));
        ch.set_state(ChannelState {
            ctrl,
            count: 5,
            down_q: true,
            fz: InputFilter {
                level: true,
                ..Default::default()
            },
            zg_q: true,
            ..Default::default()
        });
        ch.clock(&ChannelInputs::default());
        assert_eq!(ch.state().count, 4, "the event edge still steps");
        ch.clock(&ChannelInputs::default());
        assert_eq!(ch.state().count, 0);
        assert_eq!(ch.state().index, 4);

        let mut r = Rig::new(28, ctrl_field("IDX_CLEAR", 1));
        r.walk(&cycles(&FWD, 2));
        assert_eq!(r.count(), 8);
        r.z(true);
        assert_eq!(r.count(), 0);
        r.walk(&FWD[..1]);
        assert_eq!(r.count(), 1);
        assert!(r.ch.state().seen);
        r.cmd("CLEAR_STATUS");
        assert!(!r.ch.state().seen);
    }

    #[test]
    fn one_shot_index_acts_once_per_arm() {
        let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_ONESHOT", 1);
        let mut r = Rig::new(28, ctrl);
        r.walk(&FWD);
        r.z(true);
        r.z(false);
        assert_eq!(r.ch.state().index, 0, "not armed: no latch");
        assert!(r.ch.state().seen, "SEEN records every event");
        r.cmd("ARM");
        assert!(r.ch.state().armed);
        assert_eq!(status_field("ARMED", r.ch.status()), 1);
        r.walk(&FWD);
        r.z(true);
        assert_eq!(r.ch.state().index, 8);
        assert!(!r.ch.state().armed, "the first event disarms");
        r.z(false);
        r.walk(&FWD);
        r.z(true);
        assert_eq!(r.ch.state().index, 8, "disarmed: no second latch");
    }

    #[test]
    fn arm_wins_over_disarm_in_the_same_clock() {
        let ctrl = ctrl_field("IDX_ONESHOT", 1) | ctrl_field("IDX_LATCH", 1);
        let mut ch = Channel::new(CounterParams::new(28, 8));
        ch.set_state(ChannelState {
            ctrl,
            count: 3,
            armed: true,
            fz: InputFilter {
                level: true,
                ..Default::default()
            },
            zg_q: true,
            ..Default::default()
        });
        ch.clock(&ChannelInputs {
            cmd_write: Some(cmd_bit("ARM")),
            ..Default::default()
        });
        assert!(ch.state().armed);
        ch.clock(&ChannelInputs::default());
        assert_eq!(ch.state().index, 3);
    }

    #[test]
    fn index_gate_needs_a_and_b_high() {
        let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_GATE", 1);
        let mut r = Rig::new(28, ctrl);
        r.walk(&FWD[..1]); // (1,0), count 1
        r.z(true);
        assert!(!r.ch.state().seen, "gated off at (1,0)");
        // (1,1): the gate opens with Z high. The event is detected one
        // clock after the levels open the gate (`zg_q`), when the step into
        // (1,1) has reached the count, so the latch holds it.
        r.walk(&FWD[1..2]);
        assert!(r.ch.state().seen);
        assert_eq!(r.count(), 2);
        assert_eq!(r.ch.state().index, 2);
        r.walk(&FWD[2..]); // gate closes, count 4
        r.walk(&FWD); // reopens at (1,1), count 6
        assert_eq!(
            r.ch.state().index,
            6,
            "reopening with Z still high is a new event"
        );
    }

    #[test]
    fn index_invert_acts_on_falling_z() {
        let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_INVERT", 1);
        // Z idles high (active low): reset with Z high so no event at start.
        let mut r = Rig::at(28, 8, ctrl, (false, false, true));
        assert!(!r.ch.state().seen);
        r.walk(&FWD[..3]);
        r.z(false);
        assert!(r.ch.state().seen);
        assert_eq!(r.ch.state().index, 3);
        assert_eq!(
            status_field("Z", r.ch.status()),
            0,
            "STATUS.Z is before inversion"
        );
        r.z(true);
        r.walk(&FWD[3..]);
        assert_eq!(r.ch.state().index, 3);
    }

    #[test]
    fn command_and_index_priorities() {
        let base = ChannelState {
            count: 5,
            up_q: true,
            ..Default::default()
        };
        let run = |state: ChannelState, cmds: &[u32]| {
            let mut ch = Channel::new(CounterParams::new(28, 8));
            ch.set_state(state);
            let mut counts = Vec::new();
            for &cmd in cmds {
                ch.clock(&ChannelInputs {
                    cmd_write: Some(cmd),
                    preset: 0x1234,
                    ..Default::default()
                });
                counts.push(ch.state().count);
            }
            counts
        };
        let (clear, load) = (cmd_bit("CLEAR"), cmd_bit("LOAD"));
        assert_eq!(run(base, &[0]), [6]);
        assert_eq!(run(base, &[cmd_bit("ARM")]), [6], "other CMD bits count on");
        assert_eq!(run(base, &[clear]), [0]);
        assert_eq!(
            run(base, &[load, 0, 0]),
            [0, 0x1234, 0x1234],
            "LOAD clears, then adds PRESET in place of the step"
        );
        assert_eq!(run(base, &[clear | load, 0]), [0, 0], "CLEAR beats LOAD");
        assert_eq!(
            run(base, &[load, clear]),
            [0, 0],
            "CLEAR beats a pending LOAD"
        );
        assert_eq!(
            run(base, &[load, load, 0]),
            [0, 0, 0x1234],
            "LOAD again restarts"
        );
        let index_clear = ChannelState {
            index_clear_q: true,
            ..base
        };
        assert_eq!(run(index_clear, &[0]), [0], "index clear beats the step");
        assert_eq!(
            run(
                ChannelState {
                    load_q: true,
                    count: 0,
                    ..index_clear
                },
                &[0]
            ),
            [0],
            "index clear beats the load's second edge"
        );
    }

    #[test]
    fn load_takes_preset_modulo_two_to_the_w() {
        let mut r = Rig::new(4, 0);
        r.preset = 0xffff_fffa;
        r.cmd("LOAD");
        assert_eq!(r.ch.state().count, 0xa);
        assert_eq!(r.count(), -6);
        let mut r = Rig::new(28, 0);
        r.preset = 0x1234_5678;
        r.cmd("LOAD");
        assert_eq!(r.ch.state().count, 0x0234_5678);
    }

    #[test]
    fn count_wraps_at_both_ends() {
        for w in [4u32, 28, 32] {
            let max = CounterParams::new(w, 8).count_mask();
            let mut ch = Channel::new(CounterParams::new(w, 8));
            ch.set_state(ChannelState {
                count: max,
                up_q: true,
                ..Default::default()
            });
            ch.clock(&ChannelInputs::default());
            assert_eq!(ch.state().count, 0, "W = {w}");
            ch.set_state(ChannelState {
                down_q: true,
                ..*ch.state()
            });
            ch.clock(&ChannelInputs::default());
            assert_eq!(ch.state().count, max, "W = {w}");
        }
        // Through the pins at W = 4: 7 + 1 reads as -8, -8 - 1 reads as 7.
        let mut r = Rig::new(4, ctrl_field("MODE", mode::X4));
        r.preset = 7;
        r.cmd("LOAD");
        r.walk(&FWD[..1]);
        assert_eq!(r.ch.state().count, 8);
        assert_eq!(r.count(), -8);
        r.walk(&[(false, false)]);
        assert_eq!(r.count(), 7);
        r.walk(&cycles(&FWD, 4));
        assert_eq!(r.count(), 7, "16 steps wrap a 4-bit counter exactly once");
    }

    #[test]
    fn sign_extension_and_wrap() {
        assert_eq!(sign_extend(0x8, 4), 0xffff_fff8);
        assert_eq!(sign_extend(0x7, 4), 7);
        assert_eq!(sign_extend(0x0800_0000, 28), 0xf800_0000);
        assert_eq!(sign_extend(0x07ff_ffff, 28), 0x07ff_ffff);
        assert_eq!(sign_extend(0x8000_0000, 32), 0x8000_0000);
        assert_eq!(sign_extend(0x2, 2), 0xffff_fffe);
        assert_eq!(wrap(0x1234_5678, 28), 0x0234_5678);
        assert_eq!(wrap(0x1234_5678, 32), 0x1234_5678);
    }

    #[test]
    fn ctrl_write_is_masked_and_reads_back_live() {
        let mut ch = Channel::new(CounterParams::new(28, 8));
        ch.clock(&ChannelInputs {
            ctrl_write: Some(u32::MAX),
            ..Default::default()
        });
        let writable = regmap::counter_bank(1, 28)
            .array("CH")
            .register("CTRL")
            .writable_mask();
        assert_eq!(ch.state().ctrl, writable);
        assert_eq!(ch.read("CTRL"), writable);
        assert_eq!(ch.read("CMD"), 0);
    }

    // ---- bank ----

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
        assert_eq!(r.read(info), 3 | (28 << 8) | (8 << 16));
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
}
