//! Cycle-accurate, bit-accurate model of the top level `motion_controller`
//! with the shared RAM inside the FPGA (docs/motion_controller.md): the
//! FSMC bridge and its register decode, the identity block, the counter
//! bank, the pulse bank and the ISA bridge, wired as
//! `hdl/src/motion_controller.rs` and `hdl/src/mcu_side.rs` wire them.
//!
//! Built from the block models ([`FsmcBridgeModel`], [`Bank`],
//! [`PulseBank`], [`IsaBridgeModel`]); only the identity block's read port
//! and the MCU side's decode and read mux are modelled here. One call of
//! [`MotionControllerModel::step`] is one clock: the outputs before the
//! rising edge (with this clock's inputs), then the edge.

use crate::counter::{Bank, BusCycle, CounterParams};
use crate::fsmc_bridge::{FsmcBridgeModel, FsmcOutputs, FsmcPins};
use crate::isa_bridge::{IsaBridgeModel, IsaPins};
use crate::machine_inputs::MachinePins;
use crate::pulse_generator::PulseBank;
use crate::regmap::{self, ERR_COUNT_BITS};
use crate::safety_io::SafetyIo;
use crate::servo_dac::ServoDac;
use crate::{Config, IsaRam};

/// Every input pin of the top at one rising edge (the clock aside).
/// Multi-bit pins are right-aligned; bits beyond a pin's width are ignored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TopInputs {
    /// Synchronous reset, active high.
    pub reset: bool,
    pub fsmc_ne_n: bool,
    pub fsmc_noe_n: bool,
    pub fsmc_nwe_n: bool,
    /// FSMC A[11:0].
    pub fsmc_a: u16,
    pub fsmc_d_in: u16,
    /// ISA SA9..SA0.
    pub isa_sa: u16,
    pub isa_sd_in: u16,
    pub isa_ior_n: bool,
    pub isa_iow_n: bool,
    pub isa_aen: bool,
    pub isa_bale: bool,
    pub isa_base: u8,
    /// Encoder A, B and index pins, bit i = axis i.
    pub enc_a: u16,
    pub enc_b: u16,
    pub enc_z: u16,
    /// The e-stop chain: high = released.
    pub estop_ok: bool,
    /// LIMIT_POS, LIMIT_NEG, HOME and ALARM pins, bit i = axis i.
    pub machine: MachinePins,
}

impl TopInputs {
    /// Both buses idle (strobes high, no chip select, no BALE), encoders
    /// low, the e-stop chain closed (released).
    pub fn idle() -> Self {
        Self {
            reset: false,
            fsmc_ne_n: true,
            fsmc_noe_n: true,
            fsmc_nwe_n: true,
            fsmc_a: 0,
            fsmc_d_in: 0,
            isa_sa: 0,
            isa_sd_in: 0,
            isa_ior_n: true,
            isa_iow_n: true,
            isa_aen: false,
            isa_bale: false,
            isa_base: 0,
            enc_a: 0,
            enc_b: 0,
            enc_z: 0,
            estop_ok: true,
            machine: MachinePins::default(),
        }
    }

    fn fsmc(&self) -> FsmcPins {
        FsmcPins {
            ne_n: self.fsmc_ne_n,
            noe_n: self.fsmc_noe_n,
            nwe_n: self.fsmc_nwe_n,
            a: self.fsmc_a & 0xfff,
            d_in: self.fsmc_d_in,
        }
    }
}

impl Default for TopInputs {
    fn default() -> Self {
        Self::idle()
    }
}

/// Every output pin of the top.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TopOutputs {
    pub fsmc_d_out: u16,
    pub fsmc_d_oe: bool,
    pub isa_sd_out: u16,
    pub isa_sd_oe: bool,
    pub isa_iocs16_n: bool,
    /// The ISA IRQ line.
    pub isa_irq: bool,
    /// F1 and F2, bit i = axis i.
    pub pulse_f1: u16,
    pub pulse_f2: u16,
    /// Drive ENABLE, bit i = axis i.
    pub drive_enable: u16,
    /// The IRQ pin.
    pub irq: bool,
    /// General-purpose outputs: levels, and which pins drive.
    pub gpo_out: u16,
    pub gpo_oe: u16,
    /// The servo card's DAC pins (all 0 in a top without SERVO).
    pub dac_data: u16,
    pub dac_addr: u8,
    pub dac_cs_n: bool,
    pub dac_rw_n: bool,
    pub dac_ldac_n: bool,
    /// The serial DAC option's pins (SERVO.SERIAL.MODE = 1).
    pub dac_sclk: bool,
    pub dac_sdin: bool,
    pub dac_sync_n: bool,
}

