use super::*;

/// The strobe rises; then, after each of `n` edges: (counter, prefetch).
fn after_rise(host: &mut Host<IsaBridgeModel>, n: u32) -> Vec<(u16, u16)> {
    host.rise();
    (0..n)
        .map(|_| {
            host.edge();
            (host.dut.counter(), host.prefetch())
        })
        .collect()
}

#[test]
fn an_access_acts_three_edges_after_its_rise_and_the_prefetch_follows_at_five() {
    for write in [Some(0xffff), None] {
        let mut host = internal();
        host.dsp_write(1, 0x1111);
        host.edges(2);
        host.command(p(reg::ADDR_INC), false, write);
        if write.is_none() {
            // A read of ADDR_INC returns STATUS before the increment.
            assert_eq!(host.dut.bus(&host.pins), (0, true, false));
        }
        let seen = after_rise(&mut host, 6);
        let want = [(0, 0), (0, 0), (1, 0), (1, 0), (1, 0x1111), (1, 0x1111)];
        assert_eq!(seen, want, "ADDR_INC, write {write:?}");
    }
}

#[test]
fn a_data_write_is_queued_at_the_third_edge_and_lands_in_the_next_free_clock() {
    let mut host = internal();
    host.write(reg::STATUS, 5);
    host.command(p(reg::DATA), false, Some(0xbeef));
    host.rise();
    let mut seen = vec![];
    for _ in 0..7 {
        host.edge();
        let m = &host.dut;
        seen.push((
            m.core().queued_write(),
            m.write_pending(),
            m.ram()[5],
            host.prefetch(),
        ));
    }
    let queued = (Some((5, 0xbeef)), true, 0, 0);
    let landed = (None, false, 0xbeef, 0);
    let shown = (None, false, 0xbeef, 0xbeef);
    let idle = (None, false, 0, 0);
    assert_eq!(seen, [idle, idle, queued, landed, landed, shown, shown]);
}

#[test]
fn write_data_is_the_last_sd_sample_taken_while_iow_was_low() {
    // (SD at each edge of the command, the word written): the first sample
    // may still be settling; garbage after the rise must not count.
    let cases: [(&[u16], u16); 3] = [
        (&[0xdddd, 0x1234, 0x1234], 0x1234),
        (&[0xdddd, 1, 2, 2, 3, 0x0bad], 0x0bad),
        (&[0xffff, 0x8001], 0x8001),
    ];
    let mut covered = 0;
    for (samples, want) in cases {
        covered += 1;
        let mut host = internal();
        host.pins.sa = p(reg::DATA);
        host.pins.bale = true;
        host.edges(3);
        host.pins.bale = false;
        host.pins.iow_n = false;
        for &sd in samples {
            host.pins.sd_in = sd;
            host.edge();
        }
        host.rise();
        host.pins.sd_in = 0xeeee;
        host.edges(GAP);
        assert_eq!(host.dut.ram()[0], want, "SD samples {samples:x?}");
    }
    assert_eq!(covered, 3);
}

#[test]
fn read_data_holds_under_ior_from_the_second_edge_after_it_falls() {
    let mut host = internal();
    host.write(reg::STATUS, 7);
    host.pins.sa = p(reg::DATA);
    host.pins.bale = true;
    host.edges(2);
    assert_eq!(host.dut.bus(&host.pins), (0, false, false), "before IOR#");
    // The DSP rewrites word 7 at every edge: 0x700 at the edge before IOR#
    // falls, which reaches SD 2 edges later, then the freeze.
    host.pins.bale = false;
    host.dsp_write(7, 0x6ff);
    host.dsp_write(7, 0x700);
    host.pins.ior_n = false;
    let mut shown = vec![];
    for i in 1..=8 {
        host.dsp_write(7, 0x700 + i);
        shown.push(host.dut.bus(&host.pins));
    }
    assert!(
        shown.iter().all(|&(_, oe, _)| oe),
        "sd_oe under IOR#: {shown:x?}"
    );
    assert!(
        shown[1..].iter().all(|&(sd, _, _)| sd == 0x700),
        "{shown:x?}"
    );
    host.rise();
    host.edges(GAP);
    assert_eq!(host.prefetch(), 0x708, "the prefetch follows the RAM again");
}

