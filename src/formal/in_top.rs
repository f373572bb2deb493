//! A block's proof, proved again on the block as the top instantiates it
//! (docs/formal.md, "In the top"): the same wrapper text with its instance
//! of the block replaced by `motion_controller`, the block's ports seen
//! through `expose` under the top's prefix for the block, and its exposes
//! and breaks renamed with that prefix. The properties, covers and
//! bookkeeping stay word for word, so what was proved of the module alone
//! is proved of the copy inside the top.

use super::spec::{InTop, ProofSpec, Uses};

/// Ends the name of a proof's copy on the block inside the top.
pub const NAME_SUFFIX: &str = "_in_top";

/// The top's module name and the catalog's `uses` name for it.
pub const TOP: &str = "motion_controller";

/// The `(range, name)` of every `input` in a port list or module body.
fn inputs(decls: &str) -> Vec<(String, String)> {
    decls
        .split([',', ';', '(', ')', '\n'])
        .filter_map(|d| {
            let d = d.trim().strip_prefix("input")?.trim_start();
            let d = d.strip_prefix("wire").unwrap_or(d).trim_start();
            let (range, name) = match d.strip_prefix('[') {
                Some(r) => {
                    let (range, name) = r.split_once(']')?;
                    (format!("[{range}] "), name.trim())
                }
                None => (String::new(), d),
            };
            is_identifier(name).then(|| (range, name.to_string()))
        })
        .collect()
}

