//! The counter bank: the channels, the PRESET register and the register bus.

use super::{sign_extend, wrap, BusCycle, Channel, ChannelInputs, CounterParams};
use crate::regmap::{self, Access, Block};

/// A channel register, decoded once from the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ChReg {
    Ctrl,
    Cmd,
    Count,
    Index,
    Status,
}

impl ChReg {
    fn name(self) -> &'static str {
        match self {
            ChReg::Ctrl => "CTRL",
            ChReg::Cmd => "CMD",
            ChReg::Count => "COUNT",
            ChReg::Index => "INDEX",
            ChReg::Status => "STATUS",
        }
    }
}

/// What an address selects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Slot {
    Unmapped,
    Info,
    Snapshot,
    Preset,
    Channel(usize, ChReg),
    HomeCount(usize),
}

/// The bank: N channels, the PRESET register and the register bus.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bank {
    params: CounterParams,
    map: Block,
    /// Slot of every decodable address, indexed by address.
    decode: Vec<Slot>,
    channels: Vec<Channel>,
    preset: u32,
    /// Per channel: the count at the last home event (W bits).
    home_count: Vec<u32>,
    /// The value a read captured at the last edge (stage 1 of the
    /// two-edge read).
    read_pending: Option<u32>,
    rdata: u32,
}

impl Bank {
    /// A bank at power-up (every flop 0), decoding `regmap::counter_bank`.
    pub fn new(axes: u32, params: CounterParams) -> Self {
        let map = regmap::counter_bank_with(axes, params.width, params.features);
        let mut decode = vec![Slot::Unmapped; 1usize << map.address_bits];
        for (addr, reg, element) in map.decoded() {
            let slot = match (element, reg.name) {
                (None, "INFO") => Slot::Info,
                (None, "SNAPSHOT") => Slot::Snapshot,
                (None, "PRESET") => Slot::Preset,
                (Some(i), "HOME_COUNT") => Slot::HomeCount(i as usize),
                (Some(i), name) => {
                    let r = [
                        ChReg::Ctrl,
                        ChReg::Cmd,
                        ChReg::Count,
                        ChReg::Index,
                        ChReg::Status,
                    ]
                    .into_iter()
                    .find(|r| r.name() == name)
                    .unwrap_or_else(|| {
                        panic!("the model does not implement channel register {name}")
                    });
                    Slot::Channel(i as usize, r)
                }
                (None, name) => panic!("the model does not implement bank register {name}"),
            };
            decode[addr as usize] = slot;
        }
        let channels = (0..axes).map(|_| Channel::new(params)).collect();
        Self {
            params,
            map,
            decode,
            channels,
            preset: 0,
            home_count: vec![0; axes as usize],
            read_pending: None,
            rdata: 0,
        }
    }

    /// The register map this bank decodes.
    pub fn regmap(&self) -> &Block {
        &self.map
    }

    pub fn params(&self) -> CounterParams {
        self.params
    }

    pub fn channel(&self, i: usize) -> &Channel {
        &self.channels[i]
    }

    pub fn channels(&self) -> usize {
        self.channels.len()
    }

    /// The PRESET register as stored (raw 32 bits).
    pub fn preset(&self) -> u32 {
        self.preset
    }

    /// Per channel (STATUS.ERR, STATUS.SEEN) as they stand now, live:
    /// the safety block's counter-event inputs.
    pub fn flags(&self) -> (u32, u32) {
        self.channels
            .iter()
            .enumerate()
            .fold((0, 0), |(err, seen), (i, ch)| {
                let s = ch.state();
                (err | u32::from(s.err) << i, seen | u32::from(s.seen) << i)
            })
    }

    /// The registered read data.
    pub fn rdata(&self) -> u32 {
        self.rdata
    }

    /// The bus port is `addr[7:0]`: upper bits never reach the decoder.
    fn slot(&self, addr: u32) -> Slot {
        self.decode[wrap(addr, self.map.address_bits) as usize]
    }

    /// What a read of `addr` with `re` high in this clock returns: the
    /// register as it stands now, before this clock's edge (0 for unmapped
    /// and write-only addresses).
    pub fn read_value(&self, addr: u32) -> u32 {
        match self.slot(addr) {
            Slot::Unmapped | Slot::Snapshot => 0,
            Slot::Info => self.map.register("INFO").reset,
            Slot::Preset => sign_extend(self.preset, self.params.width),
            Slot::HomeCount(i) => sign_extend(self.home_count[i], self.params.width),
            Slot::Channel(i, r) => {
                if self.map.array("CH").register(r.name()).access == Access::WriteOnly {
                    0
                } else {
                    self.channels[i].read(r.name())
                }
            }
        }
    }

    /// One rising clock edge; `pins[i]` = (a, b, z) of channel i.
    pub fn clock(&mut self, pins: &[(bool, bool, bool)], reset: bool, bus: &BusCycle) {
        self.clock_homing(pins, reset, bus, 0);
    }

    /// One rising clock edge with the `home` input: bit i high captures
    /// channel i's count (as it stands before the edge) into HOME_COUNT.
    pub fn clock_homing(
        &mut self,
        pins: &[(bool, bool, bool)],
        reset: bool,
        bus: &BusCycle,
        home: u32,
    ) {
        self.clock_strobed(pins, reset, bus, (home, false));
    }

    /// One rising clock edge with the `home` input and the snapshot strobe
    /// (the servo tick): high, it takes the snapshot as a SNAPSHOT write
    /// does.
    pub fn clock_strobed(
        &mut self,
        pins: &[(bool, bool, bool)],
        reset: bool,
        bus: &BusCycle,
        (home, snapshot_strobe): (u32, bool),
    ) {
        assert_eq!(
            pins.len(),
            self.channels.len(),
            "pins for {} channels given to a bank of {}",
            pins.len(),
            self.channels.len()
        );
        let written = if bus.we {
            self.slot(bus.addr)
        } else {
            Slot::Unmapped
        };
        // Reads take two edges: the edge with `re` captures the addressed
        // register's value as it stands in that clock (before this edge's
        // write), the next one loads it into `rdata`.
        let rdata = match (reset, self.read_pending) {
            (true, _) => 0,
            (false, Some(value)) => value,
            (false, None) => self.rdata,
        };
        self.read_pending = (!reset && bus.re).then(|| self.read_value(bus.addr));
        let preset = self.preset;
        for (i, kept) in self.home_count.iter_mut().enumerate() {
            if reset {
                *kept = 0;
            } else if home >> i & 1 == 1 {
                *kept = self.channels[i].state().count;
            }
        }
        for (i, (ch, &(a, b, z))) in self.channels.iter_mut().zip(pins).enumerate() {
            ch.clock(&ChannelInputs {
                a,
                b,
                z,
                reset,
                ctrl_write: (written == Slot::Channel(i, ChReg::Ctrl)).then_some(bus.wdata),
                cmd_write: (written == Slot::Channel(i, ChReg::Cmd)).then_some(bus.wdata),
                snapshot: written == Slot::Snapshot || snapshot_strobe,
                preset,
            });
        }
        if reset {
            self.preset = 0;
        } else if written == Slot::Preset {
            self.preset = bus.wdata;
        }
        self.rdata = rdata;
    }
}
