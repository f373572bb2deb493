/* Host unit tests of the C driver (libmotionhdl_driver.a) on a fake bus:
 * a window of memory laid out by the generated register struct
 * (motionhdl_regs.h), so every access the driver makes lands where the
 * register table puts it, and a log of the accesses in order.
 * Built and run by tests/driver_c.rs; prints "N checks passed". */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "motionhdl_driver.h"
#include "motionhdl_regs.h"

static union {
    MOTIONHDL_TypeDef regs;
    uint8_t bytes[sizeof(MOTIONHDL_TypeDef)];
} card_mem;

#define LOG_MAX 1024
static struct {
    char op;
    uint32_t offset;
    uint32_t value;
} bus_log[LOG_MAX];
static unsigned log_len;
static unsigned checks, failures;

#define CHECK(cond)                                                                     \
    do {                                                                                \
        checks++;                                                                       \
        if (!(cond)) {                                                                  \
            failures++;                                                                 \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
        }                                                                               \
    } while (0)

#define OFF(field) ((uint32_t)offsetof(MOTIONHDL_TypeDef, field))

static void record(char op, uint32_t offset, uint32_t value) {
    if (log_len < LOG_MAX) {
        bus_log[log_len].op = op;
        bus_log[log_len].offset = offset;
        bus_log[log_len].value = value;
    }
    log_len++;
}

static uint32_t fake_read32(void *ctx, uint32_t offset) {
    uint32_t v;
    (void)ctx;
    memcpy(&v, card_mem.bytes + offset, sizeof v);
    record('R', offset, v);
    return v;
}

static void fake_write32(void *ctx, uint32_t offset, uint32_t value) {
    (void)ctx;
    memcpy(card_mem.bytes + offset, &value, sizeof value);
    record('W', offset, value);
}

static uint16_t fake_read16(void *ctx, uint32_t offset) {
    uint16_t v;
    (void)ctx;
    memcpy(&v, card_mem.bytes + offset, sizeof v);
    record('r', offset, v);
    return v;
}

static void fake_write16(void *ctx, uint32_t offset, uint16_t value) {
    (void)ctx;
    memcpy(card_mem.bytes + offset, &value, sizeof value);
    record('w', offset, value);
}

static void poke(uint32_t offset, uint32_t value) {
    memcpy(card_mem.bytes + offset, &value, sizeof value);
}

static void reset_card(void) {
    memset(&card_mem, 0, sizeof card_mem);
    poke(OFF(ID.MAGIC), MOTIONHDL_ID_MAGIC);
    poke(OFF(ID.VERSION), MOTIONHDL_ID_VERSION_reset);
    poke(OFF(ID.MAP_HASH), MOTIONHDL_MAP_HASH);
    log_len = 0;
}

static MotionhdlBus fake_bus(void) {
    MotionhdlBus bus;
    bus.ctx = NULL;
    bus.read32 = fake_read32;
    bus.write32 = fake_write32;
    bus.read16 = fake_read16;
    bus.write16 = fake_write16;
    return bus;
}

static void test_init(MotionhdlCard *card) {
    MotionhdlBus broken = fake_bus();
    reset_card();
    CHECK(motionhdl_driver_map_hash() == MOTIONHDL_MAP_HASH);
    CHECK(motionhdl_driver_axes() == MOTIONHDL_PULSE_AX_NUM);
    CHECK(motionhdl_init(card, fake_bus()) == MOTIONHDL_OK);
    CHECK(card->version == MOTIONHDL_ID_VERSION_reset);
    CHECK(log_len == 3 && bus_log[0].offset == OFF(ID.MAGIC) && bus_log[2].offset == OFF(ID.MAP_HASH));
    poke(OFF(ID.MAGIC), 0);
    CHECK(motionhdl_init(card, fake_bus()) == MOTIONHDL_ERR_MAGIC);
    reset_card();
    poke(OFF(ID.VERSION), MOTIONHDL_ID_VERSION_reset + (1u << MOTIONHDL_ID_VERSION__MAJOR_bp));
    CHECK(motionhdl_init(card, fake_bus()) == MOTIONHDL_ERR_VERSION);
    reset_card();
    poke(OFF(ID.MAP_HASH), MOTIONHDL_MAP_HASH ^ 1u);
    CHECK(motionhdl_init(card, fake_bus()) == MOTIONHDL_ERR_MAP_HASH);
    broken.write16 = NULL;
    CHECK(motionhdl_init(card, broken) == MOTIONHDL_ERR_ARGUMENT);
    CHECK(motionhdl_init(NULL, fake_bus()) == MOTIONHDL_ERR_ARGUMENT);
    reset_card();
    CHECK(motionhdl_init(card, fake_bus()) == MOTIONHDL_OK);
}