impl TopOutputs {
    /// (pin name, value) of every output, for messages and comparisons.
    pub fn pins(&self) -> [(&'static str, u32); 20] {
        [
            ("fsmc_d_out", u32::from(self.fsmc_d_out)),
            ("fsmc_d_oe", u32::from(self.fsmc_d_oe)),
            ("isa_sd_out", u32::from(self.isa_sd_out)),
            ("isa_sd_oe", u32::from(self.isa_sd_oe)),
            ("isa_iocs16_n", u32::from(self.isa_iocs16_n)),
            ("isa_irq", u32::from(self.isa_irq)),
            ("pulse_f1", u32::from(self.pulse_f1)),
            ("pulse_f2", u32::from(self.pulse_f2)),
            ("drive_enable", u32::from(self.drive_enable)),
            ("irq", u32::from(self.irq)),
            ("dac_data", u32::from(self.dac_data)),
            ("dac_addr", u32::from(self.dac_addr)),
            ("dac_cs_n", u32::from(self.dac_cs_n)),
            ("dac_rw_n", u32::from(self.dac_rw_n)),
            ("dac_ldac_n", u32::from(self.dac_ldac_n)),
            ("dac_sclk", u32::from(self.dac_sclk)),
            ("dac_sdin", u32::from(self.dac_sdin)),
            ("dac_sync_n", u32::from(self.dac_sync_n)),
            ("gpo_out", u32::from(self.gpo_out)),
            ("gpo_oe", u32::from(self.gpo_oe)),
        ]
    }
}

/// The identity block's read port: constants behind the two-edge read of
/// the register bus (`hdl/src/id_block.rs`).
#[derive(Clone, Debug, PartialEq, Eq)]
struct IdBlockModel {
    values: [u32; 1 << ID_ADDRESS_BITS],
    read_pending: bool,
    read_addr: u32,
    read_data: u32,
}

const ID_ADDRESS_BITS: u32 = 4;

impl IdBlockModel {
    fn new(id: &regmap::Block) -> Self {
        assert_eq!(id.address_bits, ID_ADDRESS_BITS);
        let mut values = [0; 1 << ID_ADDRESS_BITS];
        for r in &id.registers {
            values[r.offset as usize] = r.reset;
        }
        Self {
            values,
            read_pending: false,
            read_addr: 0,
            read_data: 0,
        }
    }

