#include "data/sample_memo.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* A sample's state; calloc's zero bytes are EMPTY. */
enum { EMPTY = 0, WRITING = 1, KEPT = 2 };

/* One slice: its samples' records, then their states. */
typedef struct slice {
  double *records;
  atomic_uchar *state;
} slice;

struct sf_sample_memo {
  int size[4], slice_axis, record_len;
  long per_slice;
  _Atomic(slice *) *slices;
  atomic_size_t bytes;
};

sf_sample_memo *sf_sample_memo_make(const int size[4], int slice_axis, int record_len) {
  if (slice_axis < 0 || slice_axis > 3 || record_len < 1) return NULL;
  long per_slice = 1;
  for (int k = 0; k < 4; ++k) {
    if (size[k] < 1) return NULL;
    if (k != slice_axis) per_slice *= size[k];
  }
  sf_sample_memo *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->slices = calloc((size_t)size[slice_axis], sizeof *m->slices);
  if (!m->slices) {
    free(m);
    return NULL;
  }
  memcpy(m->size, size, sizeof m->size);
  m->slice_axis = slice_axis;
  m->record_len = record_len;
  m->per_slice = per_slice;
  for (int i = 0; i < size[slice_axis]; ++i) atomic_init(&m->slices[i], NULL);
  atomic_init(&m->bytes, sizeof *m + (size_t)size[slice_axis] * sizeof *m->slices);
  return m;
}

void sf_sample_memo_free(sf_sample_memo *m) {
  if (!m) return;
  for (int i = 0; i < m->size[m->slice_axis]; ++i) {
    slice *s = atomic_load_explicit(&m->slices[i], memory_order_relaxed);
    if (s) free(s->records);
    free(s);
  }
  free(m->slices);
  free(m);
}

/* The slice of the sample at offset and its index within it. */
static int locate(const sf_sample_memo *m, long offset, long *index) {
  long stride = 1, below = 0, at = 0;
  for (int k = 0; k < 4; ++k) {
    long i = offset % m->size[k];
    offset /= m->size[k];
    if (k == m->slice_axis) {
      at = i;
    } else {
      below += i * stride;
      stride *= m->size[k];
    }
  }
  *index = below;
  return (int)at;
}

int sf_sample_memo_get(const sf_sample_memo *m, long offset, double *out) {
  long i;
  int at = locate(m, offset, &i);
  slice *s = atomic_load_explicit(&m->slices[at], memory_order_acquire);
  if (!s || atomic_load_explicit(&s->state[i], memory_order_acquire) != KEPT) return 0;
  memcpy(out, s->records + i * m->record_len, (size_t)m->record_len * sizeof *out);
  return 1;
}

/* The slice at, allocated if it was not; NULL if out of memory. */
static slice *slice_at(sf_sample_memo *m, int at) {
  slice *s = atomic_load_explicit(&m->slices[at], memory_order_acquire);
  if (s) return s;
  slice *fresh = malloc(sizeof *fresh);
  size_t n = (size_t)m->per_slice, record_bytes = n * (size_t)m->record_len * sizeof(double);
  /* records and states in one block; the states' zero bytes are EMPTY */
  unsigned char *block = fresh ? calloc(1, record_bytes + n * sizeof(atomic_uchar)) : NULL;
  if (!block) {
    free(fresh);
    return NULL;
  }
  fresh->records = (double *)block;
  fresh->state = (atomic_uchar *)(block + record_bytes);
  /* another thread may have made it meanwhile: its slice is kept */
  if (!atomic_compare_exchange_strong_explicit(&m->slices[at], &s, fresh, memory_order_acq_rel,
                                               memory_order_acquire)) {
    free(block);
    free(fresh);
    return s;
  }
  atomic_fetch_add_explicit(&m->bytes, sizeof *fresh + record_bytes + n * sizeof(atomic_uchar),
                            memory_order_relaxed);
  return fresh;
}

void sf_sample_memo_put(sf_sample_memo *m, long offset, const double *record) {
  long i;
  int at = locate(m, offset, &i);
  slice *s = slice_at(m, at);
  if (!s) return;
  unsigned char expected = EMPTY;
  if (!atomic_compare_exchange_strong_explicit(&s->state[i], &expected, WRITING, memory_order_acquire,
                                               memory_order_relaxed))
    return;
  memcpy(s->records + i * m->record_len, record, (size_t)m->record_len * sizeof *record);
  atomic_store_explicit(&s->state[i], KEPT, memory_order_release);
}

int sf_sample_memo_record_len(const sf_sample_memo *m) { return m->record_len; }

size_t sf_sample_memo_bytes(const sf_sample_memo *m) {
  return m ? atomic_load_explicit(&m->bytes, memory_order_relaxed) : 0;
}
