//! The board-level wrapper `motion_controller_board`: the top level with its
//! split tri-state ports (`X_in`, `X_out`, `X_oe`) joined into `inout X`
//! pins, output pairs with an enable per bit (`X_out`, `X_oe`) joined into
//! tri-state `output X` pins, and the open-collector `isa_iocs16_n` driven
//! low or released.
//!
//! The port list is the exporter's own (`VerilogModule::ports`, read from
//! the rust-hdl block), so the wrapper's and the constraints' names cannot
//! drift from the top level's; a test checks it against the generated
//! `motion_controller.v`'s declarations.

use motionhdl_hdl::{banner, catalog};
use motionhdl_model::Config;

/// Module (and file stem) of the board-level wrapper.
pub const MODULE: &str = "motion_controller_board";

/// Ports of the top level that are open-collector outputs on the board:
/// driven low when the core's output is 0, released (high impedance)
/// when it is 1; the bus has the pull-up.
pub const OPEN_COLLECTOR: &[&str] = &["isa_iocs16_n"];

/// A port of the top level, as the exporter reports it (from rust-hdl's
/// probe API, not from the Verilog text).
pub use motionhdl_hdl::ports::{Port as CorePort, PortDir as Dir};

/// What a board pin is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinKind {
    /// An input pin.
    Input,
    /// A push-pull output pin.
    Output,
    /// A bidirectional pin: `X_in`, `X_out`, `X_oe` of the top level.
    Inout,
    /// An open-collector output (drive low or float).
    OpenCollector,
    /// An output that drives or floats bit by bit: `X_out`, `X_oe` of the
    /// top level, one enable per bit (push-pull or open-drain by register).
    TriState,
}

impl PinKind {
    /// Whether the pad ever drives (needs an output-capable pin).
    pub fn drives(self) -> bool {
        !matches!(self, PinKind::Input)
    }
}

/// One port of the board-level wrapper.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BoardPort {
    pub name: String,
    pub kind: PinKind,
    pub width: u32,
}

impl BoardPort {
    /// The port's bits as they are named in constraint files: `name` for a
    /// one-bit port, else `name[i]` for i = 0..width.
    pub fn bits(&self) -> Vec<String> {
        if self.width == 1 {
            vec![self.name.clone()]
        } else {
            (0..self.width)
                .map(|i| format!("{}[{i}]", self.name))
                .collect()
        }
    }

    /// The interface the port belongs to, for grouping in constraint
    /// files: the prefix before the first `_` (`fsmc`, `isa`, `enc`,
    /// `sram`), or the name itself (`clock`, `reset`).
    pub fn group(&self) -> &str {
        self.name.split('_').next().unwrap_or(&self.name)
    }
}

/// Board ports that bring only the first few bits of a core port to pins,
/// as many as the configuration says: the core's other inputs read 0, its
/// other outputs go nowhere.
type PinsFor = fn(&Config) -> u32;
const NARROWED: [(&str, PinsFor); 2] =
    [("gpi", Config::gpio_inputs), ("gpo", Config::gpio_outputs)];

/// The bits of board port `name` on pins for `config` (`width`, the core's,
/// unless narrowed).
fn pins_of(name: &str, width: u32, config: &Config) -> u32 {
    NARROWED
        .iter()
        .find(|(n, _)| *n == name)
        .map_or(width, |(_, pins)| pins(config).min(width))
}

/// The board ports for a top level with `core` ports, in the core's order:
/// every `X_in`/`X_out`/`X_oe` triple becomes one `inout X` at the position
/// of `X_in`; every `X_out`/`X_oe` pair with an enable per bit one tri-state
/// `output X`; [`OPEN_COLLECTOR`] outputs become open-collector pins. The
/// general-purpose I/O has as many pins as `config` asks (none: no port).
pub fn board_ports(core: &[CorePort], config: &Config) -> Vec<BoardPort> {
    let mut ports = all_board_ports(core);
    for p in &mut ports {
        p.width = pins_of(&p.name, p.width, config);
    }
    ports.retain(|p| p.width > 0);
    ports
}

