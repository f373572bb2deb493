//! The machine inputs of the safety block (docs/safety_io.md, "Limits,
//! home and alarm"): per axis LIMIT_POS, LIMIT_NEG, HOME and ALARM, each
//! through a synchroniser and a filter timed by one shared prescaler, then
//! polarity, enable, sticky causes and the per-direction stops.

use crate::counter::BusCycle;
use crate::regmap::Block;
use motionhdl_spec::bus::mask_bits;
pub use motionhdl_spec::safety_io::{
    FILTER_TICKS, LIMIT_LATENCY, MACHINE_INPUTS, SOFT_LIMIT_LATENCY,
};

/// The machine pins of every axis as the FPGA reads them (bit i = axis i),
/// before polarity, and the general-purpose input pins (bit i = input i).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MachinePins {
    pub limit_pos: u32,
    pub limit_neg: u32,
    pub home: u32,
    pub alarm: u32,
    pub gpi: u32,
}

impl MachinePins {
    /// The pins in [`MACHINE_INPUTS`] order.
    pub fn kinds(&self) -> [u32; 4] {
        [self.limit_pos, self.limit_neg, self.home, self.alarm]
    }
}

/// One input's synchroniser and filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct PinFilter {
    meta: bool,
    sync: bool,
    level: bool,
    /// Ticks in a row at which `sync` differed from `level`, less one.
    count: u8,
}

impl PinFilter {
    /// The filtered level.
    pub fn level(&self) -> bool {
        self.level
    }

    /// One edge: the pin into the synchroniser; at a tick the filter
    /// takes the synchronised level once it has differed at FILTER_TICKS
    /// ticks in a row.
    pub fn clock(&mut self, pin: bool, tick: bool) {
        if tick {
            if self.sync == self.level {
                self.count = 0;
            } else if u32::from(self.count) == FILTER_TICKS - 1 {
                self.level = self.sync;
                self.count = 0;
            } else {
                self.count += 1;
            }
        }
        self.sync = self.meta;
        self.meta = pin;
    }
}

/// The filtered levels of `filters`, bit i = filter i.
pub fn levels(filters: &[PinFilter]) -> u32 {
    filters
        .iter()
        .enumerate()
        .fold(0, |bits, (i, f)| bits | u32::from(f.level()) << i)
}

/// The machine inputs of `axes` axes with their registers.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct MachineStops {
    axes: u32,
    tick_clocks: u32,
    prescaler: u32,
    /// `filters[kind][axis]`, kinds in [`MACHINE_INPUTS`] order.
    filters: [Vec<PinFilter>; 4],
    /// `*_CTRL` per kind: ENABLE in bits 15:0, ACTIVE_LOW in 31:16.
    ctrl: [u32; 4],
    limit_cause: u32,
    limit_mask: u32,
    home_alarm_cause: u32,
    home_alarm_mask: u32,
    home_stop: u32,
    home_before: u32,
}

const CTRL: [&str; 4] = [
    "LIMIT_POS_CTRL",
    "LIMIT_NEG_CTRL",
    "HOME_CTRL",
    "ALARM_CTRL",
];

impl MachineStops {
    /// As after reset, with a filter tick every `tick_clocks` clocks.
    pub fn new(axes: u32, tick_clocks: u32) -> Self {
        assert!(tick_clocks >= 1, "tick_clocks = 0 out of range 1..");
        let filters = || vec![PinFilter::default(); axes as usize];
        Self {
            axes,
            tick_clocks,
            prescaler: 0,
            filters: [filters(), filters(), filters(), filters()],
            ctrl: [0; 4],
            limit_cause: 0,
            limit_mask: 0,
            home_alarm_cause: 0,
            home_alarm_mask: 0,
            home_stop: 0,
            home_before: 0,
        }
    }

    /// The filters tick at the coming edge.
    pub fn tick(&self) -> bool {
        self.prescaler == 0
    }

    /// The filter's tick period in clocks.
    pub fn tick_clocks(&self) -> u32 {
        self.tick_clocks
    }

    /// The filtered levels of input `kind` (index into [`MACHINE_INPUTS`]).
    fn levels(&self, kind: usize) -> u32 {
        levels(&self.filters[kind])
    }

    /// Input `kind` active, after polarity, enabled or not.
    fn active(&self, kind: usize) -> u32 {
        (self.levels(kind) ^ self.ctrl[kind] >> 16) & mask_bits(self.axes)
    }

    /// Input `kind` active and enabled.
    fn acting(&self, kind: usize) -> u32 {
        self.active(kind) & self.ctrl[kind]
    }

    /// Per axis: stopped both ways (HOME_ALARM_CAUSE.ALARM, or .HOME
    /// with HOME_STOP).
    fn stop_both(&self) -> u32 {
        self.home_alarm_cause >> 16 | self.home_alarm_cause & self.home_stop
    }

    /// Per axis: no step in the positive direction (LIMIT_CAUSE.POS, an
    /// alarm or a home stop).
    pub fn stop_up(&self) -> u32 {
        (self.limit_cause | self.stop_both()) & mask_bits(self.axes)
    }

    /// Per axis: no step in the negative direction.
    pub fn stop_down(&self) -> u32 {
        (self.limit_cause >> 16 | self.stop_both()) & mask_bits(self.axes)
    }

    /// Per axis: the home event, high in the clock before the edge where
    /// HOME_ALARM_CAUSE.HOME sets (the enabled HOME input turned active):
    /// the pulse and counter banks capture HOME_POSITION and HOME_COUNT
    /// at that edge.
    pub fn home_event(&self) -> u32 {
        self.acting(2) & !self.home_before
    }

