//! The counter bank: N channels, the PRESET register and the register bus.

use crate::counter_channel::CounterChannel;
use crate::up_down_counter::UpDownCounter;
use motionhdl_spec::bus::{CounterFeatures, CounterParams};
use motionhdl_spec::regmap::{self, ERR_COUNT_BITS};
use rust_hdl::prelude::*;

/// N counter channels behind one synchronous register bus
/// (docs/counter_bank.md). `N` is the axis count (1..=16); the counter
/// width is a constructor parameter.
///
/// Bus: a write takes effect at the edge where `we` is high. A read is
/// pipelined: the edge where `re` is high captures the addressed register's
/// value as it stands in that clock, the next edge loads it into `rdata`,
/// which then holds.
#[derive(LogicBlock)]
pub struct CounterBank<const N: usize> {
    /// FPGA clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset, active high; hold at least 4 clocks.
    pub reset: Signal<In, Bit>,
    /// Encoder A pins, one per channel, asynchronous.
    pub a: Signal<In, Bits<N>>,
    /// Encoder B pins.
    pub b: Signal<In, Bits<N>>,
    /// Index pins.
    pub z: Signal<In, Bits<N>>,
    /// Per channel: the home event (the safety block's `home_event` on the
    /// MCU top); high in a clock, HOME_COUNT takes the count at its edge.
    pub home: Signal<In, Bits<N>>,
    /// Register bus word address.
    pub addr: Signal<In, Bits<8>>,
    /// Register bus write data.
    pub wdata: Signal<In, Bits<32>>,
    /// Write strobe.
    pub we: Signal<In, Bit>,
    /// Read strobe.
    pub re: Signal<In, Bit>,
    /// Read data, valid from the second clock edge after `re`.
    pub rdata: Signal<Out, Bits<32>>,
    /// Take the snapshot at this edge, as a write of SNAPSHOT does (the
    /// servo tick in the servo card's top; tie low elsewhere).
    pub snapshot_strobe: Signal<In, Bit>,
    /// Per channel: STATUS.ERR, live (flip-flops).
    pub error: Signal<Out, Bits<N>>,
    /// Per channel: STATUS.SEEN, live (flip-flops).
    pub index_seen: Signal<Out, Bits<N>>,
    channels: Vec<CounterChannel>,
    preset: DFF<Bits<32>>,
    read_data: DFF<Bits<32>>,
    // Flags of PRESET's low-half bits for the counters' look-ahead, kept
    // with PRESET so that no channel compares 32 bits on its load path.
    preset_low_is_max: DFF<Bit>,
    preset_low_is_nonzero: DFF<Bit>,
    read_pending: DFF<Bit>,
    // Read stage 1 for the bank's own registers, like each channel's.
    read_sel: DFF<Bit>,
    read_word: DFF<Bits<32>>,
    home_count: Vec<DFF<Bits<32>>>,
    addr_home_count: Vec<Constant<Bits<8>>>,
    addr_info: Constant<Bits<8>>,
    addr_snapshot: Constant<Bits<8>>,
    // 0 in a build without SNAPSHOT: its address is then unmapped.
    has_snapshot: Constant<Bit>,
    addr_preset: Constant<Bits<8>>,
    info: Constant<Bits<32>>,
    width_mask: Constant<Bits<32>>,
    low_mask: Constant<Bits<32>>,
    sign_bit: Constant<Bits<32>>,
    sign_extension: Constant<Bits<32>>,
    snapshot: Signal<Local, Bit>,
    preset_read: Signal<Local, Bits<32>>,
    read_value: Signal<Local, Bits<32>>,
    bank_read: Signal<Local, Bit>,
    error_bits: Signal<Local, Bits<N>>,
    seen_bits: Signal<Local, Bits<N>>,
    channel_bit: Vec<Constant<Bits<N>>>,
}

impl<const N: usize> CounterBank<N> {
    /// A bank of `N` channels with `width`-bit counters (2..=32; the
    /// configuration allows 8..=32) and the gateware's 8-bit error counters.
    pub fn new(width: u32) -> Self {
        Self::with_params(CounterParams::new(width, ERR_COUNT_BITS))
    }

    /// As [`CounterBank::new`], built with `features`.
    pub fn with_features(width: u32, features: CounterFeatures) -> Self {
        Self::with_params(CounterParams::new(width, ERR_COUNT_BITS).with_features(features))
    }

    /// As [`CounterBank::new`] with `err_bits`-bit error counters (1..=8),
    /// for exhaustive checks at narrow instances.
    pub fn with_err_bits(width: u32, err_bits: u32) -> Self {
        Self::with_params(CounterParams::new(width, err_bits))
    }

