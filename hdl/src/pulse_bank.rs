//! N pulse generators behind the register bus, each feeding a registered
//! pulse-mode selector (docs/pulse_generator.md).

use crate::{MoveEngine, PulseGenerator, PulseModeSelectorRegistered};
use motionhdl_spec::bus::CounterParams;
use motionhdl_spec::regmap;
use rust_hdl::prelude::*;

/// The pulse generators of `N` axes and their registers
/// (`regmap::pulse_bank`). Bus contract as the counter bank's: a write acts
/// at the edge where `we` is high; the edge where `re` is high takes the
/// address, the next edge loads `rdata`, which then holds.
#[derive(LogicBlock)]
pub struct PulseBank<const N: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<9>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Write strobe.
    pub we: Signal<In, Bit>,
    /// Read strobe.
    pub re: Signal<In, Bit>,
    /// Read data, valid from the second clock edge after `re`.
    pub rdata: Signal<Out, Bits<32>>,
    /// The counter bank's SNAPSHOT strobe: POSITION captures in that clock.
    pub snapshot: Signal<In, Bit>,
    /// The safety block's HALT: while high, RUN clears (writes to it are
    /// ignored), every segment FIFO empties and every generator drops its
    /// queued steps.
    pub halt: Signal<In, Bit>,
    /// Per axis: no step in the positive direction. An axis heading that
    /// way (its NCO rate positive, or steps up in its queue) stops as at
    /// HALT, or brakes at AX.DECEL when that is set and its rate heads up.
    pub stop_up: Signal<In, Bits<N>>,
    /// Per axis: no step in the negative direction.
    pub stop_down: Signal<In, Bits<N>>,
    /// Per axis: the home event (the safety block's `home_event`); high in
    /// a clock, HOME_POSITION takes POSITION's value at its edge.
    pub home_capture: Signal<In, Bits<N>>,
    /// Per axis: STATUS.DONE and not STATUS.BUSY (the move is out).
    pub done: Signal<Out, Bits<N>>,
    /// Per axis: STATUS.FIFO_LOW.
    pub low: Signal<Out, Bits<N>>,
    /// Per axis: POSITION >= SOFT_MAX (signed, WIDTH bits), a flip-flop
    /// one edge behind POSITION; the safety block's soft-limit input.
    pub at_soft_max: Signal<Out, Bits<N>>,
    /// Per axis: POSITION <= SOFT_MIN, likewise.
    pub at_soft_min: Signal<Out, Bits<N>>,
    /// F1 per axis (pulse, or CW pulses), registered.
    pub f1: Signal<Out, Bits<N>>,
    /// F2 per axis (direction, or CCW pulses), registered.
    pub f2: Signal<Out, Bits<N>>,
    generators: Vec<PulseGenerator>,
    engines: Vec<MoveEngine>,
    selectors: Vec<PulseModeSelectorRegistered>,
    run: DFF<Bits<N>>,
    /// `stop_up` and `stop_down` one clock ago: a stop brakes only in the
    /// clock it arrives (and while its brake runs).
    stop_up_q: DFF<Bits<N>>,
    stop_down_q: DFF<Bits<N>>,
    fresh_up: Signal<Local, Bits<N>>,
    fresh_down: Signal<Local, Bits<N>>,
    ctrl: Vec<DFF<Bits<3>>>,
    rate: Vec<DFF<Bits<32>>>,
    step_timing: Vec<DFF<Bits<32>>>,
    dir_timing: Vec<DFF<Bits<32>>>,
    low_water: Vec<DFF<Bits<32>>>,
    snap: Vec<DFF<Bits<32>>>,
    home_position: Vec<DFF<Bits<32>>>,
    soft_min: Vec<DFF<Bits<32>>>,
    soft_max: Vec<DFF<Bits<32>>>,
    decel: Vec<DFF<Bits<32>>>,
    above_max: Vec<DFF<Bit>>,
    below_min: Vec<DFF<Bit>>,
    quadrature_a: Vec<DFF<Bit>>,
    quadrature_b: Vec<DFF<Bit>>,
    out_f1: Vec<DFF<Bit>>,
    out_f2: Vec<DFF<Bit>>,
    read_pending: DFF<Bit>,
    read_addr: DFF<Bits<9>>,
    read_data: DFF<Bits<32>>,
    addr_info: Constant<Bits<9>>,
    addr_run: Constant<Bits<9>>,
    addr_ctrl: Vec<Constant<Bits<9>>>,
    addr_rate: Vec<Constant<Bits<9>>>,
    addr_step_timing: Vec<Constant<Bits<9>>>,
    addr_dir_timing: Vec<Constant<Bits<9>>>,
    addr_position: Vec<Constant<Bits<9>>>,
    addr_home_position: Vec<Constant<Bits<9>>>,
    addr_soft_min: Vec<Constant<Bits<9>>>,
    addr_soft_max: Vec<Constant<Bits<9>>>,
    addr_decel: Vec<Constant<Bits<9>>>,
    addr_status: Vec<Constant<Bits<9>>>,
    addr_seg_steps: Vec<Constant<Bits<9>>>,
    addr_seg_rate: Vec<Constant<Bits<9>>>,
    addr_seg_accel: Vec<Constant<Bits<9>>>,
    addr_seg_jerk: Vec<Constant<Bits<9>>>,
    addr_seg_push: Vec<Constant<Bits<9>>>,
    addr_low_water: Vec<Constant<Bits<9>>>,
    info: Constant<Bits<32>>,
    width_mask: Constant<Bits<32>>,
    sign_bit: Constant<Bits<32>>,
    sign_extension: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    two: Constant<Bits<32>>,
    four: Constant<Bits<32>>,
    low_water_mask: Constant<Bits<32>>,
    decel_mask: Constant<Bits<32>>,
    read_value: Signal<Local, Bits<32>>,
    axis_bit: Vec<Constant<Bits<N>>>,
    f1_bits: Signal<Local, Bits<N>>,
    f2_bits: Signal<Local, Bits<N>>,
    done_bits: Signal<Local, Bits<N>>,
    low_bits: Signal<Local, Bits<N>>,
    run_next: Signal<Local, Bits<N>>,
    stopped_bits: Signal<Local, Bits<N>>,
    axis_rate: Signal<Local, Bits<32>>,
    axis_pending: Signal<Local, Bits<16>>,
    heading_up: Signal<Local, Bit>,
    heading_down: Signal<Local, Bit>,
    axis_stopped: Signal<Local, Bit>,
    rate_into_stop: Signal<Local, Bit>,
    decelerating: Signal<Local, Bit>,
    // POSITION and the limits with the sign bit flipped: unsigned order
    // of these is the signed order of the WIDTH-bit values.
    position_key: Signal<Local, Bits<32>>,
    above_bits: Signal<Local, Bits<N>>,
    below_bits: Signal<Local, Bits<N>>,
}

