/* Example firmware scenarios on the C driver, run against the Verilator
 * model of the generated motion_controller.v (harness.cpp). Each prints one
 * line of results; testbench/tests/cosim.rs runs the same scenarios with
 * the Rust driver on the rust-hdl controller and expects the same lines,
 * clock counts included. */
#include <stdio.h>
#include <string.h>

#include "cosim.h"

static MotionhdlCard card;

static void setup(void) {
    MotionhdlAxisConfig cfg = {0, 0, 2, 2, 4, 2, 16, 0};
    unsigned i;
    int32_t rc;
    cosim_reset();
    rc = motionhdl_init(&card, cosim_bus());
    printf("card: init=%d version=0x%x axes=%u map=0x%08x\n", (int)rc, (unsigned)card.version,
           (unsigned)motionhdl_driver_axes(), (unsigned)motionhdl_driver_map_hash());
    printf("clear: %d\n", (int)motionhdl_clear_halt(&card));
    for (i = 0; i < 4; i++) {
        motionhdl_counter_configure(&card, i, 0); /* x4 */
        motionhdl_axis_configure(&card, i, &cfg);
    }
}

static MotionhdlSegment constant(uint32_t steps, int32_t period) {
    MotionhdlSegment s;
    s.steps = steps;
    s.rate = (int32_t)((((int64_t)1) << 32) / period);
    s.accel = 0;
    s.jerk = 0;
    return s;
}

static void print_sample(const char *name, unsigned n) {
    MotionhdlAxisSample s[4];
    unsigned i;
    motionhdl_sample(&card, s, 4);
    printf("%s:", name);
    for (i = 0; i < n; i++) {
        printf(" ax%u=%d/%d/%d", i, (int)s[i].position, (int)s[i].count, (int)cosim_shaft(i));
    }
    printf("\n");
}

/* S-curves on axes 0 and 1, streamed and started in one RUN write. */
static void scurve(void) {
    MotionhdlLimits lim = motionhdl_limits(2.0e6, 4.0e9, 8.0e13, 50.0e6);
    MotionhdlPlan px, py;
    MotionhdlStream sx, sy;
    uint64_t t0;
    unsigned polls = 0;
    int done;
    motionhdl_plan_scurve(1000, &lim, &px);
    motionhdl_plan_scurve(-600, &lim, &py);
    motionhdl_enable_drives(&card, 0x3);
    motionhdl_stream_init(&sx, 0);
    motionhdl_stream_init(&sy, 1);
    motionhdl_stream_refill(&card, &sx, px.segments, px.count);
    motionhdl_stream_refill(&card, &sy, py.segments, py.count);
    motionhdl_start(&card, 0x3);
    t0 = cosim_clocks();
    do {
        polls++;
        if (polls == 1000) {
            print_sample("moving", 2); /* a coherent read mid-move */
        }
        done = motionhdl_move_done(&card, 0) == MOTIONHDL_OK && motionhdl_move_done(&card, 1) == MOTIONHDL_OK;
    } while (!done && polls < 10000);
    printf("scurve: segments=%u,%u polls=%u clocks=%llu\n", (unsigned)px.count, (unsigned)py.count, polls,
           (unsigned long long)(cosim_clocks() - t0));
    cosim_idle(20);
    print_sample("after", 2);
}

/* A move of more segments than the FIFO holds on axis 2, refilled on the
 * interrupt: the firmware sleeps until the IRQ pin (active low) falls,
 * reads the causes, tops the FIFO up and acknowledges what it read. */
static void irq_stream(void) {
    MotionhdlSegment segs[100];
    MotionhdlCauses masks, c;
    MotionhdlStream s;
    uint64_t t0, waited;
    unsigned i, irqs = 0;
    int pushed = 0;
    for (i = 0; i < 100; i++) {
        segs[i] = constant(3, 30);
    }
    memset(&masks, 0, sizeof masks);
    masks.fifo_low = 0x4;
    masks.done = 0x4;
    motionhdl_irq_configure(&card, &masks, 0);
    motionhdl_stream_init(&s, 2);
    pushed = motionhdl_stream_refill(&card, &s, segs, 100) == MOTIONHDL_OK;
    motionhdl_start(&card, 0x4);
    t0 = cosim_clocks();
    for (;;) {
        for (waited = 0; cosim_irq() != 0 && waited < 200000; waited++) {
            cosim_idle(1);
        }
        if (waited == 200000) {
            break;
        }
        irqs++;
        motionhdl_causes(&card, &c);
        if (c.fifo_low & 0x4) {
            pushed = motionhdl_stream_refill(&card, &s, segs, 100) == MOTIONHDL_OK;
        }
        motionhdl_clear_causes(&card, &c);
        if ((c.done & 0x4) && pushed) {
            break;
        }
    }
    printf("irq: interrupts=%u pushed=%u clocks=%llu\n", irqs, (unsigned)s.next,
           (unsigned long long)(cosim_clocks() - t0));
    memset(&masks, 0, sizeof masks);
    motionhdl_irq_configure(&card, &masks, 0);
    cosim_idle(20);
    print_sample("irq", 3);
}

