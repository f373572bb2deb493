/* The co-simulation's board and clock, for the firmware scenarios
 * (firmware.c): the Verilator model of the generated motion_controller.v
 * behind an FSMC pin adapter (harness.cpp), with step/direction drives and
 * quadrature encoders on its pins, limit and home switches on the shafts,
 * an encoder index and the e-stop chain. Mirrors the testbench's System
 * (testbench/src/checks/motion_controller/system.rs) clock for clock. */
#ifndef MOTIONHDL_COSIM_H
#define MOTIONHDL_COSIM_H

#include <stdint.h>

#include "motionhdl_driver.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The card's bus: each access is FSMC pin changes at the FSMC_BTR1 timing
 * of motionhdl_regs.h (ADDSET, DATAST, BUSTURN at HCLK 168 MHz). */
MotionhdlBus cosim_bus(void);
/* The reset input high for 5 clocks, 4 clocks after the last access. */
void cosim_reset(void);
/* `clocks` FPGA clocks with the bus idle (the firmware busy elsewhere). */
void cosim_idle(uint64_t clocks);
/* FPGA clock edges so far. */
uint64_t cosim_clocks(void);
/* The board: e-stop chain (1 = released), switches at shaft positions
 * (active high at or beyond `at`; `on` 0 removes the switch), an index
 * every `every` steps (0: none). */
void cosim_set_estop_ok(int ok);
void cosim_set_limit_pos(unsigned axis, int on, int32_t at);
void cosim_set_home(unsigned axis, int on, int32_t at);
void cosim_set_index_every(unsigned axis, int32_t every);
/* A drive's shaft position (steps), the ENABLE pins, the IRQ pin. */
int32_t cosim_shaft(unsigned axis);
uint32_t cosim_drive_enable(void);
int cosim_irq(void);

/* The scenarios (firmware.c): prints one result line per scenario. */
int cosim_firmware_main(void);

#ifdef __cplusplus
}
#endif

#endif
