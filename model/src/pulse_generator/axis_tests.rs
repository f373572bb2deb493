//! The axis against docs/pulse_generator.md: the NCO, the queue and its
//! saturation, the clock-by-clock latency, the output timing and HALT.

use super::*;

fn timing(step_len: u32, step_space: u32, dir_setup: u32, dir_hold: u32) -> StepTiming {
    StepTiming {
        step_len,
        step_space,
        dir_setup,
        dir_hold,
    }
}

fn running(rate: i32, timing: StepTiming) -> PulseInputs {
    PulseInputs {
        enable: true,
        halt: false,
        rate,
        timing,
    }
}

fn stopped(timing: StepTiming) -> PulseInputs {
    PulseInputs {
        enable: false,
        ..running(0, timing)
    }
}

/// What the docs let one observe of the axis in one clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Seen {
    command: Request,
    pending: i32,
    step: bool,
    dir: bool,
    position: i32,
    busy: bool,
}

fn seen(g: &PulseGenerator) -> Seen {
    let (step, dir) = g.outputs();
    Seen {
        command: g.command,
        pending: g.timer.state().pending,
        step,
        dir,
        position: g.position as i32,
        busy: g.busy(),
    }
}

/// A carry in clock 0 is in the command register in clock 1, queued from
/// clock 2, on S1 from clock 3 and in `position` from clock 4; BUSY covers
/// clocks 1 to 3. Downwards S2 turns first (one clock of DIR_SETUP), which
/// shifts S1 and the position one clock later.
#[test]
fn a_carry_reaches_s1_and_position_on_the_documented_clocks() {
    let ones = timing(1, 1, 1, 1);
    for (rate, sign, s1_clock) in [(1, 1, 3), (-1, -1, 4)] {
        let mut g = PulseGenerator::new();
        // The phase one LSB short of a carry: rate ±1 carries in clock 0.
        g.phase = u32::MAX;
        let (request, blocked) = g.request(&running(rate, ones));
        let want = if sign > 0 { Request::Up } else { Request::Down };
        assert_eq!((request, blocked), (want, false), "rate {rate}");
        assert!(!g.busy(), "rate {rate}: the carry itself is not BUSY");
        g.clock(&running(rate, ones), false);
        let mut clocks = vec![seen(&g)];
        for _ in 0..8 {
            g.clock(&stopped(ones), false);
            clocks.push(seen(&g));
        }
        // clocks[n] is clock n + 1.
        assert_eq!(clocks[0].command, want, "rate {rate}: {clocks:?}");
        assert_eq!(clocks[0].pending, 0, "rate {rate}: {clocks:?}");
        assert_eq!(clocks[1].command, Request::None, "rate {rate}: {clocks:?}");
        assert_eq!(clocks[1].pending, sign, "rate {rate}: {clocks:?}");
        for (n, c) in clocks.iter().enumerate() {
            let clock = n + 1;
            let high = clock == s1_clock;
            let out = clock > s1_clock;
            assert_eq!(c.step, high, "rate {rate}, clock {clock}: {clocks:?}");
            assert_eq!(
                c.position,
                if out { sign } else { 0 },
                "rate {rate}, clock {clock}"
            );
            assert_eq!(
                c.pending,
                if out || clock == 1 { 0 } else { sign },
                "rate {rate}"
            );
            assert_eq!(c.busy, !out, "rate {rate}, clock {clock}: {clocks:?}");
            assert_eq!(c.dir, sign < 0 && clock >= 3, "rate {rate}, clock {clock}");
        }
    }
}

/// Over N clocks from phase 0 the NCO commands ⌊N·|rate| / 2^32⌋ steps
/// in the direction of rate's sign, and after the queue drains `position`
/// is that count.
#[test]
fn the_nco_commands_floor_of_clocks_times_rate() {
    let rates = [
        0,
        1 << 20,
        123_456_789,
        1 << 30,
        -(1 << 30),
        -77_777_777,
        i32::MAX,
        i32::MIN,
    ];
    let clocks: u64 = 5000;
    let mut cases = 0;
    for rate in rates {
        let mut g = PulseGenerator::new();
        let inp = running(rate, timing(1, 1, 1, 1));
        let mut commanded = 0i64;
        for _ in 0..clocks {
            commanded += match g.request(&inp).0 {
                Request::None => 0,
                Request::Up => 1,
                Request::Down => -1,
            };
            g.clock(&inp, false);
        }
        let magnitude = ((clocks * u64::from(rate.unsigned_abs())) >> 32) as i64;
        let want = if rate < 0 { -magnitude } else { magnitude };
        assert_eq!(commanded, want, "rate {rate}");
        assert_eq!(
            g.phase as u64,
            clocks * u64::from(rate.unsigned_abs()) % (1 << 32),
            "rate {rate}"
        );
        for _ in 0..20 {
            g.clock(&stopped(inp.timing), false);
        }
        assert_eq!(g.position as i32 as i64, want, "rate {rate}: all steps out");
        assert!(!g.busy(), "rate {rate}");
        cases += 1;
    }
    assert_eq!(cases, rates.len());
}

