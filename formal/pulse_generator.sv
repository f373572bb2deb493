// One axis's step/pulse generator at its shipped widths, S1/S2 through the CW/CCW selector: step/space/set-up/hold timing, no runt, no lost step (docs/pulse_generator.md)
//! uses pulse_generator
//! uses pulse_mode_selector
//! expose pulse_generator/timer_t_step_q pulse_generator/timer_t_dir_q pulse_generator/timer_len_ok_q pulse_generator/timer_space_ok_q pulse_generator/timer_hold_ok_q pulse_generator/timer_setup_ok_q pulse_generator/timer_emitted_q pulse_generator/timer_nonzero_q pulse_generator/command_up_q pulse_generator/command_down_q
//! depth 10
//! cover_depth 14
//! break p_cw_ccw_exclusive
//!   from: chip_c1_3 = 1'b0;
//!   to: chip_c1_3 = s1;
//! break p_s1_len
//!   from: timer_len_ok_d = timer_step_len <= timer_timer_one;
//!   to: timer_len_ok_d = 1'b1;
//! break p_s1_space
//!   from: timer_space_ok_d = timer_step_space <= timer_timer_one;
//!   to: timer_space_ok_d = 1'b1;
//! break p_s2_still_while_s1_high
//!   from: timer_turns = ~timer_flush & ~timer_step_q_q &
//!   to: timer_turns = ~timer_flush &
//! break p_s2_setup
//!   from: timer_setup_ok_d = timer_dir_setup <= timer_timer_one;
//!   to: timer_setup_ok_d = 1'b1;
//! break p_s2_hold
//!   from: timer_hold_ok_d = timer_dir_hold <= timer_timer_one;
//!   to: timer_hold_ok_d = 1'b1;
//! break p_no_runt
//!   from: timer_falls = timer_step_q_q & timer_len_ok_q;
//!   to: timer_falls = timer_step_q_q;
//! break p_no_runt
//!   from: chip_c2_3 = s1;
//!   to: chip_c2_3 = s1 | s2;
//! break p_no_step_lost
//!   from: position_step = one;
//!   to: position_step = 32'h0;
//! break p_no_step_lost
//!   from: timer_delta = timer_two;
//!   to: timer_delta = timer_one;
//! break p_halt
//!   from: timer_emit = ~timer_flush &
//!   to: timer_emit = 1'b1 &
//! break p_s1_timer
//!   from: localparam timer_timer_restart = 16'h2;
//!   to: localparam timer_timer_restart = 16'h3;
//! break p_s2_timer
//!   from: timer_t_dir_d = timer_timer_restart;
//!   to: timer_t_dir_d = timer_timer_one;
//! break p_queue_regs
//!   from: timer_nonzero_d = |timer_pending_next;
//!   to: timer_nonzero_d = |timer_pending_q_q;
module pulse_generator_props(
    input clock, input reset, input enable, input halt,
    input [31:0] rate, input [31:0] move_rate, input moves,
    input [15:0] step_len, input [15:0] step_space,
    input [15:0] dir_setup, input [15:0] dir_hold,
    input k);

  wire step, dir, commanded, advancing;
  wire [31:0] position, status;
  wire [15:0] timer_t_step_q, timer_t_dir_q;
  wire timer_len_ok_q, timer_space_ok_q, timer_hold_ok_q, timer_setup_ok_q;
  wire timer_emitted_q, timer_nonzero_q, command_up_q, command_down_q;
  pulse_generator uut(
    .clock(clock), .reset(reset), .enable(enable), .halt(halt),
    .rate(rate), .move_rate(move_rate), .moves(moves),
    .step_len(step_len), .step_space(step_space),
    .dir_setup(dir_setup), .dir_hold(dir_hold),
    .step(step), .dir(dir), .position(position), .commanded(commanded),
    .advancing(advancing), .status(status),
    .timer_t_step_q(timer_t_step_q), .timer_t_dir_q(timer_t_dir_q),
    .timer_len_ok_q(timer_len_ok_q), .timer_space_ok_q(timer_space_ok_q),
    .timer_hold_ok_q(timer_hold_ok_q), .timer_setup_ok_q(timer_setup_ok_q),
    .timer_emitted_q(timer_emitted_q), .timer_nonzero_q(timer_nonzero_q),
    .command_up_q(command_up_q), .command_down_q(command_down_q));

  // S1 = step, S2 = direction into the selector; K free (CTRL.MODE).
  wire f1, f2;
  pulse_mode_selector sel(.k(k), .s1(step), .s2(dir), .f1(f1), .f2(f2));

  initial assume(reset);
  reg past_valid = 0;
  always @(posedge clock) past_valid <= 1;

  // No assumption on the timings: the docs let STEP_TIMING/DIR_TIMING
  // change at any clock and promise that "the comparison in clock k uses
  // the timing of clock k-1", so an edge at the end of clock n is held to
  // the timing of clock n-1 (`*_p2` seen one clock after the edge).
  // 0 counts as 1 (docs: "minimum times in clocks (0 counts as 1)").
  reg [15:0] len_p1 = 0, len_p2 = 0, space_p1 = 0, space_p2 = 0;
  reg [15:0] setup_p1 = 0, setup_p2 = 0, hold_p1 = 0, hold_p2 = 0;
  reg reset_p = 1, halt_p = 0, step_p = 0, dir_p = 0, k_p = 0;
  // Clocks S1 was high / low, S2 was 1 / 0, up to the previous clock
  // (0 when the previous clock had the other level), saturating.
  reg [15:0] s1_high = 0, s1_low = 0, s2_one = 0, s2_zero = 0;
  // The current S1 low / S2 = 0 level began at an edge, not at a reset
  // (after a reset the levels count as long held: no edge to time from).
  reg s1_low_fresh = 0, s2_zero_fresh = 0;
  // Clocks F1 / F2 were high in CW/CCW (K = 1), up to the previous clock;
  // `clean`: that pulse rose with K already 1 (not by a mode switch).
  reg [15:0] f1_high = 0, f2_high = 0;
  reg f1_clean = 0, f2_clean = 0;

  // Step accounting: `commanded` (one step this clock, in the sign of the
  // selected rate) reaches the command register at the next edge, the
  // queue (PENDING) at the one after; a step whose S1 rose at the last
  // edge leaves PENDING for `position` at the next edge. HALT drops what
  // is queued (PENDING and the command register), reset everything.
  wire negative = moves ? move_rate[31] : rate[31];
  wire [31:0] cmd_now = commanded ? (negative ? 32'hffffffff : 32'h1) : 32'h0;
  reg [31:0] cmd_p = 0;             // the command of the previous clock
  wire rose = step && !step_p;      // S1 rose at the last edge: leaving
  wire [31:0] leaving = rose ? (dir ? 32'hffffffff : 32'h1) : 32'h0;
  wire [31:0] pending = {{16{status[15]}}, status[15:0]};
  wire [31:0] queued = pending + cmd_p;
  reg [31:0] ledger = 0;            // commanded since reset, less HALT's drops

  always @(posedge clock) begin
    len_p1 <= step_len;   len_p2 <= len_p1;
    space_p1 <= step_space; space_p2 <= space_p1;
    setup_p1 <= dir_setup; setup_p2 <= setup_p1;
    hold_p1 <= dir_hold;  hold_p2 <= hold_p1;
    reset_p <= reset; halt_p <= halt; step_p <= step; dir_p <= dir; k_p <= k;
    s1_high <= !step ? 16'h0 : (s1_high == 16'hffff ? s1_high : s1_high + 16'h1);
    s1_low <= step ? 16'h0 : (s1_low == 16'hffff ? s1_low : s1_low + 16'h1);
    s2_one <= !dir ? 16'h0 : (s2_one == 16'hffff ? s2_one : s2_one + 16'h1);
    s2_zero <= dir ? 16'h0 : (s2_zero == 16'hffff ? s2_zero : s2_zero + 16'h1);
    s1_low_fresh <= reset ? 1'b0 : (step ? 1'b1 : s1_low_fresh);
    s2_zero_fresh <= reset ? 1'b0 : (dir ? 1'b1 : s2_zero_fresh);
    f1_high <= !(k && f1) ? 16'h0 : (f1_high == 16'hffff ? f1_high : f1_high + 16'h1);
    f2_high <= !(k && f2) ? 16'h0 : (f2_high == 16'hffff ? f2_high : f2_high + 16'h1);
    f1_clean <= (k && f1) && (f1_high == 16'h0 ? k_p : f1_clean);
    f2_clean <= (k && f2) && (f2_high == 16'h0 ? k_p : f2_clean);
    cmd_p <= reset ? 32'h0 : cmd_now;
    ledger <= reset ? 32'h0 : ledger + cmd_now - (halt ? queued - leaving : 32'h0);
  end

  wire fell = !step && step_p;
  wire turned = dir != dir_p;
  // Clocks (1-based) the current level of S1 / S2 has held, this clock included.
  wire [16:0] s1_run = step ? {1'b0, s1_high} + 17'h1 : {1'b0, s1_low} + 17'h1;
  wire [16:0] s2_run = dir ? {1'b0, s2_one} + 17'h1 : {1'b0, s2_zero} + 17'h1;
  wire s1_fresh = step || s1_low_fresh;
  wire s2_fresh = dir || s2_zero_fresh;
  wire [15:0] s2_held = dir_p ? s2_one : s2_zero;   // S2's level up to the last edge
  wire f1_fell = !reset_p && k && !f1 && f1_high != 16'h0 && f1_clean;
  wire f2_fell = !reset_p && k && !f2 && f2_high != 16'h0 && f2_clean;

  wire f1_same = !(f1_high != 16'h0 && f1_clean) || f1_high == s1_high;
  wire f2_same = !(f2_high != 16'h0 && f2_clean) || f2_high == s1_high;
  wire [15:0] f_high = f1_fell ? f1_high : f2_high;
  wire runt_ok = f1_same && f2_same
                 && (!(f1_fell || f2_fell) || (f_high != 16'h0 && f_high >= len_p2));
  // Internal timer state against the runs counted here (strengthening for
  // induction; the flags are each timing compared one clock ahead).
  wire [15:0] t_step_want = s1_run >= 17'hfffe ? 16'hffff : s1_run[15:0] + 16'h1;
  wire [15:0] t_dir_want = s2_run >= 17'hfffe ? 16'hffff : s2_run[15:0] + 16'h1;
  wire s1_timer_ok = s1_fresh
      ? timer_t_step_q == t_step_want && timer_len_ok_q == (s1_run >= {1'b0, len_p1})
        && timer_space_ok_q == (s1_run >= {1'b0, space_p1})
        && timer_hold_ok_q == (s1_run >= {1'b0, hold_p1})
      : timer_t_step_q == 16'hffff && timer_len_ok_q && timer_space_ok_q && timer_hold_ok_q;
  wire s2_timer_ok = s2_fresh
      ? timer_t_dir_q == t_dir_want && timer_setup_ok_q == (s2_run >= {1'b0, setup_p1})
      : timer_t_dir_q == 16'hffff && timer_setup_ok_q;
  wire queue_regs_ok = command_up_q == (cmd_p == 32'h1) && command_down_q == (cmd_p == 32'hffffffff)
      && timer_emitted_q == rose && timer_nonzero_q == (status[15:0] != 16'h0)
      && (!rose || (dir ? $signed(pending) <= 0 : $signed(pending) >= 0));

  always @(*) begin
    if (past_valid) begin
      // Strengthening invariants (exposed registers).
      p_s1_timer: assert(s1_timer_ok);
      p_s2_timer: assert(s2_timer_ok);
      p_queue_regs: assert(queue_regs_ok);
      // No commanded step is lost: emitted (position) + queued (PENDING and
      // the command register) = commanded since reset less HALT's drops;
      // the queue never wraps (the NCO holds at +-32766/7: |queued| <= 32767).
      p_no_step_lost: assert(ledger == position + queued
                             && $signed(queued) <= 32767 && $signed(queued) >= -32767);
      // CW/CCW: never both outputs at once.
      if (k) p_cw_ccw_exclusive: assert(!(f1 && f2));
      // No runt on F1/F2 in CW/CCW: each F pulse is one S1 pulse, and
      // lasts >= STEP_LEN clocks.
      p_no_runt: assert(runt_ok);
    end
    if (past_valid && !reset_p) begin
      // Every S1 high lasts >= STEP_LEN clocks.
      if (fell) p_s1_len: assert(s1_high != 16'h0 && s1_high >= len_p2);
      // Every S1 low between steps lasts >= STEP_SPACE clocks.
      if (rose && s1_low_fresh) p_s1_space: assert(s1_low != 16'h0 && s1_low >= space_p2);
      // S2 never changes while S1 is high, nor at the edge S1 rises.
      if (step || step_p) p_s2_still_while_s1_high: assert(!turned);
      // S2 stable >= DIR_SETUP clocks (at least one) before S1 rises.
      if (rose && (dir_p || s2_zero_fresh))
        p_s2_setup: assert(s2_held != 16'h0 && s2_held >= setup_p2);
      // S2 changes only after S1 has been low >= DIR_HOLD clocks.
      if (turned && s1_low_fresh) p_s2_hold: assert(s1_low != 16'h0 && s1_low >= hold_p2);
      // HALT: the queue empties at the edge, S1 starts no step, S2 does not turn.
      if (halt_p) p_halt: assert(status[15:0] == 16'h0 && !rose && !turned);
    end
    // Covers: each property's antecedent, with timings above the minimum.
    c_cw_f1: cover(past_valid && k && f1);
    c_cw_f2: cover(past_valid && k && f2);
    c_s1_fall: cover(past_valid && !reset_p && fell && len_p2 >= 16'd3);
    c_s1_rise_after_fall: cover(past_valid && !reset_p && rose && s1_low_fresh && space_p2 >= 16'd3);
    c_s2_turn_after_fall: cover(past_valid && !reset_p && turned && s1_low_fresh && hold_p2 >= 16'd2);
    c_s1_rise_after_turn: cover(past_valid && !reset_p && rose && (dir_p || s2_zero_fresh) && setup_p2 >= 16'd2);
    c_s1_high_s2_one: cover(past_valid && !reset_p && step && step_p && dir);
    c_f1_pulse: cover(past_valid && !reset_p && f1_fell && len_p2 >= 16'd2);
    c_f2_pulse: cover(past_valid && !reset_p && f2_fell && len_p2 >= 16'd2);
    c_steps_queued: cover(past_valid && $signed(pending) >= 2 && position != 32'h0);
    c_halt_drops: cover(past_valid && !reset_p && halt && status[15:0] != 16'h0 && cmd_p != 32'h0);
    c_halt_while_high: cover(past_valid && !reset_p && halt_p && step && step_p);
  end
endmodule
