//! The external-RAM top as the ISA bridge's bench: `MotionControllerExternal`
//! wires the bridge to its own `isa_*` and `sram_*` pins (and the bridge's
//! doorbell to the MCU side), so the bridge's stimulus, cycle model and
//! dual-port SRAM chip run through the top unchanged, the FSMC idle. No
//! other check drives the top's PC side with an SRAM behind it.

use super::rust_run::{run_bench, ExternalBench, ExternalIsa, RustRun};
use crate::bfm::isa::Op;
use crate::harness::settle;
use motionhdl_hdl::MotionControllerExternal;
use motionhdl_model::isa_bridge::{IsaPins, SramPins};
use motionhdl_model::{Config, IsaRam};
use rust_hdl::prelude::{Clock, In, Signal};

impl<const N: usize> ExternalIsa for MotionControllerExternal<N> {
    fn set(&mut self, pins: &IsaPins, reset: bool, d_in: u16) {
        self.isa_sa.next = u64::from(pins.sa).into();
        self.isa_sd_in.next = u64::from(pins.sd_in).into();
        self.isa_ior_n.next = pins.ior_n;
        self.isa_iow_n.next = pins.iow_n;
        self.isa_aen.next = pins.aen;
        self.isa_bale.next = pins.bale;
        self.isa_base.next = u64::from(pins.base).into();
        self.reset.next = reset;
        self.sram_d_in.next = u64::from(d_in).into();
        // The MCU side idles: FSMC deselected, e-stop chain closed.
        self.fsmc_ne_n.next = true;
        self.fsmc_noe_n.next = true;
        self.fsmc_nwe_n.next = true;
        self.estop_ok.next = true;
        settle(self);
    }
    fn bus(&self) -> (u16, bool, bool, bool, bool) {
        (
            self.isa_sd_out.val().index() as u16,
            self.isa_sd_oe.val(),
            self.isa_iocs16_n.val(),
            self.isa_irq.val(),
            self.mcu().doorbell.val(),
        )
    }
    fn sram_pins(&self) -> SramPins {
        SramPins {
            addr: self.sram_addr.val().index() as u16,
            d_out: self.sram_d_out.val().index() as u16,
            d_oe: self.sram_d_oe.val(),
            ce_n: self.sram_ce_n.val(),
            oe_n: self.sram_oe_n.val(),
            we_n: self.sram_we_n.val(),
        }
    }
    fn counter(&self) -> u16 {
        self.pc_bus().counter()
    }
    fn clock_pin(&mut self) -> &mut Signal<In, Clock> {
        &mut self.clock
    }
}

/// [`super::run_rust`] of the external build, through the default
/// external-RAM top (4 axes) instead of the bridge alone.
pub fn run_rust_in_external_top(base: u8, ops: &[Op]) -> RustRun {
    let config = Config::default().with_isa_ram(IsaRam::External);
    let bench = ExternalBench::new(MotionControllerExternal::<4>::new(&config));
    run_bench(bench, base, ops, None)
}
