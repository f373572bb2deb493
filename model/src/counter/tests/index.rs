//! Index events: latch, clear, one-shot, gate, inversion, priorities.

use super::*;

#[test]
fn index_latch_records_the_count_one_clock_after_the_event() {
    let ctrl = ctrl_field("IDX_LATCH", 1);
    let mut ch = Channel::new(CounterParams::new(28, 8));
    ch.set_state(ChannelState {
        ctrl,
        count: 5,
        up_q: true,
        fz: InputFilter {
            level: true,
            s1: true,
            s2: true,
            cnt: 0,
        },
        zg_q: true,
        ..Default::default()
    });
    let z_high = ChannelInputs {
        z: true,
        ..Default::default()
    };
    ch.clock(&z_high);
    assert_eq!(ch.state().count, 6);
    assert!(ch.state().seen);
    assert!(ch.state().index_latch_q, "the action is registered");
    assert_eq!(ch.state().index, 0, "and lands one edge later");
    ch.clock(&z_high);
    assert_eq!(ch.state().index, 6);
    // Level, not edge: no second event while Z stays high.
    ch.set_state(ChannelState {
        count: 9,
        ..*ch.state()
    });
    ch.clock(&z_high);
    ch.clock(&z_high);
    assert_eq!(ch.state().index, 6);

    // Through the pins: index pulse at count 4.
    let mut r = Rig::new(28, ctrl);
    r.walk(&FWD);
    r.z(true);
    r.z(false);
    r.walk(&FWD[..2]);
    assert_eq!(r.count(), 6);
    assert_eq!(r.ch.state().index, 4);
}

#[test]
fn index_clear_zeroes_count_after_the_latch_took_it() {
    let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_CLEAR", 1);
    let mut ch = Channel::new(CounterParams::new(28, 8));
    ch.set_state(ChannelState {
        ctrl,
        count: 5,
        down_q: true,
        fz: InputFilter {
            level: true,
            ..Default::default()
        },
        zg_q: true,
        ..Default::default()
    });
    ch.clock(&ChannelInputs::default());
    assert_eq!(ch.state().count, 4, "the event edge still steps");
    ch.clock(&ChannelInputs::default());
    assert_eq!(ch.state().count, 0);
    assert_eq!(ch.state().index, 4);

    let mut r = Rig::new(28, ctrl_field("IDX_CLEAR", 1));
    r.walk(&cycles(&FWD, 2));
    assert_eq!(r.count(), 8);
    r.z(true);
    assert_eq!(r.count(), 0);
    r.walk(&FWD[..1]);
    assert_eq!(r.count(), 1);
    assert!(r.ch.state().seen);
    r.cmd("CLEAR_STATUS");
    assert!(!r.ch.state().seen);
}

#[test]
fn one_shot_index_acts_once_per_arm() {
    let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_ONESHOT", 1);
    let mut r = Rig::new(28, ctrl);
    r.walk(&FWD);
    r.z(true);
    r.z(false);
    assert_eq!(r.ch.state().index, 0, "not armed: no latch");
    assert!(r.ch.state().seen, "SEEN records every event");
    r.cmd("ARM");
    assert!(r.ch.state().armed);
    assert_eq!(status_field("ARMED", r.ch.status()), 1);
    r.walk(&FWD);
    r.z(true);
    assert_eq!(r.ch.state().index, 8);
    assert!(!r.ch.state().armed, "the first event disarms");
    r.z(false);
    r.walk(&FWD);
    r.z(true);
    assert_eq!(r.ch.state().index, 8, "disarmed: no second latch");
}

#[test]
fn arm_wins_over_disarm_in_the_same_clock() {
    let ctrl = ctrl_field("IDX_ONESHOT", 1) | ctrl_field("IDX_LATCH", 1);
    let mut ch = Channel::new(CounterParams::new(28, 8));
    ch.set_state(ChannelState {
        ctrl,
        count: 3,
        armed: true,
        fz: InputFilter {
            level: true,
            ..Default::default()
        },
        zg_q: true,
        ..Default::default()
    });
    ch.clock(&ChannelInputs {
        cmd_write: Some(cmd_bit("ARM")),
        ..Default::default()
    });
    assert!(ch.state().armed);
    ch.clock(&ChannelInputs::default());
    assert_eq!(ch.state().index, 3);
}