impl<const N: usize> PulseBank<N> {
    /// `N` axes (1..=16) with `width`-bit POSITION (2..=32).
    pub fn new(width: u32) -> Self {
        assert!((1..=16).contains(&N), "axes = {N} out of range 1..=16");
        let map = regmap::pulse_bank(N as u32, width);
        let k9 = |v: u32| Constant::new((v as u64).into());
        let k32 = |v: u32| Constant::new((v as u64).into());
        let ax = map.array("AX");
        let per_axis = |name: &str| (0..N as u32).map(|i| k9(ax.address(i, name))).collect();
        let width_mask = CounterParams::new(width, 1).count_mask();
        assert_eq!(map.address_bits, 9);
        // STATUS is the generator's bits 16:0 OR the move engine's above.
        assert_eq!(ax.register("STATUS").field("BUSY").lsb, 16);
        assert_eq!(ax.register("STATUS").field("MOVING").lsb, 17);
        assert_eq!(ax.register("CTRL").writable_mask(), 0b111);
        assert_eq!(ax.register("STATUS").field("PENDING").width, 16);
        // `done` and `low` take STATUS bits 18 and 27 (see update), the
        // heading PENDING's sign at bit 15.
        assert_eq!(motionhdl_spec::pulse::PENDING_BITS, 16);
        assert_eq!(ax.register("STATUS").field("DONE").lsb, 18);
        assert_eq!(ax.register("STATUS").field("FIFO_LOW").lsb, 27);
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            re: Default::default(),
            rdata: Default::default(),
            snapshot: Default::default(),
            halt: Default::default(),
            stop_up: Default::default(),
            stop_up_q: Default::default(),
            stop_down_q: Default::default(),
            fresh_up: Default::default(),
            fresh_down: Default::default(),
            stop_down: Default::default(),
            home_capture: Default::default(),
            at_soft_max: Default::default(),
            at_soft_min: Default::default(),
            done: Default::default(),
            low: Default::default(),
            f1: Default::default(),
            f2: Default::default(),
            generators: (0..N).map(|_| PulseGenerator::new()).collect(),
            engines: (0..N).map(|_| MoveEngine::new()).collect(),
            selectors: (0..N)
                .map(|_| PulseModeSelectorRegistered::default())
                .collect(),
            run: Default::default(),
            ctrl: (0..N).map(|_| Default::default()).collect(),
            rate: (0..N).map(|_| Default::default()).collect(),
            step_timing: (0..N).map(|_| Default::default()).collect(),
            dir_timing: (0..N).map(|_| Default::default()).collect(),
            low_water: (0..N).map(|_| Default::default()).collect(),
            snap: (0..N).map(|_| Default::default()).collect(),
            home_position: (0..N).map(|_| Default::default()).collect(),
            soft_min: (0..N).map(|_| Default::default()).collect(),
            soft_max: (0..N).map(|_| Default::default()).collect(),
            decel: (0..N).map(|_| Default::default()).collect(),
            above_max: (0..N).map(|_| Default::default()).collect(),
            below_min: (0..N).map(|_| Default::default()).collect(),
            quadrature_a: (0..N).map(|_| Default::default()).collect(),
            quadrature_b: (0..N).map(|_| Default::default()).collect(),
            out_f1: (0..N).map(|_| Default::default()).collect(),
            out_f2: (0..N).map(|_| Default::default()).collect(),
            read_pending: Default::default(),
            read_addr: Default::default(),
            read_data: Default::default(),
            addr_info: k9(map.register("INFO").offset),
            addr_run: k9(map.register("RUN").offset),
            addr_ctrl: per_axis("CTRL"),
            addr_rate: per_axis("RATE"),
            addr_step_timing: per_axis("STEP_TIMING"),
            addr_dir_timing: per_axis("DIR_TIMING"),
            addr_position: per_axis("POSITION"),
            addr_home_position: per_axis("HOME_POSITION"),
            addr_soft_min: per_axis("SOFT_MIN"),
            addr_soft_max: per_axis("SOFT_MAX"),
            addr_decel: per_axis("DECEL"),
            addr_status: per_axis("STATUS"),
            addr_seg_steps: per_axis("SEG_STEPS"),
            addr_seg_rate: per_axis("SEG_RATE"),
            addr_seg_accel: per_axis("SEG_ACCEL"),
            addr_seg_jerk: per_axis("SEG_JERK"),
            addr_seg_push: per_axis("SEG_PUSH"),
            addr_low_water: per_axis("FIFO_LOW_WATER"),
            info: k32(map.register("INFO").reset),
            width_mask: k32(width_mask),
            sign_bit: k32(1 << (width - 1)),
            sign_extension: k32(!width_mask),
            one: k32(1),
            two: k32(2),
            four: k32(4),
            low_water_mask: k32(ax.register("FIFO_LOW_WATER").writable_mask()),
            decel_mask: k32(ax.register("DECEL").writable_mask()),
            read_value: Default::default(),
            axis_bit: (0..N).map(|i| Constant::new((1u64 << i).into())).collect(),
            f1_bits: Default::default(),
            f2_bits: Default::default(),
            done_bits: Default::default(),
            low_bits: Default::default(),
            run_next: Default::default(),
            stopped_bits: Default::default(),
            axis_rate: Default::default(),
            axis_pending: Default::default(),
            heading_up: Default::default(),
            heading_down: Default::default(),
            axis_stopped: Default::default(),
            rate_into_stop: Default::default(),
            decelerating: Default::default(),
            position_key: Default::default(),
            above_bits: Default::default(),
            below_bits: Default::default(),
        }
    }

    /// Axis `i`'s move engine, for probing.
    pub fn engine(&self, i: usize) -> &MoveEngine {
        &self.engines[i]
    }

    /// Axis `i`'s generator, for probing.
    pub fn generator(&self, i: usize) -> &PulseGenerator {
        &self.generators[i]
    }
}

