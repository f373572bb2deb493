//! The exporter on names that contain its keywords: a signal called
//! `begin_x` once made it miscount `begin`/`end` nesting and run off the end
//! of the module.

use motionhdl_hdl::verilog::export;
use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
struct KeywordNames {
    pub clock: Signal<In, Clock>,
    pub begin_x: Signal<In, Bit>,
    pub end_y: Signal<Out, Bit>,
    begin_q: DFF<Bit>,
}

impl Logic for KeywordNames {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, begin_q);
        self.begin_q.d.next = self.begin_x.val();
        self.end_y.next = false;
        if self.begin_x.val() {
            self.end_y.next = self.begin_q.q.val();
        }
    }
}

#[test]
fn signals_named_like_keywords_export_as_identifiers() {
    let mut uut = KeywordNames::default();
    uut.connect_all();
    let text = export(&uut, "keyword_names", &["test".into()]);
    assert!(text.contains("module keyword_names("), "{text}");
    for needle in [
        "input wire begin_x;",
        "output reg end_y;",
        "if (begin_x) begin",
        "end_y = begin_q_q;",
        "endmodule // keyword_names",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in:\n{text}");
    }
    let ports: Vec<String> = motionhdl_hdl::ports::ports(&uut)
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(ports, ["clock", "begin_x", "end_y"]);
}
