//! The board-level wrapper and its pin constraints: the committed
//! `constraints/` is what the generator writes, every port bit has exactly
//! one pin, and the wrapper lints clean. That nextpnr takes the pins
//! without being told to allow unconstrained I/O, the tri-states become
//! I/O cells with output enables and the files' clock reaches nextpnr is
//! checked on `motionhdl synth`'s run (tests/synth.rs).

mod common;

use common::run;
use motionhdl::board::{self, PinKind};
use motionhdl::{artifacts, constraints, fusesoc};
use motionhdl_model::Config;
use motionhdl_testbench::harness::require_tool;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Bit → pin from one constraint file's text, panicking on a bit given
/// twice.
fn pins_of(name: &str, text: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let (bit, pin) = match words.as_slice() {
            ["set_io", bit, pin] => (bit.to_string(), pin.to_string()),
            ["LOCATE", "COMP", bit, "SITE", pin] => (
                bit.trim_matches('"').to_string(),
                pin.trim_end_matches(';').trim_matches('"').to_string(),
            ),
            ["set_location_assignment", pin, "-to", bit] => (bit.to_string(), pin.to_string()),
            _ => continue,
        };
        assert!(
            map.insert(bit.clone(), pin).is_none(),
            "{name}: {bit} has two pins"
        );
    }
    map
}

#[test]
fn committed_constraints_are_what_the_generator_writes() {
    let config = Config::default();
    let files = constraints::files(&config);
    assert_eq!(
        files.len(),
        2,
        "pcf and lpf for the default (the DE0-Nano holds 2 axes without GPIO)"
    );
    let dir = root().join("constraints");
    for f in &files {
        let committed = std::fs::read_to_string(dir.join(&f.name)).unwrap_or_else(|e| {
            panic!(
                "constraints/{}: {e}; run `motionhdl generate` and copy generated/constraints/",
                f.name
            )
        });
        assert!(
            committed == f.text,
            "constraints/{} differs from the generator: copy generated/constraints/* to constraints/",
            f.name
        );
        assert!(
            f.text.contains(&motionhdl_hdl::banner()),
            "{} lacks the banner",
            f.name
        );
    }
    // Nothing stale: every file there (but the README) is generated.
    let names: BTreeSet<String> = files.iter().map(|f| f.name.clone()).collect();
    for e in std::fs::read_dir(&dir).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().to_string();
        assert!(
            n == "README.md" || names.contains(&n),
            "constraints/{n} is not generated"
        );
    }
    // And generate writes the same into generated/constraints/.
    let generated: Vec<_> = artifacts::fpga_flow(
        &config,
        &motionhdl_hdl::catalog::motion_controller(&config).ports,
    )
    .into_iter()
    .filter(|a| a.path.starts_with("constraints"))
    .collect();
    assert_eq!(generated.len(), files.len());
    for a in generated {
        let name = a.path.file_name().unwrap().to_string_lossy().to_string();
        let f = files.iter().find(|f| f.name == name).unwrap();
        assert_eq!(a.contents, f.text.as_bytes());
    }
    // Deterministic.
    let again = constraints::files(&config);
    for (a, b) in files.iter().zip(&again) {
        assert_eq!(a.text, b.text);
    }
}

#[test]
fn every_port_bit_has_exactly_one_pin_and_no_pin_is_shared() {
    let config = Config::default();
    let ports = board::ports(&config);
    let bits: BTreeSet<String> = ports.iter().flat_map(|p| p.bits()).collect();
    assert!(bits.len() >= 84, "{} pins", bits.len());
    for f in constraints::files(&config) {
        if f.name.ends_with(".sdc") {
            continue;
        }
        let map = pins_of(&f.name, &f.text);
        let got: BTreeSet<String> = map.keys().cloned().collect();
        assert_eq!(
            got, bits,
            "{}: port bits and constrained bits differ",
            f.name
        );
        let pins: BTreeSet<&String> = map.values().collect();
        assert_eq!(pins.len(), map.len(), "{}: a pin is used twice", f.name);
    }
}

