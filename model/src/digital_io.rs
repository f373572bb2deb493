//! The safety block's general-purpose I/O (docs/safety_io.md, "General-
//! purpose I/O"): GPIO_INPUTS inputs through the machine inputs' filter
//! with edge causes, and GPIO_OUTPUTS outputs, push-pull or open-drain,
//! that take their safe state when the card halts.

use crate::counter::BusCycle;
use crate::machine_inputs::PinFilter;
use crate::regmap::Block;
use motionhdl_spec::bus::mask_bits;
pub use motionhdl_spec::safety_io::{GPIO_INPUTS, GPIO_OUTPUTS};

/// The output pins as the board drives them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpoPins {
    /// Bit i: the level pin i drives while `oe` bit i is 1.
    pub out: u32,
    /// Bit i: pin i drives (else it is released).
    pub oe: u32,
}

/// The general-purpose inputs and outputs with their registers.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct DigitalIo {
    filters: Vec<PinFilter>,
    edge_ctrl: u32,
    cause: u32,
    mask: u32,
    value: u32,
    safe: u32,
    open_drain: u32,
    /// The filtered levels at the previous edge.
    before: u32,
}

impl Default for DigitalIo {
    fn default() -> Self {
        Self::new()
    }
}

impl DigitalIo {
    /// As after reset.
    pub fn new() -> Self {
        Self {
            filters: vec![PinFilter::default(); GPIO_INPUTS as usize],
            edge_ctrl: 0,
            cause: 0,
            mask: 0,
            value: 0,
            safe: 0,
            open_drain: 0,
            before: 0,
        }
    }

    /// The filtered input levels.
    pub fn levels(&self) -> u32 {
        crate::machine_inputs::levels(&self.filters)
    }

    /// The output pins: push-pull drives the value; open-drain drives 0
    /// and releases for 1.
    pub fn pins(&self) -> GpoPins {
        let all = mask_bits(GPIO_OUTPUTS);
        GpoPins {
            out: self.value & !self.open_drain & all,
            oe: (!self.open_drain | !self.value) & all,
        }
    }

    /// OR(GPI_CAUSE AND GPI_MASK).
    pub fn irq_active(&self) -> bool {
        self.cause & self.mask != 0
    }

    /// What a read of register `name` returns, if it is one of the block's.
    pub fn read(&self, name: &str) -> Option<u32> {
        Some(match name {
            "GPI_LEVEL" => self.levels(),
            "GPI_EDGE_CTRL" => self.edge_ctrl,
            "GPI_CAUSE" => self.cause,
            "GPI_MASK" => self.mask,
            "GPO_VALUE" => self.value,
            "GPO_SAFE" => self.safe,
            "GPO_OPEN_DRAIN" => self.open_drain,
            _ => return None,
        })
    }

    /// One rising edge (not a reset): the bus, the filter's `tick`,
    /// `halting` (the e-stop latch or the bite flag will be set after this
    /// edge) and the input pins.
    pub fn clock(&mut self, map: &Block, bus: &BusCycle, tick: bool, halting: bool, pins: u32) {
        let written = |name: &str, old: u32| bus.written(map, name, old);
        let levels = self.levels();
        let rises = levels & !self.before & self.edge_ctrl;
        let falls = !levels & self.before & self.edge_ctrl >> 16;
        self.cause = (self.cause & !bus.cleared(map, "GPI_CAUSE"))
            | ((rises | falls) & mask_bits(GPIO_INPUTS));
        self.before = levels;
        self.edge_ctrl = written("GPI_EDGE_CTRL", self.edge_ctrl);
        self.mask = written("GPI_MASK", self.mask);
        self.value = if halting {
            self.safe
        } else {
            written("GPO_VALUE", self.value)
        };
        self.safe = written("GPO_SAFE", self.safe);
        self.open_drain = written("GPO_OPEN_DRAIN", self.open_drain);
        for (i, f) in self.filters.iter_mut().enumerate() {
            f.clock(pins >> i & 1 == 1, tick);
        }
    }
}

#[cfg(test)]
mod contract_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_takes_its_safe_state_while_halting_and_open_drain_releases_a_one() {
        let map = crate::regmap::safety_io(1);
        let mut io = DigitalIo::new();
        let write = |name: &str, v: u32| BusCycle::write(map.register(name).offset, v);
        io.clock(&map, &write("GPO_SAFE", 0b0101), false, false, 0);
        io.clock(&map, &write("GPO_VALUE", 0b0011), false, false, 0);
        assert_eq!(
            io.pins(),
            GpoPins {
                out: 0b0011,
                oe: 0xffff
            }
        );
        io.clock(&map, &write("GPO_OPEN_DRAIN", 0b0001), false, false, 0);
        assert_eq!(io.pins().oe & 1, 0, "open-drain 1: released");
        io.clock(&map, &write("GPO_VALUE", 0xffff), false, true, 0);
        assert_eq!(io.read("GPO_VALUE"), Some(0b0101), "safe state, write lost");
    }

    #[test]
    fn only_a_selected_edge_sets_a_cause() {
        let map = crate::regmap::safety_io(1);
        let mut io = DigitalIo::new();
        let ctrl = BusCycle::write(map.register("GPI_EDGE_CTRL").offset, 1 << 16 | 2);
        io.clock(&map, &ctrl, false, false, 0);
        for _ in 0..8 {
            io.clock(&map, &BusCycle::default(), true, false, 0b11);
        }
        assert_eq!(io.levels(), 0b11);
        assert_eq!(
            io.read("GPI_CAUSE"),
            Some(0b10),
            "input 0 selects falls only"
        );
        for _ in 0..8 {
            io.clock(&map, &BusCycle::default(), true, false, 0);
        }
        assert_eq!(io.read("GPI_CAUSE"), Some(0b11));
    }
}
