//! Real firmware against the real Verilog: the C example firmware
//! (`driver/cosim/firmware.c`, on the C driver) linked with the Verilator
//! model of the generated `motion_controller.v` through an FSMC pin adapter
//! (`driver/cosim/harness.cpp`) that drives NE1#/NOE#/NWE#/A/D at the
//! FSMC_BTR1 timing of `motionhdl_regs.h` for every access, with drives,
//! encoders, switches and the e-stop chain on the pins. The same scenarios
//! run here with the Rust driver on the whole-controller simulation (the
//! Rust bus model and board around the same Verilog, Verilated: its
//! rust-hdl twin agrees with it in tests/system.rs) and must print the
//! same lines, clock counts included; the results are also checked against what the
//! scenarios must do. A Verilog with one bit changed, or one register
//! reached at the wrong offset, fails.
//!
//! The configuration is the default with a 1 µs input filter (the
//! default's 1 ms would make the limit and home scenarios 50 times
//! longer); the filter is not part of the register map, so the driver
//! built for the default map accepts it.

use motionhdl_driver::{AxisSample, Card, Causes, Error, Input, Segment, Stream};
use motionhdl_firmware::homing::{Homing, HomingParams};
use motionhdl_firmware::scurve_segments::{plan, EngineLimits};
use motionhdl_hdl::catalog;
use motionhdl_model::Config;
use motionhdl_testbench::bfm::fsmc::Op;
use motionhdl_testbench::c_driver::{self, HOST_LIBS};
use motionhdl_testbench::checks::motion_controller::driver_bus::SETUP_AXIS;
use motionhdl_testbench::checks::motion_controller::system::{Engine, System};
use motionhdl_testbench::harness::require_tools;
use std::fmt::Write;
use std::path::Path;
use std::process::Command;

fn config() -> Config {
    Config::default().with_input_filter_us(1).unwrap()
}

/// The firmware scenarios of firmware.c, line for line, with the Rust
/// driver on the simulated controller.
struct Twin {
    card: Card<System<4>>,
    out: String,
}

fn code(r: Result<(), Error>) -> i32 {
    r.map_or_else(|e| e.code(), |()| 0)
}

fn constant(steps: u32, period: i64) -> Segment {
    Segment {
        steps,
        rate: ((1i64 << 32) / period) as i32,
        accel: 0,
        jerk: 0,
    }
}

impl Twin {
    fn sys(&mut self) -> &mut System<4> {
        self.card.bus()
    }

    fn shaft(&mut self, axis: usize) -> i32 {
        self.sys().drives[axis].position
    }

    fn setup() -> Self {
        let mut sys = System::<4>::on(Engine::for_scenarios(), &config());
        sys.exec(Op::Reset);
        let mut t = Twin {
            card: Card::new(sys),
            out: String::new(),
        };
        let (init, version) = match t.card.check() {
            Ok(v) => (0, v),
            Err(e) => (e.code(), 0),
        };
        let (axes, map) = (motionhdl_driver::AXES, motionhdl_driver::regs::MAP_HASH);
        writeln!(
            t.out,
            "card: init={init} version=0x{version:x} axes={axes} map=0x{map:08x}"
        )
        .unwrap();
        let clear = code(t.card.clear_halt());
        writeln!(t.out, "clear: {clear}").unwrap();
        for i in 0..4 {
            t.card.counter_configure(i, 0).unwrap();
            t.card.axis_configure(i, &SETUP_AXIS).unwrap();
        }
        t
    }

    fn sample(&mut self, name: &str, n: usize) {
        let mut s = [AxisSample::default(); 4];
        self.card.sample(&mut s).unwrap();
        write!(self.out, "{name}:").unwrap();
        for (i, a) in s.iter().enumerate().take(n) {
            let shaft = self.shaft(i);
            write!(self.out, " ax{i}={}/{}/{shaft}", a.position, a.count).unwrap();
        }
        writeln!(self.out).unwrap();
    }

    fn scurve(&mut self) {
        let lim = EngineLimits::from_physical(2.0e6, 4.0e9, 8.0e13, 50.0e6);
        let (px, py) = (plan(1000, lim).unwrap(), plan(-600, lim).unwrap());
        self.card.enable_drives(0x3).unwrap();
        let (mut sx, mut sy) = (Stream::new(0), Stream::new(1));
        sx.refill(&mut self.card, &px.segments).unwrap();
        sy.refill(&mut self.card, &py.segments).unwrap();
        self.card.start(0x3).unwrap();
        let t0 = self.sys().clocks;
        let mut polls = 0;
        loop {
            polls += 1;
            if polls == 1000 {
                self.sample("moving", 2);
            }
            let done = self.card.move_done(0).unwrap() && self.card.move_done(1).unwrap();
            if done || polls >= 10000 {
                break;
            }
        }
        let clocks = self.sys().clocks - t0;
        let (nx, ny) = (px.segments.len(), py.segments.len());
        writeln!(
            self.out,
            "scurve: segments={nx},{ny} polls={polls} clocks={clocks}"
        )
        .unwrap();
        self.sys().idle(20);
        self.sample("after", 2);
    }