#[test]
fn inputs_only_pins_carry_inputs_only() {
    // Two axes without the general-purpose I/O: the most whose 94 pins fit
    // the DE0-Nano's headers, DIP switches and LEDs (the default's 146 do
    // not).
    let config = Config::default()
        .with_axes(2)
        .and_then(|c| c.with_gpio_pins(0, 0))
        .unwrap();
    let ports = board::ports(&config);
    let a = constraints::assign(&constraints::CYCLONE4_DE0_NANO, &ports).unwrap();
    for x in a {
        let input_only = constraints::CYCLONE4_DE0_NANO
            .pool
            .iter()
            .any(|(p, i)| *p == x.pin && *i);
        assert!(
            !(input_only && x.port.kind.drives()),
            "{} drives but is on input-only {}",
            x.bit,
            x.pin
        );
    }
}

#[test]
fn sdc_has_the_clock_uncertainty_and_false_paths_from_async_inputs() {
    let config = Config::default();
    let ports = board::ports(&config);
    let sdc = constraints::sdc(&config, &ports);
    assert!(sdc.contains("create_clock -name clock -period 20.000 [get_ports {clock}]"));
    assert!(sdc.contains("derive_clock_uncertainty"));
    let line = sdc
        .lines()
        .find(|l| l.starts_with("set_false_path -from"))
        .unwrap();
    for p in &ports {
        let listed =
            line.contains(&format!(" {}", p.name)) || line.contains(&format!("{{{}", p.name));
        let is_async = matches!(p.kind, PinKind::Input | PinKind::Inout)
            && ["fsmc_", "isa_", "enc_"]
                .iter()
                .any(|s| p.name.starts_with(s));
        assert_eq!(
            listed, is_async,
            "{} in the input false path: {line}",
            p.name
        );
    }
    let lpf = constraints::files(&config)
        .into_iter()
        .find(|f| f.name.ends_with(".lpf"))
        .unwrap();
    assert!(lpf.text.contains("FREQUENCY PORT \"clock\" 50 MHZ;"));
}

fn scratch(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("motionhdl-{tag}-"))
        .tempdir()
        .unwrap()
}

/// Writes the top and the wrapper for `config` into `dir`.
fn write_sources(dir: &Path, config: &Config) -> [String; 2] {
    let top = motionhdl_hdl::catalog::motion_controller(config);
    std::fs::write(dir.join("motion_controller.v"), top.text).unwrap();
    std::fs::write(
        dir.join("motion_controller_board.v"),
        board::wrapper(config),
    )
    .unwrap();
    [
        "motion_controller.v".into(),
        "motion_controller_board.v".into(),
    ]
}

/// Both files together lint clean. The external-RAM top on its own has
/// Verilator UNUSEDSIGNAL warnings of its own (`mcu_ram_*`, in
/// motion_controller.v, not this wrapper), so for that build only warnings
/// in the wrapper's file count.
#[test]
fn wrapper_lints_clean_in_verilator_and_icarus_for_both_builds() {
    let (Some(verilator), Some(iverilog)) = (require_tool("verilator"), require_tool("iverilog"))
    else {
        return;
    };
    for isa_ram in ["internal", "external"] {
        let config =
            motionhdl::config_file::parse(&format!("isa_ram = \"{isa_ram}\""), "t").unwrap();
        let dir = scratch("lint");
        let files = write_sources(dir.path(), &config);
        let (ok, out, err) = run(Command::new(&verilator)
            .current_dir(dir.path())
            .args(["--lint-only", "-Wall", "--top-module", board::MODULE])
            .args(&files));
        let text = out + &err;
        if isa_ram == "internal" {
            assert!(
                ok && text.trim().is_empty(),
                "verilator ({isa_ram}):\n{text}"
            );
        } else {
            assert!(
                !text.contains("motion_controller_board.v"),
                "verilator ({isa_ram}):\n{text}"
            );
        }
        let (ok, out, err) = run(Command::new(&iverilog)
            .current_dir(dir.path())
            .args(["-Wall", "-o", "a.out", "-s", board::MODULE])
            .args(&files));
        let text = out + &err;
        assert!(
            ok && text.trim().is_empty(),
            "iverilog ({isa_ram}):\n{text}"
        );
    }
}

