/* Example: one frame pass through the MAPM coprocessor with the C driver (docs/coprocessor.md).
 *
 * A CPU program gives the driver a mapm_bus whose read32/write32 reach the coprocessor's registers
 * (e.g. a volatile uint32_t pointer to where the SoC maps them) and, where the interrupt is wired,
 * a wait_irq that sleeps until it rises. The Verilator harness (tools/harness/coproc.cpp) runs
 * every render through this very function, its bus playing the CPU over AXI4-Lite.
 *
 * Returns MAPM_OK, or a driver result with its one-line reason in why[0 .. n-1]; the counters
 * (MAPM_COUNTER_COUNT of them, named by mapm_counter_name) are read into `counters` either way. */
#include "mapm_driver.h"

int mapm_run_frame(const mapm_bus* bus, const mapm_frame* frame, int use_irq, uint64_t* counters, char* why, size_t n) {
  mapm_info info;
  unsigned k;
  int rc = mapm_identify(bus, &info);
  if (rc == MAPM_OK) rc = mapm_configure(bus, &info, frame);
  if (rc == MAPM_OK) rc = mapm_start(bus, use_irq);
  if (rc == MAPM_OK) rc = mapm_wait(bus, UINT64_MAX);
  if (rc != MAPM_E_ID && rc != MAPM_E_VERSION)
    for (k = 0; k < MAPM_COUNTER_COUNT; k++) counters[k] = mapm_counter(bus, k);
  mapm_describe(bus, rc, why, n);
  return rc;
}