fn all_board_ports(core: &[CorePort]) -> Vec<BoardPort> {
    let find = |name: &str| core.iter().find(|p| p.name == name);
    let mut out = Vec::new();
    for p in core {
        if let Some(base) = p.name.strip_suffix("_in") {
            if let (Some(o), Some(oe)) = (find(&format!("{base}_out")), find(&format!("{base}_oe")))
            {
                assert!(
                    p.dir == Dir::Input && o.dir == Dir::Output && oe.dir == Dir::Output,
                    "tri-state triple {base}_in/_out/_oe has wrong directions"
                );
                assert_eq!(p.width, o.width, "{base}_in and {base}_out widths differ");
                assert_eq!(oe.width, 1, "{base}_oe must be one bit");
                out.push(BoardPort {
                    name: base.to_string(),
                    kind: PinKind::Inout,
                    width: p.width,
                });
                continue;
            }
        }
        if let Some(base) = p.name.strip_suffix("_out") {
            if let (None, Some(oe)) = (find(&format!("{base}_in")), find(&format!("{base}_oe"))) {
                assert!(
                    p.dir == Dir::Output && oe.dir == Dir::Output && oe.width == p.width,
                    "tri-state pair {base}_out/_oe needs two outputs of one width"
                );
                out.push(BoardPort {
                    name: base.to_string(),
                    kind: PinKind::TriState,
                    width: p.width,
                });
                continue;
            }
        }
        let part_of_group = ["_out", "_oe"].iter().any(|s| {
            p.name.strip_suffix(s).is_some_and(|base| {
                find(&format!("{base}_in")).is_some()
                    || (*s == "_oe" && find(&format!("{base}_out")).is_some())
            })
        });
        if part_of_group {
            continue;
        }
        let kind = match p.dir {
            Dir::Input => PinKind::Input,
            Dir::Output if OPEN_COLLECTOR.contains(&p.name.as_str()) => {
                assert_eq!(p.width, 1, "open-collector port {} must be one bit", p.name);
                PinKind::OpenCollector
            }
            Dir::Output => PinKind::Output,
            Dir::InOut => panic!("unexpected inout port {} in the top level", p.name),
        };
        out.push(BoardPort {
            name: p.name.clone(),
            kind,
            width: p.width,
        });
    }
    out
}

/// The board ports of the top level generated for `config` (elaborates
/// it; [`board_ports`] takes ports already at hand).
pub fn ports(config: &Config) -> Vec<BoardPort> {
    board_ports(&catalog::motion_controller(config).ports, config)
}

fn range(width: u32) -> String {
    if width == 1 {
        String::new()
    } else {
        format!("[{}:0] ", width - 1)
    }
}

/// The wrapper's Verilog for a top level with ports `core`, built for
/// `config`.
pub fn wrapper_for(core: &[CorePort], config: &Config) -> String {
    let board = board_ports(core, config);
    let core_width = |name: String| core.iter().find(|c| c.name == name).map_or(1, |c| c.width);
    let mut s = String::new();
    s.push_str(&format!("// {}\n", banner()));
    s.push_str(&format!(
        "// {MODULE}: board-level wrapper of motion_controller: tri-state pins as inout with\n\
         // their output enables, the open-collector IOCS16# driven low or released.\n\
         // Ports named as on the board; pin constraints in generated/constraints/.\n"
    ));
    s.push_str("`timescale 1ns / 1ps\n`default_nettype none\n\n");
    let names: Vec<&str> = board.iter().map(|p| p.name.as_str()).collect();
    s.push_str(&format!("module {MODULE}({});\n", names.join(", ")));
    for p in &board {
        let decl = match p.kind {
            PinKind::Input => "input wire",
            PinKind::Output | PinKind::OpenCollector | PinKind::TriState => "output wire",
            PinKind::Inout => "inout wire",
        };
        s.push_str(&format!("    {decl} {}{};\n", range(p.width), p.name));
    }
    s.push('\n');
    for p in &board {
        match p.kind {
            PinKind::Inout => {
                s.push_str(&format!("    wire {}{}_out;\n", range(p.width), p.name));
                s.push_str(&format!("    wire {}_oe;\n", p.name));
            }
            PinKind::TriState => {
                let w = range(core_width(format!("{}_out", p.name)));
                s.push_str(&format!("    wire {w}{}_out;\n", p.name));
                s.push_str(&format!("    wire {w}{}_oe;\n", p.name));
            }
            PinKind::OpenCollector => {
                s.push_str(&format!("    wire {}_drive;\n", p.name));
            }
            _ => {}
        }
    }
    s.push_str("\n    motion_controller core(\n");
    let conns: Vec<String> = core
        .iter()
        .map(|c| {
            let found = board.iter().find(|b| {
                b.name == c.name
                    || (matches!(b.kind, PinKind::Inout | PinKind::TriState)
                        && ["_in", "_out", "_oe"]
                            .iter()
                            .any(|s| c.name == format!("{}{s}", b.name)))
            });
            let Some(b) = found else {
                // A narrowed port with no pins at all.
                let signal = match c.dir {
                    Dir::Input => format!("{}'d0", c.width),
                    _ => String::new(),
                };
                return format!("        .{}({signal})", c.name);
            };
            let signal = match b.kind {
                PinKind::Input if b.width < c.width => {
                    format!("{{{}'d0, {}}}", c.width - b.width, b.name)
                }
                PinKind::Input | PinKind::Output => b.name.clone(),
                PinKind::OpenCollector => format!("{}_drive", b.name),
                PinKind::Inout if c.name.ends_with("_in") => b.name.clone(),
                PinKind::Inout | PinKind::TriState => c.name.clone(),
            };
            format!("        .{}({signal})", c.name)
        })
        .collect();
    s.push_str(&conns.join(",\n"));
    s.push_str("\n    );\n\n");
    for p in &board {
        match p.kind {
            PinKind::Inout => s.push_str(&format!(
                "    assign {n} = {n}_oe ? {n}_out : {w}'bz;\n",
                n = p.name,
                w = p.width
            )),
            PinKind::OpenCollector => s.push_str(&format!(
                "    assign {n} = {n}_drive ? 1'bz : 1'b0;\n",
                n = p.name
            )),
            PinKind::TriState => {
                for i in 0..p.width {
                    let b = if p.width == 1 {
                        String::new()
                    } else {
                        format!("[{i}]")
                    };
                    s.push_str(&format!(
                        "    assign {n}{b} = {n}_oe{b} ? {n}_out{b} : 1'bz;\n",
                        n = p.name
                    ));
                }
            }
            _ => {}
        }
    }
    s.push_str("endmodule\n\n`default_nettype wire\n");
    s
}

