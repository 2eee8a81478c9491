#pragma once
// One writer per output: a lock file `<output>.lock` next to the output, holding the owner's
// pid and host name ("pid 1234 host node07"), made atomically (the text is written to a
// private file that is then hard-linked to the lock name, which fails if the name exists; on
// file systems without hard links, open with O_CREAT|O_EXCL). The lock is removed when the
// OutputLock is destroyed (normal exit and error exits, which unwind to main), and on SIGTERM,
// SIGINT and SIGHUP (a cluster's time limit sends SIGTERM first). A lock left by a process that
// died (SIGKILL, a crash) is stale: on the same host with a pid that no longer runs, it is
// reported on stderr and taken over; from another host it cannot be checked, so it is refused
// with the command that removes it.
#include <string>

namespace granudrag {

class OutputLock {
 public:
  // Locks `output` (the file the command writes, not the lock's own name). Throws Error naming
  // the output, the owner and what to do when another live process holds it.
  explicit OutputLock(const std::string& output);
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&&) = delete;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();

  const std::string& lock_path() const { return lock_; }

 private:
  std::string lock_;  // empty once moved from
};

// The lock file of `output`.
std::string lock_path_of(const std::string& output);
// This machine's host name ("unknown" if it cannot be read).
std::string host_name();

}  // namespace granudrag
