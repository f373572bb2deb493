//! The firmware driver as C firmware uses it (docs/driver.md): the
//! committed header is what cbindgen writes from the driver's C API; the C
//! unit tests, run on the host against a fake bus laid out by the generated
//! register struct, pass (and fail when the struct and the driver
//! disagree on one offset); the driver links into a Cortex-M4 firmware
//! built with Debian's arm-none-eabi-gcc, and its code size is reported.

mod common;

use common::run;
use motionhdl_testbench::c_driver::{self, HOST_LIBS};
use motionhdl_testbench::harness::{require_rust_target, require_tools};
use std::path::{Path, PathBuf};
use std::process::Command;

const THUMB: &str = "thumbv7em-none-eabihf";
/// The Cortex-M4F flags: the issue's, and the FPU's hard-float ABI that
/// thumbv7em-none-eabihf objects carry.
const ARM_FLAGS: [&str; 12] = [
    "-mcpu=cortex-m4",
    "-mthumb",
    "-mfloat-abi=hard",
    "-mfpu=fpv4-sp-d16",
    "-Os",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-std=c99",
    "-ffunction-sections",
    "-fdata-sections",
    "-Idriver/include",
];

fn root() -> PathBuf {
    c_driver::root()
}

fn driver_lib(target: Option<&str>) -> PathBuf {
    c_driver::driver_lib(target).unwrap()
}

#[test]
fn the_c_header_is_what_cbindgen_writes() {
    if require_tools(&["cbindgen"]).is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("motionhdl_driver.h");
    let (ok, o, e) = run(Command::new("cbindgen")
        .current_dir(root().join("driver"))
        .args([
            "--config",
            "cbindgen.toml",
            "--crate",
            "motionhdl-driver",
            "--output",
        ])
        .arg(&out));
    assert!(ok, "cbindgen:\n{o}{e}");
    let fresh = std::fs::read_to_string(&out).unwrap();
    let committed =
        std::fs::read_to_string(root().join("driver/include/motionhdl_driver.h")).unwrap();
    assert!(
        fresh == committed,
        "driver/include/motionhdl_driver.h is stale: run `cbindgen --config cbindgen.toml \
         --crate motionhdl-driver --output include/motionhdl_driver.h` in driver/"
    );
    for call in [
        "motionhdl_init(",
        "motionhdl_sample(",
        "motionhdl_stream_refill(",
        "motionhdl_home_poll(",
    ] {
        assert!(committed.contains(call), "no {call} in the header");
    }
}

/// Compiles the C unit tests against `regs_h`'s directory and runs them:
/// (passed, output).
fn c_unit_tests(lib: &Path, include: &Path, scratch: &Path) -> (bool, String) {
    let exe = scratch.join("test_driver");
    let (ok, o, e) = run(Command::new("gcc")
        .current_dir(root())
        .args([
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-Idriver/include",
        ])
        .arg("-I")
        .arg(include)
        .arg("driver/c/test_driver.c")
        .arg(lib)
        .args(HOST_LIBS)
        .arg("-o")
        .arg(&exe));
    assert!(ok, "gcc:\n{o}{e}");
    let (ok, o, e) = run(&mut Command::new(&exe));
    (ok, format!("{o}{e}"))
}

#[test]
fn the_c_unit_tests_pass_and_catch_a_wrong_offset() {
    if require_tools(&["gcc"]).is_none() {
        return;
    }
    let lib = driver_lib(None);
    let tmp = tempfile::tempdir().unwrap();
    let (ok, out) = c_unit_tests(&lib, &root().join("generated/include"), tmp.path());
    assert!(ok, "C unit tests:\n{out}");
    let checks: u32 = out.split(' ').next().unwrap().parse().unwrap();
    assert!(out.contains("checks, 0 failed") && checks >= 75, "{out}");
    // The register struct with SEG_RATE and SEG_ACCEL swapped, as a
    // driver with those two offsets swapped would see the card.
    let h = std::fs::read_to_string(root().join("generated/include/motionhdl_regs.h")).unwrap();
    let rate = "__O  uint32_t SEG_RATE;";
    let accel = "__O  uint32_t SEG_ACCEL;";
    assert_eq!((h.matches(rate).count(), h.matches(accel).count()), (1, 1));
    let swapped = h
        .replace(rate, "@")
        .replace(accel, rate)
        .replace('@', accel);
    let broken = tmp.path().join("broken");
    std::fs::create_dir(&broken).unwrap();
    std::fs::write(broken.join("motionhdl_regs.h"), swapped).unwrap();
    let (ok, out) = c_unit_tests(&lib, &broken, tmp.path());
    assert!(
        !ok && out.contains("SEG_RATE"),
        "the swap went unnoticed:\n{out}"
    );
    println!("C unit tests: {checks} checks pass; a swapped offset fails them");
}

