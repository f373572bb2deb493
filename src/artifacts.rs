//! Everything `motionhdl generate` writes, computed in memory first so that
//! any error happens before a byte is written.

use motionhdl_hdl::{banner, catalog, VERSION};
use motionhdl_model::Config;
use motionhdl_testbench::scenarios;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One generated file: path relative to the output directory, and contents.
pub struct Artifact {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}

/// Whether `generate` writes the scenario traces (`vcd/`): simulating the
/// whole controller for them is most of its time, so `--no-traces` leaves
/// them out for a quick regeneration of everything else.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Traces {
    Write,
    Leave,
}

/// Every generated file for `config`, in a fixed order.
pub fn all(config: &Config) -> Vec<Artifact> {
    with_traces(config, Traces::Write)
}

/// Every generated file but the traces (`generate --no-traces`), in the
/// same order as [`all`].
pub fn without_traces(config: &Config) -> Vec<Artifact> {
    with_traces(config, Traces::Leave)
}

/// The generated files for `config`, with or without the traces.
pub fn with_traces(config: &Config, traces_too: Traces) -> Vec<Artifact> {
    let mut out = Vec::new();
    let modules = catalog::all(config);
    for m in &modules {
        out.push(Artifact {
            path: PathBuf::from("verilog").join(format!("{}.v", m.name)),
            contents: m.text.clone().into_bytes(),
        });
    }
    if traces_too == Traces::Write {
        out.extend(traces(config));
    }
    out.push(Artifact {
        path: PathBuf::from("include").join("motionhdl_config.h"),
        contents: config_header(config).into_bytes(),
    });
    out.push(Artifact {
        path: PathBuf::from("include").join(crate::isa_header::FILE_NAME),
        contents: crate::isa_header::isa_header().into_bytes(),
    });
    out.extend(regmap_exports(config));
    let top = modules
        .iter()
        .find(|m| m.name == "motion_controller")
        .expect("the catalog has the top level");
    out.extend(fpga_flow(config, &top.ports));
    out
}