#[test]
fn external_ram_build_has_the_sram_data_pins_as_inout() {
    let config = motionhdl::config_file::parse("isa_ram = \"external\"", "t").unwrap();
    let ports = board::ports(&config);
    let sram_d = ports.iter().find(|p| p.name == "sram_d").unwrap();
    assert_eq!((sram_d.kind, sram_d.width), (PinKind::Inout, 16));
    let text = board::wrapper(&config);
    assert!(text.contains("assign sram_d = sram_d_oe ? sram_d_out : 16'bz;"));
}

#[test]
fn fusesoc_core_is_yaml_and_names_existing_generated_files() {
    let config = Config::default();
    let names: Vec<String> = constraints::files(&config)
        .into_iter()
        .map(|f| f.name)
        .collect();
    let text = fusesoc::core(&config, &names);
    let committed =
        std::fs::read_to_string(root().join("generated").join(fusesoc::FILE_NAME)).unwrap();
    assert_eq!(
        committed, text,
        "generated/motionhdl.core is stale: run motionhdl generate"
    );
    // FuseSoC takes the first word of the first line as the format.
    assert_eq!(text.split_whitespace().next(), Some("CAPI=2:"));
    assert!(text
        .lines()
        .next()
        .unwrap()
        .contains(&motionhdl_hdl::banner()));
    let Some(python) = require_tool("python3") else {
        return;
    };
    let dir = scratch("core");
    let core = dir.path().join("motionhdl.core");
    std::fs::write(&core, &text).unwrap();
    let out = Command::new(python)
        .args([
            "-c",
            "import json, sys, yaml; print(json.dumps(yaml.safe_load(open(sys.argv[1]))))",
            core.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if stderr.contains("No module named 'yaml'") {
        motionhdl_testbench::harness::skip_test("python3 has no yaml module (python3-yaml)");
        return;
    }
    assert!(out.status.success(), "not YAML: {stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["name"], format!("::motionhdl:{}", motionhdl_hdl::VERSION));
    let mut files = Vec::new();
    for (_, fs) in v["filesets"].as_object().unwrap() {
        for f in fs["files"].as_array().unwrap() {
            match f {
                serde_json::Value::String(s) => files.push(s.clone()),
                serde_json::Value::Object(o) => files.extend(o.keys().cloned()),
                other => panic!("bad file entry {other}"),
            }
        }
    }
    // Verilog and the iCE40 and ECP5 constraints (no DE0-Nano at 4 axes).
    assert!(files.len() >= 4, "{files:?}");
    for f in &files {
        assert!(
            root().join("generated").join(f).is_file(),
            "motionhdl.core names {f}, not in generated/"
        );
    }
    for t in ["default", "lint", "synth"] {
        assert!(v["targets"][t].is_object(), "no target {t}");
    }
    // Edalize's flow API; only Quartus, which has no flow, keeps the
    // deprecated tool API (tests/fusesoc.rs runs the flows).
    for (t, flow) in [
        ("default", "lint"),
        ("lint", "lint"),
        ("synth", "icestorm"),
        ("synth_ecp5", "trellis"),
    ] {
        assert_eq!(v["targets"][t]["flow"], flow, "target {t}");
        assert!(v["targets"][t]["default_tool"].is_null(), "target {t}");
        assert_eq!(v["targets"][t]["toplevel"], board::MODULE);
    }
    assert_eq!(v["targets"]["lint"]["flow_options"]["tool"], "verilator");
    let seed = format!("{}", fusesoc::SEED);
    let pnr = v["targets"]["synth"]["flow_options"]["nextpnr_options"]
        .as_array()
        .unwrap();
    assert!(
        pnr.windows(2)
            .any(|w| w[0] == "--seed" && w[1] == seed.as_str()),
        "{pnr:?}"
    );
}
