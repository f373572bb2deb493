//! The selector trace, parsed back with the `vcd` crate's parser: scopes and
//! names as the ports, a 1 ns timescale, and every sampled instant consistent
//! with the seed table (an independent check of the writer and scenario).

use motionhdl_model::pulse_mode_selector::from_truth_table;
use motionhdl_testbench::scenarios;
use std::collections::BTreeMap;
use vcd::{Command, ScopeItem, TimescaleUnit, Value};

fn collect(items: &[ScopeItem], path: &mut Vec<String>, out: &mut BTreeMap<vcd::IdCode, String>) {
    for item in items {
        match item {
            ScopeItem::Scope(s) => {
                path.push(s.identifier.clone());
                collect(&s.items, path, out);
                path.pop();
            }
            ScopeItem::Var(v) => {
                out.insert(v.code, format!("{}.{}", path.join("."), v.reference));
            }
            _ => {}
        }
    }
}

#[test]
fn selector_trace_parses_back_and_agrees_with_the_table() {
    let text = scenarios::find("pulse_mode_selector")
        .unwrap()
        .trace(&Default::default())
        .to_vcd_string();
    let mut parser = vcd::Parser::new(text.as_bytes());
    let header = parser.parse_header().unwrap();
    assert_eq!(header.timescale, Some((1, TimescaleUnit::NS)));
    assert!(header.date.is_none());
    let mut names = BTreeMap::new();
    collect(&header.items, &mut Vec::new(), &mut names);
    let by_name: BTreeMap<&str, vcd::IdCode> =
        names.iter().map(|(c, n)| (n.as_str(), *c)).collect();
    for port in ["k", "s1", "s2", "f1", "f2"] {
        assert!(
            by_name.contains_key(format!("pulse_mode_selector.{port}").as_str()),
            "{port}"
        );
        assert!(
            by_name.contains_key(format!("pulse_mode_selector_registered.{port}").as_str()),
            "{port}"
        );
    }
    for pin in ["a", "b", "g1_n", "g2_n", "c1_0", "c2_3", "y1", "y2"] {
        assert!(
            by_name.contains_key(format!("pulse_mode_selector.chip.{pin}").as_str()),
            "{pin}"
        );
    }

    let mut values: BTreeMap<vcd::IdCode, bool> = BTreeMap::new();
    let mut instants = 0;
    let mut seen_inputs = std::collections::BTreeSet::new();
    let mut direction_changes = 0;
    let mut last_s2 = None;
    let mut check = |values: &BTreeMap<vcd::IdCode, bool>| {
        let v = |n: &str| values[&by_name[n]];
        let (k, s2, s1) = (
            v("pulse_mode_selector.k"),
            v("pulse_mode_selector.s2"),
            v("pulse_mode_selector.s1"),
        );
        let want = from_truth_table(k, s2, s1);
        assert_eq!(
            (v("pulse_mode_selector.f1"), v("pulse_mode_selector.f2")),
            want,
            "K={k} S2={s2} S1={s1}"
        );
        assert_eq!(
            (
                v("pulse_mode_selector.chip.y1"),
                v("pulse_mode_selector.chip.y2")
            ),
            want
        );
        seen_inputs.insert((k, s2, s1));
        if last_s2.is_some_and(|l| l != s2) {
            direction_changes += 1;
        }
        last_s2 = Some(s2);
    };
    let mut pending = false;
    for cmd in parser {
        match cmd.unwrap() {
            Command::Timestamp(_) => {
                if pending {
                    check(&values);
                    instants += 1;
                }
                pending = true;
            }
            Command::ChangeScalar(id, val) => {
                values.insert(id, val == Value::V1);
            }
            _ => {}
        }
    }
    check(&values);
    instants += 1;
    assert_eq!(seen_inputs.len(), 8, "the trace sweeps all 8 inputs");
    assert!(direction_changes >= 2, "the trace shows direction changes");
    assert!(instants > 40);
}
