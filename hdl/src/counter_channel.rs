//! One channel of the counter bank: filters, decoder, counter, index logic,
//! error detection, snapshot registers and the channel's register decode.

use crate::input_filter::InputFilter;
use crate::step_decoder::StepDecoder;
use crate::up_down_counter::UpDownCounter;
use motionhdl_spec::bus::CounterParams;
use motionhdl_spec::regmap::{self, Block};
use rust_hdl::prelude::*;

/// One counter channel (docs/counter_bank.md). Counts quadrature ×4/×2/×1,
/// pulse+direction or CW/CCW input into a `width`-bit counter held in a
/// 32-bit register whose upper bits stay 0 (synthesis removes them).
///
/// The channel decodes its own registers from the register map, so the bank
/// only ORs the channels' `rdata`.
#[derive(LogicBlock)]
pub struct CounterChannel {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Encoder A (or pulse, or CW) pin, asynchronous.
    pub a: Signal<In, Bit>,
    /// Encoder B (or direction, or CCW) pin, asynchronous.
    pub b: Signal<In, Bit>,
    /// Index pin, asynchronous.
    pub z: Signal<In, Bit>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<8>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Register bus write strobe.
    pub we: Signal<In, Bit>,
    /// Register bus read strobe.
    pub re: Signal<In, Bit>,
    /// Bank-wide snapshot strobe (a write to SNAPSHOT).
    pub snapshot: Signal<In, Bit>,
    /// The bank's PRESET register, as stored.
    pub preset: Signal<In, Bits<32>>,
    /// PRESET's bits in the counter's low half are all ones (kept by the bank).
    pub preset_low_is_max: Signal<In, Bit>,
    /// PRESET's bits in the counter's low half are not all 0.
    pub preset_low_is_nonzero: Signal<In, Bit>,
    /// The register of this channel that the read one clock earlier
    /// addressed, as it stood in that clock, or 0 (the bank ORs the
    /// channels and registers the result).
    pub rdata: Signal<Out, Bits<32>>,
    /// The live count (W bits), for the bank's HOME_COUNT.
    pub count: Signal<Out, Bits<32>>,
    /// STATUS.ERR and STATUS.SEEN, live (flip-flops), for the safety
    /// block's COUNTER_CAUSE.
    pub error: Signal<Out, Bit>,
    pub index_seen: Signal<Out, Bit>,
    filter_a: InputFilter,
    filter_b: InputFilter,
    filter_z: InputFilter,
    a_prev: DFF<Bit>,
    b_prev: DFF<Bit>,
    zg_prev: DFF<Bit>,
    zg_q: DFF<Bit>,
    decoder: StepDecoder,
    counter: UpDownCounter,
    load_q: DFF<Bit>,
    err_q: DFF<Bit>,
    index_latch_q: DFF<Bit>,
    index_clear_q: DFF<Bit>,
    index: DFF<Bits<32>>,
    err: DFF<Bit>,
    err_count: DFF<Bits<8>>,
    // err_count == 2^E − 1, kept beside it so that the increment enable is
    // not an 8-bit compare (not a register of the specification).
    err_sat: DFF<Bit>,
    seen: DFF<Bit>,
    armed: DFF<Bit>,
    ctrl: DFF<Bits<32>>,
    snap_count: DFF<Bits<32>>,
    snap_index: DFF<Bits<32>>,
    snap_status: DFF<Bits<32>>,
    // Read stage 1: the addressed register's value, chosen by the address
    // bits within the channel's stride, and whether the read is for this
    // channel. So the bank's stage 2 is an AND-OR of one word per channel.
    read_sel: DFF<Bit>,
    read_word: DFF<Bits<32>>,

