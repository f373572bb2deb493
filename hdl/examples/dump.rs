use motionhdl_hdl::*;
use rust_hdl::prelude::*;
fn main() {
    let mut a = PulseModeSelectorRegistered::default();
    a.connect_all();
    println!("{}", verilog::export(&a, "pulse_mode_selector_registered", &["hdr".into()]));
}
