//! The frames the dual-CPU STM32 card's two CPUs exchange over RS-232 to
//! share "virtual memory" (seed 000, section 2, tables 1 and 2): the master
//! requests, the slave replies.
//!
//! ```text
//! master (table 1): slave address | function | start address | quantity | CRC
//! slave  (table 2): slave address | function | start address | reply data | CRC
//! ```
//!
//! Layout (Modbus RTU-like; the seed gives the fields, not their widths):
//!
//! * slave address: 1 byte; function: 1 byte;
//! * start address and quantity: 16-bit, big-endian; addresses and
//!   quantities count 16-bit words of virtual memory;
//! * data: 16-bit words, big-endian;
//! * CRC: CRC-16/MODBUS (reflected poly 0xA001, init 0xFFFF) over every
//!   byte before it, low byte first.
//!
//! Function codes ([`Function`]): 0x03 reads words, 0x10 writes them
//! (Modbus's "read holding registers" and "write multiple registers"). A
//! write request carries its words after the quantity (table 1 has no data
//! field; a write needs one). The replies:
//!
//! | frame | bytes |
//! |---|---|
//! | read request | addr, 0x03, start, quantity, CRC (8) |
//! | read reply | addr, 0x03, start, quantity words, CRC (6 + 2q) |
//! | write request | addr, 0x10, start, quantity, quantity words, CRC (8 + 2q) |
//! | write reply | addr, 0x10, start, quantity, CRC (8): the reply data is the quantity written |
//!
//! A frame is delimited by line silence, as in Modbus RTU, so decoders take
//! one whole frame. The master checks a reply against the request it sent.

use core::fmt;

/// Most words one read moves (Modbus's limit: frames stay within 256 bytes).
pub const MAX_READ_WORDS: u16 = 125;
/// Most words one write moves.
pub const MAX_WRITE_WORDS: u16 = 123;
/// Longest frame: a write request of [`MAX_WRITE_WORDS`] or a read reply of
/// [`MAX_READ_WORDS`].
pub const MAX_FRAME: usize = 256;

/// CRC-16/MODBUS lookup table, built at compile time.
const CRC_TABLE: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = i as u16;
        let mut b = 0;
        while b < 8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xA001
            } else {
                c >> 1
            };
            b += 1;
        }
        t[i] = c;
        i += 1;
    }
    t
};

/// CRC-16/MODBUS of `bytes` (poly 0x8005 reflected = 0xA001, init 0xFFFF,
/// no final xor). It goes on the wire low byte first.
pub fn crc16_modbus(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0xFFFF, |crc, &b| {
        (crc >> 8) ^ CRC_TABLE[usize::from((crc ^ u16::from(b)) as u8)]
    })
}

/// Function codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Function {
    /// Read words of the slave's virtual memory.
    Read = 0x03,
    /// Write words of the slave's virtual memory.
    Write = 0x10,
}

impl Function {
    pub fn code(self) -> u8 {
        self as u8
    }

    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0x03 => Some(Self::Read),
            0x10 => Some(Self::Write),
            _ => None,
        }
    }

    /// Most words per frame.
    pub fn max_words(self) -> u16 {
        match self {
            Self::Read => MAX_READ_WORDS,
            Self::Write => MAX_WRITE_WORDS,
        }
    }
}

/// The fields of table 1: what the master asks of which slave.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Header {
    pub slave: u8,
    pub function: Function,
    /// First word address.
    pub start: u16,
    /// Word count: 1..=`function.max_words()`.
    pub quantity: u16,
}

impl Header {
    /// Bytes of the request frame.
    pub fn request_len(&self) -> usize {
        match self.function {
            Function::Read => 8,
            Function::Write => 8 + 2 * usize::from(self.quantity),
        }
    }

    /// Bytes of the reply frame.
    pub fn reply_len(&self) -> usize {
        match self.function {
            Function::Read => 6 + 2 * usize::from(self.quantity),
            Function::Write => 8,
        }
    }

    fn check_quantity(&self) -> Result<(), FrameError> {
        let max = self.function.max_words();
        if (1..=max).contains(&self.quantity) {
            Ok(())
        } else {
            Err(FrameError::BadQuantity {
                quantity: self.quantity,
                max,
            })
        }
    }
}

