//! Our VCD writer: a real timescale, signals named as the ports, one scope
//! per block. Deterministic: no `$date`, the banner as the first comment.

use std::collections::BTreeMap;
use std::io::{self, Write};
use vcd::{IdCode, TimescaleUnit, Value};

/// Handle of one traced signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SignalId(usize);

struct SignalDef {
    scope: Vec<String>,
    name: String,
    width: u32,
    /// Shown as an analog curve in the save file: `Some(signed)`.
    analog: Option<bool>,
}

impl SignalDef {
    /// `scope.name`, the way GTKWave and [`Trace::mark_edge`] name it.
    fn path(&self) -> String {
        let mut n = self.scope.join(".");
        if !n.is_empty() {
            n.push('.');
        }
        n + &self.name
    }

    /// The name in a save file: the path, with `[msb:0]` on a vector.
    fn gtkw_name(&self) -> String {
        if self.width > 1 {
            format!("{}[{}:0]", self.path(), self.width - 1)
        } else {
            self.path()
        }
    }
}

/// A trace under construction: declare signals, then record values at
/// times in nanoseconds. Only changes are written.
pub struct Trace {
    banner: String,
    signals: Vec<SignalDef>,
    /// time -> signal -> value; later writes at the same time win.
    changes: BTreeMap<u64, BTreeMap<SignalId, u64>>,
    /// Time unit: nanoseconds, or picoseconds for traces with events
    /// between whole nanoseconds.
    unit: TimescaleUnit,
    /// A picture of the run (SVG), written beside the trace.
    plot: Option<String>,
    /// GTKWave named markers at the scenario's events: (time, name).
    markers: Vec<(u64, String)>,
}

/// GTKWave has 26 named markers, A to Z.
pub const MAX_MARKERS: usize = 26;

impl Trace {
    pub fn new(banner: impl Into<String>) -> Self {
        Self {
            banner: banner.into(),
            signals: Vec::new(),
            changes: BTreeMap::new(),
            unit: TimescaleUnit::NS,
            plot: None,
            markers: Vec::new(),
        }
    }

    /// A trace whose times are in picoseconds.
    pub fn new_ps(banner: impl Into<String>) -> Self {
        Self {
            unit: TimescaleUnit::PS,
            ..Self::new(banner)
        }
    }

    /// Declares a signal `name` of `width` bits inside the scope path
    /// `scope` (outermost first).
    pub fn signal(&mut self, scope: &[&str], name: &str, width: u32) -> SignalId {
        assert!(
            (1..=64).contains(&width),
            "signal {name}: width {width} not in 1..=64"
        );
        self.signals.push(SignalDef {
            scope: scope.iter().map(|s| s.to_string()).collect(),
            name: name.into(),
            width,
            analog: None,
        });
        SignalId(self.signals.len() - 1)
    }

    /// A signal for a quantity (a position, a voltage): recorded with
    /// [`Trace::set_quantity`], shown as a signed decimal analog curve.
    pub fn analog(&mut self, scope: &[&str], name: &str, width: u32) -> SignalId {
        let id = self.signal(scope, name, width);
        self.signals[id.0].analog = Some(true);
        id
    }

    /// A quantity that is never negative (a DAC code): an unsigned
    /// decimal analog curve.
    pub fn analog_unsigned(&mut self, scope: &[&str], name: &str, width: u32) -> SignalId {
        let id = self.signal(scope, name, width);
        self.signals[id.0].analog = Some(false);
        id
    }

    /// Records the quantity `value` on `id` at `time_ns`: two's
    /// complement on a signed signal ([`Trace::analog`]), as it is on the
    /// others, which it must fit.
    pub fn set_quantity(&mut self, time_ns: u64, id: SignalId, value: i64) {
        let s = &self.signals[id.0];
        if s.analog != Some(true) {
            let v = u64::try_from(value)
                .unwrap_or_else(|_| panic!("{}: {value} on an unsigned signal", s.name));
            return self.set(time_ns, id, v);
        }
        let half = 1i128 << (s.width - 1);
        assert!(
            (-half..half).contains(&i128::from(value)),
            "value {value} does not fit {} ({} bits, signed)",
            s.name,
            s.width
        );
        let mask = if s.width == 64 {
            u64::MAX
        } else {
            (1u64 << s.width) - 1
        };
        self.set(time_ns, id, value as u64 & mask);
    }

