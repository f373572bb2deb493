//! The MCU's side of the top level: the FSMC bridge, its register decode,
//! the identity block and the counter bank (docs/motion_controller.md).

use crate::{CounterBank, FsmcBridge, IdBlock, PulseBank, SafetyIo};
use motionhdl_spec::regmap;
use motionhdl_spec::Config;
use rust_hdl::prelude::*;

fsmc_host_block! {
    /// `N` axes of encoder input behind the MCU's register bus, and the RAM
    /// window's port for the shared RAM. Addresses come from `regmap::mcu_map`;
    /// a register address no block decodes reads 0 and ignores writes.
    pub struct McuSide<const N: usize> {
        /// Encoder A inputs, one per axis.
        pub enc_a: Signal<In, Bits<N>>,
        /// Encoder B inputs.
        pub enc_b: Signal<In, Bits<N>>,
        /// Encoder index inputs.
        pub enc_z: Signal<In, Bits<N>>,
        /// RAM window: word address (A[9:0] of an access with A11 = 1).
        pub ram_addr: Signal<Out, Bits<10>>,
        /// RAM window write data.
        pub ram_wdata: Signal<Out, Bits<16>>,
        /// RAM window write, at the edge where it is high.
        pub ram_we: Signal<Out, Bit>,
        /// The word at the previous edge's `ram_addr` (tie to 0 without a RAM).
        pub ram_rdata: Signal<In, Bits<16>>,
        /// Pulse generator outputs F1 per axis (pulse, CW or quadrature A).
        pub pulse_f1: Signal<Out, Bits<N>>,
        /// Pulse generator outputs F2 per axis (direction, CCW or quadrature B).
        pub pulse_f2: Signal<Out, Bits<N>>,
        /// The e-stop chain: high = released; low or open = stop (pull down).
        pub estop_ok: Signal<In, Bit>,
        /// LIMIT_POS pins per axis (asynchronous).
        pub limit_pos: Signal<In, Bits<N>>,
        /// LIMIT_NEG pins per axis.
        pub limit_neg: Signal<In, Bits<N>>,
        /// HOME pins per axis.
        pub home: Signal<In, Bits<N>>,
        /// Drive ALARM pins per axis.
        pub alarm: Signal<In, Bits<N>>,
        /// Drive ENABLE per axis, high = enabled.
        pub drive_enable: Signal<Out, Bits<N>>,
        /// The IRQ pin to the MCU (active low after reset).
        pub irq: Signal<Out, Bit>,
        /// The PC rang the DSP side's mailbox (ISA bridge): CAUSE.DOORBELL.
        pub doorbell: Signal<In, Bit>,
        /// SERVO block register port (the servo card's top): word address.
        pub servo_addr: Signal<Out, Bits<4>>,
        /// SERVO register write data.
        pub servo_wdata: Signal<Out, Bits<32>>,
        /// SERVO register write strobe.
        pub servo_we: Signal<Out, Bit>,
        /// SERVO register read strobe.
        pub servo_re: Signal<Out, Bit>,
        /// SERVO read data (tie to 0 without the block: its page reads 0).
        pub servo_rdata: Signal<In, Bits<32>>,
        /// The servo tick (one clock; tie low without the block): the
        /// counters' and pulse positions' snapshot at its edge, and
        /// SAFETY's CAUSE.SERVO_TICK.
        pub servo_tick: Signal<In, Bit>,
        /// The SERVO block's `safe` input: SAFETY's HALT.
        pub servo_safe: Signal<Out, Bit>,
        /// General-purpose input pins (asynchronous).
        pub gpi: Signal<In, Bits<16>>,
        /// General-purpose outputs: the level driven while `gpo_oe` is 1.
        pub gpo_out: Signal<Out, Bits<16>>,
        /// General-purpose outputs: drive the pin (else release it).
        pub gpo_oe: Signal<Out, Bits<16>>,
        mcu_bus: FsmcBridge,
        identity: IdBlock,
        counters: CounterBank<N>,
        pulses: PulseBank<N>,
        safety: SafetyIo<N>,
        // Which block the last read went to, so its `rdata` reaches the bridge.
        read_from_id: DFF<Bit>,
        read_from_counters: DFF<Bit>,
        read_from_pulses: DFF<Bit>,
        read_from_safety: DFF<Bit>,
        read_from_servo: DFF<Bit>,
        id_page: Constant<Bits<6>>,
        counter_page: Constant<Bits<2>>,
        pulse_page: Constant<Bits<1>>,
        safety_page: Constant<Bits<3>>,
        servo_page: Constant<Bits<6>>,
        counter_snapshot: Constant<Bits<8>>,
        select_id: Signal<Local, Bit>,
        select_counters: Signal<Local, Bit>,
        select_pulses: Signal<Local, Bit>,
        select_safety: Signal<Local, Bit>,
        select_servo: Signal<Local, Bit>,
        counter_snapshot_write: Signal<Local, Bit>,
    }
}