#[test]
fn the_dsp_rings_the_pc_at_its_edge_and_only_a_data_read_or_a_bell_write_answers() {
    let mut host = internal();
    let bell = |h: &Host<IsaBridgeModel>| (h.dut.status() & status::BELL != 0, h.dut.irq());
    host.write(reg::STATUS, status::IRQ_EN | mailbox::TO_PC);
    host.dsp_write(mailbox::TO_PC - 1, 1);
    assert_eq!(bell(&host), (false, false), "another word does not ring");
    host.dsp_write(mailbox::TO_PC, 0x1234);
    assert_eq!(bell(&host), (true, true), "BELL and irq at the DSP's edge");
    // STATUS loads without bit 15, DATA writes (even of all ones, and of
    // the mailbox word itself) leave it ringing.
    host.write(reg::STATUS, status::IRQ_EN | mailbox::TO_PC);
    assert_eq!(bell(&host), (true, true), "STATUS load without BELL");
    host.write(reg::STATUS, status::IRQ_EN | 0x100);
    host.write(reg::DATA, 0xffff);
    host.write(reg::STATUS, status::IRQ_EN | mailbox::TO_PC);
    host.write(reg::DATA, 0x0042);
    host.edges(4);
    assert_eq!(bell(&host), (true, true), "after PC DATA writes");
    assert_eq!(host.dut.ram()[usize::from(mailbox::TO_PC)], 0x0042);
    // The PC's DATA read of the word answers 3 edges after IOR# rises.
    host.command(p(reg::DATA), false, None);
    assert_eq!(host.dut.bus(&host.pins).0, 0x0042);
    host.rise();
    let mut seen = vec![];
    for _ in 0..4 {
        host.edge();
        seen.push(bell(&host));
    }
    assert_eq!(
        seen,
        [(true, true), (true, true), (false, false), (false, false)]
    );
    // A DSP ring at that same edge wins.
    host.dsp_write(mailbox::TO_PC, 0x1235);
    host.command(p(reg::DATA), false, None);
    host.rise();
    host.edges(2);
    host.dsp_write(mailbox::TO_PC, 0x1236);
    host.edges(GAP);
    assert_eq!(bell(&host), (true, true), "a ring at the answering edge");
    // IRQ_EN gates the line, not BELL; a 1 in bit 15 answers.
    host.write(reg::STATUS, mailbox::TO_PC);
    assert_eq!(bell(&host), (true, false), "IRQ_EN off");
    host.write(reg::STATUS, status::BELL | status::IRQ_EN);
    assert_eq!(bell(&host), (false, false), "BELL written with 1");
    assert_eq!(host.dut.status(), status::IRQ_EN);
}

#[test]
fn the_pc_rings_the_dsp_in_the_clock_before_its_mailbox_write_lands() {
    let to_dsp = usize::from(mailbox::TO_DSP);
    let mut host = internal();
    host.write(reg::STATUS, (mailbox::TO_DSP - 1) | status::AUTO_INC);
    host.write(reg::DATA, 0x1111);
    assert_eq!(host.bells, 0, "a write of another word does not ring");
    host.command(p(reg::DATA), false, Some(0x4242));
    host.rise();
    host.edges(3);
    // Queued now; the DSP takes the write port in the next clock, so the
    // PC's write (and the pulse) waits one clock.
    host.pins.dsp_addr = 5;
    host.pins.dsp_wdata = 0x5555;
    host.pins.dsp_we = true;
    assert!(!host.dut.outputs(&host.pins).bell_to_dsp, "DSP writing");
    host.edge();
    assert_eq!((host.dut.ram()[to_dsp], host.dut.ram()[5]), (0, 0x5555));
    assert!(
        host.dut.outputs(&host.pins).bell_to_dsp,
        "the landing clock"
    );
    host.edge();
    assert_eq!(host.dut.ram()[to_dsp], 0x4242);
    host.edges(GAP);
    assert_eq!(host.bells, 1, "one clock of bell_to_dsp");
    assert_eq!(host.dut.status() & status::COLLISION, 0);
}