    // Addresses and field positions, from the register map.
    addr_ctrl: Constant<Bits<8>>,
    addr_cmd: Constant<Bits<8>>,
    channel_page: Constant<Bits<5>>,
    slot_ctrl: Constant<Bits<3>>,
    slot_count: Constant<Bits<3>>,
    slot_index: Constant<Bits<3>>,
    slot_status: Constant<Bits<3>>,
    ctrl_writable: Constant<Bits<32>>,
    mode_lsb: Constant<Bits<5>>,
    reverse_bit: Constant<Bits<5>>,
    err_en_bit: Constant<Bits<5>>,
    idx_invert_bit: Constant<Bits<5>>,
    idx_latch_bit: Constant<Bits<5>>,
    idx_clear_bit: Constant<Bits<5>>,
    idx_gate_bit: Constant<Bits<5>>,
    idx_oneshot_bit: Constant<Bits<5>>,
    filter_ab_lsb: Constant<Bits<5>>,
    filter_z_lsb: Constant<Bits<5>>,
    cmd_clear_bit: Constant<Bits<5>>,
    cmd_load_bit: Constant<Bits<5>>,
    cmd_arm_bit: Constant<Bits<5>>,
    cmd_clear_status_bit: Constant<Bits<5>>,
    status_err: Constant<Bits<32>>,
    status_armed: Constant<Bits<32>>,
    status_seen: Constant<Bits<32>>,
    status_a: Constant<Bits<32>>,
    status_b: Constant<Bits<32>>,
    status_z: Constant<Bits<32>>,
    status_err_count_lsb: Constant<Bits<5>>,
    status_err_count_mask: Constant<Bits<32>>,
    // The build's features (CounterFeatures): each gates what the register
    // map alone cannot remove (commands, reads, the snapshot).
    has_index: Constant<Bit>,
    has_clear_status: Constant<Bit>,
    has_snapshot: Constant<Bit>,
    // Counter width.
    quadrature_modes: Constant<Bits<3>>,
    sign_bit: Constant<Bits<32>>,
    sign_extension: Constant<Bits<32>>,
    err_max_minus_one: Constant<Bits<8>>,

    // Combinational temporaries.
    level_a: Signal<Local, Bit>,
    level_b: Signal<Local, Bit>,
    level_z: Signal<Local, Bit>,
    illegal: Signal<Local, Bit>,
    count_now: Signal<Local, Bits<32>>,
    cmd_clear: Signal<Local, Bit>,
    cmd_load: Signal<Local, Bit>,
    zg: Signal<Local, Bit>,
    index_event: Signal<Local, Bit>,
    index_act: Signal<Local, Bit>,
    cmd_write: Signal<Local, Bit>,
    status: Signal<Local, Bits<32>>,
    count_read: Signal<Local, Bits<32>>,
    count_view: Signal<Local, Bits<32>>,
    index_view: Signal<Local, Bits<32>>,
    status_view: Signal<Local, Bits<32>>,
    index_read: Signal<Local, Bits<32>>,
}

/// A field's position in the full map. A CTRL field the build lacks is not
/// writable there (the build's CTRL mask), so its bits read 0; a CMD field
/// it lacks is gated by a feature constant.
fn bit_of(block: &Block, reg: &str, field: &str) -> Constant<Bits<5>> {
    let f = block.array("CH").register(reg).field(field);
    Constant::new((f.lsb as u64).into())
}

/// A field's mask in the build's map: 0 for a field the build lacks.
fn mask_of(block: &Block, reg: &str, field: &str) -> Constant<Bits<32>> {
    let f = block.array("CH").register(reg).find_field(field);
    Constant::new((f.map_or(0, |f| f.mask()) as u64).into())
}