    /// OR(cause AND mask) over the block's two cause registers.
    pub fn irq_active(&self) -> bool {
        self.limit_cause & self.limit_mask != 0 || self.home_alarm_cause & self.home_alarm_mask != 0
    }

    /// What a read of register `name` returns, if it is one of the block's.
    pub fn read(&self, name: &str) -> Option<u32> {
        if let Some(kind) = CTRL.iter().position(|c| *c == name) {
            return Some(self.ctrl[kind]);
        }
        Some(match name {
            "LIMIT_INPUTS" => self.active(0) | self.active(1) << 16,
            "HOME_ALARM_INPUTS" => self.active(2) | self.active(3) << 16,
            "LIMIT_CAUSE" => self.limit_cause,
            "LIMIT_MASK" => self.limit_mask,
            "HOME_ALARM_CAUSE" => self.home_alarm_cause,
            "HOME_ALARM_MASK" => self.home_alarm_mask,
            "HOME_STOP" => self.home_stop,
            _ => return None,
        })
    }

    /// One rising edge (not a reset) with the bus and the pins.
    pub fn clock(&mut self, map: &Block, bus: &BusCycle, pins: &MachinePins) {
        let written = |name: &str, old: u32| bus.written(map, name, old);
        let cleared = |name: &str| bus.cleared(map, name);
        // Limits and alarms set their causes for as long as they act;
        // HOME at the edge where it starts acting.
        let limit_events = self.acting(0) | self.acting(1) << 16;
        let home = self.acting(2);
        let home_alarm_events = self.home_event() | self.acting(3) << 16;
        self.limit_cause = (self.limit_cause & !cleared("LIMIT_CAUSE")) | limit_events;
        self.home_alarm_cause =
            (self.home_alarm_cause & !cleared("HOME_ALARM_CAUSE")) | home_alarm_events;
        self.home_before = home;
        self.limit_mask = written("LIMIT_MASK", self.limit_mask);
        self.home_alarm_mask = written("HOME_ALARM_MASK", self.home_alarm_mask);
        self.home_stop = written("HOME_STOP", self.home_stop);
        for (kind, name) in CTRL.iter().enumerate() {
            self.ctrl[kind] = written(name, self.ctrl[kind]);
        }
        let tick = self.tick();
        self.prescaler = if tick {
            self.tick_clocks - 1
        } else {
            self.prescaler - 1
        };
        for (kind, pins) in pins.kinds().into_iter().enumerate() {
            for (i, f) in self.filters[kind].iter_mut().enumerate() {
                f.clock(pins >> i & 1 == 1, tick);
            }
        }
    }
}

#[cfg(test)]
mod contract_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_level_passes_after_four_ticks_in_a_row_and_a_glitch_restarts_the_count() {
        let mut f = PinFilter::default();
        // Two synchroniser edges, then FILTER_TICKS ticks of the new level.
        f.clock(true, true);
        f.clock(true, true);
        for _ in 0..FILTER_TICKS - 1 {
            f.clock(true, true);
            assert!(!f.level());
        }
        f.clock(true, true);
        assert!(f.level());
        // A low lasting three ticks is filtered out.
        for _ in 0..3 {
            f.clock(false, true);
        }
        for _ in 0..FILTER_TICKS + 2 {
            f.clock(true, true);
            assert!(f.level(), "a three-tick glitch never passes");
        }
    }

    #[test]
    fn a_disabled_limit_sets_nothing_and_an_enabled_one_stops_its_direction() {
        let map = crate::regmap::safety_io(2);
        let mut m = MachineStops::new(2, 1);
        let pins = MachinePins {
            limit_neg: 2,
            ..Default::default()
        };
        for _ in 0..10 {
            m.clock(&map, &BusCycle::default(), &pins);
        }
        assert_eq!(m.read("LIMIT_INPUTS"), Some(2 << 16));
        assert_eq!((m.stop_up(), m.stop_down()), (0, 0), "not enabled");
        let on = BusCycle::write(map.register("LIMIT_NEG_CTRL").offset, 3);
        m.clock(&map, &on, &pins);
        m.clock(&map, &BusCycle::default(), &pins);
        assert_eq!((m.stop_up(), m.stop_down()), (0, 2));
        let clear = BusCycle::write(map.register("LIMIT_CAUSE").offset, !0);
        m.clock(&map, &clear, &pins);
        assert_eq!(m.stop_down(), 2, "still active: the clear loses");
    }

    #[test]
    fn home_stops_both_ways_only_with_home_stop_and_until_cleared() {
        let map = crate::regmap::safety_io(2);
        let write = |name: &str, v: u32| BusCycle::write(map.register(name).offset, v);
        let mut m = MachineStops::new(2, 1);
        let home = MachinePins {
            home: 1,
            ..Default::default()
        };
        m.clock(&map, &write("HOME_CTRL", 3), &MachinePins::default());
        for _ in 0..10 {
            m.clock(&map, &BusCycle::default(), &home);
        }
        assert_eq!(m.read("HOME_ALARM_CAUSE"), Some(1));
        assert_eq!((m.stop_up(), m.stop_down()), (0, 0), "HOME_STOP off");
        m.clock(&map, &write("HOME_STOP", 1), &home);
        assert_eq!((m.stop_up(), m.stop_down()), (1, 1), "stopped both ways");
        // An edge cause: cleared while the switch is still closed, it stays clear.
        m.clock(&map, &write("HOME_ALARM_CAUSE", 1), &home);
        assert_eq!((m.stop_up(), m.stop_down()), (0, 0));
    }
}
