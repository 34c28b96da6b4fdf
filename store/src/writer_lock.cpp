#include "podium/store/writer_lock.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <string>

#include "podium/base/error.h"

namespace podium::store {

namespace {

// SQLite's unix VFS locks bytes 0x40000000 .. 0x400001FF (PENDING_BYTE, RESERVED_BYTE and the
// shared range); ours lies well past them, so it never meets SQLite's own locks.
constexpr off_t kLockByte = 0x40000000 + 0x1000;

struct flock lock_request(short type) {
  struct flock l {};
  l.l_type = type;
  l.l_whence = SEEK_SET;
  l.l_start = kLockByte;
  l.l_len = 1;
  return l;
}

}  // namespace

WriterLock::WriterLock(const std::filesystem::path& database) {
  fd_ = ::open(database.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) throw base::RuntimeError(database.string() + ": cannot open for the scheduler lock: " + std::strerror(errno));
  struct flock l = lock_request(F_WRLCK);
  if (::fcntl(fd_, F_OFD_SETLK, &l) != 0) {
    const int error = errno;
    ::close(fd_);
    if (error == EAGAIN || error == EACCES)
      throw base::RuntimeError(database.string() +
                               ": another `podium run` is using this database (through this path or another "
                               "link to the same file)");
    throw base::RuntimeError(database.string() + ": cannot take the scheduler lock: " + std::strerror(error));
  }
}

WriterLock::~WriterLock() { ::close(fd_); }

bool WriterLock::held(const std::filesystem::path& database) {
  // The descriptor stays open for the process's life: closing any descriptor of the file would
  // drop the classic POSIX locks SQLite holds on it in this process (fcntl(2), "close").
  static std::mutex mutex;
  static std::map<std::filesystem::path, int> descriptors;
  std::lock_guard guard(mutex);
  auto it = descriptors.find(database);
  if (it == descriptors.end()) {
    const int fd = ::open(database.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    it = descriptors.emplace(database, fd).first;
  }
  struct flock l = lock_request(F_WRLCK);
  return ::fcntl(it->second, F_OFD_GETLK, &l) == 0 && l.l_type != F_UNLCK;
}

}  // namespace podium::store
