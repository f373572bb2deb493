//! Clean Verilog export.
//!
//! rust-hdl 0.46 emits every module as `top` or `top$path`, puts `$` in signal
//! names, sizes every integer literal at 32 bits, and gives each flip-flop its
//! own module whose clock is assigned inside the parent's `always @(*)` block
//! (a delta-cycle race that simulators may resolve differently). This module
//! rewrites that output so that:
//!
//! * each block becomes one self-contained module named after it, its
//!   children inlined with hierarchical signal names (`chip_y1`), so every
//!   generated file can be read into one project and Verilator's
//!   DECLFILENAME lint holds;
//! * flip-flops are inlined as `always @(posedge clock)` in their parent, the
//!   clock wired straight to them;
//! * no identifier contains `$`;
//! * integer literals take the width of what they are assigned to or
//!   compared with, so `verilator --lint-only -Wall` sees no WIDTH mismatch.
//!
//! Anything outside the patterns rust-hdl emits for our blocks is a panic
//! naming the line, never a silent mistranslation.
//!
//! # The rust-hdl subset it accepts
//!
//! What `generate_verilog` emits for blocks built from these, and nothing
//! else:
//!
//! * `#[derive(LogicBlock)]` structs of `Signal<In|Out|Local, Bit|Bits<N>|
//!   Signed<N>|Clock>` fields, `Constant`s (emitted as `localparam`) and
//!   child blocks, with one `#[hdl_gen] fn update`: the parent's lines are
//!   `module` headers, `input`/`output` `wire`/`reg` declarations (optionally
//!   `signed`, ranges ending at 0), `reg`/`wire` locals, `localparam`s, one
//!   `always @(*) begin … end` body and child instances with one
//!   `.port(net)` per line;
//! * `DFF<T>` children (rust-hdl's `dff_setup!`), recognised by shape
//!   (`always @(posedge clock)`, `q <= d;`, a sized initial value) and
//!   inlined as flops in the parent;
//! * `RAM<T, N>` children with one read and one write port, recognised by
//!   shape and inlined as a `reg` array;
//! * integer literals only where their width follows from the signal they
//!   are assigned to, compared with or combined with, or from a slice.
//!
//! Nesting inside an `always` body is counted on `begin`/`end` tokens, so
//! a signal named `begin_x` or `end_y` is an ordinary identifier.

use regex::Regex;
use rust_hdl::prelude::{generate_verilog, Block};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;

/// Exports `uut` (already `connect_all`ed) as Verilog whose top module is
/// `name`. `banner` lines are written first, each as a `//` comment.
pub fn export<B: Block>(uut: &B, name: &str, banner: &[String]) -> String {
    let raw = generate_verilog(uut);
    let body = rewrite(&raw, name);
    let mut out = String::new();
    for line in banner {
        out.push_str("// ");
        out.push_str(line);
        out.push('\n');
    }
    out.push_str("`timescale 1ns / 1ps\n`default_nettype none\n");
    out.push_str(&body);
    out.push_str("\n`default_nettype wire\n");
    out
}

struct RawModule {
    name: String,
    args: Vec<String>,
    lines: Vec<String>,
}

struct Dff {
    init: String,
}

