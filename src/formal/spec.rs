//! A proof file's header: the `//!` lines at the top of `formal/<proof>.sv`
//! say which generated modules it reads, which of their registers it sees,
//! how deep to prove and cover, and how to break the Verilog for each
//! property (docs/formal.md, "Writing a proof").

/// One generated module a proof reads, with its catalog arguments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Uses {
    pub module: String,
    pub args: Vec<u32>,
}

/// A one-line edit of a generated module that must make `label` fail.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Break {
    pub label: String,
    pub from: String,
    pub to: String,
}

/// `//! in_top <prefix> <axes> <width>`: prove the file again on the block
/// as `motion_controller <axes> <width>` instantiates it, where its names
/// carry `prefix` (src/formal/in_top.rs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InTop {
    pub prefix: String,
    pub args: Vec<u32>,
}

/// Everything a proof file says about itself.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProofSpec {
    pub name: String,
    pub uses: Vec<Uses>,
    /// `module/signal`, turned into output ports by yosys `expose`.
    pub expose: Vec<String>,
    pub depth: u32,
    pub cover_depth: u32,
    /// Only under `motionhdl verify --long`.
    pub long: bool,
    pub breaks: Vec<Break>,
    pub in_top: Option<InTop>,
    /// The `p_` labels of its assertions, in file order.
    pub properties: Vec<String>,
    /// The `c_` labels of its covers, in file order.
    pub covers: Vec<String>,
    pub text: String,
}

impl ProofSpec {
    /// The wrapper module the proof's file defines.
    pub fn top(&self) -> String {
        format!("{}_props", self.name)
    }

    /// Whether this is a proof's copy on the block inside the whole top
    /// (made by `in_top::derive`), not a block's own proof.
    pub fn is_in_top(&self) -> bool {
        self.name.ends_with(super::in_top::NAME_SUFFIX)
    }
}

/// Reads `text`, the proof file of `name`; a malformed header is an error
/// naming the line.
pub fn parse(name: &str, text: &str) -> Result<ProofSpec, String> {
    let mut spec = ProofSpec {
        name: name.to_string(),
        uses: Vec::new(),
        expose: Vec::new(),
        depth: 0,
        cover_depth: 0,
        long: false,
        breaks: Vec::new(),
        in_top: None,
        properties: labels(text, "assert"),
        covers: labels(text, "cover"),
        text: text.to_string(),
    };
    let mut open_break: Option<(String, Option<String>)> = None;
    for (n, line) in text.lines().enumerate() {
        let at = |why: &str| format!("formal/{name}.sv line {}: {why}: `{line}`", n + 1);
        let Some(directive) = line.strip_prefix("//!") else {
            continue;
        };
        let directive = directive.trim();
        let (word, rest) = directive.split_once(' ').unwrap_or((directive, ""));
        let rest = rest.trim();
        if let Some((label, from)) = open_break.take() {
            match (word, from) {
                ("from:", None) => {
                    open_break = Some((label, Some(rest.to_string())));
                    continue;
                }
                ("to:", Some(from)) => {
                    spec.breaks.push(Break {
                        label,
                        from,
                        to: rest.to_string(),
                    });
                    continue;
                }
                _ => return Err(at("a break needs a `from:` line, then a `to:` line")),
            }
        }
        let number = |what: &str| -> Result<u32, String> {
            rest.parse()
                .map_err(|_| at(&format!("{what} takes a whole number")))
        };
        // `<word> <name> <number>...`: the name and the numbers.
        let named = |what: &str| -> Result<(String, Vec<u32>), String> {
            let mut parts = rest.split_whitespace();
            let name = parts
                .next()
                .ok_or_else(|| at(&format!("{word} needs {what}")))?;
            let args = parts
                .map(|a| a.parse().map_err(|_| at("an argument is a number")))
                .collect::<Result<_, _>>()?;
            Ok((name.to_string(), args))
        };
        match word {
            "uses" => {
                let (module, args) = named("a module")?;
                spec.uses.push(Uses { module, args });
            }
            "expose" => spec
                .expose
                .extend(rest.split_whitespace().map(String::from)),
            "in_top" => {
                let (prefix, args) = named("a prefix")?;
                spec.in_top = Some(InTop { prefix, args });
            }
            "depth" => spec.depth = number("depth")?,
            "cover_depth" => spec.cover_depth = number("cover_depth")?,
            "long" => spec.long = true,
            "break" if !rest.is_empty() => open_break = Some((rest.to_string(), None)),
            _ => return Err(at("unknown directive")),
        }
    }
    if open_break.is_some() {
        return Err(format!(
            "formal/{name}.sv: the last break has no `to:` line"
        ));
    }
    check(&spec)?;
    Ok(spec)
}

