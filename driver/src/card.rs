//! The card: identity, counter channels, coherent reads, axes, segments.

use crate::{axis_index, regs, Bus, Error, Segment, AXES};
use motionhdl_firmware::segments::{direction, ramp_segment_clocks};
use regs::{counter, id, pulse};

pub(crate) const fn at(block: usize, reg: usize) -> u32 {
    (block + reg) as u32
}
/// Byte offset of register `reg` of counter channel `n`.
pub(crate) const fn ch(n: usize, reg: usize) -> u32 {
    at(counter::BASE_OFFSET + counter::ch::offset(n), reg)
}
/// Byte offset of register `reg` of pulse axis `n`.
pub(crate) const fn ax(n: usize, reg: usize) -> u32 {
    at(pulse::BASE_OFFSET + pulse::ax::offset(n), reg)
}
/// Byte offset of SAFETY register `reg`.
pub(crate) const fn safety_reg(reg: usize) -> u32 {
    at(regs::safety::BASE_OFFSET, reg)
}
pub(crate) const RUN: u32 = at(pulse::BASE_OFFSET, pulse::run::OFFSET);
pub(crate) const SNAPSHOT: u32 = at(counter::BASE_OFFSET, counter::snapshot::OFFSET);
const fn field(value: u32, mask: u32, pos: u32) -> u32 {
    (value & mask) >> pos
}

/// Segments the FIFO holds besides the one running.
pub const FIFO_DEPTH: u32 = motionhdl_spec::pulse::SEGMENT_FIFO_DEPTH as u32;

/// One card behind a [`Bus`].
#[derive(Debug)]
pub struct Card<B> {
    pub(crate) bus: B,
}

/// One axis at a SNAPSHOT: its counter channel and its pulse generator,
/// all captured in the same clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct AxisSample {
    /// COUNTER.CH.COUNT, sign-extended.
    pub count: i32,
    /// COUNTER.CH.INDEX, sign-extended.
    pub index: i32,
    /// COUNTER.CH.STATUS.
    pub status: u32,
    /// PULSE.AX.POSITION: steps emitted, sign-extended.
    pub position: i32,
}

/// How an axis's pulse generator drives its pins. Times in clocks (0
/// counts as 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C)]
pub struct AxisConfig {
    /// 0: pulse + direction; 1: CW/CCW (PULSE.AX.CTRL.MODE).
    pub cw_ccw: u8,
    /// Quadrature A/B instead of the selector (CTRL.QUADRATURE).
    pub quadrature: u8,
    pub step_len: u16,
    pub step_space: u16,
    pub dir_setup: u16,
    pub dir_hold: u16,
    /// STATUS.FIFO_LOW (and SAFETY.LOW_CAUSE) at or below this many
    /// segments, 0..=64.
    pub fifo_low_water: u32,
    /// Deceleration of a direction stop, 0 = instant (PULSE.AX.DECEL).
    pub decel: u32,
}

impl<B: Bus> Card<B> {
    pub const fn new(bus: B) -> Self {
        Self { bus }
    }

    /// The bus, for accesses the driver does not make.
    pub fn bus(&mut self) -> &mut B {
        &mut self.bus
    }

    /// Gives the bus back.
    pub fn into_bus(self) -> B {
        self.bus
    }

    /// Checks that the card is the one the driver was built for: ID.MAGIC,
    /// the major of ID.VERSION and ID.MAP_HASH. Returns ID.VERSION.
    pub fn check(&mut self) -> Result<u32, Error> {
        let magic = self.bus.read32(at(id::BASE_OFFSET, id::magic::OFFSET));
        if magic != regs::ID_MAGIC {
            return Err(Error::Magic(magic));
        }
        let version = self.bus.read32(at(id::BASE_OFFSET, id::version::OFFSET));
        let major = field(version, id::version::major::MASK, id::version::major::POS);
        if major != id::version::major::RESET {
            return Err(Error::Version(version));
        }
        let hash = self.bus.read32(at(id::BASE_OFFSET, id::map_hash::OFFSET));
        if hash != regs::MAP_HASH {
            return Err(Error::MapHash(hash));
        }
        Ok(version)
    }

    /// Writes a counter channel's CTRL (mode, reverse, index, filters).
    pub fn counter_configure(&mut self, channel: u32, ctrl: u32) -> Result<(), Error> {
        let n = axis_index(channel)?;
        self.bus.write32(ch(n, counter::ch::ctrl::OFFSET), ctrl);
        Ok(())
    }

    /// Sets a channel's count to `value` (PRESET, then CMD.LOAD).
    pub fn counter_load(&mut self, channel: u32, value: i32) -> Result<(), Error> {
        let n = axis_index(channel)?;
        self.bus.write32(
            at(counter::BASE_OFFSET, counter::preset::OFFSET),
            value as u32,
        );
        self.counter_command(n as u32, counter::ch::cmd::load::MASK)
    }