fn re(cell: &'static OnceLock<Regex>, pat: &str) -> &'static Regex {
    cell.get_or_init(|| Regex::new(pat).expect("valid regex"))
}

fn parse_modules(raw: &str) -> Vec<RawModule> {
    static HEADER: OnceLock<Regex> = OnceLock::new();
    let header = re(&HEADER, r"^module ([\w$]+)\(([^)]*)\);$");
    let mut modules = Vec::new();
    let mut current: Option<RawModule> = None;
    for line in raw.lines() {
        if let Some(c) = header.captures(line) {
            assert!(current.is_none(), "nested module at `{line}`");
            current = Some(RawModule {
                name: c[1].to_string(),
                args: c[2]
                    .split(',')
                    .map(|s| s.trim().to_string())
                    .filter(|s| !s.is_empty())
                    .collect(),
                lines: Vec::new(),
            });
        } else if line.starts_with("endmodule") {
            modules.push(current.take().expect("endmodule without module"));
        } else if let Some(m) = current.as_mut() {
            m.lines.push(line.trim_end().to_string());
        } else {
            assert!(line.trim().is_empty(), "text outside a module: `{line}`");
        }
    }
    assert!(current.is_none(), "unterminated module");
    modules
}

/// Recognises rust-hdl's `DFF` module and returns its initial value.
fn as_dff(m: &RawModule) -> Option<Dff> {
    static INIT: OnceLock<Regex> = OnceLock::new();
    let init = re(&INIT, r"^\s*q = (\d+'[hb][0-9a-f]+);$");
    if m.args != ["d", "q", "clock"] {
        return None;
    }
    let code: Vec<&str> = m
        .lines
        .iter()
        .map(|l| l.trim())
        .filter(|l| !l.is_empty())
        .collect();
    let shape_ok = code.contains(&"// Update code (custom)")
        && code.contains(&"always @(posedge clock) begin")
        && code.contains(&"q <= d;");
    if !shape_ok {
        return None;
    }
    let init = m.lines.iter().find_map(|l| init.captures(l))?[1].to_string();
    Some(Dff { init })
}

/// rust-hdl's `RAM` widget: one synchronous read port, one write port.
#[derive(Clone, Copy)]
struct RamShape {
    width: usize,
    depth: usize,
}

/// Recognises rust-hdl's `RAM` module (without initial contents).
fn as_ram(m: &RawModule) -> Option<RamShape> {
    static MEM: OnceLock<Regex> = OnceLock::new();
    let mem = re(&MEM, r"^reg\[(\d+):0\] mem\[(\d+):0\];$");
    let ports = [
        "read_address",
        "read_clock",
        "read_data",
        "write_address",
        "write_clock",
        "write_data",
        "write_enable",
    ];
    if m.args != ports {
        return None;
    }
    let code: Vec<&str> = m
        .lines
        .iter()
        .map(|l| l.trim())
        .filter(|l| !l.is_empty())
        .collect();
    assert!(
        !code.iter().any(|l| l.starts_with("initial")),
        "RAM {} has initial contents; the exporter does not carry them",
        m.name
    );
    let shape_ok = code.contains(&"always @(posedge read_clock) begin")
        && code.contains(&"read_data <= mem[read_address];")
        && code.contains(&"always @(posedge write_clock) begin")
        && code.contains(&"if (write_enable) begin")
        && code.contains(&"mem[write_address] <= write_data;");
    if !shape_ok {
        return None;
    }
    let c = code.iter().find_map(|l| mem.captures(l))?;
    Some(RamShape {
        width: c[1].parse::<usize>().ok()? + 1,
        depth: c[2].parse::<usize>().ok()? + 1,
    })
}

/// An inlined RAM: its memory array name and its port nets.
#[derive(Clone)]
struct Mem {
    name: String,
    shape: RamShape,
    read_clock: String,
    read_address: String,
    read_data: String,
    write_clock: String,
    write_address: String,
    write_data: String,
    write_enable: String,
}

/// An instance as rust-hdl writes it: `kind name(` then `.port(sig),` lines then `);`.
struct Instance {
    kind: String,
    name: String,
    ports: Vec<(String, String)>,
    first_line: usize,
    last_line: usize,
}

fn instances(lines: &[String]) -> Vec<Instance> {
    static OPEN: OnceLock<Regex> = OnceLock::new();
    let open = re(&OPEN, r"^\s*([\w$]+) ([\w$]+)\($");
    static PORT: OnceLock<Regex> = OnceLock::new();
    let port = re(&PORT, r"^\s*\.(\w+)\(([\w$]+)\),?$");
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if let Some(c) = open.captures(&lines[i]) {
            let mut inst = Instance {
                kind: c[1].to_string(),
                name: c[2].to_string(),
                ports: Vec::new(),
                first_line: i,
                last_line: i,
            };
            i += 1;
            while lines[i].trim() != ");" {
                let p = port
                    .captures(&lines[i])
                    .unwrap_or_else(|| panic!("unexpected port line `{}`", lines[i]));
                inst.ports.push((p[1].to_string(), p[2].to_string()));
                i += 1;
            }
            inst.last_line = i;
            out.push(inst);
        }
        i += 1;
    }
    out
}