/// The queue is signed 16-bit: with S1 held high the NCO fills it, holds its
/// phase exactly while the queue is at ±32766 or ±32767 in its direction,
/// never drops a step, and every commanded step comes out once S1 is free.
#[test]
fn a_full_queue_holds_the_nco_and_drops_no_step() {
    for rate in [i32::MAX, i32::MIN] {
        let up = rate > 0;
        let mut g = PulseGenerator::new();
        // S1 high for 65 535 clocks: the queue fills before the 2nd step.
        let slow = running(rate, timing(u32::from(u16::MAX), 1, 1, 1));
        let mut commanded = 0i64;
        let (mut held, mut deepest) = (0, 0);
        for clock in 0..70_000 {
            let pending = g.timer.state().pending;
            let toward = if up { pending } else { -pending };
            deepest = deepest.max(toward);
            assert!(
                toward <= 32767,
                "rate {rate}, clock {clock}: pending {pending}"
            );
            let (request, blocked) = g.request(&slow);
            let phase = g.phase;
            commanded += match request {
                Request::None => 0,
                Request::Up => 1,
                Request::Down => -1,
            };
            g.clock(&slow, false);
            let hold = toward >= 32766;
            assert_eq!(
                blocked, hold,
                "rate {rate}, clock {clock}: pending {pending}"
            );
            assert_eq!(
                g.phase == phase,
                hold,
                "rate {rate}, clock {clock}: pending {pending}"
            );
            if hold {
                assert_eq!(request, Request::None, "rate {rate}, clock {clock}");
                held += 1;
            }
        }
        assert!(
            held > 1000 && deepest >= 32766,
            "rate {rate}: held {held}, deepest {deepest}"
        );
        let fast = stopped(timing(1, 1, 1, 1));
        let mut clocks = 0;
        while g.busy() {
            g.clock(&fast, false);
            clocks += 1;
            assert!(clocks < 70_000, "rate {rate}: the queue never drained");
        }
        assert_eq!(g.position as i32 as i64, commanded, "rate {rate}");
        assert!(
            commanded.abs() > 32766,
            "rate {rate}: {commanded} commanded"
        );
    }
}

/// Rate 0 commands nothing and counts as the up direction (its sign bit
/// is 0): it is held, so a ramp through it waits, only while the queue is
/// full of up steps, never while it is full of down steps.
#[test]
fn rate_zero_is_held_only_by_a_full_up_queue() {
    for rate in [i32::MAX, i32::MIN] {
        let mut g = PulseGenerator::new();
        let slow = running(rate, timing(u32::from(u16::MAX), 1, 1, 1));
        for _ in 0..70_000 {
            g.clock(&slow, false);
        }
        let pending = g.timer.state().pending;
        assert!(pending.abs() >= 32766, "rate {rate}: pending {pending}");
        let zero = running(0, slow.timing);
        assert_eq!(
            g.request(&zero),
            (Request::None, rate > 0),
            "rate 0 with pending {pending}"
        );
    }
}

