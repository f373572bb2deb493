//! `FsmcTransactions` against docs/fsmc_bridge.md, "Accesses": what each
//! 16- and 32-bit access does to the slave and returns.

use super::*;

/// A register file whose words change at every read, with equal halves
/// (`k × 0x10001` for the k-th read), like the testbench's live registers:
/// a torn 32-bit read shows as unequal halves.
#[derive(Default)]
struct LiveSlave {
    reads: Vec<u16>,
}

impl FsmcSlave for LiveSlave {
    fn reg_read(&mut self, word: u16) -> u32 {
        self.reads.push(word);
        self.reads.len() as u32 * 0x1_0001
    }
    fn reg_write(&mut self, _: u16, _: u32) {}
    fn ram_read(&mut self, _: u16) -> u16 {
        0
    }
    fn ram_write(&mut self, _: u16, _: u16) {}
}

/// A slave with distinct halves in every register word.
fn patterned_slave() -> PlainSlave {
    let mut s = PlainSlave::new();
    for (w, r) in s.regs.iter_mut().enumerate() {
        *r = 0x8000_0000 | (w as u32) << 20 | 0x5a00 | w as u32 & 0xff;
    }
    for (w, r) in s.ram.iter_mut().enumerate() {
        *r = 0xc000 | w as u16;
    }
    s
}

#[test]
fn low_half_reads_the_register_once_and_returns_bits_15_0() {
    let mut s = patterned_slave();
    let mut t = FsmcTransactions::new();
    let v = s.regs[7];
    assert_eq!(t.read16(&mut s, 14), v as u16, "low half of word 7");
    assert_eq!(s.reads, [7]);
    // The kept high half serves the high half, no second read.
    assert_eq!(
        t.read16(&mut s, 15),
        (v >> 16) as u16,
        "high half of word 7"
    );
    assert_eq!(s.reads, [7]);
}

#[test]
fn thirty_two_bit_read_of_a_live_register_never_tears() {
    let mut s = LiveSlave::default();
    let mut t = FsmcTransactions::new();
    let first = t.read32(&mut s, 0x7e0);
    let second = t.read32(&mut s, 0x7e0);
    assert_eq!(first, 0x0001_0001, "one sample, equal halves");
    // Two 32-bit reads are two samples.
    assert_eq!(second, 0x0002_0002);
    assert_eq!(s.reads, [0x3f0, 0x3f0]);
}

/// Accesses made before the one under test.
type Accesses = fn(&mut FsmcTransactions, &mut LiveSlave);

#[test]
fn lone_high_half_reads_afresh() {
    // (accesses before the high half of word 5, fresh reads expected)
    let cases: [(&str, Accesses, usize); 6] = [
        ("nothing", |_, _| {}, 1),
        ("low half of another word", |t, s| _ = t.read16(s, 12), 2),
        ("whole 32-bit read of word 5", |t, s| _ = t.read32(s, 10), 2),
        (
            "RAM read after the low half",
            |t, s| {
                t.read16(s, 10);
                t.read16(s, 0x800);
            },
            2,
        ),
        (
            "register write after the low half",
            |t, s| {
                t.read16(s, 10);
                t.write16(s, 20, 1);
            },
            2,
        ),
        (
            "reset after the low half",
            |t, s| {
                t.read16(s, 10);
                t.reset();
            },
            2,
        ),
    ];
    for (what, before, reads) in cases {
        let mut s = LiveSlave::default();
        let mut t = FsmcTransactions::new();
        before(&mut t, &mut s);
        let hi = t.read16(&mut s, 11);
        assert_eq!(s.reads.len(), reads, "after {what}: {:?}", s.reads);
        assert_eq!(s.reads.last(), Some(&5), "after {what}");
        // The fresh sample's high half: the k-th read returns k in it.
        assert_eq!(hi, reads as u16, "after {what}");
    }
    assert_eq!(cases.len(), 6);
}

