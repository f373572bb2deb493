//! The servo DAC block's scenario trace, from the rust-hdl block checked
//! against its model on the way: a servo loop of a few ticks, new codes
//! staged between them, and a safe episode.

use crate::checks::servo_dac::{model_outputs, run_rust, word_address, Vector, CLOCK_HZ};
use crate::trace::Trace;
use motionhdl_model::counter::BusCycle;
use motionhdl_model::regmap;
use motionhdl_model::servo_dac::SAFE_CODE;

/// Clocks between ticks in the scenario: the reset timing's transfer of
/// 23 clocks and some room.
const PERIOD: u32 = 40;

/// The scenario's inputs: TICK_PERIOD written after reset; each period new
/// codes for the four channels, staged at different clocks; `safe` high
/// from the fifth period's third clock to the sixth's twentieth.
fn vectors() -> Vec<Vector> {
    let map = regmap::servo_dac(CLOCK_HZ);
    let ch = map.array("CH");
    let mut v = vec![
        Vector {
            reset: true,
            ..Default::default()
        };
        2
    ];
    v.push(Vector {
        bus: BusCycle::write(map.register("TICK_PERIOD").offset, PERIOD),
        ..Default::default()
    });
    let period = PERIOD as usize;
    for k in 0..7 * period {
        let (n, at) = (k / period, k % period);
        let bus = match at {
            5 | 12 | 19 | 26 => {
                let c = (at - 5) / 7;
                let code = 0x8000u32.wrapping_add(((n as u32 + 1) * 0x0900) * (c as u32 + 1));
                BusCycle::write(ch.address(c as u32, "CODE"), code & 0xffff)
            }
            _ => BusCycle::default(),
        };
        v.push(Vector {
            bus,
            safe: (n == 4 && at >= 3) || (n == 5 && at < 20),
            ..Default::default()
        });
    }
    v
}

/// `motionhdl trace servo_dac`: the block's bus, tick and DAC pins, and a
/// DAC7744 on those pins (input registers latched at CS's rise, outputs at
/// LOADDACS's rise). Panics if the block and its model disagree.
pub fn trace() -> Trace {
    let vectors = vectors();
    let observed = run_rust(&vectors);
    let want = model_outputs(&vectors);
    for (k, (o, w)) in observed.iter().zip(&want).enumerate() {
        assert_eq!(o.outputs, *w, "servo_dac trace: clock {k}");
    }
    let mut t = Trace::new(format!(
        "{} | scenario servo_dac | clock {CLOCK_HZ} Hz | tick every {PERIOD} clocks",
        motionhdl_hdl::banner_ascii()
    ));
    let top = ["servo_dac"];
    let pins = ["servo_dac", "dac_pins"];
    let dac = ["servo_dac", "dac7744"];
    let clock = t.signal(&top, "clock", 1);
    let ids = [
        t.signal(&top, "reset", 1),
        t.signal(&top, "addr", 4),
        t.signal(&top, "wdata", 32),
        t.signal(&top, "we", 1),
        t.signal(&top, "safe", 1),
        t.signal(&top, "tick", 1),
        t.signal(&pins, "data", 16),
        t.signal(&pins, "a1_a0", 2),
        t.signal(&pins, "cs_n", 1),
        t.signal(&pins, "rw_n", 1),
        t.signal(&pins, "ldac_n", 1),
    ];
    let outs = ["vout_a", "vout_b", "vout_c", "vout_d"].map(|n| t.signal(&dac, n, 16));
    let half_ns = 500_000_000 / CLOCK_HZ;
    let (mut input_regs, mut vout) = ([SAFE_CODE; 4], [SAFE_CODE; 4]);
    let mut before = observed[0].outputs.pins;
    for (k, o) in observed.iter().enumerate() {
        let time = 2 * half_ns * k as u64;
        let (v, p) = (o.vector, o.outputs.pins);
        if !before.cs_n && p.cs_n {
            input_regs[before.addr as usize] = before.data;
        }
        if !before.ldac_n && p.ldac_n {
            vout = input_regs;
        }
        before = p;
        let values = [
            u64::from(v.reset),
            u64::from(word_address(v.bus.addr)),
            u64::from(v.bus.wdata),
            u64::from(v.bus.we),
            u64::from(v.safe),
            u64::from(o.outputs.tick),
            u64::from(p.data),
            u64::from(p.addr),
            u64::from(p.cs_n),
            u64::from(p.rw_n),
            u64::from(p.ldac_n),
        ];
        for (id, value) in ids.iter().zip(values) {
            t.set(time, *id, value);
        }
        for (id, value) in outs.iter().zip(vout) {
            t.set(time, *id, u64::from(value));
        }
        t.set(time, clock, 1);
        t.set(time + half_ns, clock, 0);
        // The safe input rose at clock 166: a running transfer ends at
        // 186, the safe one at 209 (within 2 x 23 clocks of the rise).
        if k == 3 + 5 * PERIOD as usize + 15 {
            assert_eq!(vout, [SAFE_CODE; 4], "servo_dac trace: safe at clock {k}");
        }
    }
    assert_ne!(vout, [SAFE_CODE; 4], "servo_dac trace: codes after safe");
    let tick = t.mark_edge("servo_dac.tick", 1, 0, "first tick");
    t.mark_edge(
        "servo_dac.dac_pins.ldac_n",
        1,
        tick,
        "LOADDACS: outputs update",
    );
    let safe = t.mark_edge("servo_dac.safe", 1, 0, "safe rises");
    t.mark_edge("servo_dac.safe", 0, safe, "safe falls");
    t
}
