//! The servo DAC block: four staged DAC codes written to a DAC7744-style
//! parallel interface or as 24-bit SPI frames (SERIAL.MODE), latched
//! together by one LOADDACS rise, started by the servo tick, an UPDATE
//! write or the safe input's rise (docs/servo_dac.md).

use motionhdl_spec::regmap;
use motionhdl_spec::servo_dac::{DAC_CHANNELS, FRAME_BITS, SAFE_CODE};
use rust_hdl::prelude::*;

/// Word address bits the block decodes (`regmap::servo_dac`).
pub const SERVO_ADDRESS_BITS: usize = 4;
const A: usize = SERVO_ADDRESS_BITS;
const CH: usize = DAC_CHANNELS as usize;

/// Bus contract as the counter bank's: a write acts at the edge where `we`
/// is high; the edge where `re` is high takes the address, the next edge
/// loads `rdata`, which then holds. Every pin is a flip-flop, CS and
/// LOADDACS stored inverted so they are high (inactive) from
/// configuration on.
#[derive(LogicBlock)]
pub struct ServoDac {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high. Reset starts a transfer of the
    /// staged codes (SAFE_CODE after reset).
    pub reset: Signal<In, Bit>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<A>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Write strobe.
    pub we: Signal<In, Bit>,
    /// Read strobe.
    pub re: Signal<In, Bit>,
    /// Read data, valid from the second clock edge after `re`.
    pub rdata: Signal<Out, Bits<32>>,
    /// Safe state (the safety block's HALT: e-stop, watchdog bite): every
    /// transfer sends SAFE_CODE, and its rise starts one.
    pub safe: Signal<In, Bit>,
    /// The servo tick, one clock every TICK_PERIOD clocks: the counter
    /// bank's snapshot strobe; the transfer starts at the same edge.
    pub tick: Signal<Out, Bit>,
    /// DAC data D15..D0.
    pub dac_data: Signal<Out, Bits<16>>,
    /// DAC channel address A1:A0.
    pub dac_addr: Signal<Out, Bits<2>>,
    /// DAC chip select, active low.
    pub dac_cs_n: Signal<Out, Bit>,
    /// DAC R/W: always low (write).
    pub dac_rw_n: Signal<Out, Bit>,
    /// DAC LOADDACS (LDAC): its rise moves all four input registers to
    /// the outputs.
    pub dac_ldac_n: Signal<Out, Bit>,
    /// Serial DAC clock: idles high, SDIN is sampled at its falls.
    pub dac_sclk: Signal<Out, Bit>,
    /// Serial DAC data, MSB first, changing at SCLK's rises.
    pub dac_sdin: Signal<Out, Bit>,
    /// Serial DAC frame sync, active low for each 24-bit frame.
    pub dac_sync_n: Signal<Out, Bit>,
    period: DFF<Bits<32>>,
    count: DFF<Bits<32>>,
    tick_q: DFF<Bit>,
    events: DFF<Bits<2>>,
    /// TIMING: CS_LOW 7:0, LDAC_LOW 15:8.
    timing: DFF<Bits<16>>,
    serial_mode: DFF<Bit>,
    sclk_half: DFF<Bits<8>>,
    sync_high: DFF<Bits<8>>,
    prefix: DFF<Bits<32>>,
    code: Vec<DFF<Bits<16>>>,
    output: Vec<DFF<Bits<16>>>,
    shadow: Vec<DFF<Bits<16>>>,
    busy: DFF<Bit>,
    pending: DFF<Bit>,
    run_cs_low: DFF<Bits<8>>,
    run_ldac_low: DFF<Bits<8>>,
    run_serial: DFF<Bit>,
    run_sclk_half: DFF<Bits<8>>,
    run_sync_high: DFF<Bits<8>>,
    run_prefix: DFF<Bits<32>>,
    /// The frame being shifted out, MSB on SDIN, and its SCLK half.
    shift: DFF<Bits<24>>,
    half: DFF<Bits<6>>,
    channel: DFF<Bits<2>>,
    /// 0 setup, 1 CS low (a frame), 2 hold, 3 LOADDACS low.
    phase: DFF<Bits<2>>,
    wait: DFF<Bits<10>>,
    safe_q: DFF<Bit>,
    data_pin: DFF<Bits<16>>,
    addr_pin: DFF<Bits<2>>,
    cs_active: DFF<Bit>,
    ldac_active: DFF<Bit>,
    sclk_low: DFF<Bit>,
    sync_active: DFF<Bit>,
    read_pending: DFF<Bit>,
    read_addr: DFF<Bits<A>>,
    read_data: DFF<Bits<32>>,
    addr_info: Constant<Bits<A>>,
    addr_status: Constant<Bits<A>>,
    addr_events: Constant<Bits<A>>,
    addr_period: Constant<Bits<A>>,
    addr_update: Constant<Bits<A>>,
    addr_timing: Constant<Bits<A>>,
    addr_serial: Constant<Bits<A>>,
    addr_prefix: Constant<Bits<A>>,
    addr_code: Vec<Constant<Bits<A>>>,
    addr_output: Vec<Constant<Bits<A>>>,
    info: Constant<Bits<32>>,
    safe_code: Constant<Bits<16>>,
    reset_timing: Constant<Bits<16>>,
    reset_serial: Constant<Bits<32>>,
    reset_prefix: Constant<Bits<32>>,
    last_half: Constant<Bits<6>>,
    by1: Constant<Bits<5>>,
    one: Constant<Bits<10>>,
    by8: Constant<Bits<5>>,
    by16: Constant<Bits<5>>,
    mode_bit: Constant<Bits<32>>,
    channel_index: Vec<Constant<Bits<2>>>,
    last_channel: Constant<Bits<2>>,
    phase_setup: Constant<Bits<2>>,
    phase_write: Constant<Bits<2>>,
    phase_hold: Constant<Bits<2>>,
    phase_load: Constant<Bits<2>>,
    status_busy: Constant<Bits<32>>,
    status_pending: Constant<Bits<32>>,
    status_safe: Constant<Bits<32>>,
    ending: Signal<Local, Bit>,
    asked: Signal<Local, Bit>,
    free: Signal<Local, Bit>,
    start: Signal<Local, Bit>,
    events_set: Signal<Local, Bits<2>>,
    events_cleared: Signal<Local, Bits<2>>,
    read_value: Signal<Local, Bits<32>>,
    read_half: Signal<Local, Bits<16>>,
    read_half_hit: Signal<Local, Bit>,
    frame_prefix: Signal<Local, Bits<8>>,
}

