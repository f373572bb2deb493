//! Pin and timing constraints for the board-level wrapper
//! (`motion_controller_board`), derived from its port list
//! ([`crate::board::ports`]): iCE40 `.pcf`, ECP5 `.lpf`, Cyclone IV `.qsf`
//! pin assignments and `.sdc` timing.
//!
//! Each target has a fixed clock pin and an ordered pool of user pins; the
//! port bits take pins from the pool in port order (first fit, input-only
//! pins only for inputs), so the assignment is deterministic and every bit
//! gets exactly one pin. The committed `constraints/` holds the files for
//! the default configuration (4 axes, internal ISA RAM); for other
//! configurations the same generator runs, and a target whose pool is too
//! small gets no file (`motionhdl synth` then runs without pin constraints).

use crate::board::{self, BoardPort, PinKind};
use motionhdl_hdl::banner;
use motionhdl_model::Config;

/// A device and board the constraints are written for.
pub struct Board {
    /// File stem suffix and CLI name, e.g. `ice40-hx8k`.
    pub name: &'static str,
    /// Human description for file headers.
    pub description: &'static str,
    /// Where the pin names come from and what is assumed.
    pub notes: &'static [&'static str],
    /// The clock input's pin.
    pub clock_pin: &'static str,
    /// Ordered user pins; `true` marks an input-only pin.
    pub pool: &'static [(&'static str, bool)],
}

macro_rules! pins {
    ($($p:literal)*) => { &[$(($p, false)),*] };
}

/// iCE40HX8K-CT256 balls in bank order (3, 0, 1, 2), without the
/// iCE40-HX8K Breakout Board's 12 MHz oscillator (J3), LEDs (A1 A2 B3 B4
/// B5 C3 C4 C5), FTDI UART/handshake (A15 A16 B10 B12 B13 B14 B15) and SPI
/// flash (P11 P12 R11 R12) balls, and without the clock's R9. From the
/// icestorm chip database (`chipdb-8k.txt`, `.pins ct256`).
const ICE40_CT256: &[(&str, bool)] = pins!(
    // bank 3 (left)
    "B2" "E4" "B1" "F5" "C2" "C1" "D2" "F4" "D1" "G5" "E3" "G4" "E2" "H5" "F3" "G3" "F2" "H3"
    "F1" "H6" "G2" "H4" "H2" "J4" "G1" "J5" "H1" "J1" "J2" "K3" "K1" "L1" "L4" "M1" "K4" "L3"
    "L6" "M2" "K5" "N2" "L7" "M3" "M6" "N3" "L5" "M4" "P1" "M5" "P2" "N4" "R1"
    // bank 0 (top)
    "D3" "E5" "D4" "D5" "E6" "A5" "D6" "A6" "D7" "C6" "B6" "B7" "C7" "A7" "B8" "D8" "B9" "F7"
    "C8" "F9" "A9" "D9" "E9" "C9" "D10" "A11" "A10" "C10" "B11" "D11" "C11" "E10" "C13" "E11"
    "C12" "D13" "C14"
    // bank 1 (right)
    "R14" "R15" "P14" "P15" "P16" "M13" "M14" "L12" "N16" "L13" "L14" "K12" "M16" "J10" "M15"
    "J11" "L16" "K13" "K14" "J15" "K15" "K16" "J14" "J12" "J13" "J16" "H13" "H11" "H16" "H14"
    "G16" "H12" "G15" "G10" "F16" "G11" "F15" "G14" "E16" "G13" "D16" "G12" "F14" "F12" "D15"
    "F11" "E14" "C16" "F13" "B16" "E13" "D14"
    // bank 2 (bottom)
    "K11" "P13" "R16" "T16" "M12" "N12" "L11" "T13" "T14" "M11" "T15" "T10" "T11" "P10" "N10"
    "R10" "L10" "K9" "P9" "M9" "N9" "T9" "T8" "P7" "L9" "T7" "P8" "T6" "R6" "M8" "T5" "N7" "P6"
    "M7" "R4" "R5" "T3" "P5" "R3" "N5" "T2" "P4" "R2" "N6" "T1"
);

