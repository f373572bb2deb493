//! One counter channel: its registers and the logic of one clock.

use std::sync::OnceLock;

use super::{sign_extend, wrap, CounterFeatures, CounterParams, InputFilter};
use crate::regmap::{self, Block, Field};

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
    /// The field's bits; a field the build lacks has none (reads 0, writes
    /// nothing).
    fn of(f: Option<&Field>) -> Self {
        f.map_or(Self { lsb: 0, mask: 0 }, |f| Self {
            lsb: f.lsb,
            mask: f.mask(),
        })
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
        let c = |n: &str| Bits::of(ctrl.find_field(n));
        let k = |n: &str| Bits::of(cmd.find_field(n));
        let s = |n: &str| Bits::of(status.find_field(n));
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

    /// The layout for counters of `width` bits with `features`. Built once
    /// per pair: exhaustive checks create a channel per explored transition,
    /// and the map allocates.
    fn for_build(width: u32, features: CounterFeatures) -> Self {
        static LAYOUTS: OnceLock<Vec<Layout>> = OnceLock::new();
        let all = LAYOUTS.get_or_init(|| {
            (2..=32)
                .flat_map(|w| {
                    (0..16).map(move |b| {
                        let f = CounterFeatures::from_bits(b);
                        Layout::from_map(&regmap::counter_bank_with(1, w, f))
                    })
                })
                .collect()
        });
        all[(width - 2) as usize * 16 + features.bits() as usize]
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
        let params =
            CounterParams::new(params.width, params.err_bits).with_features(params.features);
        Self {
            params,
            layout: Layout::for_build(params.width, params.features),
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

        let filtering = self.params.features.filter;
        n.fa.clock(inp.a, l.filter_ab.get(s.ctrl) as u8, inp.reset, filtering);
        n.fb.clock(inp.b, l.filter_ab.get(s.ctrl) as u8, inp.reset, filtering);
        n.fz.clock(inp.z, l.filter_z.get(s.ctrl) as u8, inp.reset, filtering);
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
        } else if d.event && self.params.features.index {
            // A build without the index has no SEEN to set.
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
        // A build without the snapshot has no snapshot registers: they stay 0.
        if inp.snapshot && self.params.features.snapshot {
            n.snap_count = s.count;
            n.snap_index = s.index;
            n.snap_status = self.status();
        }
        self.state = n;
    }

    /// A channel register as the bus reads it: CTRL live, CMD 0 (write-only),
    /// COUNT / INDEX / STATUS from the snapshot registers (live in a build
    /// without SNAPSHOT), COUNT and INDEX sign-extended from W bits. Panics
    /// on a name the map does not have.
    pub fn read(&self, register: &str) -> u32 {
        let s = &self.state;
        let w = self.params.width;
        let (count, index, status) = if self.params.features.snapshot {
            (s.snap_count, s.snap_index, s.snap_status)
        } else {
            (s.count, s.index, self.status())
        };
        match register {
            "CTRL" => s.ctrl,
            "CMD" => 0,
            "COUNT" => sign_extend(count, w),
            "INDEX" if self.params.features.index => sign_extend(index, w),
            "STATUS" => status,
            other => panic!("channel has no register {other}"),
        }
    }
}
