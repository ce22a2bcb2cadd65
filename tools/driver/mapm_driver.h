/* The MAPM coprocessor's C driver (docs/coprocessor.md): identify, configure a frame pass, start
 * it, wait for it by polling or by interrupt, read the counters, and say in one line why a call
 * failed. It touches the hardware only through a mapm_bus, so the same code runs on a CPU with
 * memory-mapped registers and in the Verilator harness, which plays that CPU over AXI4-Lite.
 * C99; mapm_regs.h is generated from the register map (mapm.format.RegisterMap). */
#ifndef MAPM_DRIVER_H
#define MAPM_DRIVER_H
#include <stddef.h>
#include <stdint.h>

#include "mapm_regs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How the driver reaches the registers. `read32` and `write32` access one 32-bit register at a
 * byte offset of the register space. `wait_irq` waits for the interrupt line and returns nonzero
 * once it is high, 0 when the platform gave up waiting; NULL where there is no interrupt (the
 * driver then polls STATUS). `ctx` is passed to each. */
typedef struct mapm_bus {
  uint32_t (*read32)(void* ctx, uint32_t offset);
  void (*write32)(void* ctx, uint32_t offset, uint32_t value);
  int (*wait_irq)(void* ctx);
  void* ctx;
} mapm_bus;

/* What the identification registers say the hardware is. */
typedef struct mapm_info {
  unsigned version;
  unsigned tsm, som, soa, guard;
  unsigned exp_width, man_width, slot_bytes, arith, layout, fidelity;
  unsigned data_bytes, id_bits, addr_bits;
  unsigned tile_log2, acc_bits, count_bits;
  unsigned query_bits, node_bits;
} mapm_info;

/* One frame pass: where the arrays lie (docs/memory-layout.md), their counts, the pixels it
 * covers and the accumulator's scale. exp_width, man_width and slot_bytes state the format the
 * arrays were written in; the driver refuses a pass whose format is not the hardware's. With
 * use_stream nonzero the pass runs the queries in the order of the stream at stream_base, else
 * the query records in array order (stream_base unused). */
typedef struct mapm_frame {
  unsigned exp_width, man_width, slot_bytes;
  uint64_t node_base, photon_base, query_base, stream_base, frame_base;
  uint64_t radius;
  uint32_t node_count, query_count, pixel_base, pixel_count;
  int32_t frame_scale;
  int use_stream;
} mapm_frame;

/* Results of the calls. */
enum {
  MAPM_OK = 0,
  MAPM_E_ID = -1,      /* ID is not "MAPM": no MAPM at this address */
  MAPM_E_VERSION = -2, /* a register map this driver does not know */
  MAPM_E_FORMAT = -3,  /* the pass's number format or slot is not the hardware's */
  MAPM_E_BUSY = -4,    /* a pass is running */
  MAPM_E_TIMEOUT = -5, /* the pass did not end while the driver waited */
  MAPM_E_HW = -6       /* the pass ended in error: ERROR_CAUSE says why */
};

int mapm_identify(const mapm_bus* bus, mapm_info* info);
int mapm_configure(const mapm_bus* bus, const mapm_info* info, const mapm_frame* frame);
/* Starts the configured pass; with `irq` nonzero the pass's end raises the interrupt line. */
int mapm_start(const mapm_bus* bus, int irq);
/* Waits for the pass to end: by interrupt when the bus has one and the pass was started with it,
 * else by reading STATUS at most `max_polls` times. */
int mapm_wait(const mapm_bus* bus, uint64_t max_polls);
/* Counter k (0 .. MAPM_COUNTER_COUNT - 1), 64 bits read as one value. */
uint64_t mapm_counter(const mapm_bus* bus, unsigned k);
/* Writes one line (no newline) into buf[0 .. n-1] saying what result `code` means; for MAPM_E_HW
 * it lists ERROR_CAUSE's reasons. */
void mapm_describe(const mapm_bus* bus, int code, char* buf, size_t n);

#ifdef __cplusplus
}
#endif
#endif