/// Why a frame cannot be encoded or is rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameError {
    /// The CRC in the frame is not the CRC of its bytes.
    BadCrc {
        expected: u16,
        received: u16,
    },
    /// The frame is shorter than its header says.
    Truncated {
        needed: usize,
        got: usize,
    },
    /// The frame is longer than its header says.
    TrailingBytes {
        needed: usize,
        got: usize,
    },
    /// A frame for (or from) another slave.
    WrongAddress {
        expected: u8,
        got: u8,
    },
    UnknownFunction(u8),
    /// A reply whose function is not the request's.
    UnexpectedFunction {
        expected: u8,
        got: u8,
    },
    /// A reply whose start address is not the request's.
    UnexpectedStart {
        expected: u16,
        got: u16,
    },
    /// A write reply whose quantity is not the request's.
    UnexpectedQuantity {
        expected: u16,
        got: u16,
    },
    /// Quantity 0 or above the function's maximum.
    BadQuantity {
        quantity: u16,
        max: u16,
    },
    /// Encoding: `data` has `got` words, the frame needs `needed`.
    DataLength {
        needed: usize,
        got: usize,
    },
    /// Encoding: the buffer holds `got` bytes, the frame needs `needed`.
    BufferTooSmall {
        needed: usize,
        got: usize,
    },
    /// Serving: words start..start+quantity are not all in a memory of
    /// `size` words.
    OutOfRange {
        start: u16,
        quantity: u16,
        size: usize,
    },
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::BadCrc { expected, received } => {
                write!(
                    f,
                    "bad CRC: expected {expected:#06x}, received {received:#06x}"
                )
            }
            Self::Truncated { needed, got } => {
                write!(f, "truncated frame: needs {needed} bytes, got {got}")
            }
            Self::TrailingBytes { needed, got } => {
                write!(f, "frame of {got} bytes, its header says {needed}")
            }
            Self::WrongAddress { expected, got } => {
                write!(f, "wrong slave address: expected {expected}, got {got}")
            }
            Self::UnknownFunction(c) => write!(f, "unknown function code {c:#04x}"),
            Self::UnexpectedFunction { expected, got } => {
                write!(f, "reply function {got:#04x} to a request {expected:#04x}")
            }
            Self::UnexpectedStart { expected, got } => {
                write!(
                    f,
                    "reply start address {got:#06x}, requested {expected:#06x}"
                )
            }
            Self::UnexpectedQuantity { expected, got } => {
                write!(f, "reply quantity {got}, requested {expected}")
            }
            Self::BadQuantity { quantity, max } => {
                write!(f, "quantity {quantity} out of range 1..={max}")
            }
            Self::DataLength { needed, got } => {
                write!(f, "{got} data words, the frame needs {needed}")
            }
            Self::BufferTooSmall { needed, got } => {
                write!(f, "buffer of {got} bytes, the frame needs {needed}")
            }
            Self::OutOfRange {
                start,
                quantity,
                size,
            } => write!(
                f,
                "words {start}..{} outside a memory of {size} words",
                u32::from(start) + u32::from(quantity)
            ),
        }
    }
}

impl core::error::Error for FrameError {}

/// Big-endian 16-bit words inside a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Words<'a>(&'a [u8]);

impl<'a> Words<'a> {
    pub fn len(&self) -> usize {
        self.0.len() / 2
    }

    pub fn is_empty(&self) -> bool {
        self.0.len() < 2
    }

    pub fn get(&self, i: usize) -> Option<u16> {
        let b = self.0.get(2 * i..2 * i + 2)?;
        Some(u16::from_be_bytes([b[0], b[1]]))
    }

    pub fn iter(&self) -> impl Iterator<Item = u16> + 'a {
        self.0
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
    }
}

/// Writes header, `words` and CRC into `buf`; returns the length.
fn put(buf: &mut [u8], head: &[u8], words: &[u16]) -> Result<usize, FrameError> {
    let len = head.len() + 2 * words.len() + 2;
    if buf.len() < len {
        return Err(FrameError::BufferTooSmall {
            needed: len,
            got: buf.len(),
        });
    }
    buf[..head.len()].copy_from_slice(head);
    for (i, w) in words.iter().enumerate() {
        buf[head.len() + 2 * i..][..2].copy_from_slice(&w.to_be_bytes());
    }
    let crc = crc16_modbus(&buf[..len - 2]);
    buf[len - 2..len].copy_from_slice(&crc.to_le_bytes());
    Ok(len)
}

fn check_data(needed: usize, data: &[u16]) -> Result<(), FrameError> {
    if data.len() == needed {
        Ok(())
    } else {
        Err(FrameError::DataLength {
            needed,
            got: data.len(),
        })
    }
}

/// Encodes the master's request; `data` is the words to write (empty for a
/// read). Returns the frame length.
pub fn encode_request(buf: &mut [u8], h: &Header, data: &[u16]) -> Result<usize, FrameError> {
    h.check_quantity()?;
    let [s0, s1] = h.start.to_be_bytes();
    let [q0, q1] = h.quantity.to_be_bytes();
    let head = [h.slave, h.function.code(), s0, s1, q0, q1];
    match h.function {
        Function::Read => {
            check_data(0, data)?;
            put(buf, &head, &[])
        }
        Function::Write => {
            check_data(h.quantity.into(), data)?;
            put(buf, &head, data)
        }
    }
}

/// Encodes the slave's reply to request `h`; `data` is the words read (empty
/// for a write, whose reply echoes the quantity).
pub fn encode_reply(buf: &mut [u8], h: &Header, data: &[u16]) -> Result<usize, FrameError> {
    h.check_quantity()?;
    let [s0, s1] = h.start.to_be_bytes();
    match h.function {
        Function::Read => {
            check_data(h.quantity.into(), data)?;
            put(buf, &[h.slave, h.function.code(), s0, s1], data)
        }
        Function::Write => {
            check_data(0, data)?;
            put(buf, &[h.slave, h.function.code(), s0, s1], &[h.quantity])
        }
    }
}