/// The narrow instances of the exhaustive check and the gateware's: a
/// signed `pending_bits` queue refuses a request past ±(2^(bits−1) − 1) and
/// has no room for one decided a clock ahead within one step of it; the
/// timers saturate at 2^bits − 1.
#[test]
fn queue_and_timers_have_their_widths() {
    assert_eq!(
        StepTimer::new(PENDING_BITS, TIMER_BITS).pending_max(),
        32767
    );
    assert_eq!(StepTimer::new(PENDING_BITS, TIMER_BITS).timer_max(), 65535);
    assert_eq!(StepTimer::new(3, 3).pending_max(), 3);
    assert_eq!(StepTimer::new(3, 3).timer_max(), 7);
    // From reset the timers read as saturated: every timing is met.
    let fresh = StepTimer::new(PENDING_BITS, TIMER_BITS).state();
    assert_eq!((fresh.t_step, fresh.t_dir), (65535, 65535));
    // Fill a 3-bit queue up, then down, with S1 stuck high after its first
    // step, checking accepts/has_room at every level on the way.
    let stuck = timing(7, 1, 1, 1);
    let mut levels = Vec::new();
    for request in [Request::Up, Request::Down] {
        let mut t = StepTimer::new(3, 3);
        for _ in 0..8 {
            let p = t.state().pending;
            levels.push(p);
            assert_eq!(t.accepts(Request::Up), p < 3, "pending {p}");
            assert_eq!(t.accepts(Request::Down), p > -3, "pending {p}");
            assert_eq!(t.has_room(Request::Up), p <= 1, "pending {p}");
            assert_eq!(t.has_room(Request::Down), p >= -1, "pending {p}");
            assert!(t.accepts(Request::None) && t.has_room(Request::None));
            t.clock(
                if t.accepts(request) {
                    request
                } else {
                    Request::None
                },
                &stuck,
            );
        }
    }
    levels.sort();
    levels.dedup();
    // One step left the queue on S1, so both ends are reached.
    assert_eq!(levels, vec![-3, -2, -1, 0, 1, 2, 3]);
    // Idle, the timers saturate at their maximum.
    let mut t = StepTimer::new(3, 3);
    let mut g = PulseGenerator::new();
    for _ in 0..70_000 {
        t.clock(Request::None, &stuck);
        g.clock(&stopped(stuck), false);
    }
    let (s, w) = (t.state(), g.timer.state());
    assert_eq!((s.t_step, s.t_dir, w.t_step, w.t_dir), (7, 7, 65535, 65535));
}

/// A request past the queue's end is a caller error.
#[test]
#[should_panic(expected = "request Up with pending 3")]
fn a_request_into_a_full_queue_panics() {
    let mut t = StepTimer::new(3, 3);
    let stuck = timing(7, 1, 1, 1);
    for _ in 0..5 {
        t.clock(Request::Up, &stuck);
    }
}

/// Runs a step timer through `requests` (one a clock, None after them)
/// for `clocks` clocks; returns (S1, S2) in each clock and the steps that
/// left the queue.
fn waveform(
    requests: &[(usize, Request)],
    clocks: usize,
    timing_at: impl Fn(usize) -> StepTiming,
) -> (Vec<(bool, bool)>, i32, StepTimer) {
    let mut t = StepTimer::new(PENDING_BITS, TIMER_BITS);
    let mut wave = Vec::new();
    let mut left = 0;
    for clock in 0..clocks {
        let s = t.state();
        wave.push((s.step, s.dir));
        let request = requests
            .iter()
            .find(|(c, _)| *c == clock)
            .map_or(Request::None, |r| r.1);
        left += t.leaving();
        t.clock(request, &timing_at(clock));
    }
    (wave, left, t)
}

/// With steps queued, S1 is high exactly max(STEP_LEN, 1) clocks and low
/// exactly max(STEP_SPACE, 1) between steps; on a reversal S2 turns once S1
/// has been low max(DIR_HOLD, 1) clocks, and S1 rises once S2 has been
/// stable max(DIR_SETUP, 1) clocks and S1 low max(STEP_SPACE, 1) clocks.
#[test]
fn the_waveform_follows_every_timing_exactly() {
    use Request::{Down, Up};
    // One step up (queued from clock 1, so S1 high from clock 2), four down
    // commanded behind it, then two up again long after.
    let requests = [
        (0, Up),
        (1, Down),
        (2, Down),
        (3, Down),
        (4, Down),
        (60, Up),
        (61, Up),
    ];
    let mut cases = 0;
    for code in 0..5usize.pow(4) {
        let [l, s, su, h] = [0, 1, 2, 3].map(|d| (code / 5usize.pow(d) % 5) as u32);
        let t = timing(l, s, su, h);
        let [l1, s1, su1, h1] = [l, s, su, h].map(|v| v.max(1) as usize);
        let mut want = vec![(false, false); 100];
        let mut pulse = |from: usize| {
            for w in &mut want[from..from + l1] {
                w.0 = true;
            }
        };
        pulse(2);
        let turn = 2 + l1 + h1;
        let first_down = (2 + l1 + s1).max(turn + su1);
        for j in 0..4 {
            pulse(first_down + j * (l1 + s1));
        }
        // Back up: the queue is empty long before, so only DIR_SETUP waits.
        let turn_back = 62;
        for j in 0..2 {
            pulse(turn_back + su1 + j * (l1 + s1));
        }
        for (clock, w) in want.iter_mut().enumerate() {
            w.1 = (turn..turn_back).contains(&clock);
        }
        let (wave, left, timer) = waveform(&requests, 100, |_| t);
        assert_eq!(wave, want, "timing {t:?}");
        assert_eq!(
            (left, timer.state().pending),
            (1 - 4 + 2, 0),
            "timing {t:?}"
        );
        cases += 1;
    }
    assert_eq!(cases, 625);
}

