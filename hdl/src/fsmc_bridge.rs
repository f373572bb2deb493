//! The STM32F4 FSMC bridge (docs/fsmc_bridge.md): bank 1 (NE1), SRAM
//! mode 1, 16-bit, non-multiplexed, into a 32-bit register port and a
//! 16-bit RAM port.

use motionhdl_spec::fsmc::{read_source, ADDRESS_BITS, RAM_WINDOW_BIT};
use rust_hdl::prelude::*;

/// FSMC cycles to register-port and RAM-port transactions.
///
/// NE1#, NOE# and NWE# go through two-flop synchronisers (NOE#/NWE# with a
/// third flop for the edge detect); A and D are sampled beside them. A read
/// acts once, when its NOE# fall reaches the second flop; a write once, when
/// its NWE# rise does, with the data sampled while NWE# was still low. The
/// access's address is frozen while a synchronised strobe is low.
///
/// A11 = 0: registers, `reg_addr` = A[10:1]; 32-bit registers are two
/// halfwords, low first. A low-half read reads the register and keeps bits
/// 31:16; the high-half read right after returns them (a 32-bit read is one
/// sample); a lone high-half read reads afresh. A low-half write is kept;
/// the high-half write writes {high, kept low} in one `reg_we`.
/// A11 = 1: the RAM window, `ram_addr` = A[9:0], one word per access.
#[derive(LogicBlock)]
pub struct FsmcBridge {
    /// FPGA clock (checked at 50 MHz).
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// FSMC_NE1, asynchronous.
    pub ne_n: Signal<In, Bit>,
    /// FSMC_NOE, asynchronous.
    pub noe_n: Signal<In, Bit>,
    /// FSMC_NWE, asynchronous.
    pub nwe_n: Signal<In, Bit>,
    /// FSMC_A[11:0]: halfword address (A[k] is byte-address bit k+1).
    pub a: Signal<In, Bits<12>>,
    /// FSMC_D as the MCU drives it (the input half of the D pins).
    pub d_in: Signal<In, Bits<16>>,
    /// Data the FPGA drives on D while `d_oe` is high (from a flop).
    pub d_out: Signal<Out, Bits<16>>,
    /// Drive D: NE1# and NOE# low (combinational from the pins).
    pub d_oe: Signal<Out, Bit>,
    /// Register port: 32-bit word address A[10:1].
    pub reg_addr: Signal<Out, Bits<10>>,
    /// Register port: write data {high half, kept low half}.
    pub reg_wdata: Signal<Out, Bits<32>>,
    /// Register port: write at the edge where this is high.
    pub reg_we: Signal<Out, Bit>,
    /// Register port: read; the edge where this is high registers the
    /// address, the next edge loads `reg_rdata`.
    pub reg_re: Signal<Out, Bit>,
    /// Register port: read data, valid from the second edge after `reg_re`.
    pub reg_rdata: Signal<In, Bits<32>>,
    /// RAM port: word address A[9:0].
    pub ram_addr: Signal<Out, Bits<10>>,
    /// RAM port: write data.
    pub ram_wdata: Signal<Out, Bits<16>>,
    /// RAM port: write at the edge where this is high.
    pub ram_we: Signal<Out, Bit>,
    /// RAM port: the word at the previous edge's `ram_addr`.
    pub ram_rdata: Signal<In, Bits<16>>,
    ne_s1: DFF<Bit>,
    noe_s1: DFF<Bit>,
    noe_s2: DFF<Bit>,
    noe_s3: DFF<Bit>,
    nwe_s1: DFF<Bit>,
    nwe_s2: DFF<Bit>,
    nwe_s3: DFF<Bit>,
    a_s1: DFF<Bits<12>>,
    d_s1: DFF<Bits<16>>,
    d_s2: DFF<Bits<16>>,
    cyc_sel: DFF<Bit>,
    cyc_a: DFF<Bits<12>>,
    wdata: DFF<Bits<16>>,
    hold_lo: DFF<Bits<16>>,
    hold_hi: DFF<Bits<16>>,
    hold_word: DFF<Bits<10>>,
    hold_valid: DFF<Bit>,
    rd_p1: DFF<Bit>,
    rd_p2: DFF<Bit>,
    rd_src1: DFF<Bits<2>>,
    rd_src2: DFF<Bits<2>>,
    d_q: DFF<Bits<16>>,
    src_ram: Constant<Bits<2>>,
    src_reg_low: Constant<Bits<2>>,
    src_reg_high: Constant<Bits<2>>,
    src_hold: Constant<Bits<2>>,
    ram_bit: Constant<Bits<4>>,
    half_shift: Constant<Bits<5>>,
    rd_start: Signal<Local, Bit>,
    wr_end: Signal<Local, Bit>,
    cyc_reg: Signal<Local, Bit>,
    cyc_high: Signal<Local, Bit>,
    use_hold: Signal<Local, Bit>,
    src: Signal<Local, Bits<2>>,
}

