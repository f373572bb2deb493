//! The external-RAM top's MCU window on a board: `MotionControllerExternal`
//! hands the MCU bus's A11 = 1 window out as `window_*` pins (the RAM lives
//! on the board). The top's plan runs it with `window_rdata` tied to 0; here
//! a 1 K x 16 RAM sits on those pins, so a window word written through the
//! FSMC must read back through them, which only holds when address, data,
//! write strobe and read data are each wired to the MCU bridge's RAM port.

use super::{compare, ram_window_ops, run_top, Edge, Plan};
use crate::harness::CheckReport;
use motionhdl_hdl::MotionControllerExternal;
use motionhdl_model::Config;

/// Words in the window (`window_addr` is 10 bits).
pub const WINDOW_WORDS: usize = 1024;

/// The RAM on the board, and how it decodes the address pins (a board
/// with an address line stuck is how the check is shown able to fail).
pub struct WindowRam {
    words: Vec<u16>,
    decode: fn(usize) -> usize,
    /// The write the top asks for at the coming edge: (address, data).
    write: Option<(usize, u16)>,
    read_addr: usize,
    /// Writes the RAM took.
    pub writes: u64,
    /// Clocks where the top drove its SRAM port (a PC-side strobe) although
    /// the PC side idled: `sram_we_n` low or `sram_d_oe` high.
    pub sram_driven: u64,
}

impl WindowRam {
    pub fn new(decode: fn(usize) -> usize) -> Self {
        Self {
            words: vec![0; WINDOW_WORDS],
            decode,
            write: None,
            read_addr: 0,
            writes: 0,
            sram_driven: 0,
        }
    }

    /// A synchronous RAM: the edge takes the address (and the write, if
    /// any); `window_rdata` is the word at that address before the write.
    fn clock<const N: usize>(&mut self, uut: &mut MotionControllerExternal<N>, edge: Edge) {
        match edge {
            Edge::Before => {
                let addr = (self.decode)(uut.window_addr.val().index());
                self.read_addr = addr;
                self.write = uut
                    .window_we
                    .val()
                    .then(|| (addr, uut.window_wdata.val().index() as u16));
                self.sram_driven += u64::from(!uut.sram_we_n.val() || uut.sram_d_oe.val());
            }
            Edge::After => {
                uut.window_rdata.next = u64::from(self.words[self.read_addr]).into();
                if let Some((addr, data)) = self.write.take() {
                    self.words[addr] = data;
                    self.writes += 1;
                }
            }
        }
    }
}

/// The internal build's RAM-window ops ([`ram_window_ops`]) over the
/// window's 1024 words: the FSMC ops and the halfwords each read returns.
pub fn window_plan() -> Plan {
    let (mut ops, mut expected) = (Vec::new(), Vec::new());
    ram_window_ops(&mut [0; WINDOW_WORDS], &mut ops, &mut expected);
    Plan {
        ops,
        expected,
        ignored_writes: 0,
    }
}

/// The external-RAM top (4 axes) with `ram` on its window pins through
/// [`window_plan`]: one case per halfword read (driven from setup to end
/// with the word written); the PC side idles, so `ram.sram_driven` must
/// stay 0.
pub fn external_window_rust(config: &Config, ram: &mut WindowRam) -> CheckReport {
    let plan = window_plan();
    let uut = MotionControllerExternal::<4>::new(config);
    let (obs, _) = run_top(uut, &plan.ops, |u, edge| ram.clock(u, edge));
    compare(
        "external-RAM top: the MCU window on a board RAM, rust-hdl",
        &plan,
        &obs,
    )
}
