//! The generated traces and their save files: values from time 0, and
//! GTKWave (vcd2fst, and GTKWave itself headless) loading every one of
//! them with every signal. Under CI a missing tool fails the test;
//! elsewhere it is reported as skipped.

mod common;

use common::run;
use motionhdl_testbench::harness::require_tool;
use std::fs;
use std::process::Command;

#[test]
fn every_trace_has_every_value_at_time_0() {
    let mut traces = 0;
    for a in common::artifacts_for("") {
        if a.path.extension().is_none_or(|e| e != "vcd") {
            continue;
        }
        let text = String::from_utf8(a.contents.clone()).unwrap();
        let body = &text[text.find("$enddefinitions $end\n").expect("a VCD") + 21..];
        assert!(
            body.starts_with("#0\n"),
            "{}: first time {:?}",
            a.path.display(),
            body.lines().next()
        );
        let vars = text.matches("$var ").count();
        let at_0 = body
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with('#'))
            .count();
        assert_eq!(at_0, vars, "{}: values at time 0", a.path.display());
        traces += 1;
    }
    assert_eq!(traces, motionhdl_testbench::scenarios::SCENARIOS.len());
}

#[test]
fn vcd_loads_in_gtkwave_vcd2fst() {
    if require_tool("vcd2fst").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for a in common::artifacts_for("") {
        if a.path.extension().is_some_and(|e| e == "vcd") {
            let v = dir.path().join("t.vcd");
            let f = dir.path().join("t.fst");
            fs::write(&v, &a.contents).unwrap();
            let (ok, out, err) = run(Command::new("vcd2fst").arg(&v).arg(&f));
            assert!(ok, "{}: vcd2fst:\n{out}{err}", a.path.display());
            assert!(
                fs::metadata(&f).unwrap().len() > 100,
                "{}: empty FST",
                a.path.display()
            );
            assert!(
                !err.to_lowercase().contains("error"),
                "{}: {err}",
                a.path.display()
            );
        }
    }
}

/// GTKWave itself, headless: it must load every generated VCD and see
/// every declared signal. (vcd2fst accepts files GTKWave's own loader
/// rejects, such as any non-ASCII byte, so it is not enough on its own.)
#[test]
fn vcd_loads_in_gtkwave_with_every_signal() {
    if require_tool("gtkwave").is_none() || require_tool("xvfb-run").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("count.tcl");
    fs::write(
        &script,
        "puts \"FACS [gtkwave::getNumFacs]\"\ngtkwave::/File/Quit\n",
    )
    .unwrap();
    let mut checked = 0;
    for a in common::artifacts_for("") {
        if a.path.extension().is_none_or(|e| e != "vcd") {
            continue;
        }
        let v = dir.path().join("t.vcd");
        fs::write(&v, &a.contents).unwrap();
        let vars = String::from_utf8_lossy(&a.contents)
            .lines()
            .filter(|l| l.starts_with("$var "))
            .count();
        let (_, out, err) = run(Command::new("xvfb-run")
            .args(["-a", "gtkwave", "-S"])
            .arg(&script)
            .arg(&v));
        let facs = out
            .lines()
            .find_map(|l| l.strip_prefix("FACS "))
            .unwrap_or_else(|| {
                panic!("{}: GTKWave did not load it:\n{out}{err}", a.path.display())
            });
        assert_eq!(
            facs.trim().parse::<usize>().unwrap(),
            vars,
            "{}: signals GTKWave sees",
            a.path.display()
        );
        checked += 1;
    }
    assert!(checked >= 8, "only {checked} VCD files checked");
}

