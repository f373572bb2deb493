//! Removing what nothing reads: a net that no statement, flop, RAM port or
//! output reads (an unused output of an inlined block, such as the MCU
//! side's SERVO port in a top without the SERVO block) loses its
//! assignments and its declaration, then a local parameter nothing names;
//! repeated until nothing changes. Lint tools (`verilator -Wall`) reject
//! such nets, and synthesis would drop them anyway.

use super::flatten::Flat;
use super::re;
use std::collections::BTreeSet;
use std::sync::OnceLock;

/// The identifiers in `text`.
fn identifiers(text: &str) -> impl Iterator<Item = &str> {
    static IDENT: OnceLock<regex::Regex> = OnceLock::new();
    re(&IDENT, r"[A-Za-z_$][A-Za-z0-9_$]*")
        .find_iter(text)
        .map(|m| m.as_str())
}

/// A one-line assignment `name = …;` or `name[…] = …;`: the name, and the
/// text it reads (the right-hand side and any index of the left).
fn assignment(line: &str) -> Option<(&str, String)> {
    let t = line.trim();
    let (lhs, rhs) = t.split_once(" = ")?;
    let name = lhs.split('[').next()?;
    let simple = identifiers(name).count() == 1 && identifiers(name).next() == Some(name);
    (simple && t.ends_with(';')).then(|| (name, format!("{} {rhs}", &lhs[name.len()..])))
}

/// Every name something reads: statements' conditions and right-hand
/// sides, flops' clocks and inputs, RAM ports, the module's own ports.
fn read_names(flat: &Flat) -> BTreeSet<String> {
    let mut read = BTreeSet::new();
    let mut add = |text: &str| {
        for id in identifiers(text) {
            read.insert(id.to_string());
        }
    };
    for line in flat.comb.iter().flatten() {
        match assignment(line) {
            Some((_, reads)) => add(&reads),
            // `if`, `case`, `end`, a statement over several lines: every
            // name in it counts as read.
            None => add(line),
        }
    }
    for (c, _, d) in &flat.flops {
        add(c);
        add(d);
    }
    for m in &flat.mems {
        for n in [
            &m.read_clock,
            &m.read_address,
            &m.write_clock,
            &m.write_address,
            &m.write_data,
            &m.write_enable,
        ] {
            add(n);
        }
    }
    for (_, v) in &flat.params {
        add(v);
    }
    read.extend(flat.ports.keys().cloned());
    read
}

/// `flat` without the nets, flops and parameters nothing reads.
pub(super) fn prune_unread(mut flat: Flat) -> Flat {
    let mems: BTreeSet<String> = flat
        .mems
        .iter()
        .flat_map(|m| [m.name.clone(), m.read_data.clone()])
        .collect();
    loop {
        // A net assigned by a statement over several lines is kept: such a
        // line counts every name in it as read, its target too.
        let read = read_names(&flat);
        let dead: BTreeSet<String> = flat
            .nets
            .iter()
            .map(|n| n.name.clone())
            .filter(|n| !read.contains(n) && !mems.contains(n))
            .collect();
        let params_before = flat.params.len();
        flat.params.retain(|(p, _)| read.contains(p));
        if dead.is_empty() && flat.params.len() == params_before {
            return flat;
        }
        flat.nets.retain(|n| !dead.contains(&n.name));
        flat.flops.retain(|(_, q, _)| !dead.contains(q));
        for block in &mut flat.comb {
            block.retain(|l| assignment(l).is_none_or(|(name, _)| !dead.contains(name)));
        }
        for n in &dead {
            flat.widths.remove(n);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignments_name_their_target_and_what_they_read() {
        assert_eq!(
            assignment("a$b = c & d;"),
            Some(("a$b", " c & d;".to_string()))
        );
        assert_eq!(
            assignment("  x[3:0] = y[i];"),
            Some(("x", "[3:0] y[i];".to_string()))
        );
        assert_eq!(assignment("if (a == b) begin"), None);
        assert_eq!(assignment("x = (a"), None);
        // One identifier, but not a plain name: not an assignment to it.
        assert_eq!(assignment("{a} = b;"), None);
    }
}
