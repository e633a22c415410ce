#include "core/isolated_call.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <new>

#include <fmt/format.h>

#include "intermix/error.hpp"

// Set when built with a sanitizer: the hook a fuzzer installs to save its input on a crash.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace imx::detail {

namespace {

constexpr size_t kMaxOutput = size_t{64} << 10;
constexpr size_t kMaxError = 2048;

// The first bytes of the shared mapping: how the child ended its work.
struct ChildReport {
  int state = 0;  // 0: did not get there (crashed), 1: finished, 2: failed with `error`,
                  // 3: out of memory
  char error[kMaxError] = {};
};

class SharedMapping {
 public:
  explicit SharedMapping(size_t bytes) : bytes_(bytes) {
    void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
      throw Error(fmt::format("cannot map {} bytes to share with a decoder process: {}", bytes,
                              std::strerror(errno)));
    data_ = static_cast<std::byte*>(p);
  }
  ~SharedMapping() { munmap(data_, bytes_); }
  SharedMapping(const SharedMapping&) = delete;
  SharedMapping& operator=(const SharedMapping&) = delete;
  std::byte* data() const { return data_; }

 private:
  size_t bytes_;
  std::byte* data_ = nullptr;
};

// The address space this process maps now (/proc/self/statm's first field, in pages), read
// with system calls only: the child of a threaded process must not allocate before its work.
uint64_t mapped_bytes() {
  char text[128] = {};
  const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  const ssize_t n = read(fd, text, sizeof text - 1);
  close(fd);
  uint64_t pages = 0;
  for (ssize_t i = 0; i < n && text[i] >= '0' && text[i] <= '9'; ++i)
    pages = pages * 10 + static_cast<uint64_t>(text[i] - '0');
  return pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

[[noreturn]] void child(int output_fd, ChildReport* report, std::span<std::byte> shared,
                        const std::function<void(std::span<std::byte>)>& work,
                        uint64_t memory_limit) {
  dup2(output_fd, STDERR_FILENO);
  dup2(output_fd, STDOUT_FILENO);
  close(output_fd);
  // The child's death is the decoder's, reported by the parent: the handlers this process had
  // (a fuzzer's, which would record the input as its own crash; a sanitizer's) must not run.
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP}) signal(sig, SIG_DFL);
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  if (memory_limit > 0) {
    const rlim_t most = mapped_bytes() + memory_limit;
    const rlimit limit{most, most};
    setrlimit(RLIMIT_AS, &limit);
  }
  try {
    work(shared);
    report->state = 1;
  } catch (const std::bad_alloc&) {
    report->state = 3;
  } catch (const std::exception& e) {
    std::strncpy(report->error, e.what(), kMaxError - 1);
    report->state = 2;
  } catch (...) {
    std::strncpy(report->error, "unknown exception", kMaxError - 1);
    report->state = 2;
  }
  _exit(0);
}

}  // namespace

IsolatedResult run_isolated(size_t shared_bytes,
                            const std::function<void(std::span<std::byte>)>& work, double timeout_s,
                            const std::function<void(std::span<const std::byte>)>& finished,
                            uint64_t memory_limit) {
  const size_t header = (sizeof(ChildReport) + 63) / 64 * 64;
  SharedMapping mapping(header + shared_bytes);
  auto* report = new (mapping.data()) ChildReport;
  const std::span<std::byte> shared(mapping.data() + header, shared_bytes);

  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0)
    throw Error(fmt::format("cannot make a pipe for a decoder process: {}", std::strerror(errno)));
  const pid_t pid = fork();
  if (pid < 0) {
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    throw Error(fmt::format("cannot start a decoder process: {}", std::strerror(errno)));
  }
  if (pid == 0) {
    close(pipe_fds[0]);
    child(pipe_fds[1], report, shared, work, memory_limit);
  }
  close(pipe_fds[1]);

  IsolatedResult r;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  bool timed_out = false;
  char buffer[4096];
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{pipe_fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(std::min<int64_t>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const ssize_t n = read(pipe_fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its end: it ended
    const size_t room = kMaxOutput - std::min(kMaxOutput, r.output.size());
    r.output.append(buffer, std::min(room, static_cast<size_t>(n)));
  }
  close(pipe_fds[0]);
  if (timed_out) kill(pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out) {
    r.end = IsolatedResult::End::timed_out;
  } else if (report->state == 1) {
    r.end = IsolatedResult::End::finished;
    finished(shared);
  } else if (report->state == 2) {
    r.end = IsolatedResult::End::failed;
    r.error = report->error;
  } else if (report->state == 3) {
    r.end = IsolatedResult::End::over_memory;
  } else {
    r.end = IsolatedResult::End::crashed;
    r.detail = WIFSIGNALED(status)
                   ? fmt::format("signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                   : fmt::format("exit status {}", WEXITSTATUS(status));
  }
  return r;
}

}  // namespace imx::detail
