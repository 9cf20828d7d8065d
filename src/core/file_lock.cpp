#include "core/file_lock.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rl {

FileLock::FileLock(const std::string& path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw IoError(path + ": cannot open lock file (" + std::strerror(errno) + ")");
  struct flock l {};
  l.l_type = F_WRLCK;
  l.l_whence = SEEK_SET;
  while (::fcntl(fd_, F_SETLKW, &l) == -1) {
    if (errno == EINTR) continue;
    const int e = errno;
    ::close(fd_);
    throw IoError(path + ": cannot lock (" + std::strerror(e) + ")");
  }
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the record lock
}

}  // namespace rl
