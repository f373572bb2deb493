//! The bus side of the ISA bridge, shared by both RAM back-ends
//! (docs/isa_bridge.md): decode, synchronisers, address counter, STATUS,
//! the PC write queue and the read prefetch.

use crate::ls688::Ls688;
use motionhdl_spec::regmap::{
    self, ISA_ADDR_BITS, ISA_MAILBOX_TO_DSP, ISA_MAILBOX_TO_PC, ISA_RAM_WORDS,
};
use rust_hdl::prelude::*;

isa_card_block! {
    /// Everything of the ISA bridge but the RAM: a 74LS688 compares SA9..SA2
    /// with the base switches (G̅ = AEN), SA1..SA0 pick DATA, ADDR_CLEAR,
    /// ADDR_INC or STATUS, BALE latches the decoded address, and the counter is
    /// the RAM's PC-side address. A RAM back-end supplies the word at the
    /// counter and takes the queued PC write.
    ///
    /// Bus timing: IOR#/IOW#/BALE are synchronised (two flops) and an access
    /// acts once, when its strobe's rising edge reaches the third flop. Read data
    /// comes from a register prefetched before the strobe, through the
    /// combinational SA1..SA0 select, so SD is valid a few ns after IOR# falls.
    pub struct IsaBusCore {
        /// Back-end: the RAM word at `counter`.
        pub ram_word: Signal<In, Bits<16>>,
        /// Back-end: `ram_word` may be taken this clock.
        pub ram_word_valid: Signal<In, Bit>,
        /// Back-end: the queued write is done at this edge.
        pub write_done: Signal<In, Bit>,
        /// Back-end: the DSP wrote the queued write's word at this edge.
        pub collision_seen: Signal<In, Bit>,
        /// Back-end: the DSP wrote the PC's mailbox word at this edge.
        pub dsp_rang: Signal<In, Bit>,
        /// The address counter: the RAM's PC-side address.
        pub counter: Signal<Out, Bits<10>>,
        /// A PC write is queued.
        pub write_valid: Signal<Out, Bit>,
        /// Its word address.
        pub write_addr: Signal<Out, Bits<10>>,
        /// Its data.
        pub write_data: Signal<Out, Bits<16>>,
        decoder: Ls688,
        ior_s1: DFF<Bit>,
        ior_s2: DFF<Bit>,
        ior_s3: DFF<Bit>,
        iow_s1: DFF<Bit>,
        iow_s2: DFF<Bit>,
        iow_s3: DFF<Bit>,
        bale_s1: DFF<Bit>,
        bale_s2: DFF<Bit>,
        sel_s1: DFF<Bit>,
        sel_s2: DFF<Bit>,
        reg_s1: DFF<Bits<2>>,
        reg_s2: DFF<Bits<2>>,
        sd_s1: DFF<Bits<16>>,
        cyc_sel: DFF<Bit>,
        cyc_reg: DFF<Bits<2>>,
        wdata: DFF<Bits<16>>,
        count: DFF<Bits<10>>,
        auto_inc: DFF<Bit>,
        wrapped: DFF<Bit>,
        collision: DFF<Bit>,
        irq_en: DFF<Bit>,
        bell: DFF<Bit>,
        pw_valid: DFF<Bit>,
        pw_addr: DFF<Bits<10>>,
        pw_data: DFF<Bits<16>>,
        data_q: DFF<Bits<16>>,
        fresh: DFF<Bit>,
        reg_data: Constant<Bits<2>>,
        reg_addr_clear: Constant<Bits<2>>,
        reg_addr_inc: Constant<Bits<2>>,
        reg_status: Constant<Bits<2>>,
        addr_max: Constant<Bits<10>>,
        mailbox_to_pc: Constant<Bits<10>>,
        mailbox_to_dsp: Constant<Bits<10>>,
        irq_en_bit: Constant<Bits<4>>,
        bell_bit: Constant<Bits<4>>,
        irq_en_mask: Constant<Bits<16>>,
        bell_mask: Constant<Bits<16>>,
        auto_inc_bit: Constant<Bits<4>>,
        wrapped_bit: Constant<Bits<4>>,
        collision_bit: Constant<Bits<4>>,
        auto_inc_mask: Constant<Bits<16>>,
        wrapped_mask: Constant<Bits<16>>,
        collision_mask: Constant<Bits<16>>,
        selected: Signal<Local, Bit>,
        status: Signal<Local, Bits<16>>,
        read_end: Signal<Local, Bit>,
        write_end: Signal<Local, Bit>,
        access_end: Signal<Local, Bit>,
        advance: Signal<Local, Bit>,
        frozen: Signal<Local, Bit>,
    }
}

