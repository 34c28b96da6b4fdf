#pragma once
/// The single-writer rule of a database: one `podium run` at a time per database file.
///
/// The lock is an open-file-description lock (fcntl F_OFD_SETLK) on one byte of the database
/// file itself, past the bytes SQLite locks, so every path that reaches the file — a symlink, a
/// hard link, another mount of the same NFS export — meets the same lock, and the kernel releases
/// it when the holder dies (kill -9 included). Across machines it relies on the file server
/// honouring POSIX byte-range locks (NFSv4, or NFSv3 with lockd; not a `nolock` or
/// `local_lock=all` mount).
#include <filesystem>

namespace podium::store {

class WriterLock {
 public:
  /// Takes the lock; throws base::RuntimeError naming the file if another process holds it.
  explicit WriterLock(const std::filesystem::path& database);
  ~WriterLock();
  WriterLock(const WriterLock&) = delete;
  WriterLock& operator=(const WriterLock&) = delete;

  /// Whether a process holds the lock on `database` now (a scheduler is alive); false when the
  /// file cannot be opened. Keeps one read-only descriptor of the file open per process.
  static bool held(const std::filesystem::path& database);

 private:
  int fd_ = -1;
};

}  // namespace podium::store
