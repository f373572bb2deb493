//! A deterministic stimulus for long counter-bank runs, implemented twice:
//! in Rust (for the model and the rust-hdl bank) and as a Verilog testbench
//! (for the generated Verilog in Icarus and Verilator). Both print checksums
//! of the stimulus they applied and of `rdata`, so a generator mismatch is
//! caught as surely as a design mismatch.
//!
//! Each channel is a simulated encoder: a Gray phase that holds, steps
//! forward or back each clock; every 4096 clocks each phase jumps by two
//! (an illegal transition); Z pulses at phase 0 on some clocks. The bus
//! snapshots, reads, writes CTRL/CMD/PRESET at random; one clock in 16
//! strobes `home` on random channels (HOME_COUNT captures).

use crate::verilog_sim::{dut_instance, run_for_sums, Simulator};
use motionhdl_hdl::catalog::VerilogModule;
use motionhdl_model::counter::{Bank, BusCycle, CounterFeatures, CounterParams};
use motionhdl_model::regmap;
use std::fmt::Write as _;

/// Clocks of reset at the start of every run.
pub const RESET_CLOCKS: u64 = 4;

/// The stimulus generator.
pub struct Stimulus {
    x: u32,
    phase: Vec<u8>,
    cycle: u64,
    snapshot: u32,
    preset: u32,
    ch_base: u32,
    ch_stride: u32,
    ctrl: u32,
    cmd: u32,
    span: u32,
}

/// One clock of stimulus.
pub struct Clock {
    pub pins: Vec<(bool, bool, bool)>,
    pub reset: bool,
    pub bus: BusCycle,
    /// The `home` input: bit i captures channel i's count.
    pub home: u32,
    /// The `snapshot_strobe` input (the servo tick in the card's top).
    pub snapshot_strobe: bool,
}

impl Stimulus {
    pub fn new(axes: u32, width: u32, seed: u32) -> Self {
        let map = regmap::counter_bank(axes, width);
        let ch = map.array("CH");
        Self {
            x: seed | 1,
            phase: vec![0; axes as usize],
            cycle: 0,
            snapshot: map.register("SNAPSHOT").offset,
            preset: map.register("PRESET").offset,
            ch_base: ch.offset,
            ch_stride: ch.stride,
            ctrl: ch.register("CTRL").offset,
            cmd: ch.register("CMD").offset,
            span: ch.offset + ch.stride * axes,
        }
    }

    fn next(&mut self) -> u32 {
        crate::harness::xorshift32(&mut self.x)
    }

    pub fn clock(&mut self) -> Clock {
        let r1 = self.next();
        let r2 = self.next();
        let r3 = self.next();
        let n = self.phase.len() as u32;
        let jump = self.cycle % 4096 == 4095;
        let mut pins = Vec::new();
        for (i, p) in self.phase.iter_mut().enumerate() {
            let m = (r1 >> ((2 * i as u32) % 32)) & 3;
            if jump {
                *p = (*p + 2) & 3;
            } else if m == 1 {
                *p = (*p + 1) & 3;
            } else if m == 2 {
                *p = (*p + 3) & 3;
            }
            let a = *p == 1 || *p == 2;
            let b = *p == 2 || *p == 3;
            let z = *p == 0 && (r1 >> 31) & 1 == 1;
            pins.push((a, b, z));
        }
        let reset = self.cycle < RESET_CLOCKS;
        let c = (r2 >> 16) % n;
        let ch = self.ch_base + self.ch_stride * c;
        let bus = match r2 & 15 {
            0 => BusCycle::write(self.snapshot, r3),
            1 | 2 | 6 => BusCycle::read((r2 >> 8) % self.span),
            3 => BusCycle::write(ch + self.ctrl, r3),
            4 => BusCycle::write(ch + self.cmd, r3 & 15),
            5 => BusCycle::write(self.preset, r3),
            _ => BusCycle::default(),
        };
        let home = if (r2 >> 4) & 15 == 0 {
            (r3 >> 16) & ((1 << n) - 1)
        } else {
            0
        };
        // One clock in 16, on any bus cycle (a SNAPSHOT write too).
        let snapshot_strobe = (r2 >> 12) & 15 == 0;
        self.cycle += 1;
        Clock {
            pins,
            reset,
            bus,
            home,
            snapshot_strobe,
        }
    }
}