fn rewrite(raw: &str, top: &str) -> String {
    let modules: BTreeMap<String, RawModule> = parse_modules(raw)
        .into_iter()
        .map(|m| (m.name.clone(), m))
        .collect();
    let dffs: BTreeMap<String, Dff> = modules
        .values()
        .filter_map(|m| as_dff(m).map(|d| (m.name.clone(), d)))
        .collect();
    let rams: BTreeMap<String, RamShape> = modules
        .values()
        .filter_map(|m| as_ram(m).map(|r| (m.name.clone(), r)))
        .collect();
    let root = modules
        .get("top")
        .expect("rust-hdl output has a top module");
    let mut flat = flatten(root, &modules, &dffs, &rams);
    resolve_flop_clocks(&mut flat, &root.args);
    render(top, root, &flat)
}

/// A module with every child inlined: its own declarations, one
/// combinational block per original module, and its flip-flops.
#[derive(Default)]
struct Flat {
    /// (kind, width, name, init) for every non-port net, in order.
    nets: Vec<Net>,
    /// Width of every port and net, by name.
    widths: BTreeMap<String, usize>,
    /// This module's ports: declared kind (`input wire`, `output reg`, …)
    /// and signedness, by name.
    ports: BTreeMap<String, (String, bool)>,
    /// Local parameters: (name, value).
    params: Vec<(String, String)>,
    /// Combinational blocks, each a list of statement lines (unindented).
    comb: Vec<Vec<String>>,
    /// Flip-flops: (clock, q, d).
    flops: Vec<(String, String, String)>,
    /// Inlined RAMs.
    mems: Vec<Mem>,
}

#[derive(Clone)]
struct Net {
    width: usize,
    signed: bool,
    name: String,
    init: Option<String>,
}

