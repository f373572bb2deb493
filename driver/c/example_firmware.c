/* An STM32F4 firmware's use of the driver, as built for a Cortex-M4 by
 * tests/driver_c.rs (arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -Os -Wall
 * -Wextra -Werror, the FPU's hard-float ABI as thumbv7em-none-eabihf):
 * check the card, set two axes up, plan an S-curve for each, stream them
 * and start both in one write, feed the watchdog while it runs, read both axes
 * coherently. The FSMC set-up (FSMC_BCR1/BTR1, docs/fsmc_bridge.md) comes
 * before main in a real project. */
#include <stdint.h>

#include "motionhdl_driver.h"

#define FPGA_BASE 0x60000000u /* FSMC bank 1, NE1 */


volatile int32_t last_status;
volatile MotionhdlAxisSample axes_now[2];

static int32_t run(void) {
    MotionhdlCard card;
    MotionhdlAxisConfig cfg = {0, 0, 2, 2, 4, 2, 16, 0};
    MotionhdlStream sx, sy;
    MotionhdlAxisSample s[2];
    MotionhdlPlan px, py;
    /* 20 k steps/s, 200 k steps/s^2, 4 M steps/s^3 on the 50 MHz clock. */
    MotionhdlLimits lim = motionhdl_limits(20000.0, 200000.0, 4.0e6, 50.0e6);
    int32_t rc;
    unsigned i;

    rc = motionhdl_init(&card, motionhdl_bus_mmio(FPGA_BASE));
    if (rc != MOTIONHDL_OK) {
        return rc; /* MAGIC, VERSION or MAP_HASH mismatch */
    }
    rc = motionhdl_clear_halt(&card);
    if (rc != MOTIONHDL_OK) {
        return rc;
    }
    for (i = 0; i < 2; i++) {
        if (motionhdl_counter_configure(&card, i, 0) != MOTIONHDL_OK ||
            motionhdl_axis_configure(&card, i, &cfg) != MOTIONHDL_OK) {
            return MOTIONHDL_ERR_ARGUMENT;
        }
    }
    motionhdl_watchdog_arm(&card, 5000000u); /* 100 ms at 50 MHz */
    motionhdl_enable_drives(&card, 0x3u);
    motionhdl_stream_init(&sx, 0);
    motionhdl_stream_init(&sy, 1);
    if (motionhdl_plan_scurve(4000, &lim, &px) != MOTIONHDL_OK ||
        motionhdl_plan_scurve(-2500, &lim, &py) != MOTIONHDL_OK) {
        return MOTIONHDL_ERR_ARGUMENT;
    }
    motionhdl_stream_refill(&card, &sx, px.segments, px.count);
    motionhdl_stream_refill(&card, &sy, py.segments, py.count);
    motionhdl_start(&card, 0x3u);
    while (motionhdl_move_done(&card, 0) == MOTIONHDL_BUSY || motionhdl_move_done(&card, 1) == MOTIONHDL_BUSY) {
        motionhdl_watchdog_feed(&card);
    }
    rc = motionhdl_sample(&card, s, 2);
    axes_now[0] = s[0];
    axes_now[1] = s[1];
    return rc;
}

int main(void) {
    last_status = run();
    for (;;) {
    }
}
