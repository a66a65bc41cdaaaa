#include "util/exr_fd_write.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

int64_t sf_exr_write_fd(exr_const_context_t ctxt, int fd, const void *buffer, uint64_t sz, uint64_t offset,
                        exr_stream_error_func_ptr_t error_cb, int *write_errno) {
  const char *p = (const char *)buffer;
  uint64_t done = 0;
  while (done < sz) {
    ssize_t n = pwrite(fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (*write_errno == 0) *write_errno = n < 0 ? errno : EIO;
      error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed: %s", n < 0 ? strerror(errno) : "no progress");
      return -1;
    }
    done += (uint64_t)n;
  }
  return (int64_t)done;
}
