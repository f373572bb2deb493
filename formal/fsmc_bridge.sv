// FSMC bridge (docs/fsmc_bridge.md): a 32-bit register read as two halves returns both halves of one value as it stood in one clock (reg_rdata free, may change every clock).
//! uses fsmc_bridge
//! expose fsmc_bridge/hold_valid_q fsmc_bridge/hold_hi_q fsmc_bridge/hold_word_q
//! depth 16
//! cover_depth 20
//! break p_low_half
//!   from: d_q_d = reg_rdata[15:0];
//!   to: d_q_d = reg_rdata[31:16];
//! break p_one_sample
//!   from: d_q_d = hold_hi_q;
//!   to: d_q_d = reg_rdata[31:16];
//! break p_low_reads_word
//!   from: assign reg_addr = cyc_a_q[10:1];
//!   to: assign reg_addr = cyc_a_q[9:0];
//! break p_no_second_read
//!   from: assign reg_re = rd_start & cyc_reg & ~use_hold;
//!   to: assign reg_re = rd_start & cyc_reg;
//! break p_kept_half
//!   from: hold_hi_d = reg_rdata[31:16];
//!   to: hold_hi_d = reg_rdata[15:0];
module fsmc_bridge_props(input clock, input reset, input ne_n, input noe_n, input nwe_n,
                         input [11:0] a, input [15:0] d_in, input [31:0] reg_rdata,
                         input [15:0] ram_rdata);
  wire [15:0] d_out;
  wire d_oe;
  wire [9:0] reg_addr;
  wire [31:0] reg_wdata;
  wire reg_we, reg_re;
  wire [9:0] ram_addr;
  wire [15:0] ram_wdata;
  wire ram_we;
  // Exposed internal registers (kept half, for induction strengthening).
  wire hold_valid_q;
  wire [15:0] hold_hi_q;
  wire [9:0] hold_word_q;

  fsmc_bridge uut(.clock(clock), .reset(reset), .ne_n(ne_n), .noe_n(noe_n), .nwe_n(nwe_n),
                  .a(a), .d_in(d_in), .d_out(d_out), .d_oe(d_oe), .reg_addr(reg_addr),
                  .reg_wdata(reg_wdata), .reg_we(reg_we), .reg_re(reg_re),
                  .reg_rdata(reg_rdata), .ram_addr(ram_addr), .ram_wdata(ram_wdata),
                  .ram_we(ram_we), .ram_rdata(ram_rdata),
                  .hold_valid_q(hold_valid_q), .hold_hi_q(hold_hi_q),
                  .hold_word_q(hold_word_q));

  reg past_valid = 0;
  always @(posedge clock) past_valid <= 1;
  initial assume(reset);

  // ---- pin history (one solver step = one FPGA clock; inputs are the values
  // the edge at the end of the step samples) ----
  reg noe_q = 1, nwe_q = 1, ne_q = 1;
  reg [11:0] a_q = 0;
  reg [2:0] noe_run = 0;   // consecutive NOE#-low samples before this one (saturates at 7)
  always @(posedge clock) begin
    noe_q <= noe_n;
    nwe_q <= nwe_n;
    ne_q <= ne_n;
    a_q <= a;
    noe_run <= noe_n ? 3'd0 : (noe_run == 3'd7 ? 3'd7 : noe_run + 3'd1);
  end
  wire noe_fall = !noe_n && noe_q;
  wire noe_rise = noe_n && !noe_q;
  wire nwe_fall = !nwe_n && nwe_q;

  // ---- bus assumptions (docs/fsmc_bridge.md) ----
  always @(*) begin
    // Mode 1, one access at a time: a read strobes NOE#, a write NWE#, never both.
    assume(noe_n || nwe_n);
    if (past_valid) begin
      // ADDSET = 4 (23.8 ns >= T + FPGA_INPUT, "FSMC timing"/ADDSET): every
      // access starts with both strobes high for at least one FPGA sample.
      assume(!(noe_fall && !nwe_q));
      assume(!(nwe_fall && !noe_q));
      // Mode 1 waveform: A and NE1# are set in the address phase and held
      // through the strobe ("A (valid when NE1 falls) >= 23.8 ns to settle
      // before an edge can sample the strobe low").
      if (!noe_n && !noe_q) assume(a == a_q && ne_n == ne_q);
      // DATAST = 21 (125 ns >= 5 T + 2 + 10 + 9.95, "DATAST (reads)"): a bank-1
      // NOE# pulse spans at least 6 FPGA samples.
      if (noe_rise && !ne_q) assume(noe_run >= 3'd6);
    end
  end

  // ---- MCU-side transaction tracker (pins only) ----
  localparam IDLE = 2'd0, LO = 2'd1, GAP = 2'd2, HI = 2'd3;
  reg [1:0] st = IDLE;
  reg [9:0] w = 0;          // word address of the tracked 32-bit read
  reg re_seen = 0;          // the low-half strobe's register read happened
  reg re1 = 0, re2 = 0;     // ... one and two clocks ago
  reg [31:0] snap = 0;      // reg_rdata at the clock the read takes (edge 4 -> edge 5)
  reg snap_ok = 0;
  reg [15:0] lo_half = 0;   // what the MCU took as the low half
  reg [15:0] dout_q = 0;
  wire lo_start = noe_fall && !ne_n && !a[11] && !a[0];
  wire hi_start = noe_fall && !ne_n && !a[11] && a[0] && a[10:1] == w;

  always @(posedge clock) begin
    dout_q <= d_out;
    re1 <= 0;
    re2 <= re1;
    if (re2 && st == LO) begin
      // reg_re's edge registers the address, the next edge loads reg_rdata,
      // the bridge takes it at the edge after ("Read", edges 3-5).
      snap <= reg_rdata;
      snap_ok <= 1;
    end
    case (st)
      LO: begin
        if (reg_re && !re_seen) begin re_seen <= 1; re1 <= 1; end
        if (noe_rise) begin
          lo_half <= dout_q;            // the MCU samples at the end of DATAST
          st <= GAP;
        end
      end
      GAP: if (!nwe_n || ne_n) st <= IDLE;  // any other access, or NE1# released
      HI: if (noe_rise) st <= IDLE;
      default: ;
    endcase
    if (noe_fall) begin
      if (st == GAP && hi_start) st <= HI;
      else if (lo_start) begin
        st <= LO; w <= a[10:1]; re_seen <= 0; re1 <= 0; re2 <= 0; snap_ok <= 0;
      end
      else st <= IDLE;
    end
    if (reset) begin
      st <= IDLE; re1 <= 0; re2 <= 0;
    end
  end

  // d_out is loaded at edge 5 of the strobe and must stay until NOE# rises:
  // from the 6th low sample on it is what the MCU can take.
  wire data_due = !noe_n && noe_run >= 3'd5 && !reset;

  always @(*) begin
    if (past_valid && !reset) begin
      // The low half: bits 15:0 of reg_rdata at the clock the read takes.
      if (st == LO && data_due) p_low_half: assert(snap_ok && d_out == snap[15:0]);
      // The low-half strobe reads its register exactly once, at word A[10:1].
      if (st == LO && reg_re) p_low_reads_word: assert(!re_seen && reg_addr == w);
      // Between the halves the bridge keeps bits 31:16 of that same clock's
      // value, with the word address (docs "Register read, low half").
      if ((st == LO && data_due) || st == GAP)
        p_kept_half: assert(hold_valid_q && hold_hi_q == snap[31:16] &&
                            hold_word_q == w && (st != GAP || lo_half == snap[15:0]));
      // The high half of a 32-bit read: no second register read ...
      if (st == HI) p_no_second_read: assert(!reg_re);
      // ... and the two halves the MCU takes are one clock's reg_rdata.
      if (st == HI && data_due) p_one_sample: assert({d_out, lo_half} == snap);
    end
  end

  always @(*) begin
    c_low_half_read: cover(past_valid && st == LO && noe_rise && !reset);
    c_two_half_read: cover(past_valid && st == HI && noe_rise && !reset);
    c_reg_rdata_changes: cover(past_valid && st == HI && noe_rise && !reset &&
                               reg_rdata != snap);
  end
endmodule