    /// Writes a channel's CMD (CLEAR, LOAD, ARM, CLEAR_STATUS bits).
    pub fn counter_command(&mut self, channel: u32, cmd: u32) -> Result<(), Error> {
        let n = axis_index(channel)?;
        self.bus.write32(ch(n, counter::ch::cmd::OFFSET), cmd);
        Ok(())
    }

    /// Every axis as it stood in one clock: one SNAPSHOT write, then the
    /// reads. Fills `out[i]` for axis i (at most [`AXES`] entries).
    pub fn sample(&mut self, out: &mut [AxisSample]) -> Result<(), Error> {
        if out.len() > AXES as usize {
            return Err(Error::Argument);
        }
        self.bus.write32(SNAPSHOT, 0);
        for (n, s) in out.iter_mut().enumerate() {
            *s = AxisSample {
                count: self.bus.read32(ch(n, counter::ch::count::OFFSET)) as i32,
                index: self.bus.read32(ch(n, counter::ch::index::OFFSET)) as i32,
                status: self.bus.read32(ch(n, counter::ch::status::OFFSET)),
                position: self.bus.read32(ax(n, pulse::ax::position::OFFSET)) as i32,
            };
        }
        Ok(())
    }

    /// Sets an axis's output mode and timing for segment moves
    /// (CTRL.MOVES on; writing CTRL also clears STATUS.OVERFLOW).
    pub fn axis_configure(&mut self, axis: u32, cfg: &AxisConfig) -> Result<(), Error> {
        let n = axis_index(axis)?;
        if cfg.cw_ccw > 1 || cfg.quadrature > 1 || cfg.fifo_low_water > FIFO_DEPTH {
            return Err(Error::Argument);
        }
        let ctrl = u32::from(cfg.cw_ccw) << pulse::ax::ctrl::mode::POS
            | u32::from(cfg.quadrature) << pulse::ax::ctrl::quadrature::POS
            | pulse::ax::ctrl::moves::MASK;
        let t = pulse::ax::step_timing::step_space::POS;
        let d = pulse::ax::dir_timing::dir_hold::POS;
        let step = u32::from(cfg.step_len) | u32::from(cfg.step_space) << t;
        let dir = u32::from(cfg.dir_setup) | u32::from(cfg.dir_hold) << d;
        self.bus.write32(ax(n, pulse::ax::ctrl::OFFSET), ctrl);
        self.bus
            .write32(ax(n, pulse::ax::step_timing::OFFSET), step);
        self.bus.write32(ax(n, pulse::ax::dir_timing::OFFSET), dir);
        let low = ax(n, pulse::ax::fifo_low_water::OFFSET);
        self.bus.write32(low, cfg.fifo_low_water);
        self.bus.write32(ax(n, pulse::ax::decel::OFFSET), cfg.decel);
        Ok(())
    }

    /// PULSE.AX.STATUS, live.
    pub fn axis_status(&mut self, axis: u32) -> Result<u32, Error> {
        let n = axis_index(axis)?;
        Ok(self.bus.read32(ax(n, pulse::ax::status::OFFSET)))
    }

    /// Whether the axis's move is out: STATUS.DONE and not BUSY.
    pub fn move_done(&mut self, axis: u32) -> Result<bool, Error> {
        let s = self.axis_status(axis)?;
        Ok(s & pulse::ax::status::done::MASK != 0 && s & pulse::ax::status::busy::MASK == 0)
    }

    /// Pushes one segment: the four SEG_* words, then SEG_PUSH. The caller
    /// knows there is room (see [`Stream`]). A segment the engine cannot
    /// finish ([`runnable`]) is refused with nothing written.
    pub fn push_segment(&mut self, axis: u32, seg: &Segment) -> Result<(), Error> {
        let n = axis_index(axis)?;
        if !runnable(seg) {
            return Err(Error::Argument);
        }
        self.write_segment(n, seg);
        Ok(())
    }

    /// The four SEG_* words of a checked segment, then SEG_PUSH.
    fn write_segment(&mut self, n: usize, seg: &Segment) {
        self.bus
            .write32(ax(n, pulse::ax::seg_steps::OFFSET), seg.steps);
        self.bus
            .write32(ax(n, pulse::ax::seg_rate::OFFSET), seg.rate as u32);
        self.bus
            .write32(ax(n, pulse::ax::seg_accel::OFFSET), seg.accel as u32);
        self.bus
            .write32(ax(n, pulse::ax::seg_jerk::OFFSET), seg.jerk as u32);
        self.bus.write32(ax(n, pulse::ax::seg_push::OFFSET), 0);
    }

