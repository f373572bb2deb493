//! The firmware driver ([`motionhdl_driver`]) on the simulated controller:
//! each of its register accesses is one FSMC bus operation through the
//! bus model into the rust-hdl top, as the MCU makes it.

use super::system::System;
use crate::bfm::fsmc::Op;
use motionhdl_driver::AxisConfig;

/// The axes as [`System::setup`] sets them up, for the driver: pulse +
/// direction, 2-clock steps and spaces, direction set-up 4 and hold 2,
/// FIFO low at 16 segments, instant stops.
pub const SETUP_AXIS: AxisConfig = AxisConfig {
    cw_ccw: 0,
    quadrature: 0,
    step_len: 2,
    step_space: 2,
    dir_setup: 4,
    dir_hold: 2,
    fifo_low_water: 16,
    decel: 0,
};

/// The FSMC's A pins carry halfword addresses.
fn halfword(offset: u32) -> u16 {
    u16::try_from(offset / 2).expect("an offset inside the 8 KB window")
}

impl<const N: usize> motionhdl_driver::Bus for System<N> {
    fn read32(&mut self, offset: u32) -> u32 {
        let h = self.exec(Op::Read32 {
            a: halfword(offset),
        });
        assert_eq!(h.len(), 2, "a 32-bit read is two halfwords");
        u32::from(h[0]) | u32::from(h[1]) << 16
    }
    fn write32(&mut self, offset: u32, value: u32) {
        self.exec(Op::Write32 {
            a: halfword(offset),
            data: value,
        });
    }
    fn read16(&mut self, offset: u32) -> u16 {
        self.exec(Op::Read16 {
            a: halfword(offset),
        })[0]
    }
    fn write16(&mut self, offset: u32, value: u16) {
        self.exec(Op::Write16 {
            a: halfword(offset),
            data: value,
        });
    }
}
