//! The Verilog twin of [`TopStimulus`]: the same generator as a testbench
//! module driving `motion_controller`, so runs of millions of clocks of the
//! generated Verilog are driven from inside the simulator.

use super::{
    class, TopStimulus, ADDR, BALE, CMD, HOLD, IDLE, ISA_BASE, ISA_HOLD, RERESET_AT, RESET_CLOCKS,
    STROBE, WAIT,
};
use crate::verilog_sim::dut_instance;
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_model::Config;
use std::fmt::Write as _;

/// The Verilog testbench: the same generator driving `module` (the
/// `motion_controller` of `config`), sampling the outputs at each rising
/// edge (before it acts).
pub fn verilog_testbench(
    module: &VerilogModule,
    config: &Config,
    seed: u32,
    cycles: u64,
) -> String {
    let s = TopStimulus::new(config, seed);
    let n = config.axes();
    let top = n - 1;
    let mut writes = String::new();
    for (i, (w, c)) in s.writes.iter().enumerate() {
        let _ = writeln!(
            writes,
            "                {i}: begin write_word = 12'd{w}; write_class = 3'd{c}; end"
        );
    }
    let mut reads = String::new();
    for (i, w) in s.reads.iter().enumerate() {
        let _ = writeln!(reads, "                {i}: read_word = 12'd{w};");
    }
    format!(
        r#"`timescale 1ns / 1ps
`default_nettype none
module top_bench_tb;
{dut}    reg [31:0] x, r0, r1, r2, r3, sum_stim, sum_out, idx, shift, m;
    reg [63:0] cycle;
    reg [1:0] phase [0:{top}];
    reg [15:0] a16, b16, z16, hd, lp16, ln16, hm16, al16, gp16;
    reg [31:0] sp, sq, gx;
    reg moving, jump;
    integer i;
    // FSMC generator
    reg [1:0] f_state;
    reg [31:0] f_count, f_data;
    reg f_ours, f_write, f_two, f_late, f_first;
    reg [11:0] f_a;
    reg [11:0] f_half;
    // ISA generator
    reg [2:0] i_state;
    reg [31:0] i_count;
    reg [9:0] i_port;
    reg [7:0] i_base;
    reg i_aen, i_write, i_late, i_first;
    reg [15:0] i_data;
    reg [11:0] write_word, read_word;
    reg [2:0] write_class;

    function [31:0] xorshift(input [31:0] v);
        reg [31:0] y;
        begin
            y = v ^ (v << 13);
            y = y ^ (y >> 17);
            xorshift = y ^ (y << 5);
        end
    endfunction

    function [31:0] shape(input [2:0] c, input [31:0] d, input [31:0] sh);
        begin
            case (c)
                3'd{c_rate}: shape = $signed(d) >>> sh;
                3'd{c_timing}: shape = (d & 32'd7) | (((d >> 8) & 32'd7) << 16);
                3'd{c_small}: shape = d & 32'd7;
                3'd{c_steps}: shape = d & 32'd255;
                3'd{c_accel}: shape = $signed(d) >>> 20;
                3'd{c_near}: shape = d & 32'd4095;
                default: shape = d;
            endcase
        end
    endfunction

    task lookup_write(input [31:0] k);
        begin
            write_word = 12'd0; write_class = 3'd0;
            case (k)
{writes}                default: ;
            endcase
        end
    endtask

    task lookup_read(input [31:0] k);
        begin
            read_word = 12'd0;
            case (k)
{reads}                default: ;
            endcase
        end
    endtask

    task fsmc_end_half;
        begin
            if (f_two && f_half == 12'd0) begin
                f_half = 12'd1; f_state = 2'd{addr}; f_count = (r1 >> 28) & 32'd1;
            end else begin
                f_state = 2'd{idle};
                if (((r1 >> 24) & 32'd31) == 32'd0) f_count = 32'd64 + ((r1 >> 8) & 32'd1023);
                else f_count = (r1 >> 16) & 32'd15;
            end
        end
    endtask

    task fsmc_clock;
        begin
            if (f_count != 32'd0) f_count = f_count - 32'd1;
            else case (f_state)
                2'd{idle}: begin
                    idx = (r1 >> 8) & 32'hfff;
                    shift = 32'd1 + ((r1 >> 20) & 32'd7);
                    f_ours = 1'b1; f_half = 12'd0; f_two = 1'b0; f_write = 1'b0; f_data = r3;
                    case (r1 & 32'd15)
                        32'd0, 32'd1, 32'd2, 32'd3, 32'd4: begin
                            lookup_write(idx % 32'd{n_writes});
                            f_a = write_word << 1; f_two = 1'b1; f_write = 1'b1;
                            f_data = shape(write_class, r3, shift);
                        end
                        32'd5: begin
                            f_a = 12'd{run_a}; f_two = 1'b1; f_write = 1'b1; f_data = (r3 | (r3 >> 8)) & 32'd{axis_mask};
                        end
                        32'd6, 32'd7, 32'd8, 32'd9: begin
                            lookup_read(idx % 32'd{n_reads});
                            f_a = read_word << 1; f_two = 1'b1;
                        end
                        32'd10: f_a = 12'(idx & 32'h7ff);
                        32'd11: begin f_a = 12'(idx & 32'h7ff); f_write = 1'b1; end
                        32'd12, 32'd13: begin f_a = 12'h800 | 12'(idx & 32'h3ff); f_write = 1'b1; end
                        32'd14: f_a = 12'h800 | 12'(idx & 32'h3ff);
                        default: begin f_ours = 1'b0; f_write = r1[4]; f_a = 12'(idx); end
                    endcase
                    f_state = 2'd{addr}; f_count = (r1 >> 28) & 32'd1;
                end
                2'd{addr}: begin
                    f_state = 2'd{strobe}; f_count = 32'd5 + ((r1 >> 29) & 32'd1);
                    f_late = r1[30]; f_first = 1'b1;
                end
                2'd{strobe}: begin
                    if (f_write) begin f_state = 2'd{hold}; f_count = 32'd0; end
                    else fsmc_end_half;
                end
                default: fsmc_end_half;
            endcase
            hd = f_half == 12'd1 ? f_data[31:16] : f_data[15:0];
            fsmc_ne_n = !(f_ours && f_state != 2'd{idle});
            fsmc_noe_n = !(f_state == 2'd{strobe} && !f_write);
            fsmc_nwe_n = !(f_state == 2'd{strobe} && f_write);
            fsmc_a = f_a + f_half;
            if (f_state == 2'd{addr} && f_write) fsmc_d_in = ~hd;
            else if (f_state == 2'd{strobe} && f_write && f_first && f_late) fsmc_d_in = ~hd;
            else if ((f_state == 2'd{strobe} || f_state == 2'd{hold}) && f_write) fsmc_d_in = hd;
            else fsmc_d_in = 16'hffff;
            if (f_state == 2'd{strobe}) f_first = 1'b0;
        end
    endtask

    task isa_clock;
        begin
            if (i_count != 32'd0) i_count = i_count - 32'd1;
            else case (i_state)
                3'd{idle}: begin
                    i_write = r2[6];
                    i_aen = (r2 & 32'd15) == 32'd0;
                    if ((r2 & 32'd15) == 32'd1 || (r2 & 32'd15) == 32'd2)
                        i_base = 8'd{base} ^ 8'(32'd1 + ((r2 >> 8) & 32'h7f));
                    else i_base = 8'd{base};
                    i_port = {{i_base, r2[5:4]}};
                    i_data = r3[31:16];
                    i_state = 3'd{bale}; i_count = 32'd2;
                end
                3'd{bale}: begin i_state = 3'd{wait_}; i_count = 32'd2; end
                3'd{wait_}: begin
                    i_state = 3'd{cmd}; i_count = 32'd4 + ((r2 >> 10) & 32'd31);
                    i_late = r2[15]; i_first = 1'b1;
                end
                3'd{cmd}: begin i_state = 3'd{isa_hold}; i_count = 32'd2; end
                default: begin
                    i_state = 3'd{idle};
                    if (((r2 >> 20) & 32'd15) == 32'd0) i_count = 32'd50 + ((r2 >> 8) & 32'd255);
                    else i_count = (r2 >> 16) & 32'd7;
                end
            endcase
            isa_bale = i_state == 3'd{bale};
            isa_sa = i_port;
            isa_aen = i_state != 3'd{idle} && i_aen;
            isa_ior_n = !(i_state == 3'd{cmd} && !i_write);
            isa_iow_n = !(i_state == 3'd{cmd} && i_write);
            if (i_state == 3'd{cmd} && i_write && i_first && i_late) isa_sd_in = 16'hffff;
            else if ((i_state == 3'd{cmd} || i_state == 3'd{isa_hold}) && i_write) isa_sd_in = i_data;
            else isa_sd_in = 16'hffff;
            if (i_state == 3'd{cmd}) i_first = 1'b0;
        end
    endtask

    // The next clock's pins, applied at the falling edge (and once at the
    // start for the first rising edge).
    task gen;
        begin
            x = xorshift(x); r0 = x;
            x = xorshift(x); r1 = x;
            x = xorshift(x); r2 = x;
            x = xorshift(x); r3 = x;
            reset = cycle < 64'd{reset_clocks} ||
                ((cycle % 64'd65536) >= 64'd{rereset} && (cycle % 64'd65536) < 64'd{rereset_end});
            moving = (r0 >> 30) == 32'd0;
            jump = (cycle % 64'd8192) == 64'd8191;
            a16 = 16'd0; b16 = 16'd0; z16 = 16'd0;
            for (i = 0; i < {n}; i = i + 1) begin
                m = (r0 >> ((2 * i) % 28)) & 32'd3;
                if (jump) phase[i] = phase[i] + 2'd2;
                else if (moving && (m == 32'd1 || m == 32'd3)) phase[i] = phase[i] + 2'd1;
                else if (moving && m == 32'd2) phase[i] = phase[i] + 2'd3;
                a16[i] = phase[i] == 2'd1 || phase[i] == 2'd2;
                b16[i] = phase[i] == 2'd2 || phase[i] == 2'd3;
                z16[i] = phase[i] == 2'd0 && r0[29];
            end
            enc_a = a16[{top}:0]; enc_b = b16[{top}:0]; enc_z = z16[{top}:0];
            if ((cycle % 64'd{machine_every}) == 64'd0) begin
                sp = r3 & r2; sq = (sp & (sp >> 4)) >> 8;
                lp16 = sp[15:0] & 16'd{machine_mask}; ln16 = sp[31:16] & 16'd{machine_mask};
                hm16 = (r3[15:0] ^ r2[15:0]) & 16'd{machine_mask}; al16 = sq[15:0] & 16'd{machine_mask};
                gx = r2 ^ (r3 >> 7); gp16 = gx[15:0];
            end
            limit_pos = lp16[{top}:0]; limit_neg = ln16[{top}:0]; home = hm16[{top}:0]; alarm = al16[{top}:0]; gpi = gp16;
            fsmc_clock;
            isa_clock;
            sum_stim = sum_stim * 32'd31 + {{fsmc_d_in, fsmc_a, reset, fsmc_nwe_n, fsmc_noe_n, fsmc_ne_n}};
            sum_stim = sum_stim * 32'd31 + {{isa_sd_in, 2'd0, isa_bale, isa_aen, isa_iow_n, isa_ior_n, isa_sa}};
            sum_stim = sum_stim * 32'd31 + {{b16, a16}};
            sum_stim = sum_stim * 32'd31 + {{16'd0, z16}};
            sum_stim = sum_stim * 32'd31 + {{ln16, lp16}};
            sum_stim = sum_stim * 32'd31 + {{al16, hm16}};
            sum_stim = sum_stim * 32'd31 + {{16'd0, gp16}};
            cycle = cycle + 64'd1;
        end
    endtask

    always #5 clock = ~clock;
    initial begin
        clock = 1'b0;
        isa_base = 8'd{base};
        estop_ok = 1'b1;
        lp16 = 16'd0; ln16 = 16'd0; hm16 = 16'd0; al16 = 16'd0; gp16 = 16'd0;
        x = 32'd{seed};
        sum_stim = 32'd0;
        sum_out = 32'd0;
        cycle = 64'd0;
        for (i = 0; i < {n}; i = i + 1) phase[i] = 2'd0;
        f_state = 2'd{idle}; f_count = 32'd0; f_data = 32'd0; f_ours = 1'b0; f_write = 1'b0;
        f_two = 1'b0; f_late = 1'b0; f_first = 1'b0; f_a = 12'd0; f_half = 12'd0;
        i_state = 3'd{idle}; i_count = 32'd0; i_port = 10'd0; i_aen = 1'b0; i_write = 1'b0;
        i_late = 1'b0; i_first = 1'b0; i_data = 16'd0;
        gen;
    end
    // The outputs before the edge acts (the design's flops update after).
    always @(posedge clock) begin
        sum_out = sum_out * 32'd31 + {{12'd0, isa_irq, isa_iocs16_n, isa_sd_oe, fsmc_d_oe, fsmc_d_out}};
        sum_out = sum_out * 32'd31 + {{16'd0, isa_sd_out}};
        sum_out = sum_out * 32'd31 + {{16'(pulse_f2), 16'(pulse_f1)}};
        sum_out = sum_out * 32'd31 + {{15'd0, irq, 16'(drive_enable)}};
        sum_out = sum_out * 32'd31 + {{gpo_oe, gpo_out}};
    end
    // (Icarus starts the clock at X: X -> 0 at time 0 is no clock.)
    always @(negedge clock) if ($time != 0) begin
        if (cycle == 64'd{cycles}) begin
            $display("SUMS %0d %0d", sum_stim, sum_out);
            $finish;
        end else gen;
    end
endmodule
"#,
        dut = dut_instance(module),
        base = ISA_BASE,
        seed = s.x,
        n = n,
        top = top,
        cycles = cycles,
        reset_clocks = RESET_CLOCKS,
        rereset = RERESET_AT,
        rereset_end = RERESET_AT + RESET_CLOCKS,
        n_writes = s.writes.len(),
        n_reads = s.reads.len(),
        run_a = s.run_word * 2,
        axis_mask = s.axis_mask,
        writes = writes,
        reads = reads,
        c_rate = class::RATE,
        c_timing = class::TIMING,
        c_small = class::SMALL,
        c_steps = class::STEPS,
        c_accel = class::ACCEL,
        c_near = class::NEAR,
        idle = IDLE,
        addr = ADDR,
        strobe = STROBE,
        hold = HOLD,
        bale = BALE,
        wait_ = WAIT,
        cmd = CMD,
        isa_hold = ISA_HOLD,
        machine_every = super::MACHINE_EVERY,
        machine_mask = (1u32 << n) - 1,
    )
}
