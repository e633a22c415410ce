#include "io/streams/atomic_file.hpp"
#include "io/streams/regular_file.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <system_error>

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include "core/hash.hpp"
#include "intermix/error.hpp"
#include "io/streams/input_identity.hpp"

namespace imx {

namespace {

// ---- Registry of live temporaries, read by the signal handler -------------------------------
//
// Everything the handler touches is static, fixed-size and lock-free: a slot's path is a plain
// char array that is only read while the slot is kArmed, and slots change state by atomic
// compare-and-swap, so the handler may run in any thread at any moment.

constexpr int kSlots = 64;
constexpr std::size_t kMaxPath = 4096;

enum SlotState : int {
  kFree = 0,       // unused
  kFilling = 1,    // its owner is copying a path in; the handler skips it
  kArmed = 2,      // path complete: the handler unlinks it
  kUnlinking = 3,  // the handler is unlinking it
  kUnlinked = 4,   // the handler has unlinked it; only its owner frees it
};

struct Slot {
  std::atomic<int> state;
  char path[kMaxPath];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");

Slot g_slots[kSlots];  // zero-initialized before any code runs: every slot kFree

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr int kSignalCount = sizeof(kSignals) / sizeof(kSignals[0]);
struct sigaction g_previous[kSignalCount];  // written once, before the handler is installed

void unlink_armed_temporaries() {
  for (Slot& slot : g_slots) {
    int expected = kArmed;
    if (slot.state.compare_exchange_strong(expected, kUnlinking, std::memory_order_acquire)) {
      ::unlink(slot.path);
      slot.state.store(kUnlinked, std::memory_order_release);
    }
  }
}

extern "C" void on_terminating_signal(int sig, siginfo_t* info, void* context) {
  const int saved_errno = errno;
  unlink_armed_temporaries();
  const struct sigaction* previous = nullptr;
  for (int i = 0; i < kSignalCount; ++i)
    if (kSignals[i] == sig) previous = &g_previous[i];
  if (previous && (previous->sa_flags & SA_SIGINFO) && previous->sa_sigaction) {
    errno = saved_errno;
    previous->sa_sigaction(sig, info, context);
    return;
  }
  if (previous && previous->sa_handler != SIG_DFL && previous->sa_handler != SIG_IGN) {
    errno = saved_errno;
    previous->sa_handler(sig);
    return;
  }
  // Default action: restore it and re-raise. The signal is blocked while this handler runs, so
  // it stays pending and ends the process, with the status of this signal, when we return.
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  ::sigaction(sig, &default_action, nullptr);
  ::raise(sig);
  errno = saved_errno;
}

void install_signal_handler_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction action {};
    action.sa_sigaction = on_terminating_signal;
    action.sa_flags = SA_SIGINFO | SA_RESTART;
    sigemptyset(&action.sa_mask);
    for (int sig : kSignals) sigaddset(&action.sa_mask, sig);  // no nesting of our signals
    for (int i = 0; i < kSignalCount; ++i) {
      if (::sigaction(kSignals[i], nullptr, &g_previous[i]) != 0) continue;
      if (!(g_previous[i].sa_flags & SA_SIGINFO) && g_previous[i].sa_handler == SIG_IGN)
        continue;  // ignored (nohup, background job): it will not end the process
      ::sigaction(kSignals[i], &action, nullptr);
    }
  });
}

// A registry slot for one temporary path, armed before the file is created (so no moment
// exists when the file is there but not registered) and freed after the rename or removal.
class ArmedPath {
 public:
  explicit ArmedPath(const std::filesystem::path& path) {
    const std::string& s = path.native();
    if (s.size() >= kMaxPath) return;  // not cleaned up on a signal, but still written
    for (int i = 0; i < kSlots; ++i) {
      int expected = kFree;
      if (g_slots[i].state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire)) {
        std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
        g_slots[i].state.store(kArmed, std::memory_order_release);
        slot_ = i;
        return;
      }
    }
  }
  ~ArmedPath() { release(); }
  ArmedPath(const ArmedPath&) = delete;
  ArmedPath& operator=(const ArmedPath&) = delete;
  ArmedPath(ArmedPath&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }

  void release() {
    if (slot_ < 0) return;
    std::atomic<int>& state = g_slots[slot_].state;
    int expected = kArmed;
    if (!state.compare_exchange_strong(expected, kFree, std::memory_order_acq_rel)) {
      // A handler (in another thread, whose handler chained on) took the slot: let it finish.
      while (state.load(std::memory_order_acquire) == kUnlinking) {
      }
      state.store(kFree, std::memory_order_release);
    }
    slot_ = -1;
  }

 private:
  int slot_ = -1;
};

struct Temporary {
  std::filesystem::path path;
  ArmedPath armed;
};

// Creates a new, empty, uniquely named file beside `file` and returns its path, registered for
// removal on SIGINT / SIGTERM / SIGHUP. "wx" is exclusive creation, so two writers never share
// a temporary, and the umask applies.
Temporary create_temporary(const std::filesystem::path& file) {
  static std::atomic<uint32_t> counter{0};
  uint32_t seed =
      hash_u32(static_cast<uint32_t>(::getpid())) ^
      static_cast<uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  // The handler unlinks by this path, so it must not depend on the working folder.
  std::error_code absolute_error;
  std::filesystem::path absolute = std::filesystem::absolute(file, absolute_error);
  if (absolute_error) absolute = file;
  int last_errno = 0;
  for (int attempt = 0; attempt < 64; ++attempt) {
    uint32_t tag = hash_u32(seed ^ hash_u32(counter.fetch_add(1)));
    std::filesystem::path tmp = absolute;
    tmp += fmt::format(".tmp-{:08x}", tag);
    // Armed before it exists. Should the name be taken (EEXIST, a 1 in 2^32 clash with another
    // writer of the same file) and a signal land in that instant, the other writer's temporary
    // is removed: its rename then fails cleanly, and no output is ever half-written.
    ArmedPath armed(tmp);
    if (std::FILE* f = std::fopen(tmp.c_str(), "wx")) {
      std::fclose(f);
      return Temporary{std::move(tmp), std::move(armed)};
    }
    last_errno = errno;
    if (last_errno != EEXIST) break;
  }
  std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
  throw FileError(fmt::format("{}: cannot create a file in folder '{}': {}", file.string(),
                              folder.string(), std::strerror(last_errno)),
                  last_errno);
}

void remove_quietly(const std::filesystem::path& p) {
  std::error_code ec;
  std::filesystem::remove(p, ec);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write) {
  require_regular_or_new_file(file);  // renaming over a device or FIFO would replace it
  refuse_output_over_input(file);     // nor may an output replace what this command read
  install_signal_handler_once();
  Temporary tmp = create_temporary(file);
  try {
    {
      std::ofstream out(tmp.path, std::ios::binary | std::ios::trunc);
      if (!out)
        throw FileError(
            fmt::format("{}: cannot open '{}' for writing", file.string(), tmp.path.string()),
            errno);
      write(out);
      out.flush();
      if (!out) throw FileError(fmt::format("{}: writing failed (disk full?)", file.string()));
      out.close();
      if (out.fail())
        throw FileError(fmt::format("{}: closing failed (disk full?)", file.string()));
    }
    std::error_code ec;
    std::filesystem::rename(tmp.path, file, ec);
    if (ec)
      throw FileError(fmt::format("{}: cannot rename the temporary file into place: {}",
                                  file.string(), ec.message()),
                      ec.value());
    tmp.armed.release();
  } catch (...) {
    remove_quietly(tmp.path);
    tmp.armed.release();
    throw;
  }
}

}  // namespace imx
