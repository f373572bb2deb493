//! A block's top-level ports, read from rust-hdl's own probe API (the
//! atoms of the top scope), so nothing downstream re-parses Verilog text.

use rust_hdl::prelude::{Atom, AtomKind, Block, Probe};

/// Which way a port points, seen from the module.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortDir {
    Input,
    Output,
    InOut,
}

/// One port of an exported module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    pub name: String,
    pub dir: PortDir,
    pub width: u32,
    pub signed: bool,
}

#[derive(Default)]
struct TopAtoms {
    depth: usize,
    ports: Vec<Port>,
}

impl Probe for TopAtoms {
    fn visit_start_scope(&mut self, _name: &str, _node: &dyn Block) {
        self.depth += 1;
    }
    fn visit_end_scope(&mut self, _name: &str, _node: &dyn Block) {
        self.depth -= 1;
    }
    fn visit_atom(&mut self, name: &str, atom: &dyn Atom) {
        if self.depth != 1 {
            return;
        }
        let dir = match atom.kind() {
            AtomKind::InputParameter => PortDir::Input,
            AtomKind::OutputParameter | AtomKind::OutputPassthrough => PortDir::Output,
            AtomKind::InOutParameter => PortDir::InOut,
            _ => return,
        };
        self.ports.push(Port {
            name: name.to_string(),
            dir,
            width: atom.bits() as u32,
            signed: rust_hdl::core::atom::is_atom_signed(atom),
        });
    }
}

/// The ports of `uut`'s top level, in declaration order.
pub fn ports<B: Block>(uut: &B) -> Vec<Port> {
    let mut probe = TopAtoms::default();
    uut.accept("top", &mut probe);
    probe.ports
}
