//! Flattening: every child instance inlined into its parent with
//! hierarchical names (`chip$y1`, `$` removed on output), `DFF`s as flops,
//! `RAM`s as memory arrays, and every flop and RAM clock wired straight to
//! the clock port it comes from.

use super::parse::{self, Dff, Instance, RamShape, RawModule};
use super::re;
use regex::Regex;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;

/// A module with every child inlined: its own declarations, one
/// combinational block per original module, and its flip-flops.
#[derive(Default)]
pub(super) struct Flat {
    /// (kind, width, name, init) for every non-port net, in order.
    pub(super) nets: Vec<Net>,
    /// Width of every port and net, by name.
    pub(super) widths: BTreeMap<String, usize>,
    /// This module's ports: declared kind (`input wire`, `output reg`, …)
    /// and signedness, by name.
    pub(super) ports: BTreeMap<String, (String, bool)>,
    /// Local parameters: (name, value).
    pub(super) params: Vec<(String, String)>,
    /// Combinational blocks, each a list of statement lines (unindented).
    pub(super) comb: Vec<Vec<String>>,
    /// Flip-flops: (clock, q, d).
    pub(super) flops: Vec<(String, String, String)>,
    /// Inlined RAMs.
    pub(super) mems: Vec<Mem>,
}

#[derive(Clone)]
pub(super) struct Net {
    pub(super) width: usize,
    pub(super) signed: bool,
    pub(super) name: String,
    pub(super) init: Option<String>,
}

/// An inlined RAM: its memory array name and its port nets.
#[derive(Clone)]
pub(super) struct Mem {
    pub(super) name: String,
    pub(super) shape: RamShape,
    pub(super) read_clock: String,
    pub(super) read_address: String,
    pub(super) read_data: String,
    pub(super) write_clock: String,
    pub(super) write_address: String,
    pub(super) write_data: String,
    pub(super) write_enable: String,
}

/// `m` with its children inlined, recursively: `DFF`s and `RAM`s (by the
/// names in `dffs` and `rams`) become flops and memories, any other child
/// is looked up in `modules` and flattened in turn.
pub(super) fn flatten(
    m: &RawModule,
    modules: &BTreeMap<String, RawModule>,
    dffs: &BTreeMap<String, Dff>,
    rams: &BTreeMap<String, RamShape>,
) -> Flat {
    let insts = parse::instances(&m.lines);
    let mut flat = own_lines(m, &insts);
    for inst in insts {
        if let Some(dff) = dffs.get(&inst.kind) {
            inline_dff(&mut flat, m, &inst, dff);
            continue;
        }
        if let Some(shape) = rams.get(&inst.kind) {
            inline_ram(&mut flat, m, &inst, *shape);
            continue;
        }
        let child = modules
            .get(&inst.kind)
            .unwrap_or_else(|| panic!("no module {}", inst.kind));
        let sub = flatten(child, modules, dffs, rams);
        inline_child(&mut flat, &inst, child, sub);
    }
    flat
}

/// `m`'s own declarations, local parameters and `always @(*)` bodies; the
/// lines of `insts` are skipped, anything else is a panic naming the line.
fn own_lines(m: &RawModule, insts: &[Instance]) -> Flat {
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
            let (body, end) = parse::always_body(m, i);
            flat.comb.push(body);
            i = end;
        } else {
            panic!("unexpected line in rust-hdl module {}: `{line}`", m.name);
        }
        i += 1;
    }
    flat
}

/// A `DFF` child of `m`: a flop whose output net takes the DFF's initial
/// value.
fn inline_dff(flat: &mut Flat, m: &RawModule, inst: &Instance, dff: &Dff) {
    let q = inst.conn("q");
    let net = flat
        .nets
        .iter_mut()
        .find(|n| n.name == q)
        .unwrap_or_else(|| panic!("flop output {q} is not a local net of {}", m.name));
    net.init = Some(dff.init.clone());
    flat.flops.push((inst.conn("clock"), q, inst.conn("d")));
}

/// A `RAM` child of `m`: a memory array named after the instance.
fn inline_ram(flat: &mut Flat, m: &RawModule, inst: &Instance, shape: RamShape) {
    let read_data = inst.conn("read_data");
    let net = flat
        .nets
        .iter_mut()
        .find(|n| n.name == read_data)
        .unwrap_or_else(|| panic!("RAM output {read_data} is not a local net of {}", m.name));
    // rust-hdl's RAM reads 0 before its first clock.
    net.init = Some(format!("{}'h0", shape.width));
    let name = format!("{}$mem", inst.name);
    flat.widths.insert(name.clone(), shape.width);
    flat.mems.push(Mem {
        name,
        shape,
        read_clock: inst.conn("read_clock"),
        read_address: inst.conn("read_address"),
        read_data: inst.conn("read_data"),
        write_clock: inst.conn("write_clock"),
        write_address: inst.conn("write_address"),
        write_data: inst.conn("write_data"),
        write_enable: inst.conn("write_enable"),
    });
}

/// `sub`, the flattened `child` instantiated as `inst`, merged into
/// `flat`: the child's ports become the nets they are connected to, its
/// other names take the instance name as a prefix (`inst$name`).
fn inline_child(flat: &mut Flat, inst: &Instance, child: &RawModule, sub: Flat) {
    let rename = |id: &str| -> String {
        if child.args.iter().any(|a| a == id) {
            inst.conn(id)
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
                .map(|l| parse::rename_identifiers(l, &rename))
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

/// rust-hdl routes each flop's clock through a stub assigned in a
/// combinational block (`x$clock = clock;`). Wire the flop to the source
/// instead and drop the stub, so no clock passes through `always @(*)`.
pub(super) fn resolve_flop_clocks(flat: &mut Flat, ports: &[String]) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A flop clocked through the stub `q_reg$clock`, with `extra` in the
    /// same combinational block.
    fn stubbed_flop(extra: &str) -> Flat {
        Flat {
            nets: vec![Net {
                width: 1,
                signed: false,
                name: "q_reg$clock".into(),
                init: None,
            }],
            widths: BTreeMap::from([("clock".into(), 1), ("q_reg$clock".into(), 1)]),
            ports: BTreeMap::new(),
            params: Vec::new(),
            comb: vec![vec!["q_reg$clock = clock;".into(), extra.into()]],
            flops: vec![("q_reg$clock".into(), "q_reg$q".into(), "q_reg$d".into())],
            mems: Vec::new(),
        }
    }

    #[test]
    fn a_flop_is_wired_to_its_clock_and_the_stub_dropped() {
        let mut flat = stubbed_flop("y = q_reg$q;");
        resolve_flop_clocks(&mut flat, &["clock".into()]);
        assert_eq!(flat.flops[0].0, "clock");
        assert_eq!(flat.comb, vec![vec!["y = q_reg$q;".to_string()]]);
        assert!(flat.nets.is_empty());
    }

    #[test]
    #[should_panic(expected = "clock stub `q_reg$clock` is still read in `y = q_reg$clock;`")]
    fn a_clock_stub_read_elsewhere_panics_naming_the_line() {
        resolve_flop_clocks(&mut stubbed_flop("y = q_reg$clock;"), &["clock".into()]);
    }
}
