/* Table files (SPEC §6): one float32 scanline EXR per table, ZIP-compressed,
 * one EXR channel per colour channel, the picture in the image layout of
 * data/table.h. String header attributes make the file self-describing:
 *
 *   skyfit:format            "skyfit-table 1"
 *   skyfit:quantity          desc.quantity
 *   skyfit:parameterization  desc.parameterization
 *   skyfit:axes              JSON [{"name":..,"size":..,"min":..,"max":..,
 *                            "mapping":..}, ...], axes[0] first, numbers
 *                            with 17 significant digits (exact doubles)
 *   skyfit:channels          JSON ["r","g","b"]: the table's channel order
 *                            (EXR itself stores channels sorted by name)
 *   skyfit:tiling            "x=i0+n0*i2,y=i1+n1*i3" (data/table.h)
 *   skyfit:atmosphere        the atmosphere JSON text
 *   skyfit:content_hash      desc.content_hash ("" if none)
 *   skyfit:orders            only where t.orders.highest >= 1 (multiple
 *                            scattering): "HIGHEST LEFT", e.g. "6 0.00123"
 *   skyfit:checksum          16 hex digits: FNV-1a 64 (util/hash64.h) over
 *                            the eight strings above, in that order, each
 *                            as (8-byte little-endian length, bytes), then
 *                            skyfit:orders the same way where present, then
 *                            every value's float32 bits, little-endian, in
 *                            the memory order of data/table.h.
 *
 * The checksum is what makes a damaged file detectable: EXR has no checksum
 * of its own, ZIP's Adler-32 only covers chunks that compressed, and a
 * flipped byte in raw float data is another valid float. With it, a single
 * flipped byte anywhere in the skyfit strings or the data is always caught.
 * The same table always gives the same bytes. */
#ifndef SKYFIT_DATA_TABLE_EXR_H
#define SKYFIT_DATA_TABLE_EXR_H

#include <stddef.h>
#include "data/table.h"
#include "util/error.h"

#define SF_TABLE_EXR_FORMAT "skyfit-table 1"
#define SF_TABLE_EXR_TILING "x=i0+n0*i2,y=i1+n1*i3"

/* Writes t to path atomically (temporary sibling, then rename): on failure
 * the previous file at path is untouched and no temporary remains. An
 * unwritable folder is SF_ERR_INPUT; a non-finite value in the table is
 * SF_ERR_INTERNAL (the computation that filled it is broken). */
int sf_table_write_exr(const sf_table *t, const char *path, sf_error *err);

/* Reads and validates a table file into *out (initialised here; free it
 * with sf_table_free). Any problem — not an EXR, truncated, damaged,
 * missing or malformed skyfit attributes, channels or picture size that do
 * not match the axes, a table over max_bytes (0 = default), a non-finite
 * value, a checksum mismatch — is SF_ERR_INPUT with a message naming the
 * path and what is wrong, and leaves *out empty. */
int sf_table_read_exr(const char *path, size_t max_bytes, sf_table *out, sf_error *err);

#endif
