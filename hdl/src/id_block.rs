//! The identity block (hostmot2's IDROM in spirit): constant registers that
//! tell firmware which gateware it talks to. Values come from the register
//! map (`regmap::id_block`), so the header and the gateware cannot disagree.

use motionhdl_spec::regmap;
use motionhdl_spec::Config;
use rust_hdl::prelude::*;

/// Word addresses the block decodes (`regmap::id_block` fits in them).
pub const ID_ADDRESS_BITS: usize = 4;
const ID_WORDS: usize = 1 << ID_ADDRESS_BITS;

/// Read-only registers on the internal register bus. Same contract as the
/// counter bank: the edge where `re` is high registers the address, the next
/// edge loads `rdata`, which then holds. Unused addresses read 0.
#[derive(LogicBlock)]
pub struct IdBlock {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub reset: Signal<In, Bit>,
    /// Word address within the block.
    pub addr: Signal<In, Bits<ID_ADDRESS_BITS>>,
    /// Read strobe.
    pub re: Signal<In, Bit>,
    /// Read data, valid from the second clock edge after `re`.
    pub rdata: Signal<Out, Bits<32>>,
    read_addr: DFF<Bits<ID_ADDRESS_BITS>>,
    read_pending: DFF<Bit>,
    read_data: DFF<Bits<32>>,
    addresses: Vec<Constant<Bits<ID_ADDRESS_BITS>>>,
    values: Vec<Constant<Bits<32>>>,
    read_value: Signal<Local, Bits<32>>,
}

impl IdBlock {
    /// The identity of the gateware built for `config`.
    pub fn new(config: &Config) -> Self {
        let map = regmap::mcu_map(config);
        let id = map.block("ID");
        assert_eq!(id.address_bits as usize, ID_ADDRESS_BITS);
        assert!(id.arrays.is_empty(), "the ID block has no arrays");
        let mut values = [0u32; ID_WORDS];
        for r in &id.registers {
            assert_eq!(
                r.access,
                regmap::Access::ReadOnly,
                "ID.{} must be read-only",
                r.name
            );
            values[r.offset as usize] = r.reset;
        }
        Self {
            clock: Default::default(),
            reset: Default::default(),
            addr: Default::default(),
            re: Default::default(),
            rdata: Default::default(),
            read_addr: Default::default(),
            read_pending: Default::default(),
            read_data: Default::default(),
            addresses: (0..ID_WORDS as u64)
                .map(|a| Constant::new(a.into()))
                .collect(),
            values: values
                .iter()
                .map(|v| Constant::new((*v as u64).into()))
                .collect(),
            read_value: Default::default(),
        }
    }
}

impl Logic for IdBlock {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, read_addr, read_pending, read_data);
        self.read_pending.d.next = self.re.val();
        if self.re.val() {
            self.read_addr.d.next = self.addr.val();
        }
        self.read_value.next = 0.into();
        for i in 0..ID_WORDS {
            if self.read_addr.q.val() == self.addresses[i].val() {
                self.read_value.next = self.values[i].val();
            }
        }
        if self.read_pending.q.val() {
            self.read_data.d.next = self.read_value.val();
        }
        if self.reset.val() {
            self.read_pending.d.next = false;
            self.read_addr.d.next = 0.into();
            self.read_data.d.next = 0.into();
        }
        self.rdata.next = self.read_data.q.val();
    }
}