/// LFE5U-25F CABGA256 user balls in bank order (0, 1, 2, 3, 6, 7), without
/// the configuration bank 8 and the clock's P6. From Project Trellis'
/// `LFE5U-25F/iodb.json` (the database nextpnr-ecp5 uses).
const ECP5_CABGA256: &[(&str, bool)] = pins!(
    // bank 0
    "A2" "B3" "A3" "A4" "E4" "D4" "C4" "B4" "E5" "D5" "C5" "B5" "A5" "A6" "E6" "D6" "C6" "B6"
    "E7" "D7" "C7" "B7" "A7" "A8"
    // bank 1
    "E8" "D8" "C8" "B8" "B9" "C9" "D9" "E9" "A9" "A10" "B10" "C10" "D10" "E10" "B11" "C11"
    "D11" "E11" "A11" "A12" "B12" "C12" "D12" "E12" "B13" "C13" "D13" "E13" "A13" "A14" "B14"
    "A15"
    // bank 2
    "B16" "B15" "C14" "D14" "C16" "C15" "E14" "F14" "D16" "E15" "F13" "F12" "G12" "G13" "F15"
    "E16" "F16" "G15" "G14" "H14" "H12" "H13" "J13" "J12" "G16" "H15" "J14" "K14" "J16" "J15"
    "K16" "K15"
    // bank 3
    "L16" "L15" "M16" "M15" "K13" "K12" "L13" "L12" "N16" "P15" "L14" "M14" "P16" "R16" "M13"
    "N14" "N13" "P14" "R15" "T15" "P13" "R14" "R13" "T14" "R12" "T13" "M12" "N12" "M11" "N11"
    "P11" "P12"
    // bank 6
    "L1" "L2" "M1" "M2" "K4" "K5" "L4" "L5" "N1" "P2" "L3" "M3" "P1" "R1" "M4" "N3" "N4" "P3"
    "R2" "T2" "P4" "R3" "R4" "T3" "R5" "T4" "M5" "N5" "M6" "N6" "P5"
    // bank 7
    "B1" "B2" "C3" "D3" "C1" "C2" "E3" "F3" "D1" "E2" "F4" "F5" "G5" "G4" "F2" "E1" "F1" "G2"
    "G3" "H3" "H5" "H4" "J4" "J5" "G1" "H2" "J3" "K3" "J1" "J2" "K1" "K2"
);