fn flatten(
    m: &RawModule,
    modules: &BTreeMap<String, RawModule>,
    dffs: &BTreeMap<String, Dff>,
    rams: &BTreeMap<String, RamShape>,
) -> Flat {
    static DECL: OnceLock<Regex> = OnceLock::new();
    let decl = re(
        &DECL,
        r"^(input wire|output reg|output wire|inout wire|reg|wire)\s+(signed\s+)?(?:\[(\d+):0\]\s+)?([\w$]+);$",
    );
    static PARAM: OnceLock<Regex> = OnceLock::new();
    let param = re(
        &PARAM,
        r"^localparam\s+(?:signed\s+)?([\w$]+) = (\d+'[hb][0-9a-f]+);$",
    );
    let mut flat = Flat::default();
    let insts = instances(&m.lines);
    let in_instance = |i: usize| {
        insts
            .iter()
            .any(|n| (n.first_line..=n.last_line).contains(&i))
    };
    let mut i = 0;
    while i < m.lines.len() {
        let line = m.lines[i].trim();
        if line.is_empty() || line.starts_with("//") || in_instance(i) {
        } else if let Some(c) = decl.captures(line) {
            let width = c
                .get(3)
                .map_or(1, |w| w.as_str().parse::<usize>().unwrap() + 1);
            let name = c[4].to_string();
            flat.widths.insert(name.clone(), width);
            let signed = c.get(2).is_some();
            if c[1].starts_with("input") || c[1].starts_with("output") || c[1].starts_with("inout")
            {
                flat.ports.insert(name, (c[1].to_string(), signed));
            } else {
                flat.nets.push(Net {
                    width,
                    signed,
                    name,
                    init: None,
                });
            }
        } else if let Some(c) = param.captures(line) {
            let w: usize = c[2].split('\'').next().unwrap().parse().unwrap();
            flat.widths.insert(c[1].to_string(), w);
            flat.params.push((c[1].to_string(), c[2].to_string()));
        } else if line == "always @(*) begin" {
            let mut depth = 1;
            let mut body = Vec::new();
            i += 1;
            loop {
                let l = m.lines.get(i).unwrap_or_else(|| {
                    panic!(
                        "`always @(*) begin` in rust-hdl module {} has no matching `end`",
                        m.name
                    )
                });
                let (opens, closes) = begin_end_tokens(l);
                depth = (depth + opens).checked_sub(closes).unwrap_or_else(|| {
                    panic!(
                        "more `end` than `begin` in rust-hdl module {}: `{l}`",
                        m.name
                    )
                });
                if depth == 0 {
                    break;
                }
                body.push(l.clone());
                i += 1;
            }
            flat.comb.push(dedent(&body));
        } else {
            panic!("unexpected line in rust-hdl module {}: `{line}`", m.name);
        }
        i += 1;
    }
    for inst in insts {
        let conn = |p: &str| -> String {
            inst.ports
                .iter()
                .find(|(n, _)| n == p)
                .unwrap_or_else(|| panic!("instance {} has no port {p}", inst.name))
                .1
                .clone()
        };
        if let Some(dff) = dffs.get(&inst.kind) {
            let q = conn("q");
            let net = flat
                .nets
                .iter_mut()
                .find(|n| n.name == q)
                .unwrap_or_else(|| panic!("flop output {q} is not a local net of {}", m.name));
            net.init = Some(dff.init.clone());
            flat.flops.push((conn("clock"), q, conn("d")));
            continue;
        }
        if let Some(shape) = rams.get(&inst.kind) {
            let read_data = conn("read_data");
            let net = flat
                .nets
                .iter_mut()
                .find(|n| n.name == read_data)
                .unwrap_or_else(|| {
                    panic!("RAM output {read_data} is not a local net of {}", m.name)
                });
            // rust-hdl's RAM reads 0 before its first clock.
            net.init = Some(format!("{}'h0", shape.width));
            let name = format!("{}$mem", inst.name);
            flat.widths.insert(name.clone(), shape.width);
            flat.mems.push(Mem {
                name,
                shape: *shape,
                read_clock: conn("read_clock"),
                read_address: conn("read_address"),
                read_data: conn("read_data"),
                write_clock: conn("write_clock"),
                write_address: conn("write_address"),
                write_data: conn("write_data"),
                write_enable: conn("write_enable"),
            });
            continue;
        }
        let child = modules
            .get(&inst.kind)
            .unwrap_or_else(|| panic!("no module {}", inst.kind));
        let sub = flatten(child, modules, dffs, rams);
        let rename = |id: &str| -> String {
            if child.args.iter().any(|a| a == id) {
                conn(id)
            } else {
                format!("{}${id}", inst.name)
            }
        };
        for n in sub.nets {
            let name = rename(&n.name);
            flat.widths.insert(name.clone(), n.width);
            flat.nets.push(Net { name, ..n });
        }
        for (p, v) in sub.params {
            let name = rename(&p);
            flat.widths.insert(name.clone(), sub.widths[&p]);
            flat.params.push((name, v));
        }
        for block in sub.comb {
            flat.comb.push(
                block
                    .iter()
                    .map(|l| rename_identifiers(l, &rename))
                    .collect(),
            );
        }
        for (c, q, d) in sub.flops {
            flat.flops.push((rename(&c), rename(&q), rename(&d)));
        }
        for mem in sub.mems {
            flat.widths.insert(rename(&mem.name), mem.shape.width);
            flat.mems.push(Mem {
                name: rename(&mem.name),
                shape: mem.shape,
                read_clock: rename(&mem.read_clock),
                read_address: rename(&mem.read_address),
                read_data: rename(&mem.read_data),
                write_clock: rename(&mem.write_clock),
                write_address: rename(&mem.write_address),
                write_data: rename(&mem.write_data),
                write_enable: rename(&mem.write_enable),
            });
        }
    }
    flat
}

fn dedent(lines: &[String]) -> Vec<String> {
    let indent = lines
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    lines
        .iter()
        .map(|l| l.get(indent..).unwrap_or("").to_string())
        .collect()
}

const KEYWORDS: &[&str] = &[
    "always", "begin", "end", "if", "else", "case", "endcase", "default", "posedge", "negedge",
    "or", "and", "not",
];