#[test]
fn a_byte_load_of_the_low_half_refreshes_the_kept_half() {
    // Two low-half reads of one word in a row: two register reads, and
    // the high half then comes from the second one.
    let mut s = LiveSlave::default();
    let mut t = FsmcTransactions::new();
    assert_eq!(t.read16(&mut s, 10), 1);
    assert_eq!(t.read16(&mut s, 10), 2);
    assert_eq!(t.read16(&mut s, 11), 2);
    assert_eq!(s.reads, [5, 5]);
}

#[test]
fn thirty_two_bit_write_is_one_register_write_of_both_halves() {
    let mut s = PlainSlave::new();
    let mut t = FsmcTransactions::new();
    t.write32(&mut s, 0x7fe, 0x1234_abcd);
    assert_eq!(s.regs[0x3ff], 0x1234_abcd);
    t.write32(&mut s, 2, 0xfedc_0123);
    assert_eq!(s.regs[1], 0xfedc_0123);
    let written: Vec<usize> = (0..s.regs.len()).filter(|&w| s.regs[w] != 0).collect();
    assert_eq!(written, [1, 0x3ff]);
    assert_eq!(t.read32(&mut s, 0x7fe), 0x1234_abcd);
    assert_eq!(t.read32(&mut s, 2), 0xfedc_0123);
}

#[test]
fn low_half_write_is_kept_and_the_high_half_writes_both() {
    let mut s = PlainSlave::new();
    let mut t = FsmcTransactions::new();
    // Power-up: a lone high-half write uses 0 as the low half.
    t.write16(&mut s, 9, 0x00a5);
    assert_eq!(s.regs[4], 0x00a5_0000);
    t.write16(&mut s, 6, 0xbeef);
    assert_eq!(s.regs[3], 0, "a low half alone writes nothing");
    // A RAM write and a reset in between do not touch the kept half.
    t.write16(&mut s, 0x805, 0x1111);
    t.reset();
    t.write16(&mut s, 13, 0xcafe);
    assert_eq!(s.regs[6], 0xcafe_beef, "a lone high half of another word");
    // The high half does not replace the kept low half.
    t.write16(&mut s, 15, 0x0001);
    assert_eq!(s.regs[7], 0x0001_beef);
}

#[test]
fn ram_window_is_one_word_per_access_and_a10_is_not_decoded() {
    let mut s = patterned_slave();
    let mut t = FsmcTransactions::new();
    // (halfword address, RAM word)
    let cases = [
        (0x800u16, 0u16),
        (0x801, 1),
        (0xbff, 0x3ff),
        (0xc00, 0),
        (0xe07, 0x207),
    ];
    for (a, word) in cases {
        assert_eq!(t.read16(&mut s, a), 0xc000 | word, "read at {a:#x}");
    }
    for (a, word) in cases {
        t.write16(&mut s, a, 0x1000 + a);
        assert_eq!(s.ram[usize::from(word)], 0x1000 + a, "write at {a:#x}");
    }
    assert_eq!(cases.len(), 5);
    assert!(s.reads.is_empty(), "no register read: {:?}", s.reads);
    t.write32(&mut s, 0x810, 0x7777_3333);
    assert_eq!(&s.ram[0x10..0x12], &[0x3333, 0x7777]);
    assert_eq!(t.read32(&mut s, 0x810), 0x7777_3333);
    assert!(
        s.regs.iter().all(|&r| r & 0x8000_0000 != 0),
        "registers untouched"
    );
}

#[test]
fn only_a11_to_a0_exist() {
    // Bits above A11 are not pins: an access there is the access at the
    // address's low 12 bits.
    let mut t = FsmcTransactions::new();
    let mut s = patterned_slave();
    let cases = [0x0006u16, 0x0007, 0x0805, 0x07ff];
    for a in cases {
        let expected = t.clone().read16(&mut s.clone(), a);
        assert_eq!(t.read16(&mut s, 0xf000 | a), expected, "read at {a:#x}");
        t.write16(&mut s, 0xa000 | a, 0x4321);
    }
    assert_eq!(cases.len(), 4);
    assert_eq!(s.ram[5], 0x4321);
    assert_eq!(s.regs[3], 0x4321_4321, "word 3: low kept, high written");
    assert_eq!(s.regs[0x3ff] >> 16, 0x4321);
}
