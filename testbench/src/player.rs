//! One generic player for timed pin-event streams: the bus-functional models
//! in `bfm/` describe every cycle as pin changes at exact times, and
//! this module replays such a stream through any Verilog design in Icarus
//! or Verilator. The testbench it writes is derived from the design's ports
//! (as the exporter reports them) and from the ANSI port headers of the
//! peripheral models it wires beside the design, so no bus is modelled in
//! Verilog and no port is retyped.
//!
//! Every port is a net named as the port, with exactly one driver: the
//! stream, a constant, another net (a loop-back), the design or a
//! peripheral. The player checks that before it writes anything.

use crate::verilog_sim::{build_and_run, named_instance, net_declaration, Simulator};
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_hdl::ports::{Port, PortDir};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;

/// One step of a stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Row {
    /// At `at` ticks, set every driven net (in [`PinStream::driven`] order).
    Drive { at: u64, values: Vec<u64> },
    /// At `at` ticks, print every sampled net.
    Sample { at: u64 },
}

impl Row {
    pub fn at(&self) -> u64 {
        match self {
            Row::Drive { at, .. } | Row::Sample { at } => *at,
        }
    }

    fn at_mut(&mut self) -> &mut u64 {
        match self {
            Row::Drive { at, .. } | Row::Sample { at } => at,
        }
    }
}

/// A bus-functional model's output: what to drive when, and when to look.
#[derive(Clone, Debug, Default)]
pub struct PinStream {
    /// Nets the stream drives, in the order of each drive row's values.
    pub driven: Vec<String>,
    /// Rows in time order.
    pub rows: Vec<Row>,
    /// The run ends at this time.
    pub end: u64,
}

impl PinStream {
    /// A bus model's timed events as a stream over the nets `driven`:
    /// `drive` gives an event's values, or `None` for a sample point.
    pub fn from_events<E>(
        driven: &[&str],
        events: &[(u64, E)],
        end: u64,
        drive: impl Fn(&E) -> Option<Vec<u64>>,
    ) -> Self {
        let rows = events
            .iter()
            .map(|(at, e)| match drive(e) {
                Some(values) => Row::Drive { at: *at, values },
                None => Row::Sample { at: *at },
            })
            .collect();
        Self {
            driven: driven.iter().map(|s| s.to_string()).collect(),
            rows,
            end,
        }
    }

    /// Every time shifted `ticks` later (the initial drive stays at 0).
    pub fn delayed(mut self, ticks: u64) -> Self {
        for (i, r) in self.rows.iter_mut().enumerate() {
            let at = r.at_mut();
            if i > 0 || *at > 0 {
                *at += ticks;
            }
        }
        self.end += ticks;
        self
    }

    /// Every driven net renamed by `rename` (a bus whose pins carry a
    /// prefix on a bigger design).
    pub fn renamed(mut self, rename: impl Fn(&str) -> String) -> Self {
        for n in &mut self.driven {
            *n = rename(n);
        }
        self
    }
}

/// The free-running clock the player generates.
#[derive(Clone, Copy, Debug)]
pub struct ClockSpec {
    /// Period in ticks; low for the first half, so rising edges fall at
    /// `period / 2 + k * period`.
    pub period: u64,
    /// Ticks per nanosecond of every time in the stream.
    pub ticks_per_ns: u64,
}

impl ClockSpec {
    fn is_rising_edge(&self, t: u64) -> bool {
        t % self.period == self.period / 2
    }
}

/// A Verilog model placed beside the design (a test slave, a RAM chip).
/// Its ports come from its ANSI header; each connects to the net of the
/// same name.
#[derive(Clone, Debug)]
pub struct Peripheral {
    pub module: String,
    pub file: String,
    pub text: String,
    pub ports: Vec<Port>,
}

impl Peripheral {
    /// `text` holds module `module` with an ANSI port list; panics naming
    /// the line it cannot read.
    pub fn new(module: &str, file: &str, text: &str) -> Self {
        Self {
            module: module.into(),
            file: file.into(),
            text: text.into(),
            ports: ansi_ports(text, module),
        }
    }
}