/* Axis 0 creeps into a LIMIT_POS switch 20 steps ahead. */
static void limit_stop(void) {
    MotionhdlSegment creep = constant(40, 200);
    MotionhdlCauses c;
    cosim_set_limit_pos(0, 1, cosim_shaft(0) + 20);
    motionhdl_input_configure(&card, 0, 0x1, 0x0);
    motionhdl_push_segment(&card, 0, &creep);
    motionhdl_start(&card, 0x1);
    cosim_idle(10000);
    motionhdl_causes(&card, &c);
    printf("limit: cause=0x%x irq=%d\n", (unsigned)c.limit, cosim_irq());
    print_sample("limit", 1);
}

/* The e-stop chain opens while axes 2 and 3 move. */
static void estop(void) {
    MotionhdlSegment s = constant(200, 100);
    uint32_t status = 0;
    int32_t held, cleared;
    motionhdl_push_segment(&card, 2, &s);
    motionhdl_push_segment(&card, 3, &s);
    motionhdl_enable_drives(&card, 0xc);
    motionhdl_start(&card, 0xc);
    cosim_idle(5000);
    cosim_set_estop_ok(0);
    cosim_idle(200);
    motionhdl_safety_status(&card, &status);
    held = motionhdl_clear_halt(&card);
    printf("estop: status=0x%x enable=0x%x clear=%d\n", (unsigned)status, (unsigned)cosim_drive_enable(), (int)held);
    cosim_set_estop_ok(1);
    cosim_idle(100);
    cleared = motionhdl_clear_halt(&card);
    printf("released: clear=%d enable=0x%x\n", (int)cleared, (unsigned)cosim_drive_enable());
    print_sample("estop", 4);
}

/* The watchdog, fed three times, then not. */
static void watchdog(void) {
    MotionhdlCauses c;
    uint32_t status = 0;
    unsigned k;
    motionhdl_enable_drives(&card, 0xf);
    motionhdl_watchdog_arm(&card, 3000);
    for (k = 0; k < 3; k++) {
        cosim_idle(1000);
        motionhdl_watchdog_feed(&card);
    }
    cosim_idle(4000);
    motionhdl_safety_status(&card, &status);
    motionhdl_causes(&card, &c);
    printf("watchdog: status=0x%x enable=0x%x cause=0x%x\n", (unsigned)status, (unsigned)cosim_drive_enable(),
           (unsigned)c.card);
    motionhdl_watchdog_arm(&card, 0);
    printf("recovered: clear=%d\n", (int)motionhdl_clear_halt(&card));
}

/* Homing axis 1 onto a switch 60 steps ahead, then its next index. */
static void homing(void) {
    MotionhdlHomingParams p = {1, 60, 400, 200, 20, 1};
    MotionhdlHoming h;
    MotionhdlHome home = {0, 0, 0, 0};
    int32_t rc;
    cosim_set_home(1, 1, cosim_shaft(1) + 60);
    cosim_set_index_every(1, 25);
    motionhdl_home_start(&h, &p);
    do {
        cosim_idle(300);
        rc = motionhdl_home_poll(&card, &h, 1, &home);
    } while (rc == MOTIONHDL_BUSY);
    printf("homing: rc=%d position=%d count=%d index=%d/%u shaft=%d\n", (int)rc, (int)home.position,
           (int)home.count, (int)home.index, (unsigned)home.has_index, (int)cosim_shaft(1));
}

int cosim_firmware_main(void) {
    setup();
    scurve();
    irq_stream();
    limit_stop();
    estop();
    watchdog();
    homing();
    printf("end: clocks=%llu\n", (unsigned long long)cosim_clocks());
    return 0;
}