/// Renames every identifier in a statement line, leaving keywords, sized
/// literals (`4'h0`) and system functions (`$signed`) alone.
fn rename_identifiers(line: &str, rename: &dyn Fn(&str) -> String) -> String {
    static TOKEN: OnceLock<Regex> = OnceLock::new();
    let token = re(
        &TOKEN,
        r"(\d+'[bhd][0-9a-fA-F_]+)|(\$[A-Za-z_]\w*)|([A-Za-z_][\w$]*)",
    );
    token
        .replace_all(line, |c: &regex::Captures| match c.get(3) {
            Some(id) if !KEYWORDS.contains(&id.as_str()) => rename(id.as_str()),
            _ => c[0].to_string(),
        })
        .to_string()
}

/// rust-hdl routes each flop's clock through a stub assigned in a
/// combinational block (`x$clock = clock;`). Wire the flop to the source
/// instead and drop the stub, so no clock passes through `always @(*)`.
fn resolve_flop_clocks(flat: &mut Flat, ports: &[String]) {
    let mut stubs = BTreeSet::new();
    let mut clocks: Vec<String> = flat.flops.iter().map(|f| f.0.clone()).collect();
    for m in &flat.mems {
        clocks.push(m.read_clock.clone());
        clocks.push(m.write_clock.clone());
    }
    let mut resolved = Vec::new();
    for mut clk in clocks {
        while !ports.contains(&clk) {
            let prefix = format!("{clk} = ");
            let src = flat
                .comb
                .iter()
                .flatten()
                .find_map(|l| {
                    l.strip_prefix(&prefix)
                        .map(|r| r.trim_end_matches(';').to_string())
                })
                .unwrap_or_else(|| panic!("flop clock `{clk}` has no simple driver"));
            assert!(
                src.chars()
                    .all(|c| c.is_alphanumeric() || c == '_' || c == '$'),
                "flop clock `{clk}` is driven by logic `{src}`"
            );
            stubs.insert(clk);
            clk = src;
        }
        resolved.push(clk);
    }
    let mut resolved = resolved.into_iter();
    for f in &mut flat.flops {
        f.0 = resolved.next().expect("one clock per flop");
    }
    for m in &mut flat.mems {
        m.read_clock = resolved.next().expect("read clock");
        m.write_clock = resolved.next().expect("write clock");
    }
    for block in &mut flat.comb {
        block.retain(|l| !stubs.iter().any(|s| l.starts_with(&format!("{s} = "))));
    }
    flat.nets.retain(|n| !stubs.contains(&n.name));
    // A removed clock stub read anywhere else would now be undeclared.
    for l in flat.comb.iter().flatten() {
        for word in l.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '$')) {
            assert!(
                !stubs.contains(word),
                "clock stub `{word}` is still read in `{l}`"
            );
        }
    }
}

/// Output ports that the combinational blocks set exactly once, with one
/// unconditional top-level `port = expr;`: those lines, taken out of the
/// blocks, become continuous assignments. An output written from inside an
/// `always @(*)` block that also reads an input breaks when the outside
/// connects that output back to that input (a loopback in a testbench):
/// Icarus merges the two port nets, the block changes its own input while
/// it runs and never wakes for it, and Verilator reports the block as a
/// combinational loop.
fn hoist_output_assignments(root: &RawModule, flat: &Flat) -> (Vec<Vec<String>>, Vec<String>) {
    let mut comb = flat.comb.clone();
    let mut hoisted = Vec::new();
    for arg in &root.args {
        let Some((kind, _)) = flat.ports.get(arg) else {
            continue;
        };
        if kind == "input wire" || kind == "inout wire" {
            continue;
        }
        let prefix = format!("{arg} = ");
        let writes: Vec<(usize, usize)> = comb
            .iter()
            .enumerate()
            .flat_map(|(b, block)| {
                block
                    .iter()
                    .enumerate()
                    .filter(|(_, l)| {
                        let t = l.trim_start();
                        t.starts_with(&prefix) || t.starts_with(&format!("{arg}["))
                    })
                    .map(move |(i, _)| (b, i))
            })
            .collect();
        if let [(b, i)] = writes[..] {
            let line = &comb[b][i];
            if line.starts_with(&prefix) && line.ends_with(';') && !line.contains("?") {
                hoisted.push(format!("assign {line}"));
                comb[b].remove(i);
            }
        }
    }
    (comb, hoisted)
}