/// [`encode_request`] into a new `Vec`.
#[cfg(feature = "alloc")]
pub fn request_vec(h: &Header, data: &[u16]) -> Result<alloc::vec::Vec<u8>, FrameError> {
    let mut v = alloc::vec![0; h.request_len()];
    let n = encode_request(&mut v, h, data)?;
    v.truncate(n);
    Ok(v)
}

/// [`encode_reply`] into a new `Vec`.
#[cfg(feature = "alloc")]
pub fn reply_vec(h: &Header, data: &[u16]) -> Result<alloc::vec::Vec<u8>, FrameError> {
    let mut v = alloc::vec![0; h.reply_len()];
    let n = encode_reply(&mut v, h, data)?;
    v.truncate(n);
    Ok(v)
}

fn be16(frame: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([frame[at], frame[at + 1]])
}

/// Length, then CRC, checks of a frame of `needed` bytes.
fn check_frame(frame: &[u8], needed: usize) -> Result<(), FrameError> {
    if frame.len() < needed {
        return Err(FrameError::Truncated {
            needed,
            got: frame.len(),
        });
    }
    if frame.len() > needed {
        return Err(FrameError::TrailingBytes {
            needed,
            got: frame.len(),
        });
    }
    let expected = crc16_modbus(&frame[..needed - 2]);
    let received = u16::from_le_bytes([frame[needed - 2], frame[needed - 1]]);
    if expected != received {
        return Err(FrameError::BadCrc { expected, received });
    }
    Ok(())
}

fn function_of(frame: &[u8], min: usize) -> Result<Function, FrameError> {
    if frame.len() < 2 {
        return Err(FrameError::Truncated {
            needed: min,
            got: frame.len(),
        });
    }
    Function::from_code(frame[1]).ok_or(FrameError::UnknownFunction(frame[1]))
}

fn check_address(expected: u8, got: u8) -> Result<(), FrameError> {
    if expected == got {
        Ok(())
    } else {
        Err(FrameError::WrongAddress { expected, got })
    }
}

/// Decodes a request on the slave `slave`: the header, and the words to
/// write (empty for a read). Checks, in order: length (the function and
/// quantity fix it), CRC, address, quantity range.
pub fn decode_request(frame: &[u8], slave: u8) -> Result<(Header, Words<'_>), FrameError> {
    let function = function_of(frame, 8)?;
    if frame.len() < 6 {
        return Err(FrameError::Truncated {
            needed: 8,
            got: frame.len(),
        });
    }
    let h = Header {
        slave: frame[0],
        function,
        start: be16(frame, 2),
        quantity: be16(frame, 4),
    };
    // Bound the quantity before it sizes the frame.
    h.check_quantity()?;
    check_frame(frame, h.request_len())?;
    check_address(slave, h.slave)?;
    let words = match function {
        Function::Read => Words(&[]),
        Function::Write => Words(&frame[6..frame.len() - 2]),
    };
    Ok((h, words))
}

/// Decodes, on the master, the reply to request `sent`: the words read
/// (empty for a write). Checks length, CRC, address, function, start and (for
/// a write) the quantity.
pub fn decode_reply<'a>(frame: &'a [u8], sent: &Header) -> Result<Words<'a>, FrameError> {
    let function = function_of(frame, sent.reply_len())?;
    check_frame(frame, sent.reply_len())?;
    check_address(sent.slave, frame[0])?;
    if function != sent.function {
        return Err(FrameError::UnexpectedFunction {
            expected: sent.function.code(),
            got: function.code(),
        });
    }
    let start = be16(frame, 2);
    if start != sent.start {
        return Err(FrameError::UnexpectedStart {
            expected: sent.start,
            got: start,
        });
    }
    match function {
        Function::Read => Ok(Words(&frame[4..frame.len() - 2])),
        Function::Write => {
            let q = be16(frame, 4);
            if q != sent.quantity {
                return Err(FrameError::UnexpectedQuantity {
                    expected: sent.quantity,
                    got: q,
                });
            }
            Ok(Words(&[]))
        }
    }
}

/// The slave's side: decodes `request`, reads or writes `memory` (its
/// virtual memory, word-addressed) and encodes the reply into `reply`.
/// Returns the reply length.
pub fn serve(
    memory: &mut [u16],
    slave: u8,
    request: &[u8],
    reply: &mut [u8],
) -> Result<usize, FrameError> {
    let (h, words) = decode_request(request, slave)?;
    let (start, end) = (
        usize::from(h.start),
        usize::from(h.start) + usize::from(h.quantity),
    );
    if end > memory.len() {
        return Err(FrameError::OutOfRange {
            start: h.start,
            quantity: h.quantity,
            size: memory.len(),
        });
    }
    match h.function {
        Function::Read => encode_reply(reply, &h, &memory[start..end]),
        Function::Write => {
            for (m, w) in memory[start..end].iter_mut().zip(words.iter()) {
                *m = w;
            }
            encode_reply(reply, &h, &[])
        }
    }
}
