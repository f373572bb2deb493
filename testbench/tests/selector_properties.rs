//! Contract properties of the pulse-mode selector, for random pulse trains
//! with direction changes, and its glitch behaviour in a timed simulation.

use motionhdl_hdl::{catalog, PulseModeSelector, PulseModeSelectorRegistered};
use motionhdl_model::pulse_mode_selector::{rising_edges, PulseMode};
use motionhdl_testbench::harness::{cycle, require_tool, settle};
use proptest::prelude::*;
use rust_hdl::prelude::*;
use std::process::Command;

/// One command pulse: its direction, high time and low time in samples.
/// Direction changes only while S1 is low, as a pulse generator must.
#[derive(Clone, Debug)]
struct Pulse {
    reverse: bool,
    high: usize,
    low: usize,
}

fn pulse_train() -> impl Strategy<Value = Vec<Pulse>> {
    prop::collection::vec(
        (any::<bool>(), 1usize..5, 1usize..5).prop_map(|(reverse, high, low)| Pulse {
            reverse,
            high,
            low,
        }),
        0..40,
    )
}

/// Samples of (S2, S1): direction is set during the low time before a pulse.
fn samples(train: &[Pulse]) -> Vec<(bool, bool)> {
    let mut out = vec![(false, false)];
    for p in train {
        out.extend(std::iter::repeat_n((p.reverse, false), p.low));
        out.extend(std::iter::repeat_n((p.reverse, true), p.high));
    }
    out.push((train.last().is_some_and(|p| p.reverse), false));
    out
}

/// Runs the samples through the rust-hdl combinational selector.
fn through_hdl(mode: PulseMode, s: &[(bool, bool)]) -> Vec<(bool, bool)> {
    let mut uut = PulseModeSelector::default();
    uut.connect_all();
    s.iter()
        .map(|&(s2, s1)| {
            uut.k.next = mode.k();
            uut.s2.next = s2;
            uut.s1.next = s1;
            settle(&mut uut);
            (uut.f1.val(), uut.f2.val())
        })
        .collect()
}

/// Runs the samples through the rust-hdl registered selector (one per clock).
fn through_registered(mode: PulseMode, s: &[(bool, bool)]) -> Vec<(bool, bool)> {
    let mut uut = PulseModeSelectorRegistered::default();
    uut.connect_all();
    let mut out = Vec::new();
    for &(s2, s1) in s.iter().chain(std::iter::once(s.last().unwrap())) {
        uut.reset.next = false;
        uut.k.next = mode.k();
        uut.s2.next = s2;
        uut.s1.next = s1;
        settle(&mut uut);
        out.push((uut.f1.val(), uut.f2.val()));
        cycle(&mut uut, |u| &mut u.clock);
    }
    out.remove(0); // the registered outputs lag by one clock
    out
}