fn render(name: &str, root: &RawModule, flat: &Flat) -> String {
    let (comb, hoisted) = hoist_output_assignments(root, flat);
    let assigned: BTreeSet<String> = comb
        .iter()
        .flatten()
        .filter_map(|l| l.trim().split(" = ").next().filter(|_| l.contains(" = ")))
        .map(|s| s.to_string())
        .chain(flat.flops.iter().map(|f| f.1.clone()))
        .chain(flat.mems.iter().map(|m| m.read_data.clone()))
        .collect();
    let decl_width = |w: usize| {
        if w == 1 {
            String::new()
        } else {
            format!("[{}:0] ", w - 1)
        }
    };
    let mut t = format!("\nmodule {name}({});\n", root.args.join(", "));
    for arg in &root.args {
        let (kind, signed) = flat
            .ports
            .get(arg)
            .unwrap_or_else(|| panic!("no declaration for port {arg}"));
        let dir = match kind.as_str() {
            "input wire" => "input wire".to_string(),
            "inout wire" => "inout wire".to_string(),
            _ if assigned.contains(arg) => "output reg".to_string(),
            _ => "output wire".to_string(),
        };
        let signed = if *signed { "signed " } else { "" };
        t.push_str(&format!(
            "    {dir} {signed}{}{arg};\n",
            decl_width(flat.widths[arg])
        ));
    }
    if !flat.params.is_empty() {
        t.push('\n');
        for (p, v) in &flat.params {
            t.push_str(&format!("    localparam {p} = {v};\n"));
        }
    }
    if !flat.nets.is_empty() {
        t.push('\n');
        for n in &flat.nets {
            let kind = if assigned.contains(&n.name) {
                "reg"
            } else {
                "wire"
            };
            let signed = if n.signed { "signed " } else { "" };
            let init = n
                .init
                .as_ref()
                .map(|i| format!(" = {i}"))
                .unwrap_or_default();
            t.push_str(&format!(
                "    {kind} {signed}{}{}{init};\n",
                decl_width(n.width),
                n.name
            ));
        }
    }
    if !hoisted.is_empty() {
        t.push('\n');
        for a in &hoisted {
            t.push_str(&format!("    {}\n", size_literals(a, &flat.widths)));
        }
    }
    for block in &comb {
        if block.iter().all(|l| l.trim().is_empty()) {
            continue;
        }
        t.push_str("\n    always @(*) begin\n");
        for l in block {
            t.push_str(&format!("        {}\n", size_literals(l, &flat.widths)));
        }
        t.push_str("    end\n");
    }
    if !flat.flops.is_empty() {
        t.push('\n');
        for (c, q, d) in &flat.flops {
            t.push_str(&format!("    always @(posedge {c}) {q} <= {d};\n"));
        }
    }
    for m in &flat.mems {
        // Synchronous read, read-before-write: block RAM on iCE40 and ECP5.
        t.push_str(&format!(
            "\n    reg [{}:0] {} [0:{}];\n",
            m.shape.width - 1,
            m.name,
            m.shape.depth - 1
        ));
        // Zero at power-up, as rust-hdl simulates it and as iCE40 and ECP5
        // block RAM load from the bitstream.
        t.push_str(&format!(
            "    integer {n}_i;\n    initial for ({n}_i = 0; {n}_i < {d}; {n}_i = {n}_i + 1) {n}[{n}_i] = {w}'h0;\n",
            n = m.name,
            d = m.shape.depth,
            w = m.shape.width
        ));
        t.push_str(&format!(
            "    always @(posedge {}) {} <= {}[{}];\n",
            m.read_clock, m.read_data, m.name, m.read_address
        ));
        t.push_str(&format!(
            "    always @(posedge {}) if ({}) {}[{}] <= {};\n",
            m.write_clock, m.write_enable, m.name, m.write_address, m.write_data
        ));
    }
    t.push_str(&format!("endmodule // {name}\n"));
    // Every name must stay distinct once `$` becomes `_`.
    let mut seen: BTreeMap<String, &str> = BTreeMap::new();
    for n in flat.widths.keys() {
        let clean = n.replace('$', "_");
        if let Some(other) = seen.insert(clean.clone(), n) {
            panic!("in {name}: `{other}` and `{n}` would both become `{clean}`");
        }
    }
    strip_dollars(&t)
}