impl Default for IsaBusCore {
    fn default() -> Self {
        Self::new()
    }
}

impl IsaBusCore {
    /// The core; its registers and STATUS bits come from the register map.
    pub fn new() -> Self {
        assert_eq!(ISA_RAM_WORDS, 1 << ISA_ADDR_BITS);
        assert_eq!(ISA_ADDR_BITS, 10, "the RAM and counter are Bits<10>");
        let map = regmap::isa_bridge();
        let reg = |name: &str| Constant::new((map.register(name).offset as u64).into());
        let status = map.register("STATUS");
        let bit = |f: &str| Constant::new((status.field(f).lsb as u64).into());
        let mask = |f: &str| Constant::new((status.field(f).mask() as u64).into());
        assert_eq!(status.field("ADDR").lsb, 0);
        isa_card_new!({
            ram_word: Default::default(),
            ram_word_valid: Default::default(),
            write_done: Default::default(),
            collision_seen: Default::default(),
            dsp_rang: Default::default(),
            counter: Default::default(),
            write_valid: Default::default(),
            write_addr: Default::default(),
            write_data: Default::default(),
            decoder: Default::default(),
            ior_s1: Default::default(),
            ior_s2: Default::default(),
            ior_s3: Default::default(),
            iow_s1: Default::default(),
            iow_s2: Default::default(),
            iow_s3: Default::default(),
            bale_s1: Default::default(),
            bale_s2: Default::default(),
            sel_s1: Default::default(),
            sel_s2: Default::default(),
            reg_s1: Default::default(),
            reg_s2: Default::default(),
            sd_s1: Default::default(),
            cyc_sel: Default::default(),
            cyc_reg: Default::default(),
            wdata: Default::default(),
            count: Default::default(),
            auto_inc: Default::default(),
            wrapped: Default::default(),
            collision: Default::default(),
            irq_en: Default::default(),
            bell: Default::default(),
            pw_valid: Default::default(),
            pw_addr: Default::default(),
            pw_data: Default::default(),
            data_q: Default::default(),
            fresh: Default::default(),
            reg_data: reg("DATA"),
            reg_addr_clear: reg("ADDR_CLEAR"),
            reg_addr_inc: reg("ADDR_INC"),
            reg_status: reg("STATUS"),
            addr_max: Constant::new(((ISA_RAM_WORDS - 1) as u64).into()),
            mailbox_to_pc: Constant::new(u64::from(ISA_MAILBOX_TO_PC).into()),
            mailbox_to_dsp: Constant::new(u64::from(ISA_MAILBOX_TO_DSP).into()),
            irq_en_bit: bit("IRQ_EN"),
            bell_bit: bit("BELL"),
            irq_en_mask: mask("IRQ_EN"),
            bell_mask: mask("BELL"),
            auto_inc_bit: bit("AUTO_INC"),
            wrapped_bit: bit("WRAPPED"),
            collision_bit: bit("COLLISION"),
            auto_inc_mask: mask("AUTO_INC"),
            wrapped_mask: mask("WRAPPED"),
            collision_mask: mask("COLLISION"),
            selected: Default::default(),
            status: Default::default(),
            read_end: Default::default(),
            write_end: Default::default(),
            access_end: Default::default(),
            advance: Default::default(),
            frozen: Default::default(),
        })
    }

    /// The address counter.
    pub fn count(&self) -> u16 {
        self.count.q.val().index() as u16
    }