fn check_cw_ccw(
    train: &[Pulse],
    s: &[(bool, bool)],
    out: &[(bool, bool)],
) -> Result<(), TestCaseError> {
    let s1_pulses = rising_edges(s.iter().map(|x| x.1));
    let cw = rising_edges(out.iter().map(|x| x.0));
    let ccw = rising_edges(out.iter().map(|x| x.1));
    prop_assert!(
        out.iter().all(|&(f1, f2)| !(f1 && f2)),
        "F1 and F2 high together"
    );
    prop_assert_eq!(cw + ccw, s1_pulses);
    prop_assert_eq!(cw, train.iter().filter(|p| !p.reverse).count());
    prop_assert_eq!(ccw, train.iter().filter(|p| p.reverse).count());
    // Each pulse appears on exactly one output, for exactly its width.
    for (i, (&(s2, s1), &(f1, f2))) in s.iter().zip(out).enumerate() {
        prop_assert_eq!((f1, f2), (s1 && !s2, s1 && s2), "sample {}", i);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn cw_ccw_pulses_appear_on_exactly_one_output(train in pulse_train()) {
        let s = samples(&train);
        check_cw_ccw(&train, &s, &through_hdl(PulseMode::CwCcw, &s))?;
        check_cw_ccw(&train, &s, &through_registered(PulseMode::CwCcw, &s))?;
    }

    #[test]
    fn pulse_direction_f1_reproduces_s1(train in pulse_train()) {
        let s = samples(&train);
        for out in [through_hdl(PulseMode::PulseDirection, &s), through_registered(PulseMode::PulseDirection, &s)] {
            let f1: Vec<bool> = out.iter().map(|x| x.0).collect();
            let s1: Vec<bool> = s.iter().map(|x| x.1).collect();
            prop_assert_eq!(&f1, &s1);
            let f2: Vec<bool> = out.iter().map(|x| x.1).collect();
            let s2: Vec<bool> = s.iter().map(|x| x.0).collect();
            prop_assert_eq!(&f2, &s2);
        }
    }
}

/// Drives both generated selectors with S1 and S2 changing 1 ns apart
/// (as two CPU pins or two routes never switch at exactly the same time) and
/// records every output transition. The combinational selector must show a
/// runt pulse; the registered one may change only on a rising clock edge.
#[test]
fn registered_outputs_change_only_on_clock_edges_combinational_glitches() {
    if require_tool("iverilog").is_none() || require_tool("vvp").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let comb = catalog::pulse_mode_selector();
    let reg = catalog::pulse_mode_selector_registered();
    std::fs::write(dir.path().join("comb.v"), &comb.text).unwrap();
    std::fs::write(dir.path().join("reg.v"), &reg.text).unwrap();
    // Clock period 20 ns, rising edges at 10, 30, 50, ...; inputs change at
    // 5 + 20n, S1 and S2 1 ns apart, in both orders.
    let tb = r#"`timescale 1ns / 1ps
module glitch_tb;
    reg clock = 1'b0, reset = 1'b1, k = 1'b1, s1 = 1'b0, s2 = 1'b0;
    wire cf1, cf2, rf1, rf2;
    pulse_mode_selector c (.k(k), .s1(s1), .s2(s2), .f1(cf1), .f2(cf2));
    pulse_mode_selector_registered r (.clock(clock), .reset(reset), .k(k), .s1(s1), .s2(s2), .f1(rf1), .f2(rf2));
    always #10 clock = ~clock;
    always @(cf1 or cf2) $display("COMB %0d %b %b", $time, cf1, cf2);
    always @(rf1 or rf2) $display("REG %0d %b %b", $time, rf1, rf2);
    integer n;
    initial begin
        #25 reset = 1'b0;
        for (n = 0; n < 8; n = n + 1) begin
            #19 s1 = ~s1;       // S1 first ...
            #1  s2 = ~s2;       // ... S2 1 ns later
            #19 s2 = ~s2;       // S2 first ...
            #1  s1 = ~s1;       // ... S1 1 ns later
        end
        #40 $finish;
    end
endmodule
"#;
    std::fs::write(dir.path().join("tb.v"), tb).unwrap();
    let o = Command::new("iverilog")
        .current_dir(dir.path())
        .args(["-g2005", "-o", "g.vvp", "tb.v", "comb.v", "reg.v"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = Command::new("vvp")
        .current_dir(dir.path())
        .args(["-n", "g.vvp"])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let events = |tag: &str| -> Vec<(u64, bool, bool)> {
        out.lines()
            .filter_map(|l| l.strip_prefix(tag))
            .map(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                (f[0].parse().unwrap(), f[1] == "1", f[2] == "1")
            })
            .collect()
    };
    let reg_events = events("REG ");
    assert!(
        reg_events.len() > 4,
        "registered outputs never moved:\n{out}"
    );
    for (t, _, _) in &reg_events {
        assert!(
            *t == 0 || t % 20 == 10,
            "registered output changed at {t} ns, not on a rising edge:\n{out}"
        );
    }
    // A runt: some combinational output high for less than 2 ns.
    let comb_events = events("COMB ");
    let mut runts = 0;
    for w in comb_events.windows(2) {
        let ((t0, a1, a2), (t1, b1, b2)) = (w[0], w[1]);
        if t1 - t0 < 2 && ((a1 && !b1) || (a2 && !b2)) {
            runts += 1;
        }
    }
    assert!(
        runts > 0,
        "expected the combinational selector to glitch with skewed inputs:\n{out}"
    );
    // And none in the registered outputs: every level lasts a whole clock.
    for w in reg_events.windows(2) {
        assert!(
            w[1].0 - w[0].0 >= 20 || w[0].0 == 0,
            "registered level shorter than a clock: {w:?}"
        );
    }
}
