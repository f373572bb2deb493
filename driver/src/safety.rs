//! The safety and I/O block: e-stop, watchdog, drive enables, machine
//! inputs, interrupt causes (docs/safety_io.md).

use crate::card::safety_reg as reg;
use crate::{regs, Bus, Card, Error};
use motionhdl_spec::safety_io::WATCHDOG_KEY;
use regs::safety;

/// The sticky interrupt causes of the card, one word per cause register
/// (bit n = axis, channel or input n): read them all, handle them, then
/// write the same words back to acknowledge exactly those.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct Causes {
    /// SAFETY.CAUSE: ESTOP, WATCHDOG, DOORBELL, SERVO_TICK.
    pub card: u32,
    pub done: u32,
    pub fifo_low: u32,
    pub limit: u32,
    pub home_alarm: u32,
    pub gpi: u32,
    pub soft_limit: u32,
    pub counter: u32,
}

const CAUSE_REGS: [usize; 8] = [
    safety::cause::OFFSET,
    safety::done_cause::OFFSET,
    safety::low_cause::OFFSET,
    safety::limit_cause::OFFSET,
    safety::home_alarm_cause::OFFSET,
    safety::gpi_cause::OFFSET,
    safety::soft_limit_cause::OFFSET,
    safety::counter_cause::OFFSET,
];
const MASK_REGS: [usize; 8] = [
    safety::cause_mask::OFFSET,
    safety::done_mask::OFFSET,
    safety::low_mask::OFFSET,
    safety::limit_mask::OFFSET,
    safety::home_alarm_mask::OFFSET,
    safety::gpi_mask::OFFSET,
    safety::soft_limit_mask::OFFSET,
    safety::counter_mask::OFFSET,
];

impl Causes {
    fn words(&self) -> [u32; 8] {
        [
            self.card,
            self.done,
            self.fifo_low,
            self.limit,
            self.home_alarm,
            self.gpi,
            self.soft_limit,
            self.counter,
        ]
    }
    fn from_words(w: [u32; 8]) -> Self {
        Self {
            card: w[0],
            done: w[1],
            fifo_low: w[2],
            limit: w[3],
            home_alarm: w[4],
            gpi: w[5],
            soft_limit: w[6],
            counter: w[7],
        }
    }
}

/// Which machine input a call configures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub enum Input {
    LimitPos = 0,
    LimitNeg = 1,
    Home = 2,
    Alarm = 3,
}

impl<B: Bus> Card<B> {
    /// SAFETY.STATUS: ESTOP_INPUT, ESTOP, BITTEN, ARMED, IRQ.
    pub fn safety_status(&mut self) -> u32 {
        self.bus.read32(reg(safety::status::OFFSET))
    }

    /// Releases the e-stop latch and the watchdog's bite flag (the card
    /// halts from reset until this is done), and checks that the card runs.
    /// The drives stay off until [`Card::enable_drives`].
    pub fn clear_halt(&mut self) -> Result<(), Error> {
        let status = self.safety_status();
        if status & safety::status::estop_input::MASK != 0 {
            return Err(Error::EstopInput);
        }
        let both = safety::clear::estop::MASK | safety::clear::bitten::MASK;
        self.bus.write32(reg(safety::clear::OFFSET), both);
        let halted = safety::status::estop::MASK | safety::status::bitten::MASK;
        if self.safety_status() & halted != 0 {
            return Err(Error::StillHalted);
        }
        Ok(())
    }

    /// SAFETY.ENABLE: the drive ENABLE outputs, bit n = axis n (ignored by
    /// the card while it is halted).
    pub fn enable_drives(&mut self, mask: u32) -> Result<(), Error> {
        if mask & !safety::enable::axes::MASK != 0 {
            return Err(Error::Argument);
        }
        self.bus.write32(reg(safety::enable::OFFSET), mask);
        Ok(())
    }

    /// Arms the watchdog: it bites (halts every axis, drives off) `clocks`
    /// + 1 clocks after this or the last [`Card::watchdog_feed`]; 0 disarms.
    pub fn watchdog_arm(&mut self, clocks: u32) {
        self.bus.write32(reg(safety::wdt_timeout::OFFSET), clocks);
    }

    /// Feeds the watchdog (WDT_RELOAD with the key).
    pub fn watchdog_feed(&mut self) {
        self.bus
            .write32(reg(safety::wdt_reload::OFFSET), WATCHDOG_KEY);
    }

    /// Turns machine input `input` on for the axes in `enable`, active low
    /// for those in `active_low`.
    pub fn input_configure(
        &mut self,
        input: Input,
        enable: u32,
        active_low: u32,
    ) -> Result<(), Error> {
        let m = safety::limit_pos_ctrl::enable::MASK;
        if (enable | active_low) & !m != 0 {
            return Err(Error::Argument);
        }
        let offset = match input {
            Input::LimitPos => safety::limit_pos_ctrl::OFFSET,
            Input::LimitNeg => safety::limit_neg_ctrl::OFFSET,
            Input::Home => safety::home_ctrl::OFFSET,
            Input::Alarm => safety::alarm_ctrl::OFFSET,
        };
        let value = enable | active_low << safety::limit_pos_ctrl::active_low::POS;
        self.bus.write32(reg(offset), value);
        Ok(())
    }

    /// Reads every cause register.
    pub fn causes(&mut self) -> Causes {
        Causes::from_words(CAUSE_REGS.map(|r| self.bus.read32(reg(r))))
    }

    /// Clears the causes set in `c` (write 1 to clear; a cause whose event
    /// is still active stays set, as the register map says).
    pub fn clear_causes(&mut self, c: &Causes) {
        for (r, w) in CAUSE_REGS.iter().zip(c.words()) {
            if w != 0 {
                self.bus.write32(reg(*r), w);
            }
        }
    }

    /// Which causes drive the IRQ pin, and its polarity.
    pub fn irq_configure(&mut self, masks: &Causes, active_high: bool) {
        for (r, w) in MASK_REGS.iter().zip(masks.words()) {
            self.bus.write32(reg(*r), w);
        }
        self.bus
            .write32(reg(safety::irq_ctrl::OFFSET), u32::from(active_high));
    }
}