/// The design and everything around it.
#[derive(Clone, Debug)]
pub struct Rig {
    /// Module name and ports of the design under test.
    pub dut: String,
    pub dut_ports: Vec<Port>,
    /// Its Verilog text (generated, or a netlist of it).
    pub dut_text: String,
    /// The net the clock drives.
    pub clock_net: String,
    pub clock: ClockSpec,
    pub peripherals: Vec<Peripheral>,
    /// Nets held at a constant.
    pub ties: Vec<(String, u64)>,
    /// Nets that follow another net: (driven, source).
    pub loops: Vec<(String, String)>,
    /// Nets each sample row prints, in this order.
    pub sampled: Vec<String>,
}

impl Rig {
    /// `module` (its ports, and `text`: the generated Verilog or a netlist
    /// of it) clocked on its `clock` input, with nothing around it yet.
    pub fn new(module: &VerilogModule, text: String, clock: ClockSpec) -> Self {
        Self {
            dut: module.name.into(),
            dut_ports: module.ports.clone(),
            dut_text: text,
            clock_net: "clock".into(),
            clock,
            peripherals: Vec::new(),
            ties: Vec::new(),
            loops: Vec::new(),
            sampled: Vec::new(),
        }
    }
}

/// Who drives a net.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Driver {
    Clock,
    Stream(usize),
    Tie(u64),
    Loop(String),
    Instance(String),
}

struct Net {
    width: u32,
    driver: Option<Driver>,
    /// Read by an instance input.
    loads: bool,
}

impl Rig {
    /// Every net with its width and driver; panics naming a net with no
    /// driver, two drivers, or two widths.
    fn nets(&self, stream: &PinStream) -> BTreeMap<String, Net> {
        let mut nets: BTreeMap<String, Net> = BTreeMap::new();
        let instances = std::iter::once((self.dut.as_str(), &self.dut_ports)).chain(
            self.peripherals
                .iter()
                .map(|p| (p.module.as_str(), &p.ports)),
        );
        for (inst, ports) in instances {
            for p in ports {
                assert_ne!(p.dir, PortDir::InOut, "{inst}.{}: inout", p.name);
                let net = nets.entry(p.name.clone()).or_insert(Net {
                    width: p.width,
                    driver: None,
                    loads: false,
                });
                assert_eq!(net.width, p.width, "net {} has two widths", p.name);
                if p.dir == PortDir::Output {
                    set_driver(net, &p.name, Driver::Instance(inst.into()));
                } else {
                    net.loads = true;
                }
            }
        }
        let mut drive = |name: &str, d: Driver| {
            let net = nets
                .get_mut(name)
                .unwrap_or_else(|| panic!("no port or peripheral pin `{name}`"));
            set_driver(net, name, d);
        };
        drive(&self.clock_net, Driver::Clock);
        for (i, n) in stream.driven.iter().enumerate() {
            drive(n, Driver::Stream(i));
        }
        for (n, v) in &self.ties {
            drive(n, Driver::Tie(*v));
        }
        for (n, src) in &self.loops {
            drive(n, Driver::Loop(src.clone()));
        }
        for (name, net) in &nets {
            assert!(
                net.driver.is_some() || !net.loads,
                "net `{name}` is read but nothing drives it"
            );
        }
        for s in &self.sampled {
            assert!(nets.contains_key(s), "cannot sample `{s}`: no such net");
        }
        nets
    }

    /// The player testbench (module `motionhdl_player`) for `stream`, which
    /// it reads from `rows.hex`.
    pub fn testbench(&self, stream: &PinStream) -> String {
        self.testbench_for(&self.nets(stream), stream)
    }

    fn testbench_for(&self, nets: &BTreeMap<String, Net>, stream: &PinStream) -> String {
        let width = |n: &str| nets[n].width;
        let row_bits = row_bits(stream, &width);
        let mut t = String::new();
        let _ = writeln!(
            t,
            "// Pin-event player for {} (motionhdl).\n`timescale 1ns / 1ps\n\
             `default_nettype none\nmodule motionhdl_player;",
            self.dut
        );
        for (name, net) in nets {
            let (kind, init) = match net.driver {
                Some(Driver::Clock) | Some(Driver::Stream(_)) => ("reg", " = 0"),
                _ => ("wire", ""),
            };
            t.push_str(&net_declaration(kind, net.width, name, init));
        }
        // Constants and loop-backs after every declaration.
        for (name, net) in nets {
            match &net.driver {
                Some(Driver::Tie(v)) => {
                    let _ = writeln!(t, "    assign {name} = {}'h{v:x};", net.width);
                }
                Some(Driver::Loop(src)) => {
                    let _ = writeln!(t, "    assign {name} = {src};");
                }
                _ => {}
            }
        }
        let half_ns = self.clock.period as f64 / 2.0 / self.clock.ticks_per_ns as f64;
        let _ = writeln!(
            t,
            "    always #({half_ns:?}) {} = ~{};",
            self.clock_net, self.clock_net
        );
        let instances = std::iter::once((&self.dut, &self.dut_ports, "dut".to_string())).chain(
            self.peripherals
                .iter()
                .enumerate()
                .map(|(i, p)| (&p.module, &p.ports, format!("peripheral_{i}"))),
        );
        for (module, ports, inst) in instances {
            t.push_str(&named_instance(module, &inst, ports));
        }
        self.player_loop(&mut t, stream, row_bits, &width);
        t
    }

