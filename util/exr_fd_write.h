/* The body of an OpenEXR write callback (exr_write_func_ptr_t) onto a file
 * descriptor: every output of skyfit is an atomic file's descriptor
 * (util/atomic_file.h), so OpenEXR writes through it rather than opening
 * the path itself. Shared by the tables' cache (data/table_exr.c) and the
 * error-map images (util/exr_image.c). */
#ifndef SKYFIT_UTIL_EXR_FD_WRITE_H
#define SKYFIT_UTIL_EXR_FD_WRITE_H

#include <stdint.h>

#include <OpenEXR/openexr.h>

/* Writes sz bytes of buffer at offset of fd, retrying short writes and
 * EINTR. Returns sz, or -1 after reporting EXR_ERR_WRITE_IO through
 * error_cb and keeping the write's errno in *write_errno (the first one:
 * OpenEXR's own result code does not tell a full disk from bad input;
 * sf_write_error_status does). */
int64_t sf_exr_write_fd(exr_const_context_t ctxt, int fd, const void *buffer, uint64_t sz, uint64_t offset,
                        exr_stream_error_func_ptr_t error_cb, int *write_errno);

#endif
