#include "io/output_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace granudrag {

namespace {

// The lock files held by this process, for the signal handler: fixed storage, no allocation in
// the handler, which only calls unlink() and raise() (both async-signal-safe).
constexpr int kMaxLocks = 16;
constexpr std::size_t kMaxPath = 4096;
char held[kMaxLocks][kMaxPath];
volatile std::sig_atomic_t held_used[kMaxLocks];

extern "C" void remove_locks_and_reraise(int sig) {
  for (int k = 0; k < kMaxLocks; ++k)
    if (held_used[k]) ::unlink(held[k]);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_handlers() {
  static bool installed = false;
  if (installed) return;
  installed = true;
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    struct sigaction old {};
    sigaction(sig, nullptr, &old);
    if (old.sa_handler != SIG_DFL) continue;  // ignored or handled by someone else: leave it
    struct sigaction sa {};
    sa.sa_handler = remove_locks_and_reraise;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
  }
}

void remember(const std::string& lock) {
  if (lock.size() >= kMaxPath) return;
  for (int k = 0; k < kMaxLocks; ++k)
    if (!held_used[k]) {
      std::memcpy(held[k], lock.c_str(), lock.size() + 1);
      held_used[k] = 1;
      return;
    }
}

void forget(const std::string& lock) {
  for (int k = 0; k < kMaxLocks; ++k)
    if (held_used[k] && lock == held[k]) held_used[k] = 0;
}

struct Owner {
  long pid = -1;
  std::string host;
  bool readable = false;
};

Owner read_owner(const std::string& lock) {
  Owner o;
  std::ifstream in(lock);
  std::string word_pid, word_host;
  if (in >> word_pid >> o.pid >> word_host >> o.host && word_pid == "pid" && word_host == "host" && o.pid > 0)
    o.readable = true;
  return o;
}

// 1: made; 0: the name exists; throws for anything else.
int try_create(const std::string& lock, const std::string& text) {
  const std::string mine = lock + "." + host_name() + "." + std::to_string(::getpid());
  const int fd = ::open(mine.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0)
    throw Error("cannot create the lock file '" + mine + "': " + std::strerror(errno) +
                "; check that the output's directory is writable");
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  if (!written) {
    ::unlink(mine.c_str());
    throw Error("cannot write the lock file '" + mine + "' (disk full?)");
  }
  if (::link(mine.c_str(), lock.c_str()) == 0) {
    ::unlink(mine.c_str());
    return 1;
  }
  const int link_errno = errno;
  ::unlink(mine.c_str());
  if (link_errno == EEXIST) return 0;
  // No hard links here (some network or FUSE file systems): exclusive create, then the text.
  const int fd2 = ::open(lock.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd2 < 0) {
    if (errno == EEXIST) return 0;
    throw Error("cannot create the lock file '" + lock + "': " + std::strerror(errno));
  }
  const bool ok = ::write(fd2, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd2);
  if (!ok) {
    ::unlink(lock.c_str());
    throw Error("cannot write the lock file '" + lock + "' (disk full?)");
  }
  return 1;
}

}  // namespace

std::string lock_path_of(const std::string& output) { return output + ".lock"; }

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "unknown";
  return name;
}

OutputLock::OutputLock(const std::string& output) : lock_(lock_path_of(output)) {
  const std::string me = host_name();
  const std::string text = "pid " + std::to_string(::getpid()) + " host " + me + "\n";
  install_handlers();
  // A few rounds: a stale lock removed here may be taken by another process first.
  for (int round = 0; round < 5; ++round) {
    if (try_create(lock_, text) == 1) {
      remember(lock_);
      return;
    }
    const Owner o = read_owner(lock_);
    const std::string remove_it = "if no process writes it any more, remove the lock: rm '" + lock_ + "'";
    if (!o.readable) {
      struct stat st {};
      if (::stat(lock_.c_str(), &st) != 0) continue;  // removed meanwhile: try again
      throw Error("output '" + output + "' is locked by '" + lock_ +
                  "', which does not say which process holds it; " + remove_it);
    }
    if (o.host != me)
      throw Error("output '" + output + "' is being written by process " + std::to_string(o.pid) +
                  " on host " + o.host + " (lock '" + lock_ + "'); this host (" + me +
                  ") cannot tell whether it still runs: " + remove_it);
    const bool alive = ::kill(static_cast<pid_t>(o.pid), 0) == 0 || errno == EPERM;
    if (alive && o.pid != ::getpid())
      throw Error("output '" + output + "' is being written by process " + std::to_string(o.pid) +
                  " on this host (lock '" + lock_ +
                  "'): wait for it to finish, or stop it, or choose another "
                  "output path");
    if (o.pid == ::getpid())
      throw Error("output '" + output +
                  "' is already locked by this process (two outputs with the same name?)");
    std::fprintf(stderr,
                 "granudrag: taking over the stale lock '%s' of process %ld on %s, which no longer runs\n",
                 lock_.c_str(), o.pid, o.host.c_str());
    // Remove only the stale lock read above: rename it to a private name first, then check that
    // it is still the stale one (another process may have replaced it meanwhile).
    const std::string aside = lock_ + ".stale." + std::to_string(::getpid());
    if (::rename(lock_.c_str(), aside.c_str()) != 0) continue;
    const Owner moved = read_owner(aside);
    if (moved.readable && (moved.pid != o.pid || moved.host != o.host)) {
      // Not the stale one: a live owner took over in between. Put its lock back (unless yet
      // another has taken the name), then try again, which refuses it.
      const int restored = ::link(aside.c_str(), lock_.c_str());
      (void)restored;
      ::unlink(aside.c_str());
      continue;
    }
    ::unlink(aside.c_str());
  }
  throw Error("cannot lock output '" + output + "': '" + lock_ +
              "' keeps changing owner; is another run "
              "writing the same output?");
}

OutputLock::OutputLock(OutputLock&& other) noexcept : lock_(std::move(other.lock_)) { other.lock_.clear(); }

OutputLock::~OutputLock() {
  if (lock_.empty()) return;
  forget(lock_);
  ::unlink(lock_.c_str());
}

}  // namespace granudrag