    /// Attaches a picture of the run (an SVG document).
    pub fn set_plot(&mut self, svg: String) {
        self.plot = Some(svg);
    }

    /// The picture of the run, if the scenario draws one.
    pub fn plot(&self) -> Option<&str> {
        self.plot.as_deref()
    }

    /// Names the event at `time` (the trace's unit) with a GTKWave named
    /// marker; the save file letters them A, B, .. in time order.
    pub fn mark(&mut self, time: u64, name: &str) {
        assert!(
            self.markers.len() < MAX_MARKERS,
            "marker {name}: GTKWave has only {MAX_MARKERS} named markers"
        );
        assert!(
            !name.is_empty() && name.bytes().all(|b| b.is_ascii_graphic() || b == b' '),
            "marker {name:?}: printable ASCII on one line"
        );
        self.markers.push((time, name.to_string()));
    }

    /// Names the first edge of signal `path` (`scope.name`) to `value`
    /// at or after `after` (a change from another value; the first
    /// recorded value is no edge) and returns its time. Panics when there
    /// is none: a marker names an event the trace shows.
    pub fn mark_edge(&mut self, path: &str, value: u64, after: u64, name: &str) -> u64 {
        let i = self
            .signals
            .iter()
            .position(|s| s.path() == path)
            .unwrap_or_else(|| panic!("marker {name}: no signal {path}"));
        let mut last = None;
        let mut edge = None;
        for (t, changes) in &self.changes {
            if let Some(&v) = changes.get(&SignalId(i)) {
                if *t >= after && v == value && last.is_some_and(|l| l != value) {
                    edge = Some(*t);
                    break;
                }
                last = Some(v);
            }
        }
        let t = edge.unwrap_or_else(|| panic!("marker {name}: {path} never goes to {value}"));
        self.mark(t, name);
        t
    }

    /// The named markers, in time order: (letter, time, name).
    pub fn markers(&self) -> Vec<(char, u64, &str)> {
        let mut m: Vec<(u64, &str)> = self.markers.iter().map(|(t, n)| (*t, n.as_str())).collect();
        m.sort();
        m.into_iter()
            .zip('A'..='Z')
            .map(|((t, n), letter)| (letter, t, n))
            .collect()
    }

    /// Records `value` on `id` at `time_ns` (picoseconds for a trace made
    /// with [`Trace::new_ps`]).
    pub fn set(&mut self, time_ns: u64, id: SignalId, value: u64) {
        let w = self.signals[id.0].width;
        assert!(
            w == 64 || value < (1u64 << w),
            "value {value} does not fit {} ({w} bits)",
            self.signals[id.0].name
        );
        self.changes.entry(time_ns).or_default().insert(id, value);
    }