    fn clock(&mut self, reset: bool, re: bool, addr: u32) {
        if self.read_pending {
            self.read_data = self.values[self.read_addr as usize];
        }
        self.read_pending = re;
        if re {
            self.read_addr = addr & ((1 << ID_ADDRESS_BITS) - 1);
        }
        if reset {
            self.read_pending = false;
            self.read_addr = 0;
            self.read_data = 0;
        }
    }
}

/// What the MCU side's decode makes of the bridge's register port this clock.
struct Decode {
    bridge: FsmcOutputs,
    select_id: bool,
    select_counters: bool,
    select_pulses: bool,
    select_safety: bool,
    select_servo: bool,
    reg_rdata: u32,
}

/// The top `motion_controller` (RAM inside) for a [`Config`]: its axis
/// count and counter width. Power-up state as the block models'; the
/// pulse generators' step timers model the state after reset, so compare
/// from the first reset on (outputs agree before it too).
#[derive(Clone, Debug)]
pub struct MotionControllerModel {
    fsmc: FsmcBridgeModel,
    id: IdBlockModel,
    counters: Bank,
    pulses: PulseBank,
    safety: SafetyIo,
    isa: IsaBridgeModel,
    /// The SERVO block, in the servo card's top.
    servo: Option<ServoDac>,
    // Which block the last register read went to (McuSide's read mux).
    read_from_id: bool,
    read_from_counters: bool,
    read_from_pulses: bool,
    read_from_safety: bool,
    read_from_servo: bool,
    id_page: u32,
    counter_page: u32,
    pulse_page: u32,
    safety_page: u32,
    servo_page: u32,
    snapshot_offset: u32,
    axis_mask: u16,
    // Reused every clock: (a, b, z) per channel for the counter bank.
    enc: Vec<(bool, bool, bool)>,
}

impl MotionControllerModel {
    /// The top for `config`; panics for the external-RAM build (it has
    /// other pins).
    pub fn new(config: &Config) -> Self {
        assert_eq!(
            config.isa_ram(),
            IsaRam::Internal,
            "this model is the top with the RAM inside"
        );
        let axes = config.axes();
        assert!(
            (1..=16).contains(&axes),
            "axes = {axes} out of range 1..=16"
        );
        let map = regmap::mcu_map(config);
        let id = map.block("ID");
        let counter = map.block("COUNTER");
        let pulse = map.block("PULSE");
        let safety = map.block("SAFETY");
        // The decode compares reg_addr[9:4], [9:8], [9] and [9:7] with the
        // pages, as McuSide does; the map must agree.
        assert_eq!(id.address_bits, 4);
        assert_eq!(counter.address_bits, 8);
        assert_eq!(pulse.address_bits, 9);
        assert_eq!(safety.address_bits, 7);
        let servo_page = regmap::MCU_SERVO_WORD_BASE >> 4;
        let servo = config.servo_dac().then(|| {
            let block = map.block("SERVO");
            assert_eq!((block.base, block.address_bits), (servo_page << 4, 4));
            ServoDac::new(config.clock_hz()).at_power_up()
        });
        assert_eq!(
            map.blocks.len(),
            4 + usize::from(servo.is_some()),
            "a block the decode does not know"
        );
        Self {
            fsmc: FsmcBridgeModel::new(),
            id: IdBlockModel::new(id),
            counters: Bank::new(
                axes,
                CounterParams::new(config.counter_width(), ERR_COUNT_BITS)
                    .with_features(config.counter_features()),
            ),
            pulses: PulseBank::new(axes, config.counter_width()),
            safety: SafetyIo::new(axes, config.filter_tick_clocks()),
            isa: IsaBridgeModel::new(),
            servo,
            read_from_servo: false,
            servo_page,
            read_from_id: false,
            read_from_counters: false,
            read_from_pulses: false,
            read_from_safety: false,
            id_page: id.base >> 4,
            counter_page: counter.base >> 8,
            pulse_page: pulse.base >> 9,
            safety_page: safety.base >> 7,
            snapshot_offset: counter.register("SNAPSHOT").offset,
            axis_mask: ((1u32 << axes) - 1) as u16,
            enc: vec![(false, false, false); axes as usize],
        }
    }

    pub fn axes(&self) -> usize {
        self.enc.len()
    }
    pub fn fsmc(&self) -> &FsmcBridgeModel {
        &self.fsmc
    }
    pub fn counters(&self) -> &Bank {
        &self.counters
    }
    pub fn pulses(&self) -> &PulseBank {
        &self.pulses
    }
    pub fn safety(&self) -> &SafetyIo {
        &self.safety
    }
    pub fn isa(&self) -> &IsaBridgeModel {
        &self.isa
    }
    /// The SERVO block, in the servo card's top.
    pub fn servo(&self) -> Option<&ServoDac> {
        self.servo.as_ref()
    }

    fn decode(&self, inp: &TopInputs) -> Decode {
        let bridge = self.fsmc.outputs(&inp.fsmc());
        let a = u32::from(bridge.reg_addr);
        // The mux after the blocks: the last block read wins, in McuSide's
        // order (the pages are disjoint, so at most one flag is set).
        let mut reg_rdata = 0;
        if self.read_from_id {
            reg_rdata = self.id.read_data;
        }
        if self.read_from_counters {
            reg_rdata = self.counters.rdata();
        }
        if self.read_from_pulses {
            reg_rdata = self.pulses.rdata();
        }
        if self.read_from_safety {
            reg_rdata = self.safety.rdata();
        }
        if self.read_from_servo {
            reg_rdata = self.servo.as_ref().map_or(0, ServoDac::rdata);
        }
        Decode {
            bridge,
            select_id: (a >> 4) & 0x3f == self.id_page,
            select_counters: (a >> 8) & 3 == self.counter_page,
            select_pulses: (a >> 9) & 1 == self.pulse_page,
            select_safety: (a >> 7) & 7 == self.safety_page,
            select_servo: (a >> 4) & 0x3f == self.servo_page,
            reg_rdata,
        }
    }