#[test]
fn same_clock_writes_to_one_word_leave_the_pc_value_and_set_collision() {
    let mut host = internal();
    let collision = |h: &Host<IsaBridgeModel>| h.dut.status() & status::COLLISION != 0;
    host.write(reg::STATUS, 9);
    // A DSP write while no PC write waits is no collision.
    host.dsp_write(9, 0x0999);
    assert!(!collision(&host));
    // The DSP writes the PC's word in the clock the PC's write would land.
    let pc = status::COLLISION | 0x0aaa;
    host.command(p(reg::DATA), false, Some(pc));
    host.rise();
    host.edges(3);
    host.dsp_write(9, 0x1111);
    assert_eq!(host.dut.ram()[9], 0x1111, "the DSP's write first");
    host.edge();
    assert_eq!(host.dut.ram()[9], pc, "then the PC's");
    host.edges(GAP);
    assert!(collision(&host));
    // Sticky: DATA writes, STATUS reads and loads without bit 14 keep it.
    host.write(reg::DATA, 0xffff);
    host.read(reg::STATUS);
    host.write(reg::STATUS, status::WRAPPED | status::BELL | 9);
    assert!(collision(&host), "still set");
    host.write(reg::STATUS, status::COLLISION | 9);
    assert!(!collision(&host), "a 1 in bit 14 clears it");
    // The DSP writing a different word: the PC's lands a clock later.
    host.command(p(reg::DATA), false, Some(0x2222));
    host.rise();
    host.edges(3);
    host.dsp_write(10, 0x3333);
    assert_eq!((host.dut.ram()[9], host.dut.ram()[10]), (0xffff, 0x3333));
    host.edge();
    assert_eq!(host.dut.ram()[9], 0x2222);
    assert!(!collision(&host), "different words do not collide");
}

#[test]
fn the_dsp_port_reads_the_word_at_the_previous_edge_address() {
    let mut host = internal();
    for (addr, data) in [(0, 0xa0a0), (0x155, 0x1551), (0x3ff, 0xfff3)] {
        host.dsp_write(addr, data);
    }
    // Reading and writing one word at one edge returns the old word.
    host.dsp_write(0x155, 0x2662);
    assert_eq!(host.dut.outputs(&probe()).dsp_rdata, 0x1551);
    let mut got = vec![];
    for addr in [0x3ff, 0, 0x155, 0x200] {
        host.pins.dsp_addr = addr;
        host.edge();
        got.push(host.dut.outputs(&probe()).dsp_rdata);
    }
    assert_eq!(got, [0xfff3, 0xa0a0, 0x2662, 0]);
}

#[test]
fn wrapped_is_sticky_until_addr_clear_or_a_one_in_bit_13() {
    let mut host = internal();
    let wrapped = |h: &Host<IsaBridgeModel>| h.dut.status() & status::WRAPPED != 0;
    host.write(reg::STATUS, 0x3ff);
    host.read(reg::STATUS);
    assert!(!wrapped(&host), "loading 1023 is no wrap");
    host.write(reg::ADDR_INC, 0);
    assert_eq!((host.dut.counter(), wrapped(&host)), (0, true));
    host.write(reg::DATA, 0xffff);
    host.read(reg::STATUS);
    host.read(reg::DATA);
    host.write(reg::STATUS, status::COLLISION | status::BELL | 4);
    assert!(wrapped(&host), "still set after other accesses");
    host.write(reg::STATUS, status::WRAPPED | 4);
    assert_eq!(host.dut.status(), 4, "a 1 in bit 13 clears it");
    host.write(reg::STATUS, 0x3ff | status::AUTO_INC);
    host.read(reg::DATA);
    assert_eq!(host.dut.status(), status::WRAPPED | status::AUTO_INC);
    assert_eq!(
        host.read(reg::ADDR_CLEAR),
        status::WRAPPED | status::AUTO_INC
    );
    assert_eq!(host.dut.status(), status::AUTO_INC, "ADDR_CLEAR clears it");
}