static void test_sample(MotionhdlCard *card) {
    MotionhdlAxisSample s[MOTIONHDL_PULSE_AX_NUM];
    unsigned i;
    for (i = 0; i < MOTIONHDL_PULSE_AX_NUM; i++) {
        poke(OFF(COUNTER.CH[i].COUNT), (uint32_t)(-7 - (int32_t)i));
        poke(OFF(PULSE.AX[i].POSITION), 1000u + i);
    }
    log_len = 0;
    CHECK(motionhdl_sample(card, s, MOTIONHDL_PULSE_AX_NUM) == MOTIONHDL_OK);
    CHECK(bus_log[0].op == 'W' && bus_log[0].offset == OFF(COUNTER.SNAPSHOT));
    CHECK(log_len == 1 + 4 * MOTIONHDL_PULSE_AX_NUM);
    for (i = 0; i < MOTIONHDL_PULSE_AX_NUM; i++) {
        CHECK(s[i].count == -7 - (int32_t)i);
        CHECK(s[i].position == 1000 + (int32_t)i);
    }
    CHECK(motionhdl_sample(card, s, MOTIONHDL_PULSE_AX_NUM + 1) == MOTIONHDL_ERR_ARGUMENT);
    CHECK(motionhdl_sample(card, NULL, 1) == MOTIONHDL_ERR_ARGUMENT);
}

static void test_axis(MotionhdlCard *card) {
    MotionhdlAxisConfig cfg;
    MotionhdlSegment seg;
    memset(&cfg, 0, sizeof cfg);
    cfg.cw_ccw = 1;
    cfg.step_len = 3;
    cfg.step_space = 4;
    cfg.dir_setup = 5;
    cfg.dir_hold = 6;
    cfg.fifo_low_water = 16;
    CHECK(motionhdl_axis_configure(card, 1, &cfg) == MOTIONHDL_OK);
    CHECK(card_mem.regs.PULSE.AX[1].CTRL ==
          (MOTIONHDL_PULSE_AX_CTRL__MODE_bm | MOTIONHDL_PULSE_AX_CTRL__MOVES_bm));
    CHECK(card_mem.regs.PULSE.AX[1].STEP_TIMING ==
          (3u | 4u << MOTIONHDL_PULSE_AX_STEP_TIMING__STEP_SPACE_bp));
    CHECK(card_mem.regs.PULSE.AX[1].DIR_TIMING ==
          (5u | 6u << MOTIONHDL_PULSE_AX_DIR_TIMING__DIR_HOLD_bp));
    CHECK(card_mem.regs.PULSE.AX[1].FIFO_LOW_WATER == 16u);
    CHECK(motionhdl_axis_configure(card, MOTIONHDL_PULSE_AX_NUM, &cfg) == MOTIONHDL_ERR_ARGUMENT);
    seg.steps = 9;
    seg.rate = -5;
    seg.accel = 6;
    seg.jerk = -7;
    log_len = 0;
    CHECK(motionhdl_push_segment(card, 3, &seg) == MOTIONHDL_OK);
    CHECK(card_mem.regs.PULSE.AX[3].SEG_STEPS == 9u);
    CHECK(card_mem.regs.PULSE.AX[3].SEG_RATE == (uint32_t)-5);
    CHECK(card_mem.regs.PULSE.AX[3].SEG_ACCEL == 6u);
    CHECK(card_mem.regs.PULSE.AX[3].SEG_JERK == (uint32_t)-7);
    CHECK(log_len == 5 && bus_log[4].offset == OFF(PULSE.AX[3].SEG_PUSH));
    /* A segment that never ends (no rate, accel or jerk) touches nothing. */
    seg.rate = 0;
    seg.accel = 0;
    seg.jerk = 0;
    log_len = 0;
    CHECK(motionhdl_push_segment(card, 3, &seg) == MOTIONHDL_ERR_ARGUMENT && log_len == 0);
    card_mem.regs.PULSE.RUN = 1;
    CHECK(motionhdl_start(card, 0x6) == MOTIONHDL_OK && card_mem.regs.PULSE.RUN == 0x7);
    CHECK(motionhdl_stop(card, 0x3) == MOTIONHDL_OK && card_mem.regs.PULSE.RUN == 0x4);
}

