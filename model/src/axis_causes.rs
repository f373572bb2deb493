//! A pair of per-axis causes in the safety block, with their mask and
//! optionally an enable register: the soft limits (docs/safety_io.md,
//! "Soft limits") and the counter events ("Counter events").

use crate::counter::BusCycle;
use crate::regmap::Block;
use motionhdl_spec::bus::mask_bits;

pub use motionhdl_spec::safety_io::{CauseKind, COUNTER_EVENTS, SOFT_LIMITS};

/// The registers: the first cause in bits N-1:0, the second in N+15:16.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct AxisCauses {
    kind: CauseKind,
    axes: u32,
    ctrl: u32,
    cause: u32,
    mask: u32,
    /// The inputs in the clock before (kept for rises only).
    before: u32,
}

impl AxisCauses {
    pub fn new(axes: u32, kind: CauseKind) -> Self {
        Self {
            kind,
            axes,
            ctrl: 0,
            cause: 0,
            mask: 0,
            before: 0,
        }
    }

    /// Per axis: no step up (the first cause, for a kind that stops).
    pub fn stop_up(&self) -> u32 {
        if self.kind.stops {
            self.cause & mask_bits(self.axes)
        } else {
            0
        }
    }

    /// Per axis: no step down (the second cause, likewise).
    pub fn stop_down(&self) -> u32 {
        if self.kind.stops {
            self.cause >> 16 & mask_bits(self.axes)
        } else {
            0
        }
    }

    pub fn irq_active(&self) -> bool {
        self.cause & self.mask != 0
    }

    /// What a read of register `name` returns, if it is one of these.
    pub fn read(&self, name: &str) -> Option<u32> {
        if Some(name) == self.kind.ctrl {
            Some(self.ctrl)
        } else if name == self.kind.cause {
            Some(self.cause)
        } else if name == self.kind.mask {
            Some(self.mask)
        } else {
            None
        }
    }

    /// One rising edge (not a reset) with the inputs as they stand before
    /// it. A cause sets while its enabled input is high, or where it
    /// rises; a 1 written clears it; the input wins.
    pub fn clock(&mut self, map: &Block, bus: &BusCycle, low: u32, high: u32) {
        let axes = mask_bits(self.axes);
        let levels = (low & axes) | (high & axes) << 16;
        let mut events = match self.kind.ctrl {
            Some(_) => levels & self.ctrl,
            None => levels,
        };
        if self.kind.on_rise {
            events &= !self.before;
            self.before = levels;
        }
        self.cause = (self.cause & !bus.cleared(map, self.kind.cause)) | events;
        if let Some(ctrl) = self.kind.ctrl {
            self.ctrl = bus.written(map, ctrl, self.ctrl);
        }
        self.mask = bus.written(map, self.kind.mask, self.mask);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regmap;

    fn write(map: &Block, name: &str, data: u32) -> BusCycle {
        BusCycle::write(map.register(name).offset, data)
    }

    /// Soft limits: a level cause per enabled axis and direction (CTRL
    /// enables, taking effect the edge after its write), write-1-to-clear
    /// that does not stick while the level persists, the IRQ through the
    /// mask, and each register read back by name.
    #[test]
    fn soft_limit_causes_follow_ctrl_clear_and_mask() {
        let map = regmap::safety_io(2);
        let mut c = AxisCauses::new(2, SOFT_LIMITS);
        let ctrl = 0b01 | 0b10 << 16;
        c.clock(&map, &write(&map, "SOFT_LIMIT_CTRL", ctrl), 0b11, 0b11);
        assert_eq!(c.cause, 0, "CTRL acts from the next edge");
        c.clock(&map, &BusCycle::default(), 0b11, 0b11);
        assert_eq!((c.stop_up(), c.stop_down()), (0b01, 0b10));
        assert!(!c.irq_active(), "masked");
        c.clock(&map, &write(&map, "SOFT_LIMIT_MASK", 0b10), 0b11, 0b11);
        assert!(!c.irq_active(), "the mask covers no set cause");
        c.clock(&map, &write(&map, "SOFT_LIMIT_MASK", 0b01), 0b11, 0b11);
        assert!(c.irq_active());
        assert_eq!(c.read("SOFT_LIMIT_CTRL"), Some(ctrl));
        assert_eq!(c.read("SOFT_LIMIT_CAUSE"), Some(ctrl));
        assert_eq!(c.read("SOFT_LIMIT_MASK"), Some(0b01));
        assert_eq!(c.read("COUNTER_CAUSE"), None);
        // The level persists: a clear does not stick.
        c.clock(&map, &write(&map, "SOFT_LIMIT_CAUSE", 0b01), 0b11, 0b11);
        assert_eq!(c.cause, ctrl);
        // The levels gone: a clear of one bit clears that bit only.
        c.clock(&map, &write(&map, "SOFT_LIMIT_CAUSE", 0b01), 0, 0);
        assert_eq!(c.cause, 0b10 << 16);
        assert!(!c.irq_active());
    }

    /// Counter events: a cause at each rise only, never a stop.
    #[test]
    fn counter_events_are_rises_and_never_stop() {
        let map = regmap::safety_io(2);
        let mut c = AxisCauses::new(2, COUNTER_EVENTS);
        let idle = BusCycle::default();
        c.clock(&map, &idle, 0b01, 0b10);
        assert_eq!(c.cause, 0b01 | 0b10 << 16);
        assert_eq!((c.stop_up(), c.stop_down()), (0, 0));
        c.clock(&map, &write(&map, "COUNTER_CAUSE", c.cause), 0b01, 0b10);
        assert_eq!(c.cause, 0, "cleared; a level that stays is no new event");
        c.clock(&map, &idle, 0, 0);
        c.clock(&map, &idle, 0b01, 0);
        assert_eq!(c.cause, 0b01, "a new rise");
    }
}