    /// Writes the VCD file.
    pub fn write(&self, out: &mut impl Write) -> io::Result<()> {
        // The banner on the first line, as every generated file has it.
        // VCD is ASCII: GTKWave rejects the whole file over one other byte.
        assert!(!self.banner.contains("$end") && !self.banner.contains('\n'));
        assert!(
            self.banner.is_ascii(),
            "VCD text must be ASCII: {}",
            self.banner
        );
        writeln!(out, "$comment {} $end", self.banner)?;
        let mut w = vcd::Writer::new(out);
        w.timescale(1, self.unit)?;
        // Declare in scope order so each scope is opened once.
        let mut order: Vec<usize> = (0..self.signals.len()).collect();
        order.sort_by(|a, b| {
            self.signals[*a]
                .scope
                .cmp(&self.signals[*b].scope)
                .then(a.cmp(b))
        });
        let mut ids: BTreeMap<usize, IdCode> = BTreeMap::new();
        let mut open: Vec<String> = Vec::new();
        for i in order {
            let s = &self.signals[i];
            let common = open
                .iter()
                .zip(&s.scope)
                .take_while(|(a, b)| a == b)
                .count();
            while open.len() > common {
                w.upscope()?;
                open.pop();
            }
            for name in &s.scope[common..] {
                w.add_module(name)?;
                open.push(name.clone());
            }
            ids.insert(i, w.add_wire(s.width, &s.name)?);
        }
        while open.pop().is_some() {
            w.upscope()?;
        }
        w.enddefinitions()?;
        let mut last: BTreeMap<SignalId, u64> = BTreeMap::new();
        let mut first = true;
        for (t, changes) in &self.changes {
            let changed: Vec<(&SignalId, &u64)> = changes
                .iter()
                .filter(|(id, v)| last.get(id) != Some(v))
                .collect();
            if changed.is_empty() {
                continue;
            }
            w.timestamp(*t)?;
            if first {
                // Every signal gets a value at the first timestamp.
                for i in 0..self.signals.len() {
                    let v = changes.get(&SignalId(i)).copied().unwrap_or(0);
                    self.emit(&mut w, ids[&i], i, v)?;
                    last.insert(SignalId(i), v);
                }
                first = false;
                continue;
            }
            for (id, v) in changed {
                self.emit(&mut w, ids[&id.0], id.0, *v)?;
                last.insert(*id, *v);
            }
        }
        Ok(())
    }

    fn emit<W: Write>(
        &self,
        w: &mut vcd::Writer<W>,
        code: IdCode,
        i: usize,
        v: u64,
    ) -> io::Result<()> {
        let width = self.signals[i].width;
        if width == 1 {
            w.change_scalar(code, Value::from(v != 0))
        } else {
            w.change_vector(
                code,
                (0..width).rev().map(|b| Value::from((v >> b) & 1 != 0)),
            )
        }
    }

    /// A GTKWave save file for this trace written as `vcd_file`: every
    /// signal, one group per scope (per axis, per block), in declaration
    /// order, one-bit signals in binary, wider ones in hex and quantities
    /// as analog curves, zoomed to show the whole run, with the named
    /// markers, and the groups of scopes the run does not use (no signal
    /// ever leaves its first value) closed, so the trace opens ready to
    /// read (`gtkwave NAME.gtkw`).
    pub fn to_gtkw(&self, vcd_file: &str) -> String {
        // GTKWave trace flags: 0x20 right-justify, 0x8 binary, 0x2 hex;
        // group begin 0x800000 and end 0x1000000, each with blank 0x200.
        const BINARY: &str = "@28";
        const HEX: &str = "@22";
        // Analog step 0x8000, (signed 0x400,) decimal 0x4, right-justify;
        // each blank-stretch line 0x20000 makes the curve a row taller.
        const ANALOG_SIGNED: &str = "@8424";
        const ANALOG_UNSIGNED: &str = "@8024";
        const TALLER: &str = "@20000\n-\n-\n-\n-\n-\n";
        // A closed group adds 0x400000 to both ends, its end also 0x1000
        // (collapsed).
        const GROUP_BEGIN: &str = "@800200";
        const GROUP_END: &str = "@1000200";
        const CLOSED_BEGIN: &str = "@c00200";
        const CLOSED_END: &str = "@1401200";
        let mut out = format!(
            "[*] {}\n[dumpfile] \"{vcd_file}\"\n[timestart] 0\n[size] 1600 900\n\
             [signals_width] 260\n[sst_expanded] 1\n[sst_width] 220\n{}\n",
            self.banner,
            self.zoom_and_markers()
        );
        for (letter, _, name) in self.markers() {
            out += &format!("[markername] {letter}{name}\n");
        }
        let unused = self.unused_scopes();
        let mut order: Vec<usize> = (0..self.signals.len()).collect();
        order.sort_by(|a, b| {
            self.signals[*a]
                .scope
                .cmp(&self.signals[*b].scope)
                .then(a.cmp(b))
        });
        let group_end = |g: &str| {
            let flags = if unused.contains(g) {
                CLOSED_END
            } else {
                GROUP_END
            };
            format!("{flags}\n-{g}\n")
        };
        let mut group: Option<String> = None;
        for i in order {
            let s = &self.signals[i];
            let scope = s.scope.join(".");
            if group.as_deref() != Some(scope.as_str()) {
                if let Some(g) = group.take() {
                    out += &group_end(&g);
                }
                let begin = if unused.contains(&scope) {
                    CLOSED_BEGIN
                } else {
                    GROUP_BEGIN
                };
                out += &format!("{begin}\n-{scope}\n");
                group = Some(scope.clone());
            }
            if let Some(signed) = s.analog {
                let flags = if signed {
                    ANALOG_SIGNED
                } else {
                    ANALOG_UNSIGNED
                };
                out += &format!("{flags}\n{}[{}:0]\n{TALLER}", s.path(), s.width - 1);
            } else if s.width == 1 {
                out += &format!("{BINARY}\n{}\n", s.gtkw_name());
            } else {
                out += &format!("{HEX}\n{}\n", s.gtkw_name());
            }
        }
        if let Some(g) = group {
            out += &group_end(&g);
        }
        out
    }