/// A new timing acts one clock after it reaches the block: switching one
/// field from 10 to 1 in the (j+1)-th clock of the wait it governs ends
/// that wait after j + 2 clocks, where it would end after 1 from the start.
#[test]
fn a_new_timing_acts_one_clock_late() {
    use Request::{Down, Up};
    let two_up = [(0, Up), (1, Up)];
    let reversal = [(0, Up), (1, Down), (2, Down), (3, Down), (4, Down)];
    type Level = fn((bool, bool)) -> bool;
    let run_length = |wave: &[(bool, bool)], from: usize, pick: Level| {
        let level = pick(wave[from]);
        wave[from..]
            .iter()
            .take_while(|&&w| pick(w) == level)
            .count()
    };
    // The waits: S1 high, S1 low, S1 low before S2 turns, S2 turned
    // before S1 rises (S1 high or S2 high ends them).
    let s1 = |w: (bool, bool)| w.0;
    let s1_or_s2 = |w: (bool, bool)| w.0 || w.1;
    let mut cases = 0;
    for field in 0..4 {
        // The wait's first clock with every time 1: S1 high from clock 2 and
        // low from 3; S2 turned (set up) from clock 4.
        let (requests, start, pick): (&[_], usize, Level) = match field {
            0 => (&two_up, 2, s1),
            1 => (&two_up, 3, s1),
            2 => (&reversal, 3, s1_or_s2),
            _ => (&reversal, 4, s1),
        };
        let with = |v: u32| {
            let mut t = timing(1, 1, 1, 1);
            *[
                &mut t.step_len,
                &mut t.step_space,
                &mut t.dir_hold,
                &mut t.dir_setup,
            ][field] = v;
            t
        };
        for switch in [None, Some(0), Some(1), Some(2), Some(3), Some(4), Some(5)] {
            let (wave, _, _) = waveform(requests, 40, |clock| match switch {
                Some(j) if clock < start + j => with(10),
                _ => with(1),
            });
            let got = run_length(&wave, start, pick);
            let want = switch.map_or(1, |j| j + 2);
            assert_eq!(
                got, want,
                "field {field}, switch at wait clock {switch:?}: {wave:?}"
            );
            cases += 1;
        }
    }
    assert_eq!(cases, 28);
}

/// HALT: the NCO commands nothing and holds its phase, the queue and the
/// command register are dropped at the edge, S1 starts no step; a step
/// already high still lasts STEP_LEN, and a step that rose at the last edge
/// still enters `position`.
#[test]
fn halt_drops_the_queue_and_lets_the_high_step_finish() {
    let t = timing(5, 1, 1, 1);
    let fast = running(i32::MAX, t);
    let mut g = PulseGenerator::new();
    let mut rises = 0;
    // Run until S1 has just risen with more steps queued.
    for clock in 0.. {
        assert!(clock < 100, "no third step: {g:?}");
        let before = g.outputs().0;
        g.clock(&fast, false);
        rises += i32::from(!before && g.outputs().0);
        if rises == 3 && !before && g.outputs().0 {
            break;
        }
    }
    assert!(g.timer.state().pending >= 2, "{g:?}");
    let halt = PulseInputs { halt: true, ..fast };
    // Where the phase would carry, HALT commands nothing.
    let mut carrying = g;
    carrying.phase = u32::MAX;
    assert_eq!(carrying.request(&fast), (Request::Up, false));
    assert_eq!(carrying.request(&halt), (Request::None, false));
    let phase = g.phase;
    let mut high = 1;
    for clock in 0..30 {
        g.clock(&halt, false);
        assert_eq!(g.phase, phase, "clock {clock}");
        assert_eq!(
            (g.timer.state().pending, g.command),
            (0, Request::None),
            "clock {clock}"
        );
        high += i32::from(g.outputs().0);
        assert_eq!(g.position as i32, rises, "clock {clock}: {g:?}");
    }
    assert_eq!(high, 5, "the halted step keeps STEP_LEN");
    assert!(!g.busy());
    // Released, the NCO runs on from where it held.
    g.clock(&fast, false);
    assert_eq!(g.phase, phase.wrapping_add(i32::MAX as u32));
}

