//! How the driver reaches the card's registers.

use crate::regs;

/// One card's register window: byte offsets from its base. Registers are
/// 32 bits (on the 16-bit FSMC the low halfword first, which the gateware
/// relies on for tear-free reads); the shared RAM holds 16-bit words.
pub trait Bus {
    fn read32(&mut self, offset: u32) -> u32;
    fn write32(&mut self, offset: u32, value: u32);
    fn read16(&mut self, offset: u32) -> u16;
    fn write16(&mut self, offset: u32, value: u16);
}

/// The card mapped at `base` (e.g. [`regs::FSMC_NE1_BASE`]), with volatile
/// accesses.
#[derive(Clone, Copy, Debug)]
pub struct Mmio {
    base: usize,
}

impl Mmio {
    /// # Safety
    ///
    /// `base` must be where the card's window of [`regs::WINDOW_SIZE`]
    /// bytes is mapped, with the bus (FSMC) set up, for as long as the
    /// value is used.
    pub const unsafe fn new(base: usize) -> Self {
        Self { base }
    }
}

impl Bus for Mmio {
    fn read32(&mut self, offset: u32) -> u32 {
        // SAFETY: `new`'s contract; the driver passes register offsets only.
        unsafe { regs::read32(self.base, offset as usize) }
    }
    fn write32(&mut self, offset: u32, value: u32) {
        // SAFETY: as for read32.
        unsafe { regs::write32(self.base, offset as usize, value) }
    }
    fn read16(&mut self, offset: u32) -> u16 {
        // SAFETY: as for read32; RAM word offsets only.
        unsafe { regs::read16(self.base, offset as usize) }
    }
    fn write16(&mut self, offset: u32, value: u16) {
        // SAFETY: as for read16.
        unsafe { regs::write16(self.base, offset as usize, value) }
    }
}

impl<B: Bus + ?Sized> Bus for &mut B {
    fn read32(&mut self, offset: u32) -> u32 {
        (**self).read32(offset)
    }
    fn write32(&mut self, offset: u32, value: u32) {
        (**self).write32(offset, value)
    }
    fn read16(&mut self, offset: u32) -> u16 {
        (**self).read16(offset)
    }
    fn write16(&mut self, offset: u32, value: u16) {
        (**self).write16(offset, value)
    }
}