/// Terasic DE0-Nano (EP4CE22F17C6, 256-FBGA) expansion headers, from
/// Terasic's DE0-Nano pin table: GPIO_0_IN[1:0], GPIO_0[33:0],
/// GPIO_1_IN[1:0], GPIO_1[33:0], GPIO_2_IN[2:0], GPIO_2[12:0] (the `_IN`
/// pins are input only): 88 pins; then the DIP switches and LEDs.
const DE0_NANO: &[(&str, bool)] = &[
    // GPIO_0_IN[0..1] (JP1), input only
    ("PIN_A8", true),
    ("PIN_B8", true),
    // GPIO_0[0..33] (JP1)
    ("PIN_D3", false),
    ("PIN_C3", false),
    ("PIN_A2", false),
    ("PIN_A3", false),
    ("PIN_B3", false),
    ("PIN_B4", false),
    ("PIN_A4", false),
    ("PIN_B5", false),
    ("PIN_A5", false),
    ("PIN_D5", false),
    ("PIN_B6", false),
    ("PIN_A6", false),
    ("PIN_B7", false),
    ("PIN_D6", false),
    ("PIN_A7", false),
    ("PIN_C6", false),
    ("PIN_C8", false),
    ("PIN_E6", false),
    ("PIN_E7", false),
    ("PIN_D8", false),
    ("PIN_E8", false),
    ("PIN_F8", false),
    ("PIN_F9", false),
    ("PIN_E9", false),
    ("PIN_C9", false),
    ("PIN_D9", false),
    ("PIN_E11", false),
    ("PIN_E10", false),
    ("PIN_C11", false),
    ("PIN_B11", false),
    ("PIN_A12", false),
    ("PIN_D11", false),
    ("PIN_D12", false),
    ("PIN_B12", false),
    // GPIO_1_IN[0..1] (JP2), input only
    ("PIN_T9", true),
    ("PIN_R9", true),
    // GPIO_1[0..33] (JP2)
    ("PIN_F13", false),
    ("PIN_T15", false),
    ("PIN_T14", false),
    ("PIN_T13", false),
    ("PIN_R13", false),
    ("PIN_T12", false),
    ("PIN_R12", false),
    ("PIN_T11", false),
    ("PIN_T10", false),
    ("PIN_R11", false),
    ("PIN_P11", false),
    ("PIN_R10", false),
    ("PIN_N12", false),
    ("PIN_P9", false),
    ("PIN_N9", false),
    ("PIN_N11", false),
    ("PIN_L16", false),
    ("PIN_K16", false),
    ("PIN_R16", false),
    ("PIN_L15", false),
    ("PIN_P15", false),
    ("PIN_P16", false),
    ("PIN_R14", false),
    ("PIN_N16", false),
    ("PIN_N15", false),
    ("PIN_P14", false),
    ("PIN_L14", false),
    ("PIN_N14", false),
    ("PIN_M10", false),
    ("PIN_L13", false),
    ("PIN_J16", false),
    ("PIN_K15", false),
    ("PIN_J13", false),
    ("PIN_J14", false),
    // GPIO_2_IN[0..2] (JP3), input only
    ("PIN_E15", true),
    ("PIN_E16", true),
    ("PIN_M16", true),
    // GPIO_2[0..12] (JP3)
    ("PIN_A14", false),
    ("PIN_B16", false),
    ("PIN_C14", false),
    ("PIN_C16", false),
    ("PIN_C15", false),
    ("PIN_D16", false),
    ("PIN_D15", false),
    ("PIN_D14", false),
    ("PIN_F15", false),
    ("PIN_F16", false),
    ("PIN_F14", false),
    ("PIN_G16", false),
    ("PIN_G15", false),
    // When the headers run out: the board's DIP switches SW[0..3] (inputs
    // only) and LEDs LED[0..7] (outputs).
    ("PIN_M1", true),
    ("PIN_T8", true),
    ("PIN_B9", true),
    ("PIN_M15", true),
    ("PIN_A15", false),
    ("PIN_A13", false),
    ("PIN_B13", false),
    ("PIN_A11", false),
    ("PIN_D1", false),
    ("PIN_F3", false),
    ("PIN_B1", false),
    ("PIN_L3", false),
];

/// The DE0-Nano pool's header pins (the rest are switches and LEDs).
const DE0_NANO_HEADER_PINS: usize = 88;

/// iCE40 HX8K in the CT256 package.
pub const ICE40_HX8K: Board = Board {
    name: "ice40-hx8k",
    description: "Lattice iCE40-HX8K Breakout Board (iCE40HX8K-CT256)",
    notes: &[
        "clock: a 50 MHz oscillator on R9, a global buffer input (GBIN) of bank 2. The breakout's",
        "own 12 MHz oscillator (J3) is not used: the gateware's timing (FSMC, ISA, filters) is",
        "for clock_hz = 50 MHz, and a PLL would tie the wrapper to one device family.",
        "Pins: CT256 balls from the icestorm chip database, bank by bank, avoiding the board's",
        "LEDs, FTDI UART and SPI flash; which header pin each ball reaches is to be checked",
        "against the breakout's schematic. nextpnr-ice40 accepts the file without",
        "--pcf-allow-unconstrained (tests/constraints.rs).",
    ],
    clock_pin: "R9",
    pool: ICE40_CT256,
};

/// ECP5 LFE5U-25F in the CABGA256 package.
pub const ECP5_25K: Board = Board {
    name: "ecp5-25k",
    description: "Lattice ECP5 LFE5U-25F-6BG256 (CABGA256), Colorlight 5A-75B-class carrier",
    notes: &[
        "clock: a 50 MHz oscillator on P6 (LLC_GPLL0T_IN, the oscillator ball of the",
        "Colorlight 5A-75B v7/v8 with the same FPGA; that board's oscillator is 25 MHz, so a",
        "50 MHz part, or a PLL outside this wrapper, is assumed).",
        "Pins: CABGA256 user balls from Project Trellis' LFE5U-25F iodb.json, bank by bank,",
        "no configuration (bank 8) balls; all banks at 3.3 V (LVCMOS33). The 5A-75B's own",
        "connectors go through one-way 74HC245 buffers, so this map is for a carrier with",
        "direct I/O. nextpnr-ecp5 accepts the file without --lpf-allow-unconstrained",
        "(tests/constraints.rs).",
    ],
    clock_pin: "P6",
    pool: ECP5_CABGA256,
};

