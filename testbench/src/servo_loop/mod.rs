//! The servo card's loop closed in simulation (issue 20, docs/servo_loop.md):
//! the PC writes coarse interpolation points into the shared RAM over the
//! ISA bus-functional model and rings the DSP's doorbell; the DSP firmware
//! (the firmware crate's cubic B-spline fine interpolation and incremental
//! PID) reads them through its bus, waits for the servo tick's interrupt,
//! reads the counts the tick snapshotted, runs one PID step per axis and
//! stages the DAC codes, which the next tick loads; a DAC7744, amplifiers,
//! linear motors and grating rulers ([`plant`]) close the loop into the
//! counter bank.
//!
//! The FPGA is the bit-accurate model of the servo card's top
//! (`MotionControllerModel` with SERVO), which `tests/top_model.rs` holds
//! to the rust-hdl top pin for pin every clock; every bus access is the
//! STM32F4-timed FSMC bus-functional model's (the TMS320C32's own bus
//! bridge is not built yet) or the ISA model's, one access at a time.

pub mod dsp;
pub mod plant;
pub mod serial_dac;
pub mod trace;

use crate::bfm::fsmc::{self, documented_timing, CLOCK_TICKS, FIRST_EDGE_TICKS};
use crate::bfm::isa;
use crate::checks::motion_controller::top_model::{sample, step_rust};
use motionhdl_hdl::MotionControllerServo;
use motionhdl_model::fsmc_bridge::FsmcPins;
use motionhdl_model::motion_controller::{MotionControllerModel, TopInputs, TopOutputs};
use motionhdl_model::regmap::{self, BusMap};
use motionhdl_model::Config;
use plant::{Axis, Dac7744};
use rust_hdl::prelude::Block;
use serial_dac::SerialDac;

/// Axes of the loop (X and Y of the circle).
pub const AXES: usize = 2;
/// The card's configuration: 2 axes, SERVO, 50 MHz, the default filters.
pub fn config() -> Config {
    Config::default()
        .with_axes(AXES as u64)
        .expect("2 axes")
        .with_servo_dac(true)
}
/// Seconds per FPGA clock at 50 MHz.
pub const CLOCK_S: f64 = 20e-9;
/// The ISA card's base switches (I/O ports 0x300..0x303).
pub const ISA_BASE: u8 = 0xC0;

/// `points` + 1 coarse points of a circle of radius 500 counts, 24 per
/// turn, starting at the origin where the slides stand.
pub fn circle(points: u32) -> Vec<[i32; AXES]> {
    (0..=points)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 24.0;
            [
                (500.0 * (a.cos() - 1.0)).round() as i32,
                (500.0 * a.sin()).round() as i32,
            ]
        })
        .collect()
}

/// The card (the model top) set up, `coarse` sent by the PC and received
/// by the DSP, and the fine setpoints (`n` per span).
pub fn card_with(coarse: &[[i32; AXES]], n: u32) -> (ServoCard, Vec<[f64; AXES]>) {
    set_up(ServoCard::new(), coarse, n)
}

/// [`card_with`] on the board with the serial DAC.
pub fn serial_card_with(coarse: &[[i32; AXES]], n: u32) -> (ServoCard, Vec<[f64; AXES]>) {
    set_up(ServoCard::new().with_serial_dac(), coarse, n)
}

fn set_up(mut card: ServoCard, coarse: &[[i32; AXES]], n: u32) -> (ServoCard, Vec<[f64; AXES]>) {
    dsp::setup(&mut card);
    card.select_dac();
    card.pc_send(&dsp::encode_points(coarse));
    let got = dsp::receive_points(&mut card);
    assert_eq!(
        got, coarse,
        "the points through ISA, the RAM and the DSP bus"
    );
    let fine = dsp::fine_setpoints(&got, n);
    (card, fine)
}

/// The FPGA the bench drives: the model or the rust-hdl top.
pub trait TopEngine {
    /// The output pins now, with `p` on the input pins (before the edge).
    fn outputs(&mut self, p: &TopInputs) -> TopOutputs;
    /// [`Self::outputs`], then the rising edge.
    fn step(&mut self, p: &TopInputs) -> TopOutputs;
}

impl TopEngine for MotionControllerModel {
    fn outputs(&mut self, p: &TopInputs) -> TopOutputs {
        MotionControllerModel::outputs(self, p)
    }
    fn step(&mut self, p: &TopInputs) -> TopOutputs {
        MotionControllerModel::step(self, p)
    }
}

/// The rust-hdl servo card's top as a [`TopEngine`].
pub struct RustHdlTop(MotionControllerServo<AXES>);