/// A character of a Verilog identifier.
fn is_word(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

fn is_identifier(s: &str) -> bool {
    !s.is_empty() && s.chars().all(is_word)
}

/// Every name the module declares (ports, regs, wires, localparams).
fn declared(module_text: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in module_text.lines() {
        let mut rest = line.trim();
        let mut keyword = false;
        for k in ["input", "output", "reg", "wire", "localparam"] {
            if let Some(r) = rest.strip_prefix(k).filter(|r| r.starts_with([' ', '['])) {
                rest = r.trim_start();
                keyword = true;
            }
        }
        if !keyword {
            continue;
        }
        if let Some(r) = rest.strip_prefix('[') {
            rest = r.split_once(']').map_or("", |(_, n)| n.trim_start());
        }
        let name: String = rest.chars().take_while(|c| is_word(*c)).collect();
        if !name.is_empty() {
            names.push(name);
        }
    }
    names
}

/// `text` with every identifier in `names` given `prefix`.
fn renamed(text: &str, names: &[String], prefix: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if names.contains(word) {
            out.push_str(prefix);
        }
        out.push_str(word);
        word.clear();
    };
    for c in text.chars() {
        if is_word(c) {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// Where the first `open` starts, the text between it and the next `);`,
/// and where that `);` ends.
fn span<'a>(text: &'a str, open: &str, what: &str) -> Result<(usize, &'a str, usize), String> {
    let at = text
        .find(open)
        .ok_or_else(|| format!("no `{open}` ({what})"))?;
    let from = at + open.len();
    let len = text[from..]
        .find(");")
        .ok_or_else(|| format!("`{open}` has no `);` ({what})"))?;
    Ok((at, &text[from..from + len], from + len + 2))
}

/// `block` (a parsed proof with an `in_top` line) re-targeted at the top
/// built by `uses motion_controller <args>`; `block_text` and `top_text`
/// are the generated modules the two proofs read.
pub fn derive(block: &ProofSpec, block_text: &str, top_text: &str) -> Result<ProofSpec, String> {
    let InTop { prefix, args } = block.in_top.clone().ok_or("no in_top line")?;
    let module = &block.uses.first().ok_or("no uses line")?.module;
    let err = |e: String| format!("formal/{}.sv in the top: {e}", block.name);
    let text = &block.text;
    let (port_at, ports, body_start) =
        span(text, &format!("module {}(", block.top()), "the wrapper").map_err(err)?;
    let (inst_at, inst, inst_end) =
        span(text, &format!("  {module} uut("), "the instance").map_err(err)?;
    let block_inputs: Vec<_> = inputs(ports)
        .into_iter()
        .filter(|(_, n)| n != "clock" && n != "reset")
        .collect();
    // The wrapper's own assumptions must be about pins the top has too:
    // an assumption on a block input would constrain the top's logic.
    for line in text
        .lines()
        .filter(|l| l.contains("assume(") && !l.trim_start().starts_with("//"))
    {
        let mut words = line.split(|c: char| !is_word(c));
        if let Some(n) = words.find(|w| block_inputs.iter().any(|(_, n)| n == w)) {
            return Err(err(format!(
                "an assumption reads the block input {n}: `{}`",
                line.trim()
            )));
        }
    }
    let connections: Vec<(String, String)> = inst
        .split("),")
        .filter_map(|c| {
            let (port, wire) = c.trim().strip_prefix('.')?.split_once('(')?;
            Some((
                port.trim().to_string(),
                wire.trim_end_matches(')').trim().to_string(),
            ))
        })
        .filter(|(p, _)| p != "clock" && p != "reset")
        .collect();
    let pins: Vec<_> = inputs(top_text)
        .into_iter()
        .filter(|(_, n)| n != "clock" && n != "reset")
        .collect();
    let names = declared(block_text);
    let name = format!("{}{NAME_SUFFIX}", block.name);

    let mut header = String::new();
    for line in text[..port_at].lines() {
        let Some(d) = line.strip_prefix("//!") else {
            header.push_str(line);
            header.push('\n');
            continue;
        };
        let d = d.trim_start();
        if d.starts_with("uses ") {
            let args: Vec<String> = args.iter().map(u32::to_string).collect();
            header.push_str(&format!("//! uses {TOP} {}\n", args.join(" ")));
        } else if d.starts_with("in_top ") {
            continue;
        } else if d.starts_with("expose ") {
            header.push_str(&line.replace(&format!("{module}/"), &format!("{TOP}/{prefix}")));
            header.push('\n');
        } else if let Some(edit) = d.strip_prefix("from:").or_else(|| d.strip_prefix("to:")) {
            let key = if d.starts_with("from:") {
                "from:"
            } else {
                "to:"
            };
            // The block's continuous assignments to its ports are plain
            // assignments in the flattened top.
            let edit = edit.trim();
            let edit = edit.strip_prefix("assign ").unwrap_or(edit);
            header.push_str(&format!("//!   {key} {}\n", renamed(edit, &names, &prefix)));
        } else {
            header.push_str(line);
            header.push('\n');
        }
    }
    let exposed: Vec<String> = connections
        .iter()
        .map(|(p, _)| format!("{TOP}/{prefix}{p}"))
        .collect();
    header.push_str(&format!("//! expose {}\n", exposed.join(" ")));

    let mut module_line = format!("module {name}_props(input clock, input reset");
    for (range, n) in &pins {
        module_line.push_str(&format!(", input {range}pin_{n}"));
    }
    module_line.push_str(");\n  // The block's inputs, as the top drives them.\n");
    for (range, n) in &block_inputs {
        module_line.push_str(&format!("  wire {range}{n};\n"));
    }
    let mut instance = format!("  {TOP} uut(.clock(clock), .reset(reset)");
    for (_, n) in &pins {
        instance.push_str(&format!(", .{n}(pin_{n})"));
    }
    for (p, w) in &connections {
        instance.push_str(&format!(",\n    .{prefix}{p}({w})"));
    }
    instance.push_str(");");

    let derived = format!(
        "{header}{module_line}{}{instance}{}",
        &text[body_start..inst_at],
        &text[inst_end..]
    );
    let mut spec = super::spec::parse(&name, &derived).map_err(err)?;
    spec.uses = vec![Uses {
        module: TOP.to_string(),
        args,
    }];
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_renamed_as_whole_words_only() {
        let names = ["a_q".to_string(), "b".to_string()];
        assert_eq!(
            renamed("x = a_q + b_q + b;", &names, "p_"),
            "x = p_a_q + b_q + p_b;"
        );
    }

    #[test]
    fn ports_and_declarations_are_read() {
        assert_eq!(
            inputs("input clock, input [7:0] addr,\n input we);"),
            [
                (String::new(), "clock".to_string()),
                ("[7:0] ".to_string(), "addr".to_string()),
                (String::new(), "we".to_string()),
            ]
        );
        let m = "module m(a, b);\n    input wire [3:0] a;\n    output wire b;\n    \
                 reg c_q = 1'h0;\n    localparam k = 2;\n        reg_x = 1;\n";
        assert_eq!(declared(m), ["a", "b", "c_q", "k"]);
    }

    #[test]
    fn an_assumption_on_a_block_input_is_refused() {
        let text = "//! uses counter_bank 1 8\n//! in_top mcu_ 1 8\n//! depth 2\n\
                    //! cover_depth 2\n//! break p_x\n//!   from: q = 1;\n//!   to: q = 0;\n\
                    module q_props(input clock, input reset, input a);\n  \
                    counter_bank uut(.clock(clock), .a(a));\n  always @* assume(a);\n  \
                    always @* begin p_x: assert(1); c_y: cover(1); end\nendmodule\n";
        let spec = super::super::spec::parse("q", text).unwrap();
        let top = "module motion_controller(clock);\n    input wire clock;\n";
        let e = derive(&spec, "", top).unwrap_err();
        assert!(e.contains("the block input a"), "{e}");
    }
}