/// Cyclone IV E on the Terasic DE0-Nano.
pub const CYCLONE4_DE0_NANO: Board = Board {
    name: "cyclone4-de0nano",
    description: "Intel Cyclone IV E EP4CE22F17C6 (256-FBGA) on the Terasic DE0-Nano",
    notes: &[
        "clock: CLOCK_50, the DE0-Nano's 50 MHz oscillator on PIN_R8.",
        "Pins: the DE0-Nano's GPIO headers JP1 (GPIO_0), JP2 (GPIO_1) and JP3 (GPIO_2) from",
        "Terasic's pin table; *_IN pins are input only and carry inputs only. The headers have",
        "88 pins; any signal beyond them goes to the DIP switches SW[3:0] (inputs) or the",
        "LEDs LED[7:0] (outputs), marked below: rewire those before use. Not checked by",
        "Quartus here (no Quartus on the build machine): check in Quartus before use.",
    ],
    clock_pin: "PIN_R8",
    pool: DE0_NANO,
};

/// Every board with a constraint generator.
pub const BOARDS: [&Board; 3] = [&ICE40_HX8K, &ECP5_25K, &CYCLONE4_DE0_NANO];

/// The boards' names, as the configuration's `board` key takes them.
pub const BOARD_NAMES: [&str; 3] = [ICE40_HX8K.name, ECP5_25K.name, CYCLONE4_DE0_NANO.name];

/// One pin assignment: a port bit and its pin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    /// The port (for grouping and the kind).
    pub port: BoardPort,
    /// The bit's name in constraint syntax: `name` or `name[i]`.
    pub bit: String,
    pub pin: &'static str,
}

/// The pin of every port bit of `ports` on `board`, in port order; `Err`
/// names the first bit that found no pin.
pub fn assign(board: &Board, ports: &[BoardPort]) -> Result<Vec<Assignment>, String> {
    let mut used = vec![false; board.pool.len()];
    let mut out = Vec::new();
    for p in ports {
        for bit in p.bits() {
            let pin = if p.name == "clock" {
                board.clock_pin
            } else {
                let i = board
                    .pool
                    .iter()
                    .enumerate()
                    .position(|(i, (_, input_only))| {
                        let fits = !(p.kind.drives() && *input_only);
                        !used[i] && fits
                    })
                    .ok_or_else(|| {
                        format!(
                            "{}: no pin left for {bit} ({} pins in the pool)",
                            board.name,
                            board.pool.len()
                        )
                    })?;
                used[i] = true;
                board.pool[i].0
            };
            out.push(Assignment {
                port: p.clone(),
                bit,
                pin,
            });
        }
    }
    Ok(out)
}

fn config_line(config: &Config) -> String {
    format!(
        "configuration: {} axes, {}-bit counters, {} Hz, isa_ram = \"{}\"{}",
        config.axes(),
        config.counter_width(),
        config.clock_hz(),
        config.isa_ram().name(),
        if *config == Config::default() {
            " (the default)"
        } else {
            ""
        }
    )
}

fn group_title(group: &str) -> &'static str {
    match group {
        "clock" => "clock",
        "reset" => "reset (synchronous, active high)",
        "fsmc" => "MCU: STM32 FSMC (NE1, 16-bit)",
        "pulse" => "pulse outputs (F1/F2 of the pulse-mode selectors)",
        "isa" => "PC: ISA bus",
        "enc" => "encoders",
        "sram" => "external dual-port SRAM, left port",
        "estop" => "e-stop chain (high = released; pull the pin down on the board)",
        "limit" => "limit switches per axis (polarity and enable in SAFETY)",
        "home" => "home switches per axis",
        "alarm" => "drive ALARM inputs per axis",
        "drive" => "drive ENABLE outputs",
        "irq" => "IRQ to the MCU (active low after reset)",
        "dac" => {
            "servo DAC (DAC7744-style parallel: data, A1:A0, CS, R/W, LOADDACS; \
             SPI: SCLK, SDIN, SYNC, with LOADDACS as LDAC)"
        }
        _ => "other ports",
    }
}

