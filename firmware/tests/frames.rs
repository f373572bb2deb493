//! "Virtual memory" frames of the dual-CPU card (seed 000, tables 1 and 2).

use motionhdl_firmware::frames::{
    crc16_modbus, decode_reply, decode_request, encode_reply, encode_request, reply_vec,
    request_vec, serve, FrameError, Function, Header, MAX_FRAME, MAX_READ_WORDS, MAX_WRITE_WORDS,
};
use proptest::prelude::*;

fn read(slave: u8, start: u16, quantity: u16) -> Header {
    Header {
        slave,
        function: Function::Read,
        start,
        quantity,
    }
}

fn write(slave: u8, start: u16, quantity: u16) -> Header {
    Header {
        function: Function::Write,
        ..read(slave, start, quantity)
    }
}

#[test]
fn crc_check_value() {
    // The catalogued check value of CRC-16/MODBUS.
    assert_eq!(crc16_modbus(b"123456789"), 0x4B37);
    assert_eq!(crc16_modbus(b""), 0xFFFF);
}

#[test]
fn read_requests_match_published_modbus_frames() {
    // Modbus over serial line, read holding registers 108..110 of slave 17;
    // and the usual "read 10 registers of slave 1" example. The CRC goes low
    // byte first.
    let cases: [(Header, &[u8]); 2] = [
        (
            read(0x11, 0x006B, 3),
            &[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87],
        ),
        (
            read(0x01, 0x0000, 10),
            &[0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD],
        ),
    ];
    for (h, wire) in cases {
        assert_eq!(request_vec(&h, &[]).unwrap(), wire);
        assert_eq!(decode_request(wire, h.slave).unwrap().0, h);
    }
}

#[test]
fn frame_layouts() {
    // Write request: address, 0x10, start (BE), quantity (BE), words (BE),
    // CRC (LE).
    let f = request_vec(&write(5, 0x0102, 2), &[0xA1B2, 0xC3D4]).unwrap();
    assert_eq!(
        &f[..10],
        &[5, 0x10, 0x01, 0x02, 0x00, 0x02, 0xA1, 0xB2, 0xC3, 0xD4]
    );
    assert_eq!(f.len(), 12);
    assert_eq!(u16::from_le_bytes([f[10], f[11]]), crc16_modbus(&f[..10]));
    // Read reply: address, 0x03, start, words, CRC (table 2).
    let f = reply_vec(&read(5, 0x0102, 2), &[0xA1B2, 0xC3D4]).unwrap();
    assert_eq!(&f[..8], &[5, 0x03, 0x01, 0x02, 0xA1, 0xB2, 0xC3, 0xD4]);
    assert_eq!(f.len(), 10);
    // Write reply: the reply data is the quantity written.
    let f = reply_vec(&write(5, 0x0102, 2), &[]).unwrap();
    assert_eq!(&f[..6], &[5, 0x10, 0x01, 0x02, 0x00, 0x02]);
    assert_eq!(f.len(), 8);
    // The largest frames fit the limit.
    assert_eq!(write(1, 0, MAX_WRITE_WORDS).request_len(), MAX_FRAME - 2);
    assert_eq!(read(1, 0, MAX_READ_WORDS).reply_len(), MAX_FRAME);
}