    /// Starts every axis in `mask` in the same clock (one PULSE.RUN write;
    /// axes already running keep running).
    pub fn start(&mut self, mask: u32) -> Result<(), Error> {
        self.run_bits(mask, true)
    }

    /// Stops the axes in `mask` (no new steps; those commanded go out).
    pub fn stop(&mut self, mask: u32) -> Result<(), Error> {
        self.run_bits(mask, false)
    }

    fn run_bits(&mut self, mask: u32, set: bool) -> Result<(), Error> {
        if mask & !pulse::run::axes::MASK != 0 {
            return Err(Error::Argument);
        }
        self.update_bits(RUN, mask, set);
        Ok(())
    }

    /// Read-modify-write: the bits of `mask` in the register at `offset`
    /// set or cleared, the others kept.
    pub(crate) fn update_bits(&mut self, offset: u32, mask: u32, set: bool) {
        let old = self.bus.read32(offset);
        let new = if set { old | mask } else { old & !mask };
        self.bus.write32(offset, new);
    }

    /// Writes `data` into the shared RAM from word `word` on.
    pub fn ram_write(&mut self, word: u32, data: &[u16]) -> Result<(), Error> {
        let first = ram_range(word, data.len())?;
        for (i, &w) in data.iter().enumerate() {
            self.bus.write16(first + 2 * i as u32, w);
        }
        Ok(())
    }

    /// Reads the shared RAM from word `word` on into `data`.
    pub fn ram_read(&mut self, word: u32, data: &mut [u16]) -> Result<(), Error> {
        let first = ram_range(word, data.len())?;
        for (i, w) in data.iter_mut().enumerate() {
            *w = self.bus.read16(first + 2 * i as u32);
        }
        Ok(())
    }
}

/// Whether the move engine can finish `seg`: a segment with steps must
/// move (a rate, an accel or a jerk), and without a jerk its rate must not
/// pass 0 or leave the i32 range before the last step, at the NCO phase
/// most in its favour (the firmware crate's `ramp_segment_clocks`, in
/// closed form). A segment with a jerk is only checked to move: following it
/// takes up to 2^32 clock steps, too many for a push; the S-curve
/// planner's segments always finish.
pub fn runnable(seg: &Segment) -> bool {
    if seg.steps == 0 {
        return true;
    }
    match direction(seg) {
        0 => false,
        _ if seg.jerk != 0 => true,
        dir => ramp_segment_clocks(seg, u32::MAX, dir).is_some(),
    }
}

/// The byte offset of RAM word `word`, if `len` words from it fit.
fn ram_range(word: u32, len: usize) -> Result<u32, Error> {
    let end = (word as usize).checked_add(len).ok_or(Error::Argument)?;
    if end > regs::shared_ram::WORDS {
        return Err(Error::Argument);
    }
    Ok((regs::shared_ram::BASE_OFFSET + 2 * word as usize) as u32)
}

/// A planned move streamed into one axis's FIFO: each refill tops the
/// FIFO up from where the last left off, from a main loop or from the
/// FIFO-low interrupt (SAFETY.LOW_CAUSE).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Stream {
    pub axis: u32,
    /// Segments pushed so far.
    pub next: u32,
}

impl Stream {
    pub const fn new(axis: u32) -> Self {
        Self { axis, next: 0 }
    }

    /// Pushes as many of `segments[next..]` as the FIFO has room for
    /// (64 − STATUS.FIFO_LEVEL). Returns whether every segment is pushed.
    /// A FIFO that overflowed (STATUS.OVERFLOW) is an error: a segment was
    /// lost, so the move is not what was planned. So is a segment the
    /// engine cannot finish ([`runnable`]) among those this refill would
    /// push: none of them is pushed.
    pub fn refill<B: Bus, S: Copy + Into<Segment>>(
        &mut self,
        card: &mut Card<B>,
        segments: &[S],
    ) -> Result<bool, Error> {
        let status = card.axis_status(self.axis)?;
        if status & pulse::ax::status::overflow::MASK != 0 {
            return Err(Error::FifoOverflow(self.axis));
        }
        let level = field(
            status,
            pulse::ax::status::fifo_level::MASK,
            pulse::ax::status::fifo_level::POS,
        );
        let room = FIFO_DEPTH.saturating_sub(level) as usize;
        let from = (self.next as usize).min(segments.len());
        let batch = &segments[from..(from + room).min(segments.len())];
        // Checked first: a bad segment leaves the FIFO as it was.
        if !batch.iter().all(|&seg| runnable(&seg.into())) {
            return Err(Error::Argument);
        }
        let n = axis_index(self.axis)?;
        for &seg in batch {
            card.write_segment(n, &seg.into());
            self.next += 1;
        }
        Ok(self.next as usize >= segments.len())
    }
}
