// Counter bank, 1 channel x the shipped 28-bit count (counter_bank 1 28; channels are copies): with the filter off the count moves by exactly the decoded step of the synchronised inputs (X4/X2/X1, pulse+dir, CW/CCW, REVERSE) and by nothing else but CLEAR/LOAD/index clear/reset; an illegal transition never counts and sets ERR/ERR_COUNT only with ERR_EN; COUNT/INDEX/STATUS read the SNAPSHOT registers, which change only at SNAPSHOT (docs/counter_bank.md).
// Register map (words, generated/include/motionhdl_regs.h bytes / 4): SNAPSHOT 0x01,
// PRESET 0x02, CH0 CTRL 0x08, CMD 0x09, COUNT 0x0A, INDEX 0x0B, STATUS 0x0C.
// The expected step is decoded in this file from the raw pins delayed by the
// documented latency (two synchroniser flops + the accept register with F = 0,
// one more for a_prev/b_prev) and the CTRL fields as written over the bus;
// exposed registers only tie the wrapper's model to the implementation so
// that k-induction closes (p_sync, p_ctrl, p_flags are those invariants,
// each one a documented fact).
//! uses counter_bank 1 28
//! in_top mcu_counters_ 1 28
//! expose counter_bank/channels_0_counter_lo_q counter_bank/channels_0_counter_hi_q
//! expose counter_bank/channels_0_counter_lo_max_q counter_bank/channels_0_counter_lo_nonzero_q
//! expose counter_bank/channels_0_counter_mid_ones_q counter_bank/channels_0_counter_mid_zero_q
//! expose counter_bank/preset_q counter_bank/preset_low_is_max_q counter_bank/preset_low_is_nonzero_q
//! expose counter_bank/channels_0_filter_a_sync1_q counter_bank/channels_0_filter_a_sync2_q
//! expose counter_bank/channels_0_filter_a_accepted_q counter_bank/channels_0_filter_a_count_q
//! expose counter_bank/channels_0_filter_a_count_nonzero_q
//! expose counter_bank/channels_0_filter_b_sync1_q counter_bank/channels_0_filter_b_sync2_q
//! expose counter_bank/channels_0_filter_b_accepted_q counter_bank/channels_0_filter_b_count_q
//! expose counter_bank/channels_0_filter_b_count_nonzero_q
//! expose counter_bank/channels_0_filter_z_accepted_q
//! expose counter_bank/channels_0_a_prev_q counter_bank/channels_0_b_prev_q
//! expose counter_bank/channels_0_ctrl_q counter_bank/channels_0_index_clear_q_q
//! expose counter_bank/channels_0_index_q counter_bank/channels_0_armed_q
//! expose counter_bank/channels_0_err_count_q counter_bank/channels_0_err_sat_q
//! expose counter_bank/channels_0_snap_count_q counter_bank/channels_0_snap_index_q
//! expose counter_bank/channels_0_snap_status_q
//! depth 12
//! cover_depth 20
//! break p_sync
//!   from: channels_0_filter_a_sync2_d = channels_0_filter_a_sync1_q;
//!   to: channels_0_filter_a_sync2_d = channels_0_filter_a_pin;
//! break p_ctrl
//!   from: localparam channels_0_ctrl_writable = 32'hff03ff;
//!   to: localparam channels_0_ctrl_writable = 32'hff03f7;
//! break p_flags
//!   from: preset_low_is_max_d = (wdata & low_mask) == low_mask;
//!   to: preset_low_is_max_d = (wdata & low_mask) == 32'he;
//! break p_step
//!   from: channels_0_decoder_up_reg_d = channels_0_decoder_backward;
//!   to: channels_0_decoder_up_reg_d = channels_0_decoder_forward;
//! break p_step
//!   from: channels_0_decoder_backward = channels_0_decoder_rise_b & ~channels_0_decoder_rise_a;
//!   to: channels_0_decoder_backward = channels_0_decoder_rise_b;
//! break p_illegal_hold
//!   from: channels_0_decoder_changed_b & ~channels_0_decoder_changed_a & ~channels_0_decoder_a_ne_b
//!   to: channels_0_decoder_changed_b & ~channels_0_decoder_a_ne_b
//! break p_err
//!   from: channels_0_err_q_d = channels_0_illegal & channels_0_ctrl_q[channels_0_err_en_bit];
//!   to: channels_0_err_q_d = channels_0_illegal;
//! break p_err
//!   from: channels_0_err_d = 1'b1;
//!   to: channels_0_err_d = channels_0_err_q;
//! break p_err_count
//!   from: channels_0_err_count_d = channels_0_err_count_q + 8'h1;
//!   to: channels_0_err_count_d = channels_0_err_count_q + 8'h2;
//! break p_snap_hold
//!   from: if (channels_0_snapshot) begin
//!   to: if (1'b1) begin
//! break p_snap_capture
//!   from: channels_0_snap_count_d = channels_0_count_now;
//!   to: channels_0_snap_count_d = channels_0_index_q;
//! break p_read
//!   from: channels_0_count_view = channels_0_snap_count_q;
//!   to: channels_0_count_view = channels_0_count_now;
module counter_bank_props(input clock, input reset, input [0:0] a, input [0:0] b,
                          input [0:0] z, input [0:0] home, input [7:0] addr,
                          input [31:0] wdata, input we, input re, input snapshot_strobe);
  wire [31:0] rdata;
  wire [0:0] error, index_seen;
  wire [31:0] lo_q, hi_q, preset_q, ctrl_q, index_q, snap_count_q, snap_index_q, snap_status_q;
  wire lo_max_q, lo_nonzero_q, mid_ones_q, mid_zero_q, preset_max_q, preset_nz_q;
  wire a_s1, a_s2, a_lvl, a_cnz, b_s1, b_s2, b_lvl, b_cnz, z_lvl;
  wire [3:0] a_cnt, b_cnt;
  wire a_prev_q, b_prev_q, idx_clr_q, armed_q, err_sat_q;
  wire [7:0] err_count_q;
  // The count's width and its halves (docs "Implementation note").
  localparam W = 28, L = W / 2, H = W - L;

  counter_bank uut(
    .clock(clock), .reset(reset), .a(a), .b(b), .z(z), .home(home), .addr(addr),
    .wdata(wdata), .we(we), .re(re), .rdata(rdata), .snapshot_strobe(snapshot_strobe),
    .error(error), .index_seen(index_seen),
    .channels_0_counter_lo_q(lo_q), .channels_0_counter_hi_q(hi_q),
    .channels_0_counter_lo_max_q(lo_max_q), .channels_0_counter_lo_nonzero_q(lo_nonzero_q),
    .channels_0_counter_mid_ones_q(mid_ones_q), .channels_0_counter_mid_zero_q(mid_zero_q),
    .preset_q(preset_q), .preset_low_is_max_q(preset_max_q),
    .preset_low_is_nonzero_q(preset_nz_q),
    .channels_0_filter_a_sync1_q(a_s1), .channels_0_filter_a_sync2_q(a_s2),
    .channels_0_filter_a_accepted_q(a_lvl), .channels_0_filter_a_count_q(a_cnt),
    .channels_0_filter_a_count_nonzero_q(a_cnz),
    .channels_0_filter_b_sync1_q(b_s1), .channels_0_filter_b_sync2_q(b_s2),
    .channels_0_filter_b_accepted_q(b_lvl), .channels_0_filter_b_count_q(b_cnt),
    .channels_0_filter_b_count_nonzero_q(b_cnz),
    .channels_0_filter_z_accepted_q(z_lvl),
    .channels_0_a_prev_q(a_prev_q), .channels_0_b_prev_q(b_prev_q),
    .channels_0_ctrl_q(ctrl_q), .channels_0_index_clear_q_q(idx_clr_q),
    .channels_0_index_q(index_q), .channels_0_armed_q(armed_q),
    .channels_0_err_count_q(err_count_q), .channels_0_err_sat_q(err_sat_q),
    .channels_0_snap_count_q(snap_count_q), .channels_0_snap_index_q(snap_index_q),
    .channels_0_snap_status_q(snap_status_q));

  // ---- environment -------------------------------------------------------
  reg past_valid = 0;
  always @(posedge clock) past_valid <= 1;
  initial assume(reset);
  // The docs require reset to be held for at least 4 clocks (synchroniser,
  // level, then a_prev/b_prev); rst_len counts the reset clocks before this one.
  reg [2:0] rst_len = 0;
  always @(posedge clock) rst_len <= reset ? (rst_len == 3'd4 ? 3'd4 : rst_len + 3'd1) : 3'd0;
  always @(*) if (!reset) assume(rst_len == 3'd0 || rst_len == 3'd4);

  // ---- bus decode (docs "Register bus", "Commands") ------------------------
  wire wr_ctrl   = we && addr == 8'h08;
  wire wr_cmd    = we && addr == 8'h09;
  wire cmd_clear = wr_cmd && wdata[0];
  wire cmd_load  = wr_cmd && wdata[1];
  wire cmd_clrst = wr_cmd && wdata[3];
  wire snap_now  = (we && addr == 8'h01) || snapshot_strobe;

  // CTRL fields as written: MODE 2:0, REVERSE 3, ERR_EN 4, FILTER_AB 19:16; 0 in reset.
  reg [2:0] mode_m = 0;
  reg rev_m = 0, en_m = 0;
  reg [3:0] fab_m = 0;
  // Filter off: FILTER_AB has been 0 since reset (so the filter count is 0).
  reg filt_off = 1;
  always @(posedge clock) begin
    if (reset) begin
      mode_m <= 0; rev_m <= 0; en_m <= 0; fab_m <= 0; filt_off <= 1;
    end else if (wr_ctrl) begin
      mode_m <= wdata[2:0]; rev_m <= wdata[3]; en_m <= wdata[4]; fab_m <= wdata[19:16];
      if (wdata[19:16] != 4'd0) filt_off <= 0;
    end
  end

  // ---- the pins through the documented latency (F = 0) -------------------
  // s1, s2, level (accepted, one clock after s2 with F = 0), prev.
  reg pa1 = 0, pa2 = 0, pa3 = 0, pa4 = 0, pb1 = 0, pb2 = 0, pb3 = 0, pb4 = 0;
  always @(posedge clock) begin
    pa1 <= a; pa2 <= pa1; pa3 <= pa2; pa4 <= pa3;
    pb1 <= b; pb2 <= pb1; pb3 <= pb2; pb4 <= pb3;
  end

  // ---- the step table (docs "Counting"), decoded from (pa4,pb4) -> (pa3,pb3)
  // Gray position along the forward order 00 -> 10 -> 11 -> 01 (a,b).
  wire [1:0] pos_p = {pb4, pa4 ^ pb4};
  wire [1:0] pos_c = {pb3, pa3 ^ pb3};
  wire gray_fwd = pos_c == pos_p + 2'd1;
  wire gray_bwd = pos_c == pos_p - 2'd1;
  wire rise_a = pa3 && !pa4;
  wire rise_b = pb3 && !pb4;
  reg fwd_m, bwd_m;
  always @(*) begin
    fwd_m = 0; bwd_m = 0;
    case (mode_m)
      3'd0: begin fwd_m = gray_fwd; bwd_m = gray_bwd; end
      3'd1: begin fwd_m = gray_fwd && pa3 != pa4; bwd_m = gray_bwd && pa3 != pa4; end
      3'd2: begin fwd_m = {pa4, pb4, pa3, pb3} == 4'b0010; bwd_m = {pa4, pb4, pa3, pb3} == 4'b1000; end
      3'd3: begin fwd_m = rise_a && !pb3; bwd_m = rise_a && pb3; end
      3'd4: begin fwd_m = rise_a && !rise_b; bwd_m = rise_b && !rise_a; end
      default: ;
    endcase
  end
  wire up_m   = rev_m ? bwd_m : fwd_m;
  wire down_m = rev_m ? fwd_m : bwd_m;
  wire illegal_m = mode_m < 3'd3 && pa3 != pa4 && pb3 != pb4;

  // The decision registered (up_q/down_q: 0 in reset and in a LOAD clock),
  // LOAD's second edge, the illegal flag and err_q.
  reg upq_m = 0, downq_m = 0, loadq_m = 0, illq_m = 0, errq_m = 0, illq_noen_m = 0;
  always @(posedge clock) begin
    upq_m       <= up_m && !cmd_load && !reset;
    downq_m     <= down_m && !cmd_load && !reset;
    loadq_m     <= cmd_load && !cmd_clear && !reset;
    illq_m      <= illegal_m && !reset;
    illq_noen_m <= illegal_m && !en_m && !reset;
    errq_m      <= illegal_m && en_m && !reset;
  end

  // The live count: the high half over the low half.
  wire [W-1:0] count = {hi_q[H-1:0], lo_q[L-1:0]};
  // A legal change other than a step in the previous clock: reset, CMD.CLEAR,
  // CMD.LOAD (both edges) and an index clear (index_clear_q).
  wire other_now = reset || cmd_clear || cmd_load || loadq_m || idx_clr_q;
  reg other_p = 0;
  always @(posedge clock) other_p <= other_now;

  // STATUS as the docs define it from the live registers.
  wire [31:0] status_m = {16'd0, err_count_q, 1'b0, z_lvl, b_lvl, a_lvl, 1'b0,
                          index_seen[0], armed_q, error[0]};

  // ---- read pipeline (docs "Register bus": data two edges after re) ------
  wire rd_snap = re && (addr == 8'h0A || addr == 8'h0B || addr == 8'h0C);
  wire [31:0] rd_exp = addr == 8'h0A ? {{(32-W){snap_count_q[W-1]}}, snap_count_q[W-1:0]}
                     : addr == 8'h0B ? {{(32-W){snap_index_q[W-1]}}, snap_index_q[W-1:0]}
                     : snap_status_q;
  reg rv1 = 0, rv2 = 0;
  reg [31:0] rexp1 = 0, rexp2 = 0;
  reg [7:0] raddr1 = 0, raddr2 = 0;
  always @(posedge clock) begin
    rv1 <= rd_snap && !reset;  rexp1 <= rd_exp;  raddr1 <= addr;
    rv2 <= rv1 && !reset;      rexp2 <= rexp1;   raddr2 <= raddr1;
  end

  always @(*) begin
    // Invariant: s1, s2 are the pins one and two clocks ago; with the filter
    // off the filter count is 0, the accepted level is s2 one clock later and
    // a_prev/b_prev the level one clock later still (outside reset).
    if (past_valid)
      p_sync: assert(a_s1 == pa1 && a_s2 == pa2 && b_s1 == pb1 && b_s2 == pb2
                     && (!filt_off || (a_lvl == pa3 && b_lvl == pb3 && a_cnt == 4'd0
                                       && b_cnt == 4'd0 && !a_cnz && !b_cnz))
                     && (!filt_off || reset || (a_prev_q == pa4 && b_prev_q == pb4)));
    // Invariant: CTRL's fields are what the bus wrote (0 after reset).
    if (past_valid)
      p_ctrl: assert(ctrl_q[2:0] == mode_m && ctrl_q[3] == rev_m && ctrl_q[4] == en_m
                     && ctrl_q[19:16] == fab_m && (!filt_off || fab_m == 4'd0));
    // Invariant: the counter's look-ahead flags and the bank's PRESET flags
    // describe what they summarise (docs "Implementation note"); the mid-bit
    // flags when the low bits are 01/10; halves hold no bits above W/2.
    if (past_valid)
      p_flags: assert(lo_max_q == (&lo_q[L-1:0]) && lo_nonzero_q == (|lo_q[L-1:0])
                      && lo_q[31:L] == 0 && hi_q[31:H] == 0
                      && ((lo_q[1:0] != 2'b01 && lo_q[1:0] != 2'b10)
                          || (mid_ones_q == (&lo_q[L-1:2]) && mid_zero_q == !(|lo_q[L-1:2])))
                      && preset_max_q == (&preset_q[L-1:0])
                      && preset_nz_q == (|preset_q[L-1:0])
                      && err_sat_q == (err_count_q == 8'hff));
  end

  always @(posedge clock) if (past_valid) begin
    // Filter off: the count moves by exactly the step decided two clocks
    // before (registered in up_q/down_q, added at the next edge), unless
    // reset, CLEAR, LOAD or an index clear acted in the previous clock.
    if (filt_off && !other_p)
      p_step: assert(count == $past(count) + {{(W-1){1'b0}}, $past(upq_m)}
                             - {{(W-1){1'b0}}, $past(downq_m)});
    // An illegal transition never moves the count.
    if (filt_off && !other_p && $past(illq_m))
      p_illegal_hold: assert(count == $past(count));
    // STATUS.ERR (the `error` output): cleared by reset and CLEAR_STATUS, set
    // one clock after an illegal transition detected with ERR_EN, else holds.
    if (filt_off)
      p_err: assert(error == ($past(reset) || $past(cmd_clrst) ? 1'b0
                              : $past(errq_m) ? 1'b1 : $past(error)));
    // ERR_COUNT: the same, counting and saturating at 2^8 - 1.
    if (filt_off)
      p_err_count: assert(err_count_q == ($past(reset) || $past(cmd_clrst) ? 8'd0
                          : $past(errq_m) ? ($past(err_count_q) == 8'hff ? 8'hff : $past(err_count_q) + 8'd1)
                          : $past(err_count_q)));
    // The snapshot registers change only at SNAPSHOT (write or strobe) and
    // reset (to 0); COUNT/INDEX hold W-bit values.
    p_snap_hold: assert(snap_count_q[31:W] == 0 && snap_index_q[31:W] == 0 && index_q[31:W] == 0
                        && ($past(reset) ? (snap_count_q == 0 && snap_index_q == 0 && snap_status_q == 0)
                            : $past(snap_now) || (snap_count_q == $past(snap_count_q)
                                && snap_index_q == $past(snap_index_q)
                                && snap_status_q == $past(snap_status_q))));
    // SNAPSHOT captures count, index and status as they stood in its clock.
    if (!$past(reset) && $past(snap_now))
      p_snap_capture: assert(snap_count_q == {{(32-W){1'b0}}, $past(count)} && snap_index_q == $past(index_q)
                             && snap_status_q == $past(status_m));
    // A read of COUNT / INDEX / STATUS returns, two edges later, the snapshot
    // register as it stood in the clock of re (COUNT, INDEX sign-extended).
    if (rv2)
      p_read: assert(rdata == rexp2);
  end

  // ---- covers -----------------------------------------------------------
  reg stepped_p = 0;
  always @(posedge clock) stepped_p <= upq_m || downq_m;
  wire stepped = filt_off && !other_p && stepped_p;
  always @(posedge clock) if (past_valid) begin
    c_step_x4_up: cover(stepped && mode_m == 3'd0 && !rev_m && count == $past(count) + 1'b1);
    c_step_x4_down: cover(stepped && mode_m == 3'd0 && !rev_m && count == $past(count) - 1'b1);
    c_step_x4_reverse: cover(stepped && mode_m == 3'd0 && rev_m && count == $past(count) - 1'b1);
    c_step_x2: cover(stepped && mode_m == 3'd1);
    c_step_x1: cover(stepped && mode_m == 3'd2);
    c_step_pulse_dir_up: cover(stepped && mode_m == 3'd3 && count == $past(count) + 1'b1);
    c_step_pulse_dir_down: cover(stepped && mode_m == 3'd3 && count == $past(count) - 1'b1);
    c_step_cw: cover(stepped && mode_m == 3'd4 && count == $past(count) + 1'b1);
    c_step_ccw: cover(stepped && mode_m == 3'd4 && count == $past(count) - 1'b1);
    c_illegal_err_en: cover(filt_off && !other_p && $past(illq_m) && $past(errq_m));
    c_err_set: cover(filt_off && error && !$past(error) && err_count_q == 8'd1);
    c_illegal_err_off: cover(filt_off && !other_p && $past(illq_noen_m) && !error);
    c_load: cover(!$past(reset) && $past(loadq_m) && count == {{(W-8){1'b1}}, 8'h85});
    c_snapshot: cover(!$past(reset) && $past(snap_now) && snap_count_q != 0);
    c_read_count_negative: cover(rv2 && raddr2 == 8'h0A && rdata[31]);
    c_read_status_err: cover(rv2 && raddr2 == 8'h0C && rdata[0]);
    c_read_index: cover(rv2 && raddr2 == 8'h0B);
  end
endmodule