/// Running checksums of the stimulus and of `rdata`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sums {
    pub stimulus: u32,
    pub rdata: u32,
}

fn mix(sum: u32, v: u32) -> u32 {
    sum.wrapping_mul(31).wrapping_add(v)
}

impl Sums {
    pub fn add(&mut self, c: &Clock, rdata_after: u32) {
        let (mut a, mut b, mut z) = (0u32, 0u32, 0u32);
        for (i, p) in c.pins.iter().enumerate() {
            a |= u32::from(p.0) << i;
            b |= u32::from(p.1) << i;
            z |= u32::from(p.2) << i;
        }
        self.stimulus = mix(self.stimulus, a | (b << 16));
        self.stimulus = mix(
            self.stimulus,
            z | (c.bus.addr << 16)
                | (u32::from(c.bus.we) << 24)
                | (u32::from(c.bus.re) << 25)
                | (u32::from(c.reset) << 26),
        );
        self.stimulus = mix(self.stimulus, c.bus.wdata);
        self.stimulus = mix(self.stimulus, c.home);
        self.stimulus = mix(self.stimulus, u32::from(c.snapshot_strobe));
        self.rdata = mix(self.rdata, rdata_after);
    }
}

/// The model's checksums after `cycles` clocks from `seed`.
pub fn model_sums(
    axes: u32,
    width: u32,
    features: CounterFeatures,
    seed: u32,
    cycles: u64,
) -> Sums {
    let mut s = Stimulus::new(axes, width, seed);
    let params = CounterParams::new(width, regmap::ERR_COUNT_BITS).with_features(features);
    let mut bank = Bank::new(axes, params);
    let mut sums = Sums::default();
    for _ in 0..cycles {
        let c = s.clock();
        bank.clock_strobed(&c.pins, c.reset, &c.bus, (c.home, c.snapshot_strobe));
        sums.add(&c, bank.rdata());
    }
    sums
}