/// Replaces `$` inside identifiers with `_`; system tasks such as `$signed`
/// start with `$` and are left alone.
fn strip_dollars(text: &str) -> String {
    static ID: OnceLock<Regex> = OnceLock::new();
    let id = re(&ID, r"([A-Za-z0-9_])\$([A-Za-z0-9_])");
    let mut t = text.to_string();
    loop {
        let next = id.replace_all(&t, "${1}_${2}").to_string();
        if next == t {
            return t;
        }
        t = next;
    }
}

/// Gives 32-bit integer literals the width of their context (the left-hand
/// side of an assignment, or the other operand of a binary operator), turns
/// literal bit and part selects into plain constant selects, and rewrites
/// rust-hdl's cast `((x) & N'hff..)` of a named signal into a zero-extension
/// or truncation.
fn size_literals(line: &str, decls: &BTreeMap<String, usize>) -> String {
    static LIT: OnceLock<Regex> = OnceLock::new();
    let lit = re(&LIT, r"\b(?:32|64)'h([0-9a-f]+)");
    static CAST: OnceLock<Regex> = OnceLock::new();
    let cast = re(&CAST, r"\(\(([\w$]+)\) & (\d+)'h([0-9a-f]+)\)");
    static ASSIGN: OnceLock<Regex> = OnceLock::new();
    let assign = re(&ASSIGN, r"^(\s*)([\w$]+) = (?:32|64)'h([0-9a-f]+);$");
    static INDEX: OnceLock<Regex> = OnceLock::new();
    let index = re(&INDEX, r"\[(?:32|64)'h([0-9a-f]+)\]");
    static PART: OnceLock<Regex> = OnceLock::new();
    let part = re(&PART, r"\[\((?:32|64)'h([0-9a-f]+)\)\+:\((\d+)\)\]");
    static BINOP: OnceLock<Regex> = OnceLock::new();
    let binop = re(
        &BINOP,
        r"([\w$]+) (==|!=|<=|>=|<|>|\+|-|&|\||\^) (?:32|64)'h([0-9a-f]+)",
    );
    let width_of = |name: &str| -> usize {
        decls
            .get(name)
            .copied()
            .unwrap_or_else(|| panic!("literal sized against unknown signal `{name}` in `{line}`"))
    };
    // Sized literals are written with a marker so the final check can tell
    // them from literals nobody sized.
    let sized = |width: usize, hex: &str| -> String {
        let v = u128::from_str_radix(hex, 16).unwrap();
        assert!(
            width >= 128 || v < (1u128 << width),
            "literal 0x{hex} does not fit {width} bits in `{line}`"
        );
        format!("{width}'#{v:x}")
    };
    let hex = |h: &str| u128::from_str_radix(h, 16).unwrap();
    let mut l = cast
        .replace_all(line, |c: &regex::Captures| {
            let (name, to) = (&c[1], c[2].parse::<usize>().unwrap());
            assert_eq!(
                hex(&c[3]),
                (1u128 << to) - 1,
                "unexpected cast mask in `{line}`"
            );
            let from = width_of(name);
            match from.cmp(&to) {
                std::cmp::Ordering::Less => format!("{{{}'#0, {name}}}", to - from),
                std::cmp::Ordering::Equal => name.to_string(),
                std::cmp::Ordering::Greater => format!("{name}[{}:0]", to - 1),
            }
        })
        .to_string();
    l = part
        .replace_all(&l, |c: &regex::Captures| {
            let lo = hex(&c[1]);
            let w: u128 = c[2].parse().unwrap();
            format!("[{}:{lo}]", lo + w - 1)
        })
        .to_string();
    l = index
        .replace_all(&l, |c: &regex::Captures| format!("[{}]", hex(&c[1])))
        .to_string();
    if let Some(c) = assign.captures(&l.clone()) {
        l = format!("{}{} = {};", &c[1], &c[2], sized(width_of(&c[2]), &c[3]));
    }
    l = binop
        .replace_all(&l, |c: &regex::Captures| {
            format!("{} {} {}", &c[1], &c[2], sized(width_of(&c[1]), &c[3]))
        })
        .to_string();
    if lit.is_match(&l) {
        panic!("cannot size the literal(s) in `{line}`: assign or compare against a named signal, or use a Constant");
    }
    l.replace("'#", "'h")
}

