// The FSMC pin adapter and the board around the Verilator model of the
// generated motion_controller.v; main() runs the C firmware's scenarios.
// Time is counted as in the testbench's bus model (testbench/src/bfm/
// fsmc.rs): 42 ticks per ns, the 50 MHz FPGA clock 840 ticks, HCLK
// (168 MHz) 250 ticks, every access one timeline from time 0 whose first
// rising edge is at 420 ticks, run until 8 clocks after its end.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <vector>

#include "Vmotion_controller.h"
#include "cosim.h"
#include "motionhdl_regs.h"
#include "verilated.h"

namespace {

const uint64_t CLOCK_TICKS = 840, FIRST_EDGE = 420, HCLK = 250, GRID = 5;
const uint64_t WRITE_DATA_DELAY = 168, END_OBSERVATION = 10;
const unsigned AXES = 4, DRIVE_LATENCY = 3;

struct Pins {
    bool ne_n = true, noe_n = true, nwe_n = true;
    uint16_t a = 0, d = 0xffff;
};

struct Event {
    uint64_t t;
    unsigned order;
    bool observe;
    Pins pins;
    bool reset;
};

struct Drive {
    bool last_step = false;
    std::deque<int> pipeline = std::deque<int>(DRIVE_LATENCY, 0);
    int32_t position = 0;
    void clock(bool step, bool dir) {
        bool rising = step && !last_step;
        last_step = step;
        pipeline.push_back(rising ? (dir ? -1 : 1) : 0);
        position += pipeline.front();
        pipeline.pop_front();
    }
};

struct Switch {
    bool on = false;
    int32_t at = 0;
};

Vmotion_controller *top;
Drive drives[AXES];
Switch limit_pos[AXES], home_sw[AXES];
int32_t index_every[AXES];
bool estop_ok = true;
uint64_t edges;

void drive_pins(const Pins &p, bool reset) {
    top->reset = reset;
    top->fsmc_ne_n = p.ne_n;
    top->fsmc_noe_n = p.noe_n;
    top->fsmc_nwe_n = p.nwe_n;
    top->fsmc_a = p.a & 0xfff;
    top->fsmc_d_in = p.d;
    top->isa_ior_n = 1;
    top->isa_iow_n = 1;
    top->isa_aen = 1;
    unsigned a = 0, b = 0, z = 0, pos = 0, home = 0;
    for (unsigned i = 0; i < AXES; i++) {
        uint32_t q = (uint32_t)drives[i].position & 3u;
        a |= (unsigned)(q == 1 || q == 2) << i;
        b |= (unsigned)(q == 2 || q == 3) << i;
        z |= (unsigned)(index_every[i] != 0 && drives[i].position % index_every[i] == 0) << i;
        pos |= (unsigned)(limit_pos[i].on && drives[i].position >= limit_pos[i].at) << i;
        home |= (unsigned)(home_sw[i].on && drives[i].position >= home_sw[i].at) << i;
    }
    top->enc_a = a;
    top->enc_b = b;
    top->enc_z = z;
    top->estop_ok = estop_ok;
    top->limit_pos = pos;
    top->limit_neg = 0;
    top->home = home;
    top->alarm = 0;
    top->gpi = 0;
}

// One rising edge with these pins; then the drives see the outputs.
void edge(const Pins &p, bool reset) {
    drive_pins(p, reset);
    top->eval();
    top->clock = 1;
    top->eval();
    top->clock = 0;
    top->eval();
    for (unsigned i = 0; i < AXES; i++) {
        drives[i].clock((top->pulse_f1 >> i) & 1, (top->pulse_f2 >> i) & 1);
    }
    edges++;
}

// One bus operation: accesses (address, data) as the mode-1 waveform, or
// the reset; returns the halfwords a read latched.
std::vector<uint16_t> exec(const std::vector<std::pair<uint16_t, uint16_t>> &accesses, bool write,
                           bool reset_op) {
    std::vector<Event> ev;
    unsigned order = 0;
    Pins pins;
    uint64_t t = GRID;
    ev.push_back({0, order++, false, pins, false});
    if (reset_op) {
        t = ((t + 4 * CLOCK_TICKS) / CLOCK_TICKS + 1) * CLOCK_TICKS;
        ev.push_back({t, order++, false, pins, true});
        t += 5 * CLOCK_TICKS;
        ev.push_back({t, order++, false, pins, false});
        t += GRID;
    } else {
        pins.ne_n = false;
        for (auto [a, data] : accesses) {
            pins.a = a & 0xfff;
            if (write) {
                pins.d = (uint16_t)~data;
            }
            ev.push_back({t, order++, false, pins, false});
            uint64_t fall = t + MOTIONHDL_FSMC_ADDSET * HCLK;
            uint64_t rise = fall + MOTIONHDL_FSMC_DATAST * HCLK;
            if (write) {
                pins.nwe_n = false;
                ev.push_back({fall, order++, false, pins, false});
                pins.d = data;
                ev.push_back({fall + WRITE_DATA_DELAY, order++, false, pins, false});
                pins.nwe_n = true;
                ev.push_back({rise, order++, false, pins, false});
                t = rise + HCLK;
            } else {
                pins.noe_n = false;
                ev.push_back({fall, order++, false, pins, false});
                ev.push_back({rise - END_OBSERVATION, order++, true, pins, false});
                pins.noe_n = true;
                ev.push_back({rise, order++, false, pins, false});
                t = rise;
            }
        }
        pins.ne_n = true;
        pins.d = 0xffff;
        ev.push_back({t, order++, false, pins, false});
        t += (1 + MOTIONHDL_FSMC_BUSTURN) * HCLK;
    }
    std::stable_sort(ev.begin(), ev.end(), [](const Event &x, const Event &y) { return x.t < y.t; });
    uint64_t end = t + 8 * CLOCK_TICKS;
    std::vector<uint16_t> observed;
    Pins now;
    bool reset = false;
    size_t i = 0;
    for (uint64_t e = FIRST_EDGE;; e += CLOCK_TICKS) {
        for (; i < ev.size() && ev[i].t < e; i++) {
            if (ev[i].observe) {
                drive_pins(now, reset);
                top->eval();
                if (!top->fsmc_d_oe) {
                    std::fprintf(stderr, "cosim: the card does not drive D for a read of A=0x%03x\n", now.a);
                }
                observed.push_back((uint16_t)top->fsmc_d_out);
            } else {
                now = ev[i].pins;
                reset = ev[i].reset;
            }
        }
        if (e > end) {
            break;
        }
        edge(now, reset);
    }
    return observed;
}

// MOTIONHDL_COSIM_MISROUTE=FROM:TO (hex byte offsets) sends the
// firmware's accesses to register FROM to TO instead: what a driver with
// one wrong offset would do (the test shows the scenarios catch it).
uint32_t route(uint32_t offset) {
    static long from = -1, to = -1;
    static bool parsed = false;
    if (!parsed) {
        parsed = true;
        if (const char *m = std::getenv("MOTIONHDL_COSIM_MISROUTE")) {
            std::sscanf(m, "%lx:%lx", &from, &to);
        }
    }
    return (long)offset == from ? (uint32_t)to : offset;
}

uint32_t bus_read32(void *, uint32_t offset) {
    offset = route(offset);
    uint16_t a = (uint16_t)(offset / 2);
    auto h = exec({{a, 0}, {(uint16_t)(a + 1), 0}}, false, false);
    return (uint32_t)h[0] | (uint32_t)h[1] << 16;
}

void bus_write32(void *, uint32_t offset, uint32_t value) {
    offset = route(offset);
    uint16_t a = (uint16_t)(offset / 2);
    exec({{a, (uint16_t)value}, {(uint16_t)(a + 1), (uint16_t)(value >> 16)}}, true, false);
}

uint16_t bus_read16(void *, uint32_t offset) {
    return exec({{(uint16_t)(offset / 2), 0}}, false, false)[0];
}

void bus_write16(void *, uint32_t offset, uint16_t value) {
    exec({{(uint16_t)(offset / 2), value}}, true, false);
}

}  // namespace

