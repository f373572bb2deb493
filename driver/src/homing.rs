//! Homing: the firmware crate's sequence ([`motionhdl_firmware::homing`])
//! on the card's registers.

use crate::card::{ax, ch, safety_reg, RUN, SNAPSHOT};
use crate::{axis_index, regs, Bus, Card, Error, Segment};
use motionhdl_firmware::homing::{Home, Homing, HomingAxis, Poll};
use regs::{counter, pulse, safety};

/// One axis of a card, as the homing sequence drives it.
pub struct CardAxis<'a, B> {
    card: &'a mut Card<B>,
    axis: usize,
}

impl<'a, B: Bus> CardAxis<'a, B> {
    pub fn new(card: &'a mut Card<B>, axis: u32) -> Result<Self, Error> {
        Ok(Self {
            card,
            axis: axis_index(axis)?,
        })
    }

    fn bit(&self) -> u32 {
        1 << self.axis
    }

    /// Read-modify-write of this axis's bit in a register the axes share.
    fn update(&mut self, offset: u32, set: bool) {
        let bit = self.bit();
        self.card.update_bits(offset, bit, set);
    }

    fn ch(&self, reg: usize) -> u32 {
        ch(self.axis, reg)
    }

    fn ax(&self, reg: usize) -> u32 {
        ax(self.axis, reg)
    }
}

impl<B: Bus> HomingAxis for CardAxis<'_, B> {
    fn arm_home(&mut self) {
        self.update(safety_reg(safety::home_ctrl::OFFSET), true);
        self.update(safety_reg(safety::home_stop::OFFSET), true);
    }
    fn release_home(&mut self) {
        self.update(safety_reg(safety::home_stop::OFFSET), false);
    }
    fn start_move(&mut self, steps: i32, period: u32) {
        // One step per `period` clocks: RATE = 2^32 / period.
        let rate = ((1i64 << 32) / i64::from(period.max(1))) * i64::from(steps.signum());
        let segment = Segment {
            steps: steps.unsigned_abs(),
            rate: rate as i32,
            accel: 0,
            jerk: 0,
        };
        // The axis number was checked in `new`.
        let _ = self.card.push_segment(self.axis as u32, &segment);
        self.update(RUN, true);
    }
    fn stop(&mut self) {
        self.update(RUN, false);
    }
    fn moving(&mut self) -> bool {
        let s = self.card.bus.read32(self.ax(pulse::ax::status::OFFSET));
        let busy = pulse::ax::status::busy::MASK | pulse::ax::status::moving::MASK;
        s & (busy | pulse::ax::status::fifo_level::MASK) != 0
    }
    fn home_seen(&mut self) -> bool {
        let cause = self
            .card
            .bus
            .read32(safety_reg(safety::home_alarm_cause::OFFSET));
        cause & self.bit() != 0
    }
    fn clear_home(&mut self) {
        let bit = self.bit();
        let r = safety_reg(safety::home_alarm_cause::OFFSET);
        self.card.bus.write32(r, bit);
    }
    fn on_switch(&mut self) -> bool {
        let inputs = self
            .card
            .bus
            .read32(safety_reg(safety::home_alarm_inputs::OFFSET));
        inputs & self.bit() != 0
    }
    fn captured(&mut self) -> (i32, i32) {
        let position = self
            .card
            .bus
            .read32(self.ax(pulse::ax::home_position::OFFSET));
        let count = self
            .card
            .bus
            .read32(self.ch(counter::ch::home_count::OFFSET));
        (position as i32, count as i32)
    }
    fn arm_index(&mut self) {
        let ctrl = self.ch(counter::ch::ctrl::OFFSET);
        let old = self.card.bus.read32(ctrl);
        let latch = counter::ch::ctrl::idx_latch::MASK | counter::ch::ctrl::idx_oneshot::MASK;
        self.card.bus.write32(ctrl, old | latch);
        let cmd = self.ch(counter::ch::cmd::OFFSET);
        self.card.bus.write32(cmd, counter::ch::cmd::arm::MASK);
    }
    fn index(&mut self) -> Option<i32> {
        self.card.bus.write32(SNAPSHOT, 0);
        let status = self.card.bus.read32(self.ch(counter::ch::status::OFFSET));
        let armed = status & counter::ch::status::armed::MASK != 0;
        (!armed).then(|| self.card.bus.read32(self.ch(counter::ch::index::OFFSET)) as i32)
    }
}

impl<B: Bus> Card<B> {
    /// One step of `homing` on `axis`: Ok(None) while it runs, the home
    /// once found. Call it from a main loop or a timer; it never blocks.
    pub fn home_poll(&mut self, homing: &mut Homing, axis: u32) -> Result<Option<Home>, Error> {
        let mut a = CardAxis::new(self, axis)?;
        match homing.poll(&mut a) {
            Poll::Busy => Ok(None),
            Poll::Done(home) => Ok(Some(home)),
            Poll::Failed(e) => Err(Error::Homing(e)),
        }
    }
}