impl Default for ServoDac {
    fn default() -> Self {
        Self::new(50_000_000)
    }
}

/// A constant of `W` bits.
fn k<const W: usize>(v: u32) -> Constant<Bits<W>> {
    Constant::new((v as u64).into())
}

impl ServoDac {
    /// The block for a clock of `clock_hz` (TIMING's reset value).
    pub fn new(clock_hz: u64) -> Self {
        let map = regmap::servo_dac(clock_hz);
        assert_eq!(map.address_bits as usize, A);
        let addr = |name: &str| k(map.register(name).offset);
        let ch = map.array("CH");
        let timing = map.register("TIMING");
        assert_eq!(timing.field("CS_LOW").lsb, 0);
        assert_eq!(timing.field("LDAC_LOW").lsb, 8);
        let events = map.register("EVENTS");
        assert_eq!(events.field("TICK").lsb, 0);
        assert_eq!(events.field("OVERRUN").lsb, 1);
        let status = map.register("STATUS");
        let serial = map.register("SERIAL");
        assert_eq!(serial.field("MODE").lsb, 0);
        assert_eq!(serial.field("SCLK_HALF").lsb, 8);
        assert_eq!(serial.field("SYNC_HIGH").lsb, 16);
        let prefix = map.register("PREFIX");
        for c in 0..DAC_CHANNELS {
            assert_eq!(
                prefix.field(["CH0", "CH1", "CH2", "CH3"][c as usize]).lsb,
                8 * c
            );
        }
        assert_eq!(FRAME_BITS, 24);
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            re: Default::default(),
            rdata: Default::default(),
            safe: Default::default(),
            tick: Default::default(),
            dac_data: Default::default(),
            dac_addr: Default::default(),
            dac_cs_n: Default::default(),
            dac_rw_n: Default::default(),
            dac_ldac_n: Default::default(),
            dac_sclk: Default::default(),
            dac_sdin: Default::default(),
            dac_sync_n: Default::default(),
            period: Default::default(),
            count: Default::default(),
            tick_q: Default::default(),
            events: Default::default(),
            timing: Default::default(),
            serial_mode: Default::default(),
            sclk_half: Default::default(),
            sync_high: Default::default(),
            prefix: Default::default(),
            code: (0..CH).map(|_| Default::default()).collect(),
            output: (0..CH).map(|_| Default::default()).collect(),
            shadow: (0..CH).map(|_| Default::default()).collect(),
            busy: Default::default(),
            pending: Default::default(),
            run_cs_low: Default::default(),
            run_ldac_low: Default::default(),
            run_serial: Default::default(),
            run_sclk_half: Default::default(),
            run_sync_high: Default::default(),
            run_prefix: Default::default(),
            shift: Default::default(),
            half: Default::default(),
            channel: Default::default(),
            phase: Default::default(),
            wait: Default::default(),
            safe_q: Default::default(),
            data_pin: Default::default(),
            addr_pin: Default::default(),
            cs_active: Default::default(),
            ldac_active: Default::default(),
            sclk_low: Default::default(),
            sync_active: Default::default(),
            read_pending: Default::default(),
            read_addr: Default::default(),
            read_data: Default::default(),
            addr_info: addr("INFO"),
            addr_status: addr("STATUS"),
            addr_events: addr("EVENTS"),
            addr_period: addr("TICK_PERIOD"),
            addr_update: addr("UPDATE"),
            addr_timing: addr("TIMING"),
            addr_serial: addr("SERIAL"),
            addr_prefix: addr("PREFIX"),
            addr_code: (0..CH as u32).map(|i| k(ch.address(i, "CODE"))).collect(),
            addr_output: (0..CH as u32).map(|i| k(ch.address(i, "OUTPUT"))).collect(),
            info: k(map.register("INFO").reset),
            safe_code: k(SAFE_CODE),
            reset_timing: k(timing.reset),
            reset_serial: k(serial.reset),
            reset_prefix: k(prefix.reset),
            last_half: k(2 * FRAME_BITS - 1),
            by1: k(1),
            one: k(1),
            by8: k(8),
            by16: k(16),
            mode_bit: k(serial.field("MODE").mask()),
            channel_index: (0..CH as u32 - 1).map(k).collect(),
            last_channel: k(DAC_CHANNELS - 1),
            phase_setup: k(0),
            phase_write: k(1),
            phase_hold: k(2),
            phase_load: k(3),
            status_busy: k(status.field("BUSY").mask()),
            status_pending: k(status.field("PENDING").mask()),
            status_safe: k(status.field("SAFE").mask()),
            ending: Default::default(),
            asked: Default::default(),
            free: Default::default(),
            start: Default::default(),
            events_set: Default::default(),
            events_cleared: Default::default(),
            read_value: Default::default(),
            read_half: Default::default(),
            read_half_hit: Default::default(),
            frame_prefix: Default::default(),
        }
    }
}

