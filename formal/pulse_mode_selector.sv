// The 74LS153 pulse-mode selector (docs/pulse_generator.md): K = 0 passes
// pulse+direction through, K = 1 makes CW/CCW, F1 = S1 and not S2,
// F2 = S1 and S2, so the two never drive the motor at once. Combinational:
// every input combination is one step of the solver. Shipped module.
//! uses pulse_mode_selector
//! depth 1
//! cover_depth 1
//! break p_cw_ccw_exclusive
//!   from: chip_c1_3 = 1'b0;
//!   to: chip_c1_3 = s1;
//! break p_cw_ccw
//!   from: chip_c2_2 = 1'b0;
//!   to: chip_c2_2 = s1;
//! break p_pulse_direction
//!   from: chip_c2_1 = 1'b1;
//!   to: chip_c2_1 = s1;
module pulse_mode_selector_props(input k, input s1, input s2);
  wire f1, f2;
  pulse_mode_selector uut(.k(k), .s1(s1), .s2(s2), .f1(f1), .f2(f2));

  always @(*) begin
    // CW/CCW: never both outputs at once (the seed's runt hazard).
    if (k) p_cw_ccw_exclusive: assert(!(f1 && f2));
    // CW/CCW: the step goes to F1 for S2 = 0, to F2 for S2 = 1.
    if (k) p_cw_ccw: assert(f1 == (s1 && !s2) && f2 == (s1 && s2));
    // Pulse+direction: S1, S2 straight through.
    if (!k) p_pulse_direction: assert(f1 == s1 && f2 == s2);
    c_cw: cover(k && f1);
    c_ccw: cover(k && f2);
    c_step_forward: cover(!k && f1 && !f2);
    c_step_reverse: cover(!k && f1 && f2);
  end
endmodule