impl CounterChannel {
    /// Channel `channel` of a bank of `axes` channels with `params.width`-bit
    /// counters (2..=32), `params.err_bits`-bit error counters (1..=8) and
    /// `params.features`.
    pub fn new(axes: u32, channel: u32, params: CounterParams) -> Self {
        let CounterParams {
            width,
            err_bits,
            features,
        } = params;
        assert!(
            (2..=32).contains(&width),
            "width = {width} out of range 2..=32"
        );
        assert!(
            (1..=8).contains(&err_bits),
            "err_bits = {err_bits} out of range 1..=8"
        );
        let full = regmap::counter_bank(axes, width);
        let map = regmap::counter_bank_with(axes, width, features);
        // The map's table says which builds have CLEAR_STATUS.
        let cmd = map.array("CH").register("CMD");
        let ch = full.array("CH");
        let addr = |reg: &str| Constant::new((ch.address(channel, reg) as u64).into());
        // Read stage 1 splits the address into the channel's page (bits 7..3)
        // and the register's slot in it (bits 2..0).
        assert_eq!(ch.stride, 8, "read stage 1 assumes a stride of 8 words");
        assert_eq!(ch.offset % 8, 0, "channel pages start at a multiple of 8");
        assert_eq!(map.address_bits, 8);
        let slot = |reg: &str| Constant::new(((ch.address(channel, reg) % 8) as u64).into());
        // `illegal` tests MODE < PULSE_DIR for "a quadrature mode".
        assert!(
            [regmap::mode::X4, regmap::mode::X2, regmap::mode::X1]
                .iter()
                .all(|&m| m < regmap::mode::PULSE_DIR)
                && regmap::mode::CW_CCW > regmap::mode::PULSE_DIR
        );
        let width_mask = CounterParams::new(width, 1).count_mask();
        let sign_bit = 1u32 << (width - 1);
        let k32 = |v: u32| Constant::new((v as u64).into());
        Self {
            clock: Default::default(),
            reset: Default::default(),
            a: Default::default(),
            b: Default::default(),
            z: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            re: Default::default(),
            snapshot: Default::default(),
            preset: Default::default(),
            preset_low_is_max: Default::default(),
            preset_low_is_nonzero: Default::default(),
            rdata: Default::default(),
            count: Default::default(),
            error: Default::default(),
            index_seen: Default::default(),
            filter_a: InputFilter::with_filtering(features.filter),
            filter_b: InputFilter::with_filtering(features.filter),
            filter_z: InputFilter::with_filtering(features.filter),
            a_prev: Default::default(),
            b_prev: Default::default(),
            zg_prev: Default::default(),
            zg_q: Default::default(),
            decoder: Default::default(),
            counter: UpDownCounter::new(width),
            load_q: Default::default(),
            err_q: Default::default(),
            index_latch_q: Default::default(),
            index_clear_q: Default::default(),
            index: Default::default(),
            err: Default::default(),
            err_count: Default::default(),
            err_sat: Default::default(),
            seen: Default::default(),
            armed: Default::default(),
            ctrl: Default::default(),
            snap_count: Default::default(),
            snap_index: Default::default(),
            snap_status: Default::default(),
            read_sel: Default::default(),
            read_word: Default::default(),
            addr_ctrl: addr("CTRL"),
            addr_cmd: addr("CMD"),
            channel_page: Constant::new(((ch.address(channel, "CTRL") / 8) as u64).into()),
            slot_ctrl: slot("CTRL"),
            slot_count: slot("COUNT"),
            slot_index: slot("INDEX"),
            slot_status: slot("STATUS"),
            ctrl_writable: k32(map.array("CH").register("CTRL").writable_mask()),
            mode_lsb: bit_of(&full, "CTRL", "MODE"),
            reverse_bit: bit_of(&full, "CTRL", "REVERSE"),
            err_en_bit: bit_of(&full, "CTRL", "ERR_EN"),
            idx_invert_bit: bit_of(&full, "CTRL", "IDX_INVERT"),
            idx_latch_bit: bit_of(&full, "CTRL", "IDX_LATCH"),
            idx_clear_bit: bit_of(&full, "CTRL", "IDX_CLEAR"),
            idx_gate_bit: bit_of(&full, "CTRL", "IDX_GATE"),
            idx_oneshot_bit: bit_of(&full, "CTRL", "IDX_ONESHOT"),
            filter_ab_lsb: bit_of(&full, "CTRL", "FILTER_AB"),
            filter_z_lsb: bit_of(&full, "CTRL", "FILTER_Z"),
            cmd_clear_bit: bit_of(&full, "CMD", "CLEAR"),
            cmd_load_bit: bit_of(&full, "CMD", "LOAD"),
            cmd_arm_bit: bit_of(&full, "CMD", "ARM"),
            cmd_clear_status_bit: bit_of(&full, "CMD", "CLEAR_STATUS"),
            status_err: mask_of(&map, "STATUS", "ERR"),
            status_armed: mask_of(&map, "STATUS", "ARMED"),
            status_seen: mask_of(&map, "STATUS", "SEEN"),
            status_a: mask_of(&map, "STATUS", "A"),
            status_b: mask_of(&map, "STATUS", "B"),
            status_z: mask_of(&map, "STATUS", "Z"),
            status_err_count_lsb: bit_of(&full, "STATUS", "ERR_COUNT"),
            status_err_count_mask: mask_of(&map, "STATUS", "ERR_COUNT"),
            has_index: Constant::new(features.index),
            has_clear_status: Constant::new(cmd.find_field("CLEAR_STATUS").is_some()),
            has_snapshot: Constant::new(features.snapshot),
            quadrature_modes: Constant::new((regmap::mode::PULSE_DIR as u64).into()),
            sign_bit: k32(sign_bit),
            sign_extension: k32(!width_mask),
            err_max_minus_one: Constant::new((((1u32 << err_bits) - 2) as u64).into()),
            level_a: Default::default(),
            level_b: Default::default(),
            level_z: Default::default(),
            illegal: Default::default(),
            count_now: Default::default(),
            cmd_clear: Default::default(),
            cmd_load: Default::default(),
            zg: Default::default(),
            index_event: Default::default(),
            index_act: Default::default(),
            cmd_write: Default::default(),
            status: Default::default(),
            count_read: Default::default(),
            count_view: Default::default(),
            index_view: Default::default(),
            status_view: Default::default(),
            index_read: Default::default(),
        }
    }
}