    fn isa_pins(inp: &TopInputs, bridge: &FsmcOutputs) -> IsaPins {
        IsaPins {
            sa: inp.isa_sa & 0x3ff,
            sd_in: inp.isa_sd_in,
            ior_n: inp.isa_ior_n,
            iow_n: inp.isa_iow_n,
            aen: inp.isa_aen,
            bale: inp.isa_bale,
            base: inp.isa_base,
            // The RAM's second port is the MCU's RAM window.
            dsp_addr: bridge.ram_addr,
            dsp_wdata: bridge.ram_wdata,
            dsp_we: bridge.ram_we,
        }
    }

    fn outputs_of(&self, inp: &TopInputs, d: &Decode) -> TopOutputs {
        let isa = self.isa.outputs(&Self::isa_pins(inp, &d.bridge));
        let (mut f1, mut f2) = (0u16, 0u16);
        for i in 0..self.axes() {
            let (a, b) = self.pulses.outputs(i);
            f1 |= u16::from(a) << i;
            f2 |= u16::from(b) << i;
        }
        let dac = self.servo.as_ref().map(ServoDac::pins);
        TopOutputs {
            dac_data: dac.map_or(0, |p| p.data as u16),
            dac_addr: dac.map_or(0, |p| p.addr as u8),
            dac_cs_n: dac.is_some_and(|p| p.cs_n),
            dac_rw_n: dac.is_some_and(|p| p.rw_n),
            dac_ldac_n: dac.is_some_and(|p| p.ldac_n),
            dac_sclk: dac.is_some_and(|p| p.sclk),
            dac_sdin: dac.is_some_and(|p| p.sdin),
            dac_sync_n: dac.is_some_and(|p| p.sync_n),
            fsmc_d_out: d.bridge.d_out,
            fsmc_d_oe: d.bridge.d_oe,
            isa_sd_out: isa.sd_out,
            isa_sd_oe: isa.sd_oe,
            isa_iocs16_n: isa.iocs16_n,
            isa_irq: isa.irq,
            pulse_f1: f1,
            pulse_f2: f2,
            drive_enable: self.safety.drive_enable() as u16,
            irq: self.safety.irq_pin(),
            gpo_out: self.safety.gpo_pins().out as u16,
            gpo_oe: self.safety.gpo_pins().oe as u16,
        }
    }

    /// The output pins now, with `inp` on the input pins (some outputs are
    /// combinational from the pins: `fsmc_d_oe`, `isa_sd_oe`, `isa_sd_out`'s
    /// register select, `isa_iocs16_n`).
    pub fn outputs(&self, inp: &TopInputs) -> TopOutputs {
        self.outputs_of(inp, &self.decode(inp))
    }

    /// One rising clock edge with `inp` on the pins.
    pub fn clock(&mut self, inp: &TopInputs) {
        let d = self.decode(inp);
        self.clock_with(inp, &d);
    }

    /// [`outputs`](Self::outputs) then [`clock`](Self::clock): one clock.
    pub fn step(&mut self, inp: &TopInputs) -> TopOutputs {
        let d = self.decode(inp);
        let out = self.outputs_of(inp, &d);
        self.clock_with(inp, &d);
        out
    }