/// Header comment lines shared by every file (without comment markers).
fn header(board: &Board, config: &Config, what: &str) -> Vec<String> {
    let mut h = vec![
        banner(),
        format!("{what} of {} for the {}", board::MODULE, board.description),
        config_line(config),
    ];
    h.extend(board.notes.iter().map(|s| s.to_string()));
    h
}

/// Writes the assignments grouped by interface, one comment per group.
fn grouped(
    assignments: &[Assignment],
    comment: &str,
    mut line: impl FnMut(&Assignment) -> Vec<String>,
) -> String {
    let mut s = String::new();
    let mut last_group = "";
    for a in assignments {
        let g = a.port.group();
        if g != last_group {
            s.push_str(&format!("\n{comment} {}\n", group_title(g)));
            last_group = g;
        }
        for l in line(a) {
            s.push_str(&l);
            s.push('\n');
        }
    }
    s
}

fn mhz(config: &Config) -> String {
    let hz = config.clock_hz();
    if hz.is_multiple_of(1_000_000) {
        format!("{}", hz / 1_000_000)
    } else {
        format!("{:.6}", hz as f64 / 1e6)
    }
}

/// nextpnr-ice40 PCF.
pub fn pcf(config: &Config, assignments: &[Assignment]) -> String {
    let mut s: String = header(&ICE40_HX8K, config, "Pin constraints (nextpnr-ice40 PCF)")
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    s.push_str(&grouped(assignments, "#", |a| {
        let mut v = vec![format!("set_io {} {}", a.bit, a.pin)];
        if a.port.name == "clock" {
            v.push(format!("set_frequency clock {}", mhz(config)));
        }
        v
    }));
    s
}

/// nextpnr-ecp5 / Diamond LPF.
pub fn lpf(config: &Config, assignments: &[Assignment]) -> String {
    let mut s: String = header(&ECP5_25K, config, "Pin constraints (LPF)")
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    s.push_str("\nBLOCK RESETPATHS;\nBLOCK ASYNCPATHS;\n");
    s.push_str(&grouped(assignments, "#", |a| {
        let mut v = vec![
            format!("LOCATE COMP \"{}\" SITE \"{}\";", a.bit, a.pin),
            format!("IOBUF PORT \"{}\" IO_TYPE=LVCMOS33;", a.bit),
        ];
        if a.port.name == "clock" {
            v.push(format!("FREQUENCY PORT \"clock\" {} MHZ;", mhz(config)));
        }
        v
    }));
    s
}

/// Quartus QSF: device, top level and pin assignments.
pub fn qsf(config: &Config, assignments: &[Assignment]) -> String {
    let mut s: String = header(&CYCLONE4_DE0_NANO, config, "Pin assignments (Quartus QSF)")
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    s.push_str(
        "# Add generated/verilog/motion_controller.v and motion_controller_board.v to the\n\
         # project (VERILOG_FILE) and the .sdc beside this file (SDC_FILE).\n\n\
         set_global_assignment -name FAMILY \"Cyclone IV E\"\n\
         set_global_assignment -name DEVICE EP4CE22F17C6\n",
    );
    s.push_str(&format!(
        "set_global_assignment -name TOP_LEVEL_ENTITY {}\n",
        board::MODULE
    ));
    s.push_str("set_global_assignment -name RESERVE_ALL_UNUSED_PINS \"AS INPUT TRI-STATED\"\n");
    s.push_str(&grouped(assignments, "#", |a| {
        let overflow = DE0_NANO
            .iter()
            .position(|(p, _)| *p == a.pin)
            .is_some_and(|i| i >= DE0_NANO_HEADER_PINS);
        let mut v = Vec::new();
        if overflow {
            v.push(format!(
                "# {} is on a DIP switch / LED of the board, not a header pin",
                a.bit
            ));
        }
        v.extend([
            format!("set_location_assignment {} -to {}", a.pin, a.bit),
            format!(
                "set_instance_assignment -name IO_STANDARD \"3.3-V LVTTL\" -to {}",
                a.bit
            ),
        ]);
        v
    }));
    s
}