impl TopEngine for RustHdlTop {
    fn outputs(&mut self, p: &TopInputs) -> TopOutputs {
        sample(&mut self.0, p)
    }
    fn step(&mut self, p: &TopInputs) -> TopOutputs {
        step_rust(&mut self.0, p)
    }
}

/// The card on the bench: FPGA, DAC, motors and rulers, and the e-stop
/// chain.
pub struct ServoCard {
    top: Box<dyn TopEngine>,
    map: BusMap,
    pub axes: [Axis; AXES],
    pub dac: Dac7744,
    /// The serial option's DAC on the SPI pins, and whether the board has
    /// it (the motors on its outputs) instead of the DAC7744.
    pub spi_dac: SerialDac,
    serial: bool,
    /// The e-stop chain (high = released).
    pub estop_ok: bool,
    /// Clocks run.
    pub clocks: u64,
    isa_pins: TopInputs,
    last: TopOutputs,
}

impl Default for ServoCard {
    fn default() -> Self {
        Self::new()
    }
}

impl ServoCard {
    /// The card with the model of the FPGA.
    pub fn new() -> Self {
        Self::with_top(Box::new(MotionControllerModel::new(&config())))
    }

    /// The card with the rust-hdl top (about 300 times slower).
    pub fn on_rust_hdl() -> Self {
        let mut top = MotionControllerServo::<AXES>::new(&config());
        top.connect_all();
        Self::with_top(Box::new(RustHdlTop(top)))
    }

    fn with_top(top: Box<dyn TopEngine>) -> Self {
        let config = config();
        let mut isa_pins = TopInputs::idle();
        isa_pins.isa_base = ISA_BASE;
        Self {
            top,
            map: regmap::mcu_map(&config),
            axes: [Axis::default(); AXES],
            dac: Dac7744::default(),
            spi_dac: SerialDac::default(),
            serial: false,
            estop_ok: true,
            clocks: 0,
            isa_pins,
            last: TopOutputs::default(),
        }
    }

    /// The board with the serial DAC: the motors on its outputs, and
    /// [`Self::select_dac`] picks it.
    pub fn with_serial_dac(mut self) -> Self {
        self.serial = true;
        self
    }

    /// On the serial board, writes SERVO.SERIAL.MODE = 1 with the reset
    /// SCLK and SYNC times (the parallel board keeps the reset value).
    pub fn select_dac(&mut self) {
        if self.serial {
            let reset = self.map.block("SERVO").register("SERIAL").reset;
            self.write("SERVO", None, "SERIAL", reset | 1);
        }
    }

    /// The codes the motors' DAC outputs hold.
    pub fn dac_output(&self) -> [u16; 4] {
        match self.serial {
            false => self.dac.output,
            true => self.spi_dac.output,
        }
    }

    /// The MCU map the DSP addresses.
    pub fn map(&self) -> &BusMap {
        &self.map
    }

    /// The output pins of the last clock.
    pub fn pins(&self) -> &TopOutputs {
        &self.last
    }

    /// One clock: the FSMC pins and reset given, the ISA pins as the last
    /// ISA event left them, the rulers on the encoder inputs; then the
    /// DAC, the motors and the rulers move.
    fn edge(&mut self, fsmc: &FsmcPins, reset: bool) {
        let mut p = self.inputs(fsmc, reset);
        let (mut a, mut b) = (0u16, 0u16);
        for (i, axis) in self.axes.iter().enumerate() {
            let (ea, eb) = axis.quadrature();
            a |= u16::from(ea) << i;
            b |= u16::from(eb) << i;
        }
        p.enc_a = a;
        p.enc_b = b;
        self.last = self.top.step(&p);
        self.dac.observe(&self.last);
        self.spi_dac.observe(&self.last);
        let volts: [f64; AXES] = std::array::from_fn(|i| match self.serial {
            false => self.dac.volts(i),
            true => self.spi_dac.volts(i),
        });
        for (axis, v) in self.axes.iter_mut().zip(volts) {
            axis.advance(v, CLOCK_S);
        }
        self.clocks += 1;
    }

    /// The FSMC data the MCU would latch now.
    fn fsmc_data(&mut self, fsmc: &FsmcPins, reset: bool) -> u16 {
        let p = self.inputs(fsmc, reset);
        self.top.outputs(&p).fsmc_d_out
    }

    /// The input pins: the FSMC's and reset as given, the ISA pins as the
    /// last ISA event left them, the e-stop chain (encoders: the caller's).
    fn inputs(&self, fsmc: &FsmcPins, reset: bool) -> TopInputs {
        TopInputs {
            reset,
            fsmc_ne_n: fsmc.ne_n,
            fsmc_noe_n: fsmc.noe_n,
            fsmc_nwe_n: fsmc.nwe_n,
            fsmc_a: fsmc.a,
            fsmc_d_in: fsmc.d_in,
            estop_ok: self.estop_ok,
            ..self.isa_pins
        }
    }

