//! A Verilated model stepped from Rust, port by port and clock by clock,
//! for testbenches that react to the design's outputs every clock (the
//! whole-controller `System` of the motion controller's checks):
//! Verilator builds the generated Verilog with a small C wrapper into a
//! shared library, which is loaded here and driven through four C calls
//! (new, set, get, eval). A clock of the 4-axis top costs a few
//! microseconds this way, against about 460 µs stepping rust-hdl.
//!
//! Builds are kept under `~/.cache/motionhdl/verilated/`, one directory per
//! hash of the Verilog, the wrapper and the Verilator version, so a
//! configuration is built once across runs, test processes and checkouts;
//! Verilator's own compiles go through ccache as the other builds do
//! ([`crate::harness::cache_verilator_build`]).

use crate::harness::{cache_verilator_build, tool, user_cache};
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_hdl::ports::PortDir;
use std::ffi::{c_void, CString};
use std::fmt::Write;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;

type NewFn = unsafe extern "C" fn() -> *mut c_void;
type FreeFn = unsafe extern "C" fn(*mut c_void);
type EvalFn = unsafe extern "C" fn(*mut c_void);
type SetFn = unsafe extern "C" fn(*mut c_void, u32, u64);
type GetFn = unsafe extern "C" fn(*mut c_void, u32) -> u64;

/// One instance of a Verilated module, its registers at their power-up
/// values (zero) until driven.
pub struct Verilated {
    library: *mut c_void,
    model: *mut c_void,
    free: FreeFn,
    eval: EvalFn,
    set: SetFn,
    get: GetFn,
    /// (name, direction, width) in the module's port order: a port's
    /// number in the C calls is its index here.
    ports: Vec<(String, PortDir, u32)>,
}

impl Verilated {
    /// Builds `module` (or finds its earlier build) and makes an instance.
    pub fn new(module: &VerilogModule) -> Result<Self, String> {
        let so = build(module)?;
        let path = CString::new(so.to_string_lossy().as_bytes()).map_err(|e| e.to_string())?;
        // SAFETY: dlopen/dlsym on a library this module built from the
        // wrapper below; every symbol is looked up by the name and type the
        // wrapper gives it, and checked for null before use.
        unsafe {
            let library = libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL);
            if library.is_null() {
                return Err(format!("dlopen {}: {}", so.display(), dl_error()));
            }
            let symbol = |name: &str| -> Result<*mut c_void, String> {
                let c = CString::new(name).expect("symbol name");
                let p = libc::dlsym(library, c.as_ptr());
                if p.is_null() {
                    Err(format!("{}: no symbol {name}", so.display()))
                } else {
                    Ok(p)
                }
            };
            let new: NewFn = std::mem::transmute::<*mut c_void, NewFn>(symbol("mh_new")?);
            let free: FreeFn = std::mem::transmute::<*mut c_void, FreeFn>(symbol("mh_free")?);
            let eval: EvalFn = std::mem::transmute::<*mut c_void, EvalFn>(symbol("mh_eval")?);
            let set: SetFn = std::mem::transmute::<*mut c_void, SetFn>(symbol("mh_set")?);
            let get: GetFn = std::mem::transmute::<*mut c_void, GetFn>(symbol("mh_get")?);
            let model = new();
            Ok(Self {
                library,
                model,
                free,
                eval,
                set,
                get,
                ports: module
                    .ports
                    .iter()
                    .map(|p| (p.name.clone(), p.dir, p.width))
                    .collect(),
            })
        }
    }

    /// The number of port `name`; panics naming it when the module has
    /// no such port.
    pub fn port(&self, name: &str) -> u32 {
        let i = self
            .ports
            .iter()
            .position(|p| p.0 == name)
            .unwrap_or_else(|| panic!("the Verilated module has no port `{name}`"));
        i as u32
    }

    /// Drives input `port` with `value` (its low `width` bits); seen at
    /// the next [`Self::eval`].
    pub fn set(&mut self, port: u32, value: u64) {
        let (name, dir, width) = &self.ports[port as usize];
        debug_assert_eq!(*dir, PortDir::Input, "{name} is not an input");
        let mask = if *width >= 64 {
            u64::MAX
        } else {
            (1 << width) - 1
        };
        // SAFETY: `model` is the live instance `mh_new` returned; `port`
        // indexes the wrapper's switch, which ignores unknown numbers.
        unsafe { (self.set)(self.model, port, value & mask) }
    }

    /// Output (or input) `port`'s value after the last [`Self::eval`].
    pub fn get(&self, port: u32) -> u64 {
        // SAFETY: as in `set`.
        unsafe { (self.get)(self.model, port) }
    }

    /// Evaluates the model: the inputs set since, every clock edge among
    /// them, and the combinational logic after.
    pub fn eval(&mut self) {
        // SAFETY: as in `set`.
        unsafe { (self.eval)(self.model) }
    }
}

impl Drop for Verilated {
    fn drop(&mut self) {
        // SAFETY: the instance is freed once, then the library's handle
        // (reference-counted by dlopen) released.
        unsafe {
            (self.free)(self.model);
            libc::dlclose(self.library);
        }
    }
}

fn dl_error() -> String {
    // SAFETY: dlerror returns null or a C string valid until the next call.
    unsafe {
        let e = libc::dlerror();
        if e.is_null() {
            "unknown error".into()
        } else {
            std::ffi::CStr::from_ptr(e).to_string_lossy().into_owned()
        }
    }
}