impl Default for FsmcBridge {
    fn default() -> Self {
        Self::new()
    }
}

impl FsmcBridge {
    pub fn new() -> Self {
        assert_eq!(ADDRESS_BITS, 12, "the FSMC address is Bits<12>");
        let src = |s: u8| Constant::new(u64::from(s).into());
        Self {
            clock: Default::default(),
            reset: Default::default(),
            ne_n: Default::default(),
            noe_n: Default::default(),
            nwe_n: Default::default(),
            a: Default::default(),
            d_in: Default::default(),
            d_out: Default::default(),
            d_oe: Default::default(),
            reg_addr: Default::default(),
            reg_wdata: Default::default(),
            reg_we: Default::default(),
            reg_re: Default::default(),
            reg_rdata: Default::default(),
            ram_addr: Default::default(),
            ram_wdata: Default::default(),
            ram_we: Default::default(),
            ram_rdata: Default::default(),
            ne_s1: Default::default(),
            noe_s1: Default::default(),
            noe_s2: Default::default(),
            noe_s3: Default::default(),
            nwe_s1: Default::default(),
            nwe_s2: Default::default(),
            nwe_s3: Default::default(),
            a_s1: Default::default(),
            d_s1: Default::default(),
            d_s2: Default::default(),
            cyc_sel: Default::default(),
            cyc_a: Default::default(),
            wdata: Default::default(),
            hold_lo: Default::default(),
            hold_hi: Default::default(),
            hold_word: Default::default(),
            hold_valid: Default::default(),
            rd_p1: Default::default(),
            rd_p2: Default::default(),
            rd_src1: Default::default(),
            rd_src2: Default::default(),
            d_q: Default::default(),
            src_ram: src(read_source::RAM),
            src_reg_low: src(read_source::REG_LOW),
            src_reg_high: src(read_source::REG_HIGH),
            src_hold: src(read_source::HOLD),
            ram_bit: Constant::new(u64::from(RAM_WINDOW_BIT).into()),
            half_shift: Constant::new(16u64.into()),
            rd_start: Default::default(),
            wr_end: Default::default(),
            cyc_reg: Default::default(),
            cyc_high: Default::default(),
            use_hold: Default::default(),
            src: Default::default(),
        }
    }
}

