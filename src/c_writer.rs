//! The one C writer behind the generated headers (`motionhdl_regs.h`,
//! `motionhdl_isa.h`, the self-test): block comments wrapped to the line
//! limit, `#define` lines, and unsigned literals in the two dialects the
//! headers need.

/// Longest line a generated C file may have.
pub const MAX_LINE: usize = 100;

/// `text` as a C block comment at `indent`, words wrapped so no line
/// exceeds [`MAX_LINE`]; one line (`/* … */`) when it fits. `\n` in `text`
/// starts a paragraph.
pub fn comment(out: &mut String, indent: &str, text: &str) {
    let one = format!("{indent}/* {text} */");
    if one.len() <= MAX_LINE && !text.contains('\n') {
        out.push_str(&one);
        out.push('\n');
        return;
    }
    out.push_str(&format!("{indent}/*\n"));
    for line in crate::text::wrap(text, MAX_LINE - indent.len() - 3) {
        if line.is_empty() {
            out.push_str(&format!("{indent} *\n"));
        } else {
            out.push_str(&format!("{indent} * {line}\n"));
        }
    }
    out.push_str(&format!("{indent} */\n"));
}

/// One `#define name value` line; panics past [`MAX_LINE`].
pub fn define(out: &mut String, name: &str, value: &str) {
    line(out, &format!("#define {name} {value}"));
}

/// One line; panics past [`MAX_LINE`].
pub fn line(out: &mut String, line: &str) {
    assert!(line.len() <= MAX_LINE, "line too long: {line}");
    out.push_str(line);
    out.push('\n');
}

/// How wide the target's `int` is, which decides literal suffixes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntWidth {
    /// 32-bit `int` (the MCU side): `u` always fits.
    Bits32,
    /// 16-bit `int` (DOS compilers on the PC side): values past 16 bits
    /// need `ul`.
    Bits16,
}

impl IntWidth {
    fn suffix(self, v: u32) -> &'static str {
        match self {
            IntWidth::Bits16 if v > 0xffff => "ul",
            _ => "u",
        }
    }

    /// `v` in hex, at least 4 digits (8 past 16 bits).
    pub fn hex(self, v: u32) -> String {
        if v <= 0xffff {
            format!("0x{v:04x}{}", self.suffix(v))
        } else {
            format!("0x{v:08x}{}", self.suffix(v))
        }
    }

    /// `v` in decimal.
    pub fn dec(self, v: u32) -> String {
        format!("{v}{}", self.suffix(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_fit_the_int_width() {
        assert_eq!(IntWidth::Bits32.hex(0x1_0000), "0x00010000u");
        assert_eq!(IntWidth::Bits16.hex(0x1_0000), "0x00010000ul");
        assert_eq!(IntWidth::Bits16.hex(0xffff), "0xffffu");
        assert_eq!(IntWidth::Bits16.dec(70_000), "70000ul");
        assert_eq!(IntWidth::Bits32.dec(70_000), "70000u");
    }

    #[test]
    fn comments_wrap_at_the_line_limit() {
        let mut s = String::new();
        comment(&mut s, "", "short");
        assert_eq!(s, "/* short */\n");
        let mut s = String::new();
        comment(&mut s, "    ", &"word ".repeat(40));
        assert!(s.lines().all(|l| l.len() <= MAX_LINE), "{s}");
        assert!(s.starts_with("    /*\n     * word word"), "{s}");
        assert!(s.ends_with("\n     */\n"), "{s}");
    }
}