    /// One DSP bus operation to its end; a read returns the halfwords.
    pub fn exec(&mut self, op: fsmc::Op) -> Vec<u16> {
        let (events, end) = fsmc::timeline(&[op], &documented_timing());
        let (mut pins, mut reset) = (FsmcPins::idle(), false);
        let mut observed = Vec::new();
        let (mut edge, mut i) = (FIRST_EDGE_TICKS, 0);
        loop {
            while i < events.len() && events[i].0 < edge {
                match events[i].1 {
                    fsmc::Event::Pins(p, r) => (pins, reset) = (p, r),
                    fsmc::Event::ObserveSetup => {}
                    fsmc::Event::ObserveEnd => observed.push(self.fsmc_data(&pins, reset)),
                }
                i += 1;
            }
            if edge > end {
                return observed;
            }
            self.edge(&pins, reset);
            edge += CLOCK_TICKS;
        }
    }

    /// One PC bus operation (ISA, the card at [`ISA_BASE`]) to its end.
    pub fn isa(&mut self, op: isa::Op) {
        let (events, end) = isa::timeline(ISA_BASE, &[op]);
        let (mut edge, mut i) = (isa::FIRST_EDGE_PS, 0);
        while edge <= end {
            while i < events.len() && events[i].0 < edge {
                if let isa::Event::Pins(p, _) = events[i].1 {
                    let t = &mut self.isa_pins;
                    (t.isa_sa, t.isa_sd_in, t.isa_ior_n, t.isa_iow_n) =
                        (p.sa, p.sd_in, p.ior_n, p.iow_n);
                    (t.isa_aen, t.isa_bale) = (p.aen, p.bale);
                }
                i += 1;
            }
            self.edge(&FsmcPins::idle(), false);
            edge += isa::CLOCK_PS;
        }
    }

    /// The PC writes `words` into the shared RAM from word 0 (STATUS with
    /// AUTO_INC, then DATA per word) and rings the DSP (mailbox word).
    pub fn pc_send(&mut self, words: &[u16]) {
        let port = |offset: u16| (u16::from(ISA_BASE) << 2) + offset;
        let write = |port, data| isa::Op::IoWrite {
            port,
            aen: false,
            data,
            command_ns: isa::STANDARD_COMMAND_NS,
        };
        // STATUS: ADDR 0, AUTO_INC (bit 12).
        self.isa(write(port(3), 1 << 12));
        for &w in words {
            self.isa(write(port(0), w));
        }
        self.isa(write(
            port(3),
            (1 << 12) | regmap::ISA_MAILBOX_TO_DSP as u16,
        ));
        self.isa(write(port(0), words.len() as u16));
    }

    fn word(&self, block: &str, index: Option<u32>, reg: &str) -> u16 {
        let b = self.map.block(block);
        let w = match index {
            Some(i) => b.base + b.arrays[0].address(i, reg),
            None => b.base + b.register(reg).offset,
        };
        (w * 2) as u16
    }

    pub fn write(&mut self, block: &str, index: Option<u32>, reg: &str, data: u32) {
        let a = self.word(block, index, reg);
        self.exec(fsmc::Op::Write32 { a, data });
    }

    pub fn read(&mut self, block: &str, index: Option<u32>, reg: &str) -> u32 {
        let a = self.word(block, index, reg);
        let h = self.exec(fsmc::Op::Read32 { a });
        u32::from(h[0]) | u32::from(h[1]) << 16
    }

    /// A RAM window word (A11 = 1), 16-bit access.
    pub fn read_ram(&mut self, word: u16) -> u16 {
        let a = (regmap::MCU_RAM_BYTE_OFFSET / 2) as u16 + word;
        self.exec(fsmc::Op::Read16 { a })[0]
    }

    /// Clocks with the bus idle.
    pub fn idle(&mut self, clocks: u64) {
        for _ in 0..clocks {
            self.edge(&FsmcPins::idle(), false);
        }
    }

    /// Idles until the IRQ pin is active (low: IRQ_CTRL's reset polarity),
    /// at most `limit` clocks; whether it came.
    pub fn wait_irq(&mut self, limit: u64) -> bool {
        for _ in 0..limit {
            if !self.last.irq {
                return true;
            }
            self.idle(1);
        }
        !self.last.irq
    }

    /// Resets the FPGA.
    pub fn reset(&mut self) {
        self.exec(fsmc::Op::Reset);
    }
}
