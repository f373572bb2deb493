use super::*;

#[test]
fn card_reset_restores_power_up_registers_and_keeps_the_ram() {
    let mut covered = 0;
    for (mut card, sees_dsp) in [
        (IsaCard::new(BASE), true),
        (IsaCard::with_external_ram(BASE), false),
    ] {
        covered += 1;
        let flags = status::AUTO_INC | status::IRQ_EN;
        card.io_write(p(reg::STATUS), false, 0x3ff | flags);
        card.io_write(p(reg::DATA), false, 0x77);
        card.dsp_write(mailbox::TO_PC, 1);
        let bell = if sees_dsp { status::BELL } else { 0 };
        let before = flags | status::WRAPPED | bell;
        assert_eq!(card.status(), before, "sees DSP {sees_dsp}");
        assert_eq!(card.irq(), sees_dsp);
        card.reset();
        assert_eq!((card.status(), card.address(), card.irq()), (0, 0, false));
        assert_eq!(card.ram()[0x3ff], 0x77, "the RAM is kept");
        assert_eq!(card.dsp_read(mailbox::TO_PC), 1);
        // Which RAM the card was built for survives the reset.
        card.dsp_write(mailbox::TO_PC, 2);
        assert_eq!(card.status(), bell, "sees DSP {sees_dsp}");
    }
    assert_eq!(covered, 2);
}

#[test]
fn the_sram_port_idles_reading_with_we_inactive_from_power_up() {
    let m = IsaBridgeExternalModel::new();
    let idle = SramPins {
        addr: 0,
        d_out: 0,
        d_oe: false,
        ce_n: false,
        oe_n: false,
        we_n: true,
    };
    assert_eq!(m.sram(), idle);
    assert!(!m.irq() && !m.bell_to_dsp() && !m.takes_sample());
}

#[test]
fn an_external_data_write_is_setup_two_we_clocks_and_hold_and_reads_back_at_eleven() {
    let mut host = Host::new(Sram::new());
    host.write(reg::STATUS, 0x123);
    host.dsp_write(0x123, 0x0111);
    host.edges(GAP);
    assert_eq!(host.prefetch(), 0x0111);
    host.command(p(reg::DATA), false, Some(0x5a5a));
    host.rise();
    let (mut pins, mut shown) = (vec![], vec![]);
    for _ in 0..12 {
        host.edge();
        pins.push(host.dut.m.sram());
        shown.push(host.prefetch());
    }
    let start = pins.iter().position(|s| !reading(s));
    let start = start.unwrap_or_else(|| panic!("no write in {pins:x?}"));
    let setup = SramPins {
        addr: 0x123,
        d_out: 0x5a5a,
        d_oe: true,
        ce_n: false,
        oe_n: true,
        we_n: true,
    };
    let pulse = SramPins {
        we_n: false,
        ..setup
    };
    assert_eq!(
        pins[start..start + 4],
        [setup, pulse, pulse, setup],
        "{pins:x?}"
    );
    let after = pins[start + 4];
    assert!(
        reading(&after) && !after.d_oe && after.addr == 0x123,
        "{after:x?}"
    );
    assert_eq!(host.dut.mem[0x123], 0x5a5a);
    // The new word reaches SD 11 edges after IOW# rose, not before.
    assert!(shown[..10].iter().all(|&w| w == 0x0111), "{shown:x?}");
    assert!(shown[10..].iter().all(|&w| w == 0x5a5a), "{shown:x?}");
}

#[test]
fn the_external_build_rings_the_dsp_once_the_mailbox_word_is_in_the_sram() {
    let to_dsp = usize::from(mailbox::TO_DSP);
    let mut host = Host::new(Sram::new());
    host.write(reg::STATUS, mailbox::TO_DSP);
    host.command(p(reg::DATA), false, Some(0x0707));
    host.rise();
    let mut rang = vec![];
    for edge in 1..=GAP {
        if host.dut.bell_to_dsp(&host.pins) {
            rang.push((edge, host.dut.mem[to_dsp]));
        }
        host.edge();
    }
    assert_eq!(rang.len(), 1, "bell clocks {rang:?}");
    assert_eq!(rang[0].1, 0x0707, "the word is in the SRAM at the bell");
    // The DSP's writes are out of sight: no BELL, no irq, no COLLISION.
    host.write(reg::STATUS, status::IRQ_EN | mailbox::TO_PC);
    host.dsp_write(mailbox::TO_PC, 5);
    host.edges(3);
    assert_eq!(host.dut.status(), status::IRQ_EN | mailbox::TO_PC);
    assert!(!host.dut.irq());
    assert_eq!(host.read(reg::DATA), 5);
    host.write(reg::DATA, 6);
    assert_eq!(host.bells, 1, "a write of another word does not ring");
}