extern "C" {

MotionhdlBus cosim_bus(void) {
    MotionhdlBus b;
    b.ctx = nullptr;
    b.read32 = bus_read32;
    b.write32 = bus_write32;
    b.read16 = bus_read16;
    b.write16 = bus_write16;
    return b;
}

void cosim_reset(void) { exec({}, false, true); }

void cosim_idle(uint64_t clocks) {
    Pins idle;
    for (uint64_t k = 0; k < clocks; k++) {
        edge(idle, false);
    }
}

uint64_t cosim_clocks(void) { return edges; }
void cosim_set_estop_ok(int ok) { estop_ok = ok != 0; }
void cosim_set_limit_pos(unsigned axis, int on, int32_t at) { limit_pos[axis] = {on != 0, at}; }
void cosim_set_home(unsigned axis, int on, int32_t at) { home_sw[axis] = {on != 0, at}; }
void cosim_set_index_every(unsigned axis, int32_t every) { index_every[axis] = every; }
int32_t cosim_shaft(unsigned axis) { return drives[axis].position; }
uint32_t cosim_drive_enable(void) { return top->drive_enable; }
int cosim_irq(void) { return top->irq; }

}  // extern "C"

int main(int argc, char **argv) {
    Verilated::commandArgs(argc, argv);
    top = new Vmotion_controller;
    top->clock = 0;
    drive_pins(Pins(), false);
    top->eval();
    int rc = cosim_firmware_main();
    top->final();
    delete top;
    return rc;
}
