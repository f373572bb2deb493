// The FSMC bridge's test slave (motionhdl testbench), the twin of
// `TestSlave` in testbench/src/checks/fsmc_bridge/slave.rs: a register file with the
// counter bank's read contract (the edge with reg_re takes the address,
// the next edge loads reg_rdata; in between it shows POISON), live
// registers 0x3f0..0x3ff = {k, k} at edge k, and a RAM with the DSP-port
// contract (ram_rdata is the word at the previous edge's ram_addr). It
// counts register reads, register writes and RAM writes.
//
// The arrays start undefined: they are cleared one word a clock for the
// first CLEAR_CLOCKS clocks, so the bus stream starts that many whole
// clocks late (every phase stays as in the Rust run). Each array is written
// by the one process below.
`timescale 1ns / 1ps
`default_nettype none
module fsmc_test_slave (
    input wire clock,
    input wire [9:0] reg_addr,
    input wire [31:0] reg_wdata,
    input wire reg_we,
    input wire reg_re,
    output reg [31:0] reg_rdata,
    input wire [9:0] ram_addr,
    input wire [15:0] ram_wdata,
    input wire ram_we,
    output reg [15:0] ram_rdata,
    output reg [31:0] reg_reads,
    output reg [31:0] reg_writes,
    output reg [31:0] ram_writes
);
    localparam [31:0] POISON = 32'hdeadbeef;
    reg [31:0] regs [0:1023];
    reg [15:0] ram [0:1023];
    reg [31:0] k = 32'h0;
    reg read_pending = 1'b0;
    reg [9:0] read_word = 10'h0;
    reg clear = 1'b1;
    reg [9:0] clear_word = 10'h0;
    initial begin
        reg_rdata = 32'h0;
        ram_rdata = 16'h0;
        reg_reads = 32'h0;
        reg_writes = 32'h0;
        ram_writes = 32'h0;
    end
    always @(posedge clock) begin
        if (clear) begin
            regs[clear_word] <= 32'h0;
            ram[clear_word] <= 16'h0;
            clear_word <= clear_word + 10'd1;
            if (clear_word == 10'h3ff) clear <= 1'b0;
        end else begin
            if (read_pending)
                reg_rdata <= read_word[9:4] == 6'h3f
                    ? {k[15:0], k[15:0]} : regs[read_word];
            else if (reg_re)
                reg_rdata <= POISON;
            read_pending <= reg_re;
            if (reg_re) begin
                read_word <= reg_addr;
                reg_reads <= reg_reads + 1;
            end
            if (reg_we) begin
                reg_writes <= reg_writes + 1;
                if (reg_addr[9:4] != 6'h3f)
                    regs[reg_addr] <= reg_wdata;
            end
            ram_rdata <= ram[ram_addr];
            if (ram_we) begin
                ram_writes <= ram_writes + 1;
                ram[ram_addr] <= ram_wdata;
            end
        end
        k <= k + 1;
    end
endmodule
`default_nettype wire