impl<const N: usize> Logic for PulseBank<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            run,
            stop_up_q,
            stop_down_q,
            read_pending,
            read_addr,
            read_data
        );
        self.stop_up_q.d.next = self.stop_up.val();
        self.stop_down_q.d.next = self.stop_down.val();
        self.fresh_up.next = self.stop_up.val() & !self.stop_up_q.q.val();
        self.fresh_down.next = self.stop_down.val() & !self.stop_down_q.q.val();
        self.f1_bits.next = 0.into();
        self.f2_bits.next = 0.into();
        self.done_bits.next = 0.into();
        self.low_bits.next = 0.into();
        // Reads, stage 1: the address.
        self.read_pending.d.next = self.re.val();
        if self.re.val() {
            self.read_addr.d.next = self.addr.val();
        }
        // Stage 2: the addressed register into `rdata`.
        self.read_value.next = 0.into();
        if self.read_addr.q.val() == self.addr_info.val() {
            self.read_value.next = self.info.val();
        }
        if self.read_addr.q.val() == self.addr_run.val() {
            self.read_value.next = bit_cast::<32, N>(self.run.q.val());
        }
        self.run_next.next = self.run.q.val();
        if self.we.val() & (self.addr.val() == self.addr_run.val()) {
            self.run_next.next = self.wdata.val().get_bits::<N>(0);
        }
        self.stopped_bits.next = 0.into();
        self.above_bits.next = 0.into();
        self.below_bits.next = 0.into();
        for i in 0..N {
            // The direction the axis heads: its NCO rate's sign, or the
            // steps waiting in its queue (PENDING, signed). All flip-flops.
            self.axis_rate.next = self.rate[i].q.val();
            if self.ctrl[i].q.val().get_bit(2) | self.engines[i].braking.val() {
                self.axis_rate.next = self.engines[i].rate.val();
            }
            self.axis_pending.next = self.generators[i].status.val().get_bits::<16>(0);
            self.heading_up.next = (self.axis_rate.val().any() & !self.axis_rate.val().get_bit(31))
                | (self.axis_pending.val().any() & !self.axis_pending.val().get_bit(15));
            self.heading_down.next =
                self.axis_rate.val().get_bit(31) | self.axis_pending.val().get_bit(15);
            // A stop the NCO's rate heads into brakes when DECEL is set,
            // from the clock it arrives until the brake ends (HALT never
            // does); any other stop is instant, so a move started into a
            // standing stop is refused.
            self.rate_into_stop.next = (self.stop_up.val().get_bit(i)
                & (self.fresh_up.val().get_bit(i) | self.engines[i].braking.val())
                & self.axis_rate.val().any()
                & !self.axis_rate.val().get_bit(31))
                | (self.stop_down.val().get_bit(i)
                    & (self.fresh_down.val().get_bit(i) | self.engines[i].braking.val())
                    & self.axis_rate.val().get_bit(31));
            self.decelerating.next =
                !self.halt.val() & self.decel[i].q.val().any() & self.rate_into_stop.val();
            self.axis_stopped.next = (self.halt.val()
                | (self.stop_up.val().get_bit(i) & self.heading_up.val())
                | (self.stop_down.val().get_bit(i) & self.heading_down.val()))
                & !self.decelerating.val();
            if self.axis_stopped.val() | self.decelerating.val() {
                self.stopped_bits.next = self.stopped_bits.val() | self.axis_bit[i].val();
            }
            self.ctrl[i].clock.next = self.clock.val();
            self.quadrature_a[i].clock.next = self.clock.val();
            self.quadrature_b[i].clock.next = self.clock.val();
            self.out_f1[i].clock.next = self.clock.val();
            self.out_f2[i].clock.next = self.clock.val();
            // Quadrature A/B from the position's Gray phase, registered.
            self.quadrature_a[i].d.next = self.generators[i].position.val().get_bit(0)
                ^ self.generators[i].position.val().get_bit(1);
            self.quadrature_b[i].d.next = self.generators[i].position.val().get_bit(1);
            // The pins: one more register after the selector or quadrature.
            if self.ctrl[i].q.val().get_bit(1) {
                self.out_f1[i].d.next = self.quadrature_a[i].q.val();
                self.out_f2[i].d.next = self.quadrature_b[i].q.val();
            } else {
                self.out_f1[i].d.next = self.selectors[i].f1.val();
                self.out_f2[i].d.next = self.selectors[i].f2.val();
            }
            self.rate[i].clock.next = self.clock.val();
            self.step_timing[i].clock.next = self.clock.val();
            self.dir_timing[i].clock.next = self.clock.val();
            self.low_water[i].clock.next = self.clock.val();
            self.snap[i].clock.next = self.clock.val();
            self.home_position[i].clock.next = self.clock.val();
            self.soft_min[i].clock.next = self.clock.val();
            self.soft_max[i].clock.next = self.clock.val();
            self.decel[i].clock.next = self.clock.val();
            self.decel[i].d.next = self.decel[i].q.val();
            self.above_max[i].clock.next = self.clock.val();
            self.below_min[i].clock.next = self.clock.val();
            self.soft_min[i].d.next = self.soft_min[i].q.val();
            self.soft_max[i].d.next = self.soft_max[i].q.val();
            // Soft limits: signed WIDTH-bit compares, registered.
            self.position_key.next =
                (self.generators[i].position.val() & self.width_mask.val()) ^ self.sign_bit.val();
            self.above_max[i].d.next =
                self.position_key.val() >= (self.soft_max[i].q.val() ^ self.sign_bit.val());
            self.below_min[i].d.next =
                self.position_key.val() <= (self.soft_min[i].q.val() ^ self.sign_bit.val());
            if self.above_max[i].q.val() {
                self.above_bits.next = self.above_bits.val() | self.axis_bit[i].val();
            }
            if self.below_min[i].q.val() {
                self.below_bits.next = self.below_bits.val() | self.axis_bit[i].val();
            }
            // Moves: the engine sets the NCO's rate while CTRL.MOVES.
            self.engines[i].clock.next = self.clock.val();
            self.engines[i].reset.next = self.reset.val();
            self.engines[i].run.next =
                self.ctrl[i].q.val().get_bit(2) & self.run.q.val().get_bit(i);
            self.engines[i].commanded.next =
                self.ctrl[i].q.val().get_bit(2) & self.generators[i].commanded.val();
            self.engines[i].advancing.next = (self.ctrl[i].q.val().get_bit(2)
                | self.engines[i].braking.val())
                & self.generators[i].advancing.val();
            self.engines[i].push.next =
                self.we.val() & (self.addr.val() == self.addr_seg_push[i].val());
            self.engines[i].wdata.next = self.wdata.val();
            self.engines[i].write_steps.next =
                self.we.val() & (self.addr.val() == self.addr_seg_steps[i].val());
            self.engines[i].write_rate.next =
                self.we.val() & (self.addr.val() == self.addr_seg_rate[i].val());
            self.engines[i].write_accel.next =
                self.we.val() & (self.addr.val() == self.addr_seg_accel[i].val());
            self.engines[i].write_jerk.next =
                self.we.val() & (self.addr.val() == self.addr_seg_jerk[i].val());
            self.engines[i].clear_overflow.next =
                self.we.val() & (self.addr.val() == self.addr_ctrl[i].val());
            self.engines[i].low_water.next = self.low_water[i].q.val();
            self.engines[i].flush.next = self.axis_stopped.val();
            self.engines[i].brake.next = self.decelerating.val();
            self.engines[i].brake_rate.next = self.axis_rate.val();
            self.engines[i].decel.next = self.decel[i].q.val();
            if self.engines[i].status.val().get_bit(18)
                & !self.generators[i].status.val().get_bit(16)
            {
                self.done_bits.next = self.done_bits.val() | self.axis_bit[i].val();
            }
            if self.engines[i].status.val().get_bit(27) {
                self.low_bits.next = self.low_bits.val() | self.axis_bit[i].val();
            }
            self.ctrl[i].d.next = self.ctrl[i].q.val();
            self.rate[i].d.next = self.rate[i].q.val();
            self.step_timing[i].d.next = self.step_timing[i].q.val();
            self.dir_timing[i].d.next = self.dir_timing[i].q.val();
            self.low_water[i].d.next = self.low_water[i].q.val();
            self.snap[i].d.next = self.snap[i].q.val();
            self.home_position[i].d.next = self.home_position[i].q.val();
            self.generators[i].clock.next = self.clock.val();
            self.generators[i].reset.next = self.reset.val();
            self.generators[i].enable.next =
                self.run.q.val().get_bit(i) | self.engines[i].braking.val();
            self.generators[i].halt.next = self.axis_stopped.val();
            self.generators[i].rate.next = self.rate[i].q.val();
            self.generators[i].move_rate.next = self.engines[i].rate.val();
            self.generators[i].moves.next =
                self.ctrl[i].q.val().get_bit(2) | self.engines[i].braking.val();
            self.generators[i].step_len.next = self.step_timing[i].q.val().get_bits::<16>(0);
            self.generators[i].step_space.next = self.step_timing[i].q.val().get_bits::<16>(16);
            self.generators[i].dir_setup.next = self.dir_timing[i].q.val().get_bits::<16>(0);
            self.generators[i].dir_hold.next = self.dir_timing[i].q.val().get_bits::<16>(16);
            self.selectors[i].clock.next = self.clock.val();
            self.selectors[i].reset.next = self.reset.val();
            self.selectors[i].k.next = self.ctrl[i].q.val().get_bit(0);
            self.selectors[i].s1.next = self.generators[i].step.val();
            self.selectors[i].s2.next = self.generators[i].dir.val();
            // (replace_bit exports with 32-bit shifts: Verilator WIDTH.)
            if self.out_f1[i].q.val() {
                self.f1_bits.next = self.f1_bits.val() | self.axis_bit[i].val();
            }
            if self.out_f2[i].q.val() {
                self.f2_bits.next = self.f2_bits.val() | self.axis_bit[i].val();
            }
            if self.snapshot.val() {
                self.snap[i].d.next = self.generators[i].position.val() & self.width_mask.val();
            }
            if self.home_capture.val().get_bit(i) {
                self.home_position[i].d.next =
                    self.generators[i].position.val() & self.width_mask.val();
            }
            if self.we.val() {
                if self.addr.val() == self.addr_ctrl[i].val() {
                    self.ctrl[i].d.next = self.wdata.val().get_bits::<3>(0);
                }
                if self.addr.val() == self.addr_rate[i].val() {
                    self.rate[i].d.next = self.wdata.val();
                }
                if self.addr.val() == self.addr_step_timing[i].val() {
                    self.step_timing[i].d.next = self.wdata.val();
                }
                if self.addr.val() == self.addr_dir_timing[i].val() {
                    self.dir_timing[i].d.next = self.wdata.val();
                }
                if self.addr.val() == self.addr_soft_min[i].val() {
                    self.soft_min[i].d.next = self.wdata.val() & self.width_mask.val();
                }
                if self.addr.val() == self.addr_soft_max[i].val() {
                    self.soft_max[i].d.next = self.wdata.val() & self.width_mask.val();
                }
                if self.addr.val() == self.addr_low_water[i].val() {
                    self.low_water[i].d.next = self.wdata.val() & self.low_water_mask.val();
                }
                if self.addr.val() == self.addr_decel[i].val() {
                    self.decel[i].d.next = self.wdata.val() & self.decel_mask.val();
                }
            }
            if self.read_addr.q.val() == self.addr_ctrl[i].val() {
                // (bit_cast cannot take a loop index in #[hdl_gen].)
                if self.ctrl[i].q.val().get_bit(0) {
                    self.read_value.next = self.one.val();
                }
                if self.ctrl[i].q.val().get_bit(1) {
                    self.read_value.next = self.read_value.val() | self.two.val();
                }
                if self.ctrl[i].q.val().get_bit(2) {
                    self.read_value.next = self.read_value.val() | self.four.val();
                }
            }
            if self.read_addr.q.val() == self.addr_rate[i].val() {
                self.read_value.next = self.rate[i].q.val();
            }
            if self.read_addr.q.val() == self.addr_step_timing[i].val() {
                self.read_value.next = self.step_timing[i].q.val();
            }
            if self.read_addr.q.val() == self.addr_dir_timing[i].val() {
                self.read_value.next = self.dir_timing[i].q.val();
            }
            if self.read_addr.q.val() == self.addr_low_water[i].val() {
                self.read_value.next = self.low_water[i].q.val();
            }
            if self.read_addr.q.val() == self.addr_decel[i].val() {
                self.read_value.next = self.decel[i].q.val();
            }
            if self.read_addr.q.val() == self.addr_position[i].val() {
                self.read_value.next = self.snap[i].q.val();
                if (self.snap[i].q.val() & self.sign_bit.val()).any() {
                    self.read_value.next = self.snap[i].q.val() | self.sign_extension.val();
                }
            }
            if self.read_addr.q.val() == self.addr_home_position[i].val() {
                self.read_value.next = self.home_position[i].q.val();
                if (self.home_position[i].q.val() & self.sign_bit.val()).any() {
                    self.read_value.next =
                        self.home_position[i].q.val() | self.sign_extension.val();
                }
            }
            if self.read_addr.q.val() == self.addr_soft_min[i].val() {
                self.read_value.next = self.soft_min[i].q.val();
                if (self.soft_min[i].q.val() & self.sign_bit.val()).any() {
                    self.read_value.next = self.soft_min[i].q.val() | self.sign_extension.val();
                }
            }
            if self.read_addr.q.val() == self.addr_soft_max[i].val() {
                self.read_value.next = self.soft_max[i].q.val();
                if (self.soft_max[i].q.val() & self.sign_bit.val()).any() {
                    self.read_value.next = self.soft_max[i].q.val() | self.sign_extension.val();
                }
            }
            if self.read_addr.q.val() == self.addr_status[i].val() {
                self.read_value.next =
                    self.generators[i].status.val() | self.engines[i].status.val();
            }
            if self.reset.val() {
                self.ctrl[i].d.next = 0.into();
                self.quadrature_a[i].d.next = false;
                self.quadrature_b[i].d.next = false;
                self.out_f1[i].d.next = false;
                self.out_f2[i].d.next = false;
                self.rate[i].d.next = 0.into();
                self.step_timing[i].d.next = 0.into();
                self.dir_timing[i].d.next = 0.into();
                self.low_water[i].d.next = 0.into();
                self.snap[i].d.next = 0.into();
                self.home_position[i].d.next = 0.into();
                self.soft_min[i].d.next = 0.into();
                self.soft_max[i].d.next = 0.into();
                self.decel[i].d.next = 0.into();
                self.above_max[i].d.next = false;
                self.below_min[i].d.next = false;
            }
        }
        self.run.d.next = self.run_next.val() & !self.stopped_bits.val();
        if self.read_pending.q.val() {
            self.read_data.d.next = self.read_value.val();
        }
        if self.reset.val() {
            self.run.d.next = 0.into();
            self.stop_up_q.d.next = 0.into();
            self.stop_down_q.d.next = 0.into();
            self.read_pending.d.next = false;
            self.read_addr.d.next = 0.into();
            self.read_data.d.next = 0.into();
        }
        self.rdata.next = self.read_data.q.val();
        self.f1.next = self.f1_bits.val();
        self.f2.next = self.f2_bits.val();
        self.done.next = self.done_bits.val();
        self.low.next = self.low_bits.val();
        self.at_soft_max.next = self.above_bits.val();
        self.at_soft_min.next = self.below_bits.val();
    }
}
