// The ISA bridge's external RAM chip (motionhdl testbench), the twin of
// `DualPortSram` in testbench/src/checks/isa_bridge/rust_run.rs: an asynchronous dual-port
// SRAM with 35 ns access time (garbage, 16'hdead, until then), written
// when WE# rises. Its right port is the DSP, clocked like the internal
// build's DSP port, so the external build offers the internal build's
// DSP pins. The array starts undefined; the checks zero it through the
// DSP port first. One process writes the array: the DSP port, and the
// left port's write seen one clock after WE# rose (address and data
// still held).
`timescale 1ns / 1ps
`default_nettype none
module isa_dual_port_sram (
    input wire clock,
    input wire [9:0] ram_addr,
    input wire [15:0] ram_d_out,
    input wire ram_d_oe,
    input wire ram_ce_n,
    input wire ram_oe_n,
    input wire ram_we_n,
    output wire [15:0] ram_d_in,
    input wire [9:0] dsp_addr,
    input wire [15:0] dsp_wdata,
    input wire dsp_we,
    output reg [15:0] dsp_rdata
);
    reg [15:0] chip_mem [0:1023];
    reg [15:0] chip_q = 16'hdead;
    reg [31:0] pc_writes = 0;
    reg [31:0] dsp_writes = 0;
    reg we_n_seen = 1'b1;
    initial dsp_rdata = 16'h0;
    assign ram_d_in = ram_d_oe ? ram_d_out
        : (!ram_ce_n && !ram_oe_n && ram_we_n) ? chip_q : 16'hffff;
    always @(ram_addr or ram_oe_n or ram_ce_n or pc_writes or dsp_writes) begin
        chip_q <= 16'hdead;
        chip_q <= #35 chip_mem[ram_addr];
    end
    always @(posedge clock) begin
        dsp_rdata <= chip_mem[dsp_addr];
        we_n_seen <= ram_we_n;
        if (!we_n_seen && ram_we_n && !ram_ce_n) begin
            chip_mem[ram_addr] <= ram_d_out;
            pc_writes <= pc_writes + 1;
        end
        if (dsp_we) begin
            chip_mem[dsp_addr] <= dsp_wdata;
            dsp_writes <= dsp_writes + 1;
        end
    end
endmodule
`default_nettype wire