    /// A bank of channels built with `params` (width, error counter width,
    /// features).
    pub fn with_params(params: CounterParams) -> Self {
        assert!((1..=16).contains(&N), "axes = {N} out of range 1..=16");
        let width = params.width;
        let full = regmap::counter_bank(N as u32, width);
        let map = regmap::counter_bank_with(N as u32, width, params.features);
        let addr = |reg: &str| -> Constant<Bits<8>> {
            Constant::new((full.register(reg).offset as u64).into())
        };
        let width_mask = CounterParams::new(width, 1).count_mask();
        let k32 = |v: u32| Constant::new((v as u64).into());
        Self {
            clock: Default::default(),
            reset: Default::default(),
            a: Default::default(),
            b: Default::default(),
            z: Default::default(),
            home: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            we: Default::default(),
            re: Default::default(),
            rdata: Default::default(),
            snapshot_strobe: Default::default(),
            error: Default::default(),
            index_seen: Default::default(),
            channels: (0..N as u32)
                .map(|i| CounterChannel::new(N as u32, i, params))
                .collect(),
            preset: Default::default(),
            read_data: Default::default(),
            preset_low_is_max: Default::default(),
            preset_low_is_nonzero: Default::default(),
            read_pending: Default::default(),
            read_sel: Default::default(),
            read_word: Default::default(),
            home_count: (0..N).map(|_| Default::default()).collect(),
            addr_home_count: (0..N as u32)
                .map(|i| Constant::new((full.array("CH").address(i, "HOME_COUNT") as u64).into()))
                .collect(),
            addr_info: addr("INFO"),
            addr_snapshot: addr("SNAPSHOT"),
            has_snapshot: Constant::new(params.features.snapshot),
            addr_preset: addr("PRESET"),
            info: k32(map.register("INFO").reset),
            width_mask: k32(width_mask),
            low_mask: k32(UpDownCounter::low_mask(width)),
            sign_bit: k32(1 << (width - 1)),
            sign_extension: k32(!width_mask),
            snapshot: Default::default(),
            preset_read: Default::default(),
            read_value: Default::default(),
            bank_read: Default::default(),
            error_bits: Default::default(),
            seen_bits: Default::default(),
            channel_bit: (0..N).map(|i| Constant::new((1u64 << i).into())).collect(),
        }
    }

    /// Channel `i`, for probing in traces.
    pub fn channel(&self, i: usize) -> &CounterChannel {
        &self.channels[i]
    }
}

impl<const N: usize> Logic for CounterBank<N> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            preset,
            read_data,
            preset_low_is_max,
            preset_low_is_nonzero,
            read_pending,
            read_sel,
            read_word
        );
        self.snapshot.next = ((self.we.val() & (self.addr.val() == self.addr_snapshot.val()))
            | self.snapshot_strobe.val())
            & self.has_snapshot.val();
        self.error_bits.next = 0.into();
        self.seen_bits.next = 0.into();
        for i in 0..N {
            if self.channels[i].error.val() {
                self.error_bits.next = self.error_bits.val() | self.channel_bit[i].val();
            }
            if self.channels[i].index_seen.val() {
                self.seen_bits.next = self.seen_bits.val() | self.channel_bit[i].val();
            }
            self.channels[i].clock.next = self.clock.val();
            self.channels[i].reset.next = self.reset.val();
            self.channels[i].a.next = self.a.val().get_bit(i);
            self.channels[i].b.next = self.b.val().get_bit(i);
            self.channels[i].z.next = self.z.val().get_bit(i);
            self.channels[i].addr.next = self.addr.val();
            self.channels[i].wdata.next = self.wdata.val();
            self.channels[i].we.next = self.we.val();
            self.channels[i].re.next = self.re.val();
            self.channels[i].snapshot.next = self.snapshot.val();
            self.channels[i].preset.next = self.preset.q.val();
            self.channels[i].preset_low_is_max.next = self.preset_low_is_max.q.val();
            self.channels[i].preset_low_is_nonzero.next = self.preset_low_is_nonzero.q.val();
        }
        if (self.preset.q.val() & self.sign_bit.val()).any() {
            self.preset_read.next =
                (self.preset.q.val() & self.width_mask.val()) | self.sign_extension.val();
        } else {
            self.preset_read.next = self.preset.q.val() & self.width_mask.val();
        }
        // Reads, stage 1: the addressed word (each channel has its own).
        self.read_pending.d.next = self.re.val();
        self.bank_read.next =
            (self.addr.val() == self.addr_info.val()) | (self.addr.val() == self.addr_preset.val());
        self.read_word.d.next = self.info.val();
        if self.addr.val() == self.addr_preset.val() {
            self.read_word.d.next = self.preset_read.val();
        }
        // HOME_COUNT: the bank keeps it (a channel's slot 5 reads 0).
        for i in 0..N {
            self.home_count[i].clock.next = self.clock.val();
            self.home_count[i].d.next = self.home_count[i].q.val();
            if self.home.val().get_bit(i) {
                self.home_count[i].d.next = self.channels[i].count.val();
            }
            if self.addr.val() == self.addr_home_count[i].val() {
                self.bank_read.next = true;
                self.read_word.d.next = self.home_count[i].q.val();
                if (self.home_count[i].q.val() & self.sign_bit.val()).any() {
                    self.read_word.d.next = self.home_count[i].q.val() | self.sign_extension.val();
                }
            }
            if self.reset.val() {
                self.home_count[i].d.next = 0.into();
            }
        }
        self.read_sel.d.next = self.re.val() & self.bank_read.val();
        // Stage 2: AND-OR of one word per channel into `rdata`.
        self.read_value.next = 0.into();
        if self.read_sel.q.val() {
            self.read_value.next = self.read_word.q.val();
        }
        for i in 0..N {
            self.read_value.next = self.read_value.val() | self.channels[i].rdata.val();
        }
        if self.we.val() & (self.addr.val() == self.addr_preset.val()) {
            self.preset.d.next = self.wdata.val();
            self.preset_low_is_max.d.next =
                (self.wdata.val() & self.low_mask.val()) == self.low_mask.val();
            self.preset_low_is_nonzero.d.next = (self.wdata.val() & self.low_mask.val()).any();
        }
        if self.read_pending.q.val() {
            self.read_data.d.next = self.read_value.val();
        }
        if self.reset.val() {
            self.preset.d.next = 0.into();
            self.preset_low_is_max.d.next = false;
            self.preset_low_is_nonzero.d.next = false;
            self.read_data.d.next = 0.into();
            self.read_pending.d.next = false;
            self.read_sel.d.next = false;
        }
        self.rdata.next = self.read_data.q.val();
        self.error.next = self.error_bits.val();
        self.index_seen.next = self.seen_bits.val();
    }
}
