//! What the checks read of a channel: every register for the model
//! comparison, and the consistency of its derived flags.

use super::CounterChannel;
use crate::probe::ChannelRegisters;

impl CounterChannel {
    /// Every register, for comparison with the model every clock.
    pub fn probe(&self) -> ChannelRegisters {
        ChannelRegisters {
            fa: self.filter_a.probe(),
            fb: self.filter_b.probe(),
            fz: self.filter_z.probe(),
            a_prev: self.a_prev.q.val(),
            b_prev: self.b_prev.q.val(),
            zg_prev: self.zg_prev.q.val(),
            zg_q: self.zg_q.q.val(),
            err_q: self.err_q.q.val(),
            up_q: self.decoder.up_q.val(),
            down_q: self.decoder.down_q.val(),
            count: self.counter.value(),
            load_q: self.load_q.q.val(),
            index_latch_q: self.index_latch_q.q.val(),
            index_clear_q: self.index_clear_q.q.val(),
            index: self.index.q.val().to_u32(),
            err: self.err.q.val(),
            err_count: self.err_count.q.val().to_u32(),
            seen: self.seen.q.val(),
            armed: self.armed.q.val(),
            ctrl: self.ctrl.q.val().to_u32(),
            snap_count: self.snap_count.q.val().to_u32(),
            snap_index: self.snap_index.q.val().to_u32(),
            snap_status: self.snap_status.q.val().to_u32(),
        }
    }

    /// The counter's look-ahead flags describe its low half, the filters'
    /// flags their counters and the error counter's saturation flag the
    /// error counter (contract properties the model does not see).
    pub fn flags_consistent(&self) -> bool {
        let err_max = self.err_max_minus_one.val().to_u32() + 1;
        self.counter.lookahead_consistent()
            && self.filter_a.consistent()
            && self.filter_b.consistent()
            && self.filter_z.consistent()
            && self.err_sat.q.val() == (self.err_count.q.val().to_u32() == err_max)
    }
}
