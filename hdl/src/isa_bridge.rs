//! The ISA address-counter interface with the shared 1 K × 16 RAM inside
//! the FPGA (docs/isa_bridge.md).

use crate::isa_bus_core::IsaBusCore;
use motionhdl_spec::regmap::ISA_MAILBOX_TO_PC;
use rust_hdl::prelude::*;

isa_card_block! {
    /// ISA bus ↔ shared RAM through an address counter ([`IsaBusCore`]), the
    /// RAM in block RAM with a synchronous DSP port. A DSP write always has the
    /// RAM's write port; a queued PC write lands in the first clock the DSP
    /// leaves free. `dsp_rdata` shows the word at `dsp_addr` one edge later.
    pub struct IsaBridge {
        /// DSP port word address.
        pub dsp_addr: Signal<In, Bits<10>>,
        /// DSP port write data.
        pub dsp_wdata: Signal<In, Bits<16>>,
        /// DSP port write enable.
        pub dsp_we: Signal<In, Bit>,
        /// DSP port read data: the word at the previous edge's `dsp_addr`.
        pub dsp_rdata: Signal<Out, Bits<16>>,
        core: IsaBusCore,
        // Two copies of the RAM written together: one read port each, so the
        // PC's prefetch and the DSP never wait for each other (SB_RAM40_4K has
        // one read and one write port).
        ram_pc: RAM<Bits<16>, 10>,
        ram_dsp: RAM<Bits<16>, 10>,
        mailbox_to_pc: Constant<Bits<10>>,
    }
}

impl Default for IsaBridge {
    fn default() -> Self {
        Self::new()
    }
}

impl IsaBridge {
    pub fn new() -> Self {
        isa_card_new!({
            dsp_addr: Default::default(),
            dsp_wdata: Default::default(),
            dsp_we: Default::default(),
            dsp_rdata: Default::default(),
            core: IsaBusCore::new(),
            ram_pc: Default::default(),
            ram_dsp: Default::default(),
            mailbox_to_pc: Constant::new(u64::from(ISA_MAILBOX_TO_PC).into()),
        })
    }

    /// The address counter.
    pub fn counter(&self) -> u16 {
        self.core.count()
    }

    /// A PC write is waiting for the RAM's write port.
    pub fn write_pending(&self) -> bool {
        self.core.write_pending()
    }
}

impl Logic for IsaBridge {
    #[hdl_gen]
    fn update(&mut self) {
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
        self.core.dsp_rang.next =
            self.dsp_we.val() & (self.dsp_addr.val() == self.mailbox_to_pc.val());

        // The RAM's one write port: the DSP first.
        self.core.ram_word.next = self.ram_pc.read_data.val();
        self.core.ram_word_valid.next = true;
        self.core.write_done.next = self.core.write_valid.val() & !self.dsp_we.val();
        self.core.collision_seen.next = self.core.write_valid.val()
            & self.dsp_we.val()
            & (self.dsp_addr.val() == self.core.write_addr.val());
        self.ram_pc.write_clock.next = self.clock.val();
        self.ram_dsp.write_clock.next = self.clock.val();
        self.ram_pc.read_clock.next = self.clock.val();
        self.ram_dsp.read_clock.next = self.clock.val();
        self.ram_pc.write_enable.next = self.dsp_we.val() | self.core.write_valid.val();
        self.ram_dsp.write_enable.next = self.dsp_we.val() | self.core.write_valid.val();
        self.ram_pc.write_address.next = self.core.write_addr.val();
        self.ram_dsp.write_address.next = self.core.write_addr.val();
        self.ram_pc.write_data.next = self.core.write_data.val();
        self.ram_dsp.write_data.next = self.core.write_data.val();
        if self.dsp_we.val() {
            self.ram_pc.write_address.next = self.dsp_addr.val();
            self.ram_dsp.write_address.next = self.dsp_addr.val();
            self.ram_pc.write_data.next = self.dsp_wdata.val();
            self.ram_dsp.write_data.next = self.dsp_wdata.val();
        }
        self.ram_pc.read_address.next = self.core.counter.val();
        self.ram_dsp.read_address.next = self.dsp_addr.val();
        self.dsp_rdata.next = self.ram_dsp.read_data.val();
    }
}