/// The wrapper's Verilog for `config`.
pub fn wrapper(config: &Config) -> String {
    wrapper_for(&catalog::motion_controller(config).ports, config)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses the port declarations (`input wire [11:0] fsmc_a;`, `output reg
    /// x;`) of a generated module. Panics on a declaration it does not
    /// recognise: the exporter's format is fixed, and a silent miss would drop
    /// a pin.
    fn parse_ports(verilog: &str) -> Vec<CorePort> {
        let mut ports = Vec::new();
        for line in verilog.lines() {
            let t = line.trim();
            let dir = if let Some(rest) = t.strip_prefix("input ") {
                (Dir::Input, rest)
            } else if let Some(rest) = t.strip_prefix("output ") {
                (Dir::Output, rest)
            } else if t.starts_with("inout ") {
                panic!("unexpected inout port in the top level: {t}");
            } else {
                continue;
            };
            let (dir, rest) = dir;
            let rest = rest
                .trim_start_matches("wire ")
                .trim_start_matches("reg ")
                .trim_end_matches(';')
                .trim();
            let (width, name) = match rest.strip_prefix('[') {
                Some(r) => {
                    let (range, name) = r
                        .split_once(']')
                        .unwrap_or_else(|| panic!("bad port range: {t}"));
                    let (hi, lo) = range
                        .split_once(':')
                        .unwrap_or_else(|| panic!("bad port range: {t}"));
                    let hi: u32 = hi.trim().parse().expect("port msb");
                    let lo: u32 = lo.trim().parse().expect("port lsb");
                    assert_eq!(lo, 0, "port range must end at 0: {t}");
                    (hi + 1, name.trim())
                }
                None => (1, rest),
            };
            assert!(
                !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
                "bad port name in: {t}"
            );
            ports.push(CorePort {
                name: name.to_string(),
                dir,
                width,
                signed: false,
            });
        }
        assert!(!ports.is_empty(), "no port declarations found");
        ports
    }

    #[test]
    fn the_exporters_ports_are_the_generated_declarations() {
        use motionhdl_model::IsaRam;
        for config in [
            Config::default(),
            Config::default().with_isa_ram(IsaRam::External),
            Config::new(1, 8, 50_000_000).unwrap(),
        ] {
            let top = catalog::motion_controller(&config);
            assert_eq!(top.ports, parse_ports(&top.text), "{config:?}");
        }
    }

    #[test]
    fn triples_and_pairs_join_and_open_collector_is_kept() {
        let v = "    input wire clock;\n    input wire [15:0] d_in;\n    output reg [15:0] d_out;\n    output reg d_oe;\n    output reg isa_iocs16_n;\n    output reg [3:0] gpo_out;\n    output reg [3:0] gpo_oe;\n";
        let b = board_ports(&parse_ports(v), &Config::default());
        assert_eq!(
            b,
            vec![
                BoardPort {
                    name: "clock".into(),
                    kind: PinKind::Input,
                    width: 1
                },
                BoardPort {
                    name: "d".into(),
                    kind: PinKind::Inout,
                    width: 16
                },
                BoardPort {
                    name: "isa_iocs16_n".into(),
                    kind: PinKind::OpenCollector,
                    width: 1
                },
                BoardPort {
                    name: "gpo".into(),
                    kind: PinKind::TriState,
                    width: 4
                },
            ]
        );
        let wrapper = wrapper_for(&parse_ports(v), &Config::default());
        assert!(
            wrapper.contains("    output wire [3:0] gpo;\n"),
            "{wrapper}"
        );
        assert!(wrapper.contains("    assign gpo[3] = gpo_oe[3] ? gpo_out[3] : 1'bz;\n"));
        assert!(wrapper.contains("        .gpo_oe(gpo_oe)"), "{wrapper}");
    }

    #[test]
    fn default_board_has_the_documented_pins() {
        let ports = ports(&Config::default());
        let bits: usize = ports.iter().map(|p| p.bits().len()).sum();
        // clock, reset, FSMC 31, ISA 39, encoders 3 per axis, and whatever
        // else the top grows (pulse outputs): at least the 84 pins of the first pinned top.
        assert!(bits >= 84, "{bits}");
        assert!(ports
            .iter()
            .any(|p| p.name == "fsmc_d" && p.kind == PinKind::Inout));
        assert!(ports
            .iter()
            .any(|p| p.name == "isa_sd" && p.kind == PinKind::Inout));
    }
}