/// The Verilog testbench: the same generator, driving `module` (a
/// `counter_bank` of `axes` channels of `width` bits).
pub fn verilog_testbench(module: &VerilogModule, width: u32, seed: u32, cycles: u64) -> String {
    let axes = module
        .ports
        .iter()
        .find(|p| p.name == "a")
        .map_or(0, |p| p.width);
    let s = Stimulus::new(axes, width, seed);
    let n = axes;
    let mut t = String::new();
    let _ = write!(
        t,
        r#"`timescale 1ns / 1ps
`default_nettype none
module counter_bank_tb;
{dut}    reg [31:0] x, r1, r2, r3, c, ch, sum_stim, sum_rdata;
    reg [1:0] phase [0:{top}];
    reg [1:0] m;
    reg [15:0] a16, b16, z16, home16;
    reg jump;
    integer i;
    reg [63:0] cycle;
    function [31:0] xorshift(input [31:0] v);
        reg [31:0] y;
        begin
            y = v ^ (v << 13);
            y = y ^ (y >> 17);
            xorshift = y ^ (y << 5);
        end
    endfunction
    // Everything happens at the falling edge: sample rdata from the last
    // rising edge, then apply the next clock's stimulus. (Verilator 5.006
    // lost variable values after a delay-suspended loop in an initial block.)
    always #5 clock = ~clock;
    initial begin
        clock = 1'b0;
        x = 32'd{seed};
        sum_stim = 32'd0;
        sum_rdata = 32'd0;
        cycle = 64'd0;
        for (i = 0; i < {n}; i = i + 1) phase[i] = 2'd0;
        a = {n}'d0; b = {n}'d0; z = {n}'d0; home = {n}'d0; snapshot_strobe = 1'b0; reset = 1'b1; we = 1'b0; re = 1'b0; addr = 8'd0; wdata = 32'd0;
    end
    always @(negedge clock) begin
        if (cycle != 64'd0) sum_rdata = sum_rdata * 32'd31 + rdata;
        if (cycle == 64'd{cycles}) begin
            $display("SUMS %0d %0d", sum_stim, sum_rdata);
            $finish;
        end else begin
            x = xorshift(x); r1 = x;
            x = xorshift(x); r2 = x;
            x = xorshift(x); r3 = x;
            jump = (cycle % 64'd4096) == 64'd4095;
            a16 = 16'd0; b16 = 16'd0; z16 = 16'd0;
            for (i = 0; i < {n}; i = i + 1) begin
                m = 2'((r1 >> ((2 * i) % 32)) & 32'd3);
                if (jump) phase[i] = phase[i] + 2'd2;
                else if (m == 2'd1) phase[i] = phase[i] + 2'd1;
                else if (m == 2'd2) phase[i] = phase[i] + 2'd3;
                a16[i] = phase[i] == 2'd1 || phase[i] == 2'd2;
                b16[i] = phase[i] == 2'd2 || phase[i] == 2'd3;
                z16[i] = phase[i] == 2'd0 && r1[31];
            end
            a = a16[{top}:0]; b = b16[{top}:0]; z = z16[{top}:0];
            reset = cycle < 64'd{reset_clocks};
            c = (r2 >> 16) % 32'd{n};
            ch = 32'd{ch_base} + 32'd{ch_stride} * c;
            we = 1'b0; re = 1'b0; addr = 8'd0; wdata = 32'd0;
            case (r2 & 32'd15)
                32'd0: begin addr = 8'd{snapshot}; wdata = r3; we = 1'b1; end
                32'd1, 32'd2, 32'd6: begin addr = 8'((r2 >> 8) % 32'd{span}); re = 1'b1; end
                32'd3: begin addr = 8'(ch + 32'd{ctrl}); wdata = r3; we = 1'b1; end
                32'd4: begin addr = 8'(ch + 32'd{cmd}); wdata = r3 & 32'd15; we = 1'b1; end
                32'd5: begin addr = 8'd{preset}; wdata = r3; we = 1'b1; end
                default: ;
            endcase
            home16 = ((r2 >> 4) & 32'd15) == 32'd0 ? 16'(r3 >> 16) & 16'd{home_mask} : 16'd0;
            home = home16[{top}:0];
            snapshot_strobe = ((r2 >> 12) & 32'd15) == 32'd0;
            sum_stim = sum_stim * 32'd31 + ({{16'd0, b16}} << 16 | {{16'd0, a16}});
            sum_stim = sum_stim * 32'd31 + ({{16'd0, z16}} | ({{24'd0, addr}} << 16) | ({{31'd0, we}} << 24) | ({{31'd0, re}} << 25) | ({{31'd0, reset}} << 26));
            sum_stim = sum_stim * 32'd31 + wdata;
            sum_stim = sum_stim * 32'd31 + {{16'd0, home16}};
            sum_stim = sum_stim * 32'd31 + {{31'd0, snapshot_strobe}};
            cycle = cycle + 64'd1;
        end
    end
endmodule
"#,
        dut = dut_instance(module),
        top = n - 1,
        seed = s.x,
        n = n,
        cycles = cycles,
        reset_clocks = RESET_CLOCKS,
        ch_base = s.ch_base,
        ch_stride = s.ch_stride,
        snapshot = s.snapshot,
        span = s.span,
        ctrl = s.ctrl,
        cmd = s.cmd,
        preset = s.preset,
        home_mask = (1u32 << n) - 1,
    );
    t
}

/// Runs the generated Verilog for `cycles` clocks and returns its checksums.
pub fn verilog_sums(
    sim: Simulator,
    module: &VerilogModule,
    source: &str,
    width: u32,
    seed: u32,
    cycles: u64,
) -> Result<Sums, String> {
    verilog_sums_timed(sim, module, source, width, seed, cycles).map(|(s, _)| s)
}

/// As [`verilog_sums`], also returning how long the simulation itself ran
/// (compilation excluded).
pub fn verilog_sums_timed(
    sim: Simulator,
    module: &VerilogModule,
    source: &str,
    width: u32,
    seed: u32,
    cycles: u64,
) -> Result<(Sums, std::time::Duration), String> {
    sim.available()?;
    let (v, elapsed) = run_for_sums(
        sim,
        &[
            ("tb.v", verilog_testbench(module, width, seed, cycles)),
            ("counter_bank.v", source.to_string()),
        ],
        "counter_bank_tb",
    )?;
    Ok((
        Sums {
            stimulus: v[0],
            rdata: v[1],
        },
        elapsed,
    ))
}
