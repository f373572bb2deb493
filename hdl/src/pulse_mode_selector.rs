//! The command-pulse mode selector, built from one 74LS153 as the seed wires it.

use crate::ls153::Ls153;
use rust_hdl::prelude::*;

/// Pulse-mode selector: K = 0 gives pulse+direction (F1 = S1, F2 = S2),
/// K = 1 gives CW/CCW (F1 = ¬S2·S1, F2 = S2·S1).
///
/// Realised exactly as the seed's Fig. 3(b): one 74LS153 with B = K, A = S2,
/// strobes tied low, data inputs tied to S1, 0 or 1. Combinational: when S1
/// and S2 change together the outputs can glitch; drive pins from
/// [`PulseModeSelectorRegistered`] instead.
#[derive(LogicBlock, Default)]
pub struct PulseModeSelector {
    /// Mode: 0 = pulse+direction, 1 = CW/CCW.
    pub k: Signal<In, Bit>,
    /// Command pulse (the CPU's PWM output).
    pub s1: Signal<In, Bit>,
    /// Direction: 0 = forward (CW), 1 = reverse (CCW).
    pub s2: Signal<In, Bit>,
    /// A-phase output: pulses (K=0) or CW pulses (K=1).
    pub f1: Signal<Out, Bit>,
    /// B-phase output: direction (K=0) or CCW pulses (K=1).
    pub f2: Signal<Out, Bit>,
    chip: Ls153,
}

impl PulseModeSelector {
    /// The 74LS153 inside, for probing its pins in tests and traces.
    pub fn chip(&self) -> &Ls153 {
        &self.chip
    }
}

impl Logic for PulseModeSelector {
    #[hdl_gen]
    fn update(&mut self) {
        self.chip.b.next = self.k.val();
        self.chip.a.next = self.s2.val();
        self.chip.g1_n.next = false;
        self.chip.g2_n.next = false;
        // Section 1 (F1): S1 everywhere but (K,S2) = 11.
        self.chip.c1_0.next = self.s1.val();
        self.chip.c1_1.next = self.s1.val();
        self.chip.c1_2.next = self.s1.val();
        self.chip.c1_3.next = false;
        // Section 2 (F2): the direction level when K=0, S1 when (K,S2) = 11.
        self.chip.c2_0.next = false;
        self.chip.c2_1.next = true;
        self.chip.c2_2.next = false;
        self.chip.c2_3.next = self.s1.val();
        self.f1.next = self.chip.y1.val();
        self.f2.next = self.chip.y2.val();
    }
}

/// [`PulseModeSelector`] followed by an output register, for driving pins.
///
/// F1 and F2 come straight from flip-flops, so they change only on the clock
/// edge and cannot glitch when S1 and S2 change together. They lag the
/// inputs by one clock. Synchronous reset drives both outputs low. S1, S2
/// and K must be synchronous to `clock` (they are when the on-chip pulse
/// generator drives them); synchronise asynchronous inputs first.
#[derive(LogicBlock, Default)]
pub struct PulseModeSelectorRegistered {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high: both outputs low.
    pub reset: Signal<In, Bit>,
    /// Mode: 0 = pulse+direction, 1 = CW/CCW.
    pub k: Signal<In, Bit>,
    /// Command pulse.
    pub s1: Signal<In, Bit>,
    /// Direction.
    pub s2: Signal<In, Bit>,
    /// Registered A-phase output.
    pub f1: Signal<Out, Bit>,
    /// Registered B-phase output.
    pub f2: Signal<Out, Bit>,
    selector: PulseModeSelector,
    f1_reg: DFF<Bit>,
    f2_reg: DFF<Bit>,
}

impl Logic for PulseModeSelectorRegistered {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, f1_reg, f2_reg);
        self.selector.k.next = self.k.val();
        self.selector.s1.next = self.s1.val();
        self.selector.s2.next = self.s2.val();
        self.f1_reg.d.next = self.selector.f1.val();
        self.f2_reg.d.next = self.selector.f2.val();
        if self.reset.val() {
            self.f1_reg.d.next = false;
            self.f2_reg.d.next = false;
        }
        self.f1.next = self.f1_reg.q.val();
        self.f2.next = self.f2_reg.q.val();
    }
}