#[test]
fn index_gate_needs_a_and_b_high() {
    let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_GATE", 1);
    let mut r = Rig::new(28, ctrl);
    r.walk(&FWD[..1]); // (1,0), count 1
    r.z(true);
    assert!(!r.ch.state().seen, "gated off at (1,0)");
    // (1,1): the gate opens with Z high. The event is detected one
    // clock after the levels open the gate (`zg_q`), when the step into
    // (1,1) has reached the count, so the latch holds it.
    r.walk(&FWD[1..2]);
    assert!(r.ch.state().seen);
    assert_eq!(r.count(), 2);
    assert_eq!(r.ch.state().index, 2);
    r.walk(&FWD[2..]); // gate closes, count 4
    r.walk(&FWD); // reopens at (1,1), count 6
    assert_eq!(
        r.ch.state().index,
        6,
        "reopening with Z still high is a new event"
    );
}

#[test]
fn index_invert_acts_on_falling_z() {
    let ctrl = ctrl_field("IDX_LATCH", 1) | ctrl_field("IDX_INVERT", 1);
    // Z idles high (active low): reset with Z high so no event at start.
    let mut r = Rig::at(28, 8, ctrl, (false, false, true));
    assert!(!r.ch.state().seen);
    r.walk(&FWD[..3]);
    r.z(false);
    assert!(r.ch.state().seen);
    assert_eq!(r.ch.state().index, 3);
    assert_eq!(
        status_field("Z", r.ch.status()),
        0,
        "STATUS.Z is before inversion"
    );
    r.z(true);
    r.walk(&FWD[3..]);
    assert_eq!(r.ch.state().index, 3);
}

#[test]
fn command_and_index_priorities() {
    let base = ChannelState {
        count: 5,
        up_q: true,
        ..Default::default()
    };
    let run = |state: ChannelState, cmds: &[u32]| {
        let mut ch = Channel::new(CounterParams::new(28, 8));
        ch.set_state(state);
        let mut counts = Vec::new();
        for &cmd in cmds {
            ch.clock(&ChannelInputs {
                cmd_write: Some(cmd),
                preset: 0x1234,
                ..Default::default()
            });
            counts.push(ch.state().count);
        }
        counts
    };
    let (clear, load) = (cmd_bit("CLEAR"), cmd_bit("LOAD"));
    assert_eq!(run(base, &[0]), [6]);
    assert_eq!(run(base, &[cmd_bit("ARM")]), [6], "other CMD bits count on");
    assert_eq!(run(base, &[clear]), [0]);
    assert_eq!(
        run(base, &[load, 0, 0]),
        [0, 0x1234, 0x1234],
        "LOAD clears, then adds PRESET in place of the step"
    );
    assert_eq!(run(base, &[clear | load, 0]), [0, 0], "CLEAR beats LOAD");
    assert_eq!(
        run(base, &[load, clear]),
        [0, 0],
        "CLEAR beats a pending LOAD"
    );
    assert_eq!(
        run(base, &[load, load, 0]),
        [0, 0, 0x1234],
        "LOAD again restarts"
    );
    let index_clear = ChannelState {
        index_clear_q: true,
        ..base
    };
    assert_eq!(run(index_clear, &[0]), [0], "index clear beats the step");
    assert_eq!(
        run(
            ChannelState {
                load_q: true,
                count: 0,
                ..index_clear
            },
            &[0]
        ),
        [0],
        "index clear beats the load's second edge"
    );
}

/// STATUS packs every field at once: ERR, ARMED, SEEN and the three pin
/// levels all set, and ERR_COUNT, read in one word.
#[test]
fn status_holds_every_field_together() {
    let ctrl = ctrl_field("MODE", regmap::mode::X4)
        | ctrl_field("ERR_EN", 1)
        | ctrl_field("IDX_ONESHOT", 1);
    let mut r = Rig::at(28, 8, ctrl, (false, false, false));
    r.walk(&[(true, true)]);
    r.z(true);
    r.cmd("ARM");
    assert!(r.ch.state().armed, "Z stayed high: no new event");
    let s = r.ch.status();
    for (name, want) in [
        ("ERR", 1),
        ("ARMED", 1),
        ("SEEN", 1),
        ("A", 1),
        ("B", 1),
        ("Z", 1),
        ("ERR_COUNT", 1),
    ] {
        assert_eq!(status_field(name, s), want, "{name} in {s:#x}");
    }
}

/// A build without the index logic has no INDEX register.
#[test]
#[should_panic(expected = "channel has no register INDEX")]
fn index_is_not_a_register_without_the_index_logic() {
    let features = CounterFeatures::from_bits(0);
    assert!(!features.index);
    let ch = Channel::new(CounterParams::new(28, 8).with_features(features));
    ch.read("INDEX");
}