/// The asynchronous inputs: every input pin of the FSMC, ISA and encoder
/// interfaces (and of the external SRAM's data), in port order. Each goes
/// through a two-flop synchroniser or is sampled only while its bus
/// protocol holds it stable.
pub fn async_inputs(ports: &[BoardPort]) -> Vec<String> {
    ports
        .iter()
        .filter(|p| matches!(p.kind, PinKind::Input | PinKind::Inout))
        .filter(|p| matches!(p.group(), "fsmc" | "isa" | "enc" | "sram"))
        .map(|p| p.name.clone())
        .collect()
}

/// Quartus / TimeQuest SDC: the clock, its uncertainty, no timing on the
/// asynchronous inputs (they end in synchronisers) nor on the bus outputs
/// (their timing is the bus protocols', many clocks long).
pub fn sdc(config: &Config, ports: &[BoardPort]) -> String {
    let mut s: String = header(&CYCLONE4_DE0_NANO, config, "Timing constraints (SDC)")
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    let period = 1e9 / config.clock_hz() as f64;
    s.push_str(&format!(
        "\n# clock: {} MHz\ncreate_clock -name clock -period {period:.3} [get_ports {{clock}}]\nderive_clock_uncertainty\n",
        mhz(config)
    ));
    s.push_str(
        "\n# Asynchronous inputs: FSMC, ISA and encoder pins go through two-flop synchronisers\n\
         # (data and address are sampled only once the synchronised strobes say they are stable),\n\
         # so no timing from the pins into the first flop.\n",
    );
    let bus = |names: &[String]| {
        names
            .iter()
            .map(|n| {
                let wide = ports.iter().any(|p| &p.name == n && p.width > 1);
                if wide {
                    format!("{n}[*]")
                } else {
                    n.clone()
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    let inputs = async_inputs(ports);
    s.push_str(&format!(
        "set_false_path -from [get_ports {{{}}}]\n",
        bus(&inputs)
    ));
    let outputs: Vec<String> = ports
        .iter()
        .filter(|p| p.kind.drives())
        .map(|p| p.name.clone())
        .collect();
    s.push_str(
        "\n# Outputs: bus data and strobes whose timing the bus protocols set (FSMC DATAST,\n\
         # ISA command length), many clocks long; not timed against the clock.\n",
    );
    s.push_str(&format!(
        "set_false_path -to [get_ports {{{}}}]\n",
        bus(&outputs)
    ));
    s.push_str(
        "\n# reset is sampled synchronously: drive it from a source synchronous to clock.\n",
    );
    s
}

/// One generated constraint file: name and contents.
pub struct ConstraintFile {
    pub name: String,
    pub text: String,
}

/// File name of `board`'s constraints with extension `ext`.
pub fn file_name(board: &Board, ext: &str) -> String {
    format!("{}_{}.{ext}", board::MODULE, board.name)
}

/// Every constraint file for `config`: the PCF, LPF, QSF and SDC whose
/// pools have room for the board's pins (all of them for the default).
pub fn files(config: &Config) -> Vec<ConstraintFile> {
    files_for(config, &board::ports(config))
}

/// [`files`] for board ports already at hand.
pub fn files_for(config: &Config, ports: &[board::BoardPort]) -> Vec<ConstraintFile> {
    let ports = ports.to_vec();
    let mut out = Vec::new();
    if let Ok(a) = assign(&ICE40_HX8K, &ports) {
        out.push(ConstraintFile {
            name: file_name(&ICE40_HX8K, "pcf"),
            text: pcf(config, &a),
        });
    }
    if let Ok(a) = assign(&ECP5_25K, &ports) {
        out.push(ConstraintFile {
            name: file_name(&ECP5_25K, "lpf"),
            text: lpf(config, &a),
        });
    }
    if let Ok(a) = assign(&CYCLONE4_DE0_NANO, &ports) {
        out.push(ConstraintFile {
            name: file_name(&CYCLONE4_DE0_NANO, "qsf"),
            text: qsf(config, &a),
        });
        out.push(ConstraintFile {
            name: file_name(&CYCLONE4_DE0_NANO, "sdc"),
            text: sdc(config, &ports),
        });
    }
    out
}

#[cfg(test)]
mod tests;
