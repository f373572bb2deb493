//! The ISA address-counter interface for an external dual-port SRAM
//! (docs/isa_bridge.md, "External RAM").

use crate::isa_bus_core::IsaBusCore;
use motionhdl_spec::isa::{sram_state, SRAM_READ_SETTLE_CLOCKS};
use rust_hdl::prelude::*;

isa_card_block! {
    /// ISA bus ↔ an external 1 K × 16 dual-port SRAM (IDT7025-style; the DSP
    /// sits on the chip's other port) through an address counter
    /// ([`IsaBusCore`]). The FPGA drives the left port: while idle it reads the
    /// word at the counter (CE#, OE# low) and takes the data pins once the
    /// address has been stable for two clocks; a queued PC write is one clock
    /// of address and data set-up with OE# high, WE# low for two clocks, and
    /// one clock of hold. Every SRAM pin comes from a flop.
    pub struct IsaBridgeExternal {
        /// SRAM left-port address A9..A0.
        pub ram_addr: Signal<Out, Bits<10>>,
        /// SRAM data pins as the chip drives them.
        pub ram_d_in: Signal<In, Bits<16>>,
        /// Data the FPGA drives on the SRAM data pins while `ram_d_oe`.
        pub ram_d_out: Signal<Out, Bits<16>>,
        /// Drive the SRAM data pins.
        pub ram_d_oe: Signal<Out, Bit>,
        /// SRAM CE#.
        pub ram_ce_n: Signal<Out, Bit>,
        /// SRAM OE#.
        pub ram_oe_n: Signal<Out, Bit>,
        /// SRAM R/W# (WE#).
        pub ram_we_n: Signal<Out, Bit>,
        core: IsaBusCore,
        state: DFF<Bits<3>>,
        addr_q: DFF<Bits<10>>,
        d_out_q: DFF<Bits<16>>,
        d_oe_q: DFF<Bit>,
        ce_n_q: DFF<Bit>,
        oe_n_q: DFF<Bit>,
        // WE# active high inside, so that it is inactive from power-up.
        we_q: DFF<Bit>,
        sample: DFF<Bits<16>>,
        stable: DFF<Bits<2>>,
        st_read: Constant<Bits<3>>,
        st_setup: Constant<Bits<3>>,
        st_pulse1: Constant<Bits<3>>,
        st_pulse2: Constant<Bits<3>>,
        st_hold: Constant<Bits<3>>,
        settle: Constant<Bits<2>>,
        next_state: Signal<Local, Bits<3>>,
    }
}

impl Default for IsaBridgeExternal {
    fn default() -> Self {
        Self::new()
    }
}

impl IsaBridgeExternal {
    pub fn new() -> Self {
        let k3 = |v: u8| Constant::new((v as u64).into());
        const { assert!(SRAM_READ_SETTLE_CLOCKS < 4, "the settle counter is Bits<2>") };
        isa_card_new!({
            ram_addr: Default::default(),
            ram_d_in: Default::default(),
            ram_d_out: Default::default(),
            ram_d_oe: Default::default(),
            ram_ce_n: Default::default(),
            ram_oe_n: Default::default(),
            ram_we_n: Default::default(),
            core: IsaBusCore::new(),
            state: Default::default(),
            addr_q: Default::default(),
            d_out_q: Default::default(),
            d_oe_q: Default::default(),
            ce_n_q: Default::default(),
            oe_n_q: Default::default(),
            we_q: Default::default(),
            sample: Default::default(),
            stable: Default::default(),
            st_read: k3(sram_state::READ),
            st_setup: k3(sram_state::SETUP),
            st_pulse1: k3(sram_state::PULSE1),
            st_pulse2: k3(sram_state::PULSE2),
            st_hold: k3(sram_state::HOLD),
            settle: Constant::new((SRAM_READ_SETTLE_CLOCKS as u64).into()),
            next_state: Default::default(),
        })
    }

    /// The address counter.
    pub fn counter(&self) -> u16 {
        self.core.count()
    }
}