/// What every proof file must hold: a module to read, depths, and a break
/// for every property that names a property of the file.
fn check(spec: &ProofSpec) -> Result<(), String> {
    let name = &spec.name;
    if spec.uses.is_empty() || spec.depth == 0 || spec.cover_depth == 0 {
        return Err(format!(
            "formal/{name}.sv: needs `//! uses`, `//! depth` and `//! cover_depth` lines"
        ));
    }
    if spec.properties.is_empty() || spec.covers.is_empty() {
        return Err(format!(
            "formal/{name}.sv: needs labelled asserts (p_...) and covers (c_...)"
        ));
    }
    if !spec.text.contains(&format!("module {}(", spec.top())) {
        return Err(format!(
            "formal/{name}.sv: defines no module {}",
            spec.top()
        ));
    }
    for b in &spec.breaks {
        if !spec.properties.contains(&b.label) {
            return Err(format!(
                "formal/{name}.sv: break {} names no property of the file",
                b.label
            ));
        }
    }
    if let Some(p) = spec
        .properties
        .iter()
        .find(|p| !spec.breaks.iter().any(|b| &b.label == *p))
    {
        return Err(format!("formal/{name}.sv: property {p} has no break"));
    }
    Ok(())
}

/// The labels `label: <keyword>(` of a file, in order, each once.
fn labels(text: &str, keyword: &str) -> Vec<String> {
    let mut found = Vec::new();
    for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
        let mut rest = line;
        while let Some(at) = rest.find(&format!(": {keyword}")) {
            let before = &rest[..at];
            let label: String = before
                .chars()
                .rev()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            if !label.is_empty() && !found.contains(&label) {
                found.push(label);
            }
            rest = &rest[at + 2..];
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "// says what\n//! uses counter_bank 1 8\n//! expose m/a_q m/b_q\n\
        //! depth 12\n//! cover_depth 20\n//! break p_x\n//!   from: a = 1;\n//!   to: a = 0;\n\
        module q_props(input clock);\n  always @* begin p_x: assert(1); c_y: cover(1); end\nendmodule\n";

    #[test]
    fn a_header_is_read() {
        let s = parse("q", GOOD).unwrap();
        assert_eq!(
            s.uses,
            vec![Uses {
                module: "counter_bank".into(),
                args: vec![1, 8]
            }]
        );
        assert_eq!(s.expose, ["m/a_q", "m/b_q"]);
        assert_eq!((s.depth, s.cover_depth, s.long), (12, 20, false));
        assert_eq!(
            s.breaks,
            vec![Break {
                label: "p_x".into(),
                from: "a = 1;".into(),
                to: "a = 0;".into()
            }]
        );
        assert_eq!(s.properties, ["p_x"]);
        assert_eq!(s.covers, ["c_y"]);
    }

    #[test]
    fn a_bad_header_names_the_line() {
        let bad = GOOD.replace("//! depth 12", "//! depth twelve");
        assert!(parse("q", &bad).unwrap_err().contains("line 4"));
        let unknown = GOOD.replace("//! depth 12", "//! deep 12");
        assert!(parse("q", &unknown)
            .unwrap_err()
            .contains("unknown directive"));
        let no_to = GOOD.replace("//!   to: a = 0;\n", "");
        assert!(parse("q", &no_to).is_err());
    }

    #[test]
    fn every_property_needs_a_break() {
        let more = GOOD.replace("p_x: assert(1);", "p_x: assert(1); p_z: assert(1);");
        assert_eq!(
            parse("q", &more).unwrap_err(),
            "formal/q.sv: property p_z has no break"
        );
    }
}