impl<const N: usize> McuSide<N> {
    /// The MCU side for `config` (its axis count must be `N`).
    pub fn new(config: &Config) -> Self {
        assert_eq!(
            config.axes() as usize,
            N,
            "axes = {} but N = {N}",
            config.axes()
        );
        let map = regmap::mcu_map(config);
        let id = map.block("ID");
        let counter = map.block("COUNTER");
        let pulse = map.block("PULSE");
        let safety = map.block("SAFETY");
        // The decode below compares reg_addr[9:4] with the ID page,
        // reg_addr[9:8] with the counter page, reg_addr[9] with the pulse
        // page and reg_addr[9:7] with the safety page: the table must agree.
        assert_eq!(id.address_bits, 4);
        assert_eq!(counter.address_bits, 8);
        assert_eq!(pulse.address_bits, 9);
        assert_eq!(safety.address_bits, 7);
        // SERVO's page (reg_addr[9:4]) is decoded in every build; without
        // the block its port reads 0 and its writes go nowhere.
        let servo_page = regmap::MCU_SERVO_WORD_BASE >> 4;
        let servo_blocks = usize::from(config.servo_dac());
        if config.servo_dac() {
            let servo = map.block("SERVO");
            assert_eq!((servo.base, servo.address_bits), (servo_page << 4, 4));
        }
        assert_eq!(
            map.blocks.len(),
            4 + servo_blocks,
            "a block the decode does not know"
        );
        assert_eq!(regmap::MCU_HALFWORD_ADDRESS_BITS, 12);
        // The bridge sends every A11 = 1 access to the RAM port.
        assert!(map.memories.len() <= 1);
        for m in &map.memories {
            assert_eq!(m.byte_offset, 1 << 12, "RAM window is A11 = 1");
            assert_eq!(m.words, 1 << 10);
        }
        fsmc_host_new!({
            enc_a: Default::default(),
            enc_b: Default::default(),
            enc_z: Default::default(),
            ram_addr: Default::default(),
            ram_wdata: Default::default(),
            ram_we: Default::default(),
            ram_rdata: Default::default(),
            mcu_bus: FsmcBridge::new(),
            identity: IdBlock::new(config),
            counters: CounterBank::with_features(
                config.counter_width(),
                config.counter_features(),
            ),
            pulses: PulseBank::new(config.counter_width()),
            safety: SafetyIo::new(config.filter_tick_clocks()),
            estop_ok: Default::default(),
            limit_pos: Default::default(),
            limit_neg: Default::default(),
            home: Default::default(),
            alarm: Default::default(),
            drive_enable: Default::default(),
            irq: Default::default(),
            doorbell: Default::default(),
            gpi: Default::default(),
            gpo_out: Default::default(),
            gpo_oe: Default::default(),
            read_from_safety: Default::default(),
            read_from_servo: Default::default(),
            servo_page: Constant::new((servo_page as u64).into()),
            select_servo: Default::default(),
            counter_snapshot_write: Default::default(),
            servo_addr: Default::default(),
            servo_wdata: Default::default(),
            servo_we: Default::default(),
            servo_re: Default::default(),
            servo_rdata: Default::default(),
            servo_tick: Default::default(),
            servo_safe: Default::default(),
            safety_page: Constant::new(((safety.base >> 7) as u64).into()),
            select_safety: Default::default(),
            pulse_f1: Default::default(),
            pulse_f2: Default::default(),
            read_from_pulses: Default::default(),
            pulse_page: Constant::new(((pulse.base >> 9) as u64).into()),
            counter_snapshot: Constant::new((counter.register("SNAPSHOT").offset as u64).into()),
            select_pulses: Default::default(),
            read_from_id: Default::default(),
            read_from_counters: Default::default(),
            id_page: Constant::new(((id.base >> 4) as u64).into()),
            counter_page: Constant::new(((counter.base >> 8) as u64).into()),
            select_id: Default::default(),
            select_counters: Default::default(),
        })
    }