impl Logic for IsaBridgeExternal {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, state, addr_q, d_out_q, d_oe_q, ce_n_q, oe_n_q, we_q, sample, stable
        );
        self.core.clock.next = self.clock.val();
        self.core.reset.next = self.reset.val();
        self.core.sa.next = self.sa.val();
        self.core.sd_in.next = self.sd_in.val();
        self.core.ior_n.next = self.ior_n.val();
        self.core.iow_n.next = self.iow_n.val();
        self.core.aen.next = self.aen.val();
        self.core.bale.next = self.bale.val();
        self.core.base.next = self.base.val();
        self.sd_out.next = self.core.sd_out.val();
        self.sd_oe.next = self.core.sd_oe.val();
        self.iocs16_n.next = self.core.iocs16_n.val();
        self.irq.next = self.core.irq.val();
        self.bell_to_dsp.next = self.core.bell_to_dsp.val();
        // The DSP sits on the SRAM's other port, out of the FPGA's sight:
        // the chip's own mailbox interrupts serve it (docs/isa_bridge.md).
        self.core.dsp_rang.next = false;

        self.core.ram_word.next = self.sample.q.val();
        self.core.ram_word_valid.next = (self.state.q.val() == self.st_read.val())
            & (self.stable.q.val() >= self.settle.val())
            & !self.core.write_valid.val();
        self.core.write_done.next = self.state.q.val() == self.st_hold.val();
        self.core.collision_seen.next = false;
        self.sample.d.next = self.ram_d_in.val();

        self.next_state.next = self.st_read.val();
        if self.state.q.val() == self.st_read.val() {
            if self.core.write_valid.val() {
                self.next_state.next = self.st_setup.val();
            }
        } else if self.state.q.val() == self.st_setup.val() {
            self.next_state.next = self.st_pulse1.val();
        } else if self.state.q.val() == self.st_pulse1.val() {
            self.next_state.next = self.st_pulse2.val();
        } else if self.state.q.val() == self.st_pulse2.val() {
            self.next_state.next = self.st_hold.val();
        }
        self.state.d.next = self.next_state.val();
        if self.next_state.val() == self.st_read.val() {
            self.addr_q.d.next = self.core.counter.val();
            self.d_oe_q.d.next = false;
            self.ce_n_q.d.next = false;
            self.oe_n_q.d.next = false;
            self.we_q.d.next = false;
        } else if self.next_state.val() == self.st_setup.val() {
            self.addr_q.d.next = self.core.write_addr.val();
            self.d_out_q.d.next = self.core.write_data.val();
            self.d_oe_q.d.next = true;
            self.ce_n_q.d.next = false;
            self.oe_n_q.d.next = true;
            self.we_q.d.next = false;
        } else {
            self.we_q.d.next = (self.next_state.val() == self.st_pulse1.val())
                | (self.next_state.val() == self.st_pulse2.val());
        }
        // Clocks the read address has been on the pins, up to the settle time.
        self.stable.d.next = 0.into();
        if (self.next_state.val() == self.st_read.val())
            & (self.state.q.val() == self.st_read.val())
            & (self.core.counter.val() == self.addr_q.q.val())
        {
            self.stable.d.next = self.stable.q.val();
            if self.stable.q.val() != self.settle.val() {
                self.stable.d.next = self.stable.q.val() + 1;
            }
        }
        if self.reset.val() {
            self.state.d.next = self.st_read.val();
            self.stable.d.next = 0.into();
            self.d_oe_q.d.next = false;
            self.we_q.d.next = false;
            self.oe_n_q.d.next = false;
            self.ce_n_q.d.next = false;
        }
        self.ram_addr.next = self.addr_q.q.val();
        self.ram_d_out.next = self.d_out_q.q.val();
        self.ram_d_oe.next = self.d_oe_q.q.val();
        self.ram_ce_n.next = self.ce_n_q.q.val();
        self.ram_oe_n.next = self.oe_n_q.q.val();
        self.ram_we_n.next = !self.we_q.q.val();
    }
}
