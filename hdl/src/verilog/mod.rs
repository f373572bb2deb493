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
//!
//! # Layout
//!
//! * `parse` reads rust-hdl's text: modules, child instances, the `DFF`
//!   and `RAM` widgets, `always` bodies (nesting counted on `begin`/`end`)
//!   and the identifiers of a statement line;
//! * `flatten` inlines every child into one flat module and
//!   wires flops and RAMs to the clock port;
//! * `prune` takes out nets and parameters nothing reads (an inlined
//!   block's unused output);
//! * `emit` writes the flat module: continuous assignments for outputs
//!   set once, literals sized from context, no `$` in any name.

mod emit;
mod flatten;
mod parse;
mod prune;

use regex::Regex;
use rust_hdl::prelude::{generate_verilog, Block};
use std::collections::BTreeMap;
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

/// A regex compiled once, on first use.
fn re(cell: &'static OnceLock<Regex>, pat: &str) -> &'static Regex {
    cell.get_or_init(|| Regex::new(pat).expect("valid regex"))
}

fn rewrite(raw: &str, top: &str) -> String {
    let modules: BTreeMap<String, parse::RawModule> = parse::parse_modules(raw)
        .into_iter()
        .map(|m| (m.name.clone(), m))
        .collect();
    let dffs: BTreeMap<String, parse::Dff> = modules
        .values()
        .filter_map(|m| parse::as_dff(m).map(|d| (m.name.clone(), d)))
        .collect();
    let rams: BTreeMap<String, parse::RamShape> = modules
        .values()
        .filter_map(|m| parse::as_ram(m).map(|r| (m.name.clone(), r)))
        .collect();
    let root = modules
        .get("top")
        .expect("rust-hdl output has a top module");
    let mut flat = flatten::flatten(root, &modules, &dffs, &rams);
    flatten::resolve_flop_clocks(&mut flat, &root.args);
    let flat = prune::prune_unread(flat);
    emit::render(top, root, &flat)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nets_nothing_reads_are_taken_out_with_what_only_they_read() {
        let raw = "module top(a, y);\n    input wire a;\n    output reg y;\n    \
                   localparam k = 1'b1;\n    localparam used = 1'b0;\n    reg dead;\n    \
                   reg feeds_dead;\n    reg live;\n    always @(*) begin\n        \
                   feeds_dead = a & k;\n        dead = feeds_dead;\n        \
                   live = a ^ used;\n        y = live;\n    end\nendmodule\n";
        let out = rewrite(raw, "t");
        assert!(!out.contains("dead"), "{out}");
        assert!(!out.contains("localparam k"), "{out}");
        assert!(out.contains("live = a ^ used;"), "{out}");
        assert!(out.contains("localparam used"), "{out}");
    }

    #[test]
    fn a_net_assigned_over_several_lines_keeps_its_declaration() {
        // Its statement cannot be taken out line by line, so the net stays
        // declared even though nothing reads it.
        let raw = "module top(a, y);\n    input wire a;\n    output reg y;\n    \
                   reg unread;\n    always @(*) begin\n        unread = a &\n            \
                   a;\n        y = a;\n    end\nendmodule\n";
        let out = rewrite(raw, "t");
        assert!(out.contains("unread = a &"), "{out}");
        assert!(out.contains("reg unread;"), "{out}");
    }

    #[test]
    #[should_panic(expected = "unexpected line in rust-hdl module top: `initial begin`")]
    fn an_unsupported_construct_panics_naming_its_line() {
        let raw = "module top(a);\n    input wire a;\n    initial begin\n    end\nendmodule\n";
        rewrite(raw, "t");
    }
}
