//! The top level: the MCU (FSMC) and the PC (ISA) reach the counter bank,
//! the identity block and the shared RAM (docs/motion_controller.md). Three
//! builds: the RAM inside the FPGA or an external dual-port SRAM (as the
//! ISA bridge has two), and the servo card's, with the RAM inside and the
//! SERVO block.

use crate::servo_dac::ServoDac;
use crate::{IsaBridge, IsaBridgeExternal, McuSide};
use motionhdl_spec::{Config, IsaRam};
use rust_hdl::prelude::*;

/// One top build: the ports and wiring both builds share (clock, reset and
/// the FSMC host pins from `fsmc_host_block!`, wired to the MCU side; the
/// ISA bus to the PC's bridge; encoders and pulse outputs), then the
/// build's own ports and its own wiring, written as `to = from;` for
/// `self.to.next = self.from.val();`.
///
/// The field order is the Verilog port order: the shared ports, the
/// build's own, then the sub-blocks `mcu` and `pc_bus`; `update` runs the
/// shared wiring, then the build's. A macro rather than a shared sub-block,
/// because `#[derive(LogicBlock)]` would name a sub-block's ports `sub$port`
/// and change the top's Verilog ports. `#[hdl_gen]` sees the statements
/// already expanded, plain assignments only.
macro_rules! top_level {
    (
        $(#[$struct_attr:meta])*
        pub struct $name:ident {
            $(
                $(#[$port_attr:meta])*
                pub $port:ident: $port_ty:ty,
            )*
        }
        pc_bus: $bridge:ident,
        blocks { $( $block:ident: $block_ty:ty = $block_new:path; )* }
        $(#[$new_attr:meta])*
        fn new asserts $ram:ident, servo_dac = $servo:literal, $ram_why:literal;
        wiring {
            $( $($to:ident).+ = $($from:ident).+; )*
        }
    ) => {
        fsmc_host_block! {
            $(#[$struct_attr])*
            pub struct $name<const N: usize> {
                /// ISA SA9..SA0.
                pub isa_sa: Signal<In, Bits<10>>,
                /// ISA SD15..SD0 as the bus drives it.
                pub isa_sd_in: Signal<In, Bits<16>>,
                /// Data the card drives on SD while `isa_sd_oe` is high.
                pub isa_sd_out: Signal<Out, Bits<16>>,
                /// Drive ISA SD.
                pub isa_sd_oe: Signal<Out, Bit>,
                /// ISA IOR#.
                pub isa_ior_n: Signal<In, Bit>,
                /// ISA IOW#.
                pub isa_iow_n: Signal<In, Bit>,
                /// ISA AEN (high in DMA cycles).
                pub isa_aen: Signal<In, Bit>,
                /// ISA BALE.
                pub isa_bale: Signal<In, Bit>,
                /// I/O base switches (SA9..SA2 of the card's first port).
                pub isa_base: Signal<In, Bits<8>>,
                /// ISA IOCS16#, for an open-collector pad.
                pub isa_iocs16_n: Signal<Out, Bit>,
                /// ISA IRQ line, active high (STATUS.BELL AND STATUS.IRQ_EN of
                /// the ISA bridge).
                pub isa_irq: Signal<Out, Bit>,
                /// Encoder A inputs, one per axis.
                pub enc_a: Signal<In, Bits<N>>,
                /// Encoder B inputs.
                pub enc_b: Signal<In, Bits<N>>,
                /// Encoder index inputs.
                pub enc_z: Signal<In, Bits<N>>,
                /// Command pulse outputs F1 per axis (pulse, CW or quadrature A).
                pub pulse_f1: Signal<Out, Bits<N>>,
                /// Command pulse outputs F2 per axis (direction, CCW or quadrature B).
                pub pulse_f2: Signal<Out, Bits<N>>,
                /// The e-stop chain, asynchronous: high = released; low, or
                /// an open wire pulled down on the board, = stop.
                pub estop_ok: Signal<In, Bit>,
                /// Limit switches in the positive direction, one per axis
                /// (asynchronous; polarity and enable in SAFETY).
                pub limit_pos: Signal<In, Bits<N>>,
                /// Limit switches in the negative direction.
                pub limit_neg: Signal<In, Bits<N>>,
                /// Home switches.
                pub home: Signal<In, Bits<N>>,
                /// Drive ALARM outputs.
                pub alarm: Signal<In, Bits<N>>,
                /// Drive ENABLE outputs per axis, high = enabled.
                pub drive_enable: Signal<Out, Bits<N>>,
                /// IRQ to the MCU (active low after reset; docs/safety_io.md).
                pub irq: Signal<Out, Bit>,
                /// General-purpose inputs (asynchronous; docs/safety_io.md).
                pub gpi: Signal<In, Bits<16>>,
                /// General-purpose outputs: the level driven while `gpo_oe`
                /// is 1 (the board wrapper makes each a tri-state pin).
                pub gpo_out: Signal<Out, Bits<16>>,
                /// General-purpose outputs: drive the pin (else release it).
                pub gpo_oe: Signal<Out, Bits<16>>,
                $(
                    $(#[$port_attr])*
                    pub $port: $port_ty,
                )*
                mcu: McuSide<N>,
                pc_bus: $bridge,
                $( $block: $block_ty, )*
            }
        }

        impl<const N: usize> $name<N> {
            $(#[$new_attr])*
            pub fn new(config: &Config) -> Self {
                assert_eq!(config.isa_ram(), IsaRam::$ram, $ram_why);
                assert_eq!(config.servo_dac(), $servo, "servo_dac: the top with(out) SERVO");
                fsmc_host_new!({
                    isa_sa: Default::default(),
                    isa_sd_in: Default::default(),
                    isa_sd_out: Default::default(),
                    isa_sd_oe: Default::default(),
                    isa_ior_n: Default::default(),
                    isa_iow_n: Default::default(),
                    isa_aen: Default::default(),
                    isa_bale: Default::default(),
                    isa_base: Default::default(),
                    isa_iocs16_n: Default::default(),
                    isa_irq: Default::default(),
                    enc_a: Default::default(),
                    enc_b: Default::default(),
                    enc_z: Default::default(),
                    pulse_f1: Default::default(),
                    pulse_f2: Default::default(),
                    estop_ok: Default::default(),
                    limit_pos: Default::default(),
                    limit_neg: Default::default(),
                    home: Default::default(),
                    alarm: Default::default(),
                    drive_enable: Default::default(),
                    irq: Default::default(),
                    gpi: Default::default(),
                    gpo_out: Default::default(),
                    gpo_oe: Default::default(),
                    $( $port: Default::default(), )*
                    mcu: McuSide::new(config),
                    pc_bus: $bridge::new(),
                    $( $block: $block_new(config), )*
                })
            }

            /// The MCU side, for probing in traces.
            pub fn mcu(&self) -> &McuSide<N> {
                &self.mcu
            }

            /// The ISA bridge, for the checks that run the bridge's own
            /// stimulus through the top.
            pub fn pc_bus(&self) -> &$bridge {
                &self.pc_bus
            }
        }

        impl<const N: usize> Logic for $name<N> {
            #[hdl_gen]
            fn update(&mut self) {
                self.mcu.clock.next = self.clock.val();
                self.mcu.reset.next = self.reset.val();
                self.pc_bus.clock.next = self.clock.val();
                self.pc_bus.reset.next = self.reset.val();
                // MCU side.
                self.mcu.fsmc_ne_n.next = self.fsmc_ne_n.val();
                self.mcu.fsmc_noe_n.next = self.fsmc_noe_n.val();
                self.mcu.fsmc_nwe_n.next = self.fsmc_nwe_n.val();
                self.mcu.fsmc_a.next = self.fsmc_a.val();
                self.mcu.fsmc_d_in.next = self.fsmc_d_in.val();
                self.fsmc_d_out.next = self.mcu.fsmc_d_out.val();
                self.fsmc_d_oe.next = self.mcu.fsmc_d_oe.val();
                self.mcu.enc_a.next = self.enc_a.val();
                self.mcu.enc_b.next = self.enc_b.val();
                self.mcu.enc_z.next = self.enc_z.val();
                self.pulse_f1.next = self.mcu.pulse_f1.val();
                self.pulse_f2.next = self.mcu.pulse_f2.val();
                self.mcu.estop_ok.next = self.estop_ok.val();
                self.mcu.limit_pos.next = self.limit_pos.val();
                self.mcu.limit_neg.next = self.limit_neg.val();
                self.mcu.home.next = self.home.val();
                self.mcu.alarm.next = self.alarm.val();
                self.drive_enable.next = self.mcu.drive_enable.val();
                self.irq.next = self.mcu.irq.val();
                self.mcu.gpi.next = self.gpi.val();
                self.gpo_out.next = self.mcu.gpo_out.val();
                self.gpo_oe.next = self.mcu.gpo_oe.val();
                // PC side.
                self.pc_bus.sa.next = self.isa_sa.val();
                self.pc_bus.sd_in.next = self.isa_sd_in.val();
                self.isa_sd_out.next = self.pc_bus.sd_out.val();
                self.isa_sd_oe.next = self.pc_bus.sd_oe.val();
                self.pc_bus.ior_n.next = self.isa_ior_n.val();
                self.pc_bus.iow_n.next = self.isa_iow_n.val();
                self.pc_bus.aen.next = self.isa_aen.val();
                self.pc_bus.bale.next = self.isa_bale.val();
                self.pc_bus.base.next = self.isa_base.val();
                self.isa_iocs16_n.next = self.pc_bus.iocs16_n.val();
                self.isa_irq.next = self.pc_bus.irq.val();
                // The PC rang the MCU's mailbox: a SAFETY cause.
                self.mcu.doorbell.next = self.pc_bus.bell_to_dsp.val();
                // No SERVO block unless the build's wiring below has one:
                // its page reads 0, no tick.
                self.mcu.servo_rdata.next = 0.into();
                self.mcu.servo_tick.next = false;
                $( self.$($to).+.next = self.$($from).+.val(); )*
            }
        }
    };
}

top_level! {
    /// `N` axes, the MCU's register bus ([`McuSide`]) and the PC's ISA bridge
    /// with the shared RAM in block RAM; the RAM's second port is the MCU's RAM
    /// window.
    pub struct MotionController {}
    pc_bus: IsaBridge,
    blocks {}
    /// The top level for `config` (axis count `N`, RAM inside).
    fn new asserts Internal, servo_dac = false, "this top has the RAM inside";
    wiring {
        // The shared RAM's second port is the MCU's RAM window.
        pc_bus.dsp_addr = mcu.ram_addr;
        pc_bus.dsp_wdata = mcu.ram_wdata;
        pc_bus.dsp_we = mcu.ram_we;
        mcu.ram_rdata = pc_bus.dsp_rdata;
    }
}

top_level! {
    /// As [`MotionController`] with the shared RAM outside the FPGA: the ISA
    /// bridge drives the SRAM's left port and the MCU (or DSP) wires straight to
    /// its right port. The MCU bus's A11 = 1 window (1 K x 16) then holds no
    /// RAM of the gateware's (ID.RAM_BASE and RAM_WORDS read 0); its port comes
    /// out as `window_*` for the board (a peripheral, or the SRAM's right port
    /// routed through the FPGA). With `window_rdata` tied to 0 the window reads
    /// 0 and writes go nowhere.
    pub struct MotionControllerExternal {
        /// External dual-port SRAM, left (PC) port: word address.
        pub sram_addr: Signal<Out, Bits<10>>,
        /// SRAM data as the chip drives it.
        pub sram_d_in: Signal<In, Bits<16>>,
        /// Data the FPGA drives on the SRAM's data pins while `sram_d_oe`.
        pub sram_d_out: Signal<Out, Bits<16>>,
        /// Drive the SRAM's data pins.
        pub sram_d_oe: Signal<Out, Bit>,
        /// SRAM CE#.
        pub sram_ce_n: Signal<Out, Bit>,
        /// SRAM OE#.
        pub sram_oe_n: Signal<Out, Bit>,
        /// SRAM R/W# (WE#).
        pub sram_we_n: Signal<Out, Bit>,
        /// MCU window (A11 = 1): word address A[9:0].
        pub window_addr: Signal<Out, Bits<10>>,
        /// MCU window write data.
        pub window_wdata: Signal<Out, Bits<16>>,
        /// MCU window write, one clock, at the edge where it is high.
        pub window_we: Signal<Out, Bit>,
        /// The word at the previous edge's `window_addr` (tie to 0 if unused).
        pub window_rdata: Signal<In, Bits<16>>,
    }
    pc_bus: IsaBridgeExternal,
    blocks {}
    /// The top level for `config` (axis count `N`, RAM external).
    fn new asserts External, servo_dac = false, "this top has the RAM outside";
    wiring {
        // The MCU window goes to the board.
        window_addr = mcu.ram_addr;
        window_wdata = mcu.ram_wdata;
        window_we = mcu.ram_we;
        mcu.ram_rdata = window_rdata;
        // The SRAM's left port.
        sram_addr = pc_bus.ram_addr;
        pc_bus.ram_d_in = sram_d_in;
        sram_d_out = pc_bus.ram_d_out;
        sram_d_oe = pc_bus.ram_d_oe;
        sram_ce_n = pc_bus.ram_ce_n;
        sram_oe_n = pc_bus.ram_oe_n;
        sram_we_n = pc_bus.ram_we_n;
    }
}

top_level! {
    /// The servo card (the TMS320C32 seed's SH-2000TH): [`MotionController`]
    /// with the SERVO block (docs/servo_dac.md) on the MCU bus. Its tick
    /// takes the counters' and pulse positions' snapshot at the edge where
    /// its transfer of the staged codes starts, and is SAFETY's
    /// CAUSE.SERVO_TICK; SAFETY's HALT sends the DAC its safe code.
    pub struct MotionControllerServo {
        /// DAC7744-style parallel DAC: data D15..D0.
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
        /// Serial (SPI) DAC option, SERVO.SERIAL.MODE = 1: SCLK, idles
        /// high.
        pub dac_sclk: Signal<Out, Bit>,
        /// Serial DAC data, MSB first.
        pub dac_sdin: Signal<Out, Bit>,
        /// Serial DAC frame sync, active low.
        pub dac_sync_n: Signal<Out, Bit>,
    }
    pc_bus: IsaBridge,
    blocks {
        servo: ServoDac = servo_dac_for;
    }
    /// The top level for `config` (axis count `N`, RAM inside, SERVO).
    fn new asserts Internal, servo_dac = true, "the servo card's top has the RAM inside";
    wiring {
        pc_bus.dsp_addr = mcu.ram_addr;
        pc_bus.dsp_wdata = mcu.ram_wdata;
        pc_bus.dsp_we = mcu.ram_we;
        mcu.ram_rdata = pc_bus.dsp_rdata;
        servo.clock = clock;
        servo.reset = reset;
        servo.addr = mcu.servo_addr;
        servo.wdata = mcu.servo_wdata;
        servo.we = mcu.servo_we;
        servo.re = mcu.servo_re;
        mcu.servo_rdata = servo.rdata;
        servo.safe = mcu.servo_safe;
        mcu.servo_tick = servo.tick;
        dac_data = servo.dac_data;
        dac_addr = servo.dac_addr;
        dac_cs_n = servo.dac_cs_n;
        dac_rw_n = servo.dac_rw_n;
        dac_ldac_n = servo.dac_ldac_n;
        dac_sclk = servo.dac_sclk;
        dac_sdin = servo.dac_sdin;
        dac_sync_n = servo.dac_sync_n;
    }
}

/// The SERVO block for `config`'s clock.
fn servo_dac_for(config: &Config) -> ServoDac {
    assert!(
        config.servo_dac(),
        "a servo top for a configuration without it"
    );
    ServoDac::new(config.clock_hz())
}
