// motion_controller, 1 axis x 8-bit counters, filter tick 2 clocks (input_filter_us = 8), external RAM (docs/motion_controller.md, "The machine side"): the safety block's HALT and direction stops reach the pins as documented through the pulse bank as the top wires them: e-stop halts in ESTOP_LATENCY with drive_enable low; after HALT no step edge on pulse_f1/pulse_f2 after h+2 (h+3 with QUADRATURE); a direction stop starts no S1 rise that way from e+2 and shows no step edge that way after e+3; F1 and F2 never high together in CW/CCW.
//! uses motion_controller 1 8
//! expose motion_controller/mcu_safety_halt motion_controller/mcu_safety_stop_up motion_controller/mcu_safety_stop_down motion_controller/mcu_pulses_selectors_0_s1 motion_controller/mcu_pulses_selectors_0_s2 motion_controller/mcu_pulses_ctrl_0_q motion_controller/mcu_pulses_decel_0_q
//! depth 12
//! cover_depth 24
//! break p_estop_halt
//!   from: mcu_safety_halt = mcu_safety_estop_latch_q | mcu_safety_bitten_q;
//!   to: mcu_safety_halt = mcu_safety_bitten_q;
//! break p_no_enable_while_halt
//!   from: mcu_drive_enable = mcu_safety_drive_enable;
//!   to: mcu_drive_enable = 1'b1;
//! break p_halt_no_s1
//!   from: mcu_pulses_halt = mcu_safety_halt;
//!   to: mcu_pulses_halt = mcu_safety_bitten_q;
//! break p_halt_no_step
//!   from: mcu_pulses_halt = mcu_safety_halt;
//!   to: mcu_pulses_halt = 1'b0;
//! break p_stop_up_no_s1
//!   from: mcu_pulses_stop_up = mcu_safety_stop_up;
//!   to: mcu_pulses_stop_up = mcu_safety_stop_down;
//! break p_stop_down_no_s1
//!   from: mcu_pulses_stop_down = mcu_safety_stop_down;
//!   to: mcu_pulses_stop_down = mcu_safety_stop_up;
//! break p_stop_up_no_step
//!   from: mcu_pulses_selectors_0_s2 = mcu_pulses_generators_0_dir;
//!   to: mcu_pulses_selectors_0_s2 = ~mcu_pulses_generators_0_dir;
//! break p_stop_down_no_step
//!   from: mcu_pulses_selectors_0_s2 = mcu_pulses_generators_0_dir;
//!   to: mcu_pulses_selectors_0_s2 = ~mcu_pulses_generators_0_dir;
//! break p_cw_ccw_exclusive
//!   from: mcu_pulses_selectors_0_selector_chip_c2_2 = 1'b0;
//!   to: mcu_pulses_selectors_0_selector_chip_c2_2 = mcu_pulses_selectors_0_selector_s1;
module motion_controller_props(input clock, input reset, input fsmc_ne_n, input fsmc_noe_n,
  input fsmc_nwe_n, input [11:0] fsmc_a, input [15:0] fsmc_d_in, input [9:0] isa_sa,
  input [15:0] isa_sd_in, input isa_ior_n, input isa_iow_n, input isa_aen, input isa_bale,
  input [7:0] isa_base, input enc_a, input enc_b, input enc_z, input estop_ok, input limit_pos,
  input limit_neg, input home, input alarm, input [15:0] gpi, input [15:0] sram_d_in,
  input [15:0] window_rdata);
  wire [15:0] fsmc_d_out, isa_sd_out, gpo_out, gpo_oe, sram_d_out, window_wdata;
  wire [9:0] sram_addr, window_addr;
  wire fsmc_d_oe, isa_sd_oe, isa_iocs16_n, isa_irq, pulse_f1, pulse_f2, drive_enable, irq;
  wire sram_d_oe, sram_ce_n, sram_oe_n, sram_we_n, window_we;
  // Exposed: the safety block's HALT and direction stops (what it sends the
  // pulse bank; the wiring between them is what this proof checks), axis 0's S1/S2 before the selector, its CTRL (MODE,
  // QUADRATURE, RUN) and DECEL.
  wire halt, s1, s2;
  wire stop_up, stop_down;
  wire [2:0] ctrl;
  wire [31:0] decel;
  motion_controller uut(.clock(clock), .reset(reset), .fsmc_ne_n(fsmc_ne_n),
    .fsmc_noe_n(fsmc_noe_n), .fsmc_nwe_n(fsmc_nwe_n), .fsmc_a(fsmc_a), .fsmc_d_in(fsmc_d_in),
    .fsmc_d_out(fsmc_d_out), .fsmc_d_oe(fsmc_d_oe), .isa_sa(isa_sa), .isa_sd_in(isa_sd_in),
    .isa_sd_out(isa_sd_out), .isa_sd_oe(isa_sd_oe), .isa_ior_n(isa_ior_n), .isa_iow_n(isa_iow_n),
    .isa_aen(isa_aen), .isa_bale(isa_bale), .isa_base(isa_base), .isa_iocs16_n(isa_iocs16_n),
    .isa_irq(isa_irq), .enc_a(enc_a), .enc_b(enc_b), .enc_z(enc_z), .pulse_f1(pulse_f1),
    .pulse_f2(pulse_f2), .estop_ok(estop_ok), .limit_pos(limit_pos), .limit_neg(limit_neg),
    .home(home), .alarm(alarm), .drive_enable(drive_enable), .irq(irq), .gpi(gpi),
    .gpo_out(gpo_out), .gpo_oe(gpo_oe), .sram_addr(sram_addr), .sram_d_in(sram_d_in),
    .sram_d_out(sram_d_out), .sram_d_oe(sram_d_oe), .sram_ce_n(sram_ce_n),
    .sram_oe_n(sram_oe_n), .sram_we_n(sram_we_n), .window_addr(window_addr),
    .window_wdata(window_wdata), .window_we(window_we), .window_rdata(window_rdata),
    .mcu_safety_halt(halt), .mcu_safety_stop_up(stop_up), .mcu_safety_stop_down(stop_down),
    .mcu_pulses_selectors_0_s1(s1), .mcu_pulses_selectors_0_s2(s2),
    .mcu_pulses_ctrl_0_q(ctrl), .mcu_pulses_decel_0_q(decel));

  initial assume(reset);
  // Reset held >= 3 clocks: weaker than the documented >= 4
  // (docs/motion_controller.md, "Pins"), so that case is covered.
  reg [2:0] age = 0;          // clocks since reset fell, saturating at 7
  reg [1:0] reset_len = 0;    // clocks reset has been high, saturating at 3
  // Histories, bit i = the value i + 1 clocks ago.
  reg [3:0] halt_h = 0, up_h = 0, down_h = 0, estop_low_h = 0;
  reg [3:0] ctrl_moved_h = 0, decel_h = 0;
  reg f1_q = 0, f2_q = 0, s1_q = 0, enable_q = 0;
  reg [1:0] ctrl_q = 0;
  always @(posedge clock) begin
    age <= reset ? 3'd0 : (age == 3'd7 ? age : age + 3'd1);
    reset_len <= reset ? (reset_len == 2'd3 ? reset_len : reset_len + 2'd1) : 2'd0;
    halt_h <= {halt_h[2:0], halt};
    up_h <= {up_h[2:0], stop_up};
    down_h <= {down_h[2:0], stop_down};
    estop_low_h <= {estop_low_h[2:0], !estop_ok};
    ctrl_q <= ctrl[1:0];
    ctrl_moved_h <= {ctrl_moved_h[2:0], ctrl[1:0] != ctrl_q};
    decel_h <= {decel_h[2:0], decel != 0};
    f1_q <= pulse_f1; f2_q <= pulse_f2; s1_q <= s1; enable_q <= drive_enable;
  end
  always @(*) if (!reset && reset_len != 0) assume(reset_len == 2'd3);

  // A step edge on the pins: an F1 rise with K = 0 (F2 is the direction),
  // an F1 or F2 rise with K = 1, any change with QUADRATURE.
  wire quad = ctrl[1], k = ctrl[0];
  wire f1_rise = pulse_f1 && !f1_q, f2_rise = pulse_f2 && !f2_q;
  wire pin_change = pulse_f1 != f1_q || pulse_f2 != f2_q;
  wire step_edge = quad ? pin_change : (k ? (f1_rise || f2_rise) : f1_rise);
  wire s1_rise = s1 && !s1_q;
  // A step edge upward (S2 = 0 is the positive direction): K = 0, F1
  // rises with F2 low; K = 1, F1 rises. Downward: F1 rises with F2 high;
  // F2 rises.
  wire up_edge = k ? f1_rise : (f1_rise && !pulse_f2);
  wire down_edge = k ? f2_rise : (f1_rise && pulse_f2);
  // CTRL's MODE and QUADRATURE unchanged for the last 4 clocks: a write of
  // them remaps the pins, which is not a step.
  wire mode_steady = ctrl[1:0] == ctrl_q && ctrl_moved_h == 0;
  wire decel_off = decel == 0 && decel_h == 0;

  always @(posedge clock) if (age >= 3'd5) begin
    // estop_ok low at edge k (sampled from the clock before it): HALT and
    // drive_enable low from edge k + 2.
    if (estop_low_h[2]) p_estop_halt: assert(halt);
    // No drive enable while HALT (the pin is a flip-flop set with HALT).
    if (halt) p_no_enable_while_halt: assert(!drive_enable);
    // HALT high since edge h: no S1 rise after h, no step edge on the pins
    // after h + 2 (h + 3 with QUADRATURE).
    if (halt_h[0]) p_halt_no_s1: assert(!s1_rise);
    if (mode_steady && halt_h[2:0] == 3'b111 && (!quad || halt_h[3]))
      p_halt_no_step: assert(!step_edge);
    // A direction stop set since edge e + 1 (DECEL = 0): no S1 rise that
    // way from e + 2 on, no step edge that way on the pins after e + 3.
    if (decel_off && up_h[0]) p_stop_up_no_s1: assert(!(s1_rise && !s2));
    if (decel_off && down_h[0]) p_stop_down_no_s1: assert(!(s1_rise && s2));
    if (decel_off && mode_steady && !quad && up_h[2:0] == 3'b111)
      p_stop_up_no_step: assert(!up_edge);
    if (decel_off && mode_steady && !quad && down_h[2:0] == 3'b111)
      p_stop_down_no_step: assert(!down_edge);
    // CW/CCW: F1 and F2 never high together.
    if (mode_steady && k && !quad) p_cw_ccw_exclusive: assert(!(pulse_f1 && pulse_f2));
  end

  // Each property's antecedent is reachable, and the latency bounds are
  // tight: step edges do come out up to the last edge each bound allows.
  wire steady_pd_cw = mode_steady && !quad && decel_off;
  always @(posedge clock) if (age >= 3'd5) begin
    c_estop: cover(estop_low_h[2] && halt && !halt_h[0]);
    c_enable_dropped: cover(halt && !halt_h[0] && enable_q);
    c_halt_while_stepping: cover(halt_h[0] && !halt_h[1] && s1_q);
    c_step_edge_at_h2: cover(mode_steady && !quad && step_edge && halt_h[1:0] == 2'b11 && !halt_h[2]);
    c_quad_edge_at_h3: cover(mode_steady && quad && step_edge && halt_h[2:0] == 3'b111 && !halt_h[3]);
    c_stop_up_while_stepping: cover(up_h[0] && !up_h[1] && s1_q && !s2);
    c_stop_down_while_stepping: cover(down_h[0] && !down_h[1] && s1_q && s2);
    c_up_edge_at_e3: cover(steady_pd_cw && up_edge && up_h[1:0] == 2'b11 && !up_h[2]);
    c_down_edge_at_e3: cover(steady_pd_cw && down_edge && down_h[1:0] == 2'b11 && !down_h[2]);
    c_cw_ccw_f1: cover(mode_steady && k && !quad && pulse_f1);
    c_cw_ccw_f2: cover(mode_steady && k && !quad && pulse_f2);
  end
endmodule
