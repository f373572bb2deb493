//! Reading rust-hdl's Verilog text: its modules, their child instances, the
//! `DFF` and `RAM` widgets recognised by shape, `always` bodies (nesting
//! counted on `begin`/`end` tokens) and the identifiers of a statement line.

use super::re;
use regex::Regex;
use std::sync::OnceLock;

/// One `module … endmodule` of rust-hdl's output.
pub(super) struct RawModule {
    pub(super) name: String,
    pub(super) args: Vec<String>,
    pub(super) lines: Vec<String>,
}

/// rust-hdl's `DFF` widget: its initial value.
pub(super) struct Dff {
    pub(super) init: String,
}

pub(super) fn parse_modules(raw: &str) -> Vec<RawModule> {
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
pub(super) fn as_dff(m: &RawModule) -> Option<Dff> {
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
pub(super) struct RamShape {
    pub(super) width: usize,
    pub(super) depth: usize,
}

/// Recognises rust-hdl's `RAM` module (without initial contents).
pub(super) fn as_ram(m: &RawModule) -> Option<RamShape> {
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

/// An instance as rust-hdl writes it: `kind name(` then `.port(sig),` lines then `);`.
pub(super) struct Instance {
    pub(super) kind: String,
    pub(super) name: String,
    pub(super) ports: Vec<(String, String)>,
    pub(super) first_line: usize,
    pub(super) last_line: usize,
}

impl Instance {
    /// The net connected to port `p`.
    pub(super) fn conn(&self, p: &str) -> String {
        self.ports
            .iter()
            .find(|(n, _)| n == p)
            .unwrap_or_else(|| panic!("instance {} has no port {p}", self.name))
            .1
            .clone()
    }
}

pub(super) fn instances(lines: &[String]) -> Vec<Instance> {
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

/// The body of the `always @(*) begin` at `m.lines[start]`, unindented,
/// and the index of the line that holds its closing `end`.
pub(super) fn always_body(m: &RawModule, start: usize) -> (Vec<String>, usize) {
    let mut depth = 1;
    let mut body = Vec::new();
    let mut i = start + 1;
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
            return (dedent(&body), i);
        }
        body.push(l.clone());
        i += 1;
    }
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

const KEYWORDS: &[&str] = &[
    "always", "begin", "end", "if", "else", "case", "endcase", "default", "posedge", "negedge",
    "or", "and", "not",
];

/// Renames every identifier in a statement line, leaving keywords, sized
/// literals (`4'h0`) and system functions (`$signed`) alone.
pub(super) fn rename_identifiers(line: &str, rename: &dyn Fn(&str) -> String) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn begin_and_end_count_as_whole_tokens_only() {
        assert_eq!(begin_end_tokens("if (begin_x) begin"), (1, 0));
        assert_eq!(begin_end_tokens("end else begin"), (1, 1));
        assert_eq!(begin_end_tokens("    end_y = x$end;"), (0, 0));
        assert_eq!(begin_end_tokens("end"), (0, 1));
        assert_eq!(begin_end_tokens("endcase"), (0, 0));
    }
}