static void test_stream(MotionhdlCard *card) {
    MotionhdlSegment segs[70];
    MotionhdlStream stream;
    unsigned i, pushes = 0;
    for (i = 0; i < 70; i++) {
        segs[i].steps = i + 1;
        segs[i].rate = 1 << 28;
        segs[i].accel = 0;
        segs[i].jerk = 0;
    }
    CHECK(motionhdl_stream_init(&stream, 0) == MOTIONHDL_OK);
    poke(OFF(PULSE.AX[0].STATUS), 0);
    log_len = 0;
    CHECK(motionhdl_stream_refill(card, &stream, segs, 70) == MOTIONHDL_BUSY);
    CHECK(stream.next == 64);
    for (i = 0; i < log_len && i < LOG_MAX; i++) {
        pushes += bus_log[i].offset == OFF(PULSE.AX[0].SEG_PUSH);
    }
    CHECK(pushes == 64);
    /* The FIFO drained to 60: four more go in, two are left. */
    poke(OFF(PULSE.AX[0].STATUS), 60u << MOTIONHDL_PULSE_AX_STATUS__FIFO_LEVEL_bp);
    CHECK(motionhdl_stream_refill(card, &stream, segs, 70) == MOTIONHDL_BUSY);
    CHECK(stream.next == 68 && card_mem.regs.PULSE.AX[0].SEG_STEPS == 68u);
    poke(OFF(PULSE.AX[0].STATUS), 0);
    CHECK(motionhdl_stream_refill(card, &stream, segs, 70) == MOTIONHDL_OK);
    CHECK(stream.next == 70);
    poke(OFF(PULSE.AX[0].STATUS), MOTIONHDL_PULSE_AX_STATUS__OVERFLOW_bm);
    CHECK(motionhdl_stream_refill(card, &stream, segs, 70) == MOTIONHDL_ERR_FIFO_OVERFLOW);
    poke(OFF(PULSE.AX[0].STATUS), MOTIONHDL_PULSE_AX_STATUS__DONE_bm);
    CHECK(motionhdl_move_done(card, 0) == MOTIONHDL_OK);
    poke(OFF(PULSE.AX[0].STATUS), MOTIONHDL_PULSE_AX_STATUS__DONE_bm | MOTIONHDL_PULSE_AX_STATUS__BUSY_bm);
    CHECK(motionhdl_move_done(card, 0) == MOTIONHDL_BUSY);
}

static void test_safety(MotionhdlCard *card) {
    MotionhdlCauses causes;
    uint32_t status = 0;
    poke(OFF(SAFETY.STATUS), MOTIONHDL_SAFETY_STATUS__ESTOP_INPUT_bm | MOTIONHDL_SAFETY_STATUS__ESTOP_bm);
    CHECK(motionhdl_clear_halt(card) == MOTIONHDL_ERR_ESTOP_INPUT);
    CHECK(card_mem.regs.SAFETY.CLEAR == 0);
    poke(OFF(SAFETY.STATUS), 0);
    CHECK(motionhdl_clear_halt(card) == MOTIONHDL_OK);
    CHECK(card_mem.regs.SAFETY.CLEAR ==
          (MOTIONHDL_SAFETY_CLEAR__ESTOP_bm | MOTIONHDL_SAFETY_CLEAR__BITTEN_bm));
    CHECK(motionhdl_safety_status(card, &status) == MOTIONHDL_OK && status == 0);
    CHECK(motionhdl_watchdog_arm(card, 5000) == MOTIONHDL_OK && card_mem.regs.SAFETY.WDT_TIMEOUT == 5000u);
    CHECK(motionhdl_watchdog_feed(card) == MOTIONHDL_OK && card_mem.regs.SAFETY.WDT_RELOAD != 0);
    CHECK(motionhdl_enable_drives(card, 0x5) == MOTIONHDL_OK && card_mem.regs.SAFETY.ENABLE == 0x5u);
    CHECK(motionhdl_input_configure(card, 2, 0x3, 0x1) == MOTIONHDL_OK);
    CHECK(card_mem.regs.SAFETY.HOME_CTRL == (0x3u | 0x1u << MOTIONHDL_SAFETY_HOME_CTRL__ACTIVE_LOW_bp));
    CHECK(motionhdl_input_configure(card, 4, 0, 0) == MOTIONHDL_ERR_ARGUMENT);
    poke(OFF(SAFETY.CAUSE), MOTIONHDL_SAFETY_CAUSE__WATCHDOG_bm);
    poke(OFF(SAFETY.LIMIT_CAUSE), 0x10);
    CHECK(motionhdl_causes(card, &causes) == MOTIONHDL_OK);
    CHECK(causes.card == MOTIONHDL_SAFETY_CAUSE__WATCHDOG_bm && causes.limit == 0x10 && causes.done == 0);
    log_len = 0;
    CHECK(motionhdl_clear_causes(card, &causes) == MOTIONHDL_OK && log_len == 2);
    memset(&causes, 0, sizeof causes);
    causes.fifo_low = 0xf;
    CHECK(motionhdl_irq_configure(card, &causes, 1) == MOTIONHDL_OK);
    CHECK(card_mem.regs.SAFETY.LOW_MASK == 0xfu && card_mem.regs.SAFETY.IRQ_CTRL == 1u);
}