    fn irq_stream(&mut self) {
        let segs = vec![constant(3, 30); 100];
        let masks = Causes {
            fifo_low: 0x4,
            done: 0x4,
            ..Causes::default()
        };
        self.card.irq_configure(&masks, false);
        let mut s = Stream::new(2);
        let mut pushed = s.refill(&mut self.card, &segs).unwrap();
        self.card.start(0x4).unwrap();
        let t0 = self.sys().clocks;
        let mut irqs = 0;
        loop {
            let mut waited = 0;
            while self.sys().irq() && waited < 200_000 {
                self.sys().idle(1);
                waited += 1;
            }
            if waited == 200_000 {
                break;
            }
            irqs += 1;
            let c = self.card.causes();
            if c.fifo_low & 0x4 != 0 {
                pushed = s.refill(&mut self.card, &segs).unwrap();
            }
            self.card.clear_causes(&c);
            if c.done & 0x4 != 0 && pushed {
                break;
            }
        }
        let clocks = self.sys().clocks - t0;
        writeln!(
            self.out,
            "irq: interrupts={irqs} pushed={} clocks={clocks}",
            s.next
        )
        .unwrap();
        self.card.irq_configure(&Causes::default(), false);
        self.sys().idle(20);
        self.sample("irq", 3);
    }

    fn limit_stop(&mut self) {
        let at = self.shaft(0) + 20;
        self.sys().limit_pos_at[0] = Some(at);
        self.card
            .input_configure(Input::LimitPos, 0x1, 0x0)
            .unwrap();
        self.card.push_segment(0, &constant(40, 200)).unwrap();
        self.card.start(0x1).unwrap();
        self.sys().idle(10000);
        let c = self.card.causes();
        let irq = u8::from(self.sys().irq());
        writeln!(self.out, "limit: cause=0x{:x} irq={irq}", c.limit).unwrap();
        self.sample("limit", 1);
    }

    fn estop(&mut self) {
        let s = constant(200, 100);
        self.card.push_segment(2, &s).unwrap();
        self.card.push_segment(3, &s).unwrap();
        self.card.enable_drives(0xc).unwrap();
        self.card.start(0xc).unwrap();
        self.sys().idle(5000);
        self.sys().estop_ok = false;
        self.sys().idle(200);
        let status = self.card.safety_status();
        let held = code(self.card.clear_halt());
        let enable = self.sys().drive_enable();
        writeln!(
            self.out,
            "estop: status=0x{status:x} enable=0x{enable:x} clear={held}"
        )
        .unwrap();
        self.sys().estop_ok = true;
        self.sys().idle(100);
        let cleared = code(self.card.clear_halt());
        let enable = self.sys().drive_enable();
        writeln!(self.out, "released: clear={cleared} enable=0x{enable:x}").unwrap();
        self.sample("estop", 4);
    }

    fn watchdog(&mut self) {
        self.card.enable_drives(0xf).unwrap();
        self.card.watchdog_arm(3000);
        for _ in 0..3 {
            self.sys().idle(1000);
            self.card.watchdog_feed();
        }
        self.sys().idle(4000);
        let status = self.card.safety_status();
        let cause = self.card.causes().card;
        let enable = self.sys().drive_enable();
        writeln!(
            self.out,
            "watchdog: status=0x{status:x} enable=0x{enable:x} cause=0x{cause:x}"
        )
        .unwrap();
        self.card.watchdog_arm(0);
        let clear = code(self.card.clear_halt());
        writeln!(self.out, "recovered: clear={clear}").unwrap();
    }

    fn homing(&mut self) {
        let params = HomingParams {
            toward: 1,
            fast_period: 60,
            slow_period: 400,
            max_travel: 200,
            backoff: 20,
            index: true,
        };
        let at = self.shaft(1) + 60;
        self.sys().home_at[1] = Some(at);
        self.sys().index_every[1] = Some(25);
        let mut homing = Homing::new(params).unwrap();
        let found = loop {
            self.sys().idle(300);
            match self.card.home_poll(&mut homing, 1) {
                Ok(None) => {}
                other => break other,
            }
        };
        let shaft = self.shaft(1);
        let line = match found {
            Ok(Some(h)) => format!(
                "homing: rc=0 position={} count={} index={}/{} shaft={shaft}",
                h.position,
                h.count,
                h.index.unwrap_or(0),
                u8::from(h.index.is_some())
            ),
            Err(e) => format!(
                "homing: rc={} position=0 count=0 index=0/0 shaft={shaft}",
                e.code()
            ),
            Ok(None) => unreachable!(),
        };
        writeln!(self.out, "{line}").unwrap();
    }
}

fn rust_run() -> String {
    let mut t = Twin::setup();
    t.scurve();
    t.irq_stream();
    t.limit_stop();
    t.estop();
    t.watchdog();
    t.homing();
    let clocks = t.sys().clocks;
    writeln!(t.out, "end: clocks={clocks}").unwrap();
    t.out
}