    fn clock_with(&mut self, inp: &TopInputs, d: &Decode) {
        let reset = inp.reset;
        let b = &d.bridge;
        let isa_pins = Self::isa_pins(inp, b);
        // Everything below reads the state before the edge: the decode was
        // taken from it, and each block model keeps its own old values.
        let isa_out = self.isa.outputs(&isa_pins);
        let ram_rdata = isa_out.dsp_rdata;
        self.fsmc.clock(&inp.fsmc(), reset, d.reg_rdata, ram_rdata);

        let addr = u32::from(b.reg_addr);
        self.id.clock(reset, b.reg_re && d.select_id, addr);

        let counter_bus = BusCycle {
            addr: addr & 0xff,
            wdata: b.reg_wdata,
            we: b.reg_we && d.select_counters,
            re: b.reg_re && d.select_counters,
        };
        for (i, e) in self.enc.iter_mut().enumerate() {
            *e = (
                inp.enc_a >> i & 1 == 1,
                inp.enc_b >> i & 1 == 1,
                inp.enc_z >> i & 1 == 1,
            );
        }
        // The safety block's home event and the channels' flags (the
        // states before the edge).
        let home = self.safety.home_event();
        let counter_flags = self.counters.flags();
        // The servo tick takes both snapshots at its edge; HALT is the
        // SERVO block's safe input (both as they stand before the edge).
        let servo_tick = self.servo.as_ref().is_some_and(ServoDac::tick);
        let halt = self.safety.halted();
        self.counters
            .clock_strobed(&self.enc, reset, &counter_bus, (home, servo_tick));

        // The counter bank's SNAPSHOT also captures the pulse positions.
        let snapshot = counter_bus.we && counter_bus.addr == self.snapshot_offset || servo_tick;
        let pulse_bus = BusCycle {
            addr: addr & 0x1ff,
            wdata: b.reg_wdata,
            we: b.reg_we && d.select_pulses,
            re: b.reg_re && d.select_pulses,
        };
        let safety_bus = BusCycle {
            addr: addr & 0x7f,
            wdata: b.reg_wdata,
            we: b.reg_we && d.select_safety,
            re: b.reg_re && d.select_safety,
        };
        self.safety.clock_with_pulses(
            &mut self.pulses,
            reset,
            (&pulse_bus, snapshot),
            &safety_bus,
            (inp.estop_ok, inp.machine),
            (
                counter_flags.0,
                counter_flags.1,
                isa_out.bell_to_dsp,
                servo_tick,
            ),
        );
        if let Some(servo) = &mut self.servo {
            let servo_bus = BusCycle {
                addr: addr & 0xf,
                wdata: b.reg_wdata,
                we: b.reg_we && d.select_servo,
                re: b.reg_re && d.select_servo,
            };
            servo.clock(reset, &servo_bus, halt);
        }

        self.isa.clock(&isa_pins, reset);

        if b.reg_re {
            self.read_from_id = d.select_id;
            self.read_from_counters = d.select_counters;
            self.read_from_pulses = d.select_pulses;
            self.read_from_safety = d.select_safety;
            self.read_from_servo = d.select_servo;
        }
        if reset {
            self.read_from_id = false;
            self.read_from_counters = false;
            self.read_from_pulses = false;
            self.read_from_safety = false;
            self.read_from_servo = false;
        }
    }

    /// Bits of `pulse_f1`/`pulse_f2` and the encoder inputs that exist.
    pub fn axis_mask(&self) -> u16 {
        self.axis_mask
    }
}

#[cfg(test)]
mod wiring_tests;

#[cfg(test)]
mod tests {
    use super::*;

    /// The MCU reads ID.MAGIC through the FSMC pins: a 16-bit read held
    /// long enough for the bridge's five-edge read latency.
    #[test]
    fn reads_the_magic_through_the_pins() {
        let config = Config::default();
        let mut m = MotionControllerModel::new(&config);
        let mut inp = TopInputs::idle();
        inp.reset = true;
        for _ in 0..5 {
            m.step(&inp);
        }
        inp.reset = false;
        for _ in 0..5 {
            m.step(&inp);
        }
        let magic = regmap::mcu_map(&config).block("ID").registers[0].reset;
        let mut halves = Vec::new();
        for a in [0u16, 1] {
            inp.fsmc_ne_n = false;
            inp.fsmc_a = a;
            m.step(&inp);
            inp.fsmc_noe_n = false;
            let mut out = TopOutputs::default();
            for _ in 0..8 {
                out = m.step(&inp);
            }
            assert!(out.fsmc_d_oe);
            halves.push(out.fsmc_d_out);
            inp.fsmc_noe_n = true;
            inp.fsmc_ne_n = true;
            for _ in 0..3 {
                m.step(&inp);
            }
        }
        assert_eq!(u32::from(halves[0]) | u32::from(halves[1]) << 16, magic);
        assert_eq!(m.outputs(&inp).pulse_f1 & !m.axis_mask(), 0);
    }
}