/// The C wrapper around `V<module>`: one Verilator context per instance,
/// and a switch over the ports by number in declaration order.
pub fn wrapper(module: &VerilogModule) -> String {
    let top = format!("V{}", module.name);
    let mut set = String::new();
    let mut get = String::new();
    for (i, p) in module.ports.iter().enumerate() {
        assert!(
            p.width <= 64,
            "{}: port {} is {} bits; the wrapper passes up to 64",
            module.name,
            p.name,
            p.width
        );
        if p.dir == PortDir::Input {
            let _ = writeln!(set, "    case {i}: t.{} = v; break;", p.name);
        }
        let _ = writeln!(get, "    case {i}: return t.{};", p.name);
    }
    format!(
        "// Rust's handle on {top} (motionhdl testbench, verilated.rs).\n\
         #include \"{top}.h\"\n#include \"verilated.h\"\n#include <cstdint>\n\
         struct Mh {{\n    VerilatedContext context;\n    {top} top;\n    \
         Mh() : top(&context, \"top\") {{}}\n}};\n\
         extern \"C\" {{\n\
         void* mh_new() {{ return new Mh; }}\n\
         void mh_free(void* p) {{ auto m = static_cast<Mh*>(p); m->top.final(); delete m; }}\n\
         void mh_eval(void* p) {{ static_cast<Mh*>(p)->top.eval(); }}\n\
         void mh_set(void* p, uint32_t i, uint64_t v) {{\n  auto& t = static_cast<Mh*>(p)->top;\n  \
         switch (i) {{\n{set}    default: break;\n  }}\n}}\n\
         uint64_t mh_get(void* p, uint32_t i) {{\n  auto& t = static_cast<Mh*>(p)->top;\n  \
         switch (i) {{\n{get}    default: return 0;\n  }}\n}}\n}}\n"
    )
}

/// The shared library of `module`, built now unless an earlier build of
/// the same text by the same Verilator is in the cache.
fn build(module: &VerilogModule) -> Result<PathBuf, String> {
    let verilator = tool("verilator")?;
    let version = Command::new(&verilator)
        .arg("--version")
        .output()
        .map_err(|e| format!("verilator --version: {e}"))?;
    let wrapper = wrapper(module);
    let mut hash = std::collections::hash_map::DefaultHasher::new();
    (&module.text, &wrapper, &version.stdout).hash(&mut hash);
    let root = user_cache().join("verilated");
    let dir = root.join(format!("{}-{:016x}", module.name, hash.finish()));
    let so = |d: &Path| d.join("obj").join("libmodel.so");
    if so(&dir).is_file() {
        return Ok(so(&dir));
    }
    std::fs::create_dir_all(&root).map_err(|e| format!("{}: {e}", root.display()))?;
    // One process builds, the others wait for it (tests run two at a time
    // and often want the same configuration first).
    let lock = std::fs::File::create(dir.with_extension("lock"))
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    let _held = Flock::exclusive(&lock);
    if so(&dir).is_file() {
        return Ok(so(&dir));
    }
    // Built beside the cache entry and renamed into it whole: a process
    // that finds the directory finds a finished library.
    let staged = root.join(format!(
        ".build-{}-{:016x}",
        std::process::id(),
        hash.finish()
    ));
    let _ = std::fs::remove_dir_all(&staged);
    std::fs::create_dir_all(&staged).map_err(|e| format!("{}: {e}", staged.display()))?;
    let v = format!("{}.v", module.name);
    std::fs::write(staged.join(&v), &module.text).map_err(|e| e.to_string())?;
    std::fs::write(staged.join("wrapper.cpp"), &wrapper).map_err(|e| e.to_string())?;
    let mut c = Command::new(&verilator);
    cache_verilator_build(&mut c);
    c.current_dir(&staged)
        .args(["--cc", "--exe", "--build", "-j", "2", "-Wno-fatal"])
        .args(["--top-module", module.name, "-Mdir", "obj"])
        .args([
            "-CFLAGS",
            "-fPIC",
            "-LDFLAGS",
            "-shared",
            "-o",
            "libmodel.so",
        ])
        .args([v.as_str(), "wrapper.cpp"]);
    if let Err(e) = crate::verilog_sim::run(&mut c, "verilator (shared library)") {
        let _ = std::fs::remove_dir_all(&staged);
        return Err(format!("{}: {e}", module.name));
    }
    if std::fs::rename(&staged, &dir).is_err() {
        // Another process finished the same build first: use its copy.
        let _ = std::fs::remove_dir_all(&staged);
    }
    if so(&dir).is_file() {
        Ok(so(&dir))
    } else {
        Err(format!("{}: no library after the build", dir.display()))
    }
}

/// An exclusive `flock` on a file, released when dropped (or when the
/// process ends).
struct Flock<'a>(&'a std::fs::File);

impl<'a> Flock<'a> {
    fn exclusive(file: &'a std::fs::File) -> Self {
        use std::os::fd::AsRawFd;
        // SAFETY: flock on a descriptor this struct borrows for its life.
        unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) };
        Self(file)
    }
}

impl Drop for Flock<'_> {
    fn drop(&mut self) {
        use std::os::fd::AsRawFd;
        // SAFETY: as in `exclusive`.
        unsafe { libc::flock(self.0.as_raw_fd(), libc::LOCK_UN) };
    }
}
