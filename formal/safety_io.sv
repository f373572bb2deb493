// safety_io, narrow instance 1 axis + filter tick P = 2 clocks (shipped P = 12 500 makes the 4P+2 window unreachable; axes are copies): a limit held 4P+2 samples raises its direction stop by the next edge and it holds until a clear; e-stop halts in ESTOP_LATENCY = 3 edges, the watchdog bites T+1 edges after arm/reload, HALT holds until CLEAR, no ENABLE while HALT; irq = OR(cause AND mask) IRQ_LATENCY = 1 edge later (docs/safety_io.md)
//! uses safety_io 1 2
//! expose safety_io/cause_q safety_io/cause_mask_q safety_io/done_cause_q safety_io/done_mask_q safety_io/low_cause_q safety_io/low_mask_q
//! expose safety_io/machine_limit_cause_q safety_io/machine_limit_mask_q safety_io/machine_home_alarm_cause_q safety_io/machine_home_alarm_mask_q
//! expose safety_io/gpio_cause_q safety_io/gpio_mask_q safety_io/soft_cause_q safety_io/soft_mask_q safety_io/counter_events_cause_q safety_io/counter_events_mask_q
//! expose safety_io/active_high_q safety_io/machine_pos_ctrl_q safety_io/machine_neg_ctrl_q safety_io/machine_ticking_q
//! expose safety_io/count_q safety_io/armed_q safety_io/timeout_q safety_io/bitten_q
//! depth 14
//! cover_depth 20
//! break p_filter_tick
//!   from: localparam machine_tick_reload = 24'h1;
//!   to: localparam machine_tick_reload = 24'h2;
//! break p_regs
//!   from: machine_limit_mask_d = machine_wdata & machine_ctrl_mask;
//!   to: machine_limit_mask_d = machine_wdata;
//! break p_stop_up
//!   from: machine_stop_up = machine_limit_cause_q[0:0] | machine_stop_both;
//!   to: machine_stop_up = machine_stop_both;
//! break p_stop_up
//!   from: machine_pos_acting = machine_pos_active & machine_pos_ctrl_q[0:0];
//!   to: machine_pos_acting = machine_pos_active & machine_pos_ctrl_q[0:0] & ~machine_home_acting;
//! break p_stop_down
//!   from: machine_stop_down = machine_limit_cause_q[16:16] | machine_stop_both;
//!   to: machine_stop_down = machine_stop_both;
//! break p_stop_down
//!   from: machine_neg_filters_0_sync_d = machine_neg_filters_0_meta_q;
//!   to: machine_neg_filters_0_sync_d = machine_neg_filters_0_meta_q & machine_neg_filters_0_sync_q;
//! break p_stop_up_holds
//!   from: assign stop_up = machine_stop_up | soft_stop_up | counter_events_stop_up;
//!   to: assign stop_up = machine_stop_up | soft_stop_up | counter_events_stop_up | doorbell;
//! break p_stop_down_holds
//!   from: machine_limit_cause_d = machine_limit_kept | machine_limit_events;
//!   to: machine_limit_cause_d = machine_limit_events;
//! break p_estop_halt
//!   from: latch_next = estop_sync_q | (estop_latch_q & ~(write_clear & wdata[0]));
//!   to: latch_next = (estop_sync_q & ~we) | (estop_latch_q & ~(write_clear & wdata[0]));
//! break p_estop_halt
//!   from: estop_sync_d = estop_meta_q;
//!   to: estop_sync_d = estop_meta_q & estop_meta_d;
//! break p_halt_holds
//!   from: bitten_next = bite | (bitten_q & ~(write_clear & wdata[1]));
//!   to: bitten_next = bite | (bitten_q & ~(we & wdata[1]));
//! break p_no_enable_while_halt
//!   from: halting = latch_next | bitten_next;
//!   to: halting = latch_next;
//! break p_wdt_model
//!   from: reload = we & (addr == addr_reload) & (wdata == key) & armed_q;
//!   to: reload = we & (addr == addr_reload) & (wdata[15:0] == key[15:0]) & armed_q;
//! break p_bite
//!   from: bite = armed_q & ~|count_q & ~reload & ~write_timeout;
//!   to: bite = armed_q & ~|count_q & ~reload & ~write_timeout & ~we;
//! break p_wdt_cause
//!   from: system_events = system_events | watchdog_cause;
//!   to: system_events = system_events | (watchdog_cause & {4{~doorbell}});
//! break p_irq
//!   from: irq_low_d = irq_active != active_high_q;
//!   to: irq_low_d = irq_active;
//! break p_irq
//!   from: irq_active = |(cause_q & cause_mask_q) | |(done_cause_q & done_mask_q) | |(low_cause_q & low_mask_q) | machine_irq_active | gpio_irq_active | soft_irq_active | counter_events_irq_active;
//!   to: irq_active = |(cause_q & cause_mask_q) | |(done_cause_q & done_mask_q) | |(low_cause_q & low_mask_q) | gpio_irq_active | soft_irq_active | counter_events_irq_active;
module safety_io_props(
  input clock, input reset,
  input [6:0] addr, input [31:0] wdata, input we, input re,
  input estop_ok, input done, input low,
  input limit_pos, input limit_neg, input home, input alarm,
  input at_soft_max, input at_soft_min, input counter_error, input index_seen,
  input doorbell, input servo_tick, input [15:0] gpi);

  // Instance facts (docs/safety_io.md): P = filter_tick_clocks = 2 in this
  // build, FILTER_TICKS = 4, so a pin held 4P+2 samples has passed its filter.
  localparam integer P = 2;
  localparam integer FW = 4 * P + 2;            // samples a held pin needs
  localparam [31:0] WATCHDOG_KEY = 32'h5AFED06E;
  // Register word offsets (regmap::safety_io).
  localparam [6:0] A_CLEAR = 7'd2, A_WDT_TIMEOUT = 7'd4, A_WDT_RELOAD = 7'd5,
                   A_IRQ_CTRL = 7'd7, A_CAUSE_MASK = 7'd9, A_DONE_MASK = 7'd11,
                   A_LOW_MASK = 7'd13, A_LIMIT_POS_CTRL = 7'd14, A_LIMIT_NEG_CTRL = 7'd15,
                   A_LIMIT_CAUSE = 7'd20, A_LIMIT_MASK = 7'd21, A_HOME_ALARM_CAUSE = 7'd22,
                   A_HOME_ALARM_MASK = 7'd23, A_GPI_MASK = 7'd27, A_HOME_STOP = 7'd31,
                   A_SOFT_LIMIT_CAUSE = 7'd33, A_SOFT_LIMIT_MASK = 7'd34, A_COUNTER_MASK = 7'd36;
  localparam [31:0] AXIS_FIELDS = 32'h0001_0001; // [N-1:0] and [N+15:16], N = 1

  wire [31:0] rdata;
  wire halt, stop_up, stop_down, home_event, drive_enable, irq;
  wire [15:0] gpo_out, gpo_oe;
  // exposed registers (the documented cause/mask/CTRL/watchdog registers)
  wire [3:0] cause_q, cause_mask_q;
  wire done_cause_q, done_mask_q, low_cause_q, low_mask_q;
  wire [31:0] machine_limit_cause_q, machine_limit_mask_q;
  wire [31:0] machine_home_alarm_cause_q, machine_home_alarm_mask_q;
  wire [15:0] gpio_cause_q, gpio_mask_q;
  wire [31:0] soft_cause_q, soft_mask_q, counter_events_cause_q, counter_events_mask_q;
  wire active_high_q, machine_ticking_q;
  wire [31:0] machine_pos_ctrl_q, machine_neg_ctrl_q;
  wire [31:0] count_q, timeout_q;
  wire armed_q, bitten_q;

  safety_io uut(
    .clock(clock), .reset(reset), .addr(addr), .wdata(wdata), .we(we), .re(re), .rdata(rdata),
    .estop_ok(estop_ok), .done(done), .low(low),
    .limit_pos(limit_pos), .limit_neg(limit_neg), .home(home), .alarm(alarm),
    .at_soft_max(at_soft_max), .at_soft_min(at_soft_min),
    .counter_error(counter_error), .index_seen(index_seen),
    .doorbell(doorbell), .servo_tick(servo_tick),
    .halt(halt), .stop_up(stop_up), .stop_down(stop_down), .home_event(home_event),
    .drive_enable(drive_enable), .irq(irq), .gpi(gpi), .gpo_out(gpo_out), .gpo_oe(gpo_oe),
    .cause_q(cause_q), .cause_mask_q(cause_mask_q), .done_cause_q(done_cause_q),
    .done_mask_q(done_mask_q), .low_cause_q(low_cause_q), .low_mask_q(low_mask_q),
    .machine_limit_cause_q(machine_limit_cause_q), .machine_limit_mask_q(machine_limit_mask_q),
    .machine_home_alarm_cause_q(machine_home_alarm_cause_q),
    .machine_home_alarm_mask_q(machine_home_alarm_mask_q),
    .gpio_cause_q(gpio_cause_q), .gpio_mask_q(gpio_mask_q),
    .soft_cause_q(soft_cause_q), .soft_mask_q(soft_mask_q),
    .counter_events_cause_q(counter_events_cause_q), .counter_events_mask_q(counter_events_mask_q),
    .active_high_q(active_high_q), .machine_pos_ctrl_q(machine_pos_ctrl_q),
    .machine_neg_ctrl_q(machine_neg_ctrl_q), .machine_ticking_q(machine_ticking_q),
    .count_q(count_q), .armed_q(armed_q), .timeout_q(timeout_q), .bitten_q(bitten_q));

  initial assume(reset);
  reg past_valid = 0;
  reg [1:0] age = 0;                         // edges seen, saturating at 3
  always @(posedge clock) begin
    past_valid <= 1;
    if (age != 2'd3) age <= age + 2'd1;
  end

  // ---- bus shadows: what the read-write registers must hold (writes act at
  // the edge where `we` is high; every register resets to 0) ----
  reg [31:0] sh_pos_ctrl = 0, sh_neg_ctrl = 0, sh_limit_mask = 0, sh_ha_mask = 0;
  reg [31:0] sh_soft_mask = 0, sh_counter_mask = 0;
  reg [15:0] sh_gpi_mask = 0;
  reg [3:0] sh_cause_mask = 0;
  reg sh_done_mask = 0, sh_low_mask = 0, sh_active_high = 0;
  always @(posedge clock)
    if (reset) begin
      sh_pos_ctrl <= 0; sh_neg_ctrl <= 0; sh_limit_mask <= 0; sh_ha_mask <= 0;
      sh_soft_mask <= 0; sh_counter_mask <= 0; sh_gpi_mask <= 0; sh_cause_mask <= 0;
      sh_done_mask <= 0; sh_low_mask <= 0; sh_active_high <= 0;
    end else if (we) begin
      if (addr == A_LIMIT_POS_CTRL)  sh_pos_ctrl <= wdata & AXIS_FIELDS;
      if (addr == A_LIMIT_NEG_CTRL)  sh_neg_ctrl <= wdata & AXIS_FIELDS;
      if (addr == A_LIMIT_MASK)      sh_limit_mask <= wdata & AXIS_FIELDS;
      if (addr == A_HOME_ALARM_MASK) sh_ha_mask <= wdata & AXIS_FIELDS;
      if (addr == A_SOFT_LIMIT_MASK) sh_soft_mask <= wdata & AXIS_FIELDS;
      if (addr == A_COUNTER_MASK)    sh_counter_mask <= wdata & AXIS_FIELDS;
      if (addr == A_GPI_MASK)        sh_gpi_mask <= wdata[15:0];
      if (addr == A_CAUSE_MASK)      sh_cause_mask <= wdata[3:0];
      if (addr == A_DONE_MASK)       sh_done_mask <= wdata[0];
      if (addr == A_LOW_MASK)        sh_low_mask <= wdata[0];
      if (addr == A_IRQ_CTRL)        sh_active_high <= wdata[0];
    end

  // ---- watchdog as documented: WDT_TIMEOUT = T arms (0 disarms) and loads
  // WDT_COUNT; the key while armed reloads; else count down, bite at 0 ----
  reg [31:0] wd_T = 0, wd_left = 0;
  reg wd_armed = 0, wd_bite = 0, wd_reloaded = 0;
  always @(posedge clock) begin
    wd_bite <= 0;
    if (reset) begin
      wd_T <= 0; wd_left <= 0; wd_armed <= 0; wd_reloaded <= 0;
    end else if (we && addr == A_WDT_TIMEOUT) begin
      wd_T <= wdata; wd_left <= wdata; wd_armed <= |wdata;
    end else if (we && addr == A_WDT_RELOAD && wdata == WATCHDOG_KEY && wd_armed) begin
      wd_left <= wd_T; wd_reloaded <= 1;
    end else if (wd_armed) begin
      if (wd_left == 0) begin wd_armed <= 0; wd_bite <= 1; end
      else wd_left <= wd_left - 1;
    end
  end

  // ---- filter prescaler: ticks at the first edge after reset, then every P ----
  reg [1:0] phase = 0;                       // clocks since the last tick
  always @(posedge clock) phase <= reset ? 2'd0 : (phase == P - 1 ? 2'd0 : phase + 2'd1);

  // ---- pin history: bit i = the sample taken at edge (now - i) ----
  reg [FW+1:0] lp_hist = 0, ln_hist = 0, rst_hist = 0;
  always @(posedge clock) begin
    lp_hist <= {lp_hist[FW:0], limit_pos};
    ln_hist <= {ln_hist[FW:0], limit_neg};
    rst_hist <= {rst_hist[FW:0], reset};
  end
  // the pin read the same level L at the FW edges before this one, no reset
  // from the first of them to this edge
  wire lp_held = (lp_hist[FW:1] == {FW{lp_hist[1]}}) && rst_hist[FW:0] == 0;
  wire ln_held = (ln_hist[FW:1] == {FW{ln_hist[1]}}) && rst_hist[FW:0] == 0;
  // ... and that level was active and enabled in the clock before this edge
  reg [31:0] pos_ctrl_before = 0, neg_ctrl_before = 0;   // the CTRLs in the clock before
  always @(posedge clock) begin
    pos_ctrl_before <= sh_pos_ctrl;
    neg_ctrl_before <= sh_neg_ctrl;
  end
  wire lp_acting = lp_held && ((lp_hist[1] ^ pos_ctrl_before[16]) & pos_ctrl_before[0]);
  wire ln_acting = ln_held && ((ln_hist[1] ^ neg_ctrl_before[16]) & neg_ctrl_before[0]);

  wire irq_cause = |(cause_q & sh_cause_mask) | (done_cause_q & sh_done_mask)
                 | (low_cause_q & sh_low_mask) | |(machine_limit_cause_q & sh_limit_mask)
                 | |(machine_home_alarm_cause_q & sh_ha_mask) | |(gpio_cause_q & sh_gpi_mask)
                 | |(soft_cause_q & sh_soft_mask) | |(counter_events_cause_q & sh_counter_mask);

  wire w_stop_clear = we && (addr == A_LIMIT_CAUSE || addr == A_HOME_ALARM_CAUSE
                          || addr == A_SOFT_LIMIT_CAUSE || addr == A_HOME_STOP);

  always @(posedge clock) if (past_valid) begin
    // the shared filter prescaler ticks every P clocks from reset
    p_filter_tick: assert(machine_ticking_q == (phase == 0));
    // read-write registers hold what the bus wrote (the masks and CTRLs used below)
    p_regs: assert(machine_pos_ctrl_q == sh_pos_ctrl && machine_neg_ctrl_q == sh_neg_ctrl
                   && machine_limit_mask_q == sh_limit_mask && machine_home_alarm_mask_q == sh_ha_mask
                   && soft_mask_q == sh_soft_mask && counter_events_mask_q == sh_counter_mask
                   && gpio_mask_q == sh_gpi_mask && cause_mask_q == sh_cause_mask
                   && done_mask_q == sh_done_mask && low_mask_q == sh_low_mask
                   && active_high_q == sh_active_high);

    // LIMIT_POS held active FW = 4P+2 samples (filter passed by the last),
    // enabled: stop_up by the next edge (LIMIT_LATENCY), and at every edge while it stays
    if (lp_acting) p_stop_up: assert(stop_up);
    if (ln_acting) p_stop_down: assert(stop_down);
    // a stop is released only by a W1C of its cause (or HOME_STOP) or reset
    if ($past(stop_up) && !$past(reset) && !$past(w_stop_clear)) p_stop_up_holds: assert(stop_up);
    if ($past(stop_down) && !$past(reset) && !$past(w_stop_clear)) p_stop_down_holds: assert(stop_down);

    // estop_ok low at edge k (sampled from the clock before it): HALT from edge k+2
    if (age == 3 && !$past(estop_ok, 3)) p_estop_halt: assert(halt);
    // HALT falls only at a CLEAR write (ESTOP or BITTEN bit)
    if ($past(halt) && !$past(reset) && !($past(we) && $past(addr) == A_CLEAR && |$past(wdata[1:0])))
      p_halt_holds: assert(halt);
    // no drive enabled while HALT
    if (halt) p_no_enable_while_halt: assert(!drive_enable);

    // watchdog registers as documented (WDT_TIMEOUT, WDT_COUNT, STATUS.ARMED)
    p_wdt_model: assert(timeout_q == wd_T && count_q == wd_left && armed_q == wd_armed
                        && (wd_armed || wd_left == 0));
    // the bite: BITTEN and HALT set at edge e + T + 1 ...
    if (wd_bite) p_bite: assert(bitten_q && halt && !drive_enable);
    // ... CAUSE.WATCHDOG and BITTEN set there, and rise at no other edge
    if (!$past(reset))
      p_wdt_cause: assert((!wd_bite || cause_q[1]) && (wd_bite
                          || !((cause_q[1] && !$past(cause_q[1])) || (bitten_q && !$past(bitten_q)))));

    // irq follows STATUS.IRQ = OR(cause AND mask) and IRQ_CTRL.ACTIVE_HIGH one edge later
    if (!$past(reset)) p_irq: assert(irq == !($past(irq_cause) ^ $past(sh_active_high)));
  end

  // ---- covers: every antecedent is reachable ----
  always @(posedge clock) if (past_valid) begin
    c_limit_pos_stop: cover(lp_acting && stop_up && !$past(stop_up));
    // the whole window is needed: the pin changed just before it
    c_limit_pos_full_window: cover(lp_acting && stop_up && !$past(stop_up)
                                   && lp_hist[FW+1] != lp_hist[1] && $past(sh_pos_ctrl[0], 2));
    c_limit_pos_active_low: cover(lp_acting && !lp_hist[1]);
    c_limit_neg_stop: cover(ln_acting && stop_down && !$past(stop_down));
    c_stop_up_cleared: cover($past(stop_up) && !stop_up && !$past(reset));
    c_stop_down_cleared: cover($past(stop_down) && !stop_down && !$past(reset));
    c_estop: cover(age == 3 && !$past(estop_ok, 3) && halt && !$past(halt));
    c_estop_drive_off: cover(age == 3 && !$past(estop_ok, 3) && $past(drive_enable) && !drive_enable);
    c_halt_cleared: cover($past(halt) && !halt);
    c_bite: cover(wd_bite && !$past(halt));
    c_bite_after_reload: cover(wd_bite && wd_reloaded && $past(drive_enable));
    c_irq_limit: cover(!$past(reset) && !irq && $past(irq)
                       && |$past(machine_limit_cause_q & sh_limit_mask));
    c_irq_active_high: cover(!$past(reset) && irq && $past(sh_active_high) && $past(irq_cause));
  end
endmodule
