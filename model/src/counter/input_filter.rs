//! Synchroniser and digital filter of one counter input pin.

/// Synchroniser + digital filter for one input (spec "Input conditioning").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InputFilter {
    /// First synchroniser flop.
    pub s1: bool,
    /// Second synchroniser flop: the sample the filter judges.
    pub s2: bool,
    /// Accepted level.
    pub level: bool,
    /// Clocks still to see before a change of `s2` is accepted (a 4-bit
    /// register counting down from F).
    pub cnt: u8,
}

impl InputFilter {
    /// Width of `cnt` and of the FILTER_AB / FILTER_Z settings.
    const CNT_MASK: u8 = 0xf;

    /// One rising edge. `setting` is F; only its low 4 bits exist in
    /// hardware. `cnt` counts down: it is loaded with F on every clock where
    /// `s2` equals `level` (and when a change is accepted), and a change is
    /// accepted when it reaches 0. So F is taken on the last clock before a
    /// change starts; writing CTRL during a change does not alter it.
    /// Without `filtering` (a build without the filter) `cnt` is always 0.
    pub fn clock(&mut self, pin: bool, setting: u8, reset: bool, filtering: bool) {
        let f = setting & Self::CNT_MASK;
        let before = *self;
        self.s1 = pin;
        self.s2 = before.s1;
        if reset {
            self.level = before.s2;
            self.cnt = 0;
        } else if before.s2 == before.level {
            self.cnt = f;
        } else if before.cnt == 0 {
            self.level = before.s2;
            self.cnt = f;
        } else {
            self.cnt = before.cnt - 1;
        }
        if !filtering {
            self.cnt = 0;
        }
    }
}