impl Logic for ServoDac {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            period,
            count,
            tick_q,
            events,
            timing,
            busy,
            pending,
            run_cs_low,
            run_ldac_low,
            serial_mode,
            sclk_half,
            sync_high,
            prefix,
            run_serial,
            run_sclk_half,
            run_sync_high,
            run_prefix,
            shift,
            half,
            channel,
            phase,
            wait,
            safe_q,
            data_pin,
            addr_pin,
            cs_active,
            ldac_active,
            sclk_low,
            sync_active,
            read_pending,
            read_addr,
            read_data
        );
        for i in 0..CH {
            self.code[i].clock.next = self.clock.val();
            self.code[i].d.next = self.code[i].q.val();
            self.output[i].clock.next = self.clock.val();
            self.output[i].d.next = self.output[i].q.val();
            self.shadow[i].clock.next = self.clock.val();
            self.shadow[i].d.next = self.shadow[i].q.val();
        }
        // Reads: the address at the `re` edge, the value at the next.
        self.read_pending.d.next = self.re.val();
        if self.re.val() {
            self.read_addr.d.next = self.addr.val();
        }
        self.read_value.next = 0.into();
        if self.read_addr.q.val() == self.addr_info.val() {
            self.read_value.next = self.info.val();
        }
        if self.read_addr.q.val() == self.addr_status.val() {
            if self.busy.q.val() {
                self.read_value.next = self.read_value.val() | self.status_busy.val();
            }
            if self.pending.q.val() {
                self.read_value.next = self.read_value.val() | self.status_pending.val();
            }
            if self.safe_q.q.val() {
                self.read_value.next = self.read_value.val() | self.status_safe.val();
            }
        }
        if self.read_addr.q.val() == self.addr_events.val() {
            self.read_value.next = bit_cast::<32, 2>(self.events.q.val());
        }
        if self.read_addr.q.val() == self.addr_period.val() {
            self.read_value.next = self.period.q.val();
        }
        if self.read_addr.q.val() == self.addr_timing.val() {
            self.read_value.next = bit_cast::<32, 16>(self.timing.q.val());
        }
        if self.read_addr.q.val() == self.addr_serial.val() {
            self.read_value.next = (bit_cast::<32, 8>(self.sclk_half.q.val()) << self.by8.val())
                | (bit_cast::<32, 8>(self.sync_high.q.val()) << self.by16.val());
            if self.serial_mode.q.val() {
                self.read_value.next = self.read_value.val() | self.mode_bit.val();
            }
        }
        if self.read_addr.q.val() == self.addr_prefix.val() {
            self.read_value.next = self.prefix.q.val();
        }
        // The channels' 16-bit registers through one mux leg.
        self.read_half.next = 0.into();
        self.read_half_hit.next = false;
        for i in 0..CH {
            if self.read_addr.q.val() == self.addr_code[i].val() {
                self.read_half.next = self.code[i].q.val();
                self.read_half_hit.next = true;
            }
            if self.read_addr.q.val() == self.addr_output[i].val() {
                self.read_half.next = self.output[i].q.val();
                self.read_half_hit.next = true;
            }
        }
        if self.read_half_hit.val() {
            self.read_value.next = bit_cast::<32, 16>(self.read_half.val());
        }
        if self.read_pending.q.val() {
            self.read_data.d.next = self.read_value.val();
        }
        // The running channel's frame prefix.
        self.frame_prefix.next = self.run_prefix.q.val().get_bits::<8>(0);
        if self.channel.q.val() == self.channel_index[1].val() {
            self.frame_prefix.next = self.run_prefix.q.val().get_bits::<8>(8);
        }
        if self.channel.q.val() == self.channel_index[2].val() {
            self.frame_prefix.next = self.run_prefix.q.val().get_bits::<8>(16);
        }
        if self.channel.q.val() == self.last_channel.val() {
            self.frame_prefix.next = self.run_prefix.q.val().get_bits::<8>(24);
        }
        // The transfer: a request starts one at an edge where none runs or
        // the running one ends; else it waits, one deep.
        self.ending.next = self.busy.q.val()
            & (self.phase.q.val() == self.phase_load.val())
            & !self.wait.q.val().any();
        self.asked.next = self.tick_q.q.val()
            | (self.we.val() & (self.addr.val() == self.addr_update.val()))
            | (self.safe.val() & !self.safe_q.q.val());
        self.free.next = !self.busy.q.val() | self.ending.val();
        self.start.next = self.free.val() & (self.asked.val() | self.pending.q.val());
        self.events_set.next = 0.into();
        if self.tick_q.q.val() {
            self.events_set.next = 1.into();
            if !self.free.val() {
                self.events_set.next = 3.into();
            }
        }
        if self.ending.val() {
            for i in 0..CH {
                self.output[i].d.next = self.shadow[i].q.val();
            }
        }
        if self.start.val() {
            self.busy.d.next = true;
            self.pending.d.next = false;
            for i in 0..CH {
                self.shadow[i].d.next = self.code[i].q.val();
                if self.safe.val() {
                    self.shadow[i].d.next = self.safe_code.val();
                }
            }
            self.run_cs_low.d.next = self.timing.q.val().get_bits::<8>(0);
            self.run_ldac_low.d.next = self.timing.q.val().get_bits::<8>(8);
            self.run_serial.d.next = self.serial_mode.q.val();
            self.run_sclk_half.d.next = self.sclk_half.q.val();
            self.run_sync_high.d.next = self.sync_high.q.val();
            self.run_prefix.d.next = self.prefix.q.val();
            self.channel.d.next = 0.into();
            self.phase.d.next = 0.into();
            self.wait.d.next = 0.into();
            if self.serial_mode.q.val() {
                self.wait.d.next = bit_cast::<10, 8>(self.sync_high.q.val());
            }
            self.addr_pin.d.next = 0.into();
            self.data_pin.d.next = self.code[0].q.val();
            if self.safe.val() {
                self.data_pin.d.next = self.safe_code.val();
            }
        } else {
            self.pending.d.next = self.pending.q.val() | self.asked.val();
            if self.busy.q.val() & (self.phase.q.val() == self.phase_setup.val()) {
                self.wait.d.next = self.wait.q.val() - 1;
                if !self.wait.q.val().any() {
                    self.phase.d.next = self.phase_write.val();
                    self.wait.d.next = bit_cast::<10, 8>(self.run_cs_low.q.val());
                    if self.run_serial.q.val() {
                        // The frame: the channel's prefix, then its code
                        // (on the data pins since the setup began).
                        self.wait.d.next = bit_cast::<10, 8>(self.run_sclk_half.q.val());
                        self.half.d.next = 0.into();
                        self.shift.d.next = (bit_cast::<24, 8>(self.frame_prefix.val())
                            << self.by16.val())
                            | bit_cast::<24, 16>(self.data_pin.q.val());
                    }
                }
            }
            if self.busy.q.val() & (self.phase.q.val() == self.phase_write.val()) {
                self.wait.d.next = self.wait.q.val() - 1;
                if !self.wait.q.val().any() {
                    self.wait.d.next = 0.into();
                    self.phase.d.next = self.phase_hold.val();
                    if self.run_serial.q.val() & (self.half.q.val() != self.last_half.val()) {
                        // The next SCLK half; a rise moves SDIN on a bit.
                        self.phase.d.next = self.phase_write.val();
                        self.half.d.next = self.half.q.val() + 1;
                        self.wait.d.next = bit_cast::<10, 8>(self.run_sclk_half.q.val());
                        if self.half.q.val().get_bit(0) {
                            self.shift.d.next = self.shift.q.val() << self.by1.val();
                        }
                    }
                }
            }
            if self.busy.q.val() & (self.phase.q.val() == self.phase_hold.val()) {
                if self.channel.q.val() == self.last_channel.val() {
                    self.phase.d.next = self.phase_load.val();
                    self.wait.d.next = bit_cast::<10, 8>(self.run_ldac_low.q.val());
                    if self.run_serial.q.val() {
                        // SYNC high SYNC_HIGH + 1 clocks before LDAC falls.
                        self.wait.d.next = bit_cast::<10, 8>(self.run_ldac_low.q.val())
                            + bit_cast::<10, 8>(self.run_sync_high.q.val())
                            + self.one.val();
                    }
                } else {
                    self.channel.d.next = self.channel.q.val() + 1;
                    self.addr_pin.d.next = self.channel.q.val() + 1;
                    self.phase.d.next = self.phase_setup.val();
                    if self.run_serial.q.val() {
                        self.wait.d.next = bit_cast::<10, 8>(self.run_sync_high.q.val());
                    }
                    for i in 1..CH {
                        if self.channel.q.val() == self.channel_index[i - 1].val() {
                            self.data_pin.d.next = self.shadow[i].q.val();
                        }
                    }
                }
            }
            if self.busy.q.val() & (self.phase.q.val() == self.phase_load.val()) {
                self.wait.d.next = self.wait.q.val() - 1;
                if !self.wait.q.val().any() {
                    self.wait.d.next = 0.into();
                    self.busy.d.next = false;
                }
            }
        }
        // The pins' next levels, from the next state.
        self.cs_active.d.next = self.busy.q.val()
            & !self.start.val()
            & !self.run_serial.q.val()
            & ((self.phase.q.val() == self.phase_setup.val())
                | ((self.phase.q.val() == self.phase_write.val()) & self.wait.q.val().any()));
        if self.run_serial.q.val() {
            // LDAC low for the load phase's last LDAC_LOW + 1 clocks.
            self.ldac_active.d.next = self.busy.q.val()
                & !self.start.val()
                & (self.phase.q.val() == self.phase_load.val())
                & self.wait.q.val().any()
                & (self.wait.q.val()
                    <= bit_cast::<10, 8>(self.run_ldac_low.q.val()) + self.one.val());
        } else {
            self.ldac_active.d.next = self.busy.q.val()
                & !self.start.val()
                & (((self.phase.q.val() == self.phase_hold.val())
                    & (self.channel.q.val() == self.last_channel.val()))
                    | ((self.phase.q.val() == self.phase_load.val()) & self.wait.q.val().any()));
        }
        self.sync_active.d.next = self.busy.q.val()
            & !self.start.val()
            & self.run_serial.q.val()
            & (((self.phase.q.val() == self.phase_setup.val()) & !self.wait.q.val().any())
                | (self.phase.q.val() == self.phase_write.val()));
        self.sclk_low.d.next = self.busy.q.val()
            & !self.start.val()
            & self.run_serial.q.val()
            & (self.phase.q.val() == self.phase_write.val())
            & (self.half.q.val().get_bit(0) ^ !self.wait.q.val().any());
        // The servo tick: every PERIOD clocks; a write restarts it.
        self.tick_q.d.next = self.period.q.val().any() & !self.count.q.val().any();
        self.count.d.next = self.count.q.val() - 1;
        if !self.count.q.val().any() {
            self.count.d.next = self.period.q.val() - 1;
        }
        if !self.period.q.val().any() {
            self.count.d.next = 0.into();
        }
        if self.we.val() & (self.addr.val() == self.addr_period.val()) {
            self.period.d.next = self.wdata.val();
            self.count.d.next = self.wdata.val() - 1;
            if !self.wdata.val().any() {
                self.count.d.next = 0.into();
            }
            self.tick_q.d.next = false;
        }
        // Registers; a new event wins over a clear in the same clock.
        self.events_cleared.next = 0.into();
        if self.we.val() & (self.addr.val() == self.addr_events.val()) {
            self.events_cleared.next = self.wdata.val().get_bits::<2>(0);
        }
        self.events.d.next =
            (self.events.q.val() & !self.events_cleared.val()) | self.events_set.val();
        if self.we.val() & (self.addr.val() == self.addr_timing.val()) {
            self.timing.d.next = self.wdata.val().get_bits::<16>(0);
        }
        if self.we.val() & (self.addr.val() == self.addr_serial.val()) {
            self.serial_mode.d.next = self.wdata.val().get_bit(0);
            self.sclk_half.d.next = self.wdata.val().get_bits::<8>(8);
            self.sync_high.d.next = self.wdata.val().get_bits::<8>(16);
        }
        if self.we.val() & (self.addr.val() == self.addr_prefix.val()) {
            self.prefix.d.next = self.wdata.val();
        }
        for i in 0..CH {
            if self.we.val() & (self.addr.val() == self.addr_code[i].val()) {
                self.code[i].d.next = self.wdata.val().get_bits::<16>(0);
            }
        }
        self.safe_q.d.next = self.safe.val();
        if self.reset.val() {
            self.period.d.next = 0.into();
            self.count.d.next = 0.into();
            self.tick_q.d.next = false;
            self.events.d.next = 0.into();
            self.timing.d.next = self.reset_timing.val();
            for i in 0..CH {
                self.code[i].d.next = self.safe_code.val();
                self.output[i].d.next = self.safe_code.val();
                self.shadow[i].d.next = self.safe_code.val();
            }
            self.busy.d.next = false;
            self.pending.d.next = true;
            self.run_cs_low.d.next = self.reset_timing.val().get_bits::<8>(0);
            self.run_ldac_low.d.next = self.reset_timing.val().get_bits::<8>(8);
            self.serial_mode.d.next = false;
            self.sclk_half.d.next = self.reset_serial.val().get_bits::<8>(8);
            self.sync_high.d.next = self.reset_serial.val().get_bits::<8>(16);
            self.prefix.d.next = self.reset_prefix.val();
            self.run_serial.d.next = false;
            self.run_sclk_half.d.next = self.reset_serial.val().get_bits::<8>(8);
            self.run_sync_high.d.next = self.reset_serial.val().get_bits::<8>(16);
            self.run_prefix.d.next = self.reset_prefix.val();
            self.shift.d.next = 0.into();
            self.half.d.next = 0.into();
            self.channel.d.next = 0.into();
            self.phase.d.next = 0.into();
            self.wait.d.next = 0.into();
            self.safe_q.d.next = false;
            self.data_pin.d.next = self.safe_code.val();
            self.addr_pin.d.next = 0.into();
            self.cs_active.d.next = false;
            self.ldac_active.d.next = false;
            self.sclk_low.d.next = false;
            self.sync_active.d.next = false;
            self.read_pending.d.next = false;
            self.read_addr.d.next = 0.into();
            self.read_data.d.next = 0.into();
        }
        self.rdata.next = self.read_data.q.val();
        self.tick.next = self.tick_q.q.val();
        self.dac_data.next = self.data_pin.q.val();
        self.dac_addr.next = self.addr_pin.q.val();
        self.dac_cs_n.next = !self.cs_active.q.val();
        self.dac_rw_n.next = false;
        self.dac_ldac_n.next = !self.ldac_active.q.val();
        self.dac_sclk.next = !self.sclk_low.q.val();
        self.dac_sdin.next = self.shift.q.val().get_bit(23);
        self.dac_sync_n.next = !self.sync_active.q.val();
    }
}