/// Every scenario's trace and GTKWave save file, in `SCENARIOS` order.
/// The whole-controller scenarios are most of `generate`'s time and do
/// not depend on each other, so they run on every core; the files are the
/// same whatever the thread count.
fn traces(config: &Config) -> Vec<Artifact> {
    let list = scenarios::SCENARIOS;
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut done: Vec<(usize, Vec<Artifact>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers.min(list.len()))
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(s) = list.get(i) else { break mine };
                        mine.push((i, trace_files(s, config)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    done.sort_by_key(|(i, _)| *i);
    assert_eq!(done.len(), list.len(), "every scenario traced once");
    done.into_iter().flat_map(|(_, files)| files).collect()
}

/// One scenario's files, simulated once per test run: a run's processes
/// share them through `MOTIONHDL_RUN_CACHE` when it is set
/// (`harness::run_cached`; scripts/test sets it, `generate` alone does
/// not).
fn trace_files(s: &scenarios::Scenario, config: &Config) -> Vec<Artifact> {
    let key = (VERSION, s.name, format!("{config:?}"));
    let packed = motionhdl_testbench::harness::run_cached("traces", &key, || {
        Ok::<_, std::convert::Infallible>(pack(&simulate_trace(s, config)))
    });
    let packed = packed.unwrap_or_else(|never| match never {});
    unpack(&packed).unwrap_or_else(|| simulate_trace(s, config))
}

/// One scenario's save file, its plot if it draws one, and its trace.
fn simulate_trace(s: &scenarios::Scenario, config: &Config) -> Vec<Artifact> {
    let trace = s.trace(config);
    let vcd = format!("{}.vcd", s.name);
    let mut files = vec![Artifact {
        path: PathBuf::from("vcd").join(format!("{}.gtkw", s.name)),
        contents: trace.to_gtkw(&vcd).into_bytes(),
    }];
    if let Some(svg) = trace.plot() {
        files.push(Artifact {
            path: PathBuf::from("vcd").join(format!("{}.svg", s.name)),
            contents: svg.as_bytes().to_vec(),
        });
    }
    files.push(Artifact {
        path: PathBuf::from("vcd").join(vcd),
        contents: trace.to_vcd_string().into_bytes(),
    });
    files
}

/// `files` as one byte string: per file, its path and length on a line,
/// then its bytes.
fn pack(files: &[Artifact]) -> Vec<u8> {
    let mut out = Vec::new();
    for f in files {
        out.extend(format!("{}\t{}\n", f.path.display(), f.contents.len()).into_bytes());
        out.extend(&f.contents);
    }
    out
}

/// [`pack`]'s files again; `None` for bytes it did not write.
fn unpack(mut bytes: &[u8]) -> Option<Vec<Artifact>> {
    let mut files = Vec::new();
    while !bytes.is_empty() {
        let eol = bytes.iter().position(|&b| b == b'\n')?;
        let (path, len) = std::str::from_utf8(&bytes[..eol]).ok()?.split_once('\t')?;
        let len: usize = len.parse().ok()?;
        let rest = bytes.get(eol + 1..)?;
        files.push(Artifact {
            path: PathBuf::from(path),
            contents: rest.get(..len)?.to_vec(),
        });
        bytes = &rest[len..];
    }
    Some(files)
}

/// The FPGA flow's files for the top level with ports `top`: the
/// board-level wrapper, its pin and timing constraints (for the boards
/// whose pins suffice) and the FuseSoC core.
pub fn fpga_flow(config: &Config, top: &[crate::board::CorePort]) -> Vec<Artifact> {
    let mut out = vec![Artifact {
        path: PathBuf::from("verilog").join(format!("{}.v", crate::board::MODULE)),
        contents: crate::board::wrapper_for(top, config).into_bytes(),
    }];
    let constraints =
        crate::constraints::files_for(config, &crate::board::board_ports(top, config));
    for f in &constraints {
        out.push(Artifact {
            path: PathBuf::from("constraints").join(&f.name),
            contents: f.text.clone().into_bytes(),
        });
    }
    let names: Vec<String> = constraints.iter().map(|f| f.name.clone()).collect();
    out.push(Artifact {
        path: PathBuf::from(crate::fusesoc::FILE_NAME),
        contents: crate::fusesoc::core(config, &names).into_bytes(),
    });
    out
}

/// The MCU register map's exports, all from `regmap::mcu_map(config)`: the
/// C header and its self-test, CMSIS-SVD, JSON, Markdown and a Rust module.
pub fn regmap_exports(config: &Config) -> Vec<Artifact> {
    use crate::regmap_export::{c_header, json, markdown, rust_module, selftest, svd};
    let map = motionhdl_model::regmap::mcu_map(config);
    let file = |path: PathBuf, text: String| Artifact {
        path,
        contents: text.into_bytes(),
    };
    vec![
        file(
            PathBuf::from("include").join(c_header::FILE_NAME),
            c_header::header(&map),
        ),
        file(
            PathBuf::from("test").join(selftest::FILE_NAME),
            selftest::program(&map),
        ),
        file(PathBuf::from(svd::FILE_NAME), svd::svd(&map)),
        file(PathBuf::from(json::FILE_NAME), json::json(&map)),
        file(PathBuf::from(json::SCHEMA_FILE_NAME), json::schema()),
        file(PathBuf::from(markdown::FILE_NAME), markdown::markdown(&map)),
        file(
            PathBuf::from("rust").join(rust_module::FILE_NAME),
            rust_module::module(&map),
        ),
    ]
}

/// The build configuration as a C header, so firmware can check at compile
/// time that it matches the gateware it talks to.
pub fn config_header(config: &Config) -> String {
    use crate::c_writer::{comment, define, line, IntWidth::Bits32};
    let mut o = String::new();
    comment(&mut o, "", &banner());
    comment(
        &mut o,
        "",
        "motionhdl_config.h: build configuration of the motionhdl gateware.",
    );
    line(&mut o, "#ifndef MOTIONHDL_CONFIG_H");
    line(&mut o, "#define MOTIONHDL_CONFIG_H");
    o.push('\n');
    line(&mut o, "#include <stdint.h>");
    o.push('\n');
    define(&mut o, "MOTIONHDL_VERSION", &format!("\"{VERSION}\""));
    o.push('\n');
    comment(
        &mut o,
        "",
        "Number of axes in the counter bank and pulse generators.",
    );
    define(&mut o, "MOTIONHDL_AXES", &Bits32.dec(config.axes()));
    comment(
        &mut o,
        "",
        "Counter width in bits; counts wrap modulo 2^width and read sign-extended.",
    );
    define(
        &mut o,
        "MOTIONHDL_COUNTER_WIDTH",
        &Bits32.dec(config.counter_width()),
    );
    comment(&mut o, "", "FPGA clock frequency in Hz.");
    // `ul`: the clock needs 32 bits even where int has 16.
    define(
        &mut o,
        "MOTIONHDL_CLOCK_HZ",
        &format!("{}ul", config.clock_hz()),
    );
    o.push('\n');
    comment(
        &mut o,
        "",
        "Pulse-mode selector K input (74LS153 wiring of the dual-CPU seed card).",
    );
    define(
        &mut o,
        "MOTIONHDL_PULSE_MODE_PULSE_DIR",
        "0u /* F1 = pulse, F2 = direction */",
    );
    define(
        &mut o,
        "MOTIONHDL_PULSE_MODE_CW_CCW",
        "1u    /* F1 = CW pulses, F2 = CCW pulses */",
    );
    o.push('\n');
    line(&mut o, "#endif /* MOTIONHDL_CONFIG_H */");
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_files_unpack_whole_and_a_cut_copy_is_refused() {
        let files = vec![
            Artifact {
                path: PathBuf::from("vcd/a.gtkw"),
                contents: b"[dumpfile] \"a.vcd\"\n".to_vec(),
            },
            Artifact {
                path: PathBuf::from("vcd/a.vcd"),
                contents: vec![0, b'\n', b'\t', 255],
            },
        ];
        let packed = pack(&files);
        let back = unpack(&packed).expect("unpacks");
        assert_eq!(back.len(), 2);
        for (a, b) in files.iter().zip(&back) {
            assert_eq!((&a.path, &a.contents), (&b.path, &b.contents));
        }
        for cut in 1..packed.len() {
            let got = unpack(&packed[..cut]);
            let whole_files = got.as_ref().map_or(0, Vec::len);
            assert!(got.is_none() || whole_files == 1, "cut at {cut}");
        }
    }
}