/// HALT at the edge where S2 would turn, or S1 would rise: neither does.
#[test]
fn halt_neither_turns_s2_nor_starts_a_step() {
    let ones = timing(1, 1, 1, 1);
    let mut cases = 0;
    for request in [Request::Down, Request::Up] {
        let mut t = StepTimer::new(PENDING_BITS, TIMER_BITS);
        t.clock(request, &ones);
        // Queued in clock 1: Down would turn S2, Up would raise S1.
        assert_eq!(t.emits(), i32::from(request == Request::Up), "{request:?}");
        let before = t.state();
        t.clock_flushing(Request::None, &ones, true);
        let s = t.state();
        assert_eq!(
            (s.pending, s.step, s.dir),
            (0, false, before.dir),
            "{request:?}"
        );
        for _ in 0..5 {
            t.clock(Request::None, &ones);
            assert!(
                !t.state().step && t.state().dir == before.dir,
                "{request:?}"
            );
        }
        cases += 1;
    }
    assert_eq!(cases, 2);
}

/// Without `enable` the NCO holds and commands nothing, while the steps
/// already commanded still go out.
#[test]
fn without_enable_queued_steps_still_go_out() {
    let t = timing(3, 3, 1, 1);
    let mut g = PulseGenerator::new();
    let mut commanded = 0;
    for _ in 0..40 {
        commanded += i32::from(g.request(&running(i32::MIN, t)).0 == Request::Down);
        g.clock(&running(i32::MIN, t), false);
    }
    assert!(g.timer.state().pending < -5, "{g:?}");
    let off = PulseInputs {
        enable: false,
        ..running(i32::MIN, t)
    };
    let phase = g.phase;
    for clock in 0..200 {
        assert_eq!(g.request(&off), (Request::None, false), "clock {clock}");
        g.clock(&off, false);
        assert_eq!(g.phase, phase, "clock {clock}");
    }
    assert_eq!((g.position as i32, g.busy()), (-commanded, false));
}

/// Reset returns the axis, and a step timer, to their power-up state.
#[test]
fn reset_returns_to_power_up() {
    let mut g = PulseGenerator::default();
    let inp = running(-(1 << 29), timing(2, 2, 2, 2));
    for _ in 0..100 {
        g.clock(&inp, false);
    }
    assert_ne!(g, PulseGenerator::new());
    g.clock(&inp, true);
    assert_eq!(g, PulseGenerator::new());
    let mut t = g.timer;
    let fresh = t;
    t.clock(Request::Down, &inp.timing);
    t.clock(Request::Down, &inp.timing);
    assert_ne!(t, fresh);
    let saved = t.state();
    t.reset();
    assert_eq!(t, fresh);
    t.set_state(saved);
    assert_eq!(t.state(), saved);
}

/// `emits` is the step S1 starts at an edge, with its direction: -1 down,
/// +1 up, once per queued step.
#[test]
fn emits_gives_the_direction_of_the_step_it_starts() {
    let ones = timing(1, 1, 1, 1);
    let mut cases = 0;
    for (request, sign) in [(Request::Down, -1), (Request::Up, 1)] {
        let mut t = StepTimer::new(PENDING_BITS, TIMER_BITS);
        t.clock(request, &ones);
        let mut emitted = Vec::new();
        for _ in 0..10 {
            if t.emits() != 0 {
                emitted.push(t.emits());
            }
            t.clock(Request::None, &ones);
        }
        assert_eq!(emitted, vec![sign], "{request:?}");
        cases += 1;
    }
    assert_eq!(cases, 2);
}