mod inspect;

impl Logic for CounterChannel {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            a_prev,
            b_prev,
            zg_prev,
            zg_q,
            load_q,
            err_q,
            index_latch_q,
            index_clear_q,
            index,
            err,
            err_count,
            err_sat,
            seen,
            armed,
            ctrl,
            snap_count,
            snap_index,
            snap_status,
            read_sel,
            read_word
        );
        // Input conditioning.
        self.filter_a.clock.next = self.clock.val();
        self.filter_b.clock.next = self.clock.val();
        self.filter_z.clock.next = self.clock.val();
        self.filter_a.reset.next = self.reset.val();
        self.filter_b.reset.next = self.reset.val();
        self.filter_z.reset.next = self.reset.val();
        self.filter_a.pin.next = self.a.val();
        self.filter_b.pin.next = self.b.val();
        self.filter_z.pin.next = self.z.val();
        self.filter_a.setting.next = self
            .ctrl
            .q
            .val()
            .get_bits::<4>(self.filter_ab_lsb.val().index());
        self.filter_b.setting.next = self
            .ctrl
            .q
            .val()
            .get_bits::<4>(self.filter_ab_lsb.val().index());
        self.filter_z.setting.next = self
            .ctrl
            .q
            .val()
            .get_bits::<4>(self.filter_z_lsb.val().index());
        self.level_a.next = self.filter_a.level.val();
        self.level_b.next = self.filter_b.level.val();
        self.level_z.next = self.filter_z.level.val();

        // Commands.
        self.cmd_write.next = self.we.val() & (self.addr.val() == self.addr_cmd.val());
        self.cmd_clear.next =
            self.cmd_write.val() & self.wdata.val().get_bit(self.cmd_clear_bit.val().index());
        self.cmd_load.next =
            self.cmd_write.val() & self.wdata.val().get_bit(self.cmd_load_bit.val().index());

        // Step decision, registered before it reaches the counter.
        self.decoder.clock.next = self.clock.val();
        // LOAD's second edge adds PRESET, not a step: the step decided now
        // is dropped here, which keeps the counter's carry-in a plain flop.
        self.decoder.hold.next = self.reset.val() | self.cmd_load.val();
        self.decoder.a.next = self.level_a.val();
        self.decoder.b.next = self.level_b.val();
        self.decoder.a_prev.next = self.a_prev.q.val();
        self.decoder.b_prev.next = self.b_prev.q.val();
        self.decoder.mode.next = self.ctrl.q.val().get_bits::<3>(self.mode_lsb.val().index());
        self.decoder.reverse.next = self.ctrl.q.val().get_bit(self.reverse_bit.val().index());
        // Illegal: a quadrature mode (X4, X2, X1 are 0..=2) and A and B
        // both changed.
        self.illegal.next = (self.level_a.val() ^ self.a_prev.q.val())
            & (self.level_b.val() ^ self.b_prev.q.val())
            & (self.ctrl.q.val().get_bits::<3>(self.mode_lsb.val().index())
                < self.quadrature_modes.val());

        // Index.
        self.zg.next = (self.level_z.val()
            ^ self.ctrl.q.val().get_bit(self.idx_invert_bit.val().index()))
            & (!self.ctrl.q.val().get_bit(self.idx_gate_bit.val().index())
                | (self.level_a.val() & self.level_b.val()));
        self.index_event.next = self.zg_q.q.val() & !self.zg_prev.q.val();
        self.index_act.next = self.index_event.val()
            & (!self
                .ctrl
                .q
                .val()
                .get_bit(self.idx_oneshot_bit.val().index())
                | self.armed.q.val());

        // Counter. CLEAR, the first edge of LOAD and a registered
        // clear-on-index are its synchronous reset; the second edge of LOAD
        // adds PRESET to the cleared count in place of the step.
        self.counter.clock.next = self.clock.val();
        self.counter.up.next = self.decoder.up_q.val();
        self.counter.down.next = self.decoder.down_q.val();
        self.counter.load_value.next = self.preset.val();
        self.counter.load_low_is_max.next = self.preset_low_is_max.val();
        self.counter.load_low_is_nonzero.next = self.preset_low_is_nonzero.val();
        self.counter.load.next = self.load_q.q.val();
        self.counter.clear.next = self.reset.val()
            | self.cmd_clear.val()
            | self.cmd_load.val()
            | self.index_clear_q.q.val();
        self.count_now.next = self.counter.count.val();
        self.count.next = self.count_now.val();
        self.error.next = self.err.q.val();
        self.index_seen.next = self.seen.q.val();
        self.load_q.d.next = self.cmd_load.val() & !self.cmd_clear.val();
        // Index actions are registered and act at the next edge, on the
        // count after the event's edge (a register, not the adder output).
        self.index_latch_q.d.next =
            self.index_act.val() & self.ctrl.q.val().get_bit(self.idx_latch_bit.val().index());
        self.index_clear_q.d.next =
            self.index_act.val() & self.ctrl.q.val().get_bit(self.idx_clear_bit.val().index());

        // Next state. Later assignments take priority.
        self.a_prev.d.next = self.level_a.val();
        self.b_prev.d.next = self.level_b.val();
        self.zg_q.d.next = self.zg.val();
        if self.reset.val() {
            self.zg_prev.d.next = self.zg.val();
        } else {
            self.zg_prev.d.next = self.zg_q.q.val();
        }
        self.err_q.d.next =
            self.illegal.val() & self.ctrl.q.val().get_bit(self.err_en_bit.val().index());
        if self.index_latch_q.q.val() {
            self.index.d.next = self.count_now.val();
        }
        if self.err_q.q.val() {
            self.err.d.next = true;
            if !self.err_sat.q.val() {
                self.err_count.d.next = self.err_count.q.val() + 1;
                self.err_sat.d.next = self.err_count.q.val() == self.err_max_minus_one.val();
            }
        }
        if self.index_event.val() & self.has_index.val() {
            self.seen.d.next = true;
        }
        if self.index_act.val()
            & self
                .ctrl
                .q
                .val()
                .get_bit(self.idx_oneshot_bit.val().index())
        {
            self.armed.d.next = false;
        }
        if self.cmd_write.val() {
            if self.wdata.val().get_bit(self.cmd_arm_bit.val().index()) & self.has_index.val() {
                self.armed.d.next = true;
            }
            if self
                .wdata
                .val()
                .get_bit(self.cmd_clear_status_bit.val().index())
                & self.has_clear_status.val()
            {
                self.err.d.next = false;
                self.err_count.d.next = 0.into();
                self.err_sat.d.next = false;
                self.seen.d.next = false;
            }
        }
        if self.we.val() & (self.addr.val() == self.addr_ctrl.val()) {
            self.ctrl.d.next = self.wdata.val() & self.ctrl_writable.val();
        }

        // Status word and snapshot.
        self.status.next = (bit_cast::<32, 8>(self.err_count.q.val())
            << self.status_err_count_lsb.val())
            & self.status_err_count_mask.val();
        if self.err.q.val() {
            self.status.next = self.status.val() | self.status_err.val();
        }
        if self.armed.q.val() {
            self.status.next = self.status.val() | self.status_armed.val();
        }
        if self.seen.q.val() {
            self.status.next = self.status.val() | self.status_seen.val();
        }
        if self.level_a.val() {
            self.status.next = self.status.val() | self.status_a.val();
        }
        if self.level_b.val() {
            self.status.next = self.status.val() | self.status_b.val();
        }
        if self.level_z.val() {
            self.status.next = self.status.val() | self.status_z.val();
        }
        if self.snapshot.val() {
            self.snap_count.d.next = self.count_now.val();
            self.snap_index.d.next = self.index.q.val();
            self.snap_status.d.next = self.status.val();
        }

        // Reads, stage 1: the addressed register's value now (captured, or
        // live in a build without SNAPSHOT); W-bit values sign-extended to
        // 32 bits.
        if self.has_snapshot.val() {
            self.count_view.next = self.snap_count.q.val();
            self.index_view.next = self.snap_index.q.val();
            self.status_view.next = self.snap_status.q.val();
        } else {
            self.count_view.next = self.count_now.val();
            self.index_view.next = self.index.q.val();
            self.status_view.next = self.status.val();
        }
        if (self.count_view.val() & self.sign_bit.val()).any() {
            self.count_read.next = self.count_view.val() | self.sign_extension.val();
        } else {
            self.count_read.next = self.count_view.val();
        }
        if (self.index_view.val() & self.sign_bit.val()).any() {
            self.index_read.next = self.index_view.val() | self.sign_extension.val();
        } else {
            self.index_read.next = self.index_view.val();
        }
        self.read_sel.d.next =
            self.re.val() & (self.addr.val().get_bits::<5>(3) == self.channel_page.val());
        self.read_word.d.next = 0.into();
        if self.addr.val().get_bits::<3>(0) == self.slot_ctrl.val() {
            self.read_word.d.next = self.ctrl.q.val();
        }
        if self.addr.val().get_bits::<3>(0) == self.slot_count.val() {
            self.read_word.d.next = self.count_read.val();
        }
        if (self.addr.val().get_bits::<3>(0) == self.slot_index.val()) & self.has_index.val() {
            self.read_word.d.next = self.index_read.val();
        }
        if self.addr.val().get_bits::<3>(0) == self.slot_status.val() {
            self.read_word.d.next = self.status_view.val();
        }

        if self.reset.val() {
            self.index.d.next = 0.into();
            self.err.d.next = false;
            self.err_count.d.next = 0.into();
            self.err_sat.d.next = false;
            self.seen.d.next = false;
            self.armed.d.next = false;
            self.load_q.d.next = false;
            self.err_q.d.next = false;
            self.index_latch_q.d.next = false;
            self.index_clear_q.d.next = false;
            self.ctrl.d.next = 0.into();
            self.snap_count.d.next = 0.into();
            self.snap_index.d.next = 0.into();
            self.snap_status.d.next = 0.into();
            self.read_sel.d.next = false;
        }

        // Reads, stage 2: the word, if the read was for this channel.
        self.rdata.next = 0.into();
        if self.read_sel.q.val() {
            self.rdata.next = self.read_word.q.val();
        }
    }
}
