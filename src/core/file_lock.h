// An exclusive lock shared by processes, on other machines too: a POSIX record lock (fcntl) on a
// lock file. NFS supports these through its lock manager, and the kernel releases the lock when
// its holder exits or is killed, so a cancelled cluster task never leaves a stale lock behind.
#pragma once
#include <string>

#include "core/io_error.h"

namespace rl {

class FileLock {
 public:
  // Blocks until the lock on `path` (created if missing) is held. Throws IoError when the file
  // cannot be opened or locked.
  explicit FileLock(const std::string& path);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace rl