    /// A PC write is queued.
    pub fn write_pending(&self) -> bool {
        self.pw_valid.q.val()
    }
}

impl Logic for IsaBusCore {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, ior_s1, ior_s2, ior_s3, iow_s1, iow_s2, iow_s3, bale_s1, bale_s2, sel_s1,
            sel_s2, reg_s1, reg_s2, sd_s1, cyc_sel, cyc_reg, wdata, count, auto_inc, wrapped,
            collision, irq_en, bell, pw_valid, pw_addr, pw_data, data_q, fresh
        );
        // Address decode: the 74LS688 on the pins, G̅ = AEN.
        self.decoder.p.next = self.sa.val().get_bits::<8>(2);
        self.decoder.q.next = self.base.val();
        self.decoder.g_n.next = self.aen.val();
        self.selected.next = !self.decoder.p_eq_q_n.val();
        self.iocs16_n.next = self.decoder.p_eq_q_n.val();

        // Read path, combinational like the buffers on a real card.
        self.status.next = bit_cast::<16, 10>(self.count.q.val());
        if self.auto_inc.q.val() {
            self.status.next = self.status.val() | self.auto_inc_mask.val();
        }
        if self.wrapped.q.val() {
            self.status.next = self.status.val() | self.wrapped_mask.val();
        }
        if self.collision.q.val() {
            self.status.next = self.status.val() | self.collision_mask.val();
        }
        if self.irq_en.q.val() {
            self.status.next = self.status.val() | self.irq_en_mask.val();
        }
        if self.bell.q.val() {
            self.status.next = self.status.val() | self.bell_mask.val();
        }
        self.sd_oe.next = self.selected.val() & !self.ior_n.val();
        self.sd_out.next = self.status.val();
        if self.sa.val().get_bits::<2>(0) == self.reg_data.val() {
            self.sd_out.next = self.data_q.q.val();
        }

        // Synchronisers; SA1..SA0, the decode and SD travel beside the
        // strobes so that each is sampled at the same edges.
        self.ior_s1.d.next = self.ior_n.val();
        self.ior_s2.d.next = self.ior_s1.q.val();
        self.ior_s3.d.next = self.ior_s2.q.val();
        self.iow_s1.d.next = self.iow_n.val();
        self.iow_s2.d.next = self.iow_s1.q.val();
        self.iow_s3.d.next = self.iow_s2.q.val();
        self.bale_s1.d.next = self.bale.val();
        self.bale_s2.d.next = self.bale_s1.q.val();
        self.sel_s1.d.next = self.selected.val();
        self.sel_s2.d.next = self.sel_s1.q.val();
        self.reg_s1.d.next = self.sa.val().get_bits::<2>(0);
        self.reg_s2.d.next = self.reg_s1.q.val();
        self.sd_s1.d.next = self.sd_in.val();
        // BALE latches the decoded address for the cycle.
        if self.bale_s2.q.val() {
            self.cyc_sel.d.next = self.sel_s2.q.val();
            self.cyc_reg.d.next = self.reg_s2.q.val();
        }
        // SD sampled while IOW# has been low for two samples is inside the
        // bus's write-data window; the last such sample is the written word.
        if !self.iow_s1.q.val() & !self.iow_s2.q.val() {
            self.wdata.d.next = self.sd_s1.q.val();
        }

        // One action per strobe, at its rising edge.
        self.read_end.next = self.ior_s2.q.val() & !self.ior_s3.q.val() & self.cyc_sel.q.val();
        self.write_end.next = self.iow_s2.q.val() & !self.iow_s3.q.val() & self.cyc_sel.q.val();
        self.access_end.next = self.read_end.val() | self.write_end.val();
        self.advance.next = self.access_end.val()
            & ((self.cyc_reg.q.val() == self.reg_addr_inc.val())
                | ((self.cyc_reg.q.val() == self.reg_data.val()) & self.auto_inc.q.val()));

        if self.write_end.val() & (self.cyc_reg.q.val() == self.reg_status.val()) {
            self.count.d.next = self.wdata.q.val().get_bits::<10>(0);
            self.auto_inc.d.next = self.wdata.q.val().get_bit(self.auto_inc_bit.val().index());
            self.irq_en.d.next = self.wdata.q.val().get_bit(self.irq_en_bit.val().index());
        } else if self.access_end.val() & (self.cyc_reg.q.val() == self.reg_addr_clear.val()) {
            self.count.d.next = 0.into();
        } else if self.advance.val() {
            self.count.d.next = self.count.q.val() + 1;
        }
        if self.advance.val() & (self.count.q.val() == self.addr_max.val()) {
            self.wrapped.d.next = true;
        } else if (self.access_end.val() & (self.cyc_reg.q.val() == self.reg_addr_clear.val()))
            | (self.write_end.val()
                & (self.cyc_reg.q.val() == self.reg_status.val())
                & self.wdata.q.val().get_bit(self.wrapped_bit.val().index()))
        {
            self.wrapped.d.next = false;
        }

        // The queued PC write: the back-end says when it is done and
        // whether the DSP wrote the same word meanwhile.
        if self.collision_seen.val() {
            self.collision.d.next = true;
        } else if self.write_end.val()
            & (self.cyc_reg.q.val() == self.reg_status.val())
            & self.wdata.q.val().get_bit(self.collision_bit.val().index())
        {
            self.collision.d.next = false;
        }
        // The doorbells, IDT7130-style: the DSP's write of the PC's mailbox
        // word rings the PC; the PC's read of that word (or a 1 written to
        // STATUS.BELL) answers it. A ring in the same clock wins.
        if self.dsp_rang.val() {
            self.bell.d.next = true;
        } else if (self.read_end.val()
            & (self.cyc_reg.q.val() == self.reg_data.val())
            & (self.count.q.val() == self.mailbox_to_pc.val()))
            | (self.write_end.val()
                & (self.cyc_reg.q.val() == self.reg_status.val())
                & self.wdata.q.val().get_bit(self.bell_bit.val().index()))
        {
            self.bell.d.next = false;
        }
        self.irq.next = self.bell.q.val() & self.irq_en.q.val();
        self.bell_to_dsp.next = self.write_done.val()
            & self.pw_valid.q.val()
            & (self.pw_addr.q.val() == self.mailbox_to_dsp.val());
        if self.write_end.val() & (self.cyc_reg.q.val() == self.reg_data.val()) {
            self.pw_valid.d.next = true;
            self.pw_addr.d.next = self.count.q.val();
            self.pw_data.d.next = self.wdata.q.val();
        } else if self.write_done.val() {
            self.pw_valid.d.next = false;
        }
        self.counter.next = self.count.q.val();
        self.write_valid.next = self.pw_valid.q.val();
        self.write_addr.next = self.pw_addr.q.val();
        self.write_data.next = self.pw_data.q.val();
        // The prefetch follows the RAM. While the PC reads this card it
        // holds, once it holds a valid word, so SD changes at most once
        // under IOR# (from stale to valid, early, with a slow back-end).
        self.frozen.next = self.cyc_sel.q.val() & !self.ior_s2.q.val() & self.fresh.q.val();
        if !self.frozen.val() {
            if self.ram_word_valid.val() {
                self.data_q.d.next = self.ram_word.val();
            }
            self.fresh.d.next = self.ram_word_valid.val();
        }

        if self.reset.val() {
            self.ior_s1.d.next = true;
            self.ior_s2.d.next = true;
            self.ior_s3.d.next = true;
            self.iow_s1.d.next = true;
            self.iow_s2.d.next = true;
            self.iow_s3.d.next = true;
            self.bale_s1.d.next = false;
            self.bale_s2.d.next = false;
            self.sel_s1.d.next = false;
            self.sel_s2.d.next = false;
            self.cyc_sel.d.next = false;
            self.count.d.next = 0.into();
            self.auto_inc.d.next = false;
            self.wrapped.d.next = false;
            self.collision.d.next = false;
            self.irq_en.d.next = false;
            self.bell.d.next = false;
            self.pw_valid.d.next = false;
        }
    }
}