    fn player_loop(
        &self,
        t: &mut String,
        stream: &PinStream,
        row_bits: u32,
        width: &dyn Fn(&str) -> u32,
    ) {
        let _ = writeln!(
            t,
            "    localparam real TICKS_PER_NS = {:?};",
            self.clock.ticks_per_ns as f64
        );
        let _ = writeln!(
            t,
            "    reg [{}:0] rows [0:{}];",
            row_bits - 1,
            stream.rows.len().max(1) - 1
        );
        let _ = writeln!(t, "    reg [{}:0] row;\n    integer i;", row_bits - 1);
        let _ = writeln!(t, "    task automatic wait_until(input [63:0] when);");
        let _ = writeln!(
            t,
            "        #((when * 1.0) / TICKS_PER_NS - $realtime);\n    endtask"
        );
        let _ = writeln!(
            t,
            "    initial begin\n        $readmemh(\"rows.hex\", rows);"
        );
        let _ = writeln!(
            t,
            "        for (i = 0; i < {}; i = i + 1) begin",
            stream.rows.len()
        );
        let _ = writeln!(
            t,
            "            row = rows[i];\n            wait_until(row[{}:{}]);",
            row_bits - 1,
            row_bits - 64
        );
        let _ = writeln!(t, "            if (row[{}]) begin", row_bits - 65);
        let mut hi = row_bits - 65;
        for n in &stream.driven {
            let lo = hi - width(n);
            let _ = writeln!(t, "                {n} = row[{}:{lo}];", hi - 1);
            hi = lo;
        }
        let fmt = vec!["%h"; self.sampled.len()].join(" ");
        let _ = writeln!(t, "            end else begin");
        let _ = writeln!(
            t,
            "                $display(\"S {fmt}\", {});",
            self.sampled.join(", ")
        );
        let _ = writeln!(t, "            end\n        end");
        let _ = writeln!(
            t,
            "        wait_until(64'd{});\n        $display(\"DONE\");",
            stream.end
        );
        let _ = writeln!(
            t,
            "        $finish;\n    end\nendmodule\n`default_nettype wire"
        );
    }

    /// Plays `stream` in `sim`: one value per sampled net per sample row,
    /// `None` where the net held X or Z.
    pub fn play(
        &self,
        sim: Simulator,
        stream: &PinStream,
    ) -> Result<Vec<Vec<Option<u64>>>, String> {
        self.check_timing(stream);
        sim.available()?;
        let nets = self.nets(stream);
        let width = |n: &str| nets[n].width;
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let d = dir.path();
        let write =
            |name: &str, text: &str| fs::write(d.join(name), text).map_err(|e| e.to_string());
        write("player.v", &self.testbench_for(&nets, stream))?;
        write("dut.v", &self.dut_text)?;
        let mut files = vec!["player.v", "dut.v"];
        for p in &self.peripherals {
            write(&p.file, &p.text)?;
            files.push(&p.file);
        }
        write("rows.hex", &rows_hex(stream, &width))?;
        let (stdout, _) = build_and_run(sim, d, "motionhdl_player", &files, true)?;
        if !stdout.lines().any(|l| l == "DONE") {
            return Err(format!("player did not finish:\n{stdout}"));
        }
        let samples: Vec<Vec<Option<u64>>> = stdout
            .lines()
            .filter_map(|l| l.strip_prefix("S ").or((l == "S").then_some("")))
            .map(|l| {
                l.split_whitespace()
                    .map(|x| u64::from_str_radix(x, 16).ok())
                    .collect()
            })
            .collect();
        let want = stream
            .rows
            .iter()
            .filter(|r| matches!(r, Row::Sample { .. }))
            .count();
        if samples.len() != want || samples.iter().any(|s| s.len() != self.sampled.len()) {
            return Err(format!(
                "expected {want} samples of {} nets, got:\n{stdout}",
                self.sampled.len()
            ));
        }
        Ok(samples)
    }

