// Atomic file writing: output goes to a temporary file beside the target, then a rename.
#pragma once
#include <filesystem>
#include <functional>
#include <ostream>

namespace imx {

// Calls `write` with a binary stream on a new temporary file in `file`'s folder, then renames
// it over `file`, so readers never see a half-written file. When `write` throws or any I/O
// step fails, the temporary file is removed and the error (an imx::Error naming `file`)
// propagates; an existing `file` is then left untouched. A `file` that is one of the inputs
// this process opened (the same file once links are resolved: input_identity.hpp) is refused
// before anything is written.
//
// Interruption: the first call installs (once per process) a handler for SIGINT, SIGTERM and
// SIGHUP that unlinks every temporary still alive in any thread, then lets the signal take
// its course: the previous handler is called if there was one, otherwise the default
// disposition is restored and the signal re-raised, so the process still dies of it. A signal
// that was ignored when the handler would have been installed stays ignored. An interrupted
// write therefore leaves neither a `*.tmp-*` file nor a half-replaced `file`. The registry of
// live temporaries is fixed-size (64 concurrent writes, paths up to 4095 bytes); a write
// beyond that still works but is not cleaned up on a signal.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write);

}  // namespace imx