static void test_ram_and_homing(MotionhdlCard *card) {
    uint16_t out[3] = {1, 2, 3}, back[3];
    MotionhdlHoming homing;
    MotionhdlHomingParams p;
    MotionhdlHome home;
    CHECK(motionhdl_ram_write(card, 10, out, 3) == MOTIONHDL_OK);
    CHECK(card_mem.regs.SHARED_RAM[11] == 2);
    CHECK(motionhdl_ram_read(card, 10, back, 3) == MOTIONHDL_OK && back[2] == 3);
    CHECK(motionhdl_ram_write(card, MOTIONHDL_SHARED_RAM_WORDS - 2, out, 3) == MOTIONHDL_ERR_ARGUMENT);
    memset(&homing, 0, sizeof homing);
    p.toward = 2; /* not +1 or -1 */
    p.fast_period = 50;
    p.slow_period = 500;
    p.max_travel = 1000;
    p.backoff = 20;
    p.index = 0;
    CHECK(motionhdl_home_start(&homing, &p) == MOTIONHDL_ERR_ARGUMENT);
    CHECK(motionhdl_home_poll(card, &homing, 0, &home) == MOTIONHDL_ERR_ARGUMENT);
    p.toward = 1;
    CHECK(motionhdl_home_start(&homing, &p) == MOTIONHDL_OK);
    /* The first poll arms HOME and starts the fast search. */
    log_len = 0;
    CHECK(motionhdl_home_poll(card, &homing, 0, &home) == MOTIONHDL_BUSY);
    CHECK((card_mem.regs.SAFETY.HOME_STOP & 1u) == 1u && (card_mem.regs.PULSE.RUN & 1u) == 1u);
    CHECK(card_mem.regs.PULSE.AX[0].SEG_STEPS == 1000u);
}

static void test_plan(void) {
    MotionhdlLimits lim = motionhdl_limits(20000.0, 200000.0, 4.0e6, 50.0e6);
    MotionhdlLimits zero = {0, 0, 0};
    MotionhdlPlan plan, back;
    unsigned i;
    uint32_t steps = 0;
    CHECK(lim.rate > 0 && lim.accel > 0 && lim.jerk > 0);
    CHECK(motionhdl_plan_scurve(1000, &lim, &plan) == MOTIONHDL_OK);
    CHECK(plan.count >= 1 && plan.count <= MOTIONHDL_PLAN_SEGMENTS && plan.clocks > 0);
    for (i = 0; i < plan.count; i++) {
        steps += plan.segments[i].steps;
        CHECK(plan.segments[i].rate >= 0);
    }
    CHECK(steps == 1000u);
    /* At 20000 steps/s a 1000-step move takes more than 50 ms. */
    CHECK(plan.clocks > 2500000u);
    CHECK(motionhdl_plan_scurve(-1000, &lim, &back) == MOTIONHDL_OK);
    CHECK(back.count == plan.count && back.segments[0].jerk == -plan.segments[0].jerk);
    CHECK(motionhdl_plan_scurve(1000, &zero, &plan) == MOTIONHDL_ERR_ARGUMENT);
    CHECK(motionhdl_plan_scurve(1000, NULL, &plan) == MOTIONHDL_ERR_ARGUMENT);
}

int main(void) {
    MotionhdlCard card;
    test_init(&card);
    test_sample(&card);
    test_axis(&card);
    test_stream(&card);
    test_safety(&card);
    test_ram_and_homing(&card);
    test_plan();
    printf("%u checks, %u failed\n", checks, failures);
    return failures == 0 ? 0 : 1;
}