fn run(cmd: &mut Command, what: &str) -> String {
    let o = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{what}:\n{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    text
}

/// Builds the co-simulation of `verilog` with the C firmware in `dir` and
/// runs it: its standard output.
fn c_run(dir: &Path, verilog: &str, lib: &Path) -> String {
    let root = c_driver::root();
    let includes = ["driver/include", "generated/include", "driver/cosim"].map(|d| root.join(d));
    std::fs::write(dir.join("motion_controller.v"), verilog).unwrap();
    let mut gcc = Command::new("gcc");
    gcc.args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2", "-c"]);
    for i in &includes {
        gcc.arg("-I").arg(i);
    }
    let firmware = dir.join("firmware.o");
    run(
        gcc.arg(root.join("driver/cosim/firmware.c"))
            .arg("-o")
            .arg(&firmware),
        "gcc firmware.c",
    );
    let cflags: Vec<String> = includes
        .iter()
        .map(|i| format!("-I{}", i.display()))
        .collect();
    let mut v = Command::new("verilator");
    motionhdl_testbench::harness::cache_verilator_build(&mut v);
    v.current_dir(dir)
        .args(["--cc", "--exe", "--build", "-j", "2", "-Wno-fatal", "-O2"])
        .args([
            "--top-module",
            "motion_controller",
            "-Mdir",
            "obj",
            "-o",
            "cosim",
        ])
        .arg("-CFLAGS")
        .arg(format!("{} -std=c++17 -O1", cflags.join(" ")))
        .arg("-LDFLAGS")
        .arg(HOST_LIBS.join(" "))
        .arg(dir.join("motion_controller.v"))
        .arg(root.join("driver/cosim/harness.cpp"))
        .arg(&firmware)
        .arg(lib);
    run(&mut v, "verilator");
    run(
        &mut Command::new(dir.join("obj/cosim")),
        "the co-simulation",
    )
}

/// What the scenarios must do, whatever either simulation says.
fn check_results(out: &str) {
    let line = |prefix: &str| {
        out.lines()
            .find(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no `{prefix}` line in\n{out}"))
    };
    assert_eq!(
        line("card:"),
        "card: init=0 version=0x100 axes=4 map=0x64b357b8"
    );
    assert_eq!(line("clear:"), "clear: 0");
    assert_eq!(
        line("after:"),
        "after: ax0=1000/1000/1000 ax1=-600/-600/-600"
    );
    assert!(
        line("moving:").contains("ax0=") && !line("moving:").contains("ax0=0/"),
        "{out}"
    );
    assert_eq!(
        line("limit: cause"),
        "limit: cause=0x1 irq=1",
        "LIMIT_CAUSE.POS for axis 0"
    );
    // Stopped on the switch at 1020, within the filter's few steps.
    let stopped: i32 = line("limit: ax0")
        .rsplit('/')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((1020..1024).contains(&stopped), "{out}");
    assert_eq!(line("estop:"), "estop: status=0x3 enable=0x0 clear=-6");
    assert_eq!(line("released:"), "released: clear=0 enable=0x0");
    assert!(
        line("watchdog:").starts_with("watchdog: status=0x4 enable=0x0 cause=0x3"),
        "{out}"
    );
    assert_eq!(line("recovered:"), "recovered: clear=0");
    let homing = line("homing:");
    assert!(
        homing.starts_with("homing: rc=0 position=") && homing.contains("/1 shaft="),
        "{out}"
    );
}

#[test]
fn c_firmware_on_the_verilog_gives_the_rust_results() {
    if require_tools(&["gcc", "g++", "verilator", "make"]).is_none() {
        return;
    }
    let config = config();
    let module = catalog::motion_controller(&config);
    let lib = c_driver::driver_lib(None).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let c = c_run(dir.path(), &module.text, &lib);
    let rust = rust_run();
    check_results(&rust);
    assert_eq!(
        c, rust,
        "C firmware on Verilator vs the Rust driver on rust-hdl"
    );
    println!("{c}");
    // The firmware's SEG_RATE writes of axis 0 landing on SEG_ACCEL, as
    // from a driver with that offset wrong: the S-curve goes astray.
    let misrouted = run(
        Command::new(dir.path().join("obj/cosim")).env("MOTIONHDL_COSIM_MISROUTE", "85c:860"),
        "the co-simulation, misrouted",
    );
    assert!(
        !misrouted.contains("after: ax0=1000/1000/1000 "),
        "{misrouted}"
    );
    // One bit of the card's identity changed in the Verilog: the firmware
    // finds no card, and every line after the check differs.
    let magic = "32'h4d48444c";
    assert_eq!(module.text.matches(magic).count(), 1, "the MAGIC constant");
    let broken = tempfile::tempdir().unwrap();
    let c = c_run(
        broken.path(),
        &module.text.replace(magic, "32'h4d48444d"),
        &lib,
    );
    assert!(c.starts_with("card: init=-1 "), "{c}");
}