    /// The stream keeps the promises that make a zero-delay replay exact:
    /// rows in time order, no drive on a rising clock edge, no sample at
    /// the time of a drive (it would race the design's settling).
    fn check_timing(&self, stream: &PinStream) {
        let mut last_drive = None;
        let mut last = 0;
        for r in &stream.rows {
            assert!(r.at() >= last, "rows out of order at {}", r.at());
            last = r.at();
            match r {
                Row::Drive { at, values } => {
                    assert_eq!(
                        values.len(),
                        stream.driven.len(),
                        "one value per driven net"
                    );
                    assert!(
                        !self.clock.is_rising_edge(*at),
                        "a drive at {at} races a clock edge"
                    );
                    last_drive = Some(*at);
                }
                Row::Sample { at } => {
                    assert_ne!(last_drive, Some(*at), "a sample at {at} races a drive");
                }
            }
        }
        assert!(stream.end >= last, "the stream ends before its last row");
    }
}

fn set_driver(net: &mut Net, name: &str, d: Driver) {
    if let Some(old) = &net.driver {
        panic!("net `{name}` has two drivers: {old:?} and {d:?}");
    }
    net.driver = Some(d);
}

fn row_bits(stream: &PinStream, width: &dyn Fn(&str) -> u32) -> u32 {
    64 + 1 + stream.driven.iter().map(|n| width(n)).sum::<u32>()
}

/// `rows.hex`: per row the time (64 bits), drive flag, then every driven
/// value, most significant first.
fn rows_hex(stream: &PinStream, width: &dyn Fn(&str) -> u32) -> String {
    let mut hex = String::new();
    for r in &stream.rows {
        let mut fields = vec![(64, r.at())];
        match r {
            Row::Drive { values, .. } => {
                fields.push((1, 1));
                for (n, v) in stream.driven.iter().zip(values) {
                    fields.push((width(n), *v));
                }
            }
            Row::Sample { .. } => {
                fields.push((1, 0));
                fields.extend(stream.driven.iter().map(|n| (width(n), 0)));
            }
        }
        hex.push_str(&crate::verilog_sim::pack_hex(&fields));
        hex.push('\n');
    }
    hex
}

/// The ports of `module` in `text`, an ANSI header of one port per line
/// (`input wire [15:0] name,`). Panics naming a line it cannot read.
pub fn ansi_ports(text: &str, module: &str) -> Vec<Port> {
    let start = text
        .lines()
        .position(|l| l.trim_start().starts_with(&format!("module {module}")))
        .unwrap_or_else(|| panic!("no `module {module}` header"));
    let mut ports = Vec::new();
    for (n, line) in text.lines().enumerate().skip(start + 1) {
        let l = line.split("//").next().unwrap_or("").trim();
        if l.is_empty() {
            continue;
        }
        if l.starts_with(");") {
            return ports;
        }
        let words: Vec<&str> = l.trim_end_matches(',').split_whitespace().collect();
        let bad = || -> ! { panic!("line {}: cannot read port `{line}`", n + 1) };
        let dir = match words.first() {
            Some(&"input") => PortDir::Input,
            Some(&"output") => PortDir::Output,
            _ => bad(),
        };
        let rest: Vec<&str> = words[1..]
            .iter()
            .copied()
            .filter(|w| !matches!(*w, "wire" | "reg"))
            .collect();
        let (width, name) = match rest.as_slice() {
            [name] => (1, *name),
            [range, name] => {
                let hi = range
                    .strip_prefix('[')
                    .and_then(|r| r.strip_suffix(":0]"))
                    .and_then(|h| h.parse::<u32>().ok())
                    .unwrap_or_else(|| bad());
                (hi + 1, *name)
            }
            _ => bad(),
        };
        ports.push(Port {
            name: name.into(),
            dir,
            width,
            signed: false,
        });
    }
    panic!("module {module}: port list does not end with `);`")
}
