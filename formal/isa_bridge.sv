// ISA bridge, internal-RAM build (docs/isa_bridge.md): each IOR#/IOW# strobe acts exactly once (counter, AUTO_INC, IRQ_EN, the sticky STATUS bits, one queued RAM write per DATA write, the doorbells), and nothing happens with AEN high or another base.
//! uses isa_bridge
//! expose isa_bridge/core_count_q isa_bridge/core_auto_inc_q isa_bridge/core_cyc_sel_q isa_bridge/core_cyc_reg_q isa_bridge/core_pw_valid_q isa_bridge/core_pw_addr_q isa_bridge/core_pw_data_q isa_bridge/ram_pc_write_enable isa_bridge/ram_pc_write_address isa_bridge/ram_pc_write_data isa_bridge/core_wrapped_q isa_bridge/core_collision_q isa_bridge/core_irq_en_q isa_bridge/core_bell_q
//! depth 12
//! cover_depth 24
//! break p_counter
//!   from: core_count_d = core_count_q + 10'h1;
//!   to: core_count_d = core_count_q + 10'h2;
//! break p_counter
//!   from: core_write_end = core_iow_s2_q & ~core_iow_s3_q & core_cyc_sel_q;
//!   to: core_write_end = core_iow_s2_q & core_cyc_sel_q;
//! break p_counter
//!   from: core_read_end = core_ior_s2_q & ~core_ior_s3_q & core_cyc_sel_q;
//!   to: core_read_end = core_ior_s2_q & ~core_ior_s3_q;
//! break p_auto_inc
//!   from: core_auto_inc_d = core_wdata_q[core_auto_inc_bit];
//!   to: core_auto_inc_d = core_wdata_q[core_irq_en_bit];
//! break p_ram_write_once
//!   from: ram_pc_write_enable = dsp_we | core_write_valid;
//!   to: ram_pc_write_enable = dsp_we | core_write_valid | core_write_end;
//! break p_ram_write_word
//!   from: ram_pc_write_data = core_write_data;
//!   to: ram_pc_write_data = ~core_write_data;
//! break p_sd_oe_quiet
//!   from: core_sd_oe = core_selected & ~core_ior_n;
//!   to: core_sd_oe = ~core_ior_n;
//! break p_sd_oe_quiet
//!   from: core_decoder_p_eq_q_n = ~((core_decoder_p == core_decoder_q) & ~core_decoder_g_n);
//!   to: core_decoder_p_eq_q_n = ~(core_decoder_p == core_decoder_q);
//! break p_wrapped
//!   from: if (core_advance & (core_count_q == core_addr_max)) begin
//!   to: if (core_advance) begin
//! break p_collision
//!   from: core_collision_seen = core_write_valid & dsp_we & (dsp_addr == core_write_addr);
//!   to: core_collision_seen = dsp_we & (dsp_addr == core_write_addr);
//! break p_irq_en
//!   from: core_irq_en_d = core_wdata_q[core_irq_en_bit];
//!   to: core_irq_en_d = core_wdata_q[core_auto_inc_bit];
//! break p_bell
//!   from: (core_read_end & (core_cyc_reg_q == core_reg_data) & (core_count_q == core_mailbox_to_pc))
//!   to: (core_access_end & (core_cyc_reg_q == core_reg_data) & (core_count_q == core_mailbox_to_pc))
//! break p_irq
//!   from: core_irq = core_bell_q & core_irq_en_q;
//!   to: core_irq = core_bell_q;
//! break p_bell_to_dsp
//!   from: core_bell_to_dsp = core_write_done & core_pw_valid_q & (core_pw_addr_q == core_mailbox_to_dsp);
//!   to: core_bell_to_dsp = core_pw_valid_q & (core_pw_addr_q == core_mailbox_to_dsp);
//! break p_queued_write
//!   from: core_pw_data_d = core_wdata_q;
//!   to: core_pw_data_d = core_sd_s1_q;
//! break p_latched_cycle
//!   from: core_cyc_sel_d = core_sel_s2_q;
//!   to: core_cyc_sel_d = ~core_sel_s2_q;
module isa_bridge_props(input clock, input reset, input [9:0] sa, input [15:0] sd_in,
                        input ior_n, input iow_n, input aen, input bale, input [7:0] base,
                        input [9:0] dsp_addr, input [15:0] dsp_wdata, input dsp_we);
  wire [15:0] sd_out;
  wire sd_oe, iocs16_n, irq, bell_to_dsp;
  wire [15:0] dsp_rdata;
  // Exposed internals: the address counter and AUTO_INC (STATUS fields), the
  // latched cycle decode, the one-deep PC write queue and the RAM write port.
  wire [9:0] core_count_q;
  wire core_auto_inc_q, core_cyc_sel_q;
  wire [1:0] core_cyc_reg_q;
  wire core_pw_valid_q;
  wire [9:0] core_pw_addr_q;
  wire [15:0] core_pw_data_q;
  wire ram_pc_write_enable;
  wire [9:0] ram_pc_write_address;
  wire [15:0] ram_pc_write_data;
  wire core_wrapped_q, core_collision_q, core_irq_en_q, core_bell_q;

  isa_bridge uut(.clock(clock), .reset(reset), .sa(sa), .sd_in(sd_in), .sd_out(sd_out),
                 .sd_oe(sd_oe), .ior_n(ior_n), .iow_n(iow_n), .aen(aen), .bale(bale),
                 .base(base), .iocs16_n(iocs16_n), .irq(irq), .bell_to_dsp(bell_to_dsp),
                 .dsp_addr(dsp_addr), .dsp_wdata(dsp_wdata), .dsp_we(dsp_we),
                 .dsp_rdata(dsp_rdata),
                 .core_count_q(core_count_q), .core_auto_inc_q(core_auto_inc_q),
                 .core_cyc_sel_q(core_cyc_sel_q), .core_cyc_reg_q(core_cyc_reg_q),
                 .core_pw_valid_q(core_pw_valid_q), .core_pw_addr_q(core_pw_addr_q),
                 .core_pw_data_q(core_pw_data_q),
                 .ram_pc_write_enable(ram_pc_write_enable),
                 .ram_pc_write_address(ram_pc_write_address),
                 .ram_pc_write_data(ram_pc_write_data),
                 .core_wrapped_q(core_wrapped_q), .core_collision_q(core_collision_q),
                 .core_irq_en_q(core_irq_en_q), .core_bell_q(core_bell_q));

  reg past_valid = 0;
  always @(posedge clock) past_valid <= 1;
  initial assume(reset);

  localparam R_DATA = 2'd0, R_CLEAR = 2'd1, R_INC = 2'd2, R_STATUS = 2'd3;

  // ---- pin history (one step = one FPGA clock; inputs = what its edge samples) ----
  reg ior_q = 1, iow_q = 1, aen_q = 0;
  reg bale_q = 0, bale_qq = 0;
  reg [9:0] sa_q = 0;
  reg [7:0] base_q = 0;
  reg bale_ok = 0;          // a BALE sample since the last reset
  always @(posedge clock) begin
    ior_q <= ior_n; iow_q <= iow_n; aen_q <= aen; sa_q <= sa; base_q <= base;
    bale_q <= bale; bale_qq <= bale_q;
    if (reset) bale_ok <= 0; else if (bale) bale_ok <= 1;
  end
  wire sel_pins = !aen && sa[9:2] == base;   // the '688 with G = AEN
  wire ior_rise = ior_n && !ior_q;
  wire iow_rise = iow_n && !iow_q;

  // ---- transaction model from the docs ("Registers", "Timing") ----
  // The cycle a command belongs to (SA, AEN as they stand under the strobe).
  reg cmd_sel = 0, cmd_aen = 0;
  reg [1:0] cmd_reg = 0;
  // Write data: the last SD sample taken while IOW# had been low for two
  // samples in a row.
  reg [15:0] m_wdata = 0;
  always @(posedge clock) begin
    if (!ior_n || !iow_n) begin cmd_sel <= sel_pins; cmd_aen <= aen; cmd_reg <= sa[1:0]; end
    if (!iow_n && !iow_q) m_wdata <= sd_in;
  end
  // An access acts once, 3 edges after its strobe rises: the rise is first
  // sampled at step r, the access acts at the edge ending step r+2.
  reg a1_v = 0, a1_w = 0, a1_sel = 0, a1_aen = 0, a2_v = 0, a2_w = 0, a2_sel = 0, a2_aen = 0;
  reg [1:0] a1_reg = 0, a2_reg = 0;
  reg [15:0] a1_data = 0, a2_data = 0;
  always @(posedge clock) begin
    a1_v <= (ior_rise || iow_rise) && !reset;
    a1_w <= iow_rise; a1_sel <= cmd_sel; a1_aen <= cmd_aen; a1_reg <= cmd_reg; a1_data <= m_wdata;
    a2_v <= a1_v && !reset;
    a2_w <= a1_w; a2_sel <= a1_sel; a2_aen <= a1_aen; a2_reg <= a1_reg; a2_data <= a1_data;
  end
  wire act = a2_v && a2_sel;                 // this card, AEN low: the access acts
  wire act_data_write = act && a2_w && a2_reg == R_DATA;

  // Counter and AUTO_INC per the register table: what the exposed counter
  // must be after this clock, from its value now and the access acting now.
  reg [9:0] m_cnt = 0;      // expected counter (set each clock from the last one)
  reg m_auto = 0;
  always @(posedge clock) begin
    m_cnt <= core_count_q;
    m_auto <= core_auto_inc_q;
    if (reset) begin
      m_cnt <= 0; m_auto <= 0;
    end else if (act) begin
      case (a2_reg)
        R_DATA: if (core_auto_inc_q) m_cnt <= core_count_q + 10'd1;
        R_CLEAR: m_cnt <= 0;
        R_INC: m_cnt <= core_count_q + 10'd1;
        R_STATUS: if (a2_w) begin m_cnt <= a2_data[9:0]; m_auto <= a2_data[12]; end
      endcase
    end
  end

  // A DATA write is queued with the counter and its data as it acts and lands
  // in the first later clock in which the DSP does not write.
  reg pending = 0;
  reg [9:0] p_addr = 0;
  reg [15:0] p_data = 0;
  wire pc_lands = ram_pc_write_enable && !dsp_we;   // a DSP write always takes the port
  always @(posedge clock) begin
    if (reset) pending <= 0;
    else if (act_data_write) begin pending <= 1; p_addr <= core_count_q; p_data <= a2_data; end
    else if (pending && !dsp_we) pending <= 0;
  end

  // STATUS's IRQ_EN and sticky bits per the register table and "Doorbells":
  // WRAPPED sets as an advance leaves 0x3FF, clears at ADDR_CLEAR or a 1
  // written to bit 13; COLLISION sets when the DSP writes the word a queued
  // PC write waits for, clears at a 1 written to bit 14; BELL sets at the
  // DSP's write of ISA_MAILBOX_TO_PC (winning over a clear in the same
  // clock), clears at the PC's DATA read of that word or a 1 written to
  // bit 15.
  localparam [9:0] MAILBOX_TO_PC = 10'h3FE, MAILBOX_TO_DSP = 10'h3FF;
  wire advance = act && (a2_reg == R_INC || (a2_reg == R_DATA && core_auto_inc_q));
  wire status_write = act && a2_w && a2_reg == R_STATUS;
  reg m_wrapped = 0, m_collision = 0, m_irq_en = 0, m_bell = 0;
  always @(posedge clock) begin
    m_wrapped <= core_wrapped_q; m_collision <= core_collision_q;
    m_irq_en <= core_irq_en_q; m_bell <= core_bell_q;
    if (reset) begin
      m_wrapped <= 0; m_collision <= 0; m_irq_en <= 0; m_bell <= 0;
    end else begin
      if (advance && core_count_q == 10'h3FF) m_wrapped <= 1;
      else if ((act && a2_reg == R_CLEAR) || (status_write && a2_data[13])) m_wrapped <= 0;
      if (pending && dsp_we && dsp_addr == p_addr) m_collision <= 1;
      else if (status_write && a2_data[14]) m_collision <= 0;
      if (status_write) m_irq_en <= a2_data[11];
      if (dsp_we && dsp_addr == MAILBOX_TO_PC) m_bell <= 1;
      else if ((act && !a2_w && a2_reg == R_DATA && core_count_q == MAILBOX_TO_PC)
               || (status_write && a2_data[15])) m_bell <= 0;
    end
  end

  // ---- bus assumptions (docs/isa_bridge.md) ----
  reg past_iow_low2 = 0, past_ior_low2 = 0;   // the strobe was low in the two samples before this one
  always @(posedge clock) begin
    past_iow_low2 <= !iow_n && !iow_q;
    past_ior_low2 <= !ior_n && !ior_q;
  end
  always @(*) begin
    // One bus cycle at a time: IOR# and IOW# are never both low.
    assume(ior_n || iow_n);
    if (past_valid) begin
      // The base switches do not move.
      assume(base == base_q);
      // SA and AEN change only with a new bus cycle, while BALE is high and no
      // command is low (testbench/src/bfm/isa.rs: SA and AEN held through the
      // command and after; "Timing": SA1..SA0 and the decode travel beside
      // the strobe; "Decode": the card never answers in DMA cycles).
      if (!(bale && ior_n && iow_n)) assume(sa == sa_q && aen == aen_q);
      // Write data: commands of >= 2 clocks ("Back-to-back cycles").
      if (iow_rise) assume(!iow_q && past_iow_low2);
      if (ior_rise) assume(past_ior_low2);
    end
    // Every bus cycle starts with BALE: no command before a BALE since reset.
    if (!ior_n || !iow_n) assume(bale_ok && !reset);
    // Reset (hold >= 5 clocks, "Pins") comes with the bus idle: no command,
    // no access still to act, no PC write queued.
    if (reset) assume(ior_n && iow_n && ior_q && iow_q && !a1_v && !a2_v && !pending);
    // "The queue holds one PC write: the DSP must leave one clock free between
    // two PC writes": a DATA write does not act while the last one still
    // waits behind a DSP write in this clock.
    if (act_data_write && pending) assume(!dsp_we);
  end

  // ---- properties ----
  always @(*) begin
    if (past_valid && !reset) begin
      // The address counter moves exactly as the acted accesses say: once per
      // ADDR_INC / DATA-with-AUTO_INC, cleared by ADDR_CLEAR, loaded by a
      // STATUS write, and never by a cycle with AEN high or another base.
      p_counter: assert(core_count_q == m_cnt);
      p_auto_inc: assert(core_auto_inc_q == m_auto);
      p_wrapped: assert(core_wrapped_q == m_wrapped);
      p_collision: assert(core_collision_q == m_collision);
      p_irq_en: assert(core_irq_en_q == m_irq_en);
      p_bell: assert(core_bell_q == m_bell);
      // The ISA IRQ line is BELL AND IRQ_EN; the DSP's doorbell pulses in
      // the one clock the PC's write of ISA_MAILBOX_TO_DSP lands.
      p_irq: assert(irq == (m_bell && m_irq_en));
      p_bell_to_dsp: assert(bell_to_dsp == (pc_lands && p_addr == MAILBOX_TO_DSP));
      // The PC side writes the RAM exactly once per DATA write, and at no
      // other time ...
      p_ram_write_once: assert(pc_lands == (pending && !dsp_we));
      // ... at the counter the write acted at, with its data.
      if (pc_lands) p_ram_write_word: assert(ram_pc_write_address == p_addr &&
                                             ram_pc_write_data == p_data);
      // The queued write is the model's (induction strengthening).
      p_queued_write: assert(core_pw_valid_q == pending &&
                             (!pending || (core_pw_addr_q == p_addr && core_pw_data_q == p_data)));
      // BALE latched this cycle's decode (induction strengthening): once BALE
      // has been low for three samples the latch matches the pins.
      if (bale_ok && !bale && !bale_q && !bale_qq)
        p_latched_cycle: assert(core_cyc_sel_q == sel_pins && core_cyc_reg_q == sa[1:0]);
    end
    // Nothing drives SD with AEN high or another base.
    if (aen || sa[9:2] != base) p_sd_oe_quiet: assert(!sd_oe);
  end

  always @(*) begin
    if (past_valid && !reset) begin
      c_data_write: cover(act && a2_w && a2_reg == R_DATA);
      c_data_read_auto_inc: cover(act && !a2_w && a2_reg == R_DATA && core_auto_inc_q);
      c_addr_clear_read: cover(act && !a2_w && a2_reg == R_CLEAR && core_count_q != 0);
      c_addr_clear_write: cover(act && a2_w && a2_reg == R_CLEAR);
      c_addr_inc_read: cover(act && !a2_w && a2_reg == R_INC);
      c_addr_inc_write: cover(act && a2_w && a2_reg == R_INC);
      c_status_write: cover(act && a2_w && a2_reg == R_STATUS);
      c_status_read: cover(act && !a2_w && a2_reg == R_STATUS);
      c_ram_write_lands: cover(pc_lands);
      c_ram_write_waits: cover(pending && dsp_we);
      c_aen_high_write: cover(a2_v && a2_w && a2_aen && a2_reg == R_INC);
      c_aen_high_read: cover(a2_v && !a2_w && a2_aen && a2_reg == R_DATA);
      c_other_base: cover(a2_v && !a2_aen && !a2_sel);
      c_aen_high_ior: cover(!ior_n && aen && sa[9:2] == base);
      c_wraps: cover(advance && core_count_q == 10'h3FF);
      c_collision: cover(pending && dsp_we && dsp_addr == p_addr);
      c_irq_en_set: cover(status_write && a2_data[11]);
      c_irq: cover(irq);
      c_bell_taken: cover(m_bell && act && !a2_w && a2_reg == R_DATA && core_count_q == MAILBOX_TO_PC);
      c_bell_to_dsp: cover(bell_to_dsp);
    end
  end
endmodule
