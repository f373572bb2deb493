//! Pin groups that several blocks bring out under the same names: the ISA
//! card's bus pins (both ISA bridges and their shared core) and the FSMC
//! host pins (the MCU side and both top builds).
//!
//! Macros rather than a shared sub-block, because `#[derive(LogicBlock)]`
//! names a sub-block's ports `sub$port`, which would change the Verilog
//! ports. Each group has two macros: one declares a block whose first
//! ports are the group (the field order is the Verilog port order), one
//! builds `Self { .. }` with the group's signals defaulted and the caller's
//! fields after them. (The ISA bridges' pass-through of the group to their
//! core stays written out in each `update`: `#[hdl_gen]` only accepts a body
//! whose `self` has the hygiene of its own expansion, so a macro cannot
//! add statements to a caller's body.)

/// Declares `pub struct $name` with clock, reset and the ISA card's bus
/// pins as its first ports, then the caller's fields.
macro_rules! isa_card_block {
    (
        $(#[$attr:meta])*
        pub struct $name:ident { $($fields:tt)* }
    ) => {
        $(#[$attr])*
        #[derive(LogicBlock)]
        pub struct $name {
            /// FPGA clock (checked at 50 MHz).
            pub clock: Signal<In, Clock>,
            /// Synchronous reset, active high.
            pub reset: Signal<In, Bit>,
            /// ISA address SA9..SA0.
            pub sa: Signal<In, Bits<10>>,
            /// ISA data as the bus drives it (the input half of the SD pins).
            pub sd_in: Signal<In, Bits<16>>,
            /// Data the card drives on SD while `sd_oe` is high.
            pub sd_out: Signal<Out, Bits<16>>,
            /// Drive SD: the card is addressed and IOR# is low (combinational).
            pub sd_oe: Signal<Out, Bit>,
            /// IOR#, asynchronous.
            pub ior_n: Signal<In, Bit>,
            /// IOW#, asynchronous.
            pub iow_n: Signal<In, Bit>,
            /// AEN: high during DMA cycles, when the card must not answer.
            pub aen: Signal<In, Bit>,
            /// BALE: the address is latched while it is high.
            pub bale: Signal<In, Bit>,
            /// Base-address switches: the card answers on ports base*4..base*4+3.
            pub base: Signal<In, Bits<8>>,
            /// IOCS16#, for an open-collector pad (drive low when 0): the
            /// 74LS688's P=Q̅ output, so 16-bit cycles are not split.
            pub iocs16_n: Signal<Out, Bit>,
            /// The card's ISA IRQ line, active high: STATUS.BELL AND
            /// STATUS.IRQ_EN, from flops.
            pub irq: Signal<Out, Bit>,
            /// High for the one clock in which the PC's write of the DSP
            /// mailbox word lands in the RAM: the DSP side's doorbell.
            pub bell_to_dsp: Signal<Out, Bit>,
            $($fields)*
        }
    };
}

/// `Self { .. }` for an `isa_card_block!` block: the group's signals
/// defaulted, then the fields given.
macro_rules! isa_card_new {
    ({ $($fields:tt)* }) => {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            sa: Default::default(),
            sd_in: Default::default(),
            sd_out: Default::default(),
            sd_oe: Default::default(),
            ior_n: Default::default(),
            iow_n: Default::default(),
            aen: Default::default(),
            bale: Default::default(),
            base: Default::default(),
            iocs16_n: Default::default(),
            irq: Default::default(),
            bell_to_dsp: Default::default(),
            $($fields)*
        }
    };
}

/// Declares `pub struct $name<const N: usize>` with clock, reset and the
/// FSMC host pins as its first ports, then the caller's fields.
macro_rules! fsmc_host_block {
    (
        $(#[$attr:meta])*
        pub struct $name:ident<const N: usize> { $($fields:tt)* }
    ) => {
        $(#[$attr])*
        #[derive(LogicBlock)]
        pub struct $name<const N: usize> {
            /// FPGA clock (50 MHz by default).
            pub clock: Signal<In, Clock>,
            /// Synchronous reset, active high; hold at least 4 clocks.
            pub reset: Signal<In, Bit>,
            /// FSMC NE (chip select), asynchronous.
            pub fsmc_ne_n: Signal<In, Bit>,
            /// FSMC NOE (read strobe).
            pub fsmc_noe_n: Signal<In, Bit>,
            /// FSMC NWE (write strobe).
            pub fsmc_nwe_n: Signal<In, Bit>,
            /// FSMC A[11:0]: halfword address (byte address bits 12..1).
            pub fsmc_a: Signal<In, Bits<12>>,
            /// FSMC D[15:0] as the MCU drives it.
            pub fsmc_d_in: Signal<In, Bits<16>>,
            /// Data the FPGA drives on FSMC D while `fsmc_d_oe` is high.
            pub fsmc_d_out: Signal<Out, Bits<16>>,
            /// Drive FSMC D.
            pub fsmc_d_oe: Signal<Out, Bit>,
            $($fields)*
        }
    };
}

/// `Self { .. }` for an `fsmc_host_block!` block: the group's signals
/// defaulted, then the fields given.
macro_rules! fsmc_host_new {
    ({ $($fields:tt)* }) => {
        Self {
            clock: Default::default(),
            reset: Default::default(),
            fsmc_ne_n: Default::default(),
            fsmc_noe_n: Default::default(),
            fsmc_nwe_n: Default::default(),
            fsmc_a: Default::default(),
            fsmc_d_in: Default::default(),
            fsmc_d_out: Default::default(),
            fsmc_d_oe: Default::default(),
            $($fields)*
        }
    };
}