/// How many `begin` and `end` keywords a line holds, counted on whole
/// identifier tokens (`begin_x` is neither).
fn begin_end_tokens(line: &str) -> (usize, usize) {
    let tokens = line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'));
    tokens.fold((0, 0), |(b, e), t| match t {
        "begin" => (b + 1, e),
        "end" => (b, e + 1),
        _ => (b, e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decls(pairs: &[(&str, usize)]) -> BTreeMap<String, usize> {
        pairs.iter().map(|(n, w)| (n.to_string(), *w)).collect()
    }

    #[test]
    fn literals_take_their_context_width() {
        let d = decls(&[("q$d", 4), ("x", 28)]);
        assert_eq!(size_literals("    q$d = 32'h0;", &d), "    q$d = 4'h0;");
        assert_eq!(
            size_literals("    a = x + 32'h1;", &d),
            "    a = x + 28'h1;"
        );
        assert_eq!(
            size_literals("if (x == 32'h3) begin", &d),
            "if (x == 28'h3) begin"
        );
        assert_eq!(size_literals("    a = x[32'h3];", &d), "    a = x[3];");
        assert_eq!(
            size_literals("    a = x[(32'h10)+:(3)];", &d),
            "    a = x[18:16];"
        );
        assert_eq!(
            size_literals("    x = 32'h0;", &decls(&[("x", 32)])),
            "    x = 32'h0;"
        );
    }

    #[test]
    fn casts_of_named_signals_extend_or_truncate() {
        let d = decls(&[("m", 3), ("w", 32)]);
        assert_eq!(
            size_literals("e = ((m) & 32'hffffffff) << s;", &d),
            "e = {29'h0, m} << s;"
        );
        assert_eq!(size_literals("e = ((w) & 8'hff);", &d), "e = w[7:0];");
        assert_eq!(size_literals("e = ((w) & 32'hffffffff);", &d), "e = w;");
    }

    #[test]
    #[should_panic(expected = "does not fit")]
    fn oversized_literal_is_rejected() {
        size_literals("    q$d = 32'h10;", &decls(&[("q$d", 4)]));
    }

    #[test]
    #[should_panic(expected = "cannot size")]
    fn unsizable_literal_is_rejected() {
        size_literals("    a = (32'h1 << b);", &decls(&[]));
    }

    #[test]
    fn begin_and_end_count_as_whole_tokens_only() {
        assert_eq!(begin_end_tokens("if (begin_x) begin"), (1, 0));
        assert_eq!(begin_end_tokens("end else begin"), (1, 1));
        assert_eq!(begin_end_tokens("    end_y = x$end;"), (0, 0));
        assert_eq!(begin_end_tokens("end"), (0, 1));
        assert_eq!(begin_end_tokens("endcase"), (0, 0));
    }

    #[test]
    #[should_panic(expected = "unexpected line in rust-hdl module top: `initial begin`")]
    fn an_unsupported_construct_panics_naming_its_line() {
        let raw = "module top(a);\n    input wire a;\n    initial begin\n    end\nendmodule\n";
        rewrite(raw, "t");
    }

    #[test]
    fn dollars_leave_system_functions_alone() {
        assert_eq!(
            strip_dollars("a$b$c = $signed(x$y);"),
            "a_b_c = $signed(x_y);"
        );
    }
}