/// Links `objects` into a Cortex-M4 ELF (newlib's start-up, nosys stubs,
/// unused sections dropped) and returns its text size in bytes.
fn arm_text(objects: &[&Path], keep: &[&str], elf: &Path) -> u64 {
    let mut cmd = Command::new("arm-none-eabi-gcc");
    cmd.current_dir(root()).args(&ARM_FLAGS[..4]).args(objects);
    cmd.args(["--specs=nosys.specs", "-Wl,--gc-sections"]);
    for k in keep {
        cmd.arg(format!("-Wl,--undefined={k}"));
    }
    let (ok, o, e) = run(cmd.arg("-o").arg(elf));
    assert!(ok, "arm-none-eabi-gcc link:\n{o}{e}");
    let (ok, o, e) = run(Command::new("arm-none-eabi-size").arg(elf));
    assert!(ok, "arm-none-eabi-size:\n{o}{e}");
    o.lines()
        .nth(1)
        .and_then(|l| l.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn the_driver_links_into_cortex_m4_firmware() {
    if require_tools(&["arm-none-eabi-gcc", "arm-none-eabi-size"]).is_none() {
        return;
    }
    if require_rust_target(THUMB).is_none() {
        return;
    }
    let lib = driver_lib(Some(THUMB));
    let tmp = tempfile::tempdir().unwrap();
    let compile = |src: &str, obj: &Path| {
        let (ok, o, e) = run(Command::new("arm-none-eabi-gcc")
            .current_dir(root())
            .args(ARM_FLAGS)
            .arg("-c")
            .arg(src)
            .arg("-o")
            .arg(obj));
        assert!(ok, "arm-none-eabi-gcc -c {src}:\n{o}{e}");
    };
    let example = tmp.path().join("example.o");
    compile("driver/c/example_firmware.c", &example);
    let empty_c = tmp.path().join("empty.c");
    std::fs::write(&empty_c, "int main(void) { for (;;) { } }\n").unwrap();
    let empty = tmp.path().join("empty.o");
    compile(empty_c.to_str().unwrap(), &empty);
    let header = std::fs::read_to_string(root().join("driver/include/motionhdl_driver.h")).unwrap();
    let api: Vec<&str> = header
        .lines()
        .filter_map(|l| l.split_once(" motionhdl_").map(|(_, r)| r))
        .filter_map(|r| r.split_once('(').map(|(name, _)| name))
        .collect();
    assert!(api.len() >= 25, "{} calls in the header", api.len());
    let names: Vec<String> = api.iter().map(|n| format!("motionhdl_{n}")).collect();
    let keep: Vec<&str> = names.iter().map(String::as_str).collect();
    let bare = arm_text(&[&empty], &[], &tmp.path().join("empty.elf"));
    let used = arm_text(&[&example, &lib], &[], &tmp.path().join("example.elf"));
    let all = arm_text(&[&empty, &lib], &keep, &tmp.path().join("all.elf"));
    assert!(used > bare && all > used, "sizes {bare} {used} {all}");
    println!(
        "Cortex-M4 -Os: example firmware {} bytes of driver code, the whole C API ({} calls) {} bytes (text beyond newlib's start-up, {bare} bytes)",
        used - bare,
        api.len(),
        all - bare
    );
}