    /// Scopes (as `a.b`) none of whose signals ever leaves the value it
    /// has at the first recorded time: the channels or axes a scenario
    /// does not use.
    pub fn unused_scopes(&self) -> std::collections::BTreeSet<String> {
        let mut first: BTreeMap<SignalId, u64> = BTreeMap::new();
        let mut varies = vec![false; self.signals.len()];
        for changes in self.changes.values() {
            for (id, v) in changes {
                if *first.entry(*id).or_insert(*v) != *v {
                    varies[id.0] = true;
                }
            }
        }
        let mut used = std::collections::BTreeSet::new();
        let mut all = std::collections::BTreeSet::new();
        for (s, v) in self.signals.iter().zip(varies) {
            all.insert(s.scope.join("."));
            if v {
                used.insert(s.scope.join("."));
            }
        }
        all.difference(&used).cloned().collect()
    }

    /// GTKWave's zoom and marker line: time units per pixel are 2^-zoom,
    /// so the run from 0 to its last change fits in 1000 of the ~1100
    /// pixels of wave area the save file's window has; no primary marker,
    /// then the 26 named markers' times (-1 = unset).
    fn zoom_and_markers(&self) -> String {
        const WAVE_PIXELS: f64 = 1000.0;
        let end = self.changes.keys().next_back().copied().unwrap_or(0).max(1);
        // (+ 0.0: no "-0" in the file.)
        let zoom = -(end as f64 / WAVE_PIXELS).log2().ceil() + 0.0;
        let mut times = vec![-1i128; MAX_MARKERS];
        for (i, (_, t, _)) in self.markers().into_iter().enumerate() {
            times[i] = i128::from(t);
        }
        let named: Vec<String> = times.iter().map(i128::to_string).collect();
        format!("*{zoom:.6} -1 {}", named.join(" "))
    }

    /// Every signal as GTKWave names it (`scope.name`, `[msb:0]` on
    /// vectors), for checking a save file against its trace.
    pub fn gtkw_names(&self) -> Vec<String> {
        self.signals.iter().map(SignalDef::gtkw_name).collect()
    }

    /// The VCD text as a string.
    pub fn to_vcd_string(&self) -> String {
        let mut buf = Vec::new();
        self.write(&mut buf).expect("writing to memory cannot fail");
        String::from_utf8(buf).expect("VCD is ASCII/UTF-8")
    }
}

/// Half a clock period in whole nanoseconds (the traces' timescale is 1 ns).
pub fn half_period_ns(config: &motionhdl_model::Config) -> u64 {
    (config.clock_period_ps() / 2).div_ceil(1000).max(1)
}