    /// The safety block's per-axis stops (up, down), for the top's
    /// contract checks.
    pub fn stops(&self) -> (u32, u32) {
        (
            self.safety.stop_up.val().index() as u32,
            self.safety.stop_down.val().index() as u32,
        )
    }

    /// The safety block's HALT, for the top's contract checks.
    pub fn halt(&self) -> bool {
        self.safety.halt.val()
    }

    /// The pulse bank, for the top's contract checks.
    pub fn pulses(&self) -> &PulseBank<N> {
        &self.pulses
    }

    /// The counter bank, for probing in traces.
    pub fn counters(&self) -> &CounterBank<N> {
        &self.counters
    }
}

impl<const N: usize> Logic for McuSide<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            read_from_id,
            read_from_counters,
            read_from_pulses,
            read_from_safety,
            read_from_servo
        );
        self.safety.clock.next = self.clock.val();
        self.safety.reset.next = self.reset.val();
        self.pulses.clock.next = self.clock.val();
        self.pulses.reset.next = self.reset.val();
        self.mcu_bus.clock.next = self.clock.val();
        self.mcu_bus.reset.next = self.reset.val();
        self.identity.clock.next = self.clock.val();
        self.identity.reset.next = self.reset.val();
        self.counters.clock.next = self.clock.val();
        self.counters.reset.next = self.reset.val();
        // MCU side.
        self.mcu_bus.ne_n.next = self.fsmc_ne_n.val();
        self.mcu_bus.noe_n.next = self.fsmc_noe_n.val();
        self.mcu_bus.nwe_n.next = self.fsmc_nwe_n.val();
        self.mcu_bus.a.next = self.fsmc_a.val();
        self.mcu_bus.d_in.next = self.fsmc_d_in.val();
        self.fsmc_d_out.next = self.mcu_bus.d_out.val();
        self.fsmc_d_oe.next = self.mcu_bus.d_oe.val();
        // Register decode from the map.
        self.select_id.next = self.mcu_bus.reg_addr.val().get_bits::<6>(4) == self.id_page.val();
        self.select_counters.next =
            self.mcu_bus.reg_addr.val().get_bits::<2>(8) == self.counter_page.val();
        self.identity.addr.next = self.mcu_bus.reg_addr.val().get_bits::<4>(0);
        self.identity.re.next = self.mcu_bus.reg_re.val() & self.select_id.val();
        self.counters.addr.next = self.mcu_bus.reg_addr.val().get_bits::<8>(0);
        self.counters.wdata.next = self.mcu_bus.reg_wdata.val();
        self.counters.we.next = self.mcu_bus.reg_we.val() & self.select_counters.val();
        self.counters.re.next = self.mcu_bus.reg_re.val() & self.select_counters.val();
        self.select_pulses.next =
            self.mcu_bus.reg_addr.val().get_bits::<1>(9) == self.pulse_page.val();
        self.pulses.addr.next = self.mcu_bus.reg_addr.val().get_bits::<9>(0);
        self.pulses.wdata.next = self.mcu_bus.reg_wdata.val();
        self.pulses.we.next = self.mcu_bus.reg_we.val() & self.select_pulses.val();
        self.pulses.re.next = self.mcu_bus.reg_re.val() & self.select_pulses.val();
        // The counter bank's SNAPSHOT also captures the pulse positions, so
        // commanded and counted positions are read as one coherent set; the
        // servo tick takes both at its edge, as the write does.
        self.counter_snapshot_write.next = self.mcu_bus.reg_we.val()
            & self.select_counters.val()
            & (self.mcu_bus.reg_addr.val().get_bits::<8>(0) == self.counter_snapshot.val());
        self.pulses.snapshot.next = self.counter_snapshot_write.val() | self.servo_tick.val();
        self.counters.snapshot_strobe.next = self.servo_tick.val();
        self.select_servo.next =
            self.mcu_bus.reg_addr.val().get_bits::<6>(4) == self.servo_page.val();
        self.servo_addr.next = self.mcu_bus.reg_addr.val().get_bits::<4>(0);
        self.servo_wdata.next = self.mcu_bus.reg_wdata.val();
        self.servo_we.next = self.mcu_bus.reg_we.val() & self.select_servo.val();
        self.servo_re.next = self.mcu_bus.reg_re.val() & self.select_servo.val();
        self.servo_safe.next = self.safety.halt.val();
        self.safety.servo_tick.next = self.servo_tick.val();
        self.select_safety.next =
            self.mcu_bus.reg_addr.val().get_bits::<3>(7) == self.safety_page.val();
        self.safety.addr.next = self.mcu_bus.reg_addr.val().get_bits::<7>(0);
        self.safety.wdata.next = self.mcu_bus.reg_wdata.val();
        self.safety.we.next = self.mcu_bus.reg_we.val() & self.select_safety.val();
        self.safety.re.next = self.mcu_bus.reg_re.val() & self.select_safety.val();
        // The machine side: HALT stops every axis; move events raise IRQ.
        self.safety.estop_ok.next = self.estop_ok.val();
        self.safety.limit_pos.next = self.limit_pos.val();
        self.safety.limit_neg.next = self.limit_neg.val();
        self.safety.home.next = self.home.val();
        self.safety.alarm.next = self.alarm.val();
        self.pulses.stop_up.next = self.safety.stop_up.val();
        self.pulses.stop_down.next = self.safety.stop_down.val();
        self.pulses.home_capture.next = self.safety.home_event.val();
        self.counters.home.next = self.safety.home_event.val();
        self.safety.at_soft_max.next = self.pulses.at_soft_max.val();
        self.safety.at_soft_min.next = self.pulses.at_soft_min.val();
        self.safety.counter_error.next = self.counters.error.val();
        self.safety.index_seen.next = self.counters.index_seen.val();
        self.safety.doorbell.next = self.doorbell.val();
        self.safety.done.next = self.pulses.done.val();
        self.safety.low.next = self.pulses.low.val();
        self.pulses.halt.next = self.safety.halt.val();
        self.drive_enable.next = self.safety.drive_enable.val();
        self.irq.next = self.safety.irq.val();
        self.safety.gpi.next = self.gpi.val();
        self.gpo_out.next = self.safety.gpo_out.val();
        self.gpo_oe.next = self.safety.gpo_oe.val();
        self.pulse_f1.next = self.pulses.f1.val();
        self.pulse_f2.next = self.pulses.f2.val();
        if self.mcu_bus.reg_re.val() {
            self.read_from_id.d.next = self.select_id.val();
            self.read_from_counters.d.next = self.select_counters.val();
            self.read_from_pulses.d.next = self.select_pulses.val();
            self.read_from_safety.d.next = self.select_safety.val();
            self.read_from_servo.d.next = self.select_servo.val();
        }
        self.mcu_bus.reg_rdata.next = 0.into();
        if self.read_from_id.q.val() {
            self.mcu_bus.reg_rdata.next = self.identity.rdata.val();
        }
        if self.read_from_counters.q.val() {
            self.mcu_bus.reg_rdata.next = self.counters.rdata.val();
        }
        if self.read_from_pulses.q.val() {
            self.mcu_bus.reg_rdata.next = self.pulses.rdata.val();
        }
        if self.read_from_safety.q.val() {
            self.mcu_bus.reg_rdata.next = self.safety.rdata.val();
        }
        if self.read_from_servo.q.val() {
            self.mcu_bus.reg_rdata.next = self.servo_rdata.val();
        }
        if self.reset.val() {
            self.read_from_id.d.next = false;
            self.read_from_counters.d.next = false;
            self.read_from_pulses.d.next = false;
            self.read_from_safety.d.next = false;
            self.read_from_servo.d.next = false;
        }
        // The RAM window.
        self.ram_addr.next = self.mcu_bus.ram_addr.val();
        self.ram_wdata.next = self.mcu_bus.ram_wdata.val();
        self.ram_we.next = self.mcu_bus.ram_we.val();
        self.mcu_bus.ram_rdata.next = self.ram_rdata.val();
        // Encoders.
        self.counters.a.next = self.enc_a.val();
        self.counters.b.next = self.enc_b.val();
        self.counters.z.next = self.enc_z.val();
    }
}
