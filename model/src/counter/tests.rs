//! Tests of the counter bank model, one file per part of the logic, and
//! the rigs they drive it with.

use super::*;
use crate::regmap;

mod bank;
mod counting;
mod filter;
mod index;

/// Edges from a pin change to the count with F = 0: two synchroniser
/// flops, the filter's accept, `up_q`, the count.
const PIN_TO_COUNT: usize = 5;

/// Edges from a Z change to INDEX with F = 0: two synchroniser flops,
/// the filter's accept, `zg_q`, `index_latch_q`, the index register.
const PIN_TO_INDEX: usize = 6;

fn ctrl_field(name: &str, value: u32) -> u32 {
    let map = regmap::counter_bank(1, 28);
    let f = map.array("CH").register("CTRL").field(name);
    (value << f.lsb) & f.mask()
}

fn cmd_bit(name: &str) -> u32 {
    regmap::counter_bank(1, 28)
        .array("CH")
        .register("CMD")
        .field(name)
        .mask()
}

fn status_field(name: &str, status: u32) -> u32 {
    regmap::counter_bank(1, 28)
        .array("CH")
        .register("STATUS")
        .field(name)
        .get(status)
}

/// A channel driven through its pins, like the bank drives it.
struct Rig {
    ch: Channel,
    pins: (bool, bool, bool),
    preset: u32,
}

impl Rig {
    /// Reset for 4 clocks with the pins at (a, b, z), then CTRL = ctrl,
    /// then enough idle clocks for the pipeline to be quiet.
    fn at(width: u32, err_bits: u32, ctrl: u32, pins: (bool, bool, bool)) -> Self {
        let mut r = Rig {
            ch: Channel::new(CounterParams::new(width, err_bits)),
            pins,
            preset: 0,
        };
        for _ in 0..4 {
            r.clock(ChannelInputs {
                reset: true,
                ..Default::default()
            });
        }
        r.clock(ChannelInputs {
            ctrl_write: Some(ctrl),
            ..Default::default()
        });
        r.idle(PIN_TO_COUNT);
        r
    }

    fn new(width: u32, ctrl: u32) -> Self {
        Self::at(width, 8, ctrl, (false, false, false))
    }

    fn clock(&mut self, extra: ChannelInputs) {
        let (a, b, z) = self.pins;
        self.ch.clock(&ChannelInputs {
            a,
            b,
            z,
            preset: self.preset,
            ..extra
        });
    }

    fn idle(&mut self, n: usize) {
        for _ in 0..n {
            self.clock(ChannelInputs::default());
        }
    }

    /// Applies each (a, b) for one clock, then lets the pipeline drain.
    fn walk(&mut self, ab: &[(bool, bool)]) {
        for &(a, b) in ab {
            self.pins.0 = a;
            self.pins.1 = b;
            self.idle(1);
        }
        self.idle(PIN_TO_INDEX);
    }

    fn z(&mut self, z: bool) {
        self.pins.2 = z;
        self.idle(PIN_TO_INDEX);
    }

    fn cmd(&mut self, name: &str) {
        self.cmd_word(cmd_bit(name));
    }

    /// A CMD write, then one idle clock so that a LOAD completes.
    fn cmd_word(&mut self, word: u32) {
        self.clock(ChannelInputs {
            cmd_write: Some(word),
            ..Default::default()
        });
        self.idle(1);
    }

    fn count(&self) -> i64 {
        i64::from(sign_extend(self.ch.state().count, self.ch.params().width) as i32)
    }
}

/// Pin levels (a, b).
type Ab = (bool, bool);

const FWD: [(bool, bool); 4] = [(true, false), (true, true), (false, true), (false, false)];
const BWD: [(bool, bool); 4] = [(false, true), (true, true), (true, false), (false, false)];

fn cycles(pattern: &[(bool, bool); 4], n: usize) -> Vec<(bool, bool)> {
    pattern.iter().copied().cycle().take(4 * n).collect()
}