/// Every trace has a GTKWave save file beside it that names exactly the
/// trace's signals, grouped by scope; GTKWave itself (headless) opens the
/// trace with it and shows every signal in that order, run from another
/// directory the way the README says (`gtkwave X.vcd X.gtkw`), with the
/// scenario's named markers and its unused scopes' groups closed.
#[test]
fn gtkw_save_files_show_every_signal_grouped_by_scope() {
    let config = Default::default();
    let files = common::artifacts_for("");
    let text = |name: &str| -> String {
        let a = files
            .iter()
            .find(|a| a.path == std::path::Path::new("vcd").join(name))
            .unwrap_or_else(|| panic!("no generated vcd/{name}"));
        String::from_utf8(a.contents.clone()).unwrap()
    };
    let gtkwave = require_tool("gtkwave").is_some() && require_tool("xvfb-run").is_some();
    let dir = tempfile::tempdir().unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    let script = dir.path().join("shown.tcl");
    fs::write(
        &script,
        "foreach x [gtkwave::getDisplayedSignals] { puts \"SHOWN $x\" }\n\
         foreach m {A B C D E F G H I J K L M N O P Q R S T U V W X Y Z} \
         { puts \"MARKER $m [gtkwave::getNamedMarker $m]\" }\n\
         gtkwave::/File/Quit\n",
    )
    .unwrap();
    let (mut checked, mut marker_count, mut closed_groups) = (0, 0, 0);
    for s in motionhdl_testbench::scenarios::SCENARIOS {
        let trace = s.trace(&config);
        let names = trace.gtkw_names();
        let gtkw = text(&format!("{}.gtkw", s.name));
        assert!(gtkw.starts_with("[*] Generated by motionhdl"), "{}", s.name);
        assert!(gtkw.contains(&format!("[dumpfile] \"{}.vcd\"", s.name)));
        let listed: Vec<&str> = gtkw
            .lines()
            .filter(|l| !l.starts_with(['@', '[', '-', '*']))
            .collect();
        let mut want: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut got = listed.clone();
        want.sort();
        got.sort();
        assert_eq!(got, want, "{}: signals in the save file", s.name);
        // Zoomed to fit: 2^-zoom time units per pixel, the whole run in
        // 1000 pixels and more than half of them.
        let zoom: f64 = gtkw
            .lines()
            .find_map(|l| l.strip_prefix('*'))
            .and_then(|l| l.split(' ').next())
            .and_then(|z| z.parse().ok())
            .unwrap_or_else(|| panic!("{}: no zoom line", s.name));
        let vcd = text(&format!("{}.vcd", s.name));
        let end: f64 = vcd
            .lines()
            .filter_map(|l| l.strip_prefix('#'))
            .next_back()
            .unwrap()
            .parse()
            .unwrap();
        let per_pixel = (-zoom).exp2();
        assert!(
            end <= 1000.0 * per_pixel && end > 500.0 * per_pixel,
            "{}: zoom {zoom} for a run of {end}",
            s.name
        );
        let open = |begin: &str, end: &str| {
            let b = gtkw.lines().filter(|l| *l == begin).count();
            assert_eq!(b, gtkw.lines().filter(|l| *l == end).count(), "{}", s.name);
            b
        };
        let (opened, closed) = (open("@800200", "@1000200"), open("@c00200", "@1401200"));
        assert!(opened > 0, "{}: groups", s.name);
        assert_eq!(
            closed,
            trace.unused_scopes().len(),
            "{}: closed groups",
            s.name
        );
        closed_groups += closed;
        // Named markers: one letter per event, in time order, within the
        // run, each with its time on the zoom line.
        let markers = trace.markers();
        assert!(!markers.is_empty(), "{}: no named marker", s.name);
        let times: Vec<i128> = gtkw
            .lines()
            .find_map(|l| l.strip_prefix('*'))
            .unwrap()
            .split(' ')
            .skip(2)
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(times.len(), 26, "{}: 26 named marker slots", s.name);
        for (i, (letter, time, name)) in markers.iter().enumerate() {
            assert!(gtkw.contains(&format!("\n[markername] {letter}{name}\n")));
            assert_eq!(times[i], i128::from(*time), "{}: marker {letter}", s.name);
            assert!(
                (*time as f64) <= end,
                "{}: marker {name} after the run",
                s.name
            );
        }
        assert!(times[markers.len()..].iter().all(|t| *t == -1));
        marker_count += markers.len();
        if gtkwave {
            let vcd = dir.path().join(format!("{}.vcd", s.name));
            let save = dir.path().join(format!("{}.gtkw", s.name));
            fs::write(&vcd, text(&format!("{}.vcd", s.name))).unwrap();
            fs::write(&save, &gtkw).unwrap();
            let (_, out, err) = run(Command::new("xvfb-run")
                .current_dir(elsewhere.path())
                .args(["-a", "gtkwave", "-S"])
                .arg(&script)
                .arg(&vcd)
                .arg(&save));
            let shown: Vec<&str> = out
                .lines()
                .filter_map(|l| l.strip_prefix("SHOWN "))
                .collect();
            assert_eq!(shown, listed, "{}: GTKWave shows\n{out}{err}", s.name);
            // GTKWave reads the named markers' times back.
            let read: Vec<(char, i128)> = out
                .lines()
                .filter_map(|l| l.strip_prefix("MARKER "))
                .map(|l| {
                    let (letter, t) = l.split_once(' ').unwrap();
                    (letter.chars().next().unwrap(), t.trim().parse().unwrap())
                })
                .filter(|(_, t)| *t != -1)
                .collect();
            let want: Vec<(char, i128)> = markers
                .iter()
                .map(|(l, t, _)| (*l, i128::from(*t)))
                .collect();
            assert_eq!(
                read, want,
                "{}: GTKWave's named markers\n{out}{err}",
                s.name
            );
        }
        checked += 1;
    }
    assert_eq!(checked, motionhdl_testbench::scenarios::SCENARIOS.len());
    assert!(checked >= 14, "only {checked} scenarios");
    // Six counter scenarios use channel 0 of 4, one uses 0..2: 19 unused.
    assert!(closed_groups >= 19, "{closed_groups} closed groups");
    println!("{checked} save files, {marker_count} named markers, {closed_groups} closed groups");
}

/// A scenario that draws a plot has it beside its trace in generated/,
/// bannered, with a curve (and its legend swatch) per series: the servo
/// loop's 4 panels of 2, the system move's 2 axes x (position and velocity
/// planned and executed, acceleration and jerk planned).
#[test]
fn plots_are_written_beside_their_traces() {
    let files = common::artifacts_for("");
    let mut plots = Vec::new();
    for s in motionhdl_testbench::scenarios::SCENARIOS {
        let svg = files
            .iter()
            .find(|a| a.path == std::path::Path::new("vcd").join(format!("{}.svg", s.name)));
        assert_eq!(svg.is_some(), s.plot, "{}: plot file", s.name);
        if let Some(a) = svg {
            let text = String::from_utf8(a.contents.clone()).unwrap();
            assert!(text.starts_with(&format!("<!-- {} -->\n<svg ", motionhdl_hdl::banner())));
            plots.push((s.name, motionhdl_testbench::plot::curves(&text)));
        }
    }
    assert_eq!(plots, [("system", 2 * 2 * 6), ("servo_loop", 2 * 8)]);
}
