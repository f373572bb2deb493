//! Emitting the flat module: its ports (`output reg` only where a block
//! assigns them), parameters and nets, output ports set once as continuous
//! `assign`s, the combinational blocks with their literals sized from
//! context, the flops and the RAMs; then `$` leaves every identifier.

use super::flatten::{Flat, Mem};
use super::parse::RawModule;
use super::re;
use regex::Regex;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;

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

/// The flat module `flat` as Verilog module `name`, with `root`'s ports in
/// their order.
pub(super) fn render(name: &str, root: &RawModule, flat: &Flat) -> String {
    let (comb, hoisted) = hoist_output_assignments(root, flat);
    let assigned = assigned_names(&comb, flat);
    let mut body = String::new();
    if !hoisted.is_empty() {
        body.push('\n');
        for a in &hoisted {
            body.push_str(&format!("    {}\n", size_literals(a, &flat.widths)));
        }
    }
    for block in &comb {
        if block.iter().all(|l| l.trim().is_empty()) {
            continue;
        }
        body.push_str("\n    always @(*) begin\n");
        for l in block {
            body.push_str(&format!("        {}\n", size_literals(l, &flat.widths)));
        }
        body.push_str("    end\n");
    }
    if !flat.flops.is_empty() {
        body.push('\n');
        for (c, q, d) in &flat.flops {
            body.push_str(&format!("    always @(posedge {c}) {q} <= {d};\n"));
        }
    }
    for m in &flat.mems {
        push_mem(&mut body, m);
    }
    let decls = Decls {
        assigned,
        selected: selected_names(&body),
    };
    let mut t = format!("\nmodule {name}({});\n", root.args.join(", "));
    push_ports(&mut t, root, flat, &decls);
    push_locals(&mut t, flat, &decls);
    t.push_str(&body);
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

/// Every name a combinational block, a flop or a RAM read port assigns:
/// declared `reg`, the rest `wire`.
fn assigned_names(comb: &[Vec<String>], flat: &Flat) -> BTreeSet<String> {
    comb.iter()
        .flatten()
        .filter_map(|l| l.trim().split(" = ").next().filter(|_| l.contains(" = ")))
        .map(|s| s.to_string())
        .chain(flat.flops.iter().map(|f| f.1.clone()))
        .chain(flat.mems.iter().map(|m| m.read_data.clone()))
        .collect()
}

/// What a declaration needs to know of the module's body.
struct Decls {
    /// Names assigned in a block, a flop or a RAM port: `reg`.
    assigned: BTreeSet<String>,
    /// Names with a bit or part select somewhere (`x[0]`).
    selected: BTreeSet<String>,
}

impl Decls {
    /// The range of `name`'s `w`-bit declaration: nothing for one bit,
    /// unless the body selects a bit of it (a one-axis bank's `x[0]`),
    /// which Verilog allows only on a vector: then `[0:0]`.
    fn width(&self, name: &str, w: usize) -> String {
        if w == 1 && !self.selected.contains(name) {
            String::new()
        } else {
            format!("[{}:0] ", w - 1)
        }
    }
}

/// Every identifier followed by `[` in `body`.
fn selected_names(body: &str) -> BTreeSet<String> {
    static SELECT: OnceLock<Regex> = OnceLock::new();
    re(&SELECT, r"([A-Za-z_$][\w$]*)\[")
        .captures_iter(body)
        .map(|c| c[1].to_string())
        .collect()
}

/// The port declarations, in `root`'s port order.
fn push_ports(t: &mut String, root: &RawModule, flat: &Flat, decls: &Decls) {
    for arg in &root.args {
        let (kind, signed) = flat
            .ports
            .get(arg)
            .unwrap_or_else(|| panic!("no declaration for port {arg}"));
        let dir = match kind.as_str() {
            "input wire" => "input wire".to_string(),
            "inout wire" => "inout wire".to_string(),
            _ if decls.assigned.contains(arg) => "output reg".to_string(),
            _ => "output wire".to_string(),
        };
        let signed = if *signed { "signed " } else { "" };
        t.push_str(&format!(
            "    {dir} {signed}{}{arg};\n",
            decls.width(arg, flat.widths[arg])
        ));
    }
}

/// The local parameters, then the nets with their initial values.
fn push_locals(t: &mut String, flat: &Flat, decls: &Decls) {
    if !flat.params.is_empty() {
        t.push('\n');
        for (p, v) in &flat.params {
            t.push_str(&format!("    localparam {p} = {v};\n"));
        }
    }
    if !flat.nets.is_empty() {
        t.push('\n');
        for n in &flat.nets {
            let kind = if decls.assigned.contains(&n.name) {
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
                decls.width(&n.name, n.width),
                n.name
            ));
        }
    }
}

/// An inlined RAM: its array, zeroed at power-up, and its two ports.
fn push_mem(t: &mut String, m: &Mem) {
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
    fn dollars_leave_system_functions_alone() {
        assert_eq!(
            strip_dollars("a$b$c = $signed(x$y);"),
            "a_b_c = $signed(x_y);"
        );
    }

    #[test]
    fn a_one_bit_net_with_a_select_is_a_vector() {
        // A one-axis bank's `limit[0]`: Verilator rejects a select of a
        // scalar, so that net is declared [0:0]; other one-bit nets stay
        // scalars and wider ones keep their range.
        let decls = Decls {
            assigned: BTreeSet::new(),
            selected: selected_names("pin = a$limit[0] & b[3:1] & mem[addr];"),
        };
        assert_eq!(
            decls.selected,
            ["a$limit", "b", "mem"].map(String::from).into()
        );
        assert_eq!(decls.width("a$limit", 1), "[0:0] ");
        assert_eq!(decls.width("pin", 1), "");
        assert_eq!(decls.width("b", 4), "[3:0] ");
    }
}
