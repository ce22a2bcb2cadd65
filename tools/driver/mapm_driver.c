/* The MAPM coprocessor's C driver: see mapm_driver.h and docs/coprocessor.md. */
#include "mapm_driver.h"

#include <stdio.h>
#include <string.h>

static uint32_t rd(const mapm_bus* b, uint32_t off) { return b->read32(b->ctx, off); }
static void wr(const mapm_bus* b, uint32_t off, uint32_t v) { b->write32(b->ctx, off, v); }
static unsigned field(uint32_t reg, uint32_t mask, unsigned shift) { return (unsigned)((reg & mask) >> shift); }
static void wr64(const mapm_bus* b, uint32_t lo, uint32_t hi, uint64_t v) {
  wr(b, lo, (uint32_t)v);
  wr(b, hi, (uint32_t)(v >> 32));
}

int mapm_identify(const mapm_bus* b, mapm_info* i) {
  uint32_t r;
  memset(i, 0, sizeof *i);
  if (rd(b, MAPM_REG_ID) != MAPM_ID_MAGIC) return MAPM_E_ID;
  i->version = field(rd(b, MAPM_REG_VERSION), MAPM_VERSION_MAP_MASK, MAPM_VERSION_MAP_SHIFT);
  if (i->version != MAPM_REGMAP_VERSION) return MAPM_E_VERSION;
  r = rd(b, MAPM_REG_HW_COUNTS);
  i->tsm = field(r, MAPM_HW_COUNTS_TSM_MASK, MAPM_HW_COUNTS_TSM_SHIFT);
  i->som = field(r, MAPM_HW_COUNTS_SOM_MASK, MAPM_HW_COUNTS_SOM_SHIFT);
  i->soa = field(r, MAPM_HW_COUNTS_SOA_MASK, MAPM_HW_COUNTS_SOA_SHIFT);
  i->guard = field(r, MAPM_HW_COUNTS_GUARD_MASK, MAPM_HW_COUNTS_GUARD_SHIFT);
  r = rd(b, MAPM_REG_HW_FORMAT);
  i->exp_width = field(r, MAPM_HW_FORMAT_EXP_WIDTH_MASK, MAPM_HW_FORMAT_EXP_WIDTH_SHIFT);
  i->man_width = field(r, MAPM_HW_FORMAT_MAN_WIDTH_MASK, MAPM_HW_FORMAT_MAN_WIDTH_SHIFT);
  i->slot_bytes = field(r, MAPM_HW_FORMAT_SLOT_BYTES_MASK, MAPM_HW_FORMAT_SLOT_BYTES_SHIFT);
  i->arith = field(r, MAPM_HW_FORMAT_ARITH_MASK, MAPM_HW_FORMAT_ARITH_SHIFT);
  i->layout = field(r, MAPM_HW_FORMAT_LAYOUT_MASK, MAPM_HW_FORMAT_LAYOUT_SHIFT);
  i->fidelity = field(r, MAPM_HW_FORMAT_FIDELITY_MASK, MAPM_HW_FORMAT_FIDELITY_SHIFT);
  r = rd(b, MAPM_REG_HW_MEMORY);
  i->data_bytes = field(r, MAPM_HW_MEMORY_DATA_BYTES_MASK, MAPM_HW_MEMORY_DATA_BYTES_SHIFT);
  i->id_bits = field(r, MAPM_HW_MEMORY_ID_BITS_MASK, MAPM_HW_MEMORY_ID_BITS_SHIFT);
  i->addr_bits = field(r, MAPM_HW_MEMORY_ADDR_BITS_MASK, MAPM_HW_MEMORY_ADDR_BITS_SHIFT);
  r = rd(b, MAPM_REG_HW_FRAME);
  i->tile_log2 = field(r, MAPM_HW_FRAME_TILE_LOG2_MASK, MAPM_HW_FRAME_TILE_LOG2_SHIFT);
  i->acc_bits = field(r, MAPM_HW_FRAME_ACC_BITS_MASK, MAPM_HW_FRAME_ACC_BITS_SHIFT);
  i->count_bits = field(r, MAPM_HW_FRAME_COUNT_BITS_MASK, MAPM_HW_FRAME_COUNT_BITS_SHIFT);
  r = rd(b, MAPM_REG_HW_INDICES);
  i->query_bits = field(r, MAPM_HW_INDICES_QUERY_BITS_MASK, MAPM_HW_INDICES_QUERY_BITS_SHIFT);
  i->node_bits = field(r, MAPM_HW_INDICES_NODE_BITS_MASK, MAPM_HW_INDICES_NODE_BITS_SHIFT);
  return MAPM_OK;
}