impl Logic for FsmcBridge {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, ne_s1, noe_s1, noe_s2, noe_s3, nwe_s1, nwe_s2, nwe_s3, a_s1, d_s1, d_s2,
            cyc_sel, cyc_a, wdata, hold_lo, hold_hi, hold_word, hold_valid, rd_p1, rd_p2, rd_src1,
            rd_src2, d_q
        );
        // Synchronisers; A and D sampled at the same edges as the strobes.
        self.ne_s1.d.next = self.ne_n.val();
        self.noe_s1.d.next = self.noe_n.val();
        self.noe_s2.d.next = self.noe_s1.q.val();
        self.noe_s3.d.next = self.noe_s2.q.val();
        self.nwe_s1.d.next = self.nwe_n.val();
        self.nwe_s2.d.next = self.nwe_s1.q.val();
        self.nwe_s3.d.next = self.nwe_s2.q.val();
        self.a_s1.d.next = self.a.val();
        self.d_s1.d.next = self.d_in.val();
        self.d_s2.d.next = self.d_s1.q.val();
        // The access: NE1# and A two edges behind the pins, frozen while a
        // synchronised strobe is low.
        if self.noe_s2.q.val() & self.nwe_s2.q.val() {
            self.cyc_sel.d.next = !self.ne_s1.q.val();
            self.cyc_a.d.next = self.a_s1.q.val();
        }
        // Write data: D sampled while NWE# had been low at two edges in a row.
        if !self.nwe_s2.q.val() & !self.nwe_s3.q.val() {
            self.wdata.d.next = self.d_s2.q.val();
        }

        // One action per strobe.
        self.rd_start.next = !self.noe_s2.q.val() & self.noe_s3.q.val() & self.cyc_sel.q.val();
        self.wr_end.next = self.nwe_s2.q.val() & !self.nwe_s3.q.val() & self.cyc_sel.q.val();
        self.cyc_reg.next = !self.cyc_a.q.val().get_bit(self.ram_bit.val().index());
        self.cyc_high.next = self.cyc_a.q.val().get_bit(0);
        self.use_hold.next = self.cyc_high.val()
            & self.hold_valid.q.val()
            & (self.hold_word.q.val() == self.cyc_a.q.val().get_bits::<10>(1));

        // The ports: addresses and data from flops, strobes for one clock.
        self.reg_addr.next = self.cyc_a.q.val().get_bits::<10>(1);
        self.reg_wdata.next = (bit_cast::<32, 16>(self.wdata.q.val()) << self.half_shift.val())
            | bit_cast::<32, 16>(self.hold_lo.q.val());
        self.reg_we.next = self.wr_end.val() & self.cyc_reg.val() & self.cyc_high.val();
        self.reg_re.next = self.rd_start.val() & self.cyc_reg.val() & !self.use_hold.val();
        self.ram_addr.next = self.cyc_a.q.val().get_bits::<10>(0);
        self.ram_wdata.next = self.wdata.q.val();
        self.ram_we.next = self.wr_end.val() & !self.cyc_reg.val();
        if self.wr_end.val() & self.cyc_reg.val() & !self.cyc_high.val() {
            self.hold_lo.d.next = self.wdata.q.val();
        }

        // Read pipeline: start (edge 3 registers the port address), the
        // register port's data (edge 4), d_out (edge 5).
        self.src.next = self.src_reg_high.val();
        if !self.cyc_reg.val() {
            self.src.next = self.src_ram.val();
        } else if !self.cyc_high.val() {
            self.src.next = self.src_reg_low.val();
        } else if self.use_hold.val() {
            self.src.next = self.src_hold.val();
        }
        self.rd_p1.d.next = self.rd_start.val();
        self.rd_p2.d.next = self.rd_p1.q.val();
        if self.rd_start.val() {
            self.rd_src1.d.next = self.src.val();
            self.hold_word.d.next = self.cyc_a.q.val().get_bits::<10>(1);
        }
        self.rd_src2.d.next = self.rd_src1.q.val();
        if self.rd_start.val() | self.wr_end.val() {
            self.hold_valid.d.next = false;
        }
        if self.rd_p2.q.val() {
            if self.rd_src2.q.val() == self.src_ram.val() {
                self.d_q.d.next = self.ram_rdata.val();
            } else if self.rd_src2.q.val() == self.src_reg_low.val() {
                self.d_q.d.next = self.reg_rdata.val().get_bits::<16>(0);
                self.hold_hi.d.next = self.reg_rdata.val().get_bits::<16>(16);
                self.hold_valid.d.next = true;
            } else if self.rd_src2.q.val() == self.src_reg_high.val() {
                self.d_q.d.next = self.reg_rdata.val().get_bits::<16>(16);
            } else {
                self.d_q.d.next = self.hold_hi.q.val();
            }
        }
        self.d_out.next = self.d_q.q.val();
        self.d_oe.next = !self.ne_n.val() & !self.noe_n.val();

        if self.reset.val() {
            self.ne_s1.d.next = true;
            self.noe_s1.d.next = true;
            self.noe_s2.d.next = true;
            self.noe_s3.d.next = true;
            self.nwe_s1.d.next = true;
            self.nwe_s2.d.next = true;
            self.nwe_s3.d.next = true;
            self.cyc_sel.d.next = false;
            self.hold_valid.d.next = false;
            self.rd_p1.d.next = false;
            self.rd_p2.d.next = false;
        }
    }
}