fn header() -> impl Strategy<Value = Header> {
    (
        any::<u8>(),
        any::<bool>(),
        any::<u16>(),
        1u16..=MAX_WRITE_WORDS,
    )
        .prop_map(|(slave, w, start, quantity)| {
            if w {
                write(slave, start, quantity)
            } else {
                read(slave, start, quantity)
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn requests_and_replies_round_trip(h in header(), words in prop::collection::vec(any::<u16>(), MAX_WRITE_WORDS as usize)) {
        let data = &words[..usize::from(h.quantity)];
        let (req_data, reply_data): (&[u16], &[u16]) = match h.function {
            Function::Read => (&[], data),
            Function::Write => (data, &[]),
        };
        let req = request_vec(&h, req_data).unwrap();
        prop_assert_eq!(req.len(), h.request_len());
        let (got, w) = decode_request(&req, h.slave).unwrap();
        prop_assert_eq!(got, h);
        prop_assert_eq!(w.iter().collect::<Vec<_>>(), req_data);
        let rep = reply_vec(&h, reply_data).unwrap();
        prop_assert_eq!(rep.len(), h.reply_len());
        let w = decode_reply(&rep, &h).unwrap();
        prop_assert_eq!(w.len(), reply_data.len());
        prop_assert_eq!(w.is_empty(), reply_data.is_empty());
        prop_assert_eq!(w.iter().collect::<Vec<_>>(), reply_data);
        // Random access agrees with the iterator, and ends where it ends.
        for i in 0..=reply_data.len() {
            prop_assert_eq!(w.get(i), reply_data.get(i).copied());
        }
    }
}

/// Flips every bit of `frame` in turn; every flip must be rejected.
/// Returns (bits flipped, flips reported as a bad CRC).
fn flip_every_bit(
    frame: &[u8],
    decode: impl Fn(&[u8]) -> Result<(), FrameError>,
) -> (usize, usize) {
    let (mut bits, mut crc) = (0, 0);
    let mut f = frame.to_vec();
    for i in 0..frame.len() * 8 {
        f[i / 8] ^= 1 << (i % 8);
        match decode(&f) {
            Ok(()) => panic!("bit {i} flipped, frame accepted: {f:02x?}"),
            Err(FrameError::BadCrc { .. }) => crc += 1,
            Err(_) => {}
        }
        f[i / 8] ^= 1 << (i % 8);
        bits += 1;
    }
    assert_eq!(decode(&f), Ok(()), "the unflipped frame");
    (bits, crc)
}

#[test]
fn every_single_bit_error_is_detected() {
    let data: Vec<u16> = (0..7).map(|i| 0x1234u16.wrapping_mul(i + 1)).collect();
    let (rh, wh) = (read(9, 0x0040, 7), write(9, 0x0040, 7));
    let frames = [
        (request_vec(&rh, &[]).unwrap(), true, rh),
        (request_vec(&wh, &data).unwrap(), true, wh),
        (reply_vec(&rh, &data).unwrap(), false, rh),
        (reply_vec(&wh, &[]).unwrap(), false, wh),
    ];
    let (mut total, mut expected_bits) = (0, 0);
    for (frame, is_request, h) in &frames {
        let (bits, crc) = if *is_request {
            flip_every_bit(frame, |f| decode_request(f, 9).map(|_| ()))
        } else {
            flip_every_bit(frame, |f| decode_reply(f, h).map(|_| ()))
        };
        assert_eq!(bits, frame.len() * 8);
        // Flips in the address, start, data and CRC bytes leave the length
        // alone and must be caught by the CRC itself.
        let length_bytes = if *is_request { 3 } else { 1 }; // function (+ quantity)
        assert!(
            crc >= (frame.len() - length_bytes) * 8,
            "{crc} of {bits} by CRC"
        );
        total += bits;
        expected_bits += frame.len() * 8;
    }
    // 8 + 22 + 20 + 8 bytes.
    assert_eq!(total, expected_bits);
    assert_eq!(total, (8 + 22 + 20 + 8) * 8);
}

#[test]
fn decoding_errors_say_what_is_wrong() {
    let h = write(3, 0x0010, 2);
    let f = request_vec(&h, &[1, 2]).unwrap();
    // Truncated: the quantity says 8 + 2·2 bytes.
    assert_eq!(
        decode_request(&f[..9], 3),
        Err(FrameError::Truncated { needed: 12, got: 9 })
    );
    assert_eq!(
        decode_request(&f[..1], 3),
        Err(FrameError::Truncated { needed: 8, got: 1 })
    );
    let mut long = f.clone();
    long.push(0);
    assert_eq!(
        decode_request(&long, 3),
        Err(FrameError::TrailingBytes {
            needed: 12,
            got: 13
        })
    );
    // Bad CRC: expected is the CRC of the bytes, received what came.
    let mut bad = f.clone();
    bad[11] ^= 0x80;
    let expected = crc16_modbus(&f[..10]);
    let received = expected ^ 0x8000;
    let e = decode_request(&bad, 3).unwrap_err();
    assert_eq!(e, FrameError::BadCrc { expected, received });
    assert_eq!(
        e.to_string(),
        format!("bad CRC: expected {expected:#06x}, received {received:#06x}")
    );
    // Another slave's frame.
    assert_eq!(
        decode_request(&f, 4),
        Err(FrameError::WrongAddress {
            expected: 4,
            got: 3
        })
    );
    assert_eq!(
        FrameError::WrongAddress {
            expected: 4,
            got: 3
        }
        .to_string(),
        "wrong slave address: expected 4, got 3"
    );
    // Unknown function (with a valid CRC, so only the code is wrong).
    let mut unknown = vec![3, 0x06, 0, 0x10, 0, 1];
    let c = crc16_modbus(&unknown);
    unknown.extend(c.to_le_bytes());
    assert_eq!(
        decode_request(&unknown, 3),
        Err(FrameError::UnknownFunction(0x06))
    );
    // A reply that does not answer the request.
    let rh = read(3, 0x0010, 2);
    let other_start = reply_vec(&read(3, 0x0011, 2), &[1, 2]).unwrap();
    assert_eq!(
        decode_reply(&other_start, &rh),
        Err(FrameError::UnexpectedStart {
            expected: 0x10,
            got: 0x11
        })
    );
    let other_function = reply_vec(&write(3, 0x0010, 1), &[]).unwrap();
    // A read reply of 2 words is 10 bytes; a write reply is 8.
    assert_eq!(
        decode_reply(&other_function, &rh),
        Err(FrameError::Truncated { needed: 10, got: 8 })
    );
    let w1 = write(3, 0x0010, 3);
    assert_eq!(
        decode_reply(&other_function, &w1),
        Err(FrameError::UnexpectedQuantity {
            expected: 3,
            got: 1
        })
    );
    let ack_as_read = reply_vec(&write(3, 0x0010, 1), &[]).unwrap();
    assert_eq!(
        decode_reply(&ack_as_read, &read(3, 0x0010, 1)),
        Err(FrameError::UnexpectedFunction {
            expected: 0x03,
            got: 0x10
        })
    );
    assert_eq!(
        decode_reply(&ack_as_read, &write(2, 0x0010, 1)),
        Err(FrameError::WrongAddress {
            expected: 2,
            got: 3
        })
    );
}

#[test]
fn short_frames_are_judged_by_what_they_hold() {
    // Two bytes: enough for the function code, so an unknown one is named.
    assert_eq!(
        decode_request(&[1, 0x99], 1),
        Err(FrameError::UnknownFunction(0x99))
    );
    // A known function shorter than a header.
    assert_eq!(
        decode_request(&[1, 0x03, 0], 1),
        Err(FrameError::Truncated { needed: 8, got: 3 })
    );
    // A whole header: the quantity it gives sizes the frame wanted.
    assert_eq!(
        decode_request(&[1, 0x10, 0, 0, 0, 3], 1),
        Err(FrameError::Truncated { needed: 14, got: 6 })
    );
}

#[test]
fn a_read_may_end_at_the_last_word_of_memory() {
    let mut memory = [7u16; 64];
    let mut reply = [0u8; MAX_FRAME];
    let h = read(7, 62, 2);
    let n = serve(&mut memory, 7, &request_vec(&h, &[]).unwrap(), &mut reply).unwrap();
    let words = decode_reply(&reply[..n], &h).unwrap();
    assert_eq!(words.iter().collect::<Vec<_>>(), [7, 7]);
    // One word: not empty, and only index 0 holds it.
    let h = read(7, 63, 1);
    let n = serve(&mut memory, 7, &request_vec(&h, &[]).unwrap(), &mut reply).unwrap();
    let words = decode_reply(&reply[..n], &h).unwrap();
    assert!(!words.is_empty());
    assert_eq!((words.get(0), words.get(1)), (Some(7), None));
}

#[test]
fn encoding_errors() {
    let mut buf = [0u8; 16];
    assert_eq!(
        encode_request(&mut buf, &read(1, 0, 0), &[]),
        Err(FrameError::BadQuantity {
            quantity: 0,
            max: MAX_READ_WORDS
        })
    );
    assert_eq!(
        encode_request(&mut buf, &write(1, 0, MAX_WRITE_WORDS + 1), &[]),
        Err(FrameError::BadQuantity {
            quantity: MAX_WRITE_WORDS + 1,
            max: MAX_WRITE_WORDS
        })
    );
    assert_eq!(
        encode_request(&mut buf, &write(1, 0, 3), &[1, 2]),
        Err(FrameError::DataLength { needed: 3, got: 2 })
    );
    assert_eq!(
        encode_reply(&mut buf, &read(1, 0, 7), &[0; 7]),
        Err(FrameError::BufferTooSmall {
            needed: 20,
            got: 16
        })
    );
    assert_eq!(encode_reply(&mut buf, &read(1, 0, 5), &[0; 5]), Ok(16));
}

#[test]
fn the_master_writes_and_reads_the_slave_virtual_memory() {
    let mut memory = [0u16; 64];
    let mut reply = [0u8; MAX_FRAME];
    // Write 3 words at 10.
    let h = write(7, 10, 3);
    let req = request_vec(&h, &[100, 200, 300]).unwrap();
    let n = serve(&mut memory, 7, &req, &mut reply).unwrap();
    assert!(decode_reply(&reply[..n], &h).unwrap().is_empty());
    assert_eq!(&memory[9..14], &[0, 100, 200, 300, 0]);
    // Read 4 words back from 9.
    let h = read(7, 9, 4);
    let n = serve(&mut memory, 7, &request_vec(&h, &[]).unwrap(), &mut reply).unwrap();
    let words = decode_reply(&reply[..n], &h).unwrap();
    assert_eq!(words.iter().collect::<Vec<_>>(), [0, 100, 200, 300]);
    assert_eq!((words.get(1), words.get(4)), (Some(100), None));
    // Past the end of memory.
    let h = read(7, 62, 3);
    assert_eq!(
        serve(&mut memory, 7, &request_vec(&h, &[]).unwrap(), &mut reply),
        Err(FrameError::OutOfRange {
            start: 62,
            quantity: 3,
            size: 64
        })
    );
    // Another slave's request is not served.
    assert_eq!(
        serve(&mut memory, 8, &req, &mut reply),
        Err(FrameError::WrongAddress {
            expected: 8,
            got: 7
        })
    );
}