int mapm_configure(const mapm_bus* b, const mapm_info* i, const mapm_frame* f) {
  if (f->exp_width != i->exp_width || f->man_width != i->man_width || f->slot_bytes != i->slot_bytes) return MAPM_E_FORMAT;
  if (rd(b, MAPM_REG_STATUS) & MAPM_STATUS_BUSY_MASK) return MAPM_E_BUSY;
  wr64(b, MAPM_REG_NODE_BASE_LO, MAPM_REG_NODE_BASE_HI, f->node_base);
  wr64(b, MAPM_REG_PHOTON_BASE_LO, MAPM_REG_PHOTON_BASE_HI, f->photon_base);
  wr64(b, MAPM_REG_QUERY_BASE_LO, MAPM_REG_QUERY_BASE_HI, f->query_base);
  wr64(b, MAPM_REG_STREAM_BASE_LO, MAPM_REG_STREAM_BASE_HI, f->stream_base);
  wr64(b, MAPM_REG_FRAME_BASE_LO, MAPM_REG_FRAME_BASE_HI, f->frame_base);
  wr64(b, MAPM_REG_RADIUS_LO, MAPM_REG_RADIUS_HI, f->radius);
  wr(b, MAPM_REG_NODE_COUNT, f->node_count);
  wr(b, MAPM_REG_QUERY_COUNT, f->query_count);
  wr(b, MAPM_REG_PIXEL_BASE, f->pixel_base);
  wr(b, MAPM_REG_PIXEL_COUNT, f->pixel_count);
  wr(b, MAPM_REG_FRAME_SCALE, (uint32_t)f->frame_scale);
  wr(b, MAPM_REG_QUERY_ORDER, f->use_stream ? MAPM_QUERY_ORDER_STREAM_MASK : 0u);
  return MAPM_OK;
}

int mapm_start(const mapm_bus* b, int irq) {
  if (rd(b, MAPM_REG_STATUS) & MAPM_STATUS_BUSY_MASK) return MAPM_E_BUSY;
  wr(b, MAPM_REG_IRQ_STATUS, MAPM_IRQ_STATUS_DONE_MASK);
  wr(b, MAPM_REG_IRQ_ENABLE, irq ? MAPM_IRQ_ENABLE_DONE_MASK : 0u);
  wr(b, MAPM_REG_CONTROL, MAPM_CONTROL_START_MASK);
  return MAPM_OK;
}

int mapm_wait(const mapm_bus* b, uint64_t max_polls) {
  uint64_t n;
  uint32_t s = 0;
  if (b->wait_irq && (rd(b, MAPM_REG_IRQ_ENABLE) & MAPM_IRQ_ENABLE_DONE_MASK)) {
    if (!b->wait_irq(b->ctx)) return MAPM_E_TIMEOUT;
    wr(b, MAPM_REG_IRQ_STATUS, MAPM_IRQ_STATUS_DONE_MASK);
    s = rd(b, MAPM_REG_STATUS);
  } else {
    for (n = 0; n < max_polls; n++) {
      s = rd(b, MAPM_REG_STATUS);
      if (!(s & MAPM_STATUS_BUSY_MASK)) break;
    }
    if (s & MAPM_STATUS_BUSY_MASK) return MAPM_E_TIMEOUT;
  }
  if (s & MAPM_STATUS_ERROR_MASK) return MAPM_E_HW;
  return (s & MAPM_STATUS_DONE_MASK) ? MAPM_OK : MAPM_E_TIMEOUT;
}

uint64_t mapm_counter(const mapm_bus* b, unsigned k) {
  const uint32_t off = MAPM_COUNTER_BASE + 8u * k;
  const uint64_t lo = rd(b, off); /* latches the high word */
  return lo | (uint64_t)rd(b, off + 4u) << 32;
}

void mapm_describe(const mapm_bus* b, int code, char* buf, size_t n) {
  const char* what = 0;
  size_t used;
  unsigned bit;
  uint32_t cause;
  if (n == 0) return;
  switch (code) {
    case MAPM_OK: what = "ok"; break;
    case MAPM_E_ID: what = "no MAPM answers at this address (ID is not \"MAPM\")"; break;
    case MAPM_E_VERSION: what = "the MAPM's register map is not the version this driver knows"; break;
    case MAPM_E_FORMAT: what = "the arrays' number format or slot size is not the MAPM's (HW_FORMAT)"; break;
    case MAPM_E_BUSY: what = "the MAPM is busy with a frame pass"; break;
    case MAPM_E_TIMEOUT: what = "the frame pass did not end while the driver waited"; break;
    case MAPM_E_HW: break;
    default: what = "unknown result"; break;
  }
  if (what) {
    snprintf(buf, n, "%s", what);
    return;
  }
  cause = rd(b, MAPM_REG_ERROR_CAUSE);
  snprintf(buf, n, "the frame pass ended in error:");
  for (bit = 0; bit < MAPM_ERROR_CAUSES; bit++) {
    if (!(cause >> bit & 1u)) continue;
    used = strlen(buf);
    if (used + 1 < n) snprintf(buf + used, n - used, " %s;", mapm_error_reason(bit));
  }
  used = strlen(buf);
  if (cause == 0 && used + 1 < n) snprintf(buf + used, n - used, " no cause recorded");
  else if (used > 0 && buf[used - 1] == ';') buf[used - 1] = '\0';
}
