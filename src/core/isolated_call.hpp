// Running a third-party decoder that may abort or crash on corrupt input (GDCM's JPEG codecs
// assert, OpenJPEG can fault) in a child process, so that its end is an error message and not
// the end of the program, or of the Python interpreter that loaded intermix.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace imx::detail {

struct IsolatedResult {
  // over_memory: the child ran out of the address space `memory_limit` gave it.
  enum class End { finished, failed, crashed, timed_out, over_memory };
  End end = End::crashed;
  std::string error;   // failed: the imx::Error (or other exception) `work` threw
  std::string detail;  // crashed: "signal 6 (Aborted)" or "exit status 1"
  std::string output;  // what the child printed on stderr (library chatter), at most 64 KiB
};

// Runs `work` in a forked child with `shared_bytes` bytes of zeroed memory shared with this
// process; when the child finished, `finished` reads what it wrote there (before the memory is
// unmapped). `work` throws to fail. The child's stderr is captured, never
// shown; a child still running after `timeout_s` is killed. The child runs only `work` and then
// _exits: no atexit handlers, no stdio flushes, no other threads (so `work` must not wait on
// this process's threads or locks held by them). `memory_limit` bytes (0: none) bound the address
// space the child may add to what it had at the fork: past them its allocations fail, and a
// std::bad_alloc ends it as over_memory (a hostile stream must not decode into all of memory).
// Throws imx::Error when the process or the memory cannot be made.
IsolatedResult run_isolated(size_t shared_bytes,
                            const std::function<void(std::span<std::byte>)>& work, double timeout_s,
                            const std::function<void(std::span<const std::byte>)>& finished,
                            uint64_t memory_limit = 0);

}  // namespace imx::detail
