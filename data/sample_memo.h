/* A memo of one derived record (a fixed number of doubles) per sample of a
 * 4-axis grid, filled on first use and shared between threads: the sunlit
 * air F (data/sunlit_ray.h) of the single-scattering tables' samples, which
 * a low-sun lookup (data/sky_lookup.c) needs at its 16 corners, had been
 * computed again at every lookup (17 evaluations of F per lookup, about 6x
 * the lookup's time).
 *
 * Storage is taken one slice of the slice axis at a time (a sample's
 * index along it), when a record of that slice is first kept: the lookup
 * reads the suns below its blend's upper end (24 of the default 32 mu_s
 * samples) and, for rays that keep to the top altitude cell, any sun; a
 * command that looks at neither takes none. sf_table_set_memory_bytes
 * counts all of it (51 MB for the RGB default).
 *
 * A record is kept by the first thread to offer it and read back as kept;
 * a thread that finds it missing or still being written computes its own.
 * The record is a pure function of the sample, so a reader gets the same
 * bits whichever thread computed it, whatever the number of threads.
 * Running out of memory for a slice keeps nothing there (the records are
 * then computed at every use, as without a memo). */
#ifndef SKYFIT_DATA_SAMPLE_MEMO_H
#define SKYFIT_DATA_SAMPLE_MEMO_H

#include <stddef.h>

typedef struct sf_sample_memo sf_sample_memo;

/* A memo of records of record_len doubles over a grid of size[0..3]
 * samples (axes[0] fastest, data/table.h), taken in slices along
 * slice_axis. NULL if out of memory (or a size or record_len < 1). */
sf_sample_memo *sf_sample_memo_make(const int size[4], int slice_axis, int record_len);
void sf_sample_memo_free(sf_sample_memo *m);

/* The record of the sample at offset (in samples): 1 and out filled if
 * kept, else 0. */
int sf_sample_memo_get(const sf_sample_memo *m, long offset, double *out);

/* Keeps record as the sample's at offset unless one is kept or being kept. */
void sf_sample_memo_put(sf_sample_memo *m, long offset, const double *record);

/* Doubles per record. */
int sf_sample_memo_record_len(const sf_sample_memo *m);

/* Bytes taken so far (slices allocated, and the memo itself). */
size_t sf_sample_memo_bytes(const sf_sample_memo *m);

#endif
